"""The pillar dynamics' limits and accuracy (issue 30, theory.md §14), each against a
reference that shares no code with the integrator:

- accuracy: the tip deflection against the same run at twice the Chebyshev degree and half
  the tolerance, overdamped and ringing (mu = 13);
- energy: d/dt (elastic + kinetic) = the drag's and the tip load's power, every term by this
  file's own Chebyshev interpolation and Gauss-Legendre quadrature of the trajectory's
  public nodal angles and rates (not ``PillarTrajectory.energy``), the time derivative by
  fourth-order central differences of the dense output;
- steady: constant drives relax to ``solve_pillar``'s state at strongly tilted bases, the
  law-of-the-wall profile and with inertia (tests/test_dynamics_integrate.py covers the
  upright and mildly tilted pillar in the three named profiles, overdamped);
- nonlinear against linear with inertia (mu = 13; the overdamped case is in
  tests/test_dynamics_integrate.py): a small Gaussian pulse about a large deflection against
  the linear response, that is the Fourier integral of the transfer function (itself tested
  against the Krylov-function cantilever, tests/test_dynamics_linear.py) times the pulse's
  closed-form spectrum.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import scipy.fft
from numpy.polynomial import chebyshev as cheb

import hairbed
from hairbed._core.wall_law import wall_law_coefficients
from hairbed.dynamics import linearise_pillar, sampled, simulate_pillar, sine, step

FloatArray = np.ndarray

# ---------------------------------------------------------------- accuracy


def test_overdamped_step_is_converged_to_1e8() -> None:
    """A step to Lambda = 10 from rest at the default N = 32, rtol 1e-10 against N = 64,
    rtol 5e-11 (measured 6.3e-12)."""
    t = np.array([0.0, 0.01, 0.05, 0.2, 1.0])
    runs = [
        simulate_pillar(step(10.0), t, num=num, rtol=rtol, atol=1e-2 * rtol)
        for num, rtol in ((32, 1e-10), (64, 5e-11))
    ]
    assert all(r.success for r in runs)
    assert runs[0].tip_deflection[-1] > 0.5  # the pillar moved (to x1 = 0.5394)
    for name in ("tip_deflection", "tip_height"):
        diff = np.max(np.abs(getattr(runs[0], name) - getattr(runs[1], name)))
        assert diff <= 1e-8, (name, diff)


def test_ringing_pillar_is_converged_to_1e8() -> None:
    """mu = 13 (the PDMS pillar in water), Lambda rising smoothly from 0 to 10 over one T
    (5 - 5 cos(pi t): the start at rest is smooth, so the collocation's highest modes are
    not struck; a sharp step at mu = 13 rings in every resolved mode for hundreds of T) and
    on to t = 2 T: N = 16, rtol 1e-10 against N = 32, rtol 5e-11 (measured 3.0e-11)."""
    t = np.linspace(0.0, 2.0, 9)
    drive = sine(5.0, 5.0, np.pi, -0.5 * np.pi)
    runs = [
        simulate_pillar(drive, t, mu=13.0, num=num, rtol=rtol, atol=1e-2 * rtol)
        for num, rtol in ((16, 1e-10), (32, 5e-11))
    ]
    assert all(r.success for r in runs)
    assert runs[0].tip_deflection[-1] > 0.5
    for name in ("tip_deflection", "tip_height"):
        diff = np.max(np.abs(getattr(runs[0], name) - getattr(runs[1], name)))
        assert diff <= 1e-8, (name, diff)


# ---------------------------------------------------------------- energy

_GX, _GW = np.polynomial.legendre.leggauss(96)
_GS, _GW = 0.5 * (_GX + 1.0), 0.5 * _GW  # Gauss-Legendre on [0, 1]
_FINE = 256
_XF = -np.cos(np.pi * np.arange(_FINE + 1) / _FINE)


def _lobatto_series(values: FloatArray) -> FloatArray:
    """The Chebyshev series interpolating values at x_j = -cos(pi j/M), j = 0..M (a type-I
    discrete cosine transform: c_k = (2/M) sum'' f(cos(pi j/M)) cos(pi j k/M))."""
    m = values.size - 1
    c = scipy.fft.dct(values[::-1], type=1) / m
    c[0] *= 0.5
    c[-1] *= 0.5
    return np.asarray(c)


def _budget(run: Any, k: int, profile: Any) -> dict[str, float]:
    """The energy budget at output k from the nodal theta and theta_t alone (units E I/L,
    time T): the interpolants in x = 2 s - 1 through the Gauss-Lobatto nodes (checked to be
    the nodes; by a discrete cosine transform), r_t = int_0^s theta_t (cos, -sin) ds' by
    Chebyshev integration on 257 points, the integrals over s by 96-point Gauss-Legendre."""
    num = run.s.size - 1
    lobatto = 0.5 * (1.0 - np.cos(np.pi * np.arange(num + 1) / num))
    assert np.allclose(run.s, lobatto, rtol=0.0, atol=1e-15)  # no map: plain nodes
    x = 2.0 * run.s - 1.0
    assert np.allclose(x, -np.cos(np.pi * np.arange(num + 1) / num), rtol=0.0, atol=1e-15)
    th, tt = _lobatto_series(run.theta[k]), _lobatto_series(run.theta_t[k])
    thf, ttf = cheb.chebval(_XF, th), cheb.chebval(_XF, tt)

    def primitive(values: FloatArray) -> FloatArray:  # int_0^s in s, as a series in x
        return np.asarray(0.5 * cheb.chebint(_lobatto_series(values), lbnd=-1.0))

    vx, vz = primitive(ttf * np.cos(thf)), primitive(-ttf * np.sin(thf))
    zc = primitive(np.cos(thf))
    xq = 2.0 * _GS - 1.0
    thq = cheb.chebval(xq, th)
    ths = 2.0 * cheb.chebval(xq, cheb.chebder(th))
    thst = 2.0 * cheb.chebval(xq, cheb.chebder(tt))
    vxq, vzq, zq = cheb.chebval(xq, vx), cheb.chebval(xq, vz), cheb.chebval(xq, zc)
    tx, tz = np.sin(thq), np.cos(thq)  # the tangent (x, z)
    along = tx * vxq + tz * vzq
    g, chi = run.gamma, run.tangential_mass
    u = run.forcing[k] * profile(zq)
    ax, az = vxq - (1.0 - g) * tx * along, vzq - (1.0 - g) * tz * along  # [I - (1-g) t t] r_t
    tip_speed = float(cheb.chebval(1.0, vx))
    return {
        "elastic": float(0.5 * _GW @ ths**2),
        "kinetic": float(0.5 * run.mu * _GW @ (vxq**2 + vzq**2 - (1.0 - chi) * along**2)),
        # the drag's power on the moving pillar, f . r_t with f = A (u e_x - r_t), and P x1_t
        "power": float(_GW @ (u * ax) - _GW @ (vxq * ax + vzq * az) + run.tip_load[k] * tip_speed),
        "elastic_rate": float(_GW @ (ths * thst)),
        # the power of the mass turning with the tangent (docstring of the ringing test)
        "turning_mass": float(
            -run.mu * (1.0 - chi) * _GW @ (cheb.chebval(xq, tt) * along * (tz * vxq - tx * vzq))
        ),
    }


def test_lobatto_series_interpolates() -> None:
    x = -np.cos(np.pi * np.arange(17) / 16)
    c = _lobatto_series(np.exp(x) * np.sin(3 * x))
    assert np.allclose(cheb.chebval(x, c), np.exp(x) * np.sin(3 * x), rtol=0.0, atol=1e-14)
    assert np.allclose(c, cheb.chebfit(x, np.exp(x) * np.sin(3 * x), 16), rtol=0, atol=1e-13)


def test_energy_balance_overdamped_independent_quadrature() -> None:
    """mu = 0: d(elastic)/dt = int theta_s theta_st ds from the nodal rates, at every output
    time of a step at a tilted base (measured 4.8e-13 of the largest power, 3.4)."""
    run = simulate_pillar(
        step(10.0), np.linspace(0.0, 0.5, 11), theta0=0.3, rtol=1e-10, atol=1e-12
    )
    assert run.success
    rows = [_budget(run, k, lambda z: z) for k in range(1, run.t.size)]
    rate = np.array([r["elastic_rate"] for r in rows])
    power = np.array([r["power"] for r in rows])
    assert np.max(np.abs(power)) > 1.0  # the pillar moves
    assert np.max(np.abs(rate - power)) <= 1e-10 * np.max(np.abs(power))


def test_energy_balance_ringing_independent_quadrature() -> None:
    """mu = 13, an anisotropic mass (chi = 0.6), a tilted base, the sublayer's forcing rising
    smoothly and a tip load: d(elastic + kinetic)/dt by fourth-order central differences
    (h = 2e-3: truncation h^4 ~ 1e-11) of the dense output at rtol 1e-10 against the power at
    the centre, at 7 times (measured 1.1e-9 of the largest power).

    The model's inertia -m_n [I - (1 - chi) t t] r_tt (theory.md §14, D3) is not the
    variation of K = (mu/2) int r_t . [I - (1 - chi) t t] r_t when chi < 1: the mass turns
    with the tangent (t_t = theta_t n), so the budget carries the extra power
    -mu (1 - chi) int theta_t (r_t . t)(r_t . n) ds (0.02 of the power here; zero for chi = 1).
    A tip load that changes in time adds a spatial error that falls with N (2.6e-8 at N = 16,
    3.5e-9 at N = 24): the load here is constant."""
    h = 2e-3
    centres = np.linspace(0.3, 1.8, 7)
    times = np.sort(np.concatenate([centres + j * h for j in (-2, -1, 0, 1, 2)]))
    run = simulate_pillar(
        sine(5.0, 5.0, np.pi, -0.5 * np.pi), np.concatenate([[0.0], times]), theta0=0.3,
        tip_load=0.5, mu=13.0, tangential_mass=0.6, num=16,
        rtol=1e-10, atol=1e-12,
    )  # fmt: skip
    assert run.success
    rows = [_budget(run, k, lambda z: z) for k in range(1, run.t.size)]
    total = np.array([r["elastic"] + r["kinetic"] for r in rows]).reshape(-1, 5)
    power = np.array([r["power"] + r["turning_mass"] for r in rows]).reshape(-1, 5)[:, 2]
    rate = (-total[:, 4] + 8.0 * total[:, 3] - 8.0 * total[:, 1] + total[:, 0]) / (12.0 * h)
    kinetic = np.array([r["kinetic"] for r in rows])
    assert np.max(kinetic) > 1e-2 * np.max(np.abs(total))  # inertia matters here
    turning = np.array([r["turning_mass"] for r in rows])
    assert np.max(np.abs(turning)) > 1e-2 * np.max(np.abs(power))  # the extra term matters
    assert np.max(np.abs(power)) > 0.5
    assert np.max(np.abs(rate - power)) <= 5e-9 * np.max(np.abs(power))


def test_the_trajectorys_own_energy_budget_with_an_anisotropic_mass() -> None:
    """PillarTrajectory.energy() with chi < 1: its input carries the turning mass's power
    -mu (1 - chi) int theta_t (r_t . t)(r_t . n) ds (0.019 of a power of 0.86 here)."""
    h = 2e-3
    centres = np.linspace(0.3, 1.8, 7)
    times = np.sort(np.concatenate([centres + j * h for j in (-2, -1, 0, 1, 2)]))
    run = simulate_pillar(
        sine(5.0, 5.0, np.pi, -0.5 * np.pi), np.concatenate([[0.0], times]), theta0=0.3,
        mu=13.0, tangential_mass=0.6, num=16, rtol=1e-10, atol=1e-12,
    )  # fmt: skip
    e = run.energy()
    total = (e["elastic"] + e["kinetic"])[1:].reshape(-1, 5)
    balance = (e["input"] - e["dissipation"])[1:].reshape(-1, 5)[:, 2]
    rate = (-total[:, 4] + 8.0 * total[:, 3] - 8.0 * total[:, 1] + total[:, 0]) / (12.0 * h)
    assert np.max(np.abs(rate - balance)) <= 5e-9 * np.max(np.abs(balance))


# ---------------------------------------------------------------- steady


def _wall_law(l_plus: float) -> Any:
    row = wall_law_coefficients(l_plus)[0][0]

    def profile(z: FloatArray) -> FloatArray:
        return np.asarray(cheb.chebval(2.0 * np.asarray(z) - 1.0, row))

    return profile


@pytest.mark.parametrize(
    ("lam", "theta0", "profile", "mu", "t_end"),
    [
        (5.0, -1.2, "sublayer", 0.0, 5.0),  # tilted far upstream, bent back over
        (40.0, -0.6, "sublayer", 0.0, 5.0),
        (10.0, 0.8, "sublayer", 0.0, 5.0),
        (12.0, 1.3, "sublayer", 0.0, 5.0),  # tilted far downstream, close to the wall
        (15.0, 0.2, "wall-law", 0.0, 5.0),  # Spalding's u+ at L+ = 30
        (10.0, -0.4, "sublayer", 0.2, 12.0),  # with inertia: decays like e^{-t/(2 mu)}
    ],
)
def test_constant_drive_relaxes_to_the_static_state_tilted(
    lam: float, theta0: float, profile: str, mu: float, t_end: float
) -> None:
    """Overdamped, a step from rest; with inertia the drive rises smoothly over one T and is
    then constant (a sharp step rings in every resolved mode, each decaying only at 1/(2 mu):
    100,000 steps at N = 32; measured within 7e-14 at t = 12 T)."""
    prof: Any = _wall_law(30.0) if profile == "wall-law" else profile
    st = hairbed.solve_pillar(lam, theta0, profile=prof)
    assert st.success
    drive: Any = step(lam)
    if mu > 0.0:

        def drive(t: FloatArray) -> FloatArray:
            return lam * 0.5 * (1.0 - np.cos(np.pi * np.minimum(t, 1.0)))

    run = simulate_pillar(
        drive, [0.0, 0.1, t_end], theta0=theta0, profile=prof, mu=mu, rtol=1e-9, atol=1e-11
    )
    assert run.success
    assert abs(st.tip_angle - theta0) > 0.05  # the pillar bent
    for ours, theirs in (
        (run.tip_deflection, st.tip_deflection),
        (run.tip_height, st.tip_height),
        (run.tip_angle, st.tip_angle),
        (run.base_moment, st.base_curvature),
    ):
        assert abs(ours[-1] - theirs) <= 1e-10 * max(1.0, abs(theirs)), (ours[-1], theirs)


# ---------------------------------------------------------------- nonlinear against linear


def test_small_pulse_about_a_large_deflection_is_the_linear_response_with_inertia() -> None:
    """mu = 13 about the state Lambda = 20, theta0 = 0.3 (x1 = 0.62): Lambda = 20 + eps g(t),
    g = exp(-(t - t0)^2/(2 s^2)) (s = 0.4, t0 = 3: g(0) = 6e-13). The linear response from
    rest is x(t) = (1/pi) Re int_0^inf H(w) G(w) e^{iwt} dw with G = s sqrt(2 pi)
    e^{-s^2 w^2/2 - i w t0}, by the trapezoidal rule (step 0.005: the integrand is analytic in
    a strip of half-width 1/(2 mu) = 0.038 about the real axis, error ~ e^{-2 pi 0.038/0.005}
    = 1e-21; cut at w = 20, where G ~ e^{-32}). The tip's motion minus eps x(t) is
    O(eps^2) (measured 2.7e-4 eps^2, ratio 4.00 for eps halved)."""
    lam0, theta0, mu = 20.0, 0.3, 13.0
    width, centre = 0.4, 3.0
    st = hairbed.solve_pillar(lam0, theta0, num=32)
    lin = linearise_pillar(st, mu=mu)
    dw = 0.005
    om = np.arange(0.0, 20.0 + 0.5 * dw, dw)
    big_h = lin.frequency_response(om).tip_deflection
    spectrum = width * np.sqrt(2.0 * np.pi) * np.exp(-0.5 * (width * om) ** 2 - 1j * om * centre)
    weights = np.full(om.size, dw)
    weights[0] = 0.5 * dw
    tt = np.linspace(1.5, 7.0, 12)
    linear = (np.exp(1j * np.outer(tt, om)) @ (weights * big_h * spectrum)).real / np.pi
    assert np.max(np.abs(linear)) > 5e-3  # the pulse moves the tip
    ts = np.linspace(0.0, 7.5, 3001)
    errs = []
    for eps in (1e-2, 5e-3):
        drive = sampled(ts, lam0 + eps * np.exp(-0.5 * ((ts - centre) / width) ** 2))
        run = simulate_pillar(
            drive, np.concatenate([[0.0], tt]), theta0=theta0, initial=st, mu=mu, num=16,
            rtol=1e-9, atol=1e-11, max_steps=40_000,
        )  # fmt: skip
        assert run.success
        errs.append(
            float(np.max(np.abs(run.tip_deflection[1:] - st.tip_deflection - eps * linear)))
        )
        assert errs[-1] <= 1e-3 * eps**2
    assert 3.5 <= errs[0] / errs[1] <= 4.5  # quadratic in the amplitude
