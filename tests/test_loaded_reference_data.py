"""The distributed-load reference data on its own: invariants, no solver.

``tests/data/loaded_mpmath.json`` (from ``tests/reference/generate_loaded.py``, mpmath only)
is the reference of issue 20's solver. These tests check what the file itself must satisfy,
without :mod:`hairbed`'s solver, so that the data can be trusted before it is used:

- layout (issue 20's interface) and digits: every number a decimal string of >= 25
  significant digits, states sorted by tip height, the shape on s = 1/4, 1/2, 3/4;
- the loads W and Pi are the drive's formulas at the tabulated tip height;
- the identity theta'(0) = W h1 + Pi h1^2/2 on every state;
- the shape is consistent with the tip values: z increases to h1, theta rises from theta0 to
  the tip angle below pi/2, and each step of x lies between ds sin(theta) at its two ends;
- the small-load limit x1 = W/3 + Pi/8 at theta0 = 0, with a remainder of order load^2;
- coverage: both drives with and without the wall moving, theta0 from -1.5 to 1.5, loads from
  1e-6 to 1e4, eps up to 0.99, the pi = 0 wall problem, and a bistable window of each drive
  with all its states (count 1, 3, ..., 3, 1 through the window; stable, unstable, stable).
"""

from __future__ import annotations

import json
from collections import Counter
from typing import Any

import pytest
from conftest import DATA
from mpmath import mp, mpf

PATH = DATA / "loaded_mpmath.json"
DATA_ = json.loads(PATH.read_text())
CASES: list[dict[str, Any]] = DATA_["cases"]
STATES = [(case, state) for case in CASES for state in case["states"]]
SCALARS = ("tip_height", "tip_deflection", "tip_angle", "base_curvature", "W", "Pi")
mp.dps = 40


def _ids(item: tuple[dict[str, Any], dict[str, Any]]) -> str:
    c, s = item
    drive = f"pi={c['pi']}" if c["drive"] == "pressure" else f"q={c['q']}"
    return f"{c['label']}:{drive},omega2={c['omega2']},eps={c['eps']},th0={c['theta0']}"


def _significant_digits(text: str) -> int:
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mantissa)


def _loads(case: dict[str, Any], h1: mpf) -> tuple[mpf, mpf]:
    eps, omega2 = mpf(case["eps"]), mpf(case["omega2"])
    u = 1 - eps * h1
    if case["drive"] == "pressure":
        p = mpf(case["pi"] or 0)
        return omega2 / u + p / 2 * (1 / eps - h1), p
    q = mpf(case["q"])
    return q / u**2 - 2 * omega2 / u, 2 * eps * q / u**3 - 6 * eps * omega2 / u**2


def test_layout():
    assert DATA_["generator"] == "tests/reference/generate_loaded.py"
    assert DATA_["dps"] >= 30 and isinstance(DATA_["checks"], str)
    for case in CASES:
        assert case["drive"] in ("pressure", "flow")
        if case["drive"] == "pressure":
            assert case["q"] is None and isinstance(case["pi"], float)
        else:
            assert case["pi"] is None and isinstance(case["q"], float)
        for key in ("omega2", "eps", "theta0"):
            assert isinstance(case[key], float)
        assert 0 < case["eps"] < 1 and -1.5 <= case["theta0"] <= 1.5
        assert isinstance(case["label"], str) and case["label"]
        assert case["states"], "every case has at least one state"
        for state in case["states"]:
            assert set(SCALARS) <= set(state) and state["stable"] in (True, False, None)
            assert state["shape"]["s"] == [0.25, 0.5, 0.75]
            texts = [state[k] for k in SCALARS]
            texts += [v for k in ("x", "z", "theta") for v in state["shape"][k]]
            assert all(len(state["shape"][k]) == 3 for k in ("x", "z", "theta"))
            for text in texts:
                assert isinstance(text, str)
                mpf(text)
                # a value that is exactly representable (Pi = pi = 1.0) has fewer digits
                assert _significant_digits(text) >= 25 or mpf(text) == float(text), text


def test_states_sorted_and_distinct():
    for case in CASES:
        h = [mpf(s["tip_height"]) for s in case["states"]]
        assert all(b - a > mpf("1e-8") for a, b in zip(h, h[1:])), case
        assert all(0 < v <= 1 for v in h)


@pytest.mark.parametrize("item", STATES, ids=[_ids(i) for i in STATES])
def test_loads_and_identity(item):
    case, state = item
    h1 = mpf(state["tip_height"])
    w, big_pi = _loads(case, h1)
    assert abs(mpf(state["W"]) - w) <= mpf("1e-25") * max(1, abs(w))
    assert abs(mpf(state["Pi"]) - big_pi) <= mpf("1e-25") * max(1, abs(big_pi))
    m = mpf(state["base_curvature"])
    assert abs(m - (w * h1 + big_pi * h1**2 / 2)) <= mpf("1e-25") * max(1, abs(m))


@pytest.mark.parametrize("item", STATES, ids=[_ids(i) for i in STATES])
def test_shape_consistent_with_tip(item):
    case, state = item
    sh = state["shape"]
    z = [mpf(0)] + [mpf(v) for v in sh["z"]] + [mpf(state["tip_height"])]
    th = [mpf(case["theta0"])] + [mpf(v) for v in sh["theta"]] + [mpf(state["tip_angle"])]
    x = [mpf(0)] + [mpf(v) for v in sh["x"]] + [mpf(state["tip_deflection"])]
    s = [mpf(0)] + [mpf(v) for v in sh["s"]] + [mpf(1)]
    # the fundamental family: theta rises from theta0 towards pi/2, z increases to h1 (under
    # strong loads the hair lies flat beyond the base layer: z = h1, theta = pi/2 to the 30
    # digits written, hence the one-digit allowance)
    ulp = mpf("1e-29")
    assert all(b >= a for a, b in zip(z, z[1:]))
    assert all(b >= a for a, b in zip(th, th[1:])) and th[-1] < mp.pi / 2 + ulp
    for k in range(4):
        ds = s[k + 1] - s[k]
        # x' = sin(theta) with theta increasing: the mean value lies between the ends
        dx = x[k + 1] - x[k]
        assert ds * mp.sin(th[k]) - ulp <= dx <= ds * mp.sin(th[k + 1]) + ulp
        assert z[k + 1] - z[k] <= ds
    assert mpf(state["base_curvature"]) > 0


def test_small_load_limit():
    """x1 = W/3 + Pi/8 at theta0 = 0, the remainder of order load^2.

    At theta0 = 0 it is even of order load^3: x1 is odd in (W, Pi) (theta -> -theta).
    The cases span loads 1e-6 to 1e-2, so the bound tests the shrinking.
    """
    small = [
        (c, s)
        for c, s in STATES
        if c["theta0"] == 0.0 and mpf(s["W"]) + abs(mpf(s["Pi"])) < mpf("0.02")
    ]
    assert len(small) >= 4
    for _case, s in small:
        load = mpf(s["W"]) + abs(mpf(s["Pi"]))
        remainder = mpf(s["tip_deflection"]) - (mpf(s["W"]) / 3 + mpf(s["Pi"]) / 8)
        assert abs(remainder) <= load**3 / 10, (load, remainder)
    loads = sorted(mpf(s["W"]) + abs(mpf(s["Pi"])) for _, s in small)
    assert loads[0] < 1e-5 and loads[-1] > 1e-3


def test_coverage_of_drives_and_ranges():
    assert len(CASES) >= 45 and len(STATES) >= 40
    kinds = Counter((c["drive"], c["omega2"] != 0) for c in CASES)
    for kind in (("pressure", False), ("pressure", True), ("flow", False), ("flow", True)):
        assert kinds[kind] >= 4, kinds
    wall = [c for c in CASES if c["drive"] == "pressure" and c["pi"] == 0.0]
    assert len(wall) >= 3
    assert min(c["theta0"] for c in CASES) == -1.5 and max(c["theta0"] for c in CASES) == 1.5
    for drive in ("pressure", "flow"):
        th = [c["theta0"] for c in CASES if c["drive"] == drive]
        assert min(th) == -1.5 and max(th) == 1.5
    assert max(c["eps"] for c in CASES) >= 0.99
    w = [mpf(s["W"]) for _, s in STATES]
    big_pi = [abs(mpf(s["Pi"])) for _, s in STATES if mpf(s["Pi"]) != 0]
    assert min(w) <= 1e-6 and max(w) >= 1e4
    assert min(big_pi) <= 1e-6 and max(big_pi) >= 1e4


def test_windows_have_every_state():
    """A bistable window of each loaded drive, crossed on a grid: 1, 3, ..., 3, 1 states."""
    found = 0
    for drive, label in (("pressure", "pressure window"), ("flow", "flow window")):
        grid = [c for c in CASES if c["drive"] == drive and c["label"] == label]
        key = "omega2" if drive == "pressure" else "q"
        grid.sort(key=lambda c: c[key])
        counts = [len(c["states"]) for c in grid]
        assert len(grid) >= 4 and counts[0] == 1 and counts[-1] == 1, counts
        assert all(n == 3 for n in counts[1:-1]), counts
        for c in grid:
            if len(c["states"]) == 3:
                found += 1
                assert [s["stable"] for s in c["states"]] == [True, False, True]
                if drive == "pressure":
                    assert c["pi"] != 0.0  # the distributed load is on
    assert found >= 4
    # the wall problem's window (pi = 0) is there too
    assert any(len(c["states"]) == 3 for c in CASES if c["drive"] == "pressure" and c["pi"] == 0.0)


def test_stability_alternates():
    """Along the tip height the states alternate stable, unstable, ..., the first stable."""
    for case in CASES:
        flags = [s["stable"] for s in case["states"]]
        if None in flags:
            continue
        assert flags == [k % 2 == 0 for k in range(len(flags))], case["label"]


def test_folds_bound_the_windows():
    """Each fold lies between the grid inputs with one and three states, and its tip height
    between the two states of the window that merge there."""
    folds = DATA_["folds"]
    assert len(folds) >= 4
    sides = Counter((f["drive"], f["window_side"]) for f in folds)
    for drive in ("pressure", "flow"):
        assert sides[(drive, "lower")] >= 1 and sides[(drive, "upper")] >= 1
    for f in folds:
        name = f["parameter"]
        assert f[name] is None
        value, h1 = mpf(f["value"]), mpf(f["tip_height"])
        fixed = {k: f[k] for k in ("drive", "omega2", "pi", "q", "eps", "theta0") if k != name}
        grid = [
            c
            for c in CASES
            if c["label"].endswith("window") and all(c[k] == v for k, v in fixed.items())
        ]
        one = [c[name] for c in grid if len(c["states"]) == 1]
        three = [c for c in grid if len(c["states"]) == 3]
        assert one and three
        if f["window_side"] == "lower":
            outside = max(v for v in one if v < value)
            inside = min(three, key=lambda c: c[name])
            pair = inside["states"][1:]  # the middle and the upper state merge
        else:
            outside = min(v for v in one if v > value)
            inside = max(three, key=lambda c: c[name])
            pair = inside["states"][:2]  # the lower and the middle state merge
        assert min(outside, inside[name]) < value < max(outside, inside[name])
        assert mpf(pair[0]["tip_height"]) < h1 < mpf(pair[1]["tip_height"])
        # the loads and the identity at the fold
        case = dict(fixed, **{name: value})
        w, big_pi = _loads(case, h1)
        assert abs(mpf(f["W"]) - w) <= mpf("1e-25") * max(1, w)
        assert abs(mpf(f["Pi"]) - big_pi) <= mpf("1e-25") * max(1, abs(big_pi))
        m = mpf(f["base_curvature"])
        assert abs(m - (w * h1 + big_pi * h1**2 / 2)) <= mpf("1e-25") * max(1, m)


def test_near_fold_counts():
    """A relative 1e-4 inside each fold: three states, the merging pair close; outside: one."""
    folds = DATA_["folds"]
    near = [c for c in CASES if c["label"].endswith("near fold")]
    assert len(near) == 2 * len(folds)
    for f in folds:
        name = f["parameter"]
        value = mpf(f["value"])
        mine = [c for c in near if c["drive"] == f["drive"] and abs(c[name] / value - 1) < 2e-4]
        assert len(mine) == 2
        for c in mine:
            above = c[name] > value
            inside = above == (f["window_side"] == "lower")
            assert len(c["states"]) == (3 if inside else 1), (f, c[name])
            if inside:
                h = [mpf(s["tip_height"]) for s in c["states"]]
                gaps = (h[1] - h[0], h[2] - h[1])
                close = gaps[1] if f["window_side"] == "lower" else gaps[0]
                assert close < 0.05 and close < max(gaps) / 5
                assert (
                    abs(
                        (h[1] + (h[2] if f["window_side"] == "lower" else h[0])) / 2
                        - mpf(f["tip_height"])
                    )
                    < 0.02
                )
