"""The explorer in a real browser: ``hairbed explore`` served, Debian's Chromium driven by
Playwright (headless, no network: a dead proxy for everything but the loopback).

What is checked against the library (expectations computed here with ``hairbed.solve``,
``HairBed.deform`` and ``solve_all``, never read from the app): the table after loading a URL,
after dragging the omega2 slider across both folds of a bistable case and after typing; the
library's own error message for bad typed and URL input, with the last good state kept; the URL
after a change and a fresh page opened from it; Back and Forward (the view follows the URL,
restoring adds no history entry); the JSON and CSV downloads; SI mode; twirling states.
Also: the page makes no request outside 127.0.0.1, the server writes no traceback, and Ctrl-C
stops it with one line and exit status 130. A screenshot of each view is saved (in
``HAIRBED_SCREENSHOTS`` when set, else in pytest's temporary directory).

Needs the ``app`` extra (panel, playwright) and Chromium at /usr/bin/chromium (Debian package
``chromium``; ``HAIRBED_CHROMIUM`` names another executable). Where one is missing the tests
skip, saying which; with ``HAIRBED_REQUIRE_BROWSER=1`` (set by .ci/run) they fail instead.
Playwright's own browser download (``playwright install``) is never used.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
import warnings
from pathlib import Path
from urllib.parse import urlparse

import numpy as np
import pytest

import hairbed

CHROMIUM = os.environ.get("HAIRBED_CHROMIUM", "/usr/bin/chromium")
REQUIRE = os.environ.get("HAIRBED_REQUIRE_BROWSER", "") == "1"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--proxy-server=http://127.0.0.1:9",  # nothing but the loopback leaves the browser
]
BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}
TIMEOUT = 60.0  # [s] for one view to update on this (shared, 2-core) machine


def _unavailable(reason: str) -> None:
    if REQUIRE:
        pytest.fail(f"browser tests required (HAIRBED_REQUIRE_BROWSER=1) but {reason}")
    pytest.skip(reason)


def _missing() -> str | None:
    try:
        import panel  # noqa: F401
    except ImportError:
        return "panel is not installed (pip install 'hairbed[app]')"
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "playwright is not installed (pip install 'hairbed[app]')"
    if not (Path(CHROMIUM).is_file() and os.access(CHROMIUM, os.X_OK)):
        return f"no Chromium at {CHROMIUM} (apt-get install chromium)"
    return None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """``hairbed explore`` on a free loopback port: (base URL, process, stderr path)."""
    reason = _missing()
    if reason:
        _unavailable(reason)
    port = _free_port()
    logs = tmp_path_factory.mktemp("explore")
    out, err = logs / "stdout.txt", logs / "stderr.txt"
    with open(out, "w") as fo, open(err, "w") as fe:
        proc = subprocess.Popen(
            [sys.executable, "-m", "hairbed", "explore", "--port", str(port), "--no-browser"],
            stdout=fo,
            stderr=fe,
        )
    base = f"http://127.0.0.1:{port}/"
    deadline = time.monotonic() + 300.0
    while True:
        if proc.poll() is not None:
            pytest.fail(f"hairbed explore exited with {proc.returncode}: {err.read_text()}")
        try:
            with urllib.request.urlopen(base, timeout=5) as r:
                if r.status == 200:
                    break
        except OSError:
            pass
        if time.monotonic() > deadline:
            proc.kill()
            pytest.fail("hairbed explore did not answer within 300 s")
        time.sleep(0.5)
    yield base, proc, err
    if proc.poll() is None:
        proc.kill()
        proc.wait()


@pytest.fixture(scope="module")
def browser(server, tmp_path_factory):
    """A headless Chromium context with a fresh profile; records every request's URL."""
    from playwright.sync_api import Error, sync_playwright

    profile = tmp_path_factory.mktemp("chromium-profile")
    requests: list[str] = []
    with sync_playwright() as pw:
        try:
            ctx = pw.chromium.launch_persistent_context(
                str(profile),
                executable_path=CHROMIUM,
                headless=True,
                args=CHROMIUM_ARGS,
                viewport={"width": 1400, "height": 1500},
                accept_downloads=True,
            )
        except Error as exc:
            _unavailable(f"Chromium at {CHROMIUM} does not start: {str(exc).splitlines()[0]}")
        ctx.on("request", lambda r: requests.append(r.url))
        ctx.requests = requests  # type: ignore[attr-defined]
        yield ctx
        ctx.close()


@pytest.fixture(scope="module")
def shots(tmp_path_factory) -> Path:
    where = os.environ.get("HAIRBED_SCREENSHOTS")
    path = Path(where) if where else tmp_path_factory.mktemp("screenshots")
    path.mkdir(parents=True, exist_ok=True)
    return path


# -- reading the page ----------------------------------------------------------------------


def _open(browser, server, query: str = ""):
    page = browser.new_page()
    page.goto(server[0] + query)
    page.locator("table.hb-states td[data-field='xi']").first.wait_for(timeout=TIMEOUT * 1e3)
    return page


def _cells(page, field: str) -> dict[str, str]:
    return dict(
        page.locator(f"table.hb-states td[data-field='{field}']").evaluate_all(
            "els => els.map(e => [e.dataset.state, e.textContent])"
        )
    )


def _until(check, what: str):
    """Poll ``check()`` until it returns something truthy (the Bokeh views update
    asynchronously); fail naming ``what`` after TIMEOUT."""
    deadline = time.monotonic() + TIMEOUT
    last = None
    while time.monotonic() < deadline:
        try:
            last = check()
        except Exception as exc:  # an element being re-rendered
            last = exc
        else:
            if last:
                return last
        time.sleep(0.05)
    pytest.fail(f"timed out waiting for {what}; last: {last!r}")


def _shown_omega2(page) -> float | None:
    """omega2 of the table, once it is the one of the omega2 field (the update arrived)."""
    typed = page.locator(".hb-omega2 input").input_value()
    cells = set(_cells(page, "omega2").values())
    if len(cells) == 1 and float(cells.pop()) == float(typed):
        return float(typed)
    return None


def _check_states(page, omega2: float, eps: float, theta0: float) -> list[str]:
    """The table holds exactly the library's states at these inputs; returns their roots."""
    n = hairbed.solve(omega2, eps, theta0).n_roots
    roots = ["low", "mid", "high"] if n == 3 else ["low"]
    assert page.locator("table.hb-states").get_attribute("data-count") == str(len(roots))
    for field in ("xi", "tip_deflection", "tip_height", "tip_angle", "base_curvature"):
        shown = _cells(page, field)
        assert sorted(shown) == sorted(roots), field
        for root in roots:
            expected = getattr(hairbed.solve(omega2, eps, theta0, root=root), field)
            assert float(shown[root]) == pytest.approx(expected, rel=1e-11, abs=1e-13), (
                field,
                root,
            )
    return roots


def _drag_omega2(page, target: float) -> None:
    """Drag the omega2 slider's handle to ``target`` in eight mouse moves (each one an
    update that re-solves every state); the slider runs over log10(omega2) in [-3, 3]."""
    track = page.locator(".hb-omega2-slider .noUi-base").bounding_box()
    handle = page.locator(".hb-omega2-slider .noUi-handle").bounding_box()
    x = handle["x"] + handle["width"] / 2
    y = handle["y"] + handle["height"] / 2
    x1 = track["x"] + (math.log10(target) + 3.0) / 6.0 * track["width"]
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 9):
        page.mouse.move(x + (x1 - x) * k / 8, y)
        page.wait_for_timeout(40)
    page.mouse.up()


def _settled(page) -> float:
    """omega2 once the page is quiet: the field and the whole table unchanged for a second
    (the updates of a drag may still be arriving), and the table showing the field's value."""

    def snapshot():
        return (
            page.locator(".hb-omega2 input").input_value(),
            page.locator("table.hb-states").inner_text(),
            _shown_omega2(page),
        )

    deadline = time.monotonic() + TIMEOUT
    last, since = None, time.monotonic()
    while time.monotonic() < deadline:
        try:
            now = snapshot()
        except Exception:  # an element being re-rendered
            now = None
        if now != last:
            last, since = now, time.monotonic()
        elif now is not None and now[2] is not None and time.monotonic() - since > 1.0:
            return now[2]
        time.sleep(0.1)
    pytest.fail(f"the page did not settle; last: {last!r}")


def _error_text(page) -> str:
    alert = page.locator(".hb-error")
    if not alert.is_visible():
        return ""
    return alert.locator("p").first.text_content() or ""


def _error_texts(page) -> list[str]:
    """Every message shown (one paragraph each)."""
    alert = page.locator(".hb-error")
    if not alert.is_visible():
        return []
    return alert.locator("p").all_text_contents()


def _type(page, key: str, value: str) -> None:
    box = page.locator(f".hb-{key} input")
    box.fill(value)
    box.press("Enter")


def _heading(name: str) -> str:
    """A CSV heading "name [CF units]" of hairbed's variables table (as its sweeps write)."""
    from hairbed._variables import SOLUTION

    units = SOLUTION[name].units
    return f"{name} [{units}]" if units else name


def _library_message(*args) -> str:
    with pytest.raises(ValueError) as info:
        hairbed.solve(*args)
    return str(info.value)


# -- the tests ----------------------------------------------------------------------


def test_page_loads_everything_from_the_loopback(browser, server, shots):
    page = _open(browser, server)
    _until(lambda: _shown_omega2(page), "the first view")
    _check_states(page, 2.0, 0.5, 0.0)  # the paper's worked example
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-default.png"), full_page=True)
    hosts = {urlparse(u).netloc for u in browser.requests if urlparse(u).scheme in ("http", "ws")}
    assert hosts == {urlparse(server[0]).netloc}, hosts
    assert all(urlparse(u).scheme in ("http", "ws", "data", "blob") for u in browser.requests)
    page.close()


def test_slider_across_both_folds(browser, server, shots):
    """Drag the omega2 slider through the window of three states of (eps, theta0) =
    (0.9, -1.5) (between the folds, theory.md §5) and out above it."""
    window = hairbed.branches.folds(0.9, -1.5).omega2
    lo_fold, hi_fold = float(min(window)), float(max(window))
    page = _open(browser, server, "?omega2=0.8&eps=0.9&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 0.8, "the view at omega2 = 0.8")
    assert _check_states(page, 0.8, 0.9, -1.5) == ["low"]
    seen = []
    for target, count in ((1.2, 3), (2.5, 1)):
        assert (lo_fold < target < hi_fold) == (count == 3)
        _drag_omega2(page, target)
        w = _settled(page)
        # where the handle stopped (a loaded machine may drop a mouse move): inside the window
        # of three states, then above the upper fold
        assert (lo_fold < w < hi_fold) if count == 3 else (w > hi_fold), (w, target)
        assert len(_check_states(page, w, 0.9, -1.5)) == count
        seen.append(w)
        if count == 3:
            page.screenshot(path=str(shots / "explorer-three-states.png"), full_page=True)
    # the URL follows: it reproduces the last view in a fresh page
    url = _until(lambda: page.url if f"omega2={seen[-1]:.6g}" in page.url else None, "the URL")
    other = browser.new_page()
    other.goto(url)
    _until(lambda: _shown_omega2(other) == seen[-1], "the view of the link")
    for field in ("xi", "tip_deflection", "energy"):
        assert _cells(other, field) == _cells(page, field)
    other.close()
    page.close()


def test_typed_values_and_bad_input(browser, server, shots):
    page = _open(browser, server, "?omega2=1.2&eps=0.9&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 1.2, "the view at omega2 = 1.2")
    _type(page, "omega2", "1.3")
    _until(lambda: _shown_omega2(page) == 1.3, "the typed omega2")
    _check_states(page, 1.3, 0.9, -1.5)
    good = _cells(page, "tip_deflection")
    for key, text, args in (
        ("omega2", "-1", (-1.0, 0.9, -1.5)),
        ("omega2", "abc", ("abc", 0.9, -1.5)),
        ("eps", "1", (1.3, 1.0, -1.5)),
        ("theta0", "nan", (1.3, 0.9, float("nan"))),
    ):
        _type(page, key, text)
        expected = _library_message(*args)
        _until(lambda e=expected: _error_text(page) == e, f"the message {expected!r}")
        assert _cells(page, "tip_deflection") == good  # the last good state stays
        if key == "omega2" and text == "abc":
            page.screenshot(path=str(shots / "explorer-bad-input.png"), full_page=True)
        _type(page, key, {"omega2": "1.3", "eps": "0.9", "theta0": "-1.5"}[key])
        _until(lambda: _error_text(page) == "", "the message to go")
    _type(page, "theta0", "-1")
    _type(page, "eps", "0.95")
    _type(page, "omega2", "0.3")
    _until(  # all three typed values, omega2 (typed last) included
        lambda: (
            _cells(page, "eps").get("low") == "0.95"
            and _cells(page, "theta0")["low"] == "-1"
            and _shown_omega2(page) == 0.3
        ),
        "the typed eps, theta0 and omega2",
    )
    _check_states(page, 0.3, 0.95, -1.0)
    page.close()


INPUTS = ("omega2", "eps", "theta0")


def _url_inputs(page) -> tuple[float, float, float]:
    """omega2, eps, theta0 of the page's URL (read in the page: Playwright's ``page.url``
    follows a ``pushState`` only while Playwright waits on something)."""
    from urllib.parse import parse_qs

    args = parse_qs(page.evaluate("window.location.search").lstrip("?"))
    return float(args["omega2"][0]), float(args["eps"][0]), float(args["theta0"][0])


def _view_follows_url(page) -> tuple[float, float, float]:
    """Wait until the view shows the URL's inputs: the fields, the table's omega2, eps and
    theta0 and its states those of ``hairbed.solve`` there."""

    def agree():
        omega2, eps, theta0 = _url_inputs(page)
        fields = tuple(float(page.locator(f".hb-{k} input").input_value()) for k in INPUTS)
        table = tuple(set(_cells(page, k).values()) for k in INPUTS)
        if fields == (omega2, eps, theta0) and all(
            len(t) == 1 and float(t.pop()) == v for t, v in zip(table, fields)
        ):
            return omega2, eps, theta0
        return None

    inputs = _until(agree, "the view of the URL")
    _check_states(page, *inputs)
    return inputs


def test_back_and_forward_restore_the_view(browser, server):
    """Two typed changes of omega2, each a history entry of its own (further apart than
    SETTLE_MS); Back and Forward move the address bar and the view together (the states of
    ``hairbed.solve`` at the URL's inputs) and add no entry."""
    from hairbed.explorer._history import SETTLE_MS

    page = _open(browser, server, "?omega2=0.8&eps=0.9&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 0.8, "the view at omega2 = 0.8")
    # the loaded link is written out whole, in place (no new entry)
    _until(lambda: "twirl=0" in page.evaluate("window.location.search"), "the whole query")
    length = page.evaluate("history.length")
    for w in (1.2, 2.5):
        page.wait_for_timeout(2 * SETTLE_MS)  # a settled view: the next change is an entry
        _type(page, "omega2", str(w))
        _until(lambda w=w: _shown_omega2(page) == w, f"the typed omega2 = {w}")
        _until(lambda w=w: _url_inputs(page)[0] == w, f"the URL of omega2 = {w}")
    assert page.evaluate("history.length") == length + 2
    counts = {0.8: 1, 1.2: 3, 2.5: 1}  # across the window of three states and out above it
    for move, w in (
        (page.go_back, 1.2),
        (page.go_back, 0.8),
        (page.go_forward, 1.2),
        (page.go_forward, 2.5),
        (page.go_back, 1.2),
    ):
        move()
        _until(lambda w=w: _url_inputs(page)[0] == w, f"the URL of omega2 = {w}")
        assert _view_follows_url(page) == (w, 0.9, -1.5)
        assert len(_cells(page, "xi")) == counts[w]
        assert _error_text(page) == ""
    page.wait_for_timeout(2 * SETTLE_MS)  # the server's answers to Back/Forward add nothing
    assert page.evaluate("history.length") == length + 2
    assert _url_inputs(page)[0] == 1.2
    # a change after going back starts a new branch of the history: Forward leads nowhere
    _type(page, "omega2", "1.3")
    _until(lambda: _url_inputs(page)[0] == 1.3, "the URL of omega2 = 1.3")
    assert _view_follows_url(page) == (1.3, 0.9, -1.5)
    page.go_back()
    _until(lambda: _url_inputs(page)[0] == 1.2, "the URL of omega2 = 1.2")
    assert _view_follows_url(page) == (1.2, 0.9, -1.5)
    page.close()


def test_bad_url_shows_the_message_and_the_defaults(browser, server):
    page = _open(browser, server, "?omega2=2&eps=1.5")
    expected = _library_message(2.0, 1.5, 0.0)
    _until(lambda: _error_text(page) == expected, "the URL's message")
    # the field shows the value of the view on screen again, not the bad text
    _until(lambda: page.locator(".hb-eps input").input_value() == "0.5", "the good eps")
    _check_states(page, 2.0, 0.5, 0.0)  # the defaults
    page.close()
    page = _open(browser, server, "?omega2=zero")
    expected = _library_message("zero", 0.5, 0.0)
    _until(lambda: _error_text(page) == expected, "the URL's message")
    page.close()


def test_downloads_match_the_library(browser, server, tmp_path):
    page = _open(browser, server, "?omega2=1.2&eps=0.9&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 1.2, "the view at omega2 = 1.2")
    files = {}
    for kind in ("json", "csv"):
        with page.expect_download(timeout=TIMEOUT * 1e3) as info:
            page.locator(f".hb-download-{kind} button").click()
        path = tmp_path / info.value.suggested_filename
        info.value.save_as(path)
        files[kind] = path.read_text()
    doc = json.loads(files["json"])
    rows = list(csv.DictReader(io.StringIO(files["csv"])))
    assert (
        [s["state"] for s in doc["states"]]
        == [r["state"] for r in rows]
        == [
            "low",
            "mid",
            "high",
        ]
    )
    for rec, row in zip(doc["states"], rows):
        ref = hairbed.solve(1.2, 0.9, -1.5, root=rec["state"])
        for name, value in ref.as_dict().items():
            cell = row[_heading(name)]
            if isinstance(value, bool):
                assert rec[name] is value and cell == str(value)
            else:
                assert rec[name] == value and float(cell) == value, name
    assert [r["stable"] for r in rows] == ["True", "False", "True"]
    page.close()


def test_unknown_link_parameter_and_the_png_download(browser, server, tmp_path, shots):
    """Issue 33: a link's unknown parameter leaves its known ones applied, and says so; the
    PNG button downloads the view on screen (its states painted, not a blank page)."""
    page = _open(browser, server, "?omega2=1.2&eps=0.9&theta0=-1.5&colour=red")
    _until(lambda: _shown_omega2(page) == 1.2, "the link's known inputs applied")
    assert sorted(_cells(page, "xi")) == ["high", "low", "mid"]
    texts = _until(lambda: _error_texts(page), "the note of the ignored parameter")
    assert any("ignored the unknown URL parameter 'colour'" in t for t in texts), texts
    _until(lambda: "colour" not in page.url and "omega2=1.2" in page.url, "the view's own URL")
    with page.expect_download(timeout=TIMEOUT * 1e3) as info:
        page.locator(".hb-download-png button").click()
    assert info.value.suggested_filename == "hairbed-view.png"
    path = tmp_path / "view.png"
    info.value.save_as(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib.image

    img = np.round(matplotlib.image.imread(path)[..., :3] * 255.0).astype(np.int64)
    code = (img[..., 0] << 16) | (img[..., 1] << 8) | img[..., 2]
    for rgb in (0x0072B2, 0xD55E00, 0x009E73):  # the low, mid and high states' colours
        assert int(np.count_nonzero(code == rgb)) > 100, hex(rgb)
    page.screenshot(path=str(shots / "unknown-parameter.png"))
    page.close()


def test_si_mode(browser, server, shots):
    query = "?si=1&velocity=0.3&base_angle=0.2&density=1000&" + "&".join(
        f"{k}={v!r}" for k, v in BED.items()
    )
    page = _open(browser, server, query)
    bed = hairbed.HairBed(**BED, base_angle=0.2, density=1000.0)
    st = bed.deform(0.3)

    def shown():
        cells = page.locator("td[data-field='si_wall_shear_stress']").all_text_contents()
        return cells or None

    tau = _until(shown, "the SI rows")
    assert float(tau[0]) == pytest.approx(st.wall_shear_stress, rel=1e-11)
    assert float(_cells(page, "si_tip_deflection")["low"]) == pytest.approx(
        st.tip_deflection, rel=1e-11
    )
    gap = bed.channel_height - st.tip_height
    reynolds = float(_cells(page, "si_reynolds_number")["low"])
    assert reynolds == pytest.approx(st.reynolds_number, rel=1e-11)
    assert reynolds == pytest.approx(1000.0 * 0.3 * gap / bed.viscosity, rel=1e-11)
    assert page.locator(".hb-eps input").input_value() == repr(bed.eps)
    assert page.locator("ul.hb-warn").count() == 0  # Re ~ 0.4: the library warns of nothing
    page.screenshot(path=str(shots / "explorer-si.png"), full_page=True)
    # faster: the gap flow leaves the Stokes regime; the page shows the library's warning
    _type(page, "velocity", "3")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bed.deform(3.0)
    expected = [f"{w.category.__name__}: {' '.join(str(w.message).split())}" for w in caught]
    assert expected and "Reynolds" in expected[0]
    _until(
        lambda: page.locator("ul.hb-warn li").all_text_contents() == expected,
        "the library's warning",
    )
    _type(page, "velocity", "0.3")
    _until(lambda: page.locator("ul.hb-warn").count() == 0, "the warning to go")
    _type(page, "length", "-1e-3")
    with pytest.raises(ValueError) as info:
        hairbed.HairBed(**{**BED, "length": -1e-3})
    _until(lambda: _error_text(page) == str(info.value), "the bed's message")
    assert float(page.locator("td[data-field='si_wall_shear_stress']").first.text_content()) == (
        pytest.approx(st.wall_shear_stress, rel=1e-11)
    )
    page.close()


def test_twirling_states(browser, server, shots):
    page = _open(browser, server, "?omega2=200&eps=0.5&theta0=0&twirl=1")
    ref = [s for s in hairbed.solve_all(200.0, 0.5, 0.0) if (s.sign, s.n) != (1, 0)]
    table = page.locator("table.hb-twirl")
    _until(lambda: table.get_attribute("data-count") == str(len(ref)), "the twirling table")
    xi = table.locator("td[data-field='xi']").all_text_contents()
    assert [float(v) for v in xi] == pytest.approx([s.xi for s in ref], rel=1e-11)
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-twirling.png"), full_page=True)
    page.close()


# -- issue 23: where users start, errors in full, legible states, downloads with units -----


def test_presets_and_the_beds_own_base_angle(browser, server, shots):
    """Item 11: the presets, and SI mode with the bed's own base angle: switched on from a
    hair leaning into the flow (theta0 = -1.5), the default bed is upright (before, the
    pillar took theta0 = -1.5 and lay flat)."""
    page = _open(browser, server)
    _until(lambda: _shown_omega2(page) == 2.0, "the worked example")
    page.locator(".hb-preset-bistable button").click()
    _until(lambda: _shown_omega2(page) == 1.2, "the bistable preset")
    assert _check_states(page, 1.2, 0.9, -1.5) == ["low", "mid", "high"]
    page.locator(".hb-si .bk-body").click()  # the SI switch, from theta0 = -1.5
    bed = hairbed.HairBed(**BED, density=1260.0)  # base angle 0: upright
    st = bed.deform(0.1)

    def si_deflection():
        cells = _cells(page, "si_tip_deflection")
        return float(cells["low"]) if cells else None

    tip = _until(si_deflection, "the SI rows")
    assert tip == pytest.approx(st.tip_deflection, rel=1e-11)
    assert page.locator(".hb-base_angle input").input_value() == "0"
    assert float(page.locator(".hb-theta0 input").input_value()) == 0.0
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-si-from-leaning.png"), full_page=True)
    page.locator(".hb-preset-twirling button").click()
    _until(lambda: _shown_omega2(page) == 200.0, "the twirling preset")
    ref = [s for s in hairbed.solve_all(200.0, 0.5, 0.0) if (s.sign, s.n) != (1, 0)]
    table = page.locator("table.hb-twirl")
    _until(lambda: table.get_attribute("data-count") == str(len(ref)), "the twirling table")
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-preset-twirling.png"), full_page=True)
    page.locator(".hb-preset-sensor button").click()
    _until(lambda: page.locator(".hb-velocity input").is_visible(), "the sensor bed")
    tau = _until(lambda: _cells(page, "si_wall_shear_stress").get("low"), "the sensor's stress")
    assert float(tau) == pytest.approx(bed.deform(0.1).wall_shear_stress, rel=1e-11)
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-preset-sensor.png"), full_page=True)
    page.close()


def test_bad_url_lists_every_parameter(browser, server, shots):
    """Item 12: three bad values, three messages (before: only the first), and the fields
    show the view on screen (before: the bad text stayed)."""
    page = _open(browser, server, "?omega2=-1&eps=1.5&theta0=3")
    expected = [
        _library_message(-1.0, 0.5, 0.0),
        _library_message(1.0, 1.5, 0.0),
        _library_message(1.0, 0.5, 3.0),
    ]
    _until(lambda: _error_texts(page) == expected, "every message")
    fields = [page.locator(f".hb-{k} input").input_value() for k in INPUTS]
    assert fields == ["2", "0.5", "0"]
    _check_states(page, 2.0, 0.5, 0.0)
    page.screenshot(path=str(shots / "explorer-bad-url.png"), full_page=True)
    page.close()


def test_warnings_on_top_and_within_the_page(browser, server, shots):
    """Item 12: the library's validity warning sits above the views and inside the page's
    width (before: below the table, wider than the window)."""
    query = "?si=1&velocity=3&density=1000&" + "&".join(f"{k}={v!r}" for k, v in BED.items())
    page = _open(browser, server, query)
    item = page.locator("ul.hb-warn li").first
    _until(lambda: item.is_visible(), "the warning")
    assert "Reynolds" in (item.text_content() or "")
    box = item.bounding_box()
    # above the row of the controls and the views (the omega2 slider is near its top)
    views = page.locator(".hb-omega2-slider").bounding_box()
    table = page.locator("table.hb-states").bounding_box()
    assert box["y"] + box["height"] <= views["y"] and box["y"] < table["y"], (box, views)
    width = page.evaluate("window.innerWidth")
    assert box["x"] + box["width"] <= width, (box, width)
    assert page.evaluate("document.documentElement.scrollWidth") <= width
    page.screenshot(path=str(shots / "explorer-warning.png"), full_page=True)
    page.close()


def test_legible_states(browser, server, shots):
    """Item 13: the twirling checkbox ticks by its label; the slider shows the state's value
    (0.897, before 0.90); in SI mode the URL carries the view's omega2 (before, the one of
    the update before)."""
    page = _open(browser, server, "?omega2=1.2&eps=0.897&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 1.2, "the view at omega2 = 1.2")
    shown = page.locator(".hb-eps-slider .bk-slider-value")
    _until(lambda: shown.text_content() == "0.897", "the slider's value 0.897")
    page.get_by_text("show twirling states").click()
    ref = [s for s in hairbed.solve_all(1.2, 0.897, -1.5) if (s.sign, s.n) != (1, 0)]
    _until(lambda: page.locator(".hb-twirl-table p, table.hb-twirl").count() == 1, "twirling")
    count = page.locator("table.hb-twirl").get_attribute("data-count") if ref else "0"
    assert count == str(len(ref))
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-legible.png"), full_page=True)
    page.close()
    page = _open(browser, server, "?si=1&velocity=0.1")
    bed = hairbed.HairBed(**BED, density=1260.0)
    for v in (0.3, 0.05):
        _type(page, "velocity", repr(v))
        _until(lambda v=v: _url_inputs(page)[0] == bed.omega2(v), f"the URL at v = {v}")
    page.close()


def test_downloads_carry_units_and_the_shape(browser, server, tmp_path):
    """Item 14: the CSV heads its columns "name [units]", the JSON names every variable's
    units, and the shape CSV is the hair's shape of every state (the library's profile)."""
    page = _open(browser, server, "?omega2=1.2&eps=0.9&theta0=-1.5")
    _until(lambda: _shown_omega2(page) == 1.2, "the view at omega2 = 1.2")
    files = {}
    for kind in ("json", "csv", "shape"):
        with page.expect_download(timeout=TIMEOUT * 1e3) as info:
            page.locator(f".hb-download-{kind} button").click()
        path = tmp_path / info.value.suggested_filename
        info.value.save_as(path)
        files[kind] = path.read_text()
    header = next(csv.reader(io.StringIO(files["csv"])))
    assert {"tip_deflection [1]", "tip_angle [rad]", "theta0 [rad]"} <= set(header)
    doc = json.loads(files["json"])
    assert doc["variables"]["tip_angle"]["units"] == "rad"
    rows = list(csv.DictReader(io.StringIO(files["shape"])))
    assert [r["state"] for r in rows].count("mid") == len(rows) // 3
    for root in ("low", "mid", "high"):
        ref = hairbed.solve(1.2, 0.9, -1.5, root=root)
        mine = [r for r in rows if r["state"] == root]
        sigma = [float(r["sigma [1]"]) for r in mine]
        assert sigma[0] == 0.0 and sigma[-1] == 1.0
        assert [float(r["x [1]"]) for r in mine] == pytest.approx(ref.x(sigma), rel=1e-12)
        assert [float(r["z [1]"]) for r in mine] == pytest.approx(ref.z(sigma), rel=1e-12)
        assert float(mine[-1]["x [1]"]) == pytest.approx(ref.tip_deflection, rel=1e-12)
    page.close()


def _search(page) -> dict[str, str]:
    from urllib.parse import parse_qsl

    return dict(parse_qsl(page.evaluate("window.location.search").lstrip("?")))


def _check_loaded(page, load_key: str, omega2: float, eps: float, theta0: float) -> float:
    """Wait until the table shows the load typed into its field, then check every state
    against ``hairbed.solve_loaded`` (each root of ``solve_loaded_all``'s count)."""

    def arrived():
        typed = float(page.locator(f".hb-{load_key} input").input_value())
        cells = set(_cells(page, load_key).values())
        return typed if len(cells) == 1 and float(cells.pop()) == typed else None

    load = _until(arrived, f"the view at the typed {load_key}")
    args = {"omega2": omega2, "eps": eps, "theta0": theta0, load_key: load}
    n = len(hairbed.solve_loaded_all(**args))
    roots = {1: ["low"], 2: ["low", "high"], 3: ["low", "mid", "high"]}[n]
    assert page.locator("table.hb-states").get_attribute("data-count") == str(n)
    for field in ("tip_height", "tip_deflection", "tip_angle", "base_curvature"):
        shown = _cells(page, field)
        assert sorted(shown) == sorted(roots), field
        for root in roots:
            expected = float(getattr(hairbed.solve_loaded(**args, root=root), field))
            assert float(shown[root]) == pytest.approx(expected, rel=1e-9, abs=1e-12), (
                field, root,
            )  # fmt: skip
    return load


def _valve_shown(page) -> dict[str, float]:
    cells = page.locator("table.hb-valve td[data-field]").evaluate_all(
        "els => els.map(e => [e.dataset.field, e.textContent])"
    )
    return {k: float(v) for k, v in cells}


def test_pump_drives_the_load_and_the_valve(browser, server, shots):
    """Issue 20, item 4: select each drive, move the load (typed and by its slider), switch
    to the valve view, values against the library, and reload the view from its URL."""
    page = _open(browser, server, "?omega2=0&eps=0.5&theta0=0.5")
    _until(lambda: _shown_omega2(page) == 0.0, "the view at omega2 = 0")
    page.locator(".hb-drive button", has_text="pressure gradient").click()
    _until(lambda: _search(page).get("drive") == "pressure", "the pressure drive in the URL")
    assert _check_loaded(page, "pi", 0.0, 0.5, 0.5) == 1.0  # the default load
    _type(page, "pi", "5")
    assert _check_loaded(page, "pi", 0.0, 0.5, 0.5) == 5.0
    # the load slider (log10 abs(pi) in [-3, 3]): a click on its track near pi = 30
    track = page.locator(".hb-load-slider .noUi-base").bounding_box()
    page.mouse.click(track["x"] + (math.log10(30.0) + 3.0) / 6.0 * track["width"],
                     track["y"] + track["height"] / 2)  # fmt: skip
    _until(lambda: float(page.locator(".hb-pi input").input_value()) > 5.0, "the slider's pi")
    pi = _check_loaded(page, "pi", 0.0, 0.5, 0.5)
    assert 10.0 < pi < 100.0, pi
    _type(page, "pi", "5")
    _check_loaded(page, "pi", 0.0, 0.5, 0.5)
    # the valve view: the flow both ways at the pump's drop, walls at rest
    page.locator(".hb-view button", has_text="valve").click()
    shown = _until(lambda: _valve_shown(page), "the valve's readout")
    ref = hairbed.solve_loaded(np.zeros(2), 0.5, 0.5, pi=np.array([5.0, -5.0]))
    u = 1.0 - 0.5 * np.asarray(ref.tip_height)
    assert shown["drop"] == 5.0
    assert shown["diodicity"] == pytest.approx((u[0] / u[1]) ** 3, rel=1e-9)
    assert shown["forward_ratio"] == pytest.approx(1.0 / u[0] ** 3, rel=1e-9)
    assert shown["forward"] == pytest.approx(5.0 * u[0] ** 3 / (2 * 0.5), rel=1e-9)
    assert page.locator(".hb-valve-flow").is_visible()
    assert not page.locator(".hb-branch").is_visible()
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-valve.png"), full_page=True)
    # a fresh page from the URL: the same drive, load, view and values
    args = _until(lambda: _search(page) if _search(page).get("view") == "valve" else None, "URL")
    assert (args["drive"], float(args["pi"])) == ("pressure", 5.0)
    again = browser.new_page()
    again.goto(server[0] + page.evaluate("window.location.search"))
    assert _until(lambda: _valve_shown(again), "the valve after reload") == shown
    assert again.locator(".hb-pi input").input_value() == "5"
    _check_loaded(again, "pi", 0.0, 0.5, 0.5)
    again.close()
    # the flow drive in a window of three states, and a bad load: the library's message
    page.locator(".hb-view button", has_text="branch diagram").click()
    page.locator(".hb-drive button", has_text="flow rate").click()
    _until(lambda: _search(page).get("drive") == "flow", "the flow drive in the URL")
    _type(page, "eps", "0.9")
    _type(page, "theta0", "-1.2")
    _type(page, "q", "0.05")
    _until(lambda: _cells(page, "eps").get("low") == "0.9", "eps = 0.9")
    _until(lambda: _cells(page, "theta0").get("low") == "-1.2", "theta0 = -1.2")
    _check_loaded(page, "q", 0.0, 0.9, -1.2)
    assert page.locator("table.hb-states").get_attribute("data-count") == "3"
    assert _cells(page, "stable") == {"low": "True", "mid": "False", "high": "True"}
    page.screenshot(path=str(shots / "explorer-flow-drive.png"), full_page=True)
    _type(page, "q", "nan")
    with pytest.raises(ValueError) as info:
        hairbed.solve_loaded(0.0, 0.9, -1.2, q=float("nan"))
    assert _until(lambda: _error_text(page), "the error message") == str(info.value)
    assert page.locator("table.hb-states").get_attribute("data-count") == "3"  # kept
    # back to the wall speed: the closed form's states again
    _type(page, "q", "0.05")
    _type(page, "omega2", "1.2")
    page.locator(".hb-drive button", has_text="wall speed").click()
    _until(lambda: "drive" not in _search(page), "the wall drive's URL")
    _until(lambda: _shown_omega2(page) == 1.2, "the wall drive's view")
    _check_states(page, 1.2, 0.9, -1.2)
    page.close()


def _pillar_cells(page, table: str = "hb-pillar-states") -> dict[str, str]:
    """The pillar's one-state table (or the linear formula's): field -> text."""
    cells = page.locator(f"table.{table} td[data-field]").evaluate_all(
        "els => els.map(e => [e.dataset.field, e.textContent])"
    )
    return dict(cells)


def _pillar_at(page, forcing: float) -> dict[str, str] | None:
    """The pillar's table once it shows ``forcing`` (the update arrived)."""
    cells = _pillar_cells(page)
    return cells if cells and float(cells.get("forcing", "nan")) == forcing else None


def _check_pillar(cells: dict[str, str], forcing: float, theta0: float) -> None:
    ref = hairbed.solve_pillar(forcing, theta0)
    for field in ("tip_deflection", "tip_height", "tip_angle", "base_curvature", "drag_x"):
        assert float(cells[field]) == pytest.approx(getattr(ref, field), rel=1e-11, abs=1e-13)
    assert cells["status"] == "0" and cells["message"] == "ok"


def test_pillar_mode_lambda_and_the_calibration_curve(browser, server, shots):
    """Issue 21, item 3: select the pillar mode, move Lambda by its slider, switch to the
    calibration view, the numbers against hairbed.solve_pillar and the linear cantilever
    formula, and a fresh page from the URL."""
    page = _open(browser, server, "?omega2=2")
    page.locator(".hb-mode button", has_text="isolated pillar").click()
    _until(lambda: _search(page).get("mode") == "pillar", "the pillar mode in the URL")
    _check_pillar(_until(lambda: _pillar_at(page, 1.0), "the pillar at Lambda = 1"), 1.0, 0.0)
    assert not page.locator(".hb-channel").is_visible()
    _type(page, "pillar_theta0", "0.3")
    _until(lambda: _pillar_cells(page).get("theta0") == "0.3", "theta0 = 0.3")
    # the Lambda slider (log10 abs(Lambda) in [-3, 4]): a click on its track near 30
    track = page.locator(".hb-forcing-slider .noUi-base").bounding_box()
    page.mouse.click(track["x"] + (math.log10(30.0) + 3.0) / 7.0 * track["width"],
                     track["y"] + track["height"] / 2)  # fmt: skip
    lam = _until(
        lambda: (v := float(page.locator(".hb-forcing input").input_value())) > 5.0 and v,
        "the slider's Lambda",
    )
    assert 10.0 < lam < 100.0, lam
    _check_pillar(_until(lambda: _pillar_at(page, lam), "the pillar at the slider's Lambda"),
                  lam, 0.3)  # fmt: skip
    # the calibration view: the linear formula's slope and error, and where it is 1 % off
    page.locator(".hb-pillar-view button", has_text="calibration curve").click()
    lin = _until(lambda: _pillar_cells(page, "hb-pillar-linear"), "the linear formula")
    slope = 11.0 * math.cos(0.3) ** 3 / 120.0
    assert float(lin["slope"]) == pytest.approx(slope, rel=1e-10)
    assert float(lin["rest"]) == pytest.approx(math.sin(0.3), rel=1e-11)  # 12 digits shown
    x1 = float(hairbed.solve_pillar(lam, 0.3).tip_deflection)
    assert float(lin["error"]) == pytest.approx(abs((x1 - math.sin(0.3)) / slope - lam) / lam)
    at = float(lin["level_0.01"])
    x1 = float(hairbed.solve_pillar(at, 0.3).tip_deflection)
    assert abs((x1 - math.sin(0.3)) / slope - at) / at == pytest.approx(0.01, rel=0.02)
    assert page.locator(".hb-pillar-calibration").is_visible()
    page.wait_for_timeout(500)
    page.screenshot(path=str(shots / "explorer-pillar-calibration.png"), full_page=True)
    # a fresh page from the URL: the same mode, inputs, view and numbers
    args = _until(
        lambda: _search(page) if _search(page).get("pillar_view") == "calibration" else None,
        "the calibration view in the URL",
    )
    assert (args["mode"], float(args["forcing"]), args["pillar_theta0"]) == ("pillar", lam, "0.3")
    again = browser.new_page()
    again.goto(server[0] + page.evaluate("window.location.search"))
    again_lin = _until(lambda: _pillar_cells(again, "hb-pillar-linear"), "the view after reload")
    assert again_lin == lin
    assert _until(lambda: _pillar_at(again, lam), "the states after reload") == _pillar_cells(page)
    again.close()
    # bad input: the library's message, the last good view kept
    _type(page, "pillar_theta0", "2")
    with pytest.raises(ValueError) as info:
        hairbed.solve_pillar(0.0, 2.0)
    assert _until(lambda: _error_text(page), "the error message") == str(info.value)
    assert _pillar_cells(page).get("theta0") == "0.3"
    page.close()


def test_zz_server_clean_and_ctrl_c(server, browser):
    """Last: the server wrote no traceback, and Ctrl-C ends it with one line, status 130."""
    base, proc, err = server
    hosts = {urlparse(u).netloc for u in browser.requests if urlparse(u).scheme in ("http", "ws")}
    assert hosts == {urlparse(base).netloc}, hosts
    proc.send_signal(signal.SIGINT)
    try:
        code = proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        pytest.fail("hairbed explore did not stop on Ctrl-C")
    text = err.read_text()
    assert "Traceback" not in text, text
    assert code == 130, text
    assert text.strip().splitlines()[-1] == "hairbed: interrupted"
