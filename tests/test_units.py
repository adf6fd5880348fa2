"""HairBed: the dimensionless groups, the SI state, the mirror image and validation."""

import dataclasses
import math

import numpy as np
import pytest

import hairbed
from hairbed.units import CLOSE_PACKING_FRACTION, HairBed, HairState

# A 1 mm hair of radius 50 um at 400 um spacing, E = 1 MPa, H = 2 mm, eta = 1 Pa s.
L, A, E, H, ETA, DELTA = 1e-3, 50e-6, 1e6, 2e-3, 1.0, 400e-6


def make_bed(**kw):
    args = dict(
        length=L, radius=A, youngs_modulus=E, channel_height=H, viscosity=ETA, spacing=DELTA
    )
    args.update(kw)
    return HairBed(**args)


def test_groups_against_hand_formulas():
    bed = make_bed()
    # written differently from the code: I and phi substituted by hand,
    # omega^2 = 2 sqrt(3) L^2 eta v delta^2 / (pi E a^4 H)
    v = 0.1
    assert bed.omega2(v) == pytest.approx(
        2 * math.sqrt(3) * L**2 * ETA * v * DELTA**2 / (math.pi * E * A**4 * H), rel=1e-14
    )
    assert bed.eps == pytest.approx(0.5, rel=1e-15)
    assert bed.second_moment == pytest.approx(math.pi * 6.25e-18 / 4, rel=1e-14)
    assert bed.packing_fraction == pytest.approx(2 * math.pi / math.sqrt(3) / 64, rel=1e-14)
    assert bed.wall_area_per_hair == pytest.approx(math.sqrt(3) / 2 * DELTA**2, rel=1e-14)
    assert bed.bending_stiffness == pytest.approx(E * math.pi * A**4 / 4, rel=1e-14)
    # a hand-computed number: v_c = E a^2 H phi / (4 L^2 eta) = 0.0708516...
    assert bed.velocity_scale == pytest.approx(
        1e6 * 2.5e-9 * 2e-3 * (math.pi / (32 * math.sqrt(3))) / 4e-6, rel=1e-14
    )
    assert bed.omega2(bed.velocity_scale) == pytest.approx(1.0, rel=1e-15)
    assert bed.omega2(-v) == bed.omega2(v)


def test_spacing_and_packing_fraction_describe_the_same_bed():
    by_spacing = make_bed()
    by_phi = make_bed(spacing=None, packing_fraction=by_spacing.packing_fraction)
    assert by_phi.spacing == pytest.approx(DELTA, rel=1e-14)
    assert by_phi.velocity_scale == pytest.approx(by_spacing.velocity_scale, rel=1e-14)
    # hexagonal close packing: touching hairs, a = delta / 2
    assert CLOSE_PACKING_FRACTION == pytest.approx(2 * math.pi / math.sqrt(3) * 0.25, rel=1e-15)


def test_deform_matches_the_dimensionless_solution():
    bed = make_bed(base_angle=0.2)
    v = np.array([0.0, 0.01, 0.1, 1.0, 30.0])
    state = bed.deform(v)
    assert isinstance(state, HairState)
    w = 2 * math.sqrt(3) * L**2 * ETA * v * DELTA**2 / (math.pi * E * A**4 * H)
    sol = hairbed.solve(w, L / H, 0.2)
    np.testing.assert_allclose(state.tip_deflection, L * sol.tip_deflection, rtol=1e-13)
    np.testing.assert_allclose(state.tip_height, L * sol.tip_height, rtol=1e-13)
    tau = ETA * v / (H - L * sol.tip_height)
    np.testing.assert_allclose(state.wall_shear_stress, tau, rtol=1e-13)
    np.testing.assert_allclose(state.force_per_hair, tau * math.sqrt(3) / 2 * DELTA**2, rtol=1e-13)
    np.testing.assert_allclose(state.stress_ratio, 1 / (1 - 0.5 * sol.tip_height), rtol=1e-13)
    # at rest: straight hair, no stress
    assert state.tip_deflection[0] == pytest.approx(L * math.sin(0.2), rel=1e-14)
    assert state.wall_shear_stress[0] == 0.0
    assert state.stress_ratio[0] == pytest.approx(1 / (1 - 0.5 * math.cos(0.2)), rel=1e-14)
    # the profile ends at the tip, in metres
    x, z = state.profile(50)
    assert x.shape == z.shape == (5, 50)
    np.testing.assert_allclose(x[:, -1], state.tip_deflection, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(z[:, -1], state.tip_height, rtol=1e-12)
    # the hair is inextensible: its length is L
    seg = np.hypot(np.diff(x, axis=1), np.diff(z, axis=1)).sum(axis=1)
    np.testing.assert_allclose(seg, L, rtol=1e-3)


def test_vectorised_like_scalar_calls():
    bed = make_bed(base_angle=-0.3)
    v = np.array([[-0.2, 0.0], [0.05, 0.4]])
    state = bed.deform(v)
    assert np.shape(state.tip_deflection) == (2, 2)
    for idx in np.ndindex(v.shape):
        one = bed.deform(float(v[idx]))
        assert isinstance(one.tip_deflection, float)
        assert state.tip_deflection[idx] == pytest.approx(one.tip_deflection, rel=1e-14)
        assert state.wall_shear_stress[idx] == pytest.approx(one.wall_shear_stress, rel=1e-14)


def test_negative_velocity_is_the_mirror_image():
    theta0, v = 0.4, np.array([0.02, 0.3, 3.0])
    back = make_bed(base_angle=theta0).deform(-v)
    mirror = make_bed(base_angle=-theta0).deform(v)
    np.testing.assert_allclose(back.tip_deflection, -mirror.tip_deflection, rtol=1e-14)
    np.testing.assert_allclose(back.tip_height, mirror.tip_height, rtol=1e-14)
    np.testing.assert_allclose(back.tip_angle, -mirror.tip_angle, rtol=1e-14)
    np.testing.assert_allclose(back.wall_shear_stress, -mirror.wall_shear_stress, rtol=1e-14)
    np.testing.assert_allclose(back.force_per_hair, -mirror.force_per_hair, rtol=1e-14)
    xb, zb = back.profile(20)
    xm, zm = mirror.profile(20)
    np.testing.assert_allclose(xb, -xm, atol=1e-18)
    np.testing.assert_allclose(zb, zm, atol=1e-18)
    # the base angle is kept: the hair leaves its base towards +x, then the flow bends it back
    assert np.all(xb[:, 1] > 0)
    assert np.all(back.tip_deflection < L * math.sin(theta0))
    # stress opposes the motion of the wall and is larger against the grain
    assert np.all(back.wall_shear_stress < 0)
    forward = make_bed(base_angle=theta0).deform(v)
    assert np.all(-back.wall_shear_stress > forward.wall_shear_stress)


def test_root_selection_in_the_bistable_window():
    # theta0 = -1, eps = 0.95: three states for 0.29696 < omega^2 < 0.31966 (theory.md §5)
    bed = make_bed(channel_height=L / 0.95, base_angle=-1.0)
    v = 0.31 * bed.velocity_scale
    heights = [bed.deform(v, root=r).tip_height for r in ("low", "mid", "high")]
    states = [hairbed.solve(0.31, 0.95, -1.0, root=r) for r in ("low", "mid", "high")]
    np.testing.assert_allclose(heights, [L * s.tip_height for s in states], rtol=1e-12)
    assert len(set(heights)) == 3


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(length=0.0), "length must be positive"),
        (dict(radius=-1e-6), "radius must be positive"),
        (dict(youngs_modulus=float("nan")), "youngs_modulus must be finite"),
        (dict(viscosity=0), "viscosity must be positive"),
        (dict(channel_height=float("inf")), "channel_height must be finite"),
        (dict(length="1 mm"), "length must be a real number"),
        (dict(spacing=100e-6), "less than half the spacing"),
        (dict(spacing=None), "exactly one of spacing"),
        (dict(packing_fraction=0.1), "exactly one of spacing"),
        (dict(spacing=None, packing_fraction=0.95), "close packing"),
        (dict(spacing=None, packing_fraction=-0.1), "packing_fraction must be positive"),
        (dict(channel_height=L), "less than channel_height"),
        (dict(base_angle=math.pi / 2), r"base_angle must lie in \(-pi/2, pi/2\)"),
        (dict(base_angle=float("nan")), "base_angle"),
    ],
)
def test_invalid_beds_say_what_is_wrong(kw, match):
    with pytest.raises(ValueError, match=match):
        make_bed(**kw)


def test_invalid_velocity_and_deflection():
    bed = make_bed()
    with pytest.raises(ValueError, match="velocity"):
        bed.deform(float("nan"))
    with pytest.raises(ValueError, match="root"):
        bed.deform(0.1, root="middle")
    with pytest.raises(ValueError, match=r"tip deflection must lie in \(-length, length\)"):
        bed.velocity_from_tip_deflection(L)


def test_calibration_curve_round_trip():
    bed = make_bed(base_angle=0.3)
    v = np.array([-5.0, -0.3, -0.01, 0.0, 1e-4, 0.02, 0.3, 5.0, 300.0])
    state = bed.deform(v)
    back = bed.velocity_from_tip_deflection(state.tip_deflection)
    np.testing.assert_allclose(back, v, rtol=1e-10, atol=1e-15)
    tau = bed.wall_shear_stress_from_tip_deflection(state.tip_deflection)
    np.testing.assert_allclose(tau, state.wall_shear_stress, rtol=1e-10, atol=1e-12)
    # the deflection of a bed at rest reads zero flow
    assert bed.velocity_from_tip_deflection(L * math.sin(0.3)) == 0.0


def test_linear_calibration_is_the_tangent_of_the_exact_one():
    bed = make_bed(base_angle=0.25)
    rest = L * math.sin(0.25)
    # tangent at rest: relative error O(deflection)
    for dd in (1e-9, 1e-8):
        for sign in (1, -1):
            d = rest + sign * dd * L
            exact = bed.velocity_from_tip_deflection(d)
            linear = bed.linear_velocity_from_tip_deflection(d)
            assert linear == pytest.approx(exact, rel=50 * dd)
    # and fails at large deflection: it underestimates the flow (the bed stiffens)
    d = L * 0.8
    assert bed.linear_velocity_from_tip_deflection(d) < 0.7 * bed.velocity_from_tip_deflection(d)
    # the linear stress uses the gap at rest
    d = rest + 1e-3 * L
    v_lin = bed.linear_velocity_from_tip_deflection(d)
    assert bed.linear_wall_shear_stress_from_tip_deflection(d) == pytest.approx(
        ETA * v_lin / (H - L * math.cos(0.25)), rel=1e-14
    )


def test_fit_profile_in_metres():
    bed = make_bed(base_angle=0.1)
    state = bed.deform(0.25)
    x, z = state.profile(15)
    res = bed.fit_profile(x, z)
    assert res.fit.theta0 == 0.1
    assert res.velocity == pytest.approx(0.25, rel=1e-9)
    assert res.velocity_stderr == pytest.approx(res.fit.omega2_stderr * bed.velocity_scale)
    assert res.success and res.status == 0 and res.message == res.fit.message


def test_equality_and_repr():
    assert make_bed() == make_bed()
    assert make_bed() != make_bed(base_angle=0.1)
    assert hash(make_bed()) == hash(make_bed())
    assert "spacing=0.0004" in repr(make_bed())
    # the repr builds the same bed again (spacing only: packing_fraction is derived)
    assert "packing_fraction" not in repr(make_bed())
    assert eval(repr(make_bed()), {"HairBed": HairBed}) == make_bed()
    # frozen, with the given one of spacing / packing fraction filled in
    with pytest.raises(dataclasses.FrozenInstanceError):
        make_bed().length = 2.0
    by_phi = make_bed(spacing=None, packing_fraction=make_bed().packing_fraction)
    assert by_phi.spacing == pytest.approx(make_bed().spacing, rel=1e-14)
    assert isinstance(make_bed(base_angle=0).base_angle, float)
