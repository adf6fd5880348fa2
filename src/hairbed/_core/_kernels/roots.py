"""Every root of the self-consistency equation ln omega^2(t) = ln omega^2 on one branch.

omega^2(t) along a branch (``branch.evaluate``) is explicit, so the forward problem is one
scalar equation. Its critical points (folds) depend on (eps, theta0) but not on omega^2:

* Physical branch (sign +1, n = 0). d ln omega^2/dt = 0 where eps = G(t) with
  G = 2 g / (h1 (g + expit(-t)/2)), g = d ln omega_eps/dt. For theta0 >= 0, G >= 1 > eps:
  the branch is monotone. For theta0 < 0, G has a single minimum eps_c(theta0) at t_c(theta0)
  (checked by a dense scan in the tests): no fold for eps < eps_c, and for eps > eps_c exactly
  two, one either side of t_c, where G = eps. eps_c and t_c are tabulated once per process in
  u = ln(1 + sin theta0) (eps_c rises with u), so most elements need no fold search at all.
* Every other branch: the slope is scanned on a grid in t that reaches down to
  ln(1 + sin theta0) - 12 (the structure near theta0 = -pi/2 lives there); sign changes and
  dips of |slope| that cross zero inside one cell (two close folds) are refined.

Between folds the branch is monotone; each piece that brackets the target gets a safeguarded
Newton iteration on ln omega^2 (bisection where a step would leave the bracket; a step below
the convergence threshold ends it). Every root ends with a status: 0 converged, -1 no such
root, -2 iteration limit.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .branch import LN_OMEGA2_NONE, base_angle, base_terms, evaluate, evaluate_at, log_expit
from .weak import weak_shape

__all__ = [
    "MAX_FOLDS",
    "MAX_ROOTS",
    "STATUS_CONVERGED",
    "STATUS_MAXITER",
    "STATUS_NO_ROOT",
    "T_MIN",
    "branch_roots",
    "critical_table",
    "newton",
    "newton_last",
    "physical_folds",
    "scan_folds",
    "scan_folds_step",
    "scan_points",
    "start_from_table",
    "start_physical",
    "start_table",
    "t_max",
]

MAX_FOLDS = 4
MAX_ROOTS = MAX_FOLDS + 1
STATUS_CONVERGED = 0
STATUS_NO_ROOT = -1
STATUS_MAXITER = -2
#: Below every root: ln omega^2 is exact down here and omega^2 underflows long before.
T_MIN = -1000.0
_MAXITER = 100
_LN4 = math.log(4.0)
#: Grid step of the fold scan of the twirling branches: on 740,000 random and near-cusp
#: (eps, theta0, branch), 360,000 of them within 1e-15 to 0.5 of theta0 = -pi/2, the scan found
#: the same folds with this step as with step 1/32 (tests/test_fold_scan.py compares them).
_SCAN_STEP = 1.0
#: Below this ln(omega_eps^2) the weak-forcing series gives the starting point.
_LN_SERIES_START = math.log(0.5)


@kernel
def t_max(ln_target):
    """A t beyond every root of omega^2 = e^ln_target (omega_eps >= omega ~ t/2 at large t)."""
    return 4.0 * math.exp(0.5 * min(ln_target, 1400.0)) + 60.0


@kernel
def start_physical(ln_target, eps, theta0):
    """Starting t on the physical branch: the weak-forcing series, else the limits."""
    s, c, oms, ops = base_angle(theta0)
    ln_oe2_weak = ln_target - math.log1p(-eps * c)
    if ln_oe2_weak < _LN_SERIES_START:
        # weak forcing: the perturbation series (``weak``) for h1 and theta1 at omega_eps^2,
        # with omega_eps^2 = omega^2/(1 - eps h1) by fixed-point iteration
        w2 = math.exp(ln_target)
        e2 = math.exp(ln_oe2_weak)
        for _ in range(2):
            e2 = w2 / (1.0 - eps * (c + weak_shape(1.0, e2, s, c)[2]))
        dth = weak_shape(1.0, e2, s, c)[0]
        half = math.sin(0.5 * dth)
        ratio = (c * math.sin(dth) - 2.0 * s * half * half) / oms  # (xi - sin theta0)/(1 - s)
        if 0.0 < ratio < 0.9:
            return math.log(ratio) - math.log1p(-ratio)
    if ln_oe2_weak < 0.0:
        # theta ~ theta0, h1 ~ cos theta0, d ~ omega_eps^2 cos^2(theta0)/2
        ln_d = ln_oe2_weak + 2.0 * math.log(c) - math.log(2.0)
        ln_ratio = ln_d - math.log(oms)
        if ln_ratio > -1e-3:
            ln_ratio = -1e-3
        return ln_ratio - math.log(-math.expm1(ln_ratio))
    # strong forcing: omega_eps = K - v0 ~ ln(4 cn0/(1 + sn0)) - tau/2 at xi = 1
    r2 = math.sqrt(2.0 * oms)
    w2 = math.exp(ln_target)
    oe = 0.5 * (eps * r2 + math.sqrt(eps * eps * 2.0 * oms + 4.0 * w2))
    sn0 = math.sqrt(0.5 * ops)
    cn0 = math.sqrt(0.5 * oms)
    tau = 2.0 * (_LN4 + math.log(cn0) - math.log1p(sn0) - oe)
    log_qc = math.log(2.0) + tau - math.log(oms)
    if log_qc > -1e-3:
        log_qc = -1e-3
    return math.log(-math.expm1(log_qc)) - log_qc


@kernel
def newton(ln_target, t, lo, hi, rising, eps, theta0, sign, n):
    """Safeguarded Newton on ln omega^2(t) = ln_target in [lo, hi], monotone there.

    Returns (t, status). Steps that would leave the bracket are replaced by bisection; the
    bracket shrinks at every evaluation, so the iteration cannot leave its piece.
    """
    r = newton_last(ln_target, t, lo, hi, rising, eps, theta0, sign, n)
    return r[0], r[1]


@kernel
def newton_last(ln_target, t, lo, hi, rising, eps, theta0, sign, n):
    """:func:`newton`, also returning its last evaluation: (t, status, ev, step).

    ev is ``evaluate_at`` (with slope) at t - step, the last point evaluated; step is the
    final Newton step where the iteration ended on a small step (|step| <= 1e-9 scale) or an
    exact zero (step 0), else NaN (the answer was not reached by a step from ev).
    """
    if t <= lo or t >= hi:
        t = 0.5 * (lo + hi)
    base = base_terms(theta0)
    ev = evaluate_at(t, eps, base, sign, n, True)
    for _ in range(_MAXITER):
        r = ev[0] - ln_target
        if r == 0.0:
            return t, STATUS_CONVERGED, ev, 0.0
        if (r > 0.0) == rising:
            hi = t
        else:
            lo = t
        sl = ev[1]
        tn = t - r / sl if sl != 0.0 else math.nan
        scale = max(1.0, abs(t))
        if math.isfinite(tn) and lo < tn < hi:
            # quadratic convergence: a step this small leaves an error far below one ulp
            if abs(tn - t) <= 1e-9 * scale:
                return tn, STATUS_CONVERGED, ev, tn - t
        else:
            tn = 0.5 * (lo + hi)
        if hi - lo <= 4.5e-16 * scale:
            return tn, STATUS_CONVERGED, ev, math.nan
        t = tn
        ev = evaluate_at(t, eps, base, sign, n, True)
    return t, STATUS_MAXITER, ev, math.nan


@kernel
def _g_ratio(t, theta0):
    """G(t) of the physical branch (module docstring): the eps at which t is a fold."""
    ev = evaluate(t, 0.0, theta0, 1, 0, True)
    two_g = ev[1]
    h1 = ev[14]
    qc = math.exp(log_expit(-t))
    return 2.0 * two_g / (h1 * (two_g + qc))


@kernel
def _objective(kind, t, eps, theta0, sign, n):
    """What the fold searches bracket: G(t) of the physical branch (kind 0, eps unused) or
    the slope d ln(omega^2)/dt of the branch (kind 1)."""
    if kind == 0:
        return _g_ratio(t, theta0)
    return evaluate(t, eps, theta0, sign, n, True)[1]


@kernel
def _golden_min(kind, a, b, eps, theta0, sign, n, orient, stop_below, iters):
    """Minimum of orient * objective on [a, b] by golden section: (t, value); stops early
    once the value is below ``stop_below``."""
    gr = 0.5 * (math.sqrt(5.0) - 1.0)
    c = b - gr * (b - a)
    d = a + gr * (b - a)
    fc = orient * _objective(kind, c, eps, theta0, sign, n)
    fd = orient * _objective(kind, d, eps, theta0, sign, n)
    for _ in range(iters):
        if fc < stop_below:
            return c, fc
        if fd < stop_below:
            return d, fd
        if fc < fd:
            b = d
            d = c
            fd = fc
            c = b - gr * (b - a)
            fc = orient * _objective(kind, c, eps, theta0, sign, n)
        else:
            a = c
            c = d
            fc = fd
            d = a + gr * (b - a)
            fd = orient * _objective(kind, d, eps, theta0, sign, n)
    if fc < fd:
        return c, fc
    return d, fd


@kernel
def _illinois(kind, a, fa, b, fb, eps, theta0, sign, n, shift):
    """t in [a, b] with objective(t) = shift, where fa, fb (objective - shift at a, b) differ
    in sign: Illinois regula falsi, to a bracket of a few ulp."""
    side = 0
    for _ in range(200):
        t = (a * fb - b * fa) / (fb - fa)
        if not (min(a, b) < t < max(a, b)):
            t = 0.5 * (a + b)
        ft = _objective(kind, t, eps, theta0, sign, n) - shift
        if ft == 0.0 or abs(b - a) <= 1.8e-15 * max(1.0, abs(t)):
            return t
        if (ft > 0.0) == (fb > 0.0):
            b = t
            fb = ft
            if side == -1:
                fa *= 0.5
            side = -1
        else:
            a = t
            fa = ft
            if side == 1:
                fb *= 0.5
            side = 1
    return 0.5 * (a + b)


@kernel
def critical_table(u_grid):
    """t_c and eps_c = min_t G(t) of the physical branch at theta0 = arcsin(e^u - 1)."""
    size = u_grid.size
    t_c = np.empty(size)
    eps_c = np.empty(size)
    for i in range(size):
        theta0 = math.asin(math.exp(u_grid[i]) - 1.0)
        tm, gm = _golden_min(0, -60.0, 4.0, 0.0, theta0, 1, 0, 1.0, -1.0, 90)
        t_c[i] = tm
        eps_c[i] = gm
    return t_c, eps_c


@kernel
def physical_folds(eps, theta0, t_guess, folds):
    """Folds of the physical branch near its G minimum (t_guess ~ t_c); returns how many."""
    tm = t_guess
    gm = _g_ratio(tm, theta0)
    if not gm < eps:
        tm, gm = _golden_min(0, t_guess - 3.0, t_guess + 3.0, 0.0, theta0, 1, 0, 1.0, eps, 60)
        if not gm < eps:
            return 0
    # expand outwards until G exceeds eps, then solve G = eps on each side
    a = tm
    ga = gm
    step = 1.0
    b = tm - step
    gb = _g_ratio(b, theta0)
    while gb <= eps and b > T_MIN:
        a = b
        ga = gb
        step *= 2.0
        b = max(tm - step, T_MIN)
        gb = _g_ratio(b, theta0)
    if gb <= eps:
        return 0
    folds[0] = _illinois(0, b, gb - eps, a, ga - eps, 0.0, theta0, 1, 0, eps)
    a = tm
    ga = gm
    step = 1.0
    b = tm + step
    gb = _g_ratio(b, theta0)
    while gb <= eps and b < 60.0:
        a = b
        ga = gb
        step *= 2.0
        b = tm + step
        gb = _g_ratio(b, theta0)
    if gb <= eps:
        return 0
    folds[1] = _illinois(0, a, ga - eps, b, gb - eps, 0.0, theta0, 1, 0, eps)
    return 2


@kernel
def scan_folds(eps, theta0, sign, n, folds, grid):
    """Folds of any branch: scan of the slope on a grid in t, then refinement. ln omega^2 at
    the grid points goes into ``grid`` where it is long enough (``scan_points``), for
    :func:`branch_roots` to bracket its roots with."""
    return scan_folds_step(eps, theta0, sign, n, folds, _SCAN_STEP, grid)


@kernel
def scan_points(theta0, h):
    """(t_lo, steps) of the fold scan: grid points t_lo + i h, i = 0..steps, up to t = 4."""
    s, c, oms, ops = base_angle(theta0)
    t_lo = min(-8.0, math.log(ops) - 12.0)
    return t_lo, int(math.ceil((4.0 - t_lo) / h))


@kernel
def scan_folds_step(eps, theta0, sign, n, folds, h, grid):
    """:func:`scan_folds` on a grid of step h (the tests compare steps)."""
    t_lo, steps = scan_points(theta0, h)
    record = grid.size > steps
    count = 0
    t_prev2 = t_lo
    f_prev2 = 0.0
    t_prev = t_lo
    ev = evaluate(t_lo, eps, theta0, sign, n, True)
    f_prev = ev[1]
    if record:
        grid[0] = ev[0]
    for i in range(1, steps + 1):
        t = t_lo + i * h
        ev = evaluate(t, eps, theta0, sign, n, True)
        f = ev[1]
        if record:
            grid[i] = ev[0]
        if count >= MAX_FOLDS:
            if record:
                continue
            break
        if (f > 0.0) != (f_prev > 0.0) and f != 0.0 and f_prev != 0.0:
            folds[count] = _illinois(1, t_prev, f_prev, t, f, eps, theta0, sign, n, 0.0)
            count += 1
        elif i >= 2 and (f > 0.0) == (f_prev > 0.0) == (f_prev2 > 0.0):
            # two folds inside one cell: |slope| dips between grid points without a change
            if abs(f_prev) < abs(f_prev2) and abs(f_prev) < abs(f) and count + 2 <= MAX_FOLDS:
                orient = 1.0 if f_prev > 0.0 else -1.0
                tm, fm = _golden_min(1, t_prev2, t, eps, theta0, sign, n, orient, 0.0, 60)
                if fm < 0.0:
                    fl = _objective(1, t_prev2, eps, theta0, sign, n)
                    fmid = orient * fm
                    folds[count] = _illinois(1, t_prev2, fl, tm, fmid, eps, theta0, sign, n, 0.0)
                    folds[count + 1] = _illinois(1, tm, fmid, t, f, eps, theta0, sign, n, 0.0)
                    count += 2
        t_prev2 = t_prev
        f_prev2 = f_prev
        t_prev = t
        f_prev = f
    # sort (the dip refinement may have appended out of order)
    for i in range(count):
        for j in range(i + 1, count):
            if folds[j] < folds[i]:
                tmp = folds[i]
                folds[i] = folds[j]
                folds[j] = tmp
    return count


@kernel
def branch_roots(ln_target, eps, theta0, sign, n, folds, n_folds, roots, status, start, grid):
    """All roots on the branch, given its folds; fills ``roots``/``status`` and returns count.

    ln_target = -inf (omega^2 = 0) gives t = -inf on the physical branch (the hair at rest)
    and no root elsewhere. ``start`` is the table of :func:`start_from_table`; ``grid`` holds
    ln omega^2 at the fold scan's points (``scan_folds``) where it was recorded there (its
    size exceeds the scan's steps), else it is ignored: then each root's piece is narrowed to
    one grid cell before Newton starts, with no further evaluation.
    """
    physical = sign > 0 and n == 0
    if ln_target == -math.inf:
        if physical:
            roots[0] = -math.inf
            status[0] = STATUS_CONVERGED
            return 1
        return 0
    g_lo, g_steps = scan_points(theta0, _SCAN_STEP)
    use_grid = not physical and grid.size > g_steps
    hi_end = t_max(ln_target)
    count = 0
    a = T_MIN
    fa = evaluate(a, eps, theta0, sign, n, False)[0]
    for j in range(n_folds + 1):
        b = folds[j] if j < n_folds else hi_end
        fb = evaluate(b, eps, theta0, sign, n, False)[0]
        lo_v = min(fa, fb)
        hi_v = max(fa, fb)
        if lo_v < ln_target <= hi_v and fa != LN_OMEGA2_NONE and fb != LN_OMEGA2_NONE:
            rising = fb > fa
            t0 = math.nan
            if physical:
                t0 = start_from_table(ln_target, eps, theta0, start)
            lo, flo, hi, fhi = a, fa, b, fb
            if use_grid:
                # the scan's points inside the piece: the first one past the target closes
                # the bracket (the piece is monotone)
                i0 = max(0, int(math.ceil((a - g_lo) / _SCAN_STEP)))
                for i in range(i0, g_steps + 1):
                    t_i = g_lo + i * _SCAN_STEP
                    if t_i >= b:
                        break
                    if t_i <= a:
                        continue
                    f_i = grid[i]
                    if (f_i < ln_target) == (flo < fhi):
                        lo, flo = t_i, f_i
                    else:
                        hi, fhi = t_i, f_i
                        break
            if not lo < t0 < hi:
                # narrow a wide piece by probes 12, 24, 48, ... from its finite end (omega^2
                # is nearly flat towards T_MIN and grows like t^2 towards t_max), then start
                # from the secant point
                step = 12.0
                while hi - lo > 2.0 * step:
                    if j == 0:
                        s_t = hi - step
                    else:
                        s_t = lo + step
                    f_s = evaluate(s_t, eps, theta0, sign, n, False)[0]
                    if (f_s < ln_target) == (flo < fhi):
                        lo, flo = s_t, f_s
                    else:
                        hi, fhi = s_t, f_s
                    if j == 0:
                        if lo == s_t:
                            break  # the root is within the last step of the fold
                    elif hi == s_t:
                        break
                    step *= 2.0
                t0 = lo + (hi - lo) * (ln_target - flo) / (fhi - flo)
            t, st = newton(ln_target, t0, lo, hi, rising, eps, theta0, sign, n)
            roots[count] = t
            status[count] = st
            count += 1
        a = b
        fa = fb
    return count


@kernel
def start_table(x_grid, th_grid):
    """Tables of the physical branch at eps = 0 for Newton's starting point.

    For ln(omega_eps^2) = x_grid[j] and theta0 = th_grid[i]: T[i, j] = t and H[i, j] = h1.
    (omega_eps and h1 as functions of t do not depend on eps, so one table serves every eps:
    omega^2 = omega_eps^2 (1 - eps h1).) Each row is solved by Newton with continuation.
    """
    nt = th_grid.size
    nx = x_grid.size
    tab_t = np.empty((nt, nx))
    tab_h = np.empty((nt, nx))
    for i in range(nt):
        th = th_grid[i]
        t = start_physical(x_grid[0], 0.0, th)
        for j in range(nx):
            x = x_grid[j]
            t, st = newton(x, t, T_MIN, t_max(x), True, 0.0, th, 1, 0)
            tab_t[i, j] = t
            tab_h[i, j] = evaluate(t, 0.0, th, 1, 0, False)[14]
    return tab_t, tab_h


@kernel
def _cubic_weights(f):
    """4-point Lagrange weights at fraction f in [0, 1] of the middle interval."""
    return (
        -f * (f - 1.0) * (f - 2.0) / 6.0,
        (f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0,
        -(f + 1.0) * f * (f - 2.0) / 2.0,
        (f + 1.0) * f * (f - 1.0) / 6.0,
    )


@kernel
def _bicubic(tab, i, wi, j, wj):
    """sum_a sum_b wi[a] wj[b] tab[i - 1 + a, j - 1 + b], unrolled (no tuple indexing)."""
    w0, w1, w2, w3 = wj
    r0 = (
        w0 * tab[i - 1, j - 1]
        + w1 * tab[i - 1, j]
        + w2 * tab[i - 1, j + 1]
        + w3 * tab[i - 1, j + 2]
    )
    r1 = w0 * tab[i, j - 1] + w1 * tab[i, j] + w2 * tab[i, j + 1] + w3 * tab[i, j + 2]
    r2 = (
        w0 * tab[i + 1, j - 1]
        + w1 * tab[i + 1, j]
        + w2 * tab[i + 1, j + 1]
        + w3 * tab[i + 1, j + 2]
    )
    r3 = (
        w0 * tab[i + 2, j - 1]
        + w1 * tab[i + 2, j]
        + w2 * tab[i + 2, j + 1]
        + w3 * tab[i + 2, j + 2]
    )
    return wi[0] * r0 + wi[1] * r1 + wi[2] * r2 + wi[3] * r3


@kernel
def _cubic_slopes(f):
    """Derivatives d/df of the 4-point Lagrange weights."""
    return (
        -(3.0 * f * f - 6.0 * f + 2.0) / 6.0,
        (3.0 * f * f - 4.0 * f - 1.0) / 2.0,
        -(3.0 * f * f - 2.0 * f - 2.0) / 2.0,
        (3.0 * f * f - 1.0) / 6.0,
    )


@kernel
def start_from_table(ln_target, eps, theta0, table):
    """Newton's start on the physical branch from the eps = 0 tables (``start_table``).

    X = ln(omega_eps^2) solves X + ln(1 - eps H(X)) = ln(omega^2) (a few Newton steps on the
    interpolated h1 = H), then t = T(X) is interpolated (bicubic: 4-point Lagrange in both
    directions). Falls back to :func:`start_physical` outside the tables.
    """
    x_lo, dx, th_lo, dth, tab_t, tab_h = table
    nt, nx = tab_t.shape
    fi = (theta0 - th_lo) / dth
    i = int(math.floor(fi))
    if i < 1 or i > nt - 3:
        return start_physical(ln_target, eps, theta0)
    wi = _cubic_weights(fi - i)
    c = math.cos(theta0)
    x = ln_target - math.log1p(-eps * c)
    for _ in range(2):
        fj = (x - x_lo) / dx
        j = int(math.floor(fj))
        if j < 1 or j > nx - 3:
            return start_physical(ln_target, eps, theta0)
        f = fj - j
        wj = _cubic_weights(f)
        dwj = _cubic_slopes(f)
        h1 = _bicubic(tab_h, i, wi, j, wj)
        dh = _bicubic(tab_h, i, wi, j, dwj)
        one_minus = 1.0 - eps * h1
        g = x + math.log(one_minus) - ln_target
        dg = 1.0 - eps * dh / (dx * one_minus)
        if not dg > 0.0:
            return start_physical(ln_target, eps, theta0)
        x -= g / dg
        if abs(g) < 1e-9:
            break
    fj = (x - x_lo) / dx
    j = int(math.floor(fj))
    if j < 1 or j > nx - 3:
        return start_physical(ln_target, eps, theta0)
    return _bicubic(tab_t, i, wi, j, _cubic_weights(fj - j))
