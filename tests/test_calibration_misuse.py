"""hairbed.calibration misapplied as a sensor engineer would: each trap as a test.

References: the calibration points themselves (their SHA-256 recomputed here with hashlib),
the bed's own public linear and exact calibrations (for the linear ranges), the scaling laws
of the SI model (a degenerate pair leaves the model unchanged), Drummond & Tahir's
permeability formula written out here, and Reynolds numbers from the definitions.
"""

from __future__ import annotations

import hashlib
import json
import math
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hairbed import CalibrationWarning, HairBed, ModelValidityWarning
from hairbed._core.validation import STATUS_MESSAGES
from hairbed._version import __version__
from hairbed.calibration import fit, linear_range, measure, model_tip_deflection
from hairbed.calibration_files import read_calibration, write_calibration

#: The README's sensor: 1 mm hairs, radius 50 um, 400 um spacing, under 2 mm of glycerol.
README_BED = HairBed(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
)
TRUE = replace(README_BED, packing_fraction=None, youngs_modulus=1.3e6, base_angle=0.1)
VELOCITY = np.linspace(0.01, 0.3, 10)


def _sha256(kind: str, *arrays: np.ndarray) -> str:
    h = hashlib.sha256(kind.encode())
    for a in arrays:
        h.update(np.asarray(a, dtype="<f8").tobytes())
    return h.hexdigest()


# -- item 1: the calibration file holds the bed, the data's fingerprint and the version ------


def test_calibration_file_holds_the_whole_bed(tmp_path: Path) -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    res = fit(README_BED, d, velocity=VELOCITY, sigma=2e-6, free=("youngs_modulus", "base_angle"))
    path = tmp_path / "cal.json"
    write_calibration(res, path)
    doc = json.loads(path.read_text())
    assert doc["hairbed_version"] == __version__
    assert doc["data"]["sha256"] == _sha256("velocity", VELOCITY, d, np.full(10, 2e-6))
    assert doc["data"]["points"] == 10 and doc["data"]["kind"] == "velocity"
    assert doc["bed"]["radius"] == 50e-6 and doc["bed"]["channel_height"] == 2e-3
    assert doc["parameters"]["youngs_modulus"]["start"] == 1e6
    back = read_calibration(path)
    assert back.bed == res.bed  # every parameter, fitted or fixed
    assert back.values == res.values and back.stderr == res.stderr
    np.testing.assert_array_equal(back.covariance, res.covariance)
    assert back.fingerprint == res.fingerprint and back.status == res.status
    # measuring with the file is measuring with the calibration
    a = measure(res.bed, 3e-4, sigma=2e-6, fit=res)
    b = measure(back.bed, 3e-4, sigma=2e-6, fit=back)
    assert a.wall_shear_stress == b.wall_shear_stress
    assert a.wall_shear_stress_stderr == b.wall_shear_stress_stderr


def test_calibration_file_refuses_what_it_cannot_trust(tmp_path: Path) -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    res = fit(README_BED, d, velocity=VELOCITY, sigma=2e-6, free="youngs_modulus,base_angle")
    path = tmp_path / "cal.json"
    write_calibration(res, path)
    doc = json.loads(path.read_text())
    old = {k: doc[k] for k in ("parameters", "covariance")}  # the file of before: no bed
    (tmp_path / "old.json").write_text(json.dumps(old))
    with pytest.raises(ValueError, match="not a hairbed calibration file"):
        read_calibration(tmp_path / "old.json")
    doc["bed"]["youngs_modulus"] = 2e6  # hand-edited: the bed no longer holds the fit
    (tmp_path / "edited.json").write_text(json.dumps(doc))
    with pytest.raises(ValueError, match="youngs_modulus"):
        read_calibration(tmp_path / "edited.json")


def test_without_sigma_the_fingerprint_has_no_sigma() -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    res = fit(TRUE, d, velocity=VELOCITY)
    assert res.fingerprint == _sha256("velocity", VELOCITY, d)


# -- item 3: an impossible fit is marked ---------------------------------------------------


def test_one_point_without_sigma_warns_and_says_so() -> None:
    d = model_tip_deflection(TRUE, velocity=[0.1])
    with pytest.warns(CalibrationWarning, match="no degrees of freedom"):
        res = fit(README_BED, d, velocity=[0.1])
    assert res.dof == 0 and res.status == 5 and res.status in STATUS_MESSAGES
    assert "no degrees of freedom" in res.message and "infinite" in res.message
    assert math.isinf(res.stderr["youngs_modulus"])
    assert res.chi2_unit == "m^2" and not res.weighted
    # with sigma, the errors are those of sigma, but chi2 still says nothing
    with pytest.warns(CalibrationWarning, match="no degrees of freedom"):
        res = fit(README_BED, d, velocity=[0.1], sigma=1e-6)
    assert res.status == 5 and math.isfinite(res.stderr["youngs_modulus"])
    assert res.chi2_unit == "1"


def test_a_fit_with_degrees_of_freedom_does_not_warn() -> None:
    d = model_tip_deflection(TRUE, velocity=VELOCITY)
    with warnings.catch_warnings():
        warnings.simplefilter("error", CalibrationWarning)
        res = fit(README_BED, d, velocity=VELOCITY, sigma=2e-6)
    assert res.status == 0 and res.dof == 9


def test_the_degenerate_parameters_are_named() -> None:
    tau = np.asarray(TRUE.deform(VELOCITY).wall_shear_stress)
    d = model_tip_deflection(TRUE, wall_shear_stress=tau)
    res = fit(TRUE, d, wall_shear_stress=tau, sigma=2e-6, free=("youngs_modulus", "radius"))
    assert res.status == -4 and not res.success
    assert "youngs_modulus, radius" in res.message and "delta^2/(E a^4)" in res.message
    assert "channel_height" not in res.message and "viscosity" not in res.message
    # the claim itself: E -> c E with a -> c^(-1/4) a at fixed spacing leaves the model alone
    c = 1.7
    other = replace(TRUE, packing_fraction=None, youngs_modulus=c * 1.3e6, radius=c**-0.25 * 50e-6)
    np.testing.assert_allclose(
        model_tip_deflection(other, wall_shear_stress=tau), d, rtol=1e-12, atol=0
    )
    # velocity data: the viscosity joins the combination
    dv = model_tip_deflection(TRUE, velocity=VELOCITY)
    res = fit(TRUE, dv, velocity=VELOCITY, sigma=2e-6, free=("youngs_modulus", "viscosity"))
    assert res.status == -4 and "eta delta^2/(E a^4)" in res.message
    other = replace(TRUE, packing_fraction=None, youngs_modulus=c * 1.3e6, viscosity=c * 1.0)
    np.testing.assert_allclose(model_tip_deflection(other, velocity=VELOCITY), dv, rtol=1e-12)
    # stress data do not hold the channel height
    res = fit(TRUE, d, wall_shear_stress=tau, sigma=2e-6, free=("channel_height",))
    assert res.status == -4 and "channel_height does not enter stress data" in res.message


# -- item 4: the linear range of the stress and of the speed --------------------------------


def _relative_errors(bed: HairBed, d: float) -> tuple[float, float]:
    ev = bed.linear_velocity_from_tip_deflection(d) / bed.velocity_from_tip_deflection(d) - 1
    et = (
        bed.linear_wall_shear_stress_from_tip_deflection(d)
        / bed.wall_shear_stress_from_tip_deflection(d)
        - 1
    )
    return float(ev), float(et)


def test_linear_range_of_the_stress_is_not_that_of_the_speed() -> None:
    stress = linear_range(README_BED, 0.05, quantity="wall_shear_stress")
    speed = linear_range(README_BED, 0.05, quantity="velocity")
    both = linear_range(README_BED, 0.05)
    ev, et = _relative_errors(README_BED, stress.tip_deflection)
    assert abs(et) == pytest.approx(0.05, rel=1e-6) and abs(ev) > 0.05
    ev, et = _relative_errors(README_BED, speed.tip_deflection)
    assert abs(ev) == pytest.approx(0.05, rel=1e-6) and abs(et) < 0.05
    # the trap: the stress limit is 27 % beyond where the speed's linear calibration ends
    assert stress.wall_shear_stress / speed.wall_shear_stress == pytest.approx(1.27, abs=0.01)
    assert both.limits["wall_shear_stress"] == stress and both.limits["velocity"] == speed
    assert both.tip_deflection == speed.tip_deflection and both.quantity == "both"
    with pytest.raises(ValueError, match="quantity must be one of"):
        linear_range(README_BED, 0.05, quantity="stress")


# -- item 5: validity everywhere the model is evaluated in SI -------------------------------

#: The sensor bed of the issue: PDMS pillars (L = 500 um, a = 25 um, 150 um apart) in water.
WATER_SENSOR = HairBed(
    length=500e-6,
    radius=25e-6,
    youngs_modulus=2e6,
    channel_height=1e-3,
    viscosity=1e-3,
    spacing=150e-6,
    density=1000.0,
)


def test_model_tip_deflection_and_fit_warn_outside_stokes_flow() -> None:
    v = np.array([0.05, 0.1])
    with pytest.warns(ModelValidityWarning, match="Reynolds number"):
        d = model_tip_deflection(WATER_SENSOR, velocity=v)
    with pytest.warns(ModelValidityWarning, match="Reynolds number"):
        fit(WATER_SENSOR, d, velocity=v, sigma=1e-7)
    with pytest.warns(ModelValidityWarning, match="Reynolds number"):
        model_tip_deflection(WATER_SENSOR, wall_shear_stress=1.0)
    slow = replace(WATER_SENSOR, packing_fraction=None, viscosity=1.0)  # glycerol
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelValidityWarning)
        model_tip_deflection(slow, velocity=1e-4)


def test_the_water_sensor_is_outside_stokes_flow_over_its_whole_range() -> None:
    """From the smallest readable deflection (1 um) to the end of its linear range."""
    end = linear_range(WATER_SENSOR, 0.05, quantity="wall_shear_stress").tip_deflection
    with pytest.warns(ModelValidityWarning):
        states = WATER_SENSOR.state_from_tip_deflection(np.linspace(1e-6, end, 50))
    gap = WATER_SENSOR.channel_height - np.asarray(states.tip_height)
    reynolds = 1000.0 * np.abs(np.asarray(states.velocity)) * gap / 1e-3
    assert np.min(reynolds) > 10.0  # at 1 um of deflection already


def _drummond_tahir(a: float, phi: float) -> float:
    return (
        a**2
        / (8 * phi)
        * (
            -math.log(phi)
            - 1.497
            + 2 * phi
            - phi**2 / 2
            - 0.739 * phi**4
            + 2.534 * phi**5 / (1 + 1.2758 * phi)
        )
    )


def test_the_dense_bed_condition() -> None:
    phi = WATER_SENSOR.packing_fraction
    assert phi == pytest.approx(2 * math.pi / math.sqrt(3) * (25 / 150) ** 2, rel=1e-14)
    k = _drummond_tahir(25e-6, phi)
    assert WATER_SENSOR.permeability == pytest.approx(k, rel=1e-14)
    assert WATER_SENSOR.brinkman_length / WATER_SENSOR.length == pytest.approx(0.0555, abs=1e-3)
    with pytest.warns(ModelValidityWarning, match="not dense"):  # hairs 1 mm apart
        HairBed(
            length=500e-6,
            radius=25e-6,
            youngs_modulus=2e6,
            channel_height=1e-3,
            viscosity=1e-3,
            spacing=1e-3,
        )
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelValidityWarning)
        replace(README_BED, packing_fraction=None)  # sqrt(k)/L = 0.09: dense enough


def test_the_calibration_curve_in_stress() -> None:
    """HairBed.velocity_from_wall_shear_stress against the forward solve at that speed."""
    tau = np.array([-40.0, -1e-3, 0.0, 1e-6, 2.5, 19.4, 80.0])
    for bed in (README_BED, TRUE):
        v = bed.velocity_from_wall_shear_stress(tau)
        assert np.all(np.sign(v) == np.sign(tau))
        back = np.asarray(bed.deform(v).wall_shear_stress)
        np.testing.assert_allclose(back, tau, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="wall_shear_stress"):
        README_BED.velocity_from_wall_shear_stress(np.nan)
