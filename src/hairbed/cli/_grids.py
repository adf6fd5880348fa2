"""The axes of ``hairbed sweep``: a SPEC (a value, a comma list, start:stop:num[:log], or for a
path start:stop:num:updown; parsed by :mod:`hairbed._specs`) or the older
--<name>-min/--<name>-max/--num/--log form."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from hairbed._specs import parse_spec

from ._report import UsageError

__all__ = ["legacy_grid", "spec"]


def spec(text: str | None, option: str, *, path: bool = False) -> Any:
    """A SPEC of the sweep (:mod:`hairbed._specs`, the one parser): a value, a comma list, or
    start:stop:num[:log] (or :lin); with ``path``, also the up-and-down ramp :updown."""
    if text is None:
        return None
    try:
        return parse_spec(text, option, path=path)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def legacy_grid(args: argparse.Namespace, name: str, lo: float | None, hi: float | None) -> Any:
    """--<name>-min/--<name>-max/--num/--log (the older form of a 1-D SPEC)."""
    num = 101 if args.num is None else args.num
    if num < 1:
        raise UsageError(f"--num must be >= 1, got {num}")
    if args.log:
        if lo is None or hi is None or lo <= 0 or hi <= 0:
            raise UsageError(f"--log needs positive --{name}-min and --{name}-max")
        return np.geomspace(lo, hi, num)
    if lo is None or hi is None:
        raise UsageError(f"give --{name}-min and --{name}-max")
    return np.linspace(lo, hi, num)
