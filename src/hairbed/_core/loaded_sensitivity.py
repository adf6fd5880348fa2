"""Exact derivatives of loaded states (pressure and flow drives) in their inputs.

The implicit differentiation of the converged collocation system, J du/dp = -dR/dp, in the
compiled kernel ``_kernels.loaded_gradient``; this module hands it each state's node values
and assembles the table that :func:`hairbed.derivatives` returns (theory.md §11).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from .loaded import LoadedState, _ladder, _nodal_values
from .outputs import scalar_or_array

__all__ = ["LOADED_OUTPUTS", "loaded_gradient_table"]

FloatArray = NDArray[np.float64]

#: The outputs of a loaded state that are differentiated, in the kernel's order.
LOADED_OUTPUTS = (
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
    "tip_load",
    "distributed_load",
)
_CODES = {"pressure": 0, "flow": 1}
_gradient: Any = None


def _kernel() -> Any:
    global _gradient
    if _gradient is None:
        from ._kernels import loaded_gradient

        _gradient = loaded_gradient
    return _gradient


def loaded_gradient_table(
    state: LoadedState,
) -> tuple[dict[str, dict[str, Any]], Any]:
    """({output: {input: d output/d input}}, status) of a LoadedState.

    Inputs are omega2, eps, theta0 and the drive's load ("pi" or "q"). status: 0 exact
    derivatives of the discrete state; 1 at a fold (a singular Jacobian: +-inf); -1 no state
    (NaN).
    """
    load_name = "pi" if state.drive == "pressure" else "q"
    shape = state.shape_of_fields
    size = int(np.prod(shape, dtype=np.int64))

    def flat(v: Any) -> FloatArray:
        return np.ascontiguousarray(
            np.broadcast_to(np.asarray(v, dtype=np.float64), shape)
        ).reshape(-1)

    w, e, t0 = flat(state.omega2), flat(state.eps), flat(state.theta0)
    ld = flat(getattr(state, load_name))
    h1, a = flat(state.tip_height), flat(state._map)
    num = np.broadcast_to(np.asarray(state.num), shape).reshape(-1)
    ok = np.broadcast_to(np.asarray(state.status) >= 0, shape).reshape(-1)
    raw = np.asarray(state._coefs, dtype=np.float64)
    coefs = raw.reshape(3, size, raw.shape[-1])[0]  # not -1: an empty state has size 0
    k = _kernel()
    out = np.full((k.NOUT, k.NIN, size), np.nan)
    status = np.full(size, -1, dtype=np.int64)
    for n in np.unique(num[ok]):
        n = int(n)
        sel = np.flatnonzero(ok & (num == n))
        theta = _nodal_values(coefs[sel], n)
        _, nodes, d1, d2, im, _ = _ladder((n,))
        part = np.empty((k.NOUT, k.NIN, sel.size))
        st = np.empty(sel.size, dtype=np.int64)
        k.gradient_array(
            _CODES[state.drive],
            w[sel],
            e[sel],
            ld[sel],
            t0[sel],
            a[sel],
            theta,
            h1[sel],
            n,
            nodes[0],
            d1[0],
            d2[0],
            im[0],
            part,
            st,
        )
        out[:, :, sel] = part
        status[sel] = st
    inputs = ("omega2", "eps", load_name, "theta0")
    table = {
        o: {p: scalar_or_array(out[i, c].reshape(shape)) for c, p in enumerate(inputs)}
        for i, o in enumerate(LOADED_OUTPUTS)
    }
    return table, scalar_or_array(status.reshape(shape))
