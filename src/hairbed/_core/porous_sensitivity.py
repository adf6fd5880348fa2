"""Exact derivatives of porous-bed states in their inputs (theory.md §13).

A converged state u of the collocation system R(u, p) = 0 moves with the inputs p by the
implicit function theorem, J du/dp = -dR/dp, J the system's exact Jacobian (the kernel's,
``_kernels.porous.porous_jacobians``) and dR/dp written out here:

* omega2: the gap row, -1; pi (pressure drive): the stress rows, -(I_N - I_i)[cos theta],
  and the gap row, -u^2/(2 eps); q (flow drive): the flux row, -1; theta0: row 0, -1;
* kappa: the drag is proportional to 1/kappa, so the bending and stress rows' drag terms
  times -1/kappa;
* gamma: d f_x/d gamma = (w/kappa) sin^2, d f_z/d gamma = (w/kappa) sin cos, through the
  bending rows' F and the stress rows' f_x;
* eps: the gap row's d/d eps of eps w_N + u Q_N - Pi u^2/(2 eps) (u = 1 - eps h1), and the
  flux row's of 6 eps^2 Phi.

Each tip quantity's derivative follows from du/dp (x1 through I_N [cos theta du_theta]). The
states are grouped by their Chebyshev degree, each group one batched solve.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack

from .loaded import _clenshaw, _ladder, _matrices
from .outputs import scalar_or_array
from .porous import LADDER, PorousState, _description, _kernels

__all__ = ["PorousDerivatives", "porous_derivatives"]

FloatArray = NDArray[np.float64]

#: The outputs differentiated, in order.
OUTPUTS = (
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "tip_stress",
    "wall_stress",
    "tip_velocity",
    "drag_x",
    "pi",
)


@dataclass(frozen=True)
class PorousDerivatives:
    """d(output)/d(input) of porous states (:func:`porous_derivatives`).

    Attributes
    ----------
    table : dict
        ``table[output][input]``: float or array of the states' shape. Outputs
        :data:`OUTPUTS` (``pi`` for the flow drive only, where it is solved); inputs
        omega2, eps, theta0, kappa, gamma and pi (pressure drive) or q (flow drive).
    status : int or ndarray
        The states' own status; NaN derivatives where it is negative or J is singular (a
        fold: status 1 there).
    """

    table: dict[str, dict[str, Any]]
    status: Any


def _nodal(state: PorousState, num: int, sel: NDArray[np.bool_]) -> FloatArray:
    """theta, w, Q at the N + 1 nodes of each selected state, then h1 and Pi."""
    coefs = state._coefs.reshape(5, -1, state._coefs.shape[-1])[:, sel, : num + 1]
    xi = np.broadcast_to(_matrices(num)[0], (coefs.shape[1], num + 1))
    n1 = num + 1
    u = np.empty((coefs.shape[1], 3 * n1 + 2))
    for c, field in enumerate((0, 3, 4)):
        u[:, c * n1 : (c + 1) * n1] = _clenshaw(coefs[field], xi)
    u[:, 3 * n1] = np.asarray(state.tip_height, dtype=np.float64).reshape(-1)[sel]
    u[:, 3 * n1 + 1] = np.asarray(state.pi, dtype=np.float64).reshape(-1)[sel]
    return np.ascontiguousarray(u)


def porous_derivatives(state: PorousState, *, flux: bool = False) -> PorousDerivatives:
    """Exact derivatives of every tip quantity of porous states in every input.

    Parameters
    ----------
    state : PorousState
        From :func:`hairbed.solve_porous` or :func:`hairbed.solve_porous_all` (not the
        inverse's, whose forcing is an output).
    flux : bool, optional
        Also the output "flux": the flux through bed and gap per unit width in load units,
        Phi = int_0^1 w cos(theta) ds + w_1 g + Q_1 g^2/2 - Pi g^3/6, g = 1/eps - h1 (the
        bed's part by the collocation's integration; theory.md §13), which sets the flow
        rate Q' = E I Phi/(eta A) of a channel (:func:`hairbed.valve.valve_curve`).

    Returns
    -------
    PorousDerivatives

    Examples
    --------
    >>> import hairbed
    >>> d = porous_derivatives(hairbed.solve_porous(2.0, 0.5, 0.3, kappa=0.1))
    >>> round(d.table["tip_deflection"]["omega2"], 8)
    0.08698963
    """
    if not isinstance(state, PorousState):
        raise TypeError(f"state must be a hairbed.PorousState, got {type(state).__name__}")
    code = 1 if state.drive == "flow" else 0
    load = "q" if code else "pi"
    inputs = ("omega2", "eps", "theta0", "kappa", "gamma", load)
    shape = state.shape_of_fields
    size = int(np.prod(shape, dtype=np.int64))
    flat = {
        k: np.broadcast_to(np.asarray(getattr(state, k), dtype=np.float64), shape).reshape(-1)
        for k in ("omega2", "eps", "theta0", "kappa", "gamma", "pi", "q")
    }
    status = np.asarray(state.status).reshape(-1)
    nums = np.asarray(state.num).reshape(-1)
    amap = np.asarray(state._map, dtype=np.float64).reshape(-1)
    outputs = (OUTPUTS if code else OUTPUTS[:-1]) + (("flux",) if flux else ())
    table = {o: {i: np.full(size, np.nan) for i in inputs} for o in outputs}
    out_status = status.copy()
    ladder = _ladder(LADDER)
    for num in np.unique(nums[status >= 0]):
        sel = (status >= 0) & (nums == num)
        lev = LADDER.index(int(num)) if int(num) in LADDER else None
        if lev is None:  # a fixed N outside the ladder: its own operators
            nodes, d1, d2, im = (np.asarray(m) for m in _matrices(int(num))[:4])
        else:
            nodes = ladder[1][lev, : num + 1]
            d1, d2, im = (ladder[k][lev, : num + 1, : num + 1] for k in (2, 3, 4))
        _group(code, int(num), sel, state, flat, amap, nodes, d1, d2, im, table, out_status, flux)
    return PorousDerivatives(
        table={
            o: {i: scalar_or_array(v.reshape(shape)) for i, v in r.items()}
            for o, r in table.items()
        },  # fmt: skip
        status=scalar_or_array(out_status.reshape(shape)),
    )


#: The largest condition number (1-norm, LAPACK's estimate) of a state's Jacobian J with
#: finite derivatives; above it the state is at a fold, where they are infinite.
COND_FOLD = 1e14


def _solve_checked(jac: FloatArray, rhs: FloatArray, out: FloatArray) -> bool:
    """out = -J^-1 rhs (m x m, m x k) from one LU factorisation (LAPACK getrf, the right-hand
    sides one at a time by getrs: triangular solves of one column, which OpenBLAS runs on one
    thread); False (out left as it is) where J is not finite or at a fold: its condition
    number kappa_1(J) = ||J||_1 ||J^-1||_1, estimated from the factors by LAPACK's gecon
    (Hager-Higham, within a small factor of the true one, O(m^2)), at least :data:`COND_FOLD`
    (or a pivot vanishes)."""
    if not np.all(np.isfinite(jac)):
        return False
    lu, piv, info = lapack.dgetrf(jac)
    if info != 0:  # a zero pivot: singular
        return False
    norm = float(np.max(np.sum(np.abs(jac), axis=0)))
    rcond, info = lapack.dgecon(lu, norm, norm="1")
    if info != 0 or not rcond * COND_FOLD > 1.0:
        return False
    for k in range(rhs.shape[1]):
        x, info = lapack.dgetrs(lu, piv, rhs[:, k])
        out[:, k] = -x
    return True


def _group(
    code: int,
    num: int,
    sel: NDArray[np.bool_],
    state: PorousState,
    flat: dict[str, FloatArray],
    amap: FloatArray,
    nodes: Any,
    d1: Any,
    d2: Any,
    im: Any,
    table: dict[str, dict[str, FloatArray]],
    out_status: Any,
    flux: bool = False,
) -> None:
    """The derivatives of the states of one Chebyshev degree, in place into ``table``."""
    n1 = num + 1
    hi = 3 * n1
    m = hi + 2 if code else hi + 1
    u = _nodal(state, num, sel)
    count = u.shape[0]
    jac = np.zeros((count, m, m))
    ii = np.empty((count, n1, n1))
    pick = {key: np.ascontiguousarray(v[sel]) for key, v in flat.items()}
    pi_in = pick["pi"] if code == 0 else np.zeros(count)
    arrays = tuple(pick[key] for key in ("omega2", "eps", "theta0", "kappa", "gamma"))
    desc = _description(code, (*arrays, pick["q"] if code else pi_in), np.full(count, np.nan))
    _kernels().porous_jacobians(
        code,
        u,
        num,
        np.ascontiguousarray(amap[sel]),
        np.ascontiguousarray(nodes),
        np.ascontiguousarray(d1),
        np.ascontiguousarray(d2),
        np.ascontiguousarray(im),
        desc,
        jac,
        ii,
    )
    th, w, qq = u[:, :n1], u[:, n1 : 2 * n1], u[:, 2 * n1 : hi]
    h = u[:, hi]
    pi_l = u[:, hi + 1] if code else pi_in
    kap, gam, eps = pick["kappa"][:, None], pick["gamma"][:, None], pick["eps"]
    c, s = np.cos(th), np.sin(th)
    fx = w / kap * (c * c + gam * s * s)
    fz = -w / kap * (1.0 - gam) * s * c
    last = ii[:, num, :]  # I_N
    rest = last[:, None, :] - ii  # r_ij = I_N[j] - I_i[j]
    big_fx = np.einsum("eij,ej->ei", rest, fx)
    big_fz = np.einsum("eij,ej->ei", rest, fz)
    uu = 1.0 - eps * h
    rhs = np.zeros((count, m, 6))  # dR/dp: omega2, eps, theta0, kappa, gamma, load
    rhs[:, 2 * n1 + num, 0] = -1.0
    # eps: the gap row (and the flux row of the flow drive)
    safe = np.where(eps > 0.0, eps, 1.0)
    gap_eps = w[:, num] - h * qq[:, num]
    gap_eps += np.where(pi_l != 0.0, pi_l * (uu * h / safe + uu * uu / (2.0 * safe**2)), 0.0)
    rhs[:, 2 * n1 + num, 1] = gap_eps
    rhs[:, 0, 2] = -1.0
    # kappa: every drag term scales with 1/kappa
    inner = slice(1, num)
    rhs[:, inner, 3] = -(big_fx[:, inner] * c[:, inner] - big_fz[:, inner] * s[:, inner]) / kap
    rhs[:, 2 * n1 : 2 * n1 + num, 3] = -big_fx[:, :num] / kap
    # gamma
    gx = w / kap * s * s
    gz = w / kap * s * c
    bgx = np.einsum("eij,ej->ei", rest, gx)
    bgz = np.einsum("eij,ej->ei", rest, gz)
    rhs[:, inner, 4] = bgx[:, inner] * c[:, inner] - bgz[:, inner] * s[:, inner]
    rhs[:, 2 * n1 : 2 * n1 + num, 4] = bgx[:, :num]
    if code == 0:  # pi: the stress rows and the gap row
        rhs[:, 2 * n1 : 2 * n1 + num, 5] = -np.einsum("eij,ej->ei", rest, c)[:, :num]
        rhs[:, 2 * n1 + num, 5] = np.where(eps > 0.0, -uu * uu / (2.0 * safe), 0.0)
    else:  # q: the flux row; eps in the flux row
        g = 1.0 / safe - h
        phi = np.einsum("ej,ej->e", last, w * c) + w[:, num] * g + qq[:, num] * g**2 / 2.0
        phi -= pi_l * g**3 / 6.0
        rhs[:, hi + 1, 1] = 12.0 * eps * phi - 6.0 * (
            w[:, num] + qq[:, num] * g - pi_l * g * g / 2.0
        )
        rhs[:, hi + 1, 5] = -1.0
    du = np.full((count, m, 6), np.nan)
    good = np.zeros(count, dtype=bool)
    for e in range(count):
        good[e] = _solve_checked(jac[e], rhs[e], du[e])
    dth = du[:, :n1, :]
    values = {
        "tip_height": du[:, hi, :],
        "tip_deflection": np.einsum("ej,ej,ejp->ep", last, c, dth),
        "tip_angle": du[:, num, :],
        "tip_stress": du[:, 2 * n1 + num, :],
        "wall_stress": du[:, 2 * n1, :],
        "tip_velocity": du[:, n1 + num, :],
    }
    # drag_x = I_N [f_x]: through theta, w, kappa and gamma
    dfx_dth = -2.0 * w / kap * (1.0 - gam) * s * c
    dfx_dw = (c * c + gam * s * s) / kap
    dfx = dfx_dth[:, :, None] * dth + dfx_dw[:, :, None] * du[:, n1 : 2 * n1, :]
    drag = np.einsum("ej,ejp->ep", last, dfx)
    drag[:, 3] -= np.einsum("ej,ej->e", last, fx) / kap[:, 0]
    drag[:, 4] += np.einsum("ej,ej->e", last, gx)
    values["drag_x"] = drag
    if code:
        values["pi"] = du[:, hi + 1, :]
    if flux:  # Phi = I_N[w cos] + w_N g + Q_N g^2/2 - Pi g^3/6, g = 1/eps - h1
        dw = du[:, n1 : 2 * n1, :]
        gg = (1.0 / safe - h)[:, None]
        dg = -du[:, hi, :]
        dg[:, 1] -= 1.0 / safe**2
        dpi = du[:, hi + 1, :] if code else np.zeros((count, 6))
        if not code:
            dpi[:, 5] = 1.0
        wn, qn = w[:, num][:, None], qq[:, num][:, None]
        values["flux"] = (
            np.einsum("ej,ejp->ep", last, c[:, :, None] * dw - (w * s)[:, :, None] * dth)
            + du[:, n1 + num, :] * gg
            + wn * dg
            + du[:, 2 * n1 + num, :] * gg * gg / 2.0
            + qn * gg * dg
            - dpi * gg**3 / 6.0
            - pi_l[:, None] * gg * gg * dg / 2.0
        )
    names = ("omega2", "eps", "theta0", "kappa", "gamma", "q" if code else "pi")
    idx = np.flatnonzero(sel)
    for out_name, arr in values.items():
        for p, name in enumerate(names):
            table[out_name][name][idx] = arr[:, p]
    out_status[idx[~good]] = 1
