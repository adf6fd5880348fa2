"""Physical units: a bed of hairs in a channel, in SI, and the state a flow puts it in.

The dimensionless problem of the paper [1]_ has three inputs: the forcing omega^2, the
confinement eps = L/H and the base angle theta0. A real bed of cylindrical hairs of length L and
radius a, Young's modulus E, hexagonally packed at spacing delta (packing fraction phi) at the
bottom of a channel of height H filled with a fluid of viscosity eta, driven so that the top wall
moves at speed v, has (theory.md §7)::

    I       = pi a^4 / 4                                  second moment of area [m^4]
    phi     = (2 pi / sqrt 3) a^2 / delta^2               packing fraction [-]
    omega^2 = pi a^2 L^2 eta |v| / (E I H phi)            forcing [-]
    eps     = L / H                                       confinement [-]

and the dimensionless solution gives back, in SI::

    tip deflection  x1 L [m],   tip height  h1 L [m],
    wall shear stress   tau = eta v / (H - h1 L) [Pa],
    force on one hair   F = tau pi a^2 / phi [N]   (pi a^2 / phi = (sqrt 3 / 2) delta^2 is the
                                                    wall area per hair).

Direction of the flow
---------------------
x points along the flow for v > 0 and theta0 (``base_angle``) is measured from the wall normal
towards +x, so a positive base angle leans the hairs *with* the flow for v > 0 (flow with the
grain). A negative velocity is flow against the grain. The problem is then the mirror image
x -> -x of the problem with base angle -theta0 and speed abs(v): :meth:`HairBed.deform` solves that
one and mirrors x, the tip angle, the wall shear stress and the force back, so that every signed
quantity of :class:`HairState` refers to the bed's own +x axis.

References
----------
.. [1] J. P. Smucker, Z. M. Vural, J. R. Alvarado and P. J. Morrison, "Fluid Flow Induced
   Deformation of a Boundary Hair".
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import NDArray

from ._bed_drag import (
    DRAG_MODELS,
    MAX_PACKING_FRACTION,
    drag_coefficients,
    drag_logarithm_slopes,
)
from ._channel_drives import drive_inputs, gap_flow, load_scale, porous_flow
from ._core.loaded import _DRIVES, LADDER, _solve_loaded_checked, _solve_loaded_trusted
from ._core.outputs import float_or_array
from ._core.porous import _solve_porous_checked
from ._core.solver import _from_parameter, _solve_checked
from ._core.validation import (
    HALF_PI,
    _first_index,
    as_float_array,
    check_choice,
    check_number,
    check_positive,
    check_real_array,
    check_root,
    show,
)
from ._warnings import ModelValidityWarning, UnitsWarning

if TYPE_CHECKING:  # pragma: no cover
    from .bed_simulation import BedSimulation
    from .profile_fit import ProfileFit

__all__ = [
    "CLOSE_PACKING_FRACTION",
    "POROUS_SUPPORTED",
    "DENSE_BED_LIMIT",
    "PLAUSIBLE_RANGES",
    "BedProfileFit",
    "HairBed",
    "HairState",
    "transverse_permeability",
]

#: Packing fraction of touching hairs in a hexagonal array, pi / (2 sqrt 3) ~ 0.9069 [-].
CLOSE_PACKING_FRACTION = math.pi / (2.0 * math.sqrt(3.0))

#: The dense-bed condition (theory.md §10): the model stops the flow at the hair tips, valid
#: while the Brinkman length sqrt(k) over which the flow penetrates the bed is small against the
#: hair length; above sqrt(k)/L = 0.1 a :class:`hairbed.ModelValidityWarning` is issued.
DENSE_BED_LIMIT = 0.1
#: The bed models of :class:`HairBed`: the paper's dense bed, or the porous (Brinkman) bed.
MODELS = ("dense", "porous")

FloatOrArray = float | NDArray[np.float64]

#: The SI parameters of a :class:`HairBed`, with the units a pint quantity is converted to:
#: each may be an array (issue 32), and they broadcast together.
_BED_UNITS = (
    ("length", "m"),
    ("radius", "m"),
    ("youngs_modulus", "Pa"),
    ("channel_height", "m"),
    ("viscosity", "Pa*s"),
    ("spacing", "m"),
    ("packing_fraction", ""),
    ("base_angle", "rad"),
    ("density", "kg/m**3"),
)
_BED_NAMES = tuple(n for n, _ in _BED_UNITS)
#: The derived quantities of an array-valued bed, computed element by element by the scalar
#: bed's own properties (so that each element's numbers are bitwise those of the scalar bed).
_BED_DERIVED = (
    "eps",
    "second_moment",
    "bending_stiffness",
    "wall_area_per_hair",
    "velocity_scale",
    "permeability",
    "brinkman_length",
)
_BED_DRAG = ("drag_coefficients", "kappa", "drag_ratio")


def transverse_permeability(radius: float, packing_fraction: float) -> float:
    """Darcy permeability k [m^2] of a hexagonal array of cylinders for flow across their axes.

    Drummond & Tahir (1984), Int. J. Multiphase Flow 10, 515, for the hexagonal array (whose
    first terms are the dilute expansion of Sangani & Acrivos (1982), Int. J. Multiphase
    Flow 8, 193)::

        k / a^2 = (-ln phi - 1.497 + 2 phi - phi^2/2 - 0.739 phi^4
                   + 2.534 phi^5 / (1 + 1.2758 phi)) / (8 phi)

    The flow past wall-normal hairs parallel to the wall is this transverse flow.

    Parameters
    ----------
    radius : float
        Cylinder radius a [m], > 0.
    packing_fraction : float
        Area fraction phi of the cylinders [-], in (0, pi/(2 sqrt 3)) (hexagonal close
        packing).
    """
    a = _positive(radius, "radius", "m")
    phi = check_number(
        packing_fraction,
        "packing_fraction",
        low=0.0,
        high=CLOSE_PACKING_FRACTION,
        low_open=True,
        high_open=True,
    )
    k = _transverse_permeability(a, phi)
    if not 0.0 < k < math.inf:
        raise ValueError(
            f"radius {a!r} m and packing_fraction {phi!r} give a permeability that under- or "
            "overflows double precision"
        )
    return k


def _transverse_permeability(radius: float, phi: float) -> float:
    """:func:`transverse_permeability` of checked inputs."""
    series = (
        -math.log(phi) - 1.497 + 2.0 * phi - 0.5 * phi**2 - 0.739 * phi**4
        + 2.534 * phi**5 / (1.0 + 1.2758 * phi)
    )  # fmt: skip
    return radius * (radius * series / (8.0 * phi))  # never radius**2: it raises on overflow


def _warn_sparse(bed: HairBed, stacklevel: int = 4) -> None:
    """A :class:`ModelValidityWarning` where the flow penetrates the bed over more than
    :data:`DENSE_BED_LIMIT` of the hair length (the dense-bed condition, theory.md §10); for
    an array-valued bed, at its first such element."""
    ratio = np.asarray(bed.brinkman_length / bed.length, dtype=np.float64)
    sparse = ratio > DENSE_BED_LIMIT
    if np.any(sparse) and getattr(bed, "model", "dense") == "dense":
        where = _first_index(sparse)
        brinkman = _at(bed.brinkman_length, sparse)
        phi = _at(bed.packing_fraction, sparse)
        warnings.warn(
            f"the bed is not dense: the flow penetrates it over the Brinkman length sqrt(k) = "
            f"{brinkman:.3g} m, {_at(ratio, sparse):.3g} of the hair length (limit "
            f"{DENSE_BED_LIMIT:g}; packing fraction {phi:.3g}){where}, but the model "
            "loads the hairs at their tips only (to first order it overestimates the "
            "deflection by 1.5 sqrt(k)/L); HairBed(..., model='porous') solves the flow "
            "through the bed (theory.md §13)",
            ModelValidityWarning,
            stacklevel=stacklevel,
        )


def _at(value: Any, mask: NDArray[np.bool_]) -> float:
    """``value`` (a number, or an array that broadcasts to ``mask``) at the first True of
    ``mask``, as a float: what a message about an array-valued model shows."""
    arr = np.broadcast_to(np.asarray(value, dtype=np.float64), np.shape(mask))
    return float(arr[mask].flat[0]) if np.any(mask) else float(arr.flat[0])


def _sin(x: Any) -> Any:
    """sin of a base angle: math's for a number (as the scalar model always had), numpy's for
    an array (the same values on IEEE doubles, tested)."""
    return math.sin(x) if isinstance(x, float) else np.sin(x)


def _cos(x: Any) -> Any:
    """cos of a base angle, as :func:`_sin`."""
    return math.cos(x) if isinstance(x, float) else np.cos(x)


def _frozen(arr: Any) -> NDArray[np.float64]:
    """A read-only float64 copy (a model's array parameter: the model is frozen); -0.0 is
    stored as 0.0, so that equal models hash alike."""
    out = np.array(arr, dtype=np.float64) + 0.0
    out.setflags(write=False)
    return out


def _range_of(low: float, high: float | None, low_open: bool, high_open: bool) -> str:
    lo = "(" if low_open else "["
    hi = "inf)" if high is None else (f"{high:.6g})" if high_open else f"{high:.6g}]")
    return f"{lo}{low:g}, {hi}"


def _array_parameter(
    value: Any,
    name: str,
    unit: str,
    *,
    low: float = 0.0,
    high: float | None = None,
    low_open: bool = True,
    high_open: bool = True,
    shown: str | None = None,
) -> NDArray[np.float64]:
    """An array-valued model parameter (a pint quantity converted to ``unit``), every element
    finite and in the range, as a read-only float64 array; else a ValueError naming it, its
    range and the first offending index."""
    arr = check_real_array(value, name, unit)
    rng = (shown or _range_of(low, high, low_open, high_open)) + (f" [{unit}]" if unit else "")
    if arr.size == 0:
        raise ValueError(f"{name} must be a number or a non-empty array in {rng}, got an "
                         f"empty array of shape {arr.shape}")  # fmt: skip
    with np.errstate(over="ignore"):
        a = arr.astype(np.float64)
    inside = np.isfinite(a) & ((a > low) if low_open else (a >= low))
    if high is not None:
        inside &= (a < high) if high_open else (a <= high)
    bad = ~inside
    if np.any(bad):
        raise ValueError(
            f"{name} must lie in {rng} (every element), got {float(a[bad].flat[0])!r}"
            f"{_first_index(bad)}"
        )
    return _frozen(a)


def _is_array(value: Any, name: str, unit: str) -> bool:
    """Whether a model parameter is given as an array (a list, an ndarray, a pint quantity of
    one): the model then broadcasts it (issue 32). A value that is no real number is refused
    here, with the same message the scalar check gives."""
    return value is not None and check_real_array(value, name, unit).ndim > 0


def _shape_of(model: Any, names: tuple[str, ...], kind: str) -> tuple[int, ...]:
    """The broadcast shape of a model's array parameters, or a ValueError naming them."""
    shapes = [(n, np.shape(getattr(model, n))) for n in names if getattr(model, n) is not None]
    try:
        return tuple(np.broadcast_shapes(*(s for _, s in shapes)))
    except ValueError:
        given = ", ".join(f"{n} {s}" for n, s in shapes if s != ())
        raise ValueError(
            f"the array parameters of {kind} must broadcast together (numpy rules), got "
            f"shapes {given}"
        ) from None


def _array_names(model: Any, names: tuple[str, ...]) -> list[str]:
    """The parameters of ``model`` given as arrays."""
    return [n for n in names if np.ndim(getattr(model, n)) > 0]


def _phi_of_spacing(radius: float, spacing: float) -> float:
    """phi = (2 pi/sqrt 3) a^2/delta^2 (the scalar bed's expression)."""
    return 2.0 * math.pi / math.sqrt(3.0) * (radius / spacing) ** 2


def _spacing_of_phi(radius: float, phi: float) -> float:
    """delta = a sqrt(2 pi/(sqrt 3 phi)) (the scalar bed's expression)."""
    return radius * math.sqrt(2.0 * math.pi / (math.sqrt(3.0) * phi))


def _elementwise(func: Any, *args: Any) -> Any:
    """``func`` of numbers, element by element over broadcast arguments (a number of
    numbers): a model's parameter conversion, bitwise the scalar model's."""
    if all(np.ndim(a) == 0 for a in args):
        return func(*(float(a) for a in args))
    cols = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in args))
    out = np.array([func(*map(float, t)) for t in zip(*(c.reshape(-1) for c in cols))])
    return _frozen(out.reshape(cols[0].shape))


def _flat_index(index: Any, shape: tuple[int, ...], kind: str) -> int:
    """The flat (C order) position of ``index`` (an int for a 1-d shape, or a tuple of one
    int per axis; negative counts from the end) in ``shape``, or a ValueError."""
    idx = index if isinstance(index, tuple) else (index,)
    whole = all(
        isinstance(i, (int, np.integer))
        and not isinstance(i, (bool, np.bool_, np.timedelta64, np.datetime64))
        for i in idx
    )
    if not whole or len(idx) != len(shape):
        raise ValueError(
            f"index must be {len(shape)} integer(s) into the {kind}'s shape {shape} (an int "
            f"or a tuple), got {show(index)}"
        )
    flat = 0
    for i, n in zip(idx, shape):
        j = int(i) + n if int(i) < 0 else int(i)
        if not 0 <= j < n:
            raise ValueError(f"index {show(index)} is out of range for the {kind}'s shape {shape}")
        flat = flat * n + j
    return flat


def _hashable(value: Any) -> Any:
    """A field value as a hashable, comparable key: an array by its shape and bytes."""
    if isinstance(value, np.ndarray):
        return ("ndarray", value.shape, value.tobytes())
    return value


class _ArrayModel:
    """Equality, hashing and unpickling of a frozen model whose parameters may be arrays
    (HairBed, Pillar; their dataclasses leave eq to this class: eq=False)."""

    def _key(self) -> tuple[Any, ...]:
        fields = dataclasses.fields(cast(Any, self))
        return tuple(_hashable(getattr(self, f.name)) for f in fields if f.compare)

    def __eq__(self, other: object) -> bool:
        """Equal models have equal parameters (arrays: the same shape and elements)."""
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def _bare_elements(
        self, cls: type, names: Any, shape: tuple[int, ...], shared: dict[str, Any]
    ) -> Any:
        """Each element (C order) as a ``cls`` built without its checks: the parameters
        ``names`` as numbers (None where unset), the ``shared`` fields as they are."""
        cols = {
            n: np.broadcast_to(np.asarray(v, dtype=np.float64), shape).reshape(-1)
            for n in names
            if (v := getattr(self, n)) is not None
        }
        for i in range(math.prod(shape)):
            el: Any = object.__new__(cls)
            for n in names:
                object.__setattr__(el, n, float(cols[n][i]) if n in cols else None)
            for n, v in shared.items():
                object.__setattr__(el, n, v)
            yield el

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Unpickled: the array parameters and cached arrays read-only again."""

        def frozen(value: Any) -> Any:
            if isinstance(value, np.ndarray):
                return _frozen(value)
            if isinstance(value, tuple):
                return tuple(frozen(v) for v in value)
            if isinstance(value, dict):
                return {k: frozen(v) for k, v in value.items()}
            return value

        self.__dict__.update({k: frozen(v) for k, v in state.items()})


#: What a porous bed (``HairBed(..., model="porous")``) supports so far; every other method
#: and workflow says so rather than compute the dense bed's answer.
POROUS_SUPPORTED = (
    "deform, sweep, wall_shear_stress, rectification_ratio, state_from_tip_deflection, "
    "velocity_from_tip_deflection, wall_shear_stress_from_tip_deflection, "
    "velocity_from_wall_shear_stress, the linear calibrations, valve.valve_curve, "
    "valve.diodicity, valve.valve_states, fit_profile and the calibration (fit, measure, "
    "model_tip_deflection, linear_range)"
)


def require_dense(bed: Any, what: str) -> None:
    """NotImplementedError where ``what`` is asked of a porous bed, which it does not yet
    support: never the dense bed's numbers under a porous bed's name."""
    if getattr(bed, "model", "dense") != "dense":
        raise NotImplementedError(
            f"{what} supports the dense bed (model='dense') only, so far; a porous bed "
            f"supports {POROUS_SUPPORTED}"
        )


def _reynolds_of_stress(
    bed: HairBed, wall_shear_stress: NDArray[np.float64], gap: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Reynolds number rho |v| gap / eta of the gap flow at a wall shear stress [Pa].

    v = tau gap / eta, so Re = rho |tau| gap^2 / eta^2; NaN without a ``density``.
    """
    if bed.density is None:
        return np.full(np.shape(gap), np.nan)
    return bed.density * np.abs(wall_shear_stress) * gap**2 / bed.viscosity**2


def _warn_reynolds(reynolds: NDArray[np.float64]) -> None:
    """A :class:`ModelValidityWarning` where the gap's Reynolds number exceeds 1."""
    high = reynolds > 1.0
    if np.any(high):
        worst = float(np.max(reynolds[high]))
        where = "" if reynolds.ndim == 0 else f" at {int(np.count_nonzero(high))} point(s)"
        warnings.warn(
            f"Reynolds number of the gap flow {worst:.3g} > 1{where}: the model assumes Stokes "
            "(viscous) flow; inertia of the fluid is not negligible here and the results are "
            "outside the model's validity",
            ModelValidityWarning,
            stacklevel=4,
        )


#: Plausible ranges of a bed's SI inputs (low, high, unit, the likely slip below, above):
#: outside them :class:`HairBed` issues a :class:`hairbed.UnitsWarning` (and still builds the
#: bed). Hairs and pillars from tens of nanometres to a metre, under channels up to 10 m;
#: moduli from soft gels (~1 kPa) to diamond (~1.2e12 Pa); viscosities from gases
#: (~1e-5 Pa s) to pastes; densities from gases to osmium (2.26e4 kg/m^3).
PLAUSIBLE_RANGES: dict[str, tuple[float, float, str, str, str]] = {
    "length": (1e-8, 1.0, "m", "metres converted twice?", "micrometres given as metres?"),
    "radius": (1e-9, 0.1, "m", "metres converted twice?", "micrometres given as metres?"),
    "channel_height": (
        1e-8,
        10.0,
        "m",
        "metres converted twice?",
        "micrometres (or millimetres) given as metres?",
    ),
    "spacing": (1e-9, 1.0, "m", "metres converted twice?", "micrometres given as metres?"),
    "youngs_modulus": (
        1e3,
        1e13,
        "Pa",
        "a modulus in kPa, MPa or GPa given as Pa? (1 MPa = 1e6 Pa)",
        "stiffer than diamond (~1.2e12 Pa): a modulus in Pa multiplied twice?",
    ),
    "viscosity": (
        1e-6,
        1e5,
        "Pa s",
        "a kinematic viscosity [m^2/s] given for the dynamic one [Pa s]?",
        "a viscosity in mPa s (cP) given as Pa s? (1 cP = 1e-3 Pa s)",
    ),
    "density": (
        1e-2,
        3e4,
        "kg/m^3",
        "below any gas at ordinary pressure (air: 1.2 kg/m^3; water: 1000 kg/m^3)?",
        "denser than osmium (2.26e4 kg/m^3): a density in g/m^3 given as kg/m^3?",
    ),
}


def _positive(value: Any, name: str, unit: str) -> float:
    """A finite real number > 0 in SI ``unit`` (a pint quantity is converted), or a
    ValueError that names it."""
    return check_positive(value, name, unit)


def _warn_implausible(bed: Any, kind: str = "HairBed") -> None:
    """A :class:`UnitsWarning` for each SI input of a valid bed (or pillar: ``kind`` names
    its class) outside :data:`PLAUSIBLE_RANGES` (after every check has passed: an invalid bed
    gets only its error); for an array-valued input, at its first such element."""
    for name, (low, high, shown, below, above) in PLAUSIBLE_RANGES.items():
        x = getattr(bed, name, None)
        if x is None:
            continue
        a = np.asarray(x, dtype=np.float64)
        out = ~((low <= a) & (a <= high))
        if np.any(out):
            xv = _at(a, out)
            warnings.warn(
                f"{name} = {xv:g} {shown}{_first_index(out)} is outside the plausible range "
                f"[{low:g}, {high:g}] {shown}: {below if xv < low else above} ({kind} takes "
                "SI units or pint quantities)",
                UnitsWarning,
                stacklevel=4,
            )


@dataclass(frozen=True)
class BedProfileFit:
    """A flow fitted to a measured hair profile, in SI units (from :meth:`HairBed.fit_profile`).

    Attributes
    ----------
    velocity : float
        The fitted wall speed, omega^2 times :attr:`HairBed.velocity_scale` [m/s].
    velocity_stderr : float
        Its standard uncertainty [m/s].
    fit : ProfileFit
        The dimensionless fit (omega^2, theta0, their standard errors, the residual).
    success : bool
        Whether the optimiser reports convergence.
    status : int
        The fit's status (0 converged; see :class:`~hairbed.profile_fit.ProfileFit`).
    message : str
        The optimiser's message.
    """

    velocity: float
    velocity_stderr: float
    fit: ProfileFit = field(repr=False)
    success: bool
    status: int
    message: str


@dataclass(frozen=True)
class HairState:
    """A hair bed deformed by a flow, in SI units (returned by :meth:`HairBed.deform`).

    With a pump drive (``pressure_gradient`` or ``flow_rate`` given to :meth:`HairBed.deform`)
    ``solution`` is a :class:`hairbed.LoadedState` in the bed's own frame (``direction`` is
    +1), the stress is the one on the tip plane, eta v/g + G g/2, and the force per hair holds
    the bed's share of the pressure gradient too, (tau + G h1 L) pi a^2/phi.

    Attributes
    ----------
    bed : HairBed
        The bed.
    velocity : float or ndarray
        Speed of the top wall v [m/s]; negative means flow towards -x.
    omega2 : float or ndarray
        Forcing omega^2 [-] (of abs(v)).
    solution : Solution
        The dimensionless state, for base angle ``direction * bed.base_angle`` (the mirror image
        for v < 0, see the module docstring): its x and angles are in the mirrored frame.
    direction : float or ndarray
        +1 where v >= 0, -1 where v < 0 [-]: the factor that maps the solution's x to the bed's.
    tip_deflection : float or ndarray
        Horizontal position of the tip relative to the base, x1 L [m] (along +x).
    tip_height : float or ndarray
        Height of the tip above the wall, h1 L [m].
    tip_angle : float or ndarray
        Angle of the tip from the wall normal towards +x [rad].
    wall_shear_stress : float or ndarray
        The shear stress tau on the tip plane [Pa] (signed: positive towards +x). Wall drive:
        eta v / g, g = H - h1 L the gap (the same as on the top wall). Pump drive (a set
        pressure gradient G or flow rate Q', theory.md §11): eta v / g + G g / 2, the gap's
        Couette-Poiseuille stress at the tips. Porous bed: the stress of its Brinkman flow
        at the tips (theory.md §13).
    force_per_hair : float or ndarray
        Horizontal force of the flow on one hair [N] (signed like the flow): tau pi a^2 / phi
        for the wall drive; with a pump, that plus G h1 L pi a^2 / phi, the gradient's push
        on the fluid within the bed.
    stress_ratio : float or ndarray
        tau over the stress the same drive puts on the bottom wall of the bare channel of
        height H [-]: 1 / (1 - eps h1) for the wall drive (over eta v / H); with a pump,
        over eta v / H + G H / 2 (a set G) or the same with the bare channel's G of the set
        Q'. With both walls at rest it is the limit at any drive, also at zero: g / H (set
        G) or (H / g)^2 (set Q'); never 0/0.
    tip_displacement : float or ndarray
        Horizontal displacement of the tip from its position at rest, (x1 - sin theta0) L [m]
        (along +x), accurate relative to itself at weak forcing.
    reynolds_number : float or ndarray
        Reynolds number of the gap flow above the bed, rho u_max (H - h1 L) / eta [-], u_max
        the largest speed of the gap's profile (abs(v) when the wall drives it); NaN when the
        bed has no ``density``. The model assumes Stokes flow: above 1 a
        :class:`hairbed.ModelValidityWarning` is issued.
    pressure_gradient : float or ndarray
        Pressure gradient G = -dp/dx along the channel [Pa/m]: 0 when the wall drives the
        flow, set by a pump or following from a set flow rate (theory.md §11).
    flow_rate : float or ndarray
        Flow rate per unit width through the gap, Q' = v g/2 + G g^3/(12 eta) [m^2/s].

    """

    bed: HairBed = field(repr=False)
    velocity: FloatOrArray
    omega2: FloatOrArray
    solution: Any = field(repr=False)
    direction: FloatOrArray
    tip_deflection: FloatOrArray
    tip_height: FloatOrArray
    tip_angle: FloatOrArray
    wall_shear_stress: FloatOrArray
    force_per_hair: FloatOrArray
    stress_ratio: FloatOrArray
    tip_displacement: FloatOrArray
    reynolds_number: FloatOrArray
    pressure_gradient: FloatOrArray
    flow_rate: FloatOrArray

    def profile(self, num: int = 200) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The shape of the hair in metres, from base (0, 0) to tip.

        Parameters
        ----------
        num : int
            Number of points along the hair, equally spaced in arc length.

        Returns
        -------
        x, z : ndarray
            Horizontal position along +x [m] and height above the wall [m], of shape
            ``velocity.shape + (num,)``.
        """
        if hasattr(self.solution, "profile"):
            x, z = self.solution.profile(num)
        else:  # a LoadedState (a pump drive): its spectral interpolant
            _, x, z, _ = self.solution.shape(np.linspace(0.0, 1.0, num))
        scale: Any = self.bed.length
        if isinstance(scale, np.ndarray):  # an array bed: its shape broadcasts the states'
            scale = scale[..., np.newaxis]
        direction = np.asarray(self.direction, dtype=np.float64)[..., np.newaxis]
        return direction * scale * np.asarray(x), scale * np.asarray(z)


@dataclass(frozen=True, eq=False)
class HairBed(_ArrayModel):
    """A dense bed of elastic hairs at the bottom of a channel flow, in SI units.

    Every SI parameter may be an array (issue 32): the parameters broadcast together into
    :attr:`shape` and with the arrays of a call (numpy rules), each element checked on its
    own; :meth:`deform` (every model and drive), :meth:`state_from_tip_deflection` and the
    calibrations (exact and linear), :func:`hairbed.valve.valve_curve` and
    :func:`hairbed.valve.diodicity` then solve every element in one compiled call, each the
    scalar bed's result, and :meth:`item` gives the scalar bed of one element. Methods that
    need a bed of numbers say so. The derived quantities (:attr:`eps`,
    :attr:`velocity_scale`, ...) are then arrays of :attr:`shape`.

    Parameters
    ----------
    length : float or array_like
        Hair length L [m].
    radius : float or array_like
        Hair radius a [m] (the radius, not the diameter).
    youngs_modulus : float or array_like
        Young's modulus E of the hair material [Pa].
    channel_height : float or array_like
        Height H of the channel [m]; must exceed ``length``.
    viscosity : float or array_like
        Dynamic viscosity eta of the fluid [Pa s].
    spacing : float or array_like, optional
        Distance delta between neighbouring hairs of the hexagonal array [m].
    packing_fraction : float or array_like, optional
        Fraction phi of the wall covered by hair bases [-]. Give exactly one of ``spacing`` and
        ``packing_fraction``; they are related by phi = (2 pi / sqrt 3) a^2 / delta^2.
    base_angle : float or array_like, optional
        Angle theta0 of the hairs at the wall, from the wall normal towards +x [rad], in
        (-pi/2, pi/2). Positive leans the hairs along the flow of a positive velocity; negative
        leans them into it (where a tight channel can hold three states, theory.md §5).
    density : float or array_like, optional
        Density rho of the fluid [kg/m^3]. Only used to check the model's Stokes-flow
        assumption: states then carry the gap's Reynolds number, and a
        :class:`hairbed.ModelValidityWarning` is issued where it exceeds 1.

    Raises
    ------
    ValueError
        If a size is not a positive finite number, if neither or both of ``spacing`` and
        ``packing_fraction`` are given, if the hairs overlap (radius >= spacing / 2, i.e. a
        packing fraction at or beyond hexagonal close packing, pi / (2 sqrt 3) ~ 0.907), if
        ``length >= channel_height`` or if ``base_angle`` is outside (-pi/2, pi/2).

    Examples
    --------
    Soft 1 mm hairs of radius 50 um at 400 um spacing under a 2 mm layer of glycerol:

    >>> bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
    ...               viscosity=1.0, spacing=400e-6)
    >>> round(bed.eps, 12), round(bed.packing_fraction, 4)
    (0.5, 0.0567)
    >>> state = bed.deform(0.1)  # top wall at 10 cm/s
    >>> round(state.omega2, 4)
    1.4114
    >>> round(state.tip_deflection * 1e6, 1), round(state.wall_shear_stress, 2)  # um, Pa
    (539.8, 83.57)
    >>> round(bed.velocity_from_tip_deflection(state.tip_deflection), 12)  # calibration curve
    0.1
    >>> round(bed.linear_velocity_from_tip_deflection(state.tip_deflection), 4)  # linear: -43%
    0.0574
    """

    length: float
    radius: float
    youngs_modulus: float
    channel_height: float
    viscosity: float
    spacing: float | None = None
    #: not in the repr: the repr gives ``spacing``, and a bed is built from one of the two
    packing_fraction: float | None = field(default=None, repr=False)
    base_angle: float = 0.0
    density: float | None = None
    model: str = "dense"
    drag: str = "crossover"

    def __post_init__(self) -> None:
        """Validate the inputs and fill in the one of spacing / packing fraction not given."""
        given = "spacing" if self.spacing is not None else "packing_fraction"
        object.__setattr__(self, "_given", given)
        if any(_is_array(getattr(self, n), n, u) for n, u in _BED_UNITS):
            self._post_init_arrays()
            return
        length = _positive(self.length, "length", "m")
        radius = _positive(self.radius, "radius", "m")
        youngs_modulus = _positive(self.youngs_modulus, "youngs_modulus", "Pa")
        channel_height = _positive(self.channel_height, "channel_height", "m")
        viscosity = _positive(self.viscosity, "viscosity", "Pa*s")
        spacing, packing_fraction = self.spacing, self.packing_fraction
        if (spacing is None) == (packing_fraction is None):
            raise ValueError(
                "give exactly one of spacing [m] and packing_fraction [-], "
                f"got spacing={spacing!r}, packing_fraction={packing_fraction!r}"
            )
        if spacing is not None:
            spacing = _positive(spacing, "spacing", "m")
            if radius >= 0.5 * spacing:
                raise ValueError(
                    f"radius ({radius!r} m) must be less than half the spacing "
                    f"({spacing!r} m): neighbouring hairs would overlap"
                )
            phi = _phi_of_spacing(radius, spacing)
        else:
            phi = _positive(packing_fraction, "packing_fraction", "")
            if phi >= CLOSE_PACKING_FRACTION:
                raise ValueError(
                    f"packing_fraction ({phi!r}) must be less than hexagonal close packing, "
                    f"pi/(2 sqrt 3) = {CLOSE_PACKING_FRACTION:.6f}: hairs would overlap"
                )
            spacing = _spacing_of_phi(radius, phi)
        if length >= channel_height:
            raise ValueError(
                f"length ({length!r} m) must be less than channel_height "
                f"({channel_height!r} m): eps = L/H must be < 1, or the hairs would "
                "reach the top wall"
            )
        base_angle = check_number(self.base_angle, "base_angle", unit="rad")
        if not (abs(base_angle) < HALF_PI):
            raise ValueError(f"base_angle must lie in (-pi/2, pi/2) [rad], got {base_angle!r}")
        # frozen: the normalised values (floats, both of spacing and packing fraction) are set
        # once, here
        for name, value in (
            ("length", length),
            ("radius", radius),
            ("youngs_modulus", youngs_modulus),
            ("channel_height", channel_height),
            ("viscosity", viscosity),
            ("spacing", spacing),
            ("packing_fraction", phi),
            ("base_angle", base_angle),
        ):
            object.__setattr__(self, name, value)
        if self.density is not None:
            object.__setattr__(self, "density", _positive(self.density, "density", "kg/m**3"))
        try:
            scales = (self.second_moment, self.wall_area_per_hair, self.velocity_scale)
        except (ZeroDivisionError, OverflowError):  # Python floats raise instead of inf
            scales = (math.nan, math.nan, math.nan)
        if not all(0.0 < s < math.inf for s in scales):
            raise ValueError(
                "the bed's parameters (length, radius, youngs_modulus, channel_height, viscosity, "
                "spacing or packing_fraction) give a velocity scale E I H phi/(pi a^2 L^2 eta) = "
                f"{scales[2]:g} m/s, second moment {scales[0]:g} m^4 and wall area per hair "
                f"{scales[1]:g} m^2 that under- or overflow double precision: check their units"
            )
        object.__setattr__(self, "model", check_choice(self.model, "model", MODELS))
        object.__setattr__(self, "drag", check_choice(self.drag, "drag", DRAG_MODELS))
        if self.model == "porous":
            if phi > MAX_PACKING_FRACTION:
                raise ValueError(
                    f"packing_fraction must lie in (0, {MAX_PACKING_FRACTION}] for "
                    f"model='porous', got {phi!r}: the array's permeabilities (Drummond & "
                    "Tahir) that set the hairs' drag hold only below it"
                )
            if not length > 1.5 * radius:
                raise ValueError(
                    f"length/radius must exceed 1.5 for model='porous' (a slender hair: "
                    f"ln(2L/a) > 1/2 keeps zeta_par positive), got {length / radius!r}"
                )
        _warn_implausible(self)
        if self.model == "dense":
            _warn_sparse(self)

    # -- array-valued beds (issue 32) ---------------------------------------------------------

    def _post_init_arrays(self) -> None:
        """:meth:`__post_init__` of a bed with array parameters: each checked element by
        element (the first offending index named), the shapes broadcast, the derived numbers
        computed element by element by the scalar bed's own properties."""
        set_ = object.__setattr__

        def positive(name: str, unit: str) -> Any:
            value = getattr(self, name)
            if _is_array(value, name, unit):
                return _array_parameter(value, name, unit)
            return _positive(value, name, unit)

        for name, unit in _BED_UNITS[:5]:
            set_(self, name, positive(name, unit))
        spacing, packing_fraction = self.spacing, self.packing_fraction
        if (spacing is None) == (packing_fraction is None):
            raise ValueError(
                "give exactly one of spacing [m] and packing_fraction [-], "
                f"got spacing={show(spacing)}, packing_fraction={show(packing_fraction)}"
            )
        if spacing is not None:
            set_(self, "spacing", positive("spacing", "m"))
        else:
            set_(self, "packing_fraction", positive("packing_fraction", ""))
        base_angle: Any
        if _is_array(self.base_angle, "base_angle", "rad"):
            base_angle = _array_parameter(
                self.base_angle, "base_angle", "rad", low=-HALF_PI, high=HALF_PI,
                shown="(-pi/2, pi/2)",
            )  # fmt: skip
        else:
            base_angle = check_number(self.base_angle, "base_angle", unit="rad")
            if not (abs(base_angle) < HALF_PI):
                raise ValueError(f"base_angle must lie in (-pi/2, pi/2) [rad], got {base_angle!r}")
        set_(self, "base_angle", base_angle)
        if self.density is not None:
            set_(self, "density", positive("density", "kg/m**3"))
        shape = _shape_of(self, _BED_NAMES, "HairBed")
        self.__dict__["_shape"] = shape
        radius, length = self.radius, self.length
        if spacing is not None:
            spacing = self.spacing
            bad = ~np.asarray(radius < 0.5 * cast(Any, spacing))
            if np.any(bad):
                raise ValueError(
                    f"radius ({_at(radius, bad)!r} m) must be less than half the spacing "
                    f"({_at(spacing, bad)!r} m){_first_index(bad)}: neighbouring hairs would "
                    "overlap"
                )
            set_(self, "packing_fraction", _elementwise(_phi_of_spacing, radius, spacing))
        else:
            phi: Any = self.packing_fraction
            bad = ~np.asarray(phi < CLOSE_PACKING_FRACTION)
            if np.any(bad):
                raise ValueError(
                    f"packing_fraction ({_at(phi, bad)!r}){_first_index(bad)} must be less "
                    f"than hexagonal close packing, pi/(2 sqrt 3) = "
                    f"{CLOSE_PACKING_FRACTION:.6f}: hairs would overlap"
                )
            set_(self, "spacing", _elementwise(_spacing_of_phi, radius, phi))
        bad = ~np.asarray(length < self.channel_height)
        if np.any(bad):
            raise ValueError(
                f"length ({_at(length, bad)!r} m) must be less than channel_height "
                f"({_at(self.channel_height, bad)!r} m){_first_index(bad)}: eps = L/H must "
                "be < 1, or the hairs would reach the top wall"
            )
        set_(self, "model", check_choice(self.model, "model", MODELS))
        set_(self, "drag", check_choice(self.drag, "drag", DRAG_MODELS))
        self.__dict__["_derived"] = {}
        values = self._over_elements(_BED_DERIVED)
        scales = [values[n] for n in ("second_moment", "wall_area_per_hair", "velocity_scale")]
        bad = ~np.all([(0.0 < s) & (s < math.inf) for s in scales], axis=0)
        if np.any(bad):
            raise ValueError(
                "the bed's parameters (length, radius, youngs_modulus, channel_height, viscosity, "
                "spacing or packing_fraction) give a velocity scale E I H phi/(pi a^2 L^2 eta) = "
                f"{_at(scales[2], bad):g} m/s, second moment {_at(scales[0], bad):g} m^4 and "
                f"wall area per hair {_at(scales[1], bad):g} m^2{_first_index(bad)} that under- "
                "or overflow double precision: check their units"
            )
        if self.model == "porous":
            phi = cast(Any, self.packing_fraction)
            bad = ~np.asarray(phi <= MAX_PACKING_FRACTION)
            if np.any(bad):
                raise ValueError(
                    f"packing_fraction must lie in (0, {MAX_PACKING_FRACTION}] for "
                    f"model='porous', got {_at(phi, bad)!r}{_first_index(bad)}: the array's "
                    "permeabilities (Drummond & Tahir) that set the hairs' drag hold only below "
                    "it"
                )
            bad = ~np.asarray(length > 1.5 * radius)
            if np.any(bad):
                raise ValueError(
                    f"length/radius must exceed 1.5 for model='porous' (a slender hair: "
                    f"ln(2L/a) > 1/2 keeps zeta_par positive), got "
                    f"{_at(length, bad) / _at(radius, bad)!r}{_first_index(bad)}"
                )
            self._over_elements(_BED_DRAG)
        _warn_implausible(self)
        if self.model == "dense":
            _warn_sparse(self)

    @property
    def shape(self) -> tuple[int, ...]:
        """The broadcast shape of the bed's parameters: () for a bed of numbers, else that of
        its array parameters (numpy rules); results of its methods broadcast it with their
        own array arguments (issue 32)."""
        return cast("tuple[int, ...]", self.__dict__.get("_shape", ()))

    def item(self, index: Any = ()) -> HairBed:
        """The bed of numbers at ``index`` of :attr:`shape` (a bed of numbers is its own
        item): the same parameters, given the same way (spacing or packing fraction)."""
        shape = self.shape
        flat = _flat_index(index, shape, "bed")
        if not shape:
            return self
        kwargs: dict[str, Any] = {}
        for name in _BED_NAMES:
            value = getattr(self, name)
            if value is not None and name in ("spacing", "packing_fraction"):
                if name != self.__dict__["_given"]:
                    continue
            if isinstance(value, np.ndarray):
                value = float(np.broadcast_to(value, shape).reshape(-1)[flat])
            kwargs[name] = value
        return HairBed(**kwargs, model=self.model, drag=self.drag)

    def _elements(self, shape: tuple[int, ...] | None = None) -> Any:
        """The beds of numbers of every element (C order), trusted: built without a check
        (the array bed was checked), their properties the scalar bed's own code."""
        shape = self.shape if shape is None else shape
        shared = {"model": self.model, "drag": self.drag}
        yield from self._bare_elements(HairBed, _BED_NAMES, shape, shared)

    def _per_element(self, func: Any) -> NDArray[np.float64]:
        """``func(bed)`` of each element's bed of numbers, as an array of :attr:`shape`: a
        conversion of the bed's SI numbers that must match the scalar bed's bitwise."""
        out = np.array([func(bed) for bed in self._elements()], dtype=np.float64)
        return out.reshape(self.shape)

    def _over_elements(self, names: tuple[str, ...]) -> dict[str, Any]:
        """The derived quantities ``names`` of an array bed (cached): each element's
        property, NaN where it under- or overflows."""
        cache = self.__dict__["_derived"]
        missing = [n for n in names if n not in cache]
        if missing:
            rows: dict[str, list[Any]] = {n: [] for n in missing}
            for bed in self._elements():
                for n in missing:
                    try:
                        value = getattr(bed, n)
                    except (ZeroDivisionError, OverflowError, ValueError):
                        value = (math.nan, math.nan) if n == "drag_coefficients" else math.nan
                    rows[n].append(value)
            shape = self.shape
            for n in missing:
                arr = np.array(rows[n], dtype=np.float64)
                if n == "drag_coefficients":
                    cache[n] = tuple(_frozen(arr[:, k].reshape(shape)) for k in (0, 1))
                else:
                    cache[n] = _frozen(arr.reshape(shape))
        return {n: cache[n] for n in names}

    def _derived_value(self, name: str) -> Any:
        return self._over_elements((name,))[name]

    def _take(self, idx: NDArray[np.intp], shape: tuple[int, ...]) -> HairBed:
        """The bed of the flat elements ``idx`` of ``shape`` (a shape its own broadcasts
        to), as a 1-d array bed, trusted; a bed of numbers is itself."""
        if not self.shape:
            return self
        sub = object.__new__(HairBed)

        def take(a: Any) -> Any:
            if not isinstance(a, np.ndarray):
                return a
            return _frozen(np.broadcast_to(a, shape).reshape(-1)[idx])

        for f in dataclasses.fields(self):
            object.__setattr__(sub, f.name, take(getattr(self, f.name)))
        derived = {
            n: tuple(take(a) for a in v) if isinstance(v, tuple) else take(v)
            for n, v in self.__dict__["_derived"].items()
        }
        sub.__dict__.update(_derived=derived, _shape=(int(np.size(idx)),))
        sub.__dict__["_given"] = self.__dict__["_given"]
        return sub

    def _require_scalar(self, what: str) -> None:
        """A ValueError where ``what`` is asked of an array-valued bed, which it does not
        support: naming the array parameters and saying that numbers are needed."""
        if not self.shape:
            return
        skip = "packing_fraction" if self.__dict__["_given"] == "spacing" else "spacing"
        names = [n for n in _array_names(self, _BED_NAMES) if n != skip]
        verb = "is an array" if len(names) == 1 else "are arrays"
        raise ValueError(
            f"{what} needs a single bed, each parameter a number: {', '.join(names)} {verb} "
            f"(shape {self.shape}) here. HairBed.deform, the calibrations (exact and linear), "
            "valve.valve_curve, valve.diodicity, HairBed.simulate and rheometer.bed_moduli "
            "take array parameters; "
            "HairBed.item(index) gives one bed of the array"
        )

    def _broadcast_input(self, x: NDArray[np.float64], name: str) -> NDArray[np.float64]:
        """An input array broadcast with the bed's parameters (a copy), or a ValueError."""
        if not self.shape:
            return x
        try:
            shape = np.broadcast_shapes(x.shape, self.shape)
        except ValueError:
            raise ValueError(
                f"{name} of shape {x.shape} must broadcast with the bed's array parameters of "
                f"shape {self.shape} (numpy rules)"
            ) from None
        return np.array(np.broadcast_to(x, shape))

    # -- the bed -------------------------------------------------------------------------------

    @property
    def eps(self) -> float:
        """Confinement eps = L / H [-]."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("eps"))
        return self.length / self.channel_height

    @property
    def second_moment(self) -> float:
        """Second moment of area of the hair cross-section, I = pi a^4 / 4 [m^4]."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("second_moment"))
        return 0.25 * math.pi * self.radius**4

    @property
    def bending_stiffness(self) -> float:
        """Bending stiffness E I [N m^2]."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("bending_stiffness"))
        return self.youngs_modulus * self.second_moment

    @property
    def wall_area_per_hair(self) -> float:
        """Wall area per hair, pi a^2 / phi = (sqrt 3 / 2) delta^2 [m^2]."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("wall_area_per_hair"))
        return math.pi * self.radius**2 / cast(float, self.packing_fraction)  # set by post-init

    @property
    def permeability(self) -> float:
        """Darcy permeability k of the bed to flow along the wall [m^2]: that of a hexagonal
        array of cylinders across their axes (Drummond & Tahir 1984; theory.md §10)."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("permeability"))
        phi = cast(float, self.packing_fraction)  # set and checked by post-init
        return _transverse_permeability(self.radius, phi)

    @property
    def brinkman_length(self) -> float:
        """Depth sqrt(k) over which the flow penetrates the bed [m] (theory.md §10): the model
        needs it small against the hair length (:data:`DENSE_BED_LIMIT`)."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("brinkman_length"))
        return math.sqrt(self.permeability)

    @property
    def drag_coefficients(self) -> tuple[float, float]:
        """(zeta_perp, zeta_par) [Pa s]: one hair's drag per unit length and speed, normal and
        along it, under the bed's ``drag`` model (theory.md §13)."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("drag_coefficients"))
        phi = cast(float, self.packing_fraction)  # set and checked by post-init
        return drag_coefficients(
            self.drag,
            self.viscosity,
            self.length,
            self.radius,
            self.wall_area_per_hair,
            self.permeability,
            phi,
        )

    @property
    def kappa(self) -> float:
        """The porous bed's permeability over L^2, kappa = eta A/(zeta_perp L^2) [-]: the
        square of its Brinkman length in hair lengths (theory.md §13)."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("kappa"))
        zeta = self.drag_coefficients[0]
        return self.viscosity * self.wall_area_per_hair / (zeta * self.length**2)

    @property
    def drag_ratio(self) -> float:
        """gamma = zeta_par/zeta_perp [-] of the bed's ``drag`` model."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("drag_ratio"))
        perp, par = self.drag_coefficients
        return par / perp

    @property
    def velocity_scale(self) -> float:
        """Wall speed of unit forcing, E I H phi / (pi a^2 L^2 eta) [m/s]: omega^2 = v / it."""
        if "_derived" in self.__dict__:  # an array bed: element by element
            return cast(Any, self._derived_value("velocity_scale"))
        return (
            self.bending_stiffness
            * self.channel_height
            / (self.wall_area_per_hair * self.length**2 * self.viscosity)
        )

    # -- forward: velocity -> state ------------------------------------------------------------

    def omega2(self, velocity: Any) -> FloatOrArray:
        """Forcing omega^2 = pi a^2 L^2 eta abs(v) / (E I H phi) [-] of a wall speed.

        Parameters
        ----------
        velocity : array_like
            Speed of the top wall v [m/s]; the sign (direction) does not enter omega^2.

        Returns
        -------
        float or ndarray
            omega^2 [-], of the shape of ``velocity``.
        """
        return float_or_array(self._forcing(velocity, "velocity")[1])

    def _forcing(
        self, velocity: Any, name: str
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(v [m/s], omega^2 [-]) of a wall speed, refusing speeds whose omega^2 overflows."""
        v = self._broadcast_input(as_float_array(velocity, name, unit="m/s"), name)
        with np.errstate(over="ignore"):
            omega2 = np.abs(v) / self.velocity_scale
        bad = ~np.isfinite(omega2)
        if np.any(bad):
            limit = np.finfo(np.float64).max * _at(self.velocity_scale, bad)
            raise ValueError(
                f"{name} must be below {limit:.3g} m/s "
                f"for this bed (its forcing omega2 overflows), got {float(v[bad].flat[0])!r}"
                f"{_first_index(bad)}"
            )
        return v, omega2

    def _direction(self, v: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.where(v < 0.0, -1.0, 1.0)

    # -- the model's dimensionless states: one interface for every workflow (issue 29) ----------

    def _tip_state(
        self, omega2: Any, eps: Any, theta0: Any, drive: str = "pressure", load: Any = None
    ) -> Any:
        """The dimensionless state of the bed's own model (the low root where several
        coexist) at checked inputs: the wall forcing omega2 >= 0 alone (``load`` None) or a
        pump's load pi (``drive`` "pressure") or q ("flow") with omega2 the wall's signed
        forcing. A :class:`hairbed.Solution` or :class:`hairbed.LoadedState` of the dense
        bed, a :class:`hairbed.PorousState` of the porous one: every workflow asks this, and
        :func:`hairbed.sensitivity.derivatives_at` differentiates each."""
        if self.model == "dense":
            if load is None:
                return _solve_checked(omega2, eps, theta0)
            return _solve_loaded_trusted(drive, omega2, eps, theta0, load, "low")
        extra = () if load is None else (np.shape(load),)
        shape = np.broadcast_shapes(
            np.shape(omega2), np.shape(eps), np.shape(theta0), self.shape, *extra
        )
        arrays = tuple(
            np.array(np.broadcast_to(np.asarray(x, dtype=np.float64), shape))
            for x in (omega2, eps, theta0, self.kappa, self.drag_ratio, 0.0 if load is None
                      else load)
        )  # fmt: skip
        return _solve_porous_checked(drive, 0 if drive == "pressure" else 1, arrays, "low")

    def _collapsed_state(self, sol: Any) -> Any:
        """The state of the wall-driven ``sol`` (in its own frame) at eps = 0 with the same
        hair: the state a known stress on the tip plane gives (the dense bed's collapsed
        branch at the same t; the porous bed's at omega2 = its tip stress, since with no
        gap the gap's condition reads Q(1) = omega2 and the bed's equations hold no eps)."""
        if self.model == "dense":
            return _from_parameter(sol.t, 0.0, sol.theta0)
        return self._tip_state(np.asarray(sol.tip_stress, dtype=np.float64), 0.0, sol.theta0)

    def _drag_slopes(self, geometry: str) -> dict[str, tuple[float, float]]:
        """(d ln kappa/d ln P, d gamma/d ln P) of the porous bed's permeability kappa and
        drag ratio gamma in each parameter P (empty for the dense bed, whose model holds
        neither): exact, through the drag logarithms of
        :func:`hairbed._bed_drag.drag_logarithm_slopes`. kappa = A Lambda_perp/(4 pi L^2),
        gamma = Lambda_perp/(2 Lambda_par), A = pi a^2/phi; ``geometry`` is the one of
        spacing and packing fraction held fixed when the radius changes."""
        if self.model == "dense":
            return {}
        self._require_scalar("the derivatives of a porous bed in its parameters")
        phi = cast(float, self.packing_fraction)
        logs = drag_logarithm_slopes(
            self.drag, self.length, self.radius, self.wall_area_per_hair, self.permeability,
            phi,
        )  # fmt: skip
        lp, lq = logs["value"]
        radius_phi = 2.0 if geometry == "spacing" else 0.0
        # (d ln(2L/a), d ln phi, d ln A, d ln L) per unit d ln P
        moves = {
            "length": (1.0, 0.0, 0.0, 1.0),
            "radius": (-1.0, radius_phi, 2.0 - radius_phi, 0.0),
            "spacing": (0.0, -2.0, 2.0, 0.0),
            "packing_fraction": (0.0, 1.0, -1.0, 0.0),
        }
        gamma = lp / (2.0 * lq)
        out = {}
        for name, (dlg, dphi, darea, dlen) in moves.items():
            dp = logs["log_slenderness"][0] * dlg + logs["log_phi"][0] * dphi
            dq = logs["log_slenderness"][1] * dlg + logs["log_phi"][1] * dphi
            out[name] = (darea + dp / lp - 2.0 * dlen, gamma * (dp / lp - dq / lq))
        return out

    def _linear_slopes(self) -> tuple[float, float]:
        """(dx1/d omega2, dQ1/d omega2) at rest, wall drive: the linear calibration's slope
        of the tip deflection and of the stress on the tip plane (load units). The dense
        bed's closed form cos^2(theta0)/(3 (1 - eps cos theta0)) and 1/(1 - eps cos theta0);
        the porous bed's the exact derivatives of its state at rest."""
        from .inverse import _slope

        number: Any = float if not self.shape else np.asarray  # an array bed: its shape
        if self.model == "dense":
            gap0 = 1.0 - self.eps * _cos(self.base_angle)
            return number(_slope(self.eps, self.base_angle)), 1.0 / gap0
        from ._core.porous_sensitivity import porous_derivatives

        table = porous_derivatives(self._tip_state(0.0, self.eps, self.base_angle)).table
        return number(table["tip_deflection"]["omega2"]), number(table["tip_stress"]["omega2"])

    def deform(
        self,
        velocity: Any = None,
        *,
        pressure_gradient: Any = None,
        flow_rate: Any = None,
        root: str = "low",
    ) -> HairState:
        """The state of the bed under a flow: a moving wall, a pressure gradient or a flow rate.

        Parameters
        ----------
        velocity : array_like, optional
            Speed of the top wall v [m/s]; negative for flow towards -x (the mirror image, see
            the module docstring). Alone, the paper's wall-driven channel (closed form); with a
            pump drive, the wall moves too (default at rest).
        pressure_gradient : array_like, optional
            A pump's pressure gradient G = -dp/dx [Pa/m] (positive drives towards +x): the
            bed carries G pi a^2/phi per unit height and the state has no closed form
            (:func:`hairbed.solve_loaded`, theory.md §11).
        flow_rate : array_like, optional
            A pump's flow rate per unit width Q' [m^2/s] (positive towards +x); at most one of
            ``pressure_gradient`` and ``flow_rate``. Inputs broadcast together.
        root : {"low", "mid", "high"}
            Which state to return where several coexist (a hair leaning into a flow in a tight
            channel, theory.md §5): passed to :func:`hairbed.solve` (or, with a pump drive,
            the closed-form start of :func:`hairbed.solve_loaded`).

        Returns
        -------
        HairState
            Tip position, shear stress and force in SI, and the dimensionless solution.

        Examples
        --------
        >>> bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6,
        ...               channel_height=2e-3, viscosity=1.0, spacing=400e-6)
        >>> round(bed.deform(0.1).tip_deflection * 1e6, 3)  # [um]
        539.832
        >>> st = bed.deform(pressure_gradient=200.0)  # [Pa/m], both walls at rest
        >>> round(st.tip_deflection * 1e6, 4), round(st.flow_rate * 1e6, 4)  # [um], [mm^2/s]
        (1.6466, 0.0167)
        """
        root = check_root(root)
        if self.model == "porous":
            return self._deform_porous(velocity, pressure_gradient, flow_rate, root)
        if pressure_gradient is not None or flow_rate is not None:
            return self._deform_pumped(velocity, pressure_gradient, flow_rate, root)
        if velocity is None:
            raise TypeError(
                "deform() needs velocity [m/s], pressure_gradient [Pa/m] or flow_rate [m^2/s]"
            )
        v, omega2 = self._forcing(velocity, "velocity")
        direction = self._direction(v)
        # checked: omega2 finite >= 0 (_forcing), eps and the base angle by the bed itself
        sol = _solve_checked(omega2, self.eps, direction * self.base_angle, root=root)
        return self._state(v, direction, omega2, sol)

    def _deform_pumped(
        self, velocity: Any, pressure_gradient: Any, flow_rate: Any, root: str
    ) -> HairState:
        """:meth:`deform` with a pump drive: the distributed-load solver, signs kept."""
        drive, v, value, omega2, load = drive_inputs(self, velocity, pressure_gradient, flow_rate)
        # checked: the drive by drive_inputs, eps and the base angle by the bed itself
        sol = self._solve_loaded(drive, omega2, load, root)
        h1 = np.asarray(sol.tip_height, dtype=np.float64)
        flow = gap_flow(self, drive, v, value, h1)
        if self.density is not None:
            _warn_reynolds(flow["reynolds_number"])
        length = self.length
        x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
        return HairState(
            bed=self,
            velocity=float_or_array(v),
            omega2=float_or_array(np.abs(omega2)),
            solution=sol,
            direction=float_or_array(np.ones(np.shape(h1))),
            tip_deflection=float_or_array(length * x1),
            tip_height=float_or_array(length * h1),
            tip_angle=sol.tip_angle,
            wall_shear_stress=float_or_array(flow["wall_shear_stress"]),
            force_per_hair=float_or_array(flow["force_per_hair"]),
            stress_ratio=float_or_array(flow["stress_ratio"]),
            tip_displacement=float_or_array(length * (x1 - _sin(self.base_angle))),
            reynolds_number=float_or_array(flow["reynolds_number"]),
            pressure_gradient=float_or_array(flow["pressure_gradient"]),
            flow_rate=float_or_array(flow["flow_rate"]),
        )

    def _solve_loaded(self, drive: str, omega2: Any, load: Any, root: str) -> Any:
        """The dense bed's distributed-load states (:func:`hairbed.solve_loaded`) at checked
        drives, the bed's eps and base angle broadcast with them: one compiled call."""
        if not self.shape:
            return _solve_loaded_trusted(drive, omega2, self.eps, self.base_angle, load, root)
        shape = np.broadcast_shapes(np.shape(omega2), np.shape(load), self.shape)
        w, e, t0, ld = (
            np.array(np.broadcast_to(np.asarray(x, dtype=np.float64), shape))
            for x in (omega2, self.eps, self.base_angle, load)
        )
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return _solve_loaded_checked(drive, _DRIVES[drive], w, e, t0, ld, root, 1e-12, LADDER)

    def _deform_porous(
        self, velocity: Any, pressure_gradient: Any, flow_rate: Any, root: str
    ) -> HairState:
        """:meth:`deform` of the porous bed (theory.md §13): any drive, signs kept."""
        if pressure_gradient is None and flow_rate is None:
            if velocity is None:
                raise TypeError(
                    "deform() needs velocity [m/s], pressure_gradient [Pa/m] or flow_rate [m^2/s]"
                )
            v, omega2 = self._forcing(velocity, "velocity")
            omega2 = np.where(v < 0.0, -omega2, omega2)
            drive, value, load = "pressure", np.zeros(v.shape), np.zeros(v.shape)
        else:
            drive, v, value, omega2, load = drive_inputs(
                self, velocity, pressure_gradient, flow_rate
            )
        shape = np.broadcast_shapes(np.shape(omega2), np.shape(load), self.shape)
        arrays = tuple(
            np.array(np.broadcast_to(np.asarray(x, dtype=np.float64), shape))
            for x in (omega2, self.eps, self.base_angle, self.kappa, self.drag_ratio, load)
        )
        # checked: the drive by _forcing or drive_inputs, the rest by the bed itself
        sol = _solve_porous_checked(drive, 0 if drive == "pressure" else 1, arrays, root)
        flow = porous_flow(self, sol, np.asarray(v, dtype=np.float64), drive, value)
        wall = pressure_gradient is None and flow_rate is None
        self._porous_rest_ratio(flow, drive, arrays, root, wall)
        if self.density is not None:
            _warn_reynolds(flow["reynolds_number"])
        length = self.length
        x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
        return HairState(
            bed=self,
            velocity=float_or_array(v),
            omega2=float_or_array(np.abs(omega2)),
            solution=sol,
            direction=float_or_array(np.ones(shape)),
            tip_deflection=float_or_array(length * x1),
            tip_height=float_or_array(length * np.asarray(sol.tip_height)),
            tip_angle=sol.tip_angle,
            wall_shear_stress=float_or_array(flow["wall_shear_stress"]),
            force_per_hair=float_or_array(flow["force_per_hair"]),
            stress_ratio=float_or_array(flow["stress_ratio"]),
            tip_displacement=float_or_array(length * (x1 - _sin(self.base_angle))),
            reynolds_number=float_or_array(flow["reynolds_number"]),
            pressure_gradient=float_or_array(flow["pressure_gradient"]),
            flow_rate=float_or_array(flow["flow_rate"]),
        )

    def _porous_rest_ratio(
        self,
        flow: dict[str, Any],
        drive: str,
        arrays: tuple[NDArray[np.float64], ...],
        root: str,
        wall: bool,
    ) -> None:
        """The stress ratio of porous states at zero drive (0/0 there), in place: its limit,
        the ratio at a drive of 1e-100 (Stokes flow is linear in the drive at the rest
        geometry, which the hair keeps to rounding there), along the drive given: the wall's
        speed when ``wall``, else the pump's G or Q' (issue 33)."""
        rest = ((arrays[0] == 0.0) & (arrays[5] == 0.0)).reshape(-1)
        if not np.any(rest):
            return
        idx = np.flatnonzero(rest)
        probe = [np.ascontiguousarray(a.reshape(-1)[idx]) for a in arrays]
        tiny = np.full(idx.size, 1e-100)
        bed = self._take(idx, arrays[0].shape)  # an array bed: the elements at rest
        if wall:
            probe[0], v, value = tiny, tiny * bed.velocity_scale, np.zeros(idx.size)
        else:
            probe[5], v, value = tiny, np.zeros(idx.size), tiny / load_scale(bed, drive)
        sol = _solve_porous_checked(drive, 0 if drive == "pressure" else 1, tuple(probe), root)
        near = porous_flow(bed, sol, v, drive, value)["stress_ratio"]
        ratio = np.array(flow["stress_ratio"], dtype=np.float64)
        ratio.reshape(-1)[idx] = near
        flow["stress_ratio"] = ratio

    def _state(
        self,
        v: NDArray[np.float64],
        direction: NDArray[np.float64],
        omega2: NDArray[np.float64],
        sol: Any,
    ) -> HairState:
        length = self.length
        h1 = np.asarray(sol.tip_height, dtype=np.float64)
        gap = self.channel_height - h1 * length
        tau = self.viscosity * v / gap
        if self.density is None:
            reynolds = np.full(np.shape(gap), np.nan)
        else:
            reynolds = self.density * np.abs(v) * gap / self.viscosity
            _warn_reynolds(reynolds)
        return HairState(
            bed=self,
            velocity=float_or_array(v),
            omega2=float_or_array(omega2),
            solution=sol,
            direction=float_or_array(direction),
            tip_deflection=float_or_array(direction * length * np.asarray(sol.tip_deflection)),
            tip_height=float_or_array(length * h1),
            tip_angle=float_or_array(direction * np.asarray(sol.tip_angle)),
            wall_shear_stress=float_or_array(tau),
            force_per_hair=float_or_array(tau * self.wall_area_per_hair),
            stress_ratio=float_or_array(self.channel_height / gap),
            tip_displacement=float_or_array(direction * length * np.asarray(sol.tip_displacement)),
            reynolds_number=float_or_array(reynolds),
            pressure_gradient=float_or_array(np.zeros(np.shape(gap))),
            flow_rate=float_or_array(v * gap / 2.0),
        )

    def simulate(
        self,
        times: Any,
        *,
        velocity: Any = None,
        pressure_gradient: Any = None,
        flow_rate: Any = None,
        wall_shear_stress: Any = None,
        hair_density: float | None = None,
        num: int | None = None,
        num_gap: int = 16,
        rtol: float = 1e-8,
        atol: float = 1e-10,
        max_steps: int = 100_000,
        workers: int = 1,
    ) -> BedSimulation:
        """The bed's motion in time-dependent flow, in SI: the porous bed in time (theory.md
        §15; a dense bed runs the porous model of its geometry) under a top wall's speed
        v(t) [m/s] or stress tau(t) [Pa] and a pump's G(t) [Pa/m] or Q'(t) [m^2/s] (numbers:
        steps from rest at times[0]; :mod:`hairbed.dynamics` signals in SI; callables of
        t [s]), the fluid's inertia from ``density``, the hairs' from ``hair_density``
        [kg/m^3]: :func:`hairbed.bed_simulation.simulate` (a
        :class:`hairbed.bed_simulation.BedSimulation`). An array bed (a design scan) gives
        one run with its shape in front, each element the run of its :meth:`item` (on
        ``workers`` threads)."""
        from .bed_simulation import simulate

        return simulate(
            self,
            times,
            velocity=velocity,
            pressure_gradient=pressure_gradient,
            flow_rate=flow_rate,
            wall_shear_stress=wall_shear_stress,
            hair_density=hair_density,
            num=num,
            num_gap=num_gap,
            rtol=rtol,
            atol=atol,
            max_steps=max_steps,
            workers=workers,
        )

    def wall_shear_stress(self, velocity: Any, *, root: str = "low") -> FloatOrArray:
        """Shear stress on the top wall, eta v / (H - h1 L) [Pa], at wall speed v [m/s]."""
        return self.deform(velocity, root=root).wall_shear_stress

    def sweep(
        self,
        velocity: Any = None,
        *,
        pressure_gradient: Any = None,
        flow_rate: Any = None,
        root: str = "low",
        chunks: Any = None,
        progress: bool = False,
    ) -> Any:
        """The bed's states over wall speeds (or a pump's drive) as a labelled xarray Dataset.

        Tip deflection, displacement and height [m], tip angle [rad], wall shear stress [Pa],
        force per hair [N] and stress ratio, with the dimensionless fields beside them and
        the bed's parameters in the attributes; see :func:`hairbed.sweeps.bed_sweep`
        (``chunks`` and ``progress`` as in :func:`hairbed.sweep`). Needs
        ``pip install "hairbed[sweep]"``.

        Parameters
        ----------
        velocity : float or 1-D array_like, optional
            Speed of the top wall v [m/s] (the dimension ``velocity``).
        pressure_gradient, flow_rate : float or 1-D array_like, optional
            A pump's drive, G [Pa/m] or Q' [m^2/s] (at most one; a dimension of its name):
            the distributed-load solver over the grid (velocity, drive), as in :meth:`deform`.
        """
        from .sweeps import bed_sweep

        self._require_scalar("HairBed.sweep")
        return bed_sweep(
            self,
            velocity,
            pressure_gradient=pressure_gradient,
            flow_rate=flow_rate,
            root=root,
            chunks=chunks,
            progress=progress,
        )

    def rectification_ratio(self, speed: Any, *, root: str = "low") -> FloatOrArray:
        """Stress against the grain over stress with it, at wall speed abs(v) = ``speed`` [m/s].

        See :func:`hairbed.rheology.rectification_ratio`; "with the grain" is flow towards +x
        (along a positive base angle).
        """
        from .rheology import _rectification_ratio

        root = check_root(root)
        v, omega2 = self._forcing(speed, "speed")  # checked: the bed's eps and angle are too
        if self.model == "porous":
            # the stress on the tip plane against the grain (-x) over that with it (+x)
            against = self._deform_porous(-np.abs(v), None, None, root).wall_shear_stress
            along = self._deform_porous(np.abs(v), None, None, root).wall_shear_stress
            with np.errstate(invalid="ignore", divide="ignore"):
                ratio = np.abs(np.asarray(against)) / np.abs(np.asarray(along))
            return float_or_array(ratio)
        return float_or_array(_rectification_ratio(omega2, self.eps, self.base_angle, root))

    # -- inverse: tip deflection -> velocity (the sensor's calibration) -------------------------

    def _deflection(self, deflection: Any, name: str = "deflection") -> NDArray[np.float64]:
        """A tip deflection [m] (pint quantities converted) in (-length, length)."""
        d = self._broadcast_input(as_float_array(deflection, name, unit="m"), name)
        # |d| >= L, or |d|/L rounding to 1: a hair lying flat, the limit v -> inf (no state)
        with np.errstate(over="ignore"):
            bad = np.asarray(np.abs(d) / self.length >= 1.0)
        if np.any(bad):
            length = _at(self.length, bad)
            raise ValueError(
                f"{name}: the tip deflection must lie in (-length, length) = ({-length!r}, "
                f"{length!r}) m, got {float(d[bad].flat[0])!r}{_first_index(bad)} (a tip at "
                "the full length is a hair lying flat, reached only as the speed -> inf)"
            )
        return d

    def _solve_tip_deflection(
        self, deflection: Any
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], Any]:
        """Velocity, direction, omega^2 and the dimensionless solution of a tip deflection."""
        return self._invert(self._deflection(deflection))

    def _invert(
        self, d: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], Any]:
        """:meth:`_solve_tip_deflection` of a checked deflection d [m] in (-L, L), trusted."""
        from .inverse import _solution_from_tip_deflection

        length = self.length
        rest = length * _sin(self.base_angle)
        # a tip behind its rest position means flow towards -x: the mirror image. Either way
        # x1 = direction d/L lies in [sin(direction theta0), 1): no check to repeat
        direction = np.where(d < rest, -1.0, 1.0)
        sol = _solution_from_tip_deflection(
            direction * d / length, self.eps, direction * self.base_angle
        )
        omega2 = np.asarray(sol.omega2, dtype=np.float64)
        v = direction * omega2 * self.velocity_scale
        return v, direction, omega2, sol

    def state_from_tip_deflection(self, deflection: Any) -> HairState:
        """The state of a bed whose tips sit at ``deflection`` [m] from their bases (along +x).

        The tip deflection determines the state uniquely (theory.md §5), even where several
        states share one velocity.
        """
        return self._state_of_deflection(self._deflection(deflection))

    def _state_of_deflection(self, d: NDArray[np.float64]) -> HairState:
        """:meth:`state_from_tip_deflection` of a checked deflection d [m] in (-L, L), of
        either model (the wall drive)."""
        if self.model == "porous":
            return self._porous_from_tip_deflection(d)
        return self._state(*self._invert(d))

    def _porous_from_tip_deflection(self, d: NDArray[np.float64]) -> HairState:
        """:meth:`state_from_tip_deflection` of a porous bed, d [m] checked: the porous
        inverse (:func:`hairbed.inverse.porous_state_from_tip_deflection`) in the mirror
        image where the tip sits behind its rest position (flow towards -x)."""
        from .inverse import porous_state_from_tip_deflection

        length = self.length
        direction = np.where(d < length * _sin(self.base_angle), -1.0, 1.0)
        sol = porous_state_from_tip_deflection(
            direction * d / length,
            self.eps,
            direction * self.base_angle,
            kappa=self.kappa,
            gamma=self.drag_ratio,
        )
        omega2 = np.asarray(sol.omega2, dtype=np.float64)
        v = direction * omega2 * self.velocity_scale
        zero = np.zeros(np.shape(v))
        flow = porous_flow(self, sol, np.abs(v), "pressure", zero)
        x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
        return HairState(
            bed=self,
            velocity=float_or_array(v),
            omega2=float_or_array(omega2),
            solution=sol,
            direction=float_or_array(direction),
            tip_deflection=float_or_array(direction * length * x1),
            tip_height=float_or_array(length * np.asarray(sol.tip_height)),
            tip_angle=float_or_array(direction * np.asarray(sol.tip_angle)),
            wall_shear_stress=float_or_array(direction * flow["wall_shear_stress"]),
            force_per_hair=float_or_array(direction * flow["force_per_hair"]),
            stress_ratio=float_or_array(flow["stress_ratio"]),
            tip_displacement=float_or_array(
                direction * length * (x1 - np.sin(direction * self.base_angle))
            ),
            reynolds_number=float_or_array(flow["reynolds_number"]),
            pressure_gradient=float_or_array(zero),
            flow_rate=float_or_array(direction * flow["flow_rate"]),
        )

    def velocity_from_tip_deflection(self, deflection: Any) -> FloatOrArray:
        """Wall speed v [m/s] that puts the tips at ``deflection`` [m] from their bases.

        The exact calibration curve of a pillar sensor. ``deflection`` is measured along +x from
        the base and lies in (-L, L); at rest it is L sin(theta0), and a tip behind that means
        flow towards -x (negative v).

        Raises
        ------
        ValueError
            If ``|deflection| >= length``.
        """
        if self.model == "porous":
            return self.state_from_tip_deflection(deflection).velocity
        return float_or_array(self._solve_tip_deflection(deflection)[0])

    def velocity_from_wall_shear_stress(self, wall_shear_stress: Any) -> FloatOrArray:
        """Wall speed v [m/s] at which the top wall carries ``wall_shear_stress`` [Pa].

        The calibration curve in stress. The load on one hair is F = tau pi a^2/phi, so the
        stress fixes omega_eps^2 = F L^2/(E I) (theory.md §7): the state is that of the
        collapsed problem (eps = 0) at omega_eps^2, one state for every stress, whose
        forcing at the bed's eps is omega^2 = omega_eps^2 (1 - eps h1), eq. (34); then
        v = omega^2 times :attr:`velocity_scale`. A negative stress is flow towards -x.

        A porous bed's stress is the one on the tip plane (its :class:`HairState`'s), the
        same as on the top wall of the wall-driven channel: at eps = 0 it fixes the state,
        the tip load Q(1) = tau A L^2/(E I) of the bed at eps = 0 (whose equations hold no
        eps), and the gap's condition gives omega^2 = eps w(1) + (1 - eps h1) Q(1)
        (theory.md §13).
        """
        tau = as_float_array(wall_shear_stress, "wall_shear_stress", unit="Pa")
        tau = self._broadcast_input(tau, "wall_shear_stress")
        scale: Any = self.wall_area_per_hair * self.length**2 / self.bending_stiffness
        if self.shape:  # element by element: the scalar bed's number
            scale = self._per_element(
                lambda b: b.wall_area_per_hair * b.length**2 / b.bending_stiffness
            )
        with np.errstate(over="ignore"):
            forcing = np.abs(tau) * scale
        bad = ~np.isfinite(forcing)
        if np.any(bad):
            limit = np.finfo(np.float64).max / _at(scale, bad)
            raise ValueError(
                f"wall_shear_stress must be below {limit:.3g} Pa "
                f"for this bed (its forcing overflows), got {float(tau[bad].flat[0])!r}"
                f"{_first_index(bad)}"
            )
        direction = self._direction(tau)
        theta0 = direction * self.base_angle
        collapsed = self._tip_state(forcing, 0.0, theta0)
        if self.model == "dense":
            state = _from_parameter(np.asarray(collapsed.t, dtype=np.float64), self.eps, theta0)
            omega2 = np.asarray(state.omega2, dtype=np.float64)
        else:  # the gap's condition at the bed's eps: omega2 = eps w(1) + (1 - eps h1) Q(1)
            h1 = np.asarray(collapsed.tip_height, dtype=np.float64)
            w1 = np.asarray(collapsed.tip_velocity, dtype=np.float64)
            omega2 = self.eps * w1 + (1.0 - self.eps * h1) * forcing
        return float_or_array(direction * omega2 * self.velocity_scale)

    def wall_shear_stress_from_tip_deflection(self, deflection: Any) -> FloatOrArray:
        """Wall shear stress tau = eta v / (H - h1 L) [Pa] read from a tip deflection [m]."""
        return self.state_from_tip_deflection(deflection).wall_shear_stress

    def linear_velocity_from_tip_deflection(self, deflection: Any) -> FloatOrArray:
        """The small-deflection (linear) calibration: v [m/s] from a tip deflection [m].

        To first order in the forcing the hair is a cantilever under a point load at its tip
        (x1 L = F L^3/(3 E I) for an upright hair), and
        x1 = sin(theta0) + omega^2 cos^2(theta0) / (3 (1 - eps cos theta0)) (see
        :func:`hairbed.inverse.tip_deflection_slope`); the same line holds for v < 0. Compare
        with :meth:`velocity_from_tip_deflection` to see where it fails. A porous bed's
        slope dx1/d omega^2 is the exact derivative of its state at rest (theory.md §13):
        the linear response of the Brinkman bed.
        """
        d = self._deflection(deflection)
        slope = self._linear_slopes()[0]
        x1 = d / self.length - _sin(self.base_angle)
        return float_or_array(x1 / slope * self.velocity_scale)

    def linear_wall_shear_stress_from_tip_deflection(self, deflection: Any) -> FloatOrArray:
        """The linear calibration of the wall shear stress [Pa]: eta v_lin / (H - L cos theta0).

        v_lin is :meth:`linear_velocity_from_tip_deflection`; the gap is that of the hair at rest.
        A porous bed's: the stress on its tip plane at rest, v_lin/v_s dQ1/d omega^2 E I/(A L^2)
        (v_s the :attr:`velocity_scale`, dQ1/d omega^2 the exact derivative at rest).
        """
        v = np.asarray(self.linear_velocity_from_tip_deflection(deflection))
        if self.model == "dense":
            gap = self.channel_height - self.length * _cos(self.base_angle)
            return float_or_array(self.viscosity * v / gap)
        stress: Any = self.bending_stiffness / (self.wall_area_per_hair * self.length**2)
        if self.shape:  # element by element: the scalar bed's number
            stress = self._per_element(
                lambda b: b.bending_stiffness / (b.wall_area_per_hair * b.length**2)
            )
        return float_or_array(v / self.velocity_scale * self._linear_slopes()[1] * stress)

    def fit_profile(self, x: Any, z: Any, **kwargs: Any) -> BedProfileFit:
        """Fit the flow to measured points (x, z) [m] along one hair, base at the origin.

        Calls :func:`hairbed.profile_fit.fit_profile` on (x/L, z/L) with the bed's eps and, unless
        ``theta0=None`` is passed, its base angle held fixed; keyword arguments are passed on.
        Only flow towards +x is fitted. A porous bed passes its ``kappa`` and ``gamma``: its
        own states are the curves fitted.

        Returns
        -------
        BedProfileFit
            The fitted wall speed and its standard error [m/s], the dimensionless fit and how
            the optimiser ended.
        """
        from .profile_fit import fit_profile

        self._require_scalar("HairBed.fit_profile")
        kwargs.setdefault("theta0", self.base_angle)
        if self.model == "porous":  # its curves: the porous bed's states (theory.md §13)
            kwargs.setdefault("kappa", self.kappa)
            kwargs.setdefault("gamma", self.drag_ratio)
        with np.errstate(over="ignore"):  # an overflow is infinite: refused, naming x or z
            x = as_float_array(x, "x", unit="m") / self.length
            z = as_float_array(z, "z", unit="m") / self.length
        fit = fit_profile(x, z, self.eps, **kwargs)
        return BedProfileFit(
            velocity=fit.omega2 * self.velocity_scale,
            velocity_stderr=fit.omega2_stderr * self.velocity_scale,
            fit=fit,
            success=fit.success,
            status=fit.status,
            message=fit.message,
        )
