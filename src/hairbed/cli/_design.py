"""``hairbed design``: the best bed or pillar for a target, from a TOML spec."""

from __future__ import annotations

import argparse
from typing import Any

from ._options import add_command
from ._output import print_json
from ._report import CommandError, UsageError

#: ``hairbed design --help``: the summary line, the description and the examples.
ABOUT = """the best bed or pillar for a target, from a TOML spec (JSON out)

Varies SI parameters of a bed or a pillar within bounds to minimise or maximise a quantity
under constraints, the model's validity included, by SLSQP from several starts with exact
gradients (hairbed.design.optimise). The spec has a [model] table (kind = "bed" or "pillar"
and the constructor's parameters), [[variables]] tables (name, low, high, log), an
[objective] table (quantity, its arguments, sense = "min" or "max"), [[constraints]] tables
(quantity, its arguments, max = or min = bound) and an optional [options] table (starts,
seed, validity). Quantities: diodicity, resistance_ratio, gap_reynolds (pressure_drop,
channel_length), brinkman_ratio, bistable_width, tip_deflection, sensitivity, l_plus,
pillar_reynolds (wall_shear_stress), linear_range (rtol), slenderness. Prints the result as
one line of JSON; an infeasible problem prints it too (success false, the constraint that
cannot be met in its message) and exits 1.

examples:
  hairbed design valve.toml
  hairbed design sensor.toml > best.json
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``design`` subcommand's parser."""
    p = add_command(sub, "design", run, ABOUT)
    p.add_argument("spec", metavar="SPEC", help="the design's TOML spec file")


def run(args: argparse.Namespace) -> int:
    """The design of the spec, as JSON; exit status 1 when no design was found."""
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
    from hairbed.design._spec import design_from_spec, result_as_dict

    res = design_from_spec(spec)
    print_json(result_as_dict(res))
    return 0 if res.success else 1
