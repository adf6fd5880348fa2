"""The pillar mode's animated drive, without any web framework (issue 31, theory.md §14).

The pillar's "drive" view moves the pillar in an oscillating flow,

    Lambda(t) = Lambda_mean + A sin(omega t)    (t in T = zeta_perp L^4/(E I)),

beside its Bode view. The animation is the nonlinear pillar in time
(:func:`hairbed.dynamics.simulate_pillar`, quasi-steady resistive-force drag with the fluid's
added mass), started from the static state at Lambda_mean, run until its slowest mode has
decayed by ``SETTLE`` (ln(1/SETTLE)/delta, delta the decay rate of the linear modes about
the mean state, rounded up to whole periods, at most ``MAX_SETTLE_PERIODS`` periods), then
one period sampled at ``FRAMES`` frames: the shape at each frame, played in a loop by the
page (each frame only sends the precomputed shape: the server's work per frame is a copy).
The Bode view is the linear transfer function from Lambda to the tip deflection about the
mean state (:meth:`hairbed.dynamics.LinearPillar.frequency_response`) with the chosen drag
model: "quasi-steady" (the same model as the animation) or "sader" (Sader's oscillating
cylinder, which only the linear response has); the nonlinear run's first harmonic per
amplitude is marked at the drive's frequency beside it (-> the linear value as A -> 0).

The inertia number ``mu`` is the solid's, m_s E I/(zeta_perp^2 L^4). The fluid's density is
taken equal to the pillar's (a neutrally buoyant pillar, as PDMS in water): the quasi-steady
model's mass is then 2 m_s with the tangential/normal mass ratio chi = 1/2 (theory.md §14,
D3), and Sader's Reynolds scale R = rho_f b^2/(4 eta T) = 4 mu/(ln(2 L/a) + 1/2) needs the
slenderness L/a.

The views beside the animation are a registry, ``SIDE_VIEWS`` (URL key ``side_view``): the
Bode view, and the Lissajous view of a bed of such hairs in a rheometer
(:func:`lissajous_view`): the porous bed (theory.md §13, kappa and eps of the URL keys
``bed_kappa``, ``bed_eps``, the pillar's base angle) whose top wall is driven by the same
forcing, omega2(t) = Lambda_mean + A sin(omega t), i.e. the strain
gamma = -A cos(omega t)/(kappa omega) about the steady shear of Lambda_mean
(:func:`hairbed.rheometer.large_amplitude_shear`, its periodic state sampled at the FRAMES
phases of the animation's frames): the wall's stress against the strain and against the
strain rate (the Lissajous-Bowditch curves, with Cho's elastic and viscous parts), and the
point of the frame on screen.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import hairbed
from hairbed.dynamics import linearise_pillar, simulate_pillar, sine
from hairbed.rheometer import large_amplitude_shear

__all__ = [
    "BODE_OMEGA",
    "DRAG_MODELS",
    "DRIVE_DEFAULTS",
    "FRAMES",
    "NODES",
    "SIDE_VIEWS",
    "DriveAnimation",
    "DriveParams",
    "LissajousView",
    "drive_animation",
    "lissajous_view",
    "validate_drive",
]

#: The drive view's inputs and their defaults (URL keys, carried in the drive view only):
#: the amplitude A of Lambda [-], the angular frequency omega [1/T], the solid's inertia
#: number mu [-] and the drag model of the Bode view.
DRIVE_DEFAULTS: dict[str, str] = {
    "amplitude": "0.5",
    "frequency": "5",
    "mu": "1",
    "drag_model": "quasi-steady",
    "side_view": "bode",
    "bed_kappa": "1",
    "bed_eps": "0.5",
}
#: The Lissajous view's keys (carried by the URL in that side view only).
LISSAJOUS_KEYS = ("bed_kappa", "bed_eps")
#: The Bode view's drag models (the animation is always quasi-steady).
DRAG_MODELS = ("quasi-steady", "sader")
#: The views beside the animation: name -> label.
SIDE_VIEWS: dict[str, str] = {
    "bode": "Bode view of the tip deflection",
    "lissajous": "Lissajous view of a bed in a rheometer",
}
#: The Lissajous view's kappa and eps ranges (those of hairbed.rheometer).
_KAPPA_RANGE, _EPS_RANGE = (1e-4, 1e6), (1e-6, 1.0)
#: Frames of the animation's period, and the largest settling time in periods.
FRAMES = 48
MAX_SETTLE_PERIODS = 200
#: The transient's decay before the period is sampled.
SETTLE = 1e-4
#: The Bode view's frequencies omega [1/T].
BODE_OMEGA = np.geomspace(1e-2, 1e3, 151)
#: The integrator's settings: degree, tolerances, step bound.
_NUM, _RTOL, _ATOL, _MAX_STEPS = 16, 1e-6, 1e-8, 40_000
#: Points of each frame's shape: the run's collocation nodes, base first, the tip last.
NODES = _NUM + 1
#: The largest amplitude and frequency taken.
_MAX_AMPLITUDE, _MAX_OMEGA = 1e3, 1e3


@dataclass(frozen=True)
class DriveParams:
    """Validated inputs of the drive view.

    Attributes
    ----------
    amplitude : float
        A >= 0 [-], of the forcing.
    frequency : float
        omega > 0 [1/T].
    mu : float
        The solid's inertia number >= 0 [-].
    drag_model : str
        "quasi-steady" or "sader" (the Bode view's).
    side_view : str
        A key of :data:`SIDE_VIEWS`.
    bed_kappa, bed_eps : float
        The Lissajous view's bed: kappa > 0 and eps = L/H in (0, 1) [-].
    """

    amplitude: float
    frequency: float
    mu: float
    drag_model: str
    side_view: str = "bode"
    bed_kappa: float = 1.0
    bed_eps: float = 0.5


def _number(text: str) -> float | None:
    try:
        value = float(text.strip())
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def validate_drive(
    full: dict[str, str], slenderness: float | None
) -> tuple[DriveParams, list[str]]:
    """The drive view's inputs from the page's text ``full`` (every key of
    :data:`DRIVE_DEFAULTS`), and the problems found (each naming its input and range)."""
    problems: list[str] = []
    values: dict[str, float] = {}
    ranges = {
        "amplitude": (0.0, _MAX_AMPLITUDE, "an amplitude of Lambda in [0, 1e3]"),
        "frequency": (0.0, _MAX_OMEGA, "an angular frequency omega [1/T] in (0, 1e3]"),
        "mu": (0.0, 1e3, "an inertia number in [0, 1e3]"),
    }
    for key, (lo, hi, what) in ranges.items():
        v = _number(full[key])
        ok = v is not None and lo <= v <= hi and not (key == "frequency" and v == 0.0)
        if not ok:
            problems.append(f"{key} must be {what}, got {full[key]!r}")
        values[key] = v if ok and v is not None else 0.0
    model = full["drag_model"].strip()
    if model not in DRAG_MODELS:
        problems.append(f"drag_model must be one of 'quasi-steady', 'sader', got {model!r}")
    elif model == "sader" and slenderness is None:
        problems.append(
            "drag_model 'sader' needs the slenderness L/a (Sader's drag depends on the "
            "pillar's radius)"
        )
    side = full.get("side_view", DRIVE_DEFAULTS["side_view"]).strip()
    bed = {"bed_kappa": 1.0, "bed_eps": 0.5}
    if side not in SIDE_VIEWS:
        problems.append(
            f"side_view must be one of {', '.join(map(repr, SIDE_VIEWS))}, got {side!r}"
        )
    elif side == "lissajous":
        for key, (lo, hi), what in (
            ("bed_kappa", _KAPPA_RANGE, "the bed's kappa in [1e-4, 1e6]"),
            ("bed_eps", _EPS_RANGE, "the bed's eps = L/H in [1e-6, 1)"),
        ):
            v = _number(full.get(key, DRIVE_DEFAULTS[key]))
            if v is None or not lo <= v <= hi or (key == "bed_eps" and v == hi):
                problems.append(f"{key} must be {what}, got {full.get(key)!r}")
            else:
                bed[key] = v
        if values["amplitude"] == 0.0 and not any(p.startswith("amplitude") for p in problems):
            problems.append("amplitude must be > 0 in the Lissajous view (a strain to shear by)")
    params = DriveParams(values["amplitude"], values["frequency"], values["mu"], model, side,
                         bed["bed_kappa"], bed["bed_eps"])  # fmt: skip
    return params, problems


@dataclass(frozen=True)
class DriveAnimation:
    """One period of the pillar's periodic motion, and its Bode view.

    Attributes
    ----------
    t : ndarray
        The frames' times in the period [T] (from the start of the sampled period).
    x, z : ndarray
        The shape at each frame, (frame, node) [L] at the collocation nodes (base first).
    tip_x, tip_z : ndarray
        The tip at each frame [L].
    forcing : ndarray
        Lambda at each frame [-].
    mean_x, mean_z : ndarray
        The static shape at the mean forcing [L].
    harmonic : complex
        The nonlinear run's first harmonic of x1 per amplitude (x1's Fourier coefficient
        at omega over -i A) [L].
    omega : ndarray
        The Bode view's frequencies [1/T].
    bode : ndarray of complex
        dx1/dLambda at ``omega`` with the chosen drag model [L].
    bode_now : complex
        The same at the drive's frequency.
    settle : float
        The time run before the sampled period [T].
    steps : int
        The integrator's accepted steps.
    status : int
        0, or the run's status (negative: no animation; ``message`` says why).
    message : str
        "" or why there is no animation.
    timings : dict
        "solve" [ms]: the run and the response.
    """

    t: np.ndarray
    x: np.ndarray
    z: np.ndarray
    tip_x: np.ndarray
    tip_z: np.ndarray
    forcing: np.ndarray
    mean_x: np.ndarray
    mean_z: np.ndarray
    harmonic: complex
    omega: np.ndarray
    bode: np.ndarray
    bode_now: complex
    settle: float
    steps: int
    status: int
    message: str = ""
    timings: dict[str, float] = field(default_factory=dict)


def _bode(lin: Any, omega: np.ndarray, model: str, mu: float, slenderness: float | None) -> Any:
    if model == "sader" and slenderness is not None:
        reynolds = 4.0 * mu / (math.log(2.0 * slenderness) + 0.5)
        return lin.frequency_response(omega, unsteady_drag=(reynolds, slenderness)).tip_deflection
    return lin.frequency_response(omega).tip_deflection


@functools.lru_cache(maxsize=32)
def drive_animation(
    forcing: float, theta0: float, profile: str, height_ratio: float | None, gamma: float,
    tip_load: float, slenderness: float | None, amplitude: float, omega: float, mu: float,
    drag_model: str,
) -> DriveAnimation:  # fmt: skip
    """The animation and the Bode view of a pillar driven by Lambda_mean + A sin(omega t)
    (the module's description), cached per input."""
    import warnings

    start = time.perf_counter()
    kw: dict[str, Any] = {"profile": profile, "height_ratio": height_ratio, "gamma": gamma}
    empty = np.zeros((0,))
    none = np.zeros((0, 0))

    def fail(status: int, message: str) -> DriveAnimation:
        return DriveAnimation(
            empty, none, none, empty, empty, empty, empty, empty, complex("nan"), BODE_OMEGA,
            np.full(BODE_OMEGA.shape, complex("nan")), complex("nan"), math.nan, 0, status,
            message, {"solve": 1e3 * (time.perf_counter() - start)},
        )  # fmt: skip

    st = hairbed.solve_pillar(forcing, theta0, tip_load=tip_load, **kw)
    if int(st.status) < 0:
        return fail(int(st.status), f"no static state at the mean forcing: {st.message}")
    mq, chi = 2.0 * mu, (0.5 if mu > 0.0 else 1.0)  # the fluid's added mass (rho_f = rho_s)
    lin_q = linearise_pillar(st, profile=profile, height_ratio=height_ratio, mu=mq,
                             tangential_mass=chi)  # fmt: skip
    lin = lin_q
    if drag_model == "sader":  # the solid's mass; the fluid's is in Sader's drag
        lin = linearise_pillar(st, profile=profile, height_ratio=height_ratio, mu=mu)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the validity notes are the page's, not per frame
        both = _bode(lin, np.append(BODE_OMEGA, omega), drag_model, mu, slenderness)
    rate = -float(np.max(lin_q.modes(4).eigenvalues.real))
    if not rate > 0.0:
        return fail(-1, "the mean state is not stable (a mode grows): no periodic motion")
    period = 2.0 * math.pi / omega
    periods = min(MAX_SETTLE_PERIODS, math.ceil(math.log(1.0 / SETTLE) / rate / period))
    settle = periods * period
    t = settle + period * np.arange(FRAMES + 1) / FRAMES
    run = simulate_pillar(
        sine(forcing, amplitude, omega), np.concatenate([[0.0], t]), theta0=theta0,
        tip_load=tip_load, mu=mq, tangential_mass=chi, num=_NUM, rtol=_RTOL, atol=_ATOL,
        max_steps=_MAX_STEPS, profile=profile, height_ratio=height_ratio, gamma=gamma,
    )  # fmt: skip
    if run.status < 0:
        return fail(int(run.status), f"the run stopped: {run.message}")
    ii = run._ops["ii"]
    theta = np.asarray(run.theta[1:-1], dtype=np.float64)  # FRAMES frames of one period
    x = np.sin(theta) @ ii.T
    z = np.cos(theta) @ ii.T
    x1 = np.asarray(run.tip_deflection[1:-1], dtype=np.float64)
    coef = (2.0 / FRAMES) * np.sum(x1 * np.exp(-1j * omega * t[:-1]))
    harmonic = complex(coef / (-1j * amplitude)) if amplitude > 0.0 else complex(both[-1])
    theta_mean = np.asarray(run.theta[0], dtype=np.float64)
    return DriveAnimation(
        t[:-1] - settle, x, z, x[:, -1].copy(), z[:, -1].copy(),
        np.asarray(run.forcing[1:-1], dtype=np.float64), np.sin(theta_mean) @ ii.T,
        np.cos(theta_mean) @ ii.T, harmonic, BODE_OMEGA, np.asarray(both[:-1]),
        complex(both[-1]), settle, int(run.naccept), 0, "",
        {"solve": 1e3 * (time.perf_counter() - start)},
    )  # fmt: skip


@dataclass(frozen=True)
class LissajousView:
    """The Lissajous view: the bed's periodic stress under the drive (the module's
    description), at the animation's frames and as closed curves.

    Attributes
    ----------
    strain, strain_rate, stress : ndarray
        At the FRAMES frames of the animation (frame k at the same phase of the forcing):
        gamma [-], its rate [1/T] and the top wall's stress [E I/(A L^2)].
    curve : dict of str to ndarray
        :meth:`hairbed.rheometer.LAOSAnalysis.lissajous` at 181 phases: ``strain``,
        ``strain_rate``, ``total``, ``elastic``, ``viscous``.
    strain_amplitude : float
        gamma0 = A/(kappa omega) [-].
    measures : dict of str to float
        G'_1, G''_1, G'_M, G'_L [E I/(A L^2)], eta'_M, eta'_L [E I T/(A L^2)], I_3/I_1, the
        even ratio, the periodicity error and the periods run.
    status : int
        :data:`hairbed.rheometer.LARGE_STATUS` (negative: no curve; ``message`` says why).
    message : str
        "" or the reason.
    timings : dict
        "solve" [ms].
    """

    strain: np.ndarray
    strain_rate: np.ndarray
    stress: np.ndarray
    curve: dict[str, np.ndarray]
    strain_amplitude: float
    measures: dict[str, float]
    status: int
    message: str = ""
    timings: dict[str, float] = field(default_factory=dict)


@functools.lru_cache(maxsize=32)
def lissajous_view(
    forcing: float, theta0: float, kappa: float, eps: float, amplitude: float, omega: float
) -> LissajousView:
    """The bed's periodic state under the wall forcing Lambda_mean + A sin(omega t)
    (:func:`hairbed.rheometer.large_amplitude_shear` with gamma0 = A/(kappa omega), sampled at
    FRAMES phases; its strain is gamma0 sin(omega t'), t' = t - P/4), cached per input."""
    import warnings

    start = time.perf_counter()
    empty = np.zeros(0)

    def fail(status: int, message: str) -> LissajousView:
        return LissajousView(empty, empty, empty, {}, math.nan, {}, status, message,
                             {"solve": 1e3 * (time.perf_counter() - start)})  # fmt: skip

    gamma0 = amplitude / (kappa * omega)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = large_amplitude_shear(omega, gamma0, eps=eps, kappa=kappa, theta0=theta0,
                                      forcing=forcing, samples=FRAMES)  # fmt: skip
    except ValueError as exc:
        return fail(-2, str(exc))
    a = r.analysis
    if a is None or r.status < 0:
        return fail(int(r.status), str(r.message))
    # frame k: omega t = 2 pi k/FRAMES, the bed's phase omega t' = omega t - pi/2
    phase = np.mod(omega * np.asarray(r.t, dtype=np.float64), 2.0 * math.pi)
    want = np.mod(2.0 * math.pi * np.arange(FRAMES) / FRAMES - 0.5 * math.pi, 2.0 * math.pi)
    gap = np.abs(np.angle(np.exp(1j * (want[:, None] - phase[None, :]))))
    idx = np.argmin(gap, axis=1)
    rate = gamma0 * omega * np.cos(omega * np.asarray(r.t, dtype=np.float64))
    curve = {k: v for k, v in a.lissajous(181).items() if k != "asymmetric"}
    measures = {
        "storage": float(a.storage[0]),
        "loss": float(a.loss[0]),
        "minimum_modulus": a.minimum_modulus,
        "large_modulus": a.large_modulus,
        "minimum_viscosity": a.minimum_viscosity,
        "large_viscosity": a.large_viscosity,
        "third_harmonic": float(a.relative_intensity[2]) if a.harmonic.size > 2 else 0.0,
        "even_ratio": a.even_ratio,
        "periodic_error": r.periodic_error,
        "periods": float(r.periods),
    }
    return LissajousView(
        np.asarray(r.strain, dtype=np.float64)[idx], rate[idx],
        np.asarray(r.stress, dtype=np.float64)[idx], curve, gamma0, measures, int(r.status),
        "" if r.status == 0 else str(r.message), {"solve": 1e3 * (time.perf_counter() - start)},
    )  # fmt: skip
