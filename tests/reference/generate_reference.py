"""Generate the high-precision reference values in ``tests/data/reference_mpmath.json``.

Run on demand (a few minutes on two cores)::

    .venv/bin/python tests/reference/generate_reference.py [--workers 2] [--quick]

Everything is computed with mpmath and nothing from :mod:`hairbed` is imported, so the values
can test the package. For each case (omega2, eps, theta0, sign, n) the script finds EVERY root of
the branch's self-consistency equation (theory.md §2, the paper's eqs. (33) and
(34))::

    omega_eps(xi) = (2n + 1) K(mu) - sign v0(xi),   mu = (1 + xi)/2,  p = 1 - mu = (1 - xi)/2
    G = omega_eps^2 - eps sign omega_eps sqrt(2 (xi - sin theta0)) - omega2 = 0

for xi in [sin theta0, 1). The unknown is the logit t of xi in its range,
xi - sin theta0 = (1 - sin theta0) expit(t) and 1 - xi = (1 - sin theta0) expit(-t), so that both
ends are resolved (1 - xi ~ 1e-8700 at omega2 = 1e8 is an ordinary mpf: mpmath's exponents are
unbounded). Roots are bracketed on a dense grid in t (with a search of every local extremum of G
between grid points, so that close pairs of roots near a fold are not missed) and refined with
``mpmath.findroot``.

Route A (the values written out) never forms mu = 1 - p where p could be lost in rounding:
K = pi / (2 agm(1, sqrt p)), and the incomplete integrals are Carlson forms whose arguments
carry p, cos^2 and dn^2 explicitly (DLMF 19.25.5, 19.25.9). Jacobi's sn, cn, dn are obtained
by inverting F(phi | mu) = u by Newton's method in the Gudermannian variable g = asinh(tan phi) for
u <= K/2, and through the reflection sn(K - u) = cd u, cn(K - u) = k' sd u, dn(K - u) = k' nd u
(DLMF 22.4.iii) above, so that cn and dn keep their relative accuracy even at 1e-4000.
The shape is then eqs. (32), (30) and the x(sigma) formula of theory.md §3, with
theta = 2 atan2(sqrt(mu) sn, dn) - pi/2 (equal to the paper's 2 arcsin(sqrt(mu) sn) - pi/2, but
well conditioned near theta = pi/2).

Checks recorded in the output (each root's ``checks``; summary in ``metadata``):

* precision: every root re-refined and re-evaluated at a higher working precision;
* route B: where 1 - xi > 1e-150, every value recomputed with mpmath's Legendre-form
  ``ellipk``/``ellipf``/``ellipe`` and its theta-function ``ellipfun`` at a working precision
  raised by the number of digits in 1 - xi (so mu = 1 - p is exact);
* internal: the profile at sigma = 0 and 1 equals (theta0, 0, 0) and the tip formulas;
* ODE: for a subset (twirling, bistable, strongly leaning, tight-channel cases), Taylor-series
  integration of theta'' = -omega_eps^2 cos(theta), x' = sin(theta), z' = cos(theta) from
  theta(0) = theta0, theta'(0) = base_curvature, asserting theta'(1) = 0, z(1) = tip_height,
  x(1) = tip_deflection, theta(1) = tip_angle, theta, x, z at every sigma, the
  self-consistency omega_eps^2 (1 - eps z(1)) = omega2 and the branch label (sign of
  theta'(0), number of interior sign changes of theta') to at least 25 digits. The Taylor
  coefficients come from exact recurrences (``taylor_ivp``); ``mpmath.odefun`` is run as well
  where omega_eps < 2 (its finite-difference coefficients need minutes and gigabytes beyond
  omega_eps ~ 5) and must agree with it.

Every computed number is written as a string with 20 significant digits; inputs are the JSON
numbers (binary doubles, converted exactly, so the reference is for exactly the inputs a
double-precision solver sees).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import multiprocessing
import platform
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

__all__ = ["build_cases", "compute_case", "main"]

#: Working precision [decimal digits] of route A (roots and values).
DPS = 50
#: Higher precision [decimal digits] of the precision check.
CHECK_DPS = 75
#: Precision [decimal digits] of the ODE integration.
ODE_DPS = 45
#: mpmath.odefun is also run where omega_eps is below this (it is slow beyond).
ODEFUN_MAX_OMEGA = 2
#: Digits required of every check.
REQUIRED_DIGITS = 25
#: Significant digits written out.
OUT_DIGITS = 20
#: Route B is used where 1 - xi exceeds this (its working precision grows with -log10(1 - xi)).
LEGENDRE_MIN_ONE_MINUS_XI = mpf("1e-150")
#: Points along the hair where the shape is tabulated.
SIGMA = (0.0, 0.01, 0.1, 0.3, 0.5, 0.77, 0.9, 0.99, 1.0)
FIELDS = (
    "xi",
    "one_minus_xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
)
OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "reference_mpmath.json"


# ------------------------------------------------------------------------------------------
# Route A: Carlson forms with p explicit, Jacobi functions by inversion
# ------------------------------------------------------------------------------------------


class Branch:
    """A branch (sign, n) at fixed eps and theta0, in the current mpmath precision."""

    def __init__(self, omega2: float, eps: float, theta0: float, sign: int, n: int) -> None:
        self.omega2 = mpf(omega2)
        self.eps = mpf(eps)
        self.theta0 = mpf(theta0)
        self.sign = sign
        self.n = n
        self.s = mp.sin(self.theta0)
        # 1 - sin(theta0) = 2 cos^2(pi/4 + theta0/2) = dn(v0)^2 * 2, computed without
        # cancellation for theta0 near pi/2.
        half = mp.pi / 4 + self.theta0 / 2
        self.a = mp.sin(half)  # sqrt(mu) sn(v0)
        self.dn0_sq = mp.cos(half) ** 2  # dn(v0)^2 = 1 - mu s0^2
        self.c0 = 2 * self.dn0_sq  # 1 - sin(theta0): the length of the xi range

    def state(self, t: mpf) -> dict[str, mpf]:
        """Everything that depends on t alone (and the branch)."""
        e_plus = 1 / (1 + mp.exp(-t))
        e_minus = 1 / (1 + mp.exp(t))
        q = self.c0 * e_plus  # xi - sin(theta0)
        r = self.c0 * e_minus  # 1 - xi
        p = r / 2
        mu = 1 - p  # only ever a multiplier: its rounding is harmless
        kk = mp.pi / (2 * mp.agm(1, mp.sqrt(p)))
        cn0_sq = q / (2 * mu)  # cos^2(am v0) = 1 - s0^2
        s0 = self.a / mp.sqrt(mu)
        v0 = s0 * mp.elliprf(cn0_sq, self.dn0_sq, 1)
        w = (2 * self.n + 1) * kk - self.sign * v0
        return {
            "t": t,
            "q": q,
            "r": r,
            "p": p,
            "mu": mu,
            "K": kk,
            "s0": s0,
            "cn0_sq": cn0_sq,
            "v0": v0,
            "w": w,
        }

    def residual(self, t: mpf) -> mpf:
        """G(t) = omega_eps^2 (1 - eps h1) - omega2 (eq. (34))."""
        st = self.state(t)
        w = st["w"]
        return w * w - self.eps * self.sign * w * mp.sqrt(2 * st["q"]) - self.omega2

    def scaled_residual(self, t: mpf) -> mpf:
        """G / (omega_eps^2 + omega2): same sign as G, of order one."""
        st = self.state(t)
        w = st["w"]
        g = w * w - self.eps * self.sign * w * mp.sqrt(2 * st["q"]) - self.omega2
        return g / (w * w + self.omega2)


def _sncndn_half(u: mpf, p: mpf) -> tuple[mpf, mpf, mpf]:
    """sn, cn, dn(u | 1 - p) for 0 <= u <= K/2, all to full relative accuracy.

    Newton's method on F(phi | mu) = u in g = asinh(tan phi): there sin phi = tanh g,
    cos phi = sech g, F(g) = g exactly at p = 0, and dF/dg = cn/dn lies in [1/sqrt(2), 1] for
    u <= K/2, so F is concave with a slope bounded away from zero: Newton from g = u (where
    F <= u) converges monotonically.
    """
    if u == 0:
        return mpf(0), mpf(1), mpf(1)
    g = +u
    tol = mpf(2) ** (-mp.prec + 8)
    for _ in range(200):
        s = mp.tanh(g)
        c = mp.sech(g)
        d = mp.sqrt(c * c + p * s * s)
        f = s * mp.elliprf(c * c, d * d, 1) - u
        step = f * d / c
        g -= step
        if abs(step) <= tol * max(1, abs(g)):
            break
    else:  # pragma: no cover - would mean a bug in the argument above
        raise RuntimeError(f"sn/cn/dn inversion did not converge at u={u}, p={p}")
    s = mp.tanh(g)
    c = mp.sech(g)
    return s, c, mp.sqrt(c * c + p * s * s)


def sncndn(u: mpf, p: mpf, kk: mpf) -> tuple[mpf, mpf, mpf]:
    """sn, cn, dn(u | 1 - p) for 0 <= u <= K, keeping cn and dn relatively accurate."""
    if u <= kk / 2:
        return _sncndn_half(u, p)
    s, c, d = _sncndn_half(kk - u, p)
    kp = mp.sqrt(p)
    # DLMF 22.4.iii: sn(K - w) = cd w, cn(K - w) = k' sd w, dn(K - w) = k' nd w.
    return c / d, kp * s / d, kp / d


def incomplete_e(s: mpf, c: mpf, d: mpf, mu: mpf) -> mpf:
    """E(phi | mu) from sin, cos and Delta = sqrt(1 - mu sin^2) of phi (DLMF 19.25.9)."""
    return s * mp.elliprf(c * c, d * d, 1) - mu / 3 * s**3 * mp.elliprd(c * c, d * d, 1)


def jacobi_at(v: mpf, p: mpf, mu: mpf, kk: mpf, ee: mpf) -> tuple[mpf, mpf, mpf, mpf]:
    """sn, cn, dn and Jacobi's epsilon Eps(v) = E(am v | mu) at any real v.

    Reduced by v = 2jK + u, |u| <= K, with am(v) = j pi + am(u), Eps(v) = 2jE + Eps(u) and
    oddness in u.
    """
    j = int(mp.nint(v / (2 * kk)))
    u = v - 2 * j * kk
    neg = u < 0
    s, c, d = sncndn(abs(u), p, kk)
    eps_u = incomplete_e(s, c, d, mu)
    if neg:
        s, eps_u = -s, -eps_u
    if j % 2:
        s, c = -s, -c
    return s, c, d, 2 * j * ee + eps_u


def evaluate(br: Branch, t: mpf, sigmas: tuple[float, ...]) -> dict[str, Any]:
    """All values of the root at parameter t (route A)."""
    st = br.state(t)
    q, r, p, mu, kk, w, v0 = st["q"], st["r"], st["p"], st["mu"], st["K"], st["w"], st["v0"]
    sign, n = br.sign, br.n
    ee = kk - mu / 3 * mp.elliprd(0, p, 1)  # E(mu) = R_F - mu/3 R_D (DLMF 19.25.1)
    s0, cn0 = st["s0"], mp.sqrt(st["cn0_sq"])
    eps0 = incomplete_e(s0, cn0, mp.sqrt(br.dn0_sq), mu)
    root2q = mp.sqrt(2 * q)
    sqmu = mp.sqrt(mu)
    out = {
        "xi": br.s + q,
        "one_minus_xi": r,
        "omega_eps": w,
        "energy": (br.s + q) * w * w,
        "tip_height": sign * root2q / w,
        # x(1) = 1 - 2((2n+1) E - sign Eps(v0)) / omega_eps since v(1) - v0 = sign omega_eps.
        "tip_deflection": 1 - 2 * ((2 * n + 1) * ee - sign * eps0) / w,
        # sn(v(1)) = sign (-1)^n, dn(v(1)) = k' = sqrt(p).
        "tip_angle": 2 * mp.atan2(sqmu * sign * (-1) ** n, mp.sqrt(p)) - mp.pi / 2,
        "base_curvature": sign * w * root2q,
    }
    theta, x, z = [], [], []
    for sig in sigmas:
        v = v0 + sign * w * mpf(sig)
        sn, cn, dn, eps_v = jacobi_at(v, p, mu, kk, ee)
        theta.append(2 * mp.atan2(sqmu * sn, dn) - mp.pi / 2)  # eq. (32)
        z.append(2 * sqmu * (cn0 - cn) / (sign * w))  # eq. (30)
        x.append(((v - v0) - 2 * (eps_v - eps0)) / (sign * w))
    out["theta"], out["x"], out["z"] = theta, x, z
    out["_state"] = st
    return out


def trivial(br: Branch, sigmas: tuple[float, ...]) -> dict[str, Any]:
    """The undeformed hair: the physical root at omega2 = 0 (xi = sin theta0, t = -inf)."""
    th = br.theta0
    return {
        "xi": br.s,
        "one_minus_xi": br.c0,
        "omega_eps": mpf(0),
        "energy": mpf(0),
        "tip_height": mp.cos(th),
        "tip_deflection": mp.sin(th),
        "tip_angle": th,
        "base_curvature": mpf(0),
        "theta": [th for _ in sigmas],
        "x": [mpf(s) * mp.sin(th) for s in sigmas],
        "z": [mpf(s) * mp.cos(th) for s in sigmas],
    }


# ------------------------------------------------------------------------------------------
# Root finding
# ------------------------------------------------------------------------------------------


def t_grid(br: Branch) -> list[mpf]:
    """Dense grid in t: step 0.1 on [t_lo, 40], then geometric until G > 0 for good.

    Beyond t = 40 (1 - xi < 1e-17) K grows linearly in t and h1 = O(1/omega_eps), so G is
    monotone once omega_eps exceeds 1 + sqrt(1 + omega2) + 10 (G >= omega_eps (omega_eps - 2)
    - omega2 since sqrt(2 (xi - sin theta0)) <= 2).
    """
    lo = -60.0
    if br.omega2 > 0:
        lo = min(lo, math.log(float(br.omega2)) - 40)
    pts = [mpf(lo + 0.1 * k) for k in range(int(round((40 - lo) / 0.1)) + 1)]
    bound = 1 + mp.sqrt(1 + br.omega2) + 10
    t = mpf(40)
    while True:
        t = t * mpf("1.02") + mpf("0.1")
        pts.append(t)
        if br.state(t)["w"] > bound and br.residual(t) > 0:
            break
    # Two far points at the weak end, where G tends to a constant.
    return [mpf(lo - 300), mpf(lo - 100), *pts]


def _golden_extremum(f, a: mpf, b: mpf, minimum: bool, iters: int = 80) -> tuple[mpf, mpf]:
    """Golden-section search for the extremum of f on [a, b]."""
    sgn = 1 if minimum else -1
    gr = (mp.sqrt(5) - 1) / 2
    c, d = b - gr * (b - a), a + gr * (b - a)
    fc, fd = sgn * f(c), sgn * f(d)
    for _ in range(iters):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - gr * (b - a)
            fc = sgn * f(c)
        else:
            a, c, fc = c, d, fd
            d = a + gr * (b - a)
            fd = sgn * f(d)
    tm = (a + b) / 2
    return tm, f(tm)


def find_roots(br: Branch) -> tuple[list[mpf], dict[str, Any]]:
    """Every root in t of the branch's equation, increasing (= increasing xi)."""
    f = br.scaled_residual
    ts = t_grid(br)
    fs = [f(t) for t in ts]
    brackets = []
    for i in range(len(ts) - 1):
        if fs[i] == 0:
            brackets.append((ts[i], ts[i]))
        elif fs[i] * fs[i + 1] < 0:
            brackets.append((ts[i], ts[i + 1]))
    # A pair of roots between two grid points shows up as a local extremum of G with no
    # sign change around it: look inside every such extremum.
    extrema = 0
    for i in range(1, len(ts) - 1):
        d1, d2 = fs[i] - fs[i - 1], fs[i + 1] - fs[i]
        if d1 * d2 < 0 and fs[i - 1] * fs[i] > 0 and fs[i] * fs[i + 1] > 0:
            extrema += 1
            is_min = d1 < 0
            if (is_min and fs[i] < 0) or (not is_min and fs[i] > 0):
                continue  # the extremum points away from zero
            tm, fm = _golden_extremum(f, ts[i - 1], ts[i + 1], is_min)
            if fm * fs[i] < 0:
                brackets.append((ts[i - 1], tm))
                brackets.append((tm, ts[i + 1]))
    roots = []
    for a, b in sorted(brackets):
        if a == b:
            roots.append(a)
            continue
        t = mp.findroot(f, (a, b), solver="anderson", verify=False)
        if not a <= t <= b:  # pragma: no cover - fall back to plain bisection
            t = mp.findroot(f, (a, b), solver="bisect", verify=False)
        roots.append(t)
    info = {
        "grid_points": len(ts),
        "t_range": [float(ts[0]), float(ts[-1])],
        "local_extrema": extrema,
    }
    return roots, info


def polish(br: Branch, t: mpf, rel: mpf) -> mpf:
    """Refine a root at the current precision inside a small bracket around t.

    The bracket t +- rel max(1, |t|) is widened until G changes sign over it, so that the
    refinement cannot wander to a neighbouring root (three roots can be close together in a
    bistable window).
    """
    f = br.scaled_residual
    delta = rel * max(1, abs(t))
    for _ in range(40):
        a, b = t - delta, t + delta
        fa, fb = f(a), f(b)
        if fa * fb <= 0:
            break
        delta *= 10
    else:  # pragma: no cover
        raise RuntimeError(f"no sign change around t={t} for {vars(br)}")
    if fa == 0:
        return a
    if fb == 0:
        return b
    t1 = mp.findroot(f, (a, b), solver="anderson", verify=False)
    if not a <= t1 <= b:  # pragma: no cover
        t1 = mp.findroot(f, (a, b), solver="bisect", verify=False)
    return t1


# ------------------------------------------------------------------------------------------
# Route B: mpmath's Legendre forms and theta-function Jacobi functions
# ------------------------------------------------------------------------------------------


def legendre_values(case: dict[str, Any], t: mpf, sigmas: tuple[float, ...]) -> dict[str, Any]:
    """The same values from ellipk, ellipf, ellipe and ellipfun, with mu = 1 - p exact."""
    sign, n = case["sign"], case["n"]
    theta0, eps, omega2 = mpf(case["theta0"]), mpf(case["eps"]), mpf(case["omega2"])
    s = mp.sin(theta0)
    c0 = 1 - s
    q = c0 / (1 + mp.exp(-t))
    r = c0 / (1 + mp.exp(t))
    xi = s + q
    mu = 1 - r / 2
    kk = mp.ellipk(mu)
    s0 = mp.sin(mp.pi / 4 + theta0 / 2) / mp.sqrt(mu)
    phi0 = mp.asin(min(s0, mpf(1)))
    v0 = mp.ellipf(phi0, mu)
    eps0 = mp.ellipe(phi0, mu)
    w = (2 * n + 1) * kk - sign * v0
    h1 = sign * mp.sqrt(2 * (xi - s)) / w
    out = {
        "xi": xi,
        "one_minus_xi": 1 - xi,
        "omega_eps": w,
        "energy": xi * w * w,
        "tip_height": h1,
        "base_curvature": sign * w * mp.sqrt(2 * (xi - s)),
        "residual": (w * w * (1 - eps * h1) - omega2) / (w * w + omega2),
    }
    theta, x, z = [], [], []
    cn0 = mp.ellipfun("cn", v0, m=mu)
    for sig in sigmas:
        v = v0 + sign * w * mpf(sig)
        sn = mp.ellipfun("sn", v, m=mu)
        cn = mp.ellipfun("cn", v, m=mu)
        j = int(mp.nint(v / (2 * kk)))
        am = j * mp.pi + mp.atan2((-1) ** j * sn, (-1) ** j * cn)
        arg = mp.sqrt(mu) * sn
        theta.append(2 * mp.asin(max(min(arg, mpf(1)), mpf(-1))) - mp.pi / 2)
        z.append(2 * mp.sqrt(mu) * (cn0 - cn) / (sign * w))
        x.append(((v - v0) - 2 * (mp.ellipe(am, mu) - eps0)) / (sign * w))
    out["theta"], out["x"], out["z"] = theta, x, z
    out["tip_deflection"] = x[-1] if sigmas[-1] == 1.0 else None
    out["tip_angle"] = theta[-1] if sigmas[-1] == 1.0 else None
    return out


# ------------------------------------------------------------------------------------------
# ODE check
# ------------------------------------------------------------------------------------------


def taylor_ivp(
    w: mpf, theta0: mpf, dtheta0: mpf, landmarks: tuple[float, ...], order: int
) -> tuple[list[list[mpf]], int]:
    """Taylor-series integration of theta'' = -w^2 cos(theta), x' = sin(theta), z' = cos(theta).

    The series are generated exactly by the recurrences of C = cos(theta), S = sin(theta):
    C' = -S theta', S' = C theta', theta'' = -w^2 C, to ``order`` terms, with steps chosen
    from the size of the last coefficients so that the truncation error stays below the
    working precision, landing exactly on every landmark. Returns [theta, theta', x, z] at
    each landmark and the number of sign changes of theta' strictly inside (0, 1), from 16
    samples per step.
    """
    w2 = w * w
    nn = order
    tol_exp = mpf(10) ** (-mpf(mp.dps + 5) / nn)
    y, dy, x, z = +theta0, +dtheta0, mpf(0), mpf(0)
    s_pos = mpf(0)
    marks = [mpf(m) for m in landmarks]
    out: list[list[mpf]] = []
    if marks and marks[0] == 0:
        out.append([y, dy, x, z])
        marks = marks[1:]
    scale = max(1, abs(dtheta0))
    samples: list[mpf] = [dy]
    while marks:
        yc = [y, dy] + [mpf(0)] * nn
        cc = [mp.cos(y)] + [mpf(0)] * nn
        ss = [mp.sin(y)] + [mpf(0)] * nn
        for k in range(nn - 1):
            yc[k + 2] = -w2 * cc[k] / ((k + 1) * (k + 2))
            acc_c = mpf(0)
            acc_s = mpf(0)
            for j in range(k + 1):
                d = (k - j + 1) * yc[k - j + 1]
                acc_c += ss[j] * d
                acc_s += cc[j] * d
            cc[k + 1] = -acc_c / (k + 1)
            ss[k + 1] = acc_s / (k + 1)
        xc = [x] + [ss[k] / (k + 1) for k in range(nn)]
        zc = [z] + [cc[k] / (k + 1) for k in range(nn)]
        rho = max(
            max(abs(c[k]) ** (mpf(1) / k) for k in (nn - 2, nn - 1) if c[k] != 0)
            if any(c[k] != 0 for k in (nn - 2, nn - 1))
            else mpf(0)
            for c in (yc, cc, ss)
        )
        h = marks[0] - s_pos
        if rho > 0:
            h = min(h, tol_exp / rho)
        dyc = [(k + 1) * yc[k + 1] for k in range(nn)]
        for m in range(1, 16):
            samples.append(mp.polyval(dyc[::-1], h * m / 16))
        y = mp.polyval(yc[: nn + 1][::-1], h)
        dy = mp.polyval(dyc[::-1], h)
        x = mp.polyval(xc[::-1], h)
        z = mp.polyval(zc[::-1], h)
        s_pos += h
        if s_pos == marks[0]:
            out.append([y, dy, x, z])
            marks = marks[1:]
        samples.append(dy)
    # The tip is a turning point, not an interior one: ignore theta' once it is negligible.
    tiny = mpf(10) ** (-15) * scale
    signs = [1 if v > 0 else -1 for v in samples if abs(v) > tiny]
    changes = sum(1 for a, b in zip(signs, signs[1:]) if a != b)
    return out, changes


def ode_check(case: dict[str, Any], root: dict[str, Any], sigmas: tuple[float, ...]) -> dict:
    """Integrate the initial value problem from theta0 and base_curvature and compare.

    Taylor-series integration (``taylor_ivp``; ``mpmath.odefun`` too where omega_eps is
    small enough for it to finish in seconds: its finite-difference Taylor coefficients cost
    degree x (degree x precision) bits per step and it needs minutes beyond omega_eps ~ 3).
    """
    w = mpf(root["omega_eps"])
    w2 = w * w
    theta0 = mpf(case["theta0"])
    y0 = [theta0, mpf(root["base_curvature"]), mpf(0), mpf(0)]
    start = time.time()
    prof, changes = taylor_ivp(w, theta0, y0[1], sigmas, order=2 * ODE_DPS)
    y1 = prof[-1]
    methods = [f"taylor recurrences (order {2 * ODE_DPS})"]
    odefun_err = None
    if w < ODEFUN_MAX_OMEGA:

        def rhs(_s, y):
            c = mp.cos(y[0])
            return [y[1], -w2 * c, mp.sin(y[0]), c]

        sol = mp.odefun(rhs, 0, y0)
        ys = [sol(mpf(sg)) if sg > 0 else y0 for sg in sigmas]
        odefun_err = max(abs(a - b) for ya, yb in zip(ys, prof) for a, b in zip(ya, yb))
        methods.append("mpmath.odefun")
    scale = max(1, abs(y0[1]))
    errs = {
        "theta_prime_1": abs(y1[1]) / scale,
        "tip_height": abs(y1[3] - mpf(root["tip_height"])),
        "tip_deflection": abs(y1[2] - mpf(root["tip_deflection"])),
        "tip_angle": abs(y1[0] - mpf(root["tip_angle"])),
        "self_consistency": abs(w2 * (1 - mpf(case["eps"]) * y1[3]) - mpf(case["omega2"]))
        / max(1, mpf(case["omega2"])),
        "profile": max(
            max(abs(pv[0] - mpf(a)), abs(pv[2] - mpf(b)), abs(pv[3] - mpf(c)))
            for pv, a, b, c in zip(prof, root["theta"], root["x"], root["z"])
        ),
    }
    if odefun_err is not None:
        errs["odefun_vs_taylor"] = odefun_err
    worst = max(errs.values())
    digits = float(-mp.log10(worst)) if worst > 0 else float(ODE_DPS)
    label_ok = (1 if y0[1] > 0 else -1) == case["sign"] and changes == case["n"]
    return {
        "dps": ODE_DPS,
        "methods": methods,
        "digits": round(digits, 1),
        "errors": {k: mp.nstr(v, 3) for k, v in errs.items()},
        "ode_theta_prime_1": mp.nstr(y1[1], 5),
        "ode_tip_height": mp.nstr(y1[3], OUT_DIGITS),
        "ode_tip_deflection": mp.nstr(y1[2], OUT_DIGITS),
        "interior_turning_points": changes,
        "label_ok": label_ok,
        "seconds": round(time.time() - start, 1),
    }


# ------------------------------------------------------------------------------------------
# One case
# ------------------------------------------------------------------------------------------


def _agreement(a: dict[str, Any], b: dict[str, Any], keys) -> mpf:
    """Largest difference between two evaluations, relative to max(1, |value|)."""
    worst = mpf(0)
    for k in keys:
        va, vb = a[k], b[k]
        if va is None or vb is None:
            continue
        if isinstance(va, list):
            pairs = zip(va, vb)
        elif k == "one_minus_xi":  # relative: it can be 1e-8700
            pairs = [(va / vb, mpf(1))] if vb != 0 else [(va, vb)]
        else:
            pairs = [(va, vb)]
        for x, y in pairs:
            worst = max(worst, abs(x - y) / max(1, abs(y)))
    return worst


def _digits(err: mpf, cap: int) -> float:
    return float(cap) if err == 0 else round(min(float(-mp.log10(err)), float(cap)), 1)


def _fmt(value: mpf) -> str:
    return mp.nstr(value, OUT_DIGITS)


def compute_case(case: dict[str, Any]) -> dict[str, Any]:
    """Every root of one case, with its values and checks (run in a worker)."""
    start = time.time()
    sigmas = SIGMA
    mp.dps = DPS
    br = Branch(case["omega2"], case["eps"], case["theta0"], case["sign"], case["n"])
    roots_out = []
    keys = (*FIELDS, "theta", "x", "z")
    if case["omega2"] == 0 and case["sign"] == 1 and case["n"] == 0:
        vals = trivial(br, sigmas)
        vals["t"] = mpf("-inf")
        roots_out.append({"values": vals, "checks": {"trivial": True}})
        info = {"grid_points": 0, "note": "omega2 = 0: the undeformed hair, xi = sin(theta0)"}
        ts = []
    else:
        ts, info = find_roots(br)
    for t in ts:
        mp.dps = DPS
        t = polish(br, t, mpf(10) ** (-25))
        vals = evaluate(br, t, sigmas)
        checks: dict[str, Any] = {}
        res = abs(br.scaled_residual(t))
        # Internal: the profile ends agree with the boundary values and the tip formulas.
        ends = max(
            abs(vals["theta"][0] - br.theta0),
            abs(vals["x"][0]),
            abs(vals["z"][0]),
            abs(vals["theta"][-1] - vals["tip_angle"]),
            abs(vals["x"][-1] - vals["tip_deflection"]),
            abs(vals["z"][-1] - vals["tip_height"]),
        )
        checks["residual"] = mp.nstr(res, 3)
        checks["ends_digits"] = _digits(ends, DPS)
        # Precision: re-solve and re-evaluate with more digits.
        mp.dps = CHECK_DPS
        br_hi = Branch(case["omega2"], case["eps"], case["theta0"], case["sign"], case["n"])
        t_hi = polish(br_hi, +t, mpf(10) ** (-(DPS - 8)))
        vals_hi = evaluate(br_hi, t_hi, sigmas)
        vals_hi["t"] = t_hi
        checks["precision_digits"] = _digits(_agreement(vals, vals_hi, keys), CHECK_DPS)
        vals = vals_hi  # the more accurate of the two
        # sigma = 0 is the base: write its exact values rather than rounding residue (the
        # agreement was checked above).
        vals["theta"][0], vals["x"][0], vals["z"][0] = br_hi.theta0, mpf(0), mpf(0)
        # Route B where mu = 1 - p can be held exactly at a reasonable precision.
        r = vals["one_minus_xi"]
        if r > LEGENDRE_MIN_ONE_MINUS_XI:
            mp.dps = DPS + 10 + int(-mp.log10(r)) if r < 1 else DPS + 10
            leg = legendre_values(case, t_hi, sigmas)
            checks["legendre_digits"] = _digits(_agreement(leg, vals, keys), DPS)
            checks["legendre_residual"] = mp.nstr(abs(leg["residual"]), 3)
            mp.dps = CHECK_DPS
        ok = min(
            checks["precision_digits"], checks["ends_digits"], checks.get("legendre_digits", 99)
        )
        if ok < REQUIRED_DIGITS + 5:
            raise RuntimeError(f"check failed for {case}: {checks}")
        roots_out.append({"values": vals, "checks": checks})
    if case.get("ode"):
        for item in roots_out:
            mp.dps = ODE_DPS
            chk = ode_check(case, item["values"], sigmas)
            item["checks"]["ode"] = chk
            if chk["digits"] < REQUIRED_DIGITS or not chk["label_ok"]:
                raise RuntimeError(f"ODE check failed for {case}: {chk}")
    mp.dps = CHECK_DPS
    out_roots = []
    for item in roots_out:
        vals = item["values"]
        entry = {k: _fmt(vals[k]) for k in FIELDS}
        # The logit of xi (module docstring): hairbed.from_parameter's t.
        entry["t"] = _fmt(vals["t"])
        entry["theta"] = [_fmt(v) for v in vals["theta"]]
        entry["x"] = [_fmt(v) for v in vals["x"]]
        entry["z"] = [_fmt(v) for v in vals["z"]]
        entry["checks"] = item["checks"]
        out_roots.append(entry)
    result = {k: case[k] for k in ("id", "group", "omega2", "eps", "theta0", "sign", "n")}
    result["n_roots"] = len(out_roots)
    result["roots"] = out_roots
    result["search"] = info
    result["seconds"] = round(time.time() - start, 1)
    return result


# ------------------------------------------------------------------------------------------
# The cases
# ------------------------------------------------------------------------------------------

OMEGA2 = (0.0, 1e-10, 1e-6, 1e-3, 0.05, 0.5, 2.0, 10.0, 100.0, 400.0, 1e3, 1e4, 1.3e5, 1e6, 1e8)
EPS = (0.0, 0.3, 0.5, 0.9, 0.99, 0.999)
THETA0 = (-1.55, -1.5, -1.0, -0.5, -0.1, 0.0, 0.3, 1.0, 1.55)

#: Bistable windows of theory.md §5: (theta0, eps, omega2 inside, omega2 near the edges).
BISTABLE = (
    (-1.5, 0.9, (1.0, 1.2, 1.4), (0.957, 0.959, 1.484, 1.487)),
    (-1.0, 0.95, (0.31,), (0.2965, 0.2972, 0.3195, 0.3200)),
    (-0.5, 0.99, (0.0355,), (0.03490, 0.03496, 0.03616, 0.03622)),
)

#: (sign, n) of the other branches and the (omega2, eps, theta0) where they are tabulated.
OTHER_BRANCHES = ((1, 1), (1, 2), (1, 3), (-1, 0), (-1, 1), (-1, 2), (-1, 3))
BRANCH_INPUTS = (
    (1.0, 0.5, 0.0),
    (5.0, 0.0, -1.0),
    (20.0, 0.9, 0.3),
    (60.0, 0.99, -0.5),
    (60.0, 0.5, 1.0),
    (150.0, 0.3, -1.55),
    (400.0, 0.999, 0.0),
    (1e3, 0.9, 1.55),
    (1e4, 0.5, -0.1),
)

#: Inputs where every branch is tabulated (for solve_all).
ALL_BRANCHES = (
    (2.0, 0.5, 0.0),
    (50.0, 0.5, 0.0),
    (30.0, 0.99, -1.5),
    (200.0, 0.9, -0.5),
    (400.0, 0.3, 1.0),
)


def _max_n(omega2: float, sign: int) -> int:
    """Largest n for which branch (sign, n) can have a root at this omega2.

    omega_eps >= 2nK >= n pi (sign +1) or (2n + 1) pi/2 (sign -1), since K >= pi/2 and
    0 <= v0 <= K; and omega2 >= omega_eps (omega_eps - 2) (sign +1, as
    sqrt(2 (xi - sin theta0)) <= 2 and eps < 1) or omega2 >= omega_eps^2 (sign -1).
    """
    if sign == 1:
        return int((1 + math.sqrt(1 + omega2)) / math.pi)
    return max(int((math.sqrt(omega2) / (math.pi / 2) - 1) / 2), -1)


def build_cases(quick: bool = False) -> list[dict[str, Any]]:
    """The list of cases, each a dict of inputs, a readable id and a group."""
    cases: list[dict[str, Any]] = []
    seen: set[tuple] = set()

    def add(group, omega2, eps, theta0, sign=1, n=0, ode=False):
        key = (omega2, eps, theta0, sign, n)
        if key in seen:
            for c in cases:
                if (c["omega2"], c["eps"], c["theta0"], c["sign"], c["n"]) == key:
                    c["ode"] = c["ode"] or ode
            return
        seen.add(key)
        cid = f"{group}-w{omega2:g}-e{eps:g}-t{theta0:g}-s{sign:+d}-n{n}"
        cases.append(
            {
                "id": cid,
                "group": group,
                "omega2": omega2,
                "eps": eps,
                "theta0": theta0,
                "sign": sign,
                "n": n,
                "ode": ode,
            }
        )

    # Physical branch: every (omega2, theta0) pair once, eps cycling through its list.
    for i, w in enumerate(OMEGA2):
        for j, th in enumerate(THETA0):
            add("physical", w, EPS[(i + 2 * j) % len(EPS)], th)
    # Corners.
    for th in (-1.55, 1.55):
        for w in OMEGA2:
            add("physical", w, 0.999, th)
        for w in (0.0, 1e-10, 1e6, 1e8):
            add("physical", w, 0.0, th)
    for w in (1e6, 1e8):
        for th in THETA0:
            add("physical", w, 0.9, th)
    # The paper's example (theory.md §3) and the ODE subset on the physical branch.
    add("paper", 2.0, 0.5, 0.0, ode=True)
    for w, e, th in (
        (0.5, 0.999, 1.55),
        (10.0, 0.99, -1.55),
        (100.0, 0.3, 1.0),
        (1e-3, 0.9, -1.5),
        (0.05, 0.999, -1.55),
        (400.0, 0.0, 0.0),
    ):
        add("physical", w, e, th, ode=True)
    # Bistable windows and their edges.
    for th, e, inside, edges in BISTABLE:
        for w in inside:
            add("bistable", w, e, th, ode=(w == inside[0]))
        for w in edges:
            add("bistable-edge", w, e, th)
    # Other branches.
    for sign, n in OTHER_BRANCHES:
        for w, e, th in BRANCH_INPUTS:
            add("branch", w, e, th, sign, n)
    for sign, n, w, e, th in (
        (1, 1, 60.0, 0.5, 1.0),
        (-1, 0, 20.0, 0.9, 0.3),
        (1, 2, 400.0, 0.999, 0.0),
        (-1, 1, 150.0, 0.3, -1.55),
    ):
        add("branch", w, e, th, sign, n, ode=True)
    # Every branch at a few inputs.
    for w, e, th in ALL_BRANCHES:
        for sign in (1, -1):
            for n in range(_max_n(w, sign) + 1):
                add(
                    "all-branches",
                    w,
                    e,
                    th,
                    sign,
                    n,
                    ode=(w, e, th, sign, n) == (50.0, 0.5, 0.0, 1, 1),
                )
    if quick:
        cases = [c for c in cases if c["group"] != "physical" or c["omega2"] in (2.0, 1e8)]
    return cases


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="fewer cases (a smoke test)")
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    args = parser.parse_args(argv)
    cases = build_cases(args.quick)
    # Longest first so that the two workers finish together.
    order = sorted(
        range(len(cases)), key=lambda i: -(10 * cases[i]["ode"] + cases[i]["omega2"] ** 0.1)
    )
    start = time.time()
    results: list[dict[str, Any] | None] = [None] * len(cases)
    with multiprocessing.Pool(args.workers) as pool:
        for k, res in enumerate(pool.imap(compute_case, [cases[i] for i in order])):
            results[order[k]] = res
            print(
                f"[{k + 1}/{len(cases)}] {res['id']}: {res['n_roots']} root(s), "
                f"{res['seconds']} s",
                flush=True,
            )
    elapsed = time.time() - start
    roots = [r for res in results for r in res["roots"]]
    ode = [r["checks"]["ode"] for r in roots if "ode" in r["checks"]]
    leg = [r["checks"]["legendre_digits"] for r in roots if "legendre_digits" in r["checks"]]
    prec = [r["checks"]["precision_digits"] for r in roots if "precision_digits" in r["checks"]]
    n_odefun = sum(1 for c in ode if "mpmath.odefun" in c["methods"])
    # Every branch that can have a root at these inputs (whatever group tabulated it first).
    by_key = {(r["omega2"], r["eps"], r["theta0"], r["sign"], r["n"]): r["id"] for r in results}
    all_branches = []
    for w, e, th in ALL_BRANCHES:
        ids = [by_key[(w, e, th, sign, n)] for sign in (1, -1) for n in range(_max_n(w, sign) + 1)]
        all_branches.append({"omega2": w, "eps": e, "theta0": th, "case_ids": ids})
    metadata = {
        "about": "High-precision reference values for the boundary-hair problem (docs/theory.md "
        "sections 2 and 3), generated by tests/reference/generate_reference.py.",
        "mpmath_version": mpmath.__version__,
        "mpmath_backend": mpmath.libmp.BACKEND,
        "python_version": platform.python_version(),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "dps": {
            "route_a": DPS,
            "precision_check": CHECK_DPS,
            "ode": ODE_DPS,
            "route_b": "50 + 10 + digits of 1/(1 - xi)",
        },
        "significant_digits_written": OUT_DIGITS,
        "generation_seconds": round(elapsed, 1),
        "workers": args.workers,
        "n_cases": len(results),
        "n_roots": len(roots),
        "sigma": list(SIGMA),
        "fields": list(FIELDS),
        "root_order": "increasing xi (root='low' first, 'high' last, 'mid' the middle of 3)",
        "checks": {
            "precision": f"every root re-refined and re-evaluated at {CHECK_DPS} digits; "
            f"minimum agreement {min(prec)} digits over {len(prec)} roots",
            "route_b": "mpmath ellipk/ellipf/ellipe/ellipfun with mu = 1 - p held exactly, "
            f"where 1 - xi > {mp.nstr(LEGENDRE_MIN_ONE_MINUS_XI, 3)}: {len(leg)} roots, "
            f"minimum agreement {min(leg)} digits",
            "ode": "Taylor-series integration (exact coefficient recurrences; also "
            f"mpmath.odefun where omega_eps < {ODEFUN_MAX_OMEGA}: {n_odefun} roots) of "
            "theta'' = -omega_eps^2 cos(theta), "
            "x' = sin(theta), z' = cos(theta) from theta(0) = theta0, theta'(0) = "
            "base_curvature: theta'(1) = 0, z(1) = tip_height, x(1) = tip_deflection, "
            "theta(1) = tip_angle, omega_eps^2 (1 - eps z(1)) = omega2, theta/x/z at every "
            "sigma, sign of theta'(0) = sign and interior sign changes of theta' = n; "
            f"{len(ode)} roots, minimum agreement {min(c['digits'] for c in ode)} digits",
            "search": "grid in the logit t (step 0.1, geometric beyond t = 40) with a "
            "golden-section search inside every local extremum of G between grid points",
        },
        "all_branches": all_branches,
        "all_branches_note": "case_ids lists every branch (sign, n) that can have a root at "
        "these inputs: n <= (1 + sqrt(1 + omega2))/pi for sign +1 and "
        "(2n + 1) pi/2 <= sqrt(omega2) for sign -1 (see _max_n); solve_all lists their roots "
        "ordered by (n, sign +1 before -1), then by increasing xi",
    }
    out = {"metadata": metadata, "cases": results}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(
        f"{len(results)} cases, {len(roots)} roots, {elapsed:.0f} s; "
        f"ODE >= {min(c['digits'] for c in ode)} digits over {len(ode)} roots; "
        f"route B >= {min(leg)} digits; wrote {args.out}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
