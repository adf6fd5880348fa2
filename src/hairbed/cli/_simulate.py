"""``hairbed simulate``: a pillar sensor's motion under a wall-shear-stress drive, in SI.

The nonlinear pillar in time (hairbed.Pillar.simulate, theory.md §14): a step from rest or a
sine about a mean; the time series of the drive, the tip deflection and height, the tip angle
and the base moment as CSV on stdout (the header ``name [units]``), one JSON document
(--json) or a file by its extension (--out: .nc netCDF with CF attributes, .csv, .parquet,
.zarr).
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import Any

import numpy as np

from hairbed.sensor_dynamics import time_scale_and_inertia

from ._options import add_bed_options, add_command, add_json, add_sensor_pillar_options
from ._options import sensor_pillar_from as _pillar_from
from ._output import check_dataset_output, print_json, write_dataset_output
from ._report import UsageError

#: ``hairbed simulate --help``: the summary line, the description and the examples.
ABOUT = """a pillar sensor's motion under a step or a sine of the wall shear stress, in SI

The nonlinear pillar in time (hairbed.Pillar.simulate, theory.md §14): an inextensible rod
under the quasi-steady resistive-force drag of its profile, with its own mass and the fluid's
added mass (--pillar-density; or --overdamped, no inertia). The drive is a step from rest to
--wall-shear-stress at t = 0, or with --frequency a sine about it, tau_w(t) = tau +
A sin(2 pi f t), from rest in the static state at tau. The pillar is given as for
'hairbed measure --pillar' (--length, --radius, --youngs-modulus and --fluid or --viscosity
with --density); --pillar may be left out. Prints time [s], wall_shear_stress [Pa],
tip_deflection [m], tip_height [m], tip_angle [rad] and base_moment [N m] at --samples
uniform times from 0 to --t-end. A run that stops early (the pillar reaching the wall, the
step limit) says so in one line on stderr; its rows past the stop are NaN.

examples:
  hairbed simulate --wall-shear-stress 1 --pillar-density 970 --length 1e-3 \\
      --radius 50e-6 --youngs-modulus 1e6 --fluid water --t-end 0.3 > step.csv
  hairbed simulate --wall-shear-stress 1 --amplitude 0.2 --frequency 100 --t-end 0.05 \\
      --pillar-density 970 --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 --fluid air \\
      --out sine.nc
  hairbed simulate --wall-shear-stress 1 --overdamped --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --viscosity 1 --json
"""

__all__ = ["ABOUT", "add_parser", "run"]

#: The columns written, with their units (the order of the CSV).
COLUMNS = {
    "wall_shear_stress": "Pa",
    "tip_deflection": "m",
    "tip_height": "m",
    "tip_angle": "rad",
    "base_moment": "N m",
}
#: The most output times (each holds the shape at every node).
MAX_SAMPLES = 1_000_000
#: The default --t-end in decay times of the slowest mode (e^-20 = 2e-9 of the start left).
DECAY_TIMES = 20.0
#: beta_1^4 of the cantilever: the slowest overdamped rate is beta_1^4/T.
_BETA1_4 = 1.875104068711961**4


def add_parser(sub: Any) -> None:
    """The ``simulate`` subcommand's parser."""
    p = add_command(sub, "simulate", run, ABOUT)
    g = p.add_argument_group("the drive and the run")
    g.add_argument(
        "--wall-shear-stress",
        type=float,
        required=True,
        metavar="TAU",
        help="the stress of the step from rest, or the sine's mean [Pa]",
    )
    g.add_argument(
        "--frequency", type=float, metavar="F", help="a sine of this frequency [Hz] > 0"
    )
    g.add_argument(
        "--amplitude", type=float, metavar="A", help="the sine's amplitude [Pa] (with --frequency)"
    )
    g.add_argument(
        "--t-end",
        type=float,
        metavar="S",
        help="the last time [s] > 0 (default: 20 decay times of the slowest mode, 2 mu T "
        "with inertia, T/12.36 overdamped)",
    )
    g.add_argument(
        "--samples",
        type=int,
        default=501,
        metavar="N",
        help="output times from 0 to --t-end, in [2, 1e6] (default 501)",
    )
    g.add_argument(
        "--pillar-density",
        type=float,
        metavar="RHO",
        help="the pillar's density [kg/m^3] (its inertia; PDMS about 970)",
    )
    g.add_argument(
        "--overdamped", action="store_true", help="neglect all inertia (no --pillar-density)"
    )
    g.add_argument(
        "--num",
        type=int,
        default=12,
        metavar="N",
        help="Chebyshev degree, in [4, 128] (default 12)",
    )
    g.add_argument(
        "--rtol",
        type=float,
        default=1e-6,
        metavar="R",
        help="the integrator's rtol (default 1e-6)",
    )
    g.add_argument(
        "--out",
        metavar="FILE",
        help="write to FILE by its extension (.nc, .csv, .parquet, .zarr) instead of CSV on "
        "stdout",
    )
    add_json(p, "print one JSON document (with the units) instead of CSV")
    add_bed_options(p, velocity=False)
    add_sensor_pillar_options(p)
    for action in p._actions:  # a bed's, refused for a pillar: not in the help
        if action.dest in ("spacing", "packing_fraction"):
            action.help = argparse.SUPPRESS


def _drive(args: argparse.Namespace) -> Any:
    """The drive of the options: a number (a step from rest) or an SI sine."""
    from hairbed.dynamics import sine

    if args.frequency is None:
        if args.amplitude is not None:
            raise UsageError("--amplitude needs --frequency (a sine)")
        return args.wall_shear_stress
    if not (math.isfinite(args.frequency) and args.frequency > 0.0):
        raise UsageError(f"--frequency must be a finite number > 0 [Hz], got {args.frequency!r}")
    if args.amplitude is None:
        raise UsageError("--frequency needs --amplitude [Pa] (the sine's)")
    return sine(args.wall_shear_stress, args.amplitude, 2.0 * math.pi * args.frequency)


def simulate_from(args: argparse.Namespace) -> Any:
    """The SensorTrajectory of the options (checked)."""
    if args.overdamped and args.pillar_density is not None:
        raise UsageError("give --pillar-density or --overdamped, not both")
    if not args.overdamped and args.pillar_density is None:
        raise UsageError(
            "simulate needs --pillar-density [kg/m^3] (the pillar's inertia), or --overdamped"
        )
    if not 2 <= args.samples <= MAX_SAMPLES:
        raise UsageError(f"--samples must be in [2, {MAX_SAMPLES}], got {args.samples}")
    drive = _drive(args)
    pillar = _pillar_from(args, "simulate")
    t_end = args.t_end
    if t_end is None:
        t_scale, mu, _ = time_scale_and_inertia(
            pillar, args.pillar_density, overdamped=args.overdamped
        )
        slow = 2.0 * mu if 4.0 * mu * _BETA1_4 > 1.0 else 1.0 / _BETA1_4
        t_end = DECAY_TIMES * slow * t_scale
    elif not (math.isfinite(t_end) and t_end > 0.0):
        raise UsageError(f"--t-end must be a finite number > 0 [s], got {t_end!r}")
    t = np.linspace(0.0, t_end, args.samples)
    return pillar.simulate(
        drive,
        t,
        pillar_density=args.pillar_density,
        overdamped=args.overdamped,
        num=args.num,
        rtol=args.rtol,
        atol=0.1 * args.rtol,
    )


def run(args: argparse.Namespace) -> int:
    """The pillar's motion as CSV, JSON or a file."""
    if args.json and args.out is not None:
        raise UsageError("give --json or --out, not both")
    if not args.json:
        check_dataset_output(args.out)
    run_ = simulate_from(args)
    if not run_.success:
        print(
            f"hairbed: warning: the run stopped at t = {run_.t_end:.6g} s: {run_.message} "
            "(the rows after it are NaN)",
            file=sys.stderr,
        )
    if args.json:
        print_json(
            {
                "units": {"time": "s", **COLUMNS},
                "time": run_.time.tolist(),
                **{k: getattr(run_, k).tolist() for k in COLUMNS},
                "time_scale": run_.time_scale,
                "inertia_number": run_.inertia_number,
                "status": run_.status,
                "success": run_.success,
                "message": run_.message,
                "t_end": run_.t_end,
            }
        )
        return 0
    ds = run_.to_xarray()[list(COLUMNS)]
    write_dataset_output(ds, args.out)
    return 0
