"""Large-amplitude oscillatory shear of the porous bed in time (issue 31 §2b).

The top wall is driven so that the strain (its displacement over H) is
gamma(t) = gamma0 sin(omega t): its speed V = H gamma0 omega cos(omega t), i.e. the wall
forcing omega2(t) = omega2* + kappa gamma0 omega cos(omega t) (omega2 = kappa eps V, V in L/T,
H = L/eps), about an optional pre-stress's forcing omega2*.

**The periodic steady state**, by one of two methods (``method``):

* ``"collocation"`` (the default): :func:`hairbed.dynamics.periodic_bed`, trigonometric
  collocation in time with Newton's method (theory.md §16), directly periodic; its truncation
  error below min(periodic_tol, 1e-10) (the highest harmonics' amplitudes). The ``samples``
  phases are read off its trigonometric interpolant.
* ``"transient"`` (the baseline): :func:`hairbed.dynamics.simulate_bed` (Radau IIA) from the
  steady state of the forcing at t = 0 until the transient decays. It decays at least as fast
  as the slowest mode of the linear bed about the mean state
  (:meth:`hairbed.dynamics.LinearBed.modes`, rate r = min |Re lambda|): the run covers
  n = ceil(ln(1/periodic_tol)/(r P)) + 2 periods (P = 2 pi/omega, at least 3, at most
  ``max_periods``), and the **criterion** is checked on the result: the stress over the last
  period differs from the period before by at most ``periodic_tol`` of its largest value
  (status 1 otherwise).

The period, sampled at ``samples`` uniform phases, is analysed by :func:`analyse_laos`
(harmonics, Ewoldt's measures, Lissajous curves).

At low frequency the bed follows its static states: the stress is the quasi-static rheology
Q(H) of :func:`hairbed.solve_porous` at the instantaneous forcing (``quasi_static_stress``),
to O(omega T).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .._core.porous import solve_porous
from .._core.validation import StatusResult, check_int, check_number
from ..dynamics import linearise_bed, periodic_bed, simulate_bed, sine
from ..dynamics._bed import MAX_BED_DRIVE
from ._laos import LAOSAnalysis, analyse_laos
from ._saos import EPS_MIN, KAPPA_RANGE, OMEGA_RANGE

__all__ = [
    "LARGE_METHODS",
    "LARGE_STATUS",
    "LargeAmplitudeShear",
    "PipkinMap",
    "large_amplitude_shear",
    "pipkin_map",
]

FloatArray = NDArray[np.float64]

#: Status codes of :class:`LargeAmplitudeShear`.
LARGE_STATUS = {
    0: "ok: periodic to periodic_tol",
    1: "not periodic to periodic_tol: (transient) the last two periods differ by more than "
    "periodic_tol at max_periods; (collocation) the highest harmonics exceed it at the "
    "largest degree",
    -1: "the periodic state failed (see trajectory_status: simulate_bed's BED_STATUS, or "
    "periodic_bed's PERIODIC_STATUS)",
}
#: The methods of :func:`large_amplitude_shear`.
LARGE_METHODS = ("collocation", "transient")


@dataclass(frozen=True)
class LargeAmplitudeShear(StatusResult):
    """The bed's periodic response to a large-amplitude oscillatory strain.

    Attributes
    ----------
    omega, strain_amplitude, forcing : float
        omega [1/T], gamma0 [-] and the pre-stress's steady forcing omega2* [-].
    t : ndarray
        The period's sample times [T] (end excluded): the last period's (transient), or
        k P/samples (collocation).
    strain, stress : ndarray
        gamma(t) [-] and the top wall's stress Q(H, t) [E I/(A L^2)] over the last period.
    quasi_static_stress : ndarray
        The static bed's top stress at the instantaneous forcing (solve_porous) [E I/(A L^2)].
    analysis : LAOSAnalysis or None
        :func:`analyse_laos` of the last period (None where the run failed).
    periods : int
        Periods integrated (transient; 0 for collocation).
    periodic_error : float
        Transient: max abs(stress(last period) - stress(the one before)) / max abs(stress)
        [-]; collocation: :attr:`hairbed.dynamics.PeriodicBed.error`, the truncation's
        estimate.
    trajectory_status : int
        :func:`simulate_bed`'s status (transient) or :func:`periodic_bed`'s (collocation).
    nsteps : int
        The integrator's steps (transient) or Newton's iterations (collocation).
    status : int
        ``LARGE_STATUS``.
    method : str
        ``"collocation"`` or ``"transient"``.
    harmonics : int
        The collocation's trigonometric degree H (0 for transient).
    """

    omega: float
    strain_amplitude: float
    forcing: float
    t: FloatArray
    strain: FloatArray
    stress: FloatArray
    quasi_static_stress: FloatArray
    analysis: LAOSAnalysis | None
    periods: int
    periodic_error: float
    trajectory_status: int
    nsteps: int
    status: int
    method: str = "transient"
    harmonics: int = 0

    _status_table: ClassVar[Mapping[int, str]] = LARGE_STATUS


def large_amplitude_shear(
    omega: float,
    strain_amplitude: float,
    *,
    eps: float,
    kappa: float,
    theta0: float = 0.0,
    gamma: float = 1.0,
    forcing: float = 0.0,
    inertia: float = 0.0,
    womersley: float = 0.0,
    samples: int = 64,
    periodic_tol: float = 1e-6,
    max_periods: int = 200,
    rtol: float = 1e-9,
    method: str = "collocation",
) -> LargeAmplitudeShear:
    """The porous bed's periodic steady state under gamma = gamma0 sin(omega t), analysed.

    Parameters
    ----------
    omega : float
        Angular frequency [1/T] > 0 (T = zeta_perp L^4/(E I)).
    strain_amplitude : float
        gamma0 [-] > 0: the top wall's displacement amplitude over H.
    eps, kappa, theta0, gamma : float
        The bed (as :func:`hairbed.solve_porous`).
    forcing : float, optional
        The pre-stress's steady wall forcing omega2* (default 0).
    inertia, womersley : float, optional
        mu and alpha of :func:`hairbed.dynamics.simulate_bed` (default 0: overdamped hairs,
        quasi-steady fluid; with inertia the high modes ring for about 2 mu T each, and the
        run is long).
    samples : int, optional
        Samples per period in [16, 4096] (default 64); the harmonics below samples/2.
    periodic_tol : float, optional
        The periodicity criterion (default 1e-6), in [1e-9, 0.1]; collocation meets
        min(periodic_tol, 1e-10).
    max_periods : int, optional
        The most periods integrated, in [3, 10^4] (default 200; transient only).
    rtol : float, optional
        The integrator's relative tolerance (default 1e-9, below the periodicity criterion's
        default); atol is the same (with hair inertia an atol far below rtol makes the steps
        crawl at the rates' rounding floor, measured at atol 1e-11). Transient only.
    method : {"collocation", "transient"}, optional
        The periodic state's method (the module's description): collocation in time
        (default) or integration until the transient decays.

    Returns
    -------
    LargeAmplitudeShear
    """
    om = check_number(omega, "omega", low=OMEGA_RANGE[0], high=OMEGA_RANGE[1])
    g0 = check_number(strain_amplitude, "strain_amplitude", low=0.0, low_open=True)
    e = check_number(eps, "eps", low=EPS_MIN, high=1.0, high_open=True)
    k = check_number(kappa, "kappa", low=KAPPA_RANGE[0], high=KAPPA_RANGE[1])
    th = check_number(theta0, "theta0", low=-math.pi / 2, high=math.pi / 2, low_open=True,
                      high_open=True)  # fmt: skip
    gm = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    w0 = check_number(forcing, "forcing")
    mu = check_number(inertia, "inertia", low=0.0)
    alpha = check_number(womersley, "womersley", low=0.0)
    per = check_int(samples, "samples", 16, 4096)
    tol = check_number(periodic_tol, "periodic_tol", low=1e-9, high=0.1)
    nmax = check_int(max_periods, "max_periods", 3, 10_000)
    rt = check_number(rtol, "rtol", low=1e-12, high=1e-3)
    if method not in LARGE_METHODS:
        raise ValueError(f"method must be one of {LARGE_METHODS}, got {method!r}")
    amp = k * g0 * om
    if not abs(w0) + amp <= MAX_BED_DRIVE:
        raise ValueError(
            f"strain_amplitude * omega = {g0 * om:.4g} [1/T] is too fast for this bed: the top "
            f"wall's forcing kappa gamma0 omega = {amp:.4g} plus the pre-stress's must stay "
            f"within {MAX_BED_DRIVE:g} (give a smaller strain_amplitude or omega)"
        )
    mean = solve_porous(w0, e, th, kappa=k, gamma=gm)
    if int(mean.status) < 0:
        raise ValueError(
            f"forcing {w0!r} has no steady state of this bed (status {int(mean.status)})"
        )
    period = 2.0 * math.pi / om
    if method == "collocation":
        orbit = periodic_bed(
            th, k, e, omega=om, wall=sine(w0, amp, om, math.pi / 2), gamma=gm, inertia=mu,
            womersley=alpha, tol=min(tol, 1e-10),
        )  # fmt: skip
        tl = np.arange(per, dtype=np.float64) * (period / per)
        strain = g0 * np.sin(om * tl)
        stress = np.asarray(orbit.outputs_at(tl)["wall_stress"], dtype=np.float64)
        quasi = _quasi_static(w0, amp, om, tl, e, th, k, gm)
        if orbit.status < 0:
            return LargeAmplitudeShear(
                om, g0, w0, tl, strain, stress, quasi, None, 0, math.nan, orbit.status,
                orbit.iterations, -1, "collocation", orbit.harmonics,
            )  # fmt: skip
        return LargeAmplitudeShear(
            om, g0, w0, tl, strain, stress, quasi, analyse_laos(tl, strain, stress), 0,
            orbit.error, orbit.status, orbit.iterations, 0 if orbit.error <= tol else 1,
            "collocation", orbit.harmonics,
        )  # fmt: skip
    lam = linearise_bed(mean, inertia=mu, womersley=alpha).modes(4).eigenvalues
    rate = float(np.min(np.abs(lam.real))) if lam.size else 1.0
    need = math.log(1.0 / tol) / max(rate * period, 1e-300)
    nper = int(min(max(3, math.ceil(need) + 2), nmax))
    t = np.arange(nper * per + 1, dtype=np.float64) * (period / per)
    run = simulate_bed(
        th, k, e, t_eval=t, wall=sine(w0, amp, om, math.pi / 2), gamma=gm, inertia=mu,
        womersley=alpha, rtol=rt, atol=rt, max_steps=10_000_000,
    )  # fmt: skip
    last = slice(nper * per - per, nper * per)
    prev = slice(nper * per - 2 * per, nper * per - per)
    tl = np.asarray(t[last], dtype=np.float64)
    strain = g0 * np.sin(om * tl)
    stress = np.asarray(run.wall_stress[last], dtype=np.float64)
    quasi = _quasi_static(w0, amp, om, tl, e, th, k, gm)
    if int(run.status) != 0 or not np.all(np.isfinite(run.wall_stress)):
        return LargeAmplitudeShear(
            om, g0, w0, tl, strain, stress, quasi, None, nper, math.nan, int(run.status),
            int(run.nsteps), -1,
        )  # fmt: skip
    big = float(np.max(np.abs(stress)))
    err = float(np.max(np.abs(stress - run.wall_stress[prev]))) / (big if big > 0 else 1.0)
    res = analyse_laos(tl, strain, stress)
    return LargeAmplitudeShear(
        om, g0, w0, tl, strain, stress, quasi, res, nper, err, 0, int(run.nsteps),
        0 if err <= tol else 1,
    )  # fmt: skip


def _quasi_static(
    w0: float, amp: float, om: float, tl: FloatArray, eps: float, theta0: float, kappa: float,
    gamma: float,
) -> FloatArray:  # fmt: skip
    """The static bed's top stress at the instantaneous forcing (solve_porous)."""
    qs = solve_porous(w0 + amp * np.cos(om * tl), eps, theta0, kappa=kappa, gamma=gamma)
    return np.asarray(qs.tip_stress, dtype=np.float64)  # Q(H) = Q(h1) under the wall drive


@dataclass(frozen=True)
class PipkinMap:
    """LAOS measures over frequency and strain amplitude (:func:`pipkin_map`).

    Arrays are (frequency, amplitude).

    Attributes
    ----------
    omega, strain_amplitude : ndarray
        The axes [1/T], [-].
    storage, loss : ndarray
        The first harmonic's G'_1, G''_1 [E I/(A L^2)].
    third_harmonic : ndarray
        I_3/I_1 [-] (the odd nonlinearity).
    even_ratio : ndarray
        The even part's size over I_1 [-] (a tilted bed's asymmetry).
    large_modulus, minimum_modulus, large_viscosity, minimum_viscosity : ndarray
        Ewoldt's G'_L, G'_M [E I/(A L^2)], eta'_L, eta'_M [E I T/(A L^2)].
    status : ndarray of int
        ``LARGE_STATUS`` of each run.
    """

    omega: FloatArray
    strain_amplitude: FloatArray
    storage: FloatArray
    loss: FloatArray
    third_harmonic: FloatArray
    even_ratio: FloatArray
    large_modulus: FloatArray
    minimum_modulus: FloatArray
    large_viscosity: FloatArray
    minimum_viscosity: FloatArray
    status: NDArray[np.int64]

    @property
    def success(self) -> Any:
        """True where status is 0."""
        return self.status == 0

    def to_xarray(self) -> Any:
        """An xarray.Dataset with dimensions ``frequency`` and ``amplitude`` (units, long
        names). Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "PipkinMap.to_xarray", "io")
        dims = ("frequency", "amplitude")
        mod, vis = "E I/(A L^2)", "E I T/(A L^2)"
        fields = {
            "storage": (self.storage, mod, "first-harmonic storage modulus G'_1"),
            "loss": (self.loss, mod, "first-harmonic loss modulus G''_1"),
            "third_harmonic": (self.third_harmonic, "1", "I_3/I_1"),
            "even_ratio": (self.even_ratio, "1", "even part over I_1"),
            "large_modulus": (self.large_modulus, mod, "G'_L (Ewoldt 2008)"),
            "minimum_modulus": (self.minimum_modulus, mod, "G'_M (Ewoldt 2008)"),
            "large_viscosity": (self.large_viscosity, vis, "eta'_L (Ewoldt 2008)"),
            "minimum_viscosity": (self.minimum_viscosity, vis, "eta'_M (Ewoldt 2008)"),
            "status": (self.status, "1", "status"),
        }
        return xr.Dataset(
            {n: (dims, v, {"units": u, "long_name": ln}) for n, (v, u, ln) in fields.items()},
            coords={
                "frequency": ("frequency", self.omega, {"units": "1/T", "long_name": "omega"}),
                "amplitude": ("amplitude", self.strain_amplitude, {"units": "1"}),
            },
            attrs={"title": "hairbed porous bed: Pipkin map", "Conventions": "CF-1.10"},
        )  # fmt: skip


def pipkin_map(
    omegas: Any, strain_amplitudes: Any, *, workers: int = 1, **kwargs: Any
) -> PipkinMap:
    """:func:`large_amplitude_shear` over a grid of frequencies [1/T] and strain amplitudes
    [-] (one run each; ``kwargs`` as that function's): the Pipkin map's measures.

    ``workers`` processes in [1, 64] share the runs, one cell at a time as each frees
    (forked where the platform can, so a worker starts with the parent's compiled kernels;
    threads could not: about a quarter of a collocation run is Python, holding the GIL).
    ``method="transient"`` in ``kwargs`` runs the baseline."""
    om = np.atleast_1d(np.asarray(omegas, dtype=np.float64)).reshape(-1)
    ga = np.atleast_1d(np.asarray(strain_amplitudes, dtype=np.float64)).reshape(-1)
    nw = check_int(workers, "workers", 1, 64)
    shape = (om.size, ga.size)
    names = ("storage", "loss", "third_harmonic", "even_ratio", "large_modulus",
             "minimum_modulus", "large_viscosity", "minimum_viscosity")  # fmt: skip
    vals = {n: np.full(shape, np.nan) for n in names}
    status = np.full(shape, -1, dtype=np.int64)
    cells = [(i, j) for i in range(om.size) for j in range(ga.size)]

    omega_of = [float(om[i]) for i, _ in cells]
    gamma_of = [float(ga[j]) for _, j in cells]
    if nw == 1 or len(cells) < 2:
        results = [large_amplitude_shear(w, g, **kwargs) for w, g in zip(omega_of, gamma_of)]
    else:
        results = _on_processes(nw, omega_of, gamma_of, kwargs)
    for (i, j), r in zip(cells, results):
        status[i, j] = r.status
        a = r.analysis
        if a is None:
            continue
        vals["storage"][i, j] = a.storage[0]
        vals["loss"][i, j] = a.loss[0]
        vals["third_harmonic"][i, j] = a.relative_intensity[2] if a.harmonic.size > 2 else 0.0
        vals["even_ratio"][i, j] = a.even_ratio
        vals["large_modulus"][i, j] = a.large_modulus
        vals["minimum_modulus"][i, j] = a.minimum_modulus
        vals["large_viscosity"][i, j] = a.large_viscosity
        vals["minimum_viscosity"][i, j] = a.minimum_viscosity
    return PipkinMap(omega=om, strain_amplitude=ga, status=status, **vals)


def _quiet_worker() -> None:
    """A worker leaves Ctrl-C to the parent (one line, exit 130), which ends the pool."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _cell(omega: float, gamma0: float, kwargs: dict[str, Any]) -> LargeAmplitudeShear:
    return large_amplitude_shear(omega, gamma0, **kwargs)


def _on_processes(
    workers: int, omegas: list[float], gammas: list[float], kwargs: dict[str, Any]
) -> list[LargeAmplitudeShear]:
    """The cells on ``workers`` processes, in order, each handed out as a worker frees."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    methods = multiprocessing.get_all_start_methods()
    ctx = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with ProcessPoolExecutor(workers, mp_context=ctx, initializer=_quiet_worker) as pool:
        return list(pool.map(_cell, omegas, gammas, [kwargs] * len(omegas)))
