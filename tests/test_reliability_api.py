"""Issue 33, the library half: each "wrong or silent" item and each trap of the Python API,
reproduced as a test.

Every expected value comes from an independent source: a closed form of the rest state or
the linear theory, finite differences of the solver's own states at a different input, or the
plain formula at a non-zero drive.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hairbed
from hairbed.sensitivity import derivatives_at

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}


# -- 1. tracebacks from inside numpy ------------------------------------------------------


def test_loaded_guess_of_another_shape_is_refused_by_name() -> None:
    guess = hairbed.solve(np.array([0.5, 1.0, 2.0]), 0.5, 0.1)
    with pytest.raises(ValueError, match=r"\bguess\b.*shape \(\).*\(3,\)"):
        hairbed.solve_loaded(0.5, 0.5, 0.1, pi=1.0, guess=guess)
    with pytest.raises(ValueError, match=r"\bguess\b"):
        hairbed.solve_loaded(np.array([0.5, 1.0]), 0.5, 0.1, pi=1.0, guess=guess)


def test_loaded_guess_that_broadcasts_is_used() -> None:
    w = np.array([0.5, 1.0, 2.0])
    st = hairbed.solve_loaded(w, 0.5, 0.1, pi=0.0, guess=hairbed.solve(1.0, 0.5, 0.1))
    ref = hairbed.solve(w, 0.5, 0.1)  # pi = 0: the closed form
    np.testing.assert_allclose(st.tip_height, ref.tip_height, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "make",
    [
        lambda: hairbed.derivatives(np.array([]), 0.5, pi=1.0),
        lambda: hairbed.derivatives(np.array([]), 0.5, q=1.0),
        lambda: derivatives_at(hairbed.solve_pillar(np.array([]))),
        lambda: derivatives_at(hairbed.solve_loaded(np.zeros((0, 2)), 0.5, pi=1.0)),
        lambda: hairbed.derivatives(np.array([]), 0.5),
    ],
)
def test_derivatives_of_empty_states_are_empty(make) -> None:
    d = make()
    assert np.shape(d.status)[-1:] in ((0,), (2,)) and np.size(d.status) == 0
    for row in d.table.values():
        for value in row.values():
            assert np.size(value) == 0


# -- 3. NaN with status 0 -----------------------------------------------------------------


@pytest.mark.parametrize("theta0", [0.0, 0.4, -0.3])
def test_stress_ratio_at_zero_pump_drive_is_its_limit(theta0: float) -> None:
    bed = hairbed.HairBed(**BED, base_angle=theta0)
    gap = BED["channel_height"] - BED["length"] * math.cos(theta0)  # the hair at rest
    height = BED["channel_height"]
    st = bed.deform(pressure_gradient=0.0)
    assert st.stress_ratio == pytest.approx(gap / height, rel=1e-14)  # tau/bare = g/H
    st = bed.deform(flow_rate=0.0)
    assert st.stress_ratio == pytest.approx((height / gap) ** 2, rel=1e-14)
    sw = bed.sweep(pressure_gradient=np.array([0.0, 1e-9]))
    assert np.all(np.isfinite(np.asarray(sw["stress_ratio"])))
    np.testing.assert_allclose(np.asarray(sw["stress_ratio"]), gap / height, rtol=1e-8)


def test_valve_curve_at_zero_drop_has_a_finite_stress_ratio() -> None:
    bed = hairbed.HairBed(**BED, base_angle=0.3)
    curve = hairbed.valve.valve_curve(bed, np.array([0.0, 1e-9]), 0.01)
    ratio = np.asarray(curve.states.stress_ratio)
    assert np.all(np.isfinite(ratio))
    assert ratio[0] == pytest.approx(ratio[1], rel=1e-8)


@pytest.mark.parametrize("theta0", [0.0, -1.2, 0.5])
def test_branch_parameter_derivatives_at_rest_match_differences(theta0: float) -> None:
    d = hairbed.derivatives(0.0, 0.9, theta0)
    assert d.status == 0
    assert d.dt["omega2"] == math.inf
    # t(omega2, eps, theta0) - ln(omega2) has a finite limit at rest: central differences of
    # the solver's t at a weak forcing (t is exact to rounding there)
    w, h = 1e-10, 1e-6

    def t(eps: float, t0: float) -> float:
        return float(hairbed.solve(w, eps, t0).t)

    fd_eps = (t(0.9 + h, theta0) - t(0.9 - h, theta0)) / (2 * h)
    fd_t0 = (t(0.9, theta0 + h) - t(0.9, theta0 - h)) / (2 * h)
    assert d.dt["eps"] == pytest.approx(fd_eps, rel=1e-6)
    assert d.dt["theta0"] == pytest.approx(fd_t0, rel=1e-6)
