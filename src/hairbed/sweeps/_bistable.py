"""The exact map of the three-state region over (theta0, eps) as a labelled Dataset."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.validation import as_float_array, check_flag, check_inputs
from .._optional import optional_import
from .._variables import SOLUTION, WINDOW, cf_attrs
from ..branches import BistableWindow, bistable_window, cusp
from ._attributes import dataset_attrs
from ._progress import Progress

__all__ = ["MAP_DIMS", "MAP_VARIABLES", "bistability_map"]

#: The dimensions of the map, in their order.
MAP_DIMS = ("theta0", "eps")
#: The data variables of the map, in order (the :data:`hairbed._variables.WINDOW` table).
MAP_VARIABLES = tuple(WINDOW)
#: Pairs (eps, theta0) per call of the fold search between two updates of the progress bar.
_BLOCK = 4096


def _map_axis(value: Any, name: str) -> NDArray[np.float64]:
    arr = np.atleast_1d(as_float_array(value, name))
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(
            f"{name} must be a scalar or a non-empty 1-D array, got shape {arr.shape}"
        )
    check_inputs(0.0, arr if name == "eps" else 0.0, arr if name == "theta0" else 0.0)
    return arr


def bistability_map(theta0: Any, eps: Any, *, progress: bool = False) -> Any:
    """The exact bistable window at every (theta0, eps) of a grid, as an xarray Dataset.

    Each cell's window comes from its two folds (:func:`hairbed.branches.bistable_window`,
    the compiled fold search of :func:`hairbed.solve`), not from a grid of omega^2: a grid
    of forcing misses the windows narrower than its step, which near the cusp eps_c(theta0)
    are arbitrarily narrow, and so undercounts the three-state cells (docs: "Mapping the
    bistable region").

    Parameters
    ----------
    theta0 : float or 1-D array_like
        Base angles [rad], in (-pi/2, pi/2): the first dimension.
    eps : float or 1-D array_like
        Confinements L/H [-], in [0, 1): the second dimension.
    progress : bool, optional
        A progress bar with an ETA on stderr once the work has run about a second.

    Returns
    -------
    xarray.Dataset
        Dimensions (theta0, eps); data variables ``lower_fold`` and ``upper_fold`` (omega^2 at
        the folds, NaN where the branch is monotone), ``width`` (their difference),
        ``n_states`` (3 inside a window, else 1), ``exists`` (bool) and ``cusp_eps``
        (eps_c(theta0), along theta0): the :data:`hairbed._variables.WINDOW` table, with CF
        ``units`` and ``long_name`` on every variable and coordinate.

    Raises
    ------
    ValueError
        For values out of range (naming the parameter and the first bad index), or arrays
        of more than one dimension or empty.

    Examples
    --------
    >>> ds = bistability_map([-1.5, -1.0], [0.5, 0.95])
    >>> ds["n_states"].values.tolist()
    [[1, 3], [1, 3]]
    >>> float(ds["lower_fold"].sel(theta0=-1.0, eps=0.95))
    0.29696
    """
    xr = optional_import("xarray", "hairbed.sweeps.bistability_map", "sweep")
    th = _map_axis(theta0, "theta0")
    ep = _map_axis(eps, "eps")
    progress = check_flag(progress, "progress")
    shape = (th.size, ep.size)
    lower = np.empty(shape).reshape(-1)
    upper = np.empty(shape).reshape(-1)
    e_all = np.broadcast_to(ep[None, :], shape).reshape(-1)
    t_all = np.broadcast_to(th[:, None], shape).reshape(-1)
    bar = Progress(e_all.size, desc="hairbed bistability") if progress else None
    for start in range(0, e_all.size, _BLOCK):
        part = slice(start, start + _BLOCK)
        w = bistable_window(e_all[part], t_all[part])
        lower[part], upper[part] = w.lower, w.upper
        if bar is not None:
            bar.update(e_all[part].size)
    window = BistableWindow(lower.reshape(shape), upper.reshape(shape))
    values = {
        "lower_fold": window.lower,
        "upper_fold": window.upper,
        "width": window.width,
        "n_states": window.n_states,
        "exists": window.exists,
    }
    dims = MAP_DIMS
    data_vars: dict[str, Any] = {
        k: (dims, np.asarray(v), cf_attrs(WINDOW[k])) for k, v in values.items()
    }
    data_vars["cusp_eps"] = (("theta0",), np.atleast_1d(cusp(th)), cf_attrs(WINDOW["cusp_eps"]))
    coords = {d: ((d,), v, cf_attrs(SOLUTION[d])) for d, v in (("theta0", th), ("eps", ep))}
    attrs = dataset_attrs(
        "hairbed bistability map: the exact window of three physical states",
        " (hairbed.sweeps.bistability_map)",
        1,
        0,
        "",
    )
    del attrs["root"]
    attrs["comment"] = (
        "the folds of the physical branch at every cell, exact to rounding (not a grid of "
        "omega2, which misses windows narrower than its step near the cusp)"
    )
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)
