"""``hairbed calibrate``: fit a sensor's unknown parameters to measured tip deflections."""

from __future__ import annotations

import argparse
import sys
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
from ._output import print_json, read_input
from ._report import PROG, UsageError

#: ``hairbed calibrate --help``: the summary line, the description and the examples.
ABOUT = """fit a sensor's unknown parameters to measured tip deflections

Fit the free parameters of a bed (by default Young's modulus) to tip deflections measured at
known wall speeds or wall shear stresses, by weighted least squares on the exact calibration
curve with its exact Jacobian (hairbed.calibration.fit). --data is a CSV file with a header
line: tip_deflection [m] and one of velocity [m/s], wall_shear_stress [Pa], or, for a
pump-driven bed with both walls at rest, pressure_gradient [Pa/m] or flow_rate [m^2/s];
optionally sigma [m] (the standard deviation of each deflection); a heading may carry its unit,
'tip_deflection [m]', as hairbed's own CSV files do. The bed options give the starting
values and the fixed parameters. --json prints the calibration file that 'hairbed measure
--calibration' reads: the whole bed, the fitted parameters with their covariance, the
SHA-256 of the points and the hairbed version. A fit with no degrees of freedom warns
(status 5); exit status 1 when the fit does not succeed.

With --pillar the sensor is an isolated pillar in a wall shear layer (hairbed.Pillar,
theory.md §12): --length, --radius, --youngs-modulus and --viscosity, optionally
--base-angle, --profile (a couette or poiseuille channel needs --channel-height), --density
and --drag-scale; the points are wall shear stresses, or the wall speeds of a couette
channel; --free from youngs_modulus or drag_scale, base_angle, length, radius.

examples:
  hairbed calibrate --data points.csv --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
  hairbed calibrate --data points.csv --free youngs_modulus,base_angle --sigma 1e-6 ... --json
  hairbed calibrate --pillar --data stress.csv --free youngs_modulus,base_angle \\
      --length 500e-6 --radius 25e-6 --youngs-modulus 1e6 --viscosity 1e-3
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``calibrate`` subcommand's parser."""
    p = add_command(sub, "calibrate", run, ABOUT)
    p.add_argument("--data", required=True, metavar="FILE.csv", help="calibration points (CSV)")
    p.add_argument(
        "--free",
        default="youngs_modulus",
        metavar="P1,P2",
        help="parameters to fit, comma-separated: length, radius, youngs_modulus, "
        "channel_height, viscosity, spacing, packing_fraction, base_angle; with --pillar "
        "youngs_modulus, drag_scale, base_angle, length, radius (default youngs_modulus)",
    )
    p.add_argument(
        "--sigma", type=float, metavar="S", help="standard deviation of every deflection [m]"
    )
    add_json(p)
    add_bed_options(p, velocity=False, model=True)
    add_sensor_pillar_options(p)


def _points(path: str) -> Any:
    """The calibration points of --data (hairbed.calibration.read_points)."""
    return read_input(hairbed.calibration.read_points, path, "--data")


def _print_fit(result: Any, as_json: bool) -> None:
    if isinstance(result.bed, hairbed.Pillar):
        units = hairbed.calibration.PILLAR_FREE_PARAMETERS
    else:
        units = hairbed.calibration.FREE_PARAMETERS
    if as_json:  # the calibration file: the whole bed, the data's SHA-256, the version
        print_json(hairbed.calibration_files.calibration_to_dict(result))
        return
    print(f"calibration of {result.residuals.size} points ({result.kind} known):")
    width = max(len(p) for p in result.parameters)
    for p in result.parameters:
        print(f"  {p:<{width}}  {result.values[p]:.10g} +- {result.stderr[p]:.3g} [{units[p]}]")
    if result.weighted:
        print(f"  chi2 = {result.chi2:.6g} for {result.dof} degrees of freedom")
    else:  # no sigma: not a chi2 but a sum of squares, in m^2
        print(
            f"  sum of squared residuals = {result.chi2:.6g} [m^2] for {result.dof} degrees "
            "of freedom (no sigma)"
        )
    if result.status == 0:
        word = "converged"
    elif result.status > 0:
        word = f"converged with a caveat (status {result.status})"
    else:
        word = f"NOT converged (status {result.status})"
    print(f"  {word}: {result.message}")


def _free(text: str) -> tuple[str, ...]:
    """The names of --free, each item checked: an empty one (``a,,b``, a trailing comma) is
    a usage error naming its position, not skipped."""
    items = [item.strip() for item in text.split(",")]
    for k, item in enumerate(items, start=1):
        if not item:
            raise UsageError(
                f"--free: item {k} of {text!r} is empty; give parameter names separated by "
                "single commas, e.g. youngs_modulus,base_angle"
            )
    return tuple(items)


def run(args: argparse.Namespace) -> int:
    """Read the points, fit, print; exit status 1 when the fit does not succeed."""
    free = _free(args.free)
    if args.pillar:
        bed = sensor_pillar_from(args, "calibrate")
    else:
        refuse_without_sensor_pillar(args)
        bed = need_bed(args, "calibrate")
    points = _points(args.data)
    sigma: Any = points.sigma
    if args.sigma is not None:
        if sigma is not None:
            raise UsageError("give --sigma or a sigma column in --data, not both")
        sigma = args.sigma
    result = hairbed.calibration.fit(
        bed,
        points.tip_deflection,
        sigma=sigma,
        free=free,
        **points.known(),
    )
    _print_fit(result, args.json)
    if not result.success:
        print(f"{PROG}: warning: the fit did not succeed: {result.message}", file=sys.stderr)
        return 1
    return 0
