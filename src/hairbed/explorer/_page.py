"""The explorer's page: Panel widgets and layout around :class:`~._figures.Views`.

The inputs are text fields (exact entry) with a slider each; a slider move writes its value
into the text field, and every change of a text field runs :meth:`ExplorerPage.refresh`: the
inputs are validated by the library (:func:`._model.validate`), every state is solved and
classified (:func:`._model.compute`) and all views, the table, the URL and the downloads show the
new snapshot together. Bad input shows the library's message and leaves the last good snapshot
on screen.
"""

from __future__ import annotations

import html
import io
import math
import sys
import time
from typing import Any

import panel as pn
from bokeh.models import CustomJSTickFormatter

from hairbed._variables import SI, SOLUTION

from ._figures import STATE_COLORS, Views
from ._history import BrowserHistory
from ._model import (
    BED_KEYS,
    DEFAULTS,
    INPUT_KEYS,
    SI_FIELDS,
    SOLUTION_FIELDS,
    STABILITY_SEGMENTS,
    Params,
    Snapshot,
    compute,
    inputs_from_query,
    query_from_inputs,
    snapshot_csv,
    snapshot_json,
    validate,
)

__all__ = ["ExplorerPage", "LOG_OMEGA2_RANGE"]

#: Range of the omega2 slider, in log10(omega2). Typed values may lie outside.
LOG_OMEGA2_RANGE = (-3.0, 3.0)
_THETA0_MAX = 1.57

#: Rows of the table: Solution field -> description [unit].
FIELD_LABELS: dict[str, str] = {k: SOLUTION[k].heading for k in SOLUTION_FIELDS}
SI_LABELS: dict[str, str] = {k: SI[k].heading for k in SI_FIELDS}
TWIRL_COLUMNS = ("sign", "n", "xi", "omega_eps", "tip_height", "tip_deflection", "tip_angle")

_CSS = """
:host { font-size: 13px; }
table.hb { border-collapse: collapse; font-family: ui-monospace, monospace; font-size: 12px; }
table.hb th, table.hb td { padding: 1px 8px; border-bottom: 1px solid #e5e5e5; }
table.hb th { text-align: left; background: #f4f4f4; }
table.hb td.num { text-align: right; }
ul.hb-warn { color: #8a4b00; margin: 4px 0; padding-left: 18px; }
"""


def _fmt(value: Any) -> str:
    """A table cell: 12 significant digits for floats."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return str(value)
    value = float(value)
    if math.isnan(value):
        return "nan"
    return f"{value:.12g}"


def _short(value: float) -> str:
    """A value written into a text field from a slider: 6 significant digits."""
    return f"{value:.6g}"


def _widget(cls: Any, label: str, **kw: Any) -> Any:
    """A widget with a visible label (``label`` since Panel 1.9, ``name`` before)."""
    kw["label" if "label" in cls.param else "name"] = label
    return cls(**kw)


def _table_html(snap: Snapshot) -> str:
    """Every Solution field of every physical state (one column each), and the SI values."""
    states = snap.states
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

    row("stable", f"stable (linear_stability, N={STABILITY_SEGMENTS})", [s.stable for s in states])
    row("growth_rate", "largest growth rate [1/relaxation time]", [s.growth_rate for s in states])
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
    if snap.warnings:
        items = "".join(f"<li>{html.escape(w)}</li>" for w in snap.warnings)
        out.append(f'<ul class="hb-warn">{items}</ul>')
    return "".join(out)


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
            format=CustomJSTickFormatter(code="return Number((10 ** tick).toPrecision(4))"),
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
        for k, (label, unit) in BED_KEYS.items():
            self.text[k] = _widget(
                pn.widgets.TextInput,
                f"{label} [{unit}]",
                value=DEFAULTS[k],
                css_classes=[f"hb-{k}"],
                sizing_mode="stretch_width",
            )
        self.si = pn.widgets.Switch(value=DEFAULTS["si"] == "1", css_classes=["hb-si"])
        self.twirl = _widget(
            pn.widgets.Checkbox,
            "show twirling states (every branch: solve_all)",
            value=DEFAULTS["twirl"] == "1",
            css_classes=["hb-twirl-toggle"],
        )
        self.y_choice = pn.widgets.RadioButtonGroup(
            options={"tip deflection x1": "x1", "xi": "xi"},
            value=DEFAULTS["y"],
            css_classes=["hb-y"],
        )
        self.alert = pn.pane.Alert(
            "", alert_type="danger", visible=False, css_classes=["hb-error"]
        )
        self.status = pn.pane.HTML("", css_classes=["hb-status"])
        self.link = pn.pane.HTML("", css_classes=["hb-link"])
        self.table = pn.pane.HTML("", css_classes=["hb-table"], stylesheets=[_CSS])
        self.twirl_table = pn.pane.HTML("", css_classes=["hb-twirl-table"], stylesheets=[_CSS])
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
        self.omega2_slider.param.watch(self._from_omega2_slider, "value")
        self.eps_slider.param.watch(self._from_slider("eps"), "value")
        self.theta0_slider.param.watch(self._from_slider("theta0"), "value")
        for w in self.text.values():
            w.param.watch(self._on_input, "value")
        for w in (self.twirl, self.y_choice, self.si):
            w.param.watch(self._on_input, "value")

    def _build_layout(self) -> None:
        bed = pn.Column(
            *(self.text[k] for k in BED_KEYS),
            pn.pane.HTML(
                "<small>Give either the spacing or the packing fraction (leave the other "
                "empty). In SI mode the omega^2 slider moves the wall speed, eps is L/H and "
                "theta0 is the bed's base angle.</small>"
            ),
            visible=self.si.value,
        )
        self._bed_column = bed
        controls = pn.Column(
            pn.pane.HTML("<b>Flow and geometry</b>"),
            self.omega2_slider,
            self.text["omega2"],
            self.eps_slider,
            self.text["eps"],
            self.theta0_slider,
            self.text["theta0"],
            pn.Row(pn.pane.HTML("SI units (a real bed)", margin=(8, 5)), self.si),
            bed,
            self.twirl,
            pn.pane.HTML("branch diagram ordinate:", margin=(5, 10, 0, 10)),
            self.y_choice,
            pn.Row(self.download_json, self.download_csv),
            self.link,
            self.status,
            width=330,
        )
        views = self.views
        self.layout = pn.Column(
            pn.pane.HTML(
                "<h2 style='margin:4px 0'>hairbed explorer</h2>"
                "<div>Exact states of a hair bent by channel flow "
                "(arXiv:2203.04169; <code>hairbed.solve</code>, <code>solve_all</code>, "
                "<code>branches</code>, <code>stability</code>). Solid: stable, dashed: "
                "unstable, dotted: twirling (unphysical branches).</div>",
                sizing_mode="stretch_width",
            ),
            self.alert,
            pn.Row(
                controls,
                pn.Column(
                    pn.Row(
                        pn.pane.Bokeh(views.channel, css_classes=["hb-channel"]),
                        pn.pane.Bokeh(views.branch, css_classes=["hb-branch"]),
                    ),
                    pn.Row(
                        pn.pane.Bokeh(views.bistability, css_classes=["hb-bistability"]),
                        pn.pane.Bokeh(views.phase, css_classes=["hb-phase"]),
                    ),
                    self.table,
                    self.twirl_table,
                ),
            ),
            *([self.history] if self._served else []),
        )

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

    def _from_slider(self, key: str) -> Any:
        def callback(event: Any) -> None:
            if not self._syncing:
                self.text[key].value = _short(float(event.new))

        return callback

    def _on_input(self, event: Any) -> None:
        if event.obj is self.si:
            self._bed_column.visible = bool(event.new)
        if not self._syncing:
            self.refresh()

    def _raw(self) -> dict[str, str]:
        raw = {k: w.value for k, w in self.text.items()}
        raw["si"] = "1" if self.si.value else "0"
        raw["twirl"] = "1" if self.twirl.value else "0"
        raw["y"] = str(self.y_choice.value)
        return raw

    def _on_history(self, event: Any) -> None:
        """Back or Forward in the browser: show the view of the URL it went to."""
        if not self._setting_url:
            self._apply_query(event.new, restore=True)

    def _apply_query(self, query: str, *, restore: bool = False) -> None:
        """Inputs from a URL query: put them into the fields and refresh. Unknown names or
        bad values show the library's message; the last good state stays on screen.

        With ``restore`` (a URL of the browser's history), the inputs the query does not name
        take their defaults, as in a page loaded from that URL."""
        args = inputs_from_query(query)
        unknown = sorted(set(args) - set(INPUT_KEYS))
        if unknown:
            self._show_error(
                f"unknown parameter {unknown[0]!r} in the URL; known: {', '.join(INPUT_KEYS)}"
            )
            return
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
                self.twirl.value = args["twirl"].strip().lower() in ("1", "true", "on", "yes")
            if "y" in args and args["y"] in ("x1", "xi"):
                self.y_choice.value = args["y"]
        finally:
            self._syncing = False
        # the flags as given (not as the widgets could hold them): validate says what is wrong
        raw = self._raw()
        raw.update({k: v for k, v in args.items() if k in ("si", "twirl", "y")})
        self.refresh(raw)

    # -- the update -----------------------------------------------------------------------

    def refresh(self, raw: dict[str, str] | None = None) -> bool:
        """Validate the inputs, solve every state and update every view; False on bad input.

        On bad input the library's message is shown and the last good state stays.
        """
        start = time.perf_counter()
        try:
            params = validate(self._raw() if raw is None else raw)
            snap = compute(params)
        except ValueError as exc:
            self._show_error(" ".join(str(exc).split()))
            return False
        except Exception as exc:  # a bug: one line in the page and on stderr, no traceback
            message = f"internal error: {type(exc).__name__}: {exc}"
            print(f"hairbed explore: {message}", file=sys.stderr, flush=True)
            self._show_error(message)
            return False
        solved = time.perf_counter()
        with pn.io.hold():
            self.views.update(snap)
            self.table.object = _table_html(snap)
            self.twirl_table.object = _twirl_html(snap)
            self._sync_widgets(params)
            self.alert.visible = False
            self.alert.object = ""
            self.error = ""
            query = query_from_inputs(params)
            self.link.object = (
                f'<a class="hb-permalink" href="{html.escape(query)}">link to this view</a>'
            )
            self._set_url(query)
            done = time.perf_counter()
            self.snapshot = snap
            self.timings = {
                "solve": snap.timings["solve"],
                "stability": snap.timings["stability"],
                "compute": 1e3 * (solved - start),
                "views": 1e3 * (done - solved),
                "total": 1e3 * (done - start),
            }
            t = self.timings
            self.status.object = (
                f'<small class="hb-timing" data-total-ms="{t["total"]:.3f}">server update '
                f"{t['total']:.1f} ms: solve {t['solve']:.2f} ms, stability "
                f"{t['stability']:.1f} ms, views {t['views']:.1f} ms</small>"
            )
        return True

    def _show_error(self, message: str) -> None:
        self.error = message
        self.alert.object = message
        self.alert.visible = True

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
            self.text["omega2"].disabled = p.si
            self.text["eps"].disabled = p.si
            self.eps_slider.disabled = p.si
            if p.si:
                self.text["omega2"].value = _short(p.omega2)
                self.text["eps"].value = repr(p.eps)
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

    # -- downloads ------------------------------------------------------------------------

    def _json_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(snapshot_json(self.snapshot))

    def _csv_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(snapshot_csv(self.snapshot))
