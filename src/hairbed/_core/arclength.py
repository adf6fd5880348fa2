"""Pseudo-arclength continuation of the loaded states along a drive parameter (issue 20, item 2).

The states of a drive at parameter p (omega2, pi or q) are the roots of the scalar
G(h; p) = z1(h; p) - h, z1 the tip height of the hair with the loads frozen at W(h), Pi(h)
(``loaded.solve_loaded_all``, theory.md §11). The branch is the curve G = 0 in the (p, h)
plane, followed here by pseudo-arclength continuation: a tangent step of length ds, then
Newton on [G = 0, t . (y - y_pred) = 0] (G's gradient by central differences of the
compiled fixed-load solves). A fold is where the tangent's p component changes sign; each is
refined by a golden-section search of the extremum of p(h) along the branch (p(h) by a
secant iteration on G(h, .) = 0). The step grows after easy corrections and shrinks after
hard or failed ones; at most ``max_steps`` steps, so every call ends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .loaded import _check_scalars, _gap, _quiet, solve_loaded
from .validation import check_choice, check_int, check_number, check_positive

__all__ = ["LoadedBranch", "continue_loaded"]

FloatArray = NDArray[np.float64]
_PARAMETERS = ("omega2", "pi", "q")
_FD_STEP = 1e-6
_GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)


@dataclass(frozen=True)
class LoadedBranch:
    """The branch of loaded states through a parameter range, with its folds.

    Attributes
    ----------
    parameter : str
        The parameter followed: "omega2", "pi" or "q".
    values : ndarray
        The parameter along the branch, in the order of the arclength [-].
    tip_height : ndarray
        h1 along the branch [L].
    stable : ndarray of bool
        dG/dh < 0 at each point (stable under a slow change of the tip height).
    folds : ndarray
        (k, 2): parameter and tip height of each fold (where the branch turns back in p).
    status : int
        0 the branch reached the end of the range; -2 the step limit; -3 the continuation
        stopped (a step below its minimum).
    nfev : int
        Fixed-load solves (evaluations of G).
    """

    parameter: str
    values: FloatArray
    tip_height: FloatArray
    stable: NDArray[np.bool_]
    folds: FloatArray
    status: int
    nfev: int


class _Curve:
    """G(h, p) and its gradient at scalar points, counting evaluations. ``gap`` (h, p) -> G
    replaces the dense bed's fixed-load solves (the porous bed's frozen-gap ones)."""

    def __init__(
        self, parameter: str, base: dict[str, float], tol: float, gap: Any = None
    ) -> None:
        self.parameter = parameter
        self.base = base
        self.tol = tol
        self.nfev = 0
        self.gap = gap

    def many(self, h: FloatArray, p: FloatArray) -> FloatArray:
        """G at the points (h_i, p_i): one batch of fixed-load solves."""
        h = np.atleast_1d(np.asarray(h, dtype=np.float64))
        p = np.broadcast_to(np.asarray(p, dtype=np.float64), h.shape)
        if self.gap is not None:
            self.nfev += h.size
            return np.asarray(self.gap(h, np.ascontiguousarray(p)), dtype=np.float64)
        code = 1 if "q" in self.base else 0
        load = self.base.get("q", self.base.get("pi", 0.0))
        w = p if self.parameter == "omega2" else self.base["omega2"]
        ld = load if self.parameter == "omega2" else p
        self.nfev += h.size
        return np.asarray(_gap(code, w, self.base["eps"], ld, self.base["theta0"], h, self.tol))

    def value(self, h: float, p: float) -> float:
        return float(self.many(np.array([h]), np.array([p]))[0])

    def gradient(self, h: float, p: float) -> tuple[float, float, float]:
        """(G, dG/dh, dG/dp) by central differences."""
        dh = _FD_STEP
        dp = _FD_STEP * max(1.0, abs(p))
        hs = np.array([h, h + dh, h - dh, h, h])
        ps = np.array([p, p, p, p + dp, p - dp])
        g = self.many(hs, ps)
        return g[0], (g[1] - g[2]) / (2 * dh), (g[3] - g[4]) / (2 * dp)

    def p_at(self, h: float, p: float) -> float:
        """The parameter of the branch at tip height h, by a secant iteration from p."""
        p1 = p * (1 + 1e-4) + 1e-8
        g0, g1 = self.value(h, p), self.value(h, p1)
        for _ in range(40):
            if not (math.isfinite(g0) and math.isfinite(g1)) or g1 == g0:
                break
            p2 = p1 - g1 * (p1 - p) / (g1 - g0)
            p, g0 = p1, g1
            p1, g1 = p2, self.value(h, p2)
            if abs(p1 - p) <= 1e-15 * max(1.0, abs(p1)):
                break
        return p1


@_quiet
def continue_loaded(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    pi: float | None = None,
    q: float | None = None,
    parameter: str | None = None,
    stop: float,
    ds: float = 0.02,
    max_steps: int = 2000,
    rtol: float = 1e-12,
) -> LoadedBranch:
    """Follow the branch of states from the inputs' state to ``stop`` along one parameter.

    Parameters
    ----------
    omega2, eps, theta0, pi, q : float
        The start, as in :func:`hairbed.solve_loaded` (its ``root="low"`` state).
    parameter : {"omega2", "pi", "q"}, optional
        The parameter to follow; default the drive's load (pi or q, omega2 if neither is given).
    stop : float
        The parameter value at which to end (on either side of the start).
    ds : float, optional
        The first step in the arclength of (p, h), > 0. Default 0.02.
    max_steps : int, optional
        At most this many steps, in [1, 10^6]. Default 2000.

    Returns
    -------
    LoadedBranch

    Examples
    --------
    >>> import hairbed
    >>> b = hairbed.continue_loaded(0.0, 0.9, -1.2, q=0.005, stop=0.5)
    >>> len(b.folds)
    2
    """
    drive, code, w, e, t0, ld = _check_scalars(omega2, eps, theta0, pi, q, "continue_loaded")
    default = "q" if q is not None else ("pi" if pi is not None else "omega2")
    name = check_choice(parameter if parameter is not None else default, "parameter", _PARAMETERS)
    if name != "omega2" and name != default:
        raise ValueError(
            f"parameter {name!r} needs the {'pressure' if name == 'pi' else 'flow'} drive"
        )
    step = check_positive(ds, "ds")
    limit = check_int(max_steps, "max_steps", 1, 10**6)
    tol = check_positive(rtol, "rtol")
    base = {"omega2": float(w), "eps": float(e), "theta0": float(t0)}
    if drive == "flow":
        base["q"] = float(ld)
    else:
        base["pi"] = float(ld)
    p0 = base["omega2"] if name == "omega2" else float(ld)
    end = check_number(stop, "stop")
    st = solve_loaded(**base, rtol=tol)  # type: ignore[arg-type]
    curve = _Curve(name, base, tol)
    if st.status != 0:
        return LoadedBranch(
            name, np.array([p0]), np.array([np.nan]), np.array([False]), np.empty((0, 2)), -3, 0
        )
    return _follow(curve, p0, float(st.tip_height), end, step, limit)


def _follow(
    curve: _Curve, p0: float, h0: float, end: float, step: float, limit: int
) -> LoadedBranch:
    """The pseudo-arclength continuation of :func:`continue_loaded` along ``curve`` from the
    state (p0, h0) to the parameter ``end``: the dense bed's, and the porous bed's valve
    (:func:`hairbed.valve.valve_states`) with the porous ``gap`` of :class:`_Curve`."""
    name = curve.parameter
    direction = 1.0 if end >= p0 else -1.0
    y = np.array([p0, h0])
    _, gh, gp = curve.gradient(y[1], y[0])
    tangent = np.array([-gh, gp])  # (dp, dh) orthogonal to (gp, gh)
    tangent /= np.linalg.norm(tangent)
    if tangent[0] * direction < 0:
        tangent = -tangent
    pts, stab = [y.copy()], [gh < 0]
    folds: list[tuple[float, float]] = []
    status = -2
    for _ in range(limit):
        pred = y + step * tangent
        z = pred.copy()
        ok = False
        iters = 0
        for it in range(8):
            iters = it
            g, gh, gp = curve.gradient(z[1], z[0])
            if not all(math.isfinite(v) for v in (g, gh, gp)):
                break
            mat = np.array([[gp, gh], [tangent[0], tangent[1]]])
            rhs = -np.array([g, tangent @ (z - pred)])
            try:
                dz = np.linalg.solve(mat, rhs)
            except np.linalg.LinAlgError:
                break
            z = z + dz
            if np.max(np.abs(dz)) <= 1e-13 * max(1.0, float(np.max(np.abs(z)))):
                ok = abs(curve.value(z[1], z[0])) <= 1e-12 and 0.0 < z[1] <= 1.0
                # a corrector that lands farther than a step from its prediction has left
                # for another piece of the curve (past a fold): retry with a shorter step
                ok = ok and float(np.linalg.norm(z - pred)) <= step
                break
        if not ok:
            step *= 0.5
            if step < 1e-9:
                status = -3
                break
            continue
        new_t = np.array([-gh, gp])
        new_t /= np.linalg.norm(new_t)
        if new_t @ tangent < 0:
            new_t = -new_t
        if new_t[0] * tangent[0] < 0:  # the branch turned back in p: a fold between
            before = pts[-2] if len(pts) > 1 else y
            folds.append(_refine_fold(curve, before, y, z, tangent[0] > 0))
        tangent = new_t
        y = z
        pts.append(y.copy())
        stab.append(gh < 0)
        if (y[0] - end) * direction >= 0:
            status = 0
            break
        step = min(step * (1.5 if iters <= 3 else 1.0), 0.1)
    arr = np.array(pts)
    return LoadedBranch(
        parameter=name,
        values=arr[:, 0],
        tip_height=arr[:, 1],
        stable=np.array(stab),
        folds=np.array(folds).reshape(-1, 2),
        status=status,
        nfev=curve.nfev,
    )


def _refine_fold(
    curve: _Curve, before: FloatArray, a: FloatArray, b: FloatArray, rising: bool
) -> tuple[float, float]:
    """(p, h) of the fold near branch point a (the tangent's p component changed sign between
    a and b, so the fold lies between ``before`` and b): the extremum of p(h) on that range of
    h by golden-section search (p(h) by a secant iteration on G(h, .) = 0), a maximum where p
    was ``rising`` at a, else a minimum."""
    hs = (float(before[1]), float(a[1]), float(b[1]))
    lo, hi = min(hs), max(hs)
    p_mid = float(a[0])
    # (the three points' p alone do not tell: the step after a fold can end beyond it)
    sign = 1.0 if rising else -1.0
    x1 = hi - _GOLDEN * (hi - lo)
    x2 = lo + _GOLDEN * (hi - lo)
    f1 = sign * curve.p_at(x1, p_mid)
    f2 = sign * curve.p_at(x2, p_mid)
    for _ in range(60):
        if hi - lo <= 1e-9:
            break
        if f1 > f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - _GOLDEN * (hi - lo)
            f1 = sign * curve.p_at(x1, p_mid)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + _GOLDEN * (hi - lo)
            f2 = sign * curve.p_at(x2, p_mid)
    h = 0.5 * (lo + hi)
    return curve.p_at(h, p_mid), h
