"""The porous-bed reference data on its own: invariants and limits, no solver.

``tests/data/porous_mpmath.json`` (from ``tests/reference/generate_porous.py``, mpmath only)
is the reference of issue 29's porous (Brinkman) bed. These tests check what the file itself
must satisfy, without :mod:`hairbed`, so that the data can be trusted before it is used:

- layout and digits: every computed number a decimal string of >= 25 significant digits;
- the two methods of the generator (forward Taylor, backward extrapolation shooting) agree on
  every state to < 1e-14 (they were asked for 1e-25), method 1's residuals are tiny;
- coverage: kappa from 1e-4 to 1e5, the three drives, theta0 from -1.2 to 1.2, eps to 0.95,
  gamma = 1, 1/2 and Gray & Hancock's ratio at L/a = 20 (recomputed here), >= 40 states;
- identities on every state, from the written numbers: the gap condition, the flux of the
  flow drive, the horizontal force balance F_x(0) = Q(1) - Q(0) + Pi h1, the base moment
  theta'(0) = int (z f_x - x f_z) ds, |theta| < pi/2, the tip in the unit disc;
- every coexisting state of the windows: at least three distinct states at one load between
  the two folds the generator's scan found;
- the limits: the linear theory at theta0 = 0 (the Brinkman profile's tip deflection,
  recomputed here in closed form, with a cubic remainder), kappa -> 0 with its rate
  sqrt(kappa) towards the dense bed with the rotated tip force (wall drive 1e-2 to 1e-4,
  pressure drive 0.1 to 1e-2), kappa -> infinity with its
  rate 1/kappa towards the isolated pillar; the limit states themselves re-integrated by
  ``mpmath.odefun`` (its own Taylor method, not the generator's);
- one porous state re-integrated by ``mpmath.odefun`` from its base values.
"""

from __future__ import annotations

import json
import math
from typing import Any

import pytest
from conftest import DATA
from mpmath import mp, mpf, odefun

PATH = DATA / "porous_mpmath.json"
DATA_ = json.loads(PATH.read_text())
STATES: list[dict[str, Any]] = DATA_["states"]
LIMITS: list[dict[str, Any]] = DATA_["limits"]
NUMBERS = (
    "h1", "x1", "theta1", "base_curvature", "Q0", "Q1", "w1", "pi_value", "drag_x", "drag_z",
    "flux_bed", "moment_integral", "max_abs_theta",
)  # fmt: skip
mp.dps = 40
#: |measured rate - 1/2| of the kappa -> 0 series (corrections O(sqrt(kappa)) at kappa = 1e-2)
DENSE_RATE_TOL = 0.1


def _ids(s: dict[str, Any]) -> str:
    return (
        f"{s['drive']}:k={s['kappa']:g},eps={s['eps']},th0={s['theta0']},"
        f"g={s['gamma']:.3f},L={s['load']:g}#{s['state_index']}"
    )


def _digits(text: str) -> int:
    return len(text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0"))


def _v(s: dict[str, Any], key: str) -> mpf:
    return mpf(s[key])


def _gray_hancock(slenderness: int) -> mpf:
    lg = mp.log(2 * mpf(slenderness))
    return (lg + mpf(1) / 2) / (2 * lg - 1)


def test_layout_digits_and_agreement():
    assert DATA_["generator"] == "tests/reference/generate_porous.py"
    assert not DATA_["quick"]
    for s in STATES:
        assert s["drive"] in ("wall", "pressure", "flow")
        for key in ("kappa", "eps", "theta0", "gamma", "omega2", "load"):
            assert isinstance(s[key], float), key
        for key in NUMBERS:
            assert isinstance(s[key], str)
            if mpf(s[key]) != 0:
                assert _digits(s[key]) >= 25, (key, s[key])
        assert float(s["method_difference"]) < 1e-14
        assert float(s["residual"]) < 1e-30
        assert s["digits"] >= 40 and s["method2_digits"] >= 40
        assert s["method2"] in ("backward GBS shooting", "forward GBS shooting")
        assert s["seconds_method1"] >= 0 and s["seconds_method2"] >= 0


def test_coverage():
    assert len(STATES) >= 40
    kappas = [s["kappa"] for s in STATES]
    assert min(kappas) <= 1e-4 and max(kappas) >= 1e4
    assert {s["drive"] for s in STATES} == {"wall", "pressure", "flow"}
    for drive in ("pressure", "flow"):
        ks = [s["kappa"] for s in STATES if s["drive"] == drive]
        assert min(ks) <= 1e-2 and max(ks) >= 1e3, drive
    assert min(s["theta0"] for s in STATES) == -1.2
    assert max(s["theta0"] for s in STATES) == 1.2
    assert max(s["eps"] for s in STATES) >= 0.95
    assert 0.0 in {s["eps"] for s in STATES}
    gammas = {s["gamma"] for s in STATES}
    gh = _gray_hancock(DATA_["gray_hancock"]["slenderness"])
    assert {1.0, 0.5} <= gammas
    assert any(abs(mpf(g) - gh) < mpf("1e-15") for g in gammas)
    # small and large deflections
    x1 = [abs(_v(s, "x1") - mp.sin(s["theta0"])) for s in STATES]
    assert min(x1) < mpf("1e-3") and max(_v(s, "theta1") for s in STATES) > 1.3


@pytest.mark.parametrize("s", STATES, ids=_ids)
def test_identities(s):
    kappa, eps, omega2 = mpf(s["kappa"]), mpf(s["eps"]), mpf(s["omega2"])
    h1, x1, w1, Q0, Q1 = (_v(s, k) for k in ("h1", "x1", "w1", "Q0", "Q1"))
    Pi = _v(s, "pi_value")
    scale = max(1, abs(omega2), abs(Q1), abs(Pi))
    tol = mpf("1e-25") * scale
    # the inputs are the requested ones
    if s["drive"] == "wall":
        assert Pi == 0 and s["load"] == s["omega2"]
    elif s["drive"] == "pressure":
        assert Pi == mpf(s["pi"]) and s["load"] == s["pi"]
    else:
        assert s["load"] == s["q"]
    # the gap: eps w(1) + (1 - eps h1) Q(1) - Pi (1 - eps h1)^2/(2 eps) = omega2
    u = 1 - eps * h1
    gap = eps * w1 + u * Q1 - omega2
    if s["drive"] != "wall":
        gap -= Pi * u**2 / (2 * eps)
    assert abs(gap) < tol
    # the flux q = 6 eps^2 (int w cos + w1 g + Q1 g^2/2 - Pi g^3/6), g = 1/eps - h1
    if eps > 0:
        g = 1 / eps - h1
        phi = _v(s, "flux_bed") + w1 * g + Q1 * g**2 / 2 - Pi * g**3 / 6
        assert abs(6 * eps**2 * phi - _v(s, "q_value")) < tol
        if s["drive"] == "flow":
            assert abs(_v(s, "q_value") - mpf(s["q"])) < tol
        assert h1 < 1 / eps
    # horizontal force balance and base moment
    assert abs(_v(s, "drag_x") - (Q1 - Q0 + Pi * h1)) < tol
    assert abs(_v(s, "base_curvature") - _v(s, "moment_integral")) < tol
    # the drag is downstream, the hair inextensible and monotone in z
    assert _v(s, "drag_x") > 0 and 0 < h1 <= 1 and x1**2 + h1**2 <= 1
    top = _v(s, "max_abs_theta")
    assert top < mp.pi / 2
    assert top >= max(abs(mpf(s["theta0"])), abs(_v(s, "theta1"))) - mpf("1e-30")
    assert kappa > 0


def test_windows_have_every_state():
    assert len(DATA_["windows"]) >= 2
    for w in DATA_["windows"]:
        at = [s for s in STATES if s["job"] == w["name"]]
        assert len(at) == at[0]["states_at_load"] >= 3, w["name"]
        assert [s["state_index"] for s in at] == list(range(len(at)))
        lo, hi = sorted(f[1] for f in w["folds"])
        assert lo < w["load"] < hi
        theta1 = [_v(s, "theta1") for s in at]
        assert all(b - a > mpf("1e-3") for a, b in zip(theta1, theta1[1:]))
        assert at[0]["theta0"] < 0
    drives = {w["drive"] for w in DATA_["windows"]}
    assert "wall" in drives and len(drives) >= 2


def _linear_x1(s: dict[str, Any]) -> mpf:
    """int_0^1 (w/kappa)(z^2/2 - z^3/6) dz with w = A sinh(z/l), l = sqrt(kappa), in closed
    form: int_0^1 sinh(z/l) z^n dz by the antiderivatives of z^n e^(+-z/l)."""
    kappa, eps, omega2 = mpf(s["kappa"]), mpf(s["eps"]), mpf(s["omega2"])
    ell = mp.sqrt(kappa)
    A = omega2 / (eps * mp.sinh(1 / ell) + (1 - eps) * mp.cosh(1 / ell) / ell)

    def moment(n: int, c: mpf) -> mpf:  # int_0^1 z^n e^(c z) dz
        total = mpf(0)
        for k in range(n + 1):
            total += (-1) ** k * mp.factorial(n) / mp.factorial(n - k) / c ** (k + 1) * mp.exp(c)
        return total - (-1) ** n * mp.factorial(n) / c ** (n + 1)

    def sinh_moment(n: int) -> mpf:
        return (moment(n, 1 / ell) - moment(n, -1 / ell)) / 2

    return A / kappa * (sinh_moment(2) / 2 - sinh_moment(3) / 6)


def test_linear_theory():
    """x1 -> int p (z^2/2 - z^3/6) dz at theta0 = 0 with a cubic remainder (x1 odd in load)."""
    lin = [s for s in STATES if s.get("linear")]
    assert len(lin) >= 8
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for s in lin:
        assert s["theta0"] == 0.0 and s["drive"] == "wall"
        assert abs(_linear_x1(s) / _v(s, "x1_linear") - 1) < mpf("1e-25")
        groups.setdefault((s["kappa"], s["gamma"], s["eps"]), []).append(s)
    assert len(groups) >= 4
    for members in groups.values():
        members.sort(key=lambda s: s["omega2"])
        assert len(members) == 2
        rel = [abs(_v(s, "x1") / _v(s, "x1_linear") - 1) for s in members]
        assert rel[0] < mpf("1e-4")
        ratio = rel[1] / rel[0] * (members[0]["omega2"] / members[1]["omega2"]) ** 2
        assert abs(ratio - 1) < mpf("0.01"), ratio


def _series(kind: str) -> list[tuple[dict[str, Any], list[dict[str, Any]]]]:
    out = []
    for lim in LIMITS:
        if lim["kind"] != kind:
            continue
        members = [s for s in STATES if s["job"] == lim["series"]]
        members.sort(key=lambda s: s["kappa"], reverse=(kind == "dense"))
        out.append((lim, members))
    return out


@pytest.mark.parametrize("key", ["x1", "h1", "theta1", "base_curvature"])
def test_dense_limit_rate(key):
    """kappa -> 0: the difference to the dense limit shrinks like sqrt(kappa) over every
    decade from 1e-2 to 1e-4 of a series continued below 1e-2 (the wall drive); the series
    scanned in half decades from 1 to 1e-2 (pressure, anisotropic wall) converge there at an
    algebraic rate between 1/4 and 1 over their last half decade."""
    series = _series("dense")
    assert {(lim["gamma"] == 1.0, lim["drive"] == "wall") for lim, _ in series} == {
        (True, True), (False, True), (True, False), (False, False),
    }  # fmt: skip
    assert any(m[-1]["kappa"] <= 1e-4 for _, m in series)
    for lim, members in series:
        assert len(members) >= 3 and members[-1]["kappa"] <= 1e-2
        diffs = [abs(_v(s, key) - _v(lim, key)) for s in members]
        pairs = list(zip(zip(members, diffs), zip(members[1:], diffs[1:])))
        for (a, da), (b, db) in pairs:
            rate = mp.log(da / db) / mp.log(a["kappa"] / b["kappa"])
            if members[-1]["kappa"] <= 1e-4:
                # continued to 1e-4: every decade at the asymptotic rate
                assert abs(rate - mpf(1) / 2) < DENSE_RATE_TOL, (lim["series"], key, rate)
            elif a["kappa"] == members[-2]["kappa"]:
                # scanned in half decades to 1e-2 only, not yet asymptotic there (local
                # rates from 0.3 to 0.74): converging at an algebraic rate near 1/2
                assert 0.25 < rate < 1, (lim["series"], key, a["kappa"], rate)


@pytest.mark.parametrize("key", ["x1", "h1", "theta1", "base_curvature"])
def test_pillar_limit_rate(key):
    """kappa -> infinity at fixed Lambda: the difference to the pillar shrinks like 1/kappa."""
    series = _series("pillar")
    assert len(series) >= 2
    for lim, members in series:
        assert len(members) >= 3 and members[-1]["kappa"] >= 1e4
        lam = {mpf(s["omega2"]) / mpf(s["kappa"]) for s in members}
        assert len(lam) == 1
        diffs = [abs(_v(s, key) - _v(lim, key)) for s in members]
        for (a, da), (b, db) in zip(zip(members, diffs), zip(members[1:], diffs[1:])):
            rate = mp.log(da / db) / mp.log(b["kappa"] / a["kappa"])
            assert abs(rate - 1) < 0.05, (lim["series"], key, a["kappa"], rate)


def _limit_rhs(lim: dict[str, Any]):
    g1 = 1 - mpf(lim["gamma"])
    Pi = mpf(lim["interior_pi"])
    lam = mpf(lim["omega2"]) / mpf(lim["kappa"])

    def rhs(_s, y):
        th, m, _x, z, Fx, Fz = y
        S, C = mp.sin(th), mp.cos(th)
        if lim["kind"] == "dense":
            fx, fz = Pi * C, -Pi * g1 * S * C * C / (1 - g1 * S * S)
        else:
            fx, fz = lam * z * (1 - g1 * S * S), -lam * z * g1 * S * C
        return [m, -(Fx * C - Fz * S), S, C, -fx, -fz]

    return rhs


@pytest.mark.parametrize("lim", LIMITS, ids=lambda lim: lim["series"])
def test_limit_states_by_odefun(lim):
    """Each limit state, re-integrated from its base, meets its tip conditions: the dense
    bed's tip force W (1, -r1) with W from the gap, the pillar's free tip."""
    mp.dps = 20
    try:
        y0 = [mpf(lim["theta0"]), _v(lim, "base_curvature"), mpf(0), mpf(0)]
        y0 += [_v(lim, "drag_x"), _v(lim, "drag_z")]
        y1 = odefun(_limit_rhs(lim), 0, y0)(1)
        th1, h1 = _v(lim, "theta1"), _v(lim, "h1")
        if lim["kind"] == "dense":
            eps, omega2, gamma = mpf(lim["eps"]), mpf(lim["omega2"]), mpf(lim["gamma"])
            u = 1 - eps * h1
            if lim["drive"] == "wall":
                W, Pi = omega2 / u, mpf(0)
            elif lim["drive"] == "pressure":
                Pi = mpf(lim["pi"])
                W = omega2 / u + Pi * u / (2 * eps)
            else:
                q = mpf(lim["q"])
                W, Pi = q / u**2 - 2 * omega2 / u, 2 * eps * q / u**3 - 6 * eps * omega2 / u**2
            assert abs(Pi - _v(lim, "interior_pi")) < mpf("1e-18")
            S, C = mp.sin(th1), mp.cos(th1)
            r1 = (1 - gamma) * S * C / (C * C + gamma * S * S)
            tip = (W, -W * r1)
        else:
            tip = (mpf(0), mpf(0))
        tol = mpf("1e-15")
        assert abs(y1[0] - th1) < tol and abs(y1[1]) < tol
        assert abs(y1[2] - _v(lim, "x1")) < tol and abs(y1[3] - h1) < tol
        assert abs(y1[4] - tip[0]) < tol and abs(y1[5] - tip[1]) < tol
    finally:
        mp.dps = 40


def test_porous_state_by_odefun():
    """A state of moderate kappa, re-integrated from its base values by mpmath.odefun: the
    free tip (theta' = F = 0), the tip values and the flux of the bed."""
    s = next(s for s in STATES if s["kappa"] == 1.0 and s["drive"] == "wall" and s["eps"] > 0)
    mp.dps = 20
    try:
        kappa, g1 = mpf(s["kappa"]), 1 - mpf(s["gamma"])

        def rhs(_s, y):
            th, m, x, z, w, Q, Fx, Fz, _phi = y
            S, C = mp.sin(th), mp.cos(th)
            fx, fz = w / kappa * (1 - g1 * S * S), -w / kappa * g1 * S * C
            return [m, -(Fx * C - Fz * S), S, C, C * Q, fx, -fx, -fz, w * C]

        y0 = [mpf(s["theta0"]), _v(s, "base_curvature"), 0, 0, 0, _v(s, "Q0")]
        y0 += [_v(s, "drag_x"), _v(s, "drag_z"), 0]
        y1 = odefun(rhs, 0, [mpf(v) for v in y0])(1)
        tol = mpf("1e-15")
        assert abs(y1[1]) < tol and abs(y1[6]) < tol and abs(y1[7]) < tol
        for j, key in enumerate(("theta1", None, "x1", "h1", "w1", "Q1", None, None, "flux_bed")):
            if key:
                assert abs(y1[j] - _v(s, key)) < tol, key
    finally:
        mp.dps = 40


def test_header_records_digits_and_timing():
    assert DATA_["dps"] >= 40 and DATA_["method2_dps"] >= 40
    assert DATA_["seconds_total"] > 0
    assert set(DATA_["seconds_per_job"]) >= {s["job"] for s in STATES}
    assert math.isclose(DATA_["gray_hancock"]["gamma"], float(_gray_hancock(20)), rel_tol=1e-15)
