"""How live is the explorer? Server time per update, and time until the browser shows it.

1. Server time per update: an :class:`hairbed.explorer._page.ExplorerPage` in this process,
   its omega2 slider stepped across both folds of (eps, theta0) = (0.9, -1.5) (one to three
   states and back), then the same with the twirling states of every branch; each step runs
   the app's own callback: validation, every state (``solve`` for each root, ``solve_all``),
   stability of each physical state, profiles, phase curves and every Bokeh source, the table
   and the URL. Reported: median and 90th percentile of the page's own ``timings["total"]``.
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

The machine's load average (:func:`os.getloadavg`, 1 min) is reported before and after each
part: other work on the two cores slows both the server and the browser.

Targets (issue 14): <= 50 ms server time per update, <= 150 ms until the browser shows the new
picture, on this machine (2 shared cores).

Usage::

    python benchmarks/bench_explorer.py [--steps 40] [--browser-steps 30] [--no-browser]
        [--json out.json]
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
    out["server_load_after"] = _load()
    return out


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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=40, help="slider steps per run (default 40)")
    ap.add_argument("--browser-steps", type=int, default=30, help="browser updates (default 30)")
    ap.add_argument("--no-browser", action="store_true", help="server times only")
    ap.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    args = ap.parse_args(argv)
    res = server_times(args.steps)
    if not args.no_browser:
        res.update(browser_times(args.browser_steps))
    for k, v in res.items():
        print(f"{k:32s} {v:10.2f}")
    if "physical_total_median_ms" in res:
        print(f"server target <= 50 ms: median {res['physical_total_median_ms']:.1f} ms")
    if "browser_median_ms" in res:
        print(f"browser target <= 150 ms: median {res['browser_median_ms']:.1f} ms")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
