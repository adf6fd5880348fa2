"""The nonlinear pillar in time: :func:`simulate_pillar` (issue 30, theory.md §14).

The semi-discretisation is the static pillar's Chebyshev collocation (the same mapped
nodes, the same residual kernel ``spectral._residual_drag``) with the drag of the pillar's
velocity and its inertia (:func:`hairbed._core._kernels.dynamics.pillar_rates`); theta_0 =
theta0 and theta'(1) = 0 are solved for the boundary angles, which leaves an ODE in the
interior angles (and their rates with inertia), integrated by the compiled Radau IIA of
``integrate_pillar`` (order 5, L-stable, the exact Jacobian, error control, dense output,
the wall event).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.loaded import _MAP_SCALE, _shape_at
from .._core.pillar import (
    WINDOW_THETA0,
    PillarState,
    _start_load,
    profile_coefficients,
    solve_pillar,
)
from .._core.solver import _scalar
from .._core.validation import (
    STATUS_MESSAGES,
    StatusResult,
    as_float_array,
    check_int,
    check_number,
    check_positive,
    show,
    status_messages,
)
from ._operators import _mapped
from ._signals import Signal, as_signal, check_drive

__all__ = [
    "LEAST_NUM",
    "TRAJECTORY_STATUS",
    "PillarTrajectory",
    "simulate_pillar",
    "simulate_pillars",
]

FloatArray = NDArray[np.float64]
#: The least Chebyshev degree N of a run (three interior angles): for loose work, where the
#: discretisation's error, ~ 1e-3 of the tip at N = 4 and falling about tenfold per degree
#: (docs/theory.md §14), may exceed the time integration's. The static states a run starts
#: from and maps its collocation by are solved at N >= ``_STATIC_NUM`` and evaluated at the
#: run's nodes.
LEAST_NUM = 4
_STATIC_NUM = 8


@functools.lru_cache(maxsize=256)
def _operators_at(num: int, a: float) -> tuple[FloatArray, ...]:
    """(s, ds/dxi, dd, ii, d0, D/s') of the map a at degree N, built once per (N, a) and
    shared by the runs: not to be written to."""
    from .._core.loaded import _matrices

    ops = _mapped(num, a)
    return (*ops, np.asarray(_matrices(num)[1] / ops[1][:, None]))


@functools.lru_cache(maxsize=256)
def _tip_row(num: int, a: float) -> FloatArray:
    """The row r with theta_N = r . theta (theta'(1) = 0 solved for the tip angle; r_N = 0)
    of the map a at degree N, built once per (N, a): not to be written to."""
    dd = _operators_at(num, a)[2]
    srow = -dd[num, :] / dd[num, num]
    srow[num] = 0.0
    return srow


#: The status codes of a :class:`PillarTrajectory`: the package's table and the jump event.
TRAJECTORY_STATUS: Mapping[int, str] = MappingProxyType(
    {
        **STATUS_MESSAGES,
        -9: (
            "a jump: the tip's speed |dx1/dt| reached jump_speed (the state left its "
            "quasi-static branch, as past a fold); the run stops there (t_end)"
        ),
    }
)


@dataclass(frozen=True)
class PillarTrajectory(StatusResult):
    """A pillar's motion (theory.md §14); time in T = zeta_perp L^4/(E I), lengths in L.

    Attributes
    ----------
    t : ndarray
        The output times [T]. Past an event or a failure (``t_end``) the values are NaN.
    forcing, tip_load : ndarray
        The drives Lambda(t) [-] and P(t) [E I/L^2] at t.
    tip_deflection, tip_height : ndarray
        x1(t), h1(t) [L].
    tip_angle : ndarray
        theta(1, t) [rad].
    base_moment : ndarray
        theta'(0, t): the base moment in E I/L.
    s : ndarray
        The collocation nodes [L].
    theta, theta_t : ndarray
        theta [rad] and its rate [rad/T] at the nodes, (time, node).
    mu, gamma, tangential_mass, theta0 : float
        The model's constants.
    status : int
        0 reached the last time; -8 the pillar reached abs(theta) = pi/2 (it lies on the wall:
        the event, at ``t_end``); -9 the tip's speed reached ``jump_speed`` (a jump, the
        event at ``t_end``); -2 the step limit; -3 the step size underflowed or a singular
        matrix (``TRAJECTORY_STATUS``).
    t_end : float
        Where the integration ended [T].
    nsteps, naccept, nreject, nfev, njev, nlu : int
        Work: steps tried, accepted, rejected; evaluations of the rates, Jacobians, LU
        factorisations (with ``method="exponential"``: the matrix functions, the phi
        functions of a step and the exponentials of its dense output).
    """

    t: FloatArray
    forcing: FloatArray
    tip_load: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    tip_angle: FloatArray
    base_moment: FloatArray
    s: FloatArray
    theta: FloatArray
    theta_t: FloatArray
    mu: float
    gamma: float
    tangential_mass: float
    theta0: float
    status: int
    t_end: float
    nsteps: int
    naccept: int
    nreject: int
    nfev: int
    njev: int
    nlu: int
    _ops: Any

    _status_table: ClassVar[Mapping[int, str]] = TRAJECTORY_STATUS

    def energy(self) -> dict[str, FloatArray]:
        """The energy budget at every output time (units E I/L, time T):
        ``elastic`` 1/2 int theta_s^2 ds, ``kinetic`` 1/2 mu int r_t . C r_t ds (C = I -
        (1 - chi) t t the mass's anisotropy, chi the tangential mass), ``input`` the power
        of the flow and the tip load on the moving pillar, int Lambda U(z) e_x . A r_t ds +
        P x1_t, and with chi < 1 that of the fluid's added mass as the pillar turns,
        1/2 mu int r_t . (dC/dt) r_t ds = -mu (1 - chi) int theta_t (r_t . t)(r_t . n) ds
        (the model's inertia is C r_tt, not d/dt (C r_t)), and ``dissipation``
        int r_t . A r_t ds (A = I - (1 - gamma) t t). In the model d(elastic +
        kinetic)/dt = input - dissipation."""
        ops = self._ops
        ii, d1s, prof = ops["ii"], ops["d1s"], ops["prof"]
        th, tt = self.theta, self.theta_t
        c, s = np.cos(th), np.sin(th)
        theta_s = th @ d1s.T
        elastic = 0.5 * (theta_s**2) @ ii[-1]
        vx = (tt * c) @ ii.T
        vz = -(tt * s) @ ii.T
        z = c @ ii.T

        def quad_form(ratio: float) -> FloatArray:
            p = s * vx + c * vz
            return np.asarray((vx * vx + vz * vz - (1.0 - ratio) * p * p) @ ii[-1])

        kinetic = 0.5 * self.mu * quad_form(self.tangential_mass)
        dissipation = quad_form(self.gamma)
        u = np.polynomial.chebyshev.chebval(2.0 * z - 1.0, prof)
        p = s * vx + c * vz
        ax = vx - (1.0 - self.gamma) * s * p  # (A r_t)_x
        inp = self.forcing * ((u * ax) @ ii[-1]) + self.tip_load * vx[:, -1]
        if self.tangential_mass != 1.0:  # the anisotropic mass turning with the pillar
            q = c * vx - s * vz  # n . r_t
            inp = inp - self.mu * (1.0 - self.tangential_mass) * ((tt * p * q) @ ii[-1])
        return {
            "elastic": elastic,
            "kinetic": kinetic,
            "input": inp,
            "dissipation": dissipation,
        }

    def to_xarray(self) -> Any:
        """The trajectory as an xarray.Dataset with the dimensions ``t`` (and ``s`` for the
        shape), CF attributes. Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "PillarTrajectory.to_xarray", "io")
        data = {
            "forcing": ("t", self.forcing, {"units": "1", "long_name": "forcing Lambda(t)"}),
            "tip_load": ("t", self.tip_load, {"units": "E I/L^2", "long_name": "tip load"}),
            "tip_deflection": ("t", self.tip_deflection, {"units": "L", "long_name": "x(1)"}),
            "tip_height": ("t", self.tip_height, {"units": "L", "long_name": "z(1)"}),
            "tip_angle": ("t", self.tip_angle, {"units": "rad", "long_name": "theta(1)"}),
            "base_moment": (
                "t",
                self.base_moment,
                {"units": "E I/L", "long_name": "base moment theta'(0)"},
            ),
            "theta": (("t", "s"), self.theta, {"units": "rad", "long_name": "angle"}),
            "theta_t": (("t", "s"), self.theta_t, {"units": "rad/T", "long_name": "rate"}),
        }
        return xr.Dataset(
            data,
            coords={
                "t": ("t", self.t, {"units": "T", "long_name": "time, T = zeta_perp L^4/(E I)"}),
                "s": ("s", self.s, {"units": "L", "long_name": "arc length"}),
            },
            attrs={
                "title": "hairbed pillar trajectory",
                "mu": self.mu,
                "gamma": self.gamma,
                "tangential_mass": self.tangential_mass,
                "theta0": self.theta0,
                "status": self.status,
                "message": str(self.message),
                "t_end": self.t_end,
                "Conventions": "CF-1.10",
            },
        )


def simulate_pillar(
    forcing: Any,
    t_eval: ArrayLike,
    *,
    theta0: float = 0.0,
    tip_load: Any = 0.0,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: float = 0.5,
    mu: float = 0.0,
    tangential_mass: float = 1.0,
    initial: PillarState | None = None,
    num: int = 32,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_steps: int = 100_000,
    jump_speed: float | None = None,
    method: str = "radau",
) -> PillarTrajectory:
    """A pillar in a time-dependent flow, from the nonlinear model (theory.md §14).

    E I theta_ss = -(F_x cos - F_z sin), F = P(t) e_x + int_s^L (f - m r_tt) ds',
    f = zeta_perp [I - (1 - gamma) t t] (u(z, t) e_x - r_t), u = Lambda(t) U(z) in the
    static problem's units; time in T = zeta_perp L^4/(E I), mu = m E I/(zeta_perp^2 L^4).

    Parameters
    ----------
    forcing : number, Signal or callable
        Lambda(t): a constant, a :mod:`hairbed.dynamics` signal (``step``, ``ramp``,
        ``sine``, ``pulses``, ``sampled``) or a callable of an ndarray of times (sampled at
        ``CALLABLE_SAMPLES`` uniform times of the run where rtol <= 1e-10; at a looser rtol
        at fewer, from 65 up, doubled until the interpolant of every other sample gives the
        samples between to rtol times the largest); its levels within +-1e100 (beyond it
        the compiled rates would overflow).
    t_eval : array_like
        Output times [T], finite and non-decreasing; the run starts at t_eval[0].
    theta0 : float, optional
        The base angle [rad] in (-pi/2, pi/2).
    tip_load : number, Signal or callable, optional
        P(t) [E I/L^2], its levels within +-1e100 too.
    profile, height_ratio, gamma : optional
        As in :func:`hairbed.solve_pillar`.
    mu : float, optional
        The inertia number >= 0 (0, the default: overdamped).
    tangential_mass : float, optional
        chi in (0, 1]: tangential over normal mass per unit length (added mass acts
        normally).
    initial : PillarState, optional
        The state at rest at t_eval[0]; default the static state of the drives' values just
        before it (so a step at t_eval[0] starts from its value before): straight (theta =
        theta0) where both are zero.
    num : int, optional
        The Chebyshev degree N in [``LEAST_NUM`` = 4, 128] (default 32); below 8 for loose
        work only (the discretisation's error of the tip ~ 1e-3 at N = 4).
    rtol, atol : float, optional
        The integrator's tolerances on the angles (and rates).
    max_steps : int, optional
        The most steps, in [1, 10^12] (work is bounded; status -2 beyond).
    jump_speed : float, optional
        The jump event [L/T]: the run stops (status -9, ``t_end`` the event's time, located
        on the dense output to round-off) where the tip's speed ``|dx1/dt|`` first reaches this
        positive value: on a slow drive the pillar moves at the drive's pace along its
        quasi-static branch, and at O(1) speed once it leaves it, as past a fold. Default
        None: no such event. (A drive that jumps itself, a step, starts the pillar at O(1)
        speed: set the threshold above that, or leave it off.)
    method : {"radau", "exponential"}, optional
        The integrator. "radau" (the default): Radau IIA of order 5 on y' = f(t, y).
        "exponential": the exponential Rosenbrock method exprb43 (order 4): linearised
        afresh at every step with the exact Jacobian, the linear ringing about the current
        state exact in every mode (matrix functions of h J), the remainder, second order in
        the step's change, approximated (theory.md §14): for a ringing pillar (mu > 0),
        whose every mode rings about as long as the first, its steps follow the modes'
        nonlinear interaction instead of the fastest ringing.

    Returns
    -------
    PillarTrajectory

    Examples
    --------
    >>> from hairbed.dynamics import simulate_pillar, step
    >>> run = simulate_pillar(step(10.0), [0.0, 0.05, 2.0])  # to the static 0.5393542695
    >>> run.success, round(float(run.tip_deflection[-1]), 6)
    (True, 0.539354)
    """
    te = _checked_times(t_eval)
    plain = _plain_call(theta0, gamma, mu, tangential_mass, num, rtol, atol, max_steps,
                        jump_speed)  # fmt: skip
    if plain is not None:  # plain scalars in range skip the array checks (same values)
        t0, g, m, opts = plain
    else:
        t0, g, m, opts = _checked_call(
            te, theta0, gamma, mu, tangential_mass, num, rtol, atol, max_steps, jump_speed
        )
    if not isinstance(method, str) or method not in ("radau", "exponential"):
        raise ValueError(f"method must be 'radau' or 'exponential', got {show(method)}")
    deg = opts.num
    lam_sig, tip_sig = _drives(forcing, tip_load, te, opts.rtol)
    prof = profile_coefficients(profile, height_ratio)
    # the map of the collocation: that of the static state at the drives' last values
    lam_end, tip_end = lam_sig.at_start(float(te[-1])), tip_sig.at_start(float(te[-1]))
    a = _forward_map(lam_end, t0, tip_end, prof) if method == "radau" else None
    if a is None:
        last = solve_pillar(
            lam_end,
            t0,
            profile=profile,
            height_ratio=height_ratio,
            gamma=g,
            tip_load=tip_end,
            num=max(deg, _STATIC_NUM),
        )
        a = float(last._map) if np.isfinite(last._map) else 0.0
    before = math.nextafter(float(te[0]), -math.inf)
    start: tuple[float, FloatArray] | None = None
    if initial is None and lam_sig.at_start(before) == 0.0 and tip_sig.at_start(before) == 0.0:
        pass  # no load before the start: the straight pillar theta = theta0 (start None)
    elif initial is None:  # at rest under the drives just before the start (a step: before)
        initial = solve_pillar(
            lam_sig.at_start(before),
            t0,
            profile=profile,
            height_ratio=height_ratio,
            gamma=g,
            tip_load=tip_sig.at_start(before),
            num=max(deg, _STATIC_NUM),
        )
        if int(initial.status) < 0:  # (3, a tail above rtol at a small fixed N, will do)
            raise ValueError(
                _no_start(lam_sig.at_start(before), tip_sig.at_start(before), initial.message)
                + "; pass initial="
            )
    elif not isinstance(initial, PillarState) or np.ndim(initial.tip_height) != 0:
        raise TypeError("initial must be one PillarState (a scalar solve_pillar result)")
    elif abs(float(initial.theta0) - t0) > 1e-12 or int(initial.status) < 0:
        raise ValueError(
            f"initial must be a converged state at theta0 = {t0!r}, got theta0 = "
            f"{float(initial.theta0)!r}, status {int(initial.status)}"
        )
    if initial is not None:
        start = (float(initial._map), np.asarray(initial._coefs, dtype=np.float64).reshape(3, -1))
    job = _Job(te, opts, t0, g, m, a, start, lam_sig, tip_sig, prof, method == "exponential")
    return _run(job)


def _checked_call(
    te: FloatArray,
    theta0: Any,
    gamma: Any,
    mu: Any,
    tangential_mass: Any,
    num: Any,
    rtol: Any,
    atol: Any,
    max_steps: Any,
    jump_speed: Any,
) -> tuple[float, float, float, _Options]:
    """(theta0, gamma, mu, options) by the full checks, each error naming its parameter."""
    t0 = check_number(theta0, "theta0", low=-0.5 * np.pi, high=0.5 * np.pi, low_open=True,
                      high_open=True)  # fmt: skip
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    m = check_number(mu, "mu", low=0.0)
    return t0, g, m, _options(te, tangential_mass, num, rtol, atol, max_steps, jump_speed)


_HALF_PI = 0.5 * np.pi
_MAX_STEPS = 10**12


def _plain_call(
    theta0: Any,
    gamma: Any,
    mu: Any,
    tangential_mass: Any,
    num: Any,
    rtol: Any,
    atol: Any,
    max_steps: Any,
    jump_speed: Any,
) -> tuple[float, float, float, _Options] | None:
    """:func:`_checked_call`'s values where every input is a plain number (float, numpy
    float64, a bounded int; ``num`` and ``max_steps`` ints) within its range, else None (then
    the full checks run, with their messages): the scalar call skips numpy."""
    t0, g, m, chi = _scalar(theta0), _scalar(gamma), _scalar(mu), _scalar(tangential_mass)
    rt, at = _scalar(rtol), _scalar(atol)
    jump = 0.0 if jump_speed is None else _scalar(jump_speed)
    if t0 is None or g is None or m is None or chi is None or rt is None or at is None:
        return None
    if jump is None or type(num) is not int or type(max_steps) is not int:
        return None
    if (
        -_HALF_PI < t0 < _HALF_PI
        and 0.0 < g <= 1.0
        and 0.0 <= m < math.inf
        and 0.0 < chi <= 1.0
        and 0.0 < rt < math.inf
        and 0.0 < at < math.inf
        and (jump_speed is None or 0.0 < jump < math.inf)
        and LEAST_NUM <= num <= 128
        and 1 <= max_steps <= _MAX_STEPS
    ):
        return t0, g, m, _Options(chi, num, rt, at, max_steps, jump)
    return None


def _forward_map(lam: float, theta0: float, tip: float, prof: FloatArray) -> float | None:
    """The collocation's map parameter of the static state at (Lambda, theta0, P), without
    the solve: :func:`~hairbed.solve_pillar`'s forward Newton maps its collocation by the
    closed-form start's (``_start_load``, the flow mirrored to +x), so this is the solved
    state's map wherever that Newton gives the state (Radau IIA needs only the map, not the
    state). None where the state is picked on the branch (theta0 below ``WINDOW_THETA0`` in
    the mirrored flow): there the solve's own map."""
    mirror = -1.0 if lam < 0.0 else 1.0
    if mirror * theta0 < WINDOW_THETA0 and lam != 0.0:
        return None
    # the map is 0 where the start's tip load W = Lambda int U s^2 (3 - s)/2 ds + P cannot
    # exceed _MAP_SCALE^2 (abs(U) <= the sum of abs(U's Chebyshev coefficients))
    if 0.375 * abs(lam) * float(np.sum(np.abs(prof))) + abs(tip) <= _MAP_SCALE**2:
        return 0.0
    one = np.ones(1)
    _, a = _start_load(abs(lam) * one, mirror * theta0 * one, mirror * tip * one, prof[None, :])
    return float(a[0])


@dataclass(frozen=True)
class _Options:
    """The checked options shared by every pillar of a run."""

    chi: float
    num: int
    rtol: float
    atol: float
    max_steps: int
    jump: float


@dataclass(frozen=True)
class _Job:
    """One pillar's run: everything the kernel and the trajectory need."""

    te: FloatArray
    opts: _Options
    theta0: float
    gamma: float
    mu: float
    a: float  # the collocation's map parameter
    #: the static state at t_eval[0]: its map, coefficients (None: the straight pillar)
    start: tuple[float, FloatArray] | None
    lam_sig: Signal
    tip_sig: Signal
    prof: FloatArray
    #: The exponential Rosenbrock integrator (else Radau IIA).
    exponential: bool = False


def _no_start(lam: float, tip: float, why: Any) -> str:
    """The message of a run with no static state to start from."""
    return (
        f"no static state at forcing = {show(lam)} and tip_load = {show(tip)} (the drives "
        f"just before t_eval[0]) to start from: {why}"
    )


def _checked_times(t_eval: ArrayLike) -> FloatArray:
    if type(t_eval) is np.ndarray and t_eval.dtype == np.float64 and t_eval.size:
        te = t_eval.astype(np.float64).reshape(-1)  # a copy, as as_float_array's
        if te.size <= 16:  # a few times: Python's floats (no NaN is <= anything)
            vals = te.tolist()
            ends = math.isfinite(vals[0]) and math.isfinite(vals[-1])
            if ends and all(a <= b for a, b in zip(vals, vals[1:])):
                return te  # in order between two finite ends: finite
        elif np.isfinite(te).all() and not (np.diff(te) < 0.0).any():
            return te  # a float array in order: the checks below would pass
    te = as_float_array(t_eval, "t_eval").reshape(-1)
    if te.size < 1:
        raise ValueError("t_eval must hold at least one time")
    bad = ~np.isfinite(te)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"t_eval must be finite, got {show(float(te[i]))} at index {i}")
    back = np.flatnonzero(np.diff(te) < 0.0)
    if back.size:
        i = int(back[0]) + 1
        raise ValueError(
            f"t_eval must not decrease; index {i} is {show(float(te[i]))}, after "
            f"{show(float(te[i - 1]))}"
        )
    return te


def _options(
    te: FloatArray,
    tangential_mass: float,
    num: int,
    rtol: float,
    atol: float,
    max_steps: int,
    jump_speed: float | None,
) -> _Options:
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    jump = (
        0.0
        if jump_speed is None
        else check_number(jump_speed, "jump_speed", low=0.0, low_open=True)
    )
    return _Options(
        chi=chi,
        num=check_int(num, "num", LEAST_NUM, 128),
        rtol=check_positive(rtol, "rtol"),
        atol=check_positive(atol, "atol"),
        # the kernel counts steps in int64: a bound far beyond any run, not an overflow
        max_steps=check_int(max_steps, "max_steps", 1, 10**12),
        jump=jump,
    )


def _drives(
    forcing: Any, tip_load: Any, te: FloatArray, rtol: float | None = None
) -> tuple[Signal, Signal]:
    """The drives as signals (callables sampled to the run's ``rtol``: :func:`as_signal`)."""
    t0 = float(te[0])
    span_end = float(te[-1]) if te[-1] > te[0] else t0 + 1.0
    return (
        check_drive(as_signal(forcing, "forcing", t0, span_end, rtol), "forcing"),
        check_drive(as_signal(tip_load, "tip_load", t0, span_end, rtol), "tip_load"),
    )


@functools.lru_cache(maxsize=1)
def _kernels() -> Any:
    """The compiled module ``pillar_run``, imported on first use (``import hairbed`` loads
    no kernel)."""
    from .._core._kernels import pillar_run

    return pillar_run


def _run(job: _Job) -> PillarTrajectory:
    """The compiled integration of one pillar and its trajectory (the kernel releases the
    GIL: runs of several pillars go in parallel on threads)."""
    pillar_run = _kernels()
    te, opts = job.te, job.opts
    deg, t0, g, m, chi = opts.num, job.theta0, job.gamma, job.mu, opts.chi
    ss, sp, dd, ii, d0, d1s = _operators_at(deg, job.a)
    n = deg - 1
    size = n if m == 0.0 else 2 * n
    y0 = np.zeros(size)
    if job.start is None:  # unloaded before the start: straight, theta = theta0
        y0[:n] = t0
    else:
        smap, scoef = job.start
        y0[:n] = np.asarray(_shape_at(np.array([smap]), scoef[:, None, :], (1,), ss)[3])[0, 1:deg]
    srow = _tip_row(deg, job.a)
    lam_sig, tip_sig = job.lam_sig, job.tip_sig
    drives = np.array([lam_sig.row(), tip_sig.row()])
    tk = max(lam_sig.times.size, tip_sig.times.size, 1)
    tabs = np.zeros((4, tk))
    for r, sig in ((0, lam_sig), (2, tip_sig)):
        k = sig.times.size
        if k:
            tabs[r, :k] = sig.times
            tabs[r + 1, :k] = sig.values
            if k < tk:  # held past its last sample
                tabs[r, k:] = sig.times[-1] + np.arange(1, tk - k + 1)
                tabs[r + 1, k:] = sig.values[-1]
        else:
            tabs[r] = np.arange(tk, dtype=np.float64)
    pr = np.ascontiguousarray(job.prof)
    if job.exponential:
        y_out = np.full((te.size, size), np.nan)
        counts = np.zeros(6, dtype=np.int64)
        status, t_end = _exponential(job, y0, dd, ii, srow, pr, drives, tabs, y_out, counts)
        # the angles and rates at the nodes, the tip and the base moment (NaN past an event)
        theta = np.empty((te.size, deg + 1))
        rates = np.empty((te.size, deg + 1))
        out = np.empty((4, te.size))
        pillar_run.trajectory_outputs(
            te, y_out, deg, dd, ii, srow, d0, t0, g, chi, m, pr, drives, tabs, theta, rates, out
        )
    else:  # one compiled call: the first step, the integration, the outputs
        status, t_end, counts, theta, rates, out = pillar_run.run_radau(
            y0, te, _start_span(job), opts.rtol, opts.atol, opts.max_steps, deg, dd, ii, srow,
            d0, t0, g, chi, m, pr, drives, tabs, opts.jump,
        )  # fmt: skip
    return PillarTrajectory(
        t=te,
        forcing=np.asarray(lam_sig(te), dtype=np.float64).reshape(te.shape),
        tip_load=np.asarray(tip_sig(te), dtype=np.float64).reshape(te.shape),
        tip_deflection=out[0],
        tip_height=out[1],
        tip_angle=out[2],
        base_moment=out[3],
        s=ss,
        theta=theta,
        theta_t=rates,
        mu=m,
        gamma=g,
        tangential_mass=chi,
        theta0=t0,
        status=int(status),
        t_end=float(t_end),
        nsteps=int(counts[0]),
        naccept=int(counts[1]),
        nreject=int(counts[2]),
        nfev=int(counts[3]),
        njev=int(counts[4]),
        nlu=int(counts[5]),
        _ops={"ii": ii, "d1s": d1s, "prof": job.prof},
    )


def _start_span(job: _Job) -> float:
    """The span of Radau IIA's first step (``pillar_run.start_step``, the starting step of
    Hairer, Norsett & Wanner, Solving ODEs I, II.4) [T]: to the last output time, or to the
    drives' first corner or jump after the start where that is sooner (a step's time, a
    ramp's or a pulse train's corners: the first step does not straddle it)."""
    t_start = float(job.te[0])
    return min(float(job.te[-1]) - t_start, _next_break(job.lam_sig, t_start),
               _next_break(job.tip_sig, t_start))  # fmt: skip


def _next_break(sig: Signal, t0: float) -> float:
    """The time from t0 to the signal's first corner or jump after it (inf: none known: a
    constant, a sine, a sampled signal)."""
    p = sig.params
    if sig.kind == "step":
        corners: tuple[float, ...] = (p[2],)
    elif sig.kind == "ramp":
        corners = (p[2], p[3])
    elif sig.kind == "pulses":  # the next start or end of a pulse
        period, width, start = p[2], p[3], p[4]
        k = math.floor((t0 - start) / period)
        base = start + k * period
        corners = (base, base + width, base + period)
    else:
        return math.inf
    ahead = [c - t0 for c in corners if c > t0]
    return min(ahead) if ahead else math.inf


def _exponential(
    job: _Job,
    y0: FloatArray,
    dd: FloatArray,
    ii: FloatArray,
    srow: FloatArray,
    pr: FloatArray,
    drives: FloatArray,
    tabs: FloatArray,
    y_out: FloatArray,
    counts: Any,
) -> tuple[int, float]:
    """The run by the exponential Rosenbrock integrator (``_kernels.exponential``):
    (status, t_end)."""
    from .._core._kernels import exponential as expo

    te, opts = job.te, job.opts
    pars = (opts.num, dd, ii, srow, job.theta0, job.gamma, opts.chi, job.mu, pr, drives, tabs)
    status, t_end = expo.integrate_exponential(
        y0, float(te[0]), te, opts.rtol, opts.atol, 1e-6, opts.max_steps, *pars, y_out,
        counts, opts.jump,
    )  # fmt: skip
    return int(status), float(t_end)


def simulate_pillars(
    forcing: Any,
    t_eval: ArrayLike,
    *,
    theta0: ArrayLike = 0.0,
    tip_load: Any = 0.0,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    gamma: ArrayLike = 0.5,
    mu: ArrayLike = 0.0,
    tangential_mass: float = 1.0,
    num: int = 32,
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_steps: int = 100_000,
    jump_speed: float | None = None,
    workers: int = 1,
) -> list[PillarTrajectory]:
    """Many pillars in time-dependent flows in one call: :func:`simulate_pillar` for each.

    Each pillar is its own run of the compiled integrator (its own steps and error
    control); the static states they start from and map their collocation by are solved in
    one batch (:func:`hairbed.solve_pillar` on arrays), and the runs share out over
    ``workers`` threads (the compiled integrator releases the GIL).

    Parameters
    ----------
    forcing : sequence or number, Signal or callable
        Lambda(t) of each pillar: a sequence of drives (numbers, signals or callables, as in
        :func:`simulate_pillar`), or one drive for all.
    t_eval : array_like
        The output times [T], shared (as in :func:`simulate_pillar`).
    theta0, gamma, mu : array_like, optional
        Each pillar's base angle [rad] in (-pi/2, pi/2), drag ratio in (0, 1] and inertia
        number >= 0; scalars or 1-d arrays, broadcast with the drives.
    tip_load : sequence or number, Signal or callable, optional
        P(t) [E I/L^2] of each pillar, or one for all.
    profile, height_ratio, tangential_mass, num, rtol, atol, max_steps, jump_speed
        As in :func:`simulate_pillar`, shared.
    workers : int, optional
        Threads in [1, 64] (default 1).

    Returns
    -------
    list of PillarTrajectory
        In the order of the pillars, each with its own ``status``.
    """
    te = _checked_times(t_eval)
    opts = _options(te, tangential_mass, num, rtol, atol, max_steps, jump_speed)
    nw = check_int(workers, "workers", 1, 64)

    def seq(x: Any) -> list[Any] | None:
        return list(x) if isinstance(x, (list, tuple)) else None

    lams, tips = seq(forcing), seq(tip_load)
    arrays = {}
    for name, val in (("theta0", theta0), ("gamma", gamma), ("mu", mu)):
        arr = as_float_array(val, name)
        if arr.ndim > 1:
            raise ValueError(f"{name} must be a scalar or 1-d, got shape {arr.shape}")
        arrays[name] = arr
    sizes = {len(v) for v in (lams, tips) if v is not None}
    sizes |= {a.size for a in arrays.values() if a.ndim == 1}
    if len(sizes) > 1:
        raise ValueError(
            f"forcing, tip_load, theta0, gamma and mu must have one length, got {sorted(sizes)}"
        )
    count = sizes.pop() if sizes else 1
    if count < 1:
        empty = [n for n, v in (("forcing", lams), ("tip_load", tips)) if v is not None]
        empty += [n for n, a in arrays.items() if a.ndim == 1]
        names = " and ".join(empty)
        raise ValueError(f"simulate_pillars needs at least one pillar: {names} must not be empty")
    t0s = np.broadcast_to(arrays["theta0"], (count,))
    gs = np.broadcast_to(arrays["gamma"], (count,))
    mus = np.broadcast_to(arrays["mu"], (count,))
    for name, arr, kw in (
        ("theta0", t0s, dict(low=-0.5 * np.pi, high=0.5 * np.pi, low_open=True, high_open=True)),
        ("gamma", gs, dict(low=0.0, high=1.0, low_open=True)),
        ("mu", mus, dict(low=0.0)),
    ):
        for i, v in enumerate(arr):
            try:
                check_number(float(v), name, **kw)  # type: ignore[arg-type]
            except ValueError as exc:
                raise ValueError(f"{exc} (pillar {i})") from None
    sigs = []
    for i in range(count):
        try:
            sigs.append(
                _drives(
                    lams[i] if lams is not None else forcing,
                    tips[i] if tips is not None else tip_load,
                    te,
                    opts.rtol,
                )
            )
        except (ValueError, TypeError) as exc:
            raise type(exc)(f"{exc} (pillar {i})") from None
    prof = profile_coefficients(profile, height_ratio)
    before = float(np.nextafter(te[0], -np.inf))

    def states(t: float) -> PillarState:
        return solve_pillar(
            np.array([ls.at_start(t) for ls, _ in sigs]),
            np.array(t0s),
            profile=profile,
            height_ratio=height_ratio,
            gamma=np.array(gs),
            tip_load=np.array([ts.at_start(t) for _, ts in sigs]),
            num=max(opts.num, _STATIC_NUM),
        )

    last = states(float(te[-1]))
    start = states(before)
    codes = np.asarray(start.status).reshape(-1)
    bad = np.flatnonzero(codes < 0)
    if bad.size:
        i = int(bad[0])
        lam_i, tip_i = sigs[i][0].at_start(before), sigs[i][1].at_start(before)
        raise ValueError(
            _no_start(lam_i, tip_i, status_messages(int(codes[i]))) + f" (pillar {i})"
        )
    maps = np.asarray(last._map, dtype=np.float64).reshape(-1)
    maps = np.where(np.isfinite(maps), maps, 0.0)
    smap = np.asarray(start._map, dtype=np.float64).reshape(-1)
    scoef = np.asarray(start._coefs, dtype=np.float64).reshape(3, count, -1)
    jobs = []
    for i in range(count):
        jobs.append(
            _Job(
                te,
                opts,
                float(t0s[i]),
                float(gs[i]),
                float(mus[i]),
                float(maps[i]),
                (float(smap[i]), np.ascontiguousarray(scoef[:, i])),
                sigs[i][0],
                sigs[i][1],
                prof,
            )  # fmt: skip
        )
    if nw == 1 or count == 1:
        return [_run(job) for job in jobs]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=min(nw, count)) as pool:
        return list(pool.map(_run, jobs))
