"""The pillar sensor's figures in time draw the library's numbers: the Bode plot is
``Pillar.frequency_response``'s, the step response and the film strip ``Pillar.simulate``'s,
recomputed here on the figures' own grids."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from hairbed import ModelValidityWarning, Pillar  # noqa: E402
from hairbed.plotting import FIGURES, fig_pillar_bode, fig_pillar_film, fig_pillar_step  # noqa: E402

RHO = 1000.0


@pytest.fixture(autouse=True)
def _quiet() -> object:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        yield


def _pillar(fluid: str) -> Pillar:
    return Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid=fluid)


def _line(fig: Any, gid: str) -> Any:
    for ax in fig.axes:
        for ln in ax.lines:
            if ln.get_gid() == gid:
                return ln
    raise AssertionError(f"no line {gid}")


def test_registered_for_make_run() -> None:
    assert FIGURES["pillar_bode"] is fig_pillar_bode
    assert FIGURES["pillar_step"] is fig_pillar_step
    assert FIGURES["pillar_film"] is fig_pillar_film


def test_bode_draws_the_response_with_resonance_and_bandwidth() -> None:
    fig = fig_pillar_bode(num=30)
    for fluid in ("water", "air"):
        r = _pillar(fluid).frequency_response(np.geomspace(1.0, 5000.0, 30), pillar_density=RHO)
        mag = _line(fig, f"magnitude_{fluid}")
        f = np.asarray(mag.get_xdata())
        ref = _pillar(fluid).frequency_response(f, pillar_density=RHO)
        np.testing.assert_allclose(mag.get_ydata(), ref.magnitude, rtol=1e-12)
        phase = _line(fig, f"phase_{fluid}").get_ydata()
        np.testing.assert_allclose(phase, np.degrees(np.unwrap(ref.phase)), rtol=1e-12, atol=1e-9)
        dot = _line(fig, f"resonance_{fluid}")
        assert dot.get_xdata()[0] == pytest.approx(r.resonance_frequency, rel=1e-12)
        assert r.resonance_frequency in f  # the peak itself is on the curve
        assert dot.get_ydata()[0] == pytest.approx(np.max(ref.magnitude), rel=1e-12)
        gid = f"bandwidth_{fluid}"
        spans: list[Any] = [p for ax in fig.axes for p in ax.patches if p.get_gid() == gid]
        assert len(spans) == 2
        for span in spans:
            assert span.get_x() == 1.0
            assert span.get_x() + span.get_width() == pytest.approx(r.bandwidth, rel=1e-12)
    # the two resonances as the sensor layer states them (README: 206.7 Hz in water)
    water = float(_line(fig, "resonance_water").get_xdata()[0])
    air = float(_line(fig, "resonance_air").get_xdata()[0])
    assert 150.0 < water < 260.0 and air > 400.0


def test_step_draws_the_simulation_and_the_static_state() -> None:
    fig = fig_pillar_step(num=50, periods=1.5)
    ring = _line(fig, "ringing")
    over = _line(fig, "overdamped")
    t = 1e-3 * np.asarray(ring.get_xdata())
    p = _pillar("water")
    ref = p.simulate(5.0, t, pillar_density=RHO)
    np.testing.assert_allclose(ring.get_ydata(), 1e6 * ref.tip_deflection, rtol=1e-12)
    ref_o = p.simulate(5.0, t, overdamped=True)
    np.testing.assert_allclose(over.get_ydata(), 1e6 * ref_o.tip_deflection, rtol=1e-12)
    static = 1e6 * p.deform(5.0).tip_deflection
    assert _line(fig, "static").get_ydata()[0] == pytest.approx(static, rel=1e-14)
    # it rings: the first overshoot is well above the static deflection
    assert np.max(ring.get_ydata()) > 1.3 * static
    # the overdamped step has settled on the static state by the end
    assert over.get_ydata()[-1] == pytest.approx(static, rel=1e-6)
    # the time axis spans 1.5 periods 2 pi sqrt(mu) T/beta_1^2 (written here)
    assert t[-1] == pytest.approx(1.5 * _figure_period(p), rel=1e-12)


def test_film_strip_draws_the_shapes_of_the_step() -> None:
    fig = fig_pillar_film(frames=4, periods=1.0)
    assert len(fig.axes) == 4
    titles = [float(ax.get_title().split()[0]) * 1e-3 for ax in fig.axes]
    p = _pillar("water")
    run = p.simulate(5.0, np.linspace(0.0, _figure_period(p), 4), pillar_density=RHO)
    for k in range(4):
        ln = _line(fig, f"frame_{k}")
        np.testing.assert_allclose(ln.get_xdata(), 1e6 * run.x[k], rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(ln.get_ydata(), 1e6 * run.z[k], rtol=1e-12, atol=1e-9)
        assert titles[k] == pytest.approx(run.time[k], rel=5e-3, abs=1e-9)
    # the last node of each shape is the simulated tip
    np.testing.assert_allclose(run.x[:, -1], run.tip_deflection, rtol=1e-12)
    st = p.deform(5.0)
    tip = _line(fig, "static_tip")
    assert tip.get_xdata()[0] == pytest.approx(1e6 * st.tip_deflection, rel=1e-14)


def _figure_period(p: Pillar) -> float:
    """2 pi sqrt(mu) T/beta_1^2 from the definitions."""
    zeta = 4.0 * math.pi * p.viscosity / (math.log(40.0) + 0.5)
    t_scale = zeta * 1e-12 / (1e6 * math.pi * (50e-6) ** 4 / 4.0)
    mu = (RHO + p.density) * math.pi * (50e-6) ** 2 / (zeta * t_scale)  # type: ignore[operator]
    return 2.0 * math.pi * math.sqrt(mu) * t_scale / 1.875104068711961**2
