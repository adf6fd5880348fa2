"""A pillar run's work around the integrator in one compiled call each (issue 30, theory.md
§14): Radau IIA's starting step, and the trajectory's outputs from the integrator's states.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .dynamics import integrate_pillar, pillar_rates, workspace

__all__ = [
    "START_FLOOR",
    "START_GROWTH",
    "START_PROBES",
    "run_radau",
    "start_step",
    "trajectory_outputs",
]

#: The first probe where the start says nothing of the solution's time scale (y0 or f0
#: near 0): Hairer, Norsett & Wanner's 1e-6 [T].
START_FLOOR = 1e-6
#: The starting step's probes: at most START_PROBES, each at most START_GROWTH times the last.
START_PROBES = 4
START_GROWTH = 100.0


@kernel
def start_step(
    t0, y0, span, rtol, atol, num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs,
    counts,
):  # fmt: skip
    """Radau IIA's first step [T] on the pillar's y' = f(t, y) of :func:`pillar_rates`: the
    starting step of Hairer, Norsett & Wanner (Solving ODEs I, II.4), its probe repeated at
    the step it proposes.

    With sc = atol + rtol |y0| and ||.|| the root mean square over sc: d0 = ||y0||, d1 =
    ||f0||, f0 = f(t0, y0); the probe h0 = 0.01 d0/d1 (START_FLOOR where d0 or d1 < 1e-5);
    d2 = ||f(t0 + h0, y0 + h0 f0) - f0||/h0, the size of y''; h = min(100 h0, (0.01/max(d1,
    d2))^(1/4)) (the exponent of the embedded error estimate's order 3, as scipy's Radau).
    Where h is the cap 100 h0 the probe was too short to see the solution's time scale (a
    start from rest under a drive rising from 0 like t^2: f0 = 0): the probe is repeated at
    h0 = h, at most START_PROBES times. At most ``span`` (> 0), rounded down to 1, 2 or 5
    times a power of 10 (inputs equal but for rounding take the same first step), at least
    1e-13 (|t0| + 1). Each f evaluation is counted in counts[3]."""
    m = y0.size
    least = 1e-13 * (abs(t0) + 1.0)
    if not span > 0.0:
        return START_FLOOR
    ws = workspace(num)
    f0 = np.empty(m)
    f1 = np.empty(m)
    yt = np.empty(m)
    sc = np.empty(m)
    jdummy = np.zeros((1, 1))
    pars = (num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs)
    if not pillar_rates(t0, y0, False, *pars, f0, jdummy, ws):
        return min(START_FLOOR, span)
    counts[3] += 1
    d0 = 0.0
    d1 = 0.0
    for k in range(m):
        sc[k] = atol + rtol * abs(y0[k])
        d0 += (y0[k] / sc[k]) ** 2
        d1 += (f0[k] / sc[k]) ** 2
    d0 = math.sqrt(d0 / m)
    d1 = math.sqrt(d1 / m)
    if not (math.isfinite(d0) and math.isfinite(d1)):
        return min(START_FLOOR, span)
    h0 = START_FLOOR if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(max(h0, least), span)
    h = h0
    for _ in range(START_PROBES):
        for k in range(m):
            yt[k] = y0[k] + h0 * f0[k]
        if not pillar_rates(t0 + h0, yt, False, *pars, f1, jdummy, ws):
            return min(h0, START_FLOOR)
        counts[3] += 1
        d2 = 0.0
        for k in range(m):
            d2 += ((f1[k] - f0[k]) / sc[k]) ** 2
        dm = max(d1, math.sqrt(d2 / m) / h0)
        if not math.isfinite(dm):
            return min(h0, START_FLOOR)
        h1 = (0.01 / dm) ** 0.25 if dm > 1e-15 else math.inf
        h = min(START_GROWTH * h0, h1, span)
        if not h1 > START_GROWTH * h0 or h >= span:
            break
        h0 = h
    e = math.floor(math.log10(h))
    lead = h / 10.0**e
    rounded = min(h, (5.0 if lead >= 5.0 else 2.0 if lead >= 2.0 else 1.0) * 10.0**e)
    return rounded if rounded >= least else h


@kernel
def trajectory_outputs(
    t_eval, y_out, num, dd, ii, srow, d0, theta0, gamma, chi, mu, prof, drives, tabs, theta,
    rates, out,
):  # fmt: skip
    """The trajectory from the integrator's states y_out (time, state) at t_eval: the
    angles theta and their rates at the N + 1 nodes (time, node), theta_0 = theta0 and
    theta_N = srow . theta; overdamped (mu = 0) the rates are f(t, y) of :func:`pillar_rates`,
    with inertia the state's second half; out (4, time): the tip deflection sum_j
    sin(theta_j) ii[N, j], the tip height (cos), the tip angle theta_N and the base moment
    d0 . theta. A time whose state is not finite (past an event or a failure), or whose
    rates cannot be evaluated, is NaN throughout."""
    nt = t_eval.size
    m = y_out.shape[1]
    n = num - 1
    ws = workspace(num)
    f = np.empty(m)
    jdummy = np.zeros((1, 1))
    for i in range(nt):
        good = True
        for k in range(m):
            if not math.isfinite(y_out[i, k]):
                good = False
                break
        if good and mu == 0.0:
            good = pillar_rates(
                t_eval[i], y_out[i], False, num, dd, ii, srow, theta0, gamma, chi, mu, prof,
                drives, tabs, f, jdummy, ws,
            )  # fmt: skip
        if not good:
            for j in range(num + 1):
                theta[i, j] = np.nan
                rates[i, j] = np.nan
            for r in range(4):
                out[r, i] = np.nan
            continue
        theta[i, 0] = theta0
        rates[i, 0] = 0.0
        tip = theta0 * srow[0]
        tip_rate = 0.0
        for j in range(1, num):
            theta[i, j] = y_out[i, j - 1]
            rates[i, j] = f[j - 1] if mu == 0.0 else y_out[i, n + j - 1]
            tip += theta[i, j] * srow[j]
            tip_rate += rates[i, j] * srow[j]
        theta[i, num] = tip
        rates[i, num] = tip_rate
        x = 0.0
        z = 0.0
        moment = 0.0
        for j in range(num + 1):
            x += math.sin(theta[i, j]) * ii[num, j]
            z += math.cos(theta[i, j]) * ii[num, j]
            moment += theta[i, j] * d0[j]
        out[0, i] = x
        out[1, i] = z
        out[2, i] = tip
        out[3, i] = moment


@kernel
def run_radau(
    y0, t_eval, span, rtol, atol, max_steps, num, dd, ii, srow, d0, theta0, gamma, chi, mu,
    prof, drives, tabs, jump_speed,
):  # fmt: skip
    """A pillar's run by Radau IIA in one call: the first step of :func:`start_step` over
    ``span``, ``dynamics.integrate_pillar`` from (t_eval[0], y0) to t_eval[-1], and the
    outputs of :func:`trajectory_outputs`. Returns (status, t_end, counts, theta, rates,
    out) as those."""
    nt = t_eval.size
    counts = np.zeros(6, dtype=np.int64)
    pars = (num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs)
    h0 = start_step(t_eval[0], y0, span, rtol, atol, *pars, counts)
    y_out = np.full((nt, y0.size), np.nan)
    status, t_end = integrate_pillar(
        y0, t_eval[0], t_eval, rtol, atol, h0, max_steps, *pars, y_out, counts, jump_speed
    )
    theta = np.empty((nt, num + 1))
    rates = np.empty((nt, num + 1))
    out = np.empty((4, nt))
    trajectory_outputs(t_eval, y_out, num, dd, ii, srow, d0, *pars[4:], theta, rates, out)
    return status, t_end, counts, theta, rates, out
