"""The porous bed: a hair in a Brinkman bed of its neighbours, one model for every density.

:func:`solve_porous` validates, builds a start, hands whole arrays to the compiled Chebyshev
collocation of ``_kernels.porous`` (hair and fluid solved together on the hair's nodes) and
wraps its columns in a :class:`PorousState`; :func:`solve_porous_all` finds every coexisting
state by a scan in the tip height the gap sees. The model, its assumptions and its limits are
in theory.md §13:

    theta'' = -(F_x cos theta - F_z sin theta),  theta(0) = theta0,  theta'(1) = 0,
    F(s) = int_s^1 (w/kappa) (cos^2 + gamma sin^2, -(1 - gamma) sin cos) ds',
    w' = cos(theta) Q,  w(0) = 0,  Q' = (w/kappa)(cos^2 + gamma sin^2) - Pi cos(theta),
    eps w(1) + (1 - eps h1) Q(1) - Pi (1 - eps h1)^2/(2 eps) = omega2.

kappa = k/L^2 is the bed's permeability k = eta A/zeta_perp over L^2 (the square of its
Brinkman length in L). As kappa -> 0 this is the paper's dense bed (:func:`hairbed.solve`,
:func:`hairbed.solve_loaded`); as kappa -> infinity at fixed Lambda = omega2/kappa the
isolated pillar in Couette flow (:func:`hairbed.solve_pillar`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .collocated import CollocatedState
from .loaded import _clenshaw, _ladder, _mapped_nodes
from .outputs import scalar_or_array
from .solver import _tables
from .validation import (
    HALF_PI,
    _check_range,
    _first_index,
    as_float_array,
    broadcast_named,
    check_int,
    check_positive,
    check_root,
)

__all__ = ["LADDER", "PorousState", "solve_porous", "solve_porous_all"]

#: The kernel code of the wall drive's inverse (omega2 unknown, the tip deflection given).
_INVERSE = 2

FloatArray = NDArray[np.float64]
Value = float | FloatArray
IntValue = int | NDArray[np.int64]

#: The ladder of Chebyshev degrees N (a thin bed's tip layer of width sqrt(kappa) needs the
#: upper levels; measured: kappa = 1e-4 converges at N = 64, 1e-6 at 256).
LADDER = (32, 64, 128, 256)
#: A call's ladder unless all its beds are thinner than ``_QUICK_KAPPA``: N = 16 first, at a
#: quarter of N = 32's LU (measured, 2000 states, kappa 1e-4 to 1e4, three drives: above
#: kappa = 0.3 89-94 % converge at N = 16; a thinner bed goes on to N = 32 from there).
_QUICK_LADDER = (16, *LADDER)
_QUICK_KAPPA = 0.3
_DRIVES = {"pressure": 0, "flow": 1}
_kernel_module: Any = None


def _kernels() -> Any:
    """The kernel module, imported (compiled or loaded from the cache) on first use."""
    global _kernel_module
    if _kernel_module is None:
        from ._kernels import porous

        _kernel_module = porous
    return _kernel_module


@dataclass(frozen=True, eq=False)
class PorousState(CollocatedState):
    """A state of a hair in a porous (Brinkman) bed (theory.md §13).

    Scalar inputs give float fields, array inputs arrays of the broadcast shape. Where no
    state was found (``status`` < 0) every value field is NaN. Loads and stresses are in the
    load unit E I/(A L^2) of the paper's omega^2 (a stress times A L^2/(E I)).

    Attributes
    ----------
    drive : str
        "pressure" (set pressure gradient pi; pi = 0 is the wall drive) or "flow" (set q).
    omega2, eps, theta0, kappa, gamma : float or ndarray
        The inputs: wall forcing omega^2 [-], confinement eps = L/H [-], base angle [rad],
        permeability kappa = k/L^2 [-], drag ratio gamma = zeta_par/zeta_perp [-].
    pi : float or ndarray
        Dimensionless pressure gradient pi = A G L^3/(E I) [-]: the input of the pressure
        drive, the solved one of the flow drive.
    q : float or ndarray
        Dimensionless flow rate q = 6 A eta Q' L^2/(E I H^2) [-] (NaN for the pressure drive).
    tip_height, tip_deflection : float or ndarray
        h1 = z(1), x1 = x(1) [L].
    tip_angle : float or ndarray
        theta(1) [rad].
    base_curvature : float or ndarray
        theta'(0) [1/L] = int_0^1 (F_x cos theta - F_z sin theta) ds (the base moment).
    tip_stress : float or ndarray
        Q(1) [-]: the fluid's shear stress on the tip plane (the dense bed's tip load W).
    wall_stress : float or ndarray
        Q(0) [-]: the fluid's shear stress on the bottom wall (0 in the dense limit).
    tip_velocity : float or ndarray
        w(1) [-]: the fluid's velocity at the tip plane, in load units (omega2 z/eps scale).
    drag_x, drag_z : float or ndarray
        F_x(0), F_z(0) [-]: the total drag on one hair (the base's shear and axial force).
    max_angle : float or ndarray
        the largest abs(theta) along the hair [rad]; the model needs it below pi/2 (z monotone).
    status : int or ndarray
        0 converged within the tolerance; 3 converged but inaccurate; -2, -3, -7 as
        :func:`hairbed.solve_loaded`; -8 the hair reaches abs(theta) = pi/2, outside the model
        (``STATUS_MESSAGES``).
    error_estimate : float or ndarray
        The largest Chebyshev tail of theta, w and Q (relative) plus the rounding part.
    residual : float or ndarray
        The largest residual of the collocation equations at the returned state.
    nit, num : int or ndarray
        Newton iterations over the ladder; the Chebyshev degree N of the returned state.
    stable : bool or None
        From :func:`solve_porous_all`: stable under a slow change of the gap (dG/dh1 < 0).
    """

    drive: str
    omega2: Value
    eps: Value
    theta0: Value
    kappa: Value
    gamma: Value
    pi: Value
    q: Value
    tip_height: Value
    tip_deflection: Value
    tip_angle: Value
    base_curvature: Value
    tip_stress: Value
    wall_stress: Value
    tip_velocity: Value
    drag_x: Value
    drag_z: Value
    max_angle: Value
    status: IntValue
    error_estimate: Value
    residual: Value
    nit: IntValue
    num: IntValue
    _map: FloatArray
    _coefs: FloatArray
    _out: FloatArray
    stable: Any = None

    def shape(self, s: ArrayLike) -> tuple[Any, Any, Any, Any]:
        """The hair at arc lengths ``s`` in [0, 1] [L]: (s, x [L], z [L], theta [rad]),
        each of shape ``self.shape_of_fields + s.shape``."""
        sv, fields = _fields_at(self._map, self._coefs, self.shape_of_fields, s)
        return sv, fields[1], fields[2], fields[0]

    def fluid(self, s: ArrayLike) -> tuple[Any, Any, Any, Any]:
        """The bed's fluid along the hair: (s, z [L], w [-], Q [-]) at arc lengths ``s``: its
        velocity w and shear stress Q (load units) at the height z(s) of the hair."""
        sv, fields = _fields_at(self._map, self._coefs, self.shape_of_fields, s)
        return sv, fields[2], fields[3], fields[4]


def _fields_at(
    mapping: FloatArray, coefs: FloatArray, fields: tuple[int, ...], s: ArrayLike
) -> tuple[Any, list[Any]]:
    """The five Chebyshev interpolants (theta, x, z, w, Q) at arc lengths ``s``."""
    sv = as_float_array(s, "s")
    bad = (sv < 0.0) | (sv > 1.0)
    if np.any(bad):
        raise ValueError(
            f"s must lie in [0, 1], got {float(sv[bad].flat[0])!r}{_first_index(bad)}"
        )
    if sv.ndim > 1:
        raise ValueError(f"s must be a scalar or 1-d, got shape {sv.shape}")
    flat = np.atleast_1d(sv)
    a = mapping.reshape(-1, 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        y = np.where(
            a != 0.0, np.log1p(flat[None, :] * np.expm1(a)) / np.where(a != 0, a, 1), flat
        )
    xi = 2.0 * y - 1.0
    coefs = coefs.reshape(5, -1, coefs.shape[-1])
    fs = fields + flat.shape if sv.ndim else fields
    return sv, [scalar_or_array(_clenshaw(coefs[c], xi).reshape(fs)) for c in range(5)]


def _check(
    omega2: Any, eps: Any, theta0: Any, kappa: Any, gamma: Any, pi: Any, q: Any
) -> tuple[str, int, tuple[FloatArray, ...]]:
    """The inputs validated and broadcast: (drive, code, (omega2, eps, theta0, kappa, gamma,
    pi or q))."""
    if pi is not None and q is not None:
        raise ValueError("give at most one of pi (pressure drive) and q (flow drive), got both")
    drive = "flow" if q is not None else "pressure"
    load = q if q is not None else (0.0 if pi is None else pi)
    fast = _plain_scalars(drive, omega2, eps, theta0, kappa, gamma, load)
    if fast is not None:
        return drive, _DRIVES[drive], fast
    w = as_float_array(omega2, "omega2")
    e = as_float_array(eps, "eps")
    t0 = as_float_array(theta0, "theta0")
    k = as_float_array(kappa, "kappa")
    g = as_float_array(gamma, "gamma")
    _check_range(e, (e < 0.0) | (e >= 1.0), "eps", "[0, 1)")
    _check_range(t0, np.abs(t0) >= HALF_PI, "theta0", "(-pi/2, pi/2)")
    _check_range(k, k <= 0.0, "kappa", "(0, inf)")
    _check_range(g, (g <= 0.0) | (g > 1.0), "gamma", "(0, 1]")
    name = "q" if q is not None else "pi"
    ld = as_float_array(load, name)
    w, e, t0, k, g, ld = broadcast_named(
        ("omega2", w), ("eps", e), ("theta0", t0), ("kappa", k), ("gamma", g), (name, ld)
    )
    bad = (e == 0.0) & ((ld != 0.0) if drive == "pressure" else np.ones(e.shape, bool))
    if np.any(bad):
        raise ValueError(
            f"{name} needs eps > 0 (the gap's Poiseuille flow grows with H/L = 1/eps), got "
            f"{name} = {float(ld[bad].flat[0])!r} with eps = 0{_first_index(bad)}"
        )
    return drive, _DRIVES[drive], (w, e, t0, k, g, ld)


_PLAIN = (float, int, np.float64)


def _plain_scalars(drive: str, *values: Any) -> tuple[FloatArray, ...] | None:
    """The common call's shortcut past the array checks (a tenth of a scalar solve): Python or
    numpy float scalars (or ints) that pass every check of :func:`_check`, as 0-d arrays;
    None for anything else, which the full checks then take (and refuse with their
    messages)."""
    if not all(type(v) in _PLAIN for v in values):
        return None
    try:
        w, e, t0, k, g, ld = (float(v) for v in values)
    except OverflowError:  # an int beyond float64
        return None
    fine = (
        math.isfinite(w)
        and math.isfinite(ld)
        and 0.0 <= e < 1.0
        and abs(t0) < HALF_PI
        and 0.0 < k < math.inf
        and 0.0 < g <= 1.0
        and (e > 0.0 or (drive == "pressure" and ld == 0.0))
    )
    return tuple(np.array(v) for v in (w, e, t0, k, g, ld)) if fine else None


#: Gauss-Legendre nodes and weights on [0, 1] of the start's linear tip deflection.
_GAUSS_X, _GAUSS_V = np.polynomial.legendre.leggauss(48)
_GAUSS = np.ascontiguousarray([0.5 * (_GAUSS_X + 1.0), 0.5 * _GAUSS_V])
#: The tips' map: a = -ln(_TIP_MAP / sqrt(kappa)) below kappa = _TIP_MAP^2 (measured: all of
#: a 2000-state batch from kappa = 1e-4 to 1e4 then converges at N = 32, against 12 % at N = 64
#: with the plain map).
_TIP_MAP = 0.1
#: The forcings, relative to the equivalent one, at which a hair leaning into its load is
#: checked for the dense bed's windows (``_kernels.porous._closed_start``).
_LEAN_FACTORS = np.geomspace(1.0 / 16.0, 16.0, 48)


def _linear_deflection(
    omega2: FloatArray, eps: FloatArray, kappa: FloatArray, pi: FloatArray
) -> FloatArray:
    """x1 of the straight bed's linear Brinkman theory (theory.md §13), every element: the
    kernel's (``_kernels.porous._linear_deflection``) that starts each solve."""
    args = (np.ascontiguousarray(np.broadcast_to(v, np.shape(omega2)), dtype=np.float64).ravel()
            for v in (omega2, eps, kappa, pi))  # fmt: skip
    w, e, k, pi_ = args
    out = np.empty(w.size)
    _kernels().linear_deflection_array(w, e, k, pi_, _GAUSS, out)
    return out.reshape(np.shape(omega2))


def _tip_map(code: int, kappa: FloatArray, pi: FloatArray) -> FloatArray:
    """The map parameter of each element: nodes clustered at the tips for a thin bed under
    the wall drive alone. A pressure load has a second layer at the wall (the fluid's
    w = kappa Pi deep in the bed falls to 0 there): the plain map, dense at both ends."""
    a = -np.clip(np.log(_TIP_MAP / np.sqrt(kappa)), 0.0, 30.0)
    return np.where((code == 0) & (pi == 0.0), a, 0.0)


def _run(
    code: int,
    arrays: tuple[FloatArray, ...],
    hfix: FloatArray,
    nums: tuple[int, ...],
    tol: float,
    start: FloatArray | None = None,
    x1t: FloatArray | None = None,
    fluid: bool = False,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The kernel on flat arrays: (out (NCOLS, size), coefs (5, size, N + 1), map). Without
    a ``start`` (theta, w, Q at the plain map's nodes, h1, then Pi or the inverse's omega2)
    the kernel's closed-form start (``_closed_start``) on the tips' map, and its fluid;
    with one, its fluid is used as it is unless ``fluid``. ``x1t`` the inverse's tip
    deflections (code 2)."""
    k = _kernels()
    w, e, t0, kap, g, ld = arrays
    size = w.size
    out = np.empty((k.NCOLS, size))
    coefs = np.empty((5, size, int(max(nums)) + 1))
    given = start is not None
    a = np.zeros(size) if given else _tip_map(code, kap, ld)
    desc = _description(code, arrays, hfix, x1t)
    closed = start is None  # the kernel's closed-form start and its fluid
    k.solve_porous_array(
        code,
        desc,
        a,
        np.empty((0, 0)) if start is None else start,
        *_ladder(tuple(nums)),
        tol,
        out,
        coefs,
        fluid or closed,
        closed,
        _tables(),
        _GAUSS,
        _LEAN_FACTORS,
    )
    # the model needs z(s) monotone: a state that reaches |theta| = pi/2 is outside it
    outside = (out[0] >= 0) & (out[13] >= HALF_PI)
    out[0, outside] = -8
    return out, coefs, a


def _description(
    code: int, arrays: tuple[FloatArray, ...], hfix: FloatArray, x1t: FloatArray | None = None
) -> FloatArray:
    """The kernel's load description of every element, (size, NDESC): each model and drive
    fills its own slots (``_kernels.porous.D_*``): the bed, the wall, the pump's pi or q, the
    inverse's tip deflection, the frozen gap of the scan."""
    k = _kernels()
    w, e, t0, kap, g, ld = arrays
    desc = np.zeros((w.size, k.NDESC))
    desc[:, k.D_THETA0] = t0
    desc[:, k.D_KAPPA] = kap
    desc[:, k.D_GAMMA] = g
    desc[:, k.D_OMEGA2] = w
    desc[:, k.D_EPS] = e
    desc[:, k.D_PI if code == 0 else k.D_Q] = ld if code != 2 else 0.0
    desc[:, k.D_X1] = 0.0 if x1t is None else x1t
    desc[:, k.D_HFIX] = hfix
    return desc


def _quiet(func: Any) -> Any:
    """Run ``func`` with numpy's floating-point warnings off (the status says what came)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return func(*args, **kwargs)

    return wrapper


@_quiet
def solve_porous(
    omega2: ArrayLike,
    eps: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    kappa: ArrayLike,
    gamma: ArrayLike = 1.0,
    pi: ArrayLike | None = None,
    q: ArrayLike | None = None,
    root: str = "low",
    num: int | None = None,
    rtol: float = 1e-12,
) -> PorousState:
    """A hair in a porous (Brinkman) bed, hair and fluid by one Chebyshev collocation.

    Solves, with lengths in L and s the arc length (theory.md §13),

    .. math::

        \\theta'' = -(F_x \\cos\\theta - F_z \\sin\\theta),\\quad
        F(s) = \\int_s^1 \\frac{w}{\\kappa}
        (\\cos^2\\theta + \\gamma \\sin^2\\theta, -(1 - \\gamma) \\sin\\theta \\cos\\theta)\\,ds',

        w' = Q \\cos\\theta,\\quad
        Q' = \\frac{w}{\\kappa}(\\cos^2\\theta + \\gamma\\sin^2\\theta) - \\Pi \\cos\\theta,

    with theta(0) = theta0, theta'(1) = 0, w(0) = 0, and the gap's exact Couette-Poiseuille
    profile at the tip plane, eps w(1) + u Q(1) - Pi u^2/(2 eps) = omega2, u = 1 - eps h1.
    For the flow drive Pi is solved to hold 6 eps^2 Phi = q, Phi the flux through bed and gap.

    Parameters
    ----------
    omega2 : array_like
        Wall forcing omega^2 = eta V A L^2/(E I H) [-], finite (negative: towards -x).
    eps : array_like
        Confinement eps = L/H [-], in [0, 1); > 0 where pi != 0 and for the flow drive.
    theta0 : array_like, optional
        Base angle [rad], in (-pi/2, pi/2). Default 0.
    kappa : array_like
        The bed's permeability over L^2, kappa = eta A/(zeta_perp L^2) [-], in (0, inf):
        the square of its Brinkman length in units of L.
    gamma : array_like, optional
        Drag ratio zeta_par/zeta_perp [-], in (0, 1]. Default 1 (isotropic drag).
    pi : array_like, optional
        Dimensionless pressure gradient pi = A G L^3/(E I) [-] (pressure drive).
    q : array_like, optional
        Dimensionless flow rate q = 6 A eta Q' L^2/(E I H^2) [-] (flow drive). At most one
        of ``pi`` and ``q``.
    root : {"low", "mid", "high"}, optional
        Which state where several coexist (an upstream tilt in a tight channel): "low"
        (default) the state Newton reaches from the hair at rest by the load continuation
        (the least deformed); "mid" and "high" the middle (of three) and the highest tip
        height of :func:`solve_porous_all`'s scan (status -1 where there are fewer). Where
        Newton and the continuation fail (a fold on the way), the scan's lowest state.
    num : int, optional
        A fixed Chebyshev degree N in [8, 512] instead of the ladder (32, 64, 128, 256).
    rtol : float, optional
        Tolerance on the Chebyshev tails; default 1e-12.

    Returns
    -------
    PorousState

    Raises
    ------
    ValueError
        For inputs outside their ranges (naming the parameter, its range and the first bad
        index), both ``pi`` and ``q``, or pi != 0 (or q) with eps = 0.

    Examples
    --------
    >>> import hairbed
    >>> st = hairbed.solve_porous(2.0, 0.5, kappa=1.0)
    >>> round(st.tip_deflection, 10)
    0.1457938982
    """
    drive, code, arrays = _check(omega2, eps, theta0, kappa, gamma, pi, q)
    root = check_root(root)
    tol = check_positive(rtol, "rtol")
    nums = LADDER if num is None else (check_int(num, "num", 8, 512),)
    return _solve_porous_checked(drive, code, arrays, root, tol, nums)


def _solve_porous_checked(
    drive: str,
    code: int,
    arrays: tuple[FloatArray, ...],
    root: str = "low",
    tol: float = 1e-12,
    nums: tuple[int, ...] = LADDER,
) -> PorousState:
    """:func:`solve_porous` of checked, broadcast inputs (``_check``), trusted."""
    shape = arrays[0].shape
    flat = tuple(np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in arrays)
    hfix = np.full(flat[0].size, np.nan)
    if nums != LADDER:
        out, coefs, a = _run(code, flat, hfix, nums, tol)
        return _state(drive, code, shape, arrays, out, coefs, a)
    # N = 16 first unless every bed is thin (a thin bed fails there, in a few cheap steps)
    thin = bool(np.all(flat[3] < _QUICK_KAPPA))
    out, coefs, a = _run(code, flat, hfix, LADDER if thin else _QUICK_LADDER, tol)
    again = np.flatnonzero(out[0] < 0) if not thin else np.empty(0, np.intp)
    if again.size:  # where the ladder from N = 16 failed, from N = 32's start
        o, c, ai = _run(code, tuple(v[again] for v in flat), hfix[again], LADDER, tol)
        out[:, again], coefs[:, again, :], a[again] = o, c, ai
    _rescue(drive, code, flat, root, tol, out, coefs)
    return _state(drive, code, shape, arrays, out, coefs, a)


#: The most failed elements of one call that :func:`_rescue` scans (each ~0.1 s).
MAX_RESCUE = 100


def _rescue(
    drive: str,
    code: int,
    flat: tuple[FloatArray, ...],
    root: str,
    tol: float,
    out: FloatArray,
    coefs: FloatArray,
) -> None:
    """The scan of :func:`solve_porous_all` where Newton and the continuation failed (status
    -2, -3, -7: a fold on the way; at most ``MAX_RESCUE`` a call) and on every element for
    ``root`` "mid" or "high": its state of ``root`` written into out and coefs in place."""
    if root == "low":
        todo = np.flatnonzero(np.isin(out[0], (-2, -3, -7)))[:MAX_RESCUE]
    else:
        todo = np.arange(out.shape[1])
    for i in todo:
        w, e, t0, k, g, ld = (float(v[i]) for v in flat)
        kw = {"pi": ld} if drive == "pressure" else {"q": ld}
        found = [s for s in solve_porous_all(w, e, t0, kappa=k, gamma=g, rtol=tol, **kw)
                 if s.status >= 0]  # fmt: skip
        if not found or (root == "mid" and len(found) < 3):
            out[0, i] = -1 if found else out[0, i]
            out[3:, i] = np.nan
            coefs[:, i, :] = np.nan
            continue
        pick = found[0] if root == "low" else found[-1] if root == "high" else found[1]
        out[:, i] = pick._out
        top = pick._coefs.shape[-1]
        coefs[:, i, :] = 0.0
        coefs[:, i, :top] = pick._coefs.reshape(5, top)


def _state(
    drive: str,
    code: int,
    shape: tuple[int, ...],
    arrays: tuple[FloatArray, ...],
    out: FloatArray,
    coefs: FloatArray,
    a: FloatArray,
    stable: Any = None,
) -> PorousState:
    """A PorousState of the kernel's columns, reshaped to ``shape``."""
    w, e, t0, k, g, ld = (np.reshape(v, shape) for v in arrays)
    top = coefs.shape[-1]

    def col(i: int) -> Any:
        return scalar_or_array(out[i].reshape(shape))

    return PorousState(
        drive=drive,
        omega2=scalar_or_array(w),
        eps=scalar_or_array(e),
        theta0=scalar_or_array(t0),
        kappa=scalar_or_array(k),
        gamma=scalar_or_array(g),
        pi=col(9),
        q=scalar_or_array(ld if code == 1 else np.full(shape, np.nan)),
        tip_height=col(3),
        tip_deflection=col(4),
        tip_angle=col(5),
        base_curvature=col(6),
        tip_stress=col(7),
        wall_stress=col(10),
        tip_velocity=col(8),
        drag_x=col(14),
        drag_z=col(15),
        max_angle=col(13),
        status=scalar_or_array(out[0].astype(np.int64).reshape(shape)),
        error_estimate=col(11),
        residual=col(12),
        nit=scalar_or_array(out[1].astype(np.int64).reshape(shape)),
        num=scalar_or_array(out[2].astype(np.int64).reshape(shape)),
        _map=a.reshape(shape),
        _coefs=coefs.reshape((5, *shape, top)),
        _out=out.reshape((out.shape[0], *shape)),
        stable=stable,
    )


#: The tip heights the gap sees in the scan of :func:`solve_porous_all`.
_SCAN_LOW = (1e-4, 0.02, 12)
_BISECT_STEPS = 60
_G_TOL = 1e-13
_H_TOL = 1e-12


def _frozen(
    code: int, arrays: tuple[FloatArray, ...], h: FloatArray, tol: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The states with the gap's height frozen at 1/eps - h, for every h (the scalars of
    ``arrays`` repeated)."""
    full = tuple(np.full(h.size, float(v.reshape(-1)[0])) for v in arrays)
    return _run(code, full, np.ascontiguousarray(h, dtype=np.float64), LADDER, tol)


@_quiet
def solve_porous_all(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    kappa: float,
    gamma: float = 1.0,
    pi: float | None = None,
    q: float | None = None,
    num_scan: int = 64,
    rtol: float = 1e-12,
) -> list[PorousState]:
    """Every coexisting state at scalar inputs, by a scan in the tip height the gap sees.

    With the gap frozen at the height 1/eps - h (in L), the hair and its bed have a state of
    tip height z1(h); the states of the bed are the roots of G(h) = z1(h) - h on
    0 < h <= 1. G is scanned on 12 geometric points in [1e-4, 0.02] and ``num_scan`` uniform
    ones in [0.02, 1], each sign change refined by bisection to 1e-12, and each root polished
    by the full Newton from the frozen state. At eps = 0 the gap does not feed back: one state.

    Parameters
    ----------
    omega2, eps, theta0, kappa, gamma, pi, q, rtol
        As in :func:`solve_porous`, scalars.
    num_scan : int, optional
        Uniform scan points in [0.02, 1], in [8, 10^4]. Default 64.

    Returns
    -------
    list of PorousState
        Sorted by tip height, each with ``stable`` (dG/dh < 0 at the root: True stable).
        Never empty: where the scan finds no state, one state of NaN values whose
        ``status`` (-7; -8 where the load lays the hair on the wall at every frozen gap)
        and ``message`` say so.
    """
    named: tuple[tuple[str, Any], ...] = (
        ("omega2", omega2),
        ("eps", eps),
        ("theta0", theta0),
        ("kappa", kappa),
        ("gamma", gamma),
        ("pi", pi),
        ("q", q),
    )
    for name, value in named:
        if value is None:
            continue
        try:
            shape: Any = np.shape(value)
        except ValueError:  # a ragged nested list
            shape = "ragged"
        if shape != ():
            raise ValueError(
                f"{name} must be a single number (a scalar) for solve_porous_all, got shape "
                f"{shape}"
            )
    drive, code, arrays = _check(omega2, eps, theta0, kappa, gamma, pi, q)
    tol = check_positive(rtol, "rtol")
    count = check_int(num_scan, "num_scan", 8, 10**4)
    if float(arrays[1]) == 0.0:  # no gap feedback: one state, or its failure status
        return [solve_porous(omega2, eps, theta0, kappa=kappa, gamma=gamma, pi=pi, q=q, rtol=tol)]
    h = np.unique(np.concatenate([np.geomspace(*_SCAN_LOW), np.linspace(0.02, 1.0, count)]))
    # a load that lays the hair on the wall at every frozen gap already at the first degree
    # (status -8 everywhere): no state, said at once (the ladder's finer degrees only say it
    # again, at ~20 s a call for loads like q = 1e13)
    full = tuple(np.full(h.size, float(v.reshape(-1)[0])) for v in arrays)
    first = _run(code, full, np.ascontiguousarray(h, dtype=np.float64), LADDER[:1], tol)[0]
    if np.all(first[0] == -8):
        return [_no_state(drive, code, arrays, -8)]
    out = _frozen(code, arrays, h, tol)[0]
    g = np.where(out[0] >= 0, out[3] - h, np.nan)
    lo_i = np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] <= 0.0))
    lo_i = lo_i[~np.isin(lo_i - 1, lo_i) | (g[lo_i] != 0.0)]
    if lo_i.size == 0:
        return [_no_state(drive, code, arrays)]
    lo, hi = h[lo_i], h[lo_i + 1]
    glo = g[lo_i]
    stable = glo > g[lo_i + 1]
    for _ in range(_BISECT_STEPS):
        if np.all(hi - lo <= _H_TOL):
            break
        mid = 0.5 * (lo + hi)
        o = _frozen(code, arrays, mid, tol)[0]
        gm = np.where(o[0] >= 0, o[3] - mid, 0.0)
        left = np.sign(gm) == np.sign(glo)
        lo, glo = np.where(left, mid, lo), np.where(left, gm, glo)
        hi = np.where(left, hi, mid)
    root = 0.5 * (lo + hi)
    # polish: the full Newton (the gap's own h1) from the frozen state at each root
    of, cf, af = _frozen(code, arrays, root, tol)
    size = root.size
    full = tuple(np.full(size, float(v.reshape(-1)[0])) for v in arrays)
    n1 = LADDER[0] + 1
    # the frozen states' interpolants at the plain map's nodes (the polish's start)
    sig = _mapped_nodes(np.zeros(size), LADDER[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        am = af[:, None]
        y = np.where(am != 0.0, np.log1p(sig * np.expm1(am)) / np.where(am != 0, am, 1.0), sig)
    start = np.zeros((size, 3 * n1 + 2))
    for c in range(3):
        field = cf[(0, 3, 4)[c]]
        start[:, c * n1 : (c + 1) * n1] = _clenshaw(
            np.where(np.isfinite(field), field, 0.0), 2.0 * y - 1.0
        )
    start[:, 3 * n1] = np.where(np.isfinite(of[3]), of[3], root)
    start[:, 3 * n1 + 1] = np.where(np.isfinite(of[9]), of[9], 0.0)
    out, coefs, a = _run(code, full, np.full(size, np.nan), LADDER, tol, start)
    order = np.argsort(np.where(np.isfinite(out[3]), out[3], np.inf), kind="stable")
    states: list[PorousState] = []
    last = -math.inf
    for i in order:
        if out[0, i] < 0 or abs(out[3, i] - last) <= 1e-9:
            continue
        last = out[3, i]
        one = tuple(np.array(v[i]) for v in full)
        states.append(
            _state(
                drive,
                code,
                (),
                one,
                out[:, i : i + 1],
                coefs[:, i : i + 1],
                a[i : i + 1],
                bool(stable[i]),
            )
        )
    return states or [_no_state(drive, code, arrays)]


def _no_state(
    drive: str, code: int, arrays: tuple[FloatArray, ...], status: int = -7
) -> PorousState:
    """The one state of :func:`solve_porous_all` where the scan finds none: NaN values,
    status -7 (no state reached) or -8 (the load lays the hair on the wall at every frozen
    gap), never an empty list."""
    k = _kernels()
    out = np.full((k.NCOLS, 1), np.nan)
    out[0] = status
    out[1:3] = 0
    one = tuple(np.array(float(v.reshape(-1)[0])) for v in arrays)
    coefs = np.full((5, 1, LADDER[-1] + 1), np.nan)
    return _state(drive, code, (), one, out, coefs, np.zeros(1))


def _solve_inverse_checked(
    x1: FloatArray,
    arrays: tuple[FloatArray, ...],
    theta_start: FloatArray,
    h_start: FloatArray,
    omega2_start: FloatArray,
    shape: tuple[int, ...],
    tol: float = 1e-12,
) -> PorousState:
    """The wall drive's inverse, of checked, flat inputs, trusted: the state whose tip
    deflection is ``x1`` (in (sin theta0, 1), the hair's own frame: flow towards +x), omega2
    solved, from the start theta (at the plain map's first-level nodes), h1, omega2 (the
    inverse module builds it from the closed form). ``arrays`` as :func:`_check`'s with
    omega2 and the load unused. Where Newton fails, the continuation of the tip deflection
    from rest."""
    n1 = LADDER[0] + 1
    size = x1.size
    start = np.zeros((size, 3 * n1 + 2))
    start[:, :n1] = theta_start
    start[:, 3 * n1] = h_start
    start[:, 3 * n1 + 1] = omega2_start
    out, coefs, a = _run(
        _INVERSE, arrays, np.full(size, np.nan), LADDER, tol, start, x1, fluid=True
    )
    flat = (out[17].copy(), *arrays[1:])
    return _state("pressure", 0, shape, flat, out, coefs, a)
