"""The porous bed's workflows (issue 29): the stress calibration curve, the linear
calibrations, and the calibration (model, fit, measure, linear range) take
``HairBed(..., model="porous")`` through the same code as the dense bed.

Every reference is independent of the code path it checks: forward solves
(:meth:`HairBed.deform`) against the inverses and fits, central differences against the
exact Jacobians and slopes.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from hairbed import HairBed, calibration
from hairbed.calibration import (
    FREE_PARAMETERS,
    _model,
    fit,
    linear_range,
    measure,
    model_tip_deflection,
)

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}
TRUE = HairBed(**BED, base_angle=0.3, model="porous")
VELOCITY = np.linspace(0.01, 0.2, 8)
GRADIENT = np.linspace(-2e3, 2e4, 8)
FLOW_RATE = np.linspace(1e-5, 2e-4, 8)
KNOWN = {
    "velocity": VELOCITY,
    "wall_shear_stress": np.linspace(1.0, 150.0, 6),
    "pressure_gradient": GRADIENT,
    "flow_rate": FLOW_RATE,
}


def _with(bed: HairBed, **changes: Any) -> HairBed:
    """``bed`` with ``changes``, spacing held (the packing fraction follows)."""
    keep = "packing_fraction" if "packing_fraction" not in changes else "spacing"
    return replace(bed, **{keep: None, **changes})


# -- the bed's own methods --------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.3, -0.4])
def test_velocity_from_wall_shear_stress_inverts_deform(angle: float) -> None:
    """The stress on the tip plane fixes the state: the speed back from it to 1e-12."""
    bed = _with(TRUE, base_angle=angle)
    v = np.array([-0.3, -0.02, 0.005, 0.05, 0.4])
    tau = bed.deform(v).wall_shear_stress
    back = bed.velocity_from_wall_shear_stress(tau)
    np.testing.assert_allclose(back, v, rtol=1e-12)
    assert bed.velocity_from_wall_shear_stress(0.0) == 0.0


def test_velocity_from_wall_shear_stress_in_a_window_of_three_states() -> None:
    """Hairs leaning into the flow of a tight channel: three states share a speed, and the
    stress still fixes each (states from the tip deflection inverse, across the window)."""
    bed = HairBed(
        length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=1e-3 / 0.95,
        viscosity=1.0, spacing=150e-6, base_angle=-1.2, model="porous",
    )  # fmt: skip
    d = bed.length * np.linspace(-0.85, 0.6, 9)
    st = bed.state_from_tip_deflection(d)
    back = bed.velocity_from_wall_shear_stress(st.wall_shear_stress)
    np.testing.assert_allclose(back, st.velocity, rtol=1e-10)


def test_linear_slopes_are_the_derivatives_at_rest() -> None:
    """dx1/d omega2 and dQ1/d omega2 at rest against central differences of deform."""
    for angle in (0.0, 0.5, -0.7):
        bed = _with(TRUE, base_angle=angle)
        h = 1e-4 * bed.velocity_scale
        up, down = bed.deform(h), bed.deform(-h)
        d_x1 = (up.tip_deflection - down.tip_deflection) / (2 * h) * bed.velocity_scale
        d_tau = (up.wall_shear_stress - down.wall_shear_stress) / (2 * h)
        slope, stress_slope = bed._linear_slopes()
        assert slope * bed.length == pytest.approx(d_x1, rel=1e-7)
        stress = bed.bending_stiffness / (bed.wall_area_per_hair * bed.length**2)
        assert stress_slope * stress / bed.velocity_scale == pytest.approx(d_tau, rel=1e-7)


def test_linear_calibrations_remainder_is_linear_in_the_speed() -> None:
    """v_lin/v - 1 and tau_lin/tau - 1 vanish like v (the first correction is quadratic in
    the load): halving v halves them, to 1 %."""
    bed = _with(TRUE, base_angle=0.2)
    errors = []
    for v in (2e-4, 1e-4):
        st = bed.deform(v)
        ev = bed.linear_velocity_from_tip_deflection(st.tip_deflection) / v - 1.0
        et = (
            bed.linear_wall_shear_stress_from_tip_deflection(st.tip_deflection)
            / st.wall_shear_stress
            - 1.0
        )
        errors.append((ev, et))
    (ev1, et1), (ev2, et2) = errors
    assert 0.0 < abs(ev2) < 1e-3
    assert ev1 / ev2 == pytest.approx(2.0, rel=1e-2)
    assert et1 / et2 == pytest.approx(2.0, rel=1e-2)


@pytest.mark.parametrize("drag", ["crossover", "sparse", "array"])
@pytest.mark.parametrize("geometry", ["spacing", "packing_fraction"])
def test_drag_slopes_against_central_differences(drag: str, geometry: str) -> None:
    """d ln kappa/d ln P and d gamma/d ln P against central differences of the bed's kappa
    and drag ratio (the drag models' own code)."""
    bed = _with(TRUE, drag=drag)
    slopes = bed._drag_slopes(geometry)
    keep = "packing_fraction" if geometry == "spacing" else "spacing"
    h = 1e-6
    for name in ("length", "radius", "spacing", "packing_fraction"):
        if name == keep:
            continue
        value = float(getattr(bed, name))
        up = replace(bed, **{keep: None, name: value * math.exp(h)})
        down = replace(bed, **{keep: None, name: value * math.exp(-h)})
        d_lnk = (math.log(up.kappa) - math.log(down.kappa)) / (2 * h)
        d_gam = (up.drag_ratio - down.drag_ratio) / (2 * h)
        assert slopes[name][0] == pytest.approx(d_lnk, rel=1e-7, abs=1e-9), name
        assert slopes[name][1] == pytest.approx(d_gam, rel=1e-7, abs=1e-9), name
    assert HairBed(**BED)._drag_slopes(geometry) == {}


# -- the calibration's model and its Jacobian -------------------------------------------------


def test_model_tip_deflection_is_the_deformed_beds() -> None:
    """The calibration curve of every known quantity against deform's tip deflection."""
    st = TRUE.deform(VELOCITY)
    np.testing.assert_allclose(
        model_tip_deflection(TRUE, velocity=VELOCITY), st.tip_deflection, rtol=1e-13
    )
    # the stress on the tip plane: the same states
    np.testing.assert_allclose(
        model_tip_deflection(TRUE, wall_shear_stress=st.wall_shear_stress),
        st.tip_deflection,
        rtol=1e-10,
    )
    np.testing.assert_allclose(
        model_tip_deflection(TRUE, velocity=-VELOCITY), TRUE.deform(-VELOCITY).tip_deflection,
        rtol=1e-10,
    )  # fmt: skip
    for kind, key in (("pressure_gradient", GRADIENT), ("flow_rate", FLOW_RATE)):
        ref = TRUE.deform(**{kind: key}).tip_deflection
        np.testing.assert_allclose(model_tip_deflection(TRUE, **{kind: key}), ref, rtol=1e-13)


@pytest.mark.parametrize("kind", list(KNOWN))
@pytest.mark.parametrize(
    ("geometry", "drag"),
    [("spacing", "crossover"), ("packing_fraction", "crossover"), ("spacing", "array"),
     ("packing_fraction", "sparse")],
)  # fmt: skip
def test_jacobian_against_central_differences(kind: str, geometry: str, drag: str) -> None:
    """Every column of the exact Jacobian (the state's implicit derivatives in omega2, eps,
    theta0, kappa, gamma through the SI scaling and the drag law) and dD/dx against central
    differences of the model's deflection."""
    bed = _with(TRUE, drag=drag)
    x = KNOWN[kind]
    x = np.concatenate([x, -x[:2]])  # flow against the grain too
    skip = "packing_fraction" if geometry == "spacing" else "spacing"
    free = tuple(p for p in FREE_PARAMETERS if p != skip)
    _, jac, dx, _ = _model(bed, kind, x, free, geometry)

    def model(b: HairBed, xx: np.ndarray) -> np.ndarray:
        return _model(b, kind, xx, (), geometry)[0]

    for j, name in enumerate(free):
        value = float(getattr(bed, name))
        h = 1e-6 * max(abs(value), 1e-3)
        up = replace(bed, **{skip: None, name: value + h})
        down = replace(bed, **{skip: None, name: value - h})
        ref = (model(up, x) - model(down, x)) / (2 * h)
        # per unit ln P [m]; a parameter the data do not hold (viscosity of stress data)
        # has the differences' rounding (1e-12 m) against an exact 0: a floor of 1e-2 L
        scale = max(np.max(np.abs(ref)) * value, 1e-2 * bed.length)
        assert np.max(np.abs(jac[:, j] - ref)) * value / scale < 1e-6, name
    h = 1e-6 * np.abs(x)
    ref = (model(bed, x + h) - model(bed, x - h)) / (2 * h)
    assert np.max(np.abs(dx - ref) / np.abs(ref)) < 1e-6


# -- fit ----------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kind", "free", "start"),
    [
        ("velocity", ("youngs_modulus", "base_angle"),
         {"youngs_modulus": 1.5e6, "base_angle": 0.1}),
        ("velocity", ("length",), {"length": 1.04e-3}),
        ("velocity", ("radius",), {"radius": 47e-6}),
        ("velocity", ("spacing",), {"spacing": 430e-6}),
        ("velocity", ("packing_fraction",), {"packing_fraction": 0.05}),
        ("wall_shear_stress", ("youngs_modulus", "base_angle"), {"youngs_modulus": 7e5}),
        ("wall_shear_stress", ("radius",), {"radius": 53e-6}),
        ("pressure_gradient", ("youngs_modulus",), {"youngs_modulus": 1.4e6}),
        ("flow_rate", ("youngs_modulus", "viscosity"), {"youngs_modulus": 1.4e6}),
        ("flow_rate", ("channel_height",), {"channel_height": 2.1e-3}),
    ],
)  # fmt: skip
def test_fit_recovers_the_true_parameters(
    kind: str, free: tuple[str, ...], start: dict[str, float]
) -> None:
    """Deflections of the porous bed itself (deform), fitted from a wrong start: the true
    values to 1e-8, with status 0. (E and eta enter flow-rate data together: that fit is
    the singular one, named.)"""
    if kind == "wall_shear_stress":
        x = TRUE.deform(VELOCITY).wall_shear_stress
        d = TRUE.deform(VELOCITY).tip_deflection
    else:
        x = KNOWN[kind]
        d = TRUE.deform(**{kind: x}).tip_deflection
    guess = (
        _with(TRUE, **start)
        if "packing_fraction" not in start
        else replace(TRUE, spacing=None, **start)
    )
    res = fit(guess, d, sigma=1e-6, free=free, **{kind: x})
    if "viscosity" in free:
        assert res.status == -4 and not res.success and "viscosity" in res.message
        return
    assert res.status == 0 and res.success, res.message
    assert res.bed.model == "porous" and res.bed.drag == TRUE.drag
    for name in free:
        assert res.values[name] == pytest.approx(float(getattr(TRUE, name)), rel=1e-8), name
    assert np.max(np.abs(res.residuals)) < 1e-12


def test_fit_bounds_keep_the_porous_packing_fraction() -> None:
    """A porous bed's packing fraction is fitted below its drag law's limit (0.6), not
    close packing: the bound of the fitted coordinate."""
    lo, hi = calibration._bounds(TRUE, ("packing_fraction",), "packing_fraction")
    assert math.exp(hi[0]) == pytest.approx(0.6, rel=1e-8) and math.exp(hi[0]) < 0.6


# -- measure ------------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.3, -0.5])
def test_measure_round_trip_and_sigma(angle: float) -> None:
    """Speed and stress read back from deform's deflections to 1e-12, each standard error
    |dy/dD| sigma with dy/dD by central differences of the forward solve."""
    bed = _with(TRUE, base_angle=angle)
    v = np.array([-0.1, 0.02, 0.15])
    st = bed.deform(v)
    sigma = 1e-6
    m = measure(bed, st.tip_deflection, sigma=sigma)
    assert m.success and m.status == 0
    np.testing.assert_allclose(m.velocity, v, rtol=1e-11)
    np.testing.assert_allclose(m.wall_shear_stress, st.wall_shear_stress, rtol=1e-11)
    h = 1e-6 * np.abs(v)
    up, down = bed.deform(v + h), bed.deform(v - h)
    d_dv = (up.tip_deflection - down.tip_deflection) / (2 * h)
    d_dtau = (up.tip_deflection - down.tip_deflection) / (
        up.wall_shear_stress - down.wall_shear_stress
    )
    np.testing.assert_allclose(m.velocity_stderr, sigma / np.abs(d_dv), rtol=1e-6)
    np.testing.assert_allclose(m.wall_shear_stress_stderr, sigma / np.abs(d_dtau), rtol=1e-6)


def test_measure_carries_the_fit_covariance() -> None:
    """var(v) = (sigma/(dD/dv))^2 + (dv/dE)^2 var(E), dv/dE at fixed D by central
    differences of the porous inverse of perturbed beds."""
    d = TRUE.deform(VELOCITY).tip_deflection
    noise = np.random.default_rng(5).normal(0.0, 2e-6, d.size)
    cal = fit(_with(TRUE, youngs_modulus=1.3e6), d + noise, velocity=VELOCITY, sigma=2e-6)
    bed = cal.bed
    target = 5e-4
    m = measure(bed, target, sigma=2e-6)
    mf = measure(bed, target, sigma=2e-6, fit=cal)
    e = bed.youngs_modulus
    he = 1e-6 * e
    dv_de = (
        _with(bed, youngs_modulus=e + he).velocity_from_tip_deflection(target)
        - _with(bed, youngs_modulus=e - he).velocity_from_tip_deflection(target)
    ) / (2 * he)
    expect = math.sqrt(m.velocity_stderr**2 + dv_de**2 * cal.stderr["youngs_modulus"] ** 2)
    assert mf.velocity_stderr == pytest.approx(expect, rel=1e-6)
    assert mf.status == 0


def test_measure_in_a_window_uses_the_state_the_deflection_fixes() -> None:
    """Three states share a speed: measure's errors are those of the state the deflection
    fixes (the middle one's too), sigma |dv/dD| with dv/dD by central differences of the
    porous inverse."""
    from hairbed.porous_curves import porous_branch

    bed = HairBed(
        length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=1e-3 / 0.95,
        viscosity=1.0, spacing=150e-6, base_angle=-1.2, model="porous",
    )  # fmt: skip
    branch = porous_branch(bed.eps, bed.base_angle, kappa=bed.kappa, gamma=bed.drag_ratio, num=60)
    lo, hi = sorted(branch.fold_tip_deflection)
    d = bed.length * np.array([lo - 0.05, 0.5 * (lo + hi), hi + 0.05])
    m = measure(bed, d, sigma=1e-6)
    st = bed.state_from_tip_deflection(d)
    np.testing.assert_allclose(m.velocity, st.velocity, rtol=1e-12)
    h = 1e-9
    dv = (bed.velocity_from_tip_deflection(d + h) - bed.velocity_from_tip_deflection(d - h)) / (
        2 * h
    )
    np.testing.assert_allclose(m.velocity_stderr, np.abs(dv) * 1e-6, rtol=1e-5)
    assert dv[1] < 0.0 < dv[0] and dv[2] > 0.0  # the middle state: v falls as D rises


@pytest.mark.parametrize("kind", ["pressure_gradient", "flow_rate"])
def test_measure_pump_driven_round_trip(kind: str) -> None:
    """A pump's drive read back from deform's deflections to 1e-9; the other drive's and
    the stress's standard errors through central differences of deform in the drive."""
    x = KNOWN[kind][[1, 4, 7]]
    st = TRUE.deform(**{kind: x})
    sigma = 1e-6
    m = measure(TRUE, st.tip_deflection, sigma=sigma, drive=kind)
    assert m.status == 0, m.message
    got = m.pressure_gradient if kind == "pressure_gradient" else m.flow_rate
    np.testing.assert_allclose(got, x, rtol=1e-9)
    h = 1e-6 * np.abs(x)
    up, down = TRUE.deform(**{kind: x + h}), TRUE.deform(**{kind: x - h})
    d_dx = (up.tip_deflection - down.tip_deflection) / (2 * h)
    err = sigma / np.abs(d_dx)
    mine = m.pressure_gradient_stderr if kind == "pressure_gradient" else m.flow_rate_stderr
    np.testing.assert_allclose(mine, err, rtol=1e-6)
    other = "flow_rate" if kind == "pressure_gradient" else "pressure_gradient"
    d_other = (getattr(up, other) - getattr(down, other)) / (2 * h)
    np.testing.assert_allclose(getattr(m, other + "_stderr"), np.abs(d_other) * err, rtol=1e-6)
    d_tau = (up.wall_shear_stress - down.wall_shear_stress) / (2 * h)
    np.testing.assert_allclose(m.wall_shear_stress_stderr, np.abs(d_tau) * err, rtol=1e-6)


# -- linear range -------------------------------------------------------------------------------


@pytest.mark.parametrize("angle", [0.0, 0.4])
def test_linear_range_ends_where_the_linear_calibration_misses_by_rtol(angle: float) -> None:
    """At the range's end the bed's own linear calibrations miss the exact ones (their
    inverses) by rtol; halfway there by less."""
    bed = _with(TRUE, base_angle=angle)
    rng = linear_range(bed, 0.05)
    assert rng.success and rng.quantity == "both"
    for quantity, lin, exact in (
        ("velocity", bed.linear_velocity_from_tip_deflection, bed.velocity_from_tip_deflection),
        ("wall_shear_stress", bed.linear_wall_shear_stress_from_tip_deflection,
         bed.wall_shear_stress_from_tip_deflection),
    ):  # fmt: skip
        one = rng.limits[quantity]
        d = one.tip_deflection
        assert lin(d) / exact(d) - 1.0 == pytest.approx(-0.05, abs=1e-9), quantity
        assert one.velocity == pytest.approx(bed.velocity_from_tip_deflection(d), rel=1e-10)
        assert one.wall_shear_stress == pytest.approx(
            bed.wall_shear_stress_from_tip_deflection(d), rel=1e-10
        )
        rest = bed.length * math.sin(angle)
        half = rest + 0.5 * (d - rest)
        assert abs(lin(half) / exact(half) - 1.0) < 0.05
    assert rng.tip_deflection == min(r.tip_deflection for r in rng.limits.values())


# -- valve states ---------------------------------------------------------------------------


def _all_states(bed: HairBed, drive: str, load: float) -> list[Any]:
    """Every state of the porous bed at a pump's load by solve_porous_all (its own scan)."""
    import hairbed

    kw = {"pi": load} if drive == "pressure" else {"q": load}
    found = hairbed.solve_porous_all(
        0.0, bed.eps, bed.base_angle, kappa=bed.kappa, gamma=bed.drag_ratio, **kw
    )
    return [s for s in found if s.status >= 0]


def test_valve_states_are_those_of_solve_porous_all_and_the_valve_curve() -> None:
    """A set pressure drop (one state at each): valve_states' states against
    solve_porous_all's at the same drive, and their flow and resistance against
    valve_curve's (the porous bed's deform)."""
    from hairbed import valve
    from hairbed._channel_drives import load_scale

    bed = HairBed(**{**BED, "length": 1.8e-3}, base_angle=1.0, model="porous")
    drop = np.linspace(-200.0, 200.0, 5)
    s = valve.valve_states(bed, 0.01, pressure_drop=drop)
    assert s.success and s.status == 0 and s.count.tolist() == [1] * 5
    scale = load_scale(bed, "pressure") / 0.01
    for i, dp in enumerate(drop):
        (ref,) = _all_states(bed, "pressure", dp * scale)
        assert s.tip_height[i, 0] == pytest.approx(float(ref.tip_height) * bed.length, rel=1e-9)
        assert bool(s.stable[i, 0]) == bool(ref.stable)
    curve = valve.valve_curve(bed, drop, 0.01)
    np.testing.assert_allclose(s.flow_rate[:, 0], curve.flow_rate, rtol=1e-8, atol=1e-20)
    np.testing.assert_allclose(s.resistance_ratio[:, 0], curve.resistance_ratio, rtol=1e-8)
    np.testing.assert_array_equal(s.pressure_drop[:, 0], drop)


def test_valve_states_of_a_bistable_porous_valve() -> None:
    """A set flow rate against the hairs' lean (the dense bed's bistable valve, porous):
    at every grid point valve_states finds the states solve_porous_all finds, with their
    stability, and a fold between. Past the fold the hairs reach pi/2, outside the model,
    where solve_porous_all finds no state either: the continuation stops there, and says so
    (status -3, those points not covered)."""
    from hairbed import valve
    from hairbed._channel_drives import load_scale

    bed = HairBed(**{**BED, "length": 1.6e-3}, base_angle=-1.2, model="porous")
    flow = np.linspace(0.0, 3e-6, 7)
    s = valve.valve_states(bed, 0.01, flow_rate=flow)
    assert s.count.tolist() == [1, 1, 1, 1, 2, 0, 0]
    assert s.status == -3 and not s.success and "reached" in s.message
    assert s.covered.tolist() == [True] * 5 + [False] * 2
    scale = load_scale(bed, "flow")
    for i, q in enumerate(flow):
        ref = _all_states(bed, "flow", q * scale)
        assert s.count[i] == len(ref), q
        got = s.tip_height[i, : len(ref)]
        want = [float(r.tip_height) * bed.length for r in ref]
        np.testing.assert_allclose(got, want, rtol=1e-8)
        assert s.stable[i, : len(ref)].tolist() == [bool(r.stable) for r in ref]
    np.testing.assert_array_equal(s.flow_rate[:5, 0], flow[:5])
    # the fold where the stable and the unstable state meet: past the grid's 2e-6
    assert s.fold_flow_rate.size == 1 and 2e-6 < s.fold_flow_rate[0] < 2.5e-6
    assert s.tip_height[4, 0] < s.fold_tip_height[0] < s.tip_height[4, 1]


# -- profile fit ---------------------------------------------------------------------------


@pytest.mark.parametrize("free_angle", [False, True])
def test_fit_profile_recovers_the_deformed_porous_hair(free_angle: bool) -> None:
    """Points along deform's hair: the speed (and the base angle) back to 1e-10, the rms
    distance at rounding, the fitted state the porous bed's own (its tip deflection)."""
    bed = _with(TRUE, base_angle=0.3)
    st = bed.deform(0.05)
    x, z = st.profile(20)
    kw = {"theta0": None, "theta0_guess": 0.1} if free_angle else {}
    fit_ = bed.fit_profile(x, z, **kw)
    assert fit_.success and fit_.status == 0
    assert fit_.velocity == pytest.approx(0.05, rel=1e-10)
    assert fit_.fit.theta0 == pytest.approx(0.3, abs=1e-10)
    assert fit_.fit.residual < 1e-12
    assert float(fit_.fit.solution.tip_deflection) * bed.length == pytest.approx(
        st.tip_deflection, rel=1e-10
    )


def test_fit_profile_of_the_middle_state_of_a_window() -> None:
    """Three states share a speed; the profile of the middle (unstable) one, from the porous
    inverse of its tip deflection, fits back to that state, not another root."""
    from hairbed.porous_curves import porous_branch

    bed = HairBed(
        length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=1e-3 / 0.95,
        viscosity=1.0, spacing=150e-6, base_angle=-1.2, model="porous",
    )  # fmt: skip
    branch = porous_branch(bed.eps, bed.base_angle, kappa=bed.kappa, gamma=bed.drag_ratio, num=60)
    assert branch.window is not None
    x_mid = float(np.mean(branch.fold_tip_deflection))  # between the folds: unstable
    st = bed.state_from_tip_deflection(x_mid * bed.length)
    x, z = st.profile(25)
    fit_ = bed.fit_profile(x, z)
    assert fit_.success
    assert fit_.velocity == pytest.approx(st.velocity, rel=1e-9)
    assert float(fit_.fit.solution.tip_deflection) == pytest.approx(x_mid, abs=1e-10)
