"""The porous bed against its independent mpmath reference (issue 29).

``tests/data/porous_mpmath.json`` is written by ``tests/reference/generate_porous.py``, which
imports nothing from hairbed: the model integrated from its equations by Taylor-series
shooting and by a second method, the two agreeing per state (checked in
tests/test_porous_reference_data.py). Every stored state, every drive, every state of its
windows, is compared here with the collocation.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import hairbed

DATA = json.loads((Path(__file__).parent / "data" / "porous_mpmath.json").read_text())
STATES = DATA["states"]
TOL = 1e-10
#: reference field -> PorousState field
FIELDS = {
    "h1": "tip_height",
    "x1": "tip_deflection",
    "theta1": "tip_angle",
    "base_curvature": "base_curvature",
    "Q0": "wall_stress",
    "Q1": "tip_stress",
    "w1": "tip_velocity",
    "pi_value": "pi",
    "drag_x": "drag_x",
    "drag_z": "drag_z",
}


def _kwargs(rec: dict[str, Any]) -> dict[str, Any]:
    kw: dict[str, Any] = {"kappa": rec["kappa"], "gamma": rec["gamma"]}
    if rec["drive"] == "pressure":
        kw["pi"] = rec["pi"]
    elif rec["drive"] == "flow":
        kw["q"] = rec["q"]
    return kw


def _name(rec: dict[str, Any]) -> str:
    return f"{rec['job']}-{rec['state_index']}"


def test_coverage_of_the_reference() -> None:
    """At least 40 states over kappa 1e-4..1e4, three drives, theta0 to +-1.2, eps to 0.95,
    and windows of several states."""
    assert len(STATES) >= 40
    kappas = [r["kappa"] for r in STATES]
    assert min(kappas) <= 1e-4 and max(kappas) >= 1e4
    assert {r["drive"] for r in STATES} == {"wall", "pressure", "flow"}
    assert min(r["theta0"] for r in STATES) <= -1.2 and max(r["theta0"] for r in STATES) >= 1.2
    assert max(r["eps"] for r in STATES) >= 0.95
    assert any(r["states_at_load"] >= 2 for r in STATES)


@pytest.mark.parametrize("rec", STATES, ids=_name)
def test_state_agrees_with_the_reference(rec: dict[str, Any]) -> None:
    kw = _kwargs(rec)
    args = (rec["omega2"], rec["eps"], rec["theta0"])
    if rec["states_at_load"] == 1:
        st = hairbed.solve_porous(*args, **kw)
    else:  # one of a window's states: the one of its tip height
        found = hairbed.solve_porous_all(*args, **kw)
        assert len(found) == rec["states_at_load"]
        st = min(found, key=lambda s: abs(s.tip_height - float(rec["h1"])))
    assert st.status == 0, st.message
    worst = 0.0
    for ref_name, name in FIELDS.items():
        ref = float(rec[ref_name])
        got = float(getattr(st, name))
        worst = max(worst, abs(got - ref) / max(1.0, abs(ref)))
    assert worst < TOL, (worst, rec)
    if rec.get("q_value") is not None and rec["drive"] != "flow":
        pass  # the flux of the pressure drives is checked in SI (test_porous_si)
    assert abs(float(st.max_angle) - float(rec["max_abs_theta"])) < 1e-9


def test_windows_hold_every_state() -> None:
    """Each window of the reference: solve_porous_all finds as many states, each within TOL."""
    windows = {}
    for rec in STATES:
        if rec["states_at_load"] > 1:
            windows.setdefault(rec["job"], []).append(rec)
    assert len(windows) >= 2
    for recs in windows.values():
        rec = recs[0]
        found = hairbed.solve_porous_all(rec["omega2"], rec["eps"], rec["theta0"], **_kwargs(rec))
        got = np.sort([s.tip_height for s in found])
        ref = np.sort([float(r["h1"]) for r in recs])
        np.testing.assert_allclose(got, ref, atol=TOL)
