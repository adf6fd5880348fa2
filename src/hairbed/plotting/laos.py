"""The porous bed under large-amplitude oscillatory shear (issue 31 §2b): Lissajous-Bowditch
curves at several strain amplitudes, and a Pipkin diagram (the curves over frequency and
amplitude). Every number drawn is :func:`hairbed.rheometer.large_amplitude_shear`'s (its
:meth:`~hairbed.rheometer.LAOSAnalysis.lissajous`, summed from the harmonics)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.validation import check_int
from ..rheometer import large_amplitude_shear
from ._style import figure_axes

__all__ = ["fig_bed_lissajous", "fig_pipkin"]


def _curves(omega: float, gamma0: float, kw: dict[str, Any], num: int) -> Any:
    r = large_amplitude_shear(omega, gamma0, **kw)
    if r.analysis is None or r.status < 0:
        return None, r
    return r.analysis.lissajous(num), r


def fig_bed_lissajous(
    omega: float = 1.0,
    strain_amplitudes: tuple[float, ...] = (3.0, 10.0, 30.0),
    kappa: float = 0.1,
    eps: float = 0.5,
    theta0: float = 0.4,
    num: int = 181,
    ax: Any = None,
) -> Figure:
    """Lissajous-Bowditch curves of the porous bed's periodic state at angular frequency
    ``omega`` [1/T] and each strain amplitude gamma0 [-]. The bed's stress is nearly all
    viscous (G'/G'' ~ 1e-3 here), so the elastic view shows Cho's elastic stress sigma' over
    its own largest value against gamma/gamma0 (its shape is the hairs' nonlinear
    elasticity; a straight line is linear), the whole stress over its largest value dotted;
    the viscous view the whole stress against the strain rate over its amplitude, the viscous
    stress dashed. A tilted bed (``theta0``) is asymmetric. Two panels, or ``ax`` a sequence
    of two Axes.

    Examples
    --------
    >>> fig = fig_bed_lissajous(strain_amplitudes=(1.0,), num=33)
    >>> fig.axes[0].get_xlabel()
    'strain $\\\\gamma/\\\\gamma_0$ [-]'
    """
    num = check_int(num, "num", 9, 4001)
    fig, (axe, axv) = figure_axes(ax, 1, 2, size=(9.0, 4.0))
    kw = {"eps": eps, "kappa": kappa, "theta0": theta0}
    for j, g0 in enumerate(strain_amplitudes):
        c, r = _curves(omega, float(g0), kw, num)
        color = f"C{j}"
        if c is None:
            axe.plot([], [], color=color, label=rf"$\gamma_0$ = {g0:g}: {r.message}")
            continue
        big = float(np.max(np.abs(c["total"])))
        el = float(np.max(np.abs(c["elastic"]))) or 1.0
        an = r.analysis
        label = (rf"$\gamma_0$ = {g0:g}: $I_3/I_1$ = {an.relative_intensity[2]:.2g}, "
                 rf"$S$ = {an.stiffening_ratio:.2g}")  # fmt: skip
        x, xd = c["strain"] / g0, c["strain_rate"] / (g0 * omega)
        axe.plot(x, c["elastic"] / el, color=color, label=label, gid=f"elastic_{j}")
        axe.plot(x, c["total"] / big, color=color, ls=":", lw=0.8, gid=f"elastic_view_{j}")
        axv.plot(xd, c["total"] / big, color=color, gid=f"viscous_view_{j}")
        axv.plot(xd, c["viscous"] / big, color=color, ls="--", lw=1.0, gid=f"viscous_{j}")
    axe.set_xlabel(r"strain $\gamma/\gamma_0$ [-]")
    axv.set_xlabel(r"strain rate $\dot\gamma/(\gamma_0\omega)$ [-]")
    axe.set_ylabel(r"elastic stress $\sigma'/\max\,|\sigma'|$ (dotted: $\sigma/\max\,|\sigma|$)")
    axv.set_ylabel(r"$\sigma/\max\,|\sigma|$ (dashed: viscous $\sigma''$)")
    axe.set_title(
        rf"bed $\kappa$ = {kappa:g}, $\epsilon$ = {eps:g}, $\theta_0$ = {theta0:g}, "
        rf"$\omega T$ = {omega:g}",
        fontsize=9,
    )
    axe.legend(loc="upper left", fontsize=7)
    for a in (axe, axv):
        a.axhline(0.0, color="0.7", lw=0.6)
        a.axvline(0.0, color="0.7", lw=0.6)
    return fig


def fig_pipkin(
    omegas: tuple[float, ...] = (0.1, 0.3, 1.0),
    strain_amplitudes: tuple[float, ...] = (3.0, 10.0, 30.0),
    kappa: float = 0.1,
    eps: float = 0.5,
    theta0: float = 0.4,
    num: int = 121,
    ax: Any = None,
) -> Figure:
    """A Pipkin diagram of the porous bed: at each angular frequency [1/T] (columns) and strain
    amplitude [-] (rows, the largest on top) the elastic Lissajous curve, Cho's elastic
    stress over its largest value against gamma/gamma0 (black; the whole stress, nearly all
    viscous, grey), with I_3/I_1 and Ewoldt's stiffening ratio S = (G'_L - G'_M)/G'_L; a
    cell whose run found no periodic state says so. A grid of
    panels, or ``ax`` a sequence of len(omegas) x len(strain_amplitudes) Axes (row-major, top
    row first).

    Examples
    --------
    >>> fig = fig_pipkin(omegas=(1.0,), strain_amplitudes=(1.0,), num=33)
    >>> len(fig.axes)
    1
    """
    num = check_int(num, "num", 9, 4001)
    om = [float(w) for w in omegas]
    ga = sorted((float(g) for g in strain_amplitudes), reverse=True)
    if not om or not ga:
        raise ValueError("omegas and strain_amplitudes must each hold at least one value")
    size = (2.4 * len(om) + 0.8, 2.0 * len(ga) + 0.8)
    fig, axes = figure_axes(ax, len(ga), len(om), size=size, squeeze=False)
    grid = np.asarray(axes, dtype=object).reshape(len(ga), len(om))
    kw = {"eps": eps, "kappa": kappa, "theta0": theta0}
    for i, g0 in enumerate(ga):
        for j, w in enumerate(om):
            a = grid[i, j]
            c, r = _curves(w, g0, kw, num)
            if c is None:
                a.text(0.5, 0.5, f"no periodic state\n(status {r.status})", ha="center",
                       va="center", fontsize=7, transform=a.transAxes)  # fmt: skip
            else:
                big = float(np.max(np.abs(c["total"])))
                el = float(np.max(np.abs(c["elastic"]))) or 1.0
                a.plot(c["strain"] / g0, c["total"] / big, color="0.7", lw=0.8)
                a.plot(c["strain"] / g0, c["elastic"] / el, color="k", lw=1.2,
                       gid=f"pipkin_{i}_{j}")  # fmt: skip
                an = r.analysis
                s = an.stiffening_ratio
                a.text(0.03, 0.97, f"I3/I1 {an.relative_intensity[2]:.1e}\nS {s:.2g}"
                       if math.isfinite(s) else f"I3/I1 {an.relative_intensity[2]:.1e}",
                       ha="left", va="top", fontsize=6, transform=a.transAxes)  # fmt: skip
            a.set_xticks([])
            a.set_yticks([])
            a.set_title(rf"$\omega T$ = {w:g}, $\gamma_0$ = {g0:g}", fontsize=8)
    fig.suptitle(
        rf"Pipkin diagram: elastic $\sigma'$ against $\gamma$ (normalised); "
        rf"bed $\kappa$ = {kappa:g}, "
        rf"$\epsilon$ = {eps:g}, $\theta_0$ = {theta0:g}",
        fontsize=9,
    )
    return fig
