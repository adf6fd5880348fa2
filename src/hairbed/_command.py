"""The entry point of the ``hairbed`` command (and of ``python -m hairbed``).

It takes over Ctrl-C before anything heavy is imported. The command line (:mod:`hairbed.cli`)
imports argparse, numpy and the library, 0.15-0.5 s in which a SIGINT used to end in a
``KeyboardInterrupt`` traceback. From the moment :func:`run_and_exit` runs, a Ctrl-C is the one
line ``hairbed: interrupted`` on stderr and exit status 130; once the command line is
imported, SIGINT is a ``KeyboardInterrupt`` again, so that :func:`hairbed.cli.main` can remove
a partly written file before it reports the interrupt the same way.

This module imports only ``os``, ``sys`` and ``_signal`` (the C part of ``signal``), which the
interpreter has loaded already, and ``import hairbed`` imports nothing heavy, so the handler is
in place about 1 ms after the interpreter has started running the console script. Earlier
than that hairbed cannot help (measured on an idle 2-core machine, with compiled bytecode: a
SIGINT in the first ~11 ms, before Python has installed its own handler, ends the process by
the signal, silently, which a shell reports as status 130; one in the next ~6 ms, while
``site`` and the console script's first import run, ends in Python's own traceback).
"""

from __future__ import annotations

import os
import sys

TYPE_CHECKING = False  # typing.TYPE_CHECKING, without importing typing
if TYPE_CHECKING:
    import signal
else:
    try:  # the C module, loaded at the interpreter's start-up: ``import signal`` would first
        import _signal as signal  # import enum, functools and collections (about 5 ms)
    except ImportError:  # pragma: no cover (an interpreter without it)
        import signal

__all__ = ["run_and_exit"]

#: The one line of an interrupted command (as :func:`hairbed.cli.main` prints it).
INTERRUPTED = "hairbed: interrupted\n"


def _interrupted(signum: int, frame: object) -> None:
    """SIGINT while the command line is imported: the one line, exit status 130, at once."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):  # no stream, a closed pipe: nothing to keep
            pass
    try:
        sys.stderr.write(INTERRUPTED)
        sys.stderr.flush()
    except (AttributeError, OSError, ValueError):
        pass
    os._exit(130)


def run_and_exit() -> None:
    """The ``hairbed`` command: :func:`hairbed.cli.run_and_exit`, Ctrl-C handled throughout.

    Installs a SIGINT handler (the one line, exit status 130, ``os._exit``) while the command
    line is imported, then hands SIGINT back to Python (``KeyboardInterrupt``, which
    :func:`hairbed.cli.main` turns into the same line after removing any partial file). A
    SIGINT ignored by the parent process (``SIG_IGN``, as for a background job) stays ignored.
    """
    take_over = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if take_over:
        signal.signal(signal.SIGINT, _interrupted)
    from .cli import run_and_exit as run  # argparse, numpy, the library: 0.15-0.5 s

    try:
        if take_over:
            signal.signal(signal.SIGINT, signal.default_int_handler)
        run()
    except KeyboardInterrupt:  # between the handover and cli.main's own handler
        _interrupted(signal.SIGINT, None)
