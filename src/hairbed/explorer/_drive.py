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

The views beside the animation are a registry, ``SIDE_VIEWS``: the Bode view now; the bed's
Lissajous view (the rheometer) joins it there, with its own entry and figure.
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

__all__ = [
    "BODE_OMEGA",
    "DRAG_MODELS",
    "DRIVE_DEFAULTS",
    "FRAMES",
    "NODES",
    "SIDE_VIEWS",
    "DriveAnimation",
    "DriveParams",
    "drive_animation",
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
}
#: The Bode view's drag models (the animation is always quasi-steady).
DRAG_MODELS = ("quasi-steady", "sader")
#: The views beside the animation: name -> label. The bed's Lissajous view (the rheometer's
#: stress against strain) joins here.
SIDE_VIEWS: dict[str, str] = {"bode": "Bode view of the tip deflection"}
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
    """

    amplitude: float
    frequency: float
    mu: float
    drag_model: str


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
    params = DriveParams(values["amplitude"], values["frequency"], values["mu"], model)
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
