"""Figures beyond the paper: bistability, hysteresis, rheology, calibration, numerics, speed.

Each function returns a :class:`matplotlib.figure.Figure`. Every quantity comes from the
public API (:func:`hairbed.solve`, the lab modules ``hairbed.branches``, ``hairbed.rheology``
...): the figures compute nothing of their own.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import FancyArrowPatch, Patch

import hairbed

from ._style import colors, new_figure, styled

__all__ = [
    "fig_bistability",
    "fig_calibration",
    "fig_fd_convergence",
    "fig_hysteresis",
    "fig_physical_units",
    "fig_rheology",
    "fig_speed",
    "fig_states",
    "fig_twirling",
]

# Windows of omega^2 with three physical states (theory.md §5), as (theta0, eps).
_TABLE = ((-1.5, 0.9), (-1.0, 0.95), (-0.5, 0.99))


def _window(eps: float, theta0: float) -> tuple[float, float]:
    """Bistable window of omega^2, (lower, upper) (NaNs when there is none)."""
    w = hairbed.branches.bistable_window(eps, theta0)
    return w.lower, w.upper


@styled
def fig_bistability(n_theta: int = 12, n_eps: int = 24) -> Figure:
    """Where the hair has three physical states: the cusp and the windows of forcing.

    (a) The cusp eps_c(theta0) in the (theta0, eps) plane: above it (shaded) the physical
    branch folds and a window of omega^2 with three states opens. (b) That window against eps
    for two base angles (shaded between the lower and upper folds).

    Examples
    --------
    >>> fig = fig_bistability(n_theta=3, n_eps=3)
    >>> len(fig.axes)
    2
    """
    from hairbed.branches import cusp

    fig, (ax, axw) = new_figure(1, 2, size=(9.4, 3.9))
    th = np.linspace(-1.5, -0.2, n_theta)
    ec = np.asarray(cusp(th), dtype=float)
    ax.fill_between(th, ec, 1.0, color="C1", alpha=0.3, lw=0, label="three states (bistable)")
    ax.plot(th, ec, "k-", marker="o", ms=3, label=r"cusp $\epsilon_c(\theta_0)$")
    for k, (t0, e0) in enumerate(_TABLE):
        ax.plot(
            t0, e0, "s", color="C3", ms=5, label="windows of (b) and table" if k == 0 else None
        )
    ax.set_xlim(-np.pi / 2, 0.05)
    ax.set_ylim(0.4, 1.0)
    ax.set_xlabel(r"base angle $\theta_0$ [rad]")
    ax.set_ylabel(r"confinement $\epsilon = L/H$ [-]")
    ax.set_title("(a) bistable region (hair leaning into the flow)")
    ax.legend(loc="lower right")
    for t0, c in zip((-1.5, -1.0), ("C0", "C3")):
        e_c = float(cusp(t0))
        eps = np.linspace(e_c + 1e-3, 0.985, n_eps)
        win = np.array([_window(e, t0) for e in eps])
        axw.fill_between(eps, win[:, 0], win[:, 1], color=c, alpha=0.3, lw=0)
        axw.plot(eps, win[:, 0], color=c, lw=1.2)
        axw.plot(eps, win[:, 1], color=c, lw=1.2, label=rf"$\theta_0 = {t0:g}$")
        axw.plot(e_c, np.nanmean(win[0]), "k*", ms=7)
    axw.plot([], [], "k*", ms=7, label="cusp")
    axw.set_xlabel(r"confinement $\epsilon$ [-]")
    axw.set_ylabel(r"forcing $\omega^2$ [-]")
    axw.set_title(r"(b) window of $\omega^2$ with three states")
    axw.legend(loc="center right")
    return fig


@styled
def fig_hysteresis(eps: float = 0.9, theta0: float = -1.5, num: int = 240) -> Figure:
    """Hysteresis loop of the tip deflection under a slow ramp of the forcing up and down.

    The dotted curve is the whole physical branch (its middle, between the folds, is
    unstable); the ramp up follows the low state to the upper fold and jumps, the ramp down
    follows the high state to the lower fold and jumps back.

    Examples
    --------
    >>> fig = fig_hysteresis(num=40)
    >>> len(fig.axes)
    1
    """
    lo, hi = _window(eps, theta0)
    up = np.linspace(0.3 * lo, 1.4 * hi, num)
    down = up[::-1]
    sweep = hairbed.quasistatic.sweep
    s_up, s_down = sweep(up, eps, theta0, start="low"), sweep(down, eps, theta0, start="high")
    x_up, x_down = np.asarray(s_up.tip_deflection), np.asarray(s_down.tip_deflection)
    branch = hairbed.from_parameter(np.linspace(-12, 6, 1200), eps, theta0)
    fig, ax = new_figure(size=(5.8, 4.2))
    ax.axvspan(lo, hi, color="0.9", lw=0, label="three states")
    ax.plot(
        branch.omega2,
        branch.tip_deflection,
        ":",
        color="0.3",
        lw=1.2,
        label="physical branch (all states)",
    )
    ax.plot(up, x_up, "-", color="C3", lw=3.2, alpha=0.7, label=r"ramp up ($\omega^2\uparrow$)")
    ax.plot(down, x_down, "-", color="C0", lw=1.6, label=r"ramp down ($\omega^2\downarrow$)")
    for xs, ws, c in ((x_up, up, "C3"), (x_down, down, "C0")):
        j = int(np.nanargmax(np.abs(np.diff(xs))))  # the jump is the largest step
        ax.add_patch(
            FancyArrowPatch(
                (ws[j], xs[j]),
                (ws[j], xs[j + 1]),
                arrowstyle="-|>",
                mutation_scale=14,
                color=c,
                lw=1.2,
            )
        )
    ax.set_xlim(up[0], up[-1])
    ax.set_xlabel(r"forcing $\omega^2$ [-]")
    ax.set_ylabel(r"tip deflection $x_1/L$ [-]")
    ax.set_title(rf"Hysteresis, $\epsilon = {eps:g}$, $\theta_0 = {theta0:g}$")
    ax.legend(loc="upper left")
    return fig


@styled
def fig_rheology(
    eps_values: tuple[float, ...] = (0.3, 0.6, 0.9), theta0: float = 0.5, num: int = 200
) -> Figure:
    """Wall stress of the bed against forcing: stress ratio and rectification.

    (a) tau / (eta v / H) = 1/(1 - eps h1) for upright hairs: the bed lies down and the gap
    opens, so the stress falls from 1/(1 - eps) towards 1. (b) With a base angle the bed is a
    rectifier: flow against the grain sees more stress than flow with it at the same speed.

    Examples
    --------
    >>> fig = fig_rheology(eps_values=(0.5,), num=20)
    >>> len(fig.axes)
    2
    """
    w2 = np.logspace(-2, 3, num)
    fig, (ax, axr) = new_figure(1, 2, size=(9.4, 3.9))
    for eps, c in zip(eps_values, colors(len(eps_values))):
        ax.plot(
            w2,
            hairbed.rheology.stress_ratio(w2, eps, 0.0),
            color=c,
            label=rf"$\epsilon = {eps:g}$",
        )
        ax.axhline(1 / (1 - eps), color=c, lw=0.7, ls=":")
        axr.plot(
            w2,
            hairbed.rheology.rectification_ratio(w2, eps, theta0),
            color=c,
            label=rf"$\epsilon = {eps:g}$",
        )
    ax.axhline(1.0, color="0.5", lw=0.7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"forcing $\omega^2$ [-]")
    ax.set_ylabel(r"stress ratio $\tau/(\eta v/H) = 1/(1-\epsilon h_1)$")
    ax.set_title(r"(a) stress ratio, $\theta_0 = 0$ (dotted: at rest)")
    ax.legend(loc="upper right")
    axr.axhline(1.0, color="0.5", lw=0.7)
    axr.set_xscale("log")
    axr.set_xlabel(r"forcing $\omega^2$ at $|v|$ [-]")
    axr.set_ylabel(r"$\tau_{\mathrm{against}}/\tau_{\mathrm{with}}$ [-]")
    axr.set_title(rf"(b) rectification, $\theta_0 = {theta0:g}$ rad")
    axr.legend(loc="upper left")
    return fig


@styled
def fig_calibration(
    eps_values: tuple[float, ...] = (0.0, 0.5, 0.9), theta0: float = 0.0, num: int = 400
) -> Figure:
    """Sensor calibration: forcing read from the tip deflection, exact and linear.

    (a) omega^2 against the measured x1 (exact branch curve, solid) and the small-deflection
    cantilever line (dashed). (b) Relative error of the linear calibration.

    Examples
    --------
    >>> fig = fig_calibration(eps_values=(0.5,), num=30)
    >>> len(fig.axes)
    2
    """
    t = np.linspace(-12.0, 30.0, num)
    fig, (ax, axe) = new_figure(1, 2, size=(9.4, 3.9))
    for eps, c in zip(eps_values, colors(len(eps_values))):
        s = hairbed.from_parameter(t, eps, theta0)
        x1, w2 = np.asarray(s.tip_deflection), np.asarray(s.omega2)
        lin = (x1 - np.sin(theta0)) / hairbed.inverse.tip_deflection_slope(eps, theta0)
        ax.plot(x1, w2, color=c, label=rf"exact, $\epsilon = {eps:g}$")
        ax.plot(x1, lin, "--", color=c, lw=1.1)
        axe.plot(x1, np.abs(lin - w2) / w2, color=c, label=rf"$\epsilon = {eps:g}$")
    ax.plot([], [], "--", color="0.4", lw=1.1, label="linear (cantilever)")
    ax.set_yscale("log")
    ax.set_xlim(0, 1)
    ax.set_ylim(1e-3, 1e3)
    ax.set_xlabel(r"measured tip deflection $x_1/L$ [-]")
    ax.set_ylabel(r"forcing $\omega^2 \propto v$ [-]")
    ax.set_title(rf"(a) calibration curve, $\theta_0 = {theta0:g}$")
    ax.legend(loc="lower right")
    axe.axhline(0.01, color="0.5", lw=0.7, ls=":")
    axe.text(0.98, 0.006, "1 %", color="0.4", fontsize=8, ha="right", va="top")
    axe.set_yscale("log")
    axe.set_xlim(0, 1)
    axe.set_ylim(1e-6, 1e2)
    axe.set_xlabel(r"measured tip deflection $x_1/L$ [-]")
    axe.set_ylabel(r"relative error of linear $\omega^2$ [-]")
    axe.set_title("(b) error of the linear calibration")
    axe.legend(loc="lower right")
    return fig


@styled
def fig_fd_convergence(
    omega2s: tuple[float, ...] = (0.5, 2.0, 8.0, 32.0),
    nums: tuple[int, ...] = (10, 20, 40, 80, 160, 320, 640),
    eps: float = 0.5,
) -> Figure:
    """Second-order convergence of the paper's finite differences to the exact tip height.

    Examples
    --------
    >>> fig = fig_fd_convergence(omega2s=(1.0,), nums=(10, 20))
    >>> len(fig.axes)
    1
    """
    from hairbed.numerics import finite_difference

    Ns_arr = np.asarray(nums, dtype=float)
    fig, ax = new_figure(size=(5.6, 4.2))
    for w2, c in zip(omega2s, colors(len(omega2s), "plasma")):
        exact = hairbed.solve(w2, eps).tip_height
        err = [abs(finite_difference(w2, eps, num=int(n)).tip_height - exact) for n in nums]
        ax.loglog(Ns_arr, err, "o-", color=c, ms=4, label=rf"$\omega^2 = {w2:g}$")
    ref = 0.3 * Ns_arr[0] ** 2 * Ns_arr**-2.0 * max(1e-12, ax.get_ylim()[1] * 1e-1)
    ax.loglog(Ns_arr, ref, "k--", lw=1, label=r"$\propto N^{-2}$")
    ax.set_xlabel(r"segments $N$")
    ax.set_ylabel(r"$|h_1^{\mathrm{FD}} - h_1^{\mathrm{exact}}|$ [-]")
    ax.set_title(rf"Finite-difference convergence, $\epsilon = {eps:g}$")
    ax.legend(loc="lower left")
    return fig


def _row_group(number: str) -> str:
    """The row of a sub-row ("10e" -> "10"): a reference sub-row is scaled by its target."""
    return number.rstrip("abcdefghijklmnopqrstuvwxyz")


@styled
def fig_speed(
    n: int = 100_000,
    rows: Iterable[int] | None = None,
    results: Sequence[Any] | None = None,
    repeat: int = 3,
) -> Figure:
    """Every row of the speed table (``benchmarks/bench_solve.py``, ``hairbed bench``) as its
    measured value over its target, on a log axis: a bar per row, the target at 1, green when
    it is met and red when not (grey: reference rows without a target, scaled by the target
    of their row).

    The rows are measured here by the same code, ``hairbed._benchmark.run(quick=True)``, with
    batch size ``n`` (only ``rows``, 1 to 10, if given); or passed in as ``results``, rows
    of an earlier run.

    Examples
    --------
    >>> fig = fig_speed(n=100, rows={1, 4}, repeat=1)
    >>> len(fig.axes), len(fig.axes[0].patches)
    (1, 2)
    """
    measured = results is None
    if results is None:
        from hairbed import _benchmark

        results = _benchmark.run(quick=True, rows=rows, n=n, repeat=repeat)
    scale = {_row_group(r.number): r.target for r in results if r.target is not None}
    shown = [r for r in results if scale.get(_row_group(r.number)) or r.target]
    ratios = np.array([r.value / (r.target or scale[_row_group(r.number)]) for r in shown])
    fig, ax = new_figure(size=(7.2, 0.8 + 0.36 * max(len(shown), 1)))
    if not shown:
        ax.set_xlabel("measured / target")
        ax.set_title("Speed: no rows measured")
        return fig
    cols = ["0.65" if r.passed is None else "C2" if r.passed else "C3" for r in shown]
    y = np.arange(len(shown))
    ratios = np.maximum(ratios, 1e-6)  # log axis: a zero memory delta still shows
    ax.barh(y, ratios, color=cols, height=0.6)
    ax.axvline(1.0, color="k", lw=1.0, ls="--", zorder=1)
    ax.plot(np.ones(len(shown)), y, "k|", ms=12, mew=2)
    for i, (r, q) in enumerate(zip(shown, ratios)):
        target = "" if r.target is None else f" ({r.op} {r.target:g})"
        text = f"{r.value:.3g} {r.unit}{target}"
        ax.text(max(q, 1.0) * 1.25, i, text, va="center", fontsize=7)
    ax.set_yticks(y, [f"{r.number}  {r.label}" for r in shown], fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlim(min(ratios.min(), 1.0) / 3, max(ratios.max(), 1.0) * 30)
    ax.set_xlabel("measured / target (target at 1)")
    handles = [Patch(color=c, label=t) for c, t in (("C2", "met"), ("C3", "not met"))]
    if any(r.passed is None for r in shown):
        handles.append(Patch(color="0.65", label="reference"))
    ax.legend(handles=handles, loc="lower right", fontsize=7)
    sizes = " (quick sizes)" if measured else ""
    ax.set_title(f"Speed table: every row against its target{sizes}")
    return fig


@styled
def fig_twirling(omega2: float = 200.0, eps: float = 0.5) -> Figure:
    """Every solution at one forcing: the physical hair and the twirling branches.

    Examples
    --------
    >>> fig = fig_twirling(omega2=20.0)
    >>> len(fig.axes) >= 3
    True
    """
    sols = sorted(hairbed.solve_all(omega2, eps), key=lambda s: (s.n, -s.sign))
    k = len(sols)
    ncols = min(k, 4)
    nrows = int(np.ceil(k / ncols))
    fig, axes = new_figure(nrows, ncols, size=(2.3 * ncols, 2.3 * nrows + 0.4), squeeze=False)
    for ax, s in zip(axes.flat, sols):
        x, z = s.profile(400)
        ax.plot(x, z, "-" if s.sign > 0 else "--", color="k" if s.physical else "C0", lw=1.6)
        ax.axhline(0, color="0.5", lw=0.8)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(rf"sign ${s.sign:+d}$, $n = {s.n}$, $\xi = {s.xi:.3f}$", fontsize=8.5)
        ax.tick_params(labelsize=7)
    for ax in axes.flat[k:]:
        ax.axis("off")
    fig.suptitle(
        rf"All states at $\omega^2 = {omega2:g}$, $\epsilon = {eps:g}$ "
        r"(axes $x/L$, $z/L$; physical in black)",
        fontsize=10,
    )
    return fig


@styled
def fig_physical_units() -> Figure:
    """A real bed in SI units: tip deflection and wall shear stress against wall speed.

    Soft 1 mm hairs (E = 1 MPa, radius 50 um, spacing 400 um) under 2 mm of glycerol, with
    and without a base angle, for flow with and against the grain.

    Examples
    --------
    >>> fig = fig_physical_units()
    >>> len(fig.axes)
    2
    """
    from hairbed.units import HairBed

    v = np.linspace(-0.5, 0.5, 201)
    fig, (ax, axs) = new_figure(1, 2, size=(9.4, 3.9))
    for th0, c in ((0.0, "k"), (0.3, "C3")):
        bed = HairBed(
            length=1e-3,
            radius=50e-6,
            youngs_modulus=1e6,
            channel_height=2e-3,
            viscosity=1.0,
            spacing=400e-6,
            base_angle=th0,
        )
        st = bed.deform(v)
        ax.plot(
            v * 100,
            np.asarray(st.tip_deflection) * 1e6,
            color=c,
            label=rf"$\theta_0 = {th0:g}$ rad",
        )
        axs.plot(
            v * 100, np.asarray(st.wall_shear_stress), color=c, label=rf"$\theta_0 = {th0:g}$ rad"
        )
    axs.plot(v * 100, 1.0 * v / 2e-3, ":", color="0.5", label=r"no hairs, $\eta v/H$")
    ax.set_xlabel(r"wall speed $v$ [cm/s]")
    ax.set_ylabel(r"tip deflection $x_1 L$ [$\mu$m]")
    ax.set_title("(a) tip deflection")
    ax.legend(loc="upper left")
    axs.set_xlabel(r"wall speed $v$ [cm/s]")
    axs.set_ylabel(r"wall shear stress $\tau$ [Pa]")
    axs.set_title("(b) wall shear stress")
    axs.legend(loc="upper left")
    return fig


@styled
def fig_states(solutions: list) -> Figure:
    """Profiles of a few states (used by ``hairbed solve --plot``).

    Examples
    --------
    >>> fig = fig_states([hairbed.solve(2.0, 0.5)])
    >>> fig.axes[0].get_xlabel()
    '$x/L$'
    """
    fig, ax = new_figure(size=(7.0, 3.8))
    for i, s in enumerate(solutions):
        c = f"C{i % 10}"
        x, z = s.profile(400)
        ax.plot(
            x,
            z,
            "-" if s.sign > 0 else "--",
            color=c,
            label=rf"sign ${s.sign:+d}$, $n = {s.n}$, $x_1 = {s.tip_deflection:.3f}$",
        )
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(r"$x/L$")
    ax.set_ylabel(r"$z/L$")
    if solutions:
        s = solutions[0]
        ax.set_title(
            rf"$\omega^2 = {s.omega2:g}$, $\epsilon = {s.eps:g}$, "
            rf"$\theta_0 = {s.theta0:g}$"
        )
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7.5)
    return fig
