"""Exact derivatives (hairbed.derivatives) against mpmath and finite differences of solve.

References, both independent of the implicit differentiation under test:

* ``tests/data/derivatives_mpmath.json`` (``tests/reference/generate_derivatives.py``, nothing
  from hairbed): mpmath.diff at 32 digits of the composite map inputs -> root t of the branch
  equation -> outputs, the tip height and deflection by quadrature of the closed-form shape;
* fourth-order central differences of :func:`hairbed.solve` in double precision.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed.sensitivity import INPUTS, OUTPUTS, STATUS_MESSAGES, derivatives_at

DATA = Path(__file__).parent / "data" / "derivatives_mpmath.json"
#: Measured against the mpmath set (22 cases, omega2 from 1e-13 to 1e3, every branch; 11 more
#: at strong forcing, omega2 from 4.2e2 to 1e8, are within 1.1e-15): at most
#: 1.1e-14 relative on every output and input (d base_curvature/d theta0 at theta0 = -1.5), in
#: most cases 3e-15, including weak forcing (t = -8 ... -30). The exception is a derivative
#: that vanishes to first order, as d omega_eps/d theta0 and d(tip_displacement)/d theta0 do
#: near theta0 = 0 at moderate forcing (the case t = -2.5, theta0 = -0.05; at weak forcing the
#: series takes over): it is a sum of terms as large as the output's other partials, so its
#: error is a few ulps of those (2e-17 absolute, 1e-13 relative on -2.1e-4).
MPMATH_RTOL = 5e-14
#: ... hence the absolute floor: this many times the largest partial of the same output.
MPMATH_ULPS = 2e-16


#: ... and below the smallest normal double (xi's derivatives at t > 708, ~exp(-t)) a value
#: has fewer than 16 digits at all: there they are compared absolutely, at that size.
SUBNORMAL = float(np.finfo(np.float64).tiny)


def _tolerance(case: dict, output: str, ref: float) -> float:
    scale = max(abs(float(v)) for v in case["derivatives"][output].values())
    return MPMATH_RTOL * abs(ref) + MPMATH_ULPS * scale + SUBNORMAL


#: Finite differences of solve: truncation h^4 ~ 1e-16, rounding 1e-16/h ~ 1e-12 relative to
#: the output, far more relative to a small derivative (hence the scale).
FD_RTOL = 1e-6


def _cases() -> list[dict]:
    return json.loads(DATA.read_text())["cases"]


@pytest.mark.parametrize("case", _cases(), ids=lambda c: f"t{c['t']}_e{c['eps']}_th{c['theta0']}")
def test_against_mpmath(case: dict) -> None:
    sol = hairbed.from_parameter(
        case["t"], case["eps"], case["theta0"], sign=case["sign"], n=case["n"]
    )
    assert sol.omega2 == pytest.approx(float(case["omega2"]), rel=1e-13)
    d = derivatives_at(sol)
    assert d.status == 0 and d.success
    for o in OUTPUTS:
        for p in INPUTS:
            ref = float(case["derivatives"][o][p])
            tol = _tolerance(case, o, ref)
            assert abs(d[o][p] - ref) <= tol, (o, p, d[o][p], ref)


def test_against_mpmath_through_solve() -> None:
    """derivatives(omega2, ...) on the physical branch (monotone cases) gives the same."""
    for case in _cases():
        if case["sign"] != 1 or case["n"] != 0 or case["theta0"] < 0:
            continue
        d = hairbed.derivatives(float(case["omega2"]), case["eps"], case["theta0"])
        for o in OUTPUTS:
            for p in INPUTS:
                ref = float(case["derivatives"][o][p])
                # the forcing rounded to a double: the state moves by ~1e-16 relative
                tol = 1e-12 * abs(ref) + _tolerance(case, o, ref)
                assert abs(d[o][p] - ref) <= tol, (case, o, p)


FD_CASES = [
    (2.0, 0.5, 0.0, {}),
    (0.3, 0.9, 0.4, {}),
    (50.0, 0.3, -0.7, {}),
    (0.01, 0.2, 1.2, {}),
    (1.2, 0.9, -1.5, {"root": "low"}),
    (1.2, 0.9, -1.5, {"root": "mid"}),
    (1.2, 0.9, -1.5, {"root": "high"}),
    (60.0, 0.5, 0.2, {"sign": -1}),
    (200.0, 0.5, 0.1, {"n": 1}),
    (300.0, 0.5, 0.1, {"sign": -1, "n": 1}),
]


def _fd(w: float, e: float, th: float, name: str, h: float, kw: dict) -> np.ndarray:
    def f(dx: float) -> np.ndarray:
        a = {"omega2": w, "eps": e, "theta0": th}
        a[name] += dx
        s = hairbed.solve(a["omega2"], a["eps"], a["theta0"], **kw)
        return np.array([getattr(s, o) for o in OUTPUTS])

    return (-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h)


@pytest.mark.parametrize("w, e, th, kw", FD_CASES)
def test_against_finite_differences(w: float, e: float, th: float, kw: dict) -> None:
    d = hairbed.derivatives(w, e, th, **kw)
    assert d.success
    for name in INPUTS:
        h = 1e-4 * max(1.0, abs(w)) if name == "omega2" else 1e-4
        ref = _fd(w, e, th, name, h, kw)
        got = np.array([d[o][name] for o in OUTPUTS])
        err = np.abs(got - ref) / np.maximum(np.abs(ref), 1e-3)
        assert np.all(err < FD_RTOL), (name, dict(zip(OUTPUTS, err)))


def test_vectorised_equals_elementwise() -> None:
    w = np.array([[0.5, 1.2], [1.0, 1.4]])
    e = np.array([0.9, 0.95])
    th = -1.5
    d = hairbed.derivatives(w, e, th, root="high")
    assert np.shape(d["xi"]["omega2"]) == (2, 2)
    for i in range(2):
        for j in range(2):
            one = hairbed.derivatives(float(w[i, j]), float(e[j]), th, root="high")
            for o in OUTPUTS:
                for p in INPUTS:
                    assert d[o][p][i, j] == pytest.approx(one[o][p], rel=1e-13, abs=1e-300)


def test_mapping_interface() -> None:
    d = hairbed.derivatives(2.0, 0.5)
    assert list(d) == list(OUTPUTS) and len(d) == 8
    assert all(list(d[o]) == list(INPUTS) for o in d)
    assert isinstance(d["xi"]["eps"], float)
    with pytest.raises(TypeError):
        d["xi"]["eps"] = 0.0  # type: ignore[index]
    plain = d.as_dict()
    assert json.dumps(plain)
    assert d.message == STATUS_MESSAGES[0]


def test_infinite_at_a_fold() -> None:
    f = hairbed.branches.folds(0.9, -1.5)
    sol = hairbed.from_parameter(f.t, 0.9, -1.5)
    d = derivatives_at(sol)
    assert np.all(d.status == 1) and np.all(d.at_fold)
    assert not np.any(d.success)
    assert d.message == [STATUS_MESSAGES[1]] * 2
    for o in OUTPUTS:
        for p in INPUTS:
            assert np.all(np.isinf(d[o][p])), (o, p)
    # next to the fold the derivatives are finite and grow like 1/sqrt(distance)
    near = hairbed.from_parameter(f.t + 1e-4, 0.9, -1.5)
    assert np.all(derivatives_at(near).success)


def test_no_such_state_is_nan() -> None:
    d = hairbed.derivatives(5.0, 0.9, -1.5, root="mid")  # outside the window
    assert d.status == -1 and np.isnan(d["xi"]["omega2"])
    assert d.message == STATUS_MESSAGES[-1]


def test_at_rest_limits() -> None:
    """omega2 = 0: the weak-forcing limits, continuous with small omega2."""
    for e, th in ((0.5, 0.0), (0.3, 0.7), (0.9, -1.0)):
        d0 = hairbed.derivatives(0.0, e, th)
        d1 = hairbed.derivatives(1e-8, e, th)  # differs by O(omega2)
        assert d0.success
        c = np.cos(th)
        # the cantilever under a point load at the tip: x1 - sin theta0 = omega_eps^2 c^2/3
        assert d0["tip_deflection"]["omega2"] == pytest.approx(c * c / (3 * (1 - e * c)))
        assert d0["omega_eps"]["omega2"] == np.inf
        for o in OUTPUTS:
            if o == "omega_eps":
                continue
            for p in INPUTS:
                assert d0[o][p] == pytest.approx(d1[o][p], rel=1e-5, abs=1e-6), (o, p)


def test_rejects_bad_input() -> None:
    with pytest.raises(ValueError, match="eps"):
        hairbed.derivatives(1.0, 1.0)
    with pytest.raises(ValueError, match="root"):
        hairbed.derivatives(1.0, 0.5, root="middle")
    with pytest.raises(TypeError, match="Solution"):
        derivatives_at(object())  # type: ignore[arg-type]


def test_end_of_a_twirling_branch_is_said() -> None:
    d = derivatives_at(hairbed.from_parameter(-np.inf, 0.5, 0.2, sign=-1))
    assert d.status == -5 and not d.success and np.isnan(d["xi"]["eps"])
    assert d.message == STATUS_MESSAGES[-5]
    # the physical branch's end is the hair at rest: the limits of weak forcing
    assert derivatives_at(hairbed.from_parameter(-np.inf, 0.5, 0.2)).success


#: The scan of every branch over the forcing (issue 19): omega2 from 1e-13 to 1e12, with the
#: band 3e4 < omega2 < 1.3e5 where p = (1 - xi)/2 falls from 1e-150 to underflow.
SCAN_OMEGA2 = np.concatenate([np.logspace(-13, 12, 2501), np.logspace(4.4, 5.2, 801)])
SCAN_EPS = np.array([0.0, 0.5, 0.9, 0.99])
SCAN_THETA0 = np.array([-1.5, -0.7, -0.05, 0.0, 0.3, 1.2, 1.55])


@pytest.mark.parametrize(
    "branch",
    [{}, {"root": "high"}, {"sign": -1}, {"n": 1}, {"sign": -1, "n": 1}],
    ids=["physical-low", "physical-high", "sign-1", "n1", "sign-1-n1"],
)
def test_scan_no_silent_non_finite(branch: dict) -> None:
    """Every derivative of a state with status 0 is finite, on a fine grid of the forcing."""
    w = SCAN_OMEGA2[:, None, None]
    d = hairbed.derivatives(w, SCAN_EPS[None, :, None], SCAN_THETA0[None, None, :], **branch)
    ok = np.asarray(d.status) == 0
    if "sign" not in branch and "n" not in branch:  # the physical branch: a state everywhere
        assert np.all(ok)
    else:
        assert np.count_nonzero(ok) > 0.3 * ok.size  # a twirling branch exists at high forcing
    for o in OUTPUTS:
        for p in INPUTS:
            bad = ok & ~np.isfinite(d[o][p])
            where = np.argwhere(bad)[:1].tolist()
            assert not np.any(bad), (o, p, int(np.count_nonzero(bad)), where)
    for p in INPUTS:
        assert np.all(np.isfinite(d.dt[p])[ok]), p


@pytest.mark.parametrize(
    "branch",
    [{}, {"sign": -1}, {"n": 1}, {"sign": -1, "n": 1}],
    ids=["physical", "s-1", "n1", "both"],
)
def test_tip_angle_at_strong_forcing(branch: dict) -> None:
    """The tip angle's derivatives ~ sqrt(1 - xi) ~ exp(-t/2) are normal doubles up to t = 1416,
    while 1 - xi = (1 - sin theta0) expit(-t) underflows at t = 745: they must not vanish.

    Reference: the tip angle's distance to +-pi/2 is delta = 2 arcsin(sqrt(p)),
    p = Y expit(-t), Y = (1 - sin theta0)/2, so that delta_t = -sqrt(Y) exp(-t/2) and
    delta_theta0 = -cos(theta0) exp(-t/2)/(2 sqrt(Y)) at fixed t (to relative O(exp(-t))),
    and dt/d(omega2, eps, theta0) from central differences of omega2(t, eps, theta0).
    """
    e, th = 0.5, 0.3
    y = (1.0 - np.sin(th)) / 2.0

    def w2(t: float, ee: float, tth: float) -> float:
        return float(hairbed.from_parameter(t, ee, tth, **branch).omega2)

    for t in (600.0, 720.0, 800.0, 1200.0):
        d = derivatives_at(hairbed.from_parameter(t, e, th, **branch))
        assert d.success
        h = 1e-4  # truncation ~1e-9, rounding ~1e-16 t/h ~ 1e-9 relative
        w_t = (w2(t + h, e, th) - w2(t - h, e, th)) / (2 * h)
        w_e = (w2(t, e + h, th) - w2(t, e - h, th)) / (2 * h)
        w_th = (w2(t, e, th + h) - w2(t, e, th - h)) / (2 * h)
        dt = {"omega2": 1.0 / w_t, "eps": -w_e / w_t, "theta0": -w_th / w_t}
        delta_t = -np.sqrt(y) * np.exp(-t / 2)
        delta_th = -np.cos(th) * np.exp(-t / 2) / (2.0 * np.sqrt(y))
        for name in INPUTS:
            ref = delta_t * dt[name] + (delta_th if name == "theta0" else 0.0)
            assert abs(d["tip_angle"][name]) == pytest.approx(abs(ref), rel=1e-7, abs=0.0), (
                t,
                name,
            )
