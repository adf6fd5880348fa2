"""``hairbed explore``: the interactive explorer, served to a web browser."""

from __future__ import annotations

import argparse
from typing import Any

from ._options import add_command
from ._report import CommandError, UsageError, one_line

__all__ = ["add_parser", "run"]

#: Options of the server's session bookkeeping: (dest, default, metavar, help); each >= 1.
_SESSION_OPTIONS = (
    ("session_token_expiration", 300, "S",
     "seconds a page has to connect to its session (default 300)"),
    ("check_unused_sessions", 17000, "MS",
     "how often to look for closed sessions [ms] (default 17000)"),
    ("unused_session_lifetime", 15000, "MS",
     "discard a closed session's state after this long [ms] (default 15000)"),
)  # fmt: skip


def add_parser(sub: Any) -> None:
    """The ``explore`` subcommand's parser."""
    p = add_command(
        sub,
        "explore",
        run,
        help="the interactive explorer in a web browser",
        description="Serve the interactive explorer (needs the app extra: pip install "
        "'hairbed[app]'): sliders and exact entry of omega2, eps and theta0 or of a bed in SI "
        "units; every coexisting state in the channel, the branch diagram, the bistability map, "
        "the phase portrait and a table; the inputs in the page's URL; JSON and CSV downloads. "
        "Listens on the loopback interface unless --host says otherwise. Each browser session "
        "holds about 1 MB of server memory until it is discarded, --unused-session-lifetime "
        "after its page was closed.",
        examples="examples:\n  hairbed explore\n  hairbed explore --port 8000 --no-browser\n"
        "  hairbed explore --host 0.0.0.0 --port 8000 --allow-websocket-origin example.org",
    )
    p.add_argument("--port", type=int, default=5006, help="TCP port (default 5006; 0: any free)")
    p.add_argument(
        "--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1, loopback)"
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a web browser")
    p.add_argument(
        "--allow-websocket-origin",
        action="append",
        metavar="HOST[:PORT]",
        help="also accept pages served as HOST[:PORT] (behind a proxy); repeatable",
    )
    for dest, default, metavar, text in _SESSION_OPTIONS:
        option = "--" + dest.replace("_", "-")
        p.add_argument(option, type=int, default=default, metavar=metavar, help=text)


def run(args: argparse.Namespace) -> int:
    """Check the options, then serve until interrupted."""
    from hairbed.explorer import AppMissingError, serve

    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port must be in [0, 65535], got {args.port}")
    for dest, *_ in _SESSION_OPTIONS:
        if getattr(args, dest) < 1:
            option = "--" + dest.replace("_", "-")
            raise UsageError(f"{option} must be >= 1, got {getattr(args, dest)}")
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
