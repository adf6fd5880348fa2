"""Speed and memory of the exact solver, as ratios measured in one run (issue 2, item 6).

A thin command line over :mod:`hairbed._benchmark`, which holds the measurements and the
description of every row (1 to 11; 11 the sweeps); ``hairbed bench`` and the speed figure use
the same code.

Run: ``python benchmarks/bench_solve.py [--quick] [--json PATH] [--repeat N] [--rows 1 3 ...]``.
``--quick`` shrinks the sizes (1e5 elements, fewer calls, no cold-cache run unless ``--cold``)
for a smoke test; its figures are not comparable with the targets. A full run takes about 2-3
minutes on 2 cores, about a minute of it the cold-cache compilation.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from hairbed import _benchmark

__all__ = ["main", "run"]


def run(
    quick: bool = False, repeat: int = 3, seed: int = 2026, cold: bool | None = None, **kw: Any
) -> dict[str, Any]:
    """Measure every row; returns {"meta": ..., "rows": [...]} (the JSON written)."""
    return _benchmark.measure(quick, repeat=repeat, seed=seed, cold=cold, **kw).as_dict()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller sizes, a smoke test")
    parser.add_argument("--json", type=Path, metavar="PATH", help="also write the figures here")
    parser.add_argument("--repeat", type=int, default=3, help="best of N for batch timings")
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument(
        "--cold", action="store_true", help="run the cold-cache row even with --quick"
    )
    parser.add_argument("--n", type=int, help="batch size (default 1e6, 1e5 with --quick)")
    parser.add_argument(
        "--rows", type=int, nargs="+", choices=_benchmark.NUMBERS, metavar="ROW",
        help="only these rows, 1 to 11 (default all)",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error(f"--repeat must be >= 1, got {args.repeat}")
    if args.n is not None and args.n < 2:
        parser.error(f"--n must be >= 2, got {args.n}")
    result = _benchmark.measure(
        args.quick,
        args.rows,
        repeat=args.repeat,
        seed=args.seed,
        cold=args.cold or None,
        n=args.n,
    )
    print(_benchmark.format_report(result))
    if args.json is not None:
        _benchmark.write_json(result, args.json)


if __name__ == "__main__":
    main()
