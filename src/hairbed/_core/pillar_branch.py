"""Every state of an isolated pillar: the branch through the forcing range, its folds (issue 21).

Along the branch of pillar states the tip deflection x1 moves monotonically, from the straight
pillar's sin(theta0) at Lambda = 0 towards the wall (theory.md §12), while Lambda may turn back
(the snap-through of a pillar tilted far upstream). So the branch is followed in x1: each point
is the inverse problem of ``pillar.solve_pillar_inverse`` (the shared collocation kernel with
Lambda as an unknown), all points of a grid in one batch, and the branch passes its folds
without a special step. A fold is a local extremum of Lambda(x1), refined by a golden-section
search (every fold of the branch at once); the states at a forcing are the roots of Lambda(x1)
= Lambda, refined by bisection on x1. Bounded work: a fixed grid, at most 80 golden-section or
bisection steps a root.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .loaded import LADDER, _quiet
from .pillar import (
    ATLAS_THETA0,
    PillarState,
    _atlas_branch,
    _check,
    _golden_max,
    _grid_turns,
    _inverse_checked,
    _solve_pillar_checked,
    profile_coefficients,
)
from .validation import check_int, check_number

__all__ = ["PillarBranch", "continue_pillar", "solve_pillar_all"]

FloatArray = NDArray[np.float64]
_MAX_STEPS = 80


@dataclass(frozen=True)
class PillarBranch:
    """The branch of pillar states from rest to a forcing, with its folds.

    Attributes
    ----------
    tip_deflection : ndarray
        x1 along the branch [L], increasing (decreasing for a negative forcing).
    forcing : ndarray
        Lambda at each point [-].
    tip_height : ndarray
        h1 at each point [L].
    stable : ndarray of bool
        dLambda/dx1 > 0 (for either sign of the forcing: the mirror x -> -x changes the sign
        of both), by the states' exact dx1/dLambda: stable under a slow change of the
        forcing; the middle part of an S between two folds is not.
    folds : ndarray
        (k, 2): Lambda and x1 of each fold, in the order along the branch.
    status : int
        0 every point converged; -7 some did not (their values are NaN).
    """

    tip_deflection: FloatArray
    forcing: FloatArray
    tip_height: FloatArray
    stable: NDArray[np.bool_]
    folds: FloatArray
    status: int


class _Branch:
    """Lambda(x1) of one pillar by the batched inverse, counting nothing but its inputs
    (checked scalars and the profile's coefficients, as ``solve_pillar_inverse`` passes them
    on after its checks)."""

    def __init__(self, theta0: float, gamma: float, tip_load: float, prof: FloatArray) -> None:
        self.theta0 = theta0
        self.gamma = gamma
        self.tip_load = tip_load
        self.prof = prof

    def states(self, x1: Any) -> PillarState:
        x, t0, g, tip = _check(x1, self.theta0, self.gamma, self.tip_load)
        return _inverse_checked(x, t0, g, tip, self.prof, 1e-12, LADDER)

    def forcing(self, x1: float) -> float:
        return float(self.states(x1).forcing)


def _branch(theta0: Any, profile: Any, height_ratio: Any, gamma: Any, tip_load: Any) -> _Branch:
    """The :class:`_Branch` of a pillar's scalar inputs and profile, checked here."""
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    tip = check_number(tip_load, "tip_load")
    prof = profile_coefficients(profile, height_ratio)[None, :]
    t0 = check_number(
        theta0, "theta0", low=-math.pi / 2, high=math.pi / 2, low_open=True, high_open=True
    )
    return _Branch(float(t0), float(g), float(tip), prof)


def _end_deflection(
    forcing: float, theta0: float, gamma: float, tip: float, prof: FloatArray, root: str
) -> float:
    """x1 of the state ``root`` at the end of the range."""
    lam, t0, g, tp = _check(forcing, theta0, gamma, tip)
    st = _solve_pillar_checked(lam, t0, g, tp, prof, 1e-12, LADDER, root)
    return float(st.tip_deflection)


@_quiet
def continue_pillar(
    forcing_max: float,
    theta0: float = 0.0,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: float = 0.5,
    tip_load: float = 0.0,
    num: int = 200,
) -> PillarBranch:
    """The branch of pillar states from rest (Lambda = 0) to ``forcing_max``, with its folds.

    Parameters
    ----------
    forcing_max : float
        The end of the range of Lambda [-], finite and non-zero (negative: flow towards -x).
    theta0, profile, height_ratio, gamma, tip_load
        As in :func:`hairbed.solve_pillar`, scalars.
    num : int, optional
        Points of the grid in x1, in [16, 10^4]. Default 200. For a pillar leaning onto
        the wall (theta0 < ``ATLAS_THETA0`` = -1.5 for its flow) the grid's states are
        joined by those of the branch's atlas (issue 33: the upper fold of its window lies
        within ~1e-6 of rest in x1, below the grid's first point), and its folds are the
        atlas's.

    Returns
    -------
    PillarBranch
    """
    end = check_number(forcing_max, "forcing_max")
    if end == 0.0:
        raise ValueError("forcing_max must be non-zero (the end of the range of Lambda)")
    count = check_int(num, "num", 16, 10**4)
    return _continue(end, _branch(theta0, profile, height_ratio, gamma, tip_load), count, "low")


def _continue(end: float, branch: _Branch, count: int, root: str) -> PillarBranch:
    """:func:`continue_pillar` of checked inputs, to the state ``root`` at ``end``: "low"
    ends before a window there (the state a slow ramp from rest reaches), "high" beyond it
    (so every state of Lambda up to ``end`` lies on the branch)."""
    t0 = branch.theta0
    x_end = _end_deflection(end, t0, branch.gamma, branch.tip_load, branch.prof, root)
    x_rest = math.sin(t0)
    if not math.isfinite(x_end):
        nan = np.full(0, np.nan)
        return PillarBranch(nan, nan, nan, np.zeros(0, dtype=np.bool_), np.zeros((0, 2)), -7)
    # a uniform grid in x1 from rest to the end of the range
    x = x_rest + (x_end - x_rest) * np.linspace(0.0, 1.0, count)
    st = branch.states(x)
    lam = np.asarray(st.forcing, dtype=np.float64)
    # stable where dLambda/dx1 > 0: the sign of the states' exact dx1/dLambda (implicit
    # differentiation; NaN at a fold), not a difference quotient of the grid, which
    # vanishes where the grid's x1 or Lambda round to the same values (a tiny forcing)
    with np.errstate(invalid="ignore"):
        stable = np.asarray(st.tip_deflection_slope, dtype=np.float64) > 0.0
    _, turns, kind = _grid_turns(lam[None, :])

    def value(xs: FloatArray) -> FloatArray:
        return kind * np.asarray(branch.states(xs).forcing, dtype=np.float64)

    folds = np.zeros((0, 2))
    if turns.size:  # every fold at once, to 1e-12 in x1
        xf, best = _golden_max(value, x[turns], x[turns + 2], 1e-12)
        folds = np.stack([kind * best, xf], axis=1)
    status = 0 if np.all(np.asarray(st.status) >= 0) else -7
    height = np.asarray(st.tip_height, dtype=np.float64)
    sign = math.copysign(1.0, end)
    if sign * t0 < ATLAS_THETA0 and count > 1:
        # leaning onto the wall: the window's upper fold lies within ~1e-6 of rest in x1,
        # below the first point of the grid, where the inverse fixes Lambda only to its
        # rounding; the atlas's states there (forward solves) and its refined folds
        xa, la, ha, fa = _atlas_branch(
            (sign * t0, branch.gamma, sign * branch.tip_load),
            branch.prof,
            1e-12,
            LADDER,
            abs(end),
        )
        # the grid's states (where the inverse arrived) and the atlas's on the way to the
        # end state, in the order of x1; stable where Lambda rises along the branch (for
        # the atlas's states, between their neighbours)
        on = (xa > sign * x_rest) & (xa < sign * x_end)
        good = np.isfinite(lam)
        xs = np.concatenate([x[good], sign * xa[on]])
        order = np.argsort(sign * xs, kind="stable")
        ls = np.concatenate([lam[good], sign * la[on]])[order]
        rise = np.gradient(sign * ls, sign * xs[order]) > 0.0 if xs.size > 1 else ls > 0
        mine = np.concatenate([stable[good], np.zeros(int(on.sum()), dtype=np.bool_)])[order]
        from_grid = np.concatenate([np.ones(int(good.sum()), bool), np.zeros(int(on.sum()), bool)])
        stable = np.where(from_grid[order], mine, rise)
        height = np.concatenate([height[good], ha[on]])[order]
        x, lam = xs[order], ls
        status = 0 if bool(good[-1]) else -7  # the end state itself came back
        folds = np.stack([sign * fa[:, 0], sign * fa[:, 1]], axis=1)
        folds = folds[sign * folds[:, 1] <= sign * x_end]  # on the way to the end state
    return PillarBranch(
        tip_deflection=x,
        forcing=lam,
        tip_height=height,
        stable=stable,
        folds=folds,
        status=status,
    )


@_quiet
def solve_pillar_all(
    forcing: float,
    theta0: float = 0.0,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: float = 0.5,
    tip_load: float = 0.0,
    num: int = 200,
) -> list[PillarState]:
    """Every coexisting pillar state at one forcing, sorted by tip deflection.

    The roots of Lambda(x1) = ``forcing`` on the branch of :func:`continue_pillar` (up to
    twice the forcing), each refined by bisection on x1 to the rounding of Lambda, then the
    state at that x1 (the inverse problem); its ``forcing`` is within rounding of the one
    asked for. One state outside a snap-through window, three inside (theory.md §12).

    Parameters
    ----------
    forcing : float
        Lambda [-], finite and non-zero.
    theta0, profile, height_ratio, gamma, tip_load, num
        As in :func:`continue_pillar`.

    Returns
    -------
    list of PillarState
        Each with ``stable`` in the branch's sense (:class:`PillarBranch`): in a window the
        first and last are stable, the middle one is not. Never empty: where the branch
        reaches no state (a forcing near the float range's end) the one state of
        :func:`hairbed.solve_pillar`, whose ``status`` (-7) and ``message`` say so.

    Raises
    ------
    ValueError
        For a forcing of 0 (the straight pillar: :func:`hairbed.solve_pillar`) and inputs
        outside their ranges.
    """
    lam_t = check_number(forcing, "forcing")
    if lam_t == 0.0:
        raise ValueError(
            "forcing must be non-zero for solve_pillar_all (at Lambda = 0 the one state is "
            "the straight pillar: hairbed.solve_pillar(0.0, theta0))"
        )
    branch = _branch(theta0, profile, height_ratio, gamma, tip_load)
    count = check_int(num, "num", 16, 10**4)
    if not np.any(branch.prof != 0.0):
        # no drag at all (U = 0): the one state of the tip load alone, at any forcing
        return [replace(_one_state(lam_t, branch), stable=True, n_states=1)]
    if math.copysign(1.0, lam_t) * branch.theta0 < ATLAS_THETA0:
        return _wall_states(lam_t, branch)
    # to the last state at twice the forcing: past a window there, whose far states (and
    # its lower fold) lie beyond the state a ramp from rest reaches
    br = _continue(2.0 * lam_t if abs(lam_t) < 1e300 else lam_t, branch, count, "high")
    # the folds among the grid's points (x1 monotone along the branch): else a forcing
    # between the grid's extreme Lambda and the fold's misses two states of the window
    xs = np.concatenate([br.tip_deflection, br.folds[:, 1]])
    order = np.argsort(xs if lam_t > 0.0 else -xs, kind="stable")
    xs = xs[order]
    g = np.concatenate([br.forcing, br.folds[:, 0]])[order] - lam_t
    idx = np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] <= 0.0))
    idx = idx[~np.isin(idx - 1, idx) | (g[idx] != 0.0)]
    roots = []
    rising = []
    for i in idx:
        rising.append(
            # dLambda/dx1 > 0 for either sign of the forcing (the mirror flips both)
            bool((g[i + 1] - g[i]) * (xs[i + 1] - xs[i]) > 0)
        )
        lo, hi = float(xs[i]), float(xs[i + 1])
        glo = float(g[i])
        for _ in range(_MAX_STEPS):
            if abs(hi - lo) <= 4e-16 * max(1.0, abs(hi)):
                break
            mid = 0.5 * (lo + hi)
            gm = branch.forcing(mid) - lam_t
            if gm == 0.0:
                lo = hi = mid
                break
            if (gm > 0) == (glo > 0):
                lo, glo = mid, gm
            else:
                hi = mid
        roots.append(0.5 * (lo + hi))
    if not roots:
        # no crossing on the branch (a forcing beyond its reach, ~1e300): the single-state
        # solver's answer, whose status says what came of it (-7), not an empty list
        return [_one_state(lam_t, branch)]
    order = np.argsort(roots)
    n = len(roots)
    return [replace(branch.states(roots[k]), stable=rising[k], n_states=n) for k in order]


def _wall_states(lam: float, branch: _Branch) -> list[PillarState]:
    """Every state of a pillar leaning onto the wall (theta0 < ``ATLAS_THETA0`` for its flow):
    the roots "low", "mid" and "high" of :func:`hairbed.solve_pillar`, read off the branch of
    its atlas (marched in Lambda and through the window in x1, issue 33), where the inverse
    on a grid in x1 cannot start from rest. Each with ``stable`` from the sign of its
    dx1/dLambda (positive on a rising part of the branch, for either sign of the forcing:
    the mirror x -> -x changes the sign of both)."""
    lf, t0, g, tip = _check(lam, branch.theta0, branch.gamma, branch.tip_load)
    low = _solve_pillar_checked(lf, t0, g, tip, branch.prof, 1e-12, LADDER, "low")
    n = int(low.n_states)
    roots = ("low",) if n <= 1 else ("low", "high") if n == 2 else ("low", "mid", "high")
    states = [low] + [
        _solve_pillar_checked(lf, t0, g, tip, branch.prof, 1e-12, LADDER, r) for r in roots[1:]
    ]
    return [
        replace(st, stable=bool(st.tip_deflection_slope > 0.0) if st.status >= 0 else None)
        for st in states
    ]


def _one_state(lam: float, branch: _Branch) -> PillarState:
    """:func:`hairbed.solve_pillar` of a checked forcing and branch (root "low")."""
    lf, t0, g, tip = _check(lam, branch.theta0, branch.gamma, branch.tip_load)
    return _solve_pillar_checked(lf, t0, g, tip, branch.prof, 1e-12, LADDER, "low")
