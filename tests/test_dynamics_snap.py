"""Snap-through in time: ``hairbed.dynamics.snap_through`` (issue 31 1d, theory.md §14).

The references are independent of the run: the jump's delay against the normal form of a
slow passage through a saddle-node (Delta Lambda ~ rate^(2/3), the exponent of
tests/test_dynamics_fold_jump.py, here at two rates through the workflow), the settled state
against ``solve_pillar``'s forward solve of the high root (not the branch's inverse that the
workflow uses), and the ringing against the linear modes about that state (QZ on the linear
pencil, no time stepping).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import SNAP_STATUS, SnapThrough, linearise_pillar, snap_through

THETA0 = -1.4


@pytest.fixture(scope="module")
def slow() -> SnapThrough:
    return snap_through(THETA0, rate=1e-4)


@pytest.fixture(scope="module")
def fast() -> SnapThrough:
    return snap_through(THETA0, rate=1e-2)


def test_fold_and_jump(fast: SnapThrough) -> None:
    assert fast.success and fast.message == SNAP_STATUS[0]
    assert abs(fast.fold_forcing - 16.1505) < 1e-4  # theory.md §12's upper fold
    assert 13.6 < fast.lower_fold_forcing < 13.8
    assert fast.fold_time == pytest.approx((fast.fold_forcing - fast.start_forcing) / 1e-2)
    assert fast.jump_time > fast.fold_time and fast.delay > 0.0
    assert fast.jump_forcing == pytest.approx(fast.start_forcing + 1e-2 * fast.jump_time)
    # before: on the near branch, leaning upstream beyond the fold's deflection (it lags)
    assert fast.before_tip_deflection < fast.fold_deflection < -0.9
    # after: across the window, standing over its base
    assert fast.after_tip_deflection > -0.3
    traj = fast.trajectory
    assert traj is not None and traj.success
    assert math.isnan(fast.ring_frequency) and math.isnan(fast.ring_decay)  # overdamped


def test_delay_scales_as_rate_to_two_thirds(slow: SnapThrough, fast: SnapThrough) -> None:
    """Delta Lambda = rate * delay ~ rate^(2/3): the slope over two decades of the rate."""
    d = np.array([slow.rate * slow.delay, fast.rate * fast.delay])
    slope = math.log(d[1] / d[0]) / math.log(fast.rate / slow.rate)
    assert abs(slope - 2.0 / 3.0) <= 0.05, (slope, d)  # measured 0.651 (delays 4.0e-3, 8.0e-2)
    assert slow.delay < fast.delay * (1e-2 / 1e-4) ** (1.0 / 3.0) * 1.1  # delay ~ rate^(-1/3)


@pytest.mark.parametrize("which", ["slow", "fast"])
def test_final_state_equals_the_statics(which: str, request: pytest.FixtureRequest) -> None:
    run: SnapThrough = request.getfixturevalue(which)
    high = hairbed.solve_pillar(run.jump_forcing, THETA0, root="high")
    assert int(high.status) >= 0
    assert abs(run.after_tip_deflection - float(high.tip_deflection)) <= 1e-10
    assert abs(run.after_tip_height - float(high.tip_height)) <= 1e-10
    assert run.settle_error <= 1e-10  # measured 1.3e-14 (1e-4), 8.7e-15 (1e-2)


@pytest.mark.parametrize("mu", [1.0, 13.0])
def test_ringing_matches_the_linear_modes(mu: float) -> None:
    """The tip's ringing after the jump against the slowest mode about the final static state
    (the one the tip deflection carries; the next mode is damped about as much, the drag damps
    every mode at about 1/(2 mu)). Tolerances: 1e-3 in the frequency, 5e-3 in the decay rate
    (measured 1.3e-4 and 7e-4 at mu = 1, 1.1e-4 and 1.1e-3 at mu = 13: the fit's residual
    nonlinearity and the higher modes)."""
    run = snap_through(THETA0, rate=1e-2, mu=mu)
    assert run.success
    high = hairbed.solve_pillar(run.jump_forcing, THETA0, root="high")
    lam = linearise_pillar(high, mu=mu).modes(4).eigenvalues
    first = lam[np.argmin(np.abs(lam))]
    assert first.imag != 0.0
    assert abs(run.ring_frequency - abs(first.imag)) <= 1e-3 * abs(first.imag)
    assert abs(run.ring_decay + first.real) <= 5e-3 * abs(first.real)
    assert abs(run.after_tip_deflection - float(high.tip_deflection)) <= 1e-6


@pytest.mark.parametrize("theta0", [-1.0, 0.3, -1.25])
def test_no_window_names_theta0_and_the_range(theta0: float) -> None:
    """Above -1.2 at once; at -1.25 (between -1.2 and the cusp) by the continuation."""
    with pytest.raises(ValueError, match=rf"theta0 = {theta0} has no snap-through window") as exc:
        snap_through(theta0, rate=1e-2)
    assert "-1.35" in str(exc.value) and "-1.3" in str(exc.value)


@pytest.mark.parametrize(
    ("kw", "name"),
    [
        ({"rate": 0.0}, "rate"),
        ({"rate": math.nan}, "rate"),
        ({"rate": 1e-2, "mu": -1.0}, "mu"),
        ({"rate": 1e-2, "start_forcing": 10.0}, "start_forcing"),
        ({"rate": 1e-2, "jump_speed": 0.0}, "jump_speed"),
    ],
)
def test_bad_input(kw: dict[str, float], name: str) -> None:
    with pytest.raises(ValueError, match=name):
        snap_through(THETA0, **kw)


def test_no_jump_is_a_status() -> None:
    """A threshold the jump never reaches: status -1, no silent value."""
    run = snap_through(THETA0, rate=1e-2, jump_speed=100.0)
    assert run.status == -1 and not run.success and run.message == SNAP_STATUS[-1]
    assert math.isnan(run.jump_time) and math.isnan(run.after_tip_deflection)
