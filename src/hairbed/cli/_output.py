"""What the commands print and write: tables, JSON, states, figures and their checks.

Every output path is checked before any work (:func:`check_output`) and written whole or
not at all (:mod:`hairbed.safe_files`).
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from hairbed._jsonsafe import to_plain
from hairbed._variables import SOLUTION

from ._report import UnwritableOutput, UsageError, WriteError

__all__ = [
    "FIELDS",
    "NO_COMPRESS_HELP",
    "check_dataset_output",
    "check_output",
    "figure_format",
    "print_json",
    "print_states",
    "save_figure",
    "solution_table",
    "table",
    "write_dataset_output",
]

#: Each field of a Solution (and derived quantity) -> its label and unit, for the table.
FIELDS: dict[str, str] = {name: v.heading for name, v in SOLUTION.items()}


def print_json(value: Any) -> None:
    """``value`` as one line of strict JSON on stdout (NaN and infinities as null)."""
    print(json.dumps(to_plain(value)))


def _fmt(value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, float):
        return f"{value:.15g}"
    return str(value)


def table(rows: dict[str, Any], notes: dict[str, str] | None = None) -> str:
    """``rows`` as aligned lines ``key  value  note``."""
    notes = notes or {}
    width = max(len(k) for k in rows)
    vwidth = max(len(_fmt(v)) for v in rows.values())
    lines = []
    for key, value in rows.items():
        note = notes.get(key, "")
        lines.append(f"  {key:<{width}}  {_fmt(value):>{vwidth}}  {note}".rstrip())
    return "\n".join(lines)


def solution_table(sol: Any) -> str:
    """A Solution's fields, with their meaning and unit."""
    return table(sol.as_dict(), FIELDS)


def print_states(states: list[Any], as_json: bool, head: str) -> None:
    """Labelled states (:func:`hairbed.branches.label_states`): JSON or ``head`` and a table
    each; a branch's single state is its "only" one."""
    labels = ["only" if s.count == 1 else s.root for s in states]
    if as_json:
        print_json(
            [{**s.solution.as_dict(), "root": lab, "stable": s.stable}
             for s, lab in zip(states, labels)]
        )  # fmt: skip
        return
    print(head)
    for s, lab in zip(states, labels):
        sol = s.solution
        word = {True: "stable", False: "unstable", None: "not classified"}[s.stable]
        branch = f"branch sign={sol.sign:+d}, n={sol.n}" + (" (physical)" if sol.physical else "")
        print(f"{branch}, {lab} state ({word}):")
        print(solution_table(sol))


def read_input(read: Any, path: str, option: str) -> Any:
    """``read(path)`` for an input file option: an unreadable file or one the library refuses
    (its ValueError message starts with the path) is a one-line usage error naming ``option``."""
    try:
        return read(path)
    except OSError as exc:
        raise UsageError(f"{option}: cannot read {path}: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise UsageError(f"{option} {exc}") from None


def check_output(path: str, *, directory: bool = False, parents: bool = False) -> None:
    """Refuse, before any work, an output ``path`` that cannot be written: bad input, an
    :class:`~hairbed.cli._report.UnwritableOutput` (exit status 2).

    With ``parents`` the missing directories of ``path`` will be created: the nearest one
    that exists is checked instead.
    """
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if parents:
        while not parent.exists() and parent != parent.parent:
            parent, target = parent.parent, parent
    if not parent.exists():
        raise UnwritableOutput(path, f"directory {str(parent)!r} does not exist")
    if not parent.is_dir():
        raise UnwritableOutput(path, f"{str(parent)!r} is not a directory")
    if target.is_dir() and not directory:
        raise UnwritableOutput(path, "it is a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        read_only = hasattr(os, "statvfs") and os.statvfs(parent).f_flag & os.ST_RDONLY
        reason = "read-only file system at" if read_only else "permission denied in"
        raise UnwritableOutput(path, f"{reason} {str(parent)!r}")
    try:  # what access() cannot tell (a read-only or special file system, root's rights)
        with tempfile.TemporaryFile(dir=parent, prefix=f".{target.name}.probe"):
            pass
    except OSError as exc:
        raise UnwritableOutput(path, exc) from None


def figure_format(path: str, option: str) -> str:
    """The image format of ``path`` from its extension (PNG without one), checked."""
    from matplotlib.backend_bases import FigureCanvasBase

    fmt = Path(path).suffix.lstrip(".").lower() or "png"
    known = FigureCanvasBase.get_supported_filetypes()
    if fmt not in known:
        raise UsageError(
            f"{option} {path}: unknown image format {fmt!r}; use one of .{', .'.join(known)}"
        )
    return fmt


def save_figure(fig: Any, path: str, fmt: str) -> None:
    """Save a matplotlib figure whole or not at all."""
    from hairbed.safe_files import atomic_path

    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=150, format=fmt)
    except OSError as exc:
        raise WriteError(path, exc) from None


#: Help of ``--no-compress`` (``hairbed sweep``, ``hairbed bistability --map``).
NO_COMPRESS_HELP = (
    "write .nc output uncompressed (it is otherwise zlib level 4 with shuffle: lossless, "
    "about 40%% smaller for a sweep)"
)


def check_dataset_output(out: str | None, no_compress: bool = False) -> bool:
    """Check, before any work, the ``--out`` of a dataset (None or "-": CSV on stdout): its
    format by extension and that it can be written. Returns True for stdout."""
    from hairbed import sweeps

    if out is None or out == "-":
        if no_compress:
            raise UsageError("--no-compress applies to netCDF (.nc) output only")
        return True
    kind = sweeps.output_format(out)  # an unknown extension is refused here
    if no_compress and kind != "netcdf":
        raise UsageError("--no-compress applies to netCDF (.nc) output only")
    check_output(out, directory=kind == "zarr")
    return False


def write_dataset_output(ds: Any, out: str | None, no_compress: bool = False) -> int:
    """Write a dataset to ``--out`` (checked by :func:`check_dataset_output`) whole or not at
    all, or as CSV on stdout; says what was written on stderr. Returns the points written."""
    import sys

    from hairbed import sweeps

    if out is None or out == "-":
        points = sweeps.write_csv_stream(ds, sys.stdout)
        sys.stdout.flush()
        return points
    try:
        points = sweeps.write_dataset(ds, out, compress=not no_compress)
    except OSError as exc:
        raise WriteError(out, exc) from None
    print(f"wrote {out} ({points} points)", file=sys.stderr)
    return points
