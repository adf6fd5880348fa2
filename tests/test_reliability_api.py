"""Issue 33, the library half: each "wrong or silent" item and each trap of the Python API,
reproduced as a test.

Every expected value comes from an independent source: a closed form of the rest state or
the linear theory, finite differences of the solver's own states at a different input, or the
plain formula at a non-zero drive.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hairbed
from hairbed.sensitivity import derivatives_at

BED = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 400e-6,
}


# -- 1. tracebacks from inside numpy ------------------------------------------------------


def test_loaded_guess_of_another_shape_is_refused_by_name() -> None:
    guess = hairbed.solve(np.array([0.5, 1.0, 2.0]), 0.5, 0.1)
    with pytest.raises(ValueError, match=r"\bguess\b.*shape \(\).*\(3,\)"):
        hairbed.solve_loaded(0.5, 0.5, 0.1, pi=1.0, guess=guess)
    with pytest.raises(ValueError, match=r"\bguess\b"):
        hairbed.solve_loaded(np.array([0.5, 1.0]), 0.5, 0.1, pi=1.0, guess=guess)


def test_loaded_guess_that_broadcasts_is_used() -> None:
    w = np.array([0.5, 1.0, 2.0])
    st = hairbed.solve_loaded(w, 0.5, 0.1, pi=0.0, guess=hairbed.solve(1.0, 0.5, 0.1))
    ref = hairbed.solve(w, 0.5, 0.1)  # pi = 0: the closed form
    np.testing.assert_allclose(st.tip_height, ref.tip_height, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "make",
    [
        lambda: hairbed.derivatives(np.array([]), 0.5, pi=1.0),
        lambda: hairbed.derivatives(np.array([]), 0.5, q=1.0),
        lambda: derivatives_at(hairbed.solve_pillar(np.array([]))),
        lambda: derivatives_at(hairbed.solve_loaded(np.zeros((0, 2)), 0.5, pi=1.0)),
        lambda: hairbed.derivatives(np.array([]), 0.5),
    ],
)
def test_derivatives_of_empty_states_are_empty(make) -> None:
    d = make()
    assert np.shape(d.status)[-1:] in ((0,), (2,)) and np.size(d.status) == 0
    for row in d.table.values():
        for value in row.values():
            assert np.size(value) == 0


# -- 3. NaN with status 0 -----------------------------------------------------------------


@pytest.mark.parametrize("theta0", [0.0, 0.4, -0.3])
def test_stress_ratio_at_zero_pump_drive_is_its_limit(theta0: float) -> None:
    bed = hairbed.HairBed(**BED, base_angle=theta0)
    gap = BED["channel_height"] - BED["length"] * math.cos(theta0)  # the hair at rest
    height = BED["channel_height"]
    st = bed.deform(pressure_gradient=0.0)
    assert st.stress_ratio == pytest.approx(gap / height, rel=1e-14)  # tau/bare = g/H
    st = bed.deform(flow_rate=0.0)
    assert st.stress_ratio == pytest.approx((height / gap) ** 2, rel=1e-14)
    sw = bed.sweep(pressure_gradient=np.array([0.0, 1e-9]))
    assert np.all(np.isfinite(np.asarray(sw["stress_ratio"])))
    np.testing.assert_allclose(np.asarray(sw["stress_ratio"]), gap / height, rtol=1e-8)


def test_porous_stress_ratio_at_zero_drive_is_the_weak_drive_limit() -> None:
    bed = hairbed.HairBed(**BED, model="porous")
    for kw, weak in (
        ({"pressure_gradient": 0.0}, {"pressure_gradient": 1e-6}),
        ({"flow_rate": 0.0}, {"flow_rate": 1e-15}),
        ({"velocity": 0.0}, {"velocity": 1e-12}),
    ):
        zero = bed.deform(**kw)
        assert zero.solution.status == 0
        assert zero.stress_ratio == pytest.approx(bed.deform(**weak).stress_ratio, rel=1e-9)


def test_valve_curve_at_zero_drop_has_a_finite_stress_ratio() -> None:
    bed = hairbed.HairBed(**BED, base_angle=0.3)
    curve = hairbed.valve.valve_curve(bed, np.array([0.0, 1e-9]), 0.01)
    ratio = np.asarray(curve.states.stress_ratio)
    assert np.all(np.isfinite(ratio))
    assert ratio[0] == pytest.approx(ratio[1], rel=1e-8)


@pytest.mark.parametrize("theta0", [0.0, -1.2, 0.5])
def test_branch_parameter_derivatives_at_rest_match_differences(theta0: float) -> None:
    d = hairbed.derivatives(0.0, 0.9, theta0)
    assert d.status == 0
    assert d.dt["omega2"] == math.inf
    # t(omega2, eps, theta0) - ln(omega2) has a finite limit at rest: central differences of
    # the solver's t at a weak forcing (t is exact to rounding there)
    w, h = 1e-10, 1e-6

    def t(eps: float, t0: float) -> float:
        return float(hairbed.solve(w, eps, t0).t)

    fd_eps = (t(0.9 + h, theta0) - t(0.9 - h, theta0)) / (2 * h)
    fd_t0 = (t(0.9, theta0 + h) - t(0.9, theta0 - h)) / (2 * h)
    assert d.dt["eps"] == pytest.approx(fd_eps, rel=1e-6)
    assert d.dt["theta0"] == pytest.approx(fd_t0, rel=1e-6)


# -- 2. accepted when it should be refused ------------------------------------------------


def test_a_complex_profile_is_refused_without_a_warning() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TypeError, match=r"profile: .*real numbers, got complex values"):
            hairbed.solve_pillar(2.0, profile=lambda z: (1.0 + 1.0j) * z)


@pytest.mark.parametrize("ratio", [math.nan, math.inf, 0.0, 1.5, -0.2])
def test_height_ratio_is_checked_with_a_callable_profile(ratio: float) -> None:
    with pytest.raises(ValueError, match=r"height_ratio .*\(0, 1\]"):
        hairbed.solve_pillar(2.0, profile=lambda z: z, height_ratio=ratio)


def test_solve_pillar_all_refuses_zero_forcing_as_documented() -> None:
    with pytest.raises(ValueError, match=r"forcing must be non-zero .*solve_pillar\(0\.0"):
        hairbed.solve_pillar_all(0.0)


# -- 4. an empty list with no status ------------------------------------------------------


def test_solve_pillar_all_without_drag_is_the_straight_pillar() -> None:
    (st,) = hairbed.solve_pillar_all(2.0, 0.3, profile=lambda z: 0.0 * z)
    assert st.status == 0 and st.stable is True
    # no drag: the straight pillar at its base angle (closed form)
    assert st.tip_deflection == pytest.approx(math.sin(0.3), abs=1e-14)
    assert st.tip_height == pytest.approx(math.cos(0.3), abs=1e-14)


@pytest.mark.parametrize(
    "call",
    [
        lambda: hairbed.solve_loaded_all(1e300, 0.5, 0.1),
        lambda: hairbed.solve_loaded_all(0.5, 0.5, 0.1, pi=1e300),
        lambda: hairbed.solve_loaded_all(0.5, 0.5, 0.1, q=-1e300),
        lambda: hairbed.solve_pillar_all(1e300),
        lambda: hairbed.solve_pillar_all(-1e300, 0.2),
    ],
)
def test_all_states_beyond_reach_say_so(call) -> None:
    found = call()
    assert len(found) == 1
    (st,) = found
    assert st.status < 0 and not st.success
    assert "no state" in st.message
    assert math.isnan(st.tip_height)


# -- 6. messages ----------------------------------------------------------------------------


def test_diodicity_names_the_first_zero_drop() -> None:
    bed = hairbed.HairBed(**BED)
    with pytest.raises(ValueError, match=r"pressure_drop must be non-zero .*index 2\)"):
        hairbed.valve.diodicity(bed, [1.0, -2.0, 0.0, 0.0], 0.01)


@pytest.mark.parametrize(
    "call, rng",
    [
        (lambda: hairbed.solve_pillar(1.0, rtol=math.nan), r"rtol must be finite, in \(0, inf\)"),
        (lambda: hairbed.HairBed(**{**BED, "length": math.nan}), r"length .*\(0, inf\) \[m\]"),
        (
            lambda: hairbed.valve.valve_curve(hairbed.HairBed(**BED), 1.0, math.nan),
            r"channel_length .*\(0, inf\) \[m\]",
        ),
    ],
)
def test_nan_for_a_positive_parameter_states_its_range(call, rng: str) -> None:
    with pytest.raises(ValueError, match=rng):
        call()


def test_a_nan_profile_is_reported_in_one_system_of_units() -> None:
    with pytest.raises(ValueError) as info:
        hairbed.solve_pillar(1.0, profile=lambda z: np.where(z > 0.5, np.nan, z))
    text = str(info.value)
    assert "[L]" not in text or "m/s" not in text
    assert "np.float64" not in text and "returned nan at z = " in text
    with pytest.raises(ValueError) as info:
        hairbed.Pillar(
            length=100e-6, radius=5e-6, youngs_modulus=1e6, viscosity=1e-3,
            profile=lambda z: np.where(z > 50e-6, np.nan, 1e3 * z),
        )  # fmt: skip
    text = str(info.value)
    assert "m/s at z = " in text and "[0, 1] [L]" not in text


def test_gray_hancock_ratio_stops_where_gamma_reaches_one() -> None:
    low = math.exp(1.5) / 2.0
    assert hairbed.gray_hancock_ratio(low) == 1.0  # ln(2 L/a) = 3/2: (3/2 + 1/2)/(3 - 1)
    with pytest.raises(ValueError, match=r"slenderness must lie in \[e\^1.5/2 = 2.2408, inf\)"):
        hairbed.gray_hancock_ratio(np.array([5.0, 2.2]))
    # every slenderness it accepts gives a gamma that the pillar takes
    g = hairbed.gray_hancock_ratio(np.array([low, 2.5, 10.0, 1e6]))
    assert np.all((g > 0.0) & (g <= 1.0))


# -- traps ----------------------------------------------------------------------------------


def test_valve_states_checks_the_reynolds_number_as_valve_curve_does() -> None:
    bed = hairbed.HairBed(**{**BED, "viscosity": 1e-3}, density=1000.0)
    drops = np.array([-100.0, 1.0, 100.0])
    with pytest.warns(hairbed.ModelValidityWarning, match="Reynolds"):
        hairbed.valve.valve_curve(bed, drops, 0.01)
    with pytest.warns(hairbed.ModelValidityWarning, match="Reynolds"):
        hairbed.valve.valve_states(bed, 0.01, pressure_drop=drops)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # slow: Stokes flow, no warning
        hairbed.valve.valve_states(bed, 0.01, pressure_drop=np.array([-1e-3, 1e-3]))


def test_relax_takes_a_scalar_initial_angle() -> None:
    r = hairbed.stability.relax(1.0, 0.5, 0.0, 0.0, 5.0, num=40)
    arr = hairbed.stability.relax(1.0, 0.5, 0.0, np.zeros(41), 5.0, num=40)
    np.testing.assert_array_equal(r.theta, arr.theta)
    # relaxed towards the closed-form state (the discretisation's error at num = 40)
    assert r.theta[-1][-1] == pytest.approx(hairbed.solve(1.0, 0.5).tip_angle, abs=1e-4)
    with pytest.raises(ValueError, match=r"theta_initial .*one number"):
        hairbed.stability.relax(1.0, 0.5, 0.0, np.zeros(7), 5.0, num=40)


def test_pillar_states_say_how_many_coexist() -> None:
    theta0 = -1.4
    lam = np.array([1.0, 15.0, 60.0])
    st = hairbed.solve_pillar(lam, theta0)
    for k, f in enumerate(lam):
        every = hairbed.solve_pillar_all(float(f), theta0)
        assert st.n_states[k] == len(every)
        assert all(s.n_states == len(every) for s in every)
        # each of them is a state at this forcing (the inverse at its deflection)
        for s in every:
            back = hairbed.solve_pillar_inverse(s.tip_deflection, theta0)
            assert float(back.forcing) == pytest.approx(f, rel=1e-9)
    assert list(st.n_states) == [1, 3, 1]
    assert hairbed.solve_pillar(1e300).n_states == 0
    assert hairbed.solve_pillar_inverse(0.1).n_states is None


def test_pillar_deform_in_a_window_says_there_are_three() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        pillar = hairbed.Pillar(
            length=100e-6, radius=5e-6, youngs_modulus=1e6, viscosity=1e-3, base_angle=-1.4
        )
        tau = 15.0 / pillar.forcing_per_stress  # Lambda = 15: inside the window
        d = pillar.deform(np.array([0.01, tau]))
    assert list(d.n_states) == [1, 3]
    assert "solve_pillar_all" in type(d).__doc__
    gamma = float(d.solution.gamma[1])  # Gray & Hancock's of the pillar's L/a
    every = hairbed.solve_pillar_all(float(d.forcing[1]), pillar.base_angle, gamma=gamma)
    assert float(d.tip_deflection[1]) == pytest.approx(
        pillar.length * every[0].tip_deflection, rel=1e-9
    )  # the first state, the one a ramp from rest reaches


# -- calibration: refused, and failing in one way -----------------------------------------

TRUE_BED = hairbed.HairBed(**{**BED, "youngs_modulus": 1.3e6})
SPEEDS = np.linspace(0.01, 0.2, 10)


def _pillar(**kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        return hairbed.Pillar(
            length=500e-6, radius=25e-6, youngs_modulus=2e6, viscosity=1e-3, **kw
        )


def test_fit_refuses_a_deflection_longer_than_the_hair_as_measure_does() -> None:
    from hairbed.calibration import fit, measure, model_tip_deflection

    d = model_tip_deflection(TRUE_BED, velocity=SPEEDS)
    d[3] = 1.5 * TRUE_BED.length
    with pytest.raises(ValueError, match=r"tip_deflection: .*\(first at index 3\)") as a:
        fit(TRUE_BED, d, velocity=SPEEDS)
    with pytest.raises(ValueError) as b:
        measure(TRUE_BED, d)
    assert str(a.value) == str(b.value)


def test_fit_refuses_young_and_drag_scale_together() -> None:
    from hairbed.calibration import fit, model_tip_deflection

    tau = np.linspace(0.05, 2.0, 8)
    d = model_tip_deflection(_pillar(), wall_shear_stress=tau)
    with pytest.raises(ValueError, match=r"free: youngs_modulus, drag_scale .*drag_scale/E"):
        fit(_pillar(), d, wall_shear_stress=tau, free=("youngs_modulus", "drag_scale"))


@pytest.mark.parametrize(
    "free, undetermined",
    [
        (("youngs_modulus", "radius"), {"youngs_modulus", "radius"}),
        (("channel_height",), {"channel_height"}),
        (("youngs_modulus", "viscosity", "base_angle"), {"viscosity"}),
    ],
)
def test_a_degenerate_fit_fails_in_one_way(free, undetermined) -> None:
    from hairbed.calibration import fit, model_tip_deflection

    tau = np.asarray(TRUE_BED.deform(SPEEDS).wall_shear_stress)
    d = model_tip_deflection(TRUE_BED, wall_shear_stress=tau)
    res = fit(TRUE_BED, d, wall_shear_stress=tau, sigma=2e-6, free=free)
    assert res.status == -4 and not res.success
    for j, name in enumerate(free):
        if name in undetermined:
            assert math.isnan(res.values[name]) and math.isnan(res.stderr[name])
            assert np.all(np.isnan(res.covariance[j]))
            # the bed keeps the value it was given
            assert getattr(res.bed, name) == getattr(TRUE_BED, name)
        else:  # determined: the true value, a finite error
            assert res.values[name] == pytest.approx(getattr(TRUE_BED, name), rel=1e-6, abs=1e-9)
            assert 0.0 <= res.stderr[name] < math.inf


def test_a_pillar_calibration_file_has_no_spacing(tmp_path) -> None:
    from hairbed.calibration import fit, model_tip_deflection
    from hairbed.calibration_files import (
        calibration_from_dict,
        calibration_to_dict,
        read_calibration,
        write_calibration,
    )

    tau = np.linspace(0.05, 2.0, 8)
    pillar = _pillar()
    res = fit(pillar, model_tip_deflection(pillar, wall_shear_stress=tau), wall_shear_stress=tau)
    doc = calibration_to_dict(res)
    assert doc["sensor"] == "pillar" and "geometry" not in doc
    path = tmp_path / "pillar.json"
    write_calibration(res, path)
    back = read_calibration(path)
    assert back.values == res.values
    # a file of an older hairbed (with "geometry": "spacing") still reads
    assert calibration_from_dict({**doc, "geometry": "spacing"}).values == res.values


def test_a_negative_variance_in_a_calibration_file_is_refused() -> None:
    from hairbed.calibration import fit, model_tip_deflection
    from hairbed.calibration_files import calibration_from_dict, calibration_to_dict

    d = model_tip_deflection(TRUE_BED, velocity=SPEEDS)
    doc = calibration_to_dict(fit(TRUE_BED, d, velocity=SPEEDS, sigma=2e-6))
    doc["covariance"] = [[-1e6]]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"variance of youngs_modulus is negative"):
            calibration_from_dict(doc, source="cal.json")


def test_a_degenerate_fit_round_trips_through_its_file() -> None:
    from hairbed.calibration import fit, model_tip_deflection
    from hairbed.calibration_files import calibration_from_dict, calibration_to_dict

    tau = np.asarray(TRUE_BED.deform(SPEEDS).wall_shear_stress)
    d = model_tip_deflection(TRUE_BED, wall_shear_stress=tau)
    res = fit(TRUE_BED, d, wall_shear_stress=tau, sigma=2e-6, free=("channel_height",))
    back = calibration_from_dict(calibration_to_dict(res))
    assert back.status == -4 and math.isnan(back.values["channel_height"])


def test_energy_derivatives_near_the_float_range_end_are_finite() -> None:
    # at strong forcing the energy's derivatives scale as omega2^0 (omega2) and omega2^(1/2)
    # (eps, theta0): the generic chain at 1e300 against the overflow-free form at 1.7e308
    ref = hairbed.derivatives(1e300, 0.5, 0.1)["energy"]
    top = hairbed.derivatives(1.7e308, 0.5, 0.1)
    assert top.status == 0
    got = top["energy"]
    assert got["omega2"] == pytest.approx(ref["omega2"], rel=1e-12)
    scale = math.sqrt(1.7e308 / 1e300)
    assert got["eps"] == pytest.approx(ref["eps"] * scale, rel=1e-10)
    assert got["theta0"] == pytest.approx(ref["theta0"] * scale, rel=1e-10)


@pytest.mark.parametrize("omega2", [5e-324, 1e-310])
def test_derivatives_at_a_subnormal_forcing_are_the_weak_limit(omega2: float) -> None:
    tiny = hairbed.derivatives(omega2, 0.5, 0.1)
    ref = hairbed.derivatives(1e-200, 0.5, 0.1)  # the generic path, in the same limit
    assert tiny.status == 0
    for out, row in ref.table.items():
        for name, value in row.items():
            got = tiny[out][name]
            if (out, name) == ("omega_eps", "omega2"):  # 1/(2 omega_eps (1 - eps c))
                value = value * math.sqrt(1e-200 / omega2)
            assert got == pytest.approx(value, rel=1e-9, abs=1e-12), (out, name)
    assert tiny.dt["eps"] == pytest.approx(ref.dt["eps"], rel=1e-12)
    assert tiny.dt["theta0"] == pytest.approx(ref.dt["theta0"], rel=1e-12)


def test_diodicity_says_where_it_has_no_answer() -> None:
    bed = hairbed.HairBed(**BED, base_angle=0.1)
    d = hairbed.valve.diodicity(bed, [200.0, 1e300], 0.01)
    assert list(d.status) == [0, -7] and not d.success
    assert math.isnan(d.diodicity[1]) and "no state" in d.message
    assert hairbed.valve.diodicity(bed, 200.0, 0.01).status == 0


def test_hair_state_defines_its_stresses_for_every_drive() -> None:
    doc = hairbed.HairState.__doc__
    assert "G g / 2" in doc and "G H / 2" in doc and "(H / g)^2" in doc
    bed = hairbed.HairBed(**BED, base_angle=0.2)
    v, grad = 0.01, 500.0
    st = bed.deform(v, pressure_gradient=grad)
    eta, height = BED["viscosity"], BED["channel_height"]
    gap = height - st.tip_height  # what the docstring says, from the state's tip height
    tau = eta * v / gap + grad * gap / 2.0
    assert st.wall_shear_stress == pytest.approx(tau, rel=1e-13)
    assert st.stress_ratio == pytest.approx(
        tau / (eta * v / height + grad * height / 2), rel=1e-13
    )


@pytest.mark.parametrize("key", ["dof", "status", "nfev", "nit", "solver_status"])
@pytest.mark.parametrize("bad", [math.nan, "abc", None, [], 1.5, True])
def test_a_calibration_file_count_must_be_a_whole_number(key: str, bad) -> None:
    from hairbed.calibration import fit, model_tip_deflection
    from hairbed.calibration_files import calibration_from_dict, calibration_to_dict

    d = model_tip_deflection(TRUE_BED, velocity=SPEEDS)
    doc = calibration_to_dict(fit(TRUE_BED, d, velocity=SPEEDS, sigma=2e-6))
    with pytest.raises(ValueError, match=rf"^cal\.json: {key} must be a whole number"):
        calibration_from_dict({**doc, key: bad}, source="cal.json")
