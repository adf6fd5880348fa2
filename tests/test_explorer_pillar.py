"""The explorer's pillar mode without a browser (issue 21, item 3).

Expectations are computed here from the library's public functions, called directly
(``hairbed.solve_pillar`` for each state and each root, ``solve_pillar_inverse``,
``gray_hancock_ratio``), from closed forms (the linear cantilever x1 = 11 Lambda cos^3(theta0)/120,
theory.md §12) and from central differences of ``solve_pillar``, never from the explorer's own
code path. The page in a real browser: tests/test_explorer_browser.py.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hairbed
from hairbed.explorer import _model as model
from hairbed.explorer import _pillar as pillar

#: Values computed by two paths agree to this (both converge to 1e-12 in theta).
REL = 1e-9


def _raw(**kw: object) -> dict[str, str]:
    return {"mode": "pillar", **{k: str(v) for k, v in kw.items()}}


def _message(func, *args, **kwargs) -> str:
    with pytest.raises((ValueError, TypeError)) as info:
        func(*args, **kwargs)
    return str(info.value)


# -- inputs and the URL ----------------------------------------------------------------------


def test_inputs_round_trip_through_the_url():
    p = pillar.validate_pillar(
        _raw(forcing=-3.5, pillar_theta0=0.4, profile="poiseuille", height_ratio=0.5,
             slenderness=50, tip_load=0.25, pillar_view="calibration")
    )  # fmt: skip
    q = pillar.pillar_query(p)
    assert q.startswith("?mode=pillar&forcing=-3.5&pillar_theta0=0.4&profile=poiseuille")
    again = pillar.validate_pillar(model.inputs_from_query(q))
    assert again == p
    assert p.gamma == hairbed.gray_hancock_ratio(50.0)
    assert p.kwargs == {
        "profile": "poiseuille", "height_ratio": 0.5, "gamma": p.gamma, "tip_load": 0.25,
    }  # fmt: skip


def test_old_urls_are_the_bed_and_keep_their_query():
    for query in ("?omega2=2&eps=0.5&theta0=0", "?omega2=0&drive=pressure&pi=5&view=valve"):
        args = model.inputs_from_query(query)
        assert not pillar.is_pillar(args) and pillar.mode_of(args) == "bed"
        q = model.query_from_inputs(model.validate(args))
        assert not any(k in q for k in ("mode=", "forcing=", "pillar_"))
    assert model.query_from_inputs(model.validate({"omega2": "2"})) == (
        "?omega2=2&eps=0.5&theta0=0&y=x1&si=0&twirl=0"
    )


@pytest.mark.parametrize(
    ("raw", "call"),
    [
        ({"forcing": "nan"}, lambda: hairbed.solve_pillar(math.nan)),
        ({"forcing": "abc"}, lambda: hairbed.solve_pillar("abc")),
        ({"pillar_theta0": "1.6"}, lambda: hairbed.solve_pillar(0.0, 1.6)),
        ({"profile": "poiseuille"}, lambda: hairbed.solve_pillar(0.0, profile="poiseuille")),
        ({"profile": "plug"}, lambda: hairbed.solve_pillar(0.0, profile="plug")),
        (
            {"profile": "couette", "height_ratio": "1.5"},
            lambda: hairbed.solve_pillar(0.0, profile="couette", height_ratio=1.5),
        ),
        ({"slenderness": "1"}, lambda: hairbed.gray_hancock_ratio(1.0)),
        ({"tip_load": "inf"}, lambda: hairbed.solve_pillar(0.0, tip_load=math.inf)),
    ],
)
def test_bad_input_gives_the_library_message(raw, call):
    with pytest.raises(model.InputError) as info:
        pillar.validate_pillar(_raw(**raw))
    assert info.value.messages == (_message(call),)


def test_every_bad_input_is_named_and_bad_choices_too():
    with pytest.raises(model.InputError) as info:
        pillar.validate_pillar(_raw(forcing="nan", pillar_theta0="2", pillar_view="map"))
    assert info.value.messages == (
        "pillar_view must be one of 'shape', 'calibration', 'drive', got 'map'",
        _message(hairbed.solve_pillar, math.nan),
        _message(hairbed.solve_pillar, 0.0, 2.0),
    )
    # gamma would be above 1 for L/a below e^1.5/2 = 2.24: refused by L/a itself (issue 33)
    with pytest.raises(model.InputError) as info:
        pillar.validate_pillar(_raw(slenderness="2"))
    (text,) = info.value.messages
    assert text == _message(hairbed.gray_hancock_ratio, 2.0)
    assert "slenderness must lie in [e^1.5/2" in text
    with pytest.raises(model.InputError, match="mode must be one of 'bed', 'pillar'"):
        pillar.mode_of({"mode": "bead"})


# -- states ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kw",
    [
        {"forcing": 2.0, "pillar_theta0": 0.0},
        {"forcing": -30.0, "pillar_theta0": 0.5, "slenderness": 20.0, "tip_load": 0.5},
        {"forcing": 5.0, "pillar_theta0": -0.3, "profile": "poiseuille", "height_ratio": 0.7},
    ],
)
def test_states_are_the_library_states(kw):
    snap = pillar.compute_pillar(pillar.validate_pillar(_raw(**kw)))
    gamma = hairbed.gray_hancock_ratio(kw["slenderness"]) if "slenderness" in kw else 0.5
    ref = hairbed.solve_pillar(
        kw["forcing"], kw["pillar_theta0"], profile=kw.get("profile", "sublayer"),
        height_ratio=kw.get("height_ratio"), gamma=gamma, tip_load=kw.get("tip_load", 0.0),
    )  # fmt: skip
    assert [v.label for v in snap.states] == ["low"] and snap.message == ""
    got = snap.states[0].state
    for field in pillar.PILLAR_FIELDS:
        assert getattr(got, field) == pytest.approx(getattr(ref, field), rel=REL, abs=1e-12)
    # the profile drawn is the undisturbed one: U = z, or z (1 - (L/H) z)
    r = kw.get("height_ratio", 0.0)
    z = snap.profile_z
    np.testing.assert_allclose(snap.profile_u, z * (1.0 - r * z), rtol=0, atol=1e-15)


def test_a_failed_solve_shows_no_state_with_the_library_message():
    snap = pillar.compute_pillar(pillar.validate_pillar(_raw(forcing="1e300")))
    ref = hairbed.solve_pillar(1e300)
    assert ref.status < 0 and snap.states == []
    assert snap.message == f"no state: {ref.message} (status {int(ref.status)})"
    doc = json.loads(pillar.pillar_snapshot_json(snap))
    assert doc["states"] == [] and doc["message"] == snap.message


@pytest.mark.slow
def test_snap_through_window_every_state_its_stability_and_the_folds():
    """theta0 = -1.45, Lambda = 20: three states (theory.md §12), each the library's root;
    the calibration curve's folds are extrema of the inverse problem's Lambda(x1)."""
    snap = pillar.compute_pillar(
        pillar.validate_pillar(_raw(forcing=20, pillar_theta0=-1.45, pillar_view="calibration"))
    )
    assert [(v.label, v.stable) for v in snap.states] == [
        ("low", True), ("mid", False), ("high", True),
    ]  # fmt: skip
    for v in snap.states:
        ref = hairbed.solve_pillar(20.0, -1.45, root=v.label)
        assert float(v.state.tip_deflection) == pytest.approx(ref.tip_deflection, abs=1e-9)
        assert float(v.state.tip_height) == pytest.approx(ref.tip_height, abs=1e-9)
    c = snap.calibration
    assert c is not None and c.status == 0 and c.folds.shape == (2, 2)
    assert (~c.stable).any() and c.stable[0] and c.stable[-1]
    for lam, x1 in c.folds:
        inv = hairbed.solve_pillar_inverse(x1, -1.45)
        assert float(inv.forcing) == pytest.approx(lam, rel=1e-9)
        # an extremum of Lambda(x1): both neighbours on the same side
        side = np.asarray(
            hairbed.solve_pillar_inverse(x1 + np.array([-1e-3, 1e-3]), -1.45).forcing
        )
        assert np.all(np.sign(side - lam) == np.sign(side[0] - lam))
    lo, hi = sorted(c.folds[:, 0])
    assert lo < 20.0 < hi


# -- the calibration curve -------------------------------------------------------------------


@pytest.mark.parametrize("theta0", [0.0, 0.6, -0.8])
def test_calibration_curve_against_the_library_and_the_linear_formula(theta0):
    snap = pillar.compute_pillar(
        pillar.validate_pillar(_raw(forcing=0.7, pillar_theta0=theta0, pillar_view="calibration"))
    )
    c = snap.calibration
    assert c is not None and c.status == 0 and c.folds.shape == (0, 2) and c.stable.all()
    # the linear cantilever (closed form, theory.md §12)
    assert c.rest == pytest.approx(math.sin(theta0), abs=1e-14)
    assert c.slope == pytest.approx(11.0 * math.cos(theta0) ** 3 / 120.0, rel=1e-10)
    # points of the curve against single solves
    for i in (0, 40, 90, 140):
        ref = hairbed.solve_pillar(float(c.forcing[i]), theta0)
        assert c.tip_deflection[i] == pytest.approx(ref.tip_deflection, rel=REL, abs=1e-13)
    # the 1 % and 10 % marks: the linear formula's reading of Lambda is that far off there
    for level in pillar.ERROR_LEVELS:
        lam = c.levels[level]
        x1 = float(hairbed.solve_pillar(lam, theta0).tip_deflection)
        read = (x1 - math.sin(theta0)) / (11.0 * math.cos(theta0) ** 3 / 120.0)
        assert abs(read - lam) / lam == pytest.approx(level, rel=0.02)
    # the error at the current state, and the state as a dot on the curve
    x1 = float(hairbed.solve_pillar(0.7, theta0).tip_deflection)
    slope = 11.0 * math.cos(theta0) ** 3 / 120.0
    assert snap.error_at() == pytest.approx(abs((x1 - math.sin(theta0)) / slope - 0.7) / 0.7)


def test_calibration_with_a_tip_load_and_a_channel_uses_the_slope_at_rest():
    kw = {"profile": "poiseuille", "height_ratio": 0.8, "gamma": 0.6, "tip_load": 0.3}
    snap = pillar.compute_pillar(
        pillar.validate_pillar(
            _raw(forcing=-2, pillar_theta0=0.2, profile="poiseuille", height_ratio=0.8,
                 slenderness=8.6, tip_load=0.3, pillar_view="calibration")
        )
    )  # fmt: skip
    kw["gamma"] = snap.params.gamma
    c = snap.calibration
    assert c is not None
    rest = float(hairbed.solve_pillar(0.0, 0.2, **kw).tip_deflection)
    h = 1e-4
    fd = (
        float(hairbed.solve_pillar(h, 0.2, **kw).tip_deflection)
        - float(hairbed.solve_pillar(-h, 0.2, **kw).tip_deflection)
    ) / (2 * h)
    assert c.rest == pytest.approx(rest, abs=1e-13)
    assert c.slope == pytest.approx(-fd, rel=1e-6)  # along the flow, towards -x
    x1 = float(hairbed.solve_pillar(-2.0, 0.2, **kw).tip_deflection)
    assert float(snap.states[0].state.tip_deflection) == pytest.approx(x1, rel=REL)


def test_calibration_curve_is_cached_per_pillar():
    raw = _raw(forcing=1, pillar_theta0=0.1, pillar_view="calibration")
    first = pillar.compute_pillar(pillar.validate_pillar(raw)).calibration
    moved = pillar.compute_pillar(pillar.validate_pillar({**raw, "forcing": "3"})).calibration
    other = pillar.compute_pillar(pillar.validate_pillar({**raw, "tip_load": "0.1"})).calibration
    assert moved is first and other is not first
    shape = pillar.compute_pillar(pillar.validate_pillar({**raw, "pillar_view": "shape"}))
    assert shape.calibration is None


def test_json_export_carries_the_states_and_the_linear_formula():
    snap = pillar.compute_pillar(
        pillar.validate_pillar(_raw(forcing=4, pillar_view="calibration"))
    )
    doc = json.loads(pillar.pillar_snapshot_json(snap))
    assert doc["mode"] == "pillar" and doc["inputs"]["forcing"] == "4"
    (state,) = doc["states"]
    ref = hairbed.solve_pillar(4.0)
    assert state["tip_deflection"] == pytest.approx(ref.tip_deflection, rel=REL)
    assert len(state["shape"]["x"]) == 101 and state["shape"]["x"][-1] == pytest.approx(
        ref.tip_deflection, abs=1e-12
    )
    assert doc["calibration"]["slope"] == pytest.approx(11.0 / 120.0, rel=1e-10)


# -- the page (no browser) -------------------------------------------------------------------


def test_page_pillar_mode_slider_view_and_a_bad_link():
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?mode=pillar&forcing=2", served=False)
    panel = page.pillar
    assert page.errors == () and panel.shown_mode == "pillar"
    assert panel.views.visible and not page._bed_views.visible
    assert page.history.search.startswith("?mode=pillar&forcing=2&")
    ref = hairbed.solve_pillar(2.0)
    assert f'data-field="tip_deflection">{ref.tip_deflection:.12g}<' in panel.table.object
    panel.forcing_slider.value = 1.0  # log10(abs(Lambda))
    assert page.text["forcing"].value == "10" and panel.snapshot.params.forcing == 10.0
    panel.view.value = "calibration"
    assert panel._cal_pane.visible and 'data-field="slope"' in panel.linear_table.object
    assert "pillar_view=calibration" in page.history.search
    page.text["pillar_theta0"].value = "2"  # typed: the message, the last view kept
    assert page.errors == (_message(hairbed.solve_pillar, 0.0, 2.0),)
    assert panel.snapshot.params.theta0 == 0.0
    page.text["pillar_theta0"].value = "0"
    page.text["forcing"].value = "1e300"
    assert page.errors == () and "no state" in panel.table.object
    page.text["forcing"].value = "10"
    page._apply_query("?mode=pillar&forcing=abc")  # a bad link: the fields back
    assert page.errors == (_message(hairbed.solve_pillar, "abc"),)
    assert page.text["forcing"].value == "10" and panel.mode.value == "pillar"
    panel.mode.value = "bed"  # the bed as it was
    assert page.errors == () and not panel.views.visible and page._bed_views.visible
    assert page.history.search == "?omega2=2&eps=0.5&theta0=0&y=x1&si=0&twirl=0"
    page._apply_query("?mode=pillar&forcing=3", restore=True)  # Back to a pillar view
    assert panel.shown_mode == "pillar" and panel.snapshot.params.forcing == 3.0
    assert panel.snapshot.params.view == "shape" and not panel._cal_pane.visible
    panel.mode.value = "bed"
    page.presets["pillar snap-through"].clicks += 1  # a preset opens the pillar mode
    assert panel.shown_mode == "pillar" and [v.label for v in panel.snapshot.states] == [
        "low", "mid", "high",
    ]  # fmt: skip
    assert 'data-count="3"' in panel.table.object and 'data-field="stable"' in panel.table.object
    page.release()


@pytest.mark.slow
def test_window_towards_minus_x_is_the_mirror_image():
    """Lambda -> -Lambda with theta0 -> -theta0 is the mirror image x -> -x (theory.md §12):
    the same three states, mirrored, with the same stability."""
    snap = pillar.compute_pillar(pillar.validate_pillar(_raw(forcing=-20, pillar_theta0=1.45)))
    for v in snap.states:
        ref = hairbed.solve_pillar(20.0, -1.45, root=v.label)
        assert float(v.state.tip_deflection) == pytest.approx(-ref.tip_deflection, abs=1e-9)
    assert [(v.label, v.stable) for v in snap.states] == [
        ("low", True), ("mid", False), ("high", True),
    ]  # fmt: skip


def test_a_bed_session_builds_no_pillar_figure():
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?omega2=1.2", served=False)
    assert page.pillar.views.objects == [] and not page.pillar.views.visible
    page.pillar.mode.value = "pillar"
    assert page.pillar.views.visible and len(page.pillar.views.objects) == 3
    page.release()
