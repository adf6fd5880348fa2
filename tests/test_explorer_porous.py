"""The explorer's bed-model selector (issue 29): a porous bed in SI mode, without a browser.

Expectations are computed here from the library's public API (``HairBed(..., model="porous")``
and its ``deform``, ``kappa``, ``drag_ratio``, ``hairbed.solve_porous_all``), never from the
explorer's own code path.
"""

from __future__ import annotations

import csv
import html
import io
import json
import math

import numpy as np
import pytest

import hairbed
from hairbed.explorer import _model as model

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}
#: Values of two paths agree to this (the same solver, run by each: the same bits or close).
REL = 1e-9


def _raw(**kw: object) -> dict[str, str]:
    return {k: str(v) for k, v in kw.items()}


def _porous(drag: str = "crossover", **kw: object) -> hairbed.HairBed:
    return hairbed.HairBed(**{**BED, "density": 1260.0, **kw}, model="porous", drag=drag)


def _state(snap: model.Snapshot, label: str = "low") -> model.StateView:
    return next(s for s in snap.states if s.label == label)


def _close(a: float, b: float) -> bool:
    return math.isclose(float(a), float(b), rel_tol=REL, abs_tol=1e-300)


# -- the state view ---------------------------------------------------------------------------


@pytest.mark.parametrize("drag", ["crossover", "sparse", "array"])
def test_porous_state_is_hairbed_deform(drag):
    p = model.validate(_raw(si=1, model="porous", drag=drag, velocity=0.1))
    assert p.porous and p.bed.model == "porous" and p.bed.drag == drag
    snap = model.compute(p)
    want = _porous(drag).deform(0.1)
    assert [s.label for s in snap.states] == ["low"]
    got = _state(snap).si
    for k in ("tip_deflection", "tip_height", "tip_angle", "wall_shear_stress", "force_per_hair",
              "stress_ratio", "flow_rate"):  # fmt: skip
        assert _close(getattr(got, k), getattr(want, k)), k
    # the hair drawn is the porous state's (its interpolant), the dense one's differs
    sigma = np.linspace(0.0, 1.0, 11)
    assert np.allclose(
        _state(snap).solution.shape(sigma)[1], want.solution.shape(sigma)[1], rtol=0, atol=1e-12
    )
    # stability: solve_porous_all's, at the bed's kappa and gamma
    every = hairbed.solve_porous_all(
        float(want.omega2), 0.5, 0.0, kappa=p.bed.kappa, gamma=p.bed.drag_ratio, pi=0.0
    )
    assert _state(snap).stable == bool(every[0].stable)
    # the branch diagram's low branch passes through the state
    assert snap.branch.x_label.startswith("wall speed") and "porous" in snap.branch.x_label
    assert snap.branch.states_y == [pytest.approx(float(want.tip_deflection), rel=REL)]


def test_porous_kappa_and_brinkman_length_on_the_page_and_in_the_json():
    pytest.importorskip("panel")
    from hairbed.explorer._page import porous_html

    bed = _porous("sparse")
    snap = model.compute(model.validate(_raw(si=1, model="porous", drag="sparse")))
    text = porous_html(snap)
    assert f'data-kappa="{bed.kappa!r}"' in text
    assert f'data-brinkman-length="{math.sqrt(bed.kappa) * bed.length!r}"' in text
    doc = json.loads(model.snapshot_json(snap))
    assert doc["bed"]["model"] == "porous" and doc["bed"]["drag"] == "sparse"
    assert _close(doc["bed"]["kappa"], bed.kappa)
    assert _close(doc["bed"]["drag_ratio"], bed.drag_ratio)
    assert _close(doc["bed"]["brinkman_length"], math.sqrt(bed.kappa) * 1e-3)
    assert doc["bed_variables"]["brinkman_length"]["units"] == "m"
    state = doc["states"][0]
    assert _close(state["si_tip_deflection"], bed.deform(0.1).tip_deflection)
    assert _close(state["kappa"], bed.kappa)
    rows = list(csv.reader(io.StringIO(model.snapshot_csv(snap))))
    assert "kappa [1]" in rows[0] and len(rows) == 2
    assert porous_html(model.compute(model.validate(_raw(si=1)))) == ""  # a dense bed: none


def test_porous_backward_wall_keeps_the_beds_frame():
    p = model.validate(_raw(si=1, model="porous", velocity=-0.1, base_angle=0.3))
    want = _porous(base_angle=0.3).deform(-0.1)
    got = _state(model.compute(p)).si
    assert want.tip_deflection < 0.0
    assert _close(got.tip_deflection, want.tip_deflection)
    assert _close(got.wall_shear_stress, want.wall_shear_stress)
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?si=1&model=porous&velocity=-0.1&base_angle=0.3", served=False)
    tip = [float(x[-1]) for x in page.views.ch_stable.data["xs"]]  # drawn in mm, not mirrored
    assert tip == [pytest.approx(want.tip_deflection * 1e3, rel=1e-9)]


@pytest.mark.parametrize(
    ("drive", "name", "value"),
    [("pressure", "pressure_gradient", 2e4), ("flow", "flow_rate", 1e-6)],
)
def test_porous_pump_drives_are_hairbed_deform(drive, name, value):
    p = model.validate(_raw(si=1, model="porous", drive=drive, **{name: value}, velocity=0.1))
    snap = model.compute(p)
    want = _porous().deform(0.1, **{name: value})
    got = _state(snap).si
    for k in ("tip_deflection", "tip_height", "wall_shear_stress", "pressure_gradient",
              "flow_rate"):  # fmt: skip
        assert _close(getattr(got, k), getattr(want, k)), k
    assert snap.branch.states_x == [pytest.approx(value, rel=REL)]


def test_switching_back_to_dense_restores_the_dense_numbers():
    dense_raw = _raw(si=1, velocity=0.1)
    before = _state(model.compute(model.validate(dense_raw))).si
    porous = _state(model.compute(model.validate({**dense_raw, "model": "porous"}))).si
    after_p = model.validate({**dense_raw, "model": "dense", "drag": "array"})
    after = _state(model.compute(after_p)).si
    dense = hairbed.HairBed(**BED, density=1260.0).deform(0.1)
    assert not after_p.porous and after_p.bed.model == "dense"
    assert after.tip_deflection == before.tip_deflection == dense.tip_deflection
    assert after.wall_shear_stress == dense.wall_shear_stress
    assert not math.isclose(porous.tip_deflection, dense.tip_deflection, rel_tol=1e-4)
    # a dense bed's link is the one it always was: no model, no drag
    query = model.query_from_inputs(after_p)
    assert "model=" not in query and "drag=" not in query


# -- the URL ------------------------------------------------------------------------------------


def test_url_round_trip_of_a_porous_bed():
    p = model.validate(_raw(si=1, model="porous", drag="array", velocity=0.05, view="valve"))
    query = model.query_from_inputs(p)
    assert "model=porous" in query and "drag=array" in query
    back = model.validate(model.inputs_from_query(query))
    assert back.porous and (back.bed.model, back.bed.drag) == ("porous", "array")
    assert back.bed == p.bed and back.velocity == p.velocity and back.view == "valve"
    assert model.query_from_inputs(back) == query


def test_unknown_model_or_drag_and_porous_without_si_are_refused():
    with pytest.raises(model.InputError) as info:
        model.validate(_raw(si=1, model="brinkman", drag="stokes"))
    text = str(info.value)
    assert "model must be one of 'dense', 'porous', got 'brinkman'" in text
    assert "drag must be one of 'crossover', 'sparse', 'array', got 'stokes'" in text
    with pytest.raises(model.InputError, match="si=1"):
        model.validate(_raw(model="porous"))
    # the porous bed's own limit, by the library's message
    with pytest.raises(model.InputError, match="packing_fraction must lie in"):
        model.validate(_raw(si=1, model="porous", spacing="", packing_fraction=0.7))


# -- the page: the selector, the alert of what a porous bed does not support ------------------


def test_page_selector_alert_and_png_link():
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?si=1&velocity=0.1", served=False)
    dense = _state(page.snapshot).si.tip_deflection
    assert not page.alert.visible and not page.drag.visible
    page.model.value = "porous"  # the selector: a porous bed, its drag model shown
    assert page.snapshot.params.porous and page.drag.visible
    assert _close(_state(page.snapshot).si.tip_deflection, _porous().deform(0.1).tip_deflection)
    assert "model=porous" in page.history.search and "hb-porous" in page.porous_info.object
    # a view a porous bed does not support: the library's NotImplementedError, in the alert
    page.twirl.value = [page.twirl.options[0]]
    with pytest.raises(NotImplementedError) as info:
        hairbed.units.require_dense(
            page.snapshot.params.bed, "the twirling states (hairbed.solve_all)"
        )
    alert = html.unescape(page.alert.object)
    assert page.alert.visible and str(info.value) in alert
    assert page.error == "" and page.snapshot.twirling == []  # no dense numbers, no traceback
    # the pump drives on the page: the states of HairBed(model="porous").deform
    page.twirl.value = []
    page.drive.value = "pressure"
    page.text["pressure_gradient"].value = "30000"
    want = _porous().deform(0.1, pressure_gradient=3e4)
    assert page.error == "" and page.snapshot.params.drive == "pressure"
    assert _close(_state(page.snapshot).si.tip_deflection, want.tip_deflection)
    assert page.views.ch_flow.data["x1"]  # the gap's Couette-Poiseuille profile drawn
    page.drive.value = "flow"
    assert page.error == "" and _close(
        _state(page.snapshot).si.tip_deflection,
        _porous().deform(0.1, flow_rate=1e-6).tip_deflection,
    )
    page.drive.value = "wall"
    page.twirl.value = [page.twirl.options[0]]
    page.drag.value = "array"
    assert page.snapshot.params.bed.drag == "array" and "drag=array" in page.history.search
    # the PNG export's link is the view's
    pytest.importorskip("matplotlib")
    from hairbed.explorer._export import view_figure

    fig = view_figure(page)
    assert "model=porous&drag=array" in " ".join(t.get_text() for t in fig.texts)
    # back to dense: the dense numbers, and the alert gone
    page.twirl.value = []
    page.model.value = "dense"
    assert not page.snapshot.params.porous and not page.alert.visible
    assert _state(page.snapshot).si.tip_deflection == dense
    assert page.porous_info.object == "" and "model=" not in page.history.search
