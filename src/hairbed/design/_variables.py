"""Design variables: SI parameters of a :class:`~hairbed.HairBed` or a :class:`~hairbed.Pillar`
with bounds, mapped to the unit box the optimiser works in.

A variable p in [low, high] is the coordinate u in [0, 1] of

    p = low + u (high - low)                    (linear scale)
    p = exp(ln low + u (ln high - ln low))      (log scale, low > 0)

so dp/du = high - low, or p (ln high - ln low): the chain rule from d(quantity)/dp to the
optimiser's gradient d(quantity)/du.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.validation import show
from ..pillars import Pillar
from ..units import HairBed

__all__ = ["BED_VARIABLES", "PILLAR_VARIABLES", "Space", "Variable"]

FloatArray = NDArray[np.float64]

#: The SI parameters of a HairBed a design may vary [their units].
BED_VARIABLES: dict[str, str] = {
    "length": "m",
    "radius": "m",
    "youngs_modulus": "Pa",
    "channel_height": "m",
    "viscosity": "Pa s",
    "spacing": "m",
    "packing_fraction": "-",
    "base_angle": "rad",
    "density": "kg/m^3",
}
#: The SI parameters of a Pillar a design may vary [their units].
PILLAR_VARIABLES: dict[str, str] = {
    "length": "m",
    "radius": "m",
    "youngs_modulus": "Pa",
    "viscosity": "Pa s",
    "base_angle": "rad",
    "channel_height": "m",
    "density": "kg/m^3",
    "drag_scale": "-",
}
#: How many corners of the box are built to check it (beyond, 2^12 models would be).
_MAX_CORNER_CHECK = 12


def _finite(value: Any, name: str, positive: bool = False) -> float:
    """A finite real number (> 0 with ``positive``), or a ValueError/TypeError naming it."""
    if isinstance(value, (bool, np.bool_, np.timedelta64)) or not isinstance(
        value, (int, float, np.integer, np.floating)
    ):
        raise TypeError(f"{name} must be a real number, got {show(value)}")
    x = float(value) if not isinstance(value, int) or abs(value) <= 2**1023 else math.inf
    if not math.isfinite(x) or (positive and not x > 0.0):
        raise ValueError(f"{name} must be a finite number{' > 0' if positive else ''}, got "
                         f"{show(value)}")  # fmt: skip
    return x


@dataclass(frozen=True)
class Variable:
    """One design variable: an SI parameter of the model and its bounds.

    Parameters
    ----------
    name : str
        A parameter of the base model's constructor (:data:`BED_VARIABLES` for a HairBed,
        :data:`PILLAR_VARIABLES` for a Pillar), in its SI unit.
    low, high : float
        Bounds, finite, low < high [the parameter's unit].
    log : bool
        Search in ln(p) (needs low > 0): for sizes and moduli spanning decades.

    Raises
    ------
    ValueError
        Naming the variable, for non-finite, empty or inverted bounds, or a log scale with
        low <= 0.
    """

    name: str
    low: float
    high: float
    log: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"Variable name must be a non-empty string, got {show(self.name)}")
        for side in ("low", "high"):
            value = getattr(self, side)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
                raise ValueError(
                    f"variable {self.name!r}: {side} must be a real number, got {show(value)}"
                )
            if isinstance(value, int) and abs(value) > 2**1023:  # beyond double precision
                value = math.inf
            if not math.isfinite(float(value)):
                raise ValueError(
                    f"variable {self.name!r}: {side} must be finite, got {show(value)}"
                )
            object.__setattr__(self, side, float(value))
        if not self.low < self.high:
            what = "empty" if self.low == self.high else "inverted"
            raise ValueError(
                f"variable {self.name!r}: the bounds are {what} (low {self.low!r} must be "
                f"less than high {self.high!r})"
            )
        if not isinstance(self.log, (bool, np.bool_)):
            raise ValueError(
                f"variable {self.name!r}: log must be True or False, got {show(self.log)}"
            )
        if self.log and not self.low > 0.0:
            raise ValueError(
                f"variable {self.name!r}: a log scale needs low > 0, got low {self.low!r}"
            )

    def value(self, u: float) -> float:
        """The parameter at the unit coordinate ``u`` in [0, 1], within the bounds (exp of
        ln(low) can round below low: a design's variables are fed back as ``x0``)."""
        u = _finite(u, "u")
        if u in (0.0, 1.0):
            return self.high if u == 1.0 else self.low
        if self.log:
            a, b = math.log(self.low), math.log(self.high)
            value = math.exp(a + u * (b - a))
        else:
            value = self.low + u * (self.high - self.low)
        return min(max(value, self.low), self.high) if 0.0 <= u <= 1.0 else value

    def coordinate(self, value: float) -> float:
        """The unit coordinate of a parameter value (inverse of :meth:`value`)."""
        value = _finite(value, "value", positive=self.log)
        if self.log:
            a, b = math.log(self.low), math.log(self.high)
            return (math.log(value) - a) / (b - a)
        u = (value - self.low) / (self.high - self.low)
        if not math.isfinite(u):
            raise ValueError(
                f"value {value!r} is too far outside the bounds of variable {self.name!r}: its "
                "unit coordinate overflows"
            )
        return u

    def slope(self, value: float) -> float:
        """dp/du at the parameter ``value``."""
        value = _finite(value, "value", positive=self.log)
        if self.log:
            return value * (math.log(self.high) - math.log(self.low))
        return self.high - self.low


class Space:
    """The design space: a base model and the variables that replace its parameters.

    Parameters
    ----------
    base : HairBed or Pillar
        The model whose other parameters stay as they are.
    variables : sequence of Variable
        At least one, each name once, each a parameter of ``base`` (:data:`BED_VARIABLES`,
        :data:`PILLAR_VARIABLES`).

    Notes
    -----
    A bed is built from one of spacing and packing fraction: ``packing_fraction`` is held
    (fixed, or varied) when it is a variable, otherwise the spacing; a varied radius then
    changes the packing fraction phi = (2 pi/sqrt 3) a^2/delta^2 at fixed spacing. Every
    corner of the box is built once, so that bounds that allow an impossible model (hairs
    reaching the top wall, overlapping hairs, a stubby pillar) are refused up front.
    """

    def __init__(self, base: Any, variables: Any) -> None:
        if isinstance(base, HairBed):
            allowed, kind = BED_VARIABLES, "bed"
        elif isinstance(base, Pillar):
            allowed, kind = PILLAR_VARIABLES, "pillar"
        else:
            raise TypeError(
                f"base must be a hairbed.HairBed or hairbed.Pillar, got {type(base).__name__}"
            )
        if isinstance(variables, Variable):
            variables = [variables]
        if isinstance(variables, (str, bytes, dict)) or not np.iterable(variables):
            raise TypeError(
                f"variables must be a hairbed.design.Variable or a sequence of them, got "
                f"{show(variables)}"
            )
        variables = list(variables)
        if not variables:
            raise ValueError("variables must hold at least one Variable, got none")
        seen: set[str] = set()
        for v in variables:
            if not isinstance(v, Variable):
                raise TypeError(f"variables must be hairbed.design.Variable, got {show(v)}")
            if v.name not in allowed:
                raise ValueError(
                    f"unknown design variable {v.name!r} for a {type(base).__name__}: choose "
                    f"from {', '.join(allowed)}"
                )
            if v.name in seen:
                raise ValueError(f"design variable {v.name!r} is given twice")
            seen.add(v.name)
            if v.name == "density" and getattr(base, "density", None) is None:
                raise ValueError(
                    "design variable 'density': the base model has no density to vary"
                )
            if v.name == "channel_height" and kind == "pillar" and base.channel_height is None:
                raise ValueError(
                    "design variable 'channel_height': the base pillar's profile "
                    f"{base.profile!r} has no channel"
                )
        if kind == "bed" and {"spacing", "packing_fraction"} <= seen:
            raise ValueError(
                "give at most one of the design variables spacing and packing_fraction: "
                "a bed is built from one of them"
            )
        self.base = base
        self.kind = kind
        self.variables: tuple[Variable, ...] = tuple(variables)
        self.names = tuple(v.name for v in self.variables)
        self.hold = "packing_fraction" if "packing_fraction" in seen else "spacing"
        self._check_corners()

    @property
    def size(self) -> int:
        """The number of variables."""
        return len(self.variables)

    def values(self, u: FloatArray) -> dict[str, float]:
        """{name: SI value} at the unit coordinates ``u``."""
        if isinstance(u, (str, bytes)) or not np.iterable(u) or len(u) != self.size:
            raise TypeError(f"u must be a sequence of {self.size} unit coordinates, got {show(u)}")
        return {v.name: v.value(x) for v, x in zip(self.variables, u, strict=True)}

    def _named(self, values: Any) -> dict[str, float]:
        if not isinstance(values, dict) or set(values) != set(self.names):
            raise TypeError(
                f"values must be a dict of every design variable ({', '.join(self.names)}), "
                f"got {show(values)}"
            )
        return {k: _finite(x, f"values[{k!r}]") for k, x in values.items()}

    def slopes(self, values: dict[str, float]) -> FloatArray:
        """dp/du of every variable at its value."""
        values = self._named(values)
        return np.array([v.slope(values[v.name]) for v in self.variables])

    def coordinates(self, values: dict[str, float]) -> FloatArray:
        """The unit coordinates of SI values (inverse of :meth:`values`)."""
        values = self._named(values)
        return np.array([v.coordinate(values[v.name]) for v in self.variables])

    def model(self, values: dict[str, float]) -> Any:
        """The base model with the parameters ``values`` (SI) replaced; warnings of the
        constructor (plausibility, validity) are silenced: validity is a constraint."""
        changes: dict[str, Any] = self._named(values)
        if self.kind == "bed":
            if self.hold == "packing_fraction":
                changes["spacing"] = None
            else:
                changes["packing_fraction"] = None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return dataclasses.replace(self.base, **changes)

    def _check_corners(self) -> None:
        """Build the model at every corner of the box (at most 2^12): a ValueError naming
        the bounds where a corner is not a model."""
        n = self.size
        if n > _MAX_CORNER_CHECK:
            return
        for corner in itertools.product((0.0, 1.0), repeat=n):
            values = self.values(np.array(corner))
            try:
                self.model(values)
            except (ValueError, TypeError) as exc:
                shown = ", ".join(f"{k}={v:.6g}" for k, v in values.items())
                raise ValueError(
                    f"the bounds of the design variables allow an impossible "
                    f"{type(self.base).__name__} at the corner ({shown}): {exc}"
                ) from None
