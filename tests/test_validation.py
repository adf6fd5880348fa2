"""Bad input gets a clear ValueError naming the parameter and its range."""

import numpy as np
import pytest

import hairbed
from hairbed._core.solver import fold_parameters


@pytest.mark.parametrize(
    ("args", "kwargs", "pattern"),
    [
        ((-1.0, 0.5), {}, r"omega2 must lie in \[0, inf\)"),
        ((1.0, 1.0), {}, r"eps must lie in \[0, 1\)"),
        ((1.0, -0.1), {}, r"eps must lie in \[0, 1\)"),
        ((1.0, 0.5, np.pi / 2), {}, r"theta0 must lie in \(-pi/2, pi/2\)"),
        ((1.0, 0.5, -2.0), {}, r"theta0 must lie in \(-pi/2, pi/2\)"),
        ((np.nan, 0.5), {}, r"omega2 must be finite"),
        ((np.inf, 0.5), {}, r"omega2 must be finite"),
        ((1.0, np.nan), {}, r"eps must be finite"),
        (("2", 0.5), {}, r"omega2 must be a real number"),
        ((None, 0.5), {}, r"omega2 must be a real number"),
        ((1.0, 0.5, [0.1, "a"]), {}, r"theta0 must be a real number"),
        ((1 + 2j, 0.5), {}, r"omega2 must be a real number"),
        ((True, 0.5), {}, r"omega2 must be a real number"),
        ((1.0, 0.5), {"sign": 0}, r"sign must be \+1 or -1"),
        ((1.0, 0.5), {"sign": 2}, r"sign must be \+1 or -1"),
        ((1.0, 0.5), {"n": -1}, r"n must be a whole number >= 0"),
        ((1.0, 0.5), {"n": 1.5}, r"n must be a whole number >= 0"),
        ((1.0, 0.5), {"root": "middle"}, r"root must be one of"),
        ((1.0, 0.5), {"root": 1}, r"root must be one of"),
    ],
)
def test_bad_scalar_input(args, kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        hairbed.solve(*args, **kwargs)


def test_first_offending_index_is_named():
    with pytest.raises(
        ValueError, match=r"omega2 must lie in \[0, inf\), got -2.0 \(first at index 2\)"
    ):
        hairbed.solve([1.0, 2.0, -2.0, -3.0], 0.5)
    with pytest.raises(ValueError, match=r"eps must be finite .*index 1"):
        hairbed.solve(1.0, [0.1, np.nan])
    with pytest.raises(ValueError, match=r"index \(1, 0\)"):
        hairbed.solve(np.ones((2, 2)), [[0.1, 0.2], [1.5, 0.2]])


def test_shapes_that_do_not_broadcast():
    with pytest.raises(ValueError, match="must broadcast together"):
        hairbed.solve([1.0, 2.0], [0.1, 0.2, 0.3])


def test_solve_all_takes_scalars_only():
    with pytest.raises(ValueError, match="scalar"):
        hairbed.solve_all([1.0, 2.0], 0.5)
    with pytest.raises(ValueError, match=r"eps must lie in \[0, 1\)"):
        hairbed.solve_all(1.0, 2.0)


def test_shape_arguments():
    sol = hairbed.solve(2.0, 0.5)
    with pytest.raises(ValueError, match=r"sigma must lie in \[0, 1\]"):
        sol.theta(1.5)
    with pytest.raises(ValueError, match="sigma must be finite"):
        sol.z(np.nan)
    with pytest.raises(ValueError, match="num must be an integer >= 2"):
        sol.profile(1)


def test_from_xi_range():
    with pytest.raises(ValueError, match=r"xi must lie in \[sin\(theta0\), 1\)"):
        hairbed.from_xi(1.0, 0.5)
    with pytest.raises(ValueError, match=r"xi must lie in \[sin\(theta0\), 1\)"):
        hairbed.from_xi(0.1, 0.5, 0.5)
    with pytest.raises(ValueError, match="t must be a real number"):
        hairbed.from_parameter(np.nan, 0.5)


def test_valid_edge_values_are_accepted():
    # the closed ends of the ranges are valid input, not errors
    assert hairbed.solve(0.0, 0.0).xi == 0.0
    assert np.isfinite(hairbed.solve(1.0, 0.999999, 1.5707).xi)
    assert np.isfinite(hairbed.solve(1.0, 0.5, -1.5707).xi)


def test_one_status_table_for_every_result():
    """0 ok, negative a failure, positive ok with a caveat (issue 22 item 4): every result
    type takes its messages from the one table, and the codes mean the same everywhere."""
    import hairbed.numerics._collocation as col
    from hairbed import calibration, sensitivity, stability
    from hairbed._core import solution
    from hairbed._core.validation import STATUS_MESSAGES, least_squares_status

    for module in (solution, sensitivity, stability):
        assert module.STATUS_MESSAGES is STATUS_MESSAGES
    assert STATUS_MESSAGES[-2] == "iteration limit reached"
    assert [least_squares_status(c) for c in (-1, 0, 1, 2, 3, 4)] == [-6, -2, 0, 0, 0, 0]
    assert set(col._BVP_STATUS.values()) <= set(STATUS_MESSAGES)
    # an iteration limit is -2 everywhere: the core, the numerical baselines, stability
    from hairbed.numerics import finite_difference

    fd = finite_difference(100.0, 0.5, num=80, maxiter=2)
    eq = stability.equilibrium(2.0, 0.5, 0.0, np.zeros(41), 40, maxiter=1)
    assert fd.status == eq.status == -2
    assert calibration.Measurement.__doc__ is not None and "2 a standard error" in (
        calibration.Measurement.__doc__
    )


def test_numerical_result_iterations_is_a_deprecated_alias_of_nit():
    from hairbed.numerics import shooting

    res = shooting(2.0, 0.5)
    with pytest.warns(FutureWarning, match="use NumericalResult.nit"):
        assert res.iterations == res.nit
    assert res.nfev > 0


def test_collocation_counts_its_evaluations_and_keeps_solve_bvps_code():
    from hairbed.numerics._collocation import collocation

    ok = collocation(2.0, 0.5)
    assert ok.status == 0 and ok.solver_status == 0 and ok.nfev > ok.nit > 0
    tight = collocation(200.0, 0.5, max_nodes=5, num_nodes=5)
    assert tight.solver_status == 1 and tight.status == -2 and not tight.success


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: hairbed.solve_all([1.0, 2.0], 0.5), "omega2, eps and theta0 must be scalars"),
        (lambda: hairbed.branches.folds([0.5, 0.6], 0.0), "eps and theta0 must be scalars"),
        (lambda: fold_parameters(0.5, [0.0, 0.1]), "eps and theta0 must be scalars"),
        (
            lambda: hairbed.inverse.fit_profile([0.0, 0.1, 0.2], [0.1, 0.5, 0.9], [0.5, 0.6]),
            "eps must be a scalar here",
        ),
    ],
)
def test_one_scalar_parameter_check(call, message):
    """Issue 22 item 5: solve_all, fold_parameters, the branch functions and fit_profile
    share validation.check_scalar_inputs, which names only the inputs the caller takes."""
    with pytest.raises(ValueError, match=message):
        call()


# -- deprecated names (issue 22 item 7): each old keyword still works, warns, names the new --


def test_quasistatic_start_is_a_deprecated_alias_of_root():
    from hairbed import quasistatic

    path = [1.2, 1.6, 1.2]
    with pytest.warns(FutureWarning, match="'start' is deprecated.*use 'root'"):
        old = quasistatic.sweep_with_jumps(path, 0.9, -1.5, start="high")
    new = quasistatic.sweep_with_jumps(path, 0.9, -1.5, root="high")
    assert np.array_equal(old.solution.xi, new.solution.xi)
    with pytest.warns(FutureWarning, match="'start' is deprecated"):
        assert np.array_equal(quasistatic.sweep(path, 0.9, -1.5, start="high").xi, new.solution.xi)


@pytest.mark.parametrize(
    ("call", "old", "new"),
    [
        (lambda kw: hairbed.numerics.shooting(2.0, 0.5, **kw), {"tol": 1e-9}, {"rtol": 1e-9}),
        (
            lambda kw: hairbed.numerics.shooting(20.0, 0.5, **kw),
            {"base_curvature": 3.0},
            {"guess": 3.0},
        ),
        (lambda kw: hairbed.numerics.collocation(2.0, 0.5, **kw), {"tol": 1e-7}, {"rtol": 1e-7}),
        (
            lambda kw: hairbed.numerics.collocation(2.0, 0.5, **kw),
            {"nodes": 11},
            {"num_nodes": 11},
        ),
    ],
)
def test_a_renamed_parameter_keeps_working_and_names_the_new_one(call, old, new):
    ((old_name, _),) = old.items()
    ((new_name, _),) = new.items()
    with pytest.warns(FutureWarning, match=f"'{old_name}' is deprecated.*use '{new_name}'"):
        by_old = call(old)
    by_new = call(new)
    assert by_old.tip_height == by_new.tip_height and by_old.nit == by_new.nit
    with pytest.raises(TypeError, match=f"give '{new_name}' only"):
        call({**old, **new})
