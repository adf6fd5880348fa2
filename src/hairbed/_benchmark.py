"""Speed and memory of the exact solver, as ratios measured in one run.

The one implementation behind ``benchmarks/bench_solve.py``, ``hairbed bench`` and the speed
figure (:func:`hairbed.plotting.fig_speed`). Private: the names may change.

Every figure is measured in the same run as its baseline, so the ratios carry over between
machines better than the raw times; no timing is asserted anywhere in the tests. Rows:

1. ``hairbed.solve`` on 1e6 random physical-branch inputs (theta0 in [0, 1.2], eps in
   [0, 0.95], omega2 log-uniform in [1e-3, 1e3]), time per solve over the time per element of
   one ``scipy.special.ellipkinc`` call on 1e6 random elements (target <= 3);
2. the same with theta0 in [-1.5, 1.5] and eps in [0, 0.99] (bistable window and folds
   included; target <= 5);
3. scalar ``hairbed.solve`` on a few hundred random Python-float inputs (those of row 1), in
   units of one scalar ``ellipkinc(0.5, 0.3)`` call (target <= 5);
4. ``hairbed.solve_all(200, 0.5, 0.1)`` (7 states) in scalar ellipkinc calls (target <= 50);
5. ``Solution.profile(200)`` of a scalar solution in scalar ellipkinc calls (target <= 20);
6. ``hairbed.numerics.finite_difference(..., num=80)`` (the paper's baseline) over scalar
   ``solve`` at the same inputs, median over five inputs (target >= 100);
7. peak memory of ``hairbed.solve(np.logspace(-3, 3, 10**6), 0.9, -1.5)``: ru_maxrss of a
   fresh subprocess that warms the kernels and solves, minus that of one that only warms them
   (target <= 1 GB = 1e9 bytes; each ru_maxrss is read by a wrapper process with that one child,
   so that no other child enters RUSAGE_CHILDREN);
8. row 1's inputs in two halves, solved on a ``ThreadPoolExecutor(2)`` versus one after the
   other: the speedup (the kernels release the GIL; target >= 1.8), with the process CPU time
   over the wall time of the threaded run (near 1 means no second core was free);
9. ``hairbed.solve_all(1e8, 0.5)`` (5393 states), wall time (target <= 1 s);
10. the whole process ``python -m hairbed solve --omega2 2 --eps 0.5`` with a warm numba
    cache, median of 5 runs (target <= 0.5 s); the same once with a cold cache (a fresh empty
    ``NUMBA_CACHE_DIR``; no target); and, for reference, ``python -c "import numba"`` and
    ``python -c "pass"`` (median of 5 each), and the floor of any numba program: a process
    that imports numba and calls one trivial ``njit(cache=True)`` function loaded from a warm
    cache (row 10e, median of 5).

11. sweeps (:func:`hairbed.sweep`): (a) the eager sweep of a 100 x 40 x 25 grid (omega2
    log-uniform in [1e-3, 1e3], eps in [0, 0.95], theta0 in [-1.2, 1.2]) over one
    ``hairbed.solve`` of the same 1e5 points (the cost of the labelled dataset; target <= 1.2)
    and (b) its wall time; then a 1e7-point sweep of the same ranges in blocks of ~1e5 points
    (omega2 whole: its folds are per (eps, theta0)), reduced to sums so that no result crosses
    a process boundary: (c) dask's threaded scheduler on 2 threads over the same blocks one
    after the other (the synchronous scheduler; target >= 1.8), (d) a 2-worker
    ``dask.distributed.LocalCluster`` of processes (1 thread each) over the same serial run,
    with the nanny's default ``MALLOC_TRIM_THRESHOLD_=65536``, and (e) the same with that
    setting removed (glibc's own trimming; not in quick runs), and (f) the cluster of (d) with
    blocks of ~1e6 points (not in quick runs): on 2 cores the scheduler and the client share
    the CPUs with the workers, and each block of the dataset is 2 x 13 tasks (a slice and a
    sum per variable), so fewer, larger blocks are what lets processes pay. Needs
    ``hairbed[sweep]``; ``quick`` and ``n`` scale the sizes (the big sweep has 10 n points,
    the grid min(n, 1e5)).

If the kernel sources are edited while this runs, the numba cache goes stale: to keep that out,
rows 7 and 10 start with an untimed child that refreshes it, and a warning is printed when the
sources changed during the run.

Every kernel path is called once before any timing, so compile time only enters the
cold-cache row (a warning is printed if a kernel compiled a new signature during rows 1-9).
Machines are shared and noisy: batch times (rows 1, 2, 8, 9) are the best of ``repeat``
runs; scalar latencies (rows 3 to 6) are medians of many calls (row 3: the best of 5 calls per
input, then the median over inputs; row 6: the finite differences best of 3). The load average
and the share of a core the process got in rows 1-6 are printed with the table.

``quick=True`` shrinks the sizes (1e5 elements, fewer calls, no cold-cache run unless
``cold=True``) for a smoke test; its figures are not comparable with the targets. A full run
takes about 2-3 minutes on 2 cores, about a minute of it the cold-cache compilation.

Only numpy and hairbed are imported here; scipy and ``hairbed.numerics`` when a row needs them,
matplotlib never.

Examples
--------
>>> rows = run(quick=True, n=200, repeat=1, rows={1, 4})
>>> [r.number for r in rows]
['1', '4']
>>> rows[0].unit, rows[0].target, rows[0].op, rows[0].passed in (True, False)
('x', 3.0, '<=', True)
>>> print(format_table(rows).splitlines()[0])  # doctest: +NORMALIZE_WHITESPACE
row  measured  value unit target target
"""

from __future__ import annotations

import functools
import gc
import json
import logging
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from ._core.solver import solve, solve_all

__all__ = [
    "MEASURES",
    "ROWS",
    "SECTIONS",
    "Result",
    "Row",
    "format_report",
    "format_table",
    "measure",
    "run",
    "write_json",
]

#: Row -> (what is measured, unit, target, comparison); target None: reported, no target.
ROWS: dict[str, tuple[str, str, float | None, str]] = {
    "1": ("batch physical / ellipkinc per element", "x", 3.0, "<="),
    "2": ("batch wide theta0, eps / ellipkinc per element", "x", 5.0, "<="),
    "3": ("scalar solve / scalar ellipkinc", "calls", 5.0, "<="),
    "4": ("solve_all(200, 0.5, 0.1) / scalar ellipkinc", "calls", 50.0, "<="),
    "5": ("Solution.profile(200) / scalar ellipkinc", "calls", 20.0, "<="),
    "6": ("finite_difference(num=80) / scalar solve", "x", 100.0, ">="),
    "7": ("peak memory of solve(logspace(-3, 3, n), 0.9, -1.5)", "MB", 1000.0, "<="),
    "8": ("2 threads / 1 thread, speedup", "x", 1.8, ">="),
    "9": ("solve_all(1e8, 0.5) wall time", "s", 1.0, "<="),
    "10a": ("`python -m hairbed solve`, warm cache", "s", 0.5, "<="),
    "10b": ("`python -m hairbed solve`, cold cache", "s", None, ""),
    "10c": ('`python -c "import numba"` (reference)', "s", None, ""),
    "10d": ('`python -c "pass"` (reference)', "s", None, ""),
    "10e": ("one trivial cached numba kernel, whole process (ref.)", "s", None, ""),
    "11a": ("sweep 100x40x25 / one solve of its points", "x", 1.2, "<="),
    "11b": ("sweep 100x40x25, wall time", "s", None, ""),
    "11c": ("{points}-point sweep: dask threads (2) / serial, speedup", "x", 1.8, ">="),
    "11d": ("{points}-point sweep: LocalCluster 2 processes / serial", "x", None, ""),
    "11e": ("the same, nanny without MALLOC_TRIM_THRESHOLD_", "x", None, ""),
    "11f": ("the same cluster, blocks of ~1e6 points / serial", "x", None, ""),
}
#: The rows of the issue, 1 to 10 (row 10 is the table rows 10a-10d), and the sweeps' 11.
NUMBERS = tuple(range(1, 12))

#: Inputs of row 6: (omega2, eps, theta0), all on the physical branch for the FD solver too.
FD_INPUTS = [
    (2.0, 0.5, 0.0),
    (10.0, 0.5, 0.3),
    (0.5, 0.9, 0.0),
    (50.0, 0.3, 0.1),
    (100.0, 0.8, -0.3),
]
CLI = [sys.executable, "-m", "hairbed", "solve", "--omega2", "2", "--eps", "0.5"]
#: Row 7: the child warms the array path on 10 elements; the measured child then solves n.
MEM_WARM = "import numpy as np, hairbed; hairbed.solve(np.logspace(-3, 3, 10), 0.9, -1.5)"
MEM_SOLVE = "; hairbed.solve(np.logspace(-3, 3, {n}), 0.9, -1.5)"
#: Runs one child and prints its peak RSS, so that no other child enters RUSAGE_CHILDREN.
MEM_RUNNER = (
    "import resource, subprocess, sys; "
    "subprocess.run([sys.executable, '-c', sys.argv[1]], check=True); "
    "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)"
)


@dataclass(frozen=True)
class Row:
    """One measured row of the table against its target.

    ``number`` is the row of the table ("1" ... "9", "10a" ... "10d"), ``label`` what is
    measured, ``value`` the figure in ``unit``; ``target`` and ``op`` ("<=" or ">=") the
    target (None for reference rows), ``passed`` whether it is met (None: no target);
    ``detail`` the raw timings behind the value.
    """

    number: str
    label: str
    value: float
    unit: str
    target: float | None
    op: str | None
    passed: bool | None
    detail: Mapping[str, Any] = field(default_factory=dict, compare=False, hash=False)

    @classmethod
    def of(cls, number: str, value: float, **detail: Any) -> Row:
        """The value of row ``number`` against its target in ROWS; a label's ``{points}`` is
        the size measured (``detail["points"]``), as the report's summary line says it."""
        label, unit, target, op = ROWS[number]
        if "{points}" in label:
            label = label.format(points=f"{detail['points']:.1e}" if "points" in detail else "N")
        ok = None if target is None else bool(value <= target if op == "<=" else value >= target)
        return cls(number, label, float(value), unit, target, op or None, ok, detail)

    @property
    def ratio(self) -> float | None:
        """value / target (None without a target)."""
        return None if self.target is None else self.value / self.target

    @property
    def verdict(self) -> str:
        """ "met", "missed" (a speed or memory figure outside its target on the machine that
        ran it: a measurement, not a failure of hairbed's results) or "info" (no target)."""
        return "info" if self.passed is None else ("met" if self.passed else "missed")

    def as_dict(self) -> dict[str, Any]:
        """The row as written to JSON (the keys of the original benchmark script)."""
        return {
            "row": self.number,
            "name": self.label,
            "value": self.value,
            "unit": self.unit,
            "target": self.target,
            "op": self.op,
            "pass": self.passed,
            "detail": dict(self.detail),
        }


@dataclass(frozen=True)
class Result:
    """The rows of one run and its circumstances (sizes, load, versions, time spent)."""

    rows: tuple[Row, ...]
    meta: Mapping[str, Any] = field(compare=False, hash=False)

    def as_dict(self) -> dict[str, Any]:
        """{"meta": ..., "rows": [...]}, as written to JSON."""
        return {"meta": dict(self.meta), "rows": [r.as_dict() for r in self.rows]}


# -- timing helpers -------------------------------------------------------------------------


def best_of(fn: Callable[[], Any], repeat: int, collect: bool = False) -> float:
    """Smallest wall time of ``repeat`` calls of fn [s].

    ``collect``: run the garbage collector before each call (for long batch calls only: it
    empties the CPU caches, which would slow down a short call).
    """
    best = float("inf")
    for _ in range(repeat):
        if collect:
            gc.collect()
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def median_call(fn: Callable[[], Any], calls: int, number: int = 1) -> float:
    """Median over ``calls`` timings of ``number`` back-to-back calls of fn, per call [s]."""
    times = []
    for _ in range(calls):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        times.append((time.perf_counter() - start) / number)
    return statistics.median(times)


def wall(cmd: list[str], env: dict[str, str] | None = None) -> float:
    """Wall time of one subprocess run [s] (it must succeed)."""
    start = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def peak_rss(code: str) -> int:
    """Peak resident set of a fresh ``python -c code`` [bytes]."""
    out = subprocess.run(
        [sys.executable, "-c", MEM_RUNNER, code], check=True, capture_output=True, text=True
    )
    kib_or_bytes = int(out.stdout.split()[-1])
    return kib_or_bytes if sys.platform == "darwin" else 1024 * kib_or_bytes


def kernel_hash() -> str | None:
    """Hash of the kernel sources now (they may be edited while we run), if available."""
    try:
        from ._core._jit import kernel_sources_hash

        return kernel_sources_hash.__wrapped__()
    except Exception:  # private helper: the benchmark must not depend on it
        return None


def kernel_signatures() -> dict[str, int]:
    """Compiled signatures per hairbed kernel, to check that nothing compiles while timing."""
    import importlib
    import pkgutil

    from ._core import _kernels as kernels

    counts = {}
    for info in pkgutil.iter_modules(kernels.__path__):
        module = importlib.import_module(f"{kernels.__name__}.{info.name}")
        for name, obj in vars(module).items():
            if hasattr(obj, "py_func") and hasattr(obj, "signatures"):
                counts[f"{info.name}.{name}"] = len(obj.signatures)
    return counts


def inputs(rng: np.random.Generator, n: int, theta: float, eps: float, low: float) -> tuple:
    """omega2 log-uniform in [1e-3, 1e3], eps in [0, eps], theta0 in [low, theta]."""
    omega2 = 10.0 ** rng.uniform(-3.0, 3.0, n)
    return omega2, rng.uniform(0.0, eps, n), rng.uniform(low, theta, n)


def _version(name: str) -> str | None:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(name)
    except PackageNotFoundError:
        return None


def _selection(rows: Iterable[int] | None) -> frozenset[int]:
    if rows is None:
        return frozenset(NUMBERS)
    chosen = frozenset(rows)
    bad = sorted(chosen - set(NUMBERS), key=str)
    if bad or not chosen:
        raise ValueError(f"benchmark rows are 1 to 11, got {', '.join(map(str, bad)) or 'none'}")
    return chosen


# -- the measurement: one function per row ----------------------------------------------------


@dataclass
class _Run:
    """One measurement's sizes, random inputs, thread pool and shared baselines."""

    quick: bool
    repeat: int
    n: int
    cold: bool
    pool: ThreadPoolExecutor
    row1: tuple[np.ndarray, np.ndarray, np.ndarray]
    row2: tuple[np.ndarray, np.ndarray, np.ndarray]
    phi: np.ndarray
    m: np.ndarray
    #: inputs of row 3, repeats of rows 4-6, runs of row 10
    n_scalar: int
    calls: int
    n_cli: int
    baselines: dict[str, float] = field(default_factory=dict)

    def ellipkinc_batch(self) -> float:
        """One ``ellipkinc`` element of a batch call [s] (rows 1, 2; measured once)."""
        if "batch" not in self.baselines:
            from scipy import special

            best = best_of(lambda: special.ellipkinc(self.phi, self.m), self.repeat, True)
            self.baselines["batch"] = best / self.n
        return self.baselines["batch"]

    def ellipkinc_scalar(self) -> float:
        """One scalar ``ellipkinc(0.5, 0.3)`` call [s] (rows 3-5; measured once)."""
        if "scalar" not in self.baselines:
            from scipy import special

            unit = median_call(lambda: special.ellipkinc(0.5, 0.3), self.calls, number=1000)
            self.baselines["scalar"] = unit
        return self.baselines["scalar"]


def _warm_up(run: _Run, chosen: frozenset[int]) -> None:
    """Call every path once, so that compilation (or loading the cache) is not timed."""
    solve(2.0, 0.5)
    solve(*(a[:1000] for a in run.row1))
    solve(*(a[:1000] for a in run.row2))  # folds, several (eps, theta0) pairs
    solve(np.logspace(-3, 3, 10), 0.9, -1.5)  # folds, one pair
    solve_all(200.0, 0.5, 0.1)
    solve_all(1e4, 0.5)
    solve(2.0, 0.5).profile(200)
    if 6 in chosen:
        from .numerics import finite_difference

        finite_difference(2.0, 0.5, 0.0, num=80)
    if chosen & {1, 2, 3, 4, 5, 6}:
        from scipy import special

        special.ellipkinc(0.5, 0.3)
        special.ellipkinc(np.full(10, 0.5), np.full(10, 0.3))
    list(run.pool.map(lambda a: solve(*a), [tuple(x[:10] for x in run.row1)] * 2))


def _row_batch(run: _Run, number: int) -> list[Row]:
    """Rows 1, 2: a batch solve per element over a batch ellipkinc per element."""
    t_ell = run.ellipkinc_batch()
    args = run.row1 if number == 1 else run.row2
    t_b = best_of(functools.partial(solve, *args), run.repeat, collect=True) / run.n
    detail = {"solve_ns": t_b * 1e9, "ellipkinc_ns": t_ell * 1e9, "n": run.n}
    return [Row.of(str(number), t_b / t_ell, **detail)]


def _row_scalar_solve(run: _Run) -> list[Row]:
    """Row 3: scalar solves (best of 5 per input, median over inputs) in ellipkinc calls."""
    unit = run.ellipkinc_scalar()
    per_input = [
        best_of(functools.partial(solve, w, e, t), 5)
        for w, e, t in zip(*(a[: run.n_scalar].tolist() for a in run.row1))
    ]
    t_scalar = statistics.median(per_input)
    detail = {"solve_us": t_scalar * 1e6, "ellipkinc_us": unit * 1e6, "inputs": run.n_scalar}
    return [Row.of("3", t_scalar / unit, **detail)]


def _row_solve_all(run: _Run) -> list[Row]:
    """Row 4: ``solve_all(200, 0.5, 0.1)`` in scalar ellipkinc calls."""
    unit = run.ellipkinc_scalar()
    t_all = median_call(lambda: solve_all(200.0, 0.5, 0.1), run.calls)
    states = len(solve_all(200.0, 0.5, 0.1))
    detail = {"us": t_all * 1e6, "states": states, "ellipkinc_us": unit * 1e6}
    return [Row.of("4", t_all / unit, **detail)]


def _row_profile(run: _Run) -> list[Row]:
    """Row 5: ``Solution.profile(200)`` in scalar ellipkinc calls."""
    unit = run.ellipkinc_scalar()
    sol = solve(2.0, 0.5)
    t_prof = median_call(lambda: sol.profile(200), run.calls)
    return [Row.of("5", t_prof / unit, us=t_prof * 1e6, ellipkinc_us=unit * 1e6)]


def _row_finite_difference(run: _Run) -> list[Row]:
    """Row 6: the paper's finite differences (num=80) over scalar solves, median of five."""
    from .numerics import finite_difference

    ratios, fd_ms, success = [], [], []
    for w, e, t in FD_INPUTS:
        t_fd = best_of(functools.partial(finite_difference, w, e, t, num=80), 3)
        t_an = median_call(functools.partial(solve, w, e, t), run.calls)
        ratios.append(t_fd / t_an)
        fd_ms.append(t_fd * 1e3)
        success.append(bool(finite_difference(w, e, t, num=80).success))
    fd = {"ratios": ratios, "fd_ms": fd_ms, "fd_success": success, "inputs": FD_INPUTS}
    return [Row.of("6", statistics.median(ratios), **fd)]


def _row_memory(run: _Run) -> list[Row]:
    """Row 7: peak memory of a large solve, in fresh subprocesses."""
    peak_rss(MEM_WARM)  # refreshes the kernel cache if the sources changed meanwhile
    base = peak_rss(MEM_WARM)
    peak = peak_rss(MEM_WARM + MEM_SOLVE.format(n=run.n))
    mem = {"peak_mb": peak / 1e6, "baseline_mb": base / 1e6, "n": run.n}
    return [Row.of("7", (peak - base) / 1e6, **mem)]


def _row_threads(run: _Run) -> list[Row]:
    """Row 8: two threads against one, interleaved so that a burst of load hits both alike."""
    n = run.n
    halves = [tuple(a[s].copy() for a in run.row1) for s in (slice(0, n // 2), slice(n // 2, n))]
    t_seq = t_par = cpu_par = float("inf")
    for _ in range(run.repeat):
        t_seq = min(t_seq, best_of(lambda: [solve(*h) for h in halves], 1, collect=True))
        gc.collect()
        cpu, start = time.process_time(), time.perf_counter()
        list(run.pool.map(lambda h: solve(*h), halves))
        if time.perf_counter() - start < t_par:
            t_par, cpu_par = time.perf_counter() - start, time.process_time() - cpu
    # cpu_per_wall near 2: both threads ran at once; near 1: no second core was free
    thr = {"sequential_s": t_seq, "threads_s": t_par, "cpu_per_wall": cpu_par / t_par}
    return [Row.of("8", t_seq / t_par, **thr, n=n)]


def _row_strong_forcing(run: _Run) -> list[Row]:
    """Row 9: every state at strong forcing, ``solve_all(1e8, 0.5)``."""
    t_big = best_of(lambda: solve_all(1e8, 0.5), run.repeat, collect=True)
    return [Row.of("9", t_big, states=len(solve_all(1e8, 0.5)))]


def _rows_processes(run: _Run) -> list[Row]:
    """Rows 10a-10e: whole processes (warm and cold cache, and the references)."""
    wall(CLI)  # untimed: refreshes the kernel cache if the sources changed meanwhile
    warm = [wall(CLI) for _ in range(run.n_cli)]
    rows = [Row.of("10a", statistics.median(warm), runs=warm)]
    if run.cold:
        with tempfile.TemporaryDirectory(prefix="hairbed-cold-") as cache:
            rows.append(Row.of("10b", wall(CLI, env={**os.environ, "NUMBA_CACHE_DIR": cache})))
    for num, code in (("10c", "import numba"), ("10d", "pass")):
        runs = [wall([sys.executable, "-c", code]) for _ in range(5)]
        rows.append(Row.of(num, statistics.median(runs)))
    rows.append(Row.of("10e", _trivial_kernel_process()))
    return rows


def _rows_sweeps(run: _Run) -> list[Row]:
    """Rows 11a-11f: the sweeps (:func:`sweep_rows`)."""
    return sweep_rows(run.n, run.repeat, run.quick)


#: Row -> the function that measures it.
MEASURES: dict[int, Callable[[_Run], list[Row]]] = {
    1: lambda run: _row_batch(run, 1),
    2: lambda run: _row_batch(run, 2),
    3: _row_scalar_solve,
    4: _row_solve_all,
    5: _row_profile,
    6: _row_finite_difference,
    7: _row_memory,
    8: _row_threads,
    9: _row_strong_forcing,
    10: _rows_processes,
    11: _rows_sweeps,
}
#: The sections of a run: row -> "name: what the progress line says" (its wall time is
#: reported under the name).
SECTIONS: dict[int, str] = {
    **dict.fromkeys((1, 2), "rows 1-2: batch solve against batch ellipkinc"),
    **dict.fromkeys((3, 4, 5, 6), "rows 3-6: scalar latencies"),
    7: "row 7: peak memory (subprocesses)",
    8: "row 8: two threads against one",
    9: "row 9: solve_all(1e8, 0.5)",
    10: "row 10: whole processes",
    11: "row 11: sweeps (eager grid; threads and a LocalCluster against serial blocks)",
}
#: Rows timed in this process on one thread: the share of a core they got is reported.
_SINGLE_THREAD = frozenset(range(1, 7))


def _meta(run: _Run, seed: int, chosen: frozenset[int], **measured: Any) -> dict[str, Any]:
    """The circumstances of a run, as written with its rows."""
    return {
        "quick": run.quick,
        "repeat": run.repeat,
        "seed": seed,
        "n": run.n,
        "rows": sorted(chosen),
        "scalar_inputs": run.n_scalar,
        "median_calls": run.calls,
        "cpu_count": os.cpu_count(),
        **measured,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": _version("numba"),
        "scipy": _version("scipy"),
        "hairbed": __version__,
        "platform": platform.platform(),
        "time": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
    }


def measure(
    quick: bool = False,
    rows: Iterable[int] | None = None,
    progress: Callable[[str], Any] | None = None,
    *,
    repeat: int = 3,
    seed: int = 2026,
    cold: bool | None = None,
    n: int | None = None,
) -> Result:
    """Measure the rows (1 to 11, default all) in one run; returns the rows and their meta.

    ``quick``: reduced sizes (1e5 elements instead of 1e6, fewer calls, no cold-cache row
    unless ``cold``); ``n`` overrides the batch size (rows 1, 2, 7, 8); ``repeat``: best of
    this many batch runs; ``progress(message)`` is called before each section.
    """
    chosen = _selection(rows)
    if repeat < 1:
        raise ValueError(f"repeat must be >= 1, got {repeat}")
    if n is None:
        n = 100_000 if quick else 1_000_000
    if n < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    say = progress if progress is not None else (lambda message: None)
    load_start = os.getloadavg()
    hash_start = kernel_hash()
    rng = np.random.default_rng(seed)
    out: list[Row] = []
    sections: dict[str, float] = {}
    t_start = last = time.perf_counter()

    def lap(name: str) -> None:
        """Record the wall time since the previous lap under ``name``."""
        nonlocal last
        sections[name], last = time.perf_counter() - last, time.perf_counter()

    with ThreadPoolExecutor(2) as pool:
        run = _Run(
            quick=quick,
            repeat=repeat,
            n=n,
            cold=(not quick) if cold is None else cold,
            pool=pool,
            row1=inputs(rng, n, 1.2, 0.95, 0.0),
            row2=inputs(rng, n, 1.5, 0.99, -1.5),
            phi=rng.uniform(0.0, 0.5 * np.pi, n),
            m=rng.uniform(0.0, 1.0, n),
            n_scalar=min(n, 50 if quick else 300),
            calls=21 if quick else 101,
            n_cli=3 if quick else 5,
        )
        say("warm-up: calling every kernel path once")
        _warm_up(run, chosen)
        lap("warm-up")
        sigs_start = kernel_signatures()
        cpu0, wall0 = time.process_time(), time.perf_counter()
        cpu_share: float | None = None
        compiled: list[str] | None = None
        said = ""
        for number in sorted(chosen):
            if number > 6 and cpu_share is None and chosen & _SINGLE_THREAD:
                # share of one core this process got in rows 1-6: below 1, it waited
                cpu_share = (time.process_time() - cpu0) / max(time.perf_counter() - wall0, 1e-9)
            if number > 9 and compiled is None:  # rows 10, 11 compile in their own processes
                compiled = _compiled_since(sigs_start)
            section = SECTIONS[number]
            if section != said:
                if said:
                    lap(said.partition(":")[0])
                said = section
                say(section + (" (and a cold numba cache)" if number == 10 and run.cold else ""))
            out.extend(MEASURES[number](run))
        lap(said.partition(":")[0])
    if cpu_share is None and chosen & _SINGLE_THREAD:
        cpu_share = (time.process_time() - cpu0) / max(time.perf_counter() - wall0, 1e-9)
    meta = _meta(
        run,
        seed,
        chosen,
        loadavg_start=list(load_start),
        loadavg_end=list(os.getloadavg()),
        cpu_share_single_thread=cpu_share,
        sections_s=sections,
        total_s=time.perf_counter() - t_start,
        compiled_while_timing=_compiled_since(sigs_start) if compiled is None else compiled,
        kernel_sources_changed=hash_start != kernel_hash(),
    )
    return Result(tuple(out), meta)


def _compiled_since(signatures: Mapping[str, int]) -> list[str]:
    """The kernels that compiled a new signature since ``signatures`` were counted."""
    return sorted(k for k, v in kernel_signatures().items() if v != signatures.get(k))


_TRIVIAL_KERNEL = """import numba
@numba.njit(cache=True, nogil=True)
def f(x):
    return 2.0 * x + 1.0
f(1.0)
"""


def _trivial_kernel_process() -> float:
    """Median wall time of a process that calls one trivial cached numba kernel (warm)."""
    with tempfile.TemporaryDirectory(prefix="hairbed-floor-") as tmp:
        script = Path(tmp) / "trivial_kernel.py"
        script.write_text(_TRIVIAL_KERNEL)
        env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(tmp) / "cache")}
        wall([sys.executable, str(script)], env=env)  # untimed: compiles and caches
        return statistics.median(wall([sys.executable, str(script)], env=env) for _ in range(5))


def _sweep_axes(points: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The 100 x 40 x 25 grid of row 11 scaled to about ``points`` points."""
    scale = (points / 100_000) ** (1.0 / 3.0)
    nw, ne, nt = (max(2, round(k * scale)) for k in (100, 40, 25))
    return np.geomspace(1e-3, 1e3, nw), np.linspace(0.0, 0.95, ne), np.linspace(-1.2, 1.2, nt)


def sweep_rows(n: int, repeat: int, quick: bool = False) -> list[Row]:
    """Rows 11a-11e (module docstring): the sweeps, eager, threaded and on a LocalCluster.

    ``quick``: one cluster only (11e, a second cluster, is measured in full runs).
    """
    try:
        import dask
        import distributed
    except ImportError:  # the sweep extra is not installed: the rows cannot be measured
        return []
    from .sweeps import sweep

    w, e, t = _sweep_axes(min(n, 100_000))
    grid = np.meshgrid(w, e, t, indexing="ij")
    sweep(w[:2], e[:2], t[:2])  # warm
    t_solve = best_of(lambda: solve(*grid), repeat, collect=True)
    t_sweep = best_of(lambda: sweep(w, e, t), repeat, collect=True)
    rows = [
        Row.of("11a", t_sweep / t_solve, sweep_s=t_sweep, solve_s=t_solve, points=grid[0].size),
        Row.of("11b", t_sweep, shape=[w.size, e.size, t.size]),
    ]
    w, e, t = _sweep_axes(10 * n)
    points = w.size * e.size * t.size
    chunks = {
        "omega2": w.size,
        "eps": max(1, round(100_000 / (w.size * t.size))),
        "theta0": t.size,
    }
    if chunks["eps"] * w.size * t.size > 150_000:
        chunks["theta0"] = max(1, round(100_000 / (w.size * chunks["eps"])))

    def total(blocks: Mapping[str, int], **compute: Any) -> float:
        gc.collect()
        start = time.perf_counter()
        sweep(w, e, t, chunks=blocks).sum().compute(**compute)
        return time.perf_counter() - start

    t_serial = total(chunks, scheduler="synchronous")
    cpu, t0 = time.process_time(), time.perf_counter()
    t_threads = total(chunks, scheduler="threads", num_workers=2)
    cpu_per_wall = (time.process_time() - cpu) / (time.perf_counter() - t0)
    detail = {"points": points, "chunks": chunks, "serial_s": t_serial}
    rows.append(
        Row.of("11c", t_serial / t_threads, threads_s=t_threads, cpu_per_wall=cpu_per_wall,
               **detail)
    )  # fmt: skip
    # ~1e6-point blocks for row 11f: a tenth as many tasks for the scheduler to hand out
    big = dict(chunks, eps=min(e.size, max(1, round(1_000_000 / (w.size * chunks["theta0"])))))
    for numbers, trim in ((("11d", "11f"), "default"), (("11e",), None))[: 1 if quick else 2]:
        config = {} if trim == "default" else {KEY_TRIM: None}
        with dask.config.set(config), distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
            silence_logs=logging.CRITICAL,  # a heartbeat racing the shutdown logs a traceback
        ) as cluster, distributed.Client(cluster) as client:  # fmt: skip
            client.run(lambda: sweep(1.0, 0.5).xi.values)  # each worker loads the kernels
            env = client.run(lambda: os.environ.get("MALLOC_TRIM_THRESHOLD_"))
            trims = sorted(set(map(str, env.values())))
            for number in numbers if not quick else numbers[:1]:
                blocks = big if number == "11f" else chunks
                t_cluster = total(blocks)
                rows.append(
                    Row.of(number, t_serial / t_cluster, cluster_s=t_cluster,
                           malloc_trim_threshold=trims, **dict(detail, chunks=blocks))
                )  # fmt: skip
    return sorted(rows, key=lambda r: r.number)


_CLUSTER_LABEL = {"11d": "", "11e": " untrimmed", "11f": " (1e6-point blocks)"}

#: The nanny's environment setting of glibc's trim threshold (dask's configuration key).
KEY_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"


def run(
    quick: bool = False,
    rows: Iterable[int] | None = None,
    progress: Callable[[str], Any] | None = None,
    **options: Any,
) -> list[Row]:
    """The measured rows only (see :func:`measure` for the arguments)."""
    return list(measure(quick, rows, progress, **options).rows)


# -- output ---------------------------------------------------------------------------------


def format_table(rows: Sequence[Row]) -> str:
    """The rows as a text table: row, what is measured, value, unit, target, whether the
    target is met here (met, missed, info)."""
    lines = [f"{'row':<4} {'measured':<52} {'value':>10} {'unit':<6} {'target':<9} target"]
    for r in rows:
        target = "-" if r.target is None else f"{r.op} {r.target:g}"
        lines.append(
            f"{r.number:<4} {r.label:<52} {r.value:>10.4g} {r.unit:<6} {target:<9} {r.verdict}"
        )
    return "\n".join(lines)


def format_report(result: Result) -> str:
    """The table with its circumstances (sizes, load) and the raw timings behind it."""
    meta = result.meta
    share = meta["cpu_share_single_thread"]
    lines = [
        f"hairbed {meta['hairbed']}, numba {meta['numba']}, {meta['cpu_count']} CPUs, "
        f"n = {meta['n']:.0e}, best of {meta['repeat']} (batch), medians (scalar)"
        + ("  [QUICK: reduced sizes, not comparable with the targets]" if meta["quick"] else ""),
        "load average (1, 5, 15 min): start "
        + " ".join(f"{x:.2f}" for x in meta["loadavg_start"])
        + ", end "
        + " ".join(f"{x:.2f}" for x in meta["loadavg_end"])
        + ("" if share is None else f"; share of a core in rows 1-6: {share:.2f}"),
        "",
        format_table(result.rows),
        "",
    ]
    d = {r.number: r.detail for r in result.rows}
    ell = []
    if "1" in d or "2" in d:
        ell.append(f"{(d.get('1') or d['2'])['ellipkinc_ns']:.0f} ns per batch element")
    if {"3", "4", "5"} & set(d):
        unit = next(d[k]["ellipkinc_us"] for k in ("3", "4", "5") if k in d)
        ell.append(f"{unit * 1e3:.0f} ns per scalar call")
    timing = ["ellipkinc: " + ", ".join(ell)] if ell else []
    batch = [f"{d[k]['solve_ns']:.0f} ns (row {k})" for k in ("1", "2") if k in d]
    if batch:
        timing.append("batch solve " + ", ".join(batch))
    if "3" in d:
        timing.append(f"scalar solve {d['3']['solve_us']:.1f} us")
    if "4" in d:
        timing.append(f"solve_all(200) {d['4']['us']:.0f} us ({d['4']['states']} states)")
    if "5" in d:
        timing.append(f"profile(200) {d['5']['us']:.1f} us")
    if timing:
        lines.append("; ".join(timing))
    if "6" in d:
        lines.append(
            f"FD N=80: {', '.join(f'{t:.1f}' for t in d['6']['fd_ms'])} ms; ratios "
            f"{', '.join(f'{x:.0f}' for x in d['6']['ratios'])}; "
            f"converged {all(d['6']['fd_success'])}"
        )
    other = []
    if "7" in d:
        other.append(
            f"memory: peak {d['7']['peak_mb']:.0f} MB, baseline {d['7']['baseline_mb']:.0f} MB"
        )
    if "8" in d:
        other.append(
            f"threads: {d['8']['sequential_s']:.2f} s sequential, {d['8']['threads_s']:.2f} s "
            f"on 2 (CPU/wall {d['8']['cpu_per_wall']:.2f})"
        )
    if "9" in d:
        other.append(f"solve_all(1e8): {d['9']['states']} states")
    if "10a" in d:
        other.append("warm CLI runs " + ", ".join(f"{t:.2f}" for t in d["10a"]["runs"]) + " s")
    if "11a" in d:
        other.append(
            f"sweep {'x'.join(map(str, d['11b']['shape']))}: {d['11a']['sweep_s']:.2f} s, "
            f"one solve {d['11a']['solve_s']:.2f} s"
        )
    if "11c" in d:
        other.append(
            f"{d['11c']['points']:.1e}-point sweep: serial {d['11c']['serial_s']:.1f} s, "
            f"2 threads {d['11c']['threads_s']:.1f} s (CPU/wall {d['11c']['cpu_per_wall']:.2f})"
            + "".join(
                f", LocalCluster{_CLUSTER_LABEL[k]} {d[k]['cluster_s']:.1f} s"
                for k in ("11d", "11e", "11f")
                if k in d
            )
        )
    if other:
        lines.append("; ".join(other))
    lines.append(
        "time spent: "
        + ", ".join(f"{k} {v:.0f} s" for k, v in meta["sections_s"].items())
        + f"; total {meta['total_s']:.0f} s"
    )
    missed = [r.number for r in result.rows if r.passed is False]
    if missed:
        load = meta["loadavg_start"][0]
        cpus = meta["cpu_count"]
        lines.append(
            f"missed (rows {', '.join(missed)}): a speed or memory figure outside its target "
            f"on this machine, at a load average of {load:.2f} on {cpus} CPUs"
            + (" and with --quick's reduced sizes" if meta["quick"] else "")
            + ". Timings and ratios move with the machine and whatever else runs on it (a "
            "shared machine misses speed targets); this is not an error in hairbed's results, "
            "which the test suite checks. Run 'hairbed bench --full' on an idle machine to "
            "compare with the targets."
        )
    if meta["compiled_while_timing"]:
        lines.append(
            "WARNING: kernels compiled while timing (rows 1-9 include compile time): "
            + ", ".join(meta["compiled_while_timing"])
        )
    if meta["kernel_sources_changed"]:
        lines.append(
            "WARNING: the kernel sources changed during the run; subprocess rows may include "
            "recompilation"
        )
    return "\n".join(lines)


def write_json(result: Result, path: str | os.PathLike[str]) -> None:
    """Write the figures whole or not at all (:mod:`hairbed.safe_files`)."""
    from .safe_files import write_text

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_text(path, json.dumps(result.as_dict(), indent=2) + "\n")
