"""The explorer without a browser: inputs, states, exports, the page's logic and its command.

Expectations are computed here from the library's public functions (``hairbed.solve`` for
every root, ``solve_all``, ``HairBed.deform``, ``stability.is_stable`` at another resolution),
never from the explorer's own code path. The page in a real browser is tested in
tests/test_explorer_browser.py.
"""

from __future__ import annotations

import csv
import html
import io
import json
import math
import subprocess
import sys
import warnings

import numpy as np
import pytest

import hairbed
from hairbed._variables import SI, SOLUTION, cf_attrs
from hairbed.explorer import _model as model

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}


def _raw(**kw: object) -> dict[str, str]:
    return {k: str(v) for k, v in kw.items()}


def _library_message(func, *args, **kwargs) -> str:
    with pytest.raises(ValueError) as info:
        func(*args, **kwargs)
    return str(info.value)


def _library_warnings(func, *args, **kwargs) -> tuple[object, list[str]]:
    """What the library returns and every warning it issues, as the page words them:
    "Category: message" (whitespace collapsed), each once."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = func(*args, **kwargs)
    texts = [f"{w.category.__name__}: {' '.join(str(w.message).split())}" for w in caught]
    return out, list(dict.fromkeys(texts))


def _deform_warnings(bed, velocity) -> list[str]:
    """The library's warnings for every coexisting state of a bed at a wall speed."""
    n = hairbed.solve(bed.omega2(velocity), bed.eps, math.copysign(1, velocity) * bed.base_angle)
    roots = ("low", "mid", "high") if n.n_roots == 3 else ("low",)
    out: list[str] = []
    for root in roots:
        out += _library_warnings(bed.deform, velocity, root=root)[1]
    return list(dict.fromkeys(out))


# -- importing -----------------------------------------------------------------------------------


def test_import_hairbed_imports_no_web_framework():
    code = (
        "import sys, hairbed, hairbed.explorer; f = hairbed.explore; "
        "assert callable(f) and f is hairbed.explorer.explore; "
        "bad = [m for m in ('panel', 'bokeh', 'param', 'tornado') if m in sys.modules]; "
        "print(bad)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_missing_app_extra_is_one_line_naming_the_extra():
    # panel made unimportable: the command says how to install it, in one line, exit 1 (as
    # every missing extra of the command line, tests/test_cli_errors.py)
    code = (
        "import sys; sys.modules['panel'] = None; from hairbed.cli import main; "
        "sys.exit(main(['explore', '--no-browser', '--port', '0']))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 1
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    assert lines[0].startswith("hairbed: ") and "panel" in lines[0]
    assert "pip install 'hairbed[app]'" in lines[0]


def test_explore_help_names_the_options():
    out = subprocess.run(
        [sys.executable, "-m", "hairbed", "explore", "--help"],
        capture_output=True,
        text=True,
        check=True,
    )
    for option in ("--port", "--host", "--no-browser", "--allow-websocket-origin"):
        assert option in out.stdout
    assert "127.0.0.1" in out.stdout


def test_explore_restarts_with_the_same_options():
    """``hairbed explore`` restarts itself with PYTHONMALLOC=<--allocator>: the restarted
    command line gives back every option it was given."""
    from hairbed.cli import build_parser
    from hairbed.cli._explore import _argv

    parser = build_parser()
    given = [
        "explore", "--port", "0", "--host", "0.0.0.0", "--no-browser",
        "--allow-websocket-origin", "a.org", "--allow-websocket-origin", "b.org:81",
        "--session-token-expiration", "9", "--check-unused-sessions", "700",
        "--unused-session-lifetime", "800", "--allocator", "pymalloc",
    ]  # fmt: skip
    args = parser.parse_args(given)
    again = parser.parse_args(["explore", *_argv(args)])
    assert vars(again) == vars(args)
    default = parser.parse_args(["explore"])
    assert default.allocator == "malloc" and vars(
        parser.parse_args(["explore", *_argv(default)])
    ) == vars(default)


def test_taken_port_is_a_one_line_error():
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        out = subprocess.run(
            [sys.executable, "-m", "hairbed", "explore", "--port", str(port), "--no-browser"],
            capture_output=True,
            text=True,
            timeout=120,
        )
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert f"127.0.0.1:{port}" in out.stderr


def test_websocket_origins_default_to_the_loopback():
    from hairbed.explorer import _origins

    assert _origins("127.0.0.1", 5006, ()) == ["127.0.0.1:5006", "localhost:5006"]
    assert _origins("0.0.0.0", 80, ("example.org",)) == ["0.0.0.0:80", "example.org"]


# -- validation: the library's messages ------------------------------------------------------


@pytest.mark.parametrize(
    ("raw", "args"),
    [
        (_raw(omega2="-1"), (-1.0, 0.9, -1.5)),
        (_raw(omega2="abc"), ("abc", 0.9, -1.5)),
        (_raw(omega2="nan"), (math.nan, 0.9, -1.5)),
        (_raw(omega2="inf"), (math.inf, 0.9, -1.5)),
        (_raw(eps="1"), (0.8, 1.0, -1.5)),
        (_raw(eps=""), (0.8, "", -1.5)),
        (_raw(theta0="1.6"), (0.8, 0.9, 1.6)),
    ],
)
def test_bad_dimensionless_input_gives_the_librarys_message(raw, args):
    expected = _library_message(hairbed.solve, *args)
    with pytest.raises(ValueError) as info:
        model.validate(raw)
    assert str(info.value) == expected


@pytest.mark.parametrize(
    ("change", "bed_kw"),
    [
        ({"length": "0"}, {"length": 0.0}),
        ({"radius": "x"}, {"radius": "x"}),
        ({"channel_height": "0.0005"}, {"channel_height": 0.0005}),
        ({"packing_fraction": "0.3"}, {"packing_fraction": 0.3}),
        ({"spacing": "0.00009"}, {"spacing": 0.00009}),
        ({"base_angle": "2"}, {"base_angle": 2.0}),
    ],
)
def test_bad_bed_gives_the_librarys_message(change, bed_kw):
    kw = {**BED, "base_angle": 0.0, **bed_kw}
    expected = _library_message(hairbed.HairBed, **kw)
    with pytest.raises(ValueError) as info:
        model.validate({"si": "1", **change})
    assert str(info.value) == expected


def test_bad_velocity_and_density():
    bed = hairbed.HairBed(**BED)
    expected = _library_message(bed.omega2, "fast")
    with pytest.raises(ValueError, match="velocity") as info:
        model.validate({"si": "1", "velocity": "fast"})
    assert str(info.value) == expected
    for text, value in (("-1", -1.0), ("0", 0.0), ("dense", "dense"), ("inf", math.inf)):
        expected = _library_message(hairbed.HairBed, **BED, density=value)
        with pytest.raises(ValueError, match="density") as info:
            model.validate({"si": "1", "density": text})
        assert str(info.value) == expected
    with pytest.raises(ValueError, match="unknown parameter 'foo'"):
        model.validate({"foo": "1"})
    with pytest.raises(ValueError, match="si must be 0 or 1"):
        model.validate({"si": "maybe"})
    with pytest.raises(ValueError, match="y must be one of"):
        model.validate({"y": "z"})


# -- states -------------------------------------------------------------------------------------


@pytest.mark.parametrize(("omega2", "count"), [(0.8, 1), (1.2, 3), (2.5, 1)])
def test_every_coexisting_state_is_the_librarys(omega2, count):
    snap = model.compute(model.validate(_raw(omega2=omega2, eps=0.9, theta0=-1.5)))
    assert len(snap.states) == count == hairbed.solve(omega2, 0.9, -1.5).n_roots
    roots = ("low", "mid", "high") if count == 3 else ("low",)
    for view, root in zip(snap.states, roots):
        ref = hairbed.solve(omega2, 0.9, -1.5, root=root)
        assert view.label == root
        for name in model.SOLUTION_FIELDS:
            assert getattr(view.solution, name) == getattr(ref, name), name
        # an independent resolution of the stability problem agrees (away from the folds)
        assert view.stable == hairbed.stability.is_stable(ref, 120)
    if count == 3:
        assert [v.stable for v in snap.states] == [True, False, True]
    # the folds of the branch diagram are the library's, and bracket the window
    folds = hairbed.branches.folds(0.9, -1.5)
    np.testing.assert_array_equal(np.sort(snap.folds_omega2), np.sort(folds.omega2))


def test_twirling_states_are_every_other_state_of_solve_all():
    snap = model.compute(model.validate(_raw(omega2=200, eps=0.5, theta0=0, twirl=1)))
    ref = [s for s in hairbed.solve_all(200.0, 0.5, 0.0) if (s.sign, s.n) != (1, 0)]
    assert len(snap.twirling) == len(ref) > 0
    for view, s in zip(snap.twirling, ref):
        assert (view.solution.sign, view.solution.n) == (s.sign, s.n)
        assert view.solution.xi == s.xi
    assert {c[0] for c in snap.twirl_curves} == {f"({s.sign:+d}, {s.n})" for s in ref}


def test_si_mode_is_the_beds_state():
    raw = {"si": "1", "velocity": "-0.3", "base_angle": "0.4", "density": "1000"}
    p = model.validate(raw)
    bed = hairbed.HairBed(**BED, base_angle=0.4, density=1000.0)
    assert p.bed == bed
    assert p.omega2 == bed.omega2(0.3) and p.eps == 0.5 and p.theta0 == -0.4  # mirrored
    snap = model.compute(p)
    st = bed.deform(-0.3)
    view = snap.states[0]
    assert view.si.wall_shear_stress == st.wall_shear_stress
    assert view.si.tip_deflection == st.tip_deflection < 0.0
    # the library's Reynolds number, and it is the closed form rho |v| (H - h1 L) / eta
    assert view.si.reynolds_number == st.reynolds_number
    gap = 2e-3 - st.tip_height
    assert view.si.reynolds_number == pytest.approx(1000 * 0.3 * gap / 1.0, rel=1e-14)
    assert snap.warnings == _deform_warnings(bed, -0.3) == []  # Re ~ 0.4: Stokes flow


@pytest.mark.parametrize("velocity", [0.5, 2.0, -3.0, 500.0])
def test_si_warnings_are_the_librarys(velocity):
    """Whatever the library warns about (Reynolds number above its threshold), the page shows,
    word for word; where it says nothing, the page says nothing."""
    raw = {"si": "1", "velocity": repr(velocity), "density": "1000", "base_angle": "-1.5"}
    snap = model.compute(model.validate(raw))
    bed = hairbed.HairBed(**BED, base_angle=-1.5, density=1000.0)
    expected = _deform_warnings(bed, velocity)
    assert snap.warnings == expected
    reynolds = [s.si.reynolds_number for s in snap.states]
    # the library warns exactly when a state's gap flow leaves the Stokes regime, Re > 1
    assert bool(expected) == (max(reynolds) > 1.0)
    assert all(w.startswith("ModelValidityWarning: ") for w in expected)
    if velocity == 0.5:
        assert expected == []
    else:
        assert expected and "Reynolds" in expected[0]


def test_si_units_warning_of_the_bed_is_shown():
    raw = {"si": "1", "youngs_modulus": "100", "density": "", "velocity": "1e-5"}
    bed, expected = _library_warnings(hairbed.HairBed, **{**BED, "youngs_modulus": 100.0})
    assert expected and expected[0].startswith("UnitsWarning: youngs_modulus")
    p = model.validate(raw)
    assert list(p.warnings) == expected
    snap = model.compute(p)
    assert snap.warnings == expected + _deform_warnings(bed, 1e-5)
    # no density: no Reynolds number, and no warning about it from the library
    assert math.isnan(snap.states[0].si.reynolds_number)
    assert _deform_warnings(bed, 1e-5) == []


def test_no_warnings_the_library_does_not_issue():
    """A stubby, sparse bed: the library has no check of slenderness or density of the bed,
    so the page shows none (one implementation of the model's validity)."""
    raw = {"si": "1", "radius": "0.00015", "spacing": "0.0012", "velocity": "0.1"}
    snap = model.compute(model.validate(raw))
    bed, built = _library_warnings(
        hairbed.HairBed, **{**BED, "radius": 15e-5, "spacing": 12e-4}, base_angle=0.0,
        density=1260.0,
    )  # fmt: skip
    assert snap.warnings == built + _deform_warnings(bed, 0.1)


# -- exports and the URL ------------------------------------------------------------------------


def test_json_and_csv_exports_hold_every_field():
    snap = model.compute(model.validate(_raw(omega2=1.2, eps=0.9, theta0=-1.5, twirl=1)))
    doc = json.loads(model.snapshot_json(snap))
    rows = list(csv.DictReader(io.StringIO(model.snapshot_csv(snap))))
    assert [s["state"] for s in doc["states"]] == ["low", "mid", "high"]
    assert [r["state"] for r in rows[:3]] == ["low", "mid", "high"]
    assert len(rows) == 3 + len(doc["twirling"])
    for root, rec, row in zip(("low", "mid", "high"), doc["states"], rows):
        ref = hairbed.solve(1.2, 0.9, -1.5, root=root)
        for name in model.SOLUTION_FIELDS:
            expected = getattr(ref, name)
            got_csv = row[_heading(name, SOLUTION)]
            if isinstance(expected, bool):
                assert rec[name] is expected and got_csv == str(expected)
            else:
                assert rec[name] == expected and float(got_csv) == expected, name


def test_si_export_holds_the_bed():
    snap = model.compute(model.validate({"si": "1", "velocity": "0.2"}))
    doc = json.loads(model.snapshot_json(snap))
    st = hairbed.HairBed(**BED, base_angle=0.0).deform(0.2)
    assert doc["bed"]["velocity"] == 0.2
    assert doc["states"][0]["si_wall_shear_stress"] == st.wall_shear_stress
    row = next(csv.DictReader(io.StringIO(model.snapshot_csv(snap))))
    assert float(row["si_force_per_hair [N]"]) == st.force_per_hair


def _heading(name: str, table) -> str:
    """A CSV heading as hairbed's sweeps write it, "name [CF units]", from the variables
    table (brackets only where there are units)."""
    units = table[name].units
    return f"{name} [{units}]" if units else name


def test_downloads_carry_units_and_the_shape():
    """Issue 23 item 14: the CSV headings carry the CF units of hairbed's variables table,
    the JSON names each variable's units and long name, and both carry the hair's shape
    (x, z), which is the library's profile (and, in SI, the bed's profile in metres)."""
    snap = model.compute(model.validate({"si": "1", "velocity": "-0.2", "base_angle": "0.3"}))
    bed = hairbed.HairBed(**BED, base_angle=0.3)
    st = bed.deform(-0.2)
    header = next(csv.reader(io.StringIO(model.snapshot_csv(snap))))
    for name in ("tip_deflection", "tip_angle", "theta0", "xi"):
        assert _heading(name, SOLUTION) in header
    for name in ("wall_shear_stress", "tip_deflection", "velocity", "force_per_hair"):
        assert f"si_{name} [{SI[name].units}]" in header
    assert "si_wall_shear_stress [Pa]" in header and "tip_angle [rad]" in header
    doc = json.loads(model.snapshot_json(snap))
    assert doc["variables"]["si_wall_shear_stress"] == cf_attrs(SI["wall_shear_stress"])
    assert doc["variables"]["tip_height"] == cf_attrs(SOLUTION["tip_height"])
    assert doc["bed_variables"]["length"]["units"] == "m"
    shape = doc["states"][0]["shape"]
    n = len(shape["sigma"])
    assert n >= 50 and shape["sigma"][0] == 0.0 and shape["sigma"][-1] == 1.0
    sigma = np.asarray(shape["sigma"])
    np.testing.assert_array_equal(shape["x"], st.solution.x(sigma))
    np.testing.assert_array_equal(shape["z"], st.solution.z(sigma))
    x_m, z_m = st.profile(n)
    np.testing.assert_array_equal(shape["si_x"], x_m)
    np.testing.assert_array_equal(shape["si_z"], z_m)
    # the tip of the shape is the state's tip: metres, along +x of the bed (v < 0: mirrored)
    assert shape["si_x"][-1] == pytest.approx(st.tip_deflection, rel=1e-12)
    assert shape["si_z"][-1] == pytest.approx(st.tip_height, rel=1e-12)
    assert doc["shape_variables"]["si_x"]["units"] == "m"
    rows = list(csv.DictReader(io.StringIO(model.snapshot_shape_csv(snap))))
    assert len(rows) == n * len(snap.states)
    assert {"state", "sigma [1]", "x [1]", "z [1]", "theta [rad]", "si_x [m]", "si_z [m]"} == set(
        rows[0]
    )
    assert [float(r["si_z [m]"]) for r in rows[:n]] == pytest.approx(z_m, rel=1e-15)
    assert float(rows[n - 1]["x [1]"]) == pytest.approx(st.solution.tip_deflection, rel=1e-12)


def test_query_round_trip():
    p = model.validate(_raw(omega2="1.25", eps="0.95", theta0="-1", y="xi", twirl="1"))
    q = model.query_from_inputs(p)
    assert model.validate(model.inputs_from_query(q)) == p
    si = model.validate({"si": "1", "velocity": "0.05", "packing_fraction": "0.1", "spacing": ""})
    back = model.validate(model.inputs_from_query(model.query_from_inputs(si)))
    assert back.bed == si.bed and back.velocity == 0.05


# -- the page, in process -------------------------------------------------------------------------

pn = pytest.importorskip("panel", reason="the app extra (panel) is not installed")


def _page(query: str = ""):
    from hairbed.explorer._page import ExplorerPage

    return ExplorerPage(query)


def test_slider_move_resolves_every_state():
    page = _page("?omega2=0.8&eps=0.9&theta0=-1.5")
    assert len(page.snapshot.states) == 1
    page.omega2_slider.value = math.log10(1.2)
    w = float(page.text["omega2"].value)
    assert w == pytest.approx(1.2, rel=1e-5)
    assert page.snapshot.params.omega2 == w
    assert [s.label for s in page.snapshot.states] == ["low", "mid", "high"]
    for s in page.snapshot.states:
        assert s.solution.xi == hairbed.solve(w, 0.9, -1.5, root=s.label).xi
    assert page.timings["total"] > 0.0
    page.eps_slider.value = 0.5  # below the cusp: one state again
    assert page.text["eps"].value == "0.5" and len(page.snapshot.states) == 1


def test_bad_input_keeps_the_last_good_state():
    page = _page()
    good = page.snapshot
    page.text["eps"].value = "1.5"
    assert page.error == _library_message(hairbed.solve, 0.8, 1.5, -1.5)
    assert page.alert.visible and page.snapshot is good
    page.text["eps"].value = "0.95"
    assert page.error == "" and not page.alert.visible
    assert page.snapshot.params.eps == 0.95


def test_bad_url_keeps_the_defaults_on_screen():
    page = _page("?omega2=2&eps=oops")
    assert page.error == _library_message(hairbed.solve, 2.0, "oops", -1.5)
    assert page.snapshot.params.omega2 == float(model.DEFAULTS["omega2"])
    page = _page("?omega2=2&si=perhaps")
    assert page.error == "si must be 0 or 1, got 'perhaps'"


def test_si_switch_and_twirl():
    page = _page()
    page.si.value = True
    bed = hairbed.HairBed(**BED, base_angle=-1.5)
    assert page.snapshot.params.omega2 == bed.omega2(0.1)
    assert page.text["eps"].disabled and page.text["eps"].value == repr(bed.eps)
    page.omega2_slider.value = math.log10(2.0)  # moves the wall speed
    v = float(page.text["velocity"].value)
    assert v == pytest.approx(2.0 * bed.velocity_scale, rel=1e-5)
    assert page.snapshot.states[0].si.velocity == v
    assert "wall shear stress" in page.table.object
    assert "hb-warn" not in page.table.object  # Re ~ 0.2 at the defaults: no warning
    page.twirl.value = list(page.twirl.options)  # ticked
    page.si.value = False
    page.text["omega2"].value = "200"
    page.text["eps"].value = "0.5"
    page.text["theta0"].value = "0"
    n = sum((s.sign, s.n) != (1, 0) for s in hairbed.solve_all(200.0, 0.5, 0.0))
    assert len(page.snapshot.twirling) == n
    assert f'data-count="{n}"' in page.twirl_table.object
    doc = json.loads(page._json_file().read())
    assert len(doc["twirling"]) == n


def test_page_shows_the_librarys_warnings():
    import html

    page = _page("?si=1&velocity=2&density=1000")
    bed = hairbed.HairBed(**BED, density=1000.0)
    expected = _deform_warnings(bed, 2.0)
    assert expected and page.snapshot.warnings == expected
    for text in expected:  # above the views (not below the table)
        assert f"<li>{html.escape(text)}</li>" in page.notes.object
    assert "hb-warn" not in page.table.object
    assert page.layout.objects.index(page.notes) < page.layout.objects.index(page.alert) + 2
    page.text["velocity"].value = "0.1"
    assert page.snapshot.warnings == [] and "hb-warn" not in page.notes.object


def _search(**kw: str) -> str:
    """A full query of the dimensionless view, written here (not by the explorer)."""
    args = {"omega2": "0.8", "eps": "0.9", "theta0": "-1.5", "y": "x1", "si": "0", "twirl": "0"}
    args.update(kw)
    return "?" + "&".join(f"{k}={v}" for k, v in args.items())


def _shows(page, omega2: float, eps: float, theta0: float) -> None:
    """Fields and states are those of the inputs (states: hairbed.solve's roots)."""
    assert [float(page.text[k].value) for k in ("omega2", "eps", "theta0")] == [
        omega2,
        eps,
        theta0,
    ]
    n = hairbed.solve(omega2, eps, theta0).n_roots
    states = page.snapshot.states
    assert [s.label for s in states] == (["low", "mid", "high"] if n == 3 else ["low"])
    for s in states:
        assert s.solution.xi == hairbed.solve(omega2, eps, theta0, root=s.label).xi


def test_url_follows_every_good_change():
    page = _page("?omega2=0.8&eps=0.9&theta0=-1.5")
    assert page.history.search == _search()  # the loaded link written out whole
    page.text["omega2"].value = "1.2"
    assert page.history.search == _search(omega2="1.2")
    page.text["eps"].value = "1.5"  # bad: the URL stays the one of the view on screen
    assert page.error and page.history.search == _search(omega2="1.2")
    page = _page("?eps=1.5")  # a bad link stays in the address bar, with its message
    assert page.error and page.history.search == "?eps=1.5"
    page = _page()
    assert page.history.search == _search(omega2="2", eps="0.5", theta0="0")


def test_back_and_forward_show_the_view_of_the_url():
    """The browser's Back/Forward set ``history.search``: the page shows that URL's view."""
    page = _page("?omega2=0.8&eps=0.9&theta0=-1.5")
    page.text["omega2"].value = "1.2"
    page.text["omega2"].value = "2.5"
    _shows(page, 2.5, 0.9, -1.5)
    for w in (1.2, 0.8, 1.2, 2.5):
        page.history.search = _search(omega2=str(w))
        _shows(page, w, 0.9, -1.5)
        assert page.history.search == _search(omega2=str(w))  # no other URL sent back
        assert page.error == ""
    # a history URL naming only some inputs: the others take their defaults, as in a page
    # loaded from it (not the values of the view left)
    page.text["eps"].value = "0.7"
    page.text["theta0"].value = "0.3"
    page.history.search = "?omega2=1.2"
    eps, theta0 = model.DEFAULTS["eps"], model.DEFAULTS["theta0"]
    _shows(page, 1.2, float(eps), float(theta0))
    # written out whole
    assert page.history.search == _search(omega2="1.2", eps=eps, theta0=theta0)
    # from an SI view back to a dimensionless one: the bed's fields as in a fresh page
    page.si.value = True
    page.text["velocity"].value = "0.2"
    assert page.snapshot.params.si and "si=1" in page.history.search
    page.history.search = _search(omega2="0.8")
    assert not page.si.value and not page._bed_column.visible
    assert page.text["velocity"].value == model.DEFAULTS["velocity"]
    _shows(page, 0.8, 0.9, -1.5)


def test_bad_history_url_keeps_the_last_good_state():
    page = _page("?omega2=1.2&eps=0.9&theta0=-1.5")
    good = page.snapshot
    page.history.search = "?omega2=2&eps=1.5"
    assert page.error == _library_message(hairbed.solve, 2.0, 1.5, -1.5)
    assert page.snapshot is good and page.history.search == "?omega2=2&eps=1.5"
    page.history.search = "?omega2=2&eps=1.5&colour=red"  # bad and unknown: both said
    assert page.error == _library_message(hairbed.solve, 2.0, 1.5, -1.5)
    assert "ignored the unknown URL parameter 'colour'" in html.unescape(page.alert.object)
    assert page.snapshot is good
    page.history.search = _search(omega2="1.3")  # Forward to a good URL again
    assert page.error == "" and page.history.search == _search(omega2="1.3")
    _shows(page, 1.3, 0.9, -1.5)
    # a typed change after the bad URL reaches the address bar even when it is the view's
    # last good URL (the address bar shows the bad one)
    page.history.search = "?eps=1.5"
    assert page.text["eps"].value == "0.9"  # the fields show the view on screen again
    page.text["omega2"].value = "1.25"
    page.text["omega2"].value = "1.3"
    assert page.history.search == _search(omega2="1.3")


def test_url_component_only_on_a_served_page():
    """Served: the history component is on the page; in a notebook (not served) it is not
    (the notebook's own URL is left alone)."""
    from hairbed.explorer._page import ExplorerPage

    page = _page()
    assert page.history not in page.layout.objects

    page = ExplorerPage("?omega2=1.2", served=True)
    assert page.history in page.layout.objects and not page.history.visible


# -- issue 23: an explorer that opens where users start, errors in full, legible states ---------


def test_opens_at_the_papers_worked_example():
    """Item 11: the first view is the paper's worked example, omega2 = 2, eps = 0.5,
    theta0 = 0 (its tip deflection 0.6158... of the README's quick start)."""
    page = _page()
    assert [page.text[k].value for k in ("omega2", "eps", "theta0")] == ["2", "0.5", "0"]
    _shows(page, 2.0, 0.5, 0.0)
    assert page.snapshot.states[0].solution.tip_deflection == pytest.approx(0.6158, abs=5e-5)


def test_presets():
    """Item 11: presets for a bistable window, twirling states and a sensor bed in SI."""
    page = _page()
    assert set(page.presets) == set(model.PRESETS)
    page.presets["bistable window"].clicks += 1
    w, e, th = (page.snapshot.params.omega2, page.snapshot.params.eps, page.snapshot.params.theta0)
    assert hairbed.solve(w, e, th).n_roots == 3
    _shows(page, w, e, th)
    assert "twirl=0" in page.history.search and f"omega2={page.text['omega2'].value}" in (
        page.history.search
    )
    page.presets["twirling states"].clicks += 1
    p = page.snapshot.params
    ref = [s for s in hairbed.solve_all(p.omega2, p.eps, p.theta0) if (s.sign, s.n) != (1, 0)]
    assert p.twirl and len(page.snapshot.twirling) == len(ref) > 0
    page.presets["sensor bed (SI)"].clicks += 1
    p = page.snapshot.params
    assert p.si and page._bed_column.visible and p.bed.base_angle == 0.0
    st = p.bed.deform(p.velocity)
    assert page.snapshot.states[0].si.wall_shear_stress == st.wall_shear_stress
    assert max(s.si.reynolds_number for s in page.snapshot.states) < 1.0  # Stokes flow
    page.presets["worked example"].clicks += 1
    assert not page.snapshot.params.si
    _shows(page, 2.0, 0.5, 0.0)


def test_base_angle_is_a_bed_field():
    """Item 11: SI mode has the bed's own base angle (default upright), not the dimensionless
    theta0 carried over; the theta0 slider then moves the base angle."""
    page = _page("?omega2=1.2&eps=0.9&theta0=-1.5")
    page.si.value = True
    p = page.snapshot.params
    assert p.bed == hairbed.HairBed(**BED, density=1260.0) and p.bed.base_angle == 0.0
    assert p.theta0 == 0.0 and page.text["theta0"].disabled
    # the hair at rest is drawn upright: from the base (0, 0) straight up
    rest = page.views.ch_rest.data
    assert rest["x"] == [0.0, 0.0] and rest["y"][1] > 0.0
    page.theta0_slider.value = 0.3
    assert page.text["base_angle"].value == "0.3"
    assert page.snapshot.params.bed.base_angle == 0.3 == float(page.text["theta0"].value)
    assert "base_angle=0.3" in page.history.search


def test_si_branch_diagram_in_si_units():
    """Item 11: in SI mode the branch diagram is against the wall speed or the wall shear
    stress, with the tip deflection in metres: each point is the bed's own state there
    (HairBed.deform at that speed, away from folds: eps = 0.5 has none)."""
    page = _page("?si=1&velocity=0.1")
    bed = page.snapshot.params.bed
    d = page.snapshot.branch
    assert "m/s" in page.views.branch.xaxis.axis_label
    assert "[m]" in page.views.branch.yaxis.axis_label
    st = bed.deform(0.1)
    assert d.states_x == [0.1] and d.states_y == [st.tip_deflection]
    picks = np.linspace(0, d.curve_x.size - 1, 7).astype(int)
    speeds = d.curve_x[picks]
    ref = hairbed.HairBed(**BED).deform(speeds)  # the same bed without its fluid: no warning
    np.testing.assert_allclose(d.curve_y[picks], ref.tip_deflection, rtol=1e-9, atol=0)
    page.x_choice.value = "stress"
    d = page.snapshot.branch
    assert "Pa" in page.views.branch.xaxis.axis_label and "x=stress" in page.history.search
    assert d.states_x == [st.wall_shear_stress]
    np.testing.assert_allclose(d.curve_x[picks], ref.wall_shear_stress, rtol=1e-9, atol=0)
    # the abscissa shows the stresses of omega^2 in [1e-3, 1e3], as the speed view does
    lo, hi = d.x_range
    # (the curve's first point inside the window: within a few per cent of its edge)
    assert lo == pytest.approx(bed.deform(1e-3 * bed.velocity_scale).wall_shear_stress, rel=5e-2)
    assert page.views.br_x.start == lo and page.views.br_x.end == hi


def _alone(**kw) -> str:
    """The library's message for one bad input of solve, the others valid."""
    args = {"omega2": 1.0, "eps": 0.5, "theta0": 0.0, **kw}
    return _library_message(hairbed.solve, **args)


def test_every_bad_input_is_listed():
    """Item 12: three bad values, three messages (each the library's); before only the
    first."""
    with pytest.raises(ValueError) as info:
        model.validate({"omega2": "-1", "eps": "1.5", "theta0": "3"})
    expected = (_alone(omega2=-1.0), _alone(eps=1.5), _alone(theta0=3.0))
    assert info.value.messages == expected
    with pytest.raises(ValueError) as info:
        model.validate({"si": "1", "length": "-1", "radius": "x", "velocity": "fast"})
    bed = hairbed.HairBed(**BED)
    assert info.value.messages == (
        _library_message(hairbed.HairBed, **{**BED, "length": -1.0}),
        _library_message(hairbed.HairBed, **{**BED, "radius": "x"}),
        _library_message(bed.omega2, "fast"),
    )
    # each fine alone, wrong together: the bed's message for the combination
    with pytest.raises(ValueError) as info:
        model.validate({"si": "1", "length": "0.003"})
    assert info.value.messages == (_library_message(hairbed.HairBed, **{**BED, "length": 0.003}),)


@pytest.mark.parametrize(
    "name", ["length", "radius", "youngs_modulus", "channel_height", "viscosity", "spacing"]
)
def test_each_bad_size_alone_is_the_beds_message(name):
    """Each size checked alone gives exactly HairBed's message (its unit included)."""
    for text, value in (("-1", -1.0), ("big", "big")):
        with pytest.raises(ValueError) as info:
            model.validate({"si": "1", name: text})
        assert info.value.messages == (_library_message(hairbed.HairBed, **{**BED, name: value}),)


def test_bad_url_lists_every_message_and_restores_the_fields():
    """Item 12: a link with three bad values shows the three messages and puts the values of
    the view on screen (the last good one) back in the fields."""
    page = _page("?omega2=-1&eps=1.5&theta0=3")
    assert page.errors == (_alone(omega2=-1.0), _alone(eps=1.5), _alone(theta0=3.0))
    assert page.alert.visible and page.alert.object.count("<p>") == 3
    assert [page.text[k].value for k in ("omega2", "eps", "theta0")] == [
        model.DEFAULTS[k] for k in ("omega2", "eps", "theta0")
    ]
    _shows(page, 2.0, 0.5, 0.0)
    page = _page("?si=1&length=-1&radius=x&velocity=fast")
    assert len(page.errors) == 3 and not page.si.value and not page._bed_column.visible
    assert page.text["length"].value == model.DEFAULTS["length"]
    assert page.text["velocity"].value == model.DEFAULTS["velocity"]
    # Back to a bad URL: the same
    page = _page("?omega2=1.2&eps=0.9&theta0=-1.5")
    page.history.search = "?omega2=abc&eps=2"
    assert len(page.errors) == 2 and page.text["omega2"].value == "1.2"
    assert page.text["eps"].value == "0.9"
    _shows(page, 1.2, 0.9, -1.5)


def test_si_url_in_step_with_the_view():
    """Item 13: in SI mode the URL carries the omega2 (and eps, theta0) of the view on screen;
    before, omega2 was that of the update before."""
    page = _page("?si=1&velocity=0.1")
    for v in (0.3, 0.05, -0.2):
        page.text["velocity"].value = repr(v)
        args = model.inputs_from_query(page.history.search)
        bed = page.snapshot.params.bed
        assert float(args["omega2"]) == bed.omega2(v) == page.snapshot.params.omega2
        assert float(args["theta0"]) == math.copysign(1.0, v) * bed.base_angle
        assert float(args["eps"]) == bed.eps and float(args["velocity"]) == v


def test_unstable_and_twirling_states_look_different():
    """Item 13: unstable states are drawn with long dashes in their state's colour, twirling
    ones with dots in a colour no physical state has, with diamonds at their tips; each
    figure's legend shows both as drawn."""
    from bokeh.models import GlyphRenderer

    from hairbed.explorer._figures import STATE_COLORS

    page = _page("?omega2=1.2&eps=0.9&theta0=-1.5&twirl=1")
    v = page.views

    def glyph(fig, source):
        (r,) = [
            r for r in fig.renderers if isinstance(r, GlyphRenderer) and r.data_source is source
        ]
        return r.glyph

    for fig, unstable, twirl in (
        (v.channel, v.ch_unstable, v.ch_twirl),
        (v.phase, v.ph_unstable, v.ph_twirl),
    ):
        u, t = glyph(fig, unstable), glyph(fig, twirl)
        dash, width = list(u.line_dash), u.line_width
        # dashes, not dots: each dash several line widths long
        assert dash and min(dash[::2]) >= 3 * width, (dash, width)
        assert list(t.line_dash) != dash and max(list(t.line_dash)[::2]) <= t.line_width
        assert t.line_color not in STATE_COLORS.values()
        labels = {item.label.value: item for item in fig.legend[0].items}
        assert {"unstable", "twirling"} <= set(labels)
        sample = labels["twirling"].renderers[0].glyph
        assert (sample.line_color, list(sample.line_dash)) == (t.line_color, list(t.line_dash))
        sample = labels["unstable"].renderers[0].glyph
        assert list(sample.line_dash) == dash
    tips = v.ch_twirl_tips.data
    assert len(tips["x"]) == len(page.snapshot.twirling)
    assert glyph(v.channel, v.ch_twirl_tips).marker != "circle"
