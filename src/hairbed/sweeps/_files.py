"""Writing sweeps to files, whole or not at all (:mod:`hairbed.safe_files`): netCDF, zarr,
and a long table (one row per grid point) as CSV or parquet, read back with its units."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.validation import check_flag, show
from .._jsonsafe import to_plain
from .._optional import optional_import
from ..safe_files import atomic_path
from ._attributes import INTEGER

__all__ = [
    "FORMATS",
    "NETCDF_COMPRESSION",
    "output_format",
    "read_table",
    "write_csv_stream",
    "write_dataset",
]

#: Output formats by file extension.
FORMATS = {".nc": "netcdf", ".zarr": "zarr", ".csv": "csv", ".parquet": "parquet"}


def output_format(path: str | os.PathLike[str]) -> str:
    """The format of an output path by its extension ('netcdf', 'zarr', 'csv', 'parquet').

    Raises
    ------
    ValueError
        For any other extension (checked before any work is done).
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike), got {show(path)}")
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        known = ", ".join(FORMATS)
        raise ValueError(
            f"unknown output format {suffix or '(no extension)'!r} of path {str(path)!r}; "
            f"use one of {known}"
        )
    return FORMATS[suffix]


def _columns(ds: Any) -> tuple[list[str], dict[str, NDArray[Any]], dict[str, str]]:
    """Long format: one row per grid point; dimension and scalar coordinates first."""
    ds = ds.compute()
    dims = list(ds.sizes)
    shape = tuple(ds.sizes[d] for d in dims)
    names = list(dims) + [c for c in ds.coords if c not in dims] + list(ds.data_vars)
    cols: dict[str, NDArray[Any]] = {}
    units: dict[str, str] = {}
    for name in names:
        var = ds[name]
        order = [d for d in dims if d in var.dims]
        values = np.asarray(var.transpose(*order).values)
        full = values.reshape([shape[i] if d in var.dims else 1 for i, d in enumerate(dims)])
        cols[name] = np.broadcast_to(full, shape).reshape(-1)
        units[name] = str(var.attrs.get("units", ""))
    return names, cols, units


def _csv_cell(kind: str) -> Any:
    if kind == "b":
        return lambda x: "True" if x else "False"
    if kind in "iu":
        return lambda x: str(int(x))
    return lambda x: repr(float(x))


def _write_csv(ds: Any, stream: Any) -> int:
    import csv

    names, cols, units = _columns(ds)
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow([f"{n} [{units[n]}]" if units[n] else n for n in names])
    cells = [(_csv_cell(cols[n].dtype.kind), cols[n]) for n in names]
    rows = len(next(iter(cols.values()))) if cols else 0
    step = 4096
    for start in range(0, rows, step):
        block = [[f(x) for x in c[start : start + step].tolist()] for f, c in cells]
        writer.writerows(zip(*block))
    return rows


def _json_attrs(ds: Any) -> str:
    return json.dumps(to_plain(dict(ds.attrs)))


def _write_parquet(ds: Any, path: Path) -> int:
    pa = optional_import("pyarrow", "parquet output", "sweep")
    pq = optional_import("pyarrow.parquet", "parquet output", "sweep")
    names, cols, units = _columns(ds)
    fields = []
    for n in names:
        long_name = str(ds[n].attrs.get("long_name", ""))
        meta = {b"units": units[n].encode(), b"long_name": long_name.encode()}
        fields.append(pa.field(n, pa.from_numpy_dtype(cols[n].dtype), metadata=meta))
    schema = pa.schema(
        fields,
        metadata={
            b"hairbed": _json_attrs(ds).encode(),
            b"units": json.dumps(units).encode(),
        },
    )
    table = pa.Table.from_arrays([pa.array(cols[n]) for n in names], schema=schema)
    pq.write_table(table, path)
    return table.num_rows


#: netCDF encoding of every data variable by default: zlib (deflate) level 4 with the shuffle
#: filter, read by every netCDF-4/HDF5 library (zstd needs a filter plugin in the reader).
#: Lossless: the file reads back bitwise equal.
NETCDF_COMPRESSION = {"zlib": True, "complevel": 4, "shuffle": True}


def _netcdf_encoding(ds: Any, compress: bool) -> dict[str, dict[str, Any]] | None:
    """The ``encoding=`` of ``to_netcdf``: :data:`NETCDF_COMPRESSION` on every data variable."""
    if not compress:
        return None
    return {name: dict(NETCDF_COMPRESSION) for name in ds.data_vars}


def write_dataset(ds: Any, path: str | os.PathLike[str], *, compress: bool = True) -> int:
    """Write a sweep to ``path`` in the format of its extension, whole or not at all.

    ``.nc``: netCDF-4 (CF attributes, via netCDF4); ``.zarr``: a zarr store (a directory);
    ``.csv``: long format, one row per grid point, the header ``name [units]``;
    ``.parquet``: the same long table, each field's ``units`` and ``long_name`` in its
    metadata and the dataset's attributes (JSON) in the schema's ``hairbed`` metadata. A
    lazy (dask) dataset is computed by the active scheduler while it is written.

    Returns
    -------
    int
        The number of grid points written.

    Raises
    ------
    ValueError
        For an unknown extension (before anything is written).
    """
    kind = output_format(path)
    compress = check_flag(compress, "compress")
    path = Path(path)
    points = int(np.prod(list(ds.sizes.values()), dtype=np.int64))
    lazy = bool(ds.chunks)  # dask-backed: the writer's chunk tasks run in _write_lazy
    if kind == "netcdf":
        optional_import("netCDF4", "netCDF output", "sweep")
        with atomic_path(path) as tmp:
            _write_lazy(
                ds.to_netcdf(
                    tmp,
                    engine="netcdf4",
                    format="NETCDF4",
                    compute=not lazy,
                    encoding=_netcdf_encoding(ds, compress),
                )
            )
    elif kind == "zarr":
        zarr = optional_import("zarr", "zarr output", "sweep")
        # format 2 with consolidated metadata: read by every zarr library without a warning
        fmt = {"zarr_format": 2} if int(zarr.__version__.split(".")[0]) >= 3 else {}
        with atomic_path(path, directory=True) as tmp:
            _write_lazy(ds.to_zarr(tmp, mode="w-", consolidated=True, compute=not lazy, **fmt))
    elif kind == "csv":
        with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
            _write_csv(ds, fh)
    else:
        with atomic_path(path) as tmp:
            _write_parquet(ds, tmp)
    return points


def _write_lazy(delayed: Any) -> None:
    """Compute a writer's delayed chunk tasks (xarray's ``compute=False``), waiting for all.

    With dask's threaded scheduler, a failing chunk (a full disk) ends ``compute`` while
    other chunk tasks still run; one of those reopens the netCDF file in append mode and so
    creates the temporary again after it was removed. A pool of our own, shut down (its
    running tasks waited for) before the error leaves here, keeps them from outliving the
    write. Other schedulers (a distributed cluster) are used as they are.
    """
    if not hasattr(delayed, "dask"):  # nothing lazy: written already
        return
    import concurrent.futures

    import dask
    import dask.threaded
    from dask.base import get_scheduler

    if get_scheduler(collections=[delayed]) is not dask.threaded.get:
        delayed.compute()
        return
    workers = dask.config.get("num_workers", None) or os.cpu_count() or 1
    with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        dask.compute(delayed, scheduler="threads", pool=pool)


def write_csv_stream(ds: Any, stream: Any) -> int:
    """Write a sweep's long CSV table to an open text stream (e.g. stdout); rows written."""
    return _write_csv(ds, stream)


def read_table(path: str | os.PathLike[str]) -> tuple[dict[str, NDArray[Any]], dict[str, str]]:
    """Read a long table written by :func:`write_dataset` (``.csv`` or ``.parquet``).

    Returns
    -------
    columns : dict
        Column name -> values (float64, int64 or bool, as written).
    units : dict
        Column name -> units.
    """
    kind = output_format(path)
    if kind == "parquet":
        pq = optional_import("pyarrow.parquet", "parquet input", "sweep")
        table = pq.read_table(path)
        units = {f.name: (f.metadata or {}).get(b"units", b"").decode() for f in table.schema}
        return {n: table.column(n).to_numpy() for n in table.column_names}, units
    if kind != "csv":
        raise ValueError(f"read_table reads .csv and .parquet tables, got {str(path)!r}")
    import csv

    with open(path, encoding="utf-8", newline="") as fh:
        reader = csv.reader(fh)
        header = next(reader)
        rows = list(reader)
    names, units = [], {}
    for h in header:
        name, _, rest = h.partition(" [")
        names.append(name)
        units[name] = rest[:-1] if rest.endswith("]") else ""
    columns: dict[str, NDArray[Any]] = {}
    for i, name in enumerate(names):
        raw = [r[i] for r in rows]
        if raw and raw[0] in ("True", "False"):
            columns[name] = np.array([x == "True" for x in raw])
        elif name in INTEGER or name == "step":
            columns[name] = np.array([int(x) for x in raw], dtype=np.int64)
        else:
            columns[name] = np.array([float(x) for x in raw], dtype=np.float64)
    return columns, units
