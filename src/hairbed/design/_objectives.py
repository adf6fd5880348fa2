"""Objectives and constraints of a design, in one vocabulary: named quantities of a model.

A :class:`Quantity` is a function of a model (a :class:`~hairbed.HairBed` or a
:class:`~hairbed.Pillar`) that returns its value and its gradient in the model's SI
parameters. The gradients are exact where the library has the derivatives: the implicit
differentiation of the converged collocation (loaded states of the valve, pillar states),
the closed-form partials of the branch (the folds of the bistable window) and the chain rule
through the dimensionless groups, explicit in the SI parameters (theory.md §7, §11, §12)::

    eps    = L/H                                   bed confinement [-]
    pi     = 4 G L^3/(phi E a^2)                   bed's pressure load, G = dp/l [-]
    v*     = E a^2 H phi/(4 L^2 eta)               bed's velocity scale, omega^2 = v/v* [m/s]
    phi    = (2 pi/sqrt 3) a^2/delta^2             packing fraction (spacing held) [-]
    Lambda = 16 c tau_w L^4/(E a^4 s),  s = ln(2L/a) + 1/2       pillar's forcing [-]
    gamma  = s/(2 s - 2)                           pillar's drag ratio [-]

The second derivatives that the sensitivity and the bandwidth need (the derivative of the
state's first-order system, and of the linear dynamics' operators) come from the residual
run on second-order jets (``hairbed.design._pillar_second``).

A quantity without an exact gradient (a user callable without its gradient) says so:
``exact`` is False, and its gradient is a central difference, named as such in every
result.

Constraints are written with comparisons: ``resistance_ratio(500.0, 0.01) <= 4.0``.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._core.loaded_sensitivity import loaded_gradient_table
from .._core.pillar import _solve_pillar_checked
from .._core.pillar_sensitivity import _profile_derivative, pillar_gradient_rows
from .._core.solver import _from_parameter
from .._core.validation import show
from ..branches import folds
from ..pillars import PILLAR_REYNOLDS_LIMIT, SLENDERNESS_LIMIT, SUBLAYER_L_PLUS_LIMIT, Pillar
from ..sensitivity import _partials, _physical_partials
from ..units import DENSE_BED_LIMIT, HairBed
from ..valve import valve_curve
from ._linear_range import LinearRangeTracker
from ._pillar_second import mode_gradient, slope_gradient
from ._pillar_window import WindowTracker, fold_gradient

__all__ = [
    "Constraint",
    "Quantity",
    "bandwidth",
    "bistable_width",
    "brinkman_ratio",
    "custom",
    "diodicity",
    "gap_reynolds",
    "l_plus",
    "linear_range",
    "linear_sensitivity",
    "net_flow",
    "pillar_reynolds",
    "resistance_ratio",
    "resonance_frequency",
    "sensitivity",
    "slenderness",
    "snap_window",
    "tip_deflection",
    "validity_constraints",
]

Grad = dict[str, float]
#: The gap Reynolds number above which the bed's Stokes flow is out of its range.
GAP_REYNOLDS_LIMIT = 1.0
#: The profiles whose pillar the design supports (U(z) = z: no parameter of the profile).
_PILLAR_PROFILES = ("sublayer", "couette")
#: Relative step of the central differences of a quantity without an exact gradient.
FD_STEP = 1e-5


def _comb(*terms: tuple[float, Grad]) -> Grad:
    """sum of coef * grad over dicts of partial derivatives."""
    out: Grad = {}
    for coef, g in terms:
        for k, v in g.items():
            out[k] = out.get(k, 0.0) + coef * v
    return out


@dataclass(frozen=True, eq=False)
class Quantity:
    """A named scalar function of a model, with its gradient in the SI parameters.

    Attributes
    ----------
    name : str
        What it is, with its arguments (e.g. ``"diodicity(dp=1000 Pa, l=0.01 m)"``).
    kind : {"bed", "pillar", "any"}
        The model it applies to.
    unit : str
        Its SI unit.
    exact : bool
        True when the gradient is exact (the library's derivatives and the chain rule);
        False when it is a central difference (:data:`FD_STEP`).
    validity : tuple of Quantity-producing callables
        The model-validity constraints this quantity's operating point needs.
    """

    name: str
    kind: str
    unit: str
    exact: bool
    _evaluate: Callable[[Any, str], tuple[float, Grad]] = field(repr=False)
    operating: tuple[Any, ...] = field(default=(), repr=False)
    #: True for a quantity of the porous bed too (HairBed(model="porous")).
    porous: bool = field(default=False, repr=False)

    def evaluate(self, model: Any, hold: str = "spacing") -> tuple[float, Grad]:
        """(value, {parameter: d value/d parameter}) of ``model``; ``hold`` is the one of
        spacing and packing fraction a bed is built from (:class:`~hairbed.design.Space`)."""
        if not isinstance(hold, str) or hold not in ("spacing", "packing_fraction"):
            raise ValueError(f"hold must be 'spacing' or 'packing_fraction', got {show(hold)}")
        self._check_model(model)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return self._evaluate(model, hold)

    def __call__(self, model: Any) -> float:
        """The value of the quantity for ``model``."""
        return self.evaluate(model)[0]

    def _check_model(self, model: Any) -> None:
        want = {"bed": HairBed, "pillar": Pillar}.get(self.kind)
        if want is not None and not isinstance(model, want):
            raise TypeError(
                f"{self.name} is a quantity of a {want.__name__}: model must be one, got "
                f"{type(model).__name__}"
            )
        if isinstance(model, HairBed) and model.model != "dense" and not self.porous:
            raise NotImplementedError(
                f"{self.name}: hairbed.design supports this quantity of the dense bed only, "
                "so far (of a porous bed: diodicity, resistance_ratio)"
            )
        if isinstance(model, Pillar) and model.profile not in _PILLAR_PROFILES:
            raise NotImplementedError(
                f"{self.name}: hairbed.design supports pillars of the profiles "
                f"{', '.join(map(repr, _PILLAR_PROFILES))} only, so far; got "
                f"{model.profile!r}"
            )

    def __le__(self, bound: float) -> Constraint:
        return Constraint(self, upper=bound)

    def __ge__(self, bound: float) -> Constraint:
        return Constraint(self, lower=bound)


@dataclass(frozen=True)
class Constraint:
    """``lower <= quantity`` or ``quantity <= upper`` (exactly one bound).

    Parameters
    ----------
    quantity : Quantity
    lower, upper : float, optional
        The bound, finite, in the quantity's unit.
    validity : bool
        True for a constraint of the model's validity (added by the optimiser).
    """

    quantity: Quantity
    lower: float | None = None
    upper: float | None = None
    validity: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.quantity, Quantity):
            raise TypeError(
                f"a constraint needs a hairbed.design Quantity, got {show(self.quantity)}"
            )
        if (self.lower is None) == (self.upper is None):
            raise ValueError(
                f"constraint on {self.quantity.name}: give exactly one of lower and upper"
            )
        bound = self.lower if self.lower is not None else self.upper
        if isinstance(bound, bool) or not isinstance(bound, (int, float, np.floating)):
            raise ValueError(f"constraint on {self.quantity.name}: the bound must be a number")
        if not math.isfinite(float(bound)):
            raise ValueError(
                f"constraint on {self.quantity.name}: the bound must be finite, got {show(bound)}"
            )

    @property
    def bound(self) -> float:
        """The bound [the quantity's unit]."""
        return float(self.lower if self.lower is not None else self.upper)  # type: ignore[arg-type]

    @property
    def sense(self) -> str:
        """ ">=" or "<="."""
        return ">=" if self.lower is not None else "<="

    @property
    def label(self) -> str:
        """``"name <= bound"``."""
        return f"{self.quantity.name} {self.sense} {self.bound:g}"

    def slack(self, value: float) -> float:
        """bound - value for "<=", value - bound for ">=" (negative: violated; NaN for a
        NaN value: a failed design's reports)."""
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
            raise TypeError(f"value must be a real number, got {show(value)}")
        value = float(value) if not isinstance(value, int) or abs(value) < 2**1023 else math.inf
        return value - self.bound if self.lower is not None else self.bound - value


def _number(value: Any, name: str, positive: bool = True) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)):
        raise ValueError(f"{name} must be a real number, got {show(value)}")
    try:
        x = float(value)
    except OverflowError:  # an int beyond double precision
        x = math.inf
    if not math.isfinite(x) or (positive and not x > 0.0):
        raise ValueError(
            f"{name} must be a finite number{' > 0' if positive else ''}, got {show(x)}"
        )
    return x


# -- the bed ---------------------------------------------------------------------------------


def _ln_phi(bed: HairBed, hold: str) -> Grad:
    """d ln(phi)/d parameter."""
    if hold == "packing_fraction":
        return {"packing_fraction": 1.0 / float(bed.packing_fraction)}  # type: ignore[arg-type]
    return {"radius": 2.0 / bed.radius, "spacing": -2.0 / float(bed.spacing)}  # type: ignore[arg-type]


def _ln(name: str, value: float) -> Grad:
    return {name: 1.0 / value}


@functools.lru_cache(maxsize=64)
def _valve_gaps(bed: HairBed, dp: float, length: float, hold: str) -> list[tuple[float, Grad]]:
    """[(gap g [m], dg/dparameter)] of the valve's states at +dp and -dp (theory.md §11);
    cached per (bed, dp, l, hold): the quantities of one design share the states. The
    caller must not change the dicts."""
    curve = valve_curve(bed, np.array([dp, -dp]), length)
    if not curve.success:
        raise ArithmeticError(f"the valve's states at pressure_drop +-{dp:g} Pa: {curve.message}")
    table, status = loaded_gradient_table(curve.states.solution)
    h1 = np.asarray(curve.states.solution.tip_height, dtype=np.float64)
    big_l, big_h, a, e = bed.length, bed.channel_height, bed.radius, bed.youngs_modulus
    d_ln_eps = _comb((1.0, _ln("length", big_l)), (-1.0, _ln("channel_height", big_h)))
    d_ln_pi = _comb(
        (3.0, _ln("length", big_l)),
        (-1.0, _ln_phi(bed, hold)),
        (-1.0, _ln("youngs_modulus", e)),
        (-2.0, _ln("radius", a)),
    )
    eps = bed.eps
    out = []
    for i, sign in enumerate((1.0, -1.0)):
        if int(np.asarray(status).reshape(-1)[i]) != 0:
            raise ArithmeticError(f"the valve's state at {sign * dp:g} Pa is at a fold")
        pi = sign * 4.0 * (dp / length) * big_l**3 / (float(bed.packing_fraction) * e * a * a)  # type: ignore[arg-type]
        h_eps = float(np.asarray(table["tip_height"]["eps"]).reshape(-1)[i])
        h_pi = float(np.asarray(table["tip_height"]["pi"]).reshape(-1)[i])
        h_th = float(np.asarray(table["tip_height"]["theta0"]).reshape(-1)[i])
        dh1 = _comb((h_eps * eps, d_ln_eps), (h_pi * pi, d_ln_pi), (h_th, {"base_angle": 1.0}))
        gap = big_h - h1[i] * big_l
        dgap = _comb((1.0, {"channel_height": 1.0}), (-big_l, dh1), (-h1[i], {"length": 1.0}))
        out.append((float(gap), dgap))
    return out


@functools.lru_cache(maxsize=64)
def _porous_flows(bed: HairBed, dp: float, length: float, hold: str) -> list[tuple[float, Grad]]:
    """[(Q' [m^2/s], dQ'/dparameter)] of the porous bed's valve at +dp and -dp (theory.md
    §13): Q' = E I Phi/(eta A), Phi the flux through bed and gap in load units, its exact
    derivatives in (eps, theta0, kappa, gamma, pi) (:func:`porous_derivatives` with
    ``flux``), kappa's and gamma's in the SI parameters from the bed's drag model
    (``HairBed._drag_slopes``), pi = A G L^3/(E I). Cached as :func:`_valve_gaps`."""
    from .._core.porous_sensitivity import porous_derivatives

    curve = valve_curve(bed, np.array([dp, -dp]), length)
    if not curve.success:
        raise ArithmeticError(f"the valve's states at pressure_drop +-{dp:g} Pa: {curve.message}")
    d = porous_derivatives(curve.states.solution, flux=True)
    status = np.asarray(d.status).reshape(-1)
    flows = np.asarray(curve.flow_rate, dtype=np.float64).reshape(-1)
    big_l, big_h, a, e = bed.length, bed.channel_height, bed.radius, bed.youngs_modulus
    d_ln_a = _comb((2.0, _ln("radius", a)), (-1.0, _ln_phi(bed, hold)))  # A = pi a^2/phi
    d_ln_scale = _comb(
        (1.0, _ln("youngs_modulus", e)),
        (4.0, _ln("radius", a)),
        (-1.0, _ln("viscosity", bed.viscosity)),
        (-1.0, d_ln_a),
    )
    d_ln_eps = _comb((1.0, _ln("length", big_l)), (-1.0, _ln("channel_height", big_h)))
    d_ln_pi = _comb(
        (1.0, d_ln_a), (3.0, _ln("length", big_l)), (-1.0, _ln("youngs_modulus", e)),
        (-4.0, _ln("radius", a)),
    )  # fmt: skip
    held = {"length", "radius", hold}
    slopes = {k: v for k, v in bed._drag_slopes(hold).items() if k in held}
    size = {"length": big_l, "radius": a, "spacing": bed.spacing, "packing_fraction":
            bed.packing_fraction}  # fmt: skip
    d_ln_kappa = {k: v[0] / float(size[k]) for k, v in slopes.items()}  # type: ignore[arg-type]
    d_gamma = {k: v[1] / float(size[k]) for k, v in slopes.items()}  # type: ignore[arg-type]
    kappa, eps = bed.kappa, bed.eps
    out = []
    for i, sign in enumerate((1.0, -1.0)):
        if status[i] != 0:
            raise ArithmeticError(f"the porous valve's state at {sign * dp:g} Pa is at a fold")
        row = {k: float(np.asarray(v).reshape(-1)[i]) for k, v in d.table["flux"].items()}
        pi = (
            sign
            * (dp / length)
            * float(bed.wall_area_per_hair)
            * big_l**3
            / (bed.bending_stiffness)
        )
        q = float(flows[i])
        scale = bed.bending_stiffness / (bed.viscosity * float(bed.wall_area_per_hair))
        d_phi = _comb(
            (row["eps"] * eps, d_ln_eps),
            (row["theta0"], {"base_angle": 1.0}),
            (row["kappa"] * kappa, d_ln_kappa),
            (row["gamma"], d_gamma),
            (row["pi"] * pi, d_ln_pi),
        )
        out.append((q, _comb((q, d_ln_scale), (scale, d_phi))))
    return out


def _drop(pressure_drop: Any, channel_length: Any) -> tuple[float, float]:
    dp = _number(pressure_drop, "pressure_drop [Pa]")
    return dp, _number(channel_length, "channel_length [m]")


def diodicity(pressure_drop: float, channel_length: float) -> Quantity:
    """The valve's diodicity Di = Q'(+dp)/abs(Q'(-dp)) = (g+/g-)^3 [-] at a drop dp [Pa]
    over a channel of length l [m] (:func:`hairbed.valve.diodicity`; g the gap above the
    tips, theory.md §11). Gradient exact: the loaded states' implicit derivatives in
    (eps, pi, theta0) and the chain rule. Validity: the gap's Reynolds number at both
    drops (with a density) and the dense-bed condition.

    A porous bed (``HairBed(model="porous")``, theory.md §13): Di = Q'(+dp)/abs(Q'(-dp))
    with the flow through bed and gap, Q' = E I Phi/(eta A); its gradient from the porous
    states' exact derivatives of the flux Phi in (eps, theta0, kappa, gamma, pi), with
    kappa's and gamma's in the SI parameters from the bed's drag model.

    Parameters
    ----------
    pressure_drop : float
        dp > 0 [Pa]: the valve at +dp and -dp.
    channel_length : float
        l [m], > 0.

    Returns
    -------
    Quantity
        Of a HairBed (dense or porous), unit [-].
    """
    dp, length = _drop(pressure_drop, channel_length)

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        if bed.model == "porous":  # Q'(+dp)/abs(Q'(-dp)), through bed and gap
            (qp, dqp), (qm, dqm) = _porous_flows(bed, dp, length, hold)
            di = qp / -qm
            return di, _comb((di / qp, dqp), (-di / qm, dqm))
        (gp, dgp), (gm, dgm) = _valve_gaps(bed, dp, length, hold)
        di = (gp / gm) ** 3
        return di, _comb((3.0 * di / gp, dgp), (-3.0 * di / gm, dgm))

    return Quantity(
        f"diodicity(dp={dp:g} Pa, l={length:g} m)",
        "bed",
        "-",
        True,
        evaluate,
        (("valve", dp, length),),
        porous=True,
    )


def resistance_ratio(pressure_drop: float, channel_length: float) -> Quantity:
    """R/R0 = (H/g)^3 [-] of the valve at the signed drop dp [Pa] over l [m]: its hydraulic
    resistance against the empty channel's (:func:`hairbed.valve.valve_curve`), exact
    gradient as :func:`diodicity`. Of a porous bed: the empty channel's flow over the
    bed's, H^3 G/(12 eta Q'), the flow through bed and gap (as :func:`diodicity`).

    Parameters
    ----------
    pressure_drop : float
        dp, signed (negative: flow towards -x) [Pa].
    channel_length : float
        l [m], > 0.

    Returns
    -------
    Quantity
        Of a HairBed (dense), unit [-].
    """
    if isinstance(pressure_drop, (int, float)) and pressure_drop < 0:
        dp, length = _drop(-pressure_drop, channel_length)
        index, sign = 1, -1.0
    else:
        dp, length = _drop(pressure_drop, channel_length)
        index, sign = 0, 1.0

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        h = bed.channel_height
        if bed.model == "porous":  # the empty channel's flow over the bed's, H^3 G/(12 eta Q')
            q, dq = _porous_flows(bed, dp, length, hold)[index]
            r = sign * dp * h**3 / (12.0 * bed.viscosity * length * q)
            return r, _comb(
                (3.0 * r / h, {"channel_height": 1.0}),
                (-r / bed.viscosity, {"viscosity": 1.0}),
                (-r / q, dq),
            )
        gap, dgap = _valve_gaps(bed, dp, length, hold)[index]
        r = (h / gap) ** 3
        return r, _comb((3.0 * r / h, {"channel_height": 1.0}), (-3.0 * r / gap, dgap))

    return Quantity(
        f"resistance_ratio(dp={sign * dp:g} Pa, l={length:g} m)",
        "bed",
        "-",
        True,
        evaluate,
        (("valve", dp, length),),
        porous=True,
    )


def net_flow(
    pressure_amplitude: float,
    frequency: float,
    channel_length: float,
    *,
    hair_density: float | None = None,
) -> Quantity:
    """The rectified net flow [m^2/s] of a bed pumped by dp(t) = A sin(2 pi f t) over a
    channel of length l: the period mean of the flow per unit width Q'(t) through bed and
    gap in the periodic state (:func:`hairbed.valve_dynamics.pump_net_flow`; theory.md
    §15, §16), positive along +x (the way a bed tilted by base_angle > 0 leans).

    The bed in time is the porous model of its geometry (either ``model``):
    Q' = q/(6 A eta L^2/(E I H^2)) with q the flow of §11 in the dimensionless bed of
    theta0, kappa, gamma, eps, driven by Pi(t) = Pi_A sin(omega t), Pi_A = A/l A_h L^3/(E I)
    (A_h = pi a^2/phi the wall area per hair), omega = 2 pi f T, T = zeta_perp L^4/(E I);
    with the bed's ``density`` the fluid's inertia alpha = rho L^2/(eta T), with
    ``hair_density`` the hairs' (mu, chi). Its periodic state by collocation in time
    (:func:`hairbed.dynamics.periodic_bed`, truncation error below 1e-12).

    Gradient exact: the periodic orbit differentiated implicitly, by its adjoint
    (:func:`hairbed.dynamics.periodic_adjoint`: one transposed solve for all the rates'
    exact parameter columns of ``_core._kernels.bed_parameters``;
    ``hairbed.design._net_flow``; about twice the value's cost), chained
    through kappa's and gamma's drag model (``HairBed._drag_slopes``), T, Pi_A, alpha, mu,
    chi and the flow's scale to the SI parameters.

    Parameters
    ----------
    pressure_amplitude : float
        A > 0 [Pa].
    frequency : float
        f > 0 [Hz].
    channel_length : float
        l > 0 [m].
    hair_density : float, optional
        rho_s > 0 [kg/m^3] for the hairs' inertia (default: overdamped hairs).

    Returns
    -------
    Quantity
        Of a HairBed (dense or porous), unit [m^2/s].
    """
    amp = _number(pressure_amplitude, "pressure_amplitude [Pa]")
    freq = _number(frequency, "frequency [Hz]")
    length = _number(channel_length, "channel_length [m]")
    rho_s = None if hair_density is None else _number(hair_density, "hair_density [kg/m^3]")

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        from .._bed_scales import _as_porous, _scales
        from ..bed_simulation import _within_range
        from ..dynamics._bed import MAX_BED_DRIVE
        from ._net_flow import net_flow_derivatives, pumped_orbit

        s = _within_range(_scales(bed, rho_s), bed, rho_s)
        pia = amp / length * s.pi_per_gradient
        if not (math.isfinite(pia) and pia <= MAX_BED_DRIVE):
            raise ValueError(
                f"pressure_amplitude must be at most "
                f"{MAX_BED_DRIVE / s.pi_per_gradient * length:.4g} Pa over channel_length = "
                f"{length:g} m for this bed in time (its pressure load "
                f"within {MAX_BED_DRIVE:g}), got {amp:g}"
            )
        om = 2.0 * math.pi * freq * s.time
        if not 1e-9 <= om <= 1e9:
            lo, hi = 1e-9 / (2.0 * math.pi * s.time), 1e9 / (2.0 * math.pi * s.time)
            raise ValueError(
                f"frequency must lie in [{lo:.3g}, {hi:.3g}] Hz for this bed (1e-9 to 1e9 over "
                f"its time scale 2 pi T), got {freq:g}"
            )
        orbit = pumped_orbit(s, pia, om)
        if orbit.status != 0:
            raise ArithmeticError(f"the pumped bed's periodic state: {orbit.message}")
        d = net_flow_derivatives(orbit, pia)
        qpf = s.q_per_flow
        value = float(np.mean(orbit.outputs["flow_rate"])) / qpf
        big_l, big_h, a = bed.length, bed.channel_height, bed.radius
        d_l, d_e = _ln("length", big_l), _ln("youngs_modulus", bed.youngs_modulus)
        d_a, d_eta = _ln("radius", a), _ln("viscosity", bed.viscosity)
        d_ln_area = _comb((2.0, d_a), (-1.0, _ln_phi(bed, hold)))  # A_h = pi a^2/phi
        held = {"length", "radius", hold}
        slopes = {k: v for k, v in _as_porous(bed)._drag_slopes(hold).items() if k in held}
        size = {"length": big_l, "radius": a, "spacing": bed.spacing, "packing_fraction":
                bed.packing_fraction}  # fmt: skip
        d_ln_kappa = {k: v[0] / float(size[k]) for k, v in slopes.items()}  # type: ignore[arg-type]
        d_gamma = {k: v[1] / float(size[k]) for k, v in slopes.items()}  # type: ignore[arg-type]
        # T = eta A_h L^2/(kappa E I), zeta_perp = eta A_h/(kappa L^2), I = pi a^4/4
        d_ln_t = _comb((1.0, d_eta), (1.0, d_ln_area), (2.0, d_l), (-1.0, d_ln_kappa),
                       (-1.0, d_e), (-4.0, d_a))  # fmt: skip
        d_ln_pia = _comb((1.0, d_ln_area), (3.0, d_l), (-1.0, d_e), (-4.0, d_a))
        d_ln_qpf = _comb((1.0, d_ln_area), (1.0, d_eta), (2.0, d_l), (-1.0, d_e), (-4.0, d_a),
                         (-2.0, _ln("channel_height", big_h)))  # fmt: skip
        d_ln_eps = _comb((1.0, d_l), (-1.0, _ln("channel_height", big_h)))
        terms = [
            (d["theta0"], {"base_angle": 1.0}),
            (d["gamma"], d_gamma),
            (d["kappa"] * s.kappa, d_ln_kappa),
            (d["eps"] * s.eps, d_ln_eps),
            (d["amplitude"] * pia, d_ln_pia),
            (d["ln_omega"], d_ln_t),
        ]
        rho_f = bed.density
        if s.womersley > 0.0 and rho_f is not None:  # alpha = rho L^2/(eta T)
            d_ln_rho = {"density": 1.0 / float(rho_f)}
            d_ln_alpha = _comb((1.0, d_ln_rho), (2.0, d_l), (-1.0, d_eta), (-1.0, d_ln_t))
            terms.append((d["alpha"] * s.womersley, d_ln_alpha))
        if s.inertia > 0.0 and rho_s is not None and rho_f is not None:
            # mu = (rho_s + rho_f) pi a^2/(zeta_perp T), chi = rho_s/(rho_s + rho_f)
            total = rho_s + float(rho_f)
            d_ln_zeta = _comb((1.0, d_eta), (1.0, d_ln_area), (-1.0, d_ln_kappa), (-2.0, d_l))
            d_ln_mu = _comb((1.0 / total, {"density": 1.0}), (2.0, d_a), (-1.0, d_ln_zeta),
                            (-1.0, d_ln_t))  # fmt: skip
            terms.append((d["mu"] * s.inertia, d_ln_mu))
            terms.append((-d["chi"] * rho_s / (total * total), {"density": 1.0}))
        elif s.inertia > 0.0:  # mu = rho_s pi a^2/(zeta_perp T), chi = 1
            d_ln_zeta = _comb((1.0, d_eta), (1.0, d_ln_area), (-1.0, d_ln_kappa), (-2.0, d_l))
            d_ln_mu = _comb((2.0, d_a), (-1.0, d_ln_zeta), (-1.0, d_ln_t))
            terms.append((d["mu"] * s.inertia, d_ln_mu))
        return value, _comb((1.0 / qpf, _comb(*terms)), (-value, d_ln_qpf))

    name = f"net_flow(A={amp:g} Pa, f={freq:g} Hz, l={length:g} m"
    name += ")" if rho_s is None else f", rho_s={rho_s:g} kg/m^3)"
    return Quantity(name, "bed", "m^2/s", True, evaluate, porous=True)


def gap_reynolds(pressure_drop: float, channel_length: float) -> Quantity:
    """The gap flow's Reynolds number rho u_max g/eta = rho abs(G) g^3/(8 eta^2) [-] of the
    valve at the signed drop dp [Pa] over l [m] (the walls at rest: u_max = G g^2/(8 eta)),
    needs the bed's density; exact gradient.

    Parameters
    ----------
    pressure_drop : float
        dp, signed [Pa].
    channel_length : float
        l [m], > 0.

    Returns
    -------
    Quantity
        Of a HairBed (dense), unit [-].
    """
    neg = isinstance(pressure_drop, (int, float)) and pressure_drop < 0
    dp, length = _drop(abs(pressure_drop) if neg else pressure_drop, channel_length)
    index = 1 if neg else 0

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        if bed.density is None:
            raise ValueError(f"{'gap_reynolds'}: the bed has no density [kg/m^3]")
        gap, dgap = _valve_gaps(bed, dp, length, hold)[index]
        rho, eta = bed.density, bed.viscosity
        re = rho * (dp / length) * gap**3 / (8.0 * eta * eta)
        return re, _comb(
            (re / rho, {"density": 1.0}),
            (-2.0 * re / eta, {"viscosity": 1.0}),
            (3 * re / gap, dgap),
        )

    return Quantity(
        f"gap_reynolds(dp={-dp if neg else dp:g} Pa, l={length:g} m)", "bed", "-", True, evaluate
    )


def brinkman_ratio() -> Quantity:
    """sqrt(k)/L [-]: the depth the flow penetrates the bed over the hair length
    (:attr:`hairbed.HairBed.brinkman_length`, Drummond & Tahir's k); the dense-bed model
    needs it below :data:`hairbed.units.DENSE_BED_LIMIT` = 0.1. Exact gradient (the
    permeability's series differentiated by hand).

    Returns
    -------
    Quantity
        Of a HairBed, unit [-].
    """

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        phi = float(bed.packing_fraction)  # type: ignore[arg-type]
        series = (
            -math.log(phi) - 1.497 + 2.0 * phi - 0.5 * phi**2 - 0.739 * phi**4
            + 2.534 * phi**5 / (1.0 + 1.2758 * phi)
        )  # fmt: skip
        d_series = (
            -1.0 / phi + 2.0 - phi - 4.0 * 0.739 * phi**3
            + 2.534 * (5.0 * phi**4 * (1.0 + 1.2758 * phi) - 1.2758 * phi**5)
            / (1.0 + 1.2758 * phi) ** 2
        )  # fmt: skip
        d_ln_k_phi = d_series / series - 1.0 / phi  # d ln(k/a^2)/d phi
        value = bed.brinkman_length / bed.length
        grad = _comb(
            (value, _ln("radius", bed.radius)),
            (0.5 * value * d_ln_k_phi * phi, _ln_phi(bed, hold)),
            (-value, _ln("length", bed.length)),
        )
        return value, grad

    return Quantity("brinkman_ratio", "bed", "-", True, evaluate)


#: Folds of the bed's branch at t above this use the Legendre forms of the partials (their
#: rounding grows as 1/expit(t): about 1e-13 relative here), below it the Carlson forms.
FOLD_LEGENDRE_T = -8.0


def bistable_width() -> Quantity:
    """The width [m/s] of the wall speed window in which three states coexist, for flow
    towards +x (a window exists for base_angle < 0 and eps above the cusp,
    :func:`hairbed.branches.bistable_window`): (omega2_upper - omega2_lower) v*. 0 where
    the branch is monotone (no window: a plateau on which every point is stationary).

    Gradient exact: at a fold d omega^2/dt = 0, so d omega^2_fold/dp is the partial at
    fixed t of omega^2 = omega_eps^2 (1 - eps h1), from the branch's closed-form partials
    (:mod:`hairbed.sensitivity`), plus the chain rule through v*.

    Returns
    -------
    Quantity
        Of a HairBed (dense), unit [m/s].
    """

    def evaluate(bed: HairBed, hold: str) -> tuple[float, Grad]:
        eps, th = bed.eps, bed.base_angle
        f = folds(eps, th)
        if f.lower is None:
            return 0.0, {}
        ts = np.asarray([f.upper.t, f.lower.t], dtype=np.float64)  # type: ignore[union-attr]
        sol = _from_parameter(ts, eps, th)
        # folds lie at moderate forcing (t in [-4.6, 0.4] for theta0 >= -1.55): there the
        # Legendre forms' partials agree with the Carlson forms' to 6e-15 at a seventh of
        # their cost (no dual numbers); the Carlson forms below FOLD_LEGENDRE_T
        if float(np.min(ts)) > FOLD_LEGENDRE_T:
            _, _, d_th = _partials(ts, np.full(2, th), 1, 0, sol)
        else:
            _, _, d_th = _physical_partials(ts, np.full(2, th), sol)
        oe = np.asarray(sol.omega_eps, dtype=np.float64)
        h1 = np.asarray(sol.tip_height, dtype=np.float64)
        w = oe * oe * (1.0 - eps * h1)
        dw_eps = -oe * oe * h1
        dw_th = 2.0 * oe * d_th["omega_eps"] * (1.0 - eps * h1) - oe * oe * eps * d_th["h1"]
        scale = bed.velocity_scale
        width = float(w[0] - w[1])
        d_ln_eps = _comb(
            (1.0, _ln("length", bed.length)), (-1.0, _ln("channel_height", bed.channel_height))
        )
        d_ln_scale = _comb(
            (1.0, _ln("youngs_modulus", bed.youngs_modulus)),
            (2.0, _ln("radius", bed.radius)),
            (1.0, _ln("channel_height", bed.channel_height)),
            (1.0, _ln_phi(bed, hold)),
            (-2.0, _ln("length", bed.length)),
            (-1.0, _ln("viscosity", bed.viscosity)),
        )
        grad = _comb(
            (scale * float(dw_eps[0] - dw_eps[1]) * eps, d_ln_eps),
            (scale * float(dw_th[0] - dw_th[1]), {"base_angle": 1.0}),
            (scale * width, d_ln_scale),
        )
        return scale * width, grad

    return Quantity("bistable_width", "bed", "m/s", True, evaluate)


# -- the pillar ------------------------------------------------------------------------------


def _pillar_groups(p: Pillar) -> tuple[float, Grad, float, Grad]:
    """(K = Lambda/tau_w [1/Pa], d ln K/dp, gamma, d gamma/dp)."""
    big_l, a = p.length, p.radius
    s = math.log(2.0 * big_l / a) + 0.5
    ds = _comb((1.0, _ln("length", big_l)), (-1.0, _ln("radius", a)))
    d_ln_k = _comb(
        (1.0, _ln("drag_scale", p.drag_scale)),
        (4.0, _ln("length", big_l)),
        (-1.0, _ln("youngs_modulus", p.youngs_modulus)),
        (-4.0, _ln("radius", a)),
        (-1.0 / s, ds),
    )
    gamma = s / (2.0 * s - 2.0)
    d_gamma = _comb((-2.0 / (2.0 * s - 2.0) ** 2, ds))
    return p.forcing_per_stress, d_ln_k, gamma, d_gamma


def _state_rows(p: Pillar, sol: Any, tau: float, index: int = 0) -> tuple[float, float, Any]:
    """(x1, h1, out) of element ``index`` of the pillar's states ``sol`` (at tau_w [Pa], for
    the messages); out[o, i] = d output/d input in the kernel's order (outputs tip_height,
    tip_deflection, ...; inputs forcing, theta0, gamma, ...), exact."""
    prof = np.asarray(p._core_options[0])
    dp = _profile_derivative(p._core_profile, p.height_ratio)
    dprof = np.zeros((1, 1)) if dp is None else dp[None, :]
    with np.errstate(all="ignore"):
        out, status, _ = pillar_gradient_rows(sol, prof, dprof)
    if int(status[index]) != 0:
        raise ArithmeticError(f"the pillar's state at tau_w = {tau:g} Pa is at a fold")
    x1 = float(np.asarray(sol.tip_deflection).reshape(-1)[index])
    h1 = float(np.asarray(sol.tip_height).reshape(-1)[index])
    return x1, h1, out[:, :, index]


class _RowCache:
    """:func:`_pillar_rows` memoised per (pillar, tau_w), least recently used out first;
    :meth:`seed` stores rows computed elsewhere (the linear range's root)."""

    def __init__(self, size: int = 64) -> None:
        self._size = size
        self._rows: OrderedDict[tuple[Pillar, float], tuple[float, float, Any]] = OrderedDict()

    def __call__(self, p: Pillar, tau: float) -> tuple[float, float, Any]:
        """(x1, h1, out) of the pillar's state at tau_w [Pa] (:func:`_state_rows`)."""
        key = (p, tau)
        if key in self._rows:
            self._rows.move_to_end(key)
            return self._rows[key]
        st = p.deform(tau)
        if int(np.asarray(st.status)) < 0:
            raise ArithmeticError(
                f"no state of the pillar at wall_shear_stress tau_w = {tau:g} Pa"
            )
        rows = _state_rows(p, st.solution, tau)
        self.seed(p, tau, rows)
        return rows

    def seed(self, p: Pillar, tau: float, rows: tuple[float, float, Any]) -> None:
        """Remember the rows of the state at tau_w [Pa]."""
        self._rows[(p, tau)] = rows
        self._rows.move_to_end((p, tau))
        while len(self._rows) > self._size:
            self._rows.popitem(last=False)

    def cache_clear(self) -> None:
        """Forget every state."""
        self._rows.clear()


_pillar_rows = _RowCache()


def _d_state(p: Pillar, row: Any, lam: float, d_ln_lam: Grad, d_gamma: Grad) -> Grad:
    """d(output)/dp of one output's row (d/dLambda, d/dtheta0, d/dgamma, ...)."""
    return _comb(
        (float(row[0]) * lam, d_ln_lam),
        (float(row[1]), {"base_angle": 1.0}),
        (float(row[2]), d_gamma),
    )


def _stress(spec: Any) -> Any:
    """A stress tau_w [Pa] (a number) or the end of a linear range (a :class:`Quantity`
    of :func:`linear_range`)."""
    if isinstance(spec, Quantity):
        if not spec.name.startswith("linear_range"):
            raise ValueError(
                f"a stress must be a number [Pa] or a linear_range(...) quantity, got {spec.name}"
            )
        return spec
    return _number(spec, "wall_shear_stress [Pa]")


def _stress_value(p: Pillar, spec: Any, hold: str) -> tuple[float, Grad]:
    if isinstance(spec, Quantity):
        return spec._evaluate(p, hold)
    return spec, {}


def _stress_name(spec: Any) -> str:
    return spec.name if isinstance(spec, Quantity) else f"{spec:g} Pa"


def tip_deflection(wall_shear_stress: Any) -> Quantity:
    """The pillar's tip deflection x1 L [m] at tau_w [Pa] (or at the end of a
    :func:`linear_range`), exact gradient (the collocation's implicit derivatives).

    Parameters
    ----------
    wall_shear_stress : float or Quantity
        tau_w [Pa], or a linear_range(...) quantity: at the end of that range.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [m].
    """
    spec = _stress(wall_shear_stress)

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        tau, d_tau = _stress_value(p, spec, hold)
        k, d_ln_k, _, d_gamma = _pillar_groups(p)
        x1, _, out = _pillar_rows(p, tau)
        d_ln_lam = _comb((1.0, d_ln_k), (1.0 / tau, d_tau))
        dx1 = _d_state(p, out[1], k * tau, d_ln_lam, d_gamma)
        return p.length * x1, _comb((x1, {"length": 1.0}), (p.length, dx1))

    return Quantity(
        f"tip_deflection({_stress_name(spec)})", "pillar", "m", True, evaluate, (("stress", spec),)
    )


def _scalar_state(p: Pillar, lam: float, th: float, gamma: float, tau: float) -> Any:
    """The pillar's one state at Lambda, theta0, gamma (tau_w [Pa] for the message)."""
    args = (np.array(lam), np.array(th), np.array(gamma), np.zeros(()))
    sol = _solve_pillar_checked(*args, *p._core_options)
    if int(np.asarray(sol.status)) < 0:
        raise ArithmeticError(
            f"no state of the pillar at wall_shear_stress tau_w = {tau:g} Pa: {sol.message}"
        )
    return sol


def sensitivity(wall_shear_stress: float) -> Quantity:
    """The pillar's sensitivity d(tip deflection)/d(tau_w) = L (dx1/dLambda) Lambda/tau_w
    [m/Pa] at tau_w [Pa] (:meth:`hairbed.Pillar.sensitivity`, its value exact).

    Gradient exact: a second derivative of the state, d(dx1/dLambda)/d(Lambda, theta0,
    gamma), from the implicit function theorem differentiated once more,
    J u_Lk = -R''[(u_k, e_k), (u_L, e_L)] with R'' the residual's second derivative
    along the total directions, on second-order jets
    (``hairbed.design._pillar_second``), chained to the SI parameters.

    Parameters
    ----------
    wall_shear_stress : float
        tau_w [Pa], > 0.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [m/Pa].
    """
    tau = _number(wall_shear_stress, "wall_shear_stress [Pa]")

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        k, d_ln_k, gamma, d_gamma = _pillar_groups(p)
        lam, th = k * tau, p.base_angle
        sol = _scalar_state(p, lam, th, gamma, tau)
        s0 = float(sol.tip_deflection_slope)
        _, parts = slope_gradient(sol, np.asarray(p._core_options[0])[0])
        value = p.length * s0 * k
        ds = _d_state(p, parts, lam, d_ln_k, d_gamma)
        grad = _comb((s0 * k, {"length": 1.0}), (p.length * k, ds), (value, d_ln_k))
        return value, grad

    return Quantity(
        f"sensitivity({tau:g} Pa)", "pillar", "m/Pa", True, evaluate, (("stress", tau),)
    )


def linear_sensitivity() -> Quantity:
    """The pillar's sensitivity at small stress, L c1 Lambda/tau_w [m/Pa], c1 =
    11 cos^3(theta0)/120 (the linear calibration, :attr:`hairbed.Pillar.linear_coefficient`,
    sublayer and Couette profiles): the limit of :func:`sensitivity` as tau_w -> 0, a closed
    form with an exact gradient.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [m/Pa].
    """

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        k, d_ln_k, _, _ = _pillar_groups(p)
        th = p.base_angle
        c1 = 11.0 * math.cos(th) ** 3 / 120.0
        dc1 = -33.0 * math.cos(th) ** 2 * math.sin(th) / 120.0
        value = p.length * c1 * k
        return value, _comb(
            (c1 * k, {"length": 1.0}), (p.length * k * dc1, {"base_angle": 1.0}), (value, d_ln_k)
        )

    return Quantity("linear_sensitivity", "pillar", "m/Pa", True, evaluate)


def bandwidth(wall_shear_stress: float) -> Quantity:
    """The corner frequency [Hz] of the pillar's slowest mode about its state at tau_w [Pa]:
    -Re(lambda_1)/(2 pi T), T = zeta_perp L^4/(E I) = eta Lambda/tau_w, lambda_1 the slowest
    eigenvalue of the overdamped linear dynamics (:func:`hairbed.dynamics.linearise_pillar`,
    inertia neglected, mu = 0: valid while the pillar's inertia number is small). At rest
    and upright lambda_1 = -12.362 (1 + cos b cosh b = 0).

    Gradient exact: the eigenvalue's derivative d lambda = w^H (dJ - lambda dB) v/(w^H B v)
    (w, v its left and right eigenvectors) with the total derivatives of the reduced
    pencil's J and B in (Lambda, theta0, gamma) (the state's implicit derivatives and the
    operators' second derivatives on jets, ``hairbed.design._pillar_second``), chained
    through T.

    Parameters
    ----------
    wall_shear_stress : float
        tau_w [Pa] of the state the pillar is linearised about.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [Hz].
    """
    tau = _number(wall_shear_stress, "wall_shear_stress [Pa]", positive=False)

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        from ..dynamics import linearise_pillar

        k, d_ln_k, gamma, d_gamma = _pillar_groups(p)
        lam, th = k * tau, p.base_angle
        sol = _scalar_state(p, lam, th, gamma, tau)
        lin = linearise_pillar(sol, profile=p._core_profile, height_ratio=p.height_ratio)
        r0 = float(-lin.modes(1).eigenvalues[0].real)
        _, d_lam1 = mode_gradient(sol, np.asarray(lin._prof), lin._degree())
        t_scale = p.viscosity * k
        value = r0 / (2.0 * math.pi * t_scale)
        dr = _d_state(p, -d_lam1.real[:3], lam, d_ln_k, d_gamma)
        return value, _comb(
            (value / r0, dr), (-value, d_ln_k), (-value / p.viscosity, {"viscosity": 1.0})
        )

    return Quantity(f"bandwidth({tau:g} Pa)", "pillar", "Hz", True, evaluate, (("stress", tau),))


def resonance_frequency(wall_shear_stress: float, pillar_density: float) -> Quantity:
    """The ringing frequency [Hz] of the pillar's slowest mode about its state at tau_w
    [Pa], with its inertia: Im(lambda_1)/(2 pi T), lambda_1 the slowest eigenvalue of the
    linear dynamics (:func:`hairbed.dynamics.linearise_pillar`) with the quasi-steady
    resistive drag and the inertia number mu = m E I/(zeta_perp^2 L^4), m = (rho_s + rho_f)
    pi a^2 (the fluid's added mass), tangential mass ratio chi = rho_s/(rho_s + rho_f), as
    :func:`hairbed.sensor_dynamics.frequency_response` with ``drag="quasi-steady"``; T =
    zeta_perp L^4/(E I). It is the damped natural frequency of the slowest mode (the peak of
    abs(H) of :attr:`~hairbed.sensor_dynamics.SensorResponse.resonance_frequency` lies near
    it for a light damping, below it by a factor sqrt(1 - 2 zeta^2) for a single mode). An
    overdamped slowest mode (mu below about 1/(4 beta_1^4) = 0.02) has none: an
    ArithmeticError.

    Gradient exact: the eigenvalue's derivative w^H (dA - lambda dE) v/(w^H E v) of the
    first-order pencil A = [[0, I], [J, -B]], E = [[I, 0], [0, mu M]] in (Lambda, theta0,
    gamma, mu, chi) (``hairbed.design._pillar_second``), chained through mu, chi and T.

    Parameters
    ----------
    wall_shear_stress : float
        tau_w [Pa] of the state the pillar is linearised about.
    pillar_density : float
        rho_s [kg/m^3], > 0, of the pillar's material (the fluid's density is the
        pillar's ``density``, needed).

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [Hz].
    """
    tau = _number(wall_shear_stress, "wall_shear_stress [Pa]", positive=False)
    rho_s = _number(pillar_density, "pillar_density [kg/m^3]")

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        from ..dynamics import linearise_pillar

        if p.density is None:
            raise ValueError("resonance_frequency: the pillar has no (fluid) density [kg/m^3]")
        rho_f = float(p.density)
        k, d_ln_k, gamma, d_gamma = _pillar_groups(p)
        lam, th = k * tau, p.base_angle
        sol = _scalar_state(p, lam, th, gamma, tau)
        t_scale = p.viscosity * k
        big_l, a, e = p.length, p.radius, p.youngs_modulus
        mass = (rho_s + rho_f) * math.pi * a * a
        mu = mass * big_l**4 / (p.viscosity**2 * k * k * p.bending_stiffness)
        chi = rho_s / (rho_s + rho_f)
        if not (math.isfinite(mu) and chi > 0.0):
            raise ValueError(
                f"pillar_density = {rho_s:g} kg/m^3 is out of range for this pillar: the "
                f"inertia number mu = {mu:.4g} or the mass ratio rho_s/(rho_s + rho_f) = "
                f"{chi:.4g} leaves double precision"
            )
        lin = linearise_pillar(
            sol, profile=p._core_profile, height_ratio=p.height_ratio, mu=mu, tangential_mass=chi
        )
        eig = lin.modes(2).eigenvalues
        if eig.size == 0:
            raise ArithmeticError(
                f"resonance_frequency: no mode of the pillar found at the inertia number mu = "
                f"{mu:.4g} (pillar_density = {rho_s:g} kg/m^3)"
            )
        lam1 = complex(eig[0])
        if not lam1.imag > 0.0:
            raise ArithmeticError(
                f"resonance_frequency: the pillar's slowest mode at tau_w = {tau:g} Pa is "
                f"overdamped (lambda_1 = {lam1.real:.6g} [1/T], inertia number mu = {mu:.3g}): "
                "no resonance"
            )
        _, g = mode_gradient(sol, np.asarray(lin._prof), lin._degree(), mu, chi)
        value = lam1.imag / (2.0 * math.pi * t_scale)
        d_ln_t = _comb((1.0, d_ln_k), (1.0, _ln("viscosity", p.viscosity)))
        d_ln_mu = _comb(
            (1.0 / (rho_s + rho_f), {"density": 1.0}),
            (-2.0, _ln("radius", a)),
            (4.0, _ln("length", big_l)),
            (-2.0, _ln("viscosity", p.viscosity)),
            (-2.0, d_ln_k),
            (-1.0, _ln("youngs_modulus", e)),
        )
        d_im = _comb(
            (1.0, _d_state(p, g.imag[:3], lam, d_ln_k, d_gamma)),
            (float(g.imag[3]) * mu, d_ln_mu),
            (-float(g.imag[4]) * chi / (rho_s + rho_f), {"density": 1.0}),  # d chi/d rho_f
        )
        return value, _comb((1.0 / (2.0 * math.pi * t_scale), d_im), (-value, d_ln_t))

    return Quantity(
        f"resonance_frequency({tau:g} Pa, rho_s={rho_s:g} kg/m^3)",
        "pillar",
        "Hz",
        True,
        evaluate,
        (("stress", tau),),
    )


def snap_window() -> Quantity:
    """The width [Pa] of the pillar's snap-through window in the wall shear stress:
    (Lambda_u - Lambda_l)/K, K = Lambda/tau_w, Lambda_u and Lambda_l its upper and lower
    folds, for flow towards +x (a window exists for a pillar tilted far upstream, base_angle
    below about -1.3; :func:`hairbed.dynamics.snap_through`). 0 where the branch does not
    fold (a plateau on which every point is stationary: a design needs several starts).

    The folds are followed from pillar to pillar by the secant method on dLambda/dx1 along
    the branch, or found by a scan of it (``hairbed.design._pillar_window``). Gradient
    exact: at a fold dLambda_f/dp = -(w . R_p)/(w . R_Lambda), w the left null vector of
    the collocation's Jacobian there (the implicit function theorem on the extended
    system), chained through K.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [Pa].
    """
    trackers: dict[Any, WindowTracker] = {}
    folds: dict[Any, Any] = {}

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        key = (p.profile, p.height_ratio)
        if key not in trackers:
            trackers[key] = WindowTracker(p._core_profile, p.height_ratio)
        k, d_ln_k, gamma, d_gamma = _pillar_groups(p)
        at = (key, p.base_angle, gamma)  # the folds depend on theta0 and gamma alone
        if at not in folds:
            found = trackers[key].folds(p.base_angle, gamma)
            prof = np.asarray(p._core_options[0])[0]
            folds[at] = None if found is None else [fold_gradient(found, i, prof) for i in (0, 1)]
            while len(folds) > 256:
                folds.pop(next(iter(folds)))
        if folds[at] is None:
            return 0.0, {}
        (lam_u, g_u), (lam_l, g_l) = folds[at]
        width = (lam_u - lam_l) / k
        d_lam = _comb(
            (float(g_u[0] - g_l[0]), {"base_angle": 1.0}), (float(g_u[1] - g_l[1]), d_gamma)
        )
        return width, _comb((1.0 / k, d_lam), (-width, d_ln_k))

    q = Quantity("snap_window", "pillar", "Pa", True, evaluate)
    object.__setattr__(q, "_trackers", trackers)
    return q


def linear_range(rtol: float = 0.1) -> Quantity:
    """The end tau* [Pa] of the pillar's linear range (:meth:`hairbed.Pillar.linear_range`):
    where the linear calibration's relative error first reaches ``rtol`` in (0, 1).

    Gradient exact: tau* = Lambda*/K with Lambda* the root of
    G = (x1(Lambda, theta0, gamma) - sin theta0)/(c1(theta0) Lambda) - 1 -+ rtol, so
    d Lambda* = -(G_theta0 d theta0 + G_gamma d gamma)/G_Lambda (implicit function theorem,
    the state's exact first derivatives), c1 = 11 cos^3(theta0)/120.

    Its value is :meth:`~hairbed.Pillar.linear_range`'s: the full scan at the first pillar,
    then Lambda* followed by Newton's method from the root of the nearest pillar solved
    before (``hairbed.design._linear_range.LinearRangeTracker``, checked to stay the
    first root; a failed check scans again), the same root to 1e-10.

    Parameters
    ----------
    rtol : float
        The linear calibration's relative error that ends the range, in (0, 1) [-].

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [Pa].
    """
    tol = _number(rtol, "rtol")
    if not tol < 1.0:
        raise ValueError(f"rtol must lie in (0, 1), got {show(tol)}")

    tracker = LinearRangeTracker(tol)

    @functools.lru_cache(maxsize=16)
    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        tau, state = tracker(p)
        if state is not None:  # Newton's root: its state is the batch's last
            _pillar_rows.seed(p, tau, _state_rows(p, state, tau, -1))
        k, d_ln_k, _, d_gamma = _pillar_groups(p)
        lam = k * tau
        x1, _, out = _pillar_rows(p, tau)
        th = p.base_angle
        c1 = 11.0 * math.cos(th) ** 3 / 120.0
        dc1 = -33.0 * math.cos(th) ** 2 * math.sin(th) / 120.0
        rel = x1 - math.sin(th)
        row = out[1]
        g_lam = row[0] / (c1 * lam) - rel / (c1 * lam * lam)
        g_th = (row[1] - math.cos(th)) / (c1 * lam) - rel * dc1 / (c1 * c1 * lam)
        g_gam = row[2] / (c1 * lam)
        d_lam = _comb((-g_th / g_lam, {"base_angle": 1.0}), (-g_gam / g_lam, d_gamma))
        return tau, _comb((1.0 / k, d_lam), (-tau, d_ln_k))

    q = Quantity(f"linear_range(rtol={tol:g})", "pillar", "Pa", True, evaluate)
    object.__setattr__(q, "_tracker", tracker)
    return q


def l_plus(wall_shear_stress: Any) -> Quantity:
    """The pillar's height in wall units L+ = L sqrt(abs(tau_w) rho)/eta [-] at tau_w [Pa]
    (or the end of a :func:`linear_range`); needs the density. Exact gradient.

    Parameters
    ----------
    wall_shear_stress : float or Quantity
        tau_w [Pa], or a linear_range(...) quantity.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [-].
    """
    spec = _stress(wall_shear_stress)

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        if p.density is None:
            raise ValueError("l_plus: the pillar has no density [kg/m^3]")
        tau, d_tau = _stress_value(p, spec, hold)
        rho, eta = p.density, p.viscosity
        # sqrt(|tau_w|) sqrt(rho): no overflow of the product near the largest double
        value = p.length * math.sqrt(abs(tau)) * math.sqrt(rho) / eta
        return value, _comb(
            (value / p.length, {"length": 1.0}),
            (0.5 * value / rho, {"density": 1.0}),
            (-value / eta, {"viscosity": 1.0}),
            (0.5 * value / tau, d_tau),
        )

    return Quantity(f"l_plus({_stress_name(spec)})", "pillar", "-", True, evaluate)


def pillar_reynolds(wall_shear_stress: Any) -> Quantity:
    """The pillar Reynolds number rho abs(u(tip)) 2a/eta = 2 rho abs(tau_w) L a h1/eta^2 [-]
    at tau_w [Pa] (u(tip) = tau_w h1 L/eta for the sublayer and Couette profiles); needs the
    density. Exact gradient.

    Parameters
    ----------
    wall_shear_stress : float or Quantity
        tau_w [Pa], or a linear_range(...) quantity.

    Returns
    -------
    Quantity
        Of a Pillar ("sublayer" or "couette" profile), unit [-].
    """
    spec = _stress(wall_shear_stress)

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        if p.density is None:
            raise ValueError("pillar_reynolds: the pillar has no density [kg/m^3]")
        tau, d_tau = _stress_value(p, spec, hold)
        k, d_ln_k, _, d_gamma = _pillar_groups(p)
        _, h1, out = _pillar_rows(p, tau)
        d_ln_lam = _comb((1.0, d_ln_k), (1.0 / tau, d_tau))
        dh1 = _d_state(p, out[0], k * tau, d_ln_lam, d_gamma)
        rho, eta = p.density, p.viscosity
        value = 2.0 * rho * abs(tau) * p.length * p.radius * h1 / (eta * eta)
        return value, _comb(
            (value / rho, {"density": 1.0}),
            (-2.0 * value / eta, {"viscosity": 1.0}),
            (value / p.length, {"length": 1.0}),
            (value / p.radius, {"radius": 1.0}),
            (value / h1, dh1),
            (value / tau, d_tau),
        )

    return Quantity(f"pillar_reynolds({_stress_name(spec)})", "pillar", "-", True, evaluate)


def slenderness() -> Quantity:
    """The pillar's slenderness L/a [-] (resistive-force drag needs it above
    :data:`hairbed.pillars.SLENDERNESS_LIMIT` = 10). Exact gradient.

    Returns
    -------
    Quantity
        Of a Pillar, unit [-].
    """

    def evaluate(p: Pillar, hold: str) -> tuple[float, Grad]:
        s = p.length / p.radius
        return s, {"length": 1.0 / p.radius, "radius": -s / p.radius}

    return Quantity("slenderness", "pillar", "-", True, evaluate)


# -- the user's ------------------------------------------------------------------------------


def custom(
    function: Callable[[Any], float],
    name: str = "custom",
    *,
    gradient: Callable[[Any], dict[str, float]] | None = None,
    unit: str = "",
) -> Quantity:
    """A user's quantity: ``function(model) -> float``, called ``name`` in results and
    messages, in the units ``unit`` (a label only, e.g. "Pa"; "" for none).

    With ``gradient(model) -> {parameter: d value/d parameter}`` (SI) the gradient is the
    user's (``exact`` True: the user vouches for it); without, it is a central difference
    in each design variable (relative step :data:`FD_STEP`) and ``exact`` is False.
    """
    if not callable(function):
        raise TypeError(f"custom: function must be callable, got {show(function)}")
    if gradient is not None and not callable(gradient):
        raise TypeError(f"custom: gradient must be callable or None, got {show(gradient)}")
    for label, text in (("name", name), ("unit", unit)):
        if not isinstance(text, str):
            raise TypeError(f"custom: {label} must be a string, got {show(text)}")

    def value_of(model: Any) -> float:
        try:
            v = float(function(model))
        except Exception as exc:
            raise ValueError(f"{name}: the function raised {type(exc).__name__}: {exc}") from exc
        if not math.isfinite(v):
            raise ArithmeticError(f"{name}: the function returned {v!r}")
        return v

    def evaluate(model: Any, hold: str) -> tuple[float, Grad]:
        v = value_of(model)
        if gradient is None:
            return v, {}
        return v, {k: float(x) for k, x in dict(gradient(model)).items()}

    q = Quantity(name, "any", unit, gradient is not None, evaluate)
    object.__setattr__(q, "_value_of", value_of)
    return q


# -- validity --------------------------------------------------------------------------------


def validity_constraints(model: Any, quantities: Any) -> tuple[list[Constraint], list[str]]:
    """The model-validity constraints of a design whose objectives and constraints are
    ``quantities``, and notes of the checks that could not be made.

    A bed: sqrt(k)/L <= 0.1 (the dense bed), and the gap Reynolds number <= 1 at +-dp of
    every valve quantity (with a density). A pillar: L/a >= 10, and at every stress a
    quantity uses, the pillar Reynolds number <= 0.5 and, for the sublayer profile,
    L+ <= 5 (with a density).
    """
    if not isinstance(model, (HairBed, Pillar)):
        raise TypeError(f"model must be a hairbed.HairBed or hairbed.Pillar, got {show(model)}")
    if isinstance(quantities, Quantity):
        quantities = [quantities]
    if (
        isinstance(quantities, (str, bytes, dict))
        or not np.iterable(quantities)
        or not all(isinstance(q, Quantity) for q in quantities)
    ):
        raise TypeError(
            f"quantities must be a sequence of hairbed.design quantities, got {show(quantities)}"
        )
    quantities = list(quantities)
    out: list[Constraint] = []
    notes: list[str] = []
    if isinstance(model, HairBed) and model.model == "porous":
        # the porous (Brinkman) bed holds at any depth of penetration; its packing fraction's
        # bound (Drummond & Tahir's permeabilities) is refused up front by the Space
        if any(o[0] == "valve" for q in quantities for o in q.operating):
            notes.append(
                "the gap Reynolds number of the porous bed's valve is not checked (a "
                "constraint of it is not built yet)"
            )
    elif isinstance(model, HairBed):
        out.append(Constraint(brinkman_ratio(), upper=DENSE_BED_LIMIT, validity=True))
        if any(q.name == "bistable_width" for q in quantities):
            notes.append(
                "the Reynolds number of the wall-driven flow at the bistable window is not "
                "checked (a constraint of it is not built yet)"
            )
        drops = sorted({(o[1], o[2]) for q in quantities for o in q.operating if o[0] == "valve"})
        for dp, length in drops:
            if model.density is None:
                notes.append(f"gap Reynolds number at +-{dp:g} Pa unchecked: no density")
                continue
            for s in (dp, -dp):
                out.append(
                    Constraint(gap_reynolds(s, length), upper=GAP_REYNOLDS_LIMIT, validity=True)
                )
    elif isinstance(model, Pillar):
        out.append(Constraint(slenderness(), lower=SLENDERNESS_LIMIT, validity=True))
        if any(q.name == "snap_window" for q in quantities):
            notes.append(
                "the pillar Reynolds number and L+ at the snap-through window's folds are not "
                "checked (a constraint of them is not built yet)"
            )
        stresses: list[Any] = []
        for q in quantities:
            for o in q.operating:
                if o[0] == "stress" and not any(o[1] is s or o[1] == s for s in stresses):
                    stresses.append(o[1])
            if q.name.startswith("linear_range") and not any(q is s for s in stresses):
                stresses.append(q)
        for s in stresses:
            if model.density is None:
                notes.append(
                    f"pillar Reynolds number, L+ at {_stress_name(s)} unchecked: no density"
                )
                continue
            out.append(Constraint(pillar_reynolds(s), upper=PILLAR_REYNOLDS_LIMIT, validity=True))
            if model.profile == "sublayer":
                out.append(Constraint(l_plus(s), upper=SUBLAYER_L_PLUS_LIMIT, validity=True))
    return out, notes
