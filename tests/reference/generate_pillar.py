"""Generate ``tests/data/pillar_mpmath.json``: isolated pillars in a shear layer (issue 21).

Run on demand (minutes on two cores)::

    .venv/bin/python tests/reference/generate_pillar.py [--workers 2] [--out PATH] [--quick]

It imports nothing from :mod:`hairbed` and shares no code with its solver: the equations are
written here from docs/theory.md §12. With s in [0, 1], lengths in L, forces in E I / L^2::

    theta' = m,                         m'   = -(F_x cos theta - F_z sin theta),
    F_x'   = -Lambda U(z) (cos^2 theta + gamma sin^2 theta),
    F_z'   =  Lambda U(z) (1 - gamma) sin theta cos theta,
    x'     = sin theta,                 z'   = cos theta,
    theta(0) = theta0,  x(0) = z(0) = 0,  m(1) = F_x(1) = F_z(1) = 0,

the resistive-force load f = zeta_perp (u.n) n + zeta_par (u.t) t of the undisturbed flow
u = (U(z), 0) on the pillar at rest, t = (sin theta, cos theta), n = (cos theta, -sin theta),
gamma = zeta_par/zeta_perp, F(s) = int_s^1 f. The profiles U (dimensionless, U'(0) = 1 for
the built-in ones, so that Lambda = zeta_perp tau_w L^4/(eta E I) for all three):

    "sublayer":    U = z
    "couette":     U = z               (tau_w = eta V/H; the pillar stays below H: L/H <= 1)
    "poiseuille":  U = z - (L/H) z^2   (tau_w = G H/2)
    "callable":    U = z^2             (u = U_0 (z/L)^2, Lambda = zeta_perp U_0 L^3/(E I))

Method
------
Shooting from the base, as the issue asks: unknowns m(0), F_x(0), F_z(0), residuals m(1),
F_x(1), F_z(1). Under tension T = F.t the base has a boundary layer of width T^(-1/2) and an
error at the base grows by up to exp(int sqrt(T) ds) (about 1e5 at Lambda = 1e4); the working
precision is raised by that many digits (estimated from the double-precision guess), so the
written values keep ``OUT_DIGITS`` digits.

* Guess (double precision, scipy): pseudo-arclength continuation of the shooting problem in
  (m0, F_x0, F_z0, ln Lambda) from Lambda = 1e-3 (DOP853, rtol 1e-12) up to
  ``CONT_MAX``; every crossing of a requested Lambda on the branch is a state (several inside a
  fold window), and the sign of det(d residual / d unknowns) is recorded along it (a change is
  a fold). Beyond ``CONT_MAX`` the last state is continued in ln Lambda (natural
  continuation, the same shooting). Below Lambda = 1e-3 the linear state is the guess.
* Refinement (mpmath): Newton's method, Jacobian by finite differences at the working
  precision (step 10^(-dps/2)), reused while it contracts. The integrator is a Taylor series
  method with exact recurrences (S = sin theta, C = cos theta: S' = C m, C' = -S m; every
  right-hand side is a product of series), steps from the last two coefficients relative to
  max(1, |y|), landing exactly on the shape points s = j/8.
* Inverse cases: Lambda is a fourth unknown with the condition x(1) = x1 (given).

Checks (the generator stops rather than write a value that fails one):

1. identity: theta'(0) = int_0^1 (z f_x - x f_z) ds (integrated alongside as a seventh
   equation) to ``IDENTITY_TOL``, relative to max(1, |theta'(0)|);
2. resolutions: every state re-converged with a second Taylor order and tolerance
   (``ORDERS``), so different steps; every written value agrees to ``RESOLUTION_TOL``
   (relative to max(1, |value|));
3. residuals of the boundary conditions below ``RESIDUAL_TOL`` relative to the load scale;
4. the small-Lambda limit: at theta0 = 0, Lambda <= 1e-3, x1 agrees with the closed form
   Lambda int_0^1 U(s) s^2 (3 - s)/6 ds (11/120 for U = z) to a relative
   ``LINEAR_REL * Lambda`` (the remainder is O(Lambda^2));
5. the inverse: the forward state at the found Lambda has the given x1 to ``INVERSE_TOL``.

Numbers are written as strings with ``OUT_DIGITS`` significant digits; the inputs theta0 and
Lambda are the JSON numbers (binary doubles, converted exactly); gamma is a decimal string.
"""

from __future__ import annotations

import argparse
import datetime
import hashlib
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

__all__ = ["build_cases", "compute_group", "compute_inverse", "main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "pillar_mpmath.json"
#: Base working precision [decimal digits]; raised by the amplification digits per case.
DPS = 40
#: Significant digits written out.
OUT_DIGITS = 30
#: (Taylor order, step tolerance exponent offset) of the two resolutions (check 2).
ORDERS = ((30, 4), (42, 8))
IDENTITY_TOL = mpf("1e-25")
RESOLUTION_TOL = mpf("1e-20")
RESIDUAL_TOL = mpf("1e-30")
INVERSE_TOL = mpf("1e-25")
LINEAR_REL = 2.0
#: Shape points s = j/SHAPE_N.
SHAPE_N = 8
#: Largest Lambda reached by the double-precision arclength continuation.
CONT_MAX = 300.0
#: The slenderness L/a of the Gray & Hancock pair used for the second gamma.
SLENDERNESS = 20

#: The double-precision profiles U(z) as (a1, a2): U = a1 z + a2 z^2, given the parameters.


def profile_coefficients(profile: str, params: dict[str, Any]) -> tuple[Any, Any]:
    """(a1, a2) with U(z) = a1 z + a2 z^2 (strings or floats in params are exact decimals)."""
    if profile in ("sublayer", "couette"):
        return 1, 0
    if profile == "poiseuille":
        return 1, -mpf(params["L/H"])
    if profile == "callable":
        return 0, 1
    raise ValueError(profile)


def gray_hancock_gamma(slenderness: int) -> mpf:
    """zeta_par/zeta_perp of Gray & Hancock (1955), lambda -> L.

    (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1).
    """
    lg = mp.log(2 * mpf(slenderness))
    return (lg + mpf(1) / 2) / (2 * lg - 1)


# ------------------------------------------------------------------------------------------
# Double precision: guesses and the fold scan
# ------------------------------------------------------------------------------------------


def _rhs_float(a1: float, a2: float, gam: float):
    def rhs(_s, y, lam):
        th, m, fx, fz, _x, z = y
        c, sn = math.cos(th), math.sin(th)
        u = a1 * z + a2 * z * z
        return [
            m,
            -(fx * c - fz * sn),
            -lam * u * (c * c + gam * sn * sn),
            lam * u * (1 - gam) * sn * c,
            sn,
            c,
        ]

    return rhs


def _shoot_float(case: dict[str, Any], v: np.ndarray, dense: bool = False):
    rhs = _rhs_float(case["_a1"], case["_a2"], case["_gamma"])
    sol = solve_ivp(
        rhs,
        (0.0, 1.0),
        [case["_theta0"], v[0], v[1], v[2], 0.0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
        args=(math.exp(v[3]),),
        dense_output=dense,
    )
    return sol


def _res_float(case: dict[str, Any], v: np.ndarray) -> np.ndarray:
    y = _shoot_float(case, v).y[:, -1]
    return np.array([y[1], y[2], y[3]])


def _jac_float(case: dict[str, Any], v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r0 = _res_float(case, v)
    jac = np.zeros((3, 4))
    for i in range(4):
        d = np.zeros(4)
        h = 1e-7 * max(1.0, abs(v[i]))
        d[i] = h
        jac[:, i] = (_res_float(case, v + d) - r0) / h
    return r0, jac


def linear_guess(case: dict[str, Any], lam: float) -> np.ndarray:
    """(m0, F_x0, F_z0) of the straight tilted pillar under the load (first order)."""
    th0, a1, a2, gam = case["_theta0"], case["_a1"], case["_a2"], case["_gamma"]
    c, sn = math.cos(th0), math.sin(th0)
    # U(s c) = a1 c s + a2 c^2 s^2;  f = Lambda U (c^2 + g s^2, -(1-g) s c)
    i1 = a1 * c / 2 + a2 * c * c / 3  # int_0^1 U
    i2 = a1 * c / 3 + a2 * c * c / 4  # int_0^1 U s
    fxs = lam * (c * c + gam * sn * sn)
    fzs = -lam * (1 - gam) * sn * c
    fx0, fz0 = fxs * i1, fzs * i1
    m0 = c * fxs * i2 - sn * fzs * i2  # int (z f_x - x f_z) = int s (c f_x - sn f_z)
    return np.array([m0, fx0, fz0])


def continue_branch(case: dict[str, Any], targets: list[float]) -> dict[str, Any]:
    """Arclength continuation in ln Lambda; the states at the targets and the folds."""
    lam0 = 1e-3
    v = np.concatenate([linear_guess(case, lam0), [math.log(lam0)]])
    for _ in range(8):
        r, jac = _jac_float(case, v)
        v[:3] += np.linalg.solve(jac[:, :3], -r)
        if np.max(np.abs(r)) < 1e-14:
            break
    _, jac = _jac_float(case, v)
    tvec = np.linalg.svd(jac)[2][-1]
    if tvec[3] < 0:
        tvec = -tvec
    det = np.linalg.det(jac[:, :3])
    path = [(v.copy(), det)]
    ds = 0.25
    lmax = math.log(CONT_MAX * 1.05)
    steps = 0
    while v[3] < lmax and steps < 600:
        steps += 1
        vp = v + ds * tvec
        ok = False
        for _ in range(10):
            r, jac = _jac_float(case, vp)
            a = np.vstack([jac, tvec])
            b = np.concatenate([-r, [ds - (vp - v) @ tvec]])
            dv = np.linalg.solve(a, b)
            vp = vp + dv
            if np.linalg.norm(dv) < 1e-11 * max(1.0, np.linalg.norm(vp)):
                ok = True
                break
        if not ok:
            ds /= 2
            if ds < 1e-6:
                raise RuntimeError(f"{case['label']}: continuation stalls at {v}")
            continue
        _, jac = _jac_float(case, vp)
        tn = np.linalg.svd(jac)[2][-1]
        if tn @ tvec < 0:
            tn = -tn
        v, tvec = vp, tn
        path.append((v.copy(), np.linalg.det(jac[:, :3])))
        ds = min(ds * 1.3, 0.4)
    folds = []
    for (va, da), (vb, db) in zip(path[:-1], path[1:]):
        if da * db < 0:
            folds.append(float(math.exp((va[3] + vb[3]) / 2)))
    states: dict[float, list[np.ndarray]] = {}
    for lam in targets:
        if lam < lam0:
            states[lam] = [linear_guess(case, lam)]
            continue
        if lam > math.exp(path[-1][0][3]):
            continue
        ll = math.log(lam)
        found = []
        for (va, _), (vb, _) in zip(path[:-1], path[1:]):
            if (va[3] - ll) * (vb[3] - ll) <= 0 and va[3] != vb[3]:
                t = (ll - va[3]) / (vb[3] - va[3])
                g = va[:3] + t * (vb[:3] - va[:3])
                w = np.concatenate([g, [ll]])
                for _ in range(10):
                    r, jac = _jac_float(case, w)
                    w[:3] += np.linalg.solve(jac[:, :3], -r)
                found.append(w[:3].copy())
        uniq: list[np.ndarray] = []
        for g in found:
            if all(np.max(np.abs(g - q)) > 1e-6 * max(1.0, np.max(np.abs(q))) for q in uniq):
                uniq.append(g)
        states[lam] = uniq
    return {"path": path, "folds": folds, "states": states}


def shoot_continue(case: dict[str, Any], v: np.ndarray, lam_from: float, lam_to: float):
    """Natural continuation of the shooting problem in ln Lambda from lam_from to lam_to.

    Steps of at most 0.2 in ln Lambda with a secant predictor and Newton's method (Jacobian
    by finite differences); beyond ``CONT_MAX`` the base amplification (below exp(13) up to
    Lambda = 1e4 here) still leaves the double-precision guess good to about 1e-10.
    """
    ll, target = math.log(lam_from), math.log(lam_to)
    prev = None
    cur = np.array(v, dtype=float)
    step = 0.2
    while ll < target - 1e-15:
        h = min(step, target - ll)
        guess = cur if prev is None else cur + (cur - prev[0]) * h / (ll - prev[1])
        w = np.concatenate([guess, [ll + h]])
        ok = False
        for _ in range(20):
            r, jac = _jac_float(case, w)
            dv = np.linalg.solve(jac[:, :3], -r)
            w[:3] += dv
            if np.max(np.abs(dv)) < 1e-10 * max(1.0, np.max(np.abs(w[:3]))):
                ok = True
                break
        if not ok:
            step /= 2
            if step < 1e-4:
                raise RuntimeError(f"{case['label']}: continuation stalls at Lambda = {ll}")
            continue
        prev = (cur, ll)
        cur, ll = w[:3].copy(), ll + h
    return cur, amplification(case, cur, lam_to)


def amplification(case: dict[str, Any], v: np.ndarray, lam: float) -> float:
    """int_0^1 sqrt(max(T, 0)) ds, T = F.t, along the double-precision shot."""
    sol = _shoot_float(case, np.concatenate([v, [math.log(lam)]]), dense=True)
    s = np.linspace(0.0, 1.0, 2001)
    y = sol.sol(s)
    t = y[2] * np.sin(y[0]) + y[3] * np.cos(y[0])
    return float(np.trapezoid(np.sqrt(np.maximum(t, 0.0)), s))


# ------------------------------------------------------------------------------------------
# Taylor-series integration in mpmath
# ------------------------------------------------------------------------------------------


def _dot(a: list[mpf], b: list[mpf], k: int) -> mpf:
    """sum_{j=0}^{k} a_j b_{k-j}."""
    return mp.fdot(a[: k + 1], b[k::-1])


def taylor_shoot(
    theta0: mpf,
    lam: mpf,
    gam: mpf,
    a1: Any,
    a2: Any,
    y0: list[mpf],
    order: int,
    tol_offset: int,
) -> dict[str, Any]:
    """Integrate (theta, m, F_x, F_z, x, z, M) from s = 0 to 1, y0 = (m0, F_x0, F_z0).

    M is the moment integral int_0^s (z f_x - x f_z). Returns the states at s = j/SHAPE_N.
    """
    nn = order
    eps = mpf(10) ** (-(mp.dps + tol_offset))
    g1 = 1 - gam
    y = [theta0, y0[0], y0[1], y0[2], mpf(0), mpf(0), mpf(0)]
    marks = [mpf(j) / SHAPE_N for j in range(1, SHAPE_N + 1)]
    out = [list(y)]
    s = mpf(0)
    steps = 0
    zero = mpf(0)
    while marks:
        th = [y[0]] + [zero] * nn
        m = [y[1]] + [zero] * nn
        fx = [y[2]] + [zero] * nn
        fz = [y[3]] + [zero] * nn
        xx = [y[4]] + [zero] * nn
        zz = [y[5]] + [zero] * nn
        mm = [y[6]] + [zero] * nn
        ss = [mp.sin(y[0])] + [zero] * nn
        cc = [mp.cos(y[0])] + [zero] * nn
        uu = [zero] * nn
        q = [zero] * nn  # S^2
        sc = [zero] * nn  # S C
        for k in range(nn):
            k1 = k + 1
            z2 = _dot(zz, zz, k) if a2 else zero
            uu[k] = (a1 * zz[k] if a1 else zero) + (a2 * z2 if a2 else zero)
            q[k] = _dot(ss, ss, k)
            sc[k] = _dot(ss, cc, k)
            uq = _dot(uu, q, k)
            usc = _dot(uu, sc, k)
            fxk = lam * (uu[k] - g1 * uq)
            fzk = -lam * g1 * usc
            th[k1] = m[k] / k1
            m[k1] = -(_dot(fx, cc, k) - _dot(fz, ss, k)) / k1
            fx[k1] = -fxk / k1
            fz[k1] = -fzk / k1
            xx[k1] = ss[k] / k1
            zz[k1] = cc[k] / k1
            ss[k1] = _dot(cc, m, k) / k1
            cc[k1] = -_dot(ss, m, k) / k1
            # M' = z f_x - x f_z: needs f_x, f_z series up to k; store them
            if k == 0:
                fxs = [fxk]
                fzs = [fzk]
            else:
                fxs.append(fxk)
                fzs.append(fzk)
            mm[k1] = (_dot(zz, fxs, k) - _dot(xx, fzs, k)) / k1
        series = (th, m, fx, fz, xx, zz, mm)
        h = mpf(1)
        for ser in series:
            scale = max(mpf(1), abs(ser[0]))
            for j in (nn - 1, nn):
                cj = abs(ser[j])
                if cj > 0:
                    h = min(h, (eps * scale / cj) ** (mpf(1) / j))
        h = h * mpf("0.9")
        land = False
        if s + h >= marks[0]:
            h = marks[0] - s
            land = True
        y = [mp.polyval(ser[::-1], h) for ser in series]
        s = marks[0] if land else s + h
        steps += 1
        if land:
            out.append(list(y))
            marks.pop(0)
        if steps > 200000:
            raise RuntimeError("Taylor integration: too many steps")
    return {"nodes": out, "steps": steps}


def residual_mp(case: dict[str, Any], unk: list[mpf], lam: mpf, order: int, off: int):
    r = taylor_shoot(
        case["m_theta0"], lam, case["m_gamma"], case["m_a1"], case["m_a2"], unk, order, off
    )
    end = r["nodes"][-1]
    return [end[1], end[2], end[3]], r


def newton_mp(
    case: dict[str, Any],
    unk: list[mpf],
    lam: mpf,
    order: int,
    off: int,
    inverse_x1: mpf | None = None,
) -> tuple[list[mpf], mpf, dict[str, Any]]:
    """Newton with a finite-difference Jacobian (reused while it contracts)."""
    n = 3 if inverse_x1 is None else 4
    lnlam = mp.log(lam)

    def full(v: list[mpf]):
        lm = mp.exp(v[3]) if n == 4 else lam
        res, r = residual_mp(case, v[:3], lm, order, off)
        if n == 4:
            res = res + [r["nodes"][-1][4] - inverse_x1]
        return res, r

    v = list(unk) + ([lnlam] if n == 4 else [])
    res, r = full(v)
    jac = None
    scale = max(mpf(1), max(abs(q) for q in v))
    last = None
    for _it in range(30):
        nrm = max(abs(q) for q in res)
        if nrm < mpf(10) ** (-(mp.dps - 2)) * scale:
            break
        if jac is None or (last is not None and nrm > last * mpf("1e-3")):
            hstep = mpf(10) ** (-(mp.dps // 2))
            cols = []
            for i in range(n):
                w = list(v)
                dh = hstep * max(mpf(1), abs(v[i]))
                w[i] += dh
                ri, _ = full(w)
                cols.append([(ri[j] - res[j]) / dh for j in range(n)])
            jac = mpmath.matrix(n, n)
            for i in range(n):
                for j in range(n):
                    jac[j, i] = cols[i][j]
        dv = mpmath.lu_solve(jac, mpmath.matrix([-q for q in res]))
        v = [v[i] + dv[i] for i in range(n)]
        last = nrm
        res, r = full(v)
    else:
        raise RuntimeError(f"{case['label']}: Newton does not converge ({nrm})")
    lam_out = mp.exp(v[3]) if n == 4 else lam
    return v[:3], lam_out, r


# ------------------------------------------------------------------------------------------
# Cases
# ------------------------------------------------------------------------------------------


def build_cases(quick: bool = False) -> list[dict[str, Any]]:
    """The forward groups (profile, params, gamma, theta0) with their Lambda values."""
    g_gh = mp.nstr(gray_hancock_gamma(SLENDERNESS), 40)
    half = "0.5"
    lams_full = [1e-6, 1e-3, 0.3, 3.0, 30.0, 300.0, 1e4]
    groups: list[dict[str, Any]] = []

    def add(profile, params, gamma, theta0, lams):
        groups.append(
            {
                "profile": profile,
                "profile_parameters": params,
                "gamma": gamma,
                "theta0": theta0,
                "lams": lams,
            }
        )

    if quick:
        add("sublayer", {}, half, 0.0, [1e-6, 1.0, 30.0])
        add("poiseuille", {"L/H": 0.5}, g_gh, 0.7, [1.0])
        add("sublayer", {}, half, -1.4, [15.0])
        return groups
    add("sublayer", {}, half, 0.0, lams_full[:-1])
    add("sublayer", {}, g_gh, 0.0, [1e-6, 1e-4, 1e-3, 1.0, 100.0, 300.0])
    add("sublayer", {}, half, 1.4, [1e-3, 1.0, 100.0, 1e4])
    add("sublayer", {}, g_gh, -0.7, [1e-3, 1.0, 30.0, 1e3])
    add("sublayer", {}, half, -1.4, [1e-3, 3.0, 15.0, 100.0])
    add("couette", {"L/H": 0.8}, g_gh, 0.3, [1e-6, 1.0, 300.0])
    add("poiseuille", {"L/H": 0.5}, half, 0.0, [1e-6, 1e-3, 3.0, 1e3])
    add("poiseuille", {"L/H": 1.0}, g_gh, -1.0, [1e-2, 10.0, 300.0])
    add("callable", {"u": "z**2"}, half, 0.0, [1e-6, 1e-3, 10.0, 1e3])
    add("callable", {"u": "z**2"}, g_gh, 1.0, [0.1, 100.0])
    # fold scan only (no states written): where the upstream-tilted pillar snaps through
    for th0 in (-1.25, -1.3, -1.35):
        add("sublayer", {}, half, th0, [])
    add("sublayer", {}, g_gh, -1.4, [])
    add("sublayer", {}, g_gh, -1.3, [])
    return groups


INVERSE = [
    # (profile, params, gamma key, theta0, target x1)
    ("sublayer", {}, "half", 0.0, "0.1"),
    ("sublayer", {}, "half", 0.0, "0.5"),
    ("sublayer", {}, "gh", 0.0, "0.9"),
    ("sublayer", {}, "gh", 0.5, "0.8"),
    ("poiseuille", {"L/H": 0.5}, "half", 0.0, "0.3"),
    ("couette", {"L/H": 0.8}, "gh", -0.5, "0.2"),
    ("callable", {"u": "z**2"}, "half", 0.0, "0.4"),
]


def _prepare(group: dict[str, Any]) -> dict[str, Any]:
    c = dict(group)
    c["label"] = f"{group['profile']} g={group['gamma'][:6]} th0={group['theta0']}"
    a1, a2 = profile_coefficients(group["profile"], group["profile_parameters"])
    c["_a1"], c["_a2"] = float(a1), float(a2)
    c["_gamma"] = float(mpf(group["gamma"]))
    c["_theta0"] = float(group["theta0"])
    return c


def _mp_setup(c: dict[str, Any]) -> None:
    a1, a2 = profile_coefficients(c["profile"], c["profile_parameters"])
    c["m_a1"] = mpf(a1)
    c["m_a2"] = mpf(a2)
    c["m_gamma"] = mpf(c["gamma"])
    c["m_theta0"] = mpf(c["theta0"])


def _s(v: mpf) -> str:
    return mp.nstr(v, OUT_DIGITS, strip_zeros=False, min_fixed=-4, max_fixed=6) if v != 0 else "0"


def linear_tip(c: dict[str, Any], lam: mpf) -> mpf:
    """x1 of the linear theory at theta0 = 0: Lambda int_0^1 U(s) s^2 (3 - s)/6 ds."""
    a1, a2 = c["m_a1"], c["m_a2"]
    return lam * (a1 * mpf(11) / 120 + a2 * mpf(13) / 180)


def _state_record(
    c: dict[str, Any], lam: mpf, unk: list[mpf], r: dict[str, Any]
) -> dict[str, Any]:
    nodes = r["nodes"]
    end = nodes[-1]
    return {
        "tip_deflection": end[4],
        "tip_height": end[5],
        "tip_angle": end[0],
        "base_curvature": unk[0],
        "drag_x": unk[1],
        "drag_z": unk[2],
        "moment_integral": end[6],
        "shape_x": [q[4] for q in nodes],
        "shape_z": [q[5] for q in nodes],
        "shape_theta": [q[0] for q in nodes],
        "residual": max(abs(end[1]), abs(end[2]), abs(end[3])),
        "steps": r["steps"],
    }


def _compare(a: dict[str, Any], b: dict[str, Any], label: str) -> mpf:
    worst = mpf(0)
    for k in ("tip_deflection", "tip_height", "tip_angle", "base_curvature", "drag_x", "drag_z"):
        d = abs(a[k] - b[k]) / max(mpf(1), abs(a[k]))
        worst = max(worst, d)
    for k in ("shape_x", "shape_z", "shape_theta"):
        for p, q in zip(a[k], b[k]):
            worst = max(worst, abs(p - q) / max(mpf(1), abs(p)))
    if worst > RESOLUTION_TOL:
        raise RuntimeError(f"{label}: two resolutions differ by {mp.nstr(worst, 3)}")
    return worst


def solve_state(
    c: dict[str, Any], lam_f: float, guess: np.ndarray, amp: float, inverse_x1: str | None = None
) -> dict[str, Any]:
    """Refine one state (or one inverse case) at both resolutions and check it."""
    extra = int(math.ceil(amp / math.log(10) * 1.2)) + 4
    mp.dps = DPS + extra
    _mp_setup(c)
    lam = mpf(lam_f)
    unk = [mpf(float(q)) for q in guess]
    x1t = mpf(inverse_x1) if inverse_x1 is not None else None
    recs = []
    lams = []
    for order, off in ORDERS:
        unk, lam_o, r = newton_mp(c, unk, lam, order, off, x1t)
        recs.append(_state_record(c, lam_o, unk, r))
        lams.append(lam_o)
        lam = lam_o
    label = f"{c['label']} Lambda={lam_f}"
    worst = _compare(recs[0], recs[1], label)
    if x1t is not None:
        dl = abs(lams[0] - lams[1]) / lams[1]
        if dl > RESOLUTION_TOL:
            raise RuntimeError(f"{label}: inverse Lambda differs by {dl}")
        worst = max(worst, dl)
    rec = recs[1]
    ident = abs(rec["base_curvature"] - rec["moment_integral"]) / max(
        mpf(1), abs(rec["base_curvature"])
    )
    if ident > IDENTITY_TOL:
        raise RuntimeError(f"{label}: base-moment identity off by {ident}")
    load = max(mpf(1), abs(rec["drag_x"]), abs(rec["drag_z"]))
    if rec["residual"] > RESIDUAL_TOL * load:
        raise RuntimeError(f"{label}: residual {rec['residual']}")
    lin = None
    if c["theta0"] == 0.0 and lam_f <= 1e-3 and x1t is None:
        xl = linear_tip(c, lam)
        rel = abs(rec["tip_deflection"] - xl) / xl
        if rel > LINEAR_REL * lam:
            raise RuntimeError(f"{label}: linear limit off by {rel}")
        lin = rel
    inv = None
    if x1t is not None:
        inv = abs(rec["tip_deflection"] - x1t)
        if inv > INVERSE_TOL:
            raise RuntimeError(f"{label}: inverse x1 off by {inv}")
    rec["_checks"] = {
        "dps": mp.dps,
        "identity": ident,
        "resolution": worst,
        "linear": lin,
        "inverse": inv,
        "steps": (recs[0]["steps"], recs[1]["steps"]),
    }
    rec["_lam"] = lams[1]
    return rec


def _out_case(
    c: dict[str, Any], rec: dict[str, Any], lam_f: float, index: int, count: int
) -> dict[str, Any]:
    s_list = [_s(mpf(j) / SHAPE_N) for j in range(SHAPE_N + 1)]
    return {
        "profile": c["profile"],
        "profile_parameters": c["profile_parameters"],
        "gamma": c["gamma"],
        "theta0": c["theta0"],
        "forcing": lam_f,
        "state_index": index,
        "states_at_forcing": count,
        "tip_deflection": _s(rec["tip_deflection"]),
        "tip_height": _s(rec["tip_height"]),
        "tip_angle": _s(rec["tip_angle"]),
        "base_curvature": _s(rec["base_curvature"]),
        "drag_x": _s(rec["drag_x"]),
        "drag_z": _s(rec["drag_z"]),
        "shape": {
            "s": s_list,
            "x": [_s(v) for v in rec["shape_x"]],
            "z": [_s(v) for v in rec["shape_z"]],
            "theta": [_s(v) for v in rec["shape_theta"]],
        },
        "checks": {
            "dps": rec["_checks"]["dps"],
            "identity": mp.nstr(rec["_checks"]["identity"], 3),
            "resolution": mp.nstr(rec["_checks"]["resolution"], 3),
            "linear_rel": None
            if rec["_checks"]["linear"] is None
            else mp.nstr(rec["_checks"]["linear"], 6),
            "taylor_steps": list(rec["_checks"]["steps"]),
        },
    }


def compute_group(group: dict[str, Any]) -> dict[str, Any]:
    """Every state of one (profile, gamma, theta0) group at its Lambda values."""
    t0 = time.time()
    c = _prepare(group)
    lams = group["lams"]
    small = [lam for lam in lams if lam <= CONT_MAX]
    big = [lam for lam in lams if lam > CONT_MAX]
    br = continue_branch(c, small + [CONT_MAX])
    out = []
    for lam in small:
        guesses = br["states"][lam]
        if not guesses:
            raise RuntimeError(f"{c['label']}: no state at Lambda = {lam}")
        for i, g in enumerate(guesses):
            amp = amplification(c, g, lam)
            rec = solve_state(c, lam, g, amp)
            out.append(_out_case(c, rec, lam, i, len(guesses)))
    if big:
        prev_v, prev_l = br["states"][CONT_MAX][-1], CONT_MAX
        if len(br["states"][CONT_MAX]) != 1:
            raise RuntimeError(f"{c['label']}: several states at {CONT_MAX}")
        for lam in big:
            g, amp = shoot_continue(c, prev_v, prev_l, lam)
            rec = solve_state(c, lam, g, amp)
            out.append(_out_case(c, rec, lam, 0, 1))
    mp.dps = 30
    return {
        "cases": out,
        "folds": {
            "label": c["label"],
            "profile": c["profile"],
            "gamma": c["gamma"],
            "theta0": c["theta0"],
            "folds_near_forcing": br["folds"],
            "continued_to": float(math.exp(br["path"][-1][0][3])),
        },
        "seconds": time.time() - t0,
    }


def compute_inverse(item: tuple) -> dict[str, Any]:
    profile, params, gkey, theta0, x1 = item
    gamma = "0.5" if gkey == "half" else mp.nstr(gray_hancock_gamma(SLENDERNESS), 40)
    c = _prepare(
        {"profile": profile, "profile_parameters": params, "gamma": gamma, "theta0": theta0}
    )
    # find Lambda by the double continuation: x1(Lambda) along the branch (monotone here)
    br = continue_branch(c, [CONT_MAX])
    xs, ls, vs = [], [], []
    for v, _ in br["path"]:
        y = _shoot_float(c, v).y[:, -1]
        xs.append(y[4])
        ls.append(v[3])
        vs.append(v)
    xt = float(x1)
    idx = [i for i in range(len(xs) - 1) if (xs[i] - xt) * (xs[i + 1] - xt) <= 0]
    if len(idx) != 1:
        raise RuntimeError(f"{c['label']}: x1 = {x1} is reached {len(idx)} times on the branch")
    i = idx[0]
    t = (xt - xs[i]) / (xs[i + 1] - xs[i])
    v = vs[i] + t * (vs[i + 1] - vs[i])
    lam_g = math.exp(v[3])
    amp = amplification(c, v[:3], lam_g)
    rec = solve_state(c, lam_g, v[:3], amp, inverse_x1=x1)
    res = _out_case(c, rec, lam_g, 0, 1)
    res["forcing"] = _s(rec["_lam"])
    res["given_tip_deflection"] = x1
    res["checks"]["inverse"] = mp.nstr(rec["_checks"]["inverse"], 3)
    mp.dps = 30
    return res


def _job_key(job: tuple[str, Any]) -> str:
    text = json.dumps(job, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _run(arg: tuple[tuple[str, Any], str | None]) -> tuple[str, Any]:
    """One job; its result is cached (``--cache``) so that a rerun skips it."""
    job, cache = arg
    kind, item = job
    path = Path(cache) / f"{_job_key(job)}.json" if cache else None
    if path is not None and path.exists():
        return kind, json.loads(path.read_text())
    try:
        res = compute_group(item) if kind == "group" else compute_inverse(item)
    except Exception as exc:  # reported by main, which then writes nothing
        return "error", f"{kind} {item}: {type(exc).__name__}: {exc}"
    if path is not None:
        path.write_text(json.dumps(res))
    return kind, res


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    parser.add_argument("--quick", action="store_true", help="a few cases (smoke test)")
    parser.add_argument(
        "--cache",
        type=Path,
        default=None,
        help="directory keeping each finished job, so that a rerun skips it",
    )
    args = parser.parse_args(argv)
    t0 = time.time()
    groups = build_cases(args.quick)
    groups.sort(key=lambda g: -max(g["lams"] + [0.0]))  # the longest first
    jobs: list[tuple[str, Any]] = [("group", g) for g in groups]
    inv = INVERSE[:2] if args.quick else INVERSE
    jobs += [("inverse", it) for it in inv]
    cache = None
    if args.cache is not None:
        args.cache.mkdir(parents=True, exist_ok=True)
        cache = str(args.cache)
    work = [(j, cache) for j in jobs]
    if args.workers > 1:
        with multiprocessing.Pool(args.workers) as pool:
            results = list(pool.imap(_run, work, chunksize=1))
    else:
        results = [_run(w) for w in work]
    errors = [res for kind, res in results if kind == "error"]
    if errors:
        for e in errors:
            print("FAILED:", e, file=sys.stderr)
        raise SystemExit(f"{len(errors)} job(s) failed: nothing written")
    cases, folds, inverse = [], [], []
    for kind, res in results:
        if kind == "group":
            cases.extend(res["cases"])
            folds.append(res["folds"])
            print(
                f"{res['folds']['label']}: {len(res['cases'])} states, {res['seconds']:.0f} s",
                flush=True,
            )
        else:
            inverse.append(res)
    data = {
        "generator": "tests/reference/generate_pillar.py",
        "generated": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "mpmath": mpmath.__version__,
        "dps": DPS,
        "out_digits": OUT_DIGITS,
        "equations": (
            "theta'' = -(F_x cos theta - F_z sin theta), F' = -f, "
            "f = Lambda U(z) [cos^2 theta + gamma sin^2 theta, "
            "-(1 - gamma) sin theta cos theta], "
            "theta(0) = theta0, theta'(1) = 0, F(1) = 0; docs/theory.md section 12"
        ),
        "profiles": {
            "sublayer": "U = z",
            "couette": "U = z (forcing by the wall stress eta V/H)",
            "poiseuille": "U = z - (L/H) z^2 (forcing by the wall stress G H/2)",
            "callable": "U = z**2",
        },
        "gray_hancock": {
            "slenderness": SLENDERNESS,
            "gamma": mp.nstr(gray_hancock_gamma(SLENDERNESS), 40),
        },
        "checks": {
            "identity": "base_curvature = int_0^1 (z f_x - x f_z) ds to 1e-25",
            "resolutions": f"Taylor orders/tolerances {list(ORDERS)} agree to 1e-20",
            "residual": "m(1), F_x(1), F_z(1) below 1e-30 times the load",
            "linear": "theta0 = 0, Lambda <= 1e-3: |x1/x1_lin - 1| <= 2 Lambda",
            "inverse": "x1 at the found Lambda equals the given one to 1e-25",
        },
        "folds": folds,
        "cases": cases,
        "inverse": inverse,
        "seconds": round(time.time() - t0, 1),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"{len(cases)} cases, {len(inverse)} inverse, {time.time() - t0:.0f} s -> {args.out}")


if __name__ == "__main__":
    sys.exit(main())
