"""``hairbed linear-range``: up to where a bed's linear calibration holds, stress and speed."""

from __future__ import annotations

import argparse
from typing import Any

import hairbed

from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import print_json

#: ``hairbed linear-range --help``: the summary line, the description and the examples.
ABOUT = """where the linear (point-load) calibration of a bed holds, in stress and speed

The largest tip deflection at which the linear calibration of a cantilever under a point load
at its tip is within --rtol of the exact calibration (hairbed.calibration.linear_range), for
the wall shear stress and for the wall speed apart: they end at different deflections, as the
linear speed also misses the narrowing of the gap. Each line gives the deflection [m], the
exact speed [m/s] and stress [Pa] there and the relative errors of both linear calibrations.

examples:
  hairbed linear-range --rtol 0.05 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
  hairbed linear-range --rtol 0.01 ... --json
"""

__all__ = ["ABOUT", "add_parser", "run"]

_FIELDS = (
    "tip_deflection",
    "velocity",
    "wall_shear_stress",
    "velocity_error",
    "wall_shear_stress_error",
    "status",
    "message",
)


def add_parser(sub: Any) -> None:
    """The ``linear-range`` subcommand's parser."""
    p = add_command(sub, "linear-range", run, ABOUT)
    p.add_argument(
        "--rtol",
        type=float,
        default=0.1,
        metavar="R",
        help="relative tolerance of the linear calibration, in (0, 1) (default 0.1)",
    )
    add_json(p)
    add_bed_options(p, velocity=False)


def run(args: argparse.Namespace) -> int:
    """Both linear ranges of the bed, as a table or JSON."""
    bed = need_bed(args, "linear-range")
    both = hairbed.calibration.linear_range(bed, args.rtol)
    limits = {q: both.limits[q] for q in ("wall_shear_stress", "velocity")}
    if args.json:
        out = {q: {f: getattr(r, f) for f in _FIELDS} for q, r in limits.items()}
        print_json({"rtol": both.rtol, **out})
        return 0
    print(f"linear calibration within {both.rtol:g} (relative) of the exact one:")
    for q, r in limits.items():
        name = q.replace("_", " ")
        end = "up to" if r.status == 0 else "beyond"
        print(
            f"  {name:<17}  {end} tip deflection {r.tip_deflection:.6g} m: "
            f"tau = {r.wall_shear_stress:.6g} Pa, v = {r.velocity:.6g} m/s "
            f"(errors: stress {r.wall_shear_stress_error:+.3g}, speed {r.velocity_error:+.3g})"
        )
    return 0
