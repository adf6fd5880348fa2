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
- :func:`fit_profile` fits (omega^2, theta0) to measured points along a whole hair.

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

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

from ._bracketing import find_minimum, find_root
from ._core.outputs import float_or_array
from ._core.solution import Solution
from ._core.solver import _from_parameter, _solve_checked
from ._core.validation import (
    HALF_PI,
    _first_index,
    as_float_array,
    check_inputs,
    check_number,
    check_scalar_inputs,
    check_state_inputs,
    check_tip_deflection,
    least_squares_status,
)

__all__ = [
    "ProfileFit",
    "fit_profile",
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


# -- fitting a measured profile ------------------------------------------------------------------


@dataclass(frozen=True)
class ProfileFit:
    """Result of :func:`fit_profile`.

    Attributes
    ----------
    omega2, theta0 : float
        Fitted forcing [-] and base angle [rad].
    omega2_stderr, theta0_stderr : float
        Their standard uncertainties (0 for a parameter held fixed), from the linearised
        covariance scaled by the residual variance.
    covariance : ndarray
        2 x 2 covariance of (omega2, theta0).
    residual : float
        Root-mean-square distance from the points to the fitted curve [-] (hair lengths).
    solution : Solution
        The fitted state (physical branch).
    sigma : ndarray
        Arc length [-] of the point of the curve closest to each measured point.
    success : bool
        Whether the optimiser reports convergence.
    status : int
        0 converged, -2 the evaluation limit, -6 improper input
        (:data:`~hairbed._core.validation.STATUS_MESSAGES`).
    message : str
        The optimiser's message.
    nfev : int
        Number of residual evaluations.
    nit : int
        Iterations of the optimiser (its evaluations of the Jacobian).
    solver_status : int
        :func:`scipy.optimize.least_squares`'s own status (> 0 converged, 0 the evaluation
        limit, -1 improper input).
    """

    omega2: float
    theta0: float
    omega2_stderr: float
    theta0_stderr: float
    covariance: FloatArray = field(repr=False)
    residual: float
    solution: Solution = field(repr=False)
    sigma: FloatArray = field(repr=False)
    success: bool
    status: int
    message: str
    nfev: int
    nit: int = 0
    solver_status: int = 0


#: The farthest a measured point may lie from the base [hair lengths]: the curve is continued
#: along its end tangents, so points a little beyond the tip fit; far beyond is not a hair.
_MAX_COORDINATE = 10.0
#: Base angles the fit may visit: the closed form needs |theta0| < pi/2.
_THETA0_LIMIT = HALF_PI - 1e-9


def _curve(
    t: Any, eps: float, theta0: Any, sigma: FloatArray, *, angle: bool = False
) -> tuple[FloatArray, ...]:
    """x, z (and theta) at arc lengths sigma, continued along the end tangents outside [0, 1].

    ``t`` and ``theta0`` may be arrays of shape (k,): the result then has shape (k, m). The
    continuation (C^1 at both ends) lets the orthogonal-distance fit run unconstrained: a measured
    point beyond the tip projects onto the tip's tangent instead of stalling on a bound.
    """
    t = np.asarray(t, dtype=np.float64)
    th = np.clip(np.asarray(theta0, dtype=np.float64), -_THETA0_LIMIT, _THETA0_LIMIT)
    if t.ndim:
        t, th = t[:, np.newaxis], th[:, np.newaxis]
    sol = _physical(t, eps, th)
    inside = np.clip(sigma, 0.0, 1.0)
    beyond = sigma - inside
    x = np.asarray(sol.x(inside), dtype=np.float64)
    z = np.asarray(sol.z(inside), dtype=np.float64)
    ends = np.flatnonzero(beyond)
    if not angle and ends.size == 0:
        return x, z
    theta = np.asarray(sol.theta(inside), dtype=np.float64)
    x = x + beyond * np.sin(theta)
    z = z + beyond * np.cos(theta)
    return (x, z, theta) if angle else (x, z)


def _scalar_theta0(value: Any, name: str) -> float:
    """A single base angle in (-pi/2, pi/2) [rad], the message naming ``name``."""
    th = check_number(value, name, unit="rad")
    if not abs(th) < HALF_PI:
        raise ValueError(f"{name} must lie in (-pi/2, pi/2), got {th!r}")
    return th


def fit_profile(
    x: Any,
    z: Any,
    eps: float,
    *,
    theta0: float | None = None,
    omega2_guess: float | None = None,
    theta0_guess: float | None = None,
) -> ProfileFit:
    """Least-squares fit of the forcing (and base angle) to measured points along one hair.

    Minimises the sum of squared distances from the points to the closed-form curve
    (x(sigma), z(sigma)) of the physical state (eqs. (32), (30)): an orthogonal-distance
    regression in the branch parameter t, the base angle and one arc length per point, with
    :func:`scipy.optimize.least_squares`. Because the curve is parametrised by t, every physical
    state (also the middle one of three) can be fitted without choosing a root.

    Parameters
    ----------
    x, z : array_like
        Measured points [-] in units of the hair length, with the base at the origin and the
        flow towards +x; at least three points (two for fixed ``theta0``), in any order, and at
        least one above the wall (``z > 0``): heights all zero, a hair lying on the wall, are
        the limit omega^2 -> inf or theta0 -> +-pi/2, not a state, and raise ValueError.
    eps : float
        Confinement L/H [-] (enters omega^2 only, not the shape).
    theta0 : float, optional
        Hold the base angle fixed at this value [rad]; by default it is fitted.
    omega2_guess, theta0_guess : float, optional
        Starting values; by default a coarse grid search over the physical branch.

    Returns
    -------
    ProfileFit
        omega2, theta0, their standard errors, the rms residual and the optimiser's status.

    Notes
    -----
    With a tangent of unit length, eliminating the arc lengths from the Gauss-Newton normal
    equations leaves the normal components N of the curve's derivatives with respect to
    (t, theta0): the covariance is s^2 (N^T N)^-1 with s^2 = sum(d_i^2) / (m - k) for m points
    and k fitted parameters, mapped to (omega^2, theta0) by the Jacobian of omega^2(t, theta0).

    Examples
    --------
    >>> import hairbed
    >>> sol = hairbed.solve(2.0, 0.5, 0.1)
    >>> x, z = sol.profile(20)
    >>> fit = fit_profile(x, z, 0.5)
    >>> round(fit.omega2, 8), round(fit.theta0, 8), fit.success
    (2.0, 0.1, True)
    """
    x = as_float_array(x, "x").ravel()
    z = as_float_array(z, "z").ravel()
    if x.shape != z.shape:
        raise ValueError(f"x and z must have the same number of points, got {x.size}, {z.size}")
    if np.max(np.abs(np.concatenate([x, z])), initial=0.0) > _MAX_COORDINATE:
        i = int(np.argmax(np.maximum(np.abs(x), np.abs(z)) > _MAX_COORDINATE))
        raise ValueError(
            f"x and z must be points along a hair, within {_MAX_COORDINATE:g} hair lengths of "
            f"its base, got ({float(x[i])!r}, {float(z[i])!r}) (first at index {i})"
        )
    if x.size and not np.any(z > 0.0):
        # dz/dsigma = cos(theta) > 0 along every physical state (|theta| < pi/2): a hair of
        # the model rises from its base. Heights all on (or below) the wall are a hair lying
        # on it, the limit omega2 -> inf (at eps = 0.5 the tip height falls like
        # 1.4/sqrt(omega2)) or theta0 -> +-pi/2 that no state reaches: a fit would run to the
        # edge of the base-angle range and stop there (success=False, or a theta0 at the edge).
        raise ValueError(
            "z must have a point above the wall (z > 0): a hair rises from its base "
            f"(dz/dsigma = cos(theta) > 0), got all {x.size} heights <= 0 (a hair lying on the "
            "wall is the limit omega2 -> inf or theta0 -> +-pi/2, not a state of the model)"
        )
    eps = check_scalar_inputs(eps=eps, given=("eps",))[1]
    fit_theta = theta0 is None
    k = 2 if fit_theta else 1
    m = x.size
    if m < k + 1:
        raise ValueError(f"need at least {k + 1} points to fit {k} parameter(s), got {m}")
    if not fit_theta:
        theta_fixed = _scalar_theta0(theta0, "theta0")
    if omega2_guess is not None:
        omega2_guess = check_number(omega2_guess, "omega2_guess", low=0.0)
    if theta0_guess is not None:
        theta0_guess = _scalar_theta0(theta0_guess, "theta0_guess")

    # -- starting point: a grid search on curves sampled in arc length
    num = 101
    s_grid = np.linspace(0.0, 1.0, num)
    if not fit_theta:
        th_cands = np.array([theta_fixed])
    elif theta0_guess is not None:
        th_cands = np.array([theta0_guess])
    else:
        th_cands = np.linspace(-1.4, 1.4, 15)
    best = (np.inf, 0.0, 0.0, s_grid[:m])
    for th in th_cands:
        if omega2_guess is not None:
            sol0 = _solve_checked(float(omega2_guess), eps, float(th))
            x1_0 = np.atleast_1d(np.asarray(sol0.tip_deflection, dtype=np.float64))
            tc = _t_from_tip_deflection(x1_0, np.atleast_1d(th))
            tc = np.where(np.isfinite(tc), tc, -30.0)
        else:
            tc = np.linspace(-10.0, 14.0, 25)
        cx, cz = _physical(tc, eps, th).profile(num)
        d2 = (cx[:, :, None] - x) ** 2 + (cz[:, :, None] - z) ** 2  # (t, sigma, point)
        cost = d2.min(axis=1).sum(axis=1)
        j = int(np.argmin(cost))
        if cost[j] < best[0]:
            best = (cost[j], tc[j], th, s_grid[np.argmin(d2[j], axis=0)])
    _, t_start, th_start, sigma_start = best

    def unpack(p: FloatArray) -> tuple[float, float, FloatArray]:
        if fit_theta:
            return p[0], p[1], p[2:]
        return p[0], theta_fixed, p[1:]

    def residuals(p: FloatArray) -> FloatArray:
        t, th, sg = unpack(p)
        cx, cz = _curve(t, eps, th, sg)
        return np.concatenate([cx - x, cz - z])

    def globals_jac(t: float, th: float, sg: FloatArray) -> FloatArray:
        """d(x, z)/d(t, theta0) at the points, by central differences, shape (2m, k)."""
        ht, hth = 1e-6 * max(1.0, abs(t)), 1e-6
        ts = np.array([t + ht, t - ht, t, t])[: 2 * k]
        ths = np.array([th, th, th + hth, th - hth])[: 2 * k]
        cx, cz = _curve(ts, eps, ths, sg)  # one evaluation for all shifted parameters
        steps = np.array([2.0 * ht, 2.0 * hth])[:k]
        dx = (cx[0::2] - cx[1::2]) / steps[:, None]
        dz = (cz[0::2] - cz[1::2]) / steps[:, None]
        return np.concatenate([dx, dz], axis=1).T

    def jac(p: FloatArray) -> FloatArray:
        t, th, sg = unpack(p)
        _, _, ang = _curve(t, eps, th, sg, angle=True)
        out = np.zeros((2 * m, k + m))
        out[:, :k] = globals_jac(t, th, sg)
        rows = np.arange(m)
        out[rows, k + rows] = np.sin(ang)  # dx/dsigma
        out[m + rows, k + rows] = np.cos(ang)  # dz/dsigma
        return out

    if fit_theta:
        p0 = np.concatenate([[t_start, th_start], sigma_start])
    else:
        p0 = np.concatenate([[t_start], sigma_start])
    res = optimize.least_squares(
        residuals, p0, jac=jac, method="lm", x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15
    )
    t, th, sg = unpack(res.x)
    th = float(np.clip(th, -_THETA0_LIMIT, _THETA0_LIMIT))
    sol = _physical(np.float64(t), eps, np.float64(th))
    omega2 = float(sol.omega2)

    # covariance from the normal components (see Notes)
    cx, cz, ang = _curve(t, eps, th, sg, angle=True)
    nx, nz = np.cos(ang), -np.sin(ang)
    dist = nx * (cx - x) + nz * (cz - z)
    g = globals_jac(t, th, sg)
    normal = nx[:, None] * g[:m] + nz[:, None] * g[m:]
    dof = m - k
    s2 = float(np.sum(dist**2)) / dof if dof > 0 else np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        cov_p = s2 * np.linalg.pinv(normal.T @ normal)
    # Jacobian of (omega2, theta0) with respect to (t, theta0)
    ht, hth = 1e-6 * max(1.0, abs(t)), 1e-6
    th_hi, th_lo = min(th + hth, _THETA0_LIMIT), max(th - hth, -_THETA0_LIMIT)  # inside
    w = np.asarray(
        _physical(np.array([t + ht, t - ht, t, t]), eps, np.array([th, th, th_hi, th_lo])).omega2
    )
    dw_dt = (w[0] - w[1]) / (2.0 * ht)
    if fit_theta:
        dw_dth = (w[2] - w[3]) / (th_hi - th_lo)
        jmap = np.array([[dw_dt, dw_dth], [0.0, 1.0]])
        cov = jmap @ cov_p @ jmap.T
    else:
        cov = np.zeros((2, 2))
        cov[0, 0] = dw_dt**2 * cov_p[0, 0]
    return ProfileFit(
        omega2=omega2,
        theta0=float(th),
        omega2_stderr=float(np.sqrt(cov[0, 0])),
        theta0_stderr=float(np.sqrt(cov[1, 1])),
        covariance=cov,
        residual=float(np.sqrt(np.mean(dist**2))),
        solution=sol,
        sigma=np.asarray(sg, dtype=np.float64),
        success=bool(res.success),
        status=least_squares_status(int(res.status)),
        message=str(res.message),
        nfev=int(res.nfev),
        nit=int(res.njev or 0),
        solver_status=int(res.status),
    )
