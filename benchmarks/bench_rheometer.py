"""Speed of the bed's linear dynamics and of the rheometer (issues 30 and 31), in one run.

Rows:

1. ``linearise_bed(...).frequency_response`` at 1,000 frequencies (0.01 to 10/T, one degree
   band) about a tilted, deflected state, its Schur form built once, then again on the
   built form [ms], against one LU per frequency on the same operators (the ratio), with the
   largest difference of the two;
2. one periodic steady state by ``large_amplitude_shear`` (kappa = 1, eps = 0.5,
   omega = 1/T, gamma0 = 1, overdamped, quasi-steady fluid) [s], its periods, steps and
   periodicity (target: 1e-8 in <= 50 ms);
3. a 4 x 4 Pipkin map on one thread and on two workers [s], and the ratio (target for a
   20 x 20 map: <= 20 s on one core, two workers >= 1.8x).

Each time is the best of ``--repeat`` runs in one run; the machine's load changes the times,
less their ratios. Run: ``python benchmarks/bench_rheometer.py [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Sequence
from typing import Any

import numpy as np
from bench_common import best, report

import hairbed
from hairbed.dynamics import linearise_bed
from hairbed.rheometer import large_amplitude_shear, pipkin_map

__all__ = ["main", "run"]


def run(repeat: int = 3) -> tuple[list[tuple[str, str]], dict[str, Any]]:
    rows: list[tuple[str, str]] = []
    figs: dict[str, Any] = {"load": os.getloadavg()[0]}
    st = hairbed.solve_porous(1.0, 0.5, 0.3, kappa=0.5, gamma=0.657)
    om = np.geomspace(1e-2, 10.0, 1000)
    lin = linearise_bed(st, inertia=1.0, womersley=0.1)
    t_first, fr = best(lambda: linearise_bed(st, inertia=1.0, womersley=0.1)
                       .frequency_response(om), 1)  # fmt: skip
    lin.frequency_response(om)
    t_built, fr = best(lambda: lin.frequency_response(om), repeat)
    deg = (int(fr.num[0]), int(fr.num_gap[0]))
    ops = lin.operators(*deg)
    mass, jac = np.diag(ops.mass), ops.jacobian
    col = ops.drives["wall"].astype(complex)
    row = ops.outputs["tip_deflection"]

    def direct() -> Any:
        return np.array([row @ np.linalg.solve(1j * w * mass - jac, col) for w in om])

    t_lu, h_lu = best(direct, 1)
    diff = float(np.max(np.abs(h_lu - fr.tip_deflection) / np.abs(h_lu)))
    rows += [
        ("1. bed transfer function, 1000 freq., first call [ms]", f"{1e3 * t_first:.1f}"),
        ("   on the built Schur form [ms]", f"{1e3 * t_built:.1f} (N, M = {deg})"),
        ("   one LU per frequency [ms]", f"{1e3 * t_lu:.1f} ({t_lu / t_built:.1f}x)"),
        ("   largest relative difference", f"{diff:.1e}"),
    ]
    figs.update(first_ms=1e3 * t_first, built_ms=1e3 * t_built, lu_ms=1e3 * t_lu, diff=diff)
    t_laos, r = best(lambda: large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0), repeat)
    what = f"{r.periods} periods, {r.nsteps} steps, periodic {r.periodic_error:.1e}"
    rows.append(("2. LAOS periodic state [s]", f"{t_laos:.3f} ({what})"))
    figs.update(laos_s=t_laos, laos_periodic=r.periodic_error, laos_steps=r.nsteps)
    grid = (np.geomspace(0.1, 10.0, 4), np.geomspace(0.1, 3.0, 4))
    t1, _ = best(lambda: pipkin_map(*grid, eps=0.5, kappa=1.0, workers=1), 1)
    t2, _ = best(lambda: pipkin_map(*grid, eps=0.5, kappa=1.0, workers=2), 1)
    rows += [
        ("3. Pipkin map 4 x 4, one thread [s]", f"{t1:.2f}"),
        ("   two workers [s]", f"{t2:.2f} ({t1 / t2:.2f}x)"),
    ]
    figs.update(pipkin_1_s=t1, pipkin_2_s=t2)
    rows.append(("load average (1 min)", f"{figs['load']:.1f}"))
    return rows, figs


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    rows, figs = run(args.repeat)
    report(rows, figs, args.json)


if __name__ == "__main__":
    main()
