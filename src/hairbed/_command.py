"""The ``hairbed`` command's start and its Ctrl-C (SIGINT): the one module for signals.

The console script and ``python -m hairbed`` start in :func:`run_and_exit`. It takes over
SIGINT before anything heavy is imported: the command line (:mod:`hairbed.cli`) imports
argparse, numpy and the library, a fraction of a second in which a SIGINT would otherwise end
in a ``KeyboardInterrupt`` traceback. From then until the process ends, a Ctrl-C is the one line
``hairbed: interrupted`` on stderr and exit status 130, and leaves no partial file.

One handler, :func:`_interrupted`, serves the whole command. It does not unwind the stack (a
``KeyboardInterrupt``) but ends the process at once (``os._exit``) once the temporaries of the
files being written are removed (:func:`hairbed.safe_files.remove_unfinished`; a rename onto
a target holds the signal back until it is done). Unwinding could wait without end: a chunked
netCDF write closes its file on the way out, which needs the locks that its worker threads
hold while they go on with the blocks already queued, and the interpreter's shutdown joins
those threads. A Ctrl-C after the command has done its work (while the interpreter shuts
down) ends the process at once with the command's own status, silently.

This module imports only ``os``, ``sys`` and ``_signal`` (the C part of ``signal``), which the
interpreter has loaded already, and ``import hairbed`` imports nothing heavy, so the handler is
in place as soon as the console script runs. Earlier than that hairbed cannot help: a SIGINT
before Python has installed its own handler ends the process by the signal, silently (a
shell reports status 130), and one while ``site`` and the console script's first import run
ends in Python's own traceback (the timings are in the CHANGELOG).
:func:`hairbed.cli.main` itself, called in a process of its own, turns a
``KeyboardInterrupt`` into the same line and status.
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

__all__ = ["INTERRUPTED", "run_and_exit"]

#: The one line of an interrupted command (also as :func:`hairbed.cli.main` prints it).
INTERRUPTED = "hairbed: interrupted"

#: Exit status of an interrupted command (128 + SIGINT, as a shell reports it).
INTERRUPTED_STATUS = 130


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):  # no stream, a closed pipe: nothing to keep
            pass


def _interrupted(signum: int, frame: object) -> None:
    """SIGINT while the command starts or runs: remove partial files, one line, exit 130."""
    # never import here: the signal may land inside an import; safe_files is loaded with
    # the command line, before any file is written (and may be half-loaded right now)
    safe_files = sys.modules.get("hairbed.safe_files")
    remove = getattr(safe_files, "remove_unfinished", None)
    if remove is not None:
        remove()
    _flush()
    try:
        sys.stderr.write(INTERRUPTED + "\n")
        sys.stderr.flush()
    except (AttributeError, OSError, ValueError):
        pass
    os._exit(INTERRUPTED_STATUS)


def run_and_exit() -> None:
    """The ``hairbed`` command: :func:`hairbed.cli.main`, then exit with its status.

    A SIGINT ignored by the parent process (``SIG_IGN``, as for a background job), or already
    handled by the program that calls this, is left alone.
    """
    take_over = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if take_over:
        signal.signal(signal.SIGINT, _interrupted)
    try:
        from . import safe_files  # noqa: F401 (for the handler, which must not import)
        from .cli import main  # argparse, numpy, the library: 0.15-0.5 s
    except KeyboardInterrupt:  # not taken over: SIGINT is Python's own
        _interrupted(signal.SIGINT, None)
    code = main()
    if code == INTERRUPTED_STATUS:  # main caught a KeyboardInterrupt (not taken over)
        _flush()
        os._exit(INTERRUPTED_STATUS)

    def finished(signum: int, frame: object) -> None:
        _flush()
        os._exit(code)

    if take_over:
        signal.signal(signal.SIGINT, finished)
    sys.exit(code)
