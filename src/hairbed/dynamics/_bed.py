"""The porous bed in time: its semi-discrete system and its operators (issue 30, theory.md §15).

The system M y' = g(t, y) (a constant diagonal mass vector M, an index-1 DAE; index 2 only
for Pi under a set flow rate with fluid inertia) is the compiled
:func:`hairbed._core._kernels.bed.bed_system`, on the statics' Chebyshev collocation
(:func:`hairbed.solve_porous`'s mapped nodes and operators) with the gap on a grid of its
own. This module builds its parameters, the steady vector of a :class:`PorousState` and
:func:`bed_operators`, the linear operators about that state.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core.loaded import _matrices
from .._core.porous import PorousState
from .._core.validation import check_int, check_number
from ._signals import Signal, constant

__all__ = ["BED_OUTPUTS", "BedOperators", "bed_operators"]

FloatArray = NDArray[np.float64]

#: The outputs of the bed, in the order of :attr:`BedOperators.outputs` and of a trajectory.
BED_OUTPUTS = ("tip_deflection", "tip_height", "base_moment", "wall_stress", "flow_rate")
_TOPS = {"wall": 0, "wall_stress": 1}
_PUMPS = {"pressure": 0, "flow_rate": 1}
#: The gap's degree where the fluid has no inertia (its exact profile is used instead).
_NO_GAP = 2


@dataclass(frozen=True)
class _Layout:
    """The offsets of y's blocks (theory.md §15; ``_kernels.bed.bed_layout``); -1 absent."""

    n: int
    omega: int
    accel: int
    v: int
    stress: int
    gap: int
    pi: int
    size: int


@dataclass(frozen=True)
class _System:
    """One bed's compiled system: the kernel's parameter tuple and what the outputs need."""

    params: tuple[Any, ...]
    layout: _Layout
    num: int
    num_gap: int
    s: FloatArray
    zeta: FloatArray
    d0: FloatArray
    top: int
    pump: int
    kappa: float
    eps: float
    alpha: float
    mu: float


def _kern() -> Any:
    from .._core._kernels import bed

    return bed


def _system(
    num: int,
    a: float,
    num_gap: int,
    theta0: float,
    gamma: float,
    chi: float,
    mu: float,
    kappa: float,
    eps: float,
    alpha: float,
    top: int,
    pump: int,
    top_sig: Signal,
    pump_sig: Signal,
) -> _System:
    """The kernel's parameters of one bed (degree N on the statics' map a, gap degree M)."""
    from ._integrate import _operators_at

    ss, _sp, dd, ii, d0, d1s = _operators_at(num, a)
    srow = -dd[num, :] / dd[num, num]
    srow[num] = 0.0
    ngap = num_gap if alpha > 0.0 else _NO_GAP
    x, d1, d2, im, _ = _matrices(ngap)
    zeta = 0.5 * (x + 1.0)
    dz = np.ascontiguousarray(2.0 * d1)
    dz2 = np.ascontiguousarray(4.0 * d2)
    wz = np.ascontiguousarray(0.5 * im[ngap])
    drives = np.stack([top_sig.row(), pump_sig.row()])
    tk = max(top_sig.times.size, pump_sig.times.size, 1)
    tabs = np.zeros((4, tk))
    for r, sig in ((0, top_sig), (2, pump_sig)):
        if sig.times.size:
            tabs[r, : sig.times.size] = sig.times
            tabs[r + 1, : sig.times.size] = sig.values
            tabs[r, sig.times.size :] = sig.times[-1] + np.arange(1, tk - sig.times.size + 1)
            tabs[r + 1, sig.times.size :] = sig.values[-1]
        else:
            tabs[r] = np.arange(tk, dtype=np.float64)
    ints = np.array([num, ngap, top, pump], dtype=np.int64)
    flts = np.array([theta0, gamma, chi, mu, kappa, eps, alpha], dtype=np.float64)
    params = (ints, flts, dd, ii, d1s, srow, dz, dz2, wz, zeta, drives, tabs)
    lay = _Layout(*(int(v) for v in _kern().bed_layout(num, ngap, mu, alpha, pump)))
    return _System(params, lay, num, ngap, ss, zeta, d0, top, pump, kappa, eps, alpha, mu)


def _evaluate(sys: _System, t: float, y: FloatArray, need: bool) -> tuple[bool, Any, Any]:
    """(ok, g, J) at (t, y); J only where ``need``."""
    k = _kern()
    m = sys.layout.size
    out = np.empty(m)
    jac = np.zeros((m, m))
    ws = k.bed_workspace(sys.num, sys.num_gap)
    ok = k.bed_system(float(t), np.ascontiguousarray(y, dtype=np.float64), need, sys.params,
                      out, jac, ws)  # fmt: skip
    return bool(ok), out, (jac if need else None)


def _mass(sys: _System) -> FloatArray:
    out = np.empty(sys.layout.size)
    _kern().bed_mass(sys.num, sys.num_gap, sys.mu, sys.alpha, sys.kappa, sys.pump, out)
    return out


def _angles(sys: _System, y: Any) -> Any:
    """theta at the N + 1 nodes of states y (..., size): the boundary values restored."""
    num = sys.num
    srow = sys.params[5]
    theta0 = float(sys.params[1][0])
    yy = np.asarray(y)
    th = np.empty((*yy.shape[:-1], num + 1), dtype=yy.dtype)
    th[..., 0] = theta0
    th[..., 1:num] = yy[..., : num - 1]
    th[..., num] = th[..., :num] @ srow[:num]
    return th


def _output_values(sys: Any, y: Any, pump_value: Any) -> dict[str, Any]:
    """The outputs of states y (..., size), real or complex (the complex step of
    :func:`bed_operators`): x1, h1, theta'(0), the top wall's stress Q(H) (load units of
    §13), the flow rate q = 6 eps^2 Phi, Pi. ``pump_value``: Pi (pressure drive) or q."""
    lay = sys.layout
    num = sys.num
    ii = sys.params[3]
    th = _angles(sys, y)
    c, s = np.cos(th), np.sin(th)
    yy = np.asarray(y)
    x1 = s @ ii[num]
    h1 = c @ ii[num]
    gg = 1.0 / sys.eps - h1
    v = np.zeros((*yy.shape[:-1], num + 1), dtype=yy.dtype)
    v[..., 1:] = yy[..., lay.v : lay.v + num]
    qn = yy[..., lay.stress + num]
    pi = yy[..., lay.pi] if sys.pump == 1 else pump_value
    kap = sys.kappa
    bedflux = kap * ((v * c) @ ii[num])
    if sys.alpha > 0.0:
        ngap = sys.num_gap
        vg = np.concatenate([v[..., num : num + 1], yy[..., lay.gap : lay.gap + ngap]], axis=-1)
        dz, wz = sys.params[6], sys.params[8]
        top = kap * (vg @ dz[ngap]) / gg
        flux = bedflux + kap * gg * (vg @ wz)
    else:
        top = qn - pi * gg
        flux = bedflux + kap * v[..., num] * gg + qn * gg * gg / 2.0 - pi * gg**3 / 6.0
    return {
        "tip_deflection": x1,
        "tip_height": h1,
        "base_moment": th @ sys.d0,
        "wall_stress": top,
        "flow_rate": 6.0 * sys.eps**2 * flux,
        "pressure": pi if sys.pump == 1 else pi + 0.0 * x1,
    }


def _steady_guess(sys: _System, state: PorousState) -> FloatArray:
    """y of a static state interpolated to the system's nodes, at rest."""
    lay = sys.layout
    num = sys.num
    y = np.zeros(lay.size)
    _, _, _, theta = state.shape(sys.s)
    _, _, w, q = state.fluid(sys.s)
    th = np.asarray(theta, dtype=np.float64)
    y[: num - 1] = th[1:num]
    v = np.asarray(w, dtype=np.float64) / sys.kappa
    y[lay.v : lay.v + num] = v[1:]
    y[lay.stress : lay.stress + num + 1] = np.asarray(q, dtype=np.float64)
    pi = float(state.pi)
    if lay.gap >= 0:
        h1 = float(np.cos(th) @ sys.params[3][num])
        gg = 1.0 / sys.eps - h1
        zg = sys.zeta[1:] * gg
        y[lay.gap : lay.gap + sys.num_gap] = (
            v[num] + float(q[num]) * zg / sys.kappa - pi * zg * zg / (2.0 * sys.kappa)
        )
    if lay.pi >= 0:
        y[lay.pi] = pi
    return y


def _newton_steady(sys: _System, y: FloatArray, t: float, tol: float = 1e-14) -> FloatArray:
    """Newton on g(t, y) = 0 (the steady state of the discrete system at the drives' values
    at t), with the exact Jacobian; raises ArithmeticError where it does not converge."""
    y = y.copy()
    scale = 1.0 + np.abs(y)
    for _ in range(30):
        ok, g, jac = _evaluate(sys, t, y, True)
        if not ok:
            break
        step = np.linalg.solve(jac, -g)
        y += step
        if np.max(np.abs(step) / scale) <= tol:
            ok, g, _ = _evaluate(sys, t, y, False)
            if ok:
                return y
            break
    raise ArithmeticError("the bed's steady state did not converge on the dynamics' grid")


@dataclass(frozen=True)
class BedOperators:
    """The linear operators of the semi-discrete bed about a steady state (theory.md §15).

    M y' = g(t, y) linearised about the steady y* under constant drives d*:
    M dy' = J dy + sum_d b_d dd(t), and each output o = o* + c_o . dy.

    Attributes
    ----------
    mass : ndarray
        The diagonal of M (size,) [-]: 1 for the angles (and the rates with inertia),
        alpha kappa for the fluid's velocities away from the boundaries, 0 on the algebraic
        rows.
    jacobian : ndarray
        J = dg/dy at (y*, d*), (size, size), exact.
    drives : mapping of str to ndarray
        dg/dd of each drive of the state: "wall" (omega2, the top wall's speed in the units
        of §13) and "pressure" (Pi) or "flow_rate" (q).
    steady : ndarray
        y*, the steady state of the discrete system (its g vanishes to rounding).
    outputs : mapping of str to ndarray
        The rows c_o (size,) of ``BED_OUTPUTS``: tip_deflection [L], tip_height [L],
        base_moment theta'(0) [E I/L], wall_stress (the top wall's shear stress Q(H), load
        units of §13) and flow_rate (q, §11's units).
    output_values : mapping of str to float
        o* at y* (and "pressure", Pi).
    layout : mapping of str to int
        The offsets of y's blocks: theta, omega (the rates), accel (-1 without inertia), v
        (the bed's fluid at nodes 1 .. N), stress (Q at nodes 0 .. N), gap (-1 at alpha = 0),
        pi (-1 unless the flow drive), size.
    s : ndarray
        The hair's nodes [L] (N + 1).
    zeta : ndarray
        The gap's nodes in [0, 1] (M + 1; a placeholder at alpha = 0).
    num, num_gap : int
        N and M.
    inertia, tangential_mass, womersley, kappa, eps, gamma, theta0 : float
        The model's constants.
    """

    mass: FloatArray
    jacobian: FloatArray
    drives: Mapping[str, FloatArray]
    steady: FloatArray
    outputs: Mapping[str, FloatArray]
    output_values: Mapping[str, float]
    layout: Mapping[str, int]
    s: FloatArray
    zeta: FloatArray
    num: int
    num_gap: int
    inertia: float
    tangential_mass: float
    womersley: float
    kappa: float
    eps: float
    gamma: float
    theta0: float


def _drive_columns(sys: _System, y: FloatArray) -> dict[str, FloatArray]:
    """dg/dd of the top wall's drive and the pump's (g is affine in each; written out)."""
    lay = sys.layout
    num = sys.num
    m = lay.size
    th = _angles(sys, y)
    h1 = float(np.cos(th) @ sys.params[3][num])
    gg = 1.0 / sys.eps - h1
    top_row = lay.v + num - 1 if sys.alpha <= 0.0 else lay.gap + sys.num_gap - 1
    col_top = np.zeros(m)
    col_top[top_row] = -1.0
    cols = {("wall" if sys.top == 0 else "wall_stress"): col_top}
    if sys.pump == 1:
        col = np.zeros(m)
        col[lay.pi] = -1.0
        cols["flow_rate"] = col
    else:
        col = np.zeros(m)
        col[lay.v : lay.v + num - 1] = 1.0
        if sys.alpha <= 0.0:
            col[top_row] = -sys.eps * gg * gg / 2.0 if sys.top == 0 else -gg
        else:
            col[lay.gap : lay.gap + sys.num_gap - 1] = 1.0
        cols["pressure"] = col
    return cols


def _output_rows(sys: _System, y: FloatArray, pump_value: float) -> dict[str, FloatArray]:
    """The gradients of the outputs at y by the complex step (exact to rounding: no
    difference is taken)."""
    m = y.size
    h = 1e-30
    ys = y[None, :] + 1j * h * np.eye(m)
    vals = _output_values(sys, ys, pump_value)
    return {k: np.ascontiguousarray(np.imag(vals[k]) / h) for k in BED_OUTPUTS}


def bed_operators(
    state: PorousState,
    *,
    inertia: float = 0.0,
    tangential_mass: float = 1.0,
    womersley: float = 0.0,
    num: int | None = None,
    num_gap: int = 16,
) -> BedOperators:
    """The linear operators of the porous bed in time about a steady state (theory.md §15).

    About the static state ``state`` (:func:`hairbed.solve_porous`, one state; the wall
    drive with the pressure or the flow drive) the semi-discrete bed M y' = g(t, y) is
    linearised: its diagonal mass vector M, the exact Jacobian J = dg/dy, the drives'
    columns dg/dd, the steady vector y* (the state on the dynamics' nodes, polished by
    Newton on g = 0) and the outputs' rows. Time in T = zeta_perp L^4/(E I).

    Parameters
    ----------
    state : PorousState
        One converged state (a scalar :func:`hairbed.solve_porous` result).
    inertia : float, optional
        The hair's inertia number mu = m E I/(zeta_perp^2 L^4) >= 0 [-] (default 0).
    tangential_mass : float, optional
        chi in (0, 1]: tangential over normal mass per unit length (default 1).
    womersley : float, optional
        The bed's Womersley number alpha = rho_f L^2/(eta T) >= 0 [-] (default 0: the
        quasi-steady fluid, no gap grid).
    num : int, optional
        The hair's Chebyshev degree N in [8, 128] (default: the state's).
    num_gap : int, optional
        The gap's Chebyshev degree M in [4, 128] (used where womersley > 0; default 16).

    Returns
    -------
    BedOperators
    """
    if not isinstance(state, PorousState) or np.ndim(state.tip_height) != 0:
        raise TypeError("state must be one PorousState (a scalar solve_porous result)")
    if int(state.status) < 0:
        raise ValueError(f"state must be a converged state, got status {int(state.status)}")
    mu = check_number(inertia, "inertia", low=0.0)
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    alpha = check_number(womersley, "womersley", low=0.0)
    deg = int(state.num) if num is None else check_int(num, "num", 8, 128)
    deg = min(max(deg, 8), 128)
    ngap = check_int(num_gap, "num_gap", 4, 128)
    eps = float(state.eps)
    if not eps > 0.0:
        raise ValueError("the bed's dynamics needs eps > 0 (a top wall at 1/eps), got eps = 0")
    pump = 1 if state.drive == "flow" else 0
    pump_value = float(state.q) if pump == 1 else float(state.pi)
    a = float(state._map) if np.isfinite(state._map) else 0.0
    sys = _system(
        deg, a, ngap, float(state.theta0), float(state.gamma), chi, mu, float(state.kappa),
        eps, alpha, 0, pump, constant(float(state.omega2)), constant(pump_value),
    )  # fmt: skip
    y = _newton_steady(sys, _steady_guess(sys, state), 0.0)
    ok, _, jac = _evaluate(sys, 0.0, y, True)
    vals = _output_values(sys, y, pump_value)
    lay = sys.layout
    return BedOperators(
        mass=_mass(sys),
        jacobian=jac,
        drives=MappingProxyType(_drive_columns(sys, y)),
        steady=y,
        outputs=MappingProxyType(_output_rows(sys, y, pump_value)),
        output_values=MappingProxyType({k: float(np.real(v)) for k, v in vals.items()}),
        layout=MappingProxyType(
            {
                "theta": 0,
                "omega": lay.omega,
                "accel": lay.accel,
                "v": lay.v,
                "stress": lay.stress,
                "gap": lay.gap,
                "pi": lay.pi,
                "size": lay.size,
            }
        ),
        s=sys.s,
        zeta=sys.zeta,
        num=deg,
        num_gap=sys.num_gap,
        inertia=mu,
        tangential_mass=chi,
        womersley=alpha,
        kappa=float(state.kappa),
        eps=eps,
        gamma=float(state.gamma),
        theta0=float(state.theta0),
    )
