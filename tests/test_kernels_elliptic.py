"""The elliptic and Jacobi kernels (hairbed._core._kernels.elliptic, .jacobi) against mpmath.

The references share no algorithm with the kernels: mpmath's own Carlson integrals for R_F and
R_D, and the arithmetic-geometric mean (AGM) for the rest (Abramowitz and Stegun 16.4, 17.6).
With a_0 = 1, b_0 = sqrt(p), a_n = (a_{n-1} + b_{n-1})/2, b_n = sqrt(a_{n-1} b_{n-1}),
c_n = (a_{n-1} - b_{n-1})/2:

* K = pi / (2 a_N) and (K - E)/K = (c_0^2 + 2 c_1^2 + ... + 2^N c_N^2)/2, c_0^2 = m;
* sn, cn, dn by the descending recursion phi_N = 2^N a_N u,
  sin(2 phi_{n-1} - phi_n) = (c_n/a_n) sin phi_n, sn = sin phi_0, cn = cos phi_0,
  dn = cos phi_0 / cos(phi_1 - phi_0), at u itself (no period reduction, no reflection, no
  theta series);
* Jacobi's zeta function Z(u) = c_1 sin phi_1 + ... + c_N sin phi_N, so
  u - Eps(u) = u (K - E)/K - Z(u) (Eps = Z + (E/K) u, DLMF 22.16(iii)).

Only sqrt(p) enters, so p = 1e-300 (or e^-2000) needs no 1 - p in 300 digits; the working
precision grows with ln(1/p) so that sqrt(p) is resolved next to 1 inside the recursion.
test_references_agree_with_mpmath checks these references against mpmath's ellipk, ellipe and
ellipfun where those are cheap.

Tolerances. The Carlson and complete integrals must be good to a few ulp. sn, cn and dn must
be good to RTOL relative to themselves, even where they are tiny, up to what no double
implementation can avoid: K is rounded, so the reduced argument u - 2jK carries an absolute
error of order eps (|u| + (2|j| + 1) K), which moves f by that times |f'|.
"""

from __future__ import annotations

import math
from functools import cache

import mpmath as mp
import numpy as np
import pytest

from hairbed._core._kernels.elliptic import (
    complete_e,
    complete_k,
    complete_k_m,
    k_minus_e,
    rd,
    rf,
    rf_rd,
)
from hairbed._core._kernels.jacobi_elliptic import jacobi, jacobi_prepared, jacobi_setup

EPS = 2.0**-52
#: Carlson and complete integrals: a few ulp.
ULP_TOL = 4 * EPS
#: Jacobi functions against mpmath.
RTOL = 1e-13
#: Agreement with the numpy implementation (tests/naive/elliptic.py).
NUMPY_RTOL = 1e-14
#: Below this the comparison is absolute (the double result may be subnormal or zero).
TINY = 1e-290
SEED = 20251201


def _rel(got, ref):
    return abs(got - float(ref)) / abs(ref)


# --- references ---------------------------------------------------------------------------


def _dps(p_digits, u=0.0):
    """Digits that resolve sqrt(p) next to 1 (p = 10^-p_digits), with 40 to spare."""
    return int(40 + p_digits / 2 + math.log10(1.0 + abs(u)))


class Param:
    """A parameter: doubles m, p, tau for the kernels, exact mpf values for the references."""

    def __init__(self, *, m=None, p=None, tau=None):
        if m is not None:  # m exact, p = 1 - m rounded (exact for m >= 1/2)
            self.m, self.p = m, 1.0 - m
            self.p_digits = 0.0 if m < 0.5 else -math.log10(1.0 - m)
            self._p = lambda: 1 - mp.mpf(m)
        elif p > 0.0:  # p exact, m = 1 - p rounded (exact for p >= 1/2)
            self.m, self.p = 1.0 - p, p
            self.p_digits = -math.log10(p)
            self._p = lambda: mp.mpf(p)
        else:  # p underflowed: e^tau
            self.m, self.p = 1.0, 0.0
            self.p_digits = -tau / math.log(10.0)
            self._p = lambda: mp.exp(mp.mpf(tau))
        self.tau = tau if tau is not None else (math.log(self.p) if self.p > 0 else -math.inf)
        with mp.workdps(_dps(self.p_digits)):
            pp = self._p()
            k, kme = _agm_complete(mp.sqrt(pp), 1 - pp)
            kp = mp.pi / (2 * mp.agm(1, mp.sqrt(1 - pp))) if pp < 1 else mp.inf
            self.k, self.kp, self.kme = float(k), float(kp), float(kme)
            self.k_mp, self.kme_mp, self.e_mp = k, kme, k - kme

    def __repr__(self):
        return f"Param(m={self.m!r}, p={self.p!r}, tau={self.tau!r})"

    def kernel_args(self):
        return self.m, self.p, self.tau, self.k, self.kp, self.kme


def _agm(sqrt_p):
    """The AGM scale a_n, c_n from a_0 = 1, b_0 = sqrt(p), at the current precision."""
    a, b = mp.mpf(1), sqrt_p
    aa, cc = [a], [None]
    tol = mp.ldexp(1, 8 - mp.mp.prec)
    while True:
        a, b, c = (a + b) / 2, mp.sqrt(a * b), (a - b) / 2
        aa.append(a)
        cc.append(c)
        if abs(c) <= tol * a:
            return aa, cc


def _agm_complete(sqrt_p, m):
    """K and K - E from the AGM."""
    aa, cc = _agm(sqrt_p)
    k = mp.pi / (2 * aa[-1])
    s = m + mp.fsum(mp.ldexp(c * c, n) for n, c in enumerate(cc) if n)
    return k, k * s / 2


def _agm_jacobi(u, sqrt_p, k, kme):
    """sn, cn, dn and u - Eps(u) of the mpf u from the AGM (see the module docstring)."""
    aa, cc = _agm(sqrt_p)
    n = len(aa) - 1
    phi = [mp.mpf(0)] * (n + 1)
    phi[n] = mp.ldexp(aa[n] * u, n)
    for i in range(n, 0, -1):
        phi[i - 1] = (phi[i] + mp.asin(cc[i] / aa[i] * mp.sin(phi[i]))) / 2
    zeta = mp.fsum(cc[i] * mp.sin(phi[i]) for i in range(1, n + 1))
    cn = mp.cos(phi[0])
    return mp.sin(phi[0]), cn, cn / mp.cos(phi[1] - phi[0]), u * kme / k - zeta


@cache
def _jacobi_ref(u, par):
    with mp.workdps(_dps(par.p_digits, u)):
        pp = par._p()
        k, kme = _agm_complete(mp.sqrt(pp), 1 - pp)
        return _agm_jacobi(mp.mpf(u), mp.sqrt(pp), k, kme)


def _jacobi_excess(got, ref, u, par, rtol):
    """Each error of (sn, cn, dn, u - Eps) over its tolerance (<= 1 passes); see the docstring."""
    sn, cn, dn, ume = (float(x) for x in ref)
    j = round(u / (2.0 * par.k))
    slack = 4.0 * EPS * (abs(u) + (2 * abs(j) + 1) * par.k)  # rounding of u - 2jK
    derivs = (cn * dn, -sn * dn, -par.m * sn * cn, par.m * sn * sn)
    out = []
    for i, (g, r) in enumerate(zip(got, (sn, cn, dn, ume))):
        scale = abs(r) if i < 3 else max(abs(r), 1.0, abs(u))
        out.append(abs(g - r) / (rtol * scale + slack * abs(derivs[i]) + TINY))
    return out


# --- Carlson --------------------------------------------------------------------------------


def _carlson_cases():
    rng = np.random.default_rng(SEED)
    cases = [
        (1e-300, 1e-250, 1.0),
        (0.0, 1e-300, 1.0),
        (1e-300, 0.0, 1.0),
        (1e-300, 1e-300, 1.0),
        (5e-324, 1.0, 2.0),
        (0.0, 5e-324, 1.0),
        (1.0, 1.0, 1.0),
        (0.0, 1.0, 1.0),
        (0.0, 1.0, 2.0),
        (1.0, 2.0, 3.0),
        (0.5, 1.0, 1e-200),
        (1e-20, 1.0, 1e20),
        (1e-150, 1e150, 1.0),
        (1e100, 1e100, 1e100),
        (3.0, 3.0, 3.0 + 1e-12),
    ]
    cases += [tuple(rng.uniform(0.0, 1.0, 3)) for _ in range(30)]
    for _ in range(80):
        x = 10.0 ** rng.uniform(-300.0, 20.0, 3)  # no underflow to 0: z > 0 for R_D
        if rng.uniform() < 0.25:
            x[rng.integers(2)] = 0.0  # x or y: allowed for R_D too
        cases.append(tuple(x))
    return [tuple(float(v) for v in c) for c in cases]


CARLSON_CASES = _carlson_cases()


@cache
def _carlson_ref(x, y, z):
    with mp.workdps(40):
        return mp.elliprf(x, y, z), mp.elliprd(x, y, z)


def _carlson_errors(x, y, z):
    """Relative errors of rf, rd and both halves of rf_rd (R_D only where it is finite)."""
    ref_f, ref_d = _carlson_ref(x, y, z)
    if ref_d > 1e300:  # R_D ~ z^(-3/2) overflows: outside the domain of rd and rf_rd
        return (_rel(rf(x, y, z), ref_f),)
    both = rf_rd(x, y, z)
    got = (rf(x, y, z), rd(x, y, z), *both)
    return tuple(_rel(g, r) for g, r in zip(got, (ref_f, ref_d, ref_f, ref_d)))


def test_carlson_against_mpmath():
    for x, y, z in CARLSON_CASES:
        assert max(_carlson_errors(x, y, z)) <= ULP_TOL, (x, y, z)


def test_rf_rd_share_the_sequence():
    """rf_rd gives both integrals of rf and rd (same stopping rules, same series)."""
    for x, y, z in CARLSON_CASES:
        if _carlson_ref(x, y, z)[1] < 1e300:  # R_D in range
            f, d = rf_rd(x, y, z)
            assert f == pytest.approx(rf(x, y, z), rel=2 * EPS)
            assert d == pytest.approx(rd(x, y, z), rel=2 * EPS)


# --- complete integrals ---------------------------------------------------------------------


def _complete_params():
    rng = np.random.default_rng(SEED + 1)
    ps = [1.0, 0.9, 0.75, 0.5, 0.3, 0.1, 1e-2, 1e-4, 1e-8, 2.0**-52, 1e-17, 1e-30]
    ps += [1e-100, 1e-200, 1e-300, 1e-305, 1e-310, 5e-324]
    ps += list(10.0 ** rng.uniform(-300.0, 0.0, 40))
    pars = [Param(p=float(p)) for p in ps]
    pars += [Param(p=0.0, tau=t) for t in (-5000.0, -2000.0, -800.0)]
    return pars


@pytest.fixture(scope="module")
def complete_params():
    return _complete_params()


def test_complete_integrals_against_agm(complete_params):
    for par in complete_params:
        k = complete_k(par.p, par.tau)
        assert _rel(k, par.k_mp) <= ULP_TOL, (par, k, par.k)
        kme = k_minus_e(par.m, par.p, k)
        # (below p = 1e-300 K - E = K - 1 inherits the error of the given K)
        assert abs(kme - par.kme_mp) <= ULP_TOL * par.kme + abs(k - par.k_mp), par
        assert _rel(complete_e(par.p), par.e_mp) <= ULP_TOL, par
    assert complete_e(0.0) == 1.0
    assert complete_k(0.0, -2000.0) == math.log(4.0) + 1000.0


def test_complete_e_against_mpmath():
    rng = np.random.default_rng(SEED + 2)
    for p in [1.0, 0.5, 0.25, 1e-3, 1e-10, 1e-300, 5e-324, *10.0 ** rng.uniform(-20, 0, 30)]:
        with mp.workdps(40 - int(math.log10(p)) if p > 1e-25 else 40):
            ref = mp.ellipe(1 - mp.mpf(p)) if p > 1e-25 else _e_from_agm(p)
        assert _rel(complete_e(float(p)), ref) <= ULP_TOL, p


def _e_from_agm(p):
    k, kme = _agm_complete(mp.sqrt(mp.mpf(p)), 1 - mp.mpf(p))
    return k - kme


def test_complete_k_m_against_mpmath():
    rng = np.random.default_rng(SEED + 3)
    ms = [0.0, 1e-300, 1e-10, 0.1, 0.5, 0.9, 1.0 - 1e-10, 1.0 - 2.0**-52]
    ms += list(rng.uniform(0.0, 1.0, 30))
    for m in ms:
        with mp.workdps(40):
            ref = mp.pi / (2 * mp.agm(1, mp.sqrt(1 - mp.mpf(m))))
        assert _rel(complete_k_m(float(m)), ref) <= ULP_TOL, m


# --- Jacobi functions -----------------------------------------------------------------------


def _jacobi_params():
    pars = [Param(m=m) for m in (0.0, 1e-20, 1e-8, 0.1, 0.25, 0.4, 0.5)]
    pars += [Param(p=p) for p in (0.4999999, 0.3, 0.1, 1e-2, 1e-4, 1e-8, 1e-16, 1e-30)]
    pars += [Param(p=p) for p in (1e-60, 1e-120, 1e-200, 1e-300)]
    pars.append(Param(p=0.0, tau=-2000.0))
    return pars


JACOBI_PARAMS = _jacobi_params()


def _jacobi_cases():
    rng = np.random.default_rng(SEED + 4)
    cases = []
    for par in JACOBI_PARAMS:
        k = par.k
        us = list(rng.uniform(-4.0 * k, 4.0 * k, 6))
        us += list(rng.uniform(-1e-2, 1e-2, 1) * k) + [1e-14, 1e-9, -1e-5 * k]
        us += [0.5 * k * (1 - 1e-12), 0.5 * k * (1 + 1e-12), 0.999 * k, -1.001 * k, 1.5 * k]
        us += [2 * k * (1 - 1e-9), -3.3 * k]
        if par.p_digits > 250:
            us += [1e3, -1e3, 1e4, -1e4]
        cases += [(float(u), par) for u in us]
    return cases


JACOBI_CASES = _jacobi_cases()


def test_jacobi_against_agm():
    for u, par in JACOBI_CASES:
        got = jacobi(u, *par.kernel_args())
        excess = _jacobi_excess(got, _jacobi_ref(u, par), u, par, RTOL)
        assert max(excess) <= 1.0, (u, par, got, excess)


def test_jacobi_where_cn_dn_are_tiny():
    """cn, dn = sqrt(p) (sd, nd)(K - |r|) near u = (2j + 1) K stay relatively accurate."""
    for par, ws in (
        (Param(p=1e-300), (5.0, 69.0, 150.0)),
        (Param(p=0.0, tau=-2000.0), (320.0, 480.0)),
    ):
        k = par.k
        for w in ws:
            for u in (k - w, -(k - w), 3 * k + w, 11 * k - w):
                got = jacobi(u, *par.kernel_args())
                assert 1e-300 < abs(got[1]) < 1e-60 and 1e-300 < got[2] < 1e-60
                excess = _jacobi_excess(got, _jacobi_ref(u, par), u, par, RTOL)
                assert max(excess) <= 1.0, (u, par, got, excess)


def test_jacobi_prepared_is_jacobi():
    for u, par in JACOBI_CASES[::3]:
        m, p, tau, k, kp, kme = par.kernel_args()
        c = jacobi_setup(m, p, tau, k, kp)
        assert jacobi_prepared(u, m, tau, k, kme, c) == jacobi(u, m, p, tau, k, kp, kme)


def test_jacobi_symmetries():
    """Odd/even in u, and the quarter-period values sn(K) = 1, cn(K) = 0, dn(K) = sqrt(p)."""
    for par in JACOBI_PARAMS[1:-1]:
        args = par.kernel_args()
        for u in (0.3, 1.7 * par.k, -5.2 * par.k):
            a, b = jacobi(u, *args), jacobi(-u, *args)
            assert (b[0], b[1], b[2], b[3]) == (-a[0], a[1], a[2], -a[3])
        sn, cn, dn, ume = jacobi(par.k, *args)
        assert sn == pytest.approx(1.0, rel=2 * EPS) and cn == 0.0
        assert dn == pytest.approx(math.sqrt(par.p), rel=1e-15)
        assert ume == pytest.approx(par.kme, rel=1e-15)


def test_references_agree_with_mpmath():
    """The AGM references against mpmath's ellipk, ellipe and ellipfun (cheap parameters)."""
    for p, frac in ((0.7, 0.3), (0.5, -1.7), (0.3, 0.9), (1e-3, 2.6), (1e-12, -0.55)):
        par = Param(p=p)
        u = frac * par.k
        with mp.workdps(50 - int(math.log10(p))):
            mm = 1 - mp.mpf(p)
            k, e = mp.ellipk(mm), mp.ellipe(mm)
            assert float(k) == par.k and abs(k - e - par.kme) <= 2 * EPS * par.kme
            us = mp.mpf(u)
            ref = _jacobi_ref(u, par)
            for name, r in zip(("sn", "cn", "dn"), ref):
                assert abs(mp.ellipfun(name, us, m=mm) / r - 1) < 1e-30
            j = mp.nint(us / (2 * k))
            phi = mp.asin(mp.ellipfun("sn", us - 2 * j * k, m=mm))  # am, |u - 2jK| <= K
            ume = us - 2 * j * e - mp.ellipe(phi, mm)
            assert abs(ume / ref[3] - 1) < 1e-30


# --- agreement with the numpy implementation ------------------------------------------------


def test_agreement_with_numpy_elliptic():
    """The kernels reproduce the numpy layer they replace (tests/naive/elliptic.py).

    The two round the reduced argument alike only up to the order of operations, so the
    comparison carries the same conditioning allowance as the mpmath one.
    """
    from naive.elliptic import complete_k as np_complete_k
    from naive.elliptic import complete_k_minus_e as np_complete_k_minus_e
    from naive.elliptic import jacobi as np_jacobi

    rng = np.random.default_rng(SEED + 5)
    n = 400
    p = 10.0 ** rng.uniform(-300.0, math.log10(0.9999), n)
    p[: n // 4] = rng.uniform(0.5, 1.0, n // 4)  # m <= 1/2: the q series
    m = 1.0 - p
    tau = np.log(p)
    k_np = np_complete_k(p, tau)
    kme_np = np_complete_k_minus_e(m, p, k_np)
    k = np.array([complete_k(a, b) for a, b in zip(p, tau)])
    kme = np.array([k_minus_e(a, b, c) for a, b, c in zip(m, p, k)])
    kp = np.array([complete_k_m(a) for a in p])
    assert np.allclose(k, k_np, rtol=NUMPY_RTOL, atol=0.0)
    assert np.allclose(kme, kme_np, rtol=NUMPY_RTOL, atol=0.0)
    u = rng.uniform(-5.0, 5.0, n) * k
    ref = np_jacobi(u, m, p, k, kp, kme, tau)
    for i in range(n):
        par = _FakeParam(m[i], k[i])
        got = jacobi(u[i], m[i], p[i], tau[i], k[i], kp[i], kme[i])
        excess = _jacobi_excess(got, [r[i] for r in ref], u[i], par, NUMPY_RTOL)
        assert max(excess) <= 1.0, (u[i], p[i], got, [r[i] for r in ref])


class _FakeParam:
    def __init__(self, m, k):
        self.m, self.k = float(m), float(k)
