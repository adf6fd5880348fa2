"""The figures of the paper, recomputed from the exact solution.

Each function returns a :class:`matplotlib.figure.Figure` (Agg backend, not registered with
pyplot). Figure numbers in the docstrings are those of arXiv:2203.04169 (e.g. Fig. 4).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import FancyArrowPatch, Rectangle

import hairbed

from .._core.validation import check_int
from ._style import MAX_POINTS, colors, figure_axes, styled

__all__ = [
    "fig_model",
    "fig_pendulum",
    "fig_phase_portrait",
    "fig_profiles",
    "fig_solution",
    "fig_theta0s",
]

_BRANCH_T = (-15.0, 40.0)


def _curve(
    eps: float, theta0: float = 0.0, sign: int = 1, n: int = 0, num: int = 600
) -> hairbed.Solution:
    """Exact branch curve over the logit parameter t (no root finding)."""
    t = np.linspace(*_BRANCH_T, num)
    return hairbed.from_parameter(t, eps, theta0, sign=sign, n=n)


def _phase_velocity(sol: hairbed.Solution, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """theta(sigma) and theta'(sigma): magnitude from energy conservation (eq. (7)), sign from
    the slope of theta on the grid (the closed form has no derivative method)."""
    th = np.asarray(sol.theta(sigma), dtype=float)
    w = (
        np.asarray(sol.omega_eps, dtype=float)[..., None]
        if np.ndim(sol.omega_eps)
        else float(sol.omega_eps)
    )
    xi = np.asarray(sol.xi, dtype=float)[..., None] if np.ndim(sol.xi) else float(sol.xi)
    mag = w * np.sqrt(np.clip(2.0 * (xi - np.sin(th)), 0.0, None))
    slope = np.gradient(th, sigma, axis=-1)
    return th, np.where(slope >= 0.0, mag, -mag)


@styled
def fig_model(
    omega2: float = 1.5, eps: float = 0.6, theta0: float = 0.0, ax: Any = None
) -> Figure:
    """Model schematic (Fig. 1): a bed of hairs in a channel of height H.

    Undeformed hairs (dashed) stand at the base angle; deformed hairs (solid) are exact
    profiles at (omega2, eps). Above the tips the flow is a linear shear from 0 at h(L) to the
    moving wall speed v, so the stress on the bed is eta v / (H - h(L)).

    Examples
    --------
    >>> fig = fig_model()
    >>> len(fig.axes)
    1
    """
    sol = hairbed.solve(omega2, eps, theta0)
    if not eps >= 1e-3:  # a subnormal eps makes H = L/eps infinite: nothing to draw
        raise ValueError(
            f"eps must be >= 0.001 to draw the channel (H = L/eps at most 1000 L), got {eps:g}"
        )
    x, z = sol.profile(120)
    h1, height = float(sol.tip_height), 1.0 / eps
    fig, ax = figure_axes(ax, size=(6.4, 3.1))
    ax.add_patch(Rectangle((-0.6, -0.12), 6.0, 0.12, color="0.55", hatch="///", fill=False))
    ax.add_patch(Rectangle((-0.6, height), 6.0, 0.12, color="0.55", hatch="///", fill=False))
    ax.plot([-0.6, 5.4], [0, 0], "k", lw=1.2)
    ax.plot([-0.6, 5.4], [height, height], "k", lw=1.2)
    bases = np.arange(5) * 0.75
    for i, b in enumerate(bases):
        rest = (b + np.array([0.0, np.sin(theta0)]), np.array([0.0, np.cos(theta0)]))
        ax.plot(*rest, "--", color="0.45", lw=1.2, label="undeformed" if i == 0 else None)
        ax.plot(b + x, z, color="C0", lw=2.0, label="deformed" if i == 0 else None)
    ax.plot([-0.6, 5.4], [h1, h1], ":", color="0.3", lw=1.0)
    # Couette profile above the tips: zero at the tips, v at the moving top wall.
    xa = 4.45
    for zz in np.linspace(h1 + 0.15, height - 0.05, 5):
        length = 0.8 * (zz - h1) / (height - h1)
        ax.add_patch(
            FancyArrowPatch(
                (xa, zz), (xa + length, zz), arrowstyle="-|>", mutation_scale=9, color="C3", lw=1.2
            )
        )
    ax.plot([xa, xa + 0.8], [h1, height - 0.05], color="C3", lw=1.0)
    ax.annotate(r"$v$", (xa + 0.85, height + 0.2), color="C3", ha="left", va="bottom")
    ax.add_patch(
        FancyArrowPatch(
            (xa, height + 0.22),
            (xa + 0.8, height + 0.22),
            arrowstyle="-|>",
            mutation_scale=10,
            color="C3",
        )
    )
    # Dimension arrows.
    dim: dict[str, Any] = {"arrowstyle": "<|-|>", "mutation_scale": 8, "color": "k", "lw": 0.9}
    ax.add_patch(FancyArrowPatch((-0.35, 0), (-0.35, height), **dim))
    ax.text(-0.42, 0.62 * height, r"$H$", ha="right", va="center")
    ax.add_patch(FancyArrowPatch((bases[0] - 0.12, 0), (bases[0] - 0.12, 1), **dim))
    ax.text(bases[0] - 0.17, 0.45, r"$L$", ha="right", va="center")
    ax.add_patch(FancyArrowPatch((5.2, 0), (5.2, h1), **dim))
    ax.text(5.27, h1 / 2, r"$h(L)$", ha="left", va="center")
    ax.text(
        2.2,
        h1 + 0.5 * (height - h1),
        r"shear stress $\tau = \eta v/(H - h(L))$",
        ha="center",
        va="center",
        fontsize=9,
        bbox={"boxstyle": "round", "fc": "white", "ec": "0.7"},
    )
    ax.set_xlim(-0.9, 6.0)
    ax.set_ylim(-0.2, height + 0.4)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0.02), ncol=2, fontsize=8)
    ax.set_title(
        rf"Hair bed in channel flow ($\omega^2 = {omega2:g}$, $\epsilon = L/H = {eps:g}$)"
    )
    return fig


@styled
def fig_pendulum(omega2: float = 20.0, ax: Any = None) -> Figure:
    """Two pendulum orbits meeting the same conditions (Fig. 3).

    The (sign=+1, n=0) and (sign=+1, n=1) solutions at eps = 0, so both share omega_eps =
    omega: theta(0) = 0 and theta'(1) = 0 in the time 1, drawn in the (theta, theta') plane over
    the level sets of the pendulum energy theta'^2/2 + omega^2 sin(theta).

    Examples
    --------
    >>> fig = fig_pendulum()
    >>> len(fig.axes)
    2
    """
    if not omega2 > 0.0:
        raise ValueError(f"omega2 must be > 0 for the pendulum's orbits, got {omega2!r}")
    sols = {(s.sign, s.n): s for s in hairbed.solve_all(omega2, 0.0)}
    fig, (ax, axp) = figure_axes(ax, 1, 2, size=(8.6, 4.4), width_ratios=[1.6, 1.0])
    w = float(np.sqrt(omega2))
    th = np.linspace(-np.pi - 0.3, np.pi / 2 + 0.4, 300)
    dth = np.linspace(-1.7 * w * np.sqrt(2), 1.7 * w * np.sqrt(2), 300)
    tt, dd = np.meshgrid(th, dth)
    energy = 0.5 * dd**2 + omega2 * np.sin(tt)
    ax.contour(
        tt, dd, energy, levels=np.linspace(-omega2, 3 * omega2, 13), colors="0.82", linewidths=0.7
    )
    ax.contour(tt, dd, energy, levels=[omega2], colors="0.5", linewidths=1.0, linestyles="--")
    sigma = np.linspace(0.0, 1.0, 801)
    styles = {(1, 0): ("k", r"$n = 0$ (physical)"), (1, 1): ("C0", r"$n = 1$ (twirling)")}
    for key, (col, lab) in styles.items():
        if key not in sols:
            continue
        s = sols[key]
        theta, dtheta = _phase_velocity(s, sigma)
        ax.plot(theta, dtheta, color=col, lw=2, label=lab)
        ax.plot(theta[0], dtheta[0], "o", color=col, ms=5)
        ax.plot(theta[-1], dtheta[-1], "s", color=col, ms=5)
        x, z = s.profile(300)
        axp.plot(x, z, color=col, lw=2)
    ax.plot([], [], "o", color="0.3", label=r"start $\theta(0) = 0$")
    ax.plot([], [], "s", color="0.3", label=r"end $\theta'(1) = 0$")
    ax.plot([], [], "--", color="0.5", label="separatrix")
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    ax.set_xlabel(r"angle $\theta$ [rad]")
    ax.set_ylabel(r"$\theta' = d\theta/d\sigma$ [-]")
    ax.set_title(rf"(a) phase plane, $\omega_\epsilon^2 = \omega^2 = {omega2:g}$")
    # below the plane, where it covers no orbit
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3, fontsize=8)
    ax.set_xlim(th[0], th[-1])
    axp.axhline(0, color="0.4", lw=1)
    axp.set_aspect("equal", adjustable="datalim")
    axp.set_xlabel(r"$x/L$")
    axp.set_ylabel(r"$z/L$")
    axp.set_title("(b) hair profiles")
    return fig


@styled
def fig_phase_portrait(
    xis: tuple[float, ...] = (0.05, 0.2, 0.4, 0.6, 0.8, 0.95, 0.999), ax: Any = None
) -> Figure:
    """Phase portraits and profiles for 0 <= xi <= 1 at theta0 = 0 (Fig. 2).

    Each xi fixes omega_eps (eq. (34)); the ordinate is theta'/omega_eps^2 with theta'
    from energy conservation, so the curves are not nested as usual.

    Examples
    --------
    >>> fig = fig_phase_portrait(xis=(0.3, 0.9))
    >>> len(fig.axes)
    2
    """
    xi = np.asarray(xis, dtype=float)
    # a column of states so that theta(sigma) broadcasts to (len(xis), len(sigma))
    sol = hairbed.from_xi(xi[:, None], 0.0)
    sigma = np.linspace(0.0, 1.0, 400)
    theta = np.asarray(sol.theta(sigma)).reshape(xi.size, -1)
    w = np.asarray(sol.omega_eps, dtype=float).reshape(-1, 1)
    ordinate = np.sqrt(np.clip(2.0 * (xi[:, None] - np.sin(theta)), 0.0, None)) / w
    x, z = sol.profile(200)
    x, z = np.reshape(x, (xi.size, -1)), np.reshape(z, (xi.size, -1))
    fig, (ax, axp) = figure_axes(ax, 1, 2, size=(8.6, 3.7))
    for i, c in enumerate(colors(xi.size, "plasma")):
        ax.plot(theta[i], ordinate[i], color=c, label=rf"$\xi = {xi[i]:g}$")
        axp.plot(x[i], z[i], color=c)
    ax.set_xlabel(r"$\theta$ [rad]")
    ax.set_ylabel(r"$\theta'/\omega_\epsilon^2$ [-]")
    ax.set_xlim(0, np.pi / 2)
    ax.set_ylim(bottom=0)
    ax.set_title(r"(a) phase portraits, $\theta_0 = 0$")
    ax.legend(loc="upper right", ncol=1)
    axp.set_xlabel(r"$x/L$")
    axp.set_ylabel(r"$z/L$")
    axp.set_xlim(0, 1.02)
    axp.set_ylim(0, 1.02)
    axp.set_aspect("equal")
    axp.set_title("(b) profiles")
    return fig


_EPS_SET = (0.0, 0.3, 0.6, 0.9)
_BRANCHES = ((1, 0), (-1, 0), (1, 1), (-1, 1), (1, 2), (-1, 2))


@styled
def fig_solution(
    eps_values: tuple[float, ...] = _EPS_SET, num: int = 600, ax: Any = None
) -> Figure:
    """Solution structure at theta0 = 0 (Fig. 4).

    (a) energy E against omega^2 for several eps (uncollapsed); (b) xi against omega_eps^2,
    which collapses every eps, with numbered representative profiles (solid: positive base
    curvature, dashed: negative); (c) xi against omega^2/(1 - eps), the first three branches
    and their negative-curvature counterparts. Every curve is an exact parametric branch; the
    dotted curve of (b) is the weak-forcing limit xi = omega_eps^2/2 (theory.md §3), drawn as
    the curve it is on the log axis. ``ax``: three Axes to draw (a), (b), (c) into.

    Examples
    --------
    >>> fig = fig_solution(eps_values=(0.0, 0.9), num=50)
    >>> len(fig.axes) >= 3
    True
    """
    num = check_int(num, "num", 2, MAX_POINTS)
    fig, axes = figure_axes(ax, 1, 3, size=(13.0, 4.3))
    cols = colors(len(eps_values))
    widths = {0: 2.0, 1: 1.3, 2: 0.9}
    for eps, c in zip(eps_values, cols):
        for sign, n in _BRANCHES:
            s = _curve(eps, sign=sign, n=n, num=num)
            ls = "-" if sign > 0 else "--"
            axes[0].plot(s.omega2, s.energy, ls, color=c, lw=widths[n])
            axes[2].plot(np.asarray(s.omega2) / (1.0 - eps), s.xi, ls, color=c, lw=widths[n])
    ax = axes[0]
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(1e-2, 1e3)
    ax.set_ylim(1e-3, 1e4)
    ax.set_xlabel(r"forcing $\omega^2$ [-]")
    ax.set_ylabel(r"energy $\mathcal{E}$ [-]")
    ax.set_title(r"(a) $\mathcal{E}$ vs $\omega^2$")
    eps_key = ax.legend(
        handles=[
            Line2D([], [], color=c, label=rf"$\epsilon = {e:g}$") for e, c in zip(eps_values, cols)
        ],
        loc="lower right",
    )
    ax.add_artist(eps_key)
    ax.legend(
        handles=[
            Line2D([], [], color="k", ls="-", label=r"$\theta'(0) > 0$"),
            Line2D([], [], color="k", ls="--", label=r"$\theta'(0) < 0$"),
            Line2D([], [], color="k", lw=2.0, label=r"$n = 0$"),
            Line2D([], [], color="k", lw=1.3, label=r"$n = 1$"),
            Line2D([], [], color="k", lw=0.9, label=r"$n = 2$"),
        ],
        loc="upper left",
    )
    ax = axes[2]
    ax.set_xscale("log")
    ax.set_xlim(1e-2, 1e3)
    ax.set_ylim(0, 1.03)
    ax.set_xlabel(r"$\omega^2/(1-\epsilon)$ [-]")
    ax.set_ylabel(r"$\xi = \mathcal{E}/\omega_\epsilon^2$ [-]")
    ax.set_title(r"(c) partial collapse")
    ax.legend(
        handles=[
            Line2D([], [], color=c, label=rf"$\epsilon = {e:g}$") for e, c in zip(eps_values, cols)
        ],
        loc="upper left",
    )
    # (b): eps drops out when plotted against omega_eps^2: one curve per branch.
    ax = axes[1]
    bcols = {0: "k", 1: "C0", 2: "C2"}
    for sign, n in _BRANCHES:
        s = _curve(0.0, sign=sign, n=n, num=num)
        ax.plot(
            np.asarray(s.omega_eps) ** 2,
            s.xi,
            "-" if sign > 0 else "--",
            color=bcols[n],
            lw=widths[n],
            label=rf"$n = {n}$" if sign > 0 else None,
        )
    weak = np.geomspace(1e-2, 0.7, 60)
    ax.plot(weak, weak / 2.0, ":", color="0.45", lw=1.2, label=r"$\xi = \omega_\epsilon^2/2$")
    ax.set_xscale("log")
    ax.set_xlim(1e-2, 1e3)
    ax.set_ylim(0, 1.62)
    ax.set_yticks(np.linspace(0, 1, 6))
    ax.axhline(1.0, color="0.8", lw=0.6)
    ax.set_xlabel(r"$\omega_\epsilon^2$ [-]")
    ax.set_ylabel(r"$\xi$ [-]")
    ax.set_title(r"(b) collapse onto $\omega_\epsilon^2$")
    ax.legend(loc="center left", bbox_to_anchor=(0.0, 0.36))
    # Numbered markers on the curves; a row of profile insets above xi = 1 with the same numbers.
    picks = [(0.1, 1, 0), (0.8, 1, 0), (0.999, 1, 0), (0.5, -1, 0), (0.5, 1, 1)]
    for k, (xi, sign, n) in enumerate(picks, start=1):
        s = hairbed.from_xi(xi, 0.0, sign=sign, n=n)
        ax.plot(s.omega_eps**2, s.xi, "o", ms=4, color="C3")
        ax.annotate(
            str(k),
            (s.omega_eps**2, s.xi),
            xytext=(4, -11),
            textcoords="offset points",
            fontsize=8,
            color="C3",
        )
        ins = ax.inset_axes([0.015 + 0.197 * (k - 1), 0.69, 0.18, 0.29])
        x, z = s.profile(200)
        ins.plot(x, z, "-" if sign > 0 else "--", color=bcols[n], lw=1.2)
        ins.axhline(0, color="0.5", lw=0.6)
        ins.set_aspect("equal", adjustable="datalim")
        ins.set_xticks([])
        ins.set_yticks([])
        ins.text(0.04, 0.96, str(k), transform=ins.transAxes, va="top", fontsize=8, color="C3")
    return fig


@styled
def fig_theta0s(
    eps: float = 0.61,
    theta0s: tuple[float, ...] = (-1.2, -0.8, -0.4, 0.0, 0.4, 0.8, 1.2),
    num: int = 600,
    ax: Any = None,
) -> Figure:
    """Angled hairs: xi against omega_eps for several base angles (Fig. 5).

    Examples
    --------
    >>> fig = fig_theta0s(theta0s=(-0.5, 0.5), num=50)
    >>> len(fig.axes)
    1
    """
    num = check_int(num, "num", 2, MAX_POINTS)
    fig, ax = figure_axes(ax, size=(6.4, 4.0))
    for th0, c in zip(theta0s, colors(len(theta0s), "coolwarm")):
        s = _curve(eps, th0, num=num)
        ax.plot(s.omega_eps, s.xi, color=c, label=rf"$\theta_0 = {th0:+.1f}$")
    ax.axhline(0, color="0.6", lw=0.7)
    ax.set_xscale("log")
    ax.set_xlim(1e-2, 30)
    ax.set_ylim(-1.0, 1.03)
    ax.set_xlabel(r"$\omega_\epsilon$ [-]")
    ax.set_ylabel(r"$\xi = \sin\theta_1$ [-]")
    ax.set_title(rf"Angled hairs, $\epsilon = {eps:g}$")
    ax.legend(loc="center left", bbox_to_anchor=(1.02, 0.5))  # beside: it covers no curve
    return fig


@styled
def fig_profiles(
    omega2s: tuple[float, ...] = (0.5, 2.0, 8.0, 32.0, 128.0),
    eps: float = 0.0,
    num: int = 80,
    ax: Any = None,
) -> Figure:
    """Analytic against finite-difference profiles for several E (Fig. 6).

    Thick coloured lines: the numerical solution, the paper's central differences on ``num``
    segments from theta_i = 0; thin dashed black: the exact (analytic) profile. The inset
    starts the same scheme from theta_i = -0.1 at omega^2 = 32, where it converges to a
    twirling branch, drawn with its exact counterpart.

    Examples
    --------
    >>> fig = fig_profiles(omega2s=(1.0,), num=20)
    >>> len(fig.axes), len(fig.axes[0].child_axes)  # main axes and the inset
    (1, 1)
    """
    from hairbed.numerics import finite_difference

    num = check_int(num, "num", 2, MAX_POINTS)
    fig, ax = figure_axes(ax, size=(6.4, 4.0))
    for w2, c in zip(omega2s, colors(len(omega2s), "plasma")):
        exact = hairbed.solve(w2, eps)
        fd = finite_difference(w2, eps, num=num)
        ax.plot(
            fd.x,
            fd.z,
            "-",
            color=c,
            lw=2.2,
            alpha=0.75,
            label=rf"$\omega^2 = {w2:g}$, $\mathcal{{E}} = {exact.energy:.3g}$",
        )
        x, z = exact.profile(300)
        ax.plot(x, z, "--", color="k", lw=1.0)
    ax.plot([], [], "-", color="0.5", lw=2.2, label=rf"numerical: finite differences, $N = {num}$")
    ax.plot([], [], "--", color="k", lw=1.0, label="exact (analytic)")
    ax.set_xlim(0, 1.9)
    ax.set_ylim(0, 1.05)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x/L$")
    ax.set_ylabel(r"$z/L$")
    ax.set_title(
        rf"Numerical (thick) and exact (dashed) profiles, $\epsilon = {eps:g}$, $\theta_i = 0$"
    )
    ax.legend(loc="upper right", fontsize=7.5)
    ins = ax.inset_axes([0.53, 0.08, 0.44, 0.34])
    w2 = 32.0
    fd = finite_difference(w2, eps, num=num, guess=-0.1)
    twin = [s for s in hairbed.solve_all(w2, eps) if (s.sign, s.n) == (fd.sign, fd.n)]
    ins.plot(fd.x, fd.z, "-", color="C0", lw=2.0, alpha=0.75, label="numerical")
    if twin:
        x, z = twin[0].profile(300)
        ins.plot(x, z, "--", color="k", lw=1.0, label="exact")
    ins.legend(loc="upper right", fontsize=6.5)
    ins.axhline(0, color="0.5", lw=0.6)
    ins.set_aspect("equal", adjustable="datalim")
    ins.tick_params(labelsize=7)
    ins.set_title(rf"$\theta_i = -0.1$, $\omega^2 = {w2:g}$: branch $n = {fd.n}$", fontsize=8)
    return fig
