"""``hairbed bistability``: the cusp, the folds and the bistable window of (eps, theta0), or
(``--map``) the exact window over a grid of (theta0, eps) to a labelled file."""

from __future__ import annotations

import argparse
import sys
from typing import Any

import numpy as np

import hairbed

from ._grids import spec
from ._options import EPS_HELP, THETA0_HELP, add_command, add_eps, add_json, add_theta0, refuse
from ._output import NO_COMPRESS_HELP, check_dataset_output, print_json, write_dataset_output
from ._report import UsageError

#: ``hairbed bistability --help``: the summary line, the description and the examples.
ABOUT = """cusp, folds and bistable window of a hair bed (eps, theta0)

The cusp confinement eps_c(theta0) above which the physical branch folds, its fold points
(omega2, xi, tip deflection) and the window of omega2 in which three physical states coexist
(or that there is none). Negative theta0 leans the hairs into the flow: only then (and for
eps > eps_c) is there a window (theory.md §5).

With --map THETA0_SPEC EPS_SPEC (SPECs as in hairbed sweep) it maps the exact window over
the grid of (theta0, eps) instead: lower_fold and upper_fold (omega2 at the folds, NaN
without a window), width, n_states (3 inside a window, else 1), exists, and cusp_eps along
theta0, written like a sweep (.nc, .zarr, .csv, .parquet by the extension of --out; CSV on
stdout without it). Each cell's window comes from its folds, so the map is exact however
narrow the window: a grid of omega2 (a sweep counting n_roots == 3) misses the windows
narrower than its step near the cusp, and so undercounts the three-state region.

examples:
  hairbed bistability --eps 0.95 --theta0=-1.2
  hairbed bistability --eps 0.9 --theta0=-1.5 --json
  hairbed bistability --map -1.5:-0.05:200 0.3:0.999:200 --out map.nc
JSON keys: cusp_eps, folds (list of {omega2, xi, tip_deflection, t}), window ([lower, upper]
or null)
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``bistability`` subcommand's parser."""
    p = add_command(sub, "bistability", run, ABOUT)
    add_eps(p, help=f"{EPS_HELP} (needed without --map)")
    add_theta0(p, help=f"{THETA0_HELP} (needed without --map)")
    add_json(p)
    g = p.add_argument_group("the exact map over a grid (instead of --eps and --theta0)")
    g.add_argument(
        "--map",
        nargs=2,
        metavar=("THETA0_SPEC", "EPS_SPEC"),
        help="the window at every (theta0, eps) of the grid of two SPECs (a value, a comma "
        "list or start:stop:num[:log])",
    )
    g.add_argument(
        "--out", metavar="FILE", help="the map: .nc, .zarr, .csv or .parquet (default: CSV stdout)"
    )
    g.add_argument("--no-compress", action="store_true", help=NO_COMPRESS_HELP)
    g.add_argument("--progress", action="store_true", help="progress bar with ETA on stderr")


_MAP_ONLY = {"out": "--out", "no_compress": "--no-compress", "progress": "--progress"}


def _map(args: argparse.Namespace) -> int:
    """The exact map of the window over the grid of --map, written like a sweep."""
    from hairbed import sweeps

    why = "does not apply with --map (the grid gives theta0 and eps)"
    refuse(args, {"eps": "--eps", "theta0": "--theta0", "json": "--json"}, why)
    to_stdout = check_dataset_output(args.out, args.no_compress)
    theta0 = spec(args.map[0], "--map THETA0_SPEC")
    eps = spec(args.map[1], "--map EPS_SPEC")
    ds = sweeps.bistability_map(theta0, eps, progress=args.progress)
    write_dataset_output(ds, args.out, args.no_compress)
    if not to_stdout:
        three, cells = int(ds["exists"].sum()), int(ds["exists"].size)
        print(f"three physical states in {three} of {cells} cells (exact)", file=sys.stderr)
    return 0


def run(args: argparse.Namespace) -> int:
    """Print the cusp, the folds and the window (or JSON); or write the map (--map)."""
    if args.map is not None:
        return _map(args)
    refuse(args, _MAP_ONLY, "applies to --map only")
    for dest, flag in (("eps", "--eps"), ("theta0", "--theta0")):
        if getattr(args, dest) is None:
            raise UsageError(f"{flag} is required (or --map THETA0_SPEC EPS_SPEC)")
    branches = hairbed.branches
    eps, theta0 = args.eps, args.theta0
    f = branches.folds(eps, theta0)  # first: its checks name eps and theta0
    cusp = float(branches.cusp(theta0))
    tip = np.asarray(hairbed.from_parameter(f.t, eps, theta0).tip_deflection).reshape(-1)
    folds = [
        {"omega2": float(w), "xi": float(x), "tip_deflection": float(d), "t": float(t)}
        for w, x, d, t in zip(f.omega2, f.xi, tip, f.t)
    ]
    win = branches.bistable_window(eps, theta0)
    window = [win.lower, win.upper] if win.exists else None
    if args.json:
        print_json(
            {"eps": eps, "theta0": theta0, "cusp_eps": cusp, "folds": folds, "window": window}
        )
        return 0
    lean = "into the flow" if theta0 < 0 else ("upright" if theta0 == 0 else "with the flow")
    print(f"hair bed at eps = {eps:g}, theta0 = {theta0:g} (leaning {lean})")
    if cusp < 1.0:
        print(f"  cusp: folds exist for eps > eps_c(theta0) = {cusp:.12g}")
    else:
        print("  cusp: none (the physical branch is monotone for every eps < 1 at this theta0)")
    if window is None:
        print("  no folds: one physical state at every omega^2 (no bistable window)")
        return 0
    for name, fold in zip(("lower", "upper"), folds):
        print(
            f"  {name} fold: omega2 = {fold['omega2']:.12g}, xi = {fold['xi']:.12g}, "
            f"tip deflection = {fold['tip_deflection']:.12g} [L]"
        )
    print(
        f"  window: three physical states (low and high stable, mid unstable) for "
        f"{window[0]:.12g} < omega2 < {window[1]:.12g}"
    )
    return 0
