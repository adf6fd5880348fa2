"""``hairbed measure --pillar --series``: the stress series of a tip-deflection CSV (issue 31)."""

from __future__ import annotations

import csv
import io
import json
import warnings

import numpy as np
import pytest

import hairbed
from hairbed.cli import main

PILLAR = [
    "--pillar",
    "--length",
    "1e-3",
    "--radius",
    "50e-6",
    "--youngs-modulus",
    "1e6",
    "--fluid",
    "water",
    "--pillar-density",
    "1000",
]


def _series(tmp_path, n=256, times=True):
    p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="water")
    t = np.arange(n) / 50.0  # 50 Hz: a slow series
    tau = 0.1 + 0.01 * np.sin(2 * np.pi * 1.0 * t)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        d = np.asarray(p.tip_deflection(tau))
    path = tmp_path / "series.csv"
    rows = ["time [s],tip_deflection [m]"] if times else ["tip_deflection [m]"]
    rows += [f"{a:.17g},{b:.17g}" if times else f"{b:.17g}" for a, b in zip(t, d)]
    path.write_text("\n".join(rows) + "\n")
    return path, tau


@pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
def test_series_to_csv_and_json(tmp_path, capsys):
    path, tau = _series(tmp_path)
    assert main(["measure", "--series", str(path), "--sigma", "1e-9", *PILLAR]) == 0
    out = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert out[0] == [
        "time [s]",
        "wall_shear_stress [Pa]",
        "wall_shear_stress_sigma [Pa]",
        "quasi_static_deflection [m]",
    ]
    got = np.array([float(r[1]) for r in out[1:]])
    # 1 Hz is far below the resonance (about 200 Hz): the stress within the band and 1e-4
    sigma = np.array([float(r[2]) for r in out[1:]])
    assert np.all(np.abs(got - tau) <= np.maximum(5 * sigma, 1e-4 * 0.1))
    assert main(["measure", "--series", str(path), "--json", *PILLAR]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["units"]["wall_shear_stress"] == "Pa" and doc["drag"] == "sader"
    assert len(doc["wall_shear_stress"]) == tau.size and doc["noise_estimated"] is True


def test_series_errors(tmp_path, capsys):
    path, _ = _series(tmp_path, times=False)
    # no rate and no time column
    assert main(["measure", "--series", str(path), *PILLAR]) == 2
    assert "--sample-rate" in capsys.readouterr().err
    assert main(["measure", "--series", str(path), *PILLAR[:-2], "--sample-rate", "50"]) == 2
    assert "--pillar-density" in capsys.readouterr().err
    assert main(["measure", "--series", str(path), *PILLAR[1:], "--sample-rate", "50"]) == 2
    assert "needs --pillar" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("tip_deflection [m]\n" + "1e-5\n" * 30 + "nan\n" + "1e-5\n" * 40)
    assert main(["measure", "--series", str(bad), *PILLAR, "--sample-rate", "50"]) == 2
    err = capsys.readouterr().err
    assert "finite" in err and "index 30" in err and len(err.strip().splitlines()) == 1
    gap = tmp_path / "gap.csv"
    gap.write_text(
        "time [s],tip_deflection [m]\n"
        + "".join(f"{0.02 * i + (0.1 if i > 40 else 0)!r},1e-5\n" for i in range(100))
    )
    assert main(["measure", "--series", str(gap), *PILLAR]) == 2
    assert "uniformly sampled" in capsys.readouterr().err
    assert main(["measure", *PILLAR]) == 2
    assert "--tip-deflection" in capsys.readouterr().err
    assert main(["measure", "--tip-deflection", "1e-5", *PILLAR]) == 2
    assert "--pillar-density needs --series" in capsys.readouterr().err


@pytest.mark.parametrize("sigma", ["nan", "inf", "-inf", "-1e-9"])
def test_series_sigma_must_be_a_noise(tmp_path, capsys, sigma):
    """--sigma NaN or negative was taken as 'estimate it', inf overflowed (the battery)."""
    path, _ = _series(tmp_path, n=32)
    assert main(["measure", "--series", str(path), f"--sigma={sigma}", *PILLAR]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sigma must be the series' noise" in err[0]
