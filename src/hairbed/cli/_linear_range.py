"""``hairbed linear-range``: up to where a bed's linear calibration holds, stress and speed."""

from __future__ import annotations

import argparse
from typing import Any

import hairbed

from ._options import (
    add_bed_options,
    add_command,
    add_json,
    add_sensor_pillar_options,
    need_bed,
    refuse_without_sensor_pillar,
    sensor_pillar_from,
)
from ._output import print_json

#: ``hairbed linear-range --help``: the summary line, the description and the examples.
ABOUT = """where the linear (point-load) calibration of a bed holds, in stress and speed

The largest tip deflection at which the linear calibration of a cantilever under a point load
at its tip is within --rtol of the exact calibration (hairbed.calibration.linear_range), for
the wall shear stress and for the wall speed apart: they end at different deflections, as the
linear speed also misses the narrowing of the gap. Each line gives the deflection [m], the
exact speed [m/s] and stress [Pa] there and the relative errors of both linear calibrations.

With --pillar the sensor is an isolated pillar (hairbed.Pillar, theory.md §12; its options as
for 'hairbed calibrate --pillar'): the linear calibration is the small-deflection formula
(hairbed.Pillar.linear_wall_shear_stress_from_tip_deflection), in stress; a pillar in a
couette channel also has a wall speed, which the other profiles have not.

examples:
  hairbed linear-range --rtol 0.05 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
  hairbed linear-range --rtol 0.01 ... --json
  hairbed linear-range --pillar --rtol 0.05 --length 500e-6 --radius 25e-6 \\
      --youngs-modulus 1e6 --viscosity 1e-3
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
    add_bed_options(p, velocity=False, model=True)
    add_sensor_pillar_options(p)


def run(args: argparse.Namespace) -> int:
    """Both linear ranges of the bed (or the pillar's, in stress), as a table or JSON."""
    if args.pillar:
        bed = sensor_pillar_from(args, "linear-range")
    else:
        refuse_without_sensor_pillar(args)
        bed = need_bed(args, "linear-range")
    both = hairbed.calibration.linear_range(bed, args.rtol)
    if both.limits:
        limits = {q: both.limits[q] for q in ("wall_shear_stress", "velocity")}
    else:  # a pillar without a wall speed: the range in stress alone
        limits = {both.quantity: both}
    if args.json:
        out = {q: {f: getattr(r, f) for f in _FIELDS} for q, r in limits.items()}
        print_json({"rtol": both.rtol, **out})
        return 0
    print(f"linear calibration within {both.rtol:g} (relative) of the exact one:")
    for q, r in limits.items():
        name = q.replace("_", " ")
        end = "up to" if r.status == 0 else "beyond"
        speed = f", v = {r.velocity:.6g} m/s" if r.velocity == r.velocity else ""
        errors = f"stress {r.wall_shear_stress_error:+.3g}"
        if r.velocity_error == r.velocity_error:
            errors += f", speed {r.velocity_error:+.3g}"
        print(
            f"  {name:<17}  {end} tip deflection {r.tip_deflection:.6g} m: "
            f"tau = {r.wall_shear_stress:.6g} Pa{speed} (errors: {errors})"
        )
    if not both.limits and both.velocity != both.velocity:
        print(f"  (no wall speed: a pillar in a {bed.profile} profile has none; couette has)")
    return 0
