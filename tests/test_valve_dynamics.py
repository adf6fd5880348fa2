"""Valves and pumps in time (issue 31 section 3): hairbed.valve_dynamics.

References: the steady valve curve (hairbed.valve.valve_curve, the static solver: a code path
that shares nothing with the integrator), the exact scaling of the model with the viscosity
(T and the flow's scale change, the dimensionless problem does not), and the symmetry of an
upright bed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hairbed import HairBed
from hairbed.valve import valve_curve
from hairbed.valve_dynamics import bed_time_scales, pump_net_flow, valve_switching


def _bed(viscosity: float = 1.0, base_angle: float = 0.5, model: str = "porous") -> HairBed:
    return HairBed(
        length=1e-3,
        radius=50e-6,
        youngs_modulus=1e6,
        channel_height=2e-3,
        viscosity=viscosity,
        spacing=250e-6,
        base_angle=base_angle,
        model=model,
    )


LENGTH = 0.01  # the channel [m]


@pytest.fixture(scope="module")
def switch() -> object:
    return valve_switching(_bed(), 300.0, LENGTH, duration=None, num_times=401)


def test_switching_settles_on_the_steady_valve_curve(switch):
    r = switch
    assert r.status == 0, r.message
    q1 = float(valve_curve(_bed(), 300.0, LENGTH).flow_rate)
    q0 = float(valve_curve(_bed(), 0.0, LENGTH).flow_rate)
    assert q0 == pytest.approx(0.0, abs=1e-20)
    assert r.flow_rate[-1] == pytest.approx(q1, rel=1e-7)
    assert 0.0 <= r.rise_time < r.time[-1]
    frac = (r.flow_rate - q0) / (q1 - q0)
    k = np.searchsorted(r.time, r.rise_time)
    assert frac[k] >= 0.9 - 1e-12 and (k == 0 or frac[k - 1] < 0.9)
    # the settling time: within 10 % of the change from there on, not just before
    j = np.searchsorted(r.time, r.settling_time)
    assert r.rise_time <= r.settling_time < r.time[-1]
    assert np.all(np.abs(r.flow_rate[j:] - q1) <= 0.1 * abs(q1 - q0) + 1e-12 * abs(q1))
    assert j == 0 or abs(r.flow_rate[j - 1] - q1) > 0.1 * abs(q1 - q0)


def test_switching_scales_exactly_with_the_viscosity(switch):
    """Twice the viscosity: T doubles, the load Pi and kappa stay, the flow halves."""
    r2 = valve_switching(_bed(viscosity=2.0), 300.0, LENGTH, num_times=401)
    assert r2.time_scale == pytest.approx(2.0 * switch.time_scale, rel=1e-14)
    assert r2.settling_time == pytest.approx(2.0 * switch.settling_time, rel=1e-9)
    np.testing.assert_allclose(2.0 * r2.flow_rate, switch.flow_rate, rtol=1e-7, atol=0)


def test_dense_bed_runs_the_porous_model_of_its_geometry():
    dense, porous = _bed(model="dense"), _bed()
    assert bed_time_scales(dense) == bed_time_scales(porous)


def test_pump_net_flow_tends_to_the_quasi_static_rectification():
    """f -> 0: the net flow of the periodic state -> the phase average of the valve curve,
    with an error falling like f^2 (the lag's first order is odd in the drop and averages
    out; measured 1.8e-6, 1.0e-4, 1.0e-2 relative at f T = 0.01, 0.1, 1; the errors at f T
    = 0.03, 0.1 lie well above the periodic state's and the integrator's tolerances)."""
    bed = _bed()
    t_scale = bed_time_scales(bed)["time_scale"]
    f = np.array([3e-2, 1e-1]) / t_scale
    res = pump_net_flow(bed, 300.0, f, LENGTH, samples_per_period=32, tol=1e-9, rtol=1e-9)
    assert res.success, res.message
    qs = float(res.quasi_static_net_flow[0])
    # the quasi-static net flow is not zero (the bed leans: a diode) and is positive along
    # the lean (forward flow opens the gap)
    assert qs > 0.0
    err = np.abs(res.net_flow[0] - qs)
    assert err[1] < 2e-4 * abs(qs)
    rate = math.log(err[1] / err[0]) / math.log(10.0 / 3.0)
    assert 1.9 < rate < 2.1, (err, rate)  # measured 1.9995


def test_upright_bed_pumps_nothing():
    bed = _bed(base_angle=0.0)
    t_scale = bed_time_scales(bed)["time_scale"]
    res = pump_net_flow(bed, 300.0, 0.3 / t_scale, LENGTH, samples_per_period=32)
    amp = float(np.max(np.abs(valve_curve(bed, 300.0, LENGTH).flow_rate)))
    assert abs(res.net_flow[0, 0]) < 1e-8 * amp
    assert abs(res.quasi_static_net_flow[0]) < 1e-12 * amp


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"pressure_drop": float("nan")}, "pressure_drop"),
        ({"channel_length": -1.0}, "channel_length"),
        ({"num_times": 2}, "num_times"),
        ({"duration": 0.0}, "duration"),
        ({"rtol": 1.0}, "rtol"),
        ({"hair_density": -1.0}, "hair_density"),
        ({"pressure_drop": [1.0, 2.0]}, "pressure_drop"),
        ({"pressure_drop": 1e300}, r"pressure_drop.*channel_length"),
    ],
)
def test_switching_bad_input_is_named(kwargs, match):
    args = {"pressure_drop": 100.0, "channel_length": LENGTH} | kwargs
    with pytest.raises(ValueError, match=match):
        valve_switching(_bed(), **args)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"amplitude": [1.0, -2.0]}, r"amplitude.*index 1"),
        ({"frequency": 0.0}, "frequency"),
        ({"frequency": []}, "frequency"),
        ({"samples_per_period": 4}, "samples_per_period"),
        ({"tol": 0.5}, "tol"),
        ({"max_periods": 1}, "max_periods"),
        ({"frequency": [1.0, 1e-300]}, r"frequency.*index 1"),
        ({"frequency": 1e300}, "frequency"),
        ({"channel_length": 5e-324}, "channel_length"),
    ],
)
def test_pump_bad_input_is_named(kwargs, match):
    args = {"amplitude": 100.0, "frequency": 1.0, "channel_length": LENGTH} | kwargs
    with pytest.raises(ValueError, match=match):
        pump_net_flow(_bed(), **args)


def test_a_realistic_hair_density_on_a_viscous_bed_is_taken():
    """mu ~ 1e-8 (1000 kg/m^3 in 1 Pa s) is below the dynamics' range: run as overdamped,
    the same flow as without it."""
    a = valve_switching(_bed(), 300.0, LENGTH, num_times=5, hair_density=1000.0)
    b = valve_switching(_bed(), 300.0, LENGTH, num_times=5)
    np.testing.assert_array_equal(a.flow_rate, b.flow_rate)


def test_not_a_bed_is_a_type_error():
    with pytest.raises(TypeError, match="bed"):
        valve_switching("bed", 1.0, LENGTH)  # type: ignore[arg-type]


BED_ARGS = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "250e-6",
    "--base-angle", "0.5", "--channel-length", "0.01",
]  # fmt: skip


def test_cli_pump_switch_and_net_flow(capsys):
    from hairbed.cli import main

    assert main(["pump", "--switch", "300", "--num-times", "5", "--json", *BED_ARGS]) == 0
    import json

    doc = json.loads(capsys.readouterr().out)
    q1 = float(valve_curve(_bed(model="dense"), 300.0, LENGTH).flow_rate)
    assert doc["units"]["flow_rate"] == "m^2/s"
    assert doc["status"] == 0 and len(doc["time"]) == 5
    # the dense bed's steady flow differs from the porous model's that the run follows
    assert doc["final_flow_rate"] == pytest.approx(
        float(valve_curve(_bed(), 300.0, LENGTH).flow_rate), rel=1e-12
    )
    assert doc["final_flow_rate"] != pytest.approx(q1, rel=1e-6)
    assert main(["pump", "--amplitudes", "300", "--frequencies", "0.01,0.1", *BED_ARGS]) == 0
    out = capsys.readouterr().out.splitlines()
    header = out.index("amplitude,frequency,net_flow,quasi_static_net_flow,periods,status")
    rows = [line.split(",") for line in out[header + 1 :]]
    assert [float(r[1]) for r in rows] == [0.01, 0.1]
    assert all(r[-1] == "0" for r in rows)


@pytest.mark.parametrize(
    "argv",
    [
        ["pump", *BED_ARGS],
        ["pump", "--switch", "1", "--amplitudes", "1", "--frequencies", "1", *BED_ARGS],
        ["pump", "--amplitudes", "1", *BED_ARGS],
        ["pump", "--switch", "nan", *BED_ARGS],
        ["pump", "--switch", "1", "--num-times", "1", *BED_ARGS],
    ],
)
def test_cli_pump_usage_errors_are_one_line(argv, capsys):
    from hairbed.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hairbed: ")


def test_pump_sweep_chunked_is_the_eager_net_flow(tmp_path):
    from hairbed.valve_dynamics import pump_sweep

    bed = _bed()
    t_scale = bed_time_scales(bed)["time_scale"]
    amps, freqs = np.array([100.0, 300.0]), np.array([0.1]) / t_scale
    direct = pump_net_flow(bed, amps, freqs, LENGTH, samples_per_period=16)
    lazy = pump_sweep(bed, amps, freqs, LENGTH, samples_per_period=16, chunks=1)
    assert lazy["net_flow"].chunks is not None  # dask-backed
    ds = lazy.compute()
    np.testing.assert_array_equal(ds["net_flow"].values, direct.net_flow)
    np.testing.assert_array_equal(ds["quasi_static_net_flow"].values[:, 0],
                                  direct.quasi_static_net_flow)  # fmt: skip
    assert ds["net_flow"].attrs["units"] == "m2 s-1"
    assert ds["frequency"].attrs["units"] == "Hz"
    path = tmp_path / "pump.nc"
    ds.to_netcdf(path)
    import xarray as xr

    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["net_flow"].values, direct.net_flow)
        assert back["amplitude"].attrs["units"] == "Pa"
    with pytest.raises(ValueError, match="amplitude"):
        pump_sweep(bed, [1.0, -1.0], 1.0, LENGTH)
