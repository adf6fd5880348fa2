"""Sensor calibration (hairbed.calibration): recovery, coverage, Jacobian, measure, linear range.

References: simulated data from the forward model with known parameters (recovery and the
coverage of the reported 1-sigma intervals over many noise seeds), central finite differences
of the model for the exact Jacobian, finite differences of HairBed's inversion for the
propagated errors, and HairBed's own linear calibration for the linear range.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import pytest
from tolerances import FINITE_DIFFERENCE_RTOL

import hairbed
from hairbed import HairBed
from hairbed.calibration import (
    FREE_PARAMETERS,
    _model,
    fit,
    linear_range,
    measure,
    model_tip_deflection,
)
from hairbed.cli import main

#: A soft micropillar sensor: 1 mm hairs, radius 50 um, 400 um spacing, under 2 mm of glycerol.
TRUE = HairBed(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1.3e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=0.1,
)
GUESS = replace(TRUE, packing_fraction=None, youngs_modulus=1.0e6, base_angle=0.0)
#: The guess with the true base angle, for fits of the modulus alone.
GUESS_E = replace(GUESS, packing_fraction=None, base_angle=0.1)
VELOCITY = np.linspace(0.01, 0.3, 10)
SIGMA = 2e-6  # [m]
SEEDS = 200


def _coverage_tolerance(p: float, n: int) -> float:
    """Three binomial standard deviations of a fraction of n trials."""
    return 3.0 * math.sqrt(p * (1.0 - p) / n)


def test_recovers_exact_parameters_without_noise() -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    res = fit(GUESS, d, velocity=VELOCITY, sigma=SIGMA, free=("youngs_modulus", "base_angle"))
    assert res.success and res.status == 0 and res.solver_status > 0 and res.nit > 0
    assert res.values["youngs_modulus"] == pytest.approx(1.3e6, rel=1e-10)
    assert res.values["base_angle"] == pytest.approx(0.1, abs=1e-10)
    assert res.chi2 < 1e-12 and res.dof == 8
    assert res.bed.youngs_modulus == res.values["youngs_modulus"]
    assert res.covariance.shape == (2, 2)
    assert np.allclose(np.sqrt(np.diag(res.covariance)), list(res.stderr.values()))


def test_coverage_over_seeds() -> None:
    """The reported 1-sigma interval holds the true value in ~68 % of noisy calibrations."""
    clean = model_tip_deflection(TRUE, velocity=VELOCITY)
    inside = {"youngs_modulus": 0, "base_angle": 0}
    chi2 = []
    for seed in range(SEEDS):
        noise = np.random.default_rng(seed).normal(0.0, SIGMA, VELOCITY.size)
        res = fit(
            GUESS,
            clean + noise,
            velocity=VELOCITY,
            sigma=SIGMA,
            free=("youngs_modulus", "base_angle"),
        )
        assert res.success
        chi2.append(res.chi2)
        for name, true in (("youngs_modulus", 1.3e6), ("base_angle", 0.1)):
            inside[name] += abs(res.values[name] - true) <= res.stderr[name]
    tol = _coverage_tolerance(0.6827, SEEDS)
    for name, count in inside.items():
        assert abs(count / SEEDS - 0.6827) < tol, (name, count / SEEDS)
    # chi2 follows a chi-square law with dof = 8: mean 8, sd of the mean 4/sqrt(200)
    assert abs(np.mean(chi2) - 8.0) < 3 * 4.0 / math.sqrt(SEEDS)


def test_coverage_stress_data() -> None:
    """Stress-calibrated sensors (a known wall shear stress at each point)."""
    tau = np.asarray(TRUE.deform(VELOCITY).wall_shear_stress)
    clean = model_tip_deflection(TRUE, wall_shear_stress=tau)
    assert np.allclose(clean, TRUE.deform(VELOCITY).tip_deflection, rtol=1e-12)
    inside = 0
    seeds = 100
    for seed in range(seeds):
        noise = np.random.default_rng(1000 + seed).normal(0.0, SIGMA, VELOCITY.size)
        res = fit(
            GUESS_E, clean + noise, wall_shear_stress=tau, sigma=SIGMA, free="youngs_modulus"
        )
        assert res.success and res.kind == "wall_shear_stress"
        inside += abs(res.values["youngs_modulus"] - 1.3e6) <= res.stderr["youngs_modulus"]
    assert abs(inside / seeds - 0.6827) < _coverage_tolerance(0.6827, seeds)


@pytest.mark.parametrize("kind", ["pressure_gradient", "flow_rate"])
def test_pump_driven_round_trip(kind: str) -> None:
    """Exact synthetic data of a pump-driven bed (the loaded solver) are fitted back exactly,
    and the model is that of HairBed.deform under the same drive."""
    x = PUMP_X[kind]
    clean = model_tip_deflection(TRUE, **{kind: x})
    assert np.allclose(clean, TRUE.deform(**{kind: x}).tip_deflection, rtol=1e-12, atol=0)
    free = ("youngs_modulus", "base_angle")
    res = fit(GUESS, clean, sigma=SIGMA, free=free, **{kind: x})
    assert res.success and res.status == 0 and res.kind == kind
    assert res.values["youngs_modulus"] == pytest.approx(1.3e6, rel=1e-9)
    assert res.values["base_angle"] == pytest.approx(0.1, abs=1e-9)
    assert res.chi2 < 1e-12


def test_pump_driven_degeneracy_is_named() -> None:
    d = model_tip_deflection(TRUE, pressure_gradient=GRADIENT)
    res = fit(GUESS_E, d, pressure_gradient=GRADIENT, sigma=SIGMA, free="youngs_modulus,viscosity")
    assert res.status == -4 and "viscosity does not enter pressure-gradient data" in res.message
    with pytest.raises(ValueError, match="exactly one of velocity"):
        fit(GUESS_E, d, pressure_gradient=GRADIENT, flow_rate=FLOW_RATE)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["pressure_gradient", "flow_rate"])
def test_coverage_pump_driven(kind: str) -> None:
    """The 1-sigma intervals of pump-driven calibrations hold the truth in ~68 % of 200 noisy
    fits (the seeds of test_coverage_over_seeds: the mean of the noise's own sum of squares
    over them is 9.99 for 10 points, where seeds 5000 + i give 10.85 and so a mean chi2 of
    8.7 for every kind of data, velocity too), and chi2 has the mean of its law."""
    x = PUMP_X[kind]
    clean = model_tip_deflection(TRUE, **{kind: x})
    inside = {"youngs_modulus": 0, "base_angle": 0}
    chi2 = []
    for seed in range(SEEDS):
        noise = np.random.default_rng(seed).normal(0.0, SIGMA, x.size)
        res = fit(GUESS, clean + noise, sigma=SIGMA, free=tuple(inside), **{kind: x})
        assert res.success
        chi2.append(res.chi2)
        for name, true in (("youngs_modulus", 1.3e6), ("base_angle", 0.1)):
            inside[name] += abs(res.values[name] - true) <= res.stderr[name]
    tol = _coverage_tolerance(0.6827, SEEDS)
    for name, count in inside.items():
        assert abs(count / SEEDS - 0.6827) < tol, (name, count / SEEDS)
    assert abs(np.mean(chi2) - 8.0) < 3 * 4.0 / math.sqrt(SEEDS)


@pytest.mark.parametrize("kind", ["pressure_gradient", "flow_rate"])
def test_measure_pump_driven(kind: str) -> None:
    """measure(drive=) inverts a pump-driven deflection for the known drive; its standard
    error is sigma over the slope of the curve plus the fit's covariance through the
    derivatives at fixed deflection (both checked by central differences of independent
    solves), and the stress and the other drive follow through their derivatives."""
    x = PUMP_X[kind][[0, 4, 9]]
    d = model_tip_deflection(TRUE, **{kind: x})
    m = measure(TRUE, d, sigma=SIGMA, drive=kind)
    other = "flow_rate" if kind == "pressure_gradient" else "pressure_gradient"
    assert m.success and m.status == 0
    assert np.allclose(getattr(m, kind), x, rtol=1e-12, atol=0)
    h = 1e-4 * np.abs(x)
    up, down = TRUE.deform(**{kind: x + h}), TRUE.deform(**{kind: x - h})
    slope = (np.asarray(up.tip_deflection) - np.asarray(down.tip_deflection)) / (2 * h)
    err = np.asarray(getattr(m, kind + "_stderr"))
    assert np.allclose(err, SIGMA / np.abs(slope), rtol=1e-6)
    for name, value in (("wall_shear_stress", m.wall_shear_stress_stderr),
                        (other, getattr(m, other + "_stderr"))):  # fmt: skip
        dv = (np.asarray(getattr(up, name)) - np.asarray(getattr(down, name))) / (2 * h)
        assert np.allclose(value, np.abs(dv) * err, rtol=1e-6), name
    # with a fit: the inversion's sensitivity to the fitted modulus at fixed deflection
    noise = np.random.default_rng(3).normal(0.0, SIGMA, PUMP_X[kind].size)
    cal = fit(GUESS_E, model_tip_deflection(TRUE, **{kind: PUMP_X[kind]}) + noise,
              sigma=SIGMA, **{kind: PUMP_X[kind]})  # fmt: skip
    with_fit = measure(cal.bed, d, sigma=SIGMA, fit=cal)  # the drive from cal.kind
    e = cal.values["youngs_modulus"]
    step = 1e-6 * e
    shifted = [
        np.asarray(getattr(measure(replace(cal.bed, packing_fraction=None,
                                           youngs_modulus=e + sgn * step), d, drive=kind), kind))
        for sgn in (1, -1)
    ]  # fmt: skip
    g = (shifted[0] - shifted[1]) / (2 * step)
    base = np.asarray(getattr(measure(cal.bed, d, sigma=SIGMA, drive=kind), kind + "_stderr"))
    expect = np.sqrt(base**2 + g**2 * cal.covariance[0, 0])
    assert np.allclose(getattr(with_fit, kind + "_stderr"), expect, rtol=1e-5)
    with pytest.raises(ValueError, match="drive must be"):
        measure(TRUE, d, drive="velocity")


def test_scatter_estimate_without_sigma() -> None:
    clean = model_tip_deflection(TRUE, velocity=VELOCITY)
    noise = np.random.default_rng(7).normal(0.0, SIGMA, VELOCITY.size)
    with_sigma = fit(GUESS_E, clean + noise, velocity=VELOCITY, sigma=SIGMA)
    without = fit(GUESS_E, clean + noise, velocity=VELOCITY)
    assert without.values["youngs_modulus"] == pytest.approx(
        with_sigma.values["youngs_modulus"], rel=1e-9
    )
    ratio = without.stderr["youngs_modulus"] / with_sigma.stderr["youngs_modulus"]
    assert ratio == pytest.approx(math.sqrt(with_sigma.chi2 / with_sigma.dof), rel=1e-6)
    assert without.chi2 == pytest.approx(with_sigma.chi2 * SIGMA**2, rel=1e-6)  # [m^2]


#: Known pump drives of the pump-driven calibration tests (both walls at rest): pressure
#: gradients [Pa/m] (against the grain too) and flow rates per unit width [m^2/s].
GRADIENT = np.linspace(-2e3, 2e4, 10)
FLOW_RATE = np.linspace(1e-5, 2e-4, 10)
PUMP_X = {"velocity": VELOCITY, "wall_shear_stress": np.linspace(1.0, 200.0, 6),
          "pressure_gradient": GRADIENT, "flow_rate": FLOW_RATE}  # fmt: skip


@pytest.mark.parametrize("kind", list(PUMP_X))
@pytest.mark.parametrize("geometry", ["spacing", "packing_fraction"])
def test_jacobian_against_finite_differences(kind: str, geometry: str) -> None:
    x = PUMP_X[kind]
    x = np.concatenate([x, -x[:2]])  # flow against the grain too
    free = tuple(p for p in FREE_PARAMETERS if p != ("packing_fraction" if geometry ==
                 "spacing" else "spacing"))  # fmt: skip
    _, jac, dx, _ = _model(TRUE, kind, x, free, geometry)
    keep = "packing_fraction" if geometry == "spacing" else "spacing"

    def model(bed: HairBed, xx: np.ndarray) -> np.ndarray:
        return _model(bed, kind, xx, (), geometry)[0]

    for j, name in enumerate(free):
        value = float(getattr(TRUE, name))
        h = 1e-6 * max(abs(value), 1e-3)
        up = replace(TRUE, **{keep: None, name: value + h})
        down = replace(TRUE, **{keep: None, name: value - h})
        ref = (model(up, x) - model(down, x)) / (2 * h)
        scale = np.max(np.abs(ref)) + 1e-300
        assert np.max(np.abs(jac[:, j] - ref)) / scale < 1e-6, name
    h = 1e-6 * np.abs(x)
    ref = (model(TRUE, x + h) - model(TRUE, x - h)) / (2 * h)
    assert np.max(np.abs(dx - ref) / np.abs(ref)) < 1e-6


def test_measure_propagates_sigma_and_covariance() -> None:
    clean = model_tip_deflection(TRUE, velocity=VELOCITY)
    noise = np.random.default_rng(3).normal(0.0, SIGMA, VELOCITY.size)
    cal = fit(GUESS_E, clean + noise, velocity=VELOCITY, sigma=SIGMA, free="youngs_modulus")
    bed = cal.bed
    d = 3e-4
    m = measure(bed, d, sigma=SIGMA)
    st = bed.state_from_tip_deflection(d)
    assert m.velocity == st.velocity and m.wall_shear_stress == st.wall_shear_stress
    # sigma alone: |dv/dD| sigma, dv/dD by central differences of the exact inversion
    h = 1e-9
    dv = (bed.velocity_from_tip_deflection(d + h) - bed.velocity_from_tip_deflection(d - h)) / (
        2 * h
    )
    dtau = (
        bed.wall_shear_stress_from_tip_deflection(d + h)
        - bed.wall_shear_stress_from_tip_deflection(d - h)
    ) / (2 * h)
    assert m.velocity_stderr == pytest.approx(abs(dv) * SIGMA, rel=1e-6)
    assert m.wall_shear_stress_stderr == pytest.approx(abs(dtau) * SIGMA, rel=1e-6)
    # with the calibration's covariance: + (dv/dE)^2 var(E) at fixed D
    mf = measure(bed, d, sigma=SIGMA, fit=cal)
    e = bed.youngs_modulus
    he = 1e-6 * e

    def at(modulus: float) -> HairBed:
        return replace(bed, packing_fraction=None, youngs_modulus=modulus)

    dv_de = (
        at(e + he).velocity_from_tip_deflection(d) - at(e - he).velocity_from_tip_deflection(d)
    ) / (2 * he)
    var_e = cal.stderr["youngs_modulus"] ** 2
    expect = math.sqrt((dv * SIGMA) ** 2 + dv_de**2 * var_e)
    assert mf.velocity_stderr == pytest.approx(expect, rel=1e-6)
    # the stress read from a deflection does not depend on the modulus only through v
    assert mf.wall_shear_stress_stderr > m.wall_shear_stress_stderr
    assert mf.success and mf.status == 0
    # arrays
    arr = measure(bed, np.array([1e-4, 3e-4]), sigma=SIGMA)
    assert np.asarray(arr.velocity_stderr).shape == (2,)
    assert arr.velocity_stderr[1] == pytest.approx(m.velocity_stderr, rel=1e-12)


#: A bed with three states at one speed: eps = 0.95, hairs leaning into the flow (issue 22).
BISTABLE = HairBed(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=1e-3 / 0.95,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=-1.2,
)
BISTABLE_OMEGA2 = 0.5135


def _central(f: Callable[[float], Any], x: float, h: float) -> float:
    return float((f(x + h) - f(x - h)) / (2.0 * h))


@pytest.mark.parametrize("root", ["low", "mid", "high"])
def test_measure_errors_are_those_of_the_state_the_deflection_fixes(root: str) -> None:
    """Inside a bistable window the deflection picks the state; its errors are its own.

    Reference: central differences of the exact inversion (HairBed's velocity and stress from
    a tip deflection), which share no code with the derivatives. A re-solve at the speed with
    the low root gave the low state's slope for the high one (5.55e-8 against 2.40e-8).
    """
    bed = BISTABLE
    sol = hairbed.solve(BISTABLE_OMEGA2, bed.eps, bed.base_angle, root=root)
    assert sol.status == 0 and sol.n_roots == 3
    d = bed.length * float(sol.tip_deflection)
    sigma = 1e-9
    m = measure(bed, d, sigma=sigma)
    assert m.success and m.status == 0
    assert m.velocity == pytest.approx(BISTABLE_OMEGA2 * bed.velocity_scale, rel=1e-9)
    h = 1e-6 * bed.length
    dv = _central(bed.velocity_from_tip_deflection, d, h)
    dtau = _central(bed.wall_shear_stress_from_tip_deflection, d, h)
    assert m.velocity_stderr == pytest.approx(abs(dv) * sigma, rel=FINITE_DIFFERENCE_RTOL)
    assert m.wall_shear_stress_stderr == pytest.approx(
        abs(dtau) * sigma, rel=FINITE_DIFFERENCE_RTOL
    )
    # all three at once, as an array: each keeps its own state
    if root == "high":
        states = [
            hairbed.solve(BISTABLE_OMEGA2, bed.eps, bed.base_angle, root=r)
            for r in ("low", "mid", "high")
        ]
        ds = np.array([bed.length * float(s.tip_deflection) for s in states])
        arr = measure(bed, ds, sigma=sigma)
        ref = [abs(_central(bed.velocity_from_tip_deflection, x, h)) * sigma for x in ds]
        assert np.asarray(arr.velocity_stderr) == pytest.approx(ref, rel=FINITE_DIFFERENCE_RTOL)
        assert len({round(float(e), 12) for e in arr.velocity_stderr}) == 3


def test_invert_sigma_with_a_bed_is_that_of_the_high_state() -> None:
    """``hairbed invert --sigma`` with a bed goes through measure: the same state's errors."""
    bed = BISTABLE
    sol = hairbed.solve(BISTABLE_OMEGA2, bed.eps, bed.base_angle, root="high")
    d = bed.length * float(sol.tip_deflection)
    args = ["--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6"]
    args += ["--channel-height", repr(bed.channel_height), "--viscosity", "1"]
    args += ["--spacing", "400e-6", "--base-angle=-1.2"]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["invert", "--tip-deflection", repr(d), "--sigma", "1e-9", "--json", *args])
    assert code == 0
    got = json.loads(out.getvalue())
    dv = _central(bed.velocity_from_tip_deflection, d, 1e-6 * bed.length)
    assert got["velocity_stderr"] == pytest.approx(abs(dv) * 1e-9, rel=FINITE_DIFFERENCE_RTOL)


def test_linear_range() -> None:
    for tol in (0.01, 0.1):
        lr = linear_range(TRUE, tol)
        assert lr.success and lr.status == 0
        d = lr.tip_deflection
        exact_v = TRUE.velocity_from_tip_deflection(d)
        lin_v = TRUE.linear_velocity_from_tip_deflection(d)
        exact_t = TRUE.wall_shear_stress_from_tip_deflection(d)
        lin_t = TRUE.linear_wall_shear_stress_from_tip_deflection(d)
        errors = (lin_v / exact_v - 1.0, lin_t / exact_t - 1.0)
        assert max(abs(e) for e in errors) == pytest.approx(tol, rel=1e-6)
        assert lr.velocity == pytest.approx(exact_v, rel=1e-9)
        assert lr.wall_shear_stress == pytest.approx(exact_t, rel=1e-9)
        # below it, within the tolerance
        d2 = 0.5 * (d + TRUE.length * math.sin(TRUE.base_angle))
        err2 = TRUE.linear_velocity_from_tip_deflection(d2) / TRUE.velocity_from_tip_deflection(d2)
        assert abs(err2 - 1.0) < tol


def test_singular_fit_is_reported() -> None:
    tau = np.asarray(TRUE.deform(VELOCITY).wall_shear_stress)
    d = model_tip_deflection(TRUE, wall_shear_stress=tau)
    res = fit(GUESS, d, wall_shear_stress=tau, sigma=SIGMA, free=("youngs_modulus", "viscosity"))
    assert not res.success and res.status == -4
    assert "viscosity" in res.message


def test_bad_input() -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    with pytest.raises(ValueError, match="unknown parameter"):
        fit(GUESS, d, velocity=VELOCITY, free=("stiffness",))
    with pytest.raises(ValueError, match="exactly one"):
        fit(GUESS, d, velocity=VELOCITY, wall_shear_stress=VELOCITY)
    with pytest.raises(ValueError, match="same length"):
        fit(GUESS, d[:3], velocity=VELOCITY)
    with pytest.raises(ValueError, match="sigma"):
        fit(GUESS, d, velocity=VELOCITY, sigma=-1.0)
    with pytest.raises(ValueError, match="one parameter"):
        fit(GUESS, d, velocity=VELOCITY, free=("spacing", "packing_fraction"))
    with pytest.raises(ValueError, match="rtol"):
        linear_range(TRUE, 1.5)
    with pytest.raises(ValueError, match="sigma"):
        measure(TRUE, 1e-4, sigma=-1.0)
    with pytest.raises(TypeError, match="HairBed"):
        fit(object(), d, velocity=VELOCITY)  # type: ignore[arg-type]


def test_lazy_export() -> None:
    assert hairbed.calibration.fit is fit


def test_linear_range_tolerance_is_a_deprecated_alias_of_rtol() -> None:
    """Issue 22 item 7: the old keyword and field keep working, warn and name rtol."""
    with pytest.warns(FutureWarning, match="'tolerance' is deprecated.*use 'rtol'"):
        old = linear_range(TRUE, tolerance=0.05)
    new = linear_range(TRUE, rtol=0.05)
    assert old.tip_deflection == new.tip_deflection and new.rtol == 0.05
    with pytest.warns(FutureWarning, match="use LinearRange.rtol"):
        assert new.tolerance == 0.05


# -- read_points: calibration points from a CSV file -----------------------------------------


def test_read_points_reads_the_columns_in_any_order(tmp_path):
    from hairbed.calibration import read_points

    v = [0.05, 0.1, 0.2]
    x = [1.234567890123e-4, 2.5e-4, 3.75e-4]
    s = [1e-6, 2e-6, 3e-6]
    text = "# a sensor\nSigma, velocity ,tip_deflection\n\n" + "".join(
        f"{c},{a},{b}\n" for a, b, c in zip(v, x, s)
    )
    path = tmp_path / "points.csv"
    path.write_text(text)
    points = read_points(path)
    assert points.velocity.tolist() == v
    assert points.tip_deflection.tolist() == x
    assert points.sigma.tolist() == s
    assert points.wall_shear_stress is None
    path.write_text("wall_shear_stress,tip_deflection\n0.5,1e-4\n")
    points = read_points(str(path))
    assert points.wall_shear_stress.tolist() == [0.5]
    assert points.velocity is None and points.sigma is None


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("velocity,tip_deflection\n", r"needs a header line and at least one row"),
        ("speed,tip_deflection\n1,2\n", r"unknown column 'speed'; allowed: tip_deflection"),
        ("velocity,tip_deflection\n1,2\n3\n", r"line 3 has 1 fields, not 2"),
        ("velocity,tip_deflection\n1,abc\n", r"line 2, tip_deflection: not a number: 'abc'"),
        ("velocity,sigma\n1,2\n", r"needs a tip_deflection column \[m\]"),
        ("tip_deflection,sigma\n1,2\n", r"needs exactly one of the columns velocity"),
        ("velocity,wall_shear_stress,tip_deflection\n1,2,3\n", r"needs exactly one"),
    ],
)
def test_read_points_names_the_file_line_and_column(tmp_path, text, message):
    from hairbed.calibration import read_points

    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"^{re.escape(str(path))}: .*{message}"):
        read_points(path)
    with pytest.raises(OSError):
        read_points(tmp_path / "missing.csv")


def test_fit_of_parameters_of_very_different_units_is_not_called_singular():
    """E [Pa] and L [m] differ by 1e9 in their own units: the fit of both recovers them and
    its standard errors are those of the linearised least squares, (J^T J)^-1 sigma^2 with J
    by central differences of model_tip_deflection (the rank test runs in the fitted
    coordinates, not in the units)."""
    geometry = {"radius": 50e-6, "channel_height": 2e-3, "viscosity": 1.0, "spacing": 400e-6}
    truth = {"youngs_modulus": 1.3e6, "length": 1.1e-3}
    v = np.linspace(0.01, 0.3, 12)
    d = model_tip_deflection(HairBed(**geometry, **truth), velocity=v)
    sigma = 1e-7
    res = fit(
        HairBed(**geometry, length=1.0e-3, youngs_modulus=1.0e6),
        d,
        velocity=v,
        sigma=sigma,
        free=("youngs_modulus", "length"),
    )
    assert res.status == 0 and res.success
    for name, value in truth.items():
        assert res.values[name] == pytest.approx(value, rel=1e-9)
    cols = []
    for name, value in truth.items():
        h = 1e-5 * value
        up = model_tip_deflection(HairBed(**geometry, **{**truth, name: value + h}), velocity=v)
        dn = model_tip_deflection(HairBed(**geometry, **{**truth, name: value - h}), velocity=v)
        cols.append((np.asarray(up) - np.asarray(dn)) / (2 * h))
    jac = np.column_stack(cols) / sigma
    ref = np.sqrt(np.diag(np.linalg.inv(jac.T @ jac)))
    got = [res.stderr[name] for name in truth]
    assert got == pytest.approx(ref, rel=1e-5)
