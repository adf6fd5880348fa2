"""HairBed.simulate: the porous bed in time in SI (issue 30 item 6, theory.md §15).

The SI run must be simulate_bed's dimensionless one under scalings written here from the
formulas (not taken from the code), a constant drive must end at HairBed.deform's porous
state, and bad input must be named.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed import dynamics

KW: dict[str, Any] = dict(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                          viscosity=1.0, spacing=400e-6, base_angle=0.2)  # fmt: skip


def _scales(bed: hairbed.HairBed, rho_s: float | None) -> dict[str, Any]:
    """The model's numbers and the drives' scales, from the formulas of theory.md §11/§13/§15."""
    length, a, e, h = bed.length, bed.radius, bed.youngs_modulus, bed.channel_height
    eta = bed.viscosity
    ei = e * math.pi * a**4 / 4.0
    phi = (2.0 * math.pi / math.sqrt(3.0)) * a**2 / float(bed.spacing or math.nan) ** 2
    area = math.pi * a**2 / phi
    zeta = bed.drag_coefficients[0]  # the drag law's normal coefficient [Pa s]
    t = zeta * length**4 / ei
    out: dict[str, Any] = dict(
        T=t, EI=ei, kappa=eta * area / (zeta * length**2), eps=length / h,
        omega2=area * eta * length**2 / (ei * h), stress=area * length**2 / ei,
        pi=area * length**3 / ei, q=6.0 * area * eta * length**2 / (ei * h**2),
        alpha=0.0 if bed.density is None else bed.density * length**2 / (eta * t),
        mu=0.0, chi=1.0,
    )  # fmt: skip
    if rho_s is not None:
        rho_f = bed.density or 0.0
        out["mu"] = (rho_s + rho_f) * math.pi * a**2 / (zeta * t)
        out["chi"] = rho_s / (rho_s + rho_f)
    return out


def test_si_run_is_the_dimensionless_run_under_independent_scalings():
    """A dense bed with fluid and hair inertia, an SI sine wall and an SI ramp of G; then a
    set wall stress with a callable flow rate: the SI outputs are simulate_bed's times the
    scales written above (the dense bed runs the porous model of its geometry)."""
    bed = hairbed.HairBed(**{**KW, "viscosity": 0.01}, density=1000.0)  # dense
    rho_s = 1100.0
    c = _scales(bed, rho_s)
    t_si = np.linspace(0.0, 0.1, 9)
    v0, v1, w = 5.0, 2.0, 60.0  # [m/s], [m/s], [rad/s]
    g0, g1 = 0.0, 3e6  # [Pa/m]
    run = bed.simulate(
        t_si, velocity=dynamics.sine(v0, v1, w), hair_density=rho_s,
        pressure_gradient=dynamics.ramp(g0, g1, 0.02, 0.1), num=12, num_gap=6,
    )  # fmt: skip
    ref = dynamics.simulate_bed(
        bed.base_angle, c["kappa"], c["eps"], t_eval=t_si / c["T"],
        wall=dynamics.sine(c["omega2"] * v0, c["omega2"] * v1, w * c["T"]),
        pressure=dynamics.ramp(c["pi"] * g0, c["pi"] * g1, 0.02 / c["T"], 0.1 / c["T"]),
        gamma=bed.drag_ratio, inertia=c["mu"], tangential_mass=c["chi"],
        womersley=c["alpha"], num=12, num_gap=6,
    )  # fmt: skip
    assert run.success and ref.success and run.model == "porous" and run.bed_model == "dense"
    assert run.womersley > 0.0 and run.inertia_number > 0.0
    for got, want in (
        (run.time_scale, c["T"]),
        (run.kappa, c["kappa"]),
        (run.womersley, c["alpha"]),
        (run.inertia_number, c["mu"]),
    ):
        assert got == pytest.approx(want, rel=1e-12)
    pairs = {
        "tip_deflection": bed.length * ref.tip_deflection,
        "tip_height": bed.length * ref.tip_height,
        "base_moment": c["EI"] * ref.base_moment / bed.length,
        "wall_shear_stress": ref.wall_stress / c["stress"],
        "wall_velocity": ref.wall_speed / c["omega2"],
        "flow_rate": ref.flow_rate / c["q"],
        "pressure_gradient": ref.pressure / c["pi"],
    }
    for name, want in pairs.items():
        got = getattr(run, name)
        scale = np.max(np.abs(want))
        assert scale > 0.0, name
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * scale, err_msg=name)
    ds = run.to_xarray()
    units = {"tip_deflection": "m", "base_moment": "N m", "wall_shear_stress": "Pa",
             "flow_rate": "m^2/s", "pressure_gradient": "Pa/m"}  # fmt: skip
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit and ds[name].attrs["long_name"]
    assert ds["time"].attrs["units"] == "s" and ds.attrs["model"] == "porous"

    # a set top-wall stress [Pa] and a callable flow rate [m^2/s] of t [s], no inertia
    porous = hairbed.HairBed(**KW, model="porous")
    c = _scales(porous, None)
    tau, q0 = 40.0, 2e-5

    def flow(t):
        return q0 * (1.0 - np.exp(-t / 0.3))

    t_si = np.linspace(0.0, 1.5, 7)
    run = porous.simulate(t_si, wall_shear_stress=dynamics.step(tau, 0.0, 0.1), flow_rate=flow)
    ref = dynamics.simulate_bed(
        porous.base_angle, c["kappa"], c["eps"], t_eval=t_si / c["T"],
        wall_stress=dynamics.step(c["stress"] * tau, 0.0, 0.1 / c["T"]),
        flow_rate=lambda tp: c["q"] * flow(tp * c["T"]), gamma=porous.drag_ratio,
    )  # fmt: skip
    assert run.success and ref.success and math.isnan(run.hair_density)
    np.testing.assert_allclose(run.wall_shear_stress[-1], tau, rtol=1e-12)
    for series, expected in (
        (run.tip_deflection, porous.length * ref.tip_deflection),
        (run.flow_rate, ref.flow_rate / c["q"]),
        (run.pressure_gradient, ref.pressure / c["pi"]),
        (run.wall_velocity, ref.wall_speed / c["omega2"]),
    ):
        # the callable's samples differ by rounding (t/T against t' at the same points): the
        # adaptive runs' paths differ within the integrator's tolerance (rtol 1e-8)
        np.testing.assert_allclose(series, expected, rtol=0, atol=1e-7 * np.max(np.abs(expected)))


@pytest.mark.parametrize("model", ["porous", "dense"])
def test_constant_drive_ends_at_the_static_porous_state(model):
    """A step of the wall speed and of G from rest at times[0] relaxes to HairBed.deform's
    porous state (the dense bed: the porous model of its geometry) within 1e-10 (the
    issue's steady limit; the brief asks 1e-8)."""
    bed = hairbed.HairBed(**KW, model=model)
    porous = hairbed.HairBed(**KW, model="porous")
    v, g = 0.05, 2e4
    t_end = 40.0 * _scales(bed, None)["T"]
    run = bed.simulate([0.0, t_end], velocity=v, pressure_gradient=g, rtol=1e-10, atol=1e-12)
    st = porous.deform(v, pressure_gradient=g)
    assert run.success, run.message
    assert run.tip_deflection[0] == pytest.approx(porous.length * math.sin(porous.base_angle))
    top = float(st.wall_shear_stress) - g * (porous.channel_height - float(st.tip_height))
    for got, want in (
        (run.tip_deflection[-1], st.tip_deflection),
        (run.tip_height[-1], st.tip_height),
        (run.flow_rate[-1], st.flow_rate),
        (run.wall_shear_stress[-1], top),
    ):
        assert abs(float(got) - float(want)) <= 1e-10 * abs(float(want))  # measured 1.4e-14


BAD = [
    (dict(times=[0.0, 1.0, 0.5], velocity=0.1), ValueError, "times"),
    (dict(times=[], velocity=0.1), ValueError, "times"),
    (dict(times=[0.0, np.nan], velocity=0.1), ValueError, "times"),
    (dict(times=[0.0, 1.0], velocity=0.1, wall_shear_stress=1.0), ValueError, "velocity"),
    (dict(times=[0.0, 1.0], pressure_gradient=1.0, flow_rate=1e-6), ValueError, "flow_rate"),
    (dict(times=[0.0, 1.0], velocity="fast"), TypeError, "velocity"),
    (dict(times=[0.0, 1.0], velocity=np.inf), ValueError, "velocity"),
    (dict(times=[0.0, 1.0], velocity=1e30), ValueError, "velocity"),
    (dict(times=[0.0, 1.0], pressure_gradient=lambda t: t / 0.0), ValueError, "pressure_gradient"),
    (dict(times=[0.0, 1.0], flow_rate=lambda t: t[:3]), ValueError, "flow_rate"),
    (dict(times=[0.0, 1.0], velocity=0.1, hair_density=-1.0), ValueError, "hair_density"),
    (dict(times=[0.0, 1.0], velocity=0.1, num=3), ValueError, "num"),
    (dict(times=[0.0, 1.0], velocity=0.1, rtol=0.0), ValueError, "rtol"),
]


def test_bad_input_is_named():
    bed = hairbed.HairBed(**KW, model="porous")
    for kw, err, name in BAD:
        with np.errstate(all="ignore"), pytest.raises(err, match=name):
            bed.simulate(**kw)  # type: ignore[arg-type]
    from hairbed.bed_simulation import simulate

    with pytest.raises(TypeError, match="bed"):
        simulate("bed", [0.0, 1.0], velocity=0.1)  # type: ignore[arg-type]
