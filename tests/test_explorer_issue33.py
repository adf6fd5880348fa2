"""The explorer's items of issue 33: a link's unknown parameters, the pillar's branch cache
and the export of a view as PNG.

Expectations come from the library's public functions (``hairbed.solve``,
``hairbed.solve_pillar_all``), never from the explorer's own code path.
"""

from __future__ import annotations

import html
import math

import pytest

import hairbed

pytest.importorskip("panel")


def _page(query: str = ""):
    from hairbed.explorer._page import ExplorerPage

    return ExplorerPage(query)


def _alert(page) -> str:
    return html.unescape(page.alert.object) if page.alert.visible else ""


# -- a link's unknown parameters ----------------------------------------------------------


def test_an_unknown_url_parameter_leaves_the_known_ones_applied():
    page = _page("?omega2=1.2&eps=0.9&theta0=-1.5&colour=red&zoom=2")
    p = page.snapshot.params
    assert (p.omega2, p.eps, p.theta0) == (1.2, 0.9, -1.5)
    assert len(page.snapshot.states) == hairbed.solve(1.2, 0.9, -1.5).n_roots == 3
    assert page.error == "" and page.errors == ()
    assert page.alert.visible
    text = _alert(page)
    assert "ignored the unknown URL parameters 'colour', 'zoom'" in text
    assert "omega2" in text.split("known:")[1]  # the known names are listed
    assert "colour" not in page.history.search  # the address bar shows the view's own link
    # the next change is an ordinary one: the note goes
    page.text["omega2"].value = "1.3"
    assert not page.alert.visible and page.snapshot.params.omega2 == 1.3


def test_unknown_parameters_alone_and_beside_a_bad_value():
    page = _page("?colour=red")
    assert page.snapshot.params.omega2 == 2.0 and page.alert.visible
    assert "'colour'" in _alert(page) and page.error == ""
    page = _page("?eps=1.5&colour=red")
    assert "eps" in page.error  # the library's message for the bad value
    assert "ignored the unknown URL parameter 'colour'" in _alert(page)
    assert page.snapshot.params.eps == 0.5  # the defaults stay on screen


def test_an_unknown_parameter_of_a_pillar_link_and_of_the_history():
    page = _page("?mode=pillar&forcing=3&pillar_theta0=0.2&size=big")
    p = page.pillar.snapshot.params
    assert (p.forcing, p.theta0) == (3.0, 0.2)
    assert "'size'" in _alert(page) and page.alert.visible
    x1 = float(hairbed.solve_pillar(3.0, 0.2).tip_deflection)
    assert page.pillar.snapshot.states[0].state.tip_deflection == pytest.approx(x1, rel=1e-12)
    page.history.search = "?omega2=0.7&eps=0.6&theta0=0.1&foo=1"  # Back to a bed's link
    q = page.snapshot.params
    assert (q.omega2, q.eps, q.theta0) == (0.7, 0.6, 0.1)
    assert "'foo'" in _alert(page) and page.pillar.shown_mode == "bed"
    assert math.isfinite(page.snapshot.states[0].solution.xi)


# -- a pillar's branch, cached: every forcing's states read from it ------------------------


def _counting(monkeypatch) -> dict[str, int]:
    """Count the library's branch solvers as the explorer calls them."""
    calls = {"continue_pillar": 0, "solve_pillar_all": 0}
    for name in calls:
        real = getattr(hairbed, name)

        def counted(*args, _real=real, _name=name, **kwargs):
            calls[_name] += 1
            return _real(*args, **kwargs)

        monkeypatch.setattr(hairbed, name, counted)
    return calls


def test_a_new_forcing_in_a_window_reads_the_pillars_cached_branch(monkeypatch):
    from hairbed.explorer import _pillar as pillar

    pillar.clear_pillar_caches()
    calls = _counting(monkeypatch)
    page = _page("?mode=pillar&forcing=20&pillar_theta0=-1.45")
    assert calls == {"continue_pillar": 1, "solve_pillar_all": 0}
    counts = []
    for lam in ("15.5", "18", "21", "22", "1", "30"):
        page.text["forcing"].value = lam
        assert page.errors == ()
        counts.append(len(page.pillar.snapshot.states))
    # the window of theta0 = -1.45 lies between its folds, Lambda = 14.83 and 22.29
    assert counts == [3, 3, 3, 3, 1, 1]
    page.pillar.view.value = "calibration"  # the calibration curve reads the same branch
    assert page.pillar.snapshot.calibration.folds.shape == (2, 2)
    assert calls == {"continue_pillar": 1, "solve_pillar_all": 0}
    page.text["forcing"].value = "-20"  # towards -x it leans downstream: no window
    assert len(page.pillar.snapshot.states) == 1
    assert calls == {"continue_pillar": 1, "solve_pillar_all": 0}
    page.text["pillar_theta0"].value = "1.45"  # the mirror image: a pillar of its own
    page.text["forcing"].value = "-21"
    assert len(page.pillar.snapshot.states) == 3
    assert calls == {"continue_pillar": 2, "solve_pillar_all": 0}
    pillar.clear_pillar_caches()
    assert pillar.pillar_branch.cache_info().currsize == 0


@pytest.mark.parametrize(("forcing", "theta0"), [(21.0, -1.45), (-22.2, 1.45)])
def test_the_states_read_from_the_branch_are_solve_pillar_alls(forcing, theta0):
    """Against the library's own every-state solver (bisection on its branch, no Newton),
    in both flow directions, one forcing close to the upper fold."""
    from hairbed.explorer import _pillar as pillar

    p = pillar.validate_pillar(
        {"mode": "pillar", "forcing": str(forcing), "pillar_theta0": str(theta0)}
    )
    got = pillar.branch_states(p)
    ref = hairbed.solve_pillar_all(forcing, theta0)
    assert got is not None and len(got) == len(ref) == 3
    for a, b in zip(got, ref):
        assert float(a.tip_deflection) == pytest.approx(float(b.tip_deflection), abs=1e-10)
        assert float(a.tip_height) == pytest.approx(float(b.tip_height), abs=1e-10)
        assert float(a.tip_angle) == pytest.approx(float(b.tip_angle), abs=1e-9)
        assert float(a.forcing) == pytest.approx(forcing, rel=1e-12)
        assert a.stable == b.stable and int(a.status) == 0
    assert [a.stable for a in got] == [True, False, True]
    labels = [v.label for v in pillar.compute_pillar(p).states]
    assert labels == ["low", "mid", "high"]
