"""What the explorer shows, without any web framework: inputs -> every state -> exports.

The page (``_page``) holds the inputs as text, exactly as typed or read from the URL. This
module turns them into validated parameters with the library's own checks
(:func:`hairbed.solve`, :class:`hairbed.HairBed`, :meth:`hairbed.HairBed.omega2`), solves every
coexisting state, classifies it with :func:`hairbed.stability.linear_stability` and packs what
the views, the table and the downloads need into a :class:`Snapshot`.

Everything here is plain Python and numpy, so it is tested without a browser.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import io
import json
import threading
import time
import warnings
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import parse_qsl, urlencode

import numpy as np

import hairbed
from hairbed._core.validation import check_positive
from hairbed._jsonsafe import to_plain
from hairbed._variables import BED, BED_REQUIRED, SI, SOLUTION, cf_attrs, names

__all__ = [
    "BED_KEYS",
    "DEFAULTS",
    "FLAG_KEYS",
    "INPUT_KEYS",
    "PRESETS",
    "InputError",
    "SOLUTION_FIELDS",
    "STABILITY_SEGMENTS",
    "Params",
    "Snapshot",
    "StateView",
    "compute",
    "cusp_curve",
    "inputs_from_query",
    "query_from_inputs",
    "snapshot_csv",
    "snapshot_json",
    "snapshot_shape_csv",
    "validate",
]

#: Every field of a :class:`hairbed.Solution`, in the dataclass's order.
SOLUTION_FIELDS: tuple[str, ...] = names(SOLUTION, "input", "branch", "state", "solve")

#: Segments of the discretisation of :func:`hairbed.stability.linear_stability` used live. Its
#: leading eigenvalue converges as 1/N^2; 60 segments classify the physical states as 100 do
#: (away from a fold, where no N is reliable) in about a third of the time.
STABILITY_SEGMENTS = 60

#: Inputs of a bed in SI units: key -> (label, unit). Keys are :class:`hairbed.HairBed`'s
#: fields (the base angle among them: a bed's own, not carried over from theta0) and the wall
#: speed.
BED_KEYS: dict[str, tuple[str, str]] = {
    **{
        k: (BED[k].label + (" (optional)" if k == "density" else ""), BED[k].unit)
        for k in names(BED, "bed")
    },
    "velocity": (SI["velocity"].label, SI["velocity"].unit),
}
#: Switches of the page (0 or 1).
FLAG_KEYS = ("si", "twirl")
#: Every input the page holds (and the URL carries), in the URL's order.
INPUT_KEYS: tuple[str, ...] = ("omega2", "eps", "theta0", "y", *FLAG_KEYS, "x", *BED_KEYS)

#: The page at first sight: the paper's worked example (omega^2 = 2, eps = 0.5, theta0 = 0,
#: arXiv:2203.04169 §4), and for SI mode upright soft 1 mm pillars under glycerol (the example
#: of :class:`hairbed.HairBed`).
DEFAULTS: dict[str, str] = {
    "omega2": "2",
    "eps": "0.5",
    "theta0": "0",
    "y": "x1",
    "si": "0",
    "twirl": "0",
    "x": "speed",
    "length": "0.001",
    "radius": "5e-05",
    "youngs_modulus": "1000000.0",
    "channel_height": "0.002",
    "viscosity": "1.0",
    "spacing": "0.0004",
    "packing_fraction": "",
    "base_angle": "0",
    "density": "1260.0",
    "velocity": "0.1",
}
#: Starting points, each a set of inputs (the others take :data:`DEFAULTS`): name -> inputs.
PRESETS: dict[str, dict[str, str]] = {
    "worked example": {"omega2": "2", "eps": "0.5", "theta0": "0"},
    # inside the window of three states of a hair leaning into the flow (theory.md §5)
    "bistable window": {"omega2": "1.2", "eps": "0.9", "theta0": "-1.5"},
    "twirling states": {"omega2": "200", "eps": "0.5", "theta0": "0", "twirl": "1"},
    # a wall-shear-stress sensor: 1 mm PDMS-like pillars in glycerol, Stokes flow (Re ~ 0.2)
    "sensor bed (SI)": {"si": "1", "velocity": "0.1", "base_angle": "0"},
}
#: Quantities plotted against the forcing in the branch diagram.
Y_CHOICES = {"x1": "tip_deflection", "xi": "xi"}
#: Abscissae of the branch diagram in SI mode: the wall speed or the wall shear stress.
X_CHOICES = ("speed", "stress")


class InputError(ValueError):
    """Every bad input of a view, each with the library's message.

    Attributes
    ----------
    messages : tuple of str
        One message per bad parameter (by name and allowed range), in the order of
        :data:`INPUT_KEYS`. ``str()`` of the error is the messages joined by "; ".
    """

    def __init__(self, messages: list[str]) -> None:
        self.messages = tuple(messages)
        super().__init__("; ".join(messages))


def _number(text: str) -> Any:
    """A typed number as a float, or the text itself (then the library refuses it by name)."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        return text


def _flag(raw: Mapping[str, str], key: str) -> bool:
    value = raw.get(key, DEFAULTS[key]).strip().lower()
    if value in ("1", "true", "on", "yes"):
        return True
    if value in ("0", "false", "off", "no", ""):
        return False
    raise ValueError(f"{key} must be 0 or 1, got {value!r}")


def _message(check: Any, *args: Any, **kwargs: Any) -> str | None:
    """The library's message if ``check`` refuses its arguments, else None (warnings
    dropped: only the message of a refused input is wanted)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            check(*args, **kwargs)
    except ValueError as exc:
        return str(exc)
    return None


@dataclass(frozen=True)
class Params:
    """Validated inputs of one view.

    Attributes
    ----------
    omega2, eps, theta0 : float
        The dimensionless problem actually solved [-, -, rad] (in SI mode derived from the bed:
        theta0 is the base angle mirrored for a negative wall speed, see :mod:`hairbed.units`).
    y : str
        Ordinate of the branch diagram: "x1" (tip deflection) or "xi".
    si : bool
        SI mode: the bed below and the wall speed set omega2 and eps.
    twirl : bool
        Also show the twirling states of every other branch (:func:`hairbed.solve_all`).
    bed : HairBed or None
        The bed (SI mode only).
    velocity : float or None
        Wall speed v [m/s] (SI mode only).
    raw : dict
        The inputs as text, exactly as validated (what the URL carries).
    x : str
        Abscissa of the branch diagram in SI mode: "speed" (wall speed) or "stress" (wall shear
        stress).
    warnings : tuple of str
        The warnings the library issued while validating (e.g. :class:`hairbed.UnitsWarning`
        of :class:`hairbed.HairBed` for an implausible size), as "Category: message".
    """

    omega2: float
    eps: float
    theta0: float
    y: str
    si: bool
    twirl: bool
    bed: Any = None
    velocity: float | None = None
    raw: dict[str, str] = field(default_factory=dict)
    warnings: tuple[str, ...] = ()
    x: str = "speed"


@contextmanager
def _recording() -> Iterator[list[str]]:
    """Record every warning issued inside (each time, not once per place) as
    "Category: message" with the whitespace of the message collapsed.

    The warnings filters are process-wide: this relies on the page's callbacks running one at
    a time on the server's event loop (Panel's default).
    """
    out: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield out
        finally:
            for w in caught:
                text = f"{w.category.__name__}: {' '.join(str(w.message).split())}"
                if text not in out:
                    out.append(text)


def _merge(*groups: Any) -> list[str]:
    """The warnings of several groups, in order, each once."""
    return list(dict.fromkeys(w for g in groups for w in g))


#: Valid stand-ins for the inputs not under test when each one is checked alone.
_GOOD = {"omega2": 1.0, "eps": 0.5, "theta0": 0.0}
#: The SI units in which :class:`hairbed.HairBed` checks each positive size.
_SIZE_UNITS = {
    "length": "m",
    "radius": "m",
    "youngs_modulus": "Pa",
    "channel_height": "m",
    "viscosity": "Pa*s",
}


def _bed_args(full: Mapping[str, str]) -> dict[str, Any]:
    """The arguments of :class:`hairbed.HairBed` from the page's text (empty: not given)."""
    args: dict[str, Any] = {k: _number(full[k]) for k in (*BED_REQUIRED, "base_angle")}
    for k in ("spacing", "packing_fraction", "density"):  # optional
        args[k] = _number(full[k]) if full[k].strip() else None
    return args


_REFERENCE_BED = _bed_args(DEFAULTS)


def _bed_problems(args: Mapping[str, Any]) -> list[str]:
    """The library's message for each bed parameter it refuses on its own, then (if each is
    fine alone) the one for the combination (e.g. hairs longer than the channel is high).

    Each parameter is checked by the library with the others at valid reference values
    where they do not enter its check (the sizes by the check :class:`hairbed.HairBed`
    applies to each, :func:`hairbed._core.validation.check_positive`)."""
    out: list[str] = []
    for k, unit in _SIZE_UNITS.items():
        m = _message(check_positive, args[k], k, unit)
        if m:
            out.append(m)
    spacing, packing = args["spacing"], args["packing_fraction"]
    if spacing is not None and packing is None:
        m = _message(check_positive, spacing, "spacing", "m")
    else:  # the packing fraction alone, or both or neither (the bed says which to give)
        m = _message(
            hairbed.HairBed, **{**_REFERENCE_BED, "spacing": spacing, "packing_fraction": packing}
        )
    if m:
        out.append(m)
    for k in ("base_angle", "density"):
        m = _message(hairbed.HairBed, **{**_REFERENCE_BED, k: args[k]})
        if m:
            out.append(m)
    if not out:
        m = _message(hairbed.HairBed, **args)
        if m:
            out.append(m)
    return out


def validate(raw: Mapping[str, str]) -> Params:
    """Check the page's inputs with the library's own checks.

    Parameters
    ----------
    raw : mapping of str to str
        Inputs as typed (missing keys take :data:`DEFAULTS`).

    Returns
    -------
    Params

    Raises
    ------
    InputError
        A ValueError with the library's message for every bad input (by name and allowed
        range), not only the first.

    Examples
    --------
    >>> validate({"omega2": "2", "eps": "0.5", "theta0": "0"}).omega2
    2.0
    >>> validate({"eps": "1.5"})
    Traceback (most recent call last):
    ...
    hairbed.explorer._model.InputError: eps must lie in [0, 1), got 1.5
    """
    problems: list[str] = []
    unknown = sorted(set(raw) - set(INPUT_KEYS))
    if unknown:
        problems.append(
            f"unknown parameter{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(repr(k) for k in unknown)}; known: {', '.join(INPUT_KEYS)}"
        )
    full = {k: str(raw.get(k, DEFAULTS[k])) for k in INPUT_KEYS}
    y, x_kind = full["y"].strip(), full["x"].strip()
    if y not in Y_CHOICES:
        problems.append(f"y must be one of 'x1', 'xi', got {y!r}")
    if x_kind not in X_CHOICES:
        problems.append(f"x must be one of 'speed', 'stress', got {x_kind!r}")
    flags = {}
    for k in FLAG_KEYS:
        try:
            flags[k] = _flag(full, k)
        except ValueError as exc:
            problems.append(str(exc))
            flags[k] = False
    si, twirl = flags["si"], flags["twirl"]
    if not si:
        values = {k: _number(full[k]) for k in ("omega2", "eps", "theta0")}
        m = None
        with _recording() as caught:
            try:
                hairbed.solve(**values)  # the library's checks, with its messages
            except ValueError as exc:
                m = str(exc)
        if m is not None:  # which of them: each alone, the others at valid values
            alone = [_message(hairbed.solve, **{**_GOOD, k: v}) for k, v in values.items()]
            problems += [a for a in alone if a] or [m]
        if problems:
            raise InputError(problems)
        w, e, th = (float(values[k]) for k in ("omega2", "eps", "theta0"))
        return Params(w, e, th, y, si, twirl, raw=full, warnings=tuple(caught), x=x_kind)
    bed_args = _bed_args(full)
    velocity = _number(full["velocity"])
    with _recording() as caught:
        try:
            bed = hairbed.HairBed(**bed_args)  # checks every size and the density by name
        except ValueError:
            bed = None
            problems += _bed_problems(bed_args)
        # the wall speed: against this bed, or the reference one if this one is bad
        m = _message((bed or hairbed.HairBed(**_REFERENCE_BED)).omega2, velocity)
        if m:
            problems.append(m)
        if problems:
            raise InputError(problems)
        assert bed is not None
        omega2 = float(bed.omega2(velocity))
    velocity = float(velocity)
    theta0 = (-bed.base_angle if velocity < 0.0 else bed.base_angle) + 0.0  # no -0.0
    # the problem solved, written out: the URL and the fields show the view's own values
    full.update(omega2=repr(omega2), eps=repr(bed.eps), theta0=repr(theta0))
    return Params(
        omega2,
        bed.eps,
        theta0,
        y,
        si,
        twirl,
        bed,
        velocity,
        raw=full,
        warnings=tuple(caught),
        x=x_kind,
    )


def inputs_from_query(query: str) -> dict[str, str]:
    """The inputs carried by a URL query string ('?omega2=2&eps=0.5'), as text.

    Examples
    --------
    >>> inputs_from_query("?omega2=2&eps=0.5")
    {'omega2': '2', 'eps': '0.5'}
    """
    return dict(parse_qsl(query.lstrip("?"), keep_blank_values=True))


def query_from_inputs(params: Params) -> str:
    """The URL query string of a view: the dimensionless inputs, and the bed in SI mode.

    Examples
    --------
    >>> query_from_inputs(validate({"omega2": "2", "eps": "0.5", "theta0": "0"}))
    '?omega2=2&eps=0.5&theta0=0&y=x1&si=0&twirl=0'
    """
    keys = ["omega2", "eps", "theta0", "y", *FLAG_KEYS]
    if params.si:  # omega2, eps and theta0 then the bed's (Params.raw holds them)
        keys += ["x", *BED_KEYS]  # empty ones too: an empty spacing means "the packing fraction"
    return "?" + urlencode({k: params.raw[k].strip() for k in keys})


@dataclass(frozen=True)
class StateView:
    """One state on screen.

    Attributes
    ----------
    label : str
        "low", "mid", "high" on the physical branch; "(+1, 2)" (sign, n) for a twirling one.
    solution : Solution
        The exact state (:func:`hairbed.solve` or :func:`hairbed.solve_all`).
    stable : bool or None
        Linear stability (:func:`hairbed.stability.linear_stability`); None when not computed
        (twirling states).
    growth_rate : float
        Largest real part of the eigenvalues [1 / bending relaxation time]; NaN if not computed.
    si : HairState or None
        The state in SI units (SI mode, physical states; :meth:`hairbed.HairBed.deform`), with
        the library's gap Reynolds number ``si.reynolds_number`` (NaN without a density).
    """

    label: str
    solution: Any
    stable: bool | None
    growth_rate: float
    si: Any = None


@dataclass(frozen=True)
class BranchDiagram:
    """The branch diagram as drawn: against the forcing omega^2 or, in SI mode, against the
    bed's wall speed or wall shear stress, with the tip deflection in metres.

    Attributes
    ----------
    x_label, y_label : str
        Axis labels, with units.
    x_range : (float, float)
        The abscissae of omega^2 in [1e-3, 1e3] (the range shown first).
    curve_x, curve_y : ndarray
        The physical branch.
    folds_x, folds_y : ndarray
        Its folds.
    twirl_curves : list of (str, ndarray, ndarray)
        (label, x, y) of the branches of the twirling states shown.
    states_x, states_y : list of float
        The physical states, in the order of :attr:`Snapshot.states`.
    twirl_x, twirl_y : list of float
        The twirling states, in the order of :attr:`Snapshot.twirling`.
    now : float or None
        Abscissa of the current forcing (None against the stress, which differs between
        coexisting states).
    """

    x_label: str
    y_label: str
    x_range: tuple[float, float]
    curve_x: np.ndarray
    curve_y: np.ndarray
    folds_x: np.ndarray
    folds_y: np.ndarray
    twirl_curves: list[tuple[str, np.ndarray, np.ndarray]]
    states_x: list[float]
    states_y: list[float]
    twirl_x: list[float]
    twirl_y: list[float]
    now: float | None


_FORCING_WINDOW = (1e-3, 1e3)


@dataclass(frozen=True)
class Snapshot:
    """Everything one view shows, computed from one :class:`Params`.

    Attributes
    ----------
    params : Params
    states : list of StateView
        The coexisting physical states, in order of increasing xi.
    twirling : list of StateView
        States of the other branches (only when ``params.twirl``).
    curve_omega2, curve_y : ndarray
        The physical branch of the current (eps, theta0) in the branch diagram.
    twirl_curves : list of (str, ndarray, ndarray)
        (label, omega2, y) of the branches of the twirling states shown.
    folds_omega2, folds_y : ndarray
        The folds of the physical branch (:func:`hairbed.branches.folds`).
    branch : BranchDiagram
        The branch diagram as drawn (in SI mode against the bed's wall speed or stress).
    warnings : list of str
        Every warning the library issued for this view, as "Category: message", each once:
        those of validation (:attr:`Params.warnings`) and of solving, classifying and
        deforming (e.g. :class:`hairbed.ModelValidityWarning` of :meth:`hairbed.HairBed.deform`
        where the gap's Reynolds number exceeds the Stokes regime).
    timings : dict of str to float
        Wall times of the computation [ms]: "solve" (every state), "stability", "total".
    """

    params: Params
    states: list[StateView]
    twirling: list[StateView]
    curve_omega2: np.ndarray
    curve_y: np.ndarray
    twirl_curves: list[tuple[str, np.ndarray, np.ndarray]]
    folds_omega2: np.ndarray
    folds_y: np.ndarray
    branch: BranchDiagram
    warnings: list[str]
    timings: dict[str, float]


def _roots(n_roots: int) -> tuple[str, ...]:
    if n_roots >= 3:
        return ("low", "mid", "high")
    if n_roots == 2:  # exactly at a fold
        return ("low", "high")
    return ("low",)


@functools.lru_cache(maxsize=64)
def _branch_curve(eps: float, theta0: float, sign: int, n: int) -> tuple[Any, tuple[str, ...]]:
    """The states along a branch (the exact parametric curve of :func:`hairbed.branches.curve`)
    and the warnings computing it issued (cached with it)."""
    with _recording() as caught:
        c = hairbed.branches.curve(eps, theta0, sign=sign, n=n, num=600)
    return c, tuple(caught)


@functools.lru_cache(maxsize=64)
def _folds(eps: float, theta0: float) -> tuple[Any, tuple[str, ...]]:
    """The states at the folds of the physical branch (None if none), and the warnings."""
    with _recording() as caught:
        t = np.asarray(hairbed.branches.folds(eps, theta0).t, dtype=np.float64).reshape(-1)
        s = hairbed.from_parameter(t, eps, theta0) if t.size else None
    return s, tuple(caught)


@functools.lru_cache(maxsize=16)
def _without_density(bed: Any) -> Any:
    """The bed without its fluid density: its states along a whole branch carry no Reynolds
    number and issue no warning about it (the view's warnings are its own states')."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # issued for the bed itself already
        return dataclasses.replace(bed, density=None, packing_fraction=None)


def _xy(p: Params, sol: Any) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of the branch diagram of states (a branch curve, folds): (omega^2, x1 or xi), or
    in SI mode (abs(v) [m/s] or abs(tau) [Pa], x1 L [m] or xi), the bed's own state at the
    speed that holds each (:class:`hairbed.units.HairState`; mirrored for v < 0)."""
    if sol is None:
        return np.empty(0), np.empty(0)
    w = np.asarray(sol.omega2, dtype=np.float64).reshape(-1)
    if not p.si:
        y = np.asarray(getattr(sol, Y_CHOICES[p.y]), dtype=np.float64).reshape(-1)
        x = w
    else:
        bed = _without_density(p.bed)
        direction = np.full(w.shape, -1.0 if (p.velocity or 0.0) < 0.0 else 1.0)
        with np.errstate(all="ignore"):
            st = bed._state(direction * w * bed.velocity_scale, direction, w, sol)
        x = np.abs(np.asarray(st.velocity if p.x == "speed" else st.wall_shear_stress))
        x = x.reshape(-1)
        y = np.asarray(st.tip_deflection if p.y == "x1" else sol.xi, dtype=np.float64)
        y = y.reshape(-1)
    return x, y


@functools.lru_cache(maxsize=64)
def _si_branch(
    bed: Any, backwards: bool, x: str, y: str, eps: float, theta0: float, sign: int, n: int
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of a whole branch in SI mode (cached: a move of the wall speed alone keeps the
    bed, the flow's direction and the branch)."""
    p = Params(0.0, eps, theta0, y, True, False, bed, -1.0 if backwards else 1.0, x=x)
    return _xy(p, _branch_curve(eps, theta0, sign, n)[0])


def _curve_xy(p: Params, curve: Any, sign: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) of the branch (sign, n) of the view, whose states are ``curve``."""
    if not p.si:
        return _xy(p, curve)
    backwards = (p.velocity or 0.0) < 0.0
    return _si_branch(p.bed, backwards, p.x, p.y, p.eps, p.theta0, sign, n)


def _shown(xy: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The points of a curve that a log abscissa can show (finite, x > 0)."""
    x, y = xy
    keep = np.isfinite(x) & np.isfinite(y) & (x > 0.0)
    return x[keep], y[keep]


def _labels(p: Params) -> tuple[str, str]:
    if not p.si:
        y = "tip deflection x1/L [-]" if p.y == "x1" else "xi = sin(theta1) [-]"
        return "forcing omega^2 [-]", y
    x = (
        f"wall speed |v| [{SI['velocity'].unit}]"
        if p.x == "speed"
        else f"wall shear stress |tau| [{SI['wall_shear_stress'].unit}]"
    )
    y = f"tip deflection x1 L [{SI['tip_deflection'].unit}]" if p.y == "x1" else "xi [-]"
    return x, y


def _diagram(
    p: Params, curve: Any, folds: Any, twirl: list[tuple[int, int, Any]], states: list[StateView],
    twirling: list[StateView],
) -> BranchDiagram:  # fmt: skip
    cx, cy = _curve_xy(p, curve, 1, 0)
    fx, fy = _shown(_xy(p, folds))
    lo, hi = _FORCING_WINDOW
    now: float | None
    if not p.si:
        sx = [p.omega2] * len(states)
        sy = [float(getattr(s.solution, Y_CHOICES[p.y])) for s in states]
        x_range, now = (lo, hi), p.omega2
    else:
        sx = [
            abs(float(s.si.velocity if p.x == "speed" else s.si.wall_shear_stress)) for s in states
        ]
        sy = [float(s.si.tip_deflection if p.y == "x1" else s.solution.xi) for s in states]
        if p.x == "speed":
            x_range = (lo * p.bed.velocity_scale, hi * p.bed.velocity_scale)
        else:  # the stresses the curve reaches while omega^2 is in the window
            w = np.asarray(curve.omega2, dtype=np.float64).reshape(-1)
            win = cx[(w >= lo) & (w <= hi) & np.isfinite(cx) & (cx > 0.0)]
            x_range = (float(win.min()), float(win.max())) if win.size else (lo, hi)
        now = sx[0] if p.x == "speed" else None
    cx, cy = _shown((cx, cy))
    tx, ty = [], []
    for s in twirling:  # a NaN (not drawn) where the log abscissa cannot show it
        x, y = _xy(p, s.solution)
        tx.append(float(x[0]) if x.size else float("nan"))
        ty.append(float(y[0]) if y.size else float("nan"))
    curves = [(f"({sg:+d}, {n})", *_shown(_curve_xy(p, c, sg, n))) for sg, n, c in twirl]
    x_label, y_label = _labels(p)
    return BranchDiagram(x_label, y_label, x_range, cx, cy, fx, fy, curves, sx, sy, tx, ty, now)


def compute(p: Params) -> Snapshot:
    """Solve every state of one view and classify each physical state's stability.

    Every warning the library issues on the way (and in :func:`validate`) is kept in
    :attr:`Snapshot.warnings`: the page shows exactly the library's judgement of the model's
    validity (e.g. the Reynolds number of :meth:`hairbed.HairBed.deform`).

    Examples
    --------
    >>> snap = compute(validate({"omega2": "1.2", "eps": "0.9", "theta0": "-1.5"}))
    >>> [(s.label, s.stable) for s in snap.states]
    [('low', True), ('mid', False), ('high', True)]
    """
    t0 = time.perf_counter()
    w, e, th = p.omega2, p.eps, p.theta0
    with _recording() as caught:
        low = hairbed.solve(w, e, th)
        sols = [
            (r, low if r == "low" else hairbed.solve(w, e, th, root=r))
            for r in _roots(int(low.n_roots))
        ]
        twirling_sols = (
            [s for s in hairbed.solve_all(w, e, th) if not (s.sign == 1 and s.n == 0)]
            if p.twirl
            else []
        )
        t1 = time.perf_counter()
        states = []
        for s in hairbed.branches.label_states([sol for _, sol in sols], STABILITY_SEGMENTS):
            si = p.bed.deform(p.velocity, root=s.root) if p.si else None
            states.append(StateView(s.root, s.solution, s.stable, s.growth_rate, si))
        t2 = time.perf_counter()
    twirling = [
        StateView(f"({s.sign:+d}, {s.n})", s, None, float("nan"), None) for s in twirling_sols
    ]
    curve, curve_warnings = _branch_curve(e, th, 1, 0)
    branches = sorted({(s.sign, s.n) for s in twirling_sols})
    twirl: list[tuple[int, int, Any]] = []  # (sign, n, the branch's states)
    twirl_warnings: list[str] = []
    for sg, n in branches:
        c, bwarn = _branch_curve(e, th, sg, n)
        twirl.append((sg, n, c))
        twirl_warnings += bwarn
    fold_states, fold_warnings = _folds(e, th)
    plain = dataclasses.replace(p, si=False) if p.si else p  # the dimensionless variables
    cw, cy = _shown(_xy(plain, curve))
    fw, fy = _shown(_xy(plain, fold_states))
    twirl_curves = [(f"({sg:+d}, {n})", *_shown(_xy(plain, c))) for sg, n, c in twirl]
    diagram = _diagram(p, curve, fold_states, twirl, states, twirling)
    t3 = time.perf_counter()
    return Snapshot(
        p,
        states,
        twirling,
        cw,
        cy,
        twirl_curves,
        fw,
        fy,
        diagram,
        _merge(p.warnings, caught, curve_warnings, twirl_warnings, fold_warnings),
        {
            "solve": 1e3 * (t1 - t0),
            "stability": 1e3 * (t2 - t1),
            "total": 1e3 * (t3 - t0),
        },
    )


# -- the bistability map: the cusp eps_c(theta0), once per process -----------------------------

_CUSP_LOCK = threading.Lock()
_CUSP: tuple[np.ndarray, np.ndarray] | None = None
#: Base angles of the cusp curve, denser near -pi/2 where eps_c changes fastest.
_CUSP_THETA0 = -0.5 * np.pi + (0.5 * np.pi - 0.02) * np.linspace(0.0, 1.0, 24) ** 1.6 + 0.02


def cusp_curve() -> tuple[np.ndarray, np.ndarray]:
    """(theta0, eps_c) of :func:`hairbed.branches.cusp` on a grid of base angles in (-pi/2, 0).

    Computed once per process (a few seconds) and shared by every session.
    """
    global _CUSP
    with _CUSP_LOCK:
        if _CUSP is None:
            th = np.asarray(_CUSP_THETA0, dtype=np.float64)
            ec = np.asarray(hairbed.branches.cusp(th), dtype=np.float64)
            _CUSP = (th, ec)
        return _CUSP


# -- exports ------------------------------------------------------------------------------------


#: SI fields of a :class:`hairbed.HairState`, with their units.
SI_FIELDS: dict[str, str] = {k: v.unit for k, v in SI.items()}


#: Points along the hair in the exported shapes (equally spaced in arc length).
SHAPE_POINTS = 101

_STATE_COLUMNS: dict[str, dict[str, str]] = {
    "state": {"units": "", "long_name": "which coexisting state: low, mid, high, (sign, n)"},
    "stable": {"units": "", "long_name": "linearly stable (hairbed.stability.linear_stability)"},
    "growth_rate": {
        "units": "1",
        "long_name": "largest real part of the eigenvalues, in units of 1/bending relaxation time",
    },
}
_SHAPE_COLUMNS: dict[str, dict[str, str]] = {
    "sigma": {"units": "1", "long_name": "arc length s/L from the base"},
    "x": {"units": "1", "long_name": "horizontal position x(s)/L (the solved problem's frame)"},
    "z": {"units": "1", "long_name": "height z(s)/L above the wall"},
    "theta": {"units": "rad", "long_name": "angle theta(s) from the wall normal"},
    "si_x": {"units": "m", "long_name": "horizontal position along +x of the bed (x L)"},
    "si_z": {"units": "m", "long_name": "height above the wall (z L)"},
}


def _attrs(column: str) -> dict[str, str]:
    """CF attributes (units, long_name) of an exported column."""
    if column in _STATE_COLUMNS:
        return _STATE_COLUMNS[column]
    if column.startswith("si_") and column[3:] in SI:
        return cf_attrs(SI[column[3:]])
    return cf_attrs(SOLUTION[column])


def _header(column: str) -> str:
    """A CSV heading "name [units]" (hairbed's CSV style; no brackets without units)."""
    units = _attrs(column)["units"] if column not in _SHAPE_COLUMNS else ""
    units = units or _SHAPE_COLUMNS.get(column, {}).get("units", "")
    return f"{column} [{units}]" if units else column


def _state_record(s: StateView) -> dict[str, Any]:
    rec: dict[str, Any] = {"state": s.label, "stable": s.stable, "growth_rate": s.growth_rate}
    rec.update(s.solution.as_dict())
    if s.si is not None:
        for k in SI_FIELDS:
            rec[f"si_{k}"] = getattr(s.si, k)
    return rec


def _shape(s: StateView) -> dict[str, Any]:
    """The hair's shape: arc length, x, z, theta [L, L, L, rad] (and x, z in metres in the
    bed's frame, :meth:`hairbed.units.HairState.profile`, in SI mode)."""
    sigma = np.linspace(0.0, 1.0, SHAPE_POINTS)
    sol = s.solution
    out: dict[str, Any] = {
        "sigma": sigma,
        "x": np.asarray(sol.x(sigma), dtype=np.float64),
        "z": np.asarray(sol.z(sigma), dtype=np.float64),
        "theta": np.asarray(sol.theta(sigma), dtype=np.float64),
    }
    if s.si is not None:
        out["si_x"], out["si_z"] = s.si.profile(SHAPE_POINTS)
    return out


def snapshot_json(snap: Snapshot) -> str:
    """The view as JSON: inputs, every state (every :class:`hairbed.Solution` field and its
    shape), folds, and the CF units and long name of every exported variable."""
    p = snap.params
    states = [{**_state_record(s), "shape": _shape(s)} for s in snap.states]
    twirling = [{**_state_record(s), "shape": _shape(s)} for s in snap.twirling]
    columns = list(dict.fromkeys(k for r in [*states, *twirling] for k in r if k != "shape"))
    doc: dict[str, Any] = {
        "hairbed_version": hairbed.__version__,
        "inputs": {k: p.raw[k] for k in INPUT_KEYS},
        "solved": {"omega2": p.omega2, "eps": p.eps, "theta0": p.theta0},
        "stability": f"hairbed.stability.linear_stability(N={STABILITY_SEGMENTS})",
        "states": states,
        "twirling": twirling,
        "folds": {"omega2": snap.folds_omega2, Y_CHOICES[p.y]: snap.folds_y},
        "warnings": snap.warnings,
        "variables": {k: _attrs(k) for k in columns},
        "shape_variables": {
            k: v for k, v in _SHAPE_COLUMNS.items() if p.si or not k.startswith("si_")
        },
    }
    if p.si and p.bed is not None:
        bed = p.bed
        doc["bed"] = {k: getattr(bed, k) for k in names(BED, "bed")}
        doc["bed"]["velocity"] = p.velocity
        doc["bed_variables"] = {k: cf_attrs(BED[k]) for k in names(BED, "bed")}
        doc["bed_variables"]["velocity"] = cf_attrs(SI["velocity"])
    return json.dumps(to_plain(doc), indent=2, allow_nan=False)


def _cell(value: Any) -> Any:
    v = to_plain(value)
    return "" if v is None else repr(v) if isinstance(v, float) else v


def snapshot_csv(snap: Snapshot) -> str:
    """The view's states as CSV: one row per state (physical first, then twirling), headed
    "name [units]" (CF units, as hairbed's sweeps write them); empty cells for NaN and for
    what was not computed."""
    records = [_state_record(s) for s in [*snap.states, *snap.twirling]]
    columns: list[str] = []
    for rec in records:
        columns += [k for k in rec if k not in columns]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow([_header(k) for k in columns])
    for rec in records:
        writer.writerow([_cell(rec.get(k)) for k in columns])
    return buf.getvalue()


def snapshot_shape_csv(snap: Snapshot) -> str:
    """The hair's shape of every state as CSV, long format: one row per point along each
    hair (physical states first, then twirling), headed "name [units]": state, arc length
    sigma, x, z, theta (in units of L and rad) and, in SI mode, x and z in metres."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    columns = [k for k in _SHAPE_COLUMNS if snap.params.si or not k.startswith("si_")]
    writer.writerow(["state", *(_header(k) for k in columns)])
    for s in [*snap.states, *snap.twirling]:
        shape = _shape(s)
        cols = [shape.get(k, np.full(SHAPE_POINTS, np.nan)) for k in columns]
        for i in range(SHAPE_POINTS):
            writer.writerow([s.label, *(_cell(float(c[i])) for c in cols)])
    return buf.getvalue()
