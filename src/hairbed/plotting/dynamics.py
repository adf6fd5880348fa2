"""Figures of the pillar sensor in time (theory.md §14, issues 30 and 31): its Bode plot with
the resonance and the bandwidth marked, its step response, and a film strip of its shape
during the step. Every number drawn is :meth:`hairbed.Pillar.frequency_response`'s or
:meth:`hairbed.Pillar.simulate`'s."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.validation import check_int
from .._warnings import ModelValidityWarning
from ..pillars import Pillar
from ._style import MAX_POINTS, figure_axes

__all__ = ["fig_pillar_bode", "fig_pillar_film", "fig_pillar_step", "sensor_pillar"]


def sensor_pillar(
    fluid: str, length: float = 1e-3, radius: float = 50e-6, youngs_modulus: float = 1e6
) -> Pillar:
    """The README's PDMS pillar sensor (1 mm long, 50 um radius, E = 1 MPa) in ``fluid``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        return Pillar(length=length, radius=radius, youngs_modulus=youngs_modulus, fluid=fluid)


def fig_pillar_bode(
    length: float = 1e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    pillar_density: float = 1000.0,
    frequency_range: tuple[float, float] = (1.0, 5000.0),
    num: int = 400,
    ax: Any = None,
) -> Figure:
    """The Bode plot of a pillar sensor in water and in air: abs(H) [m/Pa] and arg H [deg]
    (unwrapped) against frequency [Hz] (:meth:`hairbed.Pillar.frequency_response`, Sader's
    drag, about the straight pillar), the resonance marked by a dot, the bandwidth (abs(H)/H(0)
    within 5 % and the phase within 5 deg) shaded, and nu/(pi L^2), above which the model's
    quasi-steady drive is an idealisation (its :class:`hairbed.ModelValidityWarning`), as a
    dotted line. Two panels, or ``ax`` a sequence of two Axes.

    Examples
    --------
    >>> fig = fig_pillar_bode(num=20)
    >>> fig.axes[1].get_xlabel()
    'frequency $f$ [Hz]'
    """
    num = check_int(num, "num", 4, MAX_POINTS)
    lo, hi = frequency_range
    if not 0.0 < lo < hi < math.inf:
        raise ValueError(f"frequency_range must satisfy 0 < low < high, got {frequency_range!r}")
    fig, (axm, axp) = figure_axes(ax, 2, 1, size=(6.4, 6.0), sharex=True)
    grid = np.geomspace(lo, hi, num)
    for k, fluid in enumerate(("water", "air")):
        p = sensor_pillar(fluid, length, radius, youngs_modulus)
        with warnings.catch_warnings():  # the validity limit is drawn instead
            warnings.simplefilter("ignore", ModelValidityWarning)
            r = p.frequency_response(grid, pillar_density=pillar_density)
            f = grid
            if lo < r.resonance_frequency < hi:  # the peak itself on the curve
                f = np.sort(np.append(grid, r.resonance_frequency))
                r = p.frequency_response(f, pillar_density=pillar_density)
        color = f"C{k}"
        label = (
            f"{fluid}: $f_r$ = {r.resonance_frequency:.4g} Hz, Q = {r.quality_factor:.3g}, "
            f"band {r.bandwidth:.3g} Hz"
        )
        axm.loglog(f, r.magnitude, color=color, label=label, gid=f"magnitude_{fluid}")
        axp.semilogx(f, np.degrees(np.unwrap(r.phase)), color=color, gid=f"phase_{fluid}")
        if math.isfinite(r.resonance_frequency):
            peak = float(np.abs(r.at([r.resonance_frequency])[0]))
            axm.plot([r.resonance_frequency], [peak], "o", color=color, ms=5,
                     gid=f"resonance_{fluid}")  # fmt: skip
        for a in (axm, axp):
            a.axvspan(lo, r.bandwidth, color=color, alpha=0.12, lw=0, gid=f"bandwidth_{fluid}")
        axm.axvline(r.valid_below, color=color, ls=":", lw=1.0, gid=f"valid_below_{fluid}")
    axm.set_ylabel(r"$|H|$ = tip deflection / $\tau_w$ [m/Pa]")
    axp.set_ylabel(r"phase of $H$ [deg]")
    axp.set_xlabel(r"frequency $f$ [Hz]")
    axm.set_title(
        f"PDMS pillar L = {length * 1e3:.3g} mm, a = {radius * 1e6:.3g} um: shaded, the "
        "bandwidth; dotted, nu/(pi L^2)",
        fontsize=9,
    )
    axm.legend(loc="lower left")
    return fig


def _step_runs(
    length: float,
    radius: float,
    youngs_modulus: float,
    pillar_density: float,
    wall_shear_stress: float,
    periods: float,
    num: int,
) -> tuple[Pillar, Any, Any]:
    """(the pillar in water, the step with inertia, the overdamped step) at ``num`` times
    over ``periods`` of the ringing (2 pi/Im lambda_1 ~ 2 pi sqrt(mu) T/beta_1^2)."""
    from ..sensor_dynamics import time_scale_and_inertia

    p = sensor_pillar("water", length, radius, youngs_modulus)
    t_scale, mu, _ = time_scale_and_inertia(p, pillar_density)
    period = 2.0 * math.pi * math.sqrt(mu) * t_scale / 1.875104068711961**2
    t = np.linspace(0.0, periods * period, num)
    with warnings.catch_warnings():  # the model's validity is the figures' caption's
        warnings.simplefilter("ignore", ModelValidityWarning)
        ringing = p.simulate(wall_shear_stress, t, pillar_density=pillar_density)
        overdamped = p.simulate(wall_shear_stress, t, overdamped=True)
    return p, ringing, overdamped


def fig_pillar_step(
    length: float = 1e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    pillar_density: float = 1000.0,
    wall_shear_stress: float = 5.0,
    periods: float = 6.0,
    num: int = 600,
    ax: Any = None,
) -> Figure:
    """The step response of a pillar sensor in water: the tip deflection [um] against time
    [ms] after the wall shear stress steps from 0 to ``wall_shear_stress`` [Pa]
    (:meth:`hairbed.Pillar.simulate`, the nonlinear model), with its inertia (it rings) and
    overdamped (mu = 0: the elastoviscous relaxation alone), and the static deflection
    (:meth:`hairbed.Pillar.deform`) dashed. The model as it stands: at 5 Pa this pillar's
    Reynolds number (478) is far above the Stokes drag's range and it stands 70 wall
    units tall, which :meth:`hairbed.Pillar.simulate` warns of (silenced here).

    Examples
    --------
    >>> fig = fig_pillar_step(num=40, periods=1.0)
    >>> fig.axes[0].get_xlabel()
    'time $t$ [ms]'
    """
    num = check_int(num, "num", 4, MAX_POINTS)
    if not (math.isfinite(periods) and periods > 0.0):
        raise ValueError(f"periods must be a finite number > 0, got {periods!r}")
    p, ring, over = _step_runs(
        length, radius, youngs_modulus, pillar_density, wall_shear_stress, periods, num
    )
    fig, ax = figure_axes(ax, size=(6.4, 4.0))
    ms = 1e3 * ring.time
    ax.plot(ms, 1e6 * ring.tip_deflection, color="C0", gid="ringing",
            label=f"with inertia (mu = {ring.inertia_number:.3g})")  # fmt: skip
    ax.plot(ms, 1e6 * over.tip_deflection, color="C1", gid="overdamped",
            label="overdamped (mu = 0)")  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        static = float(p.deform(wall_shear_stress).tip_deflection)
    ax.axhline(1e6 * static, color="0.4", ls="--", lw=1.0, gid="static", label="static")
    ax.set_xlabel(r"time $t$ [ms]")
    ax.set_ylabel(r"tip deflection [$\mu$m]")
    ax.set_title(
        f"step of the wall shear stress to {wall_shear_stress:g} Pa, PDMS pillar in water "
        f"(T = {1e3 * ring.time_scale:.3g} ms)",
        fontsize=9,
    )
    ax.legend(loc="lower right")
    for run in (ring, over):
        if not run.success:
            ax.text(0.02, 0.95, f"stopped: {run.message}", transform=ax.transAxes, fontsize=8)
    return fig


def fig_pillar_film(
    length: float = 1e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    pillar_density: float = 1000.0,
    wall_shear_stress: float = 5.0,
    periods: float = 1.5,
    frames: int = 8,
    ax: Any = None,
) -> Figure:
    """A film strip of a pillar sensor's shape during a step of the wall shear stress in
    water (:meth:`hairbed.Pillar.simulate` with inertia): ``frames`` panels at equal times
    over ``periods`` of the ringing, each with the static shape at the same stress
    (:meth:`hairbed.Pillar.deform`'s tip; the dynamics' shape at the end) in grey.

    Examples
    --------
    >>> fig = fig_pillar_film(frames=3, periods=0.5)
    >>> len(fig.axes)
    3
    """
    frames = check_int(frames, "frames", 2, 40)
    if not (math.isfinite(periods) and periods > 0.0):
        raise ValueError(f"periods must be a finite number > 0, got {periods!r}")
    p, ring, _ = _step_runs(
        length, radius, youngs_modulus, pillar_density, wall_shear_stress, periods, frames
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        static = p.deform(wall_shear_stress)
    fig, axes = figure_axes(ax, 1, frames, size=(1.3 * frames + 0.8, 3.4))
    xs, zs = 1e6 * ring.x, 1e6 * ring.z
    lo = min(0.0, float(np.nanmin(xs)))
    hi = max(float(np.nanmax(xs)), 1e6 * float(static.tip_deflection))
    pad = 0.1 * 1e6 * length
    for k, a in enumerate(np.ravel(axes)):
        a.plot([1e6 * static.tip_deflection], [1e6 * static.tip_height], "x", color="0.5",
               gid="static_tip")  # fmt: skip
        a.plot(xs[k], zs[k], color="C0", lw=2.0, gid=f"frame_{k}")
        a.axhline(0.0, color="k", lw=0.8)
        a.set_xlim(lo - pad, hi + pad)
        a.set_ylim(-0.5 * pad, 1e6 * length + pad)
        a.set_aspect("equal", adjustable="box")
        if k:
            a.tick_params(labelleft=False)
        a.set_title(f"{1e3 * ring.time[k]:.3g} ms", fontsize=8)
        a.set_xlabel(r"$x$ [$\mu$m]", fontsize=8)
        a.tick_params(labelsize=7)
    np.ravel(axes)[0].set_ylabel(r"$z$ [$\mu$m]")
    fig.suptitle(
        f"the pillar's shape after a step to {wall_shear_stress:g} Pa in water "
        "(x: the static tip)",
        fontsize=9,
    )
    return fig
