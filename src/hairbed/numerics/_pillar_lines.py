"""A second-order finite-difference method of lines for the overdamped pillar (issue 30).

The independent baseline of :func:`hairbed.dynamics.simulate_pillar` (theory.md §14): the
same model on a uniform grid s_i = i/M, theta_0 = theta0, the free end by a ghost node
(theta_{M+1} = theta_{M-1}: theta'(1) = 0 to second order) with the tip row's algebraic
theta_ss(1) = -n . F(1) = 0, i.e. theta_M = theta_{M-1}; theta_ss by the three-point
difference, every integral by the cumulative trapezoidal rule, and time by
:func:`scipy.integrate.solve_ivp` (its Radau, its own finite-difference Jacobian). It shares
no code with the spectral solver. The interior and tip rows read

    B(theta) theta_t = theta_ss + n . F(s),   B theta_t = n . int_s^1 A r_t,
    r_t = int_0^s theta_t n,   F = P e_x + int_s^1 Lambda U(z) A e_x,   A = I - (1 - gamma) t t.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.integrate
from numpy.typing import ArrayLike, NDArray

from .._core.pillar import profile_coefficients
from .._core.validation import as_float_array, check_int, check_number, check_positive

__all__ = ["PillarLinesResult", "pillar_method_of_lines"]

#: The longest time span [T] a baseline run may cover: its work grows with the span, and the
#: pillar settles within a few T (the slowest mode decays like exp(-12.36 t)).
MAX_SPAN = 1e6
#: The largest |Lambda|: beyond it the finite differences' rates overflow.
MAX_FORCING = 1e8

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PillarLinesResult:
    """The finite-difference baseline's trajectory.

    Attributes
    ----------
    t : ndarray
        Output times [T].
    s : ndarray
        The grid [L].
    theta : ndarray
        theta at the grid, (time, node) [rad].
    tip_deflection, tip_height : ndarray
        x1, h1 by the trapezoidal rule [L].
    success : bool
        solve_ivp's success.
    status : int
        0, or -3 (solve_ivp failed).
    message : str
        solve_ivp's message.
    """

    t: FloatArray
    s: FloatArray
    theta: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    success: bool
    status: int
    message: str


def _cumtrapz(values: FloatArray, ds: float) -> FloatArray:
    """int_0^{s_i} along the last axis by the trapezoidal rule."""
    out = np.zeros_like(values)
    out[..., 1:] = np.cumsum(0.5 * ds * (values[..., 1:] + values[..., :-1]), axis=-1)
    return out


def pillar_method_of_lines(
    forcing: float | Callable[[float], float],
    t_eval: ArrayLike,
    *,
    theta0: float = 0.0,
    gamma: float = 0.5,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    num: int = 64,
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> PillarLinesResult:
    """The overdamped pillar from rest (straight at theta0) under Lambda(t), on M = ``num``
    uniform intervals (second order in 1/M), integrated by scipy's Radau.

    Parameters
    ----------
    forcing : float or callable
        Lambda in [-1e8, 1e8], or Lambda(t) of a float t.
    t_eval : array_like
        Output times [T], at least two, increasing strictly from the start t_eval[0], over
        at most 1e6 T.
    theta0, gamma, profile, height_ratio
        As in :func:`hairbed.solve_pillar`.
    num : int
        M in [4, 1024].
    rtol, atol : float
        solve_ivp's tolerances.
    """
    te = as_float_array(t_eval, "t_eval").reshape(-1)
    if te.size < 2:
        raise ValueError(f"t_eval must hold at least two times [T], got {te.size}")
    back = np.diff(te) <= 0.0
    if np.any(back):
        i = int(np.flatnonzero(back)[0]) + 1
        raise ValueError(
            f"t_eval must increase strictly, got {float(te[i])!r} after "
            f"{float(te[i - 1])!r} (at index {i})"
        )
    if te[-1] - te[0] > MAX_SPAN:
        raise ValueError(
            f"t_eval must span at most {MAX_SPAN:g} T (the pillar settles within a few T), "
            f"got {float(te[-1] - te[0])!r}"
        )
    t0 = check_number(theta0, "theta0", low=-0.5 * np.pi, high=0.5 * np.pi, low_open=True,
                      high_open=True)  # fmt: skip
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    m = check_int(num, "num", 4, 1024)
    rt = check_positive(rtol, "rtol")
    at = check_positive(atol, "atol")
    if callable(forcing):
        lam: Callable[[float], float] = forcing
    else:
        value = check_number(forcing, "forcing", low=-MAX_FORCING, high=MAX_FORCING)

        def lam(_t: float) -> float:
            return value

    prof = profile_coefficients(profile, height_ratio)
    ds = 1.0 / m
    s = np.linspace(0.0, 1.0, m + 1)
    # the trapezoidal integration from the base as a matrix (rows i: int_0^{s_i})
    cum = np.zeros((m + 1, m + 1))
    for i in range(1, m + 1):
        cum[i, :i] += 0.5 * ds
        cum[i, 1 : i + 1] += 0.5 * ds
    tail = cum[-1][None, :] - cum  # int_{s_i}^1

    def full(y: FloatArray) -> FloatArray:
        return np.concatenate([[t0], y, y[-1:]])  # theta_M = theta_{M-1}

    def rates(t: float, y: FloatArray) -> FloatArray:
        th = full(y)
        c, sn = np.cos(th), np.sin(th)
        z = cum @ c
        u = np.polynomial.chebyshev.chebval(2.0 * z - 1.0, prof) * lam(t)
        fx = u * (c * c + g * sn * sn)
        fz = -u * (1.0 - g) * sn * c
        fxs, fzs = tail @ fx, tail @ fz
        thss = (th[2:] - 2.0 * th[1:-1] + th[:-2]) / ds**2  # nodes 1 .. M - 1
        rhs = thss + (c[1:-1] * fxs[1:-1] - sn[1:-1] * fzs[1:-1])
        # B: theta_t -> n . int_s^1 A int_0^s theta_t n
        one = 1.0 - g
        vx = cum * c[None, :]
        vz = -cum * sn[None, :]
        ax = (1.0 - one * sn * sn)[:, None] * vx - (one * sn * c)[:, None] * vz
        az = -(one * sn * c)[:, None] * vx + (1.0 - one * c * c)[:, None] * vz
        bmat = c[:, None] * (tail @ ax) - sn[:, None] * (tail @ az)
        red = bmat[1:-1, 1:-1].copy()
        red[:, -1] += bmat[1:-1, -1]  # theta_t at the tip is that of node M - 1
        return np.asarray(np.linalg.solve(red, rhs))

    y0 = np.full(m - 1, t0)
    sol = scipy.integrate.solve_ivp(
        rates, (float(te[0]), float(te[-1])), y0, method="Radau", t_eval=te, rtol=rt, atol=at
    )
    theta = np.full((te.size, m + 1), np.nan)
    if sol.success:
        theta[:, 0] = t0
        theta[:, 1:-1] = sol.y.T
        theta[:, -1] = theta[:, -2]
    x1 = (cum[-1] * np.sin(theta)).sum(axis=1)
    h1 = (cum[-1] * np.cos(theta)).sum(axis=1)
    return PillarLinesResult(
        t=te,
        s=s,
        theta=theta,
        tip_deflection=x1,
        tip_height=h1,
        success=bool(sol.success),
        status=0 if sol.success else -3,
        message=str(sol.message),
    )
