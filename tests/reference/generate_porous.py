"""Generate ``tests/data/porous_mpmath.json``: the porous (Brinkman) bed of issue 29.

Run on demand (minutes on one or two cores)::

    .venv/bin/python tests/reference/generate_porous.py [--workers 2] [--out PATH] [--quick]

It imports nothing from :mod:`hairbed` (mpmath and the standard library only) and shares no
code with its solver: the equations are written here from issue 29. With s in [0, 1] the arc
length in units of L, w the fluid's horizontal velocity and Q its shear stress (load units)::

    theta'' = -(F_x cos theta - F_z sin theta),  theta(0) = theta0,  theta'(1) = 0,
    x' = sin theta,  z' = cos theta,  x(0) = z(0) = 0,  h1 = z(1),  x1 = x(1),
    F_x(s) =  int_s^1 (w/kappa) (cos^2 theta + gamma sin^2 theta) ds',
    F_z(s) = -int_s^1 (w/kappa) (1 - gamma) sin theta cos theta ds',
    w' = cos theta Q,  w(0) = 0,
    Q' = (w/kappa) (cos^2 theta + gamma sin^2 theta) - Pi cos theta,
    eps w(1) + (1 - eps h1) Q(1) - Pi (1 - eps h1)^2/(2 eps) = omega2      (the gap),

the Pi term absent for the wall drive (Pi = 0, where eps = 0 is allowed). Drives: "wall"
(omega2 given, Pi = 0), "pressure" (Pi and omega2 given) and "flow" (q and omega2 given, Pi
unknown, q = 6 eps^2 Phi with Phi = int_0^1 w cos theta ds + w(1) g + Q(1) g^2/2 - Pi g^3/6,
g = 1/eps - h1).

Two methods, each at >= 50 digits, must agree on every written state (``AGREE_TOL``):

1. **Forward Taylor shooting** (the values written). From s = 0 with the unknowns theta'(0),
   Q(0), F_x(0), F_z(0) (and Pi for the flow drive); conditions theta'(1) = F_x(1) = F_z(1) = 0,
   the gap (and the flux). The integrator is a Taylor series method with exact recurrences
   (S = sin theta, C = cos theta: S' = C theta', C' = -S theta'; every right-hand side is a sum
   of products of series), order ``TAYLOR_ORDER``, step from the last two coefficients. The
   fluid's growing mode exp(s/sqrt(kappa)) amplifies every error made near the base, so the
   working precision and the step tolerance carry ``extra = log10(e)/sqrt(kappa)`` more
   digits (about 140 at kappa = 1e-5). Newton's method with a finite-difference Jacobian
   (each column's step rescaled until its effect is half the available digits), reused while
   it contracts.
2. **Backward extrapolation shooting**. From the tip s = 1 down to the base with the unknowns
   theta(1), h1 = z(1), w(1) (and Pi); Q(1) from the gap condition; conditions theta(0) =
   theta0, z(0) = 0, w(0) = 0 (and the flux). The integrator is Gragg-Bulirsch-Stoer (the
   modified midpoint rule extrapolated in h^2, ``GBS_COLUMNS`` columns), adaptive, evaluating
   the right-hand side pointwise (no series). Backwards the fluid's physical mode decays;
   Newton's correction of w(1) absorbs the growing one, so no extra digits are needed.

Below kappa = 1e-2 (``SCAN_MIN_KAPPA``) the double-precision scan fails (the growing mode
amplifies by more than 1e13), and single shooting has a basin of width exp(-1/sqrt(kappa)) in
Q(0) or w(1). There the states are continued in kappa along their series (the wall drive
only, where Q(0) > 0 and the fluid's equations are homogeneous): ``nested_forward`` solves
for log Q(0) alone (the gap condition, bracketing) inside a Newton iteration on theta'(0),
F_x(0), F_z(0), from a guess extrapolated in sqrt(kappa); then method 1's Newton polishes all
four, and the second method is the same forward shooting integrated by Gragg-Bulirsch-Stoer
(a different discretisation; the record's ``method2`` says which).

Finding the states (every state of a window). A state is one of the family parametrised by
the tip angle theta1: at fixed theta1 the load scale L (the wall's omega2, the pressure's Pi,
or the flow's q, the other loads scaled with it) is an unknown of the backward shooting. The
family starts at the straight hair (theta1 = theta0, L = 0) and is followed in double
precision (the same backward shooting in Python floats, fewer columns) in steps of theta1
until L passes twice the requested load; every crossing of the requested load is a state,
every local extremum of L(theta1) a fold. The window loads are chosen by this scan (the
middle of the fold interval). Each crossing is refined by method 2 at full precision
with theta1 free, then by method 1 from method 2's base values (method 1's Newton converges
to its own root: its residual is checked at its own precision).

Limits written beside the states (``limits``): the dense bed (kappa -> 0) with its tip force
W (1, -r1), W = omega2/u + (Pi/2)(1/eps - h1), u = 1 - eps h1,
r1 = (1 - gamma) sin theta1 cos theta1/(cos^2 theta1 + gamma sin^2 theta1), and the interior
drag per length Pi cos theta (1, -(1 - gamma) sin theta cos theta/(cos^2 + gamma sin^2)) (for
the flow drive W = q/u^2 - 2 omega2/u, Pi = 2 eps q/u^3 - 6 eps omega2/u^2); the isolated
pillar (kappa -> infinity at fixed Lambda = omega2/kappa) with the drag per length
Lambda z (cos^2 + gamma sin^2, -(1 - gamma) sin cos). Both are solved by method 2's integrator
(unknowns theta1, h1) and by a forward Taylor shooting of their own (unknowns theta'(0) and
the base forces), which must agree to ``AGREE_TOL``. At theta0 = 0 and small load the linear
tip deflection x1_lin = int_0^1 p(z) (z^2/2 - z^3/6) dz with the linear Brinkman profile's drag
p = w/kappa, w = A sinh(z/l) + Pi kappa (1 - cosh(z/l)), l = sqrt(kappa), A from the gap.

Checks (the generator stops rather than write a value that fails one):

1. the two methods agree on h1, x1, theta1, theta'(0), Q(0), Q(1), w(1), Pi, F_x(0), F_z(0)
   to ``AGREE_TOL`` (relative to max(1, |value|));
2. method 1's residuals below ``RESIDUAL_TOL`` (relative to the load scale);
3. the identities: the horizontal force balance F_x(0) = Q(1) - Q(0) + Pi h1 and the base
   moment theta'(0) = int_0^1 (z f_x - x f_z) ds (integrated alongside) to ``IDENTITY_TOL``;
4. |theta| < pi/2 on the whole hair (the model's z(s) is monotone); max |theta| is found
   from the Taylor series (interior zeros of theta').

Numbers are written as strings with ``OUT_DIGITS`` significant digits; the inputs are JSON
numbers (binary doubles, converted exactly). The header records each state's working digits
and run time.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import multiprocessing
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

__all__ = ["build_cases", "compute_case", "main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "porous_mpmath.json"
#: Working digits of both methods before the amplification digits of method 1.
DPS = 50
#: Target accuracy [decimal digits] of each integration of method 1 (forward Taylor).
DIGITS = 44
#: Working digits and target accuracy of method 2 (the extrapolation table amplifies
#: rounding by up to ~1e15 with 14 columns: the margin).
DPS2 = 60
DIGITS2 = 38
#: Significant digits written out.
OUT_DIGITS = 32
AGREE_TOL = mpf("1e-25")
RESIDUAL_TOL = mpf("1e-38")
IDENTITY_TOL = mpf("1e-30")
#: Extrapolation columns of the backward Gragg-Bulirsch-Stoer integrator (full precision).
GBS_COLUMNS = 14
#: The same in double precision (the scan).
GBS_COLUMNS_FLOAT = 7
SCAN_TOL = 1e-11
#: Below this kappa the double-precision scan fails (the fluid's growing mode): states are
#: continued in kappa along their series by ``nested_forward`` and checked by forward GBS.
SCAN_MIN_KAPPA = 1e-2
#: Digits of log Q(0) in the inner solve of ``nested_forward`` (method 1 polishes after).
NESTED_DIGITS = 14
#: The slenderness L/a of the Gray & Hancock ratio used as the second gamma.
SLENDERNESS = 20

Vec = list[Any]


def gray_hancock_gamma(slenderness: int) -> mpf:
    """zeta_par/zeta_perp of Gray & Hancock (1955): (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1)."""
    lg = mp.log(2 * mpf(slenderness))
    return (lg + mpf(1) / 2) / (2 * lg - 1)


# ------------------------------------------------------------------------------------------
# The model's right-hand sides (pointwise; generic over float and mpf)
# ------------------------------------------------------------------------------------------


class Model:
    """The parameters of one state, in one number type (float or mpf)."""

    def __init__(self, case: dict[str, Any], num: Callable[[Any], Any]) -> None:
        self.num = num
        self.kappa = num(case["kappa"])
        self.gamma = num(case["gamma"])
        self.eps = num(case["eps"])
        self.theta0 = num(case["theta0"])
        self.omega2 = num(case["omega2"])
        self.Pi = num(case.get("pi", 0.0))
        self.q = num(case["q"]) if case["drive"] == "flow" else None
        self.drive = case["drive"]
        if num is float:
            self.sin, self.cos = math.sin, math.cos
        else:
            self.sin, self.cos = mp.sin, mp.cos

    def rhs(self, Pi: Any) -> Callable[[Any, Vec], Vec]:
        """y = (theta, m, x, z, w, Q, F_x, F_z, Phi, M) with Phi' = w C, M' = z f_x - x f_z."""
        kappa, g1 = self.kappa, 1 - self.gamma
        sin, cos = self.sin, self.cos

        def f(_s: Any, y: Vec) -> Vec:
            th, m, x, z, w, Q, Fx, Fz = y[:8]
            S, C = sin(th), cos(th)
            wk = w / kappa
            fx = wk * (1 - g1 * S * S)
            fz = -wk * g1 * S * C
            return [m, -(Fx * C - Fz * S), S, C, C * Q, fx - Pi * C, -fx, -fz, w * C,
                    z * fx - x * fz]  # fmt: skip

        return f

    def gap_Q1(self, w1: Any, h1: Any, omega2: Any, Pi: Any) -> Any:
        """Q(1) from the gap condition."""
        u = 1 - self.eps * h1
        rest = omega2 - self.eps * w1
        if self.drive != "wall":
            rest += Pi * u * u / (2 * self.eps)
        return rest / u

    def flux(self, phi_bed: Any, w1: Any, Q1: Any, h1: Any, Pi: Any) -> Any:
        """q = 6 eps^2 Phi."""
        g = 1 / self.eps - h1
        phi = phi_bed + w1 * g + Q1 * g * g / 2 - Pi * g**3 / 6
        return 6 * self.eps**2 * phi


# ------------------------------------------------------------------------------------------
# Method 2's integrator: Gragg-Bulirsch-Stoer
# ------------------------------------------------------------------------------------------


def _midpoint(f: Callable, s: Any, y: Vec, fy: Vec, H: Any, n: int) -> Vec:
    h = H / n
    z0 = y
    z1 = [a + h * b for a, b in zip(y, fy)]
    for i in range(1, n):
        fz = f(s + i * h, z1)
        z0, z1 = z1, [a + 2 * h * b for a, b in zip(z0, fz)]
    fz = f(s + H, z1)
    return [(a + b + h * c) / 2 for a, b, c in zip(z0, z1, fz)]


def gbs(
    f: Callable, y: Vec, s0: Any, s1: Any, tol: Any, cols: int, floors: Sequence[Any]
) -> tuple[Vec, int]:
    """y(s1) from y(s0) = y: extrapolated modified midpoint, steps adaptive (relative error
    to max(floor, |y|) per component below tol). Returns (y(s1), the number of steps)."""
    seq = [2 * (j + 1) for j in range(cols)]
    s = s0
    span = s1 - s0
    H = span / 16
    nsteps = 0
    expo = 1.0 / (2 * cols - 1)
    while True:
        rest = s1 - s
        last = abs(H) >= abs(rest)
        if last:
            H = rest
        fy = f(s, y)
        table: list[list[Vec]] = []
        for j, n in enumerate(seq):
            row = [_midpoint(f, s, y, fy, H, n)]
            for lvl in range(1, j + 1):
                # (n_j/n_{j-l})^2 - 1 as a ratio of integers: exact in any precision
                nm2 = seq[j - lvl] ** 2
                dn2 = n * n - nm2
                row.append(
                    [a + (a - b) * nm2 / dn2 for a, b in zip(row[lvl - 1], table[j - 1][lvl - 1])]
                )
            table.append(row)
        best, prev = table[-1][-1], table[-1][-2]
        err = max(
            abs(a - b) / max(fl, abs(a), abs(c)) for a, b, c, fl in zip(best, prev, y, floors)
        )
        if not (err == err) or err == math.inf:  # NaN/inf in floats
            H = H / 4
            if abs(H) < abs(span) * 1e-12:
                raise ArithmeticError("GBS step underflow")
            continue
        if err <= tol:
            y = best
            nsteps += 1
            if last:
                return y, nsteps
            s = s + H
        fac = 4.0 if err == 0 else min(4.0, max(0.2, 0.8 * float(tol / err) ** expo))
        H = H * fac


# ------------------------------------------------------------------------------------------
# Linear algebra and Newton's method (generic)
# ------------------------------------------------------------------------------------------


def solve_linear(A: list[Vec], b: Vec) -> Vec:
    """Gaussian elimination with row equilibration and partial pivoting."""
    n = len(b)
    M = []
    for i in range(n):
        sc = max(abs(v) for v in A[i])
        if sc == 0:
            raise ZeroDivisionError("singular Jacobian row")
        M.append([v / sc for v in A[i]] + [b[i] / sc])
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(M[i][k]))
        M[k], M[p] = M[p], M[k]
        if M[k][k] == 0:
            raise ZeroDivisionError("singular Jacobian")
        for i in range(k + 1, n):
            fac = M[i][k] / M[k][k]
            if fac:
                M[i] = [a - fac * c for a, c in zip(M[i], M[k])]
    x = [0] * n
    for i in reversed(range(n)):
        x[i] = (M[i][n] - sum(M[i][j] * x[j] for j in range(i + 1, n))) / M[i][i]
    return x


def _norm(r: Vec) -> Any:
    return max(abs(v) for v in r)


def newton(
    F: Callable[[Vec], Vec],
    u: Vec,
    hrel: Any,
    typ: Vec,
    xtol: Any,
    rtol: Any = 0,
    rescale: bool = False,
    maxit: int = 40,
) -> tuple[Vec, Vec, int]:
    """Newton's method with a finite-difference Jacobian, reused while the residual falls
    tenfold per step, halving the step when it does not fall.

    Column j's step is hrel * max(|u_j|, typ_j); with ``rescale`` it is rescaled until its
    effect on the residual is about hrel (for unknowns of unknown scale, such as Q(0) under
    exponential growth). Converged when the scaled Newton step is below xtol or the residual
    below rtol. Returns (u, residual, evaluations)."""
    r = F(u)
    nfev = 1
    n = len(u)
    typ = list(typ)
    J: list[Vec] | None = None
    wts: Vec = [1] * n
    fresh = False
    for _ in range(maxit):
        if _norm(r) <= rtol:
            return u, r, nfev
        if J is None:
            cols = []
            for j in range(n):
                step = hrel * max(abs(u[j]), typ[j])
                for _attempt in range(6):
                    up = list(u)
                    up[j] = u[j] + step
                    rp = F(up)
                    nfev += 1
                    if not rescale:
                        break
                    eff = _norm([a - b for a, b in zip(rp, r)])
                    ratio = eff / hrel if eff else 1e-12
                    if 1e-2 < ratio < 1e2:
                        break
                    step = step / ratio
                    typ[j] = abs(step) / hrel
                cols.append([(a - b) / step for a, b in zip(rp, r)])
            J = [[cols[j][i] for j in range(n)] for i in range(n)]
            wts = [
                1 / max(abs(J[i][j]) * max(abs(u[j]), typ[j]) for j in range(n)) for i in range(n)
            ]
            fresh = True
        d = solve_linear(J, [-v for v in r])
        dn = max(abs(d[j]) / max(abs(u[j]), typ[j]) for j in range(n))
        if dn <= xtol:
            return [a + b for a, b in zip(u, d)], r, nfev
        nr = _norm([a * b for a, b in zip(r, wts)])
        lam = 1.0
        accepted = False
        for _half in range(10):
            un = [a + lam * b for a, b in zip(u, d)]
            try:
                rn = F(un)
            except (ArithmeticError, ValueError, OverflowError):
                rn = None
            nfev += 1
            if rn is not None and _norm([a * b for a, b in zip(rn, wts)]) < nr:
                accepted = True
                break
            lam /= 2
        if not accepted:
            if fresh:
                raise ArithmeticError("Newton: no descent")
            J = None
            continue
        contraction = _norm([a * b for a, b in zip(rn, wts)]) / nr
        u, r = un, rn
        fresh = False
        if contraction > 0.1 or lam != 1:
            J = None
    raise ArithmeticError(f"Newton: no convergence in {maxit} iterations")


# ------------------------------------------------------------------------------------------
# Method 2: backward shooting (float for the scan, mpf for the reference)
# ------------------------------------------------------------------------------------------


def load_scale(*loads: Any) -> Any:
    return max([abs(v) for v in loads if v is not None] + [1e-30])


def _floors(model: Model, Ls: Any) -> list[Any]:
    one = model.num(1)
    lf = Ls * min(one, 1 / model.kappa)
    return [one, lf, one, one, Ls, Ls, lf, lf, Ls, lf]


def shoot_back(
    model: Model, th1: Any, h1: Any, w1: Any, omega2: Any, Pi: Any, cols: int, tol: Any
) -> tuple[Vec, Any]:
    """y(0) from the tip state; x is integrated from x(1) = 0 (so x1 = -x(0)),
    Phi and M from 0 at the tip. Returns (y(0), Q(1))."""
    Q1 = model.gap_Q1(w1, h1, omega2, Pi)
    zero = model.num(0)
    y1 = [th1, zero, zero, h1, w1, Q1, zero, zero, zero, zero]
    Ls = load_scale(omega2, Pi, Q1)
    y0, _n = gbs(model.rhs(Pi), y1, model.num(1), zero, tol, cols, _floors(model, Ls))
    return y0, Q1


def loads_of(model: Model, L: Any, Pi_u: Any, target: dict[str, Any]) -> tuple[Any, Any, Any]:
    """(omega2, Pi, q) on the scan's ray: the drive's load L, the others scaled with it."""
    if model.drive == "wall":
        return L, model.num(0), None
    if model.drive == "pressure":
        return L * model.num(target["omega2"]) / model.num(target["pi"]), L, None
    return L * model.num(target["omega2"]) / model.num(target["q"]), Pi_u, L


def back_residual(
    model: Model, th1: Any, h1: Any, w1: Any, omega2: Any, Pi: Any, q: Any, cols: int, tol: Any
) -> tuple[Vec, Vec, Any]:
    y0, Q1 = shoot_back(model, th1, h1, w1, omega2, Pi, cols, tol)
    r = [y0[0] - model.theta0, y0[3], y0[4]]
    if model.drive == "flow":
        r.append(model.flux(-y0[8], w1, Q1, h1, Pi) - q)
    return r, y0, Q1


def target_load(case: dict[str, Any]) -> float:
    return {"wall": case["omega2"], "pressure": case.get("pi", 0.0), "flow": case.get("q", 0.0)}[
        case["drive"]
    ]


class Scan:
    """The family of states parametrised by theta1 (double precision)."""

    def __init__(self, case: dict[str, Any]) -> None:
        self.case = case
        self.model = Model(case, float)
        self.flow = case["drive"] == "flow"

    def residual(self, th1: float, v: list[float]) -> list[float]:
        m = self.model
        h1, w1, L = v[:3]
        omega2, Pi, q = loads_of(m, L, v[3] if self.flow else None, self.case)
        r, _y0, _Q1 = back_residual(m, th1, h1, w1, omega2, Pi, q, GBS_COLUMNS_FLOAT, SCAN_TOL)
        return r

    def solve_at(self, th1: float, guess: list[float], Ls: float) -> list[float]:
        typ = [1.0, Ls, Ls] + ([Ls] if self.flow else [])
        v, _r, _n = newton(lambda v: self.residual(th1, v), guess, 1e-7, typ, 1e-10, maxit=25)
        return v

    def run(self, L_stop: float, dmax: float = 0.04) -> list[tuple[float, list[float]]]:
        th0 = float(self.case["theta0"])
        Ls = max(abs(L_stop), 1e-12)
        pts: list[tuple[float, list[float]]] = [
            (th0, [math.cos(th0), 0.0, 0.0] + ([0.0] if self.flow else []))
        ]
        dth = min(0.01, dmax)
        top = math.pi / 2 - 0.004
        while True:
            th = pts[-1][0] + dth
            if th > top:
                break
            if len(pts) >= 3:
                (ta, va), (tb, vb), (tc, vc) = pts[-3:]
                guess = [_lagrange3(th, ta, tb, tc, a, b, c) for a, b, c in zip(va, vb, vc)]
            elif len(pts) == 2:
                (ta, va), (tb, vb) = pts[-2:]
                guess = [b + (b - a) * (th - tb) / (tb - ta) for a, b in zip(va, vb)]
            else:
                guess = list(pts[-1][1])
            try:
                v = self.solve_at(th, guess, Ls)
            except (ArithmeticError, ZeroDivisionError, ValueError, OverflowError):
                dth /= 2
                if dth < 1e-6:
                    raise
                continue
            pts.append((th, v))
            dth = min(dmax, dth * 1.6)
            Lv = v[2]
            if Lv > L_stop and all(p[1][2] < Lv for p in pts[:-1]):
                break
        return pts

    def refine(self, pts: list[tuple[float, list[float]]], i: int, L: float) -> list[float]:
        """A float state at the load L between scan points i and i+1: [th1, h1, w1(, Pi)]."""
        (ta, va), (tb, vb) = pts[i], pts[i + 1]
        t = (L - va[2]) / (vb[2] - va[2])
        guess = [ta + t * (tb - ta)] + [a + t * (b - a) for a, b in zip(va, vb)]
        guess = guess[:3] + (guess[4:5] if self.flow else [])
        return guess


def _lagrange3(t: float, a: float, b: float, c: float, fa: float, fb: float, fc: float) -> float:
    return (
        fa * (t - b) * (t - c) / ((a - b) * (a - c))
        + fb * (t - a) * (t - c) / ((b - a) * (b - c))
        + fc * (t - a) * (t - b) / ((c - a) * (c - b))
    )


def crossings(pts: list[tuple[float, list[float]]], L: float) -> list[int]:
    return [i for i in range(len(pts) - 1) if (pts[i][1][2] - L) * (pts[i + 1][1][2] - L) < 0]


def folds(pts: list[tuple[float, list[float]]]) -> list[tuple[float, float]]:
    """Local extrema of L(theta1) among the scan points: (theta1, L) of the parabola's
    vertex through the three points around each."""
    out = []
    for i in range(1, len(pts) - 1):
        (ta, va), (tb, vb), (tc, vc) = pts[i - 1 : i + 2]
        if (vb[2] - va[2]) * (vc[2] - vb[2]) < 0:
            d1 = (vb[2] - va[2]) / (tb - ta)
            d2 = (vc[2] - vb[2]) / (tc - tb)
            c2 = (d2 - d1) / (tc - ta)
            tv = (ta + tb) / 2 - d1 / (2 * c2)
            out.append((tv, va[2] + d1 * (tv - ta) + c2 * (tv - ta) * (tv - tb)))
    return out


def method2(case: dict[str, Any], guess: list[float], dps: int) -> dict[str, Any]:
    """Backward GBS shooting at full precision, theta1 free."""
    mp.dps = dps
    m = Model(case, mpf)
    flow = m.drive == "flow"
    tol = mpf(10) ** (-DIGITS2)
    q = m.q

    def F(u: Vec) -> Vec:
        Pi = u[3] if flow else m.Pi
        r, _y0, _Q1 = back_residual(m, u[0], u[1], u[2], m.omega2, Pi, q, GBS_COLUMNS, tol)
        return r

    Ls = load_scale(m.omega2, m.Pi, q)
    u0 = [mpf(g) for g in guess]
    typ = [mpf(1), mpf(1), Ls] + ([Ls] if flow else [])
    u, _r, nfev = newton(F, u0, mpf(10) ** (-(DIGITS2 // 2)), typ, mpf(10) ** (-(DIGITS2 - 2)))
    Pi = u[3] if flow else m.Pi
    r, y0, Q1 = back_residual(m, u[0], u[1], u[2], m.omega2, Pi, q, GBS_COLUMNS, tol)
    return {
        "theta1": u[0], "h1": u[1], "w1": u[2], "Q1": Q1, "pi": Pi,
        "x1": -y0[2], "m0": y0[1], "Q0": y0[5], "Fx0": y0[6], "Fz0": y0[7],
        "phi_bed": -y0[8], "nfev": nfev, "residual": r,
    }  # fmt: skip


# ------------------------------------------------------------------------------------------
# Method 1: forward Taylor shooting (mpf)
# ------------------------------------------------------------------------------------------


def _horner(cs: list[mpf], t: mpf) -> mpf:
    acc = cs[-1]
    for c in reversed(cs[:-1]):
        acc = acc * t + c
    return acc


def _poly_root(cs: list[mpf], a: mpf, b: mpf) -> mpf:
    """A root of the polynomial in [a, b] (sign change), by bisection then Newton."""
    fa = _horner(cs, a)
    for _ in range(40):
        c = (a + b) / 2
        fc = _horner(cs, c)
        if (fc < 0) == (fa < 0):
            a, fa = c, fc
        else:
            b = c
    t = (a + b) / 2
    der = [k * cs[k] for k in range(1, len(cs))]
    for _ in range(12):
        t -= _horner(cs, t) / _horner(der, t)
    return t


def taylor_forward(
    m: Model, Pi: mpf, y0: Vec, order: int, tol: mpf, floors: Vec
) -> tuple[Vec, mpf, int]:
    """y(1) from y(0) by the Taylor series method; also max |theta| on [0, 1]."""
    kappa, g1 = m.kappa, 1 - m.gamma
    delta = mp.sqrt(kappa)
    fdot = mp.fdot
    s = mpf(0)
    y = list(y0)
    maxth = abs(y[0])
    nsteps = 0
    inv = [mpf(1) / (k + 1) for k in range(order)]
    while True:
        T, M, X, Z, W, Qs, FX, FZ, PH, MO = ([v] for v in y)
        S, C = [mp.sin(y[0])], [mp.cos(y[0])]
        A: list[mpf] = []
        SC: list[mpf] = []
        fx: list[mpf] = []
        fz: list[mpf] = []
        for k in range(order):
            r = inv[k]
            SSk = fdot(S, S[::-1])
            SC.append(fdot(S, C[::-1]))
            A.append((1 if k == 0 else 0) - g1 * SSk)
            fx.append(fdot(W, A[::-1]) / kappa)
            fz.append(-g1 * fdot(W, SC[::-1]) / kappa)
            T.append(M[k] * r)
            M.append(-(fdot(FX, C[::-1]) - fdot(FZ, S[::-1])) * r)
            X.append(S[k] * r)
            Z.append(C[k] * r)
            Cm = fdot(C, M[k::-1])
            Sm = fdot(S, M[k::-1])
            W.append(fdot(C, Qs[::-1]) * r)
            Qs.append((fx[k] - Pi * C[k]) * r)
            FX.append(-fx[k] * r)
            FZ.append(-fz[k] * r)
            PH.append(fdot(W[: k + 1], C[::-1]) * r)
            MO.append((fdot(Z[: k + 1], fx[::-1]) - fdot(X[: k + 1], fz[::-1])) * r)
            S.append(Cm * r)
            C.append(-Sm * r)
        series = (T, M, X, Z, W, Qs, FX, FZ, PH, MO)
        h = mpf(1) - s
        scales = [max(fl, abs(cs[0])) for cs, fl in zip(series, floors)]
        # w ~ delta Q in the fluid's modes: each scaled by the other too (relative control)
        scales[4] = max(scales[4], delta * abs(Qs[0]))
        scales[5] = max(scales[5], abs(W[0]) / delta)
        for cs, sc in zip(series, scales):
            for j in (order, order - 1):
                if cs[j] != 0:
                    h = min(h, (tol * sc / abs(cs[j])) ** (mpf(1) / j) * mpf("0.7"))
        last = s + h >= 1
        if last:
            h = 1 - s
        ynew = [_horner(cs, h) for cs in series]
        mh = ynew[1]
        if M[0] * mh < 0:
            root = _poly_root(M, mpf(0), h)
            maxth = max(maxth, abs(_horner(T, root)))
        maxth = max(maxth, abs(ynew[0]))
        y = ynew
        nsteps += 1
        if last:
            return y, maxth, nsteps
        s += h


def extra_digits(case: dict[str, Any]) -> int:
    """Digits lost to the growth exp(s/sqrt(kappa)) of the fluid's mode from the base.

    Without a pressure gradient (the wall drive) the fluid's equations are homogeneous in
    (w, Q): controlled relative to their own size their errors stay relative, and no digits
    are lost; with Pi the forcing Pi cos theta makes the errors absolute."""
    if case["drive"] == "wall":
        return 0
    return int(math.ceil(math.log10(math.e) / math.sqrt(float(case["kappa"])))) + 3


def forward_setup(case: dict[str, Any], Ls_hint: Any, integrator: str) -> tuple[Callable, dict]:
    """The forward shooting's residual function (scaled by the load) for one integrator:
    "taylor" (method 1) or "gbs" (the second method below kappa = 1e-2), at its precision."""
    extra = extra_digits(case)
    if integrator == "taylor":
        dps, digits = DPS + extra, DIGITS + extra
    else:
        dps, digits = DPS2 + extra, DIGITS2 + extra
    mp.dps = dps
    m = Model(case, mpf)
    flow = m.drive == "flow"
    tol = mpf(10) ** (-digits)
    order = max(40, min(240, int(1.3 * digits)))
    q = m.q
    Ls = load_scale(m.omega2, m.Pi, q, mpf(Ls_hint))
    floors = _floors(m, Ls)
    if m.drive == "wall":
        floors[4] = floors[5] = Ls * mpf(10) ** (-dps)

    def run(u: Vec) -> tuple[Vec, mpf, Vec, Any]:
        Pi = u[4] if flow else m.Pi
        y0 = [m.theta0, u[0], mpf(0), mpf(0), mpf(0), u[1], u[2], u[3], mpf(0), mpf(0)]
        if integrator == "taylor":
            y1, maxth, _n = taylor_forward(m, Pi, y0, order, tol, floors)
        else:
            y1, _n = gbs(m.rhs(Pi), y0, mpf(0), mpf(1), tol, GBS_COLUMNS, floors)
            maxth = mpf(-1)
        h1, w1, Q1 = y1[3], y1[4], y1[5]
        uu = 1 - m.eps * h1
        gap = m.eps * w1 + uu * Q1 - m.omega2
        if m.drive != "wall":
            gap -= Pi * uu * uu / (2 * m.eps)
        r = [y1[1], y1[6], y1[7], gap]
        if flow:
            r.append(m.flux(y1[8], w1, Q1, h1, Pi) - q)
        return [v / Ls for v in r], maxth, y1, Pi

    info = dict(dps=dps, extra=extra, order=order, Ls=Ls, flow=flow, digits=digits)
    return run, info


def forward_solve(case: dict[str, Any], start: dict[str, Any], integrator: str) -> dict[str, Any]:
    """Forward shooting (Newton on theta'(0), Q(0), F_x(0), F_z(0) (, Pi)) from ``start``."""
    run, info = forward_setup(case, start["Q1"], integrator)
    dps, extra, Ls, flow = info["dps"], info["extra"], info["Ls"], info["flow"]
    u0 = [mpf(start[k]) for k in ("m0", "Q0", "Fx0", "Fz0")] + ([start["pi"]] if flow else [])
    typ = [mpf(1), Ls * mpf(10) ** (-extra), Ls, Ls] + ([Ls] if flow else [])
    hrel = mpf(10) ** (-((dps - extra) // 2))
    u, _r, nfev = newton(
        lambda u: run(u)[0], u0, hrel, typ, mpf(0), rtol=RESIDUAL_TOL / 10, rescale=True
    )
    r, maxth, y1, Pi = run(u)
    return {
        "theta1": y1[0], "h1": y1[3], "w1": y1[4], "Q1": y1[5], "pi": Pi, "x1": y1[2],
        "m0": u[0], "Q0": u[1], "Fx0": u[2], "Fz0": u[3], "phi_bed": y1[8], "moment": y1[9],
        "max_abs_theta": maxth, "residual": max(abs(v) for v in r), "nfev": nfev,
        "dps": dps, "order": info["order"],
    }  # fmt: skip


def method1(case: dict[str, Any], start: dict[str, Any]) -> dict[str, Any]:
    """Forward Taylor shooting at DPS + extra digits, Newton from ``start``."""
    return forward_solve(case, start, "taylor")


def _illinois(f: Callable, a: mpf, fa: mpf, b: mpf, fb: mpf, xtol: mpf) -> mpf:
    """A root of f in [a, b] (f(a) f(b) < 0) by the Illinois variant of regula falsi."""
    side = 0
    for _ in range(400):
        c = (a * fb - b * fa) / (fb - fa)
        fc = f(c)
        if fc == 0 or abs(b - a) <= xtol:
            return c
        if (fc > 0) == (fb > 0):
            b, fb = c, fc
            if side == -1:
                fa /= 2
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb /= 2
            side = 1
        if abs(b - a) <= xtol:
            return (a + b) / 2
    raise ArithmeticError("Illinois: no convergence")


def nested_forward(case: dict[str, Any], guess: dict[str, Any]) -> dict[str, Any]:
    """Forward Taylor shooting for a small kappa from a rough guess (the state at a larger
    kappa): the fluid's growing mode makes Q(0) exponentially sensitive, so Q(0) is first
    solved alone (the gap condition, by bracketing in log Q(0), the others fixed) inside a
    Newton iteration on theta'(0), F_x(0), F_z(0) (the tip conditions); then all four by
    ``forward_solve``. The wall drive only (Q(0) > 0, and no digits lost)."""
    if case["drive"] != "wall":
        raise ValueError("nested_forward: the wall drive only")
    run, info = forward_setup(case, guess["Q1"], "taylor")
    state = {"x": mp.log(mpf(guess["Q0"]))}

    def gap(v: Vec, x: mpf) -> mpf:
        return run([v[0], mp.exp(x), v[1], v[2]])[0][3]

    def inner(v: Vec) -> mpf:
        x = state["x"]
        g0 = gap(v, x)
        step = mpf(1) if abs(g0) > mpf("1e-6") else mpf("1e-8")
        direction = -1 if g0 > 0 else 1
        for _ in range(200):
            x1 = x + direction * step
            g1 = gap(v, x1)
            if (g1 > 0) != (g0 > 0):
                break
            x, g0 = x1, g1
            step *= 2
        else:
            raise ArithmeticError("nested_forward: no bracket for Q(0)")
        root = _illinois(lambda t: gap(v, t), x, g0, x1, g1, mpf(10) ** (-NESTED_DIGITS))
        state["x"] = root
        return root

    def outer(v: Vec) -> Vec:
        x = inner(v)
        r = run([v[0], mp.exp(x), v[1], v[2]])[0]
        return [r[0], r[1], r[2]]

    v0 = [mpf(guess[k]) for k in ("m0", "Fx0", "Fz0")]
    Ls = info["Ls"]
    v, _r, _n = newton(outer, v0, mpf(10) ** (-7), [mpf(1), Ls, Ls], mpf(10) ** (-9))
    x = inner(v)
    start = {"m0": v[0], "Q0": mp.exp(x), "Fx0": v[1], "Fz0": v[2], "Q1": guess["Q1"]}
    return method1(case, start)


# ------------------------------------------------------------------------------------------
# The limits: dense bed (kappa -> 0), isolated pillar (kappa -> infinity), linear theory
# ------------------------------------------------------------------------------------------


def dense_loads(case: dict[str, Any], h1: Any, num: Callable) -> tuple[Any, Any]:
    """(W, Pi) of the dense limit at the tip height h1."""
    eps, omega2 = num(case["eps"]), num(case["omega2"])
    u = 1 - eps * h1
    if case["drive"] == "wall":
        return omega2 / u, num(0)
    if case["drive"] == "pressure":
        Pi = num(case["pi"])
        return omega2 / u + Pi * u / (2 * eps), Pi
    q = num(case["q"])
    return q / u**2 - 2 * omega2 / u, 2 * eps * q / u**3 - 6 * eps * omega2 / u**2


def limit_rhs(case: dict[str, Any], kind: str, num: Callable, Pi: Any) -> Callable:
    """y = (theta, m, x, z, F_x, F_z) of the dense (interior drag Pi cos theta) or pillar
    (drag Lambda z) limit."""
    g1 = 1 - num(case["gamma"])
    sin, cos = (math.sin, math.cos) if num is float else (mp.sin, mp.cos)
    lam = num(case["omega2"]) / num(case["kappa"])

    def f(_s: Any, y: Vec) -> Vec:
        th, m, _x, z, Fx, Fz = y
        S, C = sin(th), cos(th)
        a = 1 - g1 * S * S
        if kind == "dense":
            fx, fz = Pi * C, -Pi * g1 * S * C * C / a
        else:
            fx, fz = lam * z * a, -lam * z * g1 * S * C
        return [m, -(Fx * C - Fz * S), S, C, -fx, -fz]

    return f


def limit_tip(case: dict[str, Any], kind: str, th1: Any, h1: Any, num: Callable) -> tuple:
    """(F_x(1), F_z(1), Pi) just below the tip."""
    if kind == "pillar":
        return num(0), num(0), num(0)
    W, Pi = dense_loads(case, h1, num)
    g = num(case["gamma"])
    S, C = (math.sin(th1), math.cos(th1)) if num is float else (mp.sin(th1), mp.cos(th1))
    r1 = (1 - g) * S * C / (C * C + g * S * S)
    return W, -W * r1, Pi


def solve_limit(case: dict[str, Any], kind: str, guess: tuple[float, float]) -> dict[str, Any]:
    """The limit's state by backward shooting (unknowns theta1, h1), then re-integrated
    forward from its base values (a second integration that must return to the tip)."""
    out: dict[str, Any] = {}
    u: Vec = list(guess)
    for num, dps, cols, digits in (
        (float, 15, GBS_COLUMNS_FLOAT, 11),
        (mpf, DPS2, GBS_COLUMNS, DIGITS2),
    ):
        mp.dps = dps
        tol = 10.0 ** (-digits) if num is float else mpf(10) ** (-digits)

        def shoot(v: Vec, num: Callable = num, tol: Any = tol, cols: int = cols) -> Vec:
            Fx1, Fz1, Pi = limit_tip(case, kind, v[0], v[1], num)
            y1 = [v[0], num(0), num(0), v[1], Fx1, Fz1]
            f = limit_rhs(case, kind, num, Pi)
            y0, _n = gbs(f, y1, num(1), num(0), tol, cols, [num(1)] * 6)
            return y0

        def F(v: Vec, shoot: Callable = shoot, num: Callable = num) -> Vec:
            y0 = shoot(v)
            return [y0[0] - num(case["theta0"]), y0[3]]

        u = [num(v) for v in u]
        hrel = 1e-7 if num is float else mpf(10) ** (-(digits // 2))
        xtol = 1e-10 if num is float else mpf(10) ** (-(digits - 2))
        u, _r, _n = newton(F, u, hrel, [num(1), num(1)], xtol)
    y0 = shoot(u)
    Fx1, Fz1, Pi = limit_tip(case, kind, u[0], u[1], mpf)
    # forward re-integration from the base values: back to the tip conditions
    yb = [mpf(case["theta0"]), y0[1], mpf(0), mpf(0), y0[4], y0[5]]
    tol = mpf(10) ** (-DIGITS2)
    y1, _n = gbs(limit_rhs(case, kind, mpf, Pi), yb, mpf(0), mpf(1), tol, GBS_COLUMNS, [1] * 6)
    back = max(
        abs(y1[0] - u[0]), abs(y1[1]), abs(y1[3] - u[1]), abs(y1[4] - Fx1), abs(y1[5] - Fz1)
    )
    if back > mpf("1e-28"):
        raise ArithmeticError(f"limit {kind}: forward re-integration misses the tip by {back}")
    out.update(
        kind=kind, theta1=u[0], h1=u[1], x1=-y0[2], base_curvature=y0[1], drag_x=y0[4],
        drag_z=y0[5], tip_force_x=Fx1, tip_force_z=Fz1, interior_pi=Pi, reintegration=back,
    )  # fmt: skip
    return out


def linear_tip_deflection(case: dict[str, Any]) -> mpf:
    """x1 of the linear theory at theta0 = 0: the straight hair in the linear Brinkman
    profile w = A sinh(z/l) + Pi kappa (1 - cosh(z/l)), l = sqrt(kappa), with the gap
    condition at h1 = 1; x1 = int_0^1 (w/kappa) (z^2/2 - z^3/6) dz."""
    kappa, eps = mpf(case["kappa"]), mpf(case["eps"])
    omega2, Pi = mpf(case["omega2"]), mpf(case.get("pi", 0.0))
    ell = mp.sqrt(kappa)
    sh, ch = mp.sinh(1 / ell), mp.cosh(1 / ell)
    # gap: eps w(1) + (1 - eps) w'(1) - Pi (1 - eps)^2/(2 eps) = omega2
    rhs = omega2 - eps * Pi * kappa * (1 - ch) + (1 - eps) * Pi * ell * sh
    if case["drive"] != "wall":
        rhs += Pi * (1 - eps) ** 2 / (2 * eps)
    A = rhs / (eps * sh + (1 - eps) * ch / ell)

    def p(z: mpf) -> mpf:
        return (A * mp.sinh(z / ell) + Pi * kappa * (1 - mp.cosh(z / ell))) / kappa

    return mp.quad(
        lambda z: p(z) * (z**2 / 2 - z**3 / 6), [0, 1 - 10 * ell, 1] if ell < 0.05 else [0, 1]
    )


# ------------------------------------------------------------------------------------------
# One job: scan, every state at the load, both methods, checks
# ------------------------------------------------------------------------------------------


def _str(v: Any) -> str:
    return mp.nstr(mpf(v), OUT_DIGITS, strip_zeros=False, min_fixed=-4, max_fixed=6)


def state_record(
    case: dict[str, Any], L: float, r1: dict[str, Any], r2: dict[str, Any], t1: float, t2: float
) -> dict[str, Any]:
    """The checks (module docstring) and the written record of one state."""
    mp.dps = r1["dps"]
    keys = ("h1", "x1", "theta1", "m0", "Q0", "Q1", "w1", "pi", "Fx0", "Fz0", "phi_bed")
    diffs = {k: abs(mpf(r1[k]) - mpf(r2[k])) / max(1, abs(mpf(r1[k]))) for k in keys}
    agree = max(diffs.values())
    if not agree < AGREE_TOL:
        raise ArithmeticError(f"methods disagree by {agree}: {case} {diffs}")
    if not r1["residual"] < RESIDUAL_TOL:
        raise ArithmeticError(f"residual {r1['residual']}: {case}")
    Pi = mpf(r1["pi"])
    balance = r1["Fx0"] - (r1["Q1"] - r1["Q0"] + Pi * r1["h1"])
    moment = r1["m0"] - r1["moment"]
    Ls = load_scale(mpf(case["omega2"]), Pi, r1["Q1"])
    if abs(balance) > IDENTITY_TOL * Ls or abs(moment) > IDENTITY_TOL * max(1, abs(r1["m0"])):
        raise ArithmeticError(f"identity fails: {balance} {moment}")
    if not r1["max_abs_theta"] < mp.pi / 2:
        raise ArithmeticError(f"|theta| reaches pi/2: {case}")
    q = m_flux(case, r1) if case["eps"] > 0 else None
    rec = dict(case)
    rec.update(
        load=L, h1=_str(r1["h1"]), x1=_str(r1["x1"]), theta1=_str(r1["theta1"]),
        base_curvature=_str(r1["m0"]), Q0=_str(r1["Q0"]), Q1=_str(r1["Q1"]),
        w1=_str(r1["w1"]), pi_value=_str(Pi), drag_x=_str(r1["Fx0"]),
        drag_z=_str(r1["Fz0"]), flux_bed=_str(r1["phi_bed"]),
        moment_integral=_str(r1["moment"]), max_abs_theta=_str(r1["max_abs_theta"]),
        q_value=None if q is None else _str(q),
        method_difference=mp.nstr(agree, 3), residual=mp.nstr(r1["residual"], 3),
        digits=r1["dps"], taylor_order=r1["order"], method2_digits=r2.get("dps", DPS2),
        seconds_method1=round(t1, 2), seconds_method2=round(t2, 2),
    )  # fmt: skip
    if case["theta0"] == 0.0 and case.get("linear"):
        mp.dps = 40
        rec["x1_linear"] = _str(linear_tip_deflection(case))
    return rec


def solve_states(
    case: dict[str, Any], L: float, pts: list, scan: Scan
) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """Every state at the load L among the scan's crossings, by both methods: the records
    and method 1's raw results."""
    found = crossings(pts, L)
    states, raw = [], []
    for idx, i in enumerate(found):
        t0 = time.time()
        guess = scan.refine(pts, i, L)
        r2 = method2(case, guess, DPS2)
        r2["method2"] = "backward GBS"
        t2 = time.time() - t0
        r1 = method1(case, r2)
        t1 = time.time() - t0 - t2
        rec = state_record(case, L, r1, r2, t1, t2)
        rec.update(
            state_index=idx, states_at_load=len(found), method2="backward GBS shooting",
            label=f"theta1-scan crossing {idx + 1} of {len(found)}",
        )  # fmt: skip
        states.append(rec)
        raw.append(r1)
    return states, raw


def continue_in_kappa(
    case: dict[str, Any], prev: list[tuple[float, dict[str, Any]]]
) -> tuple[dict[str, Any], dict[str, Any]]:
    """A state below SCAN_MIN_KAPPA from the states of its series at larger kappa: the
    guess extrapolated in sqrt(kappa) (log Q(0) linearly in 1/sqrt(kappa)), then
    ``nested_forward`` (method 1) and the forward GBS shooting (the second method)."""
    mp.dps = DPS
    d = mp.sqrt(mpf(case["kappa"]))
    guess: dict[str, Any] = {}
    (ka, ra) = prev[-1]
    if len(prev) >= 2:
        (kb, rb) = prev[-2]
        da, db = mp.sqrt(mpf(ka)), mp.sqrt(mpf(kb))
        t = (d - da) / (db - da)
        for k in ("m0", "Fx0", "Fz0", "Q1"):
            guess[k] = mpf(ra[k]) + t * (mpf(rb[k]) - mpf(ra[k]))
        la, lb = mp.log(mpf(ra["Q0"])), mp.log(mpf(rb["Q0"]))
        tt = (1 / d - 1 / da) / (1 / db - 1 / da)
        guess["Q0"] = mp.exp(la + tt * (lb - la))
    else:
        guess = {k: mpf(ra[k]) for k in ("m0", "Fx0", "Fz0", "Q1")}
        guess["Q0"] = mpf(ra["Q0"]) * mp.exp(-(1 / d - 1 / mp.sqrt(mpf(ka))))
    t0 = time.time()
    r1 = nested_forward(case, guess)
    t1 = time.time() - t0
    r2 = forward_solve(case, r1, "gbs")
    t2 = time.time() - t0 - t1
    rec = state_record(case, target_load(case), r1, r2, t1, t2)
    rec.update(
        state_index=0, states_at_load=1, method2="forward GBS shooting",
        label=f"continued in kappa from kappa = {ka:g}",
    )  # fmt: skip
    return rec, r1


def m_flux(case: dict[str, Any], r1: dict[str, Any]) -> mpf:
    """q = 6 eps^2 Phi of a state (all drives, eps > 0)."""
    eps = mpf(case["eps"])
    g = 1 / eps - r1["h1"]
    phi = r1["phi_bed"] + r1["w1"] * g + r1["Q1"] * g**2 / 2 - mpf(r1["pi"]) * g**3 / 6
    return 6 * eps**2 * phi


def compute_case(job: dict[str, Any]) -> dict[str, Any]:
    """One job: a state (every state at its load), a window, or a limit series."""
    t0 = time.time()
    out: dict[str, Any] = {"name": job["name"], "states": [], "limits": [], "windows": []}
    cases = job["cases"]
    prev: list[dict[str, Any]] = []
    series: list[tuple[float, dict[str, Any]]] = []
    for case in cases:
        if case["kappa"] < SCAN_MIN_KAPPA:
            rec, r1 = continue_in_kappa(case, series)
            rec["job"] = job["name"]
            out["states"].append(rec)
            prev = [rec]
            series.append((case["kappa"], r1))
            continue
        scan = Scan(case)
        if job["kind"] == "window":
            pts = scan.run(job["scan_to"])
            fl = folds(pts)
            if len(fl) != 2:
                raise ArithmeticError(f"window {job['name']}: folds {fl}")
            lo, hi = sorted(f[1] for f in fl)
            L = (lo + hi) / 2
            case = dict(case)
            case[{"wall": "omega2", "pressure": "pi", "flow": "q"}[case["drive"]]] = L
            scan.case = case
            out["windows"].append(
                dict(name=job["name"], folds=[[round(t, 6), round(v, 9)] for t, v in fl],
                     load=L, drive=case["drive"])
            )  # fmt: skip
        else:
            L = target_load(case)
            pts = scan.run(2 * L)
        states, raw = solve_states(case, L, pts, scan)
        if not states:
            raise ArithmeticError(f"no state found: {case}")
        if job["kind"] == "window" and len(states) < 2:
            raise ArithmeticError(f"window {job['name']}: {len(states)} states")
        for st in states:
            st["job"] = job["name"]
        out["states"] += states
        prev = states
        series.append((case["kappa"], raw[0]))
    for kind in job.get("limits", ()):
        ref = prev[0]
        lim = solve_limit(cases[-1], kind, (float(ref["theta1"]), float(ref["h1"])))
        rec = {k: v for k, v in cases[-1].items()}
        rec.update({k: (_str(v) if isinstance(v, mpf) else v) for k, v in lim.items()})
        rec["series"] = job["name"]
        out["limits"].append(rec)
    out["seconds"] = round(time.time() - t0, 1)
    return out


# ------------------------------------------------------------------------------------------
# The cases
# ------------------------------------------------------------------------------------------

GH = float(gray_hancock_gamma(SLENDERNESS))


def _c(kappa: float, drive: str, eps: float, theta0: float, gamma: float, **loads: float) -> dict:
    case: dict[str, Any] = dict(kappa=kappa, drive=drive, eps=eps, theta0=theta0, gamma=gamma)
    case["omega2"] = loads.get("omega2", 0.0)
    if drive != "wall":
        case["pi"] = loads.get("pi", 0.0)
    if drive == "flow":
        case["q"] = loads["q"]
        del case["pi"]
    if loads.get("linear"):
        case["linear"] = True
    return case


def build_cases(quick: bool = False, small_kappa: bool = True) -> list[dict[str, Any]]:
    """The jobs: single states, windows, limit series."""
    jobs: list[dict[str, Any]] = []

    def single(name: str, case: dict[str, Any]) -> None:
        jobs.append(dict(name=name, kind="state", cases=[case]))

    # coverage: kappa 1e-2 .. 1e4, three drives, theta0 -1.2 .. 1.2, eps 0 .. 0.95 (the
    # series below reach kappa = 1e-4 and 1e5)
    cover = [
        _c(1e-4, "wall", 0.5, 0.0, 1.0, omega2=1.0),
        _c(1e-4, "wall", 0.9, 0.6, GH, omega2=2.0),
        _c(1e-3, "wall", 0.0, -0.6, 0.5, omega2=0.5),
        _c(1e-3, "pressure", 0.5, 0.3, 1.0, pi=2.0),
        _c(1e-3, "wall", 0.5, 1.0, 1.0, omega2=0.01),
        _c(0.05, "wall", 0.95, 0.0, GH, omega2=3.0),
        _c(1e-2, "flow", 0.5, 0.0, 1.0, q=1.5),
        _c(1e-2, "pressure", 0.7, -0.5, 0.5, pi=1.0, omega2=0.5),
        _c(0.1, "wall", 0.5, 0.0, 0.5, omega2=20.0),
        _c(0.1, "wall", 0.5, 1.2, 1.0, omega2=0.3),
        _c(0.1, "flow", 0.8, -0.3, GH, q=2.0, omega2=0.3),
        _c(1.0, "wall", 0.5, 0.0, 0.5, omega2=5.0),
        _c(1.0, "pressure", 0.9, 0.9, GH, pi=8.0),
        _c(1.0, "wall", 0.0, -1.2, 1.0, omega2=2.0),
        _c(10.0, "wall", 0.3, -0.9, 1.0, omega2=100.0),
        _c(10.0, "flow", 0.6, 0.4, 0.5, q=20.0),
        _c(100.0, "wall", 0.95, -1.2, GH, omega2=1000.0),
        _c(100.0, "pressure", 0.5, 0.0, 1.0, pi=200.0, omega2=100.0),
        _c(1e3, "flow", 0.9, 0.6, GH, q=5000.0, omega2=1000.0),
        _c(1e3, "wall", 0.5, 1.2, 0.5, omega2=3000.0),
        _c(1e4, "wall", 0.5, 0.3, 1.0, omega2=5e4),
        _c(1e4, "pressure", 0.2, -0.4, GH, pi=4e3),
    ]
    for i, case in enumerate(cover):
        # a single state needs the scan: kappa >= SCAN_MIN_KAPPA (the first five wait for a
        # continuation in kappa of their own; the series below reach kappa = 1e-4)
        if case["kappa"] >= SCAN_MIN_KAPPA:
            single(f"cover{i:02d}", case)
    # small loads at theta0 = 0: the linear theory (two loads each: the cubic remainder)
    for kappa, om in ((1e-2, 3e-3), (1.0, 3e-3), (100.0, 0.3)):
        for gamma in (1.0, GH):
            for f in (1.0, 2.0):
                single(f"linear k={kappa:g} g={gamma:.3f} x{f:g}",
                       _c(kappa, "wall", 0.5, 0.0, gamma, omega2=om * f, linear=True))  # fmt: skip
    # windows: every coexisting state (upstream tilt, tight channel)
    windows = [
        ("window wall k=1e-2", _c(1e-2, "wall", 0.95, -1.2, 1.0), 2.0),
        ("window wall k=2e-2", _c(2e-2, "wall", 0.95, -1.2, 1.0), 2.0),
        ("window flow k=1e-2", _c(1e-2, "flow", 0.95, -1.2, 1.0, q=1.0), 3.0),
    ]
    for name, case, top in windows:
        jobs.append(dict(name=name, kind="window", cases=[case], scan_to=top))
    # limit series: kappa -> 0 (dense) and kappa -> infinity at fixed Lambda (pillar)
    small = (1e-2, 1e-3, 1e-4)
    # below SCAN_MIN_KAPPA only the wall drive (nested_forward); the pressure series go
    # down to 1e-2 in half decades
    half = (1.0, 10**-0.5, 0.1, 10**-1.5, 1e-2)
    big = (1e2, 1e3, 1e4, 1e5)
    series = [
        ("dense wall g=1", lambda k: _c(k, "wall", 0.5, 0.3, 1.0, omega2=2.0), small),
        ("dense wall g=0.5", lambda k: _c(k, "wall", 0.5, 0.3, 0.5, omega2=2.0), small),
        ("dense wall half g=0.5", lambda k: _c(k, "wall", 0.5, 0.3, 0.5, omega2=2.0), half),
        ("dense pressure g=1", lambda k: _c(k, "pressure", 0.5, -0.3, 1.0, pi=2.0), half),
        ("dense pressure g=gh",
         lambda k: _c(k, "pressure", 0.6, 0.0, GH, pi=1.5, omega2=0.5), half),
        ("pillar g=gh", lambda k: _c(k, "wall", 0.5, 0.3, GH, omega2=5.0 * k), big),
        ("pillar g=1", lambda k: _c(k, "wall", 0.8, -0.5, 1.0, omega2=8.0 * k), big),
    ]  # fmt: skip
    for name, make, kappas in series:
        kind = "dense" if name.startswith("dense") else "pillar"
        jobs.append(dict(name=name, kind="series", cases=[make(k) for k in kappas], limits=[kind]))
    if not small_kappa:
        for job in jobs:
            job["cases"] = [c for c in job["cases"] if c["kappa"] >= 1e-2]
            if not job["cases"]:
                job["drop"] = True
            elif job["kind"] == "series" and len(job["cases"]) < 2:
                job["limits"] = []
        jobs = [j for j in jobs if not j.get("drop")]
    if quick:
        keep = {"cover11", "cover03", "window wall k=1e-2 gh"}
        jobs = [j for j in jobs if j["name"] in keep]
    return jobs


def _run(job: dict[str, Any]) -> dict[str, Any]:
    try:
        return compute_case(job)
    except (ArithmeticError, ValueError, ZeroDivisionError, IndexError) as exc:
        return {"name": job["name"], "error": f"{type(exc).__name__}: {exc}"}


def _report(job: dict[str, Any]) -> dict[str, Any]:
    res = _run(job)
    if "error" in res:
        print(f"{res['name']}: FAILED {res['error']}", flush=True)
    else:
        print(f"{res['name']}: {len(res['states'])} states, {res['seconds']} s", flush=True)
    return res


def merge(paths: list[Path], out: Path) -> None:
    """One data file from several runs of separate jobs (the header's lists joined)."""
    docs = [json.loads(p.read_text()) for p in paths]
    doc = dict(docs[-1])  # the header of the newest run
    keys = ("states", "limits", "windows", "per_state")
    lists: dict[str, list[dict[str, Any]]] = {k: [] for k in keys}
    jobs: dict[str, float] = {}

    def owner(x: dict[str, Any]) -> str:
        return x.get("job") or x.get("series") or x["name"]

    for d in docs:
        if d["quick"] or d.get("failed_jobs"):
            raise SystemExit("only complete, non-quick runs can be merged")
        if "per_state" not in d:
            # a file of the first version of this generator (commit a3bf8ab): every state
            # by the backward GBS shooting, no per-state list in the header
            for st in d["states"]:
                st.setdefault("method2", "backward GBS shooting")
            d["per_state"] = [
                {
                    "job": st["job"],
                    "state_index": st["state_index"],
                    "kappa": st["kappa"],
                    "digits_method1": st["digits"],
                    "digits_method2": st["method2_digits"],
                    "method2": st["method2"],
                    "method_difference": st["method_difference"],
                    "seconds_method1": st["seconds_method1"],
                    "seconds_method2": st["seconds_method2"],
                }
                for st in d["states"]
            ]
        names = set(d["seconds_per_job"])
        for k in keys:
            lists[k] = [x for x in lists[k] if owner(x) not in names] + d[k]
        jobs.update(d["seconds_per_job"])
    doc.update(lists)
    order = {j["name"]: i for i, j in enumerate(build_cases(False, True))}

    def rank(x: dict[str, Any]) -> tuple[int, float, int]:
        return (order.get(owner(x), len(order)), -x.get("kappa", 0.0), x.get("state_index", 0))

    for key in ("states", "limits", "windows", "per_state"):
        doc[key] = sorted(doc[key], key=rank)
    doc["seconds_per_job"] = jobs
    doc["seconds_total"] = round(sum(jobs.values()), 1)
    doc["failed_jobs"] = {}
    doc["merged_from_runs"] = len(docs)
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"merged {len(doc['states'])} states, {len(doc['limits'])} limits into {out}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    parser.add_argument("--quick", action="store_true", help="a few cases (smoke test)")
    parser.add_argument("--only", default=None, help="jobs whose name contains this text")
    parser.add_argument("--skip", default=None, help="not the jobs whose name contains this")
    parser.add_argument("--no-small-kappa", action="store_true", help="only kappa >= 1e-2")
    parser.add_argument(
        "--keep-going", action="store_true", help="write the jobs that succeeded, list the rest"
    )
    parser.add_argument(
        "--merge",
        nargs="+",
        type=Path,
        default=None,
        help="combine files written by runs of separate jobs (--only) into --out; later "
        "files replace the jobs of earlier ones",
    )
    args = parser.parse_args(argv)
    if args.merge:
        merge(args.merge, args.out)
        return
    jobs = build_cases(args.quick, not args.no_small_kappa)
    if args.only:
        jobs = [j for j in jobs if args.only in j["name"]]
    if args.skip:
        jobs = [j for j in jobs if args.skip not in j["name"]]
    t0 = time.time()
    results: list[dict[str, Any]] = []
    # longest first (the series continued below SCAN_MIN_KAPPA), so that the workers
    # finish together
    jobs.sort(key=lambda j: -sum(1 + 10 * (c["kappa"] < SCAN_MIN_KAPPA) for c in j["cases"]))
    if args.workers > 1:
        with multiprocessing.Pool(args.workers) as pool:
            results = list(pool.imap_unordered(_report, jobs))
    else:
        results = [_report(job) for job in jobs]
    failed = [r for r in results if "error" in r]
    if failed and not args.keep_going:
        sys.exit(f"{len(failed)} jobs failed; nothing written")
    results = [r for r in results if "error" not in r]
    order = {j["name"]: i for i, j in enumerate(build_cases(args.quick, True))}
    results.sort(key=lambda r: order.get(r["name"], 0))
    states = [s for r in results for s in r["states"]]
    limits = [s for r in results for s in r["limits"]]
    windows = [w for r in results for w in r["windows"]]
    doc = {
        "generator": "tests/reference/generate_porous.py",
        "generated": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "mpmath": mpmath.__version__,
        "python": sys.version.split()[0],
        "dps": DPS,
        "method2_dps": DPS2,
        "out_digits": OUT_DIGITS,
        "equations": (__doc__ or "").split("Two methods")[0].strip(),
        "gray_hancock": {"slenderness": SLENDERNESS, "gamma": GH},
        "checks": {
            "agreement": f"forward Taylor vs Gragg-Bulirsch-Stoer shooting to {AGREE_TOL}",
            "residual": f"method 1's boundary residuals below {RESIDUAL_TOL} times the load",
            "identities": f"force balance and base moment to {IDENTITY_TOL}",
            "monotone": "max |theta| < pi/2 on every state",
        },
        "quick": args.quick,
        "failed_jobs": {r["name"]: r["error"] for r in failed},
        "seconds_total": round(time.time() - t0, 1),
        "seconds_per_job": {r["name"]: r["seconds"] for r in results},
        "per_state": [
            {
                "job": st["job"],
                "state_index": st["state_index"],
                "kappa": st["kappa"],
                "digits_method1": st["digits"],
                "digits_method2": st["method2_digits"],
                "method2": st["method2"],
                "method_difference": st["method_difference"],
                "seconds_method1": st["seconds_method1"],
                "seconds_method2": st["seconds_method2"],
            }
            for st in states
        ],
        "windows": windows,
        "states": states,
        "limits": limits,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {len(states)} states, {len(limits)} limits to {args.out}")


if __name__ == "__main__":
    main()
