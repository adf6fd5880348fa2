"""The calibration and bistability commands through a subprocess: bistability, labelled states,
calibrate, measure, and the one-line model-validity warning."""

from __future__ import annotations

import contextlib
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed.calibration import model_tip_deflection
from hairbed.cli import main

BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip
#: A short stiff pillar in a 1 mm water channel.
#: A dense bed (sqrt(k) = 0.04 L, theory.md §10) of short stiff pillars in 1 mm of water: the
#: only validity warning it can get is that of the Reynolds number.
WATER = [
    "--length", "1e-4", "--radius", "20e-6", "--youngs-modulus", "1e9",
    "--channel-height", "1e-3", "--viscosity", "1e-3", "--spacing", "60e-6",
    "--density", "1000",
]  # fmt: skip


def run(*args: str) -> subprocess.CompletedProcess[str]:
    """The command in a subprocess (the real thing: exit status, stdout, stderr)."""
    return subprocess.run(
        [sys.executable, "-m", "hairbed", *args], capture_output=True, text=True, timeout=300
    )


def call(*args: str) -> subprocess.CompletedProcess[str]:
    """The same in this process (``hairbed.cli.main``), for the cheaper checks."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def one_error_line(proc: subprocess.CompletedProcess[str], *words: str) -> None:
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), proc.stderr
    for w in words:
        assert w in lines[0]


def test_bistability_json() -> None:
    proc = run("bistability", "--eps", "0.95", "--theta0=-1.2", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert set(out) >= {"cusp_eps", "folds", "window"}
    assert out["cusp_eps"] == pytest.approx(float(hairbed.branches.cusp(-1.2)), rel=1e-12)
    assert 0.8 < out["cusp_eps"] < 0.95
    lower, upper = out["window"]
    assert [f["omega2"] for f in out["folds"]] == pytest.approx([lower, upper], rel=1e-15)
    for fold in out["folds"]:
        assert set(fold) >= {"omega2", "xi", "tip_deflection"}
        # a fold: the number of physical states changes from 1 to 3 across it
        below = hairbed.solve(fold["omega2"] * (1 - 1e-6), 0.95, -1.2).n_roots
        above = hairbed.solve(fold["omega2"] * (1 + 1e-6), 0.95, -1.2).n_roots
        assert {below, above} == {1, 3}
        state = hairbed.from_xi(fold["xi"], 0.95, -1.2)
        assert state.omega2 == pytest.approx(fold["omega2"], rel=1e-9)
        assert state.tip_deflection == pytest.approx(fold["tip_deflection"], rel=1e-9)


def test_bistability_text_and_no_window() -> None:
    proc = call("bistability", "--eps", "0.95", "--theta0=-1.2")
    assert proc.returncode == 0 and "window" in proc.stdout and "lower fold" in proc.stdout
    proc = call("bistability", "--eps", "0.5", "--theta0", "0.2", "--json")
    out = json.loads(proc.stdout)
    assert out["window"] is None and out["folds"] == [] and out["cusp_eps"] == 1.0
    one_error_line(run("bistability", "--eps", "1.5", "--theta0", "0"), "eps")
    one_error_line(call("bistability", "--eps", "0.5"), "--theta0")


def test_help_says_negative_theta0_leans_into_the_flow() -> None:
    for cmd in ("solve", "bistability"):
        proc = subprocess.run(
            [sys.executable, "-m", "hairbed", cmd, "--help"],
            capture_output=True,
            text=True,
            timeout=300,
        )
        text = " ".join(proc.stdout.split())
        assert "negative leans into" in text


def test_solve_inside_a_window_lists_labelled_states() -> None:
    proc = run("solve", "--omega2", "0.5", "--eps", "0.95", "--theta0=-1.2", "--json")
    assert proc.returncode == 0, proc.stderr
    states = json.loads(proc.stdout)
    assert [s["root"] for s in states] == ["low", "mid", "high"]
    assert [s["stable"] for s in states] == [True, False, True]
    xi = [s["xi"] for s in states]
    assert xi == sorted(xi)
    for s, root in zip(states, ("low", "mid", "high")):
        ref = hairbed.solve(0.5, 0.95, -1.2, root=root)
        assert s["xi"] == pytest.approx(ref.xi, rel=1e-14)
        assert bool(hairbed.stability.is_stable(ref)) == s["stable"]
    text = call("solve", "--omega2", "0.5", "--eps", "0.95", "--theta0=-1.2").stdout
    assert "low state (stable)" in text and "mid state (unstable)" in text
    # an explicit --root gives that state alone; outside the window one state
    one = json.loads(call("solve", "--omega2", "0.5", "--eps", "0.95", "--theta0=-1.2",
                         "--root", "mid", "--json").stdout)  # fmt: skip
    assert isinstance(one, dict) and one["xi"] == pytest.approx(xi[1], rel=1e-14)
    assert isinstance(json.loads(call("solve", "--omega2", "2", "--eps", "0.5", "--json").stdout),
                      dict)  # fmt: skip


def test_all_branches_labels_every_entry() -> None:
    proc = call("solve", "--omega2", "0.5", "--eps", "0.95", "--theta0=-1.2", "--all-branches",
               "--json")  # fmt: skip
    states = json.loads(proc.stdout)
    assert all("root" in s and "stable" in s for s in states)
    physical = [s for s in states if s["physical"]]
    assert [s["root"] for s in physical] == ["low", "mid", "high"]


def test_model_validity_warning_is_one_line() -> None:
    fast = run("solve", *WATER, "--velocity", "17", "--json")
    assert fast.returncode == 0
    lines = fast.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: warning: "), fast.stderr
    assert "Reynolds" in lines[0] and "Stokes" in lines[0]
    out = json.loads(fast.stdout)
    assert out["reynolds_number"] == pytest.approx(1000 * 17 * (1e-3 - out["tip_height_m"]) / 1e-3)
    assert out["reynolds_number"] > 1e4
    slow = call("solve", *WATER, "--velocity", "1e-4", "--json")
    assert slow.returncode == 0 and slow.stderr == ""
    assert json.loads(slow.stdout)["reynolds_number"] < 1


def _write_points(path: Path, sigma_column: bool) -> tuple[np.ndarray, float]:
    true = hairbed.HairBed(length=1e-3, radius=50e-6, youngs_modulus=1.3e6,
                           channel_height=2e-3, viscosity=1.0, spacing=400e-6)  # fmt: skip
    v = np.linspace(0.01, 0.3, 10)
    d = model_tip_deflection(true, velocity=v)
    d = d + np.random.default_rng(5).normal(0.0, 2e-6, v.size)
    header = "tip_deflection,velocity" + (",sigma" if sigma_column else "")
    rows = [f"{float(a)!r},{float(b)!r}" + (",2e-6" if sigma_column else "") for a, b in zip(d, v)]
    path.write_text("\n".join([header, *rows]) + "\n")
    return d, 1.3e6


def test_calibrate_json(tmp_path: Path) -> None:
    data = tmp_path / "points.csv"
    d, true_e = _write_points(data, sigma_column=True)
    proc = run("calibrate", "--data", str(data), *BED, "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    e = out["parameters"]["youngs_modulus"]
    assert abs(e["value"] - true_e) < 4 * e["stderr"] and e["unit"] == "Pa"
    assert out["success"] and out["dof"] == 9 and out["points"] == 10
    lib = hairbed.calibration.fit(
        hairbed.HairBed(
            length=1e-3,
            radius=50e-6,
            youngs_modulus=1e6,
            channel_height=2e-3,
            viscosity=1.0,
            spacing=400e-6,
        ),  # fmt: skip
        d,
        velocity=np.linspace(0.01, 0.3, 10),
        sigma=2e-6,
    )
    assert e["value"] == pytest.approx(lib.values["youngs_modulus"], rel=1e-12)
    text = call("calibrate", "--data", str(data), *BED, "--free", "youngs_modulus").stdout
    assert "youngs_modulus" in text and "+-" in text


def test_calibrate_errors(tmp_path: Path) -> None:
    one_error_line(run("calibrate", "--data", str(tmp_path / "missing.csv"), *BED), "--data")
    bad = tmp_path / "bad.csv"
    bad.write_text("tip_deflection,speed\n1e-4,0.1\n")
    one_error_line(call("calibrate", "--data", str(bad), *BED), "speed")
    data = tmp_path / "points.csv"
    _write_points(data, sigma_column=False)
    one_error_line(
        call("calibrate", "--data", str(data), *BED, "--free", "stiffness"), "stiffness"
    )
    one_error_line(call("calibrate", "--data", str(data)), "--length")


def test_measure(tmp_path: Path) -> None:
    proc = run("measure", "--tip-deflection", "3e-4", "--sigma", "1e-6", *BED, "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    bed = hairbed.HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                          viscosity=1.0, spacing=400e-6)  # fmt: skip
    assert out["wall_shear_stress"] == pytest.approx(
        bed.wall_shear_stress_from_tip_deflection(3e-4), rel=1e-12
    )
    m = hairbed.calibration.measure(bed, 3e-4, sigma=1e-6)
    assert out["wall_shear_stress_stderr"] == pytest.approx(m.wall_shear_stress_stderr, rel=1e-12)
    text = call("measure", "--tip-deflection", "3e-4", "--sigma", "1e-6", *BED).stdout
    assert text.startswith("tau = ") and "+-" in text and "Pa" in text
    one_error_line(run("measure", "--tip-deflection", "5e-3", *BED), "deflection")
    one_error_line(call("measure", "--tip-deflection", "3e-4", "--sigma", "-1", *BED), "sigma")


def test_quasistatic_sweep_marks_direction_jumps_and_stability(tmp_path: Path) -> None:
    out = tmp_path / "path.csv"
    proc = call("sweep", "--omega2", "0.3,0.45,0.5,0.55,0.6,0.55,0.5,0.45,0.3", "--eps", "0.95",
               "--theta0=-1.2", "--quasistatic", "--out", str(out))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    import csv

    lines = [line for line in out.read_text().splitlines() if not line.startswith("#")]
    rows = [{k.split(" [")[0]: v for k, v in r.items()} for r in csv.DictReader(lines)]
    assert [int(r["n_roots"]) for r in rows] == [1, 1, 3, 3, 1, 3, 3, 1, 1]
    assert [int(r["direction"]) for r in rows] == [0, 1, 1, 1, 1, -1, -1, -1, -1]
    assert [int(r["jump"]) for r in rows] == [0, 0, 0, 0, 1, 0, 0, 1, 0]
    assert all(int(r["stable"]) == 1 for r in rows)
    assert math.isfinite(float(rows[0]["xi"]))


def test_measure_with_a_calibration(tmp_path: Path) -> None:
    data = tmp_path / "points.csv"
    _write_points(data, sigma_column=True)
    cal = tmp_path / "cal.json"
    proc = call("calibrate", "--data", str(data), *BED, "--json")
    cal.write_text(proc.stdout)
    plain = json.loads(call("measure", "--tip-deflection", "3e-4", "--sigma", "1e-6", *BED,
                            "--json").stdout)  # fmt: skip
    out = json.loads(call("measure", "--tip-deflection", "3e-4", "--sigma", "1e-6", *BED,
                          "--calibration", str(cal), "--json").stdout)  # fmt: skip
    fitted = json.loads(cal.read_text())["parameters"]["youngs_modulus"]["value"]
    bed = hairbed.HairBed(length=1e-3, radius=50e-6, youngs_modulus=fitted,
                          channel_height=2e-3, viscosity=1.0, spacing=400e-6)  # fmt: skip
    assert out["velocity"] == pytest.approx(bed.velocity_from_tip_deflection(3e-4), rel=1e-12)
    assert out["velocity_stderr"] > plain["velocity_stderr"] * (fitted / 1e6) * 0.999
    one_error_line(call("measure", "--tip-deflection", "3e-4", *BED, "--calibration",
                        str(data)), "--calibration")  # fmt: skip


@pytest.mark.parametrize(
    ("column", "values"),
    [("pressure_gradient [Pa/m]", np.linspace(-1e3, 1e4, 8)),
     ("flow_rate [m^2/s]", np.linspace(1e-5, 1e-4, 8))],
)  # fmt: skip
def test_calibrate_pump_driven_points(tmp_path: Path, column: str, values: np.ndarray) -> None:
    """A pump-driven bed's points (both walls at rest) are fitted back from a CSV column."""
    true = hairbed.HairBed(
        length=1e-3, radius=50e-6, youngs_modulus=1.3e6, channel_height=2e-3,
        viscosity=1.0, spacing=400e-6,
    )  # fmt: skip
    kind = column.split()[0]
    d = model_tip_deflection(true, **{kind: values})
    data = tmp_path / "points.csv"
    rows = "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in zip(values, d))
    data.write_text(f"{column},tip_deflection [m]\n{rows}\n")
    proc = call("calibrate", "--data", str(data), "--sigma", "1e-6", *BED, "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["kind"] == kind
    assert out["parameters"]["youngs_modulus"]["value"] == pytest.approx(1.3e6, rel=1e-9)
    assert out["data"]["sha256"] == hairbed.calibration.points_fingerprint(
        d, sigma=1e-6, **{kind: values}
    )
    # measure with that calibration reads the drive back (the kind of the calibration)
    cal = tmp_path / "cal.json"
    cal.write_text(proc.stdout)
    args = ("measure", "--calibration", str(cal), "--tip-deflection", repr(float(d[3])))
    proc = call(*args, "--sigma", "1e-6", "--json")
    assert proc.returncode == 0, proc.stderr
    m = json.loads(proc.stdout)
    assert m[kind] == pytest.approx(float(values[3]), rel=1e-8)
    assert m[kind + "_stderr"] > 0 and m["velocity"] == 0.0
    text = call(*args).stdout
    assert "G   = " in text and "Q'  = " in text
