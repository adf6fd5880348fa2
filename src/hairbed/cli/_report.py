"""How the command line reports: its errors (one line, an exit status each) and warnings.

Bad input is a :class:`UsageError` (or a ValueError of the library): ``hairbed: error:
<message>``, exit status 2. A command that cannot run here is a :class:`CommandError`
(``hairbed: <message>``, exit status 1), such as a file that cannot be written
(:class:`WriteError`) or an optional dependency not installed. A warning is the one line
``hairbed: warning: <message>``, each text once per run.
"""

from __future__ import annotations

import sys
from typing import Any

__all__ = [
    "PROG",
    "CommandError",
    "UsageError",
    "WriteError",
    "one_line",
    "show_warning",
]

PROG = "hairbed"


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class CommandError(Exception):
    """The command cannot run here (a file not writable, an extra not installed): reported as
    the one line ``hairbed: <message>``, exit status 1."""


class WriteError(CommandError):
    """``path`` cannot be written: ``hairbed: cannot write PATH: <reason>``."""

    def __init__(self, path: Any, reason: Any) -> None:
        if isinstance(reason, OSError):
            reason = reason.strerror or str(reason)
        super().__init__(f"cannot write {path}: {reason}")


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
