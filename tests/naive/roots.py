"""Every root of the self-consistency equation on one branch, vectorised.

Frozen copy of ``src/hairbed/_roots.py`` at commit 7300965 (the numpy core), kept as
the slow reference of the tests; see :mod:`naive`. Do not change the algorithms.

omega^2(t) along a branch (``_branch``) is explicit, so the forward problem is one scalar
equation omega^2(t) = omega^2. Its critical points (folds) were mapped over the whole
parameter space: for every branch they lie in -10 < t < 0.5 (t is the logit of
(xi - sin theta0)/(1 - sin theta0)); outside that window every branch is monotone, and the
physical branch is monotone everywhere for theta0 >= 0 (theory.md §5). So:

1. Fast path (physical branch, theta0 >= 0): one bracketed Newton iteration in t on
   ln omega^2, from the weak- and strong-forcing limits of theory.md §4.
2. Otherwise: the slope d(omega^2)/dt is sampled on a grid of the fold window; sign changes,
   and interior minima of |slope| that dip through zero (two folds within one cell, close to a
   cusp), are refined by bisection, which splits the real line into monotone pieces; each
   piece that brackets the target gets the same safeguarded Newton iteration.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .branch import _half_angle_terms, branch_point, omega2_and_slope
from .elliptic import LN4

__all__ = ["critical_points", "find_roots", "MAX_ROOTS"]

FloatArray = NDArray[np.float64]

#: Most roots one branch can have at given inputs (two folds -> three roots).
MAX_ROOTS = 3
_T_MIN = -745.0  # expit(-745) == 0: the base state d = 0
_CROSSOVER = 1.0  # omega_eps^2 where the strong-forcing start takes over
_GRID = np.concatenate([np.linspace(-12.0, -2.0, 101), np.linspace(-1.95, 2.0, 80)])


def _eval(t, eps, theta0, sign, n):
    bp = branch_point(t, eps, theta0, sign, n)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        return omega2_and_slope(bp)


def _start_physical(omega2: FloatArray, eps: FloatArray, theta0: FloatArray) -> FloatArray:
    """Starting t on the physical branch from the limits of theory.md §4."""
    one_minus_s, one_plus_s = _half_angle_terms(theta0)
    c = np.cos(theta0)
    # weak forcing: theta ~ theta0, h1 ~ cos theta0, xi - sin theta0 ~ omega_eps^2 cos^2/2
    oe2 = omega2 / (1.0 - eps * c)
    d = 0.5 * oe2 * c * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t_weak = np.log(d) - np.log1p(-np.minimum(d / one_minus_s, 0.999)) - np.log(one_minus_s)
        # strong forcing: omega_eps = K - v0 ~ ln(4 cn0/(1 + sn0)) - tau/2 at xi = 1
        r2 = np.sqrt(2.0 * one_minus_s)
        oe = 0.5 * (eps * r2 + np.sqrt(eps * eps * 2.0 * one_minus_s + 4.0 * omega2))
        sn0 = np.sqrt(0.5 * one_plus_s)
        cn0 = np.sqrt(0.5 * one_minus_s)
        tau = 2.0 * (LN4 + np.log(cn0) - np.log1p(sn0) - oe)
        log_qc = np.log(2.0) + tau - np.log(one_minus_s)  # qc = 2p/(1 - sin theta0)
        t_strong = np.log(-np.expm1(np.minimum(log_qc, -1e-3))) - log_qc
    t0 = np.where(oe2 < _CROSSOVER, t_weak, t_strong)
    return np.where(np.isfinite(t0), t0, 0.0)


def _newton(
    log_target: FloatArray,
    t: FloatArray,
    lo: FloatArray,
    hi: FloatArray,
    rising: FloatArray,
    eps: FloatArray,
    theta0: FloatArray,
    sign: int,
    n: int,
    maxiter: int = 200,
) -> FloatArray:
    """Safeguarded Newton on ln omega^2(t) = log_target within [lo, hi] (monotone there).

    Steps leaving the bracket are replaced by bisection; the bracket shrinks on every
    evaluation, so the iteration cannot wander onto another piece of the branch.
    """
    t = t.copy()
    lo = lo.copy()
    hi = hi.copy()
    active = np.arange(t.size)
    for _ in range(maxiter):
        if active.size == 0:
            break
        ta = t[active]
        w2, sl = _eval(ta, eps[active], theta0[active], sign, n)
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.log(w2) - log_target[active]
            step = r * w2 / sl
        above = (r > 0) == (rising[active] > 0)
        hi[active] = np.where(above, ta, hi[active])
        lo[active] = np.where(above, lo[active], ta)
        tn = ta - step
        la, ha = lo[active], hi[active]
        bad = ~np.isfinite(tn) | (tn <= la) | (tn >= ha)
        tn = np.where(bad, 0.5 * (la + ha), tn)
        # a Newton step this small leaves an error of order step^2: converged
        done = (r == 0.0) | (~bad & (np.abs(tn - ta) <= 1e-10 * np.maximum(1.0, np.abs(ta))))
        done |= (ha - la) <= 4e-16 * np.maximum(1.0, np.abs(ta))
        t[active] = np.where(r == 0.0, ta, tn)
        active = active[~done]
    return t


def _bisect_slope(
    lo: FloatArray, hi: FloatArray, eps, theta0, sign: int, n: int, iters: int = 60
) -> FloatArray:
    """A zero of d(omega^2)/dt between lo and hi where the slope changes sign."""
    _, s_lo = _eval(lo, eps, theta0, sign, n)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        _, s_mid = _eval(mid, eps, theta0, sign, n)
        same = np.sign(s_mid) == np.sign(s_lo)
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)


def _golden_min_slope(a, b, eps, theta0, sign, n, iters=50):
    """Minimum of sign(s) * slope in [a, b] (golden section), s the sign at the ends."""
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    _, s_a = _eval(a, eps, theta0, sign, n)
    orient = np.sign(s_a)
    c = b - g * (b - a)
    d = a + g * (b - a)
    fc = orient * _eval(c, eps, theta0, sign, n)[1]
    fd = orient * _eval(d, eps, theta0, sign, n)[1]
    for _ in range(iters):
        left = fc < fd
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        d_new = np.where(left, c, a + g * (b - a))
        c_new = np.where(left, b - g * (b - a), d)
        f_new = orient * _eval(np.where(left, c_new, d_new), eps, theta0, sign, n)[1]
        fd, fc = np.where(left, fc, f_new), np.where(left, f_new, fd)
        c, d = c_new, d_new
    t_min = 0.5 * (a + b)
    return t_min, orient * _eval(t_min, eps, theta0, sign, n)[1]


def critical_points(eps: FloatArray, theta0: FloatArray, sign: int, n: int) -> FloatArray:
    """Folds of a branch: the zeros of d(omega^2)/dt, as an (N, 4) array padded with NaN.

    ``eps`` and ``theta0`` are 1-D arrays of equal length N.
    """
    size = eps.size
    out = np.full((size, 4), np.nan)
    if size == 0:
        return out
    grid = np.broadcast_to(_GRID, (size, _GRID.size))
    e2 = np.broadcast_to(eps[:, None], grid.shape)
    th2 = np.broadcast_to(theta0[:, None], grid.shape)
    _, slope = _eval(grid, e2, th2, sign, n)
    sg = np.sign(slope)
    rows, cols = np.nonzero(sg[:, :-1] * sg[:, 1:] < 0)
    found = [[] for _ in range(size)]
    if rows.size:
        tc = _bisect_slope(
            grid[rows, cols], grid[rows, cols + 1], eps[rows], theta0[rows], sign, n
        )
        for r, v in zip(rows, tc):
            found[r].append(v)
    # two folds inside one cell: |slope| has an interior local minimum without a sign change
    mag = np.abs(slope)
    interior = (mag[:, 1:-1] < mag[:, :-2]) & (mag[:, 1:-1] < mag[:, 2:])
    interior &= (sg[:, :-2] == sg[:, 1:-1]) & (sg[:, 1:-1] == sg[:, 2:])
    rows, cols = np.nonzero(interior)
    if rows.size:
        a = grid[rows, cols]
        b = grid[rows, cols + 2]
        tm, fmin = _golden_min_slope(a, b, eps[rows], theta0[rows], sign, n)
        dip = fmin < 0
        if np.any(dip):
            rr, aa, bb, mm = rows[dip], a[dip], b[dip], tm[dip]
            t1 = _bisect_slope(aa, mm, eps[rr], theta0[rr], sign, n)
            t2 = _bisect_slope(mm, bb, eps[rr], theta0[rr], sign, n)
            for r, v1, v2 in zip(rr, t1, t2):
                found[r].extend([v1, v2])
    for r, vals in enumerate(found):
        vals = sorted(vals)[:4]
        out[r, : len(vals)] = vals
    return out


def find_roots(
    omega2: FloatArray, eps: FloatArray, theta0: FloatArray, sign: int, n: int
) -> FloatArray:
    """All roots t of omega^2(t) = omega2 on the branch (sign, n).

    Parameters are 1-D arrays of equal length N (already validated). Returns an
    (N, MAX_ROOTS) array of t in increasing order, padded with NaN. omega2 = 0 on the physical
    branch gives t = -inf (the undeformed hair).
    """
    size = omega2.size
    out = np.full((size, MAX_ROOTS), np.nan)
    log_target = np.log(np.where(omega2 > 0, omega2, 1.0))
    physical = sign > 0 and n == 0
    rest = (omega2 == 0.0) if physical else np.zeros(size, dtype=bool)
    out[rest, 0] = -np.inf
    fast = (theta0 >= 0.0) & ~rest if physical else np.zeros(size, dtype=bool)
    if np.any(fast):
        i = np.nonzero(fast)[0]
        t0 = _start_physical(omega2[i], eps[i], theta0[i])
        lo = np.full(i.size, _T_MIN)
        hi = _upper_bound(omega2[i])
        t0 = np.clip(t0, lo + 1.0, hi - 1.0)
        out[i, 0] = _newton(log_target[i], t0, lo, hi, np.ones(i.size), eps[i], theta0[i], sign, n)
    slow = ~fast & ~rest & (omega2 > 0.0)
    if np.any(slow):
        i = np.nonzero(slow)[0]
        out[i] = _roots_general(omega2[i], log_target[i], eps[i], theta0[i], sign, n)
    return out


def _upper_bound(omega2: FloatArray) -> FloatArray:
    # omega_eps >= omega and omega_eps ~ t/2 + O(1) for large t: this t is beyond every root
    return 4.0 * np.sqrt(omega2) + 60.0


def _roots_general(omega2, log_target, eps, theta0, sign, n):
    size = omega2.size
    out = np.full((size, MAX_ROOTS), np.nan)
    crit = critical_points(eps, theta0, sign, n)
    ends = np.concatenate(
        [np.full((size, 1), _T_MIN), crit, _upper_bound(omega2)[:, None]], axis=1
    )
    finite = np.isfinite(ends)
    w2_ends = np.full(ends.shape, np.nan)
    rr, cc = np.nonzero(finite)
    w2_ends[rr, cc] = _eval(ends[rr, cc], eps[rr], theta0[rr], sign, n)[0]
    # the monotone pieces between consecutive ends that bracket the target
    rows, slots, lo, hi, rising = [], [], [], [], []
    for r in range(size):
        pts = ends[r][finite[r]]
        vals = w2_ends[r][finite[r]]
        k = 0
        for a, b, fa, fb in zip(pts[:-1], pts[1:], vals[:-1], vals[1:]):
            if min(fa, fb) < omega2[r] <= max(fa, fb) and k < MAX_ROOTS:
                rows.append(r)
                slots.append(k)
                lo.append(a)
                hi.append(b)
                rising.append(1.0 if fb > fa else -1.0)
                k += 1
    if rows:
        rows_a = np.array(rows)
        lo_a, hi_a = np.array(lo), np.array(hi)
        t = _newton(
            log_target[rows_a],
            0.5 * (lo_a + hi_a),
            lo_a,
            hi_a,
            np.array(rising),
            eps[rows_a],
            theta0[rows_a],
            sign,
            n,
        )
        out[rows_a, np.array(slots)] = t
    return out
