"""``hairbed bistability``: the cusp, the folds and the bistable window of (eps, theta0)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import hairbed

from ._options import add_command, add_eps, add_json, add_theta0
from ._output import print_json

#: ``hairbed bistability --help``: the summary line, the description and the examples.
ABOUT = """cusp, folds and bistable window of a hair bed (eps, theta0)

The cusp confinement eps_c(theta0) above which the physical branch folds, its fold points
(omega2, xi, tip deflection) and the window of omega2 in which three physical states coexist
(or that there is none). Negative theta0 leans the hairs into the flow: only then (and for
eps > eps_c) is there a window (theory.md §5).

examples:
  hairbed bistability --eps 0.95 --theta0=-1.2
  hairbed bistability --eps 0.9 --theta0=-1.5 --json
JSON keys: cusp_eps, folds (list of {omega2, xi, tip_deflection, t}), window ([lower, upper]
or null)
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``bistability`` subcommand's parser."""
    p = add_command(sub, "bistability", run, ABOUT)
    add_eps(p, required=True)
    add_theta0(p, required=True)
    add_json(p)


def run(args: argparse.Namespace) -> int:
    """Print the cusp, the folds and the window (or JSON)."""
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
