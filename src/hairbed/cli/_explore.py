"""``hairbed explore``: the interactive explorer, served to a web browser."""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

from ._options import add_command
from ._report import CommandError, UsageError, one_line

#: ``hairbed explore --help``: the summary line, the description and the examples.
ABOUT = """the interactive explorer in a web browser

Serve the interactive explorer (needs the app extra: pip install 'hairbed[app]'): sliders
and exact entry of omega2, eps and theta0 or of a bed in SI units; every coexisting state in
the channel, the branch diagram, the bistability map, the phase portrait and a table; the
inputs in the page's URL; JSON and CSV downloads. Listens on the loopback interface unless
--host says otherwise. Each browser session holds some 4 to 5 MB of server memory until it
is discarded, --unused-session-lifetime after its page was closed. The server runs with
Python's objects from the C allocator (--allocator malloc, the default: it restarts itself
with PYTHONMALLOC=malloc), so that memory goes back to the system once the sessions close
(within ~4 MB); with CPython's own allocator (--allocator pymalloc) some 30 MB stay behind.

With --export PATH it serves nothing: it writes the view of --url-params (the query of a
link to the explorer) as a PNG, the picture of the page's "download PNG" button, drawn with
matplotlib from the page's own figures (no browser), and exits.

examples:
  hairbed explore
  hairbed explore --port 8000 --no-browser
  hairbed explore --host 0.0.0.0 --port 8000 --allow-websocket-origin example.org
  hairbed explore --export view.png --url-params '?omega2=1.2&eps=0.9&theta0=-1.5'
  hairbed explore --export pillar.png --url-params '?mode=pillar&forcing=20&pillar_theta0=-1.45'
"""

__all__ = ["ABOUT", "add_parser", "run"]

#: The server's options: (dest, type, default, metavar, help); the session options (those
#: with a metavar) must be >= 1.
_OPTIONS = (
    ("port", int, 5006, None, "TCP port (default 5006; 0: any free)"),
    ("host", str, "127.0.0.1", None, "address to listen on (default 127.0.0.1, loopback)"),
    ("session_token_expiration", int, 300, "S",
     "seconds a page has to connect to its session (default 300)"),
    ("check_unused_sessions", int, 17000, "MS",
     "how often to look for closed sessions [ms] (default 17000)"),
    ("unused_session_lifetime", int, 15000, "MS",
     "discard a closed session's state after this long [ms] (default 15000)"),
)  # fmt: skip
_SESSION_OPTIONS = tuple(o for o in _OPTIONS if o[3] is not None)
#: --allocator's choices: the values of PYTHONMALLOC it runs the server with.
ALLOCATORS = ("malloc", "pymalloc")


def add_parser(sub: Any) -> None:
    """The ``explore`` subcommand's parser."""
    p = add_command(sub, "explore", run, ABOUT)
    for dest, kind, default, _, text in _OPTIONS[:2]:
        p.add_argument("--" + dest, type=kind, default=default, help=text)
    p.add_argument("--no-browser", action="store_true", help="do not open a web browser")
    p.add_argument(
        "--allow-websocket-origin",
        action="append",
        metavar="HOST[:PORT]",
        help="also accept pages served as HOST[:PORT] (behind a proxy); repeatable",
    )
    for dest, kind, default, metavar, text in _SESSION_OPTIONS:
        option = "--" + dest.replace("_", "-")
        p.add_argument(option, type=kind, default=default, metavar=metavar, help=text)
    p.add_argument(
        "--export",
        metavar="PATH",
        help="write the view of --url-params as a PNG and exit (no server, no browser)",
    )
    p.add_argument(
        "--url-params",
        metavar="QUERY",
        help="the view to export: a link's query string ('?omega2=1.2&eps=0.9'), or the link",
    )
    p.add_argument(
        "--allocator",
        choices=ALLOCATORS,
        default="malloc",
        help="where Python's objects live: the C allocator, whose freed memory goes back to "
        "the system (malloc, default), or CPython's own arenas (pymalloc)",
    )


def run(args: argparse.Namespace) -> int:
    """Check the options, then serve until interrupted."""
    from hairbed.explorer import AppMissingError, _check_installed, serve

    if args.export is not None or args.url_params is not None:
        return _export(args)
    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port must be in [0, 65535], got {args.port}")
    for dest, *_ in _SESSION_OPTIONS:
        if getattr(args, dest) < 1:
            option = "--" + dest.replace("_", "-")
            raise UsageError(f"{option} must be >= 1, got {getattr(args, dest)}")
    try:
        _check_installed()  # before a restart: a missing extra is this process's one line
    except AppMissingError as exc:
        raise CommandError(one_line(exc)) from None  # names the module and the app extra
    _run_with_allocator(args)
    try:
        serve(
            port=args.port,
            host=args.host,
            show=not args.no_browser,
            allow_websocket_origin=args.allow_websocket_origin or (),
            **{dest: getattr(args, dest) for dest, *_ in _SESSION_OPTIONS},
        )
    except AppMissingError as exc:
        raise CommandError(one_line(exc)) from None  # names the module and the app extra
    except OSError as exc:  # the port is taken, the address is not ours, ...
        raise UsageError(
            f"cannot serve on {args.host}:{args.port}: {exc.strerror or exc}"
        ) from None
    return 0


def _export(args: argparse.Namespace) -> int:
    """``--export PATH``: the view of ``--url-params`` as a PNG, written whole or not at all."""
    from hairbed.explorer import AppMissingError, _check_installed, export_png

    from ._output import check_output
    from ._report import WriteError

    if args.export is None:
        raise UsageError("--url-params needs --export PATH (the served page takes its own URL)")
    if not args.export.lower().endswith(".png"):
        raise UsageError(f"--export {args.export}: the view is written as PNG: give a .png file")
    check_output(args.export)
    try:
        _check_installed()
        export_png(args.export, args.url_params or "")
    except AppMissingError as exc:
        raise CommandError(one_line(exc)) from None
    except ValueError as exc:
        raise UsageError(f"--url-params: {one_line(exc)}") from None
    except ImportError as exc:  # matplotlib, which draws it
        raise CommandError(one_line(exc)) from None
    except OSError as exc:
        raise WriteError(args.export, exc) from None
    print(f"hairbed explore: wrote {args.export}")
    return 0


def _run_with_allocator(args: argparse.Namespace) -> None:
    """Restart this command in a fresh interpreter with ``PYTHONMALLOC=<--allocator>`` when the
    running one has another allocator (POSIX; Windows keeps the running one).

    PYTHONMALLOC is read only when the interpreter starts. With CPython's pymalloc a 1 MiB
    arena goes back to the system only when every object in it is gone, and the few that
    outlive the sessions (interned strings, caches filled on first use) pin the arenas of the
    busiest moment: measured (``benchmarks/bench_explorer.py --served``, 8 sessions x 250
    updates, the served process alone) +31 MB after the sessions closed with pymalloc, +4 MB
    with malloc (glibc's free memory trimmed when a session is discarded), at the same speed.
    """
    if os.name != "posix" or os.environ.get("PYTHONMALLOC", "pymalloc") == args.allocator:
        return
    argv = [sys.executable, "-m", "hairbed", "explore", *_argv(args)]
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(sys.executable, argv, {**os.environ, "PYTHONMALLOC": args.allocator})


def _argv(args: argparse.Namespace) -> list[str]:
    """The command line of ``hairbed explore`` that gives ``args`` (checked)."""
    out: list[str] = []
    for dest, *_ in _OPTIONS:
        out += ["--" + dest.replace("_", "-"), str(getattr(args, dest))]
    for origin in args.allow_websocket_origin or ():
        out += ["--allow-websocket-origin", origin]
    if args.no_browser:
        out.append("--no-browser")
    return out + ["--allocator", args.allocator]
