"""Sweeps over N-dimensional grids as labelled xarray datasets, eager or chunked with dask.

:func:`sweep` solves the exact problem (:func:`hairbed.solve`, theory.md §2) on the outer
product of its inputs: every 1-D argument among omega2, eps and theta0 becomes a dimension
of that name (in that order), every scalar a scalar coordinate. The result is an
:class:`xarray.Dataset` with every :class:`~hairbed.Solution` field and the stress ratio
1 / (1 - eps h1) (theory.md §7) as data variables, CF attributes (``units``, ``long_name``)
on every variable and coordinate, and the branch, root choice and hairbed version in the
dataset's attributes. :func:`bed_sweep` (``HairBed.sweep``) does the same in SI units over
the wall speed of a bed. With ``forcing=`` it sweeps an isolated pillar in a shear layer
(:func:`hairbed.solve_pillar`, theory.md §12) over its forcing, base angle, drag ratio, tip
load and height ratio.

With ``chunks=`` the dataset is dask-backed and lazy: the grid is cut into blocks, each
solved by one call of the compiled kernels (which release the GIL, so the threaded
scheduler uses every core) when the dataset is computed, by whatever dask scheduler is
active: the threaded one by default, a ``dask.distributed`` cluster when a ``Client``
exists. The kernels work element by element, so a chunked sweep is bitwise the eager one,
and both are bitwise :func:`hairbed.solve` at the same points.

:func:`bistability_map` maps the exact bistable window (the folds of the physical branch,
:func:`hairbed.branches.bistable_window`) over a grid of (theta0, eps): exact at every cell,
where a grid of omega^2 misses the windows narrower than its step near the cusp.

:func:`response_sweep` maps a pillar sensor's linear frequency response over (mean stress,
frequency), and :func:`amplitude_sweep` its nonlinear periodic response over (amplitude,
frequency): the first harmonic, the mean shift and the distortion beside the linear response
(issue 31, theory.md §14); both chunked with dask like the others. A pulsing pump's net flow
over (amplitude, frequency) is :func:`hairbed.valve_dynamics.pump_sweep`.

:func:`parse_spec` reads the SPEC of an axis or a path, as ``hairbed sweep`` takes them: a
value, a comma list, ``start:stop:num[:log]``, or for a quasi-static path
``start:stop:num:updown``, a ramp up and back down (:mod:`hairbed._specs`).

:func:`write_dataset` writes a sweep as netCDF (``.nc``), a zarr store (``.zarr``), a long
CSV table (``.csv``, one row per grid point, units in the header) or parquet (``.parquet``,
units in the schema metadata), always whole or not at all (:mod:`hairbed.safe_files`);
:func:`read_table` reads the CSV and parquet tables back with their units.

xarray is needed here (and dask for ``chunks``, netCDF4 for ``.nc``, zarr, pyarrow):
``pip install "hairbed[sweep]"``. Importing hairbed imports none of them.

The package computes in ``_grid`` (the datasets) and ``_blocks`` (the blocks of the grid,
numpy or dask), writes in ``_files``, and names and units everything in ``_attributes``,
from the package's one variables table (``hairbed._variables``).

Examples
--------
>>> from hairbed import solve
>>> ds = sweep([0.5, 2.0], 0.5, [0.0, 0.3])
>>> dict(ds.sizes), ds.attrs["root"], ds["tip_height"].attrs["units"]
({'omega2': 2, 'theta0': 2}, 'low', '1')
>>> float(ds["xi"].sel(omega2=2.0, theta0=0.0)) == solve(2.0, 0.5).xi
True
"""

from __future__ import annotations

from .._specs import parse_spec
from ._attributes import (
    ATTRS,
    BED_ATTRS,
    DIMS,
    LOADED_ATTRS,
    LOADED_VARIABLES,
    PILLAR_ATTRS,
    PILLAR_DIMS,
    PILLAR_VARIABLES,
    PUMPED_ATTRS,
    VARIABLES,
)
from ._bistable import MAP_DIMS, MAP_VARIABLES, bistability_map
from ._files import (
    FORMATS,
    NETCDF_COMPRESSION,
    output_format,
    read_table,
    write_csv_stream,
    write_dataset,
)
from ._grid import bed_sweep, path_dataset, sweep
from ._response import (
    AMPLITUDE_STATUS,
    AMPLITUDE_VARIABLES,
    RESPONSE_VARIABLES,
    amplitude_sweep,
    response_sweep,
)

__all__ = [
    "AMPLITUDE_STATUS",
    "AMPLITUDE_VARIABLES",
    "ATTRS",
    "BED_ATTRS",
    "DIMS",
    "FORMATS",
    "LOADED_ATTRS",
    "LOADED_VARIABLES",
    "MAP_DIMS",
    "MAP_VARIABLES",
    "NETCDF_COMPRESSION",
    "PILLAR_ATTRS",
    "PILLAR_DIMS",
    "PILLAR_VARIABLES",
    "PROGRESS_DELAY",
    "PUMPED_ATTRS",
    "RESPONSE_VARIABLES",
    "VARIABLES",
    "amplitude_sweep",
    "bed_sweep",
    "bistability_map",
    "output_format",
    "parse_spec",
    "path_dataset",
    "read_table",
    "response_sweep",
    "sweep",
    "write_csv_stream",
    "write_dataset",
]

#: Seconds of work before a progress bar appears (short sweeps print nothing); read each
#: time a bar is made, so it may be set here.
PROGRESS_DELAY = 1.0
