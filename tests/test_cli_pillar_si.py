"""An isolated pillar in SI units on the command line (issue 33, "Pillar SI on the command
line"): ``solve --pillar --length ... --wall-shear-stress``, ``solve --pillar --root``,
``linear-range --pillar`` and ``sweep --pillar --wall-shear-stress``.

The SI conversion is checked against the closed form of theory.md §12 written here,
Lambda = 16 c tau_w L^4 / (E a^4 (ln(2L/a) + 1/2)) and gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1)
(Gray & Hancock), and the dimensionless states against the mpmath reference
(tests/data/pillar_mpmath.json).
"""

from __future__ import annotations

import json
import math

import pytest
from conftest import DATA
from tolerances import PILLAR_REFERENCE_ATOL

import hairbed
from hairbed.cli import main

REF = json.loads((DATA / "pillar_mpmath.json").read_text())
WINDOW = sorted(
    (c for c in REF["cases"] if c["theta0"] == -1.4 and c["forcing"] == 15.0),
    key=lambda c: c["state_index"],
)

L, A, E, ETA = 500e-6, 25e-6, 1e6, 1e-3
SI = ["--length", "500e-6", "--radius", "25e-6", "--youngs-modulus", "1e6", "--viscosity", "1e-3"]


def forcing_of(tau: float, c: float = 1.0, length: float = L) -> float:
    """Lambda of theory.md §12, from the SI inputs (Gray & Hancock's zeta_perp)."""
    return 16 * c * tau * length**4 / (E * A**4 * (math.log(2 * length / A) + 0.5))


def gamma_of(length: float = L) -> float:
    ln = math.log(2 * length / A)
    return (ln + 0.5) / (2 * ln - 1)


def _json(capsys, *args: str):
    assert main([*args, "--json"]) == 0
    out, err = capsys.readouterr()
    assert all(ln.startswith("hairbed: warning: ") for ln in err.splitlines()), err
    return json.loads(out)


def _error(capsys, *args: str) -> str:
    assert main(list(args)) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert out == "" and len(lines) == 1 and lines[0].startswith("hairbed: error: "), err
    return lines[0]


# -- solve --pillar --root: the state of a snap-through window ----------------------------------


@pytest.mark.parametrize(("root", "k"), [("low", 0), ("mid", 1), ("high", 2)])
def test_solve_pillar_root_picks_each_state_of_the_window(capsys, root: str, k: int):
    doc = _json(capsys, "solve", "--pillar", "--forcing=15", "--theta0=-1.4", f"--root={root}")
    assert doc["status"] == 0
    for name in ("tip_deflection", "tip_height", "base_curvature"):
        assert abs(doc[name] - float(WINDOW[k][name])) <= PILLAR_REFERENCE_ATOL, name


def test_solve_pillar_all_at_zero_forcing_is_refused(capsys):
    line = _error(capsys, "solve", "--pillar", "--forcing", "0", "--all")
    assert "--all needs a non-zero --forcing" in line


# -- solve --pillar with SI inputs --------------------------------------------------------------


def test_si_pillar_state_is_the_closed_form_forcing_scaled_by_the_length(capsys):
    tau = 2.0
    doc = _json(capsys, "solve", "--pillar", *SI, "--wall-shear-stress", str(tau))
    lam, gamma = forcing_of(tau), gamma_of()
    assert doc["forcing"] == pytest.approx(lam, rel=1e-13)
    assert doc["solution"]["gamma"] == pytest.approx(gamma, rel=1e-13)
    st = hairbed.solve_pillar(lam, 0.0, gamma=gamma)  # the call the command stands for
    assert doc["tip_deflection_m"] == pytest.approx(L * st.tip_deflection, rel=1e-12)
    assert doc["tip_height_m"] == pytest.approx(L * st.tip_height, rel=1e-12)
    # d(tip deflection)/d(tau_w) against a central difference of the command's own answers
    h = 1e-4
    up = _json(capsys, "solve", "--pillar", *SI, "--wall-shear-stress", str(tau + h))
    down = _json(capsys, "solve", "--pillar", *SI, "--wall-shear-stress", str(tau - h))
    slope = (up["tip_deflection_m"] - down["tip_deflection_m"]) / (2 * h)
    assert doc["sensitivity_m/Pa"] == pytest.approx(slope, rel=1e-6)
    assert "velocity" not in doc and "reynolds_number" not in doc  # not defined: not printed


def test_si_pillar_in_a_couette_channel_takes_the_wall_speed(capsys):
    h, v = 1e-3, 0.5
    doc = _json(capsys, "solve", "--pillar", *SI, "--profile=couette", "--channel-height=1e-3",
                "--velocity", str(v))  # fmt: skip
    tau = ETA * v / h
    assert doc["wall_shear_stress_Pa"] == pytest.approx(tau, rel=1e-14)
    assert doc["velocity"] == v
    assert doc["forcing"] == pytest.approx(forcing_of(tau), rel=1e-13)


def test_si_pillar_table_names_every_row_with_its_unit(capsys):
    assert main(["solve", "--pillar", *SI, "--wall-shear-stress", "2", "--drag-scale", "2"]) == 0
    out = capsys.readouterr().out
    assert "isolated pillar Pillar(" in out and "drag_scale=2.0" in out
    assert "wall shear stress tau_w [Pa]" in out and "[m/Pa]" in out and "[N m]" in out
    forcing = float(
        next(ln.split()[1] for ln in out.splitlines() if ln.split()[:1] == ["forcing"])
    )
    assert forcing == pytest.approx(forcing_of(2.0, c=2.0), rel=1e-13)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ([*SI], "needs one of --wall-shear-stress"),
        ([*SI, "--wall-shear-stress=1", "--velocity=1"], "got --wall-shear-stress and --velocity"),
        ([*SI, "--forcing=2"], "--forcing does not apply to solve --pillar"),
        ([*SI, "--wall-shear-stress=1", "--root=mid"], "--root does not apply"),
        ([*SI, "--wall-shear-stress=1", "--all"], "--all does not apply"),
        ([*SI, "--wall-shear-stress=1", "--spacing=1e-3"], "--spacing does not apply"),
        ([*SI, "--wall-shear-stress=1", "--gamma=0.5"], "--gamma does not apply"),
        ([*SI, "--velocity=1"], "velocity drives a 'couette' channel"),
        (["--length=1e-3", "--wall-shear-stress=1"], "needs also --radius"),
        (["--forcing=1", "--wall-shear-stress=1"], "--wall-shear-stress needs the SI inputs"),
        (["--forcing=1", "--drag-scale=2"], "--drag-scale needs the SI inputs"),
        ([*SI, "--wall-shear-stress=nan"], "wall_shear_stress"),
        ([*SI, "--wall-shear-stress=1", "--drag-scale=0"], "drag_scale"),
    ],
)
def test_si_pillar_bad_input_is_one_line(capsys, args: list[str], words: str):
    assert words in _error(capsys, "solve", "--pillar", *args)


@pytest.mark.parametrize("args", [["--wall-shear-stress=1"], ["--drag-scale=2"]])
def test_si_pillar_options_need_pillar(capsys, args: list[str]):
    assert "needs --pillar" in _error(capsys, "solve", "--omega2=1", "--eps=0.5", *args)


# -- linear-range --pillar ----------------------------------------------------------------------


def test_linear_range_of_a_pillar_ends_where_11_lambda_over_120_is_off_by_rtol(capsys):
    """The linear calibration of a cantilever under a load growing linearly with height is
    x1 = 11 Lambda/120 (beam theory); at the returned deflection D it is off by -rtol from the
    exact stress, whose state puts the tip at D."""
    rtol = 0.05
    doc = _json(capsys, "linear-range", "--pillar", *SI, "--rtol", str(rtol))
    assert set(doc) == {"rtol", "wall_shear_stress"}  # a sublayer has no wall speed
    r = doc["wall_shear_stress"]
    d, tau = r["tip_deflection"], r["wall_shear_stress"]
    assert r["status"] == 0 and r["velocity"] is None
    tau_linear = (d / L) * 120 / 11 / forcing_of(1.0)
    assert tau_linear / tau - 1 == pytest.approx(-rtol, abs=1e-9)
    assert r["wall_shear_stress_error"] == pytest.approx(-rtol, abs=1e-9)
    exact = hairbed.solve_pillar(forcing_of(tau), 0.0, gamma=gamma_of())
    assert L * exact.tip_deflection == pytest.approx(d, rel=1e-9)
    assert main(["linear-range", "--pillar", *SI, "--rtol", str(rtol)]) == 0
    out = capsys.readouterr().out
    assert "v = nan" not in out and "nan" not in out and "no wall speed" in out


def test_linear_range_of_a_couette_pillar_gives_the_wall_speed(capsys):
    doc = _json(capsys, "linear-range", "--pillar", *SI, "--profile=couette",
                "--channel-height=1e-3")  # fmt: skip
    r = doc["wall_shear_stress"]
    assert r["velocity"] == pytest.approx(r["wall_shear_stress"] * 1e-3 / ETA, rel=1e-14)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--pillar", *SI, "--spacing=1e-3"], "--spacing does not apply"),
        (["--pillar", "--length=1e-3"], "needs also --radius"),
        (["--drag-scale=2", "--length=1e-3"], "--drag-scale needs --pillar"),
        (["--pillar", *SI, "--rtol=2"], "rtol"),
    ],
)
def test_linear_range_pillar_bad_input_is_one_line(capsys, args: list[str], words: str):
    assert words in _error(capsys, "linear-range", *args)


# -- measure: a pillar's calibration needs no --pillar; no 'v = nan' ----------------------------


def test_measure_of_a_sublayer_pillar_prints_no_nan_speed(capsys):
    args = ["measure", "--pillar", *SI, "--tip-deflection", "5e-5", "--sigma", "1e-7"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "nan" not in out and "no wall speed" in out and out.startswith("tau = ")
    tau = float(out.split()[2])
    exact = hairbed.solve_pillar(forcing_of(tau), 0.0, gamma=gamma_of())
    assert L * exact.tip_deflection == pytest.approx(5e-5, rel=1e-5)  # tau printed to 6 digits
    assert main(["measure", "--pillar", *SI, "--profile=couette", "--channel-height=1e-3",
                 "--tip-deflection", "5e-5"]) == 0  # fmt: skip
    out = capsys.readouterr().out
    v = float(next(ln.split()[2] for ln in out.splitlines() if ln.startswith("v ")))
    assert v == pytest.approx(tau * 1e-3 / ETA, rel=1e-5)


def test_measure_takes_the_sensor_from_the_calibration_file(capsys, tmp_path):
    tau = [1.0, 2.0, 4.0, 8.0]
    pillar = hairbed.Pillar(length=L, radius=A, youngs_modulus=1.2e6, viscosity=ETA)
    d = [float(pillar.deform(t).tip_deflection) for t in tau]
    data = tmp_path / "points.csv"
    data.write_text("wall_shear_stress,tip_deflection\n" + "".join(
        f"{t!r},{x!r}\n" for t, x in zip(tau, d)))  # fmt: skip
    assert main(["calibrate", "--data", str(data), *["--pillar", *SI], "--json"]) == 0
    cal = tmp_path / "cal.json"
    cal.write_text(capsys.readouterr().out)
    with_flag = _json(capsys, "measure", "--pillar", "--calibration", str(cal),
                      "--tip-deflection", repr(d[2]))  # fmt: skip
    without = _json(capsys, "measure", "--calibration", str(cal), "--tip-deflection", repr(d[2]))
    assert without == with_flag
    assert without["wall_shear_stress"] == pytest.approx(4.0, rel=1e-8)
    assert main(["measure", "--calibration", str(cal), "--tip-deflection", repr(d[2])]) == 0
    out = capsys.readouterr().out
    assert "nan" not in out and "no wall speed" in out


# -- sweep --pillar with SI inputs ----------------------------------------------------------------


def test_sweep_of_an_si_pillar_over_wall_shear_stress(capsys, tmp_path):
    xr = pytest.importorskip("xarray")
    out = tmp_path / "pillar.nc"
    assert main(["sweep", "--pillar", *SI, "--wall-shear-stress", "0:8:5", "--out", str(out)]) == 0
    capsys.readouterr()
    with xr.open_dataset(out) as ds:
        tau = ds["wall_shear_stress"].values
        assert tau.tolist() == [0.0, 2.0, 4.0, 6.0, 8.0]
        assert ds["wall_shear_stress"].attrs["units"] == "Pa"
        assert ds["tip_deflection"].attrs["units"] == "m"
        assert ds.attrs["gamma"] == pytest.approx(gamma_of(), rel=1e-14)
        for k, t in enumerate(tau):
            lam = forcing_of(float(t))
            assert float(ds["forcing"][k]) == pytest.approx(lam, rel=1e-13, abs=0)
            st = hairbed.solve_pillar(lam, 0.0, gamma=gamma_of())
            assert float(ds["tip_deflection"][k]) == pytest.approx(
                L * st.tip_deflection, rel=1e-12, abs=1e-20
            )
            assert float(ds["scaled_tip_height"][k]) == pytest.approx(st.tip_height, rel=1e-12)
        assert "velocity" not in ds and "reynolds_number" not in ds  # no column of NaN


def test_sweep_of_an_si_pillar_in_a_couette_channel_over_wall_speed(capsys):
    argv = ["sweep", "--pillar", *SI, "--profile=couette", "--channel-height=1e-3",
            "--velocity", "0.5,1"]  # fmt: skip
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    head = lines[0].split(",")
    assert head[0] == "velocity [m s-1]" and "wall_shear_stress [Pa]" in head
    rows = [dict(zip(head, map(float, ln.split(",")))) for ln in lines[1:]]
    for row, v in zip(rows, (0.5, 1.0), strict=True):
        assert row["wall_shear_stress [Pa]"] == pytest.approx(ETA * v / 1e-3, rel=1e-14)
        assert row["forcing [1]"] == pytest.approx(forcing_of(ETA * v / 1e-3), rel=1e-13)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        ([*SI], "needs one of --wall-shear-stress SPEC"),
        ([*SI, "--wall-shear-stress=1", "--velocity=1"], "got --wall-shear-stress and --velocity"),
        ([*SI, "--forcing=1"], "--forcing does not apply to sweep --pillar"),
        ([*SI, "--wall-shear-stress=1", "--chunks=2"], "--chunks does not apply"),
        ([*SI, "--wall-shear-stress=1", "--theta0=0.1"], "--theta0 does not apply"),
        ([*SI, "--wall-shear-stress=1:2:x"], "--wall-shear-stress must be"),
        ([*SI, "--wall-shear-stress=1", "--spacing=1e-3"], "--spacing does not apply"),
        (["--forcing=1", "--drag-scale=2"], "--drag-scale needs the SI inputs"),
    ],
)
def test_sweep_of_an_si_pillar_bad_input_is_one_line(capsys, args: list[str], words: str):
    assert words in _error(capsys, "sweep", "--pillar", *args)
