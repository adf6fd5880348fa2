"""Cost of a pillar state's exact derivatives (issue 21), as ratios measured in one run.

Rows:

1. one pillar state (``hairbed.solve_pillar``, scalar call) [ms];
2. its derivatives in every input (``hairbed.sensitivity.derivatives_at``: one LU, five
   right-hand sides, six outputs) [ms], and the ratio to row 1;
3. the Richardson central differences the tests compare them with (two steps, four solves
   per input, four inputs) [ms], and the ratio to row 2;
4. a batch of 1000 states, the derivatives per state [us] (Lambda from 1e-3 to 1e3);
5. a calibration with base_angle and youngs_modulus free (9 points) [ms].

Each time is the best of ``--repeat`` runs.

Run: ``python benchmarks/bench_pillar_derivatives.py [--quick] [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import hairbed
from hairbed import calibration
from hairbed.sensitivity import derivatives_at

__all__ = ["main", "run"]

GAMMA = float(hairbed.gray_hancock_ratio(20.0))
STATE = {"forcing": 5.0, "theta0": 0.3, "gamma": GAMMA}


def _best(func: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _richardson() -> None:
    for name in ("forcing", "theta0", "gamma", "tip_load"):
        for h in (1e-3, 5e-4):
            for sgn in (1.0, -1.0):
                args = dict(STATE, tip_load=0.0)
                args[name] += sgn * h
                hairbed.solve_pillar(**args)


def run(repeat: int = 5, size: int = 1000) -> dict[str, Any]:
    """Every row; a dict of the figures."""
    st = hairbed.solve_pillar(**STATE)
    derivatives_at(st)  # compile or load the kernels
    t_one, _ = _best(lambda: hairbed.solve_pillar(**STATE), max(repeat, 20))
    t_der, _ = _best(lambda: derivatives_at(st), max(repeat, 20))
    t_fd, _ = _best(_richardson, repeat)
    lam = np.geomspace(1e-3, 1e3, size)
    batch = hairbed.solve_pillar(lam, 0.0, gamma=GAMMA)
    t_batch, d = _best(lambda: derivatives_at(batch), repeat)
    pillar = hairbed.Pillar(
        length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3, base_angle=0.2
    )
    true = hairbed.Pillar(
        length=500e-6, radius=25e-6, youngs_modulus=1.3e6, viscosity=1e-3, base_angle=0.3
    )
    tau = np.linspace(0.5, 150.0, 9)
    dd = calibration.model_tip_deflection(true, wall_shear_stress=tau)

    def fit() -> Any:
        return calibration.fit(
            pillar, dd, wall_shear_stress=tau, sigma=1e-8, free="youngs_modulus,base_angle"
        )

    t_fit, res = _best(fit, repeat)
    return {
        "hairbed": hairbed.__version__,
        "cpus": len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
        "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan,
        "one_state_ms": 1e3 * t_one,
        "derivatives_ms": 1e3 * t_der,
        "derivatives_over_state": t_der / t_one,
        "richardson_ms": 1e3 * t_fd,
        "richardson_over_derivatives": t_fd / t_der,
        "batch_size": size,
        "batch_us_per_state": 1e6 * t_batch / size,
        "batch_status_counts": {
            int(k): int(v) for k, v in zip(*np.unique(np.ravel(d.status), return_counts=True))
        },
        "fit_ms": 1e3 * t_fit,
        "fit_nfev": int(res.nfev),
        "fit_success": bool(res.success),
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="100 states, 2 repeats")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args(argv)
    figures = run(repeat=2 if args.quick else args.repeat, size=100 if args.quick else 1000)
    for key, value in figures.items():
        print(f"{key:>28}  {value:.4g}" if isinstance(value, float) else f"{key:>28}  {value}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(figures, fh, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
