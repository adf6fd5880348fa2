"""Pump-driven beds in SI (HairBed.deform with a pump drive, hairbed._channel_drives).

References: the SI definitions written out here (second moment, wall area per hair, the
dimensionless loads of theory.md §11), the closed form of the wall-driven channel (a
different solver) at G = 0, the two pump drives against each other (a flow rate computed
from a pressure-driven state must give that state back), the mirror image, and the small-load
cantilever formula x1 = W/3 + Pi/8.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hairbed import HairBed, solve

BED = dict(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
)


def _bed(**kw: float) -> HairBed:
    return HairBed(**{**BED, **kw})


def _groups(bed: HairBed) -> tuple[float, float, float]:
    """(A, E I, eps) from the definitions: A = (sqrt 3/2) spacing^2, I = pi a^4/4."""
    area = math.sqrt(3.0) / 2.0 * bed.spacing**2
    ei = bed.youngs_modulus * math.pi * bed.radius**4 / 4.0
    return area, ei, bed.length / bed.channel_height


def test_dimensionless_loads_are_the_definitions() -> None:
    bed = _bed(base_angle=0.3)
    area, ei, eps = _groups(bed)
    g, v = 3e3, 0.02
    st = bed.deform(v, pressure_gradient=g)
    assert st.solution.pi == pytest.approx(area * g * bed.length**3 / ei, rel=1e-14)
    omega2 = area * bed.viscosity * v * bed.length**2 / (ei * bed.channel_height)
    assert st.solution.omega2 == pytest.approx(omega2, rel=1e-14)
    qp = 2e-6
    st = bed.deform(flow_rate=qp)
    q = 6 * area * bed.viscosity * qp * bed.length**2 / (ei * bed.channel_height**2)
    assert st.solution.q == pytest.approx(q, rel=1e-14)


@pytest.mark.parametrize("base_angle", [-1.0, 0.0, 0.7])
def test_no_pressure_gradient_is_the_closed_form(base_angle: float) -> None:
    bed = _bed(base_angle=base_angle)
    v = np.array([1e-4, 0.01, 0.1, 0.5])
    pumped = bed.deform(v, pressure_gradient=0.0)
    exact = bed.deform(v)
    assert np.all(pumped.solution.status == 0)
    np.testing.assert_allclose(pumped.tip_deflection, exact.tip_deflection, rtol=0, atol=1e-15)
    np.testing.assert_allclose(pumped.tip_height, exact.tip_height, rtol=0, atol=1e-15)
    np.testing.assert_allclose(
        pumped.wall_shear_stress, exact.wall_shear_stress, rtol=1e-12, atol=0
    )
    np.testing.assert_allclose(pumped.flow_rate, exact.flow_rate, rtol=1e-12)
    # and the wall drive's flow rate is the Couette one, v g / 2
    gap = bed.channel_height - exact.tip_height
    np.testing.assert_allclose(exact.flow_rate, v * gap / 2, rtol=1e-15)


@pytest.mark.parametrize("velocity", [0.0, 0.05, -0.05])
def test_the_two_pump_drives_agree(velocity: float) -> None:
    """The flow rate of a pressure-driven state, set as the drive, gives the state back."""
    bed = _bed(base_angle=0.4)
    g = np.array([-2e4, -50.0, 100.0, 5e3, 4e4])
    by_pressure = bed.deform(velocity, pressure_gradient=g)
    by_flow = bed.deform(velocity, flow_rate=by_pressure.flow_rate)
    assert np.all(by_pressure.solution.status == 0) and np.all(by_flow.solution.status == 0)
    np.testing.assert_allclose(by_flow.pressure_gradient, g, rtol=1e-9)
    np.testing.assert_allclose(
        by_flow.tip_deflection, by_pressure.tip_deflection, rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(by_flow.tip_height, by_pressure.tip_height, rtol=0, atol=1e-15)
    np.testing.assert_allclose(by_flow.wall_shear_stress, by_pressure.wall_shear_stress, rtol=1e-9)


def test_gap_flow_of_a_state_from_its_profile() -> None:
    """tau, Q' and force from the Couette-Poiseuille profile, integrated numerically."""
    bed = _bed(base_angle=0.2, density=1000.0)
    v, g = 0.03, 2e3
    st = bed.deform(v, pressure_gradient=g)
    gap = bed.channel_height - st.tip_height
    y = np.linspace(0.0, gap, 20001)
    u = v * y / gap + g * y * (gap - y) / (2 * bed.viscosity)
    assert st.flow_rate == pytest.approx(np.trapezoid(u, y), rel=1e-8)
    tau = bed.viscosity * np.gradient(u, y, edge_order=2)[0]  # exact for a parabola
    assert st.wall_shear_stress == pytest.approx(tau, rel=1e-6)
    area, _, _ = _groups(bed)
    assert st.force_per_hair == pytest.approx(area * (st.wall_shear_stress + g * st.tip_height))
    reynolds = bed.density * np.max(np.abs(u)) * gap / bed.viscosity
    assert st.reynolds_number == pytest.approx(reynolds, rel=1e-8)


def test_negative_drive_is_the_mirror_image() -> None:
    g = np.array([300.0, 3e3, 3e4])
    up = _bed(base_angle=0.5).deform(pressure_gradient=g)
    down = _bed(base_angle=-0.5).deform(pressure_gradient=-g)
    np.testing.assert_allclose(down.tip_deflection, -up.tip_deflection, rtol=1e-13, atol=1e-18)
    np.testing.assert_allclose(down.tip_height, up.tip_height, rtol=1e-13)
    np.testing.assert_allclose(down.flow_rate, -up.flow_rate, rtol=1e-12)


def test_small_pressure_gradient_is_the_cantilever() -> None:
    """theta0 = 0: x1 = W/3 + Pi/8 with W = (Pi/2)(1/eps - 1) at h1 = 1.

    The remainder shrinks faster than the load squared: like its cube, as x1 is odd in the
    load at theta0 = 0 (the mirror image).
    """
    bed = _bed()
    area, ei, eps = _groups(bed)
    g = np.array([1.0, 2.0, 4.0, 8.0])
    pi = area * g * bed.length**3 / ei
    linear = (pi / 2 * (1 / eps - 1) / 3 + pi / 8) * bed.length
    st = bed.deform(pressure_gradient=g)
    remainder = np.abs(st.tip_deflection - linear)
    assert np.all(remainder < 1e-3 * np.abs(linear))
    slopes = np.diff(np.log(remainder)) / np.diff(np.log(g))
    np.testing.assert_allclose(slopes, 3.0, atol=0.05)


def test_stress_ratio_of_a_pressure_drive() -> None:
    """At v = 0, tau = G g/2 against G H/2 on the bare channel: the ratio is g/H."""
    bed = _bed(base_angle=0.3)
    st = bed.deform(pressure_gradient=[10.0, 1e4])
    gap = bed.channel_height - np.asarray(st.tip_height)
    np.testing.assert_allclose(st.stress_ratio, gap / bed.channel_height, rtol=1e-13)


def test_profile_of_a_pumped_state_ends_at_its_tip() -> None:
    st = _bed(base_angle=-0.3).deform(pressure_gradient=2e4)
    x, z = st.profile(64)
    assert x.shape == (64,) and z.shape == (64,)
    assert abs(x[0]) < 1e-18 and abs(z[0]) < 1e-18  # [m]: the spectral interpolant at s = 0
    assert x[-1] == pytest.approx(st.tip_deflection, rel=1e-12)
    assert z[-1] == pytest.approx(st.tip_height, rel=1e-12)


def test_wall_drive_unchanged() -> None:
    st = _bed().deform(0.1)
    sol = solve(st.omega2, _bed().eps, 0.0)
    assert st.tip_deflection == pytest.approx(sol.tip_deflection * 1e-3, rel=1e-15)
    assert st.pressure_gradient == 0.0


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({}, r"needs velocity \[m/s\], pressure_gradient \[Pa/m\] or flow_rate"),
        (
            {"pressure_gradient": 1.0, "flow_rate": 1e-6},
            r"at most one of pressure_gradient \[Pa/m\] and flow_rate",
        ),
        ({"pressure_gradient": float("nan")}, r"pressure_gradient"),
        ({"flow_rate": [1e-6, float("inf")]}, r"flow_rate.*index 1"),
        ({"flow_rate": 1e308}, r"flow_rate must be within"),
        ({"velocity": [1.0, 2.0], "pressure_gradient": [1.0, 2.0, 3.0]}, r"broadcast"),
    ],
)
def test_bad_pump_inputs_name_the_parameter(kwargs: dict, pattern: str) -> None:
    error = TypeError if not kwargs else ValueError
    with pytest.raises(error, match=pattern):
        _bed().deform(**kwargs)
