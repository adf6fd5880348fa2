"""``hairbed invert``: the forcing (and, given a bed, the flow) of a measured tip deflection."""

from __future__ import annotations

import argparse
import math
from typing import Any

import hairbed

from ._options import add_bed_options, add_command, add_eps, add_json, add_theta0, bed_from
from ._output import print_json, solution_table, table
from ._report import UsageError

#: ``hairbed invert --help``: the summary line, the description and the examples.
ABOUT = """forcing from a measured tip deflection

Find the forcing omega^2 (and, given a bed, the wall speed and wall shear stress) of the
physical state with a given tip deflection. With a bed this is the reading of
'hairbed measure' without --calibration (the same library call, hairbed.calibration.measure,
the same numbers), shown as a table of the whole state (omega2, force per hair, tip height);
'hairbed measure' adds a calibration file, whose bed and covariance it uses.

examples:
  hairbed invert --tip-deflection 0.6158 --eps 0.5
  hairbed invert --tip-deflection 0.3 --eps 0.9 --theta0 0.2 --json
  hairbed invert --tip-deflection 0.6158 --eps 0.5 --sigma 1e-3
  hairbed invert --tip-deflection 3.7e-4 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``invert`` subcommand's parser."""
    p = add_command(sub, "invert", run, ABOUT)
    p.add_argument(
        "--tip-deflection",
        type=float,
        required=True,
        help="tip deflection x1 [L] (in metres when a bed is given)",
    )
    add_eps(p)
    add_theta0(p)
    p.add_argument(
        "--sigma",
        type=float,
        metavar="S",
        help="standard error of the tip deflection (same unit): adds the standard error of "
        "omega2 (and of the wall speed and stress, given a bed), to first order",
    )
    add_json(p)
    add_bed_options(p, velocity=False, model=True)


def _invert_bed(args: argparse.Namespace, bed: Any, sigma: float | None) -> None:
    if args.eps is not None or args.theta0 is not None:
        raise UsageError("give either --eps/--theta0 or the physical inputs, not both")
    # the reading of 'hairbed measure' without a calibration: one library call for both
    m = hairbed.calibration.measure(bed, args.tip_deflection, sigma=sigma or 0.0)
    st = m.state
    out = {
        "tip_deflection_m": args.tip_deflection,
        "velocity": st.velocity,
        "omega2": st.omega2,
        "wall_shear_stress_Pa": st.wall_shear_stress,
        "force_per_hair_N": st.force_per_hair,
        "tip_height_m": st.tip_height,
    }
    notes = {"velocity": "[m/s]", "omega2": "[-]"}
    if sigma is not None:  # first order through the exact slope of the calibration curve
        out["sigma_m"] = sigma
        out["velocity_stderr"] = m.velocity_stderr
        out["omega2_stderr"] = m.velocity_stderr / bed.velocity_scale
        out["wall_shear_stress_stderr_Pa"] = m.wall_shear_stress_stderr
        notes["velocity_stderr"] = "[m/s], from --sigma"
    if args.json:
        print_json(out)
    else:
        print(table(out, notes))


def _invert_dimensionless(args: argparse.Namespace, sigma: float | None) -> None:
    if args.eps is None:
        raise UsageError("give --eps (or the physical inputs of a bed)")
    theta0 = 0.0 if args.theta0 is None else args.theta0
    sol = hairbed.inverse.solution_from_tip_deflection(args.tip_deflection, args.eps, theta0)
    stderr = None
    if sigma is not None:
        # first order: sigma / |d x1/d omega2|, the exact derivative (hairbed.derivatives)
        slope = float(hairbed.sensitivity.derivatives_at(sol)["tip_deflection"]["omega2"])
        stderr = sigma / abs(slope) if slope != 0.0 else math.inf
    if args.json:
        out = sol.as_dict()
        if stderr is not None:
            out = {**out, "sigma": sigma, "omega2_stderr": stderr}
        print_json(out)
        return
    if stderr is None:
        print(f"omega2 = {float(sol.omega2):.15g}")
    else:
        print(f"omega2 = {float(sol.omega2):.15g} +- {stderr:.3g} (from --sigma {sigma:g})")
    print(solution_table(sol))


def run(args: argparse.Namespace) -> int:
    """Invert the tip deflection; print the state (and its standard errors with --sigma)."""
    sigma = args.sigma
    if sigma is not None and not (math.isfinite(sigma) and sigma >= 0.0):
        raise UsageError(f"--sigma must be finite and >= 0, got {sigma:g}")
    bed = bed_from(args)
    if bed is not None:
        _invert_bed(args, bed, sigma)
    else:
        _invert_dimensionless(args, sigma)
    return 0
