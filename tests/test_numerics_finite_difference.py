"""The paper's finite differences against the analytic solution: accuracy, order, branches."""

import dataclasses
import itertools

import numpy as np
import pytest

import hairbed
from hairbed.numerics import finite_difference

#: FD with N = 400 segments: measured errors are <= 5e-6 over this sweep (h2 ~ 6e-6).
FD400_ATOL = 2e-5

SWEEP = list(itertools.product([0.1, 2.0, 10.0, 30.0], [0.0, 0.5, 0.9], [0.0, -0.7, 0.7]))


@pytest.mark.parametrize("omega2, eps, theta0", SWEEP)
def test_matches_analytic(omega2, eps, theta0):
    exact = hairbed.solve(omega2, eps, theta0)
    res = finite_difference(omega2, eps, theta0, num=400)
    assert res.success and res.status == 0
    assert (res.sign, res.n) == (1, 0) and res.physical
    assert res.tip_height == pytest.approx(exact.tip_height, abs=FD400_ATOL)
    assert res.tip_deflection == pytest.approx(exact.tip_deflection, abs=FD400_ATOL)
    assert res.xi == pytest.approx(exact.xi, abs=FD400_ATOL)
    assert res.omega_eps == pytest.approx(exact.omega_eps, rel=FD400_ATOL)
    # the base curvature sits in the boundary layer: measured relative error up to 2e-5
    assert res.base_curvature == pytest.approx(exact.base_curvature, rel=1e-4)
    np.testing.assert_allclose(res.theta, exact.theta(res.sigma), atol=FD400_ATOL)
    np.testing.assert_allclose(res.z, exact.z(res.sigma), atol=FD400_ATOL)
    np.testing.assert_allclose(res.x, exact.x(res.sigma), atol=FD400_ATOL)


def test_paper_example_values():
    # theory.md §3: omega2 = 2, eps = 0.5, theta0 = 0 (values typed in, not computed here)
    res = finite_difference(2.0, 0.5, num=1000)
    assert res.xi == pytest.approx(0.847253916541247, abs=1e-6)
    assert res.tip_height == pytest.approx(0.732706963462228, abs=1e-6)
    assert res.tip_deflection == pytest.approx(0.615831536923675, abs=1e-6)


@pytest.mark.parametrize("omega2, eps, theta0", [(2.0, 0.5, 0.0), (10.0, 0.9, -0.7)])
def test_second_order(omega2, eps, theta0):
    exact = hairbed.solve(omega2, eps, theta0)
    Ns = np.array([40, 80, 160, 320])
    results = [finite_difference(omega2, eps, theta0, num=int(N)) for N in Ns]
    for field in ("tip_height", "tip_deflection"):
        err = np.abs(np.array([getattr(r, field) for r in results]) - getattr(exact, field))
        order = -np.polyfit(np.log(Ns), np.log(err), 1)[0]
        assert 1.8 <= order <= 2.2, (field, order, err)


def test_newton_and_root_agree():
    a = finite_difference(2.0, 0.5, 0.3, num=80, method="newton")
    b = finite_difference(2.0, 0.5, 0.3, num=80, method="root")
    assert a.success and b.success
    np.testing.assert_allclose(a.theta, b.theta, atol=1e-9)
    assert a.method == "finite_difference/newton" and b.method == "finite_difference/root"


def test_strong_forcing_from_rest_is_physical():
    # The capped Newton step keeps the paper's start theta = 0 on the physical branch.
    exact = hairbed.solve(1e4, 0.5)
    res = finite_difference(1e4, 0.5, num=1280)
    assert res.success and res.physical
    assert res.tip_height == pytest.approx(exact.tip_height, rel=1e-3)


@pytest.mark.parametrize(
    "omega2, guess, branch",
    [
        (50.0, lambda s: -2 * np.pi * s, (-1, 0)),
        (20.0, lambda s: -np.pi * s, (1, 1)),
    ],
)
def test_twirling_guess_finds_a_twirling_branch(omega2, guess, branch):
    res = finite_difference(omega2, 0.5, num=400, guess=guess)
    assert res.success  # converged: but not to the physical hair
    assert not res.physical
    assert (res.sign, res.n) == branch
    twin = hairbed.solve(omega2, 0.5, sign=res.sign, n=res.n)
    assert twin.tip_height == pytest.approx(res.tip_height, abs=2e-3 * omega2**0.5)
    assert twin.xi == pytest.approx(res.xi, abs=2e-3 * omega2**0.5)
    np.testing.assert_allclose(res.theta, twin.theta(res.sigma), atol=1e-2 * omega2**0.5)


def test_nonconvergence_is_reported_not_raised():
    res = finite_difference(100.0, 0.5, num=80, maxiter=2)
    assert not res.success and res.status == -2 and res.nit == 2
    assert "iteration limit" in res.message
    assert res.theta.shape == (81,)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.success = True  # results are frozen


def test_no_forcing_is_straight():
    res = finite_difference(0.0, 0.5, 0.4, num=20)
    assert res.success and res.physical
    np.testing.assert_allclose(res.theta, 0.4, atol=1e-14)
    assert res.tip_height == pytest.approx(np.cos(0.4), abs=1e-14)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"omega2": [1.0, 2.0]}, "scalar"),
        ({"eps": 1.0}, "eps"),
        ({"theta0": 2.0}, "theta0"),
        ({"omega2": -1.0}, "omega2"),
        ({"num": 1}, "num"),
        ({"num": 10.5}, "num"),
        ({"xtol": 0.0}, "xtol"),
        ({"method": "lm"}, "method"),
        ({"guess": lambda s: np.nan * s}, "guess"),
    ],
)
def test_invalid_input_raises(kwargs, match):
    args = {"omega2": 1.0, "eps": 0.5, **kwargs}
    with pytest.raises(ValueError, match=match):
        finite_difference(**args)
