"""Shooting and collocation against the analytic solution; honest failure at strong forcing."""

import itertools

import numpy as np
import pytest

import hairbed
from hairbed.numerics import shooting
from hairbed.numerics._collocation import collocation

#: Measured: collocation (tol 1e-8) agrees to ~1e-10, shooting (rtol 1e-12) to ~1e-12.
COLLOCATION_ATOL = 1e-6
SHOOTING_ATOL = 1e-8

SWEEP = list(itertools.product([0.1, 2.0, 30.0], [0.0, 0.9], [0.0, -0.7, 0.7]))


def _check(res, exact, atol):
    assert (res.sign, res.n) == (1, 0) and res.physical
    assert res.tip_height == pytest.approx(exact.tip_height, abs=atol)
    assert res.tip_deflection == pytest.approx(exact.tip_deflection, abs=atol)
    assert res.xi == pytest.approx(exact.xi, abs=atol)
    assert res.omega_eps == pytest.approx(exact.omega_eps, rel=atol)
    assert res.base_curvature == pytest.approx(exact.base_curvature, rel=atol)
    np.testing.assert_allclose(res.theta, exact.theta(res.sigma), atol=atol)
    np.testing.assert_allclose(res.z, exact.z(res.sigma), atol=atol)


@pytest.mark.parametrize("omega2, eps, theta0", SWEEP)
def test_collocation_matches_analytic(omega2, eps, theta0):
    res = collocation(omega2, eps, theta0)
    assert res.success and res.status == 0
    _check(res, hairbed.solve(omega2, eps, theta0), COLLOCATION_ATOL)


@pytest.mark.parametrize("omega2, theta0", [(1e3, -1.0), (1e4, 0.5)])
def test_collocation_strong_forcing(omega2, theta0):
    res = collocation(omega2, 0.5, theta0)
    assert res.success
    _check(res, hairbed.solve(omega2, 0.5, theta0), 1e-5)


def test_collocation_twirling_guess_is_labelled():
    # From a straight start at omega2 = 30, solve_bvp lands on a hair bent back below its base.
    res = collocation(30.0, 0.5, guess=0.0)
    assert res.success and (res.sign, res.n) == (-1, 0)
    twin = hairbed.solve(30.0, 0.5, sign=-1, n=0)
    assert res.tip_height == pytest.approx(twin.tip_height, abs=COLLOCATION_ATOL)


@pytest.mark.parametrize("omega2, eps, theta0", SWEEP)
def test_shooting_matches_analytic(omega2, eps, theta0):
    res = shooting(omega2, eps, theta0)
    assert res.success and res.status == 0
    _check(res, hairbed.solve(omega2, eps, theta0), SHOOTING_ATOL)


def test_shooting_reports_ill_conditioning():
    # omega_eps ~ 32: the physical theta'(0) is within 1e-26 of the separatrix, far below
    # rounding. The solver must not claim a clean success.
    res = shooting(1000.0, 0.5)
    assert res.status in (-3, 3)
    assert res.status == 3 or not res.success
    assert "ill-conditioned" in res.message or "separatrix" in res.message


def test_shooting_newton_start_reaches_twirling_branch():
    # Newton from a base curvature well below the physical one finds the n = 1 branch.
    res = shooting(20.0, 0.5, guess=3.0)
    assert res.success
    twin = hairbed.solve(20.0, 0.5, sign=res.sign, n=res.n)
    assert (res.sign, res.n) == (1, 1)
    assert res.tip_height == pytest.approx(twin.tip_height, abs=SHOOTING_ATOL)


@pytest.mark.parametrize("solver", [shooting, collocation])
def test_invalid_input_raises(solver):
    with pytest.raises(ValueError, match="scalar"):
        solver(np.array([1.0, 2.0]), 0.5)
    with pytest.raises(ValueError, match="eps"):
        solver(1.0, 1.5)
