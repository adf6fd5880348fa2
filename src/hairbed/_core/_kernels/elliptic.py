r"""Carlson's symmetric elliptic integrals and the complete integrals K and E (scalar kernels).

Carlson's integrals (DLMF 19.16.1, 19.16.5) are

.. math::

    R_F(x, y, z) = \frac{1}{2} \int_0^\infty \frac{dt}{\sqrt{(t + x)(t + y)(t + z)}},
    \qquad
    R_D(x, y, z) = \frac{3}{2} \int_0^\infty \frac{dt}{\sqrt{(t + x)(t + y)} (t + z)^{3/2}},

for x, y, z >= 0 with at most one of them zero (and z > 0 for R_D). They are computed by
Carlson's duplication theorem (DLMF 19.26.18, 19.26.20): with
:math:`\lambda = \sqrt{x}\sqrt{y} + \sqrt{y}\sqrt{z} + \sqrt{z}\sqrt{x}`,

.. math::

    R_F(x, y, z) = R_F\left(\frac{x + \lambda}{4}, \frac{y + \lambda}{4},
    \frac{z + \lambda}{4}\right),
    \qquad
    R_D(x, y, z) = \frac{1}{4} R_D\left(\frac{x + \lambda}{4}, \ldots\right)
    + \frac{3}{\sqrt{z} (z + \lambda)},

which draws the three arguments together by a factor 4 per step, until a Taylor expansion about
their mean A in the elementary symmetric functions E2, E3 (E4, E5) of the scaled deviations
X = 1 - x/A, ... terminates the sum (DLMF 19.36.1; B. C. Carlson, "Numerical computation of real
or complex elliptic integrals", Numer. Algorithms 10 (1995) 13-26). Here the series runs to
seventh order, so the truncation error is of eighth order in max |X|; the loop stops once that
error is below a tenth of an ulp.

The complete integrals of parameter m = 1 - p are (DLMF 19.2.8, 19.25.1)

.. math::

    K(m) = \int_0^{\pi/2} \frac{d\theta}{\sqrt{1 - m \sin^2\theta}} = R_F(0, p, 1),
    \qquad
    E(m) = \int_0^{\pi/2} \sqrt{1 - m \sin^2\theta}\, d\theta,
    \qquad
    K(m) - E(m) = \frac{m}{3} R_D(0, p, 1).

Every function takes the complementary parameter p (not m): near the separatrix m -> 1, K has
the logarithmic singularity :math:`K = \ln 4 - \frac{1}{2} \ln p + O(p \ln p)`
(DLMF 19.12.1), so p must be known to full relative accuracy and ``tau = ln p`` is carried
where p underflows. K and E use the Cephes minimax approximations in p and ln p.

All kernels trust their inputs (the callers validate).
"""

from __future__ import annotations

import math

from .._jit import kernel

__all__ = [
    "complete_e",
    "complete_e_log",
    "complete_k",
    "complete_k_m",
    "k_minus_e",
    "rd",
    "rf",
    "rf_rd",
]

_LN4 = 1.3862943611198906188  # ln 4
#: Below this ln p the O(p) term of K = ln 4 - tau/2 + O(p ln p) is far below an ulp.
_TAU_UNDERFLOW = -700.0
_THIRD = 1.0 / 3.0
# Stop the duplication once max |X| < _RF_TOL (resp. _RD_TOL): the first omitted terms of the
# 7th-order series are below 0.016 |X|^8 for R_F and 0.082 |X|^8 for R_D (measured against
# mpmath), i.e. below 2e-17 relative.
_RF_TOL = 1.0 / 75.0
_RD_TOL = 1.0 / 90.0
#: Far more duplication steps than any finite arguments need (about 20 at most): the loop
#: cannot hang on inf or nan.
_MAX_STEPS = 100

# Cephes ellpk.c and ellpe.c (Stephen L. Moshier, Cephes Math Library 2.0/2.1), as distributed
# with SciPy (scipy/special/cephes) under the BSD-3-Clause license; highest degree first.
_KP = (
    1.37982864606273237150e-4,
    2.28025724005875567385e-3,
    7.97404013220415179367e-3,
    9.85821379021226008714e-3,
    6.87489687449949877925e-3,
    6.18901033637687613229e-3,
    8.79078273952743772254e-3,
    1.49380448916805252718e-2,
    3.08851465246711995998e-2,
    9.65735902811690126535e-2,
    1.38629436111989062502e0,
)
_KQ = (
    2.94078955048598507511e-5,
    9.14184723865917226571e-4,
    5.94058303753167793257e-3,
    1.54850516649762399335e-2,
    2.39089602715924892727e-2,
    3.01204715227604046988e-2,
    3.73774314173823228969e-2,
    4.88280347570998239232e-2,
    7.03124996963957469739e-2,
    1.24999999999870820058e-1,
    4.99999999999999999821e-1,
)
_EP = (
    1.53552577301013293365e-4,
    2.50888492163602060990e-3,
    8.68786816565889628429e-3,
    1.07350949056076193403e-2,
    7.77395492516787092951e-3,
    7.58395289413514708519e-3,
    1.15688436810574127319e-2,
    2.18317996015557253103e-2,
    5.68051945617860553470e-2,
    4.43147180560990850618e-1,
    1.00000000000000000299e0,
)
_EQ = (
    3.27954898576485872656e-5,
    1.00962792679356715133e-3,
    6.50609489976927491433e-3,
    1.68862163993311317300e-2,
    2.61769742454493659583e-2,
    3.34833904888224918614e-2,
    4.27180926518931511717e-2,
    5.85936634471101055642e-2,
    9.37499997197644278445e-2,
    2.49999999999888314361e-1,
)


@kernel
def _rf_series(dx, dy, fa):
    """7th-order Carlson series of R_F sqrt(A) from the initial deviations A0 - x, A0 - y."""
    xx = dx * fa
    yy = dy * fa
    zz = -xx - yy  # X + Y + Z = 0 exactly
    xy = xx * yy
    e2 = xy - zz * zz
    e3 = xy * zz
    return (
        1.0
        + e3 * (1.0 / 14.0 + e3 * (3.0 / 104.0))
        + e2
        * (-0.1 + e2 * (1.0 / 24.0 - e2 * (5.0 / 208.0)) + e3 * (e2 * (1.0 / 16.0) - 3.0 / 44.0))
    )


@kernel
def _rd_series(dx, dy, fa):
    """7th-order Carlson series of R_D A^(3/2) from the initial deviations A0 - x, A0 - y."""
    xx = dx * fa
    yy = dy * fa
    zz = (xx + yy) * -_THIRD  # X + Y + 3 Z = 0
    xy = xx * yy
    z2 = zz * zz
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * zz
    e4 = 3.0 * (xy - z2) * z2
    e5 = xy * z2 * zz
    return (
        1.0
        + e2 * (-3.0 / 14.0 + e2 * (9.0 / 88.0 - e2 * (1.0 / 16.0)))
        + e3 * (1.0 / 6.0 + e3 * (3.0 / 40.0) + e2 * (e2 * (45.0 / 272.0) - 9.0 / 52.0))
        + e4 * (-3.0 / 22.0 + e2 * (3.0 / 20.0) - e3 * (9.0 / 68.0))
        + e5 * (3.0 / 26.0 - e2 * (9.0 / 68.0))
    )


@kernel
def rf(x, y, z):
    """Carlson's R_F(x, y, z) for x, y, z >= 0, at most one of them zero.

    Returns
    -------
    float
        R_F to a few ulp, for arguments anywhere from subnormal to about 1e307.
    """
    a0 = (x + y + z) * _THIRD
    dx = a0 - x
    dy = a0 - y
    q = max(abs(dx), abs(dy), abs(a0 - z))  # 4^n max |X_n| A_n, never overflows
    a = a0
    f = 1.0  # 4^-n
    for _ in range(_MAX_STEPS):
        if not q >= _RF_TOL * a:  # also stops at once on nan
            break
        sx = math.sqrt(x)  # product of roots, not root of product: no underflow
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x = (x + lam) * 0.25
        y = (y + lam) * 0.25
        z = (z + lam) * 0.25
        a = (a + lam) * 0.25
        q *= 0.25
        f *= 0.25
    # X_n = 4^-n (A0 - x0) / A_n exactly: no cancellation from A_n - x_n
    return _rf_series(dx, dy, f / a) / math.sqrt(a)


@kernel
def rd(x, y, z):
    """Carlson's R_D(x, y, z) for x, y >= 0 (at most one zero) and z > 0.

    Returns
    -------
    float
        R_D to a few ulp, for arguments anywhere from subnormal to about 1e307 (where R_D,
        of order z^(-3/2), does not overflow).
    """
    a0 = (x + y + 3.0 * z) * 0.2
    dx = a0 - x
    dy = a0 - y
    q = max(abs(dx), abs(dy), abs(a0 - z))
    a = a0
    f = 1.0
    s = 0.0
    for _ in range(_MAX_STEPS):
        if not q >= _RD_TOL * a:
            break
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        s += f / (sz * (z + lam))
        x = (x + lam) * 0.25
        y = (y + lam) * 0.25
        z = (z + lam) * 0.25
        a = (a + lam) * 0.25
        q *= 0.25
        f *= 0.25
    sa = math.sqrt(a)
    g = f / (a * sa)  # 4^-n A^(-3/2)
    return g * _rd_series(dx, dy, g * sa) + 3.0 * s


@kernel
def rf_rd(x, y, z):
    """R_F(x, y, z) and R_D(x, y, z) from one shared duplication sequence.

    The duplication step (the three roots) is the same for both integrals; only the means
    differ, so both are carried until both series have converged.

    Returns
    -------
    tuple of float
        (R_F, R_D).
    """
    af0 = (x + y + z) * _THIRD
    ad0 = (x + y + 3.0 * z) * 0.2
    dfx = af0 - x
    dfy = af0 - y
    ddx = ad0 - x
    ddy = ad0 - y
    qf = max(abs(dfx), abs(dfy), abs(af0 - z))
    qd = max(abs(ddx), abs(ddy), abs(ad0 - z))
    af = af0
    ad = ad0
    f = 1.0
    s = 0.0
    for _ in range(_MAX_STEPS):
        if not (qf >= _RF_TOL * af or qd >= _RD_TOL * ad):
            break
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        s += f / (sz * (z + lam))
        x = (x + lam) * 0.25
        y = (y + lam) * 0.25
        z = (z + lam) * 0.25
        af = (af + lam) * 0.25
        ad = (ad + lam) * 0.25
        qf *= 0.25
        qd *= 0.25
        f *= 0.25
    r_f = _rf_series(dfx, dfy, f / af) / math.sqrt(af)
    sa = math.sqrt(ad)
    g = f / (ad * sa)
    return r_f, g * _rd_series(ddx, ddy, g * sa) + 3.0 * s


@kernel
def _horner(x, c):
    """Polynomial with coefficients c (highest degree first) at x."""
    r = c[0]
    for i in range(1, len(c)):
        r = r * x + c[i]
    return r


@kernel
def complete_k(p, tau):
    """Complete elliptic integral K(m) of parameter m = 1 - p, given p in [0, 1].

    Parameters
    ----------
    p : float
        Complementary parameter (may have underflowed to 0).
    tau : float
        ln p, finite even where p underflowed (used for the logarithmic term).

    Returns
    -------
    float
        K(m): Cephes ``ellpk``, K = P(p) - ln(p) Q(p), and ln 4 - tau/2 once tau < -700.
    """
    if tau < _TAU_UNDERFLOW:
        return _LN4 - 0.5 * tau
    return _horner(p, _KP) - tau * _horner(p, _KQ)


@kernel
def complete_k_m(m):
    """Complete elliptic integral K(m) for a parameter m in [0, 1) given directly.

    Returns
    -------
    float
        K(m), via :func:`complete_k` with p = 1 - m (exact for m >= 1/2) and ln p = log1p(-m).
    """
    return complete_k(1.0 - m, math.log1p(-m))


@kernel
def complete_e(p):
    """Complete elliptic integral E(m) of parameter m = 1 - p, given p in [0, 1].

    Returns
    -------
    float
        E(m): Cephes ``ellpe``, E = P(p) - p ln(p) Q(p); E = 1 at p = 0.
    """
    if p == 0.0:
        return 1.0
    return complete_e_log(p, math.log(p))


@kernel
def complete_e_log(p, tau):
    """:func:`complete_e` given tau = ln p as well (a caller that carries it saves a log)."""
    if p == 0.0:
        return 1.0
    return _horner(p, _EP) - tau * (p * _horner(p, _EQ))


@kernel
def k_minus_e(m, p, k):
    """K(m) - E(m) without cancellation, for m = 1 - p.

    Parameters
    ----------
    m, p : float
        Parameter and complementary parameter, both accurate.
    k : float
        K(m) (used once p < 1e-300, where K - E = K - 1 to relative order p ln p).

    Returns
    -------
    float
        (m/3) R_D(0, p, 1) (DLMF 19.25.1).
    """
    if p < 1e-300:
        return k - 1.0
    return m / 3.0 * rd(0.0, p, 1.0)
