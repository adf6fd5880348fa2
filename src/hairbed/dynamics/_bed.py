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
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.loaded import _matrices
from .._core.porous import PorousState
from .._core.validation import (
    STATUS_MESSAGES,
    StatusResult,
    check_int,
    check_number,
    check_positive,
    show,
)
from ._signals import Signal, as_signal, constant

__all__ = [
    "BED_OUTPUTS",
    "BED_STATUS",
    "BedOperators",
    "BedTrajectory",
    "bed_operators",
    "simulate_bed",
]

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


def _solve(a: FloatArray, b: FloatArray) -> FloatArray | None:
    """a^-1 b by the compiled LU with partial pivoting (``spectral._lu_factor``), None where
    a is singular: numpy's solve would call a threaded BLAS whose idle threads spin on a
    loaded machine (about 100 ms of CPU for one 127 x 127 solve)."""
    from .._core._kernels.spectral import _lu_apply, _lu_factor

    lu = np.array(a, dtype=np.float64, order="C")
    x = np.array(b, dtype=np.float64)
    piv = np.empty(x.size, dtype=np.int64)
    if not _lu_factor(lu, piv, x.size):
        return None
    _lu_apply(lu, piv, x, x.size)
    return x


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
        speed = sys.eps * kap * vg[..., ngap]
    else:
        top = qn - pi * gg
        flux = bedflux + kap * v[..., num] * gg + qn * gg * gg / 2.0 - pi * gg**3 / 6.0
        speed = sys.eps * (kap * v[..., num] + gg * qn - pi * gg * gg / 2.0)
    return {
        "tip_deflection": x1,
        "tip_height": h1,
        "base_moment": th @ sys.d0,
        "wall_stress": top,
        "flow_rate": 6.0 * sys.eps**2 * flux,
        "wall_speed": speed,
        "pressure": pi if sys.pump == 1 else pi + 0.0 * x1,
    }


def _steady_guess(sys: _System, state: PorousState) -> FloatArray:
    """y of a static state interpolated to the system's nodes, at rest."""
    lay = sys.layout
    num = sys.num
    y = np.zeros(lay.size)
    # theta, w and Q of state.shape and state.fluid in one evaluation, the Chebyshev series
    # cut after its last nonzero coefficient (the padding's zeros add nothing: the same
    # sums, 15x faster at N = 16 of 256)
    from .._core.porous import _fields_at

    used = np.flatnonzero(np.any(state._coefs.reshape(-1, state._coefs.shape[-1]) != 0, axis=0))
    coefs = state._coefs[..., : int(used[-1]) + 1 if used.size else 1]
    _, fields = _fields_at(state._map, coefs, state.shape_of_fields, sys.s)
    theta, w, q = fields[0], fields[3], fields[4]
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


#: Newton's last step (relative): below it the iteration has converged quadratically (the
#: error after it is its square) and what is left is the rounding of the solve (the
#: collocation's matrices have condition numbers up to ~1e8).
_NEWTON_TOL = 1e-9


def _newton_steady(sys: _System, y: FloatArray, t: float, tol: float = _NEWTON_TOL) -> FloatArray:
    """Newton on g(t, y) = 0 (the steady state of the discrete system at the drives' values
    at t), with the exact Jacobian; raises ArithmeticError where it does not converge."""
    y = y.copy()
    scale = 1.0 + np.abs(y)
    for _ in range(30):
        ok, g, jac = _evaluate(sys, t, y, True)
        if not ok:
            break
        step = _solve(jac, -g)
        if step is None:
            break
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
    M dy' = J dy + sum_d b_d dd(t), and each output o = o* + c_o . dy + sum_d f_d,o dd(t)
    (f the feedthrough: an output that depends on a drive directly).

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
    feedthrough : mapping of str to ndarray
        f_d (len(BED_OUTPUTS),), in the order of ``BED_OUTPUTS``, for each drive of
        ``drives``: the outputs' direct dependence on the drive at fixed y, so that
        do = c_o . dy + f_d dd. Nonzero only for the pressure where the fluid has no
        inertia (womersley = 0): the quasi-steady gap's exact profile carries Pi itself,
        wall_stress -g and flow_rate -eps^2 g^3, g = 1/eps - h1 [L] (theory.md §13).
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
    feedthrough: Mapping[str, FloatArray]
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


def _feedthrough(
    sys: _System, y: FloatArray, pump_value: float, drives: Mapping[str, FloatArray]
) -> dict[str, FloatArray]:
    """d o/d d at fixed y for each drive, by the complex step on the pump's value (the
    outputs read the drive only there: Pi of the quasi-steady gap; the wall's drive and the
    flow rate enter g alone)."""
    h = 1e-30
    out: dict[str, FloatArray] = {}
    for name in drives:
        f = np.zeros(len(BED_OUTPUTS))
        if name == "pressure":
            vals = _output_values(sys, y.astype(np.complex128), complex(pump_value, h))
            f = np.array([float(np.imag(vals[k])) / h for k in BED_OUTPUTS])
        out[name] = f
    return out


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
    Newton on g = 0), the outputs' rows and their feedthrough from the drives. Time in
    T = zeta_perp L^4/(E I).

    Parameters
    ----------
    state : PorousState
        One converged state (a scalar :func:`hairbed.solve_porous` result).
    inertia : float, optional
        The hair's inertia number mu = m E I/(zeta_perp^2 L^4) [-]: 0 (default) or in
        [1e-6, 1e6].
    tangential_mass : float, optional
        chi in (0, 1]: tangential over normal mass per unit length (default 1).
    womersley : float, optional
        The bed's Womersley number alpha = rho_f L^2/(eta T) [-]: 0 (default: the
        quasi-steady fluid, no gap grid) or in [1e-6, 1e6].
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
    mu, chi, alpha = _checked_masses(inertia, tangential_mass, womersley)
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
    cols = _drive_columns(sys, y)
    return BedOperators(
        mass=_mass(sys),
        jacobian=jac,
        drives=MappingProxyType(cols),
        steady=y,
        outputs=MappingProxyType(_output_rows(sys, y, pump_value)),
        feedthrough=MappingProxyType(_feedthrough(sys, y, pump_value, cols)),
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


# ---------------------------------------------------------------------------------------
# The nonlinear bed in time
# ---------------------------------------------------------------------------------------

#: The status codes of a :class:`BedTrajectory` (the package's table).
BED_STATUS: Mapping[int, str] = STATUS_MESSAGES


_LOAD = "E I/(A L^2)"
#: The series of a bed in time, one value per time: (units, long_name) for the datasets of
#: :class:`BedTrajectory` and :class:`hairbed.dynamics.BedBatch`.
SERIES_ATTRS: Mapping[str, tuple[str, str]] = MappingProxyType(
    {
        "top_drive": ("1", "top wall drive"),
        "pump_drive": ("1", "pump drive"),
        "tip_deflection": ("L", "tip deflection x1"),
        "tip_height": ("L", "tip height h1"),
        "tip_angle": ("rad", "tip angle theta(1)"),
        "base_moment": ("E I/L", "base moment theta'(0)"),
        "wall_stress": (_LOAD, "top wall shear stress"),
        "wall_speed": ("1", "top wall speed omega2 = eta V A L^2/(E I H)"),
        "flow_rate": ("1", "flow rate q = 6 eps^2 Phi"),
        "pressure": ("1", "pressure gradient Pi = A G L^3/(E I)"),
    }
)
#: The series at the hair's nodes, (time, node).
NODE_SERIES_ATTRS: Mapping[str, tuple[str, str]] = MappingProxyType(
    {
        "theta": ("rad", "angle"),
        "theta_t": ("rad/T", "angular rate"),
        "velocity": ("L/T", "fluid velocity at the node"),
        "stress": (_LOAD, "fluid shear stress at the node"),
    }
)


def _drive_names(
    table: Mapping[str, tuple[str, str]], top: str, pump: str
) -> dict[str, tuple[str, str]]:
    """The series table with the drives' long names saying which drive each is."""
    out = dict(table)
    out["top_drive"] = (table["top_drive"][0], f"top wall drive ({top})")
    out["pump_drive"] = (table["pump_drive"][0], f"pump drive ({pump})")
    return out


@dataclass(frozen=True)
class BedTrajectory(StatusResult):
    """A porous bed's motion (theory.md §15); time in T = zeta_perp L^4/(E I), lengths in L,
    stresses and loads in the units of §13 (a stress times A L^2/(E I)).

    Attributes
    ----------
    t : ndarray
        The output times [T]. Past an event or a failure (``t_end``) the values are NaN.
    top, pump : str
        The drives: "wall" (the top wall's speed omega2(t)) or "wall_stress" (its shear
        stress); "pressure" (Pi(t)) or "flow_rate" (q(t); Pi is then the unknown).
    top_drive, pump_drive : ndarray
        The drives' values at t.
    tip_deflection, tip_height : ndarray
        x1(t), h1(t) [L].
    tip_angle : ndarray
        theta(1, t) [rad].
    base_moment : ndarray
        theta'(0, t) [E I/L].
    wall_stress : ndarray
        The top wall's shear stress Q(1/eps, t) [-] (what a rheometer measures).
    wall_speed : ndarray
        The top wall's speed as omega2 = eta V A L^2/(E I H) [-] (the drive, or the free
        wall's speed under a set stress).
    flow_rate : ndarray
        q(t) = 6 eps^2 Phi [-] (§11's units).
    pressure : ndarray
        Pi(t) [-].
    s : ndarray
        The hair's collocation nodes [L].
    theta, theta_t : ndarray
        theta [rad] and its rate [rad/T] at the nodes, (time, node).
    velocity, stress : ndarray
        The fluid's velocity v [L/T] and shear stress Q [-] at the nodes' heights z(s_j, t),
        (time, node).
    kappa, eps, gamma, theta0, inertia, tangential_mass, womersley : float
        The model's constants (womersley alpha = rho_f L^2/(eta T)).
    num, num_gap : int
        The Chebyshev degrees of the hair and the gap (the gap's only where womersley > 0).
    status : int
        0 reached the last time; -8 a node reached abs(theta) = pi/2 (outside the model,
        at ``t_end``); -2 the step limit; -3 the step size underflowed or a singular matrix
        (``BED_STATUS``).
    t_end : float
        Where the integration ended [T].
    nsteps, naccept, nreject, nfev, njev, nlu : int
        Work: steps tried, accepted, rejected; evaluations of g, Jacobians, LU
        factorisations.
    """

    t: FloatArray
    top: str
    pump: str
    top_drive: FloatArray
    pump_drive: FloatArray
    tip_deflection: FloatArray
    tip_height: FloatArray
    tip_angle: FloatArray
    base_moment: FloatArray
    wall_stress: FloatArray
    wall_speed: FloatArray
    flow_rate: FloatArray
    pressure: FloatArray
    s: FloatArray
    theta: FloatArray
    theta_t: FloatArray
    velocity: FloatArray
    stress: FloatArray
    kappa: float
    eps: float
    gamma: float
    theta0: float
    inertia: float
    tangential_mass: float
    womersley: float
    num: int
    num_gap: int
    status: int
    t_end: float
    nsteps: int
    naccept: int
    nreject: int
    nfev: int
    njev: int
    nlu: int

    _status_table: ClassVar[Mapping[int, str]] = BED_STATUS

    def to_xarray(self) -> Any:
        """The trajectory as an xarray.Dataset with the dimensions ``t`` and ``s``, CF
        attributes. Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedTrajectory.to_xarray", "io")

        data: dict[str, Any] = {
            name: ("t", getattr(self, name), {"units": units, "long_name": long})
            for name, (units, long) in _drive_names(SERIES_ATTRS, self.top, self.pump).items()
        }
        for name, (units, long) in NODE_SERIES_ATTRS.items():
            data[name] = (("t", "s"), getattr(self, name), {"units": units, "long_name": long})
        return xr.Dataset(
            data,
            coords={
                "t": ("t", self.t, {"units": "T", "long_name": "time, T = zeta_perp L^4/(E I)"}),
                "s": ("s", self.s, {"units": "L", "long_name": "arc length"}),
            },
            attrs={
                "title": "hairbed porous bed trajectory",
                "kappa": self.kappa,
                "eps": self.eps,
                "gamma": self.gamma,
                "theta0": self.theta0,
                "inertia": self.inertia,
                "tangential_mass": self.tangential_mass,
                "womersley": self.womersley,
                "top": self.top,
                "pump": self.pump,
                "status": self.status,
                "message": str(self.message),
                "t_end": self.t_end,
                "Conventions": "CF-1.10",
            },
        )


def _consistent(sys: _System, y: FloatArray, t: float) -> FloatArray:
    """The algebraic unknowns solved at time t with the differential ones held (index 1:
    Newton on the algebraic rows; the index-2 Pi of a set flow rate with fluid inertia is
    kept)."""
    mass = _mass(sys)
    alg = np.flatnonzero(mass == 0.0)
    if sys.layout.pi >= 0 and sys.alpha > 0.0:
        alg = alg[alg != sys.layout.pi]
    y = y.copy()
    for _ in range(30):
        ok, g, jac = _evaluate(sys, t, y, True)
        if not ok:
            break
        step = _solve(jac[np.ix_(alg, alg)], -g[alg])
        if step is None:
            break
        y[alg] += step
        if np.max(np.abs(step) / (1.0 + np.abs(y[alg]))) <= _NEWTON_TOL:
            return y
    raise ArithmeticError("no consistent start of the bed's algebraic unknowns")


#: The bed in time's ranges: kappa (below, the tips' layer sqrt(kappa) needs more than
#: N = 128; above, the isolated pillar of simulate_pillar to 1e-6), eps (a gap of at most
#: 1000 L), the inertia and Womersley numbers (0, or within [1e-6, 1e6]) and the drives'
#: levels (the static states end near |theta| = pi/2 long before).
KAPPA_RANGE = (1e-6, 1e6)
EPS_MIN = 1e-3
NUMBER_RANGE = (1e-6, 1e6)
MAX_BED_DRIVE = 1e6


def _zero_or_within(value: float, name: str) -> float:
    lo, hi = NUMBER_RANGE
    if value != 0.0 and not lo <= value <= hi:
        raise ValueError(f"{name} must be 0 or lie in [{lo:g}, {hi:g}], got {show(value)}")
    return value


def _bounded_drive(sig: Signal, name: str) -> Signal:
    from ._signals import _peak

    peak = _peak(sig)
    if not peak <= MAX_BED_DRIVE:
        raise ValueError(
            f"{name} must stay within [-{MAX_BED_DRIVE:g}, {MAX_BED_DRIVE:g}] for the bed in "
            f"time, got a {sig.kind} drive of magnitude {show(peak)}"
        )
    return sig


def _top_drive(wall: Any, wall_stress: Any) -> tuple[int, Any, str]:
    if wall is not None and wall_stress is not None:
        raise ValueError(
            "give at most one of wall (the top wall's speed) and wall_stress (its shear "
            "stress), got both"
        )
    if wall_stress is not None:
        return 1, wall_stress, "wall_stress"
    return 0, (0.0 if wall is None else wall), "wall"


def _pump_drive(pressure: Any, flow_rate: Any) -> tuple[int, Any, str]:
    if pressure is not None and flow_rate is not None:
        raise ValueError("give at most one of pressure (Pi(t)) and flow_rate (q(t)), got both")
    if flow_rate is not None:
        return 1, flow_rate, "flow_rate"
    return 0, (0.0 if pressure is None else pressure), "pressure"


def _static_start(
    sys: _System, theta0: float, kappa: float, eps: float, gamma: float, top_v: float,
    pump_v: float, t: float,
) -> FloatArray:  # fmt: skip
    """The discrete system's steady state at the drives' values at time t: from
    :func:`hairbed.solve_porous` (the wall drive; under a set wall stress, omega2 by a
    secant on the static solver's top stress), polished by Newton on g = 0."""
    from .._core.porous import solve_porous

    kw = {"q": pump_v} if sys.pump == 1 else {"pi": pump_v}

    def state(omega2: float) -> PorousState:
        return solve_porous(omega2, eps, theta0, kappa=kappa, gamma=gamma, **kw)

    if sys.top == 0:
        st = state(top_v)
    else:

        def top_stress(s: PorousState) -> float:
            return float(s.tip_stress) - float(s.pi) * (1.0 / eps - float(s.tip_height))

        w0, st = 0.0, state(0.0)
        f0 = top_stress(st) - top_v
        w1 = (1.0 - eps) * top_v if top_v != 0.0 else 0.0
        for _ in range(8):
            if w1 == w0 or int(st.status) < 0:
                break
            st = state(w1)
            f1 = top_stress(st) - top_v
            if f1 == f0:
                break
            w0, w1, f0 = w1, w1 - f1 * (w1 - w0) / (f1 - f0), f1
    drives = (
        f"{'wall' if sys.top == 0 else 'wall_stress'} = {show(top_v)}, "
        f"{'pressure' if sys.pump == 0 else 'flow_rate'} = {show(pump_v)}"
    )
    if int(st.status) < 0:
        raise ValueError(
            f"no static state at the drives' values at t_eval[0] to start from ({drives}: "
            f"{st.message}); pass initial="
        )
    try:
        return _newton_steady(sys, _steady_guess(sys, st), t)
    except ArithmeticError:
        raise ValueError(
            f"the steady state at the drives' values at t_eval[0] ({drives}) did not converge "
            "on the dynamics' grid (N too small for the bed's tip layer?): pass num= or "
            "initial="
        ) from None


def _checked_masses(
    inertia: Any, tangential_mass: Any, womersley: Any
) -> tuple[float, float, float]:
    """(mu, chi, alpha) checked: the inertia and Womersley numbers 0 or within NUMBER_RANGE,
    chi in (0, 1]."""
    mu = _zero_or_within(check_number(inertia, "inertia", low=0.0), "inertia")
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    alpha = _zero_or_within(check_number(womersley, "womersley", low=0.0), "womersley")
    return mu, chi, alpha


def _checked_bed(
    theta0: Any, kappa: Any, eps: Any, gamma: Any, inertia: Any, tangential_mass: Any,
    womersley: Any, num_gap: Any,
) -> tuple[float, float, float, float, float, float, float, int]:  # fmt: skip
    """The bed in time's model, checked (simulate_bed's and periodic_bed's ranges): (theta0,
    kappa, eps, gamma, mu, chi, alpha, num_gap)."""
    t0 = check_number(theta0, "theta0", low=-0.5 * np.pi, high=0.5 * np.pi, low_open=True,
                      high_open=True)  # fmt: skip
    kap = check_number(kappa, "kappa", low=KAPPA_RANGE[0], high=KAPPA_RANGE[1])
    e = check_number(eps, "eps", low=EPS_MIN, high=1.0, high_open=True)
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    mu, chi, alpha = _checked_masses(inertia, tangential_mass, womersley)
    return t0, kap, e, g, mu, chi, alpha, check_int(num_gap, "num_gap", 4, 128)


def simulate_bed(
    theta0: float,
    kappa: float,
    eps: float,
    *,
    t_eval: ArrayLike,
    wall: Any = None,
    pressure: Any = None,
    flow_rate: Any = None,
    wall_stress: Any = None,
    gamma: float = 1.0,
    inertia: float = 0.0,
    tangential_mass: float = 1.0,
    womersley: float = 0.0,
    initial: PorousState | None = None,
    num: int | None = None,
    num_gap: int = 16,
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 100_000,
) -> BedTrajectory:
    """A porous bed in time-dependent flow, hairs and fluid together (theory.md §15).

    The hair of §14 (D1-D4) in the Brinkman bed of §13, the fluid laterally uniform with its
    own inertia: with v the fluid's velocity [L/T], f = [I - (1 - gamma) t t](v e_x - r_t)
    the drag per length on a hair,

        theta'' = -(F_x cos - F_z sin),  F = int_s^1 (f - mu C r_tt) ds',
        alpha kappa v_t = kappa v_zz + Pi(t) - f_x/cos(theta)   inside the bed,
        alpha kappa v_t = kappa v_zz + Pi(t)                     in the gap,

    v(0) = 0, v and v_z continuous at the tip plane, the top wall's speed or stress at
    z = 1/eps, and Pi given or held by a set flow rate. Time in T = zeta_perp L^4/(E I).

    Parameters
    ----------
    theta0 : float
        The base angle [rad] in (-pi/2, pi/2).
    kappa : float
        The bed's permeability over L^2 [-] in [1e-6, 1e6].
    eps : float
        L/H [-] in [1e-3, 1).
    t_eval : array_like
        Output times [T], finite and non-decreasing; the run starts at t_eval[0].
    wall, wall_stress : number, Signal or callable, optional
        The top wall's drive: its speed as omega2(t) = eta V A L^2/(E I H) (default 0), or
        its shear stress (load units of §13; the wall's speed is then free). At most one;
        levels within [-1e6, 1e6] (as the pump's).
    pressure, flow_rate : number, Signal or callable, optional
        The pump: Pi(t) = A G L^3/(E I) (default 0), or the flow rate q(t) of §11 (Pi is then
        the unknown that holds it; with womersley > 0 it must not jump). At most one.
    gamma : float, optional
        Drag ratio zeta_par/zeta_perp in (0, 1] (default 1).
    inertia : float, optional
        mu = m E I/(zeta_perp^2 L^4): 0 (the default: overdamped hairs) or in [1e-6, 1e6].
    tangential_mass : float, optional
        chi in (0, 1]: tangential over normal mass per length (default 1).
    womersley : float, optional
        alpha = rho_f L^2/(eta T): 0 (the default: the quasi-steady fluid, a fast path with
        the gap's exact profile) or in [1e-6, 1e6].
    initial : PorousState, optional
        The bed's state at t_eval[0] (at rest; a scalar :func:`hairbed.solve_porous` result
        of the same theta0, kappa, eps, gamma); default the steady state of the drives'
        values just before t_eval[0] (a step at t_eval[0] starts from its value before).
    num : int, optional
        The hair's Chebyshev degree N in [8, 128] (default: that of the start's static
        state).
    num_gap : int, optional
        The gap's degree M in [4, 128] (womersley > 0; default 16).
    rtol, atol : float, optional
        The integrator's tolerances (default 1e-8, 1e-10).
    max_steps : int, optional
        The most steps, in [1, 10^12] (status -2 beyond).

    Returns
    -------
    BedTrajectory

    Raises
    ------
    ValueError, TypeError
        For inputs outside their ranges, naming the parameter.

    Examples
    --------
    >>> from hairbed.dynamics import simulate_bed, step
    >>> run = simulate_bed(0.0, 0.1, 0.5, wall=step(1.0), t_eval=[0.0, 5.0])
    >>> run.success, round(float(run.tip_deflection[-1]), 6)  # solve_porous: 0.2714279566
    (True, 0.271428)
    """
    from ._integrate import _checked_times

    te = _checked_times(t_eval)
    t0, kap, e, g, mu, chi, alpha, ngap = _checked_bed(
        theta0, kappa, eps, gamma, inertia, tangential_mass, womersley, num_gap
    )
    tol_r = check_positive(rtol, "rtol")
    tol_a = check_positive(atol, "atol")
    steps = check_int(max_steps, "max_steps", 1, 10**12)
    top, top_in, top_name = _top_drive(wall, wall_stress)
    pump, pump_in, pump_name = _pump_drive(pressure, flow_rate)
    span_end = float(te[-1]) if te[-1] > te[0] else float(te[0]) + 1.0
    top_sig = _bounded_drive(as_signal(top_in, top_name, float(te[0]), span_end), top_name)
    pump_sig = _bounded_drive(as_signal(pump_in, pump_name, float(te[0]), span_end), pump_name)
    before = float(np.nextafter(te[0], -np.inf))
    if pump == 1 and alpha > 0.0 and pump_sig.at_start(before) != pump_sig.at_start(te[0]):
        raise ValueError(
            "flow_rate must not jump at t_eval[0] where womersley > 0 (with the fluid's inertia "
            "a jump of the flow rate needs an impulsive pressure): use a ramp"
        )
    if initial is not None:
        if not isinstance(initial, PorousState) or np.ndim(initial.tip_height) != 0:
            raise TypeError("initial must be one PorousState (a scalar solve_porous result)")
        same = all(
            abs(float(getattr(initial, k)) - v) <= 1e-12 * max(1.0, abs(v))
            for k, v in (("theta0", t0), ("kappa", kap), ("eps", e), ("gamma", g))
        )
        if not same or int(initial.status) < 0:
            raise ValueError(
                "initial must be a converged state of the same theta0, kappa, eps and gamma, "
                f"got status {int(initial.status)}, theta0 = {float(initial.theta0)!r}, "
                f"kappa = {float(initial.kappa)!r}, eps = {float(initial.eps)!r}, "
                f"gamma = {float(initial.gamma)!r}"
            )
    if num is None:
        deg = int(initial.num) if initial is not None else 32
    else:
        deg = check_int(num, "num", 8, 128)
    a = 0.0
    if initial is not None and np.isfinite(initial._map):
        a = float(initial._map)
    elif top == 0 and pump == 0 and pump_sig.kind == "constant" and pump_sig.params[0] == 0.0:
        from .._core.porous import _tip_map

        a = float(_tip_map(0, np.array(kap), np.array(0.0)))
    sys = _system(deg, a, ngap, t0, g, chi, mu, kap, e, alpha, top, pump, top_sig, pump_sig)
    if initial is not None:
        y0 = _steady_guess(sys, initial)
    else:
        y0 = _static_start(sys, t0, kap, e, g, top_sig.at_start(before),
                           pump_sig.at_start(before), before)  # fmt: skip
    try:
        y0 = _consistent(sys, y0, float(te[0]))
    except ArithmeticError:
        raise ValueError(
            f"no consistent start at t_eval[0] under the drives {top_name} = "
            f"{show(top_sig.at_start(float(te[0])))}, {pump_name} = "
            f"{show(pump_sig.at_start(float(te[0])))}"
        ) from None
    return _integrate(sys, y0, te, tol_r, tol_a, steps, top_sig, pump_sig, top_name, pump_name)


def _integrate(
    sys: _System, y0: FloatArray, te: FloatArray, rtol: float, atol: float, max_steps: int,
    top_sig: Signal, pump_sig: Signal, top_name: str, pump_name: str,
) -> BedTrajectory:  # fmt: skip
    """The compiled run and its trajectory."""
    from .._core._kernels import dynamics as kern

    lay = sys.layout
    m = lay.size
    mass = _mass(sys)
    index2 = lay.pi if (lay.pi >= 0 and sys.alpha > 0.0) else m
    y_out = np.full((te.size, m), np.nan)
    counts = np.zeros(6, dtype=np.int64)
    status, t_end = kern.integrate_bed(
        y0, mass, index2, float(te[0]), te, rtol, atol, 1e-6, max_steps, sys.params, y_out,
        counts,
    )  # fmt: skip
    num = sys.num
    ok = np.all(np.isfinite(y_out), axis=1)
    y_out[~ok] = np.nan
    pump_vals = np.asarray(pump_sig(te), dtype=np.float64).reshape(te.shape)
    vals = _output_values(sys, y_out, pump_vals)
    theta = _angles(sys, y_out)
    rates = np.full_like(theta, np.nan)
    rates[:, 0] = 0.0
    rates[:, 1:num] = y_out[:, lay.omega : lay.omega + num - 1]
    rates[:, num] = rates[:, 1:num] @ sys.params[5][1:num]
    rates[~ok] = np.nan
    vel = np.zeros_like(theta)
    vel[:, 1:] = y_out[:, lay.v : lay.v + num]
    vel[~ok] = np.nan
    stress = y_out[:, lay.stress : lay.stress + num + 1].copy()
    return BedTrajectory(
        t=te,
        top=top_name,
        pump=pump_name,
        top_drive=np.asarray(top_sig(te), dtype=np.float64).reshape(te.shape),
        pump_drive=pump_vals,
        tip_deflection=np.asarray(vals["tip_deflection"]),
        tip_height=np.asarray(vals["tip_height"]),
        tip_angle=theta[:, num].copy(),
        base_moment=np.asarray(vals["base_moment"]),
        wall_stress=np.asarray(vals["wall_stress"]),
        wall_speed=np.asarray(vals["wall_speed"]),
        flow_rate=np.asarray(vals["flow_rate"]),
        pressure=np.asarray(vals["pressure"]),
        s=sys.s,
        theta=theta,
        theta_t=rates,
        velocity=vel,
        stress=stress,
        kappa=sys.kappa,
        eps=sys.eps,
        gamma=float(sys.params[1][1]),
        theta0=float(sys.params[1][0]),
        inertia=sys.mu,
        tangential_mass=float(sys.params[1][2]),
        womersley=sys.alpha,
        num=num,
        num_gap=sys.num_gap if sys.alpha > 0.0 else 0,
        status=int(status),
        t_end=float(t_end),
        nsteps=int(counts[0]),
        naccept=int(counts[1]),
        nreject=int(counts[2]),
        nfev=int(counts[3]),
        njev=int(counts[4]),
        nlu=int(counts[5]),
    )
