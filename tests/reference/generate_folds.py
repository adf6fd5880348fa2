"""Generate ``tests/data/folds_mpmath.json``: the folds in nearly closed channels, in mpmath.

Run on demand (a few minutes on two cores)::

    .venv/bin/python tests/reference/generate_folds.py [--workers 2] [--out PATH]

It imports nothing from :mod:`hairbed`; the branch, its folds and its roots come from
``generate_reference.py`` and ``generate_corners.py`` (route A: Carlson forms with p explicit).
Two groups, tested by ``tests/test_branches.py``:

* ``near_folds``: the physical branch at eps = 0.99, 0.995, 0.999 and base angles from -0.6 to
  -pi/2 + 3e-8, at forcings omega2 = omega2_f (1 -+ delta) (rounded to a double) a relative
  delta = 1e-8, 1e-10, 1e-12, 1e-14 inside the three-state window from either fold. Every root
  (xi, tip angle, tip deflection, tip height, omega_eps, t) at 50 digits and, for each, the
  largest change of each field when one input (omega2, eps or theta0) moves by one ulp: near a
  fold the state is ill-conditioned in omega2, and a double-precision solver can do no better
  than that change. (Within a few ulp of a fold, delta ~ 3e-16, one ulp of eps or theta0
  already removes the pair of roots; such forcings are not tabulated.)
  The fold structure of the perturbed inputs is recomputed (branch_structure); a move that takes
  roots out of the window (within 3e-8 of theta0 = -pi/2 one ulp of theta0 moves the upper fold
  by more than 1e-12) is listed in ``removes_roots`` and the change is the largest over the
  other moves (one ulp of omega2 always keeps the roots), a lower bound.
* ``cusp``: eps_c(theta0) = min_t G(t), G = 2 g/(h1 (g + expit(-t)/2)) with
  g = d ln(omega_eps)/dt (the confinement at which d ln(omega2)/dt has a double zero), for base
  angles from -1 to -pi/2 + 1e-10; the minimum is found on a grid of step 1/4 and refined as
  the zero of dG/dt at 40 digits, and checked again at 60 digits (30 digits of agreement).

Every computed number is written as a string with 20 significant digits.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import multiprocessing
import sys
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))
import generate_corners as gc  # noqa: E402
import generate_reference as gr  # noqa: E402

__all__ = ["build_tasks", "main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "folds_mpmath.json"
OUT_DIGITS = 20
#: Working precision of the roots [decimal digits].
ROOT_DPS = 50
FIELDS = ("xi", "tip_angle", "tip_deflection", "tip_height", "omega_eps")
EPS_VALUES = (0.99, 0.995, 0.999)
THETA0_VALUES = (-0.6, -1.0, -1.5, -1.5707963)
DELTAS = (1e-8, 1e-10, 1e-12, 1e-14)
CUSP_THETA0 = (-1.0, -1.5, -1.57, -1.5707, -1.570796, -1.5707963, -1.57079632, -1.5707963267)


def _fmt(v: mpf) -> str:
    return mp.nstr(v, OUT_DIGITS)


def _roots(s: dict[str, Any], omega2: float) -> list[dict[str, mpf]]:
    """Every root on the branch tabulated in ``s`` at omega2, with its fields."""
    ts = gc.roots_on_branch(s, omega2, ROOT_DPS)
    mp.dps = ROOT_DPS
    br = gr.Branch(omega2, s["eps"], s["theta0"], 1, 0)
    out = []
    for t in ts:
        vals = gr.evaluate(br, t, ())
        out.append({"t": t, **{f: vals[f] for f in FIELDS}})
    return out


def task_cell(eps: float, theta0: float) -> list[dict[str, Any]]:
    """The near-fold cases of one (eps, theta0)."""
    s = gc.branch_structure(eps, theta0)
    perturbed = [
        (1, gc.branch_structure(math.nextafter(eps, 2.0), theta0), "eps+"),
        (1, gc.branch_structure(math.nextafter(eps, 0.0), theta0), "eps-"),
        (1, gc.branch_structure(eps, math.nextafter(theta0, 0.0)), "theta0+"),
        (1, gc.branch_structure(eps, math.nextafter(theta0, -2.0)), "theta0-"),
    ]
    cases = []
    for fold in s["folds"]:
        inward = -1 if fold["kind"] == "max" else 1
        for delta in DELTAS:
            omega2 = float(fold["omega2"] * (1 + inward * mpf(delta)))
            roots = _roots(s, omega2)
            moved = [
                _roots(s, math.nextafter(omega2, math.inf)),
                _roots(s, math.nextafter(omega2, 0.0)),
            ]
            moved += [_roots(p, omega2) for _, p, _ in perturbed]
            names = ["omega2+", "omega2-"] + [name for _, _, name in perturbed]
            kept = [m for m in moved if len(m) == len(roots)]
            removes = [name for name, m in zip(names, moved) if len(m) != len(roots)]
            packed = []
            for k, r in enumerate(roots):
                # over the one-ulp moves that keep every root: a lower bound of the change
                # where a move takes the root out of the window (``removes_roots``)
                change = {f: _fmt(max(abs(m[k][f] - r[f]) for m in kept)) for f in ("t", *FIELDS)}
                packed.append({**{f: _fmt(v) for f, v in r.items()}, "rounding_change": change})
            cases.append(
                {
                    "eps": eps,
                    "theta0": theta0,
                    "fold": fold["kind"],
                    "fold_omega2": _fmt(fold["omega2"]),
                    "delta": delta,
                    "omega2": omega2,
                    "n_roots": len(roots),
                    "removes_roots": removes,
                    "roots": packed,
                }
            )
    return cases


def _g_ratio(br: gr.Branch, t: mpf) -> mpf:
    """G(t): the eps at which t is a fold of the physical branch."""
    g = mp.diff(lambda u: mp.log(br.state(u)["w"]), t)
    st = br.state(t)
    h1 = mp.sqrt(2 * st["q"]) / st["w"]
    return 2 * g / (h1 * (g + 1 / (1 + mp.exp(t)) / 2))


def _cusp_at(theta0: float, dps: int) -> tuple[mpf, mpf]:
    mp.dps = dps
    br = gr.Branch(0.0, 0.5, theta0, 1, 0)
    lo = 2 * mp.log(br.a) - 30
    ts = [lo + i * mpf("0.25") for i in range(int((20 - lo) * 4))]
    gs = [_g_ratio(br, t) for t in ts]
    k = min(range(len(gs)), key=lambda i: gs[i])
    tm = mp.findroot(lambda u: mp.diff(lambda v: _g_ratio(br, v), u), ts[k])
    assert ts[k - 1] < tm < ts[k + 1], (theta0, tm)
    return tm, _g_ratio(br, tm)


def task_cusp(theta0: float) -> dict[str, Any]:
    t_lo, e_lo = _cusp_at(theta0, 40)
    t_hi, e_hi = _cusp_at(theta0, 60)
    digits = gr._digits(abs(e_lo / e_hi - 1), 40)
    assert digits >= 30, (theta0, digits)
    return {"theta0": theta0, "eps_c": _fmt(e_hi), "t_c": _fmt(t_hi), "digits": digits}


def build_tasks() -> list[tuple]:
    tasks: list[tuple] = [("cell", e, th) for e in EPS_VALUES for th in THETA0_VALUES]
    tasks += [("cusp", th) for th in CUSP_THETA0]
    return tasks


def run_task(task: tuple) -> tuple[str, Any]:
    if task[0] == "cell":
        return "near_folds", task_cell(task[1], task[2])
    return "cusp", task_cusp(task[1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    args = parser.parse_args(argv)
    tasks = build_tasks()
    with multiprocessing.Pool(args.workers) as pool:
        results = pool.map(run_task, tasks, chunksize=1)
    near: list[dict[str, Any]] = []
    cusp: list[dict[str, Any]] = []
    for kind, value in results:
        if kind == "near_folds":
            near += value
        else:
            cusp.append(value)
    data = {
        "metadata": {
            "generator": "tests/reference/generate_folds.py",
            "mpmath": mpmath.__version__,
            "date": datetime.date.today().isoformat(),
            "root_dps": ROOT_DPS,
            "n_near_folds": len(near),
            "n_cusp": len(cusp),
        },
        "near_folds": near,
        "cusp": cusp,
    }
    tmp = args.out.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1) + "\n")
    tmp.replace(args.out)
    print(f"wrote {args.out}: {len(near)} near-fold cases, {len(cusp)} cusps")
    return 0


if __name__ == "__main__":
    sys.exit(main())
