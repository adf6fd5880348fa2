"""The porous bed in a rheometer (issue 31 §2): its storage and loss moduli against frequency
at several pre-stresses, with the crossover from stress lag to stress lead marked. Every
number drawn is :func:`hairbed.rheometer.oscillatory_shear`'s."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from .._core.validation import check_int
from ..rheometer import oscillatory_shear
from ._style import MAX_POINTS, figure_axes

__all__ = ["fig_bed_moduli"]


def fig_bed_moduli(
    kappa: float = 1.0,
    eps: float = 0.5,
    inertia: float = 1.0,
    womersley: float = 0.0,
    forcings: tuple[float, ...] = (0.0, 2.0),
    frequency_range: tuple[float, float] = (0.1, 100.0),
    num: int = 40,
    ax: Any = None,
) -> Figure:
    """G'(omega) and G''(omega) of the porous bed (the top wall's stress per strain, in
    E I/(A L^2); omega in 1/T) about each steady wall forcing of ``forcings`` (the
    pre-stresses), abs(G') dashed where G' < 0 (the stress leads the wall's speed), and the
    phase of the stress against the wall's speed [deg]; the lead crossover (G' = 0) is marked
    by a dot on the phase's zero line. Two panels, or ``ax`` a sequence of two Axes.

    Examples
    --------
    >>> fig = fig_bed_moduli(num=8, forcings=(0.0,))
    >>> fig.axes[1].get_xlabel()
    'angular frequency $\\\\omega T$ [-]'
    """
    num = check_int(num, "num", 4, MAX_POINTS)
    lo, hi = frequency_range
    if not 0.0 < lo < hi < math.inf:
        raise ValueError(f"frequency_range must satisfy 0 < low < high, got {frequency_range!r}")
    fig, (axm, axp) = figure_axes(ax, 2, 1, size=(6.4, 6.0), sharex=True)
    om = np.geomspace(lo, hi, num)
    res = oscillatory_shear(
        om, np.asarray(forcings, dtype=np.float64), eps=eps, kappa=kappa, inertia=inertia,
        womersley=womersley,
    )  # fmt: skip
    for j in range(res.forcing.size):
        color = f"C{j}"
        g1, g2 = res.storage[:, j], res.loss[:, j]
        tag = f"{j}"
        label = rf"$\sigma^*$ = {res.pre_stress[j]:.3g}"
        axm.loglog(om, g2, color=color, label=f"G'' ({label})", gid=f"loss_{tag}")
        axm.loglog(om, np.where(g1 > 0, g1, np.nan), color=color, ls="-.", lw=1.2,
                   gid=f"storage_{tag}")  # fmt: skip
        axm.loglog(om, np.where(g1 < 0, -g1, np.nan), color=color, ls=":", lw=1.2,
                   gid=f"storage_negative_{tag}")  # fmt: skip
        axp.semilogx(om, np.degrees(res.lead[:, j]), color=color, gid=f"lead_{tag}")
        wc = float(res.lead_crossover[j])
        if math.isfinite(wc):
            axp.plot([wc], [0.0], "o", color=color, ms=5, gid=f"crossover_{tag}")
    axp.axhline(0.0, color="0.5", lw=0.8)
    axm.set_ylabel(r"$G''$ (solid), $G'$ (dash-dot; $-G'$ dotted) [$EI/(AL^2)$]")
    axp.set_ylabel("stress phase against wall speed [deg]")
    axp.set_xlabel(r"angular frequency $\omega T$ [-]")
    axm.set_title(
        rf"bed $\kappa$ = {kappa:g}, $\epsilon$ = {eps:g}, $\mu$ = {inertia:g}, "
        rf"$\alpha$ = {womersley:g}: below 0 the stress lags, above it leads",
        fontsize=9,
    )
    axm.legend(loc="upper left", fontsize=8)
    return fig
