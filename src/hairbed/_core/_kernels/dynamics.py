"""Compiled parts of the pillar's dynamics (issue 30, theory.md §14).

The linear response about a static state: the pencil (s E - A) in generalised Schur form,
Q^H (A, E) Z = (AA, BB) upper triangular, is solved at each frequency by back substitution
(O(n^2) a frequency, backward stable).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._jit import kernel
from . import bed as _bed
from .rod_motion import (
    SIGNAL_CONSTANT,
    SIGNAL_PULSES,
    SIGNAL_RAMP,
    SIGNAL_SAMPLED,
    SIGNAL_SINE,
    SIGNAL_STEP,
    drive_value,
    projected_load,
)
from .spectral import _jacobian_drag, _lu_apply, _lu_factor, _residual_drag

__all__ = [
    "SIGNAL_CONSTANT",
    "SIGNAL_PULSES",
    "SIGNAL_RAMP",
    "SIGNAL_SAMPLED",
    "SIGNAL_SINE",
    "SIGNAL_STEP",
    "STATUS_MAXSTEPS",
    "STATUS_OK",
    "STATUS_OUTSIDE",
    "STATUS_JUMP",
    "STATUS_STEP_TOO_SMALL",
    "drive_value",
    "integrate_bed",
    "integrate_pillar",
    "pencil_outputs",
    "pencil_solve",
    "pillar_rates",
    "tip_speed",
    "projected_load",
    "workspace",
]


@kernel
def pencil_solve(aa, bb, g, sv, y):
    """y[f] of (sv[f] BB - AA) y[f] = g[f] for every frequency f (AA, BB upper triangular,
    complex (m, m); g, y complex (nf, m))."""
    m = aa.shape[0]
    for f in range(sv.size):
        s = sv[f]
        for i in range(m - 1, -1, -1):
            acc = g[f, i]
            for j in range(i + 1, m):
                acc -= (s * bb[i, j] - aa[i, j]) * y[f, j]
            y[f, i] = acc / (s * bb[i, i] - aa[i, i])


#: Frequencies per block of :func:`pencil_outputs` (its stages stay in the L1 cache).
_FBLOCK = 32


@kernel
def pencil_outputs(aa, bb, g, sv, cz, out):
    """out[r, f] = cz[r] . y(sv[f]) with (sv[f] BB - AA) y = g (one right-hand side g for
    every frequency; cz (rows, m) the outputs in the Schur basis; out complex (rows, nf)).

    The back substitution runs over blocks of frequencies at once, in real arithmetic on
    split real and imaginary parts, the frequency the innermost (contiguous) index: the
    operations of each frequency are those of a scalar back substitution, in the same order,
    while the loop over the block vectorises."""
    m = aa.shape[0]
    rows = cz.shape[0]
    nf = sv.size
    fb = _FBLOCK
    yr = np.empty((m, fb))
    yi = np.empty((m, fb))
    accr = np.empty(fb)
    acci = np.empty(fb)
    sr = np.empty(fb)
    si = np.empty(fb)
    for f0 in range(0, nf, fb):
        nb = min(fb, nf - f0)
        for f in range(nb):
            sr[f] = sv[f0 + f].real
            si[f] = sv[f0 + f].imag
        for i in range(m - 1, -1, -1):
            gr = g[i].real
            gi = g[i].imag
            for f in range(nb):
                accr[f] = gr
                acci[f] = gi
            for j in range(i + 1, m):
                ar = aa[i, j].real
                ai = aa[i, j].imag
                br = bb[i, j].real
                bi = bb[i, j].imag
                for f in range(nb):
                    cr = sr[f] * br - si[f] * bi - ar
                    ci = sr[f] * bi + si[f] * br - ai
                    accr[f] -= cr * yr[j, f] - ci * yi[j, f]
                    acci[f] -= cr * yi[j, f] + ci * yr[j, f]
            ar = aa[i, i].real
            ai = aa[i, i].imag
            br = bb[i, i].real
            bi = bb[i, i].imag
            for f in range(nb):
                dr = sr[f] * br - si[f] * bi - ar
                di = sr[f] * bi + si[f] * br - ai
                den = dr * dr + di * di
                yr[i, f] = (accr[f] * dr + acci[f] * di) / den
                yi[i, f] = (acci[f] * dr - accr[f] * di) / den
        for r in range(rows):
            for f in range(nb):
                accr[f] = 0.0
                acci[f] = 0.0
            for i in range(m):
                cr = cz[r, i].real
                ci = cz[r, i].imag
                for f in range(nb):
                    accr[f] += cr * yr[i, f] - ci * yi[i, f]
                    acci[f] += cr * yi[i, f] + ci * yr[i, f]
            for f in range(nb):
                out[r, f0 + f] = complex(accr[f], acci[f])


# ---------------------------------------------------------------------------------------
# The nonlinear pillar in time: the semi-discretisation and its Radau IIA integrator.
# ---------------------------------------------------------------------------------------

#: Status codes of :func:`integrate_pillar`.
STATUS_OK = 0
#: The pillar reached |theta| = pi/2 somewhere (lying on the wall): outside the model.
STATUS_OUTSIDE = -8
STATUS_MAXSTEPS = -2
STATUS_STEP_TOO_SMALL = -3
#: The tip's speed |dx1/dt| reached the run's ``jump_speed``: the state left its quasi-static
#: branch (a jump at a fold); the run stops there.
STATUS_JUMP = -9

_SQ6 = math.sqrt(6.0)
#: Radau IIA of order 5 (three stages): nodes, coefficients, and the embedded order-3
#: estimate's weights over gamma0 (Hairer & Wanner, Solving ODEs II, IV.8).
_C1 = (4.0 - _SQ6) / 10.0
_C2 = (4.0 + _SQ6) / 10.0
_RA = (
    ((88.0 - 7.0 * _SQ6) / 360.0, (296.0 - 169.0 * _SQ6) / 1800.0, (-2.0 + 3.0 * _SQ6) / 225.0),
    ((296.0 + 169.0 * _SQ6) / 1800.0, (88.0 + 7.0 * _SQ6) / 360.0, (-2.0 - 3.0 * _SQ6) / 225.0),
    ((16.0 - _SQ6) / 36.0, (16.0 + _SQ6) / 36.0, 1.0 / 9.0),
)
_DD = (-(13.0 + 7.0 * _SQ6) / 3.0, (-13.0 + 7.0 * _SQ6) / 3.0, -1.0 / 3.0)
_U1 = 1.0 / ((6.0 + 81.0 ** (1.0 / 3.0) - 9.0 ** (1.0 / 3.0)) / 30.0)


def _transformation() -> tuple[Any, Any, float, float]:
    """(T, T^-1, alpha, beta) with T^-1 A^-1 T = [[U1, 0, 0], [0, alpha, beta], [0, -beta,
    alpha]] (A the Radau IIA matrix): the stages decouple into one real system (U1/h - J)
    and one complex ((alpha - i beta)/h - J) (Hairer & Wanner, IV.8)."""
    a = np.array(_RA)
    val, vec = np.linalg.eig(np.linalg.inv(a))
    r = int(np.argmin(np.abs(val.imag)))
    c = int(np.argmax(val.imag))
    tm = np.column_stack([vec[:, r].real, vec[:, c].real, vec[:, c].imag])
    ti = np.linalg.inv(tm)
    return (
        tuple(tuple(float(x) for x in row) for row in tm),
        tuple(tuple(float(x) for x in row) for row in ti),
        float(val[c].real),
        float(val[c].imag),
    )


_TM, _TI, _ALPHA, _BETA = _transformation()


@kernel
def _full_angles(y, off, num, theta0, srow, th):
    """theta at the N + 1 nodes from the interior values y[off:off + N - 1]: theta_0 =
    theta0 (the clamp), theta_N = srow . theta (theta'(1) = 0)."""
    th[0] = theta0
    acc = srow[0] * theta0
    for j in range(1, num):
        th[j] = y[off + j - 1]
        acc += srow[j] * th[j]
    th[num] = acc


@kernel
def _reduce_into(full, num, srow, out, r0, c0, scale):
    """out[r0 + i - 1, c0 + k - 1] = scale (full[i, k] + full[i, N] srow[k]) for the
    interior i, k in 1 .. N - 1: a node operator on the interior unknowns (theta_N =
    srow . theta, theta_0 fixed)."""
    for i in range(1, num):
        for k in range(1, num):
            out[r0 + i - 1, c0 + k - 1] = scale * (full[i, k] + full[i, num] * srow[k])


@kernel
def pillar_rates(
    t, y, need, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, f, jac, ws
):
    """The semi-discrete pillar y' = f(t, y) (theory.md §14) and, where ``need``, its exact
    Jacobian df/dy into jac.

    y: the interior angles theta_1 .. theta_N-1 (mu = 0), then their rates (mu > 0). The
    interior collocation rows read B(theta) theta_t + mu [M(theta) theta_tt + (the
    centripetal part, theta_t^2)] = R(theta; Lambda(t), P(t)), R the static residual of
    ``spectral._residual_drag`` (rows theta'' + n . F), B and M by :func:`projected_load`;
    theta_0 = theta0 and theta'(1) = 0 (theta_N = srow . theta) close them. drives (2, 8):
    per drive (Lambda, P) its kind then its parameters; tabs (4, K): the sampled drives'
    times and values. ws: a workspace of :func:`_workspace`'s shapes (a tuple)."""
    vec = ws[0]
    th, rate, acc, zero, res = vec[0], vec[1], vec[2], vec[3], vec[4]
    u, val1, val2, val3 = vec[5], vec[6], vec[7], vec[8]
    mats = ws[1]
    opa1, opb1, dth1, opa2 = mats[0], mats[1], mats[2], mats[3]
    opb2, dth2, bmat, sjac = mats[4], mats[5], mats[6], mats[7]
    pm = ws[2]
    piv = ws[3]
    gw = ws[4]
    wrk = ws[5]
    n = num - 1
    n1 = num + 1
    lam = drive_value(int(drives[0, 0]), drives[0, 1:], tabs[0], tabs[1], t)
    tip = drive_value(int(drives[1, 0]), drives[1, 1:], tabs[2], tabs[3], t)
    _full_angles(y, 0, num, theta0, srow, th)
    for j in range(n1):
        u[j] = th[j]
        zero[j] = 0.0
    u[n1] = 0.0
    cs, sn, z, fx, fz = wrk[10], wrk[11], wrk[12], wrk[13], wrk[14]
    _residual_drag(u, num, dd, ii, theta0, lam, gamma, tip, prof, cs, sn, z, res, fx, fz)
    if mu == 0.0:
        projected_load(th, zero, zero, gamma, num, ii, 1, val1, opa1, opb1, dth1, wrk)
        _reduce_into(opa1, num, srow, bmat, 0, 0, 1.0)
        if not _lu_factor(bmat, piv, n):
            return False
        for i in range(n):
            f[i] = res[i + 1]
        _lu_apply(bmat, piv, f, n)
        if need:
            rate[0] = 0.0
            acc_n = 0.0
            for j in range(1, num):
                rate[j] = f[j - 1]
                acc_n += srow[j] * rate[j]
            rate[num] = acc_n
            projected_load(th, rate, zero, gamma, num, ii, 2, val1, opa1, opb1, dth1, wrk)
            _jacobian_drag(u, num, dd, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz, gw, pm, sjac)
            for i in range(n1):
                for k in range(n1):
                    dth1[i, k] = sjac[i, k] - dth1[i, k]
            _reduce_into(dth1, num, srow, jac, 0, 0, 1.0)
            col = val2
            for k in range(n):
                for i in range(n):
                    col[i] = jac[i, k]
                _lu_apply(bmat, piv, col, n)
                for i in range(n):
                    jac[i, k] = col[i]
        return True
    # with inertia: y = (theta, theta_t) on the interior
    rate[0] = 0.0
    acc_n = 0.0
    for j in range(1, num):
        rate[j] = y[n + j - 1]
        acc_n += srow[j] * rate[j]
    rate[num] = acc_n
    for j in range(n1):
        acc[j] = -rate[j] * rate[j]  # b = -theta_t^2 (the centripetal part of r_tt)
    # the drag B theta_t (its operator only for the Jacobian), the inertia's operator M
    projected_load(th, rate, zero, gamma, num, ii, 2 if need else 0, val1, opa1, opb1, dth1, wrk)
    projected_load(th, zero, acc, chi, num, ii, 2 if need else 1, val2, opa2, opb2, dth2, wrk)
    _reduce_into(opa2, num, srow, bmat, 0, 0, mu)
    if not _lu_factor(bmat, piv, n):
        return False
    for i in range(n):
        f[i] = y[n + i]
        f[n + i] = res[i + 1] - val1[i + 1] - mu * val2[i + 1]
    tail = f[n:]
    _lu_apply(bmat, piv, tail, n)
    if not need:
        return True
    # the accelerations at the nodes, then the inertia's derivative in theta at them
    zero[0] = 0.0
    acc_n = 0.0
    for j in range(1, num):
        zero[j] = f[n + j - 1]
        acc_n += srow[j] * zero[j]
    zero[num] = acc_n
    projected_load(th, zero, acc, chi, num, ii, 2, val3, opa2, opb2, dth2, wrk)
    for j in range(n1):
        zero[j] = 0.0
    _jacobian_drag(u, num, dd, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz, gw, pm, sjac)
    for i in range(n1):
        for k in range(n1):
            dth1[i, k] = sjac[i, k] - dth1[i, k] - mu * dth2[i, k]
            # d/d theta_t: -B and the centripetal -mu opb (-2 theta_t)
            opa1[i, k] = -opa1[i, k] + 2.0 * mu * opb2[i, k] * rate[k]
    m = 2 * n
    for i in range(m):
        for k in range(m):
            jac[i, k] = 0.0
    for i in range(n):
        jac[i, n + i] = 1.0
    _reduce_into(dth1, num, srow, jac, n, 0, 1.0)
    _reduce_into(opa1, num, srow, jac, n, n, 1.0)
    col = val2
    for k in range(m):
        for i in range(n):
            col[i] = jac[n + i, k]
        _lu_apply(bmat, piv, col, n)
        for i in range(n):
            jac[n + i, k] = col[i]
    return True


@kernel
def workspace(num):
    """The workspace tuple of :func:`pillar_rates` for degree N (allocated once a run)."""
    n1 = num + 1
    return (
        np.zeros((9, n1 + 1)),
        np.zeros((8, n1 + 1, n1 + 1)),
        np.zeros((2, n1, n1)),
        np.zeros(n1 + 1, dtype=np.int64),
        np.zeros((4, n1)),
        np.zeros((15, n1 + 1)),
    )


@kernel
def _dense(y0, z, m, tau, out):
    """The collocation polynomial of a Radau step at tau in [0, 1] (0: y0, c_i: y0 + Z_i):
    y0 + sum_i L_i(tau) Z_i over the nodes 0, c1, c2, 1."""
    l1 = tau * (tau - _C2) * (tau - 1.0) / (_C1 * (_C1 - _C2) * (_C1 - 1.0))
    l2 = tau * (tau - _C1) * (tau - 1.0) / (_C2 * (_C2 - _C1) * (_C2 - 1.0))
    l3 = tau * (tau - _C1) * (tau - _C2) / ((1.0 - _C1) * (1.0 - _C2))
    for k in range(m):
        out[k] = y0[k] + l1 * z[k] + l2 * z[m + k] + l3 * z[2 * m + k]


@kernel
def _lowest_cos(y, num, theta0, srow, th):
    """min_j cos(theta_j): <= 0 where the pillar reaches |theta| = pi/2."""
    _full_angles(y, 0, num, theta0, srow, th)
    low = 2.0
    for j in range(num + 1):
        low = min(low, math.cos(th[j]))
    return low


@kernel
def tip_speed(
    t, y, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, ft, dummy, ws, th
):
    """|dx1/dt| = |sum_j I_Nj cos(theta_j) theta_t,j| at (t, y) [L/T]: the rates are y's
    second half with inertia, f(t, y) of :func:`pillar_rates` when overdamped (NaN where
    that fails)."""
    n = num - 1
    _full_angles(y, 0, num, theta0, srow, th)
    acc = 0.0
    if mu == 0.0:
        if not pillar_rates(
            t,
            y,
            False,
            num,
            dd,
            ii,
            srow,
            theta0,
            gamma,
            chi,
            mu,
            prof,
            drives,
            tabs,
            ft,
            dummy,
            ws,
        ):
            return math.nan
        tn = 0.0
        for j in range(1, num):
            acc += ii[num, j] * math.cos(th[j]) * ft[j - 1]
            tn += srow[j] * ft[j - 1]
    else:
        tn = 0.0
        for j in range(1, num):
            acc += ii[num, j] * math.cos(th[j]) * y[n + j - 1]
            tn += srow[j] * y[n + j - 1]
    acc += ii[num, num] * math.cos(th[num]) * tn
    return abs(acc)


@kernel
def integrate_pillar(
    y0,
    t_start,
    t_eval,
    rtol,
    atol,
    h_start,
    max_steps,
    num,
    dd,
    ii,
    srow,
    theta0,
    gamma,
    chi,
    mu,
    prof,
    drives,
    tabs,
    y_out,
    counts,
    jump_speed=0.0,
):
    """Radau IIA (order 5, three stages, L-stable, stiffly accurate) on y' = f(t, y) of
    :func:`pillar_rates` from (t_start, y0) to t_eval[-1], writing y at every t_eval
    (sorted, >= t_start) into y_out by the collocation polynomial (dense output): the
    integrator :func:`_radau` with the pillar's model (mass I).

    Events, located by bisection on the dense output, stop the run: the pillar reaching
    |theta| = pi/2 at a node (it lies on the wall); where ``jump_speed`` > 0, the tip's speed
    |dx1/dt| (:func:`tip_speed`) reaching it (a jump off a fold). Returns (status, t_end):
    0, -8 at the wall, -9 at a jump, -2 after max_steps steps, -3 for a step below
    1e-14 (t + 1) or a singular matrix. counts: steps, accepted, rejected, f evaluations,
    Jacobians, LU factorisations."""
    m = y0.size
    mass = np.ones(m)
    pp = (num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs)
    return _radau(
        MODEL_PILLAR, mass, m, y0, t_start, t_eval, rtol, atol, h_start, max_steps, num,
        theta0, srow, pp, _no_bed(), y_out, counts, jump_speed,
    )  # fmt: skip


@kernel
def integrate_bed(y0, mass, index2, t_start, t_eval, rtol, atol, h_start, max_steps, bp,
                  y_out, counts):  # fmt: skip
    """Radau IIA (:func:`_radau`) on the porous bed's M y' = g(t, y) of
    ``bed.bed_system`` (theory.md §15; ``bp`` its parameter tuple, ``mass`` the diagonal of
    M, the components from ``index2`` on of index 2: Pi under a set flow rate with fluid
    inertia), writing y at every t_eval into y_out. Events: a node reaching |theta| = pi/2
    (status -8). Returns (status, t_end) as :func:`integrate_pillar`."""
    num = bp[0][0]
    theta0 = bp[1][0]
    srow = bp[5]
    z2 = np.zeros((1, 1))
    pp = (num, z2, z2, srow, 0.0, 1.0, 1.0, 0.0, np.zeros(1), np.zeros((2, 8)), np.zeros((4, 1)))
    return _radau(
        MODEL_BED, mass, index2, y0, t_start, t_eval, rtol, atol, h_start, max_steps, num,
        theta0, srow, pp, bp, y_out, counts, 0.0,
    )  # fmt: skip


@kernel
def _no_bed():
    """A bed parameter tuple of the right types for the pillar's runs (never read)."""
    ints = np.zeros(4, dtype=np.int64)
    ints[1] = 2
    z2 = np.zeros((1, 1))
    z1 = np.zeros(1)
    return (ints, np.zeros(7), z2, z2, z2, z1, z2, z2, z1, z1, np.zeros((2, 8)),
            np.zeros((4, 1)))  # fmt: skip


@kernel
def _lu_apply_t(lut, piv, r, m):
    """Solve with LU factors stored transposed (lut = the factors of :func:`_lu_factor`,
    transposed; its row swaps piv): r[:m] becomes the solution. The substitutions run over
    lut's rows, contiguous and free of reductions (the compiler vectorises them), the
    columns of L and U: the same products as ``_lu_apply``, summed in another order."""
    for k in range(m):
        p = piv[k]
        if p != k:
            t = r[k]
            r[k] = r[p]
            r[p] = t
    for k in range(m):  # L, unit lower triangular, by its columns
        f = r[k]
        if f != 0.0:
            lk = lut[k]
            for i in range(k + 1, m):
                r[i] -= lk[i] * f
    for i in range(m - 1, -1, -1):  # U by its columns
        lk = lut[i]
        f = r[i] / lk[i]
        r[i] = f
        if f != 0.0:
            for j in range(i):
                r[j] -= lk[j] * f


@kernel
def _reduced_factor(jac, dsel, asel, red, ired, col):
    """The algebraic unknowns of M y' = g eliminated from J (once a Jacobian): with d the
    kept components (``dsel``: M != 0, and the index-2 ones) and a the algebraic ones
    (``asel``), into ``red`` = (jaa, wt, kred, jdd_val, lu) and ``ired`` = (piva, jda_ptr,
    jda_col): the LU factors of J_aa (partial pivoting, stored transposed in jaa, its swaps
    in piva), W = J_aa^-1 J_ad stored transposed (wt, nd x na), J_da by its nonzeros (each
    row's from jda_ptr[i] to jda_ptr[i + 1]: the columns jda_col, the values jdd_val) and
    the reduced Jacobian K = J_dd - J_da W (nd x nd) in kred: (c M - J) x = r then needs
    only the LU of the small c M_d - K (:func:`_reduced_solve`). ``lu`` a work matrix
    (na x na). False where J_aa is singular."""
    jaa, wt, kred, jda_val, lu = red
    piva, jda_ptr, jda_col = ired
    nd = dsel.size
    na = asel.size
    for i in range(na):
        ai = asel[i]
        for k in range(na):
            lu[i, k] = jac[ai, asel[k]]
    if not _lu_factor(lu, piva, na):
        return False
    for i in range(na):
        for k in range(na):
            jaa[k, i] = lu[i, k]
    for k in range(nd):
        dk = dsel[k]
        for i in range(na):
            col[i] = jac[asel[i], dk]
        _lu_apply_t(jaa, piva, col, na)
        for i in range(na):
            wt[k, i] = col[i]
    nz = 0
    for i in range(nd):
        di = dsel[i]
        jda_ptr[i] = nz
        for k in range(nd):
            kred[i, k] = jac[di, dsel[k]]
        for l in range(na):
            f = jac[di, asel[l]]
            if f != 0.0:
                jda_col[nz] = l
                jda_val[nz] = f
                nz += 1
                for k in range(nd):
                    kred[i, k] -= f * wt[k, l]
    jda_ptr[nd] = nz
    return True


@kernel
def _reduced_solve(r, lus, pivs, dsel, asel, red, ired, ua, xd):
    """r[:m] := (c M - J)^-1 r[:m] (real) by the elimination of :func:`_reduced_factor`
    (lus, pivs the LU factors of c M_d - K): u = J_aa^-1 r_a, x_d = (c M_d - K)^-1
    (r_d - J_da u), x_a = -u - W x_d. ua (2, na) and xd (nd) are work arrays."""
    jaa, wt, jda_val = red[0], red[1], red[3]
    piva, jda_ptr, jda_col = ired
    nd = dsel.size
    na = asel.size
    ur = ua[0]
    for i in range(na):
        ur[i] = r[asel[i]]
    _lu_apply_t(jaa, piva, ur, na)
    for i in range(nd):
        acc = r[dsel[i]]
        for q in range(jda_ptr[i], jda_ptr[i + 1]):
            acc -= jda_val[q] * ur[jda_col[q]]
        xd[i] = acc
    _lu_apply(lus, pivs, xd, nd)
    for k in range(nd):
        f = xd[k]
        r[dsel[k]] = f
        if f != 0.0:
            wk = wt[k]
            for l in range(na):
                ur[l] += wk[l] * f
    for l in range(na):
        r[asel[l]] = -ur[l]


@kernel
def _reduced_solve_c(r, lus, pivs, dsel, asel, red, ired, ua, xd):
    """:func:`_reduced_solve` for a complex r and c (lus complex; xd complex (nd)): the
    real and imaginary parts of r_a go through the real J_aa^-1 and W apart."""
    jaa, wt, jda_val = red[0], red[1], red[3]
    piva, jda_ptr, jda_col = ired
    nd = dsel.size
    na = asel.size
    ur = ua[0]
    ui = ua[1]
    for i in range(na):
        v = r[asel[i]]
        ur[i] = v.real
        ui[i] = v.imag
    _lu_apply_t(jaa, piva, ur, na)
    _lu_apply_t(jaa, piva, ui, na)
    for i in range(nd):
        acc = r[dsel[i]]
        for q in range(jda_ptr[i], jda_ptr[i + 1]):
            l = jda_col[q]
            acc -= jda_val[q] * complex(ur[l], ui[l])
        xd[i] = acc
    _lu_apply(lus, pivs, xd, nd)
    for k in range(nd):
        f = xd[k]
        r[dsel[k]] = f
        wk = wt[k]
        fr = f.real
        fi = f.imag
        for l in range(na):
            ur[l] += wk[l] * fr
            ui[l] += wk[l] * fi
    for l in range(na):
        r[asel[l]] = -complex(ur[l], ui[l])


@kernel
def _rates(model, t, y, need, pp, bp, f, jac, ws, wsb):
    """The model's right-hand side g(t, y) of M y' = g and, where ``need``, its Jacobian:
    the pillar's :func:`pillar_rates` (M = I) or the bed's ``bed.bed_system``."""
    if model == MODEL_PILLAR:
        return pillar_rates(
            t, y, need, pp[0], pp[1], pp[2], pp[3], pp[4], pp[5], pp[6], pp[7], pp[8], pp[9],
            pp[10], f, jac, ws,
        )  # fmt: skip
    return _bed.bed_system(t, y, need, bp, f, jac, wsb)


@kernel
def _radau(
    model,
    mass,
    index2,
    y0,
    t_start,
    t_eval,
    rtol,
    atol,
    h_start,
    max_steps,
    num,
    theta0,
    srow,
    pp,
    bp,
    y_out,
    counts,
    jump_speed,
):
    """Radau IIA (order 5, three stages, L-stable, stiffly accurate) on M y' = g(t, y) with
    a constant diagonal mass vector ``mass`` (M = I: an ODE; zeros: the algebraic rows of an
    index-1 DAE), the model's g of :func:`_rates` (``model``: MODEL_PILLAR with its
    parameters ``pp``, MODEL_BED with ``bp``), from (t_start, y0) to t_eval[-1], writing y
    at every t_eval (sorted, >= t_start) into y_out by the collocation polynomial (dense
    output). The components from ``index2`` on are of index 2 (their error and Newton
    increments are scaled by h, as RADAU5 does).

    Simplified Newton on the stages with the exact Jacobian, the 3m system (1/h) A^-1 x M -
    I x J decoupled by the eigenvectors of A into one real and one complex system of size m
    ((U1/h) M - J and ((alpha - i beta)/h) M - J, two LUs), at most 7 iterations; the
    embedded order-3 error estimate of Hairer & Wanner (Solving ODEs II, IV.8),
    ((gamma0/h) M - J)^-1 (f0 + M sum_i DD_i Z_i/h), refined once after a rejection; the step
    by 0.9 err^(-1/4) within [0.2, 5]. Error norm: the root mean square of
    err/(atol + rtol max(|y0|, |y1|)) over the differential components (mass != 0), and the
    Newton increments' norm likewise: an index-1 DAE's algebraic components follow from the
    differential ones, and their estimate and increments are the rounding of the
    ill-conditioned collocation (condition ~1e8) at tight tolerances (the algebraic
    variables suppressed from the tests, as IDA's ``suppressalg``; SUNDIALS, Hindmarsh et
    al. 2005). The Jacobian and the LUs are reused as in Hairer &
    Wanner's RADAU5: after a step whose Newton converged in one iteration or with a
    contraction below 1e-3 the next step keeps the Jacobian (a new one is taken at the step's
    start after any rejection or divergent Newton with an old one), and keeps the LUs too where
    the proposed step is within [1, 1.2] of the last (the step is then kept).

    The bed's algebraic components (mass 0, index 1) are eliminated once a Jacobian
    (:func:`_reduced_factor`): their rows of c M - J do not depend on c, so the LU of J_aa
    and the reduced Jacobian K = J_dd - J_da J_aa^-1 J_ad serve every step size, and each
    new step needs only the LUs of c M_d - K on the kept components (31 of 127 unknowns for
    the overdamped bed with the quasi-steady fluid at N = 32; the full LUs cost 40x more).
    Its solves (:func:`_reduced_solve`) agree with the full LU's to about 1e-7 relatively at
    the largest steps (|W| = |J_aa^-1 J_ad| ~ 4e10): the simplified Newton's increments
    only, whose fixed point, the collocation solution, is the same; the Newton
    contraction, at most 0.03 before the test passes, absorbs it. Where J_aa is singular,
    the full LUs.

    Events as :func:`integrate_pillar` (the jump event for the pillar only)."""
    m = y0.size
    n_eval = t_eval.size
    mdiff = 0  # the error test counts the differential components (IDA's suppressalg)
    for k in range(m):
        if mass[k] != 0.0:
            mdiff += 1
    mdiff = max(mdiff, 1)
    ws = workspace(num if model == MODEL_PILLAR else 2)
    wsb = _bed.bed_workspace(num if model == MODEL_BED else 2, bp[0][1])
    th_tmp = np.empty(num + 1)
    y = y0.copy()
    y1 = np.empty(m)
    yt = np.empty(m)
    f0 = np.empty(m)
    ft = np.empty(m)
    jac = np.zeros((m, m))
    dummy = np.zeros((m, m))
    e2 = np.empty((m, m), dtype=np.complex128)
    piv2 = np.empty(m, dtype=np.int64)
    rc = np.empty(m, dtype=np.complex128)
    w = np.zeros(3 * m)
    e1 = np.empty((m, m))
    piv1 = np.empty(m, dtype=np.int64)
    # the algebraic components eliminated (:func:`_reduced_factor`): the bed's DAE
    nkeep = 0
    for k in range(m):
        if mass[k] != 0.0 or k >= index2:
            nkeep += 1
    nalg = m - nkeep if model == MODEL_BED else 0
    nkeep = m - nalg
    dsel = np.empty(nkeep, dtype=np.int64)
    asel = np.empty(nalg, dtype=np.int64)
    ik = 0
    ia = 0
    for k in range(m):
        if nalg == 0 or mass[k] != 0.0 or k >= index2:
            dsel[ik] = k
            ik += 1
        else:
            asel[ia] = k
            ia += 1
    red = (
        np.empty((nalg, nalg)),
        np.empty((nkeep, nalg)),
        np.empty((nkeep, nkeep)),
        np.empty(nkeep * nalg),
        np.empty((nalg, nalg)),
    )
    ired = (
        np.empty(nalg, dtype=np.int64),
        np.empty(nkeep + 1, dtype=np.int64),
        np.empty(nkeep * nalg, dtype=np.int64),
    )
    kred = red[2]
    col_a = np.empty(nalg)
    ua = np.empty((2, nalg))
    xd = np.empty(nkeep)
    xdc = np.empty(nkeep, dtype=np.complex128)
    s1 = np.empty((nkeep, nkeep))
    s2 = np.empty((nkeep, nkeep), dtype=np.complex128)
    reduced = False  # the current Jacobian's elimination is in use
    z = np.zeros(3 * m)
    z_prev = np.zeros(3 * m)
    g = np.empty(3 * m)
    err = np.empty(m)
    sc = np.empty(m)
    fst = np.empty((3, m))
    t = t_start
    t_end = t_eval[n_eval - 1]
    h = min(h_start, t_end - t) if t_end > t else 0.0
    nxt = 0
    while nxt < n_eval and t_eval[nxt] <= t:
        for k in range(m):
            y_out[nxt, k] = y[k]
        nxt += 1
    h_prev = 0.0
    have_prev = False
    rejected = False
    first = True
    steps = 0
    fnewt = 0.03
    cs = (_C1, _C2, 1.0)
    reuse = False  # the last step's Newton converged fast: its Jacobian serves this one
    fresh = False  # jac is the Jacobian at the step's start (t, y)
    h_lu = -1.0  # the step of the factorisations e1, e2 of the current jac (-1: none)
    while nxt < n_eval:
        if steps >= max_steps:
            return STATUS_MAXSTEPS, t
        if not _rates(
            model,
            t,
            y,
            not reuse,
            pp,
            bp,
            f0,
            dummy if reuse else jac,
            ws,
            wsb,
        ):
            return STATUS_STEP_TOO_SMALL, t
        counts[3] += 1
        if not reuse:
            counts[4] += 1
            h_lu = -1.0
        fresh = not reuse
        while True:  # attempts of this step
            steps += 1
            counts[0] += 1
            if h < 1e-14 * (abs(t) + 1.0) or steps > max_steps:
                return (STATUS_STEP_TOO_SMALL if steps <= max_steps else STATUS_MAXSTEPS), t
            # the stages' Newton matrix, decoupled by T: the real (U1/h) I - J (also the
            # error estimate's) and the complex ((alpha - i beta)/h) I - J
            if h != h_lu:
                shift = complex(_ALPHA / h, -_BETA / h)
                if h_lu < 0.0:  # a new Jacobian: its algebraic block eliminated once
                    reduced = nalg > 0 and _reduced_factor(jac, dsel, asel, red, ired, col_a)
                    if nalg > 0:
                        counts[5] += 1
                if reduced:
                    for i in range(nkeep):
                        for k in range(nkeep):
                            s1[i, k] = -kred[i, k]
                            s2[i, k] = -kred[i, k]
                        mi = mass[dsel[i]]
                        s1[i, i] += _U1 / h * mi
                        s2[i, i] += shift * mi
                    counts[5] += 2
                    if not _lu_factor(s1, piv1, nkeep) or not _lu_factor(s2, piv2, nkeep):
                        return STATUS_STEP_TOO_SMALL, t
                else:
                    for i in range(m):
                        for k in range(m):
                            e1[i, k] = -jac[i, k]
                            e2[i, k] = -jac[i, k]
                        e1[i, i] += _U1 / h * mass[i]
                        e2[i, i] += shift * mass[i]
                    counts[5] += 2
                    if not _lu_factor(e1, piv1, m) or not _lu_factor(e2, piv2, m):
                        return STATUS_STEP_TOO_SMALL, t
                h_lu = h
            # the start of the stages: the last step's polynomial, or Euler
            if have_prev and not rejected:
                for si in range(3):
                    _dense(y - y, z_prev, m, 1.0 + cs[si] * h / h_prev, yt)
                    for k in range(m):
                        z[si * m + k] = yt[k] - z_prev[2 * m + k]
            else:
                for si in range(3):
                    for k in range(m):  # (y' = g/M on the differential rows, 0 else)
                        fk = f0[k] if mass[k] == 1.0 else (f0[k] / mass[k] if mass[k] else 0.0)
                        z[si * m + k] = cs[si] * h * fk
            for k in range(m):
                sc[k] = atol + rtol * abs(y[k])
                if k >= index2:
                    sc[k] /= h
                for si in range(3):  # W = T^-1 Z
                    w[si * m + k] = (
                        _TI[si][0] * z[k] + _TI[si][1] * z[m + k] + _TI[si][2] * z[2 * m + k]
                    )
            ok = False
            rate_old = 1.0
            norm_old = 0.0
            eta = 1.0
            nit = 0
            for it in range(7):
                nit = it + 1
                good = True
                for si in range(3):
                    for k in range(m):
                        yt[k] = y[k] + z[si * m + k]
                    if not _rates(
                        model,
                        t + cs[si] * h,
                        yt,
                        False,
                        pp,
                        bp,
                        ft,
                        dummy,
                        ws,
                        wsb,
                    ):
                        good = False
                        break
                    for k in range(m):
                        fst[si, k] = ft[k]
                counts[3] += 3
                if not good:
                    break
                # the right-hand sides in W: -(Lambda/h) W + T^-1 F
                for k in range(m):
                    tf0 = _TI[0][0] * fst[0, k] + _TI[0][1] * fst[1, k] + _TI[0][2] * fst[2, k]
                    tf1 = _TI[1][0] * fst[0, k] + _TI[1][1] * fst[1, k] + _TI[1][2] * fst[2, k]
                    tf2 = _TI[2][0] * fst[0, k] + _TI[2][1] * fst[1, k] + _TI[2][2] * fst[2, k]
                    w0, w1, w2 = w[k], w[m + k], w[2 * m + k]
                    mk = mass[k]
                    g[k] = tf0 - _U1 / h * mk * w0
                    r2 = tf1 - mk * (_ALPHA * w1 + _BETA * w2) / h
                    r3 = tf2 - mk * (-_BETA * w1 + _ALPHA * w2) / h
                    rc[k] = complex(r2, r3)
                if reduced:
                    _reduced_solve(g, s1, piv1, dsel, asel, red, ired, ua, xd)
                    _reduced_solve_c(rc, s2, piv2, dsel, asel, red, ired, ua, xdc)
                else:
                    _lu_apply(e1, piv1, g, m)
                    _lu_apply(e2, piv2, rc, m)
                for k in range(m):
                    g[m + k] = rc[k].real
                    g[2 * m + k] = rc[k].imag
                norm = 0.0
                for k in range(m):
                    d0, d1, d2 = g[k], g[m + k], g[2 * m + k]
                    w[k] += d0
                    w[m + k] += d1
                    w[2 * m + k] += d2
                    for si in range(3):  # dZ = T dW
                        dz = _TM[si][0] * d0 + _TM[si][1] * d1 + _TM[si][2] * d2
                        z[si * m + k] += dz
                        if mass[k] != 0.0:
                            norm += (dz / sc[k]) ** 2
                norm = math.sqrt(norm / (3 * mdiff))
                if it > 0:
                    rate_old = norm / norm_old if norm_old > 0.0 else 0.0
                    if rate_old >= 0.99:
                        break
                    eta = rate_old / (1.0 - rate_old)
                else:
                    eta = max(eta, 1e-16) ** 0.8 if not first else 1.0
                norm_old = norm
                if eta * norm <= fnewt or norm == 0.0:
                    ok = True
                    break
                if not math.isfinite(norm):
                    break
            if not ok:
                rejected = True
                counts[2] += 1
                if not fresh:  # an old Jacobian: a new one, the same step
                    if not _rates(
                        model,
                        t,
                        y,
                        True,
                        pp,
                        bp,
                        f0,
                        jac,
                        ws,
                        wsb,
                    ):
                        return STATUS_STEP_TOO_SMALL, t
                    counts[3] += 1
                    counts[4] += 1
                    fresh = True
                    h_lu = -1.0
                else:
                    h *= 0.5
                continue
            for k in range(m):
                y1[k] = y[k] + z[2 * m + k]
                sc[k] = atol + rtol * max(abs(y[k]), abs(y1[k]))
                if k >= index2:
                    sc[k] /= h
            for k in range(m):
                acc = f0[k]
                if mass[k] == 1.0:
                    for si in range(3):
                        acc += _DD[si] * z[si * m + k] / h
                else:
                    part = 0.0
                    for si in range(3):
                        part += _DD[si] * z[si * m + k] / h
                    acc += mass[k] * part
                err[k] = acc
            if reduced:
                _reduced_solve(err, s1, piv1, dsel, asel, red, ired, ua, xd)
            else:
                _lu_apply(e1, piv1, err, m)
            en = 0.0
            for k in range(m):
                if mass[k] != 0.0:
                    en += (err[k] / sc[k]) ** 2
            en = math.sqrt(en / mdiff)
            if en >= 1.0 and (first or rejected):
                for k in range(m):
                    yt[k] = y[k] + err[k]
                _rates(
                    model,
                    t,
                    yt,
                    False,
                    pp,
                    bp,
                    ft,
                    dummy,
                    ws,
                    wsb,
                )
                counts[3] += 1
                for k in range(m):
                    acc = ft[k]
                    if mass[k] == 1.0:
                        for si in range(3):
                            acc += _DD[si] * z[si * m + k] / h
                    else:
                        part = 0.0
                        for si in range(3):
                            part += _DD[si] * z[si * m + k] / h
                        acc += mass[k] * part
                    err[k] = acc
                if reduced:
                    _reduced_solve(err, s1, piv1, dsel, asel, red, ired, ua, xd)
                else:
                    _lu_apply(e1, piv1, err, m)
                en = 0.0
                for k in range(m):
                    if mass[k] != 0.0:
                        en += (err[k] / sc[k]) ** 2
                en = math.sqrt(en / mdiff)
            fac = 0.9 * (2 * 7 + 1) / (nit + 2 * 7)
            if not math.isfinite(en):
                en = 1e10
            grow = fac * max(en, 1e-10) ** -0.25
            h_new = h * min(5.0, max(0.2, grow))
            if en < 1.0:
                break
            rejected = True
            counts[2] += 1
            h = h_new if not first else 0.1 * h
            if not fresh:
                if not _rates(
                    model,
                    t,
                    y,
                    True,
                    pp,
                    bp,
                    f0,
                    jac,
                    ws,
                    wsb,
                ):
                    return STATUS_STEP_TOO_SMALL, t
                counts[3] += 1
                counts[4] += 1
                fresh = True
                h_lu = -1.0
        # accepted: dense output, the event, the next step
        counts[1] += 1
        t_new = t + h
        low = _lowest_cos(y1, num, theta0, srow, th_tmp)
        t_stop = t_new
        status = STATUS_OK
        if low <= 0.0:  # bisection for the first time a node reaches pi/2
            lo = 0.0
            hi = 1.0
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                _dense(y, z, m, mid, yt)
                if _lowest_cos(yt, num, theta0, srow, th_tmp) <= 0.0:
                    hi = mid
                else:
                    lo = mid
            t_stop = t + hi * h
            status = STATUS_OUTSIDE
        if jump_speed > 0.0 and model == MODEL_PILLAR:
            tau = (t_stop - t) / h
            if tau < 1.0:
                _dense(y, z, m, tau, yt)
            else:
                for k in range(m):
                    yt[k] = y1[k]
            v = tip_speed(
                t_stop,
                yt,
                num,
                pp[1],
                pp[2],
                srow,
                theta0,
                pp[5],
                pp[6],
                pp[7],
                pp[8],
                pp[9],
                pp[10],
                ft,
                dummy,
                ws,
                th_tmp,
            )
            counts[3] += 1
            if not v < jump_speed:  # (NaN too) the first crossing, by bisection
                lo = 0.0
                hi = tau
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    _dense(y, z, m, mid, yt)
                    v = tip_speed(
                        t + mid * h,
                        yt,
                        num,
                        pp[1],
                        pp[2],
                        srow,
                        theta0,
                        pp[5],
                        pp[6],
                        pp[7],
                        pp[8],
                        pp[9],
                        pp[10],
                        ft,
                        dummy,
                        ws,
                        th_tmp,
                    )
                    counts[3] += 1
                    if not v < jump_speed:
                        hi = mid
                    else:
                        lo = mid
                t_stop = t + hi * h
                status = STATUS_JUMP
        while nxt < n_eval and t_eval[nxt] <= t_stop:
            _dense(y, z, m, (t_eval[nxt] - t) / h, yt)
            for k in range(m):
                y_out[nxt, k] = yt[k]
            nxt += 1
        if status != STATUS_OK:
            return status, t_stop
        for k in range(3 * m):
            z_prev[k] = z[k]
        for k in range(m):
            y[k] = y1[k]
        h_prev = h
        have_prev = True
        t = t_new
        if rejected:
            h_new = min(h_new, h)
        reuse = nit == 1 or rate_old < 1e-3
        if reuse and h <= h_new <= 1.2 * h:
            h_new = h  # the LUs too
        rejected = False
        first = False
        h = min(h_new, t_end - t) if t_end - t > 0.0 else h_new
        if t_end - t <= 1e-14 * (abs(t) + 1.0):
            while nxt < n_eval:
                for k in range(m):
                    y_out[nxt, k] = y[k]
                nxt += 1
    return STATUS_OK, t


#: The models of :func:`_radau`.
MODEL_PILLAR = 0
MODEL_BED = 1
