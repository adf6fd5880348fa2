"""What simulate_pillar skips to cut its fixed costs, held to what it replaces (issue 30).

Radau IIA maps its collocation by the static state's map at the drives' last values; the
run takes that number from the closed-form start (``_forward_map``) instead of solving the
state. The reference is the solve itself (:func:`hairbed.solve_pillar`'s ``_map``): the two
must be the same number wherever the solve's forward Newton gives the state, including loads
large enough for a non-zero map, both flow directions and tip loads; for a tilt in the
snap-through range the run still solves.
"""

from __future__ import annotations

import numpy as np
import pytest

import hairbed
from hairbed._core.pillar import profile_coefficients
from hairbed.dynamics import simulate_pillar
from hairbed.dynamics._integrate import _forward_map

CASES = [
    # (Lambda, theta0, tip load, profile, L/H, map > 0); the map is 0 up to a start's tip
    # load of 9 (0.275 Lambda cos(theta0) for U = z)
    (2.0, 0.0, 0.0, "sublayer", None, False),  # 0 by the bound 3/8 Lambda sum abs(U_k) <= 9
    (30.0, 0.0, 0.0, "sublayer", None, False),  # the bound 11.25 fails; the load 8.25 <= 9
    (40.0, 0.3, 0.0, "sublayer", None, True),
    (3.0e3, -0.4, 0.0, "sublayer", None, True),
    (-5.0e4, 0.7, 2.0, "couette", 0.5, True),  # towards -x, with a tip load
    (8.0e2, -1.1, -30.0, "poiseuille", 0.7, True),
    (0.0, 0.2, 50.0, "sublayer", None, True),  # the tip load alone
    (1.0e6, 1.2, 0.0, "poiseuille", 0.3, True),
]


@pytest.mark.parametrize(("lam", "theta0", "tip", "profile", "ratio", "mapped"), CASES)
def test_the_map_without_the_solve_is_the_solves(
    lam: float, theta0: float, tip: float, profile: str, ratio: float | None, mapped: bool
) -> None:
    prof = profile_coefficients(profile, ratio)
    for num in (8, 32):
        st = hairbed.solve_pillar(
            lam, theta0, profile=profile, height_ratio=ratio, tip_load=tip, num=num
        )
        assert int(st.status) >= 0
        assert _forward_map(lam, theta0, tip, prof) == float(st._map)
    assert (float(st._map) > 0.0) == mapped


def test_a_tilt_in_the_window_range_is_left_to_the_solve() -> None:
    prof = profile_coefficients("sublayer")
    assert _forward_map(5.0, -1.3, 0.0, prof) is None  # upstream tilt, flow towards +x
    assert _forward_map(-5.0, 1.3, 0.0, prof) is None  # its mirror image
    assert _forward_map(-5.0, -1.3, 0.0, prof) is not None  # downstream: no window


def test_a_callable_drive_over_a_span_too_short_for_its_samples() -> None:
    with pytest.raises(ValueError, match=r"forcing: the run's span .* too short"):
        simulate_pillar(lambda t: np.ones_like(t), [1e12, 1e12 + 1e-3])
