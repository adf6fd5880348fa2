"""An isolated micropillar wall-shear-stress sensor in SI units (issue 21, theory.md §12).

A pillar of length L, radius a and Young's modulus E stands alone on the wall of a flow of
viscosity eta, clamped at the base angle theta0, and is bent by the resistive-force drag of the
undisturbed profile along its whole height. The dimensionless state
(:func:`hairbed.solve_pillar`) depends on one forcing, for the wall shear stress tau_w::

    I          = pi a^4 / 4                                  second moment of area [m^4]
    zeta_perp  = c 4 pi eta / (ln(2L/a) + 1/2)               normal drag coefficient [Pa s]
    gamma      = (ln(2L/a) + 1/2) / (2 ln(2L/a) - 1)         zeta_par / zeta_perp [-]
    Lambda     = zeta_perp tau_w L^4 / (eta E I)             forcing [-]

(Gray & Hancock's coefficients with the pillar length for their wavelength, theory.md §12;
c is :attr:`Pillar.drag_scale`, 1 by default, the factor a calibration may fit: the
coefficients are known to O(1/ln(L/a)) only). In a Couette channel of height H the wall
stress is tau_w = eta V/H (V the moving wall's speed); in a Poiseuille channel
tau_w = G H/2 (G = -dp/dx). The dimensionless solution gives back, in SI::

    tip deflection x1 L [m],  tip height h1 L [m],  base moment E I theta'(0)/L [N m],
    drag F(0) E I/L^2 [N],    sensitivity dx1/dtau_w = L (dx1/dLambda) Lambda/tau_w [m/Pa].

Unlike a bed there is no mirror image to take: a negative stress (flow towards -x) is a
negative Lambda, solved as it is.

The profile "wall-law" is Spalding's law of the wall (theory.md §12, "The mean flow the
pillar stands in") in the wall units of the stress, u_tau = sqrt(abs(tau_w)/rho) and
nu = eta/rho: the pillar's height in wall units L+ = L u_tau/nu sets its dimensionless
profile U(z) = u+(L+ z)/L+, so the forcing depends on tau_w through Lambda and through the
shape of U. Every SI state reports L+ (with a density, or a ``fluid`` preset that gives it).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from ._bracketing import find_root
from ._core.loaded import _kernels
from ._core.outputs import float_or_array, scalar_or_array
from ._core.pillar import (
    _DRAG_INVERSE,
    PROFILES,
    PillarState,
    _callable_coefficients,
    _inverse_checked,
    _kernel_run,
    _mirror,
    _options,
    _pillar_state,
    _solve_pillar_checked,
    _state_start,
    gray_hancock_ratio,
    profile_coefficients,
)
from ._core.pillar_sensitivity import _profile_derivative, pillar_gradient_rows
from ._core.validation import (
    HALF_PI,
    STATUS_MESSAGES,
    _first_index,
    as_float_array,
    check_int,
    check_number,
    check_positive,
    real_values,
    show,
    status_messages,
)
from ._core.wall_law import (
    MAX_L_PLUS,
    WALL_LAW_B,
    WALL_LAW_KAPPA,
    _u_plus,
    row_groups,
    wall_law_coefficients,
)
from ._ranges import LinearRange
from ._warnings import ModelValidityWarning
from .units import (
    _array_names,
    _array_parameter,
    _ArrayModel,
    _at,
    _flat_index,
    _frozen,
    _is_array,
    _shape_of,
    _sin,
    _warn_implausible,
)

__all__ = [
    "FLUIDS",
    "MAX_L_PLUS",
    "MIN_SLENDERNESS",
    "PILLAR_PROFILES",
    "PILLAR_REYNOLDS_LIMIT",
    "SLENDERNESS_LIMIT",
    "SUBLAYER_L_PLUS_LIMIT",
    "Pillar",
    "PillarDeformation",
]

FloatOrArray = float | NDArray[np.float64]
FloatArray = NDArray[np.float64]

#: Below this slenderness L/a slender-body (resistive-force) theory is out of its range
#: (theory.md §12): a :class:`hairbed.ModelValidityWarning`.
SLENDERNESS_LIMIT = 10.0
#: The least slenderness L/a of a pillar: Gray & Hancock's gamma = (ln(2L/a) + 1/2)/
#: (2 ln(2L/a) - 1) is 1 at ln(2L/a) = 3/2 and above 1 (no longer a slender body) below.
MIN_SLENDERNESS = math.exp(1.5) / 2.0
#: Above this pillar Reynolds number rho abs(u(tip)) 2a/eta the Stokes drag is out of its range
#: (theory.md §12): a :class:`hairbed.ModelValidityWarning`.
PILLAR_REYNOLDS_LIMIT = 0.5
#: The profiles of a :class:`Pillar`: the core's and Spalding's law of the wall.
PILLAR_PROFILES = (*PROFILES, "wall-law")
#: Above this height in wall units L+ the viscous sublayer (u+ = y+, 2.7 % off at y+ = 5)
#: in Spalding's law) no longer holds along the pillar: the "sublayer" profile gets a
#: :class:`hairbed.ModelValidityWarning` that points to the "wall-law" profile.
SUBLAYER_L_PLUS_LIMIT = 5.0
#: Fluid presets at 20 C and 101.325 kPa: name -> (viscosity eta [Pa s], density rho
#: [kg/m^3]). Water and air: CRC Handbook of Chemistry and Physics (W. M. Haynes, ed., 97th
#: ed., CRC Press 2016: "Viscosity of liquids", "Properties of water in the range 0-100 C",
#: "Viscosity of gases", dry air); glycerol: the viscosity of J. B. Segur and H. E. Oberstar,
#: "Viscosity of glycerol and its aqueous solutions", Ind. Eng. Chem. 43, 2117-2120 (1951),
#: and the density of the CRC Handbook.
FLUIDS: dict[str, tuple[float, float]] = {
    "water": (1.0016e-3, 998.21),
    "glycerol": (1.412, 1261.3),
    "air": (1.825e-5, 1.2041),
}
#: The SI parameters of a :class:`Pillar` with the units a pint quantity is converted to: each
#: may be an array (issue 32), and they broadcast together.
_PILLAR_UNITS = (
    ("length", "m"),
    ("radius", "m"),
    ("youngs_modulus", "Pa"),
    ("viscosity", "Pa s"),
    ("base_angle", "rad"),
    ("drag_scale", ""),
    ("channel_height", "m"),
    ("density", "kg/m^3"),
)
_PILLAR_NAMES = tuple(n for n, _ in _PILLAR_UNITS)
#: Gauss-Legendre nodes of the linear coefficient (exact for a profile of degree < 390).
_GAUSS = np.polynomial.legendre.leggauss(200)
#: The search grid of :meth:`Pillar.linear_range`: the fraction u of the way from the tip at
#: rest to the wall (x1 = sin theta0 + u (1 - sin theta0)).
_RANGE_GRID = np.concatenate([np.geomspace(1e-6, 0.05, 60), np.linspace(0.05, 0.999, 96)[1:]])
#: The chunks in which :meth:`Pillar.linear_range` evaluates the grid, from rest.
_RANGE_CHUNKS = 6


@dataclass(frozen=True)
class PillarDeformation:
    """A pillar bent by a flow, in SI units (from :meth:`Pillar.deform`).

    Scalar inputs give float fields, array inputs arrays of their shape. Where no state was
    found (``status`` < 0) the value fields are NaN.

    Attributes
    ----------
    pillar : Pillar
        The pillar.
    wall_shear_stress : float or ndarray
        The wall shear stress tau_w [Pa] (negative: flow towards -x).
    velocity : float or ndarray
        The moving wall's speed V = tau_w H/eta of a Couette channel [m/s]; NaN otherwise.
    pressure_gradient : float or ndarray
        G = -dp/dx = 2 tau_w/H of a Poiseuille channel [Pa/m]; NaN otherwise.
    forcing : float or ndarray
        Lambda = zeta_perp tau_w L^4/(eta E I) [-].
    solution : PillarState
        The dimensionless state (:func:`hairbed.solve_pillar`).
    tip_deflection : float or ndarray
        Horizontal position of the tip relative to the base, x1 L [m] (along +x).
    tip_height : float or ndarray
        Height of the tip above the wall, h1 L [m].
    tip_angle : float or ndarray
        Angle of the tip from the wall normal towards +x [rad].
    tip_displacement : float or ndarray
        Horizontal displacement of the tip from its position at rest, (x1 - sin theta0) L [m].
    base_moment : float or ndarray
        Bending moment at the base, E I theta'(0)/L [N m] (positive: tilting towards +x).
    drag : float or ndarray
        Streamwise drag on the whole pillar, F_x(0) E I/L^2 [N].
    drag_wall_normal : float or ndarray
        Wall-normal drag on the whole pillar, F_z(0) E I/L^2 [N].
    sensitivity : float or ndarray
        d(tip deflection)/d(tau_w) [m/Pa], exact (implicit differentiation of the
        collocation system, :attr:`PillarState.tip_deflection_slope`); NaN at a fold.
    reynolds_number : float or ndarray
        Pillar Reynolds number rho abs(u(tip)) 2a/eta [-], u(tip) the undisturbed speed at
        the tip's height; NaN without a ``density``. Above
        :data:`PILLAR_REYNOLDS_LIMIT` a :class:`hairbed.ModelValidityWarning` is issued.
    height_in_wall_units : float or ndarray
        The pillar's length in wall units L+ = L sqrt(abs(tau_w)/rho)/nu [-], nu = eta/rho
        (the height of the upright pillar); NaN without a ``density``. The "wall-law"
        profile's shape depends on it; with the "sublayer" profile above
        :data:`SUBLAYER_L_PLUS_LIMIT` a :class:`hairbed.ModelValidityWarning` is issued.
    status : int or ndarray
        The solver's status (0 ok, 3 inaccurate, 6 found but others may coexist, negative failed;
        ``STATUS_MESSAGES``).
    n_states : int or ndarray
        How many states coexist at this stress (:attr:`hairbed.PillarState.n_states`): 1, or
        3 inside a snap-through window (a pillar tilted far against the flow), where this is
        the first one a slow ramp from rest reaches; ``hairbed.solve_pillar_all(forcing,
        theta0, gamma=..., profile=...)`` of this state's ``solution`` gives all three. 0
        where no state was found.
    """

    pillar: Pillar = field(repr=False)
    wall_shear_stress: FloatOrArray
    velocity: FloatOrArray
    pressure_gradient: FloatOrArray
    forcing: FloatOrArray
    solution: Any = field(repr=False)
    tip_deflection: FloatOrArray
    tip_height: FloatOrArray
    tip_angle: FloatOrArray
    tip_displacement: FloatOrArray
    base_moment: FloatOrArray
    drag: FloatOrArray
    drag_wall_normal: FloatOrArray
    sensitivity: FloatOrArray
    reynolds_number: FloatOrArray
    status: Any
    height_in_wall_units: FloatOrArray = math.nan
    n_states: Any = None

    @property
    def success(self) -> Any:
        """True where the state converged within the tolerance (status 0)."""
        return self.solution.success

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, STATUS_MESSAGES)

    def profile(self, num: int = 200) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The shape of the pillar in metres, from the base (0, 0) to the tip.

        Parameters
        ----------
        num : int
            Number of points along the pillar, equally spaced in arc length.

        Returns
        -------
        x, z : ndarray
            Horizontal position along +x [m] and height above the wall [m], of shape
            ``wall_shear_stress.shape + (num,)``.
        """
        num = check_int(num, "num", 2, 10**7)
        _, x, z, _ = self.solution.shape(np.linspace(0.0, 1.0, num))
        scale: Any = self.pillar.length
        if isinstance(scale, np.ndarray):  # an array pillar: its shape broadcasts the states'
            scale = scale[..., np.newaxis]
        return scale * np.asarray(x), scale * np.asarray(z)


class _ChebyshevProfile:
    """A dimensionless profile U(z), z in [0, 1], given by Chebyshev coefficients in 2 z - 1
    (what the core resolves a callable into; passing it on re-resolves it exactly)."""

    def __init__(self, coefs: FloatArray) -> None:
        self.coefs = coefs

    def __call__(self, z: FloatArray) -> FloatArray:
        return np.asarray(
            np.polynomial.chebyshev.chebval(2.0 * np.asarray(z) - 1.0, self.coefs),
            dtype=np.float64,
        )


def _merged(
    shape: tuple[int, ...],
    flat: FloatArray,
    solve: Callable[[NDArray[np.intp], FloatArray], Any],
    prof: FloatArray,
) -> Any:
    """One PillarState of ``shape`` from the solves ``solve(indices, profile row)`` of the
    flat elements that share each distinct profile row of ``prof`` (the core takes one
    profile a call where it walks a branch)."""
    _, inv = np.unique(prof, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    size = flat.size
    merged: dict[str, Any] = {}
    for g in range(int(inv.max()) + 1 if size else 0):
        sel = np.flatnonzero(inv == g)
        part = solve(sel, row_groups(prof[sel[:1]])[0][1])
        for f in dataclasses.fields(part):
            if f.name == "stable" or getattr(part, f.name) is None:
                continue
            value = np.asarray(getattr(part, f.name))
            if f.name == "_coefs":
                value = value.reshape(3, sel.size, value.shape[-1])
                if f.name not in merged:
                    merged[f.name] = np.full((3, size, value.shape[-1]), np.nan)
                merged[f.name][:, sel, :] = value
                continue
            value = value.reshape(sel.size)
            if f.name not in merged:
                merged[f.name] = np.zeros(size, dtype=value.dtype)
            merged[f.name][sel] = value
    if not merged:  # an empty input: the core's own empty state
        return solve(np.zeros(0, dtype=np.intp), np.ascontiguousarray(prof[:1]))
    fields = {}
    for name, value in merged.items():
        if name == "_coefs":
            fields[name] = value.reshape((3, *shape, value.shape[-1]))
        elif name == "_map":
            fields[name] = value.reshape(shape)
        else:
            fields[name] = scalar_or_array(value.reshape(shape))
    return PillarState(**fields)


#: The kernel's columns of a PillarState's fields (``_core.pillar._pillar_state``).
_COLUMNS = {
    "status": 0,
    "nit": 1,
    "num": 2,
    "tip_height": 4,
    "tip_deflection": 5,
    "tip_angle": 6,
    "base_curvature": 7,
    "drag_x": 8,
    "drag_z": 9,
    "error_estimate": 10,
    "residual": 11,
    "forcing": 12,
    "tip_deflection_slope": 13,
}


def _raw(state: Any) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A PillarState back as the kernel's flat (out, coefs, a), to start from it."""
    size = int(np.prod(state.shape_of_fields, dtype=np.int64))
    out = np.zeros((_kernels().NCOLS, size))
    for name, col in _COLUMNS.items():
        out[col] = np.asarray(getattr(state, name), dtype=np.float64).reshape(-1)
    raw = np.asarray(state._coefs, dtype=np.float64)
    coefs = np.array(raw.reshape(3, size, raw.shape[-1]))
    return out, coefs, np.array(np.asarray(state._map, dtype=np.float64).reshape(-1))


#: The wall-law profiles a Pillar keeps (by L+), so that a state and its sensitivity, or an
#: inverse's last steps, compute each profile once.
_ROWS_CACHED = 4096


def _trimmed(prof: FloatArray) -> list[tuple[int, FloatArray]]:
    """Each row of zero-padded coefficients without its trailing zeros (at least one)."""
    out = []
    for i, row in enumerate(prof):
        keep = np.flatnonzero(row)
        out.append((i, row[: (int(keep[-1]) + 1 if keep.size else 1)].copy()))
    return out


#: Newton steps of the wall-law inverse in the stress, and its relative step tolerance.
_WALL_NEWTON = 40
_WALL_XTOL = 1e-13


@dataclass(frozen=True, eq=False)
class Pillar(_ArrayModel):
    """An isolated elastic pillar on the wall of a shear flow, in SI units (theory.md §12).

    Every SI parameter may be an array (issue 32): they broadcast together into
    :attr:`shape` and with the stresses of a call (numpy rules), each element checked on its
    own; :meth:`deform`, :meth:`tip_deflection`, :meth:`sensitivity`, the inverse and the
    linear calibration then solve every element in one compiled call (one per distinct
    profile where the elements' profiles differ), and :meth:`item` gives the scalar pillar of
    one element. Methods that need a pillar of numbers say so.

    Parameters
    ----------
    length : float or array_like
        Pillar length L [m].
    radius : float or array_like
        Pillar radius a [m] (the radius, not the diameter); the slenderness L/a must be at
        least :data:`MIN_SLENDERNESS` = e^1.5/2 (Gray & Hancock's ratio gamma <= 1), and below
        :data:`SLENDERNESS_LIMIT` a :class:`hairbed.ModelValidityWarning` is issued.
    youngs_modulus : float or array_like
        Young's modulus E of the pillar [Pa].
    viscosity : float or array_like, optional
        Dynamic viscosity eta of the fluid [Pa s]; required unless a ``fluid`` gives it.
    base_angle : float or array_like, optional
        Base angle theta0 from the wall normal towards +x [rad], in (-pi/2, pi/2); default 0.
    profile : {"sublayer", "couette", "poiseuille", "wall-law"} or callable, optional
        The undisturbed profile: the viscous sublayer u = tau_w z/eta (default), Couette or
        Poiseuille flow in a channel of height ``channel_height``, Spalding's law of the wall
        u = u_tau u+(z u_tau/nu) from the sublayer through the log region ("wall-law": needs
        the ``density``; theory.md §12, valid within the inner layer of a turbulent
        boundary layer, L+ up to 1e4, ``MAX_L_PLUS``), or a callable u(z) [m/s]
        of heights z [m] (an ndarray in [0, L]) giving the flow at a reference wall shear
        stress eta u'(0), which must not vanish; :meth:`deform` scales it to the stress asked
        for.
    channel_height : float or array_like, optional
        Channel height H [m] of the "couette" and "poiseuille" profiles (required there, not
        accepted otherwise); the pillar must fit, L <= H.
    density : float or array_like, optional
        Fluid density rho [kg/m^3]: the wall units of the "wall-law" profile, and the
        validity checks of every state (the pillar Reynolds number, the height in wall units
        L+). Without it (and without a ``fluid``) those checks are off, which the first SI
        state of the pillar says once (a :class:`hairbed.ModelValidityWarning`).
    drag_scale : float or array_like, optional
        A factor c > 0 on both drag coefficients [-] (default 1: Gray & Hancock's); what a
        calibration of the drag fits (``free=("drag_scale",)``).
    fluid : {"water", "glycerol", "air"}, optional
        A fluid preset at 20 C (:data:`FLUIDS`): its viscosity and density, unless
        ``viscosity`` or ``density`` is given too (then the value given is used).

    Examples
    --------
    >>> p = Pillar(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3)
    >>> st = p.deform(wall_shear_stress=1.0)  # [Pa]
    >>> round(st.tip_deflection * 1e6, 4), round(st.sensitivity * 1e6, 4)  # [um], [um/Pa]
    (27.8862, 27.6395)
    >>> round(p.wall_shear_stress_from_tip_deflection(st.tip_deflection), 12)  # [Pa]
    1.0
    >>> round(p.linear_range(0.01).wall_shear_stress, 4)  # the linear formula to 1 % [Pa]
    1.5087

    A 1 mm pillar in water stands about 30 wall units tall at 1 Pa, above the sublayer:

    >>> w = Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="water",
    ...            profile="wall-law")
    >>> st = w.deform(1.0)
    >>> round(st.height_in_wall_units, 2)  # L+ [-]
    31.54
    """

    length: float
    radius: float
    youngs_modulus: float
    viscosity: float = None  # type: ignore[assignment]  # or from ``fluid``
    base_angle: float = 0.0
    profile: Any = "sublayer"
    channel_height: float | None = None
    density: float | None = None
    drag_scale: float = 1.0
    fluid: str | None = None
    #: the dimensionless profile the core solves (built-in name or Chebyshev profile)
    _core_profile: Any = field(init=False, repr=False, compare=False)
    _core_options: Any = field(init=False, repr=False, compare=False)
    #: Lambda / tau_w [1/Pa] and u(tip)/(tau_w U(h1)) [m/(s Pa)]
    _per_stress: tuple[float, float] = field(init=False, repr=False, compare=False)
    #: whether the missing density has been told (once per pillar)
    _told: list[bool] = field(init=False, repr=False, compare=False)
    #: the wall-law profile's rows (U, L+ dU/dL+) of the L+ met so far
    _rows: dict[float, tuple[FloatArray, FloatArray]] = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "_told", [False])
        set_(self, "_rows", {})
        if self.fluid is not None:
            if not isinstance(self.fluid, str) or self.fluid not in FLUIDS:
                raise ValueError(
                    f"fluid must be one of {', '.join(map(repr, FLUIDS))} (at 20 C), got "
                    f"{show(self.fluid)}"
                )
            eta, rho = FLUIDS[self.fluid]
            if self.viscosity is None:
                set_(self, "viscosity", eta)
            if self.density is None:
                set_(self, "density", rho)
        if self.viscosity is None:
            raise TypeError(
                "Pillar() needs the viscosity [Pa s] of the fluid, or a fluid preset "
                f"(fluid= one of {', '.join(map(repr, FLUIDS))})"
            )
        if any(_is_array(getattr(self, n), n, u) for n, u in _PILLAR_UNITS):
            self._post_init_arrays()
            return
        for name, unit in (
            ("length", "m"),
            ("radius", "m"),
            ("youngs_modulus", "Pa"),
            ("viscosity", "Pa s"),
        ):
            set_(self, name, check_positive(getattr(self, name), name, unit))
        set_(
            self,
            "base_angle",
            check_number(
                self.base_angle,
                "base_angle",
                low=-HALF_PI,
                high=HALF_PI,
                low_open=True,
                high_open=True,
                unit="rad",
            ),
        )
        set_(self, "drag_scale", check_positive(self.drag_scale, "drag_scale"))
        if self.density is not None:
            set_(self, "density", check_positive(self.density, "density", "kg/m^3"))
        profile = self.profile
        channel = isinstance(profile, str) and profile in ("couette", "poiseuille")
        if not callable(profile) and not (isinstance(profile, str) and profile in PILLAR_PROFILES):
            raise ValueError(
                f"profile must be one of {', '.join(map(repr, PILLAR_PROFILES))} or a callable "
                f"u(z) [m/s] of z [m], got {show(profile)}"
            )
        if profile == "wall-law" and self.density is None:
            raise ValueError(
                "profile 'wall-law' needs the fluid's density [kg/m^3] for its wall units "
                "u_tau = sqrt(tau_w/rho), nu = eta/rho: give density= or fluid="
            )
        if channel:
            if self.channel_height is None:
                raise ValueError(f"profile {profile!r} needs channel_height H [m] (L <= H)")
            h = check_positive(self.channel_height, "channel_height", "m")
            set_(self, "channel_height", h)
            if self.length > h:
                raise ValueError(
                    f"length {self.length!r} m must not exceed channel_height {h!r} m: the "
                    "pillar must fit in its channel (L <= H)"
                )
        elif self.channel_height is not None:
            raise ValueError(
                "channel_height is used only by the 'couette' and 'poiseuille' profiles, got "
                f"{show(self.channel_height)} with profile {show(profile)}"
            )
        slenderness = self.length / self.radius
        if not math.isfinite(slenderness):
            raise ValueError(
                f"length {self.length!r} m over radius {self.radius!r} m overflows double "
                "precision (the slenderness L/a)"
            )
        # the core takes gamma in (0, 1]: Gray & Hancock's ratio passes 1 at L/a = e^1.5/2
        if not slenderness >= MIN_SLENDERNESS:
            raise ValueError(
                f"radius {self.radius!r} m: the slenderness length/radius must be at least "
                f"e^1.5/2 = {MIN_SLENDERNESS:.4f} (Gray & Hancock's ratio zeta_par/zeta_perp "
                f"<= 1), got {slenderness!r}"
            )
        self._derive()
        _warn_implausible(self, "Pillar")
        if slenderness < SLENDERNESS_LIMIT:
            warnings.warn(
                f"the pillar's slenderness L/a = {slenderness:.3g} is below "
                f"{SLENDERNESS_LIMIT:g}: slender-body (resistive-force) drag is out of its "
                "range (theory.md §12)",
                ModelValidityWarning,
                stacklevel=3,
            )

    def _derive(self, resolved: tuple[Any, float] | None = None) -> None:
        """Set the core's profile and options and the scales per stress of a checked pillar
        of numbers (``resolved``: a callable profile's (U, speed) already resolved), or a
        ValueError where they under- or overflow."""
        set_ = object.__setattr__
        profile = self.profile
        with np.errstate(all="ignore"):  # numpy floats: inf or 0 on overflow, checked below
            length, radius = np.float64(self.length), np.float64(self.radius)
            per_stress = float(
                self.normal_drag_coefficient
                * (length / radius) ** 4
                / (self.viscosity * self.youngs_modulus * np.pi / 4.0)
            )
            speed = float(length / np.float64(self.viscosity))  # u(tip) = tau_w L U(h1)/eta
        core: Any = "sublayer" if profile == "wall-law" else profile
        if callable(profile):
            core, speed = self._callable_profile(profile) if resolved is None else resolved
        if not (math.isfinite(per_stress) and per_stress > 0.0 and math.isfinite(speed)):
            raise ValueError(
                "length, radius, youngs_modulus, viscosity and drag_scale give a forcing per "
                f"unit stress zeta_perp L^4/(eta E I) = {per_stress!r} 1/Pa (or a speed scale "
                "L/eta) that under- or overflows double precision"
            )
        set_(self, "_core_profile", core)
        # the core's checked keywords (solve_pillar's defaults), once: the solves trust them
        set_(self, "_core_options", _options(core, self.height_ratio, 1e-12, None))
        set_(self, "_per_stress", (per_stress, speed))

    # -- array-valued pillars (issue 32) -------------------------------------------------------

    def _post_init_arrays(self) -> None:
        """:meth:`__post_init__` of a pillar with array parameters: each checked element by
        element (the first offending index named), the shapes broadcast, the scales computed
        element by element by the scalar pillar's own code."""
        set_ = object.__setattr__

        def checked(name: str, unit: str, **kw: Any) -> Any:
            value = getattr(self, name)
            if _is_array(value, name, unit):
                return _array_parameter(value, name, unit, **kw)
            if "shown" in kw:
                return check_number(value, name, low=-HALF_PI, high=HALF_PI, low_open=True,
                                    high_open=True, unit=unit)  # fmt: skip
            return check_positive(value, name, unit)

        for name, unit in _PILLAR_UNITS[:4]:
            set_(self, name, checked(name, unit))
        set_(self, "base_angle", checked("base_angle", "rad", low=-HALF_PI, high=HALF_PI,
                                         shown="(-pi/2, pi/2)"))  # fmt: skip
        set_(self, "drag_scale", checked("drag_scale", ""))
        if self.density is not None:
            set_(self, "density", checked("density", "kg/m^3"))
        profile = self.profile
        channel = isinstance(profile, str) and profile in ("couette", "poiseuille")
        if not callable(profile) and not (isinstance(profile, str) and profile in PILLAR_PROFILES):
            raise ValueError(
                f"profile must be one of {', '.join(map(repr, PILLAR_PROFILES))} or a callable "
                f"u(z) [m/s] of z [m], got {show(profile)}"
            )
        if profile == "wall-law" and self.density is None:
            raise ValueError(
                "profile 'wall-law' needs the fluid's density [kg/m^3] for its wall units "
                "u_tau = sqrt(tau_w/rho), nu = eta/rho: give density= or fluid="
            )
        if channel:
            if self.channel_height is None:
                raise ValueError(f"profile {profile!r} needs channel_height H [m] (L <= H)")
            set_(self, "channel_height", checked("channel_height", "m"))
        elif self.channel_height is not None:
            raise ValueError(
                "channel_height is used only by the 'couette' and 'poiseuille' profiles, got "
                f"{show(self.channel_height)} with profile {show(profile)}"
            )
        shape = _shape_of(self, _PILLAR_NAMES, "Pillar")
        self.__dict__["_shape"] = shape
        if callable(profile) and (np.ndim(self.length) or np.ndim(self.viscosity)):
            raise ValueError(
                "a callable profile u(z) [m/s] needs a single length and viscosity (its "
                "dimensionless shape depends on them): give them as numbers"
            )
        length, radius = self.length, self.radius
        if channel:
            bad = ~np.asarray(length <= cast(Any, self.channel_height))
            if np.any(bad):
                raise ValueError(
                    f"length {_at(length, bad)!r} m must not exceed channel_height "
                    f"{_at(self.channel_height, bad)!r} m{_first_index(bad)}: the pillar must "
                    "fit in its channel (L <= H)"
                )
        with np.errstate(all="ignore"):
            slenderness = np.broadcast_to(np.asarray(length / radius), shape)
        bad = ~np.isfinite(slenderness)
        if np.any(bad):
            raise ValueError(
                f"length {_at(length, bad)!r} m over radius {_at(radius, bad)!r} m"
                f"{_first_index(bad)} overflows double precision (the slenderness L/a)"
            )
        bad = ~(slenderness >= MIN_SLENDERNESS)
        if np.any(bad):
            raise ValueError(
                f"radius {_at(radius, bad)!r} m{_first_index(bad)}: the slenderness "
                f"length/radius must be at least e^1.5/2 = {MIN_SLENDERNESS:.4f} (Gray & "
                f"Hancock's ratio zeta_par/zeta_perp <= 1), got {_at(slenderness, bad)!r}"
            )
        resolved = None
        if callable(profile):  # the same for every element: resolved once
            resolved = self._callable_profile(profile)
        elements = list(self._elements())
        failed = np.zeros(len(elements), dtype=bool)
        for i, el in enumerate(elements):
            try:
                el._derive(resolved)
            except ValueError:
                failed[i] = True
        if np.any(failed):
            bad = failed.reshape(shape)
            raise ValueError(
                "length, radius, youngs_modulus, viscosity and drag_scale give a forcing per "
                f"unit stress zeta_perp L^4/(eta E I) (or a speed scale L/eta) that under- or "
                f"overflows double precision{_first_index(bad)}"
            )
        first = elements[0]
        varying = profile == "poiseuille" and np.ndim(cast(Any, self.height_ratio)) > 0
        set_(self, "_core_profile", first._core_profile)
        set_(self, "_core_options", None if varying else first._core_options)
        per = np.array([el._per_stress for el in elements], dtype=np.float64)
        set_(self, "_per_stress", tuple(_frozen(per[:, k].reshape(shape)) for k in (0, 1)))
        self.__dict__["_elements_cache"] = elements
        self.__dict__["_derived"] = {}
        _warn_implausible(self, "Pillar")
        low = slenderness < SLENDERNESS_LIMIT
        if np.any(low):
            warnings.warn(
                f"the pillar's slenderness L/a = {_at(slenderness, low):.3g}{_first_index(low)} "
                f"is below {SLENDERNESS_LIMIT:g}: slender-body (resistive-force) drag is out of "
                "its range (theory.md §12)",
                ModelValidityWarning,
                stacklevel=3,
            )

    @property
    def shape(self) -> tuple[int, ...]:
        """The broadcast shape of the pillar's parameters: () for a pillar of numbers, else
        that of its array parameters (numpy rules); results of its methods broadcast it with
        their own array arguments (issue 32)."""
        return cast("tuple[int, ...]", self.__dict__.get("_shape", ()))

    def item(self, index: Any = ()) -> Pillar:
        """The pillar of numbers at ``index`` of :attr:`shape` (a pillar of numbers is its
        own item)."""
        shape = self.shape
        flat = _flat_index(index, shape, "pillar")
        if not shape:
            return self
        kwargs: dict[str, Any] = {}
        for name in _PILLAR_NAMES:
            value = getattr(self, name)
            if isinstance(value, np.ndarray):
                value = float(np.broadcast_to(value, shape).reshape(-1)[flat])
            kwargs[name] = value
        return Pillar(**kwargs, profile=self.profile)

    def _elements(self) -> Any:
        """The pillars of numbers of every element (C order), trusted and without their
        scales (:meth:`_derive`): the array pillar was checked."""
        cached = self.__dict__.get("_elements_cache")
        if cached is not None:
            yield from cached
            return
        shared = {"profile": self.profile, "fluid": self.fluid, "_told": self._told,
                  "_rows": self._rows}  # fmt: skip
        yield from self._bare_elements(Pillar, _PILLAR_NAMES, self.shape, shared)

    def _derived_value(self, name: str) -> Any:
        """An array pillar's derived quantity ``name``, each element's own (cached)."""
        cache = self.__dict__["_derived"]
        if name not in cache:
            values = np.array([getattr(el, name) for el in self._elements()], dtype=np.float64)
            cache[name] = _frozen(values.reshape(self.shape))
        return cache[name]

    def _require_scalar(self, what: str) -> None:
        """A ValueError where ``what`` is asked of an array-valued pillar, which it does not
        support: naming the array parameters and saying that numbers are needed."""
        if not self.shape:
            return
        names = _array_names(self, _PILLAR_NAMES)
        verb = "is an array" if len(names) == 1 else "are arrays"
        raise ValueError(
            f"{what} needs a single pillar, each parameter a number: {', '.join(names)} "
            f"{verb} (shape {self.shape}) here. Pillar.deform, tip_deflection, sensitivity, "
            "the inverse, the linear calibration, frequency_response and simulate take array "
            "parameters; "
            "Pillar.item(index) gives one pillar of the array"
        )

    def _broadcast_input(self, x: FloatArray, name: str) -> FloatArray:
        """An input array broadcast with the pillar's parameters (a copy), or a ValueError."""
        if not self.shape:
            return x
        try:
            shape = np.broadcast_shapes(x.shape, self.shape)
        except ValueError:
            raise ValueError(
                f"{name} of shape {x.shape} must broadcast with the pillar's array parameters "
                f"of shape {self.shape} (numpy rules)"
            ) from None
        return np.array(np.broadcast_to(x, shape))

    def _flat(self, x: Any, shape: tuple[int, ...]) -> FloatArray:
        """A parameter (number or array) broadcast to ``shape`` and flattened."""
        return np.broadcast_to(np.asarray(x, dtype=np.float64), shape).reshape(-1)

    def _profile_rows(self, shape: tuple[int, ...]) -> FloatArray:
        """The core profile's Chebyshev row of every element of ``shape`` (flat): one row
        unless the profile varies between the elements ("poiseuille" with an array L/H)."""
        if self._core_options is not None:
            return np.asarray(self._core_options[0])
        ratio = self._flat(self.height_ratio, shape)
        return np.array([profile_coefficients(self._core_profile, r) for r in ratio.tolist()])

    def _callable_profile(self, func: Callable[..., Any]) -> tuple[Any, float]:
        """(dimensionless profile U, u(tip)/(tau_w U(h1)) [m/(s Pa)]) of a callable u(z)."""
        length = self.length

        def checked(z: FloatArray) -> FloatArray:  # the user's u(z) of z [m], checked in SI
            zm = np.asarray(z) * length
            try:
                raw = func(zm)
            except Exception as exc:  # the user's function: say whose error it is
                raise ValueError(
                    f"profile: the callable raised {type(exc).__name__}: {exc} (it is called "
                    "with an ndarray of heights z in [0, length] [m])"
                ) from exc
            vals = real_values(raw, "profile: the callable", "real speeds [m/s]")
            if vals.shape != zm.shape:
                raise ValueError(
                    f"profile: the callable must return an array of the shape of z "
                    f"{zm.shape}, got shape {vals.shape}"
                )
            bad = ~np.isfinite(vals)
            if np.any(bad):
                i = int(np.flatnonzero(bad)[0])
                raise ValueError(
                    f"profile: the callable returned {float(vals[i])!r} m/s at z = "
                    f"{float(zm[i])!r} m (index {i}); it must be finite on [0, length]"
                )
            return vals

        coefs = _callable_coefficients(checked)  # [m/s]
        slope = 2.0 * float(
            np.polynomial.chebyshev.chebval(-1.0, np.polynomial.chebyshev.chebder(coefs))
        )  # du/d(z/L) at the wall [m/s]
        big = float(np.max(np.abs(coefs)))
        if not abs(slope) > 1e-12 * big:
            raise ValueError(
                "profile: the callable's wall shear stress eta u'(0) is zero (or not resolved); "
                "a callable profile is scaled by its wall shear stress, which must not vanish"
            )
        tau_ref = self.viscosity * slope / length
        # U(z) = u(z L) eta/(tau_ref L): U'(0) = 1 as for the built-in profiles
        return _ChebyshevProfile(coefs / slope), slope / tau_ref

    # -- derived quantities ---------------------------------------------------------------------

    @property
    def bending_stiffness(self) -> float:
        """E I = E pi a^4/4 [N m^2]."""
        if "_derived" in self.__dict__:  # an array pillar: element by element
            return cast(Any, self._derived_value("bending_stiffness"))
        with np.errstate(over="ignore"):  # inf rather than an OverflowError
            return float(self.youngs_modulus * (np.pi / 4.0) * np.float64(self.radius) ** 4)

    @property
    def slenderness(self) -> float:
        """L/a [-]."""
        if "_derived" in self.__dict__:  # an array pillar: element by element
            return cast(Any, self._derived_value("slenderness"))
        return self.length / self.radius

    @property
    def drag_ratio(self) -> float:
        """gamma = zeta_par/zeta_perp of Gray & Hancock's coefficients [-]
        (:func:`hairbed.gray_hancock_ratio`)."""
        if "_derived" in self.__dict__:  # an array pillar: element by element
            return cast(Any, self._derived_value("drag_ratio"))
        return float(gray_hancock_ratio(self.slenderness))

    @property
    def normal_drag_coefficient(self) -> float:
        """zeta_perp = c 4 pi eta/(ln(2L/a) + 1/2) [Pa s], c = :attr:`drag_scale`."""
        if "_derived" in self.__dict__:  # an array pillar: element by element
            return cast(Any, self._derived_value("normal_drag_coefficient"))
        return (
            self.drag_scale
            * 4.0
            * math.pi
            * self.viscosity
            / (math.log(2.0 * self.slenderness) + 0.5)
        )

    @property
    def height_ratio(self) -> float | None:
        """L/H of a channel profile [-]; None otherwise."""
        if "_derived" in self.__dict__ and self.channel_height is not None:
            return cast(Any, self._derived_value("height_ratio"))
        return None if self.channel_height is None else self.length / self.channel_height

    @property
    def forcing_per_stress(self) -> float:
        """Lambda/tau_w = zeta_perp L^4/(eta E I) [1/Pa]."""
        return self._per_stress[0]

    @property
    def linear_coefficient(self) -> float:
        """c1 of the linear formula x1 = sin(theta0) + c1 Lambda [-] (theory.md §12).

        c1 = cos^2(theta0) int_0^1 U(s cos theta0) s^2 (3 - s)/6 ds: 11 cos^3(theta0)/120 for
        the sublayer and Couette, (33 - 26 L/H)/360 for Poiseuille at theta0 = 0, and for the
        "wall-law" profile the sublayer's, its limit as L+ -> 0 (the shape of its profile
        changes with the stress; :meth:`linear_range` says how far the formula holds).
        """
        if "_derived" in self.__dict__:  # an array pillar: element by element
            return cast(Any, self._derived_value("linear_coefficient"))
        c = math.cos(self.base_angle)
        xg, wg = _GAUSS
        s = 0.5 * (xg + 1.0)
        u = self._profile_values(s * c)
        return float(c * c * np.sum(0.5 * wg * u * s * s * (3.0 - s) / 6.0))

    def _profile_values(self, z: FloatArray) -> FloatArray:
        """The dimensionless profile U at heights z [L]."""
        core = self._core_profile
        if callable(core):
            return np.asarray(core(z), dtype=np.float64)
        if self._core_options is None:  # each element its own profile (of z's shape)
            shape = np.shape(z)
            rows = self._profile_rows(shape)
            t = 2.0 * np.asarray(z, dtype=np.float64).reshape(-1) - 1.0
            values = np.polynomial.chebyshev.chebval(t, rows.T, tensor=False)
            return np.asarray(values, dtype=np.float64).reshape(shape)
        if self.shape:  # one profile for every element: the core's row
            coefs = np.asarray(self._core_options[0])[0]
        else:
            coefs = profile_coefficients(core, self.height_ratio)
        return np.asarray(np.polynomial.chebyshev.chebval(2.0 * z - 1.0, coefs))

    # -- the forward problem ----------------------------------------------------------------------

    def _stress(self, wall_shear_stress: Any, velocity: Any, pressure_gradient: Any) -> FloatArray:
        """The wall shear stress [Pa] of exactly one of the three drives, checked."""
        given = [
            (n, v)
            for n, v in (
                ("wall_shear_stress", wall_shear_stress),
                ("velocity", velocity),
                ("pressure_gradient", pressure_gradient),
            )
            if v is not None
        ]
        if len(given) != 1:
            raise TypeError(
                "deform() needs exactly one of wall_shear_stress [Pa], velocity [m/s] (a "
                "'couette' pillar) and pressure_gradient [Pa/m] (a 'poiseuille' pillar), got "
                + (", ".join(n for n, _ in given) or "none")
            )
        name, value = given[0]
        if name == "wall_shear_stress":
            return self._broadcast_input(as_float_array(value, name, unit="Pa"), name)
        needs = "couette" if name == "velocity" else "poiseuille"
        if self.profile != needs:
            raise ValueError(
                f"{name} drives a {needs!r} channel; this pillar's profile is "
                f"{show(self.profile)}: give wall_shear_stress [Pa]"
            )
        h: Any = self.channel_height
        h = float(h) if not self.shape else h
        if name == "velocity":  # tau_w = eta V/H
            v = self._broadcast_input(as_float_array(value, name, unit="m/s"), name)
            return v * (self.viscosity / h)
        g = self._broadcast_input(as_float_array(value, name, unit="Pa/m"), name)
        return g * (0.5 * h)  # tau_w = G H/2

    def _forcing(self, tau: FloatArray) -> FloatArray:
        with np.errstate(over="ignore"):
            lam = tau * self.forcing_per_stress
        bad = ~np.isfinite(lam)
        if np.any(bad):
            raise ValueError(
                f"wall_shear_stress must be below "
                f"{np.finfo(np.float64).max / _at(self.forcing_per_stress, bad):.3g} Pa in "
                "magnitude for "
                f"this pillar (its forcing overflows), got {float(tau[bad].flat[0])!r}"
                f"{_first_index(bad)}"
            )
        return lam

    def _options_of(self) -> Any:
        """The core's options (profile row, tolerance, ladder); an array pillar whose
        profile varies between elements gives the first element's row (replaced per group)."""
        if self._core_options is not None:
            return self._core_options
        return next(iter(self._elements()))._core_options

    def _solve(self, lam: FloatArray) -> Any:
        """The dimensionless states at forcings ``lam`` (checked, finite)."""
        t0, g, tip = self._checked_like(lam)
        varying = self._core_options is None
        if (self.profile != "wall-law" and not varying) or np.size(lam) == 0:
            return _solve_pillar_checked(lam, t0, g, tip, *self._options_of())
        # the profile of each stress (or element): one solve per distinct profile
        _, tol, nums = self._options_of()
        flat = np.asarray(lam, dtype=np.float64).reshape(-1)
        if varying:  # "poiseuille" with an array L/H
            prof = self._profile_rows(np.shape(lam))
        else:  # tau_w = Lambda/(Lambda/tau_w)
            prof, _ = self._wall_rows(np.asarray(lam) / self.forcing_per_stress)
        return _merged(
            np.shape(lam),
            flat,
            lambda sel, row: _solve_pillar_checked(
                flat[sel],
                t0.reshape(-1)[sel],
                g.reshape(-1)[sel],
                tip.reshape(-1)[sel],
                row,
                tol,
                nums,
            ),
            prof,
        )

    # -- the law of the wall ----------------------------------------------------------------------

    def _l_plus(self, tau: FloatArray) -> FloatArray:
        """L+ = L sqrt(abs(tau_w)/rho)/nu [-] at stresses ``tau`` [Pa]; NaN without a density."""
        if self.density is None:
            return np.full(np.shape(tau), np.nan)
        rho = self.density
        with np.errstate(over="ignore", invalid="ignore"):
            return np.asarray(
                self.length * np.sqrt(np.abs(tau) / rho) * rho / self.viscosity, dtype=np.float64
            )

    def _wall_rows(self, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The wall-law profile's Chebyshev rows U and L+ dU/dL+ at flat stresses ``tau``
        [Pa] (:func:`hairbed._core.wall_law.wall_law_coefficients`); a ValueError naming the
        stress where L+ exceeds :data:`MAX_L_PLUS`."""
        lp = self._l_plus(tau)
        lp = np.where(np.isnan(lp), 0.0, lp)  # no state there (NaN stays NaN): any profile
        bad = ~(lp <= MAX_L_PLUS)
        if np.any(bad):
            with np.errstate(all="ignore"):
                limit = _at(
                    MAX_L_PLUS * self.viscosity / (self.length * np.sqrt(cast(Any, self.density))),
                    bad,
                )
            raise ValueError(
                f"wall_shear_stress {float(tau[bad].flat[0])!r} Pa{_first_index(bad)} puts "
                f"the pillar {float(lp[bad].flat[0]):.4g} wall units tall, above "
                f"L+ = {MAX_L_PLUS:g}, the tallest the 'wall-law' profile resolves: the "
                f"stress must stay below {limit * limit:.4g} Pa in magnitude"
            )
        uniq, inv = np.unique(lp.reshape(-1), return_inverse=True)
        cache = self._rows  # read and written whole entries: safe from several threads
        found = {v: hit for v in uniq.tolist() if (hit := cache.get(v)) is not None}
        new = [v for v in uniq.tolist() if v not in found]
        if new:
            prof, dprof = wall_law_coefficients(np.array(new))
            for v, (_, row), (_, drow) in zip(new, _trimmed(prof), _trimmed(dprof)):
                found[v] = (row, drow)
            if len(cache) + len(new) > _ROWS_CACHED:
                cache.clear()
            cache.update({v: found[v] for v in new})
        rows = [found[v] for v in uniq.tolist()]
        width = max(max(r.size, d.size) for r, d in rows) if rows else 2
        prof = np.zeros((uniq.size, width))
        dprof = np.zeros((uniq.size, width))
        for i, (r, d) in enumerate(rows):
            prof[i, : r.size] = r
            dprof[i, : d.size] = d
        return prof[inv.reshape(-1)], dprof[inv.reshape(-1)]

    def _stress_slope(self, tau: FloatArray, sol: Any) -> FloatArray:
        """dx1/dtau_w [1/Pa] of the states ``sol`` at stresses ``tau`` [Pa] (their shape):
        dx1/dLambda Lambda/tau_w, plus the profile's part for the "wall-law" profile."""
        if self.profile == "wall-law":
            return self._wall_slope(np.asarray(tau, dtype=np.float64), sol).reshape(np.shape(tau))
        return np.asarray(sol.tip_deflection_slope) * self.forcing_per_stress

    def _tip_derivatives(self, tau: FloatArray, sol: Any) -> dict[str, FloatArray]:
        """dx1/d(forcing, theta0, gamma, height_ratio, log_l_plus) (flat) of states ``sol`` at
        stresses ``tau`` [Pa], exact (implicit differentiation of the collocation, each state
        with its own profile); "log_l_plus" is d/d ln L+ at fixed Lambda (0 unless the profile
        is "wall-law"), for a calibration that frees the length."""
        flat = np.asarray(tau, dtype=np.float64).reshape(-1)
        if self.profile == "wall-law":
            prof, dprof = self._wall_rows(flat)
        else:
            prof = np.asarray(self._core_options[0])
            dp = _profile_derivative(self._core_profile, self.height_ratio)
            dprof = np.zeros((1, 1)) if dp is None else dp[None, :]
        self._require_scalar("the derivatives of a pillar's state in its parameters")
        with np.errstate(all="ignore"):
            out, _, _ = pillar_gradient_rows(sol, prof, dprof)
        x1 = out[1]
        wall = self.profile == "wall-law"
        return {
            "forcing": x1[0],
            "theta0": x1[1],
            "gamma": x1[2],
            "height_ratio": np.zeros(flat.size) if wall else x1[3],
            "log_l_plus": x1[3] if wall else np.zeros(flat.size),
        }

    def _wall_slope(self, tau: FloatArray, sol: Any) -> FloatArray:
        """d(x1)/d(tau_w) [1/Pa] of wall-law states ``sol`` at stresses ``tau`` (flat):
        through Lambda ~ tau_w and through the profile's L+ ~ sqrt(tau_w),

            dx1/dtau_w = x1_Lambda Lambda/tau_w + x1_q/(2 tau_w),   q = ln L+,

        both derivatives exact (:func:`hairbed._core.pillar_sensitivity.pillar_gradient_rows` with
        dU/dq = z U' - U); x1_q/tau_w -> 0 as tau_w -> 0 (the sublayer)."""
        prof, dprof = self._wall_rows(tau)
        out, _, _ = pillar_gradient_rows(sol, prof, dprof)
        x1_lam, x1_q = out[1, 0], out[1, 3]
        flat = np.asarray(tau, dtype=np.float64).reshape(-1)
        fps = self._flat(self.forcing_per_stress, np.shape(tau)) if self.shape else (
            self.forcing_per_stress
        )  # fmt: skip
        with np.errstate(divide="ignore", invalid="ignore"):
            shape_part = np.where(flat != 0.0, x1_q / (2.0 * flat), 0.0)
        return np.asarray(x1_lam * fps + shape_part, dtype=np.float64)

    def _checked_like(self, a: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """theta0, gamma and the tip load (none) at the shape of checked inputs ``a``."""
        shape = np.shape(a)
        return (
            np.array(np.broadcast_to(self.base_angle, shape), dtype=np.float64),
            np.array(np.broadcast_to(self.drag_ratio, shape), dtype=np.float64),
            np.zeros(shape),
        )

    def deform(
        self,
        wall_shear_stress: Any = None,
        *,
        velocity: Any = None,
        pressure_gradient: Any = None,
    ) -> PillarDeformation:
        """The pillar's state in a flow, in SI (vectorised).

        Parameters
        ----------
        wall_shear_stress : array_like, optional
            The wall shear stress tau_w [Pa] (negative: flow towards -x).
        velocity : array_like, optional
            Instead, the moving wall's speed V [m/s] of a "couette" pillar (tau_w = eta V/H).
        pressure_gradient : array_like, optional
            Instead, G = -dp/dx [Pa/m] of a "poiseuille" pillar (tau_w = G H/2).

        Returns
        -------
        PillarDeformation
            Inside a snap-through window (``n_states`` 3) the state a slow ramp of the flow
            from rest reaches; :func:`hairbed.solve_pillar_all` at its ``forcing`` gives all.
        """
        tau = self._stress(wall_shear_stress, velocity, pressure_gradient)
        lam = self._forcing(tau)
        return self._state(tau, lam, self._solve(lam))

    def _state(
        self, tau: FloatArray, lam: FloatArray, sol: Any, tell: bool = True
    ) -> PillarDeformation:
        """The SI view of the dimensionless states ``sol`` at stresses ``tau`` [Pa]; without a
        density the first (with ``tell``) says once that the validity checks are off."""
        length, ei = self.length, self.bending_stiffness
        x1 = np.asarray(sol.tip_deflection, dtype=np.float64)
        h1 = np.asarray(sol.tip_height, dtype=np.float64)
        nan = np.full(np.shape(x1), np.nan)
        h = self.channel_height
        l_plus = self._l_plus(tau)
        wall = self.profile == "wall-law"
        slope = self._stress_slope(tau, sol)
        if self.density is None:
            reynolds = nan
            if tell and not self._told[0]:
                self._told[0] = True
                warnings.warn(
                    "this pillar has no density: the checks of the model's validity (the "
                    "pillar Reynolds number, the height in wall units L+) are off; give "
                    f"density= [kg/m^3] or fluid= (one of {', '.join(map(repr, FLUIDS))})",
                    ModelValidityWarning,
                    stacklevel=3,
                )
        else:
            with np.errstate(invalid="ignore"):
                hz = np.clip(h1, 0.0, 1.0)
                if wall:  # u(tip) = sign(tau) u_tau u+(h1 L+)
                    rho = self.density
                    y = np.where(np.isfinite(hz * l_plus), hz * l_plus, 0.0).reshape(-1)
                    u_tip = np.where(
                        np.isfinite(hz),
                        np.sign(tau)
                        * np.sqrt(np.abs(tau) / rho)
                        * _u_plus(y, WALL_LAW_KAPPA, WALL_LAW_B).reshape(np.shape(hz)),
                        np.nan,
                    )
                else:
                    u_tip = tau * self._per_stress[1] * self._profile_values(hz)
            reynolds = self.density * np.abs(u_tip) * 2.0 * self.radius / self.viscosity
            high = reynolds > PILLAR_REYNOLDS_LIMIT
            if np.any(high):
                warnings.warn(
                    f"pillar Reynolds number {float(np.max(reynolds[high])):.3g} > "
                    f"{PILLAR_REYNOLDS_LIMIT:g}: the Stokes (resistive-force) drag of the model "
                    "is out of its range (theory.md §12)",
                    ModelValidityWarning,
                    stacklevel=3,
                )
            high = l_plus > SUBLAYER_L_PLUS_LIMIT
            if self.profile == "sublayer" and np.any(high):
                warnings.warn(
                    f"the pillar stands L+ = {float(np.max(l_plus[high])):.3g} wall units "
                    f"tall, above the viscous sublayer (L+ ~ {SUBLAYER_L_PLUS_LIMIT:g}) that "
                    "its 'sublayer' profile assumes: use profile='wall-law' (Spalding's law "
                    "of the wall, theory.md §12)",
                    ModelValidityWarning,
                    stacklevel=3,
                )
        return PillarDeformation(
            pillar=self,
            wall_shear_stress=float_or_array(tau),
            velocity=float_or_array(
                tau * (h / self.viscosity) if self.profile == "couette" and h is not None else nan
            ),
            pressure_gradient=float_or_array(
                2.0 * tau / h if self.profile == "poiseuille" and h is not None else nan
            ),
            forcing=float_or_array(lam),
            solution=sol,
            tip_deflection=float_or_array(length * x1),
            tip_height=float_or_array(length * h1),
            tip_angle=float_or_array(sol.tip_angle),
            tip_displacement=float_or_array(length * (x1 - _sin(self.base_angle))),
            base_moment=float_or_array(ei * np.asarray(sol.base_curvature) / length),
            drag=float_or_array(ei * np.asarray(sol.drag_x) / length / length),
            drag_wall_normal=float_or_array(ei * np.asarray(sol.drag_z) / length / length),
            sensitivity=float_or_array(length * slope),
            reynolds_number=float_or_array(reynolds),
            status=sol.status,
            height_in_wall_units=float_or_array(l_plus),
            n_states=sol.n_states,
        )

    def _solved(self, wall_shear_stress: Any) -> PillarDeformation:
        """:meth:`deform` at stresses, or a ValueError where no state was found (a bare
        number cannot carry a status)."""
        st = self.deform(wall_shear_stress)
        status = np.asarray(st.status)
        bad = status < 0
        if np.any(bad):
            tau = np.asarray(st.wall_shear_stress)
            raise ValueError(
                f"wall_shear_stress {float(tau[bad].flat[0])!r} Pa{_first_index(bad)}: no state "
                f"found ({STATUS_MESSAGES[int(status[bad].flat[0])]}); deform() returns the "
                "status"
            )
        return st

    def tip_deflection(self, wall_shear_stress: Any) -> FloatOrArray:
        """The tip deflection x1 L [m] at wall shear stresses tau_w [Pa] (the calibration
        curve); a ValueError where no state is found (:meth:`deform` gives the status)."""
        return self._solved(wall_shear_stress).tip_deflection

    def sensitivity(self, wall_shear_stress: Any) -> FloatOrArray:
        """d(tip deflection)/d(tau_w) [m/Pa] at wall shear stresses tau_w [Pa], exact.

        L (dx1/dLambda) Lambda/tau_w, dx1/dLambda by implicit differentiation of the
        collocation system (:attr:`PillarState.tip_deflection_slope`); NaN at a fold; a
        ValueError where no state is found.
        """
        return self._solved(wall_shear_stress).sensitivity

    # -- the inverse: the calibration curve read backwards -------------------------------------

    def _deflection(self, deflection: Any, name: str = "tip_deflection") -> FloatArray:
        """A tip deflection [m] (pint quantities converted) in (-length, length)."""
        if self.shape and (self.profile == "wall-law" or self._core_options is None):
            self._require_scalar(
                f"the inverse of a {self.profile!r} pillar (its profile varies per element)"
            )
        d = self._broadcast_input(as_float_array(deflection, name, unit="m"), name)
        with np.errstate(over="ignore"):
            bad = np.asarray(np.abs(d) / self.length >= 1.0)
        if np.any(bad):
            length = _at(self.length, bad)
            raise ValueError(
                f"{name} must lie in (-length, length) = ({-length!r}, {length!r}) m, got "
                f"{float(d[bad].flat[0])!r}{_first_index(bad)} (a tip at the full length is "
                "a pillar lying flat, reached only as the stress -> inf)"
            )
        return d

    def _invert(
        self, d: FloatArray, name: str = "tip_deflection", strict: bool = True
    ) -> tuple[FloatArray, Any]:
        """(tau_w [Pa], the dimensionless states) of checked deflections d [m]; where no state
        is found a ValueError naming ``name`` (``strict``) or NaN."""
        x1 = np.asarray(d / self.length, dtype=np.float64)  # in (-1, 1): d was checked
        if self.profile == "wall-law":
            sol = self._invert_wall(x1)
        else:
            sol = _inverse_checked(x1, *self._checked_like(x1), *self._core_options)
        status = np.asarray(sol.status)
        bad = status < 0
        if np.any(bad) and strict:
            i = _first_index(bad)
            raise ValueError(
                f"{name}: no state of this pillar has the tip deflection "
                f"{float(d[bad].flat[0])!r} m{i} (beyond the reachable range: "
                f"{STATUS_MESSAGES[int(status[bad].flat[0])]})"
            )
        lam = np.asarray(sol.forcing, dtype=np.float64)
        return lam / self.forcing_per_stress, sol

    def _inverse_rows(self, x1: FloatArray, prof: FloatArray) -> Any:
        """The inverse states at flat tip deflections x1 [L], each with its profile row."""
        t0, g, tip = self._checked_like(x1)
        _, tol, nums = self._core_options
        return _merged(
            x1.shape,
            x1,
            lambda sel, row: _inverse_checked(x1[sel], t0[sel], g[sel], tip[sel], row, tol, nums),
            prof,
        )

    def _invert_wall(self, x1: Any) -> Any:
        """The wall-law states at tip deflections x1 [L] (any shape).

        The stress t = abs(tau_w) solves g = ln Lambda(x1; L+(t)) - ln(t Lambda/tau_w) = 0
        (flow towards -x as its mirror image), Lambda(x1; L+) the inverse problem at the
        profile of L+ = L sqrt(t/rho)/nu. In ln t, dg/d ln t = beta/2 - 1 with
        beta = d ln Lambda/d ln L+ = -x1_q/(x1_Lambda Lambda) at fixed x1 (the state's exact
        derivatives, q = ln L+); beta lies in [0, 1) (u+ is concave: the wall law's U falls
        with L+ at most like 1/L+), so g falls strictly and Newton's method in ln t from the
        sublayer's stress (L+ = 0, where g >= 0) converges to the one root. Each step's inverse
        is one batched call started from the step before (each element with its own profile),
        and what that misses is solved again from the straight pillar. No state, no convergence in
        ``_WALL_NEWTON`` steps, or a stress beyond the resolved range of the profile (L+ above
        ``MAX_L_PLUS``): status -2 and NaN."""
        shape = np.shape(x1)
        flat = np.asarray(x1, dtype=np.float64).reshape(-1)
        t0, g, tip = (v.reshape(-1) for v in self._checked_like(flat))
        _, tol, nums = self._core_options
        fps = self.forcing_per_stress
        mirror = np.where(flat < np.sin(t0), -1.0, 1.0)
        xm, tm = mirror * flat, mirror * t0
        out, coefs, a = _raw(_inverse_checked(xm, tm, g, tip, *self._core_options))
        t = out[12] / fps
        # the largest stress whose profile is resolved (L+ = MAX_L_PLUS); the root lies at or
        # above the sublayer's stress (the wall law's U is below z), so beyond it: no state
        rho = float(self.density)  # type: ignore[arg-type]
        t_max = rho * (MAX_L_PLUS * self.viscosity / (rho * self.length)) ** 2 * (1.0 - 1e-12)
        failed = ~np.isfinite(t) | (t > t_max)
        active = ~failed & (t > 0.0)
        for _ in range(_WALL_NEWTON):
            idx = np.flatnonzero(active)
            if idx.size == 0:
                break
            ta = t[idx]
            prof, dprof = self._wall_rows(ta)
            o = np.empty((out.shape[0], idx.size))
            c = np.empty((3, idx.size, coefs.shape[-1]))
            theta_start, extra = _state_start(out[:, idx], coefs[:, idx], nums)
            for grp, rows in row_groups(prof):  # each its profile's length
                e = idx[grp]
                o[:, grp], c[:, grp] = _kernel_run(
                    _DRAG_INVERSE,
                    xm[e] - np.sin(tm[e]),  # the kernel's inverse: x1 - sin(theta0)
                    tm[e],
                    g[e],
                    tip[e],
                    np.zeros(e.size),
                    np.ascontiguousarray(theta_start[grp]),
                    np.ascontiguousarray(extra[grp]),
                    rows,
                    tol,
                    nums,
                )
            miss = np.flatnonzero(o[0] < 0)
            if miss.size:  # from the straight pillar, with the core's continuation and walk
                mo, mc, _ = _raw(self._inverse_rows(xm[idx[miss]], prof[miss]))
                o[:, miss], c[:, miss] = mo, mc
            st = _pillar_state((idx.size,), o[12], tm[idx], g[idx], tip[idx], o, c, a[idx])
            out[:, idx], coefs[:, idx] = o, c
            lam = o[12]
            grad, _, _ = pillar_gradient_rows(st, prof, dprof)
            with np.errstate(divide="ignore", invalid="ignore"):
                beta = -grad[1, 3] / grad[1, 0] / lam  # d ln Lambda/d ln L+ at fixed x1
                gt = np.log(lam / (fps * ta))
                step = gt / (0.5 * beta - 1.0)  # in ln t
            new = ta * np.exp(-step)
            # a step beyond the resolved range goes to its end; from there, a root beyond it
            # (g > 0 at t_max, g falling) is no state of this profile
            beyond = (ta >= t_max) & (gt > 0.0)
            new = np.minimum(new, t_max)
            bad = ~np.isfinite(new) | beyond | (o[0] < 0)
            failed[idx[bad]] = True
            t[idx] = np.where(bad, ta, new)
            done = bad | (np.abs(step) <= _WALL_XTOL)
            active[idx[done]] = False
        failed |= active  # no convergence
        out[0, failed] = -2
        out[4:, failed] = np.nan
        coefs[:, failed, :] = np.nan
        _mirror(out, coefs, mirror)
        return _pillar_state(
            shape,
            out[12].reshape(shape),
            t0.reshape(shape),
            g.reshape(shape),
            tip.reshape(shape),
            out,
            coefs,
            a,
        )

    def state_from_tip_deflection(self, tip_deflection: Any) -> PillarDeformation:
        """The state of the pillar whose tip sits at ``tip_deflection`` [m] from its base.

        The deflection fixes the state uniquely (x1 moves monotonically along the branch,
        theory.md §12), snap-through windows included.
        """
        d = self._deflection(tip_deflection)
        tau, sol = self._invert(d)
        return self._state(tau, np.asarray(sol.forcing, dtype=np.float64), sol)

    def wall_shear_stress_from_tip_deflection(self, tip_deflection: Any) -> FloatOrArray:
        """The wall shear stress tau_w [Pa] that puts the tip at ``tip_deflection`` [m].

        The exact calibration curve read backwards (vectorised). ``tip_deflection`` is
        measured along +x from the base and lies in (-L, L); at rest it is L sin(theta0),
        and a tip behind that means flow towards -x (negative tau_w).

        Raises
        ------
        ValueError
            If abs(tip_deflection) >= length, or no state reaches it.
        """
        return float_or_array(self._invert(self._deflection(tip_deflection))[0])

    def linear_wall_shear_stress_from_tip_deflection(self, tip_deflection: Any) -> FloatOrArray:
        """The linear calibration: tau_w [Pa] = (x1 - sin theta0)/(c1 Lambda/tau_w).

        x1 = d/L, c1 the profile's :attr:`linear_coefficient` (x1 = sin theta0 +
        11 Lambda cos^3(theta0)/120 for the sublayer, theory.md §12). Compare with
        :meth:`wall_shear_stress_from_tip_deflection` to see where it fails
        (:meth:`linear_range`).
        """
        d = self._deflection(tip_deflection)
        x1 = d / self.length - _sin(self.base_angle)
        return float_or_array(x1 / (self.linear_coefficient * self.forcing_per_stress))

    def linear_range(self, rtol: float = 0.1) -> LinearRange:
        """The largest deflection at which the linear calibration is within ``rtol``.

        The linear calibration (:meth:`linear_wall_shear_stress_from_tip_deflection`) reads
        tau_lin = (x1 - sin theta0)/(c1 Lambda/tau_w) from a deflection; its relative error
        tau_lin/tau_w - 1 against the exact curve (:meth:`wall_shear_stress_from_tip_deflection`)
        is followed along the branch from rest (flow towards +x, exact states by the inverse
        solver), and the first deflection where abs of it reaches ``rtol`` is found by a
        bracketed root search. The linear range of tau_w is [0, ``wall_shear_stress``].

        Parameters
        ----------
        rtol : float
            Relative tolerance, in (0, 1).

        Returns
        -------
        LinearRange
            With ``quantity="wall_shear_stress"``; ``velocity`` is the Couette wall speed
            there (NaN for the other profiles) and ``velocity_error`` the same relative error.
        """
        self._require_scalar("Pillar.linear_range")
        tol = check_number(rtol, "rtol", low=0.0, high=1.0, low_open=True, high_open=True)
        rest = math.sin(self.base_angle)
        # the grid from rest in chunks, up to the first that leaves the tolerance (or finds no
        # state): the larger deflections beyond are not needed (the wall law's cost most)
        parts = []
        for chunk in np.array_split(_RANGE_GRID, _RANGE_CHUNKS):
            parts.append(self._linear_error(chunk))
            if np.any(~(np.abs(parts[-1]) <= tol)):
                break
        err = np.concatenate(parts)
        searched = _RANGE_GRID[: err.size]
        # the search ends where the inverse first finds no state (a pillar almost flat on
        # the wall, Lambda beyond the solver's reach)
        reached = np.flatnonzero(~np.isfinite(err))
        grid = searched[: reached[0]] if reached.size else searched
        err = err[: grid.size]
        over = np.flatnonzero(~(np.abs(err) <= tol))
        if grid.size == 0:
            raise ValueError(
                "no state of this pillar found at the smallest deflection searched "
                f"({_RANGE_GRID[0]:g} of the way to the wall)"
            )
        if over.size == 0:
            u_star, status = float(grid[-1]), 4
            message = "the linear calibration stays within the tolerance over the whole range"
        elif over[0] == 0:
            raise ValueError(
                f"rtol {tol!r} is below the linear calibration's error at the smallest "
                f"deflection searched ({_RANGE_GRID[0]:g} of the way to the wall)"
            )
        else:
            i = int(over[0])
            sign = 1.0 if err[i] > 0 else -1.0
            u_star = float(
                np.ravel(
                    find_root(
                        lambda u: (
                            sign * self._linear_error(np.ravel(u)).reshape(np.shape(u)) - tol
                        ),
                        _RANGE_GRID[i - 1],
                        _RANGE_GRID[i],
                        xatol=1e-14,
                        what="the end of the linear range",
                    ).x
                )[0]
            )
            status, message = 0, "found"
        d = self.length * (rest + u_star * (1.0 - rest))
        tau, _ = self._invert(np.array([d]))
        e = float(self._linear_error(np.array([u_star]))[0])
        velocity = (
            float(tau[0]) * float(self.channel_height) / self.viscosity  # type: ignore[arg-type]
            if self.profile == "couette"
            else math.nan
        )
        return LinearRange(
            tip_deflection=d,
            velocity=velocity,
            wall_shear_stress=float(tau[0]),
            rtol=tol,
            velocity_error=e if self.profile == "couette" else math.nan,
            wall_shear_stress_error=e,
            success=status == 0,
            status=status,
            message=message,
            quantity="wall_shear_stress",
        )

    def _linear_error(self, u: FloatArray) -> FloatArray:
        """tau_lin/tau_w - 1 at the fractions u of the way from rest to the wall."""
        rest = math.sin(self.base_angle)
        d = self.length * (rest + u * (1.0 - rest))
        tau, _ = self._invert(d, strict=False)
        lin = (u * (1.0 - rest)) / (self.linear_coefficient * self.forcing_per_stress)
        return np.asarray(lin / tau - 1.0, dtype=np.float64)

    # -- in time (hairbed.sensor_dynamics, theory.md §14) ------------------------------------

    def frequency_response(
        self,
        frequency: Any,
        *,
        wall_shear_stress: float = 0.0,
        pillar_density: float | None = None,
        drag: str = "sader",
        magnitude_tolerance: float = 0.05,
        phase_tolerance: float = math.radians(5.0),
    ) -> Any:
        """The tip deflection per wall shear stress H(f) [m/Pa] against frequency f [Hz],
        linearised about the static state at the mean ``wall_shear_stress`` [Pa], with the
        resonance, its quality factor and the bandwidth:
        :func:`hairbed.sensor_dynamics.frequency_response` (a
        :class:`hairbed.sensor_dynamics.SensorResponse`). An array pillar (a design scan)
        gives one response with its shape in front, each element that of its :meth:`item`."""
        from .sensor_dynamics import frequency_response

        return frequency_response(
            self,
            frequency,
            wall_shear_stress=wall_shear_stress,
            pillar_density=pillar_density,
            drag=drag,
            magnitude_tolerance=magnitude_tolerance,
            phase_tolerance=phase_tolerance,
        )

    def wall_shear_stress_from_tip_deflection_series(
        self,
        tip_deflection: Any,
        sample_rate: float | None = None,
        *,
        times: Any = None,
        noise_sigma: float | None = None,
        pillar_density: float | None = None,
        drag: str = "sader",
    ) -> Any:
        """The wall-shear-stress series [Pa] with its 1-sigma band of a tip-deflection series
        [m] sampled at ``sample_rate`` [Hz] (or at uniform ``times`` [s]): the exact static
        inverse about the mean and a Wiener deconvolution of the dynamics,
        :func:`hairbed.sensor_dynamics.wall_shear_stress_from_tip_deflection_series` (a
        :class:`hairbed.sensor_dynamics.StressSeries`)."""
        from .sensor_dynamics import wall_shear_stress_from_tip_deflection_series as series

        self._require_scalar("Pillar.wall_shear_stress_from_tip_deflection_series")
        return series(
            self,
            tip_deflection,
            sample_rate,
            times=times,
            noise_sigma=noise_sigma,
            pillar_density=pillar_density,
            drag=drag,
        )

    def simulate(
        self,
        wall_shear_stress: Any,
        t: Any,
        *,
        pillar_density: float | None = None,
        overdamped: bool = False,
        num: int = 12,
        rtol: float = 1e-6,
        atol: float = 1e-7,
        max_steps: int = 100_000,
        workers: int = 1,
    ) -> Any:
        """The pillar's nonlinear motion [m] at times ``t`` [s] under a wall-shear-stress drive
        tau_w(t) [Pa] (a number: a step from rest at t[0]; a :mod:`hairbed.dynamics` signal
        in seconds and pascals; or a callable of t [s]), from rest in the static state before
        t[0]: :func:`hairbed.sensor_dynamics.simulate` (a
        :class:`hairbed.sensor_dynamics.SensorTrajectory`). An array pillar (a design scan)
        gives one run with its shape in front, each element the run of its :meth:`item`
        (on ``workers`` threads)."""
        from .sensor_dynamics import simulate

        return simulate(
            self,
            wall_shear_stress,
            t,
            pillar_density=pillar_density,
            overdamped=overdamped,
            num=num,
            rtol=rtol,
            atol=atol,
            max_steps=max_steps,
            workers=workers,
        )
