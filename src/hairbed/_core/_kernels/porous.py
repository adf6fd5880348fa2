"""Chebyshev collocation of the porous bed (issue 29, theory.md §13): a hair in a Brinkman bed.

The fluid inside the bed is solved with the hair, on the hair's own nodes: while z(s) is
monotone, the bed's momentum balance eta u_zz + G = (1/A) f_x/cos(theta) is, along the arc
length, w' = cos(theta) Q and Q' = f_x - Pi cos(theta), with w the fluid's velocity and Q its
shear stress in load units (theory.md §13). Unknowns at the N + 1 mapped nodes s_j: theta_j,
w_j, Q_j, then h1 and, for the flow drive, Pi. The rows:

    theta_0 = theta0
    (d2 theta)_i + F_x(s_i) cos theta_i - F_z(s_i) sin theta_i = 0,   i = 1 .. N - 1
    (d theta)_N = 0
    w_i - (I [cos(theta) Q])_i = 0,                                  i = 0 .. N
    Q_i - Q_N + ((I_N - I_i) [f_x - Pi cos(theta)]) = 0,             i = 0 .. N - 1
    eps w_N + u Q_N - Pi u^2/(2 eps) - omega2 = 0,   u = 1 - eps h1   (the gap's exact profile)
    h1 - (I [cos(theta)])_N = 0
    flow drive: 6 eps^2 Phi - q = 0,  Phi = (I [w cos(theta)])_N + w_N g + Q_N g^2/2 - Pi g^3/6,
    g = 1/eps - h1
    inverse (``DRIVE_INVERSE``): omega2 an unknown, (I [sin(theta)])_N - x1t = 0

with the drag per unit length f_x = (w/kappa)(cos^2 + gamma sin^2),
f_z = -(w/kappa)(1 - gamma) sin cos, and F(s_i) = (I_N - I_i) f, I the spectral integration
matrix from the base. Every entry of the Jacobian is written out (no z-dependence enters: the
fluid lives on the hair's arc length), so one Jacobian costs O(N^2) and one Newton step the LU
of a (3N + 4)-square matrix. ``hfix`` (NaN: free) freezes the tip height that the gap sees,
for the scan of ``solve_porous_all``: the states are the roots of z1(hfix) - hfix.

Newton, its line search, the chord steps, the ladder of N and the load continuation from rest
are those of ``spectral`` (the same constants and the same in-place LU). The error estimate is
the largest Chebyshev tail of theta, w and Q (the fluid's relative to its largest value) plus
the rounding part ``ROUNDING`` N^2 max(1, |theta|). Status codes as ``spectral``'s.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .description import (
    D_EPS,
    D_GAMMA,
    D_HFIX,
    D_KAPPA,
    D_OMEGA2,
    D_PI,
    D_Q,
    D_THETA0,
    D_X1,
    NDESC,
)
from .shape import shape_point, shape_setup
from .spectral import (
    MAX_CONTINUATION,
    MAXITER,
    ROUNDING,
    STATUS_BREAKDOWN,
    STATUS_INACCURATE,
    STATUS_LOST,
    STATUS_MAXITER,
    _clenshaw,
    _coefficients,
    _lu_apply,
    _lu_factor,
    _map,
    _operators,
)
from .state import MAX_FOLDS, MAX_ROOTS, NFIELDS, ROOT_LOW, find_folds, needs_folds, solve_one

__all__ = [
    "D_EPS",
    "D_GAMMA",
    "D_HFIX",
    "D_KAPPA",
    "D_OMEGA2",
    "D_PI",
    "D_Q",
    "D_THETA0",
    "D_X1",
    "NDESC",
    "DRIVE_FLOW",
    "DRIVE_INVERSE",
    "DRIVE_PRESSURE",
    "NCOLS",
    "linear_deflection_array",
    "porous_jacobians",
    "solve_porous_array",
]

DRIVE_PRESSURE = 0
DRIVE_FLOW = 1
#: The inverse problem of the wall drive: omega2 is the unknown that puts the tip at x1t.
DRIVE_INVERSE = 2
_XTOL = 1e-12
_FULL_STEP = 1e-7
_CHORD_START = 1e-3
_CHORD_RATE = 0.1
#: The load description of one element: the slots of its row of ``desc`` (the one table of
#: ``description``). Each drive fills its own (the inverse's tip deflection, the flow drive's
#: q); none is reused for another.
#: Output columns of :func:`solve_porous_array`: status, nit, num, h1, x1, theta1, theta'(0),
#: Q(1) (the tip plane's stress), w(1), Pi, Q(0) (the wall's stress), error estimate,
#: residual, max |theta|, F_x(0), F_z(0) (the drag's totals), the map parameter, omega2
#: (the input, or the inverse's solution).
NCOLS = 18


@kernel
def _fields(u, num, ii, kappa, gamma, cs, sn, fx, fz):
    """cos, sin, f_x, f_z at the nodes; returns the totals F_x(0), F_z(0)."""
    n1 = num + 1
    one_g = 1.0 - gamma
    for j in range(n1):
        c = math.cos(u[j])
        s = math.sin(u[j])
        cs[j] = c
        sn[j] = s
        wk = u[n1 + j] / kappa
        fx[j] = wk * (c * c + gamma * s * s)
        fz[j] = -wk * one_g * s * c
    tx = 0.0
    tz = 0.0
    for j in range(n1):
        tx += ii[num, j] * fx[j]
        tz += ii[num, j] * fz[j]
    return tx, tz


@kernel
def _residual(u, num, dd, ii, code, d, cs, sn, fx, fz, res):
    """The residual of the collocation system (the module's rows) at u into res, with cos,
    sin and the drag at the nodes into cs, sn, fx, fz; returns its sum of squares. ``d`` the
    element's load description (the ``D_*`` slots)."""
    theta0, kappa, gamma, omega2 = d[D_THETA0], d[D_KAPPA], d[D_GAMMA], d[D_OMEGA2]
    eps, pi_in, q, x1t, hfix = d[D_EPS], d[D_PI], d[D_Q], d[D_X1], d[D_HFIX]
    n1 = num + 1
    wo = n1
    qo = 2 * n1
    hi = 3 * n1
    h = u[hi] if math.isnan(hfix) else hfix
    pi_l = u[hi + 1] if code == DRIVE_FLOW else pi_in
    if code == DRIVE_INVERSE:
        omega2 = u[hi + 1]
    tx, tz = _fields(u, num, ii, kappa, gamma, cs, sn, fx, fz)
    res[0] = u[0] - theta0
    ref = u[num]
    for i in range(1, num):
        a2 = 0.0
        ax = 0.0
        az = 0.0
        for j in range(n1):
            a2 += dd[i, j] * (u[j] - ref)
            ax += ii[i, j] * fx[j]
            az += ii[i, j] * fz[j]
        res[i] = a2 + (tx - ax) * cs[i] - (tz - az) * sn[i]
    a1 = 0.0
    for j in range(n1):
        a1 += dd[num, j] * (u[j] - ref)
    res[num] = a1
    # the fluid
    totg = 0.0
    for j in range(n1):
        totg += ii[num, j] * (fx[j] - pi_l * cs[j])
    qn = u[qo + num]
    for i in range(n1):
        acc = 0.0
        accg = 0.0
        for j in range(n1):
            acc += ii[i, j] * cs[j] * u[qo + j]
            accg += ii[i, j] * (fx[j] - pi_l * cs[j])
        res[wo + i] = u[wo + i] - acc
        if i < num:
            res[qo + i] = u[qo + i] - qn + (totg - accg)
    uu = 1.0 - eps * h
    gap = eps * u[wo + num] + uu * qn - omega2
    if pi_l != 0.0:
        gap -= pi_l * uu * uu / (2.0 * eps)
    res[qo + num] = gap
    zt = 0.0
    for j in range(n1):
        zt += ii[num, j] * cs[j]
    res[hi] = u[hi] - zt
    m = hi + 1
    if code == DRIVE_FLOW:
        g = 1.0 / eps - h
        phi = u[wo + num] * g + qn * g * g / 2.0 - pi_l * g * g * g / 6.0
        for j in range(n1):
            phi += ii[num, j] * u[wo + j] * cs[j]
        res[hi + 1] = 6.0 * eps * eps * phi - q
        m = hi + 2
    elif code == DRIVE_INVERSE:
        x1 = 0.0
        for j in range(n1):
            x1 += ii[num, j] * sn[j]
        res[hi + 1] = x1 - x1t
        m = hi + 2
    ss = 0.0
    for i in range(m):
        ss += res[i] * res[i]
    return ss


@kernel
def _jacobian(u, num, dd, ii, code, d, cs, sn, fx, fz, dfx, dfz, jac):
    """The exact Jacobian of :func:`_residual` at u into jac (cs, sn, fx, fz from that call;
    dfx, dfz workspace for the drag's derivatives in theta)."""
    kappa, gamma, eps, pi_in, hfix = d[D_KAPPA], d[D_GAMMA], d[D_EPS], d[D_PI], d[D_HFIX]
    n1 = num + 1
    wo = n1
    qo = 2 * n1
    hi = 3 * n1
    m = hi + 1 if code == DRIVE_PRESSURE else hi + 2
    free = math.isnan(hfix)
    h = u[hi] if free else hfix
    pi_l = u[hi + 1] if code == DRIVE_FLOW else pi_in
    one_g = 1.0 - gamma
    for i in range(m):
        for k in range(m):
            jac[i, k] = 0.0
    for j in range(n1):
        c, s = cs[j], sn[j]
        wk = u[wo + j] / kappa
        dfx[j] = -2.0 * wk * one_g * s * c  # d f_x / d theta
        dfz[j] = -wk * one_g * (c * c - s * s)  # d f_z / d theta
    tx = 0.0
    tz = 0.0
    for j in range(n1):
        tx += ii[num, j] * fx[j]
        tz += ii[num, j] * fz[j]
    jac[0, 0] = 1.0
    for i in range(1, num):
        ci, si = cs[i], sn[i]
        ax = 0.0
        az = 0.0
        for j in range(n1):
            ax += ii[i, j] * fx[j]
            az += ii[i, j] * fz[j]
        fxi = tx - ax
        fzi = tz - az
        for k in range(n1):
            r = ii[num, k] - ii[i, k]
            ak = cs[k] * cs[k] + gamma * sn[k] * sn[k]
            bk = one_g * sn[k] * cs[k]
            jac[i, k] = dd[i, k] + r * (ci * dfx[k] - si * dfz[k])
            jac[i, wo + k] = r * (ci * ak + si * bk) / kappa
        jac[i, i] -= fxi * si + fzi * ci
    for k in range(n1):
        jac[num, k] = dd[num, k]
    # w rows
    for i in range(n1):
        jac[wo + i, wo + i] = 1.0
        for k in range(n1):
            jac[wo + i, k] = ii[i, k] * sn[k] * u[qo + k]
            jac[wo + i, qo + k] = -ii[i, k] * cs[k]
    # Q rows
    for i in range(num):
        jac[qo + i, qo + i] += 1.0
        jac[qo + i, qo + num] -= 1.0
        dp = 0.0
        for k in range(n1):
            r = ii[num, k] - ii[i, k]
            ak = cs[k] * cs[k] + gamma * sn[k] * sn[k]
            jac[qo + i, k] = r * (dfx[k] + pi_l * sn[k])
            jac[qo + i, wo + k] = r * ak / kappa
            dp -= r * cs[k]
        if code == DRIVE_FLOW:
            jac[qo + i, hi + 1] = dp
    uu = 1.0 - eps * h
    qn = u[qo + num]
    jac[qo + num, wo + num] = eps
    jac[qo + num, qo + num] = uu
    if free:
        jac[qo + num, hi] = -eps * qn
        if pi_l != 0.0:
            jac[qo + num, hi] += pi_l * uu
    if code == DRIVE_FLOW:
        jac[qo + num, hi + 1] = -uu * uu / (2.0 * eps)
    for k in range(n1):
        jac[hi, k] = ii[num, k] * sn[k]
    jac[hi, hi] = 1.0
    if code == DRIVE_INVERSE:
        jac[qo + num, hi + 1] = -1.0
        for k in range(n1):
            jac[hi + 1, k] = ii[num, k] * cs[k]
    if code == DRIVE_FLOW:
        g = 1.0 / eps - h
        e6 = 6.0 * eps * eps
        for k in range(n1):
            jac[hi + 1, k] = -e6 * ii[num, k] * u[wo + k] * sn[k]
            jac[hi + 1, wo + k] = e6 * ii[num, k] * cs[k]
        jac[hi + 1, wo + num] += e6 * g
        jac[hi + 1, qo + num] = e6 * g * g / 2.0
        if free:
            jac[hi + 1, hi] = e6 * (-u[wo + num] - qn * g + pi_l * g * g / 2.0)
        jac[hi + 1, hi + 1] = -eps * eps * g * g * g


@kernel
def _step_size(step, u, num, m):
    """The max norm of a Newton step: theta and h1 in radians and L, the fluid relative to
    its largest value, Pi relative to max(1, |Pi|)."""
    n1 = num + 1
    scale = 1.0
    for i in range(n1, 3 * n1):
        scale = max(scale, abs(u[i]))
    big = 0.0
    for i in range(n1):
        big = max(big, abs(step[i]))
    for i in range(n1, 3 * n1):
        big = max(big, abs(step[i]) / scale)
    big = max(big, abs(step[3 * n1]))
    if m > 3 * n1 + 1:
        big = max(big, abs(step[m - 1]) / max(1.0, abs(u[m - 1])))
    return big


@kernel
def _fluid_solve(u, num, dd, ii, code, d, work, jac, sub, piv):
    """The fluid (w, Q and, for the flow drive, Pi) of the hair's shape in u, in place: the
    fluid's rows are linear in the fluid's unknowns at a fixed shape, so one solve of their
    block. Returns False where that block is singular."""
    n1 = num + 1
    hi = 3 * n1
    cs, sn, fx, fz, dfx, dfz = work[0], work[1], work[2], work[3], work[4], work[5]
    res = work[6]
    _residual(u, num, dd, ii, code, d, cs, sn, fx, fz, res)
    _jacobian(u, num, dd, ii, code, d, cs, sn, fx, fz, dfx, dfz, jac)
    k = 2 * n1 + (1 if code == DRIVE_FLOW else 0)  # the inverse's omega2 stays
    rhs = work[7]
    for a in range(k):
        ra = n1 + a if a < 2 * n1 else hi + 1
        rhs[a] = -res[ra]
        for b in range(k):
            cb = n1 + b if b < 2 * n1 else hi + 1
            sub[a, b] = jac[ra, cb]
    if not _lu_factor(sub, piv, k):
        return False
    _lu_apply(sub, piv, rhs, k)
    for a in range(k):
        ra = n1 + a if a < 2 * n1 else hi + 1
        u[ra] += rhs[a]
    return True


@kernel
def _newton(u, num, dd, ii, code, d, work, jac, piv, nit0, maxiter):
    """Damped Newton on the collocation system from u (in place), as ``spectral``'s: the
    exact Jacobian, a backtracking line search on the squared residual (a step limited to
    one radian and a tenth of the height first), chord steps once it contracts fast.
    Returns (status, iterations, max abs(residual)). ``work`` is (12, >= m)."""
    eps, hfix = d[D_EPS], d[D_HFIX]
    n1 = num + 1
    hi = 3 * n1
    m = hi + 1 if code == DRIVE_PRESSURE else hi + 2
    cs, sn, fx, fz, dfx, dfz = work[0], work[1], work[2], work[3], work[4], work[5]
    res, step, trial = work[6], work[7], work[8]
    f = _residual(u, num, dd, ii, code, d, cs, sn, fx, fz, res)
    chord = False
    last = math.inf
    for it in range(maxiter):
        if not math.isfinite(f):
            return STATUS_BREAKDOWN, nit0 + it, math.nan
        if not chord:
            _jacobian(u, num, dd, ii, code, d, cs, sn, fx, fz, dfx, dfz, jac)
            if not _lu_factor(jac, piv, m):
                return STATUS_BREAKDOWN, nit0 + it, math.nan
        for i in range(m):
            step[i] = -res[i]
        _lu_apply(jac, piv, step, m)
        big = _step_size(step, u, num, m)
        if not math.isfinite(big):
            return STATUS_BREAKDOWN, nit0 + it, math.nan
        if chord and big > _CHORD_RATE * last:  # the chord contracts too slowly: refresh
            chord = False
            _jacobian(u, num, dd, ii, code, d, cs, sn, fx, fz, dfx, dfz, jac)
            if not _lu_factor(jac, piv, m):
                return STATUS_BREAKDOWN, nit0 + it, math.nan
            for i in range(m):
                step[i] = -res[i]
            _lu_apply(jac, piv, step, m)
            big = _step_size(step, u, num, m)
        lam = 1.0
        if big > _FULL_STEP:
            lam = min(1.0, 1.0 / big, 0.1 / max(abs(step[hi]), 1e-300))
        while True:
            for i in range(m):
                trial[i] = u[i] + lam * step[i]
            if math.isnan(hfix) and 1.0 - eps * trial[hi] <= 0.0:
                ft = math.inf
            else:
                ft = _residual(trial, num, dd, ii, code, d, cs, sn, fx, fz, res)
            if big <= _FULL_STEP or ft <= (1.0 - 1e-4 * lam) * f:
                break
            lam *= 0.5
            if lam < 1e-6:
                return STATUS_BREAKDOWN, nit0 + it + 1, math.sqrt(f)
        for i in range(m):
            u[i] = trial[i]
        f = ft
        chord = lam == 1.0 and big <= _CHORD_START and big <= _CHORD_RATE * last
        last = big
        if abs(u[hi]) > 1.0 + 1e-9 or (math.isnan(hfix) and 1.0 - eps * u[hi] <= 0.0):
            return STATUS_LOST, nit0 + it + 1, math.nan
        for j in range(n1):
            if abs(u[j]) > 10.0:
                return STATUS_LOST, nit0 + it + 1, math.nan
        if lam * big <= _XTOL:
            rmax = 0.0
            for i in range(m):
                rmax = max(rmax, abs(res[i]))
            return 0, nit0 + it + 1, rmax
    return STATUS_MAXITER, nit0 + maxiter, math.sqrt(f)


@kernel
def _continuation(u, keep, num, dd, ii, code, d, work, jac, piv, nit0):
    """Newton along the load factor lam from 0 (at rest) to 1, scaling omega2, Pi and q;
    for the inverse (``DRIVE_INVERSE``) lam moves the tip from its rest, sin(theta0), to x1t,
    and omega2 (an unknown) starts at 0."""
    n1 = num + 1
    hi = 3 * n1
    m = hi + 1 if code == DRIVE_PRESSURE else hi + 2
    inverse = code == DRIVE_INVERSE
    theta0 = d[D_THETA0]
    rest = math.sin(theta0)
    dl = d.copy()  # the description along the continuation: its loads scaled
    prev = keep[1]
    last = keep[2]
    for j in range(m):
        last[j] = 0.0
    for j in range(n1):
        last[j] = theta0
    last[hi] = math.cos(theta0)
    for j in range(m):
        prev[j] = last[j]
    lam = 0.0
    lam_prev = 0.0
    dlam = 0.125
    nit = nit0
    rmax = math.nan
    for _ in range(MAX_CONTINUATION):
        target = min(1.0, lam + dlam)
        slope = (target - lam) / (lam - lam_prev) if lam > lam_prev else 0.0
        for j in range(m):
            u[j] = last[j] + slope * (last[j] - prev[j])
        dl[D_OMEGA2] = target * d[D_OMEGA2]
        dl[D_PI] = target * d[D_PI]
        dl[D_Q] = target * d[D_Q]
        dl[D_X1] = rest + target * (d[D_X1] - rest) if inverse else d[D_X1]
        status, nit, rmax = _newton(u, num, dd, ii, code, dl, work, jac, piv, nit, 12)
        if status == 0:
            for j in range(m):
                prev[j] = last[j]
                last[j] = u[j]
            lam_prev = lam
            lam = target
            if lam >= 1.0:
                return 0, nit, rmax
            dlam *= 2.0
        else:
            dlam *= 0.25
            if dlam < 1e-6:
                return STATUS_LOST, nit, math.nan
    return STATUS_MAXITER, nit, math.nan


@kernel
def _linear_deflection(omega2, eps, kappa, pi, gauss):
    """x1 of the straight bed's linear Brinkman theory (theory.md §13): w'' = w/kappa - Pi,
    w(0) = 0, the gap condition at z = 1, and x1 = int_0^1 (w/kappa)(z^2/2 - z^3/6) dz by the
    Gauss-Legendre rule ``gauss`` (nodes, weights on [0, 1]). With l = sqrt(kappa),
    w = kappa Pi + B1 e^((z - 1)/l) + B2 e^(-z/l) (no overflow at small l)."""
    ell = math.sqrt(kappa)
    e1 = math.exp(-1.0 / ell)
    gp = pi * (1.0 - eps) ** 2 / (2.0 * eps) if pi != 0.0 else 0.0
    a21 = eps + (1.0 - eps) / ell
    a22 = eps * e1 - (1.0 - eps) * e1 / ell
    r1 = -kappa * pi
    r2 = omega2 + gp - eps * kappa * pi
    det = e1 * a22 - a21
    b1 = (r1 * a22 - r2) / det
    b2 = (e1 * r2 - a21 * r1) / det
    acc = 0.0
    for j in range(gauss.shape[1]):
        z = gauss[0, j]
        w = kappa * pi + b1 * math.exp((z - 1.0) / ell) + b2 * math.exp(-z / ell)
        acc += w / kappa * (z * z / 2.0 - z * z * z / 6.0) * gauss[1, j]
    return acc


@kernel
def linear_deflection_array(omega2, eps, kappa, pi, gauss, out):
    """:func:`_linear_deflection` of every element into out."""
    for e in range(omega2.size):
        out[e] = _linear_deflection(omega2[e], eps[e], kappa[e], pi[e], gauss)


@kernel
def _closed_start(code, d, num, ss, u, tables, gauss, lean, folds, roots, status, rows, grid):
    """The start of one element into u (theta, w = Q = 0 at the nodes s = ss, h1, Pi): the
    closed-form hair (theory.md §3) under the tip load W_eq that deflects the straight hair
    as the bed's linear Brinkman load does, W_eq = 3 x1_lin (mirrored where negative); the
    flow drive's Pi from the dense bed's formula of §11. A hair leaning into its load starts
    at rest (theory.md §5: it can have several states; the load continuation from rest
    follows the least deformed), unless the wall drive's dense bed has one state at every
    forcing W_eq (1 - eps) ``lean`` (factors within 16 either way; its windows hold the
    porous bed's), and unless the gap is frozen (``D_HFIX``, solve_porous_all's scan, whose
    load is fixed). The kernel then replaces the fluid by the fluid of this shape."""
    w, e, t0, kap, hfix = d[D_OMEGA2], d[D_EPS], d[D_THETA0], d[D_KAPPA], d[D_HFIX]
    n1 = num + 1
    if code == DRIVE_FLOW:
        uu = 1.0 - e * math.cos(t0)
        pi = 2.0 * e * d[D_Q] / uu**3 - 6.0 * e * w / uu**2
    else:
        pi = d[D_PI]
    frozen = not math.isnan(hfix)
    weq = 3.0 * _linear_deflection(w, e, kap, pi, gauss)
    if frozen:  # a frozen gap: its stress, not the straight hair's
        weq = weq * (1.0 - e) / (1.0 - e * hfix)
    if not math.isfinite(weq):
        weq = 0.0
    mirror = -1.0 if weq < 0.0 else 1.0
    mt0 = mirror * t0
    row = rows[0]
    _solve_dense(min(abs(weq), 1e12), 0.0, mt0, tables, folds, roots, status, row, grid)
    ok = not math.isnan(row[0])
    if ok and mt0 < 0.0 and e > 0.0 and not frozen:
        ok = code == DRIVE_PRESSURE and pi == 0.0
        base = abs(weq) * (1.0 - e)
        for f in lean:
            if not ok:
                break
            _solve_dense(base * f, e, mt0, tables, folds, roots, status, rows[1], grid)
            ok = rows[1, 1] == 1.0
    h = row[7]
    if ok:
        setup = shape_setup(row[0], 0.0, mt0, 1, 0)
        for j in range(n1):
            u[j] = mirror * shape_point(ss[j], 1, 0, setup)[0]
    else:
        for j in range(n1):
            u[j] = t0
    for j in range(n1, 3 * n1):
        u[j] = 0.0
    u[3 * n1] = h if ok and math.isfinite(h) else math.cos(t0)
    u[3 * n1 + 1] = pi


@kernel
def _solve_dense(omega2, eps, theta0, tables, folds, roots, status, row, grid):
    """The dense bed's closed form (theory.md §3) of one element, root "low", into ``row``
    (``FIELDS``), with its own fold search as ``state.solve_scalar``."""
    for j in range(MAX_FOLDS):
        folds[j] = math.nan
    n_folds = -1
    if needs_folds(eps, theta0, 1, 0, tables):
        n_folds = find_folds(eps, theta0, 1, 0, tables, folds, grid)
    solve_one(
        omega2, eps, theta0, 1, 0, ROOT_LOW, folds, n_folds, roots, status, row, tables, grid
    )


@kernel
def solve_porous_array(
    code,
    desc,
    a,
    start,
    nums,
    nodes,
    d1s,
    d2s,
    ims,
    cms,
    rtol,
    out,
    coefs,
    fluid_start,
    closed_start,
    tables,
    gauss,
    lean,
):
    """Every element on the ladder of N, its load description the row ``desc[e]`` (the
    ``D_*`` slots). ``start`` (size, 3 (nums[0] + 1) + 2): theta, w, Q
    at the first level's nodes, h1, Pi (flow drive); with ``fluid_start`` its fluid is
    replaced by the fluid of its shape (:func:`_fluid_solve`) before Newton. With
    ``closed_start`` (wall and pressure drives) ``start`` is not read: each element starts
    from :func:`_closed_start` (``tables`` the closed form's, ``gauss`` the linear
    deflection's rule, ``lean`` the factors of its check of windows) and its fluid. ``a`` the map
    parameter of each element (negative: nodes clustered at the tips, for a thin bed's
    layer). Writes out (NCOLS, size) and coefs (5, size, nmax + 1): the Chebyshev
    coefficients in xi of theta, x, z, w, Q."""
    levels = nums.size
    nmax = 0
    for lev in range(levels):
        nmax = max(nmax, nums[lev])
    mmax = 3 * (nmax + 1) + 2
    work = np.empty((12, mmax))
    # flat buffers, viewed as contiguous (m, m) and (N + 1, N + 1) matrices at each level: a
    # level touches only its own m^2 entries (as rows of an (mmax, mmax) array it touched a
    # page per row: measured 4x the kernel's time at N = 16)
    jbuf = np.empty(mmax * mmax)
    sbuf = np.empty(mmax * mmax)
    dbuf = np.empty((nmax + 1) * (nmax + 1))
    ibuf = np.empty((nmax + 1) * (nmax + 1))
    piv = np.empty(mmax, dtype=np.int64)
    u = np.empty(mmax)
    keep = np.empty((3, mmax))
    folds = np.empty(MAX_FOLDS)
    roots = np.empty(MAX_ROOTS)
    rstat = np.empty(MAX_ROOTS, dtype=np.int64)
    rows = np.empty((2, NFIELDS))
    grid = np.empty(0)
    sp = np.empty(nmax + 1)
    ss = np.empty(nmax + 1)
    coef = np.empty(nmax + 1)
    vals = np.empty((3, nmax + 1))
    for e in range(desc.shape[0]):
        d = desc[e]
        num = nums[0]
        n1 = num + 1
        nst = 3 * n1 + 2
        if not closed_start:
            for j in range(nst):
                u[j] = start[e, j]
        status = 0
        nit = 0
        rmax = math.nan
        tail = math.nan
        rounding = 0.0
        lev_done = 0
        for lev in range(levels):
            num = nums[lev]
            n1 = num + 1
            if lev > 0:
                prev = nums[lev - 1]
                p1 = prev + 1
                h = u[3 * p1]
                pl = u[3 * p1 + 1]
                for c in range(3):
                    for j in range(p1):
                        sp[j] = u[c * p1 + j]
                    _coefficients(sp, prev, cms[lev - 1], coef)
                    for j in range(n1):
                        vals[c, j] = _clenshaw(coef, prev, nodes[lev, j])
                for c in range(3):
                    for j in range(n1):
                        u[c * n1 + j] = vals[c, j]
                u[3 * n1] = h
                u[3 * n1 + 1] = pl
            m = 3 * n1 + 2
            jac = jbuf[: m * m].reshape((m, m))
            sub = sbuf[: m * m].reshape((m, m))
            dd = dbuf[: n1 * n1].reshape((n1, n1))
            ii = ibuf[: n1 * n1].reshape((n1, n1))
            _map(a[e], num, nodes[lev], sp, ss)
            _operators(num, d1s[lev], d2s[lev], ims[lev], sp, a[e], dd, ii)
            if lev == 0 and closed_start:
                _closed_start(
                    code, d, num, ss, u, tables, gauss, lean, folds, roots, rstat, rows, grid
                )
            for j in range(m):
                keep[0, j] = u[j]
            if lev == 0 and fluid_start:
                _fluid_solve(u, num, dd, ii, code, d, work, jac, sub, piv)
            status, nit, rmax = _newton(u, num, dd, ii, code, d, work, jac, piv, nit, MAXITER)
            if status != 0 and lev == 0:
                status, nit, rmax = _continuation(
                    u, keep, num, dd, ii, code, d, work, jac, piv, nit
                )
            lev_done = lev
            if status != 0:
                break
            # the tail of theta and of Q (relative to its scale)
            _coefficients(u, num, cms[lev], coef)
            tail = abs(coef[num]) + abs(coef[num - 1]) + abs(coef[num - 2])
            scale = 1.0
            for j in range(n1):
                scale = max(scale, abs(u[2 * n1 + j]), abs(u[n1 + j]))
            for c in (1, 2):
                for j in range(n1):
                    sp[j] = u[c * n1 + j]
                _coefficients(sp, num, cms[lev], coef)
                tail = max(
                    tail, (abs(coef[num]) + abs(coef[num - 1]) + abs(coef[num - 2])) / scale
                )
            big = 1.0
            for j in range(n1):
                big = max(big, abs(u[j]))
            rounding = ROUNDING * num * num * big
            if tail <= rtol:
                break
        num = nums[lev_done]
        n1 = num + 1
        if status == 0 and tail > rtol:
            status = STATUS_INACCURATE
        out[0, e] = status
        out[1, e] = nit
        out[2, e] = num
        for c in range(5):
            for k in range(nmax + 1):
                coefs[c, e, k] = math.nan if status < 0 else 0.0
        if status < 0:
            for c in range(3, NCOLS):
                out[c, e] = math.nan
            continue
        dd = dbuf[: n1 * n1].reshape((n1, n1))
        ii = ibuf[: n1 * n1].reshape((n1, n1))
        _map(a[e], num, nodes[lev_done], sp, ss)
        _operators(num, d1s[lev_done], d2s[lev_done], ims[lev_done], sp, a[e], dd, ii)
        cs, sn, fx, fz = work[0], work[1], work[2], work[3]
        tx, tz = _fields(u, num, ii, d[D_KAPPA], d[D_GAMMA], cs, sn, fx, fz)
        hi = 3 * n1
        h = u[hi]
        x1 = 0.0
        for j in range(n1):
            x1 += ii[num, j] * sn[j]
        # base moment theta'(0) = int_0^1 (F_x cos - F_z sin) ds
        quad = 0.0
        for i in range(n1):
            ax = 0.0
            az = 0.0
            for j in range(n1):
                ax += ii[i, j] * fx[j]
                az += ii[i, j] * fz[j]
            quad += ii[num, i] * ((tx - ax) * cs[i] - (tz - az) * sn[i])
        tmax = 0.0
        for j in range(n1):
            tmax = max(tmax, abs(u[j]))
        out[3, e] = h
        out[4, e] = x1
        out[5, e] = u[num]
        out[6, e] = quad
        out[7, e] = u[2 * n1 + num]  # Q(1), the tip stress
        out[8, e] = u[n1 + num]  # w(1)
        out[9, e] = u[hi + 1] if code == DRIVE_FLOW else d[D_PI]
        out[17, e] = u[hi + 1] if code == DRIVE_INVERSE else d[D_OMEGA2]
        out[10, e] = u[2 * n1]  # Q(0), the wall stress
        out[11, e] = tail + rounding
        out[12, e] = rmax
        out[13, e] = tmax
        out[14, e] = tx
        out[15, e] = tz
        out[16, e] = a[e]
        cm = cms[lev_done]
        _coefficients(u, num, cm, coef)
        for k in range(n1):
            coefs[0, e, k] = coef[k]
        for c in range(2):
            g = sn if c == 0 else cs
            for i in range(n1):
                acc = 0.0
                for j in range(n1):
                    acc += ii[i, j] * g[j]
                sp[i] = acc
            _coefficients(sp, num, cm, coef)
            for k in range(n1):
                coefs[1 + c, e, k] = coef[k]
        for c in range(2):
            for j in range(n1):
                sp[j] = u[(1 + c) * n1 + j]
            _coefficients(sp, num, cm, coef)
            for k in range(n1):
                coefs[3 + c, e, k] = coef[k]


@kernel
def porous_jacobians(code, u, num, a, nodes, d1, d2, im, desc, jac, ii):
    """The collocation system's exact Jacobian at each element's state u[e] (theta, w, Q at
    the N + 1 nodes of its map a[e], h1, then Pi for the flow drive; one N for all) into
    jac[e], and its integration matrix into ii[e]: the implicit differentiation of converged
    states (``hairbed._core.porous_sensitivity``). ``desc`` their load descriptions."""
    n1 = num + 1
    m = u.shape[1]
    sp = np.empty(n1)
    ss = np.empty(n1)
    dd = np.empty((n1, n1))
    work = np.empty((6, n1))
    res = np.empty(m)
    for e in range(u.shape[0]):
        d = desc[e]
        _map(a[e], num, nodes, sp, ss)
        _operators(num, d1, d2, im, sp, a[e], dd, ii[e])
        _residual(u[e], num, dd, ii[e], code, d, work[0], work[1], work[2], work[3], res)
        _jacobian(
            u[e],
            num,
            dd,
            ii[e],
            code,
            d,
            work[0],
            work[1],
            work[2],
            work[3],
            work[4],
            work[5],
            jac[e],
        )
