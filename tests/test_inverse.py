"""The inverse problem, checked against the forward solver (an independent root find)."""

import math

import numpy as np
import pytest

import hairbed
from hairbed import inverse

OMEGA2 = np.concatenate([np.logspace(-3, 4, 22), [1e6]])  # xi rounds to 1 above ~400
EPS = [0.0, 0.5, 0.9]
THETA0 = [-1.0, -0.3, 0.0, 0.4, 1.0]


@pytest.mark.parametrize("eps", EPS)
@pytest.mark.parametrize("theta0", THETA0)
def test_round_trip_tip_deflection(eps, theta0):
    sol = hairbed.solve(OMEGA2, eps, theta0)
    back = inverse.omega2_from_tip_deflection(sol.tip_deflection, eps, theta0)
    np.testing.assert_allclose(back, OMEGA2, rtol=1e-10, atol=0)


def test_round_trip_strong_forcing_where_xi_is_one():
    w = np.array([1e4, 1e6, 1e8])
    sol = hairbed.solve(w, 0.5, 0.2)
    assert np.all(sol.xi == 1.0)  # xi carries no information here: t does
    back = inverse.solution_from_tip_deflection(sol.tip_deflection, 0.5, 0.2)
    np.testing.assert_allclose(back.omega2, w, rtol=1e-10)
    np.testing.assert_allclose(back.tip_height, sol.tip_height, rtol=1e-10)


def test_tip_deflection_determines_each_of_three_coexisting_states():
    # theta0 = -1, eps = 0.95: three physical states at omega^2 = 0.31 (theory.md §5)
    states = [hairbed.solve(0.31, 0.95, -1.0, root=r) for r in ("low", "mid", "high")]
    x1 = [s.tip_deflection for s in states]
    assert x1[0] < x1[1] < x1[2]
    back = inverse.solution_from_tip_deflection(x1, 0.95, -1.0)
    np.testing.assert_allclose(back.omega2, 0.31, rtol=1e-10)
    np.testing.assert_allclose(back.xi, [s.xi for s in states], rtol=1e-10)


@pytest.mark.parametrize("theta0", [-1.4, -1.0, -0.3, 0.0, 0.7, 1.4])
def test_tip_deflection_is_monotone_on_the_physical_branch(theta0):
    # the premise of a unique answer (theory.md §5), on a dense scan of the branch
    t = np.linspace(-20, 60, 4001)
    x1 = np.asarray(hairbed.from_parameter(t, 0.5, theta0).tip_deflection)
    assert np.all(np.diff(x1) >= 0)


def test_weak_forcing_matches_the_linear_limit():
    # below ~1e-5 the inverse uses a series; compare with the first-order (linear) answer,
    # whose relative error is O(omega^2)
    for theta0 in (-0.8, 0.0, 0.6):
        for dx in (1e-300, 1e-20, 1e-12, 1e-8):
            x1 = math.sin(theta0) + dx
            if x1 - math.sin(theta0) == 0.0:
                continue
            w = inverse.omega2_from_tip_deflection(x1, 0.5, theta0)
            lin = inverse.linear_omega2_from_tip_deflection(x1, 0.5, theta0)
            assert w == pytest.approx(lin, rel=1e-6)
    assert inverse.omega2_from_tip_deflection(0.0, 0.5) == 0.0
    assert inverse.omega2_from_tip_deflection(math.sin(-0.7), 0.5, -0.7) == 0.0


def test_series_and_root_find_agree_where_they_meet():
    # omega_eps^2 = 1e-5 is the switch: the two methods on either side must join smoothly
    theta0 = 0.3
    c2 = math.cos(theta0) ** 2
    x1 = math.sin(theta0) + np.array([0.999, 1.001]) * 1e-5 * c2 / 3
    w = inverse.omega2_from_tip_deflection(x1, 0.2, theta0)
    assert w[1] / w[0] == pytest.approx(1.001 / 0.999, rel=2e-7)


def test_linear_slope_against_the_exact_solution():
    for eps, theta0 in [(0.0, 0.0), (0.5, 0.0), (0.9, 0.0), (0.5, 0.3), (0.9, -1.0)]:
        w = 1e-7
        sol = hairbed.solve(w, eps, theta0)
        slope = (sol.tip_deflection - math.sin(theta0)) / w
        assert slope == pytest.approx(inverse.tip_deflection_slope(eps, theta0), rel=1e-5)
    # the cantilever under a point load at the tip: 1 / (3 (1 - eps)) for upright hairs
    assert inverse.tip_deflection_slope(0.5) == pytest.approx(2 / 3, rel=1e-15)


def linear_error(x1, eps, theta0=0.0):
    exact = inverse.omega2_from_tip_deflection(x1, eps, theta0)
    return inverse.linear_omega2_from_tip_deflection(x1, eps, theta0) / exact - 1


def test_where_the_linear_calibration_fails():
    # measured: 1% at x1 = 0.098 and 10% at x1 = 0.31 (eps = 0); 0.040 and 0.13 (eps = 0.9)
    assert abs(linear_error(0.09, 0.0)) < 0.01 < abs(linear_error(0.11, 0.0))
    assert abs(linear_error(0.30, 0.0)) < 0.10 < abs(linear_error(0.32, 0.0))
    assert abs(linear_error(0.035, 0.9)) < 0.01 < abs(linear_error(0.045, 0.9))
    assert abs(linear_error(0.12, 0.9)) < 0.10 < abs(linear_error(0.14, 0.9))
    assert linear_error(0.5, 0.5) < -0.2  # it always underestimates the forcing


@pytest.mark.parametrize("bad", [1.0000000000000002, 1.5, -0.01])
def test_tip_deflection_out_of_range(bad):
    with pytest.raises(ValueError, match=r"x1 must lie in \[sin\(theta0\), 1\)"):
        inverse.omega2_from_tip_deflection(bad, 0.5, 0.0)


FLAT = r"x1 must lie in \[sin\(theta0\), 1\) .*got 1\.0.*lying flat.*omega2 -> inf"


@pytest.mark.parametrize("theta0", [0.0, -1.2, 0.7, 1.5707963])
def test_a_flat_hair_is_refused_by_every_inverse(theta0):
    """x1 = 1 is the limit omega2 -> inf (issue 19): no inverse returns it as a state (it gave
    omega2 = 8.7e31 at theta0 = 0). Near pi/2 solve's x1 rounds to 1 at moderate forcing;
    just below 1 the inverse still answers, and gives back the state's tip deflection."""
    with pytest.raises(ValueError, match=FLAT):
        inverse.omega2_from_tip_deflection(1.0, 0.5, theta0)
    with pytest.raises(ValueError, match=FLAT):
        inverse.solution_from_tip_deflection(1.0, 0.5, theta0)
    with pytest.raises(ValueError, match=FLAT):
        inverse.linear_omega2_from_tip_deflection(1.0, 0.5, theta0)
    with pytest.raises(ValueError, match=r"x1 must lie .*\(first at index 1\)"):
        inverse.omega2_from_tip_deflection(np.array([np.sin(theta0), 1.0]), 0.5, theta0)
    below = float(np.nextafter(1.0, 0.0))
    if below > np.sin(theta0):
        sol = inverse.solution_from_tip_deflection(below, 0.5, theta0)
        assert sol.status == 0 and np.isfinite(sol.omega2) and sol.tip_deflection == below
    # the tip height and the bed refuse the same limit
    with pytest.raises(ValueError, match=r"h1 must lie in \[1e-150"):
        inverse.omega2_from_tip_height(0.0, 0.5, min(theta0, 1.5))
    bed = hairbed.HairBed(
        length=1e-3, radius=5e-5, youngs_modulus=1e6, channel_height=2e-3, viscosity=1.0,
        spacing=4e-4, base_angle=min(theta0, 1.5),
    )  # fmt: skip
    for d in (1e-3, -1e-3, float(np.nextafter(1e-3, 0.0))):
        if abs(d) / 1e-3 >= 1.0:
            with pytest.raises(ValueError, match=r"must lie in \(-length, length\).*flat"):
                bed.velocity_from_tip_deflection(d)


def test_a_deflection_that_rounds_to_sin_theta0_at_one_is_the_rest_state():
    """Where even sin(theta0) rounds to 1, x1 = 1 is the hair at rest (omega2 = 0)."""
    sol = inverse.solution_from_tip_deflection(1.0, 0.5, 1.5707963267948963)
    assert sol.t == -np.inf and sol.omega2 == 0.0


def test_tip_deflection_input_validation():
    with pytest.raises(ValueError, match="x1 must lie"):
        inverse.omega2_from_tip_deflection(0.1, 0.5, 0.2)  # below sin(0.2)
    with pytest.raises(ValueError, match="eps"):
        inverse.omega2_from_tip_deflection(0.5, 1.0)
    with pytest.raises(ValueError, match="theta0"):
        inverse.omega2_from_tip_deflection(0.5, 0.5, 2.0)
    with pytest.raises(ValueError, match="finite"):
        inverse.omega2_from_tip_deflection(float("nan"), 0.5)


def test_vectorised_shapes():
    x1 = np.array([[0.1, 0.5], [0.7, 0.9]])
    w = inverse.omega2_from_tip_deflection(x1, np.array([0.0, 0.5]), 0.0)
    assert w.shape == (2, 2)
    assert w[1, 1] == pytest.approx(inverse.omega2_from_tip_deflection(0.9, 0.5), rel=1e-14)
    assert isinstance(inverse.omega2_from_tip_deflection(0.5, 0.5), float)
    assert inverse.omega2_from_tip_height([0.5, 0.6, 0.7], 0.5).shape == (3, 2)


# -- tip height ----------------------------------------------------------------------------------


@pytest.mark.parametrize("theta0", [0.0, 0.5, 1.2])
def test_tip_height_has_one_answer_for_upright_or_downstream_hairs(theta0):
    w = np.logspace(-2, 4, 13)
    sol = hairbed.solve(w, 0.6, theta0)
    answers = inverse.omega2_from_tip_height(sol.tip_height, 0.6, theta0)
    np.testing.assert_allclose(answers[:, 0], w, rtol=1e-10)
    assert np.all(np.isnan(answers[:, 1]))


def test_tip_height_has_two_answers_for_a_hair_leaning_into_the_flow():
    eps, theta0 = 0.3, -0.8  # no folds here: solve gives one state per forcing
    h_max = inverse.max_tip_height(theta0)
    # against a dense scan of the branch
    t = np.linspace(-15, 15, 30001)
    scan = np.asarray(hairbed.from_parameter(t, eps, theta0).tip_height)
    assert scan.max() <= h_max * (1 + 1e-15)
    t_fine = t[np.argmax(scan)] + np.linspace(-2e-3, 2e-3, 20001)
    fine = np.asarray(hairbed.from_parameter(t_fine, eps, theta0).tip_height)
    assert fine.max() <= h_max * (1 + 1e-15)
    assert h_max == pytest.approx(fine.max(), abs=1e-13)
    assert math.cos(theta0) < h_max <= 1.0
    targets = math.cos(theta0) + np.array([0.1, 0.5, 0.9]) * (h_max - math.cos(theta0))
    answers = inverse.omega2_from_tip_height(targets, eps, theta0)
    assert np.all(np.isfinite(answers))
    for col in range(2):
        sol = hairbed.solve(answers[:, col], eps, theta0)
        np.testing.assert_allclose(sol.tip_height, targets, rtol=1e-10)
    # first answer on the rising limb (smaller xi): the hair still leans into the flow
    first = hairbed.solve(answers[:, 0], eps, theta0)
    second = hairbed.solve(answers[:, 1], eps, theta0)
    assert np.all(first.xi < second.xi)
    # below the rest height only the bent-over state remains
    low = inverse.omega2_from_tip_height(0.3, eps, theta0)
    assert np.isnan(low[1])
    assert hairbed.solve(low[0], eps, theta0).tip_height == pytest.approx(0.3, rel=1e-10)
    # exactly the rest height: rest itself, and a bent-over state
    rest = inverse.omega2_from_tip_height(math.cos(theta0), eps, theta0)
    assert rest[0] == 0.0 and rest[1] > 0


def test_tip_height_round_trip_in_the_bistable_window():
    states = [hairbed.solve(0.31, 0.95, -1.0, root=r) for r in ("low", "mid", "high")]
    for s in states:
        answers = inverse.omega2_from_tip_height(s.tip_height, 0.95, -1.0)
        assert np.nanmin(np.abs(answers - 0.31)) < 1e-9


@pytest.mark.parametrize(("h1", "theta0"), [(0.0, 0.0), (1.01, 0.0), (0.99, 0.2), (1.0, -0.5)])
def test_tip_height_out_of_range(h1, theta0):
    with pytest.raises(ValueError, match="h1 must lie in"):
        inverse.omega2_from_tip_height(h1, 0.5, theta0)
