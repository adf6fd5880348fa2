"""What the command line's tables say is what they hold (issue 33, "Labels", "Twirling
branches", "hairbed bench FAIL rows"): names and notes checked against independent values."""

from __future__ import annotations

import json
import re

import pytest

import hairbed
from hairbed.cli import main


def _run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


# -- --all-branches below the twirling onset says why one state ---------------------------------


@pytest.mark.parametrize(
    ("omega2", "eps", "theta0"), [(2.0, 0.5, 0.0), (0.5, 0.95, -1.2), (1e-3, 0.0, 1.4)]
)
def test_all_branches_below_the_onset_says_where_twirling_starts(capsys, omega2, eps, theta0):
    argv = ["solve", f"--omega2={omega2}", f"--eps={eps}", f"--theta0={theta0}", "--all-branches"]
    status, out, err = _run(capsys, *argv)
    assert status == 0 and err == ""
    head = out.splitlines()[0]
    assert "physical branch only" in head and "no twirling branch has a state below" in head
    onset = float(re.search(r"below omega2 = ([0-9.e+-]+),", head).group(1))
    assert onset > omega2

    # the onset brackets the forcings at which solve_all first finds a twirling state
    def twirls(w: float) -> bool:
        return any(not s.physical for s in hairbed.solve_all(w, eps, theta0))

    assert twirls(onset * (1 + 1e-8)) and not twirls(onset * (1 - 1e-8))
    status, out, err = _run(capsys, *argv, "--json")
    assert status == 0 and all(s["physical"] for s in json.loads(out))
    assert err.startswith("hairbed: note: no twirling branch has a state below"), err


def test_all_branches_above_the_onset_has_no_note(capsys):
    status, out, err = _run(capsys, "solve", "--omega2=20", "--eps=0.5", "--all-branches")
    assert status == 0 and err == "" and "physical branch only" not in out
    assert out.startswith("3 state(s) at omega2=20")


# -- the valve table's dx1 is the tip's deflection from rest ------------------------------------

VALVE = [
    "--channel-length", "0.01", "--length", "1.8e-3", "--radius", "50e-6",
    "--youngs-modulus", "1e6", "--channel-height", "2e-3", "--viscosity", "1",
    "--spacing", "400e-6", "--base-angle", "1.0",
]  # fmt: skip


def test_valve_table_gives_the_tip_deflection_from_rest(capsys):
    import math

    status, out, _ = _run(capsys, "valve", "--pressure-drop", "1e-9,200", *VALVE, "--json")
    assert status == 0
    rows = json.loads(out)["curve"]
    for r in rows:  # the displacement is the position less its value at rest, L sin(theta0)
        assert r["tip_displacement"] == pytest.approx(
            r["tip_deflection"] - 1.8e-3 * math.sin(1.0), rel=1e-12, abs=1e-18
        )
    assert abs(rows[0]["tip_displacement"]) < 1e-12  # no drop: no deflection
    assert rows[0]["tip_deflection"] == pytest.approx(1.8e-3 * math.sin(1.0), rel=1e-9)
    status, out, _ = _run(capsys, "valve", "--pressure-drop", "1e-9,200", *VALVE)
    lines = out.splitlines()
    assert "dx1 [m]" in lines[1] and "x1 [m]" not in lines[1].replace("dx1 [m]", "")
    cells = [ln.split() for ln in lines[2:]]
    assert float(cells[1][3]) == pytest.approx(rows[1]["tip_displacement"], rel=1e-5)
    assert abs(float(cells[0][3])) < 1e-12


# -- hairbed bench: rows outside their target are 'missed', said why; 11c's size ---------------


def _result(rows, quick=True):
    from hairbed import _benchmark

    meta = {
        "hairbed": "x", "numba": "y", "cpu_count": 2, "n": 1e5, "repeat": 1, "quick": quick,
        "loadavg_start": [6.5, 6.0, 5.0], "loadavg_end": [6.0, 6.0, 5.0],
        "cpu_share_single_thread": None, "sections_s": {"rows": 1.0}, "total_s": 1.0,
        "compiled_while_timing": [], "kernel_sources_changed": False,
    }  # fmt: skip
    return _benchmark.Result(tuple(rows), meta)


def test_bench_labels_a_missed_target_as_a_measurement_not_a_failure():
    from hairbed import _benchmark

    slow = _benchmark.Row.of("8", 1.1, sequential_s=2.0, threads_s=1.8, cpu_per_wall=1.1)
    fast = _benchmark.Row.of("6", 150.0, fd_ms=[1.0], ratios=[150.0], fd_success=[True])
    assert (slow.passed, slow.verdict, fast.verdict) == (False, "missed", "met")
    text = _benchmark.format_report(_result([fast, slow]))
    assert "FAIL" not in text and "PASS" not in text
    line = next(ln for ln in text.splitlines() if ln.startswith("8 "))
    assert line.rstrip().endswith("missed")
    note = next(ln for ln in text.splitlines() if ln.startswith("missed (rows 8)"))
    assert "load average of 6.50 on 2 CPUs" in note and "not an error" in note
    assert "--quick" in note
    text = _benchmark.format_report(_result([fast], quick=False))
    assert "missed" not in text  # nothing missed: no note


def test_bench_row_11c_names_the_size_its_summary_gives():
    from hairbed import _benchmark

    row = _benchmark.Row.of("11c", 1.5, points=1_000_000, serial_s=3.0, threads_s=2.0,
                            cpu_per_wall=1.5, chunks={})  # fmt: skip
    assert row.label == "1.0e+06-point sweep: dask threads (2) / serial, speedup"
    text = _benchmark.format_report(_result([row]))
    assert "1.0e+06-point sweep: serial 3.0 s" in text and "1e7" not in text
