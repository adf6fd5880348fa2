"""Pillars leaning onto the wall (issue 33, item 7): every state, theta0 up to -1.57.

A pillar tilted upstream to within a few hundredths of a radian of the wall has a snap-through
window from Lambda ~ 17 up to a fold that grows without bound as theta0 -> -pi/2 (127 at -1.55,
3306 at -1.57), and at a large forcing it lies downstream with a boundary layer at its base.
Before, 85 of 400 forcings from 1e-3 to 1e5 had no state at theta0 = -1.54, 106 at -1.55, 318
at -1.565 and all 400 at -1.57. Here, independently of the solver's collocation:

- every one of the 400 forcings has a state (status 0, one or three of them), whose shape
  satisfies the moment balance in its integrated form, theta(s) = theta0 + int_0^s m with
  m(s) = int_s^1 (F_x cos theta - F_z sin theta) and F(s) = int_s^1 f, by quadratures of
  the returned shape on a graded grid (not the collocation's differentiation), and whose base
  curvature is the integral m(0);
- the flow towards -x is the mirror image of the flow towards +x (theta0 -> -theta0);
- states in and around the window against scipy's ``solve_bvp`` (a different method: a
  fourth-order collocation on its own adaptive mesh), started from the returned shape;
- ``solve_pillar_all`` finds as many states as the crossings of the forcing along a dense
  scan of Lambda(x1) by the inverse problem (x1 fixed, Lambda an unknown);
- within 1e-4 of the wall (theta0 = -1.5707, -1.57075 and their mirror images), where x1 ~ -1
  rounds away the window's turn, every root of every forcing, as many as the crossings along
  this test's own scan of the branch in the tip displacement x1 - sin(theta0) by scipy's
  ``solve_bvp``, each balancing to 1e-10.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson, solve_bvp

import hairbed

GAMMA = 0.5
FORCINGS = np.geomspace(1e-3, 1e5, 400)
THETA0 = (-1.52, -1.54, -1.55, -1.56, -1.565, -1.57)
#: The integrated moment balance of a returned shape (quadrature on 2001 graded points).
BALANCE_RTOL = 1e-9
#: The same within 1e-4 of the wall (issue 33 item 7), on a grid graded less (b = 4).
WALL_BALANCE_RTOL = 1e-10
#: solve_bvp at tol 1e-9 (its relative residual) against the collocation.
BVP_RTOL = 1e-6


def _balance(
    st: hairbed.PillarState, points: int = 2001, grading: float = 8.0
) -> tuple[np.ndarray, np.ndarray]:
    """Per state: the largest misfit of theta(s) - theta0 - int_0^s m (relative to the
    largest turn of theta, at least 1) and of theta'(0) - m(0) (relative to max(1, |m(0)|)),
    all integrals by cumulative Simpson on a grid graded towards the base (s = expm1(b t)/
    expm1(b) at uniform t, b = ``grading``)."""
    b = grading
    s = np.expm1(b * np.linspace(0.0, 1.0, points)) / np.expm1(b)
    s[-1] = 1.0
    _, _, z, th = st.shape(s)
    th, z = np.atleast_2d(th), np.atleast_2d(z)
    lam = np.atleast_1d(np.asarray(st.forcing, dtype=np.float64))[:, None]
    c, sn = np.cos(th), np.sin(th)
    fx = lam * z * (c * c + GAMMA * sn * sn)  # the sublayer U(z) = z
    fz = -lam * z * (1.0 - GAMMA) * sn * c

    def tail(g: np.ndarray) -> np.ndarray:
        cum = cumulative_simpson(g, x=s, axis=-1, initial=0.0)
        return cum[:, -1:] - cum

    fx_in, fz_in = tail(fx), tail(fz)
    m = tail(fx_in * c - fz_in * sn)
    t0 = np.atleast_1d(np.asarray(st.theta0, dtype=np.float64))[:, None]
    rec = t0 + cumulative_simpson(m, x=s, axis=-1, initial=0.0)
    scale = np.maximum(1.0, np.max(np.abs(th - t0), axis=1))
    shape = np.max(np.abs(rec - th), axis=1) / scale
    base = np.abs(m[:, 0] - np.atleast_1d(st.base_curvature)) / np.maximum(1.0, np.abs(m[:, 0]))
    return shape, base


@pytest.mark.parametrize("theta0", THETA0)
def test_every_forcing_has_a_state_that_balances(theta0: float) -> None:
    st = hairbed.solve_pillar(FORCINGS, theta0)
    status = np.asarray(st.status)
    assert np.count_nonzero(status == 0) == FORCINGS.size, np.flatnonzero(status != 0)
    assert set(np.unique(st.n_states)) <= {1, 3}
    shape, base = _balance(st)
    assert shape.max() < BALANCE_RTOL, FORCINGS[shape.argmax()]
    assert base.max() < BALANCE_RTOL, FORCINGS[base.argmax()]
    # at a large forcing the pillar has flipped over and lies downstream near the wall
    assert float(st.tip_deflection[-1]) > 0.95


def test_window_states_balance_and_mirror() -> None:
    """The middle and far states of the window at -1.57 balance too, and a flow towards -x
    gives the mirror image x -> -x of every state (theta0 -> -theta0)."""
    lam = np.geomspace(20.0, 3000.0, 25)  # inside the window (17.7, 3306) at -1.57
    for root in ("mid", "high"):
        st = hairbed.solve_pillar(lam, -1.57, root=root)
        assert np.all(np.asarray(st.status) == 0)
        assert np.all(np.asarray(st.n_states) == 3)
        shape, base = _balance(st)
        assert shape.max() < BALANCE_RTOL and base.max() < BALANCE_RTOL
    fwd = hairbed.solve_pillar(FORCINGS, -1.57)
    back = hairbed.solve_pillar(-FORCINGS, 1.57)
    assert np.all(np.asarray(back.status) == 0)
    np.testing.assert_allclose(back.tip_deflection, -fwd.tip_deflection, rtol=0, atol=1e-11)
    np.testing.assert_allclose(back.tip_height, fwd.tip_height, rtol=0, atol=1e-11)


def _bvp(st: hairbed.PillarState) -> tuple[float, float, float]:
    """(x1, h1, theta'(0)) of scipy's solve_bvp at the state's forcing, from its shape."""
    t0, lam = float(st.theta0), float(st.forcing)
    s = np.expm1(8.0 * np.linspace(0.0, 1.0, 400)) / math.expm1(8.0)
    _, x, z, th = st.shape(s)
    c, sn = np.cos(th), np.sin(th)
    fx, fz = lam * z * (c * c + GAMMA * sn * sn), -lam * z * (1.0 - GAMMA) * sn * c
    cum_x = cumulative_simpson(fx, x=s, initial=0.0)
    cum_z = cumulative_simpson(fz, x=s, initial=0.0)
    y0 = np.vstack([th, np.gradient(th, s), cum_x[-1] - cum_x, cum_z[-1] - cum_z, x, z])

    def rhs(_s: np.ndarray, y: np.ndarray) -> np.ndarray:
        th, _m, fxi, fzi, _x, z = y
        c, sn = np.cos(th), np.sin(th)
        return np.vstack(
            [
                y[1],
                -(fxi * c - fzi * sn),
                -lam * z * (c * c + GAMMA * sn * sn),
                lam * z * (1.0 - GAMMA) * sn * c,
                sn,
                c,
            ]
        )

    def bc(ya: np.ndarray, yb: np.ndarray) -> np.ndarray:
        return np.array([ya[0] - t0, ya[4], ya[5], yb[1], yb[2], yb[3]])

    sol = solve_bvp(rhs, bc, s, y0, tol=1e-9, max_nodes=100000)
    assert sol.status == 0, sol.message
    return float(sol.y[4, -1]), float(sol.y[5, -1]), float(sol.y[1, 0])


@pytest.mark.parametrize(("theta0", "forcing"), [(-1.55, 5.0), (-1.55, 50.0), (-1.57, 300.0)])
def test_states_against_solve_bvp(theta0: float, forcing: float) -> None:
    states = hairbed.solve_pillar_all(forcing, theta0)
    assert len(states) == (1 if forcing < 17.0 else 3)
    for st in states:
        assert st.status == 0
        x1, h1, m0 = _bvp(st)
        assert abs(float(st.tip_deflection) - x1) < BVP_RTOL
        assert abs(float(st.tip_height) - h1) < BVP_RTOL
        assert abs(float(st.base_curvature) - m0) < BVP_RTOL * max(1.0, abs(m0))


@pytest.mark.parametrize("theta0", [-1.55, -1.57])
def test_solve_pillar_all_counts_the_crossings_of_a_dense_scan(theta0: float) -> None:
    rest = math.sin(theta0)
    u = np.concatenate(
        [np.geomspace(1e-10, 1e-3, 100, endpoint=False), np.linspace(1e-3, 0.97, 300)]
    )
    scan = hairbed.solve_pillar_inverse(rest + (1.0 - rest) * u, theta0)
    ok = np.asarray(scan.status) == 0
    # the inverse cannot fix Lambda from x1 within ~1e-4 of rest (x1 hardly moves there):
    # those points are left out, the branch is monotone there
    assert np.all(u[~ok] < 1e-3)
    lam = np.concatenate([[0.0], np.asarray(scan.forcing)[ok]])
    turns = np.flatnonzero(np.diff(lam)[:-1] * np.diff(lam)[1:] < 0.0) + 1
    assert turns.size == 2  # the window's two folds
    lam_max = float(np.asarray(scan.forcing)[ok][-1])
    tested = 0
    for forcing in np.geomspace(1e-2, 0.5 * lam_max, 24):
        if np.min(np.abs(lam[turns] / forcing - 1.0)) < 0.05:
            continue  # the scan's extreme points lie within a few per cent of the folds
        g = lam - forcing
        crossings = int(np.count_nonzero(g[:-1] * g[1:] < 0.0))
        states = hairbed.solve_pillar_all(forcing, theta0)
        assert len(states) == crossings, forcing
        assert all(s.status == 0 and s.n_states == crossings for s in states)
        np.testing.assert_allclose([float(s.forcing) for s in states], forcing, rtol=1e-12)
        tested += 1
    assert tested >= 20


@pytest.mark.parametrize(("theta0", "sign"), [(-1.57, 1.0), (1.57, -1.0), (-1.55, 1.0)])
def test_continue_pillar_has_both_folds_and_every_state_up_to_them(
    theta0: float, sign: float
) -> None:
    """The branch near the wall has both folds of the window (the upper one within ~1e-6 of
    rest in x1, under the grid's first point); just inside each fold solve_pillar_all finds
    three states, just outside one; the branch's points are in the order of x1."""
    br = hairbed.continue_pillar(sign * 1e4, theta0)
    assert br.status == 0
    assert np.all(np.diff(sign * br.tip_deflection) > 0.0)
    assert br.folds.shape == (2, 2)
    hi, lo = sorted(np.abs(br.folds[:, 0]), reverse=True)
    assert 17.0 < lo < 18.0 and hi > 100.0
    for lam, n in [(lo * 1.0001, 3), (hi * 0.9999, 3), (lo * 0.9999, 1), (hi * 1.0001, 1)]:
        assert len(hairbed.solve_pillar_all(sign * lam, theta0)) == n, lam


@functools.cache
def _bvp_branch(theta0: float) -> tuple[np.ndarray, np.ndarray]:
    """(d, Lambda) along the branch of a pillar leaning onto the wall (flow towards +x), by
    scipy's solve_bvp with Lambda as its unknown parameter, at given tip displacements
    d = x1 - sin(theta0) from 1e-13 to the wall: this test's own parametrisation (not the
    solver's collocation, its atlas or its inverse). The unknowns phi = theta - theta0, m =
    theta', F, xi = x - s sin(theta0) and z, each scaled by its size near rest (phi and m by
    d/cos(theta0), xi by d, z by cos(theta0), F by Lambda cos(theta0)), so that its tolerance
    means the same at d = 1e-13 as at d = 1; xi' = 2 cos(theta0 + phi/2) sin(phi/2) (no
    cancellation); each d started from the state of the one before (d is monotone along the
    branch, so no fold stops the march)."""
    c0 = math.cos(theta0)
    span = 1.0 - math.sin(theta0)
    ds = np.concatenate(
        [np.geomspace(1e-13, 1.0, 70), span - np.geomspace(span - 1.0, span - 1.9595, 32)[1:]]
    )
    mesh = np.linspace(0.0, 1.0, 41)
    y = np.zeros((6, mesh.size))
    y[0], y[4], y[5] = mesh, mesh, mesh  # phi ~ d s/c0, xi ~ d s, z ~ c0 s
    p = np.array([math.log(ds[0] / (11.0 * c0**3 / 120.0))])  # ln Lambda, linear theory
    scale_f = math.exp(p[0]) * c0
    lam, p_prev = [], p
    for d in ds:
        sc = np.array([d / c0, d / c0, scale_f, scale_f, d, c0])

        def rhs(_s: np.ndarray, yy: np.ndarray, pp: np.ndarray, sc: np.ndarray = sc) -> np.ndarray:
            lam_ = math.exp(pp[0])
            phi, m, fx, fz, z = yy[0] * sc[0], yy[1] * sc[1], yy[2] * sc[2], yy[3] * sc[3], yy[5]
            th = theta0 + phi
            c, sn = np.cos(th), np.sin(th)
            zz = z * sc[5]
            return np.vstack(
                [
                    m / sc[0],
                    -(fx * c - fz * sn) / sc[1],
                    -lam_ * zz * (c * c + GAMMA * sn * sn) / sc[2],
                    lam_ * zz * (1.0 - GAMMA) * sn * c / sc[3],
                    2.0 * np.cos(theta0 + 0.5 * phi) * np.sin(0.5 * phi) / sc[4],
                    c / sc[5],
                ]
            )

        def bc(ya: np.ndarray, yb: np.ndarray, _p: np.ndarray) -> np.ndarray:
            return np.array([ya[0], ya[4], ya[5], yb[1], yb[2], yb[3], yb[4] - 1.0])

        guess = p + (p - p_prev)  # the secant in ln Lambda
        # beyond d = 1 (the lower fold at 0.46) the branch only rises: a coarser tolerance
        tol = 1e-5 if d <= 1.0 else 1e-4
        sol = solve_bvp(rhs, bc, mesh, y, guess, tol=tol, max_nodes=20000)
        assert sol.status == 0, (d, sol.message)
        mesh, p_prev, p = sol.x, p, sol.p
        new_f = math.exp(p[0]) * c0
        y = sol.y.copy()
        y[2:4] *= scale_f / new_f  # the forces in the next step's scale
        scale_f = new_f
        lam.append(math.exp(p[0]))
    return ds, np.array(lam)


@pytest.mark.parametrize("theta0", [-1.5707, -1.57075])
def test_at_the_wall_every_state_is_found(theta0: float) -> None:
    """theta0 within 1e-4 of the wall (issue 33 item 7): the window's upper fold (27330 at
    -1.5707) lies at a tip displacement x1 - sin(theta0) of 1.4e-8, where x1 ~ -1 moves by
    1e-14 across it. Every one of 400 forcings from 1e-3 to 1e5 has its states (before: 371
    with status 6, a lower bound of the count, and 29 with none), as many as the crossings of
    the forcing along an independent scan of the branch (scipy's solve_bvp in the tip
    displacement), every root (low, mid, high) balancing the integrated moment equation; and
    a flow towards -x at -theta0 gives the mirror image of every root."""
    d, lam = _bvp_branch(theta0)
    # the scan starts in the linear range: Lambda = d/(11 cos^3(theta0)/120) from rest (0, 0)
    assert abs(lam[0] * 11.0 * math.cos(theta0) ** 3 / 120.0 / d[0] - 1.0) < 1e-3
    # the folds: the scan's extremes, refined by the parabola in ln d through their neighbours
    turns = np.flatnonzero(np.diff(lam)[:-1] * np.diff(lam)[1:] < 0.0) + 1
    assert turns.size == 2
    folds = []
    for k in turns:
        coef = np.polyfit(np.log(d[k - 1 : k + 2]), lam[k - 1 : k + 2], 2)
        folds.append(coef[2] - coef[1] ** 2 / (4.0 * coef[0]))
    lo, hi = min(folds), max(folds)
    assert 17.0 < lo < 18.0 and hi > 2e4
    expected = np.where((FORCINGS > lo) & (FORCINGS < hi), 3, 1)
    # the scan puts the folds within ~1e-3 of the solver's (27330.36 and 17.6897 at -1.5707):
    # forcings within 1e-2 of them are not counted (at most one a fold)
    sure = np.min(np.abs(np.log(FORCINGS[:, None] / np.array(folds)[None, :])), axis=1) > 1e-2
    win = sure & (expected == 3)  # inside the window, not within 1e-2 of a fold
    roots = {}
    for root in ("low", "mid", "high"):
        lam_r = FORCINGS if root == "low" else FORCINGS[win]
        st = hairbed.solve_pillar(lam_r, theta0, root=root)
        assert np.all(np.asarray(st.status) == 0), (root, np.flatnonzero(st.status != 0))
        n = np.asarray(st.n_states)
        if root == "low":
            np.testing.assert_array_equal(n[sure], expected[sure])
        else:
            assert np.all(n == 3)
        assert set(np.unique(n)) <= {1, 3}
        shape, base = _balance(st, points=2001, grading=4.0)  # measured: 3.7e-11 at most
        assert shape.max() < WALL_BALANCE_RTOL and base.max() < WALL_BALANCE_RTOL, root
        back = hairbed.solve_pillar(-lam_r, -theta0, root=root)  # the mirror image
        assert np.all(np.asarray(back.status) == 0)
        np.testing.assert_array_equal(back.n_states, n)
        np.testing.assert_allclose(back.tip_deflection, -st.tip_deflection, rtol=0, atol=1e-11)
        np.testing.assert_allclose(back.tip_height, st.tip_height, rtol=0, atol=1e-11)
        roots[root] = st
    # inside the window the three are distinct, in the order of the branch (x1 rises along it)
    rest = math.sin(theta0)
    d_low = np.asarray(roots["low"].tip_deflection)[win] - rest
    d_mid = np.asarray(roots["mid"].tip_deflection) - rest
    d_high = np.asarray(roots["high"].tip_deflection) - rest
    assert np.all(d_low < d_mid) and np.all(d_mid < d_high)


@pytest.mark.parametrize("theta0", [-1.57078, -math.pi / 2 + 1e-7])
def test_a_fold_beyond_the_range_nearer_still(theta0: float) -> None:
    """At theta0 = -1.57078 (1.6e-5 from the wall) the window's upper fold (~1.6e5) lies
    beyond the largest forcing: the march through the window ends at the wall's side of the
    range, where a step of 0.05 in d would pass the wall (before: it stopped there, and every
    forcing said status 6). At pi/2 - 1e-7 the march from rest starts where theta - theta0
    is resolved (its first step at 1e-2 moved theta by less than its rounding: status -7
    everywhere). Every root of every forcing balances; at Lambda = 1e5 the low state still
    leans on the wall and the high one has flipped over. Within 1e-9 of the wall no state is
    claimed."""
    lam = np.geomspace(1e-3, 1e5, 100)
    low = hairbed.solve_pillar(lam, theta0)
    assert np.all(np.asarray(low.status) == 0)
    three = np.asarray(low.n_states) == 3
    assert np.all(three == (lam > 18.0))  # the lower fold: 17.69 (-1.5707 and -1.57075)
    for st in (low, *(hairbed.solve_pillar(lam[three], theta0, root=r) for r in ("mid", "high"))):
        assert np.all(np.asarray(st.status) == 0)
        shape, base = _balance(st, points=2001, grading=4.0)
        assert shape.max() < WALL_BALANCE_RTOL and base.max() < WALL_BALANCE_RTOL
    assert float(low.tip_deflection[-1]) < -0.99 and float(st.tip_deflection[-1]) > 0.95
    # the low and high states are the stable ones, for the flow either way (before, with
    # the flow towards -x, solve_pillar_all called the middle one stable and not the others)
    for sign in (1.0, -1.0):
        states = hairbed.solve_pillar_all(sign * 100.0, sign * theta0)
        assert [s.stable for s in (states if sign > 0 else states[::-1])] == [True, False, True]
    beyond = hairbed.solve_pillar(lam, -math.pi / 2 + 1e-9)
    assert np.all(np.asarray(beyond.status) == -7) and np.all(np.asarray(beyond.n_states) == 0)
