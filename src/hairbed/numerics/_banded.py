"""The one finite-difference operator of the hair problem: banded, plus a rank-one coupling.

Used by the paper's finite-difference baseline (:func:`hairbed.numerics.finite_difference`)
and by the relaxation dynamics of :mod:`hairbed.stability`: both discretise

    F[theta] = theta'' + omega_eps^2[theta] cos(theta),    omega_eps^2 = omega^2 / (1 - eps h1),
    theta(0) = theta0,    theta'(1) = 0,    h1 = int_0^1 cos(theta) dsigma,

on ``num`` equal segments (theory.md §8): unknowns theta_1..theta_N at sigma_i = i/N, central
differences, the free end through a ghost node theta_{N+1} = theta_{N-1}, h1 by the trapezoidal
rule; second order throughout. Every row depends on every unknown through h1, so the Jacobian is
tridiagonal plus a rank-one term, and a Newton step costs O(N): a banded solve and the
Sherman-Morrison formula.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import linalg

__all__ = ["HairOperator"]

FloatArray = NDArray[np.float64]


class HairOperator:
    """The discrete operator F on ``num`` segments at fixed (omega2, eps, theta0).

    Two scalings of the same equations: :meth:`residual` has its rows multiplied by h^2 (the
    last by h^2 / 2), so that the banded part is symmetric and O(1), as the paper's scheme;
    :meth:`rhs` is F itself at the nodes (the right-hand side theta_t of the relaxation
    dynamics). Their Newton steps are the same.

    Parameters
    ----------
    omega2, eps, theta0 : float
        Forcing [-], confinement [-] and base angle [rad] (validated by the caller).
    num : int
        Number of segments N, at least 2 (checked by the caller).
    """

    def __init__(self, omega2: float, eps: float, theta0: float, num: int) -> None:
        self.omega2, self.eps, self.theta0, self.num = omega2, eps, theta0, num
        self.h = 1.0 / num
        # Trapezoid weights of the unknowns in units of h (the last node carries half weight),
        # the same halving as the ghost-point row of the residual.
        self.w = np.ones(num)
        self.w[-1] = 0.5
        # Banded storage of the constant tridiagonal part, (1, 1) bands.
        ab = np.empty((3, num))
        ab[0, :] = 1.0
        ab[1, :] = -2.0
        ab[1, -1] = -1.0
        ab[2, :] = 1.0
        self.ab = ab

    def tip_height(self, th: FloatArray) -> float:
        """h1, the trapezoid sum of cos(theta) [-]."""
        return self.h * (0.5 * np.cos(self.theta0) + float(self.w @ np.cos(th)))

    def omega_eps2(self, h1: float) -> float:
        """omega_eps^2 = omega^2 / (1 - eps h1) [-]."""
        return self.omega2 / (1.0 - self.eps * h1)

    def residual(self, th: FloatArray) -> FloatArray:
        """Rows i < N: theta_{i-1} - 2 theta_i + theta_{i+1} + h^2 W cos(theta_i); row N:
        theta_{N-1} - theta_N + (h^2 / 2) W cos(theta_N), with W = omega_eps^2."""
        h2W = self.h**2 * self.omega_eps2(self.tip_height(th))
        r = np.empty_like(th)
        r[0] = self.theta0 - 2.0 * th[0]
        r[1:] = th[:-1] - 2.0 * th[1:]
        r[:-1] += th[1:]
        r[-1] += th[-1]  # the ghost-point row: theta_{N-1} - theta_N
        r += h2W * self.w * np.cos(th)
        return r

    def rhs(self, th: FloatArray) -> FloatArray:
        """F at the unknown nodes: the residual's rows divided by h^2 (the last by h^2 / 2)."""
        return self.residual(th) / (self.h**2 * self.w)

    def _parts(self, th: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Bands of the residual's Jacobian and its rank-one term: J = T + u v^T."""
        h1 = self.tip_height(th)
        W = self.omega_eps2(h1)
        c, s = np.cos(th), np.sin(th)
        ab = self.ab.copy()
        ab[1] -= self.h**2 * W * self.w * s
        # dr_i/dW = h^2 w_i cos(theta_i);  dW/dtheta_j = dW/dh1 * dh1/dtheta_j.
        u = self.h**2 * self.w * c
        v = (self.eps * W / (1.0 - self.eps * h1)) * (-self.h * self.w * s)
        return ab, u, v

    def newton_step(self, th: FloatArray, r: FloatArray) -> FloatArray:
        """Solve J dx = -r in O(N) (J the residual's Jacobian at ``th``, r its residual):
        banded solve plus Sherman-Morrison for the rank-one term."""
        ab, u, v = self._parts(th)
        yz = linalg.solve_banded((1, 1), ab, np.column_stack([-r, u]), check_finite=False)
        y, z = yz[:, 0], yz[:, 1]
        return y - z * (float(v @ y) / (1.0 + float(v @ z)))

    def rhs_jacobian(self, th: FloatArray) -> FloatArray:
        """Dense Jacobian of :meth:`rhs` (not symmetric: the load is not conservative)."""
        ab, u, v = self._parts(th)
        jac = np.diag(ab[1]) + np.diag(ab[0, 1:], 1) + np.diag(ab[2, :-1], -1)
        jac += np.outer(u, v)
        return jac / (self.h**2 * self.w)[:, None]
