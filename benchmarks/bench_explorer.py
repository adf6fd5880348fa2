"""How live is the explorer? Server time per update, and time until the browser shows it.

1. Server time per update: an :class:`hairbed.explorer._page.ExplorerPage` in this process,
   its omega2 slider stepped across both folds of (eps, theta0) = (0.9, -1.5) (one to three
   states and back), then the same with the twirling states of every branch; each step runs
   the app's own callback: validation, every state (``solve`` for each root, ``solve_all``),
   stability of each physical state, profiles, phase curves and every Bokeh source, the table
   and the URL. Reported: median and 90th percentile of the page's own ``timings["total"]``.
   Then a pump drive (issue 20): the load slider of the flow drive across its window of three
   states at (0.9, -1.2), wall at rest (``solve_loaded_all`` per update), in the branch view
   and in the valve view (``flow_*``).
2. Until the browser shows it: ``hairbed explore`` served, Debian's Chromium (headless, no
   network) on the page; a new exact omega2 is written into the text field from within the
   page (``change`` event, as typing and Enter do) and the time is taken in the page from the
   event until the table shows the new value, plus one animation frame (the canvas of the
   figures is painted in the frame after the update). Playwright's own overhead is not in it,
   nor the search for the table through the page's shadow roots (done once, before the
   clock starts: the table's pane keeps its element and re-writes only its content).
   Also reported: when the server's document patch (the new picture) reaches the page
   (``browser_patch_*``: the served update, serialisation and the websocket; the rest is the
   browser applying and painting it), and the served page's own server time per update
   (``served_total_*``, its ``timings["total"]``, read from the page).

3. Many users at once (``--sessions N``): the explorer's own session page
   (:func:`hairbed.explorer._session_page`, as ``hairbed explore`` serves it, its clean-up
   when a session is discarded included) on a Panel/Bokeh server in this process, N Bokeh
   client sessions (``bokeh.client.pull_session``, one thread each) driving ``--updates``
   updates each at the same time: omega2 up and down across both folds of (0.9, -1.5), every
   10th update another view (twirling states on/off, the branch diagram's ordinate, eps and
   theta0), one session giving bad input (a word, a negative omega2, NaN) every 7th update.
   Each update waits until the session's page has refreshed. Checked: no error in any good
   session, every page shows its own session's inputs, the bad input only in its own session,
   and each page's downloads (JSON parsed strictly, CSV) after its last update. First one
   warm-up session (the server's one-time costs: Panel's templates, Bokeh's first documents),
   then ``--rounds`` rounds of N sessions. Reported: the pages' server time per update
   (``timings["total"]``, median and 90th percentile), the time until a session's update is
   done (queueing included), resident memory [MB] and Python's allocated blocks at the start
   (after the warm-up) and after each round's sessions are closed, discarded by the server
   and their pages collected (counted: 0 left). (Bokeh's client applies the server's patches
   only in part, so the checks read the server's page objects; the server sees only
   websocket clients, as from browsers. The clients' documents live in this process too:
   the resident memory is the server's and the clients' together.)

   ``--drive pump`` drives the flow drive instead (walls at rest, (0.9, -1.2)): its load q
   across the window of three states and back, every 10th update the valve view or the
   ordinate switched, or eps or theta0; the bad session types a word, NaN, a bad eps or
   theta0. ``--drive both`` (the default) runs the wall drive's sessions, then the pump's,
   each reported on its own. The sessions sweep the same slider values (each from another
   start), so the explorer's caches of a pump's states per input serve other sessions too;
   ``--distinct`` gives each session its own values (the caches then serve only a session's
   own way back): ``state_cache_hits`` / ``_misses`` count them.

   Memory after the sessions close: the server keeps nothing of them (every page collected,
   no session left, the shared caches emptied, Python's live heap back within ~10^4 blocks
   of the start, most of them the benchmark's closed Bokeh client connections), but the
   resident memory stays near the high-water mark of the busiest round. Measured with
   ``sys._debugmallocstats`` (8 x 60 updates): CPython's small-object heap holds 72.1 MB in
   live blocks at the start, 145.7 MB after the updates and 72.7 MB after close, but its
   arenas (1 MiB each) stay at 150 against 80 at the start: 71 MB of empty pools inside
   arenas that each keep a few live objects, so none can be unmapped. A second round of as
   many sessions reuses them instead of adding to them. The session-destroy hook collects
   and calls glibc's ``malloc_trim(0)`` (:func:`hairbed.explorer._return_freed_memory`);
   with ``PYTHONMALLOC=malloc`` (every object from the C allocator, so trimmed too) +18 /
   +26 MB remain (8 x 100, 2 rounds). Part of that is the clients' documents, which live in
   this process too: part 4 measures the served process alone.

4. The served process alone (``--served``, with ``--sessions`` (default 8), ``--updates`` and
   ``--rounds``): ``hairbed explore`` started as users start it, a process of its own, once
   with each ``--allocator`` (malloc, the default, and pymalloc), driven by Bokeh client
   sessions in this process (the wall drive's plan of part 3, session 0's bad input included;
   each update awaited until the server's patch of the page's link arrives, a bad one until
   its alert shows and goes again). Its resident memory is read from ``/proc/<pid>/status``
   after a warm-up session (the start), after each round's updates and once the closed
   sessions are discarded; the server time per update is read from the status line's
   patches. Measured (8 x 250 updates, 2 rounds): with malloc +22 / +31 MB after the updates
   and +3.9 MB after close; with pymalloc +35 MB and +31 MB (the arenas of part 3), at the
   same speed (75 s a round both, server p90 6.4 / 6.2 ms: the clients are not in its process).

5. The pillar in a snap-through window (issue 33; ``--pillar`` alone, and in part 1): new
   forcings between the folds of theta0 = -1.45, each read from the pillar's branch cached on
   the first view (``pillar_window_*``), against one ``solve_pillar_all`` (a branch per
   forcing, the way before) as a ratio.

The machine's load average (:func:`os.getloadavg`, 1 min) is reported before and after each
part: other work on the two cores slows both the server and the browser.

Targets (issue 14): <= 50 ms server time per update, <= 150 ms until the browser shows the new
picture, on this machine (2 shared cores). Issue 19, with 8 sessions: no error, p90 server time
per update <= 100 ms, resident memory after 2,000 updates within 100 MB of the start and back
near the start once the sessions are closed.

Usage::

    python benchmarks/bench_explorer.py [--steps 40] [--browser-steps 30] [--no-browser]
        [--sessions 8 --updates 250] [--served] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Callable
from typing import Any

import numpy as np

CHROMIUM = os.environ.get("HAIRBED_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--proxy-server=http://127.0.0.1:9",
]
# Records when each websocket message from the server arrives (installed before the page's
# scripts run), to tell the server's part of an update from the browser's.
_JS_INIT = """
(() => {
  window.__hb_received = [];
  const Socket = window.WebSocket;
  window.WebSocket = class extends Socket {
    constructor(...args) {
      super(...args);
      this.addEventListener('message', ev => {
        if (typeof ev.data === 'string' && ev.data.includes('"PATCH-DOC"'))
          window.__hb_received.push(performance.now());
      });
    }
  };
})();
"""
# Finds the omega2 field and the table's pane through the open shadow roots of Bokeh's
# components (before the clock starts), sets the field, waits for the table to show it
# (polling once per frame) and one frame more.
_JS_UPDATE = """
async ([value, shown]) => {
  const find = (root, sel) => {
    const hit = root.querySelector(sel);
    if (hit) return hit;
    for (const el of root.querySelectorAll('*')) {
      if (el.shadowRoot) { const r = find(el.shadowRoot, sel); if (r) return r; }
    }
    return null;
  };
  const host = find(document, '.hb-omega2');  // the widget; its input is in its shadow root
  const input = find(host.shadowRoot || host, 'input');
  const pane = find(document, '.hb-table');  // kept across updates; its content is replaced
  const table = pane.shadowRoot || pane;
  const frame = () => new Promise(r => requestAnimationFrame(r));
  window.__hb_received = [];
  const t0 = performance.now();
  input.value = value;
  input.dispatchEvent(new Event('change', {bubbles: true}));
  for (;;) {
    await frame();
    const cell = table.querySelector('table.hb-states td[data-field="omega2"]');
    if (cell && cell.textContent === shown) break;
    if (performance.now() - t0 > 20000) return null;
  }
  await frame();
  const t1 = performance.now();
  const patch = window.__hb_received.length ? window.__hb_received[0] - t0 : NaN;
  const status = find(document, '.hb-status');
  const timing = (status.shadowRoot || status).querySelector('.hb-timing');
  return [t1 - t0, patch, timing ? Number(timing.dataset.totalMs) : NaN];
}
"""


def _pct(values: list[float], q: float) -> float:
    return float(np.percentile(np.asarray(values), q))


def _load() -> float:
    return float(os.getloadavg()[0])


def server_times(steps: int) -> dict[str, float]:
    from hairbed.explorer._page import ExplorerPage

    out: dict[str, float] = {"server_load_before": _load()}
    for twirl in (False, True):
        page = ExplorerPage(f"?omega2=0.8&eps=0.9&theta0=-1.5&twirl={int(twirl)}")
        logs = np.concatenate(
            [np.linspace(math.log10(0.8), math.log10(2.0), steps // 2)] * 2
        )  # up across both folds, then again (no warm-up effects in the median)
        totals, solves, stab, counts = [], [], [], []
        for x in logs:
            page.omega2_slider.value = float(x)
            assert page.error == "", page.error
            totals.append(page.timings["total"])
            solves.append(page.timings["solve"])
            stab.append(page.timings["stability"])
            counts.append(len(page.snapshot.states))
        tag = "twirl" if twirl else "physical"
        out[f"{tag}_total_median_ms"] = statistics.median(totals)
        out[f"{tag}_total_p90_ms"] = _pct(totals, 90)
        out[f"{tag}_solve_median_ms"] = statistics.median(solves)
        out[f"{tag}_stability_median_ms"] = statistics.median(stab)
        out[f"{tag}_max_states"] = float(max(counts))
        if twirl:
            out["twirl_states_at_end"] = float(len(page.snapshot.twirling))
    # the pump drives (issue 20): the load slider across the flow drive's window of three
    # states at (eps, theta0) = (0.9, -1.2), wall at rest, in the branch and the valve view
    for view in ("branch", "valve"):
        page = ExplorerPage(f"?omega2=0&eps=0.9&theta0=-1.2&drive=flow&q=0.01&view={view}")
        logs = np.concatenate([np.linspace(-2.0, math.log10(0.3), steps // 2)] * 2)
        totals, counts = [], []
        for x in logs:
            page.load_slider.value = float(x)
            assert page.error == "", page.error
            totals.append(page.timings["total"])
            counts.append(len(page.snapshot.states))
        out[f"flow_{view}_total_median_ms"] = statistics.median(totals)
        out[f"flow_{view}_total_p90_ms"] = _pct(totals, 90)
        out[f"flow_{view}_max_states"] = float(max(counts))
    out.update(pillar_window_times(steps))
    out["server_load_after"] = _load()
    return out


def pillar_window_times(steps: int) -> dict[str, float]:
    """The pillar mode inside a snap-through window (issue 33): theta0 = -1.45, ``steps`` new
    forcings Lambda between its folds (14.83 and 22.29, three states each), every one new to
    the page, after the first view (which follows the pillar's branch, cached per pillar).
    Reported: that first update, the median and 90th percentile of the new forcings' updates
    [ms], and what one :func:`hairbed.solve_pillar_all` (the way before: a branch per
    forcing) takes at such a forcing, as a ratio to the median."""
    import hairbed
    from hairbed.explorer._page import ExplorerPage
    from hairbed.explorer._pillar import clear_pillar_caches

    clear_pillar_caches()
    hairbed.solve_pillar(1.0)  # the kernels compiled
    start = time.perf_counter()
    page = ExplorerPage("?mode=pillar&forcing=20&pillar_theta0=-1.45", served=False)
    first = page.timings["total"]
    page_ms = 1e3 * (time.perf_counter() - start)
    totals, counts = [], []
    for lam in np.linspace(15.0, 22.2, max(steps, 2)):
        page.text["forcing"].value = f"{lam:.6g}"
        assert page.error == "", page.error
        totals.append(page.timings["total"])
        counts.append(len(page.pillar.snapshot.states))
    start = time.perf_counter()
    hairbed.solve_pillar_all(18.5, -1.45)
    every = 1e3 * (time.perf_counter() - start)
    new = statistics.median(totals)
    page.release()
    return {
        "pillar_window_first_ms": first,
        "pillar_window_page_ms": page_ms,
        "pillar_window_new_median_ms": new,
        "pillar_window_new_p90_ms": _pct(totals, 90),
        "pillar_window_min_states": float(min(counts)),
        "solve_pillar_all_ms": every,
        "solve_pillar_all_over_new": every / new,
    }


def browser_times(steps: int) -> dict[str, float]:
    from playwright.sync_api import sync_playwright

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen(
        [sys.executable, "-m", "hairbed", "explore", "--port", str(port), "--no-browser"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    base = f"http://127.0.0.1:{port}/"
    try:
        deadline = time.monotonic() + 300
        while True:
            try:
                with urllib.request.urlopen(base, timeout=5):
                    break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise RuntimeError("hairbed explore did not start") from None
                time.sleep(0.5)
        with sync_playwright() as pw:
            ctx = pw.chromium.launch_persistent_context(
                tempfile.mkdtemp(prefix="hb-chromium-"),
                executable_path=CHROMIUM,
                headless=True,
                args=CHROMIUM_ARGS,
                viewport={"width": 1400, "height": 1500},
            )
            ctx.add_init_script(_JS_INIT)
            page = ctx.new_page()
            page.goto(base + "?omega2=0.8&eps=0.9&theta0=-1.5")
            page.locator("table.hb-states td[data-field='xi']").first.wait_for(timeout=120000)
            page.wait_for_timeout(1000)
            values = np.geomspace(0.8, 2.0, steps)
            times, patches, served = [], [], []
            load_before = _load()
            for k, w in enumerate(values):
                text = f"{w:.6g}"
                shown = f"{float(text):.12g}"
                if k and shown == f"{float(f'{values[k - 1]:.6g}'):.12g}":
                    continue
                res = page.evaluate(_JS_UPDATE, [text, shown])
                if res is None:
                    raise RuntimeError(f"the page did not show omega2 = {text}")
                times.append(res[0])
                patches.append(res[1])
                served.append(res[2])
            load_after = _load()
            ctx.close()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    return {
        "browser_median_ms": statistics.median(times),
        "browser_p90_ms": _pct(times, 90),
        "browser_patch_median_ms": float(np.nanmedian(patches)),
        "browser_patch_p90_ms": float(np.nanpercentile(patches, 90)),
        "served_total_median_ms": float(np.nanmedian(served)),
        "served_total_p90_ms": float(np.nanpercentile(served, 90)),
        "browser_updates": float(len(times)),
        "browser_load_before": load_before,
        "browser_load_after": load_after,
    }


def _rss_mb() -> float:
    """Resident memory of this process [MB] (Linux /proc; NaN elsewhere)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    return math.nan


#: Bad inputs of the misbehaving session, and the parameter each message must name.
BAD_INPUTS = [("omega2", "lots"), ("omega2", "-1"), ("eps", "nan"), ("theta0", "2")]
#: The same for a pump drive's session (the flow drive: its load q).
BAD_PUMP_INPUTS = [("q", "lots"), ("q", "nan"), ("eps", "nan"), ("theta0", "2")]
#: Where each drive's sessions start: the wall drive inside the window of three states of
#: (0.9, -1.5); the flow drive (walls at rest) below the window of (0.9, -1.2), which its
#: load q in [0.027, 0.15] crosses (one state, three, one).
START = {
    "wall": {"omega2": "0.8", "eps": "0.9", "theta0": "-1.5"},
    "pump": {"omega2": "0", "eps": "0.9", "theta0": "-1.2", "drive": "flow", "q": "0.01"},
}
#: The views each drive's sessions switch to and fro (a toggle each: to the other value).
TOGGLES = {"twirl": ("0", "1"), "y": ("x1", "xi"), "view": ("branch", "valve")}


def _bad_inputs(drive: str) -> list[tuple[str, str]]:
    return BAD_PUMP_INPUTS if drive == "pump" else BAD_INPUTS


def _plan(
    k: int, updates: int, bad: bool, drive: str = "wall", distinct: bool = False
) -> list[tuple[str, str]]:
    """The (field, value) updates of session ``k``: the forcing across both folds (omega2 of
    the wall drive, the load q of the flow drive), every 10th update another view (the wall
    drive's twirling states and ordinate; a pump's valve view and ordinate) or another eps
    or theta0. The sessions sweep the same values (as users on the same slider steps), each
    from another start; ``distinct``: each session's values 1e-4 k apart from the others'
    (no session meets another's inputs: the explorer's caches serve only its own sweep's
    way back)."""
    if drive == "pump":
        logs = np.linspace(-2.0, math.log10(0.3), 25)
        field, views = "q", [("view", ""), ("y", "")]
        eps0, theta0 = 0.9, "-1.2"
    else:
        logs = np.linspace(math.log10(0.5), math.log10(2.5), 25)
        field, views = "omega2", [("twirl", ""), ("y", "")]
        eps0, theta0 = 0.9, "-1.5"
    sweep = np.concatenate([logs, logs[-2:0:-1]])  # up and down, no value twice in a row
    bad_inputs = _bad_inputs(drive)
    plan: list[tuple[str, str]] = []
    for i in range(updates):
        if bad and i % 7 == 3:
            plan.append(bad_inputs[(i // 7) % len(bad_inputs)])
        elif i % 10 == 9:
            choices = [*views, ("eps", f"{eps0 - 0.001 * (k % 5):.3f}"), ("theta0", theta0)]
            plan.append(choices[(i // 10 + k) % len(choices)])
        else:
            value = 10.0 ** sweep[(i + 3 * k) % sweep.size] * (1.0 + 1e-4 * k * distinct)
            plan.append((field, f"{value:.6g}"))
    return plan


def _server_sessions(server: Any) -> int:
    """Sessions the Bokeh server still holds (closed ones until it discards them)."""
    return len(server.get_sessions())


def sessions(
    n_sessions: int = 8,
    updates: int = 250,
    timeout: float = 20.0,
    rounds: int = 2,
    drive: str = "wall",
    distinct: bool = False,
) -> dict[str, Any]:
    """Part 3 of the module docstring. Returns the figures and ``problems`` (a list of str).

    The served app is ``hairbed explore``'s own (:func:`hairbed.explorer._session_page`, its
    clean-up when a session is discarded included). First one session of a few updates
    (the server's one-time costs: Panel's templates, Bokeh's first documents), then
    ``rounds`` rounds of ``n_sessions`` sessions; resident memory is read after each round's
    sessions are closed, discarded by the server and the explorer's own clean-up has run.
    """
    import gc
    import threading
    import weakref

    import panel as pn
    from panel.io.server import get_server

    import hairbed.explorer as explorer
    from hairbed.explorer import _model

    pn.extension()
    pages: dict[str, Any] = {}  # session id -> weak reference: a discarded page can go

    def app() -> Any:  # hairbed.explorer._session, keeping a (weak) handle on the page
        page = explorer._session_page()
        pages[pn.state.curdoc.session_context.id] = weakref.ref(page)
        return page.layout

    _model.cusp_curve()
    _model.compute(_model.validate({"twirl": "1"}))  # the kernels, as `hairbed explore` does
    server = get_server(
        {"/": app},
        port=0,
        start=False,
        show=False,
        check_unused_sessions_milliseconds=500,
        unused_session_lifetime_milliseconds=1000,
    )
    server.start()
    loop = threading.Thread(target=server.io_loop.start, daemon=True)
    loop.start()
    url = f"http://127.0.0.1:{server.port}/"
    out: dict[str, Any] = {
        "drive": drive,
        "distinct": distinct,
        "sessions": n_sessions,
        "updates_per_session": updates,
    }
    problems: list[str] = []

    def settle() -> int:
        """Wait until every closed session is discarded, its page gone and the server's own
        clean-up done; the pages left."""
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and (
            any(ref() is not None for ref in pages.values()) or _server_sessions(server)
        ):
            time.sleep(0.5)
            gc.collect()
        time.sleep(1.5)
        return sum(ref() is not None for ref in pages.values())

    try:
        warm = _round(url, pages, 1, 12, timeout, drive, distinct)
        problems += [f"warm-up: {p}" for p in warm["problems"]]
        out["warmup_pages_left"] = settle()
        out["load_before"] = _load()
        out["rss_start_mb"] = _rss_mb()
        out["blocks_start"] = sys.getallocatedblocks()
        totals: list[float] = []
        waits: list[float] = []
        counts: set[int] = set()
        start = time.perf_counter()
        for r in range(1, rounds + 1):
            res = _round(url, pages, n_sessions, updates, timeout, drive, distinct)
            counts |= res["counts"]
            totals += res["totals"]
            waits += res["waits"]
            problems += [f"round {r}: {p}" for p in res["problems"]]
            out[f"round{r}_wall_s"] = res["wall_s"]
            out[f"round{r}_load_after"] = _load()
            out[f"round{r}_rss_after_updates_mb"] = res["rss_after_updates_mb"]
            out[f"round{r}_pages_left"] = settle()
            out[f"round{r}_sessions_left"] = _server_sessions(server)
            out[f"round{r}_rss_after_close_mb"] = _rss_mb()
            out[f"round{r}_blocks_after_close"] = sys.getallocatedblocks()
            if out[f"round{r}_pages_left"] or out[f"round{r}_sessions_left"]:
                problems.append(f"round {r}: pages or sessions kept after the sessions closed")
        out["wall_s"] = time.perf_counter() - start
    finally:
        server.io_loop.add_callback(server.stop)
        server.io_loop.add_callback(server.io_loop.stop)
        loop.join(10)
    out["updates"] = len(waits)
    out["state_counts"] = sorted(counts)  # 1 and 3: the folds crossed
    states_cache = getattr(_model, "_PUMP_STATES", None)  # the pump states' cache (hits)
    if states_cache is not None:
        out["state_cache_hits"] = states_cache.hits
        out["state_cache_misses"] = states_cache.misses
    out["server_median_ms"] = statistics.median(totals) if totals else math.nan
    out["server_p90_ms"] = _pct(totals, 90) if totals else math.nan
    out["wait_median_ms"] = statistics.median(waits) if waits else math.nan
    out["wait_p90_ms"] = _pct(waits, 90) if waits else math.nan
    out["problems"] = problems
    return out


def _round(url: str, pages: dict[str, Any], n_sessions: int, updates: int,
           timeout: float, drive: str = "wall", distinct: bool = False
           ) -> dict[str, Any]:  # fmt: skip
    """``n_sessions`` client sessions at once, ``updates`` each (session 0 gives bad input
    too), then closed: the pages' server times, the waits, problems and the memory."""
    import gc
    import threading

    from bokeh.client import pull_session

    problems: list[str] = []
    totals: list[float] = []
    waits: list[float] = []
    counts: set[int] = set()
    bad_inputs = _bad_inputs(drive)
    lock = threading.Lock()
    barrier = threading.Barrier(n_sessions)
    opened: list[Any] = []

    def run_session(k: int) -> None:
        bad = k == 0
        session = pull_session(url=url, arguments=START[drive])
        with lock:
            opened.append(session)
        page = pages[session.id]()  # made for this session, in the server's thread
        by_class = {
            c: m
            for m in session.document.select({})
            for c in (getattr(m, "css_classes", None) or [])
        }
        barrier.wait()

        def update(i: int, field: str, value: str) -> None:
            """Set one input from the client; wait until this session's page has refreshed."""
            timings, snapshot = page.timings, page.snapshot
            start = time.perf_counter()
            if field == "twirl":
                box = by_class["hb-twirl-toggle"]  # a Checkbox, or Panel's CheckboxGroup
                on = value == "1"
                box.active = ([0] if on else []) if isinstance(box.active, list) else on
            elif field == "y":
                by_class["hb-y"].active = 0 if value == "x1" else 1
            elif field == "view":
                by_class["hb-view"].active = 0 if value == "branch" else 1
            else:
                by_class[f"hb-{field}"].value = value
            is_bad = (field, value) in bad_inputs
            while page.timings is timings and page.snapshot is snapshot:
                if is_bad and page.error:
                    break
                if time.perf_counter() - start > timeout:
                    problems.append(f"session {k} update {i} ({field}={value}): no refresh")
                    break
                session.force_roundtrip()
                time.sleep(0.002)
            with lock:
                waits.append(1e3 * (time.perf_counter() - start))
            if is_bad:
                if field not in page.error:
                    problems.append(f"session {k}: bad {field}={value!r} not reported")
                return
            if page.error:
                problems.append(f"session {k} update {i} ({field}={value}): {page.error}")
                return
            with lock:
                totals.append(page.timings["total"])
                counts.add(len(page.snapshot.states))
            raw = page.snapshot.params.raw
            if raw[field] != value:
                problems.append(f"session {k}: shows {field}={raw[field]}, was given {value}")

        for i, (field, value) in enumerate(_plan(k, updates, bad, drive, distinct)):
            current = page.snapshot.params.raw
            if field in TOGGLES:  # a view switch: always to the other view
                a, b = TOGGLES[field]
                value = b if current[field] == a else a
            elif value == current[field] and (field, value) not in bad_inputs:
                # the same value again (the sweep's turning point next to a view switch)
                # would be no change at all: a neighbouring value instead
                theta0 = START[drive]["theta0"]
                near = f"{float(theta0) + 0.05:.6g}"
                value = {"eps": "0.895", "theta0": near}.get(field, f"{1.01 * float(value):.6g}")
                if value == current[field]:
                    value = {"eps": "0.9", "theta0": theta0}.get(field, value)
            update(i, field, value)
            if (field, value) in bad_inputs:  # the field back to its last good value
                update(i, field, current[field])
        # the downloads of the last view: strict JSON (no NaN), a CSV with a header
        try:
            json.loads(page._json_file().getvalue(), parse_constant=_no_constant)
            if not page._csv_file().getvalue().splitlines()[0]:
                problems.append(f"session {k}: empty CSV download")
        except Exception as exc:
            problems.append(f"session {k}: download failed: {type(exc).__name__}: {exc}")

    def guarded(k: int) -> None:
        try:
            run_session(k)
        except Exception as exc:  # a failure of the driver itself: reported, never silent
            barrier.abort()
            problems.append(f"session {k}: {type(exc).__name__}: {exc}")

    threads = [threading.Thread(target=guarded, args=(k,)) for k in range(n_sessions)]
    start = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.perf_counter() - start
    gc.collect()
    rss = _rss_mb()
    for session in opened:
        session.close()
        # the client's own event loop (one per pull_session, not closed by Bokeh): the
        # driver's, not the server's, memory
        session._connection._loop.close(all_fds=True)
    opened.clear()
    return {
        "totals": totals,
        "waits": waits,
        "counts": counts,
        "problems": problems,
        "wall_s": wall,
        "rss_after_updates_mb": rss,
    }


def _process_rss_mb(pid: int) -> float:
    """Resident memory [MB] of process ``pid`` (Linux /proc)."""
    with open(f"/proc/{pid}/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return float(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for process {pid}")


def served(
    n_sessions: int = 8, updates: int = 200, rounds: int = 2, allocator: str = "malloc"
) -> dict[str, Any]:
    """Part 4 (``--served``): the resident memory of ``hairbed explore`` itself, a process
    of its own as users run it (``--allocator``), while ``n_sessions`` Bokeh client sessions
    in this process drive it: the wall drive's plan of part 3 (omega2 across both folds,
    every 10th update the twirling states or the ordinate, session 0's bad input every 7th).
    Each update waits until the client's copy of the page's status line changes; the
    server time per update is read from it, and a bad input must show the alert (a good one
    must not). Memory: after one warm-up session (the start), after each round's updates, and
    once its sessions are closed and discarded (the served process's memory steady)."""
    import threading

    import panel  # noqa: F401  (the client resolves Panel's models)
    from bokeh.client import pull_session

    import hairbed.explorer._page  # noqa: F401  (and the explorer's own)

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    command = [
        sys.executable, "-m", "hairbed", "explore", "--port", str(port), "--no-browser",
        "--check-unused-sessions", "500", "--unused-session-lifetime", "1000",
        "--allocator", allocator,
    ]  # fmt: skip
    proc = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}/"
    out: dict[str, Any] = {"allocator": allocator, "sessions": n_sessions, "updates": updates}
    problems: list[str] = []
    totals: list[float] = []
    lock = threading.Lock()

    def run(k: int, n: int) -> None:
        session = pull_session(url=url, arguments=START["wall"])
        try:
            by = {
                c: m
                for m in session.document.select({})
                for c in (getattr(m, "css_classes", None) or [])
            }
            # what the server sends, read off each message (Bokeh's client drops the patches
            # that arrive while it waits for a reply): the link changes with every good update
            # (it holds every input), the status line carries the server time, the alert
            # shows a bad input
            link, status, alert = (by[c].id for c in ("hb-link", "hb-status", "hb-error"))
            seen: dict[str, Any] = {"links": 0, "alert": False}
            connection = session._connection
            pop = connection._pop_message

            async def watched() -> Any:
                message = await pop()
                if message is not None and message.msgtype == "PATCH-DOC":
                    for ev in message.content.get("events", []):
                        model, attr = (ev.get("model") or {}).get("id"), ev.get("attr")
                        if model == link and attr == "text":
                            seen["links"] += 1
                        elif model == alert and attr == "visible":
                            seen["alert"] = bool(ev["new"])
                        elif model == status and "data-total-ms=&quot;" in str(ev.get("new")):
                            ms = str(ev["new"]).split("data-total-ms=&quot;")[1]
                            with lock:
                                totals.append(float(ms.split("&quot;")[0]))
                return message

            connection._pop_message = watched

            def wait(i: int, field: str, value: str, done: Callable[[], bool]) -> None:
                deadline = time.monotonic() + 60
                while not done():
                    if time.monotonic() > deadline:
                        problems.append(f"session {k} update {i} ({field}={value}): no refresh")
                        return
                    session.force_roundtrip()
                    time.sleep(0.002)

            twirl, y, current = False, 0, dict(START["wall"])
            for i, (field, value) in enumerate(_plan(k, n, k == 0)):
                before = seen["links"]
                if field == "twirl":  # a view switch: always to the other view
                    twirl = not twirl
                    box = by["hb-twirl-toggle"]
                    box.active = ([0] if twirl else []) if isinstance(box.active, list) else twirl
                elif field == "y":
                    y = 1 - y
                    by["hb-y"].active = y
                else:
                    if (field, value) not in BAD_INPUTS:
                        if float(value) == float(current[field]):  # no change: a neighbour
                            value = {"eps": "0.895", "theta0": "-1.45"}.get(
                                field, f"{1.01 * float(value):.6g}"
                            )
                        current[field] = value
                    by[f"hb-{field}"].value = value
                if (field, value) not in BAD_INPUTS:
                    wait(i, field, value, lambda n=before: seen["links"] != n)
                    if seen["alert"]:
                        problems.append(f"session {k} update {i} ({field}={value}): an alert")
                    continue
                wait(i, field, value, lambda: seen["alert"])
                by[f"hb-{field}"].value = current[field]  # back to a good value
                wait(i, field, current[field], lambda: not seen["alert"])
        finally:
            session.close()
            session._connection._loop.close(all_fds=True)

    def round_(n_sess: int, n: int) -> float:
        threads = [threading.Thread(target=run, args=(k, n)) for k in range(n_sess)]
        t0 = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        return time.perf_counter() - t0

    def steady() -> float:
        """The served process's memory once it stopped falling (sessions discarded)."""
        time.sleep(3.0)
        last = _process_rss_mb(proc.pid)
        for _ in range(30):
            time.sleep(1.0)
            now = _process_rss_mb(proc.pid)
            if abs(now - last) < 0.5:
                return now
            last = now
        return last

    try:
        deadline = time.monotonic() + 300
        while True:
            try:
                with urllib.request.urlopen(url, timeout=5):
                    break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    raise RuntimeError("hairbed explore did not start") from None
                time.sleep(0.5)
        with open(f"/proc/{proc.pid}/environ", "rb") as fh:
            env = dict(v.split(b"=", 1) for v in fh.read().split(b"\0") if b"=" in v)
        out["served_pythonmalloc"] = env.get(b"PYTHONMALLOC", b"").decode()
        round_(1, 12)
        out["rss_start_mb"] = steady()
        for r in range(1, rounds + 1):
            out[f"round{r}_wall_s"] = round_(n_sessions, updates)
            out[f"round{r}_rss_after_updates_mb"] = _process_rss_mb(proc.pid)
            out[f"round{r}_rss_after_close_mb"] = steady()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    out["server_median_ms"] = statistics.median(totals) if totals else math.nan
    out["server_p90_ms"] = _pct(totals, 90) if totals else math.nan
    out["problems"] = problems
    return out


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} in a JSON download")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=40, help="slider steps per run (default 40)")
    ap.add_argument("--browser-steps", type=int, default=30, help="browser updates (default 30)")
    ap.add_argument("--no-browser", action="store_true", help="server times only")
    ap.add_argument(
        "--pillar", action="store_true", help="the pillar's snap-through window rows only"
    )
    ap.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    ap.add_argument("--sessions", type=int, default=0, help="part 3 only: N client sessions")
    ap.add_argument("--updates", type=int, default=250, help="updates per session (part 3)")
    ap.add_argument("--rounds", type=int, default=2, help="rounds of N sessions (part 3)")
    ap.add_argument(
        "--drive",
        choices=("wall", "pump", "both"),
        default="both",
        help="part 3: the wall drive's sessions, the flow drive's (a pump), or both in turn",
    )
    ap.add_argument(
        "--distinct",
        action="store_true",
        help="part 3: no two sessions at the same inputs (each its own values)",
    )
    ap.add_argument(
        "--served",
        action="store_true",
        help="part 4: the memory of a served `hairbed explore` (its own process) under "
        "--sessions N (default 8) x --updates, with each --allocator",
    )
    args = ap.parse_args(argv)
    if args.served:
        results, failed = {}, False
        for allocator in ("malloc", "pymalloc"):
            res = served(args.sessions or 8, args.updates, args.rounds, allocator)
            results[allocator] = res
            print(f"-- served, --allocator {allocator}")
            for k, v in res.items():
                print(f"{k:32s} {v}" if not isinstance(v, float) else f"{k:32s} {v:10.2f}")
            start = res["rss_start_mb"]
            closed = res[f"round{args.rounds}_rss_after_close_mb"] - start
            print(
                f"targets: after updates +{res['round1_rss_after_updates_mb'] - start:.1f} MB "
                f"(<= 100), after close +{closed:.1f} MB (near 0), "
                f"p90 server {res['server_p90_ms']:.1f} ms, "
                f"{len(res['problems'])} problems (0)"
            )
            failed = failed or bool(res["problems"])
        if args.json:
            with open(args.json, "w") as fh:
                json.dump(results, fh, indent=2)
        return 1 if failed else 0
    if args.sessions:
        drives = ["wall", "pump"] if args.drive == "both" else [args.drive]
        results, failed = {}, False
        for drive in drives:
            many = sessions(
                args.sessions, args.updates, rounds=args.rounds, drive=drive,
                distinct=args.distinct,
            )  # fmt: skip
            results[drive] = many
            print(f"-- {drive} drive, {args.sessions} sessions x {args.updates} updates")
            for k, v in many.items():
                print(f"{k:32s} {v}" if not isinstance(v, float) else f"{k:32s} {v:10.2f}")
            failed = failed or bool(many["problems"])
        for drive, many in results.items():
            start, last = many["rss_start_mb"], args.rounds
            print(
                f"targets ({drive} drive): p90 server {many['server_p90_ms']:.1f} ms (<= 100), "
                f"memory after updates +{many['round1_rss_after_updates_mb'] - start:.1f} MB "
                f"(<= 100), after close +{many['round1_rss_after_close_mb'] - start:.1f} MB "
                f"(round 1), +{many[f'round{last}_rss_after_close_mb'] - start:.1f} MB "
                f"(round {last}), {len(many['problems'])} problems (0)"
            )
        if args.json:
            with open(args.json, "w") as fh:
                json.dump(results, fh, indent=2)
        return 1 if failed else 0
    res = pillar_window_times(args.steps) if args.pillar else server_times(args.steps)
    if not args.no_browser and not args.pillar:
        res.update(browser_times(args.browser_steps))
    for k, v in res.items():
        print(f"{k:32s} {v:10.2f}")
    if "physical_total_median_ms" in res:
        print(f"server target <= 50 ms: median {res['physical_total_median_ms']:.1f} ms")
    if "pillar_window_new_median_ms" in res:
        median, p90 = res["pillar_window_new_median_ms"], res["pillar_window_new_p90_ms"]
        print(
            f"pillar window target <= 100 ms per new Lambda: median {median:.1f} ms, "
            f"p90 {p90:.1f} ms ({res['solve_pillar_all_over_new']:.0f}x less than a "
            "solve_pillar_all)"
        )
    if "browser_median_ms" in res:
        print(f"browser target <= 150 ms: median {res['browser_median_ms']:.1f} ms")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
