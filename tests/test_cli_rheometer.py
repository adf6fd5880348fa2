"""``hairbed rheometer``: its numbers are hairbed.rheometer.bed_moduli's, bad options one line.

The moduli themselves are checked against independent references in test_rheometer.py; here
the command is a thin layer, so its CSV, JSON and dataset must carry the library call's values
exactly (floats printed by repr round-trip), and every bad option must end in one line on
stderr with exit status 2.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.cli import main
from hairbed.rheometer import BedModuli, bed_moduli

BED: dict[str, Any] = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 250e-6,
    "density": 1000.0,
}
ARGS = [tok for k, v in BED.items() for tok in ("--" + k.replace("_", "-"), repr(v))]
FREQ = [3.0, 30.0, 100.0, 300.0]  # G' changes sign between 30 and 100 Hz
SPEED = 1e-3


@pytest.fixture(scope="module")
def reference() -> BedModuli:
    return bed_moduli(hairbed.HairBed(**BED), np.array(FREQ), SPEED)


def test_csv_and_json_are_the_library_call(
    reference: BedModuli, capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    r = reference
    cmd = ["rheometer", "--frequencies", ",".join(map(repr, FREQ)), "--velocity", repr(SPEED)]
    assert main([*cmd, *ARGS]) == 0
    out = capsys.readouterr().out.splitlines()
    notes = dict(line[2:].split(" = ", 1) for line in out if line.startswith("# "))
    assert float(notes["pre_stress"].split()[0]) == r.pre_stress[0]
    lead_x = float(notes["lead_crossover"].split()[0])
    assert lead_x == r.lead_crossover[0]
    assert 30.0 < lead_x < 100.0
    assert notes["status"] == "0"
    rows = [line for line in out if not line.startswith("#")]
    assert rows[0] == "frequency [Hz],storage [Pa],loss [Pa],phase [deg],status"
    table = np.array([[float(x) for x in row.split(",")] for row in rows[1:]])
    np.testing.assert_array_equal(table[:, 0], FREQ)
    np.testing.assert_array_equal(table[:, 1], r.storage[:, 0])
    np.testing.assert_array_equal(table[:, 2], r.loss[:, 0])
    # the phase against the strain, arg G*, is the lead against the wall's speed + 90 deg
    lead = np.degrees(r.lead[:, 0]) + 90.0
    np.testing.assert_allclose(table[:, 3], lead, rtol=0, atol=1e-12)
    assert table[1, 3] < 90.0 < table[2, 3]  # lag below the lead crossover, lead above it

    assert main([*cmd, *ARGS, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["storage"] == r.storage[:, 0].tolist()
    assert doc["loss"] == r.loss[:, 0].tolist()
    assert doc["units"]["storage"] == "Pa" and doc["units"]["phase"] == "deg"
    assert doc["modulus_crossover"] is None or math.isfinite(doc["modulus_crossover"])

    xr = pytest.importorskip("xarray")
    path = tmp_path / "moduli.nc"
    assert main([*cmd, *ARGS, "--out", str(path)]) == 0
    with xr.open_dataset(path) as ds:
        np.testing.assert_array_equal(ds["storage"].values, r.storage)
        assert ds["storage"].attrs["units"] == "Pa"
        assert ds["phase"].attrs["units"] == "deg"
        assert ds.attrs["kappa"] == r.dimensionless.kappa


@pytest.mark.parametrize(
    ("extra", "says"),
    [
        (["--frequencies", "1,-2"], "--frequencies must be finite and > 0"),
        (["--frequencies", "10,1"], "--frequencies must increase"),
        (["--frequencies", "1:x"], "--frequencies"),
        (["--frequencies", "1", "--velocity", "inf"], "--velocity"),
        (["--frequencies", "1", "--hair-density", "-3"], "hair_density"),
        (["--frequencies", "1", "--hair-density", "1e300"], "hair_density"),
        (["--frequencies", "1", "--out", "x.foo"], "unknown output format"),
        (["--frequencies", "1", "--json", "--out", "x.nc"], "--json and --out"),
        (["--frequencies", "1", "--drag", "sparse"], "--model porous only"),
    ],
)
def test_bad_options_are_one_line_and_exit_2(
    extra: list[str], says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["rheometer", *extra, *ARGS]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hairbed: error: ") and says in err


def test_no_bed_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rheometer", "--frequencies", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "physical inputs" in err
