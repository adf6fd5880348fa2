"""The snap-through window of a pillar tilted upstream, for a design (issue 32).

A pillar tilted far against the flow (theta0 below about -1.3 for flow towards +x) has a
window of forcings Lambda_l < Lambda < Lambda_u in which three states coexist: its branch of
states folds at Lambda_u (the upper fold, met first from rest) and at Lambda_l (theory.md
§12, :func:`hairbed.continue_pillar`). A design follows both folds from pillar to pillar:

* the value: each fold is a zero of g(x1) = dLambda/dx1 = 1/(dx1/dLambda) along the branch,
  parametrised by the tip deflection x1 (the inverse states of
  :func:`hairbed.solve_pillar_inverse`, with their exact dx1/dLambda); the secant method on
  g from the folds of the nearest pillar solved before, both folds at once, or the
  branch's scan (:func:`hairbed.continue_pillar`, golden-section folds) where there is none
  near or the secant fails its checks;
* the gradient: at a fold the Jacobian J of the collocation is singular, with a left null
  vector w; differentiating R(u, Lambda_f, p) = 0 along the fold and projecting on w
  (the implicit function theorem on the extended system R = 0, J phi = 0),

      dLambda_f/dp = -(w . R_p)/(w . R_Lambda),

  with R_p, R_Lambda the residual's partials (exact, on jets:
  :mod:`hairbed.design._pillar_second`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.pillar import ATLAS_THETA0, WINDOW_THETA0, PillarState
from .._core.pillar_branch import _branch, continue_pillar
from ._pillar_second import _inputs, _level, _residual

__all__ = ["WindowTracker", "fold_gradient"]

FloatArray = NDArray[np.float64]

#: The secant's steps at most, and its tolerance on x1 [L].
_MAX_STEPS = 40
_XTOL = 1e-9
#: A pillar farther than this in (theta0, gamma) from every pillar solved before is scanned.
_NEAR = 0.05
#: Points of the scan's grid in x1.
_GRID = 120


def fold_gradient(state: PillarState, index: int, prof: FloatArray) -> tuple[float, FloatArray]:
    """(Lambda_f, dLambda_f/d(theta0, gamma)) of element ``index`` of a 1-D batch of pillar
    states, at a fold: the left null vector w of the collocation's Jacobian (its smallest
    singular vector) and the residual's exact partials, dLambda_f/dp = -(w . R_p)/(w .
    R_Lambda)."""
    from .._core.loaded import _chebyshev_values

    def at(v: Any) -> float:
        return float(np.asarray(v).reshape(-1)[index])

    num = int(at(state.num))
    raw = np.asarray(state._coefs, dtype=np.float64)
    coefs = raw.reshape(3, -1, raw.shape[-1])[0, index, : num + 1]
    theta = _chebyshev_values(num) @ coefs
    lev = _level(num, at(state._map))
    u0 = np.append(theta, lev.ii[num] @ np.cos(theta))
    m = u0.size
    p = (at(state.forcing), at(state.theta0), at(state.gamma))
    res = _residual(lev, *_inputs(u0, p, np.eye(m + 3), np.zeros((0, m + 3))), prof=prof)
    jac = res.a[:m].T
    w = np.linalg.svd(jac)[0][:, -1]
    r_p = res.a[m:] @ w  # (Lambda, theta0, gamma)
    return p[0], -r_p[1:] / r_p[0]


class WindowTracker:
    """The folds (x1 of the upper and the lower) of the pillars of one profile, followed
    from pillar to pillar by the secant method (module docstring); ``scans`` and
    ``secants`` count how each pillar's folds were found."""

    def __init__(self, profile: Any, height_ratio: float | None) -> None:
        self.profile = profile
        self.height_ratio = height_ratio
        self._known: list[tuple[float, float, float, float]] = []
        self._none: set[tuple[float, float]] = set()
        self.scans = 0
        self.secants = 0

    def _scan(self, branch: Any) -> tuple[float, float] | None:
        """(x_u, x_l) of the branch's scan, or None: no window. The inverse states on a
        grid of x1 from rest to 0.97 (denser near rest, where the upper fold lies for a
        strong tilt), the folds where dx1/dLambda changes sign, refined by the secant
        method; below ``ATLAS_THETA0`` (the fold within ~1e-6 of rest)
        :func:`hairbed.continue_pillar`'s atlas."""
        self.scans += 1
        theta0 = branch.theta0
        if theta0 > WINDOW_THETA0:
            return None
        if theta0 < ATLAS_THETA0:
            end = 20.0
            for _ in range(12):
                b = continue_pillar(
                    end, theta0, profile=self.profile, height_ratio=self.height_ratio,
                    gamma=branch.gamma, num=60,
                )  # fmt: skip
                if b.folds.shape[0] >= 2:
                    return float(b.folds[0, 1]), float(b.folds[1, 1])
                end *= 2.0
            return None
        rest = math.sin(theta0)
        t = np.linspace(0.0, 1.0, _GRID + 1)[1:]
        x = rest + (0.97 - rest) * t * t
        slope = np.asarray(branch.states(x).tip_deflection_slope, dtype=np.float64)
        up = np.flatnonzero((slope[:-1] > 0.0) & (slope[1:] < 0.0))
        if up.size == 0:
            return None
        down = np.flatnonzero(
            (slope[:-1] < 0.0) & (slope[1:] > 0.0) & (np.arange(x.size - 1) > up[0])
        )
        if down.size == 0:
            return None
        i, j = int(up[0]), int(down[0])
        xs = self._secant(branch, np.array([x[i], x[j]]), np.array([x[i + 1], x[j + 1]]))
        return None if xs is None else (float(xs[0]), float(xs[1]))

    def _secant(self, branch: Any, xa: FloatArray, xb: FloatArray) -> FloatArray | None:
        """Both folds' x1 by the secant method on 1/(dx1/dLambda) from the points xa, xb
        (an element whose state is the fold itself, a singular Jacobian and a NaN slope,
        is done); None where it fails."""

        def g(x: FloatArray) -> FloatArray:
            return 1.0 / np.asarray(branch.states(x).tip_deflection_slope, dtype=np.float64)

        x0, x1 = np.array(xa, dtype=np.float64), np.array(xb, dtype=np.float64)
        both = g(np.concatenate([x0, x1]))
        g0, g1 = both[: x0.size], both[x0.size :]
        done = ~np.isfinite(g0)  # a start at the fold itself (to rounding): done
        x1 = np.where(done, x0, x1)
        g1 = np.where(done, np.nan, g1)
        for _ in range(_MAX_STEPS):
            done |= ~np.isfinite(g1)
            if not np.all(np.isfinite(g0[~done])):
                return None
            with np.errstate(divide="ignore", invalid="ignore"):
                step = np.where(done | (g1 == g0), 0.0, g1 * (x1 - x0) / (g1 - g0))
            if not np.all(np.isfinite(step)):
                return None
            x0, g0 = x1.copy(), g1.copy()
            x1 = x1 - step
            done |= np.abs(step) <= _XTOL
            if np.any(np.abs(x1) >= 1.0):
                return None
            if np.all(done):
                return x1
            todo = np.flatnonzero(~done)
            g1[todo] = g(x1[todo])
        return None

    def folds(self, theta0: float, gamma: float) -> PillarState | None:
        """The states at the upper and the lower fold of the pillar (theta0, gamma),
        elements 0 and 1 of the batch returned, or None where it has no window."""
        branch = _branch(theta0, self.profile, self.height_ratio, gamma, 0.0)
        if (theta0, gamma) in self._none:
            return None
        near = None
        if self._known:
            dist = [math.hypot(k[0] - theta0, k[1] - gamma) for k in self._known]
            i = int(np.argmin(dist))
            if dist[i] <= _NEAR:
                near = self._known[i]
        if near is not None:
            guess = np.array([near[2], near[3]])
            xs = self._secant(branch, guess, guess + np.array([-1e-4, 1e-4]))
            st = None if xs is None else self._checked(branch, xs)
            if st is not None and xs is not None:
                self.secants += 1
                self._remember(theta0, gamma, xs)
                return st
        found = self._scan(branch)
        st = None if found is None else self._checked(branch, np.array(found))
        if st is None:
            self._none.add((theta0, gamma))
            if len(self._none) > 4096:
                self._none.clear()
            return None
        self._remember(theta0, gamma, np.array(found))
        return st

    def _remember(self, theta0: float, gamma: float, xs: FloatArray) -> None:
        self._known.append((theta0, gamma, float(xs[0]), float(xs[1])))
        if len(self._known) > 256:
            self._known.pop(0)

    @staticmethod
    def _checked(branch: Any, xs: FloatArray) -> PillarState | None:
        """The states at x1 = (x_u, x_l) and beside them, if x_u is a maximum of Lambda
        (an upper fold), x_l a minimum after it (the lower) and Lambda_u > Lambda_l."""
        d = 1e-4
        st = branch.states(np.concatenate([xs, xs - d, xs + d]))
        lam = np.asarray(st.forcing, dtype=np.float64)
        ok = (
            bool(np.all(np.isfinite(lam)))
            and xs[0] < xs[1] - 1e-6
            and lam[0] > lam[1]
            and lam[2] < lam[0] > lam[4]
            and lam[3] > lam[1] < lam[5]
        )
        return st if ok else None
