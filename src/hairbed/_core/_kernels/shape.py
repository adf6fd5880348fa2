"""The shape theta(sigma), x(sigma), z(sigma) of a state in closed form (eqs. (32), (30) of [1]_).

With v(sigma) = v0 + sign omega_eps sigma [1]_,

    theta = 2 arcsin(sqrt(mu) sn(v | mu)) - pi/2,
    z = 2 sqrt(mu) (cn(v0) - cn(v))/(sign omega_eps),
    x = ((v - v0) - 2 (Eps(v) - Eps(v0)))/(sign omega_eps),

Eps(v) = E(am v | mu) Jacobi's epsilon function (the x formula follows from
sin theta = 2 mu sn^2 v - 1 and int sn^2 = (v - Eps)/mu).

* Physical branch: v runs from v0 = K - kv to K. Where v <= K/2, the formulas above as they
  stand for theta0 >= 0, and for theta0 < 0 the addition theorems relative to the base (as
  for the other branches, below; a hair lying against the flow starts almost flat); beyond,
  with
  w = K - v = kv (1 - sigma), the reflection sn(K - w) = cd w, cn(K - w) = sqrt(p) sd w,
  dn(K - w) = sqrt(p) nd w (DLMF 22.4) gives, without cancellation near theta = pi/2 and
  without the underflow of sqrt(p) at strong forcing,

      pi/2 - theta = 2 atan2(sqrt(p), sqrt(mu) cn w),   z = 2 sqrt(mu) (cn0 - sqrt(p) sd w)/kv,
      x = -sigma + 2 ((kv - Eps(kv)) - (w - Eps(w)) + mu (sn(kv) sn0 - sn w cd w))/kv,

  with sn(kv) = cn0/dn0 and cd(kv) = sn0. At huge forcing (ln p < -1380, where sqrt(p)
  underflows) the direct forms, accurate in absolute terms. At weak forcing
  (omega_eps^2 <= WEAK_MAX) the displacements from the straight hair are the regular
  perturbation series of ``weak``, accurate relative to themselves.
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

from .._jit import kernel
from .branch import base_angle, evaluate, tip_displacement
from .elliptic import complete_k_m, k_minus_e, rd
from .jacobi_elliptic import jacobi_prepared, jacobi_setup, sncndn_prepared
from .weak import WEAK_MAX, weak_shape

__all__ = ["ShapeSetup", "shape_point", "shape_setup", "shape_setup_from"]

#: Everything the shape needs at one state (``shape_setup``), computed once per state.
ShapeSetup = namedtuple(
    "ShapeSetup",
    "mu p tau k kp kme sn0 cn0 dn0 kv oe v0 v0_me s c theta0 oms one_minus_x1 jc",
)

_HALF_PI = 0.5 * math.pi


@kernel
def shape_setup(t, eps, theta0, sign, n):
    """Everything the shape needs at one state, computed once per state.

    Returns a :data:`ShapeSetup`; its one_minus_x1 is 1 - x(1) on the physical branch (else
    0), jc the constants of ``jacobi.jacobi_setup``.
    """
    return shape_setup_from(evaluate(t, eps, theta0, sign, n, False), theta0, sign, n)


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
    v0_me = mu / 3.0 * sn0 * sn0 * sn0 * rd(cn0 * cn0, dn0 * dn0, 1.0)  # v0 - E(phi0 | mu)
    s, c, oms, ops = base_angle(theta0)
    one_minus_x1 = 0.0
    if sign > 0 and n == 0 and kv > 0.0:
        one_minus_x1 = tip_displacement(p, mu, sn0, cn0, dn0, kv, s, oms)[2]
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
    )


@kernel
def shape_point(sigma, sign, n, setup):
    """(theta, x, z, dtheta, dx, dz) at arc length sigma; d* are the displacements from the
    straight hair at rest (theta0, sigma sin theta0, sigma cos theta0)."""
    mu, p, tau, k, kme, jc = setup.mu, setup.p, setup.tau, setup.k, setup.kme, setup.jc
    sn0, cn0, dn0, kv, oe = setup.sn0, setup.cn0, setup.dn0, setup.kv, setup.oe
    s, c, theta0, oms = setup.s, setup.c, setup.theta0, setup.oms
    v0, v0_me, one_minus_x1 = setup.v0, setup.v0_me, setup.one_minus_x1
    if oe == 0.0 or sigma == 0.0:  # the hair at rest, or its clamped base
        return theta0, sigma * s, sigma * c, 0.0, 0.0, 0.0
    if sign > 0 and n == 0:
        if oe * oe <= WEAK_MAX:
            dth, dx, dz = weak_shape(sigma, oe * oe, s, c)
            return theta0 + dth, sigma * s + dx, sigma * c + dz, dth, dx, dz
        v = v0 + kv * sigma
        rm = math.sqrt(mu)
        if tau < -1380.0:
            # huge forcing: sqrt(p) and dn near K underflow; the direct form is accurate in
            # absolute terms (theta = pi/2 to every digit away from the ends)
            sn_v, cn_v, dn_v, me_v = jacobi_prepared(v, mu, tau, k, kme, jc)
            theta = 2.0 * math.atan2(rm * sn_v, dn_v) - _HALF_PI
            z = 2.0 * rm * (cn0 - cn_v) / kv
            x = -sigma + 2.0 * (me_v - v0_me) / kv
            return theta, x, z, theta - theta0, x - sigma * s, z - sigma * c
        if kv * sigma <= 0.25:
            pass  # a short arc from the base: the addition theorems below, relative to it
        elif v > 0.5 * k or theta0 >= 0.0:
            # w = K - v: the reflection, where cn v and dn v are of order sqrt(p)
            w = kv * (1.0 - sigma)
            sn_w, cn_w, dn_w, _ = sncndn_prepared(w, mu, tau, k, jc)
            sqp = math.exp(0.5 * tau) if p < 1e-290 else math.sqrt(p)  # p may be subnormal
            theta = _HALF_PI - 2.0 * math.atan2(sqp, rm * cn_w)
            z = 2.0 * rm * (cn0 - sqp * sn_w / dn_w) / kv
            # 1 - sin(theta) = 2 p nd^2(w): int_sigma^1 (1 - sin theta) = J(w) with
            # J(a) = (2 p/kv) (a + (mu/3) sn^3 R_D(cn^2, 1, dn^2)), all terms positive
            s3 = sn_w * sn_w * sn_w
            if dn_w * dn_w > 1e-280:
                j_w = 2.0 * p / kv * (w + mu / 3.0 * s3 * rd(cn_w * cn_w, 1.0, dn_w * dn_w))
            else:  # R_D(cn^2, 1, dn^2) -> 3/(dn (dn + cn)) as cn, dn -> 0
                r = sqp / dn_w
                j_w = 2.0 * p * w / kv + 2.0 * mu * s3 / kv * r * (sqp / (dn_w + cn_w))
            part = one_minus_x1 - j_w  # int_0^sigma (1 - sin theta)
            x = sigma - part
            return theta, x, z, theta - theta0, sigma * oms - part, z - sigma * c
        # leaning into the flow, near the base: the addition theorems below, relative to it
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
