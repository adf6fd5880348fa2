"""The one result type shared by the numerical baselines, and helpers to fill it."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.validation import check_scalar_inputs

__all__ = ["MAX_OMEGA2", "NumericalResult", "branch_label", "scalar_inputs"]

#: The strongest forcing the numerical baselines take (omega = 10^4: a base boundary layer of
#: width 1e-4, which needs grids of 10^5 and more; the exact solver has no such limit).
MAX_OMEGA2 = 1e8

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class NumericalResult:
    """Outcome of a numerical solve of the hair problem, in the style of ``scipy.optimize``.

    Every field is filled even when ``success`` is False: it then describes the last iterate,
    which is what a user needs to judge what went wrong.

    Attributes
    ----------
    success : bool
        True if the solver met its convergence criterion.
    status : int
        The package's one convention (:data:`hairbed._core.validation.STATUS_MESSAGES`): 0
        converged; -2 iteration limit reached; -3 the iteration stalled or broke down
        (singular step, no descent, integrator failure); 3 converged, but the answer is known
        to be inaccurate (shooting at strong forcing, see ``message``; ``success`` is True).
    message : str
        Human-readable description of ``status``.
    nit : int
        Nonlinear iterations taken (Newton steps, root-finder calls or collocation mesh
        refinements, depending on the method; MINPACK's hybr reports none: its ``nfev``).
        ``iterations`` is its deprecated old name.
    method : str
        Which solver produced the result.
    omega2, eps, theta0 : float
        The inputs: forcing omega^2 [-], confinement eps = L/H [-] and base angle [rad].
    sigma : ndarray
        Arc length of the nodes [-], from 0 (base) to 1 (tip).
    theta : ndarray
        Angle from the vertical at the nodes [rad].
    x, z : ndarray
        Centreline coordinates at the nodes [-] (downstream and wall-normal, in hair lengths).
    tip_height : float
        h1 = z(1) = int_0^1 cos(theta) dsigma [-].
    tip_deflection : float
        x1 = x(1) = int_0^1 sin(theta) dsigma [-].
    xi : float
        Similarity variable xi = sin(theta(1)) (eq. (14)) [-].
    omega_eps : float
        Effective frequency omega_eps = sqrt(omega^2 / (1 - eps h1)) (eq. (5)) [-].
    base_curvature : float
        theta'(0) [-].
    sign : int
        Sign of theta'(0) in the converged shape (+1 if it is zero).
    n : int
        Number of interior turning points (sign changes of theta') in the converged shape.
        The physical branch is ``sign == 1, n == 0``.
    nfev : int
        Evaluations of the residual or of the right-hand side.
    solver_status : int or None
        The underlying scipy solver's own status code (solve_bvp, root), None for the
        package's own iterations.
    """

    success: bool
    status: int
    message: str
    nit: int
    method: str
    omega2: float
    eps: float
    theta0: float
    sigma: FloatArray = field(repr=False)
    theta: FloatArray = field(repr=False)
    x: FloatArray = field(repr=False)
    z: FloatArray = field(repr=False)
    tip_height: float
    tip_deflection: float
    xi: float
    omega_eps: float
    base_curvature: float
    sign: int
    n: int
    nfev: int = 0
    solver_status: int | None = None

    @property
    def iterations(self) -> int:
        """Deprecated: the old name of :attr:`nit`."""
        warnings.warn(
            "NumericalResult.iterations is deprecated; use NumericalResult.nit",
            FutureWarning,
            stacklevel=2,
        )
        return self.nit

    @property
    def physical(self) -> bool:
        """True if the shape lies on the physical branch (``sign == 1`` and ``n == 0``)."""
        return self.sign == 1 and self.n == 0


def branch_label(dtheta: FloatArray, base_curvature: float) -> tuple[int, int]:
    """Branch label (sign, n) read off a computed shape.

    Parameters
    ----------
    dtheta : ndarray
        Samples of theta' (or of differences of theta) along the hair, base to tip, fine
        enough to resolve every turning point.
    base_curvature : float
        theta'(0) [-].

    Returns
    -------
    sign, n : int
        Sign of theta'(0) (+1 when zero, as for the undeformed hair) and the number of sign
        changes of theta' strictly inside the hair.
    """
    d = np.asarray(dtheta, dtype=np.float64)
    scale = float(np.max(np.abs(d))) if d.size else 0.0
    # theta' vanishes at the tip by construction, so samples there carry only rounding noise:
    # ignore entries far below the shape's own scale rather than count noise as turning points.
    d = d[np.abs(d) > 1e-9 * scale] if scale > 0 else d[:0]
    n = int(np.count_nonzero(np.signbit(d[1:]) != np.signbit(d[:-1])))
    sign = -1 if base_curvature < 0 else 1
    return sign, n


def scalar_inputs(omega2: Any, eps: Any, theta0: Any) -> tuple[float, float, float]:
    """Validate the physical inputs like the core does, and insist they are scalars.

    Raises
    ------
    ValueError
        If a value is out of range (message from :func:`hairbed._core.validation.check_inputs`),
        omega2 > ``MAX_OMEGA2``, or any input is an array: the numerical baselines solve one
        state at a time.
    """
    return check_scalar_inputs(
        omega2,
        eps,
        theta0,
        omega2_max=MAX_OMEGA2,
        why=" (the boundary layer of width 1/omega is beyond any grid of a numerical baseline; "
        "hairbed.solve is exact at any forcing)",
    )
