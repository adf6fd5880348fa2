"""Branches as parametric curves, folds and the cusp (theory.md §5)."""

import json
import math

import numpy as np
import pytest
from conftest import DATA
from tolerances import ATOL, RTOL

import hairbed
from hairbed.branches import bistable_window, curve, cusp, folds, log_slope

#: tests/reference/generate_folds.py (mpmath only): states near the folds at eps >= 0.99, and
#: the cusp eps_c(theta0) up to theta0 = -pi/2 + 1e-10.
FOLDS_REF = json.loads((DATA / "folds_mpmath.json").read_text())
NEAR_FOLDS = FOLDS_REF["near_folds"]
#: Near a fold a state is ill-conditioned in omega2: a double-precision solver is held to
#: max(NEAR_FOLD_RTOL |value|, ROUNDING_FACTOR x the change one ulp of an input makes).
NEAR_FOLD_RTOL = 1e-10
ROUNDING_FACTOR = 4.0

# theory.md §5: windows of omega^2 with three physical states, computed independently
# (quoted to 5 significant figures).
WINDOWS = [
    (-1.5, 0.9, 0.95766, 1.4859),
    (-1.0, 0.95, 0.29696, 0.31966),
    (-0.5, 0.99, 0.034935, 0.036187),
]


@pytest.mark.parametrize(("theta0", "eps", "lower", "upper"), WINDOWS)
def test_folds_reproduce_math_md_windows(theta0, eps, lower, upper):
    f = folds(eps, theta0)
    assert f.omega2.shape == f.xi.shape == f.t.shape == (2,)
    # Ordered by omega^2, lower fold first; along the branch the upper fold comes first.
    assert np.all(np.diff(f.omega2) > 0) and np.all(np.diff(f.xi) < 0)
    assert f.lower.omega2 == f.omega2[0] == pytest.approx(lower, rel=5e-5)
    assert f.upper.omega2 == f.omega2[1] == pytest.approx(upper, rel=5e-5)
    assert (f.lower.xi, f.lower.t) == (f.xi[0], f.t[0])
    w = bistable_window(eps, theta0)
    assert w.exists
    assert (w.lower, w.upper) == pytest.approx((lower, upper), rel=5e-5)


@pytest.mark.parametrize(("theta0", "eps", "lower", "upper"), WINDOWS)
def test_folds_against_dense_scan(theta0, eps, lower, upper):
    # Independent of the fold refinement: local extrema of omega^2 sampled densely in t.
    c = curve(eps, theta0, num=40001, t_span=(-8.0, 4.0))
    w = np.asarray(c.omega2)
    k_max = np.nonzero((w[1:-1] > w[:-2]) & (w[1:-1] > w[2:]))[0] + 1
    k_min = np.nonzero((w[1:-1] < w[:-2]) & (w[1:-1] < w[2:]))[0] + 1
    assert k_max.size == 1 and k_min.size == 1 and k_max[0] < k_min[0]
    f = folds(eps, theta0)
    # The sampled extremum cannot beat the true one, and the grid (step 3e-4 in t) gets within
    # ~1e-7 relative of it.
    assert w[k_max[0]] <= f.upper.omega2 * (1 + 1e-14)
    assert w[k_min[0]] >= f.lower.omega2 * (1 - 1e-14)
    assert w[k_max[0]] == pytest.approx(f.upper.omega2, rel=1e-7)
    assert w[k_min[0]] == pytest.approx(f.lower.omega2, rel=1e-7)
    xi = np.asarray(c.xi)
    assert xi[k_max[0] - 1] < f.upper.xi < xi[k_max[0] + 1]
    assert xi[k_min[0] - 1] < f.lower.xi < xi[k_min[0] + 1]


@pytest.mark.parametrize(("theta0", "eps"), [(-1.5, 0.9), (-0.5, 0.99)])
def test_folds_are_extrema_to_high_accuracy(theta0, eps):
    f = folds(eps, theta0)
    for k, t in enumerate(f.t):
        # omega^2 is quadratic at a fold: a shift of 1e-5 in t changes it by ~1e-10 relative,
        # always in the same direction on both sides if t is accurate to well below 1e-5.
        side = np.asarray(hairbed.from_parameter(t + np.array([-1e-5, 1e-5]), eps, theta0).omega2)
        if k == 1:  # the upper fold: a local maximum
            assert np.all(side < f.omega2[k])
        else:
            assert np.all(side > f.omega2[k])
        assert abs(float(log_slope(t, eps, theta0))) < 1e-9


@pytest.mark.parametrize(
    ("theta0", "eps"), [(0.0, 0.5), (-1.5, 0.9), (-0.5, 0.99), (1.2, 0.999), (-1.5707963, 0.3)]
)
def test_log_slope_is_the_derivative_of_ln_omega2(theta0, eps):
    """Against a sixth-order difference of ln(omega^2) along from_parameter (a path that never
    computes a slope): Richardson extrapolation of fourth-order central differences at steps
    h and h/2, truncation ~h^6 ~ 1e-12 and rounding ~1e-16/h ~ 1e-14."""
    t = np.concatenate([np.linspace(-20.0, 12.0, 65), [-300.0, 40.0, 300.0]])
    h = 1e-2

    def central(step):
        f = np.log(
            np.asarray(
                hairbed.from_parameter(
                    t[:, None] + step * np.array([-2.0, -1.0, 1.0, 2.0]), eps, theta0
                ).omega2
            )
        )
        return (f[:, 0] - 8.0 * f[:, 1] + 8.0 * f[:, 2] - f[:, 3]) / (12.0 * step)

    fd = (16.0 * central(h / 2) - central(h)) / 15.0
    got = np.asarray(log_slope(t, eps, theta0))
    np.testing.assert_allclose(got, fd, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize(
    ("theta0", "eps"), [(0.0, 0.5), (0.0, 0.99), (0.5, 0.999), (1.2, 0.9), (-1.0, 0.8)]
)
def test_monotone_branch_has_no_folds(theta0, eps):
    f = folds(eps, theta0)
    assert f.omega2.size == 0 and f.xi.size == 0
    assert f.lower is None and f.upper is None
    w = bistable_window(eps, theta0)
    assert np.isnan(w.lower) and np.isnan(w.upper) and not w.exists
    w = np.asarray(curve(eps, theta0, num=4001, t_span=(-12.0, 12.0)).omega2)
    assert np.all(np.diff(w) > 0)


@pytest.mark.parametrize(
    ("theta0", "expected", "tol"), [(-1.5, 0.52, 0.005), (-1.0, 0.91, 0.005), (-0.4, 0.99, 0.005)]
)
def test_cusp_matches_math_md(theta0, expected, tol):
    assert cusp(theta0) == pytest.approx(expected, abs=tol)


@pytest.mark.parametrize("theta0", [-1.2, -0.6])
def test_cusp_separates_monotone_from_folded(theta0):
    ec = float(cusp(theta0))
    assert 0.0 < ec < 1.0
    assert folds(ec - 1e-6, theta0).omega2.size == 0
    assert folds(ec + 1e-6, theta0).omega2.size == 2
    # Just above the cusp the window is tiny and both folds sit close together.
    f = folds(ec + 1e-6, theta0)
    assert abs(f.omega2[0] - f.omega2[1]) < 1e-6 * f.omega2[0]


def test_cusp_tends_to_one_and_is_one_for_nonnegative_base_angle():
    values = cusp(np.array([-1.5, -1.0, -0.4, -0.1]))
    assert values.shape == (4,)
    assert np.all(np.diff(values) > 0) and values[-1] < 1.0
    assert values[-1] > 0.999
    assert cusp(0.0) == 1.0 and cusp(0.7) == 1.0


def test_curve_is_the_branch_solve_returns():
    c = curve(0.5, 0.3, num=7, t_span=(-6.0, 6.0))
    assert np.shape(c.xi) == (7,)
    assert np.all(np.diff(c.xi) > 0) and np.all(np.diff(c.omega2) > 0)
    s = hairbed.solve(np.asarray(c.omega2), 0.5, 0.3)
    np.testing.assert_allclose(s.xi, c.xi, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(s.tip_height, c.tip_height, rtol=1e-10)


def test_curve_of_other_branches():
    down = curve(0.5, 0.0, sign=-1, num=50)
    assert np.all(np.asarray(down.base_curvature) < 0) and np.all(np.asarray(down.tip_height) < 0)
    twirl = curve(0.5, 0.0, n=1, num=50)
    assert np.all(np.asarray(twirl.omega2) > 0)
    # More turning points need more forcing (omega_eps >= 3K - v0 > K - v0).
    phys = curve(0.5, 0.0, num=50)
    assert np.all(np.asarray(twirl.omega_eps) > np.asarray(phys.omega_eps))


@pytest.mark.parametrize(
    "call",
    [
        lambda: curve(1.0, 0.0),
        lambda: curve(0.5, 2.0),
        lambda: curve(0.5, 0.0, num=1),
        lambda: curve(0.5, 0.0, sign=0),
        lambda: curve(0.5, 0.0, t_span=(1.0, -1.0)),
        lambda: folds(-0.1, 0.0),
        lambda: folds(np.array([0.5, 0.6]), 0.0),
        lambda: cusp(np.pi / 2),
    ],
)
def test_invalid_input_raises(call):
    with pytest.raises(ValueError):
        call()


def _near_fold_id(c):
    return f"eps{c['eps']:g}-t{c['theta0']!r}-{c['fold']}-d{c['delta']:g}"


@pytest.mark.parametrize("case", NEAR_FOLDS, ids=[_near_fold_id(c) for c in NEAR_FOLDS])
def test_states_near_folds_in_nearly_closed_channels(case):
    """Every root within 1e-8 to 1e-14 (relative in omega2) of a fold at eps = 0.99 ... 0.999:
    xi, tip angle, tip deflection, tip height and omega_eps to max(1e-10 relative, 4x the
    change that rounding one input to its neighbouring double makes, from mpmath; where one
    ulp of theta0 takes roots out of the window, ``removes_roots``, the largest change of the
    other moves, a lower bound)."""
    n = case["n_roots"]
    names = ["low", "mid", "high"] if n == 3 else ["low", "high"][: max(n, 1)]
    index = [0, 1, 2] if n == 3 else [0, n - 1][: max(n, 1)]
    lines = []
    for k, name in zip(index, names):
        sol = hairbed.solve(case["omega2"], case["eps"], case["theta0"], root=name)
        label = f"solve({case['omega2']!r}, {case['eps']!r}, {case['theta0']!r}, root={name!r})"
        if sol.n_roots != n:
            lines.append(f"{label}: n_roots {sol.n_roots}, mpmath {n}")
            continue
        ref = case["roots"][k]
        for f in ("xi", "tip_angle", "tip_deflection", "tip_height", "omega_eps"):
            want = float(ref[f])
            change = ref["rounding_change"][f]
            allowed = NEAR_FOLD_RTOL * abs(want)
            if change is not None:
                allowed = max(allowed, ROUNDING_FACTOR * float(change))
            err = abs(getattr(sol, f) - want)
            if not err <= allowed:
                lines.append(
                    f"{label}.{f} = {getattr(sol, f)!r}, mpmath {want!r}: error {err:.3e} "
                    f"({err / abs(want):.2e} relative), allowed {allowed:.3e}"
                )
    assert not lines, "\n".join(lines)


def test_cusp_matches_mpmath_up_to_minus_half_pi():
    """eps_c(theta0) = min_t G(t) from mpmath, theta0 from -1 to -pi/2 + 1e-10 (where eps_c
    ~ 6e-4 and one ulp of theta0 moves it by ~5e-10)."""
    ref = FOLDS_REF["cusp"]
    theta0 = np.array([c["theta0"] for c in ref])
    want = np.array([float(c["eps_c"]) for c in ref])
    got = np.asarray(cusp(theta0))
    bad = ~np.isclose(got, want, rtol=RTOL, atol=ATOL)
    lines = [
        f"  cusp({t!r}) = {g!r}, mpmath {w!r} (diff {g - w:.3e})"
        for t, g, w in zip(theta0[bad], got[bad], want[bad])
    ]
    assert not lines, "\n".join(lines)
    assert math.isclose(float(cusp(theta0[0])), got[0], rel_tol=0.0, abs_tol=1e-15)


# -- label_states: the coexisting states named low/mid/high and classified ------------------


def _omega2_rises_along_the_branch(sol, h=1e-5):
    """Whether omega^2 increases with xi at the state (a central difference in t of
    from_parameter): on the physical branch the states between the folds, where it falls, are
    the unstable ones (theory.md §5), the test's independent criterion."""
    from scipy.special import logit

    s0 = np.sin(float(sol.theta0))
    t = float(logit((float(sol.xi) - s0) / (1.0 - s0)))
    up = float(hairbed.from_parameter(t + h, sol.eps, sol.theta0).omega2)
    down = float(hairbed.from_parameter(t - h, sol.eps, sol.theta0).omega2)
    return up > down


@pytest.mark.parametrize(
    ("omega2", "eps", "theta0"),
    [(1.2, 0.9, -1.5), (0.5135, 0.95, -1.2), (0.9, 0.92, -1.4), (2.0, 0.5, 0.0), (50.0, 0.9, 0.3)],
)
def test_label_states_names_and_classifies_the_states_of_the_branch(omega2, eps, theta0):
    from hairbed.branches import label_states

    low = hairbed.solve(omega2, eps, theta0)
    names = {1: ("low",), 2: ("low", "high"), 3: ("low", "mid", "high")}[int(low.n_roots)]
    states = [hairbed.solve(omega2, eps, theta0, root=r) for r in names]
    labelled = label_states(states)
    assert [s.root for s in labelled] == list(names)
    assert all(s.count == len(names) for s in labelled)
    assert all(s.solution is sol for s, sol in zip(labelled, states))
    xi = [float(s.solution.xi) for s in labelled]
    assert xi == sorted(xi)
    for s in labelled:
        assert s.status == 0
        assert s.stable == _omega2_rises_along_the_branch(s.solution)
        assert s.stable == (s.growth_rate < 0.0)


def test_label_states_groups_the_branches_of_solve_all():
    from hairbed.branches import label_states

    states = hairbed.solve_all(200.0, 0.5, 0.1)
    labelled = label_states(states)
    assert len(labelled) == len(states) > 3
    for s in labelled:
        same = [t for t in states if (t.sign, t.n) == (s.solution.sign, s.solution.n)]
        assert s.count == len(same)
        place = next(i for i, t in enumerate(same) if t is s.solution)
        names = {1: ("low",), 2: ("low", "high"), 3: ("low", "mid", "high")}[s.count]
        assert s.root == names[place]
    # the physical state alone on its branch, stable (a hair bent by a flow is at rest)
    physical = [s for s in labelled if s.solution.physical]
    assert [(s.root, s.count, s.stable) for s in physical] == [("low", 1, True)]


def test_label_states_refuses_what_is_not_a_scalar_solution():
    from hairbed.branches import label_states

    with pytest.raises(TypeError, match=r"solutions\[1\] must be a hairbed.Solution"):
        label_states([hairbed.solve(1.0, 0.5), 1.0])
    with pytest.raises(ValueError, match=r"solutions\[0\] must be a scalar Solution"):
        label_states([hairbed.solve(np.array([1.0, 2.0]), 0.5)])
    with pytest.raises(ValueError, match="num"):
        label_states([hairbed.solve(1.0, 0.5)], num=1)
    assert label_states([]) == []
