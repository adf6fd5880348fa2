"""The explorer's drive view (issue 31): the pillar moving in an oscillating flow beside its
Bode view, without a browser (tests/test_explorer_drive_browser.py has the served page).

References, computed here with the library and from the definitions, never read from the
app: the Bode view against hairbed.dynamics.linearise_pillar's transfer function, with the
inertia number and Sader's Reynolds scale computed from an SI pillar (PDMS-like, in a fluid
of its own density); the animation's first harmonic against that linear response, its error
O(A^2) (two amplitudes); each frame the page sends is the run's shape at that frame.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import linearise_pillar

pytest.importorskip("panel")

from hairbed.explorer._drive import FRAMES, drive_animation, validate_drive  # noqa: E402
from hairbed.explorer._page import ExplorerPage  # noqa: E402
from hairbed.explorer._pillar import validate_pillar  # noqa: E402


def _si_groups(slender: float) -> tuple[float, float]:
    """(mu of the solid, Sader's R) of a pillar L = 1 mm, a = L/slender, E = 1 MPa, rho_s =
    rho_f = 1000 kg/m^3, eta = 1 mPa s, from the definitions (theory.md §12, §14)."""
    length, e, rho, eta = 1e-3, 1e6, 1000.0, 1e-3
    a = length / slender
    zeta = 4.0 * math.pi * eta / (math.log(2.0 * slender) + 0.5)
    t = zeta * length**4 / (e * math.pi * a**4 / 4.0)
    mu = rho * math.pi * a * a / (zeta * t)
    return mu, rho * (2.0 * a) ** 2 / (4.0 * eta * t)


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_bode_view_and_the_nonlinear_first_harmonic() -> None:
    slender = 20.0
    mu, reynolds = _si_groups(slender)
    lam, theta0, gamma = 8.0, 0.3, 0.5
    st = hairbed.solve_pillar(lam, theta0, gamma=gamma)
    args = (lam, theta0, "sublayer", None, gamma, 0.0, slender)
    omega = 3.0
    sader = drive_animation(*args, 0.2, omega, mu, "sader")
    want = linearise_pillar(st, mu=mu).frequency_response(
        np.append(sader.omega, omega), unsteady_drag=(reynolds, slender)
    )
    assert np.allclose(sader.bode, want.tip_deflection[:-1], rtol=1e-12, atol=0)
    assert sader.bode_now == pytest.approx(want.tip_deflection[-1], rel=1e-12)
    # quasi-steady: the fluid's added mass (rho_f = rho_s) in the normal mass, chi = 1/2
    lin = linearise_pillar(st, mu=2.0 * mu, tangential_mass=0.5)
    h = complex(lin.frequency_response(omega).tip_deflection[0])
    errs = []
    for amp in (2.0, 1.0):  # large enough that the O(A^2) term is above the run's 1e-4
        a = drive_animation(*args, amp, omega, mu, "quasi-steady")
        assert a.status == 0 and a.x.shape == (FRAMES, 17)
        assert a.bode_now == pytest.approx(h, rel=1e-12)
        # the frames are one period of Lambda + A sin(omega t) at the run's times
        want_forcing = lam + amp * np.sin(omega * (a.t + a.settle))
        assert np.allclose(a.forcing, want_forcing, rtol=1e-12, atol=1e-12)
        # the tip at each frame: x1 = int_0^1 sin(theta) ds of the run's angles
        assert np.allclose(a.x[:, 0], 0.0, atol=1e-15) and np.allclose(a.z[:, 0], 0.0)
        errs.append(abs(a.harmonic - h) / abs(h))
    assert errs[0] <= 0.05, errs
    assert abs(errs[0] / errs[1] - 4.0) <= 0.4, errs  # O(A^2)


def test_drive_inputs_are_checked_by_name() -> None:
    full = {"amplitude": "-1", "frequency": "0", "mu": "nan", "drag_model": "stokes"}
    _, problems = validate_drive(full, None)
    assert len(problems) == 4
    for key in ("amplitude", "frequency", "mu", "drag_model"):
        assert any(p.startswith(key) for p in problems), key
    with pytest.raises(ValueError, match="slenderness"):
        validate_pillar({"mode": "pillar", "pillar_view": "drive", "drag_model": "sader"})
    # outside the drive view its inputs are not read (nor carried by the link)
    p = validate_pillar({"mode": "pillar", "amplitude": "-1"})
    assert p.drive is None


def test_page_url_frames_and_json() -> None:
    query = "?mode=pillar&pillar_view=drive&forcing=2&amplitude=0.4&frequency=4&mu=0.5"
    page = ExplorerPage(query, served=False)
    assert not page.errors
    link = page.link.object
    for part in ("pillar_view=drive", "amplitude=0.4", "frequency=4", "mu=0.5",
                 "drag_model=quasi-steady"):  # fmt: skip
        assert part in link, part
    panel = page.pillar
    a = panel._anim
    assert a is not None and a.status == 0
    assert panel.dr_shape.data["x"] == a.x[0].tolist()
    for k in range(1, FRAMES + 2):  # one period and one frame: the loop starts again
        panel.next_frame(k)
        assert panel.dr_shape.data["x"] == a.x[k % FRAMES].tolist()
        assert panel.dr_tip.data["y"] == [float(a.tip_z[k % FRAMES])]  # the tip's dot
    panel.next_frame()  # the clock's frame (a served page's periodic callback)
    assert panel.dr_shape.data["x"] in [row.tolist() for row in a.x]
    assert len(panel.frame_ms) == FRAMES + 2
    assert 'data-field="frame_p90"' in panel.drive_table.object
    from hairbed.explorer._export import page_figures

    assert page_figures(page) == [[panel.drive_fig, panel.bode_gain_fig], [panel.bode_phase_fig]]
    doc = json.loads(panel._json_file().getvalue())
    assert doc["drive"]["inputs"]["amplitude"] == "0.4"
    assert len(doc["drive"]["tip_deflection"]) == FRAMES
    # the Sader drag needs the slenderness: the message, the last good view kept
    panel.drag_model.value = "sader"
    assert page.errors and "slenderness" in page.errors[0]
    assert panel._anim is a
    page.text["slenderness"].value = "20"
    assert not page.errors and "drag_model=sader" in page.link.object
    panel.view.value = "shape"  # another view: no animation, no drive keys in the link
    assert panel._anim is None and "amplitude" not in page.link.object
    page.release()
