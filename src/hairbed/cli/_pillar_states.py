"""``hairbed solve --pillar``: an isolated pillar in a wall shear layer (theory.md §12).

One state at ``--forcing`` (:func:`hairbed.solve_pillar`), every coexisting one with ``--all``
(:func:`hairbed.solve_pillar_all`), the forcing of a measured ``--tip-deflection``
(:func:`hairbed.solve_pillar_inverse`), or the branch from rest to ``--branch MAX`` with its
folds (:func:`hairbed.continue_pillar`). Every field is printed with its unit, from the one
variables table (:data:`hairbed._variables.PILLAR`).
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import hairbed
from hairbed._variables import PILLAR

from ._options import BED_OPTIONS, PILLAR_OPTIONS, pillar_keywords, refuse
from ._output import check_output, figure_format, print_json, save_figure, table
from ._report import UsageError

__all__ = ["PILLAR_MODES", "add_modes", "refuse_without_pillar", "run"]

#: The options choosing what ``solve --pillar`` computes: dest -> flag.
PILLAR_MODES = {"tip_deflection": "--tip-deflection", "all": "--all", "branch": "--branch"}

#: Each pillar variable -> its label and unit, for the tables.
_NOTES = {name: v.heading for name, v in PILLAR.items()}
_NOTES["profile"] = "undisturbed profile U(z)"

#: The options of a bed of hairs, which a pillar does not take: dest -> flag.
_HAIR_OPTIONS = {
    "omega2": "--omega2",
    "eps": "--eps",
    "root": "--root",
    "pi": "--pi",
    "q": "--q",
    "pressure_gradient": "--pressure-gradient",
    "flow_rate": "--flow-rate",
    "velocity": "--velocity",
    "all_branches": "--all-branches",
    **{kw: flag for flag, (kw, _) in BED_OPTIONS.items()},
}


def add_modes(group: Any) -> None:
    """``--tip-deflection``, ``--all`` and ``--branch`` into the pillar options' group."""
    group.add_argument(
        "--tip-deflection",
        type=float,
        metavar="X1",
        help="the inverse: the forcing of a measured tip deflection x1 [L], in (-1, 1)",
    )
    group.add_argument(
        "--all",
        action="store_true",
        help="every coexisting state at --forcing, with its stability (three in a "
        "snap-through window)",
    )
    group.add_argument(
        "--branch",
        type=float,
        metavar="MAX",
        help="the branch of states from rest to the forcing MAX [-], with its folds",
    )


def refuse_without_pillar(args: argparse.Namespace) -> None:
    """A pillar's option given without ``--pillar``: a usage error naming it."""
    refuse(args, {**PILLAR_OPTIONS, **PILLAR_MODES}, "needs --pillar (an isolated pillar)")


def _as_given(value: Any, flag: str) -> Any:
    return value


def _rows(state: Any, inputs: dict[str, Any]) -> dict[str, Any]:
    """A PillarState's fields by API names, in the table's order (its inputs, its outputs,
    the solver's), with the profile first and the status's message after it."""
    rows: dict[str, Any] = dict(inputs)
    for name in PILLAR:
        if name == "height_ratio":
            continue
        if name == "stable" and state.stable is None:
            continue
        rows[name] = getattr(state, name)
        if name == "status":
            rows["message"] = state.message
    return rows


def _branch_rows(branch: Any, inputs: dict[str, Any], end: float, theta0: float) -> dict[str, Any]:
    folds = [{"forcing": float(lam), "tip_deflection": float(x1)} for lam, x1 in branch.folds]
    return {
        **inputs,
        "forcing_max": end,
        "theta0": theta0,
        "status": branch.status,
        "folds": folds,
        "tip_deflection": branch.tip_deflection,
        "forcing": branch.forcing,
        "tip_height": branch.tip_height,
        "stable": branch.stable,
    }


def _print_branch(rows: dict[str, Any]) -> None:
    x1 = np.asarray(rows["tip_deflection"])
    print(
        f"pillar branch from rest to forcing {rows['forcing_max']:g} at theta0="
        f"{rows['theta0']:g} ({rows['profile']} profile): {x1.size} points, status "
        f"{rows['status']}"
    )
    folds = rows["folds"]
    if not folds:
        print("no fold: one state at every forcing of the range")
    for k, fold in enumerate(folds, start=1):
        at, tip = fold["forcing"], fold["tip_deflection"]
        print(f"fold {k}: forcing {at:.12g}, tip deflection {tip:.12g}")
    heads = ("tip_deflection", "forcing", "tip_height", "stable")
    print("  ".join(f"{h:>22}" for h in heads))
    for x, lam, h, st in zip(x1, rows["forcing"], rows["tip_height"], rows["stable"]):
        print(f"{x:>22.15g}  {lam:>22.15g}  {h:>22.15g}  {bool(st)!s:>22}")


def _plot(states: list[Any], path: str, fmt: str) -> None:
    import sys

    from hairbed.plotting import fig_pillar_states

    save_figure(fig_pillar_states(states), path, fmt)
    what = f"{len(states)} shape{'s' if len(states) > 1 else ''}"
    print(f"wrote {path} ({fmt.upper()}, {what})", file=sys.stderr)


def run(args: argparse.Namespace) -> list[Any]:
    """``solve --pillar``: check the options, solve, print (and draw the shapes with
    ``--plot``); returns the states solved."""
    if args.sign != 1 or args.n != 0:
        raise UsageError("--sign and --n do not apply to a pillar (one branch from rest)")
    refuse(args, _HAIR_OPTIONS, "does not apply with --pillar")
    modes = [
        flag for dest, flag in PILLAR_MODES.items() if getattr(args, dest) not in (None, False)
    ]
    if args.forcing is not None and args.tip_deflection is not None:
        raise UsageError("give --forcing or --tip-deflection, not both")
    if args.all and args.forcing is None:
        raise UsageError("--all needs --forcing")
    if len(modes) > 1:
        raise UsageError(
            f"give one of --tip-deflection, --all and --branch, got {' and '.join(modes)}"
        )
    if args.branch is not None and args.forcing is not None:
        raise UsageError("--branch MAX gives the range of forcing; not with --forcing")
    if args.forcing is None and args.tip_deflection is None and args.branch is None:
        raise UsageError("--pillar needs --forcing, --tip-deflection or --branch MAX")
    fmt = ""
    if args.plot:  # checked before any work
        if args.branch is not None:
            raise UsageError("--plot draws states; not with --branch (see hairbed figures)")
        from hairbed._optional import optional_import

        optional_import("matplotlib", "solve --plot")
        fmt = figure_format(args.plot, "--plot")
        check_output(args.plot)
    kw = pillar_keywords(args, _as_given)
    theta0 = 0.0 if args.theta0 is None else args.theta0
    inputs = {"profile": kw.get("profile", "sublayer")}
    if "height_ratio" in kw:
        inputs["height_ratio"] = kw["height_ratio"]
    if args.branch is not None:
        branch = hairbed.continue_pillar(args.branch, theta0, **kw)
        rows = _branch_rows(branch, inputs, args.branch, theta0)
        if args.json:
            print_json(rows)
        else:
            _print_branch(rows)
        return []
    if args.tip_deflection is not None:
        states = [hairbed.solve_pillar_inverse(args.tip_deflection, theta0, **kw)]
    elif args.all:
        states = hairbed.solve_pillar_all(args.forcing, theta0, **kw)
    else:
        states = [hairbed.solve_pillar(args.forcing, theta0, **kw)]
    docs = [_rows(st, inputs) for st in states]
    if args.json:
        print_json(docs if args.all else docs[0])
    else:
        _print_states(docs, args, theta0)
    if args.plot:
        _plot(states, args.plot, fmt)
    return states


def _print_states(docs: list[dict[str, Any]], args: argparse.Namespace, theta0: float) -> None:
    if args.all:
        print(f"{len(docs)} pillar state(s) at forcing {args.forcing:g}, theta0={theta0:g}:")
    for k, rows in enumerate(docs):
        if args.all:
            word = {True: "stable", False: "unstable", None: "not classified"}[rows.get("stable")]
            print(f"state {k + 1} ({word}):")
        message = rows.pop("message")
        print(table(rows, _NOTES))
        if rows["status"] != 0:  # the words of a failure, below the table (too long for it)
            print(f"  status {rows['status']}: {message}")
