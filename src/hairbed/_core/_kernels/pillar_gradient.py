"""Derivatives of pillar states by implicit differentiation of the collocation (issue 21).

A converged pillar state u = (theta at the N + 1 mapped nodes, h1) of :mod:`.spectral` (drive
``DRIVE_DRAG``) is a root of the discrete system R(u; p) = 0 for the inputs
p = (Lambda, theta0, gamma, height ratio, tip load). Differentiating it at fixed map parameter
and degree,

    J du/dp = -dR/dp,

with J the exact Jacobian of the collocation (:func:`.spectral._jacobian_drag`), factored once
per state (:func:`.spectral._lu_factor`) and applied to the five right-hand sides. dR/dp is
nonzero in row 0 (theta_0 - theta0) for theta0 and in the interior ODE rows for the others,
whose internal force F(s_i) = P e_x + int_{s_i}^1 f depends on p at fixed u through the drag
f = Lambda U(z) [cos^2 + gamma sin^2, -(1 - gamma) sin cos] (linear in Lambda, in gamma and
in the profile U, whose derivative in the height ratio L/H is the profile ``dprof``) and the
tip load P. The outputs follow by the chain rule: h1 and theta(1) are unknowns,
x1 = I_s sin(theta) at the tip, the drag F(0) = P e_x + int_0^1 f and the base curvature
theta'(0) = P h1 + int_0^1 (z f_x - x f_z) through theta, z = I_s cos(theta) and
x = I_s sin(theta) at the nodes. The result is the exact derivative of the discrete state,
which agrees with the derivative of the ODE's state to the collocation's accuracy.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .spectral import (
    _jacobian_drag,
    _lu_apply,
    _lu_factor,
    _map,
    _operators,
    _residual_drag,
    profile_value,
)

__all__ = ["NIN", "NOUT", "STATUS_FOLD", "gradient_array"]

#: Inputs differentiated with respect to, in this order: Lambda, theta0, gamma, the height
#: ratio L/H (through ``dprof``, dU/d(L/H)), the tip load.
NIN = 5
#: Outputs, in this order: h1, x1, theta(1), theta'(0), F_x(0), F_z(0).
NOUT = 6
#: A singular Jacobian (a fold of the branch): the derivatives are infinite (NaN here).
STATUS_FOLD = 1


@kernel
def gradient_array(
    lam, theta0, gamma, tip, a, theta, h1, num, nodes, d1, d2, im, prof, dprof, out, status, rmax
):
    """d(outputs)/d(inputs) of every pillar state of one degree ``num`` into out
    (NOUT, NIN, size).

    ``theta`` (size, num + 1) holds theta at the state's mapped nodes (map parameter ``a``)
    and ``h1`` its tip height; ``nodes``, ``d1``, ``d2``, ``im`` are the level's nodes in xi,
    differentiation matrices and integration matrix (as for ``solve_loaded_array``); ``prof``
    and ``dprof`` (1 or size, K) the Chebyshev coefficients of U(z) and of dU/d(L/H). status
    gets 0, or ``STATUS_FOLD`` where the Jacobian is singular (the outputs are then NaN);
    rmax the largest residual of the collocation system at the state (what says that the
    state is a root of this system: of these inputs and this profile).
    """
    n1 = num + 1
    m = n1 + 1
    jac = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    u = np.empty(m)
    res = np.empty(m)
    rhs = np.empty((NIN, m))
    gx = np.empty((NIN, n1))
    gz = np.empty((NIN, n1))
    dtip = np.zeros(NIN)
    dtip[4] = 1.0
    cs = np.empty(n1)
    sn = np.empty(n1)
    z = np.empty(n1)
    xs = np.empty(n1)
    fx = np.empty(n1)
    fz = np.empty(n1)
    dz = np.empty(n1)
    dxs = np.empty(n1)
    gw = np.empty((4, n1))
    pm = np.empty((2, n1, n1))
    sp = np.empty(n1)
    ss = np.empty(n1)
    dd = np.empty((n1, n1))
    ii = np.empty((n1, n1))
    for e in range(lam.size):
        pr = prof[e if prof.shape[0] > 1 else 0]
        dpr = dprof[e if dprof.shape[0] > 1 else 0]
        lm, g, pt = lam[e], gamma[e], tip[e]
        for j in range(n1):
            u[j] = theta[e, j]
        u[n1] = h1[e]
        _map(a[e], num, nodes, sp, ss)
        _operators(num, d1, d2, im, sp, a[e], dd, ii)
        _residual_drag(u, num, dd, ii, theta0[e], lm, g, pt, pr, cs, sn, z, res, fx, fz)
        big = 0.0
        for i in range(m):
            big = max(big, abs(res[i]))
        rmax[e] = big
        _jacobian_drag(u, num, dd, ii, lm, g, pt, pr, cs, sn, z, fx, fz, gw, pm, jac)
        bx, bz, ax, az = gw[0], gw[1], gw[2], gw[3]  # df/dtheta and df/dz at the nodes
        for i in range(n1):
            acc = 0.0
            for j in range(n1):
                acc += ii[i, j] * sn[j]
            xs[i] = acc
        # the explicit partials of the drag per unit length at fixed u
        one_g = 1.0 - g
        for j in range(n1):
            uu, _ = profile_value(pr, z[j])
            du, _ = profile_value(dpr, z[j])
            c, s = cs[j], sn[j]
            nx = c * c + g * s * s
            nz = -one_g * s * c
            gx[0, j] = uu * nx
            gz[0, j] = uu * nz
            gx[1, j] = 0.0
            gz[1, j] = 0.0
            gx[2, j] = lm * uu * s * s
            gz[2, j] = lm * uu * s * c
            gx[3, j] = lm * du * nx
            gz[3, j] = lm * du * nz
            gx[4, j] = 0.0
            gz[4, j] = 0.0
        for k in range(NIN):
            tx = dtip[k]
            tz = 0.0
            for j in range(n1):
                tx += ii[num, j] * gx[k, j]
                tz += ii[num, j] * gz[k, j]
            for i in range(m):
                rhs[k, i] = 0.0
            for i in range(1, num):
                ax_i = 0.0
                az_i = 0.0
                for j in range(n1):
                    ax_i += ii[i, j] * gx[k, j]
                    az_i += ii[i, j] * gz[k, j]
                rhs[k, i] = -((tx - ax_i) * cs[i] - (tz - az_i) * sn[i])
        rhs[1, 0] = 1.0  # -dR_0/dtheta0
        status[e] = 0
        if not _lu_factor(jac, piv, m):
            status[e] = STATUS_FOLD
            for o in range(NOUT):
                for k in range(NIN):
                    out[o, k, e] = math.nan
            continue
        h = u[n1]
        finite = True
        for k in range(NIN):
            col = rhs[k]
            _lu_apply(jac, piv, col, m)
            dh = col[n1]
            for i in range(n1):
                az_i = 0.0
                ax_i = 0.0
                for j in range(n1):
                    az_i -= ii[i, j] * sn[j] * col[j]
                    ax_i += ii[i, j] * cs[j] * col[j]
                dz[i] = az_i
                dxs[i] = ax_i
            dfx_t = dtip[k]
            dfz_t = 0.0
            dq = dtip[k] * h + pt * dh
            for j in range(n1):
                dfx = gx[k, j] + bx[j] * col[j] + ax[j] * dz[j]
                dfz = gz[k, j] + bz[j] * col[j] + az[j] * dz[j]
                w = ii[num, j]
                dfx_t += w * dfx
                dfz_t += w * dfz
                dq += w * (dz[j] * fx[j] + z[j] * dfx - dxs[j] * fz[j] - xs[j] * dfz)
            out[0, k, e] = dh
            out[1, k, e] = dxs[num]
            out[2, k, e] = col[num]
            out[3, k, e] = dq
            out[4, k, e] = dfx_t
            out[5, k, e] = dfz_t
            for o in range(NOUT):
                if not math.isfinite(out[o, k, e]):
                    finite = False
        if not finite:  # an overflow of a nearly singular Jacobian: at the fold
            status[e] = STATUS_FOLD
            for o in range(NOUT):
                for k in range(NIN):
                    out[o, k, e] = math.nan
