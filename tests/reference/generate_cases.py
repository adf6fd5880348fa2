"""Generate the second high-precision reference set, ``tests/data/reference_cases.json``.

Run on demand (a few minutes on two cores; ``make reference`` runs it with the others)::

    .venv/bin/python tests/reference/generate_cases.py [--workers 2] [--out PATH] [--compare PATH]

The inputs below are those of an independent reference set made for this project in 30-digit
mpmath arithmetic (60 and more digits at huge forcing) from the reduced closed forms, a sample
re-derived by Taylor-series integration of the ODE with ``mpmath.odefun``. This script
recomputes every value with the machinery of ``generate_reference.py`` (route A: Carlson forms
with p = (1 - xi)/2 explicit, every root of the branch bracketed and refined; the precision and
Legendre-form checks of ``compute_case``), so the data can be regenerated and extended here;
``--compare`` reports the agreement, in significant digits, with another file of the same
layout (such as the original set) and records it in the output's ``metadata``. When first
generated (2026-12-01) the two sets agreed to at least 18.6 significant digits on every one of
their values, the limit of their 20-digit rounding. Nothing from :mod:`hairbed` is imported.

Sections of the output (every computed number a string with 20 significant digits):

* ``forward``: the physical branch (sign +1, n 0); ``solutions`` lists every root in
  increasing xi (three in the bistable cases), each with xi, omega_eps, energy, tip_height,
  tip_deflection, tip_angle, base_curvature, sign, n;
* ``branches``: other branches; ``solutions`` may be empty where the branch has no state;
* ``huge``: very strong forcing, where xi rounds to 1 in double precision and nothing else does;
* ``profiles``: theta(sigma) of the physical state at ``sigma``, and the tip values
  ``ode_h1`` = z(1), ``ode_x1`` = x(1), ``ode_dtheta1`` = theta'(1) of a Taylor-series
  integration of the initial value problem from theta0 and the base curvature
  (``taylor_ivp``), which shares no formula with the closed forms;
* ``inverse``: the physical state with a given tip deflection x1 (found by a bracketed root
  search of x1(t), which does not depend on eps): its tip height, xi and the forcing omega2
  that holds it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import multiprocessing
import platform
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))
from generate_reference import (  # noqa: E402
    CHECK_DPS,
    DPS,
    ODE_DPS,
    OUT_DIGITS,
    Branch,
    _fmt,
    compute_case,
    evaluate,
    find_roots,
    polish,
    taylor_ivp,
)

__all__ = ["main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "reference_cases.json"
#: Fields of each solution (the API names of hairbed.Solution).
FIELDS = (
    "xi",
    "omega_eps",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
    "energy",
)

#: Physical-branch inputs (omega2, eps, theta0); the last five lie in or near a three-state window.
FORWARD = (
    (0.0011374812, 0.320594, 0.0),
    (0.00032140602, 0.0, 0.43771),
    (0.00025467861, 0.362032, 0.104058),
    (0.1085225, 0.037121, 0.021564),
    (0.093677291, 0.089806, -1.247419),
    (0.0036531941, 0.122564, 0.947871),
    (1.0957731, 0.938232, 0.369556),
    (0.00021187454, 0.966493, -0.299627),
    (0.0010227879, 0.286713, 1.039559),
    (51.627906, 0.305397, -1.108403),
    (1.1781515, 0.178919, 0.0),
    (0.04043736, 0.0, 0.402849),
    (0.00026134139, 0.062161, 0.138459),
    (0.098434228, 0.673596, -0.85272),
    (0.14869304, 0.579706, -0.538973),
    (7.8155768, 0.786436, -0.580676),
    (0.47465223, 0.568679, -0.74212),
    (0.010364882, 0.722151, 1.087899),
    (0.084500592, 0.116885, 1.392507),
    (0.26469254, 0.150465, 0.745709),
    (4.7589484, 0.038815, 0.0),
    (1.0260808, 0.0, 0.767256),
    (7.3632164, 0.31061, 1.088886),
    (0.15611237, 0.574096, 0.273673),
    (0.20829956, 0.935234, 0.985907),
    (8.1366222, 0.060063, 0.476041),
    (56.685699, 0.983165, 0.426674),
    (4.792576, 0.381934, -0.624673),
    (0.0015008547, 0.457078, -1.384568),
    (23.857829, 0.058365, -1.110422),
    (0.0054113277, 0.128047, 0.0),
    (125.87915, 0.0, -0.316246),
    (0.7015835, 0.444696, -1.216314),
    (111.65837, 0.811087, 1.111813),
    (0.032463711, 0.411144, -0.642579),
    (0.0011387971, 0.948154, 1.114159),
    (0.0042988529, 0.229637, -0.938969),
    (0.0069059962, 0.583232, -0.043608),
    (0.038439259, 0.414757, -1.438129),
    (6.814839, 0.943567, 0.19239),
    (1.2, 0.9, -1.5),
    (0.8, 0.95, -1.2),
    (0.31, 0.95, -1.0),
    (1.65, 0.61, -1.45),
    (0.0355, 0.99, -0.5),
)
#: Other branches (omega2, eps, theta0, sign, n); some have no state at these inputs.
BRANCHES = (
    (89.030772, 0.555833, 0.030983, 1, 1),
    (133.64359, 0.80958, -0.892014, 1, 2),
    (29.311912, 0.718086, 0.749026, -1, 0),
    (75.560054, 0.093183, -0.202042, -1, 1),
    (14.285565, 0.060613, -0.875504, 1, 1),
    (7.751371, 0.306048, -0.675394, 1, 2),
    (9.386192, 0.136138, -0.999533, -1, 0),
    (193.359289, 0.022951, -0.27278, -1, 1),
)
#: Huge forcing (omega2, eps, theta0): xi rounds to 1 in double precision, the rest does not.
HUGE = (
    (10000.0, 0.5, 0.0),
    (10000.0, 0.3, 0.7),
    (10000.0, 0.8, -0.9),
)
#: Profiles on the physical branch (omega2, eps, theta0), tabulated at PROFILE_SIGMA.
PROFILES = (
    (0.0011374812, 0.320594, 0.0),
    (0.0010227879, 0.286713, 1.039559),
    (0.47465223, 0.568679, -0.74212),
    (0.20829956, 0.935234, 0.985907),
    (0.7015835, 0.444696, -1.216314),
)
PROFILE_SIGMA = (0.1, 0.37, 0.5, 0.83, 1.0)
#: Inverse problems (eps, theta0, tip deflection x1 as a decimal string, read exactly).
INVERSE = (
    (0.141123, 0.296579, "0.41740035763703235923"),
    (0.345955, -0.396787, "-0.25995914609865983088"),
    (0.943448, 0.907236, "0.85649253851024035436"),
    (0.08159, -0.04203, "0.040062194667020282283"),
    (0.251519, -0.409147, "0.4039303550823172471"),
    (0.021941, -0.88026, "0.41512744035086395878"),
    (0.139272, 0.073469, "0.41756880199216403128"),
    (0.501704, -1.22969, "0.38424279768771959704"),
    (0.661387, 0.944645, "0.84518435190439239312"),
    (0.15869, -0.346581, "0.36955517417359470204"),
    (0.740102, 0.08474, "0.29236043338580438259"),
    (0.770936, -0.720092, "0.5468454909020956759"),
    (0.765775, 0.916835, "0.91595000936994131431"),
    (0.215403, 0.62367, "0.73325540585138432279"),
    (0.027531, -0.375537, "-0.32424636599979428323"),
    (0.246216, -0.573512, "0.16871679136532356037"),
    (0.424866, 1.186939, "0.97893732413584526423"),
    (0.907251, 1.268899, "0.96627148191991538582"),
    (0.215504, -0.726798, "-0.4395683886764860934"),
    (0.592863, -0.768629, "0.35788895979096755725"),
    (0.4555, 0.885132, "0.87779882186009407231"),
    (0.08054, 0.779074, "0.84070236760431342029"),
    (0.743188, 1.065421, "0.94204656439435970406"),
    (0.169596, -0.057115, "0.52637237636086162331"),
    (0.760782, -0.435455, "0.60160777840876747238"),
    (0.381317, -0.27082, "0.61217659032034038635"),
    (0.161503, 0.584477, "0.59450594396835708195"),
    (0.859609, -0.907008, "0.16091940342622284898"),
    (0.785185, -0.919947, "0.47559865243394512455"),
    (0.332887, 0.408898, "0.62598356013730597733"),
)


# ------------------------------------------------------------------------------------------
# Computation (one task per input, run in a worker)
# ------------------------------------------------------------------------------------------


def _solutions(omega2: float, eps: float, theta0: float, sign: int, n: int) -> list[dict]:
    case = {
        "id": f"w{omega2:g}-e{eps:g}-t{theta0:g}-s{sign:+d}-n{n}",
        "group": "cases",
        "omega2": omega2,
        "eps": eps,
        "theta0": theta0,
        "sign": sign,
        "n": n,
    }
    result = compute_case(case)  # every root, with the precision and Legendre checks
    out = []
    for root in result["roots"]:
        entry = {k: root[k] for k in FIELDS}
        entry["sign"], entry["n"] = sign, n
        out.append(entry)
    return out


def _physical_root(omega2: float, eps: float, theta0: float) -> tuple[Branch, mpf]:
    """The lowest-xi root of the physical branch, at CHECK_DPS."""
    mp.dps = DPS
    br = Branch(omega2, eps, theta0, 1, 0)
    ts, _ = find_roots(br)
    t = polish(br, ts[0], mpf(10) ** (-25))
    mp.dps = CHECK_DPS
    br = Branch(omega2, eps, theta0, 1, 0)
    return br, polish(br, +t, mpf(10) ** (-(DPS - 8)))


def _profile(omega2: float, eps: float, theta0: float) -> dict[str, Any]:
    br, t = _physical_root(omega2, eps, theta0)
    vals = evaluate(br, t, PROFILE_SIGMA)
    mp.dps = ODE_DPS
    w, dtheta0 = +vals["omega_eps"], +vals["base_curvature"]
    prof, _ = taylor_ivp(w, mpf(theta0), dtheta0, (1.0,), order=2 * ODE_DPS)
    _, dtheta1, x1, z1 = prof[-1]
    mp.dps = CHECK_DPS
    return {
        "omega2": omega2,
        "eps": eps,
        "theta0": theta0,
        "sigma": list(PROFILE_SIGMA),
        "theta": [_fmt(v) for v in vals["theta"]],
        "ode_h1": _fmt(z1),
        "ode_x1": _fmt(x1),
        "ode_dtheta1": _fmt(dtheta1),
    }


def _inverse(eps: float, theta0: float, x1_text: str) -> dict[str, Any]:
    mp.dps = CHECK_DPS
    target = mpf(x1_text)
    br = Branch(0.0, eps, theta0, 1, 0)  # x1(t) does not depend on omega2 or eps

    def gap(t: mpf) -> mpf:
        return evaluate(br, t, ())["tip_deflection"] - target

    lo, hi = mpf(-4), mpf(4)
    while gap(lo) > 0:
        lo *= 2
    while gap(hi) < 0:
        hi *= 2
    for _ in range(60):  # bisection to a narrow bracket, then the secant-type solver
        mid = (lo + hi) / 2
        if gap(mid) < 0:
            lo = mid
        else:
            hi = mid
    t = mp.findroot(gap, (lo, hi), solver="anderson", tol=mpf(10) ** (-(CHECK_DPS - 10)))
    vals = evaluate(br, t, ())
    if abs(vals["tip_deflection"] - target) > mpf(10) ** (-(CHECK_DPS - 15)):
        raise RuntimeError(f"inverse did not converge for {(eps, theta0, x1_text)}")
    w, h1 = vals["omega_eps"], vals["tip_height"]
    return {
        "eps": eps,
        "theta0": theta0,
        "tip_deflection": x1_text,
        "tip_height": _fmt(h1),
        "omega2": _fmt(w * w * (1 - mpf(eps) * h1)),
        "xi": _fmt(vals["xi"]),
    }


def _task(item: tuple[str, tuple]) -> tuple[str, dict[str, Any]]:
    section, args = item
    if section in ("forward", "huge"):
        w, e, th = args
        return section, {"omega2": w, "eps": e, "theta0": th, "solutions": _solutions(*args, 1, 0)}
    if section == "branches":
        w, e, th, sign, n = args
        out = {"omega2": w, "eps": e, "theta0": th, "sign": sign, "n": n}
        out["solutions"] = _solutions(*args)
        return section, out
    if section == "profiles":
        return section, _profile(*args)
    return section, _inverse(*args)


# ------------------------------------------------------------------------------------------
# Comparison with another file of the same layout
# ------------------------------------------------------------------------------------------


def _numbers(entry: dict[str, Any], prefix: str = "") -> dict[str, str]:
    out: dict[str, str] = {}
    for key, value in entry.items():
        if isinstance(value, str):
            out[prefix + key] = value
        elif isinstance(value, list):
            for i, v in enumerate(value):
                if isinstance(v, dict):
                    out.update(_numbers(v, f"{prefix}{key}[{i}]."))
                elif isinstance(v, str):
                    out[f"{prefix}{key}[{i}]"] = v
    return out


def compare(ours: dict[str, Any], other: dict[str, Any]) -> tuple[float, str]:
    """Fewest significant digits on which the two files agree, and where."""
    mp.dps = 40
    worst, where = mpf(40), ""
    for section in ("forward", "branches", "huge", "profiles", "inverse"):
        if len(ours[section]) != len(other[section]):
            raise ValueError(
                f"{section}: {len(ours[section])} entries, other has {len(other[section])}"
            )
        for k, (a, b) in enumerate(zip(ours[section], other[section])):
            na, nb = _numbers(a), _numbers(b)
            if set(na) != set(nb):
                raise ValueError(f"{section}[{k}]: different values {sorted(set(na) ^ set(nb))}")
            for key in na:
                x, y = mpf(na[key]), mpf(nb[key])
                scale = max(abs(x), abs(y))
                if scale == 0 or x == y:
                    continue
                # relative for ordinary values, absolute near zero (theta'(1) ~ 1e-31)
                err = abs(x - y) / (scale if scale > mpf(10) ** -12 else 1)
                digits = -mp.log10(err)
                if digits < worst:
                    worst, where = digits, f"{section}[{k}].{key}: {na[key]} vs {nb[key]}"
    return float(mp.nstr(worst, 4)), where


# ------------------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    parser.add_argument("--compare", type=Path, metavar="PATH", help="report the agreement")
    args = parser.parse_args(argv)
    items = (
        [("forward", a) for a in FORWARD]
        + [("branches", a) for a in BRANCHES]
        + [("huge", a) for a in HUGE]
        + [("profiles", a) for a in PROFILES]
        + [("inverse", a) for a in INVERSE]
    )
    start = time.time()
    with multiprocessing.Pool(args.workers) as pool:
        results = pool.map(_task, items, chunksize=1)
    data: dict[str, Any] = {"metadata": {}}
    for section in ("forward", "branches", "huge", "profiles", "inverse"):
        data[section] = [r for s, r in results if s == section]
    data["metadata"] = {
        "about": "Second high-precision reference set for the boundary-hair problem "
        "(docs/theory.md sections 2 and 3; API names of hairbed). Its inputs are those of an "
        "independent set made for the project in 30-digit mpmath arithmetic (60 and more at "
        "huge forcing) from the reduced closed forms, a sample re-derived by Taylor-series "
        "integration of the ODE; every value here is recomputed from them by "
        "tests/reference/generate_cases.py (mpmath only, nothing from hairbed).",
        "generator": "tests/reference/generate_cases.py (make reference)",
        "mpmath_version": mpmath.__version__,
        "python_version": platform.python_version(),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "dps": {"roots_and_values": CHECK_DPS, "ode": ODE_DPS},
        "significant_digits_written": OUT_DIGITS,
        "generation_seconds": round(time.time() - start, 1),
        "sections": {
            "forward": "physical branch (sign +1, n 0); solutions: every root, increasing xi",
            "branches": "other branches; solutions may be empty",
            "huge": "very strong forcing; xi rounds to 1 in double precision",
            "profiles": "theta at sigma on the physical branch; ode_*: tip values of a "
            "Taylor-series integration of the initial value problem",
            "inverse": "physical state with the given tip deflection: tip_height, xi, omega2",
        },
    }
    if args.compare:
        other = json.loads(args.compare.read_text())
        digits, where = compare(data, other)
        data["metadata"]["agreement_with_original_set"] = (
            f"at least {digits} significant digits on every value (worst: {where})"
        )
        print(f"agreement with {args.compare}: {digits} digits (worst: {where})")
    text = json.dumps(data, indent=1) + "\n"
    tmp = args.out.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(args.out)  # written whole or not at all
    print(f"wrote {args.out} ({sum(len(v) for k, v in data.items() if k != 'metadata')} entries)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
