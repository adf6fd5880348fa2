"""hairbed.design: the linear range followed by Newton's method against the full scan.

:class:`hairbed.design._linear_range.LinearRangeTracker` finds the end of a pillar's linear
range by Newton's method from the root of a nearby pillar; the reference is
:meth:`hairbed.Pillar.linear_range` of each pillar on its own (a grid of inverse states from
rest and a bracketed root search), an independent path.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hairbed import Pillar
from hairbed import design as D
from hairbed.design._linear_range import LinearRangeTracker

AGREE = 1e-10


def _pillar(**kw: float) -> Pillar:
    base = dict(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=0.1, density=1000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Pillar(**{**base, **kw})  # type: ignore[arg-type]


def _nearby(seed: int, count: int, tilt: float) -> list[Pillar]:
    rng = np.random.default_rng(seed)
    return [
        _pillar(
            length=500e-6 * (1.0 + 0.05 * rng.standard_normal()),
            radius=25e-6 * (1.0 + 0.05 * rng.standard_normal()),
            youngs_modulus=1e6 * (1.0 + rng.random()),
            base_angle=tilt + 0.01 * rng.standard_normal(),
        )
        for _ in range(count)
    ]


@pytest.mark.parametrize(("rtol", "tilt"), [(0.05, 0.0), (0.01, 0.3), (0.1, -0.2)])
def test_newton_root_is_the_scan_root(rtol: float, tilt: float) -> None:
    tracker = LinearRangeTracker(rtol)
    pillars = _nearby(int(rtol * 1000), 8, tilt)
    for p in pillars:
        tau, _ = tracker(p)
        ref = p.linear_range(rtol)
        assert ref.success
        assert tau == pytest.approx(ref.wall_shear_stress, rel=AGREE, abs=0.0)
    # the first pillar is scanned, the rest followed by Newton's method
    assert tracker.scans >= 1
    assert tracker.newton >= len(pillars) - 2


def test_newton_state_is_the_root_state() -> None:
    tracker = LinearRangeTracker(0.05)
    first, second = _nearby(7, 2, 0.0)
    tracker(first)
    tau, state = tracker(second)
    assert state is not None  # from Newton's method, with its state last in the batch
    lam = float(np.asarray(state.forcing).reshape(-1)[-1])
    assert lam == pytest.approx(tau * second.forcing_per_stress, rel=1e-15)
    x1 = float(np.asarray(state.tip_deflection).reshape(-1)[-1])
    assert x1 * second.length == pytest.approx(second.tip_deflection(tau), rel=1e-12)


def test_far_pillar_is_scanned_again() -> None:
    tracker = LinearRangeTracker(0.05)
    tracker(_pillar(base_angle=0.0))
    tracker(_pillar(base_angle=0.4))  # |d theta0| > NEIGHBOUR_DISTANCE: no neighbour
    assert tracker.scans == 2 and tracker.newton == 0


def test_quantity_value_is_the_scan_value() -> None:
    q = D.linear_range(0.05)
    for p in _nearby(3, 4, 0.0):
        assert q(p) == pytest.approx(p.linear_range(0.05).wall_shear_stress, rel=AGREE, abs=0.0)
    assert q._tracker.newton >= 2  # type: ignore[attr-defined]


def test_follow_false_scans_every_pillar() -> None:
    tracker = LinearRangeTracker(0.05, follow=False)
    for p in _nearby(5, 3, 0.0):
        tau, state = tracker(p)
        assert state is None
        assert tau == p.linear_range(0.05).wall_shear_stress
    assert tracker.scans == 3 and tracker.newton == 0
