"""hairbed.solve_loaded against the independent mpmath reference (issue 20's accuracy target).

``tests/data/loaded_mpmath.json`` is written by ``tests/reference/generate_loaded.py`` (mpmath
only, sharing no code with the solver; its checks are in the file's ``checks``). Every state of
every case is compared: the tip values, the base curvature, the loads W and Pi at the state and
the shape (x, z, theta) at s = 1/4, 1/2, 3/4, each within ``LOADED_REFERENCE_ATOL`` (absolute;
relative to the value where it exceeds 1, as for W = 1e4). Where a case has several states, the
solver's states are those of ``root="low"``, ``"mid"``, ``"high"`` in order of tip height (the
pi = 0 windows), or of :func:`hairbed.solve_loaded_all` (with a finer scan near a fold, where
the two states about to merge lie closer than its default scan cell). The folds of the file's
two loaded windows are compared with those of :func:`hairbed.continue_loaded`.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest
from conftest import DATA
from tolerances import LOADED_IDENTITY_RTOL, LOADED_REFERENCE_ATOL

import hairbed

PATH = DATA / "loaded_mpmath.json"
DATA_ = json.loads(PATH.read_text())
CASES: list[dict[str, Any]] = DATA_["cases"]
FOLDS: list[dict[str, Any]] = DATA_.get("folds", [])
SCALARS = {
    "tip_height": "tip_height",
    "tip_deflection": "tip_deflection",
    "tip_angle": "tip_angle",
    "base_curvature": "base_curvature",
    "W": "tip_load",
    "Pi": "distributed_load",
}


def _ids(case: dict[str, Any]) -> str:
    drive = f"pi={case['pi']}" if case["drive"] == "pressure" else f"q={case['q']}"
    return (
        f"{case['label']}:{drive},omega2={case['omega2']},eps={case['eps']},th0={case['theta0']}"
    )


def _kwargs(case: dict[str, Any]) -> dict[str, Any]:
    kw: dict[str, Any] = {"omega2": case["omega2"], "eps": case["eps"], "theta0": case["theta0"]}
    if case["drive"] == "pressure":
        kw["pi"] = case["pi"] or 0.0
    else:
        kw["q"] = case["q"]
    return kw


def _states(case: dict[str, Any]) -> list[Any]:
    kw = _kwargs(case)
    count = len(case["states"])
    for num_scan in (64, 1000, 10000):  # near a fold the two close roots need a fine scan
        found = hairbed.solve_loaded_all(**kw, num_scan=num_scan)
        if len(found) == count:
            return found
    if count == 1:
        return [hairbed.solve_loaded(**kw)]
    assert count == 3, "a window with more than three states needs solve_loaded_all"
    return [hairbed.solve_loaded(**kw, root=r) for r in ("low", "mid", "high")]


def _close(got: float, want: float) -> bool:
    return abs(got - want) <= LOADED_REFERENCE_ATOL * max(1.0, abs(want))


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_every_state_of_the_reference(case):
    states = _states(case)
    assert len(states) == len(case["states"])
    for st, ref in zip(states, case["states"]):
        assert st.status == 0, st.message
        for key, name in SCALARS.items():
            assert _close(getattr(st, name), float(ref[key])), (key, getattr(st, name), ref[key])
        shape = ref["shape"]
        _, x, z, theta = st.shape(np.array(shape["s"], dtype=float))
        for got, key in ((x, "x"), (z, "z"), (theta, "theta")):
            want = np.array(shape[key], dtype=float)
            assert np.all(np.abs(got - want) <= LOADED_REFERENCE_ATOL), key
        if ref.get("stable") is not None and st.stable is not None:
            assert st.stable == ref["stable"]
        h = st.tip_height
        rhs = st.tip_load * h + 0.5 * st.distributed_load * h * h
        assert abs(st.base_curvature - rhs) <= LOADED_IDENTITY_RTOL * max(1, abs(rhs))


def test_the_reference_is_wide_enough():
    """At least 19 states, pi = 0 windows with all their states, W of 100 or more."""
    n_states = sum(len(c["states"]) for c in CASES)
    assert n_states >= 19
    assert any(len(c["states"]) == 3 for c in CASES)
    assert max(float(s["W"]) for c in CASES for s in c["states"]) >= 100.0


def _fold_windows() -> list[tuple[dict[str, Any], list[dict[str, Any]]]]:
    """The reference folds grouped by window (same drive and fixed inputs)."""
    groups: dict[tuple[Any, ...], list[dict[str, Any]]] = {}
    for f in FOLDS:
        key = (f["drive"], f["parameter"], f["omega2"], f["pi"], f["q"], f["eps"], f["theta0"])
        groups.setdefault(key, []).append(f)
    return [(g[0], g) for g in groups.values()]


@pytest.mark.parametrize(
    ("first", "folds"), _fold_windows(), ids=lambda v: v["drive"] if isinstance(v, dict) else ""
)
def test_folds_of_the_reference_windows(first, folds):
    values = sorted(float(f["value"]) for f in folds)
    kw: dict[str, Any] = {"eps": first["eps"], "theta0": first["theta0"]}
    start, stop = 0.5 * values[0], 2.0 * values[-1]
    if first["parameter"] == "omega2":
        kw.update(omega2=start, pi=first["pi"], parameter="omega2")
    else:
        kw.update(omega2=first["omega2"], q=start)
    branch = hairbed.continue_loaded(**kw, stop=stop)
    assert branch.status == 0
    assert branch.folds.shape == (len(folds), 2)
    got = branch.folds[np.argsort(branch.folds[:, 0])]
    for (value, h), ref in zip(got, sorted(folds, key=lambda f: float(f["value"]))):
        assert value == pytest.approx(float(ref["value"]), rel=LOADED_REFERENCE_ATOL)
        assert h == pytest.approx(float(ref["tip_height"]), abs=1e-7)
