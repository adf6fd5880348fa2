"""Calibration misapplied on the command line: calibrate, measure, invert, the README's example.

References: the library calls the commands stand for (hairbed.calibration, through its own
API), the README's printed output, and the example data file shipped in docs/examples.
"""

from __future__ import annotations

import contextlib
import io
import json
import shlex
import subprocess
from pathlib import Path

import numpy as np

import hairbed
from hairbed.calibration import measure, model_tip_deflection
from hairbed.cli import main

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "docs" / "examples" / "points.csv"
BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip
BED_KW = dict(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
)


def call(*args: str) -> subprocess.CompletedProcess[str]:
    """The command in this process (``hairbed.cli.main``)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(args))
        except SystemExit as exc:  # --help
            code = int(exc.code or 0)
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def one_error_line(proc: subprocess.CompletedProcess[str], *words: str) -> None:
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), proc.stderr
    for w in words:
        assert w in lines[0], lines[0]


def _calibration(tmp_path: Path) -> Path:
    cal = tmp_path / "cal.json"
    proc = call("calibrate", "--data", str(EXAMPLE), "--free", "youngs_modulus,base_angle", *BED,
                "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    cal.write_text(proc.stdout)
    return cal


# -- item 1: measure uses the calibrated bed and refuses another ----------------------------


def test_measure_refuses_a_bed_option_that_disagrees(tmp_path: Path) -> None:
    cal = _calibration(tmp_path)
    wrong = [a if a != "50e-6" else "30e-6" for a in BED]  # --radius 30e-6
    one_error_line(
        call("measure", "--tip-deflection", "3e-4", "--calibration", str(cal), *wrong),
        "--radius",
        "3e-05",
        "5e-05",
    )


def test_measure_uses_the_bed_of_the_calibration_file(tmp_path: Path) -> None:
    cal = _calibration(tmp_path)
    doc = json.loads(cal.read_text())
    assert doc["bed"]["radius"] == 50e-6 and doc["hairbed_version"] == hairbed.__version__
    alone = call("measure", "--tip-deflection", "3e-4", "--sigma", "2e-6", "--calibration",
                 str(cal), "--json")  # fmt: skip
    again = call("measure", "--tip-deflection", "3e-4", "--sigma", "2e-6", "--calibration",
                 str(cal), *BED, "--json")  # fmt: skip
    assert alone.returncode == again.returncode == 0, alone.stderr + again.stderr
    got = json.loads(alone.stdout)
    assert json.loads(again.stdout) == got  # the options of calibrate: its starting values
    res = hairbed.calibration_files.read_calibration(cal)
    lib = measure(res.bed, 3e-4, sigma=2e-6, fit=res)
    assert got["wall_shear_stress"] == lib.wall_shear_stress
    assert got["wall_shear_stress_stderr"] == lib.wall_shear_stress_stderr
    one_error_line(call("measure", "--tip-deflection", "3e-4"), "--calibration", "--length")


# -- item 2: hairbed's own CSV headers, and the README's example ------------------------------


def test_calibrate_reads_name_and_units_headers(tmp_path: Path) -> None:
    true = hairbed.HairBed(**{**BED_KW, "youngs_modulus": 1.3e6})
    v = np.linspace(0.01, 0.3, 6)
    d = model_tip_deflection(true, velocity=v)
    rows = [f"{float(a)!r},{float(b)!r}" for a, b in zip(d, v)]
    plain, units = tmp_path / "plain.csv", tmp_path / "units.csv"
    plain.write_text("\n".join(["tip_deflection,velocity", *rows]) + "\n")
    units.write_text("\n".join(["tip_deflection [m],velocity [m/s]", *rows]) + "\n")
    a = call("calibrate", "--data", str(plain), *BED, "--sigma", "1e-6", "--json")
    b = call("calibrate", "--data", str(units), *BED, "--sigma", "1e-6", "--json")
    assert a.returncode == b.returncode == 0, a.stderr + b.stderr
    assert json.loads(a.stdout)["parameters"] == json.loads(b.stdout)["parameters"]
    wrong = tmp_path / "wrong.csv"
    wrong.write_text("\n".join(["tip_deflection [um],velocity [m/s]", *rows]) + "\n")
    one_error_line(call("calibrate", "--data", str(wrong), *BED), "tip_deflection", "um", "[m]")


def _readme_block() -> list[str]:
    """The README's calibrate/measure example: lines from its first command to the blank."""
    lines = (ROOT / "README.md").read_text().splitlines()
    start = next(i for i, s in enumerate(lines) if "hairbed calibrate --data docs/examples" in s)
    end = next(i for i in range(start, len(lines)) if not lines[i].strip())
    return [s[4:] for s in lines[start:end]]


def test_the_example_points_reproduce_the_readme(tmp_path: Path, monkeypatch) -> None:
    block = _readme_block()
    monkeypatch.chdir(ROOT)
    commands = [i for i, s in enumerate(block) if s.startswith("hairbed ")]
    checked = 0
    for k, i in enumerate(commands):
        text = block[i]
        j = i + 1
        while text.endswith("\\"):
            text = text[:-1] + " " + block[j].strip()
            j += 1
        expected = block[j : commands[k + 1] if k + 1 < len(commands) else len(block)]
        argv = shlex.split(text)[1:]
        if ">" in argv:  # the file the next command reads
            target = argv[argv.index(">") + 1]
            proc = call(*argv[: argv.index(">")])
            (tmp_path / target).write_text(proc.stdout)
            continue
        argv = [str(tmp_path / a) if a == "cal.json" else a for a in argv]
        proc = call(*argv)
        assert proc.returncode == 0, proc.stderr
        got = [s.strip() for s in proc.stdout.splitlines()]
        assert got == [e.strip() for e in expected], (argv, proc.stdout, expected)
        checked += 1
    assert checked == 2  # calibrate and measure


# -- item 3: an impossible fit is marked -------------------------------------------------------


def test_one_point_without_sigma_warns_and_labels_chi2(tmp_path: Path) -> None:
    one = tmp_path / "one.csv"
    one.write_text("tip_deflection,velocity\n3e-4,0.05\n")
    proc = call("calibrate", "--data", str(one), *BED)
    assert proc.returncode == 0, proc.stderr
    assert "no degrees of freedom" in proc.stderr and proc.stderr.startswith("hairbed: warning:")
    assert "sum of squared residuals" in proc.stdout and "[m^2]" in proc.stdout
    assert "converged with a caveat (status 5)" in proc.stdout
    doc = json.loads(call("calibrate", "--data", str(one), *BED, "--json").stdout)
    assert doc["status"] == 5 and doc["chi2_unit"] == "m^2"
    assert doc["parameters"]["youngs_modulus"]["stderr"] == "inf"


# -- item 6: invert with a bed is measure without a calibration -------------------------------


def test_invert_with_a_bed_is_measure_without_a_calibration() -> None:
    inv = json.loads(call("invert", "--tip-deflection", "3e-4", "--sigma", "2e-6", *BED,
                          "--json").stdout)  # fmt: skip
    mea = json.loads(call("measure", "--tip-deflection", "3e-4", "--sigma", "2e-6", *BED,
                          "--json").stdout)  # fmt: skip
    assert inv["wall_shear_stress_Pa"] == mea["wall_shear_stress"]
    assert inv["velocity"] == mea["velocity"]
    assert inv["wall_shear_stress_stderr_Pa"] == mea["wall_shear_stress_stderr"]
    lib = measure(hairbed.HairBed(**BED_KW), 3e-4, sigma=2e-6)
    assert mea["velocity_stderr"] == lib.velocity_stderr
    help_invert = call("invert", "--help").stdout
    help_measure = call("measure", "--help").stdout
    assert "hairbed measure" in help_invert and "hairbed invert" in help_measure


# -- item 4: the calibration curve in stress and the linear range on the command line -------


def test_sweep_over_wall_shear_stress(tmp_path: Path) -> None:
    out = tmp_path / "curve.csv"
    proc = call("sweep", *BED, "--wall-shear-stress", "1:50:5", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    import csv

    lines = [s for s in out.read_text().splitlines() if not s.startswith("#")]
    rows = list(csv.DictReader(lines))
    tau = np.array([float(r["wall_shear_stress [Pa]"]) for r in rows])
    np.testing.assert_allclose(tau, np.linspace(1, 50, 5), rtol=1e-12)
    bed = hairbed.HairBed(**BED_KW)
    d = np.array([float(r["tip_deflection [m]"]) for r in rows])
    np.testing.assert_allclose(d, model_tip_deflection(bed, wall_shear_stress=tau), rtol=1e-12)
    one_error_line(call("sweep", "--wall-shear-stress", "1:2:3", "--eps", "0.5"), "bed")
    one_error_line(
        call("sweep", *BED, "--wall-shear-stress", "1", "--velocity", "0.1"), "--velocity"
    )


def test_linear_range_command() -> None:
    proc = call("linear-range", "--rtol", "0.05", *BED, "--json")
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout)
    lib = hairbed.calibration.linear_range(hairbed.HairBed(**BED_KW), 0.05)
    for q in ("velocity", "wall_shear_stress"):
        assert got[q]["wall_shear_stress"] == lib.limits[q].wall_shear_stress
        assert got[q]["tip_deflection"] == lib.limits[q].tip_deflection
    text = call("linear-range", "--rtol", "0.05", *BED).stdout
    assert "wall shear stress" in text
    for q in ("velocity", "wall_shear_stress"):
        assert f"tau = {lib.limits[q].wall_shear_stress:.6g} Pa" in text
    one_error_line(call("linear-range", "--rtol", "2", *BED), "rtol")
