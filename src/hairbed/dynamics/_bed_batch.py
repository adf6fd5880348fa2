"""Many porous beds in time in one call (issue 30, theory.md §15).

:func:`simulate_beds` runs :func:`simulate_bed` for each bed of a batch (the model's
parameters as arrays, broadcast; the drives one for all or one per bed) and gathers the
outputs into one :class:`BedBatch` with a ``bed`` dimension. Each bed is its own run of the
compiled Radau IIA integrator (``_kernels.dynamics.integrate_bed``: its own steps and error
control, bitwise the run :func:`simulate_bed` gives on its own); the runs share out over
``workers`` threads, as :func:`simulate_pillars` does, since the integrator releases the
GIL (its Python preparation, the static start and the outputs, does not).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.validation import (
    StatusResult,
    as_float_array,
    check_int,
    check_positive,
    show,
)
from ._bed import (
    BED_STATUS,
    EPS_MIN,
    KAPPA_RANGE,
    NUMBER_RANGE,
    SERIES_ATTRS,
    BedTrajectory,
    _drive_names,
    simulate_bed,
)

__all__ = ["BED_BATCH_STATUS", "BedBatch", "simulate_beds"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: The status codes of each bed of a :class:`BedBatch` (those of :class:`BedTrajectory`).
BED_BATCH_STATUS: Mapping[int, str] = BED_STATUS

#: The time series of a batch, (bed, t), as in :class:`BedTrajectory`, with their units.
_PARAMS = ("theta0", "kappa", "eps", "gamma", "inertia", "tangential_mass", "womersley")
_WORK = ("nsteps", "naccept", "nreject", "nfev", "njev", "nlu")


@dataclass(frozen=True)
class BedBatch(StatusResult):
    """A batch of porous beds in time (:func:`simulate_beds`): each output of
    :class:`BedTrajectory` stacked on a ``bed`` dimension, (bed, t). Time in
    T = zeta_perp L^4/(E I) (each bed's own), lengths in L, stresses in the load units of
    §13.

    Attributes
    ----------
    t : ndarray
        The output times [T], shared. Past a bed's event or failure its values are NaN.
    top, pump : str
        The drives' kinds (as :class:`BedTrajectory`), shared.
    top_drive, pump_drive, tip_deflection, tip_height, tip_angle, base_moment, wall_stress, \
wall_speed, flow_rate, pressure : ndarray
        (bed, t): as the attributes of :class:`BedTrajectory` ([-], [L], [rad], [E I/L],
        [E I/(A L^2)]).
    theta0, kappa, eps, gamma, inertia, tangential_mass, womersley : ndarray
        (bed,): each bed's model constants.
    num, num_gap : ndarray of int
        (bed,): the Chebyshev degrees of each run.
    status : ndarray of int
        (bed,): 0 reached the last time; -8, -2, -3 as :class:`BedTrajectory`
        (``BED_BATCH_STATUS``).
    t_end : ndarray
        (bed,): where each run ended [T].
    nsteps, naccept, nreject, nfev, njev, nlu : ndarray of int
        (bed,): each run's work.
    """

    t: FloatArray
    top: str
    pump: str
    top_drive: FloatArray
    pump_drive: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    tip_angle: FloatArray
    base_moment: FloatArray
    wall_stress: FloatArray
    wall_speed: FloatArray
    flow_rate: FloatArray
    pressure: FloatArray
    theta0: FloatArray
    kappa: FloatArray
    eps: FloatArray
    gamma: FloatArray
    inertia: FloatArray
    tangential_mass: FloatArray
    womersley: FloatArray
    num: IntArray
    num_gap: IntArray
    status: IntArray
    t_end: FloatArray
    nsteps: IntArray
    naccept: IntArray
    nreject: IntArray
    nfev: IntArray
    njev: IntArray
    nlu: IntArray

    def __len__(self) -> int:
        return int(self.status.size)

    _status_table: ClassVar[Mapping[int, str]] = BED_BATCH_STATUS

    def to_xarray(self) -> Any:
        """The batch as an xarray.Dataset with the dimensions ``bed`` and ``t``, CF
        attributes. Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedBatch.to_xarray", "io")
        data: dict[str, Any] = {}
        for name, (units, long) in _drive_names(SERIES_ATTRS, self.top, self.pump).items():
            data[name] = (("bed", "t"), getattr(self, name), {"units": units, "long_name": long})
        par_units = {"theta0": "rad"}
        for name in _PARAMS:
            data[name] = ("bed", getattr(self, name), {"units": par_units.get(name, "1"),
                                                         "long_name": name})  # fmt: skip
        data["num"] = ("bed", self.num, {"units": "1", "long_name": "Chebyshev degree N"})
        data["num_gap"] = ("bed", self.num_gap, {"units": "1", "long_name": "gap degree M"})
        data["status"] = ("bed", self.status, {"units": "1", "long_name": "status"})
        data["t_end"] = ("bed", self.t_end, {"units": "T", "long_name": "end of the run"})
        for name in _WORK:
            data[name] = ("bed", getattr(self, name), {"units": "1", "long_name": name})
        return xr.Dataset(
            data,
            coords={
                "bed": ("bed", np.arange(len(self)), {"units": "1", "long_name": "bed index"}),
                "t": (
                    "t",
                    self.t,
                    {"units": "T", "long_name": "time, T = zeta_perp L^4/(E I)"},
                ),
            },
            attrs={
                "title": "hairbed porous beds in time",
                "top": self.top,
                "pump": self.pump,
                "Conventions": "CF-1.10",
            },
        )


def _per_bed(value: Any) -> list[Any] | None:
    """A drive given per bed (a list or tuple), or None for one drive for all."""
    return list(value) if isinstance(value, (list, tuple)) else None


def _check_array(name: str, value: Any, count: int, ok: Any, what: str) -> FloatArray:
    arr = as_float_array(value, name).reshape(-1)
    arr = np.full(count, arr[0]) if arr.size == 1 else arr
    with np.errstate(invalid="ignore"):
        bad = ~(np.isfinite(arr) & ok(arr))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name} must {what}, got {show(float(arr[i]))} (bed {i})")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _zero_or(lo: float, hi: float) -> Any:
    return lambda a: (a == 0.0) | ((a >= lo) & (a <= hi))


def simulate_beds(
    theta0: ArrayLike,
    kappa: ArrayLike,
    eps: ArrayLike,
    *,
    t_eval: ArrayLike,
    wall: Any = None,
    pressure: Any = None,
    flow_rate: Any = None,
    wall_stress: Any = None,
    gamma: ArrayLike = 1.0,
    inertia: ArrayLike = 0.0,
    tangential_mass: ArrayLike = 1.0,
    womersley: ArrayLike = 0.0,
    num: int | None = None,
    num_gap: int = 16,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 100_000,
    workers: int = 1,
) -> BedBatch:
    """Many porous beds in time-dependent flow in one call: :func:`simulate_bed` for each.

    The beds differ in their model constants (arrays, broadcast to one length) and may each
    have their own drives; each is its own run of the compiled integrator (bitwise what
    :func:`simulate_bed` gives for that bed alone), the runs shared out over ``workers``
    threads (the integrator releases the GIL). The equations are those of
    :func:`simulate_bed` (theory.md §15), time in T = zeta_perp L^4/(E I).

    Parameters
    ----------
    theta0, kappa, eps : array_like
        Each bed's base angle [rad] in (-pi/2, pi/2), permeability over L^2 [-] in
        [1e-6, 1e6] and L/H [-] in [1e-3, 1); scalars or 1-d, broadcast together.
    t_eval : array_like
        The output times [T], shared (finite, non-decreasing).
    wall, wall_stress, pressure, flow_rate : optional
        The drives as in :func:`simulate_bed` (a number, Signal or callable), one for all
        beds, or a list (or tuple) of them, one per bed; at most one of wall and
        wall_stress, and of pressure and flow_rate.
    gamma, inertia, tangential_mass, womersley : array_like, optional
        Each bed's drag ratio in (0, 1], mu (0 or in [1e-6, 1e6]), chi in (0, 1] and alpha
        (0 or in [1e-6, 1e6]) [-]; broadcast with the others.
    num, num_gap, rtol, atol, max_steps : optional
        As in :func:`simulate_bed`, shared.
    workers : int, optional
        Threads in [1, 64] (default 1).

    Returns
    -------
    BedBatch
        The outputs (bed, t), each bed with its own ``status``.

    Raises
    ------
    ValueError, TypeError
        For an input outside its range, naming the parameter and the first bed (its index)
        where it is.

    Examples
    --------
    >>> from hairbed.dynamics import simulate_beds, step
    >>> runs = simulate_beds(0.0, [0.1, 1.0], 0.5, wall=step(1.0), t_eval=[0.0, 5.0])
    >>> runs.success.tolist(), runs.tip_deflection.shape
    ([True, True], (2, 2))
    """
    from ._integrate import _checked_times

    te = _checked_times(t_eval)
    nw = check_int(workers, "workers", 1, 64)
    check_int(num_gap, "num_gap", 4, 128)
    if num is not None:
        check_int(num, "num", 8, 128)
    check_positive(rtol, "rtol")
    check_positive(atol, "atol")
    check_int(max_steps, "max_steps", 1, 10**12)
    values = {
        "theta0": theta0,
        "kappa": kappa,
        "eps": eps,
        "gamma": gamma,
        "inertia": inertia,
        "tangential_mass": tangential_mass,
        "womersley": womersley,
    }
    drives = {"wall": wall, "wall_stress": wall_stress, "pressure": pressure,
              "flow_rate": flow_rate}  # fmt: skip
    sizes: dict[str, int] = {}
    for name, val in values.items():
        arr = as_float_array(val, name)
        if arr.ndim > 1:
            raise ValueError(f"{name} must be a scalar or 1-d, got shape {arr.shape}")
        if arr.ndim == 1:
            sizes[name] = arr.size
    for name, val in drives.items():
        seq = _per_bed(val)
        if seq is not None:
            sizes[name] = len(seq)
    if len(set(sizes.values())) > 1:
        got = ", ".join(f"{k} {v}" for k, v in sizes.items())
        raise ValueError(f"the beds' arrays and drive lists must have one length, got {got}")
    count = next(iter(sizes.values())) if sizes else 1
    if count < 1:
        raise ValueError(f"simulate_beds needs at least one bed: {', '.join(sizes)} empty")
    lo, hi = NUMBER_RANGE
    arrs = {
        "theta0": _check_array("theta0", theta0, count,
                               lambda a: np.abs(a) < 0.5 * np.pi, "lie in (-pi/2, pi/2)"),
        "kappa": _check_array("kappa", kappa, count,
                              lambda a: (a >= KAPPA_RANGE[0]) & (a <= KAPPA_RANGE[1]),
                              f"lie in [{KAPPA_RANGE[0]:g}, {KAPPA_RANGE[1]:g}]"),
        "eps": _check_array("eps", eps, count, lambda a: (a >= EPS_MIN) & (a < 1.0),
                            f"lie in [{EPS_MIN:g}, 1)"),
        "gamma": _check_array("gamma", gamma, count, lambda a: (a > 0.0) & (a <= 1.0),
                              "lie in (0, 1]"),
        "inertia": _check_array("inertia", inertia, count, _zero_or(lo, hi),
                                f"be 0 or lie in [{lo:g}, {hi:g}]"),
        "tangential_mass": _check_array("tangential_mass", tangential_mass, count,
                                        lambda a: (a > 0.0) & (a <= 1.0), "lie in (0, 1]"),
        "womersley": _check_array("womersley", womersley, count, _zero_or(lo, hi),
                                  f"be 0 or lie in [{lo:g}, {hi:g}]"),
    }  # fmt: skip
    lists = {k: _per_bed(v) for k, v in drives.items()}

    def kwargs(i: int) -> dict[str, Any]:
        kw: dict[str, Any] = {}
        for name, val in drives.items():
            seq = lists[name]
            kw[name] = seq[i] if seq is not None else val
        return kw

    def one(i: int) -> BedTrajectory:
        try:
            return simulate_bed(
                float(arrs["theta0"][i]),
                float(arrs["kappa"][i]),
                float(arrs["eps"][i]),
                t_eval=te,
                gamma=float(arrs["gamma"][i]),
                inertia=float(arrs["inertia"][i]),
                tangential_mass=float(arrs["tangential_mass"][i]),
                womersley=float(arrs["womersley"][i]),
                num=num,
                num_gap=num_gap,
                rtol=rtol,
                atol=atol,
                max_steps=max_steps,
                **kwargs(i),
            )
        except (ValueError, TypeError) as exc:
            raise type(exc)(f"{exc} (bed {i})") from None

    if nw == 1 or count == 1:
        runs = [one(i) for i in range(count)]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=min(nw, count)) as pool:
            runs = list(pool.map(one, range(count)))
    return _gather(te, runs)


def _gather(te: FloatArray, runs: list[BedTrajectory]) -> BedBatch:
    """The runs stacked on the ``bed`` dimension."""
    first = runs[0]
    tops = {r.top for r in runs}
    pumps = {r.pump for r in runs}
    if len(tops) > 1 or len(pumps) > 1:
        raise ValueError(
            "the beds of a batch must share the kinds of their drives (wall or wall_stress, "
            f"pressure or flow_rate), got {sorted(tops)} and {sorted(pumps)}"
        )
    series: dict[str, Any] = {k: np.stack([getattr(r, k) for r in runs]) for k in SERIES_ATTRS}
    consts: dict[str, Any] = {k: np.array([float(getattr(r, k)) for r in runs]) for k in _PARAMS}
    ints: dict[str, Any] = {k: np.array([int(getattr(r, k)) for r in runs], dtype=np.int64)
            for k in ("num", "num_gap", "status", *_WORK)}  # fmt: skip
    return BedBatch(
        t=te,
        top=first.top,
        pump=first.pump,
        t_end=np.array([r.t_end for r in runs]),
        **series,
        **consts,
        **ints,
    )
