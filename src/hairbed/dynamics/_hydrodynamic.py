"""The oscillating cylinder's hydrodynamic function (Sader 1998), for a pillar's unsteady drag.

J. E. Sader, "Frequency response of cantilever beams immersed in viscous fluids with
applications to the atomic force microscope", J. Appl. Phys. 84, 64-76 (1998), eq. (20): an
infinitely long circular cylinder of diameter b oscillating normally at angular frequency w
in a fluid of density rho and viscosity eta feels, per unit length, the force

    F = (pi/4) rho w^2 b^2 Gamma(w) W(w)     (Sader's convention e^{-i w t}),

    Gamma(w) = 1 + 4 i K1(-i sqrt(i Re)) / (sqrt(i Re) K0(-i sqrt(i Re))),
    Re = rho w b^2/(4 eta),

K0, K1 the modified Bessel functions of the second kind. Re Gamma is the added mass over
the displaced fluid's (-> 1 as Re -> inf: the potential-flow added mass rho pi a^2), Im Gamma
the dissipation. It is two-dimensional: each section is taken as part of an infinitely long
cylinder, which holds where the viscous (Stokes) layer sqrt(2 eta/(rho w)) is thin against
the pillar length L. At small Re that layer grows without bound and Gamma's dissipation
grows like 1/(Re ln(1/Re)) (the Stokes paradox): the outer cut-off of the 2-D flow is the
layer, not the pillar, and the three-dimensional slender body's resistive-force coefficient
zeta_perp = 4 pi eta/(ln(2L/a) + 1/2) (cut off by L, theory.md §12) takes over.

The crossover used here: the layer equal to the pillar length, sqrt(2 eta/(rho w)) = L, i.e.
Re_c = 2 (a/L)^2 (b = 2a); below it the quasi-steady resistive force (and no added mass), at
and above it Sader's function. :func:`sader_drag_ratio` gives the resulting normal drag as a
complex multiple of the quasi-steady zeta_perp in the pillar's units (theory.md §14).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.special
from numpy.typing import ArrayLike

from .._core.outputs import scalar_or_array
from .._core.validation import _check_range, as_float_array, check_number

__all__ = ["crossover_reynolds", "hydrodynamic_function", "sader_drag_ratio"]


#: Above this Reynolds number Gamma's Bessel ratio is Hankel's large-argument expansion.
_ASYMPTOTIC_REYNOLDS = 1e16


def hydrodynamic_function(reynolds: ArrayLike) -> Any:
    """Sader's Gamma_circ(Re) of a circular cylinder, Re = rho w b^2/(4 eta) > 0 [-]
    (J. Appl. Phys. 84, 64 (1998), eq. (20); the convention e^{-i w t}: Im Gamma > 0)."""
    re = as_float_array(reynolds, "reynolds")
    _check_range(re, ~(re > 0.0) | ~np.isfinite(re), "reynolds", "(0, inf)")
    root = np.sqrt(1j * re)
    arg = -1j * root
    with np.errstate(all="ignore"):
        # exponentially scaled Bessel functions: their ratio is the same, and no overflow
        ratio = scipy.special.kve(1, arg) / scipy.special.kve(0, arg)
        # above Re = 1e16 (abs(z) = 1e8; AMOS gives up near abs(z) ~ 1e9) Hankel's
        # expansion K1/K0 = 1 + 1/(2 z) - 1/(8 z^2) + O(z^-3), exact there to rounding
        far = 1.0 + 0.5 / arg - 0.125 / (arg * arg)
        ratio = np.where(re > _ASYMPTOTIC_REYNOLDS, far, ratio)
        gamma = 1.0 + 4.0j * ratio / root
    _check_range(
        re, ~np.isfinite(gamma), "reynolds", "(0, inf) with Gamma(Re) finite (Re above ~1e-300)"
    )
    return scalar_or_array(gamma)


def crossover_reynolds(slenderness: float) -> float:
    """Re_c = 2 (a/L)^2: the Reynolds number at which the Stokes layer sqrt(2 eta/(rho w))
    equals the pillar length L (slenderness L/a > 1.5)."""
    sl = check_number(slenderness, "slenderness", low=1.5, low_open=True)
    return 2.0 / (sl * sl)


def sader_drag_ratio(omega: ArrayLike, reynolds_scale: float, slenderness: float) -> Any:
    """The normal hydrodynamic load of an oscillating pillar over the quasi-steady drag
    zeta_perp i omega W (the convention e^{i omega t} of theory.md §14), complex.

    Parameters
    ----------
    omega : array_like
        Angular frequencies [1/T] >= 0, T = zeta_perp L^4/(E I).
    reynolds_scale : float
        rho b^2/(4 eta T) > 0: Re = reynolds_scale omega.
    slenderness : float
        L/a > 1.5 (the crossover Re_c = 2 (a/L)^2, and zeta_perp's logarithm).

    Returns
    -------
    complex or ndarray
        D(omega): 1 below the crossover (resistive force, no added mass), else
        i (ln(2L/a) + 1/2) Re conj(Gamma(Re))/4, whose real part is the drag and whose
        imaginary part, divided by omega, the added mass in units of zeta_perp T.
    """
    om = as_float_array(omega, "omega")
    _check_range(om, ~(om >= 0.0) | ~np.isfinite(om), "omega", "[0, inf)")
    k = check_number(reynolds_scale, "reynolds_scale", low=0.0, low_open=True)
    sl = check_number(slenderness, "slenderness", low=1.5, low_open=True)
    with np.errstate(over="ignore"):
        re = k * om
        top = np.finfo(np.float64).max / k  # inf for a subnormal reynolds_scale
    _check_range(
        om, ~np.isfinite(re), "omega", f"[0, {top:.4g}] (Re = "
        f"reynolds_scale omega overflows)"
    )  # fmt: skip
    out = np.ones(om.shape, dtype=np.complex128)
    use = re >= crossover_reynolds(sl)
    if np.any(use):
        try:
            gam = np.asarray(hydrodynamic_function(re[use]), dtype=np.complex128)
        except ValueError as exc:
            raise ValueError(
                f"omega and reynolds_scale: Re = reynolds_scale omega is out of the range of "
                f"Sader's Gamma: {exc}"
            ) from None
        log = np.log(2.0 * sl) + 0.5
        with np.errstate(over="ignore", invalid="ignore"):
            out[use] = 1j * log * re[use] * np.conj(gam) / 4.0
        _check_range(
            om, ~np.isfinite(out), "omega", "a range where the drag ratio is finite "
            "(reynolds_scale omega, slenderness not near the largest double)"
        )  # fmt: skip
    return scalar_or_array(out)
