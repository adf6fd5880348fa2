"""The porous bed in SI: HairBed(..., model="porous") (issue 29, theory.md §13)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hairbed
from hairbed import HairBed, ModelValidityWarning

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}


def _phi(radius: float, spacing: float) -> float:
    return 2.0 * math.pi / math.sqrt(3.0) * (radius / spacing) ** 2


def _drummond_tahir(radius: float, phi: float) -> tuple[float, float]:
    """(k_perp, k_par) [m^2] of the hexagonal array, typed from Drummond & Tahir (1984)."""
    kp = (
        -math.log(phi)
        - 1.497
        + 2 * phi
        - phi**2 / 2
        - 0.739 * phi**4
        + 2.534 * phi**5 / (1 + 1.2758 * phi)
    ) / (8 * phi)
    kl = (-math.log(phi) - 1.498 + 2 * phi - phi**2 / 2 - 0.0018 * phi**6) / (4 * phi)
    return radius**2 * kp, radius**2 * kl


@pytest.mark.parametrize("drag", ["sparse", "array", "crossover"])
def test_drag_models_and_the_dimensionless_numbers(drag: str) -> None:
    bed = HairBed(**BED, model="porous", drag=drag)
    eta, length, a = 1.0, 1e-3, 50e-6
    phi = _phi(a, 400e-6)
    area = math.pi * a**2 / phi
    kp, kl = _drummond_tahir(a, phi)
    lg = math.log(2 * length / a)
    gh = (4 * math.pi * eta / (lg + 0.5), 2 * math.pi * eta / (lg - 0.5))
    arr = (eta * area / kp, eta * area / kl)
    zeta = bed.drag_coefficients
    if drag == "sparse":
        assert zeta == pytest.approx(gh, rel=1e-14)
    elif drag == "array":
        assert zeta == pytest.approx(arr, rel=1e-14)
        assert bed.kappa == pytest.approx(kp / length**2, rel=1e-14)  # exactly the permeability
    else:  # between the two, nearer the larger drag (the shorter cut-off length)
        for z, s, r in zip(zeta, gh, arr):
            assert max(s, r) < z < s + r
    assert bed.kappa == pytest.approx(eta * area / (zeta[0] * length**2), rel=1e-14)
    assert bed.drag_ratio == pytest.approx(zeta[1] / zeta[0], rel=1e-14)


def test_crossover_tends_to_each_end() -> None:
    """Far sparser than long: Gray & Hancock's; a dense array: the array's own."""
    sparse = HairBed(**{**BED, "spacing": 1.0, "channel_height": 2.0}, model="porous")
    lg = math.log(2 * 1e-3 / 50e-6)
    # the logarithms part slowly: at a spacing of 1000 L the array's cut-off is 8.5 against
    # the hair's 4.19, and the crossover within 0.3 % of Gray & Hancock's
    assert sparse.drag_coefficients[0] == pytest.approx(4 * math.pi / (lg + 0.5), rel=5e-3)
    dense = HairBed(**{**BED, "spacing": 130e-6}, model="porous")
    phi = _phi(50e-6, 130e-6)
    kp, _ = _drummond_tahir(50e-6, phi)
    area = math.pi * 50e-6**2 / phi
    assert dense.drag_coefficients[0] == pytest.approx(area / kp, rel=1e-3)


def test_deform_is_the_dimensionless_porous_state() -> None:
    bed = HairBed(**BED, model="porous", base_angle=0.2)
    v = np.array([0.05, -0.1])
    st = bed.deform(v)
    ref = hairbed.solve_porous(
        v / bed.velocity_scale, bed.eps, 0.2, kappa=bed.kappa, gamma=bed.drag_ratio
    )
    assert np.all(ref.status == 0)
    np.testing.assert_allclose(st.tip_deflection, 1e-3 * ref.tip_deflection, rtol=1e-14)
    np.testing.assert_allclose(st.tip_height, 1e-3 * ref.tip_height, rtol=1e-14)
    # the tip plane's stress and the force per hair in SI, written out here
    ei = 1e6 * math.pi * 50e-6**4 / 4
    area = bed.wall_area_per_hair
    np.testing.assert_allclose(
        st.wall_shear_stress, ref.tip_stress * ei / (area * 1e-6), rtol=1e-13
    )
    np.testing.assert_allclose(st.force_per_hair, ref.drag_x * ei / 1e-6, rtol=1e-13)


def test_flow_drive_holds_its_flow_rate() -> None:
    """The kernel's flux row against the SI flux by Gauss-Legendre of the interpolants."""
    bed = HairBed(**BED, model="porous")
    for v in (0.0, 0.02):
        st = bed.deform(v, flow_rate=np.array([2e-6, -5e-7, 1e-5]))
        np.testing.assert_allclose(st.flow_rate, [2e-6, -5e-7, 1e-5], rtol=1e-9)


def test_pressure_drive_is_odd_and_pushes_the_bed() -> None:
    bed = HairBed(**BED, model="porous")
    st = bed.deform(pressure_gradient=np.array([300.0, -300.0]))
    assert st.tip_deflection[0] > 0 and st.tip_deflection[0] == pytest.approx(
        -st.tip_deflection[1], rel=1e-12
    )
    assert st.flow_rate[0] > 0


def test_collective_stiffening() -> None:
    """The deflection per unit tip-plane stress falls with the density at fixed hairs (the
    experiments of Phys. Rev. E 2020, arXiv:2002.02834), between the isolated pillar's and
    the dense closed form's."""
    per_stress = []
    for spacing in (4e-3, 1.6e-3, 800e-6, 400e-6, 200e-6):
        bed = HairBed(**{**BED, "spacing": spacing, "channel_height": 20e-3}, model="porous")
        st = bed.deform(1e-3)
        per_stress.append(st.tip_deflection / st.wall_shear_stress)
    assert np.all(np.diff(per_stress) < 0), per_stress


def test_dense_model_warning_points_to_the_porous_model() -> None:
    with pytest.warns(ModelValidityWarning, match="model='porous'"):
        HairBed(**{**BED, "spacing": 1e-3})
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelValidityWarning)
        HairBed(**{**BED, "spacing": 1e-3}, model="porous")


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"model": "brinkman"}, "model must be one of"),
        ({"model": "porous", "drag": "stokes"}, "drag must be one of"),
        ({"model": "porous", "spacing": 105e-6}, r"packing_fraction must lie in \(0, 0.6\]"),
    ],
)
def test_bad_models_are_refused(kw: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        HairBed(**{**BED, **kw})


def test_tip_deflection_inverse_round_trip_both_directions() -> None:
    bed = HairBed(**BED, model="porous", base_angle=0.3)
    v = np.array([-0.2, -0.01, 0.0, 0.01, 0.2])
    st = bed.deform(v)
    back = bed.state_from_tip_deflection(st.tip_deflection)
    np.testing.assert_allclose(back.velocity, v, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(back.tip_height, st.tip_height, rtol=1e-12)
    np.testing.assert_allclose(back.wall_shear_stress, st.wall_shear_stress, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(back.tip_angle, st.tip_angle, atol=1e-12)
    np.testing.assert_allclose(bed.velocity_from_tip_deflection(st.tip_deflection), v, rtol=1e-9)


def test_rectification_ratio_of_a_tilted_porous_bed() -> None:
    """Against the grain the tilted bed stands up into the flow and carries more stress."""
    bed = HairBed(**BED, model="porous", base_angle=0.5)
    r = bed.rectification_ratio(np.array([0.01, 0.1]))
    against = bed.deform(-np.array([0.01, 0.1])).wall_shear_stress
    along = bed.deform(np.array([0.01, 0.1])).wall_shear_stress
    np.testing.assert_allclose(r, np.abs(against) / np.abs(along), rtol=1e-14)
    assert np.all(r > 1.0)
    assert HairBed(**BED, model="porous").rectification_ratio(0.1) == pytest.approx(1.0, abs=1e-12)


def test_porous_variables_table_is_the_state() -> None:
    import dataclasses

    from hairbed._variables import POROUS

    fields = [
        f.name
        for f in dataclasses.fields(hairbed.PorousState)
        if not f.name.startswith("_") and f.name != "drive"
    ]
    assert list(POROUS) == fields


def test_sweep_of_a_porous_bed_is_its_deform() -> None:
    pytest.importorskip("xarray")
    bed = HairBed(**BED, model="porous", base_angle=0.2)
    v = np.array([-0.05, 0.0, 0.02, 0.1])
    ds = bed.sweep(v)
    st = bed.deform(v)
    np.testing.assert_array_equal(ds.tip_deflection.values, st.tip_deflection)
    np.testing.assert_array_equal(ds.wall_shear_stress.values, st.wall_shear_stress)
    np.testing.assert_array_equal(ds.scaled_tip_height.values, st.solution.tip_height)
    assert ds.tip_deflection.attrs["units"] == "m" and ds.attrs["model"] == "porous"
    assert ds.attrs["kappa"] == bed.kappa
    grid = bed.sweep([0.0, 0.01], pressure_gradient=[100.0, 300.0], chunks=3)
    assert grid.tip_deflection.dims == ("velocity", "pressure_gradient")
    one = bed.deform(0.01, pressure_gradient=300.0)
    assert grid.tip_deflection.values[1, 1] == one.tip_deflection
    assert grid.status.dtype == np.int64 and np.all(grid.status.values == 0)


def test_valve_of_a_porous_bed_counts_the_flow_through_the_bed() -> None:
    """valve_curve and diodicity take a porous bed: its flow through bed and gap, and the
    resistance as the ratio of the flows (valve_states and the calibration:
    tests/test_porous_workflows.py)."""
    from hairbed import valve

    bed = HairBed(**BED, model="porous", base_angle=0.6)
    curve = valve.valve_curve(bed, [200.0, -200.0], 0.01)
    st = bed.deform(pressure_gradient=np.array([200.0, -200.0]) / 0.01)
    np.testing.assert_allclose(curve.flow_rate, st.flow_rate, rtol=1e-14)
    np.testing.assert_allclose(curve.resistance_ratio, curve.empty_flow_rate / curve.flow_rate)
    dense = HairBed(**BED, base_angle=0.6)
    # the porous bed lets more through than the dense one, whose bed is closed to the flow
    assert np.all(
        curve.resistance_ratio < valve.valve_curve(dense, [200.0, -200.0], 0.01).resistance_ratio
    )
    di = valve.diodicity(bed, 200.0, 0.01)
    assert di.success and di.diodicity > 1.0
