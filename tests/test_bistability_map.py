"""The exact three-state region: a grid of omega^2 undercounts it, the map of folds does not.

A sweep of 200 values of omega^2 over a (theta0, eps) grid, counting the cells where some
omega^2 has three physical states, misses the windows narrower than its step near the cusp.
``branches.bistable_window`` on arrays and ``hairbed bistability --map`` give the window at
every cell from its folds; here they are checked cell by cell against the naive numpy
implementation of the folds (tests/naive, which shares no code with the solver), against
``solve_all`` inside and just outside each window, and against the cusp where there is none.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from naive import naive_from_parameter
from naive.roots import critical_points
from tolerances import RTOL

import hairbed
from hairbed.branches import BistableWindow, bistable_window, cusp, folds
from hairbed.cli import main

xr = pytest.importorskip("xarray")

ROOT = Path(__file__).resolve().parents[1]
#: The map of the trap: base angles leaning into the flow, tight channels.
THETA0 = np.linspace(-1.5, -0.5, 21)
EPS = np.linspace(0.5, 0.99, 21)
#: The 200-point grid of forcing a user sweeps (log-spaced over the windows' range).
OMEGA2 = np.geomspace(0.01, 10.0, 200)


def _physical_count(omega2: float, eps: float, theta0: float) -> int:
    return sum(1 for s in hairbed.solve_all(omega2, eps, theta0) if s.physical)


@pytest.fixture(scope="module")
def window() -> BistableWindow:
    return bistable_window(EPS[None, :], THETA0[:, None])


def test_a_grid_of_forcing_undercounts_what_the_map_counts_exactly(window):
    """The trap: the grid finds three states in fewer cells than there are."""
    grid = hairbed.solve(OMEGA2[:, None, None], EPS[None, None, :], THETA0[None, :, None])
    seen = np.any(np.asarray(grid.n_roots) == 3, axis=0)
    exists = window.exists
    assert exists.shape == (THETA0.size, EPS.size)
    # measured: the grid sees 109 of the 121 three-state cells of this map
    assert int(seen.sum()) < int(exists.sum())
    assert not np.any(seen & ~exists)  # whatever the grid sees is in the map
    missed = exists & ~seen
    # the cells it misses are those whose window falls between two grid values
    for i, j in zip(*np.nonzero(missed)):
        lo, hi = window.lower[i, j], window.upper[i, j]
        assert not np.any((OMEGA2 > lo) & (OMEGA2 < hi))
    assert np.all(window.width[missed] < (OMEGA2[1] / OMEGA2[0] - 1.0) * window.upper[missed])


def test_every_cell_of_the_map_is_exact(window):
    """Inside each window three physical states, just outside one; no window: below the cusp."""
    exists = window.exists
    for i, j in zip(*np.nonzero(exists)):
        e, th = EPS[j], THETA0[i]
        lo, hi = window.lower[i, j], window.upper[i, j]
        assert 0.0 < lo < hi and window.width[i, j] == hi - lo
        assert window.n_states[i, j] == 3
        assert _physical_count(0.5 * (lo + hi), e, th) == 3, (th, e)
        step = 1e-3 * (hi - lo)
        assert _physical_count(lo - step, e, th) == 1
        assert _physical_count(hi + step, e, th) == 1
    eps_c = np.asarray(cusp(THETA0))
    for i, j in zip(*np.nonzero(~exists)):
        assert EPS[j] <= eps_c[i]  # the cusp's own search (scipy brackets), not the folds
        assert np.isnan(window.lower[i, j]) and np.isnan(window.upper[i, j])
        assert np.isnan(window.width[i, j]) and window.n_states[i, j] == 1
    assert np.array_equal(exists, EPS[None, :] > eps_c[:, None])


def test_the_folds_agree_with_the_naive_implementation(window):
    e, th = np.meshgrid(EPS, THETA0)
    t = critical_points(e.ravel(), th.ravel(), 1, 0)
    w = naive_from_parameter(t, e.ravel()[:, None], th.ravel()[:, None])["omega2"]
    lower = np.nanmin(np.where(np.isnan(t), np.inf, w), axis=1)
    upper = np.nanmax(np.where(np.isnan(t), -np.inf, w), axis=1)
    two = np.sum(~np.isnan(t), axis=1) == 2
    assert np.array_equal(two.reshape(e.shape), window.exists)
    np.testing.assert_allclose(window.lower.ravel()[two], lower[two], rtol=RTOL)
    np.testing.assert_allclose(window.upper.ravel()[two], upper[two], rtol=RTOL)


def test_arrays_are_the_scalar_windows_bitwise(window):
    for i, j in [(0, 0), (0, 1), (5, 17), (20, 20), (12, 3)]:
        one = bistable_window(EPS[j], THETA0[i])
        assert isinstance(one.lower, float) and isinstance(one.exists, bool)
        assert isinstance(one.n_states, int)
        f = folds(EPS[j], THETA0[i])
        if one.exists:
            assert (one.lower, one.upper) == (f.lower.omega2, f.upper.omega2)
            assert one.lower == window.lower[i, j] and one.upper == window.upper[i, j]
        else:
            assert f.lower is None and np.isnan(window.lower[i, j])


def test_shapes_broadcast_and_bad_input_names_the_parameter_and_index():
    w = bistable_window([[0.95], [0.5]], [-1.0, 0.0, -1.5])
    assert w.lower.shape == (2, 3) and w.exists.dtype == bool
    assert w.exists.tolist() == [[True, False, True], [False, False, False]]
    assert bistable_window(np.empty(0), -1.0).lower.shape == (0,)
    with pytest.raises(ValueError, match=r"eps must lie in \[0, 1\).*index 2"):
        bistable_window([0.5, 0.9, 1.0], -1.0)
    with pytest.raises(ValueError, match=r"theta0 must lie in \(-pi/2, pi/2\).*index \(1, 0\)"):
        bistable_window(0.9, [[-1.0], [-2.0]])
    with pytest.raises(ValueError, match=r"^eps and theta0 must broadcast together"):
        bistable_window([0.5, 0.9], [-1.0, -1.2, -1.4])


def test_the_map_dataset_is_labelled_from_the_variables_table(window):
    from hairbed._variables import WINDOW, cf_attrs

    ds = hairbed.sweeps.bistability_map(THETA0, EPS)
    assert dict(ds.sizes) == {"theta0": THETA0.size, "eps": EPS.size}
    assert list(ds.data_vars) == list(WINDOW)
    for name in WINDOW:
        assert {k: ds[name].attrs[k] for k in ("units", "long_name")} == cf_attrs(WINDOW[name])
    assert ds["theta0"].attrs["units"] == "rad" and ds["eps"].attrs["units"] == "1"
    np.testing.assert_array_equal(ds["lower_fold"].values, window.lower)
    np.testing.assert_array_equal(ds["upper_fold"].values, window.upper)
    assert ds["exists"].dtype == bool and ds["n_states"].dtype == np.int64
    assert ds["cusp_eps"].dims == ("theta0",)
    np.testing.assert_array_equal(ds["cusp_eps"].values, cusp(THETA0))


@pytest.mark.parametrize("ext", [".nc", ".csv", ".zarr", ".parquet"])
def test_cli_map_writes_the_exact_map(ext, tmp_path, capsys, window):
    if ext == ".nc":
        pytest.importorskip("netCDF4")
    if ext == ".zarr":
        pytest.importorskip("zarr")
    if ext == ".parquet":
        pytest.importorskip("pyarrow")
    out = tmp_path / f"map{ext}"
    argv = ["bistability", "--map", "-1.5:-0.5:21", "0.5:0.99:21", "--out", str(out)]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert f"three physical states in {int(window.exists.sum())} of 441 cells" in err
    if ext in (".nc", ".zarr"):
        ds = xr.open_zarr(out) if ext == ".zarr" else xr.open_dataset(out)
        with ds:
            np.testing.assert_array_equal(ds["lower_fold"].values, window.lower)
            assert int(ds["n_states"].sum()) == 3 * int(window.exists.sum()) + int(
                (~window.exists).sum()
            )
            assert ds["width"].attrs["units"] == "1"
        return
    cols, units = hairbed.sweeps.read_table(out)
    assert units["theta0"] == "rad" and units["upper_fold"] == "1"
    np.testing.assert_array_equal(cols["upper_fold"], window.upper.ravel())
    assert int(cols["exists"].sum()) == int(window.exists.sum())


def test_cli_map_refuses_what_does_not_apply(tmp_path, capsys):
    cases = [
        (["--map", "-1", "0.9", "--eps", "0.9"], "--eps does not apply with --map"),
        (["--map", "-1", "0.9", "--json"], "--json does not apply with --map"),
        (["--map", "-1", "0.9", "--out", "m.txt"], "unknown output format '.txt'"),
        (["--map", "-1", "0.9", "--no-compress", "--out", "m.csv"], "--no-compress applies"),
        (["--map", "-1:0:3:updown", "0.9"], "--map THETA0_SPEC: :updown makes a path"),
        (["--map", "-1", "0.5,1.2"], r"eps must lie in [0, 1), got 1.2 (first at index 1)"),
        (["--map", "-1"], "expected 2 arguments"),
        (["--eps", "0.9", "--theta0", "-1", "--out", "m.nc"], "--out applies to --map only"),
        (["--eps", "0.9"], "--theta0 is required (or --map THETA0_SPEC EPS_SPEC)"),
    ]
    for args, message in cases:
        assert main(["bistability", *args]) == 2, args
        err = capsys.readouterr().err
        assert message in err and len(err.splitlines()) == 1, (args, err)
    assert not list(tmp_path.iterdir())


def test_cli_map_csv_on_stdout_and_progress(capsys):
    assert main(["bistability", "--map", "-1.0", "0.5,0.95", "--progress"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("theta0 [rad],eps [1],lower_fold [1],upper_fold [1]")
    rows = [r.split(",") for r in out[1:]]
    assert [r[5] for r in rows] == ["1", "3"] and float(rows[1][2]) == 0.2969598280133206


def test_the_docs_and_help_warn_that_grids_miss_narrow_windows():
    proc = subprocess.run(
        [sys.executable, "-m", "hairbed", "bistability", "--help"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    text = " ".join(proc.stdout.split())
    assert "--map THETA0_SPEC EPS_SPEC" in text and "undercounts" in text
    for doc in ("README.md", "docs/theory.md"):
        body = " ".join((ROOT / doc).read_text(encoding="utf-8").split())
        assert "hairbed bistability --map" in body, doc
        assert "miss" in body and "narrow" in body, doc


def test_the_map_shows_progress_on_long_work(monkeypatch, capsys):
    sweeps = hairbed.sweeps
    monkeypatch.setattr(sweeps, "PROGRESS_DELAY", 0.0)
    ds = sweeps.bistability_map(
        np.linspace(-1.5, -0.5, 70), np.linspace(0.5, 0.99, 70), progress=True
    )
    err = capsys.readouterr().err
    assert "hairbed bistability" in err and "100%" in err and "4.90k" in err
    assert int(ds["exists"].sum()) > 0
    monkeypatch.setattr(sweeps, "PROGRESS_DELAY", 60.0)  # short work prints nothing
    sweeps.bistability_map(THETA0, EPS, progress=True)
    assert capsys.readouterr().err == ""
    with pytest.raises(TypeError, match="progress must be True or False"):
        sweeps.bistability_map(THETA0, EPS, progress=1)
