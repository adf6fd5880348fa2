"""``hairbed rheometer --laos`` and ``--pipkin``: the numbers of hairbed.rheometer.bed_laos and
bed_pipkin_map, bad options one line with exit status 2.

The SI results themselves are checked against the dimensionless run in test_laos_si.py; the
command is a thin layer, so its CSV, JSON and dataset must carry the library call's values
exactly (floats printed by repr round-trip).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.cli import main
from hairbed.rheometer import BedLAOS, bed_laos

BED: dict[str, Any] = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 250e-6,
    "density": 1000.0,
    "base_angle": 0.3,
}
ARGS = [tok for k, v in BED.items() for tok in ("--" + k.replace("_", "-"), repr(v))]
FREQ, GAMMA0, SPEED = 0.1, 10.0, 1e-3
CMD = ["rheometer", "--frequencies", repr(FREQ), "--velocity", repr(SPEED), *ARGS]


@pytest.fixture(scope="module")
def reference() -> BedLAOS:
    return bed_laos(hairbed.HairBed(**BED), FREQ, GAMMA0, SPEED)


def test_laos_csv_and_netcdf_are_the_library_call(
    reference: BedLAOS, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    r = reference
    assert main([*CMD, "--laos", repr(GAMMA0)]) == 0
    out = capsys.readouterr().out.splitlines()
    notes = dict(line[2:].split(" = ", 1) for line in out if line.startswith("# "))
    for key in ("large_modulus", "minimum_modulus", "large_viscosity", "minimum_viscosity"):
        assert float(notes[key].split(" [")[0]) == getattr(r, key), key
    assert notes["large_viscosity"].endswith("[Pa s]")
    assert float(notes["third_harmonic"].split()[0]) == r.relative_intensity[2]
    e = [float(x) for x in notes["elastic_chebyshev"].split(" [")[0].split(", ")]
    assert e == r.elastic_chebyshev[:3].tolist()
    assert notes["status"] == "0"
    rows = [line for line in out if not line.startswith("#")]
    assert rows[0] == "time [s],strain,strain rate [1/s],stress [Pa]"
    table = np.array([[float(x) for x in row.split(",")] for row in rows[1:]])
    for k, name in enumerate(("time", "strain", "strain_rate", "stress")):
        np.testing.assert_array_equal(table[:, k], getattr(r, name))

    xr = pytest.importorskip("xarray")
    pytest.importorskip("netCDF4")
    path = tmp_path / "laos.nc"
    assert main([*CMD, "--laos", repr(GAMMA0), "--out", str(path)]) == 0
    with xr.open_dataset(path) as ds:
        np.testing.assert_array_equal(ds["stress"].values, r.stress)
        np.testing.assert_array_equal(ds["viscous_chebyshev"].values, r.viscous_chebyshev)
        assert ds["viscous_chebyshev"].attrs["units"] == "Pa s"
        assert ds["strain_rate"].attrs["units"] == "s-1"
        assert ds.attrs["large_modulus_Pa"] == r.large_modulus


def test_pipkin_json_is_the_library_call(
    reference: BedLAOS, capsys: pytest.CaptureFixture[str]
) -> None:
    r = reference
    assert main([*CMD, "--laos", repr(GAMMA0), "--pipkin", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["units"]["large_viscosity"] == "Pa s" and doc["units"]["frequency"] == "Hz"
    assert doc["frequency"] == [FREQ] and doc["strain_amplitude"] == [GAMMA0]
    assert doc["storage"] == [[float(r.storage[0])]]
    assert doc["large_viscosity"] == [[r.large_viscosity]]
    assert doc["third_harmonic"] == [[float(r.relative_intensity[2])]]
    assert doc["point_status"] == [[0]] and doc["pre_stress"] == r.pre_stress


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["--laos", "1,2"], "one frequency and one strain amplitude"),
        (["--pipkin"], "--pipkin applies to --laos only"),
        (["--workers", "2"], "--workers applies to --laos only"),
        (["--laos", "1", "--samples", "8"], "--samples must lie in [16, 4096]"),
        (["--laos", "1", "--pipkin", "--workers", "0"], "--workers must lie in [1, 64]"),
        (["--laos", "1,-1", "--pipkin"], "got -1.0 (first at index 1)"),
        (["--laos", "1", "--hair-density", "1000"], "--hair-density does not apply"),
        (["--laos", "1e9"], "too fast for this bed"),
        (["--laos", "x"], "--laos"),
    ],
)
def test_bad_options_are_one_line(
    extra: list[str], words: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([*CMD, *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith("hairbed: error: ") and err.count("\n") == 1, err
    assert words in err, err
