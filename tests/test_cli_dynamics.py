"""``hairbed simulate`` and ``hairbed response``: the pillar sensor in time on the command line.

The numbers must be the library's (``Pillar.simulate``, ``Pillar.frequency_response``) with the
options' meaning (a step from rest, a sine in Hz, phases in degrees); bad input is one line on
stderr and exit status 2; Ctrl-C one line and 130.
"""

from __future__ import annotations

import csv
import io
import json
import math
import warnings
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed import ModelValidityWarning, Pillar
from hairbed.cli import main
from hairbed.dynamics import sine

PILLAR = ["--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6"]
WATER = [*PILLAR, "--fluid", "water"]


def _pillar(fluid: str = "water") -> Pillar:
    return Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid=fluid)


def _csv(text: str) -> tuple[list[str], np.ndarray]:
    rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith("#")]
    return rows[0], np.array(rows[1:], dtype=float)


def _one_error_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if not ln.startswith("hairbed: warning:")]
    assert len(lines) == 1, err
    assert lines[0].startswith("hairbed: error: "), err
    return lines[0]


@pytest.fixture(autouse=True)
def _quiet() -> object:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        yield


def test_simulate_csv_is_the_library_step(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["simulate", "--wall-shear-stress", "0.7", "--overdamped", "--t-end", "2e-3"]
    assert main([*args, "--samples", "11", *WATER]) == 0
    header, data = _csv(capsys.readouterr().out)
    assert header == [
        "time [s]",
        "wall_shear_stress [Pa]",
        "tip_deflection [m]",
        "tip_height [m]",
        "tip_angle [rad]",
        "base_moment [N m]",
    ]
    t = np.linspace(0.0, 2e-3, 11)
    ref = _pillar().simulate(0.7, t, overdamped=True)
    np.testing.assert_allclose(data[:, 0], t, rtol=1e-15)
    for j, name in enumerate(
        ("wall_shear_stress", "tip_deflection", "tip_height", "tip_angle", "base_moment"), 1
    ):
        np.testing.assert_allclose(data[:, j], getattr(ref, name), rtol=1e-14, atol=0)
    # relaxed after 3.3 T: the static state of the same stress
    assert data[-1, 2] == pytest.approx(_pillar().deform(0.7).tip_deflection, rel=1e-8)


def test_simulate_sine_json_in_hertz(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["simulate", "--wall-shear-stress", "1", "--amplitude", "0.3", "--frequency", "150"]
    args += ["--t-end", "0.01", "--samples", "21", "--pillar-density", "970", "--json"]
    assert main([*args, *PILLAR, "--fluid", "air"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["units"]["tip_deflection"] == "m" and doc["units"]["base_moment"] == "N m"
    t = np.linspace(0.0, 0.01, 21)
    ref = _pillar("air").simulate(sine(1.0, 0.3, 2.0 * math.pi * 150.0), t, pillar_density=970.0)
    assert doc["success"] and doc["status"] == 0
    np.testing.assert_allclose(doc["tip_deflection"], ref.tip_deflection, rtol=1e-14, atol=0)
    np.testing.assert_allclose(
        doc["wall_shear_stress"], 1.0 + 0.3 * np.sin(2.0 * math.pi * 150.0 * t), rtol=1e-12
    )


def test_simulate_default_t_end_is_twenty_decay_times(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """With inertia every ringing mode decays as exp(-t/(2 mu T)): t_end = 40 mu T, with
    T = zeta L^4/(E I), mu = (rho_s + rho_f) pi a^2/(zeta T) written here."""
    args = ["simulate", "--wall-shear-stress", "1", "--pillar-density", "970"]
    assert main([*args, "--samples", "3", "--json", *WATER]) == 0
    doc = json.loads(capsys.readouterr().out)
    eta, rho_f = hairbed.pillars.FLUIDS["water"]
    zeta = 4.0 * math.pi * eta / (math.log(2.0 * 20.0) + 0.5)
    t_scale = zeta * 1e-3**4 / (1e6 * math.pi * (50e-6) ** 4 / 4.0)
    mu = (970.0 + rho_f) * math.pi * (50e-6) ** 2 / (zeta * t_scale)
    assert doc["time"][-1] == pytest.approx(40.0 * mu * t_scale, rel=1e-12)
    assert doc["success"]
    static = _pillar().deform(1.0).tip_deflection
    assert doc["tip_deflection"][-1] == pytest.approx(static, rel=1e-6)


def test_simulate_netcdf_carries_cf_units(
    tmp_path: Any, capsys: pytest.CaptureFixture[str]
) -> None:
    xr = pytest.importorskip("xarray")
    pytest.importorskip("netCDF4")
    out = tmp_path / "run.nc"
    args = ["simulate", "--wall-shear-stress", "1", "--overdamped", "--t-end", "1e-3"]
    assert main([*args, "--samples", "6", "--out", str(out), *WATER]) == 0
    ds = xr.load_dataset(out)
    assert ds["tip_deflection"].dims == ("time",)
    assert ds["time"].attrs["units"] == "s"
    assert ds["tip_deflection"].attrs["units"] == "m"
    assert ds["base_moment"].attrs["units"] == "N m"
    assert ds["wall_shear_stress"].attrs["units"] == "Pa"
    ref = _pillar().simulate(1.0, np.linspace(0.0, 1e-3, 6), overdamped=True)
    np.testing.assert_allclose(ds["tip_deflection"].values, ref.tip_deflection, rtol=1e-15)


def test_response_csv_and_summary_are_the_librarys(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["response", "--pillar-density", "970", "--frequencies", "10:1000:7"]
    assert main([*args, *WATER]) == 0
    text = capsys.readouterr().out
    summary = {
        ln[2:].split(" = ")[0].split(" [")[0]: ln.split(" = ")[1]
        for ln in text.splitlines()
        if ln.startswith("# ")
    }
    header, data = _csv(text)
    assert header == ["frequency [Hz]", "magnitude [m/Pa]", "phase [deg]"]
    f = np.geomspace(10.0, 1000.0, 7)
    ref = _pillar().frequency_response(f, pillar_density=970.0)
    np.testing.assert_allclose(data[:, 0], f, rtol=1e-11)
    np.testing.assert_allclose(data[:, 1], ref.magnitude, rtol=1e-11)
    np.testing.assert_allclose(data[:, 2], ref.phase * 180.0 / math.pi, rtol=1e-11, atol=1e-11)
    assert float(summary["resonance_frequency"]) == pytest.approx(ref.resonance_frequency, 1e-9)
    assert float(summary["quality_factor"]) == pytest.approx(ref.quality_factor, rel=1e-9)
    assert float(summary["bandwidth"]) == pytest.approx(ref.bandwidth, rel=1e-9)
    assert summary["drag"] == "sader"
    assert "[Hz]" in next(ln for ln in text.splitlines() if "resonance" in ln)


def test_response_json_list_and_options(capsys: pytest.CaptureFixture[str]) -> None:
    args = ["response", "--pillar-density", "970", "--frequencies", "0,100,447.5"]
    args += ["--drag-model", "quasi-steady", "--wall-shear-stress", "0.5"]
    args += ["--magnitude-tolerance", "0.1", "--phase-tolerance", "10", "--json"]
    assert main([*args, *PILLAR, "--fluid", "air"]) == 0
    doc = json.loads(capsys.readouterr().out)
    ref = _pillar("air").frequency_response(
        [0.0, 100.0, 447.5],
        wall_shear_stress=0.5,
        pillar_density=970.0,
        drag="quasi-steady",
        magnitude_tolerance=0.1,
        phase_tolerance=math.radians(10.0),
    )
    assert doc["units"]["magnitude"] == "m/Pa" and doc["units"]["phase"] == "deg"
    np.testing.assert_allclose(doc["magnitude"], ref.magnitude, rtol=1e-14)
    np.testing.assert_allclose(doc["phase"], np.degrees(ref.phase), rtol=1e-14, atol=1e-14)
    assert doc["resonance_frequency"] == ref.resonance_frequency
    assert doc["bandwidth"] == ref.bandwidth and doc["phase_tolerance"] == pytest.approx(10.0)
    assert doc["drag"] == "quasi-steady"


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["simulate", "--wall-shear-stress", "1", *WATER], "--pillar-density"),
        (
            [
                "simulate",
                "--wall-shear-stress",
                "1",
                "--overdamped",
                "--pillar-density",
                "970",
                *WATER,
            ],
            "not both",
        ),  # fmt: skip
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--amplitude", "1", *WATER],
            "--amplitude needs --frequency",
        ),  # fmt: skip
        (
            [
                "simulate",
                "--wall-shear-stress",
                "1",
                "--overdamped",
                "--frequency",
                "-5",
                "--amplitude",
                "1",
                *WATER,
            ],
            "--frequency",
        ),  # fmt: skip
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--t-end", "-1", *WATER],
            "--t-end",
        ),  # fmt: skip
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--samples", "1", *WATER],
            "--samples",
        ),  # fmt: skip
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--out", "x.txt", *WATER],
            "unknown output format",
        ),  # fmt: skip
        (
            [
                "simulate",
                "--wall-shear-stress",
                "1",
                "--overdamped",
                "--profile",
                "wall-law",
                *WATER,
            ],
            "'wall-law'",
        ),  # fmt: skip
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--num", "3", *WATER],
            "num",
        ),  # fmt: skip
        (["simulate", "--wall-shear-stress", "1", "--overdamped", *PILLAR], "--viscosity"),
        (
            ["simulate", "--wall-shear-stress", "1", "--overdamped", "--spacing", "1e-4", *WATER],
            "--spacing",
        ),  # fmt: skip
        (["response", *WATER], "--pillar-density"),
        (
            ["response", "--pillar-density", "970", "--frequencies", "1:10", *WATER],
            "--frequencies",
        ),  # fmt: skip
        (
            ["response", "--pillar-density", "970", "--frequencies", "1,-2", *WATER],
            "frequency must be >= 0",
        ),  # fmt: skip
        (
            ["response", "--pillar-density", "970", "--frequencies", "a,b", *WATER],
            "--frequencies",
        ),  # fmt: skip
        (["response", "--pillar-density", "-970", *WATER], "pillar_density"),
        (
            ["response", "--pillar-density", "970", "--phase-tolerance", "200", *WATER],
            "--phase-tolerance",
        ),  # fmt: skip
        (["response", "--pillar-density", "970", *PILLAR, "--viscosity", "1e-3"], "density"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert needle in _one_error_line(err), err


def test_an_error_is_the_only_line_even_after_warnings(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """No static state at 1e30 Pa: the error alone, not the validity warnings before it."""
    args = ["response", "--pillar-density", "970", "--wall-shear-stress", "1e30", *WATER]
    with warnings.catch_warnings():
        warnings.simplefilter("always")  # as a user's shell has them
        assert main(args) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("hairbed: error: wall_shear_stress")


def test_ctrl_c_is_one_line_and_130(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    def interrupted(*args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(Pillar, "simulate", interrupted)
    args = ["simulate", "--wall-shear-stress", "1", "--overdamped", "--t-end", "1e-3"]
    assert main([*args, *WATER]) == 130
    assert capsys.readouterr().err.strip() == "hairbed: interrupted"
