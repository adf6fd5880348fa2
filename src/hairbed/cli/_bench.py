"""``hairbed bench``: the speed and memory table, every row against its target.

The one command line of :mod:`hairbed._benchmark`; ``benchmarks/bench_solve.py`` runs this
with full sizes by default.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ._options import add_command
from ._output import check_output
from ._report import PROG, UsageError, WriteError

#: ``hairbed bench --help``: the summary line, the description and the examples.
ABOUT = """measure every row of the speed table (ratios, targets)

Measure the speed and memory table of benchmarks/bench_solve.py in one run: batch and scalar
solves against scipy.special.ellipkinc, solve_all, profiles, the finite differences, peak
memory, threads and whole processes, each against its target. By default with reduced sizes
(about 30 s; figures not comparable with the targets); --full for the full sizes (about 2-3
minutes).

examples:
  hairbed bench
  hairbed bench --full --json bench.json
  hairbed bench --rows 1 2 3 --n 1000000 --repeat 5
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``bench`` subcommand's parser."""
    p = add_command(sub, "bench", run, ABOUT)
    size = p.add_mutually_exclusive_group()
    size.add_argument("--quick", action="store_true", help="reduced sizes (the default)")
    size.add_argument("--full", action="store_true", help="full sizes (1e6 elements ...)")
    p.add_argument("--n", type=int, help="batch size (default 1e5, 1e6 with --full)")
    p.add_argument("--repeat", type=int, default=3, help="best of this many runs (default 3)")
    p.add_argument("--seed", type=int, default=2026, help="random inputs (default 2026)")
    p.add_argument(
        "--rows",
        type=int,
        nargs="+",
        choices=range(1, 12),
        metavar="ROW",
        help="only these rows, 1 to 11 (default all)",
    )
    p.add_argument("--cold", action="store_true", help="also time a cold numba cache")
    p.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    p.add_argument("--progress", action="store_true", help="a line per section on stderr")


def _progress(message: str) -> None:
    print(f"{PROG} bench: {message}", file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> int:
    """Measure the rows, print the report, and write the JSON with --json."""
    from hairbed import _benchmark

    if args.n is not None and args.n < 2:
        raise UsageError(f"--n must be >= 2, got {args.n}")
    if args.repeat < 1:
        raise UsageError(f"--repeat must be >= 1, got {args.repeat}")
    if args.seed < 0:
        raise UsageError(f"--seed must be >= 0, got {args.seed}")
    out = None if args.json is None else Path(args.json)
    if out is not None:
        check_output(args.json, parents=True)  # missing folders are created
    result = _benchmark.measure(
        not args.full,
        args.rows,
        _progress if args.progress else None,
        repeat=args.repeat,
        seed=args.seed,
        cold=True if args.cold else None,
        n=args.n,
    )
    print(_benchmark.format_report(result), flush=True)
    if out is not None:
        try:
            _benchmark.write_json(result, out)
        except OSError as exc:
            raise WriteError(out, exc) from None
    return 0
