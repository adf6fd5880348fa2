"""``hairbed valve``: the valve curve and the diodicity on the command line."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hairbed import HairBed
from hairbed.cli import main
from hairbed.valve import diodicity, valve_curve

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
