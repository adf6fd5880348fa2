"""Generate ``tests/data/wall_law_mpmath.json``: pillars in Spalding's law of the wall (issue 31).

Run on demand (about a minute)::

    .venv/bin/python tests/reference/generate_wall_law.py [--out PATH]

It imports nothing from :mod:`hairbed` and shares no code with it: the equations are written
here from docs/theory.md §12. The mean flow is Spalding's law of the wall (D. B. Spalding, "A
single formula for the law of the wall", J. Appl. Mech. 28, 455-458, 1961),

    y+ = u+ + e^(-kappa B) [e^(kappa u+) - 1 - kappa u+ - (kappa u+)^2/2 - (kappa u+)^3/6],

kappa = 0.41, B = 5.0, in the wall units of the stress: u_tau = sqrt(tau_w/rho), nu = eta/rho,
y+ = y u_tau/nu. u+(y+) is found here by Newton's method on the formula with its
derivative written out, at ``DPS`` digits.

Each case is an SI pillar (length L, radius a, Young's modulus E, viscosity eta, density rho,
base angle theta0, wall stress tau_w). Its dimensionless inputs follow from theory.md §12:

    I = pi a^4/4,   zeta_perp = 4 pi eta/(ln(2L/a) + 1/2),
    gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1),   Lambda = zeta_perp tau_w L^4/(eta E I),
    L+ = L u_tau/nu,   U(z) = u+(L+ z)/L+   (z in L),

and the state solves, with s in [0, 1], lengths in L, forces in E I/L^2,

    theta' = m,   m' = -(F_x cos theta - F_z sin theta),   x' = sin theta,   z' = cos theta,
    F_x' = -Lambda U(z) (cos^2 theta + gamma sin^2 theta),
    F_z' =  Lambda U(z) (1 - gamma) sin theta cos theta,
    theta(0) = theta0,  x(0) = z(0) = 0,  m(1) = F_x(1) = F_z(1) = 0.

Method: shooting from the base on (m(0), F_x(0), F_z(0)), Newton's method with a
finite-difference Jacobian (step 1e-12), the initial value problem by the classical
Runge-Kutta method of order 4 with ``STEPS`` = (256, 512, 1024) equal steps; the shooting
problem is solved at each, and the outputs are extrapolated to zero step by Richardson's
method (removing the h^4 and h^5 terms). A seventh equation integrates the base moment
int_0^1 (z f_x - x f_z) ds alongside.

Checks (the generator stops rather than write a value that fails one):

1. the two Richardson estimates (from 256/512 and from 256/512/1024) agree to
   ``RESOLUTION_TOL`` relative to max(1e-3, abs(value)) in every output;
2. the identity theta'(0) = int_0^1 (z f_x - x f_z) ds to ``RESOLUTION_TOL``;
3. the boundary residuals at every step count below ``RESIDUAL_TOL``.

Written in SI: the tip deflection x(1) L [m], tip height z(1) L [m], tip angle [rad], base
moment E I theta'(0)/L [N m], drag F_x(0) E I/L^2 [N], and Lambda, gamma, L+.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import mpmath as mp

DPS = 30
STEPS = (256, 512, 1024)
RESOLUTION_TOL = 1e-12
RESIDUAL_TOL = 1e-22
KAPPA = mp.mpf("0.41")
B = mp.mpf("5.0")
OUT_DIGITS = 17

#: (name, L [m], a [m], E [Pa], eta [Pa s], rho [kg/m^3], theta0 [rad], tau_w [Pa])
CASES = (
    ("water_upright", "1e-3", "50e-6", "1e5", "1.0016e-3", "998.21", "0", "1"),
    ("water_tilted_downstream", "1e-3", "50e-6", "1e5", "1.0016e-3", "998.21", "0.3", "3"),
    ("air_tilted_upstream", "0.5e-3", "20e-6", "2e5", "1.825e-5", "1.2041", "-0.4", "0.5"),
    ("water_tall", "2e-3", "50e-6", "1e7", "1.0016e-3", "998.21", "0", "10"),
    ("water_reversed", "1e-3", "50e-6", "1e5", "1.0016e-3", "998.21", "0.2", "-2"),
)


def y_plus(u):
    k = KAPPA * u
    return u + mp.exp(-KAPPA * B) * (mp.exp(k) - 1 - k - k**2 / 2 - k**3 / 6)


def dy_plus(u):
    k = KAPPA * u
    return 1 + KAPPA * mp.exp(-KAPPA * B) * (mp.exp(k) - 1 - k - k**2 / 2)


def u_plus(y):
    """u+ of y+ >= 0: Newton's method on Spalding's formula with its derivative written out,
    from u = y+ (right of the root: y+(u) >= u, and the formula is convex), first in double
    precision, then at the working precision until the step is below its rounding."""
    if y == 0:
        return mp.mpf(0)
    yf = float(y)
    e = math.exp(-0.41 * 5.0)
    u = min(yf, math.log(max(yf, 1.0)) / 0.41 + 10.0)
    for _ in range(100):
        k = 0.41 * u
        f = u + e * (math.expm1(k) - k - k * k / 2 - k**3 / 6) - yf
        step = f / (1 + 0.41 * e * (math.expm1(k) - k - k * k / 2))
        u -= step
        if abs(step) < 1e-15 * u:
            break
    u = mp.mpf(u)
    for _ in range(8):
        step = (y_plus(u) - y) / dy_plus(u)
        u -= step
        if abs(step) < mp.mpf(10) ** (-DPS + 3) * u:
            break
    return u


def rhs(y, lam, gamma, lp):
    th, m, x, z, fx, fz, q = y
    c, s = mp.cos(th), mp.sin(th)
    zc = max(z, mp.mpf(0))
    u = u_plus(lp * zc) / lp
    gx = lam * u * (c * c + gamma * s * s)
    gz = -lam * u * (1 - gamma) * s * c
    return [m, -(fx * c - fz * s), s, c, -gx, -gz, z * gx - x * gz]


def shoot(unknowns, n, th0, lam, gamma, lp):
    m0, fx0, fz0 = unknowns
    y = [th0, m0, mp.mpf(0), mp.mpf(0), fx0, fz0, mp.mpf(0)]
    h = mp.mpf(1) / n
    for _ in range(n):
        k1 = rhs(y, lam, gamma, lp)
        k2 = rhs([a + h / 2 * b for a, b in zip(y, k1)], lam, gamma, lp)
        k3 = rhs([a + h / 2 * b for a, b in zip(y, k2)], lam, gamma, lp)
        k4 = rhs([a + h * b for a, b in zip(y, k3)], lam, gamma, lp)
        y = [a + h / 6 * (b + 2 * c + 2 * d + e) for a, b, c, d, e in zip(y, k1, k2, k3, k4)]
    return y


def solve(n, guess, th0, lam, gamma, lp):
    """The shooting problem at n steps, by Newton from ``guess``: (unknowns, end state)."""
    u = list(guess)
    eps = mp.mpf("1e-12")
    for _ in range(30):
        end = shoot(u, n, th0, lam, gamma, lp)
        res = [end[1], end[4], end[5]]
        scale = max(mp.mpf(1), abs(lam))
        if max(abs(r) for r in res) < RESIDUAL_TOL * scale:
            return u, end
        jac = mp.matrix(3, 3)
        for j in range(3):
            up = list(u)
            up[j] += eps
            e2 = shoot(up, n, th0, lam, gamma, lp)
            for i, r in enumerate((e2[1], e2[4], e2[5])):
                jac[i, j] = (r - res[i]) / eps
        step = mp.lu_solve(jac, mp.matrix(res))
        u = [u[i] - step[i] for i in range(3)]
    raise SystemExit(f"no convergence at n = {n}")


def case(name, length, radius, youngs, eta, rho, th0, tau):
    L, a, E, eta, rho, th0, tau = (mp.mpf(v) for v in (length, radius, youngs, eta, rho, th0, tau))
    inertia = mp.pi * a**4 / 4
    lg = mp.log(2 * L / a)
    zeta = 4 * mp.pi * eta / (lg + mp.mpf(1) / 2)
    gamma = (lg + mp.mpf(1) / 2) / (2 * lg - 1)
    lam = zeta * tau * L**4 / (eta * E * inertia)
    lp = L * mp.sqrt(abs(tau) / rho) * rho / eta
    # the guess: the straight cantilever under its normal load (U ~ z)
    c0 = mp.cos(th0)
    guess = [lam * c0 * c0 / 3, lam * c0 * c0 / 2, mp.mpf(0)]
    # a continuation in Lambda at the coarsest step count
    for frac in (mp.mpf(1) / 4, mp.mpf(1) / 2, mp.mpf(3) / 4, mp.mpf(1)):
        guess, _ = solve(64, guess, th0, lam * frac, gamma, lp)
    outs = []
    for n in STEPS:
        guess, end = solve(n, guess, th0, lam, gamma, lp)
        outs.append([end[2], end[3], end[0], guess[0], guess[1], end[6]])
    r1 = [(16 * f - e) / 15 for e, f in zip(outs[0], outs[1])]
    r2 = [(16 * f - e) / 15 for e, f in zip(outs[1], outs[2])]
    rich = [(32 * f - e) / 31 for e, f in zip(r1, r2)]  # the h^5 term of RK4's expansion
    for name_i, x, y in zip(("x1", "h1", "theta1", "m0", "fx0", "q"), r2, rich):
        if abs(x - y) > RESOLUTION_TOL * max(mp.mpf("1e-3"), abs(y)):
            raise SystemExit(f"{name}: {name_i} not resolved: {x} vs {y}")
    x1, h1, th1, m0, fx0, q = rich
    if abs(m0 - q) > RESOLUTION_TOL * max(1, abs(m0)):
        raise SystemExit(f"{name}: base moment identity fails: {m0} vs {q}")
    ei = E * inertia

    def out(v):
        return mp.nstr(v, OUT_DIGITS)

    return {
        "name": name,
        "forcing": out(lam),
        "gamma": out(gamma),
        "l_plus": out(lp),
        "tip_deflection": out(x1 * L),
        "tip_height": out(h1 * L),
        "tip_angle": out(th1),
        "base_moment": out(ei * m0 / L),
        "drag": out(ei * fx0 / L**2),
        "richardson_difference": mp.nstr(max(abs(x - y) for x, y in zip(r2, rich)), 3),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out",
        type=Path,
        default=Path(__file__).resolve().parents[1] / "data" / "wall_law_mpmath.json",
    )
    args = parser.parse_args(argv)
    mp.mp.dps = DPS
    cases = []
    for spec in CASES:
        name, length, radius, youngs, eta, rho, th0, tau = spec
        print(name, file=sys.stderr, flush=True)
        c = {
            "inputs": {
                "length": length,
                "radius": radius,
                "youngs_modulus": youngs,
                "viscosity": eta,
                "density": rho,
                "base_angle": th0,
                "wall_shear_stress": tau,
            }
        }
        c.update(case(*spec))
        cases.append(c)
    doc = {
        "generator": "tests/reference/generate_wall_law.py",
        "kappa": "0.41",
        "B": "5.0",
        "dps": DPS,
        "steps": list(STEPS),
        "cases": cases,
    }
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
