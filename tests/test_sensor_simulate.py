"""The pillar sensor in time, in SI (``Pillar.simulate``, issue 30 item 6).

The references are written here from the definitions: T = zeta_perp L^4/(E I) with Gray &
Hancock's zeta_perp = 4 pi eta/(ln(2L/a) + 1/2), Lambda per pascal zeta_perp L^4/(eta E I),
mu = (rho_s + rho_f) pi a^2/(zeta_perp T), and the dimensionless ``simulate_pillar`` run with
them; the final state against the static ``Pillar.deform``.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest

from hairbed import ModelValidityWarning, Pillar
from hairbed.dynamics import pulses, ramp, simulate_pillar, sine, step

L, A, E, RHO_S = 1e-3, 50e-6, 1e6, 970.0
ETA, RHO_F = 1.0e-3, 998.0


def _pillar(**kw: object) -> Pillar:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        return Pillar(length=L, radius=A, youngs_modulus=E, viscosity=ETA, density=RHO_F, **kw)  # type: ignore[arg-type]


def _scales() -> tuple[float, float, float, float, float]:
    """(T [s], Lambda per Pa, mu, chi, gamma) from the definitions."""
    ln = math.log(2.0 * L / A)
    zeta = 4.0 * math.pi * ETA / (ln + 0.5)
    ei = E * math.pi * A**4 / 4.0
    t_scale = zeta * L**4 / ei
    per_pa = zeta * L**4 / (ETA * ei)
    mu = (RHO_S + RHO_F) * math.pi * A**2 / (zeta * t_scale)
    chi = RHO_S / (RHO_S + RHO_F)
    gamma = (ln + 0.5) / (2.0 * ln - 1.0)
    return t_scale, per_pa, mu, chi, gamma


@pytest.fixture(autouse=True)
def _quiet() -> object:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        yield


def test_overdamped_step_is_the_dimensionless_run_in_si() -> None:
    p = _pillar()
    t_scale, per_pa, _, _, gamma = _scales()
    t = np.linspace(0.0, 3.0 * t_scale, 31)
    run = p.simulate(1.0, t, overdamped=True, num=32, rtol=1e-10, atol=1e-12)
    assert run.success and run.status == 0
    ref = simulate_pillar(step(per_pa), t / t_scale, gamma=gamma, num=32, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(run.tip_deflection, L * ref.tip_deflection, rtol=1e-12, atol=0)
    np.testing.assert_allclose(run.tip_height, L * ref.tip_height, rtol=1e-12)
    ei = E * math.pi * A**4 / 4.0
    np.testing.assert_allclose(run.base_moment, ei * ref.base_moment / L, rtol=1e-12, atol=0)
    assert run.time_scale == pytest.approx(t_scale, rel=1e-14)
    assert run.inertia_number == 0.0
    np.testing.assert_allclose(run.wall_shear_stress[1:], 1.0, rtol=1e-14)
    # relaxed after 3 T (slowest rate 12.36/T): the static state at the same stress
    st = p.deform(1.0)
    x_static, m_static = float(st.tip_deflection), float(st.base_moment)
    assert abs(run.tip_deflection[-1] - x_static) <= 1e-8 * x_static
    assert abs(run.base_moment[-1] - m_static) <= 1e-8 * abs(m_static)
    # the shape's last node is the tip
    assert run.x[-1, -1] == pytest.approx(run.tip_deflection[-1], rel=1e-12)
    assert run.z[-1, -1] == pytest.approx(run.tip_height[-1], rel=1e-12)
    assert run.arc_length[0] == 0.0 and run.arc_length[-1] == pytest.approx(L, rel=1e-14)


def test_ringing_step_in_water_settles_on_the_static_state() -> None:
    """mu = 8.4 (quasi-steady drag with added mass): the step overshoots, then the static
    state to 1e-8 (default N = 12, rtol 1e-6)."""
    p = _pillar()
    t_scale, per_pa, mu, chi, gamma = _scales()
    t = np.linspace(0.0, 400.0 * t_scale, 801)
    run = p.simulate(1.0, t, pillar_density=RHO_S)
    assert run.success, run.message
    assert run.inertia_number == pytest.approx(mu, rel=1e-13)
    st = p.deform(1.0)
    assert np.max(run.tip_deflection) > 1.5 * st.tip_deflection  # it rings
    assert abs(run.tip_deflection[-1] - st.tip_deflection) <= 1e-8 * st.tip_deflection
    ref = simulate_pillar(
        step(per_pa), t / t_scale, gamma=gamma, mu=mu, tangential_mass=chi, num=12,
        rtol=1e-6, atol=1e-7,
    )  # fmt: skip
    # round-off in T and Lambda moves the adaptive steps: equal to the tolerance's scale
    # (measured 3.4e-11 m = 3.4e-8 L at rtol 1e-6)
    np.testing.assert_allclose(run.tip_deflection, L * ref.tip_deflection, rtol=0, atol=1e-7 * L)


def test_named_si_signals_map_times_stresses_and_rates() -> None:
    p = _pillar()
    t_scale, per_pa, mu, chi, gamma = _scales()
    t = np.linspace(0.0, 6.0 * t_scale, 25)
    omega = 2.0 * math.pi * 200.0  # [rad/s]
    run = p.simulate(sine(1.0, 0.4, omega, 0.3), t, pillar_density=RHO_S, num=16, rtol=1e-9,
                     atol=1e-11)  # fmt: skip
    ref = simulate_pillar(
        sine(per_pa, 0.4 * per_pa, omega * t_scale, 0.3), t / t_scale, gamma=gamma, mu=mu,
        tangential_mass=chi, num=16, rtol=1e-9, atol=1e-11,
    )  # fmt: skip
    assert run.success and ref.success
    np.testing.assert_allclose(run.tip_deflection, L * ref.tip_deflection, rtol=1e-12, atol=0)
    np.testing.assert_allclose(
        run.wall_shear_stress, 1.0 + 0.4 * np.sin(omega * t + 0.3), rtol=1e-12
    )
    r2 = p.simulate(ramp(0.0, 2.0, t[4], t[10]), t, overdamped=True)
    ref2 = simulate_pillar(
        ramp(0.0, 2.0 * per_pa, t[4] / t_scale, t[10] / t_scale), t / t_scale, gamma=gamma,
        num=12, rtol=1e-6, atol=1e-7,
    )  # fmt: skip
    np.testing.assert_allclose(r2.tip_deflection, L * ref2.tip_deflection, rtol=0, atol=1e-9 * L)


def test_si_pulses_and_a_delayed_step_from_a_prestress() -> None:
    p = _pillar()
    t_scale, per_pa, _, _, gamma = _scales()
    t = np.linspace(0.0, 4.0 * t_scale, 17)
    kw: dict[str, Any] = {"overdamped": True, "num": 16, "rtol": 1e-10, "atol": 1e-12}
    run = p.simulate(pulses(0.2, 1.0, t_scale, 0.3 * t_scale, 0.5 * t_scale), t, **kw)
    ref = simulate_pillar(
        pulses(0.2 * per_pa, per_pa, 1.0, 0.3, 0.5), t / t_scale, gamma=gamma, num=16,
        rtol=1e-10, atol=1e-12,
    )  # fmt: skip
    np.testing.assert_allclose(run.tip_deflection, L * ref.tip_deflection, rtol=0, atol=1e-10 * L)
    run = p.simulate(step(1.5, 0.5, 2.0 * t_scale), t, **kw)  # from rest at 0.5 Pa
    assert run.tip_deflection[0] == pytest.approx(p.deform(0.5).tip_deflection, rel=1e-9)
    np.testing.assert_allclose(run.wall_shear_stress, np.where(t < 2.0 * t_scale, 0.5, 1.5))


def test_a_callable_in_seconds_and_pascals_matches_its_named_signal() -> None:
    p = _pillar()
    t_scale = _scales()[0]
    t = np.linspace(0.0, 2.0 * t_scale, 9)
    omega = 1.5 / t_scale
    named = p.simulate(sine(0.5, 0.5, omega), t, overdamped=True, num=16, rtol=1e-10,
                       atol=1e-12)  # fmt: skip
    func = p.simulate(
        lambda s: 0.5 + 0.5 * np.sin(omega * s), t, overdamped=True, num=16, rtol=1e-10,
        atol=1e-12,
    )  # fmt: skip
    assert named.success and func.success
    # the callable's cubic interpolant over 4097 samples: ~(dt)^4 f''''/384
    np.testing.assert_allclose(func.tip_deflection, named.tip_deflection, rtol=1e-9, atol=0)


def test_xarray_has_a_time_dimension_with_cf_units() -> None:
    pytest.importorskip("xarray")
    p = _pillar()
    t = np.linspace(0.0, 1e-3, 5)
    ds = p.simulate(1.0, t, overdamped=True).to_xarray()
    assert ds["tip_deflection"].dims == ("time",)
    assert ds["time"].attrs["units"] == "s" and ds["time"].attrs["standard_name"] == "time"
    assert ds["tip_deflection"].attrs["units"] == "m"
    assert ds["base_moment"].attrs["units"] == "N m"
    assert ds["wall_shear_stress"].attrs["units"] == "Pa"
    assert ds["x"].dims == ("time", "node")
    assert ds.attrs["status"] == 0 and ds.attrs["Conventions"] == "CF-1.10"


def test_bad_input_names_the_parameter() -> None:
    p = _pillar()
    t = [0.0, 1e-3]
    with pytest.raises(ValueError, match="pillar_density"):
        p.simulate(1.0, t)
    with pytest.raises(ValueError, match="pillar_density"):
        p.simulate(1.0, t, pillar_density=-1.0)
    with pytest.raises(TypeError, match="wall_shear_stress"):
        p.simulate("1 Pa", t, overdamped=True)
    with pytest.raises(ValueError, match="wall_shear_stress: the callable raised"):
        p.simulate(lambda s: 1 / 0, t, overdamped=True)
    with pytest.raises(ValueError, match="wall_shear_stress"):
        p.simulate(float("nan"), t, overdamped=True)
    with pytest.raises(ValueError, match="'wall-law'"):
        _pillar(profile="wall-law").simulate(1.0, t, overdamped=True)
    with pytest.raises(ValueError, match="t must stay below"):
        p.simulate(1.0, [0.0, 1e308], overdamped=True)
    nofluid = Pillar(length=L, radius=A, youngs_modulus=E, viscosity=ETA)
    with pytest.raises(ValueError, match="fluid's density"):
        nofluid.simulate(1.0, t, pillar_density=RHO_S)


def test_small_sine_has_the_linear_response_of_the_same_drag() -> None:
    """A 0.01 Pa sine at 100 Hz about 1 Pa, after the start has decayed (exp(-t/(2 mu T)):
    4e-8 left at 0.18 s): its amplitude and phase are those of the quasi-steady frequency
    response about 1 Pa (an independent path: the linear pencil, not the integrator), to the
    square of the relative amplitude."""
    p = _pillar()
    f = 100.0
    t = np.linspace(0.0, 0.2, 4001)
    run = p.simulate(sine(1.0, 0.01, 2.0 * math.pi * f), t, pillar_density=RHO_S, num=16,
                     rtol=1e-9, atol=1e-10)  # fmt: skip
    assert run.success
    tail = t >= 0.18  # two periods
    basis = np.column_stack(
        [np.ones(tail.sum()), np.sin(2 * math.pi * f * t[tail]), np.cos(2 * math.pi * f * t[tail])]
    )
    c, a, b = np.linalg.lstsq(basis, run.tip_deflection[tail], rcond=None)[0]
    lin = p.frequency_response([f], wall_shear_stress=1.0, pillar_density=RHO_S,
                               drag="quasi-steady")  # fmt: skip
    h = complex(lin.response[0])  # x = Im(H 0.01 e^{i w t}) = 0.01 (Re H sin + Im H cos)
    # measured 6.6e-7 and 7.7e-7 (the mean's second-order shift)
    assert abs(complex(a, b) / 0.01 - h) <= 1e-5 * abs(h)
    assert c == pytest.approx(p.deform(1.0).tip_deflection, rel=1e-5)


def test_the_pillars_validity_checks_run_at_the_largest_stress() -> None:
    """The README-like pillar in water at 1 Pa: Reynolds number 99.6 > 0.5 and
    L+ = L sqrt(tau/rho)/(eta/rho) = sqrt(998) = 31.6 > 5 (Pillar.deform's checks), at the
    run's largest stress, here the sine's peak."""
    p = _pillar()
    t = np.linspace(0.0, 1e-3, 5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p.simulate(sine(0.0, 1.0, 2.0 * math.pi * 250.0), t, overdamped=True)
    texts = [str(w.message) for w in caught if w.category is ModelValidityWarning]
    assert any("Reynolds number" in m for m in texts), texts
    assert any("L+ = 31.6" in m for m in texts), texts  # at 1 Pa (the peak at t = 1 ms)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p.simulate(1e-9, t, overdamped=True)  # a tiny stress: nothing to say
    assert not [w for w in caught if w.category is ModelValidityWarning]
