"""Design for a target: which bed, which pillar (issue 32).

Choose SI parameters of a :class:`~hairbed.HairBed` or a :class:`~hairbed.Pillar`
(:class:`Variable`, with bounds, optionally in log scale) to minimise or maximise a named
quantity (:func:`diodicity`, :func:`resistance_ratio`, :func:`bistable_width`,
:func:`tip_deflection`, :func:`sensitivity`, :func:`linear_sensitivity`,
:func:`linear_range`, :func:`bandwidth`, :func:`resonance_frequency`, :func:`net_flow`,
:func:`snap_window`, :func:`custom`, ...)
under constraints written in the same vocabulary (``resistance_ratio(500, 0.01) <= 4``),
with the model's validity as constraints (:func:`validity_constraints`).

:func:`optimise` runs SLSQP from several starts with the exact gradients of the library
(implicit differentiation of the states and the chain rule through the dimensionless
groups); :func:`pareto_front` traces two objectives by the epsilon-constraint method. The
results are typed (:class:`DesignResult`, :class:`ParetoFront`).
"""

from ._objectives import (
    FD_STEP,
    GAP_REYNOLDS_LIMIT,
    Constraint,
    Quantity,
    bandwidth,
    bistable_width,
    brinkman_ratio,
    custom,
    diodicity,
    gap_reynolds,
    l_plus,
    linear_range,
    linear_sensitivity,
    net_flow,
    pillar_reynolds,
    resistance_ratio,
    resonance_frequency,
    sensitivity,
    slenderness,
    snap_window,
    tip_deflection,
    validity_constraints,
)
from ._optimise import optimise
from ._pareto import pareto_front
from ._result import ConstraintReport, DesignResult, ParetoFront
from ._variables import BED_VARIABLES, PILLAR_VARIABLES, Space, Variable

__all__ = [
    "BED_VARIABLES",
    "FD_STEP",
    "GAP_REYNOLDS_LIMIT",
    "PILLAR_VARIABLES",
    "Constraint",
    "ConstraintReport",
    "DesignResult",
    "ParetoFront",
    "Quantity",
    "Space",
    "Variable",
    "bandwidth",
    "bistable_width",
    "brinkman_ratio",
    "custom",
    "diodicity",
    "gap_reynolds",
    "l_plus",
    "linear_range",
    "linear_sensitivity",
    "net_flow",
    "optimise",
    "pareto_front",
    "pillar_reynolds",
    "resistance_ratio",
    "resonance_frequency",
    "sensitivity",
    "slenderness",
    "snap_window",
    "tip_deflection",
    "validity_constraints",
]
