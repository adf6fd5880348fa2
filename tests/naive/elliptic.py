"""Elliptic functions accurate up to the separatrix (parameter m -> 1).

Frozen copy of ``src/hairbed/_elliptic.py`` at commit 7300965 (the numpy core), kept as
the slow reference of the tests; see :mod:`naive`. Do not change the algorithms.

scipy.special is used only where it is accurate (theory.md §6): ``ellipkm1`` for K near
m = 1, ``ellipk``/``ellipe`` away from it, and Carlson's ``elliprf``/``elliprd`` with arguments
formed without cancellation. The Jacobi functions are our own: scipy's ``ellipj`` is wrong for
1 - m <= 1e-10 beyond u = K (scipy issue 8480). They use period reduction to [0, K/2] and
rapidly convergent theta series, in the nome q for m <= 1/2 and, through Jacobi's imaginary
transformation, in the complementary nome for m > 1/2 (nome <= exp(-pi) either way).

Every function takes the parameter as the pair (m, p) with p = 1 - m, both accurate, so that
nothing is lost to rounding m near 1. ``tau = ln p`` is carried where p may underflow.

References
----------
.. [1] NIST DLMF, chapters 19 (elliptic integrals) and 22 (Jacobi functions).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import special

__all__ = [
    "complete_k",
    "complete_k_minus_e",
    "jacobi",
    "LN4",
]

FloatArray = NDArray[np.float64]

LN4 = float(np.log(4.0))
#: Below this ln p the parameter is treated as m = 1 in the leading terms (p underflows).
_TAU_UNDERFLOW = -700.0
_NTERMS = 5  # theta-series terms: nome <= e^{-pi}, so q^(n^2) is below 1e-21 for n = 4


def complete_k(p: FloatArray, tau: FloatArray) -> FloatArray:
    """Complete elliptic integral K(m) of parameter m = 1 - p, for any p in (0, 1].

    Uses ``ellipkm1(p)`` (accurate for tiny p) and the separatrix limit K = ln 4 - tau/2 once p
    underflows (the next term is of relative order p).
    """
    under = tau < _TAU_UNDERFLOW
    k = special.ellipkm1(np.where(under, 0.5, p))
    return np.where(under, LN4 - 0.5 * tau, k)


def complete_k_minus_e(m: FloatArray, p: FloatArray, k: FloatArray) -> FloatArray:
    """K(m) - E(m) without cancellation: (m/3) R_D(0, 1 - m, 1) (DLMF 19.25.1).

    Near m = 1 (tiny p) K - E = K - 1 to relative order p ln p.
    """
    tiny = p < 1e-300
    rd = special.elliprd(0.0, np.where(tiny, 1.0, p), 1.0)
    return np.where(tiny, k - 1.0, m / 3.0 * rd)


def _theta_small_m(a: FloatArray, k: FloatArray, log_q: FloatArray) -> tuple[FloatArray, ...]:
    """sn, cn, dn, cd, sd, nd on 0 <= a <= K/2 for m <= 1/2 (theta series in q, DLMF 22.2).

    The q^(1/4) of theta_1 and theta_2 is divided out so that m -> 0 stays finite. The last
    element of the tuple is the scale exponent of sd and nd (0 here, see _theta_large_m).
    """
    n = np.arange(_NTERMS, dtype=np.float64)
    z = (0.5 * np.pi * a / k)[..., None]
    lq = log_q[..., None]
    w12 = np.exp((n * n + n) * lq)
    alt = (-1.0) ** n
    th1 = np.sum(alt * w12 * np.sin((2 * n + 1) * z), axis=-1)
    th2 = np.sum(w12 * np.cos((2 * n + 1) * z), axis=-1)
    th2_0 = np.sum(w12, axis=-1)
    n1 = n[1:]
    w34 = np.exp(n1 * n1 * lq)
    c = np.cos(2 * n1 * z)
    th3 = 1.0 + 2.0 * np.sum(w34 * c, axis=-1)
    th4 = 1.0 + 2.0 * np.sum(alt[1:] * w34 * c, axis=-1)
    th3_0 = 1.0 + 2.0 * np.sum(w34, axis=-1)
    th4_0 = 1.0 + 2.0 * np.sum(alt[1:] * w34, axis=-1)
    sn = th3_0 / th2_0 * th1 / th4
    cn = th4_0 / th2_0 * th2 / th4
    dn = th4_0 / th3_0 * th3 / th4
    return sn, cn, dn, cn / dn, sn / dn, 1.0 / dn, np.zeros_like(a)


def _theta_large_m(a: FloatArray, kp: FloatArray, log_q1: FloatArray) -> tuple[FloatArray, ...]:
    """sn, cn, dn, cd, sd e^-y, nd e^-y and y on 0 <= a <= K/2 for m > 1/2.

    Jacobi's imaginary transformation: sn(u|m) = -i sc(iu|p), cn(u|m) = nc(iu|p),
    dn(u|m) = dc(iu|p) (DLMF 22.6.12), with theta functions of the complementary nome
    q1 = exp(-pi K/K') at the imaginary argument i y, y = pi u / (2 K'). theta_1, theta_2 are
    scaled by e^{-y}; theta_3, theta_4 need no scaling (q1^(n^2) e^{2ny} <= 1 for u <= K/2),
    so cd = cn/dn and the scaled sd, nd stay finite where cn and dn underflow (u beyond ~700
    at huge forcing). At p = 0 (q1 = 0) the series reduce to sn = tanh, cn = dn = sech.
    """
    n = np.arange(_NTERMS, dtype=np.float64)
    y = (0.5 * np.pi * a / kp)[..., None]
    lq = log_q1[..., None]
    alt = (-1.0) ** n
    e_up = np.exp((n * n + n) * lq + 2 * n * y)
    e_dn = np.exp((n * n + n) * lq - (2 * n + 2) * y)
    s_terms = alt * 0.5 * (e_up - e_dn)
    # n = 0 term (1 - e^{-2y}) / 2 without cancellation for small y
    s_terms[..., 0] = -0.5 * np.expm1(-2.0 * y[..., 0])
    big_s = np.sum(s_terms, axis=-1)
    big_c = np.sum(0.5 * (e_up + e_dn), axis=-1)
    c0 = np.sum(np.exp((n * n + n) * lq), axis=-1)
    n1 = n[1:]
    g = np.exp(n1 * n1 * lq + 2 * n1 * y) + np.exp(n1 * n1 * lq - 2 * n1 * y)
    t3 = 1.0 + np.sum(g, axis=-1)
    t4 = 1.0 + np.sum(alt[1:] * g, axis=-1)
    w = np.exp(n1 * n1 * lq)
    t3_0 = 1.0 + 2.0 * np.sum(w, axis=-1)
    t4_0 = 1.0 + 2.0 * np.sum(alt[1:] * w, axis=-1)
    y0 = y[..., 0]
    e_y = np.exp(-y0)
    sn = t3_0 / t4_0 * big_s / big_c
    cn = c0 / t4_0 * t4 * e_y / big_c
    dn = c0 / t3_0 * t3 * e_y / big_c
    cd = t3_0 / t4_0 * t4 / t3
    sd_scaled = t3_0 * t3_0 / (t4_0 * c0) * big_s / t3
    nd_scaled = t3_0 / c0 * big_c / t3
    return sn, cn, dn, cd, sd_scaled, nd_scaled, y0


def _u_minus_eps_half(
    w: FloatArray, m: FloatArray, sn: FloatArray, cn: FloatArray, dn: FloatArray
) -> FloatArray:
    """u - Eps(u) on 0 <= u <= K/2 without cancellation: (m/3) sn^3 R_D(cn^2, dn^2, 1).

    (DLMF 19.25.9 with F(am u) = u.) Where cn^2 underflows, p is tiny enough for the m = 1
    form u - tanh(u).
    """
    cn2 = cn * cn
    under = cn2 < 1e-300
    rd = special.elliprd(np.where(under, 1.0, cn2), np.where(under, 1.0, dn * dn), 1.0)
    return np.where(under, w - np.tanh(w), m / 3.0 * sn**3 * rd)


def jacobi(
    u: FloatArray,
    m: FloatArray,
    p: FloatArray,
    k: FloatArray,
    kp: FloatArray,
    k_minus_e: FloatArray,
    tau: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Jacobi sn, cn, dn and u - Eps(u) for real u and parameter m = 1 - p.

    Parameters
    ----------
    u : ndarray
        Argument (any real value).
    m, p : ndarray
        Parameter and complementary parameter, p = 1 - m, both accurate.
    k, kp : ndarray
        K(m) and K(p).
    k_minus_e : ndarray
        K(m) - E(m) (see :func:`complete_k_minus_e`).
    tau : ndarray, optional
        ln p, needed where p underflows (default ``log(p)``).

    Returns
    -------
    sn, cn, dn, u_minus_eps : ndarray
        Eps is Jacobi's epsilon function, Eps(u) = E(am(u) | m), continuous in u.

    Notes
    -----
    Reduction: u = 2 j K + r with |r| <= K (sn, cn change sign with j, dn and Eps - u are
    2K-periodic up to 2 j (K - E)); then |r| > K/2 is mapped to w = K - |r| with
    sn(K - w) = cd(w), cn(K - w) = sqrt(p) sd(w), dn(K - w) = sqrt(p) nd(w) and
    Eps(K - w) = E - Eps(w) + m sn(w) cd(w) (DLMF 22.4, 22.16.27), which keeps relative
    accuracy near the zeros of cn and dn. sqrt(p) sd and sqrt(p) nd are formed as
    exp(tau/2 + y) times scaled values, so nothing overflows or underflows early.
    """
    if tau is None:
        with np.errstate(divide="ignore"):
            tau = np.log(p)
    u, m, p, k, kp, k_minus_e, tau = np.broadcast_arrays(u, m, p, k, kp, k_minus_e, tau)
    j = np.rint(u / (2.0 * k))
    r = u - 2.0 * j * k
    parity = np.where(np.fmod(np.abs(j), 2.0) == 1.0, -1.0, 1.0)
    sgn = np.where(r < 0.0, -1.0, 1.0)
    a = np.minimum(np.abs(r), k)
    hi = a > 0.5 * k
    w = np.where(hi, k - a, a)

    small_m = m <= 0.5
    parts = [np.empty_like(w) for _ in range(7)]
    for mask, func, scale in (
        (small_m, _theta_small_m, lambda i: -np.pi * kp[i] / k[i]),
        (~small_m, _theta_large_m, lambda i: -np.pi * k[i] / kp[i]),
    ):
        if np.any(mask):
            other = k[mask] if func is _theta_small_m else kp[mask]
            for dst, val in zip(parts, func(w[mask], other, scale(mask))):
                dst[mask] = val
    sn_w, cn_w, dn_w, cd_w, sd_s, nd_s, y = parts

    w_me = _u_minus_eps_half(w, m, sn_w, cn_w, dn_w)
    factor = np.exp(0.5 * tau + y)  # sqrt(p) e^{y}
    sn_a = np.where(hi, cd_w, sn_w)
    cn_a = np.where(hi, factor * sd_s, cn_w)
    dn_a = np.where(hi, factor * nd_s, dn_w)
    a_me = np.where(hi, k_minus_e - w_me - m * sn_w * cd_w, w_me)

    sn = parity * sgn * sn_a
    cn = parity * cn_a
    u_me = 2.0 * j * k_minus_e + sgn * a_me
    return sn, cn, dn_a, u_me
