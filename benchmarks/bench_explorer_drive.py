"""The explorer's drive view (issue 31): the server's time per animation frame.

Target: at most 30 ms of server time per frame for one session, and 8 sessions animating at
once without an error (their p90 stated).

A frame is the periodic callback of a served page (``PillarPanel.next_frame``, every
``FRAME_MS``): the precomputed shape of the next frame of the period set on the figure's
data source, the document's change events held and flushed (serialised for the browser's
websocket) inside it. The page times each frame itself and shows the median and p90 of the
last 240 in its readout; this benchmark reads them from there.

1. In process, no server (``ExplorerPage(served=False)``): ``next_frame`` called
   ``--frames`` times, the model's update alone [ms] (no document to flush).
2. Served: ``hairbed explore`` in a subprocess, Debian's Chromium headless (the browser tests'
   flags: no sandbox, no GPU, no background networking, a dead proxy, a fresh profile;
   Playwright launches it by its path, never ``playwright install``). One session in the
   drive view for ``--seconds``: its median and p90 per frame; then 8 sessions at once (8
   pages, each its own session, all animating) for ``--seconds``: each one's p90, the
   largest, whether any page showed an error, and whether the server wrote a traceback.

The update that computes a new animation (the nonlinear run to the periodic state, the Bode
view; hundreds of ms to seconds) happens once per change of an input, not per frame; its
time is row 3.

Each row is measured for both views beside the animation (``--side-views``): the pillar's
Bode view, and the Lissajous view of a bed in a rheometer, whose frame also moves the bed's
point on its two Lissajous curves (the figures' keys prefixed ``lissajous_``).

Run: ``python benchmarks/bench_explorer_drive.py [--seconds S] [--json PATH]``. Needs the
``app`` extra and /usr/bin/chromium (``HAIRBED_CHROMIUM`` names another).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["main", "run"]

QUERY = "?mode=pillar&pillar_view=drive&forcing=8&pillar_theta0=0.3&amplitude=1&frequency=3&mu=1"
#: The views beside the animation and their queries.
QUERIES = {"bode": QUERY, "lissajous": QUERY + "&side_view=lissajous&bed_kappa=1&bed_eps=0.5"}
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


def _readout(page: Any) -> dict[str, str]:
    """The drive view's readout (Playwright's locators see into Panel's shadow roots)."""
    return dict(
        page.locator("table.hb-drive-table td[data-field]").evaluate_all(
            "els => els.map(e => [e.dataset.field, e.textContent])"
        )
    )


def _error(page: Any) -> str:
    alert = page.locator(".hb-error")
    return (alert.text_content() or "") if alert.is_visible() else ""


def in_process(frames: int, query: str = QUERY) -> dict[str, float]:
    """Row 1 and row 3: ``next_frame`` without a server, and the update's time."""
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage(query, served=False)  # the kernels compiled (or loaded) here
    page.text["amplitude"].value = "0.9"  # a new animation: the update's own time
    if page.errors:
        raise RuntimeError(str(page.errors))
    update = float(page.timings["total"])
    panel = page.pillar
    for k in range(frames):
        panel.next_frame(k + 1)
    ms = np.asarray(panel.frame_ms)
    page.release()
    return {
        "frame_p50_ms": float(np.percentile(ms, 50)),
        "frame_p90_ms": float(np.percentile(ms, 90)),
        "update_ms": update,
    }


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _wait_served(base: str, proc: Any, err: Path) -> None:
    deadline = time.monotonic() + 600.0
    while True:
        if proc.poll() is not None:
            raise RuntimeError(f"hairbed explore exited: {err.read_text()}")
        try:
            with urllib.request.urlopen(base, timeout=5) as r:
                if r.status == 200:
                    return
        except OSError:
            pass
        if time.monotonic() > deadline:
            raise RuntimeError("hairbed explore did not answer within 600 s")
        time.sleep(0.5)


def _sessions(
    ctx: Any, base: str, n: int, seconds: float, query: str = QUERY
) -> list[dict[str, Any]]:
    """n pages at once in the drive view for ``seconds`` after each shows its readout: each
    one's readout (the frame times the server measured) and its error text."""
    pages = [ctx.new_page() for _ in range(n)]
    for p in pages:
        p.goto(base + query)
    for p in pages:
        p.locator("table.hb-drive-table td[data-field='linear_gain']").wait_for(timeout=300e3)
    time.sleep(seconds)
    out = []
    for p in pages:
        cells = _readout(p)
        out.append({
            "p50_ms": float(cells.get("frame_p50", "nan")),
            "p90_ms": float(cells.get("frame_p90", "nan")),
            "cpu_p50_ms": float(cells.get("frame_cpu_p50", "nan")),
            "cpu_p90_ms": float(cells.get("frame_cpu_p90", "nan")),
            "rate": float(cells.get("frame_rate", "nan")),
            "frames": int(cells.get("frame_count", "0") or 0),
            "error": _error(p),
        })  # fmt: skip
    for p in pages:
        p.close()
    return out


def served(seconds: float, query: str = QUERY) -> dict[str, Any]:
    """Row 2: one session, then 8 at once, served and animating in Chromium."""
    from playwright.sync_api import sync_playwright

    port = _free_port()
    base = f"http://127.0.0.1:{port}/"
    with tempfile.TemporaryDirectory() as tmp:
        err = Path(tmp) / "stderr.txt"
        with open(Path(tmp) / "stdout.txt", "w") as fo, open(err, "w") as fe:
            proc = subprocess.Popen(
                [sys.executable, "-m", "hairbed", "explore", "--port", str(port), "--no-browser"],
                stdout=fo,
                stderr=fe,
            )
        try:
            _wait_served(base, proc, err)
            with sync_playwright() as pw:
                ctx = pw.chromium.launch_persistent_context(
                    str(Path(tmp) / "profile"),
                    executable_path=CHROMIUM,
                    headless=True,
                    args=CHROMIUM_ARGS,
                    viewport={"width": 1400, "height": 1200},
                )
                one = _sessions(ctx, base, 1, seconds, query)[0]
                eight = _sessions(ctx, base, 8, seconds, query)
                ctx.close()
        finally:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        text = err.read_text()
        at = text.find("Traceback")
        traceback = text[max(0, at - 300) : at + 3000] if at >= 0 else ""
    p90s = [s["p90_ms"] for s in eight]
    return {
        "one_p50_ms": one["p50_ms"],
        "one_p90_ms": one["p90_ms"],
        "one_frames": one["frames"],
        "one_cpu_p50_ms": one["cpu_p50_ms"],
        "one_cpu_p90_ms": one["cpu_p90_ms"],
        "one_rate": one["rate"],
        "eight_cpu_p90_ms": [s["cpu_p90_ms"] for s in eight],
        "eight_rate": [s["rate"] for s in eight],
        "eight_p90_ms": p90s,
        "eight_p50_ms": [s["p50_ms"] for s in eight],
        "eight_frames": [s["frames"] for s in eight],
        "eight_p90_max_ms": float(np.max(p90s)),
        "eight_errors": [s["error"] for s in eight if s["error"]],
        "server_traceback": traceback,
    }


def run(
    frames: int = 1000, seconds: float = 12.0, side_views: Sequence[str] = tuple(QUERIES)
) -> dict[str, Any]:
    """Every figure (a dict of plain numbers; the Lissajous view's keys prefixed
    ``lissajous_``)."""
    out: dict[str, Any] = {"frames": frames, "seconds": seconds, "side_views": list(side_views)}
    for view in side_views:
        pre = "" if view == "bode" else f"{view}_"
        got = {**in_process(frames, QUERIES[view]), **served(seconds, QUERIES[view])}
        out.update({pre + k: v for k, v in got.items()})
    out["load_average"] = os.getloadavg()[0]
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--json", help="write the figures to this file")
    parser.add_argument(
        "--side-views", default="bode,lissajous", help="the views beside the animation, A,B"
    )
    args = parser.parse_args(argv)
    views = [v.strip() for v in args.side_views.split(",") if v.strip()]
    unknown = [v for v in views if v not in QUERIES]
    if unknown or not views:
        parser.error(f"--side-views: one or more of {', '.join(QUERIES)}, got {args.side_views!r}")
    g = run(args.frames, args.seconds, views)
    for view in views:
        pre = "" if view == "bode" else f"{view}_"
        print(f"-- the {view} view beside the animation")
        _print_rows({k[len(pre) :]: v for k, v in g.items() if k.startswith(pre)} | {
            "load_average": g["load_average"]})  # fmt: skip
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(g, fh, indent=2)
    return 0


def _print_rows(f: dict[str, Any]) -> None:
    rows = [
        ("in process, next_frame p50 / p90 [ms]",
         f"{f['frame_p50_ms']:.3f} / {f['frame_p90_ms']:.3f}"),
        ("a new animation (one update) [ms]", f"{f['update_ms']:.0f}"),
        ("served, 1 session: p50 / p90 per frame [ms] (target <= 30)",
         f"{f['one_p50_ms']:.2f} / {f['one_p90_ms']:.2f} ({f['one_frames']} frames)"),
        ("  its CPU time p50 / p90 [ms]; frames per second",
         f"{f['one_cpu_p50_ms']:.2f} / {f['one_cpu_p90_ms']:.2f}; {f['one_rate']:.1f}"),
        ("served, 8 sessions: p90 per frame, each [ms]",
         " ".join(f"{v:.1f}" for v in f["eight_p90_ms"])),
        ("  largest p90 [ms]", f"{f['eight_p90_max_ms']:.1f}"),
        ("  CPU time p90, each [ms]", " ".join(f"{v:.1f}" for v in f["eight_cpu_p90_ms"])),
        ("  frames per second, each", " ".join(f"{v:.1f}" for v in f["eight_rate"])),
        ("  frames timed, each", " ".join(str(v) for v in f["eight_frames"])),
        ("  errors on the pages", str(len(f["eight_errors"]))),
        ("  traceback from the server", "yes" if f["server_traceback"] else "no"),
        ("load average", f"{f['load_average']:.1f}"),
    ]  # fmt: skip
    width = max(len(r[0]) for r in rows)
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


if __name__ == "__main__":
    sys.exit(main())
