"""The paper's finite-difference baseline (theory.md §8), with an O(N) Newton solver."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import optimize

from .._core.validation import check_choice, check_int, check_positive, node_values
from ._banded import HairOperator
from ._result import NumericalResult, branch_label, scalar_inputs

__all__ = ["finite_difference"]

FloatArray = NDArray[np.float64]

_METHODS = ("newton", "root")
#: Largest grid (segments) and iteration limit of :func:`finite_difference`.
MAX_SEGMENTS = 1_000_000
MAX_ITER = 1_000_000
_MAX_STEP = 1.0  # [rad], largest Newton update of any theta_i


def _initial_guess(guess: float | Callable[[FloatArray], Any], sigma: FloatArray) -> FloatArray:
    return node_values(guess, "guess", sigma)


def _newton(
    disc: HairOperator, th: FloatArray, xtol: float, maxiter: int
) -> tuple[FloatArray, int, str, int, int]:
    """Damped Newton on the residual, backtracking on ||r||^2. Returns theta, status, msg, it,
    nfev."""
    r = disc.residual(th)
    nfev = 1
    f = float(r @ r)
    for it in range(1, maxiter + 1):
        dx = disc.newton_step(th, r)
        if not np.all(np.isfinite(dx)):
            return th, -3, "singular Newton step (Jacobian not invertible)", it, nfev
        size = float(np.max(np.abs(dx)))
        # Cap the step at _MAX_STEP rad: the linearisation of cos(theta) means nothing over
        # larger changes, and uncapped first steps from theta = 0 at strong forcing land on
        # twirling shapes where the line search stalls.
        lam = min(1.0, _MAX_STEP / size) if size > 0 else 1.0
        while True:
            trial = th + lam * dx
            r_new = disc.residual(trial)
            nfev += 1
            f_new = float(r_new @ r_new)
            # Armijo condition for the merit function ||r||^2 (its slope along dx is -2 f).
            if f_new <= (1.0 - 1e-4 * lam) * f or lam < 1e-10:
                break
            lam *= 0.5
        th, r, f_prev, f = trial, r_new, f, f_new
        step = lam * size
        if step <= xtol * (1.0 + float(np.max(np.abs(th)))):
            return th, 0, "converged: Newton step below tolerance", it, nfev
        if lam < 1e-10 and f >= f_prev:
            return th, -3, "line search failed: no descent direction (stalled)", it, nfev
    return th, -2, f"iteration limit reached ({maxiter} Newton steps)", maxiter, nfev


def finite_difference(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    num: int = 80,
    guess: float | Callable[[FloatArray], Any] = 0.0,
    method: str = "newton",
    xtol: float = 1e-12,
    maxiter: int = 100,
) -> NumericalResult:
    """Solve the hair problem by the paper's central-difference scheme.

    Discretises theta'' = -omega_eps^2 cos(theta) (eq. (3)) on N = ``num`` equal segments with
    central differences; theta(0) = theta0 enters the first equation, theta'(1) = 0 the last
    (through a ghost node, second order); the tip height h1 is the trapezoid sum of cos(theta),
    and omega_eps^2 = omega^2 / (1 - eps h1) (eq. (5)) couples every unknown. The scheme is
    second order: errors fall as N^-2 (theory.md §8).

    Parameters
    ----------
    omega2 : float
        Forcing omega^2 [-], >= 0. Scalars only (one state per call).
    eps : float
        Confinement eps = L/H [-], in [0, 1).
    theta0 : float, optional
        Base angle [rad], in (-pi/2, pi/2).
    num : int, optional
        Number of segments N (N unknowns theta_1..theta_N), in [2, ``MAX_SEGMENTS`` = 10^6]
        (``"root"``, with its dense Jacobian, is only practical for a few hundred).
    guess : float or callable, optional
        Starting value of theta [rad] at every node, or a function of sigma giving it
        (vectorised). The default 0 is the paper's. A twirling guess such as
        ``lambda s: -3 * np.pi * s`` can lead to a non-physical branch; ``sign`` and ``n`` of
        the result say which one.
    method : {"newton", "root"}, optional
        ``"newton"``: damped Newton with the exact Jacobian, tridiagonal plus the rank-one
        coupling of the integral, solved in O(N) per step (banded solve and Sherman-Morrison).
        ``"root"``: the same residual handed to ``scipy.optimize.root`` (MINPACK hybrid method
        with a finite-difference Jacobian), as the paper did.
    xtol : float, optional
        Convergence tolerance on the step (``"newton"``) or ``xtol`` of ``scipy.optimize.root``
        (``"root"``) [rad].
    maxiter : int, optional
        Newton iteration limit (``"newton"`` only), in [1, 10^6].

    Returns
    -------
    NumericalResult
        Non-convergence is reported in ``success``/``status``/``message``, not raised.

    Raises
    ------
    ValueError
        If an input is out of range or not a scalar, ``num < 2``, or ``method`` is unknown.

    Examples
    --------
    >>> from hairbed.numerics import finite_difference
    >>> res = finite_difference(2.0, 0.5, num=400)
    >>> res.success, res.sign, res.n
    (True, 1, 0)
    >>> round(res.tip_height, 5)  # analytic 0.732706963462228
    0.73271
    """
    omega2, eps, theta0 = scalar_inputs(omega2, eps, theta0)
    num = check_int(num, "num", 2, MAX_SEGMENTS)
    method = check_choice(method, "method", _METHODS)
    xtol = check_positive(xtol, "xtol", "rad")
    maxiter = check_int(maxiter, "maxiter", 1, MAX_ITER)
    disc = HairOperator(omega2, eps, theta0, num)
    sigma = np.linspace(0.0, 1.0, num + 1)
    th0 = _initial_guess(guess, sigma[1:])

    if method == "newton":
        th, status, message, iterations, nfev = _newton(disc, th0, xtol, int(maxiter))
        solver_status = None
    else:
        sol = optimize.root(disc.residual, th0, method="hybr", options={"xtol": xtol})
        th = sol.x
        nfev = int(sol.nfev)
        iterations = nfev  # hybr reports no iteration count; its work is counted in calls
        # hybr's own flag can be True at a point where the residual is not small; check it.
        res_norm = float(np.max(np.abs(disc.residual(th))))
        ok = bool(sol.success) and res_norm < 1e-8
        solver_status = int(sol.status)
        status = 0 if ok else (-2 if sol.status == 2 else -3)
        text = " ".join(str(sol.message).split())
        message = f"scipy.optimize.root (hybr): {text} (max |residual| {res_norm:.2e})"

    return _result(
        disc,
        sigma,
        th,
        status,
        message,
        iterations,
        nfev,
        f"finite_difference/{method}",
        solver_status,
    )


def _result(
    disc: HairOperator,
    sigma: FloatArray,
    th: FloatArray,
    status: int,
    message: str,
    iterations: int,
    nfev: int,
    method: str,
    solver_status: int | None = None,
) -> NumericalResult:
    h = disc.h
    theta = np.concatenate([[disc.theta0], th])
    h1 = disc.tip_height(th)
    W = disc.omega_eps2(h1)
    # Cumulative trapezoid sums for the centreline: z' = cos(theta), x' = sin(theta).
    z = np.concatenate([[0.0], np.cumsum(0.5 * h * (np.cos(theta[1:]) + np.cos(theta[:-1])))])
    x = np.concatenate([[0.0], np.cumsum(0.5 * h * (np.sin(theta[1:]) + np.sin(theta[:-1])))])
    # Summing all rows of the scheme gives the discrete form of theta'(0) = omega_eps^2 h1
    # eq. (29): (theta_1 - theta_0)/h + (h/2) W cos(theta0) = W h1, second order like the rest.
    base_curvature = (theta[1] - theta[0]) / h + 0.5 * h * W * np.cos(disc.theta0)
    sign, n = branch_label(np.diff(theta), base_curvature)
    return NumericalResult(
        success=status == 0,
        status=status,
        message=message,
        nit=iterations,
        method=method,
        omega2=disc.omega2,
        eps=disc.eps,
        theta0=disc.theta0,
        sigma=sigma,
        theta=theta,
        x=x,
        z=z,
        tip_height=float(h1),
        tip_deflection=float(x[-1]),
        xi=float(np.sin(theta[-1])),
        omega_eps=float(np.sqrt(W)),
        base_curvature=float(base_curvature),
        sign=sign,
        n=n,
        nfev=nfev,
        solver_status=solver_status,
    )
