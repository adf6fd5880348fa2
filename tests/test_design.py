"""hairbed.design: optima against scans and grids, multi-start, validity, bad input (issue 32).

The references are independent of the optimiser: a dense scan of the objective's value
refined by a bounded scalar minimisation of the value (no gradients), and brute-force grids
of the values with the constraints checked point by point.
"""

from __future__ import annotations

import itertools
import math
import warnings

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from hairbed import HairBed, Pillar, continue_pillar
from hairbed import design as D


def _quiet(cls, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return cls(**kw)


def _bed(**kw):
    args = dict(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                viscosity=1.0, spacing=250e-6, base_angle=0.5, density=1200.0)  # fmt: skip
    args.update(kw)
    return _quiet(HairBed, **args)


def _values(space, quantities, u):
    model = space.model(space.values(np.asarray(u, dtype=np.float64)))
    return [q(model) for q in quantities]


# -- correctness -----------------------------------------------------------------------------


def test_one_variable_optimum_matches_a_refined_dense_scan():
    bed = _bed()
    q = D.diodicity(1000.0, 0.01)
    var = D.Variable("base_angle", 0.0, 1.5)
    res = D.optimise(bed, var, q, sense="max", starts=3)
    assert res.success and res.status == 0 and res.design is not None
    space = D.Space(bed, [var])
    grid = np.linspace(0.0, 1.5, 301)
    vals = np.array([_values(space, [q], [t / 1.5])[0] for t in grid])
    k = int(np.argmax(vals))
    assert 0 < k < grid.size - 1  # an interior optimum, which the scan brackets
    fine = minimize_scalar(
        lambda t: -_values(space, [q], [t / 1.5])[0],
        bounds=(grid[k - 1], grid[k + 1]),
        method="bounded",
        options={"xatol": 1e-10},
    )
    assert abs(res.variables["base_angle"] - fine.x) <= 1e-6
    assert res.objective >= -fine.fun - 1e-12
    assert res.design.base_angle == res.variables["base_angle"]
    assert res.exact_gradient and res.inexact == ()


def test_a_porous_valve_design_matches_a_refined_scan():
    """HairBed(model="porous"): the flow through bed and gap, kappa and gamma moving with
    the hairs (its exact gradients); the most diodic tilt at 300 Pa, interior."""
    bed = _bed(model="porous", density=None)
    q = D.diodicity(300.0, 0.01)
    var = D.Variable("base_angle", 0.0, 1.4)
    res = D.optimise(bed, var, q, sense="max", starts=2)
    assert res.success and res.exact_gradient and res.design.model == "porous"
    assert any("porous bed's valve is not checked" in n for n in res.notes)
    space = D.Space(bed, [var])
    grid = np.linspace(0.0, 1.4, 29)
    vals = np.array([_values(space, [q], [t / 1.4])[0] for t in grid])
    k = int(np.argmax(vals))
    assert 0 < k < grid.size - 1
    fine = minimize_scalar(
        lambda t: -_values(space, [q], [t / 1.4])[0],
        bounds=(grid[k - 1], grid[k + 1]),
        method="bounded",
        options={"xatol": 1e-10},
    )
    assert abs(res.variables["base_angle"] - fine.x) <= 1e-6
    assert res.objective >= -fine.fun - 1e-12
    with pytest.raises(NotImplementedError, match="bistable_width.*dense bed only"):
        D.optimise(bed, var, D.bistable_width(), sense="max")


def _grid_best(space, objective, constraints, n, sense):
    best = -math.inf if sense == "max" else math.inf
    for u in itertools.product(np.linspace(0.0, 1.0, n), repeat=space.size):
        vals = _values(space, [objective, *(c.quantity for c in constraints)], u)
        if all(c.slack(v) >= 0.0 for c, v in zip(constraints, vals[1:], strict=True)):
            best = max(best, vals[0]) if sense == "max" else min(best, vals[0])
    return best


def test_two_variable_constrained_optimum_beats_the_grid():
    bed = _bed()
    variables = [D.Variable("base_angle", 0.0, 1.4), D.Variable("length", 0.6e-3, 1.5e-3)]
    q = D.diodicity(1000.0, 0.01)
    budget = D.resistance_ratio(1000.0, 0.01) <= 2.5
    res = D.optimise(bed, variables, q, constraints=[budget], sense="max", starts=4)
    assert res.success
    space = D.Space(bed, variables)
    validity, _ = D.validity_constraints(bed, [q, budget.quantity])
    best = _grid_best(space, q, [budget, *validity], 15, "max")
    assert res.objective >= best - 1e-9
    (report,) = [c for c in res.constraints if c.label == budget.label]
    assert report.active and report.slack >= -1e-9 and report.multiplier > 0.0


def test_relaxing_an_active_bound_pays_its_multiplier():
    """d(optimum)/d(bound) against re-optimising at a shifted bound (central difference)."""
    bed = _bed()
    variables = [D.Variable("base_angle", 0.0, 1.4), D.Variable("length", 0.6e-3, 1.5e-3)]
    q = D.diodicity(1000.0, 0.01)

    def best(b):
        return D.optimise(bed, variables, q, constraints=[D.resistance_ratio(1000.0, 0.01) <= b],
                          sense="max", starts=1)  # fmt: skip

    res = best(2.5)
    (report,) = [c for c in res.constraints if not c.validity]
    h = 1e-3
    slope = (best(2.5 + h).objective - best(2.5 - h).objective) / (2 * h)
    assert report.multiplier == pytest.approx(slope, rel=1e-3)


def test_a_minimisation_multiplier_and_a_bound_sensitivity_match_reoptimisation():
    bed = _bed()
    highs = {"base_angle": 1.4, "length": 1.5e-3}

    def best(di_min, **high):
        top = {**highs, **high}
        variables = [D.Variable("base_angle", 0.0, top["base_angle"]),
                     D.Variable("length", 0.6e-3, top["length"])]  # fmt: skip
        return D.optimise(bed, variables, D.resistance_ratio(1000.0, 0.01),
                          constraints=[D.diodicity(1000.0, 0.01) >= di_min], starts=1)  # fmt: skip

    res = best(2.0)
    (report,) = [c for c in res.constraints if not c.validity]
    assert res.success and report.active
    h = 1e-3
    slope = (best(2.0 + h).objective - best(2.0 - h).objective) / (2 * h)
    assert slope > 0.0 and report.multiplier == pytest.approx(slope, rel=1e-3)
    (key,) = res.bound_sensitivities  # one variable sits on its upper bound
    name = key.removesuffix(".high")
    dh = 1e-6 * highs[name]
    up = best(2.0, **{name: highs[name] + dh}).objective
    down = best(2.0, **{name: highs[name] - dh}).objective
    assert res.bound_sensitivities[key] == pytest.approx((up - down) / (2 * dh), rel=1e-3)


def test_three_variable_pillar_design_beats_the_grid():
    p = _quiet(Pillar, length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=0.1,
               density=1000.0)  # fmt: skip
    variables = [
        D.Variable("length", 300e-6, 800e-6),
        D.Variable("radius", 20e-6, 30e-6),
        D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    ]
    objective = D.tip_deflection(0.5)
    constraints = [D.linear_range(0.05) >= 1.0]
    res = D.optimise(p, variables, objective, constraints=constraints, sense="max", starts=4)
    assert res.success
    space = D.Space(p, variables)
    validity, _ = D.validity_constraints(p, [objective, constraints[0].quantity])
    best = _grid_best(space, objective, [*constraints, *validity], 6, "max")
    assert res.objective >= best - 1e-15
    assert any(c.active for c in res.constraints)


def test_sensor_design_with_bandwidth_and_linear_range_beats_the_grid():
    p = _quiet(Pillar, length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=0.1,
               density=1000.0)  # fmt: skip
    variables = [D.Variable("length", 300e-6, 800e-6), D.Variable("radius", 20e-6, 30e-6)]
    objective = D.linear_sensitivity()
    constraints = [D.bandwidth(0.5) >= 8.0, D.linear_range(0.05) >= 0.5]
    res = D.optimise(p, variables, objective, constraints=constraints, sense="max", starts=2)
    assert res.success and res.exact_gradient and res.inexact == ()
    space = D.Space(p, variables)
    validity, _ = D.validity_constraints(p, [objective, *(c.quantity for c in constraints)])
    best = _grid_best(space, objective, [*constraints, *validity], 9, "max")
    assert res.objective >= best * (1 - 1e-12)
    (band,) = [c for c in res.constraints if c.label == "bandwidth(0.5 Pa) >= 8"]
    assert band.active and band.multiplier < 0.0  # a higher bandwidth costs sensitivity


def test_multistart_finds_the_global_optimum_of_a_bistable_window():
    """The width of the window is 0 (every point stationary) wherever the branch does not
    fold: a start there stays there; the scan shows the plateau and the corner optimum."""
    bed = _bed(length=1.9e-3, base_angle=-1.0, density=None)
    variables = [
        D.Variable("base_angle", -1.4, 0.0),
        D.Variable("channel_height", 1.92e-3, 2.6e-3),
    ]
    q = D.bistable_width()
    space = D.Space(bed, variables)
    scan = np.array(
        [_values(space, [q], u)[0] for u in itertools.product(np.linspace(0, 1, 9), repeat=2)]
    )
    assert np.count_nonzero(scan == 0.0) > 10 and np.max(scan) > 0.0  # plateau and window
    stuck = D.optimise(bed, variables, q, sense="max", starts=1)  # from the centre: plateau
    assert stuck.success and stuck.objective == 0.0
    res = D.optimise(bed, variables, q, sense="max", starts=8)
    assert res.success and res.objective >= np.max(scan) - 1e-12
    assert res.spread == pytest.approx(res.objective)  # the plateau's optima were reported
    assert np.any(res.local_optima == 0.0)
    assert any("bistable window is not checked" in n for n in res.notes)
    assert res.variables["base_angle"] == pytest.approx(-1.4)
    # at the corner, with no constraint, d(optimum)/d(bound) is the objective's own slope
    space_at = D.Space(bed, variables)
    h = 1e-6
    up = _values(space_at, [q], [h / 1.4, 0.0])[0]
    assert res.bound_sensitivities["base_angle.low"] == pytest.approx(
        (up - res.objective) / h, rel=1e-4
    )


def test_multistart_finds_the_widest_snap_through_window_of_a_pillar():
    """A pillar's snap-through window opens below base_angle ~ -1.33 (flow towards +x):
    above, its width is 0 and every point stationary; the scan shows the plateau and the
    corner optimum (the strongest tilt, the stiffest pillar: the width in Pa is
    (Lambda_u - Lambda_l) E a^4 s/(16 c L^4))."""
    p = _quiet(Pillar, length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3,
               density=1000.0, base_angle=-1.4)  # fmt: skip
    variables = [
        D.Variable("base_angle", -1.45, -1.0),
        D.Variable("youngs_modulus", 0.5e6, 2e6),
    ]
    q = D.snap_window()
    space = D.Space(p, variables)
    scan = np.array(
        [
            _values(space, [q], u)[0]
            for u in itertools.product(np.linspace(0, 1, 10), np.linspace(0, 1, 3))
        ]
    )
    assert np.count_nonzero(scan == 0.0) > 10 and np.max(scan) > 0.0  # plateau and window
    res = D.optimise(p, variables, q, sense="max", starts=4)
    assert res.success and res.objective >= np.max(scan) - 1e-12
    assert np.any(res.local_optima == 0.0)  # a start on the plateau stayed there
    assert res.spread == pytest.approx(res.objective)
    assert res.variables["base_angle"] == pytest.approx(-1.45)
    assert res.variables["youngs_modulus"] == pytest.approx(2e6)
    assert any("snap-through window" in n for n in res.notes)
    # the width against the statics' own folds (continue_pillar's golden-section search)
    best = res.design
    folds = continue_pillar(40.0, best.base_angle, gamma=best.drag_ratio, num=40).folds
    width = (folds[0, 0] - folds[1, 0]) / best.forcing_per_stress
    assert res.objective == pytest.approx(width, rel=1e-9)


def test_pareto_front_is_monotone_and_feasible():
    bed = _bed()
    variables = [D.Variable("base_angle", 0.0, 1.4), D.Variable("length", 0.6e-3, 1.5e-3)]
    front = D.pareto_front(
        bed,
        variables,
        D.diodicity(1000.0, 0.01),
        D.resistance_ratio(1000.0, 0.01),
        senses=("max", "min"),
        points=5,
    )
    assert front.status == 0 and front.success.all()
    assert np.all(np.diff(front.second) < 0)  # lower resistance ...
    assert np.all(np.diff(front.first) <= 1e-9)  # ... costs diodicity
    assert "epsilon-constraint" in front.method


# -- validity and infeasibility ---------------------------------------------------------------


def test_an_infeasible_problem_names_its_constraint_and_returns_no_design():
    bed = _bed()
    res = D.optimise(
        bed,
        D.Variable("base_angle", 0.0, 1.4),
        D.diodicity(1000.0, 0.01),
        constraints=[D.resistance_ratio(1000.0, 0.01) <= 0.5],  # (H/g)^3 >= 1 always
        sense="max",
        starts=3,
    )
    assert not res.success and res.status == 2 and res.design is None
    assert "resistance_ratio(dp=1000 Pa, l=0.01 m) <= 0.5" in res.message


def test_a_design_outside_validity_is_never_optimal():
    # water in the gap at 1 kPa: the gap's Reynolds number is far above 1 for every tilt
    bed = _bed(viscosity=1e-3, density=1000.0, youngs_modulus=1e9)
    res = D.optimise(bed, D.Variable("base_angle", 0.0, 1.4), D.diodicity(1000.0, 0.01),
                     sense="max", starts=2)  # fmt: skip
    assert not res.success and res.design is None
    assert "gap_reynolds" in res.message
    free = D.optimise(bed, D.Variable("base_angle", 0.0, 1.4), D.diodicity(1000.0, 0.01),
                      sense="max", starts=2, validity=False)  # fmt: skip
    assert free.success


def test_validity_binds_the_optimum():
    """The sparse bed's dense-bed condition cuts the spacing off below the unconstrained
    optimum; the optimum sits on it."""
    bed = _bed()
    res = D.optimise(bed, [D.Variable("spacing", 150e-6, 900e-6)], D.diodicity(1000.0, 0.01),
                     sense="min", starts=2)  # fmt: skip
    (dense,) = [c for c in res.constraints if c.label.startswith("brinkman_ratio")]
    assert res.success and dense.validity
    assert dense.value <= 0.1 * (1 + 1e-7)


def test_without_density_the_unchecked_validity_is_noted():
    res = D.optimise(_bed(density=None), D.Variable("base_angle", 0.2, 1.0),
                     D.diodicity(500.0, 0.01), sense="max", starts=1)  # fmt: skip
    assert res.success and any("no density" in n for n in res.notes)


# -- bad input ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("length", 2.0, 1.0), "inverted"),
        (("length", 1.0, 1.0), "empty"),
        (("length", 0.0, math.inf), "high must be finite"),
        (("length", math.nan, 1.0), "low must be finite"),
        (("length", "a", 1.0), "low must be a real number"),
        (("length", 0.0, 1.0, True), "log scale needs low > 0"),
    ],
)
def test_bad_bounds_are_refused(args, match):
    with pytest.raises(ValueError, match=match):
        D.Variable(*args)


def test_unknown_variable_objective_and_impossible_box_are_refused():
    bed = _bed()
    q = D.diodicity(1000.0, 0.01)
    with pytest.raises(ValueError, match="unknown design variable 'colour'"):
        D.optimise(bed, D.Variable("colour", 0.0, 1.0), q)
    with pytest.raises(ValueError, match="given twice"):
        D.optimise(bed, [D.Variable("length", 1e-4, 1e-3)] * 2, q)
    with pytest.raises(ValueError, match="at most one of the design variables spacing"):
        D.optimise(
            bed, [D.Variable("spacing", 2e-4, 3e-4), D.Variable("packing_fraction", 0.1, 0.2)], q
        )
    with pytest.raises(ValueError, match="impossible HairBed.*channel_height"):
        D.optimise(bed, D.Variable("length", 1e-3, 3e-3), q)
    with pytest.raises(TypeError, match="objective must be a hairbed.design quantity"):
        D.optimise(bed, D.Variable("length", 1e-4, 1e-3), "diodicity")
    with pytest.raises(TypeError, match="quantity of a pillar"):
        D.optimise(bed, D.Variable("length", 1e-4, 1e-3), D.tip_deflection(1.0))
    with pytest.raises(ValueError, match="sense must be one of"):
        D.optimise(bed, D.Variable("length", 1e-4, 1e-3), q, sense="maximum")
    with pytest.raises(ValueError, match="starts must be an integer"):
        D.optimise(bed, D.Variable("length", 1e-4, 1e-3), q, starts=0)
    with pytest.raises(TypeError, match="base must be a hairbed.HairBed or hairbed.Pillar"):
        D.optimise("bed", D.Variable("length", 1e-4, 1e-3), q)
    with pytest.raises(ValueError, match="pressure_drop"):
        D.diodicity(-1.0, 0.01)
    with pytest.raises(ValueError, match="rtol must lie in"):
        D.linear_range(1.5)
    with pytest.raises(ValueError, match="bound must be finite"):
        D.resistance_ratio(1000.0, 0.01) <= math.nan  # noqa: B015
    with pytest.raises(ValueError, match="variables must hold at least one"):
        D.optimise(bed, [], q)
    var = D.Variable("base_angle", 0.0, 1.0)
    with pytest.raises(ValueError, match="seed must be an integer"):
        D.optimise(bed, var, q, seed=-1)
    with pytest.raises(ValueError, match="maxiter must be an integer"):
        D.optimise(bed, var, q, maxiter=0)
    with pytest.raises(ValueError, match="x0 must be a dict of every design variable"):
        D.optimise(bed, var, q, x0={"length": 1e-3})
    with pytest.raises(ValueError, match=r"x0\['base_angle'\] = 2.0 must lie within"):
        D.optimise(bed, var, q, x0={"base_angle": 2.0})
    with pytest.raises(ValueError, match="log must be True or False"):
        D.Variable("length", 1e-4, 1e-3, log="yes")


def test_log_variable_ends_are_its_bounds():
    # exp(ln(low)) can round below low; a design's variables are fed back as x0 (the
    # Pareto front starts each point from its neighbour) and must lie within the bounds
    v = D.Variable("youngs_modulus", 0.5e6, 2e6, log=True)
    assert v.value(0.0) == 0.5e6 and v.value(1.0) == 2e6
    for u in np.linspace(0.0, 1.0, 101):
        assert v.low <= v.value(float(u)) <= v.high
