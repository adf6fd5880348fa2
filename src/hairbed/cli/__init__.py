"""The ``hairbed`` command line: a thin layer over the library.

Subcommands: ``solve``, ``sweep``, ``invert``, ``bistability``, ``calibrate``, ``measure``,
``linear-range``, ``figures``, ``bench``, ``demo``, ``explore``, ``simulate``, ``response``,
``rheometer``.
Run ``hairbed <command> --help`` for the options and examples of each. Bad input ends with one
line ``hairbed: error: <message>`` on stderr and exit status 2 (so is what the library does not
support yet, its ``NotImplementedError``), an output path that cannot be written (refused
before any work) included, as ``hairbed: error: cannot write PATH: <reason>``; a file whose
writing fails after the work (a full disk) with ``hairbed: cannot write PATH: <reason>`` and a
missing optional dependency with ``hairbed: <command> needs <module>: pip install
'hairbed[<extra>]'``, both exit status 1; Ctrl-C with the one line
``hairbed: interrupted`` and exit status 130, leaving no partial file behind; a warning (of the
library, such as a flow outside the model's validity, or of numpy) is the one line ``hairbed:
warning: <message>`` on stderr. Negative numbers parse as values everywhere, in exponent form
too (``--theta0 -1e-1``).

Each subcommand is a module holding its ``add_parser(sub)`` beside its ``run(args)``; the
options they share are built in ``_options``, what they print in ``_output``, how they fail in
``_report``. The console script starts in :mod:`hairbed._command`, which handles Ctrl-C for
the whole command; :func:`main` called in a process of its own reports a
``KeyboardInterrupt`` the same way.

Examples
--------
>>> main(["solve", "--omega2", "2", "--eps", "0.5", "--json"])  # doctest: +ELLIPSIS
{"omega2": 2.0, "eps": 0.5, "theta0": 0.0, "sign": 1, "n": 0, "xi": 0.84725391654124...
0
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Sequence

import hairbed
from hairbed._optional import EXTRAS, install_hint

from . import (
    _bench,
    _bistability,
    _calibrate,
    _demo,
    _design,
    _explore,
    _figures,
    _invert,
    _linear_range,
    _measure,
    _pump,
    _response,
    _rheometer,
    _simulate,
    _solve,
    _sweep,
    _valve,
)
from ._options import NEGATIVE_NUMBER, Parser, formatter
from ._report import PROG, WARNED, CommandError, UsageError, one_line, show_warning

__all__ = ["NEGATIVE_NUMBER", "build_parser", "main"]

#: Ctrl-C: the one line and exit status 130 (as :mod:`hairbed._command`'s handler ends).
INTERRUPTED = f"{PROG}: interrupted"
INTERRUPTED_STATUS = 130

#: The subcommands, in the order of ``hairbed --help``.
COMMANDS = (
    _solve,
    _sweep,
    _invert,
    _figures,
    _bench,
    _demo,
    _explore,
    _bistability,
    _calibrate,
    _measure,
    _linear_range,
    _valve,
    _pump,
    _design,
    _simulate,
    _response,
    _rheometer,
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``hairbed`` (exposed for the documentation and tests)."""
    parser = Parser(
        prog=PROG,
        formatter_class=formatter,
        description="Exact deformation of a dense bed of elastic hairs in channel flow "
        "(Smucker, Vural, Alvarado & Morrison).",
        epilog="examples:\n"
        "  hairbed demo\n"
        "  hairbed solve --omega2 2 --eps 0.5\n"
        "  hairbed sweep --omega2 0.01:100:200:log --eps 0.5,0.9 --theta0 0 --out sweep.nc\n"
        "  hairbed invert --tip-deflection 0.6 --eps 0.5\n"
        "  hairbed figures --out figures\n"
        "run 'hairbed <command> --help' for the options of a command",
    )
    parser.add_argument("--version", action="version", version=f"hairbed {hairbed.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="command", parser_class=Parser)
    for command in COMMANDS:
        command.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 a write that failed after the
    work or an extra not installed, 2 bad input, an output path refused before any work
    included, 130 Ctrl-C).

    Warnings (of the library, such as :class:`hairbed.ModelValidityWarning`, or of numpy) are
    printed as one line ``hairbed: warning: <message>`` on stderr, each text once.
    """
    WARNED.clear()
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show_warning
            return _run(argv)
    except KeyboardInterrupt:  # between the handlers of _run (e.g. leaving the warnings block)
        print(INTERRUPTED, file=sys.stderr)
        return INTERRUPTED_STATUS


def _run(argv: Sequence[str] | None) -> int:
    command = PROG
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        command = args.command
        return int(args.func(args))
    except (UsageError, ValueError, NotImplementedError) as exc:
        # NotImplementedError: what the library does not do yet for a model
        print(f"{PROG}: error: {one_line(exc)}", file=sys.stderr)
        return 2
    except ArithmeticError as exc:  # an overflow the library did not catch (a huge input)
        print(f"{PROG}: error: numerical overflow ({one_line(exc)})", file=sys.stderr)
        return 2
    except CommandError as exc:
        print(f"{PROG}: {one_line(exc)}", file=sys.stderr)
        return 1
    except ImportError as exc:  # an optional dependency missing
        name = (getattr(exc, "name", None) or "").split(".")[0]
        if "pip install" in str(exc):  # hairbed._optional.optional_import's message
            print(f"{PROG}: {one_line(exc)}", file=sys.stderr)
        elif name in EXTRAS:
            print(f"{PROG}: {command} needs {name}: {install_hint(name)}", file=sys.stderr)
        else:
            raise
        return 1
    except BrokenPipeError:  # e.g. `hairbed sweep ... | head`
        return 0
    except KeyboardInterrupt:  # Ctrl-C: files are written whole or not at all
        print(INTERRUPTED, file=sys.stderr)
        return INTERRUPTED_STATUS
