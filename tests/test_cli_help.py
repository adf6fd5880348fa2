"""Help and docs that match behaviour: stated defaults, required options, tables.

Every default a ``--help`` text states is the one the command really uses: the parser's own
default, or, for an option whose parser default is None (not given, so that a conflict with
other options can be told), the value the command falls back to (checked by running it).
A required option states no default; an option group names only options its command has.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from hairbed.cli import build_parser, main

ROOT = Path(__file__).resolve().parent.parent

#: "default X" in a help text: X is the first word after it (a number, a name, a path).
DEFAULT = re.compile(r"\bdefault:?\s+([^\s,;)]+)")


def subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(sub.choices)


def _same(stated: str, real: object) -> bool:
    if isinstance(real, bool) or real is None:
        return False
    if isinstance(real, (int, float)):
        try:
            return float(stated) == float(real)
        except ValueError:
            return False
    return stated.strip("./") == str(real).strip("./")


#: Options whose parser default is None (given or not) and whose help states the value the
#: command uses when not given; each is checked by behaviour in the tests below.
FALLBACKS = {
    ("solve", "theta0"): "0",
    ("invert", "theta0"): "0",
    ("sweep", "theta0"): "0",
    ("sweep", "sign"): "1",
    ("sweep", "n"): "0",
    ("sweep", "omega2_min"): "0",
    ("sweep", "omega2_max"): "10",
    ("sweep", "num"): "101",
    ("solve", "base_angle"): "0",
    ("sweep", "base_angle"): "0",
    ("invert", "base_angle"): "0",
    ("calibrate", "base_angle"): "0",
    ("measure", "base_angle"): "0",
    ("linear-range", "base_angle"): "0",
    ("valve", "base_angle"): "0",
    ("pump", "base_angle"): "0",
    ("rheometer", "base_angle"): "0",
    ("bench", "n"): "1e5",
    ("bench", "rows"): "all",
    ("sweep", "out"): "CSV",
    ("bistability", "out"): "CSV",  # test_bistability_map: CSV on stdout without --out
    ("solve", "root"): "inside",  # "inside a bistable window, all of them"
    # the pillar's (test_cli_pillar.py::test_pillar_fallbacks_are_the_library_defaults)
    **{
        (c, d): v
        for c in ("solve", "sweep")
        for d, v in (("profile", "sublayer"), ("gamma", "0.5"), ("tip_load", "0"))
    },
    ("calibrate", "profile"): "sublayer",
    ("measure", "profile"): "sublayer",
    ("linear-range", "profile"): "sublayer",
    # the pillar sensor's drag scale (hairbed.Pillar's default drag_scale = 1)
    ("calibrate", "drag_scale"): "1",
    ("measure", "drag_scale"): "1",
    ("linear-range", "drag_scale"): "1",
    ("solve", "drag_scale"): "1",
    ("sweep", "drag_scale"): "1",
    # the pillar sensor in time (a Pillar's defaults; --t-end's from its decay time)
    **{
        (c, d): v
        for c in ("simulate", "response")
        for d, v in (("profile", "sublayer"), ("drag_scale", "1"), ("base_angle", "0"))
    },
    ("simulate", "t_end"): "20",
}


@pytest.mark.parametrize("command", sorted(subparsers()))
def test_every_stated_default_is_the_real_one(command: str) -> None:
    p = subparsers()[command]
    for action in p._actions:
        text = action.help or ""
        if action.required:
            assert "default" not in text, f"{command} {action.option_strings}: required"
            continue
        m = DEFAULT.search(text)
        if m is None or isinstance(action, argparse._HelpAction):
            continue
        stated = m.group(1)
        if action.default is None:
            key = (command, action.dest)
            assert key in FALLBACKS, f"{command} --{action.dest}: says default {stated}, is None"
            assert FALLBACKS[key] == stated, f"{command} --{action.dest}"
        else:
            assert _same(stated, action.default), (
                f"{command} {action.option_strings}: help says default {stated}, "
                f"parser default {action.default!r}"
            )


@pytest.mark.parametrize("command", sorted(subparsers()))
def test_group_titles_name_real_options(command: str) -> None:
    p = subparsers()[command]
    options = {s for a in p._actions for s in a.option_strings}
    for group in p._action_groups:
        for name in re.findall(r"--[a-z][a-z0-9-]*", group.title or ""):
            assert name in options, f"{command}: group {group.title!r} names {name}"


def test_theta0_fallback_is_zero(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["solve", "--omega2", "2", "--eps", "0.5", "--json"]) == 0
    assert '"theta0": 0.0' in capsys.readouterr().out


def test_bistability_theta0_is_required(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bistability", "--eps", "0.9"]) == 2
    assert "--theta0" in capsys.readouterr().err


def test_si_solve_table_describes_every_row(capsys: pytest.CaptureFixture[str]) -> None:
    bed = [
        "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
        "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
    ]  # fmt: skip
    assert main(["solve", *bed, "--velocity", "1e-3"]) == 0
    out = capsys.readouterr().out
    head = out.split("dimensionless state:")[0].splitlines()[1:]
    for line in head:
        assert len(line.split()) >= 3, f"no description: {line!r}"


def test_figures_unknown_set_key_names_it(capsys: pytest.CaptureFixture[str], tmp_path) -> None:
    pytest.importorskip("matplotlib")
    code = main(["figures", "--out", str(tmp_path), "--only", "model", "--set", "foo=1"])
    err = capsys.readouterr().err
    assert code == 2 and "foo" in err and "theta0" in err
    assert not list(tmp_path.iterdir())


def test_readme_negative_values_note_is_current(capsys: pytest.CaptureFixture[str]) -> None:
    # `--theta0 -1.2:1.2:3` parses as a value: the README must not ask for the `=` form
    assert main(["sweep", "--omega2", "1", "--eps", "0.5", "--theta0", "-1.2:1.2:3"]) == 0
    capsys.readouterr()
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "when it starts\nwith `-`" not in readme and "when it starts with `-`" not in readme


def test_upper_fold_has_the_lower_xi_and_says_so() -> None:
    import hairbed

    f = hairbed.branches.folds(0.9, -1.5)
    assert f.upper is not None and f.lower is not None and f.upper.xi < f.lower.xi
    for text in (hairbed.branches.Folds.__doc__ or "", hairbed.branches.folds.__doc__ or ""):
        assert "smaller xi" in text
    docs = (ROOT / "docs" / "theory.md").read_text(encoding="utf-8")
    assert "smaller xi" in docs
