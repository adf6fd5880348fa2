"""``hairbed valve``: a hair-bed valve's flow against pressure drop, and its diodicity."""

from __future__ import annotations

import argparse
from typing import Any

import hairbed

from ._grids import spec
from ._options import add_bed_options, add_command, add_json, need_bed, refuse
from ._output import (
    NO_COMPRESS_HELP,
    check_dataset_output,
    check_output,
    figure_format,
    print_json,
    save_figure,
    write_dataset_output,
)
from ._report import UsageError

#: ``hairbed valve --help``: the summary line, the description and the examples.
ABOUT = """flow through a channel lined by a bed against the pressure drop; the diodicity

A pump holds a pressure drop dp [Pa] over a channel of length --channel-length [m], both walls
at rest: the pressure gradient dp/l loads the hairs along their height (the distributed-load
solver, hairbed.solve_loaded) and the flow per unit width through the gap above the tips,
Q' = G g^3/(12 eta), follows (hairbed.valve.valve_curve). Each line gives dp, Q' [m^2/s], the
resistance relative to the empty channel (H/g)^3, the tip's deflection dx1 [m] (its
displacement from rest along +x, (x1 - sin theta0) L; --json gives it as tip_displacement,
beside the tip's position from the base, tip_deflection = x1 L), its height h1 [m] and the
solver's status. With --diodicity the drops are taken in magnitude and each line gives
Di = Q'(+dp)/abs(Q'(-dp)) (hairbed.valve.diodicity): above 1 when the hairs lean towards +x
(--base-angle > 0), as forward flow bends them down and opens the gap.

examples:
  hairbed valve --pressure-drop 10:1000:5:log --channel-length 0.01 --length 1.8e-3 \\
      --radius 50e-6 --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 \\
      --spacing 400e-6 --base-angle 1.0
  hairbed valve --pressure-drop 200 --diodicity --channel-length 0.01 ... --json
  hairbed valve --pressure-drop +-10:1e3:20:log --channel-length 0.01 ... --plot valve.png
  hairbed valve --pressure-drop 200 --diodicity --channel-length 0.01 ... --model porous
      (a porous bed: the flow through bed and gap; --states too)

every coexisting state (--states): the branch of states is followed by continuation from rest
over the range (hairbed.valve.valve_states); each line gives the set drive, the number of
states, how many are stable and each state's Q' (or dp) with s (stable) or u (unstable); then
the folds and the jumps of the quasi-static ramps up and down (the hysteresis loop). The pump
sets the pressure drop (--pressure-drop) or the flow rate per unit width (--flow-rate [m^2/s],
which implies --states); a set flow rate against the hairs' lean is bistable:
  hairbed valve --states --flow-rate 0:3e-6:13 --channel-length 0.01 --length 1.6e-3 \\
      --radius 50e-6 --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 \\
      --spacing 400e-6 --base-angle -1.2
  ... --states --flow-rate 0:3e-6:61 --out valve.nc   (also .csv, .zarr, .parquet)
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``valve`` subcommand's parser."""
    p = add_command(sub, "valve", run, ABOUT)
    p.add_argument(
        "--pressure-drop",
        metavar="SPEC",
        help="pressure drop dp = p(0) - p(l) [Pa]: a value, a comma list, START:STOP:NUM[:log] "
        "or the two-sided +-START:STOP:NUM:log (e.g. +-10:1e4:16:log: 16 drops from 10 Pa to "
        "10 kPa each way, negative first)",
    )
    p.add_argument(
        "--flow-rate",
        metavar="SPEC",
        help="set flow rate per unit width Q' [m^2/s] (a SPEC like --pressure-drop); implies "
        "--states",
    )
    p.add_argument(
        "--channel-length",
        type=float,
        required=True,
        metavar="L",
        help="length l of the channel [m], > 0",
    )
    p.add_argument(
        "--diodicity",
        action="store_true",
        help="the diodicity Q'(+dp)/abs(Q'(-dp)) at each abs(dp) instead of the curve",
    )
    p.add_argument(
        "--root",
        default="low",
        choices=("low", "mid", "high"),
        help="the state where several coexist (default low)",
    )
    g = p.add_argument_group("every coexisting state (--states)")
    g.add_argument(
        "--states",
        action="store_true",
        help="every coexisting state at each drive, the folds and the ramps' jumps",
    )
    g.add_argument(
        "--velocity",
        type=float,
        metavar="V",
        help="top wall speed v [m/s] (both walls at rest without it)",
    )
    g.add_argument(
        "--max-steps",
        type=int,
        default=4000,
        metavar="N",
        help="continuation steps per direction, in [1, 10^6] (default 4000)",
    )
    g.add_argument(
        "--out",
        metavar="FILE",
        help="the states with units: .nc, .zarr, .csv or .parquet (a table on stdout without it)",
    )
    g.add_argument("--no-compress", action="store_true", help=NO_COMPRESS_HELP)
    add_json(p)
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="also draw what was computed into FILE (PNG, or the format of its extension): "
        "the curve, the diodicity or every state (hairbed.plotting.fig_valve_result)",
    )
    add_bed_options(p, velocity=False, model=True)


def _rows(curve: Any) -> list[dict[str, Any]]:
    import numpy as np

    fields: tuple[str, ...] = (
        "pressure_drop",
        "flow_rate",
        "resistance_ratio",
        "tip_displacement",
        "tip_height",
    )
    cols = {f: np.atleast_1d(np.asarray(getattr(curve, f), dtype=float)) for f in fields[:3]}
    cols["tip_displacement"] = np.atleast_1d(
        np.asarray(curve.states.tip_displacement, dtype=float)
    )
    cols["tip_height"] = np.atleast_1d(np.asarray(curve.tip_height, dtype=float))
    cols["tip_deflection"] = np.atleast_1d(np.asarray(curve.tip_deflection, dtype=float))
    fields = (*fields, "tip_deflection")
    status = np.atleast_1d(np.asarray(curve.status))
    return [
        {**{f: float(cols[f][i]) for f in fields}, "status": int(status[i])}
        for i in range(status.size)
    ]


_STATES_ONLY = {
    "velocity": "--velocity",
    "out": "--out",
    "no_compress": "--no-compress",
}


def _state_rows(s: Any) -> list[dict[str, Any]]:
    """Each grid point of a ValveStates: the set drive, the counts and every state."""
    fields = ("pressure_drop", "flow_rate", "tip_height", "resistance_ratio")
    return [
        {
            "value": float(s.values[i]),
            "count": int(s.count[i]),
            "count_stable": int(s.count_stable[i]),
            "covered": bool(s.covered[i]),
            "states": [
                {**{f: float(getattr(s, f)[i, k]) for f in fields}, "stable": bool(s.stable[i, k])}
                for k in range(int(s.count[i]))
            ],
        }
        for i in range(s.values.size)
    ]


def _states_doc(s: Any) -> dict[str, Any]:
    """A ValveStates as plain JSON: units in the keys' documentation (SI throughout)."""
    from dataclasses import asdict

    folds = [
        {"pressure_drop": float(a), "flow_rate": float(b), "tip_height": float(c)}
        for a, b, c in zip(s.fold_pressure_drop, s.fold_flow_rate, s.fold_tip_height)
    ]
    ramps = {
        name: [asdict(j) for j in r.jumps]
        for name, r in (("up", s.ramp_up), ("down", s.ramp_down))
    }
    return {
        "drive": s.drive,
        "units": {"value": "Pa" if s.drive == "pressure" else "m^2/s", "pressure_drop": "Pa",
                  "flow_rate": "m^2/s", "tip_height": "m", "resistance_ratio": "1"},
        "channel_length": s.channel_length,
        "velocity": s.velocity,
        "points": _state_rows(s),
        "folds": folds,
        "jumps": ramps,
        "status": s.status,
        "message": s.message,
    }  # fmt: skip


def _print_states(s: Any) -> None:
    pump = "pressure drop" if s.drive == "pressure" else "flow rate"
    walls = "both walls at rest" if s.velocity == 0.0 else f"top wall at {s.velocity:g} m/s"
    print(f"valve states over l = {s.channel_length:g} m, set {pump} ({walls}):")
    if s.drive == "pressure":
        head, other, unit = "dp [Pa]", "flow_rate", "Q' [m^2/s]"
    else:
        head, other, unit = "Q' [m^2/s]", "pressure_drop", "dp [Pa]"
    print(f"  {head:>12}  states  stable  each state's {unit} (s stable, u unstable)")
    for i, value in enumerate(s.values):
        cells = "  ".join(
            f"{getattr(s, other)[i, k]:12.6g} {'s' if s.stable[i, k] else 'u'}"
            for k in range(int(s.count[i]))
        )
        mark = "" if s.covered[i] else "  (not reached)"
        print(f"  {value:12.6g}  {s.count[i]:6d}  {s.count_stable[i]:6d}  {cells}{mark}")
    print(f"folds: {s.fold_pressure_drop.size}")
    for a, b, c in zip(s.fold_pressure_drop, s.fold_flow_rate, s.fold_tip_height):
        print(f"  dp = {a:.10g} Pa, Q' = {b:.10g} m^2/s, h1 = {c:.10g} m")
    print("jumps of the quasi-static ramps (the hysteresis loop):")
    none = True
    for name, ramp in (("up", s.ramp_up), ("down", s.ramp_down)):
        for j in ramp.jumps:
            none = False
            print(
                f"  {name:>4}: dp {j.pressure_drop_before:.6g} -> {j.pressure_drop_after:.6g} Pa,"
                f" Q' {j.flow_rate_before:.6g} -> {j.flow_rate_after:.6g} m^2/s,"
                f" h1 {j.tip_height_before:.6g} -> {j.tip_height_after:.6g} m"
            )
    if none:
        print("  none (one state at every drive of the range)")


def _run_states(args: argparse.Namespace, bed: Any, fmt: str = "") -> int:
    """``--states``: every coexisting state, the folds and the jumps (table, JSON or file)."""
    import sys

    import numpy as np

    if args.diodicity:
        raise UsageError("--diodicity does not apply with --states or --flow-rate")
    if args.out is not None and args.json:
        raise UsageError("--json does not apply with --out (the file has the states)")
    to_stdout = args.out is None or check_dataset_output(args.out, args.no_compress)
    if args.pressure_drop is not None:
        kw = {"pressure_drop": spec(args.pressure_drop, "--pressure-drop")}
    else:
        kw = {"flow_rate": spec(args.flow_rate, "--flow-rate")}
    kw = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in kw.items()}
    if not 1 <= args.max_steps <= 10**6:
        raise UsageError(f"--max-steps must be in [1, 10^6], got {args.max_steps}")
    velocity = 0.0 if args.velocity is None else args.velocity
    s = hairbed.valve.valve_states(
        bed, args.channel_length, velocity=velocity, max_steps=args.max_steps, **kw
    )
    if not s.success:  # a partial answer: said once, as the library's warnings are
        print(f"hairbed: warning: {s.message}", file=sys.stderr)
    if args.out is not None:
        write_dataset_output(s.to_dataset(), args.out, args.no_compress)
        if not to_stdout:
            jumps = len(s.ramp_up.jumps) + len(s.ramp_down.jumps)
            print(f"{s.fold_pressure_drop.size} folds, {jumps} jumps", file=sys.stderr)
    elif args.json:
        print_json(_states_doc(s))
    else:
        _print_states(s)
    if args.plot:
        _plot(s, args.plot, fmt)
    return 0


def _check_plot(args: argparse.Namespace) -> str:
    """The image format of --plot, its path checked before any work ("" without --plot)."""
    if args.plot is None:
        return ""
    from hairbed._optional import optional_import

    optional_import("matplotlib", "valve --plot")
    fmt = figure_format(args.plot, "--plot")
    check_output(args.plot)
    return fmt


def _plot(result: Any, path: str, fmt: str) -> None:
    """Draw ``result`` (a ValveCurve, Diodicity or ValveStates) into ``path``."""
    import sys

    from hairbed.plotting import fig_valve_result

    save_figure(fig_valve_result(result), path, fmt)
    print(f"wrote {path} ({fmt.upper()})", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    """The valve's curve (or its diodicity, or every state), as a table, JSON or a file."""
    import numpy as np

    fmt = _check_plot(args)
    bed = need_bed(args, "valve")
    if args.channel_length is None or not args.channel_length > 0:
        raise UsageError(f"--channel-length must be > 0 [m], got {args.channel_length!r}")
    if (args.pressure_drop is None) == (args.flow_rate is None):
        raise UsageError("give one of --pressure-drop and --flow-rate (what the pump sets)")
    if args.states or args.flow_rate is not None:
        return _run_states(args, bed, fmt)
    refuse(args, _STATES_ONLY, "applies to --states only")
    drops = np.atleast_1d(np.asarray(spec(args.pressure_drop, "--pressure-drop"), dtype=float))
    valve = hairbed.valve
    if args.diodicity:
        d = valve.diodicity(bed, drops, args.channel_length, root=args.root)
        di = np.atleast_1d(np.asarray(d.diodicity, dtype=float))
        forward, backward = _rows(d.forward), _rows(d.backward)
        if args.json:
            print_json(
                {
                    "channel_length": args.channel_length,
                    "diodicity": [
                        {"pressure_drop": f["pressure_drop"], "diodicity": float(x),
                         "forward": f, "backward": b}
                        for x, f, b in zip(di, forward, backward)
                    ],
                }
            )  # fmt: skip
            if args.plot:
                _plot(d, args.plot, fmt)
            return 0
        print(f"diodicity over l = {args.channel_length:g} m:")
        print(f"  {'|dp| [Pa]':>12}  {'Di':>10}  {'Q+ [m^2/s]':>12}  {'Q- [m^2/s]':>12}  status")
        for x, f, b in zip(di, forward, backward):
            status = max(abs(f["status"]), abs(b["status"]))
            print(
                f"  {f['pressure_drop']:12.6g}  {x:10.6g}  {f['flow_rate']:12.6g}  "
                f"{b['flow_rate']:12.6g}  {status}"
            )
        if args.plot:
            _plot(d, args.plot, fmt)
        return 0
    curve = valve.valve_curve(bed, drops, args.channel_length, root=args.root)
    rows = _rows(curve)
    if args.json:
        print_json({"channel_length": args.channel_length, "curve": rows})
    else:
        print(f"valve curve over l = {args.channel_length:g} m:")
        head = ("dp [Pa]", "Q' [m^2/s]", "R/R0", "dx1 [m]", "h1 [m]")
        print("  " + "  ".join(f"{h:>12}" for h in head) + "  status")
        for r in rows:
            cells = (r[k] for k in list(r)[:5])
            print("  " + "  ".join(f"{c:12.6g}" for c in cells) + f"  {r['status']}")
    if args.plot:
        _plot(curve, args.plot, fmt)
    return 0
