"""The one bracketed scalar root finder and minimiser of the lab modules.

Every one-dimensional search outside the compiled core (the branch parameter t of a measured
tip, the forcing along a sweep, the fold confinement of :func:`hairbed.branches.cusp`) goes
through :func:`find_root` and :func:`find_minimum` here: thin wrappers of
:mod:`scipy.optimize.elementwise` (Chandrupatla's bracketing methods, vectorised over arrays
of problems: no Python loop over elements) that grow a bracket where asked and turn a failed
search into an error that says what was sought, never a silent NaN.

The objective ``f(x, *args)`` must be elementwise: scipy calls it on the still-active
elements only, with ``args`` sliced alike.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import elementwise

__all__ = ["find_minimum", "find_root"]

Objective = Callable[..., NDArray[np.float64]]


def _tolerances(xatol: float | None, xrtol: float | None) -> dict[str, float]:
    return {k: float(v) for k, v in (("xatol", xatol), ("xrtol", xrtol)) if v is not None}


def _check(res: Any, what: str, stage: str) -> None:
    """Raise if any element of a scipy elementwise result failed."""
    status = np.asarray(res.status)
    bad = status != 0
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        raise FloatingPointError(
            f"{stage} of {what} failed (scipy.optimize.elementwise status "
            f"{int(status.ravel()[i])} at flat index {i})"
        )


def find_root(
    f: Objective,
    lower: ArrayLike,
    upper: ArrayLike,
    *,
    args: tuple[ArrayLike, ...] = (),
    grow: bool = False,
    xmin: ArrayLike | None = None,
    xmax: ArrayLike | None = None,
    xatol: float | None = None,
    xrtol: float | None = None,
    maxiter: int | None = None,
    what: str = "a root",
) -> Any:
    """Roots of a monotone ``f(x, *args)`` in [lower, upper], elementwise.

    Parameters
    ----------
    f : callable
        Elementwise objective, ``f(x, *args) -> array``, finite at every x it is given.
    lower, upper : array_like
        A bracket (``f`` of opposite signs, or zero, at the two ends) or, with ``grow``, a
        starting interval that :func:`scipy.optimize.elementwise.bracket_root` widens
        (geometrically, or towards ``xmin`` / ``xmax``) until it brackets the root.
    args : tuple of array_like
        Extra arguments of ``f``, broadcast against the brackets.
    grow : bool
        Widen the starting interval first.
    xmin, xmax : array_like, optional
        Limits of the grown bracket (inclusive).
    xatol, xrtol : float, optional
        Absolute and relative tolerances on x [units of x]; scipy's defaults (4 ulp
        relative) when omitted.
    maxiter : int, optional
        Iteration limit of the root search (scipy's default when omitted).
    what : str
        What is sought, for the error message.

    Returns
    -------
    scipy.optimize.elementwise result
        ``x`` the roots, ``bracket`` the final brackets (``bracket[1]`` is the end where f
        has the sign of ``f(upper)``), ``success``, ``status``, ``nfev``, ``nit``.

    Raises
    ------
    FloatingPointError
        If a bracket cannot be found or the search does not converge (scipy's status and
        the first failing flat index in the message).
    """
    if grow:
        b = elementwise.bracket_root(f, lower, upper, xmin=xmin, xmax=xmax, args=args)
        _check(b, what, "bracketing")
        lower, upper = b.bracket
    res = elementwise.find_root(
        f,
        (lower, upper),
        args=args,
        tolerances=_tolerances(xatol, xrtol),
        maxiter=maxiter,
    )
    _check(res, what, "root search")
    return res


def find_minimum(
    f: Objective,
    left: ArrayLike,
    middle: ArrayLike,
    right: ArrayLike,
    *,
    args: tuple[ArrayLike, ...] = (),
    xatol: float | None = None,
    xrtol: float | None = None,
    maxiter: int = 100,
    what: str = "a minimum",
) -> Any:
    """Local minima of ``f(x, *args)`` in the three-point brackets (left, middle, right).

    The brackets need ``left < middle < right`` and ``f(left) >= f(middle) <= f(right)``
    (one of them strict), as from a grid search. ``x`` is found to about sqrt(machine
    epsilon) relative by default (no better is possible from values alone); ``f_x``, the
    minimum, to rounding. Arguments and the result as for :func:`find_root`.

    Raises
    ------
    FloatingPointError
        If a bracket is invalid or the search does not converge.
    """
    res = elementwise.find_minimum(
        f,
        (left, middle, right),
        args=args,
        tolerances=_tolerances(xatol, xrtol),
        maxiter=maxiter,
    )
    _check(res, what, "minimisation")
    return res
