"""Drives as functions of time: Lambda(t) and the tip load P(t) (issue 30, theory.md §14).

A :class:`Signal` is evaluated inside the compiled integrator (``_kernels.dynamics``); the
named ones are exact, a sampled series is its piecewise cubic Hermite interpolant
(Catmull-Rom slopes), and a Python callable is sampled at ``CALLABLE_SAMPLES`` uniform times
of the run (fewer where the run's tolerance is loose and they resolve the callable to it:
:func:`as_signal`'s ``rtol``) and interpolated the same way.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.solver import _scalar
from .._core.validation import as_float_array, check_number, show

__all__ = [
    "CALLABLE_SAMPLES",
    "Signal",
    "as_signal",
    "constant",
    "pulses",
    "ramp",
    "sampled",
    "sine",
    "step",
]

FloatArray = NDArray[np.float64]
#: The uniform samples over the run of a callable drive (its cubic interpolant's error is
#: ~ (dt)^3 f''' inside, ~ (dt)^2 f'' on the two end intervals, whose slopes are one-sided):
#: all of them where no tolerance is given, the most where one is (:func:`as_signal`).
CALLABLE_SAMPLES = 4097
#: The least uniform samples of a callable drive under a tolerance (:func:`as_signal`).
CALLABLE_LEAST_SAMPLES = 65
_KINDS = {"constant": 0, "step": 1, "ramp": 2, "sine": 3, "pulses": 4, "sampled": 5}


@dataclass(frozen=True)
class Signal:
    """A drive d(t) (t in T = zeta_perp L^4/(E I)).

    Attributes
    ----------
    kind : str
        "constant", "step", "ramp", "sine", "pulses" or "sampled".
    params : tuple of float
        The kind's parameters (see the constructors :func:`step`, :func:`ramp`, ...).
    times, values : ndarray
        The samples of a "sampled" signal (empty otherwise).
    """

    kind: str
    params: tuple[float, ...]
    times: FloatArray
    values: FloatArray

    def row(self) -> FloatArray:
        """The kernel's row: the kind's code, then up to 7 parameters."""
        out = np.zeros(8)
        out[0] = _KINDS[self.kind]
        out[1 : 1 + len(self.params)] = self.params
        return out

    @functools.cached_property
    def _kernel_args(self) -> tuple[int, FloatArray, FloatArray, FloatArray]:
        """(kind code, parameters, times, values) of the kernel's ``drive_value``, built
        once per signal."""
        row = self.row()
        tt, vv = (self.times, self.values) if self.times.size else (_ZERO, _ZERO)
        return int(row[0]), row[1:], tt, vv

    def __call__(self, t: ArrayLike) -> Any:
        """d(t) [-] at the times t (the compiled evaluation the integrator uses)."""
        tv = np.asarray(t, dtype=np.float64)
        if self.kind == "constant":
            return np.full(tv.shape, self.params[0]) if tv.ndim else float(self.params[0])
        value = _drive_value()
        kind, pars, tt, vv = self._kernel_args
        if not tv.ndim:
            return float(value(kind, pars, tt, vv, float(tv)))
        out = np.array([value(kind, pars, tt, vv, float(x)) for x in tv.reshape(-1)])
        return out.reshape(tv.shape)

    def at_start(self, t0: float) -> float:
        """d(t0)."""
        if type(t0) is float and math.isfinite(t0):  # a plain time: check_number's value
            if self.kind == "constant":
                return float(self.params[0])
            kind, pars, tt, vv = self._kernel_args
            return float(_drive_value()(kind, pars, tt, vv, t0))
        return float(self(check_number(t0, "t0")))


@functools.lru_cache(maxsize=1)
def _drive_value() -> Any:
    """The compiled ``drive_value`` (imported on first use: ``import hairbed`` loads no
    kernel)."""
    from .._core._kernels import dynamics as kern

    return kern.drive_value


_EMPTY = np.zeros(0)
_ZERO = np.zeros(1)


def _finite(value: Any, name: str) -> float:
    return check_number(value, name)


def constant(value: float) -> Signal:
    """d(t) = value."""
    return Signal("constant", (_finite(value, "value"),), _EMPTY, _EMPTY)


def step(after: float, before: float = 0.0, at: float = 0.0) -> Signal:
    """d = before for t < at, after from t = at on."""
    return Signal(
        "step",
        (_finite(before, "before"), _finite(after, "after"), _finite(at, "at")),
        _EMPTY,
        _EMPTY,
    )


def ramp(start: float, end: float, t_start: float, t_end: float) -> Signal:
    """d = start until t_start, linear to end at t_end, then end (t_end > t_start)."""
    a = _finite(t_start, "t_start")
    b = _finite(t_end, "t_end")
    if not b > a:
        raise ValueError(f"t_end must be greater than t_start = {show(a)}, got {show(b)}")
    return Signal("ramp", (_finite(start, "start"), _finite(end, "end"), a, b), _EMPTY, _EMPTY)


def sine(mean: float, amplitude: float, omega: float, phase: float = 0.0) -> Signal:
    """d = mean + amplitude sin(omega t + phase) (omega [1/T] > 0)."""
    om = check_number(omega, "omega", low=0.0, low_open=True)
    return Signal(
        "sine",
        (_finite(mean, "mean"), _finite(amplitude, "amplitude"), om, _finite(phase, "phase")),
        _EMPTY,
        _EMPTY,
    )


def pulses(base: float, height: float, period: float, width: float, start: float = 0.0) -> Signal:
    """d = base, plus height during the first ``width`` of every ``period`` from ``start``
    (0 < width < period)."""
    p = check_number(period, "period", low=0.0, low_open=True)
    w = check_number(width, "width", low=0.0, low_open=True)
    if not w < p:
        raise ValueError(f"width must be less than period = {p:g}, got width {w:g}")
    return Signal(
        "pulses",
        (_finite(base, "base"), _finite(height, "height"), p, w, _finite(start, "start")),
        _EMPTY,
        _EMPTY,
    )


def sampled(times: ArrayLike, values: ArrayLike) -> Signal:
    """The piecewise cubic Hermite interpolant of (times, values) (Catmull-Rom slopes; held
    at the end values outside); times strictly increasing, at least 2 samples."""
    tt = as_float_array(times, "times").reshape(-1)
    vv = as_float_array(values, "values").reshape(-1)
    if tt.size < 2 or vv.size != tt.size:
        raise ValueError(
            f"times and values must be 1-d of the same size >= 2, got {tt.size} and {vv.size}"
        )
    for name, arr in (("times", tt), ("values", vv)):
        bad = ~np.isfinite(arr)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(f"{name} must be finite, got {show(float(arr[i]))} at index {i}")
    back = np.flatnonzero(np.diff(tt) <= 0.0)
    if back.size:
        i = int(back[0]) + 1
        raise ValueError(f"times must increase strictly; index {i} is {show(float(tt[i]))}")
    return Signal("sampled", (), np.ascontiguousarray(tt), np.ascontiguousarray(vv))


#: The largest magnitude of a drive's levels (a number; a step's, ramp's or pulse train's
#: levels; a sine's mean plus amplitude; a sampled signal's samples): far above any state
#: the statics find (they end near Lambda ~ 1e15), and far enough below the largest double
#: that the integrator's rates and Jacobians, ~ N^4 times the drive, stay finite.
MAX_DRIVE = 1e100


def _peak(sig: Signal) -> float:
    """The largest magnitude of the signal's levels (see :data:`MAX_DRIVE`)."""
    if sig.kind == "sampled":  # (the array's method: numpy's reduction, less Python)
        return float(np.abs(sig.values).max())
    if sig.kind == "constant":
        return abs(float(sig.params[0]))
    p = np.abs(np.asarray(sig.params, dtype=np.float64))
    with np.errstate(over="ignore"):
        if sig.kind == "sine":  # mean +- amplitude
            return float(p[0] + p[1])
        if sig.kind == "pulses":  # base, and base + height
            return max(float(p[0]), abs(float(np.float64(sig.params[0]) + sig.params[1])))
        return float(np.max(p[:2]))  # constant; a step's before/after; a ramp's start/end


def check_drive(sig: Signal, name: str) -> Signal:
    """``sig`` if its levels stay within :data:`MAX_DRIVE` in magnitude, else a ValueError
    naming ``name``."""
    peak = _peak(sig)
    if not peak <= MAX_DRIVE:
        raise ValueError(
            f"{name} must stay within [-{MAX_DRIVE:g}, {MAX_DRIVE:g}], got a {sig.kind} "
            f"drive of magnitude {show(peak)}"
        )
    return sig


def as_signal(value: Any, name: str, t0: float, t1: float, rtol: float | None = None) -> Signal:
    """A Signal from a number, a Signal or a callable d(t) (sampled over [t0, t1]).

    A callable is sampled at ``CALLABLE_SAMPLES`` uniform times where ``rtol`` is None. Under
    a tolerance rtol > 0 (the run's) it is sampled at K = 2^k + 1 uniform times, K from
    :func:`_first_samples` (the interpolant's error ~ K^-3, scaled from CALLABLE_SAMPLES at
    rtol = 1e-10; at least ``CALLABLE_LEAST_SAMPLES``), and K doubled (2 K - 1 times, the
    old among them) until the interpolant of every other sample reproduces the samples
    between them to rtol max|d| (the interpolant of all K, at half that spacing, is then
    within about an eighth of it inside, a quarter on the end intervals) or K reaches
    CALLABLE_SAMPLES. Like any sampling it cannot see a feature narrower than the spacing
    (t1 - t0)/(K - 1) that falls between the samples.
    """
    if isinstance(value, Signal):
        return value
    if callable(value):
        return _from_callable(value, name, t0, t1, rtol)
    x = _scalar(value)
    if x is not None and math.isfinite(x):  # a plain number: the checks' value, no numpy
        return Signal("constant", (x,), _EMPTY, _EMPTY)
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        return constant(check_number(value, name))
    raise TypeError(
        f"{name} must be a number, a hairbed.dynamics Signal (step, ramp, sine, pulses, "
        f"sampled) or a callable d(t), got {type(value).__name__}"
    )


def _first_samples(rtol: float) -> int:
    """The first count K = 2^k + 1 of a callable's samples under the tolerance rtol > 0:
    the least with 2^k >= 4096 (1e-10/rtol)^(1/3), within [``CALLABLE_LEAST_SAMPLES``,
    ``CALLABLE_SAMPLES``]."""
    want = (CALLABLE_SAMPLES - 1) * (1e-10 / rtol) ** (1.0 / 3.0)
    count = CALLABLE_LEAST_SAMPLES
    while count < CALLABLE_SAMPLES and count - 1 < want:
        count = 2 * count - 1
    return count


def _resolved(vals: FloatArray, rtol: float) -> bool:
    """Whether the cubic Hermite interpolant (Catmull-Rom slopes inside, the secant's at the
    two ends, as the kernel's ``drive_value``) of the even samples reproduces the odd ones
    to rtol max|vals| (uniform times: a slope times the spacing is a difference)."""
    even = vals[::2]
    lo, hi = even[:-1], even[1:]
    central = 0.5 * (even[2:] - even[:-2])
    s0 = np.empty_like(lo)  # the slopes at each interval's two ends, times its length
    s1 = np.empty_like(lo)
    s0[0] = hi[0] - lo[0]
    s0[1:] = central
    s1[-1] = hi[-1] - lo[-1]
    s1[:-1] = central
    mid = 0.5 * (lo + hi) + 0.125 * (s0 - s1)  # the Hermite basis at x = 1/2
    return bool(np.abs(mid - vals[1::2]).max() <= rtol * np.abs(vals).max())


@functools.lru_cache(maxsize=32)
def _sample_times(
    t0: float, t1: float, s0: float, s1: float, count: int = CALLABLE_SAMPLES
) -> tuple[FloatArray, bool]:
    """A callable's ``count`` sample times over [t0, t1] (read-only, shared: copy them) and
    whether they are distinct, built once per span and count (s0, s1: the signs of t0, t1,
    so that -0.0 is not 0.0's entry)."""
    tt = np.linspace(t0, t1, count)
    tt.setflags(write=False)
    return tt, bool(np.all(tt[1:] > tt[:-1]))


def _from_callable(
    func: Callable[..., Any], name: str, t0: float, t1: float, rtol: float | None = None
) -> Signal:
    """The callable sampled as :func:`as_signal` says."""
    count = CALLABLE_SAMPLES if rtol is None else _first_samples(rtol)
    while True:
        sig = _sampled_callable(func, name, t0, t1, count)
        if rtol is None or count >= CALLABLE_SAMPLES or _resolved(sig.values, rtol):
            return sig
        count = 2 * count - 1


def _sampled_callable(
    func: Callable[..., Any], name: str, t0: float, t1: float, count: int
) -> Signal:
    """The callable at ``count`` uniform times over [t0, t1], its values checked."""
    sign0, sign1 = math.copysign(1.0, t0), math.copysign(1.0, t1)
    shared, distinct = _sample_times(t0, t1, sign0, sign1, count)
    tt = shared.copy()
    try:
        raw = func(shared.copy())  # its own copy: a callable that writes to it changes no time
    except Exception as exc:  # the user's function: say whose error it is
        raise ValueError(
            f"{name}: the callable raised {type(exc).__name__}: {exc} (it is called with an "
            "ndarray of times [T])"
        ) from exc
    vals = np.asarray(raw, dtype=np.float64)
    if vals.shape != tt.shape:
        vals = np.broadcast_to(vals, tt.shape).copy() if vals.ndim == 0 else vals
    if vals.shape != tt.shape:
        raise ValueError(
            f"{name}: the callable must return an array of the shape of t {tt.shape}, got "
            f"{vals.shape}"
        )
    bad = ~np.isfinite(vals)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name}: the callable returned {show(float(vals[i]))} at t = {show(float(tt[i]))}"
        )
    # the samples are checked: what :func:`sampled` would check again is the times alone
    if not distinct:
        raise ValueError(
            f"{name}: the run's span [{show(t0)}, {show(t1)}] is too short at its magnitude "
            f"for {count} distinct sample times of the callable; pass a "
            "sampled(times, values) signal"
        )
    return Signal("sampled", (), tt, np.ascontiguousarray(vals, dtype=np.float64))


#: The parameters of each named signal that are levels (times the drive's scale), times
#: [s] (over T) and angular frequencies [rad/s] (times T), for :func:`si_signal`.
SI_PARAMETER_UNITS = {
    "constant": ("level",),
    "step": ("level", "level", "time"),
    "ramp": ("level", "level", "time", "time"),
    "sine": ("level", "level", "rate", "angle"),
    "pulses": ("level", "level", "time", "time", "time"),
}


def si_signal(
    drive: Any, name: str, unit: str, per_unit: float, t: FloatArray, t_scale: float,
    bound: float, subject: str, bound_name: str,
) -> Signal:  # fmt: skip
    """The dimensionless drive d'(t') = ``per_unit`` d(T t') of an SI drive d(t) [unit], t
    [s], T = ``t_scale`` [s]: a number (a step from rest at t[0]), a signal in SI or a
    callable of t [s] (sampled at CALLABLE_SAMPLES uniform times of t). A ValueError naming
    ``name`` where its levels exceed ``bound`` (dimensionless: ``bound_name`` of ``subject``) or a
    callable fails, raises or returns a value that is not finite; a TypeError for any other
    kind."""
    top = bound / per_unit  # [unit]

    def within(peak: float) -> None:
        if not peak <= top:
            raise ValueError(
                f"{name} must stay within [-{top:.4g}, {top:.4g}] {unit} for {subject} "
                f"({bound_name} within +-{bound:g}), got a drive of magnitude {show(peak)} "
                f"{unit}"
            )

    if isinstance(drive, Signal):
        within(_peak(drive))
        if drive.kind == "sampled":
            return sampled(drive.times / t_scale, drive.values * per_unit)
        scale = {"level": per_unit, "time": 1.0 / t_scale, "rate": t_scale, "angle": 1.0}
        units = SI_PARAMETER_UNITS[drive.kind]
        params = tuple(p * scale[u] for p, u in zip(drive.params, units, strict=True))
        return dataclasses.replace(drive, params=params)
    if callable(drive):
        ts = np.linspace(float(t[0]), float(t[-1]), CALLABLE_SAMPLES)
        try:
            raw = drive(ts)
        except Exception as exc:  # the user's function: say whose error it is
            raise ValueError(
                f"{name}: the callable raised {type(exc).__name__}: {exc} (it is called with "
                f"an ndarray of times [s] and returns {name} [{unit}])"
            ) from exc
        vals = np.asarray(raw, dtype=np.float64)
        if vals.ndim == 0:
            vals = np.full(ts.shape, float(vals))
        if vals.shape != ts.shape:
            raise ValueError(
                f"{name}: the callable must return an array of the shape of t {ts.shape} "
                f"[{unit}], got {vals.shape}"
            )
        bad = ~np.isfinite(vals)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"{name}: the callable returned {float(vals[i])!r} {unit} at "
                f"t = {float(ts[i])!r} s"
            )
        within(float(np.max(np.abs(vals))))
        if ts[-1] == ts[0]:
            return constant(float(vals[0]) * per_unit)
        return sampled(ts / t_scale, vals * per_unit)
    if isinstance(drive, (int, float, np.integer, np.floating)) and not isinstance(drive, bool):
        value = check_number(drive, name, unit=unit)
        within(abs(value))
        return step(value * per_unit, 0.0, float(t[0]) / t_scale)  # from rest at t[0]
    raise TypeError(
        f"{name} must be a number [{unit}] (a step from rest at the first time), a "
        f"hairbed.dynamics "
        f"signal in SI (step, ramp, sine, pulses, sampled: times [s], values [{unit}], sine's "
        f"omega [rad/s]) or a callable of t [s] returning {name} [{unit}], got "
        f"{type(drive).__name__}"
    )
