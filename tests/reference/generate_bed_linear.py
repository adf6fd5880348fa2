"""Generate ``tests/data/bed_linear_mpmath.json``: the straight porous bed at small amplitude.

Run on demand (about a minute on two cores)::

    .venv/bin/python tests/reference/generate_bed_linear.py [--workers 2] [--out PATH] [--quick]

It imports nothing from :mod:`hairbed` (mpmath and the standard library only) and shares no
code with its solver: the equations are written here from issue 30 and theory.md §13/§14.

**Units.** Lengths in L, time in T = zeta_perp L^4/(E I), the fluid's velocity v in L/T,
loads per length in E I/L^3. Then a hair's normal drag per unit length is v - X_t (one unit
of drag per unit relative velocity), its inertia mu X_tt with the inertia number
mu = m/(zeta_perp T) (§14), and the fluid's equation rho_f u_t = eta u_zz + G - f_x/A,
multiplied by A L^3/(E I), is

    alpha kappa v_t = kappa v_zz + Pi - (v - X_t)   inside the bed (0 < z < 1),
    alpha kappa v_t = kappa v_zz + Pi               in the gap (1 < z < 1/eps),

with kappa = eta A/(zeta_perp L^2) (§13), Pi = A G L^3/(E I) (§13) and the bed's Womersley
number alpha = rho_f L^2/(eta T): indeed eta A L u_zz/(E I) = kappa v_zz,
zeta_perp (L/T)(v - X_t) L^3/(E I) = v - X_t and rho_f (L/T^2) A L^3/(E I) = alpha kappa.
In §13's load units the fluid is w = kappa v and its stress Q = w_z = kappa v_z, so at
omega = 0 this is §13's straight bed, w'' = w/kappa - Pi, the hair loaded by p = w/kappa = v,
and the wall forcing omega2 = eta V A L^2/(E I H) = eps kappa V (V the wall speed in L/T).

The hair, linearised about the straight state (theta0 = 0, h1 = 1; X its deflection):

    X_zzzz + mu X_tt = v - X_t,   X(0) = X_z(0) = 0,  X_zz(1) = X_zzz(1) = 0,
    v(0) = 0,  v, v_z continuous at z = 1,
    v(1/eps) = V e^{i omega t} (the wall drive) or Pi e^{i omega t} with v(1/eps) = 0 (the
    pressure drive).

With s = i omega (convention e^{+i omega t}) this is a linear constant-coefficient ODE in z:
sixth order in the bed, second in the gap.

Two methods, each at the working precision ``dps`` plus the digits the growing modes take
(``extra``), must agree on every value (``AGREE_TOL``, relative to the largest output of its
kind at that frequency):

1. **Shooting by the matrix exponential.** The bed's first-order system in
   (X, X', X'', X''', v, v', 1) and the gap's in (v, v', 1), each exponentiated exactly
   (``mpmath.expm``); the unknowns X''(0), X'''(0), v'(0) from the three conditions
   X''(1) = X'''(1) = 0 and the top wall's.
2. **Characteristic roots.** e^{r z} solves the bed where
   (kappa r^2 - c)(r^4 + k4) + s = 0, c = 1 + alpha kappa s, k4 = mu s^2 + s: a cubic in r^2
   (``mpmath.polyroots``); a constant particular solution (where alpha = mu = 0, r = 0 is a
   double root: X = 1, z with v = s X, and the particular X = -Pi z^2/(2 kappa s)); the
   gap's exponentials e^{+-lambda z}, lambda^2 = alpha s (its parabola where alpha = 0);
   the eight coefficients from the eight conditions by one linear solve. Each exponential is
   scaled to be at most 1 on its interval.

At omega = 0 the second method is the closed form of §13, the Brinkman profile
v = Pi (1 - cosh(z/l)) + C sinh(z/l) (l = sqrt(kappa)) and x1 = int_0^1 v (z^2/2 - z^3/6) dz
(``mpmath.quad``); the first is the same shooting at s = 0.

**Stored** (per case, per frequency, per drive "wall" (per unit V [L/T]) and "pressure" (per
unit Pi)): ``tip_deflection`` X(1) [L], ``base_moment`` X_zz(0) [E I/L: theta'(0)],
``top_stress`` kappa v_z(1/eps) (the top wall's stress in §13's load units: Q = A L^2 eta
u_z/(E I)), ``bottom_stress`` kappa v_z(0) and ``tip_velocity`` kappa v(1) (w(1)), each as
[real, imaginary]. Per unit omega2 of the wall drive divide the wall drive's by eps kappa.

**Modes** (``modes``): eigenvalues s of the homogeneous problem (V = Pi = 0), the roots of
the determinant of method 1's 3 x 3 shooting matrix, by ``mpmath.findroot`` (secant, complex)
from the cantilever's -beta^4 (mu = 0) or the root of mu s^2 + s + beta^4 = 0 with
Im > 0 (1 + cos beta cosh beta = 0); each is checked by method 2's 8 x 8 determinant
(below ``DET_TOL`` relative to its size one percent away) and the hair-like root it found
must lie within 50 % of its start, the roots distinct and in the cantilever's order (a
fluid mode is not a hair mode); modes are stored for a quasi-steady fluid (alpha = 0).
The first four beta are stored too (``betas``).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import platform
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import mpmath as mp

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "bed_linear_mpmath.json"
DPS = 40
AGREE_TOL = 1e-25
DET_TOL = 1e-20

#: (kappa, eps, alpha, mu): the bed's permeability over L^2, L/H, the Womersley number
#: rho_f L^2/(eta T), the inertia number.
CASES = [
    (1.0, 0.5, 0.0, 0.0),
    (1.0, 0.5, 1.0, 1.0),
    (1e-3, 0.5, 0.0, 0.0),
    (1e-3, 0.8, 1.0, 13.0),
    (1e-2, 0.5, 10.0, 1.0),
    (0.1, 0.25, 0.1, 0.0),
    (0.1, 0.5, 1.0, 13.0),
    (10.0, 0.5, 1.0, 1.0),
    (100.0, 0.25, 1.0, 0.0),
    (1e3, 0.5, 0.0, 0.0),
    (1e3, 0.5, 0.01, 13.0),
    (1.0, 0.9, 10.0, 0.0),
]
#: omega = 0 and 10^(-3 .. 4) in half decades [1/T]
OMEGAS = [0.0] + [10.0 ** (k / 2.0) for k in range(-6, 9)]
#: the cases whose first modes are stored, and how many
MODE_CASES = [
    (1.0, 0.5, 0.0, 0.0),
    (1e3, 0.5, 0.0, 0.0),
    (1e3, 0.5, 0.0, 1.0),
    (0.1, 0.5, 0.0, 1.0),
]
NUM_MODES = 4
OUTPUTS = ("tip_deflection", "base_moment", "top_stress", "bottom_stress", "tip_velocity")


def _cplx(x: mp.mpc) -> list[float]:
    x = mp.mpc(x)
    return [float(x.real), float(x.imag)]


def _extra_digits(kappa, eps, alpha, mu, omega) -> int:
    """Digits the growing modes cost: the largest growth exp(|Re r| length) of the bed's
    and the gap's exponentials, squared (shooting from the base)."""
    s = mp.mpc(0, omega)
    grow = mp.mpf(0)
    for r in _bed_roots(kappa, alpha, mu, s, prec_only=True):
        grow = max(grow, abs(mp.re(r)))
    lam = mp.sqrt(alpha * s)
    total = grow + abs(mp.re(lam)) * (1 / mp.mpf(eps) - 1)
    return int(2 * total / mp.log(10)) + 10


def _bed_roots(kappa, alpha, mu, s, prec_only=False):
    """The six r with (kappa r^2 - c)(r^4 + k4) + s = 0."""
    kappa, alpha, mu = mp.mpf(kappa), mp.mpf(alpha), mp.mpf(mu)
    c = 1 + alpha * kappa * s
    k4 = mu * s * s + s
    # kappa p^3 - c p^2 + kappa k4 p - c k4 + s = 0
    ps = mp.polyroots([kappa, -c, kappa * k4, -c * k4 + s], maxsteps=400, extraprec=400)
    roots = []
    for p in ps:
        r = mp.sqrt(p)
        roots += [r, -r]
    return roots


# ----------------------------------------------------------------------------------------
# Method 1: shooting by the matrix exponential
# ----------------------------------------------------------------------------------------


def _bed_matrix(kappa, alpha, mu, s, pi):
    """d/dz of (X, X', X'', X''', v, v', 1) in the bed."""
    kappa, alpha, mu = mp.mpf(kappa), mp.mpf(alpha), mp.mpf(mu)
    k4 = mu * s * s + s
    c = 1 + alpha * kappa * s
    a = mp.zeros(7, 7)
    a[0, 1] = a[1, 2] = a[2, 3] = 1
    a[3, 0] = -k4  # X'''' = v - k4 X
    a[3, 4] = 1
    a[4, 5] = 1
    a[5, 0] = -s / kappa  # v'' = (c v - s X - Pi)/kappa
    a[5, 4] = c / kappa
    a[5, 6] = -pi / kappa
    return a


def _gap_matrix(kappa, alpha, s, pi):
    """d/dz of (v, v', 1) in the gap: v'' = alpha s v - Pi/kappa."""
    a = mp.zeros(3, 3)
    a[0, 1] = 1
    a[1, 0] = mp.mpf(alpha) * s
    a[1, 2] = -mp.mpf(pi) / mp.mpf(kappa)
    return a


def _shoot_maps(kappa, eps, alpha, mu, s, pi):
    phi = mp.expm(_bed_matrix(kappa, alpha, mu, s, pi))
    psi = mp.expm(_gap_matrix(kappa, alpha, s, pi) * (1 / mp.mpf(eps) - 1))
    return phi, psi


def _shoot_end(phi, psi, unknowns):
    a, b, c = unknowns
    y0 = mp.matrix([0, 0, a, b, 0, c, 1])
    y1 = phi * y0
    top = psi * mp.matrix([y1[4], y1[5], 1])
    return y0, y1, top


def method1(kappa, eps, alpha, mu, omega, wall, pi):
    """The outputs by shooting with exact matrix exponentials."""
    s = mp.mpc(0, omega)
    phi, psi = _shoot_maps(kappa, eps, alpha, mu, s, pi)

    def resid(u):
        _, y1, top = _shoot_end(phi, psi, u)
        return mp.matrix([y1[2], y1[3], top[0] - wall])

    r0 = resid((0, 0, 0))
    jac = mp.zeros(3, 3)
    for j in range(3):
        e = [0, 0, 0]
        e[j] = 1
        col = resid(tuple(e)) - r0
        for i in range(3):
            jac[i, j] = col[i]
    u = mp.lu_solve(jac, -r0)
    y0, y1, top = _shoot_end(phi, psi, (u[0], u[1], u[2]))
    kap = mp.mpf(kappa)
    return {
        "tip_deflection": y1[0],
        "base_moment": y0[2],
        "top_stress": kap * top[1],
        "bottom_stress": kap * y0[5],
        "tip_velocity": kap * y1[4],
    }


def shooting_det(kappa, eps, alpha, mu, s):
    """det of the homogeneous 3 x 3 shooting matrix (an eigenvalue where it vanishes)."""
    phi, psi = _shoot_maps(kappa, eps, alpha, mu, s, 0)
    jac = mp.zeros(3, 3)
    for j in range(3):
        e = [0, 0, 0]
        e[j] = 1
        y0 = mp.matrix([0, 0, e[0], e[1], 0, e[2], 0])
        y1 = phi * y0
        top = psi * mp.matrix([y1[4], y1[5], 0])
        jac[0, j], jac[1, j], jac[2, j] = y1[2], y1[3], top[0]
    return mp.det(jac)


# ----------------------------------------------------------------------------------------
# Method 2: characteristic roots
# ----------------------------------------------------------------------------------------


def _method2_system(kappa, eps, alpha, mu, s, wall, pi):
    """The 8 x 8 system of the coefficients and its right-hand side, with the functions
    that evaluate the solution's pieces."""
    kap, alp, m = mp.mpf(kappa), mp.mpf(alpha), mp.mpf(mu)
    pi = mp.mpf(pi)
    top = 1 / mp.mpf(eps)
    glen = top - 1
    k4 = m * s * s + s
    c = 1 + alp * kap * s
    degenerate = alp == 0 and m == 0  # r = 0 is a double root: X = 1, z with v = s X
    roots = _bed_roots(kappa, alpha, mu, s)
    if degenerate:
        roots = sorted(roots, key=abs)[2:]
        # the particular: X = -Pi z^2/(2 kappa s), v = s X (hair and fluid move together)
        qp = -pi / (2 * kap * s)

        def part(z, d, which):
            x = [qp * z * z, 2 * qp * z, 2 * qp, mp.mpf(0)][d]
            return x if which == "x" else s * x

    else:
        # a constant: k4 X = v, -c v + s X + Pi = 0
        vp = pi / (c - s / k4)
        xp = vp / k4

        def part(z, d, which):
            if d:
                return mp.mpc(0)
            return xp if which == "x" else vp

    ref = [mp.mpf(1) if mp.re(r) > 0 else mp.mpf(0) for r in roots]
    amp = [r**4 + k4 for r in roots]  # v amplitude per unit X amplitude

    def bed(z, d):
        """d-th derivatives at z of (X basis, v basis) of the six solutions."""
        xs = [r**d * mp.exp(r * (z - z0)) for r, z0 in zip(roots, ref)]
        vs = [a * x for a, x in zip(amp, xs)]
        if degenerate:
            poly = [[mp.mpf(1), z], [mp.mpf(0), mp.mpf(1)]]
            for x in poly[d] if d < 2 else [mp.mpf(0), mp.mpf(0)]:
                xs.append(x)
                vs.append(s * x)
        return xs, vs

    lam = mp.sqrt(alp * s)
    if alp == 0:
        # v = g0 + g1 (z - 1) - Pi (z - 1)^2/(2 kappa)
        def gap(z, d):
            t = z - 1
            if d == 0:
                return [mp.mpf(1), t], -pi * t * t / (2 * kap)
            return [mp.mpf(0), mp.mpf(1)], -pi * t / kap

    else:
        # v = Pi/(kappa alpha s) + g0 e^{lam (z - top)} + g1 e^{-lam (z - 1)} (Re lam >= 0)
        def gap(z, d):
            e0 = lam**d * mp.exp(lam * (z - top))
            e1 = (-lam) ** d * mp.exp(-lam * (z - 1))
            return [e0, e1], (pi / (kap * alp * s) if d == 0 else mp.mpc(0))

    a = mp.zeros(8, 8)
    rhs = mp.zeros(8, 1)
    row = 0
    # X(0) = X'(0) = 0, v(0) = 0
    for d in (0, 1):
        xs, _ = bed(mp.mpf(0), d)
        for j in range(6):
            a[row, j] = xs[j]
        rhs[row] = -part(mp.mpf(0), d, "x")
        row += 1
    _, vs = bed(mp.mpf(0), 0)
    for j in range(6):
        a[row, j] = vs[j]
    rhs[row] = -part(mp.mpf(0), 0, "v")
    row += 1
    # X''(1) = X'''(1) = 0
    for d in (2, 3):
        xs, _ = bed(mp.mpf(1), d)
        for j in range(6):
            a[row, j] = xs[j]
        rhs[row] = -part(mp.mpf(1), d, "x")
        row += 1
    # v and v' continuous at z = 1
    for d in (0, 1):
        _, vs = bed(mp.mpf(1), d)
        gs, gpart = gap(mp.mpf(1), d)
        for j in range(6):
            a[row, j] = vs[j]
        a[row, 6], a[row, 7] = -gs[0], -gs[1]
        rhs[row] = gpart - part(mp.mpf(1), d, "v")
        row += 1
    # v(top) = wall
    gs, gpart = gap(top, 0)
    a[row, 6], a[row, 7] = gs[0], gs[1]
    rhs[row] = wall - gpart
    assert glen > 0
    return a, rhs, bed, gap, part, top


def method2(kappa, eps, alpha, mu, omega, wall, pi):
    """The outputs by the characteristic roots."""
    s = mp.mpc(0, omega)
    a, rhs, bed, gap, part, top = _method2_system(kappa, eps, alpha, mu, s, wall, pi)
    coef = mp.lu_solve(a, rhs)
    kap = mp.mpf(kappa)

    def bedval(z, d, which):
        xs, vs = bed(mp.mpf(z), d)
        basis = xs if which == "x" else vs
        return mp.fsum(coef[j] * basis[j] for j in range(6)) + part(mp.mpf(z), d, which)

    gs, gpart = gap(top, 1)
    return {
        "tip_deflection": bedval(1, 0, "x"),
        "base_moment": bedval(0, 2, "x"),
        "top_stress": kap * (coef[6] * gs[0] + coef[7] * gs[1] + gpart),
        "bottom_stress": kap * bedval(0, 1, "v"),
        "tip_velocity": kap * bedval(1, 0, "v"),
    }


def method2_static(kappa, eps, wall, pi):
    """omega = 0 by §13's closed form: the Brinkman profile and the cantilever integral."""
    kap = mp.mpf(kappa)
    pi = mp.mpf(pi)
    ell = mp.sqrt(kap)
    top = 1 / mp.mpf(eps)
    g = top - 1
    # bed: v = Pi (1 - cosh(z/l)) + C sinh(z/l); gap: v = v1 + v1' (z - 1) - Pi (z-1)^2/(2 kappa)
    # v(top) = wall: [Pi (1 - ch) + C sh] + [-Pi sh/l + C ch/l] g - Pi g^2/(2 kappa) = wall
    ch, sh = mp.cosh(1 / ell), mp.sinh(1 / ell)
    cc = (wall - pi * (1 - ch) + pi * sh / ell * g + pi * g * g / (2 * kap)) / (sh + ch * g / ell)

    def v(z):
        return pi * (1 - mp.cosh(z / ell)) + cc * mp.sinh(z / ell)

    x1 = mp.quad(lambda z: v(z) * (z * z / 2 - z**3 / 6), [0, 1])
    base = mp.quad(lambda z: v(z) * z, [0, 1])  # X''(0) = int p z dz
    v1 = v(mp.mpf(1))
    dv1 = -pi * sh / ell + cc * ch / ell
    return {
        "tip_deflection": x1,
        "base_moment": base,
        "top_stress": kap * (dv1 - pi * g / kap),
        "bottom_stress": kap * cc / ell,
        "tip_velocity": kap * v1,
    }


# ----------------------------------------------------------------------------------------
# The jobs
# ----------------------------------------------------------------------------------------


def _agree(a: dict, b: dict, what: str) -> float:
    worst = mp.mpf(0)
    for name in OUTPUTS:
        scale = max(abs(a[name]), mp.mpf(10) ** (-mp.mp.dps // 2))
        worst = max(worst, abs(a[name] - b[name]) / scale)
    if worst > AGREE_TOL:
        raise ArithmeticError(f"{what}: the two methods differ by {mp.nstr(worst, 5)}")
    return float(worst)


def response_job(case: tuple[float, float, float, float]) -> dict:
    kappa, eps, alpha, mu = case
    t0 = time.time()
    rows = []
    worst = 0.0
    for omega in OMEGAS:
        extra = _extra_digits(kappa, eps, alpha, mu, omega)
        with mp.workdps(DPS + extra):
            row = {"omega": omega, "extra_digits": extra}
            for drive, wall, pi in (("wall", 1, 0), ("pressure", 0, 1)):
                r1 = method1(kappa, eps, alpha, mu, omega, wall, pi)
                if omega == 0.0:
                    r2 = method2_static(kappa, eps, wall, pi)
                else:
                    r2 = method2(kappa, eps, alpha, mu, omega, wall, pi)
                worst = max(worst, _agree(r1, r2, f"case {case} omega {omega} {drive}"))
                row[drive] = {name: _cplx(r1[name]) for name in OUTPUTS}
            rows.append(row)
    return {
        "kappa": kappa,
        "eps": eps,
        "alpha": alpha,
        "mu": mu,
        "responses": rows,
        "agreement": worst,
        "seconds": time.time() - t0,
    }


def cantilever_betas(num: int) -> list:
    """The first roots of 1 + cos(beta) cosh(beta) = 0."""
    out = []
    for k in range(num):
        guess = (2 * k + 1) * mp.pi / 2 if k else mp.mpf("1.875")
        out.append(mp.findroot(lambda b: 1 + mp.cos(b) * mp.cosh(b), guess))
    return out


def mode_job(case: tuple[float, float, float, float]) -> dict:
    kappa, eps, alpha, mu = case
    t0 = time.time()
    with mp.workdps(DPS + 40):
        betas = cantilever_betas(NUM_MODES)
        eigs = []
        for b in betas:
            b4 = b**4
            if mu == 0:
                start = -b4
            else:
                disc = mp.sqrt(mp.mpc(1 - 4 * mu * b4))
                start = (-1 + disc) / (2 * mu)
                if mp.im(start) < 0:
                    start = (-1 - disc) / (2 * mu)
            f = lambda s: shooting_det(kappa, eps, alpha, mu, s)  # noqa: E731
            root = mp.findroot(f, (mp.mpc(start), mp.mpc(start) * (1 + mp.mpf("1e-3"))),
                               tol=mp.mpf(10) ** (-2 * DPS), maxsteps=200)  # fmt: skip
            if abs(root - start) > 0.5 * abs(start):
                raise ArithmeticError(f"mode of {case} from {start} went to {root}")
            # method 2's determinant vanishes there too
            a0, *_ = _method2_system(kappa, eps, alpha, mu, root, 0, 0)
            a1, *_ = _method2_system(kappa, eps, alpha, mu, root * mp.mpf("1.01"), 0, 0)
            ratio = abs(mp.det(a0)) / abs(mp.det(a1))
            if ratio > DET_TOL:
                raise ArithmeticError(f"mode {root} of {case}: method 2's det ratio {ratio}")
            eigs.append(root)
        # distinct, and in the cantilever's order (no start went to another's mode)
        size = [abs(x) for x in eigs]
        if size != sorted(size) or min(b - a for a, b in zip(size, size[1:])) < 1e-6:
            raise ArithmeticError(f"modes of {case} out of order: {size}")
    return {
        "kappa": kappa,
        "eps": eps,
        "alpha": alpha,
        "mu": mu,
        "eigenvalues": [_cplx(x) for x in eigs],
        "cantilever": [_cplx(-(b**4)) for b in betas],
        "seconds": time.time() - t0,
    }


def _run(job):
    kind, case = job
    return kind, (response_job(case) if kind == "response" else mode_job(case))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    parser.add_argument("--quick", action="store_true", help="two cases (smoke test)")
    args = parser.parse_args(argv)
    cases = CASES[:2] if args.quick else CASES
    mcases = MODE_CASES[:1] if args.quick else MODE_CASES
    jobs = [("response", c) for c in cases] + [("mode", c) for c in mcases]
    t0 = time.time()
    if args.workers > 1:
        with multiprocessing.Pool(args.workers) as pool:
            results = pool.map(_run, jobs, chunksize=1)
    else:
        results = [_run(j) for j in jobs]
    with mp.workdps(DPS):
        betas = [float(b) for b in cantilever_betas(NUM_MODES)]
    doc = {
        "generator": "tests/reference/generate_bed_linear.py",
        "generated": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "mpmath": mp.__version__,
        "python": platform.python_version(),
        "dps": DPS,
        "agree_tol": AGREE_TOL,
        "equations": (
            "X'''' + mu X_tt = v - X_t; alpha kappa v_t = kappa v'' + Pi - (v - X_t) in "
            "0<z<1; alpha kappa v_t = kappa v'' + Pi in 1<z<1/eps; X(0)=X'(0)=0, "
            "X''(1)=X'''(1)=0, v(0)=0, v, v' continuous at 1, v(1/eps) = V; e^{i omega t}; "
            "stresses kappa v' (load units Q), tip_velocity kappa v(1) (w); per unit V [L/T] "
            "('wall') or per unit Pi ('pressure'); omega2 = eps kappa V"
        ),
        "quick": args.quick,
        "seconds_total": time.time() - t0,
        "betas": betas,
        "responses": [r for k, r in results if k == "response"],
        "modes": [r for k, r in results if k == "mode"],
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    worst = max(r["agreement"] for r in doc["responses"])
    print(f"wrote {args.out}: {len(doc['responses'])} cases, worst agreement {worst:.2e}, "
          f"{doc['seconds_total']:.1f} s", file=sys.stderr)  # fmt: skip


if __name__ == "__main__":
    main()
