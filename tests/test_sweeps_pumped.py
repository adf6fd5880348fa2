"""HairBed.sweep with a pump drive: the grid (velocity, drive), CF attributes, files.

The sweep's contract is the state of :meth:`HairBed.deform` at every grid point, bitwise,
eager or chunked; the physics of those states is tested in test_channel_drives and
test_loaded.
"""

from __future__ import annotations

import numpy as np
import pytest

xr = pytest.importorskip("xarray")

from hairbed import HairBed  # noqa: E402
from hairbed.sweeps import write_dataset  # noqa: E402

BED = HairBed(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=0.3,
)
V = np.array([-0.01, 0.0, 0.02])
G = np.array([-3e3, 100.0, 1e4, 3e4])


@pytest.mark.parametrize("chunks", [None, 2])
def test_every_point_is_deform_bitwise(chunks) -> None:
    ds = BED.sweep(V, pressure_gradient=G, chunks=chunks).compute()
    assert ds.tip_deflection.dims == ("velocity", "pressure_gradient")
    for i, v in enumerate(V):
        st = BED.deform(v, pressure_gradient=G)
        np.testing.assert_array_equal(ds.tip_deflection.values[i], st.tip_deflection)
        np.testing.assert_array_equal(ds.flow_rate.values[i], st.flow_rate)
        np.testing.assert_array_equal(ds.pi.values[i], st.solution.pi)
        np.testing.assert_array_equal(ds.status.values[i], st.solution.status)
    assert ds.status.dtype == np.int64 and ds.num.dtype == np.int64
    assert "q" not in ds and "pressure_gradient" not in ds.data_vars


def test_flow_rate_sweep_without_a_wall() -> None:
    q = np.linspace(1e-7, 1e-5, 5)
    ds = BED.sweep(flow_rate=q)
    assert ds.tip_deflection.dims == ("flow_rate",)
    assert float(ds.velocity) == 0.0
    st = BED.deform(flow_rate=q)
    np.testing.assert_array_equal(ds.pressure_gradient.values, st.pressure_gradient)
    assert ds.attrs["drive"] == "flow_rate"


def test_every_variable_has_cf_units_and_a_long_name(tmp_path) -> None:
    ds = BED.sweep(pressure_gradient=G)
    for name in [*ds.data_vars, *ds.coords]:
        assert ds[name].attrs.get("units") and ds[name].attrs.get("long_name"), name
    assert ds.pressure_gradient.attrs["units"] == "Pa m-1"
    assert ds.flow_rate.attrs["units"] == "m2 s-1"
    path = tmp_path / "pumped.nc"
    write_dataset(ds, path)
    back = xr.open_dataset(path)
    np.testing.assert_array_equal(back.tip_deflection.values, ds.tip_deflection.values)
    assert back.tip_deflection.attrs["units"] == "m"


@pytest.mark.parametrize(
    ("kwargs", "error", "pattern"),
    [
        ({}, TypeError, r"needs velocity"),
        ({"pressure_gradient": 1.0, "flow_rate": 1.0}, ValueError, r"at most one"),
        ({"pressure_gradient": [[1.0]]}, ValueError, r"pressure_gradient must be a scalar or"),
        ({"flow_rate": []}, ValueError, r"flow_rate must not be empty"),
        ({"pressure_gradient": [1.0, np.nan]}, ValueError, r"pressure_gradient.*index 1"),
        ({"pressure_gradient": G, "chunks": {"eps": 2}}, ValueError, r"unknown dimension"),
    ],
)
def test_bad_input_is_named(kwargs, error, pattern) -> None:
    with pytest.raises(error, match=pattern):
        BED.sweep(**kwargs)


@pytest.mark.parametrize("chunks", [None, 2])
def test_dimensionless_sweep_with_pi_is_solve_loaded_bitwise(chunks) -> None:
    import hairbed

    w, theta0, pi = np.array([0.0, 0.5, 1.0]), np.array([-0.5, 0.3]), np.array([0.1, 3.0, 10.0])
    ds = hairbed.sweep(w, 0.5, theta0, pi=pi, chunks=chunks).compute()
    assert ds.tip_deflection.dims == ("omega2", "theta0", "pi")
    ww, tt, pp = np.meshgrid(w, theta0, pi, indexing="ij")
    st = hairbed.solve_loaded(ww, 0.5, tt, pi=pp)
    np.testing.assert_array_equal(ds.tip_deflection.values, st.tip_deflection)
    np.testing.assert_array_equal(ds.distributed_load.values, st.distributed_load)
    np.testing.assert_array_equal(ds.status.values, st.status)
    assert ds.attrs["drive"] == "pressure" and ds.pi.attrs["units"] == "1"
    assert "q" not in ds and "pi" not in ds.data_vars


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"pi": 1.0, "q": 1.0}, r"at most one of pi and q"),
        ({"pi": 1.0, "sign": -1}, r"physical branch"),
        ({"pi": [1.0, np.inf]}, r"pi.*index 1"),
        ({"q": [[1.0]]}, r"q must be a scalar or"),
    ],
)
def test_dimensionless_bad_input_is_named(kwargs, pattern) -> None:
    import hairbed

    with pytest.raises(ValueError, match=pattern):
        hairbed.sweep(0.5, 0.5, 0.0, **kwargs)


def test_pi_needs_a_channel() -> None:
    import hairbed

    with pytest.raises(ValueError, match=r"pi != 0 needs eps > 0"):
        hairbed.sweep(0.5, [0.0, 0.5], 0.0, pi=1.0)
