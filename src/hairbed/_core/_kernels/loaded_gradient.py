"""Derivatives of loaded states by implicit differentiation of the collocation (issue 20).

A converged state u = (theta at the N + 1 mapped nodes, h1) of :mod:`.spectral` is a root of
the discrete system R(u; p) = 0 for the inputs p = (omega2, eps, load, theta0) (load = pi or
q). Differentiating it at fixed map parameter and degree,

    J du/dp = -dR/dp,

with J the exact Jacobian of the collocation (:func:`.spectral._jacobian`), factored once per
state (:func:`.spectral._lu_factor`) and applied to the four right-hand sides. dR/dp is
nonzero in two places only: row 0 (theta_0 - theta0) in theta0, and the interior ODE rows,
whose load term [W + Pi (h1 - z_i)] cos(theta_i) depends on omega2, eps and the load through
the drive's W(h1) and Pi(h1) at fixed h1 (:func:`load_partials`). The outputs follow by the
chain rule: h1 and theta(1) are unknowns, x1 = I_s sin(theta) at the tip, the loads
W(h1), Pi(h1) and the base curvature W h1 + Pi h1^2/2 (theory.md §11) through h1. The result
is the exact derivative of the discrete state, which agrees with the derivative of the ODE's
state to the collocation's accuracy (the tail of theta, ``LoadedState.error_estimate``).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .spectral import (
    DRIVE_FIXED,
    DRIVE_PRESSURE,
    _jacobian,
    _lu_apply,
    _lu_factor,
    _map,
    _operators,
    _residual,
)

__all__ = ["NIN", "NOUT", "STATUS_FOLD", "gradient_array", "load_partials"]

#: Inputs differentiated with respect to, in this order: omega2, eps, load (pi or q), theta0.
NIN = 4
#: Outputs, in this order: h1, x1, theta(1), theta'(0), W, Pi.
NOUT = 6
#: A singular Jacobian (a fold of the drive in h1): the derivatives are infinite.
STATUS_FOLD = 1


@kernel
def load_partials(code, omega2, eps, load, h):
    """Partial derivatives of the drive's (W, Pi) at fixed h1 = h in omega2, eps and the
    load: (dW/domega2, dW/deps, dW/dload, dPi/domega2, dPi/deps, dPi/dload)."""
    if code == DRIVE_FIXED:
        return 1.0, 0.0, 0.0, 0.0, 0.0, 1.0
    u = 1.0 - eps * h
    if code == DRIVE_PRESSURE:
        # W = omega2/u + (load/2)(1/eps - h), Pi = load
        w_e = omega2 * h / (u * u)
        w_l = math.inf
        if eps > 0.0:
            w_l = 0.5 * (1.0 / eps - h)
            if load != 0.0:
                w_e -= 0.5 * load / (eps * eps)
        return 1.0 / u, w_e, w_l, 0.0, 0.0, 1.0
    # flow: W = q/u^2 - 2 omega2/u, Pi = 2 eps q/u^3 - 6 eps omega2/u^2, du/deps = -h
    u2 = u * u
    u3 = u2 * u
    w_w = -2.0 / u
    w_e = 2.0 * load * h / u3 - 2.0 * omega2 * h / u2
    w_l = 1.0 / u2
    p_w = -6.0 * eps / u2
    p_e = (
        2.0 * load / u3
        + 6.0 * eps * load * h / (u3 * u)
        - 6.0 * omega2 / u2
        - 12.0 * eps * omega2 * h / u3
    )
    p_l = 2.0 * eps / u3
    return w_w, w_e, w_l, p_w, p_e, p_l


@kernel
def gradient_array(
    code, omega2, eps, load, theta0, a, theta, h1, num, nodes, d1, d2, im, out, status
):
    """d(outputs)/d(inputs) of every state of one degree ``num`` into out (NOUT, NIN, size).

    ``theta`` (size, num + 1) holds theta at the state's mapped nodes (map parameter ``a``)
    and ``h1`` its tip height; ``nodes``, ``d1``, ``d2``, ``im`` are the level's nodes in xi,
    differentiation matrices and integration matrix (as for ``solve_loaded_array``). status
    gets 0, or ``STATUS_FOLD`` where the Jacobian is singular (the row is then +-inf).
    """
    n1 = num + 1
    m = n1 + 1
    jac = np.empty((m, m))
    piv = np.empty(m, dtype=np.int64)
    u = np.empty(m)
    res = np.empty(m)
    rhs = np.empty((NIN, m))
    cs = np.empty(n1)
    sn = np.empty(n1)
    z = np.empty(n1)
    sp = np.empty(n1)
    ss = np.empty(n1)
    dd = np.empty((n1, n1))
    ii = np.empty((n1, n1))
    for e in range(omega2.size):
        for j in range(n1):
            u[j] = theta[e, j]
        u[n1] = h1[e]
        _map(a[e], num, nodes, sp, ss)
        _operators(num, d1, d2, im, sp, a[e], dd, ii)
        _, w, p, dw, dp = _residual(
            u, num, dd, ii, theta0[e], code, omega2[e], eps[e], load[e], cs, sn, z, res
        )
        _jacobian(u, num, dd, ii, cs, sn, z, w, p, dw, dp, jac)
        h = u[n1]
        w_w, w_e, w_l, p_w, p_e, p_l = load_partials(code, omega2[e], eps[e], load[e], h)
        # at eps = 0 the pressure drive's dW/dpi = 1/(2 eps) is infinite: the load's column
        # is then d/dW (times inf below), with dPi/dpi = 1 kept
        blow = not math.isfinite(w_l)
        if blow:
            w_l, p_l = 1.0, 0.0
        for k in range(NIN):
            for i in range(m):
                rhs[k, i] = 0.0
        rhs[3, 0] = 1.0  # -dR_0/dtheta0
        for i in range(1, num):
            dz = h - z[i]
            rhs[0, i] = -(w_w + p_w * dz) * cs[i]
            rhs[1, i] = -(w_e + p_e * dz) * cs[i]
            rhs[2, i] = -(w_l + p_l * dz) * cs[i]
        status[e] = 0
        if not _lu_factor(jac, piv, m):
            status[e] = STATUS_FOLD
            for o in range(NOUT):
                for k in range(NIN):
                    out[o, k, e] = math.inf
            continue
        for k in range(NIN):
            col = rhs[k]
            _lu_apply(jac, piv, col, m)
            dh = col[n1]
            dx = 0.0
            for j in range(n1):
                dx += ii[num, j] * cs[j] * col[j]
            if k == 0:
                pw, pp = w_w, p_w
            elif k == 1:
                pw, pp = w_e, p_e
            elif k == 2:
                pw, pp = w_l, p_l
            else:
                pw, pp = 0.0, 0.0
            d_w = pw + dw * dh
            d_p = pp + dp * dh
            out[0, k, e] = dh
            out[1, k, e] = dx
            out[2, k, e] = col[num]
            out[3, k, e] = d_w * h + w * dh + 0.5 * d_p * h * h + p * h * dh
            out[4, k, e] = d_w
            out[5, k, e] = d_p
            if k == 2 and blow:
                for o in range(NOUT - 1):
                    out[o, k, e] *= math.inf
                out[5, k, e] = 1.0
