"""The command line through a subprocess: output formats, exit codes, error lines."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys

import pytest
from tolerances import ATOL, RTOL

import hairbed

# The worked example of theory.md §3 (Taylor-series check at 30+ digits, independent of
# the solver): theta0 = 0, eps = 0.5, omega^2 = 2.
EXAMPLE = {
    "xi": 0.847253916541247,
    "tip_height": 0.732706963462228,
    "tip_deflection": 0.615831536923675,
}

BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip


def run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "hairbed", *args], capture_output=True, text=True, timeout=timeout
    )


def assert_one_error_line(proc: subprocess.CompletedProcess[str], *words: str) -> None:
    assert proc.returncode == 2
    assert proc.stdout == ""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith("hairbed: error: ")
    assert "Traceback" not in proc.stderr
    for w in words:
        assert w in lines[0]


def test_solve_json_matches_library_and_worked_example():
    proc = run("solve", "--omega2", "2", "--eps", "0.5", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    ref = hairbed.solve(2.0, 0.5).as_dict()
    assert set(out) == set(ref)
    for key, value in ref.items():
        if isinstance(value, float):
            assert out[key] == pytest.approx(value, rel=RTOL, abs=ATOL), key
        else:
            assert out[key] == value, key
    for key, value in EXAMPLE.items():
        assert out[key] == pytest.approx(value, rel=1e-13, abs=1e-14), key


def test_solve_table_is_readable():
    proc = run("solve", "--omega2", "2", "--eps", "0.5", "--theta0", "0.3")
    assert proc.returncode == 0
    rows = {line.split()[0]: line.split()[1] for line in proc.stdout.splitlines()}
    assert float(rows["theta0"]) == 0.3
    assert float(rows["tip_deflection"]) == pytest.approx(
        hairbed.solve(2.0, 0.5, 0.3).tip_deflection, rel=1e-13
    )


def test_demo_prints_the_worked_example():
    proc = run("demo")
    assert proc.returncode == 0
    rows = dict(line.split()[:2] for line in proc.stdout.splitlines() if line.startswith("  "))
    for key, value in EXAMPLE.items():
        assert float(rows[key]) == pytest.approx(value, rel=1e-13)


def test_all_branches_json_lists_every_state(tmp_path):
    png = tmp_path / "states.png"
    proc = run("solve", "--omega2", "20", "--eps", "0.5", "--all-branches", "--json",
               "--plot", str(png))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    states = json.loads(proc.stdout)
    assert [(s["sign"], s["n"]) for s in states] == [
        (s.sign, s.n) for s in hairbed.solve_all(20.0, 0.5)
    ]
    assert sum(s["physical"] for s in states) == 1
    # every state solves the same self-consistency: omega^2 = omega_eps^2 (1 - eps h1)
    for s in states:
        assert s["omega_eps"] ** 2 * (1 - 0.5 * s["tip_height"]) == pytest.approx(20.0, rel=1e-10)
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_invert_recovers_the_forcing():
    proc = run("invert", "--tip-deflection", repr(EXAMPLE["tip_deflection"]), "--eps", "0.5",
               "--json")  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["omega2"] == pytest.approx(2.0, rel=1e-12)


def test_physical_inputs_match_the_dimensionless_problem():
    proc = run("solve", *BED, "--velocity", "0.1", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    # omega^2 = pi a^2 L^2 eta v / (E I H phi) with I = pi a^4/4, phi = (2 pi/sqrt 3) a^2/delta^2
    a, L, eta, v, E, H, delta = 50e-6, 1e-3, 1.0, 0.1, 1e6, 2e-3, 400e-6
    phi = 2 * math.pi / math.sqrt(3) * a**2 / delta**2
    omega2 = math.pi * a**2 * L**2 * eta * v / (E * math.pi * a**4 / 4 * H * phi)
    assert out["omega2"] == pytest.approx(omega2, rel=1e-12)
    sol = hairbed.solve(omega2, L / H)
    assert out["tip_deflection_m"] == pytest.approx(sol.tip_deflection * L, rel=1e-10)
    assert out["wall_shear_stress_Pa"] == pytest.approx(
        eta * v / (H - sol.tip_height * L), rel=1e-10
    )


def test_sweep_csv(tmp_path):
    out = tmp_path / "s.csv"
    proc = run("sweep", "--omega2-min", "0.5", "--omega2-max", "4", "--num", "8", "--eps", "0.3",
               "--out", str(out))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    assert len(rows) == 8
    for row in rows:  # the header names the units (long format: tests/test_cli_sweep.py)
        w2 = float(row["omega2 [1]"])
        assert float(row["xi [1]"]) == pytest.approx(hairbed.solve(w2, 0.3).xi, rel=1e-13)


def test_sweep_to_stdout_and_netcdf(tmp_path):
    xr = pytest.importorskip("xarray")
    proc = run("sweep", "--omega2-min", "0.01", "--omega2-max", "100", "--num", "5", "--log",
               "--eps", "0.5")  # fmt: skip
    assert proc.returncode == 0
    assert proc.stdout.splitlines()[0].startswith("omega2 [1],eps [1],theta0 [rad],xi [1],")
    assert len(proc.stdout.splitlines()) == 6
    nc = tmp_path / "s.nc"
    proc = run("sweep", "--omega2-max", "3", "--num", "4", "--eps", "0.5", "--out", str(nc))
    if proc.returncode != 0:  # no netCDF engine installed: still one clean error line
        assert_one_error_line(proc, "netCDF")
        return
    ds = xr.open_dataset(nc)
    assert ds["tip_height"].values[0] == pytest.approx(1.0, rel=1e-14)  # omega^2 = 0: upright


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["solve", "--omega2", "-1", "--eps", "0.5"], ["omega2"]),
        (["solve", "--omega2", "1", "--eps", "1.5"], ["eps"]),
        (["solve", "--omega2", "1", "--eps", "0.5", "--theta0", "2"], ["theta0"]),
        (["solve", "--omega2", "nope", "--eps", "0.5"], ["--omega2"]),
        (["solve", "--eps", "0.5"], ["--omega2"]),
        (["solve", "--omega2", "1", "--eps", "0.5", "--root", "top"], ["--root"]),
        (["invert", "--tip-deflection", "1.5", "--eps", "0.5"], ["1.5"]),
        (["solve", "--length", "1e-3", "--velocity", "1"], ["--radius"]),
        (["sweep", "--eps", "0.5", "--num", "0"], ["--num"]),
        (["frobnicate"], ["frobnicate"]),
    ],
)
def test_bad_input_is_one_line(args, words, capsys):
    from hairbed.cli import main

    # in process (a subprocess each would be slow); the real process is checked below
    status = main(args)
    out, err = capsys.readouterr()
    assert_one_error_line(subprocess.CompletedProcess(args, status, out, err), *words)


@pytest.mark.parametrize(
    "args",
    [
        ["solve", "--omega2", "1", "--eps", "1.5"],
        ["invert", "--tip-deflection", "1.5", "--eps", "0.5"],
        ["frobnicate"],
    ],
)
def test_bad_input_in_a_real_process(args):
    assert_one_error_line(run(*args))


def test_help_has_examples_everywhere(capsys):
    from hairbed.cli import main

    assert "example" in run("--help").stdout
    for cmd in (["solve"], ["sweep"], ["invert"], ["figures"], ["bench"], ["demo"]):
        with pytest.raises(SystemExit) as exc:  # in process: a subprocess each would be slow
            main([*cmd, "--help"])
        assert exc.value.code == 0
        assert "example" in capsys.readouterr().out


def test_bench_runs_every_row_of_the_table(tmp_path):
    """Structure only: the values are timings of a shared machine (no timing asserts)."""
    from hairbed import _benchmark

    out = tmp_path / "sub" / "bench.json"
    # every row, whole processes and a LocalCluster included: minutes on a loaded machine
    proc = run("bench", "--quick", "--n", "1000", "--repeat", "1", "--json", str(out), timeout=600)
    assert proc.returncode == 0, proc.stderr
    # 10b (cold cache) needs --cold, 11e and 11f (bigger work) a full run
    numbers = [k for k in _benchmark.ROWS if k not in ("10b", "11e", "11f")]
    data = json.loads(out.read_text())
    points = {r["row"]: r["detail"].get("points") for r in data["rows"]}
    for k in numbers:  # a label's {points} is the size measured (the summary line's)
        label = _benchmark.ROWS[k][0].replace("{points}", f"{points.get(k) or 0:.1e}")
        assert label in proc.stdout, k
    assert "QUICK" in proc.stdout
    assert [r["row"] for r in data["rows"]] == numbers
    assert {"row", "name", "value", "unit", "target", "op", "pass"} <= set(data["rows"][0])
    assert data["meta"]["n"] == 1000 and data["meta"]["quick"] is True
    assert [p.name for p in out.parent.iterdir()] == ["bench.json"]  # no temporary file left


def test_bench_rows_and_progress():
    proc = run("bench", "--rows", "3", "5", "--repeat", "1", "--progress")
    assert proc.returncode == 0, proc.stderr
    table = [line.split()[0] for line in proc.stdout.splitlines()[3:] if line[:1].isdigit()]
    assert table == ["3", "5"]
    assert "hairbed bench: rows 3-6" in proc.stderr


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["--repeat", "0"], "--repeat"),
        (["--n", "0"], "--n"),
        (["--rows", "12"], "--rows"),
        (["--quick", "--full"], "--full"),
    ],
)
def test_bench_bad_input_is_one_line(args, word, capsys):
    from hairbed.cli import main

    status = main(["bench", *args])
    out, err = capsys.readouterr()
    assert_one_error_line(subprocess.CompletedProcess(args, status, out, err), word)


def test_figures_subcommand(tmp_path):
    proc = run("figures", "--out", str(tmp_path), "--only", "model", "theta0s", "--dpi", "50")
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.png", "theta0s.png"]
