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
import functools
import io
import json
import math
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
from hairbed._variables import BED, BED_REQUIRED, SI, SOLUTION, names

__all__ = [
    "BED_KEYS",
    "DEFAULTS",
    "FLAG_KEYS",
    "INPUT_KEYS",
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
    "validate",
]

#: Every field of a :class:`hairbed.Solution`, in the dataclass's order.
SOLUTION_FIELDS: tuple[str, ...] = names(SOLUTION, "input", "branch", "state", "solve")

#: Segments of the discretisation of :func:`hairbed.stability.linear_stability` used live. Its
#: leading eigenvalue converges as 1/N^2; 60 segments classify the physical states as 100 do
#: (away from a fold, where no N is reliable) in about a third of the time.
STABILITY_SEGMENTS = 60

#: Inputs of a bed in SI units: key -> (label, unit). Keys are :class:`hairbed.HairBed`'s
#: (but the base angle, which is theta0's field) and the wall speed.
BED_KEYS: dict[str, tuple[str, str]] = {
    **{
        k: (BED[k].label + (" (optional)" if k == "density" else ""), BED[k].unit)
        for k in names(BED, "bed")
        if k != "base_angle"
    },
    "velocity": (SI["velocity"].label, SI["velocity"].unit),
}
#: Switches of the page (0 or 1).
FLAG_KEYS = ("si", "twirl")
#: Every input the page holds (and the URL carries), in the URL's order.
INPUT_KEYS: tuple[str, ...] = ("omega2", "eps", "theta0", "y", *FLAG_KEYS, *BED_KEYS)

#: The page at first sight: a hair leaning into the flow in a tight channel, just below the
#: window of three states (theory.md §5), and soft 1 mm hairs under glycerol for SI mode (the
#: example of :class:`hairbed.HairBed`).
DEFAULTS: dict[str, str] = {
    "omega2": "0.8",
    "eps": "0.9",
    "theta0": "-1.5",
    "y": "x1",
    "si": "0",
    "twirl": "0",
    "length": "0.001",
    "radius": "5e-05",
    "youngs_modulus": "1000000.0",
    "channel_height": "0.002",
    "viscosity": "1.0",
    "spacing": "0.0004",
    "packing_fraction": "",
    "density": "1260.0",
    "velocity": "0.1",
}
#: Quantities plotted against omega2 in the branch diagram.
Y_CHOICES = {"x1": "tip_deflection", "xi": "xi"}


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
    ValueError
        With the library's message (the first bad input, by name and allowed range).

    Examples
    --------
    >>> validate({"omega2": "2", "eps": "0.5", "theta0": "0"}).omega2
    2.0
    >>> validate({"eps": "1.5"})
    Traceback (most recent call last):
    ...
    ValueError: eps must lie in [0, 1), got 1.5
    """
    unknown = sorted(set(raw) - set(INPUT_KEYS))
    if unknown:
        raise ValueError(f"unknown parameter {unknown[0]!r}; known: {', '.join(INPUT_KEYS)}")
    full = {k: str(raw.get(k, DEFAULTS[k])) for k in INPUT_KEYS}
    y = full["y"].strip()
    if y not in Y_CHOICES:
        raise ValueError(f"y must be one of 'x1', 'xi', got {y!r}")
    si, twirl = _flag(full, "si"), _flag(full, "twirl")
    if not si:
        w, e, th = (_number(full[k]) for k in ("omega2", "eps", "theta0"))
        with _recording() as caught:
            hairbed.solve(w, e, th)  # the library's checks, with its messages
        return Params(
            float(w), float(e), float(th), y, si, twirl, raw=full, warnings=tuple(caught)
        )
    bed_args: dict[str, Any] = {k: _number(full[k]) for k in BED_REQUIRED}
    for k in ("spacing", "packing_fraction"):  # give exactly one: HairBed says so otherwise
        bed_args[k] = _number(full[k]) if full[k].strip() else None
    bed_args["base_angle"] = _number(full["theta0"])
    # optional: without it the states carry no Reynolds number (NaN) and no check of it
    bed_args["density"] = _number(full["density"]) if full["density"].strip() else None
    with _recording() as caught:
        bed = hairbed.HairBed(**bed_args)  # checks every size and the density by name
        velocity = _number(full["velocity"])
        omega2 = float(bed.omega2(velocity))  # checks the wall speed by name
    velocity = float(velocity)
    theta0 = -bed.base_angle if velocity < 0.0 else bed.base_angle
    return Params(
        omega2, bed.eps, theta0, y, si, twirl, bed, velocity, raw=full, warnings=tuple(caught)
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
    if params.si:
        keys += list(BED_KEYS)  # empty ones too: an empty spacing means "the packing fraction"
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
    warnings: list[str]
    timings: dict[str, float]


def _roots(n_roots: int) -> tuple[str, ...]:
    if n_roots >= 3:
        return ("low", "mid", "high")
    if n_roots == 2:  # exactly at a fold
        return ("low", "high")
    return ("low",)


@functools.lru_cache(maxsize=64)
def _branch_curve(
    eps: float, theta0: float, sign: int, n: int, y: str
) -> tuple[Any, Any, tuple[str, ...]]:
    """(omega2, y) along a branch (the exact parametric curve of
    :func:`hairbed.branches.curve`) and the warnings computing it issued (cached with it)."""
    with _recording() as caught:
        c = hairbed.branches.curve(eps, theta0, sign=sign, n=n, num=600)
    w = np.asarray(c.omega2, dtype=np.float64)
    v = np.asarray(getattr(c, Y_CHOICES[y]), dtype=np.float64)
    keep = np.isfinite(w) & np.isfinite(v) & (w > 0.0)
    return w[keep], v[keep], tuple(caught)


@functools.lru_cache(maxsize=64)
def _folds(eps: float, theta0: float, y: str) -> tuple[Any, Any, tuple[str, ...]]:
    """(omega2, y) at the folds of the physical branch, and the warnings (cached with them)."""
    w, v = np.empty(0), np.empty(0)
    with _recording() as caught:
        t = np.asarray(hairbed.branches.folds(eps, theta0).t, dtype=np.float64).reshape(-1)
        if t.size:
            s = hairbed.from_parameter(t, eps, theta0)
            w = np.asarray(s.omega2, dtype=np.float64).reshape(-1)
            v = np.asarray(getattr(s, Y_CHOICES[y]), dtype=np.float64).reshape(-1)
    return w, v, tuple(caught)


def _stability(sol: Any) -> tuple[bool | None, float]:
    """(stable, growth rate); (None, NaN) where the classification failed (its status)."""
    res = hairbed.stability.linear_stability(sol, STABILITY_SEGMENTS, 1)
    if int(np.asarray(getattr(res, "status", 0))) != 0:
        return None, float("nan")
    return bool(np.asarray(res.stable)), float(np.asarray(res.growth_rate))


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
        for root, sol in sols:
            stable, growth = _stability(sol)
            si = p.bed.deform(p.velocity, root=root) if p.si else None
            states.append(StateView(root, sol, stable, growth, si))
        t2 = time.perf_counter()
    twirling = [
        StateView(f"({s.sign:+d}, {s.n})", s, None, float("nan"), None) for s in twirling_sols
    ]
    cw, cy, curve_warnings = _branch_curve(e, th, 1, 0, p.y)
    branches = sorted({(s.sign, s.n) for s in twirling_sols})
    twirl_curves: list[tuple[str, Any, Any]] = []
    twirl_warnings: list[str] = []
    for sg, n in branches:
        bw, by, bwarn = _branch_curve(e, th, sg, n, p.y)
        twirl_curves.append((f"({sg:+d}, {n})", bw, by))
        twirl_warnings += bwarn
    fw, fy, fold_warnings = _folds(e, th, p.y)
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


def _plain(value: Any) -> Any:
    """JSON-safe Python values; NaN and infinities become None."""
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


#: SI fields of a :class:`hairbed.HairState`, with their units.
SI_FIELDS: dict[str, str] = {k: v.unit for k, v in SI.items()}


def _state_record(s: StateView) -> dict[str, Any]:
    rec: dict[str, Any] = {"state": s.label, "stable": s.stable, "growth_rate": s.growth_rate}
    rec.update(s.solution.as_dict())
    if s.si is not None:
        for k in SI_FIELDS:
            rec[f"si_{k}"] = getattr(s.si, k)
    return rec


def snapshot_json(snap: Snapshot) -> str:
    """The view as JSON: inputs, every state (every :class:`hairbed.Solution` field), folds."""
    p = snap.params
    doc: dict[str, Any] = {
        "hairbed_version": hairbed.__version__,
        "inputs": {k: p.raw[k] for k in INPUT_KEYS},
        "solved": {"omega2": p.omega2, "eps": p.eps, "theta0": p.theta0},
        "stability": f"hairbed.stability.linear_stability(N={STABILITY_SEGMENTS})",
        "states": [_state_record(s) for s in snap.states],
        "twirling": [_state_record(s) for s in snap.twirling],
        "folds": {"omega2": snap.folds_omega2, Y_CHOICES[p.y]: snap.folds_y},
        "warnings": snap.warnings,
    }
    if p.si and p.bed is not None:
        bed = p.bed
        doc["bed"] = {k: getattr(bed, k) for k in names(BED, "bed")}
        doc["bed"]["velocity"] = p.velocity
    return json.dumps(_plain_tree(doc), indent=2, allow_nan=False)


def _plain_tree(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _plain_tree(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_plain_tree(v) for v in value]
    return _plain(value)


def snapshot_csv(snap: Snapshot) -> str:
    """The view's states as CSV: one row per state (physical first, then twirling); empty
    cells for NaN and for what was not computed."""
    records = [_state_record(s) for s in [*snap.states, *snap.twirling]]
    columns: list[str] = []
    for rec in records:
        columns += [k for k in rec if k not in columns]
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(columns)
    for rec in records:
        row = []
        for k in columns:
            v = _plain(rec.get(k))
            row.append("" if v is None else repr(v) if isinstance(v, float) else v)
        writer.writerow(row)
    return buf.getvalue()
