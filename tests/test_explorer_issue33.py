"""The explorer's items of issue 33: a link's unknown parameters, the pillar's branch cache
and the export of a view as PNG.

Expectations come from the library's public functions (``hairbed.solve``,
``hairbed.solve_pillar_all``), never from the explorer's own code path.
"""

from __future__ import annotations

import html
import math

import numpy as np
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
    calls = {"continue_pillar": 0, "solve_pillar_all": 0, "solve_pillar_inverse": 0}
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
    assert (calls["continue_pillar"], calls["solve_pillar_all"]) == (1, 0)
    counts = []
    for lam in ("15.5", "18", "21", "22", "1", "30"):
        page.text["forcing"].value = lam
        assert page.errors == ()
        counts.append(len(page.pillar.snapshot.states))
    # the window of theta0 = -1.45 lies between its folds, Lambda = 14.83 and 22.29
    assert counts == [3, 3, 3, 3, 1, 1]
    inverse = calls["solve_pillar_inverse"]
    page.text["forcing"].value = "18"  # a forcing seen before: no solve at all
    assert calls["solve_pillar_inverse"] == inverse and len(page.pillar.snapshot.states) == 3
    page.pillar.view.value = "calibration"  # the calibration curve reads the same branch
    assert page.pillar.snapshot.calibration.folds.shape == (2, 2)
    assert (calls["continue_pillar"], calls["solve_pillar_all"]) == (1, 0)
    page.text["forcing"].value = "-20"  # towards -x it leans downstream: no window
    assert len(page.pillar.snapshot.states) == 1
    assert (calls["continue_pillar"], calls["solve_pillar_all"]) == (1, 0)
    page.text["pillar_theta0"].value = "1.45"  # the mirror image: a pillar of its own
    page.text["forcing"].value = "-21"
    assert len(page.pillar.snapshot.states) == 3
    assert (calls["continue_pillar"], calls["solve_pillar_all"]) == (2, 0)
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


def test_at_a_fold_two_states_and_beside_it_three_or_one():
    """At each fold of the branch (the library's golden-section search) the read gives the
    two states that meet there, one of them the fold's; 1e-6 inside the window three,
    outside one; no warning on the way (the page would show it)."""
    import warnings

    from hairbed.explorer import _pillar as pillar

    branch = pillar.pillar_branch(1.0, -1.45, "sublayer", None, 0.5, 0.0, 0)
    (upper, x_upper), (lower, x_lower) = branch.folds  # along the branch from rest
    assert lower < upper
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for fold, x_fold, inside in ((upper, x_upper, -1.0), (lower, x_lower, 1.0)):

            def read(lam):
                p = pillar.validate_pillar(
                    {"mode": "pillar", "forcing": repr(float(lam)), "pillar_theta0": "-1.45"}
                )
                return pillar.branch_states(p)

            at = read(fold)
            assert len(at) == 2
            assert min(abs(float(s.tip_deflection) - x_fold) for s in at) < 1e-6
            assert len(read(fold * (1.0 + inside * 1e-6))) == 3
            assert len(read(fold * (1.0 - inside * 1e-6))) == 1


# -- the view as a PNG, without a browser ---------------------------------------------------

#: Colours of the low, mid and high states (Okabe-Ito), as the page draws them.
STATE_RGB = {"low": (0, 114, 178), "mid": (213, 94, 0), "high": (0, 158, 115)}


def _pixels(path) -> dict[tuple[int, int, int], int]:
    """How many pixels of the PNG have each colour (RGB, 0-255)."""
    import matplotlib.image

    img = matplotlib.image.imread(path)
    rgb = np.round(img[..., :3] * 255.0).astype(np.int64).reshape(-1, 3)
    keys, counts = np.unique((rgb[:, 0] << 16) | (rgb[:, 1] << 8) | rgb[:, 2], return_counts=True)
    return {
        (int(k) >> 16, (int(k) >> 8) & 255, int(k) & 255): int(c) for k, c in zip(keys, counts)
    }


def _tips(ax) -> list[tuple[float, float]]:
    """The single round markers of an axes (each state's tip), sorted."""
    out = []
    for line in ax.get_lines():
        x, y = (np.asarray(v, dtype=float) for v in line.get_data())
        if line.get_marker() == "o" and line.get_linestyle() == "None" and x.size == 1:
            out.append((float(x[0]), float(y[0])))
    return sorted(out)


def test_export_png_of_a_bed_draws_the_librarys_states(tmp_path):
    from hairbed.explorer import export_png
    from hairbed.explorer._export import view_figure

    query = "?omega2=1.2&eps=0.9&theta0=-1.5"
    out = export_png(tmp_path / "view.png", "http://127.0.0.1:5006/" + query)
    assert out == tmp_path / "view.png" and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["view.png"]  # no temporary left
    seen = _pixels(out)
    for label, rgb in STATE_RGB.items():  # not blank: each state painted in its colour
        assert seen.get(rgb, 0) > 100, label
    # the figure behind it: the channel view's tips are hairbed.solve's roots
    page = _page(query)
    fig = view_figure(page)
    assert len(fig.axes) == 4
    channel = fig.axes[0]
    assert channel.get_title(loc="left").startswith("the hair in the channel")
    want = sorted(
        (float(s.tip_deflection), float(s.tip_height))
        for s in (hairbed.solve(1.2, 0.9, -1.5, root=r) for r in ("low", "mid", "high"))
    )
    got = _tips(channel)
    assert len(got) == 3
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    # to scale: one unit of x as long as one of z on the picture
    box = channel.get_window_extent()
    (x0, x1), (y0, y1) = channel.get_xlim(), channel.get_ylim()
    assert (x1 - x0) / box.width == pytest.approx((y1 - y0) / box.height, rel=0.01)
    assert "link: ?omega2=1.2&eps=0.9&theta0=-1.5" in " ".join(t.get_text() for t in fig.texts)


def test_export_png_of_a_pillar_in_its_window(tmp_path):
    from hairbed.explorer import export_png
    from hairbed.explorer._export import view_figure

    query = "?mode=pillar&forcing=21&pillar_theta0=-1.45&pillar_view=calibration"
    out = export_png(tmp_path / "pillar.png", query)
    seen = _pixels(out)
    for label, rgb in STATE_RGB.items():
        assert seen.get(rgb, 0) > 50, label
    fig = view_figure(_page(query))
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    assert titles[0].startswith("the pillar") and titles[1].startswith("calibration curve")
    assert fig.axes[1].get_xscale() == "log" and fig.axes[2].get_yscale() == "log"
    want = sorted(
        (float(s.tip_deflection), float(s.tip_height))
        for s in (hairbed.solve_pillar(21.0, -1.45, root=r) for r in ("low", "mid", "high"))
    )
    assert np.allclose(_tips(fig.axes[0]), want, rtol=0, atol=1e-9)


def test_export_png_refuses_a_bad_view_and_writes_nothing(tmp_path):
    from hairbed.explorer import export_png

    target = tmp_path / "view.png"
    target.write_bytes(b"before")
    with pytest.raises(ValueError, match="unknown URL parameter 'colour'; known: omega2"):
        export_png(target, "?omega2=2&colour=red")
    with pytest.raises(ValueError) as info:
        export_png(target, "?omega2=2&eps=1.5")
    with pytest.raises(ValueError) as lib:
        hairbed.solve(2.0, 1.5)
    assert str(info.value) == str(lib.value)
    with pytest.raises(TypeError, match="path must be a str or os.PathLike"):
        export_png(None)
    with pytest.raises(ValueError, match=r"path must name a \.png file"):
        export_png(tmp_path / "view.jpg")
    with pytest.raises(TypeError, match="query must be a str"):
        export_png(target, {"omega2": 2})
    with pytest.raises(FileNotFoundError, match="does not exist"):
        export_png(tmp_path / "missing" / "view.png", "?omega2=2")
    assert target.read_bytes() == b"before"  # whole or not at all
    assert sorted(p.name for p in tmp_path.iterdir()) == ["view.png"]


def test_hairbed_explore_export(tmp_path, capsys):
    from hairbed.cli import main

    out = tmp_path / "v.png"
    assert main(["explore", "--export", str(out), "--url-params", "?omega2=0.5"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
    capsys.readouterr()
    for argv, words in (
        (["--export", str(out), "--url-params", "?omega2=-1"], "--url-params: omega2"),
        (["--export", str(out), "--url-params", "?zoom=2"], "unknown URL parameter 'zoom'"),
        (["--export", str(tmp_path / "no" / "v.png")], "cannot write"),
        (["--export", str(tmp_path / "v.svg")], "give a .png file"),
        (["--url-params", "?omega2=2"], "--url-params needs --export"),
    ):
        assert main(["explore", *argv]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and words in err, err
