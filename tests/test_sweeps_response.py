"""Sweeps of a pillar sensor in time (issue 31): hairbed.sweeps.response_sweep and
amplitude_sweep.

References: the nonlinear pillar in time (Radau IIA on the collocation ODE) against the
linear transfer function in the frequency domain (the pencil, itself checked against the
Krylov-function cantilever in tests/test_dynamics_linear.py): two different solutions of the
same model, whose first harmonic per amplitude must approach H with an error O(a^2) (the
ratio 4 for a doubled amplitude). The linear sweep's grid against the pillar's own
frequency_response at each of its points (a sweep tiles, it does not compute anew), chunked
bitwise eager, and its netCDF round trip.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hairbed
from hairbed.sweeps import amplitude_sweep, response_sweep

pytest.importorskip("xarray")
pytest.importorskip("dask")

RHO_S = 1000.0


def _pillar(fluid: str, **kw: object) -> hairbed.Pillar:
    return hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid=fluid, **kw)


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_response_sweep_grid_chunks_and_netcdf(tmp_path: object) -> None:
    xr = pytest.importorskip("xarray")
    pytest.importorskip("netCDF4")
    p = _pillar("water", profile="wall-law")
    f = np.array([0.0, 10.0, 100.0, 300.0])
    tau = np.array([0.0, 0.5, 2.0])
    ds = response_sweep(p, f, tau, pillar_density=RHO_S)
    assert ds["magnitude"].dims == ("wall_shear_stress", "frequency")
    for k, t in enumerate(tau):
        r = p.frequency_response(f, wall_shear_stress=float(t), pillar_density=RHO_S)
        h = ds["response_real"].values[k] + 1j * ds["response_imag"].values[k]
        assert np.array_equal(h, r.response) and r.status == 0
        assert np.array_equal(ds["magnitude"].values[k], np.abs(r.response))
    assert np.all(ds["status"].values == 0)
    for name in (*ds.data_vars, *ds.coords):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    lazy = response_sweep(p, f, tau, pillar_density=RHO_S, chunks={"wall_shear_stress": 2})
    assert lazy["magnitude"].chunks is not None
    assert lazy.compute().equals(ds)  # chunked along the stress is bitwise eager
    # a chunk of frequencies is its own band (LU or Schur form): the same to rounding
    band = response_sweep(p, f, tau, pillar_density=RHO_S, chunks={"frequency": 3}).compute()
    got = band["response_real"] + 1j * band["response_imag"]
    want = ds["response_real"] + 1j * ds["response_imag"]
    assert float(np.max(np.abs(got - want) / np.abs(want))) <= 1e-12
    path = tmp_path / "response.nc"  # type: ignore[operator]
    ds.to_netcdf(path)
    back = xr.open_dataset(path)
    assert back.equals(ds) and back["magnitude"].attrs["units"] == "m/Pa"
    back.close()
    one = response_sweep(p, 100.0, 1.0, pillar_density=RHO_S)  # scalars: scalar coordinates
    assert one["magnitude"].dims == () and float(one["frequency"]) == 100.0
    with pytest.raises(ValueError, match=r"frequency must be >= 0 Hz.*index 1"):
        response_sweep(p, [1.0, -1.0], pillar_density=RHO_S)
    with pytest.raises(ValueError, match="pillar_density"):
        response_sweep(p, [1.0])
    with pytest.raises(ValueError, match="drag"):
        response_sweep(p, [1.0], pillar_density=RHO_S, drag="stokes")


def test_amplitude_sweep_tends_to_the_linear_response() -> None:
    """A glycerol pillar at 1 Pa (x1 = 0.05 L): over a 2 x 2 grid, chunked one amplitude a
    block, the first harmonic per amplitude differs from H by O(a^2): the error's ratio for
    a doubled amplitude is 4; the mean shift grows like a^2 and the distortion like a."""
    p = _pillar("glycerol")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        ds = amplitude_sweep(
            p, [0.05, 0.1], [0.5, 2.0], wall_shear_stress=1.0, pillar_density=RHO_S, chunks=1
        )
    assert ds["harmonic_gain"].chunks is not None
    ds = ds.compute()
    assert ds["harmonic_gain"].dims == ("amplitude", "frequency")
    assert np.all(ds["status"].values == 0), ds["status"].values
    assert np.all(ds["periodicity"].values <= 1e-4 * ds["harmonic_gain"].values * 0.05)
    h1 = ds["harmonic_gain"].values * np.exp(1j * ds["harmonic_phase"].values)
    h = ds["linear_gain"].values * np.exp(1j * ds["linear_phase"].values)
    err = np.abs(h1 - h) / np.abs(h)
    assert np.all(err <= 1e-4), err
    assert np.all(np.abs(err[1] / err[0] - 4.0) <= 0.2), err[1] / err[0]
    shift = ds["mean_shift"].values
    assert np.all(np.abs(shift[1] / shift[0] - 4.0) <= 0.2), shift
    dist = ds["distortion"].values
    assert np.all(np.abs(dist[1] / dist[0] - 2.0) <= 0.1), dist
    for name in (*ds.data_vars, *ds.coords):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
    with pytest.raises(ValueError, match="wall-law"):
        amplitude_sweep(_pillar("water", profile="wall-law"), 0.1, 1.0, pillar_density=RHO_S)
    with pytest.raises(ValueError, match=r"amplitude must be > 0.*index 0"):
        amplitude_sweep(p, [0.0, 1.0], 1.0, pillar_density=RHO_S)
    with pytest.raises(ValueError, match="periods"):
        amplitude_sweep(p, 0.1, 1.0, pillar_density=RHO_S, periods=1)


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_cli_sweeps(tmp_path: object, capsys: pytest.CaptureFixture[str]) -> None:
    """``hairbed response --mean-stresses/--amplitudes``: the library's datasets, to a
    netCDF file or as a long CSV on stdout; bad combinations one error line, status 2."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("netCDF4")
    from hairbed.cli import main

    water = ["--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6"]
    out = tmp_path / "map.nc"  # type: ignore[operator]
    args = ["response", "--pillar-density", "970", "--frequencies", "10,100,300"]
    assert (
        main(
            [*args, "--mean-stresses", "0,1", "--chunks", "1", "--out", str(out)]
            + [*water, "--fluid", "water"]
        )
        == 0
    )
    got = xr.open_dataset(out)
    want = response_sweep(_pillar("water"), [10.0, 100.0, 300.0], [0.0, 1.0], pillar_density=970.0)
    # --chunks 1 cuts the frequencies too: each its own band, the same to rounding
    assert np.allclose(got["magnitude"].values, want["magnitude"].values, rtol=1e-12, atol=0)
    assert got["magnitude"].attrs["units"] == "m/Pa"
    # the phase in degrees, as the plain response's (it was rad in the sweep alone)
    assert got["phase"].attrs["units"] == "deg"
    assert np.allclose(got["phase"].values, np.degrees(want["phase"].values), rtol=1e-12,
                       atol=1e-12)  # fmt: skip
    got.close()
    capsys.readouterr()
    glyc = [*water, "--fluid", "glycerol", "--drag-model", "quasi-steady"]
    assert (
        main(
            [
                *args[:3],
                "--frequencies",
                "1",
                "--amplitudes",
                "0.1",
                "--wall-shear-stress",
                "1",
                *glyc,
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    assert "harmonic_gain" in text.splitlines()[0]
    assert main([*args, "--amplitudes", "0.1", *water, "--fluid", "water"]) == 2
    assert "quasi-steady" in capsys.readouterr().err
    assert main([*args, "--chunks", "2", *water, "--fluid", "water"]) == 2
    assert "--chunks" in capsys.readouterr().err
