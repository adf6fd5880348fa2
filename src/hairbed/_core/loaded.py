"""A hair under a tip load and a load per unit height: the pressure and flow drives (issue 20).

:func:`solve_loaded` validates, builds a closed-form start, hands whole arrays to the
compiled Chebyshev collocation of ``_kernels.spectral`` and wraps its columns in a
:class:`LoadedState`. The model and the method are in theory.md §11.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._kernels import description as D
from .collocated import CollocatedState
from .outputs import scalar_or_array
from .solution import Solution
from .solver import _solve_checked
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

__all__ = ["LADDER", "LoadedState", "solve_loaded", "solve_loaded_all"]

FloatArray = NDArray[np.float64]
Value = float | FloatArray
IntValue = int | NDArray[np.int64]

#: The default ladder of Chebyshev degrees N: each level starts from the previous one's
#: interpolant, and the first whose tail meets the tolerance ends the solve.
LADDER = (32, 64, 128)
#: The map parameter a = max(0, ln(sqrt(|W| + |Pi|) / _MAP_SCALE)) from the start's loads.
_MAP_SCALE = 3.0
#: The fixed-point steps on h1 that set the closed-form start of a loaded state.
_START_STEPS = 4
_DRIVES = {"pressure": 0, "flow": 1}
_spectral: Any = None
#: The profile argument of the kernel for the bed's drives (it reads one only for a pillar).
_NO_PROFILE = np.zeros((1, 1))


def _kernels() -> Any:
    """The kernel module, imported (compiled or loaded from the cache) on first use."""
    global _spectral
    if _spectral is None:
        from ._kernels import spectral

        _spectral = spectral
    return _spectral


@functools.lru_cache(maxsize=16)
def _chebyshev_values(num: int) -> FloatArray:
    """T_k(xi_j) = cos(k (pi - pi j/N)) at the N + 1 Chebyshev-Gauss-Lobatto nodes
    xi_j = -cos(pi j/N): (j, k). Built once per N; shared, so read-only."""
    j = np.arange(num + 1)
    vand = np.cos(np.outer(np.pi - np.pi * j / num, j))
    vand.flags.writeable = False
    return vand


def _nodal_values(coefs: FloatArray, num: int) -> FloatArray:
    """Each row's Chebyshev series of degree ``num`` at the N + 1 nodes of
    :func:`_chebyshev_values`: (rows, N + 1). By einsum, not a matrix product: BLAS sums a
    batch's rows in another order than one row's, so an array's derivatives would differ
    from its elements' alone (by ~1e-13 on some CPUs); einsum's rounding is the same for any
    number of rows."""
    return np.ascontiguousarray(
        np.einsum("ij,kj->ik", coefs[:, : num + 1], _chebyshev_values(num))
    )


@functools.lru_cache(maxsize=16)
def _matrices(num: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """(nodes, D, D^2, I, C) in xi on [-1, 1] at the N + 1 Chebyshev-Gauss-Lobatto nodes
    xi_j = -cos(pi j/N): differentiation, its square, integration from -1, and the map from
    node values to Chebyshev coefficients. Built once per N."""
    j = np.arange(num + 1)
    x = -np.cos(np.pi * j / num)
    x[num // 2] = 0.0 if num % 2 == 0 else x[num // 2]
    w = (-1.0) ** j
    w[0] *= 0.5
    w[-1] *= 0.5
    dx = x[:, None] - x[None, :]
    np.fill_diagonal(dx, 1.0)
    d = (w[None, :] / w[:, None]) / dx
    np.fill_diagonal(d, 0.0)
    np.fill_diagonal(d, -d.sum(axis=1))
    d2 = d @ d
    np.fill_diagonal(d2, 0.0)
    np.fill_diagonal(d2, -d2.sum(axis=1))  # the second derivative of a constant is 0 too
    vand = _chebyshev_values(num)
    half = np.ones(num + 1)
    half[0] = half[-1] = 0.5
    cmat = (2.0 / num) * (vand * half[:, None]).T * half[:, None]
    # antiderivatives from -1 of T_k at the nodes
    theta = np.pi - np.pi * j / num
    anti = np.empty((num + 1, num + 1))
    anti[:, 0] = x + 1.0
    anti[:, 1] = 0.5 * (x * x - 1.0)
    for kk in range(2, num + 1):
        up = (np.cos((kk + 1) * theta) - (-1.0) ** (kk + 1)) / (kk + 1)
        down = (np.cos((kk - 1) * theta) - (-1.0) ** (kk - 1)) / (kk - 1)
        anti[:, kk] = 0.5 * (up - down)
    imat = anti @ cmat
    return x, d, d2, imat, cmat


@functools.lru_cache(maxsize=8)
def _ladder(nums: tuple[int, ...]) -> tuple[Any, ...]:
    """The kernel's per-level arrays of a ladder, padded to its largest N (built once)."""
    top = max(nums) + 1
    lv = len(nums)
    nodes = np.zeros((lv, top))
    mats = [np.zeros((lv, top, top)) for _ in range(4)]
    for i, num in enumerate(nums):
        x, *rest = _matrices(num)
        nodes[i, : num + 1] = x
        for m, r in zip(mats, rest):
            m[i, : num + 1, : num + 1] = r
    return (np.array(nums, dtype=np.int64), nodes, *mats)


def _loads(code: int, omega2: Any, eps: Any, load: Any, h: Any) -> tuple[Any, Any]:
    """(W, Pi) of a drive at tip height h, in numpy (the start; the kernel has its own)."""
    if code == 2:
        return omega2 + 0.0 * h, load + 0.0 * h
    u = 1.0 - eps * h
    if code == 0:
        with np.errstate(divide="ignore", invalid="ignore"):
            extra = np.where(
                load != 0.0, 0.5 * load * (1.0 / np.where(eps > 0, eps, 1.0) - h), 0.0
            )
        return omega2 / u + extra, load + 0.0 * h
    return load / u**2 - 2.0 * omega2 / u, 2.0 * eps * load / u**3 - 6.0 * eps * omega2 / u**2


def _start(
    code: int, w: FloatArray, e: FloatArray, ld: FloatArray, t0: FloatArray, root: str
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """The closed-form start of every element: (t, eps_s, theta0_s, mirror, h1) of the
    physical-branch state of ``hairbed.solve`` whose tip load has the same effect.

    At pi = 0 of the pressure drive that is the state of the same problem (omega2, eps,
    theta0). Otherwise the tip load W(h1) + (3/8) Pi(h1) h1 (the uniform load's tip
    deflection, Pi/8 against W/3), fed back through the closed form's own 1/(1 - eps h1), by
    a few fixed-point steps on h1. A negative load is mirrored (theta0 -> -theta0).
    """
    if w.size == 1:
        one = _start_scalar(code, float(w[0]), float(e[0]), float(ld[0]), float(t0[0]), root)
        return tuple(np.array([v]) for v in one)  # type: ignore[return-value]
    exact = (code == 0) & (ld == 0.0)
    h = np.cos(t0)
    omega_s = np.abs(w)
    mirror = np.where(w < 0.0, -1.0, 1.0)
    sol = None
    steps = 1 if np.all(exact) else _START_STEPS
    for _ in range(steps):
        big_w, big_p = _loads(code, w, e, ld, h)
        weq = (1.0 - e * h) * (big_w + 0.375 * big_p * h)
        weq = np.where(exact, w, weq)
        weq = np.where(np.isfinite(weq), weq, 0.0)
        mirror = np.where(weq < 0.0, -1.0, 1.0)
        omega_s = np.minimum(np.abs(weq), 1e12)
        sol = _solve_checked(omega_s, e, mirror * t0, root=root)
        hn = np.asarray(sol.tip_height, dtype=np.float64)
        h = np.where(np.isfinite(hn), hn, h)
    assert sol is not None
    t = np.asarray(sol.t, dtype=np.float64)
    return t, e.copy(), mirror * t0, mirror, h


def _start_scalar(
    code: int, w: float, e: float, ld: float, t0: float, root: str
) -> tuple[float, float, float, float, float]:
    """:func:`_start` of one element in floats (the scalar kernel of the closed form)."""
    h = math.cos(t0)
    exact = code == 0 and ld == 0.0
    t, mirror = math.nan, 1.0
    for _ in range(1 if exact else _START_STEPS):
        u = 1.0 - e * h
        if code == 2:
            big_w, big_p = w, ld
        elif code == 0:
            big_w = w / u + (0.5 * ld * (1.0 / e - h) if ld != 0.0 else 0.0)
            big_p = ld
        else:
            big_w = ld / u**2 - 2.0 * w / u
            big_p = 2.0 * e * ld / u**3 - 6.0 * e * w / u**2
        weq = w if exact else u * (big_w + 0.375 * big_p * h)
        if not math.isfinite(weq):
            weq = 0.0
        mirror = -1.0 if weq < 0.0 else 1.0
        sol = _solve_checked(min(abs(weq), 1e12), e, mirror * t0, root=root)
        t = float(sol.t)
        if math.isfinite(sol.tip_height):
            h = float(sol.tip_height)
    return t, e, mirror * t0, mirror, h


def _map_parameter(code: int, w: Any, e: Any, ld: Any, h: Any) -> FloatArray:
    big_w, big_p = _loads(code, w, e, ld, h)
    scale = np.sqrt(np.abs(big_w) + np.abs(big_p))
    with np.errstate(divide="ignore"):
        a = np.log(scale / _MAP_SCALE)
    return np.where(np.isfinite(a) & (a > 0.0), np.minimum(a, 30.0), 0.0)


def _clenshaw(coef: FloatArray, x: FloatArray) -> FloatArray:
    """sum_k coef[..., k] T_k(x[..., :]) for coefficients (..., K) and points (..., M)."""
    b1 = np.zeros(x.shape)
    b2 = np.zeros(x.shape)
    for k in range(coef.shape[-1] - 1, 0, -1):
        b1, b2 = 2.0 * x * b1 - b2 + coef[..., k, None], b1
    return x * b1 - b2 + coef[..., 0, None]


def _shape_at(
    mapping: FloatArray, coefs: FloatArray, fields: tuple[int, ...], s: ArrayLike
) -> tuple[Any, Any, Any, Any]:
    """(s, x, z, theta) of collocation states (map parameters, Chebyshev coefficients of
    theta, x, z) at arc lengths s: the body of the states' ``shape`` methods."""
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
        y = np.where(a > 0.0, np.log1p(flat[None, :] * np.expm1(a)) / np.where(a > 0, a, 1), flat)
    xi = 2.0 * y - 1.0
    coefs = coefs.reshape(3, -1, coefs.shape[-1])
    out = [_clenshaw(coefs[c], xi) for c in range(3)]
    fs = fields + flat.shape if sv.ndim else fields
    theta, x, z = (o.reshape(fs) for o in out)
    return sv, scalar_or_array(x), scalar_or_array(z), scalar_or_array(theta)


@dataclass(frozen=True, eq=False)
class LoadedState(CollocatedState):
    """A state of a hair under a tip load W and a load per unit height Pi (theory.md §11).

    Scalar inputs give float fields, array inputs arrays of the broadcast shape. Where no
    state was found (``status`` < 0) every value field is NaN.

    Attributes
    ----------
    drive : str
        "pressure" (set pressure gradient pi) or "flow" (set flow rate q).
    omega2 : float or ndarray
        The paper's wall forcing omega^2 [-] (the moving top wall).
    eps : float or ndarray
        Confinement eps = L/H [-].
    theta0 : float or ndarray
        Base angle from the wall normal [rad].
    pi : float or ndarray
        Dimensionless pressure gradient pi = A G L^3/(E I) [-] (NaN for the flow drive).
    q : float or ndarray
        Dimensionless flow rate q = 6 A eta Q' L^2/(E I H^2) [-] (NaN for the pressure drive).
    tip_height : float or ndarray
        h1 = z(1) [L].
    tip_deflection : float or ndarray
        x1 = x(1) [L].
    tip_angle : float or ndarray
        theta(1) [rad].
    base_curvature : float or ndarray
        theta'(0) [1/L], = W h1 + Pi h1^2/2.
    tip_load : float or ndarray
        W at the state [-]: the load on the tip plane.
    distributed_load : float or ndarray
        Pi at the state [-]: the load per unit height inside the bed.
    status : int or ndarray
        0 converged within the tolerance; 3 converged, but the error estimate misses it; -1
        no such state at the closed-form start (``root="mid"`` outside a window); -2
        iteration limit; -3 singular Newton matrix or no descent; -7 no state from this start
        (``STATUS_MESSAGES``).
    error_estimate : float or ndarray
        The Chebyshev tail of theta (sum of the moduli of its last three coefficients) [rad]:
        an estimate of the error of theta, x and z.
    residual : float or ndarray
        The largest residual of the collocation equations at the returned state.
    nit : int or ndarray
        Newton iterations over every level of the ladder.
    num : int or ndarray
        The Chebyshev degree N of the returned state.
    stable : bool or None
        From :func:`solve_loaded_all`: True where the state is stable under a slow change of
        the tip height (dG/dh1 < 0 of the fixed-load map G, theory.md §11); None otherwise.
    """

    drive: str
    omega2: Value
    eps: Value
    theta0: Value
    pi: Value
    q: Value
    tip_height: Value
    tip_deflection: Value
    tip_angle: Value
    base_curvature: Value
    tip_load: Value
    distributed_load: Value
    status: IntValue
    error_estimate: Value
    residual: Value
    nit: IntValue
    num: IntValue
    _map: FloatArray
    _coefs: FloatArray
    stable: Any = None

    def shape(self, s: ArrayLike) -> tuple[Any, Any, Any, Any]:
        """The hair at arc lengths ``s``: (s, x, z, theta).

        Parameters
        ----------
        s : array_like
            Arc lengths in [0, 1] [L], the same for every state (1-d or scalar).

        Returns
        -------
        s, x, z, theta : ndarray
            x, z [L] and theta [rad] of shape ``self.shape_of_fields + s.shape`` (the
            Chebyshev interpolants of the collocation, spectrally accurate between the nodes).
        """
        return _shape_at(self._map, self._coefs, self.shape_of_fields, s)


def _check_scalars(
    omega2: Any, eps: Any, theta0: Any, pi: Any, q: Any, what: str
) -> tuple[str, int, FloatArray, FloatArray, FloatArray, FloatArray]:
    """:func:`_check` of inputs that must be single numbers (``what`` takes no arrays)."""
    named = (("omega2", omega2), ("eps", eps), ("theta0", theta0), ("pi", pi), ("q", q))
    for name, value in named:
        if value is None:
            continue
        try:
            shape: Any = np.shape(value)
        except ValueError:  # a ragged nested list
            shape = "ragged"
        if shape != ():
            raise ValueError(
                f"{name} must be a single number (a scalar) for {what}: it follows one "
                f"branch; got "
                f"shape {shape}"
            )
    return _check(omega2, eps, theta0, pi, q)


def _quiet(func: Any) -> Any:
    """Run ``func`` with numpy's overflow warnings off: loads near the float range overflow on
    the way, and the state's status says what came of it (-7: not reached)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return func(*args, **kwargs)

    return wrapper


def _check_load(value: Any, name: str) -> FloatArray:
    return as_float_array(value, name)


def solve_loaded(
    omega2: ArrayLike,
    eps: ArrayLike,
    theta0: ArrayLike = 0.0,
    *,
    pi: ArrayLike | None = None,
    q: ArrayLike | None = None,
    root: str = "low",
    guess: Solution | None = None,
    num: int | None = None,
    rtol: float = 1e-12,
) -> LoadedState:
    """A hair under a tip load and a load per unit height, by Chebyshev collocation.

    Solves theta'' = -[W + Pi (h1 - z)] cos(theta), theta(0) = theta0, theta'(1) = 0,
    z' = cos(theta), h1 = z(1), with the loads of a drive (theory.md §11):

    * pressure drive (``pi`` given, or neither): Pi = pi and
      W = omega2/(1 - eps h1) + (pi/2)(1/eps - h1); pi = 0 is :func:`hairbed.solve`'s problem;
    * flow drive (``q`` given), with u = 1 - eps h1: W = q/u^2 - 2 omega2/u and
      Pi = 2 eps q/u^3 - 6 eps omega2/u^2.

    Parameters
    ----------
    omega2 : array_like
        Wall forcing omega^2 [-], finite (negative: the wall moves towards -x).
    eps : array_like
        Confinement eps = L/H [-], in [0, 1); > 0 where pi != 0.
    theta0 : array_like, optional
        Base angle [rad], in (-pi/2, pi/2). Default 0.
    pi : array_like, optional
        Dimensionless pressure gradient pi = A G L^3/(E I) [-], finite.
    q : array_like, optional
        Dimensionless flow rate q = 6 A eta Q' L^2/(E I H^2) [-], finite. At most one of
        ``pi`` and ``q``.
    root : {"low", "mid", "high"}, optional
        Which state where several coexist. At pi = 0 the state of :func:`hairbed.solve`'s
        ``root`` (Newton starts from it). For a loaded drive, "mid" and "high" are the
        middle (of three) and highest tip height of :func:`solve_loaded_all`'s scan, and
        "low" (default) the state Newton reaches from the closed-form start (the scan's
        lowest where Newton fails: in the windows, which need theta0 < 0, the hair rises as
        it bends, so the lowest is the least deformed, as ``hairbed.solve``'s "low").
    guess : Solution, optional
        A closed-form state (of the broadcast shape, or a single one) to start from instead.
    num : int, optional
        A fixed Chebyshev degree N in [8, 512] instead of the ladder ``LADDER`` (32, 64, 128).
    rtol : float, optional
        Tolerance on the Chebyshev tail of theta [rad]; default 1e-12.

    Returns
    -------
    LoadedState

    Raises
    ------
    ValueError
        For inputs outside their ranges (naming the parameter, its range and the first bad
        index), both ``pi`` and ``q``, or pi != 0 with eps = 0.

    Examples
    --------
    >>> import hairbed
    >>> st = hairbed.solve_loaded(2.0, 0.5)
    >>> round(st.tip_height, 12)
    0.732706963462
    """
    drive, code, w, e, t0, ld = _check(omega2, eps, theta0, pi, q)
    root = check_root(root)
    tol = check_positive(rtol, "rtol")
    nums = LADDER if num is None else (check_int(num, "num", 8, 512),)
    if guess is not None and not isinstance(guess, Solution):
        raise TypeError(f"guess must be a hairbed.Solution, got {type(guess).__name__}")
    if guess is not None:
        _check_guess_shape(guess, w.shape)
    # loads near the float range overflow on the way (a state is then not reached: status -7)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _solve_loaded_checked(drive, code, w, e, t0, ld, root, tol, nums, guess)


def _check_guess_shape(guess: Solution, shape: tuple[int, ...]) -> None:
    """A guess must be a single state or broadcast to the inputs' shape ``shape``."""
    gshape = np.shape(guess.t)
    try:
        ok = np.broadcast_shapes(gshape, shape) == shape
    except ValueError:
        ok = False
    if not ok:
        raise ValueError(
            f"guess must be a single state or of the inputs' broadcast shape {shape}, got "
            f"shape {gshape}"
        )


def _solve_loaded_trusted(
    drive: str, omega2: FloatArray, eps: float, theta0: float, load: FloatArray, root: str
) -> LoadedState:
    """:func:`solve_loaded` of inputs checked by the caller (the SI layer): omega2 and load
    finite arrays of one shape, eps in (0, 1), |theta0| < pi/2, a valid root; default
    tolerance and ladder."""
    w = np.asarray(omega2, dtype=np.float64)
    shape = w.shape
    e, t0 = np.full(shape, float(eps)), np.full(shape, float(theta0))
    ld = np.broadcast_to(np.asarray(load, dtype=np.float64), shape).copy()
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _solve_loaded_checked(drive, _DRIVES[drive], w, e, t0, ld, root, 1e-12, LADDER)


def _solve_loaded_checked(
    drive: str,
    code: int,
    w: FloatArray,
    e: FloatArray,
    t0: FloatArray,
    ld: FloatArray,
    root: str,
    tol: float,
    nums: tuple[int, ...],
    guess: Solution | None = None,
) -> LoadedState:
    """:func:`solve_loaded` of checked, broadcast inputs (``_check``), trusted."""
    fixed_num = nums != LADDER
    shape = w.shape
    wf, ef, tf, lf = (np.ascontiguousarray(v).reshape(-1) for v in (w, e, t0, ld))
    if guess is None:
        ts, es, ths, mirror, hs = _start(code, wf, ef, lf, tf, root)
    else:
        ts, es, ths, hs = (
            np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=np.float64), shape)).reshape(
                -1
            )
            for v in (guess.t, guess.eps, guess.theta0, guess.tip_height)
        )
        mirror = np.ones(wf.size)
    a = _map_parameter(code, wf, ef, lf, hs)
    ok = ~np.isnan(ts)  # t = -inf is the hair at rest (no load): a start too
    theta_start = _closed_form_start(ts, es, ths, mirror, a, nums, ok)
    hs = np.where(ok, hs, np.cos(tf))
    out, coefs = _run(code, wf, ef, lf, tf, a, theta_start, hs, nums, tol, ok)
    if guess is None and not fixed_num:
        exact = (code == 0) & (lf == 0.0)
        scan = ~exact if root != "low" else np.zeros(wf.size, dtype=np.bool_)
        _rescue(drive, code, wf, ef, tf, lf, root, tol, out, coefs, a, scan)
    return _state(drive, code, shape, w, e, t0, ld, out, coefs, a)


#: The most failed elements of one call that :func:`_rescue` scans (each ~0.1 s).
MAX_RESCUE = 100


def _rescue(
    drive: str,
    code: int,
    wf: FloatArray,
    ef: FloatArray,
    tf: FloatArray,
    lf: FloatArray,
    root: str,
    tol: float,
    out: FloatArray,
    coefs: FloatArray,
    a: FloatArray,
    scan: NDArray[np.bool_],
) -> None:
    """Where Newton and the load continuation failed (status -2, -3, -7; a fold on the way),
    and on every element of ``scan`` (root "mid" or "high" of a loaded drive), the scan of
    :func:`solve_loaded_all` for that element and its state of ``root`` (the lowest, middle
    of three, highest tip height), written into out, coefs and a in place. At most
    ``MAX_RESCUE`` failed elements a call; the others keep their failure status."""
    failed = np.flatnonzero(np.isin(out[0], (-2, -3, -7)) & ~scan)[:MAX_RESCUE]
    for i in np.union1d(failed, np.flatnonzero(scan)):
        kw = {"pi": lf[i]} if drive == "pressure" else {"q": lf[i]}
        found = [s for s in solve_loaded_all(wf[i], ef[i], tf[i], rtol=tol, **kw) if s.status >= 0]
        if not found or (root == "mid" and len(found) < 3):
            out[0, i] = -1 if found else out[0, i]
            continue
        pick = found[0] if root == "low" else found[-1] if root == "high" else found[1]
        out[0, i] = pick.status
        for c, name in enumerate(_COLUMNS):
            if name:
                out[c, i] = getattr(pick, name)
        top = pick._coefs.shape[-1]
        coefs[:, i, :top] = pick._coefs
        a[i] = float(pick._map)


#: LoadedState's field of each kernel column (status handled apart).
_COLUMNS = (
    "",
    "nit",
    "num",
    "",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
    "tip_load",
    "distributed_load",
    "error_estimate",
    "residual",
)


def _check(
    omega2: Any, eps: Any, theta0: Any, pi: Any, q: Any
) -> tuple[str, int, FloatArray, FloatArray, FloatArray, FloatArray]:
    """The inputs validated and broadcast: (drive, code, omega2, eps, theta0, pi or q)."""
    if pi is not None and q is not None:
        raise ValueError("give at most one of pi (pressure drive) and q (flow drive), got both")
    drive = "flow" if q is not None else "pressure"
    code = _DRIVES[drive]
    w = as_float_array(omega2, "omega2")
    e = as_float_array(eps, "eps")
    t0 = as_float_array(theta0, "theta0")
    _check_range(e, (e < 0.0) | (e >= 1.0), "eps", "[0, 1)")
    _check_range(t0, np.abs(t0) >= HALF_PI, "theta0", "(-pi/2, pi/2)")
    name = "q" if q is not None else "pi"
    ld = _check_load(q if q is not None else (0.0 if pi is None else pi), name)
    w, e, t0, ld = broadcast_named(("omega2", w), ("eps", e), ("theta0", t0), (name, ld))
    if code == 0:
        bad = (ld != 0.0) & (e == 0.0)
        if np.any(bad):
            raise ValueError(
                f"pi != 0 needs eps > 0 (the gap flow's load W has (pi/2)/eps), got pi = "
                f"{float(ld[bad].flat[0])!r} with eps = 0{_first_index(bad)}"
            )
    return drive, code, w, e, t0, ld


def _mapped_nodes(a: FloatArray, num: int) -> FloatArray:
    """s at the N + 1 mapped Chebyshev nodes of each element's map parameter: (size, N + 1)
    (a > 0 clusters them at the base, a < 0 at the tip, as the porous bed's thin layer wants)."""
    xi = _matrices(num)[0]
    y = (xi + 1.0) / 2.0
    with np.errstate(invalid="ignore", divide="ignore"):
        sig = np.where(
            a[:, None] != 0.0,
            np.expm1(a[:, None] * y[None, :]) / np.expm1(np.where(a != 0, a, 1.0))[:, None],
            y[None, :],
        )
    sig = np.clip(sig, 0.0, 1.0)
    sig[:, 0] = 0.0
    sig[:, -1] = 1.0
    return np.ascontiguousarray(sig)


def _closed_form_start(
    ts: FloatArray,
    es: FloatArray,
    ths: FloatArray,
    mirror: FloatArray,
    a: FloatArray,
    nums: tuple[int, ...],
    ok: NDArray[np.bool_],
) -> FloatArray:
    """theta of the closed-form start states at the first level's mapped nodes."""
    sig = _mapped_nodes(a, nums[0])
    start = np.empty((6, ts.size, nums[0] + 1))
    from ._kernels import state as closed

    closed.shape_array(np.where(ok, ts, -np.inf), es, ths, 1, 0, sig, start)
    return np.ascontiguousarray(mirror[:, None] * start[0])


def _description(
    code: int, wf: FloatArray, ef: FloatArray, lf: FloatArray, tf: FloatArray
) -> FloatArray:
    """The kernel's load description of every element, (size, NDESC): the bed's slots of
    ``_kernels.description``: the wall's omega2 and Pi (pressure drive) or q (flow drive);
    for the scan's frozen loads (code 2) the tip force W and Pi."""
    desc = np.zeros((wf.size, D.NDESC))
    desc[:, D.D_THETA0] = tf
    desc[:, D.D_EPS] = ef
    desc[:, D.D_TIP if code == 2 else D.D_OMEGA2] = wf
    desc[:, D.D_Q if code == 1 else D.D_PI] = lf
    return desc


def _run(
    code: int,
    wf: FloatArray,
    ef: FloatArray,
    lf: FloatArray,
    tf: FloatArray,
    a: FloatArray,
    theta_start: FloatArray,
    hs: FloatArray,
    nums: tuple[int, ...],
    tol: float,
    ok: NDArray[np.bool_],
) -> tuple[FloatArray, FloatArray]:
    """The kernel on flat arrays: (out (NCOLS, size), coefs (3, size, N + 1)); elements
    without a start (not ``ok``) get status -1 and NaN values."""
    k = _kernels()
    out = np.empty((k.NCOLS, wf.size))
    coefs = np.empty((3, wf.size, int(max(nums)) + 1))
    k.solve_loaded_array(
        code,
        _description(code, wf, ef, lf, tf),
        a,
        theta_start,
        hs[:, None],
        *_ladder(tuple(nums)),
        tol,
        _NO_PROFILE,
        out,
        coefs,
    )
    out[0, ~ok] = -1
    out[4:, ~ok] = np.nan
    coefs[:, ~ok, :] = np.nan
    return out, coefs


def _state(
    drive: str,
    code: int,
    shape: tuple[int, ...],
    w: FloatArray,
    e: FloatArray,
    t0: FloatArray,
    ld: FloatArray,
    out: FloatArray,
    coefs: FloatArray,
    a: FloatArray,
    stable: Any = None,
) -> LoadedState:
    """A LoadedState of the kernel's columns, reshaped to ``shape``."""
    nan = np.full(shape, np.nan)
    top = coefs.shape[-1]

    def col(i: int) -> Any:
        return scalar_or_array(out[i].reshape(shape))

    return LoadedState(
        drive=drive,
        omega2=scalar_or_array(w.reshape(shape)),
        eps=scalar_or_array(e.reshape(shape)),
        theta0=scalar_or_array(t0.reshape(shape)),
        pi=scalar_or_array(ld.reshape(shape) if code == 0 else nan),
        q=scalar_or_array(ld.reshape(shape) if code == 1 else nan),
        tip_height=col(4),
        tip_deflection=col(5),
        tip_angle=col(6),
        base_curvature=col(7),
        tip_load=col(8),
        distributed_load=col(9),
        status=scalar_or_array(out[0].astype(np.int64).reshape(shape)),
        error_estimate=col(10),
        residual=col(11),
        nit=scalar_or_array(out[1].astype(np.int64).reshape(shape)),
        num=scalar_or_array(out[2].astype(np.int64).reshape(shape)),
        _map=a.reshape(shape),
        _coefs=coefs.reshape((3, *shape, top)),
        stable=stable,
    )


#: The tip heights of the scan of :func:`solve_loaded_all`: 12 geometric in [1e-4, 0.02], then
#: ``num_scan`` uniform in [0.02, 1].
_SCAN_LOW = (1e-4, 0.02, 12)
_BISECT_STEPS = 60
#: The bracket refinement ends where abs(G) at a bracket's end is below this, or the bracket
#: is narrower than _H_TOL max(1, h) (the polishing Newton of the drive follows).
_G_TOL = 1e-13
_H_TOL = 1e-7
#: Illinois steps before plain bisection: a true root converges in fewer; a sign change of a
#: G that jumps (the frozen-load state of a strong load switching between solutions) does not.
_ILLINOIS_STEPS = 8


def _fixed_load_states(
    code: int, w: Any, e: float, ld: Any, t0: float, h: FloatArray, tol: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The states with the loads frozen at the drive's W(h), Pi(h), for every h: (out, coefs,
    a) of the kernel (drive code 2: no feedback through h1); w and ld scalars or of h's shape."""
    full = [
        np.array(np.broadcast_to(np.asarray(v, dtype=np.float64), h.shape)) for v in (w, e, ld)
    ]
    big_w, big_p = _loads(code, full[0], full[1], full[2], h)
    big_w = np.ascontiguousarray(big_w, dtype=np.float64)
    big_p = np.ascontiguousarray(big_p, dtype=np.float64)
    zero = np.zeros(h.size)
    tf = np.full(h.size, t0)
    ts, es, ths, mirror, hs = _start(2, big_w, zero, big_p, tf, "low")
    a = _map_parameter(2, big_w, zero, big_p, hs)
    ok = ~np.isnan(ts)  # t = -inf: the hair at rest
    theta_start = _closed_form_start(ts, es, ths, mirror, a, LADDER, ok)
    out, coefs = _run(
        2, big_w, zero, big_p, tf, a, theta_start, np.where(ok, hs, 1.0), LADDER, tol, ok
    )
    return out, coefs, a


def _gap(code: int, w: Any, e: float, ld: Any, t0: float, h: FloatArray, tol: float) -> Any:
    """G(h) = h1 of the frozen-load state minus h (NaN where that state was not found)."""
    out = _fixed_load_states(code, w, e, ld, t0, h, tol)[0]
    return np.where(out[0] >= 0, out[4] - h, np.nan)


@_quiet
def solve_loaded_all(
    omega2: float,
    eps: float,
    theta0: float = 0.0,
    *,
    pi: float | None = None,
    q: float | None = None,
    num_scan: int = 64,
    rtol: float = 1e-12,
) -> list[LoadedState]:
    """Every coexisting state of the fundamental family at scalar inputs, by a scan in h1.

    With the loads frozen at the drive's W(h), Pi(h), the hair has a state of tip height
    z1(h); the states of the drive are the roots of G(h) = z1(h) - h on 0 < h <= 1. G is
    scanned on 12 geometric points in [1e-4, 0.02] and ``num_scan`` uniform ones in [0.02, 1],
    each sign change refined (all brackets at once) by at most 8 steps of the Illinois
    variant of regula falsi (superlinear, the bracket kept), then bisection, until
    abs(G) < 1e-13 at an end or the bracket is narrower than 1e-7 (60 steps at most; a
    bracket whose abs(G) did not fall tenfold in the Illinois steps is a jump of G and is
    left there), and
    each root polished by :func:`solve_loaded`'s Newton from the frozen state there. Two roots
    closer than a scan cell (a tangency, the edge of a window) can be missed.

    Parameters
    ----------
    omega2, eps, theta0, pi, q, rtol
        As in :func:`solve_loaded`, scalars.
    num_scan : int, optional
        Uniform scan points in [0.02, 1], in [8, 10^4]. Default 64.

    Returns
    -------
    list of LoadedState
        Sorted by tip height, each with ``stable`` (dG/dh < 0 at the root: True stable).
        Never empty: where the scan finds no state (loads near the float range's end) one
        state of NaN values whose ``status`` (-7) and ``message`` say so.

    Examples
    --------
    >>> import hairbed
    >>> [round(s.tip_height, 6) for s in hairbed.solve_loaded_all(0.51, 0.95, -1.2)]
    [0.536514, 0.78824, 0.884061]
    """
    drive, code, w, e, t0, ld = _check_scalars(omega2, eps, theta0, pi, q, "solve_loaded_all")
    tol = check_positive(rtol, "rtol")
    count = check_int(num_scan, "num_scan", 8, 10**4)
    wf, ef, lf, tf = float(w), float(e), float(ld), float(t0)
    h = np.unique(np.concatenate([np.geomspace(*_SCAN_LOW), np.linspace(0.02, 1.0, count)]))
    g = _gap(code, wf, ef, lf, tf, h, tol)
    lo_i = np.flatnonzero(np.isfinite(g[:-1]) & np.isfinite(g[1:]) & (g[:-1] * g[1:] <= 0.0))
    lo_i = lo_i[~np.isin(lo_i - 1, lo_i) | (g[lo_i] != 0.0)]  # a zero on a node counts once
    if lo_i.size == 0:
        return [_no_state(drive, code, w, e, t0, ld)]
    lo, hi = h[lo_i], h[lo_i + 1]
    glo, ghi = g[lo_i], g[lo_i + 1]
    stable = glo > ghi
    # Illinois: the secant point of the bracket; an end kept twice in a row has its G halved
    # (each refinement is a whole batch of frozen-load solves: few steps keep the scan cheap)
    side = np.zeros(lo.size, dtype=np.int64)  # -1: lo was kept last step, +1: hi
    tlo, thi = glo.copy(), ghi.copy()  # the true G at the ends (glo, ghi: Illinois weights)
    g_start = np.minimum(np.abs(glo), np.abs(ghi))
    jump = np.zeros(lo.size, dtype=np.bool_)
    for step in range(_BISECT_STEPS):
        best = np.minimum(np.abs(tlo), np.abs(thi))
        if step == _ILLINOIS_STEPS:
            # G did not fall tenfold in the Illinois steps: it jumps there (no root to refine;
            # the polish from the better end decides)
            jump = best > 0.1 * g_start
        done = jump | (best <= _G_TOL) | (hi - lo <= _H_TOL * np.maximum(1.0, hi))
        if np.all(done):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            secant = (lo * ghi - hi * glo) / (ghi - glo)
        mid = secant if step < _ILLINOIS_STEPS else 0.5 * (lo + hi)
        # a secant point at an end (or not finite) is replaced by the midpoint
        bad = ~np.isfinite(mid) | (mid <= lo) | (mid >= hi)
        mid = np.where(bad, 0.5 * (lo + hi), mid)
        gm = glo.copy()  # only the brackets not done are refined
        gm[~done] = _gap(code, wf, ef, lf, tf, mid[~done], tol)
        gm = np.where(np.isfinite(gm), gm, 0.0)
        left = (np.sign(gm) == np.sign(glo)) & ~done
        right = ~left & ~done
        lo_new, glo_new = np.where(left, mid, lo), np.where(left, gm, glo)
        hi_new, ghi_new = np.where(right, mid, hi), np.where(right, gm, ghi)
        tlo, thi = np.where(left, gm, tlo), np.where(right, gm, thi)
        # the end kept (hi where lo moved, lo where hi moved) twice in a row: halve its G
        ghi_new = np.where(left & (side == 1), 0.5 * ghi_new, ghi_new)
        glo_new = np.where(right & (side == -1), 0.5 * glo_new, glo_new)
        side = np.where(left, 1, np.where(right, -1, side))
        lo, glo, hi, ghi = lo_new, glo_new, hi_new, ghi_new
    root = np.where(np.abs(tlo) <= np.abs(thi), lo, hi)
    # polish with the drive's own Newton, from the frozen state at each root
    out_f, coefs_f, a_f = _fixed_load_states(code, wf, ef, lf, tf, root, tol)
    size = root.size
    wa, ea, ta, la = (np.full(size, v) for v in (wf, ef, tf, lf))
    a = _map_parameter(code, wa, ea, la, root)
    sig = _mapped_nodes(a, LADDER[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        af = a_f[:, None]
        y = np.where(af > 0.0, np.log1p(sig * np.expm1(af)) / np.where(af > 0, af, 1.0), sig)
    theta_start = np.ascontiguousarray(_clenshaw(coefs_f[0], 2.0 * y - 1.0))
    ok = (out_f[0] >= 0) & np.all(np.isfinite(theta_start), axis=1)
    theta_start[~ok] = tf
    out, coefs = _run(code, wa, ea, la, ta, a, theta_start, root, LADDER, tol, ok)
    order = np.argsort(np.where(np.isfinite(out[4]), out[4], np.inf), kind="stable")
    if np.all(out[0] < 0):
        return [_no_state(drive, code, w, e, t0, ld, int(out[0, 0]))]
    states: list[LoadedState] = []
    last = -np.inf
    for i in order:
        if out[0, i] < 0 or abs(out[4, i] - last) <= 1e-9:
            continue
        last = out[4, i]
        states.append(
            _state(
                drive,
                code,
                (),
                w,
                e,
                t0,
                ld,
                out[:, i : i + 1],
                coefs[:, i : i + 1],
                a[i : i + 1],
                stable=bool(stable[i]),
            )
        )
    return states


def _no_state(
    drive: str,
    code: int,
    w: FloatArray,
    e: FloatArray,
    t0: FloatArray,
    ld: FloatArray,
    status: int = -7,
) -> LoadedState:
    """The one state of :func:`solve_loaded_all` where its scan found none (loads near the
    float range's end): NaN values and a negative ``status`` (-7 where no root was found)."""
    out = np.full((_kernels().NCOLS, 1), np.nan)
    out[0] = status
    out[1:3] = 0
    coefs = np.full((3, 1, max(LADDER) + 1), np.nan)
    return _state(drive, code, (), w, e, t0, ld, out, coefs, np.zeros(1))
