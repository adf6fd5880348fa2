"""The explorer's pillar mode (issue 21, item 3): server time per update, as ratios in one run.

The page (``ExplorerPage``, no browser: the server's side of an update) in pillar mode:

1. a move of Lambda in the shape view (one ``solve_pillar``) [ms];
2. a move of Lambda in the calibration view, its curve cached (the dot moves) [ms];
3. a move of theta0 in the calibration view (a new curve: a ``solve_pillar`` batch of 141
   forcings) [ms], and its ratio to row 2: what the cache saves on every Lambda move;
4. the same in a snap-through window (theta0 = -1.45: every new Lambda's states read from
   the pillar's branch, ``continue_pillar`` once per pillar, which the curve shares; issue
   33) [ms]: a new Lambda, a Lambda seen before (cached), and a new theta0 (a new branch).
   ``benchmarks/bench_explorer.py --pillar`` measures the new Lambdas against
   ``solve_pillar_all``.

Each figure is the median over ``--moves`` updates (rows 1 to 3). Needs the ``app`` extra.

Run: ``python benchmarks/bench_explorer_pillar.py [--moves N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["main", "run"]


def _updates(page: Any, key: str, values: Sequence[str]) -> list[float]:
    out = []
    for v in values:
        page.text[key].value = v
        if page.errors:
            raise RuntimeError(f"{key} = {v}: {page.errors}")
        out.append(float(page.timings["total"]))
    return out


def run(moves: int = 20) -> dict[str, Any]:
    """The figures (a dict of plain numbers)."""
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?mode=pillar&forcing=1", served=False)
    lams = [f"{x:.6g}" for x in np.geomspace(0.01, 1000.0, moves)]
    thetas = [f"{x:.6g}" for x in np.linspace(-1.0, 1.0, max(3, moves // 4) + 1)[1:]]
    shape = statistics.median(_updates(page, "forcing", lams))
    page.pillar.view.value = "calibration"
    cached = statistics.median(_updates(page, "forcing", lams[::-1]))
    new_curve = statistics.median(_updates(page, "pillar_theta0", thetas))
    page.text["pillar_theta0"].value = "-1.45"
    window_lams = ["12", "15", "18", "21"]
    window_new = statistics.median(_updates(page, "forcing", window_lams))
    window_seen = statistics.median(_updates(page, "forcing", window_lams))
    window_theta = statistics.median(_updates(page, "pillar_theta0", ["-1.44", "-1.46"]))
    page.release()
    return {
        "moves": moves,
        "shape_lambda_ms": shape,
        "calibration_lambda_cached_ms": cached,
        "calibration_new_curve_ms": new_curve,
        "new_curve_over_cached": new_curve / cached,
        "window_new_lambda_ms": window_new,
        "window_seen_lambda_ms": window_seen,
        "window_new_theta0_ms": window_theta,
        "window_new_over_seen": window_new / window_seen,
        "load_average": os.getloadavg()[0],
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--moves", type=int, default=20)
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args(argv)
    f = run(args.moves)
    rows = [
        ("shape view, a move of Lambda [ms]", f"{f['shape_lambda_ms']:.1f}"),
        ("calibration view, a move of Lambda (curve cached) [ms]",
         f"{f['calibration_lambda_cached_ms']:.1f}"),
        ("calibration view, a move of theta0 (new curve) [ms]",
         f"{f['calibration_new_curve_ms']:.1f}"),
        ("  new curve / cached", f"{f['new_curve_over_cached']:.1f}x"),
        ("window theta0 = -1.45, a new Lambda [ms]", f"{f['window_new_lambda_ms']:.0f}"),
        ("  a Lambda seen before [ms]", f"{f['window_seen_lambda_ms']:.1f}"),
        ("  a new theta0 (new branch) [ms]", f"{f['window_new_theta0_ms']:.0f}"),
        ("  new / seen", f"{f['window_new_over_seen']:.0f}x"),
        ("load average", f"{f['load_average']:.1f}"),
    ]  # fmt: skip
    width = max(len(r[0]) for r in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(f, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
