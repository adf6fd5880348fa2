"""The exact analytic solver: forward problem, every branch, every coexisting state."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ._branch import branch_point, t_from_xi
from ._roots import MAX_ROOTS, find_roots
from ._validation import check_branch, check_inputs, check_root, check_state_inputs
from .solution import Solution

__all__ = ["from_parameter", "from_xi", "solve", "solve_all"]


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
    omega_eps^2 = omega^2 / (1 - eps int_0^1 cos(theta)) (eqs. {hairdiffeq}, {oe-givens},
    {eq:bcs} of [1]_), reduced to one equation for the energy xi ({solution2}, {solution3})
    and solved by a safeguarded Newton iteration; the shape is then closed-form ({solution}).

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
        leaning into the flow, math.md section 5): "low" the smallest xi (reached by raising
        the flow slowly from rest), "high" the largest (reached by lowering it from strong
        flow), "mid" the middle one (NaN where fewer than three exist).

    Returns
    -------
    Solution
        Float fields for scalar inputs, arrays of the broadcast shape otherwise; NaN value
        fields and ``n_roots == 0`` where the branch has no solution.

    Raises
    ------
    ValueError
        For inputs outside their ranges, NaN, infinity or non-numbers; the message names the
        parameter, its range and, for arrays, the first offending index.

    References
    ----------
    .. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
       Deformation of a Boundary Hair".

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
    w, e, t0 = check_inputs(omega2, eps, theta0)
    sign, n = check_branch(sign, n)
    root = check_root(root)
    shape = w.shape
    roots = find_roots(w.ravel(), e.ravel(), t0.ravel(), sign, n)
    count = np.sum(~np.isnan(roots), axis=1)
    if root == "low":
        t = roots[:, 0]
    elif root == "high":
        last = np.maximum(count - 1, 0)
        t = roots[np.arange(count.size), last]
    else:
        t = np.where(count >= 3, roots[:, min(1, MAX_ROOTS - 1)], np.nan)
    bp = branch_point(t.reshape(shape), e, t0, sign, n)
    return Solution._from_point(bp, omega2=w, n_roots=count.reshape(shape))


def solve_all(omega2: float, eps: float, theta0: float = 0.0) -> list[Solution]:
    """Every solution at scalar inputs, on every branch.

    Branches with n interior turning points need omega_eps >= 2nK, so only finitely many
    have solutions; they are searched in order of n until two consecutive n have none on
    either sign.

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
    w, e, t0 = check_inputs(omega2, eps, theta0)
    if w.ndim != 0:
        raise ValueError("solve_all takes scalar omega2, eps and theta0; use solve for arrays")
    out: list[Solution] = []
    empty_run = 0
    n = 0
    while empty_run < 2:
        found = False
        for sign in (1, -1):
            roots = find_roots(w.ravel(), e.ravel(), t0.ravel(), sign, n)[0]
            roots = roots[~np.isnan(roots)]
            for t in roots:
                bp = branch_point(np.asarray(t), e, t0, sign, n)
                out.append(Solution._from_point(bp, omega2=w, n_roots=roots.size))
                found = True
        empty_run = 0 if found else empty_run + 1
        n += 1
    return out


def from_parameter(
    t: ArrayLike, eps: ArrayLike, theta0: ArrayLike = 0.0, *, sign: int = 1, n: int = 0
) -> Solution:
    """The state on a branch at parameter t; omega2 is then an output ({solution3}).

    The parameter is the logit of the energy's position in its range,
    xi - sin(theta0) = (1 - sin theta0) expit(t) and 1 - xi = (1 - sin theta0) expit(-t), so
    that both ends (weak forcing t -> -inf, strong forcing t -> +inf, where xi rounds to 1)
    keep full accuracy. This is the exact parametric curve of the branch (math.md section 2).

    Parameters
    ----------
    t : array_like
        Branch parameter, any real number (-inf gives the undeformed hair on the physical
        branch).
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
    tt = np.asarray(t, dtype=np.float64) if not isinstance(t, str) else None
    if tt is None or (np.issubdtype(tt.dtype, np.floating) and np.any(np.isnan(tt))):
        raise ValueError("t must be a real number or array of real numbers (not NaN)")
    _, e, t0 = check_inputs(0.0, eps, theta0)
    sign, n = check_branch(sign, n)
    bp = branch_point(tt, e, t0, sign, n)
    return Solution._from_point(bp)


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
    return from_parameter(t_from_xi(x, t0), e, t0, sign=sign, n=n)
