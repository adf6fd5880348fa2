"""Linear stability of static states under a simple relaxation dynamics, and time-stepping.

The model
---------
The static problem (eq. (7), theory.md §1) says nothing about which of several coexisting
states a hair bed shows. For that we give the hair the simplest dynamics whose rest points are
exactly the static states, an overdamped relaxation of the angle:

    theta_t = theta_ss + omega_eps^2[theta] cos(theta),    0 < sigma < 1,
    theta(0, t) = theta0,    theta_s(1, t) = 0,
    omega_eps^2[theta] = omega^2 / (1 - eps h1[theta]),    h1[theta] = int_0^1 cos(theta) dsigma,

with time in units of the bending relaxation time (zeta L^4 / (E I) for a rotational drag
coefficient zeta per unit length). What it assumes:

- Overdamped: inertia of the hair and of the fluid are negligible; the bending moment is
  balanced by a drag proportional to the angular velocity, locally, with no hydrodynamic
  interaction along the hair. This is a model of relaxation, not a full elastohydrodynamic
  theory; its only job is to decide the sign of the growth rates.
- Quasi-static fluid: the channel flow adjusts instantly, so the load at every moment is the
  static one of the *current* shape: the tip force omega_eps^2 follows the current tip height
  h1 through the gap 1 - eps h1 (theory.md §7: the stress ratio 1 / (1 - eps h1)).
- The load is that of the static theory (a horizontal force at the tip); no wall contact.

The load is not conservative (the operator's Jacobian is not symmetric), so this is not a
gradient flow; it is, however, the unique local dynamics of this form whose steady states are
the paper's solutions. The feedback through h1 is what destabilises the middle state of a
bistable triple: raising the hair narrows the gap, raising the load, which bends it more, ...
In the linearisation it appears as a rank-one term added to a tridiagonal matrix.

Discretisation
--------------
N = ``num`` equal segments, nodes sigma_i = i / N, unknowns theta_1 .. theta_N (theta_0 = theta0 is
given); the second derivative by central differences, the free end by a ghost node
theta_{N+1} = theta_{N-1}, and h1 by the trapezoidal rule: second order throughout. This is
the operator of the finite-difference baseline (``hairbed.numerics._banded.HairOperator``, one
implementation for both). Its Jacobian is tridiagonal plus the rank-one coupling: Newton steps
take O(N); for the eigenvalues, at the moderate N used here, it is formed dense.

A static state is classified by the eigenvalues of this Jacobian at the discrete equilibrium
nearest the analytic state (a Newton step or two from the closed-form profile sampled on the
grid): stable when every eigenvalue has negative real part. Near a fold the critical eigenvalue
passes through zero, so within O(1/N^2) of a fold the classification is not reliable.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from ._core.solution import Solution
from ._core.validation import (
    MAX_GUESS_ANGLE,
    STATUS_MESSAGES,
    _check_range,
    as_float_array,
    check_choice,
    check_int,
    check_number,
    check_positive,
    check_scalar_inputs,
    status_messages,
)
from .numerics._banded import HairOperator
from .numerics._result import MAX_OMEGA2

__all__ = [
    "STATUS_MESSAGES",
    "Equilibrium",
    "Relaxation",
    "Stability",
    "equilibrium",
    "is_stable",
    "relax",
    "linear_stability",
]

FloatArray = NDArray[np.float64]


def _profiles(solution: Any, sigma: FloatArray, shape: tuple[int, ...]) -> FloatArray:
    """theta at the nodes for every state, shape S + (m,)."""
    try:
        out = np.asarray(solution.theta(sigma), dtype=np.float64)
        if out.shape == shape + sigma.shape:
            return out
    except ValueError:
        pass
    # Solution.theta broadcasting sigma against the solution's shape numpy-style: put sigma on
    # a leading axis and move it to the end.
    out = np.asarray(solution.theta(sigma.reshape(sigma.shape + (1,) * len(shape))))
    return np.moveaxis(out.astype(np.float64), 0, -1)


def _grid(n_seg: int) -> FloatArray:
    return np.linspace(0.0, 1.0, n_seg + 1)


@dataclass(frozen=True)
class Equilibrium:
    """A static state of the discretised problem (returned by :func:`equilibrium`).

    Attributes
    ----------
    sigma : ndarray (num + 1,)
        Arc length of the nodes [-].
    theta : ndarray (num + 1,)
        Angle at the nodes [rad] (the last iterate when ``success`` is False).
    success : bool
        Whether Newton's method converged.
    status : int
        0 converged; -2 iteration limit reached; -3 a non-finite Newton step (singular
        Jacobian) (:data:`STATUS_MESSAGES`).
    message : str
        Human-readable description of ``status``.
    nit : int
        Newton steps taken.
    nfev : int
        Evaluations of the residual (one per Newton step: it is also the step's right-hand
        side).
    """

    sigma: FloatArray
    theta: FloatArray
    success: bool
    status: int
    message: str
    nit: int
    nfev: int = 0


#: Newton's defaults in :func:`equilibrium` and the classification of :func:`linear_stability`.
_XTOL, _MAXITER = 1e-12, 50


def equilibrium(
    omega2: float,
    eps: float,
    theta0: float,
    guess: float | FloatArray | Callable[[FloatArray], Any],
    num: int = 100,
    *,
    xtol: float = _XTOL,
    maxiter: int = _MAXITER,
) -> Equilibrium:
    """The static state of the discretised problem nearest a guess (Newton's method).

    Parameters
    ----------
    omega2, eps, theta0 : float
        Forcing [-], confinement [-], base angle [rad].
    guess : float, array or callable
        theta at the num + 1 nodes sigma_i = i / num (the first is replaced by theta0), one
        angle for every node [rad], or a function of sigma such as ``Solution.theta``.
    num : int
        Number of segments, in [2, ``MAX_SEGMENTS`` = 10^6].
    xtol : float
        Convergence tolerance on the largest Newton update [rad].
    maxiter : int
        Newton iteration limit.

    Returns
    -------
    Equilibrium
        theta [rad] at the nodes, and how Newton's method ended (non-convergence is reported,
        not raised).

    Examples
    --------
    >>> import hairbed
    >>> state = hairbed.solve(2.0, 0.5)
    >>> eq = equilibrium(2.0, 0.5, 0.0, state.theta, num=200)
    >>> eq.success, eq.status, bool(abs(eq.theta[-1] - state.tip_angle) < 1e-4)
    (True, 0, True)
    """
    omega2, eps, theta0 = _scalars(omega2, eps, theta0)
    num = _check_num(num)
    xtol = check_positive(xtol, "xtol", "rad")
    maxiter = check_int(maxiter, "maxiter", 1, MAX_ITER)
    u = _initial(guess, num, "guess")[1:]
    return _equilibrium(HairOperator(omega2, eps, theta0, num), u, xtol, maxiter)


def _equilibrium(op: HairOperator, u: FloatArray, xtol: float, maxiter: int) -> Equilibrium:
    """:func:`equilibrium` of checked inputs (the discretisation ``op``, theta at the nodes
    after the base ``u``), trusted: the loop of :func:`linear_stability` calls this one."""
    num, theta0 = op.num, op.theta0
    status, message, nit = -2, f"iteration limit reached ({maxiter} Newton steps)", maxiter
    for it in range(1, int(maxiter) + 1):
        du = op.newton_step(u, op.residual(u))
        if not np.all(np.isfinite(du)):
            status, message, nit = -3, "singular Newton step (Jacobian not invertible)", it
            break
        u = u + du
        if np.max(np.abs(du)) < xtol:
            status, message, nit = 0, "converged: Newton step below tolerance", it
            break
    return Equilibrium(
        sigma=_grid(num),
        theta=np.concatenate(([theta0], u)),
        success=status == 0,
        status=status,
        message=message,
        nit=nit,
        nfev=nit,
    )


def _scalars(omega2: Any, eps: Any, theta0: Any) -> tuple[float, float, float]:
    return check_scalar_inputs(
        omega2,
        eps,
        theta0,
        omega2_max=MAX_OMEGA2,
        why=" (the discretised dynamics cannot resolve the base layer of width 1/omega beyond)",
    )


#: Largest grid (segments) of :func:`equilibrium` (banded: O(num) work).
MAX_SEGMENTS = 1_000_000
#: Largest grid of :func:`linear_stability` and :func:`relax` (dense Jacobians: O(num^2)
#: memory, O(num^3) eigenvalues).
MAX_DENSE_SEGMENTS = 4000
#: Largest Newton iteration limit.
MAX_ITER = 1_000_000


def _check_num(num: Any, high: int = MAX_SEGMENTS) -> int:
    return check_int(num, "num", 2, high)


def _initial(guess: Any, n_seg: int, name: str) -> FloatArray:
    """theta at the n_seg + 1 nodes from an array or a function of sigma (``name`` in errors)."""
    if callable(guess):
        values = as_float_array(guess(_grid(n_seg)), f"{name}(sigma)")
    else:
        values = as_float_array(guess, name)
    if values.ndim == 0:  # one angle for every node (a straight hair), as node_values takes
        _check_range(
            values,
            np.abs(values) > MAX_GUESS_ANGLE,
            name,
            f"[-{MAX_GUESS_ANGLE:g}, {MAX_GUESS_ANGLE:g}] [rad]",
        )
        return np.full(n_seg + 1, float(values))
    if values.shape != (n_seg + 1,):
        raise ValueError(
            f"{name} must give theta at the num + 1 = {n_seg + 1} nodes, got shape "
            f"{values.shape} (or one number [rad] for every node)"
        )
    return values.copy()


@dataclass(frozen=True)
class Stability:
    """Linear stability of static states (shapes follow the solution's shape S).

    Attributes
    ----------
    stable : ndarray of bool (S)
        Every eigenvalue has negative real part. False for states that do not exist (NaN).
    growth_rate : ndarray (S)
        Largest real part of the eigenvalues [1 / bending relaxation time]; NaN if no state.
    n_unstable : ndarray of int (S)
        Number of eigenvalues with positive real part (-1 if no state).
    eigenvalues : ndarray of complex (S + (k,))
        The k eigenvalues of largest real part, in decreasing order of real part.
    status : ndarray of int (S)
        How each classification ended: 0 classified; -1 no such state (the solution's
        values are NaN); -2 or -3 the discrete equilibrium near the state did not converge
        (iteration limit, singular step: values NaN, ``stable`` False; see
        ``STATUS_MESSAGES``).
    """

    stable: NDArray[np.bool_]
    growth_rate: FloatArray
    n_unstable: NDArray[np.intp]
    eigenvalues: NDArray[np.complex128]
    status: NDArray[np.intp]

    @property
    def success(self) -> bool | NDArray[np.bool_]:
        """True where the state was classified (status 0)."""
        ok = self.status == 0
        return bool(ok) if ok.ndim == 0 else ok

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, STATUS_MESSAGES)


def linear_stability(solution: Any, num: int = 100, k: int = 4) -> Stability:
    """Classify static states by the linearisation of the relaxation dynamics.

    Parameters
    ----------
    solution : Solution
        Static states (any shape; any branch, though states that twirl need larger num).
    num : int
        Number of segments of the discretisation, in [2, ``MAX_DENSE_SEGMENTS`` = 4000].
    k : int
        How many leading eigenvalues to return, in [1, num].

    Returns
    -------
    Stability

    Examples
    --------
    >>> import hairbed
    >>> states = [hairbed.solve(1.2, 0.9, -1.5, root=r) for r in ("low", "mid", "high")]
    >>> [bool(linear_stability(s).stable) for s in states]
    [True, False, True]
    """
    if not isinstance(solution, Solution):
        raise TypeError(
            "solution must be a hairbed.Solution (from hairbed.solve, from_parameter, ...), "
            f"got {type(solution).__name__}"
        )
    num = _check_num(num, MAX_DENSE_SEGMENTS)
    k = check_int(k, "k", 1, num)
    omega2 = np.asarray(solution.omega2, dtype=np.float64)
    shape = omega2.shape
    eps = np.broadcast_to(np.asarray(solution.eps, dtype=np.float64), shape)
    theta0 = np.broadcast_to(np.asarray(solution.theta0, dtype=np.float64), shape)
    profiles = _profiles(solution, _grid(num), shape)
    stable = np.zeros(shape, dtype=bool)
    growth = np.full(shape, np.nan)
    n_unstable = np.full(shape, -1, dtype=np.intp)
    eigs = np.full(shape + (k,), np.nan + 0j, dtype=np.complex128)
    status = np.full(shape, -1, dtype=np.intp)
    for idx in np.ndindex(shape):
        prof = profiles[idx]
        if not (np.isfinite(omega2[idx]) and np.all(np.isfinite(prof))):
            continue
        w, e, t0 = float(omega2[idx]), float(eps[idx]), float(theta0[idx])
        op = HairOperator(w, e, t0, num)
        eq = _equilibrium(op, np.array(prof[1:], dtype=np.float64), _XTOL, _MAXITER)
        if not eq.success:
            status[idx] = eq.status  # -2 or -3: the discrete equilibrium near it failed
            continue
        lam = np.linalg.eigvals(op.rhs_jacobian(eq.theta[1:]))
        lam = lam[np.argsort(-lam.real)]
        stable[idx] = bool(lam[0].real < 0.0)
        growth[idx] = lam[0].real
        n_unstable[idx] = int(np.count_nonzero(lam.real > 0.0))
        eigs[idx][: min(k, lam.size)] = lam[:k]
        status[idx] = 0
    return Stability(stable, growth, n_unstable, eigs, status)


def is_stable(solution: Any, num: int = 100) -> bool | NDArray[np.bool_]:
    """Whether each static state is linearly stable under the relaxation dynamics.

    See the module docstring for the model. Returns a bool (scalar solution) or a bool array of
    the solution's shape; False for states that do not exist.

    Examples
    --------
    >>> import hairbed
    >>> bool(is_stable(hairbed.solve(2.0, 0.5)))
    True
    """
    stable = linear_stability(solution, num=num, k=1).stable
    return bool(stable) if stable.ndim == 0 else stable


@dataclass(frozen=True)
class Relaxation:
    """A time-stepped run of the relaxation dynamics.

    Attributes
    ----------
    t : ndarray (m,)
        Times [bending relaxation times].
    sigma : ndarray (num + 1,)
        Arc length of the nodes [-].
    theta : ndarray (m, num + 1)
        Angle at the nodes at each time [rad].
    tip_height, tip_deflection : ndarray (m,)
        h1 and x1 (trapezoidal rule) at each time [-].
    success : bool
        Whether the integrator reached the end.
    status : int
        0 reached ``t_end``; -3 an integration step failed (:data:`STATUS_MESSAGES`).
    message : str
        The integrator's message.
    solver_status : int
        :func:`scipy.integrate.solve_ivp`'s own status (0 reached the end, -1 a step failed).
    nfev : int
        Evaluations of the right-hand side.
    """

    t: FloatArray
    sigma: FloatArray
    theta: FloatArray
    tip_height: FloatArray
    tip_deflection: FloatArray
    success: bool
    status: int
    message: str
    solver_status: int = 0
    nfev: int = 0


_STIFF_METHODS = ("BDF", "Radau", "LSODA")
#: The integrator's tolerances: solve_ivp raises rtol to 100 machine epsilons anyway, and an
#: atol below ~1e-300 overflows in its error norm.
_RTOL_MIN = 100.0 * float(np.finfo(np.float64).eps)
_ATOL_MIN = 1e-30


def _trapezoid(values: FloatArray) -> FloatArray:
    n_seg = values.shape[-1] - 1
    return (values.sum(axis=-1) - 0.5 * (values[..., 0] + values[..., -1])) / n_seg


def relax(
    omega2: float,
    eps: float,
    theta0: float,
    theta_initial: float | FloatArray | Callable[[FloatArray], Any],
    t_end: float,
    *,
    num: int = 100,
    t_eval: FloatArray | None = None,
    method: str = "BDF",
    rtol: float = 1e-8,
    atol: float = 1e-10,
) -> Relaxation:
    """Integrate the relaxation dynamics (module docstring) from an initial shape.

    Parameters
    ----------
    omega2, eps, theta0 : float
        Forcing [-], confinement [-], base angle [rad].
    theta_initial : float, array or callable
        theta at the num + 1 nodes sigma_i = i / num (the first is replaced by theta0), one
        angle for every node [rad] (a straight hair), or a function of sigma such as
        ``Solution.theta``.
    t_end : float
        Final time [bending relaxation times].
    num : int
        Number of segments, in [2, ``MAX_DENSE_SEGMENTS`` = 4000].
    t_eval : array, optional
        Output times; default: the integrator's own steps.
    method : str
        A stiff method of :func:`scipy.integrate.solve_ivp` ("BDF", "Radau" or "LSODA").
    rtol, atol : float
        Integrator tolerances: rtol in [2.2e-14, 1), atol >= 1e-30 [rad].

    Returns
    -------
    Relaxation

    Examples
    --------
    >>> run = relax(2.0, 0.5, 0.0, lambda s: 0.0 * s, 20.0, num=40)
    >>> round(float(run.tip_height[-1]), 3)
    0.733
    """
    omega2, eps, theta0 = _scalars(omega2, eps, theta0)
    t_end = check_positive(t_end, "t_end")
    num = _check_num(num, MAX_DENSE_SEGMENTS)
    method = check_choice(method, "method", _STIFF_METHODS)
    rtol = check_number(rtol, "rtol", low=_RTOL_MIN, high=1.0, high_open=True)
    atol = check_number(atol, "atol", low=_ATOL_MIN, unit="rad")
    if t_eval is not None:
        t_eval = as_float_array(t_eval, "t_eval")
        if t_eval.ndim != 1 or t_eval.size == 0:
            raise ValueError(f"t_eval must be a non-empty 1-D array, got shape {t_eval.shape}")
        bad = (t_eval < 0.0) | (t_eval > t_end)
        bad[1:] |= np.diff(t_eval) < 0.0
        if np.any(bad):
            i = int(np.argmax(bad))
            raise ValueError(
                f"t_eval must be increasing times in [0, t_end] = [0, {t_end!r}], got "
                f"{float(t_eval[i])!r} (first at index {i})"
            )
    u0 = _initial(theta_initial, num, "theta_initial")[1:]
    op = HairOperator(omega2, eps, theta0, num)
    res = solve_ivp(
        lambda _t, u: op.rhs(u),
        (0.0, float(t_end)),
        u0,
        method=method,
        jac=lambda _t, u: op.rhs_jacobian(u),
        t_eval=t_eval,
        rtol=rtol,
        atol=atol,
    )
    theta = np.concatenate((np.full((1, res.t.size), theta0), res.y), axis=0).T
    return Relaxation(
        t=res.t,
        sigma=_grid(num),
        theta=theta,
        tip_height=_trapezoid(np.cos(theta)),
        tip_deflection=_trapezoid(np.sin(theta)),
        success=bool(res.success),
        status=0 if res.status == 0 else -3,
        message=str(res.message),
        solver_status=int(res.status),
        nfev=int(res.nfev),
    )
