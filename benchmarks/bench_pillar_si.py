"""Cost of the SI pillar sensor (hairbed.Pillar) over the dimensionless core, as ratios
measured in one run.

Rows (each the best of ``--repeat`` runs):

1. one state: ``Pillar.deform`` (scalar) over ``hairbed.solve_pillar`` on the same forcing;
2. a 10^4-point calibration curve in SI (``Pillar.deform``) over ``solve_pillar``;
3. 10^3 deflections to tau_w (``Pillar.wall_shear_stress_from_tip_deflection``) over
   ``solve_pillar_inverse``;
4. one calibration (``calibration.fit`` of E to 8 points) and ``Pillar.linear_range(0.01)``
   [s], with their ratio to one state.

Run: ``python benchmarks/bench_pillar_si.py [--quick] [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import hairbed
from hairbed import calibration, safe_files

__all__ = ["main", "run"]

PILLAR = hairbed.Pillar(
    length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3, base_angle=0.3
)


def _best(func: Callable[[], Any], repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False, repeat: int = 5) -> dict[str, Any]:
    """Every row's times [s] and ratios."""
    p, k = PILLAR, PILLAR.forcing_per_stress
    core = {"theta0": p.base_angle, "gamma": p.drag_ratio}
    n_curve = 1000 if quick else 10_000
    n_inv = 100 if quick else 1000
    tau = np.geomspace(1e-3, 1e3, n_curve) / k
    d = np.asarray(p.deform(tau[:: n_curve // n_inv]).tip_deflection)
    p.deform(1.0)  # compile / load the cache outside the timings
    rows: dict[str, Any] = {}
    t_si = _best(lambda: p.deform(5.0 / k), repeat * 20)
    t_core = _best(lambda: hairbed.solve_pillar(5.0, **core), repeat * 20)
    rows["one_state"] = {"si_s": t_si, "core_s": t_core, "ratio": t_si / t_core}
    t_si = _best(lambda: p.deform(tau), repeat)
    t_core = _best(lambda: hairbed.solve_pillar(tau * k, **core), repeat)
    rows["curve"] = {"num": n_curve, "si_s": t_si, "core_s": t_core, "ratio": t_si / t_core}
    t_si = _best(lambda: p.wall_shear_stress_from_tip_deflection(d), repeat)
    t_core = _best(lambda: hairbed.solve_pillar_inverse(d / p.length, **core), repeat)
    rows["inverse"] = {"num": d.size, "si_s": t_si, "core_s": t_core, "ratio": t_si / t_core}
    pts = np.linspace(1.0, 120.0, 8)
    dd = p.deform(pts).tip_deflection
    guess = hairbed.Pillar(
        length=500e-6, radius=25e-6, youngs_modulus=1.3e6, viscosity=1e-3, base_angle=0.3
    )
    t_fit = _best(lambda: calibration.fit(guess, dd, wall_shear_stress=pts, sigma=1e-7), repeat)
    t_lr = _best(lambda: p.linear_range(0.01), max(1, repeat // 2))
    one = rows["one_state"]["si_s"]
    rows["fit"] = {"s": t_fit, "per_state": t_fit / one}
    rows["linear_range"] = {"s": t_lr, "per_state": t_lr / one}
    return {"hairbed": hairbed.__version__, "numpy": np.__version__, "rows": rows}


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    out = run(args.quick, args.repeat)
    for name, row in out["rows"].items():
        shown = ", ".join(f"{k} = {v:.4g}" for k, v in row.items())
        print(f"{name:13s} {shown}")
    if args.json:  # written whole or not at all
        safe_files.write_bytes(args.json, json.dumps(out, indent=1).encode())
    return 0


if __name__ == "__main__":
    sys.exit(main())
