"""The pillar's collocation operators at a static state, for its dynamics (theory.md §14).

The static pillar (theory.md §12) is the collocation system R(u; Lambda, P) = 0 of
``_kernels.spectral`` (drive ``DRIVE_DRAG``): u = (theta at the N + 1 mapped Chebyshev nodes,
h1), rows 0 (theta_0 = theta0), 1 .. N - 1 (D2 theta_i + n_i . F(s_i) = 0, n = (cos, -sin)),
N (theta'(1) = 0) and N + 1 (h1 = z(1)). In time the internal force F(s) = P e_x +
int_s^1 (f - mu r_tt) ds' gains the drag of the pillar's own velocity r_t and its inertia, so
the interior rows read

    B(theta) theta_t + mu M(theta) theta_tt + (terms in theta_t^2) = R(theta; Lambda(t), P(t)),

    B theta_t = n . int_s^1 A(theta) r_t ds',   A = I - (1 - gamma) t t,
    M theta_tt = n . int_s^1 C(theta) (r_tt's part in theta_tt) ds',   C = I - (1 - chi) t t,

with r_t = int_0^s theta_t (cos, -sin) ds' (by the integration matrix), t = (sin, cos) the
tangent and chi the ratio of the tangential to the normal mass per unit length. The rows
0, N and N + 1 stay algebraic. This module builds, for one converged state, the static
Jacobian J (the static solver's own kernel ``_jacobian_drag``), B and M, the drives' columns
and the outputs' rows; :mod:`._linear` reduces them to the differential unknowns.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .._core.loaded import _kernels, _matrices, _nodal_values

__all__ = ["StateOperators", "state_operators", "velocity_operators"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class StateOperators:
    """The collocation operators of one converged pillar state (N + 2 unknowns).

    Attributes
    ----------
    num : int
        The Chebyshev degree N.
    theta : ndarray
        theta at the N + 1 mapped nodes [rad].
    s : ndarray
        The mapped nodes s_j in [0, 1] [L].
    dd, ii : ndarray
        The mapped operators of the static solver: rows 1 .. N - 1 of ``dd`` the second
        derivative, row N the first; ``ii`` the integration from the base.
    d0 : ndarray
        The first derivative's row at s = 0 (theta'(0) = d0 . theta).
    jac : ndarray
        The static Jacobian dR/du, (N + 2, N + 2).
    damping, mass : ndarray
        B and M, (N + 2, N + 2), zero in the algebraic rows and the h1 column.
    drive_forcing, drive_tip_load : ndarray
        dR/dLambda and dR/dP, (N + 2,).
    """

    num: int
    theta: FloatArray
    s: FloatArray
    dd: FloatArray
    ii: FloatArray
    d0: FloatArray
    jac: FloatArray
    damping: FloatArray
    mass: FloatArray
    drive_forcing: FloatArray
    drive_tip_load: FloatArray


def _mapped(
    num: int, a: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """(s, ds/dxi, dd, ii, d0) of the static solver's map with parameter a at degree N."""
    k = _kernels()
    x, d1, d2, im, _ = _matrices(num)
    sp = np.empty(num + 1)
    ss = np.empty(num + 1)
    k._map(float(a), num, x, sp, ss)
    dd = np.empty((num + 1, num + 1))
    ii = np.empty((num + 1, num + 1))
    k._operators(num, d1, d2, im, sp, float(a), dd, ii)
    return ss, sp, dd, ii, d1[0] / sp[0]


def velocity_operators(
    theta: FloatArray, ii: FloatArray, ratio: float
) -> tuple[FloatArray, FloatArray]:
    """The rows of n . int_s^1 G(theta) r_t ds' at every node in theta_t, with G = I -
    (1 - ratio) t t and r_t = I (theta_t (cos, -sin)): (N + 1, N + 1), and the matrix
    r_t -> (x, z) components, for B (ratio gamma) and M (ratio chi)."""
    c, s = np.cos(theta), np.sin(theta)
    one = 1.0 - ratio
    vx = ii * c[None, :]  # r_t,x = I diag(cos) theta_t
    vz = -ii * s[None, :]  # r_t,z = -I diag(sin) theta_t
    gx = (1.0 - one * s * s)[:, None] * vx - (one * s * c)[:, None] * vz
    gz = -(one * s * c)[:, None] * vx + (1.0 - one * c * c)[:, None] * vz
    tail = ii[-1][None, :] - ii  # int_{s_i}^1 g = (I g)(1) - (I g)(s_i)
    return c[:, None] * (tail @ gx) - s[:, None] * (tail @ gz), np.stack([vx, vz])


def state_operators(
    num: int,
    a: float,
    coefs: FloatArray,
    forcing: float,
    gamma: float,
    tip_load: float,
    prof: FloatArray,
    chi: float,
) -> StateOperators:
    """The operators of the converged state whose Chebyshev coefficients of theta are
    ``coefs`` (degree N = ``num``, map parameter ``a``), of a flow Lambda U(z) (``prof``:
    U's Chebyshev coefficients in 2 z - 1) with drag ratio gamma and tip load P."""
    k = _kernels()
    ss, _, dd, ii, d0 = _mapped(num, a)
    theta = _nodal_values(np.ascontiguousarray(coefs[None, : num + 1]), num)[0]
    n1 = num + 1
    u = np.empty(n1 + 1)
    u[:n1] = theta
    u[n1] = float(ii[num] @ np.cos(theta))
    work = np.empty((12, n1 + 1))
    cs, sn, z, fx, fz = work[0], work[1], work[2], work[6], work[7]
    pm = np.empty((2, n1, n1))
    jac = np.zeros((n1 + 1, n1 + 1))
    p = np.ascontiguousarray(np.reshape(prof, -1), dtype=np.float64)
    k._drag_forces(u, num, ii, forcing, gamma, tip_load, p, cs, sn, z, fx, fz)
    k._jacobian_drag(
        u, num, dd, ii, forcing, gamma, tip_load, p, cs, sn, z, fx, fz, work[8:12], pm, jac
    )
    col = np.empty(n1 + 1)
    k._unit_load(u, num, ii, gamma, p, cs, sn, z, work[8], work[9], col)
    damping = np.zeros((n1 + 1, n1 + 1))
    mass = np.zeros((n1 + 1, n1 + 1))
    b, _ = velocity_operators(theta, ii, gamma)
    m, _ = velocity_operators(theta, ii, chi)
    damping[1:num, :n1] = b[1:num]
    mass[1:num, :n1] = m[1:num]
    tip = np.zeros(n1 + 1)
    tip[1:num] = np.cos(theta[1:num])  # n . e_x
    return StateOperators(
        num=num,
        theta=theta,
        s=ss,
        dd=dd,
        ii=ii,
        d0=d0,
        jac=jac,
        damping=damping,
        mass=mass,
        drive_forcing=col.copy(),
        drive_tip_load=tip,
    )
