"""The exponential integrator of the ringing pillar (``simulate_pillar(...,
method="exponential")``, ``_core/_kernels/exponential.py``, theory.md §14):

- its phi functions against mpmath's closed forms at 50 digits (small, middle and large
  arguments, the oscillatory and the decaying directions, and the switch at |z| = 1);
- the ringing pillar (mu = 13) under a smooth rise to Lambda = 2: the tip deflection at
  N = 12, rtol 1e-7 against the Radau IIA run (the other integrator, sharing only the
  semi-discrete rates) at twice the degree, N = 24, and rtol 1e-10, within 1e-8 over 30 T
  (measured 2.4e-9);
- the wall and jump events at the times Radau IIA finds (measured 3e-13 and 3e-11 apart);
- bad input: an unknown method named.
"""

from __future__ import annotations

from typing import Any

import mpmath
import numpy as np
import pytest

from hairbed._core._kernels.exponential import phi_functions
from hairbed.dynamics import sampled, simulate_pillar, step


def _phi_reference(z: complex, j: int) -> complex:
    """phi_j(z) = (e^z - sum_{k<j} z^k/k!)/z^j at 50 digits (phi_0 = e^z)."""
    with mpmath.workdps(50):
        zz = mpmath.mpc(z)
        acc = mpmath.exp(zz)
        for k in range(j):
            acc -= zz**k / mpmath.factorial(k)
        return complex(acc / zz**j)


@pytest.mark.parametrize(
    "z", [1e-9 + 2e-9j, 0.3 - 0.2j, 0.999j, -1.001, 1.0 + 0.5j, -40.0 + 800.0j, -2.5e4, 30j]
)
def test_phi_functions_against_mpmath(z: complex) -> None:
    out = np.empty(4, dtype=np.complex128)
    phi_functions(z, out)
    for j in range(4):
        ref = _phi_reference(z, j)
        assert abs(out[j] - ref) <= 1e-14 * max(abs(ref), 1e-300) + 1e-300, (j, out[j], ref)


def _rise(value: float) -> object:
    tt = np.linspace(0.0, 1.0, 201)
    return sampled(tt, 0.5 * value * (1.0 - np.cos(np.pi * tt)))


def test_ringing_pillar_against_radau_at_twice_the_degree() -> None:
    te = np.linspace(0.0, 30.0, 61)
    drive = _rise(2.0)
    run = simulate_pillar(drive, te, mu=13.0, num=12, rtol=1e-7, atol=1e-9, method="exponential")
    ref = simulate_pillar(drive, te, mu=13.0, num=24, rtol=1e-10, atol=1e-12)
    assert run.success and ref.success
    assert np.max(np.abs(run.tip_deflection - ref.tip_deflection)) < 1e-8
    assert run.njev >= 1 and run.nsteps > 0


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
