"""The Pareto front of two objectives by the epsilon-constraint method.

Optimise the first objective alone (its best a*) and the second alone (its best b*); the
second's value at a* is b0. For n levels e_k evenly spaced from b0 to b*, optimise the
first under the constraint "second at least as good as e_k" (>= e_k when the second is
maximised, <= e_k when minimised), each run started from the previous point's design. Every
point is a constrained optimum (:func:`~hairbed.design.optimise`): a front that is not
convex is traced too, unlike a weighted sum.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .._core.validation import show
from ._objectives import Constraint, Quantity
from ._optimise import SENSES, optimise
from ._result import DesignResult, ParetoFront
from ._variables import Variable

__all__ = ["pareto_front"]


def pareto_front(
    base: Any,
    variables: Variable | Sequence[Variable],
    first: Quantity,
    second: Quantity,
    *,
    senses: tuple[str, str] = ("max", "max"),
    points: int = 20,
    constraints: Sequence[Constraint] = (),
    starts: int = 4,
    seed: int = 0,
    validity: bool = True,
) -> ParetoFront:
    """The Pareto front of ``first`` against ``second`` (epsilon-constraint method).

    Parameters
    ----------
    base, variables, constraints, seed, validity
        As for :func:`~hairbed.design.optimise`.
    first, second : Quantity
        The two objectives.
    senses : (str, str)
        "min" or "max" for each.
    points : int
        Points of the front, in [2, 1000], the two single-objective optima included.
    starts : int
        Starts of the two single-objective optimisations; the points between are started
        from their neighbour's design.

    Returns
    -------
    ParetoFront
    """
    if isinstance(points, bool) or not isinstance(points, int) or not 2 <= points <= 1000:
        raise ValueError(f"points must be an integer in [2, 1000], got {show(points)}")
    if (
        not isinstance(senses, (tuple, list))
        or len(senses) != 2
        or any(not isinstance(s, str) or s not in SENSES for s in senses)
    ):
        raise ValueError(f"senses must be two of {SENSES}, got {show(senses)}")
    for name, q in (("first", first), ("second", second)):
        if not isinstance(q, Quantity):
            raise TypeError(f"{name} must be a hairbed.design quantity, got {show(q)}")
    kw: dict[str, Any] = {"seed": seed, "validity": validity}
    a = optimise(
        base, variables, first, constraints=constraints, sense=senses[0], starts=starts, **kw
    )
    b = optimise(
        base, variables, second, constraints=constraints, sense=senses[1], starts=starts, **kw
    )
    for name, r in (("first", a), ("second", b)):
        if not r.success:
            raise ValueError(f"pareto_front: the {name} objective alone: {r.message}")
    b0 = second(a.design)
    levels = np.linspace(b0, b.objective, points)
    results: list[DesignResult] = [a]
    x0 = a.variables
    for level in levels[1:-1]:
        c = (
            Constraint(second, lower=level)
            if senses[1] == "max"
            else Constraint(second, upper=level)
        )
        r = optimise(
            base, variables, first, constraints=[*constraints, c], sense=senses[0],
            starts=1, x0=x0, **kw,
        )  # fmt: skip
        results.append(r)
        if r.success:
            x0 = r.variables
    results.append(b)
    ok = np.array([r.success for r in results])
    f1 = np.array(
        [r.objective if r is not b else first(b.design) if r.success else np.nan for r in results]
    )
    f2 = np.array([second(r.design) if r.success else np.nan for r in results])
    f1 = np.where(ok, f1, np.nan)
    status = 0 if np.all(ok) else 1
    return ParetoFront(
        first=f1,
        second=f2,
        first_name=first.name,
        second_name=second.name,
        senses=(senses[0], senses[1]),
        results=tuple(results),
        success=ok,
        method=(
            f"epsilon-constraint: {first.name} ({senses[0]}) at {points - 2} levels of "
            f"{second.name} between the two single-objective optima"
        ),
        status=status,
        message="ok" if status == 0 else f"{int(np.count_nonzero(~ok))} point(s) failed",
    )
