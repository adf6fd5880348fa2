"""A design problem from a plain spec (the TOML file of ``hairbed design``), and its result
as plain data.

The spec is a mapping::

    [model]                 kind = "bed" or "pillar", then the constructor's parameters (SI)
    [[variables]]           name, low, high, log (optional)
    [objective]             quantity, its arguments, sense = "min" or "max"
    [[constraints]]         quantity, its arguments, and max = bound or min = bound
    [second]                optional: a second objective (quantity, arguments, sense): the
                            Pareto front of the two (epsilon-constraint) instead of one optimum
    [options]               starts, seed, validity, points (of a front) (optional)

Quantities and their arguments: diodicity, resistance_ratio, gap_reynolds (pressure_drop
[Pa], channel_length [m]); brinkman_ratio, bistable_width (none); tip_deflection,
sensitivity, l_plus, pillar_reynolds, bandwidth (wall_shear_stress [Pa]); linear_range
(rtol); slenderness, linear_sensitivity, snap_window (none); resonance_frequency
(wall_shear_stress [Pa], pillar_density [kg/m^3]).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Mapping
from typing import Any

from ..pillars import Pillar
from ..units import HairBed
from . import _objectives as Q
from ._objectives import Constraint, Quantity
from ._optimise import optimise
from ._pareto import pareto_front
from ._result import DesignResult, ParetoFront
from ._variables import Variable

__all__ = ["QUANTITIES", "design_from_spec", "front_as_dict", "result_as_dict"]

#: Quantity name -> (factory, its argument names).
QUANTITIES: dict[str, tuple[Callable[..., Quantity], tuple[str, ...]]] = {
    "diodicity": (Q.diodicity, ("pressure_drop", "channel_length")),
    "resistance_ratio": (Q.resistance_ratio, ("pressure_drop", "channel_length")),
    "gap_reynolds": (Q.gap_reynolds, ("pressure_drop", "channel_length")),
    "brinkman_ratio": (Q.brinkman_ratio, ()),
    "bistable_width": (Q.bistable_width, ()),
    "tip_deflection": (Q.tip_deflection, ("wall_shear_stress",)),
    "sensitivity": (Q.sensitivity, ("wall_shear_stress",)),
    "l_plus": (Q.l_plus, ("wall_shear_stress",)),
    "pillar_reynolds": (Q.pillar_reynolds, ("wall_shear_stress",)),
    "linear_range": (Q.linear_range, ("rtol",)),
    "slenderness": (Q.slenderness, ()),
    "linear_sensitivity": (Q.linear_sensitivity, ()),
    "bandwidth": (Q.bandwidth, ("wall_shear_stress",)),
    "snap_window": (Q.snap_window, ()),
    "resonance_frequency": (Q.resonance_frequency, ("wall_shear_stress", "pillar_density")),
}
_MODELS = {"bed": HairBed, "pillar": Pillar}


def _table(spec: Mapping[str, Any], key: str, where: str = "the spec") -> Mapping[str, Any]:
    value = spec.get(key)
    if not isinstance(value, Mapping):
        raise ValueError(f"{where} needs a table [{key}]")
    return value


def _unknown(table: Mapping[str, Any], allowed: set[str], where: str) -> None:
    extra = sorted(set(table) - allowed)
    if extra:
        raise ValueError(
            f"{where}: unknown key {extra[0]!r} (allowed: {', '.join(sorted(allowed))})"
        )


def _quantity(table: Mapping[str, Any], where: str, extra: set[str]) -> Quantity:
    name = table.get("quantity")
    if name not in QUANTITIES:
        raise ValueError(
            f"{where}: unknown quantity {name!r}: choose from {', '.join(QUANTITIES)}"
        )
    factory, args = QUANTITIES[name]
    _unknown(table, {"quantity", *args, *extra}, where)
    missing = [a for a in args if a not in table and a != "rtol"]
    if missing:
        raise ValueError(f"{where}: quantity {name!r} needs {missing[0]!r}")
    return factory(**{a: table[a] for a in args if a in table})


def design_from_spec(spec: Mapping[str, Any]) -> DesignResult | ParetoFront:
    """Run the design a spec describes (module docstring): one optimum, or the Pareto front
    when the spec has a [second] objective; a ValueError naming the key of anything wrong
    in it."""
    if not isinstance(spec, Mapping):
        raise ValueError("the spec must be a mapping (a TOML document)")
    _unknown(
        spec, {"model", "variables", "objective", "constraints", "options", "second"}, "the spec"
    )
    model = dict(_table(spec, "model"))
    kind = model.pop("kind", "bed")
    if kind not in _MODELS:
        raise ValueError(f"[model] kind must be 'bed' or 'pillar', got {kind!r}")
    cls = _MODELS[kind]
    names = {f.name for f in dataclasses.fields(cls) if f.init}
    _unknown(model, names, "[model]")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            base = cls(**model)
    except TypeError as exc:
        raise ValueError(f"[model]: {exc}") from None
    raw_vars = spec.get("variables")
    if not isinstance(raw_vars, list) or not raw_vars:
        raise ValueError("the spec needs at least one [[variables]] table")
    variables = []
    for i, v in enumerate(raw_vars):
        where = f"[[variables]] {i + 1}"
        if not isinstance(v, Mapping):
            raise ValueError(f"{where} must be a table")
        _unknown(v, {"name", "low", "high", "log"}, where)
        for key in ("name", "low", "high"):
            if key not in v:
                raise ValueError(f"{where} needs {key!r}")
        variables.append(Variable(v["name"], v["low"], v["high"], v.get("log", False)))
    obj = _table(spec, "objective")
    sense = obj.get("sense", "min")
    objective = _quantity(obj, "[objective]", {"sense"})
    constraints: list[Constraint] = []
    raw_cons = spec.get("constraints", [])
    if not isinstance(raw_cons, list):
        raise ValueError("[[constraints]] must be an array of tables")
    for i, c in enumerate(raw_cons):
        where = f"[[constraints]] {i + 1}"
        if not isinstance(c, Mapping):
            raise ValueError(f"{where} must be a table")
        q = _quantity(c, where, {"max", "min"})
        if ("max" in c) == ("min" in c):
            raise ValueError(f"{where}: give exactly one of max and min")
        constraints.append(q <= c["max"] if "max" in c else q >= c["min"])
    options = dict(spec.get("options", {}))
    _unknown(options, {"starts", "seed", "validity", "points"}, "[options]")
    common: dict[str, Any] = {
        "constraints": constraints,
        "seed": options.get("seed", 0),
        "validity": bool(options.get("validity", True)),
    }
    if "second" in spec:
        sec = _table(spec, "second")
        second = _quantity(sec, "[second]", {"sense"})
        return pareto_front(
            base,
            variables,
            objective,
            second,
            senses=(sense, sec.get("sense", "min")),
            points=options.get("points", 20),
            starts=options.get("starts", 4),
            **common,
        )
    if "points" in options:
        raise ValueError("[options] points is the size of a Pareto front: give a [second]")
    return optimise(
        base, variables, objective, sense=sense, starts=options.get("starts", 8), **common
    )


def _plain(x: Any) -> Any:
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


def result_as_dict(res: DesignResult) -> dict[str, Any]:
    """The result as plain data (JSON-ready; the design as its constructor's parameters)."""
    design = None
    if res.design is not None:
        design = {
            f.name: _plain(getattr(res.design, f.name))
            for f in dataclasses.fields(res.design)
            if f.init and isinstance(getattr(res.design, f.name), (int, float, str, type(None)))
        }
    return {
        "success": res.success,
        "status": res.status,
        "message": res.message,
        "objective_name": res.objective_name,
        "sense": res.sense,
        "objective": _plain(res.objective),
        "variables": {k: _plain(v) for k, v in res.variables.items()},
        "design": design,
        "constraints": [
            {k: _plain(v) for k, v in dataclasses.asdict(c).items()} for c in res.constraints
        ],
        "bound_sensitivities": {k: _plain(v) for k, v in res.bound_sensitivities.items()},
        "starts": res.starts,
        "local_optima": [_plain(float(v)) for v in res.local_optima],
        "spread": _plain(res.spread),
        "exact_gradient": res.exact_gradient,
        "inexact": list(res.inexact),
        "notes": list(res.notes),
        "nfev": res.nfev,
    }


def front_as_dict(front: ParetoFront) -> dict[str, Any]:
    """The Pareto front as plain data (JSON-ready): both objectives per point, each
    point's variables and its full result."""
    return {
        "success": bool(front.status == 0),
        "status": front.status,
        "message": front.message,
        "method": front.method,
        "first_name": front.first_name,
        "second_name": front.second_name,
        "senses": list(front.senses),
        "first": [_plain(float(v)) for v in front.first],
        "second": [_plain(float(v)) for v in front.second],
        "points": [result_as_dict(r) for r in front.results],
    }
