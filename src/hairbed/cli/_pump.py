"""``hairbed pump``: a valve switched by a step in its pressure drop, or pumped by a sine."""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ._grids import spec
from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import NO_COMPRESS_HELP, check_dataset_output, print_json, write_dataset_output
from ._report import UsageError, say_status

#: ``hairbed pump --help``: the summary line, the description and the examples.
ABOUT = """a valve in time: the flow after a step in the pressure drop, a pulsing pump's net flow

The bed's hairs in time (hairbed.dynamics.simulate_bed, theory.md §15: the porous model of the
bed's geometry, both walls at rest), under a pressure drop over a channel of length
--channel-length [m]. Two workflows (hairbed.valve_dynamics):

--switch DP: the drop steps from --initial-pressure-drop (default 0) to DP [Pa] at t = 0; prints
time [s], the flow per unit width Q' [m^2/s] and the tip height [m], and above them, in '#'
lines, the steady flows before and after, the time to 90 % of the change (rise_time) and the
time from which Q' stays within 10 % of it (settling_time) [s].

--amplitudes SPEC --frequencies SPEC: a zero-mean drop A sin(2 pi f t); prints for each
amplitude [Pa] and frequency [Hz] the net flow [m^2/s] of the periodic state (the flow averaged
over a period: the rectification of a leaning bed), its quasi-static limit (the phase average
of the steady valve curve), the periods integrated and the status; the peak frequency of each
amplitude in '#' lines. SPEC is a value, a list A,B,... or START:STOP:NUM[:log].

The hairs are overdamped unless --hair-density [kg/m^3] is given; the fluid is quasi-steady
unless --density [kg/m^3] is given (then its inertia enters). --json prints one JSON document;
--out FILE writes a dataset with units (.nc, .zarr, .csv, .parquet).

examples:
  hairbed pump --switch 300 --channel-length 0.01 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 250e-6 \\
      --base-angle 0.5
  hairbed pump --amplitudes 300 --frequencies 1e-3:1:7:log --channel-length 0.01 ... --json
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``pump`` subcommand's parser."""
    p = add_command(sub, "pump", run, ABOUT)
    g = p.add_argument_group("the drive")
    g.add_argument("--switch", type=float, metavar="DP", help="the drop after the step [Pa]")
    g.add_argument(
        "--initial-pressure-drop",
        type=float,
        default=0.0,
        metavar="DP0",
        help="the drop before the step [Pa] (default 0)",
    )
    g.add_argument(
        "--duration",
        type=float,
        metavar="S",
        help="how long to follow the switch [s] (without it: ten times the time scale "
        "T = zeta L^4/(E I))",
    )
    g.add_argument(
        "--num-times",
        type=int,
        default=201,
        metavar="N",
        help="samples of the switch's response, in [3, 10^6] (default 201)",
    )
    g.add_argument("--amplitudes", metavar="SPEC", help="the sine's amplitudes [Pa] > 0")
    g.add_argument("--frequencies", metavar="SPEC", help="the sine's frequencies [Hz] > 0")
    g.add_argument(
        "--samples-per-period",
        type=int,
        default=64,
        metavar="N",
        help="samples per period of the net flow's average, in [8, 4096] (default 64)",
    )
    g.add_argument(
        "--channel-length",
        type=float,
        required=True,
        metavar="L",
        help="length l of the channel [m], > 0",
    )
    g.add_argument(
        "--hair-density",
        type=float,
        metavar="RHO",
        help="the hairs' density [kg/m^3] (their inertia; overdamped without it)",
    )
    g.add_argument(
        "--out",
        metavar="FILE",
        help="a dataset with units: .nc, .zarr, .csv or .parquet (a table on stdout without it)",
    )
    g.add_argument("--no-compress", action="store_true", help=NO_COMPRESS_HELP)
    add_json(p)
    add_bed_options(p, velocity=False, model=True)


def _summary_lines(pairs: dict[str, tuple[Any, str]]) -> None:
    for key, (value, unit) in pairs.items():
        shown = repr(float(value)) if isinstance(value, float) else str(value)
        print(f"# {key} = {shown} [{unit}]" if unit else f"# {key} = {shown}")


def _run_switch(args: argparse.Namespace, bed: Any, to_stdout: bool) -> int:
    from ..valve_dynamics import valve_switching

    r = valve_switching(
        bed,
        args.switch,
        args.channel_length,
        initial_pressure_drop=args.initial_pressure_drop,
        duration=args.duration,
        num_times=args.num_times,
        hair_density=args.hair_density,
    )
    summary = {
        "pressure_drop": (r.pressure_drop, "Pa"),
        "initial_pressure_drop": (r.initial_pressure_drop, "Pa"),
        "initial_flow_rate": (r.initial_flow_rate, "m^2/s"),
        "final_flow_rate": (r.final_flow_rate, "m^2/s"),
        "rise_time": (r.rise_time, "s"),
        "settling_time": (r.settling_time, "s"),
        "time_scale": (r.time_scale, "s"),
        "status": (r.status, ""),
        "message": (r.message, ""),
    }
    if args.json:
        print_json(
            {
                **{k: v for k, (v, _) in summary.items()},
                "units": {k: u for k, (_, u) in summary.items() if u}
                | {"time": "s", "flow_rate": "m^2/s", "tip_height": "m"},
                "time": r.time.tolist(),
                "flow_rate": r.flow_rate.tolist(),
                "tip_height": r.tip_height.tolist(),
            }
        )
    elif not to_stdout:
        write_dataset_output(r.to_xarray(), args.out, args.no_compress)
    else:
        _summary_lines(summary)
        print("time,flow_rate,tip_height")
        for t, q, h in zip(r.time, r.flow_rate, r.tip_height):
            print(f"{float(t)!r},{float(q)!r},{float(h)!r}")
    return say_status(int(r.status), r.message)  # a NaN rise or settling time says why


def _run_pump(args: argparse.Namespace, bed: Any, to_stdout: bool) -> int:
    from ..valve_dynamics import pump_net_flow

    amps = spec(args.amplitudes, "--amplitudes")
    freqs = spec(args.frequencies, "--frequencies")
    r = pump_net_flow(
        bed,
        amps,
        freqs,
        args.channel_length,
        samples_per_period=args.samples_per_period,
        hair_density=args.hair_density,
    )
    if args.json:
        print_json(
            {
                "units": {"amplitude": "Pa", "frequency": "Hz", "net_flow": "m^2/s",
                          "quasi_static_net_flow": "m^2/s", "peak_frequency": "Hz",
                          "time_scale": "s"},
                "amplitude": r.amplitude.tolist(),
                "frequency": r.frequency.tolist(),
                "net_flow": r.net_flow.tolist(),
                "quasi_static_net_flow": r.quasi_static_net_flow.tolist(),
                "peak_frequency": r.peak_frequency.tolist(),
                "peak_at_end": r.peak_at_end.tolist(),
                "periods": r.periods.tolist(),
                "status": r.status.tolist(),
                "time_scale": r.time_scale,
                "message": r.message,
            }
        )  # fmt: skip
    elif not to_stdout:
        write_dataset_output(r.to_xarray(), args.out, args.no_compress)
    else:
        _summary_lines({"time_scale": (r.time_scale, "s"), "message": (r.message, "")})
        for a, f, end in zip(r.amplitude, r.peak_frequency, r.peak_at_end):
            where = " (at the grid's end)" if end else ""
            print(f"# peak_frequency at amplitude {float(a)!r} Pa = {float(f)!r} [Hz]{where}")
        print("amplitude,frequency,net_flow,quasi_static_net_flow,periods,status")
        for i, a in enumerate(r.amplitude):
            for j, f in enumerate(r.frequency):
                print(
                    f"{float(a)!r},{float(f)!r},{float(r.net_flow[i, j])!r},"
                    f"{float(r.quasi_static_net_flow[i])!r},"
                    f"{int(r.periods[i, j])},{int(r.status[i, j])}"
                )
    s = np.asarray(r.status).reshape(-1)
    return say_status(int(s.min()) if s.min() < 0 else int(s.max()), r.message)


def run(args: argparse.Namespace) -> int:
    """``hairbed pump``."""
    pulsed = args.amplitudes is not None or args.frequencies is not None
    if (args.switch is None) == (not pulsed):
        raise UsageError("pump needs either --switch DP or --amplitudes with --frequencies")
    if pulsed and (args.amplitudes is None or args.frequencies is None):
        raise UsageError("a pulsing pump needs both --amplitudes and --frequencies")
    if args.switch is not None and not math.isfinite(args.switch):
        raise UsageError(f"--switch must be a finite pressure drop [Pa], got {args.switch!r}")
    bed = need_bed(args, "pump")
    to_stdout = args.out is None or check_dataset_output(args.out, args.no_compress)
    if args.json and not to_stdout:
        raise UsageError("--json and --out cannot be combined")
    if pulsed:
        return _run_pump(args, bed, to_stdout)
    return _run_switch(args, bed, to_stdout)
