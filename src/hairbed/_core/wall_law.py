"""The law of the wall: Spalding's composite profile from the sublayer through the log region.

D. B. Spalding, "A single formula for the law of the wall", J. Appl. Mech. 28, 455-458
(1961), gives the distance from the wall in wall units as an explicit function of the speed
in wall units (theory.md §12, "The mean flow the pillar stands in"):

    y+ = u+ + e^(-kappa B) [e^(kappa u+) - 1 - kappa u+ - (kappa u+)^2/2 - (kappa u+)^3/6],

with u+ = u/u_tau, y+ = y u_tau/nu, u_tau = sqrt(tau_w/rho) and nu = eta/rho. It is
u+ = y+ - O(y+^4) in the viscous sublayer and u+ = ln(y+)/kappa + B + o(1) in the log
region. y+(u+) is increasing and convex for u+ >= 0 (dy+/du+ >= 1), so Newton's method from a
start where y+(u) >= y+ converges monotonically to u+(y+); :func:`spalding_u_plus` inverts it
so, vectorised. The constants are kappa = 0.41 and B = 5.0 (F. M. White, "Viscous Fluid
Flow", 3rd ed., McGraw-Hill 2006, §6-5, the values with which White quotes Spalding's
formula).

A pillar of height L in wall units L+ = L u_tau/nu sees the dimensionless profile (z in L)

    U(z) = u(z L) eta/(tau_w L) = u+(L+ z)/L+,    U(0) = 0, U'(0) = 1,

which tends to the sublayer's U = z as L+ -> 0 and depends on tau_w through L+ ~ sqrt(tau_w).
:func:`wall_law_coefficients` gives it (and L+ dU/dL+ = z U'(z) - U(z), the direction in
which it changes with the stress) as Chebyshev coefficients in 2 z - 1, resolved to rounding,
as the pillar's collocation takes a profile.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .outputs import scalar_or_array
from .validation import _check_range, as_float_array, check_number

__all__ = [
    "MAX_L_PLUS",
    "MAX_Y_PLUS",
    "row_groups",
    "WALL_LAW_B",
    "WALL_LAW_KAPPA",
    "spalding_u_plus",
    "spalding_y_plus",
    "wall_law_coefficients",
]

FloatArray = NDArray[np.float64]

#: von Karman's constant kappa of Spalding's formula [-] (White 2006, §6-5).
WALL_LAW_KAPPA = 0.41
#: The additive constant B of the log law u+ = ln(y+)/kappa + B [-] (White 2006, §6-5).
WALL_LAW_B = 5.0
#: The tallest pillar in wall units whose profile U(z) = u+(L+ z)/L+ is resolved to rounding
#: by at most 2049 Chebyshev coefficients (the degree grows like sqrt(L+): 65 at L+ = 30,
#: 513 at 1e3, 1025 at 1e4).
MAX_L_PLUS = 1e4
#: Chebyshev degrees tried for the profile of one L+.
_DEGREES = (16, 32, 64, 128, 256, 512, 1024, 2048)
#: Below this kappa u+ the bracket of Spalding's formula is summed as its Taylor series (its
#: terms cancel to x^4/24 otherwise).
_SERIES_BELOW = 1.0
_SERIES_TERMS = 20
#: For each start (3, 4): the Taylor coefficients 1/n! of sum_{n >= start} x^n/n! over
#: x^start, and of the head sum_{n < start} x^n/n!, highest power first (numpy.polyval).
_TAIL_COEFFICIENTS = {
    start: (
        np.array(
            [1.0 / math.factorial(n) for n in range(start + _SERIES_TERMS - 1, start - 1, -1)]
        ),
        np.array([1.0 / math.factorial(n) for n in range(start - 1, -1, -1)]),
    )
    for start in (3, 4)
}
#: The largest y+ taken (far beyond any wall flow; Spalding's exponential stays finite) and
#: the largest u+, times kappa.
MAX_Y_PLUS = 1e100
_MAX_KAPPA_U_PLUS = 600.0
#: Newton iterations of the inversion (monotone from the right: ~10 reach rounding).
_NEWTON_STEPS = 100


def _exp_tail(x: FloatArray, start: int) -> FloatArray:
    """sum_{n >= start} x^n/n! for x >= 0, without cancellation for small x: below
    ``_SERIES_BELOW`` its Taylor series (``_SERIES_TERMS`` terms, the last below 1e-17 of the
    first), above e^x minus the head of the series."""
    series, head = _TAIL_COEFFICIENTS[start]
    small = x < _SERIES_BELOW
    if np.all(small):
        return np.asarray(np.polyval(series, x) * x**start, dtype=np.float64)
    out = np.empty_like(x)
    xs = x[small]
    out[small] = np.polyval(series, xs) * xs**start
    xl = x[~small]
    with np.errstate(over="ignore"):
        out[~small] = np.exp(xl) - np.polyval(head, xl)
    return out


def _y_plus(u: FloatArray, kappa: float, b: float) -> FloatArray:
    return u + math.exp(-kappa * b) * _exp_tail(kappa * u, 4)


def _dy_plus(u: FloatArray, kappa: float, b: float) -> FloatArray:
    """dy+/du+ = 1 + kappa e^(-kappa B) [e^(kappa u+) - 1 - kappa u+ - (kappa u+)^2/2] >= 1."""
    return 1.0 + kappa * math.exp(-kappa * b) * _exp_tail(kappa * u, 3)


def _check_constants(kappa: Any, b: Any) -> tuple[float, float]:
    k = check_number(kappa, "kappa", low=0.1, high=1.0)
    return k, check_number(b, "b", low=-20.0, high=20.0)


def spalding_y_plus(
    u_plus: ArrayLike, *, kappa: float = WALL_LAW_KAPPA, b: float = WALL_LAW_B
) -> Any:
    """Spalding's law of the wall, explicit: y+ of u+ (vectorised).

    y+ = u+ + e^(-kappa B) [e^(kappa u+) - 1 - kappa u+ - (kappa u+)^2/2 - (kappa u+)^3/6]
    (Spalding 1961; theory.md §12).

    Parameters
    ----------
    u_plus : array_like
        Speed in wall units u/u_tau [-], >= 0 and finite.
    kappa, b : float, optional
        von Karman's constant in [0.1, 1] and the log law's constant in [-20, 20] [-]; default
        0.41 and 5.0 (White 2006, §6-5).

    Returns
    -------
    float or ndarray
        Distance from the wall in wall units y u_tau/nu [-].

    Raises
    ------
    ValueError
        Naming u_plus (and its first offending index) outside [0, 600/kappa], where the
        exponential stays finite.
    """
    k, bb = _check_constants(kappa, b)
    u = as_float_array(u_plus, "u_plus")
    top = _MAX_KAPPA_U_PLUS / k
    _check_range(u, ~((u >= 0.0) & (u <= top)), "u_plus", f"[0, {top:.6g}] (600/kappa)")
    return scalar_or_array(_y_plus(u.reshape(-1), k, bb).reshape(u.shape))


def _u_plus(y: FloatArray, kappa: float, b: float) -> FloatArray:
    """u+(y+) of checked y+ >= 0 (flat): Newton from the right of the root.

    y+(u) >= u, so u = y+ is at or right of the root; for y+ >= 1 the log law plus 5 is
    too, and the smaller is taken. Convexity keeps every iterate right of the root."""
    with np.errstate(divide="ignore"):
        log_law = np.log(np.maximum(y, 1.0)) / kappa + b + 5.0
    u = np.where(y < 1.0, y, np.minimum(y, log_law))
    low = _y_plus(u, kappa, b) < y  # not right of the root (a user's constants): step out
    while np.any(low):
        u = np.where(low, u + 5.0, u)
        low = _y_plus(u, kappa, b) < y
    active = np.ones(y.size, dtype=bool)
    for _ in range(_NEWTON_STEPS):
        ua = u[active]
        step = (_y_plus(ua, kappa, b) - y[active]) / _dy_plus(ua, kappa, b)
        new = np.maximum(ua - step, 0.0)
        u[active] = new
        # monotone from the right: done once a step no longer moves u down (rounding)
        still = step > 4.0 * np.finfo(np.float64).eps * new
        idx = np.flatnonzero(active)
        active[idx[~still]] = False
        if not np.any(active):
            break
    return u


def spalding_u_plus(
    y_plus: ArrayLike, *, kappa: float = WALL_LAW_KAPPA, b: float = WALL_LAW_B
) -> Any:
    """Spalding's law of the wall, inverted: the speed u+ at the distance y+ (vectorised).

    Newton's method on Spalding's y+(u+) (:func:`spalding_y_plus`) with its exact derivative,
    from a start on the convex side, so every iterate lies above the root and the iteration
    converges monotonically (to a few units of rounding). u+ = y+ - O(y+^4) near the wall
    and ln(y+)/kappa + B far from it.

    Parameters
    ----------
    y_plus : array_like
        Distance from the wall in wall units y u_tau/nu [-], in [0, 1e100]
        (``MAX_Y_PLUS``).
    kappa, b : float, optional
        As in :func:`spalding_y_plus`.

    Returns
    -------
    float or ndarray
        u/u_tau [-].

    Examples
    --------
    >>> import hairbed
    >>> round(hairbed.spalding_u_plus(1e-3), 12)   # the viscous sublayer, u+ = y+
    0.001
    >>> round(hairbed.spalding_u_plus(1e4), 3)   # near the log law ln(1e4)/0.41 + 5 = 27.464
    27.467
    """
    k, bb = _check_constants(kappa, b)
    y = as_float_array(y_plus, "y_plus")
    _check_range(y, ~((y >= 0.0) & (y <= MAX_Y_PLUS)), "y_plus", f"[0, {MAX_Y_PLUS:g}]")
    return scalar_or_array(_u_plus(y.reshape(-1), k, bb).reshape(y.shape))


def _chebyshev_fit_fft(values: FloatArray) -> FloatArray:
    """Chebyshev coefficients (rows) of values (rows) at t_j = -cos(pi j/K), j = 0..K."""
    k = values.shape[1] - 1
    ext = np.concatenate([values, values[:, -2:0:-1]], axis=1)
    c = np.real(np.fft.rfft(ext, axis=1))[:, : k + 1] / k
    c[:, 0] *= 0.5
    c[:, -1] *= 0.5
    c[:, 1::2] *= -1.0  # the nodes run from t = -1 (the wall) to +1 (the tip)
    return np.asarray(c, dtype=np.float64)


def wall_law_coefficients(
    l_plus: ArrayLike, *, kappa: float = WALL_LAW_KAPPA, b: float = WALL_LAW_B
) -> tuple[FloatArray, FloatArray]:
    """The pillar's profile in the law of the wall as Chebyshev coefficients in t = 2 z - 1.

    For each height L+ in wall units, U(z) = u+(L+ z)/L+ on z in [0, 1] [L] (Spalding's u+,
    :func:`spalding_u_plus`) and its change with L+, L+ dU/dL+ = z U'(z) - U(z) (with
    U'(z) = 1/(dy+/du+) at y+ = L+ z, exact). Each is sampled at 17 to 2049 Chebyshev points
    until the last three coefficients are at the level of rounding; L+ = 0 is the sublayer's
    U = z (and 0).

    Parameters
    ----------
    l_plus : array_like
        L+ = L u_tau/nu in [0, ``MAX_L_PLUS``] [-].
    kappa, b : float, optional
        As in :func:`spalding_y_plus`.

    Returns
    -------
    prof, dprof : ndarray
        Rows (one per element of ``l_plus``, flattened) of coefficients, zero-padded to a
        common length.
    """
    k, bb = _check_constants(kappa, b)
    lp = as_float_array(l_plus, "l_plus").reshape(-1)
    _check_range(lp, ~((lp >= 0.0) & (lp <= MAX_L_PLUS)), "l_plus", f"[0, {MAX_L_PLUS:g}]")
    uniq, inv = np.unique(lp, return_inverse=True)
    rows: list[FloatArray] = [np.zeros(0)] * uniq.size
    drows: list[FloatArray] = [np.zeros(0)] * uniq.size
    todo = np.flatnonzero(uniq > 0.0)
    for zero in np.flatnonzero(uniq == 0.0):
        rows[zero], drows[zero] = np.array([0.5, 0.5]), np.zeros(1)
    for deg in _DEGREES:
        if todo.size == 0:
            break
        z = 0.5 * (1.0 - np.cos(np.pi * np.arange(deg + 1) / deg))
        y = uniq[todo, None] * z[None, :]
        u = _u_plus(y.reshape(-1), k, bb).reshape(y.shape)
        slope = 1.0 / _dy_plus(u.reshape(-1), k, bb).reshape(y.shape)
        vals = u / uniq[todo, None]
        dvals = z[None, :] * slope - vals
        c, dc = _chebyshev_fit_fft(vals), _chebyshev_fit_fft(dvals)
        big = np.max(np.abs(c), axis=1)
        dbig = np.maximum(np.max(np.abs(dc), axis=1), big)
        floor = 1e-15 * big + 4.0 * deg * 2.2e-16 * np.max(np.abs(vals), axis=1)
        dfloor = 1e-15 * dbig + 4.0 * deg * 2.2e-16 * np.max(np.abs(dvals) + vals, axis=1)
        done = (np.sum(np.abs(c[:, -3:]), axis=1) <= floor) & (
            np.sum(np.abs(dc[:, -3:]), axis=1) <= dfloor
        )
        if deg == _DEGREES[-1]:
            done[:] = True  # MAX_L_PLUS keeps the profile within reach of this degree
        for j in np.flatnonzero(done):
            keep = np.flatnonzero(np.abs(c[j]) > 1e-17 * big[j])
            rows[todo[j]] = c[j, : int(keep[-1]) + 1].copy()
            dkeep = np.flatnonzero(np.abs(dc[j]) > 1e-17 * dbig[j])
            drows[todo[j]] = dc[j, : (int(dkeep[-1]) + 1 if dkeep.size else 1)].copy()
        todo = todo[~done]
    width = max([2] + [r.size for r in rows] + [r.size for r in drows])
    prof = np.zeros((uniq.size, width))
    dprof = np.zeros((uniq.size, width))
    for i in range(uniq.size):
        prof[i, : rows[i].size] = rows[i]
        dprof[i, : drows[i].size] = drows[i]
    return prof[inv.reshape(-1)], dprof[inv.reshape(-1)]


def _widths(prof: FloatArray) -> NDArray[np.int64]:
    """Each row's length without its zero padding, rounded up to a power of 2 (at least 2)."""
    nonzero = prof != 0.0
    last = np.where(nonzero.any(axis=1), prof.shape[1] - np.argmax(nonzero[:, ::-1], axis=1), 1)
    return np.asarray(2 ** np.ceil(np.log2(np.maximum(last, 2))), dtype=np.int64)


def row_groups(prof: FloatArray) -> list[tuple[NDArray[np.intp], FloatArray]]:
    """The rows of zero-padded Chebyshev coefficients grouped by their length, rounded up to a
    power of 2: [(indices, their rows trimmed to that length)]. The kernels sum a profile's
    whole row at every node, so a short profile padded to a long one's length costs as much."""
    width = _widths(prof)
    return [
        (sel, np.ascontiguousarray(prof[sel, : min(int(w), prof.shape[1])]))
        for w in np.unique(width)
        for sel in [np.flatnonzero(width == w)]
    ]
