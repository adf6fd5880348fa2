"""``hairbed design``: a TOML spec in, one line of JSON out; bad specs exit 2 (issue 32)."""

from __future__ import annotations

import json

import pytest

from hairbed.cli import main

MODEL = """
[model]
kind = "bed"
length = 1e-3
radius = 50e-6
youngs_modulus = 1e6
channel_height = 2e-3
viscosity = 1.0
spacing = 250e-6
base_angle = 0.5
density = 1200.0
"""
VARIABLES = """
[[variables]]
name = "base_angle"
low = 0.0
high = 1.4
"""
OBJECTIVE = """
[objective]
quantity = "diodicity"
pressure_drop = 1000.0
channel_length = 0.01
sense = "max"
"""
OPTIONS = """
[options]
starts = 2
"""


def _run(tmp_path, capsys, text):
    path = tmp_path / "spec.toml"
    path.write_text(text)
    status = main(["design", str(path)])
    out, err = capsys.readouterr()
    return status, out, err


def test_a_spec_gives_the_optimum_as_json(tmp_path, capsys):
    status, out, err = _run(tmp_path, capsys, MODEL + VARIABLES + OBJECTIVE + OPTIONS)
    assert status == 0 and err == ""
    res = json.loads(out)
    assert res["success"] and res["exact_gradient"]
    assert 0.7 < res["variables"]["base_angle"] < 0.85  # the interior optimum (test_design)
    assert res["design"]["base_angle"] == res["variables"]["base_angle"]
    assert any(c["validity"] for c in res["constraints"])


def test_an_infeasible_spec_prints_its_constraint_and_exits_1(tmp_path, capsys):
    cons = """
[[constraints]]
quantity = "resistance_ratio"
pressure_drop = 1000.0
channel_length = 0.01
max = 0.5
"""
    status, out, _ = _run(tmp_path, capsys, MODEL + VARIABLES + OBJECTIVE + cons + OPTIONS)
    res = json.loads(out)
    assert status == 1 and not res["success"] and res["design"] is None
    assert "resistance_ratio(dp=1000 Pa, l=0.01 m) <= 0.5" in res["message"]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (MODEL + OBJECTIVE, "at least one [[variables]]"),
        (MODEL + VARIABLES.replace("base_angle", "colour") + OBJECTIVE, "unknown design variable"),
        (MODEL + VARIABLES.replace("1.4", "-1.0") + OBJECTIVE, "inverted"),
        (MODEL + VARIABLES + OBJECTIVE.replace("diodicity", "beauty"), "unknown quantity"),
        (MODEL + VARIABLES + OBJECTIVE.replace("sense = \"max\"", "sense = \"up\""), "sense"),
        (MODEL.replace("length = 1e-3", "length = 1e-3\nfoo = 1") + VARIABLES + OBJECTIVE,
         "[model]: unknown key 'foo'"),
        (MODEL + VARIABLES + OBJECTIVE.replace("channel_length = 0.01\n", ""),
         "needs 'channel_length'"),
        ("[model\n", "not valid TOML"),
    ],
)  # fmt: skip
def test_a_bad_spec_is_one_line_and_exit_2(tmp_path, capsys, text, message):
    status, out, err = _run(tmp_path, capsys, text)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("hairbed: error:") and message in err


def test_a_missing_spec_file_exits_2(tmp_path, capsys):
    status = main(["design", str(tmp_path / "none.toml")])
    _, err = capsys.readouterr()
    assert status == 2 and "cannot read the spec" in err


def test_a_second_objective_gives_the_pareto_front_and_its_plot(tmp_path, capsys):
    second = """
[second]
quantity = "resistance_ratio"
pressure_drop = 1000.0
channel_length = 0.01
sense = "min"
"""
    options = "\n[options]\nstarts = 2\npoints = 4\n"
    path = tmp_path / "front.toml"
    path.write_text(MODEL + VARIABLES + OBJECTIVE + second + options)
    png = tmp_path / "front.png"
    status = main(["design", str(path), "--plot", str(png)])
    out, err = capsys.readouterr()
    front = json.loads(out)
    assert status == 0 and front["success"] and len(front["first"]) == 4
    assert all(b < a for a, b in zip(front["second"], front["second"][1:], strict=False))
    assert "epsilon-constraint" in front["method"]
    assert png.stat().st_size > 0 and "wrote" in err


def test_an_optimum_is_plotted_and_a_bad_plot_path_is_refused_first(tmp_path, capsys):
    path = tmp_path / "spec.toml"
    path.write_text(MODEL + VARIABLES + OBJECTIVE + OPTIONS)
    png = tmp_path / "best.png"
    assert main(["design", str(path), "--plot", str(png)]) == 0
    assert png.stat().st_size > 0
    capsys.readouterr()
    assert main(["design", str(path), "--plot", str(tmp_path / "x.nope")]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "unknown image format" in err
