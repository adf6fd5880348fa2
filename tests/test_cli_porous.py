"""The porous bed on the command line (issue 29): ``solve --kappa`` and ``--model porous``.

Every number is compared with the library's own, computed here: the CLI is a thin layer over
:func:`hairbed.solve_porous`, :func:`hairbed.solve_porous_all` and a porous
:class:`hairbed.HairBed` (its ``deform``, ``sweep``, and the valve's curve and diodicity).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.cli import main
from hairbed.cli._output import to_plain
from hairbed.cli._valve import _states_doc
from hairbed.valve import diodicity, valve_curve

#: A porous bed (the README's), in SI units.
BED_KW: dict[str, Any] = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}
BED_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in BED_KW.items()]
#: A valve's bed (tests/test_cli_valve.py's): hairs leaning with the forward flow.
VALVE_KW: dict[str, Any] = {**BED_KW, "length": 1.8e-3, "base_angle": 1.0}
VALVE_ARGS = [f"--{k.replace('_', '-')}={v}" for k, v in VALVE_KW.items()]

#: The fields of a PorousState the CLI prints (besides drive, success and message).
FIELDS = (
    "omega2",
    "eps",
    "theta0",
    "kappa",
    "gamma",
    "pi",
    "q",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
    "tip_stress",
    "wall_stress",
    "tip_velocity",
    "drag_x",
    "drag_z",
    "max_angle",
    "status",
    "error_estimate",
    "residual",
    "nit",
    "num",
)


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def _same(doc: dict[str, Any], state: Any) -> None:
    """Every field of the JSON document equals the PorousState's (NaN as null)."""
    assert doc["drive"] == state.drive
    for name in FIELDS:
        want = getattr(state, name)
        got = doc[name]
        if isinstance(want, float) and math.isnan(want):
            assert got is None, name
        else:
            assert got == want, name
    assert doc["success"] == state.success
    assert doc["message"] == state.message


def test_solve_kappa_json_is_solve_porous(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = _run(
        capsys, "solve", "--omega2", "2", "--eps", "0.5", "--kappa", "0.01", "--json"
    )
    assert status == 0 and err == ""
    doc = json.loads(out)
    st = hairbed.solve_porous(2.0, 0.5, kappa=0.01)
    _same(doc, st)
    assert doc["gamma"] == 1.0  # solve_porous's default drag ratio
    assert doc["q"] is None  # the pressure drive has no q
    assert "stable" not in doc


def test_solve_kappa_table_gamma_theta0_pump(capsys: pytest.CaptureFixture[str]) -> None:
    args = ("--omega2", "1", "--eps", "0.5", "--theta0", "0.3", "--kappa", "0.05")
    status, out, err = _run(capsys, "solve", *args, "--gamma", "0.6", "--q", "3")
    assert status == 0 and err == ""
    st = hairbed.solve_porous(1.0, 0.5, 0.3, kappa=0.05, gamma=0.6, q=3.0)
    rows = {line.split()[0]: line.split()[1] for line in out.splitlines()}
    assert rows["drive"] == "flow"
    for name in FIELDS:
        assert rows[name] == f"{getattr(st, name):.15g}", name
    assert rows["message"] == st.message


def test_solve_kappa_all_and_root(capsys: pytest.CaptureFixture[str]) -> None:
    args = ("solve", "--omega2", "1.2", "--eps", "0.9", "--theta0=-1.5", "--kappa", "1e-3")
    states = hairbed.solve_porous_all(1.2, 0.9, -1.5, kappa=1e-3)
    assert len(states) == 3  # a bistable window: stable, unstable, stable
    status, out, err = _run(capsys, *args, "--all", "--json")
    assert status == 0 and err == ""
    docs = json.loads(out)
    assert [d["root"] for d in docs] == ["low", "mid", "high"]
    for doc, st in zip(docs, states):
        _same(doc, st)
        assert doc["stable"] is st.stable
    assert [d["stable"] for d in docs] == [True, False, True]
    status, out, _ = _run(capsys, *args, "--all")
    assert status == 0
    assert out.splitlines()[0].startswith("3 state(s) of the porous bed at omega2=1.2")
    assert "mid state (unstable):" in out
    status, out, _ = _run(capsys, *args, "--root", "high", "--json")
    assert status == 0
    st = hairbed.solve_porous(1.2, 0.9, -1.5, kappa=1e-3, root="high")
    _same(json.loads(out), st)
    assert json.loads(out)["tip_height"] == pytest.approx(states[2].tip_height, abs=1e-9)


def test_si_porous_solve_is_deform(capsys: pytest.CaptureFixture[str]) -> None:
    args = ("solve", *BED_ARGS, "--velocity", "0.1", "--model", "porous", "--drag", "array")
    status, out, err = _run(capsys, *args, "--json")
    assert status == 0 and err == ""
    doc = json.loads(out)
    bed = hairbed.HairBed(**BED_KW, model="porous", drag="array")
    state = bed.deform(0.1)
    assert doc["tip_deflection_m"] == state.tip_deflection
    assert doc["wall_shear_stress_Pa"] == state.wall_shear_stress
    assert doc["force_per_hair_N"] == state.force_per_hair
    assert doc["stress_ratio"] == state.stress_ratio
    assert doc["kappa"] == bed.kappa and doc["drag_ratio"] == bed.drag_ratio
    _same(doc["solution"], state.solution)
    # the dense bed (the default) differs: the option is taken
    status, out, _ = _run(capsys, "solve", *BED_ARGS, "--velocity", "0.1", "--json")
    dense = hairbed.HairBed(**BED_KW).deform(0.1)
    assert json.loads(out)["tip_deflection_m"] == dense.tip_deflection != state.tip_deflection
    status, out, _ = _run(capsys, *args)
    assert status == 0
    assert "model='porous', drag='array'" in out.splitlines()[0]
    assert "tip_stress" in out


def test_si_porous_sweep_is_bed_sweep(capsys: pytest.CaptureFixture[str], tmp_path: Any) -> None:
    pytest.importorskip("xarray")
    path = tmp_path / "porous.csv"
    status, _, err = _run(
        capsys,
        "sweep",
        *BED_ARGS,
        "--velocity",
        "0:0.2:3",
        "--model",
        "porous",
        "--drag",
        "sparse",
        "--out",
        str(path),
    )
    assert status == 0 and "wrote" in err
    lines = path.read_text().splitlines()
    head = [h.split(" [")[0] for h in lines[0].split(",")]
    col = head.index("tip_deflection")
    got = np.array([float(line.split(",")[col]) for line in lines[1:]])
    bed = hairbed.HairBed(**BED_KW, model="porous", drag="sparse")
    want = np.asarray(bed.deform(np.array([0.0, 0.1, 0.2])).tip_deflection)
    np.testing.assert_allclose(got, want, rtol=1e-14, atol=0)


def test_porous_valve_curve_and_diodicity(capsys: pytest.CaptureFixture[str]) -> None:
    bed = hairbed.HairBed(**VALVE_KW, model="porous")
    args = ("valve", "--channel-length", "0.01", *VALVE_ARGS, "--model", "porous", "--json")
    status, out, err = _run(capsys, *args, "--pressure-drop", "200")
    assert status == 0 and err == ""
    (row,) = json.loads(out)["curve"]
    curve = valve_curve(bed, np.array([200.0]), 0.01)
    assert row["flow_rate"] == float(np.atleast_1d(curve.flow_rate)[0])
    assert row["tip_height"] == float(np.atleast_1d(curve.tip_height)[0])
    dense = valve_curve(hairbed.HairBed(**VALVE_KW), np.array([200.0]), 0.01)
    assert row["flow_rate"] != float(np.atleast_1d(dense.flow_rate)[0])
    status, out, err = _run(capsys, *args, "--pressure-drop", "200", "--diodicity")
    assert status == 0 and err == ""
    (d,) = json.loads(out)["diodicity"]
    want = diodicity(bed, np.array([200.0]), 0.01)
    assert d["diodicity"] == float(np.atleast_1d(want.diodicity)[0])


def _one_error(status: int, out: str, err: str, *words: str) -> None:
    assert status == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("hairbed: error: ")
    for word in words:
        assert word in lines[0]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "0"), ("kappa",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa=-1"), ("kappa",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "1", "--gamma", "2"), ("gamma",)),
        (("solve", "--pillar", "--forcing", "1", "--kappa", "0.1"), ("--kappa", "--pillar")),
        (("solve", "--omega2", "1", "--kappa", "0.1"), ("--eps",)),
        (("solve", "--eps", "0.5", "--kappa", "0.1"), ("--omega2",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "0.1", "--pi", "1", "--q", "1"),
         ("--pi", "--q")),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "0.1", "--forcing", "1"),
         ("--forcing",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "0.1", "--all-branches"),
         ("--all-branches",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--kappa", "0.1", "--all", "--root", "mid"),
         ("--root",)),
        (("solve", *BED_ARGS, "--velocity", "0.1", "--kappa", "0.1"), ("--model porous",)),
        (("solve", "--omega2", "1", "--eps", "0.5", "--drag", "foo"), ("--drag", "foo")),
        (("solve", "--omega2", "1", "--eps", "0.5", "--model", "porous"),
         ("--model porous", "physical inputs")),
        (("solve", *BED_ARGS, "--velocity", "0.1", "--drag", "sparse"), ("--model porous",)),
        (("solve", *BED_ARGS, "--velocity", "0.1", "--model", "porous", "--all-branches"),
         ("--all-branches",)),
        (("solve", "--pillar", "--forcing", "1", "--model", "porous"), ("--pillar",)),
        (("sweep", "--pillar", "--forcing", "1", "--drag", "array"), ("--pillar",)),
        (("sweep", "--omega2", "1", "--eps", "0.5", "--model", "porous"), ("physical inputs",)),
        (("solve", *BED_ARGS, "--spacing", "100.1e-6", "--velocity", "0.1", "--model", "porous"),
         ("packing_fraction",)),
    ],
)  # fmt: skip
def test_bad_input_is_one_line(
    capsys: pytest.CaptureFixture[str], args: tuple[str, ...], words: tuple[str, ...]
) -> None:
    _one_error(*_run(capsys, *args), *words)


def test_valve_states_of_a_porous_bed(capsys: pytest.CaptureFixture[str]) -> None:
    """valve --states --model porous: the library's valve_states of the porous bed."""
    args = ("valve", "--states", "--pressure-drop", "0:200:3", "--channel-length", "0.01")
    status, out, err = _run(capsys, *args, *VALVE_ARGS, "--model", "porous", "--json")
    assert status == 0, err
    doc = json.loads(out)
    bed = hairbed.HairBed(**VALVE_KW, model="porous")
    ref = hairbed.valve.valve_states(bed, 0.01, pressure_drop=np.linspace(0.0, 200.0, 3))
    assert doc == json.loads(json.dumps(to_plain(_states_doc(ref))))
    assert doc["status"] == 0 and len(doc["points"]) == 3


def test_subprocess_solve_kappa() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "hairbed", "solve", "--omega2", "2", "--eps", "0.5"]
        + ["--kappa", "1", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    _same(json.loads(proc.stdout), hairbed.solve_porous(2.0, 0.5, kappa=1.0))
    bad = subprocess.run(
        [sys.executable, "-m", "hairbed", "solve", "--omega2", "2", "--eps", "0.5"]
        + ["--kappa", "0"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert bad.returncode == 2 and bad.stdout == ""
    assert len(bad.stderr.splitlines()) == 1 and bad.stderr.startswith("hairbed: error: ")
