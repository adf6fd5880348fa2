"""The naive reference's elliptic layer (tests/naive) against mpmath, up to the separatrix."""

import mpmath as mp
import numpy as np
import pytest
from naive.branch import branch_point, omega2_and_slope
from naive.elliptic import complete_k, complete_k_minus_e, jacobi
from scipy import special

P_VALUES = [0.9999, 0.7, 0.5, 0.3, 1e-3, 1e-9, 1e-14, 1e-30, 1e-120]
FRACTIONS = [1e-3, 0.2, 0.49, 0.51, 0.8, 0.999, 1.4, 2.5, 3.7, -0.6, -2.2]


@pytest.fixture(autouse=True)
def _precision():
    with mp.workdps(160):
        yield


def _args(p):
    m = 1.0 - p
    k = complete_k(np.array(p), np.array(np.log(p)))
    kp = special.ellipk(p) if p < 0.5 else special.ellipkm1(m)
    return m, k, kp, complete_k_minus_e(np.array(m), np.array(p), k)


@pytest.mark.parametrize("p", P_VALUES)
def test_complete_integrals(p):
    mm = 1 - mp.mpf(p)
    m, k, _, kme = _args(p)
    assert float(k) == pytest.approx(float(mp.ellipk(mm)), rel=2e-15)
    assert float(kme) == pytest.approx(float(mp.ellipk(mm) - mp.ellipe(mm)), rel=2e-15)


def test_complete_k_after_underflow():
    tau = np.array(-2000.0)  # p = e^-2000 underflows; K = ln 4 - tau/2
    assert float(complete_k(np.array(0.0), tau)) == pytest.approx(np.log(4) + 1000, rel=1e-15)


@pytest.mark.parametrize("p", P_VALUES)
@pytest.mark.parametrize("frac", FRACTIONS)
def test_jacobi_against_mpmath(p, frac):
    mm = 1 - mp.mpf(p)
    m, k, kp, kme = _args(p)
    u = float(frac * mp.ellipk(mm))
    sn, cn, dn, ume = jacobi(np.array(u), np.array(m), np.array(p), k, np.array(kp), kme)
    us = mp.mpf(u)
    j = mp.nint(us / (2 * mp.ellipk(mm)))
    r = us - 2 * j * mp.ellipk(mm)
    eps_ref = 2 * j * mp.ellipe(mm) + mp.ellipe(mp.asin(mp.ellipfun("sn", r, m=mm)), mm)
    # relative accuracy, up to the rounding of u itself (|f'| <= 1 for sn, cn, dn)
    for got, name in ((sn, "sn"), (cn, "cn"), (dn, "dn")):
        ref = float(mp.ellipfun(name, us, m=mm))
        assert abs(float(got) - ref) <= 2e-15 * abs(ref) + 2e-16 * max(1.0, abs(u)), name
    ref = float(us - eps_ref)
    assert abs(float(ume) - ref) <= 2e-15 * abs(ref) + 2e-16 * max(1.0, abs(u))


@pytest.mark.parametrize("theta0", [-1.5, -0.3, 0.0, 0.8, 1.55])
@pytest.mark.parametrize("xi_frac", [1e-12, 1e-3, 0.3, 0.9, 1 - 1e-9])
def test_branch_point_integrals(theta0, xi_frac):
    """v0 = F(phi0 | mu) and kv = K(mu) - v0 against mpmath, at both ends of the range."""
    s = mp.sin(mp.mpf(theta0))
    xi = s + (1 - s) * mp.mpf(xi_frac)
    t = float(mp.log(xi - s) - mp.log(1 - xi))
    bp = branch_point(np.array(t), 0.5, theta0, 1, 0)
    mu = (1 + xi) / 2
    phi0 = mp.asin(mp.sin(mp.pi / 4 + mp.mpf(theta0) / 2) / mp.sqrt(mu))
    v0 = mp.ellipf(phi0, mu)
    kv = mp.ellipk(mu) - v0
    # t carries the state; compare at the xi the double t actually represents
    assert float(bp.v0) == pytest.approx(float(v0), rel=1e-13)
    assert float(bp.kv) == pytest.approx(float(kv), rel=1e-13)


def test_slope_is_the_derivative():
    t = np.linspace(-20, 40, 31)
    for sign, n in ((1, 0), (1, 2), (-1, 1)):
        for theta0 in (-1.2, 0.0, 1.1):
            bp = branch_point(t, 0.7, theta0, sign, n)
            _, slope = omega2_and_slope(bp)
            h = 1e-5 * np.maximum(1.0, np.abs(t))
            up = branch_point(t + h, 0.7, theta0, sign, n).omega2
            dn = branch_point(t - h, 0.7, theta0, sign, n).omega2
            fd = (up - dn) / (2 * h)
            assert np.allclose(slope, fd, rtol=1e-5, atol=1e-12 * np.abs(bp.omega2).max())
