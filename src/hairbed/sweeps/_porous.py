"""The SI sweep of a porous bed (``HairBed(..., model="porous").sweep``, theory.md §13)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._channel_drives import pump_drive
from .._core.validation import check_flag, check_int, check_root
from .._optional import optional_import
from .._variables import POROUS, SI, cf_attrs, names
from ._attributes import dataset_attrs, variable_attrs
from ._progress import Progress

__all__ = ["porous_sweep"]

#: The SI fields of a HairState a porous sweep holds (velocity and the drive are dimensions).
_SI_FIELDS = tuple(k for k in names(SI) if k not in ("velocity", "direction"))
#: The PorousState fields kept beside them; those that share an SI name are ``scaled_``.
_POROUS_FIELDS = tuple(k for k in names(POROUS, "porous") if k != "stable")
_SCALED = ("tip_height", "tip_deflection", "tip_angle")


def _name(field: str) -> str:
    return f"scaled_{field}" if field in _SCALED else field


def porous_sweep(
    bed: Any,
    velocity: Any,
    pressure_gradient: Any,
    flow_rate: Any,
    root: str,
    chunks: Any,
    progress: bool,
    axis: Any,
) -> Any:
    """A porous bed's states over wall speeds, or over (velocity, a pump's drive), as an
    xarray Dataset: every SI field of its :class:`~hairbed.units.HairState`, and the
    dimensionless :class:`hairbed.PorousState` fields beside them (``scaled_tip_height`` ...
    in units of L, the fluid's stresses in load units, ``status``, ``nit``, ``num``), the
    bed's parameters and its ``kappa`` and ``gamma`` in the attributes. Values are those of
    ``bed.deform``. The states are computed at once (the kernel takes the whole grid);
    ``chunks`` (an int) sets the size of the blocks along the first dimension that
    ``progress`` counts. ``axis(value, name, unit)`` checks a 1-D or scalar SI axis."""
    xr = optional_import("xarray", "HairBed.sweep", "sweep")
    root = check_root(root)
    progress = check_flag(progress, "progress")
    pumped = pressure_gradient is not None or flow_rate is not None
    if not pumped and velocity is None:
        raise TypeError("sweep() needs velocity [m/s], pressure_gradient [Pa/m] or flow_rate")
    values = {"velocity": axis(0.0 if velocity is None else velocity, "velocity", "m/s")}
    drive = None
    if pumped:
        drive, unit, given = pump_drive(pressure_gradient, flow_rate)
        values[drive] = axis(given, drive, unit)
    dims = tuple(d for d in values if values[d].ndim == 1)
    grid = np.meshgrid(*(np.atleast_1d(values[d]) for d in values), indexing="ij")
    shape = tuple(values[d].size for d in dims)
    flat = [g.reshape(-1) for g in grid]
    size = flat[0].size
    block = size if chunks is None else check_int(chunks, "chunks", 1, None)
    bar = Progress(size) if progress else None
    out: dict[str, np.ndarray] = {}
    for start in range(0, size, block):
        part = slice(start, min(size, start + block))
        kw = {drive: flat[1][part]} if drive else {}
        st = bed.deform(flat[0][part], root=root, **kw)
        sol = st.solution
        for k in _SI_FIELDS:
            out.setdefault(k, np.empty(size))[part] = np.asarray(getattr(st, k))
        for k in _POROUS_FIELDS:
            dtype = np.int64 if POROUS[k].dtype == "int64" else np.float64
            out.setdefault(_name(k), np.empty(size, dtype=dtype))[part] = np.asarray(
                getattr(sol, k)
            )
        if bar is not None:
            bar.update(part.stop - part.start)  # the bar closes itself at the total
    coords: dict[str, Any] = {
        d: ((d,) if d in dims else (), values[d], cf_attrs(SI[d])) for d in values
    }
    data_vars = {}
    for k in _SI_FIELDS:
        if k != drive:  # the drive is a coordinate
            data_vars[k] = (dims, out[k].reshape(shape), cf_attrs(SI[k]))
    for k in _POROUS_FIELDS:
        v = POROUS[k]
        data_vars[_name(k)] = (
            dims,
            out[_name(k)].reshape(shape),
            variable_attrs((v.units, v.long_name), k),
        )
    what = "wall speed" if drive is None else drive.replace("_", " ")
    attrs = dataset_attrs(
        f"hairbed sweep of a porous hair bed over the {what} (SI units)",
        " (HairBed.sweep, model='porous')",
        1,
        0,
        root,
    )
    attrs.update(
        bed=repr(bed),
        eps=float(bed.eps),
        model="porous",
        drag=bed.drag,
        kappa=float(bed.kappa),
        gamma=float(bed.drag_ratio),
    )
    if drive:
        attrs["drive"] = drive
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)
