"""hairbed.valve.valve_states: every coexisting state of a valve, its folds and hysteresis.

The bistable valve is the one the pump drives at a set flow rate with both walls at rest: at
eps = L/H = 0.8, base_angle = -1.2 the reference (tests/data/loaded_mpmath.json, mpmath,
independent of the solver) has the folds of the flow drive at q = 0.0764... and 0.2138... and
one or three states at five q through the window and just inside and outside each fold.
valve_states finds its states by continuation; they are checked against those mpmath folds
and states, against the scan of hairbed.solve_loaded_all (a different algorithm) on a grid
through the window, and against the plane Poiseuille law of the gap for the pressure drops.
A moving wall with a set pressure drop also folds: with omega2 at a reference fold of the
pressure drive (pi = 0.1), the fold is met at that pressure drop.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import DATA
from tolerances import LOADED_REFERENCE_ATOL

import hairbed
from hairbed import HairBed
from hairbed.valve import valve_curve, valve_states

REF = json.loads((DATA / "loaded_mpmath.json").read_text())
FLOW_FOLDS = sorted(
    (float(f["value"]), float(f["tip_height"])) for f in REF["folds"] if f["drive"] == "flow"
)
PRESSURE_FOLDS = [f for f in REF["folds"] if f["drive"] == "pressure"]
FLOW_CASES = [
    c
    for c in REF["cases"]
    if c["drive"] == "flow" and c["eps"] == 0.8 and c["theta0"] == -1.2 and c["omega2"] == 0.0
]
#: The folds' tip heights come from a golden-section search to 1e-9 in h1.
FOLD_HEIGHT_ATOL = 1e-7
LENGTH = 0.01  # the channel's length l [m]


def _bed(eps: float = 0.8, base_angle: float = -1.2) -> HairBed:
    return HairBed(
        length=eps * 2e-3,
        radius=50e-6,
        youngs_modulus=1e6,
        channel_height=2e-3,
        viscosity=1.0,
        spacing=400e-6,
        base_angle=base_angle,
    )


def _q_per_flow(bed: HairBed) -> float:
    """q per unit Q' [s/m^2]: q = 6 A eta Q' L^2 / (E I H^2) (theory.md §11)."""
    ei = bed.youngs_modulus * np.pi * bed.radius**4 / 4.0
    return (
        6.0 * bed.wall_area_per_hair * bed.viscosity * bed.length**2 / (ei * bed.channel_height**2)
    )


@pytest.fixture(scope="module")
def window():
    bed = _bed()
    scale = _q_per_flow(bed)
    q = np.array([float(c["q"]) for c in FLOW_CASES])
    return bed, scale, valve_states(bed, LENGTH, flow_rate=q / scale)


def test_the_folds_are_the_reference_folds(window) -> None:
    bed, scale, s = window
    assert s.success and s.status == 0 and s.drive == "flow"
    got = np.sort(s.fold_flow_rate * scale)
    np.testing.assert_allclose(got, [v for v, _ in FLOW_FOLDS], rtol=LOADED_REFERENCE_ATOL)
    heights = s.fold_tip_height[np.argsort(s.fold_flow_rate)] / bed.length
    np.testing.assert_allclose(heights, [h for _, h in FLOW_FOLDS], atol=FOLD_HEIGHT_ATOL)
    # the pressure drop that pushes Q' through the gap g: plane Poiseuille, G = 12 eta Q'/g^3
    gap = bed.channel_height - s.fold_tip_height
    want = 12.0 * bed.viscosity * s.fold_flow_rate / gap**3 * LENGTH
    np.testing.assert_allclose(s.fold_pressure_drop, want, rtol=1e-12)


def test_every_state_of_the_reference_cases(window) -> None:
    bed, _, s = window
    for i, case in enumerate(FLOW_CASES):
        ref = case["states"]
        assert s.count[i] == len(ref), case["label"]
        assert s.count_stable[i] == sum(r["stable"] for r in ref)
        got = s.tip_height[i, : s.count[i]] / bed.length
        want = [float(r["tip_height"]) for r in ref]
        np.testing.assert_allclose(got, want, atol=LOADED_REFERENCE_ATOL)
        assert s.stable[i, : s.count[i]].tolist() == [r["stable"] for r in ref]
        assert np.all(np.isnan(s.tip_height[i, s.count[i] :]))


def test_the_count_on_a_grid_through_the_window() -> None:
    """41 set flow rates through the window: three states (two stable) strictly between the
    reference folds, one outside, and the same states as the scan of solve_loaded_all."""
    bed = _bed()
    scale = _q_per_flow(bed)
    q = np.linspace(0.05, 0.25, 41)
    s = valve_states(bed, LENGTH, flow_rate=q / scale)
    (lo, _), (hi, _) = FLOW_FOLDS
    inside = (q > lo) & (q < hi)
    assert inside.sum() == 27
    np.testing.assert_array_equal(s.count, np.where(inside, 3, 1))
    np.testing.assert_array_equal(s.count_stable, np.where(inside, 2, 1))
    for i, value in enumerate(q):
        scan = hairbed.solve_loaded_all(0.0, 0.8, -1.2, q=value, num_scan=400)
        assert len(scan) == s.count[i], value
        got = s.tip_height[i, : s.count[i]] / bed.length
        np.testing.assert_allclose(got, [st.tip_height for st in scan], atol=1e-10)
        assert s.stable[i, : s.count[i]].tolist() == [bool(st.stable) for st in scan]


def test_the_ramps_jump_at_the_reference_folds(window) -> None:
    bed, scale, s = window
    (lo, h_lo), (hi, h_hi) = FLOW_FOLDS
    up, down = s.ramp_up, s.ramp_down
    assert up.direction == 1 and down.direction == -1
    assert len(up.jumps) == 1 and len(down.jumps) == 1
    for jump, fold, h_fold, pick in ((up.jumps[0], hi, h_hi, -1), (down.jumps[0], lo, h_lo, 0)):
        assert jump.drive_value * scale == pytest.approx(fold, rel=LOADED_REFERENCE_ATOL)
        assert jump.flow_rate_before == jump.flow_rate_after == jump.drive_value
        assert jump.tip_height_before / bed.length == pytest.approx(h_fold, abs=FOLD_HEIGHT_ATOL)
        # it lands on the one other state there (the scan just past the fold has one left)
        past = fold * (1.0 + 1e-6) if pick == -1 else fold * (1.0 - 1e-6)
        (other,) = hairbed.solve_loaded_all(0.0, 0.8, -1.2, q=past, num_scan=400)
        assert jump.tip_height_after / bed.length == pytest.approx(other.tip_height, abs=1e-5)
    # up: the hairs snap up and the gap closes (more pressure for the flow); down: the reverse
    assert up.jumps[0].pressure_drop_after > 3.0 * up.jumps[0].pressure_drop_before
    assert down.jumps[0].pressure_drop_after < down.jumps[0].pressure_drop_before / 3.0
    # each ramp moves one way in the set drive and only visits stable states
    assert np.all(np.diff(up.flow_rate) >= 0.0) and np.all(np.diff(down.flow_rate) <= 0.0)
    # the loop: inside the window the two ramps are on different states
    mid = 0.5 * (lo + hi) / scale
    assert np.interp(mid, up.flow_rate, up.tip_height) < np.interp(
        -mid, -down.flow_rate, down.tip_height
    )


def test_a_set_pressure_drop_at_rest_has_one_state() -> None:
    """Both walls at rest and a set pressure drop: one state throughout, that of valve_curve
    (Newton on the collocation, another algorithm), no fold and no jump."""
    bed = _bed()
    dp = np.linspace(-3000.0, 3000.0, 13)
    s = valve_states(bed, LENGTH, pressure_drop=dp)
    assert s.success and s.drive == "pressure"
    np.testing.assert_array_equal(s.count, 1)
    assert s.stable[:, 0].all() and s.fold_pressure_drop.size == 0
    assert not s.ramp_up.jumps and not s.ramp_down.jumps
    curve = valve_curve(bed, dp, LENGTH)
    np.testing.assert_allclose(s.flow_rate[:, 0], curve.flow_rate, rtol=1e-9, atol=1e-20)
    np.testing.assert_allclose(s.pressure_drop[:, 0], dp, rtol=1e-14)


@pytest.mark.parametrize("side", ["lower", "upper"])
def test_a_moving_wall_folds_at_the_reference_pressure_drop(side: str) -> None:
    """The wall at omega2 of a reference fold of the pressure drive (pi = 0.1): the set
    pressure drop meets that fold at pi = 0.1, i.e. dp = 0.1 l E I / (A L^3)."""
    ref = next(f for f in PRESSURE_FOLDS if f["window_side"] == side)
    bed = _bed(eps=0.95)
    velocity = float(ref["value"]) * bed.velocity_scale
    ei = bed.youngs_modulus * np.pi * bed.radius**4 / 4.0
    dp_fold = float(ref["pi"]) * ei / (bed.wall_area_per_hair * bed.length**3) * LENGTH
    s = valve_states(bed, LENGTH, pressure_drop=[0.0, 10.0 * dp_fold], velocity=velocity)
    assert s.success
    k = np.argmin(np.abs(s.fold_pressure_drop - dp_fold))
    assert s.fold_pressure_drop[k] == pytest.approx(dp_fold, rel=1e-9)
    assert s.fold_tip_height[k] / bed.length == pytest.approx(
        float(ref["tip_height"]), abs=FOLD_HEIGHT_ATOL
    )


def test_bounded_work_and_bad_input() -> None:
    bed = _bed()
    short = valve_states(bed, LENGTH, flow_rate=[0.0, 3e-6], max_steps=2)
    assert short.status == -2 and not short.success
    assert short.covered.tolist() == [True, False] and short.count[1] == 0
    assert "reached flow_rate" in short.message
    with pytest.raises(ValueError, match="exactly one of pressure_drop"):
        valve_states(bed, LENGTH)
    with pytest.raises(ValueError, match="exactly one of pressure_drop"):
        valve_states(bed, LENGTH, pressure_drop=[1.0], flow_rate=[1.0])
    with pytest.raises(ValueError, match=r"flow_rate.*index 1"):
        valve_states(bed, LENGTH, flow_rate=[0.0, float("nan")])
    with pytest.raises(ValueError, match="1-D"):
        valve_states(bed, LENGTH, pressure_drop=[[1.0, 2.0]])
    with pytest.raises(ValueError, match="channel_length"):
        valve_states(bed, 0.0, pressure_drop=[1.0])
    with pytest.raises(ValueError, match="channel_length .* too long"):
        valve_states(bed, 1e308, flow_rate=[0.0, 1e-6])  # G l overflows
    with pytest.raises(ValueError, match="max_steps"):
        valve_states(bed, LENGTH, pressure_drop=[1.0], max_steps=0)
    with pytest.raises(TypeError, match="HairBed"):
        valve_states("bed", LENGTH, pressure_drop=[1.0])  # type: ignore[arg-type]
