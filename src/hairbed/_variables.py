"""The one table of hairbed's variables: name -> CF units, long name, short label, group.

Every list of fields in the package (the columns of a sweep and their CF attributes, the
outputs of :func:`hairbed.derivatives`, the rows of the explorer's and the CLI's tables, the
parameters of a bed) is built from the mappings here, so adding a variable means
adding one entry (and, for a state field, the kernel's column in
``hairbed._core._kernels.FIELDS``, which a test holds equal to :data:`SOLUTION`).

- :data:`SOLUTION`: the dimensionless problem of the paper, every field of
  :class:`hairbed.Solution` in its order, then quantities derived from a state;
- :data:`BED`: the SI parameters of a :class:`hairbed.units.HairBed` (its dataclass fields,
  then its derived properties);
- :data:`SI`: the SI state of a bed, the fields of :class:`hairbed.units.HairState`;
- :data:`LOADED`: the fields of a :class:`hairbed.LoadedState` that :data:`SOLUTION` does
  not name;
- :data:`PILLAR`: an isolated pillar in a wall shear layer (theory.md §12), the inputs of
  :func:`hairbed.solve_pillar` and every field of :class:`hairbed.PillarState` in its order;
- :data:`POROUS`: a hair in a porous (Brinkman) bed (theory.md §13), every field of a
  :class:`hairbed.PorousState` in its order;
- :data:`WINDOW`: the bistable window of a pair (eps, theta0), the variables of the exact
  map :func:`hairbed.sweeps.bistability_map` (``hairbed bistability --map``).

``units`` are udunits strings as CF conventions want them ("1" for dimensionless; lengths in
units of the hair length L are dimensionless too, as udunits reads "L" as a litre), while
``unit`` is the unit as people read it in a table ("L", "1/L", "-", "m/s", "" for counts and
flags). Like sgkit's ``variables.py``, this module imports nothing: the core may use it.

Examples
--------
>>> SOLUTION["tip_height"].units, SOLUTION["tip_height"].heading
('1', 'tip height h1 [L]')
>>> names(SOLUTION, "input")
('omega2', 'eps', 'theta0')
>>> cf_attrs(SI["pressure_gradient"])
{'units': 'Pa m-1', 'long_name': 'pressure gradient along the channel, G = -dp/dx'}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

__all__ = [
    "BED",
    "BED_REQUIRED",
    "GROUPS",
    "SI",
    "LOADED",
    "PILLAR",
    "POROUS",
    "SOLUTION",
    "WINDOW",
    "Variable",
    "cf_attrs",
    "names",
]

#: The groups of variables, each with what it holds.
GROUPS: Mapping[str, str] = MappingProxyType(
    {
        "input": "the three inputs of the dimensionless problem",
        "branch": "the label (sign, n) of the branch a state lies on",
        "state": "the state's scalar outputs, differentiable in the inputs",
        "solve": "how the state was found: root count, physicality, status, branch parameter",
        "derived": "a quantity computed from a state, not a field of Solution",
        "bed": "a parameter of a hair bed in SI units (a field of HairBed)",
        "bed_model": "a choice of a hair bed's model (a field of HairBed, a string)",
        "bed_derived": "a property of a hair bed computed from its parameters",
        "si": "a state of a bed in SI units (a field of HairState)",
        "window": "the bistable window of a pair (eps, theta0): its folds, width, count",
        "loaded": "a field of a LoadedState (a distributed load) that Solution does not have",
        "pillar_input": "an input of an isolated pillar's problem (solve_pillar)",
        "pillar": "a field of a PillarState (an isolated pillar in a shear layer)",
        "porous_input": "an input of the porous bed's problem (solve_porous)",
        "porous": "a field of a PorousState (a hair in a porous, Brinkman, bed)",
    }
)


@dataclass(frozen=True)
class Variable:
    """One variable of hairbed: how to name, label and unit it.

    Attributes
    ----------
    name : str
        Its name in the API (a dataclass field, a dataset variable, a CSV column).
    group : str
        One of :data:`GROUPS`.
    units : str
        CF units (udunits): "1" for dimensionless, "rad", "m", "m s-1", "Pa s", ...
    long_name : str
        CF ``long_name``: what it is, with its formula.
    label : str
        Short label for tables and axes, without the unit ("tip height h1").
    unit : str
        The unit as shown to people ("L", "1/L", "-", "rad", "m/s"; "" for counts and flags).
    description : str
        One line on what it means.
    dtype : str
        "float64", "int64", "bool" or "str".
    """

    name: str
    group: str
    units: str
    long_name: str
    label: str
    unit: str
    description: str
    dtype: str = "float64"

    @property
    def heading(self) -> str:
        """The label with its unit in brackets, "tip height h1 [L]" (no brackets if none)."""
        return f"{self.label} [{self.unit}]" if self.unit else self.label


def _table(*entries: Variable) -> Mapping[str, Variable]:
    table = {v.name: v for v in entries}
    if len(table) != len(entries):  # pragma: no cover - a typo in this file
        raise ValueError("a variable is named twice")
    for v in entries:
        if v.group not in GROUPS:  # pragma: no cover - a typo in this file
            raise ValueError(f"{v.name}: unknown group {v.group!r}")
    return MappingProxyType(table)


_V = Variable

#: The dimensionless problem: every :class:`hairbed.Solution` field in the dataclass's order
#: (groups input, branch, state, solve), then the derived stress ratio.
SOLUTION: Mapping[str, Variable] = _table(
    _V(
        "omega2", "input", "1",
        "forcing omega^2 = pi a^2 L^2 eta v / (E I H phi)",
        "forcing omega^2", "-",
        "the flow's load on a hair relative to its bending stiffness",
    ),
    _V(
        "eps", "input", "1",
        "confinement eps = L/H (hair length over channel height)",
        "confinement eps = L/H", "-",
        "how much of the channel the hairs fill at rest, in [0, 1)",
    ),
    _V(
        "theta0", "input", "rad",
        "base angle theta0 from the wall normal",
        "base angle theta0", "rad",
        "clamping angle of the hair at the wall, in (-pi/2, pi/2); negative leans into the flow",
    ),
    _V(
        "sign", "branch", "1",
        "sign of the base curvature theta'(0) of the branch",
        "sign of theta'(0)", "",
        "+1 on the physical branch; a twirling branch may have either sign",
        "int64",
    ),
    _V(
        "n", "branch", "1",
        "number of interior turning points of the branch",
        "interior turning points n", "",
        "points inside 0 < sigma < 1 where theta' = 0; 0 on the physical branch",
        "int64",
    ),
    _V(
        "xi", "state", "1",
        "scaled energy xi = E/omega_eps^2 = sin(theta1)",
        "xi = E/omega_eps^2 = sin(theta1)", "-",
        "the one number that fixes the closed-form state (eq. (14)); rounds to 1 when forced hard",
    ),
    _V(
        "omega_eps", "state", "1",
        "effective frequency omega_eps = omega / sqrt(1 - eps h1)",
        "effective frequency omega_eps", "-",
        "the pendulum's frequency: the forcing raised by the gap narrowed by the tips (eq. (5))",
    ),
    _V(
        "energy", "state", "1",
        "Hamiltonian E = theta'^2/2 + omega_eps^2 sin(theta)",
        "Hamiltonian E", "-",
        "the conserved energy of the pendulum equation along the hair (eq. (7))",
    ),
    _V(
        "tip_height", "state", "1",
        "tip height h1 = z(1) in units of the hair length L",
        "tip height h1", "L",
        "height of the tip above the wall, int_0^1 cos(theta) dsigma (eq. (30)); at most 1",
    ),
    _V(
        "tip_deflection", "state", "1",
        "tip deflection x1 = x(1) in units of the hair length L",
        "tip deflection x1", "L",
        "horizontal position of the tip relative to the base, int_0^1 sin(theta) dsigma",
    ),
    _V(
        "tip_displacement", "state", "1",
        "tip displacement x1 - sin(theta0) from the hair at rest, in units of the hair length L",
        "tip displacement x1 - sin(theta0)", "L",
        "how far the flow moved the tip, accurate relative to itself at weak forcing",
    ),
    _V(
        "tip_angle", "state", "rad",
        "tip angle theta1 = theta(1) from the wall normal",
        "tip angle theta1", "rad",
        "angle of the hair at its free end",
    ),
    _V(
        "base_curvature", "state", "1",
        "base curvature theta'(0) in units of 1/L",
        "base curvature theta'(0)", "1/L",
        "curvature at the clamp, omega_eps^2 h1 (eq. (29)): the bending moment there",
    ),
    _V(
        "n_roots", "solve", "1",
        "number of states on this branch at these inputs",
        "states on this branch", "",
        "how many roots the branch equation has here (3 in a bistable window)",
        "int64",
    ),
    _V(
        "physical", "solve", "1",
        "state exists on the physical branch (sign +1, n 0)",
        "physical branch", "",
        "True where the state exists on the branch of a hair that rises and never twirls",
        "bool",
    ),
    _V(
        "status", "solve", "1",
        "solver status: 0 converged, -1 no such state, -2 iteration limit",
        "status (0 converged)", "",
        "how the solve of this state ended (Solution.message says it in words)",
        "int64",
    ),
    _V(
        "t", "solve", "1",
        "branch parameter t = logit((xi - sin theta0)/(1 - sin theta0))",
        "branch parameter t", "-",
        "the coordinate along the branch that the root finder solves for; -inf is rest",
    ),
    _V(
        "stress_ratio", "derived", "1",
        "wall shear stress over that of the bare channel, 1/(1 - eps h1)",
        "stress ratio 1/(1 - eps h1)", "-",
        "how much the bed raises the wall shear stress at the same wall speed",
    ),
)  # fmt: skip

#: A hair bed's SI parameters: :class:`hairbed.units.HairBed`'s fields in its order (group
#: bed), then its derived properties (group bed_derived).
BED: Mapping[str, Variable] = _table(
    _V("length", "bed", "m", "hair length L", "hair length L", "m", "length of one hair"),
    _V(
        "radius", "bed", "m", "hair radius a", "hair radius a", "m",
        "radius of a hair's circular cross-section (not its diameter)",
    ),
    _V(
        "youngs_modulus", "bed", "Pa", "Young's modulus E of the hair material",
        "Young's modulus E", "Pa", "stiffness of the hair material",
    ),
    _V(
        "channel_height", "bed", "m", "channel height H", "channel height H", "m",
        "distance from the wall of the bed to the moving top wall; more than L",
    ),
    _V(
        "viscosity", "bed", "Pa s", "dynamic viscosity eta of the fluid", "viscosity eta",
        "Pa s", "dynamic (not kinematic) viscosity of the fluid",
    ),
    _V(
        "spacing", "bed", "m", "spacing delta of the hexagonal array of hairs",
        "spacing delta", "m", "distance between neighbouring hairs (or the packing fraction)",
    ),
    _V(
        "packing_fraction", "bed", "1",
        "packing fraction phi = (2 pi / sqrt 3) a^2 / delta^2",
        "packing fraction phi", "-", "fraction of the wall covered by hair bases",
    ),
    _V(
        "base_angle", "bed", "rad", "base angle theta0 from the wall normal towards +x",
        "base angle theta0", "rad", "the hairs' clamping angle; negative leans into v > 0",
    ),
    _V(
        "density", "bed", "kg m-3", "density rho of the fluid", "fluid density rho",
        "kg/m^3", "optional: only used for the gap's Reynolds number (Stokes flow if < 1)",
    ),
    _V(
        "model", "bed_model", "1", "the bed's model: 'dense' (the paper's) or 'porous'",
        "bed model", "", "the porous model solves the flow through the bed (theory.md §13)",
        "str",
    ),
    _V(
        "drag", "bed_model", "1",
        "the porous bed's drag coefficients: 'crossover', 'sparse' or 'array'",
        "drag model", "", "Gray & Hancock's, the array's own, or the crossover between them",
        "str",
    ),
    _V(
        "eps", "bed_derived", "1", "confinement eps = L/H", "confinement eps = L/H", "-",
        "the bed's dimensionless confinement",
    ),
    _V(
        "second_moment", "bed_derived", "m4", "second moment of area I = pi a^4 / 4",
        "second moment I", "m^4", "of the hair's cross-section",
    ),
    _V(
        "bending_stiffness", "bed_derived", "N m2", "bending stiffness E I",
        "bending stiffness E I", "N m^2", "resistance of one hair to bending",
    ),
    _V(
        "wall_area_per_hair", "bed_derived", "m2",
        "wall area per hair pi a^2 / phi = (sqrt 3 / 2) delta^2",
        "wall area per hair", "m^2", "the share of the wall whose stress one hair carries",
    ),
    _V(
        "velocity_scale", "bed_derived", "m s-1",
        "wall speed of unit forcing E I H phi / (pi a^2 L^2 eta)",
        "velocity scale", "m/s", "omega^2 = abs(v) / velocity_scale",
    ),
)  # fmt: skip

#: The bed parameters without a default: every bed needs them (and one of spacing and
#: packing_fraction; base_angle defaults to 0, density to none).
BED_REQUIRED = ("length", "radius", "youngs_modulus", "channel_height", "viscosity")

#: A bed's state in SI units: the fields of :class:`hairbed.units.HairState` (all but the
#: ``bed`` and ``solution`` objects) in its order.
SI: Mapping[str, Variable] = _table(
    _V(
        "velocity", "si", "m s-1", "speed of the top wall v (negative: flow towards -x)",
        "wall speed v", "m/s", "drives the shear flow over the bed",
    ),
    _V(
        "omega2", "si", "1", SOLUTION["omega2"].long_name, "forcing omega^2 of |v|", "-",
        "the forcing of the wall speed's magnitude",
    ),
    _V(
        "direction", "si", "1", "+1 where v >= 0, -1 where v < 0", "flow direction", "-",
        "maps the solved (mirrored for v < 0) problem's x to the bed's",
    ),
    _V(
        "tip_deflection", "si", "m", "tip position along +x relative to the base, x1 L",
        "tip deflection x1 L", "m", "what a pillar sensor reads out",
    ),
    _V(
        "tip_height", "si", "m", "tip height above the wall, h1 L", "tip height h1 L", "m",
        "sets the gap H - h1 L that carries the shear",
    ),
    _V(
        "tip_angle", "si", "rad", "tip angle from the wall normal towards +x",
        "tip angle, bed frame", "rad", "angle of the free end in the bed's own frame",
    ),
    _V(
        "wall_shear_stress", "si", "Pa",
        "shear stress of the gap flow on the tip plane, eta v / g + G g / 2 with g = H - h1 L "
        "(the top wall's, eta v / g, when the wall drives the flow)",
        "wall shear stress tau", "Pa", "signed like the flow",
    ),
    _V(
        "force_per_hair", "si", "N",
        "horizontal force of the flow on one hair, (tau + G h1 L) pi a^2 / phi",
        "force per hair F", "N", "signed like the flow",
    ),
    _V(
        "stress_ratio", "si", "1",
        "shear stress on the tip plane over that the same drive puts on the bare channel's "
        "bottom wall (H / (H - h1 L) for a moving wall)",
        "stress ratio tau/tau_bare", "-", SOLUTION["stress_ratio"].description,
    ),
    _V(
        "tip_displacement", "si", "m", "tip displacement along +x from the hair at rest",
        "tip displacement", "m", "(x1 - sin theta0) L, accurate relative to itself when weak",
    ),
    _V(
        "reynolds_number", "si", "1",
        "Reynolds number of the gap flow, rho u_max (H - h1 L) / eta (u_max = abs(v) for a "
        "moving wall)",
        "gap Reynolds number rho u_max g/eta", "-",
        "NaN without a fluid density; above 1 the Stokes-flow model does not hold",
    ),
    _V(
        "pressure_gradient", "si", "Pa m-1", "pressure gradient along the channel, G = -dp/dx",
        "pressure gradient G", "Pa/m", "set by a pump, or following from a set flow rate",
    ),
    _V(
        "flow_rate", "si", "m2 s-1",
        "flow rate per unit width through the gap, v g / 2 + G g^3 / (12 eta)",
        "flow rate Q'", "m^2/s", "per unit width of the channel",
    ),
)  # fmt: skip


#: The bistable window of a pair (eps, theta0), from the exact folds
#: (:func:`hairbed.branches.bistable_window`): the variables of the map of the three-state
#: region (:func:`hairbed.sweeps.bistability_map`), in its order.
WINDOW: Mapping[str, Variable] = _table(
    _V(
        "lower_fold", "window", "1",
        "forcing omega^2 at the lower fold (the local minimum of omega^2 along the physical "
        "branch; NaN where it is monotone)",
        "omega^2 at the lower fold", "-",
        "coming down, the high state disappears here: the window's lower edge",
    ),
    _V(
        "upper_fold", "window", "1",
        "forcing omega^2 at the upper fold (the local maximum of omega^2 along the physical "
        "branch; NaN where it is monotone)",
        "omega^2 at the upper fold", "-",
        "going up, the low state disappears here: the window's upper edge",
    ),
    _V(
        "width", "window", "1",
        "width of the bistable window in omega^2, upper_fold - lower_fold",
        "window width", "-",
        "how wide in forcing the three-state range is (NaN where there is none); tiny near "
        "the cusp",
    ),
    _V(
        "n_states", "window", "1",
        "number of physical states inside the window: 3 where it exists, else 1",
        "physical states in the window", "",
        "3 where lower_fold < omega^2 < upper_fold holds three states, 1 where there is no "
        "window",
        "int64",
    ),
    _V(
        "exists", "window", "1",
        "the physical branch folds: a bistable window exists",
        "window exists", "",
        "True where three physical states coexist for some omega^2",
        "bool",
    ),
    _V(
        "cusp_eps", "window", "1",
        "cusp confinement eps_c(theta0) above which the physical branch folds",
        "cusp eps_c(theta0)", "-",
        "a window exists exactly for eps > eps_c; 1 where there is none for any eps < 1",
    ),
)  # fmt: skip


def names(table: Mapping[str, Variable], *groups: str) -> tuple[str, ...]:
    """The names of ``table`` in its order, only those of ``groups`` if any are given.

    Raises
    ------
    ValueError
        If a group is not one of :data:`GROUPS`.
    """
    for g in groups:
        if g not in GROUPS:
            raise ValueError(f"groups must be among {sorted(GROUPS)}, got {g!r}")
    return tuple(k for k, v in table.items() if not groups or v.group in groups)


def cf_attrs(variable: Variable) -> dict[str, str]:
    """The CF attributes ``{"units", "long_name"}`` of a variable (for xarray, netCDF)."""
    return {"units": variable.units, "long_name": variable.long_name}


#: The fields of a :class:`hairbed.LoadedState` (the distributed-load solver) that
#: :data:`SOLUTION` does not name, in its order; the others (the inputs, the tip, the base
#: curvature, ``status``) are those of :data:`SOLUTION`.
LOADED: Mapping[str, Variable] = _table(
    _V(
        "pi", "loaded", "1", "dimensionless pressure gradient pi = A G L^3 / (E I)",
        "pressure gradient pi", "-", "set by the pressure drive (NaN for the flow drive)",
    ),
    _V(
        "q", "loaded", "1", "dimensionless flow rate q = 6 A eta Q' L^2 / (E I H^2)",
        "flow rate q", "-", "set by the flow drive (NaN for the pressure drive)",
    ),
    _V(
        "tip_load", "loaded", "1", "tip load W = A tau L^2 / (E I) at the state",
        "tip load W", "-", "the gap flow's shear on the tip plane",
    ),
    _V(
        "distributed_load", "loaded", "1",
        "load per unit height Pi = A G L^3 / (E I) at the state",
        "distributed load Pi", "-", "the pressure gradient the bed's fluid passes to a hair",
    ),
    _V(
        "error_estimate", "loaded", "1",
        "Chebyshev tail of theta, the sum of the moduli of its last three coefficients [rad]",
        "error estimate", "-", "estimates the error of theta, x and z",
    ),
    _V(
        "residual", "loaded", "1", "largest residual of the collocation equations",
        "residual", "-", "of the returned state",
    ),
    _V(
        "nit", "loaded", "1", "Newton iterations over every level of the Chebyshev ladder",
        "Newton iterations", "", "work done", "int64",
    ),
    _V(
        "num", "loaded", "1", "Chebyshev degree N of the returned state",
        "Chebyshev degree N", "", "the resolution that met the tolerance", "int64",
    ),
    _V(
        "stable", "loaded", "1",
        "stable under a slow change of the tip height (dG/dh1 < 0 of the fixed-load map)",
        "stable", "", "from solve_loaded_all only (None elsewhere)", "bool",
    ),
)  # fmt: skip


#: An isolated pillar in a wall shear layer (theory.md §12): the inputs of
#: :func:`hairbed.solve_pillar` (group pillar_input: the fields of a
#: :class:`hairbed.PillarState` in its order, then ``height_ratio``, an input of the channel
#: profiles only), then every other field of a PillarState in its order (group pillar). A
#: table of its own, not an extension of :data:`SOLUTION`: the pillar's lengths are in its
#: length L, its forces in E I/L^2, and its base curvature is the whole drag's moment.
PILLAR: Mapping[str, Variable] = _table(
    _V(
        "forcing", "pillar_input", "1",
        "pillar forcing Lambda = zeta_perp tau_w L^4 / (eta E I)",
        "forcing Lambda", "-",
        "the drag of the shear layer relative to the pillar's bending stiffness (negative: "
        "flow towards -x)",
    ),
    _V(
        "theta0", "pillar_input", "rad",
        "base angle theta0 of the pillar from the wall normal",
        "base angle theta0", "rad",
        "clamping angle at the wall, in (-pi/2, pi/2); negative leans into the flow",
    ),
    _V(
        "gamma", "pillar_input", "1",
        "drag ratio gamma = zeta_par / zeta_perp of resistive-force theory",
        "drag ratio gamma", "-",
        "tangential over normal drag coefficient, in (0, 1]; 1/2 is the slender limit",
    ),
    _V(
        "tip_load", "pillar_input", "1",
        "horizontal force on the pillar's tip in units of E I / L^2",
        "tip load P", "EI/L^2",
        "a point force on the free end beside the drag (0 unless given)",
    ),
    _V(
        "height_ratio", "pillar_input", "1",
        "pillar length over channel height L / H of the channel profiles",
        "height ratio L/H", "-",
        "in (0, 1]: sets the Poiseuille profile U = z (1 - (L/H) z); checked for Couette",
    ),
    _V(
        "tip_deflection", "pillar", "1",
        "tip deflection x1 = x(1) of the pillar in units of its length L",
        "tip deflection x1", "L",
        "streamwise position of the tip relative to the base: what a pillar sensor reads",
    ),
    _V(
        "tip_height", "pillar", "1",
        "tip height h1 = z(1) of the pillar in units of its length L",
        "tip height h1", "L",
        "height of the tip above the wall, at most 1",
    ),
    _V(
        "tip_angle", "pillar", "rad",
        "tip angle theta1 = theta(1) of the pillar from the wall normal",
        "tip angle theta1", "rad",
        "angle of the pillar at its free end",
    ),
    _V(
        "base_curvature", "pillar", "1",
        "base curvature theta'(0) of the pillar in units of 1/L (base moment E I theta'(0)/L)",
        "base curvature theta'(0)", "1/L",
        "the moment of the whole drag about the base, in E I/L",
    ),
    _V(
        "drag_x", "pillar", "1",
        "streamwise drag on the whole pillar F_x(0) in units of E I / L^2",
        "streamwise drag F_x", "EI/L^2",
        "the integral of the drag per unit length along x (the tip load included)",
    ),
    _V(
        "drag_z", "pillar", "1",
        "wall-normal drag on the whole pillar F_z(0) in units of E I / L^2",
        "wall-normal drag F_z", "EI/L^2",
        "the integral of the drag per unit length along z",
    ),
    _V(
        "tip_deflection_slope", "pillar", "1",
        "sensitivity dx1/dLambda of the tip deflection to the forcing in units of L",
        "sensitivity dx1/dLambda", "L",
        "by implicit differentiation of the collocation system; NaN at a fold",
    ),
    _V(
        "status", "pillar", "1",
        "solver status: 0 converged, 3 inaccurate, negative failed (STATUS_MESSAGES)",
        "status (0 converged)", "",
        "how the solve ended (PillarState.message says it in words)",
        "int64",
    ),
    _V(
        "error_estimate", "pillar", "1",
        "Chebyshev tail of theta plus its rounding part [rad]",
        "error estimate", "-", "estimates the error of theta, x and z",
    ),
    _V(
        "residual", "pillar", "1", "largest residual of the collocation equations",
        "residual", "-", "of the returned state",
    ),
    _V(
        "nit", "pillar", "1", "Newton iterations over every level of the Chebyshev ladder",
        "Newton iterations", "", "work done", "int64",
    ),
    _V(
        "num", "pillar", "1", "Chebyshev degree N of the returned state",
        "Chebyshev degree N", "", "the resolution that met the tolerance", "int64",
    ),
    _V(
        "stable", "pillar", "1",
        "stable under a slow change of the forcing (on a rising part of Lambda(x1))",
        "stable", "", "from solve_pillar_all only (None elsewhere)", "bool",
    ),
    _V(
        "n_states", "pillar", "1",
        "number of states that coexist at this forcing (1, or 3 in a snap-through window)",
        "coexisting states", "", "0 where none was found; None for the inverse", "int64",
    ),
)  # fmt: skip


#: A hair in a porous (Brinkman) bed (theory.md §13), with every field of a
#: :class:`hairbed.PorousState` in its order (``drive`` aside), inputs first. Loads and the
#: fluid's stresses are in E I/(A L^2), its velocity in E I/(eta A L) (the load units of
#: the paper's omega^2).
POROUS: Mapping[str, Variable] = _table(
    _V(
        "omega2", "porous_input", "1", SOLUTION["omega2"].long_name,
        "forcing omega^2", "-", "the top wall's drive (the inverse's solved forcing)",
    ),
    _V("eps", "porous_input", "1", SOLUTION["eps"].long_name, "confinement eps", "-",
       SOLUTION["eps"].description),
    _V("theta0", "porous_input", "rad", SOLUTION["theta0"].long_name, "base angle theta0",
       "rad", SOLUTION["theta0"].description),
    _V(
        "kappa", "porous_input", "1",
        "bed permeability over L^2, kappa = eta A / (zeta_perp L^2)",
        "permeability kappa", "-", "the square of the Brinkman length in hair lengths",
    ),
    _V(
        "gamma", "porous_input", "1", "drag ratio gamma = zeta_par / zeta_perp",
        "drag ratio gamma", "-", "tangential over normal drag of a hair, in (0, 1]",
    ),
    _V(
        "pi", "porous_input", "1", LOADED["pi"].long_name, "pressure gradient pi", "-",
        "set by the pressure drive, solved by the flow drive",
    ),
    _V("q", "porous_input", "1", LOADED["q"].long_name, "flow rate q", "-",
       "set by the flow drive (NaN for the pressure drive)"),
    _V("tip_height", "porous", "1", "tip height h1 = z(1), in units of L", "tip height h1",
       "L", "sets the gap above the bed"),
    _V("tip_deflection", "porous", "1", "tip deflection x1 = x(1), in units of L",
       "tip deflection x1", "L", "along +x from the base"),
    _V("tip_angle", "porous", "rad", "tip angle theta(1) from the wall normal", "tip angle",
       "rad", "angle of the free end"),
    _V(
        "base_curvature", "porous", "1",
        "base curvature theta'(0) = int_0^1 (F_x cos theta - F_z sin theta) ds, in 1/L",
        "base curvature", "1/L", "the base moment over E I",
    ),
    _V("tip_stress", "porous", "1", "fluid shear stress on the tip plane Q(1), load units",
       "tip-plane stress Q(1)", "-", "the dense bed's tip load W in its limit"),
    _V("wall_stress", "porous", "1", "fluid shear stress on the bottom wall Q(0), load units",
       "bottom-wall stress Q(0)", "-", "0 in the dense limit"),
    _V("tip_velocity", "porous", "1", "fluid velocity at the tip plane w(1), load units",
       "tip-plane velocity w(1)", "-", "the bed's slip velocity"),
    _V("drag_x", "porous", "1", "total horizontal drag F_x(0) on one hair, in E I/L^2",
       "drag F_x(0)", "EI/L^2", "the base's shear force"),
    _V("drag_z", "porous", "1", "total vertical drag F_z(0) on one hair, in E I/L^2",
       "drag F_z(0)", "EI/L^2", "the base's axial force (0 for isotropic drag)"),
    _V("max_angle", "porous", "rad", "largest |theta| along the hair", "largest angle",
       "rad", "the model needs it below pi/2"),
    _V("status", "porous", "1", "solver status (0 converged; negative: no state)", "status",
       "", "see STATUS_MESSAGES", "int64"),
    _V("error_estimate", "porous", "1",
       "largest Chebyshev tail of theta, w and Q (relative) plus the rounding part",
       "error estimate", "-", "estimates the error of the state"),
    _V("residual", "porous", "1", "largest residual of the collocation equations",
       "residual", "-", "of the returned state"),
    _V("nit", "porous", "1", "Newton iterations over every level of the Chebyshev ladder",
       "Newton iterations", "", "work done", "int64"),
    _V("num", "porous", "1", "Chebyshev degree N of the returned state",
       "Chebyshev degree N", "", "the resolution that met the tolerance", "int64"),
    _V("stable", "porous", "1",
       "stable under a slow change of the gap (dG/dh1 < 0 of the frozen-gap map)", "stable",
       "", "from solve_porous_all only (None elsewhere)", "bool"),
)  # fmt: skip
