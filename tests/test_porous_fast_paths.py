"""The porous solver's shortcuts give what the full path gives.

``_core.porous._plain_scalars`` lets plain scalars past the array checks: every scalar it
accepts must be accepted by the full checks with the same values, and every scalar the full
checks refuse must be refused with the same message. The N = 16 first level of a call
(``_QUICK_LADDER``) must give the states of the plain ladder to the tolerance.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import hairbed
from hairbed._core import porous

VALUES = {
    "omega2": [0.0, 2.0, -3, 1e300, math.nan, math.inf, 10**400],
    "eps": [0.0, 0.5, 1.0, -0.1, np.float64(0.3), math.nan],
    "theta0": [0.0, -1.2, math.pi / 2, 1.5707963267948966, True],
    "kappa": [1.0, 1e-6, 0.0, -1.0, math.inf],
    "gamma": [1.0, 0.5, 0.0, 1.5],
    "load": [0.0, 1.0, math.nan],
}


def _full(drive, *args):
    """The full checks: the same values given as one-element arrays, reshaped back."""
    w, e, t0, k, g, ld = (
        np.array([v], dtype=object) if v is True else np.array([v]) for v in args
    )
    kw = {"q": ld} if drive == "flow" else {"pi": ld}
    try:
        _, _, arrays = porous._check(w, e, t0, k, g, kw.get("pi"), kw.get("q"))
    except (ValueError, TypeError) as exc:
        return type(exc), str(exc).replace(" (first at index 0)", "")
    return tuple(float(a.reshape(-1)[0]) for a in arrays)


def _fast(drive, *args):
    kw = {"q": args[5]} if drive == "flow" else {"pi": args[5]}
    try:
        _, _, arrays = porous._check(*args[:5], kw.get("pi"), kw.get("q"))
    except (ValueError, TypeError) as exc:
        return type(exc), str(exc).replace(" (first at index 0)", "")
    assert all(a.shape == () and a.dtype == np.float64 for a in arrays)
    return tuple(float(a) for a in arrays)


@pytest.mark.parametrize("drive", ["pressure", "flow"])
def test_plain_scalars_agree_with_the_full_checks(drive):
    accepted = refused = 0
    for args in itertools.product(*VALUES.values()):
        fast, full = _fast(drive, *args), _full(drive, *args)
        if isinstance(full[0], float):
            assert fast == full, args
            accepted += 1
        else:
            assert fast[0] is full[0] and fast[1] == full[1], (args, fast, full)
            refused += 1
    assert accepted > 50 and refused > 1000


def test_plain_scalar_states_equal_array_states():
    st = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=1.0, gamma=0.657)
    arr = hairbed.solve_porous(np.array([2.0]), 0.5, 0.3, kappa=np.array([1.0]), gamma=0.657)
    assert st.status == 0
    assert st.tip_deflection == float(arr.tip_deflection[0])
    assert st.wall_stress == float(arr.wall_stress[0])


@pytest.mark.parametrize("kw", [{}, {"pi": 1.0}, {"q": 0.3}])
def test_the_first_level_of_16_keeps_the_states(kw):
    kap = np.geomspace(1e-3, 1e3, 40)
    t0 = np.linspace(-0.4, 0.4, 40)
    quick = hairbed.solve_porous(2.0, 0.5, t0, kappa=kap, gamma=0.657, **kw)
    code = 1 if "q" in kw else 0
    _, _, arrays = porous._check(2.0, 0.5, t0, kap, 0.657, kw.get("pi"), kw.get("q"))
    flat = tuple(np.ascontiguousarray(a).reshape(-1) for a in arrays)
    out, _, _ = porous._run(code, flat, np.full(kap.size, np.nan), porous.LADDER, 1e-12)
    assert np.all(quick.status == 0)
    assert np.any(quick.num == 16)  # the shortcut is taken somewhere ...
    assert np.all(out[0] == 0) and np.all(out[2] >= 32)
    # ... and gives the plain ladder's state to the tolerance
    assert np.max(np.abs(quick.tip_deflection - out[4])) < 1e-11
    assert np.max(np.abs(quick.wall_stress - out[10]) / np.maximum(1.0, np.abs(out[10]))) < 1e-11


def test_a_load_that_lays_the_hair_flat_has_no_state_at_once():
    """q = -1.1e13 (a fuzz case): every frozen gap's state reaches pi/2 at the first degree;
    solve_porous_all says so (status -8) without climbing the ladder at every gap (20 s
    before), and solve_porous's rescue keeps its own failure."""
    import hairbed

    states = hairbed.solve_porous_all(0.5, 0.5, 0.1, kappa=0.1, q=-1.1e13)
    assert len(states) == 1 and int(states[0].status) == -8
    assert "pi/2" in states[0].message or "wall" in states[0].message
    one = hairbed.solve_porous(0.5, 0.5, 0.1, kappa=0.1, q=-1.1e13)
    assert int(one.status) < 0
