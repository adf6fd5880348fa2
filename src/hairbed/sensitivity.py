"""Exact derivatives of a state with respect to the forcing, the confinement and the base angle.

Every state lies on the explicit curve of its branch in the parameter t of
:func:`hairbed.from_parameter` (theory.md §2, §9),

    xi - sin(theta0) = (1 - sin theta0) expit(t),    1 - xi = (1 - sin theta0) expit(-t),

and at fixed t the energy xi, omega_eps, the tip height h1, the tip angle and the tip deflection
do not depend on eps; the forcing is an output, omega^2 = omega_eps^2 (1 - eps h1) (eq. (34) of
arXiv:2203.04169). The state at given (omega2, eps, theta0) is the root t of

    R(t; omega2, eps, theta0) = ln omega^2(t; eps, theta0) - ln omega2 = 0,

so by implicit differentiation dt/dp = -(dR/dp)/(dR/dt) for p in (omega2, eps, theta0), and the
total derivative of every output Y is

    dY/dp = (dY/dp)_t + (dY/dt) dt/dp.

On the twirling branches all the partial derivatives are closed forms in K(mu), E(mu),
F(phi0 | mu) and E(phi0 | mu) (mu = (1 + xi)/2, sin(phi0) = sin(pi/4 + theta0/2)/sqrt(mu)),
through (DLMF 19.4.1, 19.4.2)

    dK/dm = (E - (1 - m) K)/(2 m (1 - m)),   dE/dm = (E - K)/(2 m),
    dF/dphi = 1/Delta,   dF/dm = (E(phi) - (1 - m) F)/(2 m (1 - m)) - sin cos/(2 (1 - m) Delta),
    dE(phi)/dphi = Delta,   dE(phi)/dm = (E(phi) - F)/(2 m),   Delta = sqrt(1 - m sin^2 phi),

and, at fixed t, dmu/dt = p expit(t), dmu/dtheta0 = p cos(theta0)/(1 - sin theta0),
dphi0/dt = -sin(phi0) cos(phi0) expit(-t)/2 and dphi0/dtheta0 = sqrt(expit(t))/(2 mu), with
p = 1 - mu: every 1/p of the derivatives in m is absorbed. The incomplete integrals are the
Carlson forms of theory.md §6 (no loss near mu = 1). Nothing is differenced numerically.

On the physical branch the closed forms above would take the small changes of a barely bent
hair as differences of O(1) terms; its partials come instead from the Carlson forms of the
short arc from phi0 to pi/2 (``_physical_partials``), in arguments scaled so that nothing
under- or overflows at any forcing, with gradients from :mod:`hairbed._carlson_gradients` and
exact limit forms once expit(-t) = 2 p/(1 - sin theta0) < 1e-21; and where
omega_eps^2 <= 0.003 the tip's derivatives come from the weak-forcing series of the kernels,
differentiated exactly (``_weak_tip``). The elliptic integrals are scipy.special's and the
duplication's numpy (elementwise ufuncs over whole arrays), not the kernels' R_F, R_D, K, E,
which are scalar functions callable only from compiled loops; both agree with mpmath to a few
ulps.

Accuracy: to about 1e-14 relative of mpmath on every output, input and branch, from
omega^2 = 1e-13 to 1e8 and leaning both ways; omega2 = 0 itself is exact (the limits of the
linear theory). The measured figures and the references are in docs/accuracy.md §9.

At a fold of the branch (a state where dR/dt = 0: it appears or disappears as the inputs vary,
theory.md §5) the derivatives through dt/dp are infinite: they are returned as +-inf and the
element's ``status`` is 1 ("at a fold").

Pump drives (``pi=`` or ``q=``, theory.md §11) have no closed form: their states are the
Chebyshev collocation of :func:`hairbed.solve_loaded`, and their derivatives the implicit
differentiation of that converged discrete system, J du/dp = -dR/dp with the exact Jacobian J
factored once per state, in a compiled kernel (``_core/_kernels/loaded_gradient.py``). They
are exact for the discrete state, and agree with the ODE's to its error estimate.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import special

from ._carlson_gradients import rf_rd_gradient
from ._core.loaded import LADDER, LoadedState, _check, _solve_loaded_checked
from ._core.loaded_sensitivity import LOADED_OUTPUTS, loaded_gradient_table
from ._core.pillar import PillarState
from ._core.pillar_sensitivity import PILLAR_INPUTS, PILLAR_OUTPUTS, pillar_gradient_table
from ._core.porous import PorousState
from ._core.porous_sensitivity import porous_derivatives
from ._core.solution import Solution
from ._core.solver import _plain_inputs, _solve_checked
from ._core.validation import (
    STATUS_MESSAGES,
    check_branch,
    check_inputs,
    check_positive,
    check_root,
    scalar_or_array,
    status_messages,
)
from ._dual import Dual
from ._variables import SOLUTION, names

__all__ = [
    "INPUTS",
    "LOADED_OUTPUTS",
    "OUTPUTS",
    "PILLAR_INPUTS",
    "PILLAR_OUTPUTS",
    "STATUS_MESSAGES",
    "Derivatives",
    "derivatives",
    "derivatives_at",
]

FloatArray = NDArray[np.float64]

#: The outputs whose derivatives are returned: the state fields of :class:`hairbed.Solution`.
OUTPUTS = names(SOLUTION, "state")
#: The inputs they are differentiated with respect to.
INPUTS = names(SOLUTION, "input")

#: |dR/dt| below this (relative to its two terms) counts as a fold: there the derivatives are
#: larger than 1/FOLD_RTOL and every digit of them is rounding error.
FOLD_RTOL = 1.0e-8


_out = scalar_or_array


@dataclass(frozen=True, eq=False)
class Derivatives(Mapping[str, Mapping[str, Any]]):
    """Exact partial derivatives of the outputs of a state (returned by :func:`derivatives`).

    A read-only mapping ``{output: {"omega2": ..., "eps": ..., "theta0": ...}}`` over
    :data:`OUTPUTS` (xi, omega_eps, energy, tip_height, tip_deflection, tip_displacement,
    tip_angle, base_curvature): ``d["tip_deflection"]["omega2"]`` is d x1/d omega^2 at fixed
    eps and theta0. For a pump-driven state (a :class:`hairbed.LoadedState`) the outputs are
    :data:`LOADED_OUTPUTS` (tip_height, tip_deflection, tip_angle, base_curvature, tip_load,
    distributed_load) and the inputs omega2, eps, theta0 and the drive's "pi" or "q"; for a
    pillar state (a :class:`hairbed.PillarState`) :data:`PILLAR_OUTPUTS` in
    :data:`PILLAR_INPUTS` (:func:`derivatives_at`).
    Units: per unit of the input ([-] for omega2 and eps, [1/rad] for theta0),
    times the output's unit ([rad] for tip_angle, [L] for lengths). Floats for scalar inputs,
    arrays of the broadcast shape otherwise.

    Attributes
    ----------
    solution : Solution, LoadedState or PillarState
        The state differentiated.
    table : Mapping
        The nested mapping itself (what indexing the object reads).
    dt : Mapping
        dt/d omega2, dt/d eps, dt/d theta0 of the branch parameter t (empty for a
        LoadedState, which has no branch parameter).
    status : int or ndarray
        0 exact derivatives; 1 at a fold (the derivatives are +-inf; for a LoadedState a
        singular collocation Jacobian); -1 no such state (NaN);
        -5 the end t = -inf of a twirling branch (NaN). See :data:`STATUS_MESSAGES`, the one
        table of every result.
    """

    solution: Solution | LoadedState | PillarState | PorousState
    table: Mapping[str, Mapping[str, Any]]
    dt: Mapping[str, Any]
    status: Any

    def __getitem__(self, key: str) -> Mapping[str, Any]:
        return self.table[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self.table)

    def __len__(self) -> int:
        return len(self.table)

    @property
    def success(self) -> Any:
        """True where the derivatives are finite and exact (status 0)."""
        return _out(np.asarray(self.status) == 0)

    @property
    def at_fold(self) -> Any:
        """True where the state sits at a fold (status 1: infinite derivatives)."""
        return _out(np.asarray(self.status) == 1)

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, STATUS_MESSAGES)

    def as_dict(self) -> dict[str, dict[str, Any]]:
        """Plain nested dicts (arrays as lists), e.g. for JSON."""
        return {
            o: {p: (v.tolist() if isinstance(v, np.ndarray) else v) for p, v in m.items()}
            for o, m in self.table.items()
        }


def _logistic(t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """expit(t), expit(-t), ln expit(-t) and sqrt(expit(-t)), the last three at any t.

    expit(-t) = 2 p/(1 - sin theta0) is subnormal from t = 708 (scipy's expit flushes it to 0
    there) and 0 from t = 745, while its square root, which the tip angle's derivatives carry
    (sqrt(1 - xi^2) = 2 sqrt(p mu)), stays normal up to t = 1416: both come from the logarithm.
    """
    lqc = special.log_expit(-t)
    qc = np.where(t < 700.0, special.expit(-t), np.exp(lqc))
    sqrt_qc = np.where(t < 700.0, np.sqrt(qc), np.exp(0.5 * lqc))
    return special.expit(t), qc, lqc, sqrt_qc


def _partials(
    t: FloatArray, theta0: FloatArray, sign: int, n: int, sol: Solution
) -> tuple[FloatArray, dict[str, FloatArray], dict[str, FloatArray]]:
    """Partial derivatives in t and in theta0 at fixed t of every t-function (Legendre forms).

    Returns (h1, d_t, d_th): the solution's tip height and the partials over the keys of
    OUTPUTS plus "h1" and "ln_oe" (ln omega_eps), with the solution's values of omega_eps,
    h1 and x1. For the twirling branches; the physical one has :func:`_physical_partials`.
    """
    c = np.cos(theta0)
    # 1 -+ sin(theta0) without cancellation near +-pi/2 (as the kernels)
    oms = 2.0 * np.sin(0.5 * (0.5 * np.pi - theta0)) ** 2
    ops = 2.0 * np.sin(0.5 * (0.5 * np.pi + theta0)) ** 2
    q, qc, _, sqrt_qc = _logistic(t)
    d = oms * q  # xi - sin(theta0)
    p = 0.5 * oms * qc  # (1 - xi)/2
    mu = 1.0 - p
    two_mu = ops + d
    sn0 = np.sqrt(ops / two_mu)
    cn0 = np.sqrt(d / two_mu)
    cn0_2 = d / two_mu
    dn0 = np.sqrt(0.5 * oms)
    dn0_2 = 0.5 * oms
    # complete and incomplete integrals, Carlson forms (theory.md §6)
    k = special.ellipkm1(p)
    e = special.ellipe(mu)
    rf0 = special.elliprf(cn0_2, dn0_2, 1.0)
    rd0 = special.elliprd(cn0_2, dn0_2, 1.0)
    v0 = sn0 * rf0  # F(phi0 | mu)
    e0 = v0 - mu / 3.0 * sn0**3 * rd0  # E(phi0 | mu), DLMF 19.25.9
    pk = np.where(p > 0.0, p * np.where(np.isfinite(k), k, 0.0), 0.0)  # p K -> 0 as p -> 0
    pv0 = p * v0
    odd = 2.0 * n + 1.0

    # dmu = p r: r_t = expit(t), r_th = cos/(1 - sin)
    r = {"t": q, "th": c / oms}
    dphi = {"t": -0.5 * sn0 * cn0 * qc, "th": np.sqrt(q) / two_mu}
    out_t: dict[str, FloatArray] = {}
    out_th: dict[str, FloatArray] = {}

    oe = np.asarray(sol.omega_eps, dtype=np.float64)
    h1 = np.asarray(sol.tip_height, dtype=np.float64)
    x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
    xi = np.asarray(sol.xi, dtype=np.float64)
    root2d = np.sqrt(2.0 * d)
    # sqrt(1 - xi^2) = 2 sqrt(p mu)
    tip_turns = sign * (1 - 2 * (n % 2)) < 0  # tip_angle = -pi - arcsin(xi)
    angle_sign = -1.0 if tip_turns else 1.0
    for key, out in (("t", out_t), ("th", out_th)):
        rk = r[key]
        dk = rk * (e - pk) / (2.0 * mu)  # dK = K_m dmu
        de = (e * p - pk) * rk / (2.0 * mu)  # dE = E_m dmu
        dv0 = dphi[key] / dn0 + rk * ((e0 - pv0) / (2.0 * mu) - sn0 * cn0 / (2.0 * dn0))
        de0 = dn0 * dphi[key] + (e0 - v0) * p * rk / (2.0 * mu)
        doe = odd * dk - sign * dv0
        if key == "t":
            dxi = 2.0 * p * q
            dlog_root2d = 0.5 * qc  # d ln sqrt(2 d)
            dshift: Any = 0.0  # d sin(theta0)
        else:
            dxi = c * qc
            dlog_root2d = -c / (2.0 * oms)
            dshift = c
        g = doe / oe  # d ln omega_eps
        dh1 = h1 * (dlog_root2d - g)
        dnum = odd * (dk - 2.0 * de) - sign * (dv0 - 2.0 * de0)  # d (x1 omega_eps)
        dx1 = (dnum - x1 * doe) / oe
        if key == "t":
            dangle = q * np.sqrt(0.5 * oms / mu) * sqrt_qc
        else:
            dangle = np.sqrt(ops / two_mu) * sqrt_qc
        out["xi"] = dxi
        out["omega_eps"] = doe
        out["energy"] = dxi * oe * oe + 2.0 * xi * oe * doe
        out["tip_height"] = dh1
        out["h1"] = dh1
        out["ln_oe"] = g
        out["tip_deflection"] = dx1
        out["tip_displacement"] = dx1 - dshift
        out["tip_angle"] = angle_sign * dangle
        out["base_curvature"] = sign * root2d * oe * (g + dlog_root2d)
    return h1, out_t, out_th


#: Below this expit(-t) (t > 48) the short arc's integrals take their limit forms, exact to
#: O(expit(-t) ln expit(-t)) < 1e-19 relative (``_arc_integrals``).
ARC_LIMIT = 1.0e-21


def _arc_integrals(
    sn0_2: FloatArray, qc: FloatArray, lqc: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """The short arc's R_F and R_D in the scaled arguments (X, 1, Z) = (qc sn0^2, 1, qc).

    Returns F = R_F(X, 1, Z), G = Z R_D(X, 1, Z) and their logarithmic derivatives
    F_q = d ln F/d ln qc, F_s = d ln F/d ln sn0^2, G_q, G_s. Where qc >= ARC_LIMIT they come
    from the gradients of :mod:`hairbed._carlson_gradients` (X dR/dX and Z dR/dZ: scale-free
    and finite); below it the arguments X, Z -> 0 leave (DLMF §19.27(ii) for R_F; for R_D the
    leading term 3/(sqrt(Y Z) (sqrt(X) + sqrt(Z))) of its integral; both off by O(qc ln qc))

        F = L/2,  L = ln 16 - ln qc - 2 ln(1 + sn0),   G = 3/(1 + sn0),

    with ln qc given (``lqc``), so that nothing underflows or overflows however strong the
    forcing: F_q = -1/L, F_s = -sn0/((1 + sn0) L), G_q = 0, G_s = -sn0/(2 (1 + sn0)).
    """
    dup = qc >= ARC_LIMIT
    x = np.where(dup, qc * sn0_2, 1.0)
    z = np.where(dup, qc, 1.0)
    one = np.ones_like(x)
    (rf, grad_f), (rd, grad_d) = rf_rd_gradient(x, one, z)
    s = np.sqrt(sn0_2)
    big_l = np.log(16.0) - lqc - 2.0 * np.log1p(s)
    f = np.where(dup, rf, 0.5 * big_l)
    f_s = np.where(dup, x * grad_f[0] / rf, -s / ((1.0 + s) * big_l))
    f_q = np.where(dup, (x * grad_f[0] + z * grad_f[2]) / rf, -1.0 / big_l)
    g = np.where(dup, z * rd, 3.0 / (1.0 + s))
    g_s = np.where(dup, x * grad_d[0] / rd, -0.5 * s / (1.0 + s))
    g_q = np.where(dup, 1.0 + (x * grad_d[0] + z * grad_d[2]) / rd, 0.0)
    return f, g, f_q, f_s, g_q, g_s


def _physical_partials(
    t: FloatArray, theta0: FloatArray, sol: Solution
) -> tuple[FloatArray, dict[str, FloatArray], dict[str, FloatArray]]:
    """:func:`_partials` of the physical branch, from the Carlson forms of its short arc.

    The arc from phi0 to pi/2 is short at weak forcing, where the Legendre forms of
    :func:`_partials` would take the small tip displacement x1 - sin(theta0) and the slow
    change of h1 as differences of O(1) terms. With the Carlson forms of the arc (theory.md
    §6), X = p sn0^2, Y = dn0^2 = (1 - sin theta0)/2 and Z = p, p = Y qc, qc = expit(-t),

        omega_eps = K - F0 = cn0 R_F(X, Y, Z),   h1 = 2 sqrt(mu) / R_F(X, Y, Z),
        x1 - sin(theta0) = d (1 - w/3),   w = p R_D(X, Y, Z) / R_F(X, Y, Z),
        x1 = xi - d w/3,

    (from E - E0 = p (K - F0) + mu int cos^2/Delta and DLMF 19.25.9) nothing cancels:
    1 - w/3 -> 2/3 at weak forcing, and d ln omega_eps = d ln cn0 + d ln R_F replaces
    dK - dF0. R_F and R_D are homogeneous (degrees -1/2, -3/2), so R_F(X, Y, Z) =
    Y^(-1/2) F and w = G/F in the arguments scaled by 1/Y (``_arc_integrals``), and their
    derivatives are sums of logarithmic derivatives times d ln qc = -expit(t) dt,
    d ln sn0^2 and d ln Y, all O(1): nothing is formed from p itself, which underflows at
    t > 745 (omega^2 > 1.3e5) while 1/p^2 in the gradient overflows already at t > 350.
    The gradients of R_F and R_D keep their relative accuracy where the closed forms of the
    partials would difference R_D(Y, Z, X) - R_D(X, Y, Z) as X -> Z.

    Returns (h1, d_t, d_th) as :func:`_partials`.
    """
    c = np.cos(theta0)
    oms = 2.0 * np.sin(0.5 * (0.5 * np.pi - theta0)) ** 2  # 1 - sin(theta0)
    ops = 2.0 * np.sin(0.5 * (0.5 * np.pi + theta0)) ** 2  # 1 + sin(theta0)
    q, qc, lqc, sqrt_qc = _logistic(t)
    d = oms * q  # xi - sin(theta0)
    p = 0.5 * oms * qc  # (1 - xi)/2 (its underflow at t > 745 is harmless below)
    two_mu = ops + d
    mu = 0.5 * two_mu
    sn0_2 = ops / two_mu
    oe = np.asarray(sol.omega_eps, dtype=np.float64)
    h1 = np.asarray(sol.tip_height, dtype=np.float64)
    xi = np.asarray(sol.xi, dtype=np.float64)
    f, g, f_q, f_s, g_q, g_s = _arc_integrals(sn0_2, qc, lqc)
    w = g / f
    # d/dt and d/dtheta0 at fixed t
    dln_qc = {"t": -q, "th": 0.0 * q}
    dln_sn0_2 = {"t": -2.0 * p * q / two_mu, "th": 2.0 * c * q / (ops * two_mu)}
    dln_y = {"t": 0.0 * q, "th": -c / oms}
    dln_mu = {"t": p * q / mu, "th": c * qc / two_mu}
    # d ln(cn0/sqrt(Y)), cn0^2/Y = 2 expit(t)/(2 mu): the theta0-derivatives of ln cn0 and
    # ln sqrt(Y), -c/(2 oms) each, cancel here in closed form, not in rounding
    dln_cn0_y = {"t": 0.5 * (qc - 2.0 * p * q / two_mu), "th": -0.5 * c * qc / two_mu}
    dd = {"t": oms * q * qc, "th": -c * q}
    dxi = {"t": oms * q * qc, "th": c * qc}
    # tip angle arcsin(xi): d/dt = 2 p q / sqrt(1 - xi^2), sqrt(1 - xi^2) = 2 sqrt(p mu)
    dangle = {
        "t": q * np.sqrt(0.5 * oms / mu) * sqrt_qc,
        "th": np.sqrt(ops / two_mu) * sqrt_qc,
    }
    out_t: dict[str, FloatArray] = {}
    out_th: dict[str, FloatArray] = {}
    for key, out in (("t", out_t), ("th", out_th)):
        dln_f = f_q * dln_qc[key] + f_s * dln_sn0_2[key]
        dln_rf = dln_f - 0.5 * dln_y[key]  # R_F(X, Y, Z) = Y^(-1/2) F
        dln_w = g_q * dln_qc[key] + g_s * dln_sn0_2[key] - dln_f
        dln_h1 = 0.5 * dln_mu[key] - dln_rf
        dln_oe = dln_cn0_y[key] + dln_f  # omega_eps = cn0 R_F(X, Y, Z) = (cn0/sqrt(Y)) F
        dwd = (dd[key] * w + d * w * dln_w) / 3.0  # d (d w/3)
        out["xi"] = dxi[key]
        out["tip_angle"] = dangle[key]
        out["ln_oe"] = dln_oe
        out["omega_eps"] = dln_oe * oe
        out["energy"] = dxi[key] * oe * oe + 2.0 * xi * oe * oe * dln_oe
        out["base_curvature"] = oe * oe * h1 * (2.0 * dln_oe + dln_h1)
        out["tip_height"] = h1 * dln_h1
        out["h1"] = out["tip_height"]
        # x1 - sin(theta0) = d - d w/3 and x1 = xi - d w/3: neither sum cancels (x1 -> 1 and
        # its theta0-derivative -> 0 at strong forcing, x1 - sin(theta0) -> 0 at weak)
        out["tip_displacement"] = dd[key] - dwd
        out["tip_deflection"] = dxi[key] - dwd
    return h1, out_t, out_th


def derivatives_at(
    sol: Solution | LoadedState | PillarState | PorousState,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
) -> Derivatives:
    """Exact derivatives of the outputs of the states ``sol`` (a :class:`hairbed.Solution`,
    a :class:`hairbed.LoadedState` of :func:`hairbed.solve_loaded`, or a
    :class:`hairbed.PillarState` of :func:`hairbed.solve_pillar`).

    See :func:`derivatives`; this takes a state already at hand (any branch or root, any
    shape).

    For a PorousState (:func:`hairbed.solve_porous`, any drive, or the porous inverse's
    state) the table is that of ``hairbed._core.porous_sensitivity.porous_derivatives``:
    outputs tip_height, tip_deflection, tip_angle, tip_stress, wall_stress, tip_velocity,
    drag_x and, for the flow drive, pi; inputs omega2, eps, theta0, kappa, gamma and pi or q.

    For a PillarState the outputs are :data:`PILLAR_OUTPUTS` (tip_height, tip_deflection,
    tip_angle, base_curvature, drag_x, drag_z) and the inputs :data:`PILLAR_INPUTS`: forcing
    (Lambda), theta0, gamma, tip_load and, for a channel profile, height_ratio (L/H; at fixed
    Lambda: for "couette" the dimensionless profile does not depend on it, so its column is
    zero). They are the implicit differentiation of the converged collocation system,
    J du/dp = -dR/dp with its exact Jacobian (compiled, ``_core/_kernels/pillar_gradient.py``,
    theory.md §12): exact for the discrete state, equal to the ODE's to its error estimate.
    At a fold (a singular Jacobian) the derivatives are NaN with status 1; where there is no
    state (status < 0) NaN with status -1.

    Parameters
    ----------
    sol : Solution, LoadedState or PillarState
        The states.
    profile, height_ratio : optional
        Only for a PillarState: the profile and height ratio it was solved with (as in
        :func:`hairbed.solve_pillar`; a state that is not a root of that profile's system is
        refused with a ValueError).

    Examples
    --------
    >>> import hairbed
    >>> d = hairbed.sensitivity.derivatives_at(hairbed.solve_pillar(1e-6))
    >>> round(d["tip_deflection"]["forcing"] * 120, 9)  # the linear limit 11/120
    11.0
    """
    if isinstance(sol, PillarState):
        table, status = pillar_gradient_table(sol, profile, height_ratio)
        frozen = {o: MappingProxyType(row) for o, row in table.items()}
        return Derivatives(sol, MappingProxyType(frozen), MappingProxyType({}), status)
    if isinstance(sol, PorousState) and profile == "sublayer" and height_ratio is None:
        porous = porous_derivatives(sol)
        frozen = {o: MappingProxyType(row) for o, row in porous.table.items()}
        return Derivatives(sol, MappingProxyType(frozen), MappingProxyType({}), porous.status)
    if profile != "sublayer" or height_ratio is not None:
        raise ValueError(
            "profile and height_ratio are a PillarState's (hairbed.solve_pillar); got "
            f"profile={profile!r}, height_ratio={height_ratio!r} with a {type(sol).__name__}"
        )
    if isinstance(sol, LoadedState):
        table, status = loaded_gradient_table(sol)
        frozen = {o: MappingProxyType(row) for o, row in table.items()}
        return Derivatives(sol, MappingProxyType(frozen), MappingProxyType({}), status)
    if not isinstance(sol, Solution):
        raise TypeError(
            "sol must be a hairbed.Solution, hairbed.LoadedState or hairbed.PillarState, got "
            f"{type(sol).__name__}"
        )
    shape = sol.shape
    t = np.broadcast_to(np.asarray(sol.t, dtype=np.float64), shape)
    eps = np.broadcast_to(np.asarray(sol.eps, dtype=np.float64), shape)
    theta0 = np.broadcast_to(np.asarray(sol.theta0, dtype=np.float64), shape)
    omega2 = np.broadcast_to(np.asarray(sol.omega2, dtype=np.float64), shape)
    ok = np.asarray(sol.status) == 0
    ok = np.broadcast_to(ok, shape)
    physical = sol.sign == 1 and sol.n == 0
    rest = ok & (t == -np.inf) & physical  # omega2 = 0 on the physical branch: at rest
    branch_end = ok & (t == -np.inf) & (not physical)
    live = ok & np.isfinite(t)
    tt = np.where(live, t, 0.0)
    with np.errstate(all="ignore"):
        sol_live = sol if np.all(live) else _masked(sol, live)
        if physical:
            h1, d_t, d_th = _physical_partials(tt, theta0, sol_live)
        else:
            h1, d_t, d_th = _partials(tt, theta0, sol.sign, sol.n, sol_live)
        one_minus = 1.0 - eps * h1
        # R = 2 ln omega_eps + ln(1 - eps h1) - ln omega2
        term_k = 2.0 * d_t["ln_oe"]
        term_h = -eps * d_t["h1"] / one_minus
        r_t = term_k + term_h
        r_p = {
            "omega2": -1.0 / omega2,
            "eps": -h1 / one_minus,
            "theta0": 2.0 * d_th["ln_oe"] - eps * d_th["h1"] / one_minus,
        }
        fold = live & (np.abs(r_t) <= FOLD_RTOL * (np.abs(term_k) + np.abs(term_h)))
        r_t = np.where(fold, 0.0, r_t)
        dt = {name: -r_p[name] / r_t for name in INPUTS}
        values: dict[str, Mapping[str, Any]] = {}
        for o in OUTPUTS:
            row = {}
            for name in INPUTS:
                partial = d_th[o] if name == "theta0" else 0.0
                total = partial + d_t[o] * dt[name]
                total = np.where(live, total, np.nan)
                row[name] = total
            values[o] = row
    status = np.where(ok, np.where(fold, 1, np.where(branch_end, -5, 0)), -1).astype(np.int64)
    if physical:
        _weak_tip(
            values,
            live & ~fold,
            theta0,
            eps,
            np.asarray(sol_live.omega_eps, dtype=np.float64),
            np.broadcast_to(np.asarray(sol_live.xi, dtype=np.float64), shape),
        )
    if np.any(rest):
        _rest_values(values, dt, rest, eps, theta0)
    # below 1e-300 (subnormal omega2: 1/omega2 overflows on the way, issue 33) the linear
    # theory of rest is exact to rounding; only dt/d omega2 = 1/omega2 and d omega_eps/d
    # omega2 = 1/(2 omega_eps (1 - eps cos theta0)) stay finite there
    weakest = live & physical & ~fold & (omega2 < _WEAKEST)
    if np.any(weakest):
        _rest_values(values, dt, weakest, eps, theta0)
        oe = np.broadcast_to(np.asarray(sol.omega_eps, dtype=np.float64), shape)
        with np.errstate(divide="ignore", over="ignore"):
            dt["omega2"] = np.where(weakest, 1.0 / omega2, dt["omega2"])
            d_oe = 0.5 / (oe * (1.0 - eps * np.cos(theta0)))
        oe_row = values["omega_eps"]
        assert isinstance(oe_row, dict)
        oe_row["omega2"] = np.where(weakest, d_oe, oe_row["omega2"])
    _energy_near_overflow(values, live & ~fold, omega2, eps, sol)
    frozen = {
        o: MappingProxyType({name: _out(v) for name, v in row.items()})
        for o, row in values.items()
    }
    dt_out = MappingProxyType(
        {name: _out(np.where(live | rest, v, np.nan)) for name, v in dt.items()}
    )
    return Derivatives(sol, MappingProxyType(frozen), dt_out, _out(status))


def _weak_tip(
    values: dict[str, Mapping[str, Any]],
    where: NDArray[np.bool_],
    theta0: FloatArray,
    eps: FloatArray,
    oe: FloatArray,
    xi: FloatArray,
) -> None:
    """The tip's derivatives from the weak-forcing series where omega_eps^2 <= WEAK_MAX.

    At theta0 -> 0 some of them are of second order: the tip height's change is
    h1 - cos(theta0) ~ -b/20 with b = omega_eps^4 cos^2 (the series of the kernels,
    theory.md §7), and d(x1 - sin theta0)/d theta0 ~ -2 E s c/3 + O(E^2) with E =
    omega_eps^2; the Carlson forms take them as differences of first-order terms (relative
    accuracy ~1e-16/E there). The series dx, dz(E, theta0) at sigma = 1 are polynomials,
    differentiated exactly (one pass on duals in E and theta0, :class:`hairbed._dual.Dual`),
    and dY/dp = Y_E dE/dp + Y_theta0
    [p = theta0], with dE/dp from omega2 = E (1 - eps h1(E, theta0)) differentiated
    implicitly in the series, and Y = omega_eps = sqrt(E), h1 = cos + dz, x1 = sin + dx,
    x1 - sin = dx (physical branch only); the base curvature E h1 and the energy xi E follow.
    """
    from ._core._kernels.weak import WEAK_MAX, weak_shape

    e2 = oe * oe
    weak = where & (e2 <= WEAK_MAX)
    if not np.any(weak):
        return
    shape_fn = getattr(weak_shape, "py_func", weak_shape)  # plain Python: arrays and duals
    th = theta0[weak]
    e = e2[weak]
    xi_w = xi[weak]
    s, c = np.sin(th), np.cos(th)
    zero = np.zeros_like(e)
    one = np.ones_like(e)
    # one pass in the two directions (d/dE, d/dtheta0 at fixed E)
    _, dx, dz = shape_fn(
        1.0, Dual.of(e, (one, zero)), Dual.of(s, (zero, c)), Dual.of(c, (zero, -s))
    )
    (dx_e, dx_th), (dz_e, dz_th) = dx.partials, dz.partials
    partials = {
        "tip_height": (dz_e, dz_th - s),
        "tip_deflection": (dx_e, dx_th + c),
        "tip_displacement": (dx_e, dx_th),
    }
    # E from omega2 = E (1 - eps h1(E, theta0)), differentiated implicitly in the series
    ew = eps[weak]
    h1 = c + dz.value
    g_e = 1.0 - ew * h1 - e * ew * dz_e
    de = {"omega2": 1.0 / g_e, "eps": e * h1 / g_e, "theta0": e * ew * (dz_th - s) / g_e}
    oe_w = oe[weak]
    partials["omega_eps"] = (0.5 / oe_w, 0.0 * e)
    for output, (y_e, y_th) in partials.items():
        row = values[output]
        assert isinstance(row, dict)
        for name in INPUTS:
            new = np.array(row[name], dtype=np.float64, copy=True)
            new[weak] = y_e * de[name] + (y_th if name == "theta0" else 0.0)
            row[name] = new
    for output in ("base_curvature", "energy"):  # E h1 and xi E
        row = values[output]
        assert isinstance(row, dict)
        for name in INPUTS:
            new = np.array(row[name], dtype=np.float64, copy=True)
            if output == "base_curvature":
                new[weak] = h1 * de[name] + e * np.asarray(values["tip_height"][name])[weak]
            else:
                new[weak] = xi_w * de[name] + e * np.asarray(values["xi"][name])[weak]
            row[name] = new


def _masked(sol: Solution, live: NDArray[np.bool_]) -> Solution:
    """The solution with its value fields replaced by finite stand-ins where not ``live``."""
    from dataclasses import replace

    fill: dict[str, Any] = {}
    for name in ("omega_eps", "tip_height", "tip_deflection", "xi"):
        v = np.broadcast_to(np.asarray(getattr(sol, name), dtype=np.float64), live.shape)
        fill[name] = np.where(live, v, 1.0)
    return replace(sol, **fill)


#: Below this omega2 the derivatives are those of the linear theory at rest (exact to rounding).
_WEAKEST = 1e-300


def _energy_near_overflow(
    values: dict[str, Mapping[str, Any]],
    where: NDArray[np.bool_],
    omega2: FloatArray,
    eps: FloatArray,
    sol: Solution,
) -> None:
    """The energy's derivatives where their chain through t overflowed (omega2 near the
    float range's end, ~1e307: omega_eps^2 times a derivative in t passes 1.8e308 while
    the derivative itself is of order 1; issue 33), in place, from the total derivatives of
    xi and h1: E = xi omega2/u, u = 1 - eps h1, so

        dE/dp = (omega2/u) dxi/dp + xi [d omega2/dp + (omega2/u) (eps dh1/dp + h1 deps/dp)]/u.
    """
    bad = where & ~np.all([np.isfinite(np.asarray(values["energy"][n])) for n in INPUTS], axis=0)
    if not np.any(bad):
        return
    h1 = np.broadcast_to(np.asarray(sol.tip_height, dtype=np.float64), bad.shape)
    xi = np.broadcast_to(np.asarray(sol.xi, dtype=np.float64), bad.shape)
    u = 1.0 - eps * h1
    oe2 = omega2 / u
    row = values["energy"]
    assert isinstance(row, dict)
    for name in INPUTS:
        dxi = np.asarray(values["xi"][name], dtype=np.float64)
        dh1 = np.asarray(values["tip_height"][name], dtype=np.float64)
        d_w = 1.0 if name == "omega2" else 0.0
        d_e = h1 if name == "eps" else 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            alt = oe2 * dxi + xi * (d_w + oe2 * (eps * dh1 + d_e)) / u
        row[name] = np.where(bad, alt, row[name])


def _rest_values(
    values: dict[str, Mapping[str, Any]],
    dt: dict[str, FloatArray],
    rest: NDArray[np.bool_],
    eps: FloatArray,
    theta0: FloatArray,
) -> None:
    """The derivatives at omega2 = 0 (the hair at rest), from the linear theory of weak forcing.

    theta = theta0 + omega_eps^2 cos(theta0) (sigma - sigma^2/2): xi = s + omega_eps^2 c^2/2,
    h1 = c - omega_eps^2 s c/3, x1 = s + omega_eps^2 c^2/3 (a point load at the tip) and
    omega_eps^2 = omega2/(1 - eps c) to first order; d omega_eps/d omega2 is infinite there,
    and so is dt/d omega2 (t = -inf at rest).
    """
    s, c = np.sin(theta0), np.cos(theta0)
    g = 1.0 / (1.0 - eps * c)  # d omega_eps^2 / d omega2 at rest
    d_w = {
        "xi": 0.5 * c * c * g,
        "omega_eps": np.full_like(g, np.inf),
        "energy": s * g,
        "tip_height": -s * c * g / 3.0,
        "tip_deflection": c * c * g / 3.0,
        "tip_displacement": c * c * g / 3.0,
        "tip_angle": 0.5 * c * g,
        "base_curvature": c * g,
    }
    d_th = {
        "xi": c,
        "omega_eps": 0.0 * c,
        "energy": 0.0 * c,
        "tip_height": -s,
        "tip_deflection": c,
        "tip_displacement": 0.0 * c,
        "tip_angle": 1.0 + 0.0 * c,
        "base_curvature": 0.0 * c,
    }
    for o in OUTPUTS:
        row = values[o]
        assert isinstance(row, dict)
        row["omega2"] = np.where(rest, d_w[o], row["omega2"])
        row["eps"] = np.where(rest, 0.0, row["eps"])
        row["theta0"] = np.where(rest, d_th[o], row["theta0"])
    # t -> -inf: xi - sin(theta0) = (1 - sin theta0) e^t to first order, so
    # t = ln omega2 + 2 ln c - ln 2 - ln(1 - s) - ln(1 - eps c) (issue 33: it was NaN)
    rest_dt = {
        "omega2": np.full_like(g, np.inf),
        "eps": c * g,
        "theta0": -2.0 * np.tan(theta0) + c / (1.0 - s) - eps * s * g,
    }
    for name in INPUTS:
        dt[name] = np.where(rest, rest_dt[name], dt[name])


def derivatives(
    omega2: ArrayLike,
    eps: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    sign: int = 1,
    n: int = 0,
    root: str = "low",
    pi: ArrayLike | None = None,
    q: ArrayLike | None = None,
    rtol: float = 1e-12,
) -> Derivatives:
    """Exact partial derivatives of a state's outputs in omega2, eps and theta0 (and the load).

    Solves the state with :func:`hairbed.solve` and differentiates the branch equation
    implicitly (module docstring): closed forms, vectorised over arrays, no finite differences.
    With ``pi`` or ``q`` (a pump drive, theory.md §11) the state is that of
    :func:`hairbed.solve_loaded` and the derivatives, also in the load, are the implicit
    differentiation of its collocation system (exact for the discrete state; compiled).

    Parameters
    ----------
    omega2, eps, theta0 : array_like
        Forcing omega^2 [-] (>= 0), confinement eps = L/H [-] (in [0, 1)) and base angle [rad]
        (in (-pi/2, pi/2); negative leans into the flow), broadcast together.
    sign, n, root :
        Branch and root selection, as in :func:`hairbed.solve`. With a pump drive only
        ``root`` ("low", "mid", "high": as in :func:`hairbed.solve_loaded`).
    pi, q : array_like, optional
        The dimensionless pressure gradient or flow rate of :func:`hairbed.solve_loaded`
        (at most one). Then the table is over :data:`LOADED_OUTPUTS` and the inputs are
        omega2, eps, theta0 and "pi" or "q"; d/dpi at eps = 0 is infinite.
    rtol : float
        The collocation's tolerance with a pump drive (as in :func:`hairbed.solve_loaded`).

    Returns
    -------
    Derivatives
        A mapping ``{output: {"omega2": ..., "eps": ..., "theta0": ...}}`` over xi, omega_eps,
        energy, tip_height, tip_deflection, tip_displacement, tip_angle, base_curvature, with
        ``solution``, ``dt`` and ``status`` / ``success`` / ``message``. At a fold (status 1)
        the derivatives are +-inf; where the state does not exist (status -1) NaN. At
        omega2 = 0 (the hair at rest) the limits of weak forcing (d omega_eps/d omega2 = inf).

    Raises
    ------
    ValueError
        For inputs outside their ranges (the message names the parameter).

    Examples
    --------
    The slope of the calibration curve of a pillar sensor at omega^2 = 2, eps = 0.5:

    >>> import hairbed
    >>> d = hairbed.derivatives(2.0, 0.5)
    >>> round(d["tip_deflection"]["omega2"], 10)
    0.1017297125
    >>> round(hairbed.derivatives(0.0, 0.5)["tip_deflection"]["omega2"], 12)  # 1/(3 (1 - eps))
    0.666666666667

    A pump drive, weak: x1 = W/3 + Pi/8 with W = (pi/2)(1/eps - h1) and h1 near 1:

    >>> d = hairbed.derivatives(0.0, 0.5, pi=1e-8)
    >>> round(d["tip_deflection"]["pi"], 6)  # (1/eps - 1)/6 + 1/8
    0.291667
    """
    if pi is not None or q is not None:
        if (sign, n) != (1, 0):
            raise ValueError(
                "a pump drive (pi or q) has one family of states: give root=, not sign or n "
                f"(got sign={sign!r}, n={n!r})"
            )
        drive, code, lw, le, lt, ld = _check(omega2, eps, theta0, pi, q)
        root = check_root(root)
        tol = check_positive(rtol, "rtol")
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            state = _solve_loaded_checked(drive, code, lw, le, lt, ld, root, tol, LADDER)
        return derivatives_at(state)
    plain = _plain_inputs(omega2, eps, theta0)
    w, e, t0 = plain if plain is not None else check_inputs(omega2, eps, theta0)
    sign, n = check_branch(sign, n)
    root = check_root(root)
    return derivatives_at(_solve_checked(w, e, t0, sign, n, root))
