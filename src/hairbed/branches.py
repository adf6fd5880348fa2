"""Branches of solutions as exact parametric curves, and the folds of the physical branch.

Every branch (``sign``, ``n``) of the boundary-value problem is an explicit curve in the tip
parameter xi (theory.md §2, eq. (34)): omega^2 is an *output* of xi, so no continuation
is needed. We parametrise by the real number t of :func:`hairbed.from_parameter`,

    xi - sin(theta0) = (1 - sin theta0) expit(t),    1 - xi = (1 - sin theta0) expit(-t),

which resolves both weak forcing (t -> -inf) and strong forcing (t -> +inf).

For a hair leaning into the flow (theta0 < 0) in a tight channel (eps near 1) omega^2(t) on the
physical branch is not monotone (theory.md §5): it rises to a local maximum (the *upper
fold*, where the low state disappears) and falls to a local minimum (the *lower fold*, where the
high state disappears) before rising again. Between the two fold values of omega^2 three
physical states coexist. :func:`folds` locates the folds as the zeros of d ln(omega^2)/dt and
:func:`cusp` the confinement eps_c(theta0) at which the two folds are born.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._bracketing import find_minimum, find_root
from ._core.solution import Solution
from ._core.solver import _fold_table, _from_parameter, _log_slope, fold_parameters
from ._core.validation import (
    _first_index,
    as_float_array,
    broadcast_named,
    check_branch,
    check_inputs,
    check_int,
    check_scalar_inputs,
    float_or_array,
)

__all__ = [
    "BistableWindow",
    "Fold",
    "Folds",
    "LabelledState",
    "bistable_window",
    "curve",
    "cusp",
    "folds",
    "label_states",
    "log_slope",
]

#: Default range of the parameter t for curves: xi - sin(theta0) ~ 3e-7 (omega^2 ~ 1e-6) at the
#: weak end, 1 - xi ~ 1e-13 (omega^2 of a few hundred) at the strong end.
T_SPAN = (-15.0, 30.0)
#: The range of t of :func:`log_slope`: omega^2 ~ e^t underflows below -700.
_T_MAX = 700.0
#: The most points :func:`curve` returns.
MAX_POINTS = 10_000_000
#: Where folds are searched. Folds measured here lie in t in [-5, 1]; the window is wide on both
#: sides but stops before weak forcing, where omega^2 ~ e^t is tiny and 1 - eps h1 may cancel.
_T_SEARCH = (-20.0, 12.0)
_T_STEP = 0.02
_T_GRID = np.arange(_T_SEARCH[0], _T_SEARCH[1] + 0.5 * _T_STEP, _T_STEP)


@dataclass(frozen=True)
class Fold:
    """One fold point of the physical branch.

    Attributes
    ----------
    omega2 : float
        Forcing omega^2 [-] at the fold.
    xi : float
        Tip parameter xi = sin(theta1) [-] at the fold.
    t : float
        The curve parameter t of :func:`hairbed.from_parameter` [-] at the fold.
    """

    omega2: float
    xi: float
    t: float


@dataclass(frozen=True)
class Folds:
    """Fold points of the physical branch, in increasing omega^2: the lower fold first.

    The *lower* fold is the local minimum of omega^2 along the branch (where, coming down, the
    high state disappears), the *upper* fold the local maximum (where, going up, the low state
    disappears); three physical states coexist for ``lower.omega2 < omega^2 < upper.omega2``.
    Along the branch (increasing xi) the upper fold comes first: the *upper* fold (larger
    omega^2) has the *smaller xi* of the two, since omega^2 first rises to it, then falls.

    Attributes
    ----------
    omega2 : ndarray (k,)
        Forcing omega^2 [-] at each fold, increasing; k = 0 (monotone branch) or 2.
    xi : ndarray (k,)
        Tip parameter xi = sin(theta1) [-] at each fold.
    t : ndarray (k,)
        The curve parameter t of :func:`hairbed.from_parameter` [-] at each fold.
    """

    omega2: NDArray[np.float64]
    xi: NDArray[np.float64]
    t: NDArray[np.float64]

    def _fold(self, i: int) -> Fold | None:
        if self.omega2.size < 2:
            return None
        return Fold(float(self.omega2[i]), float(self.xi[i]), float(self.t[i]))

    @property
    def lower(self) -> Fold | None:
        """The lower fold (smallest omega^2), None when the branch is monotone."""
        return self._fold(0)

    @property
    def upper(self) -> Fold | None:
        """The upper fold (largest omega^2), None when the branch is monotone."""
        return self._fold(-1)


@dataclass(frozen=True)
class BistableWindow:
    """The range of forcing in which three physical states coexist.

    For scalar (eps, theta0) its fields are floats; for arrays, arrays of their broadcast
    shape (:func:`bistable_window`).

    Attributes
    ----------
    lower, upper : float or ndarray
        omega^2 [-] at the lower and the upper fold (lower < upper); NaN where the branch is
        monotone.
    """

    lower: float | NDArray[np.float64]
    upper: float | NDArray[np.float64]

    @property
    def exists(self) -> Any:
        """True where the branch folds (three states for lower < omega^2 < upper): a bool, or
        a bool array for arrays."""
        inside = np.less(self.lower, self.upper)
        return bool(inside) if np.ndim(inside) == 0 else inside

    @property
    def width(self) -> float | NDArray[np.float64]:
        """upper - lower [-], the width of the window in omega^2; NaN where there is none."""
        return float_or_array(np.subtract(self.upper, self.lower))

    @property
    def n_states(self) -> Any:
        """How many physical states coexist inside the window: 3 where it exists, else 1
        (an int, or an int array for arrays)."""
        n = np.where(self.exists, 3, 1).astype(np.int64)
        return int(n) if n.ndim == 0 else n


def _scalar_params(eps: Any, theta0: Any) -> tuple[float, float]:
    _, e, th = check_scalar_inputs(eps=eps, theta0=theta0, given=("eps", "theta0"))
    return e, th


def log_slope(t: Any, eps: float, theta0: float = 0.0) -> NDArray[np.float64]:
    """d ln(omega^2) / dt along the physical branch [-] (zero exactly at a fold).

    The exact derivative of the closed form (the slope Newton's method uses in
    :func:`hairbed.solve`: dK/dm and dF/dphi, dF/dm of DLMF 19.4), not a difference.

    Parameters
    ----------
    t : array_like
        Curve parameter of :func:`hairbed.from_parameter` [-], in [-700, 700].
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).
    """
    eps, theta0 = _scalar_params(eps, theta0)
    tt = as_float_array(t, "t")
    bad = np.abs(tt) > _T_MAX
    if np.any(bad):
        raise ValueError(
            f"t must lie in [-{_T_MAX:g}, {_T_MAX:g}] (beyond, omega^2 under- or overflows), got "
            f"{float(tt[bad].flat[0])!r}{_first_index(bad)}"
        )
    return _log_slope(tt, eps, theta0)


def curve(
    eps: float,
    theta0: float = 0.0,
    sign: int = 1,
    n: int = 0,
    num: int = 1001,
    t_span: tuple[float, float] = T_SPAN,
) -> Solution:
    """The exact parametric curve of one branch, from weak to strong forcing.

    Parameters
    ----------
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).
    sign, n : int
        Branch label: sign of theta'(0) and number of interior turning points (theory.md
        §2). The default is the physical branch.
    num : int
        Number of points, evenly spaced in t, in [2, ``MAX_POINTS`` = 10^7].
    t_span : (float, float)
        Range of t. The default covers omega^2 from about 1e-6 to a few hundred on the
        physical branch.

    Returns
    -------
    Solution
        States along the branch, shape (num,), ordered by increasing xi. Their ``omega2`` is the
        forcing that holds each state (eq. (34)); on the physical branch it is not monotone
        when folds exist (:func:`folds`).

    Examples
    --------
    >>> c = curve(0.9, -1.5, num=5)
    >>> bool(np.all(np.diff(c.xi) > 0))
    True
    """
    eps, theta0 = _scalar_params(eps, theta0)
    sign, n = check_branch(sign, n)
    num = check_int(num, "num", 2, MAX_POINTS)
    span = as_float_array(t_span, "t_span")
    if span.shape != (2,) or not span[0] < span[1]:
        raise ValueError(
            "t_span must be two finite increasing numbers (t_min, t_max), got "
            + (f"shape {span.shape}" if span.shape != (2,) else f"{span.tolist()!r}")
        )
    t = np.linspace(float(span[0]), float(span[1]), num)
    return _from_parameter(t, eps, theta0, sign, n)  # checked above


def folds(eps: float, theta0: float = 0.0) -> Folds:
    """Fold points of the physical branch (sign = +1, n = 0), in order along it.

    A fold is where d omega^2 / d xi = 0: a state appears or disappears as the forcing varies.
    They come from the compiled fold search that :func:`hairbed.solve` uses to count and
    bracket its roots (``hairbed._core.solver.fold_parameters``, the one fold finder of the
    package): a scan of the branch for sign changes of the slope, with a check of every local
    minimum of the slope so that two folds closer than the scan's step, near the cusp, are not
    missed, refined to rounding in t.

    Parameters
    ----------
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).

    Returns
    -------
    Folds
        Arrays (omega2, xi, t) sorted by increasing omega^2, and the two folds by name
        (``lower``, ``upper``); empty (and None) when omega^2 is monotone on the physical
        branch (always for theta0 >= 0, and for eps below :func:`cusp`). Three states
        coexist for ``lower.omega2 < omega^2 < upper.omega2``. "Upper" and "lower" rank the
        folds by omega^2: the upper fold has the smaller xi (it comes first along the branch).

    Examples
    --------
    >>> f = folds(0.9, -1.5)
    >>> f.omega2.tolist()
    [0.95766, 1.4859]
    >>> f.upper.omega2, f.upper.xi > f.lower.xi
    (1.4859, False)
    >>> folds(0.5, 0.0).lower is None
    True
    """
    eps, theta0 = _scalar_params(eps, theta0)
    ts = fold_parameters(eps, theta0)
    if ts.size == 0:
        empty = np.empty(0, dtype=np.float64)
        return Folds(empty, empty.copy(), empty.copy())
    sol = _from_parameter(ts, eps, theta0)
    omega2 = np.asarray(sol.omega2, dtype=np.float64).reshape(-1)
    order = np.argsort(omega2, kind="stable")
    xi = np.asarray(sol.xi, dtype=np.float64).reshape(-1)
    return Folds(omega2[order], xi[order], np.asarray(ts, dtype=np.float64)[order])


def bistable_window(eps: Any, theta0: Any = 0.0) -> BistableWindow:
    """The range of omega^2 in which three physical states coexist [-], exactly.

    The folds come from the compiled fold search (:func:`folds`, the one fold finder of the
    package) at every (eps, theta0) pair in one call, so a map of the window over a grid of
    both is exact at every cell, however narrow the window is near the cusp, where a grid of
    omega^2 misses it (docs: "Mapping the bistable region").

    Parameters
    ----------
    eps : array_like
        Confinement L/H [-], in [0, 1).
    theta0 : array_like
        Base angle [rad], in (-pi/2, pi/2); broadcast with ``eps``.

    Returns
    -------
    BistableWindow
        ``lower`` and ``upper``: omega^2 at the lower and upper folds, NaN where the
        branch is monotone (``exists`` is then False), ``width`` and ``n_states``. Floats
        for scalar inputs, arrays of the broadcast shape otherwise.

    Raises
    ------
    ValueError
        Naming the parameter, its range and the first offending index, or the shapes that do
        not broadcast.

    Examples
    --------
    >>> w = bistable_window(0.95, -1.0)
    >>> w.lower, w.upper
    (0.29696, 0.31966)
    >>> bistable_window(0.5, 0.0).exists
    False
    >>> bistable_window([0.5, 0.95], -1.0).exists.tolist()
    [False, True]
    """
    e = check_inputs(0.0, eps, 0.0)[1]
    th = check_inputs(0.0, 0.0, theta0)[2]
    e, th = broadcast_named(("eps", e), ("theta0", th))
    ef, tf = e.reshape(-1), th.reshape(-1)
    t, counts = _fold_table(ef, tf)
    lower = np.full(ef.shape, np.nan)
    upper = np.full(ef.shape, np.nan)
    folded = np.flatnonzero(counts >= 2)  # the physical branch has 0 or 2 folds
    if folded.size:
        pair = t[folded, :2]
        w = np.asarray(
            _from_parameter(pair, ef[folded, None], tf[folded, None]).omega2, dtype=np.float64
        ).reshape(pair.shape)
        lower[folded] = w.min(axis=1)
        upper[folded] = w.max(axis=1)
    return BistableWindow(
        float_or_array(lower.reshape(e.shape)), float_or_array(upper.reshape(e.shape))
    )


def _min_slope(eps: NDArray[np.float64], theta0: NDArray[np.float64]) -> NDArray[np.float64]:
    """Smallest d ln(omega^2)/dt over the search window (negative iff folds exist), for
    1-D arrays eps and theta0: the grid's minimum, refined by a bracketed minimisation."""
    g = _log_slope(_T_GRID, eps[:, None], theta0[:, None])
    k = np.argmin(g, axis=1)
    out = g[np.arange(k.size), k]
    inner = np.flatnonzero((k > 0) & (k < _T_GRID.size - 1))
    if inner.size:
        ki = k[inner]
        out[inner] = find_minimum(
            _log_slope,
            _T_GRID[ki - 1],
            _T_GRID[ki],
            _T_GRID[ki + 1],
            args=(eps[inner], theta0[inner]),
            xatol=1e-10,
            what="the smallest slope of ln(omega^2) along the physical branch",
        ).f_x
    return out


def cusp(theta0: Any) -> float | NDArray[np.float64]:
    """The confinement eps_c(theta0) above which the physical branch has folds [-].

    At eps_c the two folds are born together: d omega^2/dt and d^2 omega^2/dt^2 vanish at once.
    We solve min_t d ln(omega^2)/dt = 0 for eps by a bracketed root search (the minimum over
    t on a grid of step 0.02 in [-20, 12], refined by a bracketed minimisation), to about
    1e-12 in eps, for all base angles at once (``hairbed._bracketing``, on
    :mod:`scipy.optimize.elementwise`).

    Parameters
    ----------
    theta0 : array_like
        Base angle [rad], in (-pi/2, pi/2).

    Returns
    -------
    float or ndarray
        eps_c, in (0, 1]. The value 1.0 means no folds for any admissible eps < 1: this is
        the case for theta0 >= 0 (the physical branch is monotone, theory.md §5) and,
        numerically, for base angles so close to 0- that eps_c is within 1e-9 of 1
        (eps_c -> 1 as theta0 -> 0-).

    Examples
    --------
    >>> round(float(cusp(-1.0)), 2)
    0.91
    >>> float(cusp(0.2))
    1.0
    """
    th = as_float_array(theta0, "theta0")
    check_inputs(0.0, 0.0, th)
    out = np.ones(th.shape)
    flat = out.reshape(-1)  # a view of out
    lean = np.flatnonzero(th.ravel() < 0.0)
    if lean.size:
        thl = th.ravel()[lean]
        folding = _min_slope(np.full(thl.shape, _EPS_TOP), thl) < 0.0
        if np.any(folding):
            # At eps = 0, omega^2 = omega_eps^2 is monotone: the slope is positive everywhere.
            flat[lean[folding]] = find_root(
                _min_slope,
                0.0,
                _EPS_TOP,
                args=(thl[folding],),
                xatol=1e-12,
                xrtol=1e-12,
                what="the cusp confinement eps_c",
            ).x
    return float_or_array(out)


_EPS_TOP = 1.0 - 1e-9


# -- the coexisting states of a branch, named and classified ---------------------------------

#: Names of the states of one branch in increasing xi, by how many coexist: the ``root=`` of
#: :func:`hairbed.solve` that returns each (two exactly at a fold).
ROOT_NAMES: dict[int, tuple[str, ...]] = {
    1: ("low",),
    2: ("low", "high"),
    3: ("low", "mid", "high"),
}


@dataclass(frozen=True)
class LabelledState:
    """One static state among those that coexist on its branch, named and classified.

    Attributes
    ----------
    solution : Solution
        The state (scalar).
    root : str
        "low", "mid" or "high": its place in increasing xi among the ``count`` states of its
        branch (sign, n) in the list labelled, the ``root=`` of :func:`hairbed.solve` that
        returns it ("root 4", ... past three).
    count : int
        How many states of its branch were labelled together (1: the only one).
    stable : bool or None
        Linear stability (:func:`hairbed.stability.linear_stability`); None where the
        classification failed (``status``).
    growth_rate : float
        Largest real part of the eigenvalues [1 / bending relaxation time]; NaN where not
        classified.
    status : int
        ``Stability.status`` of the classification: 0 classified.
    """

    solution: Solution
    root: str
    count: int
    stable: bool | None
    growth_rate: float
    status: int


def label_states(solutions: Sequence[Solution], num: int | None = None) -> list[LabelledState]:
    """Name the coexisting states low/mid/high within their branch and classify each.

    The states of one branch (sign, n) must stand together, in increasing xi, as
    :func:`hairbed.solve_all` returns them or as ``[solve(..., root=r) for r in ("low",
    "mid", "high")]``; each run of equal (sign, n) is one branch. Each state is classified by
    the leading eigenvalue of the linearised relaxation dynamics,
    ``linear_stability(state, num, k=1)``.

    Parameters
    ----------
    solutions : sequence of Solution
        Scalar states, grouped by branch.
    num : int, optional
        Segments of the stability discretisation, in [2, 4000]. Default 100 on the
        physical branch (n = 0) and 200 on twirling ones, whose profiles turn. The leading
        eigenvalue converges as 1/num^2; near a fold, where it crosses zero, no num is
        reliable.

    Returns
    -------
    list of LabelledState
        In the order given.

    Examples
    --------
    >>> import hairbed
    >>> states = [hairbed.solve(1.2, 0.9, -1.5, root=r) for r in ("low", "mid", "high")]
    >>> [(s.root, s.count, s.stable) for s in label_states(states)]
    [('low', 3, True), ('mid', 3, False), ('high', 3, True)]
    """
    from .stability import linear_stability  # scipy.integrate: only when states are labelled

    if not isinstance(solutions, Sequence) or isinstance(solutions, str):
        raise TypeError(
            "solutions must be a list of hairbed.Solution (from hairbed.solve, solve_all), "
            f"got {type(solutions).__name__}"
        )
    for i, sol in enumerate(solutions):
        if not isinstance(sol, Solution):
            raise TypeError(f"solutions[{i}] must be a hairbed.Solution, got {type(sol).__name__}")
        if np.ndim(sol.omega2) != 0:
            raise ValueError(f"solutions[{i}] must be a scalar Solution, got shape {sol.shape}")
    out: list[LabelledState] = []
    i = 0
    while i < len(solutions):
        j = i
        while j < len(solutions) and (solutions[j].sign, solutions[j].n) == (
            solutions[i].sign,
            solutions[i].n,
        ):
            j += 1
        names = ROOT_NAMES.get(j - i, tuple(f"root {k + 1}" for k in range(j - i)))
        for sol, name in zip(solutions[i:j], names):
            res = linear_stability(sol, (100 if sol.n == 0 else 200) if num is None else num, 1)
            status = int(np.asarray(res.status))
            ok = status == 0
            out.append(
                LabelledState(
                    solution=sol,
                    root=name,
                    count=j - i,
                    stable=bool(np.asarray(res.stable)) if ok else None,
                    growth_rate=float(np.asarray(res.growth_rate)) if ok else float("nan"),
                    status=status,
                )
            )
        i = j
    return out
