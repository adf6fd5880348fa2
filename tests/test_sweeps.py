"""hairbed.sweep and HairBed.sweep: labelled grids, chunked = eager bitwise, a dask cluster.

The values are compared bitwise with ``hairbed.solve`` (the issue's contract) and, where a
closed form or an independent reference exists, with that: the hair at rest (omega^2 = 0:
h1 = cos theta0, x1 = sin theta0, stress ratio 1/(1 - eps cos theta0)) and the worked example
of docs/theory.md §3 (omega^2 = 2, eps = 0.5, theta0 = 0; a Taylor-series check at 30+ digits).
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import hairbed
from hairbed import sweeps

xr = pytest.importorskip("xarray")
pytest.importorskip("dask.array")

EXAMPLE = {"xi": 0.847253916541247, "tip_height": 0.732706963462228}
W = np.array([0.0, 0.3, 2.0, 7.5, 40.0])
E = np.array([0.0, 0.5, 0.9])
T = np.array([-1.5, -0.4, 0.0, 0.6])
BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}


def _solve_grid(w, e, t, **kw):
    ww, ee, tt = np.meshgrid(w, e, t, indexing="ij")
    return hairbed.solve(ww, ee, tt, **kw), ee


def _assert_same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    assert a.dtype == b.dtype and a.shape == b.shape
    assert np.array_equal(a, b, equal_nan=True)


def test_grid_dims_coords_and_attributes():
    ds = hairbed.sweep(W, 0.5, T)
    assert tuple(ds.dims) == ("omega2", "theta0")
    assert dict(ds.sizes) == {"omega2": W.size, "theta0": T.size}
    assert ds["eps"].ndim == 0 and float(ds["eps"]) == 0.5  # a scalar coordinate
    _assert_same(ds["omega2"].values, W)
    _assert_same(ds["theta0"].values, T)
    assert list(ds.data_vars) == list(sweeps.VARIABLES)
    for name in [*ds.data_vars, *ds.coords]:
        attrs = ds[name].attrs
        assert attrs["units"] and attrs["long_name"], name
    assert ds["theta0"].attrs["units"] == "rad" and ds["tip_angle"].attrs["units"] == "rad"
    assert ds.attrs["hairbed_version"] == hairbed.__version__
    assert (ds.attrs["branch_sign"], ds.attrs["branch_n"], ds.attrs["root"]) == (1, 0, "low")
    assert ds.attrs["Conventions"].startswith("CF-")
    full = hairbed.sweep(W, E, T, sign=-1, n=1, root="high")
    assert tuple(full.dims) == ("omega2", "eps", "theta0")
    assert (full.attrs["branch_sign"], full.attrs["branch_n"], full.attrs["root"]) == (
        -1,
        1,
        "high",
    )
    assert full["physical"].dtype == bool and full["status"].dtype == np.int64


@pytest.mark.parametrize(
    "kw", [{}, {"sign": -1, "n": 0}, {"sign": 1, "n": 1}, {"root": "high"}, {"root": "mid"}]
)
def test_values_are_bitwise_those_of_solve(kw):
    ds = hairbed.sweep(W, E, T, **kw)
    sol, ee = _solve_grid(W, E, T, **kw)
    for name in sweeps.VARIABLES[:-1]:
        _assert_same(ds[name].values, getattr(sol, name))
    h1 = np.asarray(sol.tip_height)
    _assert_same(ds["stress_ratio"].values, 1.0 / (1.0 - ee * h1))
    # the stress ratio of hairbed.rheology, and scalar solves (the compiled scalar path)
    ref = hairbed.rheology.stress_ratio(
        *np.meshgrid(W, E, T, indexing="ij"), root=kw.get("root", "low")
    )
    if not kw.get("n") and kw.get("sign", 1) == 1:
        _assert_same(ds["stress_ratio"].values, ref)
    for i, j, k in [(2, 1, 2), (4, 2, 0), (1, 0, 3)]:
        one = hairbed.solve(float(W[i]), float(E[j]), float(T[k]), **kw)
        assert ds["xi"].values[i, j, k] == one.xi or (
            math.isnan(one.xi) and np.isnan(ds["xi"].values[i, j, k])
        )


def test_values_against_closed_forms_and_the_worked_example():
    ds = hairbed.sweep(W, E, T)
    rest = ds.sel(omega2=0.0)
    cos_t = np.cos(T)[None, :]
    np.testing.assert_allclose(
        rest["tip_height"].values, np.broadcast_to(cos_t, (E.size, T.size)), rtol=1e-15
    )
    np.testing.assert_allclose(
        rest["stress_ratio"].values, 1.0 / (1.0 - E[:, None] * cos_t), rtol=1e-15
    )
    np.testing.assert_allclose(rest["tip_displacement"].values, 0.0, atol=0.0)
    point = ds.sel(omega2=2.0, eps=0.5, theta0=0.0)
    for key, value in EXAMPLE.items():
        assert float(point[key]) == pytest.approx(value, rel=1e-13)


@pytest.mark.parametrize("chunks", [1, 2, {"eps": 1}, {"omega2": 3, "theta0": 2}])
def test_chunked_equals_eager_bitwise(chunks):
    eager = hairbed.sweep(W, E, T)
    lazy = hairbed.sweep(W, E, T, chunks=chunks)
    assert lazy["xi"].chunks is not None  # dask-backed
    assert all(lazy[v].chunks is not None for v in lazy.data_vars)
    done = lazy.compute()
    for name in [*eager.data_vars, *eager.coords]:
        _assert_same(done[name].values, eager[name].values)
    assert done.attrs == eager.attrs


def test_scalar_inputs_and_one_dimension():
    ds = hairbed.sweep(2.0, 0.5)
    assert dict(ds.sizes) == {}
    assert float(ds["xi"]) == hairbed.solve(2.0, 0.5).xi
    assert float(hairbed.sweep(2.0, 0.5, chunks=4)["xi"].compute()) == float(ds["xi"])
    one = hairbed.sweep(W, 0.9, -1.5, chunks={"omega2": 2}).compute()
    _assert_same(one["xi"].values, hairbed.solve(W, 0.9, -1.5).xi)


@pytest.mark.parametrize(
    ("args", "kw", "words"),
    [
        ((np.ones((2, 2)), 0.5), {}, ["omega2", "1-D", "(2, 2)"]),
        (([], 0.5), {}, ["omega2", "empty"]),
        (([1.0, -1.0], 0.5), {}, ["omega2", "[0, inf)", "index 1"]),
        (([1.0], [0.2, 1.0]), {}, ["eps", "[0, 1)", "index 1"]),
        (([1.0], 0.5, [0.0, 2.0]), {}, ["theta0", "index 1"]),
        (([1.0], 0.5), {"chunks": 0}, ["chunks", ">= 1"]),
        (([1.0], 0.5), {"chunks": {"eps": 2}}, ["chunks", "'eps'", "omega2"]),
        (([1.0], 0.5), {"chunks": "auto"}, ["chunks"]),
        (([1.0], 0.5), {"root": "top"}, ["root"]),
        (([1.0], 0.5), {"sign": 0}, ["sign"]),
    ],
)
def test_bad_input_names_the_parameter(args, kw, words):
    with pytest.raises(ValueError) as err:
        hairbed.sweep(*args, **kw)
    for w in words:
        assert w in str(err.value)
    with pytest.raises(TypeError, match="progress"):
        hairbed.sweep(1.0, 0.5, progress="yes")


def test_import_hairbed_imports_neither_xarray_nor_dask():
    code = (
        "import sys, hairbed\n"
        "hairbed.solve(2.0, 0.5)\n"
        "bad = [m for m in ('xarray', 'dask', 'distributed', 'pyarrow', 'netCDF4', 'zarr') "
        "if m in sys.modules]\n"
        "assert not bad, bad\n"
        "assert hairbed.sweep is hairbed.sweeps.sweep\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


def test_progress_bar_on_stderr(monkeypatch, capsys):
    monkeypatch.setattr(sweeps, "PROGRESS_DELAY", 0.0)
    hairbed.sweep(W, E, T, progress=True)
    err = capsys.readouterr().err
    assert "hairbed sweep" in err and "100%" in err
    hairbed.sweep(W, E, T, chunks=2, progress=True).compute()
    err = capsys.readouterr().err
    assert "hairbed sweep" in err and "100%" in err
    hairbed.sweep(W, E, T, chunks=2).compute()
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sweeps, "PROGRESS_DELAY", 60.0)  # short sweeps print nothing
    hairbed.sweep(W, E, T, progress=True)
    assert capsys.readouterr().err == ""


def test_bed_sweep_in_si_units():
    bed = hairbed.HairBed(**BED, base_angle=0.3)
    v = np.linspace(-0.4, 0.4, 9)
    ds = bed.sweep(v)
    st = bed.deform(v)
    assert tuple(ds.dims) == ("velocity",)
    for name in ("tip_deflection", "tip_height", "tip_angle", "wall_shear_stress",
                 "force_per_hair", "stress_ratio", "omega2", "direction"):  # fmt: skip
        _assert_same(ds[name].values, getattr(st, name))
    _assert_same(ds["theta0"].values, st.solution.theta0)
    _assert_same(ds["xi"].values, st.solution.xi)
    _assert_same(ds["scaled_tip_height"].values, st.solution.tip_height)
    # independent: the SI fields from the dimensionless ones by the formulas of theory.md §7
    h1 = np.asarray(st.solution.tip_height)
    gap = BED["channel_height"] - h1 * BED["length"]
    np.testing.assert_allclose(ds["tip_height"].values, h1 * 1e-3, rtol=1e-15)
    np.testing.assert_allclose(ds["wall_shear_stress"].values, v / gap, rtol=1e-14)
    rest = ds.sel(velocity=0.0, method="nearest")
    assert float(rest["tip_height"]) == pytest.approx(1e-3 * math.cos(0.3), rel=1e-12)
    units = {k: ds[k].attrs["units"] for k in ds.variables}
    assert units["velocity"] == "m s-1" and units["tip_deflection"] == "m"
    assert units["wall_shear_stress"] == "Pa" and units["force_per_hair"] == "N"
    assert all(ds[k].attrs["long_name"] for k in ds.variables)
    assert ds.attrs["bed_length"] == 1e-3 and ds.attrs["bed_base_angle"] == 0.3
    assert ds.attrs["hairbed_version"] == hairbed.__version__
    lazy = bed.sweep(v, chunks=4, root="high")
    assert lazy["xi"].chunks is not None
    done = lazy.compute()
    high = bed.sweep(v, root="high")
    for name in ds.variables:
        _assert_same(done[name].values, high[name].values)


def test_a_bed_sweep_holds_every_hairstate_field():
    from hairbed._variables import SI

    bed = hairbed.HairBed(**BED, base_angle=-0.2, density=1260.0)
    v = np.array([-0.05, 0.0, 0.02, 0.1])
    ds, st = bed.sweep(v), bed.deform(v)
    for name, var in SI.items():
        _assert_same(ds[name].values, getattr(st, name))
        assert ds[name].attrs["units"] == var.units, name
    # independent: the gap's Reynolds number rho |v| (H - h1 L) / eta from its definition
    gap = BED["channel_height"] - np.asarray(st.solution.tip_height) * BED["length"]
    np.testing.assert_allclose(ds["reynolds_number"].values, 1260.0 * np.abs(v) * gap, rtol=1e-15)
    assert np.all(np.isnan(hairbed.HairBed(**BED).sweep(v)["reynolds_number"].values))
    with pytest.raises(ValueError, match="velocity"):
        bed.sweep(np.ones((2, 2)))
    with pytest.raises(ValueError, match="chunks"):
        bed.sweep(v, chunks={"omega2": 2})


def test_a_local_cluster_computes_the_same():
    distributed = pytest.importorskip("distributed")
    eager = hairbed.sweep(W, E, T)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:  # fmt: skip
        done = hairbed.sweep(W, E, T, chunks={"omega2": 2}).compute()
        # each worker process loaded (or compiled) the kernels itself and solved blocks
        info = client.run(lambda: (__import__("os").getpid(), hairbed._core._jit.CACHE_ENABLED))
        assert len({pid for pid, _ in info.values()}) == 2
        bed = hairbed.HairBed(**BED)
        v = np.linspace(-0.2, 0.3, 6)
        si = bed.sweep(v, chunks=2).compute()
    for name in eager.variables:
        _assert_same(done[name].values, eager[name].values)
    for name in si.variables:
        _assert_same(si[name].values, bed.sweep(v)[name].values)
