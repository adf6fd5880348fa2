"""Fitting the forcing (and base angle) to the measured shape of a whole hair.

Where a sensor images a hair instead of reading its tip, the whole centreline is data: an
orthogonal-distance regression of the closed-form curve (x(sigma), z(sigma)) of the
physical branch (eqs. (32), (30) of arXiv:2203.04169) in its branch parameter t, the base
angle and one arc length per point. The curve is parametrised by t, not by omega^2, so that
every physical state (also the middle one of three, theory.md §5) is fitted without choosing
a root; omega^2 follows from eq. (34). The tip alone is :mod:`hairbed.inverse`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

from ._core.solution import Solution
from ._core.solver import _from_parameter, _solve_checked
from ._core.validation import (
    HALF_PI,
    as_float_array,
    check_number,
    check_scalar_inputs,
    least_squares_status,
)

__all__ = ["ProfileFit", "fit_profile"]

FloatArray = NDArray[np.float64]


def _physical(t: ArrayLike, eps: ArrayLike, theta0: ArrayLike) -> Solution:
    """The physical-branch state at parameter t (theory.md §2, §3), of checked inputs."""
    return _from_parameter(t, eps, theta0)


@dataclass(frozen=True)
class ProfileFit:
    """Result of :func:`fit_profile`.

    Attributes
    ----------
    omega2, theta0 : float
        Fitted forcing [-] and base angle [rad].
    omega2_stderr, theta0_stderr : float
        Their standard uncertainties (0 for a parameter held fixed), from the linearised
        covariance scaled by the residual variance.
    covariance : ndarray
        2 x 2 covariance of (omega2, theta0).
    residual : float
        Root-mean-square distance from the points to the fitted curve [-] (hair lengths).
    solution : Solution or PorousState
        The fitted state (physical branch; a porous bed's state at its eps).
    sigma : ndarray
        Arc length [-] of the point of the curve closest to each measured point.
    success : bool
        Whether the optimiser reports convergence.
    status : int
        0 converged, -2 the evaluation limit, -6 improper input
        (:data:`~hairbed._core.validation.STATUS_MESSAGES`).
    message : str
        The optimiser's message.
    nfev : int
        Number of residual evaluations.
    nit : int
        Iterations of the optimiser (its evaluations of the Jacobian).
    solver_status : int
        :func:`scipy.optimize.least_squares`'s own status (> 0 converged, 0 the evaluation
        limit, -1 improper input).
    """

    omega2: float
    theta0: float
    omega2_stderr: float
    theta0_stderr: float
    covariance: FloatArray = field(repr=False)
    residual: float
    solution: Any = field(repr=False)  # Solution, or a porous bed's PorousState
    sigma: FloatArray = field(repr=False)
    success: bool
    status: int
    message: str
    nfev: int
    nit: int = 0
    solver_status: int = 0


#: The farthest a measured point may lie from the base [hair lengths]: the curve is continued
#: along its end tangents, so points a little beyond the tip fit; far beyond is not a hair.
_MAX_COORDINATE = 10.0
#: The largest branch parameter a guess starts from (x1 within ~1e-17 of 1: flat to rounding).
_T_GUESS_MAX = 40.0
#: Base angles the fit may visit: the closed form needs |theta0| < pi/2.
_THETA0_LIMIT = HALF_PI - 1e-9


class _Dense:
    """The dense bed's curves: the closed-form physical state in its branch parameter t."""

    #: the starting grid of the parameter, and its range for a guess
    grid = np.linspace(-10.0, 14.0, 25)
    low, high = -30.0, _T_GUESS_MAX

    def __init__(self, eps: float) -> None:
        self.eps = eps

    def states(self, t: Any, theta0: Any) -> Any:
        return _physical(t, self.eps, theta0)

    def points(self, sol: Any, s: FloatArray) -> tuple[Any, Any, Any]:
        """x, z, theta at arc lengths s (one row of each per state)."""
        return sol.x(s), sol.z(s), sol.theta(s)

    def profile(self, sol: Any, num: int) -> tuple[Any, Any]:
        return sol.profile(num)

    def omega2(self, sol: Any) -> Any:
        return sol.omega2

    def parameter(self, omega2: float, theta0: float) -> FloatArray:
        """The parameter of the (low) state at forcing omega2."""
        return np.atleast_1d(np.asarray(_solve_checked(omega2, self.eps, theta0).t))

    def final(self, t: float, theta0: float) -> Any:
        return _physical(np.float64(t), self.eps, np.float64(theta0))


class _Porous:
    """The porous bed's curves (theory.md §13) in u = ln F, F the stress on the tip plane in
    load units: with no pressure gradient F fixes the state, the bed's at eps = 0 and
    forcing F (its equations hold no eps), every state of a window too; the forcing at the
    bed's eps is omega2 = eps w(1) + (1 - eps h1) F (the gap's condition)."""

    grid = np.linspace(math.log(1e-3), math.log(1e3), 25)
    low, high = math.log(1e-12), math.log(1e8)

    def __init__(self, eps: float, kappa: float, gamma: float) -> None:
        self.eps, self.kappa, self.gamma = eps, kappa, gamma

    def states(self, u: Any, theta0: Any) -> Any:
        from ._core.porous import solve_porous

        u = np.clip(np.asarray(u, dtype=np.float64), self.low, self.high)
        return solve_porous(np.exp(u), 0.0, theta0, kappa=self.kappa, gamma=self.gamma, pi=0.0)

    def points(self, st: Any, s: FloatArray) -> tuple[Any, Any, Any]:
        _, x, z, theta = st.shape(np.asarray(s, dtype=np.float64))
        return x, z, theta

    def profile(self, st: Any, num: int) -> tuple[Any, Any]:
        _, x, z, _ = st.shape(np.linspace(0.0, 1.0, num))
        return x, z

    def omega2(self, st: Any) -> Any:
        force = np.asarray(st.omega2, dtype=np.float64)
        h1 = np.asarray(st.tip_height, dtype=np.float64)
        w1 = np.asarray(st.tip_velocity, dtype=np.float64)
        return self.eps * w1 + (1.0 - self.eps * h1) * force

    def parameter(self, omega2: float, theta0: float) -> FloatArray:
        """u of the low state at the bed's forcing omega2: its tip stress."""
        from ._core.porous import solve_porous

        st = solve_porous(omega2, self.eps, theta0, kappa=self.kappa, gamma=self.gamma)
        with np.errstate(divide="ignore"):
            return np.atleast_1d(np.log(np.asarray(st.tip_stress, dtype=np.float64)))

    def final(self, u: float, theta0: float) -> Any:
        """The fitted state at the bed's eps: of the states of its forcing
        (:func:`hairbed.solve_porous_all`), the one of the fitted hair (its tip deflection;
        the same hair at eps = 0 where none is found)."""
        from ._core.porous import solve_porous_all

        st0 = self.states(u, theta0)
        if self.eps == 0.0:
            return st0
        omega2 = float(self.omega2(st0))
        every = solve_porous_all(
            omega2, self.eps, float(theta0), kappa=self.kappa, gamma=self.gamma
        )
        found = [s for s in every if int(s.status) >= 0]
        if not found:
            return st0
        x1 = float(st0.tip_deflection)
        return min(found, key=lambda s: abs(float(s.tip_deflection) - x1))


def _curve(
    family: Any, t: Any, theta0: Any, sigma: FloatArray, *, angle: bool = False
) -> tuple[FloatArray, ...]:
    """x, z (and theta) at arc lengths sigma, continued along the end tangents outside [0, 1].

    ``t`` and ``theta0`` may be arrays of shape (k,): the result then has shape (k, m). The
    continuation (C^1 at both ends) lets the orthogonal-distance fit run unconstrained: a measured
    point beyond the tip projects onto the tip's tangent instead of stalling on a bound.
    """
    t = np.asarray(t, dtype=np.float64)
    th = np.clip(np.asarray(theta0, dtype=np.float64), -_THETA0_LIMIT, _THETA0_LIMIT)
    dense = isinstance(family, _Dense)
    if t.ndim and dense:
        t, th = t[:, np.newaxis], th[:, np.newaxis]
    sol = family.states(t, th)
    inside = np.clip(sigma, 0.0, 1.0)
    beyond = sigma - inside
    xs, zs, ts = family.points(sol, inside)
    x = np.asarray(xs, dtype=np.float64)
    z = np.asarray(zs, dtype=np.float64)
    ends = np.flatnonzero(beyond)
    if not angle and ends.size == 0:
        return x, z
    theta = np.asarray(ts, dtype=np.float64)
    x = x + beyond * np.sin(theta)
    z = z + beyond * np.cos(theta)
    return (x, z, theta) if angle else (x, z)


def _scalar_theta0(value: Any, name: str) -> float:
    """A single base angle in (-pi/2, pi/2) [rad], the message naming ``name``."""
    th = check_number(value, name, unit="rad")
    if not abs(th) < HALF_PI:
        raise ValueError(f"{name} must lie in (-pi/2, pi/2), got {th!r}")
    return th


def fit_profile(
    x: Any,
    z: Any,
    eps: float,
    *,
    theta0: float | None = None,
    omega2_guess: float | None = None,
    theta0_guess: float | None = None,
    kappa: float | None = None,
    gamma: float = 1.0,
) -> ProfileFit:
    """Least-squares fit of the forcing (and base angle) to measured points along one hair.

    Minimises the sum of squared distances from the points to the closed-form curve
    (x(sigma), z(sigma)) of the physical state (eqs. (32), (30)): an orthogonal-distance
    regression in the branch parameter t, the base angle and one arc length per point, with
    :func:`scipy.optimize.least_squares`. Because the curve is parametrised by t, every physical
    state (also the middle one of three) can be fitted without choosing a root.

    Parameters
    ----------
    x, z : array_like
        Measured points [-] in units of the hair length, with the base at the origin and the
        flow towards +x; at least three points (two for fixed ``theta0``), in any order, and at
        least one above the wall (``z > 0``): heights all zero, a hair lying on the wall, are
        the limit omega^2 -> inf or theta0 -> +-pi/2, not a state, and raise ValueError.
    eps : float
        Confinement L/H [-] (enters omega^2 only, not the shape).
    theta0 : float, optional
        Hold the base angle fixed at this value [rad]; by default it is fitted.
    omega2_guess, theta0_guess : float, optional
        Starting values; by default a coarse grid search over the physical branch.
    kappa, gamma : float, optional
        A porous bed's permeability kappa = k/L^2 > 0 and drag ratio gamma in (0, 1]
        (:func:`hairbed.solve_porous`, theory.md §13): the curves are then the porous bed's
        states, parametrised by the stress on their tip plane F (the state of the bed at
        eps = 0 and forcing F, every state of a window too), and omega^2 = eps w(1) +
        (1 - eps h1) F; ``solution`` is the state at ``eps`` (a
        :class:`hairbed.PorousState`). By default (``kappa`` None) the dense bed.

    Returns
    -------
    ProfileFit
        omega2, theta0, their standard errors, the rms residual and the optimiser's status.

    Notes
    -----
    With a tangent of unit length, eliminating the arc lengths from the Gauss-Newton normal
    equations leaves the normal components N of the curve's derivatives with respect to
    (t, theta0): the covariance is s^2 (N^T N)^-1 with s^2 = sum(d_i^2) / (m - k) for m points
    and k fitted parameters, mapped to (omega^2, theta0) by the Jacobian of omega^2(t, theta0).

    Examples
    --------
    >>> import hairbed
    >>> sol = hairbed.solve(2.0, 0.5, 0.1)
    >>> x, z = sol.profile(20)
    >>> fit = fit_profile(x, z, 0.5)
    >>> round(fit.omega2, 8), round(fit.theta0, 8), fit.success
    (2.0, 0.1, True)
    """
    x = as_float_array(x, "x").ravel()
    z = as_float_array(z, "z").ravel()
    if x.shape != z.shape:
        raise ValueError(f"x and z must have the same number of points, got {x.size}, {z.size}")
    if np.max(np.abs(np.concatenate([x, z])), initial=0.0) > _MAX_COORDINATE:
        i = int(np.argmax(np.maximum(np.abs(x), np.abs(z)) > _MAX_COORDINATE))
        raise ValueError(
            f"x and z must be points along a hair, within {_MAX_COORDINATE:g} hair lengths of "
            f"its base, got ({float(x[i])!r}, {float(z[i])!r}) (first at index {i})"
        )
    if x.size and not np.any(z > 0.0):
        # dz/dsigma = cos(theta) > 0 along every physical state (|theta| < pi/2): a hair of
        # the model rises from its base. Heights all on (or below) the wall are a hair lying
        # on it, the limit omega2 -> inf (at eps = 0.5 the tip height falls like
        # 1.4/sqrt(omega2)) or theta0 -> +-pi/2 that no state reaches: a fit would run to the
        # edge of the base-angle range and stop there (success=False, or a theta0 at the edge).
        raise ValueError(
            "z must have a point above the wall (z > 0): a hair rises from its base "
            f"(dz/dsigma = cos(theta) > 0), got all {x.size} heights <= 0 (a hair lying on the "
            "wall is the limit omega2 -> inf or theta0 -> +-pi/2, not a state of the model)"
        )
    eps = check_scalar_inputs(eps=eps, given=("eps",))[1]
    family: Any
    if kappa is None:
        family = _Dense(eps)
    else:
        family = _Porous(
            eps,
            check_number(kappa, "kappa", low=0.0, low_open=True),
            check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True),
        )
    fit_theta = theta0 is None
    k = 2 if fit_theta else 1
    m = x.size
    if m < k + 1:
        raise ValueError(f"need at least {k + 1} points to fit {k} parameter(s), got {m}")
    if not fit_theta:
        theta_fixed = _scalar_theta0(theta0, "theta0")
    if omega2_guess is not None:
        omega2_guess = check_number(omega2_guess, "omega2_guess", low=0.0)
    if theta0_guess is not None:
        theta0_guess = _scalar_theta0(theta0_guess, "theta0_guess")

    # -- starting point: a grid search on curves sampled in arc length
    num = 101
    s_grid = np.linspace(0.0, 1.0, num)
    if not fit_theta:
        th_cands = np.array([theta_fixed])
    elif theta0_guess is not None:
        th_cands = np.array([theta0_guess])
    else:
        th_cands = np.linspace(-1.4, 1.4, 15)
    best = (np.inf, 0.0, 0.0, s_grid[:m])
    for th in th_cands:
        if omega2_guess is not None:
            # the branch parameter of the guessed state itself, within the range of t whose
            # shapes a profile resolves (-inf, the hair at rest, and a hair flat to rounding
            # start from the ends of that range)
            tc = family.parameter(float(omega2_guess), float(th))
            tc = np.clip(np.where(np.isfinite(tc), tc, family.low), family.low, family.high)
        else:
            tc = family.grid
        cx, cz = family.profile(family.states(tc, th), num)
        d2 = (cx[:, :, None] - x) ** 2 + (cz[:, :, None] - z) ** 2  # (t, sigma, point)
        cost = d2.min(axis=1).sum(axis=1)
        j = int(np.argmin(cost))
        if cost[j] < best[0]:
            best = (cost[j], tc[j], th, s_grid[np.argmin(d2[j], axis=0)])
    _, t_start, th_start, sigma_start = best

    def unpack(p: FloatArray) -> tuple[float, float, FloatArray]:
        if fit_theta:
            return p[0], p[1], p[2:]
        return p[0], theta_fixed, p[1:]

    def residuals(p: FloatArray) -> FloatArray:
        t, th, sg = unpack(p)
        cx, cz = _curve(family, t, th, sg)
        return np.concatenate([cx - x, cz - z])

    def globals_jac(t: float, th: float, sg: FloatArray) -> FloatArray:
        """d(x, z)/d(t, theta0) at the points, by central differences, shape (2m, k)."""
        ht, hth = 1e-6 * max(1.0, abs(t)), 1e-6
        ts = np.array([t + ht, t - ht, t, t])[: 2 * k]
        ths = np.array([th, th, th + hth, th - hth])[: 2 * k]
        cx, cz = _curve(family, ts, ths, sg)  # one evaluation for all shifted parameters
        steps = np.array([2.0 * ht, 2.0 * hth])[:k]
        dx = (cx[0::2] - cx[1::2]) / steps[:, None]
        dz = (cz[0::2] - cz[1::2]) / steps[:, None]
        return np.concatenate([dx, dz], axis=1).T

    def jac(p: FloatArray) -> FloatArray:
        t, th, sg = unpack(p)
        _, _, ang = _curve(family, t, th, sg, angle=True)
        out = np.zeros((2 * m, k + m))
        out[:, :k] = globals_jac(t, th, sg)
        rows = np.arange(m)
        out[rows, k + rows] = np.sin(ang)  # dx/dsigma
        out[m + rows, k + rows] = np.cos(ang)  # dz/dsigma
        return out

    if fit_theta:
        p0 = np.concatenate([[t_start, th_start], sigma_start])
    else:
        p0 = np.concatenate([[t_start], sigma_start])
    res = optimize.least_squares(
        residuals, p0, jac=jac, method="lm", x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15
    )
    t, th, sg = unpack(res.x)
    th = float(np.clip(th, -_THETA0_LIMIT, _THETA0_LIMIT))
    sol = family.final(t, th)
    omega2 = float(sol.omega2)

    # covariance from the normal components (see Notes)
    cx, cz, ang = _curve(family, t, th, sg, angle=True)
    nx, nz = np.cos(ang), -np.sin(ang)
    dist = nx * (cx - x) + nz * (cz - z)
    g = globals_jac(t, th, sg)
    normal = nx[:, None] * g[:m] + nz[:, None] * g[m:]
    dof = m - k
    s2 = float(np.sum(dist**2)) / dof if dof > 0 else np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        cov_p = s2 * np.linalg.pinv(normal.T @ normal)
    # Jacobian of (omega2, theta0) with respect to (t, theta0)
    ht, hth = 1e-6 * max(1.0, abs(t)), 1e-6
    th_hi, th_lo = min(th + hth, _THETA0_LIMIT), max(th - hth, -_THETA0_LIMIT)  # inside
    w = np.asarray(
        family.omega2(
            family.states(np.array([t + ht, t - ht, t, t]), np.array([th, th, th_hi, th_lo]))
        )
    )
    dw_dt = (w[0] - w[1]) / (2.0 * ht)
    if fit_theta:
        dw_dth = (w[2] - w[3]) / (th_hi - th_lo)
        jmap = np.array([[dw_dt, dw_dth], [0.0, 1.0]])
        cov = jmap @ cov_p @ jmap.T
    else:
        cov = np.zeros((2, 2))
        cov[0, 0] = dw_dt**2 * cov_p[0, 0]
    return ProfileFit(
        omega2=omega2,
        theta0=float(th),
        omega2_stderr=float(np.sqrt(cov[0, 0])),
        theta0_stderr=float(np.sqrt(cov[1, 1])),
        covariance=cov,
        residual=float(np.sqrt(np.mean(dist**2))),
        solution=sol,
        sigma=np.asarray(sg, dtype=np.float64),
        success=bool(res.success),
        status=least_squares_status(int(res.status)),
        message=str(res.message),
        nfev=int(res.nfev),
        nit=int(res.njev or 0),
        solver_status=int(res.status),
    )
