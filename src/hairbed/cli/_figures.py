"""``hairbed figures``: every figure (or some) as image files, whole or not at all."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

from hairbed._optional import optional_import

from ._options import add_command
from ._output import check_output
from ._report import UnwritableOutput, UsageError, WriteError

#: ``hairbed figures --help``: the summary line, the description and the examples.
ABOUT = """write every figure as PNG

Recompute the paper's figures and the new ones and write PNG files (whole or not at all).
--set KEY=VALUE passes a parameter to every selected figure that has it (a comma list for a
tuple, e.g. eps_values=0.3,0.9); theta0=X is the one slice theta0s=X of the figures that draw
several base angles (unless theta0s is set), and a key that no selected figure takes, or a
value a figure cannot draw, is refused; a figure whose picture a setting cuts short says so
(a warning). The figures and their parameters: model (omega2, eps,
theta0), pendulum (omega2), phase_portrait (xis), solution (eps_values, num), theta0s (eps,
theta0s, num), profiles (omega2s, eps, num), twirling (omega2, eps, theta0), bistability
(n_theta, n_eps, theta0s), hysteresis (eps, theta0, num), rheology (eps_values, theta0,
num), calibration (eps_values, theta0, num), physical_units (length, radius, youngs_modulus,
channel_height, viscosity, spacing [SI], base_angles, max_velocity, num), fd_convergence
(omega2s, nums, eps), speed (n, repeat), valve (length, radius, youngs_modulus,
channel_height, viscosity, spacing, base_angle, channel_length [SI], max_flow_rate [m^2/s],
diode_angles, num), pillar_calibration (theta0s, forcing_min, forcing_max, num,
slenderness L/a: the drag ratio gamma of Gray & Hancock, default 20), pillar_snap (theta0,
forcing_max, forcing, num, slenderness), pillar_bode (length, radius, youngs_modulus,
pillar_density [SI], frequency_range [Hz], num), pillar_step (length, radius,
youngs_modulus, pillar_density, wall_shear_stress [SI], periods, num), pillar_film (the
same, frames).

examples:
  hairbed figures --out figures
  hairbed figures --out figs --only solution hysteresis --dpi 300
  hairbed figures --out figs --only hysteresis --set eps=0.95 --set theta0=-1.2
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``figures`` subcommand's parser."""
    p = add_command(sub, "figures", run, ABOUT)
    p.add_argument("--out", default="figures", help="output folder (default ./figures)")
    p.add_argument("--dpi", type=int, default=150, help="resolution (default 150)")
    p.add_argument("--only", nargs="+", metavar="NAME", help="only these figures")
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="a parameter of the figures (repeatable), e.g. --set eps=0.9 --set theta0=-1.2",
    )
    p.add_argument("--quiet", action="store_true", help="no line per figure")


def run(args: argparse.Namespace) -> int:
    """Check the folder and the settings, then draw and write the figures."""
    optional_import("matplotlib", "figures")
    from hairbed.plotting import make_all, parse_settings

    if args.dpi < 1:
        raise UsageError(f"--dpi must be >= 1, got {args.dpi}")
    settings = parse_settings(args.set or [], args.only)  # names and values, before any work
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UnwritableOutput(args.out, "it exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UnwritableOutput(args.out, exc) from None
    check_output(str(out / "figure.png"))
    start = time.perf_counter()
    try:
        paths = make_all(
            args.out, dpi=args.dpi, only=args.only, verbose=not args.quiet, settings=settings
        )
    except OSError as exc:
        raise WriteError(exc.filename or args.out, exc) from None
    print(f"{len(paths)} figures in {args.out}/ ({time.perf_counter() - start:.1f} s)")
    return 0
