"""Shared look of the figures: one place for sizes, fonts and colours."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import matplotlib
import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["MAX_POINTS", "RC", "colors", "figure_axes", "new_figure", "styled"]

#: The most points a figure's curve or grid may take (``num``, ``n_theta``, ...): more than a
#: figure can show, 10 inches at the largest resolution of ``make_all`` (1200 dpi) being
#: 12 000 pixels.
MAX_POINTS = 100_000

RC: Any = {  # rcParams (matplotlib types its keys as literals)
    "font.size": 10,
    "axes.labelsize": 11,
    "axes.titlesize": 11,
    "legend.fontsize": 8.5,
    "legend.framealpha": 0.9,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": True,
    "ytick.right": True,
    "lines.linewidth": 1.6,
    "savefig.bbox": "tight",
    "mathtext.fontset": "cm",
}


def colors(k: int, cmap: str = "viridis") -> list[Any]:
    """k distinguishable colours from a perceptually uniform map (ends trimmed)."""
    cm = matplotlib.colormaps[cmap]
    if k == 1:
        return [cm(0.35)]
    return [cm(0.05 + 0.8 * i / (k - 1)) for i in range(k)]


def new_figure(
    nrows: int = 1, ncols: int = 1, *, size: tuple[float, float] = (5.0, 3.8), **kw: Any
) -> tuple[Figure, Any]:
    """A Figure on an Agg canvas and its axes.

    Not registered with pyplot and the global backend is left alone: nothing is shown, nothing
    leaks, and a user's interactive session keeps its backend.
    """
    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, **kw)
    return fig, axes


def figure_axes(
    ax: Any,
    nrows: int = 1,
    ncols: int = 1,
    *,
    size: tuple[float, float] = (5.0, 3.8),
    at_least: bool = False,
    **kw: Any,
) -> tuple[Any, Any]:
    """The figure and axes a figure function draws into: new ones when ``ax`` is None, else
    those given (one Axes for a one-panel figure, a sequence of ``nrows * ncols`` Axes, or at
    least that many with ``at_least``, for a figure of several panels).

    Raises
    ------
    TypeError
        If ``ax`` is not an Axes (or a sequence of the right number of Axes).
    """
    count = nrows * ncols
    if ax is None:
        return new_figure(nrows, ncols, size=size, **kw)
    if count == 1 and not at_least:
        if not isinstance(ax, Axes):
            raise TypeError(f"ax must be a matplotlib Axes, got {type(ax).__name__}")
        return ax.figure, ax
    axes = [ax] if isinstance(ax, Axes) else list(np.ravel(np.asarray(ax, dtype=object)))
    enough = len(axes) >= count if at_least else len(axes) == count
    if not enough or not all(isinstance(a, Axes) for a in axes):
        need = f"at least {count}" if at_least else f"{count}"
        raise TypeError(f"ax must be a sequence of {need} matplotlib Axes (one per panel)")
    arr = np.empty(len(axes), dtype=object)
    arr[:] = axes
    if kw.get("squeeze", True) and not at_least and (nrows == 1 or ncols == 1):
        return axes[0].figure, arr
    return axes[0].figure, arr.reshape(-1, ncols) if not at_least else arr.reshape(1, -1)


def styled(func: Callable[..., Figure]) -> Callable[..., Figure]:
    """Run a figure function under the shared rcParams (read when artists are created)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Figure:
        with matplotlib.rc_context(RC):
            return func(*args, **kwargs)

    return wrapper
