"""Generate ``tests/data/loaded_mpmath.json``: the hair under a tip load and a load per height.

Run on demand (about ten minutes on two shared cores)::

    .venv/bin/python tests/reference/generate_loaded.py [--workers 2] [--out PATH] [--quick]
    .venv/bin/python tests/reference/generate_loaded.py --resume   # only the missing cases

``--resume`` keeps the cases of an existing ``--out`` whose inputs and label are unchanged and
computes the rest (the file is rewritten after every case, so an interrupted run resumes).

It imports nothing from :mod:`hairbed` and shares no code with its solver: the equations are
written here from issue 20 (docs/theory.md, distributed loads). With s in [0, 1]::

    theta'' = -[W + Pi (h1 - z)] cos(theta),  z' = cos(theta),  x' = sin(theta),
    theta(0) = theta0,  theta'(1) = 0,  z(0) = x(0) = 0,  h1 = z(1),

and the loads of the two drives (u = 1 - eps h1)::

    "pressure" (pi given):  W = omega2/u + (pi/2)(1/eps - h1),  Pi = pi;
    "flow" (q given):       W = q/u^2 - 2 omega2/u,  Pi = 2 eps q/u^3 - 6 eps omega2/u^2.

Method
------
The problem is shot from the tip, where it is well conditioned: in tau = 1 - s with
phi = pi/2 - theta (the angle from the flow direction) and zeta = h1 - z (the depth below the
tip plane), F = W + Pi zeta and::

    phi'' = F sin(phi),  zeta' = sin(phi),  X' = cos(phi),
    phi(0) = phi1,  phi'(0) = 0,  zeta(0) = X(0) = 0;
    residuals:  phi(1) - (pi/2 - theta0) = 0,  zeta(1) - h1 = 0.

X(1) is the tip deflection x1 and x(s) = x1 - X(1 - s); the base curvature is phi'(tau = 1).
Shooting from the base would amplify errors by exp(sqrt(F)) (1e43 at F = 1e4: strong loads
have a boundary layer at the base); from the tip the solution itself grows at that rate and the
integration keeps its relative accuracy, and phi1 ~ exp(-sqrt(F)) is an ordinary mpf.

* Scan (double precision, numpy/scipy, only to find the states): for every h1 on a grid of
  (0, 1] (41 geometric points from 1e-5 plus a uniform step of 1/240), the loads are fixed
  and the inner problem phi(1) = pi/2 - theta0 is solved for ln(phi1) in
  [ln(pi/2 - theta0) - 1.3 sqrt(F_max) - 12, ln(pi/2 - theta0)] by 7 bisections and 9
  Illinois steps on RK4 (1200 steps), vectorised over h1; on every 6th h1 a grid of 40
  values of ln(phi1) (RK4, 600 steps) shows that there is exactly one solution (the generator
  stops otherwise: that is the fundamental family, see below). Then G(h1) = zeta(1) - h1 is
  tabulated; G > 0 as h1 -> 0 and G(1) < 0 (checked). Every sign change of G, and every local
  extremum of G between grid points that points towards zero (a close pair of states near a
  fold; searched by a bounded Brent minimisation), is refined by nested Brent iterations on
  scipy's DOP853 (rtol 1e-13).
* Refinement (mpmath, ``DPS`` digits): Newton's method in (ln phi1, h1) with the exact
  Jacobian from the variational equations, integrated alongside. The integrator is a Taylor
  series method whose coefficients come from exact recurrences (S = sin phi, C = cos phi:
  S' = C phi', C' = -S phi'; the right-hand sides are then products of series), with steps
  chosen from the last two coefficients of phi relative to phi itself (so the tiny phi near
  the tip keeps its relative accuracy), landing exactly on tau = 1/4, 1/2, 3/4, 1.
* Stability ("stable"): the sign of dG/dh1 at the state, G(h1) = zeta(1) - h1 with the inner
  problem (phi(1) = pi/2 - theta0) solved: stable when dG/dh1 < 0, as on the unloaded branch.
  This is the parity of the number of real unstable eigenvalues of the quasi-static
  relaxation (exchange of stability at folds, as in hairbed.stability for the wall problem);
  an oscillatory (Hopf) loss of stability would not be seen.

Cases (``build_cases``): the wall problem (pi = 0, with two of its windows); the pressure drive
with the wall at rest (pi from 1e-6 to 1e4) and moving, one with pi < 0 against the wall; the
flow drive at rest (q from 1e-6 to 1e4) and with the wall moving, one with the wall held
against the flow (Pi < 0 at small h1); small loads at theta0 = 0 (1e-3, 1e-2); a grid of five
inputs through a window of each loaded drive (one state, three, three, three, one); and a
relative 1e-4 inside and outside each of the four folds that bound those windows. theta0 spans
-1.5 to 1.5 in both drives and eps reaches 0.99.

Which states: "every coexisting state" means every state of the fundamental family, the hair
that never turns back towards the wall (-pi/2 < theta < pi/2 along it, so z is increasing and
0 < h1 <= 1). The other solutions of the equations (the hair looping once or more about its
base, n >= 1 in the paper's notation, or crossing the wall, h1 < 0) are not listed. Every case
is chosen with F = W + Pi (h1 - z) > 0 on the whole hair for every h1 in (0, 1] (checked), so
theta increases from theta0 towards pi/2 and the inner problem has one solution per h1
(checked on the grid).

Checks (the generator stops rather than write a value that fails one):

1. identity: theta'(0) = W h1 + Pi h1^2/2 to 1e-25 (relative to max(1, theta'(0)));
2. orders: every state re-converged with a second integrator order (``ORDERS``), so different
   steps; every written value agrees to 1e-20 (relative to max(1, |value|));
3. at pi = 0 (the paper's wall problem) every state, its count and its shape agree with the
   closed form (generate_reference.py, Carlson forms, 50 digits) to 1e-25;
4. residuals of the two boundary conditions below 1e-30 and distinct states at least 1e-8
   apart in h1 (no root found twice, none lost in a merge);
5. where the load is moderate (W + |Pi| h1 <= ``ODEFUN_MAX_LOAD``), ``mpmath.odefun`` (its own
   Taylor method) integrates from the base, theta(0) = theta0 and theta'(0) = base_curvature,
   at ``ODEFUN_DPS`` digits: theta'(1) = 0, z(1) = h1, x(1), theta(1) and the shape agree to
   ``ODEFUN_TOL``.

The folds that bound the two windows are tabulated too (``folds``): the value of omega2 or q at
which two states merge, from (R1, R2, dG/dh1) = 0 by Newton's method at ``DPS`` digits (the
Jacobian by central differences), started from a double-precision estimate (the zero of the
extremum of G between the merging pair, by Brent), and re-converged at the second order.

Numbers are written as strings with ``OUT_DIGITS`` significant digits; the inputs are the
JSON numbers (binary doubles, converted exactly).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import multiprocessing
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
from mpmath import mp, mpf
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

sys.path.insert(0, str(Path(__file__).resolve().parent))
import generate_reference as gr  # noqa: E402  (the closed form, for check 3 only)

__all__ = ["build_cases", "compute_case", "compute_fold", "main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "loaded_mpmath.json"
#: Working precision of the refinement [decimal digits].
DPS = 45
#: Significant digits written out.
OUT_DIGITS = 30
#: The two Taylor orders: the states are converged with the first and re-converged with the
#: second (check 2).
ORDERS = (40, 56)
#: Tolerances of the checks.
IDENTITY_TOL = mpf("1e-25")
ORDERS_TOL = mpf("1e-20")
CLOSED_FORM_TOL = mpf("1e-25")
RESIDUAL_TOL = mpf("1e-30")
#: mpmath.odefun (check 5) is run from the base where the largest load W + |Pi| h1 is below
#: this (beyond, shooting from the base loses digits and odefun needs minutes), at ODEFUN_DPS.
ODEFUN_MAX_LOAD = 3.0
ODEFUN_DPS = 30
ODEFUN_TOL = mpf("1e-24")
#: Points along the hair where the shape is tabulated.
SHAPE_S = (0.25, 0.5, 0.75)
FIELDS = ("tip_height", "tip_deflection", "tip_angle", "base_curvature", "W", "Pi")


# ------------------------------------------------------------------------------------------
# Loads
# ------------------------------------------------------------------------------------------


def loads(case: dict[str, Any], h1: Any) -> tuple[Any, Any, Any, Any]:
    """(W, Pi, dW/dh1, dPi/dh1) at tip height h1 (floats, numpy arrays or mpf)."""
    eps, omega2 = case["_eps"], case["_omega2"]
    u = 1 - eps * h1
    if case["drive"] == "pressure":
        p = case["_pi"]
        w = omega2 / u + p / 2 * (1 / eps - h1)
        return w, p + 0 * u, omega2 * eps / u**2 - p / 2, 0 * u
    q = case["_q"]
    w = q / u**2 - 2 * omega2 / u
    big_pi = 2 * eps * q / u**3 - 6 * eps * omega2 / u**2
    dw = 2 * eps * q / u**3 - 2 * eps * omega2 / u**2
    dpi = 6 * eps**2 * q / u**4 - 12 * eps**2 * omega2 / u**3
    return w, big_pi, dw, dpi


def _float_inputs(case: dict[str, Any]) -> dict[str, Any]:
    c = dict(case)
    c["_eps"], c["_omega2"] = float(case["eps"]), float(case["omega2"])
    c["_pi"] = float(case["pi"] or 0.0)
    c["_q"] = float(case["q"] or 0.0)
    return c


def _mp_inputs(case: dict[str, Any]) -> dict[str, Any]:
    c = dict(case)
    c["_eps"], c["_omega2"] = mpf(case["eps"]), mpf(case["omega2"])
    c["_pi"] = mpf(case["pi"] or 0.0)
    c["_q"] = mpf(case["q"] or 0.0)
    return c


# ------------------------------------------------------------------------------------------
# Scan in double precision
# ------------------------------------------------------------------------------------------

SCAN_STEPS = 1200
N_LNPHI = 40
UNIQUE_EVERY = 6
BISECT = 7
ILLINOIS = 9


def _rk4_tip(w: np.ndarray, big_pi: np.ndarray, phi1: np.ndarray, steps: int):
    """phi(1), zeta(1) of the tip problem for arrays of (W, Pi, phi1), by RK4."""
    h = 1.0 / steps
    phi = phi1.copy()
    p = np.zeros_like(phi)
    z = np.zeros_like(phi)
    alive = np.ones(phi.shape, dtype=bool)

    def f(ph, zz):
        return (w + big_pi * zz) * np.sin(ph), np.sin(ph)

    for _ in range(steps):
        a1, b1 = f(phi, z)
        k1p, k1z = p, b1
        a2, b2 = f(phi + h / 2 * k1p, z + h / 2 * k1z)
        k2p, k2z = p + h / 2 * a1, b2
        a3, b3 = f(phi + h / 2 * k2p, z + h / 2 * k2z)
        k3p, k3z = p + h / 2 * a2, b3
        a4, b4 = f(phi + h * k3p, z + h * k3z)
        k4p, k4z = p + h * a3, b4
        nphi = phi + h / 6 * (k1p + 2 * k2p + 2 * k3p + k4p)
        npp = p + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        nz = z + h / 6 * (k1z + 2 * k2z + 2 * k3z + k4z)
        phi = np.where(alive, nphi, phi)
        p = np.where(alive, npp, p)
        z = np.where(alive, nz, z)
        alive &= phi < 4.0  # beyond pi the hair has turned back: out of the family
    return phi, z


def _lnphi_range(case: dict[str, Any], h1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    w, big_pi, _, _ = loads(case, h1)
    fmax = w + np.maximum(big_pi, 0.0) * h1
    top = math.log(math.pi / 2 - case["_theta0"])
    return top - 1.3 * np.sqrt(fmax) - 12.0, np.full_like(h1, top)


def _check_positive_load(case: dict[str, Any], h1: np.ndarray) -> None:
    w, big_pi, _, _ = loads(case, h1)
    fmin = w + np.minimum(big_pi, 0.0) * h1
    if not np.all(fmin > 0):
        raise RuntimeError(f"{case['label']}: the load changes sign on the hair: not tabulated")


def h1_grid() -> np.ndarray:
    geo = np.geomspace(1e-5, 1.0, 41)
    lin = np.arange(1, 241) / 240.0
    return np.unique(np.concatenate([geo, lin]))


def scan_G(case: dict[str, Any], h1: np.ndarray, steps: int = SCAN_STEPS):
    """ln(phi1) of the inner problem and G(h1) = zeta(1) - h1 on the grid h1 (RK4).

    Uniqueness of the inner solution is checked on every ``UNIQUE_EVERY``-th h1 against a
    grid of ``N_LNPHI`` values of ln(phi1); the root is then bracketed in the whole range
    and refined by bisection and Illinois steps, vectorised over h1.
    """
    phi0 = math.pi / 2 - case["_theta0"]
    w, big_pi, _, _ = loads(case, h1)
    lo, hi = _lnphi_range(case, h1)
    sub = np.arange(0, h1.size, UNIQUE_EVERY)
    t = np.linspace(0.0, 1.0, N_LNPHI)
    lnphi = lo[sub, None] + (hi - lo)[sub, None] * t[None, :]
    ph, _ = _rk4_tip(
        np.broadcast_to(w[sub, None], lnphi.shape).ravel(),
        np.broadcast_to(big_pi[sub, None], lnphi.shape).ravel(),
        np.exp(lnphi).ravel(),
        steps // 2,
    )
    r1 = ph.reshape(lnphi.shape) - phi0
    changes = np.sum(np.sign(r1[:, 1:]) != np.sign(r1[:, :-1]), axis=1)
    if not np.all(changes == 1) or not np.all(r1[:, 0] < 0):
        bad = np.nonzero(changes != 1)[0]
        raise RuntimeError(
            f"{case['label']}: inner problem has {changes[bad[:3]]} solutions at h1 = "
            f"{h1[sub][bad[:3]]}: not the fundamental family alone"
        )
    a, b = lo.copy(), hi.copy()
    fa = _rk4_tip(w, big_pi, np.exp(a), steps)[0] - phi0
    fb = _rk4_tip(w, big_pi, np.exp(b), steps)[0] - phi0
    if not (np.all(fa < 0) and np.all(fb > 0)):
        raise RuntimeError(f"{case['label']}: the range of ln(phi1) does not bracket")
    for it in range(BISECT + ILLINOIS):
        c = (a + b) / 2 if it < BISECT else b - fb * (b - a) / (fb - fa)
        fc = _rk4_tip(w, big_pi, np.exp(c), steps)[0] - phi0
        if it < BISECT:
            left = fc < 0
            a, fa = np.where(left, c, a), np.where(left, fc, fa)
            b, fb = np.where(left, b, c), np.where(left, fb, fc)
            continue
        same = np.sign(fc) == np.sign(fb)
        a = np.where(same, a, b)
        fa = np.where(same, fa / 2, fb)
        b, fb = c, fc
    _, z = _rk4_tip(w, big_pi, np.exp(b), steps)
    return b, z - h1


# Accurate double-precision version (DOP853) for the refinement of the scan's roots.


def _tip_ivp(w: float, big_pi: float, lnphi1: float) -> tuple[float, float]:
    def rhs(_t, y):
        s = math.sin(y[0])
        return [y[1], (w + big_pi * y[2]) * s, s]

    def out(_t, y):
        return 3.5 - y[0]

    out.terminal = True  # type: ignore[attr-defined]
    sol = solve_ivp(
        rhs,
        (0.0, 1.0),
        [math.exp(max(lnphi1, -700.0)), 0.0, 0.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-14 * min(1.0, math.exp(max(lnphi1, -700.0))),
        events=out,
    )
    if sol.status == 1:
        return 3.5, math.nan
    return float(sol.y[0, -1]), float(sol.y[2, -1])


def _inner(case: dict[str, Any], h1: float, guess: float) -> tuple[float, float]:
    """(ln phi1, G) at h1 by Brent on the DOP853 tip problem."""
    phi0 = math.pi / 2 - case["_theta0"]
    w, big_pi, _, _ = loads(case, h1)
    lo, hi = _lnphi_range(case, np.array([h1]))

    def r1(v):
        return _tip_ivp(w, big_pi, v)[0] - phi0

    a, b = guess - 0.5, guess + 0.5
    while r1(a) > 0 and a > lo[0]:
        a -= 2.0
    while r1(b) < 0 and b < hi[0]:
        b += 2.0
    b = min(b, float(hi[0]))
    v = brentq(r1, a, b, xtol=1e-15, rtol=1e-15, maxiter=200)
    return v, _tip_ivp(w, big_pi, v)[1] - h1


def find_states(case: dict[str, Any]) -> tuple[list[tuple[float, float]], dict[str, Any]]:
    """Every state (h1, ln phi1) in double precision; info on the scan."""
    h1 = h1_grid()
    _check_positive_load(case, np.linspace(1e-9, 1.0, 2001))
    lnphi, g = scan_G(case, h1)
    brackets = []
    for i in range(h1.size - 1):
        if g[i] == 0 or g[i] * g[i + 1] < 0:
            brackets.append((h1[i], h1[i + 1], lnphi[i]))
    extrema = 0
    for i in range(1, h1.size - 1):
        d1, d2 = g[i] - g[i - 1], g[i + 1] - g[i]
        if d1 * d2 < 0 and g[i - 1] * g[i] > 0 and g[i] * g[i + 1] > 0:
            extrema += 1
            is_min = d1 < 0
            if (is_min and g[i] < 0) or (not is_min and g[i] > 0):
                continue
            sgn = 1.0 if is_min else -1.0
            res = minimize_scalar(
                lambda v, sgn=sgn, i=i: sgn * _inner(case, v, lnphi[i])[1],
                bounds=(h1[i - 1], h1[i + 1]),
                method="bounded",
                options={"xatol": 1e-14},
            )
            gm = sgn * res.fun
            if gm * g[i] < 0:
                brackets.append((h1[i - 1], res.x, lnphi[i]))
                brackets.append((res.x, h1[i + 1], lnphi[i]))
    states = []
    for a, b, guess in sorted(brackets):
        root = brentq(
            lambda v, guess=guess: _inner(case, v, guess)[1], a, b, xtol=1e-15, rtol=1e-15
        )
        states.append((root, _inner(case, root, guess)[0]))
    g_first, g_last = float(g[0]), float(g[-1])
    if not (g_first > 0 and g_last < 0):
        raise RuntimeError(f"{case['label']}: G(0+) = {g_first}, G(1) = {g_last}")
    info = {"h1_grid_points": int(h1.size), "local_extrema": extrema}
    return states, info


# ------------------------------------------------------------------------------------------
# Taylor-series integration in mpmath
# ------------------------------------------------------------------------------------------


def _dot(a: list[mpf], b: list[mpf], k: int) -> mpf:
    """sum_{j=0}^{k} a_j b_{k-j}."""
    return mp.fdot(a[: k + 1], b[k::-1])


def taylor_tip(
    w: mpf,
    big_pi: mpf,
    dw: mpf,
    dpi: mpf,
    phi1: mpf,
    order: int,
    variational: bool,
) -> dict[str, Any]:
    """Integrate the tip problem from tau = 0 to 1 (and its variational equations).

    Returns the states [phi, phi', zeta, X] at tau = 1/4, 1/2, 3/4, 1 and, with
    ``variational``, d(phi, zeta)(1)/d(phi1) and d(phi, zeta)(1)/d(h1).
    """
    nn = order
    tol_exp = mpf(10) ** (-mpf(mp.dps + 3) / nn)
    marks = [mpf(1) / 4, mpf(1) / 2, mpf(3) / 4, mpf(1)]
    y = [phi1, mpf(0), mpf(0), mpf(0)]  # phi, p, zeta, X
    v = [mpf(1), mpf(0), mpf(0), mpf(0), mpf(0), mpf(0)]  # a, ap, b, c, cp, d
    tau = mpf(0)
    out: list[list[mpf]] = []
    steps = 0
    while marks:
        ph = [y[0]] + [mpf(0)] * nn
        pp = [y[1]] + [mpf(0)] * nn
        ze = [y[2]] + [mpf(0)] * nn
        xx = [y[3]] + [mpf(0)] * nn
        ss = [mp.sin(y[0])] + [mpf(0)] * nn
        cc = [mp.cos(y[0])] + [mpf(0)] * nn
        zs = [mpf(0)] * nn
        if variational:
            a = [v[0]] + [mpf(0)] * nn
            ap = [v[1]] + [mpf(0)] * nn
            b = [v[2]] + [mpf(0)] * nn
            c = [v[3]] + [mpf(0)] * nn
            cp = [v[4]] + [mpf(0)] * nn
            d = [v[5]] + [mpf(0)] * nn
            fc = [mpf(0)] * nn
        for k in range(nn):
            k1 = k + 1
            zs[k] = _dot(ze, ss, k)
            ph[k1] = pp[k] / k1
            pp[k1] = (w * ss[k] + big_pi * zs[k]) / k1
            ze[k1] = ss[k] / k1
            xx[k1] = cc[k] / k1
            ss[k1] = _dot(cc, pp, k) / k1
            cc[k1] = -_dot(ss, pp, k) / k1
            if variational:
                fc[k] = w * cc[k] + big_pi * _dot(ze, cc, k)
                a[k1] = ap[k] / k1
                ap[k1] = (_dot(fc, a, k) + big_pi * _dot(b, ss, k)) / k1
                b[k1] = _dot(cc, a, k) / k1
                c[k1] = cp[k] / k1
                cp[k1] = (_dot(fc, c, k) + dw * ss[k] + dpi * zs[k] + big_pi * _dot(d, ss, k)) / k1
                d[k1] = _dot(cc, c, k) / k1
        # Step from the last two coefficients of phi, relative to phi itself.
        scale = abs(ph[0])
        rho = (
            max((abs(ph[k]) / scale) ** (mpf(1) / k) for k in (nn - 1, nn) if ph[k] != 0)
            if any(ph[k] != 0 for k in (nn - 1, nn))
            else mpf(0)
        )
        h = marks[0] - tau
        if rho > 0:
            h = min(h, tol_exp / rho)
        y = [mp.polyval(s[::-1], h) for s in (ph, pp, ze, xx)]
        if variational:
            v = [mp.polyval(s[::-1], h) for s in (a, ap, b, c, cp, d)]
        tau += h
        steps += 1
        if tau == marks[0]:
            out.append(list(y))
            marks = marks[1:]
    res: dict[str, Any] = {"at": out, "steps": steps}
    if variational:
        res["d_phi1"] = (v[0], v[2])
        res["d_h1"] = (v[3], v[5])
    return res


def newton(case: dict[str, Any], h1: mpf, lnphi: mpf, order: int) -> dict[str, Any]:
    """Converge (ln phi1, h1) at the current precision; values of the state."""
    phi0 = mp.pi / 2 - case["_theta0"]
    tol = mpf(10) ** (-(mp.dps - 6))
    for it in range(40):  # noqa: B007 (it is reported)
        w, big_pi, dw, dpi = loads(case, h1)
        phi1 = mp.exp(lnphi)
        r = taylor_tip(w, big_pi, dw, dpi, phi1, order, True)
        tip = r["at"][-1]
        r1, r2 = tip[0] - phi0, tip[2] - h1
        j11, j21 = phi1 * r["d_phi1"][0], phi1 * r["d_phi1"][1]
        j12, j22 = r["d_h1"][0], r["d_h1"][1] - 1
        det = j11 * j22 - j12 * j21
        du = (r1 * j22 - r2 * j12) / det
        dh = (j11 * r2 - j21 * r1) / det
        lnphi -= du
        h1 -= dh
        if abs(du) < tol and abs(dh) < tol:
            break
    else:
        raise RuntimeError(f"{case['label']}: Newton did not converge at h1 ~ {h1}")
    w, big_pi, dw, dpi = loads(case, h1)
    phi1 = mp.exp(lnphi)
    r = taylor_tip(w, big_pi, dw, dpi, phi1, order, True)
    tip = r["at"][-1]
    j11, j21 = phi1 * r["d_phi1"][0], phi1 * r["d_phi1"][1]
    j12, j22 = r["d_h1"][0], r["d_h1"][1] - 1
    dg = (j11 * j22 - j12 * j21) / j11  # dG/dh1 with the inner problem solved
    x1 = tip[3]
    vals: dict[str, Any] = {
        "tip_height": h1,
        "tip_deflection": x1,
        "tip_angle": mp.pi / 2 - phi1,
        "base_curvature": tip[1],
        "W": w,
        "Pi": big_pi,
        # r["at"] holds tau = 1/4, 1/2, 3/4: s = 3/4, 1/2, 1/4
        "x": [x1 - r["at"][i][3] for i in (2, 1, 0)],
        "z": [h1 - r["at"][i][2] for i in (2, 1, 0)],
        "theta": [mp.pi / 2 - r["at"][i][0] for i in (2, 1, 0)],
    }
    return {
        "values": vals,
        "lnphi": lnphi,
        "residual": max(abs(tip[0] - phi0), abs(tip[2] - h1)),
        "dG_dh1": dg,
        "newton_iterations": it + 1,
        "steps": r["steps"],
    }


# ------------------------------------------------------------------------------------------
# One case
# ------------------------------------------------------------------------------------------


def _fmt(v: mpf) -> str:
    return mp.nstr(v, OUT_DIGITS)


def _rel(a: mpf, b: mpf) -> mpf:
    return abs(a - b) / max(1, abs(a))


def _max_change(va: dict[str, Any], vb: dict[str, Any]) -> mpf:
    worst = mpf(0)
    for key in FIELDS:
        worst = max(worst, _rel(va[key], vb[key]))
    for key in ("x", "z", "theta"):
        for a, b in zip(va[key], vb[key]):
            worst = max(worst, _rel(a, b))
    return worst


def closed_form_states(case: dict[str, Any]) -> list[dict[str, Any]]:
    """The wall problem's states on the fundamental branch (generate_reference, route A)."""
    mp.dps = gr.DPS
    br = gr.Branch(case["omega2"], case["eps"], case["theta0"], 1, 0)
    ts, _ = gr.find_roots(br)
    return [gr.evaluate(br, t, SHAPE_S) for t in ts]


def odefun_check(va: dict[str, Any], theta0: mpf) -> mpf:
    """Check 5: mpmath.odefun from the base (theta0, theta'(0)) in s; the largest deviation.

    theta'(1) must vanish, and z(1), x(1), theta(1) and the shape must be the tabulated ones.
    """
    mp.dps = ODEFUN_DPS
    w, big_pi, h1 = mpf(va["W"]), mpf(va["Pi"]), mpf(va["tip_height"])

    def rhs(_s, y):
        c = mp.cos(y[0])
        return [y[1], -(w + big_pi * (h1 - y[2])) * c, c, mp.sin(y[0])]

    sol = mp.odefun(rhs, 0, [theta0, mpf(va["base_curvature"]), mpf(0), mpf(0)])
    tip = sol(1)
    m = max(1, abs(va["base_curvature"]))
    err = abs(tip[1]) / m
    err = max(err, _rel(va["tip_height"], tip[2]), _rel(va["tip_deflection"], tip[3]))
    err = max(err, _rel(va["tip_angle"], tip[0]))
    for k, sk in enumerate(SHAPE_S):
        y = sol(mpf(sk))
        err = max(err, _rel(va["theta"][k], y[0]), _rel(va["z"][k], y[2]), _rel(va["x"][k], y[3]))
    return err


def compute_case(case: dict[str, Any]) -> dict[str, Any]:
    start = time.time()
    fcase = _float_inputs(case)
    fcase["_theta0"] = float(case["theta0"])
    guesses, info = find_states(fcase)
    closed = closed_form_states(case) if case["drive"] == "pressure" and not case["pi"] else None
    mp.dps = DPS
    mcase = _mp_inputs(case)
    mcase["_theta0"] = mpf(case["theta0"])
    states = []
    worst = {
        "identity": mpf(0),
        "orders": mpf(0),
        "residual": mpf(0),
        "closed_form": None,
        "odefun": None,
    }
    for h1g, lng in guesses:
        a = newton(mcase, mpf(h1g), mpf(lng), ORDERS[0])
        b = newton(mcase, a["values"]["tip_height"], a["lnphi"], ORDERS[1])
        va = a["values"]
        ident = abs(
            va["base_curvature"]
            - (va["W"] * va["tip_height"] + va["Pi"] * va["tip_height"] ** 2 / 2)
        )
        ident /= max(1, abs(va["base_curvature"]))
        change = _max_change(va, b["values"])
        resid = max(a["residual"], b["residual"])
        label = f"{case['label']} h1={mp.nstr(va['tip_height'], 8)}"
        if ident > IDENTITY_TOL:
            raise RuntimeError(f"{label}: identity off by {mp.nstr(ident, 3)}")
        if change > ORDERS_TOL:
            raise RuntimeError(f"{label}: orders {ORDERS} differ by {mp.nstr(change, 3)}")
        if resid > RESIDUAL_TOL:
            raise RuntimeError(f"{label}: residual {mp.nstr(resid, 3)}")
        worst["identity"] = max(worst["identity"], ident)
        worst["orders"] = max(worst["orders"], change)
        worst["residual"] = max(worst["residual"], resid)
        states.append((va, bool(a["dG_dh1"] < 0), a["steps"], a["newton_iterations"]))
    hs = [s[0]["tip_height"] for s in states]
    for x, y in zip(hs, hs[1:]):
        if not y - x > mpf("1e-8"):
            raise RuntimeError(f"{case['label']}: states not distinct/sorted: {x}, {y}")
    if closed is not None:
        if len(closed) != len(states):
            raise RuntimeError(
                f"{case['label']}: {len(states)} states, the closed form has {len(closed)}"
            )
        err = mpf(0)
        for (va, *_), cf in zip(states, closed):
            for key in ("tip_height", "tip_deflection", "tip_angle", "base_curvature"):
                err = max(err, _rel(cf[key], va[key]))
            for key in ("x", "z", "theta"):
                for u, v in zip(cf[key], va[key]):
                    err = max(err, _rel(u, v))
        if err > CLOSED_FORM_TOL:
            raise RuntimeError(f"{case['label']}: closed form differs by {mp.nstr(err, 3)}")
        worst["closed_form"] = err
    for va, *_ in states:
        if va["W"] + abs(va["Pi"]) * va["tip_height"] <= ODEFUN_MAX_LOAD:
            err = odefun_check(va, mpf(case["theta0"]))
            if err > ODEFUN_TOL:
                raise RuntimeError(f"{case['label']}: mpmath.odefun differs by {err}")
            worst["odefun"] = max(worst["odefun"] or mpf(0), err)
    mp.dps = DPS
    out_states = []
    for va, stable, steps, _nit in states:
        out_states.append(
            {
                **{key: _fmt(va[key]) for key in FIELDS},
                "shape": {
                    "s": list(SHAPE_S),
                    "x": [_fmt(v) for v in va["x"]],
                    "z": [_fmt(v) for v in va["z"]],
                    "theta": [_fmt(v) for v in va["theta"]],
                },
                "stable": stable,
                "taylor_steps": steps,
            }
        )
    public = {k: v for k, v in case.items() if not k.startswith("_")}
    return {
        **public,
        "states": out_states,
        "scan": info,
        "checks": {
            "identity": mp.nstr(worst["identity"], 3),
            "orders": mp.nstr(worst["orders"], 3),
            "residual": mp.nstr(worst["residual"], 3),
            "closed_form": None
            if worst["closed_form"] is None
            else mp.nstr(worst["closed_form"], 3),
            "odefun": None if worst["odefun"] is None else mp.nstr(worst["odefun"], 3),
        },
        "seconds": round(time.time() - start, 1),
    }


# ------------------------------------------------------------------------------------------
# Cases
# ------------------------------------------------------------------------------------------


def _case(drive: str, omega2: float, eps: float, theta0: float, label: str, *, pi=None, q=None):
    return {
        "drive": drive,
        "omega2": float(omega2),
        "pi": None if pi is None else float(pi),
        "q": None if q is None else float(q),
        "eps": float(eps),
        "theta0": float(theta0),
        "label": label,
    }


def build_cases(quick: bool = False) -> list[dict[str, Any]]:
    c: list[dict[str, Any]] = []
    P, F = "pressure", "flow"
    # Wall problem (pi = 0): the closed form applies (check 3).
    c.append(_case(P, 0.5, 0.5, 0.0, "wall pi=0", pi=0.0))
    c.append(_case(P, 2.0, 0.9, -0.5, "wall pi=0", pi=0.0))
    c.append(_case(P, 10.0, 0.3, 1.0, "wall pi=0", pi=0.0))
    c.append(_case(P, 0.51, 0.95, -1.2, "wall pi=0 window", pi=0.0))
    c.append(_case(P, 1.2, 0.9, -1.5, "wall pi=0 window", pi=0.0))
    if quick:
        c.append(_case(P, 0.0, 0.5, 0.3, "pressure", pi=1.0))
        c.append(_case(F, 0.0, 0.5, -0.3, "flow", q=1.0))
        return c
    # Pressure drive, wall at rest: pi from 1e-6 to 1e4.
    for pi, eps, th in [
        (1e-6, 0.5, 0.0),
        (1e-6, 0.2, 1.0),
        (1e-3, 0.5, -1.0),
        (0.1, 0.9, 0.5),
        (1.0, 0.5, 0.0),
        (1.0, 0.99, -1.5),
        (3.0, 0.7, 1.5),
        (10.0, 0.3, -0.8),
        (100.0, 0.9, 0.2),
        (1e3, 0.5, -1.5),
        (1e4, 0.1, 0.0),
        (1e4, 0.99, 1.5),
    ]:
        c.append(_case(P, 0.0, eps, th, "pressure", pi=pi))
    # Pressure drive with the wall moving.
    for w, pi, eps, th in [
        (0.5, 0.5, 0.5, 0.0),
        (2.0, 1.0, 0.9, -1.0),
        (1e3, 10.0, 0.5, 0.7),
        (1e-6, 1e-6, 0.9, 0.0),
        (5.0, 1e4, 0.2, -0.5),
    ]:
        c.append(_case(P, w, eps, th, "pressure+wall", pi=pi))
    # Pressure against the wall (pi < 0): Pi < 0, the load W + Pi (h1 - z) stays positive.
    c.append(_case(P, 2.0, 0.5, 0.3, "pressure against wall", pi=-0.5))
    # Flow drive, wall at rest: q from 1e-6 to 1e4.
    for q, eps, th in [
        (1e-6, 0.5, 0.0),
        (1e-6, 0.9, -1.5),
        (1e-3, 0.3, 1.2),
        (0.1, 0.99, 0.0),
        (1.0, 0.5, -0.5),
        (1.0, 0.99, -1.5),
        (3.0, 0.8, 1.5),
        (30.0, 0.6, -1.0),
        (300.0, 0.95, 0.4),
        (1e3, 0.2, -1.5),
        (1e4, 0.5, 0.0),
        (1e4, 0.99, -0.3),
    ]:
        c.append(_case(F, 0.0, eps, th, "flow", q=q))
    # Flow drive with the wall moving (q > 3 omega2: both loads positive; and one opposing).
    for w, q, eps, th in [
        (0.1, 1.0, 0.5, 0.0),
        (1.0, 10.0, 0.9, -1.0),
        (100.0, 1e3, 0.5, 1.0),
        (1e-7, 1e-6, 0.7, 0.0),
    ]:
        c.append(_case(F, w, eps, th, "flow+wall", q=q))
    # The wall held back against the flow (q < 3 omega2 u): Pi < 0 at small h1.
    c.append(_case(F, 0.4, 0.5, -0.2, "wall against flow", q=1.0))
    # Small loads at theta0 = 0: x1 = W/3 + Pi/8 + O(load^2), the remainder shrinking.
    for load in (1e-3, 1e-2):
        c.append(_case(P, 0.0, 0.5, 0.0, "small load", pi=load))
        c.append(_case(F, 0.0, 0.5, 0.0, "small load", q=load))
    c += WINDOW_CASES
    c += _near_fold_cases()
    return c


#: Inputs through a bistable window of each loaded drive (located by a double-precision
#: count of the sign changes of G on a grid of the drive parameter): the pressure drive with
#: the wall moving at pi = 0.1, eps = 0.95, theta0 = -1.2 (three states for omega2 about
#: 0.46 to 0.54) and the flow drive at rest, eps = 0.8, theta0 = -1.2 (q about 0.08 to 0.2);
#: each from outside the window through it to outside again.
WINDOW_CASES: list[dict[str, Any]] = [
    *(
        _case("pressure", w, 0.95, -1.2, "pressure window", pi=0.1)
        for w in (0.42, 0.47, 0.5, 0.53, 0.58)
    ),
    *(_case("flow", 0.0, 0.8, -1.2, "flow window", q=q) for q in (0.05, 0.09, 0.13, 0.18, 0.3)),
]
#: The fold values of the windows (the ``folds`` this generator tabulates, checked in main)
#: and the near-fold inputs: a relative 1e-4 inside (three states, two of them close) and
#: outside (one state) of each fold.
FOLD_VALUES = (0.4535979898120236, 0.5475626548463574, 0.07644718625543093, 0.2137887611050646)
NEAR_FOLD = 1e-4


def _near_fold_cases() -> list[dict[str, Any]]:
    out = []
    for value, inward, name in (
        (FOLD_VALUES[0], 1, "omega2"),
        (FOLD_VALUES[1], -1, "omega2"),
        (FOLD_VALUES[2], 1, "q"),
        (FOLD_VALUES[3], -1, "q"),
    ):
        for side in (1, -1):
            v = float(f"{value * (1 + side * inward * NEAR_FOLD):.15g}")
            if name == "omega2":
                out.append(_case("pressure", v, 0.95, -1.2, "pressure near fold", pi=0.1))
            else:
                out.append(_case("flow", 0.0, 0.8, -1.2, "flow near fold", q=v))
    return out


# ------------------------------------------------------------------------------------------
# Folds of the windows
# ------------------------------------------------------------------------------------------

#: The folds that bound the two windows of WINDOW_CASES: (drive, fixed inputs, the drive
#: parameter that moves, the grid values on either side (outside, inside: one state and three),
#: the indices of the two states at the inside value that merge at the fold).
FOLDS: list[dict[str, Any]] = [
    {
        "base": dict(drive="pressure", omega2=0.0, eps=0.95, theta0=-1.2, pi=0.1, q=None),
        "param": "omega2",
        "outside": 0.42,
        "inside": 0.47,
        "merging": (1, 2),
    },
    {
        "base": dict(drive="pressure", omega2=0.0, eps=0.95, theta0=-1.2, pi=0.1, q=None),
        "param": "omega2",
        "outside": 0.58,
        "inside": 0.53,
        "merging": (0, 1),
    },
    {
        "base": dict(drive="flow", omega2=0.0, eps=0.8, theta0=-1.2, pi=None, q=0.0),
        "param": "q",
        "outside": 0.05,
        "inside": 0.09,
        "merging": (1, 2),
    },
    {
        "base": dict(drive="flow", omega2=0.0, eps=0.8, theta0=-1.2, pi=None, q=0.0),
        "param": "q",
        "outside": 0.3,
        "inside": 0.18,
        "merging": (0, 1),
    },
]


def _with_param(case: dict[str, Any], name: str, value: Any) -> dict[str, Any]:
    c = dict(case)
    c["_" + name] = value
    return c


def _fold_double(spec: dict[str, Any]) -> tuple[float, float, float]:
    """(parameter, h1, ln phi1) of the fold in double precision (DOP853, nested Brent)."""
    base = dict(spec["base"], label="fold")
    name = spec["param"]

    def at(value: float) -> dict[str, Any]:
        c = _float_inputs(dict(base, **{name: value}))
        c["_theta0"] = float(base["theta0"])
        return c

    inside = at(spec["inside"])
    states, _ = find_states(inside)
    i, j = spec["merging"]
    (ha, la), (hb, _) = states[i], states[j]
    sgn = 1.0 if i == 0 else -1.0  # G has a minimum between the pair (low, mid), else a max

    def extremum(value: float) -> tuple[float, float]:
        c = at(value)
        res = minimize_scalar(
            lambda v: sgn * _inner(c, v, la)[1],
            bounds=(ha - 0.02, hb + 0.02),
            method="bounded",
            options={"xatol": 1e-12},
        )
        return sgn * res.fun, res.x

    def g_ext(value: float) -> float:
        return extremum(value)[0]

    value = brentq(g_ext, spec["outside"], spec["inside"], xtol=1e-14, rtol=1e-14)
    h1 = extremum(value)[1]
    return value, h1, _inner(at(value), h1, la)[0]


def _fold_residual(case: dict[str, Any], name: str, xs: list[mpf], order: int):
    """(R1, R2, dG/dh1) at (ln phi1, h1, parameter) and the integration."""
    lnphi, h1, value = xs
    c = _with_param(case, name, value)
    w, big_pi, dw, dpi = loads(c, h1)
    phi1 = mp.exp(lnphi)
    r = taylor_tip(w, big_pi, dw, dpi, phi1, order, True)
    tip = r["at"][-1]
    j11, j21 = phi1 * r["d_phi1"][0], phi1 * r["d_phi1"][1]
    j12, j22 = r["d_h1"][0], r["d_h1"][1] - 1
    phi0 = mp.pi / 2 - c["_theta0"]
    res = [tip[0] - phi0, tip[2] - h1, (j11 * j22 - j12 * j21) / j11]
    return res, tip, (w, big_pi)


def _fold_newton(case: dict[str, Any], name: str, xs: list[mpf], order: int) -> list[mpf]:
    """Newton's method on (R1, R2, dG/dh1) = 0, the Jacobian by central differences."""
    step = mpf(10) ** (-(mp.dps // 3))
    tol = mpf(10) ** (-(mp.dps - 8))
    for _ in range(30):
        f0, _, _ = _fold_residual(case, name, xs, order)
        jac = mp.matrix(3, 3)
        for k in range(3):
            hk = step * max(1, abs(xs[k]))
            up = list(xs)
            dn = list(xs)
            up[k] += hk
            dn[k] -= hk
            fu = _fold_residual(case, name, up, order)[0]
            fd = _fold_residual(case, name, dn, order)[0]
            for i in range(3):
                jac[i, k] = (fu[i] - fd[i]) / (2 * hk)
        dx = mp.lu_solve(jac, mp.matrix(f0))
        xs = [xs[k] - dx[k] for k in range(3)]
        if max(abs(dx[k]) / max(1, abs(xs[k])) for k in range(3)) < tol:
            return xs
    raise RuntimeError(f"fold Newton did not converge at {xs}")


def compute_fold(spec: dict[str, Any]) -> dict[str, Any]:
    """One fold: its parameter value and state at DPS digits, checked at a second order."""
    start = time.time()
    value, h1, lnphi = _fold_double(spec)
    mp.dps = DPS
    base = spec["base"]
    case = _mp_inputs(dict(base, label="fold"))
    case["_theta0"] = mpf(base["theta0"])
    name = spec["param"]
    xs = _fold_newton(case, name, [mpf(lnphi), mpf(h1), mpf(value)], ORDERS[0])
    ys = _fold_newton(case, name, xs, ORDERS[1])
    change = max(_rel(a, b) for a, b in zip(xs, ys))
    res, tip, (w, big_pi) = _fold_residual(case, name, xs, ORDERS[0])
    lo, hi = sorted((spec["outside"], spec["inside"]))
    if change > ORDERS_TOL or not lo < xs[2] < hi or max(abs(r) for r in res) > RESIDUAL_TOL:
        raise RuntimeError(f"fold {spec}: change {change}, value {xs[2]}, residual {res}")
    m = tip[1]
    ident = abs(m - (w * xs[1] + big_pi * xs[1] ** 2 / 2)) / max(1, abs(m))
    if ident > IDENTITY_TOL:
        raise RuntimeError(f"fold {spec}: identity off by {ident}")
    inputs = {k: base[k] for k in ("drive", "omega2", "pi", "q", "eps", "theta0")}
    inputs[name] = None
    return {
        **inputs,
        "parameter": name,
        "value": _fmt(xs[2]),
        "window_side": "lower" if spec["inside"] > spec["outside"] else "upper",
        "tip_height": _fmt(xs[1]),
        "tip_deflection": _fmt(tip[3]),
        "tip_angle": _fmt(mp.pi / 2 - mp.exp(xs[0])),
        "base_curvature": _fmt(m),
        "W": _fmt(w),
        "Pi": _fmt(big_pi),
        "checks": {
            "orders": mp.nstr(change, 3),
            "residual": mp.nstr(max(abs(r) for r in res), 3),
            "identity": mp.nstr(ident, 3),
            "double_precision_value": value,
        },
        "seconds": round(time.time() - start, 1),
    }


def _key(case: dict[str, Any]) -> tuple:
    return tuple(case[k] for k in INPUT_KEYS)


INPUT_KEYS = ("drive", "omega2", "pi", "q", "eps", "theta0", "label")


def _write(
    path: Path, results: list[dict[str, Any]], seconds: float, folds: list | None = None
) -> int:
    """Write the cases computed so far (in the order of build_cases); the number of states."""
    n_states = sum(len(r["states"]) for r in results)
    worst = {
        key: max(float(r["checks"][key]) for r in results if r["checks"][key] is not None)
        for key in ("identity", "orders", "residual", "closed_form", "odefun")
        if any(r["checks"][key] is not None for r in results)
    }
    data = {
        "generator": "tests/reference/generate_loaded.py",
        "mpmath": mpmath.__version__,
        "date": datetime.date.today().isoformat(),
        "dps": DPS,
        "digits_written": OUT_DIGITS,
        "taylor_orders": list(ORDERS),
        "generation_seconds": round(seconds, 1),
        "n_cases": len(results),
        "n_states": n_states,
        "checks": (
            "every state: theta'(0) = W h1 + Pi h1^2/2 (worst {identity:.1e}); converged "
            "again with Taylor order {o1} instead of {o0}, every value agrees (worst "
            "{orders:.1e}); boundary residuals (worst {residual:.1e}); at pi = 0 the states, "
            "their count and shape equal the closed form of generate_reference.py (worst "
            "{closed:.1e}); where W + |Pi| h1 <= {omax}, mpmath.odefun from the base reproduces "
            "theta'(1) = 0, the tip and the shape (worst {odefun:.1e}). "
            "States: the fundamental family (-pi/2 < theta < pi/2, 0 < h1 <= 1), "
            "all of them, found by a scan in h1 (see the generator's docstring); stable: "
            "dG/dh1 < 0."
        ).format(
            identity=worst.get("identity", float("nan")),
            orders=worst.get("orders", float("nan")),
            residual=worst.get("residual", float("nan")),
            closed=worst.get("closed_form", float("nan")),
            odefun=worst.get("odefun", float("nan")),
            omax=ODEFUN_MAX_LOAD,
            o0=ORDERS[0],
            o1=ORDERS[1],
        ),
        "cases": results,
        "folds": folds or [],
        "folds_note": (
            "the folds bounding the two windows: parameter (omega2 or q, null among the inputs) "
            "at which the two states of the window that merge there coincide, solved as "
            "(phi(1) = pi/2 - theta0, zeta(1) = h1, dG/dh1 = 0) by Newton's method in mpmath "
            "from a double-precision estimate, re-converged at the second Taylor order"
        ),
    }
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1) + "\n")
    tmp.replace(path)
    return n_states


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    parser.add_argument("--quick", action="store_true", help="a few cases (a smoke test)")
    parser.add_argument(
        "--resume",
        action="store_true",
        help="keep the cases already in --out (same inputs and generator) and compute the rest",
    )
    args = parser.parse_args(argv)
    cases = build_cases(args.quick)
    done: dict[tuple, dict[str, Any]] = {}
    previous = 0.0
    if args.resume and args.out.exists():
        old = json.loads(args.out.read_text())
        done = {_key(r): r for r in old["cases"]}
        previous = old.get("generation_seconds", 0.0)
    todo = [c for c in cases if _key(c) not in done]
    start = time.time()
    with multiprocessing.Pool(args.workers) as pool:
        for k, res in enumerate(pool.imap_unordered(compute_case, todo, chunksize=1)):
            done[_key(res)] = res
            print(
                f"[{k + 1}/{len(todo)}] {res['drive']} {res['label']}: "
                f"{len(res['states'])} state(s), {res['seconds']} s",
                flush=True,
            )
            partial = [done[_key(c)] for c in cases if _key(c) in done]
            _write(args.out, partial, previous + time.time() - start)
        results = [done[_key(c)] for c in cases]
        folds = [] if args.quick else pool.map(compute_fold, FOLDS, chunksize=1)
    for f, value in zip(folds, FOLD_VALUES):
        if abs(float(f["value"]) - value) > 1e-12 * value:
            raise RuntimeError(f"FOLD_VALUES is stale: {value} but the fold is at {f['value']}")
    n_states = _write(args.out, results, previous + time.time() - start, folds)
    print(f"wrote {args.out}: {len(results)} cases, {n_states} states, {len(folds)} folds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
