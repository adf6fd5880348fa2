"""Snap-through in time: a slow ramp through the upper fold of a pillar's window (issue 31 1d).

A pillar tilted far upstream has a snap-through window (theory.md §12): its branch of static
states turns at an upper fold Lambda_f. :func:`snap_through` takes the fold from the statics
(``continue_pillar``), ramps the forcing at a given rate from the near branch through it in
time (:func:`simulate_pillar`, the jump event of status -9 locating the jump), then holds the
forcing at its value at the jump and follows the pillar onto the far branch: the delay of the
jump behind the static fold, the states before and after (the after-state against the statics'
state at the held forcing) and, with inertia, the ringing's frequency and decay rate fitted
from the tip deflection (theory.md §14).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .._core.pillar import WINDOW_THETA0
from .._core.pillar_branch import continue_pillar, solve_pillar_all
from .._core.validation import StatusResult, check_int, check_number, check_positive
from ._integrate import PillarTrajectory, simulate_pillar
from ._signals import ramp

__all__ = ["SNAP_STATUS", "SnapThrough", "snap_through"]

FloatArray = NDArray[np.float64]
#: Damped pairs fitted to the ringing.
_PAIRS = 2

#: The status codes of a :class:`SnapThrough`.
SNAP_STATUS: Mapping[int, str] = MappingProxyType(
    {
        0: "the jump was found and the pillar settled on the statics' state after it",
        1: (
            "the pillar had not settled within `settle_tol` of the statics' state at the "
            "end of the run (lengthen `settle_time`)"
        ),
        -1: (
            "no jump: the tip's speed never reached `jump_speed` on the ramp to the fold "
            "plus `overshoot` (lower `jump_speed` or raise `overshoot`)"
        ),
        -2: "the integration failed (the trajectory's status and message say how)",
    }
)

#: Where a window exists for the sublayer profile at gamma = 1/2 (theory.md §12: the cusp
#: lies between theta0 = -1.35 and -1.3; none was found above -1.3).
_WINDOW_TEXT = (
    "a snap-through window exists only for a pillar tilted far upstream: theta0 below the "
    "cusp, which lies between -1.35 and -1.3 for the sublayer profile at gamma = 1/2 "
    "(theory.md §12), down to -pi/2"
)


@dataclass(frozen=True)
class SnapThrough(StatusResult):
    """A snap-through in time (theory.md §14); time in T = zeta_perp L^4/(E I), lengths in L.

    Attributes
    ----------
    theta0, rate, mu, gamma : float
        The inputs: base angle [rad], ramp rate dLambda/dt [1/T], inertia number [-], drag
        ratio [-].
    fold_forcing, fold_deflection : float
        The static upper fold Lambda_f [-] and its tip deflection [L] (``continue_pillar``).
    lower_fold_forcing : float
        The window's lower fold [-].
    start_forcing : float
        The forcing the ramp starts from [-], at rest on the near branch.
    fold_time : float
        When the ramp crosses the static fold [T], (Lambda_f - start_forcing)/rate.
    jump_time : float
        The jump [T]: where the tip's speed first reaches ``jump_speed`` (status -9 of
        :func:`simulate_pillar`).
    delay : float
        jump_time - fold_time [T] (the slow passage past a fold: about rate^(-1/3)).
    jump_forcing : float
        Lambda at the jump [-]; the forcing is held there afterwards (the final forcing).
    before_tip_deflection, before_tip_height : float
        The state as the ramp crosses the fold, t = fold_time [L].
    after_tip_deflection, after_tip_height : float
        The state at the end of the run, ``settle_time`` after the jump [L].
    static_tip_deflection, static_tip_height : float
        The statics' state at ``jump_forcing`` (past the window: the far branch's) [L].
    settle_error : float
        max of abs(after - static) over the tip deflection and height [L].
    ring_frequency, ring_decay : float
        With inertia, the angular frequency omega [rad/T] and decay rate delta [1/T] of the
        tip deflection's ringing after the jump: the larger of two damped pairs c + sum A
        exp(-delta t) cos(omega t + phi) fitted from 8 mu after the jump (the large motion
        decayed) to 0.6 ``settle_time``; NaN overdamped (mu = 0, or no oscillation).
    trajectory : PillarTrajectory
        The run: the ramp to the jump, then the hold (t from 0 at start_forcing).
    status : int
        ``SNAP_STATUS``: 0 done; 1 not settled; -1 no jump; -2 the integration failed.
    """

    theta0: float
    rate: float
    mu: float
    gamma: float
    fold_forcing: float
    fold_deflection: float
    lower_fold_forcing: float
    start_forcing: float
    fold_time: float
    jump_time: float
    delay: float
    jump_forcing: float
    before_tip_deflection: float
    before_tip_height: float
    after_tip_deflection: float
    after_tip_height: float
    static_tip_deflection: float
    static_tip_height: float
    settle_error: float
    ring_frequency: float
    ring_decay: float
    trajectory: PillarTrajectory | None
    status: int

    _status_table: ClassVar[Mapping[int, str]] = SNAP_STATUS


def _window(
    theta0: float, profile: Any, height_ratio: float | None, gamma: float
) -> tuple[float, float, float]:
    """(upper fold's Lambda, its x1, lower fold's Lambda) from the statics, or a ValueError
    naming theta0 and where windows exist. The branch is continued to doubling forcings
    (20 to 20 * 2^11) until it has passed both folds; above ``WINDOW_THETA0`` (-1.2), where
    the statics themselves take the branch to have no window, at once."""
    if theta0 > WINDOW_THETA0:
        raise ValueError(
            f"theta0 = {theta0!r} has no snap-through window (above {WINDOW_THETA0}, where "
            f"the pillar's branch has no fold); {_WINDOW_TEXT}"
        )
    end = 20.0
    for _ in range(12):
        folds = continue_pillar(
            end, theta0, profile=profile, height_ratio=height_ratio, gamma=gamma
        ).folds
        if folds.shape[0] >= 2:
            return float(folds[0, 0]), float(folds[0, 1]), float(folds[1, 0])
        end *= 2.0
    raise ValueError(
        f"theta0 = {theta0!r} has no snap-through window (no fold on the branch of static "
        f"states up to Lambda = {end / 2.0:g}); {_WINDOW_TEXT}"
    )


def _fit_ringing(t: FloatArray, x: FloatArray) -> tuple[float, float]:
    """(omega, delta) of the dominant damped oscillation of x(t) on uniform t: x ~ c +
    sum_k A_k exp(-delta_k t) cos(omega_k t + phi_k) over two pairs (the slowest mode and the
    next, which lingers as long: the drag damps the modes about alike). Prony's order-5
    recurrence by least squares gives the start, nonlinear least squares on the samples
    refines it; the pair of the larger amplitude is returned, NaN where the recurrence has
    no complex pair."""
    from scipy.optimize import least_squares

    dt = float(t[1] - t[0])
    order = 2 * _PAIRS + 1
    rows = np.stack([x[order - 1 - k : x.size - 1 - k] for k in range(order)], axis=1)
    coef = np.linalg.lstsq(rows, x[order:], rcond=None)[0]
    roots = np.log(np.roots(np.concatenate([[1.0], -coef])).astype(np.complex128)) / dt
    pairs = roots[roots.imag > 1e-9 * np.abs(roots)]
    if pairs.size == 0:
        return math.nan, math.nan
    tau = t - t[0]
    cols = [np.ones_like(tau)]
    for s in pairs:
        e = np.exp(s.real * tau)
        cols += [e * np.cos(s.imag * tau), e * np.sin(s.imag * tau)]
    lin = np.linalg.lstsq(np.stack(cols, axis=1), x, rcond=None)[0]
    p0 = np.concatenate(
        [[lin[0]]]
        + [[lin[1 + 2 * k], lin[2 + 2 * k], s.imag, -s.real] for k, s in enumerate(pairs)]
    )

    def resid(p: FloatArray) -> FloatArray:
        y = np.full_like(tau, p[0])
        for k in range(pairs.size):
            a, b, w, d = p[1 + 4 * k : 5 + 4 * k]
            y = y + np.exp(-d * tau) * (a * np.cos(w * tau) + b * np.sin(w * tau))
        return np.asarray(y - x)

    with np.errstate(over="ignore", invalid="ignore"):
        fit = least_squares(resid, p0, x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    q = fit.x[1:].reshape(-1, 4)
    k = int(np.argmax(np.hypot(q[:, 0], q[:, 1])))
    return abs(float(q[k, 2])), float(q[k, 3])


def snap_through(
    theta0: float,
    *,
    rate: float,
    mu: float = 0.0,
    gamma: float = 0.5,
    tangential_mass: float = 1.0,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    start_forcing: float | None = None,
    overshoot: float | None = None,
    jump_speed: float = 0.1,
    settle_time: float | None = None,
    settle_tol: float = 1e-6,
    samples: int = 4001,
    num: int = 32,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 200_000,
) -> SnapThrough:
    """A pillar's snap-through in time: a slow ramp of the forcing through the upper fold of
    its window (theory.md §14).

    The static folds come from :func:`hairbed.continue_pillar`. The pillar starts at rest on
    the near branch at ``start_forcing``, the forcing rises at ``rate`` until the jump event
    (:func:`simulate_pillar` with ``jump_speed``, status -9), then it is held at its value
    there, and the run goes on for ``settle_time``: the pillar crosses to the far branch (and
    rings, with inertia) and settles on the statics' state at the held forcing.

    Parameters
    ----------
    theta0 : float
        The base angle [rad], tilted upstream far enough to have a window (about < -1.33 for
        the sublayer at gamma = 1/2).
    rate : float
        dLambda/dt [1/T] > 0 of the ramp.
    mu, gamma, tangential_mass, profile, height_ratio : optional
        As in :func:`simulate_pillar`.
    start_forcing : float, optional
        Lambda [-] the ramp starts from, inside the window (between its folds); default the
        upper fold less a tenth of the window's width.
    overshoot : float, optional
        How far past the fold [-] the ramp may go looking for the jump (status -1 where it
        finds none); default a tenth of the fold's forcing.
    jump_speed : float, optional
        The jump event's threshold on the tip's speed [L/T] (default 0.1: the quasi-static
        motion at rates up to 1e-2 stays below 0.01, a jump reaches 0.3 (mu = 13) to 1.5
        (mu = 0)).
    settle_time : float, optional
        The run after the jump [T]; default 5 + 40 mu (ringing decays at about 1/(2 mu)).
    settle_tol : float, optional
        The after-state's tolerance against the statics' [L] (status 1 beyond).
    samples : int, optional
        Output times after the jump (uniform; the ringing is fitted on them), in [64, 10^6].
    num, rtol, atol, max_steps : optional
        As in :func:`simulate_pillar`.

    Returns
    -------
    SnapThrough

    Raises
    ------
    ValueError
        For a theta0 without a window (naming the range where one exists), a start outside
        the window, and inputs outside their ranges.
    """
    t0 = check_number(theta0, "theta0", low=-0.5 * np.pi, high=0.5 * np.pi, low_open=True,
                      high_open=True)  # fmt: skip
    r = check_positive(rate, "rate")
    m = check_number(mu, "mu", low=0.0)
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    speed = check_positive(jump_speed, "jump_speed")
    tol = check_positive(settle_tol, "settle_tol")
    nsamp = check_int(samples, "samples", 64, 10**6)
    lam_f, x_f, lam_low = _window(t0, profile, height_ratio, g)
    width = lam_f - lam_low
    lam0 = (
        lam_f - 0.1 * width
        if start_forcing is None
        else check_number(
            start_forcing, "start_forcing", low=lam_low, high=lam_f, low_open=True, high_open=True
        )  # fmt: skip
    )
    over = 0.1 * lam_f if overshoot is None else check_positive(overshoot, "overshoot")
    settle = 5.0 + 40.0 * m if settle_time is None else check_positive(settle_time, "settle_time")
    kw: dict[str, Any] = dict(
        theta0=t0, profile=profile, height_ratio=height_ratio, gamma=g, mu=m,
        tangential_mass=tangential_mass, num=num, rtol=rtol, atol=atol, max_steps=max_steps,
    )  # fmt: skip
    start = solve_pillar_all(lam0, t0, profile=profile, height_ratio=height_ratio, gamma=g)[0]
    t_fold = (lam_f - lam0) / r
    t_over = (lam_f + over - lam0) / r
    # 1. the ramp to the jump: the event's time
    first = simulate_pillar(
        ramp(lam0, lam_f + over, 0.0, t_over), [0.0, t_fold, t_over], initial=start,
        jump_speed=speed, **kw,
    )  # fmt: skip
    nan = math.nan

    def result(status: int, traj: PillarTrajectory | None, **vals: float) -> SnapThrough:
        base = dict.fromkeys(
            ("jump_time", "delay", "jump_forcing", "after_tip_deflection", "after_tip_height",
             "static_tip_deflection", "static_tip_height", "settle_error", "ring_frequency",
             "ring_decay"),
            nan,
        )  # fmt: skip
        base.update(vals)
        return SnapThrough(
            theta0=t0, rate=r, mu=m, gamma=g, fold_forcing=lam_f, fold_deflection=x_f,
            lower_fold_forcing=lam_low, start_forcing=lam0, fold_time=t_fold,
            before_tip_deflection=float(first.tip_deflection[1]),
            before_tip_height=float(first.tip_height[1]), trajectory=traj, status=status,
            **base,
        )  # fmt: skip

    if first.status == 0:
        return result(-1, first)
    if first.status != -9:
        return result(-2, first)
    t_jump = first.t_end
    lam_jump = lam0 + r * t_jump
    # 2. the same ramp to the jump, held there: the crossing, the ringing, the far state
    after = np.linspace(t_jump, t_jump + settle, nsamp)
    run = simulate_pillar(
        ramp(lam0, lam_jump, 0.0, t_jump), np.concatenate([[0.0, t_fold], after]),
        initial=start, **kw,
    )  # fmt: skip
    vals = dict(jump_time=t_jump, delay=t_jump - t_fold, jump_forcing=lam_jump)
    if not run.success:
        return result(-2, run, **vals)
    far = solve_pillar_all(lam_jump, t0, profile=profile, height_ratio=height_ratio, gamma=g)[-1]
    xa, ha = float(run.tip_deflection[-1]), float(run.tip_height[-1])
    xs, hs = float(far.tip_deflection), float(far.tip_height)
    err = max(abs(xa - xs), abs(ha - hs))
    om = de = nan
    if m > 0.0:  # the ringing, once the jump's large motion has decayed (after 8 mu)
        ta, xt = run.t[2:], run.tip_deflection[2:]
        sel = (ta >= t_jump + min(8.0 * m, 0.25 * settle)) & (ta <= t_jump + 0.6 * settle)
        if int(sel.sum()) >= 16:
            om, de = _fit_ringing(ta[sel], xt[sel])
    vals.update(
        after_tip_deflection=xa, after_tip_height=ha, static_tip_deflection=xs,
        static_tip_height=hs, settle_error=err, ring_frequency=om, ring_decay=de,
    )  # fmt: skip
    return result(0 if err <= tol else 1, run, **vals)
