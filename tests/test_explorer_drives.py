"""The explorer's pump drives and valve view without a browser (issue 20, item 4).

Expectations are computed here from the library's public functions (``hairbed.solve_loaded``
for every root, ``solve_loaded_all``, ``HairBed.deform`` with ``pressure_gradient`` or
``flow_rate``, ``hairbed.valve``), never from the explorer's own code path. The dimensionless
valve view is checked against ``hairbed.valve`` of a bed in SI units (another path: the SI
layer, its own gap flow and resistance). The page in a real browser is tested in
tests/test_explorer_browser.py.
"""

from __future__ import annotations

import csv
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
#: Values computed by two paths agree to this (both converge to 1e-12 in theta).
REL = 1e-9


def _raw(**kw: object) -> dict[str, str]:
    return {k: str(v) for k, v in kw.items()}


def _library_message(func, *args, **kwargs) -> str:
    with pytest.raises(ValueError) as info:
        func(*args, **kwargs)
    return str(info.value)


def _roundtrip(p: model.Params) -> model.Params:
    return model.validate(model.inputs_from_query(model.query_from_inputs(p)))


# -- inputs and the URL --------------------------------------------------------------------


def test_pressure_drive_inputs_and_url_round_trip():
    p = model.validate(_raw(omega2=0, eps=0.5, theta0=0.5, drive="pressure", pi=5, view="valve"))
    assert (p.drive, p.load, p.load_key, p.view, p.omega2) == ("pressure", 5.0, "pi", "valve", 0.0)
    query = model.query_from_inputs(p)
    assert "drive=pressure" in query and "pi=5" in query and "view=valve" in query
    assert "q=" not in query  # only the drive's own load
    back = _roundtrip(p)
    assert (back.drive, back.load, back.view, back.omega2, back.theta0) == (
        p.drive, p.load, p.view, p.omega2, p.theta0,
    )  # fmt: skip


def test_flow_drive_negative_load_round_trips():
    p = model.validate(_raw(omega2=-0.5, eps=0.8, theta0=0.2, drive="flow", q=-0.03))
    assert (p.drive, p.load, p.omega2) == ("flow", -0.03, -0.5)
    back = _roundtrip(p)
    assert (back.drive, back.load, back.omega2) == ("flow", -0.03, -0.5)


def test_old_urls_load_as_the_wall_drive_and_keep_their_query():
    old = "?omega2=1.2&eps=0.9&theta0=-1.5&y=x1&si=0&twirl=0"
    p = model.validate(model.inputs_from_query(old))
    assert (p.drive, p.view, p.load) == ("wall", "branch", None)
    assert model.query_from_inputs(p) == old


def test_si_pump_drive_derives_its_load_from_the_bed():
    gradient = 20000.0
    raw = _raw(si=1, drive="pressure", velocity=0, pressure_gradient=gradient, base_angle=0.5)
    p = model.validate(raw)
    bed = hairbed.HairBed(**BED, base_angle=0.5)
    expected = bed.deform(pressure_gradient=gradient).solution
    assert p.load == pytest.approx(float(expected.pi), rel=1e-14)
    assert p.omega2 == 0.0 and p.theta0 == 0.5 and p.pump == gradient
    back = _roundtrip(p)
    assert (back.drive, back.pump, back.load) == ("pressure", gradient, p.load)
    assert "pressure_gradient=20000" in model.query_from_inputs(p)


@pytest.mark.parametrize(
    ("raw", "call"),
    [
        (_raw(drive="pressure", pi="x"), lambda: hairbed.solve_loaded(1.0, 0.5, pi="x")),
        (_raw(drive="flow", q="nan"), lambda: hairbed.solve_loaded(1.0, 0.5, q=float("nan"))),
        (
            _raw(drive="pressure", pi=1, eps=0),
            lambda: hairbed.solve_loaded(2.0, 0.0, pi=1.0),
        ),
        (_raw(drive="pressure", theta0=2), lambda: hairbed.solve_loaded(1.0, 0.5, 2.0, pi=1.0)),
    ],
)
def test_bad_pump_input_gives_the_library_message(raw, call):
    with pytest.raises(model.InputError) as info:
        model.validate(raw)
    with pytest.raises(ValueError) as lib:
        call()
    assert info.value.messages == (str(lib.value),)


def test_bad_choices_and_si_pump_values_are_named():
    with pytest.raises(model.InputError) as info:
        model.validate(_raw(drive="pump", view="map"))
    assert info.value.messages == (
        "drive must be one of 'wall', 'pressure', 'flow', got 'pump'",
        "view must be one of 'branch', 'valve', got 'map'",
    )
    bed = hairbed.HairBed(**BED)
    with pytest.raises(model.InputError) as info:
        model.validate(_raw(si=1, drive="flow", flow_rate="inf", channel_length=-1))
    assert info.value.messages == (
        _library_message(bed.deform, flow_rate=float("inf")),
        "channel_length must be positive, got -1.0 [m]",
    )


# -- the states ------------------------------------------------------------------------------


def test_pressure_drive_states_are_the_library_states():
    snap = model.compute(
        model.validate(_raw(omega2=2, eps=0.5, theta0=0.3, drive="pressure", pi=4))
    )
    assert [s.label for s in snap.states] == ["low"] and snap.message == ""
    expected = hairbed.solve_loaded(2.0, 0.5, 0.3, pi=4.0)
    got = snap.states[0].solution
    for field in ("tip_deflection", "tip_height", "tip_angle", "base_curvature"):
        assert float(getattr(got, field)) == pytest.approx(
            float(getattr(expected, field)), rel=REL
        )
    assert snap.states[0].stable is True
    # the branch diagram passes through the state, at abs(pi) on its abscissa
    assert snap.branch.states_x == [4.0]
    assert snap.branch.states_y[0] == pytest.approx(float(expected.tip_deflection), rel=REL)


def test_flow_drive_window_shows_three_states_with_their_stability():
    args = {"omega2": 0.0, "eps": 0.9, "theta0": -1.2, "q": 0.05}
    snap = model.compute(model.validate(_raw(**args, drive="flow")))
    assert [s.label for s in snap.states] == ["low", "mid", "high"]
    assert [s.stable for s in snap.states] == [True, False, True]
    for s in snap.states:
        ref = hairbed.solve_loaded(**args, root=s.label)
        assert int(ref.status) == 0
        assert float(s.solution.tip_height) == pytest.approx(float(ref.tip_height), rel=REL)
        assert float(s.solution.tip_deflection) == pytest.approx(
            float(ref.tip_deflection), rel=REL, abs=1e-12
        )


def test_a_failed_solve_shows_no_state_with_the_library_message():
    snap = model.compute(model.validate(_raw(omega2=0, drive="flow", q="1e300")))
    ref = hairbed.solve_loaded(0.0, 0.5, 0.0, q=1e300)
    assert int(ref.status) < 0
    assert snap.states == []
    assert ref.message in snap.message and f"status {int(ref.status)}" in snap.message
    json.loads(model.snapshot_json(snap), parse_constant=_no_constant)


def test_si_flow_drive_states_are_hairbed_deform():
    flow = 1e-6
    snap = model.compute(model.validate(_raw(si=1, drive="flow", velocity=0.05, flow_rate=flow)))
    bed = hairbed.HairBed(**BED)
    ref = bed.deform(0.05, flow_rate=flow)
    (s,) = snap.states
    assert s.si.tip_deflection == pytest.approx(float(ref.tip_deflection), rel=REL)
    assert s.si.pressure_gradient == pytest.approx(float(ref.pressure_gradient), rel=REL)
    assert float(s.solution.tip_height) == pytest.approx(float(ref.tip_height) / 1e-3, rel=REL)


# -- the valve ---------------------------------------------------------------------------------


def test_dimensionless_valve_agrees_with_hairbed_valve_of_a_bed():
    """The explorer's dimensionless valve (solve_loaded at omega2 = 0) against the SI
    library (hairbed.valve) of a bed with the same eps and base angle."""
    bed = hairbed.HairBed(**BED, base_angle=0.5)
    length, drop = 0.01, 200.0
    pi = float(bed.deform(pressure_gradient=drop / length).solution.pi)
    p = model.validate(
        _raw(omega2=0, eps=bed.eps, theta0=0.5, drive="pressure", pi=repr(pi), view="valve")
    )
    v = model.compute(p).valve
    assert v is not None and v.success and v.message == "ok"
    ref = hairbed.valve.diodicity(bed, drop, length)
    assert v.now["drop"] == pi
    assert v.now["diodicity"] == pytest.approx(float(ref.diodicity), rel=REL)
    assert v.now["forward_ratio"] == pytest.approx(float(ref.forward.resistance_ratio), rel=REL)
    assert v.now["backward_ratio"] == pytest.approx(float(ref.backward.resistance_ratio), rel=REL)
    # the flow in units of q: q = 6 A eta Q' L^2/(E I H^2), the bed's q per Q' from deform
    q_per_flow = float(bed.deform(flow_rate=1.0).solution.q)
    assert v.now["forward"] == pytest.approx(float(ref.forward.flow_rate) * q_per_flow, rel=REL)
    assert v.now["diodicity"] > 1.0  # hairs leaning towards +x: forward flow opens the gap
    # the curve: increasing drops, the empty channel above the lined one both ways
    assert np.all(np.diff(v.drop) > 0.0) and v.drop[-1] == 10.0  # 10^ceil(log10(2 pi))
    assert np.all(v.empty > v.forward) and np.all(v.empty > v.backward)


def test_si_valve_is_hairbed_valve():
    raw = _raw(si=1, drive="pressure", velocity=0, pressure_gradient=20000, base_angle=0.5)
    raw.update(view="valve", channel_length="0.02")
    v = model.compute(model.validate(raw)).valve
    bed = hairbed.HairBed(**BED, base_angle=0.5, density=1260.0)
    assert v.now["drop"] == pytest.approx(20000 * 0.02, rel=1e-14)
    ref = hairbed.valve.diodicity(bed, v.drop, 0.02)
    np.testing.assert_allclose(v.diodicity, ref.diodicity, rtol=REL)
    np.testing.assert_allclose(v.forward, ref.forward.flow_rate, rtol=REL)
    np.testing.assert_allclose(v.backward, np.abs(ref.backward.flow_rate), rtol=REL)
    np.testing.assert_allclose(v.empty, ref.forward.empty_flow_rate, rtol=1e-14)
    np.testing.assert_allclose(v.forward_ratio, ref.forward.resistance_ratio, rtol=REL)


def test_valve_of_the_wall_drive_and_without_a_top_wall():
    v = model.compute(model.validate(_raw(view="valve", theta0=-0.4))).valve
    assert v is not None and v.now["drop"] == 1.0  # the reference drop, pi = 1
    ref = hairbed.solve_loaded(np.zeros(2), 0.5, -0.4, pi=np.array([1.0, -1.0]))
    u = 1.0 - 0.5 * np.asarray(ref.tip_height)
    assert v.now["diodicity"] == pytest.approx((u[0] / u[1]) ** 3, rel=REL)
    assert v.now["diodicity"] < 1.0  # leaning against +x
    v0 = model.compute(model.validate(_raw(view="valve", eps=0))).valve
    assert v0.now == {} and not v0.success and "eps = 0" in v0.message


# -- exports -------------------------------------------------------------------------------------


def _no_constant(name: str):
    raise ValueError(f"{name} in JSON")


def test_pump_drive_exports():
    snap = model.compute(
        model.validate(_raw(omega2=0, eps=0.9, theta0=-1.2, drive="flow", q=0.05, view="valve"))
    )
    doc = json.loads(model.snapshot_json(snap), parse_constant=_no_constant)
    assert doc["solved"]["drive"] == "flow" and doc["solved"]["q"] == 0.05
    assert [s["state"] for s in doc["states"]] == ["low", "mid", "high"]
    assert doc["variables"]["distributed_load"]["units"] == "1"
    assert doc["valve"]["now"]["drop"] > 0.0
    ref = hairbed.solve_loaded(0.0, 0.9, -1.2, q=0.05, root="mid")
    assert doc["states"][1]["tip_height"] == pytest.approx(float(ref.tip_height), rel=REL)
    _, x, z, _ = ref.shape(np.linspace(0.0, 1.0, model.SHAPE_POINTS))
    np.testing.assert_allclose(doc["states"][1]["shape"]["z"], z, rtol=REL, atol=1e-12)
    rows = list(csv.reader(io.StringIO(model.snapshot_csv(snap))))
    assert "distributed_load [1]" in rows[0] and len(rows) == 4
    shape_rows = list(csv.reader(io.StringIO(model.snapshot_shape_csv(snap))))
    assert len(shape_rows) == 1 + 3 * model.SHAPE_POINTS


# -- the page (no browser) ---------------------------------------------------------------------


def test_page_switches_drive_moves_the_load_and_shows_the_valve():
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?omega2=0&theta0=0.5&drive=pressure&pi=5", served=False)
    assert page.errors == () and page.snapshot.params.drive == "pressure"
    assert page.text["pi"].visible and not page.text["q"].visible
    page.load_slider.value = 1.0  # log10(abs(pi))
    assert page.text["pi"].value == "10" and page.snapshot.params.load == 10.0
    page.view_choice.value = "valve"
    assert page._valve_flow_pane.visible and not page._branch_pane.visible
    assert 'data-field="diodicity"' in page.valve_table.object
    page.drive.value = "flow"
    assert page.snapshot.params.drive == "flow" and page.text["q"].visible
    page.text["q"].value = "1e300"  # no state: the message, not a traceback
    assert page.errors == () and "no state" in page.table.object
    page.text["q"].value = "nan"
    assert page.errors == (_library_message(hairbed.solve_loaded, 0.0, 0.5, 0.5, q=math.nan),)
    page.text["q"].value = "0.05"
    page.view_choice.value = "branch"
    assert page.errors == () and page.snapshot.params.view == "branch"
    assert page._branch_pane.visible and not page._valve_flow_pane.visible
    page.release()


def test_freed_memory_goes_back_where_the_c_library_can():
    from hairbed import explorer

    assert explorer._return_freed_memory() in (-1, 0, 1)


def test_si_load_slider_moves_the_pumps_gradient_even_from_zero():
    pytest.importorskip("panel")
    from hairbed.explorer._page import ExplorerPage

    page = ExplorerPage("?si=1&drive=pressure&velocity=0&pressure_gradient=0", served=False)
    assert page.errors == () and page.snapshot.params.load == 0.0
    page.load_slider.value = math.log10(0.5)  # abs(pi) = 0.5
    per_gradient = float(hairbed.HairBed(**BED).deform(pressure_gradient=1.0).solution.pi)
    gradient = float(page.text["pressure_gradient"].value)
    assert gradient == pytest.approx(0.5 / per_gradient, rel=1e-5)  # 6 digits in the field
    assert page.snapshot.params.pump == gradient
    assert page.snapshot.params.load == pytest.approx(gradient * per_gradient, rel=1e-14)
    page.release()


# -- the caches of the update path (issue 19 item 5) --------------------------------------------


def test_cached_pump_states_are_the_librarys_and_keep_their_warnings():
    """A second view at the same inputs comes from the cache: the same states, equal to a
    fresh solve of the library's, and the same warnings (the solve's own, replayed)."""
    model.clear_caches()
    raw = _raw(si=1, drive="flow", velocity=0.05, flow_rate=1e-3)
    first = model.compute(model.validate(raw))
    misses = model._PUMP_STATES.misses
    again = model.compute(model.validate(raw))
    assert model._PUMP_STATES.misses == misses  # no new solve
    assert [s.solution for s in again.states] == [s.solution for s in first.states]
    assert again.warnings == first.warnings
    assert any("Reynolds number" in w for w in again.warnings)
    ref = hairbed.HairBed(**BED).deform(0.05, flow_rate=1e-3)
    assert again.states[0].si.tip_deflection == pytest.approx(float(ref.tip_deflection), rel=REL)
    # the window of three states, twice: the library's states each time
    args = {"omega2": 0.0, "eps": 0.9, "theta0": -1.2, "q": 0.05}
    for _ in range(2):
        snap = model.compute(model.validate(_raw(**args, drive="flow")))
        fresh = hairbed.solve_loaded_all(**args)
        assert [float(s.solution.tip_height) for s in snap.states] == [
            float(f.tip_height) for f in fresh
        ]


def test_cache_is_bounded_least_recently_used_and_exact_in_its_keys():
    calls: list[tuple[float, ...]] = []

    def make(*args: float) -> tuple[float, ...]:
        calls.append(args)
        return args

    cache = model._Cache(3)
    for x in (1.0, 2.0, 3.0, 1.0, 4.0):  # 1.0 used again: 2.0 is the oldest when 4.0 comes
        cache.get(make, x)
    assert len(cache) == 3 and calls == [(1.0,), (2.0,), (3.0,), (4.0,)]
    cache.get(make, 2.0)  # evicted: made again
    assert calls[-1] == (2.0,) and len(cache) == 3
    cache.get(make, -0.0)
    cache.get(make, 0.0)  # 0.0 and -0.0 are other inputs
    assert calls[-2:] == [(-0.0,), (0.0,)]

    def bad(x: float) -> None:
        raise ValueError("x is bad")

    with pytest.raises(ValueError):
        cache.get(bad, 5.0)
    with pytest.raises(ValueError):  # a refused input is not cached: refused again
        cache.get(bad, 5.0)
    cache.clear()
    assert len(cache) == 0


def test_a_pump_state_shape_is_evaluated_once_for_both_views():
    from hairbed.explorer import _figures

    st = hairbed.solve_loaded(0.0, 0.9, -1.2, q=0.05)
    x, z = _figures._profile(st, 200)
    th, dth = _figures._phase(st, 200)
    _, x_ref, z_ref, th_ref = st.shape(np.linspace(0.0, 1.0, 200))
    assert np.array_equal(x, x_ref) and np.array_equal(z, z_ref) and np.array_equal(th, th_ref)
    assert _figures._loaded_shape(st, 200)[2] is th  # shared, not evaluated again
    assert not th.flags.writeable
