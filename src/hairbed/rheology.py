"""Rheology of a hair bed: the wall shear stress it transmits, and its rectification.

The hairs shorten the channel to the gap H - h1 L above their tips, so the top wall feels the
stress eta v / (H - h1 L) instead of eta v / H (theory.md §7). Relative to the bare channel,

    stress ratio = tau / (eta v / H) = 1 / (1 - eps h1) = omega_eps^2 / omega^2     (eq. (34)).

At rest the hairs stand at h1 = cos(theta0): the ratio is 1 / (1 - eps cos theta0). Strong flow
lays them flat (h1 -> 0) and the ratio falls to 1: the bed shear-thins.

A bed of tilted hairs (theta0 != 0) is anisotropic. Flow *with* the grain (along the tilt,
theta0 > 0 for flow towards +x) bends the hairs over; flow *against* it first lifts them, which
narrows the gap (theory.md §5). Reversing the flow is the mirror image theta0 -> -theta0 at
the same omega^2 (see :mod:`hairbed.units`), so the rectification ratio is

    rectification ratio = stress_ratio(omega^2, eps, -theta0) / stress_ratio(omega^2, eps, theta0),

1 for upright hairs and above 1 for theta0 > 0 (more resistance against the grain).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.outputs import float_or_array
from ._core.solver import _solve_checked
from ._core.validation import check_inputs, check_root

__all__ = [
    "rectification_ratio",
    "rest_stress_ratio",
    "stress_ratio",
]

FloatOrArray = float | NDArray[np.float64]


def stress_ratio(omega2: Any, eps: Any, theta0: Any = 0.0, *, root: str = "low") -> FloatOrArray:
    """Wall shear stress over that of the bare channel, 1 / (1 - eps h1) [-].

    Parameters
    ----------
    omega2 : array_like
        Forcing omega^2 [-], >= 0.
    eps : array_like
        Confinement L/H [-], in [0, 1).
    theta0 : array_like
        Base angle [rad], in (-pi/2, pi/2); positive leans the hairs with the flow.
    root : {"low", "mid", "high"}
        Which state where several coexist (see :func:`hairbed.solve`).

    Returns
    -------
    float or ndarray
        tau / (eta v / H) [-], of the broadcast shape of the inputs; at omega^2 = 0 the limit
        1 / (1 - eps cos theta0).

    Examples
    --------
    >>> round(stress_ratio(0.0, 0.5), 12)  # upright hairs at rest fill half the channel
    2.0
    >>> round(stress_ratio(2.0, 0.5), 6)  # theory.md §3: h1 = 0.732706963462228
    1.578167
    """
    root = check_root(root)
    w, e, th = check_inputs(omega2, eps, theta0)
    return float_or_array(_stress_ratio(w, e, th, root))


def _stress_ratio(omega2: Any, eps: Any, theta0: Any, root: str) -> Any:
    """:func:`stress_ratio` of checked inputs, trusted."""
    h1 = np.asarray(_solve_checked(omega2, eps, theta0, root=root).tip_height, dtype=np.float64)
    return 1.0 / (1.0 - eps * h1)


def rest_stress_ratio(eps: Any, theta0: Any = 0.0) -> FloatOrArray:
    """The stress ratio of a bed at rest (slow flow), 1 / (1 - eps cos theta0) [-]."""
    _, e, th = check_inputs(0.0, eps, theta0)
    return float_or_array(1.0 / (1.0 - e * np.cos(th)))


def rectification_ratio(omega2: Any, eps: Any, theta0: Any, *, root: str = "low") -> FloatOrArray:
    """Stress against the grain over stress with the grain, at the same wall speed [-].

    Parameters
    ----------
    omega2 : array_like
        Forcing omega^2 [-] of the wall speed abs(v), >= 0.
    eps : array_like
        Confinement L/H [-], in [0, 1).
    theta0 : array_like
        Base angle [rad]: the hairs lean along the flow "with the grain".
    root : {"low", "mid", "high"}
        Which state where several coexist; against the grain (base angle -abs(theta0)) a tight
        bed can be bistable (theory.md §5).

    Returns
    -------
    float or ndarray
        stress_ratio(omega2, eps, -theta0) / stress_ratio(omega2, eps, theta0) [-]; 1 for
        theta0 = 0 or omega^2 = 0, and above 1 for theta0 > 0 and omega^2 > 0.

    Examples
    --------
    >>> round(rectification_ratio(1.0, 0.5, 0.0), 12)
    1.0
    >>> bool(rectification_ratio(1.0, 0.5, 0.3) > 1.0)
    True
    """
    root = check_root(root)
    w, e, th = check_inputs(omega2, eps, theta0)
    return float_or_array(_rectification_ratio(w, e, th, root))


def _rectification_ratio(omega2: Any, eps: Any, theta0: Any, root: str) -> Any:
    """:func:`rectification_ratio` of checked inputs, trusted."""
    return _stress_ratio(omega2, eps, -theta0, root) / _stress_ratio(omega2, eps, theta0, root)
