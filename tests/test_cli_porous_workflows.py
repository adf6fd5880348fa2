"""The porous bed's workflows on the command line (issue 29): ``invert``, ``linear-range``,
``calibrate`` and ``measure`` with ``--model porous`` (and ``--drag``).

The CLI is a thin layer over the library: each number is compared with the library's own
(a porous :class:`hairbed.HairBed`), computed here; the round trips go from the bed's
forward solve (``deform``) through the command and back.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed import calibration
from hairbed.cli import main

BED_KW: dict[str, Any] = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
    "base_angle": 0.3,
}
BED_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in BED_KW.items()]
POROUS = hairbed.HairBed(**BED_KW, model="porous")
VELOCITY = np.linspace(0.01, 0.2, 6)


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def _one_error(status: int, out: str, err: str, *words: str) -> None:
    assert status == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("hairbed: error: ")
    for word in words:
        assert word in lines[0], lines[0]


def _points(path: Path, bed: hairbed.HairBed) -> Path:
    """A calibration file of the bed's own deflections at VELOCITY."""
    d = bed.deform(VELOCITY).tip_deflection
    rows = "\n".join(f"{float(v)!r},{float(x)!r}" for v, x in zip(VELOCITY, d))
    path.write_text("velocity,tip_deflection\n" + rows + "\n")
    return path


def test_invert_porous_is_the_library_measure(capsys: pytest.CaptureFixture[str]) -> None:
    st = POROUS.deform(0.05)
    args = ("invert", "--tip-deflection", repr(st.tip_deflection), *BED_ARGS)
    status, out, err = _run(capsys, *args, "--model", "porous", "--sigma", "1e-6", "--json")
    assert status == 0, err
    doc = json.loads(out)
    assert doc["velocity"] == pytest.approx(0.05, rel=1e-11)
    assert doc["wall_shear_stress_Pa"] == pytest.approx(st.wall_shear_stress, rel=1e-11)
    m = calibration.measure(POROUS, st.tip_deflection, sigma=1e-6)
    assert doc["velocity_stderr"] == m.velocity_stderr
    assert doc["wall_shear_stress_stderr_Pa"] == m.wall_shear_stress_stderr
    # the dense bed's answer differs: the option reaches the bed
    status, out, _ = _run(capsys, *args, "--json")
    assert status == 0 and json.loads(out)["velocity"] != pytest.approx(0.05, rel=1e-3)


@pytest.mark.parametrize("drag", ["crossover", "array"])
def test_linear_range_porous(capsys: pytest.CaptureFixture[str], drag: str) -> None:
    args = ("linear-range", *BED_ARGS, "--model", "porous", "--drag", drag, "--rtol", "0.05")
    status, out, err = _run(capsys, *args, "--json")
    assert status == 0, err
    doc = json.loads(out)
    ref = calibration.linear_range(hairbed.HairBed(**BED_KW, model="porous", drag=drag), 0.05)
    for q in ("velocity", "wall_shear_stress"):
        assert doc[q]["tip_deflection"] == ref.limits[q].tip_deflection
        assert doc[q]["wall_shear_stress"] == ref.limits[q].wall_shear_stress
    status, out, _ = _run(capsys, *args)
    assert status == 0 and "linear calibration within 0.05" in out


def test_calibrate_then_measure_porous(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """calibrate --model porous recovers the modulus of the porous bed's own deflections;
    its file keeps the model and the drag law, and measure --calibration reads a new
    deflection back to its speed."""
    data = _points(tmp_path / "points.csv", POROUS)
    start = [a for a in BED_ARGS if not a.startswith("--youngs-modulus")] + [
        "--youngs-modulus=1.4e6"
    ]
    args = ("calibrate", "--data", str(data), *start, "--model", "porous", "--sigma", "1e-6")
    status, out, err = _run(capsys, *args, "--json")
    assert status == 0, err
    doc = json.loads(out)
    assert doc["bed"]["model"] == "porous" and doc["bed"]["drag"] == "crossover"
    fitted = doc["parameters"]["youngs_modulus"]["value"]
    assert fitted == pytest.approx(1e6, rel=1e-8)
    cal = tmp_path / "cal.json"
    cal.write_text(out)
    read = hairbed.calibration_files.read_calibration(cal)
    assert read.bed.model == "porous" and read.bed.kappa == pytest.approx(POROUS.kappa)
    st = POROUS.deform(0.07)
    margs = ("measure", "--calibration", str(cal), "--tip-deflection", repr(st.tip_deflection))
    status, out, err = _run(capsys, *margs, "--sigma", "1e-6", "--json")
    assert status == 0, err
    m = json.loads(out)
    assert m["velocity"] == pytest.approx(0.07, rel=1e-8)
    assert m["wall_shear_stress"] == pytest.approx(st.wall_shear_stress, rel=1e-8)
    # the model in the file is the bed's: --model porous agrees, --drag array does not
    status, out, err = _run(capsys, *margs, "--model", "porous", "--json")
    assert status == 0, err
    _one_error(*_run(capsys, *margs, "--drag", "array"), "--drag array", "crossover")


def test_measure_porous_without_calibration(capsys: pytest.CaptureFixture[str]) -> None:
    st = POROUS.deform(-0.03)
    args = ("measure", "--tip-deflection", repr(st.tip_deflection), *BED_ARGS)
    status, out, err = _run(capsys, *args, "--model", "porous", "--json")
    assert status == 0, err
    assert json.loads(out)["velocity"] == pytest.approx(-0.03, rel=1e-10)


def test_a_dense_calibration_refuses_model_porous(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    dense = hairbed.HairBed(**BED_KW)
    data = _points(tmp_path / "points.csv", dense)
    status, out, err = _run(capsys, "calibrate", "--data", str(data), *BED_ARGS, "--json")
    assert status == 0, err
    cal = tmp_path / "cal.json"
    cal.write_text(out)
    assert json.loads(out)["bed"]["model"] == "dense"
    args = ("measure", "--calibration", str(cal), "--tip-deflection", "3e-4")
    _one_error(*_run(capsys, *args, "--model", "porous"), "--model porous", "dense")


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("invert", "--tip-deflection", "0.3", "--eps", "0.5", "--model", "porous"),
         ("--model porous", "physical inputs")),
        (("linear-range", "--model", "porous"), ("--model porous", "physical inputs")),
        (("linear-range", *BED_ARGS, "--drag", "array"), ("--drag array", "--model porous")),
        (("invert", "--tip-deflection", "2e-3", *BED_ARGS, "--model", "porous"),
         ("tip_deflection", "length")),
        (("measure", "--tip-deflection", "1e-4", *BED_ARGS, "--spacing=101e-6",
          "--model", "porous"), ("packing_fraction", "0.6")),
        (("linear-range", "--pillar", "--length=1e-3", "--radius=50e-6",
          "--youngs-modulus=1e6", "--viscosity=1", "--model", "porous"),
         ("--model porous", "pillar")),
        (("calibrate", "--data", "missing.csv", *BED_ARGS, "--model", "nonsense"),
         ("--model",)),
    ],
)  # fmt: skip
def test_bad_input_is_one_line(
    capsys: pytest.CaptureFixture[str], args: tuple[str, ...], words: tuple[str, ...]
) -> None:
    _one_error(*_run(capsys, *args), *words)
