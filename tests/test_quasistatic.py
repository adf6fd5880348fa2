"""Quasi-static sweeps: continuity, jumps at the folds, hysteresis (theory.md §5)."""

import numpy as np
import pytest

import hairbed
from hairbed.branches import folds
from hairbed.quasistatic import sweep, sweep_with_jumps

THETA0, EPS = -1.5, 0.9  # window 0.95766 < omega^2 < 1.4859 (theory.md §5)


def _ramp():
    up = np.linspace(0.5, 2.0, 61)
    return up, up[::-1].copy()


def test_up_ramp_follows_low_root_and_down_ramp_the_high_root():
    up, down = _ramp()
    s_up = sweep(up, EPS, THETA0)
    s_down = sweep(down, EPS, THETA0, root="high")
    low = hairbed.solve(up, EPS, THETA0, root="low")
    high = hairbed.solve(up, EPS, THETA0, root="high")
    upper = folds(EPS, THETA0).upper.omega2
    lower = folds(EPS, THETA0).lower.omega2
    before = up < upper
    # Up: the low root while it exists, then the only root left (the high one).
    np.testing.assert_allclose(s_up.xi[before], low.xi[before], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(s_up.xi[~before], high.xi[~before], rtol=1e-10, atol=1e-12)
    # Down: the high root until the lower fold, then the low one.
    down_high = down > lower
    high_d = hairbed.solve(down, EPS, THETA0, root="high")
    low_d = hairbed.solve(down, EPS, THETA0, root="low")
    np.testing.assert_allclose(s_down.xi[down_high], high_d.xi[down_high], rtol=1e-10)
    np.testing.assert_allclose(s_down.xi[~down_high], low_d.xi[~down_high], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(
        s_up.tip_height[before], low.tip_height[before], rtol=1e-10, atol=1e-12
    )
    # Inside the window the two ramps disagree: that is the hysteresis loop.
    inside = (up > lower) & (up < upper)
    assert inside.sum() > 10
    s_down_on_up = s_down.xi[::-1]
    assert np.all(s_down_on_up[inside] - s_up.xi[inside] > 0.5)


def test_jumps_sit_at_the_folds():
    up, down = _ramp()
    path = np.concatenate([up, down])
    run = sweep_with_jumps(path, EPS, THETA0)
    sol, jumps = run.solution, run.jumps
    lower, upper = folds(EPS, THETA0).omega2
    first_above = int(np.argmax(up > upper))
    first_below = up.size + int(np.argmax(down < lower))
    assert jumps.tolist() == [first_above, first_below]
    # Continuous everywhere else: neighbouring states differ by what the step in omega^2 gives.
    dxi = np.abs(np.diff(sol.xi))
    smooth = np.ones(dxi.size, dtype=bool)
    smooth[jumps - 1] = False
    assert dxi[smooth].max() < 0.1 < dxi[~smooth].min()
    np.testing.assert_allclose(sol.omega2, path, rtol=1e-12)


def test_monotone_branch_sweep_is_the_solve_and_never_jumps():
    path = np.concatenate([np.linspace(0.01, 30.0, 40), np.linspace(30.0, 0.01, 40)])
    run = sweep_with_jumps(path, 0.5, 0.3)
    sol, jumps = run.solution, run.jumps
    assert jumps.size == 0
    ref = hairbed.solve(path, 0.5, 0.3)
    np.testing.assert_allclose(sol.xi, ref.xi, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(sol.tip_deflection, ref.tip_deflection, rtol=1e-10, atol=1e-12)


def test_start_selects_the_initial_state_inside_the_window():
    w = np.array([1.2])
    low = sweep(w, EPS, THETA0, root="low")
    high = sweep(w, EPS, THETA0, root="high")
    np.testing.assert_allclose(low.xi, hairbed.solve(1.2, EPS, THETA0, root="low").xi, rtol=1e-10)
    np.testing.assert_allclose(
        high.xi, hairbed.solve(1.2, EPS, THETA0, root="high").xi, rtol=1e-10
    )


def test_strong_forcing_and_empty_path():
    sol = sweep([1.0, 300.0, 5e3], 0.5, 0.0)
    ref = hairbed.solve(np.array([1.0, 300.0, 5e3]), 0.5, 0.0)
    np.testing.assert_allclose(sol.tip_height, ref.tip_height, rtol=1e-10)
    # No forcing: the undeformed hair, h1 = cos(theta0) (theory.md §4).
    rest = sweep([0.0, 1e5], 0.5, -0.3)
    assert rest.tip_height[0] == pytest.approx(np.cos(-0.3), rel=1e-14)
    assert rest.omega2[1] == pytest.approx(1e5, rel=1e-12)
    run = sweep_with_jumps(np.empty(0), 0.5, 0.0)
    sol, jumps = run.solution, run.jumps
    assert np.shape(sol.xi) == (0,) and jumps.size == 0


@pytest.mark.parametrize(
    "call",
    [
        lambda: sweep(np.ones((2, 2)), 0.5, 0.0),
        lambda: sweep([1.0, -1.0], 0.5, 0.0),
        lambda: sweep([1.0], np.array([0.5, 0.6]), 0.0),
        lambda: sweep([1.0], 0.5, 0.0, root="mid"),
        lambda: sweep([1.0], 1.5, 0.0),
    ],
)
def test_invalid_input_raises(call):
    with pytest.raises(ValueError):
        call()


def test_sweep_reports_the_true_number_of_roots():
    """n_roots counts every physical state at each omega^2, as solve does (3 in a window)."""
    path = np.linspace(0.3, 0.7, 9)
    s = sweep(path, 0.95, -1.2)
    assert s.n_roots.tolist() == hairbed.solve(path, 0.95, -1.2).n_roots.tolist()
    assert s.n_roots.tolist() == [1, 1, 1, 1, 3, 3, 1, 1, 1]


def test_sweep_marks_direction_jumps_and_stability():
    up_down = np.concatenate([np.linspace(0.8, 1.6, 9), np.linspace(1.6, 0.8, 9)])
    run = sweep_with_jumps(up_down, 0.9, -1.5)
    assert run.direction.tolist() == [0] + [1] * 8 + [0] + [-1] * 8
    assert np.flatnonzero(run.jumped).tolist() == run.jumps.tolist() == [7, 16]
    assert run.stable.all()
    # the states followed are the stable ones of the relaxation dynamics (independent check)
    inside = np.flatnonzero(run.solution.n_roots == 3)
    assert inside.size > 0
    assert bool(np.all(hairbed.stability.is_stable(run.solution[inside])))
