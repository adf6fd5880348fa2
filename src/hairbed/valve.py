"""The bed as a valve: flow against pressure drop, hydraulic resistance, diodicity.

A channel of length l [m] and height H, a dense bed on its floor, both walls at rest, a
pressure drop dp = p(0) - p(l) [Pa] across it: the pressure gradient is G = dp/l and the
flow per unit width through the gap g = H - h1 L above the tips is (theory.md §11)::

    Q'  = G g^3 / (12 eta)                 flow rate per unit width [m^2/s]
    R   = dp / Q'                          hydraulic resistance per unit width [Pa s/m^2]
    R0  = 12 eta l / H^3                   the empty channel's, so  R / R0 = (H / g)^3

The hairs bend under G (the tip plane's shear and the load inside the bed), so the gap and
hence the resistance depend on the flow: a bed of hairs tilted at theta0 != 0 is a diode.
Forward flow (along the tilt) bends the hairs down and opens the gap; backward flow lifts
them and closes it. The diodicity is Di = Q'(+dp) / abs(Q'(-dp)) at the same abs(dp).

:func:`valve_curve` gives one state per drop. :func:`valve_states` gives every coexisting
state over a range of the pump's drive (a set pressure drop or a set flow rate), with its
stability, the folds, and the quasi-static ramps up and down with their jumps: the hysteresis
loop. A set flow rate against the hairs' lean is bistable (theory.md §11).

Examples
--------
>>> from hairbed import HairBed
>>> bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
...               viscosity=1.0, spacing=400e-6, base_angle=0.5)
>>> d = diodicity(bed, 200.0, 0.01)   # 200 Pa over 1 cm
>>> round(d.diodicity, 4)
1.434
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._channel_drives import drive_inputs, gap_flow, porous_flow
from ._core.arclength import LoadedBranch, _Curve, _follow, continue_loaded
from ._core.loaded import _gap
from ._core.outputs import float_or_array
from ._core.porous import LADDER
from ._core.porous import _run as _porous_run
from ._core.porous import _state as _porous_state
from ._core.validation import (
    STATUS_MESSAGES,
    _first_index,
    as_float_array,
    check_int,
    check_number,
    check_positive,
    check_root,
)
from ._optional import optional_import
from .units import HairBed, HairState, _warn_reynolds

__all__ = [
    "Diodicity",
    "ValveCurve",
    "ValveJump",
    "ValveRamp",
    "ValveStates",
    "diodicity",
    "valve_curve",
    "valve_states",
]

FloatOrArray = float | NDArray[np.float64]


@dataclass(frozen=True)
class ValveCurve:
    """Flow through a hair-bed valve against the pressure drop (from :func:`valve_curve`).

    Attributes
    ----------
    pressure_drop : float or ndarray
        dp = p(0) - p(l) [Pa] (positive drives the flow towards +x).
    channel_length : float
        l [m].
    flow_rate : float or ndarray
        Q' [m^2/s] per unit width, signed like dp.
    empty_flow_rate : float or ndarray
        dp H^3 / (12 eta l) [m^2/s]: the channel without hairs at the same drop.
    resistance_ratio : float or ndarray
        R / R0 [-], the resistance relative to the empty channel: (H / g)^3 for the dense
        bed, the empty channel's flow over the flow through bed and gap for a porous one
        (its limit (H / g)^3 at no flow).
    tip_deflection, tip_height : float or ndarray
        The hair's tip [m] (along +x, above the wall).
    states : HairState
        The states themselves (:meth:`hairbed.HairBed.deform` with ``pressure_gradient``).
    status : int or ndarray
        The solver's status per point (0 converged; ``STATUS_MESSAGES``).
    success : bool
        True where every point converged.
    message : str
        What happened (the first failing point's message).
    """

    pressure_drop: FloatOrArray
    channel_length: float
    flow_rate: FloatOrArray
    empty_flow_rate: FloatOrArray
    resistance_ratio: FloatOrArray
    tip_deflection: FloatOrArray
    tip_height: FloatOrArray
    states: HairState
    status: Any
    success: bool
    message: str


@dataclass(frozen=True)
class Diodicity:
    """Forward against backward flow at the same pressure drop (from :func:`diodicity`).

    Attributes
    ----------
    pressure_drop : float or ndarray
        abs(dp) [Pa].
    forward, backward : ValveCurve
        The valve at +abs(dp) and at -abs(dp).
    diodicity : float or ndarray
        Di = Q'(+abs(dp)) / abs(Q'(-abs(dp))) [-]: above 1 when the hairs lean towards +x.
    success : bool
        True where both directions converged.
    status, message
        Of the two curves (issue 33): 0 and "ok", else the first failed status of the
        forward curve, then of the backward one (``STATUS_MESSAGES``), where Di is NaN.
    """

    pressure_drop: FloatOrArray
    forward: ValveCurve
    backward: ValveCurve
    diodicity: FloatOrArray
    success: bool

    @property
    def status(self) -> Any:
        """Elementwise: the forward curve's status where it failed, else the backward's."""
        ahead, behind = np.asarray(self.forward.status), np.asarray(self.backward.status)
        worst = np.where(ahead != 0, ahead, behind).astype(np.int64)
        return int(worst) if worst.ndim == 0 else worst

    @property
    def message(self) -> str:
        """ "ok", or the first failed curve's message."""
        return self.forward.message if not self.forward.success else self.backward.message


def valve_curve(
    bed: HairBed, pressure_drop: Any, channel_length: float, *, root: str = "low"
) -> ValveCurve:
    """Flow per unit width through a channel of length l lined by ``bed`` at drops dp.

    Parameters
    ----------
    bed : HairBed
        The bed (its channel height H and the fluid's viscosity included).
    pressure_drop : array_like
        dp = p(0) - p(l) [Pa], finite; negative drives the flow towards -x.
    channel_length : float
        l [m], positive: the pressure gradient is G = dp / l.
    root : {"low", "mid", "high"}
        Which state where several coexist (passed to :meth:`hairbed.HairBed.deform`).

    Returns
    -------
    ValveCurve

    See Also
    --------
    valve_states : every coexisting state, the folds and the hysteresis loop.
    """
    if not isinstance(bed, HairBed):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    dp = as_float_array(pressure_drop, "pressure_drop", unit="Pa")
    bed._broadcast_input(dp, "pressure_drop")  # an array bed: the error names pressure_drop
    length = check_positive(channel_length, "channel_length", unit="m")
    root = check_root(root)
    with np.errstate(over="ignore"):
        gradient = dp / length
        empty = dp * (bed.channel_height**3 / (12.0 * bed.viscosity * length))
    bad = ~np.isfinite(gradient) | ~np.isfinite(empty)
    if np.any(bad):
        raise ValueError(
            f"pressure_drop / channel_length [Pa/m] overflows: pressure_drop "
            f"{float(dp[bad].flat[0])!r} Pa over channel_length {length!r} m"
            f"{_first_index(bad)}"
        )
    states = bed.deform(pressure_gradient=gradient, root=root)
    flow = np.asarray(states.flow_rate, dtype=np.float64)
    gap = bed.channel_height - np.asarray(states.tip_height, dtype=np.float64)
    ratio = (bed.channel_height / gap) ** 3
    if bed.model == "porous":  # the flow through the bed too: the ratio of the flows
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(flow != 0.0, empty / np.where(flow != 0.0, flow, 1.0), ratio)
    status = np.asarray(states.solution.status)
    failed = np.flatnonzero(status.reshape(-1) != 0)
    message = "ok" if failed.size == 0 else STATUS_MESSAGES[int(status.reshape(-1)[failed[0]])]
    return ValveCurve(
        pressure_drop=float_or_array(dp),
        channel_length=length,
        flow_rate=float_or_array(flow),
        empty_flow_rate=float_or_array(empty),
        resistance_ratio=float_or_array(ratio),
        tip_deflection=states.tip_deflection,
        tip_height=states.tip_height,
        states=states,
        status=states.solution.status,
        success=bool(failed.size == 0),
        message=message,
    )


def diodicity(
    bed: HairBed, pressure_drop: Any, channel_length: float, *, root: str = "low"
) -> Diodicity:
    """The diodicity Di = Q'(+abs(dp)) / abs(Q'(-abs(dp))) of a channel lined by ``bed``.

    Parameters are those of :func:`valve_curve`; ``pressure_drop`` is taken in magnitude
    (it must not be 0, where the ratio is 0/0).
    """
    dp = np.abs(as_float_array(pressure_drop, "pressure_drop", unit="Pa"))
    zero = dp == 0.0
    if np.any(zero):
        raise ValueError(
            "pressure_drop must be non-zero for a diodicity (0/0 at no flow), got 0.0"
            f"{_first_index(zero)}"
        )
    forward = valve_curve(bed, dp, channel_length, root=root)
    backward = valve_curve(bed, -dp, channel_length, root=root)
    ahead = np.asarray(forward.flow_rate, dtype=np.float64)
    behind = np.abs(np.asarray(backward.flow_rate, dtype=np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        # both flows underflow to 0 only at drops of ~1e-300 Pa, where Di -> 1 (at rest the
        # gap is the same both ways)
        di = np.where((ahead == 0.0) & (behind == 0.0), 1.0, ahead / behind)
    return Diodicity(
        pressure_drop=float_or_array(dp),
        forward=forward,
        backward=backward,
        diodicity=float_or_array(di),
        success=forward.success and backward.success,
    )


@dataclass(frozen=True)
class ValveJump:
    """One jump of a quasi-static ramp of the pump (in :class:`ValveRamp`).

    The ramp follows a stable state until it meets a fold, where that state disappears and the
    bed snaps, at the same set drive, to the stable state of the other piece of the branch.

    Attributes
    ----------
    drive_value : float
        The set drive where the jump happens: the pressure drop [Pa] (pressure drive) or the
        flow rate per unit width [m^2/s] (flow drive); a fold's value.
    pressure_drop_before, pressure_drop_after : float
        dp [Pa] at the fold and on the landing state (equal for the pressure drive).
    flow_rate_before, flow_rate_after : float
        Q' [m^2/s] per unit width (equal for the flow drive).
    tip_height_before, tip_height_after : float
        h1 L [m], the tips' height above the wall.
    """

    drive_value: float
    pressure_drop_before: float
    pressure_drop_after: float
    flow_rate_before: float
    flow_rate_after: float
    tip_height_before: float
    tip_height_after: float


@dataclass(frozen=True)
class ValveRamp:
    """A quasi-static ramp of the pump across the whole range (in :class:`ValveStates`).

    Attributes
    ----------
    direction : int
        +1 the set drive rises from the range's low end to its high end, -1 it falls back.
    pressure_drop, flow_rate, tip_height : ndarray
        The path followed [Pa], [m^2/s], [m]: points of the stable pieces of the branch, and at
        each jump the fold and then the landing state (two points at the same set drive).
    jumps : tuple of ValveJump
        The jumps, in the order met.
    """

    direction: int
    pressure_drop: NDArray[np.float64]
    flow_rate: NDArray[np.float64]
    tip_height: NDArray[np.float64]
    jumps: tuple[ValveJump, ...]


@dataclass(frozen=True)
class ValveStates:
    """Every coexisting state of a valve over a range of the pump's drive (:func:`valve_states`).

    ``drive`` says what the pump sets: the pressure drop ("pressure") or the flow rate per unit
    width ("flow"); the other follows from each state. The branch of states is followed by
    pseudo-arclength continuation (:func:`hairbed.continue_loaded`) from rest (drive 0) to both
    ends of the range, its folds located, and at every value of ``values`` each crossing of
    the branch is a state.

    Attributes
    ----------
    drive : {"pressure", "flow"}
        What the pump sets.
    channel_length : float
        l [m].
    velocity : float
        The top wall's speed v [m/s] (0: both walls at rest).
    values : ndarray
        The set drive at each grid point, shape (num,): pressure drop [Pa] or flow rate
        [m^2/s].
    count, count_stable : ndarray of int
        The number of coexisting states at each grid point, and how many of them are stable
        (0 where the branch was not followed that far: see ``covered``).
    covered : ndarray of bool
        True where the continuation reached that grid point.
    pressure_drop, flow_rate, tip_height, resistance_ratio : ndarray
        Each state at each grid point, shape (num, max(count)) sorted by tip height, padded
        with NaN: dp [Pa], Q' [m^2/s], h1 L [m], (H / g)^3 [-].
    stable : ndarray of bool
        Linear stability of each state under the set drive (dG/dh1 < 0, theory.md §11),
        shape (num, max(count)), False in the padding.
    branch_pressure_drop, branch_flow_rate, branch_tip_height : ndarray
        The branch of states along its arclength from the range's low end to its high end
        [Pa], [m^2/s], [m], the folds included as points.
    branch_stable : ndarray of bool
        Stability along the branch (False at the folds).
    fold_pressure_drop, fold_flow_rate, fold_tip_height : ndarray
        The folds of the branch [Pa], [m^2/s], [m], in the order of the branch.
    ramp_up, ramp_down : ValveRamp
        The quasi-static ramps up and back down the range, with their jumps: together the
        hysteresis loop.
    status : int
        0 the continuation covered the range; -2 its step limit or -3 it broke down
        (``STATUS_MESSAGES``), the grid then only partly covered.
    success : bool
        status == 0.
    message : str
        What happened.
    nfev : int
        Fixed-load solves used by the continuation.
    """

    drive: str
    channel_length: float
    velocity: float
    values: NDArray[np.float64]
    count: NDArray[np.int64]
    count_stable: NDArray[np.int64]
    covered: NDArray[np.bool_]
    pressure_drop: NDArray[np.float64]
    flow_rate: NDArray[np.float64]
    tip_height: NDArray[np.float64]
    resistance_ratio: NDArray[np.float64]
    stable: NDArray[np.bool_]
    branch_pressure_drop: NDArray[np.float64]
    branch_flow_rate: NDArray[np.float64]
    branch_tip_height: NDArray[np.float64]
    branch_stable: NDArray[np.bool_]
    fold_pressure_drop: NDArray[np.float64]
    fold_flow_rate: NDArray[np.float64]
    fold_tip_height: NDArray[np.float64]
    ramp_up: ValveRamp
    ramp_down: ValveRamp
    status: int
    success: bool
    message: str
    nfev: int

    def to_dataset(self) -> Any:
        """The grid's states as an xarray Dataset with CF units, dimensions (point, state).

        Data variables: the set drive ``values`` (point), ``count`` and ``count_stable``
        (point), ``pressure_drop``, ``flow_rate``, ``tip_height``, ``resistance_ratio``,
        ``stable`` (point, state; NaN/False padding). The folds and the ramps' jumps, which
        are not on the grid, are attributes (arrays [Pa], [m^2/s], [m]), with the drive,
        channel length [m], wall speed [m/s], status and message. Needs xarray (the
        ``sweep`` extra).
        """
        xr = optional_import("xarray", "ValveStates.to_dataset", "sweep")
        set_unit = "Pa" if self.drive == "pressure" else "m^2/s"
        set_name = "set pressure drop" if self.drive == "pressure" else "set flow rate per width"
        grid = ("point", "state")
        jumps = [(r.direction, j) for r in (self.ramp_up, self.ramp_down) for j in r.jumps]

        def attrs(units: str, long_name: str) -> dict[str, str]:
            return {"units": units, "long_name": long_name}

        data = {
            "values": (("point",), self.values, attrs(set_unit, set_name)),
            "count": (("point",), self.count, attrs("1", "number of coexisting states")),
            "count_stable": (("point",), self.count_stable, attrs("1", "stable states")),
            "covered": (("point",), self.covered, attrs("1", "reached by the continuation")),
            "pressure_drop": (grid, self.pressure_drop, attrs("Pa", "pressure drop p(0) - p(l)")),
            "flow_rate": (grid, self.flow_rate, attrs("m^2/s", "flow rate per unit width")),
            "tip_height": (grid, self.tip_height, attrs("m", "tip height h1 L")),
            "resistance_ratio": (
                grid,
                self.resistance_ratio,
                attrs("1", "resistance relative to the empty channel (H/g)^3"),
            ),
            "stable": (grid, self.stable, attrs("1", "linearly stable under the set drive")),
        }
        return xr.Dataset(
            data,
            coords={
                "point": ("point", np.arange(self.values.size)),
                "state": ("state", np.arange(self.stable.shape[1])),
            },
            attrs={
                "title": "hairbed valve: every coexisting state (hairbed.valve.valve_states)",
                "drive": self.drive,
                "channel_length_m": self.channel_length,
                "velocity_m_per_s": self.velocity,
                "fold_pressure_drop_Pa": self.fold_pressure_drop,
                "fold_flow_rate_m2_per_s": self.fold_flow_rate,
                "fold_tip_height_m": self.fold_tip_height,
                "jump_direction": np.array([d for d, _ in jumps], dtype=np.int64),
                **{
                    f"jump_{field}_{unit}": np.array([getattr(j, field) for _, j in jumps])
                    for field, unit in (
                        ("drive_value", "Pa" if self.drive == "pressure" else "m2_per_s"),
                        ("pressure_drop_before", "Pa"),
                        ("pressure_drop_after", "Pa"),
                        ("flow_rate_before", "m2_per_s"),
                        ("flow_rate_after", "m2_per_s"),
                        ("tip_height_before", "m"),
                        ("tip_height_after", "m"),
                    )
                },
                "status": self.status,
                "message": self.message,
            },
        )


class _Drive:
    """The valve's drive in the solver's terms: G(h, p) and the SI values of a state."""

    def __init__(self, bed: HairBed, drive: str, velocity: float, length: float) -> None:
        unit = 1.0 / length if drive == "pressure" else 1.0  # G [Pa/m] per Pa of drop
        grad, flow = (unit, None) if drive == "pressure" else (None, 1.0)
        _, v, _, omega2, load = drive_inputs(bed, velocity, grad, flow)
        self.bed, self.drive, self.length = bed, drive, length
        self.v = np.asarray(v, dtype=np.float64)
        self.omega2 = float(omega2)
        self.scale = float(load)  # the dimensionless load per unit of the SI drive
        self.code = 0 if drive == "pressure" else 1
        self.porous = bed.model == "porous"

    def _frozen(self, h: NDArray[np.float64], p: NDArray[np.float64]) -> tuple[Any, Any, Any, Any]:
        """The porous bed's states of load p with the gap frozen at the tip height h (the
        kernel's columns, coefficients, map, and the inputs; at a root of G the bed's own
        states): theory.md §13, :func:`hairbed.solve_porous_all`'s scan."""
        b = self.bed
        n = h.size
        arrays = tuple(
            np.full(n, float(x)) for x in (self.omega2, b.eps, b.base_angle, b.kappa,
                                            b.drag_ratio)
        ) + (np.ascontiguousarray(p, dtype=np.float64),)  # fmt: skip
        out, coefs, amap = _porous_run(
            self.code, arrays, np.ascontiguousarray(h, dtype=np.float64), LADDER, 1e-12
        )
        return out, coefs, amap, arrays

    def gap(self, h: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
        """G(h, p) = z1 - h with the drive's dimensionless load p (NaN where not found): the
        dense bed's fixed-load solves, the porous bed's frozen-gap ones."""
        b = self.bed
        if self.porous:
            h = np.atleast_1d(np.asarray(h, dtype=np.float64))
            out = self._frozen(h, np.broadcast_to(np.asarray(p, dtype=np.float64), h.shape))[0]
            return np.where(out[0] >= 0, out[3] - h, np.nan)
        return np.asarray(_gap(self.code, self.omega2, b.eps, p, b.base_angle, h, 1e-12))

    def si(self, p: Any, h: Any) -> dict[str, NDArray[np.float64]]:
        """dp [Pa], Q' [m^2/s], h1 L [m] and (H/g)^3 of states (load p, tip height h [L]);
        a porous bed's: its flow through bed and gap, R/R0 the empty channel's flow over it
        (as :func:`valve_curve`), and the gap's Reynolds number."""
        p = np.asarray(p, dtype=np.float64)
        h = np.asarray(h, dtype=np.float64)
        value = p / self.scale  # dp [Pa] or Q' [m^2/s]
        given = value / self.length if self.drive == "pressure" else value
        if self.porous:
            return self._porous_si(p, h, given)
        flow = gap_flow(self.bed, self.drive, self.v, given, h)
        gap = self.bed.channel_height - h * self.bed.length
        with np.errstate(over="ignore"):  # a huge channel_length: refused by valve_states
            drop = flow["pressure_gradient"] * self.length
        return {
            "pressure_drop": drop,
            "flow_rate": flow["flow_rate"],
            "tip_height": h * self.bed.length,
            "resistance_ratio": (self.bed.channel_height / gap) ** 3,
        }

    def _porous_si(
        self, p: NDArray[np.float64], h: NDArray[np.float64], given: NDArray[np.float64]
    ) -> dict[str, NDArray[np.float64]]:
        """:meth:`si` of the porous bed: its states at (p, h) (frozen gap, a root of G) and
        their flow (:func:`hairbed._channel_drives.porous_flow`); NaN where p or h is."""
        b = self.bed
        keys = ("pressure_drop", "flow_rate", "tip_height", "resistance_ratio",
                "reynolds_number")  # fmt: skip
        res = {k: np.full(p.shape, np.nan) for k in keys}
        ok = np.isfinite(p) & np.isfinite(h)
        if np.any(ok):
            pf, hf = p[ok], h[ok]
            out, coefs, amap, arrays = self._frozen(hf, pf)
            drive = "pressure" if self.code == 0 else "flow"
            state = _porous_state(drive, self.code, (hf.size,), arrays, out, coefs, amap)
            v = np.full(hf.size, float(self.v))
            flow = porous_flow(b, state, v, drive, given[ok])
            q = flow["flow_rate"]
            with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
                grad = flow["pressure_gradient"]
                gap = b.channel_height - hf * b.length
                ratio = np.where(
                    q != 0.0,
                    grad * b.channel_height**3 / (12.0 * b.viscosity * np.where(q != 0, q, 1.0)),
                    (b.channel_height / gap) ** 3,
                )
                # the drive's own quantity is the one set: exactly so, at any (p, h)
                res["pressure_drop"][ok] = (
                    given[ok] * self.length if self.code == 0 else grad * self.length
                )
            res["flow_rate"][ok] = q if self.code == 0 else given[ok]
            res["tip_height"][ok] = np.asarray(state.tip_height) * b.length
            res["resistance_ratio"][ok] = ratio
            res["reynolds_number"][ok] = flow["reynolds_number"]
        return res

    def states_at(
        self,
        p: NDArray[np.float64],
        lo: NDArray[np.float64],
        hi: NDArray[np.float64],
        guess: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """The states' tip heights at loads p near ``guess`` between branch tip heights lo and
        hi, and their stability (dG/dh < 0); NaN (and False) where G(., p) has no sign change
        there. Another state of the same load can lie in [lo, hi] too (the branch is not a
        graph over h1), so G is sampled on ``_SAMPLES`` cells of it and the sign change
        nearest the guess refined by regula falsi (all points at once)."""
        if p.size == 0:
            return p.copy(), np.zeros(0, dtype=np.bool_)
        t = np.linspace(0.0, 1.0, _SAMPLES + 1)
        hs = lo[:, None] + t[None, :] * (hi - lo)[:, None]
        g = self.gap(hs.ravel(), np.repeat(p, t.size)).reshape(hs.shape)
        change = np.isfinite(g[:, :-1]) & np.isfinite(g[:, 1:]) & (g[:, :-1] * g[:, 1:] <= 0.0)
        centre = 0.5 * (hs[:, :-1] + hs[:, 1:])
        cell = np.argmin(np.where(change, np.abs(centre - guess[:, None]), np.inf), axis=1)
        rows = np.arange(p.size)
        ok = change[rows, cell]
        a, b = hs[rows, cell], hs[rows, cell + 1]
        ga, gb = g[rows, cell], g[rows, cell + 1]
        stable = (ga - gb) * (b - a) > 0.0  # G falls as h rises
        # the Illinois variant of regula falsi on the bracket [a, b] (a bisection step where
        # the secant leaves it): superlinear, the bracket kept
        done = ~ok | (ga == 0.0) | (gb == 0.0)
        for _ in range(_ITERATIONS):
            done |= np.abs(b - a) <= 4e-16 * np.maximum(1.0, np.abs(b))
            if np.all(done):
                break
            with np.errstate(divide="ignore", invalid="ignore"):
                m = b - gb * (b - a) / (gb - ga)
            inside = np.isfinite(m) & (m > np.minimum(a, b)) & (m < np.maximum(a, b))
            m = np.where(inside, m, 0.5 * (a + b))
            gm = np.zeros(p.size)
            todo = np.flatnonzero(~done)  # only the unconverged points are solved again
            gm[todo] = self.gap(m[todo], p[todo])
            gm = np.where(np.isfinite(gm), gm, 0.0)
            flip = np.sign(gm) != np.sign(gb)  # the root between b and m: b becomes the end
            keep = ~done
            a, ga = np.where(keep & flip, b, a), np.where(keep & flip, gb, ga)
            ga = np.where(keep & ~flip, 0.5 * ga, ga)  # the stale end's weight halved
            b, gb = np.where(keep, m, b), np.where(keep, gm, gb)
            # G is the difference of two tip heights, each to about 1e-15: converged there
            done |= np.abs(gm) <= _GAP_ATOL
        best = np.where(np.abs(gb) <= np.abs(ga), b, a)
        return np.where(ok, best, np.nan), np.where(ok, stable, False)


_SAMPLES = 8
_ITERATIONS = 60
#: The gap G at which a state is converged (h1's rounding, a few ulp of 1).
_GAP_ATOL = 1e-15


def valve_states(
    bed: HairBed,
    channel_length: float,
    *,
    pressure_drop: Any = None,
    flow_rate: Any = None,
    velocity: float = 0.0,
    max_steps: int = 4000,
) -> ValveStates:
    """Every coexisting state of a valve over a range of the pump, its folds and hysteresis.

    The pump sets either the pressure drop dp over the channel or the flow rate Q' per unit
    width. The branch of states is followed by pseudo-arclength continuation
    (:func:`hairbed.continue_loaded`) from rest to both ends of the range; at each grid value
    every crossing of the branch is a state (refined by regula falsi on the fixed-load gap
    G(h1) = z1 - h1, theory.md §11), its stability the sign of dG/dh1. The quasi-static ramps
    up and down follow the stable pieces and jump at the folds (:class:`ValveRamp`). States
    on a piece of the curve that the branch from rest does not reach within the range (an
    isolated loop) are not found.

    With both walls at rest a set pressure drop had one state wherever we looked (no fold for
    eps = L/H from 0.3 to 0.99, base angles from -1.4 to 1.4, abs(pi) up to 30). A set flow
    rate folds when the flow lifts the hairs (flow against their lean: ``base_angle`` and Q'
    of opposite signs): the gradient that pushes Q' through the closing gap grows like 1/g^3,
    a stronger feedback than the wall drive's (theory.md §11). At eps = 0.8, base_angle = -1.2
    the valve is bistable for 0.0764 < q < 0.2138, q = 6 A eta Q' L^2 / (E I H^2).

    A porous bed (``HairBed(..., model="porous")``, theory.md §13) follows the same
    continuation on its own G(h1, p), the tip height of its states with the gap frozen at
    h1 (:func:`hairbed.solve_porous_all`'s scan) minus h1; its flow is the flow through bed
    and gap and R/R0 the empty channel's flow over it, as :func:`valve_curve` has them. Where
    its hairs reach abs(theta) = pi/2 the branch leaves the model and the continuation
    stops there (status -3, the grid points beyond not covered).

    Parameters
    ----------
    bed : HairBed
        The bed (its channel height H and the fluid's viscosity included).
    channel_length : float
        l [m], positive.
    pressure_drop : array_like, optional
        The grid of set pressure drops dp = p(0) - p(l) [Pa], finite, 1-D.
    flow_rate : array_like, optional
        The grid of set flow rates per unit width Q' [m^2/s], finite, 1-D. Exactly one of
        ``pressure_drop`` and ``flow_rate``.
    velocity : float, optional
        Top wall speed v [m/s]. Default 0 (both walls at rest).
    max_steps : int, optional
        Continuation steps per direction, in [1, 10^6]. Default 4000 (bounded work).

    Returns
    -------
    ValveStates

    Examples
    --------
    >>> import numpy as np
    >>> from hairbed import HairBed
    >>> bed = HairBed(length=1.6e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
    ...               viscosity=1.0, spacing=400e-6, base_angle=-1.2)
    >>> s = valve_states(bed, 0.01, flow_rate=np.linspace(0.0, 3e-6, 7))
    >>> s.count.tolist()
    [1, 1, 3, 3, 1, 1, 1]
    >>> [round(j.drive_value * 1e6, 5) for j in s.ramp_up.jumps + s.ramp_down.jumps]
    [1.9723, 0.70526]
    """
    if not isinstance(bed, HairBed):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    bed._require_scalar("valve.valve_states")
    length = check_positive(channel_length, "channel_length", unit="m")
    if (pressure_drop is None) == (flow_rate is None):
        raise ValueError(
            "give exactly one of pressure_drop [Pa] and flow_rate [m^2/s]: what the pump sets"
        )
    drive = "pressure" if pressure_drop is not None else "flow"
    name, unit = ("pressure_drop", "Pa") if drive == "pressure" else ("flow_rate", "m^2/s")
    values = as_float_array(pressure_drop if drive == "pressure" else flow_rate, name, unit=unit)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D grid [{unit}], got shape {values.shape}")
    speed = check_number(velocity, "velocity")
    steps = check_int(max_steps, "max_steps", 1, 10**6)
    bed_drive = _Drive(bed, drive, speed, length)
    with np.errstate(over="ignore"):
        loads = values * bed_drive.scale
    bad = ~np.isfinite(loads)
    if np.any(bad):
        raise ValueError(
            f"{name} [{unit}] overflows the dimensionless load for this bed, got "
            f"{float(values[bad][0])!r}{_first_index(bad)}"
        )
    p, h, stab, folds, status, nfev = _branch(bed, bed_drive, loads, steps)
    out = _assemble(bed_drive, values, loads, p, h, stab, folds, status, nfev)
    if bed.density is not None:  # as valve_curve (HairBed.deform) checks it (issue 33)
        _warn_reynolds(_branch_reynolds(bed_drive, loads, p, h))
    over = np.isfinite(out.branch_tip_height) & ~np.isfinite(out.branch_pressure_drop)
    if np.any(over):
        raise ValueError(
            f"channel_length {length!r} m is too long for this bed: the pressure drop G l [Pa] "
            f"of its states overflows"
        )
    return out


def _branch_reynolds(
    d: _Drive, loads: NDArray[np.float64], p: NDArray[np.float64], h: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The gap's Reynolds number at the branch's states within the range of the loads."""
    inside = np.isfinite(h) & (p >= np.min(loads)) & (p <= np.max(loads))
    if d.porous:
        return d.si(p[inside], h[inside])["reynolds_number"]
    value = p[inside] / d.scale  # dp [Pa] or Q' [m^2/s]
    given = value / d.length if d.drive == "pressure" else value
    return gap_flow(d.bed, d.drive, d.v, given, h[inside])["reynolds_number"]


def _branch(
    bed: HairBed, d: _Drive, loads: NDArray[np.float64], steps: int
) -> tuple[Any, Any, Any, Any, int, int]:
    """The branch from rest to both ends of the loads' range, the folds inserted as points."""
    kw = {"pi": 0.0} if d.drive == "pressure" else {"q": 0.0}
    low, high = float(np.min(loads)), float(np.max(loads))
    pieces, folds, status, nfev = [], [], 0, 0
    # from rest (a single state) down to the low end, then up to the high end
    for stop in ([low] if low < 0.0 else []) + ([high] if high > 0.0 or low >= 0.0 else []):
        if d.porous:  # the same continuation on the porous bed's frozen-gap G(h, p)
            b = _continue_porous(bed, d, stop, steps)
        else:
            b = continue_loaded(
                d.omega2, bed.eps, bed.base_angle, stop=stop, max_steps=steps, **kw
            )
        nfev += b.nfev
        status = status if b.status == 0 else b.status
        piece = _with_folds(np.c_[b.values, b.tip_height, b.stable], b.folds)
        if stop < 0.0:
            pieces.append(piece[::-1])
            folds.append(b.folds[::-1])
        else:
            pieces.append(piece if not pieces else piece[1:])
            folds.append(b.folds)
    arr = np.vstack(pieces)
    return arr[:, 0], arr[:, 1], arr[:, 2].astype(bool), np.vstack(folds), status, nfev


def _continue_porous(bed: HairBed, d: _Drive, stop: float, steps: int) -> Any:
    """The porous bed's branch from rest (its low state at zero load) to the load ``stop``:
    :func:`hairbed.continue_loaded`'s continuation on the porous G(h, p) of the drive."""
    name = "pi" if d.code == 0 else "q"
    rest = bed._tip_state(
        np.array(d.omega2), bed.eps, bed.base_angle, "pressure" if d.code == 0 else "flow",
        np.array(0.0),
    )  # fmt: skip
    base = {"omega2": d.omega2, "eps": bed.eps, "theta0": bed.base_angle, name: 0.0}
    curve = _Curve(name, base, 1e-12, gap=d.gap)
    h0 = float(rest.tip_height)
    if not (int(rest.status) >= 0 and math.isfinite(h0)):
        return LoadedBranch(
            name, np.array([0.0]), np.array([np.nan]), np.array([False]), np.empty((0, 2)), -3, 0
        )
    return _follow(curve, 0.0, h0, stop, 0.02, steps)


def _with_folds(pts: NDArray[np.float64], folds: NDArray[np.float64]) -> NDArray[np.float64]:
    """The branch points (p, h, stable) with each fold (p, h) inserted where h lies between
    two neighbours at the turn (so the branch reaches the fold's extreme p)."""
    out = pts
    for fp, fh in folds:
        dp = np.diff(out[:, 0])
        best, where = np.inf, None
        for i in range(out.shape[0] - 1):
            lo, hi = sorted((out[i, 1], out[i + 1, 1]))
            if lo <= fh <= hi:
                # at a fold the branch's p turns: the segment next to a sign change of dp
                turn = (i > 0 and dp[i - 1] * dp[i] <= 0) or (
                    i + 1 < dp.size and dp[i] * dp[i + 1] <= 0
                )
                gap = abs(out[i, 0] - fp) + abs(out[i + 1, 0] - fp)
                if turn and gap < best:
                    best, where = gap, i
        if where is not None:
            out = np.insert(out, where + 1, [fp, fh, 0.0], axis=0)
    return out


def _crossings(p: NDArray[np.float64], v: float) -> NDArray[np.intp]:
    """The segments (i, i + 1) of the branch that cross load v (half-open, the last end in)."""
    rising = p[1:] >= p[:-1]
    inside = np.where(rising, (p[:-1] <= v) & (v < p[1:]), (p[1:] < v) & (v <= p[:-1]))
    idx = np.flatnonzero(inside)
    if p.size > 1 and p[-1] == v:
        idx = np.append(idx, p.size - 2)
    return np.unique(idx)


def _ramp(d: _Drive, p: Any, h: Any, direction: int) -> ValveRamp:
    """The quasi-static ramp along the branch (p ascending in its order for direction +1):
    the record values of the set drive are the points visited; a gap in them is a jump from
    the fold (the last record) to the landing crossing at the fold's load."""
    order = np.arange(p.size) if direction > 0 else np.arange(p.size)[::-1]
    pp, hh = p[order] * direction, h[order]
    path_p, path_h, jumps = [pp[0]], [hh[0]], []
    best, last = pp[0], 0
    for i in range(1, pp.size):
        if pp[i] <= best:
            continue
        if i > last + 1 and pp[i - 1] < best:  # jumped over a fold and the unstable piece
            frac = (best - pp[i - 1]) / (pp[i] - pp[i - 1])
            land, _ = d.states_at(
                np.array([best * direction]),
                np.array([hh[i - 1]]),
                np.array([hh[i]]),
                np.array([hh[i - 1] + frac * (hh[i] - hh[i - 1])]),
            )
            landing = float(land[0]) if np.isfinite(land[0]) else float(hh[i])
            path_p.append(best)
            path_h.append(landing)
            jumps.append((best * direction, float(hh[last]), landing))
        path_p.append(pp[i])
        path_h.append(hh[i])
        best, last = pp[i], i
    ps = np.array(path_p) * direction
    si = d.si(ps, np.array(path_h))
    out: list[ValveJump] = []
    for value, before, after in jumps:
        s = d.si(np.array([value, value]), np.array([before, after]))
        out.append(
            ValveJump(
                drive_value=float(value / d.scale),
                pressure_drop_before=float(s["pressure_drop"][0]),
                pressure_drop_after=float(s["pressure_drop"][1]),
                flow_rate_before=float(s["flow_rate"][0]),
                flow_rate_after=float(s["flow_rate"][1]),
                tip_height_before=float(s["tip_height"][0]),
                tip_height_after=float(s["tip_height"][1]),
            )
        )
    return ValveRamp(direction, si["pressure_drop"], si["flow_rate"], si["tip_height"], tuple(out))


def _assemble(
    d: _Drive,
    values: NDArray[np.float64],
    loads: NDArray[np.float64],
    p: Any,
    h: Any,
    stab: Any,
    folds: Any,
    status: int,
    nfev: int,
) -> ValveStates:
    """The grid's states from the branch, the ramps, the SI fields."""
    covered = (loads >= np.min(p)) & (loads <= np.max(p))
    seg = [_crossings(p, float(v)) if c else np.zeros(0, np.intp) for v, c in zip(loads, covered)]
    count = np.array([s.size for s in seg], dtype=np.int64)
    width = max(1, int(count.max(initial=0)))
    rows = np.repeat(np.arange(values.size), count)
    idx = np.concatenate(seg) if seg else np.zeros(0, np.intp)
    at = loads[rows]
    dp = p[idx + 1] - p[idx]
    frac = (at - p[idx]) / np.where(dp != 0.0, dp, 1.0)
    lin = h[idx] + frac * (h[idx + 1] - h[idx])
    hs, st = d.states_at(at, h[idx], h[idx + 1], lin)
    # where G(., value) has no sign change on the segment: the linear interpolation along the
    # branch, and the branch's stability
    miss = ~np.isfinite(hs)
    hs = np.where(miss, lin, hs)
    st = np.where(miss, stab[idx] & stab[idx + 1], st)
    # each grid point's states in columns, sorted by tip height
    order = np.lexsort((hs, rows))
    start = np.concatenate([[0], np.cumsum(count)[:-1]]).astype(np.intp)
    col = np.arange(order.size) - start[rows[order]]
    grid_h = np.full((values.size, width), np.nan)
    grid_p = np.full((values.size, width), np.nan)
    grid_s = np.zeros((values.size, width), dtype=np.bool_)
    grid_h[rows[order], col] = hs[order]
    grid_s[rows[order], col] = st[order]
    grid_p[rows[order], col] = loads[rows[order]]
    s = d.si(grid_p, grid_h)
    br = d.si(p, h)
    fo = d.si(folds[:, 0], folds[:, 1]) if folds.size else d.si(np.zeros(0), np.zeros(0))
    fold_point = np.isin(p, folds[:, 0]) if folds.size else np.zeros(p.size, dtype=np.bool_)
    message = "ok"
    if status != 0:
        reach = d.si(np.array([p.min(), p.max()]), np.array([h[0], h[-1]]))
        what = "pressure_drop" if d.drive == "pressure" else "flow_rate"
        message = (
            f"{STATUS_MESSAGES[status]}: the continuation reached {what} "
            f"{float(reach[what][0]):.6g} to {float(reach[what][1]):.6g} only; the grid "
            f"points beyond have count 0 (covered False)"
        )
    return ValveStates(
        drive=d.drive,
        channel_length=d.length,
        velocity=float(d.v),
        values=values,
        count=count,
        count_stable=np.sum(grid_s, axis=1).astype(np.int64),
        covered=covered,
        pressure_drop=s["pressure_drop"],
        flow_rate=s["flow_rate"],
        tip_height=s["tip_height"],
        resistance_ratio=s["resistance_ratio"],
        stable=grid_s,
        branch_pressure_drop=br["pressure_drop"],
        branch_flow_rate=br["flow_rate"],
        branch_tip_height=br["tip_height"],
        branch_stable=np.asarray(stab, dtype=np.bool_) & ~fold_point,
        fold_pressure_drop=fo["pressure_drop"],
        fold_flow_rate=fo["flow_rate"],
        fold_tip_height=fo["tip_height"],
        ramp_up=_ramp(d, p, h, +1),
        ramp_down=_ramp(d, p, h, -1),
        status=int(status),
        success=status == 0,
        message=message,
        nfev=int(nfev),
    )
