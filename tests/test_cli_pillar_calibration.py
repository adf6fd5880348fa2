"""``hairbed calibrate --pillar`` and ``hairbed measure --pillar`` (issue 21): the round trip
through a CSV of synthetic points and the calibration file, and the one-line errors."""

from __future__ import annotations

import contextlib
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed.calibration import model_tip_deflection
from hairbed.cli import main

PILLAR = [
    "--length", "500e-6", "--radius", "25e-6", "--youngs-modulus", "1e6",
    "--viscosity", "1e-3", "--base-angle", "0.2",
]  # fmt: skip
TRUE = hairbed.Pillar(
    length=500e-6, radius=25e-6, youngs_modulus=1.3e6, viscosity=1e-3, base_angle=0.3
)
TAU = np.linspace(0.5, 150.0, 9)


def call(*args: str) -> subprocess.CompletedProcess[str]:
    """The command in this process (``hairbed.cli.main``)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def one_error_line(proc: subprocess.CompletedProcess[str], *words: str) -> None:
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), proc.stderr
    for w in words:
        assert w in lines[0], lines[0]


@pytest.fixture
def points(tmp_path: Path) -> Path:
    d = model_tip_deflection(TRUE, wall_shear_stress=TAU)
    path = tmp_path / "stress.csv"
    rows = "".join(f"{float(t)!r},{float(x)!r}\n" for t, x in zip(TAU, d))
    path.write_text("wall_shear_stress [Pa],tip_deflection [m]\n" + rows)
    return path


def test_calibrate_and_measure_round_trip(points: Path, tmp_path: Path) -> None:
    proc = call("calibrate", "--pillar", "--data", str(points), "--sigma", "1e-8",
                "--free", "youngs_modulus,base_angle", *PILLAR)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "youngs_modulus  1300000 +-" in proc.stdout and "base_angle      0.3 +-" in proc.stdout
    assert "[rad]" in proc.stdout
    proc = call("calibrate", "--pillar", "--data", str(points), "--sigma", "1e-8",
                "--free", "youngs_modulus,base_angle", *PILLAR, "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    assert doc["sensor"] == "pillar" and doc["bed"]["profile"] == "sublayer"
    assert doc["parameters"]["base_angle"]["value"] == pytest.approx(0.3, rel=1e-9)
    assert doc["parameters"]["base_angle"]["unit"] == "rad"
    cal = tmp_path / "cal.json"
    cal.write_text(proc.stdout)
    d4 = float(model_tip_deflection(TRUE, wall_shear_stress=TAU[4]))
    proc = call("measure", "--pillar", "--calibration", str(cal), "--json",
                "--tip-deflection", repr(d4), "--sigma", "1e-6")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    m = json.loads(proc.stdout)
    assert m["wall_shear_stress"] == pytest.approx(TAU[4], rel=1e-8)
    assert 0 < m["wall_shear_stress_stderr"] < 0.1 * TAU[4] and m["success"]
    assert m["forcing"] == pytest.approx(TAU[4] * TRUE.forcing_per_stress, rel=1e-8)
    # the file's pillar is the calibrated one: the same as hairbed.calibration.measure's
    fit = hairbed.calibration_files.read_calibration(cal)
    ref = hairbed.calibration.measure(fit.bed, d4, sigma=1e-6, fit=fit)
    assert m["wall_shear_stress_stderr"] == pytest.approx(ref.wall_shear_stress_stderr)
    # without a calibration: the pillar of the options
    proc = call("measure", "--pillar", "--tip-deflection", repr(d4), *PILLAR[:-2],
                "--base-angle", "0.3", "--youngs-modulus", "1.3e6")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("tau = 75.25 +- 0 Pa"), proc.stdout
    # the file says it is a pillar's: --pillar may be left out (issue 33), the same answer
    alone = call("measure", "--calibration", str(cal), "--json", "--tip-deflection", repr(d4),
                 "--sigma", "1e-6")  # fmt: skip
    assert alone.returncode == 0, alone.stderr
    assert json.loads(alone.stdout) == m
    # a disagreeing option against the file
    one_error_line(call("measure", "--pillar", "--calibration", str(cal), "--tip-deflection",
                        "1e-4", "--profile", "couette"), "--profile couette")  # fmt: skip
    one_error_line(call("measure", "--pillar", "--calibration", str(cal), "--tip-deflection",
                        "1e-4", "--spacing", "1e-3"), "--spacing does not apply")  # fmt: skip


def test_calibrate_of_a_couette_pillar_by_wall_speed(tmp_path: Path) -> None:
    """Points of wall speeds (tau_w = eta V/H), the length free (it enters Lambda, gamma and
    the scale of the deflection)."""
    args = {"radius": 25e-6, "youngs_modulus": 1e6, "viscosity": 1e-3, "profile": "couette",
            "channel_height": 1e-3}  # fmt: skip
    true = hairbed.Pillar(length=530e-6, **args)
    v = np.linspace(0.05, 20.0, 7)
    d = model_tip_deflection(true, velocity=v)
    path = tmp_path / "speed.csv"
    path.write_text("velocity,tip_deflection\n" + "".join(f"{a!r},{b!r}\n" for a, b in
                                                       zip(v.tolist(), d.tolist())))  # fmt: skip
    proc = call("calibrate", "--pillar", "--profile", "couette", "--channel-height", "1e-3",
                "--data", str(path), "--free", "length", "--json", "--length", "500e-6",
                "--radius", "25e-6", "--youngs-modulus", "1e6", "--viscosity", "1e-3")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    assert doc["kind"] == "velocity" and doc["bed"]["channel_height"] == 1e-3
    assert doc["parameters"]["length"]["value"] == pytest.approx(530e-6, rel=1e-9)


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["--spacing", "1e-4"], ("--spacing does not apply to calibrate --pillar",)),
        (["--gamma", "0.5"], ("--gamma does not apply to calibrate --pillar",)),
        (["--free", "spacing"], ("unknown parameter 'spacing'", "base_angle, length, radius")),
        (["--drag-scale", "-1"], ("drag_scale",)),
        (["--profile", "poiseuille"], ("channel_height",)),
    ],
)
def test_calibrate_pillar_errors_are_one_line(
    points: Path, extra: list[str], words: tuple[str, ...]
) -> None:
    one_error_line(call("calibrate", "--pillar", "--data", str(points), *PILLAR, *extra), *words)


def test_pillar_options_need_pillar_and_geometry(points: Path) -> None:
    one_error_line(call("calibrate", "--data", str(points), *PILLAR, "--drag-scale", "2"),
                   "--drag-scale needs --pillar")  # fmt: skip
    one_error_line(call("measure", "--tip-deflection", "1e-4", "--profile", "couette"),
                   "--profile needs --pillar")  # fmt: skip
    one_error_line(call("calibrate", "--pillar", "--data", str(points), "--length", "1e-3"),
                   "needs also --radius, --youngs-modulus, --viscosity")  # fmt: skip


def test_subprocess_exit_status_and_stderr(points: Path) -> None:
    """The real thing once: freeing E with the drag scale (one parameter, c/E) is refused as
    bad input (issue 33): exit 2 with a one-line error naming why."""
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "hairbed",
            "calibrate",
            "--pillar",
            "--data",
            str(points),
            "--free",
            "youngs_modulus,drag_scale",
            *PILLAR,
        ],  # fmt: skip
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "drag_scale/E" in lines[0], proc.stderr
