"""The result type of the exact solver: one state (or an array of states) of the hair."""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._branch import BranchPoint, shape_terms, tip_deflection
from ._validation import as_float_array

__all__ = ["Solution"]

FloatArray = NDArray[np.float64]


def _out(a: Any) -> Any:
    """0-d arrays become Python scalars (floats, bools, ints)."""
    a = np.asarray(a)
    return a.item() if a.ndim == 0 else a


def _map_arrays(bp: BranchPoint, func: Any) -> BranchPoint:
    """A branch point with ``func`` applied to every array field (labels kept)."""
    values = {f.name: getattr(bp, f.name) for f in fields(bp)}
    return BranchPoint(
        **{k: func(v) if isinstance(v, np.ndarray) else v for k, v in values.items()}
    )


@dataclass(frozen=True, eq=False)
class Solution:
    """A state of the hair on one branch, in the paper's dimensionless variables [1]_.

    Scalar inputs give float fields, array inputs give arrays of the broadcast shape. Where
    the requested branch has no solution at the inputs, every value field is NaN and
    ``n_roots`` is 0.

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
        Scaled energy xi = E/omega_eps^2 = sin(theta1) [-] (eq. {xi}); rounds to 1 at strong
        forcing although the other fields stay exact.
    omega_eps : float or ndarray
        Effective frequency omega_eps = omega / sqrt(1 - eps h1) [-] (eq. {oe-givens}).
    energy : float or ndarray
        Hamiltonian E = theta'^2/2 + omega_eps^2 sin(theta) [-] (eq. {hairH}).
    tip_height : float or ndarray
        h1 = z(1) = int_0^1 cos(theta) dsigma, in units of the hair length L [-] (eq. {hs}).
    tip_deflection : float or ndarray
        x1 = x(1) = int_0^1 sin(theta) dsigma, in units of L [-].
    tip_angle : float or ndarray
        theta1 = theta(1) [rad].
    base_curvature : float or ndarray
        theta'(0) = omega_eps^2 h1, in units of 1/L [-] (eq. {intOrig}).
    n_roots : int or ndarray
        Number of solutions on this branch at these inputs (3 in a bistable window).
    physical : bool or ndarray
        True on the physical branch (sign = +1, n = 0) where a solution exists: the hair rises
        monotonically and never touches the wall. Every other branch twirls.

    References
    ----------
    .. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
       Deformation of a Boundary Hair".
    """

    omega2: Any
    eps: Any
    theta0: Any
    sign: int
    n: int
    xi: Any
    omega_eps: Any
    energy: Any
    tip_height: Any
    tip_deflection: Any
    tip_angle: Any
    base_curvature: Any
    n_roots: Any
    physical: Any
    _point: BranchPoint = field(repr=False)

    @classmethod
    def _from_point(
        cls, bp: BranchPoint, omega2: FloatArray | None = None, n_roots: Any = None
    ) -> Solution:
        """Assemble the fields from a branch point (t = NaN marks 'no solution')."""
        missing = np.isnan(bp.t)
        if n_roots is None:
            n_roots = np.where(missing, 0, 1)
        n_roots = np.broadcast_to(np.asarray(n_roots, dtype=np.int64), bp.t.shape)
        if omega2 is None:
            omega2 = bp.omega2
        with np.errstate(invalid="ignore", divide="ignore"):
            x1 = tip_deflection(bp)

        def nan_where_missing(a: FloatArray) -> Any:
            return _out(np.where(missing, np.nan, a))

        return cls(
            omega2=_out(omega2),
            eps=_out(bp.eps),
            theta0=_out(bp.theta0),
            sign=bp.sign,
            n=bp.n,
            xi=nan_where_missing(bp.xi),
            omega_eps=nan_where_missing(bp.omega_eps),
            energy=nan_where_missing(bp.energy),
            tip_height=nan_where_missing(bp.tip_height),
            tip_deflection=nan_where_missing(x1),
            tip_angle=nan_where_missing(bp.tip_angle),
            base_curvature=nan_where_missing(bp.base_curvature),
            n_roots=_out(n_roots),
            physical=_out((bp.sign == 1) & (bp.n == 0) & ~missing),
            _point=bp,
        )

    @property
    def shape(self) -> tuple[int, ...]:
        """Shape of the array fields (() for a single state)."""
        return np.shape(self.xi)

    def _shape(self, sigma: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        s = as_float_array(sigma, "sigma")
        bad = (s < 0.0) | (s > 1.0)
        if np.any(bad):
            raise ValueError(f"sigma must lie in [0, 1], got {float(s[bad].flat[0])!r}")
        with np.errstate(invalid="ignore", divide="ignore"):
            return shape_terms(self._point, s)

    def theta(self, sigma: ArrayLike) -> Any:
        """Angle theta(sigma) from the vertical [rad] (eq. {solution}).

        Parameters
        ----------
        sigma : array_like
            Arc length s/L in [0, 1], broadcast against the solution's shape.
        """
        return _out(self._shape(sigma)[0])

    def x(self, sigma: ArrayLike) -> Any:
        """Horizontal position x(sigma) = int_0^sigma sin(theta) in units of L [-].

        Closed form ((v - v0) - 2 (Eps(v) - Eps(v0))) / (sign omega_eps), math.md section 3.
        """
        return _out(self._shape(sigma)[1])

    def z(self, sigma: ArrayLike) -> Any:
        """Height z(sigma) = h(sigma) = int_0^sigma cos(theta) in units of L [-] (eq. {hs})."""
        return _out(self._shape(sigma)[2])

    def profile(self, num: int = 200) -> tuple[Any, Any]:
        """Points (x, z) along the hair for plotting, in units of L.

        Returns arrays of shape ``self.shape + (num,)``, from the base (sigma = 0) to the tip.
        """
        if isinstance(num, bool) or not isinstance(num, (int, np.integer)) or num < 2:
            raise ValueError(f"num must be an integer >= 2, got {num!r}")
        sigma = np.linspace(0.0, 1.0, int(num))
        sigma = sigma.reshape((1,) * len(self.shape) + (num,))
        expanded = _map_arrays(self._point, lambda a: a[..., None])
        with np.errstate(invalid="ignore", divide="ignore"):
            _, x, z = shape_terms(expanded, sigma)
        return x, z

    def __getitem__(self, index: Any) -> Solution:
        """Select states of an array solution with numpy indexing."""
        if self.shape == ():
            raise TypeError("a scalar Solution cannot be indexed")
        sub = _map_arrays(self._point, lambda a: a[index])
        return Solution._from_point(
            sub,
            omega2=np.asarray(self.omega2)[index],
            n_roots=np.asarray(self.n_roots)[index],
        )

    def as_dict(self) -> dict[str, Any]:
        """The public fields by their API names (arrays as lists), e.g. for JSON."""
        out: dict[str, Any] = {}
        for f in fields(self):
            if f.name.startswith("_"):
                continue
            v = getattr(self, f.name)
            out[f.name] = v.tolist() if isinstance(v, np.ndarray) else v
        return out
