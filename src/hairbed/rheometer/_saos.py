"""Small-amplitude oscillatory shear of the porous bed about a pre-stress (issue 31 §2a).

The rheometer moves the top wall; the strain is the wall's displacement over the channel's
height, gamma = delta/H, so the wall's speed is V = H gamma_dot. About the steady state of a
constant wall forcing omega2* (the pre-stress: the top wall's steady stress sigma* =
Q(H)), a small oscillation gamma = Re(gamma_hat e^{i omega t}) moves the forcing
omega2 = eta V A L^2/(E I H) = kappa eps V (V in L/T, lengths in L, H = L/eps) by
kappa i omega gamma_hat, so the complex modulus is

    G*(omega) = G' + i G'' = i omega kappa H_Q(omega)   [E I/(A L^2)],

H_Q the linear bed's transfer function from the wall forcing to the top wall's stress
(:func:`hairbed.dynamics.linearise_bed`; time in T = zeta_perp L^4/(E I), stresses in §13's
load units Q = A L^2 eta u_z/(E I), so a modulus in E I/(A L^2)). A bare Newtonian channel
gives G* = i omega kappa: G'' = eta omega in these units.

**Lag and lead.** The phase of the stress against the wall's speed, arg G* - pi/2, is
negative where the stress lags the speed (G' > 0: the hairs' elasticity stores energy) and
positive where it leads (G' < 0: the inertia of the fluid, or of the hairs, dominates). The
**lead crossover** is the frequency where G' changes sign; the **modulus crossover** where
G' = G''. Both are set by the groups of the model (theory.md §13-§15): kappa = eta A/(zeta_perp
L^2) (the fluid's viscosity against the hairs' drag), the Womersley number alpha =
rho_f L^2/(eta T) (the fluid's inertia), the inertia number mu = m/(zeta_perp T) (the hairs'),
the confinement eps = L/H, the tilt theta0, the drag ratio gamma and the pre-stress's forcing
omega2*; the time unit T = zeta_perp L^4/(E I) carries the hairs' elasticity. Without any
inertia (alpha = mu = 0) G' >= 0 at every frequency: no lead.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from dataclasses import replace as dataclasses_replace
from typing import Any, ClassVar

import numpy as np
import scipy.optimize
from numpy.typing import ArrayLike, NDArray

from .._bed_scales import _scales
from .._core.porous import solve_porous
from .._core.validation import StatusResult, as_float_array, check_number, show
from ..bed_simulation import _within_range
from ..dynamics import LinearBed, linearise_bed
from ..units import HairBed

__all__ = ["SAOS_STATUS", "BedModuli", "OscillatoryShear", "bed_moduli", "oscillatory_shear"]

FloatArray = NDArray[np.float64]

#: Status codes of :class:`OscillatoryShear` (per frequency and pre-stress).
SAOS_STATUS = {
    0: "ok",
    3: "inaccurate: the frequency is beyond the linear bed's resolution (N or M > 128)",
    -1: "no steady state at this pre-stress's forcing (solve_porous failed)",
}
_MODULUS_UNITS = "E I/(A L^2)"
#: The rheometer's ranges: kappa (its states converge on the dynamics' grid, N <= 128), the
#: smallest eps = L/H, and omega [1/T] of the bed in time.
KAPPA_RANGE = (1e-4, 1e6)
EPS_MIN = 1e-6
OMEGA_RANGE = (1e-9, 1e9)


@dataclass(frozen=True)
class OscillatoryShear(StatusResult):
    """The bed's moduli over frequency and pre-stress (:func:`oscillatory_shear`).

    Arrays are (frequency, pre_stress).

    Attributes
    ----------
    omega : ndarray
        Angular frequencies [1/T].
    forcing : ndarray
        The steady wall forcings omega2* of the pre-stresses [-].
    pre_stress : ndarray
        The top wall's steady stress at each forcing [E I/(A L^2)] (§13's Q(H)).
    storage, loss : ndarray
        G', G'' [E I/(A L^2)].
    phase : ndarray
        arg G* [rad]: the stress's phase against the strain.
    lead : ndarray
        arg G* - pi/2 [rad]: the stress's phase against the wall's speed (< 0 lag, > 0 lead).
    lead_crossover, modulus_crossover : ndarray
        Per pre-stress, the lowest frequency [1/T] in the range where G' changes sign and
        where G' = G'' (Brent's method on the linear response); NaN where there is none.
    kappa, eps, theta0, gamma, inertia, womersley : float
        The bed.
    status : ndarray of int
        ``SAOS_STATUS`` (frequency, pre_stress).
    """

    omega: FloatArray
    forcing: FloatArray
    pre_stress: FloatArray
    storage: FloatArray
    loss: FloatArray
    phase: FloatArray
    lead: FloatArray
    lead_crossover: FloatArray
    modulus_crossover: FloatArray
    kappa: float
    eps: float
    theta0: float
    gamma: float
    inertia: float
    womersley: float
    status: NDArray[np.int64]

    _status_table: ClassVar[Mapping[int, str]] = SAOS_STATUS

    @property
    def loss_tangent(self) -> FloatArray:
        """tan(delta) = G''/G' [-]."""
        return self.loss / self.storage

    def to_xarray(self) -> Any:
        """An xarray.Dataset with dimensions ``frequency`` and ``pre_stress`` (CF units and
        long names; the crossovers on ``pre_stress``). Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "OscillatoryShear.to_xarray", "io")
        dims = ("frequency", "pre_stress")

        def att(units: str, name: str) -> dict[str, str]:
            return {"units": units, "long_name": name}

        return xr.Dataset(
            {
                "storage": (dims, self.storage, att(_MODULUS_UNITS, "storage modulus G'")),
                "loss": (dims, self.loss, att(_MODULUS_UNITS, "loss modulus G''")),
                "phase": (dims, self.phase, att("rad", "stress phase against the strain")),
                "lead": (dims, self.lead, att("rad", "stress phase against the wall speed")),
                "status": (dims, self.status, att("1", "status")),
                "lead_crossover": (
                    "pre_stress",
                    self.lead_crossover,
                    att("1/T", "frequency where G' changes sign (lag to lead)"),
                ),
                "modulus_crossover": (
                    "pre_stress",
                    self.modulus_crossover,
                    att("1/T", "frequency where G' = G''"),
                ),
            },
            coords={
                "frequency": (
                    "frequency",
                    self.omega,
                    att("1/T", "angular frequency, T = zeta_perp L^4/(E I)"),
                ),
                "pre_stress": (
                    "pre_stress",
                    self.pre_stress,
                    att(_MODULUS_UNITS, "the top wall's steady shear stress"),
                ),
                "forcing": (
                    "pre_stress",
                    self.forcing,
                    att("1", "steady wall forcing omega2 = eta V A L^2/(E I H)"),
                ),
            },
            attrs={
                "title": "hairbed porous bed: small-amplitude oscillatory shear",
                "kappa": self.kappa,
                "eps": self.eps,
                "theta0": self.theta0,
                "gamma": self.gamma,
                "inertia": self.inertia,
                "womersley": self.womersley,
                "strain": "top wall displacement / channel height",
                "time_convention": "exp(i omega t)",
                "Conventions": "CF-1.10",
            },
        )  # fmt: skip


def _modulus(lin: LinearBed, omega: FloatArray) -> tuple[Any, Any]:
    fr = lin.frequency_response(omega, "wall")
    return 1j * omega * float(lin.state.kappa) * fr.wall_stress, fr.status


def _crossing(lin: LinearBed, om: FloatArray, f: FloatArray, which: str) -> float:
    """The lowest frequency of a sign change of f (G' or G' - G'') on the grid, refined
    by Brent's method in log omega."""
    sign = np.sign(f)
    idx = np.flatnonzero(sign[:-1] * sign[1:] < 0)
    if idx.size == 0:
        return math.nan
    i = int(idx[0])

    def fun(x: float) -> float:
        g = _modulus(lin, np.array([math.exp(x)]))[0][0]
        return float(g.real if which == "lead" else g.real - g.imag)

    return math.exp(
        scipy.optimize.brentq(fun, math.log(om[i]), math.log(om[i + 1]), xtol=1e-13, rtol=1e-13)
    )


def oscillatory_shear(
    omega: ArrayLike,
    forcing: ArrayLike = 0.0,
    *,
    eps: float,
    kappa: float,
    theta0: float = 0.0,
    gamma: float = 1.0,
    inertia: float = 0.0,
    womersley: float = 0.0,
    tangential_mass: float = 1.0,
) -> OscillatoryShear:
    """Storage and loss moduli of the porous bed under small-amplitude oscillatory shear.

    Parameters
    ----------
    omega : array_like
        Angular frequencies [1/T] (T = zeta_perp L^4/(E I)), finite and > 0, increasing.
    forcing : array_like, optional
        The pre-stresses as steady wall forcings omega2* = eta V* A L^2/(E I H) [-] (default
        0: about the bed at rest); the pre-stress itself is the state's top wall stress.
    eps, kappa, theta0, gamma : float
        The bed (as :func:`hairbed.solve_porous`): L/H in (0, 1), kappa > 0, base angle
        [rad], drag ratio in (0, 1].
    inertia, womersley, tangential_mass : float, optional
        mu, alpha and chi of :func:`hairbed.dynamics.linearise_bed` (default 0, 0, 1).

    Returns
    -------
    OscillatoryShear
        G'(omega, sigma*), G''(omega, sigma*), the phases and the crossovers.

    Examples
    --------
    >>> import numpy as np
    >>> r = oscillatory_shear(np.array([0.1, 1.0]), eps=0.5, kappa=1.0)
    >>> bool(np.all(r.storage > 0)), bool(np.all(r.lead < 0))  # no inertia: the stress lags
    (True, True)
    """
    om = as_float_array(omega, "omega").reshape(-1)
    bad = (om <= 0.0) | ~np.isfinite(om)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"omega must be finite and > 0 [1/T], got {show(float(om[i]))} (first at index {i})"
        )
    if om.size > 1 and np.any(np.diff(om) <= 0.0):
        i = int(np.flatnonzero(np.diff(om) <= 0.0)[0]) + 1
        raise ValueError(f"omega must increase, got omega[{i}] <= omega[{i - 1}]")
    fo = as_float_array(forcing, "forcing").reshape(-1)
    e = check_number(eps, "eps", low=EPS_MIN, high=1.0, high_open=True)
    k = check_number(kappa, "kappa", low=KAPPA_RANGE[0], high=KAPPA_RANGE[1])
    th = check_number(theta0, "theta0", low=-math.pi / 2, high=math.pi / 2, low_open=True,
                      high_open=True)  # fmt: skip
    g = check_number(gamma, "gamma", low=0.0, high=1.0, low_open=True)
    mu = check_number(inertia, "inertia", low=0.0)
    alpha = check_number(womersley, "womersley", low=0.0)
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    shape = (om.size, fo.size)
    storage = np.full(shape, np.nan)
    loss = np.full(shape, np.nan)
    status = np.full(shape, -1, dtype=np.int64)
    pre = np.full(fo.size, np.nan)
    lead_x = np.full(fo.size, np.nan)
    mod_x = np.full(fo.size, np.nan)
    for j, w in enumerate(fo):
        st = solve_porous(float(w), e, th, kappa=k, gamma=g)
        if int(st.status) < 0:
            continue
        lin = linearise_bed(st, inertia=mu, womersley=alpha, tangential_mass=chi)
        gs, stat = _modulus(lin, om)
        storage[:, j], loss[:, j], status[:, j] = gs.real, gs.imag, stat
        pre[j] = float(st.tip_stress)  # the wall drive's top stress Q(H) = Q(h1) (Pi = 0)
        lead_x[j] = _crossing(lin, om, gs.real, "lead")
        mod_x[j] = _crossing(lin, om, gs.real - gs.imag, "modulus")
    phase = np.arctan2(loss, storage)
    return OscillatoryShear(
        omega=om,
        forcing=fo,
        pre_stress=pre,
        storage=storage,
        loss=loss,
        phase=phase,
        lead=phase - math.pi / 2,
        lead_crossover=lead_x,
        modulus_crossover=mod_x,
        kappa=k,
        eps=e,
        theta0=th,
        gamma=g,
        inertia=mu,
        womersley=alpha,
        status=status,
    )


@dataclass(frozen=True)
class BedModuli(StatusResult):
    """G'(f) and G''(f) of a :class:`hairbed.HairBed` in SI (:func:`bed_moduli`).

    Arrays are (frequency, pre_stress); an array bed's (issue 32) have its shape S in front
    (the crossovers and pre-stresses S + (pre_stress,), the scales S, ``dimensionless`` an
    object array of shape S); :meth:`item` gives one bed's moduli.

    Attributes
    ----------
    frequency : ndarray
        f [Hz].
    speed : ndarray
        The pre-stresses' steady wall speeds [m/s].
    pre_stress : ndarray
        The top wall's steady stress at each speed [Pa].
    storage, loss : ndarray
        G', G'' [Pa].
    lead : ndarray
        The stress's phase against the wall's speed [rad] (< 0 lag, > 0 lead).
    lead_crossover, modulus_crossover : ndarray
        Per pre-stress, the frequencies [Hz] where G' changes sign and where G' = G''.
    time_scale : float
        T = zeta_perp L^4/(E I) [s].
    modulus_scale : float
        E I/(A L^2) [Pa].
    dimensionless : OscillatoryShear
        The same in the bed's units (omega T, moduli over the modulus scale) with the groups
        kappa, eps, alpha, mu.
    """

    frequency: FloatArray
    speed: FloatArray
    pre_stress: FloatArray
    storage: FloatArray
    loss: FloatArray
    lead: FloatArray
    lead_crossover: FloatArray
    modulus_crossover: FloatArray
    time_scale: Any
    modulus_scale: Any
    dimensionless: Any
    #: The array bed of an array result (None for a bed of numbers).
    bed: Any = field(default=None, repr=False, compare=False)

    @property
    def shape(self) -> tuple[int, ...]:
        """The bed's shape: () for a bed of numbers (issue 32)."""
        return tuple(np.shape(self.time_scale))

    @property
    def status(self) -> NDArray[np.int64]:
        """``SAOS_STATUS`` (frequency, pre_stress), behind the bed's shape for an array
        bed."""
        if not self.shape:
            return self.dimensionless.status
        rows = np.stack([d.status for d in self.dimensionless.reshape(-1)])
        return rows.reshape(self.shape + rows.shape[1:])

    _status_table: ClassVar[Mapping[int, str]] = SAOS_STATUS

    def item(self, index: Any = ()) -> BedModuli:
        """The moduli of the bed at ``index`` of :attr:`shape` (as
        :meth:`hairbed.HairBed.item` indexes it); a bed of numbers' are themselves."""
        from .._model_axes import checked_index

        k = checked_index(index, self.shape, "result")
        if not self.shape:
            return self
        arrays: dict[str, Any] = {n: np.array(getattr(self, n)[k]) for n in _PER_BED}
        return dataclasses_replace(
            self,
            time_scale=float(self.time_scale[k]),
            modulus_scale=float(self.modulus_scale[k]),
            dimensionless=self.dimensionless[k],
            bed=None,
            **arrays,
        )

    def to_xarray(self) -> Any:
        """An xarray.Dataset with dimensions ``frequency`` [Hz] and ``pre_stress`` [Pa]. Needs
        the ``io`` extra. An array bed's moduli have its axes in front, named ``bed``
        (``bed_0``, ... for several), with the bed's array parameters as coordinates."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedModuli.to_xarray", "io")
        if self.shape:
            return self._array_xarray(xr)
        dims = ("frequency", "pre_stress")
        p, f = "pre_stress", "frequency"

        def att(units: str, name: str) -> dict[str, str]:
            return {"units": units, "long_name": name}

        return xr.Dataset(
            {
                "storage": (dims, self.storage, att("Pa", "storage modulus G'")),
                "loss": (dims, self.loss, att("Pa", "loss modulus G''")),
                "lead": (dims, self.lead, att("rad", "stress phase against the wall speed")),
                "status": (dims, self.status, att("1", "status")),
                "lead_crossover": (p, self.lead_crossover, att("Hz", "G' = 0")),
                "modulus_crossover": (p, self.modulus_crossover, att("Hz", "G' = G''")),
            },
            coords={
                "frequency": (f, self.frequency, att("Hz", "frequency")),
                "pre_stress": (p, self.pre_stress, att("Pa", "top wall's steady stress")),
                "speed": (p, self.speed, att("m s-1", "steady wall speed")),
            },
            attrs={
                "title": "hairbed bed in a rheometer (SI)",
                "time_scale_s": self.time_scale,
                "modulus_scale_Pa": self.modulus_scale,
                "Conventions": "CF-1.10",
            },
        )  # fmt: skip

    def _array_xarray(self, xr: Any) -> Any:
        """:meth:`to_xarray` of an array bed's moduli."""
        from .._model_axes import model_coords, model_dims

        beds = model_dims("bed", self.shape)
        dims, p = (*beds, "frequency", "pre_stress"), (*beds, "pre_stress")

        def att(units: str, name: str) -> dict[str, str]:
            return {"units": units, "long_name": name}

        coords = model_coords(self.bed, "bed", _BED_PARAMETERS)
        coords["frequency"] = ("frequency", self.frequency, att("Hz", "frequency"))
        coords["speed"] = ("pre_stress", self.speed, att("m s-1", "steady wall speed"))
        return xr.Dataset(
            {
                "storage": (dims, self.storage, att("Pa", "storage modulus G'")),
                "loss": (dims, self.loss, att("Pa", "loss modulus G''")),
                "lead": (dims, self.lead, att("rad", "stress phase against the wall speed")),
                "status": (dims, self.status, att("1", "status")),
                "pre_stress": (p, self.pre_stress, att("Pa", "top wall's steady stress")),
                "lead_crossover": (p, self.lead_crossover, att("Hz", "G' = 0")),
                "modulus_crossover": (p, self.modulus_crossover, att("Hz", "G' = G''")),
                "time_scale": (beds, self.time_scale, att("s", "T = zeta_perp L^4/(E I)")),
                "modulus_scale": (beds, self.modulus_scale, att("Pa", "E I/(A L^2)")),
            },
            coords=coords,
            attrs={"title": "hairbed bed in a rheometer (SI, array bed)",
                   "Conventions": "CF-1.10"},
        )  # fmt: skip


#: The arrays of a :class:`BedModuli` with one row per bed of an array bed.
_PER_BED = ("pre_stress", "storage", "loss", "lead", "lead_crossover", "modulus_crossover")
#: The parameters of a HairBed that may be arrays (the coordinates of an array result).
_BED_PARAMETERS = ("length", "radius", "youngs_modulus", "channel_height", "viscosity",
                   "spacing", "packing_fraction", "base_angle", "density")  # fmt: skip


def bed_moduli(
    bed: HairBed,
    frequency: ArrayLike,
    speed: ArrayLike = 0.0,
    *,
    hair_density: float | None = None,
) -> BedModuli:
    """G'(f) and G''(f) [Pa] of a hair bed in a rheometer, about steady wall speeds [m/s].

    The bed's porous model (theory.md §13, the drag of ``bed.drag``) in the units of
    :func:`oscillatory_shear`: T = zeta_perp L^4/(E I), omega = 2 pi f T, moduli in
    E I/(A L^2) [Pa]; the Womersley number alpha = rho_f L^2/(eta T) from ``bed.density``
    (0, a quasi-steady fluid, without one); the hairs' inertia mu = m/(zeta_perp T) with
    m = (rho_s + rho_f) pi a^2 and chi = rho_s/(rho_s + rho_f) where ``hair_density`` rho_s
    [kg/m^3] is given (0, overdamped hairs, without one). A number below the bed dynamics'
    range (1e-6) is run as 0, its effect of that relative order (a realistic hair in a
    viscous fluid: mu ~ 1e-8), as :meth:`hairbed.HairBed.simulate` does.

    Parameters
    ----------
    bed : HairBed
        The bed (any ``model``: its porous description is used). An array-valued bed
        (issue 32, a design scan) gives one result with the bed's shape S in front: storage,
        loss, lead and status of shape S + (frequency, pre_stress), the pre-stresses and
        crossovers S + (pre_stress,), the time and modulus scales S; each element's linear
        bed about its own steady states (one after the other: the linearisation is per
        bed), bitwise the result of its :meth:`hairbed.HairBed.item`
        (:meth:`BedModuli.item`).
    frequency : array_like
        f [Hz], finite, > 0, increasing.
    speed : array_like, optional
        Steady wall speeds of the pre-stresses [m/s] (default 0; the sign is the direction).
    hair_density : float, optional
        rho_s [kg/m^3] > 0.

    Returns
    -------
    BedModuli
    """
    if not isinstance(bed, HairBed):
        raise TypeError(f"bed must be a HairBed, got {type(bed).__name__}")
    f = as_float_array(frequency, "frequency", unit="Hz").reshape(-1)
    v = as_float_array(speed, "speed", unit="m/s").reshape(-1)
    bad = ~(np.isfinite(f) & (f > 0.0))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"frequency must be finite and > 0 [Hz], got {show(float(f[i]))} (first at index {i})"
        )
    down = np.flatnonzero(np.diff(f) <= 0.0)
    if down.size:
        i = int(down[0]) + 1
        raise ValueError(f"frequency must increase, got frequency[{i}] <= frequency[{i - 1}]")
    if hair_density is not None:
        check_number(hair_density, "hair_density", low=0.0, low_open=True)
    if bed.shape:
        return _array_moduli(bed, f, v, hair_density)
    return _moduli_of(bed, f, v, hair_density)


def _array_moduli(
    bed: HairBed, f: FloatArray, v: FloatArray, hair_density: float | None
) -> BedModuli:
    """:func:`bed_moduli` of an array bed (issue 32): each element's linear bed about its
    own steady states (the linearisation is per bed), as the bed of numbers computes it (so
    each element is bitwise its :meth:`hairbed.HairBed.item`'s), stacked behind the bed's
    shape."""
    from .._model_axes import element_index

    shape = tuple(bed.shape)
    out = []
    for k, el in enumerate(bed._elements()):
        try:
            out.append(_moduli_of(el, f, v, hair_density))
        except ValueError as exc:  # this element's scales or its frequencies' range
            raise ValueError(f"{exc} (bed {element_index(k, shape)})") from None

    def stacked(name: str) -> Any:
        rows = np.array([getattr(r, name) for r in out], dtype=np.float64)
        return rows.reshape(shape + rows.shape[1:])

    dimless = np.empty(len(out), dtype=object)
    dimless[:] = [r.dimensionless for r in out]
    return BedModuli(
        frequency=f,
        speed=v,
        **{n: stacked(n) for n in (*_PER_BED, "time_scale", "modulus_scale")},
        dimensionless=dimless.reshape(shape),
        bed=bed,
    )


def _moduli_of(
    bed: HairBed, f: FloatArray, v: FloatArray, hair_density: float | None
) -> BedModuli:
    """:func:`bed_moduli` of a bed of numbers at checked frequencies and speeds."""
    # the one HairBed -> model conversion (T, alpha, mu, chi; numbers below the bed
    # dynamics' range run as 0, their effect of that relative order)
    sc = _within_range(_scales(bed, hair_density), bed, hair_density)
    ei = float(bed.bending_stiffness)
    tscale = sc.time
    gscale = ei / (float(bed.wall_area_per_hair) * float(bed.length) ** 2)
    alpha, mu, chi = sc.womersley, sc.inertia, sc.tangential_mass
    forcing = np.sign(v) * bed._forcing(np.abs(v), "speed")[1].reshape(-1)
    with np.errstate(over="ignore", under="ignore"):
        om = 2.0 * math.pi * f * tscale
    out = np.flatnonzero(~((om >= OMEGA_RANGE[0]) & (om <= OMEGA_RANGE[1])))
    if out.size:
        i = int(out[0])
        lo, hi = (w / (2.0 * math.pi * tscale) for w in OMEGA_RANGE)
        raise ValueError(
            f"frequency must lie in [{lo:.4g}, {hi:.4g}] Hz for this bed (omega T in "
            f"[{OMEGA_RANGE[0]:g}, {OMEGA_RANGE[1]:g}]), got {show(float(f[i]))} (first at "
            f"index {i})"
        )
    res = oscillatory_shear(
        om, forcing, eps=bed.eps, kappa=bed.kappa, theta0=bed.base_angle, gamma=bed.drag_ratio,
        inertia=mu, womersley=alpha, tangential_mass=chi,
    )  # fmt: skip
    hz = 1.0 / (2.0 * math.pi * tscale)
    return BedModuli(
        frequency=f,
        speed=v,
        pre_stress=res.pre_stress * gscale,
        storage=res.storage * gscale,
        loss=res.loss * gscale,
        lead=res.lead,
        lead_crossover=res.lead_crossover * hz,
        modulus_crossover=res.modulus_crossover * hz,
        time_scale=tscale,
        modulus_scale=gscale,
        dimensionless=res,
    )
