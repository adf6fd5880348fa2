"""Solving one element end to end, and the array drivers that loop over elements.

One element: fold search (unless the caller passes the folds of its (eps, theta0), found
once per distinct pair), every root on the branch, the requested one (low/mid/high), and
every output field at it. The array drivers call the same element kernel, so a scalar call
and a one-element array give bitwise the same numbers.

Output columns (``FIELDS``): t, n_roots, status, omega2, xi, omega_eps, energy, tip_height,
tip_deflection, tip_displacement, tip_angle, base_curvature.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from . import FIELDS
from .branch import base_angle, base_terms, evaluate_at, tip_displacement
from .elliptic import complete_k
from .roots import (
    MAX_FOLDS,
    MAX_ROOTS,
    STATUS_CONVERGED,
    STATUS_NO_ROOT,
    T_MIN,
    branch_roots,
    newton_last,
    physical_folds,
    scan_folds,
    start_from_table,
    t_max,
)
from .shape import shape_point, shape_setup, shape_setup_from, shape_xz
from .weak import WEAK_MAX, weak_shape

__all__ = [
    "FIELDS",
    "ROOT_HIGH",
    "ROOT_LOW",
    "ROOT_MID",
    "fields_array",
    "log_slope_array",
    "fields_at",
    "fields_from",
    "folds_array",
    "needs_folds_array",
    "profile_array",
    "shape_array",
    "solve_all_kernel",
    "solve_array",
    "solve_one",
    "solve_scalar",
    "write_fields",
    "write_state",
]

NFIELDS = len(FIELDS)
#: Work space for the fold scan's values of ln omega^2 (``roots.scan_folds``): its grid has
#: at most 90 points (theta0 within an ulp of -pi/2 starts it at t = -84.3).
GRID_SIZE = 128
ROOT_LOW = 0
ROOT_MID = 1
ROOT_HIGH = 2
_HALF_PI = 0.5 * math.pi


@kernel
def fields_at(t, eps, theta0, sign, n):
    """omega2, xi, omega_eps, energy, tip_height, tip_deflection, tip_displacement, tip_angle,
    base_curvature of the state at parameter t (t = -inf: the hair at rest)."""
    base = base_terms(theta0)
    return fields_from(evaluate_at(t, eps, base, sign, n, False), 0.0, base, theta0, sign, n)


@kernel
def _tip_angle(xi, p, mu, sign, n):
    """theta(1) from xi = sin(theta1), with p = (1 - xi)/2 and mu = (1 + xi)/2 exact."""
    if xi > 0.5:
        upper = _HALF_PI - 2.0 * math.asin(math.sqrt(p))
    elif xi < -0.5:
        upper = 2.0 * math.asin(math.sqrt(mu)) - _HALF_PI
    else:
        upper = math.asin(xi)
    if sign * (1 - 2 * (n % 2)) > 0:
        return upper
    return -math.pi - upper


@kernel
def fields_from(ev, step, base, theta0, sign, n):
    """:func:`fields_at` at t + step from the branch point ``ev`` evaluated at t.

    step = 0: the fields at t itself. Otherwise ev carries the t-derivatives (``evaluate_at``
    with the slope) and every field is moved by its first-order Taylor term, exact to
    O(step^2) (callers pass |step| <= 1e-9, so the remainder is below 1e-18 relative): with
    q = expit(t), d' = d (1 - q), p' = -p q, omega_eps' = g omega_eps, h1' = h1 ((1 - q)/2 - g),
    and for the tip deflection x1' = xi'/2 + (xi - x1) g, which follows from
    x1 = xi - (1/(2 omega_eps^2)) int_0^1 theta'^2 dsigma (the energy integral, eq. (7)) and
    d/dxi int theta'^2 dsigma = omega_eps^2 at fixed omega_eps (the path in theta depends on
    xi alone; the integrand vanishes at its turning points and at the tip).
    """
    ln_w2 = ev[0]
    xi = ev[2]
    d = ev[3]
    p = ev[4]
    mu = ev[6]
    sn0 = ev[7]
    cn0 = ev[8]
    dn0 = ev[9]
    kv = ev[12]
    oe = ev[13]
    h1 = ev[14]
    root2d = ev[15]
    s, c, oms = base[1], base[2], base[3]
    one_minus_x1 = -1.0  # not at hand
    if oe == 0.0:
        x1 = s
        disp = 0.0
    elif sign > 0 and n == 0:
        if oe * oe <= WEAK_MAX:
            disp = weak_shape(1.0, oe * oe, s, c)[1]
            x1 = s + disp
        else:
            x1, disp, one_minus_x1 = tip_displacement(p, mu, sn0, cn0, dn0, kv, s, oms)
    else:
        x1 = shape_point(1.0, sign, n, shape_setup_from(ev, theta0, sign, n))[1]
        disp = x1 - s
    if step != 0.0:
        slope = ev[1]
        g = ev[17]
        q = d / oms
        qc = 2.0 * p / oms
        # xi - x1 = d - disp without cancellation at weak forcing, (1 - x1) - 2 p at strong
        if d < p or one_minus_x1 < 0.0:
            xi_minus_x1 = d - disp
        else:
            xi_minus_x1 = one_minus_x1 - 2.0 * p
        dx1 = p * q + xi_minus_x1 * g  # xi'/2 + (xi - x1) g, xi' = 2 p q
        ln_w2 += slope * step
        d += d * qc * step
        p -= p * q * step
        mu = 1.0 - p
        xi = s + d if d < p else 1.0 - 2.0 * p
        h1 += h1 * (0.5 * qc - g) * step
        if h1 > 1.0:
            h1 = 1.0
        root2d += 0.5 * root2d * qc * step
        oe += oe * g * step
        if one_minus_x1 >= 0.0 and one_minus_x1 < 0.5:
            one_minus_x1 -= dx1 * step
            x1 = 1.0 - one_minus_x1
            disp = oms - one_minus_x1
        else:
            x1 += dx1 * step
            disp += dx1 * step
    omega2 = math.exp(ln_w2)
    tip_angle = _tip_angle(xi, p, mu, sign, n)
    energy = xi * oe * oe
    base_curvature = sign * oe * root2d
    return omega2, xi, oe, energy, h1, x1, disp, tip_angle, base_curvature


@kernel
def _physical_t_guess(theta0, u_lo, du, t_c):
    """t_c interpolated from the table (module ``roots``)."""
    s, c, oms, ops = base_angle(theta0)
    x = (math.log(ops) - u_lo) / du
    i = int(math.floor(x))
    if i < 0:
        return t_c[0]
    if i >= t_c.size - 1:
        return t_c[t_c.size - 1]
    f = x - i
    return (1.0 - f) * t_c[i] + f * t_c[i + 1]


@kernel
def needs_folds(eps, theta0, sign, n, tables):
    """False where the branch is certainly monotone at (eps, theta0).

    Physical branch: theta0 >= 0, or eps below the tabulated eps_c at the lower table node
    (eps_c rises with u = ln(1 + sin theta0), so that node's value is a lower bound).
    """
    u_lo, du, eps_c = tables[0], tables[1], tables[2]
    if not (sign > 0 and n == 0):
        return True
    if theta0 >= 0.0:
        return False
    s, c, oms, ops = base_angle(theta0)
    i = int(math.floor((math.log(ops) - u_lo) / du))
    if i < 0:
        i = 0
    if i >= eps_c.size:
        i = eps_c.size - 1
    return eps >= eps_c[i] * (1.0 - 1e-9)


@kernel
def find_folds(eps, theta0, sign, n, tables, folds, grid):
    """The folds of the branch at (eps, theta0) into ``folds``; returns how many. A twirling
    branch's scan records ln omega^2 into ``grid`` if it is long enough (``scan_folds``)."""
    u_lo, du, t_c = tables[0], tables[1], tables[3]
    if sign > 0 and n == 0:
        return physical_folds(eps, theta0, _physical_t_guess(theta0, u_lo, du, t_c), folds)
    return scan_folds(eps, theta0, sign, n, folds, grid)


@kernel(inline="always")  # a call would copy and refcount every array of `tables`
def solve_one(
    omega2, eps, theta0, sign, n, root, folds, n_folds, roots, status, out, tables, grid
):
    """Solve one element into ``out`` (length NFIELDS, see ``FIELDS``).

    ``n_folds`` < 0: the branch is certainly monotone and physical (fast path); otherwise the
    ``folds`` of (eps, theta0) are given. ``roots`` and ``status`` are work arrays of length
    MAX_ROOTS (allocated once per driver call, not per element); ``tables`` are the
    process-wide tables (``hairbed._core.solver._tables``); ``grid`` the scan's values of
    ln omega^2 from ``find_folds`` (or an empty array).
    """
    ln_target = math.log(omega2) if omega2 > 0.0 else -math.inf
    if n_folds < 0 and ln_target > -math.inf:
        start = tables[4]
        t0 = start_from_table(ln_target, eps, theta0, start)
        t, st, ev, step = newton_last(
            ln_target, t0, T_MIN, t_max(ln_target), True, eps, theta0, 1, 0
        )
        if abs(step) <= 1e-9 and root != ROOT_MID:
            # the fields from Newton's last evaluation, moved by its final step (exact to
            # O(step^2), below 1e-18): no evaluation at the root itself
            vals = fields_from(ev, step, base_terms(theta0), theta0, 1, 0)
            write_fields(out, t, 1, st, vals)
            return
        roots[0] = t
        status[0] = st
        count = 1
    else:
        count = branch_roots(
            ln_target, eps, theta0, sign, n, folds, max(n_folds, 0), roots, status, tables[4], grid
        )
    pick = -1
    if root == ROOT_LOW:
        pick = 0 if count >= 1 else -1
    elif root == ROOT_HIGH:
        pick = count - 1
    elif count >= 3:
        pick = 1
    out[1] = count
    if pick < 0:
        out[0] = math.nan
        out[2] = STATUS_NO_ROOT
        for j in range(3, out.size):
            out[j] = math.nan
        return
    write_state(out, roots[pick], count, status[pick], eps, theta0, sign, n)


@kernel
def write_state(out, t, count, status, eps, theta0, sign, n):
    """One output row (``FIELDS``) of the state at parameter t: t, count, status, fields."""
    write_fields(out, t, count, status, fields_at(t, eps, theta0, sign, n))


@kernel
def write_fields(out, t, count, status, vals):
    """One output row (``FIELDS``): t, count, status and the fields ``vals``."""
    out[0] = t
    out[1] = count
    out[2] = status
    for j in range(len(vals)):
        out[3 + j] = vals[j]


@kernel
def solve_scalar(omega2, eps, theta0, sign, n, root, tables):
    """One element with its own fold search: the NFIELDS values as a tuple of floats."""
    folds = np.full(MAX_FOLDS, math.nan)
    grid = np.empty(0)  # as solve_array: a scalar and a one-element array agree bitwise
    if needs_folds(eps, theta0, sign, n, tables):
        n_folds = find_folds(eps, theta0, sign, n, tables, folds, grid)
    else:
        n_folds = -1
    row = np.empty(NFIELDS)
    roots = np.empty(MAX_ROOTS)
    status = np.empty(MAX_ROOTS, dtype=np.int64)
    solve_one(omega2, eps, theta0, sign, n, root, folds, n_folds, roots, status, row, tables, grid)
    return (
        row[0],
        row[1],
        row[2],
        row[3],
        row[4],
        row[5],
        row[6],
        row[7],
        row[8],
        row[9],
        row[10],
        row[11],
    )


@kernel
def needs_folds_array(eps, theta0, sign, n, tables):
    size = eps.size
    out = np.empty(size, dtype=np.bool_)
    for i in range(size):
        out[i] = needs_folds(eps[i], theta0[i], sign, n, tables)
    return out


@kernel
def folds_array(eps, theta0, sign, n, tables):
    """Folds of each (eps, theta0) pair: (folds (N, MAX_FOLDS), counts (N,))."""
    size = eps.size
    folds = np.full((size, MAX_FOLDS), math.nan)
    counts = np.empty(size, dtype=np.int64)
    no_grid = np.empty(0)
    for i in range(size):
        counts[i] = find_folds(eps[i], theta0[i], sign, n, tables, folds[i], no_grid)
    return folds, counts


@kernel
def solve_array(omega2, eps, theta0, sign, n, root, pair, folds, counts, out, tables):
    """Solve every element; pair[i] >= 0 indexes the folds of element i's (eps, theta0),
    pair[i] < 0 marks a certainly monotone physical element. ``out`` is (NFIELDS, N)."""
    row = np.empty(NFIELDS)
    roots = np.empty(MAX_ROOTS)
    status = np.empty(MAX_ROOTS, dtype=np.int64)
    no_grid = np.empty(0)
    for i in range(omega2.size):
        j = pair[i]
        f = folds[max(j, 0)]
        c = counts[j] if j >= 0 else -1
        solve_one(
            omega2[i], eps[i], theta0[i], sign, n, root, f, c, roots, status, row, tables, no_grid
        )
        for k in range(NFIELDS):
            out[k, i] = row[k]


@kernel
def fields_array(t, eps, theta0, sign, n, out):
    """Fields at given parameters (``from_parameter``): out is (NFIELDS, N)."""
    row = np.empty(NFIELDS)
    for i in range(t.size):
        write_state(row, t[i], 1, STATUS_CONVERGED, eps[i], theta0[i], sign, n)
        for k in range(NFIELDS):
            out[k, i] = row[k]


@kernel
def log_slope_array(t, eps, theta0, sign, n, out):
    """d ln(omega^2)/dt of the branch at each t (``branch.evaluate_at``'s exact slope, the one
    Newton uses): out has t's size."""
    for i in range(t.size):
        out[i] = evaluate_at(t[i], eps[i], base_terms(theta0[i]), sign, n, True)[1]


@kernel
def shape_array(t, eps, theta0, sign, n, sigma, out):
    """theta, x, z and their displacements at sigma[i, j] of state i: out (6, N, M)."""
    for i in range(t.size):
        if math.isnan(t[i]):
            for j in range(sigma.shape[1]):
                for k in range(6):
                    out[k, i, j] = math.nan
            continue
        setup = shape_setup(t[i], eps[i], theta0[i], sign, n)
        for j in range(sigma.shape[1]):
            vals = shape_point(sigma[i, j], sign, n, setup)
            for k in range(6):
                out[k, i, j] = vals[k]


@kernel
def solve_all_kernel(omega2, eps, theta0, max_n, tables):
    """Every state on every branch (sign, n <= max_n): (rows (K, NFIELDS), signs, ns)."""
    ln_target = math.log(omega2) if omega2 > 0.0 else -math.inf
    cap = 16
    rows = np.empty((cap, NFIELDS))
    signs = np.empty(cap, dtype=np.int64)
    ns = np.empty(cap, dtype=np.int64)
    folds = np.full(MAX_FOLDS, math.nan)
    roots = np.empty(MAX_ROOTS)
    status = np.empty(MAX_ROOTS, dtype=np.int64)
    grid = np.empty(GRID_SIZE)
    total = 0
    # omega_eps >= 2 n K(mu0) (sign +1) or (2 n + 1) K(mu0) (sign -1), mu0 = (1 + sin theta0)/2
    # the smallest parameter on a branch, and omega^2 = omega_eps (omega_eps -+ eps sqrt(2 d)):
    # once a branch's lower bound exceeds omega^2, so do those of every larger n
    s, c, oms, ops = base_angle(theta0)
    k0 = complete_k(0.5 * oms, math.log(0.5 * oms))
    r_max = eps * math.sqrt(2.0 * oms)
    open_plus = True
    open_minus = True
    for n in range(max_n + 1):
        if n >= 1 and open_plus:
            a = 2.0 * n * k0
            open_plus = a <= 0.5 * r_max or a * (a - r_max) <= omega2
        if open_minus:
            b = (2.0 * n + 1.0) * k0
            open_minus = b * b <= omega2
        if not (open_plus or open_minus):
            break
        for sign in (1, -1):
            if (sign > 0 and not open_plus) or (sign < 0 and not open_minus):
                continue
            if needs_folds(eps, theta0, sign, n, tables):
                n_folds = find_folds(eps, theta0, sign, n, tables, folds, grid)
            else:
                n_folds = 0
            count = branch_roots(
                ln_target, eps, theta0, sign, n, folds, n_folds, roots, status, tables[4], grid
            )
            for j in range(count):
                if total == cap:
                    cap *= 2
                    rows2 = np.empty((cap, NFIELDS))
                    rows2[:total] = rows[:total]
                    rows = rows2
                    s2 = np.empty(cap, dtype=np.int64)
                    s2[:total] = signs[:total]
                    signs = s2
                    n2 = np.empty(cap, dtype=np.int64)
                    n2[:total] = ns[:total]
                    ns = n2
                write_state(rows[total], roots[j], count, status[j], eps, theta0, sign, n)
                signs[total] = sign
                ns[total] = n
                total += 1
    return rows[:total], signs[:total], ns[:total]


@kernel
def profile_array(t, eps, theta0, sign, n, num):
    """x and z of state i at sigma = j/(num - 1) (numpy's linspace(0, 1, num)): (N, num) each."""
    size = t.size
    xs = np.empty((size, num))
    zs = np.empty((size, num))
    step = 1.0 / (num - 1)
    for i in range(size):
        if math.isnan(t[i]):
            xs[i, :] = math.nan
            zs[i, :] = math.nan
            continue
        setup = shape_setup(t[i], eps[i], theta0[i], sign, n)
        for j in range(num):
            sigma = 1.0 if j == num - 1 else j * step
            xs[i, j], zs[i, j] = shape_xz(sigma, sign, n, setup)
    return xs, zs
