"""hairbed.solve_loaded: a tip load plus a load per unit height (issue 20, item 1).

Checked against what shares no code with the Chebyshev collocation:

* (a) at pi = 0 the wall-driven closed form ``hairbed.solve`` (elliptic functions), also in
  the bistable windows (every root of ``hairbed.solve_all``), with the solver started from
  other states of the branch (``from_parameter`` at a shifted t), so the agreement is the
  solver's, not its start's;
* (b) the small-load limit x1 = W/3 + Pi/8 of a cantilever at theta0 = 0, whose remainder
  relative to x1 shrinks like the load squared (x1 is odd in the loads there);
* (c) the base-moment identity theta'(0) = W h1 + Pi h1^2/2 on every returned state;
* (d) bad input;
* (e) strong loads (W, Pi to 1e4): converged, and the error estimate honest against N doubled;
  moderate loads against ``scipy.integrate.solve_bvp`` at a tight tolerance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_bvp
from tolerances import (
    LOADED_BVP_ATOL,
    LOADED_CLOSED_FORM_ATOL,
    LOADED_ESTIMATE_MARGIN,
    LOADED_IDENTITY_RTOL,
    LOADED_LIMIT_SLOPE_ATOL,
)

import hairbed

FIELDS = ("tip_height", "tip_deflection", "tip_angle")


def _identity(st):
    """(c) on every state: theta'(0) = W h1 + Pi h1^2/2, relative to max(1, |theta'(0)|)."""
    ok = np.asarray(st.status) >= 0
    h = np.asarray(st.tip_height)[ok]
    rhs = np.asarray(st.tip_load)[ok] * h + 0.5 * np.asarray(st.distributed_load)[ok] * h * h
    lhs = np.asarray(st.base_curvature)[ok]
    scale = np.maximum(1.0, np.abs(lhs))
    assert np.all(np.abs(lhs - rhs) <= LOADED_IDENTITY_RTOL * scale)
    bad = ~ok
    for name in (*FIELDS, "base_curvature", "tip_load", "error_estimate"):
        assert np.all(np.isnan(np.asarray(getattr(st, name))[bad])), name  # no NaN dressed up


def _agree_with_closed_form(st, ref):
    for name in FIELDS:
        assert np.max(np.abs(np.asarray(getattr(st, name)) - getattr(ref, name))) <= (
            LOADED_CLOSED_FORM_ATOL
        ), name
    curv = np.asarray(ref.base_curvature)
    diff = np.abs(np.asarray(st.base_curvature) - curv)
    assert np.all(diff <= LOADED_CLOSED_FORM_ATOL * np.maximum(1.0, np.abs(curv)))


# (a) -----------------------------------------------------------------------------------


def test_pi_zero_matches_closed_form_on_a_grid():
    rng = np.random.default_rng(20)
    size = 400
    omega2 = 10.0 ** rng.uniform(-6, 4, size)
    eps = rng.uniform(0.0, 0.99, size)
    theta0 = rng.uniform(-1.5, 1.5, size)
    ref = hairbed.solve(omega2, eps, theta0)
    st = hairbed.solve_loaded(omega2, eps, theta0, pi=0.0)
    assert np.all(st.status == 0)
    _agree_with_closed_form(st, ref)
    _identity(st)
    assert np.allclose(st.tip_load * (1 - eps * st.tip_height), omega2, rtol=1e-13, atol=0)
    assert np.all(st.distributed_load == 0.0)


def test_pi_zero_from_shifted_starts():
    """The solver, not its start: begun from other states of the branch (t shifted by -1..1)."""
    rng = np.random.default_rng(21)
    size = 200
    omega2 = 10.0 ** rng.uniform(-3, 3, size)
    eps = rng.uniform(0.0, 0.9, size)
    theta0 = rng.uniform(-1.2, 1.2, size)
    ref = hairbed.solve(omega2, eps, theta0)
    guess = hairbed.from_parameter(ref.t + rng.uniform(-1.0, 1.0, size), eps, theta0)
    st = hairbed.solve_loaded(omega2, eps, theta0, guess=guess)
    assert np.all(st.status == 0)
    assert np.all(st.nit >= 3)  # it had work to do
    _agree_with_closed_form(st, ref)
    _identity(st)


@pytest.mark.parametrize(
    ("eps", "theta0", "low", "high"),
    [(0.95, -1.2, 0.4642, 0.5518), (0.9, -1.2, 0.5847, 0.6017), (0.95, -1.0, 0.3011, 0.3189)],
)
def test_pi_zero_every_state_of_a_bistable_window(eps, theta0, low, high):
    count = 0
    for omega2 in np.linspace(low, high, 7)[1:-1]:
        states = [s for s in hairbed.solve_all(omega2, eps, theta0) if s.physical]
        assert len(states) == 3
        for s in states:
            for shift in (-0.05, 0.05):
                guess = hairbed.from_parameter(s.t + shift, eps, theta0)
                st = hairbed.solve_loaded(omega2, eps, theta0, guess=guess)
                assert st.status == 0
                _agree_with_closed_form(st, s)
                _identity(st)
                count += 1
        for root, s in zip(("low", "mid", "high"), states):
            st = hairbed.solve_loaded(omega2, eps, theta0, root=root)
            _agree_with_closed_form(st, s)
    assert count == 30


def test_negative_wall_forcing_is_the_mirror():
    st = hairbed.solve_loaded(-3.0, 0.5, 0.3)
    ref = hairbed.solve(3.0, 0.5, -0.3)
    assert st.status == 0
    assert st.tip_height == pytest.approx(ref.tip_height, abs=LOADED_CLOSED_FORM_ATOL)
    assert st.tip_deflection == pytest.approx(-ref.tip_deflection, abs=LOADED_CLOSED_FORM_ATOL)
    assert st.tip_angle == pytest.approx(-ref.tip_angle, abs=LOADED_CLOSED_FORM_ATOL)


# (b) -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("drive", "omega2", "eps"),
    [("pressure", 0.0, 0.5), ("pressure", 1.0, 0.3), ("flow", 0.0, 0.5), ("flow", 1.0, 0.4)],
)
def test_small_load_limit(drive, omega2, eps):
    """x1 = W/3 + Pi/8 + O(load^3) at theta0 = 0: the remainder relative to x1 falls like the
    load squared (slope 2 of log |remainder/x1| against log load, fitted)."""
    scale = np.geomspace(1e-3, 3e-2, 8)
    load = 2.0 * scale
    kw = {"pi": load} if drive == "pressure" else {"q": load}
    st = hairbed.solve_loaded(omega2 * scale, eps, 0.0, **kw)
    assert np.all(st.status == 0)
    _identity(st)
    lead = st.tip_load / 3.0 + st.distributed_load / 8.0
    rel = np.abs(st.tip_deflection - lead) / np.abs(st.tip_deflection)
    slope = np.polyfit(np.log(scale), np.log(rel), 1)[0]
    assert abs(slope - 2.0) <= LOADED_LIMIT_SLOPE_ATOL
    ratios = rel[1:] / rel[:-1]
    step = scale[1] / scale[0]
    assert np.allclose(ratios, step**2, rtol=0.05)
    assert np.all(rel < 0.05)


# (c) and the state's own consistency ------------------------------------------------------


@pytest.mark.parametrize("drive", ["pressure", "flow"])
def test_identity_and_shape_on_random_states(drive):
    rng = np.random.default_rng(22 if drive == "pressure" else 23)
    size = 300
    omega2 = 10.0 ** rng.uniform(-4, 3, size) * rng.choice([0.0, 1.0, -1.0], size)
    eps = rng.uniform(0.01, 0.99, size)
    theta0 = rng.uniform(-1.5, 1.5, size)
    load = 10.0 ** rng.uniform(-6, 4, size) * rng.choice([1.0, -1.0], size)
    kw = {"pi": load} if drive == "pressure" else {"q": load}
    st = hairbed.solve_loaded(omega2, eps, theta0, **kw)
    _identity(st)
    assert np.mean(st.status == 0) > 0.97
    assert set(np.unique(st.status)) <= {0, 3, -2, -3, -7}
    ok = st.status == 0
    s, x, z, theta = st.shape(np.array([0.0, 0.5, 1.0]))
    assert np.allclose(theta[ok, 0], theta0[ok], atol=1e-13, rtol=0)
    assert np.all(np.abs(x[ok, 0]) <= 1e-13) and np.all(np.abs(z[ok, 0]) <= 1e-13)
    for got, name in (
        (x[:, 2], "tip_deflection"),
        (z[:, 2], "tip_height"),
        (theta[:, 2], "tip_angle"),
    ):
        assert np.allclose(got[ok], getattr(st, name)[ok], atol=1e-12, rtol=0), name
    # the drive's loads at the state, recomputed here from its formulas
    h, u = st.tip_height, 1.0 - eps * st.tip_height
    if drive == "pressure":
        with np.errstate(divide="ignore", invalid="ignore"):
            w = omega2 / u + np.where(load != 0, 0.5 * load * (1 / eps - h), 0.0)
        p = load
    else:
        w = load / u**2 - 2 * omega2 / u
        p = 2 * eps * load / u**3 - 6 * eps * omega2 / u**2
    assert np.allclose(st.tip_load[ok], w[ok], rtol=1e-13, atol=1e-300)
    assert np.allclose(st.distributed_load[ok], p[ok], rtol=1e-13, atol=1e-300)


def test_scalar_and_array_agree():
    one = hairbed.solve_loaded(1.5, 0.6, 0.2, q=3.0)
    many = hairbed.solve_loaded([1.5, 1.5], 0.6, 0.2, q=3.0)
    assert isinstance(one.tip_height, float) and isinstance(one.status, int)
    assert many.tip_height.shape == (2,)
    for name in (*FIELDS, "base_curvature"):
        assert getattr(many, name)[1] == getattr(one, name)
    assert one.success is True and one.message == "ok"
    assert one.drive == "flow" and math.isnan(one.pi) and one.q == 3.0


# (d) -----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        ({"omega2": 1.0, "eps": 0.5, "pi": 1.0, "q": 1.0}, ["pi", "q", "both"]),
        ({"omega2": 1.0, "eps": 0.0, "pi": 1.0}, ["pi", "eps"]),
        ({"omega2": 1.0, "eps": [0.5, 0.0], "pi": 1.0}, ["pi", "eps", "index 1"]),
        ({"omega2": math.nan, "eps": 0.5}, ["omega2"]),
        ({"omega2": math.inf, "eps": 0.5, "q": 1.0}, ["omega2"]),
        ({"omega2": 1.0, "eps": 1.0}, ["eps", "[0, 1)"]),
        ({"omega2": 1.0, "eps": -0.1}, ["eps", "[0, 1)"]),
        ({"omega2": 1.0, "eps": [0.2, 0.5, 1.2]}, ["eps", "index 2"]),
        ({"omega2": 1.0, "eps": 0.5, "theta0": 1.6}, ["theta0", "(-pi/2, pi/2)"]),
        ({"omega2": 1.0, "eps": 0.5, "pi": math.inf}, ["pi"]),
        ({"omega2": 1.0, "eps": 0.5, "q": math.nan}, ["q"]),
        ({"omega2": 1.0, "eps": 0.5, "num": 4}, ["num"]),
        ({"omega2": 1.0, "eps": 0.5, "rtol": -1.0}, ["rtol"]),
        ({"omega2": 1.0, "eps": 0.5, "root": "middle"}, ["root"]),
        ({"omega2": [1.0, 2.0], "eps": [0.5, 0.5, 0.5]}, ["broadcast"]),
    ],
)
def test_bad_input(kwargs, words):
    with pytest.raises(ValueError) as info:
        hairbed.solve_loaded(**kwargs)
    for word in words:
        assert word in str(info.value)


def test_bad_guess_and_shape_arguments():
    with pytest.raises(TypeError, match="guess"):
        hairbed.solve_loaded(1.0, 0.5, guess=0.7)
    st = hairbed.solve_loaded(1.0, 0.5, pi=1.0)
    with pytest.raises(ValueError, match=r"s must lie in \[0, 1\]"):
        st.shape([0.5, 1.5])


# (e) -----------------------------------------------------------------------------------

STRONG = [("pressure", 0.0, 0.5, t0, 1e4) for t0 in (-1.5, -0.7, 0.0, 0.7, 1.5)] + [
    ("pressure", 1e4, 0.99, 0.0, 1e-6),
    ("pressure", 1e4, 0.2, -1.5, 1e4),
    ("flow", 0.0, 0.5, 0.0, 1e4),
    ("flow", 0.0, 0.9, -1.5, 1e4),
    ("flow", 0.0, 0.2, 1.5, 5e3),
    ("flow", 1e3, 0.5, 0.3, 1e4),
]


@pytest.mark.parametrize(("drive", "omega2", "eps", "theta0", "load"), STRONG)
def test_strong_loads_converge_with_an_honest_estimate(drive, omega2, eps, theta0, load):
    kw = {"pi": load} if drive == "pressure" else {"q": load}
    st = hairbed.solve_loaded(omega2, eps, theta0, **kw)
    assert st.status == 0, st.message
    _identity(st)
    assert max(abs(st.tip_load), abs(st.distributed_load)) >= 1e3
    fine = hairbed.solve_loaded(omega2, eps, theta0, num=2 * st.num, **kw)
    assert fine.status == 0
    bound = LOADED_ESTIMATE_MARGIN * (st.error_estimate + fine.error_estimate)
    for name in FIELDS:
        assert abs(getattr(st, name) - getattr(fine, name)) <= bound, name
    grid = np.linspace(0.0, 1.0, 41)
    for a, b in zip(st.shape(grid)[1:], fine.shape(grid)[1:]):
        assert np.max(np.abs(a - b)) <= bound
    assert st.error_estimate <= 1e-10


def test_estimate_honest_on_random_states():
    """Against N doubled, over moderate and strong loads of both drives."""
    rng = np.random.default_rng(24)
    size = 200
    omega2 = 10.0 ** rng.uniform(-3, 3, size)
    eps = rng.uniform(0.05, 0.95, size)
    theta0 = rng.uniform(-1.4, 1.4, size)
    load = 10.0 ** rng.uniform(-3, 4, size)
    for kw in ({"pi": load}, {"q": load}):
        st = hairbed.solve_loaded(omega2, eps, theta0, **kw)
        ok = st.status == 0
        for num in (32, 64):
            sel = ok & (st.num == num)
            if not np.any(sel):
                continue
            fine = hairbed.solve_loaded(
                omega2[sel],
                eps[sel],
                theta0[sel],
                num=2 * num,
                **{k: v[sel] for k, v in kw.items()},
            )
            bound = LOADED_ESTIMATE_MARGIN * (st.error_estimate[sel] + fine.error_estimate)
            for name in FIELDS:
                assert np.all(np.abs(getattr(st, name)[sel] - getattr(fine, name)) <= bound)


def _bvp_reference(drive, omega2, eps, theta0, load, start):
    """An independent solution by scipy's solve_bvp (h1 as its unknown parameter), at a loose
    tolerance first and then at 1e-10 from that solution. ``start`` (a LoadedState, or None
    for the hair at rest) only seeds its first Newton iteration, on a coarse mesh of 21
    points; its own iteration and mesh refinement then converge to its own solution."""

    def loads(h):
        u = 1.0 - eps * h
        if drive == "pressure":
            return omega2 / u + 0.5 * load * (1.0 / eps - h), load
        return load / u**2 - 2 * omega2 / u, 2 * eps * load / u**3 - 6 * eps * omega2 / u**2

    def fun(s, y, p):
        w, pi = loads(p[0])
        th, m, z, x = y
        return np.vstack([m, -(w + pi * (p[0] - z)) * np.cos(th), np.cos(th), np.sin(th)])

    def bc(ya, yb, p):
        return np.array([ya[0] - theta0, yb[1], ya[2], ya[3], yb[2] - p[0]])

    s = np.linspace(0.0, 1.0, 21)
    if start is None:
        y = np.vstack([theta0 + 0 * s, 0 * s, s * math.cos(theta0), s * math.sin(theta0)])
        p0 = math.cos(theta0)
    else:
        _, x, z, th = start.shape(s)
        y = np.vstack([th, np.gradient(th, s), z, x])
        p0 = start.tip_height
    sol = solve_bvp(fun, bc, s, y, p=[p0], tol=1e-6)
    assert sol.success, sol.message
    sol = solve_bvp(fun, bc, sol.x, sol.y, p=sol.p, tol=1e-10, bc_tol=1e-12, max_nodes=100000)
    assert sol.success, sol.message
    return sol.p[0], sol.sol(1.0)[3], sol.sol(1.0)[0], sol.sol(0.0)[1]


@pytest.mark.parametrize(
    ("drive", "omega2", "eps", "theta0", "load"),
    [
        ("pressure", 0.0, 0.5, 0.0, 2.0),
        ("pressure", 1.0, 0.3, 0.5, 5.0),
        ("pressure", 0.5, 0.8, -0.6, 1.0),
        ("flow", 0.0, 0.5, 0.0, 3.0),
        ("flow", 2.0, 0.4, 0.8, 8.0),
        ("flow", 0.0, 0.7, -0.4, 1.5),
    ],
)
def test_against_solve_bvp(drive, omega2, eps, theta0, load):
    kw = {"pi": load} if drive == "pressure" else {"q": load}
    st = hairbed.solve_loaded(omega2, eps, theta0, **kw)
    assert st.status == 0
    h1, x1, th1, curv = _bvp_reference(
        drive, omega2, eps, theta0, load, None if theta0 >= 0 else st
    )
    assert st.tip_height == pytest.approx(h1, abs=LOADED_BVP_ATOL)
    assert st.tip_deflection == pytest.approx(x1, abs=LOADED_BVP_ATOL)
    assert st.tip_angle == pytest.approx(th1, abs=LOADED_BVP_ATOL)
    assert st.base_curvature == pytest.approx(curv, abs=LOADED_BVP_ATOL * max(1, abs(curv)))


# every coexisting state (solve_loaded_all) ------------------------------------------------


@pytest.mark.parametrize(("eps", "theta0", "low", "high"), [(0.95, -1.2, 0.4642, 0.5518)])
def test_all_states_count_through_a_pi_zero_window(eps, theta0, low, high):
    """The count of states on a grid through the window equals the closed form's."""
    width = high - low
    for omega2 in np.linspace(low - 0.2 * width, high + 0.2 * width, 13):
        ref = [s for s in hairbed.solve_all(omega2, eps, theta0) if s.physical]
        found = hairbed.solve_loaded_all(omega2, eps, theta0)
        assert len(found) == len(ref)
        for st, s in zip(found, ref):
            _agree_with_closed_form(st, s)
            _identity(st)
        if len(found) == 3:
            assert [s.stable for s in found] == [True, False, True]


def test_all_states_of_a_flow_window():
    """A bistable window of the flow drive (eps = 0.9, theta0 = -1.2, wall at rest): counts 1,
    3, ..., 3, 1; every state checked against solve_bvp; the ends are solve_loaded's low and
    high states."""
    eps, theta0 = 0.9, -1.2
    counts = []
    for q in np.geomspace(0.01, 10.0, 40)[4:18]:
        found = hairbed.solve_loaded_all(0.0, eps, theta0, q=q)
        counts.append(len(found))
        for st in found:
            assert st.status == 0
            _identity(st)
        if len(found) == 3:
            assert [s.stable for s in found] == [True, False, True]
            for st in found:
                h1, x1, th1, _ = _bvp_reference("flow", 0.0, eps, theta0, q, st)
                assert st.tip_height == pytest.approx(h1, abs=LOADED_BVP_ATOL)
                assert st.tip_deflection == pytest.approx(x1, abs=LOADED_BVP_ATOL)
                assert st.tip_angle == pytest.approx(th1, abs=LOADED_BVP_ATOL)
            lo = hairbed.solve_loaded(0.0, eps, theta0, q=q, root="low")
            hi = hairbed.solve_loaded(0.0, eps, theta0, q=q, root="high")
            assert abs(lo.tip_height - found[0].tip_height) <= 1e-12
            assert abs(hi.tip_height - found[-1].tip_height) <= 1e-12
    assert counts[0] == 1 and counts[-1] == 1 and 3 in counts
    inner = counts[counts.index(3) : len(counts) - counts[::-1].index(3)]
    assert set(inner) == {3}


def test_all_states_bad_input():
    with pytest.raises(ValueError, match="scalar"):
        hairbed.solve_loaded_all([1.0, 2.0], 0.5)
    with pytest.raises(ValueError, match="num_scan"):
        hairbed.solve_loaded_all(1.0, 0.5, num_scan=2)
    with pytest.raises(ValueError, match="pi"):
        hairbed.solve_loaded_all(1.0, 0.0, pi=1.0)


def test_failure_statuses_are_honest():
    """Status 3 where the grid cannot reach the tolerance, -1 where the state does not exist:
    never a NaN dressed as a state, never an estimate below the tolerance with a caveat."""
    coarse = hairbed.solve_loaded(0.0, 0.5, 0.0, pi=1e4, num=8)
    assert coarse.status == 3 and coarse.success is False
    assert coarse.error_estimate > 1e-12 and np.isfinite(coarse.tip_height)
    assert "inaccurate" in coarse.message
    fine = hairbed.solve_loaded(0.0, 0.5, 0.0, pi=1e4)
    assert abs(coarse.tip_height - fine.tip_height) <= coarse.error_estimate + fine.error_estimate
    none = hairbed.solve_loaded(2.0, 0.5, 0.0, root="mid")
    assert none.status == -1 and none.success is False
    assert np.isnan(none.tip_height) and np.isnan(none.error_estimate)
    assert np.all(np.isnan(none.shape([0.0, 1.0])[1]))
    _identity(none)


@pytest.mark.parametrize("drive", [{}, {"pi": 0.0}, {"q": 0.0}])
@pytest.mark.parametrize("theta0", [-1.2, 0.0, 0.7])
def test_no_load_at_all_is_the_hair_at_rest(drive, theta0) -> None:
    """omega2 = 0 and no pump: the straight hair, x1 = sin(theta0), h1 = cos(theta0)."""
    st = hairbed.solve_loaded(0.0, 0.6, theta0, **drive)
    assert st.status == 0
    assert st.tip_deflection == pytest.approx(math.sin(theta0), abs=1e-14)
    assert st.tip_height == pytest.approx(math.cos(theta0), abs=1e-14)
    assert abs(st.base_curvature) < 1e-14


def test_huge_loads_say_so_without_a_warning() -> None:
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st = hairbed.solve_loaded(1e308, 0.5, 0.3, pi=1e308)
    assert st.status != 0 and math.isnan(st.tip_deflection)
