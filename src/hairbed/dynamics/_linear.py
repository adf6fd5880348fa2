"""Linear dynamics of an isolated pillar about any static state (issue 30, theory.md §14).

About a converged state u* of the static collocation (theory.md §12) a small motion
u = u* + v e^{s t} (time in T = zeta_perp L^4/(E I), the convention e^{i omega t}: s = i omega)
obeys

    (mu s^2 M + s B - J) v = b delta,

J the static Jacobian, B the drag of the pillar's own velocity, M its inertia
(:mod:`._operators`), b the column of the drive (the forcing Lambda or the tip load P) and
mu = m E I/(zeta_perp^2 L^4) the inertia number. The rows 0 (theta_0 = theta0), N
(theta'(1) = 0) and N + 1 (h1 = z(1)) are algebraic: they are solved for the boundary
unknowns (theta_0, theta_N, h1) in terms of the interior ones, v_a = S v_d, which leaves the
pencil on the N - 1 interior angles. With inertia it is linearised to the first-order pencil
(s E - A) of twice the size, A = [[0, I], [J, -B]], E = [[I, 0], [0, mu M]].

The pencil is reduced once to the generalised Schur form (QZ, complex): Q^H (A, E) Z upper
triangular, so each frequency costs one triangular solve (O(n^2)), backward stable, however
stiff the pencil (the Chebyshev bending rates grow like N^8: the eigenvector basis of the
modes is too ill-conditioned to sum residues at 1e-10). Above N = 32 one step of iterative
refinement on the pencil itself recovers the accuracy of a direct solve, and a band of fewer
than 64 frequencies is solved directly (one LU each; the QZ would cost more). The degree is
chosen per frequency from the complex wavenumber k^4 = mu omega^2 - i omega of the straight
cantilever (the smallest of 32, 64, 128, 256 with N >= |k| + 16); the state's Chebyshev series
is evaluated at its nodes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from .._core.pillar import PillarState, profile_coefficients
from .._core.validation import StatusResult, as_float_array, check_number, show
from ._hydrodynamic import sader_drag_ratio
from ._operators import StateOperators, state_operators, velocity_operators
from ._validity import warn_dynamics_validity

__all__ = [
    "DRIVES",
    "LINEAR_STATUS",
    "OUTPUTS",
    "FrequencyResponse",
    "LinearPillar",
    "PillarModes",
    "linearise_pillar",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: The drives of a linear response: the forcing Lambda (the flow's amplitude, its profile
#: fixed), a horizontal tip force P [E I/L^2], and a change of the flow's shape ("profile":
#: the flow Lambda U(z) + delta V(z), V given as ``drive_profile``).
DRIVES = ("forcing", "tip_load", "profile")
#: The outputs of a linear response: x1 and h1 [L], and the base moment theta'(0) [E I/L].
OUTPUTS = ("tip_deflection", "tip_height", "base_moment")
#: Chebyshev degrees of the frequency bands (the smallest with N >= |k| + _MARGIN).
_BANDS = (32, 64, 128, 256)
#: Above N = 32 a band of fewer frequencies than this is solved directly (an LU each), a
#: larger one through the Schur form (its QZ costs about as much as this many LUs).
_DIRECT = 64
_MARGIN = 16
#: Status codes of a linear result (the package's convention: 0 ok, positive a caveat).
LINEAR_STATUS = {
    0: "ok",
    3: (
        "inaccurate: a frequency beyond the resolution of N = 256 (|k| > 240, k^4 = mu "
        "omega^2 - i omega): the values there are not converged"
    ),
}
#: The static state must be a root of the given profile's system to this (relative).
_STATE_RESIDUAL = 1e-7


@dataclass(frozen=True)
class _Pencil:
    """The reduced pencil at one degree N and its generalised Schur form."""

    num: int
    ops: StateOperators
    jr: FloatArray
    br: FloatArray
    mr: FloatArray
    aa: ComplexArray
    bb: ComplexArray
    q: ComplexArray
    z: ComplexArray
    expand: FloatArray  # (N + 2, n): the full v of the interior unknowns
    outputs: FloatArray  # (3, n): x1, h1, theta'(0)
    drives: FloatArray  # (2, n): the reduced columns of Lambda and P


def _reduce(ops: StateOperators, mu: float, schur: bool = True) -> _Pencil:
    num = ops.num
    n1 = num + 1
    alg = np.array([0, num, n1])
    dif = np.arange(1, num)
    jac = ops.jac
    jaa = jac[np.ix_(alg, alg)]
    # v_a = S v_d from the algebraic rows (their drives are zero: theta0, theta'(1) = 0 and
    # h1 = z(1) hold whatever the load)
    smat = -np.linalg.solve(jaa, jac[np.ix_(alg, dif)])

    def red(x: FloatArray) -> FloatArray:
        return np.ascontiguousarray(x[np.ix_(dif, dif)] + x[np.ix_(dif, alg)] @ smat)

    jr, br, mr = red(jac), red(ops.damping), red(ops.mass)
    n = num - 1
    expand = np.zeros((n1 + 1, n))
    expand[dif, np.arange(n)] = 1.0
    expand[alg] = smat
    c, s = np.cos(ops.theta), np.sin(ops.theta)
    rows = np.stack(
        [ops.ii[num] * c, -ops.ii[num] * s, ops.d0]
    )  # x1 = I sin, h1 = I cos, theta'(0)
    outputs = rows @ expand[:n1]
    # the drives act on the interior rows; the algebraic rows carry none (J_da J_aa^-1 0)
    drives = np.stack([ops.drive_forcing[dif], ops.drive_tip_load[dif]])
    if not schur:
        none = np.zeros((0, 0), dtype=np.complex128)
        return _Pencil(num, ops, jr, br, mr, none, none, none, none, expand, outputs, drives)
    a_mat, e_mat = _first_order(jr, br, mr, mu)
    aa, bb, q, z = scipy.linalg.qz(a_mat, e_mat, output="complex")
    return _Pencil(num, ops, jr, br, mr, aa, bb, q, z, expand, outputs, drives)


def _first_order(
    jr: FloatArray, br: FloatArray, mr: FloatArray, mu: float
) -> tuple[FloatArray, FloatArray]:
    """(A, E) of the first-order pencil s E - A: (J, B) overdamped; with inertia
    A = [[0, I], [J, -B]], E = [[I, 0], [0, mu M]] on (v, s v)."""
    if mu == 0.0:
        return jr, br
    n = jr.shape[0]
    zero = np.zeros((n, n))
    return (
        np.block([[zero, np.eye(n)], [jr, -br]]),
        np.block([[np.eye(n), zero], [zero, mu * mr]]),
    )


#: Above this inertia number the modes come from the undamped pencil and the damping's
#: first-order correction, exact to (1/sqrt(mu))^2 = 1e-16 relative.
_LIGHT_DAMPING_MU = 1e16


def _eigen(
    jr: FloatArray, br: FloatArray, mr: FloatArray, mu: float
) -> tuple[ComplexArray, ComplexArray]:
    """Eigenvalues lambda and right vectors (angles first) of mu lambda^2 M v + lambda B v = J v.

    With inertia the pencil is solved on sigma = sqrt(mu) lambda, sigma^2 M v + eps sigma B v =
    J v with eps = 1/sqrt(mu): its damping block shrinks like eps instead of its mass growing
    like mu, so QZ keeps the decay rate ~1/(2 mu) to full relative precision (unscaled, mu =
    1e20 gave a spurious growing mode and 1e30 no finite eigenvalue). Beyond eps^2 = 1e-16
    the damping is below the rounding of sigma: there sigma = sigma0 + eps sigma1, with
    sigma0^2 M v = J v and, for the left vector w, sigma1 = -w^H B v/(2 w^H M v) (first-order
    perturbation; the next term is eps^2 relative).
    """
    if mu <= _LIGHT_DAMPING_MU:
        scale = np.sqrt(mu) if mu > 1.0 else 1.0
        a_mat, e_mat = _first_order(jr, br / scale, mr, mu / scale**2)
        lam, vec = scipy.linalg.eig(a_mat, e_mat)
        # a subnormal mu leaves E singular to rounding: its inertial modes are infinite
        # eigenvalues (dropped by the callers), not to be divided into NaN
        return (lam / scale if scale != 1.0 else lam), vec
    nu, left, right = scipy.linalg.eig(jr, mr, left=True, right=True)
    sigma0 = np.sqrt(nu.astype(np.complex128))
    sigma1 = -np.einsum("ij,ij->j", left.conj(), br @ right) / (
        2.0 * np.einsum("ij,ij->j", left.conj(), mr @ right)
    )
    root = np.sqrt(mu)
    lam = np.concatenate([sigma0 / root + sigma1 / mu, -sigma0 / root + sigma1 / mu])
    return lam, np.concatenate([right, right], axis=1)


@dataclass(frozen=True)
class PillarModes:
    """The linear modes of a pillar about a static state (theory.md §14).

    A mode is v(s) e^{lambda t} (t in T = zeta_perp L^4/(E I)).

    Attributes
    ----------
    eigenvalues : ndarray of complex
        lambda [1/T], the finite ones, ordered by modulus (a stable state has Re < 0;
        overdamped modes are real; with inertia they come in conjugate pairs, each listed).
    s : ndarray
        The collocation nodes s_j [L] of the shapes.
    shapes : ndarray of complex
        theta of each mode at the nodes [rad], (mode, node), scaled to a largest modulus 1.
    tip_deflection : ndarray of complex
        x1 of each shape [L] (its tip motion, at the same scale).
    num : int
        The Chebyshev degree N.
    status : int
        0 (``LINEAR_STATUS``).
    """

    eigenvalues: ComplexArray
    s: FloatArray
    shapes: ComplexArray
    tip_deflection: ComplexArray
    num: int
    status: int = 0

    @property
    def success(self) -> bool:
        """True (a modal decomposition does not fail short of an error)."""
        return self.status == 0

    @property
    def message(self) -> str:
        """``LINEAR_STATUS`` of ``status``."""
        return LINEAR_STATUS[self.status]

    @property
    def frequency(self) -> FloatArray:
        """abs(Im lambda) [1/T]: the angular frequency of each mode (0 when overdamped)."""
        return np.abs(self.eigenvalues.imag)

    @property
    def damping_ratio(self) -> FloatArray:
        """-Re lambda/abs(lambda) [-] of each mode (1 when overdamped)."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)


@dataclass(frozen=True)
class FrequencyResponse(StatusResult):
    """Transfer functions of a pillar about a static state (theory.md §14).

    For a drive delta(t) = Re(delta_hat e^{i omega t}) (t in T) each output is
    Re(H(omega) delta_hat e^{i omega t}): H is the complex amplitude per unit drive.

    Attributes
    ----------
    omega : ndarray
        Angular frequencies [1/T].
    drive : str
        "forcing" (delta Lambda, the flow's profile fixed), "tip_load" (delta P [E I/L^2]) or
        "profile" (the flow Lambda U(z) + delta V(z), V the ``drive_profile`` given).
    tip_deflection, tip_height : ndarray of complex
        dx1, dh1 per unit drive [L].
    base_moment : ndarray of complex
        d theta'(0) per unit drive: the base moment in E I/L.
    num : ndarray of int
        The Chebyshev degree N used at each frequency.
    mu, gamma, tangential_mass : float
        The inertia number, the drag ratio, chi = the tangential/normal mass ratio.
    status : ndarray of int
        0, or 3 where the frequency is beyond N = 256 (``LINEAR_STATUS``).
    """

    omega: FloatArray
    drive: str
    tip_deflection: ComplexArray
    tip_height: ComplexArray
    base_moment: ComplexArray
    num: NDArray[np.int64]
    mu: float
    gamma: float
    tangential_mass: float
    status: NDArray[np.int64]

    _status_table: ClassVar[Mapping[int, str]] = LINEAR_STATUS

    def to_xarray(self) -> Any:
        """The response as an xarray.Dataset with the dimension ``omega`` and CF attributes:
        the outputs' amplitude and phase (the complex values split, as netCDF has no complex
        type), the degree and the status. Needs the ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "FrequencyResponse.to_xarray", "io")
        units = {"tip_deflection": "L", "tip_height": "L", "base_moment": "E I/L"}
        per = "L^2/(E I)" if self.drive == "tip_load" else "1"
        data: dict[str, Any] = {}
        for name in OUTPUTS:
            h = getattr(self, name)
            data[f"{name}_real"] = (
                "omega",
                h.real,
                {"units": f"{units[name]} {per}", "long_name": f"Re d{name}/d{self.drive}"},
            )
            data[f"{name}_imag"] = (
                "omega",
                h.imag,
                {"units": f"{units[name]} {per}", "long_name": f"Im d{name}/d{self.drive}"},
            )
            data[f"{name}_gain"] = (
                "omega",
                np.abs(h),
                {"units": f"{units[name]} {per}", "long_name": f"|d{name}/d{self.drive}|"},
            )
            data[f"{name}_phase"] = (
                "omega",
                np.angle(h),
                {"units": "rad", "long_name": f"phase of d{name}/d{self.drive} (e^(i omega t))"},
            )
        data["num"] = ("omega", self.num, {"long_name": "Chebyshev degree N"})
        data["status"] = (
            "omega",
            self.status,
            {"long_name": "status", "comment": "0 ok; 3 beyond the resolution of N = 256"},
        )
        return xr.Dataset(
            data,
            coords={
                "omega": (
                    "omega",
                    self.omega,
                    {
                        "units": "1/T",
                        "long_name": "angular frequency, T = zeta_perp L^4/(E I)",
                    },
                )
            },
            attrs={
                "title": "hairbed pillar frequency response",
                "drive": self.drive,
                "mu": self.mu,
                "gamma": self.gamma,
                "tangential_mass": self.tangential_mass,
                "time_convention": "exp(i omega t)",
                "Conventions": "CF-1.10",
            },
        )


@dataclass(frozen=True, eq=False)
class LinearPillar:
    """A pillar's linear dynamics about one static state (from :func:`linearise_pillar`).

    Attributes
    ----------
    state : PillarState
        The static state (scalar).
    mu : float
        The inertia number m E I/(zeta_perp^2 L^4) [-].
    tangential_mass : float
        chi, the tangential over the normal mass per unit length [-] (1: no added mass;
        m_s/(m_s + m_f) for a pillar of density rho_s in a fluid of density rho_f, whose added
        mass rho_f pi a^2 acts on normal motion only).
    """

    state: PillarState
    mu: float
    tangential_mass: float
    _prof: FloatArray = field(repr=False)
    _pencils: dict[int, _Pencil] = field(default_factory=dict, repr=False)

    def _pencil(self, num: int, schur: bool = True) -> _Pencil:
        """The reduced pencil at degree ``num``, with its Schur form where ``schur`` (built
        once per degree)."""
        have = self._pencils.get(num)
        if have is None or (schur and have.aa.size == 0):
            self._pencils[num] = _build_pencil(self, num, schur)
        return self._pencils[num]

    def modes(self, num_modes: int = 6, *, num: int | None = None) -> PillarModes:
        """The ``num_modes`` slowest modes (smallest abs(lambda)), by the QZ algorithm on the
        pencil at degree ``num`` (default: the state's, at least 32)."""
        k = _check_count(num_modes, "num_modes")
        deg = self._degree() if num is None else _check_degree(num)
        p = self._pencil(deg, schur=False)
        n = deg - 1
        lam, vec = _eigen(p.jr, p.br, p.mr, self.mu)
        fin = np.flatnonzero(np.isfinite(lam))
        # by modulus (to 10 digits, so that a conjugate pair is one key), then Im > 0 first
        size = np.array([float(f"{x:.10g}") for x in np.abs(lam[fin])])
        order = fin[np.lexsort((-lam[fin].imag, size))][:k]
        v = vec[:n, order].T  # interior angles of each mode
        full = v @ p.expand[: deg + 1].T
        big = np.abs(full).max(axis=1, keepdims=True)
        tip = full[np.arange(full.shape[0]), np.abs(full).argmax(axis=1)]
        full = full / (tip[:, None] / np.abs(tip[:, None])) / big
        return PillarModes(
            eigenvalues=lam[order].astype(np.complex128),
            s=p.ops.s.copy(),
            shapes=full.astype(np.complex128),
            tip_deflection=(full @ (p.ops.ii[deg] * np.cos(p.ops.theta))).astype(np.complex128),
            num=deg,
        )

    def growth_rate(self) -> float:
        """max Re lambda over the modes [1/T]: negative where the state is linearly stable
        (the physical model's linearisation, not a relaxation device; at a fold it is 0)."""
        return float(np.max(self.modes(4).eigenvalues.real))

    @property
    def stable(self) -> bool:
        """True where every mode decays (:meth:`growth_rate` < 0)."""
        return self.growth_rate() < 0.0

    def _degree(self) -> int:
        return max(32, int(self.state.num))

    def frequency_response(
        self,
        omega: ArrayLike,
        drive: str = "forcing",
        *,
        num: int | None = None,
        unsteady_drag: tuple[float, float] | None = None,
        drive_profile: Any = None,
    ) -> FrequencyResponse:
        """Transfer functions from ``drive`` to x1, h1 and theta'(0) at the frequencies
        ``omega`` [1/T] (finite, >= 0; any shape is flattened), each band by its own degree
        N (or all at ``num``).

        ``drive="profile"`` drives the flow's shape: the flow is Lambda U(z) + delta(t) V(z)
        (in the forcing's units, U the state's profile), V = ``drive_profile``: a callable
        V(z) (as a profile of :func:`linearise_pillar`) or V's Chebyshev coefficients in
        2 z - 1 (1-D, finite, at most 4097). The drive column is exact: the drag is linear in
        the flow, so dR/d delta is the unit load of V at the state (the column of "forcing"
        with V for U). V = U is the "forcing" drive. A profile that changes with a
        parameter p, U(z; p), is driven by V = dU/dp (the law of the wall's shape, theory.md
        §14).

        ``unsteady_drag=(reynolds_scale, slenderness)`` replaces the quasi-steady normal
        drag by the oscillating cylinder's (:func:`sader_drag_ratio`: Sader's hydrodynamic
        function above the crossover Re = 2 (a/L)^2, resistive force below), with
        reynolds_scale = rho_f b^2/(4 eta T) and slenderness L/a; the fluid's added mass is
        then in the drag, so ``mu`` must be the solid's own (rho_s pi a^2) and the mass
        isotropic (tangential_mass 1). The tangential drag stays gamma zeta_perp. Each
        frequency is one LU (no Schur form: the pencil is no longer polynomial)."""
        om = as_float_array(omega, "omega").reshape(-1)
        bad = ~np.isfinite(om) | (om < 0.0)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"omega must be finite and >= 0 [1/T], got {show(float(om[i]))} (first at "
                f"index {i})"
            )
        if not isinstance(drive, str) or drive not in DRIVES:
            raise ValueError(f"drive must be one of {DRIVES}, got {show(drive)}")
        col = DRIVES.index(drive)
        vprof = None
        if drive == "profile":
            if drive_profile is None:
                raise ValueError(
                    "drive 'profile' needs drive_profile: a callable V(z) or V's Chebyshev "
                    "coefficients in 2 z - 1"
                )
            vprof = _drive_coefficients(drive_profile)
        elif drive_profile is not None:
            raise ValueError(
                f"drive_profile is the shape of drive 'profile', not of {show(drive)}: pass "
                "drive='profile'"
            )
        wave = np.sqrt(np.sqrt(np.hypot(self.mu * om * om, om)))  # |k|
        if num is None:
            need = wave + _MARGIN
            degs = np.full(om.size, _BANDS[-1], dtype=np.int64)
            for b in _BANDS[::-1]:
                degs[need <= b] = b
            degs = np.maximum(degs, self._degree())
        else:
            degs = np.full(om.size, _check_degree(num), dtype=np.int64)
        status = np.where(wave + _MARGIN > degs, 3, 0).astype(np.int64)
        out = np.empty((3, om.size), dtype=np.complex128)
        drag = None
        if unsteady_drag is not None:
            if self.tangential_mass != 1.0:
                raise ValueError(
                    "unsteady_drag carries the fluid's added mass: linearise with "
                    "tangential_mass = 1 and mu of the solid alone"
                )
            if not isinstance(unsteady_drag, tuple) or len(unsteady_drag) != 2:
                raise ValueError(
                    "unsteady_drag must be a pair (reynolds_scale, slenderness), got "
                    f"{show(unsteady_drag)}"
                )
            drag = np.asarray(sader_drag_ratio(om, *unsteady_drag), dtype=np.complex128)
            drag = drag.reshape(-1)
            warn_dynamics_validity(om, self.mu, *unsteady_drag, unsteady_drag=True)
        for deg in np.unique(degs):
            sel = np.flatnonzero(degs == deg)
            rhs = self._drive_column(int(deg), col, vprof)
            if drag is None:
                out[:, sel] = self._response(int(deg), om[sel], rhs)
            else:
                out[:, sel] = self._unsteady_response(int(deg), om[sel], rhs, drag[sel])
        return FrequencyResponse(
            omega=om,
            drive=drive,
            tip_deflection=out[0],
            tip_height=out[1],
            base_moment=out[2],
            num=degs,
            mu=self.mu,
            gamma=float(self.state.gamma),
            tangential_mass=self.tangential_mass,
            status=status,
        )

    def _drive_column(self, deg: int, col: int, vprof: FloatArray | None) -> FloatArray:
        """The reduced drive column at degree ``deg``: the pencil's own ("forcing",
        "tip_load") or the unit load of the profile ``vprof`` ("profile")."""
        p = self._pencil(deg, schur=False)
        if vprof is None:
            return np.asarray(p.drives[col])
        from .._core.loaded import _kernels

        ops = p.ops
        num = ops.num
        n1 = num + 1
        u = np.empty(n1 + 1)
        u[:n1] = ops.theta
        u[n1] = float(ops.ii[num] @ np.cos(ops.theta))
        work = np.empty((5, n1 + 1))
        full = np.empty(n1 + 1)
        _kernels()._unit_load(
            u,
            num,
            ops.ii,
            float(self.state.gamma),
            vprof,
            work[0],
            work[1],
            work[2],
            work[3],
            work[4],
            full,
        )
        # the algebraic rows carry no load (as the pencil's own drives)
        return np.ascontiguousarray(full[1:num])

    def _unsteady_response(
        self, deg: int, om: FloatArray, drive: FloatArray, drag: ComplexArray
    ) -> ComplexArray:
        """The outputs with the normal drag zeta_perp D(omega) (Sader's, theory.md §14) and
        the solid's mass mu (isotropic): one LU a frequency."""
        p = self._pencil(deg, schur=False)
        ops = p.ops
        num = ops.num
        dif = np.arange(1, num)
        n1 = num + 1

        def red(x: FloatArray) -> FloatArray:
            full = np.zeros((n1 + 1, n1 + 1))
            full[1:num, :n1] = x[1:num]
            return np.asarray(full[dif] @ p.expand)

        b0 = red(velocity_operators(ops.theta, ops.ii, 0.0)[0])  # the normal part
        b1 = red(velocity_operators(ops.theta, ops.ii, 1.0)[0])
        m1 = b1  # the isotropic mass has the operator of the isotropic drag
        gamma = float(self.state.gamma)
        sv = 1j * om
        mats = (
            (self.mu * sv * sv)[:, None, None] * m1
            + (sv * drag)[:, None, None] * b0
            + (gamma * sv)[:, None, None] * (b1 - b0)
            - p.jr[None, :, :]
        )
        n = deg - 1
        rhs = np.broadcast_to(drive.astype(np.complex128), (om.size, n))
        v = np.linalg.solve(mats, rhs[:, :, None])[:, :, 0]
        return np.asarray((v @ p.outputs.T).T)

    def _response(self, deg: int, om: FloatArray, drive: FloatArray) -> ComplexArray:
        """The outputs at the frequencies ``om``, all at degree ``deg``: (3, size)."""
        from .._core._kernels import dynamics as kern

        n = deg - 1
        sv = np.ascontiguousarray(1j * om)
        if deg > 32 and om.size < _DIRECT:  # a few frequencies: one LU each, no Schur form
            p = self._pencil(deg, schur=False)
            mats = (
                (self.mu * sv * sv)[:, None, None] * p.mr
                + sv[:, None, None] * p.br
                - p.jr[None, :, :]
            )
            rhs = np.broadcast_to(drive.astype(np.complex128), (om.size, n))
            v = np.linalg.solve(mats, rhs[:, :, None])[:, :, 0]
            return np.asarray((v @ p.outputs.T).T)
        p = self._pencil(deg)
        m = p.aa.shape[0]
        qh = np.ascontiguousarray(p.q.conj().T)
        full = np.zeros(m, dtype=np.complex128)
        full[m - n :] = drive
        if deg <= 32:  # one right-hand side: the outputs straight from the Schur basis
            out = np.empty((3, om.size), dtype=np.complex128)
            cz = np.zeros((3, m), dtype=np.complex128)
            cz[:, :n] = p.outputs
            kern.pencil_outputs(p.aa, p.bb, qh @ full, sv, np.ascontiguousarray(cz @ p.z), out)
            return out

        def solve(rhs: ComplexArray) -> ComplexArray:
            g = np.zeros((om.size, m), dtype=np.complex128)
            g[:, m - n :] = rhs
            y = np.empty_like(g)
            kern.pencil_solve(p.aa, p.bb, np.ascontiguousarray(g @ qh.T), sv, y)
            return (y @ p.z.T)[:, :n]

        # at N > 32 one step of iterative refinement on the pencil itself
        rhs = np.broadcast_to(full[m - n :], (om.size, n))
        v = solve(rhs)
        res = rhs - (
            (v @ p.mr.T) * (self.mu * sv * sv)[:, None] + (v @ p.br.T) * sv[:, None] - v @ p.jr.T
        )
        v = v + solve(res)
        return np.asarray((v @ p.outputs.T).T)


def _build_pencil(lin: LinearPillar, num: int, schur: bool) -> _Pencil:
    st = lin.state
    coefs = np.zeros(num + 1)
    c0 = np.asarray(st._coefs)[0].reshape(-1)
    keep = min(num + 1, int(st.num) + 1)
    coefs[:keep] = c0[:keep]
    ops = state_operators(
        num,
        float(st._map),
        coefs,
        float(st.forcing),
        float(st.gamma),
        float(st.tip_load),
        lin._prof,
        lin.tangential_mass,
    )
    return _reduce(ops, lin.mu, schur)


#: The longest Chebyshev series of a drive profile (the wall law's reach 1025 terms).
_MAX_DRIVE_TERMS = 4097


def _drive_coefficients(value: Any) -> FloatArray:
    """The Chebyshev coefficients (in 2 z - 1) of a drive profile: a callable V(z), resolved
    as a profile of :func:`linearise_pillar`, or the coefficients themselves."""
    if callable(value):
        return np.ascontiguousarray(profile_coefficients(value), dtype=np.float64)
    if isinstance(value, (str, bytes)):
        raise ValueError(
            "drive_profile must be a callable V(z) or V's Chebyshev coefficients in 2 z - 1, "
            f"got {show(value)}"
        )
    arr = as_float_array(value, "drive_profile")
    if arr.ndim != 1 or not (1 <= arr.size <= _MAX_DRIVE_TERMS):
        raise ValueError(
            "drive_profile must be a 1-D array of 1 to "
            f"{_MAX_DRIVE_TERMS} Chebyshev coefficients, got shape {arr.shape}"
        )
    return np.ascontiguousarray(arr, dtype=np.float64)


def _check_count(value: Any, name: str) -> int:
    # numpy's timedelta64 is an integer type too: refused as any non-count
    if (
        isinstance(value, (bool, np.timedelta64))
        or not isinstance(value, (int, np.integer))
        or value < 1
    ):
        raise ValueError(f"{name} must be an integer >= 1, got {show(value)}")
    return int(value)


def _check_degree(value: Any) -> int:
    if (
        isinstance(value, (bool, np.timedelta64))
        or not isinstance(value, (int, np.integer))
        or not (8 <= value <= 512)
    ):
        raise ValueError(f"num must be an integer in [8, 512], got {show(value)}")
    return int(value)


def linearise_pillar(
    state: PillarState,
    *,
    profile: Any = "sublayer",
    height_ratio: float | None = None,
    mu: float = 0.0,
    tangential_mass: float = 1.0,
) -> LinearPillar:
    """The linear dynamics of a pillar about its static state ``state`` (theory.md §14).

    Any converged state of :func:`hairbed.solve_pillar` (any tilt, forcing, branch, large
    deflection): the small motion about it, with the drag of the pillar's velocity relative
    to the fluid (resistive force, the state's gamma) and its inertia.

    Parameters
    ----------
    state : PillarState
        One converged state (a scalar ``solve_pillar`` result, status >= 0).
    profile, height_ratio : optional
        The profile it was solved with (as in :func:`hairbed.solve_pillar`; checked by the
        collocation residual at the state). The forcing drive moves Lambda at this profile.
    mu : float, optional
        The inertia number m E I/(zeta_perp^2 L^4) >= 0 [-]; 0 (default) is overdamped.
    tangential_mass : float, optional
        chi in (0, 1]: the mass per unit length for motion along the pillar over that for
        normal motion (the added mass of the fluid acts normally only). Default 1.

    Returns
    -------
    LinearPillar
        With :meth:`LinearPillar.modes` and :meth:`LinearPillar.frequency_response`.

    Examples
    --------
    >>> import hairbed
    >>> from hairbed.dynamics import linearise_pillar
    >>> lin = linearise_pillar(hairbed.solve_pillar(0.0))
    >>> round(float(-lin.modes(1).eigenvalues[0].real), 8)  # beta_1^4: 1 + cos b cosh b = 0
    12.36236337
    """
    if not isinstance(state, PillarState):
        raise TypeError(f"state must be a PillarState, got {type(state).__name__}")
    if np.ndim(state.tip_height) != 0:
        raise ValueError(
            f"state must be one state (a scalar solve_pillar result), got shape "
            f"{np.shape(state.tip_height)}"
        )
    if int(state.status) < 0:
        raise ValueError(f"state has no solution (status {int(state.status)}: {state.message})")
    m = check_number(mu, "mu", low=0.0)
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    prof = profile_coefficients(profile, height_ratio)
    lin = LinearPillar(state=state, mu=m, tangential_mass=chi, _prof=prof)
    _check_state(lin)
    return lin


def _check_state(lin: LinearPillar) -> None:
    """The state must be a root of the profile's collocation system (else the profile given
    is not the one it was solved with)."""
    from .._core.loaded import _kernels

    st = lin.state
    ops = lin._pencil(lin._degree()).ops
    num = ops.num
    n1 = num + 1
    u = np.empty(n1 + 1)
    u[:n1] = ops.theta
    u[n1] = float(ops.ii[num] @ np.cos(ops.theta))
    work = np.empty((12, n1 + 1))
    res = np.empty(n1 + 1)
    _kernels()._residual_drag(
        u,
        num,
        ops.dd,
        ops.ii,
        float(st.theta0),
        float(st.forcing),
        float(st.gamma),
        float(st.tip_load),
        np.ascontiguousarray(lin._prof),
        work[0],
        work[1],
        work[2],
        res,
        work[6],
        work[7],
    )
    scale = 1.0 + abs(float(st.forcing)) + abs(float(st.tip_load))
    worst = float(np.max(np.abs(res[1:num])))
    if not math.isfinite(worst) or worst > _STATE_RESIDUAL * scale:
        raise ValueError(
            f"state is not a state of this profile (collocation residual {worst:.3g}): pass "
            "the profile and height_ratio it was solved with"
        )
