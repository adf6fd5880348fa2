"""A branch of solutions as an explicit curve in one parameter (theory.md §2).

Frozen copy of ``src/hairbed/_branch.py`` at commit 7300965 (the numpy core), kept as
the slow reference of the tests; see :mod:`naive`. Do not change the algorithms.

The energy xi = sin(theta1) is the natural unknown, but it cannot be carried in double precision
at either end of its range [sin theta0, 1): weak forcing needs d = xi - sin(theta0) to relative
accuracy, strong forcing needs p = (1 - xi)/2, which underflows. Both are exact functions of the
logit parameter t:

    d = (1 - sin theta0) expit(t),     2 p = (1 - sin theta0) expit(-t).

Everything on the branch (sign, n) is then explicit in t [1]_ (theory.md §§2 and 3):

    mu = (1 + xi)/2 = 1 - p,   sn0^2 = (1 + sin theta0)/(2 mu),  cn0^2 = d/(2 mu),
    dn0^2 = (1 - sin theta0)/2,
    v0 = F(arcsin sn0 | mu),   kv = K(mu) - v0                      (Legendre form of eq. (33))
    omega_eps = (2n + 1) K - sign v0 = 2nK + kv (sign +1) or (2n + 2)K - kv (sign -1)
    theta'(0) = sign omega_eps sqrt(2 d),   h1 = theta'(0)/omega_eps^2    (eq. (29))
    omega^2 = omega_eps^2 (1 - eps h1)                                   (eq. (34))

v0 and kv are both Carlson integrals with non-cancelling arguments (theory.md §6):
v0 = sn0 R_F(cn0^2, cn0^2 + p sn0^2, 1) and kv = cn0 R_F(p sn0^2, p, cn0^2 + p sn0^2) (the
complementary amplitude), and the smaller one is computed, the other by difference.

References
----------
.. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
   Deformation of a Boundary Hair".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import special

from .elliptic import complete_k, complete_k_minus_e, jacobi

__all__ = [
    "BranchPoint",
    "branch_point",
    "omega2_and_slope",
    "shape_terms",
    "tip_deflection",
]

FloatArray = NDArray[np.float64]


def _half_angle_terms(theta0: FloatArray) -> tuple[FloatArray, FloatArray]:
    """1 - sin(theta0) and 1 + sin(theta0) without cancellation near +-pi/2."""
    quarter = 0.25 * np.pi
    one_minus_s = 2.0 * np.sin(quarter - 0.5 * theta0) ** 2
    one_plus_s = 2.0 * np.cos(quarter - 0.5 * theta0) ** 2
    return one_minus_s, one_plus_s


@dataclass(frozen=True)
class BranchPoint:
    """Everything on a branch at parameter t (arrays of one broadcast shape)."""

    t: FloatArray
    eps: FloatArray
    theta0: FloatArray
    sign: int
    n: int
    d: FloatArray  # xi - sin(theta0)
    p: FloatArray  # (1 - xi)/2
    tau: FloatArray  # ln p
    mu: FloatArray  # (1 + xi)/2, the parameter of the Jacobi functions
    sn0: FloatArray
    cn0: FloatArray
    dn0: FloatArray
    k: FloatArray  # K(mu)
    v0: FloatArray
    kv: FloatArray  # K(mu) - v0
    omega_eps: FloatArray
    root2d: FloatArray  # sqrt(2 d)
    omega2: FloatArray

    @property
    def xi(self) -> FloatArray:
        s = np.sin(self.theta0)
        return np.where(self.d < self.p, s + self.d, 1.0 - 2.0 * self.p)

    @property
    def tip_height(self) -> FloatArray:
        """h1 = theta'(0)/omega_eps^2 (eq. (29)); 1 at omega_eps = 0 is cos(theta0)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            h1 = self.sign * self.root2d / self.omega_eps
        return np.where(self.omega_eps > 0.0, h1, np.cos(self.theta0))

    @property
    def base_curvature(self) -> FloatArray:
        return self.sign * self.omega_eps * self.root2d

    @property
    def tip_angle(self) -> FloatArray:
        """theta(1): arcsin(xi) at an upper turning point, -pi - arcsin(xi) at a lower one."""
        xi = self.xi
        upper = np.where(
            xi > 0.5,
            0.5 * np.pi - 2.0 * np.arcsin(np.sqrt(self.p)),
            np.where(xi < -0.5, 2.0 * np.arcsin(np.sqrt(self.mu)) - 0.5 * np.pi, np.arcsin(xi)),
        )
        if self.sign * (-1) ** self.n > 0:
            return upper
        return -np.pi - upper

    @property
    def energy(self) -> FloatArray:
        return self.xi * self.omega_eps**2


def branch_point(
    t: FloatArray, eps: FloatArray, theta0: FloatArray, sign: int, n: int
) -> BranchPoint:
    """Evaluate the branch (sign, n) at parameter t (see module docstring)."""
    t, eps, theta0 = np.broadcast_arrays(
        np.asarray(t, dtype=np.float64),
        np.asarray(eps, dtype=np.float64),
        np.asarray(theta0, dtype=np.float64),
    )
    one_minus_s, one_plus_s = _half_angle_terms(theta0)
    q = special.expit(t)
    qc = special.expit(-t)
    d = one_minus_s * q
    p = 0.5 * one_minus_s * qc
    tau = np.log(0.5 * one_minus_s) + special.log_expit(-t)
    mu = 0.5 * (one_plus_s + d)
    two_mu = one_plus_s + d
    sn0_2 = one_plus_s / two_mu
    cn0_2 = d / two_mu
    sn0 = np.sqrt(sn0_2)
    cn0 = np.sqrt(cn0_2)
    dn0 = np.sqrt(0.5 * one_minus_s)
    k = complete_k(p, tau)
    z = cn0_2 + p * sn0_2
    # the smaller of v0 and K - v0 directly (tan^2 phi0 < 1/sqrt(p) <=> v0 < K/2)
    direct = sn0_2 * np.sqrt(p) < cn0_2
    # one Carlson integral per element: v0 = sn0 R_F(cn0^2, z, 1) or kv = cn0 R_F(p sn0^2, p, z)
    with np.errstate(invalid="ignore", divide="ignore"):
        rf = np.where(direct, sn0, cn0) * special.elliprf(
            np.where(direct, cn0_2, p * sn0_2), np.where(direct, z, p), np.where(direct, 1.0, z)
        )
    v0 = np.where(direct, rf, k - rf)
    kv = np.where(direct, k - rf, rf)
    kv = np.where(d == 0.0, 0.0, kv)
    if sign > 0:
        omega_eps = 2 * n * k + kv
    else:
        omega_eps = (2 * n + 2) * k - kv
    root2d = np.sqrt(2.0 * d)
    omega2 = omega_eps * (omega_eps - sign * eps * root2d)
    return BranchPoint(
        t=t,
        eps=eps,
        theta0=theta0,
        sign=sign,
        n=n,
        d=d,
        p=p,
        tau=tau,
        mu=mu,
        sn0=sn0,
        cn0=cn0,
        dn0=dn0,
        k=k,
        v0=v0,
        kv=kv,
        omega_eps=omega_eps,
        root2d=root2d,
        omega2=omega2,
    )


def omega2_and_slope(bp: BranchPoint) -> tuple[FloatArray, FloatArray]:
    """omega^2 on the branch and its derivative d(omega^2)/dt.

    Uses dK/dm = (E - pK)/(2 m p) and, for v0 = F(phi0 | mu), dF/dphi = 1/dn0 and
    dF/dm = E(phi0)/(2 m p) - F/(2 m) - sn0 cn0/(2 p dn0) (DLMF 19.4), with every 1/p and
    1/cn0 absorbed into d(xi)/dt = 2 p expit(t) = d expit(-t).
    """
    q = special.expit(bp.t)
    qc = special.expit(-bp.t)
    m = bp.mu
    p = bp.p
    k = bp.k
    # E only enters the Newton slope: scipy's ellipe(m) is accurate enough here
    e = special.ellipe(m)
    # E(phi0 | mu) = v0 - (mu/3) sn0^3 R_D(cn0^2, dn0^2, 1)
    e0 = bp.v0 - m / 3.0 * bp.sn0**3 * special.elliprd(bp.cn0**2, bp.dn0**2, 1.0)
    # dxi/dt = 2 p q; the factors below are (d/dxi) * (dxi/dt)
    dk_dt = q * (e - p * k) / (2.0 * m)
    # dphi0/dxi = -sn0/(4 mu cn0); times dxi/dt = d qc with cn0 = sqrt(d/(2 mu))
    dphi_dt = -bp.sn0 * qc * np.sqrt(bp.d) * np.sqrt(2.0 * m) / (4.0 * m)
    # dF/dm * dmu/dt with dmu/dt = p q
    df_dm_dt = q * (e0 - p * bp.v0) / (2.0 * m) - q * bp.sn0 * bp.cn0 / (2.0 * bp.dn0)
    dv0_dt = dphi_dt / bp.dn0 + df_dm_dt
    domega_eps_dt = (2 * bp.n + 1) * dk_dt - bp.sign * dv0_dt
    droot2d_dt = 0.5 * bp.root2d * qc
    s = bp.sign
    slope = (2.0 * bp.omega_eps - s * bp.eps * bp.root2d) * domega_eps_dt - (
        s * bp.eps * bp.omega_eps * droot2d_dt
    )
    return bp.omega2, slope


def tip_deflection(bp: BranchPoint) -> FloatArray:
    """x(1) (eq. (32) integrated); algebraic on the physical branch, else via the shape.

    On the physical branch v runs from v0 to K and, with w = K - v, everything at the tip is
    algebraic in sn0, cn0, dn0: sn(kv) = cn0/dn0, cn(kv) = sqrt(p) sn0/dn0,
    dn(kv) = sqrt(p)/dn0, so x1 = -1 + 2 mu (s0 S + (S^3/3) R_D(cn(kv)^2, dn(kv)^2, 1)) / kv
    with S = sn(kv) (kv - Eps(kv) by DLMF 19.25.9).
    """
    if bp.sign != 1 or bp.n != 0:
        return shape_terms(bp, np.ones_like(bp.t))[1]
    m = bp.mu
    big_s = bp.cn0 / bp.dn0
    a2 = bp.p / (bp.dn0 * bp.dn0)
    under = a2 < 1e-300  # separatrix: kv - Eps(kv) -> kv - 1
    with np.errstate(invalid="ignore", divide="ignore"):
        rd = special.elliprd(np.where(under, 1.0, a2 * bp.sn0**2), np.where(under, 1.0, a2), 1.0)
        kv_me = np.where(under, bp.kv - 1.0, m / 3.0 * big_s**3 * rd)
        x1 = -1.0 + 2.0 * (m * bp.sn0 * big_s + kv_me) / bp.kv
    return np.where(bp.kv > 0.0, x1, np.sin(bp.theta0))


def shape_terms(bp: BranchPoint, sigma: FloatArray):
    """theta, x, z at arc length sigma along the shape of a branch point (eqs. (32), (30)).

    With delta = v - v0 = sign omega_eps sigma the addition theorems (DLMF 22.8, 22.16.27) give
    sn, cn, dn of v and Eps(v) - Eps(v0) = Eps(delta) - m sn0 sn(delta) sn(v) relative to the
    base, so that short arcs and weak forcing keep their accuracy.
    """
    m = bp.mu
    p = bp.p
    k = bp.k
    kp = np.where(p < 0.5, special.ellipk(p), special.ellipkm1(m))
    kme = complete_k_minus_e(m, p, k)
    delta = bp.sign * bp.omega_eps * sigma
    sd, cd, dd, dme = jacobi(delta, m, p, k, kp, kme, bp.tau)
    sn0, cn0, dn0 = bp.sn0, bp.cn0, bp.dn0
    den = dn0**2 + m * sn0**2 * cd**2
    sn_v = (sn0 * cd * dd + cn0 * sd * dn0) / den
    dn_v = (dn0 * dd - m * sn0 * cn0 * sd * cd) / den
    one_minus_cd = np.where(cd > 0.0, sd * sd / (1.0 + cd), 1.0 - cd)
    cn_diff = (cn0 * one_minus_cd - m * cn0 * sn0**2 * sd**2 + sn0 * dn0 * sd * dd) / den
    theta = 2.0 * np.arctan2(np.sqrt(m) * sn_v, dn_v) - 0.5 * np.pi
    with np.errstate(divide="ignore", invalid="ignore"):
        z = 2.0 * np.sqrt(m) * cn_diff / (bp.sign * bp.omega_eps)
        x = (-delta + 2.0 * dme + 2.0 * m * sn0 * sd * sn_v) / (bp.sign * bp.omega_eps)
    rest = bp.omega_eps == 0.0
    if np.any(rest):
        theta0 = np.broadcast_to(bp.theta0, theta.shape)
        sig = np.broadcast_to(sigma, theta.shape)
        theta = np.where(rest, theta0, theta)
        z = np.where(rest, sig * np.cos(theta0), z)
        x = np.where(rest, sig * np.sin(theta0), x)
    return theta, x, z
