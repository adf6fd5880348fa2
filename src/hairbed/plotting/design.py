"""The figure of a design (``hairbed design --plot``): a Pareto front, or an optimum's
starts and constraints."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from ._style import figure_axes

__all__ = ["fig_design_result"]


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
