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

import inspect
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from .._core.validation import check_int
from ..safe_files import atomic_path
from .design import fig_sensor_design, fig_valve_design
from .dynamics import fig_pillar_bode, fig_pillar_film, fig_pillar_step
from .extra import (
    fig_bistability,
    fig_calibration,
    fig_fd_convergence,
    fig_hysteresis,
    fig_physical_units,
    fig_pillar_calibration,
    fig_pillar_snap,
    fig_pillar_states,
    fig_rheology,
    fig_speed,
    fig_states,
    fig_twirling,
    fig_valve,
    fig_valve_result,
)
from .laos import fig_bed_lissajous, fig_pipkin
from .paper import (
    fig_model,
    fig_pendulum,
    fig_phase_portrait,
    fig_profiles,
    fig_solution,
    fig_theta0s,
)
from .porous import fig_collective_stiffening
from .rheometer import fig_bed_moduli
from .valve_dynamics import fig_valve_pump

__all__ = [
    "FIGURES",
    "fig_bed_lissajous",
    "fig_bed_moduli",
    "fig_bistability",
    "fig_calibration",
    "fig_collective_stiffening",
    "fig_fd_convergence",
    "fig_hysteresis",
    "fig_model",
    "fig_pendulum",
    "fig_phase_portrait",
    "fig_physical_units",
    "fig_pillar_bode",
    "fig_pillar_calibration",
    "fig_pillar_film",
    "fig_pillar_snap",
    "fig_pillar_states",
    "fig_pillar_step",
    "fig_pipkin",
    "fig_profiles",
    "fig_rheology",
    "fig_sensor_design",
    "fig_solution",
    "fig_speed",
    "fig_states",
    "fig_theta0s",
    "fig_twirling",
    "fig_valve",
    "fig_valve_design",
    "fig_valve_pump",
    "fig_valve_result",
    "make_all",
    "parameters",
    "parse_settings",
]

#: The largest resolution :func:`make_all` writes [dots per inch].
MAX_DPI = 1200

#: File stem -> figure function, in the order of the guide (paper first).
FIGURES: dict[str, Callable[..., Figure]] = {
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
    "valve": fig_valve,
    "fd_convergence": fig_fd_convergence,
    "speed": fig_speed,
    "pillar_calibration": fig_pillar_calibration,
    "pillar_snap": fig_pillar_snap,
    "collective_stiffening": fig_collective_stiffening,
    "valve_design": fig_valve_design,
    "sensor_design": fig_sensor_design,
    "pillar_bode": fig_pillar_bode,
    "pillar_step": fig_pillar_step,
    "pillar_film": fig_pillar_film,
    "bed_moduli": fig_bed_moduli,
    "bed_lissajous": fig_bed_lissajous,
    "pipkin": fig_pipkin,
    "valve_pump": fig_valve_pump,
}


def _selected(only: Iterable[str] | None) -> list[str]:
    wanted = None if only is None else {name.removeprefix("fig_") for name in only}
    unknown = set() if wanted is None else wanted - set(FIGURES)
    if unknown:
        raise ValueError(f"unknown figure name(s) {sorted(unknown)}; choose from {list(FIGURES)}")
    return [name for name in FIGURES if wanted is None or name in wanted]


def parameters(name: str) -> dict[str, Any]:
    """The parameters of figure ``name`` that can be set (numbers or tuples of numbers), with
    their defaults.

    >>> parameters("hysteresis")
    {'eps': 0.9, 'theta0': -1.5, 'num': 240}
    """
    sig = inspect.signature(FIGURES[name.removeprefix("fig_")])
    out = {}
    for p in sig.parameters.values():
        d = p.default
        number = isinstance(d, (int, float)) and not isinstance(d, bool)
        numbers = isinstance(d, tuple) and d and all(isinstance(v, (int, float)) for v in d)
        if number or numbers:
            out[p.name] = d
    return out


def _convert(text: str, default: Any, key: str) -> Any:
    kind = type(default[0]) if isinstance(default, tuple) else type(default)
    items = [t.strip() for t in text.split(",")] if isinstance(default, tuple) else [text.strip()]
    values = []
    for item in items:
        try:
            values.append(int(item) if kind is int else float(item))
        except ValueError:
            form = "integers" if kind is int else "numbers"
            form = f"a comma list of {form}" if isinstance(default, tuple) else form[:-1]
            form = form.replace("integer", "an integer").replace("number", "a number", 1)
            raise ValueError(f"--set {key}: {text!r} is not {form}") from None
    return tuple(values) if isinstance(default, tuple) else values[0]


#: A single value of a figure's plural parameter: ``--set theta0=X`` is ``theta0s=(X,)`` for
#: the figures that take theta0s and not theta0 (bistability, pillar_calibration), unless
#: theta0s is set too.
SINGULAR = {"theta0": "theta0s"}


def parse_settings(
    settings: Iterable[str], only: Iterable[str] | None = None
) -> dict[str, dict[str, Any]]:
    """The keyword arguments of each figure from ``KEY=VALUE`` texts (``hairbed figures
    --set``): a value goes to every figure among ``only`` (default all) that has a parameter
    KEY, converted to its type (a comma list for a tuple); ``theta0=X`` goes as the one
    slice ``theta0s=(X,)`` to the figures that draw several base angles
    (:data:`SINGULAR`), so that no selected figure ignores it.

    Raises
    ------
    ValueError
        For a text without ``=``, a key that no selected figure takes (naming those it could
        be) or a value that is not a number of the parameter's kind.

    Examples
    --------
    >>> parse_settings(["eps=0.8", "theta0=-1.2"], only=["hysteresis", "model"])
    {'model': {'eps': 0.8, 'theta0': -1.2}, 'hysteresis': {'eps': 0.8, 'theta0': -1.2}}
    """
    names = _selected(only)
    table = {name: parameters(name) for name in names}
    out: dict[str, dict[str, Any]] = {name: {} for name in names}
    singles: dict[str, dict[str, Any]] = {name: {} for name in names}
    for text in settings:
        key, sep, value = text.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ValueError(f"--set takes KEY=VALUE, got {text!r}")
        takers = [name for name in names if key in table[name]]
        plural = SINGULAR.get(key, "")
        slices = [n for n in names if plural and plural in table[n] and key not in table[n]]
        if not takers and not slices:
            known = sorted({k for params in table.values() for k in params})
            raise ValueError(
                f"--set {key}: no figure among {', '.join(names)} takes {key!r}; "
                f"they take {', '.join(known)}"
            )
        for name in takers:
            out[name][key] = _convert(value, table[name][key], key)
        for name in slices:
            singles[name][plural] = (_convert(value, 0.0, key),)
    for name, kw in singles.items():
        for plural, values in kw.items():
            out[name].setdefault(plural, values)  # an explicit theta0s wins
    return {name: kw for name, kw in out.items() if kw}


def make_all(
    out_dir: str | Path,
    *,
    dpi: int = 150,
    only: Iterable[str] | None = None,
    verbose: bool = True,
    settings: Mapping[str, Mapping[str, Any]] | None = None,
) -> list[Path]:
    """Write every figure as ``<out_dir>/<name>.png`` and return the paths written.

    Parameters
    ----------
    out_dir : str or Path
        Folder, created if needed.
    dpi : int, optional
        Resolution of the PNGs [dots per inch], in [1, ``MAX_DPI`` = 1200] (a 10-inch
        figure at 1200 dpi is already a 12000-pixel image).
    only : iterable of str, optional
        Names (keys of :data:`FIGURES`, with or without the ``fig_`` prefix) to make.
    verbose : bool, optional
        Print one line per figure on stdout.
    settings : mapping, optional
        Keyword arguments per figure name (as from :func:`parse_settings`).

    Returns
    -------
    list of Path
        The files written.
    """
    dpi = check_int(dpi, "dpi", 1, MAX_DPI)
    names = _selected(only)
    settings = settings or {}
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in names:
        kwargs = dict(settings.get(name, {}))
        try:
            fig = FIGURES[name](**kwargs)
        except (ValueError, TypeError) as exc:
            if not kwargs:
                raise
            given = ", ".join(f"{k}={v}" for k, v in kwargs.items())
            raise ValueError(f"figure {name} ({given}): {exc}") from None
        path = out / f"{name}.png"
        with atomic_path(path) as tmp:  # whole or not at all
            fig.savefig(tmp, dpi=dpi, format="png")
        paths.append(path)
        if verbose:
            print(f"wrote {path}")
    return paths
