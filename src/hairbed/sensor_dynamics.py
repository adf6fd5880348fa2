"""A micropillar wall-shear-stress sensor in time, in SI (issue 31, theory.md §14).

The dimensionless linear dynamics of :mod:`hairbed.dynamics` (:func:`linearise_pillar` about
the large-deflection static state at the mean stress) mapped onto a :class:`hairbed.Pillar`:

    T     = zeta_perp L^4/(E I)                  the elastoviscous time [s]
    omega = 2 pi f T                             the dimensionless angular frequency [-]
    mu    = m E I/(zeta_perp^2 L^4) = m/(zeta_perp T)   the inertia number [-]
    H(f)  = L (Lambda/tau_w) H_Lambda(omega)     tip deflection per wall shear stress [m/Pa]

with m = (rho_s + rho_f) pi a^2 and chi = rho_s/(rho_s + rho_f) for the quasi-steady drag
(the fluid's added mass on normal motion, theory.md §14 D3), or m = rho_s pi a^2 and Sader's
oscillating-cylinder drag (which carries the added mass) for ``drag="sader"``.

- :func:`frequency_response`: the Bode data, the static gain, the resonance, its quality
  factor and the usable bandwidth (:class:`SensorResponse`).
- :func:`simulate`: the nonlinear pillar in time under a wall-shear-stress drive tau_w(t)
  (a step, a named signal in seconds and pascals, a callable), in SI
  (:class:`SensorTrajectory`).
- :func:`wall_shear_stress_from_tip_deflection_series`: a measured tip-deflection series back
  to the wall-shear-stress series with its 1-sigma band: the exact static inverse about the
  mean and a Wiener deconvolution of the dynamics (:class:`StressSeries`).

:meth:`hairbed.Pillar.frequency_response`, :meth:`hairbed.Pillar.simulate` and
:meth:`hairbed.Pillar.wall_shear_stress_from_tip_deflection_series` call these.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from dataclasses import replace as dataclasses_replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.ndimage
import scipy.optimize
from numpy.typing import NDArray

from ._core.validation import (
    as_float_array,
    check_choice,
    check_int,
    check_number,
    check_positive,
    show,
    status_messages,
)
from ._model_axes import checked_index as _checked_index
from ._warnings import ModelValidityWarning
from .dynamics import linearise_pillar, warn_dynamics_validity
from .dynamics._signals import MAX_DRIVE, si_signal

if TYPE_CHECKING:  # the Pillar's module calls this one (its methods): no import cycle
    from .pillars import Pillar

__all__ = [
    "BANDWIDTH_MIN_TOLERANCE",
    "DRAG_MODELS",
    "MIN_SERIES_SAMPLES",
    "SENSOR_STATUS",
    "SensorResponse",
    "SensorTrajectory",
    "StressSeries",
    "frequency_response",
    "simulate",
    "time_scale_and_inertia",
    "wall_shear_stress_from_tip_deflection_series",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: The drag models of the sensor's dynamics (theory.md §14): Sader's oscillating cylinder
#: above the crossover (the default), or the quasi-steady resistive force with added mass.
DRAG_MODELS = ("sader", "quasi-steady")
#: Status codes of a :class:`SensorResponse` and a :class:`StressSeries` (0 ok, positive a
#: caveat).
SENSOR_STATUS = {
    0: "ok",
    3: (
        "inaccurate: a frequency beyond the resolution of the dynamics' N = 256 (theory.md "
        "§14): the values there are not converged"
    ),
    5: (
        "the noise was estimated from the top fifth of the band, whose spectrum is not flat "
        "(its lower half holds more power than its upper half, by over 4 standard deviations "
        "of the ratio): the signal "
        "is still there, the estimate is too large and the band unreliable; give noise_sigma"
    ),
}
#: A noise band is flat where the mean spectra of its two halves (M bins each) differ by at
#: most this many of their ratio's standard deviations sqrt(2/M) (a mean of M periodogram
#: values has the relative deviation 1/sqrt(M)).
_NOISE_FLATNESS = 4.0
#: The shortest series :func:`wall_shear_stress_from_tip_deflection_series` takes.
MIN_SERIES_SAMPLES = 64
#: beta_1^4 of the cantilever (1 + cos b cosh b = 0): the scale of the internal scan.
_BETA1_4 = 1.875104068711961**4
#: The internal scan of the resonance and the bandwidth: omega/omega_1 from 1e-4 to 30.
_SCAN = np.concatenate([[0.0], np.geomspace(1e-4, 30.0, 240)])
#: Sampling times are uniform where each step is within this of the mean step (relative).
_UNIFORM_RTOL = 1e-6
#: Half-width (in frequency bins) of the moving average of the stress spectrum's estimate.
_SMOOTH_BINS = 8
#: The top fraction of the band whose mean spectrum estimates the noise (white).
_NOISE_BAND = 0.2
#: Chebyshev degrees tried for the static inverse over a series' range of deflections.
_INVERSE_DEGREES = (32, 64, 128, 256)
#: The interpolated static inverse must agree with the exact one to this (relative).
_INVERSE_RTOL = 1e-10


def _as_pillar(pillar: Any) -> Pillar:
    """``pillar`` if it is a :class:`hairbed.Pillar` (checked by its interface: the Pillar's
    module calls this one, which therefore does not import it)."""
    if type(pillar).__name__ != "Pillar" or not hasattr(pillar, "forcing_per_stress"):
        raise TypeError(f"pillar must be a hairbed.Pillar, got {type(pillar).__name__}")
    return pillar


@dataclass(frozen=True, eq=False)
class _Model:
    """The linear dynamics of one pillar about one mean stress, in SI."""

    pillar: Any
    mean_stress: float
    drag: str
    pillar_density: float
    time_scale: float  # T [s]
    inertia_number: float  # mu [-]
    tangential_mass: float
    reynolds_scale: float  # rho_f b^2/(4 eta T)
    gain_scale: float  # [m/Pa] per unit of the dimensionless forcing response
    static_gain: float  # dx/dtau_w [m/Pa] (the pillar's exact sensitivity)
    valid_below: float  # [Hz]: the Stokes layer equals the pillar's length
    status: int
    lin: Any = field(repr=False)
    #: The flow's change per unit of the forcing's, V(z) = U + (z U' - U)/2, as Chebyshev
    #: coefficients in 2 z - 1 ('wall-law'; None: the profile is fixed, V = U).
    drive_profile: FloatArray | None = field(default=None, repr=False)

    def response(self, frequency: FloatArray) -> tuple[ComplexArray, NDArray[np.int64]]:
        """H [m/Pa] at frequencies [Hz] >= 0 and the dynamics' status of each."""
        om = 2.0 * math.pi * self.time_scale * np.asarray(frequency, dtype=np.float64)
        drag = (
            (self.reynolds_scale, float(self.pillar.slenderness)) if self.drag == "sader" else None
        )
        if self.drive_profile is None:
            fr = self.lin.frequency_response(om.reshape(-1), unsteady_drag=drag)
        else:
            fr = self.lin.frequency_response(
                om.reshape(-1),
                "profile",
                unsteady_drag=drag,
                drive_profile=self.drive_profile,
            )
        h = self.gain_scale * fr.tip_deflection
        return h.reshape(np.shape(frequency)), np.asarray(fr.status).reshape(np.shape(frequency))


def _model(pillar: Any, mean_stress: Any, pillar_density: Any, drag: Any) -> _Model:
    p = _as_pillar(pillar)
    tau = check_number(mean_stress, "wall_shear_stress", unit="Pa")
    if pillar_density is None:
        raise ValueError(
            "pillar_density [kg/m^3] is needed for the pillar's inertia (PDMS: about 1e3)"
        )
    rho_s = check_positive(pillar_density, "pillar_density", "kg/m^3")
    model = check_choice(drag, "drag", DRAG_MODELS)
    if p.density is None:
        raise ValueError(
            "the pillar needs the fluid's density [kg/m^3] for its dynamics (the added mass, "
            "the Stokes layer): give Pillar(density=...) or Pillar(fluid=...)"
        )
    rho_f = float(p.density)
    eta, length, a = p.viscosity, p.length, p.radius
    zeta = p.normal_drag_coefficient
    ei = p.bending_stiffness
    t_scale = zeta * length**4 / ei
    area = math.pi * a * a
    if model == "sader":  # the fluid's added mass is in Sader's drag: the solid's mass alone
        mass, chi = rho_s * area, 1.0
    else:
        mass, chi = (rho_s + rho_f) * area, rho_s / (rho_s + rho_f)
    mu = mass / (zeta * t_scale)
    if not (math.isfinite(mu) and mu > 0.0 and chi > 0.0):
        raise ValueError(
            f"pillar_density = {show(rho_s)} kg/m^3: the inertia number mu = {mu:.4g} or the "
            f"mass ratio {chi:.4g} under- or overflows double precision"
        )
    values = (t_scale, mu, rho_f * (2.0 * a) ** 2 / (4.0 * eta * t_scale))
    if not all(math.isfinite(v) and v > 0.0 for v in values):
        raise ValueError(
            "the pillar's time scale zeta_perp L^4/(E I), inertia number or Reynolds scale "
            f"under- or overflows double precision: {values!r}"
        )
    st = p._solved(tau)  # the static state at the mean stress (a ValueError if none)
    wall = p.profile == "wall-law"
    shape = None
    if wall:
        rows, drows = p._wall_rows(np.array([tau]))
        row = rows[0]
        # Lambda U(z; L+) with Lambda ~ tau_w and q = ln L+ = ln|tau_w|/2 + const: the load's
        # change per unit stress is (Lambda/tau_w) (U + (dU/dq)/2), dU/dq = z U' - U (the
        # drive column of the linear pencil, exact; theory.md §14)
        shape = np.ascontiguousarray(row + 0.5 * drows[0])
    else:
        row = np.asarray(p._core_options[0][0])

    def prof(z: FloatArray) -> FloatArray:
        return np.asarray(np.polynomial.chebyshev.chebval(2.0 * z - 1.0, row))

    lin = linearise_pillar(st.solution, profile=prof, mu=mu, tangential_mass=chi)
    gain_scale = length * p.forcing_per_stress
    static = float(st.sensitivity)
    return _Model(
        pillar=p,
        mean_stress=tau,
        drag=model,
        pillar_density=rho_s,
        time_scale=t_scale,
        inertia_number=mu,
        tangential_mass=chi,
        reynolds_scale=values[2],
        gain_scale=gain_scale,
        static_gain=static,
        valid_below=(eta / rho_f) / (math.pi * length * length),
        status=0,
        lin=lin,
        drive_profile=shape,
    )


def _warn_validity(model: _Model, frequency: FloatArray, stacklevel: int) -> None:
    """A ModelValidityWarning where a frequency [Hz] is above the model's range."""
    top = float(np.max(frequency)) if np.size(frequency) else 0.0
    f_c = model.valid_below
    if top > f_c:
        warnings.warn(
            f"frequencies up to {top:.4g} Hz exceed nu/(pi L^2) = {f_c:.4g} Hz, above which "
            "the Stokes layer sqrt(2 nu/omega) is shorter than the pillar: there a wall-stress "
            "fluctuation no longer drives the quasi-steady profile of the model along the "
            "whole pillar (theory.md §14, D2)",
            ModelValidityWarning,
            stacklevel=stacklevel,
        )
    if model.drag == "quasi-steady":  # the dynamics' own checks (Sader's: in its response)
        warn_dynamics_validity(
            2.0 * math.pi * model.time_scale * np.asarray(frequency).reshape(-1),
            model.inertia_number,
            model.reynolds_scale,
            float(model.pillar.slenderness),
            stacklevel=stacklevel + 1,
        )


@dataclass(frozen=True)
class SensorResponse:
    """A pillar sensor's frequency response in SI (from :func:`frequency_response`).

    The tip deflection of a wall shear stress tau_w(t) = tau_mean + Re(tau_hat e^{2 pi i f t})
    is x(t) = x_mean + Re(H(f) tau_hat e^{2 pi i f t}), linearised about the static state at
    tau_mean (theory.md §14).

    The response of an array pillar of shape S (issue 32) holds S in front: ``response``,
    ``magnitude`` and ``phase`` of shape S + frequency.shape, the per-pillar numbers (static
    gain, resonance, quality factor, bandwidth, time scale, inertia number, valid_below,
    status) arrays of shape S; :meth:`item` gives one pillar's response.

    Attributes
    ----------
    frequency : ndarray
        The frequencies f [Hz].
    response : ndarray of complex
        H(f) [m/Pa].
    magnitude : ndarray
        abs(H) [m/Pa].
    phase : ndarray
        arg H [rad] (the convention e^{+i 2 pi f t}: a lag is negative).
    static_gain : float
        H(0) = d(tip deflection)/d(tau_w) [m/Pa], the pillar's exact sensitivity.
    resonance_frequency : float
        The frequency of the largest abs(H) [Hz]; NaN where abs(H) has no peak (overdamped).
    quality_factor : float
        f_res/(f_2 - f_1), f_1 < f_res < f_2 where abs(H) = abs(H(f_res))/sqrt(2) (the
        half-power width) [-]; NaN without a resonance or a lower half-power point.
    bandwidth : float
        The largest f_b [Hz] with abs(abs(H)/H(0) - 1) <= ``magnitude_tolerance`` and
        abs(arg(H/H(0))) <= ``phase_tolerance`` at every f in [0, f_b].
    magnitude_tolerance : float
        [-] (relative).
    phase_tolerance : float
        [rad].
    wall_shear_stress : float
        The mean stress tau_mean [Pa] of the linearisation.
    drag : str
        The drag model: "sader" (Sader's oscillating cylinder above the crossover Reynolds
        number 2 (a/L)^2, the quasi-steady resistive force below) or "quasi-steady"
        (the resistive force with the fluid's added mass).
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    inertia_number : float
        mu = m/(zeta_perp T) [-] (m the normal mass per length of the model).
    valid_below : float
        nu/(pi L^2) [Hz]: above it the Stokes layer sqrt(2 nu/omega) is shorter than the
        pillar (a :class:`hairbed.ModelValidityWarning`).
    status : int
        0, or 3 (a frequency beyond the resolution); ``SENSOR_STATUS``.
    """

    frequency: FloatArray
    response: ComplexArray
    magnitude: FloatArray
    phase: FloatArray
    static_gain: Any
    resonance_frequency: Any
    quality_factor: Any
    bandwidth: Any
    magnitude_tolerance: float
    phase_tolerance: float
    wall_shear_stress: float
    drag: str
    time_scale: Any
    inertia_number: Any
    valid_below: Any
    status: Any
    _model: Any = field(repr=False, compare=False)
    #: The array pillar of an array response (None for a pillar of numbers).
    pillar: Any = field(default=None, repr=False, compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """The pillar's shape: () for a pillar of numbers (issue 32)."""
        return tuple(np.shape(self.status))

    @property
    def success(self) -> Any:
        """True where status is 0 (an array of the pillar's shape for an array pillar)."""
        ok = np.asarray(self.status) == 0
        return bool(ok) if ok.ndim == 0 else ok

    @property
    def message(self) -> str | list[Any]:
        """``SENSOR_STATUS`` of ``status`` (a nested list for an array pillar)."""
        return status_messages(self.status, SENSOR_STATUS)

    def item(self, index: Any = ()) -> SensorResponse:
        """The response of the pillar at ``index`` of :attr:`shape` (as
        :meth:`hairbed.Pillar.item` indexes it); a pillar of numbers' response is itself."""
        k = _checked_index(index, self.shape, "response")
        if not self.shape:
            return self

        fields: dict[str, Any] = {n: float(np.asarray(getattr(self, n))[k]) for n in _PER_PILLAR}
        return dataclasses_replace(
            self,
            response=np.array(self.response[k]),
            magnitude=np.array(self.magnitude[k]),
            phase=np.array(self.phase[k]),
            status=int(self.status[k]),
            _model=self._model[k],
            pillar=None,
            **fields,
        )

    def at(self, frequency: Any) -> ComplexArray:
        """H(f) [m/Pa] at other frequencies f [Hz] (finite, >= 0), of their shape (behind
        the pillar's shape for an array pillar)."""
        f = _frequencies(frequency)
        if not self.shape:
            return self._model.response(f)[0]
        rows = [m.response(f)[0] for m in self._model.reshape(-1)]
        return np.stack(rows).reshape(self.shape + f.shape)

    def to_xarray(self) -> Any:
        """The response as an xarray.Dataset with the dimension ``frequency`` and CF
        attributes (H split into magnitude and phase, and real and imaginary parts: netCDF
        has no complex type). Needs the ``io`` extra. An array pillar's response has its
        axes in front, named ``pillar`` (``pillar_0``, ``pillar_1``, ... for a pillar of
        several axes), with the pillar's array parameters as coordinates and the resonance,
        quality factor, bandwidth, static gain and status as variables on them."""
        from ._optional import optional_import

        xr = optional_import("xarray", "SensorResponse.to_xarray", "io")
        if self.shape:
            return self._array_xarray(xr)
        h = self.response
        data = {
            "magnitude": (
                "frequency",
                self.magnitude,
                {"units": "m/Pa", "long_name": "tip deflection per wall shear stress, |H|"},
            ),
            "phase": (
                "frequency",
                self.phase,
                {"units": "rad", "long_name": "phase of H (exp(+i 2 pi f t))"},
            ),
            "response_real": ("frequency", h.real, {"units": "m/Pa", "long_name": "Re H"}),
            "response_imag": ("frequency", h.imag, {"units": "m/Pa", "long_name": "Im H"}),
        }
        return xr.Dataset(
            data,
            coords={
                "frequency": (
                    "frequency",
                    self.frequency,
                    {"units": "Hz", "long_name": "frequency", "standard_name": "frequency"},
                )
            },
            attrs={
                "title": "hairbed pillar sensor frequency response",
                "static_gain_m_per_Pa": self.static_gain,
                "resonance_frequency_Hz": self.resonance_frequency,
                "quality_factor": self.quality_factor,
                "bandwidth_Hz": self.bandwidth,
                "magnitude_tolerance": self.magnitude_tolerance,
                "phase_tolerance_rad": self.phase_tolerance,
                "wall_shear_stress_Pa": self.wall_shear_stress,
                "drag": self.drag,
                "time_scale_s": self.time_scale,
                "inertia_number": self.inertia_number,
                "valid_below_Hz": self.valid_below,
                "status": self.status,
                "message": self.message,
                "time_convention": "exp(+i 2 pi f t)",
                "Conventions": "CF-1.10",
            },
        )

    def _array_xarray(self, xr: Any) -> Any:
        """:meth:`to_xarray` of an array pillar's response."""
        from ._model_axes import model_coords, model_dims

        shape = self.shape
        dims = model_dims("pillar", shape)
        both = (*dims, "frequency")
        f = np.asarray(self.frequency).reshape(-1)
        h = np.asarray(self.response).reshape(shape + f.shape)

        def var(value: Any, units: str, long_name: str, on: tuple[str, ...] = both) -> Any:
            return (on, np.asarray(value), {"units": units, "long_name": long_name})

        data = {
            "magnitude": var(np.abs(h), "m/Pa", "tip deflection per wall shear stress, |H|"),
            "phase": var(np.angle(h), "rad", "phase of H (exp(+i 2 pi f t))"),
            "response_real": var(h.real, "m/Pa", "Re H"),
            "response_imag": var(h.imag, "m/Pa", "Im H"),
            "static_gain": var(self.static_gain, "m/Pa", "static gain H(0)", dims),
            "resonance_frequency": var(self.resonance_frequency, "Hz", "resonance", dims),
            "quality_factor": var(self.quality_factor, "1", "half-power quality factor", dims),
            "bandwidth": var(self.bandwidth, "Hz", "usable bandwidth", dims),
            "time_scale": var(self.time_scale, "s", "T = zeta_perp L^4/(E I)", dims),
            "inertia_number": var(self.inertia_number, "1", "inertia number mu", dims),
            "valid_below": var(self.valid_below, "Hz", "nu/(pi L^2)", dims),
            "status": var(self.status, "1", "status", dims),
        }
        coords = model_coords(self.pillar, "pillar", _PILLAR_PARAMETERS)
        coords["frequency"] = (
            "frequency",
            f,
            {"units": "Hz", "long_name": "frequency", "standard_name": "frequency"},
        )
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "title": "hairbed pillar sensor frequency response (array pillar)",
                "magnitude_tolerance": self.magnitude_tolerance,
                "phase_tolerance_rad": self.phase_tolerance,
                "wall_shear_stress_Pa": self.wall_shear_stress,
                "drag": self.drag,
                "time_convention": "exp(+i 2 pi f t)",
                "Conventions": "CF-1.10",
            },
        )


#: The fields of a :class:`SensorResponse` with one value per pillar.
_PER_PILLAR = (
    "static_gain",
    "resonance_frequency",
    "quality_factor",
    "bandwidth",
    "time_scale",
    "inertia_number",
    "valid_below",
)
#: The parameters of a Pillar that may be arrays (the coordinates of an array response).
_PILLAR_PARAMETERS = (
    "length",
    "radius",
    "youngs_modulus",
    "viscosity",
    "base_angle",
    "drag_scale",
    "channel_height",
    "density",
)


def _frequencies(frequency: Any) -> FloatArray:
    f = as_float_array(frequency, "frequency", unit="Hz")
    bad = ~((f >= 0.0) & (f <= _MAX_FREQUENCY))
    if np.any(bad):
        i = int(np.flatnonzero(bad.reshape(-1))[0])
        raise ValueError(
            f"frequency must be >= 0 and <= {_MAX_FREQUENCY:g} [Hz], got "
            f"{float(f.reshape(-1)[i])!r} (first at index {i})"
        )
    return f


#: The largest frequency taken [Hz]: far beyond any pillar's resolved dynamics (status 3),
#: and below where omega^2 overflows for any pillar's time scale.
_MAX_FREQUENCY = 1e100


def _scan(model: _Model) -> tuple[FloatArray, ComplexArray]:
    """The response on the internal grid: 0 and omega/omega_1 in [1e-4, 30], omega_1 the
    slowest rate of the straight cantilever (mu lambda^2 + lambda + beta_1^4 = 0)."""
    mu = model.inertia_number
    if mu * 4.0 * _BETA1_4 > 1.0:  # a ringing pair: |lambda| = beta_1^2/sqrt(mu)
        rate = math.sqrt(_BETA1_4 / mu)
    else:
        rate = _BETA1_4 if mu == 0.0 else (1.0 - math.sqrt(1.0 - 4.0 * mu * _BETA1_4)) / (2 * mu)
    f = _SCAN * rate / (2.0 * math.pi * model.time_scale)
    return f, model.response(f)[0]


def _abs_at(model: _Model, f: float) -> float:
    return float(abs(model.response(np.array([f]))[0][0]))


def _resonance(model: _Model, f: FloatArray, h: ComplexArray) -> tuple[float, float]:
    """(the frequency of the peak of abs(H) [Hz], the half-power quality factor)."""
    mag = np.abs(h)
    i = int(np.argmax(mag))
    if i == 0 or i == mag.size - 1 or not mag[i] > mag[0]:
        return math.nan, math.nan
    res = scipy.optimize.minimize_scalar(
        lambda x: -_abs_at(model, x),
        bounds=(float(f[i - 1]), float(f[i + 1])),
        method="bounded",
        options={"xatol": 1e-12 * float(f[i])},
    )
    f_r = float(res.x)
    peak = max(_abs_at(model, f_r), float(mag[i]))
    half = peak / math.sqrt(2.0)

    def g(x: float) -> float:
        return _abs_at(model, x) - half

    # the grid with the peak in it: a half-power point lies between a point below half and
    # its neighbour towards the peak
    below = np.flatnonzero((f < f_r) & (mag < half))
    above = np.flatnonzero((f > f_r) & (mag < half))
    if below.size == 0 or above.size == 0:
        return f_r, math.nan
    j, k = int(below[-1]), int(above[0])
    left = f[j + 1] if f[j + 1] < f_r and mag[j + 1] >= half else f_r
    right = f[k - 1] if f[k - 1] > f_r and mag[k - 1] >= half else f_r
    f1 = scipy.optimize.brentq(g, float(f[j]), float(left), xtol=1e-14 * f_r)
    f2 = scipy.optimize.brentq(g, float(right), float(f[k]), xtol=1e-14 * f_r)
    return f_r, f_r / (f2 - f1)


#: The smallest bandwidth tolerance: below, abs(H)/H(0) - 1 is rounding (and 1/tol overflows).
BANDWIDTH_MIN_TOLERANCE = 1e-12


def _bandwidth(model: _Model, f: FloatArray, h: ComplexArray, mtol: float, ptol: float) -> float:
    """The largest f_b [Hz] within both tolerances on [0, f_b] (the first crossing of the
    scan, refined by Brent's method)."""
    h0 = h[0]

    def excess(hv: ComplexArray) -> FloatArray:
        r = hv / h0
        return np.asarray(np.maximum(np.abs(np.abs(r) - 1.0) / mtol, np.abs(np.angle(r)) / ptol))

    out = excess(h) - 1.0
    over = np.flatnonzero(out > 0.0)
    if over.size == 0:
        return math.nan
    k = int(over[0])
    return float(
        scipy.optimize.brentq(
            lambda x: float(excess(model.response(np.array([x]))[0])[0]) - 1.0,
            float(f[k - 1]),
            float(f[k]),
            xtol=1e-14 * float(f[k]),
        )
    )


def frequency_response(
    pillar: Pillar,
    frequency: Any,
    *,
    wall_shear_stress: float = 0.0,
    pillar_density: float | None = None,
    drag: str = "sader",
    magnitude_tolerance: float = 0.05,
    phase_tolerance: float = math.radians(5.0),
) -> SensorResponse:
    """The tip deflection per wall shear stress of a pillar sensor against frequency, in SI.

    Linearised about the static state at the mean stress (any deflection, theory.md §14):
    H(f) = L (Lambda/tau_w) H_Lambda(2 pi f T) [m/Pa], H_Lambda the dimensionless transfer
    function from the forcing to the tip deflection (:meth:`hairbed.dynamics.LinearPillar.
    frequency_response`), T = zeta_perp L^4/(E I) [s], the inertia number
    mu = m E I/(zeta_perp^2 L^4) with the mass per length m of the drag model (module
    docstring). For the 'wall-law' profile, whose shape changes with the stress too, the
    drive is the flow's exact change per unit stress, (Lambda/tau_w) (U + (z U' - U)/2)
    (the linear pencil's "profile" drive): H = L (Lambda/tau_w) H_V(2 pi f T), exact at
    every frequency, with H(0) the pillar's exact sensitivity dx/dtau_w.

    Parameters
    ----------
    pillar : Pillar
        The sensor; it needs the fluid's ``density`` (or a ``fluid`` preset). An
        array-valued pillar (issue 32: any of its SI parameters an array, a design scan)
        gives one response with the pillar's shape in front: each element linearised about
        its own static state, bitwise the response of its :meth:`hairbed.Pillar.item`
        (:meth:`SensorResponse.item`; the elements run one after the other, the
        linearisation being per pillar).
    frequency : array_like
        Frequencies f >= 0 [Hz] (any shape).
    wall_shear_stress : float, optional
        The mean stress tau_mean [Pa] to linearise about; default 0 (the pillar at rest).
    pillar_density : float
        The pillar's density rho_s > 0 [kg/m^3] (its mass per length rho_s pi a^2).
    drag : {"sader", "quasi-steady"}, optional
        Sader's oscillating-cylinder drag above the crossover Re = 2 (a/L)^2 (default), or the
        quasi-steady resistive force with the fluid's added mass rho_f pi a^2 (theory.md §14).
    magnitude_tolerance : float, optional
        The bandwidth's tolerance on abs(H)/H(0) - 1, in [1e-12, 1) [-]; default 0.05.
    phase_tolerance : float, optional
        The bandwidth's tolerance on the phase, in [1e-12, pi) [rad]; default 5 degrees.

    Returns
    -------
    SensorResponse
        With the resonance (the peak of abs(H)), its half-power quality factor and the
        bandwidth, each found on an internal scan refined by Brent's method. For an array
        pillar of shape S: ``response`` of shape S + frequency.shape, the resonance, quality
        factor, bandwidth, static gain, time scale, inertia number and status arrays of
        shape S; :meth:`SensorResponse.to_xarray` names the axes ``pillar`` (``pillar_0``,
        ... for several) with the pillar's array parameters as coordinates.

    Warns
    -----
    ModelValidityWarning
        For frequencies above nu/(pi L^2) [Hz], where the Stokes layer sqrt(2 nu/omega) is
        shorter than the pillar: a stress fluctuation there no longer drives the
        quasi-steady profile over the whole pillar; and where the dynamics' own assumptions
        fail (:func:`hairbed.dynamics.dynamics_validity`: the quasi-steady drag there too,
        Sader's drag at a bending wavelength under 10 diameters, rotary inertia). The
        internal scan of the resonance and the bandwidth does not warn.

    Examples
    --------
    The README pillar (1 mm long, 50 um in radius, E = 1 MPa, 1000 kg/m^3) in water:

    >>> import hairbed
    >>> p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="water")
    >>> r = p.frequency_response([0.0, 0.1], pillar_density=1000.0)
    >>> round(r.static_gain * 1e6, 4), r.drag  # [um/Pa]
    (56.0213, 'sader')
    >>> round(r.resonance_frequency, 1), round(r.quality_factor, 2), round(r.bandwidth, 1)
    (206.7, 1.39, 40.7)
    """
    f = _frequencies(frequency)
    mtol = check_number(
        magnitude_tolerance,
        "magnitude_tolerance",
        low=BANDWIDTH_MIN_TOLERANCE,
        high=1.0,
        high_open=True,
    )
    ptol = check_number(
        phase_tolerance,
        "phase_tolerance",
        low=BANDWIDTH_MIN_TOLERANCE,
        high=math.pi,
        high_open=True,
        unit="rad",
    )
    p = _as_pillar(pillar)
    if p.shape:
        return _array_response(p, f, wall_shear_stress, pillar_density, drag, mtol, ptol)
    model = _model(p, wall_shear_stress, pillar_density, drag)
    _warn_validity(model, f, 3)
    return _response_of(model, f, mtol, ptol)


def _response_of(model: _Model, f: FloatArray, mtol: float, ptol: float) -> SensorResponse:
    """The response of one pillar's linear model at checked frequencies and tolerances."""
    h, status = model.response(f)  # with Sader's drag the dynamics' own checks warn here
    with warnings.catch_warnings():  # the internal scan's frequencies are not the user's
        warnings.simplefilter("ignore", ModelValidityWarning)
        fs, hs = _scan(model)
        f_r, q = _resonance(model, fs, hs)
        bw = _bandwidth(model, fs, hs, mtol, ptol)
    code = 3 if np.any(status == 3) else model.status
    return SensorResponse(
        frequency=f,
        response=h,
        magnitude=np.abs(h),
        phase=np.angle(h),
        static_gain=model.static_gain,
        resonance_frequency=f_r,
        quality_factor=q,
        bandwidth=bw,
        magnitude_tolerance=mtol,
        phase_tolerance=ptol,
        wall_shear_stress=model.mean_stress,
        drag=model.drag,
        time_scale=model.time_scale,
        inertia_number=model.inertia_number,
        valid_below=model.valid_below,
        status=int(code),
        _model=model,
    )


def _array_response(
    p: Any, f: FloatArray, tau: Any, rho_s: Any, drag: Any, mtol: float, ptol: float
) -> SensorResponse:
    """:func:`frequency_response` of an array pillar (issue 32): each element's linear
    model about its own static state and its response, resonance and bandwidth, as the
    pillar of numbers computes them (so each element is bitwise its
    :meth:`hairbed.Pillar.item`'s), stacked behind the pillar's shape. The linearisation
    (a QZ or an LU per frequency of each element's own pencil) is per element: the elements
    run one after the other, the warnings of their runs re-issued once per kind."""
    from ._model_axes import element_index, reissue

    shape = tuple(p.shape)
    # the arguments shared by every element, checked once (their errors name no element)
    check_number(tau, "wall_shear_stress", unit="Pa")
    if rho_s is not None:
        check_positive(rho_s, "pillar_density", "kg/m^3")
    check_choice(drag, "drag", DRAG_MODELS)
    runs: list[SensorResponse] = []
    records: list[list[warnings.WarningMessage]] = []
    for k, el in enumerate(p._elements()):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                model = _model(el, tau, rho_s, drag)
            except ValueError as exc:
                raise ValueError(f"{exc} (pillar {element_index(k, shape)})") from None
            _warn_validity(model, f, 3)
            runs.append(_response_of(model, f, mtol, ptol))
        records.append(list(caught))
    reissue(records, shape, "pillar", 3)
    first = runs[0]

    def stacked(name: str, dtype: Any = np.float64) -> Any:
        rows = np.array([getattr(r, name) for r in runs], dtype=dtype)
        return rows.reshape(shape + rows.shape[1:])

    models = np.empty(len(runs), dtype=object)
    models[:] = [r._model for r in runs]
    return SensorResponse(
        frequency=f,
        response=stacked("response", np.complex128),
        magnitude=stacked("magnitude"),
        phase=stacked("phase"),
        static_gain=stacked("static_gain"),
        resonance_frequency=stacked("resonance_frequency"),
        quality_factor=stacked("quality_factor"),
        bandwidth=stacked("bandwidth"),
        magnitude_tolerance=mtol,
        phase_tolerance=ptol,
        wall_shear_stress=first.wall_shear_stress,
        drag=first.drag,
        time_scale=stacked("time_scale"),
        inertia_number=stacked("inertia_number"),
        valid_below=stacked("valid_below"),
        status=stacked("status", np.int64),
        _model=models.reshape(shape),
        pillar=p,
    )


# -- from a deflection series to the stress series ----------------------------------------------


@dataclass(frozen=True)
class StressSeries:
    """A wall-shear-stress series recovered from a tip-deflection series (from
    :func:`wall_shear_stress_from_tip_deflection_series`).

    Attributes
    ----------
    time : ndarray
        The sampling times [s] (from 0, or the ``times`` given).
    wall_shear_stress : ndarray
        tau_w(t) [Pa].
    wall_shear_stress_sigma : ndarray
        Its 1-sigma band [Pa]: the Wiener filter's mean-square error (noise and the part of
        the signal it suppresses), through the local slope of the calibration.
    quasi_static_deflection : ndarray
        The deflection the pillar would have without dynamics [m] (the deconvolved series).
    tip_deflection : ndarray
        The measured series [m].
    mean_wall_shear_stress : float
        The exact static inverse of the mean deflection [Pa].
    frequency : ndarray
        The frequencies of the spectra [Hz] (0 to the Nyquist frequency).
    stress_spectrum : ndarray
        The one-sided power spectral density of the stress fluctuation [Pa^2/Hz], corrected by
        the transfer function: (P_x - N)/abs(H)^2, smoothed, >= 0.
    deflection_spectrum : ndarray
        The measured one-sided PSD P_x of the deflection fluctuation [m^2/Hz] (smoothed).
    noise_spectrum : float
        The (white) noise's one-sided PSD N = 2 sigma^2/f_s [m^2/Hz].
    wiener_gain : ndarray
        abs(W H) [-]: the fraction of the stress passed at each frequency (1: all, 0: none).
    noise_sigma : float
        The deflection noise's standard deviation [m] (given or estimated).
    noise_estimated : bool
        True where ``noise_sigma`` was estimated from the top fifth of the band.
    sample_rate : float
        f_s [Hz].
    response : SensorResponse
        The linear response about the mean (its resonance, bandwidth, drag model).
    status : int
        ``SENSOR_STATUS``: the response's, or 5 where an estimated noise is not flat.
    """

    time: FloatArray
    wall_shear_stress: FloatArray
    wall_shear_stress_sigma: FloatArray
    quasi_static_deflection: FloatArray
    tip_deflection: FloatArray
    mean_wall_shear_stress: float
    frequency: FloatArray
    stress_spectrum: FloatArray
    deflection_spectrum: FloatArray
    noise_spectrum: float
    wiener_gain: FloatArray
    noise_sigma: float
    noise_estimated: bool
    sample_rate: float
    response: SensorResponse = field(repr=False)
    status: int = 0

    @property
    def success(self) -> bool:
        """True where status is 0."""
        return self.status == 0

    @property
    def message(self) -> str:
        """``SENSOR_STATUS`` of ``status``."""
        return SENSOR_STATUS[self.status]

    def to_xarray(self) -> Any:
        """The series (dimension ``time``) and the spectra (dimension ``frequency``) as an
        xarray.Dataset with CF attributes. Needs the ``io`` extra."""
        from ._optional import optional_import

        xr = optional_import("xarray", "StressSeries.to_xarray", "io")
        return xr.Dataset(
            {
                "wall_shear_stress": (
                    "time",
                    self.wall_shear_stress,
                    {"units": "Pa", "long_name": "wall shear stress"},
                ),
                "wall_shear_stress_sigma": (
                    "time",
                    self.wall_shear_stress_sigma,
                    {"units": "Pa", "long_name": "1-sigma uncertainty of the wall shear stress"},
                ),
                "quasi_static_deflection": (
                    "time",
                    self.quasi_static_deflection,
                    {"units": "m", "long_name": "deconvolved (quasi-static) tip deflection"},
                ),
                "tip_deflection": (
                    "time",
                    self.tip_deflection,
                    {"units": "m", "long_name": "measured tip deflection"},
                ),
                "stress_spectrum": (
                    "frequency",
                    self.stress_spectrum,
                    {"units": "Pa2 Hz-1", "long_name": "one-sided PSD of the stress fluctuation"},
                ),
                "deflection_spectrum": (
                    "frequency",
                    self.deflection_spectrum,
                    {"units": "m2 Hz-1", "long_name": "one-sided PSD of the deflection"},
                ),
                "wiener_gain": (
                    "frequency",
                    self.wiener_gain,
                    {"units": "1", "long_name": "|W H|, the fraction of the stress passed"},
                ),
            },
            coords={
                "time": ("time", self.time, {"units": "s", "long_name": "time"}),
                "frequency": (
                    "frequency",
                    self.frequency,
                    {"units": "Hz", "long_name": "frequency"},
                ),
            },
            attrs={
                "title": "hairbed wall shear stress from a tip-deflection series",
                "mean_wall_shear_stress_Pa": self.mean_wall_shear_stress,
                "noise_sigma_m": self.noise_sigma,
                "noise_estimated": int(self.noise_estimated),
                "noise_spectrum_m2_per_Hz": self.noise_spectrum,
                "sample_rate_Hz": self.sample_rate,
                "drag": self.response.drag,
                "resonance_frequency_Hz": self.response.resonance_frequency,
                "bandwidth_Hz": self.response.bandwidth,
                "status": self.status,
                "message": self.message,
                "Conventions": "CF-1.10",
            },
        )


#: The largest noise_sigma taken [m] (its square, times the series' length, stays finite).
_MAX_NOISE = 1e100


def _series(deflection: Any, sample_rate: Any, times: Any) -> tuple[FloatArray, float, FloatArray]:
    """(the checked series [m], f_s [Hz], the times [s]); a clear error for NaN, a short
    series, or times that are not uniform (a gap, jitter)."""
    d = as_float_array(deflection, "tip_deflection", unit="m")
    if d.ndim != 1:
        raise ValueError(f"tip_deflection must be a 1-D series, got shape {d.shape}")
    n = d.size
    if n < MIN_SERIES_SAMPLES:
        raise ValueError(
            f"tip_deflection must hold at least {MIN_SERIES_SAMPLES} samples, got {n}"
        )
    if (sample_rate is None) == (times is None):
        raise TypeError("give exactly one of sample_rate [Hz] and times [s]")
    if times is None:
        fs = check_number(sample_rate, "sample_rate", low=1e-100, high=_MAX_FREQUENCY, unit="Hz")
        return d, fs, np.arange(n) / fs
    t = as_float_array(times, "times", unit="s")
    if t.shape != d.shape:
        raise ValueError(f"times must have the shape of tip_deflection {d.shape}, got {t.shape}")
    step = np.diff(t)
    if not np.all(step > 0.0):
        i = int(np.flatnonzero(~(step > 0.0))[0])
        raise ValueError(
            f"times must increase strictly, got {float(t[i + 1])!r} s after {float(t[i])!r} s "
            f"(index {i + 1})"
        )
    dt = float(np.median(step))
    off = np.abs(step - dt) > _UNIFORM_RTOL * dt
    if np.any(off):
        i = int(np.flatnonzero(off)[0])
        raise ValueError(
            f"times must be uniformly sampled: the step from index {i} to {i + 1} is "
            f"{float(step[i])!r} s against the median {dt!r} s (a gap or jitter beyond "
            f"{_UNIFORM_RTOL:g} relative); resample the series to a uniform rate first"
        )
    return d, (n - 1) / float(t[-1] - t[0]), t


def _static_inverse(pillar: Any, x: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(tau_w [Pa], dtau_w/dx [Pa/m]) at deflections x [m]: the exact inverse of the
    calibration curve at Chebyshev points over x's range, interpolated (checked against the
    exact inverse to ``_INVERSE_RTOL`` between the points; else the exact inverse at every
    sample)."""
    lo, hi = float(np.min(x)), float(np.max(x))
    if hi - lo <= 1e-12 * max(abs(hi), abs(lo), pillar.length * 1e-12):
        tau = pillar._invert(pillar._deflection(x, "the deconvolved deflection"))[0]
        slope = 1.0 / float(pillar.sensitivity(float(np.mean(tau))))
        return np.asarray(tau), np.full(x.shape, slope)
    mid, half = 0.5 * (hi + lo), 0.5 * (hi - lo)
    cheb = np.polynomial.chebyshev
    for deg in _INVERSE_DEGREES:
        nodes = np.cos(np.pi * np.arange(deg + 1) / deg)
        xs = mid + half * nodes
        tau_nodes = pillar._invert(pillar._deflection(xs, "the deconvolved deflection"))[0]
        coefs = cheb.chebfit(nodes, tau_nodes, deg)
        check = np.cos(np.pi * (np.arange(deg) + 0.5) / deg)[:: max(1, deg // 16)]
        exact = pillar._invert(mid + half * check)[0]
        err = np.max(np.abs(cheb.chebval(check, coefs) - exact))
        if err <= _INVERSE_RTOL * max(float(np.max(np.abs(tau_nodes))), 1e-300):
            u = (x - mid) / half
            return (
                np.asarray(cheb.chebval(u, coefs)),
                np.asarray(cheb.chebval(u, cheb.chebder(coefs)) / half),
            )
    tau = pillar._invert(x)[0]  # not smooth enough to interpolate: every sample exactly
    return np.asarray(tau), np.asarray(1.0 / np.asarray(pillar.sensitivity(tau)))


def wall_shear_stress_from_tip_deflection_series(
    pillar: Pillar,
    tip_deflection: Any,
    sample_rate: float | None = None,
    *,
    times: Any = None,
    noise_sigma: float | None = None,
    pillar_density: float | None = None,
    drag: str = "sader",
    smoothing: int = _SMOOTH_BINS,
) -> StressSeries:
    """The wall-shear-stress series tau_w(t) [Pa] of a measured tip-deflection series x(t).

    The sensor is taken as its static calibration curve x = X(tau_w) (exact, nonlinear)
    followed by its linear dynamics about the mean, normalised to a unit static gain,
    G(f) = H(f)/H(0) (:func:`frequency_response` at the mean stress). Then, with the series
    mean-free, x' = x - mean(x), and its discrete Fourier transform X'_k at f_k = k f_s/n:

    1. the mean stress is the exact static inverse of mean(x);
    2. the quasi-static deflection is q = mean(x) + IDFT[H(0) W_k X'_k], with the Wiener
       filter W = H^* S/(abs(H)^2 S + N) = H^*/(abs(H)^2 + N/S) (the linear inverse of the
       dynamics, regularised where the noise N exceeds the signal); S_k, the stress
       fluctuation's spectrum, is estimated as (abs(X'_k)^2 - N_k)/abs(H_k)^2 averaged over
       2 ``smoothing`` + 1 neighbouring frequencies (>= 0), N_k = n sigma^2 for white noise;
    3. tau_w(t) = X^-1(q(t)), the exact static inverse (interpolated to 1e-10 over q's
       range between exact inverses).

    The 1-sigma band is the Wiener filter's mean-square error: per frequency
    E_k = S_k N_k/(abs(H_k)^2 S_k + N_k) (the noise passed and the signal suppressed), summed
    over the frequencies (Parseval, with the mean's sigma^2/(n H(0)^2)) and carried through
    the local slope dX^-1/dx. The series is taken as periodic (a discrete Fourier transform):
    within a few response times of its ends the join adds an error the band does not hold.

    Parameters
    ----------
    pillar : Pillar
        The sensor (with the fluid's density or a ``fluid`` preset).
    tip_deflection : array_like
        The measured tip deflections x [m], 1-D, at least ``MIN_SERIES_SAMPLES``, finite, in
        (-L, L).
    sample_rate : float, optional
        f_s [Hz], in [1e-100, 1e100]; or instead ``times``.
    times : array_like, optional
        The sampling times [s], strictly increasing and uniform to 1e-6 relative (a gap or
        jitter is refused: resample first).
    noise_sigma : float, optional
        The measurement noise's standard deviation [m] (white), in [0, 1e100]. Default:
        estimated from the mean spectrum of the top fifth of the band (which must then be
        noise: the sensor's response has fallen below the noise there; where that band's
        spectrum is not flat, status 5 says so).
    pillar_density : float
        The pillar's density [kg/m^3].
    drag : {"sader", "quasi-steady"}, optional
        The drag model of the dynamics (:func:`frequency_response`).
    smoothing : int, optional
        The half-width in frequency bins of the spectrum's moving average (>= 1); default 8.

    Returns
    -------
    StressSeries

    Raises
    ------
    ValueError
        NaN or infinity (naming the first index), a series shorter than
        ``MIN_SERIES_SAMPLES``, non-uniform or non-increasing times, a deflection outside
        (-L, L), a negative noise_sigma, or no static state at the mean deflection.
    """
    d, fs, t = _series(tip_deflection, sample_rate, times)
    p = _as_pillar(pillar)
    d = p._deflection(d)
    m = check_int(smoothing, "smoothing", 1, d.size // 4)
    n = d.size
    mean = float(np.mean(d))
    tau_mean = float(p._invert(np.array([mean]), "the mean of tip_deflection")[0][0])
    freq = np.asarray(np.fft.rfftfreq(n, 1.0 / fs), dtype=np.float64)
    resp = frequency_response(
        p, freq, wall_shear_stress=tau_mean, pillar_density=pillar_density, drag=drag
    )
    h = resp.response
    h0 = float(h[0].real)
    xk = np.fft.rfft(d - mean)
    power = np.abs(xk) ** 2
    if noise_sigma is None:
        top = freq >= (1.0 - _NOISE_BAND) * freq[-1]
        noise_var = float(np.mean(power[top])) / n
        estimated = True
        half = np.array_split(power[top], 2)
        spread = _NOISE_FLATNESS * math.sqrt(2.0 / max(1, half[1].size))
        flat = float(np.mean(half[0])) <= (1.0 + spread) * float(np.mean(half[1]))
    else:
        sig = check_number(noise_sigma, "noise_sigma", low=0.0, high=_MAX_NOISE, unit="m")
        noise_var = sig * sig
        estimated, flat = False, True
    nk = n * noise_var
    h2 = np.abs(h) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        raw = np.where(h2 > 0.0, (power - nk) / h2, 0.0)
    raw[0] = 0.0
    s = np.maximum(scipy.ndimage.uniform_filter1d(raw, 2 * m + 1, mode="nearest"), 0.0)
    s[0] = 0.0
    den = h2 * s + nk
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(den > 0.0, np.conj(h) * s / den, 0.0)
        err = np.where(den > 0.0, s * nk / den, 0.0)
    err[0] = nk / (h0 * h0) if h0 != 0.0 else 0.0  # the mean's own noise
    weight = np.full(freq.size, 2.0)
    weight[0] = 1.0
    if n % 2 == 0:
        weight[-1] = 1.0
    var_tau = float(np.sum(weight * err)) / (n * n)
    q = mean + np.fft.irfft(h0 * w * xk, n)
    try:
        tau, slope = _static_inverse(p, q)
    except ValueError as exc:  # the inverse of the dynamics blew the series up
        how = "estimated" if estimated else "given"
        raise ValueError(
            f"{exc}: the series changes faster than the sensor can follow at sample_rate = "
            f"{show(fs)} Hz, pillar_density = {show(resp._model.pillar_density)} kg/m^3 and "
            f"noise_sigma = {show(math.sqrt(noise_var))} m ({how}), so undoing its dynamics "
            "amplifies the series beyond the pillar's length: check sample_rate and "
            "pillar_density, or give a larger noise_sigma"
        ) from None
    sigma = math.sqrt(var_tau) * abs(h0) * np.abs(slope)
    scale = 2.0 / (n * fs)
    psd_x = scipy.ndimage.uniform_filter1d(power, 2 * m + 1, mode="nearest") * scale
    return StressSeries(
        time=t,
        wall_shear_stress=np.asarray(tau, dtype=np.float64),
        wall_shear_stress_sigma=np.asarray(sigma, dtype=np.float64),
        quasi_static_deflection=q,
        tip_deflection=d,
        mean_wall_shear_stress=tau_mean,
        frequency=freq,
        stress_spectrum=s * scale,
        deflection_spectrum=psd_x,
        noise_spectrum=2.0 * noise_var / fs,
        wiener_gain=np.abs(w * h),
        noise_sigma=math.sqrt(noise_var),
        noise_estimated=estimated,
        sample_rate=fs,
        response=resp,
        status=resp.status if flat else 5,
    )


# -- the pillar in time: the nonlinear simulation in SI -----------------------------------------


@dataclass(frozen=True)
class SensorTrajectory:
    """A pillar's motion under a wall-shear-stress drive, in SI (from :func:`simulate`).

    The nonlinear model in time (:func:`hairbed.dynamics.simulate_pillar`, theory.md §14)
    with the quasi-steady resistive-force drag and the fluid's added mass on normal motion,
    mapped to SI: t = T t', T = zeta_perp L^4/(E I); tau_w = Lambda/(Lambda/tau_w); lengths
    L x; the base moment E I theta'(0)/L.

    The run of an array pillar of shape S (issue 32) holds S in front of every series
    (time,) or (time, node) and of the arc length; ``time_scale``, ``inertia_number``,
    ``status``, ``t_end`` and ``trajectory`` (an object array of the dimensionless runs) are
    of shape S; :meth:`item` gives one pillar's run.

    Attributes
    ----------
    time : ndarray
        The output times [s]. Past an event or a failure (``t_end``) the values are NaN.
    wall_shear_stress : ndarray
        The drive tau_w(t) [Pa] at the times (as the integrator evaluates it).
    tip_deflection, tip_height : ndarray
        x(L, t), z(L, t) [m].
    tip_angle : ndarray
        theta(L, t) [rad].
    base_moment : ndarray
        E I theta_s(0, t) [N m].
    arc_length : ndarray
        The collocation nodes s [m] (0 to L).
    angle : ndarray
        theta [rad] at the nodes, (time, node).
    x, z : ndarray
        The pillar's shape [m] at the nodes, (time, node).
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    inertia_number : float
        mu = m/(zeta_perp T) [-], m = (rho_s + rho_f) pi a^2 (0 when ``overdamped``).
    pillar_density : float
        rho_s [kg/m^3] (NaN when ``overdamped``).
    status : int
        The integrator's code: 0 reached the last time, -8 the pillar reached the wall,
        -2 the step limit, -3 a step-size underflow (:data:`hairbed.dynamics.
        TRAJECTORY_STATUS`).
    t_end : float
        Where the integration ended [s].
    trajectory : hairbed.dynamics.PillarTrajectory
        The dimensionless run (time in T, lengths in L).
    """

    time: FloatArray
    wall_shear_stress: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    tip_angle: FloatArray
    base_moment: FloatArray
    arc_length: FloatArray
    angle: FloatArray
    x: FloatArray
    z: FloatArray
    time_scale: float
    inertia_number: float
    pillar_density: float
    status: Any
    t_end: Any
    trajectory: Any = field(repr=False, compare=False)
    #: The array pillar of an array run (None for a pillar of numbers).
    pillar: Any = field(default=None, repr=False, compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """The pillar's shape: () for a pillar of numbers (issue 32)."""
        return tuple(np.shape(self.status))

    @property
    def success(self) -> Any:
        """True where the run reached its last time (status 0); an array of the pillar's
        shape for an array pillar."""
        ok = np.asarray(self.status) == 0
        return bool(ok) if ok.ndim == 0 else ok

    @property
    def message(self) -> str | list[Any]:
        """The status's message (a nested list for an array pillar)."""
        if not self.shape:
            return str(self.trajectory.message)
        return np.vectorize(lambda r: str(r.message), otypes=[object])(self.trajectory).tolist()

    def item(self, index: Any = ()) -> SensorTrajectory:
        """The run of the pillar at ``index`` of :attr:`shape` (as :meth:`hairbed.Pillar.item`
        indexes it); a pillar of numbers' run is itself."""
        k = _checked_index(index, self.shape, "run")
        if not self.shape:
            return self
        per = ("time_scale", "inertia_number", "t_end")
        fields: dict[str, Any] = {n: float(np.asarray(getattr(self, n))[k]) for n in per}
        arrays: dict[str, Any] = {n: np.array(getattr(self, n)[k]) for n in _RUN_SERIES}
        return dataclasses_replace(
            self,
            status=int(self.status[k]),
            trajectory=self.trajectory[k],
            pillar=None,
            **fields,
            **arrays,
        )

    def to_xarray(self) -> Any:
        """The motion as an xarray.Dataset with the dimensions ``time`` (and ``node`` for the
        shape), CF attributes. Needs the ``io`` extra. An array pillar's run has its axes in
        front, named ``pillar`` (``pillar_0``, ... for several), with the pillar's array
        parameters as coordinates and each element's time scale, inertia number, status and
        end as variables on them."""
        from ._optional import optional_import

        xr = optional_import("xarray", "SensorTrajectory.to_xarray", "io")
        if self.shape:
            return self._array_xarray(xr)
        t2 = ("time", "node")
        data = {
            "wall_shear_stress": (
                "time",
                self.wall_shear_stress,
                {"units": "Pa", "long_name": "wall shear stress (the drive)"},
            ),
            "tip_deflection": (
                "time",
                self.tip_deflection,
                {"units": "m", "long_name": "tip deflection (streamwise)"},
            ),
            "tip_height": ("time", self.tip_height, {"units": "m", "long_name": "tip height"}),
            "tip_angle": ("time", self.tip_angle, {"units": "rad", "long_name": "tip angle"}),
            "base_moment": (
                "time",
                self.base_moment,
                {"units": "N m", "long_name": "bending moment at the base"},
            ),
            "angle": (t2, self.angle, {"units": "rad", "long_name": "tangent angle"}),
            "x": (t2, self.x, {"units": "m", "long_name": "streamwise position of the pillar"}),
            "z": (t2, self.z, {"units": "m", "long_name": "height of the pillar"}),
        }
        return xr.Dataset(
            data,
            coords={
                "time": (
                    "time",
                    self.time,
                    {"units": "s", "long_name": "time", "standard_name": "time"},
                ),
                "arc_length": (
                    "node",
                    self.arc_length,
                    {"units": "m", "long_name": "arc length from the base"},
                ),
            },
            attrs={
                "title": "hairbed pillar sensor in time",
                "time_scale_s": self.time_scale,
                "inertia_number": self.inertia_number,
                "pillar_density_kg_per_m3": self.pillar_density,
                "drag": "quasi-steady",
                "status": self.status,
                "message": self.message,
                "t_end_s": self.t_end,
                "Conventions": "CF-1.10",
            },
        )

    def _array_xarray(self, xr: Any) -> Any:
        """:meth:`to_xarray` of an array pillar's run."""
        from ._model_axes import model_coords, model_dims

        dims = model_dims("pillar", self.shape)
        t1, t2 = (*dims, "time"), (*dims, "time", "node")

        def var(value: Any, on: tuple[str, ...], units: str, long_name: str) -> Any:
            return (on, np.asarray(value), {"units": units, "long_name": long_name})

        data = {
            "wall_shear_stress": var(self.wall_shear_stress, t1, "Pa",
                                     "wall shear stress (the drive)"),
            "tip_deflection": var(self.tip_deflection, t1, "m", "tip deflection (streamwise)"),
            "tip_height": var(self.tip_height, t1, "m", "tip height"),
            "tip_angle": var(self.tip_angle, t1, "rad", "tip angle"),
            "base_moment": var(self.base_moment, t1, "N m", "bending moment at the base"),
            "angle": var(self.angle, t2, "rad", "tangent angle"),
            "x": var(self.x, t2, "m", "streamwise position of the pillar"),
            "z": var(self.z, t2, "m", "height of the pillar"),
            "time_scale": var(self.time_scale, dims, "s", "T = zeta_perp L^4/(E I)"),
            "inertia_number": var(self.inertia_number, dims, "1", "inertia number mu"),
            "status": var(self.status, dims, "1", "status"),
            "t_end": var(self.t_end, dims, "s", "end of the run"),
        }  # fmt: skip
        coords = model_coords(self.pillar, "pillar", _PILLAR_PARAMETERS)
        coords["time"] = (
            "time",
            self.time,
            {"units": "s", "long_name": "time", "standard_name": "time"},
        )
        coords["arc_length"] = (
            (*dims, "node"),
            self.arc_length,
            {"units": "m", "long_name": "arc length from the base"},
        )
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "title": "hairbed pillar sensor in time (array pillar)",
                "pillar_density_kg_per_m3": self.pillar_density,
                "drag": "quasi-steady",
                "Conventions": "CF-1.10",
            },
        )  # fmt: skip


#: The series of a :class:`SensorTrajectory` (one row per pillar of an array run).
_RUN_SERIES = ("wall_shear_stress", "tip_deflection", "tip_height", "tip_angle",
               "base_moment", "arc_length", "angle", "x", "z")  # fmt: skip


def _si_drive(drive: Any, t: FloatArray, t_scale: float, per_stress: float) -> Any:
    """The dimensionless Lambda(t') of an SI drive tau_w(t) [Pa], t [s]."""
    return si_signal(drive, "wall_shear_stress", "Pa", per_stress, t, t_scale, MAX_DRIVE,
                     "this pillar", "the forcing (Lambda/tau_w) tau_w")  # fmt: skip


def time_scale_and_inertia(
    pillar: Pillar, pillar_density: float | None = None, *, overdamped: bool = False
) -> tuple[float, float, float]:
    """(T [s], mu [-], chi [-]) of :func:`simulate`: the elastoviscous time
    T = zeta_perp L^4/(E I), the inertia number mu = (rho_s + rho_f) pi a^2/(zeta_perp T)
    and the tangential-to-normal mass ratio chi = rho_s/(rho_s + rho_f) of the quasi-steady
    drag with the fluid's added mass; (T, 0, 1) when ``overdamped``.

    Raises
    ------
    ValueError
        A missing or non-positive pillar_density [kg/m^3], a pillar without the fluid's
        density, or a time scale that under- or overflows.
    """
    p = _as_pillar(pillar)
    if not isinstance(overdamped, (bool, np.bool_)):
        raise TypeError(f"overdamped must be True or False, got {show(overdamped)}")
    zeta = p.normal_drag_coefficient
    t_scale = zeta * p.length**4 / p.bending_stiffness
    if not (math.isfinite(t_scale) and t_scale > 0.0):
        raise ValueError(
            f"the pillar's time scale zeta_perp L^4/(E I) = {t_scale!r} s under- or overflows"
        )
    if overdamped:
        return t_scale, 0.0, 1.0
    if pillar_density is None:
        raise ValueError(
            "pillar_density [kg/m^3] is needed for the pillar's inertia (PDMS: about 970), "
            "or overdamped=True to neglect it"
        )
    rho_s = check_positive(pillar_density, "pillar_density", "kg/m^3")
    if p.density is None:
        raise ValueError(
            "the pillar needs the fluid's density [kg/m^3] for its added mass: give "
            "Pillar(density=...) or Pillar(fluid=...), or overdamped=True"
        )
    rho_f = float(p.density)
    per_density = math.pi * p.radius**2 / (zeta * t_scale)  # (no overflow of rho pi first)
    mu = (rho_s + rho_f) * per_density
    if not rho_s / (rho_s + rho_f) > 0.0:
        raise ValueError(
            f"pillar_density = {show(pillar_density)} kg/m^3 is too small against the fluid's "
            f"{rho_f:g} kg/m^3: the mass ratio rho_s/(rho_s + rho_f) underflows to 0"
        )
    if not math.isfinite(mu):
        raise ValueError(
            f"pillar_density must be below {np.finfo(np.float64).max / per_density:.4g} "
            f"kg/m^3 for this pillar (the inertia number overflows), got {show(pillar_density)}"
        )
    return t_scale, mu, rho_s / (rho_s + rho_f)


def simulate(
    pillar: Pillar,
    wall_shear_stress: Any,
    t: Any,
    *,
    pillar_density: float | None = None,
    overdamped: bool = False,
    num: int = 12,
    rtol: float = 1e-6,
    atol: float = 1e-7,
    max_steps: int = 100_000,
    workers: int = 1,
) -> SensorTrajectory:
    """A pillar sensor's nonlinear motion under a wall-shear-stress drive tau_w(t), in SI.

    :func:`hairbed.dynamics.simulate_pillar` (the planar inextensible rod with the
    quasi-steady resistive-force drag of the pillar's profile, theory.md §14) in the units

        T = zeta_perp L^4/(E I) [s],  Lambda = (Lambda/tau_w) tau_w,
        mu = (rho_s + rho_f) pi a^2/(zeta_perp T),  chi = rho_s/(rho_s + rho_f)

    (the fluid's added mass acts on normal motion only), and back: lengths L x [m], the base
    moment E I theta_s(0)/L [N m]. The pillar starts at rest in the static state of the drive
    just before t[0] (a number: at rest in still fluid, the step at t[0]). The pillar's
    validity checks (its Reynolds number, its height in wall units; theory.md §12) run on the
    static state at the run's largest stress, each a :class:`hairbed.ModelValidityWarning`.

    Parameters
    ----------
    pillar : Pillar
        The sensor; its fluid's density is needed for the inertia (``density=`` or ``fluid=``)
        unless ``overdamped``. Its profile must not be 'wall-law' (whose shape changes with
        tau_w(t)).
    wall_shear_stress : number, Signal or callable
        tau_w(t) [Pa]: a number (a step from rest at t[0]); a :mod:`hairbed.dynamics` signal
        given in SI (``step(after, before, at)``, ``ramp``, ``sine(mean, amplitude, omega,
        phase)``, ``pulses``, ``sampled``: times [s], stresses [Pa], omega [rad/s]); or a
        callable tau_w(t) [Pa] of an ndarray of times [s] (sampled at
        ``hairbed.dynamics.CALLABLE_SAMPLES`` uniform times of the run). Its magnitude at
        most 1e100/(Lambda/tau_w) [Pa] (the dynamics' bound on the forcing).
    t : array_like
        The output times [s], finite and non-decreasing.
    pillar_density : float
        rho_s [kg/m^3] (PDMS: about 970); not needed when ``overdamped``.
    overdamped : bool, optional
        Neglect all inertia (mu = 0): the elastoviscous relaxation alone.
    num : int, optional
        The Chebyshev degree N in [4, 128]. The default 12 with rtol 1e-6, atol 1e-7: a sharp
        step with inertia strikes every resolved mode, and in the quasi-steady drag every
        ringing mode decays at the same rate 1/(2 mu T), so the work grows fast with N
        (the PDMS pillar in water, a step to 1 Pa: N = 12 takes about 15,000 steps to
        t = 490 T and ends 4e-14 L from the static state; N = 16 at rtol 1e-8 exceeds
        100,000). A smooth drive (``ramp``, ``sine``, a callable) allows larger N.
    rtol, atol : float, optional
        The integrator's tolerances on the angles [rad] (and rates).
    max_steps : int, optional
        The most steps (status -2 beyond).
    workers : int, optional
        Threads in [1, 64] for the runs of an array pillar (default 1; the compiled
        integrator releases the GIL).

    Returns
    -------
    SensorTrajectory
        For an array pillar of shape S (issue 32: a design scan), one run with S in front
        of every series (``tip_deflection`` of shape S + (time,), ``angle``, ``x``, ``z`` S
        + (time, node)) and ``time_scale``, ``inertia_number``, ``status``, ``t_end`` of
        shape S: each element bitwise the run of its :meth:`hairbed.Pillar.item`
        (:meth:`SensorTrajectory.item`), the runs shared out over ``workers`` threads.

    Raises
    ------
    ValueError
        A missing pillar_density or fluid density, a 'wall-law' pillar, bad times, or a drive
        that cannot be evaluated (naming the parameter).

    Examples
    --------
    >>> import numpy as np, hairbed
    >>> p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, viscosity=1.0,
    ...                    density=1260.0)  # a glycerol-like fluid
    >>> run = p.simulate(1.0, np.linspace(0.0, 2.0, 5), overdamped=True)
    >>> round(run.time_scale, 4), run.status  # T [s]: settled after 2 s
    (0.6111, 0)
    >>> round(float(run.tip_deflection[-1] / p.deform(1.0).tip_deflection), 8)  # N = 12
    1.0
    """
    p = _as_pillar(pillar)
    if p.profile == "wall-law":
        raise ValueError(
            "simulate() does not take a 'wall-law' pillar: the law of the wall changes its "
            "shape with tau_w(t), which the dynamics' fixed profile U(z) cannot follow; use "
            "'sublayer' (or frequency_response, which linearises the wall law)"
        )
    tt = as_float_array(t, "t", unit="s").reshape(-1)
    if tt.size == 0:
        raise ValueError("t must hold at least one time [s]")
    max_steps = check_int(max_steps, "max_steps", 1, 10**9)
    back = np.flatnonzero(np.diff(tt) < 0.0)
    if back.size:
        i = int(back[0]) + 1
        raise ValueError(f"t must not decrease [s]; t[{i}] = {show(float(tt[i]))} is earlier")
    workers = check_int(workers, "workers", 1, 64)
    if p.shape:
        return _array_simulate(p, wall_shear_stress, tt, pillar_density, overdamped, num,
                               rtol, atol, max_steps, workers)  # fmt: skip
    t_scale, mu, chi, t_dim, lam = _run_inputs(p, wall_shear_stress, tt, pillar_density,
                                               overdamped)  # fmt: skip
    run = _simulate_one(p, lam, t_dim, mu, chi, num, rtol, atol, max_steps)
    rho_s = math.nan if overdamped else float(pillar_density)  # type: ignore[arg-type]
    return _trajectory_of(p, run, tt, t_scale, mu, rho_s)


def _simulate_one(
    p: Any, lam: Any, t_dim: Any, mu: float, chi: float, num: int, rtol: float, atol: float,
    max_steps: int,
) -> Any:  # fmt: skip
    """One scalar pillar's run in units of T (simulate_pillar with the pillar's model)."""
    from . import dynamics

    return dynamics.simulate_pillar(
        lam,
        t_dim,
        theta0=p.base_angle,
        profile=p._core_profile,
        height_ratio=p.height_ratio,
        gamma=p.drag_ratio,
        mu=mu,
        tangential_mass=chi,
        num=num,
        rtol=rtol,
        atol=atol,
        max_steps=max_steps,
    )


def _run_inputs(
    p: Any, drive: Any, tt: FloatArray, pillar_density: Any, overdamped: bool
) -> tuple[float, float, float, FloatArray, Any]:
    """(T [s], mu, chi, t/T, the dimensionless drive) of one pillar of numbers' run."""
    t_scale, mu, chi = time_scale_and_inertia(p, pillar_density, overdamped=overdamped)
    with np.errstate(over="ignore"):
        t_dim = tt / t_scale
    if tt.size and np.all(np.isfinite(tt)) and not np.all(np.isfinite(t_dim)):
        raise ValueError(
            f"t must stay below {np.finfo(np.float64).max * t_scale:.4g} s in magnitude for "
            f"this pillar (t/T overflows, T = {t_scale:.4g} s), got {float(np.max(np.abs(tt)))!r}"
        )
    lam = _si_drive(drive, tt, t_scale, p.forcing_per_stress)
    return t_scale, mu, chi, t_dim, lam


def _trajectory_of(
    p: Any, run: Any, tt: FloatArray, t_scale: float, mu: float, rho_s: float
) -> SensorTrajectory:
    """One pillar of numbers' run in SI (the static validity checks at its largest stress
    run here)."""
    ei, length = p.bending_stiffness, p.length
    per_stress = p.forcing_per_stress
    tau = np.asarray(run.forcing, dtype=np.float64) / per_stress
    finite = tau[np.isfinite(tau)]
    if finite.size and np.max(np.abs(finite)) > 0.0:  # the static checks at the largest stress
        p.deform(finite[np.argmax(np.abs(finite))])
    ii = run._ops["ii"]  # the collocation's integration matrix: the shape from the angles
    return SensorTrajectory(
        time=tt,
        wall_shear_stress=tau,
        tip_deflection=length * run.tip_deflection,
        tip_height=length * run.tip_height,
        tip_angle=np.asarray(run.tip_angle, dtype=np.float64),
        base_moment=ei * run.base_moment / length,
        arc_length=length * run.s,
        angle=run.theta,
        x=length * (np.sin(run.theta) @ ii.T),
        z=length * (np.cos(run.theta) @ ii.T),
        time_scale=t_scale,
        inertia_number=mu,
        pillar_density=rho_s,
        status=int(run.status),
        t_end=float(run.t_end) * t_scale,
        trajectory=run,
    )


def _array_simulate(
    p: Any,
    drive: Any,
    tt: FloatArray,
    pillar_density: Any,
    overdamped: bool,
    num: int,
    rtol: float,
    atol: float,
    max_steps: int,
    workers: int,
) -> SensorTrajectory:
    """:func:`simulate` of an array pillar (issue 32): each element's run is the compiled
    integration :func:`hairbed.dynamics.simulate_pillar` of the pillar of numbers (so each
    is bitwise its :meth:`hairbed.Pillar.item`'s), shared out over ``workers`` threads (the
    integrator releases the GIL), the runs stacked behind the pillar's shape."""
    from ._model_axes import element_index, reissue

    shape = tuple(p.shape)
    elements = list(p._elements())
    # the arguments every element shares, checked once (their errors name no element)
    time_scale_and_inertia(elements[0], pillar_density, overdamped=overdamped)
    rho_s = math.nan if overdamped else float(pillar_density)
    inputs = []
    for k, el in enumerate(elements):
        try:
            inputs.append(_run_inputs(el, drive, tt, pillar_density, overdamped))
        except ValueError as exc:  # this element's scales or its drive's range
            raise ValueError(f"{exc} (pillar {element_index(k, shape)})") from None

    def one(k: int) -> Any:
        el, (_, mu, chi, t_dim, lam) = elements[k], inputs[k]
        try:
            return _simulate_one(el, lam, t_dim, mu, chi, num, rtol, atol, max_steps)
        except ValueError as exc:
            raise ValueError(f"{exc} (pillar {element_index(k, shape)})") from None

    if workers == 1 or len(elements) == 1:
        runs = [one(k) for k in range(len(elements))]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=min(workers, len(elements))) as pool:
            runs = list(pool.map(one, range(len(elements))))
    records = []
    out = []
    for k, el in enumerate(elements):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out.append(_trajectory_of(el, runs[k], tt, inputs[k][0], inputs[k][1], rho_s))
        records.append(list(caught))
    reissue(records, shape, "pillar", 3)

    def stacked(name: str, dtype: Any = np.float64) -> Any:
        rows = np.array([getattr(r, name) for r in out], dtype=dtype)
        return rows.reshape(shape + rows.shape[1:])

    trajectories = np.empty(len(out), dtype=object)
    trajectories[:] = runs
    return SensorTrajectory(
        time=tt,
        wall_shear_stress=stacked("wall_shear_stress"),
        tip_deflection=stacked("tip_deflection"),
        tip_height=stacked("tip_height"),
        tip_angle=stacked("tip_angle"),
        base_moment=stacked("base_moment"),
        arc_length=stacked("arc_length"),
        angle=stacked("angle"),
        x=stacked("x"),
        z=stacked("z"),
        time_scale=stacked("time_scale"),
        inertia_number=stacked("inertia_number"),
        pillar_density=rho_s,
        status=stacked("status", np.int64),
        t_end=stacked("t_end"),
        trajectory=trajectories.reshape(shape),
        pillar=p,
    )
