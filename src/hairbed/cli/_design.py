"""``hairbed design``: the best bed or pillar for a target, from a TOML spec."""

from __future__ import annotations

import argparse
from typing import Any

from ._options import add_command
from ._output import check_output, figure_format, print_json, save_figure
from ._report import CommandError, UsageError

#: ``hairbed design --help``: the summary line, the description and the examples.
ABOUT = """the best bed or pillar for a target, from a TOML spec (JSON out)

Varies SI parameters of a bed or a pillar within bounds to minimise or maximise a quantity
under constraints, the model's validity included, by SLSQP from several starts with exact
gradients (hairbed.design.optimise). The spec has a [model] table (kind = "bed" or "pillar"
and the constructor's parameters), [[variables]] tables (name, low, high, log), an
[objective] table (quantity, its arguments, sense = "min" or "max"), [[constraints]] tables
(quantity, its arguments, max = or min = bound), optionally a [second] objective (then the
Pareto front of the two, by the epsilon-constraint method) and an optional [options] table
(starts, seed, validity, points). Quantities: diodicity, resistance_ratio, gap_reynolds
(pressure_drop, channel_length), brinkman_ratio, bistable_width, tip_deflection,
sensitivity, l_plus, pillar_reynolds, bandwidth (wall_shear_stress), resonance_frequency
(wall_shear_stress, pillar_density), linear_range (rtol), slenderness, linear_sensitivity,
snap_window. Prints the result as one line of JSON; a problem with no
design (infeasible: the constraint that cannot be met is in its message) prints it too and
exits 1.

examples (docs/examples/valve.toml is a whole spec, the valve of docs/api/design.rst):
  hairbed design docs/examples/valve.toml
  hairbed design sensor.toml > best.json
  hairbed design front.toml --plot front.png
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``design`` subcommand's parser."""
    p = add_command(sub, "design", run, ABOUT)
    p.add_argument("spec", metavar="SPEC", help="the design's TOML spec file")
    p.add_argument(
        "--plot",
        metavar="FILE",
        help="also draw the result into FILE (PNG, or the format of its extension): the "
        "Pareto front, or the optimum's starts and constraints "
        "(hairbed.plotting.design.fig_design_result)",
    )


def run(args: argparse.Namespace) -> int:
    """The design of the spec, as JSON; exit status 1 when no design was found."""
    fmt = ""
    if args.plot is not None:  # checked before any work
        from hairbed._optional import optional_import

        optional_import("matplotlib", "design --plot")
        fmt = figure_format(args.plot, "--plot")
        check_output(args.plot)
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        raise CommandError("design needs Python 3.11 or later (tomllib) to read TOML") from None
    try:
        with open(args.spec, "rb") as fh:
            spec = tomllib.load(fh)
    except OSError as exc:
        raise UsageError(f"cannot read the spec {args.spec}: {exc.strerror or exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise UsageError(f"the spec {args.spec} is not valid TOML: {exc}") from None
    from hairbed.design import DesignResult
    from hairbed.design._spec import design_from_spec, front_as_dict, result_as_dict

    res = design_from_spec(spec)
    if isinstance(res, DesignResult):
        print_json(result_as_dict(res))
        ok = res.success
    else:
        print_json(front_as_dict(res))
        ok = res.status == 0
    if fmt:
        import sys

        from hairbed.plotting.design import fig_design_result

        save_figure(fig_design_result(res), args.plot, fmt)
        print(f"wrote {args.plot} ({fmt.upper()})", file=sys.stderr)
    return 0 if ok else 1
