"""The isolated-pillar reference data on its own: invariants, no solver.

``tests/data/pillar_mpmath.json`` (from ``tests/reference/generate_pillar.py``, mpmath only) is
the reference of issue 21's pillar solver (docs/theory.md §12). These tests check what the
file itself must satisfy, without :mod:`hairbed`, so that the data can be trusted before it is
used:

- layout and digits: every computed number a decimal string of >= 25 significant digits, the
  shape on s = j/8 starting at the clamp and ending at the tabulated tip;
- coverage: the three built-in profiles and a callable one, theta0 from -1.4 to 1.4, Lambda
  from 1e-6 to 1e4, gamma = 1/2 and Gray & Hancock's ratio at L/a = 20 (recomputed here),
  >= 36 states and >= 6 inverse cases;
- physics that holds for every state: the drag is downstream (U >= 0), the pillar is
  inextensible (each chord of the shape at most its arclength), the tip lies in the unit disc;
- the small-deflection limits x1 = Lambda int_0^1 U(s) s^2 (3 - s)/6 ds at theta0 = 0
  (11 Lambda/120 for the sublayer), with a relative remainder of order Lambda^2, and the
  tilted sublayer x1 = sin(theta0) + 11 Lambda cos^3(theta0)/120 + O(Lambda^2);
- a re-integration by ``mpmath.odefun`` (its own Taylor method, not the generator's) from the
  tabulated base values of a few states, fold states included: the boundary conditions at
  the tip, the tip values, the shape and the base-moment identity
  theta'(0) = int_0^1 (z f_x - x f_z) ds;
- the inverse cases reproduce their given tip deflection, and lie on the forward curve;
- the snap-through window: three distinct states at theta0 = -1.4, Lambda = 15, folds found
  there and none for theta0 >= -1.3.
"""

from __future__ import annotations

import json
from typing import Any

import pytest
from conftest import DATA
from mpmath import mp, mpf, odefun

PATH = DATA / "pillar_mpmath.json"
DATA_ = json.loads(PATH.read_text())
CASES: list[dict[str, Any]] = DATA_["cases"]
INVERSE: list[dict[str, Any]] = DATA_["inverse"]
SCALARS = ("tip_deflection", "tip_height", "tip_angle", "base_curvature", "drag_x", "drag_z")
mp.dps = 40


def _ids(case: dict[str, Any]) -> str:
    p = ",".join(f"{k}={v}" for k, v in case["profile_parameters"].items())
    return (
        f"{case['profile']}({p}):g={case['gamma'][:5]},th0={case['theta0']},"
        f"L={case['forcing']}#{case['state_index']}"
    )


def _significant_digits(text: str) -> int:
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return len(mantissa)


def _profile(case: dict[str, Any]) -> tuple[mpf, mpf]:
    """(a1, a2): U(z) = a1 z + a2 z^2, written here from the docs, not imported."""
    name = case["profile"]
    if name in ("sublayer", "couette"):
        return mpf(1), mpf(0)
    if name == "poiseuille":
        return mpf(1), -mpf(case["profile_parameters"]["L/H"])
    assert name == "callable" and case["profile_parameters"] == {"u": "z**2"}
    return mpf(0), mpf(1)


def _gray_hancock(slenderness: int) -> mpf:
    lg = mp.log(2 * mpf(slenderness))
    return (lg + mpf(1) / 2) / (2 * lg - 1)


def _linear_tip(case: dict[str, Any]) -> mpf:
    a1, a2 = _profile(case)
    return mpf(case["forcing"]) * (a1 * mpf(11) / 120 + a2 * mpf(13) / 180)


def test_layout_and_digits():
    assert DATA_["generator"] == "tests/reference/generate_pillar.py"
    assert DATA_["dps"] >= 30 and isinstance(DATA_["checks"], dict)
    for case in CASES + INVERSE:
        assert case["profile"] in ("sublayer", "couette", "poiseuille", "callable")
        assert isinstance(case["theta0"], float) and -1.4 <= case["theta0"] <= 1.4
        texts = [case[k] for k in SCALARS]
        texts += [v for k in ("x", "z", "theta") for v in case["shape"][k]]
        for text in texts:
            assert isinstance(text, str)
            mpf(text)
            if mpf(text) != 0:
                assert _significant_digits(text) >= 25, text
        shape = case["shape"]
        assert [mpf(s) for s in shape["s"]] == [mpf(j) / 8 for j in range(9)]
        assert all(len(shape[k]) == 9 for k in ("x", "z", "theta"))
        assert mpf(shape["x"][0]) == 0 and mpf(shape["z"][0]) == 0
        assert abs(mpf(shape["theta"][0]) - mpf(case["theta0"])) < mpf("1e-28")
        assert mpf(shape["x"][-1]) == mpf(case["tip_deflection"])
        assert mpf(shape["z"][-1]) == mpf(case["tip_height"])
        assert mpf(shape["theta"][-1]) == mpf(case["tip_angle"])
    for case in CASES:
        assert isinstance(case["forcing"], float) and case["forcing"] > 0
    for inv in INVERSE:
        assert isinstance(inv["forcing"], str) and _significant_digits(inv["forcing"]) >= 25


def test_coverage():
    assert len(CASES) >= 36 and len(INVERSE) >= 6
    assert {c["profile"] for c in CASES} == {"sublayer", "couette", "poiseuille", "callable"}
    assert min(c["theta0"] for c in CASES) == -1.4
    assert max(c["theta0"] for c in CASES) == 1.4
    assert min(c["forcing"] for c in CASES) <= 1e-6
    assert max(c["forcing"] for c in CASES) >= 1e4
    gammas = {mpf(c["gamma"]) for c in CASES}
    gh = _gray_hancock(DATA_["gray_hancock"]["slenderness"])
    assert mpf("0.5") in gammas
    # the generator wrote the ratio to 16 digits; that decimal string is the input used
    assert any(abs(g - gh) < mpf("1e-15") for g in gammas)
    assert {c["profile"] for c in INVERSE} >= {"sublayer", "poiseuille"}
    for profile in ("sublayer", "couette", "poiseuille", "callable"):
        lams = [c["forcing"] for c in CASES if c["profile"] == profile]
        assert min(lams) <= 1e-2 and max(lams) >= 100, profile


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_every_state_is_physical(case):
    x1, h1 = mpf(case["tip_deflection"]), mpf(case["tip_height"])
    assert x1**2 + h1**2 <= 1
    assert 0 < h1 <= 1
    # U >= 0 on the pillar and cos^2 + gamma sin^2 > 0: the streamwise drag is downstream
    assert mpf(case["drag_x"]) > 0
    xs = [mpf(v) for v in case["shape"]["x"]]
    zs = [mpf(v) for v in case["shape"]["z"]]
    for j in range(8):
        chord = mp.sqrt((xs[j + 1] - xs[j]) ** 2 + (zs[j + 1] - zs[j]) ** 2)
        assert chord <= mpf(1) / 8 * (1 + mpf("1e-28"))
    if "L/H" in case["profile_parameters"]:
        assert max(zs) <= 1 / mpf(case["profile_parameters"]["L/H"])


def _small(profile: str, theta0: float) -> list[dict[str, Any]]:
    found = [
        c
        for c in CASES
        if c["profile"] == profile and c["theta0"] == theta0 and c["forcing"] <= 1e-3
    ]
    return sorted(found, key=lambda c: c["forcing"])


@pytest.mark.parametrize("profile", ["sublayer", "poiseuille", "callable"])
def test_linear_limit(profile):
    """x1 = Lambda int_0^1 U(s) s^2 (3 - s)/6 ds at theta0 = 0 (11/120, (33 - 26 L/H)/360, ...)."""
    small = _small(profile, 0.0)
    assert small
    for c in small:
        lam = mpf(c["forcing"])
        rel = abs(mpf(c["tip_deflection"]) / _linear_tip(c) - 1)
        assert rel <= lam**2 / 10, (c["forcing"], rel)


def test_linear_remainder_is_second_order():
    """The relative remainder of 11 Lambda/120 is c Lambda^2 with one c (x1 is odd in Lambda)."""
    for gamma in {c["gamma"] for c in _small("sublayer", 0.0)}:
        small = [c for c in _small("sublayer", 0.0) if c["gamma"] == gamma]
        assert len(small) >= 2
        ratios = []
        for c in small:
            lam = mpf(c["forcing"])
            ratios.append(abs(mpf(c["tip_deflection"]) / (11 * lam / 120) - 1) / lam**2)
        assert ratios[0] > 0
        assert max(ratios) / min(ratios) - 1 < mpf("1e-3"), ratios


def test_linear_limit_tilted_sublayer():
    """x1 = sin theta0 + 11 Lambda cos^3(theta0)/120 + O(Lambda^2) for a tilted pillar."""
    tilted = [
        c
        for c in CASES
        if c["profile"] in ("sublayer", "couette") and c["theta0"] != 0 and c["forcing"] <= 1e-3
    ]
    assert {c["theta0"] for c in tilted} >= {1.4, -0.7, -1.4}
    for c in tilted:
        th0, lam = mpf(c["theta0"]), mpf(c["forcing"])
        lin = 11 * lam * mp.cos(th0) ** 3 / 120
        dx = mpf(c["tip_deflection"]) - mp.sin(th0)
        assert abs(dx / lin - 1) <= 5 * lam, (c["theta0"], c["forcing"])


def _reintegrate(case: dict[str, Any], dps: int) -> list[list[mpf]]:
    """mpmath.odefun from the tabulated base values: the state at s = j/8, plus M(s)."""
    mp.dps = dps
    lam, g = mpf(case["forcing"]), mpf(case["gamma"])
    a1, a2 = _profile(case)

    def rhs(_s, y):
        th, m, fx, fz, x, z, _moment = y
        c, s = mp.cos(th), mp.sin(th)
        u = a1 * z + a2 * z * z
        f_x = lam * u * (c * c + g * s * s)
        f_z = -lam * u * (1 - g) * s * c
        return [m, -(fx * c - fz * s), -f_x, -f_z, s, c, z * f_x - x * f_z]

    y0 = [mpf(case["theta0"])] + [mpf(case[k]) for k in ("base_curvature", "drag_x", "drag_z")]
    sol = odefun(rhs, 0, y0 + [mpf(0)] * 3)
    return [sol(mpf(j) / 8) for j in range(9)]


def _odefun_cases() -> list[dict[str, Any]]:
    """The three states of the snap-through window and one of each other profile."""
    fold = [c for c in CASES if c["theta0"] == -1.4 and c["forcing"] == 15.0]
    other = [
        c
        for c in CASES
        if (c["profile"], c["forcing"]) in (("callable", 10.0), ("poiseuille", 3.0))
    ]
    return fold + other


@pytest.mark.parametrize("case", _odefun_cases(), ids=_ids)
def test_odefun_reintegration(case):
    try:
        nodes = _reintegrate(case, 22)
        tol = mpf("1e-15")
        end = nodes[-1]
        for v in end[1:4]:  # m(1) = F_x(1) = F_z(1) = 0
            assert abs(v) < tol
        for j, y in enumerate(nodes):
            assert abs(y[0] - mpf(case["shape"]["theta"][j])) < tol
            assert abs(y[4] - mpf(case["shape"]["x"][j])) < tol
            assert abs(y[5] - mpf(case["shape"]["z"][j])) < tol
        assert abs(end[6] - mpf(case["base_curvature"])) < tol  # the base-moment identity
    finally:
        mp.dps = 40


def test_inverse_cases():
    for inv in INVERSE:
        assert abs(mpf(inv["tip_deflection"]) - mpf(inv["given_tip_deflection"])) < mpf("1e-25")
        assert mpf(inv["forcing"]) > 0
    # on the forward curve: at theta0 = 0, gamma = 1/2 the sublayer x1(Lambda) is increasing,
    # so the inverse Lambda of x1 = 0.5 lies between the forward states around it
    fwd = sorted(
        (
            (c["forcing"], mpf(c["tip_deflection"]))
            for c in CASES
            if c["profile"] == "sublayer" and c["theta0"] == 0.0 and c["gamma"] == "0.5"
        ),
    )
    assert all(a[1] < b[1] for a, b in zip(fwd[:-1], fwd[1:]))
    for inv in INVERSE:
        if inv["profile"] == "sublayer" and inv["theta0"] == 0.0 and inv["gamma"] == "0.5":
            x = mpf(inv["given_tip_deflection"])
            lam = mpf(inv["forcing"])
            below = [lf for lf, xf in fwd if xf < x]
            above = [lf for lf, xf in fwd if xf > x]
            assert max(below) < lam < min(above)


def test_tip_deflection_increases_with_forcing_without_folds():
    """Outside a fold window x1 grows with Lambda along every group of the reference."""
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for c in CASES:
        key = (c["profile"], json.dumps(c["profile_parameters"]), c["gamma"], c["theta0"])
        groups.setdefault(key, []).append(c)
    checked = 0
    for members in groups.values():
        if any(c["states_at_forcing"] != 1 for c in members):
            continue
        members.sort(key=lambda c: c["forcing"])
        x1 = [mpf(c["tip_deflection"]) for c in members]
        assert all(a < b for a, b in zip(x1[:-1], x1[1:])), members[0]["profile"]
        checked += 1
    assert checked >= 8


def test_snap_through_window():
    at15 = [
        c
        for c in CASES
        if c["profile"] == "sublayer" and c["theta0"] == -1.4 and c["forcing"] == 15.0
    ]
    assert len(at15) == 3 and all(c["states_at_forcing"] == 3 for c in at15)
    x1 = sorted(mpf(c["tip_deflection"]) for c in at15)
    assert x1[1] - x1[0] > mpf("1e-3") and x1[2] - x1[1] > mpf("1e-3")
    folds = {
        (f["profile"], f["gamma"], f["theta0"]): f["folds_near_forcing"] for f in DATA_["folds"]
    }
    window = folds[("sublayer", "0.5", -1.4)]
    assert len(window) == 2 and min(window) < 15.0 < max(window)
    for (profile, _gamma, theta0), found in folds.items():
        if theta0 >= -1.3:
            assert found == [], (profile, theta0)
    for f in DATA_["folds"]:
        assert f["continued_to"] >= 300.0
