"""The porous bed's branch of states along its tip deflection, and its folds (theory.md §13).

A tip deflection determines a state of the wall-driven porous bed, even where several states
share one forcing: the inverse (:func:`hairbed.inverse.porous_state_from_tip_deflection`)
solves for the forcing omega2 at a given tip deflection x1. So the whole branch is the
explicit curve omega2(x1), no continuation needed, and its folds are the extrema of that
curve: a local maximum (the low state ends) and a local minimum (the high state ends), with
three states between them. A state is stable where omega2 rises with x1 (a slow increase
of the drive moves the tip on along the flow).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.validation import check_int, check_number
from .inverse import porous_state_from_tip_deflection

__all__ = ["PorousBranch", "porous_branch"]

FloatArray = NDArray[np.float64]

#: Golden-section steps that refine a fold's tip deflection (the bracket shrinks by 0.618 a
#: step: 60 steps take a scan cell below 1e-14 of L).
_GOLDEN_STEPS = 60


@dataclass(frozen=True)
class PorousBranch:
    """A porous bed's branch of wall-driven states along the tip deflection.

    Attributes
    ----------
    tip_deflection : ndarray
        x1 [L], the curve's parameter, from the hair at rest towards flat.
    omega2 : ndarray
        The forcing of each state [-] (NaN where the inverse found none: status < 0).
    tip_height : ndarray
        h1 [L] of each state.
    stable : ndarray of bool
        Where omega2 rises with x1.
    status : ndarray of int
        The inverse's status of each point.
    fold_tip_deflection, fold_omega2 : ndarray
        The folds: the local extrema of omega2(x1), in x1 order (empty where omega2 rises
        throughout: one state at every forcing).
    fold_kind : tuple of str
        "upper" (a local maximum of omega2: the low state ends) or "lower" (a minimum).
    """

    tip_deflection: FloatArray
    omega2: FloatArray
    tip_height: FloatArray
    stable: NDArray[np.bool_]
    status: NDArray[np.int64]
    fold_tip_deflection: FloatArray
    fold_omega2: FloatArray
    fold_kind: tuple[str, ...]

    @property
    def window(self) -> tuple[float, float] | None:
        """(lower, upper) fold forcing of a window of three states, or None."""
        if len(self.fold_kind) != 2:
            return None
        return float(np.min(self.fold_omega2)), float(np.max(self.fold_omega2))


def _omega2(x1: FloatArray, args: tuple[float, float, float, float]) -> Any:
    eps, theta0, kappa, gamma = args
    return porous_state_from_tip_deflection(x1, eps, theta0, kappa=kappa, gamma=gamma)


def porous_branch(
    eps: float,
    theta0: float = 0.0,
    *,
    kappa: float,
    gamma: float = 1.0,
    x1_max: float = 0.99,
    num: int = 200,
) -> PorousBranch:
    """The wall-driven porous bed's states along their tip deflection, with the folds.

    The curve omega2(x1) on ``num`` tip deflections uniform from the hair at rest,
    sin(theta0), to ``x1_max``, each by the porous inverse; each sign change of its slope
    bracketing a fold refined by golden-section search on omega2 (all folds at once) to a
    tip deflection within 1e-14, where omega2 is stationary (its error there is quadratic
    in that of x1). Folds closer than a scan cell can be missed.

    Parameters
    ----------
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).
    kappa, gamma : float
        The bed's permeability over L^2 and drag ratio (:func:`hairbed.solve_porous`).
    x1_max : float, optional
        The end of the curve [L], in (sin(theta0), 1). Default 0.99.
    num : int, optional
        Points of the curve, in [8, 10^5]. Default 200.

    Returns
    -------
    PorousBranch

    Examples
    --------
    >>> b = porous_branch(0.95, -1.2, kappa=1e-4, num=60)
    >>> [round(w, 4) for w in b.window]
    [0.4933, 0.5886]
    """
    eps_f = check_number(eps, "eps", low=0.0, high=1.0, high_open=True)
    t0 = check_number(theta0, "theta0", low=-math.pi / 2, high=math.pi / 2, low_open=True,
                      high_open=True)  # fmt: skip
    rest = math.sin(t0)
    top = check_number(x1_max, "x1_max", low=rest, high=1.0, low_open=True, high_open=True)
    count = check_int(num, "num", 8, 10**5)
    k = check_number(kappa, "kappa", low=0.0, low_open=True)
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    args = (eps_f, t0, k, g)
    x1 = np.linspace(rest, top, count)
    st = _omega2(x1, args)
    w = np.asarray(st.omega2, dtype=np.float64)
    ok = np.asarray(st.status) >= 0
    slope = np.diff(w)
    # a fold lies where the slope changes sign between two cells (both ends found)
    turn = np.flatnonzero(
        ok[:-2] & ok[1:-1] & ok[2:] & (np.sign(slope[:-1]) * np.sign(slope[1:]) < 0)
    )
    lo, hi = x1[turn], x1[turn + 2]
    upper = slope[turn] > 0  # rising then falling: a maximum
    sgn = np.where(upper, -1.0, 1.0)  # minimise sgn * omega2
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo.copy(), hi.copy()
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc = sgn * np.asarray(_omega2(c, args).omega2) if turn.size else np.zeros(0)
    fd = sgn * np.asarray(_omega2(d, args).omega2) if turn.size else np.zeros(0)
    for _ in range(_GOLDEN_STEPS if turn.size else 0):
        left = fc < fd  # the minimum lies in [a, d]: d becomes c, a new c
        a, b = np.where(left, a, c), np.where(left, d, b)
        c_new = np.where(left, b - ratio * (b - a), d)
        d_new = np.where(left, c, a + ratio * (b - a))
        probe = np.where(left, c_new, d_new)
        fp = sgn * np.asarray(_omega2(probe, args).omega2)
        fc, fd = np.where(left, fp, fd), np.where(left, fc, fp)
        c, d = c_new, d_new
    fold_x = 0.5 * (a + b)
    fold_w = np.asarray(_omega2(fold_x, args).omega2, dtype=np.float64) if turn.size else fold_x
    stable = np.concatenate([slope > 0, [bool(slope[-1] > 0)]]) & ok
    return PorousBranch(
        tip_deflection=x1,
        omega2=np.where(ok, w, np.nan),
        tip_height=np.asarray(st.tip_height, dtype=np.float64),
        stable=stable,
        status=np.asarray(st.status, dtype=np.int64),
        fold_tip_deflection=fold_x,
        fold_omega2=fold_w,
        fold_kind=tuple("upper" if u else "lower" for u in upper),
    )
