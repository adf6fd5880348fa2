"""Hostile input to the newer options of the command line (issue 33): every refusal is one line
``hairbed: error: ...`` naming the option, exit status 2, never a traceback.

In process (:func:`hairbed.cli.main`), fast; the real-process promises are those of
tests/test_cli_errors.py.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hairbed.cli import main


def one_error(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> str:
    """``main(argv)`` exits 2 with one line ``hairbed: error: ...`` holding every word."""
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), err
    assert "Traceback" not in err and out == "", (out, err)
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


# -- item 5: calibration files that are JSON but not a calibration ------------------------------

NOT_A_CALIBRATION = {
    "array": ("[1,2,3]", "got a JSON array"),
    "number": ("42", "got a JSON number"),
    "null": ("null", "got a JSON null"),
    "string": ('"cal"', "got a JSON string"),
    "boolean": ("true", "got a JSON boolean"),
    "nested array": ("[" * 40 + "1" + "]" * 40, "got a JSON array"),
    "nested too deeply": ("[" * 200_000 + "]" * 200_000, "nested too deeply"),
    "nested objects": ('{"a":' * 200_000 + "1" + "}" * 200_000, "nested too deeply"),
    "empty object": ("{}", "not a hairbed calibration file"),
}


@pytest.mark.parametrize("name", sorted(NOT_A_CALIBRATION))
@pytest.mark.parametrize("command", ["measure", "measure --pillar"])
def test_a_file_that_is_not_a_calibration_is_one_line(name, command, tmp_path: Path, capsys):
    text, words = NOT_A_CALIBRATION[name]
    path = tmp_path / "cal.json"
    path.write_text(text)
    argv = [*command.split(), "--tip-deflection", "1e-4", "--calibration", str(path)]
    one_error(capsys, argv, "--calibration", str(path), words)


# -- item 2: --free with an empty item ----------------------------------------------------------

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "docs" / "examples" / "points.csv"
BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip
PILLAR = [
    "--pillar", "--length", "500e-6", "--radius", "25e-6", "--youngs-modulus", "1e6",
    "--viscosity", "1e-3",
]  # fmt: skip


@pytest.mark.parametrize(
    ("free", "item"),
    [
        ("youngs_modulus,,base_angle", "item 2"),
        ("youngs_modulus,", "item 2"),
        (",youngs_modulus", "item 1"),
        (",", "item 1"),
        ("", "item 1"),
        ("youngs_modulus, ,base_angle", "item 2"),
    ],
)
@pytest.mark.parametrize("sensor", ["bed", "pillar"])
def test_free_with_an_empty_item_is_refused(capsys, free: str, item: str, sensor: str):
    options = BED if sensor == "bed" else PILLAR
    argv = ["calibrate", "--data", str(EXAMPLE), "--free", free, *options]
    one_error(capsys, argv, "--free", item, "is empty")


# -- Ranges and sweeps: the two-sided logarithmic range on the command line ---------------------

VALVE_BED = [
    "--length", "1.8e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
    "--base-angle", "1.0", "--channel-length", "0.01",
]  # fmt: skip


def test_valve_takes_a_two_sided_log_range_and_says_so_in_help(capsys):
    import json

    assert main(["valve", "--pressure-drop", "+-10:1e3:2:log", *VALVE_BED, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    drops = [r["pressure_drop"] for r in doc["curve"]]
    assert drops == pytest.approx([-1e3, -10.0, 10.0, 1e3], rel=4e-16)
    # backward flow for the negative drops, forward for the positive
    assert [r["flow_rate"] < 0 for r in doc["curve"]] == [True] * 2 + [False] * 2
    with pytest.raises(SystemExit):
        main(["valve", "--help"])
    assert "+-START:STOP:NUM:log" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    assert "+-start:stop:num:log" in capsys.readouterr().out


def test_a_range_through_zero_prints_zero(capsys):
    assert main(["sweep", *BED, "--velocity=-0.05:0.1:4"]) == 0
    rows = capsys.readouterr().out.splitlines()[1:]
    assert [r.split(",")[0] for r in rows][:2] == ["-0.05", "0.0"] and len(rows) == 4


@pytest.mark.parametrize(
    "spec", ["+-10:1e4:4", "+-1e4:10:3:log", "+-0:1:3:log", "+-10:1e4:3:log:updown"]
)
def test_bad_two_sided_ranges_are_one_line(capsys, spec: str):
    one_error(capsys, ["valve", "--pressure-drop", spec, *VALVE_BED], "--pressure-drop", spec)
