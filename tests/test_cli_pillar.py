"""``hairbed solve --pillar`` and ``hairbed sweep --pillar`` (issue 21): the values against the
library's pillar states computed here and the mpmath reference, the JSON round trip, the
tables' units, and bad input as one line with exit status 2."""

from __future__ import annotations

import json
import math

import pytest
from conftest import DATA
from tolerances import PILLAR_REFERENCE_ATOL

import hairbed
from hairbed._variables import PILLAR
from hairbed.cli import main

REF = json.loads((DATA / "pillar_mpmath.json").read_text())
#: The three states of the snap-through window at theta0 = -1.4, Lambda = 15 (sublayer).
WINDOW = sorted(
    (c for c in REF["cases"] if c["theta0"] == -1.4 and c["forcing"] == 15.0),
    key=lambda c: c["state_index"],
)
#: The state fields the command prints, in the PILLAR table's order.
FIELDS = tuple(k for k in PILLAR if k not in ("height_ratio", "stable"))


def _run(capsys, *args: str) -> tuple[int, str, str]:
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def _json(capsys, *args: str):
    status, out, err = _run(capsys, *args, "--json")
    assert status == 0 and err == "", err
    return json.loads(out)


def test_one_state_is_the_library_state_with_every_field(capsys):
    doc = _json(capsys, "solve", "--pillar", "--forcing=2", "--theta0=0.3", "--gamma=0.7")
    st = hairbed.solve_pillar(2.0, 0.3, gamma=0.7)
    assert set(doc) == {"profile", "message", *FIELDS}
    for name in FIELDS:
        assert doc[name] == getattr(st, name), name
    assert doc["profile"] == "sublayer" and doc["message"] == "ok"


def test_pillar_fallbacks_are_the_library_defaults(capsys):
    """--profile, --gamma and --tip-load not given: sublayer, 0.5 and 0, as their help says
    (tests/test_cli_help.py), in solve and in sweep."""
    doc = _json(capsys, "solve", "--pillar", "--forcing=3")
    st = hairbed.solve_pillar(3.0, 0.0, profile="sublayer", gamma=0.5, tip_load=0.0)
    assert doc["profile"] == "sublayer" and doc["gamma"] == 0.5 and doc["tip_load"] == 0.0
    assert doc["tip_deflection"] == st.tip_deflection
    pytest.importorskip("xarray")
    status, out, err = _run(capsys, "sweep", "--pillar", "--forcing=3")
    head, row = out.strip().splitlines()
    values = dict(zip((h.split()[0] for h in head.split(",")), row.split(",")))
    assert float(values["gamma"]) == 0.5 and float(values["tip_load"]) == 0.0
    assert float(values["tip_deflection"]) == pytest.approx(st.tip_deflection, abs=1e-14)


def test_the_table_names_every_field_with_its_unit(capsys):
    status, out, err = _run(capsys, "solve", "--pillar", "--forcing=2")
    assert status == 0 and err == ""
    st = hairbed.solve_pillar(2.0)
    rows = {line.split()[0]: line for line in out.splitlines()}
    for name in FIELDS:
        assert PILLAR[name].heading in rows[name], name
    assert "drag F_x [EI/L^2]" in rows["drag_x"] and "[L]" in rows["tip_deflection"]
    assert float(rows["tip_deflection"].split()[1]) == pytest.approx(st.tip_deflection, 1e-14)


def test_small_forcing_is_the_linear_cantilever(capsys):
    """x1 = 11 Lambda/120 (theory.md §12) up to O(Lambda^3) at theta0 = 0."""
    doc = _json(capsys, "solve", "--pillar", "--forcing=1e-4")
    assert doc["tip_deflection"] == pytest.approx(11e-4 / 120, rel=1e-9)


def test_slenderness_is_gray_and_hancock(capsys):
    doc = _json(capsys, "solve", "--pillar", "--forcing=1", "--slenderness=20")
    lg = math.log(40.0)
    assert doc["gamma"] == pytest.approx((lg + 0.5) / (2 * lg - 1), rel=1e-15)
    assert doc["tip_deflection"] == hairbed.solve_pillar(1.0, gamma=doc["gamma"]).tip_deflection


def test_inverse_is_the_reference(capsys):
    case = next(c for c in REF["inverse"] if c["profile"] == "poiseuille")
    ratio = case["profile_parameters"]["L/H"]
    x1 = float(case["tip_deflection"])
    doc = _json(
        capsys, "solve", "--pillar", f"--tip-deflection={x1}", "--profile=poiseuille",
        f"--height-ratio={ratio}",
    )  # fmt: skip
    assert doc["profile"] == "poiseuille" and doc["height_ratio"] == ratio
    assert abs(doc["forcing"] - float(case["forcing"])) <= PILLAR_REFERENCE_ATOL * float(
        case["forcing"]
    )
    st = hairbed.solve_pillar_inverse(x1, profile="poiseuille", height_ratio=ratio)
    assert doc["forcing"] == st.forcing


def test_all_lists_the_three_states_of_the_window(capsys):
    docs = _json(capsys, "solve", "--pillar", "--forcing=15", "--theta0=-1.4", "--all")
    assert [d["stable"] for d in docs] == [True, False, True]
    for doc, case in zip(docs, WINDOW, strict=True):
        for name in ("tip_deflection", "tip_height", "base_curvature"):
            assert abs(doc[name] - float(case[name])) <= PILLAR_REFERENCE_ATOL, name
    status, out, err = _run(capsys, "solve", "--pillar", "--forcing=15", "--theta0=-1.4", "--all")
    assert "3 pillar state(s)" in out and out.count("(unstable)") == 1


def test_branch_and_its_folds(capsys):
    doc = _json(capsys, "solve", "--pillar", "--branch=40", "--theta0=-1.4")
    br = hairbed.continue_pillar(40.0, -1.4)
    assert doc["status"] == 0 and len(doc["folds"]) == 2
    assert doc["tip_deflection"] == br.tip_deflection.tolist()
    assert doc["forcing"] == br.forcing.tolist()
    assert doc["stable"] == br.stable.tolist()
    # the reference locates them to within its continuation step (theory.md §12): 16.0, 13.7
    found = sorted(f["forcing"] for f in doc["folds"])
    assert found == pytest.approx([13.7, 16.0], abs=0.3)
    # a state either side of each fold: three states inside the window, one outside
    lo, hi = found
    assert len(hairbed.solve_pillar_all(lo + 0.05, -1.4)) == 3
    assert len(hairbed.solve_pillar_all(hi + 0.05, -1.4)) == 1
    status, out, err = _run(capsys, "solve", "--pillar", "--branch=40", "--theta0=-1.4")
    assert status == 0 and out.count("fold ") == 2
    assert len(out.splitlines()) == 3 + 1 + br.forcing.size


def test_plot_draws_the_three_states(capsys, tmp_path):
    pytest.importorskip("matplotlib")
    path = tmp_path / "states.png"
    status, out, err = _run(
        capsys, "solve", "--pillar", "--forcing=15", "--theta0=-1.4", "--all", f"--plot={path}"
    )
    assert status == 0 and "3 pillar state(s)" in out
    assert err.strip() == f"wrote {path} (PNG, 3 shapes)"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_no_fold_upright(capsys):
    status, out, err = _run(capsys, "solve", "--pillar", "--branch=50")
    assert status == 0 and "no fold" in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--forcing=2"], "--forcing needs --pillar"),
        (["--omega2=1", "--eps=0.5", "--gamma=0.5"], "--gamma needs --pillar"),
        (["--pillar"], "--pillar needs --forcing, --tip-deflection or --branch"),
        (["--pillar", "--forcing=1", "--eps=0.5"], "--eps does not apply with --pillar"),
        (["--pillar", "--forcing=1", "--all", "--root=mid"], "--root does not apply with --all"),
        (["--pillar", "--branch=3", "--root=mid"], "--root chooses the state at --forcing"),
        (
            ["--pillar", "--forcing=1", "--length=1e-3"],
            "--forcing does not apply to solve --pillar",
        ),
        (["--pillar", "--forcing=0", "--all"], "--all needs a non-zero --forcing"),
        (["--pillar", "--forcing=1", "--n=1"], "--sign and --n do not apply"),
        (["--pillar", "--forcing=1", "--tip-deflection=0.2"], "not both"),
        (["--pillar", "--forcing=1", "--branch=3"], "not with --forcing"),
        (["--pillar", "--tip-deflection=0.2", "--all"], "--all needs --forcing"),
        (["--pillar", "--forcing=1", "--gamma=0.5", "--slenderness=9"], "not both"),
        (["--pillar", "--forcing=1", "--gamma=0"], "gamma must lie in (0, 1]"),
        (
            ["--pillar", "--forcing=1", "--slenderness=1"],
            "slenderness must lie in [e^1.5/2 = 2.2408, inf)",
        ),
        (["--pillar", "--forcing=nan"], "forcing"),
        (["--pillar", "--forcing=1", "--theta0=2"], "theta0 must lie in (-pi/2, pi/2)"),
        (["--pillar", "--forcing=1", "--profile=poiseuille"], "needs height_ratio"),
        (["--pillar", "--forcing=1", "--profile=couette", "--height-ratio=2"], "height_ratio"),
        (["--pillar", "--tip-deflection=1"], "tip_deflection must lie in (-1, 1)"),
        (["--pillar", "--branch=0"], "forcing_max must be non-zero"),
        (["--pillar", "--forcing=1", "--profile=jet"], "invalid choice"),
        (["--pillar", "--branch=3", "--plot=b.png"], "not with --branch"),
        (["--pillar", "--forcing=1", "--height-ratio=0.5"], "applies to the channel profiles"),
        (["--pillar", "--forcing=1", "--plot=b.xyz"], "unknown image format"),
    ],
)
def test_bad_input_is_one_line(capsys, args: list[str], message: str):
    status, out, err = _run(capsys, "solve", *args)
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error:"), err
    assert message in lines[0], err


# -- hairbed sweep --pillar ----------------------------------------------------------------


def test_sweep_writes_the_library_grid(tmp_path, capsys):
    xr = pytest.importorskip("xarray")
    out = tmp_path / "pillar.nc"
    status, _, err = _run(
        capsys, "sweep", "--pillar", "--forcing=0.1,1,10", "--theta0=-0.5,0,0.5",
        "--slenderness=20", f"--out={out}",
    )  # fmt: skip
    assert status == 0 and "wrote" in err
    with xr.open_dataset(out) as ds:
        assert dict(ds.sizes) == {"forcing": 3, "theta0": 3}
        assert float(ds["gamma"]) == hairbed.gray_hancock_ratio(20.0)
        assert ds["drag_x"].attrs["long_name"] == PILLAR["drag_x"].long_name
        st = hairbed.solve_pillar(0.1, -0.5, gamma=float(ds["gamma"]))
        got = float(ds["tip_deflection"].sel(forcing=0.1, theta0=-0.5))
        assert got == pytest.approx(st.tip_deflection, abs=1e-14)


def test_sweep_to_csv_on_stdout(capsys):
    pytest.importorskip("xarray")
    status, out, err = _run(
        capsys, "sweep", "--pillar", "--forcing=1:3:3", "--profile=poiseuille",
        "--height-ratio=0.5,1",
    )  # fmt: skip
    assert status == 0 and err == ""
    lines = out.strip().splitlines()
    head = lines[0].split(",")
    assert head[:2] == ["forcing [1]", "height_ratio [1]"] and "tip_deflection [1]" in head
    assert len(lines) == 1 + 6


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--pillar"], "needs --forcing SPEC"),
        (["--pillar", "--forcing=1", "--omega2=1"], "--omega2 does not apply with --pillar"),
        (["--pillar", "--forcing=1", "--eps=0.5"], "--eps does not apply with --pillar"),
        (["--pillar", "--forcing=1", "--quasistatic"], "--quasistatic does not apply"),
        (["--pillar", "--forcing=1", "--root=high"], "--root does not apply"),
        (["--pillar", "--forcing=1", "--radius=1e-5"], "--forcing does not apply to sweep"),
        (["--forcing=1", "--eps=0.5"], "--forcing needs --pillar"),
        (["--pillar", "--forcing=1", "--gamma=0.2,2"], "gamma must lie in (0, 1]"),
        (["--pillar", "--forcing=1", "--profile=couette", "--height-ratio=0.5,3"], "index 1"),
        (["--pillar", "--forcing=1", "--profile=poiseuille"], "needs height_ratio"),
        (["--pillar", "--forcing=1:x:3"], "--forcing"),
        (["--pillar", "--forcing=1", "--height-ratio=0.5"], "applies to the channel profiles"),
    ],
)
def test_sweep_bad_input_is_one_line(capsys, args: list[str], message: str):
    pytest.importorskip("xarray")
    status, out, err = _run(capsys, "sweep", *args)
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], err


def test_help_lists_the_pillar_options(capsys):
    with pytest.raises(SystemExit):
        main(["solve", "--help"])
    out = capsys.readouterr().out
    for flag in (
        "--pillar",
        "--forcing",
        "--tip-deflection",
        "--all ",
        "--branch",
        "--slenderness",
    ):
        assert flag in out, flag
