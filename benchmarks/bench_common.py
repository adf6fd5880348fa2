"""What the benchmark scripts share: the best of repeated runs and the table they print.

Imported by the scripts beside it (``python benchmarks/bench_loaded.py`` puts this folder on
``sys.path``); not a benchmark itself.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable, Sequence
from typing import Any

__all__ = ["best", "best_cpu", "report"]


def best(func: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """(best wall time of ``repeat`` runs [s], the result of the last run)."""
    fastest, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        fastest = min(fastest, time.perf_counter() - t0)
    return fastest, out


def best_cpu(func: Callable[[], Any], repeat: int) -> tuple[float, float, Any]:
    """(best wall time [s], the process CPU time of that same run [s], its result)."""
    fastest, cpu, out = math.inf, math.nan, None
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        res = func()
        wall, used = time.perf_counter() - t0, time.process_time() - c0
        if wall < fastest:
            fastest, cpu, out = wall, used, res
    return fastest, cpu, out


def report(rows: Sequence[tuple[str, str]], figures: dict[str, Any], path: str | None) -> None:
    """Print the rows (name, value) as an aligned table; write ``figures`` as JSON to
    ``path`` when it is given."""
    width = max(len(r[0]) for r in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")
    if path:
        with open(path, "w") as fh:
            json.dump(figures, fh, indent=2)
