"""The typed results of a design: one optimum (:class:`DesignResult`) and a Pareto front
(:class:`ParetoFront`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["ConstraintReport", "DesignResult", "ParetoFront"]


@dataclass(frozen=True)
class ConstraintReport:
    """One constraint at the design found.

    Attributes
    ----------
    label : str
        ``"quantity <= bound"`` or ``"quantity >= bound"``.
    value, bound : float
        The quantity's value at the design and its bound [the quantity's unit].
    slack : float
        How far inside the bound (negative: violated).
    active : bool
        True where the bound holds with equality (to 1e-6 relative).
    multiplier : float
        d(optimal objective)/d(bound) [objective's unit per bound's unit]: how the optimum's
        objective changes as the bound rises (the Lagrange multiplier, what relaxing the
        bound would pay); 0 when inactive.
    validity : bool
        True for a constraint of the model's validity.
    """

    label: str
    value: float
    bound: float
    slack: float
    active: bool
    multiplier: float
    validity: bool


@dataclass(frozen=True)
class DesignResult:
    """The best design of a multi-start optimisation (:func:`hairbed.design.optimise`).

    Attributes
    ----------
    success : bool
        True when a local optimiser converged to a design that meets every constraint,
        model validity included. Otherwise ``design`` is None.
    status : int
        0 optimum found; 1 no start converged; 2 infeasible (no start met the constraints).
    message : str
        What happened; for an infeasible problem, the constraint that cannot be met.
    design : HairBed or Pillar or None
        The optimal model, None unless ``success``.
    variables : dict
        {name: SI value} of the design (of the least infeasible end point when infeasible).
    objective : float
        The objective's value at the design [its unit].
    objective_name : str
    sense : {"min", "max"}
    constraints : tuple of ConstraintReport
        Every constraint, user's and validity's, at the design.
    bound_sensitivities : dict
        {"name.low" or "name.high": d(optimal objective)/d(bound)} [objective's unit per the
        variable's SI unit] of the variables at an active bound.
    starts : int
        The number of local optimisations run.
    local_optima : ndarray
        The objective values of the starts that converged feasibly, sorted best first.
    spread : float
        max - min of ``local_optima`` (0 when the starts agree; NaN when none converged).
    exact_gradient : bool
        True when every gradient used is exact; see ``inexact``.
    inexact : tuple of str
        The quantities whose gradient is a central difference.
    notes : tuple of str
        Validity checks that could not be made (e.g. no density).
    nfev : int
        Objective evaluations over all starts.
    """

    success: bool
    status: int
    message: str
    design: Any
    variables: dict[str, float]
    objective: float
    objective_name: str
    sense: str
    constraints: tuple[ConstraintReport, ...]
    bound_sensitivities: dict[str, float]
    starts: int
    local_optima: NDArray[np.float64]
    spread: float
    exact_gradient: bool
    inexact: tuple[str, ...]
    notes: tuple[str, ...]
    nfev: int

    @property
    def active(self) -> tuple[ConstraintReport, ...]:
        """The active constraints."""
        return tuple(c for c in self.constraints if c.active)


@dataclass(frozen=True)
class ParetoFront:
    """The Pareto front of two objectives by the epsilon-constraint method
    (:func:`hairbed.design.pareto_front`).

    Attributes
    ----------
    first, second : ndarray
        The two objectives' values at each point of the front [their units], ordered from
        the first objective's optimum to the second's.
    first_name, second_name : str
    senses : (str, str)
    results : tuple of DesignResult
        The optimisation of each point (its design, constraints and multipliers).
    success : ndarray of bool
        Per point.
    method : str
        How the front was made.
    status : int
        0 every point converged, 1 some did not (their values are NaN).
    message : str
    """

    first: NDArray[np.float64]
    second: NDArray[np.float64]
    first_name: str
    second_name: str
    senses: tuple[str, str]
    results: tuple[DesignResult, ...] = field(repr=False)
    success: NDArray[np.bool_]
    method: str
    status: int
    message: str
