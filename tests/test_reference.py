"""The exact solver against independent high-precision reference values.

Two sources, neither computed by :mod:`hairbed`:

- ``tests/data/reference_mpmath.json``, from ``tests/reference/generate_reference.py``: every
  root of a branch's self-consistency equation found in 50 to 75-digit mpmath arithmetic with
  Carlson forms and Jacobi functions by inversion, cross-checked against mpmath's Legendre and
  theta-function routines and, for a subset, against Taylor-series integration of the ODE
  (see the file's ``metadata``);
- ``tests/data/reference_cases.json``, from ``tests/reference/generate_cases.py``: a second
  set of inputs (forward, twirling, huge forcing, profiles with the tip values of a
  Taylor-series integration of the ODE, inverse problems), taken from an independent 30-digit
  reference made for the project and recomputed by the same mpmath machinery (the file's
  ``metadata`` says how well the two agree).

Failures name the case (omega2, eps, theta0, sign, n, root) and the fields that disagree,
with the difference, so that they can be reproduced with one call of :func:`hairbed.solve`.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from conftest import DATA
from tolerances import ATOL, RTOL

import hairbed
from hairbed import inverse

REFERENCE_PATH = DATA / "reference_mpmath.json"
REFERENCE = json.loads(REFERENCE_PATH.read_text())
CASES: list[dict[str, Any]] = REFERENCE["cases"]
SIGMA = np.array(REFERENCE["metadata"]["sigma"], dtype=np.float64)
#: Solution fields with a reference value (one_minus_xi is not an API field; it is checked
#: through from_parameter, whose parameter t the reference records).
FIELDS = (
    "xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_angle",
    "base_curvature",
)
PROFILE = ("theta", "x", "z")
PHYSICAL = [c for c in CASES if c["sign"] == 1 and c["n"] == 0]

SECOND = json.loads((DATA / "reference_cases.json").read_text())


def _label(case: dict[str, Any], root: str | None = None) -> str:
    text = (
        f"solve(omega2={case['omega2']!r}, eps={case['eps']!r}, theta0={case['theta0']!r}, "
        f"sign={case.get('sign', 1)}, n={case.get('n', 0)}"
    )
    return text + (f", root={root!r})" if root else ")")


def _mismatches(name: str, got: Any, expected: Any) -> list[str]:
    """Lines describing where got and expected (float or array) are not isclose."""
    got = np.atleast_1d(np.asarray(got, dtype=np.float64))
    expected = np.atleast_1d(np.asarray(expected, dtype=np.float64))
    if got.shape != expected.shape:
        return [f"  {name}: shape {got.shape}, expected {expected.shape}"]
    # NaN matches NaN: the reference has none, and "no solution" must agree array vs scalar
    ok = np.isclose(got, expected, rtol=RTOL, atol=ATOL, equal_nan=True)
    lines = []
    for i in np.flatnonzero(~ok):
        where = name if got.size == 1 else f"{name}[sigma={SIGMA[i]:g}]"
        g, e = float(got[i]), float(expected[i])
        diff = g - e
        rel = abs(diff) / abs(e) if e else math.inf
        lines.append(f"  {where}: got {g!r}, expected {e!r} (diff {diff:.3e}, rel {rel:.3e})")
    return lines


def _compare(sol: Any, ref: dict[str, Any], label: str, profile: bool = True) -> None:
    """Assert that a scalar Solution matches one reference root, listing every mismatch."""
    lines: list[str] = []
    for f in FIELDS:
        lines += _mismatches(f, getattr(sol, f), float(ref[f]))
    if profile:
        for f in PROFILE:
            lines += _mismatches(f, getattr(sol, f)(SIGMA), [float(v) for v in ref[f]])
    assert not lines, f"{label} disagrees with the reference:\n" + "\n".join(lines)


def _assert_empty(sol: Any, label: str) -> None:
    values = [getattr(sol, f) for f in FIELDS] + [getattr(sol, f)(SIGMA) for f in PROFILE]
    bad = [f for f, v in zip(FIELDS + PROFILE, values) if not np.all(np.isnan(v))]
    assert not bad, f"{label}: no solution expected, but {bad} are not NaN"


# ------------------------------------------------------------------------------------------
# The mpmath reference
# ------------------------------------------------------------------------------------------


def test_reference_file_is_complete() -> None:
    meta = REFERENCE["metadata"]
    assert meta["n_cases"] == len(CASES) and meta["n_roots"] == sum(c["n_roots"] for c in CASES)
    # the generator's own checks passed at the digits it records
    for case in CASES:
        for root in case["roots"]:
            checks = root["checks"]
            if "ode" in checks:
                assert checks["ode"]["digits"] >= 25 and checks["ode"]["label_ok"], case["id"]
            assert checks.get("precision_digits", 99) >= 30, case["id"]
            assert checks.get("legendre_digits", 99) >= 30, case["id"]


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_solve_matches_reference(case: dict[str, Any]) -> None:
    args = (case["omega2"], case["eps"], case["theta0"])
    kw = {"sign": case["sign"], "n": case["n"]}
    roots = case["roots"]
    low = hairbed.solve(*args, **kw, root="low")
    assert low.n_roots == len(roots), (
        f"{_label(case)}: n_roots = {low.n_roots}, reference has {len(roots)} root(s) at xi = "
        f"{[r['xi'] for r in roots]}"
    )
    assert (low.sign, low.n) == (case["sign"], case["n"]), _label(case)
    high = hairbed.solve(*args, **kw, root="high")
    mid = hairbed.solve(*args, **kw, root="mid")
    if not roots:
        for sol, r in ((low, "low"), (high, "high"), (mid, "mid")):
            _assert_empty(sol, _label(case, r))
            assert sol.n_roots == 0 and not sol.physical, _label(case, r)
        return
    assert low.physical == (case["sign"] == 1 and case["n"] == 0), _label(case)
    _compare(low, roots[0], _label(case, "low"))
    _compare(high, roots[-1], _label(case, "high"))
    if len(roots) == 3:
        _compare(mid, roots[1], _label(case, "mid"))
    elif len(roots) < 3:
        _assert_empty(mid, _label(case, "mid"))


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_from_parameter_matches_reference(case: dict[str, Any]) -> None:
    """The branch curve at the reference's t reproduces the state and its forcing omega2."""
    for k, root in enumerate(case["roots"]):
        t = float(root["t"])
        sol = hairbed.from_parameter(
            t, case["eps"], case["theta0"], sign=case["sign"], n=case["n"]
        )
        label = f"from_parameter(t={t!r}) for root {k} of {_label(case)}"
        assert np.isclose(sol.omega2, case["omega2"], rtol=RTOL, atol=ATOL), (
            f"{label}: omega2 = {sol.omega2!r}, expected {case['omega2']!r}"
        )
        _compare(sol, root, label, profile=False)


def _physical_arrays() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return tuple(
        np.array([c[k] for c in PHYSICAL], dtype=np.float64) for k in ("omega2", "eps", "theta0")
    )


def _reference_root(case: dict[str, Any], root: str) -> dict[str, Any] | None:
    roots = case["roots"]
    if not roots:
        return None
    return {"low": roots[0], "high": roots[-1], "mid": roots[1] if len(roots) == 3 else None}[root]


@pytest.mark.parametrize("root", ["low", "mid", "high"])
def test_vectorised_solve_matches_scalar_and_reference(root: str) -> None:
    """All physical-branch cases in ONE array call give the scalar results and the reference."""
    w, e, t = _physical_arrays()
    sol = hairbed.solve(w, e, t, root=root)
    assert np.shape(sol.xi) == w.shape and np.shape(sol.n_roots) == w.shape
    lines = []
    for i, case in enumerate(PHYSICAL):
        scalar = hairbed.solve(case["omega2"], case["eps"], case["theta0"], root=root)
        label = _label(case, root)
        if sol.n_roots[i] != scalar.n_roots or sol.n_roots[i] != case["n_roots"]:
            lines.append(
                f"{label}: n_roots array {sol.n_roots[i]}, scalar {scalar.n_roots}, "
                f"reference {case['n_roots']}"
            )
            continue
        ref = _reference_root(case, root)
        for f in FIELDS:
            a = getattr(sol, f)[i]
            bad = _mismatches(f + " (array vs scalar)", a, getattr(scalar, f))
            if ref is None:
                bad += [] if np.isnan(a) else [f"  {f}: {float(a)!r}, expected NaN"]
            else:
                bad += _mismatches(f + " (array vs reference)", a, float(ref[f]))
            lines += [f"{label}:{b}" for b in bad]
    assert not lines, "\n".join(lines)


@pytest.mark.parametrize("name", PROFILE)
def test_vectorised_profile_matches_reference(name: str) -> None:
    """theta/x/z broadcast numpy-style: sigma of shape (m, 1) against a solution of shape (S,)."""
    w, e, t = _physical_arrays()
    sol = hairbed.solve(w, e, t)
    got = getattr(sol, name)(SIGMA[:, None]).T
    assert np.shape(got) == w.shape + SIGMA.shape
    lines = []
    for i, case in enumerate(PHYSICAL):
        ref = _reference_root(case, "low")
        lines += [
            f"{_label(case)}:{b}" for b in _mismatches(name, got[i], [float(v) for v in ref[name]])
        ]
    assert not lines, "\n".join(lines)


ALL_BRANCHES = REFERENCE["metadata"]["all_branches"]


@pytest.mark.parametrize(
    "entry",
    ALL_BRANCHES,
    ids=[f"w{a['omega2']:g}-e{a['eps']:g}-t{a['theta0']:g}" for a in ALL_BRANCHES],
)
def test_solve_all_matches_reference(entry: dict[str, Any]) -> None:
    by_id = {c["id"]: c for c in CASES}
    branches = sorted((by_id[i] for i in entry["case_ids"]), key=lambda c: (c["n"], -c["sign"]))
    expected = [(c, r) for c in branches for r in c["roots"]]
    got = hairbed.solve_all(entry["omega2"], entry["eps"], entry["theta0"])
    label = f"solve_all({entry['omega2']!r}, {entry['eps']!r}, {entry['theta0']!r})"
    assert [(s.sign, s.n) for s in got] == [(c["sign"], c["n"]) for c, _ in expected], (
        f"{label}: branches {[(s.sign, s.n) for s in got]}, reference "
        f"{[(c['sign'], c['n']) for c, _ in expected]}"
    )
    for k, (sol, (case, root)) in enumerate(zip(got, expected)):
        assert sol.n_roots == case["n_roots"], f"{label}[{k}]: n_roots"
        assert sol.physical == (case["sign"] == 1 and case["n"] == 0), f"{label}[{k}]: physical"
        _compare(sol, root, f"{label}[{k}] = {_label(case)}")


# ------------------------------------------------------------------------------------------
# The second reference set
# ------------------------------------------------------------------------------------------


def _second(section: str) -> list[dict[str, Any]]:
    return SECOND[section]


def _second_ids(section: str) -> list[str]:
    ids = []
    for c in _second(section):
        if section == "inverse":
            ids.append(f"inverse-e{c['eps']:g}-t{c['theta0']:g}-x{float(c['tip_deflection']):.6g}")
            continue
        text = f"{section}-w{c['omega2']:g}-e{c['eps']:g}-t{c['theta0']:g}"
        ids.append(text + (f"-s{c['sign']:+d}-n{c['n']}" if "sign" in c else ""))
    return ids


def test_second_reference_is_complete() -> None:
    counts = {k: len(SECOND[k]) for k in ("forward", "branches", "huge", "profiles", "inverse")}
    assert counts == {"forward": 45, "branches": 8, "huge": 3, "profiles": 5, "inverse": 30}
    assert "generate_cases.py" in SECOND["metadata"]["generator"]


@pytest.mark.parametrize(
    "case",
    _second("forward") + _second("branches") + _second("huge"),
    ids=_second_ids("forward") + _second_ids("branches") + _second_ids("huge"),
)
def test_solve_matches_second_reference(case: dict[str, Any]) -> None:
    args = (case["omega2"], case["eps"], case["theta0"])
    kw = {"sign": case.get("sign", 1), "n": case.get("n", 0)}
    sols = case["solutions"]
    low = hairbed.solve(*args, **kw)
    assert low.n_roots == len(sols), (
        f"{_label(case)}: n_roots {low.n_roots}, reference {len(sols)}"
    )
    if not sols:
        _assert_empty(low, _label(case))
        return
    _compare(low, sols[0], _label(case, "low"), profile=False)
    _compare(hairbed.solve(*args, **kw, root="high"), sols[-1], _label(case, "high"), False)
    if len(sols) == 3:
        _compare(hairbed.solve(*args, **kw, root="mid"), sols[1], _label(case, "mid"), False)


@pytest.mark.parametrize("case", _second("profiles"), ids=_second_ids("profiles"))
def test_profile_matches_second_reference(case: dict[str, Any]) -> None:
    sol = hairbed.solve(case["omega2"], case["eps"], case["theta0"])
    label = _label(case)
    sigma = np.array(case["sigma"], dtype=np.float64)
    got = sol.theta(sigma)
    expected = np.array([float(v) for v in case["theta"]])
    ok = np.isclose(got, expected, rtol=RTOL, atol=ATOL)
    assert ok.all(), (
        f"{label}: theta at sigma={sigma[~ok]}: got {got[~ok]}, expected {expected[~ok]}"
    )
    # the tip values of the reference's Taylor-series integration of the ODE
    lines = _mismatches("tip_height (ODE)", sol.tip_height, float(case["ode_h1"]))
    lines += _mismatches("tip_deflection (ODE)", sol.tip_deflection, float(case["ode_x1"]))
    assert not lines, f"{label}:\n" + "\n".join(lines)


@pytest.mark.parametrize("case", _second("inverse"), ids=_second_ids("inverse"))
def test_inverse_matches_second_reference(case: dict[str, Any]) -> None:
    eps, theta0 = case["eps"], case["theta0"]
    x1, h1 = float(case["tip_deflection"]), float(case["tip_height"])
    omega2, xi = float(case["omega2"]), float(case["xi"])
    label = f"inverse(eps={eps!r}, theta0={theta0!r}, x1={x1!r}, h1={h1!r})"
    lines = _mismatches(
        "omega2_from_tip_deflection", inverse.omega2_from_tip_deflection(x1, eps, theta0), omega2
    )
    sol = inverse.solution_from_tip_deflection(x1, eps, theta0)
    lines += _mismatches("solution_from_tip_deflection.xi", sol.xi, xi)
    answers = np.asarray(inverse.omega2_from_tip_height(h1, eps, theta0), dtype=np.float64)
    answers = answers[~np.isnan(answers)]
    if not np.any(np.isclose(answers, omega2, rtol=RTOL, atol=ATOL)):
        lines.append(f"  omega2_from_tip_height: {answers.tolist()}, expected {omega2!r} among")
    assert not lines, f"{label}:\n" + "\n".join(lines)
