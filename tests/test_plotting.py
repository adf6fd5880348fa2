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
    "fig_bistability": {"n_theta": 3, "n_eps": 4},
    "fig_hysteresis": {"num": 40},
    "fig_rheology": {"eps_values": (0.5,), "num": 30},
    "fig_calibration": {"eps_values": (0.5,), "num": 40},
    "fig_physical_units": {},
    "fig_fd_convergence": {"omega2s": (2.0,), "nums": (10, 20, 40)},
    "fig_speed": {"n": 200, "rows": {1, 3, 6}, "repeat": 1},
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
    up = fig.axes[0].get_lines()[1]
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
