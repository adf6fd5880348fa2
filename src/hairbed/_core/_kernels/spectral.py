"""Chebyshev collocation of a hair under a tip load and a load per unit height (issue 20).

    theta'' = -[W + Pi (h1 - z(s))] cos(theta),  z' = cos(theta),  x' = sin(theta),
    theta(0) = theta0,  theta'(1) = 0,  z(0) = x(0) = 0,  h1 = z(1),

with the loads W(h1), Pi(h1) of a drive (``DRIVE_PRESSURE``, ``DRIVE_FLOW``; theory.md §11),
or the resistive-force drag of a flow on the isolated pillar (``DRIVE_DRAG``; theory.md §12).
Each element's loads come as one row of named slots, its load description (``description``),
the vocabulary that the porous bed's kernel shares.

Discretisation. Chebyshev-Gauss-Lobatto nodes xi_j = -cos(pi j/N) on [-1, 1], mapped to
s in [0, 1] by the exponential map s = expm1(a y)/expm1(a), y = (xi + 1)/2, which clusters the
nodes at the base for the boundary layer of strong loads (a = 0 is the plain affine map; the
wrapper picks a from the load). The unknowns are theta at the N + 1 nodes and h1. The rows:
theta_0 = theta0; the ODE at the interior nodes, with z = I_s cos(theta) by the spectral
integration matrix; theta'(1) = 0 by the differentiation matrix; h1 = z(1). The
differentiation and integration matrices in xi are built once per N by the wrapper
(``hairbed._core.loaded``) and passed in; the map enters as diagonal scalings.

Newton with the exact Jacobian (the drive's dW/dh1 and dPi/dh1 included), a backtracking line
search on the squared residual, at most ``MAXITER`` iterations, the linear systems by an
in-place LU with partial pivoting on preallocated arrays (no allocation per step), its
factors reused for chord steps once Newton contracts by 10 a step below 1e-3. A ladder of
N (each level started from the interpolant of the previous one) stops at the first level whose
Chebyshev tail of theta (the sum of the moduli of its last three coefficients) is within the
tolerance; the error estimate is that tail plus the rounding part ``ROUNDING`` N^2
max(1, |theta|). Where Newton fails on the first level, a continuation in the load factor from
the hair at rest (``MAX_CONTINUATION`` steps at most). The base curvature is the quadrature of
the ODE's right-hand side (theta'(0) = int_0^1 [W + Pi (h1 - z)] cos(theta) ds). Drive code
``DRIVE_FIXED`` freezes the loads (W = omega2, Pi = load) for the scan of ``solve_loaded_all``.

Status codes (``hairbed._core.validation.STATUS_MESSAGES``): 0 converged within the tolerance;
3 converged, but the tail at the largest N misses the tolerance; -2 iteration limit; -3
singular Newton matrix or no descent; -7 no state from this start (the iterate left the
physical range: |theta| > 10, h1 outside [-1, 1] or the gap 1 - eps h1 closed, or the load
continuation stalled at a fold).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from . import porous_system as ps
from .description import (
    D_DX1,
    D_EPS,
    D_GAMMA,
    D_HFIX,
    D_LAMBDA,
    D_OMEGA2,
    D_PI,
    D_Q,
    D_THETA0,
    D_TIP,
    D_X1,
)

__all__ = [
    "DRIVE_DRAG",
    "DRIVE_DRAG_INVERSE",
    "DRIVE_FIXED",
    "DRIVE_FLOW",
    "DRIVE_PRESSURE",
    "MAXITER",
    "NCOLS",
    "STATUS_BREAKDOWN",
    "STATUS_INACCURATE",
    "STATUS_LOST",
    "STATUS_MAXITER",
    "bed_arguments",
    "drive_loads",
    "solve_loaded_array",
    "solve_loaded_chain",
]

DRIVE_PRESSURE = 0
DRIVE_FLOW = 1
DRIVE_FIXED = 2
#: The isolated pillar under resistive-force drag (issue 21, theory.md §12): its description
#: holds Lambda, the drag ratio gamma and a horizontal tip force; ``prof`` the profile U(z).
DRIVE_DRAG = 3
#: The pillar's inverse problem: Lambda is an unknown, the target tip displacement
#: x1 - sin(theta0) in D_DX1.
DRIVE_DRAG_INVERSE = 4
#: The porous bed (``porous_system``, theory.md §13): codes POROUS + its drive (pressure,
#: flow, inverse), the hair's system with the fluid's fields, on this module's Newton.
POROUS = 8
MAXITER = 60
#: The rounding part of the error estimate, ROUNDING N^2 max(1, |theta|) (measured: the
#: collocation's differences between N and 2N at rounding level grow like N^2).
ROUNDING = 1e-15
#: The most steps of the load continuation that follows a failed Newton iteration.
MAX_CONTINUATION = 200
STATUS_INACCURATE = 3
STATUS_MAXITER = -2
STATUS_BREAKDOWN = -3
STATUS_LOST = -7
#: Output columns of :func:`solve_loaded_array`: status, nit, num, a, h1, x1, theta1,
#: theta'(0), W, Pi, error estimate, residual, the forcing (omega2; the pillar's Lambda),
#: the pillar's dx1/dLambda (NaN for the bed's drives), the tip displacement
#: x1 - sin(theta0) (by :func:`_displacement`, without the cancellation of x1's).
NCOLS = 15
#: A Newton step below this (max norm over theta and h1) ends the iteration.
_XTOL = 1e-12
#: Chord steps (the last LU factors reused) follow a full Newton step below _CHORD_START that
#: contracted by _CHORD_RATE; a chord step that contracts less refreshes the factors.
_CHORD_START = 1e-3
_CHORD_RATE = 0.1
#: Steps below this are taken whole, without the line search (rounding-level merit).
_FULL_STEP = 1e-7
#: The chain argument of :func:`solve_loaded_chain` that chains no element.
_NO_CHAIN = np.zeros(0, dtype=np.bool_)


@kernel
def drive_loads(code, omega2, eps, load, h):
    """(W, Pi, dW/dh1, dPi/dh1) of the drive ``code`` at tip height h (``load`` is pi or q;
    for ``DRIVE_FIXED`` W = omega2 and Pi = load, independent of h)."""
    if code == DRIVE_FIXED:  # fixed loads W = omega2, Pi = load (the scan of solve_loaded_all)
        return omega2, load, 0.0, 0.0
    u = 1.0 - eps * h
    if code == DRIVE_PRESSURE:
        w = omega2 / u
        dw = omega2 * eps / (u * u)
        if load != 0.0:  # eps > 0 here (validated)
            w += 0.5 * load * (1.0 / eps - h)
            dw -= 0.5 * load
        return w, load, dw, 0.0
    # flow drive: W = q/u^2 - 2 omega2/u, Pi = 2 eps q/u^3 - 6 eps omega2/u^2
    u2 = u * u
    u3 = u2 * u
    w = load / u2 - 2.0 * omega2 / u
    p = 2.0 * eps * load / u3 - 6.0 * eps * omega2 / u2
    dw = eps * (2.0 * load / u3 - 2.0 * omega2 / u2)
    dp = eps * eps * (6.0 * load / (u3 * u) - 12.0 * omega2 / u3)
    return w, p, dw, dp


@kernel
def _map(a, num, nodes, sp, ss):
    """s, ds/dxi at the first num + 1 entries of ``nodes`` into ss, sp (exponential map)."""
    if a == 0.0:
        for j in range(num + 1):
            ss[j] = 0.5 * (nodes[j] + 1.0)
            sp[j] = 0.5
        return
    e = math.expm1(a)
    for j in range(num + 1):
        y = 0.5 * (nodes[j] + 1.0)
        ss[j] = math.expm1(a * y) / e
        sp[j] = 0.5 * a * math.exp(a * y) / e
    ss[0] = 0.0
    ss[num] = 1.0


@kernel
def _operators(num, d1, d2, im, sp, a, dd, ii):
    """The mapped operators of one state at one level: dd rows 1 .. N - 1 the second
    derivative in s (d2/ds2 = (D2 - (a/2) D)/s'^2, as s''/s' = a/2), row N the first
    (D/s'); ii = I diag(s'), the integration in s from the base."""
    half_a = 0.5 * a
    for i in range(num + 1):
        inv = 1.0 / sp[i]
        for j in range(num + 1):
            ii[i, j] = im[i, j] * sp[j]
            if i == num:
                dd[i, j] = d1[i, j] * inv
            else:
                dd[i, j] = (d2[i, j] - half_a * d1[i, j]) * inv * inv


@kernel
def _lu_factor(mat, piv, m):
    """LU factors of mat[:m, :m] with partial pivoting, in place (the row swaps in piv);
    False if a pivot vanishes. The update runs over two rows at a time on row views (the
    compiler vectorises it; about 2.5x the speed of one row at m ~ 100) and skips the rows
    whose entry in the pivot's column is zero: the same arithmetic, bit for bit, in the
    same order, as the plain elimination."""
    for k in range(m):
        p = k
        big = abs(mat[k, k])
        for i in range(k + 1, m):
            v = abs(mat[i, k])
            if v > big:
                big = v
                p = i
        if big == 0.0 or not math.isfinite(big):
            return False
        piv[k] = p
        if p != k:
            for j in range(m):
                t = mat[k, j]
                mat[k, j] = mat[p, j]
                mat[p, j] = t
        inv = 1.0 / mat[k, k]
        rk = mat[k, k + 1 : m]
        n = m - k - 1
        i = k + 1
        while True:
            while i < m and mat[i, k] == 0.0:
                i += 1
            if i >= m:
                break
            i2 = i + 1
            while i2 < m and mat[i2, k] == 0.0:
                i2 += 1
            f = mat[i, k] * inv
            mat[i, k] = f
            ri = mat[i, k + 1 : m]
            if i2 >= m:
                for j in range(n):
                    ri[j] -= f * rk[j]
                break
            g = mat[i2, k] * inv
            mat[i2, k] = g
            r2 = mat[i2, k + 1 : m]
            for j in range(n):
                r = rk[j]
                ri[j] -= f * r
                r2[j] -= g * r
            i = i2 + 1
    return True


@kernel
def _lu_apply(mat, piv, rhs, m):
    """Solve with the factors of :func:`_lu_factor`: rhs[:m] becomes the solution."""
    for k in range(m):  # the row swaps first (the factors hold whole swapped rows) ...
        p = piv[k]
        if p != k:
            t = rhs[k]
            rhs[k] = rhs[p]
            rhs[p] = t
    for k in range(m):  # ... then L (unit lower triangular)
        f = rhs[k]
        if f != 0.0:
            for i in range(k + 1, m):
                rhs[i] -= mat[i, k] * f
    for i in range(m - 1, -1, -1):
        acc = rhs[i]
        for j in range(i + 1, m):
            acc -= mat[i, j] * rhs[j]
        rhs[i] = acc / mat[i, i]


@kernel
def _residual(u, num, dd, ii, theta0, code, omega2, eps, load, cs, sn, z, res):
    """The residual of the collocation system at u (theta at the nodes, then h1) into res;
    returns (sum of squares, W, Pi, dW, dPi). dd, ii: the mapped operators
    (:func:`_operators`); cs, sn, z: cos, sin and z at the nodes."""
    n1 = num + 1
    h = u[n1]
    for j in range(n1):
        cs[j] = math.cos(u[j])
        sn[j] = math.sin(u[j])
    for i in range(n1):
        acc = 0.0
        for j in range(n1):
            acc += ii[i, j] * cs[j]
        z[i] = acc
    w, p, dw, dp = drive_loads(code, omega2, eps, load, h)
    res[0] = u[0] - theta0
    # the operators annihilate constants: relative to theta at the tip, the products round
    # on the deflection's size, not the angle's
    ref = u[num]
    for i in range(1, num):
        a2 = 0.0
        for j in range(n1):
            a2 += dd[i, j] * (u[j] - ref)
        res[i] = a2 + (w + p * (h - z[i])) * cs[i]
    a1 = 0.0
    for j in range(n1):
        a1 += dd[num, j] * (u[j] - ref)
    res[num] = a1
    res[n1] = h - z[num]
    ss = 0.0
    for i in range(n1 + 1):
        ss += res[i] * res[i]
    return ss, w, p, dw, dp


@kernel
def _jacobian(u, num, dd, ii, cs, sn, z, w, p, dw, dp, jac):
    """The exact Jacobian of :func:`_residual` at u into jac (cs, sn, z from that call)."""
    n1 = num + 1
    h = u[n1]
    for j in range(n1 + 1):
        jac[0, j] = 0.0
    jac[0, 0] = 1.0
    for i in range(1, num):
        pc = p * cs[i]
        for j in range(n1):
            jac[i, j] = dd[i, j] + pc * ii[i, j] * sn[j]
        jac[i, i] -= (w + p * (h - z[i])) * sn[i]
        jac[i, n1] = (dw + dp * (h - z[i]) + p) * cs[i]
    for j in range(n1):
        jac[num, j] = dd[num, j]
        jac[n1, j] = ii[num, j] * sn[j]
    jac[num, n1] = 0.0
    jac[n1, n1] = 1.0


@kernel
def profile_value(prof, z):
    """(U, dU/dz) of the profile U(z) = sum_k prof[k] T_k(2 z - 1) (Chebyshev on z in [0, 1])."""
    t = 2.0 * z - 1.0
    k_max = prof.size
    val = prof[0]
    der = 0.0
    if k_max > 1:
        t_prev, t_cur = 1.0, t  # T_0, T_1
        d_prev, d_cur = 0.0, 1.0  # T_0', T_1'
        val += prof[1] * t
        der += prof[1]
        for k in range(2, k_max):
            t_next = 2.0 * t * t_cur - t_prev
            d_next = 2.0 * t_cur + 2.0 * t * d_cur - d_prev
            val += prof[k] * t_next
            der += prof[k] * d_next
            t_prev, t_cur = t_cur, t_next
            d_prev, d_cur = d_cur, d_next
    return val, 2.0 * der


@kernel
def _drag_forces(u, num, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz):
    """The drag per unit length fx, fz at the nodes and its totals (F_x(0), F_z(0)), with
    cos, sin and z at the nodes of u written into cs, sn, z (theory.md §12)."""
    n1 = num + 1
    for j in range(n1):
        cs[j] = math.cos(u[j])
        sn[j] = math.sin(u[j])
    for i in range(n1):
        acc = 0.0
        for j in range(n1):
            acc += ii[i, j] * cs[j]
        z[i] = acc
    one_g = 1.0 - gamma
    for j in range(n1):
        uu, _ = profile_value(prof, z[j])
        c, s = cs[j], sn[j]
        fx[j] = lam * uu * (c * c + gamma * s * s)
        fz[j] = -lam * uu * one_g * s * c
    tx = tip
    tz = 0.0
    for j in range(n1):
        tx += ii[num, j] * fx[j]
        tz += ii[num, j] * fz[j]
    return tx, tz


@kernel
def _internal_force(i, num, ii, fx, fz, tx, tz):
    """F(s_i) = tip + int_{s_i}^1 f ds (the totals tx, tz less the integral from the base)."""
    ax = 0.0
    az = 0.0
    for j in range(num + 1):
        ax += ii[i, j] * fx[j]
        az += ii[i, j] * fz[j]
    return tx - ax, tz - az


@kernel
def _unit_load(u, num, ii, gamma, prof, cs, sn, z, fx, fz, col):
    """dR/dLambda of the pillar's collocation system (rows 0 .. num + 1) into col: the drag
    at Lambda = 1 without the tip load (f is linear in Lambda), its per-unit-length values in
    fx, fz (workspace) and cos, sin, z at the nodes of u in cs, sn, z."""
    n1 = num + 1
    tx, tz = _drag_forces(u, num, ii, 1.0, gamma, 0.0, prof, cs, sn, z, fx, fz)
    col[0] = 0.0
    for i in range(1, num):
        fxi, fzi = _internal_force(i, num, ii, fx, fz, tx, tz)
        col[i] = fxi * cs[i] - fzi * sn[i]
    col[num] = 0.0
    col[n1] = 0.0


@kernel
def _residual_drag(u, num, dd, ii, theta0, lam, gamma, tip, prof, cs, sn, z, res, fx, fz):
    """The residual of the pillar's collocation system (theta'' = -(F_x cos - F_z sin)) at u
    into res; returns its sum of squares. Rows as :func:`_residual`."""
    n1 = num + 1
    h = u[n1]
    tx, tz = _drag_forces(u, num, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz)
    res[0] = u[0] - theta0
    ref = u[num]
    for i in range(1, num):
        a2 = 0.0
        for j in range(n1):
            a2 += dd[i, j] * (u[j] - ref)
        fxi, fzi = _internal_force(i, num, ii, fx, fz, tx, tz)
        res[i] = a2 + fxi * cs[i] - fzi * sn[i]
    a1 = 0.0
    for j in range(n1):
        a1 += dd[num, j] * (u[j] - ref)
    res[num] = a1
    res[n1] = h - z[num]
    ss = 0.0
    for i in range(n1 + 1):
        ss += res[i] * res[i]
    return ss


@kernel
def _jacobian_drag(u, num, dd, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz, gw, pm, jac):
    """The exact Jacobian of :func:`_residual_drag` at u into jac (cs, sn, z, fx, fz from that
    call). gw (4, >= num + 1) and pm (2, >= num + 1, >= num + 1) are workspace: gw holds
    df/dtheta and df/dz at the nodes, pm rows of I diag(df/dz) I, through which
    z = I cos(theta) enters F = int_s^1 f."""
    n1 = num + 1
    one_g = 1.0 - gamma
    bx, bz, ax, az = gw[0], gw[1], gw[2], gw[3]
    for j in range(n1):
        uu, du = profile_value(prof, z[j])
        c, s = cs[j], sn[j]
        bx[j] = -2.0 * lam * uu * one_g * s * c  # d fx / d theta
        bz[j] = -lam * uu * one_g * (c * c - s * s)  # d fz / d theta
        ax[j] = lam * du * (c * c + gamma * s * s)  # d fx / d z
        az[j] = -lam * du * one_g * s * c  # d fz / d z
    # F(s_i) = F(0) - (I f)_i depends on theta_k through z = I cos(theta): with
    # P_x = I diag(ax) I and P_z = I diag(az) I, row i needs
    # ci (P_x[num] - P_x[i]) - si (P_z[num] - P_z[i]); the rows at the tip once, and row i's
    # combination ci P_x[i] - si P_z[i] = I[i] diag(ci ax - si az) I in one product (one
    # triple loop, not two). pm[0] rows 0-2 are the row buffers.
    tipx, tipz, row = pm[0, 0], pm[0, 1], pm[0, 2]
    for k in range(n1):
        tipx[k] = 0.0
        tipz[k] = 0.0
    for j in range(n1):
        wx = ii[num, j] * ax[j]
        wz = ii[num, j] * az[j]
        for k in range(n1):
            tipx[k] += wx * ii[j, k]
            tipz[k] += wz * ii[j, k]
    tx = tip
    tz = 0.0
    for j in range(n1):
        tx += ii[num, j] * fx[j]
        tz += ii[num, j] * fz[j]
    for j in range(n1 + 1):
        jac[0, j] = 0.0
    jac[0, 0] = 1.0
    for i in range(1, num):
        ci, si = cs[i], sn[i]
        for k in range(n1):
            row[k] = 0.0
        for j in range(n1):
            wj = ii[i, j] * (ci * ax[j] - si * az[j])
            if wj == 0.0:
                continue
            for k in range(n1):
                row[k] += wj * ii[j, k]
        fxi, fzi = _internal_force(i, num, ii, fx, fz, tx, tz)
        for k in range(n1):
            r = ii[num, k] - ii[i, k]
            via_z = ci * tipx[k] - si * tipz[k] - row[k]
            jac[i, k] = dd[i, k] + r * (ci * bx[k] - si * bz[k]) - sn[k] * via_z
        jac[i, i] -= fxi * si + fzi * ci
        jac[i, n1] = 0.0
    for j in range(n1):
        jac[num, j] = dd[num, j]
        jac[n1, j] = ii[num, j] * sn[j]
    jac[num, n1] = 0.0
    jac[n1, n1] = 1.0


@kernel
def bed_arguments(code, d):
    """(omega2, eps, load) of a bed's drive ``code`` from the description ``d``, as
    :func:`drive_loads` reads them: the wall and Pi (pressure), the wall and q (flow), the
    frozen tip force and Pi (``DRIVE_FIXED``)."""
    if code == DRIVE_FLOW:
        return d[D_OMEGA2], d[D_EPS], d[D_Q]
    if code == DRIVE_FIXED:
        return d[D_TIP], d[D_EPS], d[D_PI]
    return d[D_OMEGA2], d[D_EPS], d[D_PI]


@kernel
def _displacement(u, num, ii, theta0):
    """The tip displacement x1 - sin(theta0) = int_0^1 (sin(theta) - sin(theta0)) ds of the
    state u, the integrand as 2 cos((theta + theta0)/2) sin((theta - theta0)/2): no
    cancellation where theta stays near theta0 (a pillar leaning onto the wall, whose x1 ~ -1
    rounds away a displacement of 1e-9 and the changes of 1e-14 along its window; issue 33)."""
    acc = 0.0
    for j in range(num + 1):
        half_sum = 0.5 * (u[j] + theta0)
        acc += ii[num, j] * (2.0 * math.cos(half_sum) * math.sin(0.5 * (u[j] - theta0)))
    return acc


@kernel
def _system(u, num, dd, ii, code, d, prof, work, res):
    """The residual of either model (``DRIVE_DRAG`` or a bed's drive) at u into res:
    (sum of squares, W, Pi, dW, dPi), the loads zero for the pillar. ``d`` the element's load
    description (``description``)."""
    if code >= POROUS:  # cos, sin, f_x, f_z into work rows 0, 1, 6, 7
        f = ps._residual(u, num, dd, ii, code - POROUS, d, work[0], work[1], work[6], work[7], res)
        return f, 0.0, 0.0, 0.0, 0.0
    if code == DRIVE_DRAG or code == DRIVE_DRAG_INVERSE:
        # for the inverse u[num + 2] is Lambda, and D_DX1 the target tip displacement
        # x1 - sin(theta0)
        inverse = code == DRIVE_DRAG_INVERSE
        n1 = num + 1
        lam = u[n1 + 1] if inverse else d[D_LAMBDA]
        cs, sn, z, fx, fz = work[0], work[1], work[2], work[6], work[7]
        f = _residual_drag(
            u, num, dd, ii, d[D_THETA0], lam, d[D_GAMMA], d[D_TIP], prof, cs, sn, z, res, fx, fz
        )
        if not inverse:
            return f, 0.0, 0.0, 0.0, 0.0
        res[n1 + 1] = _displacement(u, num, ii, d[D_THETA0]) - d[D_DX1]
        return f + res[n1 + 1] ** 2, 0.0, 0.0, 0.0, 0.0
    omega2, eps, load = bed_arguments(code, d)
    return _residual(
        u, num, dd, ii, d[D_THETA0], code, omega2, eps, load, work[0], work[1], work[2], res
    )


@kernel
def _system_jacobian(u, num, dd, ii, code, d, prof, work, pm, w, p, dw, dp, jac):
    """The Jacobian of :func:`_system` at u (after it) into jac."""
    if code >= POROUS:
        ps._jacobian(
            u,
            num,
            dd,
            ii,
            code - POROUS,
            d,
            work[0],
            work[1],
            work[6],
            work[7],
            work[8],
            work[9],
            jac,
        )
    elif code == DRIVE_DRAG or code == DRIVE_DRAG_INVERSE:
        inverse = code == DRIVE_DRAG_INVERSE
        n1 = num + 1
        lam = u[n1 + 1] if inverse else d[D_LAMBDA]
        gamma, tip = d[D_GAMMA], d[D_TIP]
        cs, sn, z = work[0], work[1], work[2]
        _jacobian_drag(
            u, num, dd, ii, lam, gamma, tip, prof, cs, sn, z, work[6], work[7], work[8:12], pm, jac
        )
        if inverse:
            # the column of Lambda: the load at Lambda = 1 (f is linear in Lambda); the row of
            # x1 - sin(theta0) = int_0^1 (sin(theta) - sin(theta0)) ds, whose derivative in
            # theta_k is the quadrature weight times cos(theta_k) (no cancellation in it)
            _unit_load(u, num, ii, gamma, prof, cs, sn, z, work[8], work[9], jac[:, n1 + 1])
            for k in range(n1):
                jac[n1 + 1, k] = ii[num, k] * cs[k]
            jac[n1 + 1, n1] = 0.0
            jac[n1 + 1, n1 + 1] = 0.0
    else:
        _jacobian(u, num, dd, ii, work[0], work[1], work[2], w, p, dw, dp, jac)


@kernel
def _step_size(code, step, u, num, m):
    """The max norm of a Newton step over theta and h1, and the relative step of Lambda
    where it is an unknown (m = n1 + 2); the porous bed's (``porous_system.step_size``)."""
    if code >= POROUS:
        return ps.step_size(step, u, num, m)
    n1 = num + 1
    big = 0.0
    for i in range(n1 + 1):
        big = max(big, abs(step[i]))
    for i in range(n1 + 1, m):
        big = max(big, abs(step[i]) / max(1.0, abs(u[i])))
    return big


@kernel
def system_size(code, num):
    """(unknowns, index of h1) of a model's system at N = num."""
    if code >= POROUS:
        return ps.size(code - POROUS, num), 3 * (num + 1)
    return num + (3 if code == DRIVE_DRAG_INVERSE else 2), num + 1


@kernel
def _gap_moves(code, d):
    """Whether the gap 1 - eps h1 follows the iterate's h1 (a bed's drive; not the pillar,
    nor a porous scan's frozen gap)."""
    if code >= POROUS:
        return math.isnan(d[D_HFIX])
    return code != DRIVE_DRAG and code != DRIVE_DRAG_INVERSE


@kernel
def _newton(u, num, dd, ii, code, d, prof, work, pm, jac, piv, nit0, maxiter, warm):
    """Damped Newton on the collocation system from u (updated in place).

    Returns (status, iterations, max abs(residual)). ``work`` is (12, >= num + 2), ``pm``
    (2, >= num + 1, >= num + 1); ``prof`` the pillar's profile (``DRIVE_DRAG``). ``warm``:
    jac and piv already hold the LU factors of a nearby state's Jacobian of this size (a
    neighbour on a curve), so the iteration starts with chord steps on them; the first
    chord step is kept if it is below ``_CHORD_START``, later ones if they contract by
    ``_CHORD_RATE``, else the Jacobian is refreshed as after any chord step.
    """
    n1 = num + 1
    m, hi = system_size(code, num)
    res, step, trial = work[3], work[4], work[5]
    gap = _gap_moves(code, d)
    eps = d[D_EPS]
    f, w, p, dw, dp = _system(u, num, dd, ii, code, d, prof, work, res)
    chord = warm  # reuse the last factors (a chord step) once Newton contracts fast
    last = _CHORD_START / _CHORD_RATE if warm else math.inf
    for it in range(maxiter):
        if not math.isfinite(f):
            return STATUS_BREAKDOWN, nit0 + it, math.nan
        if not chord:
            _system_jacobian(u, num, dd, ii, code, d, prof, work, pm, w, p, dw, dp, jac)
            if not _lu_factor(jac, piv, m):
                return STATUS_BREAKDOWN, nit0 + it, math.nan
        for i in range(m):
            step[i] = -res[i]
        _lu_apply(jac, piv, step, m)
        big = _step_size(code, step, u, num, m)
        if not math.isfinite(big):
            return STATUS_BREAKDOWN, nit0 + it, math.nan
        if chord and big > _CHORD_RATE * last:  # the chord contracts too slowly: refresh
            chord = False
            _system_jacobian(u, num, dd, ii, code, d, prof, work, pm, w, p, dw, dp, jac)
            if not _lu_factor(jac, piv, m):
                return STATUS_BREAKDOWN, nit0 + it, math.nan
            for i in range(m):
                step[i] = -res[i]
            _lu_apply(jac, piv, step, m)
            big = _step_size(code, step, u, num, m)
        lam = 1.0
        if big > _FULL_STEP:
            # limit a wild step (one radian of angle, a tenth of the height), then backtrack
            lam = min(1.0, 1.0 / big, 0.1 / max(abs(step[hi]), 1e-300))
        while True:
            for i in range(m):
                trial[i] = u[i] + lam * step[i]
            if gap and 1.0 - eps * trial[hi] <= 0.0:
                ft = math.inf
            else:
                ft, w, p, dw, dp = _system(trial, num, dd, ii, code, d, prof, work, res)
            if big <= _FULL_STEP or ft <= (1.0 - 1e-4 * lam) * f:
                break
            lam *= 0.5
            if lam < 1e-6:
                return STATUS_BREAKDOWN, nit0 + it + 1, math.sqrt(f)
        for i in range(m):
            u[i] = trial[i]
        f = ft
        # a full step well inside the region of quadratic convergence: chord steps next
        chord = lam == 1.0 and big <= _CHORD_START and big <= _CHORD_RATE * last
        last = big
        if abs(u[hi]) > 1.0 + 1e-9 or (gap and 1.0 - eps * u[hi] <= 0.0):
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
def _continuation(u, keep, num, dd, ii, code, d, dl, prof, work, pm, jac, piv, nit0):
    """Newton along the load factor lam from 0 (the hair at rest) to 1: every load of the
    description ``d`` (the wall's omega2, Pi or q, the tip force, the pillar's Lambda)
    scaled by lam, so both loads, W and Pi, of either drive. A secant predictor, the step
    grown after an easy corrector and cut after a failed one; at most ``MAX_CONTINUATION``
    steps. Ends with the state at lam = 1 in u, or a failure status. keep is (3, num + 3),
    ``dl`` the scaled description's work row. For the pillar's inverse problem
    (``DRIVE_DRAG_INVERSE``) lam moves the tip displacement x1 - sin(theta0) from the
    straight pillar's, 0, to D_DX1 (the porous bed's inverse: its tip deflection from
    sin(theta0) to D_X1), and Lambda starts at 0."""
    drag_inverse = code == DRIVE_DRAG_INVERSE
    inverse = drag_inverse or code == POROUS + ps.DRIVE_INVERSE
    theta0 = d[D_THETA0]
    m, hi = system_size(code, num)
    prev = keep[1]
    last = keep[2]
    for j in range(m):  # the hair at rest, the fluid (porous) and the unknown load at 0
        last[j] = 0.0
    for j in range(num + 1):
        last[j] = theta0
    last[hi] = math.cos(theta0)
    rest = math.sin(theta0)
    for j in range(m):
        prev[j] = last[j]
    for j in range(d.size):
        dl[j] = d[j]
    lam = 0.0
    lam_prev = 0.0
    dlam = 0.125
    nit = nit0
    status = STATUS_BREAKDOWN
    rmax = math.nan
    for _ in range(MAX_CONTINUATION):
        target = min(1.0, lam + dlam)
        slope = (target - lam) / (lam - lam_prev) if lam > lam_prev else 0.0
        for j in range(m):
            u[j] = last[j] + slope * (last[j] - prev[j])
        for slot in (D_OMEGA2, D_PI, D_Q, D_TIP, D_LAMBDA):
            dl[slot] = target * d[slot]
        if drag_inverse:
            dl[D_DX1] = target * d[D_DX1]
        elif inverse:
            dl[D_X1] = rest + target * (d[D_X1] - rest)
        status, nit, rmax = _newton(
            u, num, dd, ii, code, dl, prof, work, pm, jac, piv, nit, 12, False
        )
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
def _drag_slope(u, num, dd, ii, lam, gamma, tip, prof, work, pm, jac, piv):
    """dx1/dLambda of a converged pillar state u by implicit differentiation of the
    collocation system: J du/dLambda = -dR/dLambda, dR/dLambda the load at Lambda = 1 (f is
    linear in Lambda); NaN where J is singular (a fold). Uses work rows 0-2, 4 and 6-11."""
    n1 = num + 1
    cs, sn, z = work[0], work[1], work[2]
    fx, fz = work[6], work[7]
    _drag_forces(u, num, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz)
    _jacobian_drag(u, num, dd, ii, lam, gamma, tip, prof, cs, sn, z, fx, fz, work[8:12], pm, jac)
    if not _lu_factor(jac, piv, n1 + 1):
        return math.nan
    rhs = work[4]
    _unit_load(u, num, ii, gamma, prof, cs, sn, z, work[8], work[9], rhs)
    for i in range(n1 + 1):
        rhs[i] = -rhs[i]
    _lu_apply(jac, piv, rhs, n1 + 1)
    slope = 0.0
    for k in range(n1):
        slope += ii[num, k] * cs[k] * rhs[k]
    return slope


@kernel
def _coefficients(vals, num, cmat, coef):
    """Chebyshev coefficients coef[:num + 1] of the node values vals (cmat values -> coef)."""
    for k in range(num + 1):
        acc = 0.0
        for j in range(num + 1):
            acc += cmat[k, j] * vals[j]
        coef[k] = acc


@kernel
def _clenshaw(coef, num, x):
    """sum_k coef[k] T_k(x), k = 0 .. num."""
    b1 = 0.0
    b2 = 0.0
    for k in range(num, 0, -1):
        b0 = 2.0 * x * b1 - b2 + coef[k]
        b2 = b1
        b1 = b0
    return x * b1 - b2 + coef[0]


def solve_loaded_array(*args):
    """Solve every element: the collocation system on the ladder of N ``nums``.

    The arguments, in order: code, desc, a, start, h_start, nums, nodes, d1s, d2s, ims, cms,
    rtol, prof, out, coefs. ``desc`` (size, ``description.NDESC``): each element's load
    description, whose slots its model fills (a bed's drive: D_THETA0, D_OMEGA2, D_EPS and
    D_PI or D_Q, or D_TIP and D_PI frozen for ``DRIVE_FIXED``; the pillar: D_THETA0,
    D_LAMBDA, D_GAMMA, D_TIP, and D_DX1 for ``DRIVE_DRAG_INVERSE``). ``start`` (size,
    nums[0] + 1): theta at the mapped nodes of the first level; ``h_start`` (size, 1) the
    start's h1, or (size, 2) h1 and Lambda for ``DRIVE_DRAG_INVERSE``; ``a`` the map
    parameter of each element. ``nodes``, ``d1s``, ``d2s``, ``ims``, ``cms`` hold per level
    (padded to the largest N): the nodes in xi, the first and second differentiation
    matrices, the integration matrix from xi = -1, and the matrix from node values to
    Chebyshev coefficients. ``prof`` (1 or size, K): the pillar's profile U(z) per element,
    Chebyshev coefficients in 2 z - 1 (``DRIVE_DRAG``; unused otherwise). Writes ``out``
    (NCOLS, size) and the Chebyshev coefficients in xi of theta, x and z into ``coefs``
    (3, size, largest N + 1). For the pillar the columns W, Pi hold the drag F_x(0), F_z(0)
    and theta'(0) is int_0^1 (z f_x - x f_z) ds.

    A Python call of :func:`solve_loaded_chain` with no element chained.
    """
    solve_loaded_chain(*args, _NO_CHAIN)


@kernel
def _warm_start(u, tan, step, num_prev, cm_prev, a_prev, extra, num, nodes, a, sp, ss, coef):
    """The start of a curve's next element from the previous element's state u (theta at its
    num_prev + 1 mapped nodes, then h1 and, for the inverse, Lambda) plus ``step`` times its
    tangent ``tan`` (du/dLambda of the forward problem, du/dx1 of the inverse): the
    predictor's interpolant at this element's first-level nodes (map a), in u."""
    n_prev = num_prev + 1 + extra
    for j in range(n_prev):
        u[j] += step * tan[j]
    if num_prev == num and a_prev == a:
        return
    tail0 = u[num_prev + 1]
    tail1 = u[num_prev + 2] if extra == 2 else 0.0
    _coefficients(u, num_prev, cm_prev, coef)
    _map(a, num, nodes, sp, ss)
    e_prev = math.expm1(a_prev)
    for j in range(num + 1):
        # this element's node s_j in the previous element's coordinate xi
        y = math.log1p(ss[j] * e_prev) / a_prev if a_prev != 0.0 else ss[j]
        sp[j] = _clenshaw(coef, num_prev, min(1.0, max(-1.0, 2.0 * y - 1.0)))
    for j in range(num + 1):
        u[j] = sp[j]
    u[num + 1] = tail0
    if extra == 2:
        u[num + 2] = tail1


@kernel
def solve_loaded_chain(
    code,
    desc,
    a,
    start,
    h_start,
    nums,
    nodes,
    d1s,
    d2s,
    ims,
    cms,
    rtol,
    prof,
    out,
    coefs,
    chain,
):
    """:func:`solve_loaded_array` along a curve: where ``chain[e]`` (size 0: nowhere) the
    element e is started from the converged element e - 1 (the same problem at a nearby
    forcing or tip displacement) instead of ``start``: by the tangent predictor
    u + (Lambda_e - Lambda_e-1) du/dLambda (the tangent ``_drag_slope`` solves for; for the
    inverse u + (d_e - d_e-1) du/dd from the same tangent, d = x1 - sin(theta0)),
    interpolated to this element's map; and the first Newton steps are chord steps on the LU
    factors of the previous element's Jacobian (:func:`_newton` with ``warm``). Where that
    Newton fails, the load continuation from rest, as for a cold start. The same states to
    rounding (the same discrete problem, the same tolerance and ladder), at a fraction of the
    work.
    """
    levels = nums.size
    nmax = nums[levels - 1]
    for lev in range(levels):
        nmax = max(nmax, nums[lev])
    extra = 2 if code == DRIVE_DRAG_INVERSE else 1  # unknowns after theta: h1 (and Lambda)
    m = nmax + 1 + extra
    work = np.empty((12, m))
    pm = np.empty((2, nmax + 1, nmax + 1))
    xs = np.empty(nmax + 1)
    jac = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    # the slope's factors: apart from Newton's for the inverse (a system one larger), whose
    # own factors the next element's chord steps use
    jac_s = np.empty((m, m)) if extra == 2 else jac
    piv_s = np.empty(m, dtype=np.int64) if extra == 2 else piv
    u = np.empty(m)
    tan = np.zeros(m)
    sp = np.empty(nmax + 1)
    ss = np.empty(nmax + 1)
    coef = np.empty(nmax + 1)
    vals = np.empty(nmax + 1)
    keep = np.empty((3, m))
    dl = np.empty(desc.shape[1])
    dd = np.empty((nmax + 1, nmax + 1))
    ii = np.empty((nmax + 1, nmax + 1))
    drag = code == DRIVE_DRAG or code == DRIVE_DRAG_INVERSE
    # the curve's variable of a chain: the forcing, or the inverse's tip displacement
    var = D_DX1 if code == DRIVE_DRAG_INVERSE else D_LAMBDA if drag else D_OMEGA2
    prev_ok = False  # the previous element's state is in u
    prev_num = 0
    prev_lev = 0
    prev_a = 0.0
    fact_num = -1  # jac, piv hold factors of this level's N (-1: none)
    for e in range(desc.shape[0]):
        d = desc[e]
        pe = e if prof.shape[0] > 1 else 0
        pr = prof[pe]
        num = nums[0]
        warm = chain.size > 0 and chain[e] and prev_ok
        if warm:
            step = d[var] - desc[e - 1, var]
            _warm_start(
                u,
                tan,
                step,
                prev_num,
                cms[prev_lev],
                prev_a,
                extra,
                num,
                nodes[0],
                a[e],
                sp,
                ss,
                coef,
            )
        else:
            for j in range(num + 1):
                u[j] = start[e, j]
            for c in range(extra):
                u[num + 1 + c] = h_start[e, c]
        chord = warm and fact_num == num
        prev_ok = False
        fact_num = -1
        nit = 0
        status = 0
        rmax = math.nan
        tail = math.nan
        rounding = 0.0
        lev_done = 0
        for lev in range(levels):
            num = nums[lev]
            if lev > 0:  # the previous level's interpolant at this level's nodes
                prev = nums[lev - 1]
                h = u[prev + 1]
                lam_prev = u[prev + 2] if extra == 2 else 0.0
                _coefficients(u, prev, cms[lev - 1], coef)
                for j in range(num + 1):
                    vals[j] = _clenshaw(coef, prev, nodes[lev, j])
                for j in range(num + 1):
                    u[j] = vals[j]
                u[num + 1] = h
                if extra == 2:
                    u[num + 2] = lam_prev
            _map(a[e], num, nodes[lev], sp, ss)
            _operators(num, d1s[lev], d2s[lev], ims[lev], sp, a[e], dd, ii)
            for j in range(num + 1 + extra):
                keep[0, j] = u[j]
            status, nit, rmax = _newton(
                u, num, dd, ii, code, d, pr, work, pm, jac, piv, nit, MAXITER, chord and lev == 0
            )
            if status != 0 and lev == 0:
                # continuation in the load factor from the hair at rest
                status, nit, rmax = _continuation(
                    u, keep, num, dd, ii, code, d, dl, pr, work, pm, jac, piv, nit
                )
            lev_done = lev
            if status != 0:
                break
            _coefficients(u, num, cms[lev], coef)
            tail = abs(coef[num]) + abs(coef[num - 1]) + abs(coef[num - 2])
            big = 1.0
            for j in range(num + 1):
                big = max(big, abs(u[j]))
            rounding = ROUNDING * num * num * big
            if tail <= rtol:
                break
        num = nums[lev_done]
        if status == 0 and tail > rtol:
            status = STATUS_INACCURATE
        out[0, e] = status
        out[1, e] = nit
        out[2, e] = num
        out[3, e] = a[e]
        for c in range(3):
            for k in range(nmax + 1):
                coefs[c, e, k] = math.nan if status < 0 else 0.0
        if status < 0:
            for c in range(4, NCOLS):
                out[c, e] = math.nan
            continue
        h = u[num + 1]
        cm = cms[lev_done]
        forcing = u[num + 2] if extra == 2 else d[D_LAMBDA] if drag else bed_arguments(code, d)[0]
        out[12, e] = forcing
        # cos and sin at the nodes once (work rows 0, 1 are free here)
        cs, sn = work[0], work[1]
        for j in range(num + 1):
            cs[j] = math.cos(u[j])
            sn[j] = math.sin(u[j])
        x1 = 0.0
        for j in range(num + 1):
            x1 += ii[num, j] * sn[j]
        if drag:
            gamma, tip = d[D_GAMMA], d[D_TIP]
            # the drag and its moment about the base, theta'(0) = int_0^1 (z f_x - x f_z) ds
            fx, fz = work[6], work[7]
            w, p = _drag_forces(
                u, num, ii, forcing, gamma, tip, pr, work[0], work[1], work[2], fx, fz
            )
            for i in range(num + 1):
                acc = 0.0
                for j in range(num + 1):
                    acc += ii[i, j] * work[1, j]
                xs[i] = acc
            quad = tip * h
            for j in range(num + 1):
                quad += ii[num, j] * (work[2, j] * fx[j] - xs[j] * fz[j])
            slope = _drag_slope(u, num, dd, ii, forcing, gamma, tip, pr, work, pm, jac_s, piv_s)
            out[13, e] = slope
            # what the next element of a curve starts from: this state (u is untouched),
            # the forward problem's tangent du/dLambda (work row 4 after _drag_slope) and
            # the factors in jac, piv (the slope's exact ones for the forward problem,
            # Newton's last for the inverse)
            prev_ok = True
            prev_num = num
            prev_lev = lev_done
            prev_a = a[e]
            fact_num = num if extra == 2 or math.isfinite(slope) else -1
            # the tangent along the curve's variable: du/dLambda, or for the inverse
            # du/dx1 = (du/dLambda)/(dx1/dLambda) with dLambda/dx1 = 1/(dx1/dLambda)
            good = math.isfinite(slope) and (extra == 1 or slope != 0.0)
            scale = 1.0 if extra == 1 or not good else 1.0 / slope
            for j in range(num + 2):
                tan[j] = work[4, j] * scale if good else 0.0
            if extra == 2:
                tan[num + 2] = scale if good else 0.0
        else:
            out[13, e] = math.nan
            omega2, eps, load = bed_arguments(code, d)
            w, p, _, _ = drive_loads(code, omega2, eps, load, h)
            # theta'(0) = int_0^1 [W + Pi (h1 - z)] cos(theta) ds (the ODE integrated once,
            # by the quadrature of the integration matrix's last row)
            quad = 0.0
            for j in range(num + 1):
                zj = 0.0
                for k in range(num + 1):
                    zj += ii[j, k] * cs[k]
                quad += ii[num, j] * (w + p * (h - zj)) * cs[j]
        out[4, e] = h
        out[5, e] = x1
        out[6, e] = u[num]
        out[7, e] = quad
        out[8, e] = w
        out[9, e] = p
        out[10, e] = tail + rounding
        out[11, e] = rmax
        out[14, e] = _displacement(u, num, ii, d[D_THETA0])
        _coefficients(u, num, cm, coef)
        for k in range(num + 1):
            coefs[0, e, k] = coef[k]
        for c in range(2):
            g = sn if c == 0 else cs
            for i in range(num + 1):
                acc = 0.0
                for j in range(num + 1):
                    acc += ii[i, j] * g[j]
                vals[i] = acc
            _coefficients(vals, num, cm, coef)
            for k in range(num + 1):
                coefs[1 + c, e, k] = coef[k]
