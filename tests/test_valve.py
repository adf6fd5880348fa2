"""The bed as a valve (hairbed.valve): flow, resistance and diodicity.

References: rigid hairs (a huge modulus) leave a gap H - L cos(theta0), whose plane
Poiseuille flow is written out here; the mirror image (Di(theta0) Di(-theta0) = 1, Di = 1
upright); the flow-rate drive, a different set of loads in the solver, given the valve's
flow back must find the valve's pressure gradient.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hairbed import HairBed
from hairbed.valve import diodicity, valve_curve

BED = dict(
    length=1.8e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
)


def _bed(**kw: float) -> HairBed:
    return HairBed(**{**BED, **kw})


def test_rigid_hairs_leave_a_plane_poiseuille_gap() -> None:
    bed = _bed(youngs_modulus=1e13, base_angle=0.6)
    dp, length = np.array([-300.0, 50.0, 300.0]), 0.02
    curve = valve_curve(bed, dp, length)
    gap = bed.channel_height - bed.length * math.cos(0.6)
    expected = dp / length * gap**3 / (12 * bed.viscosity)
    np.testing.assert_allclose(curve.flow_rate, expected, rtol=1e-6)
    np.testing.assert_allclose(curve.resistance_ratio, (bed.channel_height / gap) ** 3, rtol=1e-6)
    empty = dp * bed.channel_height**3 / (12 * bed.viscosity * length)
    np.testing.assert_allclose(curve.empty_flow_rate, empty, rtol=1e-15)


def test_an_upright_bed_is_no_diode() -> None:
    d = diodicity(_bed(), [10.0, 300.0, 3e4], 0.01)
    np.testing.assert_allclose(d.diodicity, 1.0, rtol=1e-12)


@pytest.mark.parametrize("base_angle", [0.3, 1.0])
def test_the_mirror_bed_inverts_the_diodicity(base_angle: float) -> None:
    dp = np.array([20.0, 200.0, 2000.0])
    forward = diodicity(_bed(base_angle=base_angle), dp, 0.01)
    mirrored = diodicity(_bed(base_angle=-base_angle), dp, 0.01)
    assert forward.success and mirrored.success
    np.testing.assert_allclose(
        np.asarray(forward.diodicity) * np.asarray(mirrored.diodicity), 1.0, rtol=1e-11
    )
    assert np.all(np.asarray(forward.diodicity) > 1.0)  # forward flow opens the gap


def test_the_flow_rate_drive_finds_the_valve_pressure_gradient() -> None:
    bed = _bed(base_angle=1.0)
    dp, length = np.array([-20.0, 20.0, 2000.0]), 0.01
    curve = valve_curve(bed, dp, length)
    back = bed.deform(flow_rate=curve.flow_rate)
    np.testing.assert_allclose(back.pressure_gradient, dp / length, rtol=1e-9)
    np.testing.assert_allclose(back.tip_height, curve.tip_height, rtol=0, atol=1e-15)


def test_backward_flow_saturates_two_drops_one_flow() -> None:
    """Backward flow lifts the hairs and closes the gap: Q'(dp) turns back, so a set flow
    rate can be carried at two pressure drops. The flow drive finds the other one; both are
    states of the valve (each drop, solved by the pressure drive, gives that flow)."""
    bed = _bed(base_angle=1.0)
    length = 0.01
    strong = valve_curve(bed, -200.0, length)
    other = bed.deform(flow_rate=strong.flow_rate)
    assert other.solution.status == 0
    assert abs(other.pressure_gradient * length) < 0.5 * 200.0  # a much smaller drop
    again = valve_curve(bed, other.pressure_gradient * length, length)
    assert again.flow_rate == pytest.approx(strong.flow_rate, rel=1e-9)
    # between the two drops the flow is larger: the curve has a maximum (the valve closes)
    middle = valve_curve(bed, np.linspace(other.pressure_gradient * length, -200.0, 9), length)
    assert np.min(np.asarray(middle.flow_rate)[1:-1]) < strong.flow_rate


@pytest.mark.parametrize(
    ("call", "pattern"),
    [
        (lambda: valve_curve("bed", 1.0, 0.01), r"bed must be a hairbed.HairBed"),
        (lambda: valve_curve(_bed(), 1.0, 0.0), r"channel_length"),
        (lambda: valve_curve(_bed(), [1.0, float("nan")], 0.01), r"pressure_drop.*index 1"),
        (lambda: diodicity(_bed(), [0.0, 1.0], 0.01), r"pressure_drop must be non-zero"),
    ],
)
def test_bad_valve_inputs_are_named(call, pattern: str) -> None:
    with pytest.raises((TypeError, ValueError), match=pattern):
        call()
