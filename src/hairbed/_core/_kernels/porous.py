"""Chebyshev collocation of the porous bed (issue 29, theory.md §13): a hair in a Brinkman bed.

The fluid inside the bed is solved with the hair, on the hair's own nodes: while z(s) is
monotone, the bed's momentum balance eta u_zz + G = (1/A) f_x/cos(theta) is, along the arc
length, w' = cos(theta) Q and Q' = f_x - Pi cos(theta), with w the fluid's velocity and Q its
shear stress in load units (theory.md §13). The system (its unknowns theta, w, Q at the
N + 1 mapped nodes, h1 and Pi or omega2; its rows; its exact Jacobian, O(N^2) to build, no
z-dependence entering as the fluid lives on the hair's arc length) is ``porous_system``'s;
``hfix`` (D_HFIX; NaN: free) freezes the tip height that the gap sees, for the scan of
``solve_porous_all``: the states are the roots of z1(hfix) - hfix.

Newton, its line search, the chord steps and the load continuation from rest are
``spectral``'s own (one Newton for every model: the porous system enters it as the codes
``spectral.POROUS`` + drive); the ladder of N as there. The error estimate is
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
from .porous_system import DRIVE_FLOW, DRIVE_INVERSE, DRIVE_PRESSURE, _fields, _jacobian, _residual
from .shape import shape_point, shape_setup
from .spectral import (
    MAXITER,
    POROUS,
    ROUNDING,
    STATUS_INACCURATE,
    _clenshaw,
    _coefficients,
    _continuation,
    _lu_apply,
    _lu_factor,
    _map,
    _newton,
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

#: Output columns of :func:`solve_porous_array`: status, nit, num, h1, x1, theta1, theta'(0),
#: Q(1) (the tip plane's stress), w(1), Pi, Q(0) (the wall's stress), error estimate,
#: residual, max |theta|, F_x(0), F_z(0) (the drag's totals), the map parameter, omega2
#: (the input, or the inverse's solution).
NCOLS = 18


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
    dl = np.empty(NDESC)
    noprof = np.zeros(1)  # the pillar's profile and its work: unused by the porous system
    nopm = np.empty((2, 1, 1))
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
            status, nit, rmax = _newton(
                u, num, dd, ii, POROUS + code, d, noprof, work, nopm, jac, piv, nit, MAXITER, False
            )
            if status != 0 and lev == 0:
                status, nit, rmax = _continuation(
                    u, keep, num, dd, ii, POROUS + code, d, dl, noprof, work, nopm, jac, piv, nit
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
