"""The dynamics kernels (``hairbed._core._kernels.dynamics``, issue 30) on small problems.

``make test`` runs this file a second time under ``NUMBA_DISABLE_JIT=1`` (with the other
kernel tests), where every kernel executes as plain Python: small sizes keep that run fast.
References: numpy's dense solves, the drives' closed forms, central differences, and the
static solver's state.
"""

from __future__ import annotations

import math

import numpy as np

import hairbed
from hairbed._core._kernels import dynamics as kern
from hairbed.dynamics._operators import _mapped


def test_pencil_kernels_against_dense_solves() -> None:
    rng = np.random.default_rng(3)
    m = 6
    aa = np.triu(rng.standard_normal((m, m)) + 1j * rng.standard_normal((m, m)))
    bb = np.triu(rng.standard_normal((m, m)) + 1j * rng.standard_normal((m, m)))
    aa += 4.0 * np.eye(m)
    sv = 1j * np.array([0.0, 0.3, 2.0])
    g = rng.standard_normal((sv.size, m)) + 0j
    y = np.empty_like(g)
    kern.pencil_solve(aa, bb, g, sv, y)
    cz = rng.standard_normal((2, m)) + 0j
    out = np.empty((2, sv.size), dtype=np.complex128)
    kern.pencil_outputs(aa, bb, g[0].copy(), sv, cz, out)
    for f, s in enumerate(sv):
        want = np.linalg.solve(s * bb - aa, g[f])
        assert np.allclose(y[f], want, rtol=1e-12, atol=1e-12)
        assert np.allclose(out[:, f], cz @ np.linalg.solve(s * bb - aa, g[0]), rtol=1e-12)


def test_drive_values() -> None:
    empty = np.zeros(1)
    par = np.array([1.0, 2.0, 3.0, 0.5, 0.0, 0.0, 0.0])
    assert kern.drive_value(kern.SIGNAL_SINE, par, empty, empty, 0.7) == 1.0 + 2.0 * math.sin(
        3.0 * 0.7 + 0.5
    )
    ramp = np.array([0.0, 4.0, 1.0, 3.0, 0.0, 0.0, 0.0])
    assert kern.drive_value(kern.SIGNAL_RAMP, ramp, empty, empty, 2.0) == 2.0
    tt = np.array([0.0, 1.0, 2.0, 3.0])
    vv = tt**2
    assert abs(kern.drive_value(kern.SIGNAL_SAMPLED, par, tt, vv, 1.5) - 2.25) <= 1e-14


def _system(num: int) -> tuple:
    _, _, dd, ii, _ = _mapped(num, 0.0)
    srow = -dd[num, :] / dd[num, num]
    srow[num] = 0.0
    return dd, ii, srow


def test_small_integration_relaxes_to_the_static_state() -> None:
    """N = 12, a step to Lambda = 5 at theta0 = 0.2 from the state at rest: the end state of
    the Radau run is the static collocation's at N = 12 (solve_pillar, num=12)."""
    num = 12
    dd, ii, srow = _system(num)
    n = num - 1
    y0 = np.full(n, 0.2)
    drives = np.zeros((2, 8))
    drives[0, 0] = kern.SIGNAL_STEP
    drives[0, 1:4] = (0.0, 5.0, 0.0)
    prof = np.array([0.5, 0.5])
    t_eval = np.array([0.0, 0.1, 3.0])
    y_out = np.full((t_eval.size, n), np.nan)
    counts = np.zeros(6, dtype=np.int64)
    status, t_end = kern.integrate_pillar(
        y0, 0.0, t_eval, 1e-6, 1e-8, 1e-6, 2000, num, dd, ii, srow, 0.2, 0.5, 1.0, 0.0, prof,
        drives, np.zeros((4, 1)), y_out, counts,
    )  # fmt: skip
    assert status == kern.STATUS_OK and t_end == 3.0 and counts[1] > 0
    theta = np.concatenate([[0.2], y_out[-1]])
    theta = np.append(theta, theta @ srow[:num])
    st = hairbed.solve_pillar(5.0, 0.2, num=num)
    assert abs(np.sin(theta) @ ii[num] - st.tip_deflection) <= 1e-9


def test_projected_load_operator_against_numpy() -> None:
    """The operator of ``projected_load`` alone (need 1, the rates' path) and with its
    derivatives (need 2) against the numpy construction of ``velocity_operators`` (the
    linear dynamics' B and M), at a bent state, N = 10."""
    from hairbed.dynamics._operators import velocity_operators

    num = 10
    _, _, _, ii, _ = _mapped(num, 0.3)
    n1 = num + 1
    th = 0.2 + 0.9 * np.sin(np.linspace(0.0, 2.0, n1))
    rate = np.cos(np.linspace(0.0, 3.0, n1))
    for ratio in (0.5, 1.0, 0.2):
        want, _ = velocity_operators(th, ii, ratio)
        for need in (1, 2):
            val = np.zeros(n1 + 1)
            opa = np.zeros((n1 + 1, n1 + 1))
            opb, dth = opa.copy(), opa.copy()
            kern.projected_load(
                th, rate, np.zeros(n1), ratio, num, ii, need, val, opa, opb, dth,
                np.zeros((12, n1 + 1)),
            )  # fmt: skip
            assert np.allclose(opa[:n1, :n1], want, rtol=0.0, atol=1e-13)
            assert np.allclose(val[:n1], want @ rate, rtol=0.0, atol=1e-13)
