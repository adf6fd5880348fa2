"""Speed of the isolated pillar (issue 21), as ratios measured in one run.

Rows:

1. one pillar state (``hairbed.solve_pillar``, a scalar call: validation, profile, closed-form
   start, collocation) [ms];
2. ``scipy.integrate.solve_bvp`` on the same state (theta, theta', x, z, F_x, F_z with
   F(1) = 0) at the same 1e-10 accuracy (its tol tightened until its tip values are within
   1e-10 of the collocation's, checked and reported), and the ratio of the two times;
3. a calibration curve of 10^4 points, Lambda from 1e-3 to 1e3 (one call, one thread) [s],
   with its CPU time and mean Newton iterations; the same curve by the path before the
   curves (no state started from its neighbour: the closed-form start for each), with the
   ratios of wall and CPU time and the largest difference of the states; the curve in two
   halves on two Python threads (the kernels release the GIL) against one;
4. its inverse, 10^4 tip deflections to Lambda (``solve_pillar_inverse``: each state from the
   branch-grid start, not as a curve) [s], with its CPU time, on one and on two threads.

Each time is the best of ``--repeat`` runs, all in one run (the machine's load changes the
times, not much their ratios; the load average is reported). Targets (issue 21): row 1
<= 1 ms, row 2 >= 20x, row 3 <= 2 s.

Run: ``python benchmarks/bench_pillar.py [--quick] [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
from bench_common import best, best_cpu, report
from scipy.integrate import solve_bvp

import hairbed
from hairbed._core import pillar

__all__ = ["main", "run"]

#: The state of rows 1 and 2: a sublayer pillar at L/a = 20, tilted downstream.
GAMMA = float(hairbed.gray_hancock_ratio(20.0))
STATE = {"forcing": 5.0, "theta0": 0.3, "gamma": GAMMA}


def _bvp(forcing: float, theta0: float, gamma: float, tol: float) -> Any:
    """solve_bvp on (theta, theta', x, z, F_x, F_z), U = z, from the pillar at rest."""

    def fun(s: Any, y: Any) -> Any:
        th, m, _, z, fx, fz = y
        c, sn = np.cos(th), np.sin(th)
        lx = forcing * z * (c * c + gamma * sn * sn)
        lz = -forcing * z * (1.0 - gamma) * sn * c
        return np.vstack([m, -(fx * c - fz * sn), sn, c, -lx, -lz])

    def bc(ya: Any, yb: Any) -> Any:
        return np.array([ya[0] - theta0, yb[1], ya[2], ya[3], yb[4], yb[5]])

    s = np.linspace(0.0, 1.0, 11)
    y = np.vstack(
        [theta0 + 0 * s, 0 * s, s * math.sin(theta0), s * math.cos(theta0), 0 * s, 0 * s]
    )
    return solve_bvp(fun, bc, s, y, tol=tol, max_nodes=1_000_000)


def run(repeat: int = 5, size: int = 10_000) -> dict[str, Any]:
    """Every row; a dict of the figures."""
    hairbed.solve_pillar(**STATE)  # compile or load the kernels
    t_one, st = best(lambda: hairbed.solve_pillar(**STATE), max(repeat, 20))
    tips = np.array([st.tip_height, st.tip_deflection, st.tip_angle])
    tol, bvp_err, sol = 1e-6, math.inf, None
    while tol >= 1e-14:
        sol = _bvp(**STATE, tol=tol)
        got = np.array([sol.sol(1.0)[3], sol.sol(1.0)[2], sol.sol(1.0)[0]])
        bvp_err = float(np.max(np.abs(got - tips)))
        if sol.success and bvp_err <= 1e-10:
            break
        tol /= 10.0
    t_bvp, _ = best(lambda: _bvp(**STATE, tol=tol), max(1, repeat // 2))
    lam = np.geomspace(1e-3, 1e3, size)
    hairbed.solve_pillar(lam[:4], 0.0, gamma=GAMMA)

    def curve() -> Any:
        return hairbed.solve_pillar(lam, 0.0, gamma=GAMMA)

    def inverse() -> Any:
        return hairbed.solve_pillar_inverse(x1, 0.0, gamma=GAMMA)

    t_curve, cpu_curve, st_curve = best_cpu(curve, repeat)
    x1 = np.asarray(st_curve.tip_deflection)
    t_inv, cpu_inv, st_inv = best_cpu(inverse, repeat)
    with _cold():
        t_cold, cpu_cold, st_cold = best_cpu(curve, repeat)
    t_two, cpu_two, _ = best_cpu(lambda: _threads(lam, "forward"), repeat)
    t_inv_two, cpu_inv_two, _ = best_cpu(lambda: _threads(x1, "inverse"), repeat)
    round_trip = float(np.max(np.abs(np.asarray(st_inv.forcing) / lam - 1.0)))
    status = np.ravel(st_curve.status)

    def differ(a: Any, b: Any, field: str) -> float:
        u, v = np.asarray(getattr(a, field)), np.asarray(getattr(b, field))
        return float(np.max(np.abs(u - v) / np.maximum(1.0, np.abs(v))))

    return {
        "hairbed": hairbed.__version__,
        "numpy": np.__version__,
        "cpus": len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
        "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan,
        "one_state_ms": 1e3 * t_one,
        "one_state_error_estimate": st.error_estimate,
        "solve_bvp_tol": tol,
        "solve_bvp_max_tip_difference": bvp_err,
        "solve_bvp_nodes": int(sol.x.size) if sol is not None else 0,
        "solve_bvp_ms": 1e3 * t_bvp,
        "speedup_vs_solve_bvp": t_bvp / t_one,
        "curve_size": size,
        "curve_s": t_curve,
        "curve_cpu_s": cpu_curve,
        "curve_mean_nit": float(np.mean(st_curve.nit)),
        "curve_status_counts": {
            int(k): int(v) for k, v in zip(*np.unique(status, return_counts=True))
        },
        "curve_cold_s": t_cold,
        "curve_cold_cpu_s": cpu_cold,
        "curve_cold_mean_nit": float(np.mean(st_cold.nit)),
        "curve_speedup_vs_cold": t_cold / t_curve,
        "curve_cpu_ratio_vs_cold": cpu_cold / cpu_curve,
        "curve_max_difference_vs_cold": max(
            differ(st_curve, st_cold, f) for f in ("tip_deflection", "tip_height", "tip_angle")
        ),
        "curve_two_threads_s": t_two,
        "curve_two_threads_cpu_per_wall": cpu_two / t_two,
        "curve_two_threads_speedup": t_curve / t_two,
        "inverse_curve_s": t_inv,
        "inverse_curve_cpu_s": cpu_inv,
        "inverse_two_threads_s": t_inv_two,
        "inverse_two_threads_speedup": t_inv / t_inv_two,
        "inverse_round_trip_max_relative": round_trip,
    }


@contextlib.contextmanager
def _cold() -> Iterator[None]:
    """The path before the curves (issue 21): no element started from its neighbour (the
    chain's step limits set below any step), each from its closed-form start."""
    saved = pillar._CHAIN_STEP, pillar._CHAIN_ABS
    pillar._CHAIN_STEP = pillar._CHAIN_ABS = -1.0
    try:
        yield
    finally:
        pillar._CHAIN_STEP, pillar._CHAIN_ABS = saved


def _threads(values: Any, kind: str) -> list[Any]:
    """The curve in two halves (two curves), one on each of two Python threads (the kernels
    release the GIL)."""
    half = values.size // 2
    func = hairbed.solve_pillar if kind == "forward" else hairbed.solve_pillar_inverse
    with ThreadPoolExecutor(2) as pool:
        return list(pool.map(lambda v: func(v, 0.0, gamma=GAMMA), [values[:half], values[half:]]))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^3 points, 2 repeats")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args(argv)
    figures = run(repeat=2 if args.quick else args.repeat, size=1000 if args.quick else 10_000)
    rows = [
        ("one pillar state [ms] (target <= 1)", f"{figures['one_state_ms']:.3f}"),
        (
            f"solve_bvp at tol {figures['solve_bvp_tol']:.0e} [ms] "
            f"(tips within {figures['solve_bvp_max_tip_difference']:.1e}, "
            f"{figures['solve_bvp_nodes']} nodes)",
            f"{figures['solve_bvp_ms']:.1f}",
        ),
        ("speed-up vs solve_bvp (target >= 20)", f"{figures['speedup_vs_solve_bvp']:.0f}x"),
        (
            f"calibration curve of {figures['curve_size']} points, one thread [s] (target <= 2)",
            f"{figures['curve_s']:.3f}",
        ),
        ("  its CPU time [s]", f"{figures['curve_cpu_s']:.3f}"),
        ("  status counts", str(figures["curve_status_counts"])),
        ("  mean Newton iterations", f"{figures['curve_mean_nit']:.2f}"),
        ("  the path without neighbour starts [s]", f"{figures['curve_cold_s']:.3f}"),
        ("  its CPU time [s]", f"{figures['curve_cold_cpu_s']:.3f}"),
        ("  its mean Newton iterations", f"{figures['curve_cold_mean_nit']:.2f}"),
        ("  speed-up vs that path (wall, CPU)", _pair(figures, "curve")),
        (
            "  largest difference of x1, h1, theta1 from that path",
            f"{figures['curve_max_difference_vs_cold']:.1e}",
        ),
        ("  two threads (two half curves) [s]", f"{figures['curve_two_threads_s']:.3f}"),
        ("  two threads vs one", f"{figures['curve_two_threads_speedup']:.2f}x"),
        ("  CPU/wall with two threads", f"{figures['curve_two_threads_cpu_per_wall']:.2f}"),
        ("its inverse, tip deflection -> Lambda [s]", f"{figures['inverse_curve_s']:.3f}"),
        ("  its CPU time [s]", f"{figures['inverse_curve_cpu_s']:.3f}"),
        ("  two threads vs one", f"{figures['inverse_two_threads_speedup']:.2f}x"),
        (
            "  round trip, max relative change of Lambda",
            f"{figures['inverse_round_trip_max_relative']:.1e}",
        ),
        (f"load average ({figures['cpus']} CPUs)", f"{figures['load_average']:.1f}"),
    ]
    report(rows, figures, args.json)
    return 0


def _pair(figures: dict[str, Any], key: str) -> str:
    """The wall and CPU time ratios of the path before the curves to the curves'."""
    wall = figures[f"{key}_speedup_vs_cold"]
    cpu = figures[f"{key}_cpu_ratio_vs_cold"]
    return f"{wall:.2f}x, {cpu:.2f}x"


if __name__ == "__main__":
    sys.exit(main())
