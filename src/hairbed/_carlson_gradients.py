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

__all__ = ["rd_gradient", "rf_gradient", "rf_rd_gradient"]

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


def _duplicate(
    X: Dual, Y: Dual, Z: Dual, a0: tuple[Dual, ...]
) -> tuple[int, list[Dual], Dual, float]:
    """Carlson's duplication of (X, Y, Z), carrying the means A of ``a0`` along, until each
    mean passes the convergence test for every element.

    Returns (m, [A_m for each mean], sum_k 4^-k / (sqrt(z_k) (z_k + lambda_k)), 4^-m): the
    sum is R_D's; the steps, shared by R_F and R_D, are done once for both.
    """
    spreads = [_spread(a.value, (X.value, Y.value, Z.value)) for a in a0]
    means = list(a0)
    xm, ym, zm = X, Y, Z
    total = 0.0 * X
    fac = 1.0
    m = 0
    while m < _MAX_STEPS and not all(_converged(sp, m, a.value) for sp, a in zip(spreads, means)):
        sx, sy, sz = xm.sqrt(), ym.sqrt(), zm.sqrt()
        lam = sx * sy + sy * sz + sz * sx
        total = total + fac * (sz * (zm + lam)).reciprocal()
        fac /= 4.0
        xm, ym, zm = (xm + lam) / 4.0, (ym + lam) / 4.0, (zm + lam) / 4.0
        means = [(a + lam) / 4.0 for a in means]
        m += 1
    return m, means, total, fac


def _rf_series(X: Dual, Y: Dual, A0: Dual, A: Dual, m: int) -> Dual:
    """R_F from the mean A = A_m after m steps (DLMF 19.36.1)."""
    inv = A.reciprocal().ldexp(-2 * m)
    # (A0 - x0)/(4^m A_m): the exact small deviations, without the difference A_m - x_m
    dx, dy = (A0 - X) * inv, (A0 - Y) * inv
    dz = -(dx + dy)
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    series = 1.0 - e2 / 10.0 + e3 / 14.0 + (e2 * e2) / 24.0 - 3.0 * (e2 * e3) / 44.0
    return series * A.sqrt().reciprocal()


def _rd_series(X: Dual, Y: Dual, A0: Dual, A: Dual, m: int, total: Dual, fac: float) -> Dual:
    """R_D from the mean A = A_m after m steps and the sum of the steps (DLMF 19.36.2)."""
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
    return fac * (series * (A * A.sqrt()).reciprocal()) + 3.0 * total  # A^(3/2)


def _split(r: Dual) -> tuple[FloatArray, Gradient]:
    return r.a[0], (r.a[1], r.a[2], r.a[3])


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
    a0 = (X + Y + Z) / 3.0
    m, (a,), _, _ = _duplicate(X, Y, Z, (a0,))
    return _split(_rf_series(X, Y, a0, a, m))


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
    a0 = (X + Y + 3.0 * Z) / 5.0
    m, (a,), total, fac = _duplicate(X, Y, Z, (a0,))
    return _split(_rd_series(X, Y, a0, a, m, total, fac))


def rf_rd_gradient(
    x: FloatArray, y: FloatArray, z: FloatArray
) -> tuple[tuple[FloatArray, Gradient], tuple[FloatArray, Gradient]]:
    """:func:`rf_gradient` and :func:`rd_gradient` at once, from one duplication (arguments
    as for :func:`rd_gradient`): the steps run until both series converge."""
    X, Y, Z = _seed(x, y, z)
    af0, ad0 = (X + Y + Z) / 3.0, (X + Y + 3.0 * Z) / 5.0
    m, (af, ad), total, fac = _duplicate(X, Y, Z, (af0, ad0))
    return _split(_rf_series(X, Y, af0, af, m)), _split(_rd_series(X, Y, ad0, ad, m, total, fac))
