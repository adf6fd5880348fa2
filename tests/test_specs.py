"""One parser of SPECs, and a hysteresis loop from one spec (start:stop:num:updown).

Before, an up-and-down ramp for ``--quasistatic`` was a hand-written comma list. Now
``START:STOP:NUM:updown`` is one (2 NUM - 1 points, the turning point once), parsed in one
place (``hairbed._specs``, public as ``hairbed.sweeps.parse_spec``) for the command line's
axes and paths and for ``quasistatic.sweep_with_jumps``.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from hairbed import quasistatic
from hairbed._specs import MAX_SPEC_POINTS, parse_spec
from hairbed.branches import bistable_window
from hairbed.cli import main

EPS, THETA0 = 0.9, -1.5


def test_the_forms_of_a_spec():
    assert parse_spec("0.5", "--x") == 0.5 and isinstance(parse_spec("0.5", "--x"), float)
    np.testing.assert_array_equal(parse_spec("0.1, 0.5,2", "--x"), [0.1, 0.5, 2.0])
    np.testing.assert_array_equal(parse_spec("-1.2:1.2:25", "--x"), np.linspace(-1.2, 1.2, 25))
    np.testing.assert_array_equal(parse_spec("0:1:5:lin", "--x"), np.linspace(0, 1, 5))
    np.testing.assert_array_equal(parse_spec("1e-3:1e3:7:LOG", "--x"), np.geomspace(1e-3, 1e3, 7))


@pytest.mark.parametrize(
    ("text", "ramp"),
    [
        ("0.4:0.6:200:updown", np.linspace(0.4, 0.6, 200)),
        ("0.6:0.4:5:updown", np.linspace(0.6, 0.4, 5)),  # down, then back up
        ("0.01:10:31:log:updown", np.geomspace(0.01, 10, 31)),
        ("0.01:10:31:lin:updown", np.linspace(0.01, 10, 31)),
        ("0.5:2:1:updown", np.array([0.5])),
    ],
)
def test_updown_is_the_ramp_out_and_back_with_the_turning_point_once(text, ramp):
    path = parse_spec(text, "--omega2", path=True)
    num = ramp.size
    assert path.shape == (2 * num - 1,)
    np.testing.assert_array_equal(path[:num], ramp)  # out: exactly the ramp
    np.testing.assert_array_equal(path[num - 1 :], ramp[::-1])  # back: the same values
    assert np.count_nonzero(path == ramp[-1]) == 1  # the turning point once
    assert path[0] == path[-1] == ramp[0]


@pytest.mark.parametrize(
    ("text", "path", "message"),
    [
        ("0:1:3:updown", False, "--omega2: :updown makes a path (up then down, values repeated)"),
        ("1:2", True, "--omega2 must be a number, a comma list or start:stop:num[:log][:updown]"),
        ("1:2", False, "--omega2 must be a number, a comma list or start:stop:num[:log], got"),
        ("1:2:3:4:5:6", True, "--omega2 must be"),
        ("1:2:x", True, "--omega2 must be"),
        ("1:2:3:updown:log", True, "the fourth field of start:stop:num:log is 'log' or 'lin'"),
        ("1:2:3:up", True, "'log' or 'lin' (then optionally 'updown'), got '1:2:3:up'"),
        ("1:2:0:updown", True, "num in start:stop:num must be >= 1, got 0"),
        (f"0:1:{MAX_SPEC_POINTS + 1}", False, "must be at most 1e+07"),
        ("0:1:3:log:updown", True, "a log range needs positive bounds"),
        ("0:nan:3:updown", True, "must hold finite numbers (not NaN or infinity)"),
        ("1,inf", False, "must hold finite numbers"),
    ],
)
def test_bad_specs_say_what_is_wrong(text, path, message):
    with pytest.raises(ValueError, match="^--omega2") as info:
        parse_spec(text, "--omega2", path=path)
    assert message in str(info.value)


def test_a_non_string_is_a_type_error():
    with pytest.raises(TypeError, match="omega2_path must be a SPEC"):
        parse_spec(0.5, "omega2_path")  # type: ignore[arg-type]


def test_sweep_with_jumps_takes_the_spec_and_traces_the_loop():
    text = "0.8:1.6:161:updown"
    run = quasistatic.sweep_with_jumps(text, EPS, THETA0)
    ramp = np.linspace(0.8, 1.6, 161)
    path = np.concatenate([ramp, ramp[-2::-1]])  # the same values back, not a new linspace
    same = quasistatic.sweep_with_jumps(path, EPS, THETA0)
    np.testing.assert_array_equal(run.solution.xi, same.solution.xi)
    np.testing.assert_array_equal(run.jumps, same.jumps)
    # one jump up past the upper fold, one down past the lower fold: the hysteresis loop
    w = bistable_window(EPS, THETA0)
    up = int(np.argmax(path > w.upper))
    down = 160 + int(np.argmax(path[160:] < w.lower))
    assert run.jumps.tolist() == [up, down]
    assert run.direction[1:161].tolist() == [1] * 160
    assert run.direction[161:].tolist() == [-1] * 160
    xi = np.asarray(run.solution.xi)
    assert xi[up] > xi[up - 1] + 0.1 and xi[down] < xi[down - 1] - 0.1  # snaps
    assert np.asarray(quasistatic.sweep(text, EPS, THETA0).xi).tolist() == xi.tolist()


def test_sweep_with_jumps_refuses_bad_specs_by_name():
    with pytest.raises(ValueError, match="^omega2_path must be a number, a comma list"):
        quasistatic.sweep_with_jumps("0.8:1.6", EPS, THETA0)
    with pytest.raises(ValueError, match="omega2_path must be one-dimensional"):
        quasistatic.sweep_with_jumps("0.8", EPS, THETA0)
    with pytest.raises(ValueError, match=r"omega2_path must lie in \[0, inf\), got -0.2"):
        quasistatic.sweep_with_jumps("-0.2:1:3:updown", EPS, THETA0)


def test_cli_quasistatic_updown_writes_the_loop(tmp_path, capsys):
    xr = pytest.importorskip("xarray")
    pytest.importorskip("netCDF4")
    out = tmp_path / "loop.nc"
    argv = ["sweep", "--omega2", "0.8:1.6:200:updown", "--eps", "0.9", "--theta0=-1.5"]
    assert main([*argv, "--quasistatic", "--out", str(out)]) == 0
    assert "(399 points)" in capsys.readouterr().err
    with xr.open_dataset(out) as ds:
        path = parse_spec("0.8:1.6:200:updown", "--omega2", path=True)
        np.testing.assert_array_equal(ds["omega2"].values, path)
        assert int(ds["jump"].sum()) == 2
        direction = ds["direction"].values
        assert direction[1:200].min() == 1 and direction[200:].max() == -1
        run = quasistatic.sweep_with_jumps(path, 0.9, -1.5)
        np.testing.assert_array_equal(ds["xi"].values, run.solution.xi)


def test_cli_refuses_updown_on_a_grid_axis(capsys):
    cases = [
        ["sweep", "--omega2", "0.8:1.6:5:updown", "--eps", "0.9"],
        ["sweep", "--omega2", "1", "--eps", "0.5:0.9:3:updown"],
        ["sweep", "--omega2", "1", "--eps", "0.9", "--theta0=-1:0:3:updown", "--quasistatic"],
    ]
    for argv in cases:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert ":updown makes a path" in err and len(err.splitlines()) == 1, err


# -- issue 33: two-sided logarithmic ranges, negative ones, and zero in a linear range ----------


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("+-10:1e4:4:log", [-1e4, -1e3, -100.0, -10.0, 10.0, 100.0, 1e3, 1e4]),
        ("\u00b110:\u00b11e4:2:log", [-1e4, -10.0, 10.0, 1e4]),
        ("+-10:+-1e4:2:log", [-1e4, -10.0, 10.0, 1e4]),
        ("-1e4:-10:4:log", [-1e4, -1e3, -100.0, -10.0]),
    ],
)
def test_two_sided_and_negative_log_ranges(text, expected):
    values = parse_spec(text, "--pressure-drop")
    np.testing.assert_allclose(values, expected, rtol=4e-16)
    assert np.all(np.diff(values) > 0) or text.startswith("-")


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("+-10:1e4:4", "+-start:stop:num:log"),
        ("+-10", "two-sided logarithmic range"),
        ("+-1,2", "two-sided logarithmic range"),
        ("+-1e4:10:3:log", "needs 0 < start < stop"),
        ("+-0:10:3:log", "needs 0 < start < stop"),
        ("-1:10:3:log", "a log range needs positive bounds (or both negative"),
        ("+-x:10:3:log", "must be a number"),
    ],
)
def test_two_sided_log_range_errors_say_the_form(text, words):
    with pytest.raises(ValueError, match=re.escape(words)):
        parse_spec(text, "--pressure-drop")


def test_a_linear_range_through_zero_holds_zero_exactly():
    """Wherever start + k (stop - start)/(num - 1) is 0 in exact decimal arithmetic of the
    bounds as written (k integer), the value is 0.0, not a rounding residue such as 6.9e-18;
    every other value is numpy's."""
    from fractions import Fraction

    checked = 0
    for num in range(2, 120):
        for start, stop in [(-0.05, 0.1), (-0.3, 0.7), (-2e-3, 4e-3), (-1.1, 2.2), (-0.5, 0.5)]:
            values = parse_spec(f"{start!r}:{stop!r}:{num}", "--velocity")
            a, b = Fraction(repr(start)), Fraction(repr(stop))
            for k, v in enumerate(values):
                exact = a + k * (b - a) / (num - 1)
                if exact == 0:
                    assert v == 0.0, (start, stop, num, k, v)
                    checked += 1
                else:
                    assert v == np.linspace(start, stop, num)[k]
    assert checked > 100
