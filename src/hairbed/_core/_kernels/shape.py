"""The shape theta(sigma), x(sigma), z(sigma) of a state in closed form (eqs. (32), (30) of [1]_).

With v(sigma) = v0 + sign omega_eps sigma [1]_,

    theta = 2 arcsin(sqrt(mu) sn(v | mu)) - pi/2,
    z = 2 sqrt(mu) (cn(v0) - cn(v))/(sign omega_eps),
    x = ((v - v0) - 2 (Eps(v) - Eps(v0)))/(sign omega_eps),

Eps(v) = E(am v | mu) Jacobi's epsilon function (the x formula follows from
sin theta = 2 mu sn^2 v - 1 and int sn^2 = (v - Eps)/mu).

* Physical branch: v runs from v0 = K - kv to K, and the displacements from the straight hair
  (theta - theta0, x - sigma sin theta0, z - sigma cos theta0) are computed as such, never as
  differences of theta, x, z (``_physical``): each keeps its relative accuracy however short
  the arc and however close theta0 is to +-pi/2. Within SHORT_ARC of the base (kv sigma <=
  1/4) they are Taylor series of cn(v0 + r)/cn(v0) (``_cn_series``, ``_short_arc``); beyond,
  closed forms whose cancellation is bounded by ~1/SHORT_ARC^2: theta - theta0 from the
  arcsine addition, x - sigma s from the integral of cn0^2 - cn^2 (R_D forms), z - sigma c
  from cn0 - cn v, with v itself for a hair leaning into the flow near its base (v <= K/2)
  and otherwise w = K - v = kv (1 - sigma) and the reflection sn(K - w) = cd w,
  cn(K - w) = sqrt(p) sd w, dn(K - w) = sqrt(p) nd w (DLMF 22.4), which keeps cn v and dn v
  (of order sqrt(p)) accurate near theta = pi/2 and through the underflow of p at strong
  forcing. At huge forcing (ln p < -1380) mu = 1 to every digit and the m = 1 forms
  (tanh, sech) serve (``_huge``). At weak forcing (omega_eps^2 <= WEAK_MAX) the displacements
  are the regular perturbation series of ``weak``.
* Other branches: the addition theorems (DLMF 22.8, 22.16.27) with delta = v - v0, relative to
  the base, as in the paper's variables.

References
----------
.. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
   Deformation of a Boundary Hair", arXiv:2203.04169 (2022).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from .._jit import kernel
from .branch import base_angle, evaluate, tip_displacement
from .elliptic import complete_k_m, k_minus_e, rd
from .jacobi_elliptic import jacobi_prepared, jacobi_setup, sncndn_prepared
from .weak import WEAK_MAX, weak_shape

__all__ = ["ShapeSetup", "shape_point", "shape_setup", "shape_setup_from", "shape_xz"]

#: Everything the shape needs at one state (``shape_setup``), computed once per state.
ShapeSetup = namedtuple(
    "ShapeSetup",
    "mu p tau k kp kme sn0 cn0 dn0 kv oe v0 v0_me s c theta0 oms one_minus_x1 jc "
    "d root2d s_v0 pq_kv poly_theta poly_z poly_x",
)

_HALF_PI = 0.5 * math.pi
#: Arcs from the base up to this length in v (v - v0 = kv sigma) take the Taylor series.
SHORT_ARC = 0.25
#: Terms of the Taylor series of cn(v0 + r)/cn(v0): its radius is at least K(p) >= pi/2, so
#: at r <= SHORT_ARC the terms fall at least as fast as 0.16^k (0.16^24 < 1e-19).
SERIES_TERMS = 24
#: ln p below which mu = 1 - p is 1 to every digit along the hair (p < 1e-599).
_TAU_HUGE = -1380.0


@kernel
def shape_setup(t, eps, theta0, sign, n):
    """Everything the shape needs at one state, computed once per state.

    Returns a :data:`ShapeSetup`; its one_minus_x1 is 1 - x(1) on the physical branch (else
    0), jc the constants of ``jacobi.jacobi_setup``.
    """
    return shape_setup_from(evaluate(t, eps, theta0, sign, n, False), theta0, sign, n)


@kernel
def _cn_series(out, s, d, u1):
    """Taylor coefficients in r of u = cn(v0 + r)/cn(v0) (row 0) and of 1 - u^2 (row 1).

    cn'' = xi cn - 2 mu cn^3 (xi = mu - p), so with d = xi - sin(theta0) = 2 mu cn0^2,
    u'' = s u + d u (1 - u^2), u(0) = 1, u'(0) = u1 = -sn0 dn0/cn0: the products of series
    give u_(k+2) from u_0 ... u_(k+1), with nothing that cancels at theta0 = 0 or near +-pi/2
    (u_2 = s/2 exactly).
    """
    num = out.shape[1]
    u = out[0]
    a = out[1]
    u[0] = 1.0
    u[1] = u1
    a[0] = 0.0
    for k in range(num):
        if k > 0:
            acc = 0.0
            for i in range(k + 1):
                acc += u[i] * u[k - i]
            a[k] = -acc
        if k + 2 < num:
            b = 0.0
            for i in range(k + 1):
                b += u[i] * a[k - i]
            u[k + 2] = (s * u[k] + d * b) / ((k + 1.0) * (k + 2.0))


@kernel
def _row_tuple(a, i):
    """Row i of a (3, SERIES_TERMS) array as a tuple: the setup holds no array, so passing it
    to the per-point kernels costs no reference counting."""
    return (
        a[i, 0], a[i, 1], a[i, 2], a[i, 3], a[i, 4], a[i, 5], a[i, 6], a[i, 7],
        a[i, 8], a[i, 9], a[i, 10], a[i, 11], a[i, 12], a[i, 13], a[i, 14], a[i, 15],
        a[i, 16], a[i, 17], a[i, 18], a[i, 19], a[i, 20], a[i, 21], a[i, 22], a[i, 23],
    )  # fmt: skip


@kernel
def shape_setup_from(ev, theta0, sign, n):
    """:func:`shape_setup` from the branch point ``ev`` (``branch.evaluate``) already at hand."""
    p = ev[4]
    tau = ev[5]
    mu = ev[6]
    sn0 = ev[7]
    cn0 = ev[8]
    dn0 = ev[9]
    k = ev[10]
    kv = ev[12]
    oe = ev[13]
    kp = complete_k_m(p)
    kme = k_minus_e(mu, p, k)
    v0 = ev[11]
    s_v0 = sn0 * sn0 * sn0 / 3.0 * rd(cn0 * cn0, dn0 * dn0, 1.0)  # int_0^v0 sn^2
    v0_me = mu * s_v0  # v0 - E(phi0 | mu)
    s, c, oms, ops = base_angle(theta0)
    one_minus_x1 = 0.0
    pq_kv = 0.0
    series = np.zeros((3, SERIES_TERMS))
    if sign > 0 and n == 0 and kv > 0.0:
        one_minus_x1 = tip_displacement(p, mu, sn0, cn0, dn0, kv, s, oms)[2]
        # p int_0^kv sd^2 = int_v0^K cn^2, with sn(kv) = cn0/dn0, cn(kv)^2 = a2 sn0^2 and
        # dn(kv)^2 = a2, a2 = p/dn0^2; R_D(a2 sn0^2, 1, a2) -> 3/(a2 (1 + sn0)) as a2 -> 0
        big_s = cn0 / dn0
        a2 = p / (dn0 * dn0)
        if a2 > 1e-280 and p > 1e-290:
            pq_kv = p / 3.0 * big_s * big_s * big_s * rd(a2 * sn0 * sn0, 1.0, a2)
        else:
            pq_kv = big_s * big_s * big_s * dn0 * dn0 / (1.0 + sn0)
        if oe * oe > WEAK_MAX and cn0 > 0.0:  # (the weak series serves below WEAK_MAX)
            _cn_series(series, s, ev[3], -sn0 * dn0 / cn0)
            # Horner-ready: theta - theta0 ~ sum u_k r^(k+1)/(k+1), z - sigma c ~ sum_(k>=2)
            # u_k r^k, x - sigma s ~ sum a_k r^(k+1)/(k+1) (``_short_arc``)
            for j in range(SERIES_TERMS - 1, -1, -1):
                series[2, j] = series[1, j] / (j + 1.0)
                series[1, j] = series[0, j] if j >= 2 else 0.0
                series[0, j] = series[0, j] / (j + 1.0)
    jc = jacobi_setup(mu, p, tau, k, kp)  # the theta-series constants, once per state
    return ShapeSetup(
        mu,
        p,
        tau,
        k,
        kp,
        kme,
        sn0,
        cn0,
        dn0,
        kv,
        oe,
        v0,
        v0_me,
        s,
        c,
        theta0,
        oms,
        one_minus_x1,
        jc,
        ev[3],
        ev[15],
        s_v0,
        pq_kv,
        _row_tuple(series, 0),
        _row_tuple(series, 1),
        _row_tuple(series, 2),
    )


@kernel
def _short_arc(sigma, setup, angle):
    """The physical branch within SHORT_ARC of the base, from the Taylor series of cn.

    With r = kv sigma' and u = cn(v0 + r)/cn0 (``_cn_series``), theta' = 2 sqrt(mu) kv cn,
    cos(theta) = 2 sqrt(mu) sn dn and sin(theta) - sin(theta0) = 2 mu (cn0^2 - cn^2) give

        theta - theta0 = sqrt(2 d) int_0^r u,   z - sigma c = -(sqrt(2 d)/kv) sum_(k>=2) u_k r^k,
        x - sigma s = (d/kv) int_0^r (1 - u^2),

    each a sum whose leading term dominates: the displacements keep their relative accuracy
    however short the arc.
    """
    kv = setup.kv
    c_theta, c_z, c_x = setup.poly_theta, setup.poly_z, setup.poly_x
    r = kv * sigma
    h_theta = 0.0
    h_z = 0.0
    h_x = 0.0
    for j in range(SERIES_TERMS - 1, -1, -1):
        if angle:
            h_theta = h_theta * r + c_theta[j]
        h_z = h_z * r + c_z[j]
        h_x = h_x * r + c_x[j]
    dth = setup.root2d * r * h_theta
    dz = -setup.root2d / kv * h_z
    dx = setup.d / kv * (r * h_x)
    return setup.theta0 + dth, sigma * setup.s + dx, sigma * setup.c + dz, dth, dx, dz


@kernel
def _huge(sigma, setup, angle):
    """The physical branch beyond SHORT_ARC at ln p < _TAU_HUGE, where mu = 1 in doubles.

    sn = tanh, cn = dn = sech and Eps = tanh: with v = v0 + r, r = kv sigma, t0 = tanh v0,

        theta - theta0 = 4 atan(sinh(r/2)/cosh(v0 + r/2)),
        cn0 - cn v = cn0 (1 - sech r + t0 tanh r)/(1 + t0 tanh r),
        int_v0^v (cn0^2 - cn^2) = cn0^2 ((r - tanh r) + r t0 tanh r)/(1 + t0 tanh r),

    all terms positive, in exponentials of -r that neither overflow nor cancel.
    """
    kv, sn0, cn0, dn0, v0 = setup.kv, setup.sn0, setup.cn0, setup.dn0, setup.v0
    r = kv * sigma
    em = -math.expm1(-r)  # 1 - e^-r
    e2 = math.exp(-2.0 * r)
    th = -math.expm1(-2.0 * r) / (1.0 + e2)  # tanh r
    den = 1.0 + sn0 * th
    dth = 0.0
    if angle:
        dth = 4.0 * math.atan(math.exp(-v0) * em / (1.0 + math.exp(-2.0 * v0 - r)))
    cn_diff = cn0 * (em * em / (1.0 + e2) + sn0 * th) / den
    rem = cn0 * cn0 * ((r - th) + r * sn0 * th) / den
    z = 2.0 * cn_diff / kv
    dz = 2.0 * (cn_diff - r * sn0 * dn0) / kv
    dx = 2.0 * rem / kv
    return setup.theta0 + dth, sigma * setup.s + dx, z, dth, dx, dz


@kernel
def _physical(sigma, setup, angle):
    """theta, x, z and their displacements on the physical branch, v from v0 to K.

    Beyond SHORT_ARC, with v = v0 + kv sigma, cn0 - cn v and the displacements

        theta - theta0 = 2 atan2(sqrt(mu) E, dn v dn0 + mu sn v sn0),
            E = sn v dn0 - sn0 dn v = (cn0^2 - cn^2 v)/(sn v dn0 + sn0 dn v),
        z - sigma c = 2 sqrt(mu) ((cn0 - cn v) - kv sigma sn0 dn0)/kv,
        x - sigma s = (2 mu/kv) int_v0^v (cn0^2 - cn^2)

    lose at most a factor ~1/SHORT_ARC^2 to cancellation. The integral is
    int_v0^v (sn^2 - sn0^2) = S(v) - S(v0) - r sn0^2, S(u) = int_0^u sn^2 = (sn^3/3) R_D(cn^2,
    dn^2, 1), for a hair leaning into the flow near its base (v <= K/2), else, with w = K - v =
    kv (1 - sigma) and the reflection sn v = cd w, cn v = sqrt(p) sd w, dn v = sqrt(p) nd w,
    r cn0^2 - int_v0^v cn^2 with int_v0^v cn^2 = p (Q(kv) - Q(w)), Q(a) = int_0^a sd^2 =
    (sn^3/3) R_D(cn^2, 1, dn^2) at a.
    """
    if setup.kv * sigma <= SHORT_ARC:
        return _short_arc(sigma, setup, angle)
    if setup.tau < _TAU_HUGE:
        return _huge(sigma, setup, angle)
    mu, p, tau, k, jc = setup.mu, setup.p, setup.tau, setup.k, setup.jc
    sn0, cn0, dn0, kv, v0 = setup.sn0, setup.cn0, setup.dn0, setup.kv, setup.v0
    r = kv * sigma
    rm = math.sqrt(mu)
    if setup.theta0 < 0.0 and v0 + r <= 0.5 * k:
        # leaning into the flow, near the base: v itself
        sn_v, cn_v, dn_v, _ = sncndn_prepared(v0 + r, mu, tau, k, jc)
        theta = 2.0 * math.atan2(rm * sn_v, dn_v) - _HALF_PI if angle else 0.0
        s_v = sn_v * sn_v * sn_v / 3.0 * rd(cn_v * cn_v, dn_v * dn_v, 1.0)
        rem = (s_v - setup.s_v0) - r * sn0 * sn0
    else:
        # w = K - v: the reflection, where cn v and dn v are of order sqrt(p)
        w = kv * (1.0 - sigma)
        sn_w, cn_w, dn_w, _ = sncndn_prepared(w, mu, tau, k, jc)
        sqp = math.exp(0.5 * tau) if p < 1e-290 else math.sqrt(p)  # p may be subnormal
        theta = _HALF_PI - 2.0 * math.atan2(sqp, rm * cn_w) if angle else 0.0
        sn_v = cn_w / dn_w
        cn_v = sqp * sn_w / dn_w
        dn_v = sqp / dn_w
        s3 = sn_w * sn_w * sn_w
        if dn_w * dn_w > 1e-280 and p > 1e-290:
            pq_w = p / 3.0 * s3 * rd(cn_w * cn_w, 1.0, dn_w * dn_w)
        else:  # R_D(cn^2, 1, dn^2) -> 3/(dn (dn + cn)) as cn, dn -> 0
            pq_w = s3 * (sqp / dn_w) * (sqp / (dn_w + cn_w))
        rem = r * cn0 * cn0 - (setup.pq_kv - pq_w)
    cn_diff = cn0 - cn_v
    dth = 0.0
    if angle:
        e = cn_diff * (cn0 + cn_v) / (sn_v * dn0 + sn0 * dn_v)
        dth = 2.0 * math.atan2(rm * e, dn_v * dn0 + mu * sn_v * sn0)
    z = 2.0 * rm * cn_diff / kv
    dz = 2.0 * rm * (cn_diff - r * sn0 * dn0) / kv
    dx = 2.0 * mu * rem / kv
    return theta, sigma * setup.s + dx, z, dth, dx, dz


@kernel
def shape_point(sigma, sign, n, setup):
    """(theta, x, z, dtheta, dx, dz) at arc length sigma; d* are the displacements from the
    straight hair at rest (theta0, sigma sin theta0, sigma cos theta0)."""
    return _shape(sigma, sign, n, setup, True)


@kernel
def shape_xz(sigma, sign, n, setup):
    """(x, z) at arc length sigma: :func:`shape_point` without the angles (profiles)."""
    v = _shape(sigma, sign, n, setup, False)
    return v[1], v[2]


@kernel
def _shape(sigma, sign, n, setup, angle):
    """:func:`shape_point`; theta and theta - theta0 are 0 unless ``angle`` (physical branch
    beyond weak forcing, where they cost an arctangent each)."""
    mu, tau, k, kme, jc = setup.mu, setup.tau, setup.k, setup.kme, setup.jc
    sn0, cn0, dn0, oe = setup.sn0, setup.cn0, setup.dn0, setup.oe
    s, c, theta0 = setup.s, setup.c, setup.theta0
    if oe == 0.0 or sigma == 0.0:  # the hair at rest, or its clamped base
        return theta0, sigma * s, sigma * c, 0.0, 0.0, 0.0
    if sign > 0 and n == 0:
        if oe * oe <= WEAK_MAX:
            dth, dx, dz = weak_shape(sigma, oe * oe, s, c)
            return theta0 + dth, sigma * s + dx, sigma * c + dz, dth, dx, dz
        return _physical(sigma, setup, angle)
    # the other branches: the addition theorems (DLMF 22.8, 22.16.27), relative to the base
    delta = sign * oe * sigma
    sd, cd, dd, dme = jacobi_prepared(delta, mu, tau, k, kme, jc)
    m = mu
    den = dn0 * dn0 + m * sn0 * sn0 * cd * cd
    sn_v = (sn0 * cd * dd + cn0 * sd * dn0) / den
    dn_v = (dn0 * dd - m * sn0 * cn0 * sd * cd) / den
    if cd > 0.0:
        one_minus_cd = sd * sd / (1.0 + cd)
    else:
        one_minus_cd = 1.0 - cd
    cn_diff = (cn0 * one_minus_cd - m * cn0 * sn0 * sn0 * sd * sd + sn0 * dn0 * sd * dd) / den
    theta = 2.0 * math.atan2(math.sqrt(m) * sn_v, dn_v) - _HALF_PI
    so = sign * oe
    z = 2.0 * math.sqrt(m) * cn_diff / so
    x = (-delta + 2.0 * dme + 2.0 * m * sn0 * sd * sn_v) / so
    return theta, x, z, theta - theta0, x - sigma * s, z - sigma * c
