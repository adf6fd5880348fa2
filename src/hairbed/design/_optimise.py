"""The multi-start constrained optimiser of a design (SLSQP with exact gradients).

The problem is solved in the unit box of the variables (:class:`~hairbed.design.Space`):

    minimise  s_f f(u)   subject to   (b_j - q_j(u))/s_j >= 0  ("<=")  or
                                      (q_j(u) - b_j)/s_j >= 0  (">="),   0 <= u <= 1,

with s_f the largest abs(f) over the starts and s_j = max(abs(b_j), 1e-300) (a maximisation
minimises -f). Every start is a local SLSQP run (scipy.optimize.minimize) with the exact
gradient of every quantity (``Quantity.exact``); the best start that meets every
constraint, the model's validity included (to 1e-7 relative), is the design. SLSQP's
Lagrange multipliers lambda_j of the scaled problem give the price of each bound,
d f*/d b_j = -+ lambda_j s_f/s_j, and the reduced gradient of the Lagrangian that of each
active bound of a variable.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize
from scipy.stats import qmc

from .._core.validation import show
from ._objectives import FD_STEP, Constraint, Quantity, validity_constraints
from ._result import ConstraintReport, DesignResult
from ._variables import Space, Variable

__all__ = ["optimise"]

FloatArray = NDArray[np.float64]
#: A constraint is met to this relative tolerance, and active within it (scaled slack).
FEASIBLE_RTOL = 1e-7
ACTIVE_RTOL = 1e-6
#: SLSQP's tolerance on the scaled objective (about 1 at the starts): above the rounding of
#: the quantities (collocated states to ~1e-12, the linear range's Newton root to ~1e-10
#: relative), where a tighter one only stalls the line search (status 8) and restarts it
SLSQP_FTOL = 1e-12
SENSES = ("min", "max")


class _Problem:
    """The scaled problem: values and gradients in the unit box, memoised per point."""

    def __init__(self, space: Space, objective: Quantity, constraints: list[Constraint]) -> None:
        self.space = space
        self.objective = objective
        self.constraints = constraints
        self.quantities = [objective, *(c.quantity for c in constraints)]
        self._last: tuple[bytes, Any] | None = None
        self.nfev = 0

    def _fd(self, q: Quantity, u: FloatArray) -> FloatArray:
        """Central differences in u of a quantity without a gradient (``custom``)."""
        value_of = q._value_of  # type: ignore[attr-defined]
        g = np.empty(u.size)
        for i in range(u.size):
            h = FD_STEP * max(abs(u[i]), 1e-2)
            up, down = u.copy(), u.copy()
            up[i] += h
            down[i] -= h
            g[i] = (
                value_of(self.space.model(self.space.values(up)))
                - value_of(self.space.model(self.space.values(down)))
            ) / (2.0 * h)
        return g

    def at(self, u: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(values (1 + m,), gradients in u (1 + m, n)) of objective and constraints."""
        key = np.asarray(u, dtype=np.float64).tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        self.nfev += 1
        values = self.space.values(u)
        model = self.space.model(values)
        slopes = self.space.slopes(values)
        vals = np.empty(len(self.quantities))
        grads = np.empty((len(self.quantities), self.space.size))
        for k, q in enumerate(self.quantities):
            v, g = q.evaluate(model, self.space.hold)
            vals[k] = v
            if not q.exact and hasattr(q, "_value_of"):
                grads[k] = self._fd(q, np.asarray(u, dtype=np.float64))
            else:
                grads[k] = [
                    g.get(n, 0.0) * s for n, s in zip(self.space.names, slopes, strict=True)
                ]
        if not np.all(np.isfinite(vals)) or not np.all(np.isfinite(grads)):
            bad = int(np.flatnonzero(~np.isfinite(vals) | ~np.all(np.isfinite(grads), axis=1))[0])
            raise ArithmeticError(f"{self.quantities[bad].name} is not finite at {values}")
        self._last = (key, (vals, grads))
        return vals, grads


def _signs(constraints: Sequence[Constraint]) -> FloatArray:
    """+1 for ">=" (q - b), -1 for "<=" (b - q)."""
    return np.array([1.0 if c.lower is not None else -1.0 for c in constraints])


def _scales(constraints: Sequence[Constraint]) -> FloatArray:
    return np.array([max(abs(c.bound), 1e-300) for c in constraints])


def _starts(space: Space, count: int, seed: int, x0: dict[str, float] | None) -> list[FloatArray]:
    """The centre (or ``x0``), then scrambled Sobol points of the box."""
    first = np.full(space.size, 0.5) if x0 is None else np.clip(space.coordinates(x0), 0, 1)
    out = [first]
    if count > 1:
        sob = qmc.Sobol(space.size, scramble=True, seed=seed)
        out.extend(sob.random_base2(max(0, math.ceil(math.log2(count - 1))))[: count - 1])
    return out


def _objective_scale(problem: _Problem, points: list[FloatArray]) -> float:
    """The largest abs(f) over the starts (1 where all vanish or none evaluates): a start on
    a plateau f = 0 (no bistable window) must not set the scale."""
    found = []
    for u in points:
        try:
            found.append(abs(float(problem.at(u)[0][0])))
        except (ArithmeticError, ValueError):
            continue
    big = max(found, default=0.0)
    return big if big > 0.0 and math.isfinite(big) else 1.0


def _check_options(space: Space, seed: Any, maxiter: Any, x0: Any) -> None:
    """seed, maxiter and x0 of :func:`optimise`, or a ValueError naming them."""
    for name, value, low, high in (("seed", seed, 0, 2**63 - 1), ("maxiter", maxiter, 1, 100_000)):
        if isinstance(value, (bool, np.timedelta64)) or not isinstance(value, (int, np.integer)):
            raise ValueError(f"{name} must be an integer in [{low}, {high}], got {show(value)}")
        if not low <= value <= high:
            raise ValueError(f"{name} must be an integer in [{low}, {high}], got {show(value)}")
    if x0 is None:
        return
    if not isinstance(x0, dict) or set(x0) != set(space.names):
        raise ValueError(
            f"x0 must be a dict of every design variable ({', '.join(space.names)}), got "
            f"{show(x0)}"
        )
    for v in space.variables:
        x = x0[v.name]
        if isinstance(x, bool) or not isinstance(x, (int, float, np.floating)):
            raise ValueError(f"x0[{v.name!r}] must be a number, got {x!r}")
        if not v.low <= float(x) <= v.high:
            raise ValueError(
                f"x0[{v.name!r}] = {x!r} must lie within its bounds [{v.low!r}, {v.high!r}]"
            )


def _check(objective: Any, constraints: Any, sense: str, starts: Any, kind: str) -> None:
    if not isinstance(objective, Quantity):
        raise TypeError(
            "objective must be a hairbed.design quantity (diodicity(...), linear_range(...), "
            f"custom(...), ...), got {show(objective)}"
        )
    for c in constraints:
        if not isinstance(c, Constraint):
            raise TypeError(
                "constraints must be hairbed.design constraints (quantity <= bound), got "
                f"{show(c)}"
            )
    if not isinstance(sense, str) or sense not in SENSES:
        raise ValueError(f"sense must be one of {SENSES}, got {show(sense)}")
    if isinstance(starts, bool) or not isinstance(starts, int) or not 1 <= starts <= 10_000:
        raise ValueError(f"starts must be an integer in [1, 10000], got {show(starts)}")
    for q in (objective, *(c.quantity for c in constraints)):
        if q.kind not in ("any", kind):
            raise TypeError(f"{q.name} is a quantity of a {q.kind}, the design varies a {kind}")


def optimise(
    base: Any,
    variables: Variable | Sequence[Variable],
    objective: Quantity,
    *,
    constraints: Sequence[Constraint] = (),
    sense: str = "min",
    starts: int = 8,
    seed: int = 0,
    x0: dict[str, float] | None = None,
    validity: bool = True,
    maxiter: int = 200,
) -> DesignResult:
    """The best design of ``base`` over ``variables`` for an objective under constraints.

    Parameters
    ----------
    base : HairBed or Pillar
        The model; its parameters that are not variables stay fixed.
    variables : Variable or sequence of Variable
        The SI parameters to vary, with bounds (:class:`~hairbed.design.Variable`).
    objective : Quantity
        What to minimise or maximise (:func:`~hairbed.design.diodicity`, ...).
    constraints : sequence of Constraint
        ``quantity <= bound`` or ``quantity >= bound``.
    sense : {"min", "max"}
    starts : int
        Local optimisations from the centre of the box (or ``x0``) and scrambled Sobol
        points (``seed``), in [1, 10000]: bistable windows and other non-convex problems
        need several.
    x0 : dict, optional
        {name: SI value}: the first start.
    validity : bool
        Add the model's validity as constraints (default; see
        :func:`~hairbed.design.validity_constraints`). A design outside it is never
        reported as optimal.
    maxiter : int
        SLSQP's iteration limit per start, in [1, 100000].
    seed : int
        The seed of the scrambled Sobol starts, in [0, 2^63 - 1] (default 0: the same
        starts, and the same result, on every run).

    Returns
    -------
    DesignResult
        ``design`` None and ``success`` False when no start meets every constraint (the
        message names the constraint that cannot be met) or none converged.

    Examples
    --------
    >>> from hairbed import HairBed
    >>> from hairbed import design
    >>> bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
    ...               viscosity=1.0, spacing=250e-6, base_angle=0.5)
    >>> res = design.optimise(bed, design.Variable("base_angle", 0.0, 1.4),
    ...                       design.diodicity(1000.0, 0.01), sense="max", starts=2)
    >>> res.success, round(res.variables["base_angle"], 3)  # the most diodic tilt [rad]
    (True, 0.778)
    """
    space = Space(base, variables)
    if isinstance(constraints, (str, bytes, dict)) or not np.iterable(constraints):
        raise TypeError(
            f"constraints must be a sequence of hairbed.design constraints, got "
            f"{show(constraints)}"
        )
    constraints = list(constraints)
    _check(objective, constraints, sense, starts, space.kind)
    _check_options(space, seed, maxiter, x0)
    if not isinstance(validity, (bool, np.bool_)):
        raise TypeError(f"validity must be True or False, got {show(validity)}")
    notes: list[str] = []
    if validity:
        extra, notes = validity_constraints(base, [objective, *(c.quantity for c in constraints)])
        constraints = constraints + extra
    problem = _Problem(space, objective, constraints)
    sign_f = 1.0 if sense == "min" else -1.0
    sgn, scl = _signs(constraints), _scales(constraints)
    points = _starts(space, starts, seed, x0)
    fs = _objective_scale(problem, points)
    runs: list[tuple[FloatArray, Any, str]] = []
    bounds = np.array([c.bound for c in constraints])
    scipy_constraints = (
        [
            {
                "type": "ineq",
                "fun": lambda u: sgn * (problem.at(u)[0][1:] - bounds) / scl,
                "jac": lambda u: (sgn / scl)[:, None] * problem.at(u)[1][1:],
            }
        ]
        if constraints
        else []
    )

    def local(u0: FloatArray) -> Any:
        return minimize(
            lambda u: sign_f * problem.at(u)[0][0] / fs,
            u0,
            jac=lambda u: sign_f * problem.at(u)[1][0] / fs,
            method="SLSQP",
            bounds=[(0.0, 1.0)] * space.size,
            constraints=scipy_constraints,
            options={"maxiter": maxiter, "ftol": SLSQP_FTOL},
        )

    for u0 in points:
        try:
            res = local(u0)
            # SLSQP's line search can stall at an optimum held to rounding (status 8):
            # restarted there, a run that does not move confirms it
            for _ in range(2):
                if res.status != 8:
                    break
                again = local(np.clip(res.x, 0.0, 1.0))
                if again.status in (0, 8) and np.max(np.abs(again.x - res.x)) <= 1e-10:
                    again.success, again.status = True, 0
                    again.message = "converged (SLSQP's line search stalled at the optimum)"
                res = again
            u = np.clip(np.asarray(res.x, dtype=np.float64), 0.0, 1.0)
            runs.append((u, res, ""))
        except (ArithmeticError, ValueError) as exc:
            runs.append((np.asarray(u0), None, f"{type(exc).__name__}: {exc}"))
    return _assemble(problem, space, constraints, sense, runs, notes, fs, sgn, scl)


def _assemble(
    problem: _Problem,
    space: Space,
    constraints: list[Constraint],
    sense: str,
    runs: list[tuple[FloatArray, Any, str]],
    notes: list[str],
    fs: float,
    sgn: FloatArray,
    scl: FloatArray,
) -> DesignResult:
    sign_f = 1.0 if sense == "min" else -1.0
    bounds = np.array([c.bound for c in constraints])
    good: list[tuple[float, FloatArray, Any]] = []
    worst: list[tuple[float, int, FloatArray]] = []  # (largest scaled violation, which, u)
    converged = 0
    for u, res, _ in runs:
        if res is None:
            continue
        try:
            vals, _ = problem.at(u)
        except (ArithmeticError, ValueError):
            continue
        viol = -sgn * (vals[1:] - bounds) / scl if constraints else np.zeros(0)
        if res.success:
            converged += 1
        if viol.size and np.max(viol) > FEASIBLE_RTOL:
            j = int(np.argmax(viol))
            worst.append((float(viol[j]), j, u))
            continue
        if res.success:
            good.append((sign_f * float(vals[0]), u, res))
    inexact = tuple(q.name for q in problem.quantities if not q.exact)
    common = {
        "objective_name": problem.objective.name,
        "sense": sense,
        "starts": len(runs),
        "exact_gradient": not inexact,
        "inexact": inexact,
        "notes": tuple(notes),
        "nfev": problem.nfev,
    }
    if not good:
        if worst:
            viol, j, u = min(worst, key=lambda w: w[0])
            c = constraints[j]
            vals, _ = problem.at(u)
            status = 2
            message = (
                f"infeasible: the constraint {c.label} cannot be met (at best "
                f"{vals[1 + j]:.6g} over {len(runs)} starts)"
            )
            reports = _reports(problem, constraints, vals, None, fs, sense)
            values = space.values(u)
            objective = float(vals[0])
        else:
            errors = [m for _, _, m in runs if m]
            status, message = 1, "no start converged" + (f": {errors[0]}" if errors else "")
            reports, values, objective = [], {}, math.nan
        return DesignResult(
            success=False,
            status=status,
            message=message,
            design=None,
            variables=values,
            objective=objective,
            constraints=tuple(reports),
            bound_sensitivities={},
            local_optima=np.empty(0),
            spread=math.nan,
            **common,  # type: ignore[arg-type]
        )
    good.sort(key=lambda g: g[0])
    _, u, res = good[0]
    vals, grads = problem.at(u)
    optima = np.array([sign_f * g[0] for g in good])
    lam = np.asarray(getattr(res, "multipliers", np.zeros(len(constraints))), dtype=np.float64)
    reports = _reports(problem, constraints, vals, lam, fs, sense)
    values = space.values(u)
    sens = _bound_sensitivities(space, values, grads, constraints, lam, fs, sgn, scl, u, sense)
    return DesignResult(
        success=True,
        status=0,
        message=f"optimum found ({len(good)} of {len(runs)} starts converged feasibly)",
        design=space.model(values),
        variables=values,
        objective=float(vals[0]),
        constraints=tuple(reports),
        bound_sensitivities=sens,
        local_optima=optima,
        spread=float(np.max(optima) - np.min(optima)),
        **common,  # type: ignore[arg-type]
    )


def _reports(
    problem: _Problem,
    constraints: list[Constraint],
    vals: FloatArray,
    lam: FloatArray | None,
    fs: float,
    sense: str,
) -> list[ConstraintReport]:
    sign_f = 1.0 if sense == "min" else -1.0
    out = []
    for j, c in enumerate(constraints):
        value = float(vals[1 + j])
        slack = c.slack(value)
        scale = max(abs(c.bound), 1e-300)
        active = abs(slack) <= ACTIVE_RTOL * scale
        # d f*/d b of the scaled problem: relaxing b (up for "<=", down for ">=") by one unit
        # lowers the scaled objective by lambda/s_j; in the user's sense, better is positive
        mult = 0.0
        if lam is not None and lam.size == len(constraints) and active:
            # the scaled problem: d f_int*/d b = -lambda fs/s ("<=") or +lambda fs/s (">="),
            # f_int = f (min) or -f (max)
            pay = float(lam[j]) * fs / scale
            mult = sign_f * (-pay if c.upper is not None else pay)
        out.append(
            ConstraintReport(
                label=c.label,
                value=value,
                bound=c.bound,
                slack=slack,
                active=bool(active),
                multiplier=mult,
                validity=c.validity,
            )
        )
    return out


def _bound_sensitivities(
    space: Space,
    values: dict[str, float],
    grads: FloatArray,
    constraints: list[Constraint],
    lam: FloatArray,
    fs: float,
    sgn: FloatArray,
    scl: FloatArray,
    u: FloatArray,
    sense: str,
) -> dict[str, float]:
    """d(optimal objective)/d(bound) of the variables at an active bound: the gradient of
    the Lagrangian in that variable (the bound moves the variable with it)."""
    sign_f = 1.0 if sense == "min" else -1.0
    gl = sign_f * grads[0] / fs
    if constraints and lam.size == len(constraints):
        gl = gl - ((lam * sgn / scl)[:, None] * grads[1:]).sum(axis=0)
    slopes = space.slopes(values)
    out: dict[str, float] = {}
    for i, v in enumerate(space.variables):
        # moving an active bound moves the variable with it: d f*/d bound = dL/dp_i
        d_f = sign_f * gl[i] * fs / slopes[i]
        if u[i] <= 1e-9:
            out[f"{v.name}.low"] = d_f
        elif u[i] >= 1.0 - 1e-9:
            out[f"{v.name}.high"] = d_f
    return out
