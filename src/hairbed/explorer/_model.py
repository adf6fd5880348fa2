"""What the explorer shows, without any web framework: inputs -> every state -> exports.

The page (``_page``) holds the inputs as text, exactly as typed or read from the URL. This
module turns them into validated parameters with the library's own checks
(:func:`hairbed.solve`, :class:`hairbed.HairBed`, :meth:`hairbed.HairBed.omega2`), solves every
coexisting state, classifies it with :func:`hairbed.stability.linear_stability` and packs what
the views, the table and the downloads need into a :class:`Snapshot`. A pump drive (a set
pressure gradient or flow rate, theory.md §11) is solved by :func:`hairbed.solve_loaded_all`
and :meth:`hairbed.HairBed.deform`; the valve view by :mod:`hairbed.valve` (:class:`ValveView`).

Everything here is plain Python and numpy, so it is tested without a browser.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import io
import json
import math
import threading
import time
import warnings
from collections import OrderedDict
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import parse_qsl, urlencode

import numpy as np

import hairbed
from hairbed._bed_drag import DRAG_MODELS
from hairbed._channel_drives import drive_inputs
from hairbed._core.loaded import _check as _check_loaded
from hairbed._core.validation import check_inputs, check_positive
from hairbed._jsonsafe import to_plain
from hairbed._variables import BED, BED_REQUIRED, LOADED, POROUS, SI, SOLUTION, cf_attrs, names
from hairbed.units import MODELS, require_dense

from ._drive import DRIVE_DEFAULTS

__all__ = [
    "BED_KEYS",
    "DEFAULTS",
    "DRIVES",
    "LOADED_FIELDS",
    "MODELS",
    "DRAG_MODELS",
    "POROUS_FIELDS",
    "PUMP_KEYS",
    "VIEWS",
    "FLAG_KEYS",
    "INPUT_KEYS",
    "PRESETS",
    "PILLAR_DEFAULTS",
    "InputError",
    "SOLUTION_FIELDS",
    "STABILITY_SEGMENTS",
    "Params",
    "Snapshot",
    "StateView",
    "ValveView",
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
#: The fields of a :class:`hairbed.LoadedState` shown and exported (a pump drive's states):
#: the inputs, the tip, the base curvature, then :data:`hairbed._variables.LOADED`'s.
LOADED_FIELDS: tuple[str, ...] = (
    "omega2", "eps", "theta0", "tip_height", "tip_deflection", "tip_angle", "base_curvature",
    "status", *(k for k in LOADED if k != "stable"),
)  # fmt: skip

#: The fields of a :class:`hairbed.PorousState` shown and exported (a porous bed's states,
#: theory.md §13): the inputs, the tip, the base curvature, the fluid at the tip and the wall,
#: the hair's drag, then the solve's.
POROUS_FIELDS: tuple[str, ...] = (
    "omega2", "eps", "theta0", "kappa", "gamma", "pi", "q", "tip_height", "tip_deflection",
    "tip_angle", "base_curvature", "tip_stress", "wall_stress", "tip_velocity", "drag_x",
    "drag_z", "max_angle", "status", "error_estimate", "residual", "nit", "num",
)  # fmt: skip

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
#: Inputs of a pump-driven channel in SI mode: key -> (label, unit): the pump's pressure
#: gradient G or flow rate per unit width Q' (:meth:`hairbed.HairBed.deform`), and the
#: channel's length l of the valve view (:func:`hairbed.valve.valve_curve`).
PUMP_KEYS: dict[str, tuple[str, str]] = {
    "pressure_gradient": (SI["pressure_gradient"].label, SI["pressure_gradient"].unit),
    "flow_rate": (SI["flow_rate"].label, SI["flow_rate"].unit),
    "channel_length": ("channel length l (valve view)", "m"),
}
#: What drives the channel (theory.md §11): the top wall alone (the paper's closed form), a
#: pump at a set pressure gradient, or a pump at a set flow rate (the wall may move too).
DRIVES = ("wall", "pressure", "flow")
#: The dimensionless load of each pump drive (:func:`hairbed.solve_loaded`'s keyword).
LOAD_KEYS = {"pressure": "pi", "flow": "q"}
#: The SI input of each pump drive.
PUMP_INPUT = {"pressure": "pressure_gradient", "flow": "flow_rate"}
#: The second picture beside the channel: the branch diagram or the bed as a valve.
VIEWS = ("branch", "valve")
#: Switches of the page (0 or 1).
FLAG_KEYS = ("si", "twirl")
#: Every input the page holds (and the URL carries), in the URL's order.
INPUT_KEYS: tuple[str, ...] = (
    "omega2", "eps", "theta0", "y", *FLAG_KEYS, "x", "drive", "pi", "q", "view", *BED_KEYS,
    *PUMP_KEYS,
)  # fmt: skip

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
    "drive": "wall",
    "pi": "1",
    "q": "0.05",
    "view": "branch",
    "pressure_gradient": "20000",
    "flow_rate": "1e-06",
    "channel_length": "0.01",
}
#: The pillar mode's inputs and their defaults (:mod:`._pillar`; appended to
#: :data:`INPUT_KEYS` and :data:`DEFAULTS`, and carried by the URL in pillar mode only: a bed's
#: link is the one it always was): an upright pillar in the viscous sublayer at Lambda = 1, the
#: slender limit gamma = 1/2 (no slenderness given), no tip load.
PILLAR_DEFAULTS: dict[str, str] = {
    "mode": "bed",
    "forcing": "1",
    "pillar_theta0": "0",
    "profile": "sublayer",
    "height_ratio": "",
    "slenderness": "",
    "tip_load": "0",
    "pillar_view": "shape",
}
INPUT_KEYS += tuple(PILLAR_DEFAULTS)
DEFAULTS.update(PILLAR_DEFAULTS)
#: The pillar's drive view (:mod:`._drive`): amplitude, frequency, inertia and drag model,
#: carried by the URL in the drive view only.
INPUT_KEYS += tuple(DRIVE_DEFAULTS)
DEFAULTS.update(DRIVE_DEFAULTS)
#: SI mode's bed model (:class:`hairbed.HairBed`'s ``model`` and, porous, its ``drag``):
#: "dense" (the paper's bed, the default) or "porous" (the flow through the bed, theory.md
#: §13). Carried by the URL only for a porous bed: a dense bed's link is the one it always was.
BED_MODEL_DEFAULTS: dict[str, str] = {"model": "dense", "drag": "crossover"}
INPUT_KEYS += tuple(BED_MODEL_DEFAULTS)
DEFAULTS.update(BED_MODEL_DEFAULTS)
#: Starting points, each a set of inputs (the others take :data:`DEFAULTS`): name -> inputs.
PRESETS: dict[str, dict[str, str]] = {
    "worked example": {"omega2": "2", "eps": "0.5", "theta0": "0"},
    # inside the window of three states of a hair leaning into the flow (theory.md §5)
    "bistable window": {"omega2": "1.2", "eps": "0.9", "theta0": "-1.5"},
    "twirling states": {"omega2": "200", "eps": "0.5", "theta0": "0", "twirl": "1"},
    # a wall-shear-stress sensor: 1 mm PDMS-like pillars in glycerol, Stokes flow (Re ~ 0.2)
    "sensor bed (SI)": {"si": "1", "velocity": "0.1", "base_angle": "0"},
    # a tilted bed in a pressure-driven channel, both walls at rest: the valve and its diode
    "pumped valve": {
        "omega2": "0", "eps": "0.5", "theta0": "0.5", "drive": "pressure", "pi": "5",
        "view": "valve",
    },
    # an isolated pillar tilted far upstream, inside its snap-through window (theory.md §12)
    "pillar snap-through": {"mode": "pillar", "forcing": "20", "pillar_theta0": "-1.45"},
}  # fmt: skip
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
    drive : str
        What drives the channel: "wall" (the paper's closed form), "pressure" or "flow" (a
        pump; :func:`hairbed.solve_loaded`, theory.md §11).
    load : float or None
        The pump's dimensionless load [-]: pi (pressure drive) or q (flow drive); None for the
        wall drive. In SI mode derived from the bed and :attr:`pump`.
    view : str
        Beside the channel: "branch" (the branch diagram) or "valve" (the bed as a valve).
    pump : float or None
        SI mode, pump drives: the set pressure gradient G [Pa/m] or flow rate Q' [m^2/s].
    channel_length : float or None
        SI mode: the channel's length l [m] of the valve view.
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
    drive: str = "wall"
    load: float | None = None
    view: str = "branch"
    pump: float | None = None
    channel_length: float | None = None

    @property
    def porous(self) -> bool:
        """SI mode with a porous bed (``HairBed(..., model="porous")``, theory.md §13)."""
        return bool(self.si and self.bed is not None and self.bed.model == "porous")

    @property
    def load_key(self) -> str | None:
        """ "pi" or "q" (the keyword of :func:`hairbed.solve_loaded`), None for the wall."""
        return LOAD_KEYS.get(self.drive)


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


class _Cache:
    """A bounded, thread-safe LRU of results by their exact inputs, shared by every session.

    What it holds is never changed after it is made (frozen states, tuples of warnings), so
    sessions can share it. Keys are the inputs' ``repr`` (0.0 and -0.0 apart, an input that
    is not a number by its text); a call that raises is not cached.
    """

    def __init__(self, size: int) -> None:
        self.size = size
        self._items: OrderedDict[tuple[str, ...], Any] = OrderedDict()
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0

    def get(self, make: Callable[..., Any], *args: Any) -> Any:
        """``make(*args)``, from the cache if these exact arguments were given before."""
        key = tuple(repr(a) for a in args)
        with self._lock:
            if key in self._items:
                self._items.move_to_end(key)
                self.hits += 1
                return self._items[key]
            self.misses += 1
        value = make(*args)
        with self._lock:
            self._items[key] = value
            self._items.move_to_end(key)
            while len(self._items) > self.size:
                self._items.popitem(last=False)
        return value

    def clear(self) -> None:
        with self._lock:
            self._items.clear()

    def __len__(self) -> int:
        return len(self._items)


#: Entries of each cache of a pump drive's states (per parameter tuple: a whole slider's
#: range, visited to and fro, fits; each entry holds one to three states of a few kB).
PUMP_CACHE_SIZE = 256


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
    if full["model"].strip() == "porous":  # a dense bed's arguments are the ones they were
        args.update(model="porous", drag=full["drag"].strip())
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
    drive, view = full["drive"].strip(), full["view"].strip()
    if drive not in DRIVES:
        problems.append(f"drive must be one of 'wall', 'pressure', 'flow', got {drive!r}")
        drive = "wall"
    if view not in VIEWS:
        problems.append(f"view must be one of 'branch', 'valve', got {view!r}")
        view = "branch"
    model, drag = full["model"].strip(), full["drag"].strip()
    if model not in MODELS:
        problems.append(f"model must be one of 'dense', 'porous', got {model!r}")
        full["model"] = "dense"
    if drag not in DRAG_MODELS:
        problems.append(f"drag must be one of {', '.join(map(repr, DRAG_MODELS))}, got {drag!r}")
        full["drag"] = "crossover"
    flags = {}
    for k in FLAG_KEYS:
        try:
            flags[k] = _flag(full, k)
        except ValueError as exc:
            problems.append(str(exc))
            flags[k] = False
    si, twirl = flags["si"], flags["twirl"]
    if model == "porous" and not si:
        problems.append(
            "model='porous' is a bed in SI units (its permeability follows from its hairs): "
            "switch SI mode on (si=1)"
        )
    if drive != "wall":
        return _validate_pumped(full, problems, y, x_kind, si, twirl, drive, view)
    if not si:
        values = {k: _number(full[k]) for k in ("omega2", "eps", "theta0")}
        m = None
        with _recording() as caught:
            try:
                check_inputs(**values)  # hairbed.solve's own checks, with its messages
            except ValueError as exc:
                m = str(exc)
        if m is not None:  # which of them: each alone, the others at valid values
            alone = [_message(check_inputs, **{**_GOOD, k: v}) for k, v in values.items()]
            problems += [a for a in alone if a] or [m]
        if problems:
            raise InputError(problems)
        w, e, th = (float(values[k]) for k in ("omega2", "eps", "theta0"))
        return Params(
            w, e, th, y, si, twirl, raw=full, warnings=tuple(caught), x=x_kind, drive=drive,
            view=view,
        )  # fmt: skip
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
        length = _number(full["channel_length"])
        m = _message(check_positive, length, "channel_length", "m")
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
        channel_length=float(length),
        drive=drive,
        view=view,
    )


def _validate_pumped(
    full: dict[str, str], problems: list[str], y: str, x_kind: str, si: bool, twirl: bool,
    drive: str, view: str,
) -> Params:  # fmt: skip
    """:func:`validate` of a pump drive: the library's checks of :func:`hairbed.solve_loaded`
    (dimensionless) or of :meth:`hairbed.HairBed.deform` with ``pressure_gradient`` or
    ``flow_rate`` (SI), each bad parameter by name."""
    key = LOAD_KEYS[drive]
    if not si:
        values = {k: _number(full[k]) for k in ("omega2", "eps", "theta0", key)}
        m = None
        solved: tuple[str, ...] = ()
        with _recording() as caught:
            try:  # the library's checks, with its messages (the state is kept for compute)
                _, solved = _loaded_one(key, *values.values())
            except ValueError as exc:
                m = str(exc)
        if m is not None:  # which of them: each alone, the others at valid values
            good = {**_GOOD, "pi": None, "q": None, key: 1.0}
            alone = [_message(_check_loaded, **{**good, k: v}) for k, v in values.items()]
            problems += [a for a in alone if a] or [m]
        if problems:
            raise InputError(problems)
        w, e, th, ld = (float(values[k]) for k in ("omega2", "eps", "theta0", key))
        return Params(
            w, e, th, y, si, twirl, raw=full, warnings=tuple(_merge(caught, solved)), x=x_kind,
            drive=drive, load=ld, view=view,
        )  # fmt: skip
    bed_args = _bed_args(full)
    name = PUMP_INPUT[drive]
    velocity, pump = _number(full["velocity"]), _number(full[name])
    length = _number(full["channel_length"])
    with _recording() as caught:
        try:
            bed = hairbed.HairBed(**bed_args)
        except ValueError:
            bed = None
            problems += _bed_problems(bed_args)
        some = bed or hairbed.HairBed(**_REFERENCE_BED)
        # the wall speed and the pump's value, each by the checks of HairBed.deform (the
        # other at rest), against this bed or the reference one if this one is bad
        for v_try, value in ((velocity, 0.0), (0.0, pump)):
            m = _message(_drive, some, drive, v_try, value)
            if m:
                problems.append(m)
        m = _message(check_positive, length, "channel_length", "m")
        if m:
            problems.append(m)
        if problems:
            raise InputError(problems)
        assert bed is not None
        omega2, load = _drive(bed, drive, velocity, pump)
    full.update(omega2=repr(omega2), eps=repr(bed.eps), theta0=repr(bed.base_angle + 0.0))
    full[key] = repr(load)
    return Params(
        omega2, bed.eps, bed.base_angle + 0.0, y, si, twirl, bed, float(velocity),
        raw=full, warnings=tuple(caught), x=x_kind, drive=drive, load=load, view=view,
        pump=float(pump), channel_length=float(length),
    )  # fmt: skip


def load_per_unit(bed: Any, drive: str) -> tuple[float, float]:
    """(omega^2 per m/s of wall speed, pi per Pa/m or q per m^2/s) of a bed's pump drive."""
    return _drive(bed, drive, 1.0, 1.0)


def _drive(bed: Any, drive: str, velocity: Any, value: Any) -> tuple[float, float]:
    """(omega^2 signed, pi or q) of a bed at a wall speed [m/s] and a pump's set pressure
    gradient [Pa/m] or flow rate [m^2/s]: the conversion and the checks (ValueError naming
    the input) of :meth:`hairbed.HairBed.deform`."""
    given = {"pressure_gradient": None, "flow_rate": None, PUMP_INPUT[drive]: value}
    _, _, _, omega2, load = drive_inputs(bed, velocity, **given)
    return float(omega2), float(load)


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
    >>> query_from_inputs(validate({"omega2": "0", "drive": "pressure", "pi": "5"}))
    '?omega2=0&eps=0.5&theta0=0&y=x1&si=0&twirl=0&drive=pressure&pi=5'

    The drive, its load and the view are named only where they are not the defaults (the
    wall drive, the branch diagram): a link of the wall drive is the one it always was.
    """
    keys = ["omega2", "eps", "theta0", "y", *FLAG_KEYS]
    if params.porous:  # named only for a porous bed: a dense bed's link is the one it was
        keys += ["model", "drag"]
    if params.drive != "wall":
        keys += ["drive", LOAD_KEYS[params.drive]]
    if params.view != "branch":
        keys += ["view"]
    if params.si:  # omega2, eps and theta0 then the bed's (Params.raw holds them)
        keys += ["x", *BED_KEYS]  # empty ones too: an empty spacing means "the packing fraction"
        if params.drive != "wall":
            keys += [PUMP_INPUT[params.drive]]
        if params.view == "valve":
            keys += ["channel_length"]
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
class ValveView:
    """The bed as a valve: both walls at rest, a pump's pressure drop across a channel.

    In SI mode from :func:`hairbed.valve.diodicity` (the bed's channel of length l); in the
    dimensionless problem from :func:`hairbed.solve_loaded` along the pressure drive at
    omega^2 = 0, the flow in units of the flow drive's q (theory.md §11): with u = 1 - eps h1
    the gap over the channel height, q = pi u^3/(2 eps), the empty channel's pi/(2 eps), so
    that R/R0 = 1/u^3 and Di = (u(+pi)/u(-pi))^3.

    Attributes
    ----------
    x_label, flow_label : str
        The abscissa (abs(dp) [Pa], or abs(pi) [-]) and the flow's label, with units.
    drop : ndarray
        The abscissae: abs(dp) [Pa] or abs(pi) [-], increasing.
    forward, backward : ndarray
        abs(Q') [m^2/s] (or abs(q) [-]) at +drop and at -drop.
    empty : ndarray
        The empty channel's flow at the same drop.
    forward_ratio, backward_ratio : ndarray
        R/R0 [-], the hydraulic resistance relative to the empty channel, both ways.
    diodicity : ndarray
        Di = Q'(+drop)/abs(Q'(-drop)) [-].
    now : dict of str to float
        The same at the current drop (``drop``, ``forward``, ``backward``, ``forward_ratio``,
        ``backward_ratio``, ``diodicity``): the pump's (pressure drive), the state's (flow
        drive, its Pi), or a reference drop (pi = 1) for the wall drive.
    success : bool
        Every point converged (status 0).
    message : str
        What happened ("ok", the first failing point's message, or why there is no valve).
    """

    x_label: str
    flow_label: str
    drop: np.ndarray
    forward: np.ndarray
    backward: np.ndarray
    empty: np.ndarray
    forward_ratio: np.ndarray
    backward_ratio: np.ndarray
    diodicity: np.ndarray
    now: dict[str, float]
    success: bool
    message: str


#: Points of the valve curve (each way): a coarse grid, cached per bed and range.
VALVE_POINTS = 40


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
    valve : ValveView or None
        The bed as a valve (``params.view == "valve"``).
    message : str
        Why no state is shown ("" when there are states): the library's message of a solve
        whose status is negative (:data:`hairbed._core.validation.STATUS_MESSAGES`).
    unsupported : tuple of str
        What this view asked that its bed does not support (a porous bed: the library's
        :class:`NotImplementedError` message of each), shown in the page's alert instead of
        a traceback or the dense bed's numbers.
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
    valve: ValveView | None = None
    message: str = ""
    unsupported: tuple[str, ...] = ()


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


def _nice_top(drop: float) -> float:
    """The top of the valve curve's range: a power of ten at or above twice ``drop`` (a
    range that stays while the drop moves, so that the curve stays cached)."""
    return float(10.0 ** math.ceil(math.log10(2.0 * drop)))


def _grid(top: float) -> np.ndarray:
    return top * np.linspace(1.0 / VALVE_POINTS, 1.0, VALVE_POINTS)


@functools.lru_cache(maxsize=32)
def _valve_plain(eps: float, theta0: float, drops: tuple[float, ...]) -> dict[str, Any]:
    """The dimensionless valve at pi = +-drops (see :class:`ValveView`): one vectorised
    :func:`hairbed.solve_loaded` of the pressure drive, walls at rest."""
    d = np.asarray(drops, dtype=np.float64)
    both = np.concatenate([d, -d])
    st = hairbed.solve_loaded(np.zeros(both.shape), eps, theta0, pi=both)
    u = 1.0 - eps * np.asarray(st.tip_height, dtype=np.float64)
    flow = np.abs(both) * u**3 / (2.0 * eps)
    n = d.size
    status = np.asarray(st.status).reshape(-1)
    failed = np.flatnonzero(status < 0)
    return {
        "forward": flow[:n],
        "backward": flow[n:],
        "empty": d / (2.0 * eps),
        "forward_ratio": 1.0 / u[:n] ** 3,
        "backward_ratio": 1.0 / u[n:] ** 3,
        "diodicity": (u[:n] / u[n:]) ** 3,
        "success": bool(np.all(status == 0)),
        "message": "ok"
        if failed.size == 0
        else str(np.asarray(st.message).reshape(-1)[failed[0]]),
    }


@functools.lru_cache(maxsize=32)
def _valve_si(bed: Any, length: float, drops: tuple[float, ...]) -> dict[str, Any]:
    """The valve of a bed at pressure drops +-drops [Pa] over a channel of length l [m]:
    :func:`hairbed.valve.diodicity`."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the bed's warnings are the view's already
        di = hairbed.valve.diodicity(_without_density(bed), np.asarray(drops), length)
    fw, bw = di.forward, di.backward
    message = fw.message if not fw.success else bw.message
    return {
        "forward": np.abs(np.asarray(fw.flow_rate, dtype=np.float64)),
        "backward": np.abs(np.asarray(bw.flow_rate, dtype=np.float64)),
        "empty": np.abs(np.asarray(fw.empty_flow_rate, dtype=np.float64)),
        "forward_ratio": np.asarray(fw.resistance_ratio, dtype=np.float64),
        "backward_ratio": np.asarray(bw.resistance_ratio, dtype=np.float64),
        "diodicity": np.asarray(di.diodicity, dtype=np.float64),
        "success": bool(di.success),
        "message": message,
    }


_VALVE_FIELDS = (
    "forward", "backward", "forward_ratio", "backward_ratio", "diodicity",
)  # fmt: skip


def _valve(p: Params, states: list[StateView]) -> ValveView:
    """The valve view of a snapshot: the curve over a range around the current drop."""
    empty = np.empty(0)
    if not p.si and p.eps == 0.0:
        return ValveView(
            "pressure gradient abs(pi) [-]", "flow rate abs(q) [-]", empty, empty, empty,
            empty, empty, empty, empty, {}, False,
            "no valve at eps = 0: the channel has no top wall (give eps in (0, 1))",
        )  # fmt: skip
    # the current drop: the pump's, the state's pressure gradient, or a reference (pi = 1)
    if p.drive == "pressure":
        now = abs(float(p.load or 0.0))
    elif p.drive == "flow" and states and p.porous:
        now = abs(float(states[0].solution.pi))  # a PorousState's solved pi
    elif p.drive == "flow" and states:
        now = abs(float(states[0].solution.distributed_load))
    else:
        now = 0.0
    if not p.si:
        drop = now if now > 0.0 and math.isfinite(now) else 1.0
        top = _nice_top(drop)
        curve = _valve_plain(p.eps, p.theta0, tuple(_grid(top)))
        at = _valve_plain(p.eps, p.theta0, (drop,))
        x_label, flow_label = "pressure gradient abs(pi) [-]", "flow rate abs(q) [-]"
    else:
        length = float(p.channel_length or float(DEFAULTS["channel_length"]))
        _, per_gradient = _drive(p.bed, "pressure", 0.0, 1.0)  # pi per Pa/m
        drop = now / per_gradient * length  # [Pa]
        if not (drop > 0.0 and math.isfinite(drop)):
            drop = length / per_gradient
        top = _nice_top(drop)
        curve = _valve_si(p.bed, length, tuple(_grid(top)))
        at = _valve_si(p.bed, length, (drop,))
        x_label = "pressure drop abs(dp) [Pa]"
        flow_label = f"flow rate per unit width abs(Q') [{SI['flow_rate'].unit}]"
    values = {k: float(np.asarray(at[k]).reshape(-1)[0]) for k in _VALVE_FIELDS}
    message = curve["message"] if not curve["success"] else at["message"]
    return ValveView(
        x_label, flow_label, _grid(top), curve["forward"], curve["backward"], curve["empty"],
        curve["forward_ratio"], curve["backward_ratio"], curve["diodicity"],
        {"drop": drop, **values}, bool(curve["success"] and at["success"]), message,
    )  # fmt: skip


#: Loads of the branch diagram of a pump drive: abs(pi) or abs(q) in [1e-3, 1e3].
_LOAD_GRID = np.geomspace(1e-3, 1e3, 121)


@functools.lru_cache(maxsize=64)
def _loaded_branch(
    drive: str, omega2: float, eps: float, theta0: float, sign: float
) -> tuple[np.ndarray, Any]:
    """The low branch of a pump drive along its load (signed like ``sign``) at fixed
    (omega^2, eps, theta0): one vectorised :func:`hairbed.solve_loaded` on :data:`_LOAD_GRID`
    (the states it does not reach are NaN, not drawn)."""
    loads = sign * _LOAD_GRID
    kw: dict[str, Any] = {LOAD_KEYS[drive]: loads}
    st = hairbed.solve_loaded(np.full(loads.shape, omega2), eps, theta0, **kw)
    return _LOAD_GRID, st


def _loaded_y(p: Params, sol: Any) -> np.ndarray:
    """The ordinate of loaded states: x1 [L] (in SI x1 L [m]) or xi = sin(theta1)."""
    if p.y == "xi":
        return np.sin(np.asarray(sol.tip_angle, dtype=np.float64)).reshape(-1)
    x1 = np.asarray(sol.tip_deflection, dtype=np.float64).reshape(-1)
    return x1 * (p.bed.length if p.si and p.bed is not None else 1.0)


def _loaded_diagram(p: Params, states: list[StateView]) -> BranchDiagram:
    """The branch diagram of a pump drive: x1 (or xi) against abs(load), or in SI against the
    pump's abs(G) [Pa/m] or abs(Q') [m^2/s]."""
    load = float(p.load or 0.0)
    sign = -1.0 if load < 0.0 else 1.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        grid, st = _loaded_branch(p.drive, p.omega2, p.eps, p.theta0, sign)
    key = LOAD_KEYS[p.drive]
    scale = 1.0
    if p.si and p.bed is not None:
        _, per_unit = _drive(p.bed, p.drive, 0.0, 1.0)
        scale = 1.0 / per_unit
    x = grid * scale
    y = _loaded_y(p, st)
    keep = np.isfinite(y) & (np.asarray(st.status).reshape(-1) >= 0)
    sx = [abs(load) * scale] * len(states)
    sy = [float(_loaded_y(p, s.solution)[0]) for s in states]
    if p.si:
        name = PUMP_INPUT[p.drive]
        x_label = f"{SI[name].label} abs [{SI[name].unit}]"
        y_label = f"tip deflection x1 L [{SI['tip_deflection'].unit}]" if p.y == "x1" else "xi [-]"
    else:
        x_label = f"{LOADED[key].label} abs({key}) [-] (low branch, omega^2 = {p.omega2:.6g})"
        y_label = "tip deflection x1/L [-]" if p.y == "x1" else "xi = sin(theta1) [-]"
    now = abs(load) * scale if load != 0.0 else None
    e = np.empty(0)
    return BranchDiagram(
        x_label, y_label, (float(x[0]), float(x[-1])), x[keep], y[keep], e, e, [], sx, sy,
        [], [], now,
    )  # fmt: skip


def _loaded_labels(n: int) -> tuple[str, ...]:
    return _roots(n) if n <= 3 else ("low", "mid", "high")


def _solve_loaded_recorded(
    key: str, omega2: Any, eps: Any, theta0: Any, load: Any
) -> tuple[Any, tuple[str, ...]]:
    """:func:`hairbed.solve_loaded` of a pump drive (``key``: "pi" or "q") and the warnings
    it issued."""
    with _recording() as caught:
        st = hairbed.solve_loaded(omega2, eps, theta0, **{key: load})
    return st, tuple(caught)


_LOADED_ONE = _Cache(PUMP_CACHE_SIZE)


def _loaded_one(
    key: str, omega2: Any, eps: Any, theta0: Any, load: Any
) -> tuple[Any, tuple[str, ...]]:
    """:func:`_solve_loaded_recorded`, cached per exact inputs (:func:`validate` checks the
    inputs with it and :func:`compute` falls back on the same state)."""
    return _LOADED_ONE.get(_solve_loaded_recorded, key, omega2, eps, theta0, load)


def _pump_states_uncached(
    drive: str, omega2: float, eps: float, theta0: float, load: float
) -> tuple[tuple[Any, ...], str, tuple[str, ...]]:
    """(states, message, warnings) of a pump drive: every coexisting state by
    :func:`hairbed.solve_loaded_all` (at most the lowest, the middle and the highest), else
    the state of :func:`hairbed.solve_loaded` if its status is not negative, else none and
    the library's message."""
    key = LOAD_KEYS[drive]
    message = ""
    with _recording() as caught:
        every = hairbed.solve_loaded_all(omega2, eps, theta0, **{key: load})
        found = [s for s in every if int(s.status) >= 0]  # none found: one failed state
        if len(found) > 3:  # more than a window's three: the lowest, the middle, the highest
            found = [found[0], found[len(found) // 2], found[-1]]
        one_warnings: tuple[str, ...] = ()
        if not found:
            one, one_warnings = _loaded_one(key, omega2, eps, theta0, load)
            found = [one] if int(one.status) >= 0 else []
            if not found:
                message = f"no state: {one.message} (status {int(one.status)})"
    return tuple(found), message, tuple(_merge(caught, one_warnings))


_PUMP_STATES = _Cache(PUMP_CACHE_SIZE)


def _deformed_uncached(
    bed: Any, velocity: float, drive: str, pump: Any, root: str
) -> tuple[Any, tuple[str, ...]]:
    """:meth:`hairbed.HairBed.deform` of a pump drive's state ``root``, and its warnings."""
    with _recording() as caught:
        si = bed.deform(velocity, **{PUMP_INPUT[drive]: pump}, root=root)
    return si, tuple(caught)


_DEFORMED = _Cache(PUMP_CACHE_SIZE)


def _compute_pumped(p: Params) -> Snapshot:
    """:func:`compute` of a pump drive: every coexisting state by
    :func:`hairbed.solve_loaded_all` (with its stability under a slow change of the tip
    height), else the state of :func:`hairbed.solve_loaded`; in SI mode each also by
    :meth:`hairbed.HairBed.deform`. A solve with a negative status shows no state, with the
    library's message.

    The states (and the SI states) are cached per exact inputs (:data:`PUMP_CACHE_SIZE`
    each, shared by every session, with the warnings their solve issued): a slider dragged
    back over values it passed, or another session at the same inputs, costs no new solve."""
    t0 = time.perf_counter()
    found, message, solve_warnings = _PUMP_STATES.get(
        _pump_states_uncached, p.drive, p.omega2, p.eps, p.theta0, p.load
    )
    with _recording() as caught:
        labels = _loaded_labels(len(found))
        t1 = time.perf_counter()
        states = []
        deform_warnings: list[str] = []
        for label, sol in zip(labels, found):
            si = None
            if p.si and p.bed is not None:
                si, w = _DEFORMED.get(
                    _deformed_uncached, p.bed, p.velocity or 0.0, p.drive, p.pump, label
                )
                deform_warnings += w
            stable = None if sol.stable is None else bool(sol.stable)
            states.append(StateView(label, sol, stable, float("nan"), si))
        t2 = time.perf_counter()
        diagram = _loaded_diagram(p, states)
        valve = _valve(p, states) if p.view == "valve" else None
    e = np.empty(0)
    t3 = time.perf_counter()
    return Snapshot(
        p, states, [], diagram.curve_x, diagram.curve_y, [], e, e, diagram,
        _merge(p.warnings, solve_warnings, deform_warnings, caught),
        {"solve": 1e3 * (t1 - t0), "stability": 1e3 * (t2 - t1), "total": 1e3 * (t3 - t0)},
        valve, message,
    )  # fmt: skip


# -- a porous bed (theory.md §13) ------------------------------------------------------------


def _porous_all_uncached(
    bed: Any, drive: str, omega2: float, load: float
) -> tuple[tuple[Any, ...], tuple[str, ...]]:
    """Every coexisting state of a porous bed (:func:`hairbed.solve_porous_all`, each with
    its stability under a slow change of the gap), and the warnings: ``drive`` "wall" (pi =
    0, omega2 signed like the wall's speed), "pressure" (pi = load) or "flow" (q = load)."""
    key = "pi" if drive in ("wall", "pressure") else "q"
    with _recording() as caught:
        every = hairbed.solve_porous_all(
            omega2, bed.eps, bed.base_angle, kappa=bed.kappa, gamma=bed.drag_ratio,
            **{key: 0.0 if drive == "wall" else load},
        )  # fmt: skip
    return tuple(every), tuple(caught)


_POROUS_ALL = _Cache(PUMP_CACHE_SIZE)
_POROUS_DEFORMED = _Cache(PUMP_CACHE_SIZE)


def _porous_deformed_uncached(
    bed: Any, velocity: float, drive: str, pump: Any, root: str
) -> tuple[Any, tuple[str, ...]]:
    """:meth:`hairbed.HairBed.deform` of a porous bed's state ``root`` (any drive), and its
    warnings."""
    kw = {} if drive == "wall" else {PUMP_INPUT[drive]: pump}
    with _recording() as caught:
        si = bed.deform(velocity, **kw, root=root)
    return si, tuple(caught)


#: Points of a porous bed's branch diagram (its low branch, one vectorised deform).
POROUS_BRANCH_POINTS = 61


@functools.lru_cache(maxsize=32)
def _porous_branch(
    bed: Any, drive: str, velocity: float, sign: float
) -> tuple[np.ndarray, Any, tuple[str, ...]]:
    """The low branch of a porous bed: (abscissae, HairState of the whole grid, warnings):
    against the wall speed (omega^2 in the window, the sign of ``velocity``) or against the
    pump's abs(G) or abs(Q') (its load in the window, signed like ``sign``, the wall at
    ``velocity``)."""
    lo, hi = _FORCING_WINDOW
    with _recording() as caught, np.errstate(all="ignore"):
        if drive == "wall":
            grid = np.geomspace(lo, hi, POROUS_BRANCH_POINTS) * bed.velocity_scale
            st = _without_density(bed).deform(math.copysign(1.0, velocity) * grid)
        else:
            _, per_unit = _drive(bed, drive, 0.0, 1.0)
            grid = np.geomspace(lo, hi, POROUS_BRANCH_POINTS) / per_unit
            st = _without_density(bed).deform(velocity, **{PUMP_INPUT[drive]: sign * grid})
    return grid, st, tuple(caught)


def _porous_y(p: Params, si: Any) -> np.ndarray:
    """The ordinate of porous states: x1 L [m] or xi = sin(theta1), in the bed's frame."""
    value = si.tip_deflection if p.y == "x1" else np.sin(np.asarray(si.tip_angle))
    return np.asarray(value, dtype=np.float64).reshape(-1)


def _porous_diagram(p: Params, states: list[StateView]) -> tuple[BranchDiagram, list[str]]:
    """The branch diagram of a porous bed: its low branch (:meth:`hairbed.HairBed.deform`)
    against the wall speed or stress, or against the pump's abs(G) or abs(Q')."""
    bed = p.bed
    velocity = float(p.velocity or 0.0)
    sign = -1.0 if (p.pump or 0.0) < 0.0 else 1.0
    # the wall drive's branch depends on the wall's direction only: a new speed keeps it
    at = velocity if p.drive != "wall" else -1.0 if velocity < 0.0 else 1.0
    grid, st, caught = _porous_branch(bed, p.drive, at, sign)
    y = _porous_y(p, st)
    status = np.asarray(st.solution.status).reshape(-1)
    y_label = f"tip deflection x1 L [{SI['tip_deflection'].unit}]" if p.y == "x1" else "xi [-]"
    if p.drive == "wall":
        x_label = _labels(p)[0]
        if p.x == "stress":
            x = np.abs(np.asarray(st.wall_shear_stress, dtype=np.float64)).reshape(-1)
            sx = [abs(float(s.si.wall_shear_stress)) for s in states]
        else:
            x = grid
            sx = [abs(velocity)] * len(states)
        now: float | None = sx[0] if states and p.x == "speed" else None
    else:
        name = PUMP_INPUT[p.drive]
        x_label = f"{SI[name].label} abs [{SI[name].unit}]"
        x = grid
        sx = [abs(float(p.pump or 0.0))] * len(states)
        now = abs(float(p.pump)) if p.pump else None
    keep = np.isfinite(x) & np.isfinite(y) & (x > 0.0) & (status >= 0)
    shown = x[keep]
    x_range = (float(shown.min()), float(shown.max())) if shown.size else _FORCING_WINDOW
    sy = [float(_porous_y(p, s.si)[0]) for s in states]
    e = np.empty(0)
    diagram = BranchDiagram(
        f"{x_label} (porous bed, low branch)", y_label, x_range, x[keep], y[keep], e, e, [],
        sx, sy, [], [], now,
    )  # fmt: skip
    return diagram, list(caught)


def _unsupported(bed: Any, what: str) -> str | None:
    """The library's NotImplementedError message where ``what`` is asked of this bed."""
    try:
        require_dense(bed, what)
    except NotImplementedError as exc:
        return str(exc)
    return None


def _compute_porous(p: Params) -> Snapshot:
    """:func:`compute` of a porous bed (SI mode, ``HairBed(..., model="porous")``, theory.md
    §13), any drive: every coexisting state by :func:`hairbed.solve_porous_all` (with its
    stability under a slow change of the gap), each state as :meth:`hairbed.HairBed.deform`
    gives it (the tip, the wall shear stress, the hair's shape, the pump's G and Q'), the low
    branch in the branch diagram, the valve by :func:`hairbed.valve.diodicity`.

    What rests on the dense bed's closed form (the twirling states of :func:`hairbed.solve_all`,
    the bistability map of :func:`hairbed.branches.cusp`) is not computed for it:
    :attr:`Snapshot.unsupported` holds the library's message for each (the twirling states
    only where asked for)."""
    bed = p.bed
    t0 = time.perf_counter()
    velocity = float(p.velocity or 0.0)
    if p.drive == "wall":
        omega2, load = math.copysign(p.omega2, velocity), 0.0
    else:
        omega2, load = p.omega2, float(p.load or 0.0)
    every, all_warnings = _POROUS_ALL.get(_porous_all_uncached, bed, p.drive, omega2, load)
    found = [s for s in every if int(s.status) >= 0]
    if len(found) > 3:  # more than a window's three: the lowest, the middle, the highest
        found = [found[0], found[len(found) // 2], found[-1]]
    message = ""
    states: list[StateView] = []
    deform_warnings: list[str] = []
    t1 = time.perf_counter()
    if not found:
        one, w = _POROUS_DEFORMED.get(
            _porous_deformed_uncached, bed, velocity, p.drive, p.pump, "low"
        )
        deform_warnings += w
        if int(one.solution.status) >= 0:
            states.append(StateView("low", one.solution, None, float("nan"), one))
        else:
            message = f"no state: {one.solution.message} (status {int(one.solution.status)})"
    for label, sol in zip(_loaded_labels(len(found)), found):
        si, w = _POROUS_DEFORMED.get(
            _porous_deformed_uncached, bed, velocity, p.drive, p.pump, label
        )
        deform_warnings += w
        stable = None if sol.stable is None else bool(sol.stable)
        states.append(StateView(label, si.solution, stable, float("nan"), si))
    t2 = time.perf_counter()
    unsupported = []
    if p.twirl:
        unsupported.append(_unsupported(bed, "the twirling states (hairbed.solve_all)"))
    unsupported.append(
        _unsupported(bed, "the bistability map (hairbed.branches.cusp: the dense bed's window, "
                     "drawn for reference)")
    )  # fmt: skip
    with _recording() as caught:
        diagram, branch_warnings = _porous_diagram(p, states)
        valve = None
        if p.view == "valve":
            try:
                valve = _valve(p, states)
            except NotImplementedError as exc:
                unsupported.append(str(exc))
    e = np.empty(0)
    t3 = time.perf_counter()
    return Snapshot(
        p, states, [], diagram.curve_x, diagram.curve_y, [], e, e, diagram,
        _merge(p.warnings, all_warnings, deform_warnings, branch_warnings, caught),
        {"solve": 1e3 * (t1 - t0), "stability": 1e3 * (t2 - t1), "total": 1e3 * (t3 - t0)},
        valve, message, tuple(m for m in unsupported if m),
    )  # fmt: skip


def clear_caches() -> None:
    """Empty every cache of this module (the pump drives' states, the branch curves, folds,
    valve curves): what no session needs once none is open."""
    for cache in (_LOADED_ONE, _PUMP_STATES, _DEFORMED, _POROUS_ALL, _POROUS_DEFORMED):
        cache.clear()
    for func in (_branch_curve, _folds, _without_density, _si_branch, _valve_plain, _valve_si,
                 _loaded_branch, _porous_branch):  # fmt: skip
        func.cache_clear()


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
    if p.porous:
        return _compute_porous(p)
    if p.drive != "wall":
        return _compute_pumped(p)
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
    with _recording() as valve_warnings:
        valve = _valve(p, states) if p.view == "valve" else None
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
        _merge(p.warnings, caught, curve_warnings, twirl_warnings, fold_warnings, valve_warnings),
        {
            "solve": 1e3 * (t1 - t0),
            "stability": 1e3 * (t2 - t1),
            "total": 1e3 * (t3 - t0),
        },
        valve,
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
    "drive": {"units": "", "long_name": "what drives the channel: pressure or flow (a pump)"},
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
    if column in LOADED and column not in SOLUTION:
        return cf_attrs(LOADED[column])
    if column in POROUS and column not in SOLUTION:
        return cf_attrs(POROUS[column])
    return cf_attrs(SOLUTION[column])


def _header(column: str) -> str:
    """A CSV heading "name [units]" (hairbed's CSV style; no brackets without units)."""
    units = _attrs(column)["units"] if column not in _SHAPE_COLUMNS else ""
    units = units or _SHAPE_COLUMNS.get(column, {}).get("units", "")
    return f"{column} [{units}]" if units else column


def _is_loaded(sol: Any) -> bool:
    """A pump drive's state (:class:`hairbed.LoadedState`), not a closed-form Solution."""
    return not hasattr(sol, "as_dict")


def _is_porous(sol: Any) -> bool:
    """A porous bed's state (:class:`hairbed.PorousState`)."""
    return hasattr(sol, "kappa") and hasattr(sol, "tip_stress")


def porous_bed_info(bed: Any) -> dict[str, Any]:
    """A porous bed's model as the page shows it: model, drag, kappa = k/L^2 [-] and its
    Brinkman length sqrt(kappa) L [m] (theory.md §13), and gamma = zeta_par/zeta_perp [-]."""
    return {
        "model": bed.model,
        "drag": bed.drag,
        "kappa": bed.kappa,
        "brinkman_length": math.sqrt(bed.kappa) * bed.length,
        "drag_ratio": bed.drag_ratio,
    }


_POROUS_BED_VARIABLES: dict[str, dict[str, str]] = {
    "model": {"units": "1", "long_name": "the bed's model: 'dense' (the paper's) or 'porous'"},
    "drag": {"units": "1", "long_name": "the porous bed's drag model"},
    "kappa": {"units": "1", "long_name": "the porous bed's permeability over L^2, k/L^2"},
    "brinkman_length": {
        "units": "m",
        "long_name": "the porous bed's Brinkman length sqrt(kappa) L",
    },
    "drag_ratio": {"units": "1", "long_name": "drag ratio gamma = zeta_par/zeta_perp"},
}


def _state_record(s: StateView) -> dict[str, Any]:
    rec: dict[str, Any] = {"state": s.label, "stable": s.stable, "growth_rate": s.growth_rate}
    if _is_porous(s.solution):
        rec["drive"] = s.solution.drive
        rec.update({k: getattr(s.solution, k) for k in POROUS_FIELDS})
    elif _is_loaded(s.solution):
        rec["drive"] = s.solution.drive
        rec.update({k: getattr(s.solution, k) for k in LOADED_FIELDS})
    else:
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
    if _is_loaded(sol):
        _, x, z, theta = sol.shape(sigma)
    else:
        x, z, theta = sol.x(sigma), sol.z(sigma), sol.theta(sigma)
    out: dict[str, Any] = {
        "sigma": sigma,
        "x": np.asarray(x, dtype=np.float64),
        "z": np.asarray(z, dtype=np.float64),
        "theta": np.asarray(theta, dtype=np.float64),
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
        "solved": {
            "omega2": p.omega2,
            "eps": p.eps,
            "theta0": p.theta0,
            "drive": p.drive,
            **({p.load_key: p.load} if p.load_key else {}),
        },
        "message": snap.message,
        "stability": f"hairbed.stability.linear_stability(N={STABILITY_SEGMENTS})",
        "states": states,
        "twirling": twirling,
        "folds": {"omega2": snap.folds_omega2, Y_CHOICES[p.y]: snap.folds_y},
        **({"valve": dataclasses.asdict(snap.valve)} if snap.valve is not None else {}),
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
        if p.porous:
            doc["bed"].update(porous_bed_info(bed))
            doc["bed_variables"].update(_POROUS_BED_VARIABLES)
            doc["stability"] = "hairbed.solve_porous_all: stable under a slow change of the gap"
            doc["unsupported"] = list(snap.unsupported)
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
