"""Figures beyond the paper: bistability, hysteresis, rheology, calibration, numerics, speed,
and isolated pillars (their calibration curve and snap-through).

Each function returns a :class:`matplotlib.figure.Figure`. Every quantity comes from the
public API (:func:`hairbed.solve`, the lab modules ``hairbed.branches``, ``hairbed.rheology``
...): the figures compute nothing of their own.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import FancyArrowPatch, Patch

import hairbed

from .._core.validation import check_int
from ._style import MAX_POINTS, colors, figure_axes, new_figure, styled

__all__ = [
    "fig_bistability",
    "fig_calibration",
    "fig_fd_convergence",
    "fig_hysteresis",
    "fig_physical_units",
    "fig_pillar_calibration",
    "fig_pillar_snap",
    "fig_pillar_states",
    "fig_rheology",
    "fig_speed",
    "fig_states",
    "fig_twirling",
    "fig_valve",
    "fig_valve_result",
]

# Windows of omega^2 with three physical states (theory.md §5), as (theta0, eps).
_TABLE = ((-1.5, 0.9), (-1.0, 0.95), (-0.5, 0.99))


def _window(eps: float, theta0: float) -> tuple[float, float]:
    """Bistable window of omega^2, (lower, upper) (NaNs when there is none)."""
    w = hairbed.branches.bistable_window(eps, theta0)
    return float(w.lower), float(w.upper)


@styled
def fig_bistability(
    n_theta: int = 40, n_eps: int = 24, theta0s: tuple[float, ...] = (-1.5, -1.0), ax: Any = None
) -> Figure:
    """Where the hair has three physical states: the cusp and the windows of forcing.

    (a) The cusp eps_c(theta0) over the whole range of base angles leaning into the flow,
    -pi/2 < theta0 <= 0 (exact at ``n_theta`` base angles, denser towards both ends, and a
    monotone cubic through them, PCHIP, for a smooth line): above it (shaded) the branch folds and
    a window of omega^2 with three states opens; the vertical lines are the slices drawn in
    (b). (b) That window against eps for the base angles ``theta0s`` (shaded between the
    lower and upper folds, ``n_eps`` points from the cusp to eps = 0.985). ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_bistability(n_theta=3, n_eps=3)
    >>> len(fig.axes)
    2
    """
    from hairbed.branches import cusp

    n_theta = check_int(n_theta, "n_theta", 2, MAX_POINTS)
    n_eps = check_int(n_eps, "n_eps", 2, MAX_POINTS)
    for k, t0 in enumerate(theta0s):  # a slice with no window would be drawn as nothing
        if not (-0.5 * np.pi < t0 < 0.0) or not float(cusp(t0)) < 0.985:
            raise ValueError(
                f"theta0s[{k}] = {t0!r}: the windows drawn need a base angle leaning into the "
                "flow, -pi/2 < theta0 < 0, whose cusp eps_c(theta0) lies below eps = 0.985 "
                "(theta0 below about -0.49)"
            )
    fig, (ax, axw) = figure_axes(ax, 1, 2, size=(9.4, 3.9))
    lo = -0.5 * np.pi
    # denser towards both ends, where eps_c runs to 0 and to 1
    th = lo + (0.0 - lo) * 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, n_theta)))
    th = np.clip(th, lo + 1e-6, 0.0)
    ec = np.asarray(cusp(th), dtype=float)
    if n_theta > 2:  # eps_c is smooth and monotone in theta0: a monotone cubic between nodes
        from scipy.interpolate import PchipInterpolator

        fine = np.linspace(th[0], th[-1], 400)
        th, ec = fine, np.clip(PchipInterpolator(th, ec)(fine), 0.0, 1.0)
    ax.fill_between(th, ec, 1.0, color="C1", alpha=0.3, lw=0, label="three states (bistable)")
    ax.plot(th, ec, "k-", lw=1.6, label=r"cusp $\epsilon_c(\theta_0)$")
    cols = colors(len(theta0s), "coolwarm") if len(theta0s) > 2 else ["C0", "C3"][: len(theta0s)]
    for t0, c in zip(theta0s, cols):
        e_c = float(cusp(t0))
        ax.plot([t0, t0], [e_c, 0.985], color=c, lw=2.0)
    if len(theta0s):
        ax.plot([], [], color="0.3", lw=2.0, label="slices drawn in (b)")
    ax.set_xlim(lo, 0.0)
    ax.set_ylim(0.0, 1.0)
    ax.set_xticks([lo, -1.0, -0.5, 0.0], [r"$-\pi/2$", "-1", "-0.5", "0"])
    ax.set_xlabel(r"base angle $\theta_0$ [rad]")
    ax.set_ylabel(r"confinement $\epsilon = L/H$ [-]")
    ax.set_title("(a) bistable region (hair leaning into the flow)")
    ax.legend(loc="lower right")
    for t0, c in zip(theta0s, cols):
        e_c = float(cusp(t0))
        if not e_c < 0.985:
            continue
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
def fig_hysteresis(
    eps: float = 0.9, theta0: float = -1.5, num: int = 240, ax: Any = None
) -> Figure:
    """Hysteresis loop of the tip deflection under a slow ramp of the forcing up and down.

    The thin curve is the whole physical branch, split at its folds into the low, middle and
    high states; each piece is solid where :func:`hairbed.stability.linear_stability` finds
    its state stable and dashed where unstable (the middle one). The ramp up follows the low
    state to the upper fold and jumps, the ramp down follows the high state to the lower fold
    and jumps back.

    Examples
    --------
    >>> fig = fig_hysteresis(num=40)
    >>> len(fig.axes)
    1
    """
    from hairbed.stability import linear_stability

    num = check_int(num, "num", 3, MAX_POINTS)
    lo, hi = _window(eps, theta0)
    if not np.isfinite(lo):
        raise ValueError(
            f"no bistable window at eps = {eps:g}, theta0 = {theta0:g}: no hysteresis (needs "
            "theta0 < 0 and eps above the cusp, hairbed bistability)"
        )
    up = np.linspace(0.3 * lo, 1.4 * hi, num)
    down = up[::-1]
    sweep = hairbed.quasistatic.sweep
    s_up, s_down = sweep(up, eps, theta0, root="low"), sweep(down, eps, theta0, root="high")
    x_up, x_down = np.asarray(s_up.tip_deflection), np.asarray(s_down.tip_deflection)
    fold_t = np.sort(np.asarray(hairbed.branches.folds(eps, theta0).t, dtype=float))
    fig, ax = figure_axes(ax, size=(5.8, 4.2))
    ax.axvspan(lo, hi, color="0.9", lw=0, label="three states")
    # the branch in t: low states below the first fold, middle between, high above
    pieces = (
        np.linspace(fold_t[0] - 14.0, fold_t[0], 400),
        np.linspace(fold_t[0], fold_t[1], 400),
        np.linspace(fold_t[1], fold_t[1] + 10.0, 400),
    )
    labelled = set()
    for t in pieces:
        branch = hairbed.from_parameter(t, eps, theta0)
        middle = hairbed.from_parameter(float(t[t.size // 2]), eps, theta0)
        result = linear_stability(middle, num=100, k=1)
        stable = bool(result.stable) if result.success else None
        style = {True: "-", False: "--", None: ":"}[stable]
        label = {True: "stable states", False: "unstable states", None: "not classified"}[stable]
        ax.plot(
            branch.omega2,
            branch.tip_deflection,
            style,
            color="0.25",
            lw=1.1,
            label=None if label in labelled else label,
            gid="unstable" if stable is False else "stable" if stable else None,
        )
        labelled.add(label)
    ax.plot(up, x_up, "-", color="C3", lw=3.2, alpha=0.6, label=r"ramp up ($\omega^2\uparrow$)")
    ax.plot(
        down, x_down, "-", color="C0", lw=1.6, alpha=0.8, label=r"ramp down ($\omega^2\downarrow$)"
    )
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
    eps_values: tuple[float, ...] = (0.3, 0.6, 0.9),
    theta0: float = 0.5,
    num: int = 200,
    ax: Any = None,
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
    from matplotlib.ticker import FixedLocator, NullFormatter, NullLocator

    num = check_int(num, "num", 2, MAX_POINTS)
    w2 = np.logspace(-2, 3, num)
    fig, (ax, axr) = figure_axes(ax, 1, 2, size=(9.4, 3.9))
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
    # readable ticks on a log axis spanning less than a decade or two: 1, 1.5, 2, 3, 5, 10, ...
    top = 1.0 / (1.0 - max(eps_values)) if len(eps_values) else 2.0
    ticks = [t for t in (1, 1.2, 1.5, 2, 3, 5, 10, 20, 50, 100) if t <= 1.15 * top]
    ax.yaxis.set_major_locator(FixedLocator(ticks))
    ax.yaxis.set_minor_locator(NullLocator())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_yticks(ticks, [f"{t:g}" for t in ticks])
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
    eps_values: tuple[float, ...] = (0.0, 0.5, 0.9),
    theta0: float = 0.0,
    num: int = 400,
    ax: Any = None,
) -> Figure:
    """Sensor calibration: forcing read from the tip deflection, exact and linear.

    (a) omega^2 against the measured x1 (exact branch curve, solid) and the small-deflection
    cantilever line (dashed), omega^2_lin = (x1 - sin theta0)/slope. (b) Relative error of
    the linear calibration, of the wall speed (omega^2, solid) and of the wall shear stress
    (tau, dashed): tau is proportional to omega^2/(1 - eps h1) = omega_eps^2 exactly and to
    omega^2_lin/(1 - eps cos theta0) in the linear calibration (the gap at rest), as in
    :func:`hairbed.calibration.linear_range`. At fixed t both are independent of eps, so the
    error in tau is one curve for every eps (the dashed lines coincide). ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_calibration(eps_values=(0.5,), num=30)
    >>> len(fig.axes)
    2
    """
    num = check_int(num, "num", 2, MAX_POINTS)
    t = np.linspace(-12.0, 30.0, num)
    fig, (ax, axe) = figure_axes(ax, 1, 2, size=(9.4, 3.9))
    x_lo = float(np.sin(theta0))
    for eps, c in zip(eps_values, colors(len(eps_values))):
        s = hairbed.from_parameter(t, eps, theta0)
        x1, w2 = np.asarray(s.tip_deflection), np.asarray(s.omega2)
        lin = (x1 - x_lo) / hairbed.inverse.tip_deflection_slope(eps, theta0)
        tau_exact = np.asarray(s.omega_eps) ** 2
        tau_lin = lin / (1.0 - eps * np.cos(theta0))
        ax.plot(x1, w2, color=c, label=rf"exact, $\epsilon = {eps:g}$")
        ax.plot(x1, lin, "--", color=c, lw=1.1)
        axe.plot(x1, np.abs(lin - w2) / w2, color=c, label=rf"$\epsilon = {eps:g}$")
        axe.plot(x1, np.abs(tau_lin - tau_exact) / tau_exact, "--", color=c, lw=1.1)
    ax.plot([], [], "--", color="0.4", lw=1.1, label="linear (cantilever)")
    ax.set_yscale("log")
    ax.set_xlim(x_lo, 1)
    ax.set_ylim(1e-3, 1e3)
    ax.set_xlabel(r"measured tip deflection $x_1/L$ [-]")
    ax.set_ylabel(r"forcing $\omega^2 \propto v$ [-]")
    ax.set_title(rf"(a) calibration curve, $\theta_0 = {theta0:g}$")
    ax.legend(loc="lower right")
    axe.axhline(0.01, color="0.5", lw=0.7, ls=":")
    axe.text(0.02, 0.0125, "1 %", color="0.4", fontsize=8, ha="left", va="bottom",
             transform=axe.get_yaxis_transform())  # fmt: skip
    axe.plot([], [], "-", color="0.4", label=r"wall speed ($\omega^2$)")
    axe.plot([], [], "--", color="0.4", lw=1.1, label=r"stress $\tau$ (any $\epsilon$)")
    axe.set_yscale("log")
    axe.set_xlim(x_lo, 1)
    axe.set_ylim(1e-4, 2.0)
    axe.set_xlabel(r"measured tip deflection $x_1/L$ [-]")
    axe.set_ylabel(r"relative error of the linear calibration [-]")
    axe.set_title(r"(b) error of the linear calibration, $v$ and $\tau$")
    axe.legend(loc="lower right", ncol=2)
    return fig


@styled
def fig_fd_convergence(
    omega2s: tuple[float, ...] = (0.5, 2.0, 8.0, 32.0),
    nums: tuple[int, ...] = (10, 20, 40, 80, 160, 320, 640),
    eps: float = 0.5,
    ax: Any = None,
) -> Figure:
    """Second-order convergence of the paper's finite differences to the exact tip height.

    Examples
    --------
    >>> fig = fig_fd_convergence(omega2s=(1.0,), nums=(10, 20))
    >>> len(fig.axes)
    1
    """
    from hairbed.numerics import finite_difference

    nums = tuple(check_int(n, f"nums[{i}]", 2, MAX_POINTS) for i, n in enumerate(nums))
    Ns_arr = np.asarray(nums, dtype=float)
    fig, ax = figure_axes(ax, size=(5.6, 4.2))
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


#: The largest batch size and number of repeats :func:`fig_speed` measures (ten times the
#: batch of ``hairbed bench --full``; the best of 100 runs is as good as any).
_MAX_BATCH = 10_000_000
_MAX_REPEAT = 100


def _row_group(number: str) -> str:
    """The row of a sub-row ("10e" -> "10"): a reference sub-row is scaled by its target."""
    return number.rstrip("abcdefghijklmnopqrstuvwxyz")


@styled
def fig_speed(
    n: int = 100_000,
    rows: Iterable[int] | None = None,
    results: Sequence[Any] | None = None,
    repeat: int = 3,
    ax: Any = None,
) -> Figure:
    """Every row of the speed table (``benchmarks/bench_solve.py``, ``hairbed bench``) as its
    measured value over its target, on a log axis: a bar per row, the target at 1, green when
    it is met and red when not (grey: reference rows without a target, scaled by the target
    of their row).

    The rows are measured here by the same code, ``hairbed._benchmark.run(quick=True)``, with
    batch size ``n`` (only ``rows``, 1 to 11, if given); or passed in as ``results``, rows
    of an earlier run. The labels of the batch rows name their inputs' base angles (row 2
    and row 7 lean into the flow, theta0 < 0, where the folds are); the axis is widened until
    every value printed beside its bar lies inside it.

    Examples
    --------
    >>> fig = fig_speed(n=100, rows={1, 4}, repeat=1)
    >>> len(fig.axes), len(fig.axes[0].patches)
    (1, 2)
    """
    measured = results is None
    if results is None:
        n = check_int(n, "n", 2, _MAX_BATCH)
        repeat = check_int(repeat, "repeat", 1, _MAX_REPEAT)
        from hairbed import _benchmark

        results = _benchmark.run(quick=True, rows=rows, n=n, repeat=repeat)
    scale = {_row_group(r.number): r.target for r in results if r.target is not None}
    shown = [r for r in results if scale.get(_row_group(r.number)) or r.target]
    ratios = np.array([r.value / (r.target or scale[_row_group(r.number)]) for r in shown])
    fig, ax = figure_axes(ax, size=(7.6, 0.8 + 0.36 * max(len(shown), 1)))
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
    notes = {
        "1": r" ($\theta_0 \in [0, 1.2]$)",
        "2": r" ($\theta_0 \in [-1.5, 1.5]$)",
        "6": r" ($\theta_0 \in [-0.3, 0.3]$)",
    }
    ax.set_yticks(y, [f"{r.number}  {r.label}{notes.get(r.number, '')}" for r in shown],
                  fontsize=7)  # fmt: skip
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
    _fit_texts(ax)
    return fig


def _fit_texts(ax: Any) -> None:
    """Widen the x axis (log) until every text of ``ax`` ends inside it."""
    fig = ax.figure
    for _ in range(3):  # the layout moves the axes: measure again after each change
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        inv = ax.transData.inverted()
        right = max(
            (inv.transform(t.get_window_extent(renderer))[1, 0] for t in ax.texts), default=0.0
        )
        lo, hi = ax.get_xlim()
        if right <= hi:
            return
        ax.set_xlim(lo, hi * (right / hi) ** 1.1)


@styled
def fig_twirling(
    omega2: float = 200.0, eps: float = 0.5, theta0: float = 0.0, ax: Any = None
) -> Figure:
    """Every solution at one forcing: the physical hair and the twirling branches.

    ``ax``: at least as many Axes as there are states (the others are switched off).

    Examples
    --------
    >>> fig = fig_twirling(omega2=20.0)
    >>> len(fig.axes) >= 3
    True
    """
    sols = sorted(hairbed.solve_all(omega2, eps, theta0), key=lambda s: (s.n, -s.sign))
    k = len(sols)
    ncols = max(min(k, 4), 1)
    nrows = max(int(np.ceil(k / ncols)), 1)
    size = (2.3 * ncols, 2.3 * nrows + 0.4)
    if ax is None:
        fig, axes = new_figure(nrows, ncols, size=size, squeeze=False)
    else:
        fig, axes = figure_axes(ax, k, 1, at_least=True)
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
        rf"All states at $\omega^2 = {omega2:g}$, $\epsilon = {eps:g}$, $\theta_0 = {theta0:g}$ "
        r"(axes $x/L$, $z/L$; physical in black)",
        fontsize=10,
    )
    return fig


@styled
def fig_physical_units(
    length: float = 1e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    channel_height: float = 2e-3,
    viscosity: float = 1.0,
    spacing: float = 400e-6,
    base_angles: tuple[float, ...] = (0.0, 0.3),
    max_velocity: float = 0.5,
    num: int = 201,
    ax: Any = None,
) -> Figure:
    """A real bed in SI units: tip displacement and wall shear stress against wall speed.

    By default soft 1 mm hairs (E = 1 MPa, radius 50 um, spacing 400 um) under 2 mm of
    glycerol, with and without a base angle, for flow with and against the grain (wall speeds
    in [-max_velocity, max_velocity] [m/s]). (a) The tip displacement from the rest position
    [um] (:attr:`hairbed.HairState.tip_displacement`; zero at rest whatever the base angle);
    (b) the wall shear stress [Pa]. The bed's parameters are printed in (a). ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_physical_units(num=21)
    >>> len(fig.axes)
    2
    """
    from hairbed.units import HairBed

    num = check_int(num, "num", 2, MAX_POINTS)
    if not (np.isfinite(max_velocity) and max_velocity > 0):
        raise ValueError(f"max_velocity must be finite and > 0 [m/s], got {max_velocity!r}")
    v = np.linspace(-max_velocity, max_velocity, num)
    fig, (ax, axs) = figure_axes(ax, 1, 2, size=(9.4, 4.1))
    cols = ["k", "C3", "C0", "C2", "C1"]
    bed = None
    for i, th0 in enumerate(base_angles):
        c = cols[i % len(cols)]
        bed = HairBed(
            length=length,
            radius=radius,
            youngs_modulus=youngs_modulus,
            channel_height=channel_height,
            viscosity=viscosity,
            spacing=spacing,
            base_angle=th0,
        )
        st = bed.deform(v)
        label = rf"$\theta_0 = {th0:g}$ rad"
        ax.plot(v * 100, np.asarray(st.tip_displacement) * 1e6, color=c, label=label)
        axs.plot(v * 100, np.asarray(st.wall_shear_stress), color=c, label=label)
    axs.plot(v * 100, viscosity * v / channel_height, ":", color="0.5",
             label=r"no hairs, $\eta v/H$")  # fmt: skip
    if bed is not None:
        text = (
            f"$L$ = {length * 1e3:g} mm, $a$ = {radius * 1e6:g} $\\mu$m\n"
            f"$E$ = {youngs_modulus:.3g} Pa, $\\delta$ = {spacing * 1e6:g} $\\mu$m\n"
            f"$H$ = {channel_height * 1e3:g} mm ($\\epsilon$ = {bed.eps:.3g})\n"
            f"$\\eta$ = {viscosity:g} Pa s"
        )
        ax.text(0.97, 0.04, text, transform=ax.transAxes, ha="right", va="bottom", fontsize=7.5,
                bbox={"boxstyle": "round", "fc": "white", "ec": "0.7"})  # fmt: skip
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(r"wall speed $v$ [cm/s]")
    ax.set_ylabel(r"tip displacement $x_1 - L\sin\theta_0$ [$\mu$m]")
    ax.set_title("(a) tip displacement")
    ax.legend(loc="upper left")
    axs.set_xlabel(r"wall speed $v$ [cm/s]")
    axs.set_ylabel(r"wall shear stress $\tau$ [Pa]")
    axs.set_title("(b) wall shear stress")
    axs.legend(loc="upper left")
    return fig


@styled
def fig_states(solutions: list, ax: Any = None) -> Figure:
    """Profiles of a few states (used by ``hairbed solve --plot``).

    Examples
    --------
    >>> fig = fig_states([hairbed.solve(2.0, 0.5)])
    >>> fig.axes[0].get_xlabel()
    '$x/L$'
    """
    fig, ax = figure_axes(ax, size=(7.0, 3.8))
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


@styled
def fig_valve(
    length: float = 1.6e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    channel_height: float = 2e-3,
    viscosity: float = 1.0,
    spacing: float = 400e-6,
    base_angle: float = -1.2,
    channel_length: float = 0.01,
    max_flow_rate: float = 3e-6,
    diode_angles: tuple[float, ...] = (0.3, 0.6, 1.0),
    num: int = 201,
    ax: Any = None,
) -> Figure:
    """A hair-bed valve driven at a set flow rate: every state, the folds, the hysteresis loop.

    By default 1.6 mm hairs leaning at ``base_angle`` = -1.2 rad against the flow in a 2 mm
    channel of glycerol (eps = 0.8), a channel ``channel_length`` long, the pump setting the
    flow rate per unit width Q' from -``max_flow_rate`` to ``max_flow_rate`` [m^2/s]: both
    directions. Forward flow lifts these hairs and closes the gap, so the pressure drop that
    carries Q' grows faster than Q': the bed is bistable (theory.md §11); backward flow lays
    them down. (a) Q' against the pressure drop dp [Pa] (:func:`hairbed.valve.valve_curve`,
    one state per dp): stable at the set flow rate (solid) outside the folds of
    :func:`hairbed.valve.valve_states` (circles), unstable (dashed) between them; the
    quasi-static ramps up and down the flow rate and their jumps in dp at the folds (arrows):
    the hysteresis loop. The empty channel, dp H^3/(12 eta l), is dotted. (b) The tip height
    of every coexisting state at ``2 num - 1`` set flow rates (filled: stable, open:
    unstable) over the same curve, the three-state window shaded. (c) The diodicity
    Di = Q'(+dp)/abs(Q'(-dp)) (:func:`hairbed.valve.diodicity`) of beds tilted by
    ``diode_angles`` [rad] towards +x, over the pressure drops of (a). The legends list only
    what the bed has: no folds, unstable states, jumps or window where there are none.
    ``ax``: three Axes.

    Examples
    --------
    >>> fig = fig_valve(num=9, diode_angles=(0.5,))
    >>> len(fig.axes)
    3
    """
    from hairbed.units import HairBed
    from hairbed.valve import diodicity, valve_curve, valve_states

    num = check_int(num, "num", 2, MAX_POINTS)
    if not (np.isfinite(max_flow_rate) and max_flow_rate > 0):
        raise ValueError(f"max_flow_rate must be finite and > 0 [m^2/s], got {max_flow_rate!r}")
    geometry: dict[str, Any] = {
        "length": length,
        "radius": radius,
        "youngs_modulus": youngs_modulus,
        "channel_height": channel_height,
        "viscosity": viscosity,
        "spacing": spacing,
    }
    bed = HairBed(**geometry, base_angle=base_angle)
    flows = np.linspace(-max_flow_rate, max_flow_rate, 2 * num - 1)
    s = valve_states(bed, channel_length, flow_rate=flows)
    top = float(np.nanmax(s.branch_pressure_drop))
    bottom = float(np.nanmin(s.branch_pressure_drop))
    dp = np.unique(np.concatenate([np.linspace(bottom, top, max(2 * num, 800)), [0.0]]))
    curve = valve_curve(bed, dp, channel_length)
    q_mm = np.asarray(curve.flow_rate) * 1e6  # [mm^2/s]
    h_mm = np.asarray(curve.tip_height) * 1e3  # [mm]
    folds = np.sort(s.fold_pressure_drop)
    unstable = np.zeros(dp.size, dtype=bool)
    for a, b in zip(folds[::2], folds[1::2]):
        unstable |= (dp > a) & (dp < b)
    fig, (axq, axh, axd) = figure_axes(ax, 1, 3, size=(13.2, 4.1))
    for target, y in ((axq, q_mm), (axh, h_mm)):
        xs = dp if target is axq else q_mm
        yv = y if target is axq else h_mm
        for flag, style, label in ((False, "-", "stable"), (True, "--", "unstable")):
            if flag and not np.any(unstable):
                continue  # no unstable part: not in the legend either
            masked = np.where(unstable == flag, yv, np.nan)
            # keep each piece connected to its neighbour at the fold
            edge = np.flatnonzero(np.diff(unstable.astype(int)) != 0)
            masked[edge] = yv[edge]
            masked[edge + 1] = yv[edge + 1]
            target.plot(xs, masked, style, color="0.2", lw=1.2, gid=label,
                        label=f"{label} at the set flow rate")  # fmt: skip
    axq.plot(dp, np.asarray(curve.empty_flow_rate) * 1e6, ":", color="0.5",
             label=r"no hairs, $\Delta p\,H^3/(12\eta l)$")  # fmt: skip
    if s.fold_pressure_drop.size:
        axq.plot(s.fold_pressure_drop, s.fold_flow_rate * 1e6, "o", color="k", ms=5,
                 label="folds")  # fmt: skip
    ramps = (
        (s.ramp_up, "C3", r"ramp up ($Q'\uparrow$)"),
        (s.ramp_down, "C0", r"ramp down ($Q'\downarrow$)"),
    )
    jumped = any(ramp.jumps for ramp, _, _ in ramps)
    for ramp, c, name in ramps:
        if not jumped:
            break  # one state at every flow rate: the ramps are the curve itself
        # the ramp's path on the curve: every drop except those it jumps over
        skipped = np.zeros(dp.size, dtype=bool)
        for j in ramp.jumps:
            a, b = sorted((j.pressure_drop_before, j.pressure_drop_after))
            skipped |= (dp > a) & (dp < b)
        axq.plot(dp, np.where(skipped, np.nan, q_mm), "-", color=c, lw=3.0, alpha=0.45,
                 label=name + (" and its jump" if ramp.jumps else ""))  # fmt: skip
        for j in ramp.jumps:
            axq.add_patch(
                FancyArrowPatch(
                    (j.pressure_drop_before, j.flow_rate_before * 1e6),
                    (j.pressure_drop_after, j.flow_rate_after * 1e6),
                    arrowstyle="-|>",
                    mutation_scale=14,
                    color=c,
                    lw=1.4,
                )
            )
    axq.axhline(0.0, color="0.8", lw=0.6, zorder=0)
    axq.axvline(0.0, color="0.8", lw=0.6, zorder=0)
    axq.set_xlim(bottom, top)
    axq.set_ylim(-1.15 * max_flow_rate * 1e6, 1.15 * max_flow_rate * 1e6)
    axq.set_xlabel(r"pressure drop $\Delta p$ [Pa] (negative: backward flow)")
    axq.set_ylabel(r"flow rate per width $Q'$ [mm$^2$/s]")
    axq.set_title(rf"(a) valve curve, $\theta_0 = {base_angle:g}$, $\epsilon = {bed.eps:.3g}$")
    axq.legend(loc="lower right", fontsize=7.5)
    inside = s.count >= 3
    if np.any(inside):
        axh.axvspan(flows[inside][0] * 1e6, flows[inside][-1] * 1e6, color="0.9", lw=0,
                    label="three states")  # fmt: skip
    q_states = np.broadcast_to(flows[:, None], s.tip_height.shape) * 1e6
    h_states = s.tip_height * 1e3
    axh.plot(q_states[s.stable], h_states[s.stable], "o", color="C2", ms=3.5,
             label="states (valve_states): stable")  # fmt: skip
    bad = ~s.stable & np.isfinite(h_states)
    if np.any(bad):
        axh.plot(q_states[bad], h_states[bad], "o", mfc="none", color="C1", ms=4,
                 label="unstable")  # fmt: skip
    axh.set_xlim(-max_flow_rate * 1e6, max_flow_rate * 1e6)
    axh.set_xlabel(r"set flow rate per width $Q'$ [mm$^2$/s]")
    axh.set_ylabel(r"tip height $h_1 L$ [mm]")
    axh.set_title("(b) every coexisting state")
    axh.legend(loc="lower left", fontsize=7.5)
    drops = np.geomspace(max(top * 1e-3, 1e-9), top, max(num // 4, 8))
    cols = colors(len(diode_angles), "plasma")
    for c, angle in zip(cols, diode_angles):
        d = diodicity(HairBed(**geometry, base_angle=angle), drops, channel_length)
        axd.plot(drops, np.asarray(d.diodicity), color=c, label=rf"$\theta_0 = {angle:g}$ rad")
    axd.axhline(1.0, color="0.6", lw=0.6)
    axd.set_xscale("log")
    axd.set_xlabel(r"pressure drop $|\Delta p|$ [Pa]")
    axd.set_ylabel(r"diodicity $Q'(+\Delta p)/|Q'(-\Delta p)|$ [-]")
    axd.set_title("(c) the tilted bed as a diode")
    axd.legend(loc="upper left")
    return fig


@styled
def fig_valve_result(result: Any, ax: Any = None) -> Figure:
    """What ``hairbed valve`` computed, drawn (its ``--plot``): a
    :class:`hairbed.valve.ValveCurve` as the flow rate Q' and the tip's deflection from rest
    against the pressure drop (the empty channel dotted); a :class:`hairbed.valve.Diodicity`
    as Di = Q'(+dp)/abs(Q'(-dp)) against abs(dp); a :class:`hairbed.valve.ValveStates` as
    every state at each set drive, stable filled and unstable open, over the branch (its
    unstable part dashed) and its folds. Only what the result holds is drawn and named in the
    legend. ``ax``: two Axes (one for a Diodicity).

    Examples
    --------
    >>> import hairbed
    >>> bed = hairbed.HairBed(length=1.8e-3, radius=50e-6, youngs_modulus=1e6,
    ...                       channel_height=2e-3, viscosity=1.0, spacing=400e-6)
    >>> fig = fig_valve_result(hairbed.valve.valve_curve(bed, [-100.0, 100.0], 0.01))
    >>> len(fig.axes)
    2
    """
    from hairbed.valve import Diodicity, ValveCurve, ValveStates

    if isinstance(result, Diodicity):
        fig, axd = figure_axes(ax, 1, 1, size=(5.0, 3.8))
        drop = np.abs(np.atleast_1d(np.asarray(result.forward.pressure_drop, dtype=float)))
        di = np.atleast_1d(np.asarray(result.diodicity, dtype=float))
        axd.plot(drop, di, "o-", color="C3", ms=3, label="diodicity")
        axd.axhline(1.0, color="0.6", lw=0.6, label="no rectification (Di = 1)")
        if drop.size > 1 and np.all(drop > 0) and drop.max() / drop.min() > 20:
            axd.set_xscale("log")
        axd.set_xlabel(r"pressure drop $|\Delta p|$ [Pa]")
        axd.set_ylabel(r"diodicity $Q'(+\Delta p)/|Q'(-\Delta p)|$ [-]")
        axd.set_title(f"diodicity over l = {result.forward.channel_length:g} m")
        axd.legend(fontsize=7.5)
        return fig
    fig, (axq, axh) = figure_axes(ax, 1, 2, size=(10.0, 3.9))
    if isinstance(result, ValveCurve):
        dp = np.atleast_1d(np.asarray(result.pressure_drop, dtype=float))
        order = np.argsort(dp)
        q = np.atleast_1d(np.asarray(result.flow_rate, dtype=float))[order] * 1e6
        empty = np.atleast_1d(np.asarray(result.empty_flow_rate, dtype=float))[order] * 1e6
        dx = np.atleast_1d(np.asarray(result.states.tip_displacement, dtype=float))[order]
        dp = dp[order]
        marker = "o-" if dp.size < 30 else "-"
        axq.plot(dp, q, marker, color="0.2", ms=3, label="with the bed (valve_curve)")
        axq.plot(dp, empty, ":", color="0.5", label=r"no hairs, $\Delta p\,H^3/(12\eta l)$")
        axh.plot(dp, dx * 1e3, marker, color="C0", ms=3)
        axh.set_xlabel(r"pressure drop $\Delta p$ [Pa]")
        axh.set_ylabel(r"tip deflection from rest $(x_1 - \sin\theta_0) L$ [mm]")
        axq.set_xlabel(r"pressure drop $\Delta p$ [Pa]")
        axq.set_ylabel(r"flow rate per width $Q'$ [mm$^2$/s]")
        axq.set_title(f"(a) valve curve over l = {result.channel_length:g} m")
        axh.set_title("(b) the hairs' tips")
        axq.legend(fontsize=7.5)
        return fig
    if not isinstance(result, ValveStates):
        raise TypeError(
            "result must be a ValveCurve, Diodicity or ValveStates of hairbed.valve, got "
            f"{type(result).__name__}"
        )
    s = result
    by_flow = s.drive != "pressure"
    scale = 1e6 if by_flow else 1.0
    unit = r"$Q'$ [mm$^2$/s]" if by_flow else r"$\Delta p$ [Pa]"
    bp, bq = s.branch_pressure_drop, s.branch_flow_rate * 1e6
    bh = s.branch_tip_height * 1e3
    for flag, style, word in ((True, "-", "stable"), (False, "--", "unstable")):
        part = s.branch_stable == flag
        if not np.any(part):
            continue
        for target, x, y in ((axq, bp, bq), (axh, bq if by_flow else bp, bh)):
            target.plot(x, np.where(part, y, np.nan), style, color="0.6", lw=1.0,
                        label=f"branch, {word}")  # fmt: skip
    if s.fold_pressure_drop.size:
        axq.plot(s.fold_pressure_drop, s.fold_flow_rate * 1e6, "o", color="k", ms=5,
                 label="folds")  # fmt: skip
    value = np.broadcast_to(s.values[:, None], s.tip_height.shape) * scale
    found = np.isfinite(s.tip_height)
    for flag, face, color, word in ((True, None, "C2", "stable"), (False, "none", "C1",
                                                                    "unstable")):  # fmt: skip
        pick = found & (s.stable == flag)
        if not np.any(pick):
            continue
        xq = s.pressure_drop[pick]
        yq = s.flow_rate[pick] * 1e6
        axq.plot(
            xq, yq, "o", mfc=face, color=color, ms=4, label=f"states at the set drive, {word}"
        )
        axh.plot(value[pick], s.tip_height[pick] * 1e3, "o", mfc=face, color=color, ms=4,
                 label=word)  # fmt: skip
    axq.set_xlabel(r"pressure drop $\Delta p$ [Pa]")
    axq.set_ylabel(r"flow rate per width $Q'$ [mm$^2$/s]")
    axq.set_title(f"(a) every state over l = {s.channel_length:g} m")
    axh.set_xlabel(f"set {'flow rate per width' if by_flow else 'pressure drop'} {unit}")
    axh.set_ylabel(r"tip height $h_1 L$ [mm]")
    axh.set_title("(b) their tip heights")
    axq.legend(fontsize=7.5)
    axh.legend(fontsize=7.5)
    return fig


def _crossing(lam: Any, err: Any, level: float) -> float:
    """The first forcing where ``err`` reaches ``level`` (log-log interpolation between the
    grid points around it); NaN if it never does."""
    above = np.flatnonzero(np.isfinite(err) & (err >= level))
    if above.size == 0 or above[0] == 0:
        return float("nan")
    i = int(above[0])
    u = np.log([err[i - 1], err[i]])
    t = (np.log(level) - u[0]) / (u[1] - u[0])
    return float(np.exp(np.log(lam[i - 1]) + t * (np.log(lam[i]) - np.log(lam[i - 1]))))


@styled
def fig_pillar_calibration(
    theta0s: tuple[float, ...] = (0.0, -0.6),
    forcing_min: float = 1e-3,
    forcing_max: float = 1e3,
    num: int = 240,
    slenderness: float = 20.0,
    ax: Any = None,
) -> Figure:
    """A pillar sensor's calibration: the exact tip deflection against the linear formula.

    An isolated pillar of slenderness L/a = ``slenderness`` in the viscous sublayer
    (theory.md §12; its drag ratio gamma is Gray & Hancock's of L/a,
    :func:`hairbed.gray_hancock_ratio`: 0.657 at L/a = 20), at the base
    angles ``theta0s``, over ``num`` forcings Lambda = zeta_perp tau_w L^4/(eta E I)
    geometrically spaced from ``forcing_min`` to ``forcing_max``
    (:func:`hairbed.solve_pillar`). (a) The tip displacement x1 - sin theta0 (exact, solid)
    and the linear cantilever formula (dashed), x1 = 11 Lambda/120 upright and
    x1 = sin theta0 + 11 Lambda cos^3(theta0)/120 tilted (theory.md §12, "Small deflection").
    (b) The relative error of the forcing (so of the wall shear stress) that the linear
    formula reads from the exact deflection, abs(Lambda_lin - Lambda)/Lambda; the forcings
    where it reaches 1 % and 10 % are marked in both panels (interpolated between grid
    points). ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_pillar_calibration(theta0s=(0.0,), num=20)
    >>> len(fig.axes)
    2
    """
    num = check_int(num, "num", 2, MAX_POINTS)
    if not (0.0 < forcing_min < forcing_max < np.inf):
        raise ValueError(
            "forcing_min and forcing_max must satisfy 0 < forcing_min < forcing_max < inf, "
            f"got {forcing_min!r} and {forcing_max!r}"
        )
    gamma = _pillar_gamma(slenderness)
    lam = np.geomspace(forcing_min, forcing_max, num)
    fig, (ax, axe) = figure_axes(ax, 1, 2, size=(9.4, 3.9))
    marks = (("o", 0.01, "1 %"), ("s", 0.1, "10 %"))
    lines = []
    for t0, c in zip(theta0s, colors(len(theta0s)) if len(theta0s) > 2 else ["C0", "C3"]):
        st = hairbed.solve_pillar(lam, t0, gamma=gamma)
        rest = float(np.sin(t0))
        shift = np.asarray(st.tip_deflection) - rest
        slope = 11.0 * np.cos(t0) ** 3 / 120.0
        read = shift / slope  # the forcing the linear formula reads from x1
        err = np.abs(read - lam) / lam
        ax.plot(lam, shift, color=c, label=rf"exact, $\theta_0 = {t0:g}$")
        ax.plot(lam, slope * lam, "--", color=c, lw=1.1)
        axe.plot(lam, err, color=c, label=rf"$\theta_0 = {t0:g}$")
        reached = []
        for marker, level, text in marks:
            at = _crossing(lam, err, level)
            if not np.isfinite(at):
                continue
            y = float(np.interp(np.log(at), np.log(lam), shift))
            ax.plot([at], [y], marker, color=c, ms=5, mfc="white")
            axe.plot([at], [level], marker, color=c, ms=5, mfc="white")
            reached.append(f"{text} at {at:.3g}")
        lines.append(rf"$\theta_0 = {t0:g}$: " + (", ".join(reached) or "below 1 %"))
    axe.text(0.97, 0.03, "error reaches, at $\\Lambda$ =\n" + "\n".join(lines),
             transform=axe.transAxes, ha="right", va="bottom", fontsize=7.5,
             bbox={"boxstyle": "round", "fc": "white", "ec": "0.7"})  # fmt: skip
    ax.plot([], [], "--", color="0.4", lw=1.1, label=r"linear, $11\Lambda\cos^3\theta_0/120$")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(r"forcing $\Lambda = \zeta_\perp \tau_w L^4/(\eta E I)$ [-]")
    ax.set_ylabel(r"tip displacement $x_1 - \sin\theta_0$ [$L$]")
    ax.set_title(
        rf"(a) calibration curve, sublayer, $L/a = {slenderness:g}$ ($\gamma$ = {gamma:.3f})"
    )
    ax.legend(loc="upper left")
    for level in (0.01, 0.1):
        axe.axhline(level, color="0.6", lw=0.7, ls=":")
    axe.set_xscale("log")
    axe.set_yscale("log")
    axe.set_ylim(max(1e-10, axe.get_ylim()[0]), 2.0)
    axe.set_xlabel(r"forcing $\Lambda$ [-]")
    axe.set_ylabel(r"relative error of the linear $\Lambda$ (of $\tau_w$) [-]")
    axe.set_title("(b) error of the linear calibration")
    axe.legend(loc="center right")
    return fig


def _pillar_gamma(slenderness: float) -> float:
    """Gray & Hancock's drag ratio of a pillar of slenderness L/a (its checks name it)."""
    return float(hairbed.gray_hancock_ratio(slenderness))


def _folds_beyond(branch: Any, forcing_max: float, theta0: float, gamma: float, num: int) -> list:
    """The forcings of the folds that the branch from rest would reach past ``forcing_max``
    (found on the branch to 4 forcing_max, at least 100): where forcing_max cuts it short."""
    longer = hairbed.continue_pillar(max(4.0 * abs(forcing_max), 100.0) * np.sign(forcing_max),
                                     theta0, gamma=gamma, num=num)  # fmt: skip
    drawn = len(np.asarray(branch.folds))
    return [float(f[0]) for f in np.asarray(longer.folds)[drawn:]]


def _stability_runs(stable: Any) -> list[tuple[int, int, bool]]:
    """Runs (start, stop, stable) of equal stability, each stop the next run's start (so
    that the lines join)."""
    runs = []
    start = 0
    for i in range(1, len(stable) + 1):
        if i == len(stable) or stable[i] != stable[start]:
            runs.append((start, min(i + 1, len(stable)), bool(stable[start])))
            start = i
    return runs


@styled
def fig_pillar_snap(
    theta0: float = -1.4,
    forcing_max: float = 40.0,
    forcing: float = 15.0,
    num: int = 400,
    slenderness: float = 20.0,
    ax: Any = None,
) -> Figure:
    """The snap-through of a pillar tilted far upstream: its branch, folds and three states.

    (a) The tip deflection x1 against the forcing Lambda along the branch of states from rest
    to ``forcing_max`` (:func:`hairbed.continue_pillar`, ``num`` points in x1), for the
    sublayer, a pillar of slenderness L/a = ``slenderness`` (its drag ratio gamma that of
    :func:`hairbed.gray_hancock_ratio`), at ``theta0`` (theory.md §12, "Folds"): stable
    solid, unstable dashed, the folds marked and the window between them shaded. On a slow
    ramp up the pillar jumps at the upper fold from leaning upstream to standing over its
    base. A ``forcing_max`` that stops the branch before a fold it would reach is said: in
    the panel and as a UserWarning (``hairbed figures`` prints it), with the fold's forcing.
    (b) The coexisting states at ``forcing`` (:func:`hairbed.solve_pillar_all`; inside the
    window: three), their shapes (unstable dashed). ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_pillar_snap(num=40)
    >>> len(fig.axes)
    2
    """
    num = check_int(num, "num", 16, 10**4)
    gamma = _pillar_gamma(slenderness)
    br = hairbed.continue_pillar(forcing_max, theta0, gamma=gamma, num=num)
    cut = _folds_beyond(br, forcing_max, theta0, gamma, num)
    fig, (ax, axs) = figure_axes(ax, 1, 2, size=(9.4, 3.9))
    lam, x1 = np.asarray(br.forcing), np.asarray(br.tip_deflection)
    for a, b, stable in _stability_runs(np.asarray(br.stable)):
        ax.plot(lam[a:b], x1[a:b], "-" if stable else "--", color="C0" if stable else "C3")
    kinds = set(np.asarray(br.stable, dtype=bool).tolist())
    if True in kinds:
        ax.plot([], [], "-", color="C0", label="stable")
    if False in kinds:  # only what the branch drawn has
        ax.plot([], [], "--", color="C3", label="unstable")
    folds = np.asarray(br.folds)
    if len(folds):
        ax.plot(folds[:, 0], folds[:, 1], "ko", ms=5, mfc="white", label="folds")
        for lf, xf in folds:
            ax.annotate(f"$\\Lambda$ = {lf:.4g}", (lf, xf), xytext=(6, -3),
                        textcoords="offset points", fontsize=7.5, va="top")  # fmt: skip
    if len(folds) >= 2:
        lo, hi = float(folds[:, 0].min()), float(folds[:, 0].max())
        ax.axvspan(lo, hi, color="C1", alpha=0.2, lw=0, label="three states")
    if cut:
        where = ", ".join(f"{f:.4g}" for f in cut)
        text = (
            f"forcing_max = {forcing_max:g} stops the branch before its fold(s) at "
            f"Lambda = {where}: the snap-through is not drawn; raise forcing_max"
        )
        warnings.warn(f"fig_pillar_snap: {text}", UserWarning, stacklevel=3)
        ax.text(0.03, 0.97, text.replace("Lambda", "$\\Lambda$").replace(": ", ":\n"),
                transform=ax.transAxes, ha="left", va="top", fontsize=7.5, color="C3",
                bbox={"boxstyle": "round", "fc": "white", "ec": "C3"})  # fmt: skip
    ax.axvline(forcing, color="0.5", lw=0.7, ls=":")
    ax.set_xlabel(r"forcing $\Lambda$ [-]")
    ax.set_ylabel(r"tip deflection $x_1$ [$L$]")
    ax.set_title(
        rf"(a) the branch, $\theta_0 = {theta0:g}$, $L/a = {slenderness:g}$ "
        rf"($\gamma$ = {gamma:.3f}), sublayer"
    )
    ax.legend(loc="lower right")
    states = hairbed.solve_pillar_all(forcing, theta0, gamma=gamma)
    s = np.linspace(0.0, 1.0, 200)
    for k, st in enumerate(states):
        _, x, z, _ = st.shape(s)
        unstable = st.stable is False
        axs.plot(x, z, "--" if unstable else "-", color=f"C{k % 10}",
                 label=rf"$x_1 = {float(st.tip_deflection):.3f}$"
                 + (" (unstable)" if unstable else ""))  # fmt: skip
    axs.axhline(0.0, color="0.5", lw=0.8)
    axs.set_aspect("equal", adjustable="datalim")
    axs.set_xlabel(r"$x/L$")
    axs.set_ylabel(r"$z/L$")
    axs.set_title(rf"(b) the states at $\Lambda = {forcing:g}$")
    axs.legend(loc="upper right", fontsize=7.5)
    return fig


@styled
def fig_pillar_states(states: list, ax: Any = None) -> Figure:
    """Shapes of a few pillar states (used by ``hairbed solve --pillar --plot``): each
    :class:`hairbed.PillarState` at 200 arc lengths (:meth:`hairbed.PillarState.shape`),
    an unstable one (``stable`` False, from :func:`hairbed.solve_pillar_all`) dashed.

    Examples
    --------
    >>> fig = fig_pillar_states([hairbed.solve_pillar(2.0)])
    >>> fig.axes[0].get_xlabel()
    '$x/L$'
    """
    fig, ax = figure_axes(ax, size=(7.0, 3.8))
    s = np.linspace(0.0, 1.0, 200)
    for i, st in enumerate(states):
        _, x, z, _ = st.shape(s)
        unstable = st.stable is False
        label = rf"$\Lambda = {float(st.forcing):.4g}$, $x_1 = {float(st.tip_deflection):.3f}$"
        ax.plot(x, z, "--" if unstable else "-", color=f"C{i % 10}",
                label=label + (" (unstable)" if unstable else ""))  # fmt: skip
    ax.axhline(0, color="0.5", lw=0.8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(r"$x/L$")
    ax.set_ylabel(r"$z/L$")
    if states:
        st = states[0]
        ax.set_title(rf"pillar, $\theta_0 = {float(st.theta0):g}$, $\gamma = {float(st.gamma):g}$")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7.5)
    return fig
