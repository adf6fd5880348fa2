"""One point of a branch of solutions, as an explicit function of the branch parameter t.

The energy xi = sin(theta1) is the natural unknown of the paper's reduction [1]_ (eqs.
(33), (34)), but it cannot be carried in double precision at either end of its
range [sin theta0, 1): weak forcing needs d = xi - sin(theta0) to relative accuracy, strong
forcing needs p = (1 - xi)/2, which underflows. Both are exact functions of the logit t:

    d = (1 - sin theta0) expit(t),     2 p = (1 - sin theta0) expit(-t).

With mu = (1 + xi)/2 = 1 - p the parameter of the Jacobi functions and the amplitude
phi0 = arcsin(sn0) of the base,

    sn0^2 = (1 + sin theta0)/(2 mu),  cn0^2 = d/(2 mu),  dn0^2 = 1 - mu sn0^2 = (1 - sin theta0)/2,
    v0 = F(phi0 | mu) = sn0 R_F(cn0^2, dn0^2, 1),  kv = K(mu) - v0 = cn0 R_F(p sn0^2, p, dn0^2)

(DLMF 19.25.5 and the complementary amplitude, sn(kv) = cn0/dn0), and on the branch
(sign, n) (sign of theta'(0), n interior turning points; the paper's index is n for sign +1
and -(n + 1) for sign -1)

    omega_eps = 2 n K + kv (sign +1)  or  (2 n + 2) K - kv (sign -1),
    h1 = sign sqrt(2 d)/omega_eps (eq. (29)),   omega^2 = omega_eps^2 (1 - eps h1).

The smaller of v0 and kv is computed directly and the other by difference. Every quantity that
can under- or overflow (d, p, cn0, omega_eps^2) is formed from logarithms: ln omega^2 is exact
down to t = -1000, far below the smallest double omega^2, and h1 on the physical branch is
sqrt(2 (1 + xi))/R_F(p sn0^2, p, dn0^2), which never involves d at all. 1 - sin(theta0) and
1 + sin(theta0) are formed from pi/2 -+ theta0 in double-double, so that theta0 within an ulp
of +-pi/2 keeps its meaning.

The slope d ln(omega^2)/dt (Newton's derivative) uses dK/dm = (E - p K)/(2 m p) and
dF/dphi = 1/dn, dF/dm = (E(phi) - p F)/(2 m p) - sn cn/(2 p dn) (DLMF 19.4), every 1/p and
1/cn0 absorbed into dxi/dt = 2 p expit(t) = d expit(-t).

References
----------
.. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
   Deformation of a Boundary Hair", arXiv:2203.04169 (2022).
"""

from __future__ import annotations

import math

from .._jit import kernel
from .elliptic import complete_e_log, complete_k, rd, rf, rf_rd

__all__ = [
    "LN_OMEGA2_NONE",
    "base_angle",
    "base_terms",
    "evaluate",
    "evaluate_at",
    "log_expit",
    "tip_displacement",
]

#: pi/2 in double-double: PI_2_HI + PI_2_LO is pi/2 to 1e-33.
PI_2_HI = 1.5707963267948966
PI_2_LO = 6.123233995736766e-17
#: ln omega^2 of a point where omega^2 <= 0 (no state there: outside every bracket).
LN_OMEGA2_NONE = -1.0e300


@kernel
def log_expit(t):
    """ln(1/(1 + e^-t)) without overflow or cancellation."""
    if t >= 0.0:
        return -math.log1p(math.exp(-t))
    return t - math.log1p(math.exp(t))


@kernel
def base_angle(theta0):
    """sin, cos, 1 - sin and 1 + sin of theta0, accurate up to the ends +-pi/2.

    1 - sin(theta0) = 2 sin^2((pi/2 - theta0)/2) with pi/2 - theta0 in double-double (and
    likewise 1 + sin from theta0 + pi/2), so that no rounding of pi/2 enters.
    """
    s = math.sin(theta0)
    if theta0 > 0.5:
        up = (PI_2_HI - theta0) + PI_2_LO  # pi/2 - theta0, no rounding of pi/2
        a = math.sin(0.5 * up)
        oms = 2.0 * a * a
        ops = 1.0 + s
        c = math.sin(up)
    elif theta0 < -0.5:
        dn = (PI_2_HI + theta0) + PI_2_LO  # pi/2 + theta0
        b = math.sin(0.5 * dn)
        oms = 1.0 - s
        ops = 2.0 * b * b
        c = math.sin(dn)
    else:
        oms = 1.0 - s
        ops = 1.0 + s
        c = math.cos(theta0)
    return s, c, oms, ops


@kernel
def base_terms(theta0):
    """What the branch needs of theta0 alone, computed once per element (not per Newton step):
    (theta0, sin, cos, 1 - sin, 1 + sin, ln((1 - sin)/2), dn0 = sqrt((1 - sin)/2),
    sqrt(2 (1 - sin)))."""
    s, c, oms, ops = base_angle(theta0)
    return theta0, s, c, oms, ops, math.log(0.5 * oms), math.sqrt(0.5 * oms), math.sqrt(2.0 * oms)


@kernel
def evaluate(t, eps, theta0, sign, n, want_slope):
    """The branch (sign, n) at parameter t: :func:`evaluate_at` with ``base_terms(theta0)``."""
    return evaluate_at(t, eps, base_terms(theta0), sign, n, want_slope)


@kernel
def evaluate_at(t, eps, base, sign, n, want_slope):
    """The branch (sign, n) at parameter t, given ``base = base_terms(theta0)``.

    Returns the tuple (ln_omega2, dln_omega2_dt, xi, d, p, tau, mu, sn0, cn0, dn0, k, v0, kv,
    omega_eps, h1, root2d, rf_comp, dln_omega_eps_dt) where the two derivatives are 0 unless
    ``want_slope``; rf_comp is R_F(p sn0^2, p, dn0^2) where kv was formed from it (else 0);
    ln_omega2 is LN_OMEGA2_NONE where omega^2 <= 0. t = -inf is the undeformed hair (d = 0).
    """
    theta0, s, c, oms, ops, ln_half_oms, dn0, r2oms = base
    # expit(+-t) and their logarithms from one exp and one log1p
    if t >= 0.0:
        ex = math.exp(-t)
        l1 = math.log1p(ex)
        q = 1.0 / (1.0 + ex)
        qc = ex * q
        lq = -l1
        lqc = -t - l1
    else:
        ex = math.exp(t)
        l1 = math.log1p(ex)
        qc = 1.0 / (1.0 + ex)
        q = ex * qc
        lqc = -l1
        lq = t - l1
    d = oms * q
    p = 0.5 * oms * qc
    tau = ln_half_oms + lqc
    two_mu = ops + d
    mu = 0.5 * two_mu
    sn0_2 = ops / two_mu
    sn0 = math.sqrt(sn0_2)
    # sqrt(expit(+-t)) without the underflow of expit itself
    sq = math.sqrt(q) if q > 1e-300 else math.exp(0.5 * lq)
    cn0 = math.sqrt(oms / two_mu) * sq
    cn0_2 = cn0 * cn0
    dn0_2 = 0.5 * oms
    sqrt_p = dn0 * (math.sqrt(qc) if qc > 1e-300 else math.exp(0.5 * lqc))
    root2d = r2oms * sq
    k = complete_k(p, tau)
    rf_comp = 0.0
    rd0 = 0.0
    if sn0_2 * sqrt_p < cn0_2:  # v0 < K/2: v0 directly
        if want_slope:
            rf0, rd0 = rf_rd(cn0_2, dn0_2, 1.0)
        else:
            rf0 = rf(cn0_2, dn0_2, 1.0)
        v0 = sn0 * rf0
        kv = k - v0
    else:  # kv <= K/2: the complementary amplitude
        rf_comp = rf(p * sn0_2, p, dn0_2)
        kv = cn0 * rf_comp
        v0 = k - kv
        if want_slope:
            rd0 = rd(cn0_2, dn0_2, 1.0)
    if sign > 0:
        oe = 2.0 * n * k + kv
    else:
        oe = (2.0 * n + 2.0) * k - kv
    tiny = oe <= 1e-150  # omega_eps^2 would underflow: ln omega_eps from logarithms
    if sign > 0 and n == 0 and rf_comp > 0.0:
        h1 = math.sqrt(2.0 * two_mu) / rf_comp  # sqrt(2 d)/kv with d cancelled
    elif oe > 0.0:
        h1 = sign * root2d / oe
    else:
        h1 = c
    if d == 0.0 and lq == -math.inf:  # the end of the branch, xi = sin(theta0)
        h1 = sign * c
    if h1 > 1.0:  # int_0^1 cos(theta) <= 1: only rounding can exceed it
        h1 = 1.0
    one_minus = 1.0 - eps * h1
    if oe == 0.0 or one_minus <= 0.0:
        ln_w2 = LN_OMEGA2_NONE
    elif not tiny:
        ln_w2 = math.log(oe * oe * one_minus)
    else:  # physical branch at t < -690: kv = cn0 R_F, exact down to T_MIN
        ln_oe = 0.5 * (math.log(oms / two_mu) + lq) + math.log(rf_comp)
        ln_w2 = 2.0 * ln_oe + math.log1p(-eps * h1)
    if d < p:
        xi = s + d
    else:
        xi = 1.0 - 2.0 * p
    slope = 0.0
    g = 0.0
    if want_slope and oe > 0.0:
        m = mu
        e = complete_e_log(p, tau)
        e0 = v0 - m / 3.0 * sn0 * sn0_2 * rd0  # E(phi0 | mu), DLMF 19.25.9
        dk_dt = q * (e - p * k) / (2.0 * m)
        dphi_dt = -0.5 * sn0 * qc * cn0
        df_dm_dt = q * (e0 - p * v0) / (2.0 * m) - q * sn0 * cn0 / (2.0 * dn0)
        dv0_dt = dphi_dt / dn0 + df_dm_dt
        doe_dt = (2.0 * n + 1.0) * dk_dt - sign * dv0_dt
        g = doe_dt / oe
        dh1_dt = h1 * (0.5 * qc - g)
        slope = 2.0 * g - eps * dh1_dt / one_minus
    return (
        ln_w2,
        slope,
        xi,
        d,
        p,
        tau,
        mu,
        sn0,
        cn0,
        dn0,
        k,
        v0,
        kv,
        oe,
        h1,
        root2d,
        rf_comp,
        g,
    )


@kernel
def _one_minus_x1(p, mu, sn0, dn0, kv, a2, s3):
    """1 - x1 = (2 p/kv) (kv + (mu/3) S^3 R_D(cn^2, 1, dn^2)) at w = kv (``tip_displacement``)."""
    if a2 > 1e-280:
        return 2.0 * p / kv * (kv + mu / 3.0 * s3 * rd(a2 * sn0 * sn0, 1.0, a2))
    # R_D(z sn0^2, 1, z) -> 3/(z (1 + sn0)) as z -> 0
    return 2.0 * p + 2.0 * mu * s3 * dn0 * dn0 / (kv * (1.0 + sn0))


@kernel
def tip_displacement(p, mu, sn0, cn0, dn0, kv, s, oms):
    """The tip deflection x1, x1 - sin(theta0) and 1 - x1 on the physical branch.

    With w = K - v running from kv (base) to 0 (tip), sin(theta) = 1 - 2 p nd^2(w), so
    1 - x1 = (2 p/kv) int_0^kv nd^2 dw = (2 p/kv) (kv + (mu/3) S^3 R_D(cn^2, 1, dn^2)) at
    w = kv, with S = sn(kv) = cn0/dn0, cn(kv)^2 = p sn0^2/dn0^2, dn(kv)^2 = p/dn0^2
    (int dphi/Delta^3 = F + m (sin^3/3) R_D(cos^2, 1, Delta^2)): every term positive, so
    1 - x1 keeps its relative accuracy up to the separatrix and x1 never exceeds 1. The
    displacement is (1 - sin theta0) - (1 - x1) where x1 is near 1, else

        x1 - sin(theta0) = (2 mu/kv) (F(kv)),  F(a) = (a - Eps a)/mu + sn(a) cd(a) - a cd^2(a),

    with a - Eps(a) = (mu/3) S^3 R_D(cn^2, dn^2, 1) (DLMF 19.25.9).
    """
    big_s = cn0 / dn0
    a2 = p / (dn0 * dn0)
    s3 = big_s * big_s * big_s
    # one R_D, not two: 1 - x1 where the tip is near flat (xi > 0.5 is a cheap proxy), the
    # displacement otherwise; the other only if the proxy chose wrong
    one_minus_x1 = -1.0
    if mu > 0.75:
        one_minus_x1 = _one_minus_x1(p, mu, sn0, dn0, kv, a2, s3)
        if one_minus_x1 < 0.5:
            return 1.0 - one_minus_x1, oms - one_minus_x1, one_minus_x1
    if a2 < 1e-300:  # separatrix: kv - Eps(kv) -> kv - 1
        kv_me = kv - 1.0
    else:
        kv_me = mu / 3.0 * s3 * rd(a2 * sn0 * sn0, a2, 1.0)
    disp = 2.0 * (kv_me + mu * sn0 * (big_s - kv * sn0)) / kv
    x1 = s + disp
    if one_minus_x1 < 0.0:
        one_minus_x1 = _one_minus_x1(p, mu, sn0, dn0, kv, a2, s3) if x1 > 0.5 else 1.0 - x1
        if one_minus_x1 < 0.5:
            return 1.0 - one_minus_x1, oms - one_minus_x1, one_minus_x1
    return x1, disp, one_minus_x1
