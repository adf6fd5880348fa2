"""``hairbed measure``: the wall shear stress and speed (+- sigma) of a tip deflection."""

from __future__ import annotations

import argparse
import math
from typing import Any

import hairbed

from ._measure_series import add_series_options, refuse_series_options, run_series
from ._options import (
    BED_OPTIONS,
    add_bed_options,
    add_command,
    add_json,
    add_sensor_pillar_options,
    need_bed,
    refuse_without_sensor_pillar,
    sensor_pillar_from,
)
from ._output import print_json, read_input
from ._report import UsageError

#: ``hairbed measure --help``: the summary line, the description and the examples.
ABOUT = """wall shear stress and speed (+- sigma) from a tip deflection

Read the wall shear stress and the wall speed of a flow from the measured tip deflection of
a bed (hairbed.calibration.measure), with standard errors from the deflection's --sigma and,
with --calibration, the covariance of a calibration. With --calibration the bed is the
calibrated one, stored in the file: bed options may be left out, and one that disagrees with
it is refused (the calibrate options, starting values included, are accepted). Without
--calibration this is 'hairbed invert' with a bed: the same numbers, printed as tau and v
with their standard errors (invert also gives omega2, the force per hair and the tip height).

With --pillar the sensor is an isolated pillar (hairbed.Pillar, theory.md §12; its options
as for 'hairbed calibrate --pillar'); a --calibration written by 'hairbed calibrate --pillar
--json' says itself that it is a pillar's (--pillar may be left out): the exact inverse of
its calibration curve. v is the wall speed of a couette channel; the other profiles have
none, and the table says so (JSON: null).

examples:
  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
  hairbed calibrate --data points.csv ... --json > cal.json
  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --calibration cal.json
  hairbed measure --pillar --tip-deflection 2e-4 --sigma 1e-6 --length 500e-6 \\
      --radius 25e-6 --youngs-modulus 1e6 --viscosity 1e-3
  hairbed measure --pillar --series series.csv --sample-rate 2000 --pillar-density 1000 \\
      --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 --fluid water > stress.csv
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``measure`` subcommand's parser."""
    p = add_command(sub, "measure", run, ABOUT)
    p.add_argument(
        "--calibration",
        metavar="FILE.json",
        help="the output of 'hairbed calibrate --json': its bed is the one measured with, "
        "its covariance enters the errors",
    )
    p.add_argument("--tip-deflection", type=float, metavar="X", help="tip deflection [m]")
    p.add_argument(
        "--sigma", type=float, default=0.0, metavar="S", help="its standard deviation [m]"
    )
    add_json(p)
    add_bed_options(p, velocity=False, model=True)
    add_sensor_pillar_options(p)
    add_series_options(p)


def _load_calibration(path: str) -> Any:
    """The CalibrationFit of a calibration file (``hairbed calibrate --json``)."""
    return read_input(hairbed.calibration_files.read_calibration, path, "--calibration")


def _check_bed_options(args: argparse.Namespace, fit: Any, path: str) -> None:
    """Refuse a bed option that is neither the calibrated bed's value nor, for a fitted
    parameter, the starting value of the calibration (the options given to calibrate)."""
    pillar = isinstance(fit.bed, hairbed.Pillar)
    if args.pillar and not pillar:  # the file says which sensor it is: --pillar is optional
        raise UsageError(f"--calibration {path} is a bed's: drop --pillar")
    if not pillar:
        refuse_without_sensor_pillar(args)
    else:
        for opt, name in (("--profile", "profile"), ("--drag-scale", "drag_scale")):
            given = getattr(args, name)
            if given is not None and given != getattr(fit.bed, name):
                raise UsageError(
                    f"{opt} {given} disagrees with the pillar of --calibration {path} ({name} = "
                    f"{getattr(fit.bed, name)!r}): drop {opt} or calibrate again"
                )
    # --model and --drag have defaults: a value other than the default must be the file's
    for opt, name, default in (("--model", "model", "dense"), ("--drag", "drag", "crossover")):
        given = getattr(args, name, default)
        if given != default and pillar:
            raise UsageError(f"{opt} does not apply to a pillar (--calibration {path})")
        if given != default and given != getattr(fit.bed, name):
            raise UsageError(
                f"{opt} {given} disagrees with the bed of --calibration {path} ({name} = "
                f"{getattr(fit.bed, name)!r}): drop {opt} or calibrate again"
            )
    for opt, (name, _) in BED_OPTIONS.items():
        given = getattr(args, name)
        if given is None:
            continue
        if not hasattr(fit.bed, name):
            raise UsageError(f"{opt} does not apply to a pillar (--calibration {path})")
        held = getattr(fit.bed, name)
        allowed = [held] + ([fit.start[name]] if name in fit.start else [])
        if not any(v is not None and math.isclose(given, v, rel_tol=1e-9) for v in allowed):
            raise UsageError(
                f"{opt} {given:g} disagrees with the bed of --calibration {path} "
                f"({name} = {held!r}): measure uses the calibrated bed; drop {opt} or "
                "calibrate again"
            )


def run(args: argparse.Namespace) -> int:
    """Invert the deflection on the (calibrated) bed; print tau and v with their errors."""
    if args.series is not None:
        return run_series(args)
    if args.tip_deflection is None:
        raise UsageError("measure needs --tip-deflection [m] (or --pillar --series FILE.csv)")
    refuse_series_options(args)
    if args.calibration is None:
        fit = None
        if args.pillar:
            bed = sensor_pillar_from(args, "measure")
        else:
            refuse_without_sensor_pillar(args)
            bed = need_bed(args, "measure (or --calibration)")
    else:
        fit = _load_calibration(args.calibration)
        _check_bed_options(args, fit, args.calibration)
        bed = fit.bed
    m = hairbed.calibration.measure(bed, args.tip_deflection, sigma=args.sigma, fit=fit)
    if args.json:
        print_json(
            {
                "tip_deflection": m.tip_deflection,
                "sigma": args.sigma,
                "wall_shear_stress": m.wall_shear_stress,
                "wall_shear_stress_stderr": m.wall_shear_stress_stderr,
                "velocity": m.velocity,
                "velocity_stderr": m.velocity_stderr,
                **(
                    {"forcing": m.state.forcing}
                    if isinstance(bed, hairbed.Pillar)
                    else {"omega2": m.state.omega2}
                ),
                "reynolds_number": m.state.reynolds_number,
                "success": m.success,
                "message": m.message,
                **_pumped(m),
            }
        )
        return 0
    print(f"tau = {m.wall_shear_stress:.6g} +- {m.wall_shear_stress_stderr:.2g} Pa")
    if m.velocity == m.velocity:
        print(f"v   = {m.velocity:.6g} +- {m.velocity_stderr:.2g} m/s")
    else:  # a pillar whose profile has no wall speed (sublayer, poiseuille)
        print(f"(no wall speed v: a pillar in a {bed.profile} profile has none; couette has)")
    if m.pressure_gradient is not None:  # a pump-driven calibration (both walls at rest)
        print(f"G   = {m.pressure_gradient:.6g} +- {m.pressure_gradient_stderr:.2g} Pa/m")
        print(f"Q'  = {m.flow_rate:.6g} +- {m.flow_rate_stderr:.2g} m^2/s")
    return 0


def _pumped(m: Any) -> dict[str, Any]:
    """The pump drive's entries of --json (a calibration at known pressure gradients or flow
    rates): G and Q' with their standard errors; none otherwise."""
    if m.pressure_gradient is None:
        return {}
    return {
        "pressure_gradient": m.pressure_gradient,
        "pressure_gradient_stderr": m.pressure_gradient_stderr,
        "flow_rate": m.flow_rate,
        "flow_rate_stderr": m.flow_rate_stderr,
    }
