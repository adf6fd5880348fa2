"""Sweeps over N-dimensional grids as labelled xarray datasets, eager or chunked with dask.

:func:`sweep` solves the exact problem (:func:`hairbed.solve`, theory.md §2) on the outer
product of its inputs: every 1-D argument among omega2, eps and theta0 becomes a dimension
of that name (in that order), every scalar a scalar coordinate. The result is an
:class:`xarray.Dataset` with every :class:`~hairbed.Solution` field and the stress ratio
1 / (1 - eps h1) (theory.md §7) as data variables, CF attributes (``units``, ``long_name``)
on every variable and coordinate, and the branch, root choice and hairbed version in the
dataset's attributes. :func:`bed_sweep` (``HairBed.sweep``) does the same in SI units over
the wall speed of a bed.

With ``chunks=`` the dataset is dask-backed and lazy: the grid is cut into blocks, each
solved by one call of the compiled kernels (which release the GIL, so the threaded
scheduler uses every core) when the dataset is computed, by whatever dask scheduler is
active: the threaded one by default, a ``dask.distributed`` cluster when a ``Client``
exists. The kernels work element by element, so a chunked sweep is bitwise the eager one,
and both are bitwise :func:`hairbed.solve` at the same points.

:func:`write_dataset` writes a sweep as netCDF (``.nc``), a zarr store (``.zarr``), a long
CSV table (``.csv``, one row per grid point, units in the header) or parquet (``.parquet``,
units in the schema metadata), always whole or not at all (:mod:`hairbed.safe_files`);
:func:`read_table` reads the CSV and parquet tables back with their units.

xarray is needed here (and dask for ``chunks``, netCDF4 for ``.nc``, zarr, pyarrow):
``pip install "hairbed[sweep]"``. Importing hairbed imports none of them.

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

import json
import os
import sys
import threading
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.solver import _ROOT_CODES, _solve_arrays
from ._core.validation import (
    as_float_array,
    check_branch,
    check_flag,
    check_inputs,
    check_int,
    check_root,
    show,
)
from .safe_files import atomic_path

__all__ = [
    "ATTRS",
    "DIMS",
    "FORMATS",
    "PROGRESS_DELAY",
    "VARIABLES",
    "bed_sweep",
    "output_format",
    "path_dataset",
    "read_table",
    "sweep",
    "write_csv_stream",
    "write_dataset",
]

#: The grid's dimensions, in their order.
DIMS = ("omega2", "eps", "theta0")

#: CF attributes of every coordinate and variable of the dimensionless sweep: name -> (units,
#: long_name). "1" is CF's dimensionless unit; lengths in units of the hair length L are
#: dimensionless too (udunits reads "L" as a litre), which their long_name says.
ATTRS: dict[str, tuple[str, str]] = {
    "omega2": ("1", "forcing omega^2 = pi a^2 L^2 eta v / (E I H phi)"),
    "eps": ("1", "confinement eps = L/H (hair length over channel height)"),
    "theta0": ("rad", "base angle theta0 from the wall normal"),
    "xi": ("1", "scaled energy xi = E/omega_eps^2 = sin(theta1)"),
    "omega_eps": ("1", "effective frequency omega_eps = omega / sqrt(1 - eps h1)"),
    "energy": ("1", "Hamiltonian E = theta'^2/2 + omega_eps^2 sin(theta)"),
    "tip_height": ("1", "tip height h1 = z(1) in units of the hair length L"),
    "tip_deflection": ("1", "tip deflection x1 = x(1) in units of the hair length L"),
    "tip_displacement": (
        "1",
        "tip displacement x1 - sin(theta0) from the hair at rest, in units of the hair length L",
    ),
    "tip_angle": ("rad", "tip angle theta1 = theta(1) from the wall normal"),
    "base_curvature": ("1", "base curvature theta'(0) in units of 1/L"),
    "n_roots": ("1", "number of states on this branch at these inputs"),
    "physical": ("1", "state exists on the physical branch (sign +1, n 0)"),
    "status": ("1", "solver status: 0 converged, -1 no such state, -2 iteration limit"),
    "t": ("1", "branch parameter t = logit((xi - sin theta0)/(1 - sin theta0))"),
    "stress_ratio": ("1", "wall shear stress over that of the bare channel, 1/(1 - eps h1)"),
}
#: Data variables of :func:`sweep`, in order: every Solution field that is not a coordinate
#: or the branch label, then the stress ratio.
VARIABLES = (
    "xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_displacement",
    "tip_angle",
    "base_curvature",
    "n_roots",
    "physical",
    "status",
    "t",
    "stress_ratio",
)
_INTEGER = ("n_roots", "status")
_STATUS_FLAGS = {
    "flag_values": np.array([0, -1, -2], dtype=np.int64),
    "flag_meanings": "converged no_such_state iteration_limit",
}

#: SI sweep of a bed (:func:`bed_sweep`): name -> (units, long_name).
BED_ATTRS: dict[str, tuple[str, str]] = {
    "velocity": ("m s-1", "speed of the top wall v (negative: flow towards -x)"),
    "omega2": ATTRS["omega2"],
    "theta0": ("rad", "base angle of the solved problem, sign(v) theta0 (mirrored for v < 0)"),
    "direction": ("1", "+1 where v >= 0, -1 where v < 0"),
    "tip_deflection": ("m", "tip position along +x relative to the base, x1 L"),
    "tip_displacement": ("m", "tip displacement along +x from the hair at rest"),
    "tip_height": ("m", "tip height above the wall, h1 L"),
    "tip_angle": ("rad", "tip angle from the wall normal towards +x"),
    "wall_shear_stress": ("Pa", "shear stress on the top wall, eta v / (H - h1 L)"),
    "force_per_hair": ("N", "horizontal force of the flow on one hair, tau pi a^2 / phi"),
    "stress_ratio": ("1", "wall shear stress over that of the bare channel, H / (H - h1 L)"),
    **{
        f"scaled_{k}": (ATTRS[k][0], ATTRS[k][1] + " (mirrored frame for v < 0)")
        for k in ("tip_height", "tip_deflection", "tip_displacement", "tip_angle")
    },
    **{k: ATTRS[k] for k in ("xi", "omega_eps", "energy", "base_curvature", "t")},
    **{k: ATTRS[k] for k in ("n_roots", "physical", "status")},
}
_BED_COORDS = ("omega2", "theta0", "direction")
_BED_VARIABLES = tuple(k for k in BED_ATTRS if k != "velocity" and k not in _BED_COORDS)

#: Seconds of work before a progress bar appears (short sweeps print nothing).
PROGRESS_DELAY = 1.0

#: Output formats by file extension.
FORMATS = {".nc": "netcdf", ".zarr": "zarr", ".csv": "csv", ".parquet": "parquet"}


def _need(module: str, what: str) -> Any:
    """Import an optional dependency, or an ImportError that says how to install it."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"{what} needs {module.split('.')[0]}: pip install 'hairbed[sweep]'"
        ) from exc


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("hairbed")
    except PackageNotFoundError:  # pragma: no cover - running from a source tree
        return "unknown"


# -- arguments ------------------------------------------------------------------------------


def _axis(value: Any, name: str) -> NDArray[np.float64]:
    """A scalar (0-d) or non-empty 1-D float array, checked for its range."""
    arr = as_float_array(value, name)
    if arr.ndim > 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array, got shape {arr.shape}")
    if arr.ndim == 1 and arr.size == 0:
        raise ValueError(f"{name} must not be empty")
    args = {"omega2": 0.0, "eps": 0.0, "theta0": 0.0, name: arr}
    check_inputs(args["omega2"], args["eps"], args["theta0"])
    return arr


def _chunk_sizes(chunks: Any, sizes: Mapping[str, int]) -> dict[str, int]:
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


class _Progress:
    """A tqdm bar on stderr fed by the blocks as they finish (ETA from the rate so far).

    Shown only once the work has run for ``delay`` seconds, so short sweeps print nothing.
    Thread-safe (the threaded scheduler's blocks report from their threads). A copy sent to
    another process (a distributed worker) reports nothing: its stderr is not the user's.
    """

    def __init__(self, total: int, delay: float | None = None) -> None:
        self.total = int(total)
        self.delay = PROGRESS_DELAY if delay is None else delay
        self._lock = threading.Lock()
        self._bar: Any = None
        self._done = 0

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_NoProgress, ())

    def start(self) -> None:
        with self._lock:
            if self._bar is None:
                from tqdm import tqdm

                self._bar = tqdm(
                    total=self.total,
                    unit="pt",
                    unit_scale=True,
                    delay=self.delay,
                    file=sys.stderr,
                    desc="hairbed sweep",
                    dynamic_ncols=True,
                )

    def update(self, count: int) -> None:
        self.start()
        with self._lock:
            self._bar.update(count)
            self._done += count
            if self._done >= self.total:  # a second compute of the dataset gets a new bar
                self._bar.close()
                self._bar, self._done = None, 0


class _NoProgress:
    def start(self) -> None:
        pass

    def update(self, count: int) -> None:
        pass


# -- blocks ---------------------------------------------------------------------------------


def _grid_block(
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
    full = []
    for name in DIMS:
        if name in dims:
            i = dims.index(name)
            idx = [1] * len(dims)
            idx[i] = shape[i]
            full.append(np.broadcast_to(np.asarray(axes[i], dtype=np.float64).reshape(idx), shape))
        else:
            full.append(np.full(shape, fixed[name]))
    w, e, t0 = (np.array(a, dtype=np.float64) for a in full)  # contiguous copies
    sol = _solve_arrays(w, e, t0, sign, n, code)
    out = np.empty((len(VARIABLES), *shape))
    for k, name in enumerate(VARIABLES[:-1]):
        out[k] = getattr(sol, name)
    h1 = np.asarray(sol.tip_height, dtype=np.float64)
    out[-1] = 1.0 / (1.0 - e * h1)  # the expression of hairbed.rheology.stress_ratio
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out


def _bed_block(
    v: NDArray[np.float64], *, bed: Any, root: str, progress: Any
) -> NDArray[np.float64]:
    """One block of a bed's sweep: (3 + len(_BED_VARIABLES), len(v)), via ``bed.deform``."""
    if progress is not None:
        progress.start()
    st = bed.deform(np.asarray(v, dtype=np.float64), root=root)
    sol = st.solution
    direction = np.asarray(st.direction, dtype=np.float64)
    values = {
        "omega2": st.omega2,
        "theta0": sol.theta0,
        "direction": direction,
        "tip_deflection": st.tip_deflection,
        "tip_displacement": direction * bed.length * np.asarray(sol.tip_displacement),
        "tip_height": st.tip_height,
        "tip_angle": st.tip_angle,
        "wall_shear_stress": st.wall_shear_stress,
        "force_per_hair": st.force_per_hair,
        "stress_ratio": st.stress_ratio,
    }
    for k in ("tip_height", "tip_deflection", "tip_displacement", "tip_angle"):
        values[f"scaled_{k}"] = getattr(sol, k)
    for k in ("xi", "omega_eps", "energy", "base_curvature", "t", "n_roots", "physical"):
        values[k] = getattr(sol, k)
    values["status"] = sol.status
    names = (*_BED_COORDS, *_BED_VARIABLES)
    out = np.empty((len(names), v.size))
    for row, name in enumerate(names):
        out[row] = values[name]
    if progress is not None:
        progress.update(v.size)
    return out


def _stacked(
    block: Any,
    axes: list[NDArray[np.float64]],
    names: tuple[str, ...],
    nfields: int,
    chunks: Any,
    progress: _Progress | None,
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
    da = _need("dask.array", "a chunked sweep")
    lengths = _chunk_sizes(chunks, sizes)
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


def _variable(
    stacked: Any, k: int, name: str, dims: tuple[str, ...], attrs: Mapping[str, Any]
) -> tuple[tuple[str, ...], Any, dict[str, Any]]:
    data = stacked[k]
    if name in _INTEGER:
        data = data.astype(np.int64)
    elif name == "physical":
        data = data.astype(np.bool_)
    return dims, data, dict(attrs)


# -- the sweeps -----------------------------------------------------------------------------


def sweep(
    omega2: Any,
    eps: Any,
    theta0: Any = 0.0,
    *,
    sign: int = 1,
    n: int = 0,
    root: str = "low",
    chunks: int | Mapping[str, int] | None = None,
    progress: bool = False,
) -> Any:
    """The exact solution on the outer-product grid of the inputs, as an xarray Dataset.

    Parameters
    ----------
    omega2 : float or 1-D array_like
        Forcing omega^2 [-], >= 0.
    eps : float or 1-D array_like
        Confinement eps = L/H [-], in [0, 1).
    theta0 : float or 1-D array_like, optional
        Base angle [rad], in (-pi/2, pi/2). Default 0.
    sign, n : int, optional
        Branch, as in :func:`hairbed.solve` (default the physical branch +1, 0).
    root : {"low", "mid", "high"}, optional
        State where several coexist, as in :func:`hairbed.solve`.
    chunks : int or dict, optional
        Return a lazy, dask-backed dataset cut into blocks of this many points along every
        dimension (an int) or along the named ones (a dict ``{dim: length}``; the others
        whole). Computed by the active dask scheduler (threads by default, a
        ``dask.distributed`` cluster when a ``Client`` exists). Default: computed now.
    progress : bool, optional
        Show a progress bar with an ETA on stderr once the work has run about a second
        (for a chunked dataset: while it is computed in this process, e.g. by the threaded
        scheduler; a cluster's workers report nothing, use distributed's dashboard there).

    Returns
    -------
    xarray.Dataset
        Dimensions: those of the 1-D inputs, in the order omega2, eps, theta0 (the scalars
        are scalar coordinates). Data variables :data:`VARIABLES`: every
        :class:`~hairbed.Solution` field (``physical`` bool, ``n_roots`` and ``status``
        int64) and ``stress_ratio`` = 1/(1 - eps h1). Every variable and coordinate has CF
        ``units`` and ``long_name``; the attributes record the branch (``branch_sign``,
        ``branch_n``), ``root`` and ``hairbed_version``. Values are bitwise those of
        :func:`hairbed.solve` at the same points.

    Raises
    ------
    ValueError
        For inputs out of range (naming the parameter and the first bad index), inputs of
        more than one dimension or empty, a bad branch, root or ``chunks``.
    ImportError
        Without xarray (or dask, for ``chunks``): ``pip install "hairbed[sweep]"``.
    """
    xr = _need("xarray", "hairbed.sweep")
    values = {"omega2": _axis(omega2, "omega2"), "eps": _axis(eps, "eps")}
    values["theta0"] = _axis(theta0, "theta0")
    sign, n = check_branch(sign, n)
    code = _ROOT_CODES[check_root(root)]
    progress = check_flag(progress, "progress")
    dims = tuple(d for d in DIMS if values[d].ndim == 1)
    axes = [values[d] for d in dims]
    fixed = {d: float(values[d]) for d in DIMS if d not in dims}
    sizes = {d: values[d].size for d in dims}
    if chunks is not None:
        _chunk_sizes(chunks, sizes)  # fail before any work
    total = int(np.prod(list(sizes.values()), dtype=np.int64))
    bar = _Progress(total) if progress else None
    stacked = _stacked(
        _grid_block,
        axes,
        dims,
        len(VARIABLES),
        chunks,
        bar,
        dims=dims,
        fixed=fixed,
        sign=sign,
        n=n,
        code=code,
    )
    data_vars = {}
    for k, name in enumerate(VARIABLES):
        units, long_name = ATTRS[name]
        attrs: dict[str, Any] = {"units": units, "long_name": long_name}
        if name == "status":
            attrs.update(_STATUS_FLAGS)
        data_vars[name] = _variable(stacked, k, name, dims, attrs)
    coords = {}
    for d in DIMS:
        units, long_name = ATTRS[d]
        coords[d] = (
            (d,) if d in dims else (),
            values[d],
            {"units": units, "long_name": long_name},
        )
    attrs = {
        "title": "hairbed sweep: exact deformation of a boundary hair in channel flow",
        "Conventions": "CF-1.8",
        "source": f"hairbed {_version()} (hairbed.sweep)",
        "references": "arXiv:2203.04169",
        "hairbed_version": _version(),
        "branch_sign": np.int64(sign),
        "branch_n": np.int64(n),
        "physical_branch": np.int64(sign == 1 and n == 0),
        "root": root,
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def bed_sweep(
    bed: Any,
    velocity: Any,
    *,
    root: str = "low",
    chunks: int | Mapping[str, int] | None = None,
    progress: bool = False,
) -> Any:
    """A bed's states over wall speeds, in SI units, as an xarray Dataset (``HairBed.sweep``).

    Parameters
    ----------
    bed : HairBed
        The bed (its eps = L/H and base angle are fixed).
    velocity : float or 1-D array_like
        Speed of the top wall v [m/s], the dimension ``velocity``; negative for flow towards
        -x (the mirror image, :mod:`hairbed.units`).
    root, chunks, progress
        As in :func:`sweep` (``chunks`` an int or ``{"velocity": length}``).

    Returns
    -------
    xarray.Dataset
        Coordinates ``velocity`` [m s-1], ``omega2``, ``theta0`` (sign(v) times the base
        angle: the problem solved) and ``direction``; data variables tip deflection,
        displacement and height [m], tip angle [rad], wall shear stress [Pa], force per
        hair [N], the stress ratio H/(H - h1 L), and the dimensionless fields beside them
        (``scaled_tip_height`` ... in units of L, ``xi``, ``omega_eps``, ``energy``,
        ``base_curvature``, ``t``, ``n_roots``, ``physical``, ``status``); the bed's
        parameters in the attributes. Values are bitwise those of ``bed.deform``.
    """
    xr = _need("xarray", "HairBed.sweep")
    if not all(hasattr(bed, a) for a in ("deform", "velocity_scale", "eps", "length")):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    v = as_float_array(velocity, "velocity", unit="m/s")
    if v.ndim > 1:
        raise ValueError(f"velocity must be a scalar or a 1-D array, got shape {v.shape}")
    if v.ndim == 1 and v.size == 0:
        raise ValueError("velocity must not be empty")
    root = check_root(root)
    progress = check_flag(progress, "progress")
    dims: tuple[str, ...] = ("velocity",) if v.ndim == 1 else ()
    if chunks is not None:
        _chunk_sizes(chunks, {d: v.size for d in dims})
    bar = _Progress(v.size) if progress else None
    names = (*_BED_COORDS, *_BED_VARIABLES)
    if dims:
        stacked = _stacked(_bed_block, [v], dims, len(names), chunks, bar, bed=bed, root=root)
    else:
        one = _stacked(
            lambda progress, **kw: _bed_block(v.reshape(1), progress=progress, **kw)[:, 0],
            [],
            (),
            len(names),
            None,
            bar,
            bed=bed,
            root=root,
        )
        if chunks is not None:
            da = _need("dask.array", "a chunked sweep")
            one = da.from_array(one, chunks=-1)
        stacked = one
    coords: dict[str, Any] = {"velocity": (dims, v, _cf(BED_ATTRS["velocity"]))}
    data_vars = {}
    for k, name in enumerate(names):
        attrs = _cf(BED_ATTRS[name])
        if name == "status":
            attrs.update(_STATUS_FLAGS)
        var = _variable(stacked, k, name, dims, attrs)
        if name in _BED_COORDS:
            coords[name] = var
        else:
            data_vars[name] = var
    attrs = {
        "title": "hairbed sweep of a hair bed over the wall speed (SI units)",
        "Conventions": "CF-1.8",
        "source": f"hairbed {_version()} (HairBed.sweep)",
        "references": "arXiv:2203.04169",
        "hairbed_version": _version(),
        "branch_sign": np.int64(1),
        "branch_n": np.int64(0),
        "physical_branch": np.int64(1),
        "root": root,
        "bed": repr(bed),
        "eps": float(bed.eps),
    }
    for name, unit in (
        ("length", "m"),
        ("radius", "m"),
        ("youngs_modulus", "Pa"),
        ("channel_height", "m"),
        ("viscosity", "Pa s"),
        ("spacing", "m"),
        ("packing_fraction", "1"),
        ("base_angle", "rad"),
        ("velocity_scale", "m s-1"),
    ):
        attrs[f"bed_{name}"] = float(getattr(bed, name))
        attrs[f"bed_{name}_units"] = unit
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _cf(pair: tuple[str, str]) -> dict[str, Any]:
    return {"units": pair[0], "long_name": pair[1]}


def path_dataset(solution: Any, *, kind: str, root: str, omega2: Any = None) -> Any:
    """A 1-D :class:`~hairbed.Solution` along a path of forcing as a Dataset (dimension ``step``).

    For the quasi-static sweeps of :mod:`hairbed.quasistatic`, whose forcing path may go up
    and down (so omega2 is a coordinate along ``step``, not a dimension): ``omega2`` is the
    path as requested (default the solution's own omega2, equal to rounding). The variables
    and attributes are those of :func:`sweep`, plus ``kind``.
    """
    xr = _need("xarray", "a sweep dataset")
    w = solution.omega2 if omega2 is None else omega2
    w = np.atleast_1d(np.asarray(w, dtype=np.float64))
    dims = ("step",)
    size = w.size
    data_vars = {}
    for name in VARIABLES:
        attrs = _cf(ATTRS[name])
        if name == "status":
            attrs.update(_STATUS_FLAGS)
        if name == "stress_ratio":
            e = np.broadcast_to(np.asarray(solution.eps, dtype=np.float64), (size,))
            h1 = np.atleast_1d(np.asarray(solution.tip_height, dtype=np.float64))
            value = 1.0 / (1.0 - e * h1)
        else:
            value = np.atleast_1d(np.asarray(getattr(solution, name)))
        data_vars[name] = (dims, value, attrs)
    coords = {
        "step": (dims, np.arange(size), {"units": "1", "long_name": "index along the path"}),
        "omega2": (dims, w, _cf(ATTRS["omega2"])),
        "eps": ((), float(np.asarray(solution.eps).flat[0]), _cf(ATTRS["eps"])),
        "theta0": ((), float(np.asarray(solution.theta0).flat[0]), _cf(ATTRS["theta0"])),
    }
    attrs = {
        "title": f"hairbed {kind} sweep along a path of forcing",
        "Conventions": "CF-1.8",
        "source": f"hairbed {_version()}",
        "references": "arXiv:2203.04169",
        "hairbed_version": _version(),
        "branch_sign": np.int64(solution.sign),
        "branch_n": np.int64(solution.n),
        "physical_branch": np.int64(solution.sign == 1 and solution.n == 0),
        "root": root,
        "kind": kind,
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


# -- files ----------------------------------------------------------------------------------


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
    def plain(v: Any) -> Any:
        if isinstance(v, np.ndarray):
            return v.tolist()
        if isinstance(v, np.generic):
            return v.item()
        return v

    return json.dumps({k: plain(v) for k, v in ds.attrs.items()})


def _write_parquet(ds: Any, path: Path) -> int:
    pa = _need("pyarrow", "parquet output")
    pq = _need("pyarrow.parquet", "parquet output")
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


def write_dataset(ds: Any, path: str | os.PathLike[str]) -> int:
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
    path = Path(path)
    points = int(np.prod(list(ds.sizes.values()), dtype=np.int64))
    if kind == "netcdf":
        _need("netCDF4", "netCDF output")
        with atomic_path(path) as tmp:
            ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4")
    elif kind == "zarr":
        zarr = _need("zarr", "zarr output")
        # format 2 with consolidated metadata: read by every zarr library without a warning
        fmt = {"zarr_format": 2} if int(zarr.__version__.split(".")[0]) >= 3 else {}
        with atomic_path(path, directory=True) as tmp:
            ds.to_zarr(tmp, mode="w-", consolidated=True, **fmt)
    elif kind == "csv":
        with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8", newline="") as fh:
            _write_csv(ds, fh)
    else:
        with atomic_path(path) as tmp:
            _write_parquet(ds, tmp)
    return points


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
        pq = _need("pyarrow.parquet", "parquet input")
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
        elif name in _INTEGER or name == "step":
            columns[name] = np.array([int(x) for x in raw], dtype=np.int64)
        else:
            columns[name] = np.array([float(x) for x in raw], dtype=np.float64)
    return columns, units
