"""The view on screen as a PNG, drawn on the server: no browser, no network.

The page's figures are Bokeh's, drawn in the browser's canvas, so a plain headless
screenshot of the page shows none of them. Here the same figures are drawn with matplotlib
from what the page sends to the browser: every renderer of each Bokeh figure that is visible
(lines, multi-lines, markers, segments, quads, areas, texts, spans), its data source as it
is, its ranges, axis types, labels, title and legend. So the picture is the view's, with no
second computation of it: one implementation of what a view shows (:mod:`._figures`,
:mod:`._pillar_views`), two painters.

Above the figures: the view's link (its URL query, which reproduces it in the explorer or in
``hairbed explore --export``), and the messages the page shows above its views (the library's
warnings, a bad input's message, the ignored parameters of a link).
"""

from __future__ import annotations

import html
import io
import math
import re
import textwrap
from typing import Any

import numpy as np
from bokeh.core.property.vectorization import Field, Value
from bokeh.models import GlyphRenderer, Legend, LogScale, Range1d, Span

from .._optional import optional_import

__all__ = ["DPI", "draw_figure", "page_figures", "render_png", "view_figure"]

#: Bokeh's screen pixels to matplotlib's points (a CSS pixel is 3/4 of a point).
_PT = 0.75
#: Resolution of the PNG [dots per inch]: a CSS pixel is 1/96 inch, so 1.5 CSS pixels a dot.
DPI = 144
#: Bokeh's render levels, bottom to top, as matplotlib z-orders.
_LEVELS = {"image": 0.5, "underlay": 1.0, "glyph": 2.0, "guide": 2.5, "annotation": 3.0,
           "overlay": 4.0}  # fmt: skip
#: Bokeh's marker names as matplotlib's.
_MARKERS = {"circle": "o", "square": "s", "triangle": "^", "inverted_triangle": "v",
            "diamond": "D", "x": "x", "cross": "+", "asterisk": "*", "star": "*",
            "hex": "h", "plus": "P", "dot": "."}  # fmt: skip
#: Bokeh's legend locations as matplotlib's.
_LOCATIONS = {"top_left": "upper left", "top_right": "upper right", "top_center": "upper center",
              "bottom_left": "lower left", "bottom_right": "lower right",
              "bottom_center": "lower center", "center_left": "center left",
              "center_right": "center right", "center": "center"}  # fmt: skip


def page_figures(page: Any) -> list[list[Any]]:
    """The Bokeh figures of the view on screen, in rows as the page shows them."""
    pillar = page.pillar
    if pillar.shown_mode == "pillar" and pillar.snapshot is not None:
        rows = [[pillar.shape_fig]]
        if pillar.snapshot.params.view == "calibration":
            rows = [[pillar.shape_fig, pillar.cal_fig], [pillar.err_fig]]
        elif pillar.snapshot.params.view == "drive":  # the frame on screen and the Bode view
            rows = [[pillar.drive_fig, pillar.bode_gain_fig], [pillar.bode_phase_fig]]
            d = pillar.snapshot.params.drive
            if d is not None and d.side_view == "lissajous":  # the bed's Lissajous view
                rows = [[pillar.drive_fig, pillar.liss_fig], [pillar.liss_rate_fig]]
        return rows
    views = page.views
    p = page.snapshot.params if page.snapshot is not None else None
    if p is not None and p.view == "valve":
        return [[views.channel, views.valve_flow], [views.bistability, views.valve_ratio]]
    return [[views.channel, views.branch], [views.bistability, views.phase]]


def _spec(props: dict[str, Any], name: str, data: Any, n: int, default: Any = None) -> list[Any]:
    """A glyph's property at each of n points: a column of the source, or one value."""
    v = props.get(name, default)
    if isinstance(v, Field):
        return list(data[v.field])
    if isinstance(v, Value):
        v = v.value
    if isinstance(v, dict):  # a serialised value spec
        v = v.get("value", default)
    return [v] * n


def _color(c: Any) -> Any:
    return "none" if c is None else c


def _dashes(dash: Any, width_pt: float) -> Any:
    """A Bokeh dash pattern [px] as a matplotlib line style (its dashes scale with the width)."""
    if isinstance(dash, Value):
        dash = dash.value
    if isinstance(dash, str):
        dash = {"solid": [], "dashed": [6], "dotted": [2, 4], "dotdash": [2, 4, 6, 4],
                "dashdot": [6, 4, 2, 4]}.get(dash, [])  # fmt: skip
    dash = list(dash or [])
    if not dash:
        return "solid"
    if len(dash) % 2:
        dash = dash * 2
    scale = _PT / max(width_pt, 1e-3)
    return (0, tuple(max(d * scale, 1e-3) for d in dash))


def _col(props: dict[str, Any], name: str, data: Any) -> np.ndarray:
    """A glyph's coordinate: its column of the source, or its one value."""
    v = props.get(name)
    if isinstance(v, Field):
        return _numbers(data[v.field])
    if isinstance(v, Value):
        v = v.value
    return np.atleast_1d(np.asarray(v, dtype=np.float64))


def _line_style(props: dict[str, Any], data: Any, n: int) -> dict[str, list[Any]]:
    widths = [float(w) * _PT for w in _spec(props, "line_width", data, n, 1.0)]
    return {
        "color": [_color(c) for c in _spec(props, "line_color", data, n, "black")],
        "alpha": [float(a) for a in _spec(props, "line_alpha", data, n, 1.0)],
        "linewidth": widths,
        "linestyle": [_dashes(props.get("line_dash"), w) for w in widths],
    }


def _numbers(values: Any) -> np.ndarray:
    return np.asarray([math.nan if v is None else v for v in values], dtype=np.float64)


def _draw(ax: Any, r: Any) -> list[Any]:
    """Draw one glyph renderer on ``ax``; returns the matplotlib artists (for a legend)."""
    g, data = r.glyph, r.data_source.data
    props = g.properties_with_values(include_defaults=True)
    kind = type(g).__name__
    z = _LEVELS.get(r.level, 2.0)
    out: list[Any] = []
    if kind == "Line":
        x, y = _col(props, "x", data), _col(props, "y", data)
        s = _line_style(props, data, 1)
        out += ax.plot(x, y, color=s["color"][0], alpha=s["alpha"][0], lw=s["linewidth"][0],
                       ls=s["linestyle"][0], zorder=z)  # fmt: skip
    elif kind == "MultiLine":
        xs, ys = data[props["xs"].field], data[props["ys"].field]
        s = _line_style(props, data, len(xs))
        for k, (x, y) in enumerate(zip(xs, ys)):
            out += ax.plot(_numbers(x), _numbers(y), color=s["color"][k], alpha=s["alpha"][k],
                           lw=s["linewidth"][k], ls=s["linestyle"][k], zorder=z)  # fmt: skip
        if not len(xs):
            out += ax.plot([], [], color=s["color"][0] if s["color"] else "black",
                           lw=_PT * float(_spec(props, "line_width", data, 1, 1.0)[0]),
                           ls=_dashes(props.get("line_dash"), 1.0), zorder=z)  # fmt: skip
    elif kind == "Segment":
        x0, y0, x1, y1 = (_col(props, k, data) for k in ("x0", "y0", "x1", "y1"))
        s = _line_style(props, data, x0.size)
        for k in range(x0.size):
            out += ax.plot([x0[k], x1[k]], [y0[k], y1[k]], color=s["color"][k],
                           alpha=s["alpha"][k], lw=s["linewidth"][k], zorder=z)  # fmt: skip
    elif kind == "Scatter":
        out += _scatter(ax, props, data, z)
    elif kind == "Quad":
        n = len(data[props["left"].field]) if isinstance(props["left"], Field) else 1
        left, right, bottom, top = (_numbers(_spec(props, k, data, n)) for k in
                                    ("left", "right", "bottom", "top"))  # fmt: skip
        fill = _spec(props, "fill_color", data, n, "gray")
        line = _spec(props, "line_color", data, n, "black")
        for k in range(n):
            out.append(ax.fill_between([left[k], right[k]], bottom[k], top[k],
                                       facecolor=_color(fill[k]), edgecolor=_color(line[k]),
                                       lw=0.75, zorder=z))  # fmt: skip
    elif kind == "VArea":
        x, y1, y2 = (_col(props, k, data) for k in ("x", "y1", "y2"))
        fill = _spec(props, "fill_color", data, 1, "gray")[0]
        alpha = float(_spec(props, "fill_alpha", data, 1, 1.0)[0])
        out.append(ax.fill_between(x, y1, y2, facecolor=fill, alpha=alpha, lw=0, zorder=z))
    elif kind == "Text":
        x, y = _col(props, "x", data), _col(props, "y", data)
        n = x.size
        texts = _spec(props, "text", data, n, "")
        colors = _spec(props, "text_color", data, n, "black")
        size = str(_spec(props, "text_font_size", data, 1, "12px")[0])
        px = float(re.sub(r"[^0-9.]", "", size) or 12.0)
        dx, dy = (float(_spec(props, k, data, 1, 0.0)[0]) for k in ("x_offset", "y_offset"))
        for k in range(n):
            if texts[k] and math.isfinite(x[k]) and math.isfinite(y[k]):
                ax.annotate(str(texts[k]), (x[k], y[k]), xytext=(dx * _PT, -dy * _PT),
                            textcoords="offset points", color=colors[k], fontsize=px * _PT,
                            va="center", zorder=z, annotation_clip=True)  # fmt: skip
    return out


def _scatter(ax: Any, props: dict[str, Any], data: Any, z: float) -> list[Any]:
    x, y = _col(props, "x", data), _col(props, "y", data)
    n = x.size
    markers = _spec(props, "marker", data, n, "circle")
    angle = float(_spec(props, "angle", data, 1, 0.0)[0] or 0.0)
    sizes = [float(s) for s in _spec(props, "size", data, n, 4.0)]
    fills = _spec(props, "fill_color", data, n, "gray")
    lines = _spec(props, "line_color", data, n, "black")
    widths = [float(w) * _PT for w in _spec(props, "line_width", data, n, 1.0)]
    out = []
    for k in range(max(n, 1)):
        m = str(markers[k] if n else markers[0] if markers else "circle")
        mk = _MARKERS.get(m, "o")
        if m == "triangle" and abs(angle + math.pi / 2) < 0.1:
            mk = ">"  # pointing along +x
        fill = _color(fills[k] if n else "gray")
        face = "none" if mk in ("x", "+") else fill
        edge = _color(lines[k] if n else "black")
        if mk in ("x", "+"):
            edge = edge if edge != "none" else fill
        out += ax.plot(x[k:k + 1] if n else [], y[k:k + 1] if n else [], ls="none", marker=mk,
                       ms=(sizes[k] if n else sizes[0] if sizes else 4.0) * _PT,
                       mfc=face, mec=edge, mew=widths[k] if n else 0.75, zorder=z)  # fmt: skip
        if not n:
            break
    return out


def _span(ax: Any, s: Any) -> None:
    if s.location is None or not s.visible:
        return
    style = {"color": s.line_color or "black", "lw": float(s.line_width) * _PT,
             "ls": _dashes(s.line_dash, float(s.line_width) * _PT), "zorder": 3.0}  # fmt: skip
    loc = float(s.location)
    if not math.isfinite(loc):
        return
    if s.dimension == "height":
        lo, hi = ax.get_xlim()
        if lo <= loc <= hi:
            ax.axvline(loc, **style)
    else:
        lo, hi = ax.get_ylim()
        if lo <= loc <= hi:
            ax.axhline(loc, **style)


def _limits(rng: Any) -> tuple[float, float] | None:
    if isinstance(rng, Range1d) and rng.start is not None and rng.end is not None:
        return float(rng.start), float(rng.end)
    return None


def _size(f: Any) -> tuple[float, float, bool]:
    """(width, height) [CSS px] of a figure's frame, and whether the frame is fixed."""
    if f.frame_width and f.frame_height:
        return float(f.frame_width), float(f.frame_height), True
    return float(f.width or 600) - 70.0, float(f.height or 600) - 80.0, False


def draw_figure(ax: Any, f: Any) -> None:
    """One Bokeh figure on a matplotlib axes: its renderers, spans, ranges, labels, legend."""
    if isinstance(f.x_scale, LogScale):
        ax.set_xscale("log")
    if isinstance(f.y_scale, LogScale):
        ax.set_yscale("log")
    handles: dict[int, list[Any]] = {}
    for r in f.renderers:
        if isinstance(r, GlyphRenderer) and r.visible:
            with np.errstate(all="ignore"):
                handles[id(r)] = _draw(ax, r)
    for axis, lim in ((ax.set_xlim, _limits(f.x_range)), (ax.set_ylim, _limits(f.y_range))):
        if lim is not None:
            axis(*lim)
    for obj in (*f.center, *f.renderers):
        if isinstance(obj, Span):
            _span(ax, obj)
    ax.set_title(f.title.text if f.title is not None else "", fontsize=13 * _PT, loc="left")
    ax.set_xlabel(f.xaxis[0].axis_label or "", fontsize=12 * _PT)
    ax.set_ylabel(f.yaxis[0].axis_label or "", fontsize=12 * _PT)
    ax.tick_params(labelsize=11 * _PT)
    ax.grid(True, alpha=0.3 if f.grid[0].grid_line_alpha < 1 else 0.5, lw=0.5)
    for legend in (o for o in f.center if isinstance(o, Legend)):
        items = []
        for item in legend.items:
            label = item.label.get("value") if isinstance(item.label, dict) else item.label
            if isinstance(label, Value):
                label = label.value
            arts = [a for r in item.renderers for a in handles.get(id(r), [])[:1]]
            if arts and label:
                items.append((arts[0], str(label)))
        if items:
            ax.legend([a for a, _ in items], [t for _, t in items],
                      loc=_LOCATIONS.get(str(legend.location), "best"), fontsize=11 * _PT,
                      framealpha=0.8)  # fmt: skip


def _notes(page: Any) -> list[str]:
    """The messages the page shows above its views, as text."""
    out = []
    for pane in (page.alert, page.notes):
        if getattr(pane, "visible", True) and pane.object:
            text = re.sub(r"</(p|li)>", "\n", str(pane.object))
            text = html.unescape(re.sub(r"<[^>]+>", "", text))
            out += [line.strip() for line in text.splitlines() if line.strip()]
    return out


def view_figure(page: Any, dpi: int = DPI) -> Any:
    """The view on screen of an :class:`~._page.ExplorerPage` as a matplotlib figure.

    Every figure of the view (:func:`page_figures`) drawn by matplotlib from the data the page
    sends to the browser, each axes at its Bokeh frame's size and place in the page's rows;
    above them the view's link and the messages the page shows. Needs matplotlib (the
    ``plot`` extra).
    """
    mfigure = optional_import("matplotlib.figure", "a PNG of the explorer's view")
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    rows = page_figures(page)
    sizes = [[_size(f) for f in row] for row in rows]
    width = max(sum(w + 110.0 for w, _, _ in row) for row in sizes)
    heights = [max(h for _, h, _ in row) + 95.0 for row in sizes]
    notes = [f"link: {page.history.search or '?'}", *_notes(page)]
    lines = [
        seg
        for n in notes
        for seg in textwrap.wrap(n, int((width - 20.0) / 7.5), break_on_hyphens=False) or [""]
    ]
    head = 34.0 + 15.0 * len(lines)
    fig = mfigure.Figure(figsize=(width / 96.0, (head + sum(heights)) / 96.0), dpi=dpi)
    FigureCanvasAgg(fig)
    total = head + sum(heights)
    fig.text(0.01, 1.0 - 8.0 / total, "hairbed explorer", fontsize=14, weight="bold", va="top")
    fig.text(0.01, 1.0 - 30.0 / total, "\n".join(lines), fontsize=9, va="top",
             family="monospace", linespacing=1.25)  # fmt: skip
    top = head
    for row, hs, row_h in zip(rows, sizes, heights):
        left = 0.0
        for f, (w, h, _) in zip(row, hs):
            # the frame at (left + 80 px, top + 40 px) of its cell, as Bokeh lays it out
            ax = fig.add_axes(
                (
                    (left + 80.0) / width,
                    1.0 - (top + 40.0 + h) / total,
                    w / width,
                    h / total,
                )
            )
            draw_figure(ax, f)
            left += w + 110.0
        top += row_h
    return fig


def render_png(page: Any, dpi: int = DPI) -> bytes:
    """The view on screen of an :class:`~._page.ExplorerPage` as PNG bytes
    (:func:`view_figure`)."""
    buf = io.BytesIO()
    view_figure(page, dpi).savefig(buf, format="png", dpi=dpi, facecolor="white")
    return buf.getvalue()
