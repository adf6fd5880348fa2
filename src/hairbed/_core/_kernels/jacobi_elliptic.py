r"""Jacobi's elliptic functions sn, cn, dn and u - Eps(u) for real u (scalar kernels).

For parameter m = 1 - p in [0, 1), with K = K(m), K' = K(p) and E = E(m), the Jacobi
functions (DLMF 22.2) are

.. math::

    \operatorname{sn} u = \frac{\theta_3}{\theta_2} \frac{\theta_1(z|q)}{\theta_4(z|q)}, \quad
    \operatorname{cn} u = \frac{\theta_4}{\theta_2} \frac{\theta_2(z|q)}{\theta_4(z|q)}, \quad
    \operatorname{dn} u = \frac{\theta_4}{\theta_3} \frac{\theta_3(z|q)}{\theta_4(z|q)}, \quad
    z = \frac{\pi u}{2K}, \quad q = e^{-\pi K'/K},

(theta constants at z = 0), and Jacobi's epsilon function is
:math:`\mathrm{Eps}(u) = \int_0^u \operatorname{dn}^2 t\, dt = E(\operatorname{am} u | m)`
(DLMF 22.16(ii)), continuous in u with Eps(u + 2K) = Eps(u) + 2E; what is returned is
:math:`u - \mathrm{Eps}(u) = m \int_0^u \operatorname{sn}^2 t\, dt`.

Evaluation:

* period reduction u = 2jK + r, |r| <= K: sn and cn change sign with j, dn is 2K-periodic
  and u - Eps(u) = 2j(K - E) + (r - Eps(r)) (DLMF Table 22.4.3, 22.16(ii));
* reflection of |r| > K/2 to w = K - |r| (DLMF Table 22.4.3, 22.16(ii)):
  sn(K - w) = cd(w), cn(K - w) = sqrt(p) sd(w), dn(K - w) = sqrt(p) nd(w) and
  Eps(K - w) = E - Eps(w) + m sn(w) cd(w), which keeps relative accuracy near the zeros of
  cn and the minima of dn;
* on 0 <= w <= K/2 the theta series in the nome q for m <= 1/2 and, for m > 1/2, in the
  complementary nome q1 = exp(-pi K/K') through Jacobi's imaginary transformation
  sn(u|m) = -i sc(iu|p), cn(u|m) = nc(iu|p), dn(u|m) = dc(iu|p) (DLMF Table 22.6.1), with theta
  functions at the imaginary argument iy, y = pi w / (2K'). Either nome is at most e^-pi,
  so four terms of theta_1, theta_2 and three of theta_3, theta_4 reach full precision (the
  first omitted terms are below 1e-19 relative). In the second form theta_1, theta_2 are
  scaled by e^-y, and sqrt(p) sd, sqrt(p) nd are scaled values times sqrt(p) e^y, taken as
  sqrt(p) / e^-y where both are in range (so dn(K) = sqrt(p) to the rounding of p) and as
  exp(tau/2 + y) where p underflows: nothing over- or underflows before the result does, up
  to u ~ 1e4 at p = 0 (tau = ln p is carried where p underflows);
* w - Eps(w) = (m/3) sn^3 R_D(cn^2, dn^2, 1) (DLMF 19.25.9 with F(am w) = w), without the
  cancellation of w - Eps(w), and w - tanh w (the m = 1 form) where cn^2 underflows.

This is the scalar port of the numpy layer's ``jacobi`` (``hairbed._elliptic``, now
``tests/naive/elliptic.py``), with two refinements: the odd theta series at small y is summed
without cancellation, and a reduction that rounds to |r| just above K is folded back.
:func:`jacobi_setup` computes what depends only on the parameter; :func:`jacobi_prepared`
evaluates one argument from it (use the pair for many u at one parameter); :func:`jacobi`
does both.
"""

from __future__ import annotations

import math

from .._jit import kernel
from .elliptic import rd

__all__ = ["jacobi", "jacobi_prepared", "jacobi_setup", "sncndn_prepared"]

_PI = math.pi


@kernel
def jacobi_setup(m, p, tau, k, kp):
    """Constants of the theta series that depend only on the parameter m = 1 - p.

    Parameters
    ----------
    m, p : float
        Parameter and complementary parameter, p = 1 - m, both accurate.
    tau : float
        ln p (finite even where p underflowed).
    k, kp : float
        K(m) and K(p).

    Returns
    -------
    tuple of 16 floats
        (branch, scale, log nome, q, q^2, q^4, q^6, q^9, q^12, the five ratios of theta
        constants for sn and cd, cn, dn, sd, nd, sqrt(p) or 0 once p < 1e-300, 1/(2K)), with
        branch 0 for the nome q of m (m <= 1/2), 1 for the complementary nome q1 and
        scale = pi/(2K) or pi/(2K'); pass it to :func:`jacobi_prepared`.
    """
    if m <= 0.5:
        branch = 0.0
        lq = -_PI * kp / k
        scale = 0.5 * _PI / k
    else:
        branch = 1.0
        lq = -_PI * k / kp
        scale = 0.5 * _PI / kp
    q = math.exp(lq)
    q2 = q * q
    q4 = q2 * q2
    q6 = q4 * q2
    q9 = q6 * q2 * q
    q12 = q6 * q6
    # theta constants, the q^(1/4) of theta_2 divided out (finite as m -> 0)
    t2 = 1.0 + q2 + q6 + q12
    t3 = 1.0 + 2.0 * (q + q4 + q9)
    t4 = 1.0 - 2.0 * (q - q4 + q9)
    r3 = t3 / t4
    if branch == 0.0:
        # sn, cd ~ theta_3/theta_2; cn ~ theta_4/theta_2; dn ~ theta_4/theta_3
        k_sn = t3 / t2
        k_cn = t4 / t2
        k_dn = t4 / t3
        k_nd = r3
    else:
        k_sn = r3
        k_cn = t2 / t4
        k_dn = t2 / t3
        k_nd = t3 / t2
    k_sd = r3 * t3 / t2
    return (
        branch,
        scale,
        lq,
        q,
        q2,
        q4,
        q6,
        q9,
        q12,
        k_sn,
        k_cn,
        k_dn,
        k_sd,
        k_nd,
        # sqrt(p) to the rounding of p itself; 0 routes jacobi_prepared to exp(tau/2 + y)
        math.sqrt(p) if p >= 1e-300 else 0.0,
        0.5 / k,
    )


@kernel
def _theta_small_m(w, c):
    """sn, cn, dn, cd, sd, nd (and y = 0, e^-y = 1) at 0 <= w <= K/2 for m <= 1/2."""
    z = c[1] * w
    s = math.sin(z)
    co = math.cos(z)
    s2 = 2.0 * s * co
    c2 = (co - s) * (co + s)
    # sin, cos of 3z, 5z, 7z by rotation through 2z: errors stay ~ulp, times q^2 or less
    s3 = s * c2 + co * s2
    c3 = co * c2 - s * s2
    s5 = s3 * c2 + c3 * s2
    c5 = c3 * c2 - s3 * s2
    s7 = s5 * c2 + c5 * s2
    c7 = c5 * c2 - s5 * s2
    c4 = 2.0 * c2 * c2 - 1.0
    c6 = 2.0 * c2 * c4 - c2
    q, q2, q4, q6, q9, q12 = c[3], c[4], c[5], c[6], c[7], c[8]
    th1 = s - q2 * s3 + q6 * s5 - q12 * s7
    th2 = co + q2 * c3 + q6 * c5 + q12 * c7
    even = q4 * c4
    odd = q * c2 + q9 * c6
    th3 = 1.0 + 2.0 * (odd + even)
    th4 = 1.0 - 2.0 * (odd - even)
    i3 = 1.0 / th3
    i4 = 1.0 / th4
    return (
        c[9] * th1 * i4,
        c[10] * th2 * i4,
        c[11] * th3 * i4,
        c[9] * th2 * i3,
        c[12] * th1 * i3,
        c[13] * th4 * i3,
        0.0,
        1.0,
    )


@kernel
def _theta_large_m(w, c):
    """sn, cn, dn, cd, sd e^-y, nd e^-y, y and e^-y at 0 <= w <= K/2 for m > 1/2.

    Theta functions of the complementary nome q1 at iy, y = pi w / (2K'). With
    d = e^-2y and a = q1 e^2y <= q1^(1/2) (as w <= K/2), every term of
    e^-y theta_1, e^-y theta_2, theta_3, theta_4 is a product of factors <= 1, so none
    overflows (at p = 0 they reduce to sn = tanh, cn = dn = sech), and
    q1^(n^2+n) (e^2ny - e^-(2n+2)y) = a^n q1^(n^2) (1 - d) (1 + d + ... + d^2n) has no
    cancellation at small y.
    """
    y = c[1] * w
    if y < 0.5:
        em = math.expm1(-y)
        ey = 1.0 + em  # e^-y
        d = ey * ey
        s0 = -em * (2.0 + em)  # 1 - e^-2y without cancellation
    else:
        ey = math.exp(-y)  # not 1 + expm1(-y): that loses e^-y for large y
        d = ey * ey
        s0 = 1.0 - d
    a = math.exp(c[2] + 2.0 * y)
    q, q2, q4, q6, q9 = c[3], c[4], c[5], c[6], c[7]
    d2 = d * d
    d3 = d2 * d
    d4 = d2 * d2
    d5 = d4 * d
    g2 = 1.0 + d + d2
    g4 = g2 + d3 + d4
    g6 = g4 + d5 + d5 * d
    aq = a * q
    a2q = a * a * q4
    a3q = a * a * a * q9
    big_s = 0.5 * s0 * (1.0 - aq * g2 + a2q * g4 - a3q * g6)
    big_c = 0.5 * ((1.0 + d) + aq * (1.0 + d3) + a2q * (1.0 + d5) + a3q * (1.0 + d5 * d2))
    odd = a + q * d + q6 * a * a * a + q9 * d3
    even = q2 * a * a + q4 * d2
    t3 = 1.0 + odd + even
    t4 = 1.0 - odd + even
    ic = 1.0 / big_c
    i3 = 1.0 / t3
    return (
        c[9] * big_s * ic,
        c[10] * t4 * ey * ic,
        c[11] * t3 * ey * ic,
        c[9] * t4 * i3,
        c[12] * big_s * i3,
        c[13] * big_c * i3,
        y,
        ey,
    )


@kernel
def jacobi_prepared(u, m, tau, k, kme, c):
    """Jacobi sn, cn, dn and u - Eps(u) at one argument, from :func:`jacobi_setup`.

    Parameters
    ----------
    u : float
        Argument (any real value).
    m : float
        Parameter.
    tau : float
        ln(1 - m), finite even where 1 - m underflowed.
    k, kme : float
        K(m) and K(m) - E(m).
    c : tuple of float
        ``jacobi_setup(m, 1 - m, tau, k, K(1 - m))``.

    Returns
    -------
    tuple of float
        (sn u, cn u, dn u, u - Eps(u)).
    """
    return _jacobi_core(u, m, tau, k, kme, c, True)


@kernel
def sncndn_prepared(u, m, tau, k, c):
    """sn, cn, dn (and a 0 in place of u - Eps(u)) as :func:`jacobi_prepared`, without the
    R_D that u - Eps(u) costs."""
    return _jacobi_core(u, m, tau, k, 0.0, c, False)


@kernel
def _jacobi_core(u, m, tau, k, kme, c, want_me):
    """The body of :func:`jacobi_prepared`; u - Eps(u) only if ``want_me``."""
    k2 = 2.0 * k
    j = math.floor(u * c[15] + 0.5)
    r = u - j * k2
    # rounding of j can leave |r| just above K: fold back so the reflection sees K - |r| >= 0
    if r > k:
        r -= k2
        j += 1.0
    elif r < -k:
        r += k2
        j -= 1.0
    odd = 0.5 * j != math.floor(0.5 * j)
    neg = r < 0.0
    a = min(abs(r), k)
    hi = a > 0.5 * k
    w = k - a if hi else a
    if c[0] == 0.0:
        sn, cn, dn, cd, sd, nd, y, ey = _theta_small_m(w, c)
    else:
        sn, cn, dn, cd, sd, nd, y, ey = _theta_large_m(w, c)
    cn2 = cn * cn
    if not want_me:
        w_me = 0.0
    elif cn2 < 1e-300:
        # only reached for m so close to 1 that the m = 1 form is exact to rounding
        w_me = w - math.tanh(w)
    else:
        w_me = m / 3.0 * (sn * sn * sn) * rd(cn2, dn * dn, 1.0)
    if hi:
        # f = sqrt(p) e^y: from sqrt(p) itself (exact at u = K, dn(K) = sqrt(p)) where p and
        # e^-y are in range, else as one exponential (p underflowed, or y beyond ~690)
        if c[14] > 0.0 and ey > 1e-300:
            f = c[14] / ey
        else:
            f = math.exp(0.5 * tau + y)
        w_me = kme - w_me - m * sn * cd
        sn = cd
        cn = f * sd
        dn = f * nd
    if odd:
        sn = -sn
        cn = -cn
    if neg:
        sn = -sn
        w_me = -w_me
    return sn, cn, dn, 2.0 * j * kme + w_me


@kernel
def jacobi(u, m, p, tau, k, kp, kme):
    """Jacobi sn, cn, dn and u - Eps(u) for real u and parameter m = 1 - p.

    Parameters
    ----------
    u : float
        Argument (any real value).
    m, p : float
        Parameter and complementary parameter, p = 1 - m, both accurate; m in [0, 1).
    tau : float
        ln p, finite even where p underflowed to 0 (e.g. -2000).
    k, kp : float
        K(m) and K(p).
    kme : float
        K(m) - E(m) (:func:`hairbed._core._kernels.elliptic.k_minus_e`).

    Returns
    -------
    tuple of float
        (sn u, cn u, dn u, u - Eps(u)); Eps is Jacobi's epsilon function, Eps(u) = E(am u | m),
        continuous in u.
    """
    return jacobi_prepared(u, m, tau, k, kme, jacobi_setup(m, p, tau, k, kp))
