"""Identities every returned solution must satisfy, over the whole parameter domain.

These do not compare with stored numbers: they check the closed-form shape against the
boundary value problem itself (theta'' = -omega_eps^2 cos theta, theta(0) = theta0,
theta'(1) = 0, omega_eps^2 (1 - eps h1) = omega^2), by quadrature and finite differences that
share no formula with the solver.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from tolerances import IDENTITY_ATOL, IDENTITY_RTOL

import hairbed

log_omega2 = st.floats(min_value=-8.0, max_value=6.0)
eps_values = st.floats(min_value=0.0, max_value=0.999)
theta0_values = st.floats(min_value=-1.55, max_value=1.55)

GAUSS_X, GAUSS_W = np.polynomial.legendre.leggauss(60)


def _integral(f, a=0.0, b=1.0, pieces=None):
    """Composite Gauss-Legendre on a mesh graded towards the base (its boundary layer)."""
    if pieces is None:
        pieces = np.concatenate([[0.0], np.geomspace(1e-4, 1.0, 40)])
    total = 0.0
    for lo, hi in zip(pieces[:-1], pieces[1:]):
        s = 0.5 * (hi - lo) * GAUSS_X + 0.5 * (hi + lo)
        total += 0.5 * (hi - lo) * np.sum(GAUSS_W * f(s))
    return total


def _close(a, b, rtol=IDENTITY_RTOL, atol=IDENTITY_ATOL):
    return np.allclose(a, b, rtol=rtol, atol=atol)


@settings(max_examples=150, deadline=None)
@given(log_omega2, eps_values, theta0_values)
def test_physical_identities(lw, eps, theta0):
    omega2 = 10.0**lw
    sol = hairbed.solve(omega2, eps, theta0)
    assert sol.n_roots >= 1 and sol.physical
    # self-consistency eqs. (34) and (29)
    assert _close(sol.omega_eps**2 * (1 - eps * sol.tip_height), omega2, rtol=1e-12)
    assert _close(sol.base_curvature, sol.omega_eps**2 * sol.tip_height, rtol=1e-12)
    # boundary values and tip values of the closed-form shape
    assert _close(sol.theta(0.0), theta0, atol=1e-13)
    assert sol.x(0.0) == pytest.approx(0.0, abs=1e-13)
    assert sol.z(0.0) == pytest.approx(0.0, abs=1e-13)
    assert _close(sol.theta(1.0), sol.tip_angle, rtol=1e-12, atol=1e-12)
    assert _close(sol.z(1.0), sol.tip_height, rtol=1e-12, atol=1e-13)
    assert _close(sol.x(1.0), sol.tip_deflection, rtol=1e-12, atol=1e-13)
    assert _close(np.sin(sol.tip_angle), min(sol.xi, 1.0), rtol=1e-12, atol=1e-13)
    # the physical hair rises monotonically from theta0 and never touches the wall
    sig = np.linspace(0.0, 1.0, 101)
    th = sol.theta(sig)
    assert np.all(np.diff(th) >= -1e-13)
    assert np.all(sol.z(sig[1:]) > 0.0)
    assert sol.tip_angle <= np.pi / 2


@settings(max_examples=60, deadline=None)
@given(st.floats(min_value=-4.0, max_value=2.5), eps_values, theta0_values)
def test_shape_integrates_the_ode(lw, eps, theta0):
    """z = int cos(theta), x = int sin(theta) by quadrature of theta(sigma) alone."""
    sol = hairbed.solve(10.0**lw, eps, theta0)
    h1 = _integral(lambda s: np.cos(sol.theta(s)))
    x1 = _integral(lambda s: np.sin(sol.theta(s)))
    assert h1 == pytest.approx(sol.tip_height, rel=1e-11, abs=1e-12)
    assert x1 == pytest.approx(sol.tip_deflection, rel=1e-11, abs=1e-12)
    for s in (0.13, 0.5, 0.91):
        pieces = np.linspace(0.0, s, 9)
        assert _integral(lambda u: np.cos(sol.theta(u)), pieces=pieces) == pytest.approx(
            sol.z(s), rel=1e-11, abs=1e-12
        )
        assert _integral(lambda u: np.sin(sol.theta(u)), pieces=pieces) == pytest.approx(
            sol.x(s), rel=1e-11, abs=1e-12
        )


@settings(max_examples=60, deadline=None)
@given(st.floats(min_value=-3.0, max_value=2.0), eps_values, theta0_values)
def test_energy_is_conserved_along_the_shape(lw, eps, theta0):
    """E = theta'^2/2 + omega_eps^2 sin(theta) with theta' from central differences."""
    sol = hairbed.solve(10.0**lw, eps, theta0)
    h = 1e-5
    sig = np.linspace(0.05, 0.95, 7)
    dtheta = (sol.theta(sig + h) - sol.theta(sig - h)) / (2 * h)
    energy = 0.5 * dtheta**2 + sol.omega_eps**2 * np.sin(sol.theta(sig))
    scale = sol.omega_eps**2 + abs(sol.energy)
    assert np.allclose(energy, sol.energy, rtol=0, atol=1e-7 * scale)
    # theta'(1) = 0: theta(1) - theta(1 - h) = omega_eps^2 cos(theta1) h^2 / 2 + O(h^3)
    h = 1e-4
    drop = sol.theta(1.0) - sol.theta(1.0 - h)
    expected = 0.5 * sol.omega_eps**2 * np.cos(sol.tip_angle) * h * h
    assert drop == pytest.approx(expected, rel=1e-3, abs=1e-15)


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize("n", [0, 1, 2, 3])
@pytest.mark.parametrize(("omega2", "eps", "theta0"), [(2000.0, 0.5, 0.0), (800.0, 0.9, -0.7)])
def test_branch_labels_describe_the_shape(sign, n, omega2, eps, theta0):
    sol = hairbed.solve(omega2, eps, theta0, sign=sign, n=n, root="high")
    assert sol.n_roots >= 1, "these inputs have a solution on every branch up to n = 3"
    assert sol.physical == (sign == 1 and n == 0)
    sig = np.linspace(0.0, 1.0, 20001)
    dth = np.diff(sol.theta(sig))
    assert np.sign(dth[0]) == sign
    dth = dth[np.abs(dth) > 1e-11]  # flat stretches next to the separatrix are rounding noise
    turning = np.count_nonzero(np.sign(dth[1:]) != np.sign(dth[:-1]))
    assert turning == n
    assert sol.omega_eps**2 * (1 - eps * sol.tip_height) == pytest.approx(omega2, rel=1e-12)
    assert sol.z(1.0) == pytest.approx(sol.tip_height, rel=1e-11, abs=1e-12)
    assert sol.x(1.0) == pytest.approx(sol.tip_deflection, rel=1e-11, abs=1e-12)


def test_no_solution_gives_nan_and_zero_roots():
    # n = 3 needs omega_eps >= 6K: nothing at weak forcing
    sol = hairbed.solve(1.0, 0.5, sign=1, n=3)
    assert sol.n_roots == 0
    for name in ("xi", "omega_eps", "energy", "tip_height", "tip_deflection", "tip_angle"):
        assert np.isnan(getattr(sol, name)), name
    assert np.isnan(sol.theta(0.5))
    assert sol.physical is False


def test_rest_state():
    for theta0 in (-1.2, 0.0, 0.4):
        sol = hairbed.solve(0.0, 0.3, theta0)
        assert sol.xi == pytest.approx(np.sin(theta0), abs=1e-16)
        assert sol.tip_height == pytest.approx(np.cos(theta0), abs=1e-16)
        assert sol.tip_deflection == pytest.approx(np.sin(theta0), abs=1e-16)
        assert sol.omega_eps == 0.0 and sol.base_curvature == 0.0
        assert sol.theta(0.7) == pytest.approx(theta0, abs=1e-16)
        assert sol.z(0.5) == pytest.approx(0.5 * np.cos(theta0), abs=1e-16)


def test_weak_forcing_limit():
    # linear cantilever: theta' = omega_eps^2 cos(theta0) (1 - sigma)
    omega2, eps, theta0 = 1e-9, 0.4, 0.3
    sol = hairbed.solve(omega2, eps, theta0)
    oe2 = omega2 / (1 - eps * np.cos(theta0))
    assert sol.omega_eps**2 == pytest.approx(oe2, rel=1e-8)
    assert sol.xi - np.sin(theta0) == pytest.approx(0.5 * oe2 * np.cos(theta0) ** 2, rel=1e-8)
    assert sol.tip_deflection - np.sin(theta0) == pytest.approx(
        oe2 * np.cos(theta0) ** 2 / 3, rel=1e-7
    )


@pytest.mark.parametrize("theta0", [-1.55, -0.5, 0.0, 0.7, 1.55])
@pytest.mark.parametrize("omega2", [1e6, 1e8, 1e12])
def test_strong_forcing_tip_values_stay_exact(omega2, theta0):
    """xi rounds to 1 but h1 ~ sqrt(2(1 - sin theta0))/omega (theory.md §4)."""
    sol = hairbed.solve(omega2, 0.9, theta0)
    omega = np.sqrt(omega2)
    h1 = np.sqrt(2 * (1 - np.sin(theta0))) / omega
    assert sol.xi == 1.0
    assert sol.tip_height == pytest.approx(h1, rel=5.0 / omega)
    assert sol.tip_angle == pytest.approx(np.pi / 2, abs=1e-15)
    assert 1 - sol.tip_deflection == pytest.approx(
        2 * (1 - np.sqrt(0.5 * (1 + np.sin(theta0)))) / omega, rel=5.0 / omega
    )
    assert sol.omega_eps**2 * (1 - 0.9 * sol.tip_height) == pytest.approx(omega2, rel=1e-13)


def test_vectorised_equals_scalar():
    rng = np.random.default_rng(1)
    omega2 = 10 ** rng.uniform(-4, 5, 40)
    eps = rng.uniform(0, 0.999, 40)
    theta0 = rng.uniform(-1.55, 1.55, 40)
    vec = hairbed.solve(omega2, eps, theta0)
    assert vec.shape == (40,)
    for i in range(40):
        one = hairbed.solve(omega2[i], eps[i], theta0[i])
        for name in ("xi", "tip_height", "tip_deflection", "omega_eps", "n_roots"):
            assert getattr(vec, name)[i] == getattr(one, name), (name, i)
    x, z = vec.profile(50)
    assert x.shape == (40, 50)
    assert np.allclose(z[:, -1], vec.tip_height, rtol=1e-12, atol=1e-14)
    assert vec[3].xi == vec.xi[3]


def test_broadcasting_and_scalar_types():
    sol = hairbed.solve([[1.0], [2.0]], [0.1, 0.5, 0.9])
    assert sol.shape == (2, 3)
    assert sol.theta(np.linspace(0, 1, 3)).shape == (2, 3)
    assert sol.theta(np.ones((4, 1, 1))).shape == (4, 2, 3)
    one = hairbed.solve(2.0, 0.5)
    assert isinstance(one.xi, float) and isinstance(one.n_roots, int)
    assert isinstance(one.physical, bool)
    assert one.theta(np.array([0.2, 0.4])).shape == (2,)


BISTABLE = [(-1.5, 0.9, 0.95766, 1.4859), (-1.0, 0.95, 0.29696, 0.31966)]


@pytest.mark.parametrize(("theta0", "eps", "lower", "upper"), BISTABLE)
def test_bistable_window(theta0, eps, lower, upper):
    """Three physical states inside the window of theory.md §5, one outside."""
    inside = np.linspace(lower, upper, 7)[1:-1]
    sols = {r: hairbed.solve(inside, eps, theta0, root=r) for r in ("low", "mid", "high")}
    assert np.all(sols["low"].n_roots == 3)
    assert np.all(sols["low"].xi < sols["mid"].xi)
    assert np.all(sols["mid"].xi < sols["high"].xi)
    for sol in sols.values():
        assert np.allclose(sol.omega_eps**2 * (1 - eps * sol.tip_height), inside, rtol=1e-12)
    # deflection is monotone in xi (theory.md §5), so the three states are distinct
    assert np.all(sols["low"].tip_deflection < sols["high"].tip_deflection)
    outside = np.array([0.8 * lower, 1.2 * upper])
    out = hairbed.solve(outside, eps, theta0, root="mid")
    assert np.all(out.n_roots == 1) and np.all(np.isnan(out.xi))
    low, high = (hairbed.solve(outside, eps, theta0, root=r) for r in ("low", "high"))
    assert np.array_equal(low.xi, high.xi)


def test_solve_all_lists_every_branch():
    sols = hairbed.solve_all(300.0, 0.5, 0.2)
    labels = [(s.sign, s.n) for s in sols]
    assert labels[0] == (1, 0) and sols[0].physical
    assert not any(s.physical for s in sols[1:])
    assert labels == sorted(labels, key=lambda sn: (sn[1], -sn[0]))
    for s in sols:
        assert s.omega_eps**2 * (1 - 0.5 * s.tip_height) == pytest.approx(300.0, rel=1e-12)
        again = hairbed.solve(300.0, 0.5, 0.2, sign=s.sign, n=s.n)
        assert again.n_roots == s.n_roots
    # every branch up to n = 3 has a solution at this forcing: omega_eps ~ 17 > 6 K
    assert {(1, 1), (1, 2), (-1, 0), (-1, 2)} <= set(labels)
    assert hairbed.solve_all(0.0, 0.5)[0].tip_height == 1.0


def test_from_xi_and_parameter_round_trip():
    for theta0 in (-1.0, 0.0, 0.9):
        xi = np.sin(theta0) + (1 - np.sin(theta0)) * np.array([1e-9, 0.01, 0.5, 0.999999])
        fwd = hairbed.from_xi(xi, 0.7, theta0)
        back = hairbed.solve(fwd.omega2, 0.7, theta0, root="high" if theta0 < 0 else "low")
        sel = back.n_roots == 1
        assert np.allclose(back.xi[sel], xi[sel], rtol=1e-12, atol=1e-15)
    strong = hairbed.from_parameter(3000.0, 0.5, 0.3)
    assert strong.xi == 1.0 and strong.omega2 > 1e6
    again = hairbed.solve(strong.omega2, 0.5, 0.3)
    assert again.tip_height == pytest.approx(strong.tip_height, rel=1e-12)
