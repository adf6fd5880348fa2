"""Shared look of the figures: one place for sizes, fonts and colours."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import matplotlib
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["RC", "colors", "new_figure", "styled"]

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


def styled(func: Callable[..., Figure]) -> Callable[..., Figure]:
    """Run a figure function under the shared rcParams (read when artists are created)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Figure:
        with matplotlib.rc_context(RC):
            return func(*args, **kwargs)

    return wrapper
