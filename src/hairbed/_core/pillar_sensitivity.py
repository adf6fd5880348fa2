"""Exact derivatives of pillar states in Lambda, theta0, gamma, the height ratio and the tip load.

The implicit differentiation of the converged collocation system, J du/dp = -dR/dp, in the
compiled kernel ``_kernels.pillar_gradient``; this module hands it each state's node values
and assembles the table that :func:`hairbed.derivatives_at` returns for a
:class:`hairbed.PillarState` (theory.md §12).

A PillarState does not hold its profile, so the profile (and height ratio) the state was
solved with is given again; the kernel's residual of the collocation system at the state
checks that it is a root of that system (a different profile is refused, by name).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .loaded import _ladder, _nodal_values
from .outputs import scalar_or_array
from .pillar import PillarState, profile_coefficients
from .validation import check_number
from .wall_law import _widths

__all__ = ["PILLAR_INPUTS", "PILLAR_OUTPUTS", "pillar_gradient_rows", "pillar_gradient_table"]

FloatArray = NDArray[np.float64]

#: The outputs of a pillar state that are differentiated, in the kernel's order.
PILLAR_OUTPUTS = (
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
    "drag_x",
    "drag_z",
)
#: The inputs, in the kernel's order ("height_ratio" only for a channel profile).
PILLAR_INPUTS = ("forcing", "theta0", "gamma", "height_ratio", "tip_load")
#: A state whose collocation residual exceeds this (relative to max(1, abs(Lambda))) is not
#: a root of the system of the profile given: refused.
_RESIDUAL_CHECK = 1e-6
_gradient: Any = None


def _kernel() -> Any:
    global _gradient
    if _gradient is None:
        from ._kernels import pillar_gradient

        _gradient = pillar_gradient
    return _gradient


def _profile_derivative(profile: Any, height_ratio: float | None) -> FloatArray | None:
    """Chebyshev coefficients of dU/d(L/H) of a channel profile; None for the others."""
    if height_ratio is None or callable(profile):
        return None
    if profile == "poiseuille":  # U = z - r z^2: dU/dr = -z^2 = -(3 + 4 t + T_2)/8
        return np.array([-3.0 / 8.0, -0.5, -1.0 / 8.0])
    return np.zeros(1)  # couette: U = z whatever L/H


def pillar_gradient_table(
    state: PillarState, profile: Any = "sublayer", height_ratio: float | None = None
) -> tuple[dict[str, dict[str, Any]], Any]:
    """({output: {input: d output/d input}}, status) of a PillarState solved with
    ``profile`` and ``height_ratio``.

    Inputs: forcing (Lambda), theta0, gamma, tip_load and, for a channel profile (a
    ``height_ratio`` given), height_ratio. status: 0 exact derivatives of the discrete state;
    1 at a fold (a singular Jacobian: NaN); -1 no state (NaN).
    """
    prof = profile_coefficients(profile, height_ratio)
    if height_ratio is not None:
        height_ratio = check_number(height_ratio, "height_ratio", low=0.0, high=1.0)
    dprof = _profile_derivative(profile, height_ratio)
    shape = state.shape_of_fields
    out, status, rmax = pillar_gradient_rows(
        state, prof[None, :], (np.zeros(1) if dprof is None else dprof)[None, :]
    )
    lam = np.broadcast_to(np.asarray(state.forcing, dtype=np.float64), shape).reshape(-1)
    ok = np.broadcast_to(np.asarray(state.status) >= 0, shape).reshape(-1)
    bad = ok & ~(rmax <= _RESIDUAL_CHECK * np.maximum(1.0, np.abs(lam)))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        where = f" (index {i})" if shape else ""
        raise ValueError(
            f"profile: the state{where} is not a state of profile {profile!r} with height_ratio "
            f"{height_ratio!r} (its collocation residual is {rmax[i]:.3g}): give the profile "
            "and height_ratio it was solved with"
        )
    inputs = [p for p in PILLAR_INPUTS if p != "height_ratio" or dprof is not None]
    table = {
        o: {p: scalar_or_array(out[i, PILLAR_INPUTS.index(p)].reshape(shape)) for p in inputs}
        for i, o in enumerate(PILLAR_OUTPUTS)
    }
    return table, scalar_or_array(status.reshape(shape))


def pillar_gradient_rows(
    state: Any, prof: FloatArray, dprof: FloatArray
) -> tuple[FloatArray, NDArray[np.int64], FloatArray]:
    """d(outputs)/d(inputs) of a PillarState whose profile is given per element.

    ``prof`` and ``dprof`` (1 or size rows, flat order of the state) are the Chebyshev
    coefficients of each state's profile U(z) and of its derivative dU/dq in a parameter q
    of the profile; the kernel ``_kernels.pillar_gradient`` (J du/dp = -dR/dp at the
    converged collocation) gives, in its "height_ratio" column, the derivatives in q.
    Returns (out of shape (NOUT, NIN, size) in the kernel's order; status 0, 1 at a fold
    (NaN there) or -1 without a state (NaN); the residual of each state's collocation
    system, the check that it is a state of this profile, 0 without a state). Each group
    of rows of one length (:func:`hairbed._core.wall_law.row_groups`) is one kernel call.
    """
    shape = state.shape_of_fields
    size = int(np.prod(shape, dtype=np.int64))

    def flat(v: Any) -> FloatArray:
        return np.ascontiguousarray(
            np.broadcast_to(np.asarray(v, dtype=np.float64), shape)
        ).reshape(-1)

    lam, t0, g, tip = (flat(v) for v in (state.forcing, state.theta0, state.gamma, state.tip_load))
    h1, a = flat(state.tip_height), flat(state._map)
    num = np.broadcast_to(np.asarray(state.num), shape).reshape(-1)
    ok = np.broadcast_to(np.asarray(state.status) >= 0, shape).reshape(-1)
    raw = np.asarray(state._coefs, dtype=np.float64)
    coefs = raw.reshape(3, size, raw.shape[-1])[0]
    k = _kernel()
    out = np.full((k.NOUT, k.NIN, size), np.nan)
    status = np.full(size, -1, dtype=np.int64)
    rmax = np.zeros(size)
    pr = np.ascontiguousarray(prof, dtype=np.float64)
    dpr = np.ascontiguousarray(dprof, dtype=np.float64)
    if pr.shape[0] == 1:
        pr = np.repeat(pr, size, axis=0)
    if dpr.shape[0] == 1:
        dpr = np.repeat(dpr, size, axis=0)
    key = np.maximum(_widths(pr), _widths(dpr))  # grouped by the longer of the two rows
    for n in np.unique(num[ok]):
        n = int(n)
        _, nodes, d1, d2, im, _ = _ladder((n,))
        for w in np.unique(key[ok & (num == n)]):
            sel = np.flatnonzero(ok & (num == n) & (key == w))
            part = np.empty((k.NOUT, k.NIN, sel.size))
            st = np.empty(sel.size, dtype=np.int64)
            rm = np.empty(sel.size)
            k.gradient_array(
                lam[sel],
                t0[sel],
                g[sel],
                tip[sel],
                a[sel],
                _nodal_values(coefs[sel], n),
                h1[sel],
                n,
                nodes[0],
                d1[0],
                d2[0],
                im[0],
                np.ascontiguousarray(pr[sel, : min(int(w), pr.shape[1])]),
                np.ascontiguousarray(dpr[sel, : min(int(w), dpr.shape[1])]),
                part,
                st,
                rm,
            )
            out[:, :, sel] = part
            status[sel] = st
            rmax[sel] = rm
    return out, status, rmax
