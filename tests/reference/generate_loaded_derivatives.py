"""Generate ``tests/data/loaded_derivatives_mpmath.json``: derivatives of loaded states.

Run on demand (a few minutes on two shared cores)::

    .venv/bin/python tests/reference/generate_loaded_derivatives.py [--out PATH]

It imports nothing from :mod:`hairbed`. The states are those of the independent mpmath
reference ``tests/data/loaded_mpmath.json`` (``generate_loaded.py``: shooting from the tip,
Taylor series in mpmath at ``DPS`` digits, written from the equations of issue 20). For a
selection of its cases (``CASES``: both drives, the wall at rest and moving, theta0 of both
signs, eps to 0.99, and every state of a window of each drive) each state is re-converged by
that generator's Newton method, then every input p in (omega2, eps, load, theta0) is moved by
+-``DELTA`` (relative to max(1, abs(p))) and the state re-converged from it; the derivative is
the central difference. At ``DPS`` digits the truncation is DELTA^2 f''' ~ 1e-24 and the
rounding 1e-39/DELTA; the check: a second difference at 10 DELTA (truncation 1e-22) agrees to
``AGREE_TOL`` relative to max(1, abs(value)), or the generator stops.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))
import generate_loaded as gl  # noqa: E402  (the independent reference, beside this file)

DATA = Path(__file__).resolve().parents[1] / "data"
OUT_PATH = DATA / "loaded_derivatives_mpmath.json"
DPS = 45
DELTA = mpf("1e-12")
AGREE_TOL = mpf("1e-18")
OUT_DIGITS = 25
ORDER = gl.ORDERS[0]
INPUTS = ("omega2", "eps", "load", "theta0")
FIELDS = ("tip_height", "tip_deflection", "tip_angle", "base_curvature", "W", "Pi")
#: (label, drive, omega2, eps, theta0, load) of the cases of loaded_mpmath.json used.
CASES = (
    ("pressure", "pressure", 0.0, 0.5, 0.0, 1.0),
    ("pressure", "pressure", 0.0, 0.99, -1.5, 1.0),
    ("pressure", "pressure", 0.0, 0.3, -0.8, 10.0),
    ("pressure", "pressure", 0.0, 0.7, 1.5, 3.0),
    ("pressure+wall", "pressure", 2.0, 0.9, -1.0, 1.0),
    ("pressure against wall", "pressure", 2.0, 0.5, 0.3, -0.5),
    ("flow", "flow", 0.0, 0.5, -0.5, 1.0),
    ("flow", "flow", 0.0, 0.3, 1.2, 1e-3),
    ("flow", "flow", 0.0, 0.6, -1.0, 30.0),
    ("flow+wall", "flow", 0.1, 0.5, 0.0, 1.0),
    ("wall against flow", "flow", 0.4, 0.5, -0.2, 1.0),
    ("pressure window", "pressure", 0.5, 0.95, -1.2, 0.1),
    ("flow window", "flow", 0.0, 0.8, -1.2, 0.13),
)


def _reference_case(label: str, drive: str, omega2: float, eps: float, theta0: float, load: float):
    data = json.loads((DATA / "loaded_mpmath.json").read_text())
    key = "pi" if drive == "pressure" else "q"
    for case in data["cases"]:
        if (
            case["label"] == label
            and case["drive"] == drive
            and case["omega2"] == omega2
            and case["eps"] == eps
            and case["theta0"] == theta0
            and case[key] == load
        ):
            return case
    raise RuntimeError(f"no case {label} {drive} {omega2} {eps} {theta0} {load} in the data")


def _key(case: dict[str, Any], p: str) -> str:
    """The generator's key of input p in a case."""
    if p == "load":
        return "_pi" if case["drive"] == "pressure" else "_q"
    return "_" + p


def _mcase(case: dict[str, Any], shift: str | None = None, by: Any = 0) -> dict[str, Any]:
    c = gl._mp_inputs(case)
    c["_theta0"] = mpf(case["theta0"])
    if shift is not None:
        base = c[_key(case, shift)]
        c[_key(case, shift)] = base + by * max(mpf(1), abs(base))
    return c


def _values(case: dict[str, Any], h1: mpf, lnphi: mpf, shift: str | None = None, by: Any = 0):
    out = gl.newton(_mcase(case, shift, by), h1, lnphi, ORDER)
    return out["values"], out["lnphi"]


def _derivatives(case, state) -> tuple[dict[str, dict[str, str]], mpf]:
    mp.dps = DPS
    h1 = mpf(state["tip_height"])
    lnphi = mpmath.log(mp.pi / 2 - mpf(state["tip_angle"]))
    base, lnphi = _values(case, h1, lnphi)
    h1 = base["tip_height"]
    table: dict[str, dict[str, str]] = {f: {} for f in FIELDS}
    worst = mpf(0)
    for p in INPUTS:
        scale = max(mpf(1), abs(_mcase(case)[_key(case, p)]))
        diffs = []
        for step in (DELTA, 10 * DELTA):
            up, _ = _values(case, h1, lnphi, p, step)
            down, _ = _values(case, h1, lnphi, p, -step)
            diffs.append({f: (up[f] - down[f]) / (2 * step * scale) for f in FIELDS})
        for f in FIELDS:
            a, b = diffs[0][f], diffs[1][f]
            err = abs(a - b) / max(mpf(1), abs(a))
            worst = max(worst, err)
            if err > AGREE_TOL:
                raise RuntimeError(f"{case['label']}: d{f}/d{p} steps differ by {err}")
            table[f][p] = mp.nstr(a, OUT_DIGITS)
    return table, worst


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    args = parser.parse_args(argv)
    start = time.time()
    cases = []
    worst = mpf(0)
    for spec in CASES:
        t0 = time.time()
        case = _reference_case(*spec)
        states = []
        for state in case["states"]:
            table, err = _derivatives(case, state)
            worst = max(worst, err)
            states.append(
                {"tip_height": state["tip_height"], "stable": state["stable"], "d": table}
            )
        public = {k: case[k] for k in gl.INPUT_KEYS}
        cases.append({**public, "states": states, "seconds": round(time.time() - t0, 1)})
        print(f"{spec[0]:<24} {len(states)} state(s) {time.time() - t0:6.1f} s", flush=True)
    out = {
        "generator": "tests/reference/generate_loaded_derivatives.py",
        "mpmath": mpmath.__version__,
        "dps": DPS,
        "delta": mp.nstr(DELTA, 3),
        "inputs": list(INPUTS),
        "note": "central differences of the mpmath states of loaded_mpmath.json; 'load' is pi "
        "(pressure drive) or q (flow drive); steps relative to max(1, abs(input))",
        "worst_step_disagreement": mp.nstr(worst, 3),
        "generation_seconds": round(time.time() - start, 1),
        "cases": cases,
    }
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {args.out} ({len(cases)} cases, worst {mp.nstr(worst, 3)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
