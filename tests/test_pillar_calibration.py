"""Calibration of a pillar's geometry (issue 21): base_angle, length and radius free.

The Jacobian (derivatives_at of the PillarState through the SI scaling) against central
differences of model_tip_deflection on perturbed pillars (every state solved anew); round
trips on synthetic data; the degeneracies named; the coverage of the base angle's 1-sigma
interval over 200 seeded synthetic sensors.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from tolerances import PILLAR_JACOBIAN_FD_RTOL

import hairbed
from hairbed import calibration
from hairbed.calibration import PILLAR_FREE_PARAMETERS, _pillar_model_at

L, A, E, ETA = 500e-6, 25e-6, 1.0e6, 1.0e-3
TAU = np.linspace(0.5, 150.0, 9)  # [Pa]: x1 from 0.2 to 0.75


def _pillar(profile="sublayer", channel_height=None, **kw):
    args = {"length": L, "radius": A, "youngs_modulus": E, "viscosity": ETA, "base_angle": 0.2}
    args.update(kw)
    return hairbed.Pillar(**args, profile=profile, channel_height=channel_height)


@pytest.mark.parametrize(
    "pillar",
    [_pillar(), _pillar("poiseuille", 800e-6, base_angle=-0.6), _pillar("couette", 600e-6)],
    ids=["sublayer", "poiseuille", "couette"],
)
def test_jacobian_against_central_differences(pillar):
    names = tuple(PILLAR_FREE_PARAMETERS)
    sol = pillar._solve(pillar._forcing(TAU))
    d, jac, _ = _pillar_model_at(pillar, TAU, sol, names)
    np.testing.assert_array_equal(
        d, calibration.model_tip_deflection(pillar, wall_shear_stress=TAU)
    )
    for j, name in enumerate(names):
        v = getattr(pillar, name)
        h = 1e-5 * (1.0 if name == "base_angle" else abs(v))
        up, down = replace(pillar, **{name: v + h}), replace(pillar, **{name: v - h})
        fd = (
            calibration.model_tip_deflection(up, wall_shear_stress=TAU)
            - calibration.model_tip_deflection(down, wall_shear_stress=TAU)
        ) / (2 * h)
        big = np.max(np.abs(jac[:, j]))
        assert np.max(np.abs(fd - jac[:, j])) <= PILLAR_JACOBIAN_FD_RTOL * big, name


@pytest.mark.parametrize(
    ("changes", "free"),
    [
        ({"youngs_modulus": 1.3e6, "base_angle": 0.35}, ("youngs_modulus", "base_angle")),
        ({"length": 520e-6}, ("length",)),
        ({"radius": 23e-6}, ("radius",)),
        (
            {"radius": 23e-6, "length": 490e-6, "youngs_modulus": 1.1e6},
            ("radius", "length", "youngs_modulus"),
        ),  # fmt: skip
        (
            {"drag_scale": 0.8, "base_angle": -0.1, "radius": 26e-6},
            ("drag_scale", "base_angle", "radius"),
        ),  # fmt: skip
    ],
)
def test_round_trip(changes, free):
    true = replace(_pillar(), **changes)
    d = calibration.model_tip_deflection(true, wall_shear_stress=TAU)
    res = calibration.fit(_pillar(), d, wall_shear_stress=TAU, sigma=1e-9, free=free)
    assert res.success and res.status == 0, res.message
    for name in free:
        assert res.values[name] == pytest.approx(getattr(true, name), rel=1e-8, abs=1e-10)
        assert 0.0 < res.stderr[name] < math.inf
    m = calibration.measure(res.bed, d[3], sigma=1e-9, fit=res)
    assert m.success and m.wall_shear_stress == pytest.approx(TAU[3], rel=1e-8)


def test_round_trip_of_a_poiseuille_length():
    """L enters a Poiseuille pillar also through L/H (U = z (1 - (L/H) z))."""
    base = _pillar("poiseuille", 800e-6)
    true = replace(base, length=560e-6)
    d = calibration.model_tip_deflection(true, wall_shear_stress=TAU)
    res = calibration.fit(base, d, wall_shear_stress=TAU, sigma=1e-9, free="length,base_angle")
    assert res.success, res.message
    assert res.values["length"] == pytest.approx(560e-6, rel=1e-9)


def test_degeneracies_are_named():
    d = calibration.model_tip_deflection(_pillar(), wall_shear_stress=TAU)
    # one parameter twice (c/E): refused as spacing with packing_fraction is (issue 33)
    with pytest.raises(ValueError, match="drag_scale/E"):
        calibration.fit(
            _pillar(),
            d,
            wall_shear_stress=TAU,
            free=("youngs_modulus", "base_angle", "drag_scale"),
        )
    with pytest.raises(ValueError, match="callable profile"):
        calibration.fit(
            _pillar(profile=lambda z: 1e3 * z), d, wall_shear_stress=TAU, free="length"
        )
    with pytest.raises(ValueError, match="unknown parameter 'viscosity'"):
        calibration.fit(_pillar(), d, wall_shear_stress=TAU, free="viscosity")


@pytest.mark.slow
def test_coverage_of_the_base_angle_over_200_sensors():
    """200 synthetic sensors (fixed seed): theta0 and E fitted from 9 noisy points; the
    1-sigma interval of theta0 covers the truth in about 68.3 % of them (binomial sd 3.3 %:
    4 sd allowed)."""
    rng = np.random.default_rng(21)
    true = replace(_pillar(), youngs_modulus=1.3e6, base_angle=0.3)
    d_true = calibration.model_tip_deflection(true, wall_shear_stress=TAU)
    sigma = 2e-6  # [m], against deflections of 100 to 375 um
    hits = 0
    n = 200
    for _ in range(n):
        d = d_true + sigma * rng.standard_normal(TAU.size)
        res = calibration.fit(
            _pillar(), d, wall_shear_stress=TAU, sigma=sigma, free="youngs_modulus,base_angle"
        )
        assert res.success
        hits += abs(res.values["base_angle"] - 0.3) <= res.stderr["base_angle"]
    assert abs(hits / n - 0.683) <= 4.0 * math.sqrt(0.683 * 0.317 / n), hits
