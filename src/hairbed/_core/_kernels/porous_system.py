"""The porous bed's collocation system (theory.md §13): its residual, exact Jacobian and the
size of a Newton step, for spectral's one Newton (``spectral._newton``) and the porous
bed's driver (``porous``).

Unknowns at the N + 1 mapped nodes s_j: theta_j, w_j (the fluid's velocity), Q_j (its shear
stress), then h1 and, for the flow drive, Pi (for the inverse, omega2). The rows:

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
matrix from the base. ``hfix`` (D_HFIX; NaN: free) freezes the tip height that the gap sees.
The element's loads come as its description row ``d`` (``description``).
"""

from __future__ import annotations

import math

from .._jit import kernel
from .description import D_EPS, D_GAMMA, D_HFIX, D_KAPPA, D_OMEGA2, D_PI, D_Q, D_THETA0, D_X1

__all__ = ["DRIVE_FLOW", "DRIVE_INVERSE", "DRIVE_PRESSURE", "size", "step_size"]

DRIVE_PRESSURE = 0
DRIVE_FLOW = 1
#: The inverse problem of the wall drive: omega2 is the unknown that puts the tip at x1t.
DRIVE_INVERSE = 2


@kernel
def size(code, num):
    """The number of unknowns: theta, w, Q at the nodes, h1, and Pi or omega2."""
    return 3 * (num + 1) + (1 if code == DRIVE_PRESSURE else 2)


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
def step_size(step, u, num, m):
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
