"""Fitting a whole hair's shape (hairbed.profile_fit): exact and noisy profiles, the middle
of three states, fixed base angle, errors against the scatter of fits to noisy data."""

import math

import numpy as np
import pytest

import hairbed
from hairbed import inverse
from hairbed.profile_fit import ProfileFit, fit_profile


def test_the_old_home_still_imports_it():
    """fit_profile lived in hairbed.inverse (issue 22 item 6): the same objects there."""
    assert inverse.fit_profile is fit_profile and inverse.ProfileFit is ProfileFit
    assert hairbed.profile_fit.fit_profile is fit_profile


@pytest.mark.parametrize(("omega2", "eps", "theta0"), [(0.5, 0.2, 0.0), (3.0, 0.6, 0.2)])
def test_fit_exact_profile(omega2, eps, theta0):
    x, z = hairbed.solve(omega2, eps, theta0).profile(25)
    order = np.random.default_rng(0).permutation(25)  # points in any order
    fit = fit_profile(x[order], z[order], eps)
    assert fit.success
    assert fit.omega2 == pytest.approx(omega2, rel=1e-9)
    assert fit.theta0 == pytest.approx(theta0, abs=1e-9)
    assert fit.residual < 1e-10


def test_fit_the_middle_of_three_states():
    # parametrised by t, the fit reaches the (unstable) middle state without choosing a root
    sol = hairbed.solve(0.31, 0.95, -1.0, root="mid")
    x, z = sol.profile(25)
    fit = fit_profile(x, z, 0.95)
    assert fit.omega2 == pytest.approx(0.31, rel=1e-9)
    assert fit.solution.xi == pytest.approx(sol.xi, rel=1e-9)


def test_fit_uncertainties_match_the_scatter_of_noisy_fits():
    rng = np.random.default_rng(42)
    x, z = hairbed.solve(3.0, 0.6, 0.2).profile(30)
    noise = 0.005
    fits = [
        fit_profile(x + noise * rng.standard_normal(30), z + noise * rng.standard_normal(30), 0.6)
        for _ in range(24)
    ]
    w = np.array([f.omega2 for f in fits])
    th = np.array([f.theta0 for f in fits])
    w_err = np.mean([f.omega2_stderr for f in fits])
    th_err = np.mean([f.theta0_stderr for f in fits])
    # unbiased, and the reported errors match the scatter (24 samples: +-30% allowed)
    assert abs(w.mean() - 3.0) < 3 * w_err / math.sqrt(24) + 0.01
    assert abs(th.mean() - 0.2) < 3 * th_err / math.sqrt(24) + 0.001
    assert 0.7 < w.std(ddof=1) / w_err < 1.4
    assert 0.7 < th.std(ddof=1) / th_err < 1.4
    # the rms residual estimates the noise (a distance normal to the curve: one component)
    assert np.mean([f.residual for f in fits]) == pytest.approx(noise, rel=0.2)


def test_fit_with_fixed_base_angle():
    rng = np.random.default_rng(7)
    x, z = hairbed.solve(1.5, 0.4, -0.3).profile(20)
    fit = fit_profile(
        x + 0.002 * rng.standard_normal(20), z + 0.002 * rng.standard_normal(20), 0.4, theta0=-0.3
    )
    assert fit.theta0 == -0.3 and fit.theta0_stderr == 0.0
    assert abs(fit.omega2 - 1.5) < 4 * fit.omega2_stderr
    # a starting guess is honoured
    fit2 = fit_profile(x, z, 0.4, omega2_guess=1.0, theta0_guess=-0.2)
    assert fit2.omega2 == pytest.approx(1.5, rel=1e-9)


def test_fit_input_validation():
    with pytest.raises(ValueError, match="same number of points"):
        fit_profile([0, 0.1], [0, 0.5, 0.9], 0.5)
    with pytest.raises(ValueError, match="at least 3 points"):
        fit_profile([0, 0.1], [0, 0.5], 0.5)
    with pytest.raises(ValueError, match="eps"):
        fit_profile([0, 0.1, 0.2], [0, 0.5, 0.9], 1.5)
