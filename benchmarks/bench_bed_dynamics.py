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
   Newton, the exact Jacobian and the outputs' rows;
6. a transfer function at 1,000 frequencies (0.01 to 10/T) about a tilted, deflected state
   (``solve_porous(1, 0.5, 0.3, kappa=0.5, gamma=0.657)``, bench_rheometer's) by
   ``linearise_bed(...).frequency_response`` [target <= 5 ms], overdamped with the
   quasi-steady fluid, mu = 1 with alpha = 0.1, and mu = 13 with alpha = 1: the cost split
   (the operators; the first call: the modal form's eigenvectors and checks, or the Schur
   form; a call on the prepared linearisation, the target's figure), the method taken, and
   the largest difference from one refined LU per frequency at every 10th frequency
   (relative to the larger of the value and its static value, as the tests; and relative
   to the value itself);
7. a batch of 1,000 different beds (``simulate_beds``: steps of the wall's speed to
   omega2 in [0.5, 3] at theta0 in [-0.3, 0.3], kappa in [0.1, 3], overdamped, quasi-steady
   fluid, the default N = 32, rtol 1e-6, to t = 8 T) on one thread and on two
   [target <= 10 s on one core, two threads >= 1.8x]: the wall and the CPU time of each,
   the CPU per wall of two threads (near 2: both ran), a control (a compiled nogil loop on
   one and two threads: how many cores the machine gave then), and the largest distance
   of the last tip deflection from the static state.

Measured (one run, ``--repeat 1``, load 12.7 at the start and 14.7 at the end on 2 shared
cores, benchmarks/results/bench_bed_dynamics.json), row 7 by CPU time: 1,000 beds in 9.90 s
on one thread (9.9 ms a bed: 65 steps, 83 LUs, all reached t = 8, the last tip deflections
within 4.7e-11 of ``solve_porous``), from 137 s (137 ms a bed, load 13.6) before d8077d9.
Where the time went before, one bed (40 ms CPU with OpenBLAS on one thread, load ~6): the
kernel ~32 ms, of which by the parts' timings about 2/3 in ~40 real and complex LUs of size
127 (a new pair at every new step size; a complex one ~5x a real one), 1/5 in their solves,
1/7 in ~462 evaluations of g and 1% in ~3 Jacobians; ~6 ms evaluating the static state's
Chebyshev series to all its 256 (zero-padded) terms; and with OpenBLAS' default threads
~100 ms more in numpy's LAPACK solves of the steady and consistent starts, whose idle threads
spin on a loaded machine (most of the 137 ms). Since d8077d9 (the algebraic unknowns
eliminated once a Jacobian: LUs of size 31 per step size, ~0.16 ms a Jacobian for the
elimination; the starts on the compiled LU; the series cut after its last nonzero term) one
bed takes ~8 ms in the kernel, half of it g's ~456 evaluations at ~9 us, and ~1.9 ms in
the call's Python (the static start 0.9, the consistent start 0.4). Two threads: 1.24x in
wall time while the machine gave 1.47x to the compiled control (cpu/wall 0.17: the load,
not the batch; the call's Python, up to ~20% of a bed, holds the GIL between its kernel
calls: were all of it serial, two idle cores would give at most ~1.7x). Rows 1-5 at that
load, CPU (before d8077d9, load 13.6): row 1 12.7 / 24.9 ms at rtol 1e-6 / 1e-8 (156 /
104), row 2 51 / 116 ms (181 / 301), row 3 25 / 48 ms (78 / 131), row 4 19.5 ms (73), row
5 45 ms (90); with fluid inertia more unknowns are kept (77 of 143 at alpha = 0.5).

A quiet run (``--repeat 3``, load 0.1 at the start and 0.4 at the end; the JSON is this run):
row 7, 1,000 beds in 9.40 s on one thread (9.4 ms a bed, CPU 9.39 s; target <= 10 s) and
4.82 s on two (CPU/wall 1.92): 1.95x (target >= 1.8x; the compiled control 1.94x), end
error 4.7e-11. Rows 1-6, CPU: row 1 11.9 / 22.8 ms, row 2 47.8 / 109.5 ms, row 3 24.5 /
45.1 ms, row 4 17.8 ms, row 5 1.2 ms; row 6 (1,000 frequencies, prepared) 0.46 / 0.87 /
0.97 ms, 4.8e-13 / 4.0e-12 / 6.0e-12 from one LU per frequency.

Run: ``python benchmarks/bench_bed_dynamics.py [--repeat N] [--beds N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from typing import Any

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bench_common import best_cpu, report  # noqa: E402

import hairbed  # noqa: E402
from hairbed.dynamics import (  # noqa: E402
    bed_operators,
    linearise_bed,
    sampled,
    simulate_bed,
    simulate_beds,
    step,
)

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


def _transfer(rows: list[tuple[str, str]], figs: dict[str, Any], repeat: int) -> None:
    """Row 6: the bed's transfer function at 1,000 frequencies, its cost split."""
    from hairbed.dynamics._bed_linear import _direct

    st = hairbed.solve_porous(1.0, 0.5, 0.3, kappa=0.5, gamma=0.657)
    om = np.geomspace(1e-2, 10.0, 1000)
    for mu, alpha in ((0.0, 0.0), (1.0, 0.1), (13.0, 1.0)):
        key = f"6 transfer 1000, mu {mu:g}, alpha {alpha:g}"
        lin = linearise_bed(st, inertia=mu, womersley=alpha)
        c0, t0 = time.process_time(), time.perf_counter()
        nn, mm, _ = lin._degrees(om)
        for deg in sorted(set(zip(nn.tolist(), mm.tolist()))):
            lin.operators(deg[0], max(deg[1], 4))
        t_ops, c_ops = time.perf_counter() - t0, time.process_time() - c0
        c0, t0 = time.process_time(), time.perf_counter()
        lin.frequency_response(om)
        t_first, c_first = time.perf_counter() - t0, time.process_time() - c0
        wall, cpu, fr = best_cpu(lambda lin=lin: lin.frequency_response(om), max(repeat, 5))
        worst, plain = 0.0, 0.0
        names = ("tip_deflection", "base_moment", "wall_stress")
        static = np.array([abs(getattr(fr, k)[0]) for k in names])
        for i in range(0, om.size, 10):
            ops = lin.operators(int(fr.num[i]), max(int(fr.num_gap[i]), 4))
            ref = _direct(ops, np.array([1j * om[i]]), ops.drives["wall"])[[0, 2, 3], 0]
            got = np.array([getattr(fr, k)[i] for k in names])
            worst = max(worst, float(np.max(np.abs(got - ref) / np.maximum(abs(ref), static))))
            plain = max(plain, float(np.max(np.abs(got - ref) / np.abs(ref))))
        methods = {str(m): int(np.sum(fr.method == m)) for m in np.unique(fr.method)}
        figs[key] = {
            "operators_ms": 1e3 * t_ops,
            "operators_cpu_ms": 1e3 * c_ops,
            "first_call_ms": 1e3 * t_first,
            "first_call_cpu_ms": 1e3 * c_first,
            "prepared_ms": 1e3 * wall,
            "prepared_cpu_ms": 1e3 * cpu,
            "methods": methods,
            "degrees": sorted({(int(a), int(b)) for a, b in zip(fr.num, fr.num_gap)}),
            "max_rel_vs_refined_lu": worst,
            "max_plain_rel_vs_refined_lu": plain,
        }
        rows.append((key, f"{1e3 * wall:8.2f} ms (cpu {1e3 * cpu:.2f}) prepared; operators "
                     f"{1e3 * t_ops:.0f} ms, first call {1e3 * t_first:.0f} ms; {methods}; "
                     f"vs LU {worst:.1e} ({plain:.1e} of the value itself)"))  # fmt: skip


def _control(workers: int) -> tuple[float, float]:
    """(wall, CPU) of a fixed amount of a compiled nogil loop shared over ``workers``
    threads: how many cores the machine gives this process at the moment."""
    from concurrent.futures import ThreadPoolExecutor

    import numba

    @numba.njit(nogil=True, cache=False)
    def busy(n: int) -> float:
        acc = 0.0
        for i in range(n):
            acc += math.sin(i * 1e-3)
        return acc

    busy(10)
    c0, t0 = time.process_time(), time.perf_counter()
    with ThreadPoolExecutor(workers) as pool:
        list(pool.map(busy, [20_000_000 // workers] * workers))
    return time.perf_counter() - t0, time.process_time() - c0


def _batch(rows: list[tuple[str, str]], figs: dict[str, Any], count: int) -> None:
    """Row 7: 1,000 beds in one call, one thread and two."""
    rng = np.random.default_rng(30)
    w2 = rng.uniform(0.5, 3.0, count)
    th = rng.uniform(-0.3, 0.3, count)
    kap = rng.uniform(0.1, 3.0, count)
    te = np.array([0.0, 8.0])
    drives = [step(float(x)) for x in w2]
    times: dict[int, float] = {}
    cpus: dict[int, float] = {}
    runs: Any = None
    for workers in (1, 2):
        c0, t0 = time.process_time(), time.perf_counter()
        runs = simulate_beds(th, kap, 0.5, wall=drives, t_eval=te, rtol=1e-6, atol=1e-8,
                             workers=workers)  # fmt: skip
        times[workers] = time.perf_counter() - t0
        cpus[workers] = time.process_time() - c0
    ctl = {w: min(_control(w)[0] for _ in range(2)) for w in (1, 2)}
    st = hairbed.solve_porous(w2, 0.5, th, kappa=kap)
    err = float(np.max(np.abs(runs.tip_deflection[:, -1] - st.tip_deflection)))
    figs["7 batch"] = {
        "beds": count,
        "one_thread_s": times[1],
        "one_thread_cpu_s": cpus[1],
        "two_threads_s": times[2],
        "two_threads_cpu_s": cpus[2],
        "two_threads_cpu_per_wall": cpus[2] / times[2],
        "speedup_2_over_1": times[1] / times[2],
        "cpu_per_bed_ms": 1e3 * cpus[1] / count,
        "mean_steps": float(np.mean(runs.nsteps)),
        "mean_lu": float(np.mean(runs.nlu)),
        "control_nogil_speedup_2_over_1": ctl[1] / ctl[2],
        "all_success": bool(np.all(runs.success)),
        "max_error_vs_static": err,
    }
    rows.append((f"7 batch of {count} beds, one thread", f"{times[1]:8.2f} s (cpu "
                 f"{cpus[1]:.2f}; {1e3 * cpus[1] / count:.0f} ms a bed, "
                 f"{np.mean(runs.nsteps):.0f} steps, {np.mean(runs.nlu):.0f} LUs)"))  # fmt: skip
    rows.append(("  two threads", f"{times[2]:8.2f} s (cpu {cpus[2]:.2f}, cpu/wall "
                 f"{cpus[2] / times[2]:.2f}): {times[1] / times[2]:.2f}x; control "
                 f"{ctl[1] / ctl[2]:.2f}x; end error {err:.1e}"))  # fmt: skip


def run(repeat: int = 3, beds: int = 1000) -> tuple[list[tuple[str, str]], dict[str, Any]]:
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
    _transfer(rows, figs, repeat)
    if beds > 0:
        _batch(rows, figs, beds)
    figs["load_end"] = os.getloadavg()[0]
    rows.append(("load average (1 min), start and end", f"{figs['load']:.1f}, "
                 f"{figs['load_end']:.1f}"))  # fmt: skip
    return rows, figs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--beds", type=int, default=1000, help="beds of row 7 (0: skip)")
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    rows, figs = run(args.repeat, args.beds)
    report(rows, figs, args.json)


if __name__ == "__main__":
    main()
