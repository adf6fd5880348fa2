"""Quasi-static sweeps of the forcing: following one state, jumps at folds, hysteresis.

When the flow is changed slowly the hair stays on the static state it is in, moving
continuously along the physical branch, as long as that state exists. Where the forcing passes a
fold (:func:`hairbed.branches.folds`) the state it was following disappears and the hair snaps
to another stable state. Which states are stable is a question of dynamics
(:mod:`hairbed.stability`): on the physical branch these are exactly the pieces where omega^2
increases with xi, the pieces between folds where it decreases being unstable. A sweep therefore
only ever visits the increasing pieces, and after a jump lands on the nearest increasing piece in
the direction of travel.

So a ramp of omega^2 up from rest follows the lowest-xi root up to the upper fold and then jumps
to the high state; the ramp back down follows the highest root down to the lower fold and jumps
back (theory.md §5): a hysteresis loop.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._bracketing import find_root
from ._core.solution import Solution
from ._core.solver import _from_parameter, _solve_checked, fold_parameters
from ._core.validation import _first_index, as_float_array, check_choice, check_scalar_inputs
from ._specs import parse_spec
from ._warnings import renamed_parameters

__all__ = ["QuasistaticSweep", "sweep", "sweep_with_jumps"]

_SMALLEST = float(np.finfo(np.float64).smallest_subnormal)


@dataclass(frozen=True)
class QuasistaticSweep:
    """A quasi-static sweep of the forcing (returned by :func:`sweep_with_jumps`).

    Attributes
    ----------
    solution : Solution
        The state at every point of the path, shape (len(omega2_path),), on the physical
        branch. Its ``omega2`` equals the path to rounding; its ``n_roots`` is the number of
        physical states that coexist at each point (3 inside a bistable window), as
        :func:`hairbed.solve` counts them.
    jumps : ndarray of int
        Indices i at which the state jumped between i - 1 and i (a fold was passed),
        increasing.
    direction : ndarray of int
        Direction of the ramp at each point: +1 where omega^2 rose from the previous point, -1
        where it fell, 0 where it stayed (and at the first point).
    stable : ndarray of bool
        Whether each state followed is stable. A quasi-static path only visits the pieces of
        the physical branch where omega^2 increases with xi, which are exactly the stable
        ones (module docstring; :func:`hairbed.stability.is_stable` agrees): True
        throughout, except NaN states.
    jumped : ndarray of bool
        True at the indices of ``jumps``.
    """

    solution: Solution
    jumps: NDArray[np.intp]
    direction: NDArray[np.int64]
    stable: NDArray[np.bool_]
    jumped: NDArray[np.bool_]


def _omega2(t: NDArray[np.float64], eps: float, theta0: float) -> NDArray[np.float64]:
    return np.asarray(_from_parameter(t, eps, theta0).omega2, dtype=np.float64)


def _stable_pieces(
    eps: float, theta0: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The increasing pieces of omega^2(t): their t-bounds and omega^2-ranges.

    Returns (t_lo, t_hi, w_lo, w_hi) for each increasing piece, ordered along the branch;
    infinite bounds are kept infinite (omega^2 -> 0 as t -> -inf and -> inf as t -> inf).
    """
    tf = fold_parameters(eps, theta0)
    bounds = np.concatenate(([-np.inf], tf, [np.inf]))
    wf = _omega2(tf, eps, theta0) if tf.size else np.empty(0)
    wb = np.concatenate(([0.0], wf, [np.inf]))
    # Pieces alternate increasing / decreasing, starting increasing at weak forcing.
    return bounds[0::2], bounds[1::2], wb[0::2], wb[1::2]


def _choose_pieces(
    path: NDArray[np.float64], w_lo: NDArray[np.float64], w_hi: NDArray[np.float64], root: str
) -> NDArray[np.intp]:
    """Index of the stable piece occupied at every point of the path."""
    inside = (path[:, None] >= w_lo) & (path[:, None] <= w_hi)
    piece = np.empty(path.size, dtype=np.intp)
    if path.size == 0:
        return piece
    cand = np.nonzero(inside[0])[0]
    current = int(cand[0] if root == "low" else cand[-1])
    for i, w in enumerate(path):
        if not inside[i, current]:
            cand = np.nonzero(inside[i])[0]
            # The state has run off the end of its piece: snap to the nearest stable piece
            # in the direction of travel (up after an upper fold, down after a lower one).
            current = int(
                cand[cand > current][0] if w > w_hi[current] else cand[cand < current][-1]
            )
        piece[i] = current
    return piece


def _log_omega2_residual(
    t: NDArray[np.float64], eps: float, theta0: float, log_target: NDArray[np.float64]
) -> NDArray[np.float64]:
    """ln omega^2(t) - ln(target), increasing on a stable piece [-] (finite where omega^2
    underflows)."""
    return np.log(np.maximum(_omega2(t, eps, theta0), _SMALLEST)) - log_target


@renamed_parameters(start="root")
def sweep_with_jumps(
    omega2_path: Any, eps: float, theta0: float = 0.0, *, root: str = "low"
) -> QuasistaticSweep:
    """Follow the physical state along a path of forcing; also say where it jumps.

    Parameters
    ----------
    omega2_path : array_like, 1-D, or str
        Successive values of the forcing omega^2 [-], >= 0, in the order applied; or a SPEC
        of them (:func:`hairbed.sweeps.parse_spec`, as ``hairbed sweep --omega2``): a
        comma list, ``start:stop:num[:log]``, or ``start:stop:num:updown`` for a ramp up to
        ``stop`` and back down (2 num - 1 points, the turning point once), a hysteresis loop.
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).
    root : {"low", "high"}
        Which state the hair is in at the first point when several coexist there: "low"
        (smallest xi: coming from rest) or "high" (largest xi: coming from strong flow), as
        :func:`hairbed.solve`'s ``root``. ``start`` is its deprecated old name.

    Returns
    -------
    QuasistaticSweep
        ``solution``, the state at every point of the path, and ``jumps``, the indices where
        a fold was passed.

    Examples
    --------
    >>> up_down = np.concatenate([np.linspace(0.8, 1.6, 9), np.linspace(1.6, 0.8, 9)])
    >>> run = sweep_with_jumps(up_down, 0.9, -1.5)
    >>> run.jumps.tolist()
    [7, 16]
    >>> sweep_with_jumps("0.8:1.6:9:updown", 0.9, -1.5).jumps.tolist()
    [7, 15]
    """
    if isinstance(omega2_path, str):
        omega2_path = parse_spec(omega2_path, "omega2_path", path=True)
    path = as_float_array(omega2_path, "omega2_path")
    if path.ndim != 1:
        raise ValueError(f"omega2_path must be one-dimensional, got shape {path.shape}")
    bad = path < 0.0
    if np.any(bad):
        raise ValueError(
            f"omega2_path must lie in [0, inf), got {float(path[bad][0])!r}{_first_index(bad)}"
        )
    _, eps, theta0 = check_scalar_inputs(eps=eps, theta0=theta0, given=("eps", "theta0"))
    root = check_choice(root, "root", ("low", "high"))

    t_lo, t_hi, w_lo, w_hi = _stable_pieces(eps, theta0)
    piece = _choose_pieces(path, w_lo, w_hi, root)

    # A bracket in t for every point: its piece's bounds, the infinite ends replaced by a
    # starting interval next to the finite one that the search widens (omega^2 is monotone
    # increasing in t on each piece, so the root is unique and the search cannot fail).
    positive = np.flatnonzero(path > 0.0)
    a, b = t_lo[piece[positive]], t_hi[piece[positive]]
    lower = np.where(np.isfinite(a), a, np.where(np.isfinite(b), b - 1.0, -1.0))
    upper = np.where(np.isfinite(b), b, lower + 1.0)
    t = np.full(path.shape, -np.inf)  # omega^2 = 0: the undeformed hair, xi = sin(theta0)
    if positive.size:
        t[positive] = find_root(
            _log_omega2_residual,
            lower,
            upper,
            args=(eps, theta0, np.log(path[positive])),
            grow=True,
            xmin=a,
            xmax=b,
            what="the branch parameter along a sweep",
        ).x
    jumps = np.nonzero(piece[1:] != piece[:-1])[0] + 1
    # from_parameter knows the state, not how many others share its omega^2: count them as
    # solve does (the branch's roots at each omega^2 of the path)
    n_roots = np.asarray(_solve_checked(path, eps, theta0).n_roots, dtype=np.int64).reshape(
        path.shape
    )
    sol = replace(_from_parameter(t, eps, theta0), n_roots=n_roots)
    direction = np.zeros(path.shape, dtype=np.int64)
    direction[1:] = np.sign(np.diff(path)).astype(np.int64)
    jumped = np.zeros(path.shape, dtype=bool)
    jumped[jumps] = True
    stable = np.asarray(sol.status) == 0
    return QuasistaticSweep(sol, jumps.astype(np.intp), direction, stable, jumped)


@renamed_parameters(start="root")
def sweep(omega2_path: Any, eps: float, theta0: float = 0.0, *, root: str = "low") -> Solution:
    """Follow the physical state continuously along a path of forcing.

    The state moves continuously with omega^2 and jumps only where the state it is following
    disappears at a fold: a ramp up then down traces the hysteresis loop when theta0 < 0 and
    eps > :func:`hairbed.branches.cusp` (theory.md §5). Use :func:`sweep_with_jumps` to get
    the jump indices too.

    Parameters
    ----------
    omega2_path : array_like, 1-D, or str
        Successive values of the forcing omega^2 [-], >= 0, or their SPEC (as
        :func:`sweep_with_jumps`: ``"0.8:1.6:200:updown"`` is a loop up and back down).
    eps : float
        Confinement L/H [-], in [0, 1).
    theta0 : float
        Base angle [rad], in (-pi/2, pi/2).
    root : {"low", "high"}
        State at the first point when several coexist there (``start`` is its deprecated old
        name).

    Returns
    -------
    Solution
        The state at every point of the path, shape (len(omega2_path),); its ``n_roots`` is
        the number of physical states at each omega^2 (3 inside a bistable window).

    Examples
    --------
    >>> s = sweep([1.2, 1.6, 1.2], 0.9, -1.5)
    >>> bool(s.xi[2] > s.xi[0])
    True
    """
    return sweep_with_jumps(omega2_path, eps, theta0, root=root).solution
