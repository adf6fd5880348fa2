"""The inverse problem: the forcing from what a microscope sees.

A micropillar shear-stress sensor measures the deflection of a pillar's tip and must return the
flow. On the physical branch (sign = +1, n = 0) every state is a point t of the explicit curve of
:func:`hairbed.from_parameter` (theory.md §2), and the tip values x1(t) and h1(t) depend on
t and theta0 only, not on eps: eps enters only in omega^2 = omega_eps^2 (1 - eps h1)
(eq. (34)). So the inverse problem is a root find in the one real number t, done here by a
vectorised bracketed method (Chandrupatla's, inverse quadratic interpolation safeguarded by
bisection, from :mod:`scipy.optimize.elementwise`), after which omega^2 is explicit. The
parameter t, not xi, is the unknown: at strong forcing xi rounds to 1 (omega^2 above ~400)
while t and the tip values stay exact.

- The tip deflection x1 rises monotonically with t from sin(theta0) at rest to 1 (theory.md
  §5), so :func:`omega2_from_tip_deflection` has one answer. Where three states share a
  forcing (theta0 < 0, eps near 1) it is the one whose tip is at x1, whichever root that is.
- The tip height h1 is not monotone when theta0 < 0: the flow first lifts a hair leaning into it
  and then bends it over, so :func:`omega2_from_tip_height` can have two answers.
- :func:`hairbed.profile_fit.fit_profile` fits (omega^2, theta0) to measured points along a
  whole hair (also importable from here).

A hair lying flat (x1 = 1, h1 = 0, every height of a profile 0) is the limit omega^2 -> inf,
not a state: every inverse refuses it with a ValueError naming the reachable range, x1 in
[sin(theta0), 1), h1 in [1e-150, :func:`max_tip_height`] (below, omega^2 ~ 2/h1^2
overflows), and :class:`hairbed.HairBed` a tip deflection in (-L, L). A tip deflection that
rounds to 1 in double precision (omega^2 above ~1e32 at theta0 = 0, sooner near pi/2) has no
finite forcing to give back.

To first order in the forcing the hair is a cantilever under a point load at its tip (the
horizontal force F = omega_eps^2 E I/L^2, of which cos(theta0) bends it): theta = theta0 +
omega_eps^2 cos(theta0) (sigma - sigma^2/2), the textbook x1 = F L^3/(3 E I) tilted by theta0, so

    x1 = sin(theta0) + omega^2 cos^2(theta0) / (3 (1 - eps cos theta0)) + O(omega^4),
    h1 = cos(theta0) - omega^2 sin(theta0) cos(theta0) / (3 (1 - eps cos theta0)) + O(omega^4),

using omega_eps^2 = omega^2 / (1 - eps h1) and h1 = cos(theta0) at rest. One order further, in
W = omega_eps^2 with c = cos(theta0), s = sin(theta0) (theta2'' = s theta1, same boundary
conditions):

    x1 - s = W c^2 / 3 - W^2 s c^2 / 5,     xi - s = sin(theta1) - s = W c^2 / 2 - W^2 s c^2 / 3,

which the inverse uses at very weak forcing, where x1 - sin(theta0) is lost to rounding. The
first order is the linear calibration of :func:`tip_deflection_slope` and
:func:`linear_omega2_from_tip_deflection`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._bracketing import find_minimum, find_root
from ._core.outputs import float_or_array
from ._core.solution import Solution
from ._core.solver import _from_parameter
from ._core.validation import (
    _first_index,
    check_inputs,
    check_state_inputs,
    check_tip_deflection,
)

__all__ = [
    "porous_state_from_tip_deflection",
    "linear_omega2_from_tip_deflection",
    "max_tip_height",
    "omega2_from_tip_deflection",
    "omega2_from_tip_height",
    "solution_from_tip_deflection",
    "tip_deflection_slope",
]

FloatArray = NDArray[np.float64]
FloatOrArray = float | FloatArray

#: Below this forcing omega_eps^2 the weak-forcing series replaces the root find (see
#: _t_from_tip_deflection): its relative error ~W^2 < 1e-10 beats the cancellation in x1.
_W_SERIES = 1e-5
#: Clips of the tip residual: the largest double below 1, the smallest normal double.
_BELOW_ONE = float(np.nextafter(1.0, 0.0))
_TINY = float(np.finfo(np.float64).tiny)


def _physical(t: ArrayLike, eps: ArrayLike, theta0: ArrayLike) -> Solution:
    """The physical-branch state at parameter t (theory.md §2, §3), of checked inputs."""
    return _from_parameter(t, eps, theta0)


# -- tip deflection ------------------------------------------------------------------------------


def _t_from_tip_deflection(x1: FloatArray, theta0: FloatArray) -> FloatArray:
    """Branch parameter t with x1(t) = x1, -inf where x1 = sin(theta0) (the hair at rest).

    x1 is checked (:func:`~hairbed._core.validation.check_tip_deflection`): in
    [sin(theta0), 1), or sin(theta0) itself.
    """
    s = np.sin(theta0)
    flat_x1, flat_th, flat_s = x1.ravel(), theta0.ravel(), s.ravel()
    out = np.full(flat_x1.shape, -np.inf)
    work = np.flatnonzero((flat_x1 > flat_s) & (flat_x1 < 1.0))
    if work.size == 0:
        return out.reshape(x1.shape)
    # Weak forcing: the tip values carry an absolute rounding error ~1e-16, so x1 - sin(theta0)
    # loses its relative accuracy as it -> 0. There the series in W = omega_eps^2 (module
    # docstring, carried to second order) gives t with a relative error ~W^2 instead.
    delta = flat_x1[work] - flat_s[work]
    c2 = np.cos(flat_th[work]) ** 2
    w_lin = 3.0 * delta / c2
    series = w_lin < _W_SERIES
    if np.any(series):
        s0, cc, dl = flat_s[work][series], c2[series], delta[series]
        a, b = cc / 3.0, s0 * cc / 5.0
        w = dl / a + b * dl * dl / a**3  # inverts x1 - s0 = a W - b W^2
        d = 0.5 * cc * w - s0 * cc * w * w / 3.0  # xi - s0 = sin(theta1) - s0
        out[work[series]] = np.log(d) - np.log((1.0 - s0) - d)
        work = work[~series]
        if work.size == 0:
            return out.reshape(x1.shape)
    target_x1, th, sw = flat_x1[work], flat_th[work], flat_s[work]
    # logit-like residual: ~ t as t -> -inf and ~ ln t as t -> +inf, easy to interpolate
    target = np.log(target_x1 - sw) - np.log1p(-target_x1)

    # x1 <= sin(theta0) and x1 >= 1 are clipped to the nearest representable values: a finite,
    # monotone residual, as the bracketed search needs
    res = find_root(
        _tip_deflection_residual,
        -1.0,
        1.0,
        args=(th, sw, target),
        grow=True,
        xatol=1e-15,
        what="the branch parameter of a tip deflection",
    )
    out[work] = res.x
    return out.reshape(x1.shape)


def _tip_deflection_residual(
    t: FloatArray, theta0: FloatArray, s: FloatArray, target: FloatArray
) -> FloatArray:
    """logit-like residual ln(x1 - s) - ln(1 - x1) - target, increasing in t [-]."""
    x = np.asarray(_physical(t, 0.0, theta0).tip_deflection, dtype=np.float64)
    x = np.minimum(x, _BELOW_ONE)
    return np.log(np.maximum(x - s, _TINY)) - np.log1p(-x) - target


def solution_from_tip_deflection(x1: Any, eps: Any, theta0: Any = 0.0) -> Solution:
    """The physical state whose tip deflection is ``x1`` (see :func:`omega2_from_tip_deflection`).

    Returns
    -------
    Solution
        From :func:`hairbed.from_parameter`, so that its omega2 is exact even where xi rounds
        to 1.
    """
    x1, eps, theta0 = check_tip_deflection(x1, eps, theta0)
    return _solution_from_tip_deflection(x1, eps, theta0)


def _solution_from_tip_deflection(x1: FloatArray, eps: Any, theta0: FloatArray) -> Solution:
    """:func:`solution_from_tip_deflection` of checked inputs (x1 in [sin theta0, 1], eps and
    theta0 in range, x1 and theta0 of one shape), trusted."""
    t = _t_from_tip_deflection(x1, theta0)
    return _physical(t, eps, theta0)


def porous_state_from_tip_deflection(
    x1: Any, eps: Any, theta0: Any = 0.0, *, kappa: Any, gamma: Any = 1.0
) -> Any:
    """The porous bed's state (theory.md §13) whose tip deflection is ``x1``, the wall drive's
    forcing omega2 solved with it (:class:`hairbed.PorousState`, its ``omega2`` the answer).

    The collocation of :func:`hairbed.solve_porous` with omega2 one more unknown and the tip
    deflection one more row, from the closed-form hair (§3) with that tip deflection under a
    fixed tip load; where Newton fails, the continuation of the tip deflection from rest. A
    tip deflection determines the state, even inside a window of several states.

    Parameters
    ----------
    x1 : array_like
        Tip deflection x(1) [L], in [sin(theta0), 1) (flow towards +x).
    eps, theta0, kappa, gamma : array_like
        As in :func:`hairbed.solve_porous`; all broadcast together.

    Returns
    -------
    PorousState

    Examples
    --------
    >>> import hairbed
    >>> st = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=0.1)
    >>> inv = porous_state_from_tip_deflection(st.tip_deflection, 0.5, 0.3, kappa=0.1)
    >>> round(inv.omega2, 10)
    2.0
    """
    from ._core import porous
    from ._core._kernels import state as closed
    from ._core.loaded import _matrices

    v, e, t = check_tip_deflection(x1, eps, theta0)
    _, _, arrays = porous._check(0.0, e, t, kappa, gamma, None, None)
    shape = arrays[0].shape
    flat = tuple(np.ascontiguousarray(a, dtype=np.float64).reshape(-1) for a in arrays)
    xf = np.ascontiguousarray(np.broadcast_to(v, shape), dtype=np.float64).reshape(-1)
    tf = flat[2]
    # the closed-form hair with this tip deflection under a fixed tip load W (eps = 0)
    tpar = _t_from_tip_deflection(xf, tf)
    fixed = _from_parameter(tpar, np.zeros(xf.size), tf)
    big_w = np.asarray(fixed.omega2, dtype=np.float64).reshape(-1)
    h = np.asarray(fixed.tip_height, dtype=np.float64).reshape(-1)
    num = porous.LADDER[0]
    sig = np.broadcast_to(0.5 * (_matrices(num)[0] + 1.0), (xf.size, num + 1))
    out6 = np.empty((6, xf.size, num + 1))
    closed.shape_array(tpar, np.zeros(xf.size), tf, 1, 0, np.ascontiguousarray(sig), out6)
    # omega2 of the same load through the bed: the linear theory's ratio, the gap at h
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        unit = porous._linear_deflection(np.ones(xf.size), flat[1], flat[3], np.zeros(xf.size))
        omega2 = big_w * (1.0 - flat[1] * h) / (3.0 * unit * (1.0 - flat[1]))
    omega2 = np.where(np.isfinite(omega2), omega2, 0.0)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return porous._solve_inverse_checked(xf, flat, out6[0], h, omega2, shape)


def omega2_from_tip_deflection(x1: Any, eps: Any, theta0: Any = 0.0) -> FloatOrArray:
    """Forcing omega^2 of the physical state whose tip deflection is ``x1``.

    Parameters
    ----------
    x1 : array_like
        Tip deflection x(1) [-] (in units of the hair length), in [sin(theta0), 1). x1 = 1
        is a hair lying flat, the limit omega2 -> inf and no state: a ValueError, like every
        inverse here at that limit (module docstring).
    eps : array_like
        Confinement L/H [-], in [0, 1).
    theta0 : array_like
        Base angle [rad], in (-pi/2, pi/2).

    Returns
    -------
    float or ndarray
        omega^2 [-] (0 at x1 = sin(theta0)), of the broadcast shape of the inputs.

    Raises
    ------
    ValueError
        If x1 is outside [sin(theta0), 1) or eps, theta0 are outside their ranges.

    Notes
    -----
    x1 is monotone in xi along the physical branch (theory.md §5), so the answer is unique;
    where three states share one forcing (theta0 < 0, eps near 1) the state with tip deflection
    x1 may be any of them (see :func:`hairbed.solve`'s ``root``). The root is found in the branch
    parameter t of :func:`hairbed.from_parameter`, then omega^2 follows from eq. (34).

    Examples
    --------
    >>> round(omega2_from_tip_deflection(0.615831536923675, 0.5), 10)  # theory.md §3
    2.0
    """
    sol = solution_from_tip_deflection(x1, eps, theta0)
    return float_or_array(sol.omega2)


def tip_deflection_slope(eps: Any, theta0: Any = 0.0) -> FloatOrArray:
    """Slope d x1 / d omega^2 at rest: cos^2(theta0) / (3 (1 - eps cos theta0)) [-].

    The linear (small-deflection) calibration x1 = sin(theta0) + slope * omega^2 of a cantilever
    under a point load at its tip, x1 = F L^3/(3 E I) (derivation in the module docstring). For
    theta0 = 0 it is 1 / (3 (1 - eps)).

    Examples
    --------
    >>> round(tip_deflection_slope(0.5), 12)
    0.666666666667
    """
    _, e, th = check_inputs(0.0, eps, theta0)
    return float_or_array(_slope(e, th))


def _slope(eps: Any, theta0: Any) -> Any:
    """:func:`tip_deflection_slope` of checked inputs."""
    c = np.cos(theta0)
    return c * c / (3.0 * (1.0 - eps * c))


def linear_omega2_from_tip_deflection(x1: Any, eps: Any, theta0: Any = 0.0) -> FloatOrArray:
    """The linear calibration omega^2 = (x1 - sin theta0) / slope [-].

    slope is :func:`tip_deflection_slope`.

    Exact as x1 -> sin(theta0); it underestimates the forcing more and more as the deflection
    grows: by 1% at x1 = 0.098 and 10% at x1 = 0.31 for theta0 = 0, eps = 0, and sooner in a
    tight channel (1% at x1 = 0.040, 10% at x1 = 0.13 for eps = 0.9), because the bending hair
    also widens the gap (see the tests).
    """
    x1, e, th = check_tip_deflection(x1, eps, theta0)
    return float_or_array((x1 - np.sin(th)) / _slope(e, th))


# -- tip height ----------------------------------------------------------------------------------

#: The lowest tip height inverted: the forcing omega^2 ~ 2/h1^2 overflows below.
_H1_MIN = 1e-150
#: Coarse grid on which the maximum of h1(t) is located before it is refined. The maximum lies
#: near t ~ ln|theta0| for a slightly leaning hair, so the grid starts far out.
_T_SCAN = np.arange(-60.0, 40.5, 0.5)


def _h1(t: FloatArray, theta0: FloatArray) -> FloatArray:
    return np.asarray(_physical(t, 0.0, theta0).tip_height, dtype=np.float64)


def _minus_h1(t: FloatArray, theta0: FloatArray) -> FloatArray:
    return -_h1(t, theta0)


def _t_of_max_tip_height(theta0: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Where h1(t) peaks on the physical branch (flattened theta0), and the peak value.

    For theta0 >= 0 the hair only bends over and h1 falls from cos(theta0) at t = -inf.
    For theta0 < 0 the flow first lifts the hair: h1 rises to a maximum (<= 1), then falls.
    """
    th = np.asarray(theta0, dtype=np.float64).ravel()
    t_max = np.full(th.shape, -np.inf)
    h_max = np.cos(th)
    lean = np.flatnonzero(th < 0.0)
    if lean.size == 0:
        return t_max, h_max
    uniq, inverse = np.unique(th[lean], return_inverse=True)
    grid = _h1(_T_SCAN[np.newaxis, :], uniq[:, np.newaxis])
    k = np.argmax(grid, axis=1)
    t_peak = _T_SCAN[k]
    # refine inside the grid (a peak on the grid's edge, for theta0 within ~1e-26 of 0-, stays
    # there): h1 is smooth and unimodal near its peak
    inner = np.flatnonzero((k > 0) & (k < _T_SCAN.size - 1))
    if inner.size:
        ki = k[inner]
        res = find_minimum(
            _minus_h1,
            _T_SCAN[ki - 1],
            _T_SCAN[ki],
            _T_SCAN[ki + 1],
            args=(uniq[inner],),
            what="the highest tip of the physical branch",
        )
        t_peak[inner] = res.x
    h_peak = np.maximum(_h1(t_peak, uniq), np.cos(uniq))
    t_max[lean] = t_peak[inverse]
    h_max[lean] = h_peak[inverse]
    return t_max, h_max


def max_tip_height(theta0: Any = 0.0) -> FloatOrArray:
    """The largest tip height h1 [-] of any physical state with base angle ``theta0``.

    cos(theta0) (the hair at rest) for theta0 >= 0; for theta0 < 0 the flow first lifts the hair
    towards the vertical and the maximum lies between cos(theta0) and 1.
    """
    _, _, th = check_inputs(0.0, 0.0, theta0)
    return float_or_array(_t_of_max_tip_height(th)[1].reshape(th.shape))


def _falling_residual(
    t: FloatArray, theta0: FloatArray, log_target: FloatArray, t_top: FloatArray
) -> FloatArray:
    """ln(h1 target) - ln h1(t), increasing for t >= t_top; not above 0 at the peak itself
    (where the peak search's rounding could put it a hair above)."""
    g = log_target - np.log(np.maximum(_h1(t, theta0), _TINY))
    return np.where(t <= t_top, np.minimum(g, 0.0), g)


def _rising_residual(
    t: FloatArray, theta0: FloatArray, target: FloatArray, t_top: FloatArray
) -> FloatArray:
    """h1(t) - h1 target, increasing for t <= t_top; not below 0 at the peak itself."""
    g = _h1(t, theta0) - target
    return np.where(t >= t_top, np.maximum(g, 0.0), g)


def omega2_from_tip_height(h1: Any, eps: Any, theta0: Any = 0.0) -> FloatArray:
    """Every forcing omega^2 of a physical state whose tip height is ``h1``.

    Parameters
    ----------
    h1 : array_like
        Tip height z(1) [-] (in units of the hair length), in [1e-150,
        :func:`max_tip_height`] (below 1e-150 the forcing, ~2/h1^2, overflows).
    eps : array_like
        Confinement L/H [-], in [0, 1).
    theta0 : array_like
        Base angle [rad], in (-pi/2, pi/2).

    Returns
    -------
    ndarray
        Shape ``broadcast_shape + (2,)``: the answers ordered by increasing tip angle (xi), padded
        with NaN. For theta0 >= 0, and for h1 < cos(theta0), there is one answer, in ``[..., 0]``
        (``[..., 1]`` is NaN). For theta0 < 0 and cos(theta0) <= h1 <= max_tip_height there are
        two: ``[..., 0]`` on the rising limb (the flow has lifted the hair, which still leans into
        it; 0 at h1 = cos(theta0)) and ``[..., 1]`` on the falling limb (bent over).

    Raises
    ------
    ValueError
        If h1 is outside (0, max_tip_height(theta0)] or eps, theta0 are outside their ranges.

    Examples
    --------
    >>> w = omega2_from_tip_height(0.732706963462228, 0.5)  # theory.md §3
    >>> round(float(w[0]), 10), bool(np.isnan(w[1]))
    (2.0, True)
    """
    h1, eps, theta0 = check_state_inputs(h1, "h1", eps, theta0)
    shape = h1.shape
    h, e, th = h1.ravel(), eps.ravel(), theta0.ravel()
    t_max, h_max = _t_of_max_tip_height(th)
    # the rounding of the peak search must not reject a state computed at the peak
    bad = (h < _H1_MIN) | (h > h_max * (1.0 + 1e-14))
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        raise ValueError(
            f"h1 must lie in [{_H1_MIN:g}, {float(h_max[i])!r}] for theta0 = {float(th[i])!r} "
            "(the highest tip of a physical state; below, omega2 ~ 2/h1^2 overflows), got "
            f"{float(h[i])!r}{_first_index(bad.reshape(shape))}"
        )
    h = np.minimum(h, h_max)
    cos0 = np.cos(th)
    out = np.full((h.size, 2), np.nan)
    t_fall = np.full(h.size, np.nan)
    t_rise = np.full(h.size, np.nan)

    # falling limb, t in [t_max, inf): h1 decreases from h_max to 0; residual ln(h1) (~ -ln t)
    fall = np.flatnonzero(h < h_max)
    if fall.size:
        t_top = t_max[fall]  # -inf for theta0 >= 0: the limb starts at rest
        start = np.where(np.isfinite(t_top), t_top, -1.0)
        res = find_root(
            _falling_residual,
            start,
            start + 1.0,
            args=(th[fall], np.log(h[fall]), t_top),
            grow=True,
            xmin=t_top,
            xatol=1e-15,
            what="the branch parameter of a tip height (falling limb)",
        )
        t_fall[fall] = res.x
    # the peak itself: one state, on neither limb
    peak = np.flatnonzero((h == h_max) & np.isfinite(t_max))
    t_fall[peak] = t_max[peak]
    # rest with theta0 >= 0
    rest = np.flatnonzero((h == h_max) & ~np.isfinite(t_max))
    t_fall[rest] = -np.inf

    # rising limb, t in (-inf, t_max): h1 increases from cos(theta0) to h_max
    rise = np.flatnonzero((th < 0.0) & (h > cos0) & (h < h_max))
    if rise.size:
        t_top = t_max[rise]
        res = find_root(
            _rising_residual,
            t_top - 1.0,
            t_top,
            args=(th[rise], h[rise], t_top),
            grow=True,
            xmax=t_top,
            xatol=1e-15,
            what="the branch parameter of a tip height (rising limb)",
        )
        t_rise[rise] = res.x
    t_rise[(th < 0.0) & (h == cos0)] = -np.inf

    both = ~np.isnan(t_rise)
    first = np.where(both, t_rise, t_fall)
    second = np.where(both, t_fall, np.nan)
    for col, t in enumerate((first, second)):
        ok = ~np.isnan(t)
        if np.any(ok):
            sol = _physical(t[ok], e[ok], th[ok])
            out[ok, col] = np.asarray(sol.omega2, dtype=np.float64)
    return out.reshape(shape + (2,))


# fit_profile lived here: importable from hairbed.inverse still (its own module is about the
# shape of a whole hair, not the tip)
from .profile_fit import ProfileFit as ProfileFit  # noqa: E402
from .profile_fit import fit_profile as fit_profile  # noqa: E402
