"""The bed as a valve: flow against pressure drop, hydraulic resistance, diodicity.

A channel of length l [m] and height H, a dense bed on its floor, both walls at rest, a
pressure drop dp = p(0) - p(l) [Pa] across it: the pressure gradient is G = dp/l and the
flow per unit width through the gap g = H - h1 L above the tips is (theory.md §11)::

    Q'  = G g^3 / (12 eta)                 flow rate per unit width [m^2/s]
    R   = dp / Q'                          hydraulic resistance per unit width [Pa s/m^2]
    R0  = 12 eta l / H^3                   the empty channel's, so  R / R0 = (H / g)^3

The hairs bend under G (the tip plane's shear and the load inside the bed), so the gap and
hence the resistance depend on the flow: a bed of hairs tilted at theta0 != 0 is a diode.
Forward flow (along the tilt) bends the hairs down and opens the gap; backward flow lifts
them and closes it. The diodicity is Di = Q'(+dp) / abs(Q'(-dp)) at the same abs(dp).

Examples
--------
>>> from hairbed import HairBed
>>> bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
...               viscosity=1.0, spacing=400e-6, base_angle=0.5)
>>> d = diodicity(bed, 200.0, 0.01)   # 200 Pa over 1 cm
>>> round(d.diodicity, 4)
1.434
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._core.outputs import float_or_array
from ._core.validation import (
    STATUS_MESSAGES,
    _first_index,
    as_float_array,
    check_positive,
    check_root,
)
from .units import HairBed, HairState

__all__ = ["Diodicity", "ValveCurve", "diodicity", "valve_curve"]

FloatOrArray = float | NDArray[np.float64]


@dataclass(frozen=True)
class ValveCurve:
    """Flow through a hair-bed valve against the pressure drop (from :func:`valve_curve`).

    Attributes
    ----------
    pressure_drop : float or ndarray
        dp = p(0) - p(l) [Pa] (positive drives the flow towards +x).
    channel_length : float
        l [m].
    flow_rate : float or ndarray
        Q' [m^2/s] per unit width, signed like dp.
    empty_flow_rate : float or ndarray
        dp H^3 / (12 eta l) [m^2/s]: the channel without hairs at the same drop.
    resistance_ratio : float or ndarray
        R / R0 = (H / g)^3 [-], the resistance relative to the empty channel.
    tip_deflection, tip_height : float or ndarray
        The hair's tip [m] (along +x, above the wall).
    states : HairState
        The states themselves (:meth:`hairbed.HairBed.deform` with ``pressure_gradient``).
    status : int or ndarray
        The solver's status per point (0 converged; ``STATUS_MESSAGES``).
    success : bool
        True where every point converged.
    message : str
        What happened (the first failing point's message).
    """

    pressure_drop: FloatOrArray
    channel_length: float
    flow_rate: FloatOrArray
    empty_flow_rate: FloatOrArray
    resistance_ratio: FloatOrArray
    tip_deflection: FloatOrArray
    tip_height: FloatOrArray
    states: HairState
    status: Any
    success: bool
    message: str


@dataclass(frozen=True)
class Diodicity:
    """Forward against backward flow at the same pressure drop (from :func:`diodicity`).

    Attributes
    ----------
    pressure_drop : float or ndarray
        abs(dp) [Pa].
    forward, backward : ValveCurve
        The valve at +abs(dp) and at -abs(dp).
    diodicity : float or ndarray
        Di = Q'(+abs(dp)) / abs(Q'(-abs(dp))) [-]: above 1 when the hairs lean towards +x.
    success : bool
        True where both directions converged.
    """

    pressure_drop: FloatOrArray
    forward: ValveCurve
    backward: ValveCurve
    diodicity: FloatOrArray
    success: bool


def valve_curve(
    bed: HairBed, pressure_drop: Any, channel_length: float, *, root: str = "low"
) -> ValveCurve:
    """Flow per unit width through a channel of length l lined by ``bed`` at drops dp.

    Parameters
    ----------
    bed : HairBed
        The bed (its channel height H and the fluid's viscosity included).
    pressure_drop : array_like
        dp = p(0) - p(l) [Pa], finite; negative drives the flow towards -x.
    channel_length : float
        l [m], positive: the pressure gradient is G = dp / l.
    root : {"low", "mid", "high"}
        Which state where several coexist (passed to :meth:`hairbed.HairBed.deform`).

    Returns
    -------
    ValveCurve
    """
    if not isinstance(bed, HairBed):
        raise TypeError(f"bed must be a hairbed.HairBed, got {type(bed).__name__}")
    dp = as_float_array(pressure_drop, "pressure_drop", unit="Pa")
    length = check_positive(channel_length, "channel_length", unit="m")
    root = check_root(root)
    with np.errstate(over="ignore"):
        gradient = dp / length
        empty = dp * (bed.channel_height**3 / (12.0 * bed.viscosity * length))
    bad = ~np.isfinite(gradient) | ~np.isfinite(empty)
    if np.any(bad):
        raise ValueError(
            f"pressure_drop / channel_length [Pa/m] overflows: pressure_drop "
            f"{float(dp[bad].flat[0])!r} Pa over channel_length {length!r} m"
            f"{_first_index(bad)}"
        )
    states = bed.deform(pressure_gradient=gradient, root=root)
    flow = np.asarray(states.flow_rate, dtype=np.float64)
    gap = bed.channel_height - np.asarray(states.tip_height, dtype=np.float64)
    ratio = (bed.channel_height / gap) ** 3
    status = np.asarray(states.solution.status)
    failed = np.flatnonzero(status.reshape(-1) != 0)
    message = "ok" if failed.size == 0 else STATUS_MESSAGES[int(status.reshape(-1)[failed[0]])]
    return ValveCurve(
        pressure_drop=float_or_array(dp),
        channel_length=length,
        flow_rate=float_or_array(flow),
        empty_flow_rate=float_or_array(empty),
        resistance_ratio=float_or_array(ratio),
        tip_deflection=states.tip_deflection,
        tip_height=states.tip_height,
        states=states,
        status=states.solution.status,
        success=bool(failed.size == 0),
        message=message,
    )


def diodicity(
    bed: HairBed, pressure_drop: Any, channel_length: float, *, root: str = "low"
) -> Diodicity:
    """The diodicity Di = Q'(+abs(dp)) / abs(Q'(-abs(dp))) of a channel lined by ``bed``.

    Parameters are those of :func:`valve_curve`; ``pressure_drop`` is taken in magnitude
    (it must not be 0, where the ratio is 0/0).
    """
    dp = np.abs(as_float_array(pressure_drop, "pressure_drop", unit="Pa"))
    if np.any(dp == 0.0):
        raise ValueError("pressure_drop must be non-zero for a diodicity (0/0 at no flow)")
    forward = valve_curve(bed, dp, channel_length, root=root)
    backward = valve_curve(bed, -dp, channel_length, root=root)
    ahead = np.asarray(forward.flow_rate, dtype=np.float64)
    behind = np.abs(np.asarray(backward.flow_rate, dtype=np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        # both flows underflow to 0 only at drops of ~1e-300 Pa, where Di -> 1 (at rest the
        # gap is the same both ways)
        di = np.where((ahead == 0.0) & (behind == 0.0), 1.0, ahead / behind)
    return Diodicity(
        pressure_drop=float_or_array(dp),
        forward=forward,
        backward=backward,
        diodicity=float_or_array(di),
        success=forward.success and backward.success,
    )
