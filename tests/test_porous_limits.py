"""The porous bed's exact limits (issue 29, theory.md §13), each with its measured rate.

Every reference here is computed by other code than the porous kernel: the paper's closed form
(`hairbed.solve`), the dense bed's collocation (`hairbed.solve_loaded`), the isolated pillar
(`hairbed.solve_pillar`), scipy's `solve_bvp` on the anisotropic dense limit derived in
theory.md §13, and the linear Brinkman theory integrated by mpmath.
"""

from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_bvp
from scipy.optimize import brentq

import hairbed

KAPPAS_DENSE = np.array([1e-3, 1e-4, 1e-5, 1e-6])


def _rates(kappas: np.ndarray, diffs: np.ndarray) -> np.ndarray:
    """The local exponents p of |diff| ~ kappa^p between neighbouring kappas."""
    d = np.abs(diffs)
    return np.log(d[1:] / d[:-1]) / np.log(kappas[1:] / kappas[:-1])


def _assert_rate(rates: np.ndarray, expected: float, tol: float, last: float) -> None:
    """Every local exponent within ``tol`` of ``expected`` and the one over the last decade,
    where the next order matters least, within ``last``."""
    assert np.all(np.abs(rates - expected) < tol), rates
    assert abs(rates[-1] - expected) < last, rates


def test_dense_limit_isotropic_is_the_papers_closed_form() -> None:
    """kappa -> 0, Pi = 0, gamma = 1: the paper's dense bed, the difference ~ sqrt(kappa)."""
    ref = hairbed.solve(2.0, 0.5, 0.3)
    st = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=KAPPAS_DENSE)
    assert np.all(st.status == 0)
    diffs = st.tip_deflection - ref.tip_deflection
    rates = _rates(KAPPAS_DENSE, diffs)
    _assert_rate(rates, 0.5, 0.06, 0.015)
    # the tip stress tends to the paper's tip load W = omega2/(1 - eps h1)
    w_ref = 2.0 / (1.0 - 0.5 * ref.tip_height)
    assert abs(st.tip_stress[-1] - w_ref) < 20 * math.sqrt(KAPPAS_DENSE[-1])


@pytest.mark.parametrize(("pi", "q"), [(3.0, None), (None, 2.0)])
def test_dense_limit_pumped_is_the_loaded_bed(pi: float | None, q: float | None) -> None:
    """kappa -> 0 with a pressure or flow drive (gamma = 1): the dense bed of
    `solve_loaded` (tip load plus a load per unit height), the difference ~ sqrt(kappa)."""
    ref = hairbed.solve_loaded(0.5, 0.5, 0.2, pi=pi, q=q)
    st = hairbed.solve_porous(0.5, 0.5, 0.2, kappa=KAPPAS_DENSE, pi=pi, q=q)
    assert np.all(st.status == 0)
    rates = _rates(KAPPAS_DENSE, st.tip_deflection - ref.tip_deflection)
    # the O(kappa) term fades: measured rates like 0.547, 0.516, 0.505
    _assert_rate(rates, 0.5, 0.06, 0.015)
    if q is not None:  # the solved pressure load tends to the dense flow drive's Pi
        rates = _rates(KAPPAS_DENSE, st.pi - ref.distributed_load)
        _assert_rate(rates, 0.5, 0.1, 0.02)


def _rotated_tip_load_state(omega2: float, eps: float, theta0: float, gamma: float) -> tuple:
    """The anisotropic dense limit at Pi = 0 (theory.md §13): theta'' = -W (cos + r1 sin),
    W = omega2/(1 - eps h1), r1 = (1 - gamma) sin(t1) cos(t1)/(cos^2 t1 + gamma sin^2 t1).
    A pendulum under the tip force W (1, -r1): with alpha = atan(r1) and phi = theta - alpha
    it is the paper's problem phi'' = -W sqrt(1 + r1^2) cos(phi), phi(0) = theta0 - alpha, at
    a fixed load (eps = 0 in the closed form), solved by `hairbed.solve`; the tip angle
    theta1 (which sets r1) and h1 (which sets W) by a fixed point. Returns (h1, x1, theta1)."""

    def shape(t1: float, h1: float) -> tuple[float, float, float]:
        c, s = math.cos(t1), math.sin(t1)
        r1 = (1.0 - gamma) * s * c / (c * c + gamma * s * s)
        alpha = math.atan(r1)
        big_w = omega2 / (1.0 - eps * h1)
        sol = hairbed.solve(big_w * math.sqrt(1.0 + r1 * r1), 0.0, theta0 - alpha)
        hp, xp = sol.tip_height, sol.tip_deflection
        # rotate the shape back: theta = phi + alpha
        h_new = math.cos(alpha) * hp - math.sin(alpha) * xp
        x_new = math.sin(alpha) * hp + math.cos(alpha) * xp
        return h_new, x_new, sol.tip_angle + alpha

    t1, h1 = theta0, math.cos(theta0)
    for _ in range(200):
        h_new, x_new, t_new = shape(t1, h1)
        if abs(h_new - h1) + abs(t_new - t1) < 1e-15:
            break
        h1, t1 = 0.5 * (h1 + h_new), 0.5 * (t1 + t_new)
    return shape(t1, h1)


def test_dense_limit_anisotropic_rotates_the_tip_force() -> None:
    """kappa -> 0, Pi = 0, gamma < 1: the tip force W (1, -r1) of the tips' boundary layer,
    not the paper's horizontal one; the difference to it ~ sqrt(kappa)."""
    gamma = 0.5
    h1, x1, t1 = _rotated_tip_load_state(2.0, 0.5, 0.3, gamma)
    st = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=KAPPAS_DENSE, gamma=gamma)
    assert np.all(st.status == 0)
    rates = _rates(KAPPAS_DENSE, st.tip_deflection - x1)
    _assert_rate(rates, 0.5, 0.06, 0.015)
    rates = _rates(KAPPAS_DENSE, st.tip_angle - t1)
    _assert_rate(rates, 0.5, 0.06, 0.015)
    # and the paper's horizontal tip load is off by an O(1) amount, not O(sqrt(kappa))
    paper = hairbed.solve(2.0, 0.5, 0.3)
    assert abs(paper.tip_deflection - x1) > 30 * abs(st.tip_deflection[-1] - x1)
    # the base's axial force: the drag's vertical total tends to -W r1
    c, s = math.cos(t1), math.sin(t1)
    r1 = (1.0 - gamma) * s * c / (c * c + gamma * s * s)
    big_w = 2.0 / (1.0 - 0.5 * h1)
    rates = _rates(KAPPAS_DENSE, st.drag_z + big_w * r1)
    _assert_rate(rates, 0.5, 0.1, 0.02)


def _pumped_anisotropic_dense(
    omega2: float, eps: float, theta0: float, pi: float, gamma: float
) -> tuple[float, float]:
    """The dense limit with Pi != 0 and gamma < 1 (theory.md §13), by scipy's solve_bvp: the
    bed's drag per unit length balances the pressure gradient horizontally,
    f = Pi cos(theta) (1, -b/a) with a = cos^2 + gamma sin^2, b = (1 - gamma) sin cos, and the
    tips' boundary layer carries W (1, -r1), W = omega2/u + (Pi/2)(1/eps - h1). The shooting
    of the tip height h1 by brentq around the BVP at fixed h1. Returns (h1, x1)."""

    def bvp_at(h_gap: float) -> tuple[float, float, float]:
        big_w = omega2 / (1.0 - eps * h_gap) + 0.5 * pi * (1.0 / eps - h_gap)

        def rhs(s: np.ndarray, y: np.ndarray) -> np.ndarray:
            th, dth, z, x, fx, fz, t1 = y
            c, sn = np.cos(th), np.sin(th)
            a = c * c + gamma * sn * sn
            b = (1.0 - gamma) * sn * c
            px = pi * c
            pz = -pi * c * b / a
            return np.vstack([dth, -(fx * c - fz * sn), c, sn, -px, -pz, np.zeros_like(th)])

        def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
            t1 = yb[6]
            c, sn = math.cos(t1), math.sin(t1)
            r1 = (1.0 - gamma) * sn * c / (c * c + gamma * sn * sn)
            return np.array(
                [
                    ya[0] - theta0,
                    yb[1],
                    ya[2],
                    ya[3],
                    yb[4] - big_w,
                    yb[5] + big_w * r1,
                    yb[0] - t1,
                ]
            )

        s = np.linspace(0.0, 1.0, 201)
        y0 = np.zeros((7, s.size))
        y0[0] = theta0
        y0[2] = s * math.cos(theta0)
        y0[3] = s * math.sin(theta0)
        y0[4] = big_w + pi * (1 - s)
        y0[6] = theta0
        sol = solve_bvp(rhs, bc, s, y0, tol=1e-11, max_nodes=200000)
        assert sol.status == 0, sol.message
        return float(sol.y[2, -1]), float(sol.y[3, -1]), float(sol.y[0, -1])

    h1 = brentq(lambda h: bvp_at(h)[0] - h, 0.3, 1.0, xtol=1e-13)
    return h1, bvp_at(h1)[1]


def test_dense_limit_pumped_anisotropic() -> None:
    """kappa -> 0 with Pi != 0 and gamma < 1: the dense bed with its anisotropic vertical
    load (solved by solve_bvp); the difference ~ sqrt(kappa)."""
    h1, x1 = _pumped_anisotropic_dense(0.5, 0.5, 0.2, 3.0, 0.6)
    st = hairbed.solve_porous(0.5, 0.5, 0.2, kappa=KAPPAS_DENSE, pi=3.0, gamma=0.6)
    assert np.all(st.status == 0)
    rates = _rates(KAPPAS_DENSE, st.tip_deflection - x1)
    _assert_rate(rates, 0.5, 0.06, 0.015)
    rates = _rates(KAPPAS_DENSE, st.tip_height - h1)
    _assert_rate(rates, 0.5, 0.06, 0.015)


@pytest.mark.parametrize("gamma", [1.0, 0.6568])
def test_sparse_limit_is_the_isolated_pillar_in_couette_flow(gamma: float) -> None:
    """kappa -> infinity at fixed Lambda = omega2/kappa, Pi = 0: the isolated pillar in the
    undisturbed Couette profile U = z; the difference ~ 1/kappa."""
    lam, eps, theta0 = 3.0, 0.5, 0.4
    kappas = np.array([1e2, 1e3, 1e4, 1e5])
    ref = hairbed.solve_pillar(lam, theta0, profile="couette", height_ratio=eps, gamma=gamma)
    st = hairbed.solve_porous(lam * kappas, eps, theta0, kappa=kappas, gamma=gamma)
    assert np.all(st.status == 0)
    rates = _rates(kappas, st.tip_deflection - ref.tip_deflection)
    _assert_rate(rates, -1.0, 0.03, 0.01)
    assert abs(st.tip_deflection[-1] - ref.tip_deflection) < 1e-4


def _linear_brinkman_x1(omega2: float, eps: float, kappa: float, pi: float) -> mp.mpf:
    """The cantilever's tip deflection x1 = int_0^1 p(z) (z^2/2 - z^3/6) dz under the drag
    per length p = w/kappa of the straight bed's linear Brinkman profile: w'' = w/kappa - Pi,
    w(0) = 0, and the gap condition eps w(1) + (1 - eps) w'(1) - Pi (1 - eps)^2/(2 eps) =
    omega2 (mpmath, 30 digits)."""
    mp.mp.dps = 30
    ell = mp.sqrt(mp.mpf(kappa))
    k = mp.mpf(kappa)
    e = mp.mpf(eps)
    # w = k Pi (1 - cosh(z/ell)) + A sinh(z/ell)
    w1 = k * pi * (1 - mp.cosh(1 / ell))
    q1 = -k * pi * mp.sinh(1 / ell) / ell
    dw1, dq1 = mp.sinh(1 / ell), mp.cosh(1 / ell) / ell
    rhs = omega2 - (e * w1 + (1 - e) * q1)
    if pi:
        rhs += pi * (1 - e) ** 2 / (2 * e)
    amp = rhs / (e * dw1 + (1 - e) * dq1)

    def p(z: mp.mpf) -> mp.mpf:
        return (k * pi * (1 - mp.cosh(z / ell)) + amp * mp.sinh(z / ell)) / k

    return mp.quad(lambda z: p(z) * (z**2 / 2 - z**3 / 6), [0, 1])


@pytest.mark.parametrize(("kappa", "pi"), [(0.3, 0.0), (3.0, 0.0), (0.05, 2.0)])
def test_small_loads_follow_the_linear_brinkman_theory(kappa: float, pi: float) -> None:
    """theta0 = 0, loads scaled by lam -> 0: x1 = lam x1_lin + O(lam^3) (odd in the load), the
    remainder measured cubic."""
    lin = float(_linear_brinkman_x1(1.0, 0.5, kappa, pi))
    lams = np.array([1e-1, 5e-2, 2.5e-2, 1.25e-2])
    st = hairbed.solve_porous(lams, 0.5, kappa=kappa, pi=lams * pi if pi else None)
    assert np.all(st.status == 0)
    rem = st.tip_deflection - lams * lin
    rates = np.log(np.abs(rem[1:] / rem[:-1])) / np.log(lams[1:] / lams[:-1])
    _assert_rate(rates, 3.0, 0.05, 0.02)


def test_identities_on_every_state() -> None:
    """The horizontal force balance F_x(0) = Q(1) - Q(0) + Pi h1 and the base moment (the
    Chebyshev derivative of theta at the base against the quadrature of the ODE)."""
    kap = np.geomspace(1e-4, 1e4, 9)[:, None]
    t0 = np.array([-0.9, 0.0, 0.9])[None, :]
    for kw in ({}, {"pi": 1.5}, {"q": 1.0}):
        st = hairbed.solve_porous(2.0, 0.6, t0, kappa=kap, gamma=0.7, **kw)
        ok = st.status == 0
        assert ok.sum() >= 25
        bal = st.drag_x - (st.tip_stress - st.wall_stress + st.pi * st.tip_height)
        scale = np.maximum(1.0, np.abs(st.drag_x))
        assert np.nanmax(np.abs(bal[ok]) / scale[ok]) < 1e-10
        # theta'(0) by a centred difference of the interpolant at tiny s (the base is an end)
        hs = 1e-5
        _, _, _, th = st.shape(np.array([0.0, hs, 2 * hs]))
        d0 = (-3 * th[..., 0] + 4 * th[..., 1] - th[..., 2]) / (2 * hs)
        err = np.abs(d0 - st.base_curvature) / np.maximum(1.0, np.abs(st.base_curvature))
        assert np.nanmax(err[ok]) < 1e-6
