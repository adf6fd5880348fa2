"""The explorer's drive view in a real browser (issue 31): ``hairbed explore`` served, Debian's
Chromium driven by Playwright (the fixtures and flags of tests/test_explorer_browser.py:
headless, a fresh profile, a dead proxy for everything but the loopback, never ``playwright
install``).

Checked against the library (computed here, never read from the app): the linear response
in the readout (hairbed.dynamics.linearise_pillar). The pillar moves: the shape the browser
holds changes between two reads and stays on the tip's path; the server's time per frame is
shown; the URL carries the drive's inputs, and a fresh page from it shows the same numbers;
Sader's drag without a slenderness is the library's message, the last good view kept.
"""

from __future__ import annotations

import math
import time

import pytest
from test_explorer_browser import (  # noqa: F401  (the fixtures)
    _error_text,
    _search,
    _type,
    _until,
    browser,
    server,
    shots,
)

import hairbed
from hairbed.dynamics import linearise_pillar

QUERY = "?mode=pillar&pillar_view=drive&forcing=8&pillar_theta0=0.3&amplitude=1&frequency=3&mu=1"
_SHAPE_JS = """() => {
  const doc = Bokeh.documents[0];
  const src = doc.get_model_by_name('hb-drive-shape');
  const path = doc.get_model_by_name('hb-drive-path');
  if (!src || !path || src.data.x.length === 0) return null;
  return {x: Array.from(src.data.x), z: Array.from(src.data.y),
          px: Array.from(path.data.x), pz: Array.from(path.data.y)};
}"""


def _readout(page) -> dict[str, str]:
    return dict(
        page.locator("table.hb-drive-table td[data-field]").evaluate_all(
            "els => els.map(e => [e.dataset.field, e.textContent])"
        )
    )


def test_the_pillar_moves_beside_its_bode_view(browser, server, shots):  # noqa: F811
    page = browser.new_page()
    page.goto(server[0] + QUERY)
    cells = _until(lambda: _readout(page).get("linear_gain") and _readout(page), "the readout")
    st = hairbed.solve_pillar(8.0, 0.3)
    lin = linearise_pillar(st, mu=2.0, tangential_mass=0.5)  # rho_f = rho_s: chi = 1/2
    h = complex(lin.frequency_response(3.0).tip_deflection[0])
    assert float(cells["linear_gain"]) == pytest.approx(abs(h), rel=1e-10)
    assert float(cells["linear_phase"]) == pytest.approx(math.atan2(h.imag, h.real), rel=1e-10)
    # A = 1 is not small: the first harmonic is near the linear gain, not equal (1.5 %)
    assert float(cells["harmonic_gain"]) == pytest.approx(abs(h), rel=0.05)
    # the pillar moves: two reads of the shape the browser draws differ, the tip on its path
    first = _until(lambda: page.evaluate(_SHAPE_JS), "the animated shape")
    page.wait_for_timeout(300)
    second = page.evaluate(_SHAPE_JS)
    assert second["x"] != first["x"]
    for shot in (first, second):
        px, pz = shot["px"], shot["pz"]
        assert min(px) - 1e-12 <= shot["x"][-1] <= max(px) + 1e-12
        assert min(pz) - 1e-12 <= shot["z"][-1] <= max(pz) + 1e-12
    frames = _until(lambda: _readout(page).get("frame_p90"), "the server's time per frame")
    assert math.isfinite(float(frames))
    page.screenshot(path=str(shots / "explorer-pillar-drive.png"), full_page=True)
    args = _search(page)
    want = {"pillar_view": "drive", "amplitude": "1", "frequency": "3", "mu": "1",
            "drag_model": "quasi-steady"}  # fmt: skip
    assert {k: args.get(k) for k in want} == want
    again = browser.new_page()
    again.goto(server[0] + page.evaluate("window.location.search"))
    again_cells = _until(lambda: _readout(again).get("linear_gain") and _readout(again), "reload")
    assert again_cells["linear_gain"] == cells["linear_gain"]
    assert again_cells["harmonic_gain"] == cells["harmonic_gain"]
    again.close()
    # Sader's drag needs the slenderness: the message, then the drag model in the URL
    page.locator(".hb-drag-model button", has_text="Sader").click()
    assert "slenderness" in _until(lambda: _error_text(page), "the error message")
    _type(page, "slenderness", "20")
    _until(lambda: _search(page).get("drag_model") == "sader", "the Sader drag in the URL")
    assert not _error_text(page)
    page.close()
    # a closed tab stops its frames: nothing is written to its closed websocket
    time.sleep(2.0)
    assert "Traceback" not in server[2].read_text()
    hosts = {u.split("/")[2] for u in browser.requests if u.startswith(("http", "ws"))}
    assert hosts == {server[0].split("/")[2]}, hosts
