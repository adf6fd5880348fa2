"""Stress ratio and rectification: analytic limits and the SI layer."""

import math

import numpy as np
import pytest

import hairbed
from hairbed import rheology
from hairbed.units import HairBed


@pytest.mark.parametrize(("eps", "theta0"), [(0.5, 0.0), (0.9, 0.3), (0.2, -1.2), (0.0, 0.5)])
def test_slow_flow_limit(eps, theta0):
    rest = 1 / (1 - eps * math.cos(theta0))
    assert rheology.stress_ratio(0.0, eps, theta0) == pytest.approx(rest, rel=1e-14)
    assert rheology.rest_stress_ratio(eps, theta0) == pytest.approx(rest, rel=1e-15)
    # O(omega^2) approach: h1 = cos(theta0) - omega^2 sin cos / (3 (1 - eps cos)) + ...
    w = 1e-6
    c, s = math.cos(theta0), math.sin(theta0)
    h1 = c - w * s * c / (3 * (1 - eps * c))
    assert rheology.stress_ratio(w, eps, theta0) == pytest.approx(1 / (1 - eps * h1), rel=1e-11)


@pytest.mark.parametrize("theta0", [-1.0, 0.0, 0.6])
def test_fast_flow_limit(theta0):
    # strong forcing lays the hair flat: h1 ~ sqrt(2 (1 - sin theta0)) / omega (theory.md §4)
    w = np.array([1e2, 1e4, 1e8])
    ratio = rheology.stress_ratio(w, 0.9, theta0)
    h1 = math.sqrt(2 * (1 - math.sin(theta0))) / np.sqrt(w)
    np.testing.assert_allclose(ratio - 1, 0.9 * h1, rtol=0.2)
    assert rheology.stress_ratio(1e12, 0.9, theta0) == pytest.approx(1.0, abs=1e-5)


def test_stress_ratio_is_omega_eps_over_omega_squared():
    # eq. (34): omega^2 = omega_eps^2 (1 - eps h1), a second route to the same number
    w = np.logspace(-2, 3, 11)
    sol = hairbed.solve(w, 0.7, 0.2)
    np.testing.assert_allclose(
        rheology.stress_ratio(w, 0.7, 0.2), sol.omega_eps**2 / w, rtol=1e-12
    )


def test_upright_bed_shear_thins():
    w = np.logspace(-3, 5, 40)
    ratio = rheology.stress_ratio(w, 0.8)
    assert np.all(np.diff(ratio) < 0)
    assert ratio[0] < 5.0 and ratio[-1] > 1.0


def test_rectification_limits():
    w = np.logspace(-3, 6, 19)
    np.testing.assert_allclose(rheology.rectification_ratio(w, 0.7, 0.0), 1.0, rtol=1e-14)
    assert rheology.rectification_ratio(0.0, 0.7, 0.5) == pytest.approx(1.0, rel=1e-14)
    r = rheology.rectification_ratio(w, 0.7, 0.5)
    assert np.all(r > 1.0)  # more resistance against the grain
    assert r[-1] == pytest.approx(1.0, abs=1e-2)  # flat hairs either way
    # and the definition through the mirror image
    np.testing.assert_allclose(rheology.rectification_ratio(w, 0.7, -0.5), 1 / r, rtol=1e-12)


def test_rectification_through_the_units_layer():
    # stress for v < 0 (against the grain) over v > 0, computed by HairBed's mirror image
    bed = HairBed(
        length=1e-3,
        radius=40e-6,
        youngs_modulus=2e6,
        channel_height=1.25e-3,
        viscosity=0.05,
        packing_fraction=0.1,
        base_angle=0.4,
    )
    speed = np.array([1e-3, 0.1, 1.0, 10.0])
    ratio = -bed.wall_shear_stress(-speed) / bed.wall_shear_stress(speed)
    np.testing.assert_allclose(bed.rectification_ratio(speed), ratio, rtol=1e-12)
    np.testing.assert_allclose(
        rheology.rectification_ratio(bed.omega2(speed), bed.eps, 0.4), ratio, rtol=1e-12
    )
    # HairState.stress_ratio is tau / (eta v / H)
    state = bed.deform(speed)
    np.testing.assert_allclose(
        state.stress_ratio, state.wall_shear_stress / (0.05 * speed / 1.25e-3), rtol=1e-13
    )


def test_root_choice_in_the_bistable_window():
    ratios = [rheology.stress_ratio(0.31, 0.95, -1.0, root=r) for r in ("low", "mid", "high")]
    heights = [hairbed.solve(0.31, 0.95, -1.0, root=r).tip_height for r in ("low", "mid", "high")]
    np.testing.assert_allclose(ratios, [1 / (1 - 0.95 * h) for h in heights], rtol=1e-13)
    # the flow has lifted the high-xi state nearest the vertical: the narrowest gap
    assert ratios[0] < ratios[1] < ratios[2]


def test_shapes_and_validation():
    out = rheology.stress_ratio(np.ones((2, 3)), np.array([0.1, 0.5, 0.9]))
    assert out.shape == (2, 3)
    assert isinstance(rheology.stress_ratio(1.0, 0.5), float)
    with pytest.raises(ValueError, match="omega2"):
        rheology.stress_ratio(-1.0, 0.5)
    with pytest.raises(ValueError, match="root"):
        rheology.rectification_ratio(1.0, 0.5, 0.2, root="top")
