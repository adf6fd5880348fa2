"""The porous bed's inverse: the wall forcing from a tip deflection (issue 29)."""

from __future__ import annotations

import numpy as np
import pytest

import hairbed
from hairbed.inverse import porous_state_from_tip_deflection


def test_round_trip_over_kappa_and_forcing() -> None:
    """Forward then inverse gives the forcing back, from a thin bed to a sparse one."""
    omega2 = np.array([0.1, 2.0, 20.0, 200.0])
    kappa = np.array([[1e-4], [1e-2], [1.0], [1e3]])
    st = hairbed.solve_porous(omega2, 0.5, 0.3, kappa=kappa, gamma=0.66)
    assert np.all(st.status == 0)
    inv = porous_state_from_tip_deflection(st.tip_deflection, 0.5, 0.3, kappa=kappa, gamma=0.66)
    assert np.all(inv.status == 0)
    np.testing.assert_allclose(inv.omega2, np.broadcast_to(omega2, (4, 4)), rtol=1e-9)
    np.testing.assert_allclose(inv.tip_height, st.tip_height, atol=1e-12)


def test_a_tip_deflection_picks_one_state_of_a_window() -> None:
    """Inside a window of three states the tip deflection tells them apart."""
    states = hairbed.solve_porous_all(0.51, 0.95, -1.2, kappa=1e-4)
    assert len(states) == 3
    x1 = np.array([s.tip_deflection for s in states])
    inv = porous_state_from_tip_deflection(x1, 0.95, -1.2, kappa=1e-4)
    assert np.all(inv.status == 0)
    np.testing.assert_allclose(inv.omega2, 0.51, rtol=1e-10)
    np.testing.assert_allclose(inv.tip_height, [s.tip_height for s in states], atol=1e-11)


def test_rest_and_bad_deflections() -> None:
    rest = porous_state_from_tip_deflection(np.sin(0.3), 0.5, 0.3, kappa=1.0)
    assert rest.status == 0 and abs(rest.omega2) < 1e-12
    with pytest.raises(ValueError, match=r"x1 must lie in \[sin\(theta0\), 1\)"):
        porous_state_from_tip_deflection(1.0, 0.5, 0.3, kappa=1.0)
    with pytest.raises(ValueError, match="kappa"):
        porous_state_from_tip_deflection(0.5, 0.5, 0.3, kappa=-1.0)
