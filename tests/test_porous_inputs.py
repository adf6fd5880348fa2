"""The porous bed's inputs, roots and states (issue 29): clear errors, every state."""

from __future__ import annotations

import numpy as np
import pytest

import hairbed


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"kappa": 0.0}, r"kappa must lie in \(0, inf\), got 0.0"),
        ({"kappa": [1.0, -1.0]}, r"kappa must lie in \(0, inf\), got -1.0 \(first at index 1\)"),
        ({"kappa": np.nan}, "kappa"),
        ({"kappa": 1.0, "gamma": 1.5}, r"gamma must lie in \(0, 1\]"),
        ({"kappa": 1.0, "gamma": 0.0}, r"gamma must lie in \(0, 1\]"),
        ({"kappa": 1.0, "eps": 1.0}, r"eps must lie in \[0, 1\)"),
        ({"kappa": 1.0, "theta0": 1.6}, r"theta0 must lie in \(-pi/2, pi/2\)"),
        ({"kappa": 1.0, "pi": 1.0, "q": 1.0}, "at most one of pi"),
        ({"kappa": 1.0, "eps": 0.0, "pi": 1.0}, "pi needs eps > 0"),
        ({"kappa": 1.0, "eps": 0.0, "q": 1.0}, "q needs eps > 0"),
        ({"kappa": 1.0, "root": "middle"}, "root"),
        ({"kappa": 1.0, "omega2": "a"}, "omega2"),
    ],
)
def test_bad_inputs_name_the_parameter(kw: dict, match: str) -> None:
    args = {"omega2": 1.0, "eps": 0.5, "theta0": 0.0, **kw}
    with pytest.raises((ValueError, TypeError), match=match):
        hairbed.solve_porous(args.pop("omega2"), args.pop("eps"), args.pop("theta0"), **args)


def test_kappa_is_required() -> None:
    with pytest.raises(TypeError, match="kappa"):
        hairbed.solve_porous(1.0, 0.5)  # type: ignore[call-arg]


def test_shapes_broadcast_and_empty_inputs() -> None:
    st = hairbed.solve_porous([[1.0], [2.0]], 0.5, [0.1, 0.2, 0.3], kappa=0.1)
    assert np.shape(st.tip_deflection) == (2, 3)
    assert np.all(st.status == 0)
    empty = hairbed.solve_porous(np.array([]), 0.5, kappa=1.0)
    assert np.shape(empty.tip_deflection) == (0,)
    # an element alone gives the same state as in the batch
    one = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=0.1)
    assert one.tip_deflection == st.tip_deflection[1, 2]
    assert isinstance(one.tip_deflection, float)


def test_window_roots_and_stability() -> None:
    """An upstream tilt in a tight channel: three states at kappa = 1e-4 (the dense bed's
    window, slightly moved), low and high stable, the middle one not; the window closes by
    kappa = 1e-3; root picks each, and "low" is the least deformed (the lowest tip)."""
    states = hairbed.solve_porous_all(0.51, 0.95, -1.2, kappa=1e-4)
    assert [s.stable for s in states] == [True, False, True]
    heights = [s.tip_height for s in states]
    assert heights == sorted(heights)
    for root, st in zip(("low", "mid", "high"), states):
        one = hairbed.solve_porous(0.51, 0.95, -1.2, kappa=1e-4, root=root)
        assert one.status == 0
        assert abs(one.tip_height - st.tip_height) < 1e-12
    assert len(hairbed.solve_porous_all(0.51, 0.95, -1.2, kappa=1e-3)) == 1
    mid = hairbed.solve_porous(0.51, 0.95, -1.2, kappa=1e-3, root="mid")
    assert mid.status == -1 and np.isnan(mid.tip_height)


def test_max_angle_is_reported_and_the_model_edge_has_a_status() -> None:
    """Every state reports its largest |theta| (the model needs it below pi/2): checked on
    the interpolated shape. Strong loads bring the tip ever closer to horizontal, never past
    it (the normal drag vanishes there); a state at or past pi/2 would be status -8."""
    st = hairbed.solve_porous(1000.0, 0.0, 1.2, kappa=[1e-2, 1.0], gamma=0.5)
    assert np.all(st.status == 0)
    _, _, _, theta = st.shape(np.linspace(0.0, 1.0, 2001))
    np.testing.assert_allclose(st.max_angle, np.max(np.abs(theta), axis=-1), atol=1e-9)
    assert np.all(st.max_angle < np.pi / 2)
    assert "outside the model" in hairbed.PorousState.__doc__
    from hairbed._core.validation import STATUS_MESSAGES

    assert "pi/2" in STATUS_MESSAGES[-8]
