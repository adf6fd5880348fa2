"""Valves and pumps in time: a bed's flow under a switched or pulsing pressure drop.

The bed as a valve (:mod:`hairbed.valve`) is a quasi-static device: its flow follows the
pressure drop through the steady states. In time the hairs lag the drop, and the flow with
them (theory.md §15, the porous bed in time, :func:`hairbed.dynamics.simulate_bed`):

- :func:`valve_switching`: a step in the pressure drop; the flow rate's response and its time
  to 90 % of the change.
- :func:`pump_net_flow`: a zero-mean oscillating drop dp(t) = A sin(2 pi f t) across a tilted
  bed. The valve's asymmetry rectifies it: the flow averaged over a period (the net flow) is
  not zero. Its quasi-static limit is the phase average of the steady valve curve,

      Q_qs(A) = (1/2 pi) int_0^{2 pi} Q'(A sin phi) d phi,

  which the net flow reaches as f -> 0; at frequencies beyond the hairs' relaxation rate
  1/T the hairs cannot follow the drop and the rectification fades.

The bed in time is the porous model of theory.md §15 (both walls at rest; the pump drives),
for a ``HairBed`` of either ``model``: its kappa, drag ratio and time scale
T = zeta_perp L^4/(E I) come from the bed's geometry and ``drag`` law. The fluid is
quasi-steady (Womersley number 0) unless the bed has a ``density``: then the fluid's inertia
enters with alpha = rho L^2/(eta T). The hairs are overdamped unless ``hair_density`` is
given (their inertia number mu = (rho_s + rho_f) pi a^2/(zeta_perp T), the fluid's added mass
with the fluid's density, 0 without it).

Units: pressure drops [Pa], channel length [m], flow rates per unit width [m^2/s], times [s],
frequencies [Hz].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._bed_scales import _as_porous, _BedScales, _scales
from ._core.porous import solve_porous
from ._core.validation import (
    _first_index,
    as_float_array,
    check_int,
    check_number,
    check_positive,
    show,
)
from ._optional import optional_import
from ._version import __version__
from .bed_simulation import _within_range
from .dynamics import BedTrajectory, linearise_bed, periodic_bed, simulate_bed, sine, step
from .dynamics._bed import MAX_BED_DRIVE
from .units import HairBed
from .valve import valve_curve

__all__ = [
    "PUMP_METHODS",
    "PUMP_STATUS",
    "PUMP_VARIABLES",
    "PumpNetFlow",
    "SWITCH_STATUS",
    "ValveSwitching",
    "bed_time_scales",
    "pump_net_flow",
    "pump_sweep",
    "valve_switching",
]

FloatArray = NDArray[np.float64]

#: Status codes of :class:`ValveSwitching` (negative: the run's own, :data:`BED_STATUS`).
SWITCH_STATUS = {
    0: "the flow settled to the steady valve curve's value",
    1: "the run ended before the flow settled (within 1e-6 of the change): a longer duration "
    "is needed",
    2: "the step changes nothing (equal drops): no rise time",
}
#: Status codes of :class:`PumpNetFlow`, per (amplitude, frequency).
PUMP_STATUS = {
    0: "the periodic state reached: the last two periods' net flows agree to the tolerance "
    "(transient), or the collocation's truncation error is below it (collocation)",
    1: "max_periods reached before two periods' net flows agreed to the tolerance "
    "(transient), or the highest harmonics exceed it at the largest degree (collocation)",
}
#: The methods of :func:`pump_net_flow`.
PUMP_METHODS = ("collocation", "transient")


def bed_time_scales(bed: HairBed, hair_density: float | None = None) -> dict[str, float]:
    """The bed's time scale and the numbers of its dynamics (theory.md §15), with the
    hairs' density ``hair_density`` rho_s [kg/m^3] (None: overdamped hairs, mu = 0).

    Returns a dict with ``time_scale`` T = zeta_perp L^4/(E I) [s], ``inertia`` mu [-],
    ``tangential_mass`` chi [-], ``womersley`` alpha = rho L^2/(eta T) [-] and ``kappa`` [-].
    """
    s = _scales(bed, hair_density)
    return {
        "time_scale": s.time,
        "inertia": s.inertia,
        "tangential_mass": s.tangential_mass,
        "womersley": s.womersley,
        "kappa": s.kappa,
    }


def _per_drop(s: _BedScales, length: float) -> float:
    """Pi per Pa of pressure drop over the channel [1/Pa] (a ValueError naming
    channel_length where it overflows or underflows)."""
    per_drop = s.pi_per_gradient / length
    if not (math.isfinite(per_drop) and per_drop > 0.0):
        raise ValueError(
            f"channel_length = {show(length)} m gives a pressure load per pascal of "
            f"{per_drop!r} for this bed: choose a channel length within about 1e-300 and 1e300 m"
        )
    return per_drop


def _channel_length(value: Any) -> float:
    return check_positive(value, "channel_length", "m")


def _drop(value: Any, name: str) -> float:
    x = as_float_array(value, name, unit="Pa")
    if x.ndim != 0:
        raise ValueError(f"{name} must be one number [Pa], got an array of shape {x.shape}")
    return float(x)


def _run(s: _BedScales, t: FloatArray, pressure: Any, **kw: Any) -> BedTrajectory:
    return simulate_bed(
        s.theta0,
        s.kappa,
        s.eps,
        t_eval=t,
        pressure=pressure,
        gamma=s.gamma,
        inertia=s.inertia,
        tangential_mass=s.tangential_mass,
        womersley=s.womersley,
        **kw,
    )


@dataclass(frozen=True)
class ValveSwitching:
    """A valve's flow after a step in its pressure drop (:func:`valve_switching`).

    Attributes
    ----------
    time : ndarray
        Times after the step [s].
    pressure_drop : float
        The drop after the step [Pa] (``initial_pressure_drop`` before it).
    initial_pressure_drop : float
        The drop before the step [Pa].
    flow_rate : ndarray
        The flow per unit width through bed and gap [m^2/s] at ``time``.
    tip_height : ndarray
        The hairs' tip height [m] at ``time``.
    initial_flow_rate, final_flow_rate : float
        The steady valve curve's flow (:func:`hairbed.valve.valve_curve`, the same bed under
        the porous model) before and after the step [m^2/s].
    rise_time : float
        The first time the flow covers 90 % of its change [s] (linear interpolation between
        the samples of ``time``; NaN where it does not within the run).
    settling_time : float
        The time from which the flow stays within 10 % of its change of the final value [s]
        (the same interpolation; with an overshoot it is later than ``rise_time``).
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    status : int
        :data:`SWITCH_STATUS`, or the run's own negative status.
    message : str
    """

    time: FloatArray
    pressure_drop: float
    initial_pressure_drop: float
    flow_rate: FloatArray
    tip_height: FloatArray
    initial_flow_rate: float
    final_flow_rate: float
    rise_time: float
    settling_time: float
    time_scale: float
    status: int
    message: str

    @property
    def success(self) -> bool:
        """True when the flow settled (status 0)."""
        return self.status == 0

    def to_xarray(self) -> Any:
        """The response as an ``xarray.Dataset`` (dimension ``time`` [s], CF attributes)."""
        import xarray as xr

        return xr.Dataset(
            {
                "flow_rate": ("time", self.flow_rate, _attrs("m2 s-1", "flow rate per width")),
                "tip_height": ("time", self.tip_height, _attrs("m", "tip height of the hairs")),
            },
            coords={"time": ("time", self.time, _attrs("s", "time after the step"))},
            attrs={
                "pressure_drop_Pa": self.pressure_drop,
                "initial_pressure_drop_Pa": self.initial_pressure_drop,
                "rise_time_s": self.rise_time,
                "settling_time_s": self.settling_time,
                "time_scale_s": self.time_scale,
                "status": self.status,
                "message": self.message,
            },
        )


def _attrs(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def _steady_flows(bed: HairBed, drops: tuple[float, ...], length: float) -> FloatArray:
    """The steady valve curve's flows [m^2/s] at ``drops`` [Pa] (the porous model)."""
    curve = valve_curve(_as_porous(bed), np.asarray(drops, dtype=np.float64), length)
    return np.asarray(curve.flow_rate, dtype=np.float64)


def valve_switching(
    bed: HairBed,
    pressure_drop: float,
    channel_length: float,
    *,
    initial_pressure_drop: float = 0.0,
    duration: float | None = None,
    num_times: int = 801,
    hair_density: float | None = None,
    rtol: float = 1e-8,
) -> ValveSwitching:
    """The valve's flow after a step of its pressure drop at t = 0.

    The bed starts in the steady state of ``initial_pressure_drop`` and the drop jumps to
    ``pressure_drop``; the hairs follow in time (theory.md §15), and the flow per unit width
    Q'(t) with them, from the steady valve curve's Q'(dp0) to Q'(dp1). The rise time is the
    first t with (Q'(t) - Q'(dp0))/(Q'(dp1) - Q'(dp0)) >= 0.9, the settling time the time from
    which Q' stays within 10 % of the change of Q'(dp1). With a quasi-steady fluid the flow
    jumps with the drop and then creeps as the hairs bend: the rise time can be 0 when the
    jump alone covers 90 % of the change. The jump can overshoot: at the instant of the step
    the hairs move with the fluid, and the drag that resists the flow is that of the relative
    velocity (theory.md §15), so the bed lets more through than in the steady state; the
    settling time then measures the hairs.

    Parameters
    ----------
    bed : HairBed
        The bed (either model; in time it is the porous model of its geometry).
    pressure_drop : float
        The drop after the step, dp1 = p(0) - p(l) [Pa].
    channel_length : float
        The channel's length l [m] (the pressure gradient is dp/l).
    initial_pressure_drop : float, optional
        The drop before the step [Pa] (default 0).
    duration : float, optional
        How long to follow the flow [s] (default 10 T).
    num_times : int, optional
        Samples of the response, uniform in time, in [3, 10^6] (default 801).
    hair_density : float, optional
        The hairs' density [kg/m^3] for their inertia (default: overdamped hairs).
    rtol : float, optional
        The integrator's relative tolerance in [1e-12, 1e-3] (default 1e-8).

    Returns
    -------
    ValveSwitching
    """
    s = _within_range(_scales(bed, hair_density), bed, hair_density)
    length = _channel_length(channel_length)
    per_drop = _per_drop(s, length)
    dp1 = _drop(pressure_drop, "pressure_drop")
    dp0 = _drop(initial_pressure_drop, "initial_pressure_drop")
    n = check_int(num_times, "num_times", 3, 10**6)
    t_end = 10.0 * s.time if duration is None else check_positive(duration, "duration", "s")
    tol = check_number(rtol, "rtol", low=1e-12, high=1e-3)
    pi0, pi1 = dp0 * per_drop, dp1 * per_drop
    for name, value, drop in (("initial_pressure_drop", pi0, dp0), ("pressure_drop", pi1, dp1)):
        if not abs(value) <= MAX_BED_DRIVE:
            raise ValueError(
                f"{name} must lie within +-{MAX_BED_DRIVE / per_drop:.4g} Pa over channel_length "
                f"= {show(length)} m for this bed in time (its pressure load Pi within "
                f"+-{MAX_BED_DRIVE:g}), got {show(drop)}"
            )
    q0, q1 = (float(q) for q in _steady_flows(bed, (dp0, dp1), length))
    time = np.linspace(0.0, t_end, n)
    traj = _run(s, time / s.time, step(pi1, pi0, 0.0), rtol=tol, atol=tol * 1e-2)
    flow = np.asarray(traj.flow_rate) / s.q_per_flow
    tip = np.asarray(traj.tip_height) * bed.length
    if traj.status < 0:
        status, message = int(traj.status), str(traj.message)
    elif q1 == q0:
        status, message = 2, SWITCH_STATUS[2]
    elif abs(flow[-1] - q1) > 1e-6 * abs(q1 - q0):
        status, message = 1, SWITCH_STATUS[1]
    else:
        status, message = 0, SWITCH_STATUS[0]
    rise = _rise_time(time, flow, q0, q1) if q1 != q0 else math.nan
    settle = _settling_time(time, flow, q0, q1) if q1 != q0 else math.nan
    return ValveSwitching(
        time=time,
        pressure_drop=dp1,
        initial_pressure_drop=dp0,
        flow_rate=flow,
        tip_height=tip,
        initial_flow_rate=q0,
        final_flow_rate=q1,
        rise_time=rise,
        settling_time=settle,
        time_scale=s.time,
        status=status,
        message=message,
    )


def _rise_time(time: FloatArray, flow: FloatArray, q0: float, q1: float) -> float:
    frac = (flow - q0) / (q1 - q0)
    above = np.nonzero(np.isfinite(frac) & (frac >= 0.9))[0]
    if above.size == 0:
        return math.nan
    k = int(above[0])
    if k == 0:
        return float(time[0])
    f0, f1 = frac[k - 1], frac[k]
    return float(time[k - 1] + (0.9 - f0) / (f1 - f0) * (time[k] - time[k - 1]))


def _settling_time(time: FloatArray, flow: FloatArray, q0: float, q1: float) -> float:
    off = np.abs(flow - q1) / abs(q1 - q0) - 0.1  # > 0: outside the band
    if not np.all(np.isfinite(off)) or off[-1] > 0.0:
        return math.nan
    outside = np.nonzero(off > 0.0)[0]
    if outside.size == 0:
        return float(time[0])
    k = int(outside[-1])  # the last sample outside; the next is inside
    o0, o1 = off[k], off[k + 1]
    return float(time[k] + o0 / (o0 - o1) * (time[k + 1] - time[k]))


@dataclass(frozen=True)
class PumpNetFlow:
    """The net flow of a bed under a zero-mean oscillating pressure drop (:func:`pump_net_flow`).

    Attributes
    ----------
    amplitude : ndarray
        The drop's amplitudes A [Pa], (na,).
    frequency : ndarray
        The drop's frequencies f [Hz], (nf,).
    net_flow : ndarray
        The flow per unit width averaged over a period of the periodic state [m^2/s],
        (na, nf). Positive: along +x (the direction the hairs lean into for theta0 > 0).
    quasi_static_net_flow : ndarray
        Its quasi-static limit, the phase average of the steady valve curve [m^2/s], (na,).
    peak_frequency : ndarray
        The frequency of the largest abs(net flow) on the grid [Hz], (na,), refined by a
        parabola through the three grid points about the peak in log f (where the peak is
        at the grid's first or last frequency, that frequency, and ``peak_at_end`` is True).
    peak_at_end : ndarray of bool
        (na,): the largest abs(net flow) lies at the grid's first or last frequency.
    periods : ndarray of int
        Periods integrated for each (amplitude, frequency), (na, nf) (0 by collocation).
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    status : ndarray of int
        :data:`PUMP_STATUS` (or the run's own negative status) per (amplitude, frequency).
    message : str
        The worst status's message.
    """

    amplitude: FloatArray
    frequency: FloatArray
    net_flow: FloatArray
    quasi_static_net_flow: FloatArray
    peak_frequency: FloatArray
    peak_at_end: NDArray[np.bool_]
    periods: NDArray[np.int64]
    time_scale: float
    status: NDArray[np.int64]
    message: str

    @property
    def success(self) -> bool:
        """True when every (amplitude, frequency) reached its periodic state."""
        return bool(np.all(self.status == 0))

    def to_xarray(self) -> Any:
        """The net flows as an ``xarray.Dataset`` (dimensions ``amplitude`` [Pa] and
        ``frequency`` [Hz], CF attributes)."""
        import xarray as xr

        dims = ("amplitude", "frequency")
        return xr.Dataset(
            {
                "net_flow": (dims, self.net_flow, _attrs("m2 s-1", "net flow rate per width")),
                "quasi_static_net_flow": (
                    "amplitude",
                    self.quasi_static_net_flow,
                    _attrs("m2 s-1", "quasi-static net flow rate per width"),
                ),
                "peak_frequency": (
                    "amplitude",
                    self.peak_frequency,
                    _attrs("Hz", "frequency of the largest net flow"),
                ),
                "periods": (dims, self.periods, _attrs("1", "periods integrated")),
                "status": (dims, self.status, _attrs("1", "status")),
            },
            coords={
                "amplitude": (
                    "amplitude",
                    self.amplitude,
                    _attrs("Pa", "pressure drop amplitude"),
                ),
                "frequency": ("frequency", self.frequency, _attrs("Hz", "drive frequency")),
            },
            attrs={"time_scale_s": self.time_scale, "message": self.message},
        )


def _positive_array(value: Any, name: str, unit: str) -> FloatArray:
    x = np.atleast_1d(as_float_array(value, name, unit=unit))
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"{name} must be one number or a 1-d array of them [{unit}], got "
                         f"shape {x.shape}")  # fmt: skip
    bad = ~(x > 0.0)
    if np.any(bad):
        raise ValueError(f"{name} must be in (0, inf) {unit}, got {float(x[bad][0])!r}"
                         f"{_first_index(bad)}")  # fmt: skip
    return x


def _quasi_static(bed: HairBed, amplitude: float, length: float, samples: int) -> float:
    """(1/2 pi) int Q'(A sin phi) d phi by the periodic trapezoidal rule on ``samples`` phases
    (spectrally accurate for the smooth periodic integrand)."""
    porous = _as_porous(bed)
    phi = 2.0 * math.pi * np.arange(samples) / samples
    return float(
        np.mean(np.asarray(valve_curve(porous, amplitude * np.sin(phi), length).flow_rate))
    )


def pump_net_flow(
    bed: HairBed,
    amplitude: Any,
    frequency: Any,
    channel_length: float,
    *,
    samples_per_period: int = 64,
    max_periods: int = 400,
    tol: float = 1e-6,
    hair_density: float | None = None,
    rtol: float = 1e-8,
    method: str = "collocation",
) -> PumpNetFlow:
    """The net flow of a bed pumped by dp(t) = A sin(2 pi f t): the rectification in time.

    For each amplitude and frequency the bed's periodic state, by one of two methods:

    * ``"collocation"`` (the default): :func:`hairbed.dynamics.periodic_bed`, trigonometric
      collocation in time with Newton's method (theory.md §16), its truncation error below
      min(tol, 1e-10); the net flow is the exact period-mean of its flow rate.
    * ``"transient"`` (the baseline): the bed starts at rest (dp = 0) and is integrated
      (:func:`hairbed.dynamics.simulate_bed`) period after period; the net flow of a period
      is the mean of Q'(t) over it by the periodic trapezoidal rule on
      ``samples_per_period`` samples (spectrally accurate on a periodic state). The
      periodic state is reached when two consecutive periods' net flows agree within
      ``tol`` times the flow amplitude max abs(Q'(t)) of the last period; the net flow
      reported is the last period's. The run is extended (doubling its periods) up to
      ``max_periods``.

    The quasi-static net flow, the phase average of the steady valve curve, is computed by
    :func:`hairbed.valve.valve_curve` on the same phases: the net flow tends to it as f -> 0.

    Parameters
    ----------
    bed : HairBed
        The bed (either model; in time it is the porous model of its geometry).
    amplitude : float or array_like
        The drop's amplitudes A [Pa], positive, (na,).
    frequency : float or array_like
        The drop's frequencies f [Hz], positive, (nf,).
    channel_length : float
        The channel's length l [m].
    samples_per_period : int, optional
        In [8, 4096] (default 64).
    max_periods : int, optional
        In [2, 10^5] (default 400).
    tol : float, optional
        The periodic state's tolerance in [1e-12, 1e-2] (default 1e-6).
    hair_density : float, optional
        The hairs' density [kg/m^3] for their inertia (default: overdamped hairs).
    rtol : float, optional
        The integrator's relative tolerance in [1e-12, 1e-3] (default 1e-8; transient only).
    method : {"collocation", "transient"}, optional
        The periodic state's method (above; default "collocation").

    Returns
    -------
    PumpNetFlow
    """
    s = _within_range(_scales(bed, hair_density), bed, hair_density)
    length = _channel_length(channel_length)
    per_drop = _per_drop(s, length)
    amps = _positive_array(amplitude, "amplitude", "Pa")
    freqs = _positive_array(frequency, "frequency", "Hz")
    m = check_int(samples_per_period, "samples_per_period", 8, 4096)
    kmax = check_int(max_periods, "max_periods", 2, 10**5)
    ptol = check_number(tol, "tol", low=1e-12, high=1e-2)
    itol = check_number(rtol, "rtol", low=1e-12, high=1e-3)
    if method not in PUMP_METHODS:
        raise ValueError(f"method must be one of {PUMP_METHODS}, got {method!r}")
    with np.errstate(over="ignore"):
        big = amps * per_drop
    bad = ~(big <= MAX_BED_DRIVE)
    if np.any(bad):
        raise ValueError(
            f"amplitude must be at most {MAX_BED_DRIVE / per_drop:.4g} Pa over channel_length = "
            f"{show(length)} m for this bed in time (its pressure load Pi within "
            f"{MAX_BED_DRIVE:g}), got {show(float(amps[bad][0]))}"
            f"{_first_index(bad)}"
        )
    with np.errstate(over="ignore", under="ignore"):
        omega_t = 2.0 * math.pi * freqs * s.time  # the angular frequency in 1/T
    bad = ~((omega_t >= 1e-9) & (omega_t <= 1e9))
    if np.any(bad):
        lo, hi = 1e-9 / (2.0 * math.pi * s.time), 1e9 / (2.0 * math.pi * s.time)
        raise ValueError(
            f"frequency must lie in [{lo:.3g}, {hi:.3g}] Hz for this bed (1e-9 to 1e9 over its "
            f"time scale 2 pi T), got {show(float(freqs[bad][0]))}{_first_index(bad)}"
        )
    na, nf = amps.size, freqs.size
    net = np.full((na, nf), np.nan)
    periods = np.zeros((na, nf), dtype=np.int64)
    status = np.zeros((na, nf), dtype=np.int64)
    messages: dict[int, str] = {0: PUMP_STATUS[0]}
    qs = np.array([_quasi_static(bed, float(a), length, m) for a in amps])
    rate = _slowest_decay(s) if method == "transient" else math.nan
    for i, pia in enumerate(big):
        for j, om in enumerate(omega_t):
            if method == "collocation":
                orbit = periodic_bed(
                    s.theta0, s.kappa, s.eps, omega=float(om), pressure=sine(0.0, float(pia),
                    float(om)), gamma=s.gamma, inertia=s.inertia,
                    tangential_mass=s.tangential_mass, womersley=s.womersley,
                    tol=min(ptol, 1e-10),
                )  # fmt: skip
                status[i, j] = orbit.status
                if orbit.status >= 0:
                    net[i, j] = orbit.mean("flow_rate") / s.q_per_flow
                if orbit.status != 0:
                    messages[orbit.status] = (
                        PUMP_STATUS[1] if orbit.status == 1 else str(orbit.message)
                    )
                continue
            # the periods for the start's transient to decay below tol at the rest state's
            # slowest rate (the check below extends the run where the cycle's rate is slower)
            k = int(
                min(
                    kmax, max(4, math.ceil(math.log(1.0 / ptol) * om / (2.0 * math.pi * rate)) + 2)
                )
            )
            while True:
                t = np.arange(k * m + 1) * (2.0 * math.pi / om) / m
                traj = _run(s, t, sine(0.0, float(pia), float(om)), rtol=itol, atol=itol * 1e-2)
                if traj.status < 0:
                    status[i, j] = traj.status
                    messages[int(traj.status)] = str(traj.message)
                    break
                flow = np.asarray(traj.flow_rate) / s.q_per_flow
                last = flow[(k - 1) * m : k * m]
                prev = flow[(k - 2) * m : (k - 1) * m]
                net[i, j] = float(np.mean(last))
                scale = float(np.max(np.abs(last)))
                periods[i, j] = k
                if abs(net[i, j] - float(np.mean(prev))) <= ptol * scale:
                    break
                if k >= kmax:
                    status[i, j] = 1
                    messages[1] = PUMP_STATUS[1]
                    break
                k = min(2 * k, kmax)
    peak, at_end = _peaks(freqs, net)
    worst = int(status.min()) if np.any(status < 0) else int(status.max())
    return PumpNetFlow(
        amplitude=amps,
        frequency=freqs,
        net_flow=net,
        quasi_static_net_flow=qs,
        peak_frequency=peak,
        peak_at_end=at_end,
        periods=periods,
        time_scale=s.time,
        status=status,
        message=messages[worst],
    )


def _slowest_decay(s: _BedScales) -> float:
    """The slowest decay rate [1/T] of the bed's small motions about rest (the smallest
    -Re lambda of :func:`hairbed.dynamics.linearise_bed`'s modes)."""
    rest = solve_porous(0.0, s.eps, s.theta0, kappa=s.kappa, gamma=s.gamma, pi=0.0)
    lin = linearise_bed(
        rest, inertia=s.inertia, tangential_mass=s.tangential_mass, womersley=s.womersley
    )
    lam = lin.modes(4).eigenvalues
    return float(np.min(-lam.real))


def _peaks(freqs: FloatArray, net: FloatArray) -> tuple[FloatArray, NDArray[np.bool_]]:
    """The frequency of the largest abs(net flow) per amplitude, refined in log f."""
    na = net.shape[0]
    peak = np.full(na, np.nan)
    at_end = np.zeros(na, dtype=bool)
    if freqs.size == 0:
        return peak, at_end
    order = np.argsort(freqs)
    lf = np.log(freqs[order])
    for i in range(na):
        y = np.abs(net[i, order])
        if not np.all(np.isfinite(y)):
            continue
        k = int(np.argmax(y))
        if k == 0 or k == y.size - 1:
            at_end[i] = True
            peak[i] = float(freqs[order][k])
            continue
        x0, x1, x2 = lf[k - 1], lf[k], lf[k + 1]
        y0, y1, y2 = y[k - 1], y[k], y[k + 1]
        den = (x0 - x1) * (x0 - x2) * (x1 - x2)
        a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den
        b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den
        peak[i] = float(np.exp(-b / (2.0 * a))) if a < 0 else float(freqs[order][k])
    return peak, at_end


#: The variables of :func:`pump_sweep`: name -> (units, long_name).
PUMP_VARIABLES: dict[str, tuple[str, str]] = {
    "net_flow": ("m2 s-1", "net flow rate per width over a period of the periodic state"),
    "quasi_static_net_flow": ("m2 s-1", "phase average of the steady valve curve's flow rate"),
    "periods": ("1", "periods integrated"),
    "status": ("1", "0 periodic to tol; 1 max_periods reached; negative: the run's status"),
}
_SWEEP_COORDS = {
    "amplitude": ("Pa", "amplitude of the pressure drop, A sin(2 pi f t)"),
    "frequency": ("Hz", "frequency of the pressure drop"),
}


def _sweep_block(
    amps: FloatArray,
    freqs: FloatArray,
    *,
    bed: Any,
    channel_length: float,
    options: dict[str, Any],
    progress: Any,
) -> FloatArray:
    """One block: (4, amplitudes, frequencies)."""
    r = pump_net_flow(bed, amps, freqs, channel_length, **options)
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
    method: str = "collocation",
) -> Any:
    """The net flow of a bed pumped by dp(t) = A sin(2 pi f t) over the grid (amplitude,
    frequency), as an xarray Dataset with units (:func:`pump_net_flow`
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
        "method": method,
    }
    if method not in PUMP_METHODS:
        raise ValueError(f"method must be one of {PUMP_METHODS}, got {method!r}")
    # every input checked now (one cheap cell), not inside a lazy block
    from .sweeps._blocks import stacked  # the sweeps' blocks (numpy now or dask later)

    amps = _positive_array(amplitude, "amplitude", "Pa")
    freqs = _positive_array(frequency, "frequency", "Hz")
    _scales(bed, hair_density)
    length = _channel_length(channel_length)
    data = stacked(
        _sweep_block,
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
              for (d, (u, ln)), a in zip(_SWEEP_COORDS.items(), (amps, freqs))}  # fmt: skip
    attrs = {
        "title": "hairbed: a pulsing pump's net flow over amplitude and frequency",
        "Conventions": "CF-1.8",
        "source": f"hairbed {__version__}",
        "bed": repr(bed),
        "channel_length_m": length,
        "time_scale_s": bed_time_scales(bed, hair_density)["time_scale"],
        "model": "the porous bed in time (theory.md section 15)",
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)
