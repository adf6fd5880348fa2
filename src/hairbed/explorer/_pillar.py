"""The explorer's pillar mode, without any web framework: an isolated pillar (theory.md §12).

The mode selector of the page switches between the bed (:mod:`._model`) and one isolated
pillar in a wall shear layer. Its inputs are text, as typed or read from the URL, and are
checked one by one by the library (:func:`hairbed.solve_pillar`,
:func:`hairbed.gray_hancock_ratio`); the states are the library's: :func:`hairbed.solve_pillar`,
and where a snap-through window can exist (a pillar tilted far upstream, theta0 below
``WINDOW_THETA0`` against the flow) every coexisting state with its stability, read from the
pillar's cached branch (:func:`branch_states`; :func:`hairbed.solve_pillar_all` beyond it).
The calibration view draws the tip deflection x1 against the forcing
Lambda: the exact curve (a :func:`hairbed.solve_pillar` batch, and where a window can exist
the branch of :func:`hairbed.continue_pillar` with its folds and unstable part) against the
linear formula x1 = x1(0) + (dx1/dLambda at 0) Lambda, and the forcings where the linear
formula's reading of Lambda is 1 % and 10 % off (the error of :meth:`hairbed.Pillar.linear_range`
and ``fig_pillar_calibration``). The curve is cached per pillar (base angle, profile, height
ratio, drag ratio, tip load, the flow's direction), so a move of Lambda only moves the dot;
where a window can exist, the branch of :func:`hairbed.continue_pillar` is cached per pillar
too (:func:`pillar_branch`), and every forcing's states are read from it
(:func:`branch_states`): a new forcing in the window costs a few inverse solves, not a new
branch.

Everything here is plain Python and numpy, so it is tested without a browser.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import time
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlencode

import numpy as np

import hairbed
from hairbed._core.pillar import WINDOW_THETA0, profile_coefficients
from hairbed._jsonsafe import to_plain

from ._drive import (
    DRIVE_DEFAULTS,
    LISSAJOUS_KEYS,
    DriveAnimation,
    DriveParams,
    LissajousView,
    drive_animation,
    lissajous_view,
    validate_drive,
)
from ._model import DEFAULTS, INPUT_KEYS, PILLAR_DEFAULTS, InputError, _merge, _number, _recording

__all__ = [
    "CALIBRATION_GRID",
    "MODES",
    "PILLAR_CHOICES",
    "PILLAR_DEFAULTS",
    "PILLAR_FIELDS",
    "PILLAR_VIEWS",
    "Calibration",
    "PillarParams",
    "PillarView",
    "PillarSnapshot",
    "branch_states",
    "calibration_curve",
    "clear_pillar_caches",
    "compute_pillar",
    "mode_of",
    "is_pillar",
    "pillar_branch",
    "pillar_query",
    "pillar_snapshot_json",
    "validate_pillar",
]

#: The page's modes: a bed of hairs in a channel, or one isolated pillar.
MODES = ("bed", "pillar")
#: The pillar mode's views: its shape in the profile, its calibration curve, or its motion
#: in an oscillating flow beside its Bode view (:mod:`._drive`).
PILLAR_VIEWS = ("shape", "calibration", "drive")
#: The pillar's inputs chosen from a list (not typed).
PILLAR_CHOICES = ("mode", "profile", "pillar_view", "drag_model")
#: Every :class:`hairbed.PillarState` field shown and exported, in the dataclass's order.
PILLAR_FIELDS: tuple[str, ...] = (
    "forcing", "theta0", "gamma", "tip_load", "tip_deflection", "tip_height", "tip_angle",
    "base_curvature", "drag_x", "drag_z", "tip_deflection_slope", "status", "error_estimate",
    "residual", "nit", "num",
)  # fmt: skip
#: The forcings abs(Lambda) of the calibration curve [-] (and of the slider, in log10).
CALIBRATION_GRID = np.geomspace(1e-3, 1e4, 141)
#: Where a snap-through window can exist the branch is followed (:func:`hairbed.continue_pillar`)
#: up to this abs(Lambda), with this many points, and the batch carries the curve beyond.
BRANCH_FORCING = 100.0
BRANCH_POINTS = 300
#: The linear formula's error levels marked on the calibration curve.
ERROR_LEVELS = (0.01, 0.1)
#: Heights of the profile drawn beside the pillar [L].
PROFILE_POINTS = 41


def mode_of(raw: Any) -> str:
    """The mode the inputs (text, as typed) ask for: "bed" (also without a mode) or "pillar".

    Raises
    ------
    InputError
        For any other mode.
    """
    mode = str(raw.get("mode", "bed")).strip()
    if mode not in MODES:
        raise InputError([f"mode must be one of 'bed', 'pillar', got {mode!r}"])
    return mode


def is_pillar(raw: Any) -> bool:
    """Whether inputs (text, as typed) leave the bed's mode: for the pillar's, or for a bad
    mode (which :func:`mode_of` then names)."""
    return str(raw.get("mode", "bed")).strip() != "bed"


@dataclass(frozen=True)
class PillarParams:
    """Validated inputs of the pillar mode.

    Attributes
    ----------
    forcing : float
        Lambda = zeta_perp tau_w L^4/(eta E I) [-] (negative: flow towards -x).
    theta0 : float
        Base angle from the wall normal [rad].
    profile : str
        "sublayer", "couette" or "poiseuille".
    height_ratio : float or None
        L/H of a channel profile.
    slenderness : float or None
        L/a [-]; None: the slender limit.
    gamma : float
        zeta_par/zeta_perp [-]: :func:`hairbed.gray_hancock_ratio` of the slenderness, 1/2
        without one.
    tip_load : float
        A horizontal force on the tip [E I/L^2].
    view : str
        "shape", "calibration" or "drive".
    raw : dict
        Every input of the page as text, as validated.
    warnings : tuple of str
        The library's warnings while validating.
    drive : DriveParams or None
        The drive view's inputs (that view only).
    """

    forcing: float
    theta0: float
    profile: str
    height_ratio: float | None
    slenderness: float | None
    gamma: float
    tip_load: float
    view: str
    raw: dict[str, str] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    drive: DriveParams | None = None

    @property
    def kwargs(self) -> dict[str, Any]:
        """The keywords of :func:`hairbed.solve_pillar` beside the forcing and theta0."""
        return {
            "profile": self.profile,
            "height_ratio": self.height_ratio,
            "gamma": self.gamma,
            "tip_load": self.tip_load,
        }

    @property
    def window(self) -> bool:
        """A snap-through window can exist here: the pillar tilted far against the flow
        (theta0 below ``WINDOW_THETA0``, mirrored for a flow towards -x)."""
        return self.forcing != 0.0 and math.copysign(1.0, self.forcing) * self.theta0 < (
            WINDOW_THETA0
        )


def _problem(check: Any, *args: Any, **kwargs: Any) -> str | None:
    """The library's message if ``check`` refuses its arguments (ValueError or TypeError)."""
    try:
        check(*args, **kwargs)
    except (ValueError, TypeError) as exc:
        return " ".join(str(exc).split())
    return None


def validate_pillar(raw: Any) -> PillarParams:
    """Check the pillar mode's inputs with the library's own checks, each by name.

    Parameters
    ----------
    raw : mapping of str to str
        Inputs as typed (missing keys take their defaults).

    Returns
    -------
    PillarParams

    Raises
    ------
    InputError
        With the library's message for every bad input.

    Examples
    --------
    >>> validate_pillar({"mode": "pillar", "forcing": "2"}).forcing
    2.0
    >>> validate_pillar({"mode": "pillar", "pillar_theta0": "2"})
    Traceback (most recent call last):
    ...
    hairbed.explorer._model.InputError: theta0 must lie in (-pi/2, pi/2), got 2.0
    """
    problems: list[str] = []
    unknown = sorted(set(raw) - set(INPUT_KEYS))
    if unknown:
        problems.append(
            f"unknown parameter{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(repr(k) for k in unknown)}; known: {', '.join(INPUT_KEYS)}"
        )
    full = {k: str(raw.get(k, DEFAULTS[k])) for k in INPUT_KEYS}
    view = full["pillar_view"].strip()
    if view not in PILLAR_VIEWS:
        problems.append(
            f"pillar_view must be one of 'shape', 'calibration', 'drive', got {view!r}"
        )
    lam, t0, tip = (_number(full[k]) for k in ("forcing", "pillar_theta0", "tip_load"))
    profile = full["profile"].strip()
    ratio_text, slender_text = full["height_ratio"].strip(), full["slenderness"].strip()
    ratio = _number(ratio_text) if ratio_text else None
    slender = _number(slender_text) if slender_text else None
    gamma: Any = 0.5
    with _recording() as caught:
        # each alone, the others at rest and upright (a solve at Lambda = 0 is ~1 ms)
        for m in (
            _problem(hairbed.solve_pillar, lam),
            _problem(hairbed.solve_pillar, 0.0, t0),
            _problem(profile_coefficients, profile, ratio),
            _problem(hairbed.solve_pillar, 0.0, tip_load=tip),
        ):
            if m:
                problems.append(m)
        if slender is not None:
            m = _problem(hairbed.gray_hancock_ratio, slender)
            if m:
                problems.append(m)
            else:
                gamma = float(hairbed.gray_hancock_ratio(slender))
                m = _problem(hairbed.solve_pillar, 0.0, gamma=gamma)
                if m:  # a stubby pillar: Gray & Hancock's ratio leaves the solver's range
                    problems.append(
                        f"slenderness {slender!r} gives gamma = {gamma!r} "
                        f"(hairbed.gray_hancock_ratio), which the pillar refuses: {m}"
                    )
    drive = None
    if view == "drive":  # its inputs are checked (and carried by the URL) in that view only
        drive, bad = validate_drive(full, None if slender is None else float(slender))
        problems += bad
        full["drag_model"] = drive.drag_model
    if problems:
        raise InputError(problems)
    full["profile"], full["pillar_view"] = profile, view
    return PillarParams(
        float(lam), float(t0) + 0.0, profile, None if ratio is None else float(ratio),
        None if slender is None else float(slender), float(gamma), float(tip) + 0.0, view,
        raw=full, warnings=tuple(caught), drive=drive,
    )  # fmt: skip


def pillar_query(p: PillarParams) -> str:
    """The URL query string of a pillar view: the mode and every pillar input.

    Examples
    --------
    >>> pillar_query(validate_pillar({"mode": "pillar", "forcing": "2"}))
    '?mode=pillar&forcing=2&pillar_theta0=0&profile=sublayer&height_ratio=&slenderness=&tip_load=0&pillar_view=shape'
    """
    keys = (*PILLAR_DEFAULTS, *DRIVE_DEFAULTS) if p.view == "drive" else tuple(PILLAR_DEFAULTS)
    if p.drive is None or p.drive.side_view != "lissajous":  # the bed's keys in its view only
        keys = tuple(k for k in keys if k not in LISSAJOUS_KEYS)
    return "?" + urlencode({k: p.raw[k].strip() for k in keys} | {"mode": "pillar"})


@dataclass(frozen=True)
class Calibration:
    """The calibration curve of one pillar: x1 against Lambda, exact and linear.

    Attributes
    ----------
    forcing : ndarray
        abs(Lambda) along the curve [-], for the branch from rest in the flow's direction.
    tip_deflection : ndarray
        x1 there [L] (NaN where no state was found).
    stable : ndarray of bool
        Stable under a slow change of the forcing (False on the middle part of an S).
    folds : ndarray
        (k, 2): abs(Lambda) and x1 of each fold.
    rest : float
        x1 at Lambda = 0 [L] (sin theta0 without a tip load).
    slope : float
        dx1/dLambda at Lambda = 0 [L] (the state's ``tip_deflection_slope``), signed along the
        flow: the linear formula is x1 = rest + slope abs(Lambda).
    error : ndarray
        abs(Lambda_lin - Lambda)/Lambda [-], Lambda_lin = (x1 - rest)/slope: the linear
        formula's relative error in the forcing (the wall shear stress) it reads from the
        exact deflection, at each point of the curve.
    levels : dict of float to float
        The first abs(Lambda) where the error reaches each of :data:`ERROR_LEVELS` along the
        branch from rest (interpolated in log Lambda and log error; NaN: not reached).
    status : int
        0 every point converged; -7 some did not (NaN there).
    """

    forcing: np.ndarray
    tip_deflection: np.ndarray
    stable: np.ndarray
    folds: np.ndarray
    rest: float
    slope: float
    error: np.ndarray
    levels: dict[float, float]
    status: int

    def linear(self, forcing: Any) -> Any:
        """The linear formula's x1 at abs(Lambda) [L]."""
        return self.rest + self.slope * np.asarray(forcing, dtype=np.float64)


def _crossing(lam: np.ndarray, err: np.ndarray, level: float) -> float:
    """The first abs(Lambda) where ``err`` reaches ``level`` (log-log interpolation)."""
    ok = np.isfinite(err) & (err > 0.0)
    above = np.flatnonzero(ok & (err >= level))
    if above.size == 0:
        return math.nan
    i = int(above[0])
    if i == 0 or not ok[i - 1]:
        return float(lam[i])
    u0, u1 = math.log(err[i - 1]), math.log(err[i])
    t = (math.log(level) - u0) / (u1 - u0) if u1 != u0 else 1.0
    return float(math.exp(math.log(lam[i - 1]) + t * (math.log(lam[i]) - math.log(lam[i - 1]))))


@functools.lru_cache(maxsize=32)
def pillar_branch(
    sign: float, theta0: float, profile: str, height_ratio: float | None, gamma: float,
    tip_load: float, level: int,
) -> Any:  # fmt: skip
    """The branch of a pillar from rest in the flow's direction ``sign`` (+1 or -1), cached
    per pillar: :func:`hairbed.continue_pillar` to ``sign`` :data:`BRANCH_FORCING` 10^level
    with :data:`BRANCH_POINTS` points, or None where it failed (status < 0, or no point).

    The calibration curve (level 0) and every forcing's states in a snap-through window
    (:func:`branch_states`) read it: a new forcing solves no branch again.
    """
    kw = {"profile": profile, "height_ratio": height_ratio, "gamma": gamma, "tip_load": tip_load}
    end = sign * BRANCH_FORCING * 10.0**level
    branch = hairbed.continue_pillar(end, theta0, num=BRANCH_POINTS, **kw)
    if branch.status != 0 or branch.forcing.size < 2:
        return None
    return branch


#: Newton steps (each one batched inverse solve of every root) of :func:`branch_states`,
#: and its ends: Lambda within this relative rounding of the forcing, or a step in x1 below
#: this relative rounding (the inverse solve's Lambda is noisy at ~1e-15).
_NEWTON_STEPS = 40
_LAMBDA_ROUNDING = 1e-14
_X_ROUNDING = 2 * 2.0**-52


def _cubic_root(xs: np.ndarray, g: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """A start for each root of g in [xs[i], xs[i + 1]] (g changes sign there): the root in
    the bracket of the cubic through the four points around it, or the chord's where there
    is none (fewer than four points, a NaN among them, points bunched or far apart)."""
    n = xs.size
    lo, hi = xs[idx], xs[idx + 1]
    glo, ghi = g[idx], g[idx + 1]
    with np.errstate(all="ignore"):
        out = np.where(ghi != glo, lo - glo * (hi - lo) / (ghi - glo), lo)
    if n >= 4:
        first = np.clip(idx - 1, 0, n - 4)
        for k in range(idx.size):
            px, pg = xs[first[k] : first[k] + 4], g[first[k] : first[k] + 4]
            width = hi[k] - lo[k]
            if not (np.all(np.isfinite(pg)) and width != 0.0):
                continue
            t = (px - lo[k]) / width  # the bracket is [0, 1] in t
            gaps = np.diff(np.sort(t))
            if gaps.size < 3 or gaps.min() < 1e-3 or np.max(np.abs(t)) > 10.0:
                continue  # points too close or too far for a well-posed cubic: the chord
            roots = np.roots(np.polyfit(t, pg, 3))
            real = roots[np.abs(roots.imag) <= 1e-9].real
            real = real[(real >= 0.0) & (real <= 1.0)]
            if real.size:
                out[k] = lo[k] + width * float(real[np.argmin(np.abs(real - 0.5))])
    return np.where(glo == 0.0, lo, np.where(ghi == 0.0, hi, out))


def branch_states(p: PillarParams) -> list[Any] | None:
    """Every coexisting state of a pillar at its forcing, read from its cached branch
    (:func:`pillar_branch`), sorted by tip deflection, each with ``stable`` in the branch's
    sense (dLambda/dx1 > 0); None where the branch does not cover the forcing (then
    :func:`hairbed.solve_pillar_all` is the way).

    As :func:`hairbed.solve_pillar_all`, the states at Lambda are the roots of
    Lambda(x1) = Lambda on a branch followed up to twice the forcing (the first of the levels
    :data:`BRANCH_FORCING` 10^k that reaches it), bracketed between its points and folds.
    Each root starts from the root of the cubic through the four branch points around it
    and is refined by Newton's method on x1 with the exact dLambda/dx1 =
    1/``tip_deflection_slope`` of :func:`hairbed.solve_pillar_inverse` (the roots not yet
    converged in one batch per step; a step that leaves its bracket bisects it instead)
    until Lambda is the forcing to rounding (1e-14) or the step is below x1's rounding. A
    forcing inside the window costs a few batched inverse solves, not a new branch; one seen
    before costs nothing (the states are cached per input too).
    """
    found = _states_on_branch(p.forcing, p.theta0, *p.kwargs.values())
    return None if found is None else list(found)


@functools.lru_cache(maxsize=64)
def _states_on_branch(
    lam: float, theta0: float, profile: str, height_ratio: float | None, gamma: float,
    tip_load: float,
) -> tuple[Any, ...] | None:  # fmt: skip
    """:func:`branch_states` of the pillar's inputs (cached: a slider moved back and forth
    reads each forcing once)."""
    kw = {"profile": profile, "height_ratio": height_ratio, "gamma": gamma, "tip_load": tip_load}
    if lam == 0.0 or not math.isfinite(lam):
        return None
    sign = -1.0 if lam < 0.0 else 1.0
    level = max(0, math.ceil(math.log10(2.0 * abs(lam) / BRANCH_FORCING)))
    if level > 3:
        return None
    branch = pillar_branch(sign, theta0, *kw.values(), level)
    if branch is None:
        return None
    xs = np.concatenate([branch.tip_deflection, branch.folds[:, 1]])
    order = np.argsort(sign * xs, kind="stable")
    xs = xs[order]
    g = np.concatenate([branch.forcing, branch.folds[:, 0]])[order] - lam
    idx = np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] <= 0.0))
    idx = idx[~np.isin(idx - 1, idx) | (g[idx] != 0.0)]  # a root on a point: once
    if idx.size == 0:
        return None
    lo, hi = xs[idx].copy(), xs[idx + 1].copy()
    glo = g[idx].copy()
    x = _cubic_root(xs, g, idx)
    best_x, best_g = x.copy(), np.full(x.shape, np.inf)
    todo = np.arange(x.size)  # the roots not converged yet: solved together each step
    for _ in range(_NEWTON_STEPS):
        st = hairbed.solve_pillar_inverse(x[todo], theta0, **kw)
        gx = np.asarray(st.forcing, dtype=np.float64).reshape(-1) - lam
        xt = x[todo]
        better = np.abs(gx) < np.abs(best_g[todo])
        best_x[todo] = np.where(better, xt, best_x[todo])
        best_g[todo] = np.where(better, gx, best_g[todo])
        # the bracket shrinks to the side of x where the sign of g stays
        left = np.sign(gx) == np.sign(glo[todo])
        lo[todo], glo[todo] = np.where(left, xt, lo[todo]), np.where(left, gx, glo[todo])
        hi[todo] = np.where(left, hi[todo], xt)
        with np.errstate(all="ignore"):
            step = -gx * np.asarray(st.tip_deflection_slope, dtype=np.float64).reshape(-1)
            new = xt + step
        a, b = lo[todo], hi[todo]
        inside = np.isfinite(new) & ((new - a) * (new - b) < 0.0)
        new = np.where(inside, new, 0.5 * (a + b))
        # converged: Lambda to rounding, or a Newton step (or bracket) below x1's rounding
        tiny = _X_ROUNDING * np.maximum(1.0, np.abs(xt))
        done = (np.abs(best_g[todo]) <= _LAMBDA_ROUNDING * abs(lam)) | (
            (inside & (np.abs(step) <= tiny)) | (np.abs(b - a) <= tiny)
        )
        x[todo] = np.where(done, xt, new)
        todo = todo[~done]
        if todo.size == 0:
            break
    found = [hairbed.solve_pillar_inverse(float(v), theta0, **kw) for v in np.sort(best_x)]
    if any(int(s.status) < 0 for s in found):
        return None
    return tuple(dataclasses.replace(s, stable=bool(s.tip_deflection_slope > 0.0)) for s in found)


@functools.lru_cache(maxsize=32)
def calibration_curve(
    sign: float, theta0: float, profile: str, height_ratio: float | None, gamma: float,
    tip_load: float,
) -> Calibration:  # fmt: skip
    """The calibration curve of a pillar in the flow's direction ``sign`` (+1 or -1), cached.

    A :func:`hairbed.solve_pillar` batch on :data:`CALIBRATION_GRID`; where a snap-through
    window can exist, the branch of :func:`hairbed.continue_pillar` up to
    :data:`BRANCH_FORCING` (folds, stability) in place of the batch's points there.
    """
    kw = {"profile": profile, "height_ratio": height_ratio, "gamma": gamma, "tip_load": tip_load}
    at_rest = hairbed.solve_pillar(0.0, theta0, **kw)
    rest = float(at_rest.tip_deflection)
    slope = sign * float(at_rest.tip_deflection_slope)
    grid = CALIBRATION_GRID
    lam, stable = grid, np.ones(grid.shape, dtype=np.bool_)
    folds = np.zeros((0, 2))
    branch = None
    if sign * theta0 < WINDOW_THETA0:
        branch = pillar_branch(sign, theta0, profile, height_ratio, gamma, tip_load, 0)
    if branch is None:  # the batch alone
        st = hairbed.solve_pillar(sign * grid, theta0, **kw)
        ok = np.asarray(st.status) >= 0
        x = np.where(ok, np.asarray(st.tip_deflection, dtype=np.float64), np.nan)
    else:  # the batch below and beyond the branch, the branch between
        bl = np.abs(np.asarray(branch.forcing, dtype=np.float64))
        out = (grid < bl[1]) | (grid > BRANCH_FORCING)
        st = hairbed.solve_pillar(sign * grid[out], theta0, **kw)
        ok = np.asarray(st.status) >= 0
        xb = np.where(ok, np.asarray(st.tip_deflection, dtype=np.float64), np.nan)
        n_low = int(np.sum(grid < bl[1]))
        lam = np.concatenate([grid[:n_low], bl[1:], grid[out][n_low:]])
        x = np.concatenate([xb[:n_low], np.asarray(branch.tip_deflection)[1:], xb[n_low:]])
        ones = np.ones(n_low, dtype=np.bool_), np.ones(xb.size - n_low, dtype=np.bool_)
        stable = np.concatenate([ones[0], np.asarray(branch.stable, dtype=np.bool_)[1:], ones[1]])
        folds = np.array(branch.folds, dtype=np.float64).reshape(-1, 2)
        folds[:, 0] = np.abs(folds[:, 0])
    status = 0 if bool(np.all(ok)) else -7
    with np.errstate(all="ignore"):
        err = np.abs((x - rest) / slope - lam) / lam
    # the levels along the branch from rest, before any fold
    first = int(np.flatnonzero(~stable)[0]) if not bool(np.all(stable)) else lam.size
    levels = {lv: _crossing(lam[:first], err[:first], lv) for lv in ERROR_LEVELS}
    return Calibration(lam, x, stable, folds, rest, slope, err, levels, status)


@dataclass(frozen=True)
class PillarView:
    """One pillar state on screen: its label ("low", "mid", "high" in a window, along the
    branch from rest) and the library's :class:`hairbed.PillarState`."""

    label: str
    state: Any

    @property
    def stable(self) -> bool | None:
        s = self.state.stable
        return None if s is None else bool(s)


@dataclass(frozen=True)
class PillarSnapshot:
    """Everything the pillar mode shows, computed from one :class:`PillarParams`.

    Attributes
    ----------
    params : PillarParams
    states : list of PillarView
        Every coexisting state (one outside a snap-through window), along the branch from
        rest; empty when the solve failed (then :attr:`message` says why).
    profile_z, profile_u : ndarray
        The undisturbed profile U(z) [-] at heights z [L] in [0, 1].
    calibration : Calibration or None
        The calibration curve (the calibration view only).
    warnings : list of str
        The library's warnings, "Category: message", each once.
    timings : dict of str to float
        Wall times [ms]: "solve", "calibration", "total".
    message : str
        Why no state is shown ("" when there are states).
    animation : DriveAnimation or None
        The drive view's period of motion and Bode view (that view only).
    lissajous : LissajousView or None
        The drive view's Lissajous view of the bed (side_view "lissajous" only).
    """

    params: PillarParams
    states: list[PillarView]
    profile_z: np.ndarray
    profile_u: np.ndarray
    calibration: Calibration | None
    warnings: list[str]
    timings: dict[str, float]
    message: str = ""
    animation: DriveAnimation | None = None
    lissajous: LissajousView | None = None

    def error_at(self) -> float:
        """The linear formula's relative error at the first state [-] (NaN without one or
        without the calibration curve)."""
        c = self.calibration
        if c is None or not self.states or self.params.forcing == 0.0:
            return math.nan
        x1 = float(self.states[0].state.tip_deflection)
        lam = abs(self.params.forcing)
        return abs((x1 - c.rest) / c.slope - lam) / lam


@functools.lru_cache(maxsize=64)
def _every_state(
    forcing: float, theta0: float, profile: str, height_ratio: float | None, gamma: float,
    tip_load: float,
) -> tuple[Any, ...]:  # fmt: skip
    """:func:`hairbed.solve_pillar_all` (seconds in a window: cached, so that a slider moved
    back and forth solves each forcing once)."""
    kw = {"profile": profile, "height_ratio": height_ratio, "gamma": gamma, "tip_load": tip_load}
    return tuple(hairbed.solve_pillar_all(forcing, theta0, **kw))


def clear_pillar_caches() -> None:
    """Empty the pillar mode's caches (branches, calibration curves, states): what no session
    needs once none is open."""
    for func in (pillar_branch, _states_on_branch, calibration_curve, _every_state):
        func.cache_clear()
    drive_animation.cache_clear()
    lissajous_view.cache_clear()


def _labels(n: int, sign: float) -> list[str]:
    """Labels of n states sorted by x1: along the branch from rest (towards -x for a negative
    forcing), as :func:`hairbed.solve_pillar`'s roots; two exactly at a fold."""
    names = {1: ["low"], 2: ["low", "high"], 3: ["low", "mid", "high"]}.get(
        n, [f"state {k}" for k in range(n)]
    )
    return names if sign > 0 else names[::-1]


def compute_pillar(p: PillarParams) -> PillarSnapshot:
    """Solve every state of the pillar (and its calibration curve in the calibration view).

    Where a snap-through window can exist, every state is read from the pillar's cached
    branch (:func:`branch_states`), by :func:`hairbed.solve_pillar_all` where that branch
    does not reach. A failed solve (status < 0) shows no state, with the library's message.

    Examples
    --------
    >>> snap = compute_pillar(validate_pillar({"mode": "pillar", "forcing": "20",
    ...                                        "pillar_theta0": "-1.45"}))
    >>> [(s.label, s.stable) for s in snap.states]
    [('low', True), ('mid', False), ('high', True)]
    """
    t0 = time.perf_counter()
    message = ""
    with _recording() as caught:
        found: list[Any] = []
        if p.window:  # from the pillar's cached branch; beyond it, solve_pillar_all
            read = branch_states(p)
            found = read if read is not None else [
                s
                for s in _every_state(p.forcing, p.theta0, *p.kwargs.values())
                if int(s.status) >= 0
            ]  # fmt: skip
        if not found:
            one = hairbed.solve_pillar(p.forcing, p.theta0, **p.kwargs)
            if int(one.status) >= 0:
                found = [one]
            else:
                message = f"no state: {one.message} (status {int(one.status)})"
        sign = -1.0 if p.forcing < 0.0 else 1.0
        states = [PillarView(lb, s) for lb, s in zip(_labels(len(found), sign), found)]
        order = {"low": 0, "mid": 1, "high": 2}
        states.sort(key=lambda v: order.get(v.label, 3))
        t1 = time.perf_counter()
        z = np.linspace(0.0, 1.0, PROFILE_POINTS)
        coef = profile_coefficients(p.profile, p.height_ratio)
        u = np.polynomial.chebyshev.chebval(2.0 * z - 1.0, coef)
        cal = None
        if p.view == "calibration":
            cal = calibration_curve(sign, p.theta0, p.profile, p.height_ratio, p.gamma, p.tip_load)
        anim = None
        if p.view == "drive" and p.drive is not None and states:
            d = p.drive
            anim = drive_animation(
                p.forcing, p.theta0, p.profile, p.height_ratio, p.gamma, p.tip_load,
                p.slenderness, d.amplitude, d.frequency, d.mu, d.drag_model,
            )  # fmt: skip
        liss = None
        if p.view == "drive" and p.drive is not None and p.drive.side_view == "lissajous":
            d = p.drive
            liss = lissajous_view(p.forcing, p.theta0, d.bed_kappa, d.bed_eps, d.amplitude,
                                  d.frequency)  # fmt: skip
    t2 = time.perf_counter()
    key = "drive" if p.view == "drive" else "calibration"
    return PillarSnapshot(
        p, states, z, u, cal, _merge(p.warnings, caught),
        {"solve": 1e3 * (t1 - t0), key: 1e3 * (t2 - t1), "total": 1e3 * (t2 - t0)},
        message, anim, liss,
    )  # fmt: skip


def pillar_snapshot_json(snap: PillarSnapshot) -> str:
    """The pillar view as JSON: its inputs, every state (every shown field and its shape at
    101 arc lengths) and, in the calibration view, the linear formula's figures."""
    p = snap.params
    sigma = np.linspace(0.0, 1.0, 101)
    states = []
    for v in snap.states:
        _, x, z, theta = v.state.shape(sigma)
        rec: dict[str, Any] = {"state": v.label, "stable": v.stable}
        rec.update({k: getattr(v.state, k) for k in PILLAR_FIELDS})
        rec["message"] = v.state.message
        rec["shape"] = {"sigma": sigma, "x": x, "z": z, "theta": theta}
        states.append(rec)
    doc: dict[str, Any] = {
        "hairbed_version": hairbed.__version__,
        "mode": "pillar",
        "inputs": {k: p.raw[k] for k in PILLAR_DEFAULTS},
        "solved": {"forcing": p.forcing, "theta0": p.theta0, **p.kwargs},
        "message": snap.message,
        "states": states,
        "warnings": snap.warnings,
    }
    a = snap.animation
    if a is not None and p.drive is not None:
        doc["drive"] = {
            "inputs": {k: p.raw[k] for k in DRIVE_DEFAULTS},
            "status": a.status,
            "message": a.message,
            "settle_time": a.settle,
            "frame_time": a.t,
            "forcing": a.forcing,
            "tip_deflection": a.tip_x,
            "tip_height": a.tip_z,
            "first_harmonic": {"real": a.harmonic.real, "imag": a.harmonic.imag},
            "linear": {"real": a.bode_now.real, "imag": a.bode_now.imag},
        }
        if p.drive.side_view != "lissajous":  # the bed's keys in its view only
            for k in LISSAJOUS_KEYS:
                doc["drive"]["inputs"].pop(k)
    li = snap.lissajous
    if li is not None and "drive" in doc:
        doc["drive"]["lissajous"] = {
            "units": {"strain": "1", "strain_rate": "1/T", "stress": "E I/(A L^2)"},
            "status": li.status,
            "message": li.message,
            "strain_amplitude": li.strain_amplitude,
            "strain": li.strain,
            "strain_rate": li.strain_rate,
            "stress": li.stress,
            "measures": li.measures,
        }
    c = snap.calibration
    if c is not None:
        doc["calibration"] = {
            "rest": c.rest,
            "slope": c.slope,
            "error_levels": {f"{lv:g}": c.levels[lv] for lv in ERROR_LEVELS},
            "folds": c.folds,
        }
    return json.dumps(to_plain(doc), indent=2, allow_nan=False)
