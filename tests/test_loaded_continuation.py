"""hairbed.continue_loaded: pseudo-arclength continuation of loaded states (issue 20, item 2).

The folds are checked against what does not come from the continuation: at pi = 0 the closed
form's folds (``fold_parameters``, elliptic functions); for the flow drive the count of
states of ``solve_loaded_all`` just inside and just outside each fold (3 and 1). Every point
of the branch is a state (``solve_loaded_all`` at its parameter has one of its tip height),
the stability changes at each fold, and every call ends (bounded steps).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import DATA
from tolerances import LOADED_REFERENCE_ATOL

import hairbed
from hairbed._core.solver import fold_parameters


def test_folds_of_the_wall_problem_match_the_closed_form():
    eps, theta0 = 0.95, -1.2
    branch = hairbed.continue_loaded(0.3, eps, theta0, stop=0.8)
    assert branch.status == 0
    exact = hairbed.from_parameter(fold_parameters(eps, theta0), eps, theta0)
    got = branch.folds[np.argsort(branch.folds[:, 0])]
    want = np.c_[exact.omega2, exact.tip_height]
    want = want[np.argsort(want[:, 0])]
    assert got.shape == (2, 2)
    assert np.allclose(got[:, 0], want[:, 0], rtol=1e-10, atol=0)
    assert np.allclose(got[:, 1], want[:, 1], atol=1e-7, rtol=0)


def test_folds_of_a_flow_window_bracket_the_count():
    eps, theta0 = 0.9, -1.2
    branch = hairbed.continue_loaded(0.0, eps, theta0, q=0.005, stop=0.5)
    assert branch.status == 0 and branch.folds.shape == (2, 2)
    low, high = np.sort(branch.folds[:, 0])
    for q, count in ((low * 0.999, 1), (low * 1.001, 3), (high * 0.999, 3), (high * 1.001, 1)):
        assert len(hairbed.solve_loaded_all(0.0, eps, theta0, q=q, num_scan=4000)) == count, q
    # the stability flips at each fold: stable, unstable, stable along the S
    flips = np.flatnonzero(np.diff(branch.stable.astype(int)) != 0)
    assert flips.size == 2
    assert branch.stable[0] and branch.stable[-1]
    # every point is a state
    for i in range(0, branch.values.size, 5):
        found = hairbed.solve_loaded_all(0.0, eps, theta0, q=branch.values[i], num_scan=4000)
        assert min(abs(s.tip_height - branch.tip_height[i]) for s in found) <= 1e-9


def test_no_fold_in_a_monotone_range_and_bounded_steps():
    branch = hairbed.continue_loaded(0.0, 0.5, 0.0, pi=0.1, stop=50.0)
    assert branch.status == 0 and branch.folds.shape == (0, 2)
    assert np.all(np.diff(branch.values) > 0) and np.all(branch.stable)
    short = hairbed.continue_loaded(0.0, 0.5, 0.0, pi=0.1, stop=50.0, max_steps=3)
    assert short.status == -2 and short.values.size <= 4


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"omega2": [0.1, 0.2], "eps": 0.5, "stop": 1.0}, "scalar"),
        ({"omega2": 0.1, "eps": 0.5, "q": 1.0, "parameter": "pi", "stop": 1.0}, "pressure"),
        ({"omega2": 0.1, "eps": 0.5, "parameter": "speed", "stop": 1.0}, "parameter"),
        ({"omega2": 0.1, "eps": 0.5, "stop": 1.0, "ds": 0.0}, "ds"),
        ({"omega2": 0.1, "eps": 0.5, "stop": 1.0, "max_steps": 0}, "max_steps"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hairbed.continue_loaded(**kwargs)


REFERENCE = json.loads((DATA / "loaded_mpmath.json").read_text())
PRESSURE_FOLDS = [f for f in REFERENCE["folds"] if f["drive"] == "pressure"]


@pytest.mark.parametrize(("start", "ds"), [(0.3, 0.02), (0.3, 0.05), (0.4, 0.02)])
def test_the_branch_does_not_leap_past_a_fold(start, ds):
    """From starts where the corrector used to leave for a far piece of the curve past the
    lower fold (to omega2 = -2.9), the branch stays connected and finds both reference folds
    (mpmath, tests/data/loaded_mpmath.json)."""
    branch = hairbed.continue_loaded(
        start, 0.95, -1.2, pi=0.1, parameter="omega2", stop=0.8, ds=ds
    )
    assert branch.status == 0
    steps = np.hypot(np.diff(branch.values), np.diff(branch.tip_height))
    # a tangent step (at most 0.1) and a correction orthogonal to it no longer than the step
    assert np.max(steps) <= 0.1 * np.sqrt(2.0) + 1e-12
    want = sorted(float(f["value"]) for f in PRESSURE_FOLDS)
    got = np.sort(branch.folds[:, 0])
    assert got.shape == (2,)
    np.testing.assert_allclose(got, want, rtol=LOADED_REFERENCE_ATOL)


@pytest.mark.parametrize("side", ["lower", "upper"])
def test_a_reference_fold_is_met_along_the_other_parameter(side):
    """A fold is a point (omega2, pi, h1) where G = dG/dh1 = 0, whatever the parameter: with
    omega2 held at the reference's fold value (pi = 0.1), continuation in pi meets a fold at
    pi = 0.1 with the reference's tip height. Any other fold on the way is confirmed by the
    count of the scan solve_loaded_all (3 states on its window side, 1 on the other)."""
    ref = next(f for f in PRESSURE_FOLDS if f["window_side"] == side)
    omega2 = float(ref["value"])
    branch = hairbed.continue_loaded(omega2, 0.95, -1.2, pi=0.0, stop=1.0)
    assert branch.status == 0
    near = branch.folds[np.argmin(np.abs(branch.folds[:, 0] - 0.1))]
    assert near[0] == pytest.approx(0.1, rel=LOADED_REFERENCE_ATOL)
    assert near[1] == pytest.approx(float(ref["tip_height"]), abs=1e-7)
    for value, _ in branch.folds:
        if abs(value - 0.1) < 1e-6:
            continue
        counts = [
            len(hairbed.solve_loaded_all(omega2, 0.95, -1.2, pi=value + d, num_scan=4000))
            for d in (-1e-3 * abs(value), 1e-3 * abs(value))
        ]
        assert sorted(counts) == [1, 3], (value, counts)
