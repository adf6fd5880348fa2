"""The bed's Newton matrices by the elimination of their algebraic unknowns (issue 30's
batch speed; ``_kernels.dynamics._reduced_factor`` and ``_reduced_solve``).

Reference: numpy's LAPACK solve of the whole matrix c M - J (an independent LU with partial
pivoting), at the Radau IIA shifts c = U1/h and (alpha - i beta)/h over the step sizes a run
takes.
"""

from __future__ import annotations

import numpy as np
import pytest

from hairbed._core._kernels import dynamics as kern
from hairbed._core._kernels.spectral import _lu_factor
from hairbed.dynamics._bed import _evaluate, _mass, _static_start, _system
from hairbed.dynamics._signals import as_signal, step

#: The eigenvalues of the Radau IIA (order 5) matrix's inverse, U1 and alpha -+ i beta
#: (Hairer & Wanner, Solving ODEs II, IV.8), from the matrix written out here.
_S6 = np.sqrt(6.0)
_A = np.array(
    [
        [(88 - 7 * _S6) / 360, (296 - 169 * _S6) / 1800, (-2 + 3 * _S6) / 225],
        [(296 + 169 * _S6) / 1800, (88 + 7 * _S6) / 360, (-2 - 3 * _S6) / 225],
        [(16 - _S6) / 36, (16 + _S6) / 36, 1 / 9],
    ]
)


def _parts(ev: np.ndarray) -> tuple[float, complex]:
    real = float(ev[np.argmin(np.abs(ev.imag))].real)
    cplx = complex(ev[np.argmax(ev.imag)])
    return real, cplx.conjugate()


@pytest.mark.parametrize(("kappa", "mu", "alpha"), [(0.1, 0.0, 0.0), (2.0, 0.3, 0.5)])
def test_reduced_solve_is_the_full_lu(kappa: float, mu: float, alpha: float) -> None:
    """x = (c M - J)^-1 r by the elimination agrees with numpy's full solve to 1e-6
    relatively (the elimination's rounding, |J_aa^-1 J_ad| ~ 4e10, measured ~1e-7) for a
    real and a complex right-hand side, at h from 1e-6 to 1; a singular J_aa is refused."""
    sig = as_signal(step(1.0), "wall", 0.0, 8.0)
    sys = _system(24, 0.0, 8, 0.2, 1.0, 1.0, mu, kappa, 0.5, alpha, 0, 0, sig,
                  as_signal(0.0, "pressure", 0.0, 8.0))  # fmt: skip
    y = _static_start(sys, 0.2, kappa, 0.5, 1.0, 1.0, 0.0, 0.0)
    ok, _, jac = _evaluate(sys, 0.5, y, True)  # the drive stepped: away from the steady
    assert ok
    mass = _mass(sys)
    m = mass.size
    dsel = np.flatnonzero(mass != 0.0).astype(np.int64)
    asel = np.flatnonzero(mass == 0.0).astype(np.int64)
    nd, na = dsel.size, asel.size
    red = (np.empty((na, na)), np.empty((nd, na)), np.empty((nd, nd)), np.empty(nd * na),
           np.empty((na, na)))  # fmt: skip
    ired = (np.empty(na, np.int64), np.empty(nd + 1, np.int64), np.empty(nd * na, np.int64))
    assert kern._reduced_factor(jac, dsel, asel, red, ired, np.empty(na))
    u1, shift = _parts(np.linalg.eigvals(np.linalg.inv(_A)))
    rng = np.random.default_rng(7)
    worst = 0.0
    for h in (1e-6, 1e-3, 1e-1, 1.0):
        for c in (u1 / h, shift / h):
            cplx = isinstance(c, complex)
            dtype = np.complex128 if cplx else np.float64
            s = np.diag(c * mass[dsel]).astype(dtype) - red[2]
            piv = np.empty(nd, np.int64)
            assert _lu_factor(s, piv, nd)
            r = rng.standard_normal(m) + (1j * rng.standard_normal(m) if cplx else 0.0)
            want = np.linalg.solve(np.diag(c * mass) - jac, r)
            got = np.array(r, dtype=dtype)
            solve = kern._reduced_solve_c if cplx else kern._reduced_solve
            solve(got, s, piv, dsel, asel, red, ired, np.empty((2, na)), np.empty(nd, dtype))
            worst = max(worst, float(np.max(np.abs(got - want)) / np.max(np.abs(want))))
    assert worst < 1e-6
    bad = jac.copy()
    bad[asel[3], :] = 0.0  # an algebraic row that reads nothing: J_aa singular
    assert not kern._reduced_factor(bad, dsel, asel, red, ired, np.empty(na))
