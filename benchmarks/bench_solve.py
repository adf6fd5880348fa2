"""Speed and memory of the exact solver, as ratios measured in one run (issue 2, item 6).

``hairbed bench`` with the full sizes by default: the rows and their descriptions (1 to 11;
11 the sweeps) are in :mod:`hairbed._benchmark`, the options in ``hairbed bench --help``.

Run: ``python benchmarks/bench_solve.py [--quick] [--json PATH] [--repeat N] [--rows 1 3 ...]``.
``--quick`` shrinks the sizes (1e5 elements, fewer calls, no cold-cache run unless ``--cold``)
for a smoke test; its figures are not comparable with the targets. A full run takes about 2-3
minutes on 2 cores, about a minute of it the cold-cache compilation.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from hairbed.cli import main as hairbed_main

__all__ = ["main"]


def main(argv: Sequence[str] | None = None) -> int:
    """``hairbed bench --full ARGV`` (``hairbed bench ARGV`` when ARGV has --quick)."""
    args = list(sys.argv[1:] if argv is None else argv)
    size = [] if "--quick" in args or "--full" in args else ["--full"]
    return hairbed_main(["bench", *size, *args])


if __name__ == "__main__":
    sys.exit(main())
