"""Pump-driven channels in SI: a set pressure gradient or a set flow rate (theory.md §11).

A pump drives the channel at a set pressure gradient G = -dp/dx [Pa/m] or a set flow rate per
unit width Q' [m^2/s], the top wall at rest or moving at v [m/s]. The gap g = H - h1 L above
the tips carries a Couette-Poiseuille flow, and the fluid inside the dense bed, at rest, passes
G on to the hairs::

    u(y)  = v y/g + G y (g - y)/(2 eta)            gap flow, y above the tip plane [m/s]
    tau   = eta v/g + G g/2                        shear stress on the tip plane [Pa]
    Q'    = v g/2 + G g^3/(12 eta)                 flow rate per unit width [m^2/s]
    pi    = A G L^3/(E I),   q = 6 A eta Q' L^2/(E I H^2),   omega^2 = A eta v L^2/(E I H)

with A = pi a^2/phi the wall area per hair. Signs are kept (a negative G, Q' or v drives
towards -x): the solver of the distributed load takes signed loads, so no mirror image is
needed here. This module converts between the two and evaluates the gap flow of a state; it
imports nothing of :mod:`hairbed.units`, which uses it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.validation import _first_index, as_float_array, broadcast_named

__all__ = ["drive_inputs", "gap_flow", "load_scale", "porous_flow", "pump_drive"]

FloatArray = NDArray[np.float64]


def _finite_scaled(value: FloatArray, scale: float, name: str, unit: str) -> FloatArray:
    """value * scale, refusing values whose dimensionless load overflows."""
    with np.errstate(over="ignore"):
        out = value * scale
    bad = ~np.isfinite(out)
    if np.any(bad):  # an array-valued bed's scale: at the first offending element
        limit = np.finfo(np.float64).max / float(np.broadcast_to(scale, bad.shape)[bad].flat[0])
        raise ValueError(
            f"{name} must be within +-{limit:.3g} {unit} for this bed (its dimensionless load "
            f"overflows), got {float(value[bad].flat[0])!r}{_first_index(bad)}"
        )
    return out


def pump_drive(pressure_gradient: Any, flow_rate: Any) -> tuple[str, str, Any]:
    """(name, unit, value) of the one pump drive given; ValueError when both are."""
    if pressure_gradient is not None and flow_rate is not None:
        raise ValueError(
            "give at most one of pressure_gradient [Pa/m] and flow_rate [m^2/s]: a pump sets "
            "one of them, and the other follows from the state"
        )
    if pressure_gradient is not None:
        return "pressure_gradient", "Pa/m", pressure_gradient
    return "flow_rate", "m^2/s", flow_rate


def load_scale(bed: Any, drive: str) -> float:
    """pi/G [m/Pa] of the "pressure" drive, q/Q' [s/m^2] of the "flow" drive; an array of
    the bed's shape for an array-valued bed (each element the scalar bed's number)."""
    if getattr(bed, "shape", ()):
        return bed._per_element(lambda one: load_scale(one, drive))
    if drive == "pressure":
        return float(bed.wall_area_per_hair * bed.length**3 / bed.bending_stiffness)
    return float(
        6.0
        * bed.wall_area_per_hair
        * bed.viscosity
        * bed.length**2
        / (bed.bending_stiffness * bed.channel_height**2)
    )


def drive_inputs(
    bed: Any, velocity: Any, pressure_gradient: Any, flow_rate: Any
) -> tuple[str, FloatArray, FloatArray, FloatArray, FloatArray]:
    """(drive, v, drive value, omega^2 signed, pi or q) of checked SI inputs, broadcast.

    ``drive`` is "pressure" (``pressure_gradient`` given) or "flow" (``flow_rate`` given);
    ``velocity`` None means a wall at rest. Raises ValueError naming the parameter.
    """
    name, unit, given = pump_drive(pressure_gradient, flow_rate)
    v = np.zeros(()) if velocity is None else as_float_array(velocity, "velocity", unit="m/s")
    drive = "pressure" if name == "pressure_gradient" else "flow"
    scale = load_scale(bed, drive)
    value = as_float_array(given, name, unit=unit)
    if getattr(bed, "shape", ()):  # each input against the bed first: the error names it
        for a, n in ((value, name), (v, "velocity")):
            bed._broadcast_input(a, n)
    v, value = broadcast_named(("velocity", v), (name, value))
    if getattr(bed, "shape", ()):  # an array-valued bed: the drive broadcast with it
        v, value = (bed._broadcast_input(a, n) for a, n in ((v, "velocity"), (value, name)))
    omega2 = _finite_scaled(v, 1.0 / bed.velocity_scale, "velocity", "m/s")
    load = _finite_scaled(value, scale, name, unit)
    return drive, np.asarray(v, dtype=np.float64), value, omega2, load


def gap_flow(
    bed: Any, drive: str, v: FloatArray, value: FloatArray, h1: FloatArray
) -> dict[str, FloatArray]:
    """The gap flow of states of tip height ``h1`` [L]: G, Q', tau, stress ratio, Re.

    ``value`` is the drive's set G [Pa/m] or Q' [m^2/s]. The stress ratio compares tau with
    the stress the same drive (same v and G, or same v and Q') puts on the bottom wall of the
    bare channel of height H; the Reynolds number is rho u_max g/eta with u_max the largest
    speed of the gap's profile (|v| for a Couette flow, as :meth:`HairBed.deform` has it).
    """
    eta, height = bed.viscosity, bed.channel_height
    gap = height - h1 * bed.length
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if drive == "pressure":
            g_grad = value
            flow = v * gap / 2.0 + g_grad * gap**3 / (12.0 * eta)
            bare = eta * v / height + g_grad * height / 2.0
        else:
            flow = value
            g_grad = 12.0 * eta * (flow - v * gap / 2.0) / gap**3
            g_bare = 12.0 * eta * (flow - v * height / 2.0) / height**3
            bare = eta * v / height + g_bare * height / 2.0
        tau = eta * v / gap + g_grad * gap / 2.0
        ratio = tau / bare
        # a pump with the wall at rest: tau and the bare stress are both proportional to the
        # drive, so their ratio is its limit at any drive, also at zero (not 0/0): g/H for a
        # set G, (H/g)^2 for a set Q' (the walls at rest and no drive: the hair at rest)
        still = v == 0.0
        if np.any(still):
            limit = gap / height if drive == "pressure" else (height / gap) ** 2
            ratio = np.where(still, limit, ratio)
        # the profile's largest speed: the wall, or the parabola's vertex inside the gap
        vertex = gap / 2.0 + np.where(g_grad != 0.0, eta * v / (g_grad * gap), np.inf)
        inside = (vertex > 0.0) & (vertex < gap)
        y = np.where(inside, vertex, 0.0)
        u_vertex = v * y / gap + g_grad * y * (gap - y) / (2.0 * eta)
        u_max = np.maximum(np.abs(v), np.where(inside, np.abs(u_vertex), 0.0))
    if bed.density is None:
        reynolds = np.full(np.shape(gap), np.nan)
    else:
        reynolds = bed.density * u_max * gap / eta
    force = bed.wall_area_per_hair * (tau + g_grad * h1 * bed.length)
    return {
        "pressure_gradient": np.asarray(g_grad, dtype=np.float64),
        "flow_rate": np.asarray(flow, dtype=np.float64),
        "wall_shear_stress": np.asarray(tau, dtype=np.float64),
        "force_per_hair": np.asarray(force, dtype=np.float64),
        "stress_ratio": np.asarray(ratio, dtype=np.float64),
        "reynolds_number": np.asarray(reynolds, dtype=np.float64),
    }


#: Gauss-Legendre nodes and weights on [0, 1] of the flux through a porous bed.
_GAUSS_X, _GAUSS_V = np.polynomial.legendre.leggauss(64)
_GAUSS_S, _GAUSS_W = 0.5 * (_GAUSS_X + 1.0), 0.5 * _GAUSS_V


def porous_flow(
    bed: Any, state: Any, v: FloatArray, drive: str, value: FloatArray
) -> dict[str, FloatArray]:
    """The flow of porous-bed states (a :class:`hairbed.PorousState` of ``bed``) in SI: G,
    Q' (through bed and gap), the stress on the tip plane, the force per hair, the stress
    ratio and the gap's Reynolds number (theory.md §13).

    The state's fluid is in load units: w = eta A L u/(E I), Q = A L^2 q/(E I); its Pi is
    A G L^3/(E I) and its flux Phi = eta A Q'/(E I). The stress ratio compares the tip
    plane's stress with the stress the same drive puts on the bottom wall of the bare channel,
    as :func:`gap_flow` does.
    """
    ei, area, length = bed.bending_stiffness, bed.wall_area_per_hair, bed.length
    eta, height = bed.viscosity, bed.channel_height
    stress = ei / (area * length**2)
    h1 = np.asarray(state.tip_height, dtype=np.float64)
    tau = np.asarray(state.tip_stress, dtype=np.float64) * stress
    g_grad = np.asarray(state.pi, dtype=np.float64) * ei / (area * length**3)
    u_tip = np.asarray(state.tip_velocity, dtype=np.float64) * ei / (eta * area * length)
    gap = height - h1 * length
    # the flux through the bed, int_0^1 w cos(theta) ds, by Gauss-Legendre on the interpolants
    _, _, _, theta = state.shape(_GAUSS_S)
    _, _, w, _ = state.fluid(_GAUSS_S)
    inside = np.sum(np.asarray(w) * np.cos(np.asarray(theta)) * _GAUSS_W, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        bed_flux = inside * ei / (eta * area)
        flow = bed_flux + u_tip * gap + tau * gap**2 / (2.0 * eta) - g_grad * gap**3 / (6.0 * eta)
        if drive == "pressure":
            bare = eta * v / height + g_grad * height / 2.0
        else:
            g_bare = 12.0 * eta * (value - v * height / 2.0) / height**3
            bare = eta * v / height + g_bare * height / 2.0
        ratio = tau / bare
        # the gap's largest speed: its ends, or the parabola's vertex inside it
        vertex = np.where(g_grad != 0.0, tau / g_grad, -1.0)
        in_gap = (vertex > 0.0) & (vertex < gap)
        y = np.where(in_gap, vertex, 0.0)
        u_vertex = u_tip + tau * y / eta - g_grad * y * y / (2.0 * eta)
        u_max = np.maximum(
            np.maximum(np.abs(v), np.abs(u_tip)), np.where(in_gap, np.abs(u_vertex), 0.0)
        )
    if bed.density is None:
        reynolds = np.full(np.shape(gap), np.nan)
    else:
        reynolds = bed.density * u_max * gap / eta
    force = np.asarray(state.drag_x, dtype=np.float64) * ei / length**2
    return {
        "pressure_gradient": np.asarray(g_grad, dtype=np.float64),
        "flow_rate": np.asarray(flow, dtype=np.float64),
        "wall_shear_stress": np.asarray(tau, dtype=np.float64),
        "force_per_hair": np.asarray(force, dtype=np.float64),
        "stress_ratio": np.asarray(ratio, dtype=np.float64),
        "reynolds_number": np.asarray(reynolds, dtype=np.float64),
    }
