"""The computation of a sweep: the grid cut into blocks, each solved by one kernel call,
stacked into one (variables, *grid) array, numpy now or dask later.

The kernels work element by element, so a block is bitwise the same points solved alone,
and a chunked sweep bitwise the eager one.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.loaded import solve_loaded
from .._core.pillar import solve_pillar
from .._core.solver import _solve_arrays
from .._core.validation import check_int
from .._optional import optional_import
from .._variables import SI
from ._attributes import (
    BED_COORDS,
    BED_SCALED,
    BED_VARIABLES,
    DIMS,
    INTEGER,
    LOADED_VARIABLES,
    PILLAR_DIMS,
    PILLAR_VARIABLES,
    VARIABLES,
    pumped_variables,
)
from ._progress import Progress


def chunk_sizes(chunks: Any, sizes: Mapping[str, int]) -> dict[str, int]:
    """Chunk length per dimension from an int or a dict {dim: int} (missing: whole)."""

    def length(value: Any, where: str) -> int:
        return check_int(value, f"chunks{where}", 1, 2**40)

    if isinstance(chunks, Mapping):
        unknown = [k for k in chunks if k not in sizes]
        if unknown:
            dims = ", ".join(sizes) or "none (every input is a scalar)"
            raise ValueError(
                f"chunks has unknown dimension {unknown[0]!r}; the grid's dimensions are {dims}"
            )
        return {d: length(chunks[d], f"[{d!r}]") if d in chunks else n for d, n in sizes.items()}
    c = length(chunks, "")
    return dict.fromkeys(sizes, c)


def _full_inputs(
    axes: tuple[NDArray[np.float64], ...],
    dims: tuple[str, ...],
    fixed: Mapping[str, float],
    names: tuple[str, ...],
) -> dict[str, NDArray[np.float64]]:
    """Every input of a block at every point of it: the block's axes broadcast over its
    outer-product shape, the fixed (scalar) inputs filled in."""
    shape = tuple(a.size for a in axes)
    full = {}
    for name in names:
        if name in dims:
            i = dims.index(name)
            idx = [1] * len(dims)
            idx[i] = shape[i]
            full[name] = np.broadcast_to(np.asarray(axes[i], dtype=np.float64).reshape(idx), shape)
        else:
            full[name] = np.full(shape, fixed[name])
    return full


def grid_block(
    *axes: NDArray[np.float64],
    dims: tuple[str, ...],
    fixed: Mapping[str, float],
    sign: int,
    n: int,
    code: int,
    progress: Any,
) -> NDArray[np.float64]:
    """One block of the grid: (len(VARIABLES), *block shape) float64, one kernel call."""
    if progress is not None:
        progress.start()
    shape = tuple(a.size for a in axes)
    full = _full_inputs(axes, dims, fixed, DIMS)
    w, e, t0 = (np.array(full[d], dtype=np.float64) for d in DIMS)  # contiguous copies
    sol = _solve_arrays(w, e, t0, sign, n, code)
    out = np.empty((len(VARIABLES), *shape))
    for k, name in enumerate(VARIABLES[:-1]):
        out[k] = getattr(sol, name)
    h1 = np.asarray(sol.tip_height, dtype=np.float64)
    out[-1] = 1.0 / (1.0 - e * h1)  # the expression of hairbed.rheology.stress_ratio
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out


def bed_block(
    v: NDArray[np.float64], *, bed: Any, root: str, progress: Any
) -> NDArray[np.float64]:
    """One block of a bed's sweep: (3 + len(BED_VARIABLES), len(v)), via ``bed.deform``."""
    if progress is not None:
        progress.start()
    st = bed.deform(np.asarray(v, dtype=np.float64), root=root)
    sol = st.solution
    values = {k: getattr(st, k) for k in SI if k != "velocity"}
    values["theta0"] = sol.theta0
    for k in BED_SCALED:
        values[f"scaled_{k}"] = getattr(sol, k)
    for k in BED_VARIABLES:  # the dimensionless fields under their own names
        if k not in values:
            values[k] = getattr(sol, k)
    names = (*BED_COORDS, *BED_VARIABLES)
    out = np.empty((len(names), v.size))
    for row, name in enumerate(names):
        out[row] = values[name]
    if progress is not None:
        progress.update(v.size)
    return out


def loaded_block(
    *axes: NDArray[np.float64],
    dims: tuple[str, ...],
    fixed: Mapping[str, float],
    drive: str,
    root: str,
    progress: Any,
) -> NDArray[np.float64]:
    """One block of a dimensionless sweep with a distributed load (``drive`` "pi" or "q"):
    (nvars, *block shape), one call of the distributed-load solver."""
    if progress is not None:
        progress.start()
    shape = tuple(a.size for a in axes)
    full = _full_inputs(axes, dims, fixed, (*DIMS, drive))
    pi, q = (full["pi"], None) if drive == "pi" else (None, full["q"])
    st = solve_loaded(full["omega2"], full["eps"], full["theta0"], pi=pi, q=q, root=root)
    names = LOADED_VARIABLES
    out = np.empty((len(names), *shape))
    for row, name in enumerate(names):
        out[row] = getattr(st, name)
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out


def pillar_block(
    *axes: NDArray[np.float64],
    dims: tuple[str, ...],
    fixed: Mapping[str, float],
    profile: Any,
    progress: Any,
) -> NDArray[np.float64]:
    """One block of a pillar's sweep: (len(PILLAR_VARIABLES), *block shape), one call of
    :func:`hairbed.solve_pillar` per height ratio of the block (the profile's coefficients
    depend on it; every other input is broadcast)."""
    if progress is not None:
        progress.start()
    shape = tuple(a.size for a in axes)
    names = tuple(d for d in PILLAR_DIMS if d in dims or d in fixed)
    full = _full_inputs(axes, dims, fixed, names)
    out = np.empty((len(PILLAR_VARIABLES), *shape))
    ratios: list[tuple[float | None, tuple[Any, ...]]]
    if "height_ratio" in dims:  # the last dimension: one solve per value of it
        ratios = [(float(r), (..., j)) for j, r in enumerate(axes[dims.index("height_ratio")])]
    else:
        ratios = [(fixed.get("height_ratio"), (...,))]
    for ratio, where in ratios:
        st = solve_pillar(
            full["forcing"][where],
            full["theta0"][where],
            profile=profile,
            height_ratio=ratio,
            gamma=full["gamma"][where],
            tip_load=full["tip_load"][where],
        )
        for row, name in enumerate(PILLAR_VARIABLES):
            out[(row, *where)] = getattr(st, name)
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out


def pumped_block(
    *axes: NDArray[np.float64],
    dims: tuple[str, ...],
    fixed: Mapping[str, float],
    bed: Any,
    drive: str,
    root: str,
    progress: Any,
) -> NDArray[np.float64]:
    """One block of a pump-driven bed's sweep over (velocity, drive): (nvars, *block)."""
    if progress is not None:
        progress.start()
    shape = tuple(a.size for a in axes)
    full = _full_inputs(axes, dims, fixed, ("velocity", drive))
    st = bed.deform(full["velocity"], root=root, **{drive: full[drive]})
    sol = st.solution
    names = pumped_variables(drive)
    out = np.empty((1 + len(names), *shape))
    out[0] = st.omega2
    for row, name in enumerate(names, start=1):
        if name.startswith("scaled_"):
            out[row] = getattr(sol, name.removeprefix("scaled_"))
        elif hasattr(st, name):  # an SI field; the rest are the solver's
            out[row] = getattr(st, name)
        else:
            out[row] = getattr(sol, name)
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out


def stacked(
    block: Any,
    axes: list[NDArray[np.float64]],
    names: tuple[str, ...],
    nfields: int,
    chunks: Any,
    progress: Progress | None,
    /,
    **kwargs: Any,
) -> Any:
    """The (nfields, *grid) array of all variables: numpy (eager) or dask (chunked)."""
    sizes = {d: a.size for d, a in zip(names, axes)}
    if chunks is None:
        if progress is None or not names:
            return block(*axes, progress=progress, **kwargs)
        # eager with a progress bar: blocks along the first dimension of ~1e4 points each
        first = axes[0]
        rest = int(np.prod([a.size for a in axes[1:]], dtype=np.int64))
        step = max(1, 10_000 // max(rest, 1))
        parts = [
            block(first[i : i + step], *axes[1:], progress=progress, **kwargs)
            for i in range(0, first.size, step)
        ]
        return np.concatenate(parts, axis=1)
    da = optional_import("dask.array", "a chunked sweep", "sweep")
    lengths = chunk_sizes(chunks, sizes)
    if not names:  # every input a scalar: one block
        import dask

        value = dask.delayed(block, pure=True)(progress=progress, **kwargs)
        return da.from_delayed(value, shape=(nfields,), dtype=np.float64)
    inputs = []
    index = "abcdefghijklmnopqrstuvwxy"[: len(names)]
    for d, a, letter in zip(names, axes, index):
        inputs += [da.from_array(a, chunks=lengths[d], name=f"hairbed-{d}-{_token(a)}"), letter]
    with warnings.catch_warnings():  # many small blocks are what was asked for
        warnings.simplefilter("ignore", da.PerformanceWarning)
        return da.blockwise(
            block,
            "z" + index,
            *inputs,
            new_axes={"z": nfields},
            dtype=np.float64,
            concatenate=True,
            meta=np.empty((0,) * (len(names) + 1)),
            progress=progress,
            **kwargs,
        )


def _token(a: NDArray[np.float64]) -> str:
    import hashlib

    return hashlib.sha1(np.ascontiguousarray(a).tobytes()).hexdigest()[:16]


def variable(
    stacked: Any, k: int, name: str, dims: tuple[str, ...], attrs: Mapping[str, Any]
) -> tuple[tuple[str, ...], Any, dict[str, Any]]:
    data = stacked[k]
    if name in INTEGER:
        data = data.astype(np.int64)
    elif name == "physical":
        data = data.astype(np.bool_)
    return dims, data, dict(attrs)
