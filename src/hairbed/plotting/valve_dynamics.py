"""Figures of the valve and the pump in time (theory.md §15, issue 31 section 3): the flow
after a step in the pressure drop, and the net flow of a pulsing drop against its frequency.
Every number drawn is :func:`hairbed.valve_dynamics.valve_switching`'s or
:func:`hairbed.valve_dynamics.pump_net_flow`'s."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.validation import check_int
from ..units import HairBed
from ..valve_dynamics import bed_time_scales, pump_net_flow, valve_switching
from ._style import MAX_POINTS, figure_axes

__all__ = ["fig_valve_pump", "pump_bed"]


def pump_bed(base_angle: float = 0.5) -> HairBed:
    """The figure's bed: 1 mm hairs of radius 50 um, E = 1 MPa, 250 um apart, in a 2 mm
    channel of a fluid of 1 Pa s, leaning ``base_angle`` along +x (the porous model)."""
    return HairBed(
        length=1e-3,
        radius=50e-6,
        youngs_modulus=1e6,
        channel_height=2e-3,
        viscosity=1.0,
        spacing=250e-6,
        base_angle=base_angle,
        model="porous",
    )


def fig_valve_pump(
    base_angle: float = 0.5,
    channel_length: float = 0.01,
    pressure_drop: float = 300.0,
    amplitudes: tuple[float, ...] = (300.0,),
    frequency_range: tuple[float, float] = (1e-2, 1e2),
    num: int = 5,
    ax: Any = None,
) -> Figure:
    """A leaning bed as a valve in time: (a) the flow per unit width after a step of the
    pressure drop from 0 to ``pressure_drop`` [Pa], over its final value, against t/T, the
    rise and settling times marked; (b) the net flow of a zero-mean drop A sin(2 pi f t)
    against f T for each amplitude, its quasi-static limit (the phase average of the steady
    valve curve) dashed. T = zeta_perp L^4/(E I). Two panels, or ``ax`` a sequence of two
    Axes.

    Examples
    --------
    >>> fig = fig_valve_pump(num=2, amplitudes=(300.0,))
    >>> fig.axes[1].get_xlabel()
    'frequency $f T$'
    """
    num = check_int(num, "num", 2, MAX_POINTS)
    lo, hi = frequency_range
    if not 0.0 < lo < hi < math.inf:
        raise ValueError(f"frequency_range must satisfy 0 < low < high, got {frequency_range!r}")
    bed = pump_bed(base_angle)
    t_scale = bed_time_scales(bed)["time_scale"]
    fig, (axs, axn) = figure_axes(ax, 1, 2, size=(10.0, 4.0))
    r = valve_switching(bed, pressure_drop, channel_length, duration=0.1 * t_scale, num_times=401)
    axs.plot(r.time / t_scale, r.flow_rate / r.final_flow_rate, color="C0", gid="switch_flow")
    axs.axhline(1.0, color="0.5", lw=0.8)
    for name, value, style in (("rise", r.rise_time, ":"), ("settling", r.settling_time, "--")):
        if math.isfinite(value):
            axs.axvline(value / t_scale, color="C3", ls=style, lw=1.0,
                        label=f"{name} time {value:.3g} s", gid=f"{name}_time")  # fmt: skip
    axs.set_xlabel("time $t/T$")
    axs.set_ylabel("flow rate $Q'(t)/Q'(\\infty)$")
    axs.set_title(f"(a) a step of the drop to {pressure_drop:g} Pa", fontsize=10)
    axs.legend(fontsize=8)
    freqs = np.geomspace(lo, hi, num) / t_scale
    res = pump_net_flow(bed, np.asarray(amplitudes, dtype=float), freqs, channel_length,
                        samples_per_period=32)  # fmt: skip
    for k, a in enumerate(res.amplitude):
        color = f"C{k}"
        axn.semilogx(freqs * t_scale, res.net_flow[k] * 1e6, "o-", color=color, ms=4,
                     label=f"A = {a:g} Pa", gid=f"net_flow_{k}")  # fmt: skip
        axn.axhline(res.quasi_static_net_flow[k] * 1e6, color=color, ls="--", lw=0.8,
                    gid=f"quasi_static_{k}")  # fmt: skip
    axn.set_xlabel("frequency $f T$")
    axn.set_ylabel("net flow rate [mm$^2$/s]")
    axn.set_title("(b) the pump: net flow of $A \\sin(2\\pi f t)$", fontsize=10)
    axn.legend(fontsize=8)
    return fig
