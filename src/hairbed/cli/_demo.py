"""``hairbed demo``: the paper's worked example."""

from __future__ import annotations

import argparse
from typing import Any

import hairbed

from ._options import add_command
from ._output import solution_table

#: ``hairbed demo --help``: the summary line, the description and the examples.
ABOUT = """the paper's worked example

Solve omega2 = 2, eps = 0.5, theta0 = 0 and print the state.

example:
  hairbed demo
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``demo`` subcommand's parser."""
    add_command(sub, "demo", run, ABOUT)


def run(args: argparse.Namespace) -> int:
    """Print the exact state of omega2 = 2, eps = 0.5, theta0 = 0."""
    sol = hairbed.solve(2.0, 0.5, 0.0)
    print("The paper's example: a hair standing upright (theta0 = 0) in a channel twice its")
    print("length (eps = L/H = 0.5) under forcing omega^2 = 2; exact solution:")
    print(solution_table(sol))
    return 0
