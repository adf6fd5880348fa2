"""Compiled parts of the pillar's dynamics (issue 30, theory.md §13).

The linear response about a static state: the pencil (s E - A) in generalised Schur form,
Q^H (A, E) Z = (AA, BB) upper triangular, is solved at each frequency by back substitution
(O(n^2) a frequency, backward stable).
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel

__all__ = ["pencil_outputs", "pencil_solve"]


@kernel
def pencil_solve(aa, bb, g, sv, y):
    """y[f] of (sv[f] BB - AA) y[f] = g[f] for every frequency f (AA, BB upper triangular,
    complex (m, m); g, y complex (nf, m))."""
    m = aa.shape[0]
    for f in range(sv.size):
        s = sv[f]
        for i in range(m - 1, -1, -1):
            acc = g[f, i]
            for j in range(i + 1, m):
                acc -= (s * bb[i, j] - aa[i, j]) * y[f, j]
            y[f, i] = acc / (s * bb[i, i] - aa[i, i])


@kernel
def pencil_outputs(aa, bb, g, sv, cz, out):
    """out[r, f] = cz[r] . y(sv[f]) with (sv[f] BB - AA) y = g (one right-hand side g for
    every frequency; cz (rows, m) the outputs in the Schur basis; out complex (rows, nf))."""
    m = aa.shape[0]
    rows = cz.shape[0]
    y = np.empty(m, dtype=np.complex128)
    for f in range(sv.size):
        s = sv[f]
        for i in range(m - 1, -1, -1):
            acc = g[i]
            for j in range(i + 1, m):
                acc -= (s * bb[i, j] - aa[i, j]) * y[j]
            y[i] = acc / (s * bb[i, i] - aa[i, i])
        for r in range(rows):
            acc = 0.0j
            for i in range(m):
                acc += cz[r, i] * y[i]
            out[r, f] = acc
