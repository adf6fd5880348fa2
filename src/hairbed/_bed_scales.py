"""A HairBed as the porous bed in time: its dimensionless model and SI scales (theory.md §15).

The one conversion of a :class:`hairbed.HairBed` (either ``model``: the dense bed runs the
porous model of its geometry) to :func:`hairbed.dynamics.simulate_bed`'s numbers, shared by
:mod:`hairbed.valve_dynamics` and :mod:`hairbed.bed_simulation` (``HairBed.simulate``):

    T     = zeta_perp L^4/(E I)                   the elastoviscous time [s]
    alpha = rho_f L^2/(eta T)                     the Womersley number (0 without density)
    mu    = (rho_s + rho_f) pi a^2/(zeta_perp T)  the hairs' inertia number (0 without rho_s)
    chi   = rho_s/(rho_s + rho_f)                 tangential over normal mass [-]
    Pi = A L^3/(E I) G,  q = 6 A eta L^2/(E I H^2) Q',  omega2 = A eta L^2/(E I H) v,
    Q (load units of §13) = A L^2/(E I) tau,      A = pi a^2/phi.

It imports nothing of :mod:`hairbed.units` (which calls it): the bed is checked by its
interface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ._channel_drives import load_scale
from ._core.validation import check_positive, show

__all__: list[str] = []


@dataclass(frozen=True)
class _BedScales:
    """A bed's dimensionless model and the SI scales of its drives and outputs."""

    theta0: float
    kappa: float
    eps: float
    gamma: float
    time: float  # T [s]
    inertia: float  # mu [-]
    tangential_mass: float  # chi [-]
    womersley: float  # alpha [-]
    pi_per_gradient: float  # Pi per G [1/(Pa/m)]
    q_per_flow: float  # q per Q' [1/(m^2/s)]
    omega2_per_velocity: float  # omega2 per v [1/(m/s)]
    load_per_stress: float  # Q per tau [1/Pa]


def _is_bed(bed: Any) -> bool:
    return type(bed).__name__ == "HairBed" and hasattr(bed, "drag_coefficients")


def _as_porous(bed: Any) -> Any:
    """The same bed under the porous model (the bed in time is §15's porous model); a
    porous bed is itself."""
    if bed.model == "porous":
        return bed
    return type(bed)(
        length=bed.length,
        radius=bed.radius,
        youngs_modulus=bed.youngs_modulus,
        channel_height=bed.channel_height,
        viscosity=bed.viscosity,
        spacing=bed.spacing,
        base_angle=bed.base_angle,
        density=bed.density,
        model="porous",
        drag=bed.drag,
    )


def _scales(bed: Any, hair_density: Any) -> _BedScales:
    """The bed's porous model in time and its SI scales (``hair_density`` [kg/m^3] or
    None: overdamped hairs)."""
    if not _is_bed(bed):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    # an array bed's elements come here one by one (simulate, rheometer.bed_moduli)
    bed._require_scalar("the bed in time (valve_dynamics, the rheometer's bed_laos)")
    porous = _as_porous(bed)
    zeta = porous.drag_coefficients[0]
    t_scale = zeta * bed.length**4 / bed.bending_stiffness
    if not (math.isfinite(t_scale) and t_scale > 0.0):
        raise ValueError(f"the bed's time scale zeta_perp L^4/(E I) = {t_scale!r} s under- or "
                         "overflows")  # fmt: skip
    rho_f = bed.density
    alpha = 0.0 if rho_f is None else float(rho_f) * bed.length**2 / (bed.viscosity * t_scale)
    mu, chi = 0.0, 1.0
    if hair_density is not None:
        rho_s = check_positive(hair_density, "hair_density", "kg/m^3")
        added = 0.0 if rho_f is None else float(rho_f)
        mu = (rho_s + added) * math.pi * bed.radius**2 / (zeta * t_scale)
        chi = rho_s / (rho_s + added)
        if not (math.isfinite(mu) and chi > 0.0):
            raise ValueError(f"hair_density = {show(hair_density)} kg/m^3 gives an inertia "
                             "number that over- or underflows")  # fmt: skip
    area = float(porous.wall_area_per_hair)
    return _BedScales(
        theta0=float(bed.base_angle),
        kappa=float(porous.kappa),
        eps=float(bed.eps),
        gamma=float(porous.drag_ratio),
        time=t_scale,
        inertia=mu,
        tangential_mass=chi,
        womersley=alpha,
        pi_per_gradient=float(load_scale(porous, "pressure")),
        q_per_flow=float(load_scale(porous, "flow")),
        omega2_per_velocity=1.0 / float(porous.velocity_scale),
        load_per_stress=area * bed.length**2 / bed.bending_stiffness,
    )
