"""The explorer's live views as Bokeh figures, built once and updated in place.

Every update replaces the ``data`` of the ``ColumnDataSource`` objects whose content changed
(and moves a range only where the data left it); Bokeh sends only those to the browser, which
redraws just the figures that changed: no figure is rebuilt, no image is rendered on the server
and no range is fitted in the browser (a browser-fitted range is sent back to the server and
re-lays out the axes on every update).
"""

from __future__ import annotations

import math
import weakref
from typing import Any

import numpy as np
from bokeh.models import (
    ColumnDataSource,
    Legend,
    LegendItem,
    Range1d,
    Span,
)
from bokeh.plotting import figure

from .._jsonsafe import to_plain
from ._model import Snapshot, cusp_curve

__all__ = ["Views"]

#: Colours of the low, mid and high states (Okabe-Ito: colour-blind safe).
STATE_COLORS = {"low": "#0072B2", "mid": "#D55E00", "high": "#009E73"}
#: Twirling states: a colour of their own (Okabe-Ito's reddish purple), dots and diamonds.
TWIRL_COLOR = "#CC79A7"
TWIRL_DASH = [2, 4]
TWIRL_MARKER = "diamond"
#: Unstable states: long dashes (Bokeh's "dashed", 6 on 6 off, reads as dots at width 3).
UNSTABLE_DASH = [12, 6]
REST_COLOR = "#bdbdbd"
FOLD_COLOR = "black"
#: Pixels of the channel view's frame; its ranges keep one unit of x as long as one of z.
_FRAME_W, _FRAME_H = 460, 330
_PROFILE_POINTS = 200
_TWIRL_POINTS = 400
_PHASE_POINTS = 200
#: Render level of everything that moves with the flow: Bokeh repaints only this layer of a
#: figure when only such renderers changed, and keeps the axes, grid, legend and the fixed
#: curves painted (a full repaint of a figure costs tens of ms in a software-rendered canvas).
_LIVE = "overlay"


def _empty_lines() -> dict[str, list[Any]]:
    return {"xs": [], "ys": [], "color": [], "label": []}


def _fig(title: str, x_label: str, y_label: str, **kw: Any) -> Any:
    f = figure(
        title=title,
        x_axis_label=x_label,
        y_axis_label=y_label,
        toolbar_location="above",
        tools="pan,wheel_zoom,box_zoom,reset,save",
        **kw,
    )
    f.toolbar.autohide = True  # shown on hover: the title stays readable
    f.title.text_font_size = "13px"
    f.axis.axis_label_text_font_size = "12px"
    f.axis.axis_label_text_font_style = "normal"
    return f


def _style_legend(f: Any, items: list[tuple[str, list[Any]]], location: str) -> None:
    legend = Legend(
        items=[LegendItem(label=label, renderers=r) for label, r in items],
        location=location,
        label_text_font_size="11px",
        background_fill_alpha=0.8,
        spacing=0,
        padding=4,
        margin=4,
    )
    f.add_layout(legend)


_NAN = [float("nan")]


def _legend_lines(f: Any, *keys: str) -> dict[str, Any]:
    """Renderers for the legend only: fixed styles and one NaN point each (nothing on the plot;
    Bokeh draws no legend sample for a renderer without data, and the real renderers take
    their colours from the data). Only those of ``keys``: every renderer costs paint time."""
    make = {
        "stable": lambda: f.line(_NAN, _NAN, color="black", line_width=3),
        "unstable": lambda: f.line(
            _NAN, _NAN, color="black", line_width=3, line_dash=UNSTABLE_DASH
        ),
        "twirling": lambda: f.line(
            _NAN, _NAN, color=TWIRL_COLOR, line_width=2, line_dash=TWIRL_DASH
        ),
        "twirl_marker": lambda: f.scatter(
            _NAN, _NAN, marker=TWIRL_MARKER, size=9, color=TWIRL_COLOR, line_color="black"
        ),
        "rest": lambda: f.line(_NAN, _NAN, color=REST_COLOR, line_width=2),
        "curve": lambda: f.line(_NAN, _NAN, color="black", line_width=2),
        "folds": lambda: f.scatter(
            _NAN, _NAN, marker="x", size=12, line_width=3, color=FOLD_COLOR
        ),
        "state": lambda: f.scatter(_NAN, _NAN, color="white", size=10, line_color="black"),
    }
    return {k: make[k]() for k in keys}


def _equal(a: Any, b: Any) -> bool:
    """Whether two columns (or column entries) hold the same values (NaN equal to NaN)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        x, y = np.asarray(a), np.asarray(b)
        if x.shape != y.shape or x.dtype.kind != y.dtype.kind:
            return False
        return bool(np.array_equal(x, y, equal_nan=x.dtype.kind in "fc"))
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_equal(u, v) for u, v in zip(a, b))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    return bool(a == b)


def _bounds(*arrays: Any) -> tuple[float, float] | None:
    """(min, max) of the finite values of the arrays, or None."""
    finite = [v[np.isfinite(v)] for v in (np.asarray(a, dtype=np.float64) for a in arrays)]
    finite = [v for v in finite if v.size]
    if not finite:
        return None
    return float(min(v.min() for v in finite)), float(max(v.max() for v in finite))


def _fit(rng: Any, bounds: tuple[float, float] | None, sticky: bool) -> None:
    """Set a Range1d to ``bounds`` with 5 % padding (a flat range gets a unit's width).

    ``sticky``: leave the range where it is while the data stays inside it and fills at least
    half of it, so that a slider move does not re-lay out the axes on every step.
    """
    if bounds is None:
        return
    lo, hi = bounds
    span = hi - lo
    if sticky and rng.start <= lo and hi <= rng.end and span >= 0.5 * (rng.end - rng.start):
        return
    pad = 0.05 * span if span > 0.0 else 0.5 * max(abs(lo), 1.0)
    if sticky:
        pad *= 2.0  # room to move before the next change of range
    rng.start, rng.end = lo - pad, hi + pad


#: (x, z, theta) of a pump drive's states at ``num`` points, kept as long as the state
#: itself (the model caches states per input: a state shown again is not evaluated again).
_LOADED_SHAPES: weakref.WeakKeyDictionary[Any, dict[int, tuple[np.ndarray, ...]]] = (
    weakref.WeakKeyDictionary()
)


def _loaded_shape(sol: Any, num: int) -> tuple[np.ndarray, ...]:
    """(x, z, theta) [L, L, rad] of a :class:`hairbed.LoadedState` at ``num`` equally spaced
    arc lengths in [0, 1] (its spectral interpolant, ``shape``), evaluated once per state
    and ``num`` (read-only arrays: the channel view and the phase portrait share them)."""
    per = _LOADED_SHAPES.get(sol)
    if per is None:
        per = _LOADED_SHAPES.setdefault(sol, {})
    got = per.get(num)
    if got is None:
        _, x, z, theta = sol.shape(np.linspace(0.0, 1.0, num))
        got = tuple(np.asarray(v, dtype=np.float64) for v in (x, z, theta))
        for a in got:
            a.flags.writeable = False
        per[num] = got
    return got


def _profile(sol: Any, num: int) -> tuple[np.ndarray, np.ndarray]:
    """(x, z) [L] of a state along the hair: a closed-form Solution's ``profile`` or a pump
    drive's :class:`hairbed.LoadedState` (its spectral interpolant, ``shape``)."""
    if hasattr(sol, "profile"):
        x, z = sol.profile(num)
        return np.asarray(x, dtype=np.float64), np.asarray(z, dtype=np.float64)
    x, z, _ = _loaded_shape(sol, num)
    return x, z


def _phase(sol: Any, num: int) -> tuple[np.ndarray, np.ndarray]:
    """theta(sigma) and theta'(sigma) [1/L] at ``num`` equally spaced sigma in [0, 1]: the
    magnitude from the first integral theta'^2 / 2 + omega_eps^2 sin(theta) = E
    (theory.md §2), the sign from the slope. A pump drive's state has no such integral:
    theta' there is the slope of its interpolant."""
    sigma = np.linspace(0.0, 1.0, num)
    if not hasattr(sol, "omega_eps"):
        th = _loaded_shape(sol, num)[2]
        return th, np.gradient(th, sigma, edge_order=2)
    th = np.asarray(sol.theta(sigma), dtype=np.float64)
    w2 = float(sol.omega_eps) ** 2
    mag = np.sqrt(np.clip(2.0 * (float(sol.energy) - w2 * np.sin(th)), 0.0, None))
    return th, np.where(np.gradient(th, sigma) >= 0.0, mag, -mag)


class Views:
    """The four live figures (channel, branch diagram, bistability map, phase portrait)."""

    def __init__(self) -> None:
        #: The data last given to each source (by id): an unchanged source is not re-sent.
        self._shown: dict[int, dict[str, Any]] = {}
        self.channel = self._channel()
        self.branch = self._branch()
        self.bistability = self._bistability()
        self.phase = self._phase_portrait()
        self.valve_flow, self.valve_ratio = self._valve()

    # -- construction -----------------------------------------------------------------------

    def _channel(self) -> Any:
        self.ch_x = Range1d(-1.2, 1.2)
        self.ch_z = Range1d(-0.1, 1.6)
        f = _fig(
            "the hair in the channel, to scale",
            "x/L [-] (along the flow)",
            "z/L [-] (height)",
            x_range=self.ch_x,
            y_range=self.ch_z,
            frame_width=_FRAME_W,
            frame_height=_FRAME_H,
        )
        self.ch_floor = f.quad(
            left=-100, right=100, bottom=-100, top=0, fill_color="#d9d9d9", line_color="black"
        )
        self.ch_roof = f.quad(
            left=-100, right=100, bottom=1.0e9, top=1.0e9 + 100, fill_color="#d9d9d9"
        )
        self.ch_roof.glyph.line_color = "black"
        self.ch_flow = ColumnDataSource({"x0": [], "y0": [], "x1": [], "y1": []})
        f.segment(
            "x0", "y0", "x1", "y1", source=self.ch_flow, level=_LIVE, color="#9ecae1", line_width=2
        )
        f.scatter(
            "x1", "y1", source=self.ch_flow, level=_LIVE, marker="triangle", angle=-np.pi / 2,
            size=7, color="#9ecae1",
        )  # fmt: skip
        self.ch_rest = ColumnDataSource({"x": [], "y": []})
        f.line("x", "y", source=self.ch_rest, level=_LIVE, color=REST_COLOR, line_width=2)
        self.ch_twirl = ColumnDataSource(_empty_lines())
        f.multi_line(
            "xs", "ys", source=self.ch_twirl, level=_LIVE, color=TWIRL_COLOR, line_width=2,
            line_dash=TWIRL_DASH,
        )  # fmt: skip
        self.ch_twirl_tips = ColumnDataSource({"x": [], "y": []})
        f.scatter("x", "y", source=self.ch_twirl_tips, level=_LIVE, marker=TWIRL_MARKER, size=9,
                  color=TWIRL_COLOR, line_color="black")  # fmt: skip
        self.ch_stable = ColumnDataSource(_empty_lines())
        f.multi_line("xs", "ys", source=self.ch_stable, level=_LIVE, color="color", line_width=3)
        self.ch_unstable = ColumnDataSource(_empty_lines())
        f.multi_line(
            "xs",
            "ys",
            source=self.ch_unstable,
            level=_LIVE,
            color="color",
            line_width=3,
            line_dash=UNSTABLE_DASH,
        )
        self.ch_tips = ColumnDataSource({"x": [], "y": [], "color": [], "label": []})
        f.scatter("x", "y", source=self.ch_tips, level=_LIVE, color="color", size=7)
        f.text(
            "x", "y", text="label", source=self.ch_tips, level=_LIVE, text_font_size="11px",
            x_offset=6, y_offset=-4, text_color="color",
        )  # fmt: skip
        sample = _legend_lines(f, "stable", "unstable", "twirling", "twirl_marker", "rest")
        _style_legend(
            f,
            [
                ("stable", [sample["stable"]]),
                ("unstable", [sample["unstable"]]),
                ("twirling", [sample["twirling"], sample["twirl_marker"]]),
                ("at rest", [sample["rest"]]),
            ],
            "top_left",
        )
        f.grid.grid_line_alpha = 0.3
        return f

    def _branch(self) -> Any:
        f = _fig(
            "branch diagram at the current (eps, theta0)",
            "forcing omega^2 [-]",
            "tip deflection x1/L [-]",
            x_axis_type="log",
            x_range=Range1d(1e-3, 1e3),
            y_range=Range1d(-1.0, 1.0),
            width=470,
            height=360,
        )
        self.br_x, self.br_y = f.x_range, f.y_range
        self._br_window: tuple[float, float] = (1e-3, 1e3)
        self.br_curve = ColumnDataSource({"x": [], "y": []})
        f.line("x", "y", source=self.br_curve, color="black", line_width=2)
        self.br_twirl = ColumnDataSource(_empty_lines())
        f.multi_line("xs", "ys", source=self.br_twirl, color=TWIRL_COLOR, line_width=2,
                     line_dash=TWIRL_DASH)  # fmt: skip
        self.br_folds = ColumnDataSource({"x": [], "y": []})
        f.scatter("x", "y", source=self.br_folds, marker="x", size=12, line_width=3,
                  color=FOLD_COLOR)  # fmt: skip
        self.br_now = Span(dimension="height", location=1.0, line_color="#999999",
                           line_dash="dashed", level=_LIVE)  # fmt: skip
        f.add_layout(self.br_now)
        self.br_states = ColumnDataSource({"x": [], "y": [], "color": [], "label": []})
        f.scatter("x", "y", source=self.br_states, level=_LIVE, color="color", size=10,
                  line_color="black")  # fmt: skip
        sample = _legend_lines(f, "curve", "folds", "state", "twirling", "twirl_marker")
        self.br_twirl_states = ColumnDataSource({"x": [], "y": []})
        f.scatter("x", "y", source=self.br_twirl_states, level=_LIVE, marker=TWIRL_MARKER,
                  size=9, color=TWIRL_COLOR, line_color="black")  # fmt: skip
        _style_legend(
            f,
            [
                ("physical branch", [sample["curve"]]),
                ("folds", [sample["folds"]]),
                ("current states", [sample["state"]]),
                ("twirling branches, states", [sample["twirling"], sample["twirl_marker"]]),
            ],
            "top_left",
        )
        return f

    def _bistability(self) -> Any:
        f = _fig(
            "where three states coexist",
            "base angle theta0 [rad]",
            "confinement eps = L/H [-]",
            x_range=Range1d(-np.pi / 2, np.pi / 2),
            y_range=Range1d(0.0, 1.0),
            width=470,
            height=360,
        )
        th, ec = cusp_curve()
        region = f.varea(x=th, y1=ec, y2=np.ones_like(ec), fill_color="#E69F00", fill_alpha=0.35)
        cusp = f.line(th, ec, color="black", line_width=2)
        self.bi_now = ColumnDataSource({"x": [], "y": [], "color": []})
        f.scatter("x", "y", source=self.bi_now, level=_LIVE, size=12, color="color",
                  line_color="black", marker="circle")  # fmt: skip
        _style_legend(
            f,
            [
                ("three states (folded branch)", [region]),
                ("cusp eps_c(theta0)", [cusp]),
                ("current (theta0, eps)", [_legend_lines(f, "state")["state"]]),
            ],
            "bottom_right",
        )
        return f

    def _phase_portrait(self) -> Any:
        f = _fig(
            "phase portraits (square: base, circle: tip)",
            "angle theta [rad]",
            "curvature theta' [1/L]",
            x_range=Range1d(-1.0, 1.0),
            y_range=Range1d(-1.0, 1.0),
            width=470,
            height=360,
        )
        self.ph_x, self.ph_y = f.x_range, f.y_range
        self.ph_twirl = ColumnDataSource(_empty_lines())
        f.multi_line(
            "xs", "ys", source=self.ph_twirl, level=_LIVE, color=TWIRL_COLOR, line_width=2,
            line_dash=TWIRL_DASH,
        )  # fmt: skip
        self.ph_stable = ColumnDataSource(_empty_lines())
        f.multi_line("xs", "ys", source=self.ph_stable, level=_LIVE, color="color", line_width=3)
        self.ph_unstable = ColumnDataSource(_empty_lines())
        f.multi_line("xs", "ys", source=self.ph_unstable, level=_LIVE, color="color",
                     line_width=3, line_dash=UNSTABLE_DASH)  # fmt: skip
        self.ph_ends = ColumnDataSource({"x": [], "y": [], "color": [], "marker": []})
        f.scatter(
            "x", "y", source=self.ph_ends, level=_LIVE, color="color", marker="marker", size=8
        )
        sample = _legend_lines(f, "stable", "unstable", "twirling")
        _style_legend(
            f,
            [
                ("stable", [sample["stable"]]),
                ("unstable", [sample["unstable"]]),
                ("twirling", [sample["twirling"]]),
            ],
            "top_right",
        )
        return f

    def _valve(self) -> tuple[Any, Any]:
        """The bed as a valve: the flow against the pressure drop, and the resistance
        relative to the empty channel with the diodicity (shown instead of the branch diagram
        and the phase portrait in the valve view)."""
        flow = _fig(
            "the valve: flow against pressure drop (walls at rest)",
            "pressure drop abs(dp) [Pa]",
            "flow rate abs(Q') [m^2/s]",
            x_range=Range1d(0.0, 1.0),
            y_range=Range1d(0.0, 1.0),
            width=470,
            height=360,
        )
        self.vf_x, self.vf_y = flow.x_range, flow.y_range
        self.vf = ColumnDataSource({"x": [], "forward": [], "backward": [], "empty": []})
        empty = flow.line("x", "empty", source=self.vf, color=REST_COLOR, line_width=2)
        fwd = flow.line("x", "forward", source=self.vf, color=STATE_COLORS["low"], line_width=3)
        bwd = flow.line(
            "x", "backward", source=self.vf, color=STATE_COLORS["mid"], line_width=3,
            line_dash=UNSTABLE_DASH,
        )  # fmt: skip
        self.vf_now = Span(dimension="height", location=0.0, line_color="#999999",
                           line_dash="dashed", level=_LIVE)  # fmt: skip
        flow.add_layout(self.vf_now)
        _style_legend(
            flow,
            [("forward (+dp)", [fwd]), ("backward (-dp)", [bwd]), ("empty channel", [empty])],
            "top_left",
        )
        ratio = _fig(
            "resistance relative to the empty channel, and diodicity",
            "pressure drop abs(dp) [Pa]",
            "R/R0 [-], Di [-]",
            x_range=Range1d(0.0, 1.0),
            y_range=Range1d(0.0, 2.0),
            width=470,
            height=360,
        )
        self.vr_x, self.vr_y = ratio.x_range, ratio.y_range
        self.vr = ColumnDataSource(
            {"x": [], "forward_ratio": [], "backward_ratio": [], "diodicity": []}
        )
        rf = ratio.line(
            "x", "forward_ratio", source=self.vr, color=STATE_COLORS["low"], line_width=3
        )
        rb = ratio.line(
            "x", "backward_ratio", source=self.vr, color=STATE_COLORS["mid"], line_width=3,
            line_dash=UNSTABLE_DASH,
        )  # fmt: skip
        di = ratio.line("x", "diodicity", source=self.vr, color="black", line_width=2)
        self.vr_now = Span(dimension="height", location=0.0, line_color="#999999",
                           line_dash="dashed", level=_LIVE)  # fmt: skip
        ratio.add_layout(self.vr_now)
        _style_legend(
            ratio,
            [("R/R0 forward", [rf]), ("R/R0 backward", [rb]), ("diodicity Di", [di])],
            "top_left",
        )
        return flow, ratio

    # -- update -----------------------------------------------------------------------------

    def _set(self, source: Any, data: dict[str, Any]) -> None:
        """Give ``source`` new data, unless it holds exactly these values already (then nothing
        is sent and its figure is not repainted)."""
        last = self._shown.get(id(source))
        if last is not None and last.keys() == data.keys():
            if all(_equal(last[k], data[k]) for k in data):
                return
        self._shown[id(source)] = data
        # plain lists travel inside the patch's one JSON message: Bokeh sends every numpy
        # array as a binary buffer of its own, two websocket frames each (tens per update)
        source.data = {k: to_plain(v, strict=False) for k, v in data.items()}

    def release(self) -> None:
        """Forget the data last given to each source (the page's session is gone)."""
        self._shown.clear()

    def update(self, snap: Snapshot) -> None:
        """Show a snapshot: new data for every source of the four figures."""
        p = snap.params
        phys = [(s.label, s.solution, s.stable) for s in snap.states]
        twirl = [s.solution for s in snap.twirling]
        scale, unit = 1.0, "L"
        if p.si and p.bed is not None:
            scale, unit = p.bed.length * 1e3, "mm"
        self._update_channel(p, phys, twirl, scale, unit)
        self._update_branch(snap, phys)
        self._set(
            self.bi_now,
            {
                "x": [p.theta0],
                "y": [p.eps],
                "color": [STATE_COLORS["mid"] if len(phys) >= 3 else STATE_COLORS["low"]],
            },
        )
        self._update_phase(phys, twirl)
        self.bistability.title.text = "where three states coexist" + (
            " (of the dense bed, for reference)"
            if p.porous
            else ""
            if p.drive == "wall"
            else " (of the wall drive)"
        )
        if snap.valve is not None:
            self._update_valve(snap.valve)

    def _update_valve(self, v: Any) -> None:
        for f in (self.valve_flow, self.valve_ratio):
            f.xaxis.axis_label = v.x_label
        self.valve_flow.yaxis.axis_label = v.flow_label
        self._set(
            self.vf,
            {"x": v.drop, "forward": v.forward, "backward": v.backward, "empty": v.empty},
        )
        self._set(
            self.vr,
            {
                "x": v.drop,
                "forward_ratio": v.forward_ratio,
                "backward_ratio": v.backward_ratio,
                "diodicity": v.diodicity,
            },
        )
        top = float(v.drop[-1]) if v.drop.size else 1.0
        for rng in (self.vf_x, self.vr_x):
            rng.start, rng.end = 0.0, top
        _fit(self.vf_y, _bounds(v.forward, v.backward, v.empty, [0.0]), sticky=False)
        _fit(
            self.vr_y,
            _bounds(v.forward_ratio, v.backward_ratio, v.diodicity, [0.0, 1.0]),
            sticky=False,
        )
        where = float(v.now.get("drop", 0.0))
        for span in (self.vf_now, self.vr_now):
            span.location = where

    def _update_channel(
        self, p: Any, phys: list[Any], twirl: list[Any], scale: float, unit: str
    ) -> None:
        # the solution's frame is the bed's mirror image for a negative wall speed
        # (a pump drive's and a porous bed's states keep their signs: no mirror)
        backwards = (
            p.si and p.drive == "wall" and not p.porous and p.velocity is not None
            and p.velocity < 0.0
        )  # fmt: skip
        mirror = -1.0 if backwards else 1.0
        lines = {True: _empty_lines(), False: _empty_lines()}
        tips: dict[str, list[Any]] = {"x": [], "y": [], "color": [], "label": []}
        top_tip = 0.0
        for label, sol, stable in phys:
            x, z = _profile(sol, _PROFILE_POINTS)
            x, z = mirror * scale * x, scale * z
            d = lines[bool(stable)]
            d["xs"].append(x)
            d["ys"].append(z)
            d["color"].append(STATE_COLORS[label])
            d["label"].append(label)
            tips["x"].append(float(x[-1]))
            tips["y"].append(float(z[-1]))
            tips["color"].append(STATE_COLORS[label])
            tips["label"].append(label)
            top_tip = max(top_tip, float(z[-1]))
        self._set(self.ch_stable, lines[True])
        self._set(self.ch_unstable, lines[False])
        tw = _empty_lines()
        for sol in twirl:
            x, z = sol.profile(_TWIRL_POINTS)
            tw["xs"].append(mirror * scale * np.asarray(x))
            tw["ys"].append(scale * np.asarray(z))
            tw["color"].append(TWIRL_COLOR)
            tw["label"].append(f"({sol.sign:+d}, {sol.n})")
        self._set(self.ch_twirl, tw)
        self._set(
            self.ch_twirl_tips,
            {"x": [float(x[-1]) for x in tw["xs"]], "y": [float(z[-1]) for z in tw["ys"]]},
        )
        self._set(self.ch_tips, tips)
        base = mirror * p.theta0
        self._set(
            self.ch_rest,
            {
                "x": [0.0, scale * np.sin(base)],
                "y": [0.0, scale * np.cos(base)],
            },
        )
        # to scale: equal units on both axes; the top wall shown when it is within 4 L
        height = scale / p.eps if p.eps > 0.0 else np.inf
        shown = height <= 4.0 * scale
        top = (height if shown else 1.3 * scale) + 0.08 * scale
        bottom = -0.08 * scale
        span_z = top - bottom
        span_x = max(span_z * _FRAME_W / _FRAME_H, 2.5 * scale)
        span_z = span_x * _FRAME_H / _FRAME_W
        top = bottom + span_z
        self.ch_x.start, self.ch_x.end = -0.5 * span_x, 0.5 * span_x
        self.ch_z.start, self.ch_z.end = bottom, top
        roof = height if shown else 1.0e9
        self.ch_roof.glyph.bottom = roof
        self.ch_roof.glyph.top = roof + 100.0 * scale
        flow: dict[str, list[float]] = {"x0": [], "y0": [], "x1": [], "y1": []}
        if shown and height > top_tip:
            # the gap flow between the highest tip and the top wall: the wall's linear shear,
            # and for a pump Couette-Poiseuille, u ~ a y/g + b (y/g)(1 - y/g) with
            # a = eta v/g and b = G g/2 from the low state's loads W and Pi (theory.md §11)
            fracs = (0.25, 0.5, 0.75, 1.0)
            # (a porous bed's state, in the bed's frame: Pi = pi, W = its tip stress Q(1))
            porous = p.porous
            backwards_wall = porous and p.velocity is not None and p.velocity < 0.0
            profile = [f * (-1.0 if backwards_wall else mirror) for f in fracs]
            if p.drive != "wall" and not phys:  # no state: no gap flow to show
                profile = []
            elif p.drive != "wall":
                sol = phys[0][1]
                gap = 1.0 / p.eps - float(sol.tip_height)  # [L]
                load = sol.pi if porous else sol.distributed_load
                pressure = 0.5 * float(load) * gap
                wall = float(sol.tip_stress if porous else sol.tip_load) - pressure
                profile = [wall * f + pressure * f * (1.0 - f) for f in fracs]
            peak = max((abs(u) for u in profile), default=0.0)
            for frac, u in zip(fracs, profile):
                zf = top_tip + frac * (height - top_tip) * 0.97
                length = 0.35 * scale * (u / peak if peak > 0.0 and math.isfinite(peak) else 0.0)
                x0 = 0.5 * span_x - 0.45 * scale - 0.2 * scale
                flow["x0"].append(x0)
                flow["y0"].append(zf)
                flow["x1"].append(x0 + length)
                flow["y1"].append(zf)
        self._set(self.ch_flow, flow)
        note = f"top wall at z = H = {height:.3g} {unit}" + ("" if shown else " (above)")
        if p.eps == 0.0:
            note = "no top wall (eps = 0)"
        self.channel.title.text = f"the hair in the channel, to scale ({note})"
        self.channel.xaxis.axis_label = f"x [{unit}] (along the flow)"
        self.channel.yaxis.axis_label = f"z [{unit}] (height)"

    def _update_branch(self, snap: Snapshot, phys: list[Any]) -> None:
        d = snap.branch  # in the dimensionless variables, or the bed's in SI mode
        self.branch.xaxis.axis_label = d.x_label
        self.branch.yaxis.axis_label = d.y_label
        if self._br_window != d.x_range:  # a new abscissa (SI mode, another bed): re-framed
            self._br_window = d.x_range
            self.br_x.start, self.br_x.end = d.x_range
        self._set(self.br_curve, {"x": d.curve_x, "y": d.curve_y})
        tw = _empty_lines()
        for label, x, y in d.twirl_curves:
            tw["xs"].append(x)
            tw["ys"].append(y)
            tw["color"].append(TWIRL_COLOR)
            tw["label"].append(label)
        self._set(self.br_twirl, tw)
        self._set(self.br_folds, {"x": d.folds_x, "y": d.folds_y})
        self.br_now.visible = d.now is not None
        if d.now is not None:
            self.br_now.location = d.now if d.now > 0.0 else d.x_range[0]
        self._set(
            self.br_states,
            {
                "x": d.states_x,
                "y": d.states_y,
                "color": [STATE_COLORS[label] for label, _, _ in phys],
                "label": [label for label, _, _ in phys],
            },
        )
        self._set(self.br_twirl_states, {"x": d.twirl_x, "y": d.twirl_y})
        # the whole branch (and the twirling ones shown), fixed while only omega2 moves
        _fit(
            self.br_y,
            _bounds(d.curve_y, *(y for _, _, y in d.twirl_curves), d.states_y),
            sticky=False,
        )

    def _update_phase(self, phys: list[Any], twirl: list[Any]) -> None:
        lines = {True: _empty_lines(), False: _empty_lines()}
        ends: dict[str, list[Any]] = {"x": [], "y": [], "color": [], "marker": []}
        for label, sol, stable in phys:
            th, dth = _phase(sol, _PHASE_POINTS)
            d = lines[bool(stable)]
            d["xs"].append(th)
            d["ys"].append(dth)
            d["color"].append(STATE_COLORS[label])
            d["label"].append(label)
            for i, marker in ((0, "square"), (-1, "circle")):
                ends["x"].append(float(th[i]))
                ends["y"].append(float(dth[i]))
                ends["color"].append(STATE_COLORS[label])
                ends["marker"].append(marker)
        self._set(self.ph_stable, lines[True])
        self._set(self.ph_unstable, lines[False])
        tw = _empty_lines()
        for sol in twirl:
            th, dth = _phase(sol, _TWIRL_POINTS)
            tw["xs"].append(th)
            tw["ys"].append(dth)
            tw["color"].append(TWIRL_COLOR)
            tw["label"].append(f"({sol.sign:+d}, {sol.n})")
        self._set(self.ph_twirl, tw)
        self._set(self.ph_ends, ends)
        shown = [*lines[True]["xs"], *lines[False]["xs"], *tw["xs"]]
        _fit(self.ph_x, _bounds(*shown), sticky=True)
        shown = [*lines[True]["ys"], *lines[False]["ys"], *tw["ys"]]
        _fit(self.ph_y, _bounds(*shown), sticky=True)
