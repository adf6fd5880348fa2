"""The pillar sensor in time, in SI (issue 31, items 1b and 1c; hairbed.sensor_dynamics).

Every reference is computed here by another path: the SI scalings from their formulas and
the dimensionless transfer function of hairbed.dynamics; the Euler-Bernoulli cantilever in
Krylov functions (mpmath, tests/test_dynamics_linear.py) with the quasi-steady drag and
added mass, or Sader's drag from mpmath's Bessel functions; dense scans for the peak, the
half-power points and the bandwidth.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.optimize
from test_dynamics_linear import _cantilever, _gamma_mpmath

import hairbed
from hairbed import sensor_dynamics as sd
from hairbed.dynamics import linearise_pillar

RHO_S = 1000.0  # the pillar's density [kg/m^3]


def _readme(fluid: str, **kw: object) -> hairbed.Pillar:
    return hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid=fluid, **kw)


def _scalings(p: hairbed.Pillar, drag: str) -> dict[str, float]:
    """T, Lambda/tau_w, mu, chi and Sader's Reynolds scale from their formulas."""
    eta, rho_f, length, a, e = p.viscosity, p.density, p.length, p.radius, p.youngs_modulus
    log = math.log(2.0 * length / a) + 0.5
    zeta = 4.0 * math.pi * eta / log
    ei = e * math.pi * a**4 / 4.0
    t = zeta * length**4 / ei
    area = math.pi * a * a
    mass = RHO_S * area if drag == "sader" else (RHO_S + rho_f) * area
    return {
        "T": t,
        "per_stress": zeta * length**4 / (eta * ei),
        "mu": mass * ei / (zeta**2 * length**4),
        "chi": 1.0 if drag == "sader" else RHO_S / (RHO_S + rho_f),
        "re_scale": rho_f * (2 * a) ** 2 / (4 * eta * t),
        "gamma": (log) / (2 * math.log(2 * length / a) - 1),
        "slender": length / a,
        "log": log,
    }


def _quiet(func, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        return func(*args, **kw)


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
@pytest.mark.parametrize("drag", ["quasi-steady", "sader"])
def test_si_response_is_the_dimensionless_one_times_the_scalings(drag: str) -> None:
    """At a large deflection (2 Pa on a soft sublayer pillar in a viscous liquid):
    H = L (Lambda/tau_w) H_Lambda(2 pi f T), the scalings computed here."""
    p = hairbed.Pillar(
        length=1e-3, radius=50e-6, youngs_modulus=1e5, viscosity=1e-2, density=1100.0
    )
    tau = 2.0
    sc = _scalings(p, drag)
    lam = sc["per_stress"] * tau
    st = hairbed.solve_pillar(lam, gamma=sc["gamma"])
    assert st.tip_deflection > 0.3  # large deflection
    lin = linearise_pillar(st, mu=sc["mu"], tangential_mass=sc["chi"])
    f = np.array([0.0, 0.1, 1.0, 10.0, 50.0])
    unsteady = (sc["re_scale"], sc["slender"]) if drag == "sader" else None
    want = (
        p.length
        * sc["per_stress"]
        * lin.frequency_response(2 * np.pi * f * sc["T"], unsteady_drag=unsteady).tip_deflection
    )
    r = _quiet(p.frequency_response, f, wall_shear_stress=tau, pillar_density=RHO_S, drag=drag)
    assert r.success and r.drag == drag
    assert np.allclose(r.response, want, rtol=1e-10, atol=0.0)
    assert np.allclose(r.magnitude, np.abs(want), rtol=1e-10)
    assert np.allclose(r.phase, np.angle(want), rtol=0.0, atol=1e-10)
    assert abs(r.time_scale - sc["T"]) <= 1e-12 * sc["T"]
    # the static gain is the pillar's exact sensitivity (central differences of deform)
    h = 1e-5
    fd = (p.tip_deflection(tau + h) - p.tip_deflection(tau - h)) / (2 * h)
    assert abs(r.static_gain - fd) <= 1e-7 * abs(fd)
    assert abs(r.response[0] - r.static_gain) <= 1e-9 * r.static_gain


def _reference(p: hairbed.Pillar, drag: str):
    """|H(f)| [m/Pa] of the straight cantilever (Krylov functions, mpmath): the sublayer's
    linear load, the drag D = 1 (quasi-steady, mu with the added mass) or Sader's."""
    sc = _scalings(p, drag)

    def h(f: float) -> complex:
        om = 2 * math.pi * f * sc["T"]
        d: complex = 1.0
        if drag == "sader":
            re = sc["re_scale"] * om
            if re >= 2.0 / sc["slender"] ** 2:
                d = 1j * sc["log"] * re * np.conj(_gamma_mpmath(re)) / 4
        return p.length * sc["per_stress"] * _cantilever(om, sc["mu"], "linear", d)[0]

    return h, sc


def _peak_and_q(h, f_guess: float) -> tuple[float, float]:
    """The peak of |h| by a dense scan and Brent's method, and the half-power Q."""
    grid = np.linspace(0.3 * f_guess, 1.7 * f_guess, 281)
    mag = np.array([abs(h(x)) for x in grid])
    i = int(np.argmax(mag))
    res = scipy.optimize.minimize_scalar(
        lambda x: -abs(h(x)),
        bounds=(grid[i - 1], grid[i + 1]),
        method="bounded",
        options={"xatol": 1e-11 * f_guess},
    )
    f_r = float(res.x)
    half = abs(h(f_r)) / math.sqrt(2)
    below = np.flatnonzero((grid < f_r) & (mag < half))
    above = np.flatnonzero((grid > f_r) & (mag < half))
    if below.size == 0:
        return f_r, math.nan
    f1 = scipy.optimize.brentq(lambda x: abs(h(x)) - half, grid[below[-1]], f_r, xtol=1e-13)
    f2 = scipy.optimize.brentq(lambda x: abs(h(x)) - half, f_r, grid[above[0]], xtol=1e-13)
    return f_r, f_r / (f2 - f1)


@pytest.mark.parametrize("fluid", ["water", "air"])
@pytest.mark.parametrize("drag", ["quasi-steady", "sader"])
def test_resonance_and_quality_factor_of_the_euler_bernoulli_cantilever(
    fluid: str, drag: str
) -> None:
    """The README pillar (PDMS-like, 1 mm, 50 um) at rest: the peak of |H| and its half-power
    Q against the cantilever's closed form; with the quasi-steady drag near the pole of
    mu lambda^2 + lambda + beta_1^4 = 0 (1 + cos b cosh b = 0), Q near |lambda|/(2 |Re|)."""
    p = _readme(fluid)
    r = _quiet(p.frequency_response, [1.0], pillar_density=RHO_S, drag=drag)
    h, sc = _reference(p, drag)
    f_r, q = _peak_and_q(h, r.resonance_frequency)
    assert abs(r.resonance_frequency - f_r) <= 1e-7 * f_r, (r.resonance_frequency, f_r)
    if math.isnan(q):
        assert math.isnan(r.quality_factor)
    else:
        assert abs(r.quality_factor - q) <= 1e-6 * q, (r.quality_factor, q)
    if drag == "quasi-steady":
        b = scipy.optimize.brentq(lambda x: 1 + math.cos(x) * math.cosh(x), 1.5, 2.2)
        b4 = b**4  # beta_1^4 of 1 + cos b cosh b = 0
        lam = complex(np.roots([sc["mu"], 1.0, b4])[0])
        f_pole = abs(lam.imag) / (2 * math.pi * sc["T"])
        q_pole = abs(lam) / (2 * abs(lam.real))
        assert abs(r.resonance_frequency / f_pole - 1) < 0.01  # a peak is not a pole
        assert abs(r.quality_factor / q_pole - 1) < 0.02


def test_bandwidth_by_a_dense_scan_of_the_closed_form() -> None:
    """The first frequency where |H|/H(0) leaves 1 +- 5 % or the phase leaves +-5 degrees,
    scanned on the closed form (water, Sader's drag) at 1000 points."""
    p = _readme("water")
    r = _quiet(p.frequency_response, [1.0], pillar_density=RHO_S)
    h, sc = _reference(p, "sader")
    h0 = p.length * sc["per_stress"] * 11 / 120  # the static cantilever under p = s
    assert abs(r.static_gain - h0) <= 1e-10 * h0
    grid = np.linspace(0.0, 1.9993 * r.bandwidth, 1001)[1:]  # not aligned with f_b
    vals = np.array([h(x) for x in grid]) / h0
    bad = (np.abs(np.abs(vals) - 1) > 0.05) | (np.abs(np.angle(vals)) > math.radians(5))
    first = grid[np.flatnonzero(bad)[0]]
    step = grid[1] - grid[0]
    assert first - step <= r.bandwidth <= first, (r.bandwidth, first)
    assert r.bandwidth < r.resonance_frequency


def test_a_frequency_beyond_the_stokes_layer_warns() -> None:
    p = _readme("water")
    f_c = (p.viscosity / p.density) / (math.pi * p.length**2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hairbed.ModelValidityWarning)
        r = p.frequency_response([0.0, 0.5 * f_c], pillar_density=RHO_S)
    assert abs(r.valid_below - f_c) <= 1e-12 * f_c
    with pytest.warns(hairbed.ModelValidityWarning, match="Stokes layer"):
        p.frequency_response([2.0 * f_c], pillar_density=RHO_S)
    with pytest.warns(hairbed.ModelValidityWarning, match="quasi-steady resistive-force"):
        p.frequency_response([2.0 * f_c], pillar_density=RHO_S, drag="quasi-steady")


def test_bad_inputs_of_the_response() -> None:
    p = _readme("water")
    with pytest.raises(ValueError, match="pillar_density"):
        p.frequency_response([1.0])
    with pytest.raises(ValueError, match="pillar_density"):
        p.frequency_response([1.0], pillar_density=-1.0)
    with pytest.raises(ValueError, match="drag must be one of"):
        p.frequency_response([1.0], pillar_density=RHO_S, drag="stokes")
    with pytest.raises(ValueError, match=r"frequency must be >= 0.*index 1"):
        p.frequency_response([1.0, -2.0], pillar_density=RHO_S)
    with pytest.raises(ValueError, match=r"frequency must be finite.*index 0"):
        p.frequency_response([np.nan], pillar_density=RHO_S)
    with pytest.raises(ValueError, match="magnitude_tolerance"):
        p.frequency_response([1.0], pillar_density=RHO_S, magnitude_tolerance=0.0)
    dry = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, viscosity=1e-3)
    with pytest.raises(ValueError, match="density"):
        dry.frequency_response([1.0], pillar_density=RHO_S)
    with pytest.raises(TypeError, match="hairbed.Pillar"):
        sd.frequency_response("pillar", [1.0], pillar_density=RHO_S)  # type: ignore[arg-type]


def test_response_to_xarray() -> None:
    pytest.importorskip("xarray")
    p = _readme("air")
    r = _quiet(p.frequency_response, [0.0, 10.0, 100.0], pillar_density=RHO_S)
    ds = r.to_xarray()
    assert ds["magnitude"].dims == ("frequency",)
    assert ds["magnitude"].attrs["units"] == "m/Pa" and ds["phase"].attrs["units"] == "rad"
    assert ds["frequency"].attrs["units"] == "Hz"
    assert ds.attrs["drag"] == "sader" and ds.attrs["Conventions"] == "CF-1.10"
    assert np.allclose(ds["magnitude"].values, r.magnitude)


# -- 1c: the stress series ----------------------------------------------------------------------


def _turbulent_series(
    p: hairbed.Pillar, tau_mean: float, f_r: float, n: int, seed: int, cut: float = np.inf
):
    """A seeded Gaussian stress series with the spectrum S(f) ~ (1 + (f/f0)^2)^(-5/6) (a -5/3
    tail), f0 = 0.3 f_res, sampled at 10 f_res (reaching 5 f_res), rms 20 % of the mean; and
    its deflection through the exact static curve (deform) and the linear dynamics about the
    mean, G = H/H(0) from the scalings computed here (the model's forward path, built
    independently of hairbed.sensor_dynamics)."""
    fs = 10.0 * f_r
    rng = np.random.default_rng(seed)
    f = np.fft.rfftfreq(n, 1 / fs)
    spec = 1.0 / (1 + (f / (0.3 * f_r)) ** 2) ** (5 / 6)
    spec[0] = 0.0
    spec[f > cut] = 0.0
    amp = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) * np.sqrt(spec)
    amp[-1] = amp[-1].real
    tp = np.fft.irfft(amp, n)
    tau = tau_mean + 0.2 * tau_mean * tp / tp.std()
    quasi = np.asarray(p.tip_deflection(tau))
    sc = _scalings(p, "sader")
    st = hairbed.solve_pillar(sc["per_stress"] * tau_mean, gamma=sc["gamma"])
    lin = linearise_pillar(st, mu=sc["mu"])
    h = lin.frequency_response(
        2 * np.pi * f * sc["T"], unsteady_drag=(sc["re_scale"], sc["slender"])
    ).tip_deflection
    g = h / h[0].real
    mean = quasi.mean()
    defl = mean + np.fft.irfft(np.fft.rfft(quasi - mean) * g, n)
    return tau, defl, fs, f, h * p.length * sc["per_stress"]


def test_deconvolution_target() -> None:
    """Issue 31's target: the recovered stress within the noise floor up to 0.8 f_res, and
    its 1-sigma band covering 68 % +- 3 % of the samples."""
    p = _readme("water")
    tau_mean = 0.2
    r = _quiet(p.frequency_response, [0.0], wall_shear_stress=tau_mean, pillar_density=RHO_S)
    f_r = r.resonance_frequency
    n = 2**15
    tau, defl, fs, f, h = _turbulent_series(p, tau_mean, f_r, n, seed=31)
    sigma = 2e-3 * defl.std()
    noisy = defl + sigma * np.random.default_rng(7).standard_normal(n)
    out = _quiet(
        p.wall_shear_stress_from_tip_deflection_series,
        noisy,
        fs,
        noise_sigma=sigma,
        pillar_density=RHO_S,
    )
    assert out.success and out.time.shape == tau.shape
    err = out.wall_shear_stress - tau
    coverage = float(np.mean(np.abs(err) <= out.wall_shear_stress_sigma))
    assert abs(coverage - 0.68) <= 0.03, coverage
    # the error's spectrum up to 0.8 f_res against the noise floor n sigma^2/|H|^2 [Pa^2]
    band = (f > 0) & (f <= 0.8 * f_r)
    # (a mean of M periodogram values: relative sampling deviation 1/sqrt(M), allowed 3 times)
    ratio = np.mean(np.abs(np.fft.rfft(err)[band]) ** 2 * np.abs(h[band]) ** 2) / (n * sigma**2)
    assert ratio <= 1.0 + 3.0 / math.sqrt(np.count_nonzero(band)), ratio
    assert abs(out.mean_wall_shear_stress - tau.mean()) <= 1e-3 * tau_mean
    # the corrected spectrum follows the stress's own, where the signal dominates
    lo = (f > 0.05 * f_r) & (f < 0.8 * f_r)
    own = 2 * np.abs(np.fft.rfft(tau - tau.mean())) ** 2 / (n * fs)
    assert 0.8 < np.mean(out.stress_spectrum[lo]) / np.mean(own[lo]) < 1.25


def test_the_noise_estimate_and_its_flag() -> None:
    """Estimated from the top fifth of the band: within 3 % of the true sigma where that band
    is noise alone (the stress band-limited to 3 f_res of the 5 f_res sampled), and status 5
    where the signal still reaches it."""
    p = _readme("water")
    r = _quiet(p.frequency_response, [0.0], wall_shear_stress=0.2, pillar_density=RHO_S)
    n = 2**14
    for cut, status in ((3.0 * r.resonance_frequency, 0), (np.inf, 5)):
        tau, defl, fs, _, _ = _turbulent_series(p, 0.2, r.resonance_frequency, n, 3, cut)
        sigma = 2e-3 * defl.std()
        noisy = defl + sigma * np.random.default_rng(11).standard_normal(n)
        out = _quiet(
            p.wall_shear_stress_from_tip_deflection_series, noisy, fs, pillar_density=RHO_S
        )
        assert out.noise_estimated and out.status == status, (cut, out.status)
        if status == 0:
            assert abs(out.noise_sigma / sigma - 1.0) <= 0.03, out.noise_sigma / sigma
        else:
            assert out.noise_sigma > 1.5 * sigma and "noise_sigma" in out.message


def test_series_bad_inputs() -> None:
    p = _readme("water")
    good = np.full(128, 1e-5) + 1e-7 * np.sin(np.arange(128))
    kw = {"pillar_density": RHO_S}
    bad = good.copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match=r"tip_deflection must be finite.*index 5"):
        p.wall_shear_stress_from_tip_deflection_series(bad, 100.0, **kw)
    with pytest.raises(ValueError, match="at least 64 samples"):
        p.wall_shear_stress_from_tip_deflection_series(good[:10], 100.0, **kw)
    with pytest.raises(TypeError, match="exactly one of sample_rate"):
        p.wall_shear_stress_from_tip_deflection_series(good, **kw)
    t = np.arange(128) / 100.0
    gap = t.copy()
    gap[60:] += 0.05
    with pytest.raises(ValueError, match=r"uniformly sampled: the step from index 59 to 60"):
        p.wall_shear_stress_from_tip_deflection_series(good, times=gap, **kw)
    back = t.copy()
    back[3] = back[2]
    with pytest.raises(ValueError, match="increase strictly"):
        p.wall_shear_stress_from_tip_deflection_series(good, times=back, **kw)
    far = good.copy()
    far[3] = 2e-3
    with pytest.raises(ValueError, match=r"\(-length, length\).*index 3"):
        p.wall_shear_stress_from_tip_deflection_series(far, 100.0, **kw)
    with pytest.raises(ValueError, match="noise_sigma"):
        p.wall_shear_stress_from_tip_deflection_series(good, 100.0, noise_sigma=-1.0, **kw)
    with pytest.raises(ValueError, match="sample_rate"):
        p.wall_shear_stress_from_tip_deflection_series(good, 0.0, **kw)
    # uniform times give the rate
    out = _quiet(p.wall_shear_stress_from_tip_deflection_series, good, times=t, **kw)
    assert abs(out.sample_rate - 100.0) <= 1e-9 and np.all(out.time == t)


@pytest.mark.slow
def test_deconvolution_of_the_nonlinear_pillar_in_time() -> None:
    """The forward path by the nonlinear pillar in time (simulate_pillar, quasi-steady drag
    with added mass), driven by the band-limited stress on a grid 8 times finer than the
    samples (so that the drive's interpolation adds nothing near the resonance), started a
    periodic eighth of the series early: the recovered stress within the noise floor up to
    0.8 f_res and its band covering 68 % +- 3 % (1024 samples at 4 f_res)."""
    from hairbed.dynamics import sampled, simulate_pillar

    p = _readme("water")
    tau_mean, n, over = 0.2, 1024, 8
    r = _quiet(
        p.frequency_response,
        [0.0],
        wall_shear_stress=tau_mean,
        pillar_density=RHO_S,
        drag="quasi-steady",
    )
    f_r = r.resonance_frequency
    fs, warm = 4.0 * f_r, n // 8
    rng = np.random.default_rng(5)
    f = np.fft.rfftfreq(n, 1 / fs)
    spec = 1.0 / (1 + (f / (0.3 * f_r)) ** 2) ** (5 / 6)
    spec[0] = spec[-1] = 0.0
    amp = (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) * np.sqrt(spec)
    tp = np.fft.irfft(amp, n)
    scale = 0.2 * tau_mean / tp.std()
    tau = tau_mean + scale * tp
    fine_amp = np.zeros(n * over // 2 + 1, dtype=complex)
    fine_amp[: f.size] = amp
    fine = tau_mean + scale * over * np.fft.irfft(fine_amp, n * over)
    assert np.allclose(fine[::over], tau, rtol=0.0, atol=1e-12)
    sc = _scalings(p, "quasi-steady")
    ext = np.concatenate([fine[-warm * over :], fine])
    t_fine = (np.arange(ext.size) - warm * over) / (fs * over) / sc["T"]
    run = simulate_pillar(
        sampled(t_fine, sc["per_stress"] * ext),
        t_fine[::over],
        gamma=sc["gamma"],
        mu=sc["mu"],
        tangential_mass=sc["chi"],
        rtol=1e-8,
        atol=1e-10,
        max_steps=10**6,
    )
    assert run.success
    defl = p.length * run.tip_deflection[warm:]
    sigma = 2e-3 * defl.std()
    noisy = defl + sigma * np.random.default_rng(9).standard_normal(n)
    out = _quiet(
        p.wall_shear_stress_from_tip_deflection_series,
        noisy,
        fs,
        noise_sigma=sigma,
        pillar_density=RHO_S,
        drag="quasi-steady",
    )
    err = out.wall_shear_stress - tau
    coverage = float(np.mean(np.abs(err) <= out.wall_shear_stress_sigma))
    assert abs(coverage - 0.68) <= 0.03, coverage
    h = r.at(f)
    band = (f > 0) & (f <= 0.8 * f_r)
    ratio = np.mean(np.abs(np.fft.rfft(err)[band]) ** 2 * np.abs(h[band]) ** 2) / (n * sigma**2)
    assert ratio <= 1.0 + 3.0 / math.sqrt(np.count_nonzero(band)), ratio


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_wall_law_response_is_exact() -> None:
    """'wall-law' at 1 Pa (L+ = 32): the drive is the flow's exact change with the stress,
    its amplitude and its shape (status 0). References written here: H(0) against central
    differences of deform; the drive column at the large deflection (x1 = 0.3) against
    central differences in tau_w of three static outputs of solve_pillar in the profile
    u+(L+ z)/L+ from spalding_u_plus (the stress moves Lambda and L+ together); at rest
    (L+ = 0) the sublayer's response."""
    p = hairbed.Pillar(
        length=1e-3, radius=50e-6, youngs_modulus=1e5, fluid="water", profile="wall-law"
    )
    f = [0.0, 10.0, 100.0, 300.0]
    r = p.frequency_response(f, wall_shear_stress=1.0, pillar_density=RHO_S)
    h = 1e-5
    fd = (p.tip_deflection(1.0 + h) - p.tip_deflection(1.0 - h)) / (2 * h)
    assert abs(r.response[0] - fd) <= 1e-7 * fd and r.status == 0 and r.success
    # the drive column at large deflection: every static output's derivative in tau_w
    model = sd._model(p, 1.0, RHO_S, "quasi-steady")
    st = model.lin.state
    per = p.forcing_per_stress
    lp = p.deform(1.0).height_in_wall_units

    def outputs(tau: float) -> np.ndarray:
        lt = lp * math.sqrt(tau)

        def prof(z: np.ndarray) -> np.ndarray:
            return np.asarray(hairbed.spalding_u_plus(lt * z)) / lt

        s = hairbed.solve_pillar(per * tau, theta0=0.0, gamma=float(st.gamma), profile=prof)
        return np.array([s.tip_deflection, s.tip_height, s.base_curvature])

    d = 1e-4
    want = (outputs(1.0 + d) - outputs(1.0 - d)) / (2 * d)
    got = model.lin.frequency_response(0.0, "profile", drive_profile=model.drive_profile)
    got_v = per * np.array([got.tip_deflection[0], got.tip_height[0], got.base_moment[0]])
    assert float(st.tip_deflection) > 0.2
    assert np.all(np.abs(got_v.imag) <= 1e-12 * np.abs(got_v.real))
    assert np.allclose(got_v.real, want, rtol=1e-7, atol=1e-9), (got_v, want)
    # the shape's part is no longer the forcing's: H/H(0) differs from H_Lambda/H_Lambda(0)
    hl = model.lin.frequency_response(2 * math.pi * model.time_scale * np.array(f[1:]))
    g_law = np.asarray(r.response[1:]) / r.response[0]
    ref0 = model.lin.frequency_response(0.0).tip_deflection[0]
    assert np.max(np.abs(g_law - hl.tip_deflection / ref0)) > 1e-4
    sub = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e5, fluid="water")
    rest = p.frequency_response(f[:3], pillar_density=RHO_S)
    want0 = sub.frequency_response(f[:3], pillar_density=RHO_S)
    assert rest.status == 0 and np.allclose(rest.response, want0.response, rtol=1e-9)


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_series_to_xarray() -> None:
    pytest.importorskip("xarray")
    p = _readme("water")
    t = np.arange(256) / 100.0
    x = np.asarray(p.tip_deflection(0.1 + 0.01 * np.sin(2 * np.pi * t)))
    out = p.wall_shear_stress_from_tip_deflection_series(x, 100.0, pillar_density=RHO_S)
    ds = out.to_xarray()
    assert ds["wall_shear_stress"].dims == ("time",) and ds["stress_spectrum"].dims == (
        "frequency",
    )
    assert ds["wall_shear_stress"].attrs["units"] == "Pa" and ds["time"].attrs["units"] == "s"
    assert ds.attrs["drag"] == "sader" and ds.sizes["frequency"] == 129
