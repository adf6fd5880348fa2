"""``hairbed solve``: one state (or every coexisting one) as a table or JSON."""

from __future__ import annotations

import argparse
import sys
from typing import Any

import hairbed
from hairbed._optional import optional_import
from hairbed._variables import POROUS, SI

from . import _pillar_states
from ._options import (
    add_bed_options,
    add_branch,
    add_command,
    add_eps,
    add_json,
    add_pillar_options,
    add_theta0,
    bed_from,
    refuse,
    refuse_model,
)
from ._output import (
    check_output,
    figure_format,
    print_json,
    print_states,
    save_figure,
    solution_table,
    table,
)
from ._report import UsageError

#: ``hairbed solve --help``: the summary line, the description and the examples.
ABOUT = """solve one state (table or JSON)

Solve the boundary-value problem for one set of inputs.

examples:
  hairbed solve --omega2 2 --eps 0.5
  hairbed solve --omega2 2 --eps 0.5 --theta0 0.3 --json
  hairbed solve --omega2 200 --eps 0.5 --all-branches --plot states.png
  hairbed solve --omega2 1.2 --eps 0.9 --theta0 -1.5 --root high
  hairbed solve --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 \\
      --channel-height 2e-3 --viscosity 1 --spacing 400e-6 --velocity 0.1
  hairbed solve --omega2 0.5 --eps 0.5 --pi 2        # a pump's pressure gradient too
  hairbed solve --length 1e-3 ... --spacing 400e-6 --pressure-gradient 2e4
  hairbed solve --omega2 2 --eps 0.5 --kappa 0.01   # a porous bed (theory.md §13)
  hairbed solve --omega2 1.2 --eps 0.9 --theta0=-1.5 --kappa 1e-3 --all   # 3 states
  hairbed solve --pi 5 --eps 0.5 --kappa 0.01 --json  # a porous bed under a pump
  hairbed solve --length 1e-3 ... --spacing 400e-6 --velocity 0.1 --model porous \\
      --drag array                                   # an SI porous bed
  hairbed solve --pillar --forcing 2                 # an isolated pillar (theory.md §12)
  hairbed solve --pillar --forcing 15 --theta0=-1.4 --all --json
  hairbed solve --pillar --tip-deflection 0.3 --profile poiseuille --height-ratio 0.5
  hairbed solve --pillar --forcing 15 --theta0=-1.4 --root mid   # one of them
  hairbed solve --pillar --branch 40 --theta0=-1.4   # the snap-through branch and its folds
  hairbed solve --pillar --length 500e-6 --radius 25e-6 --youngs-modulus 1e6 \\
      --viscosity 1e-3 --wall-shear-stress 2       # an SI pillar: the state at tau_w [Pa]
"""

__all__ = ["ABOUT", "add_parser", "run", "twirling_onset"]


def add_parser(sub: Any) -> None:
    """The ``solve`` subcommand's parser."""
    p = add_command(sub, "solve", run, ABOUT)
    p.add_argument("--omega2", type=float, help="forcing omega^2 [-], >= 0")
    add_eps(p)
    add_theta0(p)
    add_branch(
        p,
        sign=1,
        n=0,
        root=None,
        root_help="which state where several coexist (default: inside a bistable window, all "
        "of them, labelled low/mid/high with their stability; elsewhere the one state); with "
        "--pillar --forcing, the state in a snap-through window (default low)",
    )
    p.add_argument(
        "--all-branches",
        action="store_true",
        help="every state on every branch, labelled low/mid/high and stable/unstable; below "
        "the twirling onset (the fold of branch sign=-1, n=0) the physical states only, with "
        "the onset's omega2",
    )
    add_json(p, "print JSON (fields by API names)")
    p.add_argument("--plot", metavar="FILE", help="also draw the profile(s) into FILE (PNG)")
    pump = p.add_argument_group(
        "pump drives (the distributed-load solver, hairbed.solve_loaded; at most one)"
    )
    pump.add_argument(
        "--pi", type=float, metavar="PI", help="dimensionless pressure gradient A G L^3/(E I) [-]"
    )
    pump.add_argument(
        "--q", type=float, metavar="Q", help="dimensionless flow rate 6 A eta Q' L^2/(E I H^2) [-]"
    )
    pump.add_argument(
        "--pressure-gradient",
        type=float,
        metavar="G",
        help="with a bed: the pump's pressure gradient G = -dp/dx [Pa/m]",
    )
    pump.add_argument(
        "--flow-rate",
        type=float,
        metavar="Q",
        help="with a bed: the pump's flow rate per unit width Q' [m^2/s]",
    )
    porous = p.add_argument_group(
        "a porous bed, dimensionless (hairbed.solve_porous, theory.md §13; with --omega2, "
        "--eps, --theta0, --pi or --q)"
    )
    porous.add_argument(
        "--kappa",
        type=float,
        metavar="K",
        help="the bed's permeability over L^2, kappa = k/L^2 [-], > 0: solve the porous "
        "bed (its drag ratio is --gamma; --all lists every state, --root picks one)",
    )
    add_bed_options(p, model=True)
    pillar = add_pillar_options(p)
    _pillar_states.add_modes(pillar)
    for action in pillar._group_actions:
        if action.dest == "gamma":  # shared with the porous bed, whose default is 1
            action.help = (
                "drag ratio gamma = zeta_par/zeta_perp [-], in (0, 1] (default 0.5 with "
                "--pillar, 1 with --kappa)"
            )
        elif action.dest == "all":
            action.help = f"{action.help}; with --kappa every state of the porous bed"


#: The SI table's rows (named with their unit suffix) -> their label and unit.
_SI_NOTES = {
    f"{name}_{v.unit}" if v.unit not in ("-", "rad", "m/s") else name: v.heading
    for name, v in SI.items()
}
_SI_NOTES["eps"] = "confinement eps = L/H [-]"
_SI_NOTES["kappa"] = "permeability kappa = k/L^2 [-] (--model porous)"
_SI_NOTES["drag_ratio"] = "drag ratio gamma = zeta_par/zeta_perp [-] (--model porous)"


def _pump_options(args: argparse.Namespace) -> list[str]:
    names = ("pi", "q", "pressure_gradient", "flow_rate")
    return ["--" + n.replace("_", "-") for n in names if getattr(args, n) is not None]


def _loaded_table(state: Any) -> dict[str, Any]:
    """The fields of a LoadedState by API names (the inputs, the tip, the solver's)."""
    keys = ("drive", "omega2", "eps", "theta0", "pi", "q", "tip_height", "tip_deflection")
    rest = ("tip_angle", "base_curvature", "tip_load", "distributed_load", "status")
    extra = ("error_estimate", "residual", "nit", "num")
    out = {k: getattr(state, k) for k in (*keys, *rest, *extra)}
    out["message"] = state.message
    return {k: v for k, v in out.items() if not (isinstance(v, float) and v != v)}


#: The porous table's rows -> their label and unit.
_POROUS_NOTES = {name: v.heading for name, v in POROUS.items()}
#: The fields of a PorousState, in the order of the dataclass (its arrays left out).
_POROUS_FIELDS = tuple(POROUS)


def porous_table(state: Any) -> dict[str, Any]:
    """Every field of a PorousState by API names (``stable`` where classified), its success
    and message; NaN kept (null in JSON), so that every state has the same keys."""
    out = {k: getattr(state, k) for k in ("drive", *_POROUS_FIELDS) if k != "stable"}
    if state.stable is not None:
        out["stable"] = state.stable
    out["success"] = state.success
    out["message"] = state.message
    return out


#: The options that a dimensionless porous bed (--kappa) does not take: dest -> flag.
_NOT_POROUS = {
    "pressure_gradient": "--pressure-gradient",
    "flow_rate": "--flow-rate",
    "all_branches": "--all-branches",
    "plot": "--plot",
    "velocity": "--velocity",
}
#: The pillar options that it does not take either (--gamma and --all it shares).
_PILLAR_ONLY = {
    "forcing": "--forcing",
    "profile": "--profile",
    "height_ratio": "--height-ratio",
    "slenderness": "--slenderness",
    "tip_load": "--tip-load",
    "tip_deflection": "--tip-deflection",
    "branch": "--branch",
    "wall_shear_stress": "--wall-shear-stress",
    "drag_scale": "--drag-scale",
    "fluid": "--fluid",
}


def _porous_labels(states: list[Any]) -> list[str]:
    """low/mid/high of the states of solve_porous_all (sorted by tip height); "only" for one."""
    if len(states) == 1:
        return ["only"]
    if len(states) == 3:
        return ["low", "mid", "high"]
    if len(states) == 2:
        return ["low", "high"]
    return [f"state {i + 1}" for i in range(len(states))]


def _solve_porous(args: argparse.Namespace) -> None:
    """--kappa: the porous bed on the dimensionless inputs (hairbed.solve_porous, or every
    state by hairbed.solve_porous_all with --all)."""
    kappa = args.kappa
    if args.pillar:
        raise UsageError("--kappa does not apply to --pillar (a porous bed of hairs)")
    refuse(args, _PILLAR_ONLY, "does not apply to a porous bed (--kappa); it needs --pillar")
    if bed_from(args) is not None:
        raise UsageError(
            "--kappa is the dimensionless porous bed; for a bed in SI units give --model "
            "porous instead"
        )
    refuse(args, _NOT_POROUS, "does not apply to the dimensionless porous bed (--kappa)")
    if args.sign != 1 or args.n != 0:
        raise UsageError("--sign and --n do not apply to a porous bed (one branch from rest)")
    if args.pi is not None and args.q is not None:
        raise UsageError("give at most one pump drive, got --pi and --q")
    if args.eps is None:
        raise UsageError("give --eps with --kappa")
    if args.omega2 is None and args.pi is None and args.q is None:
        raise UsageError("give --omega2 (or a pump's --pi or --q) with --kappa")
    if args.all and args.root is not None:
        raise UsageError("--root does not apply with --all (which gives every state)")
    w = 0.0 if args.omega2 is None else args.omega2
    theta0 = 0.0 if args.theta0 is None else args.theta0
    inputs: dict[str, Any] = {"kappa": kappa, "pi": args.pi, "q": args.q}
    if args.gamma is not None:
        inputs["gamma"] = args.gamma
    if not args.all:
        st = hairbed.solve_porous(w, args.eps, theta0, root=args.root or "low", **inputs)
        rows = porous_table(st)
        if args.json:
            print_json(rows)
        else:
            print(table(rows, _POROUS_NOTES))
        return
    states = hairbed.solve_porous_all(w, args.eps, theta0, **inputs)
    labels = _porous_labels(states)
    if args.json:
        print_json([{**porous_table(st), "root": lab} for st, lab in zip(states, labels)])
        return
    gamma = states[0].gamma
    at = f"omega2={w:g}, eps={args.eps:g}, theta0={theta0:g}, kappa={kappa:g}, gamma={gamma:g}"
    if args.pi is not None:
        at += f", pi={args.pi:g}"
    if args.q is not None:
        at += f", q={args.q:g}"
    found = [st for st in states if st.status >= 0]
    print(f"{len(found)} state(s) of the porous bed at {at}:")
    for st, lab in zip(states, labels):
        word = {True: "stable", False: "unstable", None: "not classified"}[st.stable]
        print(f"{lab} state ({word}):")
        print(table(porous_table(st), _POROUS_NOTES))


def _solve_loaded(args: argparse.Namespace) -> list[Any]:
    """--pi or --q: the distributed-load solver on the dimensionless inputs."""
    if args.eps is None:
        raise UsageError("give --eps with --pi or --q")
    if args.pressure_gradient is not None or args.flow_rate is not None:
        raise UsageError("--pressure-gradient and --flow-rate need the physical inputs of a bed")
    if args.all_branches or args.sign != 1 or args.n != 0:
        raise UsageError("--pi and --q solve the physical state (no --all-branches, --sign, --n)")
    w = 0.0 if args.omega2 is None else args.omega2
    theta0 = 0.0 if args.theta0 is None else args.theta0
    st = hairbed.solve_loaded(w, args.eps, theta0, pi=args.pi, q=args.q, root=args.root or "low")
    rows = _loaded_table(st)
    if args.json:
        print_json(rows)
    else:
        print(table(rows))
    return [st]


def _solve_bed(args: argparse.Namespace, bed: Any) -> list[Any]:
    """The state of a bed at --velocity (or a pump's drive), in SI units and dimensionless."""
    if args.omega2 is not None or args.eps is not None or args.theta0 is not None:
        raise UsageError("give either --omega2/--eps/--theta0 or the physical inputs, not both")
    if args.pi is not None or args.q is not None:
        raise UsageError("with a bed, give --pressure-gradient [Pa/m] or --flow-rate [m^2/s]")
    pumped = args.pressure_gradient is not None or args.flow_rate is not None
    if args.velocity is None and not pumped:
        raise UsageError("physical inputs need --velocity [m/s] (or a pump's drive)")
    if pumped and args.all_branches:
        raise UsageError("--all-branches applies to the wall-driven channel only")
    porous = bed.model == "porous"
    if porous and args.all_branches:
        raise UsageError("--all-branches applies to the dense bed (--model dense) only")
    state = bed.deform(
        args.velocity,
        pressure_gradient=args.pressure_gradient,
        flow_rate=args.flow_rate,
        root=args.root or "low",
    )
    si = {
        "velocity": state.velocity,
        "omega2": state.omega2,
        "eps": bed.eps,
        "tip_deflection_m": state.tip_deflection,
        "tip_height_m": state.tip_height,
        "tip_angle": state.tip_angle,
        "wall_shear_stress_Pa": state.wall_shear_stress,
        "force_per_hair_N": state.force_per_hair,
        "stress_ratio": state.stress_ratio,
        "tip_displacement_m": state.tip_displacement,
    }
    if bed.density is not None:
        si["reynolds_number"] = state.reynolds_number
    if pumped:
        si["pressure_gradient_Pa/m"] = state.pressure_gradient
        si["flow_rate_m^2/s"] = state.flow_rate
    if porous:
        si["kappa"] = bed.kappa
        si["drag_ratio"] = bed.drag_ratio
        dimensionless = porous_table(state.solution)
    elif pumped:
        dimensionless = _loaded_table(state.solution)
    else:
        dimensionless = state.solution.as_dict()
    if args.json:
        print_json({**si, "solution": dimensionless})
    else:
        print(f"Hair bed {bed!r}")
        print(table(si, _SI_NOTES))
        print("dimensionless state:")
        if porous:
            print(table(dimensionless, _POROUS_NOTES))
        else:
            print(table(dimensionless) if pumped else solution_table(state.solution))
    return [] if porous else [state.solution]


def twirling_onset(eps: float, theta0: float) -> float:
    """The least omega^2 at which a twirling branch has a state: the fold of the branch
    (sign=-1, n=0), its minimum of omega^2 (theory.md §9; the other twirling branches start
    higher); NaN if the fold search finds none."""
    from hairbed.branches import fold_parameters

    t = fold_parameters(eps, theta0, sign=-1, n=0)
    if t.size == 0:
        return float("nan")
    w = hairbed.from_parameter(t, eps, theta0, sign=-1, n=0).omega2
    return float(min(w.tolist() if hasattr(w, "tolist") else [w]))


def _below_twirling(eps: float, theta0: float) -> str:
    """Why --all-branches found only physical states: the forcing is below the onset."""
    onset = twirling_onset(eps, theta0)
    if onset != onset:
        return "no twirling branch has a state at this forcing"
    return (
        f"no twirling branch has a state below omega2 = {onset:.10g}, the fold of branch "
        "sign=-1, n=0 where the first twirling states appear"
    )


def _solve_dimensionless(args: argparse.Namespace) -> list[Any]:
    """The state at --omega2/--eps/--theta0, or every coexisting one, labelled."""
    if args.omega2 is None or args.eps is None:
        raise UsageError("give --omega2 and --eps (or the physical inputs with --velocity)")
    w, eps = args.omega2, args.eps
    theta0 = 0.0 if args.theta0 is None else args.theta0
    at = f"omega2={w:g}, eps={eps:g}, theta0={theta0:g}"
    if args.all_branches:
        sols = hairbed.solve_all(w, eps, theta0)
        head = f"{len(sols)} state(s) at {at}:"
        if all(s.physical for s in sols):  # below the twirling onset: say so, and where it is
            why = _below_twirling(eps, theta0)
            if args.json:
                print(f"hairbed: note: {why}", file=sys.stderr)
            head = f"{len(sols)} state(s) at {at} (the physical branch only: {why}):"
        print_states(hairbed.branches.label_states(sols), args.json, head)
        return sols
    branch = {"sign": args.sign, "n": args.n}
    s = hairbed.solve(w, eps, theta0, **branch, root=args.root or "low")
    if args.root is None and s.success and s.n_roots > 1:
        # inside a window: every state of the branch, labelled, with its stability
        roots = ("low", "mid", "high") if s.n_roots == 3 else ("low", "high")
        sols = [hairbed.solve(w, eps, theta0, **branch, root=r) for r in roots]
        head = (
            f"{len(sols)} states on branch sign={args.sign:+d}, n={args.n} at {at} "
            "(a bistable window; --root selects one):"
        )
        print_states(hairbed.branches.label_states(sols), args.json, head)
        return sols
    if args.json:
        print_json(s.as_dict())
    else:
        print(solution_table(s))
    return [s]


def run(args: argparse.Namespace) -> int:
    """Solve, print, and draw the profiles with --plot."""
    if args.kappa is not None:
        _solve_porous(args)
        return 0
    if args.pillar:
        refuse_model(args, "applies to a bed of hairs, not --pillar")
        _pillar_states.run(args)
        return 0
    _pillar_states.refuse_without_pillar(args)
    fmt = ""
    if args.plot:  # checked before any work
        optional_import("matplotlib", "solve --plot")
        fmt = figure_format(args.plot, "--plot")
        check_output(args.plot)
    bed = bed_from(args)
    pumps = _pump_options(args)
    if len(pumps) > 1:
        raise UsageError(f"give at most one pump drive, got {' and '.join(pumps)}")
    if pumps and args.plot:
        raise UsageError("--plot draws closed-form states; not with a pump drive")
    if bed is not None and bed.model == "porous" and args.plot:
        raise UsageError("--plot draws closed-form states; not with --model porous")
    if bed is not None:
        sols = _solve_bed(args, bed)
    elif args.pi is not None or args.q is not None:
        sols = _solve_loaded(args)
    elif pumps:
        raise UsageError(f"{pumps[0]} needs the physical inputs of a bed (--length, ...)")
    else:
        sols = _solve_dimensionless(args)
    if args.plot:
        from hairbed.plotting import fig_states

        save_figure(fig_states(sols), args.plot, fmt)
        what = f"{len(sols)} profile{'s' if len(sols) > 1 else ''}"
        print(f"wrote {args.plot} ({fmt.upper()}, {what})", file=sys.stderr)
    return 0
