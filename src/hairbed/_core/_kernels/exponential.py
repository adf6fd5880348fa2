"""An exponential integrator for the ringing pillar (issue 30, theory.md §14).

The semi-discrete pillar y' = f(t, y) of ``dynamics.pillar_rates`` is split about a steady
state y* of the drives' final values, f(y*) = 0 (Newton on the rates themselves), with J the
exact Jacobian there:

    e = y - y*,   e' = J e + N(t, e),   N = f(t, y* + e) - J e,

so N vanishes like |e|^2 once the drives are constant. J is diagonalised once, J = V Lambda
V^-1 (small and dense: 2 (N - 1) unknowns), and the run is in the modal coordinates w = V^-1 e:
each mode's linear part exp(h lambda_k) is exact, whatever its frequency, and only the
remainder V^-1 N is approximated. The scheme is the explicit exponential Runge-Kutta method of
order 4 (five stages) of M. Hochbruck and A. Ostermann, Explicit exponential Runge-Kutta
methods for semilinear parabolic problems, SIAM J. Numer. Anal. 43, 1069-1090 (2005), eq.
(5.19); its weights are those of the quadratic through the remainder at t, t + h/2 (the fifth
stage) and t + h (the fourth), integrated exactly against exp((h - s) Lambda). The error
estimate is the difference from the linear interpolant through t and t + h (an order-2
solution from the same stages), the step 0.9 err^(-1/3) within [0.2, 5]; the dense output is
the same quadratic integrated to any point of the step.

With the drag every mode of the ringing pillar decays at about 1/(2 mu): a step rings in all
of them for hundreds of T, and an integrator that approximates J e too must follow each
excited mode's oscillation to the end. Here the linear ringing costs nothing; the steps are
set by the remainder, small once the motion is.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .dynamics import _lowest_cos, pillar_rates, tip_speed, workspace
from .spectral import _lu_apply, _lu_factor

__all__ = ["integrate_exponential", "phi_functions", "steady_modes"]

#: Status codes (those of ``dynamics.integrate_pillar``).
_OK = 0
_OUTSIDE = -8
_MAXSTEPS = -2
_SMALL = -3
_JUMP = -9
#: The largest condition number ||V||_1 ||V^-1||_1 of the modal basis accepted (beyond it a
#: nearly defective J: status -3, a singular matrix).
_COND_MAX = 1e10


@kernel
def phi_functions(z, out):
    """out[j] = phi_j(z) for j = 0 .. 3 (complex z): phi_0 = e^z, phi_{j+1}(z) = (phi_j(z) -
    1/j!)/z (phi_j(0) = 1/j!). A Taylor series of 24 terms where |z| < 1 (the recurrence
    cancels there), the recurrence elsewhere."""
    if abs(z) < 1.0:
        for j in range(1, 4):
            term = complex(1.0 / math.gamma(j + 1.0))
            acc = complex(0.0)
            for k in range(24):
                acc += term
                term = term * z / (k + j + 1.0)
            out[j] = acc
        out[0] = np.exp(z)
        return
    e = np.exp(z)
    out[0] = e
    out[1] = (e - 1.0) / z
    out[2] = (out[1] - 1.0) / z
    out[3] = (out[2] - 0.5) / z


@kernel
def steady_modes(
    y_guess, t, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, ystar, counts
):
    """The steady state y* of the rates at time t (f(t, y*) = 0) by Newton from y_guess with
    the exact Jacobian, then J = df/dy there and its eigendecomposition J = V diag(lam) V^-1.
    Newton stops at a relative step below 1e-14, or below 1e-9 once it no longer halves (the
    round-off of the rates). Returns (ok, lam, V, V^-1); ok False where Newton does not
    converge in 30 iterations, a matrix is singular or the modal basis is nearly defective
    (condition number above 1e10)."""
    m = y_guess.size
    ws = workspace(num)
    f = np.empty(m)
    jac = np.zeros((m, m))
    piv = np.empty(m, dtype=np.int64)
    lam = np.zeros(m, dtype=np.complex128)
    vec = np.zeros((m, m), dtype=np.complex128)
    inv = np.zeros((m, m), dtype=np.complex128)
    for k in range(m):
        ystar[k] = y_guess[k]
    done = False
    prev = math.inf
    for _ in range(30):
        if not pillar_rates(
            t, ystar, True, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, f,
            jac, ws,
        ):  # fmt: skip
            return False, lam, vec, inv
        counts[3] += 1
        counts[4] += 1
        counts[5] += 1
        if not _lu_factor(jac, piv, m):
            return False, lam, vec, inv
        _lu_apply(jac, piv, f, m)
        big = 0.0
        for k in range(m):
            ystar[k] -= f[k]
            big = max(big, abs(f[k]) / (1.0 + abs(ystar[k])))
        if big < 1e-14 or (big < 1e-9 and big > 0.5 * prev):  # converged, or round-off
            done = True
            break
        prev = big
    # the Jacobian at y* itself
    if not done or not pillar_rates(
        t, ystar, True, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, f, jac,
        ws,
    ):  # fmt: skip
        return False, lam, vec, inv
    counts[3] += 1
    counts[4] += 1
    lam, vec = np.linalg.eig(jac.astype(np.complex128))
    inv = np.linalg.inv(vec)
    if not _norm1(vec) * _norm1(inv) <= _COND_MAX:
        return False, lam, vec, inv
    return True, lam, vec, inv


@kernel
def _norm1(a):
    """The 1-norm (largest column sum) of a complex matrix."""
    big = 0.0
    for k in range(a.shape[1]):
        acc = 0.0
        for i in range(a.shape[0]):
            acc += abs(a[i, k])
        big = max(big, acc)
    return big


@kernel
def _remainder(
    t, w, ystar, lam, vec, inv, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs,
    y, f, jdummy, ws, out,
):  # fmt: skip
    """out = V^-1 f(t, y* + Re(V w)) - lam w, the remainder in modal coordinates (y holds
    the state). False where the rates fail (a singular operator)."""
    m = w.size
    for i in range(m):
        acc = 0.0
        for k in range(m):
            acc += (vec[i, k] * w[k]).real
        y[i] = ystar[i] + acc
    if not pillar_rates(
        t, y, False, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs, f, jdummy,
        ws,
    ):  # fmt: skip
        return False
    for i in range(m):
        cacc = 0j
        for k in range(m):
            cacc += inv[i, k] * f[k]
        out[i] = cacc - lam[i] * w[i]
    return True


@kernel
def _to_state(w, ystar, vec, y):
    """y = y* + Re(V w)."""
    m = w.size
    for i in range(m):
        acc = 0.0
        for k in range(m):
            acc += (vec[i, k] * w[k]).real
        y[i] = ystar[i] + acc


@kernel
def _dense(w, n1, n5, n4, lam, h, tau, pw, out):
    """The step's dense output at t + tau (0 <= tau <= h) in modal coordinates: the
    remainder's quadratic through (0, n1), (h/2, n5), (h, n4), N(s) = n1 + a s/h + b (s/h)^2,
    integrated exactly, exp(tau lam) w + tau phi1 n1 + (tau^2/h) phi2 a + 2 (tau^3/h^2)
    phi3 b (the phi_j at tau lam). pw: a complex work array of 4."""
    r = tau / h
    for k in range(w.size):
        phi_functions(tau * lam[k], pw)
        a = -3.0 * n1[k] + 4.0 * n5[k] - n4[k]
        b = 2.0 * n1[k] - 4.0 * n5[k] + 2.0 * n4[k]
        out[k] = pw[0] * w[k] + tau * (pw[1] * n1[k] + r * pw[2] * a + 2.0 * r * r * pw[3] * b)


@kernel
def integrate_exponential(
    y0,
    ystar,
    lam,
    vec,
    inv,
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
    """The exponential Runge-Kutta method of order 4 (module docstring) on e' = J e + N(t, e)
    about y* (``steady_modes``: lam, V = vec, V^-1 = inv) from (t_start, y0), writing y at
    every t_eval (sorted, >= t_start) into y_out by the dense output.

    Error norm: the root mean square of err/(atol + rtol max(|y0|, |y1|)) over the state's
    components, err the difference of the order-4 and order-2 solutions. Events, located by
    bisection on the dense output, stop the run as in ``dynamics.integrate_pillar``: a node
    reaching |theta| = pi/2 (status -8); where ``jump_speed`` > 0, the tip's speed reaching
    it (-9). Returns (status, t_end): 0, -8, -9, -2 after max_steps steps, -3 for a step
    below 1e-14 (t + 1) or failed rates. counts: steps, accepted, rejected, f evaluations,
    Jacobians, LU factorisations (these two from ``steady_modes``)."""
    m = y0.size
    n_eval = t_eval.size
    ws = workspace(num)
    th_tmp = np.empty(num + 1)
    y = np.empty(m)
    yt = np.empty(m)
    y1 = np.empty(m)
    f = np.empty(m)
    jdummy = np.zeros((m, m))
    w = np.empty(m, dtype=np.complex128)
    wn = np.empty(m, dtype=np.complex128)
    ws2 = np.empty(m, dtype=np.complex128)
    wd = np.empty(m, dtype=np.complex128)
    n1 = np.empty(m, dtype=np.complex128)
    n2 = np.empty(m, dtype=np.complex128)
    n3 = np.empty(m, dtype=np.complex128)
    n4 = np.empty(m, dtype=np.complex128)
    n5 = np.empty(m, dtype=np.complex128)
    nn = np.empty(m, dtype=np.complex128)
    ph = np.empty((m, 4), dtype=np.complex128)  # phi_j(h lam)
    pq = np.empty((m, 4), dtype=np.complex128)  # phi_j(h lam/2)
    pw = np.empty(4, dtype=np.complex128)
    derr = np.empty(m, dtype=np.complex128)
    err = np.empty(m)
    for i in range(m):
        cacc = 0j
        for k in range(m):
            cacc += inv[i, k] * (y0[k] - ystar[k])
        w[i] = cacc
        y[i] = y0[i]
    t = t_start
    t_end = t_eval[n_eval - 1]
    h = min(h_start, t_end - t) if t_end > t else 0.0
    nxt = 0
    while nxt < n_eval and t_eval[nxt] <= t:
        for k in range(m):
            y_out[nxt, k] = y[k]
        nxt += 1
    if nxt >= n_eval:
        return _OK, t
    pr = (num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs)
    if not _remainder(t, w, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, n1):
        return _SMALL, t
    counts[3] += 1
    steps = 0
    rejected = False
    while nxt < n_eval:
        steps += 1
        counts[0] += 1
        if steps > max_steps:
            return _MAXSTEPS, t
        if h < 1e-14 * (abs(t) + 1.0):
            return _SMALL, t
        for k in range(m):
            phi_functions(h * lam[k], pw)
            for j in range(4):
                ph[k, j] = pw[j]
            phi_functions(0.5 * h * lam[k], pw)
            for j in range(4):
                pq[k, j] = pw[j]
        good = True
        # stages 2 and 3 at t + h/2, 4 at t + h, 5 at t + h/2 (Hochbruck & Ostermann)
        for k in range(m):
            ws2[k] = pq[k, 0] * w[k] + h * 0.5 * pq[k, 1] * n1[k]
        good = _remainder(t + 0.5 * h, ws2, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, n2)
        if good:
            for k in range(m):
                ws2[k] = pq[k, 0] * w[k] + h * (
                    (0.5 * pq[k, 1] - pq[k, 2]) * n1[k] + pq[k, 2] * n2[k]
                )
            good = _remainder(t + 0.5 * h, ws2, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, n3)
        if good:
            for k in range(m):
                ws2[k] = ph[k, 0] * w[k] + h * (
                    (ph[k, 1] - 2.0 * ph[k, 2]) * n1[k] + ph[k, 2] * (n2[k] + n3[k])
                )
            good = _remainder(t + h, ws2, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, n4)
        if good:
            for k in range(m):
                a52 = 0.5 * pq[k, 2] - ph[k, 3] + 0.25 * ph[k, 2] - 0.5 * pq[k, 3]
                a54 = 0.25 * pq[k, 2] - a52
                a51 = 0.5 * pq[k, 1] - 2.0 * a52 - a54
                ws2[k] = pq[k, 0] * w[k] + h * (a51 * n1[k] + a52 * (n2[k] + n3[k]) + a54 * n4[k])
            good = _remainder(t + 0.5 * h, ws2, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, n5)
        counts[3] += 4
        en = 1e10
        if good:
            for k in range(m):
                p1, p2, p3 = ph[k, 1], ph[k, 2], ph[k, 3]
                wn[k] = ph[k, 0] * w[k] + h * (
                    (p1 - 3.0 * p2 + 4.0 * p3) * n1[k]
                    + (-p2 + 4.0 * p3) * n4[k]
                    + (4.0 * p2 - 8.0 * p3) * n5[k]
                )
                # minus the order-2 solution e^{hL} w + h ((phi1 - phi2) n1 + phi2 n4)
                derr[k] = h * (
                    (-2.0 * p2 + 4.0 * p3) * n1[k]
                    + (-2.0 * p2 + 4.0 * p3) * n4[k]
                    + (4.0 * p2 - 8.0 * p3) * n5[k]
                )
            _to_state(wn, ystar, vec, y1)
            for i in range(m):
                acc = 0.0
                for k in range(m):
                    acc += (vec[i, k] * derr[k]).real
                err[i] = acc
            en = 0.0
            for i in range(m):
                sc = atol + rtol * max(abs(y[i]), abs(y1[i]))
                en += (err[i] / sc) ** 2
            en = math.sqrt(en / m)
            if not math.isfinite(en):
                en = 1e10
        fac = min(5.0, max(0.2, 0.9 * max(en, 1e-12) ** (-1.0 / 3.0)))
        if en > 1.0:
            rejected = True
            counts[2] += 1
            h *= min(fac, 0.5) if not good else fac
            continue
        # accepted: the remainder at the new point (the next step's first stage)
        counts[1] += 1
        if not _remainder(t + h, wn, ystar, lam, vec, inv, *pr, yt, f, jdummy, ws, nn):
            return _SMALL, t + h
        counts[3] += 1
        t_new = t + h
        t_stop = t_new
        status = _OK
        if _lowest_cos(y1, num, theta0, srow, th_tmp) <= 0.0:
            lo = 0.0
            hi = 1.0
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                _dense(w, n1, n5, n4, lam, h, mid * h, pw, wd)
                _to_state(wd, ystar, vec, yt)
                if _lowest_cos(yt, num, theta0, srow, th_tmp) <= 0.0:
                    hi = mid
                else:
                    lo = mid
            t_stop = t + hi * h
            status = _OUTSIDE
        if jump_speed > 0.0:
            tau = (t_stop - t) / h
            _dense(w, n1, n5, n4, lam, h, tau * h, pw, wd)
            _to_state(wd, ystar, vec, yt)
            v = tip_speed(t_stop, yt, *pr, f, jdummy, ws, th_tmp)
            counts[3] += 1
            if not v < jump_speed:
                lo = 0.0
                hi = tau
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    _dense(w, n1, n5, n4, lam, h, mid * h, pw, wd)
                    _to_state(wd, ystar, vec, yt)
                    v = tip_speed(t + mid * h, yt, *pr, f, jdummy, ws, th_tmp)
                    counts[3] += 1
                    if not v < jump_speed:
                        hi = mid
                    else:
                        lo = mid
                t_stop = t + hi * h
                status = _JUMP
        while nxt < n_eval and t_eval[nxt] <= t_stop:
            _dense(w, n1, n5, n4, lam, h, t_eval[nxt] - t, pw, wd)
            _to_state(wd, ystar, vec, yt)
            for k in range(m):
                y_out[nxt, k] = yt[k]
            nxt += 1
        if status != _OK:
            return status, t_stop
        for k in range(m):
            w[k] = wn[k]
            n1[k] = nn[k]
            y[k] = y1[k]
        t = t_new
        if rejected:
            fac = min(fac, 1.0)
        rejected = False
        h = h * fac
        if t_end - t > 0.0:
            h = min(h, t_end - t)
        if t_end - t <= 1e-14 * (abs(t) + 1.0):
            while nxt < n_eval:
                for k in range(m):
                    y_out[nxt, k] = y[k]
                nxt += 1
    return _OK, t
