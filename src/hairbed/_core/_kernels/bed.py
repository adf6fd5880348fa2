"""The porous bed in time (issue 30, theory.md §15): its semi-discrete system
M y' = g(t, y) with a constant diagonal mass vector, and the exact Jacobian dg/dy.

The hair on the statics' mapped Chebyshev nodes s_j (j = 0 .. N), the bed's fluid on the
same nodes (v_j = v(z(s_j, t), t), the fluid's velocity in L/T, and Q_j = kappa v_z its
shear stress in the load units of §13), the gap [h1, 1/eps] on a Chebyshev grid of its own
in zeta in [0, 1] (z = h1 + zeta g, g = 1/eps - h1) where the fluid has inertia (alpha > 0).
The unknowns y, in this order (n = N - 1):

    theta_1 .. theta_N-1                       differential, mass 1: theta' = omega
    omega_1 .. omega_N-1  (the rates)          mu = 0: algebraic, the hair's force balance
                                               mu > 0: differential, mass 1: omega' = a
    a_1 .. a_N-1  (mu > 0: the accelerations)  algebraic, the hair's force balance
    v_1 .. v_N                                 v_1 .. v_N-1 mass alpha kappa (the fluid's
                                               momentum), v_N algebraic (the tip plane)
    Q_0 .. Q_N                                 algebraic: Q_j = kappa (D v)_j / cos theta_j
    gap v_1 .. v_M    (alpha > 0)              v_1 .. v_M-1 mass alpha kappa, v_M the top
                                               wall's row (algebraic)
    Pi                (flow drive)             algebraic: 6 eps^2 Phi = q(t)

theta_0 = theta0 and theta_N = srow . theta (theta'(1) = 0) are eliminated, as in the
pillar's ``dynamics.pillar_rates``; v_0 = 0 and the gap's v at zeta = 0 is the bed's v_N.

The rows (c = cos theta, s = sin theta at the node, K = I - (1 - gamma) t t):

    hair     R_i(theta, v) - (B omega)_i - mu [(M a)_i + C_i(omega)] = 0,  i = 1 .. N - 1,
             R the static collocation row of ``porous_system._residual`` with w = kappa v
             (D2 theta + n . int K v e_x), B omega = n . int K r_t and M a + C =
             n . int C_m r_tt by ``dynamics.projected_load``;
    bed      alpha kappa v_j' = (D Q)_j / c_j + Pi - f_x,j / c_j + alpha Q_j z_t,j,
             f_x = K_xx (v - x_t) - K_xz z_t (the drag on the hair, relative velocity),
             z_t = -int_0^s sin(theta) omega: the node moves with the hair;
    stress   kappa (D v)_j / c_j - Q_j = 0,  j = 0 .. N;
    tip      alpha = 0, the gap's exact Couette-Poiseuille profile: the wall drive
             eps kappa v_N + eps g Q_N - Pi eps g^2/2 = omega2(t), the stress drive
             Q_N - Pi g = tau(t); alpha > 0: Q_N = kappa (D_zeta v)_0 / g;
    gap      alpha kappa v_k' = kappa (D2_zeta v)_k / g^2 + Pi
                                + alpha kappa (D_zeta v)_k (1 - zeta_k) h1_t / g,
    top      wall: eps kappa v_M = omega2(t); stress: kappa (D_zeta v)_M / g = tau(t);
    flow     6 eps^2 Phi - q(t) = 0, Phi = kappa (int v cos ds + int_gap v dz) (alpha = 0:
             the gap's flux kappa v_N g + Q_N g^2/2 - Pi g^3/6 of its exact profile).

``bp``, the bed's parameters: (ints, flts, dd, ii, d1s, srow, dz, dz2, wz, zeta, drives,
tabs) with ints = (N, M, top (0 wall speed, 1 wall stress), pump (0 pressure, 1 flow)),
flts = (theta0, gamma, chi, mu, kappa, eps, alpha), dd, ii the statics' mapped operators,
d1s the first derivative in s, dz, dz2 the gap's first and second derivatives in zeta,
wz its Clenshaw-Curtis weights on [0, 1], zeta its nodes, drives (2, 8) the top wall's and
the pump's signals (``dynamics.drive_value``), tabs (4, K) their samples.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .description import D_EPS, D_GAMMA, D_HFIX, D_KAPPA, D_THETA0, NDESC
from .porous_system import DRIVE_PRESSURE, _jacobian, _residual
from .rod_motion import drive_value, projected_load

__all__ = ["bed_layout", "bed_mass", "bed_system", "bed_workspace"]

TOP_WALL = 0
TOP_STRESS = 1
PUMP_PRESSURE = 0
PUMP_FLOW = 1


@kernel
def bed_layout(num, num_gap, mu, alpha, pump):
    """The offsets of y's blocks: (n, omega, a, v, Q, gap, Pi, size); -1 where absent."""
    n = num - 1
    oom = n
    if mu > 0.0:
        oac = 2 * n
        ov = 3 * n
    else:
        oac = -1
        ov = 2 * n
    oq = ov + num
    og = oq + num + 1
    opi = og + (num_gap if alpha > 0.0 else 0)
    size = opi + (1 if pump == PUMP_FLOW else 0)
    if pump != PUMP_FLOW:
        opi = -1
    if alpha <= 0.0:
        og = -1
    return n, oom, oac, ov, oq, og, opi, size


@kernel
def bed_mass(num, num_gap, mu, alpha, kappa, pump, out):
    """The diagonal mass vector M of M y' = g(t, y) into out."""
    n, oom, oac, ov, oq, og, opi, size = bed_layout(num, num_gap, mu, alpha, pump)
    for i in range(size):
        out[i] = 0.0
    for i in range(n):
        out[i] = 1.0
        if mu > 0.0:
            out[oom + i] = 1.0
    if alpha > 0.0:
        for j in range(1, num):
            out[ov + j - 1] = alpha * kappa
        for k in range(1, num_gap):
            out[og + k - 1] = alpha * kappa


@kernel
def bed_workspace(num, num_gap):
    """The workspace of :func:`bed_system` for degrees N and M (allocated once a run)."""
    n1 = num + 1
    ms = 3 * n1 + 2
    return (
        np.zeros((20, n1 + 1)),
        np.zeros((8, n1, n1)),
        np.zeros((ms, ms)),
        np.zeros(ms),
        np.zeros(NDESC),
        np.zeros((6, n1)),
        np.zeros((15, n1 + 1)),
        np.zeros((3, num_gap + 1)),
    )


@kernel
def _put(jac, r, off, full, num, srow, scale):
    """jac[r, off + k - 1] += scale (full[k] + full[N] srow[k]) for the interior k: a row's
    derivative in the N + 1 nodal values of an angle-like field (the boundary values
    eliminated: node 0 fixed, node N = srow . interior)."""
    fn = full[num]
    for k in range(1, num):
        jac[r, off + k - 1] += scale * (full[k] + fn * srow[k])


@kernel
def bed_system(t, y, need, bp, out, jac, ws):
    """g(t, y) of M y' = g (the module's rows) into out and, where ``need``, its exact
    Jacobian dg/dy into jac. Returns False where a value is not finite. ws: the tuple of
    :func:`bed_workspace`."""
    ints, flts, dd, ii, d1s, srow, dz, dz2, wz, zeta = (
        bp[0], bp[1], bp[2], bp[3], bp[4], bp[5], bp[6], bp[7], bp[8], bp[9]
    )  # fmt: skip
    num, ngap, top, pump = ints[0], ints[1], ints[2], ints[3]
    theta0, gamma, chi, mu, kappa, eps, alpha = (
        flts[0], flts[1], flts[2], flts[3], flts[4], flts[5], flts[6]
    )  # fmt: skip
    n, oom, oac, ov, oq, og, opi, size = bed_layout(num, ngap, mu, alpha, pump)
    n1 = num + 1
    vec, mats, sjac, u, desc, pw, wrk, gv = ws
    th, om, ac, bb, vv, qq = vec[0], vec[1], vec[2], vec[3], vec[4], vec[5]
    val1, val2, cs, sn, kxx, kxz = vec[6], vec[7], vec[8], vec[9], vec[10], vec[11]
    rx, rz, dv, dq, fx, tmp = vec[12], vec[13], vec[14], vec[15], vec[16], vec[17]
    tmp2, zero = vec[18], vec[19]
    opa1, opb1, dth1, opa2, opb2, dth2 = mats[0], mats[1], mats[2], mats[3], mats[4], mats[5]
    vg, dg1, dg2 = gv[0], gv[1], gv[2]
    drives = bp[10]
    tabs = bp[11]
    wall = drive_value(int(drives[0, 0]), drives[0, 1:], tabs[0], tabs[1], t)
    pump_v = drive_value(int(drives[1, 0]), drives[1, 1:], tabs[2], tabs[3], t)
    # the nodal fields
    th[0] = theta0
    accn = srow[0] * theta0
    for j in range(1, num):
        th[j] = y[j - 1]
        accn += srow[j] * th[j]
    th[num] = accn
    om[0] = 0.0
    accn = 0.0
    for j in range(1, num):
        om[j] = y[oom + j - 1]
        accn += srow[j] * om[j]
    om[num] = accn
    if mu > 0.0:
        ac[0] = 0.0
        accn = 0.0
        for j in range(1, num):
            ac[j] = y[oac + j - 1]
            accn += srow[j] * ac[j]
        ac[num] = accn
        for j in range(n1):
            bb[j] = -om[j] * om[j]
    vv[0] = 0.0
    for j in range(1, n1):
        vv[j] = y[ov + j - 1]
    for j in range(n1):
        qq[j] = y[oq + j]
        zero[j] = 0.0
    pi_l = y[opi] if pump == PUMP_FLOW else pump_v
    one_g = 1.0 - gamma
    for j in range(n1):
        c = math.cos(th[j])
        s = math.sin(th[j])
        cs[j] = c
        sn[j] = s
        kxx[j] = 1.0 - one_g * s * s
        kxz[j] = -one_g * s * c
    h1 = 0.0
    for j in range(n1):
        h1 += ii[num, j] * cs[j]
        ax = 0.0
        az = 0.0
        a1 = 0.0
        a2 = 0.0
        for k in range(n1):  # four independent sums in one loop (each in its own order)
            w = ii[j, k]
            d = d1s[j, k]
            ax += w * om[k] * cs[k]
            az -= w * om[k] * sn[k]
            a1 += d * vv[k]
            a2 += d * qq[k]
        rx[j] = ax
        rz[j] = az
        dv[j] = a1
        dq[j] = a2
    for j in range(n1):
        fx[j] = kxx[j] * (vv[j] - rx[j]) - kxz[j] * rz[j]
    gg = 1.0 / eps - h1
    h1t = rz[num]
    # the hair's static rows (w = kappa v), by the statics' kernel
    for j in range(n1):
        u[j] = th[j]
        u[n1 + j] = kappa * vv[j]
        u[2 * n1 + j] = qq[j]
    u[3 * n1] = h1
    u[3 * n1 + 1] = 0.0
    for i in range(desc.size):
        desc[i] = 0.0
    desc[D_THETA0] = theta0
    desc[D_KAPPA] = kappa
    desc[D_GAMMA] = gamma
    desc[D_EPS] = eps
    desc[D_HFIX] = math.nan
    res = tmp2
    pcs, psn, pfx, pfz = pw[0], pw[1], pw[2], pw[3]
    _residual(u, num, dd, ii, DRIVE_PRESSURE, desc, pcs, psn, pfx, pfz, sjac[0])
    for i in range(n1):
        res[i] = sjac[0, i]
    lev = 2 if need else 0
    projected_load(th, om, zero, gamma, num, ii, lev, val1, opa1, opb1, dth1, wrk)
    if mu > 0.0:
        projected_load(th, ac, bb, chi, num, ii, lev, val2, opa2, opb2, dth2, wrk)
    # the rows
    ohair = oac if mu > 0.0 else oom
    for i in range(n):
        out[i] = om[i + 1]
        if mu > 0.0:
            out[oom + i] = ac[i + 1]
        r = res[i + 1] - val1[i + 1]
        if mu > 0.0:
            r -= mu * val2[i + 1]
        out[ohair + i] = r
    for j in range(1, num):
        out[ov + j - 1] = (dq[j] - fx[j]) / cs[j] + pi_l + alpha * qq[j] * rz[j]
    for j in range(n1):
        out[oq + j] = kappa * dv[j] / cs[j] - qq[j]
    ovn = ov + num - 1
    d0g = 0.0
    d1g = 0.0
    wsum = 0.0
    if alpha <= 0.0:
        if top == TOP_WALL:
            out[ovn] = eps * (kappa * vv[num] + gg * qq[num] - pi_l * gg * gg / 2.0) - wall
        else:
            out[ovn] = qq[num] - pi_l * gg - wall
    else:
        vg[0] = vv[num]
        for k in range(1, ngap + 1):
            vg[k] = y[og + k - 1]
        for k in range(ngap + 1):
            a1 = 0.0
            a2 = 0.0
            for l in range(ngap + 1):
                a1 += dz[k, l] * vg[l]
                a2 += dz2[k, l] * vg[l]
            dg1[k] = a1
            dg2[k] = a2
            wsum += wz[k] * vg[k]
        d0g = dg1[0]
        d1g = dg1[ngap]
        out[ovn] = qq[num] - kappa * d0g / gg
        for k in range(1, ngap):
            out[og + k - 1] = (
                kappa * dg2[k] / (gg * gg)
                + pi_l
                + alpha * kappa * dg1[k] * (1.0 - zeta[k]) * h1t / gg
            )
        if top == TOP_WALL:
            out[og + ngap - 1] = eps * kappa * vg[ngap] - wall
        else:
            out[og + ngap - 1] = kappa * d1g / gg - wall
    e6 = 6.0 * eps * eps
    bedflux = 0.0
    for j in range(n1):
        bedflux += ii[num, j] * vv[j] * cs[j]
    if pump == PUMP_FLOW:
        if alpha <= 0.0:
            phi = kappa * bedflux + kappa * vv[num] * gg + qq[num] * gg * gg / 2.0
            phi -= pi_l * gg * gg * gg / 6.0
        else:
            phi = kappa * bedflux + kappa * gg * wsum
        out[opi] = e6 * phi - pump_v
    for i in range(size):
        if not math.isfinite(out[i]):
            return False
    if not need:
        return True
    # ---------------- the exact Jacobian ----------------
    for i in range(size):
        for k in range(size):
            jac[i, k] = 0.0
    _jacobian(u, num, dd, ii, DRIVE_PRESSURE, desc, pcs, psn, pfx, pfz, pw[4], pw[5], sjac)
    wo = n1
    for i in range(n):
        r = ohair + i
        node = i + 1
        if mu > 0.0:
            jac[i, oom + i] = 1.0
            jac[oom + i, oac + i] = 1.0
        else:
            jac[i, oom + i] = 1.0
        for k in range(n1):
            tmp[k] = sjac[node, k] - dth1[node, k]
            if mu > 0.0:
                tmp[k] -= mu * dth2[node, k]
        _put(jac, r, 0, tmp, num, srow, 1.0)
        for k in range(n1):
            tmp[k] = -opa1[node, k]
            if mu > 0.0:
                tmp[k] += 2.0 * mu * opb2[node, k] * om[k]
        _put(jac, r, oom, tmp, num, srow, 1.0)
        if mu > 0.0:
            for k in range(n1):
                tmp[k] = -mu * opa2[node, k]
            _put(jac, r, oac, tmp, num, srow, 1.0)
        for k in range(1, n1):
            jac[r, ov + k - 1] = kappa * sjac[node, wo + k]
    # the bed's momentum rows
    for j in range(1, num):
        r = ov + j - 1
        cj = cs[j]
        for k in range(n1):
            jac[r, oq + k] = d1s[j, k] / cj
        jac[r, oq + j] += alpha * rz[j]
        jac[r, ov + j - 1] = -kxx[j] / cj
        if pump == PUMP_FLOW:
            jac[r, opi] = 1.0
        for k in range(n1):
            w = ii[j, k]
            tmp[k] = w * (kxx[j] * cs[k] - kxz[j] * sn[k]) / cj - alpha * qq[j] * w * sn[k]
        _put(jac, r, oom, tmp, num, srow, 1.0)
        sj = sn[j]
        for k in range(n1):
            w = ii[j, k] * om[k]
            tmp[k] = -w * (kxx[j] * sn[k] + kxz[j] * cs[k]) / cj - alpha * qq[j] * w * cs[k]
        dkxx = -2.0 * one_g * sj * cj
        dkxz = -one_g * (cj * cj - sj * sj)
        dfx = dkxx * (vv[j] - rx[j]) - dkxz * rz[j]
        tmp[j] += -dfx / cj + (dq[j] - fx[j]) * sj / (cj * cj)
        _put(jac, r, 0, tmp, num, srow, 1.0)
    # the stress rows
    for j in range(n1):
        r = oq + j
        cj = cs[j]
        for k in range(1, n1):
            jac[r, ov + k - 1] = kappa * d1s[j, k] / cj
        jac[r, oq + j] = -1.0
        for k in range(n1):
            tmp[k] = 0.0
        tmp[j] = kappa * dv[j] * sn[j] / (cj * cj)
        _put(jac, r, 0, tmp, num, srow, 1.0)
    # d g / d theta_k = I_Nk sin(theta_k) (g = 1/eps - h1), d h1_t / d theta_k and d omega_k
    for k in range(n1):
        tmp2[k] = ii[num, k] * sn[k]
    r = ovn
    if alpha <= 0.0:
        if top == TOP_WALL:
            jac[r, ovn] = eps * kappa
            jac[r, oq + num] = eps * gg
            if pump == PUMP_FLOW:
                jac[r, opi] = -eps * gg * gg / 2.0
            _put(jac, r, 0, tmp2, num, srow, eps * (qq[num] - pi_l * gg))
        else:
            jac[r, oq + num] = 1.0
            if pump == PUMP_FLOW:
                jac[r, opi] = -gg
            _put(jac, r, 0, tmp2, num, srow, -pi_l)
    else:
        jac[r, oq + num] = 1.0
        jac[r, ovn] -= kappa * dz[0, 0] / gg
        for k in range(1, ngap + 1):
            jac[r, og + k - 1] = -kappa * dz[0, k] / gg
        _put(jac, r, 0, tmp2, num, srow, kappa * d0g / (gg * gg))
        for k in range(1, ngap):
            r = og + k - 1
            fk = alpha * kappa * (1.0 - zeta[k]) / gg
            jac[r, ovn] += kappa * dz2[k, 0] / (gg * gg) + fk * h1t * dz[k, 0]
            for l in range(1, ngap + 1):
                jac[r, og + l - 1] = kappa * dz2[k, l] / (gg * gg) + fk * h1t * dz[k, l]
            if pump == PUMP_FLOW:
                jac[r, opi] = 1.0
            dgg = -2.0 * kappa * dg2[k] / (gg * gg * gg) - fk * dg1[k] * h1t / gg
            for q in range(n1):
                tmp[q] = dgg * tmp2[q] - fk * dg1[k] * ii[num, q] * om[q] * cs[q]
            _put(jac, r, 0, tmp, num, srow, 1.0)
            for q in range(n1):
                tmp[q] = -fk * dg1[k] * ii[num, q] * sn[q]
            _put(jac, r, oom, tmp, num, srow, 1.0)
        r = og + ngap - 1
        if top == TOP_WALL:
            jac[r, r] = eps * kappa
        else:
            jac[r, ovn] += kappa * dz[ngap, 0] / gg
            for l in range(1, ngap + 1):
                jac[r, og + l - 1] = kappa * dz[ngap, l] / gg
            _put(jac, r, 0, tmp2, num, srow, -kappa * d1g / (gg * gg))
    if pump == PUMP_FLOW:
        r = opi
        for j in range(1, n1):
            jac[r, ov + j - 1] = e6 * kappa * ii[num, j] * cs[j]
        for q in range(n1):
            tmp[q] = -e6 * kappa * ii[num, q] * vv[q] * sn[q]
        _put(jac, r, 0, tmp, num, srow, 1.0)
        if alpha <= 0.0:
            jac[r, ovn] += e6 * kappa * gg
            jac[r, oq + num] = e6 * gg * gg / 2.0
            jac[r, opi] = -eps * eps * gg * gg * gg
            coef = e6 * (kappa * vv[num] + qq[num] * gg - pi_l * gg * gg / 2.0)
        else:
            jac[r, ovn] += e6 * kappa * gg * wz[0]
            for k in range(1, ngap + 1):
                jac[r, og + k - 1] = e6 * kappa * gg * wz[k]
            coef = e6 * kappa * wsum
        _put(jac, r, 0, tmp2, num, srow, coef)
    return True
