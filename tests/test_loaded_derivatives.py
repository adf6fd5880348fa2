"""Derivatives of pump-driven (loaded) states: hairbed.derivatives(..., pi=|q=) (issue 20).

References: central differences of hairbed.solve_loaded with Richardson extrapolation (an
independent path: every perturbed state is solved anew), and the mpmath central differences
of tests/data/loaded_derivatives_mpmath.json (tests/reference/generate_loaded_derivatives.py,
which shares no code with the solver), on both drives, the wall at rest and moving, theta0 of
both signs, and every state of a bistable window of each drive.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from tolerances import LOADED_DERIVATIVE_FD_RTOL, LOADED_DERIVATIVE_REFERENCE_RTOL

import hairbed
from hairbed.sensitivity import LOADED_OUTPUTS, derivatives_at

DATA = Path(__file__).parent / "data" / "loaded_derivatives_mpmath.json"
FIELDS = {
    "tip_height": "tip_height",
    "tip_deflection": "tip_deflection",
    "tip_angle": "tip_angle",
    "base_curvature": "base_curvature",
    "tip_load": "W",
    "distributed_load": "Pi",
}
#: (omega2, eps, theta0, drive keyword, load, root)
CASES = [
    (0.0, 0.5, 0.3, "pi", 5.0, "low"),
    (2.0, 0.9, -1.0, "pi", 1.0, "low"),
    (2.0, 0.5, 0.3, "pi", -0.5, "low"),
    (0.0, 0.99, 1.4, "pi", 30.0, "low"),
    (0.0, 0.5, -0.5, "q", 1.0, "low"),
    (0.1, 0.5, 1.2, "q", 1.0, "low"),
    (0.4, 0.5, -0.2, "q", 1.0, "low"),
    (0.0, 0.6, -1.0, "q", 300.0, "low"),
    *((0.5, 0.95, -1.2, "pi", 0.1, r) for r in ("low", "mid", "high")),
    *((0.0, 0.8, -1.2, "q", 0.13, r) for r in ("low", "mid", "high")),
]


def _solve(args: dict[str, Any], root: str) -> hairbed.LoadedState:
    st = hairbed.solve_loaded(**args, root=root)
    assert st.success, (args, root, st.message)
    return st


def _central(args: dict[str, Any], name: str, h: float, root: str) -> dict[str, float]:
    up, down = dict(args), dict(args)
    up[name] += h
    down[name] -= h
    a, b = _solve(up, root), _solve(down, root)
    return {o: (getattr(a, o) - getattr(b, o)) / (2 * h) for o in LOADED_OUTPUTS}


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c[3]}={c[4]}-w{c[0]}-t{c[2]}-{c[5]}")
def test_against_richardson_finite_differences(case: tuple[Any, ...]) -> None:
    omega2, eps, theta0, key, load, root = case
    args = {"omega2": omega2, "eps": eps, "theta0": theta0, key: load}
    d = hairbed.derivatives(**args, root=root)
    assert d.success and d.status == 0 and isinstance(d.solution, hairbed.LoadedState)
    assert set(d) == set(LOADED_OUTPUTS) and set(d["tip_height"]) == {"omega2", "eps", key,
                                                                    "theta0"}  # fmt: skip
    for name in ("omega2", "eps", key, "theta0"):
        # near the folds of a window the higher derivatives are large: a smaller step
        h = (1e-3 if root == "low" and eps < 0.95 else 1e-4) * max(1.0, abs(args[name]))
        if name == "eps":
            h = min(h, 0.25 * (1.0 - eps))
        coarse, fine = _central(args, name, h, root), _central(args, name, h / 2, root)
        for o in LOADED_OUTPUTS:
            ref = (4.0 * fine[o] - coarse[o]) / 3.0
            got = d[o][name]
            assert abs(got - ref) <= LOADED_DERIVATIVE_FD_RTOL * max(1.0, abs(ref)), (
                name,
                o,
                got,
                ref,
            )


def _reference() -> list[dict[str, Any]]:
    return json.loads(DATA.read_text())["cases"]


def test_against_mpmath_finite_differences() -> None:
    """Every state of every case of the mpmath reference, windows with every root."""
    worst, count = 0.0, 0
    cases = _reference()
    assert {c["drive"] for c in cases} == {"pressure", "flow"}
    assert {np.sign(c["theta0"]) for c in cases} == {-1.0, 0.0, 1.0}
    assert max(len(c["states"]) for c in cases) == 3
    for case in cases:
        key = "pi" if case["drive"] == "pressure" else "q"
        args = {k: case[k] for k in ("omega2", "eps", "theta0")}
        args[key] = case[key]
        roots = ["low"] if len(case["states"]) == 1 else ["low", "mid", "high"]
        assert len(roots) == len(case["states"])
        for root, ref in zip(roots, case["states"]):
            d = hairbed.derivatives(**args, root=root)
            assert d.success, (case["label"], root)
            st = d.solution
            assert abs(st.tip_height - float(ref["tip_height"])) < 1e-10
            for o, f in FIELDS.items():
                for name, rname in (("omega2", "omega2"), ("eps", "eps"), (key, "load"),
                                    ("theta0", "theta0")):  # fmt: skip
                    r = float(ref["d"][f][rname])
                    err = abs(d[o][name] - r) / max(1.0, abs(r))
                    worst = max(worst, err)
                    count += 1
                    assert err <= LOADED_DERIVATIVE_REFERENCE_RTOL, (case["label"], root, o, name)
    assert count >= 13 * 6 * 4


def test_arrays_and_derivatives_at_agree_with_scalars() -> None:
    w = np.array([[0.0, 0.5], [1.0, 2.0]])
    d = hairbed.derivatives(w, 0.7, -0.4, q=2.0)
    st = hairbed.solve_loaded(w, 0.7, -0.4, q=2.0)
    again = derivatives_at(st)
    for o in LOADED_OUTPUTS:
        for name in ("omega2", "eps", "q", "theta0"):
            assert np.shape(d[o][name]) == (2, 2)
            assert np.array_equal(d[o][name], again[o][name])
            one = hairbed.derivatives(float(w[1, 0]), 0.7, -0.4, q=2.0)[o][name]
            assert d[o][name][1, 0] == pytest.approx(one, rel=1e-13, abs=1e-15)
    assert d.dt == {}


def test_small_load_limit_and_closed_form_at_pi_zero() -> None:
    """x1 = W/3 + Pi/8 at small loads (theta0 = 0, h1 -> 1): d x1/d pi = (1/eps - 1)/6 + 1/8;
    at pi = 0 the omega2, eps and theta0 derivatives are those of the closed form."""
    eps = 0.5
    d = hairbed.derivatives(0.0, eps, pi=1e-9)
    assert d["tip_deflection"]["pi"] == pytest.approx((1 / eps - 1) / 6 + 1 / 8, rel=1e-8)
    d = hairbed.derivatives(0.0, eps, q=1e-9)  # W = q/u^2, Pi = 2 eps q/u^3, u = 1 - eps
    u = 1 - eps
    assert d["tip_deflection"]["q"] == pytest.approx(1 / (3 * u**2) + eps / (4 * u**3), rel=1e-8)
    loaded = hairbed.derivatives(1.5, 0.6, 0.4, pi=0.0)
    closed = hairbed.derivatives(1.5, 0.6, 0.4)
    for o in ("tip_height", "tip_deflection", "tip_angle", "base_curvature"):
        for name in ("omega2", "eps", "theta0"):
            assert loaded[o][name] == pytest.approx(closed[o][name], rel=1e-10, abs=1e-12)


def test_edges_and_bad_input() -> None:
    d = hairbed.derivatives(0.3, 0.0, pi=0.0)  # W has (pi/2)/eps: infinite at eps = 0
    assert d.success and np.isinf(d["tip_deflection"]["pi"]) and d["tip_deflection"]["pi"] > 0
    assert np.isfinite(d["tip_deflection"]["omega2"])
    d = hairbed.derivatives(0.51, 0.95, -1.2, pi=0.0, root="mid")  # the wall problem's window
    assert d.success
    none = hairbed.derivatives([0.3, 5.0], 0.95, -1.2, pi=0.1, root="mid")  # no mid at 5
    assert list(none.status) == [-1, -1]
    assert np.isnan(none["tip_deflection"]["pi"][1])
    with pytest.raises(ValueError, match="root="):
        hairbed.derivatives(0.3, 0.5, pi=1.0, sign=-1)
    with pytest.raises(ValueError, match="both"):
        hairbed.derivatives(0.3, 0.5, pi=1.0, q=1.0)
    with pytest.raises(ValueError, match="eps"):
        hairbed.derivatives(0.3, 0.0, pi=1.0)
    with pytest.raises(TypeError, match="LoadedState"):
        derivatives_at(3.0)
