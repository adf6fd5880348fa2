"""The bed's periodic steady state by collocation in time (hairbed.dynamics.periodic_bed).

References that share no code with the collocation: the long transient of the compiled
Radau IIA integrator (simulate_bed, run until the start has decayed far below the
tolerance); central finite differences of periodic_bed itself in a drive's amplitude for the
forced variational equation (periodic_sensitivity solves a linear system, the differences
two nonlinear ones); the linear bed's transfer function and the quasi-static rheology are
the references of tests/test_rheometer_large.py, which runs the collocation by default.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import (
    PeriodicBed,
    bed_operators,
    periodic_bed,
    periodic_sensitivity,
    simulate_bed,
    sine,
    step,
)

HALF_PI = 0.5 * math.pi


@pytest.fixture(scope="module")
def laos() -> PeriodicBed:
    # kappa = 1, eps = 0.5, the wall forcing cos(t): the hairs swing by 0.3 rad
    return periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0, 1.0, HALF_PI))


def test_collocation_is_the_long_transient(laos: PeriodicBed) -> None:
    """Six periods of Radau IIA at rtol 1e-11 (the slowest mode decays like e^(-14.9 t): the
    start is gone to 1e-40): the last period's states and stress equal the collocation's to
    1e-8 (measured 4.9e-11 on the stress)."""
    assert laos.success, laos.message
    assert laos.error < 1e-10
    period = 2.0 * math.pi
    t = np.linspace(0.0, 6.0 * period, 6 * 16 + 1)
    run = simulate_bed(0.0, 1.0, 0.5, t_eval=t, wall=sine(0.0, 1.0, 1.0, HALF_PI),
                       rtol=1e-11, atol=1e-11)  # fmt: skip
    assert run.success
    last = t[-17:-1]
    out = laos.outputs_at(last)
    stress = run.wall_stress[-17:-1]
    assert np.max(np.abs(out["wall_stress"] - stress)) < 1e-8 * np.max(np.abs(stress))
    theta = laos.states_at(last)[:, : run.num - 1]
    assert np.max(np.abs(theta - run.theta[-17:-1, 1:-1])) < 1e-8
    assert np.max(np.abs(out["tip_deflection"] - run.tip_deflection[-17:-1])) < 1e-8
    # the phases' own values: the interpolant passes through them
    np.testing.assert_allclose(laos.states_at(laos.t), laos.y, rtol=0, atol=1e-13)
    # the upright bed's state has half-wave symmetry: the mean stress vanishes
    assert abs(laos.mean("wall_stress")) < 1e-12


def test_strong_drive_needs_continuation_and_agrees_with_the_transient() -> None:
    """omega = 10, the forcing swings by +-30: the tips swing by +-1.1 rad and the harmonics
    decay by only 0.38 per odd pair. Newton from the linear response fails; the amplitude
    continuation converges, with H = 96 (measured stress difference 2.3e-12; checked here at
    the transient's cheaper 1e-9)."""
    wall = sine(0.0, 30.0, 10.0, HALF_PI)
    st = periodic_bed(0.0, 1.0, 0.5, omega=10.0, wall=wall)
    assert st.success and st.start == "continuation" and st.harmonics >= 48
    period = 2.0 * math.pi / 10.0
    t = np.linspace(0.0, 5.0 * period, 5 * 8 + 1)
    run = simulate_bed(0.0, 1.0, 0.5, t_eval=t, wall=wall, rtol=1e-9, atol=1e-9)
    stress = run.wall_stress[-9:-1]
    out = st.outputs_at(t[-9:-1])["wall_stress"]
    assert np.max(np.abs(out - stress)) < 1e-6 * np.max(np.abs(stress))


def test_fluid_inertia_and_a_pressure_drive_agree_with_the_transient() -> None:
    """womersley = 0.5 (the fluid's velocities are differential unknowns: the general
    ordering of the Schur complement), a tilted bed, the pressure 2 sin(t): four periods of
    Radau IIA at rtol 1e-10 (the last two agree to 1e-11) against the collocation, to 1e-8
    (measured 3.9e-11 on the flow rate, 4.8e-11 on the stress)."""
    drive = {"pressure": sine(0.0, 2.0, 1.0), "womersley": 0.5}
    st = periodic_bed(0.4, 0.5, 0.5, omega=1.0, **drive)
    assert st.success, st.message
    t = np.linspace(0.0, 8.0 * math.pi, 4 * 8 + 1)
    run = simulate_bed(0.4, 0.5, 0.5, t_eval=t, rtol=1e-10, atol=1e-10, **drive)
    out = st.outputs_at(t[-9:-1])
    for name in ("flow_rate", "wall_stress", "tip_deflection"):
        ref = getattr(run, name)[-9:-1]
        assert np.max(np.abs(out[name] - ref)) < 1e-8 * np.max(np.abs(ref)), name


def test_sensitivity_is_the_finite_difference_of_the_orbit(laos: PeriodicBed) -> None:
    """d/dA of the orbit under the wall forcing A cos(t), at A = 1: the forced variational
    equation with G = b_wall cos(t) (b_wall, the rates' column of the wall drive, from
    bed_operators) against central differences of periodic_bed at A +- 1e-4 (truncation
    ~1e-9)."""
    rest = hairbed.solve_porous(0.0, 0.5, 0.0, kappa=1.0)
    col = bed_operators(rest, num=32).drives["wall"]  # g is affine in the wall's drive
    forcing = np.cos(laos.t)[:, None] * col[None, :]
    sens = periodic_sensitivity(laos, forcing)
    h = 1e-4
    plus = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0 + h, 1.0, HALF_PI))
    minus = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0 - h, 1.0, HALF_PI))
    assert plus.y.shape == laos.y.shape == minus.y.shape
    fd = (plus.y - minus.y) / (2.0 * h)
    scale = np.max(np.abs(fd), axis=0) + 1.0
    assert np.max(np.abs(sens.states[:, :, 0] - fd) / scale) < 1e-7
    np.testing.assert_allclose(sens.initial[:, 0], sens.states[0, :, 0], rtol=0, atol=0)
    # the mean of tip_height moves at second order in A: its derivative is not zero
    for name in ("tip_height", "base_moment"):
        fd_mean = (plus.mean(name) - minus.mean(name)) / (2.0 * h)
        assert sens.mean_outputs[name][0] == pytest.approx(fd_mean, rel=1e-6, abs=1e-10)
    # a callable of (t, y) gives the same columns
    again = periodic_sensitivity(laos, lambda t, y: np.stack([np.cos(t) * col, col], 1))
    np.testing.assert_allclose(again.states[:, :, 0], sens.states[:, :, 0], rtol=0,
                               atol=1e-12 * np.max(np.abs(sens.states)))  # fmt: skip
    assert again.states.shape[2] == 2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"omega": 0.0, "wall": 1.0}, "omega"),
        ({"omega": 1.0, "wall": step(1.0)}, "wall must be a number or a hairbed.dynamics.sine"),
        ({"omega": 1.0, "wall": sine(0.0, 1.0, 1.5)}, "whole multiple of omega"),
        ({"omega": 1.0, "flow_rate": sine(0.0, 1.0, 1.0), "womersley": 1.0}, "index-2"),
        ({"omega": 1.0, "wall": 1.0, "tol": 0.5}, "tol"),
        ({"omega": 1.0, "wall": 1.0, "harmonics": 1}, "harmonics"),
        ({"omega": 1.0, "wall": 1.0, "harmonics": 20, "max_harmonics": 10}, "max_harmonics"),
        ({"omega": 1.0, "wall": sine(0.0, 2e6, 1.0)}, "wall must stay within"),
        ({"omega": 1.0, "wall": 1.0, "wall_stress": 1.0}, "at most one"),
    ],
)
def test_bad_input_is_named(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        periodic_bed(0.0, 1.0, 0.5, **kwargs)


def test_bad_sensitivity_input_is_named(laos: PeriodicBed) -> None:
    kk, m = laos.y.shape
    with pytest.raises(TypeError, match="orbit must be a PeriodicBed"):
        periodic_sensitivity("orbit", np.zeros((kk, m)))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=rf"forcing must have shape \({kk}, {m}\)"):
        periodic_sensitivity(laos, np.zeros((kk + 1, m)))
    bad = np.zeros((kk, m))
    bad[2, 5] = np.nan
    with pytest.raises(ValueError, match=r"forcing must be finite.*\(2, 5\)"):
        periodic_sensitivity(laos, bad)
    with pytest.raises(ValueError, match="t must be finite"):
        laos.states_at([0.0, np.inf])
    with pytest.raises(ValueError, match="output must be one of"):
        laos.mean("speed")


def test_pump_net_flow_by_collocation_is_the_transient_one() -> None:
    """A tilted bed pumped by a zero-mean pressure drop (valve_dynamics): the net flow by
    collocation equals the transient's (run to tol 1e-9, rtol 1e-10) to 1e-8 of itself
    (measured 5.4e-10)."""
    from hairbed import HairBed
    from hairbed.valve_dynamics import bed_time_scales, pump_net_flow

    bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                  viscosity=1.0, spacing=250e-6, base_angle=0.5)  # fmt: skip
    f = 0.3 / bed_time_scales(bed)["time_scale"]
    kw = {"samples_per_period": 32, "tol": 1e-9}
    col = pump_net_flow(bed, 300.0, f, 0.01, **kw)
    tra = pump_net_flow(bed, 300.0, f, 0.01, method="transient", rtol=1e-10, **kw)
    assert col.success and tra.success
    assert col.periods[0, 0] == 0 and tra.periods[0, 0] > 2
    assert abs(col.net_flow[0, 0] - tra.net_flow[0, 0]) < 1e-8 * abs(tra.net_flow[0, 0])
    assert col.net_flow[0, 0] > 0.0
    with pytest.raises(ValueError, match="method must be one of"):
        pump_net_flow(bed, 300.0, f, 0.01, method="shooting")


def test_a_fine_degree_stops_at_its_rounding_not_in_failure() -> None:
    """At N = 64 the collocation's rates carry ~eps N^4 of rounding (Newton's steps stall at
    1.5e-9): Newton ends there instead of failing (status -1 before), and the orbit is N = 32's
    to the collocation's accuracy."""
    wall = sine(0.0, 1.0, 1.0)
    coarse = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall, num=32)
    fine = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall, num=64)
    assert coarse.status == 0 and fine.status == 0, fine.message
    t = np.linspace(0.0, coarse.period, 17)
    for name in ("tip_deflection", "wall_stress"):
        a, b = coarse.outputs_at(t)[name], fine.outputs_at(t)[name]
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(a)), name


def test_a_dense_bed_swinging_by_radians_converges() -> None:
    """A dense bed (kappa = 1.24e-3) pumped by 5.6 sin(3.6 t): the hairs swing from -1.12 to
    1.43 rad and the harmonics fall by only 0.92 a degree (H about 290 at tol 1e-12). The
    phase average is no preconditioner there (GMRES stalled: status -1 before); the cyclic
    implicit Euler one with each phase's Jacobian converges, forward (periodic_bed,
    periodic_sensitivity) and transposed (periodic_adjoint). The two linear solvers agree on
    d(mean tip deflection)/d(amplitude) with the pump's column G = (dg/dPi) sin(omega t)."""
    from hairbed.dynamics import periodic_adjoint
    from hairbed.dynamics._bed import _drive_columns

    om, amp = 3.6254389214718943, 5.63200165800367
    st = periodic_bed(0.6814894645080146, 0.0012396401733536838, 0.49451273679737745,
                      omega=om, pressure=sine(0.0, amp, om), gamma=0.5048698916260019,
                      tol=1e-10)  # fmt: skip
    assert st.status == 0, st.message
    assert st.harmonics > 150 and st.error <= 1e-10
    theta = st.y[:, : st._sys.num - 1]
    assert theta.max() > 1.4 and theta.min() < -1.1
    sin = np.sin(om * st.t)
    forcing = np.stack([_drive_columns(st._sys, y)["pressure"] for y in st.y]) * sin[:, None]
    forward = periodic_sensitivity(st, forcing).mean_outputs["tip_deflection"][0]
    backward = periodic_adjoint(st, "tip_deflection").mean_derivative(forcing)[0]
    assert forward == pytest.approx(backward, rel=1e-9)
    assert abs(forward) > 1e-3


def test_hairs_that_snap_through_start_from_the_transient() -> None:
    """A dense bed (kappa = 4.5e-3, base angle 0.87) pumped by 8.9 sin(1.37 t): the hairs
    lie over at +1.51 rad and snap through to -1.33 within a tenth of the period. Newton
    fails from the linear, quasi-static (it converges at H = 12 to a state beyond pi/2) and
    continuation starts (status -1 before); from the state approached in time it converges
    (H = 296). Against five periods of Radau IIA from the mean state at rtol 1e-10 (the
    start is gone by the third: measured 2.2e-11 on the flow rate in the last four), to 1e-8
    of each output's swing."""
    om, amp = 1.3719990678682017, 8.949327975886504
    bed = (0.8729668791571756, 0.0044956135341491284, 0.42110103012930805)
    drive = {"pressure": sine(0.0, amp, om), "gamma": 0.5082445296602109,
             "womersley": 0.00016448243666509541}  # fmt: skip
    st = periodic_bed(*bed, omega=om, **drive)
    assert st.status == 0 and st.start == "transient", (st.message, st.start)
    assert st.error <= 1e-10 and st.harmonics > 150
    theta = st.y[:, : st._sys.num - 1]
    assert theta.max() > 1.5 and theta.min() < -1.3
    t = np.linspace(0.0, 5.0 * st.period, 5 * 16 + 1)
    run = simulate_bed(*bed, t_eval=t, rtol=1e-10, atol=1e-12, **drive)
    assert run.success, run.message
    out = st.outputs_at(t[-17:-1])
    for name in ("flow_rate", "tip_deflection", "wall_stress"):
        ref = getattr(run, name)[-17:-1]
        assert np.max(np.abs(out[name] - ref)) < 1e-8 * np.ptp(ref), name
