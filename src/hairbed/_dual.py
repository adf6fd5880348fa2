"""Forward-mode dual numbers over numpy arrays: a value and its partials in k directions.

A :class:`Dual` stacks the value and its first partial derivatives in one float array ``a``
of shape (1 + k, ...): ``a[0]`` is the value, ``a[1:]`` the partials. Arithmetic on duals
applies the chain rule to every direction at once (sum, product, reciprocal, square root), so
running an algorithm on duals differentiates it exactly, in the floating-point operations of
the algorithm itself: nothing is differenced. Floats and plain arrays mix in as constants.

Two users: Carlson's duplication with the gradient in its three arguments
(:mod:`hairbed._carlson_gradients`, k = 3) and the weak-forcing series of the kernels, run on
duals in the forcing and the base angle (:mod:`hairbed.sensitivity`, k = 2).

Examples
--------
>>> import numpy as np
>>> x = Dual.variable(np.array([2.0, 3.0]), 0, 2)  # d/dx
>>> y = Dual.variable(np.array([5.0, 7.0]), 1, 2)  # d/dy
>>> f = x * y + 3.0 * x - (x * x).sqrt()
>>> f.value.tolist(), f.partials[0].tolist(), f.partials[1].tolist()
([14.0, 27.0], [7.0, 9.0], [2.0, 3.0])
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["Dual"]

FloatArray = NDArray[np.float64]


class Dual:
    """A value with its partial derivatives in k directions, stacked in ``a`` (1 + k, ...).

    Attributes
    ----------
    a : ndarray
        ``a[0]`` the value, ``a[1:]`` the k partial derivatives, each of the value's shape.
    """

    __slots__ = ("a",)

    def __init__(self, a: FloatArray) -> None:
        self.a = a

    @classmethod
    def variable(cls, value: ArrayLike, direction: int, k: int) -> Dual:
        """The independent variable ``value`` of direction ``direction`` among ``k``."""
        v = np.asarray(value, dtype=np.float64)
        a = np.zeros((1 + k, *v.shape))
        a[0] = v
        a[1 + direction] = 1.0
        return cls(a)

    @classmethod
    def of(cls, value: ArrayLike, partials: tuple[ArrayLike, ...]) -> Dual:
        """The dual with the given value and partials (broadcast to one shape)."""
        parts = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (value, *partials)))
        return cls(np.stack(parts))

    @property
    def value(self) -> FloatArray:
        """The value ``a[0]``."""
        return self.a[0]

    @property
    def partials(self) -> FloatArray:
        """The partial derivatives ``a[1:]`` (k, ...)."""
        return self.a[1:]

    def __add__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            return Dual(self.a + o.a)
        out = self.a.copy()
        out[0] = out[0] + o
        return Dual(out)

    __radd__ = __add__

    def __neg__(self) -> Dual:
        return Dual(-self.a)

    def __sub__(self, o: Any) -> Dual:
        return self + (-o)

    def __rsub__(self, o: Any) -> Dual:
        return (-self) + o

    def __mul__(self, o: Any) -> Dual:
        if isinstance(o, Dual):
            same = self.a.shape == o.a.shape
            out = (
                np.empty_like(self.a)
                if same
                else np.empty(np.broadcast_shapes(self.a.shape, o.a.shape))
            )
            out[0] = self.a[0] * o.a[0]
            out[1:] = self.a[0] * o.a[1:] + o.a[0] * self.a[1:]
            return Dual(out)
        return Dual(self.a * o)  # a constant: broadcasts over the value's shape

    __rmul__ = __mul__

    def __truediv__(self, o: float) -> Dual:
        return Dual(self.a / o)

    def reciprocal(self) -> Dual:
        """1/u, with the partials -u'/u^2."""
        out = np.empty_like(self.a)
        out[0] = 1.0 / self.a[0]
        out[1:] = -self.a[1:] * (out[0] * out[0])
        return Dual(out)

    def sqrt(self) -> Dual:
        """sqrt(u), with the partials u'/(2 sqrt u) (infinite at u = 0: the true partial)."""
        out = np.empty_like(self.a)
        out[0] = np.sqrt(self.a[0])
        if np.all(out[0] > 0.0):
            out[1:] = self.a[1:] / (2.0 * out[0])
        else:  # the errstate only where needed: it costs more than the division
            with np.errstate(divide="ignore", invalid="ignore"):
                out[1:] = self.a[1:] / (2.0 * out[0])
        return Dual(out)

    def ldexp(self, exponent: int) -> Dual:
        """u 2^exponent, exactly (value and partials)."""
        return Dual(np.ldexp(self.a, exponent))
