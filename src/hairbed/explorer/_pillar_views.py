"""The pillar mode on the page: its widgets, figures and readouts (Panel and Bokeh).

:class:`PillarPanel` holds the pillar's inputs (text fields with sliders, the profile and the
view), three figures built once and updated in place (the pillar in its undisturbed profile
u(z), the calibration curve x1 against Lambda and the linear formula's error) and the table of
every coexisting state. The page (:class:`~._page.ExplorerPage`) registers it: a mode selector
switches between the bed's controls and views and the pillar's, its text fields join the
page's (the URL, Back and Forward, a bad link's restore work as for the bed), and
:func:`refresh_pillar` is the page's update in pillar mode.
"""

from __future__ import annotations

import html
import io
import math
import time
from typing import Any

import numpy as np
import panel as pn
from bokeh.models import ColumnDataSource, CustomJSTickFormatter, Range1d, Span

from .._jsonsafe import to_plain
from ._drive import DRIVE_DEFAULTS, SIDE_VIEWS
from ._figures import (
    FOLD_COLOR,
    REST_COLOR,
    STATE_COLORS,
    UNSTABLE_DASH,
    _equal,
    _fig,
    _legend_lines,
    _style_legend,
)
from ._model import PILLAR_DEFAULTS
from ._pillar import (
    ERROR_LEVELS,
    PILLAR_FIELDS,
    PillarSnapshot,
    compute_pillar,
    mode_of,
    pillar_query,
    pillar_snapshot_json,
    validate_pillar,
)

__all__ = ["FRAME_MS", "LOG_FORCING_RANGE", "PillarPanel", "drive_html", "refresh_pillar"]

#: Range of the forcing slider, in log10(abs(Lambda)); the sign is the typed value's.
LOG_FORCING_RANGE = (-3.0, 4.0)
_THETA0_MAX = 1.57
#: The pillar's text fields: key -> label.
TEXT_LABELS = {
    "forcing": "Lambda [-], zeta_perp tau_w L^4/(eta E I) (exact, signed)",
    "pillar_theta0": "theta0 [rad], in (-pi/2, pi/2) (exact)",
    "height_ratio": "height ratio L/H [-], in (0, 1] (couette, poiseuille)",
    "slenderness": "slenderness L/a [-], > 1.5 (empty: gamma = 1/2)",
    "tip_load": "tip load [E I/L^2] (along +x)",
    "amplitude": "drive amplitude A of Lambda [-]: Lambda + A sin(omega t)",
    "bed_kappa": "the bed's kappa = eta A/(zeta_perp L^2) [-], in [1e-4, 1e6]",
    "bed_eps": "the bed's eps = L/H [-], in (0, 1)",
    "frequency": "drive frequency omega [1/T], T = zeta_perp L^4/(E I)",
    "mu": "inertia number mu [-], the solid's m_s E I/(zeta_perp^2 L^4)",
}
#: The drive view's inputs among the text fields (shown in that view only).
DRIVE_TEXT = ("amplitude", "frequency", "mu")
DRAG_OPTIONS = {"quasi-steady": "quasi-steady", "Sader (oscillating cylinder)": "sader"}
#: The views beside the animation (:data:`._drive.SIDE_VIEWS`), as the selector shows them.
SIDE_OPTIONS = {"Bode (pillar)": "bode", "Lissajous (bed in a rheometer)": "lissajous"}
#: Milliseconds between the animation's frames (one period in FRAMES frames: about 2 s).
FRAME_MS = 40
#: Frame times kept for the page's p50/p90 readout, and how often it is shown (frames).
_FRAME_WINDOW = 240
_FRAMES_SHOWN = 48
MODE_OPTIONS = {"bed of hairs": "bed", "isolated pillar": "pillar"}
PROFILE_OPTIONS = {"sublayer": "sublayer", "couette": "couette", "poiseuille": "poiseuille"}
VIEW_OPTIONS = {"shape": "shape", "calibration curve": "calibration", "drive (animation)": "drive"}
#: Rows of the state table: field -> label [unit].
FIELD_LABELS = {
    "forcing": "forcing Lambda [-]",
    "theta0": "base angle theta0 [rad]",
    "gamma": "drag ratio gamma = zeta_par/zeta_perp [-]",
    "tip_load": "tip load [E I/L^2]",
    "tip_deflection": "tip deflection x1 [L]",
    "tip_height": "tip height h1 [L]",
    "tip_angle": "tip angle theta(1) [rad]",
    "base_curvature": "base curvature theta'(0) [1/L]",
    "drag_x": "drag, streamwise [E I/L^2]",
    "drag_z": "drag, wall-normal [E I/L^2]",
    "tip_deflection_slope": "dx1/dLambda [L]",
    "status": "status",
    "error_estimate": "error estimate [rad]",
    "residual": "residual",
    "nit": "Newton iterations",
    "num": "Chebyshev degree N",
}
_CSS = """
:host { font-size: 13px; }
table.hb { border-collapse: collapse; font-family: ui-monospace, monospace; font-size: 12px; }
table.hb th, table.hb td { padding: 1px 8px; border-bottom: 1px solid #e5e5e5; }
table.hb th { text-align: left; background: #f4f4f4; }
table.hb td.num { text-align: right; }
"""
_SHAPE_POINTS = 121
#: The forcing slider's shown value: abs(Lambda), to 6 significant digits.
_SHOWN_LOG = "return String(Number((10 ** tick).toPrecision(6)))"
#: Where the profile's arrows start [L], and the length of the largest [L].
_PROFILE_X0, _PROFILE_LEN = -1.7, 0.6


def _fmt(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer, str)):
        return html.escape(str(value))
    value = float(value)
    return "nan" if math.isnan(value) else f"{value:.12g}"


def _short(value: float) -> str:
    return f"{value:.6g}"


def _widget(cls: Any, label: str, **kw: Any) -> Any:
    kw["label" if "label" in cls.param else "name"] = label
    return cls(**kw)


def table_html(snap: PillarSnapshot) -> str:
    """Every shown :class:`hairbed.PillarState` field of every state (a column each); no
    state: the library's message."""
    if not snap.states:
        return (
            '<table class="hb hb-pillar-states" data-count="0"><thead><tr><th>no state</th>'
            "</tr></thead></table>"
            f'<p class="hb-pillar-nostate">{html.escape(snap.message or "no state")}</p>'
        )
    head = "".join(
        f'<th style="color:{STATE_COLORS.get(v.label, "black")}">{html.escape(v.label)}</th>'
        for v in snap.states
    )
    rows = []

    def row(key: str, label: str, values: list[Any]) -> None:
        cells = "".join(
            f'<td class="num" data-state="{v.label}" data-field="{key}">{_fmt(x)}</td>'
            for v, x in zip(snap.states, values)
        )
        rows.append(f'<tr data-row="{key}"><th>{html.escape(label)}</th>{cells}</tr>')

    if snap.params.window:
        row("stable", "stable (dLambda/dx1 > 0 on the branch)", [v.stable for v in snap.states])
    for key in PILLAR_FIELDS:
        row(key, FIELD_LABELS[key], [getattr(v.state, key) for v in snap.states])
    row("message", "message", [v.state.message for v in snap.states])
    n = len(snap.states)
    return (
        f'<table class="hb hb-pillar-states" data-count="{n}"><thead><tr>'
        f"<th>{n} state{'s' if n > 1 else ''}</th>{head}</tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table>"
    )


def linear_html(snap: PillarSnapshot) -> str:
    """The linear formula at the current forcing (the calibration view only)."""
    c = snap.calibration
    if c is None:
        return ""
    lam = abs(snap.params.forcing)
    rows: list[tuple[str, str, Any]] = [
        ("rest", "x1 at rest (Lambda = 0) [L]", c.rest),
        ("slope", "dx1/dLambda at Lambda = 0 [L]", c.slope),
        ("linear", "linear x1 at abs(Lambda) [L]", float(c.linear(lam))),
        ("error", "error of the linear Lambda read from x1 [-]", snap.error_at()),
        *((f"level_{lv:g}", f"abs(Lambda) where it reaches {lv:.0%}", c.levels[lv])
          for lv in ERROR_LEVELS),
    ]  # fmt: skip
    for k, (lf, xf) in enumerate(c.folds):
        rows.append((f"fold_{k}", f"fold {k + 1}: abs(Lambda), x1", f"{lf:.8g}, {xf:.8g}"))
    body = "".join(
        f'<tr><th>{html.escape(label)}</th><td class="num" data-field="{key}">{_fmt(v)}</td></tr>'
        for key, label, v in rows
    )
    return (
        f'<table class="hb hb-pillar-linear" data-status="{c.status}"><thead><tr>'
        f"<th>the linear formula</th><th></th></tr></thead><tbody>{body}</tbody></table>"
    )


def _connected() -> bool:
    """Whether a browser is connected to this served session (True outside a server): a tab
    closed stops the frames at once, not when the server discards its session some seconds
    later (a frame written to its closed websocket would be an error in the server's log)."""
    doc = pn.state.curdoc
    context = getattr(doc, "session_context", None) if doc is not None else None
    session = getattr(context, "session", None) if context is not None else None
    return session is None or int(session.connection_count) > 0


def drive_html(
    snap: PillarSnapshot,
    frame_ms: list[float] | None = None,
    frame_cpu_ms: list[float] | None = None,
    frame_at: list[float] | None = None,
) -> str:
    """The drive view's readout: the nonlinear run's first harmonic against the linear
    response at the drive's frequency, the run, and the server's time per frame (wall and
    this thread's CPU time [ms], and the frames' rate [1/s])."""
    a = snap.animation
    d = snap.params.drive
    if a is None or d is None:
        return ""
    if a.status < 0:
        return (
            f'<p class="hb-drive-message" data-status="{a.status}">no animation: '
            f"{html.escape(a.message)}</p>"
        )
    rows = [
        ("linear_gain", f"linear |dx1/dLambda| at omega ({d.drag_model}) [L]", abs(a.bode_now)),
        ("linear_phase", "linear phase [rad]", math.atan2(a.bode_now.imag, a.bode_now.real)),
        ("harmonic_gain", "nonlinear first harmonic |x1_1|/A (quasi-steady) [L]", abs(a.harmonic)),
        ("harmonic_phase", "its phase [rad]", math.atan2(a.harmonic.imag, a.harmonic.real)),
        ("settle_time", "time run before the period shown [T]", a.settle),
        ("steps", "integrator steps", a.steps),
        ("frames", "frames per period", a.x.shape[0]),
    ]
    if frame_ms:
        ms = np.asarray(frame_ms, dtype=np.float64)
        rows += [
            ("frame_p50", "server time per frame, median [ms]", float(np.percentile(ms, 50))),
            ("frame_p90", "server time per frame, p90 [ms]", float(np.percentile(ms, 90))),
            ("frame_count", "frames timed", ms.size),
        ]
    if frame_cpu_ms:
        cpu = np.asarray(frame_cpu_ms, dtype=np.float64)
        rows += [
            ("frame_cpu_p50", "its CPU time, median [ms]", float(np.percentile(cpu, 50))),
            ("frame_cpu_p90", "its CPU time, p90 [ms]", float(np.percentile(cpu, 90))),
        ]
    if frame_at and len(frame_at) > 1:
        rate = (len(frame_at) - 1) / max(frame_at[-1] - frame_at[0], 1e-9)
        rows.append(("frame_rate", f"frames per second (asked: {1e3 / FRAME_MS:g})", rate))
    body = "".join(
        f'<tr><th>{html.escape(label)}</th><td class="num" data-field="{key}">{_fmt(v)}</td></tr>'
        for key, label, v in rows
    )
    return f'<table class="hb hb-drive-table">{body}</table>'


#: The Lissajous view's readout: measure -> label [unit].
LISSAJOUS_LABELS = {
    "strain_amplitude": "strain amplitude gamma0 = A/(kappa omega) [-]",
    "storage": "G'_1 [E I/(A L^2)]",
    "loss": "G''_1 [E I/(A L^2)]",
    "minimum_modulus": "G'_M (Ewoldt) [E I/(A L^2)]",
    "large_modulus": "G'_L (Ewoldt) [E I/(A L^2)]",
    "minimum_viscosity": "eta'_M (Ewoldt) [E I T/(A L^2)]",
    "large_viscosity": "eta'_L (Ewoldt) [E I T/(A L^2)]",
    "third_harmonic": "I_3/I_1 [-]",
    "even_ratio": "even part over I_1 [-] (a tilted bed)",
    "periodic_error": "periodicity error [-]",
    "liss_solve_ms": "time to the periodic state [ms]",
}


def lissajous_html(snap: PillarSnapshot) -> str:
    """The Lissajous view's readout: the bed's LAOS measures, or why there are none."""
    li = snap.lissajous
    if li is None:
        return ""
    if li.status < 0:
        return (
            f'<p class="hb-lissajous-message" data-status="{li.status}">no Lissajous view: '
            f"{html.escape(li.message)}</p>"
        )
    values = {**li.measures, "strain_amplitude": li.strain_amplitude,
              "liss_solve_ms": li.timings.get("solve", math.nan)}  # fmt: skip
    body = "".join(
        f'<tr><th>{html.escape(label)}</th><td class="num" data-field="{key}">'
        f"{_fmt(values.get(key))}</td></tr>"
        for key, label in LISSAJOUS_LABELS.items()
    )
    note = (
        "the porous bed (kappa, eps above, the pillar's theta0) whose top wall is driven by "
        "the same forcing Lambda + A sin(omega t); time in T, stress in E I/(A L^2)"
    )
    return (
        f'<table class="hb hb-lissajous-table" data-status="{li.status}"><caption>'
        f"{html.escape(note)}</caption>{body}</table>"
    )


def _runs(stable: np.ndarray) -> list[tuple[int, int, bool]]:
    """Runs (start, stop, stable) of equal stability, each ending on the next one's start."""
    runs, start = [], 0
    for i in range(1, len(stable) + 1):
        if i == len(stable) or stable[i] != stable[start]:
            runs.append((start, min(i + 1, len(stable)), bool(stable[start])))
            start = i
    return runs


class PillarPanel:
    """The pillar mode's widgets, figures and tables (see the module's description)."""

    def __init__(self) -> None:
        self._shown: dict[int, dict[str, Any]] = {}
        self._syncing = False
        #: The last good pillar view on screen (None: none yet).
        self.snapshot: PillarSnapshot | None = None
        #: The mode on screen: "bed" or "pillar".
        self.shown_mode = "bed"
        #: The animation on screen (None: none), its frame, the server's time per frame [ms]
        #: (the last _FRAME_WINDOW) and the periodic callback that plays it (served pages).
        self._anim: Any = None
        #: The Lissajous view on screen (None: not shown).
        self._liss: Any = None
        self._frame = 0
        self._clock: float | None = None
        self._timed = 0
        self.frame_ms: list[float] = []
        self.frame_cpu_ms: list[float] = []
        self.frame_at: list[float] = []
        self._player: Any = None
        self._build_widgets()
        self._build_layout()

    # -- widgets ----------------------------------------------------------------------------

    def _build_widgets(self) -> None:
        lo, hi = LOG_FORCING_RANGE
        self.mode = pn.widgets.RadioButtonGroup(
            options=MODE_OPTIONS, value=PILLAR_DEFAULTS["mode"], css_classes=["hb-mode"]
        )
        self.forcing_slider = _widget(
            pn.widgets.FloatSlider, "forcing abs(Lambda) (log scale)", start=lo, end=hi,
            step=0.005, value=math.log10(float(PILLAR_DEFAULTS["forcing"])),
            format=CustomJSTickFormatter(code=_SHOWN_LOG),
            css_classes=["hb-forcing-slider"], sizing_mode="stretch_width",
        )  # fmt: skip
        self.theta0_slider = _widget(
            pn.widgets.FloatSlider, "base angle theta0 [rad]", start=-_THETA0_MAX,
            end=_THETA0_MAX, step=0.005, value=float(PILLAR_DEFAULTS["pillar_theta0"]),
            css_classes=["hb-pillar_theta0-slider"], sizing_mode="stretch_width",
        )  # fmt: skip
        self.text = {
            k: _widget(
                pn.widgets.TextInput,
                label,
                value={**PILLAR_DEFAULTS, **DRIVE_DEFAULTS}[k],
                css_classes=[f"hb-{k}"],
                sizing_mode="stretch_width",
            )  # fmt: skip
            for k, label in TEXT_LABELS.items()
        }
        self.profile = pn.widgets.RadioButtonGroup(
            options=PROFILE_OPTIONS, value=PILLAR_DEFAULTS["profile"], css_classes=["hb-profile"]
        )
        self.view = pn.widgets.RadioButtonGroup(
            options=VIEW_OPTIONS, value=PILLAR_DEFAULTS["pillar_view"],
            css_classes=["hb-pillar-view"],
        )  # fmt: skip
        self.drag_model = pn.widgets.RadioButtonGroup(
            options=DRAG_OPTIONS, value=DRIVE_DEFAULTS["drag_model"], css_classes=["hb-drag-model"]
        )
        self.side_view = pn.widgets.RadioButtonGroup(
            options=SIDE_OPTIONS, value=DRIVE_DEFAULTS["side_view"], css_classes=["hb-side-view"]
        )
        assert set(SIDE_OPTIONS.values()) == set(SIDE_VIEWS)
        self.drive_table = pn.pane.HTML("", css_classes=["hb-pillar-drive"], stylesheets=[_CSS])
        self.table = pn.pane.HTML("", css_classes=["hb-pillar-table"], stylesheets=[_CSS])
        self.linear_table = pn.pane.HTML("", css_classes=["hb-pillar-linear"], stylesheets=[_CSS])
        self.liss_table = pn.pane.HTML("", css_classes=["hb-lissajous"], stylesheets=[_CSS])
        self.download_json = pn.widgets.FileDownload(
            callback=self._json_file, filename="hairbed-pillar.json", label="download JSON",
            css_classes=["hb-pillar-download-json"],
        )  # fmt: skip
        self.forcing_slider.param.watch(self._from_forcing_slider, "value")
        self.theta0_slider.param.watch(self._from_theta0_slider, "value")

    def choices(self) -> dict[str, str]:
        """The chosen (not typed) inputs, as text."""
        return {
            "mode": str(self.mode.value),
            "profile": str(self.profile.value),
            "pillar_view": str(self.view.value),
            "drag_model": str(self.drag_model.value),
            "side_view": str(self.side_view.value),
        }

    def apply_choices(self, args: dict[str, str]) -> None:
        """The choices a URL names (a bad one stays as it was: validation names it)."""
        for key, w in (
            ("mode", self.mode),
            ("profile", self.profile),
            ("pillar_view", self.view),
            ("drag_model", self.drag_model),
            ("side_view", self.side_view),
        ):
            if key in args and args[key].strip() in w.options.values():
                w.value = args[key].strip()

    def _from_forcing_slider(self, event: Any) -> None:
        if self._syncing:
            return
        last = self.snapshot.params.forcing if self.snapshot is not None else 1.0
        sign = -1.0 if last < 0.0 else 1.0
        self.text["forcing"].value = _short(sign * float(_short(10.0 ** float(event.new))))

    def _from_theta0_slider(self, event: Any) -> None:
        if not self._syncing:
            self.text["pillar_theta0"].value = _short(float(event.new))

    # -- figures ------------------------------------------------------------------------------

    def _build_figures(self) -> None:
        f = _fig(
            "the pillar in the undisturbed flow u(z), to scale",
            "x/L [-] (along the flow)",
            "z/L [-] (height)",
            x_range=Range1d(-1.8, 1.2),
            y_range=Range1d(-0.1, 1.3),
            frame_width=460,
            frame_height=int(460 * 1.4 / 3.0),
        )
        f.quad(left=-100, right=100, bottom=-100, top=0, fill_color="#d9d9d9", line_color="black")
        self.top_wall = Span(dimension="width", location=1e9, line_color="black", line_width=2)
        f.add_layout(self.top_wall)
        self.sh_flow = ColumnDataSource({"x0": [], "y0": [], "x1": [], "y1": []})
        f.segment("x0", "y0", "x1", "y1", source=self.sh_flow, color="#9ecae1", line_width=2)
        f.scatter("x1", "y1", source=self.sh_flow, marker="triangle", angle=-np.pi / 2, size=7,
                  color="#9ecae1")  # fmt: skip
        self.sh_profile = ColumnDataSource({"x": [], "y": []})
        f.line("x", "y", source=self.sh_profile, color="#3182bd", line_width=2)
        self.sh_rest = ColumnDataSource({"x": [], "y": []})
        f.line("x", "y", source=self.sh_rest, color=REST_COLOR, line_width=2)
        self.sh_stable = ColumnDataSource({"xs": [], "ys": [], "color": []})
        f.multi_line("xs", "ys", source=self.sh_stable, color="color", line_width=3)
        self.sh_unstable = ColumnDataSource({"xs": [], "ys": [], "color": []})
        f.multi_line("xs", "ys", source=self.sh_unstable, color="color", line_width=3,
                     line_dash=UNSTABLE_DASH)  # fmt: skip
        self.sh_tips = ColumnDataSource({"x": [], "y": [], "color": [], "label": []})
        f.scatter("x", "y", source=self.sh_tips, color="color", size=7)
        f.text("x", "y", text="label", source=self.sh_tips, text_font_size="11px", x_offset=6,
               y_offset=-4, text_color="color")  # fmt: skip
        sample = _legend_lines(f, "stable", "unstable", "rest")
        prof = f.line([math.nan], [math.nan], color="#3182bd", line_width=2)
        _style_legend(
            f,
            [
                ("stable", [sample["stable"]]),
                ("unstable", [sample["unstable"]]),
                ("at rest", [sample["rest"]]),
                ("u(z), scaled", [prof]),
            ],
            "top_right",
        )
        f.grid.grid_line_alpha = 0.3
        self.shape_fig = f

        c = _fig(
            "calibration curve: tip deflection against the forcing",
            "forcing abs(Lambda) [-]",
            "tip deflection x1 [L]",
            x_axis_type="log",
            x_range=Range1d(1e-3, 1e4),
            y_range=Range1d(-1.0, 1.0),
            width=470,
            height=360,
        )
        self.cal_stable = ColumnDataSource({"xs": [], "ys": []})
        c.multi_line("xs", "ys", source=self.cal_stable, color="black", line_width=2)
        self.cal_unstable = ColumnDataSource({"xs": [], "ys": []})
        c.multi_line("xs", "ys", source=self.cal_unstable, color="black", line_width=2,
                     line_dash=UNSTABLE_DASH)  # fmt: skip
        self.cal_linear = ColumnDataSource({"x": [], "y": []})
        lin = c.line("x", "y", source=self.cal_linear, color="#E69F00", line_width=2,
                     line_dash="dashed")  # fmt: skip
        self.cal_folds = ColumnDataSource({"x": [], "y": []})
        c.scatter("x", "y", source=self.cal_folds, marker="x", size=12, line_width=3,
                  color=FOLD_COLOR)  # fmt: skip
        self.cal_levels = ColumnDataSource({"x": [], "y": [], "marker": [], "label": []})
        lv = c.scatter("x", "y", source=self.cal_levels, marker="marker", size=9,
                       fill_color="white", line_color="#E69F00", line_width=2)  # fmt: skip
        c.text("x", "y", text="label", source=self.cal_levels, text_font_size="11px",
               x_offset=8, y_offset=8, text_color="#b07800")  # fmt: skip
        self.cal_now = Span(dimension="height", location=1.0, line_color="#999999",
                            line_dash="dashed")  # fmt: skip
        c.add_layout(self.cal_now)
        self.cal_states = ColumnDataSource({"x": [], "y": [], "color": []})
        c.scatter("x", "y", source=self.cal_states, color="color", size=10, line_color="black")
        sample = _legend_lines(c, "curve", "folds", "state")
        unst = c.line([math.nan], [math.nan], color="black", line_width=2, line_dash=UNSTABLE_DASH)
        _style_legend(
            c,
            [
                ("exact (stable)", [sample["curve"]]),
                ("exact (unstable)", [unst]),
                ("linear formula", [lin]),
                ("linear 1 %, 10 % off", [lv]),
                ("folds", [sample["folds"]]),
                ("current state", [sample["state"]]),
            ],
            "top_left",
        )
        self.cal_fig = c

        e = _fig(
            "error of the linear formula's Lambda read from x1",
            "forcing abs(Lambda) [-]",
            "abs(Lambda_lin - Lambda)/Lambda [-]",
            x_axis_type="log",
            y_axis_type="log",
            x_range=Range1d(1e-3, 1e4),
            y_range=Range1d(1e-5, 10.0),
            width=470,
            height=300,
        )
        self.err_curve = ColumnDataSource({"x": [], "y": []})
        e.line("x", "y", source=self.err_curve, color="black", line_width=2)
        for level in ERROR_LEVELS:
            e.add_layout(Span(dimension="width", location=level, line_color="#E69F00",
                              line_dash="dotted", line_width=2))  # fmt: skip
        self.err_now = ColumnDataSource({"x": [], "y": [], "color": []})
        e.scatter("x", "y", source=self.err_now, color="color", size=10, line_color="black")
        self.err_fig = e
        self._build_drive_figures()

    def _build_drive_figures(self) -> None:
        """The drive view: the pillar moving (one frame of the period at a time) and the
        Bode view beside it (:data:`._drive.SIDE_VIEWS`; the bed's Lissajous view joins
        there)."""
        d = _fig(
            "the pillar in the oscillating flow Lambda + A sin(omega t), to scale",
            "x/L [-] (along the flow)",
            "z/L [-] (height)",
            x_range=Range1d(-1.2, 1.2),
            y_range=Range1d(-0.1, 1.3),
            frame_width=400,
            frame_height=int(400 * 1.4 / 2.4),
        )
        d.quad(left=-100, right=100, bottom=-100, top=0, fill_color="#d9d9d9", line_color="black")
        self.dr_mean = ColumnDataSource({"x": [], "y": []}, name="hb-drive-mean")
        mean = d.line("x", "y", source=self.dr_mean, color=REST_COLOR, line_width=2,
                      line_dash="dashed")  # fmt: skip
        self.dr_path = ColumnDataSource({"x": [], "y": []}, name="hb-drive-path")
        path = d.line("x", "y", source=self.dr_path, color="#E69F00", line_width=1.5)
        self.dr_shape = ColumnDataSource({"x": [], "y": []}, name="hb-drive-shape")
        now = d.line("x", "y", source=self.dr_shape, color=STATE_COLORS["low"], line_width=3)
        # the tip's dot: its own source (a PNG export draws every point of a source)
        self.dr_tip = ColumnDataSource({"x": [], "y": []}, name="hb-drive-tip")
        d.scatter("x", "y", source=self.dr_tip, color=STATE_COLORS["low"], size=8)
        _style_legend(
            d,
            [("now", [now]), ("static, at the mean", [mean]), ("the tip's path", [path])],
            "top_left",
        )
        d.grid.grid_line_alpha = 0.3
        self.drive_fig = d
        g = _fig(
            "Bode view: tip deflection per forcing dx1/dLambda",
            "omega [1/T]",
            "|dx1/dLambda| [L]",
            x_axis_type="log",
            y_axis_type="log",
            width=430,
            height=260,
        )
        self.bode_gain = ColumnDataSource({"x": [], "y": []}, name="hb-bode-gain")
        lin = g.line("x", "y", source=self.bode_gain, color="black", line_width=2)
        self.bode_now_gain = ColumnDataSource({"x": [], "y": []})
        nl = g.scatter("x", "y", source=self.bode_now_gain, color="#D55E00", size=10,
                       line_color="black")  # fmt: skip
        self.bode_mark = Span(dimension="height", location=1.0, line_color="#999999",
                              line_dash="dashed")  # fmt: skip
        g.add_layout(self.bode_mark)
        _style_legend(
            g, [("linear", [lin]), ("nonlinear run, first harmonic", [nl])], "bottom_left"
        )
        self.bode_gain_fig = g
        h = _fig(
            "phase of dx1/dLambda (a lag is negative)",
            "omega [1/T]",
            "phase [deg]",
            x_axis_type="log",
            x_range=g.x_range,
            width=430,
            height=220,
        )
        self.bode_phase = ColumnDataSource({"x": [], "y": []}, name="hb-bode-phase")
        h.line("x", "y", source=self.bode_phase, color="black", line_width=2)
        self.bode_now_phase = ColumnDataSource({"x": [], "y": []})
        h.scatter("x", "y", source=self.bode_now_phase, color="#D55E00", size=10,
                  line_color="black")  # fmt: skip
        self.bode_phase_mark = Span(dimension="height", location=1.0, line_color="#999999",
                                    line_dash="dashed")  # fmt: skip
        h.add_layout(self.bode_phase_mark)
        self.bode_phase_fig = h
        self._build_lissajous_figures()

    def _build_lissajous_figures(self) -> None:
        """The Lissajous view: the bed's wall stress against the strain (with Cho's elastic
        part) and against the strain rate (with the viscous part), the frame's point on
        each."""
        figs = []
        for x_label, part, title in (
            ("strain gamma [-]", "elastic", "Lissajous: the bed's wall stress against strain"),
            ("strain rate [1/T]", "viscous", "against the strain rate"),
        ):
            f = _fig(title, x_label, "stress [E I/(A L^2)]", width=430, height=240)
            total = ColumnDataSource({"x": [], "y": []})
            tot = f.line("x", "y", source=total, color="black", line_width=2)
            along = ColumnDataSource({"x": [], "y": []})
            pl = f.line("x", "y", source=along, color="#0072B2", line_width=2, line_dash="dashed")
            name = "hb-liss-dot" if part == "elastic" else "hb-liss-rate-dot"
            dot = ColumnDataSource({"x": [], "y": []}, name=name)
            now = f.scatter("x", "y", source=dot, color="#D55E00", size=10, line_color="black")
            _style_legend(
                f, [("stress", [tot]), (f"{part} part", [pl]), ("now", [now])], "top_left"
            )
            f.grid.grid_line_alpha = 0.3
            figs.append((f, total, along, dot))
        (self.liss_fig, self.liss_total, self.liss_elastic, self.liss_dot) = figs[0]
        (self.liss_rate_fig, self.liss_rate_total, self.liss_viscous, self.liss_rate_dot) = figs[1]

    def _build_layout(self) -> None:
        self.controls = pn.Column(
            pn.pane.HTML("<b>Isolated pillar</b> (theory.md §12)", margin=(5, 10, 0, 10)),
            self.forcing_slider,
            self.text["forcing"],
            self.theta0_slider,
            self.text["pillar_theta0"],
            pn.pane.HTML("undisturbed profile u(z):", margin=(5, 10, 0, 10)),
            self.profile,
            self.text["height_ratio"],
            self.text["slenderness"],
            self.text["tip_load"],
            pn.pane.HTML("view:", margin=(5, 10, 0, 10)),
            self.view,
            self._drive_controls(),
            self.download_json,
            visible=False,
            margin=0,
        )
        #: The pillar's views: empty until the pillar mode is first shown (a session that
        #: stays with the bed sends no figure of the pillar to its browser).
        self.views = pn.Column(visible=False)

    def _drive_controls(self) -> Any:
        """The drive view's inputs (shown in that view only)."""
        self.lissajous_controls = pn.Column(
            self.text["bed_kappa"], self.text["bed_eps"], visible=False, margin=0,
            css_classes=["hb-lissajous-controls"],
        )  # fmt: skip
        self.drive_controls = pn.Column(
            *(self.text[k] for k in DRIVE_TEXT),
            pn.pane.HTML("drag of the Bode view:", margin=(5, 10, 0, 10)),
            self.drag_model,
            pn.pane.HTML("beside the animation:", margin=(5, 10, 0, 10)),
            self.side_view,
            self.lissajous_controls,
            visible=False,
            margin=0,
            css_classes=["hb-drive-controls"],
        )
        return self.drive_controls

    def _ensure_views(self) -> None:
        """Build the figures and fill :attr:`views` (once)."""
        if self.views.objects:
            return
        self._build_figures()
        self._cal_pane = pn.Column(
            pn.pane.Bokeh(self.cal_fig), pn.pane.Bokeh(self.err_fig),
            css_classes=["hb-pillar-calibration"], visible=False,
        )  # fmt: skip
        self._shape_pane = pn.Column(
            pn.pane.Bokeh(self.shape_fig), css_classes=["hb-pillar-shape"]
        )
        # the views beside the animation (._drive.SIDE_VIEWS): the pillar's Bode view and
        # the Lissajous view of a bed in a rheometer, one shown at a time
        self._side_views = {
            "bode": pn.Column(
                pn.pane.Bokeh(self.bode_gain_fig),
                pn.pane.Bokeh(self.bode_phase_fig),
                css_classes=["hb-drive-bode"],
            ),
            "lissajous": pn.Column(
                pn.pane.Bokeh(self.liss_fig),
                pn.pane.Bokeh(self.liss_rate_fig),
                self.liss_table,
                css_classes=["hb-drive-lissajous"],
                visible=False,
            ),
        }
        assert set(self._side_views) == set(SIDE_VIEWS)
        self._drive_pane = pn.Row(
            pn.Column(pn.pane.Bokeh(self.drive_fig), self.drive_table),
            pn.Column(*self._side_views.values()),
            css_classes=["hb-pillar-drive-view"],
            visible=False,
        )
        self.views.objects = [
            pn.Row(self._shape_pane, self._cal_pane, self._drive_pane),
            self.linear_table,
            self.table,
        ]

    # -- update -------------------------------------------------------------------------------

    def _set(self, source: Any, data: dict[str, Any]) -> None:
        last = self._shown.get(id(source))
        if last is not None and last.keys() == data.keys():
            if all(_equal(last[k], data[k]) for k in data):
                return
        self._shown[id(source)] = data
        source.data = {k: to_plain(v, strict=False) for k, v in data.items()}

    def update(self, snap: PillarSnapshot) -> None:
        """Show a snapshot: the shape, the profile, the curve, the tables."""
        self._ensure_views()
        p = snap.params
        s = np.linspace(0.0, 1.0, _SHAPE_POINTS)
        stable: dict[str, list[Any]] = {"xs": [], "ys": [], "color": []}
        unstable: dict[str, list[Any]] = {"xs": [], "ys": [], "color": []}
        tips: dict[str, list[Any]] = {"x": [], "y": [], "color": [], "label": []}
        for v in snap.states:
            _, x, z, _ = v.state.shape(s)
            target = unstable if v.stable is False else stable
            color = STATE_COLORS.get(v.label, "black")
            target["xs"].append(np.asarray(x, dtype=np.float64))
            target["ys"].append(np.asarray(z, dtype=np.float64))
            target["color"].append(color)
            tips["x"].append(float(v.state.tip_deflection))
            tips["y"].append(float(v.state.tip_height))
            tips["color"].append(color)
            tips["label"].append(v.label if len(snap.states) > 1 else "")
        self._set(self.sh_stable, stable)
        self._set(self.sh_unstable, unstable)
        self._set(self.sh_tips, tips)
        self._set(self.sh_rest, {"x": [0.0, math.sin(p.theta0)], "y": [0.0, math.cos(p.theta0)]})
        u = np.asarray(snap.profile_u, dtype=np.float64)
        big = float(np.max(np.abs(u))) or 1.0
        sign = -1.0 if p.forcing < 0.0 else 1.0
        ux = _PROFILE_X0 + sign * _PROFILE_LEN * u / big
        if sign < 0.0:
            ux = ux + _PROFILE_LEN
        self._set(self.sh_profile, {"x": ux, "y": snap.profile_z})
        every = slice(0, None, 8)
        base = _PROFILE_X0 + (_PROFILE_LEN if sign < 0.0 else 0.0)
        arrows = {
            "x0": np.full(u[every].shape, base),
            "y0": snap.profile_z[every],
            "x1": ux[every],
            "y1": snap.profile_z[every],
        }
        self._set(self.sh_flow, arrows)
        channel = p.profile != "sublayer" and p.height_ratio is not None
        self.top_wall.location = 1.0 / p.height_ratio if channel and p.height_ratio else 1e9
        self._update_calibration(snap)
        self.table.object = table_html(snap)
        self.linear_table.object = linear_html(snap)
        self.linear_table.visible = snap.calibration is not None
        self._cal_pane.visible = p.view == "calibration"
        self._update_drive(snap)

    def _update_drive(self, snap: PillarSnapshot) -> None:
        """The drive view: the animation's static parts and first frame, the Bode view."""
        drive = snap.params.view == "drive"
        self._drive_pane.visible = drive
        self._shape_pane.visible = not drive
        a = snap.animation if drive else None
        if a is not self._anim:
            self._anim, self._frame, self._clock = a, 0, None
            for kept in (self.frame_ms, self.frame_cpu_ms, self.frame_at):
                kept.clear()
        self.drive_table.object = drive_html(snap) if drive else ""
        if a is None or a.status < 0:
            self._set(self.dr_shape, {"x": [], "y": []})
            self._set(self.dr_path, {"x": [], "y": []})
            self._set(self.dr_tip, {"x": [], "y": []})
            return
        self._set(self.dr_mean, {"x": a.mean_x, "y": a.mean_z})
        self._set(self.dr_path, {"x": np.append(a.tip_x, a.tip_x[:1]),
                                 "y": np.append(a.tip_z, a.tip_z[:1])})  # fmt: skip
        self.dr_shape.data = {"x": a.x[0].tolist(), "y": a.z[0].tolist()}
        self.dr_tip.data = {"x": [float(a.tip_x[0])], "y": [float(a.tip_z[0])]}
        gain = np.abs(a.bode)
        self._set(self.bode_gain, {"x": a.omega, "y": gain})
        self._set(self.bode_phase, {"x": a.omega, "y": np.degrees(np.unwrap(np.angle(a.bode)))})
        d = snap.params.drive
        assert d is not None
        for name, pane in self._side_views.items():
            pane.visible = name == d.side_view
        self._update_lissajous(snap)
        self.bode_mark.location = self.bode_phase_mark.location = d.frequency
        ph = math.degrees(math.atan2(a.harmonic.imag, a.harmonic.real))
        # the harmonic's phase on the linear curve's branch (unwrapped there)
        lin_ph = float(np.interp(math.log(d.frequency), np.log(a.omega),
                                 np.degrees(np.unwrap(np.angle(a.bode)))))  # fmt: skip
        ph += 360.0 * round((lin_ph - ph) / 360.0)
        self._set(self.bode_now_gain, {"x": [d.frequency], "y": [abs(a.harmonic)]})
        self._set(self.bode_now_phase, {"x": [d.frequency], "y": [ph]})

    def _update_lissajous(self, snap: PillarSnapshot) -> None:
        """The Lissajous view's curves, the first frame's points and its readout."""
        li = snap.lissajous
        self._liss = li if li is not None and li.status >= 0 else None
        self.liss_table.object = lissajous_html(snap)
        if self._liss is None:
            for src in (self.liss_total, self.liss_elastic, self.liss_dot, self.liss_rate_total,
                        self.liss_viscous, self.liss_rate_dot):  # fmt: skip
                self._set(src, {"x": [], "y": []})
            return
        c = self._liss.curve
        self._set(self.liss_total, {"x": c["strain"], "y": c["total"]})
        self._set(self.liss_elastic, {"x": c["strain"], "y": c["elastic"]})
        self._set(self.liss_rate_total, {"x": c["strain_rate"], "y": c["total"]})
        self._set(self.liss_viscous, {"x": c["strain_rate"], "y": c["viscous"]})
        self._liss_frame(0)

    def _liss_frame(self, k: int) -> None:
        li = self._liss
        if li is None or not li.stress.size:
            return
        k %= li.stress.size
        y = [float(li.stress[k])]
        self.liss_dot.data = {"x": [float(li.strain[k])], "y": y}
        self.liss_rate_dot.data = {"x": [float(li.strain_rate[k])], "y": y}

    def next_frame(self, frame: int | None = None) -> None:
        """The animation's frame of the clock (the periodic callback of a served page), or
        ``frame``: the precomputed shape of that frame sent to the figure, its server time
        kept (the model's update and the document's events, held and flushed here)."""
        a = self._anim
        if a is None or a.status < 0 or not a.x.size or not _connected():
            return
        start, cpu = time.perf_counter(), time.thread_time()
        # the frame of the clock: the period takes FRAMES x FRAME_MS on screen, whatever
        # frames a busy server drops (the first call starts the clock)
        if self._clock is None:
            self._clock = start - self._frame * FRAME_MS / 1e3
        k = int((start - self._clock) * 1e3 / FRAME_MS) if frame is None else int(frame)
        k %= a.x.shape[0]
        self._frame = k
        with pn.io.hold():  # both changes in one message
            self.dr_shape.data = {"x": a.x[k].tolist(), "y": a.z[k].tolist()}
            self.dr_tip.data = {"x": [float(a.tip_x[k])], "y": [float(a.tip_z[k])]}
            self._liss_frame(k)  # the bed's point at the same phase of the forcing
        self.frame_ms.append(1e3 * (time.perf_counter() - start))
        self.frame_cpu_ms.append(1e3 * (time.thread_time() - cpu))
        self.frame_at.append(start)
        for kept in (self.frame_ms, self.frame_cpu_ms, self.frame_at):
            del kept[:-_FRAME_WINDOW]
        self._timed += 1
        if self._timed % _FRAMES_SHOWN == 0 and self.snapshot is not None:  # the readout
            self.drive_table.object = drive_html(
                self.snapshot, self.frame_ms, self.frame_cpu_ms, self.frame_at
            )

    def play(self, served: bool) -> None:
        """Start (in the drive view of a served page) or stop the periodic callback."""
        on = served and self._anim is not None and self.shown_mode == "pillar"
        if on and self._player is None:
            self._player = pn.state.add_periodic_callback(self.next_frame, period=FRAME_MS)
        elif not on and self._player is not None:
            self._player.stop()
            self._player = None

    def _update_calibration(self, snap: PillarSnapshot) -> None:
        c = snap.calibration
        if c is None:
            return
        lam, x1 = c.forcing, c.tip_deflection
        stable: dict[str, list[Any]] = {"xs": [], "ys": []}
        unstable: dict[str, list[Any]] = {"xs": [], "ys": []}
        for a, b, ok in _runs(c.stable):
            target = stable if ok else unstable
            target["xs"].append(lam[a:b])
            target["ys"].append(x1[a:b])
        self._set(self.cal_stable, stable)
        self._set(self.cal_unstable, unstable)
        self._set(self.cal_linear, {"x": lam, "y": c.linear(lam)})
        self._set(self.cal_folds, {"x": c.folds[:, 0], "y": c.folds[:, 1]})
        levels: dict[str, list[Any]] = {"x": [], "y": [], "marker": [], "label": []}
        for lv, marker in zip(ERROR_LEVELS, ("circle", "square")):
            at = c.levels[lv]
            if math.isfinite(at):
                levels["x"].append(at)
                levels["y"].append(float(np.interp(np.log(at), np.log(lam), x1)))
                levels["marker"].append(marker)
                levels["label"].append(f"{lv:.0%}")
        self._set(self.cal_levels, levels)
        lam_now = abs(snap.params.forcing)
        dots: dict[str, list[Any]] = {"x": [], "y": [], "color": []}
        if lam_now > 0.0:
            for v in snap.states:
                dots["x"].append(lam_now)
                dots["y"].append(float(v.state.tip_deflection))
                dots["color"].append(STATE_COLORS.get(v.label, "black"))
        self._set(self.cal_states, dots)
        self.cal_now.location = lam_now if lam_now > 0.0 else 1e-30
        finite = np.isfinite(x1)
        lo = min(float(np.min(x1[finite])), c.rest) if finite.any() else -1.0
        hi = max(float(np.max(x1[finite])), c.rest) if finite.any() else 1.0
        pad = 0.05 * (hi - lo or 1.0)
        rng = self.cal_fig.y_range
        if (rng.start, rng.end) != (lo - pad, hi + pad):
            rng.start, rng.end = lo - pad, hi + pad
        keep = np.isfinite(c.error) & (c.error > 0.0) & c.stable
        # the stable parts only: a NaN breaks the line over the unstable part of an S
        self._set(self.err_curve, {"x": lam, "y": np.where(keep, c.error, np.nan)})
        now_err = snap.error_at()
        ok = lam_now > 0.0 and math.isfinite(now_err) and now_err > 0.0
        color = STATE_COLORS.get(snap.states[0].label, "black") if snap.states else "black"
        self._set(self.err_now, {"x": [lam_now] if ok else [], "y": [now_err] if ok else [],
                                 "color": [color] if ok else []})  # fmt: skip
        if keep.any():
            top = max(10.0, float(np.max(c.error[keep])) * 2.0)
            bottom = max(1e-12, float(np.min(c.error[keep])) / 2.0)
            rng = self.err_fig.y_range
            if (rng.start, rng.end) != (bottom, top):
                rng.start, rng.end = bottom, top

    def sync(self, snap: PillarSnapshot) -> None:
        """Sliders and choices to the validated inputs."""
        p = snap.params
        self._syncing = True
        try:
            lo, hi = LOG_FORCING_RANGE
            if p.forcing != 0.0:
                self.forcing_slider.value = min(max(math.log10(abs(p.forcing)), lo), hi)
            self.theta0_slider.value = min(max(p.theta0, -_THETA0_MAX), _THETA0_MAX)
            self.text["height_ratio"].visible = p.profile != "sublayer"
            self.profile.value = p.profile
            self.view.value = p.view
            self.drive_controls.visible = p.view == "drive"
            if p.drive is not None:
                self.drag_model.value = p.drive.drag_model
                self.side_view.value = p.drive.side_view
                self.lissajous_controls.visible = p.drive.side_view == "lissajous"
        finally:
            self._syncing = False

    def show_mode(self, page: Any, mode: str) -> None:
        """Show the bed's or the pillar's controls and views (and the mode selector's)."""
        pillar = mode == "pillar"
        self.shown_mode = mode
        if not pillar:
            self.play(False)  # the bed's views: no animation plays
        self._syncing = True
        try:
            self.mode.value = mode
        finally:
            self._syncing = False
        for obj, on in (
            (page._bed_controls, not pillar),
            (page._bed_views, not pillar),
            (self.controls, pillar),
            (self.views, pillar),
        ):
            if obj.visible != on:
                obj.visible = on

    def place(self, page: Any, controls: Any) -> None:
        """Register the mode on the page: the mode selector on top of the controls, the
        bed's controls (but the PNG download, the link and the timing) in a column of their
        own beside the pillar's, the pillar's views beside the bed's, the pillar's fields among
        the page's."""
        keep = (page.download_png, page.link, page.status)
        page._bed_controls = pn.Column(*(o for o in controls.objects if o not in keep), margin=0)
        controls.objects = [
            pn.pane.HTML("<b>What to explore</b>", margin=(5, 10, 0, 10)),
            self.mode,
            page._bed_controls,
            self.controls,
            *keep,
        ]
        for obj in page.layout.objects:
            if isinstance(obj, pn.Row) and any(o is controls for o in obj.objects):
                page._bed_views = obj.objects[1]
                obj.append(self.views)
                break
        page.text.update(self.text)
        for w in (*self.text.values(), self.mode, self.profile, self.view, self.drag_model,
                  self.side_view):  # fmt: skip
            w.param.watch(page._on_input, "value")

    def restore(self, page: Any) -> bool:
        """After a bad link: the fields back to the view on screen. True if that is the
        pillar's (then the page's own restore is not wanted)."""
        if self.shown_mode != "pillar" or self.snapshot is None:
            self.show_mode(page, "bed")
            return False
        p = self.snapshot.params
        page._syncing = True
        try:
            for k, w in page.text.items():
                w.value = p.raw[k]
        finally:
            page._syncing = False
        self.sync(self.snapshot)
        self.show_mode(page, "pillar")
        return True

    def release(self) -> None:
        if self._player is not None:
            self._player.stop()
            self._player = None
        self._anim = None
        self._liss = None
        for kept in (self.frame_ms, self.frame_cpu_ms, self.frame_at):
            kept.clear()
        self.snapshot = None
        self._shown.clear()

    def _json_file(self) -> io.StringIO:
        assert self.snapshot is not None
        return io.StringIO(pillar_snapshot_json(self.snapshot))


def refresh_pillar(page: Any, raw: dict[str, str], notes_html: Any) -> bool:
    """The page's update in pillar mode: validate, solve, show; False on bad input (the
    library's message above the views, the last good view kept). ``notes_html``: the page's
    HTML of the library's warnings."""
    panel: PillarPanel = page.pillar
    start = time.perf_counter()
    try:
        mode_of(raw)
        params = validate_pillar(raw)
        snap = compute_pillar(params)
    except Exception as exc:
        return bool(page._failed(exc, (ValueError, TypeError)))
    solved = time.perf_counter()
    drive = params.view == "drive"
    with pn.io.hold():
        panel.update(snap)
        panel.sync(snap)
        panel.show_mode(page, "pillar")
        page._published(
            notes_html(snap.warnings),
            pillar_query(params),
            snap.timings,
            ("drive", "drive animation") if drive else ("calibration", "calibration curve"),
            (start, solved),
        )
        panel.snapshot = snap
    panel.play(bool(getattr(page, "_served", False)))
    return True
