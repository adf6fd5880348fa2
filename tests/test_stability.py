"""Stability of static states under the relaxation dynamics, checked by time-stepping."""

import numpy as np
import pytest

import hairbed
from hairbed import stability as st
from hairbed.numerics._banded import HairOperator

W, EPS, THETA0 = 1.2, 0.9, -1.5  # inside the window 0.95766 .. 1.4859 (theory.md §5)
ROOTS = ("low", "mid", "high")


@pytest.fixture(scope="module")
def triple():
    return [hairbed.solve(W, EPS, THETA0, root=r) for r in ROOTS]


def test_low_and_high_are_stable_mid_is_not(triple):
    res = [st.linear_stability(s) for s in triple]
    assert [bool(r.stable) for r in res] == [True, False, True]
    assert [int(r.n_unstable) for r in res] == [0, 1, 0]
    # The leading eigenvalues are real (the rank-one coupling does not make them complex here).
    for r in res:
        assert np.all(np.abs(r.eigenvalues.imag) < 1e-8)
    assert [bool(st.is_stable(s)) for s in triple] == [True, False, True]


def test_growth_rates_converge_with_resolution(triple):
    coarse = [float(st.linear_stability(s, num=50).growth_rate) for s in triple]
    fine = [float(st.linear_stability(s, num=100).growth_rate) for s in triple]
    # Second-order discretisation: halving the step changes the rate by ~3e-4 here.
    np.testing.assert_allclose(coarse, fine, rtol=2e-3)


def test_vectorised_over_the_solution_shape():
    s = hairbed.solve(np.array([0.5, 2.0, 10.0]), 0.5, 0.0)
    stable = st.is_stable(s, num=60)
    assert stable.shape == (3,) and stable.all()
    missing = hairbed.solve(np.array([1.2, 2.0]), EPS, THETA0, root="mid")  # one has no mid root
    assert st.is_stable(missing, num=60).tolist() == [False, False]


def test_discrete_equilibrium_converges_to_the_analytic_state(triple):
    errors = []
    for n_seg in (50, 100):
        sigma = np.linspace(0.0, 1.0, n_seg + 1)
        exact = triple[1].theta(sigma)
        eq = st.equilibrium(W, EPS, THETA0, exact, n_seg)
        assert eq.success and eq.status == 0 and eq.message.startswith("converged")
        errors.append(np.max(np.abs(eq.theta - exact)))
    assert errors[1] < errors[0] / 3.5  # second order


def test_jacobian_matches_finite_differences():
    rng = np.random.default_rng(1)
    u = -1.0 + 0.3 * rng.random(12)
    op = HairOperator(W, EPS, THETA0, u.size)
    jac = op.rhs_jacobian(u)
    h = 1e-6
    fd = np.empty_like(jac)
    for j in range(u.size):
        e = np.zeros(u.size)
        e[j] = h
        fd[:, j] = (op.rhs(u + e) - op.rhs(u - e)) / (2 * h)
    np.testing.assert_allclose(jac, fd, rtol=1e-6, atol=1e-4)
    # the O(N) Newton step (banded + Sherman-Morrison) solves the same dense system
    r = op.residual(u)
    dense = np.linalg.solve(jac * (op.h**2 * op.w)[:, None], -r)
    np.testing.assert_allclose(op.newton_step(u, r), dense, rtol=1e-10, atol=1e-12)


def test_time_stepping_confirms_the_classification(triple):
    n_seg = 100
    sigma = np.linspace(0.0, 1.0, n_seg + 1)
    h_low, h_high = triple[0].tip_height, triple[2].tip_height
    ends = {}
    for name, s in zip(ROOTS, triple):
        for delta in (1e-3, -1e-3):
            run = st.relax(W, EPS, THETA0, s.theta(sigma) + delta * sigma, 40.0, num=n_seg)
            assert run.success
            ends[name, delta] = run.tip_height[-1]
    # Perturbed stable states come back: to the discrete equilibrium, which is within the
    # discretisation error (~2e-5 at N = 100) of the analytic tip height.
    for name, s, h in (("low", triple[0], h_low), ("high", triple[2], h_high)):
        theta_eq = st.equilibrium(W, EPS, THETA0, s.theta, n_seg).theta
        h_discrete = (np.cos(theta_eq).sum() - 0.5 * np.cos(theta_eq[[0, -1]]).sum()) / n_seg
        for delta in (1e-3, -1e-3):
            assert ends[name, delta] == pytest.approx(h_discrete, abs=1e-7)
            assert ends[name, delta] == pytest.approx(h, abs=1e-4)
    # The middle state departs, one way to the high state and the other to the low one.
    assert ends["mid", 1e-3] == pytest.approx(h_high, abs=1e-4)
    assert ends["mid", -1e-3] == pytest.approx(h_low, abs=1e-4)


def test_relaxation_from_rest_reaches_the_worked_example():
    # theory.md §3: theta0 = 0, eps = 0.5, omega^2 = 2 gives h1 = 0.732706963462228,
    # x1 = 0.615831536923675.
    run = st.relax(2.0, 0.5, 0.0, np.zeros(81), 30.0, num=80, t_eval=np.array([0.0, 30.0]))
    assert run.theta.shape == (2, 81)
    assert run.tip_height[0] == pytest.approx(1.0)
    assert run.tip_height[-1] == pytest.approx(0.732706963462228, abs=1e-4)
    assert run.tip_deflection[-1] == pytest.approx(0.615831536923675, abs=1e-4)


@pytest.mark.parametrize(
    "call",
    [
        lambda: st.relax(1.0, 0.5, 0.0, np.zeros(5), 1.0, num=10),
        lambda: st.relax(1.0, 0.5, 0.0, np.zeros(11), -1.0, num=10),
        lambda: st.relax(-1.0, 0.5, 0.0, np.zeros(11), 1.0, num=10),
        lambda: st.equilibrium(1.0, 0.5, 0.0, np.zeros(2), num=1),
    ],
)
def test_invalid_input_raises(call):
    with pytest.raises(ValueError):
        call()


def test_equilibrium_reports_instead_of_raising(triple):
    # One Newton step from a poor guess cannot meet the tolerance: reported, not raised.
    eq = st.equilibrium(W, EPS, THETA0, np.zeros(41), 40, maxiter=1)
    assert not eq.success and eq.status == -2 and "iteration limit" in eq.message
    assert eq.nit == eq.nfev == 1 and eq.theta.shape == eq.sigma.shape == (41,)
    assert eq.theta[0] == THETA0
    ok = st.equilibrium(W, EPS, THETA0, triple[0].theta, 40)
    assert ok.success and ok.status == 0 and ok.nit <= 5


def test_stability_says_how_each_classification_ended():
    missing = hairbed.solve(np.array([1.2, 2.0]), EPS, THETA0, root="mid")  # 2.0 has no mid
    res = st.linear_stability(missing, num=60)
    assert res.status.tolist() == [0, -1]
    assert res.success.tolist() == [True, False]
    assert res.message[1] == st.STATUS_MESSAGES[-1]
    one = st.linear_stability(hairbed.solve(2.0, 0.5), num=40)
    assert one.success is True and one.message == st.STATUS_MESSAGES[0]


def test_relaxation_reports_the_integrator_status():
    run = st.relax(2.0, 0.5, 0.0, np.zeros(21), 1.0, num=20)
    assert run.success and run.status == 0
