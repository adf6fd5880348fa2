"""The command line's parser for the documentation (sphinx-argparse, ``api/cli.rst``).

:func:`hairbed.cli.build_parser` itself, with every description and epilog that is laid out
by hand (indented examples) turned into a literal block, so that reStructuredText shows it as
``--help`` does instead of parsing its indentation.
"""

from __future__ import annotations

import argparse
import textwrap

from hairbed.cli import build_parser


def _literal(text: str | None) -> str | None:
    if not text or not any(line[:1].isspace() for line in text.splitlines()):
        return text
    body = textwrap.indent(textwrap.dedent(text).strip("\n"), "    ")
    return ".. code-block:: text\n\n" + body


def _walk(parser: argparse.ArgumentParser) -> None:
    parser.description = _literal(parser.description)
    parser.epilog = _literal(parser.epilog)
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                _walk(sub)


def parser() -> argparse.ArgumentParser:
    """``hairbed``'s parser, its hand-made layouts as literal blocks."""
    p = build_parser()
    _walk(p)
    return p
