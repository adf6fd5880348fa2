"""The porous bed in time (issue 30, theory.md §15), measured in one run; wall times the best
of ``--repeat``, the CPU time of that run beside it (on a shared machine the wall time counts
the other processes' load, the CPU time does not).

Rows:

1. a step in the top wall's speed (omega2 0 -> 1) of the bed kappa = 0.1, eps = 0.5,
   theta0 = 0.2, gamma = 1, overdamped hairs, the quasi-steady fluid (alpha = 0, N = 32 on
   the statics' tip map), at rtol 1e-6 and 1e-8 (atol rtol/100), run to t = 8 T: the error
   of the tip deflection against the static state (``solve_porous``) at the end, and the
   first output time from which it stays below 1e-8;
2. the same with the fluid's inertia, alpha = 0.5 (the gap on M = 16);
3. the same step under a set pressure gradient Pi = 0.8 with alpha = 0.5 (the plain map;
   the impulsive start of the fluid's boundary layers);
4. an inertial hair (mu = 0.2, kappa = 1, N = 24), the wall's speed rising as
   3 (1 - cos(pi t/2))/2 over 2 T, to t = 22 T (the resistive drag damps every mode at
   1/(2 mu); every excited high mode rings as long);
5. ``bed_operators`` about the static state (N = 32, alpha = 0.5): the steady vector's
   Newton, the exact Jacobian and the outputs' rows.

(A transfer function at 1,000 frequencies on these operators is ``linearise_bed``'s, not
measured here.)

Run: ``python benchmarks/bench_bed_dynamics.py [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_common import best_cpu, report  # noqa: E402

import hairbed  # noqa: E402
from hairbed.dynamics import bed_operators, sampled, simulate_bed, step  # noqa: E402

__all__ = ["main", "run"]

_TE = np.linspace(0.0, 8.0, 161)


def _settle(run: Any, static: float) -> tuple[float, float]:
    """(the last error, the first output time from which the error stays below 1e-8)."""
    err = np.abs(run.tip_deflection - static)
    above = np.flatnonzero(~(err < 1e-8))
    t_in = float(run.t[above[-1] + 1]) if above.size and above[-1] + 1 < run.t.size else 0.0
    if above.size and above[-1] + 1 >= run.t.size:
        t_in = float("nan")
    return float(err[-1]), t_in


def run(repeat: int = 3) -> tuple[list[tuple[str, str]], dict[str, Any]]:
    """The rows and the figures."""
    rows: list[tuple[str, str]] = []
    figs: dict[str, Any] = {"load": os.getloadavg()[0]}
    simulate_bed(0.2, 0.1, 0.5, wall=step(1.0), t_eval=[0.0, 0.1], num=16)  # compile
    cases: list[tuple[str, dict[str, Any], dict[str, float]]] = [
        ("1 wall step, alpha 0", {"wall": step(1.0)}, {"omega2": 1.0}),
        ("2 wall step, alpha 0.5", {"wall": step(1.0), "womersley": 0.5}, {"omega2": 1.0}),
        (
            "3 pressure step, alpha 0.5",
            {"wall": 1.0, "pressure": step(0.8), "womersley": 0.5},
            {"omega2": 1.0, "pi": 0.8},
        ),
    ]
    for name, kw, static in cases:
        st = hairbed.solve_porous(theta0=0.2, eps=0.5, kappa=0.1, **static)
        for rtol in (1e-6, 1e-8):

            def one(kw: dict[str, Any] = kw, rtol: float = rtol) -> Any:
                return simulate_bed(
                    0.2, 0.1, 0.5, t_eval=_TE, rtol=rtol, atol=rtol / 100, num=32, **kw
                )

            wall, cpu, out = best_cpu(one, repeat)
            err, t_in = _settle(out, float(st.tip_deflection))
            key = f"{name}, rtol {rtol:g}"
            figs[key] = {
                "wall_s": wall,
                "cpu_s": cpu,
                "steps": out.nsteps,
                "njev": out.njev,
                "error_end": err,
                "t_within_1e-8": t_in,
                "status": out.status,
            }
            text = f"{1e3 * wall:8.1f} ms (cpu {1e3 * cpu:.1f}), {out.nsteps} steps, "
            text += f"{out.njev} J, error {err:.1e}, within 1e-8 from t = {t_in:g}"
            rows.append((key, text))
    tt = np.linspace(0.0, 2.0, 401)
    drive = sampled(tt, 1.5 * (1.0 - np.cos(np.pi * tt / 2.0)))
    st = hairbed.solve_porous(3.0, 0.5, 0.2, kappa=1.0)
    te = np.linspace(0.0, 22.0, 111)
    wall, cpu, out = best_cpu(
        lambda: simulate_bed(
            0.2, 1.0, 0.5, wall=drive, inertia=0.2, t_eval=te, rtol=1e-5, atol=1e-6, num=24
        ),  # fmt: skip
        repeat,
    )
    err, t_in = _settle(out, float(st.tip_deflection))
    figs["4 inertial hair"] = {"wall_s": wall, "cpu_s": cpu, "steps": out.nsteps,
                               "error_end": err, "t_within_1e-8": t_in}  # fmt: skip
    rows.append(("4 inertial hair mu 0.2, smooth rise", f"{1e3 * wall:8.1f} ms (cpu "
                 f"{1e3 * cpu:.1f}), {out.nsteps} steps, error {err:.1e}, within 1e-8 from "
                 f"t = {t_in:g}"))  # fmt: skip
    st = hairbed.solve_porous(1.0, 0.5, 0.2, kappa=0.1)
    wall, cpu, op = best_cpu(lambda: bed_operators(st, womersley=0.5, num=32), repeat)
    figs["5 bed_operators"] = {"wall_s": wall, "cpu_s": cpu, "size": int(op.layout["size"])}
    rows.append(("5 bed_operators N 32, alpha 0.5", f"{1e3 * wall:8.1f} ms (cpu "
                 f"{1e3 * cpu:.1f}), {op.layout['size']} unknowns"))  # fmt: skip
    rows.append(("load average (1 min)", f"{figs['load']:.1f}"))
    return rows, figs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    rows, figs = run(args.repeat)
    report(rows, figs, args.json)


if __name__ == "__main__":
    main()
