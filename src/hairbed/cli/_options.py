"""The parser and the options several subcommands share, written once.

The parser reports bad input as one line (:class:`~hairbed.cli._report.UsageError`) and
reads every negative number as a value. The builders add the options whose names and help
texts must agree between subcommands: ``--eps``, ``--theta0``, ``--json``, the physical
inputs of a bed, which :func:`bed_from` turns into a :class:`hairbed.HairBed`, and those of
an isolated pillar (``--pillar``, ``--forcing``, ``--profile`` ...), which
:func:`pillar_keywords` turns into the keywords of :func:`hairbed.solve_pillar`.
"""

from __future__ import annotations

import argparse
import re
from collections.abc import Callable
from typing import Any

import numpy as np

import hairbed
from hairbed._variables import BED, BED_REQUIRED, PILLAR

from ._report import UsageError

__all__ = [
    "BED_OPTIONS",
    "EPS_HELP",
    "NEGATIVE_NUMBER",
    "PILLAR_OPTIONS",
    "THETA0_HELP",
    "Parser",
    "add_bed_options",
    "add_branch",
    "add_command",
    "add_eps",
    "add_json",
    "add_model_options",
    "add_pillar_options",
    "add_theta0",
    "bed_from",
    "formatter",
    "need_bed",
    "pillar_keywords",
    "refuse",
    "refuse_model",
    "refuse_without_sensor_pillar",
    "sensor_pillar_from",
    "add_fluid_option",
    "add_sensor_pillar_options",
]

#: A negative number as a value, not an option: -1, -.5, -1e-1, -1.2:1.2:25, -inf, -nan
#: (argparse's own pattern, ``^-\d+$|^-\d*\.\d+$``, takes ``-1e-1`` for an option).
NEGATIVE_NUMBER = re.compile(r"^-(?:\.?\d|inf(?:inity)?$|nan$)", re.IGNORECASE)

#: Help text of the confinement.
EPS_HELP = "confinement eps = L/H [-], in [0, 1)"

#: Help text of a base angle: its sign convention.
THETA0_HELP = (
    "base angle theta0 [rad], in (-pi/2, pi/2). Positive leans with the flow, "
    "negative leans into it (where a tight channel can hold three states)"
)

#: What the command line adds to the label of a bed parameter in its option's help.
_BED_NOTES = {
    "spacing": "(or --packing-fraction)",
    "packing_fraction": "(or --spacing)",
    "base_angle": "(default 0; negative leans into a flow towards +x)",
    "density": "(optional: checks Re < 1)",
}
#: Physical inputs of a bed: option name -> (HairBed keyword, help text).
BED_OPTIONS: dict[str, tuple[str, str]] = {
    "--" + name.replace("_", "-"): (name, f"{v.heading} {_BED_NOTES.get(name, '')}".rstrip())
    for name, v in BED.items()
    if v.group == "bed"
}


class Parser(argparse.ArgumentParser):
    """argparse, but errors are one line on stderr (no usage block) and every negative number
    (exponent form, SPEC, -inf) is a value."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def formatter(prog: str) -> argparse.HelpFormatter:
    """The help layout: descriptions and examples as written, option help from column 32."""
    return argparse.RawDescriptionHelpFormatter(prog, max_help_position=32)


def add_command(
    sub: Any, name: str, run: Callable[[argparse.Namespace], int], about: str
) -> argparse.ArgumentParser:
    """A subcommand's parser; ``run(args)`` runs it and returns the exit status.

    ``about`` is its ``--help`` text: the one-line summary (shown by ``hairbed --help``), a
    blank line, the description, a blank line and the examples (from the line "examples:"
    on), each printed as written.
    """
    summary, _, rest = about.partition("\n\n")
    description, _, examples = rest.partition("\n\nexample")
    p = sub.add_parser(
        name,
        help=summary,
        formatter_class=formatter,
        description=description.strip(),
        epilog=("example" + examples).rstrip() if examples else None,
    )
    p.set_defaults(func=run)
    return p


def add_branch(
    p: argparse.ArgumentParser, sign: int | None, n: int | None, root: str | None, root_help: str
) -> None:
    """``--sign``, ``--n`` (the branch) and ``--root`` (the state on it), with their defaults
    (None: not given, which a command may refuse)."""
    p.add_argument(
        "--sign",
        type=int,
        default=sign,
        choices=(1, -1),
        help="sign of the base curvature of the branch (default 1)",
    )
    p.add_argument(
        "--n", type=int, default=n, help="interior turning points of the branch (default 0)"
    )
    p.add_argument("--root", default=root, choices=("low", "mid", "high"), help=root_help)


def add_eps(p: argparse.ArgumentParser, **kwargs: Any) -> None:
    """``--eps`` (a float unless ``type``/``metavar`` say otherwise)."""
    p.add_argument("--eps", **{"type": float, "help": EPS_HELP, **kwargs})


def add_theta0(p: argparse.ArgumentParser, **kwargs: Any) -> None:
    """``--theta0`` with its sign convention; "default 0" unless it is required (the command
    takes None, not given, as 0)."""
    text = THETA0_HELP if kwargs.get("required") else f"{THETA0_HELP} (default 0)"
    p.add_argument("--theta0", **{"type": float, "help": text, **kwargs})


def add_json(p: argparse.ArgumentParser, help: str = "print JSON") -> None:
    """``--json``: the output as one JSON document on stdout."""
    p.add_argument("--json", action="store_true", help=help)


def add_bed_options(
    p: argparse.ArgumentParser, velocity: bool = True, model: bool = False
) -> None:
    """The physical inputs of a bed (SI units), and ``--velocity`` unless told not to; with
    ``model`` also ``--model`` and ``--drag`` (:func:`add_model_options`)."""
    g = p.add_argument_group("physical inputs (SI units, instead of the dimensionless ones)")
    for opt, (_, text) in BED_OPTIONS.items():
        g.add_argument(opt, type=float, metavar="X", help=text)
    if velocity:
        g.add_argument("--velocity", type=float, metavar="V", help="top wall speed v [m/s]")
    if model:
        add_model_options(g)


#: The bed models (``HairBed(model=...)``) and the porous bed's drag laws (``drag=...``).
MODEL_CHOICES = ("dense", "porous")
DRAG_CHOICES = ("crossover", "sparse", "array")


def add_model_options(g: Any) -> None:
    """``--model dense|porous`` and ``--drag crossover|sparse|array``: the ``model`` and
    ``drag`` of the :class:`hairbed.HairBed` that :func:`bed_from` builds."""
    g.add_argument(
        "--model",
        choices=MODEL_CHOICES,
        default="dense",
        help="the bed's model (default dense): dense, the paper's bed that stops the flow at "
        "the tips; porous, the flow through the bed too (a Brinkman medium, theory.md §13), "
        "packing fraction <= 0.6",
    )
    g.add_argument(
        "--drag",
        choices=DRAG_CHOICES,
        default="crossover",
        help="with --model porous: the hairs' drag law in the bed (default crossover), "
        "hairbed.HairBed's drag",
    )


def refuse_model(args: argparse.Namespace, why: str) -> None:
    """``--model porous`` or ``--drag`` other than crossover: a usage error ``why``, where
    the command builds no bed of hairs (the parser's defaults are let through)."""
    if getattr(args, "model", "dense") != "dense":
        raise UsageError(f"--model {args.model} {why}")
    if getattr(args, "drag", "crossover") != "crossover":
        raise UsageError(f"--drag {args.drag} {why}")


def bed_from(args: argparse.Namespace) -> Any | None:
    """The HairBed of the physical options (with ``--model`` and ``--drag`` where the command
    has them), or None when none is given (``--model porous`` or ``--drag`` then refused)."""
    given = {kw: getattr(args, kw) for kw, _ in BED_OPTIONS.values()}
    given = {k: v for k, v in given.items() if v is not None}
    if not given:
        refuse_model(args, "needs the physical inputs of a bed (--length, --radius, ...)")
        return None
    missing = [k for k in BED_REQUIRED if k not in given]
    if missing:
        names = ", ".join("--" + k.replace("_", "-") for k in missing)
        raise UsageError(f"physical inputs need also {names}")
    for kw in ("model", "drag"):
        value = getattr(args, kw, None)
        if value is not None:
            given[kw] = value
    if given.get("model") == "dense" and given.get("drag", "crossover") != "crossover":
        raise UsageError(f"--drag {given['drag']} applies to --model porous only")
    return hairbed.HairBed(**given)


def need_bed(args: argparse.Namespace, what: str) -> Any:
    """The HairBed of the physical options, which the command ``what`` cannot do without."""
    bed = bed_from(args)
    if bed is None:
        raise UsageError(f"{what} needs the physical inputs of a bed (--length, --radius, ...)")
    return bed


def refuse(args: argparse.Namespace, options: dict[str, str], why: str) -> None:
    """UsageError naming the first of ``options`` (dest -> flag) that was given."""
    for dest, flag in options.items():
        value = getattr(args, dest)
        if value is not None and value is not False:
            raise UsageError(f"{flag} {why}")


#: The options of an isolated pillar besides ``--pillar`` and ``--theta0``: dest -> flag.
PILLAR_OPTIONS = {
    "forcing": "--forcing",
    "profile": "--profile",
    "height_ratio": "--height-ratio",
    "gamma": "--gamma",
    "slenderness": "--slenderness",
    "tip_load": "--tip-load",
}


def add_pillar_options(p: argparse.ArgumentParser, *, spec: bool = False) -> Any:
    """``--pillar`` and the inputs of an isolated pillar (:func:`hairbed.solve_pillar`): floats,
    or SPECs of a sweep's axes with ``spec``. Returns the argument group (for more options)."""
    g = p.add_argument_group(
        "an isolated pillar in a wall shear layer (hairbed.solve_pillar, theory.md §12)"
    )
    g.add_argument(
        "--pillar",
        action="store_true",
        help="an isolated pillar under resistive-force drag instead of a bed of hairs",
    )
    kind: dict[str, Any] = {"metavar": "SPEC"} if spec else {"type": float, "metavar": "X"}

    def text(name: str, note: str) -> str:
        return f"{PILLAR[name].long_name} [{PILLAR[name].unit}]{note}"

    g.add_argument("--forcing", **kind, help=text("forcing", ", finite"))
    g.add_argument(
        "--profile",
        choices=("sublayer", "couette", "poiseuille", "wall-law"),
        help="undisturbed profile U(z): sublayer and couette U = z, poiseuille "
        "U = z (1 - (L/H) z) (default sublayer); wall-law, Spalding's law of the wall, for an "
        "SI pillar with --density or --fluid",
    )
    g.add_argument(
        "--height-ratio", **kind, help=text("height_ratio", ", in (0, 1]; needed by poiseuille")
    )
    g.add_argument("--gamma", **kind, help=text("gamma", ", in (0, 1] (default 0.5)"))
    g.add_argument(
        "--slenderness",
        **kind,
        help="slenderness L/a [-], > 1.5: gamma of Gray & Hancock's coefficients (instead of "
        "--gamma)",
    )
    g.add_argument("--tip-load", **kind, help=text("tip_load", " (default 0)"))
    return g


def pillar_keywords(
    args: argparse.Namespace, convert: Callable[[Any, str], Any]
) -> dict[str, Any]:
    """The keywords ``profile``, ``height_ratio``, ``gamma`` and ``tip_load`` of
    :func:`hairbed.solve_pillar` from the pillar options (each value through ``convert(value,
    flag)``, e.g. a sweep's SPEC parser); ``--slenderness`` gives gamma by
    :func:`hairbed.gray_hancock_ratio`. Options not given are left out."""
    if args.gamma is not None and args.slenderness is not None:
        raise UsageError("give --gamma or --slenderness, not both")
    if args.height_ratio is not None and args.profile in (None, "sublayer"):
        raise UsageError(
            "--height-ratio applies to the channel profiles (--profile couette or poiseuille)"
        )
    if args.profile == "wall-law":
        raise UsageError(
            "--profile wall-law needs an SI pillar (its shape depends on the stress in wall "
            "units: --length, --radius, --youngs-modulus and --fluid or --viscosity and "
            "--density), not --forcing"
        )
    out: dict[str, Any] = {}
    if args.profile is not None:
        out["profile"] = args.profile
    for dest in ("height_ratio", "gamma", "tip_load"):
        value = getattr(args, dest)
        if value is not None:
            out[dest] = convert(value, PILLAR_OPTIONS[dest])
    if args.slenderness is not None:
        sl = convert(args.slenderness, "--slenderness")
        try:
            with np.errstate(over="ignore", invalid="ignore"):  # checked just below
                gamma = hairbed.gray_hancock_ratio(sl)
        except ValueError as exc:
            raise UsageError(f"--slenderness: {exc}") from None
        if not np.all(np.isfinite(gamma)):  # ln(2 L/a) overflows beyond about 1e308
            too_big = f"--slenderness {args.slenderness}: too large for ln(2 L/a) (<= 8e307)"
            raise UsageError(too_big)
        out["gamma"] = gamma
    return out


#: The dimensionless pillar options that an SI pillar sensor (``calibrate``/``measure``
#: ``--pillar``) does not take: its gamma is Gray & Hancock's of L/a, its L/H is L over
#: --channel-height, its forcing follows from the known stress.
_DIMENSIONLESS_PILLAR = {k: v for k, v in PILLAR_OPTIONS.items() if k not in ("profile",)}
#: The bed options an SI pillar does not have.
_NOT_A_PILLAR = {"spacing": "--spacing", "packing_fraction": "--packing-fraction"}


def add_sensor_pillar_options(p: argparse.ArgumentParser) -> None:
    """``--pillar`` (an isolated SI pillar sensor, :class:`hairbed.Pillar`) for the commands
    that take the bed options: the shared pillar group of :func:`add_pillar_options`, whose
    ``--profile`` it uses (its dimensionless options are hidden from the help and refused),
    plus ``--drag-scale``."""
    g = add_pillar_options(p)
    for action in g._group_actions:  # refused with --pillar here (sensor_pillar_from): hidden
        if action.dest in _DIMENSIONLESS_PILLAR:
            action.help = argparse.SUPPRESS
    g.add_argument(
        "--drag-scale",
        type=float,
        metavar="C",
        help="with --pillar: a factor c > 0 on both drag coefficients [-] (default 1, Gray & "
        "Hancock's)",
    )
    add_fluid_option(g)


def add_fluid_option(g: Any) -> None:
    """``--fluid``: a fluid preset of :class:`hairbed.Pillar` (viscosity and density at 20 C)."""
    g.add_argument(
        "--fluid",
        choices=("water", "glycerol", "air"),
        help="with --pillar: the fluid at 20 C (its viscosity and density, "
        "hairbed.pillars.FLUIDS; --viscosity or --density given too override it); with a "
        "density the Reynolds-number and L+ checks run",
    )


def sensor_pillar_from(args: argparse.Namespace, what: str) -> Any:
    """The :class:`hairbed.Pillar` of the bed options (--length, --radius, --youngs-modulus,
    --viscosity, or --fluid instead of the viscosity; --base-angle, --channel-height,
    --density optional), --profile, --drag-scale and --fluid, for ``what`` with
    ``--pillar``."""
    refuse(
        args,
        _DIMENSIONLESS_PILLAR,
        f"does not apply to {what} --pillar (an SI pillar: give --length, --radius, ...)",
    )
    refuse(args, _NOT_A_PILLAR, f"does not apply to {what} --pillar (an isolated pillar)")
    refuse_model(args, f"does not apply to {what} --pillar (an isolated pillar)")
    given = {kw: getattr(args, kw) for kw, _ in BED_OPTIONS.values() if kw not in _NOT_A_PILLAR}
    given = {k: v for k, v in given.items() if v is not None}
    fluid = getattr(args, "fluid", None)
    required = ("length", "radius", "youngs_modulus") + (() if fluid else ("viscosity",))
    missing = [k for k in required if k not in given]
    if missing:
        names = ", ".join("--" + k.replace("_", "-") for k in missing)
        raise UsageError(f"{what} --pillar needs also {names}")
    if args.profile is not None:
        given["profile"] = args.profile
    if args.drag_scale is not None:
        given["drag_scale"] = args.drag_scale
    if fluid is not None:
        given["fluid"] = fluid
    return hairbed.Pillar(**given)


def refuse_without_sensor_pillar(args: argparse.Namespace) -> None:
    """An option of :func:`add_sensor_pillar_options` given without ``--pillar``: a usage
    error naming it."""
    refuse(
        args,
        {**PILLAR_OPTIONS, "drag_scale": "--drag-scale", "fluid": "--fluid"},
        "needs --pillar (an isolated pillar sensor)",
    )
