"""``hairbed valve``: a hair-bed valve's flow against pressure drop, and its diodicity."""

from __future__ import annotations

import argparse
from typing import Any

import hairbed

from ._grids import spec
from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import print_json
from ._report import UsageError

#: ``hairbed valve --help``: the summary line, the description and the examples.
ABOUT = """flow through a channel lined by a bed against the pressure drop; the diodicity

A pump holds a pressure drop dp [Pa] over a channel of length --channel-length [m], both walls
at rest: the pressure gradient dp/l loads the hairs along their height (the distributed-load
solver, hairbed.solve_loaded) and the flow per unit width through the gap above the tips,
Q' = G g^3/(12 eta), follows (hairbed.valve.valve_curve). Each line gives dp, Q' [m^2/s], the
resistance relative to the empty channel (H/g)^3, the tip deflection and height [m] and the
solver's status. With --diodicity the drops are taken in magnitude and each line gives
Di = Q'(+dp)/abs(Q'(-dp)) (hairbed.valve.diodicity): above 1 when the hairs lean towards +x
(--base-angle > 0), as forward flow bends them down and opens the gap.

examples:
  hairbed valve --pressure-drop 10:1000:5:log --channel-length 0.01 --length 1.8e-3 \\
      --radius 50e-6 --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 \\
      --spacing 400e-6 --base-angle 1.0
  hairbed valve --pressure-drop 200 --diodicity --channel-length 0.01 ... --json
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``valve`` subcommand's parser."""
    p = add_command(sub, "valve", run, ABOUT)
    p.add_argument(
        "--pressure-drop",
        metavar="SPEC",
        required=True,
        help="pressure drop dp = p(0) - p(l) [Pa]: a value, a comma list or START:STOP:NUM[:log]",
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
    add_json(p)
    add_bed_options(p, velocity=False)


def _rows(curve: Any) -> list[dict[str, Any]]:
    import numpy as np

    fields = ("pressure_drop", "flow_rate", "resistance_ratio", "tip_deflection", "tip_height")
    cols = {f: np.atleast_1d(np.asarray(getattr(curve, f), dtype=float)) for f in fields}
    status = np.atleast_1d(np.asarray(curve.status))
    return [
        {**{f: float(cols[f][i]) for f in fields}, "status": int(status[i])}
        for i in range(status.size)
    ]


def run(args: argparse.Namespace) -> int:
    """The valve's curve (or its diodicity), as a table or JSON."""
    import numpy as np

    bed = need_bed(args, "valve")
    drops = np.atleast_1d(np.asarray(spec(args.pressure_drop, "--pressure-drop"), dtype=float))
    if args.channel_length is None or not args.channel_length > 0:
        raise UsageError(f"--channel-length must be > 0 [m], got {args.channel_length!r}")
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
            return 0
        print(f"diodicity over l = {args.channel_length:g} m:")
        print(f"  {'|dp| [Pa]':>12}  {'Di':>10}  {'Q+ [m^2/s]':>12}  {'Q- [m^2/s]':>12}  status")
        for x, f, b in zip(di, forward, backward):
            status = max(abs(f["status"]), abs(b["status"]))
            print(
                f"  {f['pressure_drop']:12.6g}  {x:10.6g}  {f['flow_rate']:12.6g}  "
                f"{b['flow_rate']:12.6g}  {status}"
            )
        return 0
    curve = valve.valve_curve(bed, drops, args.channel_length, root=args.root)
    rows = _rows(curve)
    if args.json:
        print_json({"channel_length": args.channel_length, "curve": rows})
        return 0
    print(f"valve curve over l = {args.channel_length:g} m:")
    head = ("dp [Pa]", "Q' [m^2/s]", "R/R0", "x1 [m]", "h1 [m]")
    print("  " + "  ".join(f"{h:>12}" for h in head) + "  status")
    for r in rows:
        cells = (r[k] for k in list(r)[:5])
        print("  " + "  ".join(f"{c:12.6g}" for c in cells) + f"  {r['status']}")
    return 0
