"""Carlson's R_F and R_D with their gradients, by forward differentiation of the duplication.

The partial derivatives of the symmetric integrals have closed forms (DLMF 19.18), e.g.

    dR_F/dx = -R_D(y, z, x)/6,    dR_D/dx = (R_D(y, z, x) - R_D(x, y, z)) / (2 (z - x)),

but the second is a difference that loses every digit as x -> z, which is where the weak
forcing of a hair puts it (theory.md §6: the arguments p sn0^2 and p of the short arc of a
barely bent hair). Here each function is evaluated by Carlson's duplication (DLMF 19.36.1;
B. C. Carlson, Numer. Algorithms 10 (1995) 13) with every quantity carried as a value and its
three partial derivatives (forward-mode automatic differentiation, :class:`hairbed._dual.Dual`):
the derivative of the algorithm is a sum of positive terms and of the small corrections of the
final series, so the gradient has the relative accuracy of the value, for any arguments.
Nothing is differenced.

The duplication runs until 4^-m max|A0 - x_i| < 2e-3 |A_m| (Carlson's test for a relative
error of about 1e-16 of the series) holds for every element: a loop over iterations, not over
elements (each step is a vectorised numpy operation), and further steps leave the values
exact, so the elements that converged earlier lose nothing.

Examples
--------
The gradient of R_F checks the identity dR_F/dx = -R_D(y, z, x)/6 (DLMF 19.18.1), and
Euler's relation for the homogeneous R_D (degree -3/2): x.grad R_D = -3/2 R_D.

>>> import numpy as np
>>> f, (fx, fy, fz) = rf_gradient(np.array([0.3]), np.array([1.2]), np.array([2.0]))
>>> d, (dx, dy, dz) = rd_gradient(np.array([1.2]), np.array([2.0]), np.array([0.3]))
>>> bool(abs(fx[0] + d[0] / 6) < 1e-15 * abs(fx[0]))
True
>>> d, g = rd_gradient(np.array([0.3]), np.array([1.2]), np.array([2.0]))
>>> bool(abs(0.3 * g[0][0] + 1.2 * g[1][0] + 2.0 * g[2][0] + 1.5 * d[0]) < 1e-14 * d[0])
True
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._dual import Dual

__all__ = ["rd_gradient", "rf_gradient"]

FloatArray = NDArray[np.float64]
Gradient = tuple[FloatArray, FloatArray, FloatArray]

#: Duplications at most: each divides the spread of the arguments by 4 (a spread of 1e300
#: relative needs fewer than 500).
_MAX_STEPS = 600
#: The convergence test of the series: 4^-m spread < _SCALE |A_m|. Carlson's factor is
#: (3 r)^(1/6) = 2.6e-3 for R_F and (r/4)^(1/6) = 1.7e-3 for R_D at r = 1e-16: the smaller.
_SCALE = 1.7e-3


def _seed(x: FloatArray, y: FloatArray, z: FloatArray) -> tuple[Dual, Dual, Dual]:
    """x, y, z as duals in the three directions, broadcast to one shape."""
    bx, by, bz = np.broadcast_arrays(x, y, z)
    return Dual.variable(bx, 0, 3), Dual.variable(by, 1, 3), Dual.variable(bz, 2, 3)


def _spread(a0: FloatArray, args: tuple[FloatArray, ...]) -> FloatArray:
    return np.max([np.abs(a0 - a) for a in args], axis=0)


def _converged(spread: FloatArray, m: int, a: FloatArray) -> bool:
    """Carlson's test for every element: 4^-m max|A0 - x_i| < _SCALE |A_m|."""
    with np.errstate(invalid="ignore"):
        # A_m = 0 (two arguments 0: R_F or R_D infinite) never converges: nothing to refine
        return bool(np.all(~(np.ldexp(spread, -2 * m) >= _SCALE * np.abs(a)) | (a == 0.0)))


def rf_gradient(x: FloatArray, y: FloatArray, z: FloatArray) -> tuple[FloatArray, Gradient]:
    """R_F(x, y, z) and its partial derivatives (dR_F/dx, dR_F/dy, dR_F/dz).

    Parameters
    ----------
    x, y, z : ndarray
        Non-negative, at most one of them zero (broadcast together); trusted, not checked.

    Returns
    -------
    (ndarray, (ndarray, ndarray, ndarray))
        The value and the gradient, each of the broadcast shape.
    """
    X, Y, Z = _seed(x, y, z)
    A0 = (X + Y + Z) / 3.0
    A = A0
    spread = _spread(A0.value, (X.value, Y.value, Z.value))
    xm, ym, zm = X, Y, Z
    m = 0
    while m < _MAX_STEPS and not _converged(spread, m, A.value):
        sx, sy, sz = xm.sqrt(), ym.sqrt(), zm.sqrt()
        lam = sx * sy + sy * sz + sz * sx
        xm, ym, zm, A = (xm + lam) / 4.0, (ym + lam) / 4.0, (zm + lam) / 4.0, (A + lam) / 4.0
        m += 1
    inv = A.reciprocal().ldexp(-2 * m)
    # (A0 - x0)/(4^m A_m): the exact small deviations, without the difference A_m - x_m
    dx, dy = (A0 - X) * inv, (A0 - Y) * inv
    dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    series = 1.0 - e2 / 10.0 + e3 / 14.0 + (e2 * e2) / 24.0 - 3.0 * (e2 * e3) / 44.0
    r = series * A.sqrt().reciprocal()
    return r.a[0], (r.a[1], r.a[2], r.a[3])


def rd_gradient(x: FloatArray, y: FloatArray, z: FloatArray) -> tuple[FloatArray, Gradient]:
    """R_D(x, y, z) and its partial derivatives (dR_D/dx, dR_D/dy, dR_D/dz).

    Parameters
    ----------
    x, y : ndarray
        Non-negative, not both zero; trusted.
    z : ndarray
        Positive; trusted.

    Returns
    -------
    (ndarray, (ndarray, ndarray, ndarray))
        The value and the gradient, each of the broadcast shape.
    """
    X, Y, Z = _seed(x, y, z)
    A0 = (X + Y + 3.0 * Z) / 5.0
    A = A0
    spread = _spread(A0.value, (X.value, Y.value, Z.value))
    xm, ym, zm = X, Y, Z
    total = 0.0 * X
    fac = 1.0
    m = 0
    while m < _MAX_STEPS and not _converged(spread, m, A.value):
        sx, sy, sz = xm.sqrt(), ym.sqrt(), zm.sqrt()
        lam = sx * sy + sy * sz + sz * sx
        total = total + fac * (sz * (zm + lam)).reciprocal()
        fac /= 4.0
        xm, ym, zm, A = (xm + lam) / 4.0, (ym + lam) / 4.0, (zm + lam) / 4.0, (A + lam) / 4.0
        m += 1
    inv = A.reciprocal().ldexp(-2 * m)
    dx, dy = (A0 - X) * inv, (A0 - Y) * inv
    dz = -(dx + dy) / 3.0
    xy = dx * dy
    z2 = dz * dz
    e2 = xy - 6.0 * z2
    e3 = (3.0 * xy - 8.0 * z2) * dz
    e4 = 3.0 * ((xy - z2) * z2)
    e5 = xy * (z2 * dz)
    series = (
        1.0
        - 3.0 * e2 / 14.0
        + e3 / 6.0
        + 9.0 * (e2 * e2) / 88.0
        - 3.0 * e4 / 22.0
        - 9.0 * (e2 * e3) / 52.0
        + 3.0 * e5 / 26.0
    )
    r = fac * (series * (A * A.sqrt()).reciprocal()) + 3.0 * total  # A^(3/2)
    return r.a[0], (r.a[1], r.a[2], r.a[3])
