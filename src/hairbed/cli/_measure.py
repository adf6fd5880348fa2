"""``hairbed measure``: the wall shear stress and speed (+- sigma) of a tip deflection."""

from __future__ import annotations

import argparse
import json
import math
from dataclasses import replace
from typing import Any

import numpy as np

import hairbed

from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import print_json
from ._report import UsageError

#: ``hairbed measure --help``: the summary line, the description and the examples.
ABOUT = """wall shear stress and speed (+- sigma) from a tip deflection

Read the wall shear stress and the wall speed of a flow from the measured tip deflection of
a bed (hairbed.calibration.measure), with standard errors from the deflection's --sigma and,
with --calibration, the covariance of a calibration.

examples:
  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
  hairbed calibrate --data points.csv ... --json > cal.json
  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --calibration cal.json ...
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``measure`` subcommand's parser."""
    p = add_command(sub, "measure", run, ABOUT)
    p.add_argument(
        "--calibration",
        metavar="FILE.json",
        help="the output of 'hairbed calibrate --json': its fitted values replace the bed's, "
        "its covariance enters the errors",
    )
    p.add_argument(
        "--tip-deflection", type=float, required=True, metavar="X", help="tip deflection [m]"
    )
    p.add_argument(
        "--sigma", type=float, default=0.0, metavar="S", help="its standard deviation [m]"
    )
    add_json(p)
    add_bed_options(p, velocity=False)


def _load_calibration(path: str, bed: Any) -> Any:
    """The CalibrationFit of a ``hairbed calibrate --json`` output, applied to ``bed``."""
    calibration = hairbed.calibration
    try:
        with open(path) as fh:
            data = json.load(fh)
        params = data["parameters"]
        names = tuple(params)
        values = {p: float(params[p]["value"]) for p in names}
        stderr = {p: float(params[p]["stderr"]) for p in names}
        cov = np.array(data["covariance"], dtype=np.float64)
        geometry = data.get("geometry", "spacing")
    except OSError as exc:
        raise UsageError(f"--calibration: cannot read {path}: {exc.strerror or exc}") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise UsageError(
            f"--calibration {path}: not the JSON of 'hairbed calibrate --json' ({exc})"
        ) from None
    if cov.shape != (len(names), len(names)):
        raise UsageError(f"--calibration {path}: covariance is not {len(names)} x {len(names)}")
    for p in names:
        if p not in calibration.FREE_PARAMETERS:
            raise UsageError(f"--calibration {path}: unknown parameter {p!r}")
    other = "packing_fraction" if geometry == "spacing" else "spacing"
    fitted = replace(bed, **{other: None}, **values)
    return calibration.CalibrationFit(
        bed=fitted,
        parameters=names,
        values=values,
        stderr=stderr,
        covariance=cov,
        residuals=np.asarray(data.get("residuals", []), dtype=np.float64),
        chi2=float(data.get("chi2", math.nan)),
        dof=int(data.get("dof", 0)),
        kind=str(data.get("kind", "velocity")),
        success=bool(data.get("success", True)),
        status=int(data.get("status", 0)),
        message=str(data.get("message", "")),
        nfev=0,
        geometry=geometry,
    )


def run(args: argparse.Namespace) -> int:
    """Invert the deflection on the (calibrated) bed; print tau and v with their errors."""
    bed = need_bed(args, "measure")
    fit = None if args.calibration is None else _load_calibration(args.calibration, bed)
    if fit is not None:
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
                "omega2": m.state.omega2,
                "reynolds_number": m.state.reynolds_number,
                "success": m.success,
                "message": m.message,
            }
        )
        return 0
    print(f"tau = {m.wall_shear_stress:.6g} +- {m.wall_shear_stress_stderr:.2g} Pa")
    print(f"v   = {m.velocity:.6g} +- {m.velocity_stderr:.2g} m/s")
    return 0
