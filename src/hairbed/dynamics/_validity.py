"""Where the pillar dynamics' assumptions fail (theory.md §14): a ModelValidityWarning.

The dimensionless dynamics knows the fluid and the pillar's thickness only through the
Reynolds scale R = rho_f b^2/(4 eta T) (Re = R omega, b = 2a) and the slenderness L/a, the
pair that ``LinearPillar.frequency_response(..., unsteady_drag=(R, L/a))`` takes. With
them, at angular frequencies omega [1/T]:

- **D4, the quasi-steady drag**: the Stokes layer delta = sqrt(2 eta/(rho_f omega)) must be
  longer than the pillar, Re < 2 (a/L)^2 (``crossover_reynolds``); delta/a = sqrt(2/Re).
- **Sader's function** is the drag of an infinitely long cylinder in two-dimensional flow:
  the bending wavelength 2 pi/|k| must be long against the diameter b, at least
  :data:`SADER_WAVELENGTH_LIMIT` diameters.
- **D1, rotary inertia neglected** (and with it the Timoshenko shear): the rotary over the
  translational inertia of a bending wave of wavenumber |k| [1/L] is (r_g |k|)^2, r_g = a/2 the
  radius of gyration of the section; at most :data:`ROTARY_INERTIA_LIMIT`.

The wavenumber is the straight cantilever's, |k|^4 = |mu omega^2 - i omega D(omega)|
(D = 1 quasi-steady, ``sader_drag_ratio`` with the oscillating cylinder's drag).
"""

from __future__ import annotations

import warnings

import numpy as np
from numpy.typing import ArrayLike

from .._core.validation import _check_range, as_float_array, check_number, show
from .._warnings import ModelValidityWarning
from ._hydrodynamic import crossover_reynolds, sader_drag_ratio

__all__ = [
    "ROTARY_INERTIA_LIMIT",
    "SADER_WAVELENGTH_LIMIT",
    "dynamics_validity",
    "warn_dynamics_validity",
]

#: The largest rotary over translational inertia, (a |k|/2)^2, of the rod model (D1).
ROTARY_INERTIA_LIMIT = 0.01
#: The shortest bending wavelength, in diameters, for Sader's two-dimensional drag.
SADER_WAVELENGTH_LIMIT = 10.0


def dynamics_validity(
    omega: ArrayLike,
    mu: float,
    reynolds_scale: float,
    slenderness: float,
    *,
    unsteady_drag: bool = False,
) -> tuple[str, ...]:
    """The assumptions of the pillar dynamics that fail at the frequencies ``omega``.

    Parameters
    ----------
    omega : array_like
        Angular frequencies [1/T] >= 0, T = zeta_perp L^4/(E I).
    mu : float
        The inertia number m/(zeta_perp T) >= 0 [-].
    reynolds_scale : float
        R = rho_f b^2/(4 eta T) > 0 [T]: the frequency Reynolds number is Re = R omega.
    slenderness : float
        L/a > 1.5 [-].
    unsteady_drag : bool, optional
        True where the oscillating cylinder's drag (``sader_drag_ratio``) is used, False
        (default) for the quasi-steady resistive force.

    Returns
    -------
    tuple of str
        One message per failed assumption (empty where all hold): the quasi-steady drag with
        a Stokes layer shorter than the pillar (Re > 2 (a/L)^2), Sader's drag with a bending
        wavelength ``2 pi/|k|`` below ``SADER_WAVELENGTH_LIMIT`` diameters, rotary inertia
        ``(a |k|/(2 L))^2`` above ``ROTARY_INERTIA_LIMIT``; each names the highest offending
        frequency.

    Examples
    --------
    >>> from hairbed.dynamics import dynamics_validity
    >>> dynamics_validity([0.1, 1.0], mu=13.0, reynolds_scale=2.0, slenderness=20.0)[0][:40]
    'omega up to 1 [1/T]: the Stokes layer sq'
    """
    om = as_float_array(omega, "omega").reshape(-1)
    _check_range(om, ~(om >= 0.0) | ~np.isfinite(om), "omega", "[0, inf)")
    m = check_number(mu, "mu", low=0.0)
    r = check_number(reynolds_scale, "reynolds_scale", low=0.0, low_open=True)
    sl = check_number(slenderness, "slenderness", low=1.5, low_open=True)
    if not isinstance(unsteady_drag, (bool, np.bool_)):
        raise TypeError(f"unsteady_drag must be True or False, got {show(unsteady_drag)}")
    if om.size == 0:
        return ()
    out: list[str] = []
    with np.errstate(over="ignore", invalid="ignore"):  # a huge omega: |k| = inf, flagged
        re = r * om
    drag = (
        np.asarray(sader_drag_ratio(om, r, sl), dtype=np.complex128).reshape(-1)
        if unsteady_drag
        else np.ones(om.size, dtype=np.complex128)
    )
    with np.errstate(over="ignore", invalid="ignore"):
        wave = np.sqrt(np.sqrt(np.abs(m * om * om - 1j * om * drag)))  # |k| [1/L]
    wave = np.where(np.isnan(wave), np.inf, wave)
    if not unsteady_drag:
        bad = re > crossover_reynolds(sl)
        if np.any(bad):
            top = float(np.max(om[bad]))
            ratio = float(np.sqrt(2.0 / (r * top)))  # delta/a at the highest
            out.append(
                f"omega up to {top:.4g} [1/T]: the Stokes layer sqrt(2 eta/(rho_f omega)) is "
                f"shorter than the pillar there (Re = {r * top:.3g} > 2 (a/L)^2 = "
                f"{crossover_reynolds(sl):.3g}; the layer is {ratio:.3g} radii): the "
                "quasi-steady resistive-force drag (theory.md §14, D4) does not hold; "
                "frequency_response(..., unsteady_drag=(reynolds_scale, slenderness)) uses "
                "the oscillating cylinder's"
            )
    else:
        diameters = 2.0 * np.pi / np.maximum(wave, 1e-300) * sl / 2.0
        bad = diameters < SADER_WAVELENGTH_LIMIT
        if np.any(bad):
            top = float(np.max(om[bad]))
            out.append(
                f"omega up to {top:.4g} [1/T]: the bending wavelength 2 pi/|k| is "
                f"{float(np.min(diameters)):.3g} diameters, below {SADER_WAVELENGTH_LIMIT:g}: "
                "Sader's drag of a cylinder in two-dimensional flow does not hold"
            )
    rotary = (wave / (2.0 * sl)) ** 2
    bad = rotary > ROTARY_INERTIA_LIMIT
    if np.any(bad):
        top = float(np.max(om[bad]))
        out.append(
            f"omega up to {top:.4g} [1/T]: the rotary inertia is {float(np.max(rotary)):.3g} "
            f"of the translational (a |k|/(2 L))^2 > {ROTARY_INERTIA_LIMIT:g}: the "
            "Euler-Bernoulli rod without rotary inertia and shear (theory.md §14, D1) does "
            "not hold"
        )
    return tuple(out)


def warn_dynamics_validity(
    omega: ArrayLike,
    mu: float,
    reynolds_scale: float,
    slenderness: float,
    *,
    unsteady_drag: bool = False,
    stacklevel: int = 2,
) -> None:
    """Issue one :class:`hairbed.ModelValidityWarning` per message of
    :func:`dynamics_validity` (same parameters; ``stacklevel`` as in
    :func:`warnings.warn`)."""
    if isinstance(stacklevel, (bool, np.bool_, np.timedelta64)) or not isinstance(
        stacklevel, (int, np.integer)
    ):
        raise TypeError(f"stacklevel must be an integer, got {show(stacklevel)}")
    if not 1 <= stacklevel <= 10_000:
        raise ValueError(f"stacklevel must lie in [1, 10000], got {show(stacklevel)}")
    for message in dynamics_validity(
        omega,
        mu=mu,
        reynolds_scale=reynolds_scale,
        slenderness=slenderness,
        unsteady_drag=unsteady_drag,
    ):
        warnings.warn(message, ModelValidityWarning, stacklevel=stacklevel + 1)
