"""The interactive explorer: move the flow in a browser and watch every state of the hair.

``hairbed explore`` serves it on the loopback interface; :func:`explore` returns the same page
for a Jupyter notebook. It needs the ``app`` extra (Panel and Bokeh):
``pip install 'hairbed[app]'``. Importing this package imports neither; the functions do.

The page solves every coexisting physical state (:func:`hairbed.solve`, every root) and on
request every twirling state (:func:`hairbed.solve_all`) on each change of an input, classifies
the physical states with :func:`hairbed.stability.linear_stability`, and shows them in the
channel to scale, on the branch diagram (:mod:`hairbed.branches`), on the map of the cusp and in
the phase plane, with a table of every :class:`hairbed.Solution` field. The inputs live in the
page's URL, and the browser's Back and Forward show the view of the URL they go to
(:mod:`._history`); the current state downloads as JSON and CSV (with units) and the hair's
shape as CSV.

A drive selector switches to a pump-driven channel (theory.md §11): a set pressure gradient or
flow rate, its load pi or q beside omega^2, every state by :func:`hairbed.solve_loaded_all`
(and :meth:`hairbed.HairBed.deform` in SI units); the valve view shows the bed as a valve
(:mod:`hairbed.valve`: flow against pressure drop, resistance, diodicity). In SI units a
bed-model selector (URL ``model=porous`` and ``drag=crossover|sparse|array``, named only for a
porous bed) takes every state from ``HairBed(..., model="porous")`` (theory.md §13), shows its
kappa and Brinkman length, and says in the page's alert what a porous bed does not support.

A mode selector switches to one isolated pillar in a wall shear layer (theory.md §12,
:mod:`._pillar`): its state by :func:`hairbed.solve_pillar` (every coexisting state, where a
snap-through window can exist, read from its branch, :func:`hairbed.continue_pillar`, cached
per pillar) drawn in the
undisturbed profile u(z), and its calibration curve, the tip deflection against the forcing
Lambda against the linear formula, with where that formula is 1 % and 10 % off.

:func:`export_png` (``hairbed explore --export``, and the page's "download PNG" button) writes
a view as a PNG without a browser: matplotlib draws the page's own Bokeh figures from the data
they hold (:mod:`._export`).
"""

from __future__ import annotations

import signal
import sys
import threading
import webbrowser
from collections.abc import Sequence
from typing import Any

from .._optional import extra_of, install_hint

__all__ = ["AppMissingError", "explore", "export_png", "serve"]


class AppMissingError(ImportError):
    """Panel or Bokeh is not installed (the ``app`` extra)."""


def _missing(package: str) -> AppMissingError:
    return AppMissingError(
        f"the explorer needs {package}, which is not installed: {install_hint(package)}"
    )


def _check_installed() -> None:
    """Raise :class:`AppMissingError` if Panel or Bokeh is not installed, without importing
    them (``hairbed explore`` asks before it restarts itself)."""
    import importlib.util

    for package in ("panel", "bokeh"):
        if importlib.util.find_spec(package) is None:
            raise _missing(package)


def _page_module() -> Any:
    try:
        from . import _page
    except ModuleNotFoundError as exc:
        if extra_of(exc) == "app":
            raise _missing((exc.name or "").split(".")[0]) from None
        raise
    return _page


def explore(query: str = "") -> Any:
    """The explorer as a Panel object, e.g. to show in a Jupyter notebook.

    Parameters
    ----------
    query : str, optional
        Inputs as a URL query string, e.g. ``"?omega2=1.2&eps=0.9&theta0=-1.5"``.

    Returns
    -------
    panel.layout.Column
        The page (display it as the last expression of a cell, or ``.servable()``).

    Raises
    ------
    AppMissingError
        If Panel is not installed (``pip install 'hairbed[app]'``).
    """
    page = _page_module()
    import panel as pn

    pn.extension()
    return page.ExplorerPage(query).layout


def export_png(path: Any, query: str = "") -> Any:
    """Write the explorer's view of ``query`` as a PNG, without a browser.

    The page is made as ``hairbed explore`` makes it for a link with this query, and its
    figures (those of the view: the bed's four, or the pillar's) are drawn by matplotlib from
    the data the page sends to the browser, with the view's link and the page's messages
    above them: the picture the page's "download PNG" button gives. The file is written whole
    or not at all (:mod:`hairbed.safe_files`).

    Parameters
    ----------
    path : str or os.PathLike
        The PNG file to write (its name ends in .png).
    query : str, optional
        The view's inputs as a URL query string (``"?omega2=1.2&eps=0.9&theta0=-1.5"``, or a
        whole link to the explorer); empty: the page at first sight.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        If the query names an unknown parameter or gives a bad value (the library's message
        for each): a script's view must be the one it asks for; if ``path`` is not a .png.
    TypeError
        If ``path`` or ``query`` is not text.
    OSError
        If the file cannot be written (nothing is written then).
    AppMissingError
        If Panel or Bokeh is not installed (``pip install 'hairbed[app]'``).
    ImportError
        If matplotlib is not installed (``pip install 'hairbed[plot]'``).

    Examples
    --------
    >>> from hairbed.explorer import export_png
    >>> export_png("view.png", "?omega2=1.2&eps=0.9&theta0=-1.5")  # doctest: +SKIP
    PosixPath('view.png')
    """
    import os
    from pathlib import Path

    from ..safe_files import write_bytes

    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike (a .png file), got {path!r}")
    if not str(os.fspath(path)).lower().endswith(".png"):
        raise ValueError(f"path must name a .png file (the view is written as PNG), got {path!r}")
    if not isinstance(query, str):
        raise TypeError(f"query must be a str (a link's query: '?omega2=2'), got {query!r}")
    query = query.split("?", 1)[1] if "?" in query else query
    page_module = _page_module()
    from ._export import render_png
    from ._model import INPUT_KEYS, inputs_from_query

    unknown = sorted(set(inputs_from_query(query)) - set(INPUT_KEYS))
    if unknown:
        raise ValueError(
            f"unknown URL parameter{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(repr(k) for k in unknown)}; known: {', '.join(INPUT_KEYS)}"
        )
    page = page_module.ExplorerPage(query, served=False)
    if page.errors:
        raise ValueError("; ".join(page.errors))
    data = render_png(page)
    page.release()
    write_bytes(path, data)
    return Path(path)


#: Served sessions whose page was made and not yet discarded (:func:`_on_destroyed`).
_open_sessions = 0
_sessions_lock = threading.Lock()


def _session_page() -> Any:
    """One browser session's page (an :class:`~._page.ExplorerPage`), started from the inputs
    in its URL; released when the server discards the session (:func:`_on_destroyed`)."""
    global _open_sessions
    import weakref

    import panel as pn

    page_module = _page_module()
    args = pn.state.session_args or {}
    from urllib.parse import urlencode

    query = urlencode(
        [(k, v.decode("utf-8", "replace")) for k, vs in args.items() for v in vs], doseq=False
    )
    page = page_module.ExplorerPage(query)
    doc = pn.state.curdoc
    if doc is not None and doc.session_context is not None:
        ref = weakref.ref(page)  # the document's callback must not keep the page alive
        with _sessions_lock:
            _open_sessions += 1
        doc.on_session_destroyed(lambda _context: _on_destroyed(ref))
    return page


def _session() -> Any:
    """One browser session's page, as ``hairbed explore`` serves it (its Panel layout)."""
    return _session_page().layout


def _on_destroyed(ref: Any) -> None:
    """A session was discarded: its page drops what it holds (its snapshot, the data last sent
    to each figure), even if something outside the session's document still refers to it;
    once no session is left, the caches the sessions shared (states per input, branch and
    valve curves: :func:`._model.clear_caches`) are emptied too. Then, once the server has let
    go of the session's document, the memory freed goes back to the operating system
    (:func:`_return_freed_memory`)."""
    global _open_sessions
    page = ref()
    if page is not None:
        page.release()
    del page
    with _sessions_lock:
        _open_sessions = max(_open_sessions - 1, 0)
        last = _open_sessions == 0
    if last:
        from ._model import clear_caches
        from ._pillar import clear_pillar_caches

        clear_caches()
        clear_pillar_caches()
    try:
        from tornado.ioloop import IOLoop

        IOLoop.current().add_callback(_return_freed_memory)  # after the document is dropped
    except Exception:  # no event loop (called directly): now
        _return_freed_memory()


def _malloc_trim() -> Any:
    """glibc's ``malloc_trim`` through ctypes, or None where the C library has none (musl,
    macOS, Windows)."""
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        trim = libc.malloc_trim
    except (OSError, AttributeError):
        return None
    trim.argtypes = [ctypes.c_size_t]
    trim.restype = ctypes.c_int
    return trim


def _return_freed_memory() -> int:
    """Collect the cycles a closed session left, then hand the C allocator's free pages back
    to the operating system (glibc ``malloc_trim(0)``; nothing where the C library lacks it).

    Without it the server's resident memory stays at the high-water mark of its busiest
    moment after the sessions close (the heap itself is back at the start). Returns 1 if
    memory was released, 0 if not, -1 where ``malloc_trim`` is not available.
    """
    import gc

    gc.collect()
    trim = _malloc_trim()
    return -1 if trim is None else int(trim(0))


def serve(
    port: int = 5006,
    host: str = "127.0.0.1",
    *,
    show: bool = True,
    allow_websocket_origin: Sequence[str] = (),
    session_token_expiration: int = 300,
    check_unused_sessions: int = 17000,
    unused_session_lifetime: int = 15000,
    log: Any = None,
) -> None:
    """Serve the explorer until interrupted (Ctrl-C: KeyboardInterrupt once the server stopped).

    Every asset (Bokeh's and Panel's JavaScript and CSS) is served by this server itself: the
    page makes no request to any other host.

    Parameters
    ----------
    port : int
        TCP port (0: any free port).
    host : str
        Address to listen on; the loopback interface by default. Another address exposes the
        explorer to the network: only when asked.
    show : bool
        Open the page in the default web browser.
    allow_websocket_origin : sequence of str
        Extra ``host[:port]`` origins allowed to open the session's websocket (behind a proxy);
        the served address itself (and localhost for the loopback) is always allowed.
    session_token_expiration : int
        Seconds a session token stays valid before the page connects.
    check_unused_sessions, unused_session_lifetime : int
        How often [ms] to look for, and after how long [ms] to discard, sessions whose page was
        closed. An open session holds some 4 to 5 MB of server memory (measured with
        ``benchmarks/bench_explorer.py --served``: 8 sessions of 250 updates added 22 to
        35 MB to the served process). Once the sessions are discarded, their objects are
        collected, the caches they shared are emptied and the C allocator's free memory is
        handed back to the system (``malloc_trim`` where glibc has it). How much of it the
        process returns depends on the allocator, fixed when the interpreter starts:
        with ``PYTHONMALLOC=malloc`` the resident memory is back within ~4 MB of the start;
        with CPython's default pymalloc some 31 MB stay (the 1 MiB arenas of the busiest
        moment, each kept mapped by a few objects that outlive the sessions; a later round
        reuses them). ``hairbed explore`` restarts itself with ``PYTHONMALLOC=malloc``
        (``--allocator``); this function serves in the running interpreter as it is.
    log : file, optional
        Where to print the address (default stdout).
    """
    _page_module()
    import panel as pn

    from ._model import compute, cusp_curve, validate

    out = sys.stdout if log is None else log
    pn.extension()
    if port == 0:
        port = _free_port(host)
    server = pn.serve(
        {"/": _session},
        port=port,
        address=host,
        websocket_origin=_origins(host, port, allow_websocket_origin),
        show=False,
        start=False,
        title="hairbed explorer",
        session_token_expiration=session_token_expiration,
        check_unused_sessions_milliseconds=check_unused_sessions,
        unused_session_lifetime_milliseconds=unused_session_lifetime,
    )
    # bound (a taken port has failed above): now the slow part, before the first page
    print("hairbed explore: preparing (kernels, the cusp curve) ...", file=out, flush=True)
    cusp_curve()
    compute(validate({"twirl": "1"}))  # load the compiled kernels
    from ._pillar import compute_pillar, validate_pillar

    compute_pillar(validate_pillar({"mode": "pillar"}))  # and the pillar's
    server.io_loop.asyncio_loop.set_exception_handler(_closed_socket_handler)
    server.start()
    actual = server.port
    url = f"http://{_url_host(host)}:{actual}/"
    print(f"hairbed explore: serving {url} (Ctrl-C to stop)", file=out, flush=True)
    if show:
        server.io_loop.add_callback(webbrowser.open, url)
    interrupted = []

    def on_sigint(*_: Any) -> None:  # Panel's own handler stops quietly: ours says so
        interrupted.append(True)
        server.io_loop.asyncio_loop.call_soon_threadsafe(server.io_loop.stop)

    previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        server.io_loop.start()
    finally:
        signal.signal(signal.SIGINT, previous)
        server.stop()
    if interrupted:
        raise KeyboardInterrupt


def _closed_socket_handler(loop: Any, context: dict[str, Any]) -> None:
    """The event loop's handler of an exception no task retrieved: a message written to a
    browser tab that has just closed (tornado's WebSocketClosedError, as the drive view's
    animation frames meet a closing tab) is expected and said nowhere; anything else goes to
    the loop's default handler (the server's log)."""
    from tornado.iostream import StreamClosedError
    from tornado.websocket import WebSocketClosedError

    if isinstance(context.get("exception"), (WebSocketClosedError, StreamClosedError)):
        return
    loop.default_exception_handler(context)


def _url_host(host: str) -> str:
    return f"[{host}]" if ":" in host else host


def _free_port(host: str) -> int:
    import socket

    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])


def _origins(host: str, port: int, extra: Sequence[str]) -> list[str]:
    """The websocket origins allowed: the served address (and localhost for the loopback)."""
    base = [f"{_url_host(host)}:{port}"]
    if host in ("127.0.0.1", "::1", "localhost"):
        base += [f"localhost:{port}", f"127.0.0.1:{port}"]
    return list(dict.fromkeys([*base, *extra]))
