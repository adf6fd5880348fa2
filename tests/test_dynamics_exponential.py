"""The exponential Rosenbrock integrator of the ringing pillar (``simulate_pillar(...,
method="exponential")``, ``_core/_kernels/exponential.py``, theory.md §14):

- its matrix functions against mpmath's matrix exponential at 30 digits: phi_0 .. phi_4 and
  phi_1 at half the argument of a far-from-normal, oscillatory 4 x 4 matrix (from the
  exponential of the block matrix [[A, I, 0, ..], [0, 0, I, ..], ..], whose first block row
  is e^A, phi_1(A), .., phi_4(A)) and of a damped oscillator's 2 x 2 matrix at norms from
  0.1 to 150 (every degree and scaling the least-work choice takes there), and the balanced
  exponential of a badly scaled one;
- the Taylor degrees' thresholds theta_nb: the largest arguments at which the series'
  remainders are below 2^-53, summed by mpmath at 40 digits;
- the ringing pillar (mu = 13) under a smooth rise to Lambda = 2: the tip deflection at
  N = 12, rtol 1e-8 against the Radau IIA run (the other integrator, sharing only the
  semi-discrete rates) at twice the degree, N = 24, and rtol 1e-10, within 1e-8 over 30 T
  (measured 7.5e-10);
- a true step (no smoothing) against Radau IIA at rtol 1e-10 (measured 4.9e-12);
- the wall and jump events at the times Radau IIA finds;
- bad input: an unknown method named.
"""

from __future__ import annotations

from typing import Any

import mpmath
import numpy as np
import pytest

from hairbed._core._kernels.exponential import (
    _EXP_THETAS,
    _PHI_THETAS,
    expm_augmented,
    phi_matrices,
)
from hairbed.dynamics import sampled, simulate_pillar, step


def _phi_reference(a: np.ndarray) -> list[np.ndarray]:
    """phi_0(A) .. phi_4(A) at 30 digits: the first block row of exp of the block matrix
    with A, then identities above the diagonal (mpmath's expm)."""
    p = a.shape[0]
    with mpmath.workdps(30):
        big = mpmath.zeros(5 * p, 5 * p)
        for i in range(p):
            for k in range(p):
                big[i, k] = mpmath.mpf(float(a[i, k]))
        for blk in range(4):
            for i in range(p):
                big[blk * p + i, (blk + 1) * p + i] = 1
        ex = mpmath.expm(big)
        return [
            np.array([[float(ex[i, j * p + k]) for k in range(p)] for i in range(p)])
            for j in range(5)
        ]


def test_phi_matrices_against_mpmath() -> None:
    # oscillatory (eigenvalues near +-20i, +-7i), weakly damped, far from normal
    a = np.array(
        [[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [-300.0, 90.0, -0.5, 0.1],
         [40.0, -60.0, 0.2, -0.3]]
    )  # fmt: skip
    out = np.empty((5, 4, 4))
    half = np.empty((4, 4))
    phi_matrices(a, 4, out, half, np.empty((3, 4, 4)))
    ref = _phi_reference(a)
    for k in range(5):
        scale = np.max(np.abs(ref[k]))
        assert np.max(np.abs(out[k] - ref[k])) <= 1e-12 * scale, k
    ref_half = _phi_reference(0.5 * a)[1]
    assert np.max(np.abs(half - ref_half)) <= 1e-12 * np.max(np.abs(ref_half))


def test_phi_matrices_every_degree_against_mpmath() -> None:
    """A damped oscillator's matrix times 0.4 .. 70 (||.||_1 1.8 .. 320): the least-work
    choices s = 1 .. 5 and Taylor degrees 14 .. 34 of phi_4 (nb = 3 .. 7), each phi_k to
    1e-12 of its largest entry (measured: at most 7e-15, but 2.5e-13 in phi_0 = e^A where
    it has decayed to 1e-6)."""
    base = np.array([[-0.1, 1.0], [-4.5, -0.3]])
    for scale in (0.4, 1.5, 2.0, 3.0, 4.0, 10.0, 70.0):  # (s, nb) (1, 3) .. (5, 7)
        a = scale * base
        out = np.empty((5, 2, 2))
        half = np.empty((2, 2))
        phi_matrices(a, 4, out, half, np.empty((3, 2, 2)))
        ref = _phi_reference(a)
        for k in range(5):
            assert np.max(np.abs(out[k] - ref[k])) <= 1e-12 * np.max(np.abs(ref[k])), (scale, k)
        ref_half = _phi_reference(0.5 * a)[1]
        assert np.max(np.abs(half - ref_half)) <= 1e-12 * np.max(np.abs(ref_half)), scale


def test_taylor_thresholds_against_mpmath() -> None:
    """theta_nb of ``_PHI_THETAS`` is the largest x with max_k k! sum_{i > 5 nb + 3 - k}
    x^i/(i + k)! <= 2^-53 (phi_0 .. phi_4 from phi_4's polynomial of degree 5 nb - 1),
    theta_nb of ``_EXP_THETAS`` the largest with sum_{i > 5 nb - 1} x^i/i! <= 2^-53: the
    remainder at theta is 2^-53 to 1e-12, and above it 1e-6 further on."""

    def remainders(x: Any, nb: int) -> tuple[Any, Any]:
        deg = 5 * nb - 1
        unit = mpmath.mpf(2) ** -53
        phi = max(
            mpmath.factorial(k)
            * mpmath.fsum(x**i / mpmath.factorial(i + k) for i in range(deg + 5 - k, deg + 150))
            for k in range(5)
        )
        exp = mpmath.fsum(x**i / mpmath.factorial(i) for i in range(deg + 1, deg + 150))
        return phi / unit, exp / unit

    with mpmath.workdps(40):
        for nb in range(3, 8):
            for which, table in enumerate((_PHI_THETAS, _EXP_THETAS)):
                theta = mpmath.mpf(float(table[nb]))
                assert abs(remainders(theta, nb)[which] - 1) < 1e-12, (nb, which)
                assert remainders(theta * (1 + 1e-6), nb)[which] > 1, (nb, which)


def test_balanced_exponential_against_mpmath() -> None:
    # a similarity by diag(1, 1e3, 1e-3, 1) of an oscillatory matrix: 1-norm 1e5 to 1e6
    base = np.array(
        [[-0.2, 3.0, 0.0, 0.5], [-3.0, -0.1, 1.0, 0.0], [0.0, -1.0, -0.4, 2.0],
         [0.3, 0.0, -2.0, -0.1]]
    )  # fmt: skip
    d = np.array([1.0, 1e3, 1e-3, 1.0])
    a = base * d[None, :] / d[:, None]
    e = np.empty((4, 4))
    expm_augmented(a, e, np.zeros((4, 4, 4)))
    with mpmath.workdps(30):
        ref = mpmath.expm(mpmath.matrix(a.tolist()))
        ref = np.array([[float(ref[i, k]) for k in range(4)] for i in range(4)])
    # each entry to 1e-12 of its own scale, d_k/d_i (e^a = D^-1 e^base D)
    assert np.all(np.abs(e - ref) <= 1e-12 * d[None, :] / d[:, None])


def _rise(value: float) -> object:
    tt = np.linspace(0.0, 1.0, 201)
    return sampled(tt, 0.5 * value * (1.0 - np.cos(np.pi * tt)))


def test_ringing_pillar_against_radau_at_twice_the_degree() -> None:
    te = np.linspace(0.0, 30.0, 61)
    drive = _rise(2.0)
    run = simulate_pillar(drive, te, mu=13.0, num=12, rtol=1e-8, atol=1e-10, method="exponential")
    ref = simulate_pillar(drive, te, mu=13.0, num=24, rtol=1e-10, atol=1e-12)
    assert run.success and ref.success
    assert np.max(np.abs(run.tip_deflection - ref.tip_deflection)) < 1e-8
    assert run.njev >= 1 and run.nsteps > 0


def test_true_step_against_radau() -> None:
    """The ringing pillar struck by a true step (Lambda 0 -> 4 at t = 0, no smoothing: every
    mode of the grid rings), N = 8, over 12 T: rtol 1e-8 within 1e-9 of Radau IIA at
    rtol 1e-10 in the tip deflection at every output time (measured 4.9e-12)."""
    te = np.linspace(0.0, 12.0, 121)
    kw: dict[str, Any] = {"mu": 13.0, "num": 8}
    run = simulate_pillar(step(4.0), te, rtol=1e-8, atol=1e-9, method="exponential", **kw)
    ref = simulate_pillar(step(4.0), te, rtol=1e-10, atol=1e-12, max_steps=10**6, **kw)
    assert run.success and ref.success
    assert np.max(np.abs(run.tip_deflection - ref.tip_deflection)) < 1e-9


def test_unknown_method_is_named() -> None:
    with pytest.raises(ValueError, match="method"):
        simulate_pillar(1.0, [0.0, 1.0], method="rk45")


def test_events_agree_with_radau() -> None:
    """The wall event (a downstream-tilted pillar struck by Lambda = 300 overshoots to the
    wall, theory.md §14) and the jump event (the tip's speed reaching 0.05 L/T after a
    step), each located on the dense output by bisection: the same times as Radau IIA."""
    kw: dict[str, Any] = {"theta0": 1.3, "mu": 1.0, "num": 12, "rtol": 1e-8, "atol": 1e-10}
    te = [0.0, 0.1, 0.5]
    wall = [simulate_pillar(step(300.0), te, method=m, **kw) for m in ("radau", "exponential")]
    assert [r.status for r in wall] == [-8, -8]
    assert abs(wall[0].t_end - wall[1].t_end) < 1e-9
    assert np.isfinite(wall[1].tip_deflection[1]) and np.isnan(wall[1].tip_deflection[2])
    jump = [
        simulate_pillar(step(20.0), te, method=m, jump_speed=0.05, **kw)
        for m in ("radau", "exponential")
    ]
    assert [r.status for r in jump] == [-9, -9]
    assert abs(jump[0].t_end - jump[1].t_end) < 1e-8  # (measured 3e-11)
