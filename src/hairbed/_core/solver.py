"""The exact analytic solver: forward problem, every branch, every coexisting state.

The wrappers here validate, then hand whole arrays to the compiled kernels of
``hairbed._core._kernels`` (which trust their inputs), then wrap the kernels' columns in a
:class:`~hairbed.Solution`. Kernels are imported on first use, so importing hairbed
compiles (or loads from the cache) nothing.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .solution import Solution
from .validation import (
    HALF_PI,
    as_float_array,
    broadcast_named,
    check_branch,
    check_inputs,
    check_int,
    check_root,
    check_scalar_inputs,
    check_state_inputs,
)

__all__ = ["fold_parameters", "from_parameter", "from_xi", "solve", "solve_all"]

_ROOT_CODES = {"low": 0, "mid": 1, "high": 2}
#: Table of the physical branch's fold threshold eps_c over u = ln(1 + sin theta0).
_U_LO = -80.0
_U_NODES = 1025
#: Tables of Newton's start: ln(omega_eps^2) in [-8, 8] and theta0 in [-1.5, 1.5].
_X_LO, _X_HI, _DX = -8.0, 8.0, 1.0 / 16.0
_TH_MAX, _TH_NODES = 1.5, 129
#: The most values of n :func:`solve_all` searches without an explicit ``max_n``.
MAX_BRANCHES = 10_000
_state: Any = None
_table: tuple[Any, ...] | None = None


def _kernels() -> Any:
    """The kernel module, imported (compiled or loaded from the cache) on first use."""
    global _state
    if _state is None:
        from ._kernels import state

        _state = state
    return _state


def _tables() -> tuple[Any, ...]:
    """The process-wide tables of the kernels, built on first use (cached on disk).

    (u_lo, du, lower, t_c, start): lower[i] <= eps_c(u) on [u_i, u_i+1] over
    u = ln(1 + sin theta0), below which the physical branch is monotone (module docstring of
    ``_kernels.roots``; the margin covers the curvature of eps_c between nodes), t_c the
    minimiser of G; and ``start``, the eps = 0 tables of Newton's starting point
    (``_kernels.roots.start_table``). They are pure functions of the kernel sources, so they
    are kept beside the kernel cache under the kernel sources' hash (an edit rebuilds them);
    a table only steers where Newton starts and where folds are searched, never a result.
    """
    global _table
    if _table is None:
        from ._kernels import roots

        u = np.linspace(_U_LO, 0.0, _U_NODES)
        x = np.arange(_X_LO, _X_HI + 0.5 * _DX, _DX)
        th = np.linspace(-_TH_MAX, _TH_MAX, _TH_NODES)
        cached = _load_tables()
        if cached is not None and (
            cached["t_c"].shape != u.shape or cached["tab_t"].shape != (th.size, x.size)
        ):
            cached = None
        if cached is None:
            t_c, eps_c = roots.critical_table(u)
            tab_t, tab_h = roots.start_table(x, th)
            _save_tables(t_c=t_c, eps_c=eps_c, tab_t=tab_t, tab_h=tab_h)
        else:
            t_c, eps_c, tab_t, tab_h = (cached[k] for k in ("t_c", "eps_c", "tab_t", "tab_h"))
        left, right = eps_c[:-1], eps_c[1:]
        lower = np.minimum(left, right) - 0.05 * np.abs(right - left) - 1e-9
        lower = np.append(lower, lower[-1])
        start = (float(x[0]), float(x[1] - x[0]), float(th[0]), float(th[1] - th[0]), tab_t, tab_h)
        _table = (_U_LO, float(u[1] - u[0]), lower, t_c, start)
    return _table


def _tables_path() -> Any:
    from . import _jit
    from ._kernels import roots

    cache = getattr(roots.start_table, "_cache", None)
    path = getattr(cache, "cache_path", None)
    if not _jit.CACHE_ENABLED or not path:
        return None
    import hashlib
    from pathlib import Path

    # the grids are part of the key: tables built on other grids are never loaded
    grids = repr((_U_LO, _U_NODES, _X_LO, _X_HI, _DX, _TH_MAX, _TH_NODES)).encode()
    key = hashlib.sha256(_jit.kernel_sources_hash().encode() + grids).hexdigest()[:20]
    return Path(path) / f"tables-{key}.npz"


def _load_tables() -> Any:
    path = _tables_path()
    if path is None or not path.exists():
        return None
    try:
        with np.load(path) as data:
            return {k: np.array(data[k]) for k in ("t_c", "eps_c", "tab_t", "tab_h")}
    except (OSError, ValueError, KeyError):
        return None


def _save_tables(**arrays: Any) -> None:
    """Write the tables whole or not at all (temporary file, then rename)."""
    import os
    import tempfile
    from pathlib import Path

    path = _tables_path()
    if path is None:
        return
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".npz.tmp")
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    except OSError:
        Path(tmp).unlink(missing_ok=True)


_BIG_INT = 2**1000


def _scalar(value: Any) -> float | None:
    """A plain real number as a float (fast path of the validation), else None."""
    if type(value) is float or type(value) is np.float64:
        return float(value)
    if type(value) is int and -_BIG_INT < value < _BIG_INT:  # else float() overflows
        return float(value)
    return None


def _plain_inputs(omega2: Any, eps: Any, theta0: Any) -> tuple[float, float, float] | None:
    """(omega2, eps, theta0) as floats when all three are plain numbers in range, else None
    (then the full checks of ``check_inputs`` run, with their messages). Skipping numpy for
    the common scalar call is most of a scalar solve's speed."""
    w, e, th = _scalar(omega2), _scalar(eps), _scalar(theta0)
    if (
        w is not None
        and e is not None
        and th is not None
        and 0.0 <= w < math.inf
        and 0.0 <= e < 1.0
        and abs(th) < HALF_PI
    ):
        return w, e, th
    return None


def solve(
    omega2: ArrayLike,
    eps: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    sign: int = 1,
    n: int = 0,
    root: str = "low",
) -> Solution:
    """Solve the self-consistent boundary value problem of a boundary hair exactly.

    theta'' = -omega_eps^2 cos(theta), theta(0) = theta0, theta'(1) = 0, with
    omega_eps^2 = omega^2 / (1 - eps int_0^1 cos(theta)) (eqs. (3), (5),
    (6) of [1]_), reduced to one equation for the energy xi (eqs. (33), (34))
    and solved by a safeguarded Newton iteration in compiled code; the shape is then
    closed-form (eq. (32)).

    Parameters
    ----------
    omega2 : array_like
        Forcing omega^2 = pi a^2 L^2 eta v / (E I H phi) [-], >= 0.
    eps : array_like
        Confinement eps = L/H [-], in [0, 1).
    theta0 : array_like, optional
        Base angle from the vertical [rad], in (-pi/2, pi/2); positive leans with the flow.
    sign : {1, -1}, optional
        Sign of the base curvature theta'(0) of the branch. Default +1.
    n : int, optional
        Number of interior turning points of the branch, >= 0. Default 0. ``sign=1, n=0`` is
        the physical branch; every other branch twirls (the paper's index is n for sign +1 and
        -(n + 1) for sign -1).
    root : {"low", "mid", "high"}, optional
        Which state where the branch has several at these inputs (the bistable window of a hair
        leaning into the flow in a tight channel): "low" the smallest xi (reached by raising
        the flow slowly from rest), "high" the largest (reached by lowering it from strong
        flow), "mid" the middle one (NaN, status -1, where fewer than three exist).

    Returns
    -------
    Solution
        Float fields for scalar inputs, arrays of the broadcast shape otherwise; NaN value
        fields, ``status == -1`` and the branch's ``n_roots`` where the requested state does
        not exist.

    Raises
    ------
    ValueError
        For inputs outside their ranges, NaN, infinity or non-numbers; the message names the
        parameter, its range and, for arrays, the first offending index.

    References
    ----------
    .. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
       Deformation of a Boundary Hair", arXiv:2203.04169 (2022).

    Examples
    --------
    The paper's example, a vertical hair at omega^2 = 2 in a channel twice its length:

    >>> import hairbed
    >>> sol = hairbed.solve(2.0, 0.5)
    >>> round(sol.xi, 12), round(sol.tip_height, 12), round(sol.tip_deflection, 12)
    (0.847253916541, 0.732706963462, 0.615831536924)
    >>> round(float(sol.theta(1.0)), 12) == round(sol.tip_angle, 12)
    True
    """
    plain = _plain_inputs(omega2, eps, theta0)
    if plain is not None:
        w, e, th = plain
        sign, n = check_branch(sign, n)
        code = _ROOT_CODES[check_root(root)]
        row = _kernels().solve_scalar(w, e, th, sign, n, code, _tables())
        return Solution._from_row(row, e, th, sign, n, w)
    wa, ea, ta = check_inputs(omega2, eps, theta0)
    sign, n = check_branch(sign, n)
    code = _ROOT_CODES[check_root(root)]
    return _solve_arrays(wa, ea, ta, sign, n, code)


def _solve_arrays(
    w: np.ndarray, e: np.ndarray, t0: np.ndarray, sign: int, n: int, code: int
) -> Solution:
    k = _kernels()
    shape = w.shape
    wf, ef, tf = (np.ascontiguousarray(a).reshape(-1) for a in (w, e, t0))
    tables = _tables()
    need = k.needs_folds_array(ef, tf, sign, n, tables)
    idx = np.flatnonzero(need)
    pair = np.full(wf.size, -1, dtype=np.int64)
    if idx.size:
        ei, ti = ef[idx], tf[idx]
        if np.all(ei == ei[0]) and np.all(ti == ti[0]):
            ue, ut = ei[:1], ti[:1]
            pair[idx] = 0
        else:  # the folds depend on (eps, theta0) only: once per distinct pair
            keys, inverse = np.unique(np.stack([ei, ti], axis=1), axis=0, return_inverse=True)
            ue = np.ascontiguousarray(keys[:, 0])
            ut = np.ascontiguousarray(keys[:, 1])
            pair[idx] = inverse.reshape(-1)
        folds, counts = k.folds_array(ue, ut, sign, n, tables)
    else:
        folds = np.full((1, k.MAX_FOLDS), np.nan)
        counts = np.zeros(1, dtype=np.int64)
    out = np.empty((k.NFIELDS, wf.size))
    k.solve_array(wf, ef, tf, sign, n, code, pair, folds, counts, out, tables)
    return Solution._from_columns(out, shape, e, t0, sign, n, w)


def solve_all(
    omega2: float, eps: float, theta0: float = 0.0, *, max_n: int | None = None
) -> list[Solution]:
    """Every solution at scalar inputs, on every branch.

    A branch with n interior turning points needs omega_eps >= 2 n K >= n pi, and
    omega_eps^2 <= omega^2/(1 - eps) on every branch, so only n <= sqrt(omega^2/(1 - eps))/pi
    can have solutions; all of them are searched (or those with n <= ``max_n``).

    Parameters
    ----------
    omega2, eps, theta0 : float
        As in :func:`solve`, scalars.
    max_n : int, optional
        Search only branches with n <= max_n (default: every branch that can have a state;
        a ValueError where that is more than ``MAX_BRANCHES`` = 10^4 values of n, i.e.
        omega^2 above ~1e9 (1 - eps)).

    Returns
    -------
    list of Solution
        Ordered by branch, (sign=+1, n=0) first, then by increasing n with sign +1 before
        sign -1 at each n, and within a branch by increasing xi. ``physical`` is True only for
        the first entries (the physical branch).

    Examples
    --------
    >>> import hairbed
    >>> [(s.sign, s.n) for s in hairbed.solve_all(50.0, 0.5)]
    [(1, 0), (-1, 0), (1, 1)]
    """
    plain = _plain_inputs(omega2, eps, theta0)
    if plain is not None:
        wf, ef, tf = plain
    else:
        wf, ef, tf = check_scalar_inputs(omega2, eps, theta0)
    bound_f = math.floor(math.sqrt(wf) / math.sqrt(1.0 - ef) / math.pi) + 1.0
    if max_n is not None:
        bound = int(min(bound_f, check_int(max_n, "max_n", 0)))
    elif bound_f > MAX_BRANCHES:
        raise ValueError(
            f"omega2 = {wf!r} has states on {bound_f:.3g} branches (n <= sqrt(omega2/(1 - eps))"
            f"/pi); solve_all searches at most {MAX_BRANCHES} of them unless max_n is given"
        )
    else:
        bound = int(bound_f)
    rows, signs, ns = _kernels().solve_all_kernel(wf, ef, tf, bound, _tables())
    build = Solution._from_row
    return [
        build(r, ef, tf, s, k, wf) for r, s, k in zip(rows.tolist(), signs.tolist(), ns.tolist())
    ]


def from_parameter(
    t: ArrayLike, eps: ArrayLike, theta0: ArrayLike = 0.0, *, sign: int = 1, n: int = 0
) -> Solution:
    """The state on a branch at parameter t; omega2 is then an output (eq. (34)).

    The parameter is the logit of the energy's position in its range,
    xi - sin(theta0) = (1 - sin theta0) expit(t) and 1 - xi = (1 - sin theta0) expit(-t), so
    that both ends (weak forcing t -> -inf, strong forcing t -> +inf, where xi rounds to 1)
    keep full accuracy. This is the exact parametric curve of the branch.

    Parameters
    ----------
    t : array_like
        Branch parameter, a real number or -inf (the end xi = sin(theta0) of the branch: on
        the physical branch the undeformed hair). +inf (xi = 1 exactly) is not a state.
    eps, theta0 : array_like
        As in :func:`solve`.
    sign, n : int
        Branch label, as in :func:`solve`.

    Examples
    --------
    >>> import hairbed
    >>> round(hairbed.from_parameter(0.0, 0.5).xi, 12)
    0.5
    """
    tt = as_float_array(t, "t", allow_minus_inf=True)
    _, e, t0 = check_inputs(0.0, eps, theta0)
    sign, n = check_branch(sign, n)
    tt, e, t0 = broadcast_named(("t", tt), ("eps", e), ("theta0", t0))
    return _from_parameter(tt, e, t0, sign, n)


def _from_parameter(t: Any, eps: Any, theta0: Any, sign: int = 1, n: int = 0) -> Solution:
    """:func:`from_parameter` of checked inputs, trusted (root-finding loops call this one):
    t real or -inf, eps in [0, 1), |theta0| < pi/2, broadcastable; a valid branch label."""
    tt, e, t0 = (np.array(a, dtype=np.float64) for a in np.broadcast_arrays(t, eps, theta0))
    k = _kernels()
    out = np.empty((k.NFIELDS, tt.size))
    k.fields_array(tt.reshape(-1), e.reshape(-1), t0.reshape(-1), sign, n, out)
    return Solution._from_columns(out, tt.shape, e, t0, sign, n, None)


def _log_slope(t: Any, eps: Any, theta0: Any, sign: int = 1, n: int = 0) -> np.ndarray:
    """d ln(omega^2)/dt along the branch (sign, n) at checked, broadcastable t, eps, theta0:
    the kernel's exact slope (DLMF 19.4 derivatives of K and F), as an array of the broadcast
    shape."""
    tt, e, t0 = (np.array(a, dtype=np.float64) for a in np.broadcast_arrays(t, eps, theta0))
    out = np.empty(tt.size)
    _kernels().log_slope_array(tt.reshape(-1), e.reshape(-1), t0.reshape(-1), sign, n, out)
    return out.reshape(tt.shape)


def _solve_checked(
    omega2: Any, eps: Any, theta0: Any, sign: int = 1, n: int = 0, root: str = "low"
) -> Solution:
    """:func:`solve` of checked inputs, trusted: omega2 >= 0 finite, eps in [0, 1),
    |theta0| < pi/2, broadcastable; a valid branch label and root. Plain floats take the
    scalar kernel (bitwise the same states)."""
    code = _ROOT_CODES[root]
    if np.ndim(omega2) == 0 and np.ndim(eps) == 0 and np.ndim(theta0) == 0:
        wf, ef, tf = float(omega2), float(eps), float(theta0)
        row = _kernels().solve_scalar(wf, ef, tf, sign, n, code, _tables())
        return Solution._from_row(row, ef, tf, sign, n, wf)
    w, e, t0 = (np.array(a, dtype=np.float64) for a in np.broadcast_arrays(omega2, eps, theta0))
    return _solve_arrays(w, e, t0, sign, n, code)


def from_xi(
    xi: ArrayLike, eps: ArrayLike, theta0: ArrayLike = 0.0, *, sign: int = 1, n: int = 0
) -> Solution:
    """The state on a branch at a given energy xi in [sin theta0, 1); omega2 is an output.

    See :func:`from_parameter` for states so close to xi = 1 that xi cannot express them.

    Examples
    --------
    >>> import hairbed
    >>> sol = hairbed.from_xi(0.847253916541247, 0.5)
    >>> round(sol.omega2, 10)
    2.0
    """
    x, e, t0 = check_state_inputs(xi, "xi", eps, theta0)
    low = np.sin(t0)
    bad = (x < low) | (x >= 1.0)
    if np.any(bad):
        raise ValueError(
            f"xi must lie in [sin(theta0), 1), got {float(x[bad].flat[0])!r}"
            + ("" if x.ndim == 0 else f" (first at index {np.argwhere(bad)[0].tolist()})")
        )
    sign, n = check_branch(sign, n)
    with np.errstate(divide="ignore"):
        t = np.log(x - low) - np.log1p(-x)  # logit((xi - sin theta0)/(1 - sin theta0))
    return _from_parameter(t, e, t0, sign, n)  # checked: no second pass


def fold_parameters(eps: float, theta0: float = 0.0, *, sign: int = 1, n: int = 0) -> np.ndarray:
    """Branch parameters t of the folds of the branch (sign, n) at scalar (eps, theta0).

    The compiled fold search of :func:`solve` (one implementation); increasing.
    """
    _, e, t0 = check_scalar_inputs(eps=eps, theta0=theta0, given=("eps", "theta0"))
    sign, n = check_branch(sign, n)
    t, counts = _fold_table(np.array([e]), np.array([t0]), sign, n)
    return t[0, : counts[0]]


def _fold_table(
    eps: np.ndarray, theta0: np.ndarray, sign: int = 1, n: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """The folds of the branch (sign, n) at each pair of checked 1-D arrays (eps, theta0).

    The compiled fold search of :func:`solve` over all pairs in one call, the pairs where the
    branch is certainly monotone skipped. Returns (t, counts): t of shape (N, MAX_FOLDS),
    each row's ``counts[i]`` folds first and increasing, NaN after them.
    """
    k = _kernels()
    tables = _tables()
    t = np.full((eps.size, k.MAX_FOLDS), np.nan)
    counts = np.zeros(eps.size, dtype=np.int64)
    need = np.flatnonzero(k.needs_folds_array(eps, theta0, sign, n, tables))
    if need.size:
        folds, found = k.folds_array(eps[need], theta0[need], sign, n, tables)
        t[need] = np.sort(folds, axis=1)  # the NaN after the folds sort last
        counts[need] = found
    return t, counts
