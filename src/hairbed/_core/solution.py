"""The result type of the exact solver: one state (or an array of states) of the hair."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._kernels import FIELDS
from .validation import (
    STATUS_MESSAGES,
    _first_index,
    as_float_array,
    broadcast_named,
    check_int,
    scalar_or_array,
    show,
    status_messages,
)

__all__ = ["STATUS_MESSAGES", "Solution"]

FloatArray = NDArray[np.float64]
#: A float for a single state, an array of the broadcast shape otherwise.
Value = float | FloatArray
IntValue = int | NDArray[np.int64]
BoolValue = bool | NDArray[np.bool_]


# where each field sits in a kernel's output (a dict literal over these is ~1 us faster per
# scalar solve than building the dict from FIELDS, a tenth of the call)
(
    _C_T,
    _C_N_ROOTS,
    _C_STATUS,
    _C_OMEGA2,
    _C_XI,
    _C_OMEGA_EPS,
    _C_ENERGY,
    _C_TIP_HEIGHT,
    _C_TIP_DEFLECTION,
    _C_TIP_DISPLACEMENT,
    _C_TIP_ANGLE,
    _C_BASE_CURVATURE,
) = (
    FIELDS.index(name)
    for name in (
        "t",
        "n_roots",
        "status",
        "omega2",
        "xi",
        "omega_eps",
        "energy",
        "tip_height",
        "tip_deflection",
        "tip_displacement",
        "tip_angle",
        "base_curvature",
    )
)

_SHAPE_KERNELS: Any = None


def _shape_kernels() -> Any:
    """The kernel module of the shapes, imported on first use (compiles or loads only then)."""
    global _SHAPE_KERNELS
    if _SHAPE_KERNELS is None:
        from ._kernels import state

        _SHAPE_KERNELS = state
    return _SHAPE_KERNELS


#: 0-d arrays become Python scalars (floats, bools, ints).
_out = scalar_or_array


@dataclass(frozen=True, eq=False)
class Solution:
    """A state of the hair on one branch, in the dimensionless variables of the paper.

    The variables are those of [1]_.

    Scalar inputs give float fields, array inputs give arrays of the broadcast shape. Where
    the requested state does not exist at the inputs, every value field is NaN, ``status``
    is -1 and ``n_roots`` says how many states the branch has there.

    Attributes
    ----------
    omega2 : float or ndarray
        Forcing omega^2 = pi a^2 L^2 eta v / (E I H phi) [-] (input of :func:`hairbed.solve`).
    eps : float or ndarray
        Confinement eps = L/H [-].
    theta0 : float or ndarray
        Base angle from the vertical [rad].
    sign : int
        Sign of the base curvature theta'(0) of the branch.
    n : int
        Number of interior turning points (theta' = 0 inside 0 < sigma < 1) of the branch.
    xi : float or ndarray
        Scaled energy xi = E/omega_eps^2 = sin(theta1) [-] (eq. (14) of [1]_); rounds to 1 at
        strong forcing although the other fields stay exact.
    omega_eps : float or ndarray
        Effective frequency omega_eps = omega / sqrt(1 - eps h1) [-] (eq. (5)).
    energy : float or ndarray
        Hamiltonian E = theta'^2/2 + omega_eps^2 sin(theta) [-] (eq. (7)).
    tip_height : float or ndarray
        h1 = z(1) = int_0^1 cos(theta) dsigma, in units of the hair length L [-] (eq. (30));
        never above 1.
    tip_deflection : float or ndarray
        x1 = x(1) = int_0^1 sin(theta) dsigma, in units of L [-].
    tip_displacement : float or ndarray
        x1 - sin(theta0), the tip's horizontal displacement from the hair at rest, in units of
        L [-]; accurate relative to itself at weak forcing (omega_eps^2 cos^2(theta0)/3 to
        leading order: a point load at the tip, x1 = F L^3/(3 E I)).
    tip_angle : float or ndarray
        theta1 = theta(1) [rad].
    base_curvature : float or ndarray
        theta'(0) = omega_eps^2 h1, in units of 1/L [-] (eq. (29)).
    n_roots : int or ndarray
        Number of solutions on this branch at these inputs (3 in a bistable window).
    physical : bool or ndarray
        True on the physical branch (sign = +1, n = 0) where a solution exists: the hair rises
        monotonically and never touches the wall. Every other branch twirls.
    status : int or ndarray
        How the solve of each element ended: 0 converged, -1 no such state (see ``n_roots``),
        -2 iteration limit (``STATUS_MESSAGES``).
    t : float or ndarray
        Branch parameter, the logit of (xi - sin theta0)/(1 - sin theta0) [-]; -inf is the
        hair at rest.

    References
    ----------
    .. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
       Deformation of a Boundary Hair", arXiv:2203.04169 (2022).
    """

    omega2: Value
    eps: Value
    theta0: Value
    sign: int
    n: int
    xi: Value
    omega_eps: Value
    energy: Value
    tip_height: Value
    tip_deflection: Value
    tip_displacement: Value
    tip_angle: Value
    base_curvature: Value
    n_roots: IntValue
    physical: BoolValue
    status: IntValue
    t: Value

    @classmethod
    def _from_row(
        cls, row: Any, eps: float, theta0: float, sign: int, n: int, omega2: Any
    ) -> Solution:
        """A single state from the kernel's output tuple (columns ``_kernels.FIELDS``).

        Built without the frozen dataclass's per-field ``object.__setattr__`` (a scalar solve
        is a few microseconds; the generated ``__init__`` alone would double it).
        """
        status = int(row[_C_STATUS])
        values = {
            "omega2": row[_C_OMEGA2] if omega2 is None else omega2,
            "eps": eps,
            "theta0": theta0,
            "sign": sign,
            "n": n,
            "xi": row[_C_XI],
            "omega_eps": row[_C_OMEGA_EPS],
            "energy": row[_C_ENERGY],
            "tip_height": row[_C_TIP_HEIGHT],
            "tip_deflection": row[_C_TIP_DEFLECTION],
            "tip_displacement": row[_C_TIP_DISPLACEMENT],
            "tip_angle": row[_C_TIP_ANGLE],
            "base_curvature": row[_C_BASE_CURVATURE],
            "n_roots": int(row[_C_N_ROOTS]),
            "physical": sign == 1 and n == 0 and status == 0,
            "status": status,
            "t": row[_C_T],
        }
        obj = object.__new__(cls)
        object.__setattr__(obj, "__dict__", values)
        return obj

    @classmethod
    def _from_columns(
        cls,
        out: FloatArray,
        shape: tuple[int, ...],
        eps: FloatArray,
        theta0: FloatArray,
        sign: int,
        n: int,
        omega2: FloatArray | None,
    ) -> Solution:
        """States from the kernel's (NFIELDS, N) output, reshaped to ``shape``."""

        values = {name: _out(out[i].reshape(shape)) for i, name in enumerate(FIELDS)}
        status = out[FIELDS.index("status")].reshape(shape).astype(np.int64)
        values.update(
            eps=_out(eps),
            theta0=_out(theta0),
            n_roots=_out(out[FIELDS.index("n_roots")].reshape(shape).astype(np.int64)),
            status=_out(status),
            physical=_out((status == 0) & (sign == 1) & (n == 0)),
        )
        if omega2 is not None:
            values["omega2"] = _out(omega2)
        return cls(sign=sign, n=n, **values)

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the array fields (() for a single state)."""
        return np.shape(self.xi)

    @property
    def success(self) -> BoolValue:
        """True where the state exists and its solve converged (status 0)."""
        return _out(np.asarray(self.status) == 0)

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for array solutions)."""
        return status_messages(self.status, STATUS_MESSAGES)

    def _shape_values(self, sigma: ArrayLike) -> FloatArray:
        s = as_float_array(sigma, "sigma")
        bad = (s < 0.0) | (s > 1.0)
        if np.any(bad):
            raise ValueError(
                f"sigma must lie in [0, 1], got {float(s[bad].flat[0])!r}{_first_index(bad)}"
            )
        t = np.asarray(self.t, dtype=np.float64)
        try:
            np.broadcast_shapes(t.shape, s.shape)
        except ValueError:
            raise ValueError(
                f"sigma must broadcast against the solution's shape {t.shape}, got shape "
                f"{s.shape} (for the same arc lengths on every state, add axes: "
                "sigma[:, None] ... or use profile(num))"
            ) from None
        t, e, th, s = broadcast_named(
            ("the solution's t", t),
            ("eps", np.asarray(self.eps, dtype=np.float64)),
            ("theta0", np.asarray(self.theta0, dtype=np.float64)),
            ("sigma", s),
        )
        shape = t.shape
        size = t.size
        out = np.empty((6, size, 1))
        _shape_kernels().shape_array(
            np.ascontiguousarray(t).reshape(size),
            np.ascontiguousarray(e).reshape(size),
            np.ascontiguousarray(th).reshape(size),
            self.sign,
            self.n,
            np.ascontiguousarray(s).reshape(size, 1),
            out,
        )
        return out.reshape((6, *shape))

    def theta(self, sigma: ArrayLike) -> Any:
        """Angle theta(sigma) from the vertical [rad] (eq. (32)).

        Parameters
        ----------
        sigma : array_like
            Arc length s/L in [0, 1], broadcast against the solution's shape.
        """
        return _out(self._shape_values(sigma)[0])

    def x(self, sigma: ArrayLike) -> Any:
        """Horizontal position x(sigma) = int_0^sigma sin(theta) in units of L [-]."""
        return _out(self._shape_values(sigma)[1])

    def z(self, sigma: ArrayLike) -> Any:
        """Height z(sigma) = h(sigma) = int_0^sigma cos(theta) in units of L [-] (eq. (30))."""
        return _out(self._shape_values(sigma)[2])

    def displacement(self, sigma: ArrayLike) -> tuple[Any, Any, Any]:
        """Displacements from the hair at rest at arc length sigma.

        Returns (theta - theta0 [rad], x - sigma sin(theta0), z - sigma cos(theta0)) in units
        of L [-]. On the physical branch each is accurate relative to itself (to ~1e-14 against
        mpmath), also where it is far below the rounding error of theta, x and z themselves:
        at weak forcing, on short arcs from the base, near theta0 = +-pi/2. On the twirling
        branches they are theta - theta0, x - sigma sin(theta0), z - sigma cos(theta0).
        """
        v = self._shape_values(sigma)
        return _out(v[3]), _out(v[4]), _out(v[5])

    def profile(self, num: int = 200) -> tuple[Any, Any]:
        """Points (x, z) along the hair for plotting, in units of L.

        Returns arrays of shape ``self.shape + (num,)``, from the base (sigma = 0) to the tip;
        num in [2, 10^7].
        """
        num = check_int(num, "num", 2, 10**7)
        kernels = _shape_kernels()
        if type(self.t) is float:  # a single state: no numpy broadcasting (~10 us a call)
            xs, zs = kernels.profile_array(
                np.array([self.t]),
                np.array([self.eps]),
                np.array([self.theta0]),
                self.sign,
                self.n,
                num,
            )
            return xs[0], zs[0]
        shape = self.shape

        def flat(v: Any) -> FloatArray:
            return np.array(np.broadcast_to(np.asarray(v, dtype=np.float64), shape)).reshape(-1)

        t, e, th = (flat(v) for v in (self.t, self.eps, self.theta0))
        xs, zs = kernels.profile_array(t, e, th, self.sign, self.n, num)
        return xs.reshape((*shape, num)), zs.reshape((*shape, num))

    def __getitem__(self, index: Any) -> Solution:
        """Select states of an array solution with numpy indexing."""
        if self.shape == ():
            raise TypeError("a scalar Solution cannot be indexed")
        shape = self.shape
        try:
            np.empty(shape, dtype=np.bool_)[index]
        except (IndexError, ValueError, TypeError, OverflowError) as exc:
            raise IndexError(
                f"index {show(index)} does not select states of a Solution of shape {shape} "
                f"({exc})"
            ) from None
        values: dict[str, Any] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("sign", "n"):
                values[f.name] = v
            else:
                values[f.name] = _out(np.broadcast_to(np.asarray(v), shape)[index])
        return Solution(**values)

    def as_dict(self) -> dict[str, Any]:
        """The public fields by their API names (arrays as lists), e.g. for JSON."""
        out: dict[str, Any] = {}
        for f in fields(self):
            v = getattr(self, f.name)
            out[f.name] = v.tolist() if isinstance(v, np.ndarray) else v
        return out
