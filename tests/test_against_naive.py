"""The public API against the slow numpy reference in tests/naive (stumpy's practice).

tests/naive is hairbed's numpy core as it was before the numba kernels. Every fast path must
reproduce it to RTOL/ATOL on random inputs of every branch and root, away from the corners its
docstring lists (theta0 near +-pi/2, omega2 < 1e-8 here, t = +-inf).
"""

import numpy as np
import pytest
from naive import (
    FIELDS,
    naive_from_parameter,
    naive_shape,
    naive_solve,
    naive_solve_all,
)
from naive.branch import branch_point
from naive.roots import critical_points
from tolerances import ATOL, RTOL

import hairbed

SEED = 20240611
ROOTS = ("low", "mid", "high")
TWIRLING = [(1, 1), (1, 2), (1, 3), (-1, 0), (-1, 1), (-1, 2), (-1, 3)]
ALL_BRANCHES = [(1, 0), *TWIRLING]
SIGMAS = (0.0, 0.1, 0.37, 0.5, 0.9, 1.0)
THETA0_MAX = 1.55
EPS_MAX = 0.99


def _rng(*key: int) -> np.random.Generator:
    """A fixed generator per test (and per branch), independent of test order."""
    return np.random.default_rng([SEED, *(k + 10 for k in key)])


def _inputs(rng, size, log_omega2=(-8.0, 6.0)):
    omega2 = 10.0 ** rng.uniform(*log_omega2, size)
    eps = rng.uniform(0.0, EPS_MAX, size)
    theta0 = rng.uniform(-THETA0_MAX, THETA0_MAX, size)
    return omega2, eps, theta0


def _close(actual, expected, what):
    assert np.shape(actual) == np.shape(expected), what
    np.testing.assert_allclose(actual, expected, rtol=RTOL, atol=ATOL, err_msg=what)


def assert_matches(sol, ref, what=""):
    """Every public field of a Solution against a naive state dict."""
    assert (sol.sign, sol.n) == (ref["sign"], ref["n"]), what
    for name in FIELDS:
        _close(getattr(sol, name), ref[name], f"{name} {what}")
    np.testing.assert_array_equal(sol.n_roots, ref["n_roots"], err_msg=f"n_roots {what}")
    np.testing.assert_array_equal(sol.physical, ref["physical"], err_msg=f"physical {what}")
    _close(sol.omega2, ref["omega2"], f"omega2 {what}")
    np.testing.assert_array_equal(sol.eps, ref["eps"], err_msg=f"eps {what}")
    np.testing.assert_array_equal(sol.theta0, ref["theta0"], err_msg=f"theta0 {what}")


def assert_shapes_match(sol, ref, what=""):
    """theta, x, z at every sigma of SIGMAS (scalar and as an array) and the profile."""
    args = (ref["t"], ref["eps"], ref["theta0"], ref["sign"], ref["n"])
    for sigma in SIGMAS:
        theta, x, z = naive_shape(*args, sigma)
        _close(sol.theta(sigma), theta, f"theta({sigma}) {what}")
        _close(sol.x(sigma), x, f"x({sigma}) {what}")
        _close(sol.z(sigma), z, f"z({sigma}) {what}")
    # sigma broadcast against the state's shape, as the API documents
    sigma = np.reshape(SIGMAS, (len(SIGMAS),) + (1,) * np.ndim(ref["t"]))
    theta, x, z = naive_shape(*args, sigma)
    _close(sol.theta(sigma), theta, f"theta(array) {what}")
    _close(sol.x(sigma), x, f"x(array) {what}")
    _close(sol.z(sigma), z, f"z(array) {what}")
    num = 9
    expanded = [np.asarray(a)[..., None] for a in args[:3]]
    _, x, z = naive_shape(*expanded, *args[3:], np.linspace(0.0, 1.0, num))
    px, pz = sol.profile(num)
    _close(px, x, f"profile x {what}")
    _close(pz, z, f"profile z {what}")


@pytest.mark.parametrize("root", ROOTS)
def test_physical_branch(root):
    omega2, eps, theta0 = _inputs(_rng(0), 2000)
    ref = naive_solve(omega2, eps, theta0, root=root)
    sol = hairbed.solve(omega2, eps, theta0, root=root)
    assert_matches(sol, ref, f"physical root={root}")
    assert np.all(ref["n_roots"] >= 1)


@pytest.mark.parametrize("sign, n", TWIRLING)
@pytest.mark.parametrize("root", ROOTS)
def test_twirling_branches(sign, n, root):
    omega2, eps, theta0 = _inputs(_rng(1, sign, n), 300, log_omega2=(-2.0, 5.0))
    ref = naive_solve(omega2, eps, theta0, sign=sign, n=n, root=root)
    sol = hairbed.solve(omega2, eps, theta0, sign=sign, n=n, root=root)
    assert_matches(sol, ref, f"sign={sign} n={n} root={root}")
    assert np.any(ref["n_roots"] >= 1)  # not all empty


def _fold_omega2(eps, theta0, sign, n):
    """omega2 at the folds of a branch, (N, 4) NaN-padded, from the naive reference."""
    crit = critical_points(eps, theta0, sign, n)
    return branch_point(crit, eps[:, None], theta0[:, None], sign, n).omega2


@pytest.mark.parametrize("sign, n", [(-1, 0), (-1, 1), (-1, 2), (-1, 3)])
@pytest.mark.parametrize("root", ROOTS)
def test_two_root_states(sign, n, root):
    # every sign -1 branch has one fold, a minimum of omega2 below its value at the base state
    # (t -> -inf): between the two there are two states
    rng = _rng(2, sign, n)
    eps = rng.uniform(0.0, EPS_MAX, 100)
    theta0 = rng.uniform(-THETA0_MAX, THETA0_MAX, 100)
    fold = _fold_omega2(eps, theta0, sign, n)[:, 0]
    base = branch_point(-745.0, eps, theta0, sign, n).omega2
    omega2 = fold + rng.uniform(0.02, 0.98, 100) * (base - fold)
    ref = naive_solve(omega2, eps, theta0, sign=sign, n=n, root=root)
    assert np.all(ref["n_roots"] == 2)
    sol = hairbed.solve(omega2, eps, theta0, sign=sign, n=n, root=root)
    assert_matches(sol, ref, f"two roots sign={sign} n={n} root={root}")


def _bistable_inputs():
    """(omega2, eps, theta0) inside the three-state window of the physical branch."""
    rng = _rng(3)
    rows = [(0.9, -1.5, 0.9577, 1.4859), (0.95, -1.0, 0.29696, 0.31966)]
    eps = rng.uniform(0.7, EPS_MAX, 400)
    theta0 = rng.uniform(-THETA0_MAX, -0.8, 400)
    fold = _fold_omega2(eps, theta0, 1, 0)
    two = np.sum(np.isfinite(fold), axis=1) == 2
    rows += [(e, t, min(f), max(f)) for e, t, f in zip(eps[two], theta0[two], fold[two, :2])]
    omega2, eps, theta0 = [], [], []
    for e, t, lo, hi in rows:
        # strictly inside: away from the folds, where the state is ill-conditioned in omega2
        u = rng.uniform(0.02, 0.98, 5)
        omega2.extend(lo + u * (hi - lo))
        eps.extend([e] * u.size)
        theta0.extend([t] * u.size)
    return np.array(omega2), np.array(eps), np.array(theta0)


def test_bistable_windows():
    omega2, eps, theta0 = _bistable_inputs()
    assert omega2.size >= 100
    xi = {}
    for root in ROOTS:
        ref = naive_solve(omega2, eps, theta0, root=root)
        np.testing.assert_array_equal(ref["n_roots"], 3)
        sol = hairbed.solve(omega2, eps, theta0, root=root)
        assert_matches(sol, ref, f"bistable root={root}")
        xi[root] = sol.xi
    assert np.all(xi["low"] < xi["mid"]) and np.all(xi["mid"] < xi["high"])


@pytest.mark.parametrize("sign, n", ALL_BRANCHES)
def test_from_parameter(sign, n):
    rng = _rng(4, sign, n)
    t = rng.uniform(-30.0, 30.0, 500)
    eps = rng.uniform(0.0, EPS_MAX, 500)
    theta0 = rng.uniform(-THETA0_MAX, THETA0_MAX, 500)
    ref = naive_from_parameter(t, eps, theta0, sign, n)
    sol = hairbed.from_parameter(t, eps, theta0, sign=sign, n=n)
    assert_matches(sol, ref, f"from_parameter sign={sign} n={n}")


def test_broadcasting_and_scalars():
    omega2 = np.array([[0.5], [2.0], [30.0]])
    eps = np.array([0.0, 0.5, 0.9])
    theta0 = np.array([[[-1.2]], [[0.3]]])
    for root in ROOTS:
        ref = naive_solve(omega2, eps, theta0, root=root)
        sol = hairbed.solve(omega2, eps, theta0, root=root)
        assert sol.shape == (2, 3, 3)
        assert_matches(sol, ref, f"broadcast root={root}")
        assert_shapes_match(sol, ref, f"broadcast root={root}")
    ref = naive_solve(2.0, 0.5, 0.1, sign=-1, n=1)
    sol = hairbed.solve(2.0, 0.5, 0.1, sign=-1, n=1)
    assert isinstance(sol.xi, float) and isinstance(sol.n_roots, int)
    assert_matches(sol, ref, "scalar")
    assert_shapes_match(sol, ref, "scalar")


@pytest.mark.parametrize("sign, n", ALL_BRANCHES)
def test_shapes(sign, n):
    rng = _rng(5, sign, n)
    size = 200 if (sign, n) == (1, 0) else 60
    low = -8.0 if (sign, n) == (1, 0) else -2.0
    omega2, eps, theta0 = _inputs(rng, size, log_omega2=(low, 5.0))
    for root in ("low", "high"):
        ref = naive_solve(omega2, eps, theta0, sign=sign, n=n, root=root)
        sol = hairbed.solve(omega2, eps, theta0, sign=sign, n=n, root=root)
        assert_shapes_match(sol, ref, f"sign={sign} n={n} root={root}")
    ref = naive_from_parameter(rng.uniform(-30.0, 30.0, size), eps, theta0, sign, n)
    sol = hairbed.from_parameter(ref["t"], eps, theta0, sign=sign, n=n)
    assert_shapes_match(sol, ref, f"from_parameter sign={sign} n={n}")


def test_shapes_bistable():
    omega2, eps, theta0 = _bistable_inputs()
    for root in ROOTS:
        ref = naive_solve(omega2, eps, theta0, root=root)
        sol = hairbed.solve(omega2, eps, theta0, root=root)
        assert_shapes_match(sol, ref, f"bistable root={root}")


SOLVE_ALL_CASES = [
    (2.0, 0.5, 0.0),
    (50.0, 0.5, 0.0),
    (1e-3, 0.3, 0.7),
    (0.3, 0.95, -1.0),  # inside the bistable window
    (1.2, 0.9, -1.5),  # inside the bistable window
    (8.0, 0.0, -0.4),
    (120.0, 0.8, 1.3),
    (700.0, 0.2, -1.2),
    (3000.0, 0.99, 0.5),
    (1e4, 0.6, -1.54),
    (15.0, 0.97, 1.54),
    (0.05, 0.1, -0.9),
]


@pytest.mark.parametrize("omega2, eps, theta0", SOLVE_ALL_CASES)
def test_solve_all(omega2, eps, theta0):
    refs = naive_solve_all(omega2, eps, theta0)
    sols = hairbed.solve_all(omega2, eps, theta0)
    assert [(s.sign, s.n) for s in sols] == [(r["sign"], r["n"]) for r in refs]
    for i, (sol, ref) in enumerate(zip(sols, refs)):
        assert_matches(sol, ref, f"solve_all state {i}")
        if i < 6:
            assert_shapes_match(sol, ref, f"solve_all state {i}")
