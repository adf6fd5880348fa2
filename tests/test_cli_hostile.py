"""Hostile input to the newer options of the command line (issue 33): every refusal is one line
``hairbed: error: ...`` naming the option, exit status 2, never a traceback.

In process (:func:`hairbed.cli.main`), fast; the real-process promises are those of
tests/test_cli_errors.py.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from hairbed.cli import main


def one_error(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> str:
    """``main(argv)`` exits 2 with one line ``hairbed: error: ...`` holding every word."""
    assert main(argv) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), err
    assert "Traceback" not in err and out == "", (out, err)
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


# -- item 5: calibration files that are JSON but not a calibration ------------------------------

NOT_A_CALIBRATION = {
    "array": ("[1,2,3]", "got a JSON array"),
    "number": ("42", "got a JSON number"),
    "null": ("null", "got a JSON null"),
    "string": ('"cal"', "got a JSON string"),
    "boolean": ("true", "got a JSON boolean"),
    "nested array": ("[" * 40 + "1" + "]" * 40, "got a JSON array"),
    "nested too deeply": ("[" * 200_000 + "]" * 200_000, "nested too deeply"),
    "nested objects": ('{"a":' * 200_000 + "1" + "}" * 200_000, "nested too deeply"),
    "empty object": ("{}", "not a hairbed calibration file"),
}


@pytest.mark.parametrize("name", sorted(NOT_A_CALIBRATION))
@pytest.mark.parametrize("command", ["measure", "measure --pillar"])
def test_a_file_that_is_not_a_calibration_is_one_line(name, command, tmp_path: Path, capsys):
    text, words = NOT_A_CALIBRATION[name]
    path = tmp_path / "cal.json"
    path.write_text(text)
    argv = [*command.split(), "--tip-deflection", "1e-4", "--calibration", str(path)]
    one_error(capsys, argv, "--calibration", str(path), words)


# -- item 2: --free with an empty item ----------------------------------------------------------

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "docs" / "examples" / "points.csv"
BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip
PILLAR = [
    "--pillar", "--length", "500e-6", "--radius", "25e-6", "--youngs-modulus", "1e6",
    "--viscosity", "1e-3",
]  # fmt: skip


@pytest.mark.parametrize(
    ("free", "item"),
    [
        ("youngs_modulus,,base_angle", "item 2"),
        ("youngs_modulus,", "item 2"),
        (",youngs_modulus", "item 1"),
        (",", "item 1"),
        ("", "item 1"),
        ("youngs_modulus, ,base_angle", "item 2"),
    ],
)
@pytest.mark.parametrize("sensor", ["bed", "pillar"])
def test_free_with_an_empty_item_is_refused(capsys, free: str, item: str, sensor: str):
    options = BED if sensor == "bed" else PILLAR
    argv = ["calibrate", "--data", str(EXAMPLE), "--free", free, *options]
    one_error(capsys, argv, "--free", item, "is empty")


# -- Ranges and sweeps: the two-sided logarithmic range on the command line ---------------------

VALVE_BED = [
    "--length", "1.8e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
    "--base-angle", "1.0", "--channel-length", "0.01",
]  # fmt: skip


def test_valve_takes_a_two_sided_log_range_and_says_so_in_help(capsys):
    import json

    assert main(["valve", "--pressure-drop", "+-10:1e3:2:log", *VALVE_BED, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    drops = [r["pressure_drop"] for r in doc["curve"]]
    assert drops == pytest.approx([-1e3, -10.0, 10.0, 1e3], rel=4e-16)
    # backward flow for the negative drops, forward for the positive
    assert [r["flow_rate"] < 0 for r in doc["curve"]] == [True] * 2 + [False] * 2
    with pytest.raises(SystemExit):
        main(["valve", "--help"])
    assert "+-START:STOP:NUM:log" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    assert "+-start:stop:num:log" in capsys.readouterr().out


def test_a_range_through_zero_prints_zero(capsys):
    assert main(["sweep", *BED, "--velocity=-0.05:0.1:4"]) == 0
    rows = capsys.readouterr().out.splitlines()[1:]
    assert [r.split(",")[0] for r in rows][:2] == ["-0.05", "0.0"] and len(rows) == 4


@pytest.mark.parametrize(
    "spec", ["+-10:1e4:4", "+-1e4:10:3:log", "+-0:1:3:log", "+-10:1e4:3:log:updown"]
)
def test_bad_two_sided_ranges_are_one_line(capsys, spec: str):
    one_error(capsys, ["valve", "--pressure-drop", spec, *VALVE_BED], "--pressure-drop", spec)


# -- the newer options under the hostile values of tests/test_fuzz.py ---------------------------

SI_PILLAR = [
    "--length=500e-6", "--radius=25e-6", "--youngs-modulus=1e6", "--viscosity=1e-3",
    "--base-angle=0.1",
]  # fmt: skip
#: command -> (a valid argv, the options to replace by each hostile value).
NEW_OPTIONS: dict[str, tuple[list[str], tuple[str, ...]]] = {
    "solve-pillar-si": (
        ["solve", "--pillar", *SI_PILLAR, "--wall-shear-stress=2"],
        ("--wall-shear-stress", "--drag-scale", "--base-angle", "--radius"),
    ),
    "solve-pillar-couette": (
        ["solve", "--pillar", *SI_PILLAR, "--profile=couette", "--channel-height=1e-3",
         "--velocity=0.5"],
        ("--velocity", "--channel-height"),
    ),
    "solve-pillar-root": (
        ["solve", "--pillar", "--forcing=15", "--theta0=-1.4", "--root=mid"],
        ("--forcing", "--root"),
    ),
    "solve-pillar-all": (["solve", "--pillar", "--forcing=2", "--all"], ("--forcing",)),
    "solve-all-branches": (
        ["solve", "--omega2=2", "--eps=0.5", "--all-branches"],
        ("--omega2", "--eps", "--theta0"),
    ),
    "sweep-pillar-si": (
        ["sweep", "--pillar", *SI_PILLAR, "--wall-shear-stress=1,2"],
        ("--wall-shear-stress", "--drag-scale"),
    ),
    "linear-range-pillar": (
        ["linear-range", "--pillar", *SI_PILLAR, "--rtol=0.05"],
        ("--rtol", "--drag-scale"),
    ),
    "valve-two-sided": (
        ["valve", "--pressure-drop=+-10:100:2:log", "--channel-length=0.01", *BED[:-2],
         "--spacing=400e-6"],
        ("--pressure-drop",),
    ),
    "calibrate-free": (
        ["calibrate", "--data", str(EXAMPLE), *BED, "--free=youngs_modulus"],
        ("--free",),
    ),
}  # fmt: skip
HOSTILE = [
    "nan", "-inf", "1e400", "-1", "-1e-1", "1e308", "9" * 30, "5e-324", "0", "-0.0", "",
    "abc", "0x10", "1,2,,3", "1:2", "1:2:x", "0:1:0", "0:1:-3:log", "+-0:1:3:log",
    "+-1:10:2", "+-1e4:1:2:log", "1j", "None", " 0.5 ", "0.5\n1", ",",
]  # fmt: skip


@pytest.mark.parametrize("command", sorted(NEW_OPTIONS))
def test_new_options_answer_every_hostile_value_in_one_line(command, capsys, tmp_path,
                                                            monkeypatch):  # fmt: skip
    """Each hostile value of each new option: exit 0 with at most warning lines on stderr,
    or exit 2 with one line ``hairbed: error: ...`` (never a traceback, never exit 1)."""
    monkeypatch.chdir(tmp_path)
    base, options = NEW_OPTIONS[command]
    assert main(base) == 0, capsys.readouterr().err
    capsys.readouterr()
    failures = []
    for option in options:
        for value in HOSTILE:
            argv = [a for a in base if not a.startswith(option + "=")] + [f"{option}={value}"]
            try:
                code = main(argv)
            except SystemExit as exc:  # pragma: no cover - argparse exits are errors here
                code = 99 if exc.code is None else int(exc.code)
            _, err = capsys.readouterr()
            lines = err.splitlines()
            ok = "Traceback" not in err and (
                (code == 0 and all(ln.startswith("hairbed: warning: ") for ln in lines))
                or (code == 2 and len(lines) == 1 and lines[0].startswith("hairbed: error: "))
            )
            if not ok:
                failures.append(f"{argv}: exit {code}, stderr {err!r}")
    assert not failures, "\n".join(failures)


def test_pump_switch_that_changes_nothing_says_why_its_times_are_nan(capsys):
    """`--switch 0` from rest printed rise_time = nan with exit 0 and nothing on stderr (the
    battery's 'silent NaN'): the result's message is now one warning line."""
    code = main(
        ["pump", "--switch=0", "--duration=1", "--num-times=3", "--channel-length=0.01",
         "--length=1e-3", "--radius=50e-6", "--youngs-modulus=1e6", "--channel-height=2e-3",
         "--viscosity=1", "--spacing=400e-6"]
    )  # fmt: skip
    out, err = capsys.readouterr()
    assert code == 0 and "# rise_time = nan [s]" in out
    assert err.splitlines() == [
        "hairbed: warning: the step changes nothing (equal drops): no rise time"
    ]


def test_response_frequencies_take_the_log_spelling_of_every_spec():
    """`hairbed response --frequencies 1:1000:4:log` (the spelling of every other SPEC, and
    of `hairbed rheometer --frequencies`) was refused, although LO:HI:N is log-spaced here:
    now the same frequencies; any other fourth field is refused in one line."""
    import numpy as np

    from hairbed.cli._report import UsageError
    from hairbed.cli._response import parse_frequencies

    expected = [1.0, 10.0, 100.0, 1000.0]
    np.testing.assert_allclose(parse_frequencies("1:1000:4:log"), expected, rtol=1e-15)
    np.testing.assert_allclose(parse_frequencies("1:1000:4"), expected, rtol=1e-15)
    with pytest.raises(UsageError, match="LO:HI:N:log"):
        parse_frequencies("1:1000:4:lin")


@pytest.mark.parametrize(
    "status, code, line",
    [(0, 0, None), (2, 0, "hairbed: warning: a caveat"), (-1, 1, "hairbed: a caveat")],
)
def test_a_result_status_is_said_in_one_line(status, code, line, capsys):
    """rheometer (moduli, --laos, --pipkin) and pump exited 1 on a failed run, or 0 on a
    caveat, with NaN in the table and nothing on stderr (the help's own Pipkin example, a
    cell at 1 Hz and gamma0 = 30 whose periodic state fails): now one line says why."""
    from hairbed.cli._report import say_status

    assert say_status(status, "a\n caveat") == code
    err = capsys.readouterr().err.splitlines()
    assert err == ([] if line is None else [line])
