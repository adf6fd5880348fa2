"""Linear dynamics of the porous bed about any steady state (issue 30, theory.md §15).

About a converged state of :func:`hairbed.solve_porous` (any tilt, forcing, branch) the
semi-discrete bed M y' = g(t, y) of :func:`bed_operators` is linearised: a small motion
y = y* + Y e^{s t} under a drive d = d* + D e^{s t} (time in T = zeta_perp L^4/(E I), the
convention e^{i omega t}: s = i omega) obeys

    (s M - J) Y = b D,   output o = o* + (c . Y + f D) e^{s t},

with M the constant diagonal mass vector (zeros on the algebraic rows: the stresses, the tip
plane, the rates of an overdamped hair, the fluid of a quasi-steady bed), J the exact
Jacobian, b the drive's column, c the output's row and f its direct feedthrough (the
quasi-steady gap's stress and flux carry the pressure gradient itself: -g and -eps^2 g^3,
g = 1/eps - h1, where the fluid has no inertia; 0 otherwise).

- **Modes**: the finite eigenvalues of the pencil (J, M) by the QZ algorithm; a singular M
  has infinite eigenvalues (the algebraic rows), which are dropped.
- **Transfer functions**, first by the pencil's modal form, O(n) a frequency: with the
  finite eigenvalues lambda_k of (J, M) and their right and left vectors x_k, w_k,

      H(s) = sum_k (c . x_k)(w_k^H b)/((s - lambda_k) w_k^H M x_k) + D,

  D constant (the algebraic rows' infinite eigenvalues, index 1) and fixed by the exact
  value at s = 0: D = H(0) - sum_k(0), H(0) = c (-J)^{-1} b by one LU and one step of
  iterative refinement. The eigenvectors of the stiff pencil (bending rates ~ N^8) are not
  a well-conditioned basis, so the sum is checked on every call that asks a higher
  frequency than before, at a few of the requested frequencies (log-spaced up to the
  highest, and the resonances Im lambda_k of the modes with the highest peaks) against the
  refined direct solve, to ``_MODAL_TOL`` relative to the larger of the value and its static
  value. Where it misses, the modes below 10 times the highest frequency are polished by
  Newton's method on the bordered pencil (right vectors on (J, M), left ones on (J^T, M);
  its residual on the pencil itself gives the pairs the componentwise accuracy of a refined
  solve: at mu = 13, N = 32 the resonances go from 1.3e-9 to 7e-12) and checked again;
  where that misses too, the band falls back to the Schur form below.
- **Transfer functions by the Schur form** (the fallback): the pencil is reduced once to
  the complex generalised Schur form Q^H (J, M) Z = (AA, BB), and each frequency costs two
  triangular solves (``_kernels.dynamics.pencil_solve``, the pillar's kernel, O(n^2) a
  frequency): the solve and one step of iterative refinement on the pencil itself, as the
  pillar's above N = 32; a band of fewer than 64 frequencies is solved by one LU each
  instead.

  Eliminating the algebraic rows first (the Schur complement of the index-1 DAE, M being
  diagonal) was measured and rejected: the reduced matrix is a fourth-order operator
  (norm ~1e11 at N = 32) and its transfer functions are 1e-8 from the reference at N = 32
  and 1e-3 at N = 128 whatever solves them (2.6e-11 and 1.6e-6 with refinement in long
  double), against 1e-12 on the full pencil.

The resolution is chosen per frequency from the straight bed's length scales: the hair's
complex wavenumber |k|, k^4 = mu omega^2 - i omega (N >= |k| + 16, as the pillar's), the bed's
fluid layer 1/|l_b|, l_b^2 = (1 + i alpha kappa omega)/kappa, and the gap's Stokes layer
1/|l_g|, l_g^2 = i alpha omega, over the gap g: a Chebyshev grid resolves a layer of width
delta at its end to 1e-12 with about sqrt(30/delta) + 8 nodes. N and the gap's M are the
smallest of 32, 64, 128 (N) and 16, 32, 64, 128 (M) that meet them; a frequency whose
degrees fall short (beyond 128, or a smaller ``num``/``num_gap`` given) has status 3.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from .._core.porous import PorousState
from .._core.validation import StatusResult, as_float_array, check_number, show
from ._bed import BED_OUTPUTS, BedOperators, bed_operators

__all__ = [
    "BED_LINEAR_STATUS",
    "BedFrequencyResponse",
    "BedModes",
    "LinearBed",
    "linearise_bed",
]

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Status codes of a linear bed result (0 ok, positive a caveat).
BED_LINEAR_STATUS = {
    0: "ok",
    3: (
        "inaccurate: the degrees used are below the resolution this frequency needs (the "
        "hair's wavenumber or a fluid layer too thin for N or the gap's M: beyond 128, or a "
        "smaller num or num_gap given): the values there are not converged"
    ),
}
_HAIR_BANDS = (32, 64, 128)
_GAP_BANDS = (16, 32, 64, 128)
_MARGIN = 16
#: A band of fewer than this many frequencies is solved by one LU each (measured: a complex
#: QZ of the pencil costs about as much as 30 to 100 LUs), unless its Schur form is built.
_DIRECT = 64
#: Eigenvalues above this modulus [1/T] are the algebraic rows' infinite ones (rounded).
_INFINITE = 1e13


#: The modal form is used where it matches the refined direct solve to this (relative to
#: the larger of the value and its static value) at every check frequency: the issue's 1e-10
#: with a margin of 3 (the errors peak at the resonances, and those are checked).
_MODAL_TOL = 3e-11
#: The least damped modes whose resonances are checked, and the log-spaced checks below the
#: highest frequency asked.
_MODAL_PEAKS = 6
_MODAL_GRID = 3
#: Where the checks miss, the modes below this many times the top frequency are polished
#: by Newton's method (at most ``_REFINE_MAX`` of them, else the Schur form).
_REFINE_REACH = 10.0
_REFINE_MAX = 96
#: Frequencies per product of the modal sum.
_MODAL_BLOCK = 64


@dataclass(frozen=True)
class _Pencil:
    ops: BedOperators
    aa: ComplexArray
    bb: ComplexArray
    q: ComplexArray
    z: ComplexArray


@dataclass(eq=False)
class _Modal:
    """The pencil's modal form at one (N, M): the finite eigenvalues, their right and left
    vectors (those of modulus below ``refined_below`` polished by Newton's method), the
    outputs' rows on the right vectors over w_k^H M x_k and the left vectors conjugated;
    per drive (cached in ``drives``) its residues, the constant D and the checks passed."""

    ops: BedOperators
    lam: ComplexArray
    xr: ComplexArray  # (size, n): x_k
    wl: ComplexArray  # (size, n): w_k
    right: ComplexArray  # (outputs, n): (c . x_k)/(w_k^H M x_k)
    left: ComplexArray  # (n, size): w_k^H
    refined_below: float = 0.0
    drives: dict[str, _ModalDrive] = field(default_factory=dict)


@dataclass(eq=False)
class _ModalDrive:
    column: FloatArray  # (size,): b
    residues: ComplexArray  # (outputs, n)
    const: ComplexArray  # (outputs,): D
    static: ComplexArray  # (outputs,): H(0) without the feedthrough
    checked_up_to: float = 0.0
    ok: bool = True


@dataclass(frozen=True)
class BedModes:
    """The linear modes of the porous bed about a steady state (theory.md §15).

    A mode is Y e^{lambda t} (t in T = zeta_perp L^4/(E I)).

    Attributes
    ----------
    eigenvalues : ndarray of complex
        lambda [1/T], the finite ones ordered by modulus (conjugate pairs both listed, Im > 0
        first); a stable state has Re < 0.
    tip_deflection, wall_stress : ndarray of complex
        The tip's motion [L] and the top wall's stress (§13's load units) of each mode,
        the mode scaled so that its largest angle has modulus 1 and real tip deflection
        >= 0 (where the tip moves).
    num, num_gap : int
        The Chebyshev degrees N of the hair and M of the gap.
    status : int
        0 (``BED_LINEAR_STATUS``).
    """

    eigenvalues: ComplexArray
    tip_deflection: ComplexArray
    wall_stress: ComplexArray
    num: int
    num_gap: int
    status: int = 0

    @property
    def success(self) -> bool:
        """True where status is 0."""
        return self.status == 0

    @property
    def message(self) -> str:
        """``BED_LINEAR_STATUS`` of ``status``."""
        return BED_LINEAR_STATUS[self.status]

    @property
    def frequency(self) -> FloatArray:
        """abs(Im lambda) [1/T] of each mode (0 when overdamped)."""
        return np.abs(self.eigenvalues.imag)

    @property
    def damping_ratio(self) -> FloatArray:
        """-Re lambda/abs(lambda) [-] of each mode."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)


_UNITS = {
    "tip_deflection": "L",
    "tip_height": "L",
    "base_moment": "E I/L",
    "wall_stress": "E I/(A L^2)",
    "flow_rate": "1",
}
_DRIVE_UNITS = {
    "wall": "1 (omega2 = eta V A L^2/(E I H))",
    "pressure": "1 (Pi = A G L^3/(E I))",
    "flow_rate": "1 (q = 6 A eta Q' L^2/(E I H^2))",
}


@dataclass(frozen=True)
class BedFrequencyResponse(StatusResult):
    """Transfer functions of the porous bed about a steady state (theory.md §15).

    For a drive d(t) = d* + Re(D e^{i omega t}) (t in T) each output is
    o* + Re(H(omega) D e^{i omega t}): H is the complex amplitude per unit drive.

    Attributes
    ----------
    omega : ndarray
        Angular frequencies [1/T].
    drive : str
        "wall" (the wall forcing omega2 = eta V A L^2/(E I H), i.e. the top wall's speed),
        "pressure" (Pi) or "flow_rate" (q), as the state's drives.
    tip_deflection, tip_height : ndarray of complex
        dx1, dh1 per unit drive [L].
    base_moment : ndarray of complex
        d theta'(0) per unit drive [E I/L].
    wall_stress : ndarray of complex
        The top wall's shear stress per unit drive, in §13's load units Q = A L^2 eta u_z/
        (E I).
    flow_rate : ndarray of complex
        q = 6 eps^2 Phi per unit drive (§11's units).
    num, num_gap : ndarray of int
        The degrees N (hair) and M (gap) used at each frequency.
    inertia, womersley, tangential_mass : float
        mu, alpha and chi of the linearisation.
    status : ndarray of int
        0, or 3 beyond the resolution (``BED_LINEAR_STATUS``).
    method : ndarray of str
        How each frequency was solved: "lu" (one LU each: a band of fewer than 64 whose
        forms are not built), "modal" (the checked modal form) or "schur" (the Schur form
        with a refinement step, where the modal form missed its check).
    """

    omega: FloatArray
    drive: str
    tip_deflection: ComplexArray
    tip_height: ComplexArray
    base_moment: ComplexArray
    wall_stress: ComplexArray
    flow_rate: ComplexArray
    num: NDArray[np.int64]
    num_gap: NDArray[np.int64]
    inertia: float
    womersley: float
    tangential_mass: float
    status: NDArray[np.int64]
    method: NDArray[np.str_]

    _status_table: ClassVar[Mapping[int, str]] = BED_LINEAR_STATUS

    def to_xarray(self) -> Any:
        """The response as an xarray.Dataset on ``omega`` with CF attributes: each output's
        real and imaginary parts, gain and phase, the degrees and the status. Needs the
        ``io`` extra."""
        from .._optional import optional_import

        xr = optional_import("xarray", "BedFrequencyResponse.to_xarray", "io")
        per = f"per unit {self.drive}"
        data: dict[str, Any] = {}
        for name in BED_OUTPUTS:
            h = getattr(self, name)
            unit = _UNITS[name]
            for suffix, value, u, what in (
                ("real", h.real, unit, "Re"),
                ("imag", h.imag, unit, "Im"),
                ("gain", np.abs(h), unit, "abs"),
                ("phase", np.angle(h), "rad", "arg"),
            ):
                data[f"{name}_{suffix}"] = (
                    "omega",
                    value,
                    {"units": u, "long_name": f"{what} d{name}/d{self.drive} ({per})"},
                )
        data["num"] = ("omega", self.num, {"units": "1", "long_name": "Chebyshev degree N"})
        data["num_gap"] = ("omega", self.num_gap, {"units": "1", "long_name": "gap degree M"})
        data["status"] = ("omega", self.status, {"units": "1", "long_name": "status"})
        data["method"] = ("omega", self.method.astype(str), {"long_name": "solution method"})
        return xr.Dataset(
            data,
            coords={
                "omega": (
                    "omega",
                    self.omega,
                    {"units": "1/T", "long_name": "angular frequency, T = zeta_perp L^4/(E I)"},
                )
            },
            attrs={
                "title": "hairbed porous bed frequency response",
                "drive": self.drive,
                "drive_units": _DRIVE_UNITS.get(self.drive, "1"),
                "inertia": self.inertia,
                "womersley": self.womersley,
                "tangential_mass": self.tangential_mass,
                "time_convention": "exp(i omega t)",
                "Conventions": "CF-1.10",
            },
        )


@dataclass(frozen=True, eq=False)
class LinearBed:
    """The porous bed's linear dynamics about one steady state (:func:`linearise_bed`).

    Attributes
    ----------
    state : PorousState
        The static state (scalar).
    inertia, tangential_mass, womersley : float
        mu, chi and the bed's Womersley number alpha = rho_f L^2/(eta T) [-].
    """

    state: PorousState
    inertia: float
    tangential_mass: float
    womersley: float
    _pencils: dict[tuple[int, int], _Pencil] = field(default_factory=dict, repr=False)
    _ops: dict[tuple[int, int], BedOperators] = field(default_factory=dict, repr=False)
    _modals: dict[tuple[int, int], _Modal | None] = field(default_factory=dict, repr=False)

    @property
    def drives(self) -> tuple[str, ...]:
        """The drives of this state (:func:`bed_operators`' columns): "wall" and "pressure",
        or "wall" and "flow_rate" for a state of the flow drive."""
        return ("wall", "flow_rate" if self.state.drive == "flow" else "pressure")

    def _default(self) -> tuple[int, int]:
        return max(_HAIR_BANDS[0], min(int(self.state.num), 128)), _GAP_BANDS[0]

    def operators(self, num: int, num_gap: int) -> BedOperators:
        """:func:`bed_operators` at the degrees (N, M), built once each: N in [8, 128], M in
        [4, 128]."""
        deg, gdeg = _check_degree(num, "num"), _check_degree(num_gap, "num_gap", 4)
        key = (deg, gdeg if self.womersley > 0.0 else 0)
        have = self._ops.get(key)
        if have is None:
            have = bed_operators(
                self.state,
                inertia=self.inertia,
                tangential_mass=self.tangential_mass,
                womersley=self.womersley,
                num=key[0],
                num_gap=max(key[1], 4),
            )
            self._ops[key] = have
        return have

    def _pencil(self, num: int, num_gap: int) -> _Pencil:
        key = (int(num), int(num_gap) if self.womersley > 0.0 else 0)
        have = self._pencils.get(key)
        if have is None:
            ops = self.operators(num, max(num_gap, 4))
            aa, bb, q, z = scipy.linalg.qz(ops.jacobian, np.diag(ops.mass), output="complex")
            have = _Pencil(ops, aa, bb, q, z)
            self._pencils[key] = have
        return have

    def _modal(self, num: int, num_gap: int) -> _Modal | None:
        """The modal form at (N, M), built once; None where the pencil has fewer finite
        eigenvalues than differential rows (index 2: D would not be constant) or a mode
        has w_k^H M x_k = 0 (a defective pencil)."""
        key = (int(num), int(num_gap) if self.womersley > 0.0 else 0)
        if key in self._modals:
            return self._modals[key]
        ops = self.operators(num, max(num_gap, 4))
        have: _Modal | None = None
        with np.errstate(all="ignore"):
            lam, left, right = scipy.linalg.eig(
                ops.jacobian, np.diag(ops.mass), left=True, right=True
            )
        fin = np.isfinite(lam) & (np.abs(lam) < _INFINITE)
        # complex always (eig gives real vectors where every eigenvalue is real)
        lam, left, right = (np.asarray(x, dtype=np.complex128) for x in (lam, left, right))
        lam, left, right = lam[fin], left[:, fin], right[:, fin]
        if lam.size == np.count_nonzero(ops.mass):
            none = np.zeros((0, 0), dtype=np.complex128)
            have = _Modal(ops, lam.astype(np.complex128), right, left, none, none)
            if not _derive(have):
                have = None
        self._modals[key] = have
        return have

    def _modal_drive(self, md: _Modal, drive: str) -> _ModalDrive:
        """The residues of ``drive`` and D from the exact H(0) (refined LU of -J); not ok
        where J is singular (a fold)."""
        have = md.drives.get(drive)
        if have is None:
            col = np.asarray(md.ops.drives[drive], dtype=np.float64)
            h0 = _direct(md.ops, np.zeros(1, dtype=np.complex128), col)[:, 0]
            none = np.zeros(0, dtype=np.complex128)
            have = _ModalDrive(col, none, none, h0)
            _drive_terms(md, have)
            md.drives[drive] = have
        return have

    def _modal_checked(self, md: _Modal, mdd: _ModalDrive, om: FloatArray) -> bool:
        """Whether the modal form holds to ``_MODAL_TOL`` at the frequencies ``om``: checked
        against the refined direct solve (once per band and drive, and again when a higher
        frequency is asked) at log-spaced frequencies up to the highest asked and at the
        resonances (Im lambda_k) of the modes with the highest peaks |R_k|/|Re lambda_k|
        in that range."""
        if not mdd.ok:
            return False
        pos = om[om > 0.0]
        if pos.size == 0:
            return True  # H(0) is the anchor itself
        top = float(pos.max())
        if top <= mdd.checked_up_to:
            return True
        if self._modal_check(md, mdd, float(pos.min()), top):
            mdd.checked_up_to = top
            return True
        # polish the modes below 10 times the top frequency by Newton's method, once
        reach = _REFINE_REACH * top
        if reach > md.refined_below and _refine(md, reach):
            for other in md.drives.values():
                _drive_terms(md, other)
            if self._modal_check(md, mdd, float(pos.min()), top, 0.0):
                mdd.checked_up_to = top
                return True
        mdd.ok = False
        return False

    @staticmethod
    def _modal_check(
        md: _Modal, mdd: _ModalDrive, low: float, top: float, done: float | None = None
    ) -> bool:
        """The checks of :meth:`_modal_checked` from ``done`` (default: those passed) to
        ``top``."""
        done = mdd.checked_up_to if done is None else done
        low = max(low, done)
        checks = list(np.geomspace(low, top, _MODAL_GRID + 1)) if low < top else [top]
        lam = md.lam
        inside = np.flatnonzero((lam.imag > done) & (lam.imag <= top))
        if inside.size:
            with np.errstate(all="ignore"):
                peak = np.abs(mdd.residues[:, inside]).max(axis=0) / np.abs(lam[inside].real)
            order = np.argsort(-np.nan_to_num(peak, nan=np.inf))[:_MODAL_PEAKS]
            checks += [float(lam[inside[k]].imag) for k in order]
        sv = 1j * np.array(sorted(set(checks)))
        want = _direct(md.ops, sv, mdd.column)
        got = _modal_values(lam, mdd, sv)
        with np.errstate(all="ignore"):
            level = np.abs(mdd.residues) @ np.abs(1.0 / (sv[None, :] - lam[:, None]))
            scale = np.maximum(np.abs(want), np.abs(mdd.static)[:, None])
            # an output that vanishes identically (the flow rate under a set flow rate; the
            # tip height about the straight hair) is judged against the largest static value
            big = float(np.max(np.abs(mdd.static)))
            zero = np.all(scale <= 1e-12 * big, axis=1)
            scale[zero] = big
            bound = _MODAL_TOL * scale + 64.0 * _EPS * (level + np.abs(mdd.const)[:, None])
            return bool(np.all(np.abs(got - want) <= bound))

    def modes(
        self, num_modes: int = 6, *, num: int | None = None, num_gap: int | None = None
    ) -> BedModes:
        """The ``num_modes`` slowest modes (smallest abs(lambda)) of the pencil (J, M) at the
        degrees N = ``num`` (default: the state's, at least 32) and M = ``num_gap``
        (default 32), by the QZ algorithm; the infinite eigenvalues of the algebraic rows
        are dropped."""
        k = _check_count(num_modes, "num_modes")
        deg = self._default()[0] if num is None else _check_degree(num, "num")
        gdeg = 32 if num_gap is None else _check_degree(num_gap, "num_gap", 4)
        ops = self.operators(deg, gdeg)
        lam, vec = scipy.linalg.eig(ops.jacobian, np.diag(ops.mass))
        fin = np.flatnonzero(np.isfinite(lam) & (np.abs(lam) < _INFINITE))
        size = np.array([float(f"{x:.10g}") for x in np.abs(lam[fin])])
        order = fin[np.lexsort((-lam[fin].imag, size))][:k]
        v = vec[:, order]
        nth = int(ops.num) - 1
        big = np.abs(v[:nth]).max(axis=0)
        tip = ops.outputs["tip_deflection"] @ v
        phase = np.where(np.abs(tip) > 0, tip / np.where(tip == 0, 1, np.abs(tip)), 1.0)
        v = v / (phase * np.where(big > 0, big, 1.0))[None, :]
        return BedModes(
            eigenvalues=lam[order].astype(np.complex128),
            tip_deflection=(ops.outputs["tip_deflection"] @ v).astype(np.complex128),
            wall_stress=(ops.outputs["wall_stress"] @ v).astype(np.complex128),
            num=int(ops.num),
            num_gap=int(ops.num_gap) if self.womersley > 0.0 else 0,
        )

    def growth_rate(self) -> float:
        """max Re lambda over the slowest modes [1/T]: negative where the state is stable."""
        return float(np.max(self.modes(4).eigenvalues.real))

    @property
    def stable(self) -> bool:
        """True where every mode decays (:meth:`growth_rate` < 0)."""
        return self.growth_rate() < 0.0

    def _degrees(self, om: FloatArray) -> tuple[NDArray[np.int64], NDArray[np.int64], Any]:
        """N and M per frequency from the straight bed's length scales (module docstring),
        and the resolutions (N, M) they need (status 3 where a degree used is below its
        need: beyond 128, or a smaller ``num``/``num_gap`` given)."""
        mu, alpha = self.inertia, self.womersley
        kappa, eps = float(self.state.kappa), float(self.state.eps)
        gap = max(1.0 / eps - float(self.state.tip_height), 1e-3)
        with np.errstate(over="ignore"):  # beyond N = 128 anyway (status 3)
            wave = np.sqrt(np.sqrt(np.hypot(mu * om * om, om)))
            layer = np.sqrt(np.hypot(1.0, alpha * kappa * om) / kappa)
        need_n = np.maximum(wave + _MARGIN, np.sqrt(30.0 * layer) + 8.0)
        need_m = np.sqrt(30.0 * gap * np.sqrt(alpha * om)) + 8.0
        nn = _bands(need_n, _HAIR_BANDS)
        nn = np.maximum(nn, self._default()[0])
        mm = _bands(need_m, _GAP_BANDS) if alpha > 0.0 else np.zeros(om.size, dtype=np.int64)
        return nn, mm, (need_n, need_m)

    def frequency_response(
        self,
        omega: ArrayLike,
        drive: str = "wall",
        *,
        num: int | None = None,
        num_gap: int | None = None,
    ) -> BedFrequencyResponse:
        """Transfer functions from ``drive`` to every output of ``BED_OUTPUTS`` at the
        frequencies ``omega`` [1/T] (finite, >= 0; flattened), each band of frequencies at
        its own degrees (or all at ``num`` and ``num_gap``).

        The drive is one of :attr:`drives`: "wall" (omega2, the top wall's speed),
        "pressure" (Pi) or "flow_rate" (q)."""
        om = as_float_array(omega, "omega").reshape(-1)
        bad = ~np.isfinite(om) | (om < 0.0)
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"omega must be finite and >= 0 [1/T], got {show(float(om[i]))} (first at "
                f"index {i})"
            )
        drives = self.drives
        if not isinstance(drive, str) or drive not in drives:
            raise ValueError(f"drive must be one of {drives} for this state, got {show(drive)}")
        nn, mm, (need_n, need_m) = self._degrees(om)
        if num is not None:
            nn = np.full(om.size, _check_degree(num, "num"), dtype=np.int64)
        if num_gap is not None:
            mm = np.full(om.size, _check_degree(num_gap, "num_gap", 4), dtype=np.int64)
        if self.womersley <= 0.0:
            mm[:] = 0
        # status 3 where the degrees used (chosen or given) miss the resolution needed
        short = (need_n > nn) | ((need_m > mm) & (self.womersley > 0.0))
        status = np.where(short, 3, 0).astype(np.int64)
        out = np.empty((len(BED_OUTPUTS), om.size), dtype=np.complex128)
        method = np.empty(om.size, dtype="<U5")
        for key in sorted(set(zip(nn.tolist(), mm.tolist()))):
            sel = np.flatnonzero((nn == key[0]) & (mm == key[1]))
            out[:, sel], method[sel] = self._response(key[0], key[1], om[sel], drive)
        values = dict(zip(BED_OUTPUTS, out))
        return BedFrequencyResponse(
            omega=om,
            drive=drive,
            num=nn,
            num_gap=mm,
            inertia=self.inertia,
            womersley=self.womersley,
            tangential_mass=self.tangential_mass,
            status=status,
            method=method,
            **values,
        )

    def _feedthrough(self, ops: BedOperators, drive: str) -> FloatArray:
        """f: the outputs' direct dependence on the drive (``BedOperators.feedthrough``)."""
        return np.asarray(ops.feedthrough[drive], dtype=np.float64)

    def _response(
        self, num: int, num_gap: int, om: FloatArray, drive: str
    ) -> tuple[ComplexArray, str]:
        """The outputs (len(BED_OUTPUTS), om.size) at the degrees (N, M), and the method."""
        from .._core._kernels import dynamics as kern

        ops = self.operators(num, max(num_gap, 4))
        rows = np.stack([ops.outputs[k] for k in BED_OUTPUTS])
        col = np.asarray(ops.drives[drive], dtype=np.float64)
        feed = self._feedthrough(ops, drive)[:, None]
        sv = np.ascontiguousarray(1j * om)
        m = col.size
        key = (num, num_gap)
        if om.size < _DIRECT and key not in self._pencils and key not in self._modals:
            mats = sv[:, None, None] * np.diag(ops.mass)[None] - ops.jacobian[None]
            rhs = np.broadcast_to(col.astype(np.complex128), (om.size, m))
            y = np.linalg.solve(mats, rhs[:, :, None])[:, :, 0]
            return np.asarray(rows @ y.T + feed, dtype=np.complex128), "lu"
        if key not in self._pencils:  # the modal form, where it is checked to hold
            md = self._modal(num, num_gap)
            if md is not None:
                mdd = self._modal_drive(md, drive)
                if self._modal_checked(md, mdd, om):
                    return np.asarray(_modal_values(md.lam, mdd, sv) + feed), "modal"
        p = self._pencil(num, num_gap)
        qh = np.ascontiguousarray(p.q.conj().T)
        zt = np.ascontiguousarray(p.z.T)
        mass = ops.mass

        def solve(rhs: ComplexArray) -> ComplexArray:
            y = np.empty_like(rhs)
            kern.pencil_solve(p.aa, p.bb, np.ascontiguousarray(rhs @ qh.T), sv, y)
            return np.asarray(y @ zt)

        # one step of iterative refinement on the pencil itself: the Schur form's back
        # substitution alone loses digits to the pencil's scaling (measured 4e-10 against
        # the mpmath reference, 1e-12 with the step, as a direct solve)
        rhs = np.broadcast_to(col.astype(np.complex128), (om.size, m))
        y = solve(np.ascontiguousarray(rhs))
        res = rhs - (sv[:, None] * (y * mass[None, :]) - y @ ops.jacobian.T)
        y = y + solve(np.ascontiguousarray(res))
        return np.asarray(rows @ y.T + feed, dtype=np.complex128), "schur"


_EPS = float(np.finfo(np.float64).eps)


def _derive(md: _Modal) -> bool:
    """The outputs' rows on the right vectors over w_k^H M x_k and the left vectors
    conjugated, from ``md.xr`` and ``md.wl``; False where a mode has w_k^H M x_k = 0 (a
    defective pencil) or a value is not finite."""
    ops = md.ops
    rows = np.stack([ops.outputs[k] for k in BED_OUTPUTS])
    with np.errstate(all="ignore"):
        nrm = np.einsum("ik,i,ik->k", md.wl.conj(), ops.mass, md.xr)
        md.right = (rows @ md.xr) / nrm[None, :]
    md.left = np.ascontiguousarray(md.wl.conj().T)
    return bool(np.all(np.abs(nrm) > 0.0) and np.all(np.isfinite(md.right)))


def _drive_terms(md: _Modal, mdd: _ModalDrive) -> None:
    """The residues R_k and the constant D = H(0) - sum_k R_k/(0 - lambda_k) of a drive
    (again after a refinement: the checks start over)."""
    mdd.residues = md.right * (md.left @ mdd.column)[None, :]
    with np.errstate(all="ignore"):
        mdd.const = mdd.static - mdd.residues @ (1.0 / (0.0 - md.lam))
    mdd.ok = bool(np.all(np.isfinite(mdd.const)))
    mdd.checked_up_to = 0.0


def _newton_pair(
    jac: FloatArray, mass: FloatArray, lam: complex, x: ComplexArray
) -> tuple[complex, ComplexArray]:
    """(lambda, x) of (J - lambda M) x = 0 polished by two steps of Newton's method on the
    bordered system [[J - lambda M, -M x], [x^H, 0]] (one LU): its residual, taken on the
    pencil itself, brings the pair to the componentwise accuracy a refined solve has."""
    n = jac.shape[0]
    x = x / np.linalg.norm(x)
    mat = np.zeros((n + 1, n + 1), dtype=np.complex128)
    mat[:n, :n] = jac - lam * np.diag(mass)
    mat[:n, n] = -mass * x
    mat[n, :n] = x.conj()
    lu = scipy.linalg.lu_factor(mat, check_finite=False)
    rhs = np.zeros(n + 1, dtype=np.complex128)
    for _ in range(2):
        rhs[:n] = lam * (mass * x) - jac @ x
        rhs[n] = 0.0
        step = scipy.linalg.lu_solve(lu, rhs, check_finite=False)
        x = x + step[:n]
        lam = lam + step[n]
    return complex(lam), x


def _refine(md: _Modal, reach: float) -> bool:
    """Polish the modes with refined_below < abs(lambda) <= reach (at most
    ``_REFINE_MAX``), right vectors on (J, M) and left ones on (J^T, M); False where there
    are more or a step fails."""
    pick = np.flatnonzero((np.abs(md.lam) > md.refined_below) & (np.abs(md.lam) <= reach))
    if pick.size > _REFINE_MAX:
        return False
    jac, mass = md.ops.jacobian, md.ops.mass
    lam, xr, wl = md.lam.copy(), md.xr.copy(), md.wl.copy()
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
        for k in pick:
            lam_r, x = _newton_pair(jac, mass, complex(md.lam[k]), md.xr[:, k])
            lam_l, w = _newton_pair(jac.T, mass, complex(md.lam[k]), md.wl[:, k].conj())
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(w))):
                return False
            lam[k], xr[:, k], wl[:, k] = lam_r, x, w.conj()
    md.lam, md.xr, md.wl = lam, xr, wl
    md.refined_below = reach
    return _derive(md)


def _modal_values(lam: ComplexArray, mdd: _ModalDrive, sv: ComplexArray) -> ComplexArray:
    """sum_k R_k/(s - lambda_k) + D at each s of ``sv``: (outputs, sv.size). In blocks of
    ``_MODAL_BLOCK`` frequencies: each product stays below the size at which a threaded BLAS
    starts its threads (measured on two loaded cores: 32 ms for 1,000 frequencies in one
    product, 0.8 ms in blocks)."""
    out = np.empty((mdd.residues.shape[0], sv.size), dtype=np.complex128)
    for j in range(0, sv.size, _MODAL_BLOCK):
        part = sv[j : j + _MODAL_BLOCK]
        out[:, j : j + part.size] = mdd.residues @ (1.0 / (part[None, :] - lam[:, None]))
    return out + mdd.const[:, None]


def _direct(ops: BedOperators, sv: ComplexArray, col: FloatArray) -> ComplexArray:
    """The outputs c . y of (s M - J) y = col (no feedthrough) at each s of ``sv`` by one LU
    and one step of iterative refinement; NaN where the matrix is singular."""
    rows = np.stack([ops.outputs[k] for k in BED_OUTPUTS])
    out = np.full((rows.shape[0], sv.size), np.nan, dtype=np.complex128)
    rhs = col.astype(np.complex128)
    for i, s in enumerate(sv):
        mat = s * np.diag(ops.mass) - ops.jacobian
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            try:
                lu = scipy.linalg.lu_factor(mat, check_finite=False)
            except (ValueError, np.linalg.LinAlgError):  # pragma: no cover - finite J
                continue
            if not np.all(np.abs(np.diag(lu[0])) > 0.0):
                continue
            y = scipy.linalg.lu_solve(lu, rhs, check_finite=False)
            y = y + scipy.linalg.lu_solve(lu, rhs - mat @ y, check_finite=False)
        out[:, i] = rows @ y
    return out


def _bands(need: FloatArray, bands: tuple[int, ...]) -> NDArray[np.int64]:
    out = np.full(need.size, bands[-1], dtype=np.int64)
    for b in bands[::-1]:
        out[need <= b] = b
    return out


def _check_count(value: Any, name: str) -> int:
    if (
        isinstance(value, (bool, np.timedelta64))
        or not isinstance(value, (int, np.integer))
        or value < 1
    ):
        raise ValueError(f"{name} must be an integer >= 1, got {show(value)}")
    return int(value)


def _check_degree(value: Any, name: str, low: int = 8) -> int:
    if (
        isinstance(value, (bool, np.timedelta64))
        or not isinstance(value, (int, np.integer))
        or not (low <= value <= 128)
    ):
        raise ValueError(f"{name} must be an integer in [{low}, 128], got {show(value)}")
    return int(value)


def linearise_bed(
    state: PorousState,
    *,
    inertia: float = 0.0,
    tangential_mass: float = 1.0,
    womersley: float = 0.0,
) -> LinearBed:
    """The linear dynamics of the porous bed about its steady state ``state`` (theory.md §15).

    Any converged state of :func:`hairbed.solve_porous` (any tilt, forcing, branch, the
    wall drive with the pressure or the flow drive): the small motion of the hairs and the
    fluid about it, from :func:`bed_operators` (the same discretisation as the bed in time).

    Parameters
    ----------
    state : PorousState
        One converged state (a scalar ``solve_porous`` result, status >= 0, eps > 0).
    inertia : float, optional
        The hair's inertia number mu = m E I/(zeta_perp^2 L^4) >= 0 [-] (default 0).
    tangential_mass : float, optional
        chi in (0, 1]: tangential over normal mass per unit length [-] (default 1).
    womersley : float, optional
        The bed's Womersley number alpha = rho_f L^2/(eta T) >= 0 [-] (default 0: the
        quasi-steady fluid).

    Returns
    -------
    LinearBed
        With :meth:`LinearBed.modes` and :meth:`LinearBed.frequency_response`.

    Examples
    --------
    >>> import hairbed
    >>> from hairbed.dynamics import linearise_bed
    >>> lin = linearise_bed(hairbed.solve_porous(0.0, 0.5, kappa=1e3))
    >>> round(float(-lin.modes(1).eigenvalues[0].real), 3)  # the pillar's beta_1^4 = 12.362
    12.365
    """
    if not isinstance(state, PorousState):
        raise TypeError(f"state must be a PorousState, got {type(state).__name__}")
    if np.ndim(state.tip_height) != 0:
        raise ValueError(
            "state must be one state (a scalar solve_porous result), got shape "
            f"{np.shape(state.tip_height)}"
        )
    if int(state.status) < 0:
        raise ValueError(f"state has no solution (status {int(state.status)}: {state.message})")
    mu = check_number(inertia, "inertia", low=0.0)
    chi = check_number(tangential_mass, "tangential_mass", low=0.0, high=1.0, low_open=True)
    alpha = check_number(womersley, "womersley", low=0.0)
    if not math.isfinite(mu) or not math.isfinite(alpha):  # pragma: no cover - checked above
        raise ValueError("inertia and womersley must be finite")
    return LinearBed(state=state, inertia=mu, tangential_mass=chi, womersley=alpha)
