"""Bad input to the pillar solver (issue 21) gets one clear error naming the parameter."""

from __future__ import annotations

import numpy as np
import pytest

import hairbed


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: hairbed.solve_pillar(np.nan), r"forcing must be finite"),
        (lambda: hairbed.solve_pillar([1.0, np.inf]), r"forcing .*index 1"),
        (lambda: hairbed.solve_pillar(1.0, 1.6), r"theta0 must lie in \(-pi/2, pi/2\)"),
        (lambda: hairbed.solve_pillar(1.0, gamma=0.0), r"gamma must lie in \(0, 1\]"),
        (lambda: hairbed.solve_pillar(1.0, gamma=[0.5, 1.5]), r"gamma .*index 1"),
        (lambda: hairbed.solve_pillar(1.0, profile="plug"), r"profile must be one of"),
        (lambda: hairbed.solve_pillar(1.0, profile="poiseuille"), r"needs height_ratio"),
        (
            lambda: hairbed.solve_pillar(1.0, profile="poiseuille", height_ratio=1.5),
            r"height_ratio",
        ),
        (lambda: hairbed.solve_pillar(1.0, profile=lambda z: 1.0), r"shape of z"),
        (lambda: hairbed.solve_pillar(1.0, profile=lambda z: z / 0.0), r"must be finite"),
        (lambda: hairbed.solve_pillar(1.0, profile=lambda z: 1 / (z - 0.5)), r"not resolved"),
        (lambda: hairbed.solve_pillar(1.0, profile=lambda z: np.abs(z - 0.3)), r"not resolved"),
        (lambda: hairbed.solve_pillar(1.0, profile=lambda z: z.foo), r"callable raised"),
        (lambda: hairbed.solve_pillar(1.0, num=4), r"num"),
        (lambda: hairbed.solve_pillar(1.0, rtol=-1.0), r"rtol"),
        (lambda: hairbed.solve_pillar([1.0, 2.0], [0.0, 0.1, 0.2]), r"broadcast|shape"),
        (lambda: hairbed.solve_pillar_inverse(1.0), r"tip_deflection must lie in \(-1, 1\)"),
        (lambda: hairbed.solve_pillar_inverse([0.1, -1.2]), r"tip_deflection .*index 1"),
        (lambda: hairbed.continue_pillar(0.0), r"forcing_max must be non-zero"),
        (
            lambda: hairbed.gray_hancock_ratio(2.2),
            r"slenderness must lie in \[e\^1.5/2 = 2.2408, inf\), got 2.2",
        ),
    ],
)
def test_clear_errors(call, match):
    with np.errstate(all="raise"):  # no numpy warning on the way to the message
        with pytest.raises((ValueError, TypeError), match=match):
            call()


def test_gray_hancock_ratio_formula():
    lg = np.log(40.0)
    assert hairbed.gray_hancock_ratio(20.0) == pytest.approx((lg + 0.5) / (2 * lg - 1), rel=1e-15)


def test_every_forcing_has_a_state():
    """A state for every finite forcing from 1e-8 to 1e5, either direction, at base angles to
    within 0.12 of the wall (never a NaN with status 0)."""
    lam = np.concatenate([-np.geomspace(1e-8, 1e5, 14), [0.0], np.geomspace(1e-8, 1e5, 14)])
    for t0 in (-1.45, -1.4, 0.0, 1.45):
        st = hairbed.solve_pillar(lam, t0)
        status = np.asarray(st.status)
        ok = status >= 0
        assert np.all(np.isfinite(np.asarray(st.tip_deflection)[ok]))
        assert np.all(np.isnan(np.asarray(st.tip_deflection)[~ok]))
        assert np.all(status == 0), (t0, status)


def test_scalar_and_array_agree():
    lam = np.array([0.5, 5.0, 50.0])
    st = hairbed.solve_pillar(lam, 0.2)
    for i, v in enumerate(lam):
        one = hairbed.solve_pillar(float(v), 0.2)
        assert isinstance(one.tip_deflection, float)
        # the same kernel; the scalar's closed-form start rounds apart by an ulp or so
        assert one.tip_deflection == pytest.approx(st.tip_deflection[i], rel=1e-14, abs=0)
