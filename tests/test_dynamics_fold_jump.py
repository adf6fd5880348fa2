"""The jump off a fold as an event of the pillar's dynamics (issue 30, theory.md §14).

A pillar tilted far upstream (theta0 = -1.4) has a snap-through window: its branch of static
states turns at an upper fold Lambda_f = 16.15 (``hairbed.continue_pillar``, the statics' fold
finder, independent of the integrator). A slow ramp of the forcing through Lambda_f moves the
pillar along the branch until past the fold, where it leaves at O(1) speed for the far branch.
The slow passage through a saddle-node (x' = r t + x^2 in its normal form) delays the jump by
Delta Lambda = c r^(2/3): the test fits that exponent over three decades of the rate r.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import ramp, simulate_pillar, step
from hairbed.dynamics._integrate import TRAJECTORY_STATUS

THETA0 = -1.4
LAM0 = 16.0
#: The event's threshold [L/T]: the quasi-static motion at these rates stays below 0.01, the
#: jump's own peak speed is 1.5.
JUMP_SPEED = 0.5


@pytest.fixture(scope="module")
def fold() -> float:
    folds = hairbed.continue_pillar(20.0, THETA0).folds
    assert folds.shape == (2, 2) and folds[0, 0] > LAM0 > folds[1, 0]
    return float(folds[0, 0])


@pytest.fixture(scope="module")
def start() -> hairbed.PillarState:
    states = hairbed.solve_pillar_all(LAM0, THETA0)
    assert len(states) == 3 and states[0].stable
    return states[0]  # the near branch, below the upper fold


def test_jump_delay_scales_as_rate_to_two_thirds(fold: float, start: hairbed.PillarState) -> None:
    rates = np.array([1e-5, 1e-4, 1e-3, 1e-2])
    delays = []
    for r in rates:
        t_end = (fold + 1.0 - LAM0) / r  # past the fold by 1: the jump comes first
        run = simulate_pillar(
            ramp(LAM0, LAM0 + 2.0, 0.0, 2.0 / r), [0.0, t_end], theta0=THETA0,
            initial=start, rtol=1e-8, atol=1e-10, jump_speed=JUMP_SPEED,
        )  # fmt: skip
        assert run.status == -9 and not run.success
        assert run.message == TRAJECTORY_STATUS[-9]
        assert 0.0 < run.t_end < t_end
        # the output past the event is NaN and says so by the status, never a silent value
        assert math.isfinite(run.tip_deflection[0]) and math.isnan(run.tip_deflection[-1])
        delays.append(LAM0 + r * run.t_end - fold)
    d = np.array(delays)
    assert np.all(d > 0.0) and np.all(np.diff(d) > 0.0)  # past the static fold, later if faster
    slope = np.polyfit(np.log(rates), np.log(d), 1)[0]
    assert abs(slope - 2.0 / 3.0) <= 0.05, (slope, d)  # measured 0.661


def test_without_the_event_the_jump_lands_on_the_far_branch(
    fold: float, start: hairbed.PillarState
) -> None:
    """The same ramp run through (no jump_speed): once the forcing holds at 18, past the
    window, the pillar rests in the one static state there (the far branch)."""
    r = 1e-2
    lam1 = LAM0 + 2.0
    run = simulate_pillar(
        ramp(LAM0, lam1, 0.0, 2.0 / r), [0.0, 0.9 * (fold - LAM0) / r, 2.0 / r + 5.0],
        theta0=THETA0, initial=start, rtol=1e-8, atol=1e-10,
    )  # fmt: skip
    assert run.success
    far = hairbed.solve_pillar_all(lam1, THETA0)
    assert len(far) == 1
    assert abs(run.tip_deflection[-1] - far[0].tip_deflection) <= 1e-8
    near = hairbed.continue_pillar(20.0, THETA0).folds[1, 1]  # x1 at the lower fold
    assert run.tip_deflection[1] < -0.9 and far[0].tip_deflection > near  # jumped across


def test_no_fold_no_event() -> None:
    """An upright pillar on the same kind of ramp never leaves its branch: status 0."""
    run = simulate_pillar(
        ramp(0.0, 10.0, 0.0, 100.0), [0.0, 100.0], rtol=1e-8, atol=1e-10,
        jump_speed=JUMP_SPEED,
    )  # fmt: skip
    assert run.success and run.t_end == 100.0


def test_a_step_is_a_jump_at_its_start() -> None:
    """A step of the drive starts the pillar at O(1) speed: with a threshold below that the
    event is at the step itself (t_end within the first step's bisection of t = 0)."""
    run = simulate_pillar(step(10.0), [0.0, 1.0], jump_speed=0.1)
    assert run.status == -9 and 0.0 <= run.t_end <= 1e-6


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, "fast"])
def test_bad_jump_speed(bad: object) -> None:
    with pytest.raises((ValueError, TypeError), match="jump_speed"):
        simulate_pillar(step(1.0), [0.0, 1.0], jump_speed=bad)  # type: ignore[arg-type]
