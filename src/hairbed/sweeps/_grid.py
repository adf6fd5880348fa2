"""The sweeps: the exact solution on a grid of inputs (or along a path) as a labelled
xarray Dataset, eager or dask-backed, with CF attributes on every variable."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._channel_drives import pump_drive
from .._core.solver import _ROOT_CODES
from .._core.validation import (
    as_float_array,
    check_branch,
    check_flag,
    check_inputs,
    check_root,
)
from .._optional import optional_import
from ._attributes import (
    ATTRS,
    BED_ATTRS,
    BED_COORDS,
    BED_PARAMETERS,
    BED_UNITS,
    BED_VARIABLES,
    DIMS,
    LOADED_ATTRS,
    LOADED_VARIABLES,
    PILLAR_ATTRS,
    PILLAR_DIMS,
    PILLAR_INTEGER,
    PILLAR_VARIABLES,
    PUMPED_ATTRS,
    PUMPED_INTEGER,
    VARIABLES,
    cf,
    dataset_attrs,
    pumped_variables,
    variable_attrs,
)
from ._blocks import (
    bed_block,
    chunk_sizes,
    grid_block,
    loaded_block,
    pillar_block,
    pumped_block,
    stacked,
    variable,
)
from ._progress import Progress

__all__ = ["bed_sweep", "path_dataset", "sweep"]


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


def _si_axis(value: Any, name: str, unit: str) -> NDArray[np.float64]:
    """A scalar (0-d) or non-empty 1-D finite float array of an SI quantity."""
    arr = as_float_array(value, name, unit=unit)
    if arr.ndim > 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array, got shape {arr.shape}")
    if arr.ndim == 1 and arr.size == 0:
        raise ValueError(f"{name} must not be empty")
    return arr


def sweep(
    omega2: Any = None,
    eps: Any = None,
    theta0: Any = 0.0,
    *,
    sign: int = 1,
    n: int = 0,
    root: str = "low",
    chunks: int | Mapping[str, int] | None = None,
    progress: bool = False,
    pi: Any = None,
    q: Any = None,
    forcing: Any = None,
    gamma: Any = None,
    tip_load: Any = None,
    height_ratio: Any = None,
    profile: Any = None,
) -> Any:
    """The exact solution on the outer-product grid of the inputs, as an xarray Dataset.

    With ``forcing`` it is the sweep of an isolated pillar (theory.md §12) instead: see
    ``forcing`` below.

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
    pi, q : float or 1-D array_like, optional
        A pump's drive (at most one): the dimensionless pressure gradient pi or flow rate q
        of :func:`hairbed.solve_loaded`, a fourth dimension after theta0. The grid is then
        solved by the distributed-load solver (the physical branch; ``sign``/``n`` must be
        the default) and the variables are :data:`LOADED_VARIABLES`.
    forcing : float or 1-D array_like, optional
        An isolated pillar's forcing Lambda = zeta_perp tau_w L^4/(eta E I) [-]: the grid is
        then that of :func:`hairbed.solve_pillar` over the dimensions ``forcing``,
        ``theta0``, ``gamma``, ``tip_load`` and ``height_ratio`` (the 1-D ones among them, in
        that order; the others scalar coordinates), and ``omega2``, ``eps``, ``pi``, ``q``,
        ``sign``, ``n`` and ``root`` do not apply. The data variables are
        :data:`PILLAR_VARIABLES` (every :class:`hairbed.PillarState` field but its inputs;
        ``status``, ``nit`` and ``num`` int64), with the CF attributes of
        :data:`hairbed._variables.PILLAR`; the profile's name is in the dataset's
        attributes (the height ratio, when given, is a coordinate). Values are those of
        :func:`hairbed.solve_pillar` at the same points, to its tolerance (a batch's Newton
        iterations stop together, so a point solved alone may differ in the last digits).
    gamma, tip_load : float or 1-D array_like, optional
        With ``forcing``: the drag ratio zeta_par/zeta_perp in (0, 1] [-] (default 1/2) and a
        horizontal tip force [E I/L^2] (default 0).
    height_ratio : float or 1-D array_like, optional
        With ``forcing``: L/H in (0, 1] of the channel profiles (required for "poiseuille").
    profile : {"sublayer", "couette", "poiseuille"} or callable, optional
        With ``forcing``: the undisturbed profile U(z) (default "sublayer").

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
    xr = optional_import("xarray", "hairbed.sweep", "sweep")
    pillar = {"gamma": gamma, "tip_load": tip_load, "height_ratio": height_ratio}
    if forcing is not None:
        given = {"omega2": omega2, "eps": eps, "pi": pi, "q": q}
        wrong = [k for k, v in given.items() if v is not None]
        if wrong or (sign, n, root) != (1, 0, "low"):
            what = wrong[0] if wrong else "sign, n and root"
            raise ValueError(
                f"{what}: a pillar's sweep (forcing=) takes forcing, theta0, gamma, tip_load, "
                "height_ratio and profile only"
            )
        return _pillar_sweep(forcing, theta0, pillar, profile, chunks, progress)
    wrong = [k for k, v in {**pillar, "profile": profile}.items() if v is not None]
    if wrong:
        raise ValueError(f"{wrong[0]} applies to a pillar's sweep only (give forcing=)")
    if omega2 is None or eps is None:
        raise TypeError("sweep() needs omega2 and eps (or forcing= for a pillar)")
    if pi is not None or q is not None:
        return _loaded_sweep(omega2, eps, theta0, pi, q, sign, n, root, chunks, progress)
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
        chunk_sizes(chunks, sizes)  # fail before any work
    total = int(np.prod(list(sizes.values()), dtype=np.int64))
    bar = Progress(total) if progress else None
    data = stacked(
        grid_block,
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
    data_vars = {
        name: variable(data, k, name, dims, variable_attrs(ATTRS[name], name))
        for k, name in enumerate(VARIABLES)
    }
    coords = {d: ((d,) if d in dims else (), values[d], cf(ATTRS[d])) for d in DIMS}
    attrs = dataset_attrs(
        "hairbed sweep: exact deformation of a boundary hair in channel flow",
        " (hairbed.sweep)",
        sign,
        n,
        root,
    )
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _loaded_sweep(
    omega2: Any,
    eps: Any,
    theta0: Any,
    pi: Any,
    q: Any,
    sign: int,
    n: int,
    root: str,
    chunks: Any,
    progress: bool,
) -> Any:
    """:func:`sweep` with a distributed load: the grid (omega2, eps, theta0, pi or q)."""
    xr = optional_import("xarray", "hairbed.sweep", "sweep")
    if pi is not None and q is not None:
        raise ValueError("give at most one of pi and q (a pump sets one drive)")
    if check_branch(sign, n) != (1, 0):
        raise ValueError("sign and n: a sweep with pi or q follows the physical branch (1, 0)")
    drive = "pi" if pi is not None else "q"
    values = {
        "omega2": _si_axis(omega2, "omega2", "-"),
        "eps": _axis(eps, "eps"),
        "theta0": _axis(theta0, "theta0"),
        drive: _si_axis(pi if q is None else q, drive, "-"),
    }
    root = check_root(root)
    progress = check_flag(progress, "progress")
    dims = tuple(d for d in values if values[d].ndim == 1)
    fixed = {d: float(values[d]) for d in values if d not in dims}
    sizes = {d: values[d].size for d in dims}
    if chunks is not None:
        chunk_sizes(chunks, sizes)
    if drive == "pi":  # checked before any work, as solve_loaded would
        bad = (values["eps"].reshape(-1) == 0.0).any() and (values["pi"] != 0.0).any()
        if bad:
            raise ValueError("pi != 0 needs eps > 0 (the gap flow's load W has (pi/2)/eps)")
    bar = Progress(int(np.prod(list(sizes.values()), dtype=np.int64))) if progress else None
    names = LOADED_VARIABLES
    kw = dict(dims=dims, fixed=fixed, drive=drive, root=root)
    data = _stacked_grid(loaded_block, values, dims, names, chunks, bar, **kw)
    coords = {d: ((d,) if d in dims else (), values[d], cf(LOADED_ATTRS[d])) for d in values}
    data_vars = _coded_variables(data, names, dims, LOADED_ATTRS, PUMPED_INTEGER)
    attrs = dataset_attrs(
        "hairbed sweep: a boundary hair under a pump's distributed load", " (hairbed.sweep)",
        1, 0, root,
    )  # fmt: skip
    attrs["drive"] = "pressure" if drive == "pi" else "flow"
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _pillar_sweep(
    forcing: Any,
    theta0: Any,
    pillar: Mapping[str, Any],
    profile: Any,
    chunks: Any,
    progress: bool,
) -> Any:
    """:func:`sweep` of an isolated pillar: the grid of (forcing, theta0, gamma, tip_load,
    height_ratio), each block by :func:`hairbed.solve_pillar`."""
    xr = optional_import("xarray", "hairbed.sweep", "sweep")
    profile = "sublayer" if profile is None else profile
    defaults = {"gamma": 0.5, "tip_load": 0.0}
    given = {"forcing": forcing, "theta0": theta0, **defaults}
    given.update({k: v for k, v in pillar.items() if v is not None})
    values = {d: _si_axis(given[d], d, "-") for d in PILLAR_DIMS if d in given}
    _check_pillar_axes(values, profile)
    progress = check_flag(progress, "progress")
    dims = tuple(d for d in values if values[d].ndim == 1)
    fixed = {d: float(values[d]) for d in values if d not in dims}
    sizes = {d: values[d].size for d in dims}
    if chunks is not None:
        chunk_sizes(chunks, sizes)
    bar = Progress(int(np.prod(list(sizes.values()), dtype=np.int64))) if progress else None
    names = PILLAR_VARIABLES
    kw = dict(dims=dims, fixed=fixed, profile=profile)
    data = _stacked_grid(pillar_block, values, dims, names, chunks, bar, **kw)
    coords = {d: ((d,) if d in dims else (), values[d], cf(PILLAR_ATTRS[d])) for d in values}
    data_vars = _coded_variables(data, names, dims, PILLAR_ATTRS, PILLAR_INTEGER)
    attrs = dataset_attrs(
        "hairbed sweep: an isolated pillar in a wall shear layer (theory.md §12)",
        " (hairbed.sweep)", 1, 0, "low",
    )  # fmt: skip
    for key in ("branch_sign", "branch_n", "physical_branch", "root"):  # no branches here
        del attrs[key]
    attrs["profile"] = profile if isinstance(profile, str) else f"callable {profile!r}"
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _stacked_grid(
    block: Any,
    values: Mapping[str, NDArray[np.float64]],
    axis_dims: tuple[str, ...],
    names: Sequence[str],
    chunks: Any,
    bar: Any,
    /,
    **kw: Any,
) -> Any:
    """The stacked fields of a collocation sweep's grid (one dask chunk of the one state where
    no input is an axis but chunks are asked for); ``kw`` go to the block."""
    axes = [values[d] for d in axis_dims]
    data = stacked(block, axes, axis_dims, len(names), chunks if axis_dims else None, bar, **kw)
    if not axis_dims and chunks is not None:
        da = optional_import("dask.array", "a chunked sweep", "sweep")
        data = da.from_array(data, chunks=-1)
    return data


def _coded_variables(
    data: Any,
    names: Sequence[str],
    dims: tuple[str, ...],
    table: Mapping[str, Any],
    integer: Any,
) -> dict[str, Any]:
    """The data variables of a collocation sweep: CF attributes from ``table``, the integer
    fields as int64, and the status pointing to the solver's codes (more than the closed
    form's flags)."""
    out = {}
    for k, name in enumerate(names):
        var = data[k]
        if name in integer:
            var = var.astype(np.int64)
        attrs = cf(table[name])
        if name == "status":
            attrs["comment"] = "0 converged; others: hairbed._core.validation.STATUS_MESSAGES"
        out[name] = (dims, var, attrs)
    return out


def _check_pillar_axes(values: Mapping[str, NDArray[np.float64]], profile: Any) -> None:
    """The ranges of a pillar's axes, before any work, as :func:`hairbed.solve_pillar`
    checks them (its messages, naming the parameter and the first bad index)."""
    from .._core.pillar import _check, profile_coefficients
    from .._core.validation import _check_range

    inputs = ("forcing", "theta0", "gamma", "tip_load")
    for d in inputs:  # one axis at a time: the axes do not broadcast together
        _check(*(values[d] if k == d else (0.5 if k == "gamma" else 0.0) for k in inputs))
    ratios = values.get("height_ratio")
    if ratios is not None:
        _check_range(ratios, ~((ratios > 0.0) & (ratios <= 1.0)), "height_ratio", "(0, 1]")
        profile_coefficients(profile, float(ratios.reshape(-1)[0]))
    else:
        profile_coefficients(profile, None)  # e.g. "poiseuille" without a height ratio


def bed_sweep(
    bed: Any,
    velocity: Any = None,
    *,
    pressure_gradient: Any = None,
    flow_rate: Any = None,
    root: str = "low",
    chunks: int | Mapping[str, int] | None = None,
    progress: bool = False,
) -> Any:
    """A bed's states over wall speeds, in SI units, as an xarray Dataset (``HairBed.sweep``).

    Parameters
    ----------
    bed : HairBed
        The bed (its eps = L/H and base angle are fixed).
    velocity : float or 1-D array_like, optional
        Speed of the top wall v [m/s], the dimension ``velocity``; negative for flow towards
        -x (the mirror image, :mod:`hairbed.units`). With a pump drive, default 0 (at rest).
    pressure_gradient, flow_rate : float or 1-D array_like, optional
        A pump's drive, G [Pa/m] or Q' [m^2/s] (at most one), the dimension of its name: the
        grid is then the outer product of ``velocity`` and it, solved by the distributed-load
        solver (:meth:`hairbed.HairBed.deform`). The variables are :data:`PUMPED_ATTRS`: the
        SI state, the dimensionless tip ``scaled_*`` in the bed's frame, and the solver's
        ``pi`` or ``q``, loads, ``status``, error estimate, residual, ``nit`` and ``num``.
    root, chunks, progress
        As in :func:`sweep` (``chunks`` an int or ``{"velocity": length}``).

    Returns
    -------
    xarray.Dataset
        Coordinates ``velocity`` [m s-1], ``omega2``, ``theta0`` (sign(v) times the base
        angle: the problem solved) and ``direction``; data variables every other
        :class:`~hairbed.units.HairState` field (tip deflection, height and displacement
        [m], tip angle [rad], wall shear stress [Pa], force per hair [N], the stress ratio
        H/(H - h1 L), the gap's Reynolds number, NaN without a fluid density), and the
        dimensionless fields beside them
        (``scaled_tip_height`` ... in units of L, ``xi``, ``omega_eps``, ``energy``,
        ``base_curvature``, ``t``, ``n_roots``, ``physical``, ``status``); the bed's
        parameters in the attributes. Values are bitwise those of ``bed.deform``.
    """
    xr = optional_import("xarray", "HairBed.sweep", "sweep")
    if not all(hasattr(bed, a) for a in ("deform", "velocity_scale", "eps", "length")):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    if getattr(bed, "shape", ()):  # an array-valued bed (issue 32): one sweep per bed
        bed._require_scalar("HairBed.sweep")
    if getattr(bed, "model", "dense") == "porous":
        from ._porous import porous_sweep

        return porous_sweep(
            bed, velocity, pressure_gradient, flow_rate, root, chunks, progress, _si_axis
        )
    if pressure_gradient is not None or flow_rate is not None:
        return _pumped_sweep(bed, velocity, pressure_gradient, flow_rate, root, chunks, progress)
    if velocity is None:
        raise TypeError("sweep() needs velocity [m/s], pressure_gradient [Pa/m] or flow_rate")
    v = as_float_array(velocity, "velocity", unit="m/s")
    if v.ndim > 1:
        raise ValueError(f"velocity must be a scalar or a 1-D array, got shape {v.shape}")
    if v.ndim == 1 and v.size == 0:
        raise ValueError("velocity must not be empty")
    root = check_root(root)
    progress = check_flag(progress, "progress")
    dims: tuple[str, ...] = ("velocity",) if v.ndim == 1 else ()
    if chunks is not None:
        chunk_sizes(chunks, {d: v.size for d in dims})
    bar = Progress(v.size) if progress else None
    names = (*BED_COORDS, *BED_VARIABLES)
    if dims:
        data = stacked(bed_block, [v], dims, len(names), chunks, bar, bed=bed, root=root)
    else:
        data = stacked(
            lambda progress, **kw: bed_block(v.reshape(1), progress=progress, **kw)[:, 0],
            [],
            (),
            len(names),
            None,
            bar,
            bed=bed,
            root=root,
        )
        if chunks is not None:
            da = optional_import("dask.array", "a chunked sweep", "sweep")
            data = da.from_array(data, chunks=-1)
    coords: dict[str, Any] = {"velocity": (dims, v, cf(BED_ATTRS["velocity"]))}
    data_vars = {}
    for k, name in enumerate(names):
        var = variable(data, k, name, dims, variable_attrs(BED_ATTRS[name], name))
        if name in BED_COORDS:
            coords[name] = var
        else:
            data_vars[name] = var
    attrs = dataset_attrs(
        "hairbed sweep of a hair bed over the wall speed (SI units)",
        " (HairBed.sweep)",
        1,
        0,
        root,
    )
    return xr.Dataset(data_vars, coords=coords, attrs=_bed_attrs(bed, attrs))


def _bed_attrs(bed: Any, attrs: dict[str, Any]) -> dict[str, Any]:
    attrs.update(bed=repr(bed), eps=float(bed.eps))
    for name in BED_PARAMETERS:
        attrs[f"bed_{name}"] = float(getattr(bed, name))
        attrs[f"bed_{name}_units"] = BED_UNITS[name]
    return attrs


def _pumped_sweep(
    bed: Any,
    velocity: Any,
    pressure_gradient: Any,
    flow_rate: Any,
    root: str,
    chunks: Any,
    progress: bool,
) -> Any:
    """:func:`bed_sweep` with a pump drive: the grid (velocity, drive), outer product."""
    xr = optional_import("xarray", "HairBed.sweep", "sweep")
    drive, unit, given = pump_drive(pressure_gradient, flow_rate)
    values = {
        "velocity": _si_axis(0.0 if velocity is None else velocity, "velocity", "m/s"),
        drive: _si_axis(given, drive, unit),
    }
    root = check_root(root)
    progress = check_flag(progress, "progress")
    dims = tuple(d for d in ("velocity", drive) if values[d].ndim == 1)
    fixed = {d: float(values[d]) for d in values if d not in dims}
    sizes = {d: values[d].size for d in dims}
    if chunks is not None:
        chunk_sizes(chunks, sizes)
    bar = Progress(int(np.prod(list(sizes.values()), dtype=np.int64))) if progress else None
    names = ("omega2", *pumped_variables(drive))
    kw = dict(dims=dims, fixed=fixed, bed=bed, drive=drive, root=root)
    data = _stacked_grid(pumped_block, values, dims, names, chunks, bar, **kw)
    coords: dict[str, Any] = {
        d: ((d,) if d in dims else (), values[d], cf(PUMPED_ATTRS[d])) for d in values
    }
    data_vars = _coded_variables(data, names, dims, PUMPED_ATTRS, PUMPED_INTEGER)
    coords["omega2"] = data_vars.pop("omega2")  # the forcing each state has: a coordinate
    what = "pressure gradient" if drive == "pressure_gradient" else "flow rate"
    attrs = dataset_attrs(
        f"hairbed sweep of a pump-driven hair bed over the {what} (SI units)",
        " (HairBed.sweep)",
        1,
        0,
        root,
    )
    attrs["drive"] = drive
    return xr.Dataset(data_vars, coords=coords, attrs=_bed_attrs(bed, attrs))


def path_dataset(solution: Any, *, kind: str, root: str, omega2: Any = None) -> Any:
    """A 1-D :class:`~hairbed.Solution` along a path of forcing as a Dataset (dimension ``step``).

    For the quasi-static sweeps of :mod:`hairbed.quasistatic`, whose forcing path may go up
    and down (so omega2 is a coordinate along ``step``, not a dimension): ``omega2`` is the
    path as requested (default the solution's own omega2, equal to rounding). The variables
    and attributes are those of :func:`sweep`, plus ``kind``.
    """
    xr = optional_import("xarray", "a sweep dataset", "sweep")
    w = solution.omega2 if omega2 is None else omega2
    w = np.atleast_1d(np.asarray(w, dtype=np.float64))
    dims = ("step",)
    size = w.size
    data_vars = {}
    for name in VARIABLES:
        if name == "stress_ratio":
            e = np.broadcast_to(np.asarray(solution.eps, dtype=np.float64), (size,))
            h1 = np.atleast_1d(np.asarray(solution.tip_height, dtype=np.float64))
            value = 1.0 / (1.0 - e * h1)
        else:
            value = np.atleast_1d(np.asarray(getattr(solution, name)))
        data_vars[name] = (dims, value, variable_attrs(ATTRS[name], name))
    coords = {
        "step": (dims, np.arange(size), {"units": "1", "long_name": "index along the path"}),
        "omega2": (dims, w, cf(ATTRS["omega2"])),
        "eps": ((), float(np.asarray(solution.eps).flat[0]), cf(ATTRS["eps"])),
        "theta0": ((), float(np.asarray(solution.theta0).flat[0]), cf(ATTRS["theta0"])),
    }
    attrs = dataset_attrs(
        f"hairbed {kind} sweep along a path of forcing", "", solution.sign, solution.n, root
    )
    attrs["kind"] = kind
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)
