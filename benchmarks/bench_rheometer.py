"""Speed of the bed's linear dynamics and of the rheometer (issues 30 and 31), in one run.

Rows:

1. ``linearise_bed(...).frequency_response`` at 1,000 frequencies (0.01 to 10/T, one degree
   band) about a tilted, deflected state, first call, then again on the prepared
   linearisation (its checked modal form, theory.md §15) [ms], against one LU per frequency
   on the same operators (the ratio), with the largest difference of the two;
2. one periodic steady state to 1e-8 (kappa = 1, eps = 0.5, omega = 1/T, gamma0 = 1,
   overdamped, quasi-steady fluid; target <= 50 ms): ``periodic_bed`` alone (collocation in
   time, theory.md §16) and the whole ``large_amplitude_shear`` with its analysis, wall
   and thread CPU time [ms], its degree, Newton and GMRES iterations; the transient
   baseline (``method="transient"``, periodic_tol 1e-8) the same way, and the two states'
   largest stress difference;
3. a 20 x 20 Pipkin map (omega 0.1 to 10/T, gamma0 0.1 to 3, log-spaced) on one worker and
   on two (processes, forked), wall and CPU time [s] (the workers' own included) and
   CPU/wall, and the ratio of the walls (target: <= 20 s on one core, two workers >= 1.8x);
   ``--pipkin N`` an N x N map.

OpenBLAS runs on one thread (set here before numpy loads): "one core" is one. The machine is
shared: each time is the best of ``--repeat`` runs in one run, CPU times are given beside
the walls (thread CPU time where one thread works), and the load average is printed. On a
loaded machine two workers cannot show their speed-up in wall time (CPU/wall tells).
Run: ``python benchmarks/bench_rheometer.py [--repeat N] [--pipkin N] [--json PATH]``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: one core is one

import argparse  # noqa: E402
import math  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
from bench_common import best, best_cpu, report  # noqa: E402

import hairbed  # noqa: E402
from hairbed.dynamics import linearise_bed, periodic_bed, sine  # noqa: E402
from hairbed.rheometer import large_amplitude_shear, pipkin_map  # noqa: E402

__all__ = ["main", "run"]


def _best_thread(func: Callable[[], Any], repeat: int) -> tuple[float, float, Any]:
    """(best wall [s], the least thread CPU time [s], the last result) of ``repeat`` runs."""
    wall, cpu, out = math.inf, math.inf, None
    for _ in range(repeat):
        c0, t0 = time.thread_time(), time.perf_counter()
        out = func()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.thread_time() - c0)
    return wall, cpu, out


def _children_cpu() -> float:
    """CPU time [s] of the finished worker processes so far."""
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def run(repeat: int = 3, pipkin: int = 20) -> tuple[list[tuple[str, str]], dict[str, Any]]:
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
        (
            "   on the prepared linearisation [ms]",
            f"{1e3 * t_built:.2f} (N, M = {deg}; {sorted(set(fr.method.tolist()))})",
        ),
        ("   one LU per frequency [ms]", f"{1e3 * t_lu:.1f} ({t_lu / t_built:.1f}x)"),
        ("   largest relative difference", f"{diff:.1e}"),
    ]
    figs.update(first_ms=1e3 * t_first, built_ms=1e3 * t_built, lu_ms=1e3 * t_lu, diff=diff)
    wall = sine(0.0, 1.0, 1.0, 0.5 * math.pi)
    periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall)  # compiled once

    def state() -> Any:
        return periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall)

    def laos(method: str) -> Any:
        return large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0, periodic_tol=1e-8,
                                     method=method)  # fmt: skip

    w_pb, c_pb, pb = _best_thread(state, max(repeat, 5))
    w_col, c_col, col = _best_thread(lambda: laos("collocation"), max(repeat, 5))
    w_tr, c_tr, tr = _best_thread(lambda: laos("transient"), 2)  # the first compiles
    diff = float(np.max(np.abs(col.stress - tr.stress)) / np.max(np.abs(tr.stress)))
    rows += [
        ("2. periodic state to 1e-8, periodic_bed [ms]",
         f"{1e3 * w_pb:.1f} wall, {1e3 * c_pb:.1f} CPU (H = {pb.harmonics}, "
         f"{pb.iterations} Newton, {pb.krylov_iterations} GMRES, error {pb.error:.1e})"),
        ("   large_amplitude_shear, collocation [ms]",
         f"{1e3 * w_col:.1f} wall, {1e3 * c_col:.1f} CPU"),
        ("   large_amplitude_shear, transient [ms]",
         f"{1e3 * w_tr:.1f} wall, {1e3 * c_tr:.1f} CPU ({tr.periods} periods, {tr.nsteps} "
         f"steps; {c_tr / c_col:.0f}x the CPU)"),
        ("   stress, collocation - transient", f"{diff:.1e} of max abs(stress)"),
    ]  # fmt: skip
    figs.update(periodic_ms=1e3 * w_pb, periodic_cpu_ms=1e3 * c_pb, laos_ms=1e3 * w_col,
                laos_cpu_ms=1e3 * c_col, transient_ms=1e3 * w_tr,
                transient_cpu_ms=1e3 * c_tr, harmonics=pb.harmonics,
                periodic_error=pb.error, methods_diff=diff)  # fmt: skip
    grid = (np.geomspace(0.1, 10.0, pipkin), np.geomspace(0.1, 3.0, pipkin))
    t1, cpu1, m1 = best_cpu(lambda: pipkin_map(*grid, eps=0.5, kappa=1.0, workers=1), 1)
    before = _children_cpu()
    t2, cpu2, m2 = best_cpu(lambda: pipkin_map(*grid, eps=0.5, kappa=1.0, workers=2), 1)
    cpu2 += _children_cpu() - before
    same = bool(np.array_equal(m1.storage, m2.storage, equal_nan=True))
    ok = int(np.count_nonzero(m1.success))
    rows += [
        (f"3. Pipkin map {pipkin} x {pipkin}, one worker [s]",
         f"{t1:.2f} wall, {cpu1:.2f} CPU (CPU/wall {cpu1 / t1:.2f}; {ok} of "
         f"{m1.status.size} cells periodic)"),
        ("   two workers (processes) [s]",
         f"{t2:.2f} wall, {cpu2:.2f} CPU (CPU/wall {cpu2 / t2:.2f}; {t1 / t2:.2f}x; "
         f"{'the same' if same else 'NOT the same'} moduli)"),
    ]  # fmt: skip
    figs.update(pipkin_n=pipkin, pipkin_1_s=t1, pipkin_1_cpu_s=cpu1, pipkin_2_s=t2,
                pipkin_2_cpu_s=cpu2, pipkin_ok=ok)  # fmt: skip
    figs["load_end"] = os.getloadavg()[0]
    rows.append(
        (
            "load average (1 min), start and end",
            f"{figs['load']:.1f}, {figs['load_end']:.1f} on {os.cpu_count()} cores",
        )
    )
    return rows, figs


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--pipkin", type=int, default=20)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    rows, figs = run(args.repeat, args.pipkin)
    report(rows, figs, args.json)


if __name__ == "__main__":
    main()
