"""Hostile inputs to the pillar's dynamics, the sensor's dynamics and design (issue 33).

The sixteen (target, argument) pairs that ``tests/test_fuzz.py`` listed as known failures:
each is fixed where the value enters (the wrapper validates, the kernel trusts), and here
the fix is pinned down: the error names the argument and its range, or the answer is the
right one (Sader's Gamma at large Reynolds numbers and the pillar's L+ against mpmath).
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import mpmath
import numpy as np
import pytest

import hairbed
from hairbed import design, dynamics, sensor_dynamics


@pytest.fixture(scope="module")
def pillar() -> hairbed.Pillar:
    return hairbed.Pillar(
        length=500e-6,
        radius=25e-6,
        youngs_modulus=1e6,
        viscosity=1e-3,
        base_angle=0.1,
        density=1000.0,
    )


def _gamma_mpmath(re: float) -> complex:
    """Sader's Gamma(Re) = 1 + 4 i K1(z)/(sqrt(i Re) K0(z)), z = -i sqrt(i Re), at 40 digits."""
    with mpmath.workdps(40):
        root = mpmath.sqrt(1j * mpmath.mpf(re))
        z = -1j * root
        return complex(1 + 4j * mpmath.besselk(1, z) / (root * mpmath.besselk(0, z)))


@pytest.mark.parametrize("re", [1e15, 1e16, 3e16, 1e18, 1e19, 1e36, 1e200, 1.7e308])
def test_sader_gamma_at_large_reynolds_numbers(re):
    """Above Re ~ 1e18 the Bessel functions' routine gives up (NaN); Hankel's expansion takes
    over at 1e16: Gamma - 1 (the part that carries the physics there) to 1e-14 relative."""
    got = complex(dynamics.hydrodynamic_function(re))
    ref = _gamma_mpmath(re)
    assert abs(got - ref) <= 1e-14 * abs(ref - 1.0)


def test_sensor_response_at_huge_frequencies(pillar):
    """3e38 Hz was Sader's Gamma's range error naming neither frequency nor its range: now a
    response (beyond the resolved dynamics: status 3), falling with the frequency."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        r = pillar.frequency_response(
            [10.0, 3e38, 1e100], wall_shear_stress=1.0, pillar_density=1000.0
        )
        at = r.at(np.float32(3e38))
    assert r.status == 3
    assert np.all(np.isfinite(r.response)) and np.isfinite(at)
    assert abs(r.response[0]) > abs(r.response[1]) > abs(r.response[2]) > 0.0


def _series_pillar_and_data(pillar):
    stress = 1.0 + 0.1 * np.sin(np.arange(64) / 5.0)
    return [float(d) for d in pillar.tip_deflection(stress)]


@pytest.mark.parametrize(
    ("kw", "names"),
    [
        (dict(sample_rate=2**63), ("sample_rate", "pillar_density", "noise_sigma")),
        (dict(pillar_density=2**63), ("sample_rate", "pillar_density", "noise_sigma")),
        (dict(noise_sigma=1e300), ("noise_sigma", "[0, 1e+100]")),
    ],
)
def test_stress_series_beyond_the_sensor(pillar, kw, names):
    """A series that the sensor's dynamics cannot have made (sampled at 9e18 Hz, a pillar of
    9e18 kg/m^3) and a noise whose square overflows: a ValueError naming the arguments."""
    data = _series_pillar_and_data(pillar)
    args = {"sample_rate": 1000.0, "pillar_density": 1000.0, **kw}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        with pytest.raises(ValueError) as info:
            sensor_dynamics.wall_shear_stress_from_tip_deflection_series(pillar, data, **args)
    for name in names:
        assert name in str(info.value)
    assert "np.float64" not in str(info.value)


def test_stress_series_noise_at_its_bound(pillar):
    """noise_sigma = 1e100 m (the bound): the filter passes the mean alone, finitely."""
    data = _series_pillar_and_data(pillar)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        out = pillar.wall_shear_stress_from_tip_deflection_series(
            data, sample_rate=1000.0, noise_sigma=1e100, pillar_density=1000.0
        )
    assert np.all(np.isfinite(out.wall_shear_stress))
    assert np.all(np.isfinite(out.wall_shear_stress_sigma))
    assert np.allclose(out.wall_shear_stress, out.mean_wall_shear_stress, rtol=1e-12)


@pytest.mark.parametrize(
    ("kw", "text"),
    [
        (dict(forcing=1e20), "forcing = 1e+20 and tip_load = 0.0"),
        (dict(forcing=0.0, tip_load=1e100), "tip_load = 1e+100"),
        (dict(forcing=1e300), "forcing must stay within [-1e+100, 1e+100]"),
        (dict(forcing=dynamics.step(-2e100)), "forcing must stay within"),
        (dict(forcing=2.0, tip_load=dynamics.sine(0.0, 1.5e100, 1.0)), "tip_load must stay"),
        (dict(forcing=2.0, t_eval=np.array([0.2, -0.5])), "index 1 is -0.5, after 0.2"),
    ],
)
def test_simulate_pillar_names_the_drive(kw, text):
    """No static state to start from, a drive beyond MAX_DRIVE, a decreasing time: each a
    ValueError naming the argument (and no np.float64 repr)."""
    args = {"t_eval": [0.0, 0.05], "num": 8, **kw}
    with pytest.raises(ValueError) as info:
        dynamics.simulate_pillar(**args)
    assert text in str(info.value)
    assert "np.float64" not in str(info.value)


def test_simulate_pillar_at_the_drive_bound():
    """A step to 1e100 (the bound) is taken: the compiled run fails (status -3), with finite
    rates at the start and no warning (the rates overflowed above it)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        run = dynamics.simulate_pillar(dynamics.step(1e100), [0.0, 0.05], num=8, max_steps=50)
    assert run.status < 0 and not run.success
    assert np.all(np.isfinite(run.theta_t[0]))


@pytest.mark.parametrize(
    ("kw", "text"),
    [
        (dict(forcing=[1.0, 1e20]), "forcing = 1e+20 and tip_load = 0.0"),
        (dict(forcing=[1.0, 1e20]), "(pillar 1)"),
        (dict(forcing=[]), "forcing must not be empty"),
        (dict(forcing=1.0, theta0=[]), "theta0 must not be empty"),
    ],
)
def test_simulate_pillars_names_the_drive(kw, text):
    with pytest.raises(ValueError) as info:
        dynamics.simulate_pillars(t_eval=[0.0, 0.05], num=8, **kw)
    assert text in str(info.value)


def test_sensor_simulate_bounds_the_stress(pillar):
    """1.7e308 Pa leaked numpy's invalid-value warning from the run's rates: now the SI bound
    MAX_DRIVE/(Lambda/tau_w) [Pa], named, for a number, a signal and a callable alike."""
    top = 1e100 / pillar.forcing_per_stress
    for drive in (1.7e308, dynamics.step(1.01 * top), lambda t: 0.0 * t - 1.01 * top):
        with pytest.raises(ValueError, match=r"wall_shear_stress must stay within \[-"):
            sensor_dynamics.simulate(pillar, drive, [0.0, 1e-3], overdamped=True, num=8)


def test_l_plus_near_the_largest_double(pillar):
    """L+ = L sqrt(abs(tau_w) rho)/eta at tau_w = 1.7e308 Pa: finite (the product tau_w rho
    overflowed to inf), against mpmath."""
    value = design.l_plus(1.7e308)(pillar)
    ref = mpmath.mpf(500e-6) * mpmath.sqrt(mpmath.mpf(1.7e308) * 1000) / mpmath.mpf(1e-3)
    assert math.isclose(value, float(ref), rel_tol=1e-15)


def test_design_sensitivity_where_no_state(pillar):
    """1e300 Pa: no state of the pillar; the quantity says so (the optimiser's signal), naming
    the stress, where it was a NaN."""
    with pytest.raises(ArithmeticError, match="wall_shear_stress"):
        design.sensitivity(1e300)(pillar)


_RESPONSE = [
    "response",
    "--frequencies=10,100",
    "--pillar-density=1000",
    "--length=500e-6",
    "--radius=25e-6",
    "--youngs-modulus=1e6",
    "--fluid=water",
]


@pytest.mark.parametrize(
    ("option", "value", "code"),
    [
        ("--magnitude-tolerance", "1e-13", 2),
        ("--magnitude-tolerance", "1", 2),
        ("--magnitude-tolerance", "nan", 2),
        ("--phase-tolerance", "5e-11", 2),
        ("--phase-tolerance", "180", 2),
        ("--phase-tolerance", "-inf", 2),
        ("--magnitude-tolerance", "1e-12", 0),  # the library's bounds, as the help states
        ("--phase-tolerance", "5.73e-11", 0),
    ],
)
def test_response_cli_tolerances(option, value, code, capsys):
    """`hairbed response`: the help's ranges are the library's (at least 1e-12, in rad for
    the phase); outside them one line on stderr naming the option, exit 2."""
    from hairbed.cli import main

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        got = main([*_RESPONSE, f"{option}={value}"])
    err = capsys.readouterr().err
    assert got == code
    lines = [line for line in err.splitlines() if not line.startswith("hairbed: warning:")]
    if code:
        assert len(lines) == 1 and option in lines[0] and "Traceback" not in err
    else:
        assert not lines


def test_response_cli_help_states_the_library_range(capsys):
    from hairbed.cli import main

    with pytest.raises(SystemExit):
        main(["response", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "in [1e-12, 1) (default 0.05)" in text
    assert f"in [{math.degrees(sensor_dynamics.BANDWIDTH_MIN_TOLERANCE):.3g}, 180)" in text


def test_laos_stress_at_any_phase_and_periods_as_counts():
    """LAOSAnalysis.stress is periodic in the phase: far out (theta + 2 pi 1e6) it is the
    record's band-limited stress itself (harmonics 1 to 3), and at 1.7e308 finite with no
    overflow warning; a timedelta64 is not a count of periods."""
    from hairbed.rheometer import analyse_laos

    phase = np.arange(64) * 2.0 * np.pi / 64.0
    strain = 0.5 * np.sin(phase)
    stress = 2.0 * strain + 0.3 * strain**3 + 0.75 * np.cos(phase)
    res = analyse_laos(phase, strain, stress)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        far = res.stress(phase + 2.0 * np.pi * 1e6)["total"]
        huge = res.stress(1.7e308)["total"]
    assert np.max(np.abs(far - stress)) <= 1e-8 * np.max(np.abs(stress))
    assert np.isfinite(huge)
    for name in ("periods", "num_harmonics"):
        bad: dict[str, Any] = {name: np.timedelta64(1, "s")}
        with pytest.raises(ValueError, match=name):
            analyse_laos(phase, strain, stress, **bad)


@pytest.mark.parametrize("rho_s", [5e-324, 1.7e308])
def test_resonance_frequency_names_the_density(pillar, rho_s):
    """A pillar density whose inertia number or mass ratio leaves double precision: named,
    not an IndexError or 'mu'/'tangential_mass'."""
    with pytest.raises((ValueError, ArithmeticError), match="pillar_density"):
        design.resonance_frequency(1.0, rho_s)(pillar)


def test_resonance_of_a_very_heavy_pillar_scales_as_its_mass(pillar):
    """Where the damping is far below the inertia (mu ~ 1e296 at rho_s = 1e300) the modes
    are the undamped pencil's, sigma^2 M v = J v with lambda = sigma/sqrt(mu): the frequency
    goes as 1/sqrt(rho_s + rho_f) to 1/mu (once the eigensolver found no mode there)."""
    heavy, light = (design.resonance_frequency(1.0, r)(pillar) for r in (1e300, 1e100))
    assert math.isfinite(heavy) and heavy > 0.0
    assert heavy * 1e150 == pytest.approx(light * 1e50, rel=1e-10)


def test_amplitude_sweep_bounds_the_amplitude(pillar):
    with pytest.raises(ValueError, match=r"amplitude must be at most .* \(first at index 1\)"):
        hairbed.sweeps.amplitude_sweep(
            pillar, [0.1, 1e300], [10.0], wall_shear_stress=1.0, pillar_density=1000.0
        )


def test_linear_bed_degrees_and_huge_frequencies():
    """LinearBed.operators checks its degrees by name (NaN reached int()); at omega = 1e300
    the bands' length scales overflowed with numpy's warning: beyond N = 128, status 3."""
    lin = dynamics.linearise_bed(hairbed.solve_porous(2.0, 0.5, 0.1, kappa=0.1), inertia=0.1)
    for num, num_gap, name in ((math.nan, 4, "num"), (3, 4, "num"), (8, 2**63, "num_gap")):
        with pytest.raises(ValueError, match=rf"{name} must be an integer in \["):
            lin.operators(num, num_gap)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = lin.frequency_response([0.1, 1e300])
    assert list(r.status) == [0, 3]


@pytest.mark.parametrize("f", [1e300, 5e-324])
def test_amplitude_sweep_bounds_the_frequency(pillar, f):
    """1e300 Hz gave a NaN atol named as such, 5e-324 Hz numpy's warning: now the range."""
    with pytest.raises(ValueError, match=r"frequency must lie in \[1e-100, 1e\+100\] Hz"):
        hairbed.sweeps.amplitude_sweep(pillar, [0.1], [10.0, f], pillar_density=1000.0)


@pytest.mark.parametrize("mu", [5e-324, 1e-310])
def test_modes_at_a_subnormal_inertia_number(mu):
    """A subnormal mu leaked numpy's 'invalid value in divide' (the pencil's infinite
    eigenvalues divided by 1): now no warning, and the modes of the straight pillar are the
    overdamped cantilever's, lambda = -beta^4 with 1 + cos(beta) cosh(beta) = 0 (mpmath;
    the inertial correction is O(mu), far below rounding)."""
    state = hairbed.solve_pillar(0.0, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = dynamics.linearise_pillar(state, mu=mu).modes(4).eigenvalues
    f = lambda b: 1 + mpmath.cos(b) * mpmath.cosh(b)  # noqa: E731
    ref = [-float(mpmath.findroot(f, g) ** 4) for g in (1.875, 4.694, 7.855, 10.996)]
    np.testing.assert_allclose(got, ref, rtol=1e-10)
