"""The axes of ``hairbed sweep``: a SPEC (a value, a comma list, start:stop:num[:log]) or the
older --<name>-min/--<name>-max/--num/--log form."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from ._report import UsageError

__all__ = ["legacy_grid", "spec"]


def spec(text: str | None, option: str) -> Any:
    """A SPEC of the sweep: a value, a comma list, or start:stop:num[:log] (or :lin)."""
    if text is None:
        return None
    form = "a number, a comma list or start:stop:num[:log]"
    parts = text.split(":")
    try:
        if len(parts) == 1:
            items = [p for p in text.split(",")]
            if len(items) == 1:
                return float(items[0])
            return np.array([float(p) for p in items])
        if len(parts) not in (3, 4):
            raise ValueError
        start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
        spacing = parts[3].strip().lower() if len(parts) == 4 else "lin"
    except ValueError:
        raise UsageError(f"{option} must be {form}, got {text!r}") from None
    if spacing not in ("lin", "log"):
        raise UsageError(f"{option}: the fourth field of start:stop:num:log is 'log' or 'lin'")
    if num < 1:
        raise UsageError(f"{option}: num in start:stop:num must be >= 1, got {num}")
    if spacing == "log":
        if start <= 0 or stop <= 0:
            raise UsageError(f"{option}: a log range needs positive bounds, got {text!r}")
        return np.geomspace(start, stop, num)
    return np.linspace(start, stop, num)


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
