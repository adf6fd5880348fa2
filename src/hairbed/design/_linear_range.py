"""The end of a pillar's linear range, followed from design to design by Newton's method.

:meth:`hairbed.Pillar.linear_range` scans the branch from rest (a grid of exact inverse
states) for the first deflection where the linear calibration's relative error

    e(Lambda) = (x1(Lambda) - sin theta0)/(c1 Lambda) - 1

reaches ``rtol``: some tens of states, 12-30 ms. A design evaluates it at a few hundred
nearby pillars, and its value depends on the pillar only through the dimensionless
problem (theta0, gamma and the profile): the root Lambda* of

    G(Lambda) = e(Lambda) - s rtol,   s = +-1 the sign of the error there,

moves continuously with (theta0, gamma). :class:`LinearRangeTracker` solves it by Newton's
method from the root of the nearest pillar solved before, with the exact derivative of the
state, dG/dLambda = (dx1/dLambda - (x1 - sin theta0)/Lambda)/(c1 Lambda) (the collocation's
``tip_deflection_slope``): 2-4 forward states instead of a scan. The root it finds is
accepted only where it is still the first: abs(e) <= rtol and dx1/dLambda > 0 at the
fractions :data:`CHECK_FRACTIONS` of the way from rest (one batched solve, with the root's
own state). A pillar without a neighbour within :data:`NEIGHBOUR_DISTANCE` in (theta0, gamma),
a Newton iteration that fails, or a check that fails, is scanned by
:meth:`~hairbed.Pillar.linear_range` itself, and its root remembered.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np

from .._core.pillar import _solve_pillar_checked
from ..pillars import Pillar

__all__ = ["CHECK_FRACTIONS", "NEIGHBOUR_DISTANCE", "LinearRangeTracker"]

#: The fractions of Lambda* at which the error is checked to stay within the tolerance.
CHECK_FRACTIONS = np.array([0.1, 0.3, 0.5, 0.7, 0.85, 0.95])
#: A root is followed from a remembered one at most this far in max(|d theta0|, |d gamma|).
NEIGHBOUR_DISTANCE = 0.05
#: Newton's iteration limit, and the relative step below which it has converged.
NEWTON_STEPS = 12
NEWTON_XTOL = 1e-9
#: An accepted root's last Newton correction, relative to Lambda*.
ROOT_RTOL = 1e-10
#: Roots remembered per tracker.
MEMORY = 256


def _profile_key(p: Pillar) -> tuple[Any, ...]:
    prof, tol, nums = p._core_options
    return (np.asarray(prof, dtype=np.float64).tobytes(), float(tol), tuple(nums))


class LinearRangeTracker:
    """Lambda* of :meth:`hairbed.Pillar.linear_range` for a stream of nearby pillars.

    Parameters
    ----------
    rtol : float
        The linear calibration's relative error that ends the range, in (0, 1) [-].

    follow : bool
        False: every pillar is scanned (:meth:`~hairbed.Pillar.linear_range`), the cost
        without the tracker (``benchmarks/bench_design.py``).

    Attributes
    ----------
    scans, newton : int
        How many roots came from a full scan and how many from Newton's method.
    """

    def __init__(self, rtol: float, follow: bool = True) -> None:
        self.rtol = float(rtol)
        self.follow = bool(follow)
        self._memory: deque[tuple[tuple[Any, ...], float, float, float, float]] = deque(
            maxlen=MEMORY
        )
        self.scans = 0
        self.newton = 0

    def __call__(self, p: Pillar) -> tuple[float, Any]:
        """(tau* [Pa], the state at Lambda* = K tau*: a PillarState of one element).

        Raises
        ------
        ArithmeticError
            When :meth:`~hairbed.Pillar.linear_range` finds no end of the range.
        """
        key = _profile_key(p)
        th, gamma = p.base_angle, p.drag_ratio
        near = self._nearest(key, th, gamma) if self.follow else None
        if near is not None:
            found = self._newton(p, near[0], near[1])
            if found is not None:
                self.newton += 1
                lam, state = found
                self._memory.append((key, th, gamma, lam, near[1]))
                return lam / p.forcing_per_stress, state
        return self._scan(p, key)

    def _nearest(
        self, key: tuple[Any, ...], th: float, gamma: float
    ) -> tuple[float, float] | None:
        best, where = NEIGHBOUR_DISTANCE, None
        for k, t, g, lam, sign in self._memory:
            if k != key:
                continue
            dist = max(abs(t - th), abs(g - gamma))
            if dist <= best:
                best, where = dist, (lam, sign)
        return where

    def _scan(self, p: Pillar, key: tuple[Any, ...]) -> tuple[float, Any]:
        rng = p.linear_range(self.rtol)
        if not rng.success:
            raise ArithmeticError(f"linear_range(rtol={self.rtol:g}): {rng.message}")
        self.scans += 1
        tau = float(rng.wall_shear_stress)
        lam = tau * p.forcing_per_stress
        sign = 1.0 if rng.wall_shear_stress_error > 0 else -1.0
        self._memory.append((key, p.base_angle, p.drag_ratio, lam, sign))
        return tau, None

    def _solve(self, p: Pillar, lam: Any) -> Any:
        lam = np.asarray(lam, dtype=np.float64)
        return _solve_pillar_checked(lam, *p._checked_like(lam), *p._core_options)

    def _newton(self, p: Pillar, lam: float, sign: float) -> tuple[float, Any] | None:
        """(Lambda*, its state) from Newton's method started at ``lam``, or None."""
        rest = math.sin(p.base_angle)
        c1 = p.linear_coefficient
        target = sign * self.rtol
        for _ in range(NEWTON_STEPS):
            sol = self._solve(p, np.array([lam]))
            if int(np.asarray(sol.status).reshape(-1)[0]) < 0:
                return None
            x1 = float(np.asarray(sol.tip_deflection).reshape(-1)[0])
            slope = float(np.asarray(sol.tip_deflection_slope).reshape(-1)[0])
            g = (x1 - rest) / (c1 * lam) - 1.0 - target
            dg = (slope - (x1 - rest) / lam) / (c1 * lam)
            if not (math.isfinite(g) and math.isfinite(dg)) or dg == 0.0:
                return None
            step = g / dg
            new = lam - step
            if not (0.5 * lam <= new <= 2.0 * lam):
                return None
            lam = new
            if abs(step) <= NEWTON_XTOL * lam:
                return self._checked(p, lam, target, rest, c1)
        return None

    def _checked(
        self, p: Pillar, lam: float, target: float, rest: float, c1: float
    ) -> tuple[float, Any] | None:
        """The state at ``lam`` and the check that it is the first root, or None."""
        lams = np.append(CHECK_FRACTIONS * lam, lam)
        sol = self._solve(p, lams)
        status = np.asarray(sol.status).reshape(-1)
        x1 = np.asarray(sol.tip_deflection, dtype=np.float64).reshape(-1)
        slope = np.asarray(sol.tip_deflection_slope, dtype=np.float64).reshape(-1)
        err = (x1 - rest) / (c1 * lams) - 1.0
        if np.any(status < 0) or not np.all(slope > 0.0):
            return None
        dg = (slope[-1] - (x1[-1] - rest) / lam) / (c1 * lam)
        if not abs((err[-1] - target) / dg) <= ROOT_RTOL * lam:
            return None
        if not np.all(np.abs(err[:-1]) <= self.rtol):
            return None
        return lam, sol
