"""The SI pillar sensor (hairbed.Pillar, issue 21): against the mpmath reference through SI
arithmetic written here, the inverse, the linear range, the sensitivity, calibration with its
coverage, and bad input."""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from tolerances import FINITE_DIFFERENCE_RTOL, PILLAR_REFERENCE_ATOL

import hairbed
from hairbed import calibration

DATA = json.loads((Path(__file__).parent / "data" / "pillar_mpmath.json").read_text())
L, A, E, ETA = 500e-6, 25e-6, 1.0e6, 1.0e-3  # L/a = 20: the reference's Gray & Hancock gamma
#: The relative rounding of tau -> Lambda in SI (a few ulps), times the deflection's slope.
SI_ROUNDING = 1e-14


def _forcing_per_stress(length=L, radius=A, modulus=E, eta=ETA, scale=1.0):
    """Lambda/tau_w [1/Pa], written out: zeta_perp L^4/(eta E I), I = pi a^4/4, zeta_perp =
    4 pi eta/(ln(2L/a) + 1/2) (Gray & Hancock)."""
    inertia = math.pi * radius**4 / 4.0
    zeta = scale * 4.0 * math.pi * eta / (math.log(2.0 * length / radius) + 0.5)
    return zeta * length**4 / (eta * modulus * inertia)


def _pillar(profile="sublayer", theta0=0.0, height_ratio=None, **kw):
    h = kw.pop("channel_height", None if height_ratio is None else L / height_ratio)
    return hairbed.Pillar(
        length=L,
        radius=A,
        youngs_modulus=E,
        viscosity=ETA,
        base_angle=theta0,
        profile=profile,
        channel_height=h,
        **kw,
    )


def _gamma_cases(section):
    """The reference's states at the Gray & Hancock gamma of L/a = 20 (a Pillar's own), one
    state per forcing, built-in profiles."""
    g = float(DATA["gray_hancock"]["gamma"])
    return [
        c
        for c in DATA[section]
        if abs(float(c["gamma"]) - g) < 1e-15
        and c["profile"] != "callable"
        and c["states_at_forcing"] == 1
    ]


def test_gamma_is_gray_hancock_of_the_slenderness():
    lg = math.log(2.0 * 20.0)
    assert _pillar().drag_ratio == pytest.approx((lg + 0.5) / (2.0 * lg - 1.0), rel=1e-15)
    assert _pillar().drag_ratio == pytest.approx(float(DATA["gray_hancock"]["gamma"]), rel=1e-15)


def test_si_states_match_the_mpmath_reference():
    """Every reference state at the pillar's gamma, driven in SI by the wall stress, the
    Couette wall speed V = tau H/eta or the Poiseuille gradient G = 2 tau/H."""
    cases = _gamma_cases("cases")
    assert len(cases) >= 15
    k = _forcing_per_stress()
    ei = E * math.pi * A**4 / 4.0
    for c in cases:
        r = c["profile_parameters"].get("L/H")
        p = _pillar(c["profile"], c["theta0"], r)
        tau = c["forcing"] / k
        if c["profile"] == "couette":
            st = p.deform(velocity=tau * (L / r) / ETA)
        elif c["profile"] == "poiseuille":
            st = p.deform(pressure_gradient=2.0 * tau / (L / r))
        else:
            st = p.deform(wall_shear_stress=tau)
        assert st.success, c
        assert st.wall_shear_stress == pytest.approx(tau, rel=1e-14)
        x1, h1 = float(c["tip_deflection"]), float(c["tip_height"])
        # the SI conversion rounds Lambda by ~1e-16: it moves x1 by slope * that
        atol = PILLAR_REFERENCE_ATOL + SI_ROUNDING * c["forcing"]
        assert st.tip_deflection / L == pytest.approx(x1, abs=atol), c
        assert st.tip_height / L == pytest.approx(h1, abs=atol), c
        assert st.tip_displacement / L == pytest.approx(x1 - math.sin(c["theta0"]), abs=atol)
        assert st.tip_angle == pytest.approx(float(c["tip_angle"]), abs=atol)
        big = max(1.0, abs(float(c["base_curvature"])), abs(float(c["drag_x"])))
        assert st.base_moment * L / ei == pytest.approx(float(c["base_curvature"]), abs=atol * big)
        assert st.drag * L**2 / ei == pytest.approx(float(c["drag_x"]), abs=atol * big)
        assert st.drag_wall_normal * L**2 / ei == pytest.approx(float(c["drag_z"]), abs=atol * big)


def test_inverse_matches_the_mpmath_reference():
    cases = _gamma_cases("inverse")
    assert len(cases) >= 3
    k = _forcing_per_stress()
    for c in cases:
        r = c["profile_parameters"].get("L/H")
        p = _pillar(c["profile"], c["theta0"], r)
        tau = p.wall_shear_stress_from_tip_deflection(float(c["given_tip_deflection"]) * L)
        assert tau * k == pytest.approx(float(c["forcing"]), rel=1e-10), c


@pytest.mark.parametrize(
    "profile, theta0, ratio",
    [("sublayer", 0.0, None), ("sublayer", -1.2, None), ("couette", 0.6, 0.7),
     ("poiseuille", 0.0, 1.0)],
)  # fmt: skip
def test_inverse_round_trip(profile, theta0, ratio):
    """tau -> deflection -> tau within 1e-10, Lambda from 1e-6 to 1e4, both flow directions."""
    p = _pillar(profile, theta0, ratio)
    lam = np.geomspace(1e-6, 1e4, 21)
    tau = np.concatenate([lam, -lam[::3]]) / _forcing_per_stress()
    d = p.deform(tau).tip_deflection
    back = p.wall_shear_stress_from_tip_deflection(d)
    # 1e-10, plus the conditioning of reading a displacement (x1 - sin theta0) off a deflection
    # measured from the base: an absolute error ~1e-15 of x1 (the rounding of d, the solves'
    # own) moves tau by 1e-15/(x1 - sin theta0) relative, 2.5e-8 at Lambda = 1e-6, -1.2 rad
    x1 = d / L
    cond = 2e-15 / np.abs(x1 - math.sin(theta0))
    assert np.all(np.abs(back / tau - 1.0) <= 1e-10 + cond)
    strict = (np.abs(tau) * _forcing_per_stress() >= 1e-3) | (theta0 == 0.0)
    np.testing.assert_allclose(back[strict], tau[strict], rtol=1e-10, atol=0.0)
    again = p.state_from_tip_deflection(d)
    np.testing.assert_allclose(again.tip_deflection, d, rtol=1e-13, atol=1e-13 * L)


def test_sensitivity_against_finite_differences_and_the_linear_limit():
    p = _pillar("sublayer", 0.4)
    tau = np.array([1e-3, 0.3, 3.0, 30.0, 300.0])
    h = 1e-5 * tau
    fd = (p.tip_deflection(tau + h) - p.tip_deflection(tau - h)) / (2.0 * h)
    np.testing.assert_allclose(p.sensitivity(tau), fd, rtol=FINITE_DIFFERENCE_RTOL)
    # at rest: the linear cantilever, dx/dtau = L 11 cos^3(theta0)/120 Lambda/tau
    lin = L * 11.0 * math.cos(0.4) ** 3 / 120.0 * _forcing_per_stress()
    assert p.sensitivity(0.0) == pytest.approx(lin, rel=1e-12)


@pytest.mark.parametrize(
    "profile, ratio, theta0, closed",
    [
        ("sublayer", None, 0.0, 11.0 / 120.0),
        ("sublayer", None, -0.9, 11.0 * math.cos(-0.9) ** 3 / 120.0),
        ("couette", 0.5, 0.3, 11.0 * math.cos(0.3) ** 3 / 120.0),
        ("poiseuille", 0.5, 0.0, (33.0 - 26.0 * 0.5) / 360.0),
        ("poiseuille", 1.0, 0.0, (33.0 - 26.0) / 360.0),
    ],
)
def test_linear_coefficient_closed_forms(profile, ratio, theta0, closed):
    assert _pillar(profile, theta0, ratio).linear_coefficient == pytest.approx(closed, rel=1e-13)


def test_callable_profile_is_scaled_by_its_wall_stress():
    """u(z) = s (z + z^2/L) [m/s]: wall stress eta s, U = z + z^2 in L, x1_lin = 11/120 +
    13/180 per Lambda; its states are those of the core's callable U = z + z^2."""
    s = 3.0
    p = hairbed.Pillar(
        length=L, radius=A, youngs_modulus=E, viscosity=ETA, profile=lambda z: s * (z + z * z / L)
    )
    assert p.linear_coefficient == pytest.approx(11.0 / 120.0 + 13.0 / 180.0, rel=1e-13)
    tau = np.array([0.1, 10.0])
    lam = tau * _forcing_per_stress()
    core = hairbed.solve_pillar(lam, profile=lambda z: z + z * z, gamma=p.drag_ratio)
    np.testing.assert_allclose(p.deform(tau).tip_deflection / L, core.tip_deflection, rtol=1e-12)


@pytest.mark.parametrize("theta0", [0.0, 0.5])
def test_linear_range_against_the_exact_curve(theta0):
    p = _pillar("sublayer", theta0)
    lr = p.linear_range(0.05)
    assert lr.success and lr.status == 0 and lr.quantity == "wall_shear_stress"
    c3 = 11.0 * math.cos(theta0) ** 3 / 120.0
    k = _forcing_per_stress()

    def err(d):
        exact = p.wall_shear_stress_from_tip_deflection(d)
        return (d / L - math.sin(theta0)) / (c3 * k) / exact - 1.0

    assert abs(err(lr.tip_deflection)) == pytest.approx(0.05, abs=1e-9)
    below = np.linspace(0.02, 0.98, 9) * (lr.tip_deflection - L * math.sin(theta0))
    assert np.all(np.abs(err(L * math.sin(theta0) + below)) < 0.05)
    assert p.deform(lr.wall_shear_stress).tip_deflection == pytest.approx(
        lr.tip_deflection, rel=1e-10
    )
    assert calibration.linear_range(p, rtol=0.05).wall_shear_stress == pytest.approx(
        lr.wall_shear_stress, rel=1e-12
    )
    # tighter tolerance, shorter range
    assert (
        _pillar().linear_range(0.01).wall_shear_stress
        < _pillar().linear_range(0.05).wall_shear_stress
    )


def test_calibration_round_trip_and_model():
    true = replace(_pillar(), youngs_modulus=1.3e6)
    tau = np.linspace(0.5, 200.0, 9)
    d = calibration.model_tip_deflection(true, wall_shear_stress=tau)
    np.testing.assert_array_equal(d, true.deform(tau).tip_deflection)
    res = calibration.fit(_pillar(), d, wall_shear_stress=tau, sigma=1e-8)
    assert res.success and res.kind == "wall_shear_stress"
    assert res.values["youngs_modulus"] == pytest.approx(1.3e6, rel=1e-9)
    drag = calibration.fit(_pillar(), d, wall_shear_stress=tau, free="drag_scale")
    assert drag.values["drag_scale"] == pytest.approx(1.0 / 1.3, rel=1e-9)
    # E and c are one parameter (c/E): refused before the fit (issue 33)
    with pytest.raises(ValueError, match="drag_scale/E"):
        calibration.fit(_pillar(), d, wall_shear_stress=tau, free=("youngs_modulus", "drag_scale"))
    m = calibration.measure(res.bed, d[4], sigma=1e-8, fit=res)
    assert m.wall_shear_stress == pytest.approx(tau[4], rel=1e-9) and m.success
    # Couette: calibrated by wall speeds V = tau H/eta
    cou = replace(_pillar("couette", 0.2, 0.5), youngs_modulus=1.3e6)
    v = np.linspace(0.1, 50.0, 6)
    dc = calibration.model_tip_deflection(cou, velocity=v)
    fc = calibration.fit(replace(cou, youngs_modulus=1e6), dc, velocity=v)
    assert fc.values["youngs_modulus"] == pytest.approx(1.3e6, rel=1e-9) and fc.kind == "velocity"
    assert fc.fingerprint == calibration.points_fingerprint(dc, velocity=v)
    mc = calibration.measure(fc.bed, dc[2], sigma=1e-8)
    assert mc.velocity == pytest.approx(v[2], rel=1e-9)
    assert mc.velocity_stderr == pytest.approx(mc.wall_shear_stress_stderr * 2 * L / ETA)


def test_coverage_of_one_sigma_intervals_over_200_sensors():
    """200 synthetic sensors (fixed seed): E fitted from 8 noisy points, then a new deflection
    measured; the 1-sigma intervals of E and of the measured tau_w each cover the truth in
    about 68.3 % of the sensors (binomial sd 3.3 %: 4 sd allowed)."""
    rng = np.random.default_rng(20261203)
    true = replace(_pillar(theta0=0.2), youngs_modulus=1.3e6)
    tau = np.linspace(1.0, 120.0, 8)
    d_true = true.deform(tau).tip_deflection
    tau_new = 60.0
    d_new = float(true.deform(tau_new).tip_deflection)
    sigma = 1e-6  # [m], against deflections of 25 to 250 um
    guess = _pillar(theta0=0.2)
    hit_e = hit_t = 0
    n = 200
    for _ in range(n):
        res = calibration.fit(
            guess, d_true + sigma * rng.standard_normal(8), wall_shear_stress=tau, sigma=sigma
        )
        assert res.success
        hit_e += abs(res.values["youngs_modulus"] - 1.3e6) <= res.stderr["youngs_modulus"]
        m = calibration.measure(
            res.bed, d_new + sigma * rng.standard_normal(), sigma=sigma, fit=res
        )
        hit_t += abs(m.wall_shear_stress - tau_new) <= m.wall_shear_stress_stderr
    for hits in (hit_e, hit_t):
        assert abs(hits / n - 0.683) <= 4.0 * math.sqrt(0.683 * 0.317 / n), (hit_e, hit_t)


def test_no_convergence_is_a_status():
    st = _pillar().deform([1.0, 1e300])
    assert list(st.status >= 0) == [True, False] and np.isnan(st.tip_deflection[1])
    assert st.success.tolist() == [True, False] and st.message[0] == "ok"


def test_reynolds_and_slenderness_warnings():
    with pytest.warns(hairbed.ModelValidityWarning, match="slenderness"):
        hairbed.Pillar(length=L, radius=L / 5, youngs_modulus=E, viscosity=ETA)
    p = _pillar(density=1000.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st = p.deform(0.01)
    # Re = rho u(tip) 2a/eta with u(tip) = tau h1 L/eta (the sublayer at the tip's height)
    assert st.reynolds_number == pytest.approx(
        1000.0 * 0.01 * st.tip_height / ETA * 2 * A / ETA, rel=1e-13
    )
    with pytest.warns(hairbed.ModelValidityWarning, match="Reynolds"):
        p.deform(100.0)
    assert math.isnan(_pillar().deform(1.0).reynolds_number)


def _wrong_shape(z):
    return np.ones(3)


@pytest.mark.parametrize(
    "make, error, match",
    [
        (lambda: _pillar().__class__(-L, A, E, ETA), ValueError, r"length must be positive"),
        (lambda: _pillar().__class__(L, math.nan, E, ETA), ValueError, r"radius must be finite"),
        (
            lambda: _pillar().__class__(L, A, 0.0, ETA),
            ValueError,
            r"youngs_modulus must be positive",
        ),
        (lambda: _pillar().__class__(L, A, E, math.inf), ValueError, r"viscosity must be finite"),
        (lambda: _pillar(theta0=2.0), ValueError, r"base_angle must lie in \(-1.5708, 1.5708\)"),
        (
            lambda: _pillar("couette", height_ratio=1.5),
            ValueError,
            r"length .* must not exceed channel_height",
        ),
        (lambda: _pillar("poiseuille"), ValueError, r"profile 'poiseuille' needs channel_height"),
        (lambda: _pillar(channel_height=1e-3), ValueError, r"channel_height is used only by"),
        (lambda: _pillar("plug"), ValueError, r"profile must be one of 'sublayer', 'couette'"),
        (
            lambda: _pillar(_wrong_shape),
            ValueError,
            r"profile: the callable must return an array of the shape",
        ),
        (
            lambda: _pillar(lambda z: np.where(z > 0, z, np.nan)),
            ValueError,
            r"profile: the callable returned nan m/s at z = 0.0 m \(index 0\)",
        ),
        (
            lambda: _pillar(lambda z: (z / L) ** 2),
            ValueError,
            r"wall shear stress eta u'\(0\) is zero",
        ),
        (
            lambda: _pillar().__class__(L, L, E, ETA),
            ValueError,
            r"slenderness length/radius must be at least e\^1.5/2 = 2.2408",
        ),
        (  # gamma 1.064 > 1: the core's drag ratio is out of (0, 1]
            lambda: _pillar().__class__(L, L / 2.0, E, ETA),
            ValueError,
            r"slenderness length/radius must be at least .* got 2.0",
        ),
        (lambda: _pillar(drag_scale=-1.0), ValueError, r"drag_scale must be positive"),
        (lambda: _pillar(density=0.0), ValueError, r"density must be positive"),
        (lambda: _pillar().deform(), TypeError, r"exactly one of wall_shear_stress"),
        (
            lambda: _pillar().deform(velocity=1.0),
            ValueError,
            r"velocity drives a 'couette' channel",
        ),
        (
            lambda: _pillar().deform([1.0, math.nan]),
            ValueError,
            r"wall_shear_stress must be finite .*index 1",
        ),
        (
            lambda: replace(_pillar(), radius=L / 1e3).deform(1e303),
            ValueError,
            r"wall_shear_stress must be below .* Pa in magnitude",
        ),
        (
            lambda: _pillar().wall_shear_stress_from_tip_deflection([1e-4, -L]),
            ValueError,
            r"tip_deflection must lie in \(-length, length\) .*index 1",
        ),
        (lambda: _pillar().linear_range(0.0), ValueError, r"rtol must lie in \(0, 1\)"),
        (
            lambda: calibration.fit(_pillar(), [1e-5], wall_shear_stress=[1.0], free="spacing"),
            ValueError,
            r"unknown parameter 'spacing'; allowed for a pillar: youngs_modulus, drag_scale, "
            "base_angle, length, radius",
        ),
        (
            lambda: calibration.fit(_pillar(), [1e-5], velocity=[1.0]),
            ValueError,
            r"velocity drives a 'couette' channel",
        ),
        (
            lambda: calibration.fit("pillar", [1e-5], wall_shear_stress=[1.0]),
            TypeError,
            r"bed must be a hairbed.HairBed or a hairbed.Pillar, got str",
        ),
        (
            lambda: calibration.linear_range(_pillar(), quantity="velocity"),
            ValueError,
            r"quantity 'velocity' needs a 'couette' pillar",
        ),
    ],
)
def test_bad_input_is_named(make, error, match):
    with pytest.raises(error, match=match):
        make()


def test_measure_refuses_a_fit_of_the_other_sensor():
    bed = hairbed.HairBed(
        length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3, viscosity=1.0,
        spacing=400e-6,
    )  # fmt: skip
    v = np.linspace(0.01, 0.2, 4)
    res = calibration.fit(bed, calibration.model_tip_deflection(bed, velocity=v), velocity=v)
    with pytest.raises(
        TypeError, match="fit is the calibration of a HairBed, but bed is a Pillar"
    ):
        calibration.measure(_pillar(), 1e-5, fit=res)


def test_linear_range_of_a_pillar_leaning_downstream():
    """theta0 = 1.4: the tip starts 0.985 L out and the inverse finds no state right at the
    wall; the search stops there instead of failing, and the range is still found."""
    p = _pillar("sublayer", 1.4)
    lr = p.linear_range(0.5)
    assert lr.status == 0 and lr.wall_shear_stress_error == pytest.approx(-0.5, abs=1e-9)
    d = lr.tip_deflection
    lin = (d / L - math.sin(1.4)) / (11.0 * math.cos(1.4) ** 3 / 120.0 * _forcing_per_stress())
    assert lin / p.wall_shear_stress_from_tip_deflection(d) - 1.0 == pytest.approx(-0.5, abs=1e-9)


def test_a_pillar_refuses_the_pump_drives_of_a_bed():
    """A pillar stands in a shear layer: calibrating it against a pressure gradient or a flow
    rate (a pump-driven HairBed's known quantities) is an error naming the parameter."""
    p = _pillar()
    d = np.array([1e-6, 2e-6])
    for name in ("pressure_gradient", "flow_rate"):
        with pytest.raises(ValueError, match=name):
            calibration.model_tip_deflection(p, **{name: [1.0, 2.0]})
        with pytest.raises(ValueError, match=name):
            calibration.fit(p, d, **{name: [1.0, 2.0]})
        with pytest.raises(ValueError, match="drive"):
            calibration.measure(p, d, drive=name)
