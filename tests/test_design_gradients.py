"""hairbed.design: every quantity's gradient against central differences (issue 32).

The gradient the optimiser uses (d quantity/du in the unit box of the variables, from the
library's exact derivatives and the chain rule through the SI scalings) is compared with a
fourth-order central difference of the quantity's *value* at 20 random designs: an
independent path (the value alone, solved anew at each shifted design).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

from hairbed import HairBed, Pillar
from hairbed import design as D
from hairbed.design._optimise import _Problem
from hairbed.dynamics import linearise_pillar
from hairbed.valve import valve_curve

RTOL = 1e-7
DESIGNS = 20


def _bed() -> HairBed:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                       viscosity=1.0, spacing=250e-6, base_angle=0.5, density=1200.0)  # fmt: skip


def _pillar() -> Pillar:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Pillar(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3,
                      density=1000.0, base_angle=0.2)  # fmt: skip


BED_SPACE = [
    D.Variable("length", 0.6e-3, 1.4e-3, log=True),
    D.Variable("radius", 30e-6, 60e-6),
    D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    D.Variable("channel_height", 1.6e-3, 3e-3),
    D.Variable("viscosity", 0.5, 2.0),
    D.Variable("spacing", 200e-6, 400e-6),
    D.Variable("base_angle", 0.1, 1.2),
    D.Variable("density", 800.0, 1500.0),
]
PHI_SPACE = [*BED_SPACE[:5], D.Variable("packing_fraction", 0.05, 0.2), *BED_SPACE[6:]]
WINDOW_SPACE = [
    D.Variable("length", 1.9e-3, 1.98e-3),
    D.Variable("radius", 30e-6, 60e-6, log=True),
    D.Variable("youngs_modulus", 0.5e6, 2e6),
    D.Variable("channel_height", 2.0e-3, 2.02e-3),
    D.Variable("spacing", 200e-6, 400e-6),
    D.Variable("base_angle", -1.4, -0.9),
]
PILLAR_SPACE = [
    D.Variable("length", 300e-6, 800e-6),
    D.Variable("radius", 15e-6, 30e-6, log=True),
    D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    D.Variable("viscosity", 0.5e-3, 2e-3),
    D.Variable("base_angle", -0.5, 0.5),
    D.Variable("density", 800.0, 1200.0),
    D.Variable("drag_scale", 0.8, 1.2),
]
#: Pillars whose slowest mode rings clearly (damping ratio below about 0.4): near critical
#: damping Im(lambda) has a square-root branch point, where the central differences of
#: step 1e-3 lose their fourth order (the gradient stays exact; the stencil does not).
RING_SPACE = [
    D.Variable("length", 300e-6, 600e-6),
    D.Variable("radius", 20e-6, 30e-6, log=True),
    D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    D.Variable("viscosity", 0.5e-3, 1e-3),
    D.Variable("base_angle", -0.5, 0.5),
    D.Variable("density", 800.0, 1200.0),
]

#: Pillars tilted far upstream: a snap-through window (its folds followed by the secant
#: method; E only scales it).
SNAP_SPACE = [
    D.Variable("length", 300e-6, 800e-6),
    D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    D.Variable("base_angle", -1.45, -1.36),
]
#: The porous (Brinkman) bed's valve: kappa and gamma move with the length, the radius and
#: the spacing or packing fraction (the drag model's exact slopes).
POROUS_SPACE = [
    D.Variable("length", 0.6e-3, 1.4e-3, log=True),
    D.Variable("radius", 30e-6, 60e-6),
    D.Variable("spacing", 200e-6, 400e-6),
    D.Variable("base_angle", 0.1, 0.8),
]
POROUS_PHI_SPACE = [
    D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    D.Variable("channel_height", 1.6e-3, 3e-3),
    D.Variable("viscosity", 0.5, 2.0),
    D.Variable("packing_fraction", 0.05, 0.2),
]

CASES = [
    ("bed", BED_SPACE, D.diodicity(1000.0, 0.01)),
    ("bed", PHI_SPACE, D.diodicity(1000.0, 0.01)),
    ("bed", BED_SPACE, D.resistance_ratio(1000.0, 0.01)),
    ("bed", BED_SPACE, D.resistance_ratio(-800.0, 0.01)),
    ("bed", BED_SPACE, D.gap_reynolds(1000.0, 0.01)),
    ("bed", PHI_SPACE, D.gap_reynolds(-1000.0, 0.01)),
    ("bed", BED_SPACE, D.brinkman_ratio()),
    ("bed", PHI_SPACE, D.brinkman_ratio()),
    ("window", WINDOW_SPACE, D.bistable_width()),
    ("pillar", PILLAR_SPACE, D.tip_deflection(1.0)),
    ("pillar", PILLAR_SPACE, D.linear_range(0.05)),
    ("pillar", PILLAR_SPACE, D.tip_deflection(D.linear_range(0.05))),
    ("pillar", PILLAR_SPACE, D.l_plus(2.0)),
    ("pillar", PILLAR_SPACE, D.l_plus(D.linear_range(0.1))),
    ("pillar", PILLAR_SPACE, D.pillar_reynolds(1.0)),
    ("pillar", PILLAR_SPACE, D.pillar_reynolds(D.linear_range(0.05))),
    ("pillar", PILLAR_SPACE, D.slenderness()),
    ("pillar", PILLAR_SPACE, D.linear_sensitivity()),
    ("pillar", PILLAR_SPACE, D.sensitivity(1.0)),
    ("pillar", PILLAR_SPACE, D.bandwidth(1.0)),
    ("pillar", RING_SPACE, D.resonance_frequency(1.0, 1000.0)),
    ("snap", SNAP_SPACE, D.snap_window()),
    ("porous", POROUS_SPACE, D.diodicity(300.0, 0.01)),
    ("porous", POROUS_PHI_SPACE, D.resistance_ratio(-250.0, 0.01)),
]


def _slowest(p, tau, mu=0.0, chi=1.0):
    """The slowest eigenvalue of the pillar's linear dynamics about its state at tau [Pa]
    (the public dynamics API) and the time scale T = zeta_perp L^4/(E I) [s]."""
    lin = linearise_pillar(p.deform(tau).solution, profile="sublayer", mu=mu, tangential_mass=chi)
    t_scale = p.normal_drag_coefficient * p.length**4 / p.bending_stiffness
    return complex(lin.modes(2).eigenvalues[0]), t_scale


def _band_value(p):
    lam, t_scale = _slowest(p, 1.0)
    return -lam.real / (2.0 * np.pi * t_scale)


def _resonance_value(p, rho_s=1000.0):
    zeta = p.normal_drag_coefficient
    t_scale = zeta * p.length**4 / p.bending_stiffness
    mu = (rho_s + p.density) * np.pi * p.radius**2 / (zeta * t_scale)
    lam, _ = _slowest(p, 1.0, mu, rho_s / (rho_s + p.density))
    return lam.imag / (2.0 * np.pi * t_scale)


def _porous_diodicity(bed):
    """Q'(+dp)/abs(Q'(-dp)) of the valve curve (both drops in one call)."""
    q = valve_curve(bed, np.array([300.0, -300.0]), 0.01).flow_rate
    return q[0] / -q[1]


#: The value of a quantity by the library's public API (cheaper than the quantity's value
#: and gradient, and another path to it), for the central differences.
VALUES = {
    "sensitivity(1 Pa)": lambda p: p.sensitivity(1.0),
    "bandwidth(1 Pa)": _band_value,
    "resonance_frequency(1 Pa, rho_s=1000 kg/m^3)": _resonance_value,
    "diodicity(dp=300 Pa, l=0.01 m)": lambda bed: _porous_diodicity(bed),
    "resistance_ratio(dp=-250 Pa, l=0.01 m)": lambda bed: (
        valve_curve(bed, -250.0, 0.01).resistance_ratio
    ),
}


def _base(kind: str):
    if kind == "pillar":
        return _pillar()
    if kind == "porous":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                           viscosity=1.0, spacing=250e-6, base_angle=0.5,
                           model="porous")  # fmt: skip
    if kind == "snap":
        return dataclasses.replace(_pillar(), base_angle=-1.4)
    if kind == "window":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return HairBed(length=1.95e-3, radius=50e-6, youngs_modulus=1e6,
                           channel_height=2.01e-3, viscosity=1.0, spacing=250e-6,
                           base_angle=-1.0)  # fmt: skip
    return _bed()


def _central(problem: _Problem, u: np.ndarray, h: float = 1e-3) -> np.ndarray:
    """Fourth-order central differences of the objective's value in each u_i."""

    def f(x: np.ndarray) -> float:
        model = problem.space.model(problem.space.values(x))
        if problem.objective.name in VALUES:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return float(VALUES[problem.objective.name](model))
        return problem.objective.evaluate(model, problem.space.hold)[0]

    g = np.empty(u.size)
    for i in range(u.size):
        e = np.zeros(u.size)
        e[i] = h
        g[i] = (8.0 * (f(u + e) - f(u - e)) - (f(u + 2 * e) - f(u - 2 * e))) / (12.0 * h)
    return g


def _worst(kind, space, q, designs=DESIGNS, seed=0):
    problem = _Problem(D.Space(_base(kind), space), q, [])
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(designs):
        u = rng.uniform(0.02, 0.98, len(space))  # the stencil stays in the box
        exact = problem.at(u)[1][0]
        ref = _central(problem, u)
        worst = max(worst, float(np.max(np.abs(exact - ref)) / np.max(np.abs(ref))))
    return worst


@pytest.mark.parametrize(("kind", "space", "q"), CASES, ids=[c[2].name for c in CASES])
def test_gradient_matches_central_differences(kind, space, q):
    assert q.exact
    assert _worst(kind, space, q) <= RTOL


def test_the_linear_sensitivity_is_the_small_stress_limit():
    p = _pillar()
    assert D.linear_sensitivity()(p) == pytest.approx(p.sensitivity(1e-7), rel=1e-6)


def test_a_custom_quantity_without_gradient_is_marked_inexact():
    q = D.custom(lambda bed: bed.length / bed.radius, "aspect")
    assert not q.exact
    with_grad = D.custom(
        lambda bed: bed.length / bed.radius,
        "aspect",
        gradient=lambda bed: {"length": 1 / bed.radius, "radius": -bed.length / bed.radius**2},
    )
    assert with_grad.exact
    for quantity in (q, with_grad):
        problem = _Problem(D.Space(_bed(), BED_SPACE[:2]), quantity, [])
        u = np.array([0.3, 0.6])
        np.testing.assert_allclose(problem.at(u)[1][0], _central(problem, u), rtol=1e-6)


def test_the_jets_residual_is_the_kernels():
    """The residual run on jets (the second derivatives' path) is the compiled kernel's:
    zero at a converged state, its Jacobian the kernel's exact Jacobian and its partials in
    (Lambda, theta0, gamma) those of the first-order system; du/dLambda gives the kernel's
    tip slope."""
    from hairbed._core.pillar import _solve_pillar_checked
    from hairbed.design._pillar_second import _first, _inputs, _partials, _residual
    from hairbed.dynamics._operators import state_operators

    p = _pillar()
    prof = np.asarray(p._core_options[0])[0]
    for lam, th, g in [(3.0, 0.2, 0.7), (300.0, -0.4, 0.62)]:
        args = (np.array(lam), np.array(th), np.array(g), np.zeros(()))
        st = _solve_pillar_checked(*args, *p._core_options)
        num = int(st.num)
        first = _first(st, prof)
        m = first.u.size
        res = _residual(
            first.lev, *_inputs(first.u, first.p, np.eye(m + 3), np.zeros((0, m + 3))), prof=prof
        )
        assert np.max(np.abs(res.v)) <= 1e-9 * (1.0 + lam)
        jac, r_p = _partials(first.lev, first.u, first.p, prof)
        coefs = np.asarray(st._coefs)[0].reshape(-1)[: num + 1]
        ops = state_operators(num, float(st._map), coefs, lam, g, 0.0, prof, 1.0)
        big = np.abs(ops.jac).max()
        np.testing.assert_allclose(res.a[:m].T, ops.jac, rtol=0, atol=1e-12 * big)
        np.testing.assert_allclose(res.a[:m].T, jac, rtol=0, atol=1e-12 * big)
        np.testing.assert_allclose(res.a[m:].T, r_p, rtol=0, atol=1e-12 * np.abs(r_p).max())
        # du/dLambda against the kernel's tip slope dx1/dLambda
        x1_u = ops.ii[num] * np.cos(ops.theta)
        assert x1_u @ first.du[: num + 1, 0] == pytest.approx(
            float(st.tip_deflection_slope), rel=1e-12
        )
