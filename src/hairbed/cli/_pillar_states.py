"""``hairbed solve --pillar``: an isolated pillar in a wall shear layer (theory.md §12).

One state at ``--forcing`` (:func:`hairbed.solve_pillar`, ``--root`` choosing in a
snap-through window), every coexisting one with ``--all`` (:func:`hairbed.solve_pillar_all`),
the forcing of a measured ``--tip-deflection`` (:func:`hairbed.solve_pillar_inverse`), or the
branch from rest to ``--branch MAX`` with its folds (:func:`hairbed.continue_pillar`). Given
the SI inputs of a pillar (``--length``, ``--radius``, ``--youngs-modulus``, ``--viscosity``,
...), the state at a ``--wall-shear-stress`` [Pa] (or the ``--velocity`` of a Couette channel,
the ``--pressure-gradient`` of a Poiseuille one) in SI units (:meth:`hairbed.Pillar.deform`).
Every field is printed with its unit, from the one variables table
(:data:`hairbed._variables.PILLAR`).
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import hairbed
from hairbed._variables import PILLAR

from ._options import (
    BED_OPTIONS,
    PILLAR_OPTIONS,
    add_fluid_option,
    pillar_keywords,
    refuse,
    sensor_pillar_from,
)
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
    "pi": "--pi",
    "q": "--q",
    "flow_rate": "--flow-rate",
    "all_branches": "--all-branches",
}

#: The drives of an SI pillar (:meth:`hairbed.Pillar.deform`): dest -> flag.
SI_DRIVES = {
    "wall_shear_stress": "--wall-shear-stress",
    "velocity": "--velocity",
    "pressure_gradient": "--pressure-gradient",
}

#: What only an SI pillar takes (its drives, --drag-scale and --fluid): dest -> flag.
_SI_ONLY = {**SI_DRIVES, "drag_scale": "--drag-scale", "fluid": "--fluid"}

#: The rows of an SI pillar's table: PillarDeformation field -> (row name, label [unit]).
_SI_ROWS = {
    "wall_shear_stress": ("wall_shear_stress_Pa", "wall shear stress tau_w [Pa]"),
    "velocity": ("velocity", "wall speed V = tau_w H/eta of the Couette channel [m/s]"),
    "pressure_gradient": (
        "pressure_gradient_Pa/m",
        "pressure gradient G = 2 tau_w/H of the Poiseuille channel [Pa/m]",
    ),
    "forcing": ("forcing", "forcing Lambda = zeta_perp tau_w L^4/(eta E I) [-]"),
    "tip_deflection": ("tip_deflection_m", "tip position x1 L from the base, along +x [m]"),
    "tip_displacement": ("tip_displacement_m", "tip displacement (x1 - sin theta0) L [m]"),
    "tip_height": ("tip_height_m", "tip height h1 L [m]"),
    "tip_angle": ("tip_angle", "tip angle theta1 [rad]"),
    "base_moment": ("base_moment_N_m", "bending moment at the base E I theta'(0)/L [N m]"),
    "drag": ("drag_N", "streamwise drag on the pillar [N]"),
    "drag_wall_normal": ("drag_wall_normal_N", "wall-normal drag on the pillar [N]"),
    "sensitivity": ("sensitivity_m/Pa", "d(tip deflection)/d(tau_w) [m/Pa]"),
    "reynolds_number": ("reynolds_number", "pillar Reynolds number rho |u(tip)| 2a/eta [-]"),
    "height_in_wall_units": (
        "height_in_wall_units",
        "pillar length in wall units L+ = L sqrt(abs(tau_w)/rho)/nu [-]",
    ),
    "status": ("status", "status (0 converged)"),
}


def add_modes(group: Any) -> None:
    """``--tip-deflection``, ``--all`` and ``--branch`` into the pillar options' group, and
    what an SI pillar takes beside the bed options: ``--wall-shear-stress``,
    ``--drag-scale``."""
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
    group.add_argument(
        "--wall-shear-stress",
        type=float,
        metavar="TAU",
        help="with the SI inputs of a pillar (--length, --radius, --youngs-modulus, "
        "--viscosity; instead of --forcing): the wall shear stress tau_w [Pa]; or "
        "--velocity [m/s] with --profile couette, --pressure-gradient [Pa/m] with poiseuille",
    )
    group.add_argument(
        "--drag-scale",
        type=float,
        metavar="C",
        help="with the SI inputs of a pillar: a factor c > 0 on both drag coefficients [-] "
        "(default 1, Gray & Hancock's)",
    )
    add_fluid_option(group)


def refuse_without_pillar(args: argparse.Namespace) -> None:
    """A pillar's option given without ``--pillar``: a usage error naming it."""
    refuse(
        args,
        {**PILLAR_OPTIONS, **PILLAR_MODES, "wall_shear_stress": "--wall-shear-stress"},
        "needs --pillar (an isolated pillar)",
    )
    refuse(
        args,
        {"drag_scale": "--drag-scale", "fluid": "--fluid"},
        "needs --pillar and its SI inputs",
    )


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


def _check_plot(args: argparse.Namespace) -> str:
    """The image format of --plot, checked (with the path) before any work; "" without."""
    if not args.plot:
        return ""
    if args.branch is not None:
        raise UsageError("--plot draws states; not with --branch (see hairbed figures)")
    from hairbed._optional import optional_import

    optional_import("matplotlib", "solve --plot")
    fmt = figure_format(args.plot, "--plot")
    check_output(args.plot)
    return fmt


def _si_rows(d: Any) -> dict[str, Any]:
    """A PillarDeformation's SI fields, by row name; the drives its channel has not (NaN)
    and the Reynolds number and L+ without a density left out."""
    rows: dict[str, Any] = {}
    for name, (row, _) in _SI_ROWS.items():
        value = getattr(d, name)
        if (
            name in ("velocity", "pressure_gradient", "reynolds_number", "height_in_wall_units")
            and value != value
        ):
            continue
        rows[row] = value
    return rows


def _run_si(args: argparse.Namespace) -> list[Any]:
    """``solve --pillar`` with the SI inputs of a pillar: the state at a wall shear stress
    (or the wall speed of a Couette channel, the pressure gradient of a Poiseuille one)."""
    why = "does not apply to solve --pillar with SI inputs (give --wall-shear-stress [Pa])"
    refuse(args, {**PILLAR_MODES, "root": "--root"}, why)
    pillar = sensor_pillar_from(args, "solve")
    drives = [flag for dest, flag in SI_DRIVES.items() if getattr(args, dest) is not None]
    if len(drives) != 1:
        got = f", got {' and '.join(drives)}" if drives else ""
        raise UsageError(
            "solve --pillar with SI inputs needs one of --wall-shear-stress [Pa], --velocity "
            f"[m/s] (couette) and --pressure-gradient [Pa/m] (poiseuille){got}"
        )
    fmt = _check_plot(args)
    d = pillar.deform(
        args.wall_shear_stress, velocity=args.velocity, pressure_gradient=args.pressure_gradient
    )
    si = _si_rows(d)
    inputs = {"profile": pillar.profile}
    if pillar.height_ratio is not None:
        inputs["height_ratio"] = pillar.height_ratio
    dimensionless = _rows(d.solution, inputs)
    if args.json:
        print_json({**si, "solution": dimensionless})
    else:
        print(f"isolated pillar {pillar!r}")
        print(table(si, {row: note for row, note in _SI_ROWS.values()}))
        print("dimensionless state:")
        message = dimensionless.pop("message")
        print(table(dimensionless, _NOTES))
        if dimensionless["status"] != 0:
            print(f"  status {dimensionless['status']}: {message}")
    if args.plot:
        _plot([d.solution], args.plot, fmt)
    return [d.solution]


def run(args: argparse.Namespace) -> list[Any]:
    """``solve --pillar``: check the options, solve, print (and draw the shapes with
    ``--plot``); returns the states solved."""
    if args.sign != 1 or args.n != 0:
        raise UsageError("--sign and --n do not apply to a pillar (one branch from rest)")
    refuse(args, _HAIR_OPTIONS, "does not apply with --pillar")
    if any(getattr(args, kw) is not None for kw, _ in BED_OPTIONS.values()):
        return _run_si(args)
    refuse(args, _SI_ONLY, "needs the SI inputs of a pillar (--length, --radius, ...)")
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
        raise UsageError(
            "--pillar needs --forcing, --tip-deflection or --branch MAX (or the SI inputs of "
            "a pillar with --wall-shear-stress)"
        )
    if args.root is not None and args.forcing is None:
        raise UsageError("--root chooses the state at --forcing (where several coexist)")
    if args.root is not None and args.all:
        raise UsageError("--root does not apply with --all (which gives every state)")
    if args.all and args.forcing == 0.0:
        raise UsageError(
            "--all needs a non-zero --forcing (at rest the one state is the straight pillar; "
            "drop --all)"
        )
    fmt = _check_plot(args)
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
        states = [hairbed.solve_pillar(args.forcing, theta0, **kw, root=args.root or "low")]
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
