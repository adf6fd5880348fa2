"""Figures of the porous bed (theory.md §13): the collective stiffening of a hair bed."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.pillar import gray_hancock_ratio
from .._core.validation import check_int
from ..units import HairBed
from ._style import MAX_POINTS, figure_axes

__all__ = ["fig_collective_stiffening"]


def fig_collective_stiffening(
    length: float = 1e-3,
    radius: float = 50e-6,
    youngs_modulus: float = 1e6,
    height_ratio: float = 20.0,
    phi_range: tuple[float, float] = (1e-5, 0.5),
    num: int = 40,
    ax: Any = None,
) -> Figure:
    """Deflection per unit stress against packing fraction at fixed hairs: the collective
    stiffening of a bed ("Collective stiffening of soft hair assemblies", Phys. Rev. E 2020,
    arXiv:2002.02834), by the porous model of theory.md §13.

    At each packing fraction phi the bed ``HairBed(..., model="porous")`` of hairs of length
    ``length`` [m], radius ``radius`` [m] and modulus ``youngs_modulus`` [Pa] under a
    channel ``height_ratio`` hair lengths tall is driven by its top wall at a speed small
    enough for the linear response; the tip's displacement over the stress on the tip plane
    [m/Pa] is drawn for the three drag models. Beside them: the isolated pillar in the
    undisturbed shear flow of the same stress (the sparse limit: 11/120 of the drag's
    Lambda per unit stress), and the paper's dense bed, whose tip carries the stress times
    the wall area per hair, A L^3/(3 E I) per unit stress (the dense limit).

    Examples
    --------
    >>> fig = fig_collective_stiffening(num=6)
    >>> fig.axes[0].get_xlabel()
    'packing fraction $\\\\phi$ [-]'
    """
    num = check_int(num, "num", 4, MAX_POINTS)
    lo, hi = phi_range
    if not 0.0 < lo < hi <= 0.6:
        raise ValueError(f"phi_range must satisfy 0 < low < high <= 0.6, got {phi_range!r}")
    phi = np.geomspace(lo, hi, num)
    fig, ax = figure_axes(ax, size=(7.0, 4.2))
    ei = youngs_modulus * math.pi * radius**4 / 4.0
    styles = {"crossover": "-", "sparse": "--", "array": ":"}
    area = math.pi * radius**2 / phi
    for drag, style in styles.items():
        per = np.empty(num)
        for i, p in enumerate(phi):
            bed = HairBed(
                length=length,
                radius=radius,
                youngs_modulus=youngs_modulus,
                channel_height=height_ratio * length,
                viscosity=1.0,
                packing_fraction=float(p),
                model="porous",
                drag=drag,
            )
            st = bed.deform(1e-6 * bed.velocity_scale)
            per[i] = st.tip_displacement / st.wall_shear_stress
        ax.loglog(phi, per, style, color="C0", label=f"porous bed, drag {drag!r}")
    # the isolated pillar in the undisturbed flow u = tau z/eta: Lambda per unit stress
    lg = math.log(2.0 * length / radius)
    zeta = 4.0 * math.pi / (lg + 0.5)  # Gray & Hancock, eta = 1
    pillar = 11.0 / 120.0 * zeta * length**5 / ei
    ax.axhline(pillar, color="C1", lw=1.2, label="isolated pillar (sparse limit)")
    ax.loglog(phi, area * length**3 / (3.0 * ei), color="C2", lw=1.2,
              label="dense bed, tip load (the paper)")  # fmt: skip
    ax.set_xlabel(r"packing fraction $\phi$ [-]")
    ax.set_ylabel(r"tip displacement / stress [m/Pa]")
    ax.set_title(
        rf"$L = {length * 1e3:g}$ mm, $L/a = {length / radius:g}$, "
        rf"$\gamma_{{GH}} = {float(gray_hancock_ratio(length / radius)):.3f}$"
    )
    ax.legend(fontsize=7.5, loc="lower left")
    return fig
