"""The result of a linear-range search (:func:`hairbed.calibration.linear_range`), shared by
the bed and the pillar sensors (:class:`~hairbed.HairBed`, :class:`~hairbed.Pillar`)."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

__all__ = ["LinearRange"]


@dataclass(frozen=True)
class LinearRange:
    """Where the linear calibration is good enough (from :func:`hairbed.calibration.linear_range`).

    Attributes
    ----------
    tip_deflection : float
        The largest tip deflection [m] (from the base, along +x) up to which the linear
        calibration of :attr:`quantity` is within ``rtol`` (relative) of the exact one
        (for "both": of the wall speed and the wall shear stress alike).
    velocity : float
        The exact wall speed at that deflection [m/s] (a pillar: the wall speed of its
        Couette channel, NaN for the other profiles).
    wall_shear_stress : float
        The exact wall shear stress there [Pa].
    rtol : float
        The relative tolerance asked for (``tolerance`` is its deprecated old name).
    velocity_error, wall_shear_stress_error : float
        Relative errors of the linear calibrations there, linear/exact - 1 (signed).
    success : bool
        True when the tolerance is reached at a finite deflection (status 0).
    status : int
        0 found; 4 the linear calibration stays within the tolerance over the whole searched
        range (a bed: forcing up to about omega^2 = 1e7; a pillar: tip deflections up to
        0.999 of the way to the wall): the values are at its end
        (:data:`~hairbed._core.validation.STATUS_MESSAGES`).
    message : str
        What happened.
    quantity : str
        Whose linear calibration: "velocity", "wall_shear_stress" or "both".
    limits : Mapping[str, LinearRange]
        For "both", the range of each quantity alone ("velocity", "wall_shear_stress"); the
        fields above are then those of the shorter one. Empty otherwise.
    """

    tip_deflection: float
    velocity: float
    wall_shear_stress: float
    rtol: float
    velocity_error: float
    wall_shear_stress_error: float
    success: bool
    status: int
    message: str
    quantity: str = "both"
    limits: Mapping[str, LinearRange] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def tolerance(self) -> float:
        """Deprecated: the old name of :attr:`rtol`."""
        warnings.warn(
            "LinearRange.tolerance is deprecated; use LinearRange.rtol",
            FutureWarning,
            stacklevel=2,
        )
        return self.rtol
