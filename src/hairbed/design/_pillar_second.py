"""Second derivatives of a pillar state, and the derivative of its slowest mode (issue 32).

A converged pillar state u = (theta at the N + 1 mapped nodes, h1) is a root of the
collocation system R(u; p) = 0 of ``_kernels.spectral`` (drive ``DRIVE_DRAG``, theory.md
§12), p = (Lambda, theta0, gamma). The first derivatives solve J u_k = -R_k (J = dR/du, the
implicit function theorem; :mod:`hairbed._core.pillar_sensitivity`); differentiating that
system once more along p_l,

    J u_kl = -R''[(u_k, e_k), (u_l, e_l)],

where R'' is the second derivative of the residual in (u, p) along the two total
directions: it carries R_uu[u_k, u_l], R_up and R_pp at once. R'' is computed exactly by
running the residual on second-order jets (:class:`_Jet`: a value, its first derivatives in
two groups of directions a and b and the mixed second derivatives ab; forward mode, nothing
differenced). The same jets give the total derivative dJ/dp_k of the Jacobian (b the unit
directions of u) and of the damping operator B(theta, gamma) of the pillar's overdamped
dynamics (theory.md §14), from which the derivative of an eigenvalue of the pencil
(lambda B - J) v = 0 is

    d lambda = w^H (dJ - lambda dB) v / (w^H B v)

with w, v its left and right eigenvectors, after the reduction of the algebraic rows
(:func:`hairbed.dynamics._linear._reduce`) differentiated too.

The first-order system (J and R_p) is the compiled kernels' (``_jacobian_drag``,
``_unit_load``); the second derivatives run the kernel's residual (``_residual_drag``)
written over jets, whose value, Jacobian and partials agree with the kernels'
(``tests/test_design_gradients.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from .._core.loaded import _chebyshev_values, _matrices
from .._core.pillar import PillarState

__all__ = ["mode_gradient", "slope_gradient"]

FloatArray = NDArray[np.float64]


class _Jet:
    """A value with first derivatives in directions a (ka of them) and b (kb), and the
    mixed second derivatives d^2/da db: ``v`` (S), ``a`` (ka, *S), ``b`` (kb, *S), ``ab``
    (ka, kb, *S). Operands of one product have values of the same number of axes."""

    __slots__ = ("a", "ab", "b", "v")

    def __init__(self, v: Any, a: Any, b: Any, ab: Any) -> None:
        self.v, self.a, self.b, self.ab = v, a, b, ab

    @classmethod
    def const(cls, v: Any, ka: int, kb: int) -> _Jet:
        v = np.asarray(v, dtype=np.float64)
        return cls(
            v, np.zeros((ka, *v.shape)), np.zeros((kb, *v.shape)), np.zeros((ka, kb, *v.shape))
        )

    @classmethod
    def seed(cls, v: Any, a: Any, b: Any) -> _Jet:
        """An independent input: value v, its directions a (ka, *S), b (kb, *S)."""
        v = np.asarray(v, dtype=np.float64)
        a = np.asarray(a, dtype=np.float64)
        b = np.asarray(b, dtype=np.float64)
        return cls(v, a, b, np.zeros((a.shape[0], b.shape[0], *v.shape)))

    def __add__(self, o: Any) -> _Jet:
        if isinstance(o, _Jet):
            return _Jet(self.v + o.v, self.a + o.a, self.b + o.b, self.ab + o.ab)
        return _Jet(self.v + o, self.a, self.b, self.ab)

    __radd__ = __add__

    def __neg__(self) -> _Jet:
        return _Jet(-self.v, -self.a, -self.b, -self.ab)

    def __sub__(self, o: Any) -> _Jet:
        return self + (-o)

    def __rsub__(self, o: Any) -> _Jet:
        return (-self) + o

    def __mul__(self, o: Any) -> _Jet:
        if not isinstance(o, _Jet):
            return _Jet(self.v * o, self.a * o, self.b * o, self.ab * o)
        if self.ab.size == 0:  # one group of directions empty: first order only
            ab = np.zeros(np.broadcast_shapes(self.ab.shape, o.ab.shape))
        else:
            ab = (
                self.ab * o.v
                + self.a[:, None] * o.b[None]
                + self.b[None] * o.a[:, None]
                + self.v * o.ab
            )
        return _Jet(self.v * o.v, self.a * o.v + self.v * o.a, self.b * o.v + self.v * o.b, ab)

    __rmul__ = __mul__

    def _map(self, f0: Any, f1: Any, f2: Any) -> _Jet:
        """f(self) given f, f' and f'' at the value."""
        ab = f1 * self.ab + f2 * (self.a[:, None] * self.b[None])
        return _Jet(f0, f1 * self.a, f1 * self.b, ab)

    def cos(self) -> _Jet:
        c, s = np.cos(self.v), np.sin(self.v)
        return self._map(c, -s, -c)

    def sin(self) -> _Jet:
        c, s = np.cos(self.v), np.sin(self.v)
        return self._map(s, c, -s)

    def apply(self, mat: FloatArray) -> _Jet:
        """mat @ x along the value's last axis (a linear map: each part mapped)."""
        m = mat.T
        return _Jet(self.v @ m, self.a @ m, self.b @ m, self.ab @ m)

    def left(self, mat: FloatArray) -> _Jet:
        """mat @ X of a matrix-valued jet (the value's first axis)."""
        return _Jet(mat @ self.v, mat @ self.a, mat @ self.b, mat @ self.ab)

    def __getitem__(self, idx: Any) -> _Jet:
        """Index the value's axes (a tuple for several)."""
        t = idx if isinstance(idx, tuple) else (idx,)
        e = (slice(None),)
        return _Jet(self.v[t], self.a[e + t], self.b[e + t], self.ab[e + e + t])

    @staticmethod
    def concat(parts: list[_Jet]) -> _Jet:
        """The values of 1-D jets end to end."""
        return _Jet(
            np.concatenate([p.v for p in parts]),
            np.concatenate([p.a for p in parts], axis=-1),
            np.concatenate([p.b for p in parts], axis=-1),
            np.concatenate([p.ab for p in parts], axis=-1),
        )


def _profile(prof: FloatArray, z: _Jet) -> _Jet:
    """U(z) = sum_k prof[k] T_k(2 z - 1) on a jet z (the kernel's ``profile_value``)."""
    t = 2.0 * z - 1.0
    val = z * 0.0 + float(prof[0])
    if prof.size > 1:
        t_prev, t_cur = z * 0.0 + 1.0, t
        val = val + float(prof[1]) * t
        for k in range(2, prof.size):
            t_prev, t_cur = t_cur, 2.0 * t * t_cur - t_prev
            val = val + float(prof[k]) * t_cur
    return val


@dataclass(frozen=True)
class _Level:
    """The mapped operators of one degree N (the kernel's ``_map`` and ``_operators``)."""

    num: int
    dd: FloatArray
    ii: FloatArray


def _level(num: int, a: float) -> _Level:
    from ..dynamics._operators import _mapped

    _, _, dd, ii, _ = _mapped(num, a)
    return _Level(num, dd, ii)


def _residual(
    lev: _Level, u: _Jet, lam: _Jet, theta0: _Jet, gamma: _Jet, prof: FloatArray
) -> _Jet:
    """The pillar's collocation residual (the kernel's ``_residual_drag``, no tip load) on
    jets: u (N + 2,), the scalars lam, theta0, gamma of shape (1,)."""
    num = lev.num
    n1 = num + 1
    th = u[0:n1]
    c, s = th.cos(), th.sin()
    z = c.apply(lev.ii)
    uu = _profile(prof, z)
    fx = lam * uu * (c * c + gamma * s * s)
    fz = -(lam * uu * (1.0 - gamma) * s * c)
    tx = fx.apply(lev.ii[num : num + 1])
    tz = fz.apply(lev.ii[num : num + 1])
    big_fx = tx - fx.apply(lev.ii)  # F(s_i) = int_{s_i}^1 f
    big_fz = tz - fz.apply(lev.ii)
    rel = th - th[num : num + 1]
    curv = rel.apply(lev.dd)
    inner = curv + big_fx * c - big_fz * s
    return _Jet.concat(
        [
            th[0:1] - theta0,
            inner[1:num],
            curv[num : num + 1],
            u[n1 : n1 + 1] - z[num : num + 1],
        ]
    )


def _inputs(
    u0: FloatArray, p0: tuple[float, float, float], da: FloatArray, db: FloatArray
) -> tuple[_Jet, _Jet, _Jet, _Jet]:
    """Jets of u and (Lambda, theta0, gamma) along directions da (ka, m + 3) and db (kb,
    m + 3) in (u, p)."""
    m = u0.size
    u = _Jet.seed(u0, da[:, :m], db[:, :m])
    ps = [
        _Jet.seed(np.array([p0[i]]), da[:, m + i : m + i + 1], db[:, m + i : m + i + 1])
        for i in range(3)
    ]
    return u, ps[0], ps[1], ps[2]


@dataclass(frozen=True)
class _First:
    """A state's first-order system: u, p, J, du/dp (m, 3), the profile."""

    lev: _Level
    u: FloatArray
    p: tuple[float, float, float]
    jac: FloatArray
    du: FloatArray
    prof: FloatArray


def _first(state: PillarState, prof: FloatArray, num: int | None = None) -> _First:
    """J and du/d(Lambda, theta0, gamma) at a scalar state, at its own degree or, with
    ``num``, at degree ``num`` (its Chebyshev series padded, the same map): there du/dp is
    the state's own derivative carried by the interpolation (what the value computed at
    that degree sees)."""
    own = int(state.num)
    a = float(state._map)
    coefs = np.asarray(state._coefs, dtype=np.float64)[0].reshape(-1)[: own + 1]
    theta = _chebyshev_values(own) @ coefs
    lev = _level(own, a)
    p = (float(state.forcing), float(state.theta0), float(state.gamma))
    first = _solve_first(lev, theta, p, prof)
    if num is None or num == own:
        return first
    # the series padded to degree num: theta_num = V_num pad(C_own theta_own), linear in theta
    cmat = _matrices(own)[4]
    interp = _chebyshev_values(num)[:, : own + 1] @ cmat
    lev2 = _level(num, a)
    th2 = interp @ theta
    u2 = np.append(th2, lev2.ii[num] @ np.cos(th2))
    jac2 = _partials(lev2, u2, p, prof)[0]
    dth = interp @ first.du[: own + 1]
    dh = (lev2.ii[num] * -np.sin(th2)) @ dth
    du2 = np.vstack([dth, dh[None, :]])
    return _First(lev2, u2, p, jac2, du2, prof)


def _partials(
    lev: _Level, u: FloatArray, p: tuple[float, float, float], prof: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """(J, R_p) at u: the compiled kernels' exact Jacobian (``_jacobian_drag``) and dR/dLambda
    (``_unit_load``: the drag is linear in Lambda); dR/dtheta0 = -e_0, and dR/dgamma through
    the drag's df/dgamma = Lambda U (sin^2, sin cos) in the interior rows. R_p (m, 3)."""
    from .._core.loaded import _kernels

    k = _kernels()
    num = lev.num
    n1 = num + 1
    m = n1 + 1
    lam, _, gam = p
    work = np.empty((12, m))
    pm = np.empty((2, n1, n1))
    jac = np.zeros((m, m))
    cs, sn, z, fx, fz = work[0], work[1], work[2], work[6], work[7]
    pr = np.ascontiguousarray(prof, dtype=np.float64)
    uc = np.ascontiguousarray(u, dtype=np.float64)
    k._drag_forces(uc, num, lev.ii, lam, gam, 0.0, pr, cs, sn, z, fx, fz)
    k._jacobian_drag(
        uc, num, lev.dd, lev.ii, lam, gam, 0.0, pr, cs, sn, z, fx, fz, work[8:12], pm, jac
    )
    r_p = np.zeros((m, 3))
    col = np.empty(m)
    k._unit_load(uc, num, lev.ii, gam, pr, cs, sn, z, work[8], work[9], col)
    r_p[:, 0] = col
    r_p[0, 1] = -1.0
    c, s = np.cos(uc[:n1]), np.sin(uc[:n1])
    uu = np.polynomial.chebyshev.chebval(2.0 * (lev.ii @ c) - 1.0, pr)
    gx, gz = lam * uu * s * s, lam * uu * s * c
    big_x = lev.ii[num] @ gx - lev.ii @ gx  # int_{s_i}^1 df/dgamma
    big_z = lev.ii[num] @ gz - lev.ii @ gz
    r_p[1:num, 2] = big_x[1:num] * c[1:num] - big_z[1:num] * s[1:num]
    return jac, r_p


def _solve_first(
    lev: _Level, theta: FloatArray, p: tuple[float, float, float], prof: FloatArray
) -> _First:
    u = np.append(theta, lev.ii[lev.num] @ np.cos(theta))
    jac, r_p = _partials(lev, u, p, prof)
    du = np.asarray(-np.linalg.solve(jac, r_p), dtype=np.float64)
    return _First(lev, u, p, jac, du, prof)


def _directions(first: _First) -> FloatArray:
    """The total directions (u_k, e_k) of Lambda, theta0, gamma: (3, m + 3)."""
    return np.hstack([first.du.T, np.eye(3)])


def slope_gradient(state: PillarState, prof: FloatArray) -> tuple[float, FloatArray]:
    """(dx1/dLambda, d(dx1/dLambda)/d(Lambda, theta0, gamma)) of a scalar converged pillar
    state solved with the profile ``prof`` (Chebyshev coefficients of U(z)) and no tip
    load: the second derivative of the discrete state, exact (the implicit function theorem
    differentiated once more, on jets)."""
    f = _first(state, prof)
    lev, num = f.lev, f.lev.num
    n1 = num + 1
    dirs = _directions(f)
    u, lam, th0, gam = _inputs(f.u, f.p, dirs, dirs[0:1])
    res = _residual(lev, u, lam, th0, gam, prof)
    d2u = -np.linalg.solve(f.jac, res.ab[:, 0, :].T)  # (m, 3): d u_Lambda/dp_k
    x1 = u[0:n1].sin().apply(lev.ii[num : num + 1])
    x1_u = lev.ii[num] * np.cos(f.u[:n1])
    slope = float(x1_u @ f.du[:n1, 0])
    grad = x1.ab[:, 0, 0] + x1_u @ d2u[:n1]
    return slope, np.asarray(grad, dtype=np.float64)


def _row(j: _Jet) -> _Jet:
    """A 1-D jet as a row (1, n)."""
    return _Jet(j.v[None, :], j.a[:, None, :], j.b[:, None, :], j.ab[:, :, None, :])


def _col(j: _Jet) -> _Jet:
    """A 1-D jet as a column (n, 1)."""
    return _Jet(j.v[:, None], j.a[:, :, None], j.b[:, :, None], j.ab[:, :, :, None])


def _damping(lev: _Level, theta: _Jet, ratio: _Jet) -> _Jet:
    """B(theta, gamma) of :func:`hairbed.dynamics._operators.velocity_operators` on jets
    (rows 0 .. N, columns 0 .. N), value (N + 1, N + 1)."""
    ii = lev.ii
    c, s = theta.cos(), theta.sin()
    one = 1.0 - ratio  # shape (1,)
    vx = _row(c) * ii
    vz = -(_row(s) * ii)
    gx = _col(1.0 - one * s * s) * vx - _col(one * s * c) * vz
    gz = -(_col(one * s * c) * vx) + _col(1.0 - one * c * c) * vz
    tail = ii[-1][None, :] - ii
    return _col(c) * gx.left(tail) - _col(s) * gz.left(tail)


def mode_gradient(
    state: PillarState, prof: FloatArray, num: int, mu: float = 0.0, chi: float = 1.0
) -> tuple[complex, NDArray[np.complex128]]:
    """(lambda_1, d lambda_1/d(Lambda, theta0, gamma, mu, chi)) of the slowest mode of a
    scalar pillar state's linear dynamics at degree ``num`` (as
    :meth:`hairbed.dynamics.LinearPillar.modes`: the state's series padded, the algebraic
    rows reduced; the mode of the smallest abs(lambda), of a conjugate pair the one with
    Im lambda > 0): the overdamped pencil (lambda B - J) v = 0 for ``mu`` = 0, else the
    first-order pencil (lambda E - A) v = 0, A = [[0, I], [J, -B]], E = [[I, 0], [0, mu M]]
    (inertia number mu, tangential mass ratio chi). Exact: the eigenvalue's derivative
    w^H (dA - lambda dE) v/(w^H E v) from its left and right eigenvectors, with the total
    derivatives of the reduced J, B and M (jets; the implicit function theorem for the
    state's du/dp)."""
    f = _first(state, prof, num)
    lev = f.lev
    n1 = num + 1
    m = n1 + 1
    dirs = _directions(f)
    unit = np.hstack([np.eye(m), np.zeros((m, 3))])
    u, lam, th0, gam = _inputs(f.u, f.p, dirs, unit)
    res = _residual(lev, u, lam, th0, gam, f.prof)
    jac = res.b.T  # (m, m): b_j the unit directions of u
    djac = np.transpose(res.ab, (0, 2, 1))  # (3, m, m): total d J/dp_k
    # B(theta, gamma) and M(theta, chi) along the state's directions and chi's (a fourth)
    four = np.vstack([dirs, np.zeros((1, m + 3))])
    th_j, _, _, gam_j = _inputs(f.u, f.p, four, np.zeros((0, m + 3)))
    chi_j = _Jet.seed(np.array([chi]), np.array([[0.0], [0.0], [0.0], [1.0]]), np.zeros((0, 1)))
    ops = []
    for jet in (_damping(lev, th_j[0:n1], gam_j), _damping(lev, th_j[0:n1], chi_j)):
        full = np.zeros((m, m))
        full[1:num, :n1] = jet.v[1:num]
        dfull = np.zeros((4, m, m))
        dfull[:, 1:num, :n1] = jet.a[:, 1:num]
        ops.append((full, dfull))
    (damp, ddamp), (mass, dmass) = ops
    alg = np.array([0, num, n1])
    dif = np.arange(1, num)
    jaa, jad = jac[np.ix_(alg, alg)], jac[np.ix_(alg, dif)]
    smat = -np.linalg.solve(jaa, jad)

    def red(x: FloatArray, s: FloatArray) -> FloatArray:
        return x[np.ix_(dif, dif)] + x[np.ix_(dif, alg)] @ s

    jr, br, mr = red(jac, smat), red(damp, smat), red(mass, smat)
    n = num - 1
    zero = np.zeros((n, n))
    # with inertia on sigma = c lambda, c = sqrt(mu) where mu > 1, as LinearPillar.modes: the
    # damping block B/c then shrinks instead of the mass block mu M growing (QZ keeps the
    # decay rate ~1/(2 mu); unscaled, mu = 1e30 had no finite eigenvalue)
    c = math.sqrt(mu) if mu > 1.0 else 1.0
    if mu == 0.0:
        a_mat, e_mat = jr, br
    else:
        a_mat = np.block([[zero, np.eye(n)], [jr, -br / c]])
        e_mat = np.block([[np.eye(n), zero], [zero, (mu / c**2) * mr]])
    lam_all, left, right = scipy.linalg.eig(a_mat, e_mat, left=True, right=True)
    fin = np.flatnonzero(np.isfinite(lam_all))
    if fin.size == 0:
        raise ArithmeticError(f"no finite mode of the pillar at the inertia number mu = {mu:.4g}")
    size = np.array([float(f"{x:.10g}") for x in np.abs(lam_all[fin])])
    i = fin[np.lexsort((-lam_all[fin].imag, size))][0]
    sigma1 = complex(lam_all[i])
    lam1 = sigma1 / c
    w, v = left[:, i], right[:, i]
    denom = np.conj(w) @ e_mat @ v

    def rate(da: FloatArray, de: FloatArray) -> complex:
        """d sigma of the (scaled) pencil's da, de: d lambda = d sigma/c."""
        return complex((np.conj(w) @ (da - sigma1 * de) @ v) / denom)

    def pencil(djr: FloatArray, dbr: FloatArray, dmr: FloatArray) -> tuple[Any, Any]:
        if mu == 0.0:
            return djr, dbr
        return (
            np.block([[zero, zero], [djr, -dbr / c]]),
            np.block([[zero, zero], [zero, dmr / c**2]]),
        )

    grad = np.zeros(5, dtype=np.complex128)
    for k in range(4):
        dj = djac[k] if k < 3 else np.zeros((m, m))
        ds = -np.linalg.solve(jaa, dj[np.ix_(alg, alg)] @ smat + dj[np.ix_(alg, dif)])
        djr = red(dj, smat) + jac[np.ix_(dif, alg)] @ ds
        dbr = red(ddamp[k], smat) + damp[np.ix_(dif, alg)] @ ds
        dmr = mu * (red(dmass[k], smat) + mass[np.ix_(dif, alg)] @ ds)
        if mu == 0.0 and k == 3:
            continue  # no inertia: chi does not enter
        idx = k if k < 3 else 4
        grad[idx] = rate(*pencil(djr, dbr, dmr)) / c
    if mu != 0.0 and c == 1.0:
        grad[3] = rate(np.zeros_like(a_mat), np.block([[zero, zero], [zero, mr]]))
    elif mu != 0.0:  # A's block -B/sqrt(mu) and lambda = sigma/sqrt(mu) both move with mu
        d_sigma = rate(np.block([[zero, zero], [zero, br / (2.0 * mu * c)]]), np.zeros_like(e_mat))
        grad[3] = d_sigma / c - sigma1 / (2.0 * mu * c)
    return lam1, grad
