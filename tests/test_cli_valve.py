"""``hairbed valve``: the valve curve and the diodicity on the command line."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hairbed import HairBed
from hairbed.cli import main
from hairbed.valve import diodicity, valve_curve, valve_states

BED_KW = dict(
    length=1.8e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=1.0,
)
BED_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in BED_KW.items()]


def _run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(["valve", *args, *BED_ARGS])
    out, err = capsys.readouterr()
    return status, out, err


def test_curve_json_is_the_library_curve(capsys) -> None:
    args = ("--pressure-drop=-500,50,500", "--channel-length=0.01", "--json")
    status, out, err = _run(capsys, *args)
    assert status == 0 and err == ""
    doc = json.loads(out)
    curve = valve_curve(HairBed(**BED_KW), [-500.0, 50.0, 500.0], 0.01)
    got = [row["flow_rate"] for row in doc["curve"]]
    np.testing.assert_array_equal(got, curve.flow_rate)
    assert [row["status"] for row in doc["curve"]] == [0, 0, 0]


def test_diodicity_table(capsys) -> None:
    status, out, err = _run(capsys, "--pressure-drop=200", "--channel-length=0.01", "--diodicity")
    assert status == 0 and err == ""
    d = diodicity(HairBed(**BED_KW), 200.0, 0.01)
    line = out.strip().splitlines()[-1].split()
    assert float(line[1]) == pytest.approx(d.diodicity, rel=1e-5)
    assert d.diodicity > 1.0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--pressure-drop=1", "--channel-length=0"], "--channel-length must be > 0"),
        (["--pressure-drop=1:2:0", "--channel-length=0.01"], "--pressure-drop"),
        (["--channel-length=0.01"], "--pressure-drop"),
    ],
)
def test_errors_are_one_line(capsys, args: list[str], message: str) -> None:
    status, out, err = _run(capsys, *args)
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and message in err


def test_needs_a_bed(capsys) -> None:
    status = main(["valve", "--pressure-drop=1", "--channel-length=0.01"])
    _, err = capsys.readouterr()
    assert status == 2 and "needs the physical inputs of a bed" in err


#: A bed whose valve is bistable at a set flow rate (eps = 0.8, base angle -1.2: the flow
#: window of tests/data/loaded_mpmath.json, 0.0764 < q < 0.2138).
BISTABLE_KW = {**BED_KW, "length": 1.6e-3, "base_angle": -1.2}
BISTABLE_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in BISTABLE_KW.items()]
FLOWS = [0.0, 5e-7, 1e-6, 1.5e-6, 2.5e-6]


def _run_bistable(capsys, *args: str) -> tuple[int, str, str]:
    status = main(["valve", *args, "--channel-length=0.01", *BISTABLE_ARGS])
    out, err = capsys.readouterr()
    return status, out, err


@pytest.fixture(scope="module")
def states():
    return valve_states(HairBed(**BISTABLE_KW), 0.01, flow_rate=FLOWS)


def test_states_table_lists_every_state(capsys, states) -> None:
    status, out, err = _run_bistable(capsys, "--flow-rate=" + ",".join(map(str, FLOWS)))
    assert status == 0 and err == ""
    lines = out.splitlines()
    rows = lines[2 : 2 + len(FLOWS)]
    for i, row in enumerate(rows):
        cells = row.split()
        assert int(cells[1]) == states.count[i] and int(cells[2]) == states.count_stable[i]
        drops = [float(c) for c in cells[3::2]]
        marks = cells[4::2]
        np.testing.assert_allclose(drops, states.pressure_drop[i, : states.count[i]], rtol=1e-5)
        assert marks == ["s" if x else "u" for x in states.stable[i, : states.count[i]]]
    assert [int(r.split()[1]) for r in rows] == [1, 1, 3, 3, 1]
    assert "folds: 2" in out
    assert sum(line.strip().startswith(("up:", "down:")) for line in lines) == 2


def test_states_json_is_the_library(capsys, states) -> None:
    status, out, err = _run_bistable(
        capsys, "--states", "--flow-rate=" + ",".join(map(str, FLOWS)), "--json"
    )
    assert status == 0 and err == ""
    doc = json.loads(out)
    assert doc["drive"] == "flow" and doc["status"] == 0 and doc["units"]["pressure_drop"] == "Pa"
    assert [p["count"] for p in doc["points"]] == states.count.tolist()
    got = [s["pressure_drop"] for p in doc["points"] for s in p["states"]]
    want = states.pressure_drop[np.isfinite(states.pressure_drop)]
    np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal([f["flow_rate"] for f in doc["folds"]], states.fold_flow_rate)
    (up,), (down,) = doc["jumps"]["up"], doc["jumps"]["down"]
    assert up["drive_value"] == states.ramp_up.jumps[0].drive_value
    assert down["pressure_drop_after"] == states.ramp_down.jumps[0].pressure_drop_after


def test_states_files_have_units(capsys, tmp_path, states) -> None:
    xr = pytest.importorskip("xarray")
    from hairbed.sweeps import read_table

    csv = tmp_path / "valve.csv"
    status, out, err = _run_bistable(capsys, "--flow-rate=" + ",".join(map(str, FLOWS)),
                                     f"--out={csv}")  # fmt: skip
    assert status == 0 and out == "" and "2 folds, 2 jumps" in err
    cols, units = read_table(csv)
    assert units["pressure_drop"] == "Pa" and units["values"] == "m^2/s"
    assert units["tip_height"] == "m"
    got = cols["pressure_drop"].reshape(len(FLOWS), -1)
    np.testing.assert_array_equal(got, states.pressure_drop)
    nc = tmp_path / "valve.nc"
    status, _, _ = _run_bistable(capsys, "--flow-rate=" + ",".join(map(str, FLOWS)),
                                 f"--out={nc}")  # fmt: skip
    assert status == 0
    with xr.open_dataset(nc) as ds:
        assert ds["flow_rate"].attrs["units"] == "m^2/s"
        np.testing.assert_array_equal(ds["count"].values, states.count)
        np.testing.assert_array_equal(ds.attrs["fold_flow_rate_m2_per_s"], states.fold_flow_rate)


def test_states_partial_coverage_is_said(capsys) -> None:
    status, out, err = _run_bistable(capsys, "--flow-rate=0,3e-6", "--max-steps=2")
    assert status == 0 and "(not reached)" in out
    assert len(err.strip().splitlines()) == 1 and "iteration limit reached" in err
    assert err.startswith("hairbed: warning: ")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--pressure-drop=1", "--velocity=1"], "--velocity applies to --states only"),
        (["--pressure-drop=1", "--out=x.csv"], "--out applies to --states only"),
        (["--pressure-drop=1", "--flow-rate=1e-6"], "give one of --pressure-drop"),
        (["--flow-rate=1e-6", "--diodicity"], "--diodicity does not apply"),
        (["--flow-rate=1e-6", "--json", "--out=x.csv"], "--json does not apply with --out"),
        (["--flow-rate=1e-6", "--max-steps=0"], "--max-steps must be in"),
        (["--flow-rate=1e-6", "--out=x.txt"], "unknown output format"),
    ],
)
def test_states_errors_are_one_line(capsys, args: list[str], message: str) -> None:
    status, out, err = _run_bistable(capsys, *args)
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and message in err


# -- issue 33: hairbed valve --plot -------------------------------------------------------------


@pytest.mark.parametrize(
    "mode", [["--pressure-drop=+-10:100:2:log"], ["--pressure-drop=10,100", "--diodicity"],
             ["--flow-rate=0:3e-6:5"]],
)  # fmt: skip
def test_valve_plot_writes_the_figure(tmp_path, capsys, mode):
    from hairbed.cli import main

    path = tmp_path / "valve.png"
    argv = ["valve", *mode, "--channel-length=0.01", "--length=1.6e-3", "--radius=50e-6",
            "--youngs-modulus=1e6", "--channel-height=2e-3", "--viscosity=1",
            "--spacing=400e-6", "--base-angle=-1.2", "--plot", str(path)]  # fmt: skip
    assert main(argv) == 0
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {path} (PNG)" in capsys.readouterr().err
    for bad, words in ((str(tmp_path / "v.xyz"), "unknown image format"),
                       (str(tmp_path / "no" / "v.png"), "cannot write")):  # fmt: skip
        assert main([*argv[:-1], bad]) == 2
        out, err = capsys.readouterr()
        assert out == "" and err.startswith("hairbed: error: --plot" if "xyz" in bad
                                            else "hairbed: error: cannot write")  # fmt: skip
        assert words in err and len(err.splitlines()) == 1
