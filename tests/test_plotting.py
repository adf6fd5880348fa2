"""Every figure function builds a Figure with the Agg backend (small grids to stay fast)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")

from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import hairbed  # noqa: E402
from hairbed import plotting  # noqa: E402

SMALL = {
    "fig_model": {},
    "fig_pendulum": {},
    "fig_phase_portrait": {"xis": (0.2, 0.9)},
    "fig_solution": {"eps_values": (0.0, 0.6), "num": 60},
    "fig_theta0s": {"theta0s": (-0.5, 0.0, 0.5), "num": 60},
    "fig_profiles": {"omega2s": (1.0, 8.0), "num": 20},
    "fig_twirling": {"omega2": 20.0},
    "fig_bistability": {"n_theta": 40, "n_eps": 4},
    "fig_hysteresis": {"num": 40},
    "fig_rheology": {"eps_values": (0.5,), "num": 30},
    "fig_calibration": {"eps_values": (0.5,), "num": 40},
    "fig_physical_units": {"num": 21, "base_angles": (0.0, 0.3)},
    "fig_fd_convergence": {"omega2s": (2.0,), "nums": (10, 20, 40)},
    "fig_speed": {"n": 200, "rows": {1, 3, 6}, "repeat": 1},
    "fig_valve": {"num": 9, "diode_angles": (0.5,)},
    "fig_pillar_calibration": {"theta0s": (0.0, -0.6), "num": 40},
    "fig_pillar_snap": {"num": 40},
    "fig_collective_stiffening": {"num": 5},
    "fig_valve_design": {"points": 3, "num": 9},
    "fig_sensor_design": {"points": 3, "num": 9},
    "fig_pillar_bode": {"num": 20},
    "fig_pillar_step": {"num": 40, "periods": 1.0},
    "fig_pillar_film": {"frames": 3, "periods": 0.5},
    "fig_valve_pump": {"num": 2, "frequency_range": (0.1, 10.0)},
    "fig_bed_moduli": {"num": 4, "forcings": (0.0,), "inertia": 0.0},
    "fig_bed_lissajous": {"strain_amplitudes": (3.0,), "num": 33},
    "fig_pipkin": {"omegas": (0.3,), "strain_amplitudes": (3.0,), "num": 33},
}


def test_every_registered_figure_is_tested():
    assert {f"fig_{name}" for name in plotting.FIGURES} == set(SMALL)
    assert len(plotting.FIGURES) >= 12


@pytest.mark.parametrize("name", sorted(SMALL))
def test_figure_builds(name):
    fig = getattr(plotting, name)(**SMALL[name])
    assert isinstance(fig, Figure)
    assert isinstance(fig.canvas, FigureCanvasAgg)
    axes = [ax for ax in fig.axes if ax.axison]
    for ax in axes:  # every visible data axes is labelled
        assert ax.get_xlabel() or ax.get_title(), name
    fig.canvas.draw()  # layout and text rendering succeed


def test_curves_are_the_exact_solution():
    """The physical curve of fig_theta0s passes through a state found by root finding."""
    fig = plotting.fig_theta0s(theta0s=(0.0,), num=400, eps=0.5)
    line = fig.axes[0].get_lines()[0]
    w, xi = line.get_xdata(), line.get_ydata()
    sol = hairbed.solve(2.0, 0.5)
    assert np.interp(sol.omega_eps, w, xi) == pytest.approx(sol.xi, abs=1e-3)


def test_hysteresis_jumps_inside_the_window():
    fig = plotting.fig_hysteresis(num=200)
    (up,) = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("ramp up")]
    x, y = up.get_xdata(), up.get_ydata()
    j = int(np.argmax(np.abs(np.diff(y))))
    # the ramp up jumps at the upper fold of theory.md §5 (omega^2 = 1.4859)
    assert x[j] <= 1.4859 <= x[j + 1]


def test_speed_figure_has_a_bar_per_row():
    """Rows given (here made up: structure only, no timing) are drawn against their targets."""
    from hairbed._benchmark import ROWS, Row

    values = {k: 0.5 * (ROWS[k][2] or 0.2) for k in ROWS}
    values["6"] = 50.0  # below its >= 100 target: a failed row
    results = [Row.of(k, v) for k, v in values.items()]
    fig = plotting.fig_speed(results=results)
    ax = fig.axes[0]
    bars = ax.patches
    assert len(bars) == len(ROWS)
    assert [t.get_text().split()[0] for t in ax.get_yticklabels()] == list(ROWS)
    widths = {k: bar.get_width() for k, bar in zip(ROWS, bars)}
    assert widths["1"] == pytest.approx(0.5)  # measured / target
    assert widths["10d"] == pytest.approx(0.2)  # reference rows: over row 10's target
    colours = {k: matplotlib.colors.to_hex(b.get_facecolor()) for k, b in zip(ROWS, bars)}
    assert colours["6"] != colours["1"] != colours["10c"] != colours["6"]
    assert ax.get_xscale() == "log"
    fig.canvas.draw()


def test_states_figure():
    fig = plotting.fig_states(hairbed.solve_all(20.0, 0.5))
    assert len(fig.axes[0].get_lines()) >= 3


def test_pillar_states_figure():
    """Each shape ends at its state's tip; the unstable middle state of the window dashed."""
    states = hairbed.solve_pillar_all(15.0, -1.4)
    fig = plotting.fig_pillar_states(states)
    lines = [ln for ln in fig.axes[0].get_lines() if len(ln.get_xdata()) > 2]
    assert [ln.get_linestyle() for ln in lines] == ["-", "--", "-"]
    for ln, st in zip(lines, states):
        assert ln.get_xdata()[-1] == pytest.approx(st.tip_deflection, abs=1e-9)
        assert ln.get_ydata()[-1] == pytest.approx(st.tip_height, abs=1e-9)


def test_make_all_writes_pngs_and_rejects_unknown_names(tmp_path):
    paths = plotting.make_all(tmp_path, dpi=40, only=["model", "fig_theta0s"], verbose=False)
    assert [p.name for p in paths] == ["model.png", "theta0s.png"]
    assert all(p.read_bytes()[:4] == b"\x89PNG" for p in paths)
    with pytest.raises(ValueError, match="unknown figure"):
        plotting.make_all(tmp_path, only=["nope"])


def test_plotting_leaves_pyplot_alone():
    code = (
        "import sys, hairbed.plotting as p\n"
        "p.fig_model()\n"
        "assert 'matplotlib.pyplot' not in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


def test_core_never_imports_matplotlib():
    code = (
        "import sys, hairbed, hairbed._core.solver, hairbed.branches, hairbed.quasistatic\n"
        "assert 'matplotlib' not in sys.modules, 'core imported matplotlib'"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=60)


# -- issue 13, item 5: parameters, ax, and the fixes that can be checked ----------------------

#: Axes each figure draws into when given ``ax`` (twirling: at least one per state).
PANELS = {
    "fig_pendulum": 2,
    "fig_phase_portrait": 2,
    "fig_solution": 3,
    "fig_bistability": 2,
    "fig_rheology": 2,
    "fig_calibration": 2,
    "fig_physical_units": 2,
    "fig_pillar_calibration": 2,
    "fig_pillar_snap": 2,
    "fig_twirling": 8,
    "fig_valve": 3,
    "fig_valve_design": 2,
    "fig_sensor_design": 2,
    "fig_pillar_bode": 2,
    "fig_pillar_film": 3,
    "fig_valve_pump": 2,
    "fig_bed_moduli": 2,
    "fig_bed_lissajous": 2,
}


@pytest.mark.parametrize("name", sorted(SMALL))
def test_figure_draws_into_given_axes(name):
    from hairbed.plotting._style import new_figure

    k = PANELS.get(name, 1)
    size = (9.0, 8.0) if name == "fig_speed" else (3.0 * k, 3.0)  # room for its row labels
    host, axes = new_figure(1, k, size=size)
    ax = axes if k == 1 else list(axes)
    fig = getattr(plotting, name)(**SMALL[name], ax=ax)
    assert fig is host
    first = axes if k == 1 else axes[0]
    assert first.has_data() or first.patches or first.lines
    fig.canvas.draw()


@pytest.mark.parametrize("name", ["fig_hysteresis", "fig_solution", "fig_calibration"])
def test_wrong_ax_is_a_type_error_naming_ax(name):
    with pytest.raises(TypeError, match="ax must be"):
        getattr(plotting, name)(**SMALL[name], ax="axes")


@pytest.mark.parametrize("name", sorted(SMALL))
def test_no_text_or_legend_outside(name):
    """Texts of an axes end inside it; legends inside the figure."""
    fig = getattr(plotting, name)(**SMALL[name])
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    fbox = fig.bbox
    for ax in fig.axes:
        box = ax.get_window_extent(renderer)
        for text in ax.texts:
            if not text.get_text() or not text.get_visible():
                continue
            ext = text.get_window_extent(renderer)
            assert box.x0 - 2 <= ext.x0 and ext.x1 <= box.x1 + 2, (name, text.get_text())
        leg = ax.get_legend()
        if leg is not None:
            ext = leg.get_window_extent(renderer)
            assert fbox.x0 - 1 <= ext.x0 and ext.x1 <= fbox.x1 + 1, name
            assert fbox.y0 - 1 <= ext.y0 and ext.y1 <= fbox.y1 + 1, name


def _labels(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_solution_weak_limit_is_its_curve_and_a_has_its_eps_key():
    fig = plotting.fig_solution(eps_values=(0.0, 0.6), num=60)
    a, b = fig.axes[0], fig.axes[1]
    assert b.get_xscale() == "log"
    (weak,) = [ln for ln in b.get_lines() if "omega_\\epsilon^2/2" in ln.get_label()]
    x, y = np.asarray(weak.get_xdata()), np.asarray(weak.get_ydata())
    assert x.size > 10  # a curve, not a straight segment on the log axis
    np.testing.assert_allclose(y, x / 2.0)
    # (a): a legend of the eps colours besides that of the line styles
    legends = [c for c in a.get_children() if isinstance(c, matplotlib.legend.Legend)]
    texts = {t.get_text() for leg in legends for t in leg.get_texts()}
    assert {r"$\epsilon = 0$", r"$\epsilon = 0.6$"} <= texts


def test_solution_weak_limit_agrees_with_the_solver():
    """The dotted curve is the weak-forcing limit of the exact branch: xi -> omega_eps^2/2."""
    s = hairbed.solve(1e-3, 0.0)
    assert float(s.xi) == pytest.approx(float(s.omega_eps) ** 2 / 2.0, rel=1e-3)


def test_pendulum_legend_covers_no_orbit():
    fig = plotting.fig_pendulum()
    fig.canvas.draw()
    ax = fig.axes[0]
    box = ax.get_legend().get_window_extent(fig.canvas.get_renderer())
    for line in ax.get_lines():
        pts = ax.transData.transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
        inside = (
            (pts[:, 0] > box.x0)
            & (pts[:, 0] < box.x1)
            & (pts[:, 1] > box.y0)
            & (pts[:, 1] < box.y1)
        )
        assert not inside.any(), line.get_label()


def test_bistability_legend_shading_and_cusp():
    fig = plotting.fig_bistability(n_theta=30, n_eps=4)
    ax = fig.axes[0]
    labels = _labels(ax)
    assert labels == [  # no entry for a table that is not drawn
        "three states (bistable)",
        r"cusp $\epsilon_c(\theta_0)$",
        "slices drawn in (b)",
    ]
    assert "slices drawn in (b)" in labels
    shade = ax.collections[0].get_paths()[0].vertices
    assert shade[:, 0].min() == pytest.approx(-np.pi / 2, abs=1e-4)
    assert shade[:, 0].max() == pytest.approx(0.0, abs=1e-12)
    assert ax.get_xlim() == pytest.approx((-np.pi / 2, 0.0))
    (cusp_line,) = [ln for ln in ax.get_lines() if "cusp" in ln.get_label()]
    assert cusp_line.get_marker() in ("None", "", None) and cusp_line.get_xdata().size >= 200
    # the smooth line is the cusp of hairbed.branches between its 30 exact nodes too
    th, ec = np.asarray(cusp_line.get_xdata()), np.asarray(cusp_line.get_ydata())
    for i in (37, 150, 333):
        assert ec[i] == pytest.approx(float(hairbed.branches.cusp(th[i])), abs=2e-3)


def test_hysteresis_middle_branch_is_dashed_and_unstable():
    from hairbed.stability import linear_stability

    fig = plotting.fig_hysteresis(num=40)
    ax = fig.axes[0]
    unstable = [ln for ln in ax.get_lines() if ln.get_gid() == "unstable"]
    stable = [ln for ln in ax.get_lines() if ln.get_gid() == "stable"]
    assert len(unstable) == 1 and len(stable) == 2
    assert unstable[0].get_linestyle() == "--"
    assert all(ln.get_linestyle() == "-" for ln in stable)
    lo, hi = hairbed.branches.bistable_window(0.9, -1.5).lower, 1.4859
    w = np.asarray(unstable[0].get_xdata())
    assert lo - 1e-6 <= w.min() and w.max() <= hi + 1e-3  # inside the window
    # an independent state in the middle, found by root finding, is unstable
    mid = hairbed.solve(0.5 * (lo + hi), 0.9, -1.5, root="mid")
    assert not linear_stability(mid, num=100, k=1).stable
    assert {"stable states", "unstable states"} <= set(_labels(ax))


def test_profiles_say_which_line_is_numerical():
    fig = plotting.fig_profiles(omega2s=(1.0,), num=20)
    ax = fig.axes[0]
    labels = _labels(ax)
    assert any(t.startswith("numerical") for t in labels)
    assert any(t.startswith("exact") for t in labels)
    assert "numerical" in _labels(ax.child_axes[0])


def test_calibration_error_axis_and_tau():
    fig = plotting.fig_calibration(eps_values=(0.5, 0.9), num=40)
    axe = fig.axes[1]
    lo, hi = axe.get_ylim()
    assert lo >= 1e-5 and hi <= 10.0  # the errors lie in (0, 1]: no empty decades above
    dashed = [ln for ln in axe.get_lines() if ln.get_linestyle() == "--" and ln.get_xdata().size]
    assert len(dashed) == 2  # the error in tau, one per eps
    # and it does not depend on eps (the same curve of x1)
    x0, y0 = dashed[0].get_xdata(), dashed[0].get_ydata()
    np.testing.assert_allclose(np.interp(x0, dashed[1].get_xdata(), dashed[1].get_ydata()), y0,
                               rtol=1e-6)  # fmt: skip


def test_calibration_tau_error_against_the_bed():
    """The relative error in tau of the figure is that of HairBed's two stress calibrations."""
    from hairbed.units import HairBed

    bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                  viscosity=1.0, spacing=400e-6)  # fmt: skip
    d = 0.3e-3
    exact = bed.wall_shear_stress_from_tip_deflection(d)
    lin = bed.linear_wall_shear_stress_from_tip_deflection(d)
    fig = plotting.fig_calibration(eps_values=(bed.eps,), num=400)
    (tau,) = [ln for ln in fig.axes[1].get_lines() if ln.get_linestyle() == "--" and
              ln.get_xdata().size]  # fmt: skip
    got = np.interp(0.3, tau.get_xdata(), tau.get_ydata())
    assert got == pytest.approx(abs(lin / exact - 1.0), rel=2e-2)


def test_physical_units_plots_displacement_and_names_the_bed():
    fig = plotting.fig_physical_units(num=21, base_angles=(0.3,), youngs_modulus=2e6)
    ax = fig.axes[0]
    assert "displacement" in ax.get_ylabel()
    line = ax.get_lines()[0]
    v, d = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    assert d[np.argmin(np.abs(v))] == pytest.approx(0.0, abs=1e-9)  # zero at rest
    text = " ".join(t.get_text() for t in ax.texts)
    assert "1 mm" in text and "2e+06 Pa" in text and "Pa s" in text


def test_rheology_log_ticks_are_plain_numbers():
    fig = plotting.fig_rheology(eps_values=(0.3, 0.9), num=30)
    ax = fig.axes[0]
    fig.canvas.draw()
    labels = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
    assert labels[:3] == ["1", "1.2", "1.5"] and "10" in labels
    assert not any("^" in t for t in labels)


def test_speed_values_fit_the_axis():
    from hairbed._benchmark import ROWS, Row

    values = {k: 0.5 * (ROWS[k][2] or 0.2) for k in ROWS}
    values["1"] = 300.0  # far beyond its target: its text needs a wider axis
    fig = plotting.fig_speed(results=[Row.of(k, v) for k, v in values.items()])
    ax = fig.axes[0]
    fig.canvas.draw()
    right = ax.get_window_extent().x1
    assert all(t.get_window_extent().x1 <= right + 1 for t in ax.texts)
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert any("-1.5" in t for t in labels)  # row 2 says it includes theta0 < 0


def test_figure_parameters_and_settings():
    assert plotting.parameters("hysteresis") == {"eps": 0.9, "theta0": -1.5, "num": 240}
    got = plotting.parse_settings(["eps=0.95", "theta0=-1.2", "num=30"], only=["hysteresis"])
    assert got == {"hysteresis": {"eps": 0.95, "theta0": -1.2, "num": 30}}
    tup = plotting.parse_settings(["eps_values=0.3,0.9"], only=["rheology", "solution"])
    assert tup == {"solution": {"eps_values": (0.3, 0.9)}, "rheology": {"eps_values": (0.3, 0.9)}}
    for bad, words in [
        (["eps"], "KEY=VALUE"),
        (["nope=1"], "no figure"),
        (["num=1.5"], "integer"),
        (["eps=x"], "number"),
    ]:
        with pytest.raises(ValueError, match=words):
            plotting.parse_settings(bad, only=["hysteresis"])


@pytest.mark.parametrize(
    ("name", "kwargs"),
    [
        ("fig_hysteresis", {"eps": 0.5, "theta0": 0.2}),  # no window
        ("fig_hysteresis", {"num": 0}),
        ("fig_solution", {"num": -3}),
        ("fig_physical_units", {"max_velocity": -1.0}),
        ("fig_valve", {"max_flow_rate": 0.0}),
        ("fig_model", {"eps": 0.0}),
        ("fig_pendulum", {"omega2": 0.0}),
        ("fig_fd_convergence", {"nums": (10, 1)}),
        ("fig_pillar_calibration", {"forcing_min": 0.0}),
        ("fig_pillar_snap", {"num": 3}),
    ],
)
def test_figure_parameters_are_checked(name, kwargs):
    with pytest.raises(ValueError) as info:
        getattr(plotting, name)(**kwargs)
    message = str(info.value)
    assert any(k in message for k in (*kwargs, "window", "nums[1]")), message


def test_figures_command_passes_settings(tmp_path):
    cmd = [
        sys.executable,
        "-m",
        "hairbed",
        "figures",
        "--out",
        str(tmp_path),
        "--only",
        "hysteresis",
        "model",
        "--set",
        "eps=0.95",
        "--set",
        "theta0=-1.2",
        "--dpi",
        "40",
    ]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hysteresis.png", "model.png"]
    bad = subprocess.run([*cmd[:-2], "--set", "eps=1.5"], capture_output=True, text=True,
                         timeout=300)  # fmt: skip
    assert bad.returncode == 2
    lines = bad.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: ") and "eps" in lines[0]
    assert "Traceback" not in bad.stderr


def test_valve_marks_every_state_the_folds_and_the_jumps():
    """fig_valve: the curve dashed exactly between the folds of valve_states, an arrow per
    jump of the two ramps (from the fold to the landing state), every state of panel (b) the
    states of valve_states, and the diodicity of (c) that of hairbed.valve.diodicity."""
    from matplotlib.patches import FancyArrowPatch

    from hairbed.valve import valve_states

    fig = plotting.fig_valve(num=9, diode_angles=(0.5,))
    axq, axh, _ = fig.axes
    bed = hairbed.HairBed(
        length=1.6e-3,
        radius=50e-6,
        youngs_modulus=1e6,
        channel_height=2e-3,
        viscosity=1.0,
        spacing=400e-6,
        base_angle=-1.2,
    )
    s = valve_states(bed, 0.01, flow_rate=np.linspace(-3e-6, 3e-6, 17))  # both directions
    dashed = next(ln for ln in axq.get_lines() if ln.get_gid() == "unstable")
    x = np.asarray(dashed.get_xdata())[np.isfinite(np.asarray(dashed.get_ydata(), dtype=float))]
    lo, hi = np.sort(s.fold_pressure_drop)
    assert lo - 10.0 < x.min() and x.max() < hi + 10.0 and x.max() - x.min() > 0.9 * (hi - lo)
    arrows = [p for p in axq.patches if isinstance(p, FancyArrowPatch)]
    assert len(arrows) == len(s.ramp_up.jumps) + len(s.ramp_down.jumps) == 2
    points = sum(
        np.asarray(ln.get_xdata()).size for ln in axh.get_lines() if ln.get_marker() == "o"
    )
    assert points == int(s.count.sum())
    # both directions (issue 33): backward flow at negative drops, in both panels
    curve = next(ln for ln in axq.get_lines() if ln.get_gid() == "stable")
    xq, yq = np.asarray(curve.get_xdata()), np.asarray(curve.get_ydata(), dtype=float)
    assert xq.min() < 0 and np.nanmin(yq) < -2.9 and np.nanmax(yq) > 2.9
    assert np.all(
        np.sign(yq[np.isfinite(yq) & (xq != 0)]) == np.sign(xq[np.isfinite(yq) & (xq != 0)])
    )
    assert min(np.min(ln.get_xdata()) for ln in axh.get_lines() if ln.get_marker() == "o") < 0


def _legend_texts(ax) -> list[str]:
    legend = ax.get_legend()
    return [] if legend is None else [t.get_text() for t in legend.get_texts()]


def test_valve_legend_lists_only_what_the_bed_has():
    """A bed leaning with the forward flow (theta0 = 0.5) has one state at every flow rate
    (valve_states, computed here): no folds, no unstable state, no jumps, no window, and the
    legends say none of them; the bistable default bed lists each of them."""
    from hairbed.valve import valve_states

    kw = dict(num=9, diode_angles=(0.5,))
    bed = hairbed.HairBed(length=1.6e-3, radius=50e-6, youngs_modulus=1e6,
                          channel_height=2e-3, viscosity=1.0, spacing=400e-6,
                          base_angle=0.5)  # fmt: skip
    s = valve_states(bed, 0.01, flow_rate=np.linspace(-3e-6, 3e-6, 17))
    assert s.fold_pressure_drop.size == 0 and np.all(s.count == 1) and np.all(s.stable[:, 0])
    assert not s.ramp_up.jumps and not s.ramp_down.jumps
    axq, axh, _ = plotting.fig_valve(base_angle=0.5, **kw).axes
    words = " ".join(_legend_texts(axq) + _legend_texts(axh))
    for absent in ("fold", "unstable", "jump", "three states", "ramp"):
        assert absent not in words, words
    assert "stable at the set flow rate" in words
    axq, axh, _ = plotting.fig_valve(**kw).axes  # the bistable bed: every item
    words = " ".join(_legend_texts(axq) + _legend_texts(axh))
    for present in ("folds", "unstable", "and its jump", "three states"):
        assert present in words, words


def test_pillar_calibration_marks_where_the_linear_error_reaches_1_and_10_percent():
    """The marked forcings, solved here: the linear formula 11 Lambda cos^3(theta0)/120 reads
    a forcing 1 % (10 %) off there (to the figure's interpolation between grid points)."""
    fig = plotting.fig_pillar_calibration(theta0s=(0.0, -0.6), num=200)
    axe = fig.axes[1]
    gamma = gray_hancock(20.0)  # the figure's pillar: L/a = 20 by default (issue 33)
    assert f"{gamma:.3f}" in fig.axes[0].get_title() and "L/a = 20" in fig.axes[0].get_title()
    for t0, color in ((0.0, "C0"), (-0.6, "C3")):
        marks = [ln for ln in axe.get_lines() if len(ln.get_xdata()) == 1
                 and ln.get_color() == color]  # fmt: skip
        assert len(marks) == 2
        for ln, level in zip(marks, (0.01, 0.1)):
            lam = float(ln.get_xdata()[0])
            st = hairbed.solve_pillar(lam, t0, gamma=gamma)
            read = (st.tip_deflection - np.sin(t0)) / (11.0 * np.cos(t0) ** 3 / 120.0)
            assert abs(read - lam) / lam == pytest.approx(level, rel=0.02)
    # the linear formula is the small-deflection slope of the solver (theory.md §12), whatever
    # gamma (the tangential drag only compresses a straight pillar)
    for t0 in (0.0, -0.6):
        for g in (0.5, gamma):
            slope = hairbed.solve_pillar(0.0, t0, gamma=g).tip_deflection_slope
            assert slope == pytest.approx(11.0 * np.cos(t0) ** 3 / 120.0, rel=1e-10)


def gray_hancock(slenderness: float) -> float:
    """gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1) (theory.md §12), written here."""
    ln = np.log(2.0 * slenderness)
    return float((ln + 0.5) / (2.0 * ln - 1.0))


def test_pillar_snap_marks_the_folds_and_dashes_the_unstable_part():
    fig = plotting.fig_pillar_snap(num=100)
    ax, axs = fig.axes
    folds = next(ln for ln in ax.get_lines() if ln.get_label() == "folds")
    lam = np.sort(folds.get_xdata())
    gamma = gray_hancock(20.0)  # the pillar's own slenderness, L/a = 20 (issue 33)
    assert f"{gamma:.3f}" in ax.get_title()
    br = hairbed.continue_pillar(40.0, -1.4, gamma=gamma)
    assert lam == pytest.approx(np.sort(np.asarray(br.folds)[:, 0]), rel=1e-9)
    assert lam == pytest.approx([13.9, 16.45], abs=0.3)  # near gamma = 1/2's 13.7 and 16.0
    dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--" and len(ln.get_xdata())]
    assert len(dashed) == 1  # the middle part of the S, between the folds
    x = dashed[0].get_xdata()
    assert lam[0] - 0.5 <= x.min() and x.max() <= lam[1] + 0.5
    assert len([ln for ln in axs.get_lines() if len(ln.get_xdata()) > 2]) == 3  # three states


def test_valve_result_draws_what_the_valve_command_computed():
    """fig_valve_result (hairbed valve --plot): the empty channel is dp H^3/(12 eta l) (the
    closed form, here), the curve passes through valve_curve's points; the states' panel
    holds every state of valve_states once, the folds only where there are folds."""
    from hairbed.valve import diodicity, valve_curve, valve_states

    bed = hairbed.HairBed(length=1.6e-3, radius=50e-6, youngs_modulus=1e6,
                          channel_height=2e-3, viscosity=1.0, spacing=400e-6,
                          base_angle=-1.2)  # fmt: skip
    drops = np.array([-100.0, -10.0, 10.0, 100.0])
    axq, axh = plotting.fig_valve_result(valve_curve(bed, drops, 0.01)).axes
    empty = next(ln for ln in axq.get_lines() if ln.get_linestyle() == ":")
    np.testing.assert_allclose(empty.get_ydata(), drops * 2e-3**3 / (12 * 1.0 * 0.01) * 1e6,
                               rtol=1e-13)  # fmt: skip
    q = axq.get_lines()[0].get_ydata()
    assert [v < 0 for v in q] == [True, True, False, False]
    s = valve_states(bed, 0.01, flow_rate=np.linspace(-3e-6, 3e-6, 9))
    axq, axh = plotting.fig_valve_result(s).axes
    dots = [ln for ln in axh.get_lines() if ln.get_marker() == "o"]
    assert sum(len(ln.get_xdata()) for ln in dots) == int(s.count.sum())
    words = [t.get_text() for t in axq.get_legend().get_texts()]
    assert ("folds" in words) == (s.fold_pressure_drop.size > 0) and "folds" in words
    with_flow = valve_states(bed.__class__(**{**bed_kwargs(bed), "base_angle": 0.5}), 0.01,
                             flow_rate=np.linspace(-3e-6, 3e-6, 9))  # fmt: skip
    axq, _ = plotting.fig_valve_result(with_flow).axes
    words = " ".join(t.get_text() for t in axq.get_legend().get_texts())
    assert "folds" not in words and "unstable" not in words
    (axd,) = plotting.fig_valve_result(diodicity(bed, [10.0, 100.0], 0.01)).axes
    assert len(axd.get_lines()[0].get_xdata()) == 2
    with pytest.raises(TypeError, match="ValveCurve, Diodicity or ValveStates"):
        plotting.fig_valve_result(bed)


def bed_kwargs(bed) -> dict:
    return {k: getattr(bed, k) for k in ("length", "radius", "youngs_modulus",
                                         "channel_height", "viscosity", "spacing")}  # fmt: skip


def test_pillar_snap_says_when_forcing_max_cuts_the_branch_before_its_folds():
    """forcing_max = 15 stops the branch from rest below its upper fold (16.45 at L/a = 20):
    a UserWarning and a note in the panel name the folds it would reach; no fold, no
    unstable part and no window are drawn or named in the legend."""
    with pytest.warns(UserWarning, match=r"forcing_max = 15 stops the branch before its fold"):
        fig = plotting.fig_pillar_snap(num=60, forcing_max=15.0)
    ax = fig.axes[0]
    assert any("raise forcing_max" in t.get_text() for t in ax.texts)
    words = [t.get_text() for t in ax.get_legend().get_texts()]
    assert words == ["stable"]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the whole branch: no warning
        plotting.fig_pillar_snap(num=60, forcing_max=40.0)


def test_pillar_figures_take_the_slenderness_and_refuse_a_bad_one():
    fig = plotting.fig_pillar_calibration(theta0s=(0.0,), num=20, slenderness=100.0)
    assert f"{gray_hancock(100.0):.3f}" in fig.axes[0].get_title()
    with pytest.raises(ValueError, match="slenderness"):
        plotting.fig_pillar_snap(num=20, slenderness=1.0)


def test_set_theta0_is_the_one_slice_of_the_bistability_figure(tmp_path):
    """--set theta0=X is not ignored by the figures that draw several base angles: it is
    their one slice theta0s=(X,), unless theta0s is set; a slice without a window is refused
    by name and index (issue 33, Ranges and sweeps)."""
    from hairbed.branches import bistable_window, cusp

    got = plotting.parse_settings(["theta0=-1.2"], only=["bistability", "hysteresis"])
    assert got == {"bistability": {"theta0s": (-1.2,)}, "hysteresis": {"theta0": -1.2}}
    got = plotting.parse_settings(["theta0=-1.2", "theta0s=-1,-0.5"], only=["bistability"])
    assert got == {"bistability": {"theta0s": (-1.0, -0.5)}}
    fig = plotting.fig_bistability(n_theta=6, n_eps=5, **got["bistability"])
    fig = plotting.fig_bistability(n_theta=6, n_eps=5, theta0s=(-1.2,))
    ax, axw = fig.axes
    assert [t.get_text() for t in axw.get_legend().get_texts()] == [r"$\theta_0 = -1.2$", "cusp"]
    slice_ = next(ln for ln in ax.get_lines() if ln.get_xdata()[0] == -1.2)
    assert slice_.get_ydata()[0] == pytest.approx(float(cusp(-1.2)), rel=1e-12)
    lower = [ln for ln in axw.get_lines() if len(ln.get_xdata()) == 5][0]
    e, w = lower.get_xdata()[2], lower.get_ydata()[2]
    assert w == pytest.approx(bistable_window(e, -1.2).lower, rel=1e-12)
    for bad in (0.3, -0.2, -1.6):
        with pytest.raises(ValueError, match=r"theta0s\[0\] = "):
            plotting.fig_bistability(n_theta=3, n_eps=3, theta0s=(bad,))
    from hairbed.cli import main

    assert main(["figures", "--only", "bistability", "--set", "theta0=0.3", "--out",
                 str(tmp_path), "--quiet"]) == 2  # fmt: skip
