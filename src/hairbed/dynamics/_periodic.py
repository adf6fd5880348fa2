"""The porous bed's periodic steady state by collocation in time (issue 31, theory.md §16).

Under drives of period P = 2 pi/omega the semi-discrete bed M y' = g(t, y) of
:func:`hairbed.dynamics.simulate_bed` (theory.md §15) has a periodic state. Here it is found
directly, not by integrating until the transient decays:

* **Trigonometric collocation in time.** y(t) is the trigonometric polynomial of degree H
  through K = 2H + 1 equispaced phases t_k = k P/K (odd K: no Nyquist mode), and
  M (D y)_k = g(t_k, y_k) holds at every phase, D the exact derivative of the interpolant
  (by the FFT). For a smooth periodic state the error falls geometrically with H.
* **Newton** on the K m unknowns with the exact Jacobian (the kernel's dg/dy at every phase):
  M D dY - diag(J_k) dY = -R. Quadratic convergence (measured: steps 1e-1, 3e-3, 9e-7, 7e-14).
* **The linear solve.** At each phase the algebraic unknowns (mass 0) are eliminated by the
  Schur complement, dy_a = J_aa^-1 (R_a - J_ad dy_d), which leaves the differential ones:
  M_d D dy_d - A_k dy_d = r, A_k = J_dd - J_da J_aa^-1 J_ad. That system is solved by GMRES
  (Saad & Schultz 1986) preconditioned by its phase average: in frequency, one
  (i j omega M_d - mean_k A_k) solve per harmonic j (measured 4 to 12 iterations to 1e-12).
* **The degree.** From H = ``harmonics`` (default 12) H doubles, the last state interpolated as
  the start, until the two highest harmonics' amplitudes lie below ``tol`` of each
  component's scale 1 + max abs(y) (the error of the truncation, geometric decay).
* **The start.** The linear periodic response about the steady state of the drives' means
  (one (i j omega M - J) solve per harmonic of the drives); if Newton fails from it, the
  quasi-static states (g(t_k, y_k) = 0 phase by phase, the low-frequency limit); then
  continuation in the drives' swing; last, where these fail or end beyond abs(theta) =
  pi/2, the state approached in time (the bed integrated period after period until it
  settles: hairs that snap through within a small part of the period), its spectrum
  choosing the first degree.

:func:`periodic_sensitivity` solves the forced variational equation M S' = J(t) S + G(t) for
its periodic solution on the same collocation and factors: for parameter columns G = dg/dp
this is dy/dp along the periodic orbit (implicit differentiation of the periodic state;
S(0) = dy0/dp = (I - Phi)^-1 times the forced solution from rest over one period, Phi the
monodromy matrix), and the derivatives of the period-means of the outputs follow.
:func:`periodic_adjoint` solves the transposed problem once for one output's period mean,
whose derivatives in any number of parameters are then dot products with their columns.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._core.validation import (
    StatusResult,
    as_float_array,
    check_int,
    check_number,
    show,
    status_messages,
)
from ._bed import (
    BED_OUTPUTS,
    _angles,
    _bounded_drive,
    _checked_bed,
    _consistent,
    _drive_columns,
    _evaluate,
    _mass,
    _newton_steady,
    _output_values,
    _pump_drive,
    _static_start,
    _System,
    _system,
    _top_drive,
)
from ._signals import Signal, as_signal, constant, sine

__all__ = [
    "PERIODIC_ADJOINT_STATUS",
    "PERIODIC_STATUS",
    "PeriodicAdjoint",
    "PeriodicBed",
    "PeriodicSensitivity",
    "periodic_adjoint",
    "periodic_bed",
    "periodic_sensitivity",
]

FloatArray = NDArray[np.float64]

#: Status codes of :class:`PeriodicBed`.
PERIODIC_STATUS: Mapping[int, str] = MappingProxyType(
    {
        0: "periodic: Newton converged and the truncation error is below tol",
        1: "Newton converged, but the highest harmonics exceed tol at max_harmonics",
        -1: "Newton did not converge (from the linear, quasi-static, continuation and "
        "transient starts)",
        -3: "a rate is not finite at the periodic state's phases",
        -8: "the periodic state reaches abs(theta) = pi/2 at a node (outside the model)",
    }
)

#: The Krylov solver's relative tolerance on the preconditioned residual and its iterations.
_KRYLOV_TOL = 1e-12
_KRYLOV_MAX = 100
#: The phase-averaged preconditioner's GMRES iterations before the time-varying one is taken.
_AVERAGE_MAX = 40
#: Newton's largest step in the angles [rad] (a longer step is shortened to it).
_MAX_TURN = 0.5
#: The transient start (:func:`_transient_start`): at most this many periods, until the
#: state at the period's start changes by less than _SETTLE_TOL of its scale per period
#: (Newton then converges from it), integrated to _SETTLE_RTOL and _SETTLE_ATOL (at atol
#: 1e-12 the Radau steps stall on the rates' rounding: 10^6 steps for 4 periods, measured)
#: in at most _SETTLE_STEPS steps in all (about a minute at N = 32: 0.56 ms a step); its
#: harmonics above _SETTLE_FLOOR (of each component's scale) choose the first degree.
_SETTLE_PERIODS = 2000
_SETTLE_TOL = 1e-7
_SETTLE_RTOL = 1e-9
_SETTLE_ATOL = 1e-10
_SETTLE_STEPS = 100_000
_SETTLE_FLOOR = 1e-7


@dataclass(frozen=True)
class PeriodicBed:
    """The porous bed's periodic steady state (:func:`periodic_bed`).

    Attributes
    ----------
    omega, period : float
        The base angular frequency [1/T] and the period P = 2 pi/omega [T].
    t : ndarray
        The K = 2H + 1 collocation phases t_k = k P/K [T].
    y : ndarray
        The states there, (K, size), in the layout of :func:`hairbed.dynamics.bed_operators`.
    outputs : mapping of str to ndarray
        ``BED_OUTPUTS`` and ``wall_speed``, ``pressure`` at the phases (K,), in the units of
        :class:`hairbed.dynamics.BedTrajectory`.
    harmonics : int
        H, the trigonometric degree.
    error : float
        The truncation's estimate: the two highest harmonics' amplitudes over each
        component's 1 + max abs(y) [-].
    iterations : int
        Newton iterations (all degrees).
    krylov_iterations : int
        GMRES iterations (all Newton steps).
    start : str
        "linear", "quasi-static", "continuation" or "transient": the start Newton converged
        from.
    status : int
        ``PERIODIC_STATUS``.
    """

    omega: float
    period: float
    t: FloatArray
    y: FloatArray
    outputs: Mapping[str, FloatArray]
    harmonics: int
    error: float
    iterations: int
    krylov_iterations: int
    start: str
    status: int
    _sys: _System = field(repr=False)
    _pump: Signal = field(repr=False)

    @property
    def success(self) -> bool:
        """True where status is 0."""
        return self.status == 0

    @property
    def y_t(self) -> FloatArray:
        """dy/dt at the phases [1/T], (K, size): the exact derivative of the trigonometric
        interpolant (the collocation's D y)."""
        return _derivative(self.y, self.omega)

    @property
    def message(self) -> Any:
        """``PERIODIC_STATUS`` of ``status``."""
        return status_messages(self.status, PERIODIC_STATUS)

    def states_at(self, t: ArrayLike) -> FloatArray:
        """The states at times t [T] (any, taken modulo P) by the trigonometric interpolant:
        (len(t), size)."""
        tt = np.mod(as_float_array(t, "t").reshape(-1), self.period)
        return _interpolate(self.y, self.omega, tt)

    def outputs_at(self, t: ArrayLike) -> dict[str, FloatArray]:
        """``BED_OUTPUTS`` (and ``wall_speed``, ``pressure``) at times t [T]."""
        tt = np.mod(as_float_array(t, "t").reshape(-1), self.period)  # the drives' period too
        ys = self.states_at(tt)
        pump = np.asarray(self._pump(tt), dtype=np.float64).reshape(tt.shape)
        return {k: np.asarray(v, dtype=np.float64) for k, v in
                _output_values(self._sys, ys, pump).items()}  # fmt: skip

    def mean(self, output: str) -> float:
        """The period-mean of an output (exact for the trigonometric polynomial: the mean of
        its values at the K phases)."""
        if not isinstance(output, str) or output not in self.outputs:
            raise ValueError(f"output must be one of {sorted(self.outputs)}, got {show(output)}")
        return float(np.mean(self.outputs[output]))


def _derivative(y: FloatArray, omega: float) -> FloatArray:
    """The exact time derivative of the trigonometric interpolant of y (K, ...) at its K
    equispaced phases (period 2 pi/omega), by the FFT."""
    c = np.fft.rfft(y, axis=0)
    c *= (1j * omega * np.arange(c.shape[0])).reshape((-1,) + (1,) * (y.ndim - 1))
    return np.fft.irfft(c, n=y.shape[0], axis=0)


def _interpolate(y: FloatArray, omega: float, t: FloatArray) -> FloatArray:
    """The trigonometric interpolant of the K = 2H + 1 equispaced values y (K, m) at t."""
    kk = y.shape[0]
    c = np.fft.rfft(y, axis=0) / kk
    c[1:] *= 2.0
    e = np.exp(1j * omega * np.outer(t, np.arange(c.shape[0])))
    return np.ascontiguousarray(np.real(e @ c))


def _periodic_drive(value: Any, name: str, omega: float) -> Signal:
    """A constant or a sine whose frequency is a whole multiple of omega."""
    sig = _bounded_drive(as_signal(value, name, 0.0, 1.0), name)
    if sig.kind == "constant":
        return sig
    if sig.kind != "sine":
        raise ValueError(
            f"{name} must be a number or a hairbed.dynamics.sine of a whole multiple of omega "
            f"for a periodic state, got a {sig.kind} drive"
        )
    ratio = sig.params[2] / omega
    if not (ratio >= 0.5 and abs(ratio - round(ratio)) <= 1e-12 * ratio):
        raise ValueError(
            f"{name}'s frequency {show(sig.params[2])} [1/T] must be a whole multiple of "
            f"omega = {show(omega)} [1/T] (the period's harmonics), got ratio {ratio:.6g}"
        )
    return sig


def _mean_value(sig: Signal) -> float:
    return float(sig.params[0])


class _Problem:
    """One bed under periodic drives: its index sets and the collocation's operations."""

    def __init__(self, sys: _System, omega: float) -> None:
        self.sys = sys
        self.omega = omega
        self.m = sys.layout.size
        self.mass = _mass(sys)
        d = np.flatnonzero(self.mass != 0.0)
        a = np.flatnonzero(self.mass == 0.0)
        self.nd = d.size
        self.perm = np.concatenate([d, a])
        self.ident = bool(np.array_equal(self.perm, np.arange(self.m)))
        self.md = self.mass[d]
        from .._core._kernels import bed as kb

        self.kb = kb
        self.ws = kb.bed_workspace(sys.num, sys.num_gap)
        self.scratch = np.zeros((self.m, self.m))
        #: True once the phase-averaged preconditioner has failed: then the cyclic
        #: implicit Euler one (:func:`_cyclic_euler`) for every later solve
        self.time_varying = False

    def times(self, kk: int) -> FloatArray:
        return np.arange(kk) * (2.0 * math.pi / self.omega) / kk

    def rates(self, t: FloatArray, y: FloatArray, need: bool) -> tuple[bool, Any, Any]:
        """g (K, m) and, where ``need``, J (K, m, m) at the phases."""
        kk = t.size
        g = np.empty((kk, self.m))
        jac = np.zeros((kk, self.m, self.m)) if need else None
        ok = True
        for k in range(kk):
            out = jac[k] if jac is not None else self.scratch
            yk = np.ascontiguousarray(y[k])
            ok = self.kb.bed_system(float(t[k]), yk, need, self.sys.params, g[k], out, self.ws)
            if not ok:
                return False, g, jac
        return True, g, jac

    def derivative(self, y: FloatArray) -> FloatArray:
        """D y: the exact time derivative of the trigonometric interpolant at the phases."""
        return _derivative(y, self.omega)

    def solve(
        self, jac: FloatArray, rhs: FloatArray, strict: bool = True
    ) -> tuple[FloatArray, int]:
        """dY (K, m, p) of M D dY - J_k dY = rhs (K, m, p) on the periodic collocation (J_k
        the Jacobians (K, m, m) at the phases); the GMRES iterations (all columns).
        ``strict`` as :func:`_gmres`'s."""
        nd = self.nd
        kk, _, p = rhs.shape
        if self.ident:
            jp, rp = jac, rhs
        else:
            jp, rp = jac[:, self.perm][:, :, self.perm], rhs[:, self.perm]
        # the algebraic unknowns eliminated at each phase: J_aa^-1 [J_ad, r_a]
        xr = np.linalg.solve(jp[:, nd:, nd:], np.concatenate([jp[:, nd:, :nd], rp[:, nd:]], 2))
        x, ra = xr[:, :, :nd], xr[:, :, nd:]
        amat = jp[:, :nd, :nd] - jp[:, :nd, nd:] @ x
        red = rp[:, :nd] - jp[:, :nd, nd:] @ ra
        prec: Callable[[FloatArray], FloatArray]
        if self.time_varying:
            prec = _cyclic_euler(self.md, amat, 2.0 * math.pi / (self.omega * kk))
        else:
            prec = _phase_average(self.md, amat, self.omega)

        def apply(v: FloatArray) -> FloatArray:
            xv = v.reshape(kk, nd)
            out = self.md * self.derivative(xv) - (amat @ xv[:, :, None])[:, :, 0]
            return prec(out).reshape(-1)

        dd = np.empty((kk, nd, p))
        its = 0
        for j in range(p):
            if not self.time_varying:
                try:
                    xd, n_it = _gmres(apply, prec(red[:, :, j]).reshape(-1), True,
                                      _AVERAGE_MAX)  # fmt: skip
                except ArithmeticError:
                    # the phase average is no guide where the Jacobian swings with the
                    # phase (hairs swinging by radians, a dense bed): from here on the
                    # time-varying preconditioner, for this and the higher degrees
                    its += _AVERAGE_MAX
                    self.time_varying = True
                    prec = _cyclic_euler(self.md, amat, 2.0 * math.pi / (self.omega * kk))
                else:
                    dd[:, :, j] = xd.reshape(kk, nd)
                    its += n_it
                    continue
            xd, n_it = _gmres(apply, prec(red[:, :, j]).reshape(-1), strict)
            dd[:, :, j] = xd.reshape(kk, nd)
            its += n_it
        out = np.empty((kk, self.m, p))
        out[:, self.perm[:nd]] = dd
        out[:, self.perm[nd:]] = -ra - x @ dd
        return out, its


def _phase_average(
    md: FloatArray, amat: FloatArray, omega: float
) -> Callable[[FloatArray], FloatArray]:
    """The preconditioner of M_d D x - A_k x_k = r by its phase average: in frequency, one
    (i j omega M_d - mean_k A_k)^-1 per harmonic j. Exact where A does not vary with the
    phase; r and the result (K, nd)."""
    kk = amat.shape[0]
    w = omega * np.arange(kk // 2 + 1)
    pinv = np.linalg.inv(1j * w[:, None, None] * np.diag(md)[None] - amat.mean(0)[None])

    def prec(r: FloatArray) -> FloatArray:
        c = np.fft.rfft(r, axis=0)
        return np.fft.irfft((pinv @ c[:, :, None])[:, :, 0], n=kk, axis=0)

    return prec


def _cyclic_euler(
    md: FloatArray, amat: FloatArray, h: float
) -> Callable[[FloatArray], FloatArray]:
    """The preconditioner of M_d D x - A_k x_k = r by the periodic implicit Euler scheme on
    the same phases, with each phase's own A_k: M_d (x_k - x_(k-1))/h - A_k x_k = r_k,
    x_(-1) = x_(K-1) (h = P/K). It keeps the Jacobian's variation over the period, which the
    phase average loses where the hairs swing by radians; its derivative's symbol
    (1 - e^(-i theta))/h against the exact i theta/h (theta = j omega h) differs by a factor
    of modulus 1 to pi/2 and phase below pi/2 only, so GMRES's iterations stay bounded as K
    grows. Solved exactly by the recurrence x_k = C_k x_(k-1) + B_k^-1 r_k,
    B_k = M_d/h - A_k, C_k = B_k^-1 M_d/h, closed by the periodicity:
    x_(-1) = (I - C_(K-1) ... C_0)^-1 z_(K-1) with z the recurrence from zero;
    r and the result (K, nd)."""
    kk, nd, _ = amat.shape
    binv = np.linalg.inv(np.diag(md / h)[None] - amat)
    cmat = binv * (md / h)[None, None, :]
    prefix = np.empty_like(cmat)  # C_k ... C_0
    acc = np.eye(nd)
    for k in range(kk):
        acc = cmat[k] @ acc
        prefix[k] = acc
    close = np.linalg.inv(np.eye(nd) - acc)

    def prec(r: FloatArray) -> FloatArray:
        d = (binv @ r[:, :, None])[:, :, 0]
        z = np.empty_like(d)
        zk = np.zeros(nd)
        for k in range(kk):
            zk = cmat[k] @ zk + d[k]
            z[k] = zk
        return z + (prefix @ (close @ zk))

    return prec


def _gmres(
    apply: Callable[[FloatArray], FloatArray],
    b: FloatArray,
    strict: bool = True,
    limit: int | None = None,
) -> tuple[FloatArray, int]:
    """GMRES (Saad & Schultz 1986, Givens rotations, no restart) on the preconditioned
    system: x with ||apply(x) - b|| <= _KRYLOV_TOL ||b||; raises ArithmeticError beyond
    ``limit`` (default _KRYLOV_MAX) iterations where the residual has not fallen below 1e-6
    ||b||, unless not ``strict`` (a refinement's correction, whose right-hand side is the
    residual's rounding: then the best x of the iterations)."""
    n = b.size
    beta = float(np.linalg.norm(b))
    if beta == 0.0 or not math.isfinite(beta):
        if beta == 0.0:
            return np.zeros(n), 0
        raise ArithmeticError("a right-hand side is not finite")
    top = min(_KRYLOV_MAX if limit is None else limit, n)
    v = np.zeros((top + 1, n))
    h = np.zeros((top + 1, top))
    cs = np.zeros(top)
    sn = np.zeros(top)
    s = np.zeros(top + 1)
    s[0] = beta
    v[0] = b / beta
    for j in range(top):
        w = apply(v[j])
        basis = v[: j + 1]
        for _ in range(2):  # classical Gram-Schmidt, twice (CGS2: orthogonal to rounding)
            c = basis @ w
            h[: j + 1, j] += c
            w -= c @ basis
        hn = float(np.linalg.norm(w))
        h[j + 1, j] = hn
        for i in range(j):
            t = cs[i] * h[i, j] + sn[i] * h[i + 1, j]
            h[i + 1, j] = -sn[i] * h[i, j] + cs[i] * h[i + 1, j]
            h[i, j] = t
        r = math.hypot(h[j, j], hn)
        cs[j], sn[j] = (1.0, 0.0) if r == 0.0 else (h[j, j] / r, hn / r)
        h[j, j] = r
        s[j + 1] = -sn[j] * s[j]
        s[j] = cs[j] * s[j]
        done = abs(s[j + 1]) <= _KRYLOV_TOL * beta or hn == 0.0
        if done or j + 1 == top:
            if strict and not done and abs(s[j + 1]) > 1e-6 * beta:
                raise ArithmeticError("GMRES did not converge")
            yv = np.linalg.solve(np.triu(h[: j + 1, : j + 1]), s[: j + 1])
            return yv @ v[: j + 1], j + 1
        if not math.isfinite(hn):
            raise ArithmeticError("GMRES: a value is not finite")
        v[j + 1] = w / hn
    raise AssertionError("unreachable")  # pragma: no cover


def _scale(y: FloatArray) -> FloatArray:
    return 1.0 + np.max(np.abs(y), axis=0)


_EPS = float(np.finfo(np.float64).eps)


def _rounding_floor(num: int) -> float:
    """The collocation's rounding level at degree ``num``: the bending rows grow like
    num^4, so the rates carry about eps num^4 (a Newton step stalled at 1.5e-9 at num 64)."""
    return max(1e-10, 2.0 * _EPS * float(num) ** 4)


def _newton(
    prob: _Problem, y: FloatArray, tol: float, max_iter: int
) -> tuple[bool, FloatArray, int, int, bool]:
    """Newton on the collocation from y (K, m): (converged, y, iterations, GMRES
    iterations, rates finite)."""
    kk = y.shape[0]
    t = prob.times(kk)
    y = y.copy()
    n_th = prob.sys.num - 1
    prev = math.inf
    krylov = 0
    grow = 0
    floor = _rounding_floor(prob.sys.num)
    for it in range(1, max_iter + 1):
        ok, g, jac = prob.rates(t, y, True)
        if not ok:
            return False, y, it, krylov, False
        res = prob.mass * prob.derivative(y) - g
        try:
            step3, its = prob.solve(jac, -res[:, :, None])
            step = step3[:, :, 0]
        except (ArithmeticError, np.linalg.LinAlgError):
            return False, y, it, krylov, True
        krylov += its
        if not np.all(np.isfinite(step)):
            return False, y, it, krylov, True
        turn = float(np.max(np.abs(step[:, :n_th])))
        if turn > _MAX_TURN:
            step *= _MAX_TURN / turn
        y += step
        size = float(np.max(np.abs(step) / _scale(y)))
        # converged: the step below tol, or the error left after it (the step times the
        # contraction rate size/prev) below tol, or the rounding floor reached (the rates'
        # rounding grows like eps N^4 with the bending rows: 1.5e-9 measured at N = 64)
        if size <= tol or (size * size <= tol * prev < math.inf) or (floor > size >= 0.5 * prev):
            return True, y, it, krylov, True
        grow = grow + 1 if size > prev else 0
        if grow >= 2:
            return False, y, it, krylov, True
        prev = size
    return False, y, max_iter, krylov, True


def _tail(y: FloatArray) -> float:
    """The two highest harmonics' amplitudes over each component's scale, the largest."""
    kk = y.shape[0]
    c = np.abs(np.fft.rfft(y, axis=0)) * (2.0 / kk)
    top = np.max(c[-2:], axis=0) if c.shape[0] > 2 else np.max(c, axis=0)
    return float(np.max(top / _scale(y)))


def _next_degree(y: FloatArray, tol: float) -> int:
    """The degree at which the harmonics' envelope, fitted as geometric over the upper half
    of the present degree H, falls to tol/10 (within [H + 4, 4H]; 2H where it does not
    decay)."""
    kk = y.shape[0]
    hh = kk // 2
    c = np.abs(np.fft.rfft(y, axis=0)) * (2.0 / kk) / _scale(y)
    env = np.max(c[1:], axis=1)  # harmonics 1 .. H
    env = np.maximum(env, np.concatenate([[0.0], env[:-1]]))  # odd-only spectra: pairs
    j = np.arange(1, hh + 1)
    upper = (j >= hh // 2) & (env > 0.0)
    if np.count_nonzero(upper) < 3:
        return 2 * hh
    slope, icpt = np.polyfit(j[upper], np.log(env[upper]), 1)
    if not slope < -1e-3:
        return 2 * hh
    need = (math.log(0.1 * tol) - icpt) / slope
    return int(min(max(math.ceil(need) + 2, hh + 4), 4 * hh))


def _resample(y: FloatArray, kk_new: int) -> FloatArray:
    """The trigonometric interpolant of y (K, m) at K' equispaced phases (odd K and K'; for
    K' < K its truncation to degree (K' - 1)/2)."""
    kk = y.shape[0]
    c = np.fft.rfft(y, axis=0)
    big = np.zeros((kk_new // 2 + 1, y.shape[1]), dtype=np.complex128)
    n = min(c.shape[0], big.shape[0])
    big[:n] = c[:n]
    return np.fft.irfft(big, n=kk_new, axis=0) * (kk_new / kk)


def _refined(
    prob: _Problem, ok: bool, y1: FloatArray, finite: bool, ptol: float, hmax: int,
    newton_tol: float, nit: int,
) -> tuple[int, float, int, FloatArray, int, int, bool]:  # fmt: skip
    """From Newton's state y1 at its first degree (converged where ``ok``) the degree raised
    until the truncation error is below ptol: (status, error, H, y, Newton iterations,
    GMRES iterations, finite)."""
    total = krylov = 0
    status, err = 0, math.nan
    while ok:
        err = _tail(y1)
        if err <= ptol:
            break
        if (y1.shape[0] - 1) // 2 >= hmax:
            status = 1
            break
        hh = min(_next_degree(y1, ptol), hmax)
        ok, y1, its, kry, finite = _newton(prob, _resample(y1, 2 * hh + 1), newton_tol, nit)
        total, krylov = total + its, krylov + kry
    if not ok:
        status = -1 if finite else -3
    elif np.any(np.abs(_angles(prob.sys, y1)) >= 0.5 * math.pi):
        status = -8
    return status, err, (y1.shape[0] - 1) // 2, y1, total, krylov, finite


def _transient_start(prob: _Problem, y_mean: FloatArray, h0: int, hmax: int) -> FloatArray | None:
    """The periodic state approached in time, the last resort where Newton fails from the
    other starts (hairs that snap through within a small part of the period, whose
    quasi-static and linear guides are far from it): the bed integrated from the drives'
    mean state (simulate_bed's Radau IIA, rtol _SETTLE_RTOL) period after period until its
    state at the period's start changes by less than _SETTLE_TOL of its scale, then sampled
    over one more period at 2 hmax + 1 phases and truncated to the degree H in
    [h0, hmax] beyond which its harmonics lie below _SETTLE_FLOOR of each component's scale.
    An attracting periodic state only; None where the run stops (an event, a failure) or has
    not settled after _SETTLE_PERIODS periods or _SETTLE_STEPS steps."""
    from .._core._kernels import dynamics as kern

    sys = prob.sys
    lay = sys.layout
    m = prob.m
    index2 = lay.pi if (lay.pi >= 0 and sys.alpha > 0.0) else m
    period = 2.0 * math.pi / prob.omega
    try:
        y = _consistent(sys, y_mean, 0.0)
    except ArithmeticError:
        return None
    counts = np.zeros(6, dtype=np.int64)
    done, batch = 0, 4
    h_start = 1e-6 * period
    while done < _SETTLE_PERIODS and counts[0] < _SETTLE_STEPS:
        te = period * np.arange(done, done + batch + 1, dtype=np.float64)
        out = np.full((te.size, m), np.nan)
        status, _t_end = kern.integrate_bed(y, prob.mass, index2, float(te[0]), te,
                                            _SETTLE_RTOL, _SETTLE_ATOL, h_start,
                                            _SETTLE_STEPS - counts[0], sys.params, out,
                                            counts)  # fmt: skip
        if status != 0 or not np.all(np.isfinite(out)):
            return None
        done += batch
        y = out[-1].copy()
        change = np.max(np.abs(out[-1] - out[-2]) / (1.0 + np.abs(out[-1])))
        if change <= _SETTLE_TOL:
            break
        batch = min(2 * batch, 64)
    else:
        return None
    kk = 2 * hmax + 1
    te = period * done + prob.times(kk)
    out = np.full((kk + 1, m), np.nan)
    status, _t_end = kern.integrate_bed(y, prob.mass, index2, float(te[0]),
                                        np.append(te, period * (done + 1)), _SETTLE_RTOL,
                                        _SETTLE_ATOL, h_start, _SETTLE_STEPS - counts[0],
                                        sys.params, out, counts)  # fmt: skip
    if status != 0 or not np.all(np.isfinite(out)):
        return None
    samples = out[:kk]
    c = np.abs(np.fft.rfft(samples, axis=0)) * (2.0 / kk) / _scale(samples)
    env = np.max(c, axis=1)
    above = np.flatnonzero(env > _SETTLE_FLOOR)
    hh = int(min(max(int(above[-1]) + 1 if above.size else h0, h0), hmax))
    return _resample(samples, 2 * hh + 1)


def periodic_bed(
    theta0: float,
    kappa: float,
    eps: float,
    *,
    omega: float,
    wall: Any = None,
    pressure: Any = None,
    flow_rate: Any = None,
    wall_stress: Any = None,
    gamma: float = 1.0,
    inertia: float = 0.0,
    tangential_mass: float = 1.0,
    womersley: float = 0.0,
    num: int = 32,
    num_gap: int = 16,
    tol: float = 1e-10,
    harmonics: int = 12,
    max_harmonics: int = 384,
    max_iterations: int = 30,
) -> PeriodicBed:
    """The porous bed's periodic steady state under drives of period 2 pi/omega, directly.

    The bed of :func:`hairbed.dynamics.simulate_bed` (theory.md §15), M y' = g(t, y), under
    drives that repeat with the period P = 2 pi/omega: its periodic state y(t + P) = y(t),
    by trigonometric collocation in time with Newton's method (theory.md §16): y is the
    trigonometric polynomial of degree H through K = 2H + 1 phases t_k = k P/K and
    M y'(t_k) = g(t_k, y(t_k)) holds at each; Newton with the exact Jacobian, the algebraic
    unknowns eliminated phase by phase, the differential ones by GMRES preconditioned by the
    phase-averaged Jacobian; H doubles until the highest harmonics fall below ``tol``.
    Time in T = zeta_perp L^4/(E I). The same spatial discretisation as simulate_bed (the
    same N, map and rows): the two agree to their tolerances.

    Parameters
    ----------
    theta0, kappa, eps : float
        The bed (as :func:`hairbed.dynamics.simulate_bed`): base angle [rad] in
        (-pi/2, pi/2), kappa [-] in [1e-6, 1e6], eps = L/H [-] in [1e-3, 1).
    omega : float
        The base angular frequency [1/T], in [1e-9, 1e9].
    wall, wall_stress, pressure, flow_rate : number or sine, optional
        The drives (as simulate_bed's; at most one of each pair): numbers or
        :func:`hairbed.dynamics.sine` signals whose frequencies are whole multiples of omega.
        flow_rate is not taken with womersley > 0 (an index-2 pressure).
    gamma, inertia, tangential_mass, womersley : float, optional
        As simulate_bed's (defaults 1, 0, 1, 0).
    num : int, optional
        The hair's Chebyshev degree N in [8, 128] (default 32, simulate_bed's).
    num_gap : int, optional
        The gap's degree M in [4, 128] (womersley > 0; default 16).
    tol : float, optional
        The periodic state's accuracy in [1e-13, 1e-3] (default 1e-10): the highest
        harmonics' amplitudes over 1 + max abs(y) of each component, and Newton's last step.
    harmonics : int, optional
        The first degree H in [2, 1024] (default 12).
    max_harmonics : int, optional
        The largest degree in [harmonics, 4096] (default 384): status 1 beyond.
    max_iterations : int, optional
        Newton iterations per start and degree, in [2, 200] (default 30).

    Returns
    -------
    PeriodicBed

    Raises
    ------
    ValueError, TypeError
        For inputs outside their ranges, naming the parameter.

    Examples
    --------
    >>> from hairbed.dynamics import periodic_bed, sine
    >>> st = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0, 1.0, 1.5707963267948966))
    >>> st.success, round(float(st.outputs["wall_stress"].max()), 6)
    (True, 1.134097)
    """
    om = check_number(omega, "omega", low=1e-9, high=1e9)
    t0, kap, e, g, mu, chi, alpha, ngap = _checked_bed(
        theta0, kappa, eps, gamma, inertia, tangential_mass, womersley, num_gap
    )
    deg = check_int(num, "num", 8, 128)
    ptol = check_number(tol, "tol", low=1e-13, high=1e-3)
    h0 = check_int(harmonics, "harmonics", 2, 1024)
    hmax = check_int(max_harmonics, "max_harmonics", 2, 4096)
    if hmax < h0:
        raise ValueError(
            f"max_harmonics must be >= harmonics, got max_harmonics = {hmax} < harmonics = {h0}"
        )
    nit = check_int(max_iterations, "max_iterations", 2, 200)
    top, top_in, top_name = _top_drive(wall, wall_stress)
    pump, pump_in, pump_name = _pump_drive(pressure, flow_rate)
    if pump == 1 and alpha > 0.0:
        raise ValueError(
            "flow_rate with womersley > 0 makes the pressure an index-2 unknown, which the "
            "periodic solver does not take: drive the pressure, or use womersley = 0"
        )
    top_sig = _periodic_drive(top_in, top_name, om)
    pump_sig = _periodic_drive(pump_in, pump_name, om)
    a = 0.0
    if top == 0 and pump == 0 and pump_sig.kind == "constant" and pump_sig.params[0] == 0.0:
        from .._core.porous import _tip_map  # the map simulate_bed takes for this drive

        a = float(_tip_map(0, np.array(kap), np.array(0.0)))
    sys = _system(deg, a, ngap, t0, g, chi, mu, kap, e, alpha, top, pump, top_sig, pump_sig)
    top_mean, pump_mean = _mean_value(top_sig), _mean_value(pump_sig)
    mean_sys = _system(deg, a, ngap, t0, g, chi, mu, kap, e, alpha, top, pump,
                       constant(top_mean), constant(pump_mean))  # fmt: skip
    names = (top_name, pump_name)
    y_mean = _mean_state(mean_sys, t0, kap, e, g, top_mean, pump_mean, names)
    prob = _Problem(sys, om)
    newton_tol = max(min(1e-2 * ptol, 1e-11), 1e-14)
    hh = h0
    kk = 2 * hh + 1
    y = _linear_start(prob, mean_sys, y_mean, top_sig, pump_sig, kk)
    start = "linear"
    ok, y1, total, krylov, finite = False, y, 0, 0, True
    if np.all(np.abs(_angles(sys, y)) < 0.5 * math.pi):  # else the linear start is no guide
        ok, y1, total, krylov, finite = _newton(prob, y, newton_tol, nit)
    if not ok:
        start = "quasi-static"
        yq = _quasi_static_start(prob, y_mean, kk)
        if yq is not None:
            ok, y1, its, kry, finite = _newton(prob, yq, newton_tol, nit)
            total, krylov = total + its, krylov + kry
    if not ok:
        start = "continuation"
        build = functools.partial(_system, deg, a, ngap, t0, g, chi, mu, kap, e, alpha, top, pump)
        ok, y1, its, kry, finite = _continuation(
            build, om, top_sig, pump_sig, _linear_start(prob, mean_sys, y_mean, top_sig,
                                                        pump_sig, kk, 0.0),
            newton_tol, nit,
        )  # fmt: skip
        total, krylov = total + its, krylov + kry
    status, err, hh, y1, its, kry, finite = _refined(prob, ok, y1, finite, ptol, hmax,
                                                     newton_tol, nit)  # fmt: skip
    total, krylov = total + its, krylov + kry
    if status in (-1, -8):  # the state approached in time, the last resort
        yt = _transient_start(prob, y_mean, h0, hmax)
        if yt is not None:
            ok, y2, its, kry, fin2 = _newton(prob, yt, newton_tol, nit)
            total, krylov = total + its, krylov + kry
            res = _refined(prob, ok, y2, fin2, ptol, hmax, newton_tol, nit)
            total, krylov = total + res[4], krylov + res[5]
            if res[0] in (0, 1):  # a periodic state (status 1: short of tol at hmax)
                start = "transient"
                status, err, hh, y1, _its, _kry, finite = res
    t = prob.times(y1.shape[0])
    pump_vals = np.asarray(pump_sig(t), dtype=np.float64).reshape(t.shape)
    outs = {k: np.asarray(v, dtype=np.float64) for k, v in
            _output_values(sys, y1, pump_vals).items()}  # fmt: skip
    return PeriodicBed(
        omega=om, period=2.0 * math.pi / om, t=t, y=y1, outputs=MappingProxyType(outs),
        harmonics=hh, error=err, iterations=total, krylov_iterations=krylov, start=start,
        status=status, _sys=sys, _pump=pump_sig,
    )  # fmt: skip


def _mean_state(
    sys: _System, theta0: float, kappa: float, eps: float, gamma: float, top: float,
    pump: float, names: tuple[str, str],
) -> FloatArray:  # fmt: skip
    """The steady state of the drives' means: at rest (theta = theta0) where both vanish,
    else simulate_bed's static start."""
    if top == 0.0 and pump == 0.0:
        rest = np.zeros(sys.layout.size)
        rest[: sys.num - 1] = theta0
        return _newton_steady(sys, rest, 0.0)
    try:
        return _static_start(sys, theta0, kappa, eps, gamma, top, pump, 0.0)
    except ValueError as exc:
        raise ValueError(
            f"no steady state at the drives' means ({names[0]} = {show(top)}, {names[1]} = "
            f"{show(pump)}) to start the periodic state from: {exc}"
        ) from None


def _scaled(sig: Signal, lam: float) -> Signal:
    """The drive's swing about its mean times lam."""
    if sig.kind == "constant":
        return sig
    mean, amp, om, phase = sig.params[:4]
    return sine(mean, lam * amp, om, phase)


def _continuation(
    build: Callable[[Signal, Signal], _System], omega: float, top: Signal, pump: Signal,
    y: FloatArray, tol: float, max_iter: int,
) -> tuple[bool, FloatArray, int, int, bool]:  # fmt: skip
    """Newton along the drives' swing scaled by lam from 0 to 1 (steps from 1/4, halved on a
    failure down to 1/256, doubled after a success), each from the last state."""
    lam, step = 0.0, 0.25
    total = krylov = 0
    finite = True
    while lam < 1.0:
        nxt = min(1.0, lam + step)
        prob = _Problem(build(_scaled(top, nxt), _scaled(pump, nxt)), omega)
        ok, y1, its, kry, finite = _newton(prob, y, tol, max_iter)
        total, krylov = total + its, krylov + kry
        if ok:
            lam, y, step = nxt, y1, 2.0 * step
        else:
            step *= 0.5
            if step < 1.0 / 256.0:
                return False, y, total, krylov, finite
    return True, y, total, krylov, finite


def _linear_start(
    prob: _Problem, mean_sys: _System, y_mean: FloatArray, top: Signal, pump: Signal, kk: int,
    lam: float = 1.0,
) -> FloatArray:  # fmt: skip
    """The linear periodic response about the drives' mean state y* to the drives' swing
    times lam: for each harmonic j of the drives, (i j omega M - J) Y_j = lam b d_j."""
    ok, _g, jac = _evaluate(mean_sys, 0.0, y_mean, True)
    cols = list(_drive_columns(mean_sys, y_mean).values())
    t = prob.times(kk)
    coef = np.zeros((kk // 2 + 1, prob.m), dtype=np.complex128)
    if ok and lam != 0.0:
        for col, sig in zip(cols, (top, pump)):
            d = np.fft.rfft(np.asarray(sig(t), dtype=np.float64).reshape(t.shape) - sig.params[0])
            big = float(np.max(np.abs(d)))
            for j in range(1, d.size):
                if abs(d[j]) > 1e-12 * big:
                    mat = 1j * j * prob.omega * np.diag(prob.mass) - jac
                    coef[j] += np.linalg.solve(mat, col * (lam * d[j]))
    return y_mean[None, :] + np.fft.irfft(coef, n=kk, axis=0)


def _quasi_static_start(prob: _Problem, y_mean: FloatArray, kk: int) -> FloatArray | None:
    """The steady states of the drives' values at each phase (g(t_k, y) = 0, each from the
    last): the low-frequency limit. None where one does not converge."""
    t = prob.times(kk)
    out = np.empty((kk, prob.m))
    y = y_mean
    try:
        for k in range(kk):
            y = _newton_steady(prob.sys, y, float(t[k]))
            out[k] = y
    except ArithmeticError:
        return None
    return out


@dataclass(frozen=True)
class PeriodicSensitivity:
    """The periodic solution of the forced variational equation (:func:`periodic_sensitivity`).

    Attributes
    ----------
    states : ndarray
        S at the orbit's phases, (K, size, p): dy/dp along the periodic orbit for parameter
        columns G = dg/dp.
    initial : ndarray
        S(0) = dy0/dp, (size, p): (I - Phi)^-1 times the forced solution from rest over one
        period (Phi the monodromy matrix).
    mean_outputs : mapping of str to ndarray
        d(period-mean of the output)/dp through the state, (p,), for ``BED_OUTPUTS`` and
        ``wall_speed`` (an output's direct dependence on p at fixed y is not included).
    krylov_iterations : int
        GMRES iterations (all columns).
    """

    states: FloatArray
    initial: FloatArray
    mean_outputs: Mapping[str, FloatArray]
    krylov_iterations: int


def _forcing_columns(orbit: PeriodicBed, forcing: Any) -> FloatArray:
    """The forcing G at the orbit's phases, validated: (K, size, p)."""
    kk, m = orbit.y.shape
    if callable(forcing):
        cols = [as_float_array(forcing(float(orbit.t[k]), orbit.y[k].copy()), "forcing")
                for k in range(kk)]  # fmt: skip
        shapes = {c.shape for c in cols}
        if len(shapes) != 1:
            raise ValueError(f"forcing(t, y) must return one shape at every phase, got {shapes}")
        gg = np.stack(cols)
    else:
        gg = as_float_array(forcing, "forcing")
    return _checked_columns(gg, kk, m, f" (or a callable returning ({m},) or ({m}, p))")


def _checked_columns(gg: FloatArray, kk: int, m: int, alt: str = "") -> FloatArray:
    """Forcing columns (K, size) or (K, size, p), checked: (K, size, p)."""
    if gg.ndim not in (2, 3) or gg.shape[:2] != (kk, m):
        raise ValueError(
            f"forcing must have shape ({kk}, {m}) or ({kk}, {m}, p) at the orbit's {kk} phases"
            f"{alt}, got {gg.shape}"
        )
    bad = ~np.isfinite(gg)
    if np.any(bad):
        i = tuple(int(v) for v in np.argwhere(bad)[0])
        raise ValueError(f"forcing must be finite, got {show(float(gg[i]))} at index {i}")
    return gg[:, :, None] if gg.ndim == 2 else gg


def _checked_orbit(orbit: Any) -> None:
    if not isinstance(orbit, PeriodicBed):
        raise TypeError(f"orbit must be a PeriodicBed (periodic_bed), got {type(orbit).__name__}")
    if orbit.status not in (0, 1):
        raise ValueError(f"orbit must be converged (status 0 or 1), got status {orbit.status}")


def _orbit_jacobians(orbit: PeriodicBed) -> tuple[_Problem, FloatArray]:
    """The orbit's collocation problem and its Jacobians J_k (K, size, size)."""
    prob = _Problem(orbit._sys, orbit.omega)
    ok, _g, jac = prob.rates(orbit.t, orbit.y, True)
    if not ok:  # pragma: no cover - a converged orbit has finite rates
        raise ValueError("the orbit's rates are not finite")
    return prob, jac


def _output_gradients(orbit: PeriodicBed, names: tuple[str, ...]) -> dict[str, FloatArray]:
    """{output: its gradient c_k = d(output)/dy at each phase, (K, size)}, by the complex
    step (exact to rounding: the outputs are analytic in y), the K size steps as the rows
    of one matrix (one product per output's sum, not one per phase)."""
    kk, m = orbit.y.shape
    pump = np.asarray(orbit._pump(orbit.t), dtype=np.float64).reshape(orbit.t.shape)
    hstep = 1e-30
    rows = (orbit.y[:, None, :] + 1j * hstep * np.eye(m)[None]).reshape(kk * m, m)
    vals = _output_values(orbit._sys, rows, np.repeat(pump, m))
    return {name: np.imag(np.asarray(vals[name])).reshape(kk, m) / hstep for name in names}


def periodic_sensitivity(
    orbit: PeriodicBed,
    forcing: Any,
) -> PeriodicSensitivity:
    """The periodic solution S of M S' = J(t) S + G(t) along a periodic state: implicit
    differentiation of the periodic orbit.

    With G = dg/dp (the derivative of the bed's rates in a parameter p at fixed y, one column
    per parameter) S = dy/dp along the orbit, S(0) = dy0/dp = (I - Phi)^-1 S_p(P) with Phi
    the monodromy matrix and S_p the forced solution from rest; the derivatives of the
    period-means of the outputs follow as (1/P) int c_o(y(t)) . S(t) dt, c_o the outputs'
    gradients (exact: the mean of the trigonometric polynomial at the K phases). Solved on
    the orbit's collocation with its Newton matrix (theory.md §16), so S is exact for the
    discrete periodic problem: d(periodic_bed's state)/dp. One GMRES solve (and two of
    refinement) per column: where only one output's mean is wanted, for many columns,
    :func:`periodic_adjoint` costs one solve for all of them.

    Parameters
    ----------
    orbit : PeriodicBed
        A converged :func:`periodic_bed` result.
    forcing : array_like or callable
        G at the orbit's phases ``orbit.t``: an array (K, size) or (K, size, p), or a callable
        G(t, y) of one phase t [T] and its state y (size,) returning (size,) or (size, p).

    Returns
    -------
    PeriodicSensitivity
    """
    _checked_orbit(orbit)
    gg = _forcing_columns(orbit, forcing)
    kk = orbit.y.shape[0]
    prob, jac = _orbit_jacobians(orbit)
    s, krylov = prob.solve(jac, gg)
    for _ in range(2):  # iterative refinement on the full system's residual
        res = gg - (prob.mass[:, None] * prob.derivative(s) - jac @ s)
        fix, its = prob.solve(jac, res, strict=False)
        s += fix
        krylov += its
    grads = _output_gradients(orbit, (*BED_OUTPUTS, "wall_speed"))
    means = {name: np.einsum("km,kmp->p", grad, s) / kk for name, grad in grads.items()}
    return PeriodicSensitivity(
        states=s, initial=s[0].copy(), mean_outputs=MappingProxyType(means),
        krylov_iterations=krylov,
    )  # fmt: skip


#: Status codes of :class:`PeriodicAdjoint`.
PERIODIC_ADJOINT_STATUS: Mapping[int, str] = MappingProxyType(
    {
        0: "the transposed collocation is solved to its rounding level",
        1: "the transposed collocation's residual stayed above 1e-10 of the output's gradient "
        "after refinement",
    }
)

#: The adjoint's largest residual, relative to the output's gradient, for status 0.
_ADJOINT_RESIDUAL = 1e-10


@dataclass(frozen=True)
class PeriodicAdjoint(StatusResult):
    """The adjoint of the periodic collocation for one output's period mean
    (:func:`periodic_adjoint`).

    Attributes
    ----------
    output : str
        The output o whose period mean it differentiates.
    multipliers : ndarray
        lambda_k at the orbit's phases, (K, size) [units of the output's mean per unit of the
        rates g]: d(mean of o)/dp = sum_k lambda_k . G_k for the forcing column G = dg/dp of
        any parameter p (through the state; o's direct dependence on p at fixed y is not
        included).
    residual : float
        ||c - L^T lambda|| / ||c|| [-], L the collocation's Newton matrix and c the
        output's gradient over K.
    krylov_iterations : int
        GMRES iterations (the solve and its refinement).
    status : int
        ``PERIODIC_ADJOINT_STATUS``.
    """

    output: str
    multipliers: FloatArray
    residual: float
    krylov_iterations: int
    status: int

    _status_table: ClassVar[Mapping[int, str]] = PERIODIC_ADJOINT_STATUS

    def mean_derivative(self, forcing: Any) -> FloatArray:
        """d(mean of the output)/dp = sum_k lambda_k . G_k (p,) for forcing columns G at the
        orbit's phases: an array (K, size) or (K, size, p) (as
        :func:`periodic_sensitivity`'s, whose ``mean_outputs[output]`` this equals)."""
        kk, m = self.multipliers.shape
        gg = _checked_columns(as_float_array(forcing, "forcing"), kk, m)
        return np.asarray(np.einsum("km,kmp->p", self.multipliers, gg), dtype=np.float64)


def _transposed_solver(
    prob: _Problem, jac: FloatArray
) -> Callable[[FloatArray, bool], tuple[FloatArray, int]]:
    """The solver of L^T lambda = rhs (K, m), L Y = M D Y - J_k Y_k the collocation's Newton
    matrix: L^T lambda = -M D lambda - J_k^T lambda_k (D antisymmetric: the derivative of the
    trigonometric interpolant at an odd number of equispaced phases). As ``_Problem.solve``
    transposed: the algebraic unknowns eliminated at each phase,
    lambda_a = -J_aa^-T (rhs_a + J_da^T lambda_d), which leaves
    -M_d D lambda_d - A_k^T lambda_d = rhs_d - (J_aa^-1 J_ad)^T rhs_a with A_k the same Schur
    complement; GMRES preconditioned by the transposed phase average, per harmonic j
    (-i j omega M_d - mean_k A_k^T)^-1, or where that fails by the transposed cyclic
    implicit Euler scheme. The elimination and the preconditioner are built once; the
    solver returns lambda and its GMRES iterations (``strict`` as :func:`_gmres`'s)."""
    nd, kk = prob.nd, jac.shape[0]
    if prob.ident:
        jt = jac.transpose(0, 2, 1)
    else:
        jt = jac[:, prob.perm][:, :, prob.perm].transpose(0, 2, 1)
    lu_aa = jt[:, nd:, nd:]
    y = np.linalg.solve(lu_aa, jt[:, nd:, :nd])  # J_aa^-T J_da^T
    j_ad_t = jt[:, :nd, nd:]  # J_ad^T
    amat_t = jt[:, :nd, :nd] - j_ad_t @ y  # A_k^T
    w = prob.omega * np.arange(kk // 2 + 1)
    pinv = np.linalg.inv(-1j * w[:, None, None] * np.diag(prob.md)[None] - amat_t.mean(0)[None])

    def average(r: FloatArray) -> FloatArray:
        c = np.fft.rfft(r, axis=0)
        return np.fft.irfft((pinv @ c[:, :, None])[:, :, 0], n=kk, axis=0)

    # the phase average first; where it fails, the transposed cyclic implicit Euler
    # preconditioner (_Problem.solve's fallback): P^T's backward recurrence is the forward
    # one of the phases reversed, with B_k^T = M_d/h - A_k^T
    precs: list[Callable[[FloatArray], FloatArray]] = [average]

    def prec(r: FloatArray) -> FloatArray:
        return precs[-1](r)

    def apply(v: FloatArray) -> FloatArray:
        xv = v.reshape(kk, nd)
        out = -prob.md * prob.derivative(xv) - (amat_t @ xv[:, :, None])[:, :, 0]
        return prec(out).reshape(-1)

    def solve(rhs: FloatArray, strict: bool) -> tuple[FloatArray, int]:
        rp = rhs if prob.ident else rhs[:, prob.perm]
        z = np.linalg.solve(lu_aa, rp[:, nd:, None])  # J_aa^-T rhs_a
        red = rp[:, :nd] - (j_ad_t @ z)[:, :, 0]
        lost = 0  # the phase average's iterations where it failed
        if len(precs) == 1:
            try:
                xd, its = _gmres(apply, prec(red).reshape(-1), True, _AVERAGE_MAX)
            except ArithmeticError:
                lost = _AVERAGE_MAX
                back = _cyclic_euler(prob.md, amat_t[::-1], 2.0 * math.pi / (prob.omega * kk))
                precs.append(lambda r: back(r[::-1])[::-1])
        if len(precs) > 1:
            xd, its = _gmres(apply, prec(red).reshape(-1), strict)
            its += lost
        ld = xd.reshape(kk, nd)
        out = np.empty((kk, prob.m))
        out[:, prob.perm[:nd]] = ld
        out[:, prob.perm[nd:]] = -z[:, :, 0] - (y @ ld[:, :, None])[:, :, 0]
        return out, its

    return solve


def periodic_adjoint(orbit: PeriodicBed, output: str = "flow_rate") -> PeriodicAdjoint:
    """The adjoint of the periodic collocation for the period mean of one output: its
    derivatives in any number of parameters for the cost of one linear solve.

    The mean of an output o over the periodic orbit, <o> = (1/K) sum_k o(y_k), moves with a
    parameter p through the state: d<o>/dp = (1/K) sum_k c_k . S_k, c_k = do/dy at the phase
    t_k, S the periodic solution of the forced variational equation L S = G
    (:func:`periodic_sensitivity`: (L S)_k = M (D S)_k - J_k S_k on the orbit's collocation,
    G = dg/dp). With the multipliers lambda of the transposed problem

        L^T lambda = c/K,   (L^T lambda)_k = -M (D lambda)_k - J_k^T lambda_k

    (D, the derivative of the trigonometric interpolant at K = 2H + 1 equispaced phases, is
    antisymmetric), d<o>/dp = lambda . G = sum_k lambda_k . G_k for every column G: one
    solve instead of one per parameter (the adjoint method; Giles & Pierce, Flow Turbul.
    Combust. 65, 393, 2000), exact for the discrete periodic problem like
    :func:`periodic_sensitivity`, to which it is equal to rounding. Solved as
    periodic_sensitivity's system transposed (theory.md §16): the algebraic unknowns
    eliminated at each phase, GMRES on the differential ones preconditioned by the
    transposed phase average, then two steps of iterative refinement on the full
    transposed system's residual.

    Parameters
    ----------
    orbit : PeriodicBed
        A converged :func:`periodic_bed` result.
    output : str, optional
        One of ``BED_OUTPUTS`` or ``"wall_speed"`` (default ``"flow_rate"``).

    Returns
    -------
    PeriodicAdjoint
        ``mean_derivative(G)`` applies it to forcing columns G at the orbit's phases.

    Examples
    --------
    d<h1>/dA of the mean tip height under the wall's drive A sin(t) (g is affine in the
    drive: its column is the rates' drive column times sin(t)), as periodic_sensitivity's:

    >>> import numpy as np
    >>> import hairbed
    >>> from hairbed.dynamics import (bed_operators, periodic_adjoint, periodic_bed,
    ...                               periodic_sensitivity, sine)
    >>> orbit = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0, 1.0))
    >>> rest = hairbed.solve_porous(0.0, 0.5, 0.0, kappa=1.0)
    >>> col = bed_operators(rest, num=32).drives["wall"]
    >>> g = np.sin(orbit.t)[:, None] * col
    >>> adj = periodic_adjoint(orbit, "tip_height")
    >>> forward = periodic_sensitivity(orbit, g).mean_outputs["tip_height"]
    >>> adj.success, bool(np.allclose(adj.mean_derivative(g), forward, rtol=1e-10, atol=0))
    (True, True)
    """
    _checked_orbit(orbit)
    names = (*BED_OUTPUTS, "wall_speed")
    if not isinstance(output, str) or output not in names:
        raise ValueError(f"output must be one of {sorted(names)}, got {show(output)}")
    kk = orbit.y.shape[0]
    prob, jac = _orbit_jacobians(orbit)
    c = _output_gradients(orbit, (output,))[output] / kk
    solve = _transposed_solver(prob, jac)
    lam, krylov = solve(c, True)
    jt = jac.transpose(0, 2, 1)

    def residual(v: FloatArray) -> FloatArray:
        return c + prob.mass * prob.derivative(v) + (jt @ v[:, :, None])[:, :, 0]

    for _ in range(2):  # iterative refinement on the full transposed system's residual
        fix, its = solve(residual(lam), False)
        lam += fix
        krylov += its
    size = float(np.linalg.norm(c))
    rel = float(np.linalg.norm(residual(lam))) / size if size > 0.0 else 0.0
    return PeriodicAdjoint(
        output=output, multipliers=lam, residual=rel, krylov_iterations=krylov,
        status=0 if rel <= _ADJOINT_RESIDUAL else 1,
    )  # fmt: skip
