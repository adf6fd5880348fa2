"""The loads of a rod in motion and the drives in time, for the dynamics' kernels (theory.md
§14, §15): the value of a drive at a time (:func:`drive_value`) and the load of a velocity or
an acceleration projected on the normals, with its exact derivatives (:func:`projected_load`).
The pillar's (``dynamics``) and the porous bed's (``bed``) semi-discretisations both use them.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel

__all__ = [
    "SIGNAL_CONSTANT",
    "SIGNAL_PULSES",
    "SIGNAL_RAMP",
    "SIGNAL_SAMPLED",
    "SIGNAL_SINE",
    "SIGNAL_STEP",
    "drive_value",
    "projected_load",
]

#: Drive kinds of :func:`drive_value` (a value of Lambda(t) or P(t)).
SIGNAL_CONSTANT = 0
SIGNAL_STEP = 1
SIGNAL_RAMP = 2
SIGNAL_SINE = 3
SIGNAL_PULSES = 4
SIGNAL_SAMPLED = 5


@kernel
def drive_value(kind, par, tab_t, tab_v, t):
    """The drive at time t. ``par``: CONSTANT (v); STEP (before, after, t_step); RAMP (v0, v1,
    t0, t1: linear between); SINE (mean, amplitude, omega, phase: mean + amplitude
    sin(omega t + phase)); PULSES (base, height, period, width, t0: height added during the
    first ``width`` of each period from t0); SAMPLED: the piecewise cubic Hermite interpolant
    of (tab_t, tab_v) with Catmull-Rom slopes (held at the ends)."""
    if kind == SIGNAL_CONSTANT:
        return par[0]
    if kind == SIGNAL_STEP:
        return par[1] if t >= par[2] else par[0]
    if kind == SIGNAL_RAMP:
        if t <= par[2]:
            return par[0]
        if t >= par[3]:
            return par[1]
        return par[0] + (par[1] - par[0]) * (t - par[2]) / (par[3] - par[2])
    if kind == SIGNAL_SINE:
        return par[0] + par[1] * math.sin(par[2] * t + par[3])
    if kind == SIGNAL_PULSES:
        if t < par[4]:
            return par[0]
        phase = (t - par[4]) % par[2]
        return par[0] + (par[1] if phase < par[3] else 0.0)
    m = tab_t.size
    if t <= tab_t[0]:
        return tab_v[0]
    if t >= tab_t[m - 1]:
        return tab_v[m - 1]
    lo = 0
    hi = m - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if tab_t[mid] <= t:
            lo = mid
        else:
            hi = mid
    dt = tab_t[hi] - tab_t[lo]
    x = (t - tab_t[lo]) / dt
    d0 = (
        (tab_v[hi] - tab_v[lo - 1]) / (tab_t[hi] - tab_t[lo - 1])
        if lo > 0
        else (tab_v[hi] - tab_v[lo]) / dt
    )
    d1 = (
        (tab_v[hi + 1] - tab_v[lo]) / (tab_t[hi + 1] - tab_t[lo])
        if hi < m - 1
        else (tab_v[hi] - tab_v[lo]) / dt
    )
    h00 = (1.0 + 2.0 * x) * (1.0 - x) ** 2
    h10 = x * (1.0 - x) ** 2
    h01 = x * x * (3.0 - 2.0 * x)
    h11 = x * x * (x - 1.0)
    return h00 * tab_v[lo] + h10 * dt * d0 + h01 * tab_v[hi] + h11 * dt * d1


@kernel
def projected_load(th, a, b, ratio, num, ii, need, val, opa, opb, dth, work):
    """val_i = n_i . int_{s_i}^1 R r ds' at every node, r = I (a n + b t) (the integration
    from the base), R = I - (1 - ratio) t t, n = (cos, -sin), t = (sin, cos) at each node.
    With a = theta_t, b = 0 and ratio gamma it is the drag of the pillar's velocity; with
    a = theta_tt, b = -theta_t^2 and ratio chi its inertia. Where ``need``: opa = d val/d a,
    opb = d val/d b, dth = d val/d theta ((N + 1)^2 each; need 1: opa only, 2: all).
    work: (12, N + 1) rows, its rows 0-9 used."""
    n1 = num + 1
    c, s = work[0], work[1]
    rx, rz, gx, gz = work[2], work[3], work[4], work[5]
    cgx, cgz = work[6], work[7]  # the integrals (I g)
    p, q = work[8], work[9]
    one = 1.0 - ratio
    for j in range(n1):
        c[j] = math.cos(th[j])
        s[j] = math.sin(th[j])
    for j in range(n1):
        ax = 0.0
        az = 0.0
        for k in range(n1):
            w = ii[j, k]
            ax += w * (a[k] * c[k] + b[k] * s[k])
            az += w * (-a[k] * s[k] + b[k] * c[k])
        rx[j] = ax
        rz[j] = az
        p[j] = s[j] * ax + c[j] * az  # t . r
        q[j] = c[j] * ax - s[j] * az  # n . r
        gx[j] = ax - one * s[j] * p[j]
        gz[j] = az - one * c[j] * p[j]
    for i in range(n1):
        ax = 0.0
        az = 0.0
        for j in range(n1):
            ax += ii[i, j] * gx[j]
            az += ii[i, j] * gz[j]
        cgx[i] = ax
        cgz[i] = az
    for i in range(n1):
        fx = cgx[num] - cgx[i]
        fz = cgz[num] - cgz[i]
        val[i] = c[i] * fx - s[i] * fz
    if need == 0:
        return
    if need == 1:
        # opa alone, by two products in one call: opa = diag(c) Q P1 - diag(s) Q P2 with
        # P1 = diag(Rxx) I diag(c) - diag(Rxz) I diag(s), P2 = diag(Rxz) I diag(c) -
        # diag(Rzz) I diag(s) (the rows below, expanded), and (Q P)_ik = (I P)_Nk - (I P)_ik
        pp = np.empty((n1, 2 * n1))
        for j in range(n1):
            rxx = 1.0 - one * s[j] * s[j]
            rxz = -one * s[j] * c[j]
            rzz = 1.0 - one * c[j] * c[j]
            for k in range(n1):
                w = ii[j, k]
                pp[j, k] = w * (rxx * c[k] - rxz * s[k])
                pp[j, n1 + k] = w * (rxz * c[k] - rzz * s[k])
        ip = np.dot(np.ascontiguousarray(ii[:n1, :n1]), pp)
        for i in range(n1):
            for k in range(n1):
                opa[i, k] = c[i] * (ip[num, k] - ip[i, k]) - s[i] * (
                    ip[num, n1 + k] - ip[i, n1 + k]
                )
        return
    # W1_ij = Q_ij (c_i Rxx_j - s_i Rxz_j), W2_ij = Q_ij (c_i Rxz_j - s_i Rzz_j), Q_ij =
    # I_Nj - I_ij: val = sum_j W1_ij rx_j + W2_ij rz_j. (W1 I)_ik = c_i A1_ik - s_i A2_ik and
    # (W2 I)_ik = c_i A2_ik - s_i A3_ik with A1 = Q diag(Rxx) I, A2 = Q diag(Rxz) I, A3 =
    # Q diag(Rzz) I: three matrix products (BLAS), not a triple loop per entry
    q1 = np.empty((n1, n1))
    q2 = np.empty((n1, n1))
    q3 = np.empty((n1, n1))
    for i in range(n1):
        for j in range(n1):
            qij = ii[num, j] - ii[i, j]
            q1[i, j] = qij * (1.0 - one * s[j] * s[j])
            q2[i, j] = -qij * one * s[j] * c[j]
            q3[i, j] = qij * (1.0 - one * c[j] * c[j])
    im = np.ascontiguousarray(ii[:n1, :n1])
    a1 = np.dot(q1, im)
    a2 = np.dot(q2, im)
    a3 = np.dot(q3, im)
    for i in range(n1):
        ci, si = c[i], s[i]
        for k in range(n1):
            w1 = ci * a1[i, k] - si * a2[i, k]
            w2 = ci * a2[i, k] - si * a3[i, k]
            opa[i, k] = w1 * c[k] - w2 * s[k]
            if need == 2:
                opb[i, k] = w1 * s[k] + w2 * c[k]
                dth[i, k] = w1 * (b[k] * c[k] - a[k] * s[k]) - w2 * (b[k] * s[k] + a[k] * c[k])
    if need == 2:
        for i in range(n1):
            ci, si = c[i], s[i]
            for j in range(n1):
                # R_j's own angle: dg_j = -(1 - ratio) (n_j (t . r) + t_j (n . r))
                qij = ii[num, j] - ii[i, j]
                dgx = -one * (c[j] * p[j] + s[j] * q[j])
                dgz = -one * (-s[j] * p[j] + c[j] * q[j])
                dth[i, j] += qij * (ci * dgx - si * dgz)
        for i in range(n1):  # the outer normal n_i
            dth[i, i] -= s[i] * (cgx[num] - cgx[i]) + c[i] * (cgz[num] - cgz[i])
