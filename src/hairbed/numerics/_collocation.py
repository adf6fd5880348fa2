"""Collocation with ``scipy.integrate.solve_bvp``, the tip height as an unknown parameter."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_bvp

from .._core.validation import check_int, check_number, node_values
from .._warnings import renamed_parameters
from ._result import NumericalResult, branch_label, scalar_inputs

__all__ = ["collocation"]

FloatArray = NDArray[np.float64]

#: The smallest tolerance: solve_bvp raises any below to 100 machine epsilons (with a warning).
_TOL_MIN = 100.0 * float(np.finfo(np.float64).eps)
#: Largest mesh (and output grid) of :func:`collocation`.
MAX_NODES = 1_000_000
_GUESS_TIP_FRACTION = 0.9  # of the way from theta0 to pi/2, at strong forcing


def _default_guess(omega2: float, theta0: float) -> Callable[[FloatArray], FloatArray]:
    """A monotone start with the base boundary layer of width 1/omega (theory.md §4).

    theta rises from theta0 like 1 - exp(-omega sigma) to a tip angle that approaches pi/2 as
    the forcing grows. From theta = const (the paper's finite-difference start), solve_bvp
    fails (mesh refinement runs away) or lands on a twirling branch from about omega^2 = 3
    to 30 on, depending on theta0 and eps; from this start it found the physical branch at
    every point of a sweep omega^2 = 0.01..1e4, theta0 = -1.5..1.5, eps = 0..0.9.
    """
    k = max(np.sqrt(omega2), 1e-3)
    tip = theta0 + _GUESS_TIP_FRACTION * (0.5 * np.pi - theta0) * np.tanh(omega2)
    return lambda s: theta0 + (tip - theta0) * (-np.expm1(-k * s)) / (-np.expm1(-k))


def _system(omega2: float, eps: float) -> Callable[..., FloatArray]:
    def fun(_s: FloatArray, y: FloatArray, p: FloatArray) -> FloatArray:
        W = omega2 / (1.0 - eps * p[0])
        c, s = np.cos(y[0]), np.sin(y[0])
        return np.vstack([y[1], -W * c, c, s])

    return fun


def _jacobian(omega2: float, eps: float) -> Callable[..., tuple[FloatArray, FloatArray]]:
    def fun_jac(_s: FloatArray, y: FloatArray, p: FloatArray) -> tuple[FloatArray, FloatArray]:
        one_m = 1.0 - eps * p[0]
        W = omega2 / one_m
        c, s = np.cos(y[0]), np.sin(y[0])
        m = y.shape[1]
        dfdy = np.zeros((4, 4, m))
        dfdy[0, 1] = 1.0
        dfdy[1, 0] = W * s
        dfdy[2, 0] = -s
        dfdy[3, 0] = c
        dfdp = np.zeros((4, 1, m))
        dfdp[1, 0] = -(W * eps / one_m) * c  # d(-W cos)/dh1, with dW/dh1 = eps W / (1 - eps h1)
        return dfdy, dfdp

    return fun_jac


def _bc_jacobian(
    _ya: FloatArray, _yb: FloatArray, _p: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    dya = np.zeros((5, 4))
    dyb = np.zeros((5, 4))
    dp = np.zeros((5, 1))
    dya[0, 0] = dya[1, 2] = dya[2, 3] = 1.0
    dyb[3, 1] = dyb[4, 2] = 1.0
    dp[4, 0] = -1.0
    return dya, dyb, dp


#: solve_bvp's status in the one convention (:data:`hairbed._core.validation.STATUS_MESSAGES`).
_BVP_STATUS = {0: 0, 1: -2, 2: -3, 3: -2}


@renamed_parameters(tol="rtol", nodes="num_nodes")
def collocation(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    rtol: float = 1e-8,
    guess: float | Callable[[FloatArray], Any] | None = None,
    num_nodes: int = 21,
    max_nodes: int = 20_000,
    num: int = 201,
) -> NumericalResult:
    """Solve the hair problem by collocation (``scipy.integrate.solve_bvp``).

    The state is (theta, theta', z, x) with z' = cos(theta), x' = sin(theta) and
    theta'' = -omega_eps^2 cos(theta) (eq. (3)); the tip height h1 is an unknown parameter,
    so omega_eps^2 = omega^2 / (1 - eps h1) (eq. (5)) is a constant of the system. Five
    boundary conditions fix four components and the parameter: theta(0) = theta0, z(0) = 0,
    x(0) = 0, theta'(1) = 0 and z(1) = h1. ``solve_bvp`` (fourth-order collocation, Lobatto
    IIIA) refines its mesh until the relative residual is below ``rtol``; the exact Jacobians
    of the system and the boundary conditions are supplied.

    Parameters
    ----------
    omega2 : float
        Forcing omega^2 [-], >= 0. Scalars only (one state per call).
    eps : float
        Confinement eps = L/H [-], in [0, 1).
    theta0 : float, optional
        Base angle [rad], in (-pi/2, pi/2).
    rtol : float, optional
        ``solve_bvp`` tolerance on the relative collocation residual, in [2.2e-14, 1]; tip
        values are then accurate to about this (``tol`` is its deprecated old name).
    guess : float or callable, optional
        Starting theta [rad] at the initial nodes, or a function of sigma giving it. Default: a
        monotone rise from theta0 with a base boundary layer of width 1/omega (see
        ``_default_guess``; from theta = const solve_bvp fails or twirls at strong forcing). The
        starting theta' is its finite-difference slope, z and x its quadratures and h1 = z(1).
        Twirling guesses can reach non-physical branches; ``sign`` and ``n`` say which.
    num_nodes : int, optional
        Number of equally spaced initial mesh nodes, in [3, max_nodes] (``nodes`` is its
        deprecated old name).
    max_nodes : int, optional
        Mesh size limit passed to ``solve_bvp``, in [3, ``MAX_NODES`` = 10^6].
    num : int, optional
        Number of equally spaced output nodes (from the C1 cubic interpolant), in
        [3, 10^6].

    Returns
    -------
    NumericalResult
        ``nit`` is ``solve_bvp``'s number of mesh refinements and ``nfev`` the evaluations
        of the right-hand side; ``status`` 0 converged, -2 a limit reached (solve_bvp's 1, the
        node limit, or its 3, the boundary conditions' tolerance not met after its
        iterations), -3 a singular Jacobian (its 2); ``solver_status`` is solve_bvp's own.

    Raises
    ------
    ValueError
        If an input is out of range or not a scalar.

    Examples
    --------
    >>> from hairbed.numerics._collocation import collocation
    >>> res = collocation(2.0, 0.5)
    >>> res.success, res.sign, res.n
    (True, 1, 0)
    >>> round(res.tip_height, 8)  # analytic 0.732706963462228
    0.73270696
    """
    omega2, eps, theta0 = scalar_inputs(omega2, eps, theta0)
    rtol = check_number(rtol, "rtol", low=_TOL_MIN, high=1.0)
    max_nodes = check_int(max_nodes, "max_nodes", 3, MAX_NODES)
    num_nodes = check_int(num_nodes, "num_nodes", 3, MAX_NODES)
    if num_nodes > max_nodes:
        raise ValueError(f"num_nodes must not exceed max_nodes = {max_nodes}, got {num_nodes}")
    num = check_int(num, "num", 3, MAX_NODES)

    def bc(ya: FloatArray, yb: FloatArray, p: FloatArray) -> FloatArray:
        return np.array([ya[0] - theta0, ya[2], ya[3], yb[1], yb[2] - p[0]])

    mesh = np.linspace(0.0, 1.0, num_nodes)
    if guess is None:
        guess = _default_guess(omega2, theta0)
    th = node_values(guess, "guess", mesh)
    # A consistent starting state: slope and quadratures of the guessed angle.
    th[0] = theta0
    dth = np.gradient(th, mesh)
    step = np.diff(mesh)
    z = np.concatenate([[0.0], np.cumsum(0.5 * step * (np.cos(th[1:]) + np.cos(th[:-1])))])
    x = np.concatenate([[0.0], np.cumsum(0.5 * step * (np.sin(th[1:]) + np.sin(th[:-1])))])

    system = _system(omega2, eps)
    calls = [0]

    def counted(s: FloatArray, y: FloatArray, p: FloatArray) -> FloatArray:
        calls[0] += 1
        return system(s, y, p)

    sol = solve_bvp(
        counted,
        bc,
        mesh,
        np.vstack([th, dth, z, x]),
        p=np.array([z[-1]]),
        fun_jac=_jacobian(omega2, eps),
        bc_jac=_bc_jacobian,
        tol=rtol,
        max_nodes=int(max_nodes),
    )

    h1 = float(sol.p[0])
    W = omega2 / (1.0 - eps * h1)
    sigma = np.linspace(0.0, 1.0, int(num))
    y = sol.sol(sigma)
    # The turning points are read off theta' at the solver's own (adapted) mesh as well as the
    # output nodes, so that a sharp twirl is not missed.
    s_all = np.union1d(sol.x, sigma)
    dtheta_all = sol.sol(s_all)[1]
    sign, n = branch_label(dtheta_all[:-1], float(sol.y[1, 0]))
    text = " ".join(str(sol.message).split())
    return NumericalResult(
        success=bool(sol.success),
        status=_BVP_STATUS[int(sol.status)],
        message=f"solve_bvp: {text} ({sol.x.size} nodes)",
        nit=int(sol.niter),
        method="collocation",
        omega2=omega2,
        eps=eps,
        theta0=theta0,
        sigma=sigma,
        theta=y[0],
        x=y[3],
        z=y[2],
        tip_height=h1,
        tip_deflection=float(sol.y[3, -1]),
        xi=float(np.sin(sol.y[0, -1])),
        omega_eps=float(np.sqrt(W)),
        base_curvature=float(sol.y[1, 0]),
        sign=sign,
        n=n,
        nfev=calls[0],
        solver_status=int(sol.status),
    )
