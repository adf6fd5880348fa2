"""A hair bed in time, in SI: :meth:`hairbed.HairBed.simulate` (issue 30, theory.md §15).

The porous bed in time (:func:`hairbed.dynamics.simulate_bed`: hairs and fluid together,
the top wall's speed or stress and a pump's pressure gradient or flow rate as drives) mapped
onto a :class:`hairbed.HairBed` of either ``model`` (the dense bed runs the porous model of
its geometry: its kappa and drag ratio from the bed's ``drag`` law), in the units of
:mod:`hairbed._bed_scales`:

    t = T t',  T = zeta_perp L^4/(E I) [s]
    omega2 = A eta L^2/(E I H) v,  Q = A L^2/(E I) tau,  Pi = A L^3/(E I) G,
    q = 6 A eta L^2/(E I H^2) Q',  A = pi a^2/phi,
    alpha = rho_f L^2/(eta T) (the fluid's inertia, 0 without the bed's ``density``),
    mu = (rho_s + rho_f) pi a^2/(zeta_perp T), chi = rho_s/(rho_s + rho_f) (the hairs'),

and back: lengths L x [m], the base moment E I theta_s(0)/L [N m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from dataclasses import replace as dataclasses_replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ._bed_scales import _BedScales, _is_bed, _scales
from ._core.validation import as_float_array, check_int, check_positive, show
from ._model_axes import checked_index as _checked_index
from .dynamics import (
    BedTrajectory,
    Signal,
    simulate_bed,
)
from .dynamics._bed import MAX_BED_DRIVE, NUMBER_RANGE
from .dynamics._signals import si_signal

if TYPE_CHECKING:  # units.py calls this module (HairBed.simulate): no import cycle
    from .units import HairBed

__all__ = ["BedSimulation", "simulate"]

FloatArray = NDArray[np.float64]


#: The run's time series in SI: (attribute, units, long_name), one table for both
#: :meth:`BedSimulation.to_xarray` forms.
_SERIES = (
    ("tip_deflection", "m", "tip deflection (streamwise)"),
    ("tip_height", "m", "tip height"),
    ("tip_angle", "rad", "tip angle"),
    ("base_moment", "N m", "bending moment at the base"),
    ("wall_shear_stress", "Pa", "top wall shear stress"),
    ("wall_velocity", "m/s", "top wall speed"),
    ("flow_rate", "m^2/s", "flow rate per unit width"),
    ("pressure_gradient", "Pa/m", "pressure gradient -dp/dx"),
)


@dataclass(frozen=True)
class BedSimulation:
    """A hair bed's motion in time-dependent flow, in SI (from :meth:`hairbed.HairBed.simulate`).

    Always the porous model of theory.md §15 (``model`` "porous"; a dense ``HairBed`` runs
    the porous model of its geometry, ``bed_model`` "dense").

    The run of an array bed of shape S (issue 32) holds S in front of every series (time,);
    ``time_scale``, ``kappa``, ``drag_ratio``, ``womersley``, ``inertia_number``, ``status``,
    ``t_end`` and ``trajectory`` (an object array of the dimensionless runs) are of shape S;
    :meth:`item` gives one bed's run.

    Attributes
    ----------
    time : ndarray
        The output times [s]. Past an event or a failure (``t_end``) the values are NaN.
    tip_deflection, tip_height : ndarray
        x(L, t), z(L, t) of the hairs [m].
    tip_angle : ndarray
        theta(L, t) [rad].
    base_moment : ndarray
        E I theta_s(0, t), the bending moment at a hair's base [N m].
    wall_shear_stress : ndarray
        The shear stress on the top wall [Pa] (what a rheometer measures; the drive under
        ``wall_shear_stress``).
    wall_velocity : ndarray
        The top wall's speed [m/s] (the drive, or the free wall's under a set stress).
    flow_rate : ndarray
        Flow rate per unit width through bed and gap Q' [m^2/s].
    pressure_gradient : ndarray
        G = -dp/dx [Pa/m] (the drive, or the unknown that holds a set flow rate).
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    kappa, drag_ratio : float
        The porous model's permeability over L^2 and zeta_par/zeta_perp [-].
    womersley : float
        alpha = rho_f L^2/(eta T) [-] as run (0: the quasi-steady fluid: the bed has no
        density, or alpha < 1e-6).
    inertia_number : float
        mu = (rho_s + rho_f) pi a^2/(zeta_perp T) [-] as run (0: overdamped hairs: no
        hair_density, or mu < 1e-6).
    hair_density : float
        rho_s [kg/m^3] (NaN when not given).
    model, bed_model : str
        "porous" (the model run), and the bed's own ``model``.
    status : int
        0 reached the last time; -8 a hair node reached abs(theta) = pi/2; -2 the step
        limit; -3 a step-size underflow (:data:`hairbed.dynamics.BED_STATUS`).
    t_end : float
        Where the integration ended [s].
    trajectory : hairbed.dynamics.BedTrajectory
        The dimensionless run (time in T, lengths in L).
    """

    time: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    tip_angle: FloatArray
    base_moment: FloatArray
    wall_shear_stress: FloatArray
    wall_velocity: FloatArray
    flow_rate: FloatArray
    pressure_gradient: FloatArray
    time_scale: float
    kappa: float
    drag_ratio: float
    womersley: float
    inertia_number: float
    hair_density: float
    model: str
    bed_model: str
    status: Any
    t_end: Any
    trajectory: Any = field(repr=False, compare=False)
    #: The array bed of an array run (None for a bed of numbers).
    bed: Any = field(default=None, repr=False, compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """The bed's shape: () for a bed of numbers (issue 32)."""
        return tuple(np.shape(self.status))

    @property
    def success(self) -> Any:
        """True where the run reached its last time (status 0); an array of the bed's shape
        for an array bed."""
        ok = np.asarray(self.status) == 0
        return bool(ok) if ok.ndim == 0 else ok

    @property
    def message(self) -> str | list[Any]:
        """The status's message (:data:`hairbed.dynamics.BED_STATUS`; a nested list for an
        array bed)."""
        if not self.shape:
            return str(self.trajectory.message)
        return np.vectorize(lambda r: str(r.message), otypes=[object])(self.trajectory).tolist()

    def item(self, index: Any = ()) -> BedSimulation:
        """The run of the bed at ``index`` of :attr:`shape` (as :meth:`hairbed.HairBed.item`
        indexes it); a bed of numbers' run is itself."""
        k = _checked_index(index, self.shape, "run")
        if not self.shape:
            return self
        fields: dict[str, Any] = {n: float(np.asarray(getattr(self, n))[k]) for n in _PER_BED}
        series: dict[str, Any] = {n: np.array(getattr(self, n)[k]) for n in _BED_SERIES}
        return dataclasses_replace(
            self,
            status=int(self.status[k]),
            trajectory=self.trajectory[k],
            bed=None,
            **fields,
            **series,
        )

    def to_xarray(self) -> Any:
        """The motion as an xarray.Dataset with the dimension ``time``, CF attributes.
        Needs the ``io`` extra. An array bed's run has its axes in front, named ``bed``
        (``bed_0``, ``bed_1``, ... for several), with the bed's array parameters as
        coordinates and each element's time scale, kappa, drag ratio, Womersley and
        inertia numbers, status and end as variables on them."""
        from ._optional import optional_import

        xr = optional_import("xarray", "BedSimulation.to_xarray", "io")
        if self.shape:
            return self._array_xarray(xr)

        def var(value: FloatArray, units: str, name: str) -> Any:
            return ("time", value, {"units": units, "long_name": name})

        data = {key: var(getattr(self, key), u, name) for key, u, name in _SERIES}
        return xr.Dataset(
            data,
            coords={
                "time": (
                    "time",
                    self.time,
                    {"units": "s", "long_name": "time", "standard_name": "time"},
                )
            },
            attrs={
                "title": "hairbed hair bed in time",
                "model": self.model,
                "bed_model": self.bed_model,
                "time_scale_s": self.time_scale,
                "kappa": self.kappa,
                "drag_ratio": self.drag_ratio,
                "womersley": self.womersley,
                "inertia_number": self.inertia_number,
                "hair_density_kg_per_m3": self.hair_density,
                "status": self.status,
                "message": self.message,
                "t_end_s": self.t_end,
                "Conventions": "CF-1.10",
            },
        )

    def _array_xarray(self, xr: Any) -> Any:
        """:meth:`to_xarray` of an array bed's run."""
        from ._model_axes import model_coords, model_dims

        dims = model_dims("bed", self.shape)
        both = (*dims, "time")

        def var(value: Any, units: str, name: str, on: tuple[str, ...] = both) -> Any:
            return (on, np.asarray(value), {"units": units, "long_name": name})

        data = {
            **{key: var(getattr(self, key), u, name) for key, u, name in _SERIES},
            "time_scale": var(self.time_scale, "s", "T = zeta_perp L^4/(E I)", dims),
            "kappa": var(self.kappa, "1", "permeability over L^2", dims),
            "drag_ratio": var(self.drag_ratio, "1", "zeta_par/zeta_perp", dims),
            "womersley": var(self.womersley, "1", "Womersley number as run", dims),
            "inertia_number": var(self.inertia_number, "1", "inertia number as run", dims),
            "status": var(self.status, "1", "status", dims),
            "t_end": var(self.t_end, "s", "end of the run", dims),
        }
        coords = model_coords(self.bed, "bed", _BED_PARAMETERS)
        coords["time"] = (
            "time",
            self.time,
            {"units": "s", "long_name": "time", "standard_name": "time"},
        )
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "title": "hairbed hair bed in time (array bed)",
                "model": self.model,
                "bed_model": self.bed_model,
                "hair_density_kg_per_m3": self.hair_density,
                "Conventions": "CF-1.10",
            },
        )  # fmt: skip


#: The series of a :class:`BedSimulation` (one row per bed of an array run).
_BED_SERIES = tuple(key for key, _, _ in _SERIES)
#: The fields of a :class:`BedSimulation` with one value per bed.
_PER_BED = ("time_scale", "kappa", "drag_ratio", "womersley", "inertia_number", "t_end")
#: The parameters of a HairBed that may be arrays (the coordinates of an array run).
_BED_PARAMETERS = ("length", "radius", "youngs_modulus", "channel_height", "viscosity",
                   "spacing", "packing_fraction", "base_angle", "density")  # fmt: skip


def _si_drive(
    drive: Any, name: str, unit: str, per_unit: float, t: FloatArray, t_scale: float
) -> Signal | None:
    """The dimensionless drive of an SI one d(t) [unit], t [s]: ``per_unit`` d(T t')."""
    if drive is None:
        return None
    return si_signal(drive, name, unit, per_unit, t, t_scale, MAX_BED_DRIVE, "this bed",
                     "its dimensionless drive")  # fmt: skip


def _within_range(s: _BedScales, bed: Any, hair_density: Any) -> _BedScales:
    """The scales with a Womersley or inertia number below the bed dynamics' range
    (NUMBER_RANGE[0] = 1e-6) set to 0 (the quasi-steady fluid, overdamped hairs: their
    effect is of that relative order); one above it a ValueError naming its density."""
    lo, hi = NUMBER_RANGE
    if s.womersley > hi:
        raise ValueError(
            f"density = {show(bed.density)} kg/m^3 gives the Womersley number rho L^2/(eta T) "
            f"= {s.womersley:.4g}, above the bed dynamics' range [{lo:g}, {hi:g}]"
        )
    if s.inertia > hi:
        raise ValueError(
            f"hair_density = {show(hair_density)} kg/m^3 gives the inertia number "
            f"mu = {s.inertia:.4g}, above the bed dynamics' range [{lo:g}, {hi:g}]"
        )
    alpha = s.womersley if s.womersley >= lo else 0.0
    mu, chi = (s.inertia, s.tangential_mass) if s.inertia >= lo else (0.0, 1.0)
    return dataclasses_replace(s, womersley=alpha, inertia=mu, tangential_mass=chi)


def simulate(
    bed: HairBed,
    times: Any,
    *,
    velocity: Any = None,
    pressure_gradient: Any = None,
    flow_rate: Any = None,
    wall_shear_stress: Any = None,
    hair_density: float | None = None,
    num: int | None = None,
    num_gap: int = 16,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 100_000,
    workers: int = 1,
) -> BedSimulation:
    """A hair bed's motion in time-dependent flow, in SI (theory.md §15).

    :func:`hairbed.dynamics.simulate_bed` (the porous bed: planar inextensible hairs with the
    resistive-force drag in a laterally uniform Brinkman flow, fluid and hairs together) in
    the units of :mod:`hairbed.bed_simulation`. A dense ``HairBed`` runs the porous model of
    its geometry (its kappa and drag ratio from the bed's ``drag`` law); the result says so
    (``model`` "porous", ``bed_model``). The fluid's inertia enters with the Womersley number
    alpha = rho L^2/(eta T) when the bed has a ``density`` (else the quasi-steady fluid); the
    hairs' inertia with mu = (rho_s + rho_f) pi a^2/(zeta_perp T) when ``hair_density`` is
    given (else overdamped). A Womersley or inertia number below 1e-6 is run as 0 (the
    quasi-steady fluid, overdamped hairs; their effect is of that relative order) and the
    result holds the value run. The bed starts at rest in the steady state of the drives just
    before times[0] (a number: a step from still fluid at times[0]).

    Parameters
    ----------
    bed : HairBed
        The bed (either model).
    times : array_like
        The output times [s], finite and non-decreasing; the run starts at times[0].
    velocity, wall_shear_stress : number, Signal or callable, optional
        The top wall: its speed v(t) [m/s] (default at rest), or its shear stress tau(t) [Pa]
        (the wall then moves freely). At most one.
    pressure_gradient, flow_rate : number, Signal or callable, optional
        The pump: G(t) = -dp/dx [Pa/m] (default 0), or the flow rate per unit width Q'(t)
        [m^2/s] (G is then the unknown that holds it; with the fluid's inertia it must not
        jump: use a ramp). At most one.

        Each drive is a number (a step from rest at times[0]), a :mod:`hairbed.dynamics`
        signal given in SI (``step(after, before, at)``, ``ramp``, ``sine(mean, amplitude,
        omega, phase)``, ``pulses``, ``sampled``: times [s], values in the drive's unit,
        omega [rad/s]) or a callable d(t) of an ndarray of times [s] (sampled at
        ``hairbed.dynamics.CALLABLE_SAMPLES`` uniform times of the run). Its dimensionless
        value within +-1e6.
    hair_density : float, optional
        rho_s [kg/m^3] of the hairs (their inertia; default None: overdamped).
    num : int, optional
        The hair's Chebyshev degree in [8, 128] (default that of the start's static state).
    num_gap : int, optional
        The gap's degree in [4, 128] (with the fluid's inertia; default 16).
    rtol, atol : float, optional
        The integrator's tolerances (default 1e-8, 1e-10).
    max_steps : int, optional
        The most steps (status -2 beyond).
    workers : int, optional
        Threads in [1, 64] for the runs of an array bed (default 1; the compiled
        integrator releases the GIL).

    Returns
    -------
    BedSimulation
        For an array bed of shape S (issue 32: a design scan), one run with S in front of
        every series (``tip_deflection`` of shape S + (time,), ...) and of ``time_scale``,
        ``kappa``, ``drag_ratio``, ``womersley``, ``inertia_number``, ``status`` and
        ``t_end``: each element bitwise the run of its :meth:`hairbed.HairBed.item`
        (:meth:`BedSimulation.item`), the runs shared out over ``workers`` threads.

    Raises
    ------
    ValueError, TypeError
        Bad times, drives or densities, naming the parameter.

    Examples
    --------
    >>> import numpy as np, hairbed
    >>> bed = hairbed.HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6,
    ...                       channel_height=2e-3, viscosity=1.0, spacing=400e-6,
    ...                       model="porous")
    >>> run = bed.simulate([0.0, 60.0], velocity=0.1)  # the wall starts at 10 cm/s
    >>> run.success, round(run.time_scale, 4)  # T [s]
    (True, 3.4889)
    >>> round(float(run.tip_deflection[-1] / bed.deform(0.1).tip_deflection), 8)
    1.0
    """
    tt = as_float_array(times, "times", unit="s").reshape(-1)
    if tt.size == 0:
        raise ValueError("times must hold at least one time [s]")
    back = np.flatnonzero(np.diff(tt) < 0.0)
    if back.size:
        i = int(back[0]) + 1
        raise ValueError(f"times must not decrease [s]; times[{i}] = {show(float(tt[i]))} is "
                         "earlier")  # fmt: skip
    if velocity is not None and wall_shear_stress is not None:
        raise ValueError("give at most one of velocity [m/s] and wall_shear_stress [Pa], got both")
    if pressure_gradient is not None and flow_rate is not None:
        raise ValueError(
            "give at most one of pressure_gradient [Pa/m] and flow_rate [m^2/s], got both"
        )
    given = {"velocity": velocity, "wall_shear_stress": wall_shear_stress,
             "pressure_gradient": pressure_gradient, "flow_rate": flow_rate}  # fmt: skip
    options: dict[str, Any] = dict(
        num=num, num_gap=num_gap, rtol=rtol, atol=atol, max_steps=max_steps
    )
    workers = check_int(workers, "workers", 1, 64)
    if not _is_bed(bed) or not bed.shape:  # (not a bed: _scales says so)
        s, t_dim, drives = _run_inputs(bed, tt, given, hair_density)
        run = simulate_bed(s.theta0, s.kappa, s.eps, t_eval=t_dim, gamma=s.gamma,
                           inertia=s.inertia, tangential_mass=s.tangential_mass,
                           womersley=s.womersley, **options, **drives)  # fmt: skip
        return _simulation_of(bed, s, run, tt, hair_density)
    return _array_simulate(bed, tt, given, hair_density, options, workers)


def _run_inputs(
    bed: Any, tt: FloatArray, given: dict[str, Any], hair_density: Any
) -> tuple[_BedScales, FloatArray, dict[str, Any]]:
    """(the scales as run, t/T, the dimensionless drives) of one bed of numbers' run."""
    s: _BedScales = _scales(bed, hair_density)
    with np.errstate(over="ignore"):
        t_dim = tt / s.time
    if not np.all(np.isfinite(t_dim)):
        raise ValueError(
            f"times must stay below {np.finfo(np.float64).max * s.time:.4g} s in magnitude for "
            f"this bed (t/T overflows, T = {s.time:.4g} s), got {float(np.max(np.abs(tt)))!r}"
        )
    drives: dict[str, Any] = {
        "wall": _si_drive(given["velocity"], "velocity", "m/s", s.omega2_per_velocity, tt,
                          s.time),
        "wall_stress": _si_drive(given["wall_shear_stress"], "wall_shear_stress", "Pa",
                                 s.load_per_stress, tt, s.time),
        "pressure": _si_drive(given["pressure_gradient"], "pressure_gradient", "Pa/m",
                              s.pi_per_gradient, tt, s.time),
        "flow_rate": _si_drive(given["flow_rate"], "flow_rate", "m^2/s", s.q_per_flow, tt,
                               s.time),
    }  # fmt: skip
    return _within_range(s, bed, hair_density), t_dim, drives


def _simulation_of(
    bed: Any, s: _BedScales, run: BedTrajectory, tt: FloatArray, hair_density: Any
) -> BedSimulation:
    """One bed of numbers' run in SI."""
    length, ei = bed.length, bed.bending_stiffness
    return BedSimulation(
        time=tt,
        tip_deflection=length * run.tip_deflection,
        tip_height=length * run.tip_height,
        tip_angle=np.asarray(run.tip_angle, dtype=np.float64),
        base_moment=ei * run.base_moment / length,
        wall_shear_stress=run.wall_stress / s.load_per_stress,
        wall_velocity=run.wall_speed / s.omega2_per_velocity,
        flow_rate=run.flow_rate / s.q_per_flow,
        pressure_gradient=run.pressure / s.pi_per_gradient,
        time_scale=s.time,
        kappa=s.kappa,
        drag_ratio=s.gamma,
        womersley=s.womersley,
        inertia_number=s.inertia,
        hair_density=math.nan if hair_density is None else float(hair_density),
        model="porous",
        bed_model=str(bed.model),
        status=int(run.status),
        t_end=float(run.t_end) * s.time,
        trajectory=run,
    )


def _array_simulate(
    bed: Any,
    tt: FloatArray,
    given: dict[str, Any],
    hair_density: Any,
    options: dict[str, Any],
    workers: int,
) -> BedSimulation:
    """:func:`simulate` of an array bed (issue 32): each element's run is the compiled
    integration of the bed of numbers (:func:`hairbed.dynamics.simulate_bed`, as
    :func:`hairbed.dynamics.simulate_beds` runs each of its beds: so each element is
    bitwise its :meth:`hairbed.HairBed.item`'s), shared out over ``workers`` threads (the
    integrator releases the GIL), the runs stacked behind the bed's shape. (simulate_beds
    itself takes one time grid in T for all its beds; the elements of a scan have each
    their own T unless only the angle, the channel or the density vary.)"""
    from ._model_axes import element_index

    shape = tuple(bed.shape)
    elements = list(bed._elements())
    if hair_density is not None:  # shared by every element: its error names no element
        check_positive(hair_density, "hair_density", "kg/m^3")
    inputs = []
    for k, el in enumerate(elements):
        try:
            inputs.append(_run_inputs(el, tt, given, hair_density))
        except ValueError as exc:  # this element's scales or its drives' range
            raise ValueError(f"{exc} (bed {element_index(k, shape)})") from None

    def one(k: int) -> BedTrajectory:
        s, t_dim, drives = inputs[k]
        try:
            return simulate_bed(s.theta0, s.kappa, s.eps, t_eval=t_dim, gamma=s.gamma,
                                inertia=s.inertia, tangential_mass=s.tangential_mass,
                                womersley=s.womersley, **options, **drives)  # fmt: skip
        except ValueError as exc:
            raise ValueError(f"{exc} (bed {element_index(k, shape)})") from None

    if workers == 1 or len(elements) == 1:
        runs = [one(k) for k in range(len(elements))]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=min(workers, len(elements))) as pool:
            runs = list(pool.map(one, range(len(elements))))
    out = [_simulation_of(el, inputs[k][0], runs[k], tt, hair_density)
           for k, el in enumerate(elements)]  # fmt: skip

    def stacked(name: str, dtype: Any = np.float64) -> Any:
        rows = np.array([getattr(r, name) for r in out], dtype=dtype)
        return rows.reshape(shape + rows.shape[1:])

    trajectories = np.empty(len(runs), dtype=object)
    trajectories[:] = runs
    series = {n: stacked(n) for n in (*_BED_SERIES, *_PER_BED)}
    return BedSimulation(
        time=tt,
        **series,
        hair_density=out[0].hair_density,
        model="porous",
        bed_model=str(bed.model),
        status=stacked("status", np.int64),
        trajectory=trajectories.reshape(shape),
        bed=bed,
    )
