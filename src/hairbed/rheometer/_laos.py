"""Large-amplitude oscillatory shear (LAOS): the analysis of one periodic stress record.

Solver-independent: given a strain gamma(t) = gamma0 sin(omega t + phi) sampled uniformly
over a whole number of periods and the stress sigma(t) at the same times, the stress is
decomposed in the strain's own phase theta = omega t + phi (x = sin theta = gamma/gamma0,
y = cos theta = gamma_dot/gamma_dot0):

    sigma(theta) = sigma_0 + gamma0 sum_{n >= 1} [G'_n sin(n theta) + G''_n cos(n theta)],
    I_n = gamma0 sqrt(G'_n^2 + G''_n^2),   sigma_n = I_n sin(n theta + phi_n).

**Odd and even harmonics.** A material whose stress reverses with the strain,
sigma(-gamma, -gamma_dot) = -sigma(gamma, gamma_dot), has odd harmonics only. A tilted hair
bed is not symmetric: shear with the grain and against it differ (theory.md §5, the
rectification of :mod:`hairbed.rheology`), so its stress also has a mean sigma_0 and even
harmonics. Both are reported; the even part is the stress's asymmetric part,
sigma_a = sigma_0 + gamma0 sum_{n even} (...), and ``even_ratio`` its size against I_1.

**Elastic and viscous stresses** (K. S. Cho, K. H. Ahn and S. J. Lee, "A geometrical
interpretation of large amplitude oscillatory shear response", J. Rheol. 49, 747-758, 2005):
of the odd part, sigma' = gamma0 sum_{n odd} G'_n sin(n theta), a function of x alone (odd in
x), and sigma'' = gamma0 sum_{n odd} G''_n cos(n theta), a function of y alone (odd in y);
sigma = sigma' + sigma'' + sigma_a.

**Chebyshev coefficients** (R. H. Ewoldt, A. E. Hosoi and G. H. McKinley, "New measures for
characterizing nonlinear viscoelasticity in large amplitude oscillatory shear", J. Rheol.
52, 1427-1458, 2008, eqs. (9)-(16)): with T_n the Chebyshev polynomials of the first kind,

    sigma'(x) = gamma0 sum_{n odd} e_n T_n(x),    e_n = G'_n (-1)^((n-1)/2),
    sigma''(y) = gamma_dot0 sum_{n odd} v_n T_n(y),   v_n = G''_n/omega,

and the moduli and dynamic viscosities at the smallest and largest strain (rate):

    G'_M = d sigma/d gamma at gamma = 0 = sum_{n odd} n e_n (-1)^((n-1)/2),
    G'_L = sigma/gamma at gamma = gamma0 = sum_{n odd} e_n,
    eta'_M = d sigma/d gamma_dot at gamma_dot = 0 = sum_{n odd} n v_n (-1)^((n-1)/2),
    eta'_L = sigma/gamma_dot at gamma_dot = gamma_dot0 = sum_{n odd} v_n,

with Ewoldt's strain-stiffening ratio S = (G'_L - G'_M)/G'_L and shear-thickening ratio
T = (eta'_L - eta'_M)/eta'_L.

The harmonics are the discrete Fourier transform of the samples: exact for a stress whose
harmonics above the Nyquist frequency vanish (a trigonometric polynomial), aliased
otherwise; ``status`` 2 flags a record whose highest resolved harmonic is not negligible,
status 1 one that is not periodic over the record (the transform's bins between the
harmonics, measurable where the record spans several periods).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.validation import StatusResult, as_float_array, show

__all__ = [
    "LAOS_STATUS",
    "LAOSAnalysis",
    "analyse_laos",
]

FloatArray = NDArray[np.float64]

#: Status codes of :class:`LAOSAnalysis` (0 ok, positive a caveat).
LAOS_STATUS = {
    0: "ok",
    1: (
        "not periodic: the stress between the harmonics (over several periods) exceeds "
        "1e-6 of I_1, the transient has not decayed"
    ),
    2: (
        "under-resolved: the highest resolved harmonic exceeds 1e-8 of I_1, the harmonics may "
        "be aliased (sample more densely)"
    ),
}
#: A strain whose other harmonics exceed this fraction of its first is not a sine.
STRAIN_SINE_TOL = 1e-6
#: Tolerance of the sample times' spacing, relative to the mean step.
TIME_TOL = 1e-8
_PERIODIC_TOL = 1e-6
_ALIAS_TOL = 1e-8


@dataclass(frozen=True)
class LAOSAnalysis(StatusResult):
    """The harmonics, Chebyshev coefficients and LAOS measures of a periodic stress record.

    The units of the stress are the caller's ([stress]); the strain is dimensionless.

    Attributes
    ----------
    omega : float
        Angular frequency [1/time] of the strain.
    strain_amplitude : float
        gamma0 [-].
    strain_phase : float
        phi [rad]: the strain is gamma0 sin(omega t + phi) at the given times.
    harmonic : ndarray of int
        n = 1, 2, ..., num_harmonics.
    storage, loss : ndarray
        G'_n, G''_n [stress]: the in-phase and quadrature harmonics per unit strain (n = 1:
        the first-harmonic moduli G', G'').
    intensity : ndarray
        I_n = gamma0 abs(G*_n) [stress].
    phase : ndarray
        phi_n = atan2(G''_n, G'_n) [rad]: sigma_n = I_n sin(n theta + phi_n); phi_1 in (0,
        pi/2) is a viscoelastic stress leading the strain, phi_1 < 0 one lagging it.
    mean_stress : float
        sigma_0 [stress] (0 for a symmetric material).
    elastic_chebyshev, viscous_chebyshev : ndarray
        e_n [stress] and v_n [stress x time] for n = 1, 3, 5, ... (Ewoldt et al. 2008).
    minimum_modulus, large_modulus : float
        G'_M, G'_L [stress].
    minimum_viscosity, large_viscosity : float
        eta'_M, eta'_L [stress x time].
    even_ratio : float
        sqrt(sum_{n even} I_n^2 + sigma_0^2)/I_1 [-]: the asymmetric part against the first
        harmonic (0 for a symmetric material).
    nonperiodic : float
        The largest stress amplitude between the harmonics over I_1 [-] (a record of
        several periods; 0 for one period, where it cannot be measured).
    periods : int
        The number of whole periods in the record.
    status : int
        ``LAOS_STATUS``.
    """

    omega: float
    strain_amplitude: float
    strain_phase: float
    harmonic: NDArray[np.int64]
    storage: FloatArray
    loss: FloatArray
    intensity: FloatArray
    phase: FloatArray
    mean_stress: float
    elastic_chebyshev: FloatArray
    viscous_chebyshev: FloatArray
    minimum_modulus: float
    large_modulus: float
    minimum_viscosity: float
    large_viscosity: float
    even_ratio: float
    nonperiodic: float
    periods: int
    status: int

    _status_table: ClassVar[Mapping[int, str]] = LAOS_STATUS

    @property
    def relative_intensity(self) -> FloatArray:
        """I_n/I_1 [-]."""
        return self.intensity / self.intensity[0]

    @property
    def stiffening_ratio(self) -> float:
        """S = (G'_L - G'_M)/G'_L [-] (Ewoldt et al. 2008, eq. (22)): > 0 strain-stiffening."""
        return (self.large_modulus - self.minimum_modulus) / self.large_modulus

    @property
    def thickening_ratio(self) -> float:
        """T = (eta'_L - eta'_M)/eta'_L [-] (Ewoldt et al. 2008, eq. (23)): > 0
        shear-thickening."""
        return (self.large_viscosity - self.minimum_viscosity) / self.large_viscosity

    def stress(self, theta: ArrayLike) -> dict[str, FloatArray]:
        """The stress and its parts at the phases ``theta`` [rad] of the strain, summed from
        the harmonics: ``total``, ``elastic`` (sigma'), ``viscous`` (sigma'') and
        ``asymmetric`` (the mean and the even harmonics) [stress]."""
        # the phase within one period: n theta overflowed near the largest double
        th = np.mod(as_float_array(theta, "theta"), 2.0 * math.pi)
        g0 = self.strain_amplitude
        n = self.harmonic.astype(np.float64)
        odd = (self.harmonic % 2) == 1
        arg = np.multiply.outer(th, n)
        sn, cn = np.sin(arg), np.cos(arg)
        elastic = g0 * (sn[..., odd] @ self.storage[odd])
        viscous = g0 * (cn[..., odd] @ self.loss[odd])
        asym = self.mean_stress + g0 * (
            sn[..., ~odd] @ self.storage[~odd] + cn[..., ~odd] @ self.loss[~odd]
        )
        return {
            "total": elastic + viscous + asym,
            "elastic": elastic,
            "viscous": viscous,
            "asymmetric": asym,
        }

    def lissajous(self, num: int = 257) -> dict[str, FloatArray]:
        """Lissajous-Bowditch curves over one period, for plotting: ``theta`` [rad],
        ``strain`` [-], ``strain_rate`` [1/time], the stress and its parts of :meth:`stress`
        [stress] (the elastic curve is sigma' against the strain, the viscous sigma''
        against the strain rate), at ``num`` phases from 0 to 2 pi inclusive."""
        if (
            isinstance(num, bool)
            or not isinstance(num, (int, np.integer))
            or not 3 <= num <= 10**6
        ):
            raise ValueError(f"num must be an integer in [3, 10^6], got {show(num)}")
        th = np.linspace(0.0, 2.0 * math.pi, int(num))
        out = {
            "theta": th,
            "strain": self.strain_amplitude * np.sin(th),
            "strain_rate": self.strain_amplitude * self.omega * np.cos(th),
        }
        out.update(self.stress(th))
        return out

    def to_xarray(self) -> Any:
        """The harmonics as an xarray.Dataset (dimension ``harmonic``; the Chebyshev
        coefficients on ``odd_harmonic``), with units and long names; the scalar measures as
        attributes. Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "LAOSAnalysis.to_xarray", "io")
        data, coords = harmonic_variables(self, "stress", "stress time")
        return xr.Dataset(
            data,
            coords=coords,
            attrs={
                "title": "hairbed LAOS analysis",
                "omega": self.omega,
                "strain_amplitude": self.strain_amplitude,
                "mean_stress": self.mean_stress,
                "minimum_modulus": self.minimum_modulus,
                "large_modulus": self.large_modulus,
                "minimum_viscosity": self.minimum_viscosity,
                "large_viscosity": self.large_viscosity,
                "even_ratio": self.even_ratio,
                "nonperiodic": self.nonperiodic,
                "status": self.status,
                "references": (
                    "Cho, Ahn & Lee, J. Rheol. 49, 747 (2005); Ewoldt, Hosoi & McKinley, "
                    "J. Rheol. 52, 1427 (2008)"
                ),
                "Conventions": "CF-1.10",
            },
        )


def _attrs(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def harmonic_variables(
    record: Any, stress: str, viscosity: str
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The harmonics of a LAOS record as xarray (data variables, coordinates): G'_n, G''_n,
    I_n, I_n/I_1 and phi_n on ``harmonic``, Ewoldt's e_n and v_n on ``odd_harmonic``, with
    units and long names. ``record`` has those fields by the names of :class:`LAOSAnalysis`
    (it, or :class:`hairbed.rheometer.BedLAOS` in SI); ``stress`` and ``viscosity`` are the
    units of its moduli and of v_n. One table for every LAOS dataset."""
    odd = record.harmonic[record.harmonic % 2 == 1]
    h, o = "harmonic", "odd_harmonic"
    fields = {
        "storage": (h, record.storage, stress, "G'_n, in-phase harmonic per unit strain"),
        "loss": (h, record.loss, stress, "G''_n, quadrature harmonic per unit strain"),
        "intensity": (h, record.intensity, stress, "I_n, harmonic amplitude"),
        "relative_intensity": (h, record.relative_intensity, "1", "I_n/I_1"),
        "phase": (h, record.phase, "rad", "phi_n of sigma_n = I_n sin(n theta + phi_n)"),
        "elastic_chebyshev": (o, record.elastic_chebyshev, stress, "e_n (Ewoldt 2008)"),
        "viscous_chebyshev": (o, record.viscous_chebyshev, viscosity, "v_n (Ewoldt 2008)"),
    }
    data = {k: (d, v, _attrs(u, ln)) for k, (d, v, u, ln) in fields.items()}
    coords = {
        h: (h, record.harmonic, _attrs("1", "harmonic number n")),
        o: (o, odd, _attrs("1", "odd harmonic number n")),
    }
    return data, coords


def _check_record(time: ArrayLike, strain: ArrayLike, stress: ArrayLike) -> tuple[FloatArray, ...]:
    t = as_float_array(time, "time")
    g = as_float_array(strain, "strain")
    s = as_float_array(stress, "stress")
    for name, a in (("time", t), ("strain", g), ("stress", s)):
        if a.ndim != 1:
            raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    if not (t.size == g.size == s.size):
        raise ValueError(
            f"time, strain and stress must have one length, got {t.size}, {g.size}, {s.size}"
        )
    if t.size < 8:
        raise ValueError(f"time must have at least 8 samples, got {t.size}")
    dt = np.diff(t)
    step = (t[-1] - t[0]) / (t.size - 1)
    if not step > 0.0:
        raise ValueError("time must increase")
    bad = np.abs(dt - step) > TIME_TOL * step
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"time must be uniformly sampled (spacing {step!r}): time[{i + 1}] - time[{i}] = "
            f"{float(dt[i])!r} (first at index {i})"
        )
    return t, g, s


def analyse_laos(
    time: ArrayLike,
    strain: ArrayLike,
    stress: ArrayLike,
    *,
    periods: int = 1,
    num_harmonics: int | None = None,
) -> LAOSAnalysis:
    """Analyse a periodic stress under a sinusoidal strain (LAOS).

    Parameters
    ----------
    time : array_like
        Uniformly spaced sample times [time] covering exactly ``periods`` periods, the end
        excluded (t_k = t_0 + k P/N, P the record's length; the next sample would start the
        next period).
    strain : array_like
        gamma(t_k) = gamma0 sin(omega t_k + phi) [-], any phase phi and gamma0 > 0 (its other
        harmonics must be below ``STRAIN_SINE_TOL`` of the first).
    stress : array_like
        sigma(t_k) [stress], any units (the moduli are in the same).
    periods : int, optional
        Whole periods in the record, >= 1 (default 1). Several periods let the bins between
        the harmonics measure how periodic the record is.
    num_harmonics : int, optional
        Harmonics to keep, in [1, N/(2 periods) - 1] (default: all below the Nyquist
        frequency).

    Returns
    -------
    LAOSAnalysis
        The harmonics G'_n, G''_n, I_n, phi_n, the Chebyshev coefficients e_n, v_n, G'_M,
        G'_L, eta'_M, eta'_L (Ewoldt, Hosoi & McKinley, J. Rheol. 52, 1427, 2008), the
        asymmetry and periodicity measures, and the Lissajous curves.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(64) * 2 * np.pi / 64  # one period at omega = 1
    >>> gamma = 0.5 * np.sin(t)
    >>> sigma = 2.0 * gamma + 0.3 * gamma**3 + 1.5 * 0.5 * np.cos(t)
    >>> res = analyse_laos(t, gamma, sigma)
    >>> round(res.minimum_modulus, 12), round(res.large_modulus, 12)  # G and G + c gamma0^2
    (2.0, 2.075)
    """
    t, g, s = _check_record(time, strain, stress)
    # (numpy's timedelta64 is an integer type: a count of time, not of periods)
    if (
        isinstance(periods, (bool, np.timedelta64))
        or not isinstance(periods, (int, np.integer))
        or periods < 1
    ):
        raise ValueError(f"periods must be an integer >= 1, got {show(periods)}")
    m = int(periods)
    size = t.size
    per = size // m
    if per * m != size or per < 8:
        raise ValueError(
            f"periods must divide the number of samples ({size}) into at least 8 a period, got {m}"
        )
    nyq = (per - 1) // 2  # the highest harmonic below the Nyquist frequency
    if num_harmonics is None:
        kmax = nyq
    elif (
        isinstance(num_harmonics, (bool, np.timedelta64))
        or not isinstance(num_harmonics, (int, np.integer))
        or not 1 <= num_harmonics <= nyq
    ):
        raise ValueError(
            f"num_harmonics must be an integer in [1, {nyq}] (below the Nyquist frequency), "
            f"got {show(num_harmonics)}"
        )
    else:
        kmax = int(num_harmonics)
    step = (t[-1] - t[0]) / (size - 1)
    omega = 2.0 * math.pi * m / (size * step)
    # the strain's harmonics: a sine of one phase
    gf = np.fft.rfft(g) * (2.0 / size)
    g1 = gf[m]
    gamma0 = float(abs(g1))
    if not gamma0 > 0.0:
        raise ValueError("strain must oscillate: its first harmonic over the record is 0")
    other = np.abs(np.delete(gf, m))
    other[0] *= 0.5
    if float(other.max()) > STRAIN_SINE_TOL * gamma0:
        raise ValueError(
            "strain must be gamma0 sin(omega t + phi) over the record's periods: its other "
            f"Fourier content is {float(other.max()) / gamma0:.3g} of its first harmonic "
            f"(tolerance {STRAIN_SINE_TOL:g})"
        )
    # g = gamma0 sin(omega (t - t0) + phi): the coefficient of e^{i theta} is gamma0 e^{i phi}/(2i)
    phi = float(np.angle(g1 * 1j))
    sf = np.fft.rfft(s) / size  # sigma = sum c_k e^{i k 2 pi j/size}
    n = np.arange(1, kmax + 1)
    c = sf[n * m] * np.exp(-1j * n * phi)  # in the strain's phase theta = omega (t - t0) + phi
    storage = -2.0 * c.imag / gamma0  # sigma_n = 2 Re(c e^{i n theta}) = 2 c_r cos - 2 c_i sin
    loss = 2.0 * c.real / gamma0
    mean = float(sf[0].real)
    intensity = gamma0 * np.hypot(storage, loss)
    phase = np.arctan2(loss, storage)
    odd = n % 2 == 1
    nodd = n[odd]
    sign = np.where(((nodd - 1) // 2) % 2 == 0, 1.0, -1.0)
    e = storage[odd] * sign
    v = loss[odd] / omega
    i1 = float(intensity[0])
    even = (
        math.sqrt(float(np.sum(intensity[~odd] ** 2)) + mean * mean) / i1 if i1 > 0 else math.inf
    )
    # periodicity: the bins between the harmonics, and the end's mismatch with the start
    between = np.ones(sf.size, dtype=bool)
    between[0::m] = False
    gap = float(2.0 * np.abs(sf[between]).max()) if np.any(between) else 0.0
    nonper = gap / i1 if i1 > 0 else math.inf
    alias = float(intensity[-1]) / i1 if (i1 > 0 and kmax == nyq) else 0.0
    status = 1 if nonper > _PERIODIC_TOL else (2 if alias > _ALIAS_TOL else 0)
    return LAOSAnalysis(
        omega=omega,
        strain_amplitude=gamma0,
        strain_phase=float(np.angle(np.exp(1j * (phi - omega * t[0])))),
        harmonic=n.astype(np.int64),
        storage=storage,
        loss=loss,
        intensity=intensity,
        phase=phase,
        mean_stress=mean,
        elastic_chebyshev=e,
        viscous_chebyshev=v,
        minimum_modulus=float(np.sum(nodd * e * sign)),
        large_modulus=float(np.sum(e)),
        minimum_viscosity=float(np.sum(nodd * v * sign)),
        large_viscosity=float(np.sum(v)),
        even_ratio=even,
        nonperiodic=nonper,
        periods=m,
        status=status,
    )
