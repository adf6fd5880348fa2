"""The parameter derivatives of the porous bed in time (theory.md §15; issue 32): the
columns dg/dp and dM/dp of the semi-discrete system M y' = g(t, y; p) of
:func:`hairbed._core._kernels.bed.bed_system`, exact.

The parameters, in the order of the ``P_*`` constants (the kernel's ``flts`` and the
drives' instantaneous values):

    theta0   the base angle: th_0 = theta0 and th_N = srow . th (theta'(1) = 0), so
             dg/dtheta0 = F_0 + srow_0 F_N, F_j = dg/dth_j the rows' partial derivatives in
             the nodal angles, from the pieces :func:`bed_system` leaves in its workspace
             (the statics' Jacobian, the projected loads' angle derivatives) and the rows
             that read th_0 or th_N written out;
    gamma    the drag ratio;
    kappa    the permeability over L^2 (the mass alpha kappa of the fluid's rows too);
    eps      L/H: the gap g = 1/eps - h1 and the explicit eps of the top wall's and the
             flow's rows, written out (dg/d eps at fixed y);
    alpha    the Womersley number (alpha > 0; the mass alpha kappa too);
    mu, chi  the hairs' inertia number and tangential mass (mu > 0);
    wall     the top wall's drive at t (omega2 or the wall stress), and
    pump     the pump's drive at t (Pi or q).

g is affine in gamma, kappa, alpha, mu, chi and in the drives' values (each enters a row
linearly: the drag tensor I - (1 - gamma) t t, the fluid's kappa v, the fluid's inertia
alpha, the hairs' mu [(M a) + C] with the mass tensor I - (1 - chi) t t, the drives), so
their columns are exact differences of :func:`bed_system` at two values of the parameter
(no truncation error; rounding only). Where a parameter is absent (alpha = 0: no fluid
inertia; mu = 0: overdamped hairs) its columns are 0.
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel
from .bed import PUMP_FLOW, TOP_WALL, bed_layout, bed_system
from .rod_motion import SIGNAL_CONSTANT, drive_value

__all__ = [
    "NPAR",
    "P_ALPHA",
    "P_CHI",
    "P_EPS",
    "P_GAMMA",
    "P_KAPPA",
    "P_MU",
    "P_PUMP",
    "P_THETA0",
    "P_WALL",
    "bed_parameter_columns",
    "bed_parameter_phases",
]

P_THETA0 = 0
P_GAMMA = 1
P_KAPPA = 2
P_EPS = 3
P_ALPHA = 4
P_MU = 5
P_CHI = 6
P_WALL = 7
P_PUMP = 8
#: The number of parameters (rows of the kernel's outputs).
NPAR = 9

# the slots of the kernel's flts (bed.bed_system's order)
_F_THETA0, _F_GAMMA, _F_CHI, _F_MU, _F_KAPPA, _F_EPS, _F_ALPHA = 0, 1, 2, 3, 4, 5, 6


@kernel
def _with(bp, flts, drives):
    """bp with its flts and drives replaced."""
    return (bp[0], flts, bp[2], bp[3], bp[4], bp[5], bp[6], bp[7], bp[8], bp[9], drives, bp[11])


@kernel
def _difference(t, y, bp, slot, lo, hi, out, work, jac, ws):
    """(g(p = hi) - g(p = lo))/(hi - lo) into out, p = flts[slot] (g affine in p)."""
    flts = bp[1].copy()
    flts[slot] = hi
    ok = bed_system(t, y, False, _with(bp, flts, bp[10]), out, jac, ws)
    flts[slot] = lo
    ok = bed_system(t, y, False, _with(bp, flts, bp[10]), work, jac, ws) and ok
    for i in range(out.size):
        out[i] = (out[i] - work[i]) / (hi - lo)
    return ok


@kernel
def _drive_difference(t, y, bp, which, out, work, jac, ws):
    """dg/d(drive ``which``'s value at t): the drive held constant at 1 and at 0."""
    drives = bp[10].copy()
    drives[which, 0] = SIGNAL_CONSTANT
    drives[which, 1] = 1.0
    ok = bed_system(t, y, False, _with(bp, bp[1], drives), out, jac, ws)
    drives[which, 1] = 0.0
    ok = bed_system(t, y, False, _with(bp, bp[1], drives), work, jac, ws) and ok
    for i in range(out.size):
        out[i] = out[i] - work[i]
    return ok


@kernel
def bed_parameter_columns(t, y, bp, gp, mp, jac, ws):
    """dg/dp into gp[p] and dM/dp (the mass vector's) into mp[p], p the ``P_*`` parameters,
    at (t, y) of the system ``bp`` (``bed.bed_system``'s parameter tuple). jac: a (size,
    size) scratch matrix; ws: :func:`bed.bed_workspace`'s tuple. Returns False where a
    value is not finite."""
    ints, flts, ii, srow, zeta = bp[0], bp[1], bp[3], bp[5], bp[9]
    num, ngap, top, pump = ints[0], ints[1], ints[2], ints[3]
    mu, kappa, eps, alpha = flts[_F_MU], flts[_F_KAPPA], flts[_F_EPS], flts[_F_ALPHA]
    n, oom, oac, ov, oq, og, opi, size = bed_layout(num, ngap, mu, alpha, pump)
    n1 = num + 1
    for p in range(gp.shape[0]):
        for i in range(size):
            gp[p, i] = 0.0
            mp[p, i] = 0.0
    out = np.empty(size)
    work = np.empty(size)
    # the Jacobian's pieces at (t, y), left in the workspace
    if not bed_system(t, y, True, bp, out, jac, ws):
        return False
    vec, mats, sjac, gv = ws[0], ws[1], ws[2], ws[7]
    om, vv, qq = vec[1], vec[4], vec[5]
    cs, sn, kxx, kxz, rz, dv = vec[8], vec[9], vec[10], vec[11], vec[13], vec[14]
    dth1, dth2 = mats[2], mats[5]
    vg, dg1, dg2 = gv[0], gv[1], gv[2]
    drives, tabs = bp[10], bp[11]
    pi_l = y[opi] if pump == PUMP_FLOW else drive_value(int(drives[1, 0]), drives[1, 1:],
                                                        tabs[2], tabs[3], t)  # fmt: skip
    h1 = 0.0
    for j in range(n1):
        h1 += ii[num, j] * cs[j]
    gg = 1.0 / eps - h1
    dgg = -1.0 / (eps * eps)  # d g/d eps
    h1t = rz[num]
    d0g = dg1[0]
    d1g = dg1[ngap]
    # ---- theta0: F_0 + srow_0 F_N of every row that reads th_0 or th_N ----
    s0 = srow[0]
    th0 = gp[0]
    ohair = oac if mu > 0.0 else oom
    for i in range(n):
        node = i + 1
        f0 = sjac[node, 0] - dth1[node, 0]
        fn = sjac[node, num] - dth1[node, num]
        if mu > 0.0:
            f0 -= mu * dth2[node, 0]
            fn -= mu * dth2[node, num]
        th0[ohair + i] = f0 + s0 * fn
    for j in range(1, num):  # the bed's momentum rows: the hair's velocity at the tip node
        w = ii[j, num] * om[num]
        fn = -w * (kxx[j] * sn[num] + kxz[j] * cs[num]) / cs[j] - alpha * qq[j] * w * cs[num]
        th0[ov + j - 1] = s0 * fn
    th0[oq] = kappa * dv[0] * sn[0] / (cs[0] * cs[0])  # the stress rows at nodes 0 and N
    th0[oq + num] = s0 * kappa * dv[num] * sn[num] / (cs[num] * cs[num])
    # rows through the tip height h1 = I_N . cos(theta): dh1/dth_j = -I_Nj sin(theta_j)
    dh0 = -(ii[num, 0] * sn[0] + s0 * ii[num, num] * sn[num])  # d h1/d theta0
    ovn = ov + num - 1
    wsum = 0.0
    if alpha <= 0.0:
        if top == TOP_WALL:
            th0[ovn] = -eps * (qq[num] - pi_l * gg) * dh0
            gp[P_EPS, ovn] = (
                kappa * vv[num] + gg * qq[num] - pi_l * gg * gg / 2.0
                + eps * (qq[num] - pi_l * gg) * dgg
            )  # fmt: skip
        else:
            th0[ovn] = pi_l * dh0
            gp[P_EPS, ovn] = -pi_l * dgg
    else:
        for k in range(ngap + 1):
            wsum += bp[8][k] * vg[k]
        th0[ovn] = -kappa * d0g / (gg * gg) * dh0
        gp[P_EPS, ovn] = kappa * d0g / (gg * gg) * dgg
        for k in range(1, ngap):
            r = og + k - 1
            fk = alpha * kappa * (1.0 - zeta[k]) / gg
            d_gap = -2.0 * kappa * dg2[k] / (gg * gg * gg) - fk * dg1[k] * h1t / gg
            # h1_t = -I_N . (sin(theta) omega): its th_N part (omega_0 = 0)
            dh1t = -s0 * ii[num, num] * cs[num] * om[num]
            th0[r] = -d_gap * dh0 + fk * dg1[k] * dh1t
            gp[P_EPS, r] = d_gap * dgg
        r = og + ngap - 1
        if top == TOP_WALL:
            gp[P_EPS, r] = kappa * vg[ngap]
        else:
            th0[r] = kappa * d1g / (gg * gg) * dh0
            gp[P_EPS, r] = -kappa * d1g / (gg * gg) * dgg
    if pump == PUMP_FLOW:
        e6 = 6.0 * eps * eps
        bedflux = 0.0
        for j in range(n1):
            bedflux += ii[num, j] * vv[j] * cs[j]
        if alpha <= 0.0:
            phi = kappa * bedflux + kappa * vv[num] * gg + qq[num] * gg * gg / 2.0
            phi -= pi_l * gg * gg * gg / 6.0
            coef = e6 * (kappa * vv[num] + qq[num] * gg - pi_l * gg * gg / 2.0)
        else:
            phi = kappa * bedflux + kappa * gg * wsum
            coef = e6 * kappa * wsum
        dflux = -e6 * kappa * s0 * ii[num, num] * vv[num] * sn[num]  # v_0 = 0
        th0[opi] = dflux - coef * dh0
        gp[P_EPS, opi] = 12.0 * eps * phi + coef * dgg
    # ---- the parameters g is affine in: exact differences ----
    ok = True
    ok = _difference(t, y, bp, _F_GAMMA, 0.5, 1.0, gp[P_GAMMA], work, jac, ws) and ok
    ok = _difference(t, y, bp, _F_KAPPA, kappa, 2.0 * kappa, gp[P_KAPPA], work, jac, ws) and ok
    if alpha > 0.0:
        ok = _difference(t, y, bp, _F_ALPHA, alpha, 2.0 * alpha, gp[P_ALPHA], work, jac,
                         ws) and ok  # fmt: skip
        for j in range(1, num):
            mp[P_KAPPA, ov + j - 1] = alpha
            mp[P_ALPHA, ov + j - 1] = kappa
        for k in range(1, ngap):
            mp[P_KAPPA, og + k - 1] = alpha
            mp[P_ALPHA, og + k - 1] = kappa
    if mu > 0.0:
        ok = _difference(t, y, bp, _F_MU, mu, 2.0 * mu, gp[P_MU], work, jac, ws) and ok
        ok = _difference(t, y, bp, _F_CHI, 0.5, 1.0, gp[P_CHI], work, jac, ws) and ok
    ok = _drive_difference(t, y, bp, 0, gp[P_WALL], work, jac, ws) and ok
    ok = _drive_difference(t, y, bp, 1, gp[P_PUMP], work, jac, ws) and ok
    for p in range(gp.shape[0]):
        for i in range(size):
            if not np.isfinite(gp[p, i]):
                return False
    return ok


@kernel
def bed_parameter_phases(t, y, bp, gp, mp, jac, ws):
    """:func:`bed_parameter_columns` at every phase of an orbit in one call: t (K,), y
    (K, size), gp and mp (K, NPAR, size). Returns False where a value is not finite."""
    for k in range(t.size):
        if not bed_parameter_columns(t[k], y[k], bp, gp[k], mp[k], jac, ws):
            return False
    return True
