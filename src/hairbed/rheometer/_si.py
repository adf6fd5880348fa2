"""Large-amplitude oscillatory shear of a :class:`hairbed.HairBed` in SI (issue 31 §2b).

:func:`large_amplitude_shear` and :func:`pipkin_map` in the bed's units, run for a bed given
by its physical inputs through the one HairBed conversion (:mod:`hairbed._bed_scales`, as
:func:`bed_moduli` and :meth:`hairbed.HairBed.simulate` use it):

    T = zeta_perp L^4/(E I) [s],   omega T = 2 pi f T,   stress [Pa] = Q E I/(A L^2),
    omega2* = A eta L^2 v/(E I H)  (the pre-stress's steady wall speed v [m/s]),
    alpha = rho_f L^2/(eta T)      (the Womersley number; 0 without a fluid density).

The strain gamma = delta/H is the same number in both. Moduli (G'_n, G''_n, e_n, G'_M, G'_L)
are in Pa, viscosities (v_n, eta'_M, eta'_L) in Pa s = Pa T (dimensionless) x T, the strain
rate in 1/s. The hairs are overdamped (their inertia number is ~1e-8 for a realistic hair in a
viscous fluid, below the bed dynamics' range: the same approximation as :func:`bed_moduli`
without ``hair_density``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._bed_scales import _BedScales, _scales
from .._core.porous import solve_porous
from .._core.validation import as_float_array, check_int, check_number, show
from ..bed_simulation import _within_range
from ..dynamics._bed import MAX_BED_DRIVE
from ..units import HairBed
from ._laos import harmonic_variables
from ._large import LARGE_STATUS, LargeAmplitudeShear, PipkinMap, large_amplitude_shear, pipkin_map
from ._saos import OMEGA_RANGE

__all__ = ["BedLAOS", "BedPipkinMap", "bed_laos", "bed_pipkin_map"]

FloatArray = NDArray[np.float64]

_REFERENCES = (
    "Cho, Ahn & Lee, J. Rheol. 49, 747 (2005); Ewoldt, Hosoi & McKinley, J. Rheol. 52, 1427 (2008)"
)


def _att(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


@dataclass(frozen=True)
class BedLAOS:
    """A hair bed's periodic response to a large oscillatory strain, in SI (:func:`bed_laos`).

    Attributes
    ----------
    frequency : float
        f [Hz].
    strain_amplitude : float
        gamma0 [-]: the top wall's displacement amplitude over the channel's height.
    speed : float
        The pre-stress's steady wall speed [m/s].
    pre_stress : float
        The top wall's steady stress at ``speed`` [Pa].
    time : ndarray
        The last period's sample times [s] from its start (end excluded).
    strain, strain_rate : ndarray
        gamma(t) = gamma0 sin(2 pi f t) [-] and its rate [1/s].
    stress, quasi_static_stress : ndarray
        The top wall's stress [Pa], and the static bed's at the instantaneous wall speed [Pa].
    harmonic : ndarray of int
        n = 1, 2, ... (:func:`analyse_laos`).
    storage, loss : ndarray
        G'_n, G''_n [Pa].
    intensity : ndarray
        I_n [Pa].
    relative_intensity : ndarray
        I_n/I_1 [-].
    phase : ndarray
        phi_n [rad].
    mean_stress : float
        sigma_0 [Pa].
    elastic_chebyshev, viscous_chebyshev : ndarray
        Ewoldt's e_n [Pa] and v_n [Pa s], n = 1, 3, 5, ...
    minimum_modulus, large_modulus : float
        G'_M, G'_L [Pa].
    minimum_viscosity, large_viscosity : float
        eta'_M, eta'_L [Pa s].
    even_ratio : float
        The asymmetric part over I_1 [-].
    time_scale, modulus_scale : float
        T = zeta_perp L^4/(E I) [s] and E I/(A L^2) [Pa].
    kappa, eps, womersley : float
        The bed's groups [-].
    dimensionless : LargeAmplitudeShear
        The run in the bed's units.
    """

    frequency: float
    strain_amplitude: float
    speed: float
    pre_stress: float
    time: FloatArray
    strain: FloatArray
    strain_rate: FloatArray
    stress: FloatArray
    quasi_static_stress: FloatArray
    harmonic: NDArray[np.int64]
    storage: FloatArray
    loss: FloatArray
    intensity: FloatArray
    relative_intensity: FloatArray
    phase: FloatArray
    mean_stress: float
    elastic_chebyshev: FloatArray
    viscous_chebyshev: FloatArray
    minimum_modulus: float
    large_modulus: float
    minimum_viscosity: float
    large_viscosity: float
    even_ratio: float
    time_scale: float
    modulus_scale: float
    kappa: float
    eps: float
    womersley: float
    dimensionless: LargeAmplitudeShear

    @property
    def status(self) -> int:
        """``LARGE_STATUS`` of the run."""
        return self.dimensionless.status

    @property
    def success(self) -> bool:
        """True where status is 0."""
        return self.status == 0

    @property
    def message(self) -> Any:
        """``LARGE_STATUS`` of ``status``."""
        return self.dimensionless.message

    def lissajous(self, num: int = 257) -> dict[str, FloatArray]:
        """Lissajous-Bowditch curves over one period in SI, summed from the harmonics:
        ``theta`` [rad], ``strain`` [-], ``strain_rate`` [1/s], ``total``, ``elastic``
        (sigma', against the strain), ``viscous`` (sigma'', against the strain rate) and
        ``asymmetric`` [Pa], at ``num`` phases from 0 to 2 pi inclusive (an empty dict where
        the run failed)."""
        a = self.dimensionless.analysis
        if a is None:
            return {}
        out = a.lissajous(num)
        out["strain_rate"] = out["strain_rate"] / self.time_scale
        for key in ("total", "elastic", "viscous", "asymmetric"):
            out[key] = out[key] * self.modulus_scale
        return out

    def to_xarray(self) -> Any:
        """An xarray.Dataset: the last period on ``time`` [s], the harmonics on ``harmonic``,
        Ewoldt's coefficients on ``odd_harmonic``, the scalar measures as attributes (with
        units in their names). Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedLAOS.to_xarray", "io")
        t = "time"
        fields = {
            "strain": (self.strain, "1", "strain gamma = top wall displacement / H"),
            "strain_rate": (self.strain_rate, "s-1", "strain rate"),
            "stress": (self.stress, "Pa", "top wall shear stress"),
            "quasi_static_stress": (
                self.quasi_static_stress,
                "Pa",
                "static bed's stress at the speed now",
            ),
        }
        harmonics, coords = harmonic_variables(self, "Pa", "Pa s")
        return xr.Dataset(
            {**{k: (t, v, _att(u, ln)) for k, (v, u, ln) in fields.items()}, **harmonics},
            coords={t: (t, self.time, _att("s", "time within the last period")), **coords},
            attrs={
                "title": "hairbed bed in a rheometer: large-amplitude oscillatory shear (SI)",
                "frequency_Hz": self.frequency,
                "strain_amplitude": self.strain_amplitude,
                "speed_m_s": self.speed,
                "pre_stress_Pa": self.pre_stress,
                "mean_stress_Pa": self.mean_stress,
                "minimum_modulus_Pa": self.minimum_modulus,
                "large_modulus_Pa": self.large_modulus,
                "minimum_viscosity_Pa_s": self.minimum_viscosity,
                "large_viscosity_Pa_s": self.large_viscosity,
                "even_ratio": self.even_ratio,
                "time_scale_s": self.time_scale,
                "modulus_scale_Pa": self.modulus_scale,
                "kappa": self.kappa,
                "eps": self.eps,
                "womersley": self.womersley,
                "periods": self.dimensionless.periods,
                "periodic_error": self.dimensionless.periodic_error,
                "status": self.status,
                "message": str(self.message),
                "references": _REFERENCES,
                "Conventions": "CF-1.10",
            },
        )


@dataclass(frozen=True)
class BedPipkinMap:
    """LAOS measures of a hair bed over frequency [Hz] and strain amplitude, in SI
    (:func:`bed_pipkin_map`). Arrays are (frequency, amplitude).

    Attributes
    ----------
    frequency : ndarray
        f [Hz].
    strain_amplitude : ndarray
        gamma0 [-].
    speed, pre_stress : float
        The pre-stress's steady wall speed [m/s] and the top wall's stress at it [Pa].
    storage, loss : ndarray
        The first harmonic's G'_1, G''_1 [Pa].
    third_harmonic, even_ratio : ndarray
        I_3/I_1 and the asymmetric part over I_1 [-].
    large_modulus, minimum_modulus : ndarray
        G'_L, G'_M [Pa].
    large_viscosity, minimum_viscosity : ndarray
        eta'_L, eta'_M [Pa s].
    time_scale, modulus_scale : float
        T [s] and E I/(A L^2) [Pa].
    kappa, eps, womersley : float
        The bed's groups [-].
    dimensionless : PipkinMap
        The same in the bed's units.
    """

    frequency: FloatArray
    strain_amplitude: FloatArray
    speed: float
    pre_stress: float
    storage: FloatArray
    loss: FloatArray
    third_harmonic: FloatArray
    even_ratio: FloatArray
    large_modulus: FloatArray
    minimum_modulus: FloatArray
    large_viscosity: FloatArray
    minimum_viscosity: FloatArray
    time_scale: float
    modulus_scale: float
    kappa: float
    eps: float
    womersley: float
    dimensionless: PipkinMap

    @property
    def status(self) -> NDArray[np.int64]:
        """``LARGE_STATUS`` of each run (frequency, amplitude)."""
        return self.dimensionless.status

    @property
    def success(self) -> Any:
        """True where status is 0."""
        return self.status == 0

    def to_xarray(self) -> Any:
        """An xarray.Dataset with dimensions ``frequency`` [Hz] and ``amplitude`` (units,
        long names). Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedPipkinMap.to_xarray", "io")
        dims = ("frequency", "amplitude")
        fields = {
            "storage": (self.storage, "Pa", "first-harmonic storage modulus G'_1"),
            "loss": (self.loss, "Pa", "first-harmonic loss modulus G''_1"),
            "third_harmonic": (self.third_harmonic, "1", "I_3/I_1"),
            "even_ratio": (self.even_ratio, "1", "even part over I_1"),
            "large_modulus": (self.large_modulus, "Pa", "G'_L (Ewoldt 2008)"),
            "minimum_modulus": (self.minimum_modulus, "Pa", "G'_M (Ewoldt 2008)"),
            "large_viscosity": (self.large_viscosity, "Pa s", "eta'_L (Ewoldt 2008)"),
            "minimum_viscosity": (self.minimum_viscosity, "Pa s", "eta'_M (Ewoldt 2008)"),
            "status": (self.status, "1", "status (LARGE_STATUS)"),
        }
        return xr.Dataset(
            {n: (dims, v, _att(u, ln)) for n, (v, u, ln) in fields.items()},
            coords={
                "frequency": ("frequency", self.frequency, _att("Hz", "frequency")),
                "amplitude": ("amplitude", self.strain_amplitude, _att("1", "strain amplitude")),
            },
            attrs={
                "title": "hairbed bed in a rheometer: Pipkin map (SI)",
                "speed_m_s": self.speed,
                "pre_stress_Pa": self.pre_stress,
                "time_scale_s": self.time_scale,
                "modulus_scale_Pa": self.modulus_scale,
                "kappa": self.kappa,
                "eps": self.eps,
                "womersley": self.womersley,
                "status_messages": "; ".join(f"{k}: {v}" for k, v in LARGE_STATUS.items()),
                "references": _REFERENCES,
                "Conventions": "CF-1.10",
            },
        )


def _bed_scales(bed: Any) -> _BedScales:
    if not isinstance(bed, HairBed):
        raise TypeError(f"bed must be a HairBed, got {type(bed).__name__}")
    # the one HairBed -> model conversion; numbers below the dynamics' range run as 0
    return _within_range(_scales(bed, None), bed, None)


def _omegas(frequency: Any, sc: _BedScales, name: str) -> tuple[FloatArray, FloatArray]:
    """(f, 2 pi f T) of finite f > 0 [Hz] within the bed dynamics' range of omega T."""
    f = as_float_array(frequency, name, unit="Hz").reshape(-1)
    if f.size == 0:
        raise ValueError(f"{name} must hold at least one frequency [Hz], got an empty array")
    bad = ~(f > 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name} must be > 0 [Hz], got {show(float(f[i]))} (first at index {i})")
    with np.errstate(over="ignore", under="ignore"):
        om = 2.0 * math.pi * f * sc.time
    out = ~((om >= OMEGA_RANGE[0]) & (om <= OMEGA_RANGE[1]))
    if np.any(out):
        i = int(np.flatnonzero(out)[0])
        lo, hi = (w / (2.0 * math.pi * sc.time) for w in OMEGA_RANGE)
        raise ValueError(
            f"{name} must lie in [{lo:.4g}, {hi:.4g}] Hz for this bed (omega T in "
            f"[{OMEGA_RANGE[0]:g}, {OMEGA_RANGE[1]:g}]), got {show(float(f[i]))} (first at "
            f"index {i})"
        )
    return f, om


def _amplitudes(strain_amplitude: Any, name: str) -> FloatArray:
    g = as_float_array(strain_amplitude, name).reshape(-1)
    if g.size == 0:
        raise ValueError(f"{name} must hold at least one amplitude, got an empty array")
    bad = ~(g > 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{name} must be > 0, got {show(float(g[i]))} (first at index {i})")
    return g


def _check_drive(
    sc: _BedScales,
    w0: float,
    om: FloatArray,
    g0: FloatArray,
    speed: float,
    names: tuple[str, str] = ("strain_amplitude", "frequency"),
) -> None:
    """The wall's forcing within the bed dynamics' range, said in SI (``names``: the
    caller's names of the amplitudes and the frequencies)."""
    amp = sc.kappa * float(np.max(g0)) * float(np.max(om))
    if not abs(w0) + amp <= MAX_BED_DRIVE:
        v_max = MAX_BED_DRIVE / sc.omega2_per_velocity
        v_amp = amp / sc.omega2_per_velocity
        raise ValueError(
            f"{names[0]} x {names[1]} is too fast for this bed: the top wall's speed "
            f"amplitude H gamma0 2 pi f = {v_amp:.4g} m/s plus abs(speed) = {abs(speed):.4g} m/s "
            f"must stay within {v_max:.4g} m/s (give a smaller {names[0]} or {names[1]})"
        )


def _pre_stress(sc: _BedScales, w0: float) -> float:
    st = solve_porous(w0, sc.eps, sc.theta0, kappa=sc.kappa, gamma=sc.gamma)
    if int(st.status) < 0:
        raise ValueError(f"speed gives a forcing {w0!r} with no steady state of this bed")
    return float(st.tip_stress) / sc.load_per_stress


def bed_laos(
    bed: HairBed,
    frequency: float,
    strain_amplitude: float,
    speed: float = 0.0,
    *,
    samples: int = 64,
    periodic_tol: float = 1e-6,
    max_periods: int = 200,
    rtol: float = 1e-9,
) -> BedLAOS:
    """A hair bed's periodic state under the strain gamma = gamma0 sin(2 pi f t), in SI.

    The top wall moves by delta(t) = H gamma(t) about a steady speed v (the pre-stress); its
    stress sigma(t) [Pa] over the last period is analysed by :func:`analyse_laos` (Fourier
    harmonics, Ewoldt's Chebyshev coefficients, Lissajous-Bowditch curves). The run is
    :func:`large_amplitude_shear` in the bed's units (the module's description gives the
    scales); the bed's porous description with the drag law of ``bed.drag`` and the fluid's
    inertia from ``bed.density`` (a quasi-steady fluid without one).

    Parameters
    ----------
    bed : HairBed
        The bed (any ``model``: its porous description is used).
    frequency : float
        f [Hz] > 0, with 2 pi f T in [1e-9, 1e9].
    strain_amplitude : float
        gamma0 [-] > 0.
    speed : float, optional
        The pre-stress's steady wall speed [m/s] (default 0; the sign is the direction).
    samples, periodic_tol, max_periods, rtol : optional
        As :func:`large_amplitude_shear` (samples per period, the periodicity criterion, the
        most periods, the integrator's tolerance).

    Returns
    -------
    BedLAOS
        Stress [Pa] against strain [-] and strain rate [1/s], I_n/I_1, G'_M, G'_L [Pa],
        eta'_M, eta'_L [Pa s], e_n [Pa], v_n [Pa s]; ``dimensionless`` the run itself.
    """
    sc = _bed_scales(bed)
    f, om = _omegas(check_number(frequency, "frequency", unit="Hz"), sc, "frequency")
    g0 = _amplitudes(check_number(strain_amplitude, "strain_amplitude"), "strain_amplitude")
    v = check_number(speed, "speed", unit="m/s")
    w0 = v * sc.omega2_per_velocity
    _check_drive(sc, w0, om, g0, v)
    res = large_amplitude_shear(
        float(om[0]), float(g0[0]), eps=sc.eps, kappa=sc.kappa, theta0=sc.theta0,
        gamma=sc.gamma, forcing=w0, womersley=sc.womersley, samples=samples,
        periodic_tol=periodic_tol, max_periods=max_periods, rtol=rtol,
    )  # fmt: skip
    ts, gs = sc.time, 1.0 / sc.load_per_stress
    t = (res.t - res.t[0]) * ts
    a = res.analysis
    nan = math.nan
    empty = np.zeros(0)
    return BedLAOS(
        frequency=float(f[0]),
        strain_amplitude=float(g0[0]),
        speed=v,
        pre_stress=_pre_stress(sc, w0),
        time=t,
        strain=res.strain,
        strain_rate=float(g0[0]) * float(om[0]) / ts * np.cos(float(om[0]) * res.t),
        stress=res.stress * gs,
        quasi_static_stress=res.quasi_static_stress * gs,
        harmonic=a.harmonic if a is not None else np.zeros(0, dtype=np.int64),
        storage=a.storage * gs if a is not None else empty,
        loss=a.loss * gs if a is not None else empty,
        intensity=a.intensity * gs if a is not None else empty,
        relative_intensity=a.relative_intensity if a is not None else empty,
        phase=a.phase if a is not None else empty,
        mean_stress=a.mean_stress * gs if a is not None else nan,
        elastic_chebyshev=a.elastic_chebyshev * gs if a is not None else empty,
        viscous_chebyshev=a.viscous_chebyshev * gs * ts if a is not None else empty,
        minimum_modulus=a.minimum_modulus * gs if a is not None else nan,
        large_modulus=a.large_modulus * gs if a is not None else nan,
        minimum_viscosity=a.minimum_viscosity * gs * ts if a is not None else nan,
        large_viscosity=a.large_viscosity * gs * ts if a is not None else nan,
        even_ratio=a.even_ratio if a is not None else nan,
        time_scale=ts,
        modulus_scale=gs,
        kappa=sc.kappa,
        eps=sc.eps,
        womersley=sc.womersley,
        dimensionless=res,
    )


def bed_pipkin_map(
    bed: HairBed,
    frequencies: ArrayLike,
    strain_amplitudes: ArrayLike,
    speed: float = 0.0,
    *,
    workers: int = 1,
    samples: int = 64,
    periodic_tol: float = 1e-6,
    max_periods: int = 200,
    rtol: float = 1e-9,
) -> BedPipkinMap:
    """A hair bed's Pipkin map in SI: :func:`bed_laos`'s measures over a grid of frequencies
    f [Hz] and strain amplitudes gamma0 [-] (:func:`pipkin_map` in the bed's units, one run
    per cell, ``workers`` processes in [1, 64]). ``speed`` (the pre-stress's steady wall
    speed [m/s]), ``samples``, ``periodic_tol``, ``max_periods`` and ``rtol`` are those of
    :func:`bed_laos`, for every cell.

    Returns
    -------
    BedPipkinMap
        G'_1, G''_1, G'_L, G'_M [Pa], eta'_L, eta'_M [Pa s], I_3/I_1 and the even ratio,
        arrays (frequency, amplitude).
    """
    sc = _bed_scales(bed)
    f, om = _omegas(frequencies, sc, "frequencies")
    g0 = _amplitudes(strain_amplitudes, "strain_amplitudes")
    v = check_number(speed, "speed", unit="m/s")
    check_int(workers, "workers", 1, 64)
    w0 = v * sc.omega2_per_velocity
    _check_drive(sc, w0, om, g0, v, ("strain_amplitudes", "frequencies"))
    res = pipkin_map(
        om, g0, workers=workers, eps=sc.eps, kappa=sc.kappa, theta0=sc.theta0, gamma=sc.gamma,
        forcing=w0, womersley=sc.womersley, samples=samples, periodic_tol=periodic_tol,
        max_periods=max_periods, rtol=rtol,
    )  # fmt: skip
    ts, gs = sc.time, 1.0 / sc.load_per_stress
    return BedPipkinMap(
        frequency=f,
        strain_amplitude=g0,
        speed=v,
        pre_stress=_pre_stress(sc, w0),
        storage=res.storage * gs,
        loss=res.loss * gs,
        third_harmonic=res.third_harmonic,
        even_ratio=res.even_ratio,
        large_modulus=res.large_modulus * gs,
        minimum_modulus=res.minimum_modulus * gs,
        large_viscosity=res.large_viscosity * gs * ts,
        minimum_viscosity=res.minimum_viscosity * gs * ts,
        time_scale=ts,
        modulus_scale=gs,
        kappa=sc.kappa,
        eps=sc.eps,
        womersley=sc.womersley,
        dimensionless=res,
    )
