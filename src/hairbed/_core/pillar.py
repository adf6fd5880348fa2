"""An isolated pillar in a wall shear layer, loaded by resistive-force drag (issue 21).

:func:`solve_pillar` validates, turns the profile into Chebyshev coefficients, builds a
closed-form start and hands whole arrays to the same compiled collocation as the pressure and
flow drives (``_kernels.spectral``, drive ``DRIVE_DRAG``): one solver, its Newton, its load
continuation, its ladder of N and its status codes. The model is theory.md §12:

    theta'' = -(F_x cos theta - F_z sin theta),   F(s) = int_s^1 f ds',
    f = Lambda U(z) [cos^2 theta + gamma sin^2 theta, -(1 - gamma) sin theta cos theta],
    theta(0) = theta0,   theta'(1) = 0,   x(0) = z(0) = 0.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .loaded import (
    LADDER,
    _closed_form_start,
    _kernels,
    _ladder,
    _map_parameter,
    _quiet,
    _shape_at,
    _start,
)
from .outputs import scalar_or_array
from .validation import (
    HALF_PI,
    STATUS_MESSAGES,
    _check_range,
    as_float_array,
    broadcast_named,
    check_int,
    check_number,
    check_positive,
    status_messages,
)

__all__ = [
    "PROFILES",
    "PillarState",
    "gray_hancock_ratio",
    "profile_coefficients",
    "solve_pillar",
    "solve_pillar_inverse",
]

FloatArray = NDArray[np.float64]
Value = float | FloatArray
IntValue = int | NDArray[np.int64]
#: The built-in profiles U(z) (z in L, theory.md §12).
PROFILES = ("sublayer", "couette", "poiseuille")
_DRAG = 3
#: Chebyshev degrees tried for a callable profile (sampled at the Chebyshev points).
_PROFILE_DEGREES = (16, 32, 64, 128, 256)
#: A callable profile's coefficients are resolved when the last three are below this times
#: the largest one (plus the fit's rounding, 4 K eps max abs(U)).
_PROFILE_TAIL = 1e-15
#: Gauss-Legendre nodes of the start's equivalent tip load.
_GAUSS = np.polynomial.legendre.leggauss(24)


def gray_hancock_ratio(slenderness: ArrayLike) -> Any:
    """gamma = zeta_par/zeta_perp of Gray & Hancock's coefficients (theory.md §12).

    gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1) [-], for the slenderness L/a > 1.5 (where
    ln(2L/a) > 1/2 keeps zeta_par positive).
    """
    sl = as_float_array(slenderness, "slenderness")
    _check_range(sl, ~(sl > 1.5) | ~np.isfinite(sl), "slenderness", "(1.5, inf)")
    lg = np.log(2.0 * sl)
    return scalar_or_array((lg + 0.5) / (2.0 * lg - 1.0))


def _chebyshev_fit(values: FloatArray) -> FloatArray:
    """Chebyshev coefficients of the values at the K + 1 points t_j = -cos(pi j/K)."""
    k = values.size - 1
    j = np.arange(k + 1)
    vand = np.cos(np.outer(np.pi - np.pi * j / k, j))  # T_m(t_j), rows j
    half = np.ones(k + 1)
    half[0] = half[-1] = 0.5
    return (2.0 / k) * half * ((vand * half[:, None]).T @ values)


def profile_coefficients(
    profile: Any = "sublayer", height_ratio: float | None = None
) -> FloatArray:
    """The profile U(z), z in [0, 1] [L], as Chebyshev coefficients in t = 2 z - 1.

    Parameters
    ----------
    profile : {"sublayer", "couette", "poiseuille"} or callable
        "sublayer" and "couette": U = z; "poiseuille": U = z (1 - (L/H) z); a callable
        U(z) takes an ndarray of heights z in [0, 1] [L] and returns finite values of the same
        shape [-] (a smooth function: it is resolved to 1e-15 by at most 257 coefficients).
    height_ratio : float, optional
        L/H in (0, 1] of the channel profiles (required for "poiseuille"; checked for
        "couette", where the pillar must fit in the channel).
    """
    if callable(profile):
        return _callable_coefficients(profile)
    if not isinstance(profile, str) or profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES} or a callable U(z), got {profile!r}")
    if height_ratio is not None:
        r = check_number(height_ratio, "height_ratio", low=0.0, high=1.0, low_open=True)
    elif profile == "poiseuille":
        raise ValueError("profile 'poiseuille' needs height_ratio = L/H in (0, 1]")
    if profile == "poiseuille":
        # z - r z^2 with z = (1 + t)/2: (1 + t)/2 - r (3 + 4 t + T_2)/8
        return np.array([0.5 - 3.0 * r / 8.0, 0.5 - r / 2.0, -r / 8.0])
    return np.array([0.5, 0.5])


def _callable_coefficients(func: Callable[..., Any]) -> FloatArray:
    coef = np.zeros(1)
    for k in _PROFILE_DEGREES:
        t = -np.cos(np.pi * np.arange(k + 1) / k)
        z = 0.5 * (t + 1.0)
        try:
            raw = func(z)
        except Exception as exc:  # the user's function: say whose error it is
            raise ValueError(
                f"profile: the callable raised {type(exc).__name__}: {exc} (it is called with "
                f"an ndarray of heights z in [0, 1] [L])"
            ) from exc
        try:
            vals = np.asarray(raw, dtype=np.float64)
        except (TypeError, ValueError):
            raise TypeError(
                f"profile: the callable must return real numbers, got {type(raw).__name__}"
            ) from None
        if vals.shape != z.shape:
            raise ValueError(
                f"profile: the callable must return an array of the shape of z {z.shape}, "
                f"got shape {vals.shape}"
            )
        bad = ~np.isfinite(vals)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"profile: the callable returned {vals[i]!r} at z = {z[i]!r} (index {i}); it "
                f"must be finite on [0, 1]"
            )
        coef = _chebyshev_fit(vals)
        big = float(np.max(np.abs(coef)))
        # resolved: the last three coefficients at the fit's rounding level (K eps max U)
        floor = _PROFILE_TAIL * big + 4.0 * k * 2.2e-16 * float(np.max(np.abs(vals)))
        if big == 0.0 or float(np.sum(np.abs(coef[-3:]))) <= floor:
            keep = np.flatnonzero(np.abs(coef) > 1e-17 * max(big, 1e-300))
            return coef[: (int(keep[-1]) + 1 if keep.size else 1)].copy()
    raise ValueError(
        "profile: the callable is not resolved by 257 Chebyshev coefficients on [0, 1] (it "
        "must be smooth there; a kink or jump needs a smooth approximation)"
    )


@dataclass(frozen=True, eq=False)
class PillarState:
    """A steady state of an isolated pillar in a shear flow (theory.md §12).

    Scalar inputs give float fields, array inputs arrays of the broadcast shape. Where no
    state was found (``status`` < 0) every value field is NaN. Lengths are in the pillar
    length L, forces in E I/L^2.

    Attributes
    ----------
    forcing : float or ndarray
        Lambda = zeta_perp tau_w L^4/(eta E I) [-] (negative: flow towards -x).
    theta0 : float or ndarray
        Base angle from the wall normal [rad].
    gamma : float or ndarray
        Drag ratio zeta_par/zeta_perp [-].
    tip_load : float or ndarray
        A horizontal force on the tip [E I/L^2] (0 unless given).
    tip_deflection, tip_height : float or ndarray
        x1 = x(1), h1 = z(1) [L].
    tip_angle : float or ndarray
        theta(1) [rad].
    base_curvature : float or ndarray
        theta'(0) [1/L] = int_0^1 (z f_x - x f_z) ds (+ the tip load's moment): the base
        moment in E I/L.
    drag_x, drag_z : float or ndarray
        The drag on the whole pillar F(0) = int_0^1 f ds [E I/L^2] (streamwise and
        wall-normal; the tip load included in drag_x).
    tip_deflection_slope : float or ndarray
        dx1/dLambda [L] at the state, by implicit differentiation of the collocation system
        (exact to its accuracy; NaN at a fold, where it is infinite). The sensitivity of a
        sensor: dx1/dtau_w = tip_deflection_slope Lambda/tau_w.
    status : int or ndarray
        0 converged within the tolerance; 3 the error estimate misses it; -2 iteration limit;
        -3 singular Newton matrix or no descent; -7 no state from this start
        (``STATUS_MESSAGES``).
    error_estimate : float or ndarray
        The Chebyshev tail of theta plus its rounding part [rad].
    residual : float or ndarray
        The largest residual of the collocation equations.
    nit, num : int or ndarray
        Newton iterations (every level), and the Chebyshev degree N of the state.
    stable : bool or None
        From :func:`hairbed.solve_pillar_all`: True where the state is stable under a slow
        change of the forcing (on a rising part of the branch Lambda(x1)); None otherwise.
    """

    forcing: Value
    theta0: Value
    gamma: Value
    tip_load: Value
    tip_deflection: Value
    tip_height: Value
    tip_angle: Value
    base_curvature: Value
    drag_x: Value
    drag_z: Value
    tip_deflection_slope: Value
    status: IntValue
    error_estimate: Value
    residual: Value
    nit: IntValue
    num: IntValue
    _map: FloatArray
    _coefs: FloatArray
    stable: Any = None

    @property
    def success(self) -> Any:
        """True where the state converged within the tolerance (status 0)."""
        return scalar_or_array(np.asarray(self.status) == 0)

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, STATUS_MESSAGES)

    @property
    def shape_of_fields(self) -> tuple[int, ...]:
        """Shape of the array fields (() for a single state)."""
        return np.shape(self.tip_height)

    def shape(self, s: ArrayLike) -> tuple[Any, Any, Any, Any]:
        """The pillar at arc lengths ``s`` in [0, 1] [L]: (s, x, z, theta), as
        :meth:`hairbed.LoadedState.shape` (the spectral interpolants of the collocation)."""
        return _shape_at(self._map, self._coefs, self.shape_of_fields, s)


def _check(
    forcing: Any, theta0: Any, gamma: Any, tip_load: Any
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    lam = as_float_array(forcing, "forcing")
    t0 = as_float_array(theta0, "theta0")
    g = as_float_array(gamma, "gamma")
    tip = as_float_array(tip_load, "tip_load")
    _check_range(t0, np.abs(t0) >= HALF_PI, "theta0", "(-pi/2, pi/2)")
    _check_range(g, (g <= 0.0) | (g > 1.0), "gamma", "(0, 1]")
    lam, t0, g, tip = broadcast_named(
        ("forcing", lam), ("theta0", t0), ("gamma", g), ("tip_load", tip)
    )
    return lam, t0, g, tip


def _equivalent_tip_load(lam: FloatArray, t0: FloatArray, prof: FloatArray) -> FloatArray:
    """The horizontal tip force whose linear deflection is the drag's: P = 3 x1_lin/cos(theta0)
    = Lambda int_0^1 U(s cos theta0) s^2 (3 - s)/2 ds (the straight pillar's normal load)."""
    xg, wg = _GAUSS
    s = 0.5 * (xg + 1.0)
    z = s[None, :] * np.cos(t0)[:, None]
    u = np.polynomial.chebyshev.chebval(2.0 * z - 1.0, prof[0])
    return lam * (u @ (0.5 * wg * s * s * (3.0 - s) / 2.0))


@_quiet
def solve_pillar(
    forcing: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: ArrayLike = 0.5,
    tip_load: ArrayLike = 0.0,
    num: int | None = None,
    rtol: float = 1e-12,
) -> PillarState:
    """An isolated pillar under resistive-force drag, by Chebyshev collocation.

    Solves theta'' = -(F_x cos theta - F_z sin theta) with F(s) = P e_x + int_s^1 f ds',
    f = Lambda U(z) [cos^2 theta + gamma sin^2 theta, -(1 - gamma) sin theta cos theta],
    z' = cos theta, x' = sin theta, theta(0) = theta0, theta'(1) = 0 (theory.md §12), by
    the collocation of :func:`hairbed.solve_loaded` (the same kernel, its Newton with the
    exact Jacobian, load continuation and ladder of N).

    Parameters
    ----------
    forcing : array_like
        Lambda = zeta_perp tau_w L^4/(eta E I) [-], finite (negative: flow towards -x).
    theta0 : array_like, optional
        Base angle from the wall normal [rad], in (-pi/2, pi/2). Default 0.
    profile : {"sublayer", "couette", "poiseuille"} or callable, optional
        The undisturbed profile U(z) (:func:`profile_coefficients`). Default "sublayer".
    height_ratio : float, optional
        L/H in (0, 1] for "poiseuille" (and "couette", checked).
    gamma : array_like, optional
        zeta_par/zeta_perp in (0, 1] [-]. Default 1/2, the slender limit;
        :func:`gray_hancock_ratio` gives Gray & Hancock's at a finite L/a.
    tip_load : array_like, optional
        A horizontal force on the tip [E I/L^2], finite. Default 0.
    num : int, optional
        A fixed Chebyshev degree N in [8, 512] instead of the ladder (32, 64, 128).
    rtol : float, optional
        Tolerance on the Chebyshev tail of theta [rad]; default 1e-12.

    Returns
    -------
    PillarState

    Examples
    --------
    >>> import hairbed
    >>> st = hairbed.solve_pillar(1e-3)
    >>> round(st.tip_deflection / (11e-3 / 120), 6)   # the linear cantilever, x1 = 11 Lambda/120
    1.0
    """
    lam, t0, g, tip = _check(forcing, theta0, gamma, tip_load)
    prof = profile_coefficients(profile, height_ratio)[None, :]
    tol = check_positive(rtol, "rtol")
    nums = LADDER if num is None else (check_int(num, "num", 8, 512),)
    return _solve_pillar_checked(lam, t0, g, tip, prof, tol, nums)


def _solve_pillar_checked(
    lam: FloatArray,
    t0: FloatArray,
    g: FloatArray,
    tip: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> PillarState:
    """:func:`solve_pillar` of checked, broadcast inputs; ``prof`` (1 or size, K)."""
    shape = lam.shape
    lf, tf, gf, pf = (
        np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (lam, t0, g, tip)
    )
    prof = np.ascontiguousarray(prof, dtype=np.float64)
    weq = _equivalent_tip_load(lf, tf, np.broadcast_to(prof, (1, prof.shape[1]))) + pf
    zero = np.zeros(lf.size)
    ts, es, ths, mirror, hs = _start(2, weq, zero, zero, tf, "low")
    a = _map_parameter(2, weq, zero, zero, hs)
    ok = ~np.isnan(ts)
    theta_start = _closed_form_start(ts, es, ths, mirror, a, nums, ok)
    theta_start[~ok] = tf[~ok, None]
    hs = np.where(ok, hs, np.cos(tf))
    k = _kernels()
    out = np.empty((k.NCOLS, lf.size))
    coefs = np.empty((3, lf.size, int(max(nums)) + 1))
    k.solve_loaded_array(
        _DRAG,
        lf,
        gf,
        pf,
        tf,
        a,
        theta_start,
        hs[:, None],
        *_ladder(tuple(nums)),
        tol,
        prof,
        out,
        coefs,
    )
    _rescue(lf, tf, gf, pf, prof, tol, nums, out, coefs, a)
    return _pillar_state(shape, lam, t0, g, tip, out, coefs, a)


def _pillar_state(
    shape: tuple[int, ...],
    lam: FloatArray,
    t0: FloatArray,
    g: FloatArray,
    tip: FloatArray,
    out: FloatArray,
    coefs: FloatArray,
    a: FloatArray,
) -> PillarState:
    """A PillarState of the kernel's columns, reshaped to ``shape``."""

    def col(i: int) -> Any:
        return scalar_or_array(out[i].reshape(shape))

    return PillarState(
        forcing=scalar_or_array(lam.reshape(shape)),
        theta0=scalar_or_array(t0.reshape(shape)),
        gamma=scalar_or_array(g.reshape(shape)),
        tip_load=scalar_or_array(tip.reshape(shape)),
        tip_deflection=col(5),
        tip_height=col(4),
        tip_angle=col(6),
        base_curvature=col(7),
        drag_x=col(8),
        drag_z=col(9),
        tip_deflection_slope=col(13),
        status=scalar_or_array(out[0].astype(np.int64).reshape(shape)),
        error_estimate=col(10),
        residual=col(11),
        nit=scalar_or_array(out[1].astype(np.int64).reshape(shape)),
        num=scalar_or_array(out[2].astype(np.int64).reshape(shape)),
        _map=a.reshape(shape),
        _coefs=coefs.reshape((3, *shape, coefs.shape[-1])),
    )


_DRAG_INVERSE = 4


@_quiet
def solve_pillar_inverse(
    tip_deflection: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: ArrayLike = 0.5,
    tip_load: ArrayLike = 0.0,
    num: int | None = None,
    rtol: float = 1e-12,
) -> PillarState:
    """The pillar state of a given tip deflection, with its forcing Lambda (the inverse).

    The collocation system of :func:`solve_pillar` with Lambda as one more unknown and the
    equation x(1) = x1, solved by the same Newton (the exact Jacobian's Lambda column is the
    load at Lambda = 1, as f is linear in Lambda), from the straight pillar by a continuation
    in x1 where Newton does not converge at once. x1 moves monotonically along the branch
    of states, so this is every state, fold windows included (theory.md §12).

    Parameters
    ----------
    tip_deflection : array_like
        x1 [L], in (-1, 1): above sin(theta0) for a flow towards +x, below for -x.
    theta0, profile, height_ratio, gamma, tip_load, num, rtol
        As in :func:`solve_pillar`.

    Returns
    -------
    PillarState
        ``forcing`` holds the Lambda found (NaN where ``status`` < 0).
    """
    x1 = as_float_array(tip_deflection, "tip_deflection")
    _check_range(x1, np.abs(x1) >= 1.0, "tip_deflection", "(-1, 1)")
    x1b, t0, g, tip = _check(x1, theta0, gamma, tip_load)
    prof = profile_coefficients(profile, height_ratio)[None, :]
    tol = check_positive(rtol, "rtol")
    nums = LADDER if num is None else (check_int(num, "num", 8, 512),)
    shape = x1b.shape
    xf, tf, gf, pf = (
        np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (x1b, t0, g, tip)
    )
    out, coefs, a = _inverse_run(xf, tf, gf, pf, prof, tol, nums)
    return _pillar_state(shape, out[12], t0, g, tip, out, coefs, a)


def _inverse_run(
    xf: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The kernel's inverse problem on flat checked arrays: (out, coefs, a); out[12] is
    Lambda. Started from the straight pillar (Lambda = 0; the kernel continues in x1)."""
    theta_start = np.ascontiguousarray(np.repeat(tf[:, None], nums[0] + 1, axis=1))
    extra = np.stack([np.cos(tf), np.zeros(xf.size)], axis=1)
    k = _kernels()
    out = np.empty((k.NCOLS, xf.size))
    coefs = np.empty((3, xf.size, int(max(nums)) + 1))
    a = np.zeros(xf.size)
    k.solve_loaded_array(
        _DRAG_INVERSE,
        xf,
        gf,
        pf,
        tf,
        a,
        theta_start,
        extra,
        *_ladder(tuple(nums)),
        tol,
        prof,
        out,
        coefs,
    )
    return out, coefs, a


#: The rescue's grid in the fraction u of the way from the straight pillar's x1 to the wall's
#: (x1 = sin(theta0) + u (+-1 - sin(theta0))): fine through the snap-through windows, then
#: geometric towards the wall (Lambda ~ 1e5 at u = 0.999).
_RESCUE_GRID = np.concatenate(
    [np.linspace(0.0, 0.9, 49)[1:], 1.0 - np.geomspace(0.1, 1e-3, 16)[1:]]
)
#: The most regula-falsi steps of the rescue.
_RESCUE_STEPS = 60


def _rescue(
    lf: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    out: FloatArray,
    coefs: FloatArray,
    a: FloatArray,
) -> None:
    """Where the forward Newton and its load continuation failed (a fold on the way: the pillar
    beyond its snap-through window), the state of the same forcing through the inverse
    problem: Lambda(x1) on a grid from the straight pillar, the first crossing of the forcing
    (the state a slow ramp from rest reaches), refined by the Illinois regula falsi on x1,
    every failed element at once; written into out, coefs and a in place."""
    bad = np.flatnonzero((out[0] < 0) & (lf != 0.0))
    if bad.size == 0:
        return
    grid = _RESCUE_GRID
    nb, reps = bad.size, grid.size
    rest = np.sin(tf[bad])
    wall = np.where(lf[bad] > 0.0, 1.0, -1.0)

    def excess(u: FloatArray, rows: Any) -> tuple[FloatArray, Any]:
        """wall (Lambda(x1(u)) - forcing) at the fractions u (rows, k) of the elements rows."""
        k = u.shape[1]
        e = bad[rows]
        x = (rest[rows, None] + (wall - rest)[rows, None] * u).reshape(-1)
        rep = [np.repeat(v[e], k) for v in (tf, gf, pf)]
        res = _inverse_run(x, rep[0], rep[1], rep[2], prof, tol, nums)
        lam = res[0][12].reshape(-1, k)
        return wall[rows, None] * (lam - lf[e][:, None]), res

    g_grid = excess(np.ascontiguousarray(np.broadcast_to(grid, (nb, reps))), np.arange(nb))[0]
    beyond = np.isfinite(g_grid) & (g_grid >= 0.0)
    rows = np.flatnonzero(beyond.any(axis=1))
    if rows.size == 0:
        return
    first = np.argmax(beyond[rows], axis=1)
    hi = grid[first]
    g_hi = g_grid[rows, first]
    prev = np.maximum(first - 1, 0)
    lo = np.where(first > 0, grid[prev], 0.0)
    # below the forcing at the grid point before, or at the rest state (Lambda = 0)
    g_lo = np.where(first > 0, g_grid[rows, prev], -np.abs(lf[bad][rows]))
    side = np.zeros(rows.size)
    scale = np.abs(lf[bad][rows])
    u = hi
    for _ in range(_RESCUE_STEPS):
        u = np.where(g_hi != g_lo, hi - g_hi * (hi - lo) / (g_hi - g_lo), 0.5 * (lo + hi))
        u = np.where((u > lo) & (u < hi), u, 0.5 * (lo + hi))
        g = excess(u[:, None], rows)[0][:, 0]
        g = np.where(np.isfinite(g), g, 0.5 * (g_lo + g_hi))
        up = g >= 0.0
        # Illinois: halve the value of the end kept twice in a row
        g_lo = np.where(up & (side == 1.0), 0.5 * g_lo, g_lo)
        g_hi = np.where(~up & (side == -1.0), 0.5 * g_hi, g_hi)
        hi, g_hi = np.where(up, u, hi), np.where(up, g, g_hi)
        lo, g_lo = np.where(up, lo, u), np.where(up, g_lo, g)
        side = np.where(up, 1.0, -1.0)
        if np.all((np.abs(g) <= 4e-16 * scale) | (hi - lo <= 1e-16)):
            break
    _, (o, c, aa) = excess(u[:, None], rows)
    e = bad[rows]
    out[:, e] = o
    out[12, e] = lf[e]
    coefs[:, e, : c.shape[-1]] = c
    a[e] = aa
