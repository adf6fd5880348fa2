"""A pulsing pump's net flow over (amplitude, frequency), eager or chunked with dask (issue 31
section 3): each cell is :func:`hairbed.valve_dynamics.pump_net_flow`'s, a block of cells one
call of it, so a chunked sweep is bitwise the eager one."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import valve_dynamics as vd
from .._optional import optional_import
from .._version import __version__
from ._blocks import stacked

__all__ = ["PUMP_VARIABLES", "pump_sweep"]

FloatArray = NDArray[np.float64]

#: The variables of :func:`pump_sweep`: name -> (units, long_name).
PUMP_VARIABLES: dict[str, tuple[str, str]] = {
    "net_flow": ("m2 s-1", "net flow rate per width over a period of the periodic state"),
    "quasi_static_net_flow": ("m2 s-1", "phase average of the steady valve curve's flow rate"),
    "periods": ("1", "periods integrated"),
    "status": ("1", "0 periodic to tol; 1 max_periods reached; negative: the run's status"),
}
_COORDS = {
    "amplitude": ("Pa", "amplitude of the pressure drop, A sin(2 pi f t)"),
    "frequency": ("Hz", "frequency of the pressure drop"),
}


def _block(
    amps: FloatArray,
    freqs: FloatArray,
    *,
    bed: Any,
    channel_length: float,
    options: dict[str, Any],
    progress: Any,
) -> FloatArray:
    """One block: (4, amplitudes, frequencies)."""
    r = vd.pump_net_flow(bed, amps, freqs, channel_length, **options)
    out = np.empty((4, amps.size, freqs.size))
    out[0] = r.net_flow
    out[1] = r.quasi_static_net_flow[:, None]
    out[2] = r.periods
    out[3] = r.status
    return out


def pump_sweep(
    bed: Any,
    amplitude: Any,
    frequency: Any,
    channel_length: float,
    *,
    samples_per_period: int = 64,
    max_periods: int = 400,
    tol: float = 1e-6,
    hair_density: float | None = None,
    rtol: float = 1e-8,
    chunks: Any = None,
) -> Any:
    """The net flow of a bed pumped by dp(t) = A sin(2 pi f t) over the grid (amplitude,
    frequency), as an xarray Dataset with units (:func:`hairbed.valve_dynamics.pump_net_flow`
    at each cell; its parameters). With ``chunks`` (an int, or a dict per dimension) the
    dataset is dask-backed and lazy, each block computed when the dataset is (the threaded
    scheduler, or a ``dask.distributed`` client's workers): the integrator's kernels release
    the GIL, so threads run blocks in parallel. Needs the ``sweep`` extra.

    Variables: ``PUMP_VARIABLES``, over the dimensions ``amplitude`` [Pa] and ``frequency``
    [Hz].
    """
    xr = optional_import("xarray", "pump_sweep", "sweep")
    options = {
        "samples_per_period": samples_per_period,
        "max_periods": max_periods,
        "tol": tol,
        "hair_density": hair_density,
        "rtol": rtol,
    }
    # every input checked now (one cheap cell), not inside a lazy block
    amps = vd._positive_array(amplitude, "amplitude", "Pa")
    freqs = vd._positive_array(frequency, "frequency", "Hz")
    vd._scales(bed, hair_density)
    length = vd._channel_length(channel_length)
    data = stacked(
        _block,
        [amps, freqs],
        ("amplitude", "frequency"),
        4,
        chunks,
        None,
        bed=bed,
        channel_length=length,
        options=options,
    )
    dims = ("amplitude", "frequency")
    data_vars = {}
    for k, (name, (units, long_name)) in enumerate(PUMP_VARIABLES.items()):
        v = data[k]
        if name in ("status", "periods"):
            v = v.astype(np.int64)
        data_vars[name] = (dims, v, {"units": units, "long_name": long_name})
    coords = {d: (d, a, {"units": u, "long_name": ln})
              for (d, (u, ln)), a in zip(_COORDS.items(), (amps, freqs))}  # fmt: skip
    attrs = {
        "title": "hairbed: a pulsing pump's net flow over amplitude and frequency",
        "Conventions": "CF-1.8",
        "source": f"hairbed {__version__}",
        "bed": repr(bed),
        "channel_length_m": length,
        "time_scale_s": vd.bed_time_scales(bed, hair_density)["time_scale"],
        "model": "the porous bed in time (theory.md section 15)",
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)
