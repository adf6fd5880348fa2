"""The rectified net flow of a pumped porous bed and its exact derivatives in the bed's
dimensionless parameters (issue 32; theory.md §15, §16).

The bed in time, M y' = g(t, y; p) (:func:`hairbed.dynamics.simulate_bed`), driven by
Pi(t) = Pi_A sin(omega t) with its top wall at rest, has a periodic state
(:func:`hairbed.dynamics.periodic_bed`, trigonometric collocation in time). Its net flow is
the period mean of the flow rate q of §11, q_bar = (1/K) sum_k q(y_k, t_k).

The derivatives are those of the discrete periodic problem, exact (implicit
differentiation): the forced variational equation M S' = J S + G_p
(:func:`hairbed.dynamics.periodic_sensitivity`) has the periodic solution S = dy/dp, with
the columns

    G_p = dg/dp - (dM/dp) y'          p in theta0, gamma, kappa, eps, alpha, mu, chi
                                      (``_core._kernels.bed_parameters``, exact),
    G_A = (dg/dPi) sin(omega t)       the drive's amplitude Pi_A,
    G_w = -M y'                       ln omega: at fixed phases omega t_k the frequency
                                      scales the time derivative alone,

and d q_bar/dp = (1/K) sum_k (c_k . S_k + dq/dp|_y), c = dq/dy, the explicit partials of q
in kappa, eps and Pi by the complex step, in theta0 written out (theta_0 = theta0 and
theta_N = srow . theta enter the tip height). The sum through the state is the adjoint's,
(1/K) sum_k c_k . S_k = sum_k lambda_k . G_p(t_k) with lambda the solution of the transposed
collocation (:func:`hairbed.dynamics.periodic_adjoint`): one linear solve for all columns,
not one per column. The columns at every phase come from one compiled call
(``bed_parameter_phases``).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._core._kernels import bed as _bed_kernel
from .._core._kernels import bed_parameters as _bpk
from ..dynamics import PeriodicBed, periodic_adjoint, periodic_bed, sine
from ..dynamics._bed import _mass, _output_values

__all__: list[str] = []

FloatArray = NDArray[np.float64]

#: The parameters of :func:`net_flow_derivatives`, in order (ln_omega: d/d ln omega).
PARAMETERS = ("theta0", "gamma", "kappa", "eps", "alpha", "mu", "chi", "amplitude",
              "ln_omega")  # fmt: skip
_KERNEL_COLUMNS = (_bpk.P_THETA0, _bpk.P_GAMMA, _bpk.P_KAPPA, _bpk.P_EPS, _bpk.P_ALPHA,
                   _bpk.P_MU, _bpk.P_CHI)  # fmt: skip
#: The periodic state's accuracy (periodic_bed's tol): its truncation error, well below
#: the 1e-7 to which the gradient is checked against central differences of step 1e-4.
ORBIT_TOL = 1e-12
#: The largest degree of the periodic state: hairs that snap through within a few
#: hundredths of the period need H ~ 1,600 to 2,600 for ORBIT_TOL (measured: base angles
#: 0.76 and 1.01, swings of +-1.5 rad; 70 to 120 s an orbit).
ORBIT_MAX_HARMONICS = 4096


def pumped_orbit(s: Any, amplitude: float, omega: float) -> PeriodicBed:
    """The periodic state of the bed of scales ``s`` (``_bed_scales._BedScales``) under
    Pi(t) = amplitude sin(omega t) (amplitude [-], omega [1/T])."""
    return periodic_bed(
        s.theta0,
        s.kappa,
        s.eps,
        omega=omega,
        pressure=sine(0.0, amplitude, omega),
        gamma=s.gamma,
        inertia=s.inertia,
        tangential_mass=s.tangential_mass,
        womersley=s.womersley,
        tol=ORBIT_TOL,
        max_harmonics=ORBIT_MAX_HARMONICS,
    )


def _pump_values(orbit: PeriodicBed, amplitude: float) -> FloatArray:
    return amplitude * np.sin(orbit.omega * orbit.t)


def _flow_partials(orbit: PeriodicBed, amplitude: float) -> dict[str, FloatArray]:
    """{parameter: dq/dparameter at fixed y, at each phase (K,)}."""
    sys, y = orbit._sys, orbit.y
    h = 1e-30
    pump = _pump_values(orbit, amplitude)
    out: dict[str, FloatArray] = {}
    for name in ("kappa", "eps"):
        shifted = replace(sys, **{name: getattr(sys, name) + 1j * h})
        out[name] = np.imag(np.asarray(_output_values(shifted, y.astype(complex), pump)
                                       ["flow_rate"])) / h  # fmt: skip
    fed = _output_values(sys, y.astype(complex), pump + 1j * h)["flow_rate"]
    out["amplitude"] = np.imag(np.asarray(fed)) / h * np.sin(orbit.omega * orbit.t)
    # theta0: q = 6 eps^2 Phi, d Phi/d theta_j = (-kappa v_j + d Phi/d g) I_Nj sin theta_j
    # (g = 1/eps - h1, h1 = I_N . cos theta), theta_0 = theta0, theta_N = srow . theta
    num, lay = sys.num, sys.layout
    ii, srow = sys.params[3], sys.params[5]
    th0 = float(sys.params[1][0])
    th_n = srow[0] * th0 + y[:, : num - 1] @ srow[1:num]
    h1 = math.cos(th0) * ii[num, 0] + np.cos(y[:, : num - 1]) @ ii[num, 1:num]
    gg = 1.0 / sys.eps - (h1 + np.cos(th_n) * ii[num, num])
    vn = y[:, lay.v + num - 1]
    if sys.alpha > 0.0:
        vg = np.concatenate([vn[:, None], y[:, lay.gap : lay.gap + sys.num_gap]], axis=1)
        d_gap = sys.kappa * (vg @ sys.params[8])
    else:
        d_gap = sys.kappa * vn + y[:, lay.stress + num] * gg - pump * gg * gg / 2.0
    f0 = d_gap * ii[num, 0] * math.sin(th0)  # v_0 = 0
    fn = (-sys.kappa * vn + d_gap) * ii[num, num] * np.sin(th_n)
    out["theta0"] = 6.0 * sys.eps**2 * (f0 + srow[0] * fn)
    return out


def net_flow_derivatives(orbit: PeriodicBed, amplitude: float) -> dict[str, float]:
    """d q_bar/dp of a converged ``orbit`` (of :func:`pumped_orbit` at ``amplitude``) for p
    in :data:`PARAMETERS`; 0 for an absent parameter (alpha without the fluid's inertia,
    mu and chi of overdamped hairs). Raises ArithmeticError where a column is not finite
    or the adjoint's solve does not reach its rounding level."""
    sys, y = orbit._sys, orbit.y
    kk, m = y.shape
    absent = set()
    if sys.alpha <= 0.0:
        absent.add("alpha")
    if sys.mu <= 0.0:
        absent.update(("mu", "chi"))
    names = [n for n in PARAMETERS if n not in absent]  # one forcing column each
    gp = np.zeros((kk, _bpk.NPAR, m))
    mp = np.zeros((kk, _bpk.NPAR, m))
    ws = _bed_kernel.bed_workspace(sys.num, sys.num_gap)
    if not _bpk.bed_parameter_phases(orbit.t, y, sys.params, gp, mp, np.zeros((m, m)), ws):
        raise ArithmeticError("the bed's parameter derivatives are not finite on its orbit")
    ydot = orbit.y_t
    forcing = np.empty((kk, m, len(names)))
    for j, name in enumerate(names):
        if name == "amplitude":
            forcing[:, :, j] = gp[:, _bpk.P_PUMP] * np.sin(orbit.omega * orbit.t)[:, None]
        elif name == "ln_omega":
            forcing[:, :, j] = -_mass(sys) * ydot
        else:
            p = _KERNEL_COLUMNS[PARAMETERS.index(name)]
            forcing[:, :, j] = gp[:, p] - mp[:, p] * ydot
    adjoint = periodic_adjoint(orbit, "flow_rate")  # one transposed solve for every column
    if not adjoint.success:
        raise ArithmeticError(f"the net flow's adjoint: {adjoint.message}")
    through = adjoint.mean_derivative(forcing)
    out = dict.fromkeys(PARAMETERS, 0.0)
    for j, name in enumerate(names):
        out[name] = float(through[j])
    for name, part in _flow_partials(orbit, amplitude).items():
        out[name] += float(np.mean(part))
    return out
