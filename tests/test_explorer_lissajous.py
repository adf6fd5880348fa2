"""The explorer's Lissajous view of a bed in a rheometer beside the animated drive (issue 31).

The page is a thin layer over hairbed.rheometer.large_amplitude_shear: its points and
measures must be that call's (made here with the strain written from the drive, gamma0 =
A/(kappa omega)). The frames must be in phase with the pillar's: the bed's wall forcing,
Lambda_mean + kappa x strain rate, must equal the pillar's forcing at each frame (read from
the animation's own record). The URL carries the side view and the bed's inputs in that view
only; bad input names its key.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("panel")

from hairbed.explorer._drive import FRAMES, validate_drive  # noqa: E402
from hairbed.explorer._export import page_figures  # noqa: E402
from hairbed.explorer._model import DEFAULTS  # noqa: E402
from hairbed.explorer._page import ExplorerPage  # noqa: E402
from hairbed.rheometer import large_amplitude_shear  # noqa: E402

LAMBDA, THETA0, A, OMEGA, KAPPA, EPS = 2.0, 0.3, 2.0, 1.0, 1.0, 0.5
QUERY = (
    f"?mode=pillar&pillar_view=drive&forcing={LAMBDA}&pillar_theta0={THETA0}&amplitude={A}"
    f"&frequency={OMEGA}&mu=0.5&side_view=lissajous&bed_kappa={KAPPA}&bed_eps={EPS}"
)


def test_lissajous_beside_the_drive() -> None:
    page = ExplorerPage(QUERY, served=False)
    assert not page.errors
    link = page.link.object
    for part in ("side_view=lissajous", f"bed_kappa={KAPPA:g}", f"bed_eps={EPS:g}"):
        assert part in link, part
    panel = page.pillar
    a, li = panel._anim, panel._liss
    assert a is not None and a.status == 0 and li is not None and li.status == 0
    assert panel._side_views["lissajous"].visible and not panel._side_views["bode"].visible
    # the library's call, the strain amplitude written from the drive
    r = large_amplitude_shear(OMEGA, A / (KAPPA * OMEGA), eps=EPS, kappa=KAPPA, theta0=THETA0,
                              forcing=LAMBDA, samples=FRAMES)  # fmt: skip
    assert r.analysis is not None
    assert li.measures["large_modulus"] == r.analysis.large_modulus
    assert li.measures["minimum_viscosity"] == r.analysis.minimum_viscosity
    assert sorted(li.stress.tolist()) == sorted(r.stress.tolist())
    # in phase with the pillar: the bed's wall forcing is the pillar's at every frame
    np.testing.assert_allclose(LAMBDA + KAPPA * li.strain_rate, a.forcing, rtol=0, atol=1e-12)
    for k in range(FRAMES + 1):
        panel.next_frame(k)
        j = k % FRAMES
        assert panel.liss_dot.data == {"x": [li.strain[j]], "y": [li.stress[j]]}
        assert panel.liss_rate_dot.data["x"] == [li.strain_rate[j]]
    assert 'data-field="large_modulus"' in panel.liss_table.object
    assert page_figures(page) == [[panel.drive_fig, panel.liss_fig], [panel.liss_rate_fig]]
    doc = json.loads(panel._json_file().getvalue())
    assert doc["drive"]["inputs"]["side_view"] == "lissajous"
    assert doc["drive"]["lissajous"]["stress"] == li.stress.tolist()
    # bad input: the key named, the last good view kept
    page.text["bed_kappa"].value = "0"
    assert page.errors and "bed_kappa" in page.errors[0]
    assert panel._liss is li
    page.text["bed_kappa"].value = str(KAPPA)
    assert not page.errors
    # the Bode view: the bed's keys leave the link
    panel.side_view.value = "bode"
    assert not page.errors and "side_view=bode" in page.link.object
    assert "bed_kappa" not in page.link.object
    assert panel._side_views["bode"].visible and not panel._side_views["lissajous"].visible
    page.release()


def test_bad_side_view_is_named() -> None:
    # a choice the page does not offer stays as it was on the page (the Bode view) ...
    page = ExplorerPage(QUERY.replace("side_view=lissajous", "side_view=nyquist"), served=False)
    assert not page.errors and "side_view=bode" in page.link.object
    page.release()
    # ... and validation names it
    full = {**DEFAULTS, "side_view": "nyquist"}
    assert "side_view must be one of 'bode', 'lissajous'" in validate_drive(full, None)[1][0]
    full = {**DEFAULTS, "side_view": "lissajous", "amplitude": "0", "bed_eps": "1"}
    problems = validate_drive(full, None)[1]
    assert "bed_eps must be the bed's eps = L/H in [1e-6, 1), got '1'" in problems
    assert "amplitude must be > 0 in the Lissajous view (a strain to shear by)" in problems
