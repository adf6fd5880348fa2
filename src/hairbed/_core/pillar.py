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

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._kernels import description as D
from .collocated import CollocatedState
from .loaded import (
    LADDER,
    _chebyshev_values,
    _clenshaw,
    _closed_form_start,
    _kernels,
    _ladder,
    _map_parameter,
    _mapped_nodes,
    _quiet,
    _shape_at,
    _start,
)
from .outputs import scalar_or_array
from .validation import (
    HALF_PI,
    _check_range,
    as_float_array,
    broadcast_named,
    check_int,
    check_number,
    check_positive,
    check_root,
    real_values,
    show,
)

__all__ = [
    "ATLAS_THETA0",
    "MIN_SLENDERNESS",
    "PROFILES",
    "WINDOW_THETA0",
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


#: The least slenderness L/a of a pillar, e^1.5/2 = 2.2408...: there Gray & Hancock's ratio
#: gamma reaches 1 (ln(2L/a) = 3/2), and below it gamma > 1 leaves the model's range.
MIN_SLENDERNESS = math.exp(1.5) / 2.0


def gray_hancock_ratio(slenderness: ArrayLike) -> Any:
    """gamma = zeta_par/zeta_perp of Gray & Hancock's coefficients (theory.md §12).

    gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1) [-], for the slenderness L/a >=
    ``MIN_SLENDERNESS`` = e^1.5/2 = 2.2408 (where gamma = 1; below it gamma > 1, outside the
    range (0, 1] of :func:`solve_pillar`'s gamma, issue 33).
    """
    sl = as_float_array(slenderness, "slenderness")
    bad = ~(sl >= MIN_SLENDERNESS) | ~np.isfinite(sl)
    _check_range(sl, bad, "slenderness", f"[e^1.5/2 = {MIN_SLENDERNESS:.4f}, inf)")
    lg = math.log(2.0) + np.log(sl)  # not log(2 sl): no overflow at the float range's end
    # at most 1: ln(2 L/a) may round below 3/2 at the bound itself, where gamma = 1 exactly
    return scalar_or_array(np.minimum((lg + 0.5) / (2.0 * lg - 1.0), 1.0))


@functools.lru_cache(maxsize=8)
def _fit_operators(k: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(z_j = (1 + t_j)/2 at the K + 1 points t_j = -cos(pi j/K), the weights (2/K) h_m,
    the matrix (T_m(t_j) h_j)^T) of :func:`_chebyshev_fit` at K, h = (1/2, 1, .., 1, 1/2):
    built once per K; shared, so read-only."""
    z = 0.5 * (-np.cos(np.pi * np.arange(k + 1) / k) + 1.0)
    half = np.ones(k + 1)
    half[0] = half[-1] = 0.5
    weights = (2.0 / k) * half
    matrix = (_chebyshev_values(k) * half[:, None]).T
    for arr in (z, weights, matrix):
        arr.flags.writeable = False
    return z, weights, matrix


def _chebyshev_fit(values: FloatArray) -> FloatArray:
    """Chebyshev coefficients of the values at the K + 1 points t_j = -cos(pi j/K)."""
    _, weights, matrix = _fit_operators(values.size - 1)
    return weights * (matrix @ values)


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
    if height_ratio is not None:  # checked wherever given, a callable's too (issue 33)
        check_number(height_ratio, "height_ratio", low=0.0, high=1.0, low_open=True)
    if callable(profile):
        return _callable_coefficients(profile)
    if not isinstance(profile, str) or profile not in PROFILES:
        raise ValueError(
            f"profile must be one of {PROFILES} or a callable U(z), got {show(profile)}"
        )
    if height_ratio is not None:
        r = float(height_ratio)
    elif profile == "poiseuille":
        raise ValueError("profile 'poiseuille' needs height_ratio = L/H in (0, 1]")
    if profile == "poiseuille":
        # z - r z^2 with z = (1 + t)/2: (1 + t)/2 - r (3 + 4 t + T_2)/8
        return np.array([0.5 - 3.0 * r / 8.0, 0.5 - r / 2.0, -r / 8.0])
    return np.array([0.5, 0.5])


def _callable_coefficients(func: Callable[..., Any]) -> FloatArray:
    coef = np.zeros(1)
    for k in _PROFILE_DEGREES:
        z = _fit_operators(k)[0].copy()  # (the user's copy: the shared one is read-only)
        try:
            raw = func(z)
        except (ValueError, TypeError) as exc:
            if str(exc).startswith("profile: "):  # a checked wrapper's own message (SI units)
                raise
            raise ValueError(
                f"profile: the callable raised {type(exc).__name__}: {exc} (it is called with "
                f"an ndarray of heights z in [0, 1] [L])"
            ) from exc
        except Exception as exc:  # the user's function: say whose error it is
            raise ValueError(
                f"profile: the callable raised {type(exc).__name__}: {exc} (it is called with "
                f"an ndarray of heights z in [0, 1] [L])"
            ) from exc
        vals = real_values(raw, "profile: the callable", "real numbers")
        if vals.shape != z.shape:
            raise ValueError(
                f"profile: the callable must return an array of the shape of z {z.shape}, "
                f"got shape {vals.shape}"
            )
        bad = ~np.isfinite(vals)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"profile: the callable returned {float(vals[i])!r} at z = {float(z[i])!r} "
                f"(index {i}); it must be finite on [0, 1]"
            )
        coef = _chebyshev_fit(vals)
        big = float(np.abs(coef).max())  # (methods: numpy's reductions, less Python)
        # resolved: the last three coefficients at the fit's rounding level (K eps max U)
        floor = _PROFILE_TAIL * big + 4.0 * k * 2.2e-16 * float(np.abs(vals).max())
        if big == 0.0 or float(np.abs(coef[-3:]).sum()) <= floor:
            keep = np.flatnonzero(np.abs(coef) > 1e-17 * max(big, 1e-300))
            return coef[: (int(keep[-1]) + 1 if keep.size else 1)].copy()
    raise ValueError(
        "profile: the callable is not resolved by 257 Chebyshev coefficients on [0, 1] (it "
        "must be smooth there; a kink or jump needs a smooth approximation)"
    )


@dataclass(frozen=True, eq=False)
class PillarState(CollocatedState):
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
    n_states : int or ndarray or None
        How many states coexist at this forcing (as :attr:`hairbed.Solution.n_roots` for a
        bed), from :func:`hairbed.solve_pillar` and :func:`hairbed.solve_pillar_all`: 1, or 3
        inside a snap-through window, where ``root`` picks one and
        :func:`hairbed.solve_pillar_all` gives all of them; 0 where no state was found; a
        lower bound where the status is 6 (a pillar leaning onto the wall whose branch could
        not be followed through its window; none measured for theta0 up to -1.57075, issue
        33). None for the inverse (:func:`hairbed.solve_pillar_inverse`: one state per
        deflection).
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
    n_states: Any = None

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


def _start_load(
    lam: FloatArray, t0: FloatArray, tip: FloatArray, prof: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """(W_eq, a): the tip load of a start (the drag's equivalent tip load plus the tip load
    itself) and the collocation's map parameter from it (as for a tip load W_eq)."""
    weq = _equivalent_tip_load(lam, t0, prof[:1]) + tip
    zero = np.zeros(lam.size)
    return weq, _map_parameter(2, weq, zero, zero, np.cos(t0))


@_quiet
def solve_pillar(
    forcing: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: ArrayLike = 0.5,
    tip_load: ArrayLike = 0.0,
    root: str = "low",
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
    root : {"low", "mid", "high"}, optional
        Which state in a snap-through window (a pillar tilted far upstream, theory.md §12),
        in the order of the branch from rest: "low" (default) the first, the state a slow
        ramp of the forcing from rest reaches (leaning upstream); "high" the last (standing
        over its base); "mid" the middle, unstable one (status -1 outside a window). Outside
        the windows the one state, whatever ``root``. Where theta0 < ``WINDOW_THETA0``
        (-1.2) the state is picked on the branch (as :func:`continue_pillar` follows it).
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
    prof, tol, nums = _options(profile, height_ratio, rtol, num)
    return _solve_pillar_checked(lam, t0, g, tip, prof, tol, nums, check_root(root))


def _options(
    profile: Any, height_ratio: float | None, rtol: float, num: int | None
) -> tuple[FloatArray, float, tuple[int, ...]]:
    """The checked keywords shared by the forward and the inverse: the profile's
    coefficients (one row), the tolerance and the ladder of N."""
    prof = profile_coefficients(profile, height_ratio)[None, :]
    tol = check_positive(rtol, "rtol")
    nums = LADDER if num is None else (check_int(num, "num", 8, 512),)
    return prof, tol, nums


def _solve_pillar_checked(
    lam: FloatArray,
    t0: FloatArray,
    g: FloatArray,
    tip: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    root: str = "low",
) -> PillarState:
    """:func:`solve_pillar` of checked, broadcast inputs; ``prof`` (1 or size, K)."""
    shape = lam.shape
    lf, tf, gf, pf = (
        np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (lam, t0, g, tip)
    )
    prof = np.ascontiguousarray(prof, dtype=np.float64)
    # a flow towards -x is the mirror image x -> -x of the flow towards +x at -theta0
    mirror = np.where(lf < 0.0, -1.0, 1.0)
    lf, tf, pf = np.abs(lf), mirror * tf, mirror * pf
    k = _kernels()
    out = np.full((k.NCOLS, lf.size), np.nan)
    out[0] = -7
    coefs = np.full((3, lf.size, int(max(nums)) + 1), np.nan)
    a = np.zeros(lf.size)
    window = (tf < WINDOW_THETA0) & (lf != 0.0)  # picked on the branch, no forward Newton
    fwd = np.flatnonzero(~window)
    if fwd.size:
        o, c, aa = _forward_run(lf[fwd], tf[fwd], gf[fwd], pf[fwd], prof, tol, nums)
        out[:, fwd], coefs[:, fwd], a[fwd] = o, c, aa
    count = np.ones(lf.size, dtype=np.int64)  # one state outside the windows
    todo = (out[0] < 0) | window
    unsure = np.zeros(lf.size, dtype=np.bool_)
    _on_branch(lf, tf, gf, pf, prof, tol, nums, out, coefs, a, todo, root, count, unsure)
    count[(out[0] < 0) & (count == 1)] = 0
    out[0, unsure & (out[0] == 0)] = 6  # found, but others may coexist: it says so
    _mirror(out, coefs, mirror)
    st = _pillar_state(shape, lam, t0, g, tip, out, coefs, a)
    return replace(st, n_states=scalar_or_array(count.reshape(shape)))


#: The kernel's columns (and Chebyshev series: theta, x) that change sign with x -> -x (x1,
#: theta1, theta'(0), drag_x, the forcing, the tip displacement x1 - sin(theta0)).
_ODD_COLUMNS = (5, 6, 7, 8, 12, 14)


def _mirror(out: FloatArray, coefs: FloatArray, mirror: FloatArray) -> None:
    """Mirror the states of ``mirror`` -1 back (x1, the angles, the base moment, drag_x and
    the forcing change sign; h1, drag_z and dx1/dLambda do not), in place."""
    for col in _ODD_COLUMNS:
        out[col] *= mirror
    coefs[0] *= mirror[:, None]
    coefs[1] *= mirror[:, None]


def _forward_run(
    lf: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The kernel's forward problem on flat checked arrays: (out, coefs, a).

    The elements are solved as curves (``solve_loaded_chain``): sorted by their parameters
    and forcing, each element whose neighbour below has the same theta0, gamma, tip load and
    profile and a forcing within ``_CHAIN_STEP`` starts from that neighbour's state (its
    tangent predictor and Jacobian factors); the first of each curve from the closed-form
    start of the equivalent tip load."""
    order, chain = _curve_order(lf, tf, gf, pf, prof)
    lf, tf, gf, pf = (np.ascontiguousarray(v[order]) for v in (lf, tf, gf, pf))
    prof_s = np.ascontiguousarray(prof[order]) if prof.shape[0] > 1 else prof
    weq, a = _start_load(lf, tf, pf, prof)
    theta_start = np.repeat(tf[:, None], nums[0] + 1, axis=1)
    hs = np.cos(tf)
    head = np.flatnonzero(~chain)
    if head.size:
        zh = np.zeros(head.size)
        ts, es, ths, mirror, hh = _start(2, weq[head], zh, zh, tf[head], "low")
        ok = ~np.isnan(ts)
        th = _closed_form_start(ts, es, ths, mirror, a[head], nums, ok)
        th[~ok] = tf[head][~ok, None]
        theta_start[head] = th
        hs[head] = np.where(ok, hh, hs[head])
    out, coefs = _kernel_run(
        _DRAG, lf, tf, gf, pf, a, theta_start, hs[:, None], prof_s, tol, nums, chain
    )
    return _unsort(order, out, coefs, a)


def _kernel_run(
    code: int,
    values: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    a: FloatArray,
    theta_start: FloatArray,
    extra: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    chain: NDArray[np.bool_] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """``solve_loaded_chain`` of the drag drive ``code`` (the forcing or, for the inverse,
    the tip displacement x1 - sin(theta0) in ``values``): (out, coefs); no element chained
    where ``chain`` is None."""
    k = _kernels()
    out = np.empty((k.NCOLS, values.size))
    coefs = np.empty((3, values.size, int(max(nums)) + 1))
    desc = np.zeros((values.size, D.NDESC))
    desc[:, D.D_THETA0] = tf
    desc[:, D.D_DX1 if code == _DRAG_INVERSE else D.D_LAMBDA] = values
    desc[:, D.D_GAMMA] = gf
    desc[:, D.D_TIP] = pf
    k.solve_loaded_chain(
        code,
        desc,
        a,
        np.ascontiguousarray(theta_start),
        np.ascontiguousarray(extra),
        *_ladder(tuple(nums)),
        tol,
        prof,
        out,
        coefs,
        np.zeros(0, dtype=np.bool_) if chain is None else chain,
    )
    return out, coefs


def _unsort(
    order: NDArray[np.intp], out: FloatArray, coefs: FloatArray, a: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(out, coefs, a) of elements solved in ``order``, back in the order of the input."""
    back = np.empty_like(order)
    back[order] = np.arange(order.size)
    return out[:, back], coefs[:, back], a[back]


#: Neighbours on a curve whose forcings differ by at most this fraction of the larger (or
#: by at most _CHAIN_ABS) start one from the other (:func:`_forward_run`).
_CHAIN_STEP = 0.25
_CHAIN_ABS = 1e-2


def _curve_order(
    lf: FloatArray, tf: FloatArray, gf: FloatArray, pf: FloatArray, prof: FloatArray
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """The order that lays the elements out as curves in the forcing (per distinct theta0,
    gamma, tip load and profile row) and, in that order, which element continues the curve
    of the one before it."""
    if prof.shape[0] > 1:
        rows = np.unique(prof, axis=0, return_inverse=True)[1].reshape(-1).astype(np.float64)
    else:
        rows = np.zeros(lf.size)
    order = np.lexsort((lf, pf, gf, tf, rows))
    chain = np.zeros(lf.size, dtype=np.bool_)
    if lf.size > 1:
        keys = np.stack([rows, tf, gf, pf])[:, order]
        ls = lf[order]
        same = np.all(keys[:, 1:] == keys[:, :-1], axis=0)
        gap = np.abs(ls[1:] - ls[:-1])
        near = (gap <= _CHAIN_STEP * np.maximum(ls[1:], ls[:-1])) | (gap <= _CHAIN_ABS)
        chain[1:] = same & near & np.isfinite(ls[1:]) & np.isfinite(ls[:-1])
    return order, chain


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
    prof, tol, nums = _options(profile, height_ratio, rtol, num)
    return _inverse_checked(x1b, t0, g, tip, prof, tol, nums)


def _inverse_checked(
    x1b: FloatArray,
    t0: FloatArray,
    g: FloatArray,
    tip: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> PillarState:
    """:func:`solve_pillar_inverse` of checked, broadcast inputs (x1 in (-1, 1))."""
    shape = x1b.shape
    xf, tf, gf, pf = (
        np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (x1b, t0, g, tip)
    )
    mirror = np.where(xf < np.sin(tf), -1.0, 1.0)  # a flow towards -x, solved as its mirror
    xm, tm, pm = mirror * xf, mirror * tf, mirror * pf
    dm = xm - np.sin(tm)  # the tip displacement the kernel's inverse solves for
    start = _grid_start(dm, tm, gf, pm, prof, tol, nums)
    out, coefs, a = _inverse_run(dm, tm, gf, pm, prof, tol, nums, start, retry=True)
    _mirror(out, coefs, mirror)
    return _pillar_state(shape, out[12], t0, g, tip, out, coefs, a)


#: Steps of :func:`_walk_failed`'s march (each one batched inverse of the elements still
#: on their way), its first step as a fraction of the way, and its growth and cut factors.
_WALK_STEPS = 40
_WALK_FIRST = 0.25
_WALK_GROW = 2.0
_WALK_CUT = 0.25
#: The march gives up on an element after this many failed steps in a row (each failed
#: inverse costs the kernel's whole continuation from rest: the bound keeps a branch whose
#: states do not exist at this N, a fixed ``num=``, from taking minutes).
_WALK_TRIES = 3


def _state_start(
    out: FloatArray, coefs: FloatArray, nums: tuple[int, ...]
) -> tuple[FloatArray, FloatArray]:
    """Starts (theta at the first level's nodes; h1 and Lambda) from solved states."""
    nodes = _ladder(tuple(nums))[1][0, : nums[0] + 1]
    theta = _clenshaw(coefs[0], np.broadcast_to(nodes, (coefs.shape[1], nodes.size)))
    mapped = np.flatnonzero(out[3] != 0.0)  # states of an atlas's start: at plain nodes too
    if mapped.size:
        s = np.broadcast_to(0.5 * (nodes + 1.0), (mapped.size, nodes.size))
        theta[mapped] = _theta_at(coefs[0, mapped], out[3, mapped], s)
    return np.ascontiguousarray(theta), np.stack([out[4], out[12]], axis=1)


def _anchors(
    df: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    solved: NDArray[np.bool_],
    bad: NDArray[np.intp],
) -> NDArray[np.intp]:
    """For each failed element of ``bad``, the solved element with the same theta0, gamma and
    tip load whose tip displacement ``df`` (x1 - sin(theta0)) lies closest below its own and
    above rest (-1: none; the march then starts at rest)."""
    anchor = np.full(bad.size, -1)
    ok = np.flatnonzero(solved & (df >= 0.0))
    if ok.size == 0:
        return anchor
    keys = np.stack([tf, gf, pf], axis=1)
    for t, g, p in np.unique(keys[bad], axis=0):
        mine = (tf[bad] == t) & (gf[bad] == g) & (pf[bad] == p)
        cand = ok[(tf[ok] == t) & (gf[ok] == g) & (pf[ok] == p)]
        if cand.size == 0:
            continue
        cand = cand[np.argsort(df[cand], kind="stable")]
        pos = np.searchsorted(df[cand], df[bad[mine]], side="left") - 1
        anchor[mine] = np.where(pos >= 0, cand[np.maximum(pos, 0)], -1)
    return anchor


def _walk_failed(
    df: FloatArray,
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
    """Inverse problems (tip displacements ``df`` = x1 - sin(theta0) >= 0) whose run failed,
    solved again by a march in the displacement, in place where the march arrives. x1 is
    monotone along the branch (no fold on the way), so each element marches from the nearest
    solved state below it in the same call (same theta0, gamma, tip load), or from the straight
    pillar, each step started from the state of the step before; a step that fails is cut, one
    that succeeds grown.

    Near the wall (theta0 -> -pi/2) the kernel's continuation from rest stops at isolated
    x1 between solved ones and in bands of x1 (theory.md §12; issue 33: up to all 400 of
    a scan of the forcing at theta0 = -1.57 had status -7)."""
    bad = np.flatnonzero(out[0] < 0)
    if bad.size == 0:
        return
    anchor = _anchors(df, tf, gf, pf, out[0] >= 0, bad)
    xt = df[bad]
    has = anchor >= 0
    xc = np.where(has, df[np.maximum(anchor, 0)], 0.0)
    theta = np.repeat(tf[bad][:, None], nums[0] + 1, axis=1)
    extra = np.stack([np.cos(tf[bad]), np.zeros(bad.size)], axis=1)
    if np.any(has):
        theta[has], extra[has] = _state_start(out[:, anchor[has]], coefs[:, anchor[has]], nums)
    step = _WALK_FIRST * (xt - xc)
    fails = np.zeros(bad.size, dtype=np.int64)
    live = np.ones(bad.size, dtype=np.bool_)
    for _ in range(_WALK_STEPS):
        act = np.flatnonzero(live)
        if act.size == 0:
            return
        last = xc[act] + step[act] >= xt[act]
        xn = np.where(last, xt[act], xc[act] + step[act])
        tb, gb, pb = (np.ascontiguousarray(v[bad[act]]) for v in (tf, gf, pf))
        start = (np.ascontiguousarray(theta[act]), np.ascontiguousarray(extra[act]))
        o, c, am = _inverse_run(
            np.ascontiguousarray(xn), tb, gb, pb, prof, tol, nums, start, walk=False, retry=False
        )
        on = o[0] >= 0
        got = act[on]
        xc[got] = xn[on]
        if got.size:
            theta[got], extra[got] = _state_start(o[:, on], c[:, on], nums)
        step[act] = np.where(on, _WALK_GROW * step[act], _WALK_CUT * step[act])
        arrived = on & last
        if np.any(arrived):
            e = bad[act[arrived]]
            out[:, e] = o[:, arrived]
            coefs[:, e] = c[:, arrived]
            a[e] = am[arrived]
            live[act[arrived]] = False
        fails[act] = np.where(on, 0, fails[act] + 1)
        live[act[fails[act] >= _WALK_TRIES]] = False


#: A batch of at least this many inverse problems per distinct (theta0, gamma, tip load)
#: starts from the states of a branch grid (:func:`_grid_start`) instead of the straight pillar.
_GRID_START_RATIO = 50


def _grid_start(
    df: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> tuple[FloatArray, FloatArray] | None:
    """Starts for a large batch of inverse problems (tip displacements ``df`` = x1 -
    sin(theta0) >= 0) that share few parameter sets (a calibration curve): the inverse on
    the branch grid of each set once, then each element's start interpolated linearly in the
    displacement between the grid states around it (theta at the nodes, h1, Lambda); None
    when the batch is not such a batch."""
    keys = np.stack([tf, gf, pf], axis=1)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    if df.size == 0 or df.size < _GRID_START_RATIO * uniq.shape[0] * 4:
        return None
    if np.all(uniq[:, 0] < ATLAS_THETA0):  # every start from an atlas (_inverse_run)
        return None
    grid = np.concatenate([[0.0], _BRANCH_GRID])
    reps = grid.size - 1
    span = 1.0 - np.sin(uniq[:, 0])  # the displacement from rest to the wall
    dg = (span[:, None] * grid[None, 1:]).reshape(-1)
    rep = [np.ascontiguousarray(np.repeat(uniq[:, c], reps)) for c in range(3)]
    o, c, _ = _inverse_run(dg, rep[0], rep[1], rep[2], prof, tol, nums)
    ng = uniq.shape[0]
    vals = _state_start(o, c, nums)[0].reshape(ng, reps, -1)
    straight = np.repeat(uniq[:, 0][:, None, None], vals.shape[2], axis=2)
    vals = np.concatenate([straight, vals], axis=1)  # the rest state first
    hg = np.concatenate([np.cos(uniq[:, 0])[:, None], o[4].reshape(ng, reps)], axis=1)
    lg = np.concatenate([np.zeros((ng, 1)), o[12].reshape(ng, reps)], axis=1)
    ok = np.isfinite(lg) & np.isfinite(hg) & np.all(np.isfinite(vals), axis=2)
    u = df / span[inv]
    j = np.clip(np.searchsorted(grid, u, side="right") - 1, 0, grid.size - 2)
    w = np.clip((u - grid[j]) / (grid[j + 1] - grid[j]), 0.0, 1.0)
    good = ok[inv, j] & ok[inv, j + 1] & (u <= grid[-1])
    theta = (1.0 - w)[:, None] * vals[inv, j] + w[:, None] * vals[inv, j + 1]
    extra = np.stack(
        [(1.0 - w) * hg[inv, j] + w * hg[inv, j + 1], (1.0 - w) * lg[inv, j] + w * lg[inv, j + 1]],
        axis=1,
    )
    theta[~good] = tf[~good, None]
    extra[~good, 0] = np.cos(tf[~good])
    extra[~good, 1] = 0.0
    return theta, extra


def _inverse_run(
    df: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    start: tuple[FloatArray, FloatArray] | None = None,
    walk: bool = True,
    retry: bool = False,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The kernel's inverse problem on flat checked arrays of tip displacements ``df`` = x1 -
    sin(theta0) (the kernel's unknown measure: x1 itself rounds away the displacement of a
    pillar leaning onto the wall): (out, coefs, a); out[12] is Lambda. Started from ``start``
    (theta at the first level's nodes; h1 and Lambda), or from the straight pillar (Lambda = 0;
    the kernel continues in x1 where Newton fails); what fails then is tried again on the
    ladder's finer levels where ``retry`` (:func:`_retry_finer`: for a branch grid and a user's
    inverse, not for every step of a search, where each failed run of the kernel costs its
    whole continuation) and marched to from the nearest solved state (:func:`_walk_failed`,
    unless ``walk`` is False). Not as curves (:func:`_forward_run`): chord steps end with an
    absolute error of Lambda of their rate times the step tolerance, too much for a relative
    accuracy of a small Lambda (and a branch grid of a tiny forcing then had turns of
    rounding)."""
    a = np.zeros(df.size)
    if start is None:
        theta_start = np.repeat(tf[:, None], nums[0] + 1, axis=1)
        extra = np.stack([np.cos(tf), np.zeros(df.size)], axis=1)
    else:
        theta_start, extra = start
    # a pillar leaning onto the wall: each start (and map) from its branch's atlas (not for
    # the steps of a walk, which start from their own states)
    wall = (tf < ATLAS_THETA0) & (df > 0.0) if walk else np.zeros(df.size, np.bool_)
    if np.any(wall):
        theta_start, extra = np.array(theta_start), np.array(extra)
        _atlas_starts(df, tf, gf, pf, prof, tol, nums, wall, theta_start, extra, a)
    out, coefs = _kernel_run(_DRAG_INVERSE, df, tf, gf, pf, a, theta_start, extra, prof, tol, nums)
    again = np.flatnonzero(wall & (out[0] < 0))
    if again.size:
        # near rest x1 fixes Lambda only to its rounding over dx1/dLambda: there the
        # kernel's own continuation from the straight pillar may still arrive
        xb, tb, gb, pb = (np.ascontiguousarray(v[again]) for v in (df, tf, gf, pf))
        plain = np.repeat(tb[:, None], nums[0] + 1, axis=1)
        ex = np.stack([np.cos(tb), np.zeros(again.size)], axis=1)
        a[again] = 0.0
        o, c = _kernel_run(_DRAG_INVERSE, xb, tb, gb, pb, a[again], plain, ex, prof, tol, nums)
        out[:, again], coefs[:, again] = o, c
    if retry:
        _retry_finer(df, tf, gf, pf, prof, tol, nums, out, coefs)
    if walk:
        _walk_failed(df, tf, gf, pf, prof, tol, nums, out, coefs, a)
    return out, coefs, a


def _retry_finer(
    df: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    out: FloatArray,
    coefs: FloatArray,
) -> None:
    """Inverse problems whose run failed, solved again from the straight pillar on the
    ladder's finer levels alone (for the default ladder: from N = 64, then from N = 128),
    in place where that converges.

    A pillar leaning onto the wall (theta0 <= -1.5) bends in a boundary layer at its base that
    the coarsest level resolves too poorly for its Newton and continuation to reach some
    states (isolated x1 along the branch and bands of the forcing gave status -7, issue 33);
    the finer levels reach them."""
    # only where the branch has solved states in this call (a grid): a branch that fails
    # everywhere (an absurd tip load) is not one of this, and each failed run is dear
    keys = np.stack([tf, gf, pf], axis=1)
    solved = np.unique(keys[out[0] >= 0], axis=0)
    for start in range(1, len(nums)):
        bad = np.flatnonzero(out[0] < 0)
        if bad.size and solved.size:
            near = (keys[bad][:, None, :] == solved[None, :, :]).all(axis=2).any(axis=1)
            bad = bad[near]
        else:
            bad = bad[:0]
        if bad.size == 0:
            return
        sub = tuple(nums[start:])
        xb, tb, gb, pb = (np.ascontiguousarray(v[bad]) for v in (df, tf, gf, pf))
        theta_start = np.repeat(tb[:, None], sub[0] + 1, axis=1)
        extra = np.stack([np.cos(tb), np.zeros(bad.size)], axis=1)
        o, c = _kernel_run(
            _DRAG_INVERSE, xb, tb, gb, pb, np.zeros(bad.size), theta_start, extra, prof, tol, sub
        )
        on = o[0] >= 0
        out[:, bad[on]] = o[:, on]
        coefs[:, bad[on]] = c[:, on]


#: The branch grid of :func:`_on_branch` in the fraction u of the way from the straight
#: pillar's x1 to the wall's (x1 = sin(theta0) + u (+-1 - sin(theta0))): geometric from
#: rest (a pillar tilted nearly onto the wall, theta0 -> -pi/2, turns at u ~ 0.004 already),
#: fine through the snap-through windows, then geometric towards the wall (Lambda ~ 1e5 at
#: u = 0.999).
_BRANCH_GRID = np.concatenate(
    [
        np.geomspace(1e-6, 0.0075, 49)[:-1],
        np.linspace(0.0, 0.9, 121)[1:],
        1.0 - np.geomspace(0.1, 1e-3, 25)[1:],
    ]
)
#: Below this base angle a pillar may have a snap-through window (the cusp lies between
#: -1.35 and -1.3 for the sublayer; no fold was found above -1.25 in the reference or the
#: scans, theory.md §12): there the state of ``root`` is picked on the branch.
WINDOW_THETA0 = -1.2


def _on_branch(
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
    todo: NDArray[np.bool_],
    root: str,
    n_found: NDArray[np.int64] | None = None,
    unsure: NDArray[np.bool_] | None = None,
) -> None:
    """The state of ``root`` on the branch from rest, for the elements ``todo``, written into
    out, coefs and a in place (and how many states each has, into ``n_found``; into
    ``unsure`` True where that count is only a lower bound: a pillar so near the wall that
    its atlas could not cross its window, at a forcing below the window's upper fold).

    The branch Lambda(x1) of each distinct (theta0, gamma, tip load) is the inverse problem on
    a grid in x1 (one batched call, shared by the elements that have those parameters; in the
    tip displacement d = x1 - sin(theta0), the inverse's measure, as every grid here); the
    crossings of each element's forcing are its states, in the order of the branch: "low" the
    first (the state a slow ramp from rest reaches), "high" the last, "mid" the middle of
    three (status -1 if there are not three). Each state is then the forward Newton at the
    forcing, from the grid states on either side of its crossing, interpolated linearly in
    Lambda. Used where the forward Newton failed (a fold on the way of its load continuation)
    and, for every root, where a window can exist (theta0 < ``WINDOW_THETA0``).
    """
    idx = np.flatnonzero(todo & (lf != 0.0))
    if idx.size == 0:
        return
    grid = _BRANCH_GRID
    reps = grid.size
    sign = np.where(lf[idx] > 0.0, 1.0, -1.0)
    keys = np.stack([tf[idx], gf[idx], pf[idx], sign], axis=1)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    # the grid in the tip displacement d = x1 - sin(theta0), from rest (0) towards the wall
    span = uniq[:, 3] - np.sin(uniq[:, 0])
    x = (span[:, None] * grid[None, :]).reshape(-1)
    # a pillar leaning onto the wall: its branch from its atlas, not from the grid
    wall = uniq[:, 0] < ATLAS_THETA0
    grid_keys = np.flatnonzero(~wall)
    x_grid = x.reshape(-1, reps)
    lam_grid = np.full((uniq.shape[0], reps), np.nan)
    coef_grid = np.full((uniq.shape[0], reps, max(nums) + 1), np.nan)
    h_grid, a_grid, fx_grid = (np.full((uniq.shape[0], reps), np.nan) for _ in range(3))
    if grid_keys.size:
        sel = np.repeat(~wall, reps)
        rep = [np.ascontiguousarray(np.repeat(uniq[grid_keys, c], reps)) for c in range(3)]
        o, c, _ = _inverse_run(
            np.ascontiguousarray(x[sel]), rep[0], rep[1], rep[2], prof, tol, nums, retry=True
        )
        lam_grid[grid_keys] = o[12].reshape(-1, reps)
        coef_grid[grid_keys, :, : c.shape[-1]] = c[0].reshape(grid_keys.size, reps, -1)
        h_grid[grid_keys] = o[4].reshape(-1, reps)
        a_grid[grid_keys] = o[3].reshape(-1, reps)
        fx_grid[grid_keys] = o[8].reshape(-1, reps)
    fresh = np.ones(uniq.shape[0], dtype=np.bool_)
    atlases: dict[int, _Atlas] = {}
    if np.any(wall):
        need = np.zeros(uniq.shape[0])
        np.maximum.at(need, inv, np.abs(lf[idx]))
        now = (x_grid, lam_grid, coef_grid, h_grid, a_grid, fx_grid)
        grids, atlases, fresh = _atlas_rows(uniq, wall, need, now, prof, tol, nums)
        x_grid, lam_grid, coef_grid, h_grid, a_grid, fx_grid = grids
    # each fold between grid points in place of the grid's extreme point: else a forcing
    # between the grid's extreme Lambda and the fold's misses two states of the window (an
    # atlas's once: kept with it)
    _refine_turns(
        uniq, x_grid, lam_grid, coef_grid, h_grid, prof, tol, nums, a_grid, fx_grid, fresh
    )
    for row, atlas in atlases.items():
        if fresh[row]:
            kept = (x_grid, lam_grid, coef_grid, h_grid, a_grid, fx_grid)
            atlas.refined = (len(atlas.points), tuple(g[row].copy() for g in kept))
    # every element's crossings of its forcing along its branch (from rest: Lambda = 0)
    lam_b = np.concatenate([np.zeros((uniq.shape[0], 1)), lam_grid], axis=1)[inv]
    gexc = sign[:, None] * (lam_b - lf[idx][:, None])
    finite = np.isfinite(gexc[:, :-1]) & np.isfinite(gexc[:, 1:])
    cross = finite & (np.sign(gexc[:, :-1]) != np.sign(gexc[:, 1:])) & (gexc[:, 1:] != 0.0)
    count = cross.sum(axis=1)
    if n_found is not None:
        n_found[idx] = count
    for row, atlas in atlases.items():
        if unsure is not None and atlas.crossed and not atlas.open:
            # the march stopped: in d through the window (before d replaced x1 as its
            # measure: theta0 = -1.5707, issue 33), the window's far states never followed,
            # so every forcing up to its upper fold; or in Lambda beyond it (theta0 = -1.57078
            # at 1.07e5), the forcings beyond the march's end, up to that fold
            top = max(p.lam for p in atlas.points)
            end = atlas.points[-1].lam if atlas.through else 0.0
            near = (inv == row) & (np.abs(lf[idx]) <= top) & (np.abs(lf[idx]) > end)
            unsure[idx[near]] = True
    pick = np.full(idx.size, -1)
    for k in np.flatnonzero(count > 0):
        where = np.flatnonzero(cross[k])
        if root == "low":
            pick[k] = where[0]
        elif root == "high":
            pick[k] = where[-1]
        elif count[k] == 3:
            pick[k] = where[1]
    good = np.flatnonzero(pick >= 0)
    bad = idx[pick < 0]
    out[0, bad] = -1 if root == "mid" else -7
    out[4:, bad] = np.nan
    coefs[:, bad, :] = np.nan
    if good.size == 0:
        return
    e = idx[good]
    j = pick[good]  # the crossing lies between branch points j and j + 1 (0 = rest)
    gu = inv[good]
    lam0 = lam_b[good, j]
    lam1 = lam_b[good, j + 1]
    wgt = np.clip((lf[e] - lam0) / np.where(lam1 != lam0, lam1 - lam0, 1.0), 0.0, 1.0)
    # the start: the grid states on either side, at the nodes of the forcing's own map (near
    # the wall: the map of the drag of the states, whose base layer the start's misses)
    _, a2 = _start_load(lf[e], tf[e], pf[e], prof)
    jm = np.maximum(j - 1, 0)
    fx0 = np.where(j == 0, 0.0, fx_grid[gu, jm])
    a2 = np.where(wall[gu], _drag_map((1.0 - wgt) * fx0 + wgt * fx_grid[gu, j]), a2)
    s2 = _mapped_nodes(a2, nums[0])
    th1 = _theta_at(coef_grid[gu, j], a_grid[gu, j], s2)
    th0 = np.where(
        (j == 0)[:, None], tf[e][:, None], _theta_at(coef_grid[gu, jm], a_grid[gu, jm], s2)
    )
    h0 = np.where(j == 0, np.cos(tf[e]), h_grid[gu, np.maximum(j - 1, 0)])
    h1 = h_grid[gu, j]
    start = np.ascontiguousarray((1.0 - wgt)[:, None] * th0 + wgt[:, None] * th1)
    hs = np.ascontiguousarray(((1.0 - wgt) * h0 + wgt * h1)[:, None])
    o2, c2 = _kernel_run(_DRAG, lf[e], tf[e], gf[e], pf[e], a2, start, hs, prof, tol, nums)
    # x1 (and d) moves monotonically along the branch: the state of the crossing lies in its
    # cell; a Newton that went to another state of the window (near a fold the two that merge
    # there are close) is replaced by the root of Lambda(d) = forcing in the cell
    x_b = np.concatenate([np.zeros((uniq.shape[0], 1)), x_grid], axis=1)
    xa, xb = x_b[gu, j], x_b[gu, j + 1]
    lo, hi = np.minimum(xa, xb), np.maximum(xa, xb)
    slack = 1e-12 * np.maximum(np.abs(lo), np.abs(hi))
    miss = ~((o2[0] >= 0) & (o2[14] >= lo - slack) & (o2[14] <= hi + slack))
    if np.any(miss):
        m = np.flatnonzero(miss)
        o3, c3 = _cell_root(xa[m], xb[m], lf[e][m], tf[e][m], gf[e][m], pf[e][m], prof, tol, nums)
        o2[:, m] = o3
        c2 = np.array(c2)
        width = min(c2.shape[-1], c3.shape[-1])
        c2[:, m, :] = np.nan
        c2[:, m, :width] = c3[:, :, :width]
        a2 = np.where(miss, o2[3], a2)
    out[:, e] = o2
    coefs[:, e, : c2.shape[-1]] = c2
    a[e] = a2


#: Steps of the golden-section search for a fold (its bracket shrinks by 0.618 a step: 1e-12
#: of it after 58). For root= it stops at a bracket of 1e-9 of the tip displacement
#: x1 - sin(theta0) (relative: near the wall the fold lies at d ~ 1e-9): Lambda is flat at the
#: fold, so its extreme value is then within ~1e-18 relative, below rounding.
_GOLDEN_STEPS = 80
_GOLDEN_XTOL = 1e-9
_GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)


def _golden_max(
    value: Callable[[FloatArray], FloatArray],
    a: FloatArray,
    b: FloatArray,
    xtol: float,
    relative: bool = False,
) -> tuple[FloatArray, FloatArray]:
    """Maxima of ``value`` (elementwise, one call a step for every bracket) on the brackets
    [a, b] (either order) by golden-section search, to a bracket of ``xtol`` relative (and
    absolute below 1, unless ``relative``: for a tip displacement, whose size is its own
    scale): (x, value there)."""
    a, b = np.array(a, dtype=np.float64), np.array(b, dtype=np.float64)
    c, d = b - _GOLDEN * (b - a), a + _GOLDEN * (b - a)
    fc, fd = value(c), value(d)
    for _ in range(_GOLDEN_STEPS):
        size = np.abs(a) if relative else np.maximum(1.0, np.abs(a))
        if np.all(np.abs(b - a) <= xtol * size):
            break
        left = fc > fd  # the maximum lies in [a, d]: d <- c, and a new c
        b, a = np.where(left, d, b), np.where(left, a, c)
        new = np.where(left, b - _GOLDEN * (b - a), a + _GOLDEN * (b - a))
        f_new = value(new)
        c, d, fc, fd = (
            np.where(left, new, d),
            np.where(left, c, new),
            np.where(left, f_new, fd),
            np.where(left, fc, f_new),
        )
    return np.where(fc > fd, c, d), np.maximum(fc, fd)


def _grid_turns(
    lam_grid: FloatArray,
) -> tuple[NDArray[np.intp], NDArray[np.intp], FloatArray]:
    """The turns of Lambda along each row of branch grids (rows, points): (row, i, kind) of
    each, a fold between points i and i + 2; kind 1 where Lambda rises then falls (a
    maximum), -1 for a minimum. Points with a non-finite Lambda turn nothing."""
    dl = np.diff(lam_grid, axis=1)
    turn = np.isfinite(dl[:, :-1]) & np.isfinite(dl[:, 1:]) & (dl[:, :-1] * dl[:, 1:] < 0.0)
    kk, ii = np.nonzero(turn)
    return kk, ii, np.where(dl[kk, ii] > 0.0, 1.0, -1.0)


def _refine_turns(
    keys: FloatArray,
    x_grid: FloatArray,
    lam_grid: FloatArray,
    coef_grid: FloatArray,
    h_grid: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    a_grid: FloatArray | None = None,
    fx_grid: FloatArray | None = None,
    rows: NDArray[np.bool_] | None = None,
) -> None:
    """Each turn of Lambda along a branch grid (a fold between grid points i and i + 2; the
    grid's abscissa ``x_grid`` the tip displacement x1 - sin(theta0)) refined by a
    golden-section search in it (to a relative bracket), every turn of every key at once (one
    batched inverse a step), and the fold's state written in place of the grid's extreme point
    i + 1 (x1 stays monotone along the grid), in place (with its map and drag F_x(0) into
    ``a_grid`` and ``fx_grid`` where given); only the turns of ``rows`` where given."""
    kk, ii, kind = _grid_turns(lam_grid)
    if rows is not None:
        mine = rows[kk]
        kk, ii, kind = kk[mine], ii[mine], kind[mine]
    if kk.size == 0:
        return
    t, g, p = (np.ascontiguousarray(keys[kk, c]) for c in range(3))

    def value(xs: FloatArray) -> FloatArray:
        o, _, _ = _inverse_run(np.ascontiguousarray(xs), t, g, p, prof, tol, nums)
        return np.where(np.isfinite(o[12]), kind * o[12], -np.inf)

    xf, _ = _golden_max(value, x_grid[kk, ii], x_grid[kk, ii + 2], _GOLDEN_XTOL, relative=True)
    o, cf, _ = _inverse_run(np.ascontiguousarray(xf), t, g, p, prof, tol, nums)
    ok = (o[0] >= 0) & np.isfinite(o[12]) & (kind * o[12] >= kind * lam_grid[kk, ii + 1])
    kk, ii, o, cf = kk[ok], ii[ok], o[:, ok], cf[:, ok]
    x_grid[kk, ii + 1] = xf[ok]
    lam_grid[kk, ii + 1] = o[12]
    h_grid[kk, ii + 1] = o[4]
    if a_grid is not None and fx_grid is not None:
        a_grid[kk, ii + 1] = o[3]
        fx_grid[kk, ii + 1] = o[8]
    width = min(coef_grid.shape[-1], cf.shape[-1])
    coef_grid[kk, ii + 1, :] = np.nan
    coef_grid[kk, ii + 1, :width] = cf[0][:, :width]


#: Illinois steps of :func:`_cell_root` (superlinear: ~10 reach the rounding of d).
_CELL_STEPS = 60


def _cell_root(
    xa: FloatArray,
    xb: FloatArray,
    lam: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> tuple[FloatArray, FloatArray]:
    """The states where Lambda(d) = ``lam`` with the tip displacement d = x1 - sin(theta0)
    between the branch points xa and xb (one crossing there): the Illinois method in d, every
    element at once (one batched inverse a step), to the rounding of d, then the inverse state
    at the root: (out, coefs)."""
    tf, gf, pf = (np.ascontiguousarray(v) for v in (tf, gf, pf))

    def residual(xs: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        o, cf, _ = _inverse_run(np.ascontiguousarray(xs), tf, gf, pf, prof, tol, nums)
        return o[12] - lam, o, cf

    a, b = xa.copy(), xb.copy()
    fa, oa, ca = residual(a)
    fb, ob, cb = residual(b)
    # a branch point at rest (Lambda = 0) or a fold may sit exactly on the forcing: done
    best_o = np.where((fa == 0.0)[None, :], oa, ob)
    best_c = np.where((fa == 0.0)[None, :, None], ca, cb)
    done = (fa == 0.0) | (fb == 0.0) | ~np.isfinite(fa) | ~np.isfinite(fb)
    side = np.zeros(a.size)
    for _ in range(_CELL_STEPS):
        if np.all(done):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            x = np.where(fb != fa, b - fb * (b - a) / (fb - fa), 0.5 * (a + b))
        inside = (x - a) * (x - b) < 0.0
        x = np.where(inside, x, 0.5 * (a + b))
        fx, ox, cx = residual(x)
        upd = ~done
        best_o[:, upd], best_c[:, upd] = ox[:, upd], cx[:, upd]
        same = np.sign(fx) == np.sign(fb)
        # Illinois: halve the stale end's value when the same end is kept twice
        fa = np.where(upd & same & (side == 1.0), 0.5 * fa, fa)
        a = np.where(upd & ~same, b, a)
        fa = np.where(upd & ~same, fb, fa)
        b, fb = np.where(upd, x, b), np.where(upd, fx, fb)
        side = np.where(upd, np.where(same, 1.0, -1.0), side)
        done |= (
            (fx == 0.0)
            | ~np.isfinite(fx)
            | (np.abs(b - a) <= 4e-16 * np.maximum(np.abs(a), np.abs(b)))
        )
    return best_o, best_c


# ------------------------------------------------------------------------------------------
# The branch near the wall: an atlas of states marched along it (issue 33)
# ------------------------------------------------------------------------------------------

#: Below this base angle (after the mirror of a flow towards -x) the branch of a pillar may
#: be read from its atlas (:func:`_atlas`) where the inverse from rest fails: a pillar
#: leaning onto the wall. At -1.5 the inverse grid reaches every state (issue 33).
ATLAS_THETA0 = -1.5
#: The first forcing of the atlas's march from rest, and its step factors: grown to at most
#: ``_ATLAS_GROW`` after an easy step, cut to a quarter of its excess over 1 after a failed
#: one; the march ends at a fold when the factor's excess falls below ``_ATLAS_FOLD``.
_ATLAS_START = 1e-2
#: ... or later, where the straight pillar's theta - theta0 ~ Lambda cos^2(theta0)/11 reaches
#: this (some 5000 times theta's rounding): nearer the wall (theta0 = -pi/2 + 1e-7) the
#: first step's deflection would be below theta's rounding and its x1 - sin(theta0) zero
_ATLAS_TURN = 1e-12
#: ... but not beyond this: the window's upper fold lies at ~2.6/cos(theta0) for the
#: sublayer (27330 at -1.5707), so the first step stays below 1e-3 of it down to
#: cos(theta0) = 3.3e-9; nearer the wall the atlas gives up (status -7, no state claimed)
_ATLAS_FIRST_MAX = 1e6
_ATLAS_GROW = 2.0
_ATLAS_FOLD = 1e-7
#: A step of the forward march that takes more Newton iterations than this (every level)
#: counts as failed: its Newton may have left the branch for another state (the inverse's
#: one state per x1 cannot).
_ATLAS_NIT = 40
#: Kernel calls of one march at most (each a few Newton steps; a failed one the kernel's
#: continuation from rest).
_ATLAS_CALLS = 400
#: The least step of the march through the window, relative to the tip displacement (and a
#: tenth of it ends the march): a few hundred times its rounding.
_ATLAS_DSTEP = 1e-13
#: The largest forcing an atlas is extended to (for a tip deflection nearer the wall).
_ATLAS_MAX = 1e12
#: The atlases kept (per theta0, gamma, tip load, profile and ladder), the oldest dropped.
_ATLAS_CACHE: dict[tuple[Any, ...], _Atlas] = {}
_ATLAS_KEEP = 32


@dataclass
class _Point:
    """One state of an atlas: the tip displacement d = x1 - sin(theta0) (the march's measure:
    near the wall x1 ~ -1 rounds away the changes of d along the window), Lambda, h1,
    dx1/dLambda, the map parameter a, the drag F_x(0) (which sets the next map), the
    Chebyshev coefficients of theta (in xi of map a)."""

    d: float
    lam: float
    h: float
    slope: float
    a: float
    fx: float
    coef: FloatArray


@dataclass
class _Atlas:
    """The states of one pillar's branch in the order of x1: from rest by a march in Lambda
    to the upper fold, through the window by a march in the tip displacement x1 -
    sin(theta0), then again in Lambda."""

    points: list[_Point]
    open: bool = True  # the marches so far arrived (the atlas may be extended)
    crossed: bool = False  # the march through the window was tried (it is done once)
    through: bool = False  # and it got through (Lambda rose past the upper fold again)
    #: the branch grid of the points but rest with its folds refined (:func:`_refine_turns`),
    #: and how many points it was made of
    refined: tuple[int, tuple[FloatArray, ...]] | None = None

    def arrays(self) -> tuple[FloatArray, ...]:
        """(d = x1 - sin(theta0), Lambda, h1, a, F_x(0)) of the points and their theta
        coefficients (n, K)."""
        pts = self.points
        cols = [np.array([getattr(p, f) for p in pts]) for f in ("d", "lam", "h", "a", "fx")]
        return (*cols, np.stack([p.coef for p in pts]))


def _theta_at(coef: FloatArray, a: FloatArray, s: FloatArray) -> FloatArray:
    """theta of states (Chebyshev coefficients (n, K) in xi of their maps a (n,)) at arc
    lengths s (n, M): the inverse of the map s = expm1(a y)/expm1(a), then Clenshaw."""
    a = np.asarray(a, dtype=np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        den = np.where(a != 0.0, a, 1.0)[:, None]
        y = np.where(a[:, None] != 0.0, np.log1p(s * np.expm1(a)[:, None]) / den, s)
    return _clenshaw(coef, 2.0 * np.clip(y, 0.0, 1.0) - 1.0)


def _drag_map(fx: Any) -> FloatArray:
    """The map parameter of a state whose drag is F_x(0) (the base layer's tension), as
    ``loaded``'s for a tip load of that size."""
    f = np.atleast_1d(np.asarray(fx, dtype=np.float64))
    zero = np.zeros(f.size)
    return _map_parameter(2, np.where(np.isfinite(f), f, 0.0), zero, zero, np.ones(f.size))


def _atlas_step(
    code: int,
    value: float,
    key: tuple[float, float, float],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    cur: _Point,
    prev: _Point | None,
) -> _Point | None:
    """One step of a march: the state of ``code`` (forward: Lambda = value; inverse: the tip
    displacement d = value) from the secant predictor through ``prev`` and ``cur`` (along
    Lambda or d), at the map of cur's drag; None where the kernel fails or labours."""
    a = float(_drag_map(cur.fx)[0])
    s = _mapped_nodes(np.array([a]), nums[0])
    theta = _theta_at(cur.coef[None, :], np.array([cur.a]), s)[0]
    h, lam = cur.h, cur.lam
    if prev is not None:
        along = (prev.lam, cur.lam) if code == _DRAG else (prev.d, cur.d)
        if along[1] != along[0]:
            r = (value - along[1]) / (along[1] - along[0])
            theta = theta + r * (theta - _theta_at(prev.coef[None, :], np.array([prev.a]), s)[0])
            h, lam = h + r * (h - prev.h), lam + r * (lam - prev.lam)
    extra = [[h]] if code == _DRAG else [[h, lam]]
    t0, g, p = key
    o, c = _kernel_run(
        code,
        np.array([value]),
        np.array([t0]),
        np.array([g]),
        np.array([p]),
        np.array([a]),
        np.ascontiguousarray(theta[None, :]),
        np.array(extra, dtype=np.float64),
        prof,
        tol,
        nums,
    )
    if not (o[0, 0] >= 0 and (code == _DRAG_INVERSE or o[1, 0] <= _ATLAS_NIT)):
        return None
    coef = np.nan_to_num(c[0, 0], nan=0.0)
    return _Point(
        float(o[14, 0]), float(o[12, 0]), float(o[4, 0]), float(o[13, 0]), a, float(o[8, 0]), coef
    )


def _march_forcing(
    pts: list[_Point],
    lam_end: float,
    key: tuple[float, float, float],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> bool:
    """March Lambda up from the last point to ``lam_end`` (the forward problem, each step
    from the secant through the last two points), appending the states: True where it
    arrives, False where its steps shrink to nothing (a fold) or run out."""
    fac = _ATLAS_GROW
    for _ in range(_ATLAS_CALLS):
        cur = pts[-1]
        if cur.lam >= lam_end:
            return True
        first = max(_ATLAS_START, _ATLAS_TURN * 11.0 / math.cos(key[0]) ** 2)
        if cur.lam == 0.0 and first > _ATLAS_FIRST_MAX:
            return False  # so near the wall that theta cannot carry the deflection
        lam = min(lam_end, first if cur.lam == 0.0 else cur.lam * fac)
        prev = pts[-2] if len(pts) > 1 else None
        new = _atlas_step(_DRAG, lam, key, prof, tol, nums, cur, prev)
        # on the rising part Lambda and x1 grow together (dx1/dLambda > 0), by at most
        # what the larger slope gives: else the Newton went to another state
        if (
            new is None
            or not new.slope > 0.0
            or not 0.0 < new.d - cur.d <= 2.0 * max(new.slope, cur.slope) * (lam - cur.lam)
        ):
            fac = 1.0 + 0.25 * (fac - 1.0)
            if fac - 1.0 < _ATLAS_FOLD:
                return False
            continue
        pts.append(new)
        fac = min(_ATLAS_GROW, 1.0 + 2.0 * (fac - 1.0))
    return False


def _march_deflection(
    pts: list[_Point],
    lam_past: float,
    key: tuple[float, float, float],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> bool:
    """March the tip displacement d = x1 - sin(theta0) up from the last point (the inverse
    problem, each step from the secant through the last two points) across a snap-through
    window: until Lambda, having fallen, rises again (dx1/dLambda > 0) beyond ``lam_past``
    (or beyond twice it, where the march in Lambda stopped short of a fold). True where it
    gets there. Its steps are relative to d: near the wall (theta0 = -1.5707) the window's
    upper fold lies at d ~ 1e-9 and the branch turns there within ~1e-5 of d, 1e-14 in x1,
    below x1's rounding (issue 33)."""
    span = 1.0 - math.sin(key[0])  # the displacement from rest to the wall
    step = 4.0 * (pts[-1].d - pts[-2].d) if len(pts) > 1 else 1e-9
    step = max(step, _ATLAS_DSTEP * pts[-1].d)
    turned = False  # past the fold: Lambda has fallen (dx1/dLambda < 0)
    for _ in range(_ATLAS_CALLS):
        cur = pts[-1]
        turned |= cur.slope < 0.0
        if cur.slope > 0.0 and (turned and cur.lam > lam_past or cur.lam > 2.0 * lam_past):
            return True
        d_new = cur.d + step
        if not d_new < span:  # towards the wall (a fold beyond 1e5): halve the way left
            step = 0.5 * (span - cur.d)
            d_new = cur.d + step
            if not (d_new < span and step > _ATLAS_DSTEP * cur.d):
                return False
        new = _atlas_step(_DRAG_INVERSE, d_new, key, prof, tol, nums, cur, pts[-2])
        if new is None:
            step *= 0.25
            if step < 0.1 * _ATLAS_DSTEP * cur.d:
                return False
            continue
        pts.append(new)
        step = min(2.0 * step, 0.05)
    return False


def _atlas(
    key: tuple[float, float, float],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    lam_top: float = 0.0,
    d_top: float = 0.0,
) -> _Atlas:
    """The atlas of the branch of ``key`` (theta0, gamma, tip load; a flow towards +x) to at
    least the forcing ``lam_top`` and the tip displacement x1 - sin(theta0) ``d_top``
    (cached, and extended by a later call that needs more).

    The inverse problem in x1 cannot start from rest for a pillar lying within a few
    hundredths of a radian of the wall: there x1 hardly moves with Lambda (dx1/dLambda = 11
    cos^3(theta0)/120, 5e-11 at theta0 = -1.57), so Lambda is fixed by x1 only to its
    rounding over that, and the inverse's Newton stalls; and at a large forcing the plain
    nodes miss the boundary layer at the base. So the branch is marched: the forward
    problem in Lambda from rest up to the upper fold of the window (where its steps shrink
    to nothing), the inverse in the tip displacement x1 - sin(theta0) (which, unlike x1,
    resolves the window's turn near the wall) through the window until Lambda rises past that
    fold again, then the forward problem in Lambda; every step from the secant through the two
    states before it, at the map of the previous state's drag (its base layer)."""
    ck = (*key, prof.tobytes(), tuple(nums), tol)
    atlas = _ATLAS_CACHE.get(ck)
    if atlas is None:
        t0 = key[0]
        coef = np.zeros(max(nums) + 1)
        coef[0] = t0
        atlas = _Atlas([_Point(0.0, 0.0, math.cos(t0), math.nan, 0.0, 0.0, coef)])
        if len(_ATLAS_CACHE) >= _ATLAS_KEEP:
            _ATLAS_CACHE.pop(next(iter(_ATLAS_CACHE)))
        _ATLAS_CACHE[ck] = atlas
    pts = atlas.points
    while atlas.open and pts[-1].lam < _ATLAS_MAX and (pts[-1].lam < lam_top or pts[-1].d < d_top):
        # from rest through the window first, wherever the forcing asked for lies: a forcing
        # in the window has three states
        target = max(lam_top, 1.0, 4.0 * pts[-1].lam) if atlas.crossed else _ATLAS_MAX
        if _march_forcing(pts, target, key, prof, tol, nums):
            continue
        # the march in Lambda ended at a fold: through the window in d, once
        atlas.open = not atlas.crossed and len(pts) > 1
        if atlas.open:
            atlas.crossed = True
            atlas.open = atlas.through = _march_deflection(pts, pts[-1].lam, key, prof, tol, nums)
    return atlas


def _atlas_rows(
    uniq: FloatArray,
    wall: NDArray[np.bool_],
    need: FloatArray,
    grids: tuple[FloatArray, ...],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
) -> tuple[tuple[FloatArray, ...], dict[int, _Atlas], NDArray[np.bool_]]:
    """The branch grids (the tip displacement x1 - sin(theta0), Lambda, theta coefficients, h1,
    map, F_x(0); a row per key of ``uniq``) with the rows of the keys ``wall`` replaced by
    their atlases (past twice the forcing ``need`` of each, without the rest state), all rows
    padded with NaN at the end to the longest; the atlases (by row); and which rows still need
    their folds refined (an atlas's refined grid is kept with it)."""
    atlases = {
        int(k): _atlas(
            (float(uniq[k, 0]), float(uniq[k, 1]), float(uniq[k, 2])),
            prof[:1],
            tol,
            nums,
            lam_top=2.0 * float(need[k]),
        )
        for k in np.flatnonzero(wall)
    }
    fresh = np.ones(uniq.shape[0], dtype=np.bool_)
    rows: dict[int, tuple[FloatArray, ...]] = {}
    for k, atlas in atlases.items():
        if atlas.refined is not None and atlas.refined[0] == len(atlas.points):
            rows[k] = atlas.refined[1]
            fresh[k] = False
        else:
            arr = atlas.arrays()
            rows[k] = tuple(arr[c][1:] for c in (0, 1, 5, 2, 3, 4))  # the grids' order
    width = max([grids[0].shape[1]] + [r[0].shape[0] for r in rows.values()])
    out = []
    for i, g in enumerate(grids):
        new = np.full((g.shape[0], width, *g.shape[2:]), np.nan)
        new[:, : g.shape[1]] = g
        for k, row in rows.items():
            new[k] = np.nan
            new[k, : row[i].shape[0]] = row[i]
        out.append(new)
    return tuple(out), atlases, fresh


def _atlas_starts(
    xf: FloatArray,
    tf: FloatArray,
    gf: FloatArray,
    pf: FloatArray,
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    wall: NDArray[np.bool_],
    theta: FloatArray,
    extra: FloatArray,
    a: FloatArray,
) -> None:
    """Starts of the inverse problems ``wall`` (tip displacements ``xf`` = x1 - sin(theta0) >
    0, theta0 < ATLAS_THETA0) from the atlas of their branch: the two atlas states around
    each, interpolated linearly in the displacement (theta at the first level's nodes of the
    map of their drag, h1, Lambda), in place."""
    idx = np.flatnonzero(wall)
    rows = prof.shape[0] > 1
    keys = np.stack([tf[idx], gf[idx], pf[idx]], axis=1)
    if rows:
        keys = np.concatenate([keys, idx[:, None].astype(np.float64)], axis=1)
    uniq, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    for u in range(uniq.shape[0]):
        mine = idx[inv == u]
        row = prof[mine[:1]] if rows else prof
        key = (float(uniq[u, 0]), float(uniq[u, 1]), float(uniq[u, 2]))
        xa, la, ha, aa, fa, ca = _atlas(key, row, tol, nums, d_top=float(xf[mine].max())).arrays()
        j = np.clip(np.searchsorted(xa, xf[mine], side="right") - 1, 0, xa.size - 2)
        if xa.size < 2:
            continue
        w = np.clip((xf[mine] - xa[j]) / (xa[j + 1] - xa[j]), 0.0, 1.0)
        am = _drag_map((1.0 - w) * fa[j] + w * fa[j + 1])
        s = _mapped_nodes(am, nums[0])
        th = (1.0 - w)[:, None] * _theta_at(ca[j], aa[j], s) + w[:, None] * _theta_at(
            ca[j + 1], aa[j + 1], s
        )
        theta[mine] = th
        extra[mine, 0] = (1.0 - w) * ha[j] + w * ha[j + 1]
        extra[mine, 1] = (1.0 - w) * la[j] + w * la[j + 1]
        a[mine] = am


def _atlas_branch(
    key: tuple[float, float, float],
    prof: FloatArray,
    tol: float,
    nums: tuple[int, ...],
    lam_top: float,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The branch of a pillar leaning onto the wall (``key``: theta0 < ``ATLAS_THETA0``, a
    flow towards +x) from its atlas, past ``lam_top``, with its folds refined as for
    ``root=`` (:func:`_refine_turns`, kept with the atlas): (x1, Lambda, h1, folds (k, 2)
    of Lambda and x1), rest not included; x1 = sin(theta0) + d of the atlas's tip
    displacements d."""
    uniq = np.array([key], dtype=np.float64)
    none = np.full((1, 0), np.nan)
    empty = (none, none, np.full((1, 0, max(nums) + 1), np.nan), none, none, none)
    grids, atlases, fresh = _atlas_rows(
        uniq, np.array([True]), np.array([0.5 * lam_top]), empty, prof[:1], tol, nums
    )
    x, lam, coef, h, a, fx = grids
    _refine_turns(uniq, x, lam, coef, h, prof[:1], tol, nums, a, fx, fresh)
    atlas = atlases[0]
    if fresh[0]:
        atlas.refined = (len(atlas.points), tuple(g[0].copy() for g in grids))
    ok = np.isfinite(lam[0])
    _, turns, _ = _grid_turns(lam[:, ok])
    xs, ls = math.sin(key[0]) + x[0, ok], lam[0, ok]
    return xs, ls, h[0, ok], np.stack([ls[turns + 1], xs[turns + 1]], axis=1)
