"""Figures of hairbed: the paper's, recomputed from the exact solution, and new ones.

Every ``fig_*`` function returns a :class:`matplotlib.figure.Figure` drawn with the Agg
backend (not registered with pyplot, so nothing is shown and nothing leaks). This is the only
part of the package that imports matplotlib; the numerical core never imports it.

Examples
--------
>>> from hairbed.plotting import fig_theta0s
>>> fig = fig_theta0s(theta0s=(0.0,), num=40)
>>> fig.axes[0].get_xlabel()
'$\\\\omega_\\\\epsilon$ [-]'

Write every figure into a folder:

>>> import tempfile
>>> paths = make_all(tempfile.mkdtemp(), only=["fig_model"], verbose=False)
>>> [p.name for p in paths]
['model.png']
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

from matplotlib.figure import Figure

from ..safe_files import atomic_path
from .extra import (
    fig_bistability,
    fig_calibration,
    fig_fd_convergence,
    fig_hysteresis,
    fig_physical_units,
    fig_rheology,
    fig_speed,
    fig_states,
    fig_twirling,
)
from .paper import (
    fig_model,
    fig_pendulum,
    fig_phase_portrait,
    fig_profiles,
    fig_solution,
    fig_theta0s,
)

__all__ = [
    "FIGURES",
    "fig_bistability",
    "fig_calibration",
    "fig_fd_convergence",
    "fig_hysteresis",
    "fig_model",
    "fig_pendulum",
    "fig_phase_portrait",
    "fig_physical_units",
    "fig_profiles",
    "fig_rheology",
    "fig_solution",
    "fig_speed",
    "fig_states",
    "fig_theta0s",
    "fig_twirling",
    "make_all",
]

#: File stem -> figure function, in the order of the guide (paper first).
FIGURES: dict[str, Callable[[], Figure]] = {
    "model": fig_model,
    "pendulum": fig_pendulum,
    "phase_portrait": fig_phase_portrait,
    "solution": fig_solution,
    "theta0s": fig_theta0s,
    "profiles": fig_profiles,
    "twirling": fig_twirling,
    "bistability": fig_bistability,
    "hysteresis": fig_hysteresis,
    "rheology": fig_rheology,
    "calibration": fig_calibration,
    "physical_units": fig_physical_units,
    "fd_convergence": fig_fd_convergence,
    "speed": fig_speed,
}


def make_all(
    out_dir: str | Path,
    *,
    dpi: int = 150,
    only: Iterable[str] | None = None,
    verbose: bool = True,
) -> list[Path]:
    """Write every figure as ``<out_dir>/<name>.png`` and return the paths written.

    Parameters
    ----------
    out_dir : str or Path
        Folder, created if needed.
    dpi : int, optional
        Resolution of the PNGs [dots per inch].
    only : iterable of str, optional
        Names (keys of :data:`FIGURES`, with or without the ``fig_`` prefix) to make.
    verbose : bool, optional
        Print one line per figure on stdout.

    Returns
    -------
    list of Path
        The files written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    wanted = None if only is None else {name.removeprefix("fig_") for name in only}
    unknown = set() if wanted is None else wanted - set(FIGURES)
    if unknown:
        raise ValueError(f"unknown figure name(s) {sorted(unknown)}; choose from {list(FIGURES)}")
    paths = []
    for name, func in FIGURES.items():
        if wanted is not None and name not in wanted:
            continue
        fig = func()
        path = out / f"{name}.png"
        with atomic_path(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=dpi, format="png")
        paths.append(path)
        if verbose:
            print(f"wrote {path}")
    return paths
