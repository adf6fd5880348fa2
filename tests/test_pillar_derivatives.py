"""Derivatives of pillar states: hairbed.sensitivity.derivatives_at(PillarState) (issue 21).

References: central differences of hairbed.solve_pillar with Richardson extrapolation (an
independent path: every perturbed state is solved anew, from its own start) on tilted states,
both flow directions, a tip load and the channel profiles, the signs of the branch's slope
through a snap-through window, and the linear limit dx1/dLambda = 11/120 (theory.md §12).
The mpmath reference is tests/test_pillar_derivatives_reference.py.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from tolerances import PILLAR_DERIVATIVE_FD_RTOL

import hairbed
from hairbed.sensitivity import PILLAR_INPUTS, PILLAR_OUTPUTS, derivatives_at

#: (forcing, theta0, gamma, tip_load, profile, height_ratio)
CASES = [
    (3.0, 0.3, 0.6, 0.0, "sublayer", None),
    (-20.0, 0.5, 0.5, 0.7, "sublayer", None),
    (400.0, -1.0, 0.55, 0.0, "sublayer", None),
    (50.0, -0.8, 0.7, 0.0, "poiseuille", 0.6),
    (8.0, 1.2, 0.45, 0.0, "poiseuille", 1.0),
    (1e3, 1.0, 0.55, 0.0, "couette", 0.5),
]


def _state(args: dict[str, Any]) -> hairbed.PillarState:
    st = hairbed.solve_pillar(**args)
    assert st.success, (args, st.message)
    return st


def _central(args: dict[str, Any], name: str, h: float) -> dict[str, float]:
    up, down = dict(args), dict(args)
    up[name] += h
    down[name] -= h
    a, b = _state(up), _state(down)
    return {o: (getattr(a, o) - getattr(b, o)) / (2 * h) for o in PILLAR_OUTPUTS}


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[4]}-L{c[0]}-t{c[1]}-P{c[3]}")
def test_against_richardson_finite_differences(case: tuple[Any, ...]) -> None:
    lam, theta0, gamma, tip, profile, ratio = case
    args = {"forcing": lam, "theta0": theta0, "gamma": gamma, "tip_load": tip,
            "profile": profile, "height_ratio": ratio}  # fmt: skip
    d = derivatives_at(_state(args), profile=profile, height_ratio=ratio)
    assert d.success and d.status == 0 and d.dt == {}
    names = [p for p in PILLAR_INPUTS if p != "height_ratio" or ratio is not None]
    assert set(d) == set(PILLAR_OUTPUTS) and set(d["tip_height"]) == set(names)
    for name in names:
        h = 1e-3 * max(1.0, abs(args[name]))
        if name == "height_ratio":
            h = min(h, 0.25 * (1.0 - ratio)) if ratio < 1.0 else 0.0
        if name == "gamma":
            h = 1e-3
        if h == 0.0:  # L/H = 1: the channel's end, one-sided only
            continue
        coarse, fine = _central(args, name, h), _central(args, name, h / 2)
        for o in PILLAR_OUTPUTS:
            ref = (4.0 * fine[o] - coarse[o]) / 3.0
            got = d[o][name]
            assert abs(got - ref) <= PILLAR_DERIVATIVE_FD_RTOL * max(1e-3, abs(ref)), (
                name,
                o,
                got,
                ref,
            )
        if name == "forcing":  # the solver's own slope, the same derivative
            assert d["tip_deflection"]["forcing"] == pytest.approx(
                d.solution.tip_deflection_slope, rel=1e-10
            )
    if profile == "couette":  # U = z whatever L/H: no dependence at fixed Lambda
        assert all(d[o]["height_ratio"] == 0.0 for o in PILLAR_OUTPUTS)


def test_linear_limit_and_arrays() -> None:
    """dx1/dLambda -> 11/120 and dx1/dtheta0 -> 1 at rest (theta0 = 0); the drag of a
    straight pillar is Lambda/2 along x (int_0^1 z dz), its base moment Lambda/3."""
    lam = np.array([[1e-8, 0.0], [-1e-8, 1e-9]])
    st = hairbed.solve_pillar(lam, 0.0, gamma=0.5)
    d = derivatives_at(st)
    assert np.shape(d["tip_deflection"]["forcing"]) == (2, 2)
    assert np.all(d.status == 0)
    assert np.allclose(d["tip_deflection"]["forcing"], 11.0 / 120.0, rtol=1e-7, atol=0)
    assert np.allclose(d["tip_deflection"]["theta0"], 1.0, rtol=1e-7)
    assert np.allclose(d["drag_x"]["forcing"], 0.5, rtol=1e-7)
    assert np.allclose(d["base_curvature"]["forcing"], 1.0 / 3.0, rtol=1e-7)
    assert np.allclose(d["drag_x"]["tip_load"], 1.0, rtol=1e-12)
    assert np.allclose(d["base_curvature"]["tip_load"], 1.0, rtol=1e-7)  # P h1, h1 -> 1
    one = derivatives_at(hairbed.solve_pillar(float(lam[1, 1]), 0.0))
    for o in PILLAR_OUTPUTS:
        for p in d[o]:
            assert d[o][p][1, 1] == pytest.approx(one[o][p], rel=1e-12, abs=1e-15)


def test_slope_through_a_snap_through_window_has_the_branch_sign() -> None:
    """Along the branch of theta0 = -1.45 (a window: Lambda(x1) falls between its folds),
    dx1/dLambda has the sign of dx1/dLambda of the branch, is finite with status 0, and the
    other inputs' derivatives stay finite: never a NaN with status 0."""
    br = hairbed.continue_pillar(5e3, -1.45)
    assert br.folds.shape[0] >= 2
    x1 = np.linspace(0.1, 0.95, 60) * (1.0 - np.sin(-1.45)) + np.sin(-1.45)
    st = hairbed.solve_pillar_inverse(x1, -1.45)
    d = derivatives_at(st)
    good = np.asarray(d.status) == 0
    assert good.sum() >= 55
    for o in PILLAR_OUTPUTS:
        for p in d[o]:
            assert np.all(np.isfinite(d[o][p][good]))
            assert np.all(np.isnan(d[o][p][~good]))
    lam = np.asarray(st.forcing)
    branch = np.sign(np.gradient(lam, x1))  # dLambda/dx1 along the branch
    slope = np.sign(d["tip_deflection"]["forcing"])
    inner = good & (np.abs(np.gradient(lam, x1)) > 1.0)  # away from the folds
    assert np.any(branch[inner] < 0)  # the window is sampled
    assert np.all(slope[inner] == branch[inner])


def test_no_state_is_nan_with_a_status_and_a_wrong_profile_is_refused() -> None:
    st = hairbed.solve_pillar([3.0, 5.0], -1.45, root="mid")  # no three states at 3 or 5
    d = derivatives_at(st)
    assert np.all(np.asarray(st.status) < 0) and np.all(np.asarray(d.status) == -1)
    assert np.all(np.isnan(d["tip_deflection"]["forcing"]))
    st = hairbed.solve_pillar(30.0, 0.2, profile="poiseuille", height_ratio=0.8)
    with pytest.raises(ValueError, match="profile"):
        derivatives_at(st)  # solved with a Poiseuille profile, not the sublayer's
    with pytest.raises(ValueError, match="profile"):
        derivatives_at(st, profile="poiseuille", height_ratio=0.3)
    ok = derivatives_at(st, profile="poiseuille", height_ratio=0.8)
    assert ok.success and "height_ratio" in ok["tip_deflection"]
    with pytest.raises(ValueError, match="PillarState"):
        derivatives_at(hairbed.solve(1.0, 0.5), profile="couette")
    with pytest.raises(TypeError, match="PillarState"):
        derivatives_at(3.0)  # type: ignore[arg-type]


def test_callable_profile() -> None:
    """A callable profile is resolved again from the callable: the same derivatives as its
    polynomial equivalent (U = z - 0.3 z^2 is Poiseuille at L/H = 0.3, in the forcing)."""

    def prof(z: Any) -> Any:
        return z - 0.3 * z * z

    a = derivatives_at(hairbed.solve_pillar(40.0, 0.4, profile=prof), profile=prof)
    b = derivatives_at(
        hairbed.solve_pillar(40.0, 0.4, profile="poiseuille", height_ratio=0.3),
        profile="poiseuille",
        height_ratio=0.3,
    )
    assert "height_ratio" not in a["tip_height"]
    for o in PILLAR_OUTPUTS:
        for p in a[o]:
            assert a[o][p] == pytest.approx(b[o][p], rel=1e-10, abs=1e-13)
