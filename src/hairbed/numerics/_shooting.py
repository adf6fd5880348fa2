"""Shooting on the base curvature (the approach of Alvarado et al. 2017), with honest failure."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from .._bracketing import find_root
from .._core.validation import check_int, check_number, check_positive
from .._warnings import renamed_parameters
from ._result import NumericalResult, branch_label, scalar_inputs

__all__ = ["shooting"]

FloatArray = NDArray[np.float64]

_RTOL = 1e-12  # solve_ivp tolerances: near the limit of DOP853 in double precision
_ATOL = 1e-13
_MACHEPS = float(np.finfo(np.float64).eps)
#: Strongest forcing and largest starting base curvature of :func:`shooting` (at omega2 = 1e4
#: the physical root is already within rounding of the separatrix: status -3).
MAX_OMEGA2 = 1e4
MAX_CURVATURE = 1e3
#: Largest output grid and Newton iteration limit of :func:`shooting`.
MAX_POINTS = 1_000_000
MAX_ITER = 1_000_000
#: Status 3 when 1 - xi (the distance of the tip angle from pi/2) is resolved worse than this.
_GAP_RTOL = 1e-3
#: Status 3 when the integrated tip height and the identity (eq. (29)) disagree by more.
_CONSISTENCY_TOL = 1e-6


def _rhs(omega2: float, eps: float, c: float) -> Callable[[float, FloatArray], FloatArray]:
    """Right-hand side for theta, theta', z, x and the sensitivities d/dc of theta, theta'.

    omega_eps^2 = omega^2 + eps * theta'(0): integrating theta'' = -W cos(theta) over the hair
    gives theta'(1) - theta'(0) = -W h1 (eq. (29)), so once theta'(1) = 0 this is the same as
    W = omega^2 / (1 - eps h1) (eq. (5)). Shooting is then a scalar problem in theta'(0).
    """
    W = omega2 + eps * c

    def f(_s: float, y: FloatArray) -> FloatArray:
        th, dth, _z, _x, a, da = y
        c_, s_ = np.cos(th), np.sin(th)
        # a = d theta / dc obeys the variational equation, with dW/dc = eps.
        return np.array([dth, -W * c_, c_, s_, da, W * s_ * a - eps * c_])

    return f


class _Shooter:
    """Integrates the initial value problem from the base and counts the work."""

    def __init__(self, omega2: float, eps: float, theta0: float) -> None:
        self.omega2, self.eps, self.theta0 = omega2, eps, theta0
        self.nfev = 0
        self.nivp = 0

    def integrate(self, c: float, t_eval: FloatArray | None = None) -> Any:
        y0 = np.array([self.theta0, c, 0.0, 0.0, 0.0, 1.0])
        sol = solve_ivp(
            _rhs(self.omega2, self.eps, c),
            (0.0, 1.0),
            y0,
            method="DOP853",
            rtol=_RTOL,
            atol=_ATOL,
            t_eval=t_eval,
        )
        self.nfev += sol.nfev
        self.nivp += 1
        return sol

    def residual(self, c: float) -> float:
        """theta'(1) for base curvature c (NaN if the integration fails)."""
        sol = self.integrate(c)
        return float(sol.y[1, -1]) if sol.success else float("nan")


def _separatrix_bounds(omega2: float, eps: float, theta0: float) -> tuple[float, float]:
    """Interval of theta'(0) from which the orbit can reach a turning point (theta' = 0).

    The energy, eq. (7), is conserved: c^2/2 + W sin(theta0) = W sin(theta1) <= W at a turning
    point, with W = omega^2 + eps c. So every solution, on every branch, has
    c^2 <= 2 (omega^2 + eps c)(1 - sin theta0): c between the two roots of that quadratic.
    Outside it the hair rotates over the top (theta' never vanishes).
    """
    q = 1.0 - np.sin(theta0)
    a = eps * q
    root = np.sqrt(a * a + 2.0 * omega2 * q)
    return float(a - root), float(a + root)


def _bracket_physical(shooter: _Shooter, c_hi: float) -> tuple[float, float, float, float] | None:
    """Bracket the largest root of theta'(1)(c) below the upper separatrix bound c_hi.

    That root is the physical one: just below c_hi the hair creeps towards theta = pi/2 and has
    not turned by the tip (theta'(1) > 0); at the physical c it turns exactly at the tip; below
    it turns inside (theta'(1) < 0) until the next, twirling (n = 1), root. The distance of the
    physical c from c_hi shrinks like 1 - xi ~ exp(-2 omega_eps) (theory.md §4), so step
    down from c_hi geometrically, from rounding level upwards.
    """
    delta = 8.0 * _MACHEPS
    c_up: float | None = None
    r_up = 0.0
    while True:
        c = c_hi * (1.0 - delta)
        r = shooter.residual(c)
        if not np.isfinite(r):
            return None
        if r < 0.0:
            if c_up is None:
                return None  # even the closest representable start has turned: unresolvable
            return c, r, c_up, r_up
        c_up, r_up = c, r
        if delta == 1.0:
            return None  # theta'(1) > 0 all the way down to c = 0: no physical root
        delta = min(4.0 * delta, 1.0)


def _newton(
    shooter: _Shooter, c: float, c_lo: float, c_hi: float, tol: float, maxiter: int
) -> tuple[float, int, str, int]:
    """Newton on theta'(1)(c) = 0 with the variational derivative, kept inside the separatrix
    bounds and backtracking while |theta'(1)| does not decrease."""
    sol = shooter.integrate(c)
    for it in range(1, maxiter + 1):
        if not sol.success or not np.all(np.isfinite(sol.y[:, -1])):
            return c, -3, f"integrator failed: {sol.message}", it
        r, sens = float(sol.y[1, -1]), float(sol.y[5, -1])
        if abs(r) <= tol * max(1.0, abs(c)):
            return c, 0, f"converged (d theta'(1)/d theta'(0) = {sens:.3e})", it - 1
        if sens == 0.0:
            return c, -3, "zero sensitivity d theta'(1)/d theta'(0)", it
        dc = -r / sens
        # No solution lies beyond the separatrix bounds; orbits past them rotate.
        if c + dc >= c_hi:
            dc = 0.5 * (c_hi - c)
        elif c + dc <= c_lo:
            dc = 0.5 * (c_lo - c)
        lam = 1.0
        while True:
            trial = shooter.integrate(c + lam * dc)
            if trial.success and abs(trial.y[1, -1]) < abs(r):
                break
            lam *= 0.5
            if lam < 1e-8:
                return (
                    c,
                    2,
                    f"stalled: no step reduces |theta'(1)| = {abs(r):.3e} "
                    f"(d theta'(1)/d theta'(0) = {sens:.3e})",
                    it,
                )
        c, sol = c + lam * dc, trial
    return c, -2, f"iteration limit reached ({maxiter} Newton steps)", maxiter


@renamed_parameters(base_curvature="guess", tol="rtol")
def shooting(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    guess: float | None = None,
    rtol: float = 1e-10,
    maxiter: int = 50,
    num: int = 201,
) -> NumericalResult:
    """Solve the hair problem by shooting on the base curvature theta'(0).

    Integrates theta'' = -omega_eps^2 cos(theta) (eq. (3)), z' = cos(theta),
    x' = sin(theta) from the base with ``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-12),
    taking omega_eps^2 = omega^2 + eps theta'(0), which is the self-consistency
    of eq. (5) once theta'(1) = 0 (integrating eq. (3) once gives
    theta'(0) = omega_eps^2 h1, eq. (29)). The base curvature is adjusted until
    theta'(1) = 0:

    * ``guess=None``: the physical root, bracketed as the largest root below the
      separatrix (beyond which the hair rotates over the top), then the package's bracketed
      root search (``scipy.optimize.elementwise.find_root``, Chandrupatla's method).
    * a number: Newton's method from there, with the derivative from the variational
      equations. It may reach a twirling branch; ``sign`` and ``n`` say which.

    The problem is exponentially ill-conditioned at strong forcing: the physical theta'(0) lies
    within a relative distance ~ 1 - xi ~ 32 exp(-2 omega_eps) of the separatrix, and
    d theta'(1) / d theta'(0) grows like exp(omega_eps). Once that distance nears the
    integrator's tolerance the tip angle is not resolved (``status`` 3, with the estimate in
    ``message``); once it falls below rounding (omega_eps above about 18) no double-precision
    theta'(0) turns at the tip and the solve fails (``status`` -3).

    Parameters
    ----------
    omega2 : float
        Forcing omega^2 [-], in [0, ``MAX_OMEGA2`` = 10^4]. Scalars only (one state per call).
    eps : float
        Confinement eps = L/H [-], in [0, 1).
    theta0 : float, optional
        Base angle [rad], in (-pi/2, pi/2).
    guess : float, optional
        Starting value of the base curvature theta'(0) [-] for Newton's method, in
        [-1000, 1000] (a hair twirling ~10 times; beyond, each integration takes minutes);
        default: bracket the physical root. ``base_curvature`` is its deprecated old name.
    rtol : float, optional
        Newton convergence tolerance on abs(theta'(1)) relative to max(1, abs(theta'(0)))
        (``tol`` is its deprecated old name).
    maxiter : int, optional
        Newton iteration limit, in [1, 10^6].
    num : int, optional
        Number of equally spaced output nodes, in [3, 10^6].

    Returns
    -------
    NumericalResult
        ``nit`` counts Newton steps, or initial value problems solved when bracketing;
        ``nfev`` the evaluations of the right-hand side over every integration.

    Raises
    ------
    ValueError
        If an input is out of range or not a scalar, or ``guess`` is not finite.

    Examples
    --------
    >>> from hairbed.numerics import shooting
    >>> res = shooting(2.0, 0.5)
    >>> res.success, res.sign, res.n
    (True, 1, 0)
    >>> round(res.tip_height, 9)  # analytic 0.732706963462228
    0.732706963
    """
    omega2, eps, theta0 = scalar_inputs(omega2, eps, theta0)
    if omega2 > MAX_OMEGA2:
        raise ValueError(
            f"omega2 must lie in [0, {MAX_OMEGA2:g}] for shooting (beyond, no double-precision "
            f"theta'(0) turns at the tip; hairbed.solve is exact at any forcing), got {omega2!r}"
        )
    num = check_int(num, "num", 3, MAX_POINTS)
    if guess is not None:
        guess = check_number(guess, "guess", low=-MAX_CURVATURE, high=MAX_CURVATURE)
    rtol = check_positive(rtol, "rtol")
    maxiter = check_int(maxiter, "maxiter", 1, MAX_ITER)
    shooter = _Shooter(omega2, eps, theta0)
    c_lo, c_hi = _separatrix_bounds(omega2, eps, theta0)

    if omega2 == 0.0 and guess is None:
        c, status, message, iterations = 0.0, 0, "converged: no forcing, straight hair", 0
    elif guess is not None:
        c, status, message, iterations = _newton(
            shooter, float(guess), c_lo, c_hi, rtol, int(maxiter)
        )
    else:
        bracket = _bracket_physical(shooter, c_hi)
        if bracket is None:
            c = c_hi * (1.0 - 8.0 * _MACHEPS)
            status = -3
            message = (
                "no bracket: the physical theta'(0) is within rounding of the separatrix "
                f"bound {c_hi:.17g} (exponential ill-conditioning at strong forcing)"
            )
        else:
            a, _, b, _ = bracket
            try:
                c = float(
                    find_root(
                        np.vectorize(shooter.residual, otypes=[np.float64]),
                        a,
                        b,
                        xatol=4 * _MACHEPS * abs(b),
                        xrtol=4 * _MACHEPS,
                        what="the physical base curvature",
                    ).x
                )
                status, message = 0, "converged: bracketed the physical root (find_root)"
            except FloatingPointError as exc:  # NaN from a failed integration
                c, status, message = 0.5 * (a + b), -3, f"root search failed: {exc}"
            gap = (c_hi - c) / c_hi
            # The relative error of c is about the integrator tolerance; the tip angle depends
            # on c only through this gap (1 - xi is proportional to it).
            if status == 0 and _RTOL / gap > _GAP_RTOL:
                status = 3
                message = (
                    f"converged, but ill-conditioned: theta'(0) is {gap:.1e} (relative) below "
                    f"the separatrix, so the integrator tolerance {_RTOL:.0e} resolves 1 - xi "
                    f"only to ~{_RTOL / gap:.0e} relative"
                )
        iterations = shooter.nivp

    sigma = np.linspace(0.0, 1.0, int(num))
    final = shooter.integrate(c, t_eval=sigma)
    if final.success and final.y.shape[1] == sigma.size:
        theta, dtheta, z, x = final.y[0], final.y[1], final.y[2], final.y[3]
    else:  # the integration broke down: report what there is, padded with NaN
        status = -3
        message += f"; final integration failed: {final.message}"
        pad = np.full((6, sigma.size), np.nan)
        pad[:, : final.y.shape[1]] = final.y
        theta, dtheta, z, x = pad[0], pad[1], pad[2], pad[3]
    W = omega2 + eps * c
    if status in (0, 3) and abs(dtheta[-1]) > 1e-6 * max(1.0, abs(c)):
        status = -3
        message += f"; but |theta'(1)| = {abs(dtheta[-1]):.1e}: the boundary condition fails"
    # theta'(0) = omega_eps^2 h1 (eq. (29)) holds for the exact shape; the integrated z(1)
    # departs from it when the initial value problem amplifies integration error.
    mismatch = abs(z[-1] - c / W) if W > 0 else 0.0
    if status == 0 and mismatch > _CONSISTENCY_TOL:
        status = 3
        message += (
            f"; but z(1) and theta'(0)/omega_eps^2 (eq. (29)) differ by {mismatch:.1e}: "
            "integration error amplified (ill-conditioned), the shape is inaccurate"
        )
    sign, n = branch_label(dtheta[:-1], c)
    return NumericalResult(
        success=status in (0, 3),
        status=status,
        message=message,
        nit=int(iterations),
        method="shooting",
        omega2=omega2,
        eps=eps,
        theta0=theta0,
        sigma=sigma,
        theta=theta,
        x=x,
        z=z,
        tip_height=float(z[-1]),
        tip_deflection=float(x[-1]),
        xi=float(np.sin(theta[-1])),
        omega_eps=float(np.sqrt(W)) if W >= 0 else float("nan"),
        base_curvature=float(c),
        sign=sign,
        n=n,
        nfev=int(shooter.nfev),
    )
