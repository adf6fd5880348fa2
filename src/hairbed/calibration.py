"""Calibration of a pillar (hair) wall-shear-stress sensor, with uncertainties.

A sensor is a :class:`~hairbed.HairBed` whose tip deflection is read out. Calibrating it means
fitting the bed's unknown parameters (Young's modulus, base angle, length, ...) to tip
deflections measured at known wall speeds or known wall shear stresses; measuring with it means
inverting the calibrated curve for the stress and the speed of a new deflection, with an error
bar that carries the deflection's noise and the calibration's covariance.

The model is the exact one (theory.md §2, §7): at wall speed v the forcing is
omega^2 = v / ``bed.velocity_scale`` and the tip deflection L x1(omega^2, eps, theta0). At a
known wall shear stress tau the load on one hair is F = tau pi a^2/phi, a point load at the tip,
so that omega_eps^2 = F L^2/(E I) and the deflection L x1 is that of the collapsed branch at
omega_eps (it depends on neither the channel height nor the viscosity, which stress data cannot
determine). Every Jacobian is exact: the derivatives of :func:`hairbed.derivatives` (implicit
differentiation of the branch equation) through the chain rule of the SI scaling, no finite
differences. Positive parameters are fitted in their logarithms (the base angle as itself);
standard errors are returned in the parameters' own units (the linearisation, delta method).

A pump-driven bed (both walls at rest, theory.md §11) is calibrated the same way against known
pressure gradients G [Pa/m] or flow rates per unit width Q' [m^2/s]: the deflection is
L x1(pi, eps, theta0) with pi = A G L^3/(E I), or L x1(q, eps, theta0) with
q = 6 A eta Q' L^2/(E I H^2), the states of :func:`hairbed.solve_loaded` (the low state where
several coexist), and the Jacobian the implicit differentiation of its collocation
(:func:`hairbed.derivatives` with ``pi=`` or ``q=``). Signs are kept (no mirror image).

The weak-forcing limit is a cantilever under a point load at the tip, x1 - sin(theta0) =
omega_eps^2 cos^2(theta0)/3 (F L^3/(3 E I) in metres); :func:`linear_range` says up to which
deflection that line is within a tolerance of the exact calibration.

A porous bed (``HairBed(..., model="porous")``, theory.md §13) takes the same path: its
states come from the bed (``HairBed._tip_state``, the porous solver), their exact derivatives
from :func:`hairbed.sensitivity.derivatives_at` (the implicit differentiation of the porous
collocation, in omega^2, eps, theta0, kappa, gamma and the pump's load), and the Jacobian
gains the terms of the bed's permeability kappa and drag ratio gamma, which move with L, a
and phi through its drag law (exact derivatives of the drag logarithms). Its stress data are
the stress on the tip plane: with Pi = 0 that fixes the state as at eps = 0, as for the dense
bed. Its linear calibration is the exact slope at rest.

The same :func:`fit`, :func:`measure`, :func:`model_tip_deflection` and :func:`linear_range`
take an isolated pillar, a :class:`~hairbed.Pillar` (theory.md §12): its deflection
L x1(Lambda) at known wall shear stresses (or the wall speeds of a Couette channel), with
Lambda = c zeta_perp tau_w L^4/(eta E I). A pillar fits its Young's modulus or the drag
coefficients' scale c (they enter only as c/E, so one of them), its base angle, length and
radius (:data:`PILLAR_FREE_PARAMETERS`; L and a enter Lambda, gamma = gray_hancock_ratio(L/a),
the height ratio L/H of a Poiseuille channel and the scale of D = L x1), with the exact
Jacobian of the implicit differentiation of the collocation system
(:func:`hairbed.sensitivity.derivatives_at` of a PillarState) through that SI scaling, and
:func:`measure` reads tau_w with the same propagation of sigma and covariance. Stress data
determine a and E apart only through the slow gamma(L/a) and ln(2L/a): free both and expect
large, strongly correlated errors.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import least_squares

from ._bed_drag import MAX_PACKING_FRACTION
from ._bracketing import find_root
from ._channel_drives import gap_flow
from ._core.outputs import float_or_array
from ._core.solver import _from_parameter
from ._core.validation import (
    as_float_array,
    check_number,
    check_sigma,
    check_type,
    least_squares_status,
    show,
)
from ._ranges import LinearRange
from ._variables import BED, names
from ._warnings import (
    CalibrationWarning,
    ModelValidityWarning,
    UnitsWarning,
    renamed_parameters,
)
from .pillars import Pillar
from .sensitivity import derivatives_at
from .units import (
    CLOSE_PACKING_FRACTION,
    HairBed,
    _reynolds_of_stress,
    _warn_reynolds,
    _warn_sparse,
)

__all__ = [
    "FREE_PARAMETERS",
    "PILLAR_FREE_PARAMETERS",
    "CalibrationFit",
    "CalibrationPoints",
    "LinearRange",
    "Measurement",
    "fit",
    "linear_range",
    "measure",
    "model_tip_deflection",
    "points_fingerprint",
    "read_points",
]

FloatArray = NDArray[np.float64]

#: Parameters of a bed that a calibration may fit, with their units.
FREE_PARAMETERS: dict[str, str] = {k: BED[k].unit for k in names(BED, "bed") if k != "density"}
#: Parameters of a :class:`~hairbed.Pillar` that a calibration may fit, with their units.
PILLAR_FREE_PARAMETERS: dict[str, str] = {
    "youngs_modulus": "Pa",
    "drag_scale": "1",
    "base_angle": "rad",
    "length": "m",
    "radius": "m",
}
_LINEAR = ("base_angle",)  # fitted as themselves; the others in their logarithms
_HALF_PI = 0.5 * math.pi
#: The smallest sigma of a fit, relative to the hair length (1e-12 L: far below any
#: microscope; smaller weights overflow).
_SIGMA_LOW = 1e-12
#: The pump drives a calibration may be given, with the unit of the known quantity and the
#: drive of :func:`hairbed.solve_loaded` it maps to.
_PUMPS = {"pressure_gradient": ("Pa/m", "pressure"), "flow_rate": ("m^2/s", "flow")}
#: What each kind of data is, in words (the messages).
_UNITS = {"velocity": "m/s", "wall_shear_stress": "Pa", **{k: v[0] for k, v in _PUMPS.items()}}


# -- the model and its exact Jacobian ---------------------------------------------------------


def _rebuild(bed: HairBed, geometry: str, **changes: Any) -> HairBed:
    """A copy of ``bed`` with ``changes``; ``geometry`` ("spacing" or "packing_fraction") is
    the one of the two that stays fixed when the radius changes."""
    if geometry == "spacing":
        return replace(bed, packing_fraction=None, **changes)
    return replace(bed, spacing=None, **changes)


def _log_slopes(geometry: str, kind: str) -> dict[str, tuple[float, float]]:
    """(d ln X/d ln P, d ln eps/d ln P) for each positive parameter P, where X is omega^2
    (velocity data), omega_eps^2 (stress data), pi (pressure gradient) or q (flow rate)."""
    radius = -4.0 if geometry == "spacing" else -2.0
    if kind == "pressure_gradient":  # pi = A G L^3/(E I): no eta; H through eps only
        return {
            "length": (3.0, 1.0),
            "radius": (radius, 0.0),
            "youngs_modulus": (-1.0, 0.0),
            "channel_height": (0.0, -1.0),
            "viscosity": (0.0, 0.0),
            "spacing": (2.0, 0.0),
            "packing_fraction": (-1.0, 0.0),
        }
    if kind == "flow_rate":  # q = 6 A eta Q' L^2/(E I H^2)
        return {
            "length": (2.0, 1.0),
            "radius": (radius, 0.0),
            "youngs_modulus": (-1.0, 0.0),
            "channel_height": (-2.0, -1.0),
            "viscosity": (1.0, 0.0),
            "spacing": (2.0, 0.0),
            "packing_fraction": (-1.0, 0.0),
        }
    if kind == "velocity":  # omega^2 = 4 L^2 eta v/(E a^2 H phi), eps = L/H
        return {
            "length": (2.0, 1.0),
            "radius": (radius, 0.0),
            "youngs_modulus": (-1.0, 0.0),
            "channel_height": (-1.0, -1.0),
            "viscosity": (1.0, 0.0),
            "spacing": (2.0, 0.0),
            "packing_fraction": (-1.0, 0.0),
        }
    # omega_eps^2 = F L^2/(E I) = 4 L^2 tau/(E a^2 phi): neither H nor eta
    return {
        "length": (2.0, 0.0),
        "radius": (radius, 0.0),
        "youngs_modulus": (-1.0, 0.0),
        "channel_height": (0.0, 0.0),
        "viscosity": (0.0, 0.0),
        "spacing": (2.0, 0.0),
        "packing_fraction": (-1.0, 0.0),
    }


def _forcing(bed: HairBed, kind: str, x: FloatArray) -> tuple[FloatArray, FloatArray, float]:
    """(direction, forcing, d forcing/d|x|) of wall speeds or stresses ``x``: the forcing is
    omega^2 (velocity data) or omega_eps^2 (stress data), linear in |x|; for pump data the
    signed load pi or q, linear in x (direction 1: the loaded solver takes signed loads)."""
    if kind in _PUMPS:
        if kind == "pressure_gradient":
            scale = bed.wall_area_per_hair * bed.length**3 / bed.bending_stiffness
        else:
            scale = (
                6.0
                * bed.wall_area_per_hair
                * bed.viscosity
                * bed.length**2
                / (bed.bending_stiffness * bed.channel_height**2)
            )
        return np.ones(x.shape), x * scale, scale
    direction = np.where(x < 0.0, -1.0, 1.0)
    if kind == "velocity":
        scale = 1.0 / bed.velocity_scale
    else:  # omega_eps^2 = tau (wall area per hair) L^2/(E I)
        scale = bed.wall_area_per_hair * bed.length**2 / bed.bending_stiffness
    return direction, np.abs(x) * scale, scale


def _model(
    bed: HairBed, kind: str, x: FloatArray, free: Sequence[str], geometry: str
) -> tuple[FloatArray, FloatArray, FloatArray, Any]:
    """:func:`_model_at` of the calibration curve's state at ``x``: the low root where several
    states share one speed (stress data have one state: x1 does not depend on eps, and at
    eps = 0 the branch is monotone)."""
    return _model_at(bed, kind, x, _curve_state(bed, kind, x), free, geometry)


def _curve_state(bed: HairBed, kind: str, x: FloatArray) -> Any:
    """The dimensionless state of the calibration curve at wall speeds or stresses ``x``."""
    direction, forcing, _ = _forcing(bed, kind, x)
    if not np.all(np.isfinite(forcing)):  # a fit's trial bed far from the data's scale
        raise ValueError(f"the forcing of {kind} {float(np.max(np.abs(x)))!r} overflows")
    if kind in _PUMPS:
        zero = np.zeros(forcing.shape)
        return bed._tip_state(zero, bed.eps, bed.base_angle, _PUMPS[kind][1], forcing)
    eps = bed.eps if kind == "velocity" else 0.0
    return bed._tip_state(forcing, eps, direction * bed.base_angle)


def _warn_validity(
    bed: HairBed, kind: str, x: FloatArray, sol: Any, shape: tuple[int, ...]
) -> None:
    """The model's validity where it was evaluated in SI: a :class:`ModelValidityWarning`
    where the gap flow's Reynolds number exceeds 1 (as :meth:`HairBed.deform` does; the bed's
    dense-bed condition is checked when the bed is made). The gap is H - h1 L of the state
    (h1 is the same on the collapsed curve of stress data)."""
    if bed.density is None:
        return
    h1 = np.asarray(sol.tip_height, dtype=np.float64).reshape(-1)
    gap = bed.channel_height - bed.length * h1
    if kind in _PUMPS:
        flow = gap_flow(bed, _PUMPS[kind][1], np.zeros(x.shape), x, h1)
        reynolds = np.where(np.isfinite(h1), flow["reynolds_number"], 0.0)
    elif kind == "velocity":
        reynolds = bed.density * np.abs(x) * gap / bed.viscosity
    else:
        reynolds = _reynolds_of_stress(bed, x, gap)
    _warn_reynolds(reynolds.reshape(shape))


def _model_at(
    bed: HairBed, kind: str, x: FloatArray, sol: Any, free: Sequence[str], geometry: str
) -> tuple[FloatArray, FloatArray, FloatArray, Any]:
    """Tip deflection D [m] at wall speeds or stresses ``x``, dD/dP for each free parameter P
    (in P's units; shape (len(x), len(free))) and dD/dx; and the derivatives used.

    ``sol`` is the dimensionless state at each x (forcing of :func:`_forcing`, base angle
    direction * theta0; eps = 0 for stress data; a LoadedState of the load for pump data):
    the one the derivatives are taken on, so that inside a bistable window they are those of
    the state meant, not of another root.
    """
    direction, forcing, d_forcing = _forcing(bed, kind, x)
    length = bed.length
    der = derivatives_at(sol)
    x1 = np.asarray(sol.tip_deflection, dtype=np.float64).reshape(-1)
    dx1 = der["tip_deflection"]
    load = {"pressure_gradient": "pi", "flow_rate": "q"}.get(kind, "omega2")
    dx1_w, dx1_e, dx1_t = (
        np.asarray(dx1[name], dtype=np.float64).reshape(-1) for name in (load, "eps", "theta0")
    )
    deflection = direction * length * x1
    slopes = _log_slopes(geometry, kind)
    # a porous bed's kappa and gamma move with its geometry (empty for the dense bed)
    drag = bed._drag_slopes(geometry)
    if drag:
        dx1_k, dx1_g = (
            np.asarray(dx1[name], dtype=np.float64).reshape(-1) for name in ("kappa", "gamma")
        )
        kappa = bed.kappa
    eps = bed.eps
    jac = np.empty((x.size, len(free)))
    for j, name in enumerate(free):
        if name == "base_angle":
            jac[:, j] = length * dx1_t  # direction^2 = 1
            continue
        value = float(getattr(bed, name))
        lw, le = slopes[name]
        dlog = dx1_w * forcing * lw + (dx1_e * eps * le if kind != "wall_shear_stress" else 0.0)
        if name in drag:
            lk, lg = drag[name]
            dlog = dlog + dx1_k * kappa * lk + dx1_g * lg
        d_lnp = direction * (length * dlog + (x1 * length if name == "length" else 0.0))
        jac[:, j] = d_lnp / value
    # dD/dx: dD/d forcing times d forcing/d|x| times d|x|/dx (= direction): direction^2 = 1
    dx = length * dx1_w * d_forcing
    return deflection, jac, dx, der


def model_tip_deflection(
    bed: HairBed | Pillar,
    *,
    velocity: ArrayLike | None = None,
    wall_shear_stress: ArrayLike | None = None,
    pressure_gradient: ArrayLike | None = None,
    flow_rate: ArrayLike | None = None,
) -> Any:
    """The bed's tip deflection [m] at wall speeds [m/s], wall shear stresses [Pa], or (both
    walls at rest) pressure gradients G = -dp/dx [Pa/m] or flow rates per unit width [m^2/s].

    The calibration curve itself (flow towards +x for positive values, its mirror image for
    negative ones; the low state where several coexist at one speed). Give exactly one of
    the four (a :class:`~hairbed.Pillar` takes ``wall_shear_stress``, or ``velocity``, the
    wall speed of a "couette" pillar: its :meth:`~hairbed.Pillar.deform`). Where a
    pump-driven state is not found the deflection is NaN.
    """
    check_type(bed, "bed", (HairBed, Pillar), _SENSORS)
    bed._require_scalar("the calibration")
    if isinstance(bed, Pillar):
        _no_pump(pressure_gradient, flow_rate)
        return bed.deform(_pillar_known(bed, velocity, wall_shear_stress)[1]).tip_deflection
    kind, x = _known(bed, velocity, wall_shear_stress, pressure_gradient, flow_rate)
    flat = x.reshape(-1)
    sol = _curve_state(bed, kind, flat)
    _warn_validity(bed, kind, flat, sol, x.shape)
    return float_or_array(_model_at(bed, kind, flat, sol, (), "spacing")[0].reshape(x.shape))


def _known(
    bed: HairBed, velocity: Any, stress: Any, gradient: Any = None, flow: Any = None
) -> tuple[str, FloatArray]:
    given = {
        "velocity": velocity,
        "wall_shear_stress": stress,
        "pressure_gradient": gradient,
        "flow_rate": flow,
    }
    named = [k for k, v in given.items() if v is not None]
    if len(named) != 1:
        got = ", ".join(f"{k}={show(v)}" for k, v in given.items() if v is not None) or "none"
        raise ValueError(
            "give exactly one of velocity [m/s], wall_shear_stress [Pa], pressure_gradient "
            f"[Pa/m] and flow_rate [m^2/s], got {got}"
        )
    kind = named[0]
    if kind in _PUMPS:
        value = as_float_array(given[kind], kind, unit=_UNITS[kind])
        with np.errstate(over="ignore"):
            load = _forcing(bed, kind, value)[1]
        bad = ~np.isfinite(load)
        if np.any(bad):
            limit = np.finfo(np.float64).max / _forcing(bed, kind, np.ones(1))[2]
            raise ValueError(
                f"{kind} must be within +-{limit:.3g} "
                f"{_UNITS[kind]} for this bed (its dimensionless load overflows), got "
                f"{float(value[bad].flat[0])!r}"
            )
        return kind, value
    if velocity is not None:
        return "velocity", bed._forcing(velocity, "velocity")[0]
    tau = as_float_array(stress, "wall_shear_stress", unit="Pa")
    with np.errstate(over="ignore"):
        forcing = np.abs(tau) * bed.wall_area_per_hair * bed.length**2 / bed.bending_stiffness
    bad = ~np.isfinite(forcing)
    if np.any(bad):
        limit = (
            np.finfo(np.float64).max * bed.bending_stiffness / bed.wall_area_per_hair
        ) / bed.length**2
        raise ValueError(
            f"wall_shear_stress must be below {limit:.3g} Pa for this bed (its forcing "
            f"overflows), got {float(tau[bad].flat[0])!r}"
        )
    return "wall_shear_stress", tau


# -- the pillar's model (theory.md §12) --------------------------------------------------------

#: What ``bed`` may be.
_SENSORS = "a hairbed.HairBed or a hairbed.Pillar"


def _no_pump(gradient: Any, flow: Any) -> None:
    """A pillar stands in a shear layer: no pump drive to calibrate against."""
    for name, value in (("pressure_gradient", gradient), ("flow_rate", flow)):
        if value is not None:
            raise ValueError(
                f"{name} is a pump-driven HairBed's known quantity; a Pillar takes "
                "velocity [m/s] or wall_shear_stress [Pa]"
            )


def _pillar_known(
    pillar: Pillar, velocity: Any, stress: Any
) -> tuple[str, FloatArray, FloatArray]:
    """(kind, the known wall shear stresses [Pa], the values given) of a pillar's calibration
    points: stresses, or the wall speeds of a "couette" pillar (tau_w = eta V/H; the kind is
    then "velocity")."""
    if (velocity is None) == (stress is None):
        raise ValueError(
            "give exactly one of velocity [m/s] (a 'couette' pillar) and wall_shear_stress "
            f"[Pa], got velocity={show(velocity)}, wall_shear_stress={show(stress)}"
        )
    if velocity is not None:
        tau = pillar._stress(None, velocity, None)
        kind, given = "velocity", as_float_array(velocity, "velocity", unit="m/s")
    else:
        tau = pillar._stress(stress, None, None)
        kind, given = "wall_shear_stress", tau
    pillar._forcing(tau)  # its overflow, named
    return kind, tau, given


def _pillar_model_at(
    pillar: Pillar, tau: FloatArray, sol: Any, free: Sequence[str]
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tip deflection D [m] of a pillar at wall shear stresses ``tau`` [Pa] (states ``sol``),
    dD/dP for each free parameter P in P's units (shape (len(tau), len(free))) and dD/dtau.

    D = L x1(Lambda, theta0, gamma[, L/H][, L+]) with (theory.md §12)

        Lambda = 16 c tau L^4/(E a^4 (ln(2L/a) + 1/2)),
        gamma = (ln(2L/a) + 1/2)/(2 ln(2L/a) - 1),

    so dD/d ln E = -L x1_Lambda Lambda, dD/d ln c = +L x1_Lambda Lambda, dD/d theta0 =
    L x1_theta0, dD/d ln L = D + L [x1_Lambda Lambda (4 - 1/(ln(2L/a) + 1/2)) + x1_gamma
    dgamma/dln(2L/a) + x1_r r] (r = L/H of a Poiseuille channel) and dD/d ln a = L [-x1_Lambda
    Lambda (4 - 1/(ln(2L/a) + 1/2)) - x1_gamma dgamma/dln(2L/a)], with
    dgamma/dln(2L/a) = -2/(2 ln(2L/a) - 1)^2: the exact derivatives of the collocation system
    (:func:`hairbed.sensitivity.derivatives_at` of a PillarState; for E and c alone its
    :attr:`hairbed.PillarState.tip_deflection_slope`). With the "wall-law" profile, whose
    shape depends on L+ = L sqrt(tau/rho)/nu (not on E, c or a), dD/d ln L gains
    L x1_(ln L+) and dD/dtau is the pillar's sensitivity (through Lambda and L+).
    """
    length = pillar.length
    x1 = np.asarray(sol.tip_deflection, dtype=np.float64).reshape(-1)
    slope = np.asarray(sol.tip_deflection_slope, dtype=np.float64).reshape(-1)
    lam = np.asarray(sol.forcing, dtype=np.float64).reshape(-1)
    jac = np.empty((x1.size, len(free)))
    geometric = [n for n in free if n in _PILLAR_GEOMETRY]
    d: Any = None
    if geometric:
        d = pillar._tip_derivatives(tau, sol)
    lg = math.log(2.0 * pillar.slenderness)
    dlam = 4.0 - 1.0 / (lg + 0.5)  # d ln Lambda/d ln L = -d ln Lambda/d ln a
    dgam = -2.0 / (2.0 * lg - 1.0) ** 2  # d gamma/d ln(2L/a)

    def of(name: str) -> FloatArray:
        return np.asarray(d[name], dtype=np.float64).reshape(-1)

    for j, name in enumerate(free):
        if name in ("youngs_modulus", "drag_scale"):
            sign = -1.0 if name == "youngs_modulus" else 1.0
            jac[:, j] = sign * length * slope * lam / float(getattr(pillar, name))
        elif name == "base_angle":
            jac[:, j] = length * of("theta0")
        else:
            # the part through ln(2L/a), + for L, - for a
            part = of("forcing") * lam * dlam + of("gamma") * dgam
            if name == "length":
                extra = x1.copy()
                if pillar.profile == "poiseuille":
                    extra += of("height_ratio") * float(pillar.height_ratio)  # type: ignore[arg-type]
                # the wall law's L+ = L u_tau/nu: d ln L+/d ln L = 1
                extra += of("log_l_plus")
                jac[:, j] = extra + part
            else:
                jac[:, j] = -length * part / pillar.radius
    return length * x1, jac, length * pillar._stress_slope(tau, sol).reshape(-1)


#: The geometric parameters of a pillar whose Jacobian needs the derivatives of the state in
#: theta0, gamma and the height ratio (not only in Lambda).
_PILLAR_GEOMETRY = ("base_angle", "length", "radius")


def _pillar_degeneracies(pillar: Pillar, names: Sequence[str]) -> list[str]:
    """Why a pillar's model cannot determine ``names`` (empty if it can).

    D = L x1(Lambda, theta0, gamma, L/H) with Lambda proportional to c tau L^4/(E a^4
    (ln(2L/a) + 1/2)) and gamma a function of L/a alone: E and the drag scale c enter only as
    c/E, whatever else is free. (L, a, E) map one to one to (the scale L of D, gamma(L/a),
    Lambda/tau), so they are determined together, but a and E apart only through the slow
    gamma(L/a) and the logarithm in Lambda: expect large, strongly correlated errors.
    """
    out = []
    together = [n for n in names if n in ("youngs_modulus", "drag_scale")]
    if len(together) > 1:
        out.append(
            f"{', '.join(together)} enter the model only through the one combination "
            "drag_scale/E (Lambda = c zeta_perp tau_w L^4/(eta E I)): free at most one of them"
        )
    if "length" in names and callable(pillar.profile):
        out.append(
            "length: a callable profile u(z) is given in metres, so its dimensionless shape "
            "U(z/L) changes with L in a way the model does not differentiate; fix the length "
            "or use a built-in profile"
        )
    return out


# -- fit ---------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CalibrationFit:
    """The result of :func:`fit`: the calibrated bed and the uncertainty of its parameters.

    Attributes
    ----------
    bed : HairBed or Pillar
        The bed (or pillar) with the fitted parameters.
    parameters : tuple of str
        The free parameters, in the order of ``covariance``.
    values : Mapping[str, float]
        Fitted value of each free parameter, in its unit (:data:`FREE_PARAMETERS`).
    stderr : Mapping[str, float]
        Its standard error (square root of the covariance's diagonal), same unit.
    covariance : ndarray (k, k)
        Covariance of the fitted parameters in their units (linearised at the fit). With
        ``sigma`` given it is (J^T W J)^-1; without, scaled by chi2/dof.
    residuals : ndarray
        Measured minus fitted tip deflection at each calibration point [m].
    chi2 : float
        With ``sigma``: the sum of the squared residuals over sigma^2 [-]. Without: the sum
        of the squared residuals [m^2] (:attr:`chi2_unit` says which).
    dof : int
        Degrees of freedom: number of points minus number of free parameters.
    kind : str
        What the deflections were measured at: "velocity", "wall_shear_stress",
        "pressure_gradient" or "flow_rate".
    success : bool
        The optimiser converged and the parameters are determined by the data.
    status : int
        0 converged; 5 converged with no degrees of freedom (as many points as free
        parameters: the curve passes through every point, chi2 says nothing of the model,
        and without ``sigma`` the standard errors are infinite); -2 the evaluation limit;
        -4 the data do not determine every free parameter (a singular Jacobian; the message
        names the parameters that enter the model only together): the undetermined ones
        have NaN values, standard errors and covariances, and ``bed`` keeps their given
        values (a fit fails in this one way: it neither raises nor returns the optimiser's
        wandering values)
        (:data:`~hairbed._core.validation.STATUS_MESSAGES`).
    message : str
        What happened.
    nfev : int
        Number of evaluations of the model.
    nit : int
        Iterations of the optimiser (its evaluations of the Jacobian).
    solver_status : int
        :func:`scipy.optimize.least_squares`'s own status (1 to 4: which tolerance stopped
        it, 0 the evaluation limit, -1 improper input).
    weighted : bool
        Whether the deflections had a ``sigma`` (chi2 is then dimensionless).
    fingerprint : str
        SHA-256 of the calibration points (:func:`points_fingerprint`): which data the
        calibration came from.
    start : Mapping[str, float]
        The starting value of each free parameter (the bed given to :func:`fit`).
    """

    bed: HairBed | Pillar
    parameters: tuple[str, ...]
    values: Mapping[str, float]
    stderr: Mapping[str, float]
    covariance: FloatArray
    residuals: FloatArray
    chi2: float
    dof: int
    kind: str
    success: bool
    status: int
    message: str
    nfev: int
    nit: int = 0
    solver_status: int = 0
    #: the one of spacing / packing fraction held fixed when the radius varies
    geometry: str = field(default="spacing", repr=False)
    weighted: bool = True
    fingerprint: str = ""
    start: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def chi2_unit(self) -> str:
        """The unit of :attr:`chi2`: "1" (weighted by sigma) or "m^2" (a sum of squares)."""
        return "1" if self.weighted else "m^2"

    @property
    def reduced_chi2(self) -> float:
        """chi2 / dof (about 1 for a good model with correct sigma); NaN when dof = 0."""
        return self.chi2 / self.dof if self.dof > 0 else float("nan")


def _undetermined(
    names: Sequence[str], sv: FloatArray, vt: FloatArray, why: Sequence[str]
) -> NDArray[np.bool_]:
    """Which free parameters a rank-deficient fit leaves undetermined: those with a part in
    the null space of its Jacobian (in the fit's coordinates), and those a degeneracy names."""
    out = np.zeros(len(names), dtype=np.bool_)
    if sv.size:
        null = vt[sv <= sv[0] * 1e-10]
        out |= np.any(np.abs(null) > 1e-6, axis=0)
    for j, nm in enumerate(names):
        out[j] |= any(re.search(rf"\b{nm}\b", text) is not None for text in why)
    if not np.any(out):  # singular, but no parameter stands out: none is determined
        out[:] = True
    return out


def _check_free(
    free: Any, allowed: Mapping[str, str] = FREE_PARAMETERS, what: str = "bed"
) -> tuple[str, ...]:
    if isinstance(free, str):
        free = tuple(p.strip() for p in free.split(",") if p.strip())
    try:
        names = tuple(free)
    except TypeError:
        raise ValueError(f"free must be a sequence of parameter names, got {show(free)}") from None
    if not names:
        raise ValueError(f"free must name at least one parameter of the {what}")
    for name in names:
        if not isinstance(name, str) or name not in allowed:
            raise ValueError(
                f"free: unknown parameter {show(name)}; allowed for a {what}: {', '.join(allowed)}"
            )
    if len(set(names)) != len(names):
        raise ValueError(f"free names a parameter twice: {names!r}")
    if "spacing" in names and "packing_fraction" in names:
        raise ValueError(
            "free: spacing and packing_fraction are one parameter (phi = (2 pi/sqrt 3) a^2/"
            "delta^2); free at most one of them"
        )
    return names


def _degeneracies(names: Sequence[str], kind: str, geometry: str) -> list[str]:
    """Why the model cannot determine ``names`` from ``kind`` data (empty if it can).

    Velocity data: D = L x1(omega^2, L/H, theta0) with omega^2 = 4 L^2 eta v/(E a^2 H phi),
    and phi = (2 pi/sqrt 3) a^2/delta^2 at fixed spacing, so E, a, eta and delta (or phi)
    enter only through eta delta^2/(E a^4) (at fixed spacing) or eta/(E a^2 phi) (at fixed
    packing fraction); L enters also as the scale of D and through eps, H through eps.
    Stress data: D = L x1(omega_eps^2, theta0) with omega_eps^2 = 4 L^2 tau/(E a^2 phi):
    H and eta do not enter, and E, a and delta (or phi) only through delta^2/(E a^4) (or
    1/(E a^2 phi)).
    Pressure-gradient data: D = L x1(pi, L/H, theta0) with pi = A G L^3/(E I): eta does not
    enter, and E, a, delta (or phi) only as for stress data. Flow-rate data: q = 6 A eta Q'
    L^2/(E I H^2), E, a, eta, delta (or phi) only as for velocity data.
    """
    out = []
    group = ["youngs_modulus", "radius", "spacing", "packing_fraction"]
    if kind == "pressure_gradient" and "viscosity" in names:
        out.append(
            "viscosity does not enter pressure-gradient data (both walls at rest: the load "
            "is the gradient times the wall area per hair)"
        )
    if kind in ("velocity", "flow_rate"):
        group.append("viscosity")
        combination = "eta delta^2/(E a^4)" if geometry == "spacing" else "eta/(E a^2 phi)"
    elif kind == "pressure_gradient":
        combination = "delta^2/(E a^4)" if geometry == "spacing" else "1/(E a^2 phi)"
    else:
        absent = [n for n in names if n in ("channel_height", "viscosity")]
        if absent:
            out.append(
                f"{' and '.join(absent)} do{'es' if len(absent) == 1 else ''} not enter stress "
                "data (the load on a hair is the stress times its wall area)"
            )
        combination = "delta^2/(E a^4)" if geometry == "spacing" else "1/(E a^2 phi)"
    together = [n for n in names if n in group]
    if len(together) > 1:
        out.append(
            f"{', '.join(together)} enter the model only through the one combination "
            f"{combination}: free at most one of them"
        )
    return out


def points_fingerprint(
    tip_deflection: ArrayLike,
    *,
    velocity: ArrayLike | None = None,
    wall_shear_stress: ArrayLike | None = None,
    sigma: ArrayLike | None = None,
    pressure_gradient: ArrayLike | None = None,
    flow_rate: ArrayLike | None = None,
) -> str:
    """SHA-256 (hex) of calibration points: which data a calibration came from.

    The digest of the bytes of the kind ("velocity", "wall_shear_stress",
    "pressure_gradient" or "flow_rate", ASCII), then the known flows, the deflections and (if
    given) sigma broadcast to them, each as little-endian float64.
    :attr:`CalibrationFit.fingerprint` is this of the data :func:`fit` was given.
    """
    given = {
        "velocity": velocity,
        "wall_shear_stress": wall_shear_stress,
        "pressure_gradient": pressure_gradient,
        "flow_rate": flow_rate,
    }
    named = [k for k, v in given.items() if v is not None]
    if len(named) != 1:
        raise ValueError(
            "give exactly one of velocity [m/s], wall_shear_stress [Pa], pressure_gradient "
            "[Pa/m] and flow_rate [m^2/s]"
        )
    kind = named[0]
    known = as_float_array(given[kind], kind, unit=_UNITS[kind])
    d = as_float_array(tip_deflection, "tip_deflection", unit="m").reshape(-1)
    if known.size != d.size:
        raise ValueError(
            f"tip_deflection and {kind} must have the same length, got {d.size} and {known.size}"
        )
    sig = None if sigma is None else check_sigma(sigma, "sigma", d.shape, unit="m")
    return _fingerprint(kind, known.reshape(-1), d, sig)


def _fingerprint(kind: str, x: FloatArray, d: FloatArray, sigma: Any) -> str:
    digest = hashlib.sha256(kind.encode("ascii"))
    digest.update(np.ascontiguousarray(x, dtype="<f8").tobytes())
    digest.update(np.ascontiguousarray(d, dtype="<f8").tobytes())
    if sigma is not None:
        s = np.broadcast_to(np.asarray(sigma, dtype=np.float64), d.shape)
        digest.update(np.ascontiguousarray(s, dtype="<f8").tobytes())
    return digest.hexdigest()


def _pillar_bounds(pillar: Pillar, free: tuple[str, ...]) -> tuple[FloatArray, FloatArray]:
    """Bounds of a pillar's fitted coordinates (theta0 in (-pi/2, pi/2), L <= H, L/a > 1.5
    for the one of L, a that is free alone); E and the drag scale in their logarithms are
    unbounded."""
    lo = np.full(len(free), -np.inf)
    hi = np.full(len(free), np.inf)
    margin = 1e-9
    for j, name in enumerate(free):
        if name == "base_angle":
            lo[j], hi[j] = -_HALF_PI + margin, _HALF_PI - margin
        elif name == "length":
            if pillar.channel_height is not None:
                hi[j] = math.log(pillar.channel_height)
            if "radius" not in free:
                lo[j] = math.log(1.5 * pillar.radius) + margin
        elif name == "radius" and "length" not in free:
            hi[j] = math.log(pillar.length / 1.5) - margin
    return lo, hi


def _bounds(bed: HairBed, free: tuple[str, ...], geometry: str) -> tuple[FloatArray, FloatArray]:
    """Bounds of the fitted coordinates that keep the bed valid (L < H, a < delta/2, ...)."""
    lo = np.full(len(free), -np.inf)
    hi = np.full(len(free), np.inf)
    margin = 1e-9
    for j, name in enumerate(free):
        if name == "base_angle":
            lo[j], hi[j] = -_HALF_PI + margin, _HALF_PI - margin
        elif name == "length" and "channel_height" not in free:
            hi[j] = math.log(bed.channel_height) - margin
        elif name == "channel_height" and "length" not in free:
            lo[j] = math.log(bed.length) + margin
        elif name == "radius" and geometry == "spacing" and "spacing" not in free:
            hi[j] = math.log(0.5 * float(bed.spacing)) - margin  # type: ignore[arg-type]
        elif name == "spacing" and "radius" not in free:
            lo[j] = math.log(2.0 * bed.radius) + margin
        elif name == "packing_fraction":
            top = CLOSE_PACKING_FRACTION if bed.model == "dense" else MAX_PACKING_FRACTION
            hi[j] = math.log(top) - margin
    return lo, hi


def fit(
    bed: HairBed | Pillar,
    tip_deflection: ArrayLike,
    *,
    wall_shear_stress: ArrayLike | None = None,
    velocity: ArrayLike | None = None,
    sigma: ArrayLike | None = None,
    free: Sequence[str] | str = ("youngs_modulus",),
    pressure_gradient: ArrayLike | None = None,
    flow_rate: ArrayLike | None = None,
) -> CalibrationFit:
    """Fit a bed's unknown parameters to tip deflections measured at known flows.

    Weighted least squares on the exact calibration curve (Levenberg-Marquardt-type trust
    region, :func:`scipy.optimize.least_squares`, with the exact Jacobian of
    :func:`hairbed.derivatives` through the SI scaling; module docstring). The bed's current
    values are the starting point and the values of the parameters not fitted.

    Parameters
    ----------
    bed : HairBed or Pillar
        The sensor, with its best prior values.
    tip_deflection : array_like
        Measured tip deflections [m] along +x, one per calibration point.
    wall_shear_stress : array_like, optional
        The known wall shear stress of each point [Pa]. Give this or ``velocity``.
    velocity : array_like, optional
        The known top-wall speed of each point [m/s].
    pressure_gradient, flow_rate : array_like, optional
        Or, for a pump-driven bed with both walls at rest, the known pressure gradient
        G = -dp/dx [Pa/m] or flow rate per unit width Q' [m^2/s] of each point (module
        docstring; the Jacobian by implicit differentiation of the loaded states).
    sigma : float or array_like, optional
        Standard deviation of each measured deflection [m], in [1e-12 L, L] (L the hair
        length): one number, or one per point. Without it the errors are estimated from the
        scatter of the residuals (chi2/dof).
    free : sequence of str or comma-separated str
        Parameters to fit, from :data:`FREE_PARAMETERS` (``"youngs_modulus"`` by default),
        or for a pillar :data:`PILLAR_FREE_PARAMETERS` (youngs_modulus or drag_scale,
        base_angle, length, radius; length not with a callable profile). Stress data do
        not determine ``channel_height`` or ``viscosity``, pressure-gradient data not
        ``viscosity``; a
        pillar takes ``velocity`` only in a Couette channel (tau_w = eta V/H).

    Returns
    -------
    CalibrationFit
        The fitted bed, values, standard errors, covariance, residuals, chi2, and how the
        optimiser ended (``success``, ``status``, ``message``).

    Raises
    ------
    ValueError
        For inconsistent inputs (lengths, non-positive sigma, unknown parameter names,
        fewer points than free parameters).

    Examples
    --------
    >>> import numpy as np
    >>> from hairbed import HairBed
    >>> true = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1.3e6,
    ...                channel_height=2e-3, viscosity=1.0, spacing=400e-6)
    >>> v = np.linspace(0.01, 0.2, 8)
    >>> d = model_tip_deflection(true, velocity=v)
    >>> guess = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6,
    ...                 channel_height=2e-3, viscosity=1.0, spacing=400e-6)
    >>> result = fit(guess, d, velocity=v, sigma=1e-6)
    >>> round(result.values["youngs_modulus"] / 1e6, 9), result.success
    (1.3, True)
    """
    check_type(bed, "bed", (HairBed, Pillar), _SENSORS)
    bed._require_scalar("the calibration")
    pillar = isinstance(bed, Pillar)
    if isinstance(bed, Pillar):
        _no_pump(pressure_gradient, flow_rate)
        names = _check_free(free, PILLAR_FREE_PARAMETERS, "pillar")
        if "youngs_modulus" in names and "drag_scale" in names:  # one parameter, c/E
            raise ValueError(f"free: {_pillar_degeneracies(bed, names)[0]}")
        kind, x, given = _pillar_known(bed, velocity, wall_shear_stress)
    else:
        names = _check_free(free)
        kind, x = _known(bed, velocity, wall_shear_stress, pressure_gradient, flow_rate)
        given = x
    if "length" in names:  # the fitted length must hold them; checked after the fit
        d = as_float_array(tip_deflection, "tip_deflection", unit="m").reshape(-1)
    else:  # as measure() checks them: a tip deflection lies in (-length, length)
        d = bed._deflection(tip_deflection, "tip_deflection").reshape(-1)
    x = x.reshape(-1)
    if x.size != d.size:
        raise ValueError(
            f"tip_deflection and {kind} must have the same length, got {d.size} and {x.size}"
        )
    if d.size < len(names):
        raise ValueError(
            f"a fit of {len(names)} parameter(s) needs at least as many points, got {d.size}"
        )
    sig: FloatArray | None = None
    if sigma is None:  # unit weights, in units of the hair length (well-scaled optimiser)
        weights = np.full(d.size, 1.0 / bed.length)
    else:
        sig = check_sigma(
            sigma, "sigma", d.shape, unit="m", low=_SIGMA_LOW * bed.length, high=bed.length
        )
        weights = 1.0 / sig
    geometry = "packing_fraction" if "packing_fraction" in names else "spacing"

    def coords_to_bed(p: FloatArray) -> Any:
        changes = {
            name: (float(v) if name in _LINEAR else math.exp(float(v)))
            for name, v in zip(names, p)
        }
        with warnings.catch_warnings():  # a trial bed's: the fitted bed is checked below
            warnings.simplefilter("ignore", UnitsWarning)
            warnings.simplefilter("ignore", ModelValidityWarning)
            if isinstance(bed, Pillar):
                return replace(bed, **changes)  # type: ignore[arg-type]
            return _rebuild(bed, geometry, **changes)

    def scale(b: Any) -> FloatArray:  # dP/dp of each coordinate
        return np.array([1.0 if nm in _LINEAR else float(getattr(b, nm)) for nm in names])

    cache: dict[bytes, tuple[FloatArray, FloatArray]] = {}

    def evaluate(p: FloatArray) -> tuple[FloatArray, FloatArray]:
        key = p.tobytes()
        if key not in cache:
            b = coords_to_bed(p)
            if pillar:
                model, jac, _ = _pillar_model_at(b, x, b._solve(b._forcing(x)), names)
            else:
                model, jac, _, _ = _model(b, kind, x, names, geometry)
            cache.clear()
            cache[key] = (weights * (model - d), weights[:, None] * jac * scale(b))
        return cache[key]

    p0 = np.array(
        [float(getattr(bed, nm)) if nm in _LINEAR else math.log(getattr(bed, nm)) for nm in names]
    )
    if isinstance(bed, Pillar):
        why = _pillar_degeneracies(bed, names)
        if "length" in names and callable(bed.profile):
            raise ValueError(f"free: {why[-1]}")
        lo, hi = _pillar_bounds(bed, names)
    else:
        lo, hi = _bounds(bed, names, geometry)
    p0 = np.clip(p0, lo, hi)
    try:
        res = least_squares(
            lambda p: evaluate(p)[0],
            p0,
            jac=lambda p: evaluate(p)[1],
            bounds=(lo, hi),
            method="trf",
            xtol=1e-12,
            ftol=1e-12,
            gtol=1e-12,
        )
    except ValueError as exc:  # a trial bed outside the admissible range (L >= H, ...)
        raise ValueError(f"the fit left the admissible parameters of the bed: {exc}") from None
    fitted = coords_to_bed(res.x)
    r, jw = evaluate(res.x)
    chi2 = float(r @ r)  # of the internal weights: the scatter estimate below uses it
    dof = d.size - len(names)
    # the rank in the fitted coordinates (logarithms: E [Pa] and L [m] differ by 1e9 in their
    # own units, which alone would pass for a singular Jacobian), the covariance then carried
    # to the own units, diag(dP/dp) C diag(dP/dp)
    to_units = scale(fitted)
    u, sv, vt = np.linalg.svd(jw, full_matrices=False)
    why = (
        _pillar_degeneracies(bed, names)
        if isinstance(bed, Pillar)
        else _degeneracies(names, kind, geometry)
    )
    rank_ok = not why and sv.size > 0 and sv[-1] > sv[0] * 1e-10
    status, success, message = (
        least_squares_status(int(res.status)),
        bool(res.success),
        str(res.message),
    )
    undetermined = np.zeros(len(names), dtype=np.bool_)
    if rank_ok:
        cov = (vt.T / sv**2) @ vt
        cov = to_units[:, None] * cov * to_units[None, :]
    else:
        # one way to fail (issue 33): a status, and NaN for what the data do not determine
        # (the parameters in the Jacobian's null space, or named by a degeneracy), never
        # the optimiser's wandering values or an infinite error
        undetermined = _undetermined(names, sv, vt, why)
        keep = sv > (sv[0] if sv.size else 0.0) * 1e-10
        pinv = np.zeros((len(names), len(names)))
        if np.any(keep):  # the determined combinations' part (pseudo-inverse)
            pinv = (vt[keep].T / sv[keep] ** 2) @ vt[keep]
        cov = to_units[:, None] * pinv * to_units[None, :]
        cov[undetermined, :] = np.nan
        cov[:, undetermined] = np.nan
        status, success = -4, False
        message = "the data do not determine every free parameter (singular Jacobian): " + (
            "; ".join(why) if why else "fix some of " + ", ".join(names)
        )
    if sigma is None:
        cov = cov * (chi2 / dof if dof > 0 else np.inf)
        chi2 *= bed.length**2  # [m^2]: the sum of squared residuals
    if dof == 0 and status == 0:
        status = 5
        message = (
            f"no degrees of freedom: {d.size} point(s) for {len(names)} free parameter(s), "
            "so the curve passes through every point and chi2 says nothing of the model"
            + ("" if sigma is not None else "; without sigma the standard errors are infinite")
        )
        warnings.warn(f"calibration.fit: {message}", CalibrationWarning, stacklevel=2)
    if pillar:
        # the model's validity at the data (the pillar Reynolds number, L+); without a density
        # that the checks are off is said by the fitted pillar's first state asked for
        lam = fitted._forcing(x)
        fitted._state(x, lam, fitted._solve(lam), tell=False)
    else:
        if set(names) & {"length", "radius", "spacing", "packing_fraction"}:
            _warn_sparse(fitted, stacklevel=3)
        _warn_validity(fitted, kind, x, _curve_state(fitted, kind, x), x.shape)
    stderr = np.sqrt(np.diag(cov))
    values = {
        nm: math.nan if undetermined[j] else float(getattr(fitted, nm))
        for j, nm in enumerate(names)
    }
    if np.any(undetermined):  # the bed keeps its given values of the undetermined ones
        back = {nm: float(getattr(bed, nm)) for j, nm in enumerate(names) if undetermined[j]}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnitsWarning)
            warnings.simplefilter("ignore", ModelValidityWarning)
            if isinstance(bed, Pillar):
                fitted = replace(fitted, **back)
            else:
                fitted = _rebuild(fitted, geometry, **back)
    return CalibrationFit(
        bed=fitted,
        parameters=names,
        values=MappingProxyType(values),
        stderr=MappingProxyType({nm: float(e) for nm, e in zip(names, stderr)}),
        covariance=cov,
        residuals=-r / weights,
        chi2=chi2,
        dof=dof,
        kind=kind,
        success=success,
        status=status,
        message=message,
        nfev=int(res.nfev),
        nit=int(res.njev or 0),
        solver_status=int(res.status),
        geometry=geometry,
        weighted=sigma is not None,
        fingerprint=_fingerprint(kind, given.reshape(-1), d, sig),
        start=MappingProxyType({nm: float(getattr(bed, nm)) for nm in names}),
    )


# -- measure -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Measurement:
    """A flow read from a tip deflection, with standard errors (from :func:`measure`).

    Attributes
    ----------
    tip_deflection : float or ndarray
        The measured deflection [m].
    wall_shear_stress, wall_shear_stress_stderr : float or ndarray
        Wall shear stress tau [Pa] and its standard error [Pa].
    velocity, velocity_stderr : float or ndarray
        Top-wall speed v [m/s] and its standard error [m/s].
    state : HairState or PillarDeformation
        The state of the bed (or pillar) at that deflection.
    success : bool
        True when every error is finite (no fold, no singular calibration).
    status : int
        0 ok; 2 a standard error is infinite (at a fold of the bed, or an undetermined fit);
        -2 (a pump drive) the inversion did not reach the deflection in its iteration limit
        (:data:`~hairbed._core.validation.STATUS_MESSAGES`).
    message : str
        What happened.
    pressure_gradient, pressure_gradient_stderr : float or ndarray or None
        For a pump-driven bed (``drive`` of :func:`measure`): the pressure gradient
        G = -dp/dx [Pa/m] and its standard error; None otherwise.
    flow_rate, flow_rate_stderr : float or ndarray or None
        The same of the flow rate per unit width Q' [m^2/s].
    """

    tip_deflection: Any
    wall_shear_stress: Any
    wall_shear_stress_stderr: Any
    velocity: Any
    velocity_stderr: Any
    state: Any = field(repr=False)  # HairState or PillarDeformation
    success: bool
    status: int
    message: str
    pressure_gradient: Any = None
    pressure_gradient_stderr: Any = None
    flow_rate: Any = None
    flow_rate_stderr: Any = None


#: The most Newton steps of the inversion of a pump-driven bed's deflection.
_MEASURE_STEPS = 60
#: It ends where the dimensionless deflection x1 is reached within this.
_MEASURE_XTOL = 1e-13


def _invert_pumped(bed: HairBed, kind: str, d: FloatArray) -> tuple[FloatArray, Any, bool]:
    """(known drive x, LoadedState, converged) of deflections d [m] of a pump-driven bed (both
    walls at rest): damped Newton on the load with the exact dx1/dload, from the slope at
    rest, the low state at every step."""
    drive = _PUMPS[kind][1]
    name = "pi" if drive == "pressure" else "q"
    target = d / bed.length
    zero = np.zeros(d.size)
    eps, angle = bed.eps, bed.base_angle
    rest = bed._tip_state(zero, eps, angle, drive, zero)
    slope = np.asarray(derivatives_at(rest)["tip_deflection"][name], dtype=np.float64)
    x1 = np.asarray(rest.tip_deflection, dtype=np.float64).reshape(-1)
    load = (target - x1) / slope.reshape(-1)
    good = zero.copy()
    st = rest
    converged = False
    for _ in range(_MEASURE_STEPS):
        st = bed._tip_state(zero, eps, angle, drive, load)
        x1 = np.asarray(st.tip_deflection, dtype=np.float64).reshape(-1)
        lost = ~np.isfinite(x1)
        if np.any(lost):  # no state there: back halfway to the last load that had one
            load = np.where(lost, 0.5 * (load + good), load)
            continue
        good = load
        r = x1 - target
        if np.all(np.abs(r) <= _MEASURE_XTOL):
            converged = True
            break
        dx = np.asarray(derivatives_at(st)["tip_deflection"][name], dtype=np.float64)
        step = -r / dx.reshape(-1)
        limit = np.maximum(1.0, np.abs(load))  # at most the load itself a step
        load = load + np.clip(step, -limit, limit)
    scale = _forcing(bed, kind, np.ones(1))[2]
    return load / scale, st, converged


def _porous_pump_slopes(
    bed: HairBed, kind: str, state: Any, der: Any
) -> tuple[FloatArray, FloatArray]:
    """(d tau/dx, d other/dx) of a porous bed's pump-driven states at the known drive x
    (G [Pa/m] or Q' [m^2/s]), exact: tau = Q(1) E I/(A L^2), G = pi E I/(A L^3), from the
    derivatives ``der`` of the states. The flux of a set G is no output of the pressure
    drive's derivatives: dQ'/dG is 1/(dG/dQ') of the same state solved as the flow drive at
    its flux (NaN where that solve finds another state)."""
    name = "pi" if kind == "pressure_gradient" else "q"
    scale = _forcing(bed, kind, np.ones(1))[2]
    stress = bed.bending_stiffness / (bed.wall_area_per_hair * bed.length**2)
    to_g = stress / bed.length  # G per unit pi
    d_tau = np.asarray(der["tip_stress"][name], dtype=np.float64).reshape(-1) * scale * stress
    if kind == "flow_rate":
        d_pi = np.asarray(der["pi"]["q"], dtype=np.float64).reshape(-1)
        return d_tau, d_pi * scale * to_g
    q_scale = _forcing(bed, "flow_rate", np.ones(1))[2]
    flux = np.asarray(state.flow_rate, dtype=np.float64).reshape(-1)
    zero = np.zeros(flux.size)
    twin = bed._tip_state(zero, bed.eps, bed.base_angle, "flow", flux * q_scale)
    same = (
        np.abs(
            np.asarray(twin.tip_height).reshape(-1)
            - np.asarray(state.tip_height, dtype=np.float64).reshape(-1) / bed.length
        )
        <= 1e-8
    )
    d_pi = np.asarray(derivatives_at(twin)["pi"]["q"], dtype=np.float64).reshape(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        d_flux = np.where(same, 1.0 / (d_pi * q_scale * to_g), np.nan)
    return d_tau, d_flux


def _measure_pumped(
    bed: HairBed, kind: str, d: FloatArray, s: FloatArray, fit: CalibrationFit | None
) -> Measurement:
    """:func:`measure` of a pump-driven bed: the known drive of :func:`fit` from deflections."""
    flat = d.reshape(-1)
    x, sol, converged = _invert_pumped(bed, kind, flat)
    names = fit.parameters if fit is not None else ()
    geometry = fit.geometry if fit is not None else "spacing"
    _, jac, dd_dx, der = _model_at(bed, kind, x, sol, names, geometry)
    sig = np.broadcast_to(s, d.shape).reshape(-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        var = (sig / dd_dx) ** 2
        if fit is not None:
            g = -jac / dd_dx[:, None]
            var = var + np.einsum("ij,jk,ik->i", g, fit.covariance, g)
    err = np.sqrt(var)
    xs = x.reshape(d.shape)  # the state in the deflection's shape (floats for a scalar)
    state = bed.deform(None, pressure_gradient=xs if kind == "pressure_gradient" else None,
                       flow_rate=xs if kind == "flow_rate" else None)  # fmt: skip
    # the stress and the other drive follow from x and h1(x): their errors through x (at
    # fixed bed: the bed's own covariance enters through x only)
    name = "pi" if kind == "pressure_gradient" else "q"
    scale = _forcing(bed, kind, np.ones(1))[2]
    if bed.model == "porous":
        d_tau, d_other = _porous_pump_slopes(bed, kind, state, der)
    else:
        dh = np.asarray(der["tip_height"][name], dtype=np.float64).reshape(-1)
        dh = dh * scale * bed.length
        gap = bed.channel_height - bed.length * np.asarray(sol.tip_height).reshape(-1)
        eta = bed.viscosity
        if kind == "pressure_gradient":  # tau = G g/2, Q' = G g^3/(12 eta), dg/dG = -dh
            d_tau = gap / 2.0 - x * dh / 2.0
            d_other = gap**3 / (12.0 * eta) - x * gap**2 * dh / (4.0 * eta)
        else:  # G = 12 eta Q'/g^3, tau = G g/2 = 6 eta Q'/g^2
            d_tau = 6.0 * eta / gap**2 + 12.0 * eta * x * dh / gap**3
            d_other = 12.0 * eta / gap**3 + 36.0 * eta * x * dh / gap**4
    shape = d.shape
    errs = {
        kind: float_or_array(err.reshape(shape)),
        "other": float_or_array((np.abs(d_other) * err).reshape(shape)),
    }
    finite = bool(np.all(np.isfinite(err)))
    status = -2 if not converged else (0 if finite else 2)
    message = {
        0: "ok",
        2: "a standard error is infinite (a fold of the bed, or an undetermined fit)",
        -2: f"the inversion did not reach the deflection in {_MEASURE_STEPS} Newton steps",
    }[status]
    pressure = kind == "pressure_gradient"
    return Measurement(
        tip_deflection=float_or_array(d),
        wall_shear_stress=state.wall_shear_stress,
        wall_shear_stress_stderr=float_or_array((np.abs(d_tau) * err).reshape(shape)),
        velocity=float_or_array(np.zeros(shape)),
        velocity_stderr=float_or_array(np.zeros(shape)),
        state=state,
        success=status == 0,
        status=status,
        message=message,
        pressure_gradient=state.pressure_gradient,
        pressure_gradient_stderr=errs[kind] if pressure else errs["other"],
        flow_rate=state.flow_rate,
        flow_rate_stderr=errs["other"] if pressure else errs[kind],
    )


def measure(
    bed: HairBed | Pillar,
    tip_deflection: ArrayLike,
    *,
    sigma: ArrayLike = 0.0,
    fit: CalibrationFit | None = None,
    drive: str | None = None,
) -> Measurement:
    """Wall shear stress and wall speed from a measured tip deflection, with standard errors.

    The exact inversion of :meth:`HairBed.state_from_tip_deflection` (the deflection fixes the
    state uniquely, theory.md §5). The standard errors propagate, to first order, the
    deflection's ``sigma`` and, when ``fit`` is given, the covariance of its fitted
    parameters: var = (dy/dD sigma)^2 + g^T C g with g = dy/dP at fixed D.

    Parameters
    ----------
    bed : HairBed or Pillar
        The calibrated sensor (usually ``fit.bed``). A pillar's wall speed (``velocity``) is
        that of a Couette channel, NaN for the other profiles.
    tip_deflection : array_like
        Measured tip deflection D [m] along +x, in (-L, L).
    sigma : float or array_like
        Its standard deviation [m]: 0 or in (0, L] (L the hair length), one number or one
        per deflection.
    fit : CalibrationFit, optional
        The calibration whose parameter covariance is propagated too.
    drive : {None, "pressure_gradient", "flow_rate"}, optional
        A pump-driven bed (both walls at rest): read the pressure gradient or the flow rate
        instead, by Newton's method on the load with the exact derivatives of the loaded
        state (the low state where several coexist). By default the ``kind`` of ``fit``
        when it is one of these. The stress on the tip plane and the other drive follow
        from the state; their standard errors are those of the drive carried through their
        derivatives at fixed bed.

    Returns
    -------
    Measurement
    """
    check_type(bed, "bed", (HairBed, Pillar), _SENSORS)
    bed._require_scalar("the calibration")
    if fit is not None:
        check_type(fit, "fit", CalibrationFit, "a CalibrationFit (from calibration.fit) or None")
        if type(fit.bed) is not type(bed):
            raise TypeError(
                f"fit is the calibration of a {type(fit.bed).__name__}, but bed is a "
                f"{type(bed).__name__}"
            )
    if isinstance(bed, Pillar) and drive is not None:
        raise ValueError(
            f"drive={show(drive)} is a pump-driven HairBed's; a Pillar is read back as a "
            "wall shear stress (drive=None)"
        )
    d = bed._deflection(tip_deflection, "tip_deflection")
    s = check_sigma(sigma, "sigma", d.shape, unit="m", allow_zero=True, high=bed.length)
    if isinstance(bed, Pillar):
        return _measure_pillar(bed, d, s, fit)
    if drive is None and fit is not None and fit.kind in _PUMPS:
        drive = fit.kind
    if drive is not None:
        if drive not in _PUMPS:
            raise ValueError(
                f"drive must be None, 'pressure_gradient' or 'flow_rate', got {show(drive)}"
            )
        return _measure_pumped(bed, drive, d, s, fit)
    state = bed._state_of_deflection(d)  # d checked: no check again on the way down
    sol = state.solution
    v = np.asarray(state.velocity, dtype=np.float64).reshape(-1)
    tau = np.asarray(state.wall_shear_stress, dtype=np.float64).reshape(-1)
    names = fit.parameters if fit is not None else ()
    geometry = fit.geometry if fit is not None else "spacing"
    # the derivatives of the state the deflection fixes (any root of a bistable window), not
    # of a forward solve at its speed; the stress model's state is the same t at eps = 0
    _, jac_v, dd_dv, _ = _model_at(bed, "velocity", v, sol, names, geometry)
    collapsed = bed._collapsed_state(sol)
    _, jac_t, dd_dt, _ = _model_at(bed, "wall_shear_stress", tau, collapsed, names, geometry)
    sig = np.broadcast_to(s, d.shape).reshape(-1)
    ev, et = _stderr(sig, dd_dv, jac_v, fit), _stderr(sig, dd_dt, jac_t, fit)
    finite = bool(np.all(np.isfinite(ev)) and np.all(np.isfinite(et)))
    shape = d.shape
    return Measurement(
        tip_deflection=float_or_array(d),
        wall_shear_stress=state.wall_shear_stress,
        wall_shear_stress_stderr=float_or_array(et.reshape(shape)),
        velocity=state.velocity,
        velocity_stderr=float_or_array(ev.reshape(shape)),
        state=state,
        success=finite,
        status=0 if finite else 2,
        message="ok"
        if finite
        else "a standard error is infinite (a fold of the bed, or an undetermined fit)",
    )


def _stderr(
    sig: FloatArray, dd_dy: FloatArray, jac: FloatArray, fit: CalibrationFit | None
) -> FloatArray:
    """Standard error of a flow y read from a deflection D: var = (sigma/(dD/dy))^2 +
    g^T C g, g = dy/dP = -(dD/dP)/(dD/dy) at fixed D, C the fit's covariance."""
    with np.errstate(divide="ignore", invalid="ignore"):
        var = (sig / dd_dy) ** 2
        if fit is not None:
            g = -jac / dd_dy[:, None]
            var = var + np.einsum("ij,jk,ik->i", g, fit.covariance, g)
    return np.asarray(np.sqrt(var), dtype=np.float64)


def _measure_pillar(
    pillar: Pillar, d: FloatArray, s: FloatArray, fit: CalibrationFit | None
) -> Measurement:
    """:func:`measure` of a pillar at checked deflections ``d`` [m] and their ``s`` [m]: the
    exact inverse (:meth:`Pillar.state_from_tip_deflection`), the stress's error through
    dD/dtau = the sensitivity, and the wall speed's for a "couette" pillar (V = tau_w H/eta;
    NaN for the other profiles)."""
    tau, sol = pillar._invert(d)
    state = pillar._state(tau, np.asarray(sol.forcing, dtype=np.float64), sol)
    names = fit.parameters if fit is not None else ()
    _, jac, dd_dt = _pillar_model_at(pillar, tau.reshape(-1), sol, names)
    sig = np.broadcast_to(s, d.shape).reshape(-1)
    et = _stderr(sig, dd_dt, jac, fit).reshape(d.shape)
    if pillar.profile == "couette":
        to_v = float(pillar.channel_height) / pillar.viscosity  # type: ignore[arg-type]
    else:
        to_v = math.nan
    finite = bool(np.all(np.isfinite(et)))
    return Measurement(
        tip_deflection=float_or_array(d),
        wall_shear_stress=state.wall_shear_stress,
        wall_shear_stress_stderr=float_or_array(et),
        velocity=state.velocity,
        velocity_stderr=float_or_array(et * to_v),
        state=state,
        success=finite,
        status=0 if finite else 2,
        message="ok"
        if finite
        else "a standard error is infinite (a fold of the pillar, or an undetermined fit)",
    )


# -- linear range ------------------------------------------------------------------------------


def _linear_errors(t: FloatArray, eps: float, theta0: float) -> tuple[Any, FloatArray, FloatArray]:
    """(states, relative error of the linear velocity, ... of the linear stress) at t."""
    sol = _from_parameter(t, eps, theta0)
    c = math.cos(theta0)
    gap0 = 1.0 - eps * c
    slope = c * c / (3.0 * gap0)
    w_lin = np.asarray(sol.tip_displacement) / slope  # linear omega^2
    err_v = w_lin / np.asarray(sol.omega2) - 1.0
    err_t = w_lin / (gap0 * np.asarray(sol.omega_eps) ** 2) - 1.0
    return sol, err_v, err_t


#: The quantities whose linear calibration :func:`linear_range` bounds.
_QUANTITIES = ("wall_shear_stress", "velocity", "both")


def _worst(ev: FloatArray, et: FloatArray, quantity: str) -> FloatArray:
    if quantity == "velocity":
        return np.abs(ev)
    if quantity == "wall_shear_stress":
        return np.abs(et)
    return np.maximum(np.abs(ev), np.abs(et))


#: A porous bed's linear range is sought along its branch parametrised by u, the tip's
#: fraction of the way from rest to a flat hair, x1 = sin(theta0) + u (1 - sin(theta0)):
#: on this grid (the inverse of :func:`hairbed.inverse.porous_state_from_tip_deflection`).
_POROUS_LINEAR_GRID = np.concatenate(
    [np.geomspace(1e-6, 0.05, 40), np.linspace(0.05, 0.98, 94)[1:]]
)


def _linear_curve(bed: HairBed) -> tuple[FloatArray, Any]:
    """(grid, errors) of the bed's branch from rest (flow towards +x): ``errors(p)`` gives
    (relative error of the linear velocity, ... of the linear stress, omega^2, the stress on
    the tip plane in load units, x1) at branch parameters p. The dense bed's parameter is
    its closed form's t; the porous bed's the u of :data:`_POROUS_LINEAR_GRID`, its states
    the porous inverse's, its linear calibration the exact slopes at rest
    (:meth:`HairBed.linear_velocity_from_tip_deflection`)."""
    eps, theta0 = bed.eps, bed.base_angle
    if bed.model == "dense":

        def dense(t: FloatArray) -> tuple[FloatArray, ...]:
            sol, ev, et = _linear_errors(t, eps, theta0)
            oe2 = np.asarray(sol.omega_eps, dtype=np.float64) ** 2
            x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
            return ev, et, np.asarray(sol.omega2, dtype=np.float64), oe2, x1

        return np.arange(-30.0, 40.0 + 1e-9, 0.1), dense
    from .inverse import porous_state_from_tip_deflection

    slope, stress_slope = bed._linear_slopes()
    rest = math.sin(theta0)
    kappa, gamma = bed.kappa, bed.drag_ratio

    def porous(u: FloatArray) -> tuple[FloatArray, ...]:
        x1 = rest + np.asarray(u, dtype=np.float64) * (1.0 - rest)
        st = porous_state_from_tip_deflection(x1, eps, theta0, kappa=kappa, gamma=gamma)
        omega2 = np.asarray(st.omega2, dtype=np.float64)
        stress = np.asarray(st.tip_stress, dtype=np.float64)
        w_lin = (x1 - rest) / slope
        return w_lin / omega2 - 1.0, w_lin * stress_slope / stress - 1.0, omega2, stress, x1

    return _POROUS_LINEAR_GRID, porous


@renamed_parameters(tolerance="rtol")
def linear_range(
    bed: HairBed | Pillar, rtol: float = 0.1, *, quantity: str = "both"
) -> LinearRange:
    """The largest deflection at which the linear calibration of ``quantity`` is within ``rtol``.

    The linear calibration is that of a cantilever under a point load at the tip:
    x1 - sin(theta0) = omega^2 cos^2(theta0)/(3 (1 - eps cos theta0)) for the speed
    (:meth:`HairBed.linear_velocity_from_tip_deflection`) and the stress of the gap at rest
    (:meth:`HairBed.linear_wall_shear_stress_from_tip_deflection`). Along the physical branch
    from rest (flow towards +x) the first deflection where the relative error reaches
    ``rtol`` is found by a bracketed root search. The two calibrations fail at different
    deflections: the linear speed also misses the narrowing of the gap (the stress ratio
    1/(1 - eps h1)), so for a stress sensor ask for ``quantity="wall_shear_stress"``.

    Parameters
    ----------
    bed : HairBed or Pillar
        The sensor; a pillar's range is :meth:`Pillar.linear_range` (its linear formula
        x1 = sin theta0 + c1 Lambda, theory.md §12), the wall shear stress's.
    rtol : float
        Relative tolerance, in (0, 1) (``tolerance`` is its deprecated old name).
    quantity : {"both", "wall_shear_stress", "velocity"}
        Whose linear calibration is bounded; "both" (the default) returns the range in
        which both hold and, in ``limits``, the range of each.

    Returns
    -------
    LinearRange
    """
    check_type(bed, "bed", (HairBed, Pillar), _SENSORS)
    bed._require_scalar("the calibration")
    tol = check_number(rtol, "rtol", low=0.0, high=1.0, low_open=True, high_open=True)
    if not isinstance(quantity, str) or quantity not in _QUANTITIES:
        raise ValueError(
            f"quantity must be one of {', '.join(map(repr, _QUANTITIES))}, got {show(quantity)}"
        )
    if isinstance(bed, Pillar):
        if quantity == "velocity" and bed.profile != "couette":
            raise ValueError(
                "quantity 'velocity' needs a 'couette' pillar (its wall speed); this one's "
                f"profile is {show(bed.profile)}"
            )
        return bed.linear_range(tol)
    if quantity != "both":
        return _linear_range(bed, tol, quantity)
    each = {q: _linear_range(bed, tol, q) for q in ("velocity", "wall_shear_stress")}
    shorter = min(each.values(), key=lambda r: r.tip_deflection)
    return replace(shorter, quantity="both", limits=MappingProxyType(each))


def _linear_range(bed: HairBed, tol: float, quantity: str) -> LinearRange:
    """:func:`linear_range` of one quantity, its inputs checked."""
    grid, errors = _linear_curve(bed)
    ev, et = errors(grid)[:2]
    over = np.flatnonzero(_worst(ev, et, quantity) > tol)
    if over.size == 0:
        p_star, status = float(grid[-1]), 4
        message = "the linear calibration stays within the tolerance over the whole range"
    elif over[0] == 0:
        raise ValueError(
            f"rtol {tol!r} is below the linear calibration's error at the weakest forcing"
        )
    else:
        i = int(over[0])

        def excess(p: FloatArray) -> FloatArray:
            e_v, e_t = errors(p)[:2]
            return _worst(e_v, e_t, quantity) - tol

        p_star = float(
            np.ravel(
                find_root(
                    excess,
                    grid[i - 1],
                    grid[i],
                    xatol=1e-13,
                    what="the end of the linear range",
                ).x
            )[0]
        )
        status, message = 0, "found"
    ev1, et1, omega2, stress, x1 = (float(np.ravel(a)[0]) for a in errors(np.array([p_star])))
    velocity = omega2 * bed.velocity_scale
    return LinearRange(
        tip_deflection=bed.length * x1,
        velocity=velocity,
        wall_shear_stress=bed.viscosity * bed.velocity_scale * stress / bed.channel_height,
        rtol=tol,
        velocity_error=ev1,
        wall_shear_stress_error=et1,
        success=status == 0,
        status=status,
        message=message,
        quantity=quantity,
    )


# -- calibration points from a file ------------------------------------------------------------

#: Columns of a calibration file, with their units.
POINT_COLUMNS: dict[str, str] = {
    "tip_deflection": "m",
    "velocity": "m/s",
    "wall_shear_stress": "Pa",
    "pressure_gradient": "Pa/m",
    "flow_rate": "m^2/s",
    "sigma": "m",
}
#: The columns of the known quantity, one of which a calibration file has.
_KNOWN_COLUMNS = ("velocity", "wall_shear_stress", "pressure_gradient", "flow_rate")


def _column(heading: str, path: Any) -> str:
    """The column name of a heading "name" or "name [units]" (the units checked)."""
    text = heading.strip()
    name, unit = text, None
    if text.endswith("]") and "[" in text:
        name, _, unit = text[:-1].partition("[")
        name, unit = name.strip(), unit.strip()
    name = name.lower()
    if name not in POINT_COLUMNS:
        raise ValueError(f"{path}: unknown column {text!r}; allowed: {', '.join(POINT_COLUMNS)}")
    if unit is not None and unit != POINT_COLUMNS[name]:
        raise ValueError(f"{path}: column {name} is in [{POINT_COLUMNS[name]}] (SI), got [{unit}]")
    return name


@dataclass(frozen=True)
class CalibrationPoints:
    """Measured calibration points, as :func:`fit` takes them.

    Attributes
    ----------
    tip_deflection : ndarray (k,)
        Measured tip deflections [m].
    velocity : ndarray (k,), or None
        The known wall speeds [m/s] (or None: stresses known).
    wall_shear_stress : ndarray (k,), or None
        The known wall shear stresses [Pa] (or None: speeds known).
    sigma : ndarray (k,), or None
        The standard deviation of each deflection [m], if the file has them.
    pressure_gradient, flow_rate : ndarray (k,), or None
        The known pressure gradients [Pa/m] or flow rates per unit width [m^2/s] of a
        pump-driven bed (both walls at rest), or None.
    """

    tip_deflection: FloatArray
    velocity: FloatArray | None
    wall_shear_stress: FloatArray | None
    sigma: FloatArray | None
    pressure_gradient: FloatArray | None = None
    flow_rate: FloatArray | None = None

    def known(self) -> dict[str, FloatArray]:
        """The known quantity as the keyword :func:`fit` takes: ``{name: values}``."""
        return {k: v for k in _KNOWN_COLUMNS if (v := getattr(self, k)) is not None}


def read_points(path: str | os.PathLike[str]) -> CalibrationPoints:
    """Read calibration points from a CSV file with a header line.

    The columns (in any order, names case-insensitive) are ``tip_deflection`` [m] and exactly
    one of ``velocity`` [m/s], ``wall_shear_stress`` [Pa], ``pressure_gradient`` [Pa/m] and
    ``flow_rate`` [m^2/s] (the last two: a pump-driven bed), optionally ``sigma`` [m]; empty
    lines and lines starting with ``#`` are skipped. A name may carry its unit in the
    ``name [units]`` style of hairbed's own CSV files (``tip_deflection [m]``), which must
    then be the SI unit above. The values are checked by :func:`fit`.

    Parameters
    ----------
    path : str or path-like
        The CSV file.

    Returns
    -------
    CalibrationPoints

    Raises
    ------
    OSError
        The file cannot be read.
    ValueError
        The file is not such a table; the message starts with ``path`` and names the line
        and the column.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     f = pathlib.Path(tmp) / "points.csv"
    ...     _ = f.write_text("velocity,tip_deflection\\n0.1,2e-4\\n0.2,3.5e-4\\n")
    ...     points = read_points(f)
    >>> points.velocity, points.tip_deflection, points.wall_shear_stress
    (array([0.1, 0.2]), array([0.0002 , 0.00035]), None)
    """
    import csv

    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise ValueError(f"{path}: needs a header line and at least one row")
    header = [_column(h, path) for h in rows[0]]
    columns: dict[str, list[float]] = {h: [] for h in header}
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise ValueError(f"{path}: line {i} has {len(row)} fields, not {len(header)}")
        for h, cell in zip(header, row):
            try:
                columns[h].append(float(cell))
            except ValueError:
                raise ValueError(f"{path}: line {i}, {h}: not a number: {cell!r}") from None
    if "tip_deflection" not in columns:
        raise ValueError(f"{path}: needs a tip_deflection column [m]")
    if sum(k in columns for k in _KNOWN_COLUMNS) != 1:
        raise ValueError(
            f"{path}: needs exactly one of the columns velocity [m/s], wall_shear_stress [Pa], "
            "pressure_gradient [Pa/m] and flow_rate [m^2/s]"
        )
    arrays = {h: np.array(v, dtype=np.float64) for h, v in columns.items()}
    return CalibrationPoints(
        tip_deflection=arrays["tip_deflection"],
        velocity=arrays.get("velocity"),
        wall_shear_stress=arrays.get("wall_shear_stress"),
        sigma=arrays.get("sigma"),
        pressure_gradient=arrays.get("pressure_gradient"),
        flow_rate=arrays.get("flow_rate"),
    )
