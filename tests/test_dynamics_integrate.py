"""The nonlinear pillar in time (issue 30, theory.md §14): hairbed.dynamics.simulate_pillar.

References independent of the integrator: the static solver (constant drives relax to its
state), the linear transfer function about a large deflection (tested itself against the
Krylov-function cantilever, tests/test_dynamics_linear.py: a small sine agrees with it up to
the square of the amplitude), the energy balance of the model, the drives' closed forms.
"""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import DYNAMICS_ENERGY_RTOL, DYNAMICS_STEADY_ATOL

import hairbed
from hairbed.dynamics import (
    linearise_pillar,
    pulses,
    ramp,
    sampled,
    simulate_pillar,
    sine,
    step,
)


@pytest.mark.parametrize(
    ("lam", "theta0", "profile", "ratio"),
    [(10.0, 0.0, "sublayer", None), (30.0, -0.5, "poiseuille", 0.6), (-8.0, 0.4, "couette", 1.0)],
)
def test_constant_drive_relaxes_to_the_static_state(
    lam: float, theta0: float, profile: str, ratio: float | None
) -> None:
    run = simulate_pillar(
        step(lam), [0.0, 0.01, 5.0], theta0=theta0, profile=profile, height_ratio=ratio,
        rtol=1e-8, atol=1e-10,
    )  # fmt: skip
    st = hairbed.solve_pillar(lam, theta0, profile=profile, height_ratio=ratio)
    assert run.success and run.status == 0 and run.t_end == 5.0
    assert abs(run.tip_deflection[0] - np.sin(theta0)) <= 1e-14  # at rest before the step
    for ours, theirs in (
        (run.tip_deflection, st.tip_deflection),
        (run.tip_height, st.tip_height),
        (run.tip_angle, st.tip_angle),
        (run.base_moment, st.base_curvature),
    ):
        assert abs(ours[-1] - theirs) <= DYNAMICS_STEADY_ATOL * max(1.0, abs(theirs))
    # on the way, the tip moves monotonically towards the state (overdamped, one sign)
    assert (
        0.0
        < (run.tip_deflection[1] - run.tip_deflection[0])
        / (st.tip_deflection - run.tip_deflection[0])
        < 1.0
    )


def test_small_sine_about_a_large_deflection_is_the_linear_response() -> None:
    """Lambda = 20 + eps sin(5 t) about the state at theta0 = 0.3 (x1 = 0.62): the tip's
    motion minus eps Im(H e^{i omega t}) is O(eps^2) once the start has decayed."""
    lam0, theta0, om = 20.0, 0.3, 5.0
    st = hairbed.solve_pillar(lam0, theta0, num=32)
    h = linearise_pillar(st).frequency_response([om]).tip_deflection[0]
    tt = np.linspace(3.0, 3.0 + 2.0 * np.pi / om, 25)
    errs = []
    for eps in (1e-2, 5e-3):
        run = simulate_pillar(
            sine(lam0, eps, om), np.concatenate([[0.0], tt]), theta0=theta0, initial=st,
            rtol=1e-11, atol=1e-13,
        )  # fmt: skip
        assert run.success
        linear = (eps * h * np.exp(1j * om * tt)).imag
        errs.append(float(np.max(np.abs(run.tip_deflection[1:] - st.tip_deflection - linear))))
        assert errs[-1] <= 1e-3 * eps**2  # measured 2.2e-4 eps^2
    assert 3.5 <= errs[0] / errs[1] <= 4.5  # quadratic in the amplitude


def test_energy_balance_overdamped() -> None:
    """d(elastic)/dt = input power - dissipation at every output time (theta_t is the
    integrated rate, so the left side is exact at each time)."""
    run = simulate_pillar(
        ramp(0.0, 20.0, 0.0, 0.5), np.concatenate([[0.0], np.linspace(0.05, 1.0, 40)]),
        theta0=0.3, rtol=1e-10, atol=1e-12,
    )  # fmt: skip
    e = run.energy()
    ii, d1 = run._ops["ii"], run._ops["d1s"]
    rate = (((run.theta @ d1.T) * (run.theta_t @ d1.T)) @ ii[-1])[1:]
    balance = (e["input"] - e["dissipation"])[1:]
    assert np.all(e["dissipation"] >= 0.0) and np.all(e["kinetic"] == 0.0)
    assert np.max(np.abs(rate - balance)) <= DYNAMICS_ENERGY_RTOL * np.max(np.abs(e["input"]))
    assert np.max(np.abs(balance)) > 1.0  # the pillar moves


def test_energy_balance_with_inertia() -> None:
    """d(elastic + kinetic)/dt (central differences of the dense output) = input -
    dissipation, a pillar with mu = 0.5 under a smooth ramp of the tip load."""
    ts = np.linspace(0.2, 0.6, 41)
    dt = 1e-4
    times = np.sort(np.concatenate([ts - dt, ts + dt, ts]))
    run = simulate_pillar(
        0.0, times, tip_load=ramp(0.0, 2.0, 0.0, 1.0), theta0=0.2, mu=0.5, num=12,
        rtol=1e-8, atol=1e-10,
    )  # fmt: skip
    assert run.success
    e = run.energy()
    total = (e["elastic"] + e["kinetic"]).reshape(-1, 3)
    rate = (total[:, 2] - total[:, 0]) / (2 * dt)
    balance = (e["input"] - e["dissipation"]).reshape(-1, 3)[:, 1]
    assert np.max(np.abs(rate - balance)) <= 1e-5 * np.max(np.abs(balance))


def test_the_tip_reaching_the_wall_is_an_event() -> None:
    """Tilted downstream and struck hard with inertia, the pillar overshoots to the wall:
    status -8 at the event time, NaN after it."""
    t = np.linspace(0.0, 1.0, 11)
    run = simulate_pillar(step(300.0), t, theta0=1.3, mu=1.0, num=16, rtol=1e-4, atol=1e-6)
    assert run.status == -8 and not run.success and "outside the model" in run.message
    assert 0.1 < run.t_end < 0.25  # measured 0.1661 (0.16610 at N = 32)
    before = t <= run.t_end
    assert np.all(np.isfinite(run.tip_deflection[before]))
    assert np.all(np.isnan(run.tip_deflection[~before]))


def test_work_is_bounded() -> None:
    run = simulate_pillar(step(10.0), [0.0, 5.0], max_steps=5)
    assert run.status == -2 and np.isnan(run.tip_deflection[-1]) and run.nsteps <= 6


def test_signals_closed_forms() -> None:
    t = np.array([-1.0, 0.0, 0.25, 0.5, 1.0, 2.0])
    assert np.array_equal(step(3.0, 1.0, at=0.5)(t), [1, 1, 1, 3, 3, 3])
    assert np.allclose(ramp(0.0, 4.0, 0.0, 1.0)(t), [0, 0, 1, 2, 4, 4], rtol=0, atol=1e-15)
    assert np.allclose(sine(1.0, 2.0, 3.0, 0.1)(t), 1.0 + 2.0 * np.sin(3.0 * t + 0.1))
    assert np.array_equal(pulses(1.0, 5.0, 1.0, 0.3)(t), [1, 6, 6, 1, 6, 6])
    # the cubic Hermite interpolant reproduces its samples and a quadratic inside
    tt = np.linspace(0.0, 2.0, 21)
    sig = sampled(tt, tt**2)
    assert np.allclose(sig(tt), tt**2, rtol=0, atol=1e-15)
    mid = np.linspace(0.1, 1.7, 7) + 0.05  # the end intervals' slopes are one-sided
    assert np.allclose(sig(mid), mid**2, rtol=0, atol=1e-12)


def test_a_callable_drive_is_its_samples() -> None:
    times = [0.0, 0.3, 0.6]
    named = simulate_pillar(sine(5.0, 1.0, 4.0), times, rtol=1e-10, atol=1e-12)
    func = simulate_pillar(lambda t: 5.0 + np.sin(4.0 * t), times, rtol=1e-10, atol=1e-12)
    assert np.max(np.abs(named.tip_deflection - func.tip_deflection)) <= 1e-9


def test_bad_inputs() -> None:
    with pytest.raises(ValueError, match=r"t_eval .* index 2"):
        simulate_pillar(1.0, [0.0, 1.0, 0.5])
    with pytest.raises(ValueError, match="t_eval must be finite"):
        simulate_pillar(1.0, [0.0, np.nan])
    with pytest.raises(ValueError, match="theta0"):
        simulate_pillar(1.0, [0.0, 1.0], theta0=2.0)
    with pytest.raises(ValueError, match="num"):
        simulate_pillar(1.0, [0.0, 1.0], num=3)
    with pytest.raises(ValueError, match="mu"):
        simulate_pillar(1.0, [0.0, 1.0], mu=-0.1)
    with pytest.raises(TypeError, match="forcing"):
        simulate_pillar("ten", [0.0, 1.0])
    with pytest.raises(ValueError, match="forcing: the callable raised"):
        simulate_pillar(lambda t: 1 / 0, [0.0, 1.0])
    with pytest.raises(ValueError, match="forcing: the callable returned nan"):
        simulate_pillar(lambda t: np.full_like(t, np.nan), [0.0, 1.0])
    with pytest.raises(ValueError, match="t_end"):
        ramp(0.0, 1.0, 1.0, 0.5)
    with pytest.raises(ValueError, match="times must increase strictly; index 2"):
        sampled([0.0, 1.0, 1.0], [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="width"):
        pulses(0.0, 1.0, 1.0, 2.0)
    with pytest.raises(TypeError, match="initial"):
        simulate_pillar(1.0, [0.0, 1.0], initial=hairbed.solve_pillar([1.0, 2.0]))


def test_xarray_export() -> None:
    pytest.importorskip("xarray")
    run = simulate_pillar(step(5.0), [0.0, 0.1, 0.2], num=16)
    ds = run.to_xarray()
    assert ds["tip_deflection"].dims == ("t",) and ds["theta"].dims == ("t", "s")
    assert ds["t"].attrs["units"] == "T" and ds.attrs["status"] == 0
    assert np.array_equal(ds["tip_deflection"].values, run.tip_deflection)


def test_late_relaxation_decays_at_the_slowest_mode() -> None:
    """Released from the state at Lambda = 20.0005 to Lambda = 20 (theta0 = 0.3, x1 = 0.62),
    the tip's distance to the new state decays like e^{lambda_1 t}, lambda_1 the slowest
    mode of the linearisation there (-36.736; the next, -504, is gone by t = 0.1)."""
    st = hairbed.solve_pillar(20.0, 0.3, num=32)
    lam1 = linearise_pillar(st).modes(1).eigenvalues[0]
    assert lam1.imag == 0.0 and lam1.real < -30.0
    t = np.array([0.0, 0.1, 0.15, 0.2])
    run = simulate_pillar(
        20.0, t, theta0=0.3, initial=hairbed.solve_pillar(20.0005, 0.3, num=32),
        rtol=1e-12, atol=1e-14,
    )  # fmt: skip
    d = run.tip_deflection - st.tip_deflection
    rates = np.log(d[2:] / d[1:-1]) / 0.05
    # measured within 3e-6 (the amplitude's nonlinearity and the integration's error)
    assert np.all(np.abs(rates - lam1.real) <= 2e-5 * abs(lam1.real)), (rates, lam1)


@pytest.mark.parametrize("mu", [0.0, 2.0])
def test_the_rates_jacobian_is_exact(mu: float) -> None:
    """The integrator's Jacobian of the semi-discrete rates (static Jacobian, the drag and
    inertia operators' derivatives, the centripetal term) against central differences of
    the rates, at a random bent state (tilted, a Poiseuille-like profile, gamma and chi
    apart from 1)."""
    from hairbed._core._kernels import dynamics as kern
    from hairbed.dynamics._operators import _mapped

    num = 16
    _, _, dd, ii, _ = _mapped(num, 0.0)
    srow = -dd[num, :] / dd[num, num]
    srow[num] = 0.0
    prof = np.array([0.45, 0.45, -0.05])
    drives = np.stack([step(10.0).row(), step(0.3).row()])
    tabs = np.zeros((4, 1))
    ws = kern.workspace(num)
    n = num - 1
    m = n if mu == 0.0 else 2 * n
    y = 0.15 * np.random.default_rng(1).standard_normal(m)
    args = (num, dd, ii, srow, 0.2, 0.6, 0.7, mu, prof, drives, tabs)
    f = np.zeros(m)
    jac = np.zeros((m, m))
    assert kern.pillar_rates(0.1, y, True, *args, f, jac, ws)
    fd = np.zeros((m, m))
    h = 1e-6
    for k in range(m):
        cols = []
        for sgn in (1.0, -1.0):
            yk = y.copy()
            yk[k] += sgn * h
            fk = np.zeros(m)
            kern.pillar_rates(0.1, yk, False, *args, fk, np.zeros((m, m)), ws)
            cols.append(fk)
        fd[:, k] = (cols[0] - cols[1]) / (2 * h)
    # central differences: truncation ~h^2, rounding ~1e-16 |f|/h (|f| ~ 1e3 here)
    assert np.max(np.abs(jac - fd)) <= 1e-7 * np.max(np.abs(jac))
