"""The porous bed's branch along its tip deflection and its folds (theory.md §13)."""

from __future__ import annotations

import numpy as np
import pytest

import hairbed
from hairbed.branches import bistable_window
from hairbed.porous_curves import porous_branch


@pytest.fixture(scope="module")
def branch():  # type: ignore[no-untyped-def]
    return porous_branch(0.95, -1.2, kappa=1e-4, num=60)


def test_the_folds_bound_the_window_of_three_states(branch) -> None:  # type: ignore[no-untyped-def]
    low, high = branch.window
    assert branch.fold_kind == ("upper", "lower")
    for w, count in ((low * (1 + 1e-4), 3), (high * (1 - 1e-4), 3), (low * (1 - 1e-3), 1),
                     (high * (1 + 1e-3), 1)):  # fmt: skip
        states = hairbed.solve_porous_all(w, 0.95, -1.2, kappa=1e-4, num_scan=256)
        assert len(states) == count, (w, [s.tip_height for s in states])


def test_stability_agrees_with_the_frozen_gap_criterion(branch) -> None:  # type: ignore[no-untyped-def]
    """solve_porous_all's stable (dG/dh1 < 0 of the frozen gap) against the branch's rising
    omega2(x1), at the window's middle."""
    w = float(np.mean(branch.window))
    for st in hairbed.solve_porous_all(w, 0.95, -1.2, kappa=1e-4):
        i = np.searchsorted(branch.tip_deflection, st.tip_deflection)
        rising = branch.omega2[i] > branch.omega2[i - 1]
        assert rising == st.stable


def test_thin_bed_window_tends_to_the_dense_closed_forms() -> None:
    """kappa -> 0: the window's folds tend to the paper's (branches.bistable_window, the
    closed form), the difference ~ sqrt(kappa)."""
    dense = bistable_window(0.95, -1.2)
    diffs = []
    kappas = np.array([1e-3, 1e-4, 1e-5])
    for k in kappas:
        b = porous_branch(0.95, -1.2, kappa=float(k), num=30)
        diffs.append(abs(b.window[1] - float(dense.upper)))
    rates = np.log(np.array(diffs[1:]) / np.array(diffs[:-1])) / np.log(kappas[1:] / kappas[:-1])
    # measured 0.52, 0.506 (the upper fold 0.643, 0.589, 0.572 against the dense 0.565)
    assert np.all(np.abs(rates - 0.5) < 0.04), rates


def test_a_single_state_bed_has_no_fold() -> None:
    b = porous_branch(0.5, 0.3, kappa=1e-2, num=20)
    assert b.window is None and b.fold_kind == ()
    assert np.all(b.stable) and np.all(np.diff(b.omega2) > 0)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"eps": 1.0}, "eps"),
        ({"theta0": 2.0}, "theta0"),
        ({"kappa": 0.0}, "kappa"),
        ({"kappa": float("nan")}, "kappa"),
        ({"gamma": 1.5}, "gamma"),
        ({"x1_max": 1.0}, "x1_max"),
        ({"x1_max": -0.9}, "x1_max"),
        ({"num": 3}, "num"),
        ({"eps": [0.5, 0.6]}, "eps"),
    ],
)
def test_bad_inputs_name_the_parameter(kw: dict, match: str) -> None:
    args = {"eps": 0.5, "theta0": 0.3, "kappa": 1e-2, **kw}
    with pytest.raises(ValueError, match=match):
        porous_branch(**args)
