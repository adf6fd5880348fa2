"""The slow reference every fast path must match (stumpy's ``tests/naive.py`` practice).

This package is the numpy implementation of hairbed's analytic core as it stood at commit
7300965, before the numba kernels: ``elliptic``, ``branch`` and ``roots`` are verbatim copies
of ``src/hairbed/_elliptic.py``, ``_branch.py`` and ``_roots.py`` (imports made relative,
``t_from_xi`` removed), and the functions below redo the array code of ``hairbed.solve`` and
``hairbed.Solution``. It imports numpy and scipy only, never hairbed, so it stays fixed while
src/ changes. Inputs are assumed valid (no checking) and are broadcast; results are plain
dicts of float arrays (0-d for scalar inputs).

It is accurate to about 1e-13 over the parameter space, except in these known corners, which
the tests comparing with it must avoid:

- theta0 within 1e-5 of -pi/2: ``roots`` misses roots;
- theta0 within 1e-6 of +pi/2: the shapes theta, x, z are wrong;
- omega2 < 1e-10: the shapes lose relative accuracy;
- t = +-inf (the branch ends), and omega2 below 1e-300.

Import it from a test module as ``from naive import naive_solve`` (pytest puts tests/ on
sys.path).

Examples
--------
>>> r = naive_solve(2.0, 0.5)
>>> round(float(r["xi"]), 12), int(r["n_roots"])
(0.847253916541, 1)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .branch import BranchPoint, branch_point, shape_terms, tip_deflection
from .roots import MAX_ROOTS, find_roots

__all__ = [
    "FIELDS",
    "naive_from_parameter",
    "naive_roots",
    "naive_shape",
    "naive_solve",
    "naive_solve_all",
]

#: The value fields of a state, NaN where there is no solution (as in ``hairbed.Solution``).
FIELDS = (
    "xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
)


def _floats(*arrays: Any) -> list[np.ndarray]:
    return [np.asarray(a, dtype=np.float64) for a in np.broadcast_arrays(*arrays)]


def _state(bp: BranchPoint, omega2: np.ndarray, n_roots: np.ndarray) -> dict[str, Any]:
    """The fields of ``Solution._from_point`` (t = NaN marks 'no solution')."""
    missing = np.isnan(bp.t)
    with np.errstate(invalid="ignore", divide="ignore"):
        values = {
            "xi": bp.xi,
            "omega_eps": bp.omega_eps,
            "energy": bp.energy,
            "tip_height": bp.tip_height,
            "tip_deflection": tip_deflection(bp),
            "tip_angle": bp.tip_angle,
            "base_curvature": bp.base_curvature,
        }
    out: dict[str, Any] = {k: np.where(missing, np.nan, v) for k, v in values.items()}
    out["n_roots"] = np.broadcast_to(np.asarray(n_roots, dtype=np.int64), bp.t.shape).copy()
    out["t"] = np.array(bp.t, dtype=np.float64)
    out["omega2"] = np.array(omega2, dtype=np.float64)
    out["eps"] = np.array(bp.eps)
    out["theta0"] = np.array(bp.theta0)
    out["sign"] = bp.sign
    out["n"] = bp.n
    out["physical"] = (bp.sign == 1) & (bp.n == 0) & ~missing
    return out


def naive_roots(omega2: Any, eps: Any, theta0: Any, sign: int, n: int) -> np.ndarray:
    """Every root t of the branch (sign, n): shape ``broadcast + (3,)``, increasing, NaN-padded."""
    w, e, t0 = _floats(omega2, eps, theta0)
    roots = find_roots(w.ravel(), e.ravel(), t0.ravel(), sign, n)
    return roots.reshape(w.shape + (MAX_ROOTS,))


def naive_solve(
    omega2: Any, eps: Any, theta0: Any = 0.0, sign: int = 1, n: int = 0, root: str = "low"
) -> dict[str, Any]:
    """The state ``hairbed.solve(omega2, eps, theta0, sign=sign, n=n, root=root)`` returns.

    Keys: the value fields of :data:`FIELDS`, ``n_roots`` (roots of the branch at the inputs,
    whichever ``root`` is selected; 0 where there is none), ``t`` (the branch parameter, NaN
    where the selected root does not exist), and the inputs ``omega2``, ``eps``, ``theta0``,
    ``sign``, ``n`` and ``physical``.
    """
    w, e, t0 = _floats(omega2, eps, theta0)
    roots = naive_roots(w, e, t0, sign, n).reshape(-1, MAX_ROOTS)
    count = np.sum(~np.isnan(roots), axis=1)
    if root == "low":
        t = roots[:, 0]
    elif root == "high":
        t = roots[np.arange(count.size), np.maximum(count - 1, 0)]
    elif root == "mid":
        t = np.where(count >= 3, roots[:, 1], np.nan)
    else:
        raise ValueError(f"root must be 'low', 'mid' or 'high', got {root!r}")
    bp = branch_point(t.reshape(w.shape), e, t0, sign, n)
    return _state(bp, w, count.reshape(w.shape))


def naive_from_parameter(
    t: Any, eps: Any, theta0: Any = 0.0, sign: int = 1, n: int = 0
) -> dict[str, Any]:
    """The state ``hairbed.from_parameter(t, eps, theta0, sign=sign, n=n)`` returns.

    Same keys as :func:`naive_solve`, with ``omega2`` an output and ``n_roots`` 1 (0 where t is
    NaN).
    """
    tt, e, t0 = _floats(t, eps, theta0)
    bp = branch_point(tt, e, t0, sign, n)
    return _state(bp, bp.omega2, np.where(np.isnan(tt), 0, 1))


def naive_shape(
    t: Any, eps: Any, theta0: Any, sign: int, n: int, sigma: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """theta, x, z at arc length sigma of the state at parameter t of branch (sign, n).

    ``t`` is the ``"t"`` of a :func:`naive_solve` or :func:`naive_from_parameter` result (NaN
    gives NaN). sigma is broadcast against the state, as in ``Solution.theta``; for
    ``Solution.profile`` pass the state arrays with a trailing axis of length 1.
    """
    bp = branch_point(t, eps, theta0, sign, n)
    s = np.asarray(sigma, dtype=np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        return shape_terms(bp, s)


def naive_solve_all(omega2: float, eps: float, theta0: float = 0.0) -> list[dict[str, Any]]:
    """Every state ``hairbed.solve_all`` returns, in its order, as 0-d :func:`naive_solve` dicts.

    Branches in order of n, sign +1 before -1 at each n, roots by increasing t (increasing xi);
    the search stops after two consecutive n without a solution on either sign.
    """
    w, e, t0 = _floats(omega2, eps, theta0)
    out: list[dict[str, Any]] = []
    empty_run = 0
    n = 0
    while empty_run < 2:
        found = False
        for sign in (1, -1):
            roots = find_roots(w.ravel(), e.ravel(), t0.ravel(), sign, n)[0]
            roots = roots[~np.isnan(roots)]
            for t in roots:
                bp = branch_point(np.asarray(t), e, t0, sign, n)
                out.append(_state(bp, w, np.asarray(roots.size)))
                found = True
        empty_run = 0 if found else empty_run + 1
        n += 1
    return out
