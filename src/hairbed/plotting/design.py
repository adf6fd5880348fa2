"""The figures of a design: what ``hairbed design --plot`` computed (a Pareto front, or an
optimum's starts and constraints), and the gallery's worked valve and sensor designs."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.validation import check_int
from ._style import MAX_POINTS, figure_axes

__all__ = [
    "fig_design_result",
    "fig_sensor_design",
    "fig_valve_design",
    "sensor_design_example",
    "valve_design_example",
]


def fig_design_result(result: Any, ax: Any = None) -> Figure:
    """What :mod:`hairbed.design` computed, drawn.

    A :class:`hairbed.design.ParetoFront` as the second objective against the first, each
    point of the front marked (failed points left out). A
    :class:`hairbed.design.DesignResult` in two panels: the objective reached from each
    start (its local optima, the best filled), and every constraint's value over its bound
    (1 is the bound; active constraints filled, validity constraints grey). ``ax``: one Axes
    for a front, two for an optimum.

    Examples
    --------
    >>> import hairbed
    >>> from hairbed import design
    >>> bed = hairbed.HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6,
    ...                       channel_height=2e-3, viscosity=1.0, spacing=250e-6)
    >>> res = design.optimise(bed, design.Variable("base_angle", 0.0, 1.4),
    ...                       design.diodicity(1000.0, 0.01), sense="max", starts=2)
    >>> len(fig_design_result(res).axes)
    2
    """
    from hairbed.design import DesignResult, ParetoFront

    if isinstance(result, ParetoFront):
        fig, axp = figure_axes(ax, 1, 1, size=(5.2, 4.0))
        ok = np.asarray(result.success, dtype=bool)
        axp.plot(result.first[ok], result.second[ok], "o-", color="C0", ms=4)
        axp.set_xlabel(f"{result.first_name} ({result.senses[0]})")
        axp.set_ylabel(f"{result.second_name} ({result.senses[1]})")
        axp.set_title("Pareto front (epsilon-constraint)", fontsize=9)
        return fig
    if not isinstance(result, DesignResult):
        raise TypeError(
            f"result must be a hairbed.design DesignResult or ParetoFront, got "
            f"{type(result).__name__}"
        )
    fig, (axs, axc) = figure_axes(ax, 1, 2, size=(10.0, 3.9))
    optima = np.asarray(result.local_optima, dtype=float)
    if optima.size:
        axs.plot(np.arange(1, optima.size + 1), optima, "o", color="C0", mfc="none")
        axs.plot([1], optima[:1], "o", color="C0")
    axs.set_xlabel("converged start (best first)")
    axs.set_ylabel(result.objective_name)
    axs.set_title(f"{result.starts} starts: spread {result.spread:.3g}", fontsize=9)
    labels = [c.label for c in result.constraints]
    ratios = [c.value / c.bound if c.bound != 0 else np.nan for c in result.constraints]
    colors = ["0.6" if c.validity else "C3" for c in result.constraints]
    y = np.arange(len(labels))
    for yi, r, col, c in zip(y, ratios, colors, result.constraints, strict=True):
        axc.plot([r], [yi], "o", color=col, mfc=col if c.active else "none")
    axc.axvline(1.0, color="k", lw=0.6)
    axc.set_yticks(y, labels, fontsize=7)
    axc.set_xlabel("value / bound (1: on the bound)")
    axc.set_title(result.message, fontsize=8)
    return fig


def _valve_bed() -> Any:
    from hairbed import HairBed

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                       viscosity=1.0, spacing=250e-6, base_angle=0.5, density=1200.0)  # fmt: skip


def _sensor_pillar() -> Any:
    from hairbed import Pillar

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Pillar(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=0.1,
                      density=1000.0)  # fmt: skip


def valve_design_example(
    pressure_drop: float = 1000.0,
    channel_length: float = 0.01,
    resistance_budget: float = 2.5,
    points: int = 12,
    starts: int = 4,
) -> tuple[Any, Any]:
    """The worked valve design of :func:`fig_valve_design`: (its Pareto front, its chosen
    design), both from :mod:`hairbed.design`.

    A bed of 1 mm hairs (radius 50 um, E = 1 MPa, spacing 250 um) in a 2 mm channel of
    glycerol-like oil (eta = 1 Pa s, rho = 1200 kg/m^3), its base angle in [0, 1.4] rad and
    its length in [0.6, 1.5] mm designed: the diodicity at ``pressure_drop`` [Pa] over
    ``channel_length`` [m] (maximised) against the resistance ratio R/R0 there (minimised),
    ``points`` points by the epsilon-constraint method; the chosen design is the most
    diodic whose R/R0 <= ``resistance_budget``, with the model's validity.
    """
    from hairbed import design as D

    bed = _valve_bed()
    variables = [D.Variable("base_angle", 0.0, 1.4), D.Variable("length", 0.6e-3, 1.5e-3)]
    di = D.diodicity(pressure_drop, channel_length)
    rr = D.resistance_ratio(pressure_drop, channel_length)
    front = D.pareto_front(bed, variables, di, rr, senses=("max", "min"), points=points,
                           starts=starts)  # fmt: skip
    chosen = D.optimise(bed, variables, di, constraints=[rr <= resistance_budget],
                        sense="max", starts=starts)  # fmt: skip
    return front, chosen


def sensor_design_example(
    rtol: float = 0.05,
    min_range: float = 1.0,
    points: int = 10,
    starts: int = 4,
) -> tuple[Any, Any]:
    """The worked sensor design of :func:`fig_sensor_design`: (its Pareto front, its chosen
    design), both from :mod:`hairbed.design`.

    A pillar of radius 25 um in the viscous sublayer of an oil (eta = 0.1 Pa s,
    rho = 1000 kg/m^3), its length in [300, 800] um and its Young's modulus in
    [0.5, 2] MPa (log scale) designed: the sensitivity of the linear calibration (the tip
    deflection per wall shear stress as tau_w -> 0, maximised) against the end of the linear
    range to ``rtol`` (maximised), ``points`` points by the epsilon-constraint method; the
    chosen design is the most sensitive whose linear range reaches ``min_range`` [Pa], with
    the model's validity.
    """
    from hairbed import design as D

    pillar = _sensor_pillar()
    variables = [
        D.Variable("length", 300e-6, 800e-6),
        D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    ]
    sens, rng = D.linear_sensitivity(), D.linear_range(rtol)
    front = D.pareto_front(pillar, variables, sens, rng, senses=("max", "max"), points=points,
                           starts=starts)  # fmt: skip
    chosen = D.optimise(pillar, variables, sens, constraints=[rng >= min_range], sense="max",
                        starts=starts)  # fmt: skip
    return front, chosen


def _front_panel(axp: Any, front: Any, chosen: Any, second: Any, scale: tuple[float, float],
                 log: bool) -> None:  # fmt: skip
    ok = np.asarray(front.success, dtype=bool)
    axp.plot(front.second[ok] * scale[1], front.first[ok] * scale[0], "o-", color="C0", ms=4,
             label="Pareto front")  # fmt: skip
    if chosen.success:
        axp.plot([second(chosen.design) * scale[1]], [chosen.objective * scale[0]], "*",
                 color="C3", ms=12, label="chosen design")  # fmt: skip
    if log:
        axp.set_xscale("log")
        axp.set_yscale("log")
    axp.legend(fontsize=8, loc="best")


def fig_valve_design(
    pressure_drop: float = 1000.0,
    channel_length: float = 0.01,
    resistance_budget: float = 2.5,
    points: int = 12,
    num: int = 81,
    ax: Any = None,
) -> Figure:
    """A worked valve design (:mod:`hairbed.design`): the Pareto front and the chosen valve.

    The bed of :func:`valve_design_example` (1 mm hairs in a 2 mm channel), its base angle
    and hair length designed. (a) The Pareto front of the diodicity Di at ``pressure_drop``
    [Pa] over ``channel_length`` [m] (maximised) against the resistance ratio R/R0 there
    (minimised), ``points`` points (:func:`hairbed.design.pareto_front`,
    epsilon-constraint); the star is the chosen design, the most diodic with
    R/R0 <= ``resistance_budget`` (:func:`hairbed.design.optimise`). (b) The chosen
    design's valve curve (:func:`hairbed.valve.valve_curve`): the flow rate per unit width
    Q' against dp over +-2 ``pressure_drop`` at ``num`` drops, the starting bed's dashed,
    the empty channel's dotted, the working drops +-dp marked. ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_valve_design(points=3, num=9)
    >>> len(fig.axes)
    2
    """
    from hairbed import design as D
    from hairbed.valve import valve_curve

    num = check_int(num, "num", 3, MAX_POINTS)
    points = check_int(points, "points", 2, MAX_POINTS)

    front, chosen = valve_design_example(pressure_drop, channel_length, resistance_budget,
                                         points)  # fmt: skip
    fig, (axp, axv) = figure_axes(ax, 1, 2, size=(10.0, 4.0))
    rr = D.resistance_ratio(pressure_drop, channel_length)
    _front_panel(axp, front, chosen, rr, (1.0, 1.0), log=False)
    axp.axvline(resistance_budget, color="0.5", lw=0.8, ls=":")
    axp.set_xlabel(f"resistance ratio R/R0 at {pressure_drop:g} Pa [-] (min)")
    axp.set_ylabel(f"diodicity at {pressure_drop:g} Pa [-] (max)")
    axp.set_title("(a) Pareto front, epsilon-constraint", fontsize=9)
    dp = np.linspace(-2.0 * pressure_drop, 2.0 * pressure_drop, num)
    if chosen.success:
        curve = valve_curve(chosen.design, dp, channel_length)
        axv.plot(dp, np.asarray(curve.flow_rate) * 1e6, color="C3", label="chosen design")
        axv.plot(dp, np.asarray(curve.empty_flow_rate) * 1e6, ":", color="0.4",
                 label="empty channel")  # fmt: skip
        at = valve_curve(chosen.design, np.array([pressure_drop, -pressure_drop]),
                         channel_length)  # fmt: skip
        axv.plot(at.pressure_drop, np.asarray(at.flow_rate) * 1e6, "o", color="C3", mfc="white")
        v = chosen.variables
        axv.set_title(
            f"(b) base angle {v['base_angle']:.3f} rad, L = {v['length'] * 1e3:.3f} mm: "
            f"Di = {chosen.objective:.3g}",
            fontsize=9,
        )
    base = valve_curve(_valve_bed(), dp, channel_length)
    axv.plot(dp, np.asarray(base.flow_rate) * 1e6, "--", color="C0", lw=1.0,
             label="starting bed")  # fmt: skip
    axv.set_xlabel("pressure drop dp [Pa]")
    axv.set_ylabel("flow rate per unit width Q' [mm^2/s]")
    axv.legend(fontsize=8, loc="upper left")
    return fig


def fig_sensor_design(
    rtol: float = 0.05,
    min_range: float = 1.0,
    points: int = 10,
    num: int = 61,
    ax: Any = None,
) -> Figure:
    """A worked sensor design (:mod:`hairbed.design`): the Pareto front and the chosen
    pillar's calibration curve.

    The pillar of :func:`sensor_design_example` (radius 25 um in the viscous sublayer), its
    length and Young's modulus designed. (a) The Pareto front of the linear calibration's
    sensitivity [um/Pa] (maximised) against the end of the linear range to ``rtol`` [Pa]
    (maximised), ``points`` points (:func:`hairbed.design.pareto_front`); the star is the
    chosen design, the most sensitive whose linear range reaches ``min_range`` [Pa]
    (:func:`hairbed.design.optimise`). (b) The chosen pillar's calibration curve: its exact
    tip deflection (:meth:`hairbed.Pillar.tip_deflection`, solid) and the linear formula
    (dashed) against tau_w over twice its linear range at ``num`` stresses, the end of the
    range (where the linear formula's reading is ``rtol`` off) marked. ``ax``: two Axes.

    Examples
    --------
    >>> fig = fig_sensor_design(points=3, num=9)
    >>> len(fig.axes)
    2
    """
    from hairbed import design as D

    num = check_int(num, "num", 3, MAX_POINTS)
    points = check_int(points, "points", 2, MAX_POINTS)
    front, chosen = sensor_design_example(rtol, min_range, points)
    fig, (axp, axc) = figure_axes(ax, 1, 2, size=(10.0, 4.0))
    rng_q = D.linear_range(rtol)
    _front_panel(axp, front, chosen, rng_q, (1e6, 1.0), log=True)
    axp.axvline(min_range, color="0.5", lw=0.8, ls=":")
    axp.set_xlabel(f"end of the linear range ({rtol:g}) [Pa] (max)")
    axp.set_ylabel("sensitivity [um/Pa] (max)")
    axp.set_title("(a) Pareto front, epsilon-constraint", fontsize=9)
    if chosen.success:
        p = chosen.design
        end = p.linear_range(rtol)
        tau = np.linspace(0.0, 2.0 * end.wall_shear_stress, num)
        axc.plot(tau, np.asarray(p.tip_deflection(tau)) * 1e6, color="C3", label="exact")
        axc.plot(tau, chosen.objective * tau * 1e6, "--", color="0.3", label="linear formula")
        axc.plot([end.wall_shear_stress], [end.tip_deflection * 1e6], "o", color="C3",
                 mfc="white", label=f"linear range end ({rtol:g})")  # fmt: skip
        v = chosen.variables
        axc.set_title(
            f"(b) L = {v['length'] * 1e6:.0f} um, E = {v['youngs_modulus'] / 1e6:.3g} MPa: "
            f"{chosen.objective * 1e6:.3g} um/Pa to {end.wall_shear_stress:.3g} Pa",
            fontsize=9,
        )
    axc.set_xlabel("wall shear stress tau_w [Pa]")
    axc.set_ylabel("tip deflection [um]")
    axc.legend(fontsize=8, loc="upper left")
    return fig
