"""The explorer's page: Panel widgets and layout around :class:`~._figures.Views`.

The inputs are text fields (exact entry) with a slider each; a slider move writes its value
into the text field, and every change of a text field runs :meth:`ExplorerPage.refresh`: the
inputs are validated by the library (:func:`._model.validate`), every state is solved and
classified (:func:`._model.compute`) and all views, the table, the URL and the downloads show the
new snapshot together. Bad input shows the library's message for every bad parameter (above
the views, with the library's warnings) and leaves the last good snapshot on screen; after a
bad link (loaded, or reached by Back or Forward) the fields show that snapshot's inputs again,
while a bad typed value stays in its field to be corrected.
"""

from __future__ import annotations

import html
import importlib.util
import io
import math
import sys
import time
from typing import Any

import panel as pn
from bokeh.models import CustomJSTickFormatter

from hairbed._variables import LOADED, POROUS, SI, SOLUTION

from ._figures import STATE_COLORS, Views
from ._history import BrowserHistory
from ._model import (
    BED_KEYS,
    DEFAULTS,
    DRAG_MODELS,
    DRIVES,
    INPUT_KEYS,
    LOAD_KEYS,
    LOADED_FIELDS,
    MODELS,
    POROUS_FIELDS,
    PRESETS,
    PUMP_INPUT,
    PUMP_KEYS,
    SI_FIELDS,
    SOLUTION_FIELDS,
    STABILITY_SEGMENTS,
    VIEWS,
    InputError,
    Params,
    Snapshot,
    compute,
    inputs_from_query,
    load_per_unit,
    porous_bed_info,
    query_from_inputs,
    snapshot_csv,
    snapshot_json,
    snapshot_shape_csv,
    validate,
)
from ._pillar import PILLAR_CHOICES, is_pillar
from ._pillar_views import PillarPanel, refresh_pillar

__all__ = ["ExplorerPage", "LOG_OMEGA2_RANGE"]

#: Range of the omega2 slider, in log10(omega2). Typed values may lie outside.
LOG_OMEGA2_RANGE = (-3.0, 3.0)
#: Range of the load slider of a pump drive, in log10(abs(pi)) or log10(abs(q)); the sign is
#: the typed value's.
LOG_LOAD_RANGE = (-3.0, 3.0)
_THETA0_MAX = 1.57

#: Rows of the table: Solution field -> description [unit].
FIELD_LABELS: dict[str, str] = {k: SOLUTION[k].heading for k in SOLUTION_FIELDS}
SI_LABELS: dict[str, str] = {k: SI[k].heading for k in SI_FIELDS}
LOADED_LABELS: dict[str, str] = {
    k: (SOLUTION[k].heading if k in SOLUTION else LOADED[k].heading) for k in LOADED_FIELDS
}
#: Labels of the drive selector and of the view selector.
DRIVE_OPTIONS = {"wall speed": "wall", "pressure gradient": "pressure", "flow rate": "flow"}
VIEW_OPTIONS = {"branch diagram": "branch", "valve": "valve"}
TWIRL_LABEL = "show twirling states (every branch: solve_all)"
TWIRL_COLUMNS = ("sign", "n", "xi", "omega_eps", "tip_height", "tip_deflection", "tip_angle")

_CSS = """
:host { font-size: 13px; }
table.hb { border-collapse: collapse; font-family: ui-monospace, monospace; font-size: 12px; }
table.hb th, table.hb td { padding: 1px 8px; border-bottom: 1px solid #e5e5e5; }
table.hb th { text-align: left; background: #f4f4f4; }
table.hb td.num { text-align: right; }
"""
#: The messages above the views (bad input, the library's warnings): they wrap, never widen
#: the page.
_NOTE_CSS = """
:host { width: 100%; }
div.hb-notes { box-sizing: border-box; max-width: 100%; margin: 2px 0; padding: 6px 10px;
  border-radius: 4px; font-size: 13px; white-space: normal; overflow-wrap: anywhere; }
div.hb-notes p, div.hb-notes li { margin: 2px 0; }
div.hb-errors { color: #721c24; background: #f8d7da; border: 1px solid #f5c6cb; }
div.hb-warnings { color: #6b3a00; background: #fff3cd; border: 1px solid #ffe08a; }
ul.hb-warn { margin: 0; padding-left: 18px; }
"""


def _fmt(value: Any) -> str:
    """A table cell: 12 significant digits for floats."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, (int, str)):
        return html.escape(str(value))
    value = float(value)
    if math.isnan(value):
        return "nan"
    return f"{value:.12g}"


def _short(value: float) -> str:
    """A value written into a text field from a slider: 6 significant digits."""
    return f"{value:.6g}"


#: A slider's shown value: the state's own, to 6 significant digits (0.897, not 0.90).
_SHOWN = "return String(Number(Number(tick).toPrecision(6)))"
#: The same for the omega^2 slider, which runs over log10(omega^2).
_SHOWN_LOG = "return String(Number((10 ** tick).toPrecision(6)))"


def _widget(cls: Any, label: str, **kw: Any) -> Any:
    """A widget with a visible label (``label`` since Panel 1.9, ``name`` before)."""
    kw["label" if "label" in cls.param else "name"] = label
    return cls(**kw)


#: Rows of a porous bed's table: PorousState field -> description [unit].
POROUS_LABELS: dict[str, str] = {k: POROUS[k].heading for k in POROUS_FIELDS}


def porous_html(snap: Snapshot) -> str:
    """A porous bed's model above its table: the drag model, kappa = k/L^2 and the Brinkman
    length sqrt(kappa) L (theory.md §13); empty for a dense bed."""
    p = snap.params
    if not p.porous:
        return ""
    info = porous_bed_info(p.bed)
    return (
        f'<p class="hb-porous" data-kappa="{info["kappa"]!r}" '
        f'data-brinkman-length="{info["brinkman_length"]!r}">porous bed '
        f"(<code>HairBed(..., model=&quot;porous&quot;, drag=&quot;{html.escape(info['drag'])}"
        f"&quot;)</code>, theory.md §13): permeability kappa = k/L<sup>2</sup> = "
        f"{_fmt(info['kappa'])}, Brinkman length sqrt(kappa) L = "
        f"{_fmt(info['brinkman_length'])} m, drag ratio gamma = {_fmt(info['drag_ratio'])}; "
        "stability under a slow change of the gap (<code>solve_porous_all</code>)</p>"
    )


def unsupported_message(snap: Snapshot) -> str:
    """What the alert says of the views this bed does not support (the library's
    NotImplementedError messages; empty: none)."""
    return "; ".join(snap.unsupported)


def _unsupported_html(snap: Snapshot) -> str:
    if not snap.unsupported:
        return ""
    items = "".join(f"<p>{html.escape(m)}</p>" for m in snap.unsupported)
    return f'<div class="hb-notes hb-warnings hb-unsupported">{items}</div>'


def _table_html(snap: Snapshot) -> str:
    """Every Solution field of every physical state (one column each), and the SI values;
    a pump drive's states by the fields of :class:`hairbed.LoadedState`; no state: the
    library's message."""
    states = snap.states
    if not states:
        return (
            '<table class="hb hb-states" data-count="0"><thead><tr><th>no state</th></tr>'
            "</thead></table>"
            f'<p class="hb-nostate">{html.escape(snap.message or "no state")}</p>'
        )
    loaded = snap.params.drive != "wall"
    porous = snap.params.porous
    head = "".join(
        f'<th style="color:{STATE_COLORS[s.label]}">{html.escape(s.label)}</th>' for s in states
    )
    rows = []

    def row(key: str, label: str, values: list[Any]) -> None:
        cells = "".join(
            f'<td class="num" data-state="{s.label}" data-field="{key}">{_fmt(v)}</td>'
            for s, v in zip(states, values)
        )
        rows.append(f'<tr data-row="{key}"><th>{html.escape(label)}</th>{cells}</tr>')

    if porous:
        row("stable", "stable (solve_porous_all: dG/dh1 < 0)", [s.stable for s in states])
        for key in POROUS_FIELDS:
            row(key, POROUS_LABELS[key], [getattr(s.solution, key) for s in states])
        row("message", "message", [s.solution.message for s in states])
    elif loaded:
        row("stable", "stable (solve_loaded_all: dG/dh1 < 0)", [s.stable for s in states])
        for key in LOADED_FIELDS:
            row(key, LOADED_LABELS[key], [getattr(s.solution, key) for s in states])
        row("message", "message", [s.solution.message for s in states])
    else:
        stability = f"stable (linear_stability, N={STABILITY_SEGMENTS})"
        row("stable", stability, [s.stable for s in states])
        growth = "largest growth rate [1/relaxation time]"
        row("growth_rate", growth, [s.growth_rate for s in states])
        for key in SOLUTION_FIELDS:
            row(key, FIELD_LABELS.get(key, key), [getattr(s.solution, key) for s in states])
    if snap.params.si:
        for key in SI_FIELDS:
            row(f"si_{key}", SI_LABELS[key], [getattr(s.si, key) for s in states])
    out = [
        f'<table class="hb hb-states" data-count="{len(states)}">'
        f"<thead><tr><th>{len(states)} physical state{'s' if len(states) > 1 else ''}</th>"
        f"{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"
    ]
    return "".join(out)


#: The valve's readout at the current drop: field -> label.
VALVE_LABELS = {
    "drop": "at the drop",
    "forward": "flow forward (+dp)",
    "backward": "flow backward (-dp), abs",
    "forward_ratio": "R/R0 forward",
    "backward_ratio": "R/R0 backward",
    "diodicity": "diodicity Di",
}


def _valve_html(snap: Snapshot) -> str:
    """The valve at the current drop (the valve view only): a table, or why there is none."""
    v = snap.valve
    if v is None:
        return ""
    if not v.now:
        return f'<p class="hb-valve-message">{html.escape(v.message)}</p>'
    unit = v.x_label.split("[")[-1].rstrip("]") if "[" in v.x_label else ""
    flow_unit = v.flow_label.split("[")[-1].rstrip("]") if "[" in v.flow_label else ""
    units = {"drop": unit, "forward": flow_unit, "backward": flow_unit}
    rows = "".join(
        f"<tr><th>{html.escape(label)}{f' [{units[k]}]' if k in units else ' [-]'}</th>"
        f'<td class="num" data-field="{k}">{_fmt(v.now[k])}</td></tr>'
        for k, label in VALVE_LABELS.items()
    )
    status = "" if v.success else f'<p class="hb-valve-message">{html.escape(v.message)}</p>'
    return (
        f'<table class="hb hb-valve" data-success="{int(v.success)}"><thead><tr>'
        f"<th>the valve (walls at rest)</th><th></th></tr></thead><tbody>{rows}</tbody>"
        f"</table>{status}"
    )


def _warnings_html(warnings: list[str]) -> str:
    """The library's warnings of the view, above the views (empty: nothing)."""
    if not warnings:
        return ""
    items = "".join(f"<li>{html.escape(w)}</li>" for w in warnings)
    return f'<div class="hb-notes hb-warnings"><ul class="hb-warn">{items}</ul></div>'


def _errors_html(messages: tuple[str, ...]) -> str:
    """Every bad input's message, one paragraph each (empty: nothing)."""
    if not messages:
        return ""
    items = "".join(f"<p>{html.escape(m)}</p>" for m in messages)
    return f'<div class="hb-notes hb-errors">{items}</div>'


def ignored_message(names: tuple[str, ...]) -> str:
    """What the alert says of unknown URL parameters (ignored; the known ones applied)."""
    s = "s" if len(names) > 1 else ""
    return (
        f"ignored the unknown URL parameter{s} {', '.join(repr(k) for k in names)} "
        f"(the others are applied); known: {', '.join(INPUT_KEYS)}"
    )


def _ignored_html(names: tuple[str, ...]) -> str:
    """The unknown URL parameters of the link just applied (empty: nothing)."""
    if not names:
        return ""
    text = html.escape(ignored_message(names))
    return f'<div class="hb-notes hb-warnings hb-ignored"><p>{text}</p></div>'


def _twirl_html(snap: Snapshot) -> str:
    if not snap.params.twirl:
        return ""
    if not snap.twirling:
        return '<p class="hb-twirl" data-count="0">no twirling states at this forcing</p>'
    head = "".join(f"<th>{html.escape(c)}</th>" for c in ("branch", *TWIRL_COLUMNS))
    body = []
    for s in snap.twirling:
        cells = "".join(
            f'<td class="num" data-field="{c}">{_fmt(getattr(s.solution, c))}</td>'
            for c in TWIRL_COLUMNS
        )
        body.append(f'<tr data-state="{html.escape(s.label)}"><th>{s.label}</th>{cells}</tr>')
    return (
        f'<table class="hb hb-twirl" data-count="{len(snap.twirling)}"><thead><tr>{head}</tr>'
        f"</thead><tbody>{''.join(body)}</tbody></table>"
    )


class ExplorerPage:
    """One session's page. ``layout`` is the Panel object to serve or show in Jupyter.

    Parameters
    ----------
    query : str, optional
        A URL query string ('?omega2=1.2&eps=0.9'): the inputs to start from.
    served : bool, optional
        Keep the browser's address bar and history in step with the view
        (:class:`~._history.BrowserHistory`): by default when the page is served (a
        ``hairbed explore`` session), not in a Jupyter notebook, whose URL is the notebook's.
    """

    def __init__(self, query: str = "", *, served: bool | None = None) -> None:
        self._syncing = False
        self._url_live = False  # the first (default) view does not touch the URL
        self._setting_url = False
        #: The query string of the browser's address bar (set both ways).
        self.history = BrowserHistory(
            search="?" + query.lstrip("?") if query.strip("?") else "",
            visible=False,
            css_classes=["hb-history"],
        )
        if served is None:
            doc = pn.state.curdoc
            served = doc is not None and doc.session_context is not None
        self._served = served
        if served:
            # Panel makes the session's Location from the request on first use and, doing so,
            # empties the document's stylesheet cache: made after the panes, it would have the
            # first update re-create every pane's stylesheets (a re-walk of the whole document,
            # ~250 ms, long enough to lose a slider drag under way). Made now, before the page's
            # models exist.
            _ = pn.state.location
        self.snapshot: Snapshot | None = None
        #: Server time of the last update [ms]: solve, stability, views, total.
        self.timings: dict[str, float] = {}
        self.error = ""
        #: The messages of the last bad input (one per bad parameter); () after a good one.
        self.errors: tuple[str, ...] = ()
        #: The unknown parameters of the link being applied (ignored, and said in the alert).
        self.ignored: tuple[str, ...] = ()
        self.views = Views()
        self._build_widgets()
        self._build_layout()
        # the first view: the defaults, so that a bad URL still leaves a good state on screen
        self.refresh()
        self._url_live = True
        if query.strip("?"):
            self._apply_query(query)
        elif self.snapshot is not None:
            self._set_url(query_from_inputs(self.snapshot.params))
        self.history.param.watch(self._on_history, "search")

    # -- widgets ------------------------------------------------------------------------------

    def _build_widgets(self) -> None:
        lo, hi = LOG_OMEGA2_RANGE
        w0 = float(DEFAULTS["omega2"])
        self.omega2_slider = _widget(
            pn.widgets.FloatSlider,
            "forcing omega^2 (log scale)",
            start=lo,
            end=hi,
            step=0.005,
            value=math.log10(w0),
            format=CustomJSTickFormatter(code=_SHOWN_LOG),
            css_classes=["hb-omega2-slider"],
            sizing_mode="stretch_width",
        )
        self.eps_slider = _widget(
            pn.widgets.FloatSlider,
            "confinement eps = L/H",
            start=0.0,
            end=0.999,
            step=0.001,
            value=float(DEFAULTS["eps"]),
            format=CustomJSTickFormatter(code=_SHOWN),
            css_classes=["hb-eps-slider"],
            sizing_mode="stretch_width",
        )
        self.theta0_slider = _widget(
            pn.widgets.FloatSlider,
            "base angle theta0 [rad]",
            start=-_THETA0_MAX,
            end=_THETA0_MAX,
            step=0.005,
            value=float(DEFAULTS["theta0"]),
            format=CustomJSTickFormatter(code=_SHOWN),
            css_classes=["hb-theta0-slider"],
            sizing_mode="stretch_width",
        )
        self.text = {
            k: _widget(
                pn.widgets.TextInput,
                label,
                value=DEFAULTS[k],
                css_classes=[f"hb-{k}"],
                sizing_mode="stretch_width",
            )
            for k, label in (
                ("omega2", "omega^2 [-], >= 0 (exact)"),
                ("eps", "eps [-], in [0, 1) (exact)"),
                ("theta0", "theta0 [rad], in (-pi/2, pi/2) (exact)"),
            )
        }
        self.load_slider = _widget(
            pn.widgets.FloatSlider,
            "pump load abs(pi) or abs(q) (log scale)",
            start=LOG_LOAD_RANGE[0],
            end=LOG_LOAD_RANGE[1],
            step=0.005,
            value=0.0,
            format=CustomJSTickFormatter(code=_SHOWN_LOG),
            css_classes=["hb-load-slider"],
            sizing_mode="stretch_width",
        )
        for k, label in (
            ("pi", "pi [-], pressure gradient A G L^3/(E I) (exact, signed)"),
            ("q", "q [-], flow rate 6 A eta Q' L^2/(E I H^2) (exact, signed)"),
        ):
            self.text[k] = _widget(
                pn.widgets.TextInput,
                label,
                value=DEFAULTS[k],
                css_classes=[f"hb-{k}"],
                sizing_mode="stretch_width",
            )
        for k, (label, unit) in {**BED_KEYS, **PUMP_KEYS}.items():
            self.text[k] = _widget(
                pn.widgets.TextInput,
                f"{label} [{unit}]",
                value=DEFAULTS[k],
                css_classes=[f"hb-{k}"],
                sizing_mode="stretch_width",
            )
        self.si = pn.widgets.Switch(value=DEFAULTS["si"] == "1", css_classes=["hb-si"])
        # a group of one: its label is a <label> around the box (clicking the text ticks it);
        # a Checkbox's label is a <div> beside it
        self.twirl = pn.widgets.CheckBoxGroup(
            options=[TWIRL_LABEL],
            value=[TWIRL_LABEL] if DEFAULTS["twirl"] == "1" else [],
            css_classes=["hb-twirl-toggle"],
        )
        self.y_choice = pn.widgets.RadioButtonGroup(
            options={"tip deflection x1": "x1", "xi": "xi"},
            value=DEFAULTS["y"],
            css_classes=["hb-y"],
        )
        self.drive = pn.widgets.RadioButtonGroup(
            options=DRIVE_OPTIONS, value=DEFAULTS["drive"], css_classes=["hb-drive"]
        )
        self.view_choice = pn.widgets.RadioButtonGroup(
            options=VIEW_OPTIONS, value=DEFAULTS["view"], css_classes=["hb-view"]
        )
        self.x_choice = pn.widgets.RadioButtonGroup(
            options={"wall speed": "speed", "wall shear stress": "stress"},
            value=DEFAULTS["x"],
            css_classes=["hb-x"],
        )
        #: SI mode's bed model (theory.md §13) and, for a porous bed, its drag model.
        self.model = pn.widgets.RadioButtonGroup(
            options={m: m for m in MODELS}, value=DEFAULTS["model"], css_classes=["hb-model"]
        )
        self.drag = pn.widgets.RadioButtonGroup(
            options={d: d for d in DRAG_MODELS},
            value=DEFAULTS["drag"],
            css_classes=["hb-drag"],
            visible=DEFAULTS["model"] == "porous",
        )
        #: A porous bed's kappa and Brinkman length (empty for a dense bed).
        self.porous_info = pn.pane.HTML("", css_classes=["hb-porous-info"])
        #: Every bad input's message (the library's), above the views.
        self.alert = pn.pane.HTML(
            "",
            visible=False,
            css_classes=["hb-error"],
            stylesheets=[_NOTE_CSS],
            sizing_mode="stretch_width",
        )
        #: The library's warnings of the view on screen (model validity, units), above the
        #: views.
        self.notes = pn.pane.HTML(
            "", css_classes=["hb-notes-pane"], stylesheets=[_NOTE_CSS], sizing_mode="stretch_width"
        )
        self.presets = {
            name: _widget(
                pn.widgets.Button,
                name,
                css_classes=[f"hb-preset-{name.split()[0]}"],
                margin=(2, 3),
            )
            for name in PRESETS
        }
        for name, button in self.presets.items():
            button.on_click(lambda _event, name=name: self.apply_preset(name))
        self.status = pn.pane.HTML("", css_classes=["hb-status"])
        self.link = pn.pane.HTML("", css_classes=["hb-link"])
        self.table = pn.pane.HTML("", css_classes=["hb-table"], stylesheets=[_CSS])
        self.twirl_table = pn.pane.HTML("", css_classes=["hb-twirl-table"], stylesheets=[_CSS])
        self.valve_table = pn.pane.HTML("", css_classes=["hb-valve-table"], stylesheets=[_CSS])
        self.download_json = pn.widgets.FileDownload(
            callback=self._json_file,
            filename="hairbed-state.json",
            label="download JSON",
            css_classes=["hb-download-json"],
        )
        self.download_csv = pn.widgets.FileDownload(
            callback=self._csv_file,
            filename="hairbed-state.csv",
            label="download CSV",
            css_classes=["hb-download-csv"],
        )
        self.download_shape = pn.widgets.FileDownload(
            callback=self._shape_file,
            filename="hairbed-shape.csv",
            label="shape CSV",
            css_classes=["hb-download-shape"],
        )
        #: The view on screen as a PNG, drawn on the server (:mod:`._export`): no browser.
        png = importlib.util.find_spec("matplotlib") is not None
        self.download_png = pn.widgets.FileDownload(
            callback=self._png_file,
            filename="hairbed-view.png",
            label="download PNG" if png else "PNG: needs matplotlib (pip install 'hairbed[plot]')",
            disabled=not png,
            css_classes=["hb-download-png"],
        )
        self.omega2_slider.param.watch(self._from_omega2_slider, "value")
        self.eps_slider.param.watch(self._from_slider("eps"), "value")
        self.theta0_slider.param.watch(self._from_slider("theta0"), "value")
        self.load_slider.param.watch(self._from_load_slider, "value")
        for w in self.text.values():
            w.param.watch(self._on_input, "value")
        for w in (
            self.twirl, self.y_choice, self.x_choice, self.si, self.drive, self.view_choice,
            self.model, self.drag,
        ):  # fmt: skip
            w.param.watch(self._on_input, "value")
        #: The pillar mode (:mod:`._pillar_views`), registered in :meth:`_build_layout`.
        self.pillar = PillarPanel()

    def _build_layout(self) -> None:
        bed = pn.Column(
            pn.pane.HTML("bed model (theory.md §13):", margin=(5, 10, 0, 10)),
            self.model,
            self.drag,
            *(self.text[k] for k in BED_KEYS),
            *(self.text[k] for k in PUMP_KEYS),
            pn.pane.HTML(
                "<small>Give either the spacing or the packing fraction (leave the other "
                "empty). In SI mode the omega^2 slider moves the wall speed and the theta0 "
                "slider the base angle; omega^2, eps = L/H and theta0 (mirrored for v &lt; 0) "
                "follow from the bed.</small>"
            ),
            pn.pane.HTML("branch diagram abscissa:", margin=(5, 10, 0, 10)),
            self.x_choice,
            visible=self.si.value,
        )
        self._bed_column = bed
        controls = pn.Column(
            pn.pane.HTML("<b>Start from</b>", margin=(5, 10, 0, 10)),
            pn.FlexBox(*self.presets.values(), css_classes=["hb-presets"]),
            pn.pane.HTML("<b>Flow and geometry</b>"),
            self.omega2_slider,
            self.text["omega2"],
            self.eps_slider,
            self.text["eps"],
            self.theta0_slider,
            self.text["theta0"],
            pn.pane.HTML("<b>Drive</b> (theory.md §11)", margin=(5, 10, 0, 10)),
            self.drive,
            self.load_slider,
            self.text["pi"],
            self.text["q"],
            pn.pane.HTML("beside the channel:", margin=(5, 10, 0, 10)),
            self.view_choice,
            pn.Row(pn.pane.HTML("SI units (a real bed)", margin=(8, 5)), self.si),
            bed,
            self.twirl,
            pn.pane.HTML("branch diagram ordinate:", margin=(5, 10, 0, 10)),
            self.y_choice,
            pn.Row(self.download_json, self.download_csv, self.download_shape),
            self.download_png,
            self.link,
            self.status,
            width=330,
        )
        views = self.views
        valve = DEFAULTS["view"] == "valve"
        # each figure in a column of its own, whose visibility switches the view (a Bokeh
        # pane's own ``visible`` follows its figure's and does not come back once cleared)
        self._branch_pane = pn.Column(
            pn.pane.Bokeh(views.branch), css_classes=["hb-branch"], visible=not valve
        )
        self._phase_pane = pn.Column(
            pn.pane.Bokeh(views.phase), css_classes=["hb-phase"], visible=not valve
        )
        self._valve_flow_pane = pn.Column(
            pn.pane.Bokeh(views.valve_flow), css_classes=["hb-valve-flow"], visible=valve
        )
        self._valve_ratio_pane = pn.Column(
            pn.pane.Bokeh(views.valve_ratio), css_classes=["hb-valve-ratio"], visible=valve
        )
        self.layout = pn.Column(
            pn.pane.HTML(
                "<h2 style='margin:4px 0'>hairbed explorer</h2>"
                "<div>Exact states of a hair bent by channel flow "
                "(arXiv:2203.04169; <code>hairbed.solve</code>, <code>solve_all</code>, "
                "<code>branches</code>, <code>stability</code>). Solid: stable; long dashes: "
                "unstable; purple dots with diamonds: twirling (unphysical branches).</div>",
                sizing_mode="stretch_width",
            ),
            self.alert,
            self.notes,
            pn.Row(
                controls,
                pn.Column(
                    pn.Row(
                        pn.pane.Bokeh(views.channel, css_classes=["hb-channel"]),
                        self._branch_pane,
                        self._valve_flow_pane,
                    ),
                    pn.Row(
                        pn.pane.Bokeh(views.bistability, css_classes=["hb-bistability"]),
                        self._phase_pane,
                        self._valve_ratio_pane,
                    ),
                    self.valve_table,
                    self.porous_info,
                    self.table,
                    self.twirl_table,
                ),
            ),
            *([self.history] if self._served else []),
        )
        self.pillar.place(self, controls)

    # -- events -----------------------------------------------------------------------------

    def _from_omega2_slider(self, event: Any) -> None:
        if self._syncing:
            return
        w = float(_short(10.0 ** float(event.new)))
        good = self.snapshot.params if self.snapshot is not None else None
        if self.si.value and good is not None and good.bed is not None:
            v = good.velocity if good.velocity is not None else 1.0
            speed = math.copysign(w * good.bed.velocity_scale, v)
            self.text["velocity"].value = _short(speed)
        else:
            self.text["omega2"].value = _short(w)

    def _from_load_slider(self, event: Any) -> None:
        """The load slider: abs(pi) or abs(q) on a log scale, the sign of the typed value; in
        SI mode it moves the pump's pressure gradient or flow rate."""
        if self._syncing:
            return
        good = self.snapshot.params if self.snapshot is not None else None
        drive = str(self.drive.value)
        if drive == "wall" or good is None or good.drive != drive:
            return
        load = float(_short(10.0 ** float(event.new)))
        sign = -1.0 if (good.load or 0.0) < 0.0 else 1.0
        if self.si.value and good.bed is not None:
            _, per_unit = load_per_unit(good.bed, drive)  # the bed's load per SI unit
            self.text[PUMP_INPUT[drive]].value = _short(sign * load / per_unit)
        else:
            self.text[LOAD_KEYS[drive]].value = _short(sign * load)

    def _from_slider(self, key: str) -> Any:
        def callback(event: Any) -> None:
            if not self._syncing:
                # in SI mode theta0 follows from the bed: the slider moves its base angle
                field = "base_angle" if key == "theta0" and self.si.value else key
                self.text[field].value = _short(float(event.new))

        return callback

    def apply_preset(self, name: str) -> None:
        """Show one of :data:`~._model.PRESETS` (the inputs it does not name at their
        defaults), as a link to it would."""
        from urllib.parse import urlencode

        self._apply_query("?" + urlencode(PRESETS[name]), restore=True)

    def _on_input(self, event: Any) -> None:
        if event.obj is self.si:
            self._bed_column.visible = bool(event.new)
        if not self._syncing:
            self.refresh()

    def _raw(self) -> dict[str, str]:
        raw = {k: w.value for k, w in self.text.items()}
        raw["drive"] = str(self.drive.value)
        raw["view"] = str(self.view_choice.value)
        raw["si"] = "1" if self.si.value else "0"
        raw["twirl"] = "1" if self.twirl.value else "0"
        raw["y"] = str(self.y_choice.value)
        raw["x"] = str(self.x_choice.value)
        raw["model"] = str(self.model.value)
        raw["drag"] = str(self.drag.value)
        raw.update(self.pillar.choices())
        return raw

    def _on_history(self, event: Any) -> None:
        """Back or Forward in the browser: show the view of the URL it went to."""
        if not self._setting_url:
            self._apply_query(event.new, restore=True)

    def _apply_query(self, query: str, *, restore: bool = False) -> None:
        """Inputs from a URL query: put them into the fields and refresh. Unknown names are
        ignored and named in the alert (the known ones apply); bad values show the library's
        message and the last good state stays on screen.

        With ``restore`` (a URL of the browser's history), the inputs the query does not name
        take their defaults, as in a page loaded from that URL."""
        args = inputs_from_query(query)
        # unknown names are ignored (and named above the views): the known ones still apply
        self.ignored = tuple(sorted(set(args) - set(INPUT_KEYS)))
        args = {k: v for k, v in args.items() if k in INPUT_KEYS}
        if restore:
            args = {**{k: DEFAULTS[k] for k in INPUT_KEYS}, **args}
        self._syncing = True
        try:
            for k, v in args.items():
                if k in self.text:
                    self.text[k].value = v
            if "si" in args:
                self.si.value = args["si"].strip().lower() in ("1", "true", "on", "yes")
                self._bed_column.visible = self.si.value
            if "twirl" in args:
                on = args["twirl"].strip().lower() in ("1", "true", "on", "yes")
                self.twirl.value = [TWIRL_LABEL] if on else []
            if "y" in args and args["y"] in ("x1", "xi"):
                self.y_choice.value = args["y"]
            if "x" in args and args["x"] in ("speed", "stress"):
                self.x_choice.value = args["x"]
            if "drive" in args and args["drive"] in DRIVES:
                self.drive.value = args["drive"]
            if "view" in args and args["view"] in VIEWS:
                self.view_choice.value = args["view"]
            if "model" in args and args["model"] in MODELS:
                self.model.value = args["model"]
            if "drag" in args and args["drag"] in DRAG_MODELS:
                self.drag.value = args["drag"]
            self.pillar.apply_choices(args)
        finally:
            self._syncing = False
        # the flags as given (not as the widgets could hold them): validate says what is wrong
        raw = self._raw()
        given = ("si", "twirl", "y", "x", "drive", "view", "model", "drag")
        raw.update({k: v for k, v in args.items() if k in given})
        raw.update({k: v for k, v in args.items() if k in PILLAR_CHOICES})
        try:
            if not self.refresh(raw):
                self._restore_fields()  # a bad link: the fields show the view on screen again
        finally:
            self.ignored = ()  # said once, for this link; the next change clears the alert

    # -- the update -----------------------------------------------------------------------

    def refresh(self, raw: dict[str, str] | None = None) -> bool:
        """Validate the inputs, solve every state and update every view; False on bad input.

        On bad input the library's message is shown and the last good state stays.
        """
        if raw is None:
            raw = self._raw()
        if is_pillar(raw):  # the pillar mode (:func:`._pillar_views.refresh_pillar`)
            return refresh_pillar(self, raw, _warnings_html)
        start = time.perf_counter()
        try:
            params = validate(raw)
            snap = compute(params)
        except Exception as exc:
            return self._failed(exc, (ValueError,))
        solved = time.perf_counter()
        with pn.io.hold():
            self.views.update(snap)
            self.table.object = _table_html(snap)
            self.valve_table.object = _valve_html(snap)
            self.twirl_table.object = _twirl_html(snap)
            self.porous_info.object = porous_html(snap)
            self._sync_widgets(params)
            self.pillar.show_mode(self, "bed")
            self._published(
                _warnings_html(snap.warnings),
                query_from_inputs(params),
                snap.timings,
                ("stability", "stability"),
                (start, solved),
            )
            if snap.unsupported:  # what this bed does not support: said, not computed
                self.alert.object = _unsupported_html(snap) + _ignored_html(self.ignored)
                self.alert.visible = True
            self.snapshot = snap
        return True

    def _failed(self, exc: Exception, expected: tuple[type[Exception], ...]) -> bool:
        """Show why an update failed and return False: an :class:`InputError`'s messages, an
        ``expected`` error's one line, or any other (a bug) as an internal error, also on
        stderr, with no traceback."""
        if isinstance(exc, InputError):
            self._show_error(tuple(" ".join(m.split()) for m in exc.messages))
        elif isinstance(exc, expected):
            self._show_error((" ".join(str(exc).split()),))
        else:
            message = f"internal error: {type(exc).__name__}: {exc}"
            print(f"hairbed explore: {message}", file=sys.stderr, flush=True)
            self._show_error((message,))
        return False

    def _published(
        self,
        notes: str,
        query: str,
        solved_ms: dict[str, float],
        stage: tuple[str, str],
        clock: tuple[float, float],
    ) -> None:
        """The end of a good update (in ``pn.io.hold``): the library's warnings ``notes``, no
        error, the permalink and URL of ``query``, and the server times: the snapshot's solve
        and ``stage`` = (its key, its words) [ms], from ``clock`` = (start, solved)."""
        if self.notes.object != notes:
            self.notes.object = notes
        self.error, self.errors = "", ()
        ignored = _ignored_html(self.ignored)
        if ignored:
            self.alert.object = ignored
            self.alert.visible = True
        elif self.alert.visible:
            self.alert.visible = False
            self.alert.object = ""
        self.link.object = (
            f'<a class="hb-permalink" href="{html.escape(query)}">link to this view</a>'
        )
        self._set_url(query)
        start, solved = clock
        done = time.perf_counter()
        key, words = stage
        self.timings = {
            "solve": solved_ms["solve"],
            key: solved_ms[key],
            "compute": 1e3 * (solved - start),
            "views": 1e3 * (done - solved),
            "total": 1e3 * (done - start),
        }
        t = self.timings
        self.status.object = (
            f'<small class="hb-timing" data-total-ms="{t["total"]:.3f}">server update '
            f"{t['total']:.1f} ms: solve {t['solve']:.2f} ms, {words} "
            f"{t[key]:.1f} ms, views {t['views']:.1f} ms</small>"
        )

    def _show_error(self, messages: tuple[str, ...]) -> None:
        """Every message, one line each, above the views (the last good view stays)."""
        self.errors = messages
        self.error = "; ".join(messages)
        self.alert.object = _errors_html(messages) + _ignored_html(self.ignored)
        self.alert.visible = True

    def _restore_fields(self) -> None:
        """Every field, switch and slider back to the inputs of the view on screen (after a
        bad link: its text would otherwise stay in the fields the message names)."""
        if self.pillar.restore(self) or self.snapshot is None:
            return
        p = self.snapshot.params
        self._syncing = True
        try:
            for k, w in self.text.items():
                w.value = p.raw[k]
            self.si.value = p.si
            self._bed_column.visible = p.si
            self.twirl.value = [TWIRL_LABEL] if p.twirl else []
            self.y_choice.value = p.y
            self.x_choice.value = p.x
            self.drive.value = p.drive
            self.view_choice.value = p.view
            self.model.value = p.raw["model"]
            self.drag.value = p.raw["drag"]
        finally:
            self._syncing = False
        self._sync_widgets(p)

    def _sync_widgets(self, p: Params) -> None:
        """Sliders (and the derived fields of SI mode) to the validated inputs."""
        lo, hi = LOG_OMEGA2_RANGE
        self._syncing = True
        try:
            log_w = math.log10(p.omega2) if p.omega2 > 0.0 else lo
            self.omega2_slider.value = min(max(log_w, lo), hi)
            self.eps_slider.value = min(max(p.eps, 0.0), self.eps_slider.end)
            base = p.bed.base_angle if p.si and p.bed is not None else p.theta0
            self.theta0_slider.value = min(max(base, -_THETA0_MAX), _THETA0_MAX)
            for k in ("omega2", "eps", "theta0", "pi", "q"):  # in SI: from the bed
                self.text[k].disabled = p.si
            pumped = p.drive != "wall"
            self.load_slider.visible = pumped
            for drive, key in LOAD_KEYS.items():
                self.text[key].visible = p.drive == drive
                self.text[PUMP_INPUT[drive]].visible = p.drive == drive
            self.text["channel_length"].visible = p.view == "valve"
            if pumped and p.load:
                lo, hi = LOG_LOAD_RANGE
                self.load_slider.value = min(max(math.log10(abs(p.load)), lo), hi)
            valve = p.view == "valve"
            self._branch_pane.visible = self._phase_pane.visible = not valve
            self._valve_flow_pane.visible = self._valve_ratio_pane.visible = valve
            self.valve_table.visible = valve
            self.eps_slider.disabled = p.si
            self.drag.visible = p.raw.get("model") == "porous"
            if p.si:
                self.text["omega2"].value = _short(p.omega2)
                self.text["eps"].value = p.raw["eps"]
                self.text["theta0"].value = p.raw["theta0"]
                if pumped:
                    self.text[LOAD_KEYS[p.drive]].value = _short(float(p.load or 0.0))
        finally:
            self._syncing = False

    def _set_url(self, query: str) -> None:
        """The address bar to ``query`` (the browser adds or replaces the history entry)."""
        if self._url_live and self.history.search != query:
            self._setting_url = True
            try:
                self.history.search = query
            finally:
                self._setting_url = False

    def release(self) -> None:
        """Drop the data the page holds once its session is gone (the server discards the
        session's document and models itself): the snapshot and the figures' last data."""
        self.snapshot = None
        self.views.release()
        self.pillar.release()

    # -- downloads ------------------------------------------------------------------------

    def _json_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(snapshot_json(self.snapshot))

    def _csv_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(snapshot_csv(self.snapshot))

    def _shape_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(snapshot_shape_csv(self.snapshot))

    def _png_file(self) -> io.BytesIO:
        """The view on screen (the bed's or the pillar's) as a PNG."""
        from ._export import render_png

        return io.BytesIO(render_png(self))
