"""How the command line reports: its errors (one line, an exit status each) and warnings.

Bad input is a :class:`UsageError` (or a ValueError of the library): ``hairbed: error:
<message>``, exit status 2; an output path that cannot be written, found before any work, is
bad input too (:class:`UnwritableOutput`: ``hairbed: error: cannot write PATH: <reason>``). A
command that cannot run here is a :class:`CommandError` (``hairbed: <message>``, exit status
1), such as a file whose writing fails after the work (:class:`WriteError`: a full disk) or an
optional dependency not installed. A warning is the one line
``hairbed: warning: <message>``, each text once per run.
"""

from __future__ import annotations

import sys
from typing import Any

__all__ = [
    "PROG",
    "CommandError",
    "UnwritableOutput",
    "UsageError",
    "WriteError",
    "one_line",
    "say_status",
    "show_warning",
]

PROG = "hairbed"


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class CommandError(Exception):
    """The command cannot run here (a file not writable, an extra not installed): reported as
    the one line ``hairbed: <message>``, exit status 1."""


def _cannot_write(path: Any, reason: Any) -> str:
    if isinstance(reason, OSError):
        reason = reason.strerror or str(reason)
    return f"cannot write {path}: {reason}"


class UnwritableOutput(UsageError):
    """An output ``path`` refused before any work (a missing folder, no permission, a
    directory): bad input, ``hairbed: error: cannot write PATH: <reason>``, exit status 2."""

    def __init__(self, path: Any, reason: Any) -> None:
        super().__init__(_cannot_write(path, reason))


class WriteError(CommandError):
    """Writing ``path`` failed after the work (a full disk, a file system that failed):
    ``hairbed: cannot write PATH: <reason>``, exit status 1."""

    def __init__(self, path: Any, reason: Any) -> None:
        super().__init__(_cannot_write(path, reason))


def one_line(exc: BaseException) -> str:
    """The text of ``exc`` on one line, whatever the library wrote."""
    return " ".join(str(exc).split())


#: Texts of the warnings printed by this run of :func:`hairbed.cli.main`.
WARNED: set[str] = set()


def show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: Any = None,
    line: str | None = None,
) -> None:
    """warnings.showwarning of the command line: one line ``hairbed: warning: ...``, once per
    text (a warning raised in a loop is printed once)."""
    text = " ".join(str(message).split())
    if text in WARNED:
        return
    WARNED.add(text)
    print(f"{PROG}: warning: {text}", file=sys.stderr)


def say_status(status: int, message: Any) -> int:
    """A result's status where its table shows NaN or stops: nothing for 0; for a caveat
    (status > 0) the line ``hairbed: warning: <message>``; for a failure (< 0) the line
    ``hairbed: <message>``. The exit status: 1 for a failure, else 0."""
    if status == 0:
        return 0
    text = " ".join(str(message).split())
    if status > 0:
        print(f"{PROG}: warning: {text}", file=sys.stderr)
        return 0
    print(f"{PROG}: {text}", file=sys.stderr)
    return 1
