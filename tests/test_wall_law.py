"""The mean flow the pillar stands in (issue 31 item 1a): Spalding's law of the wall against
mpmath written here from the formula, its limits, the profile the collocation takes, pillar
states against the mpmath shooting reference tests/data/wall_law_mpmath.json, the sublayer
limit L+ -> 0, the sensitivity, the inverse, calibration, fluid presets and the warnings."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from tolerances import (
    FINITE_DIFFERENCE_RTOL,
    PILLAR_REFERENCE_ATOL,
    WALL_LAW_PROFILE_ATOL,
    WALL_LAW_RTOL,
)

import hairbed
from hairbed import calibration
from hairbed._core.wall_law import wall_law_coefficients

DATA = json.loads((Path(__file__).parent / "data" / "wall_law_mpmath.json").read_text())
KAPPA, B = mp.mpf("0.41"), mp.mpf("5.0")


def _y_plus(u):
    """Spalding (1961), written out."""
    k = KAPPA * u
    return u + mp.exp(-KAPPA * B) * (mp.exp(k) - 1 - k - k**2 / 2 - k**3 / 6)


def _u_plus(y):
    """u+(y+) by the Illinois method on Spalding's formula (mpmath, 40 digits) in a bracket:
    no Newton, no start."""
    with mp.workdps(40):
        y = mp.mpf(y)
        if y == 0:
            return mp.mpf(0)
        # y+(u) >= u, and y+(u) >= e^(-kappa B) (e^(kappa u) - 1 - ... ) exceeds y+ at the
        # log law plus 10: the root lies in [0, min(y+, that)]
        hi = min(y, mp.log(max(y, 1)) / KAPPA + B + 10)
        return mp.findroot(lambda u: _y_plus(u) - y, (mp.mpf(0), hi), solver="illinois")


def _pillar(**kw):
    base = {
        "length": 1e-3,
        "radius": 50e-6,
        "youngs_modulus": 1e5,
        "fluid": "water",
        "profile": "wall-law",
    }
    base.update(kw)
    return hairbed.Pillar(**base)


@pytest.fixture(autouse=True)
def _quiet_reynolds():
    # the pillars here are in the Reynolds numbers of real sensors (tens): that warning is
    # tested in tests/test_pillars.py; the ones of this issue are caught by name below
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="pillar Reynolds number")
        yield


# -- the profile ------------------------------------------------------------------------------


@pytest.mark.parametrize("y", [0.0, 1e-8, 1e-3, 0.5, 1.0, 4.0, 11.0, 30.0, 300.0, 1e4, 1e7])
def test_spalding_against_mpmath(y):
    u = hairbed.spalding_u_plus(y)
    ref = _u_plus(y)
    assert abs(u - float(ref)) <= WALL_LAW_RTOL * max(1e-300, float(ref)) or (y == 0 and u == 0)
    # and the explicit formula the other way
    if y > 0:
        assert hairbed.spalding_y_plus(float(ref)) == pytest.approx(y, rel=WALL_LAW_RTOL)


def test_spalding_vectorised_and_monotone():
    y = np.geomspace(1e-10, 1e8, 4001)
    u = hairbed.spalding_u_plus(y)
    assert u.shape == y.shape and np.all(np.diff(u) > 0)
    some = y[::400]
    ref = np.array([float(_u_plus(v)) for v in some])
    assert np.max(np.abs(u[::400] / ref - 1.0)) <= WALL_LAW_RTOL


def test_spalding_limits():
    # the sublayer: u+ = y+ - e^(-kappa B) (kappa y+)^4/24 + O(y+^5)
    for y in (1e-3, 1e-2):
        u = hairbed.spalding_u_plus(y)
        lead = math.exp(-0.41 * 5.0) * (0.41 * y) ** 4 / 24.0
        assert abs((y - u) / lead - 1.0) < 0.41 * y * 1.5  # the next term is O(kappa y+)
    assert hairbed.spalding_u_plus(1e-9) == pytest.approx(1e-9, rel=1e-15)
    # the log law: u+ - (ln(y+)/kappa + B) -> 0 like 1/y+ up to powers of ln(y+)
    gaps = [abs(hairbed.spalding_u_plus(y) - (math.log(y) / 0.41 + 5.0)) for y in (1e4, 1e6, 1e8)]
    assert gaps[0] < 1e-2 and gaps[1] < 1e-3 and gaps[2] < 1e-5
    assert gaps[0] > gaps[1] > gaps[2]


def test_profile_coefficients_against_mpmath():
    z = np.array([0.0, 1e-4, 0.01, 0.137, 0.5, 0.9, 1.0])
    for lp in (0.3, 5.0, 31.5, 300.0, 3000.0):
        prof, dprof = wall_law_coefficients(lp)
        cheb = np.polynomial.chebyshev
        u = cheb.chebval(2 * z - 1, prof[0])
        du = 2.0 * cheb.chebval(2 * z - 1, cheb.chebder(prof[0]))
        dq = cheb.chebval(2 * z - 1, dprof[0])
        for zi, ui, dui, dqi in zip(z, u, du, dq):
            up = _u_plus(lp * zi)
            ref = up / lp
            slope = 1 / mp.diff(_y_plus, up) if zi > 0 else mp.mpf(1)  # U' = du+/dy+
            assert abs(ui - float(ref)) <= WALL_LAW_PROFILE_ATOL
            assert abs(dui - float(slope)) <= 100 * WALL_LAW_PROFILE_ATOL * max(1.0, lp**0.5)
            assert abs(dqi - float(zi * slope - ref)) <= WALL_LAW_PROFILE_ATOL
    prof, dprof = wall_law_coefficients(0.0)  # the sublayer
    assert prof[0, :2].tolist() == [0.5, 0.5] and not np.any(prof[0, 2:]) and not np.any(dprof)


def test_spalding_bad_input():
    with pytest.raises(ValueError, match=r"y_plus.*\[0, 1e\+100\].*index 1"):
        hairbed.spalding_u_plus([1.0, -1.0])
    with pytest.raises(ValueError, match=r"y_plus.*\[0, 1e\+100\]"):
        hairbed.spalding_u_plus(1e300)
    with pytest.raises(ValueError, match=r"u_plus.*\[0, 1463.41\]"):
        hairbed.spalding_y_plus(2000.0)
    with pytest.raises(ValueError, match="y_plus"):
        hairbed.spalding_u_plus(np.nan)
    with pytest.raises(ValueError, match="kappa"):
        hairbed.spalding_u_plus(1.0, kappa=0.0)
    with pytest.raises(ValueError, match="u_plus"):
        hairbed.spalding_y_plus(-0.5)


# -- pillar states against the independent shooting reference ---------------------------------


@pytest.mark.parametrize("case", DATA["cases"], ids=lambda c: c["name"])
def test_pillar_against_mpmath_shooting(case):
    inp = {k: float(v) for k, v in case["inputs"].items()}
    tau = inp.pop("wall_shear_stress")
    p = hairbed.Pillar(
        length=inp["length"],
        radius=inp["radius"],
        youngs_modulus=inp["youngs_modulus"],
        viscosity=inp["viscosity"],
        density=inp["density"],
        base_angle=inp["base_angle"],
        profile="wall-law",
    )
    st = p.deform(tau)
    assert st.status == 0
    assert st.forcing == pytest.approx(float(case["forcing"]), rel=1e-14)
    assert st.height_in_wall_units == pytest.approx(float(case["l_plus"]), rel=1e-14)
    length = inp["length"]
    for name, scale in (
        ("tip_deflection", length),
        ("tip_height", length),
        ("tip_angle", 1.0),
        ("base_moment", p.bending_stiffness / length),
        ("drag", p.bending_stiffness / length**2),
    ):
        ref = float(case[name])
        got = getattr(st, name)
        # in the units of the state (L, rad, E I/L, E I/L^2), relative above 1
        err = abs(got - ref) / scale / max(1.0, abs(ref) / scale)
        assert err <= PILLAR_REFERENCE_ATOL, (name, got, ref, err)
    # the inverse gives the stress back
    back = p.wall_shear_stress_from_tip_deflection(float(case["tip_deflection"]))
    assert back == pytest.approx(tau, rel=1e-9)


def test_reference_data_is_what_its_inputs_say():
    # the generator's dimensionless inputs from its SI ones, written here (theory.md §12),
    # and its resolution check, without hairbed
    assert DATA["kappa"] == "0.41" and DATA["B"] == "5.0"
    for case in DATA["cases"]:
        i = {k: float(v) for k, v in case["inputs"].items()}
        lg = math.log(2 * i["length"] / i["radius"])
        inertia = math.pi * i["radius"] ** 4 / 4
        zeta = 4 * math.pi * i["viscosity"] / (lg + 0.5)
        lam = (
            zeta
            * i["wall_shear_stress"]
            * i["length"] ** 4
            / (i["viscosity"] * i["youngs_modulus"] * inertia)
        )
        lp = i["length"] * math.sqrt(abs(i["wall_shear_stress"]) * i["density"]) / i["viscosity"]
        assert float(case["forcing"]) == pytest.approx(lam, rel=1e-14)
        assert float(case["gamma"]) == pytest.approx((lg + 0.5) / (2 * lg - 1), rel=1e-14)
        assert float(case["l_plus"]) == pytest.approx(lp, rel=1e-14)
        assert float(case["richardson_difference"]) < 1e-13


# -- the sublayer limit, the slope, the inverse -----------------------------------------------


def test_wall_law_reduces_to_the_sublayer_as_l_plus_vanishes():
    # L+ -> 0 (glycerol, a small stress): U = z - c L+^3 z^4 + O(L+^4), c = e^(-kappa B)
    # kappa^4/24, so at small Lambda x1 = Lambda (11/120 - c L+^3 17/336) + O(Lambda^3)
    # (theory.md §12's kernel s^2 (3 - s)/6 against s^4: int s^6 (3 - s)/6 = 17/336)
    c = math.exp(-0.41 * 5.0) * 0.41**4 / 24.0
    p = _pillar(fluid="glycerol", profile="wall-law", youngs_modulus=1e7)
    sub = _pillar(fluid="glycerol", youngs_modulus=1e7, profile="sublayer")
    for tau in (0.158, 1.42):
        st, ss = p.deform(tau), sub.deform(tau)
        lp = st.height_in_wall_units
        assert 0.009 < lp < 0.031 and st.forcing < 0.1
        diff = (st.tip_deflection - ss.tip_deflection) / 1e-3
        assert diff == pytest.approx(-st.forcing * c * lp**3 * 17.0 / 336.0, rel=1e-2)
    # the calibration and its sensitivity tend to the sublayer's
    assert p.sensitivity(1e-3) == pytest.approx(sub.sensitivity(1e-3), rel=1e-12)
    d = sub.tip_deflection(1e-3)
    assert p.wall_shear_stress_from_tip_deflection(d) == pytest.approx(1e-3, rel=1e-12)


@pytest.mark.parametrize("tau", [0.3, 2.0, -1.5])
def test_sensitivity_is_the_derivative_in_the_stress(tau):
    p = _pillar(base_angle=0.2)
    h = 1e-3 * abs(tau)

    def d(t):
        return p.tip_deflection(t)

    # Richardson's central difference (truncation h^4)
    d1 = (d(tau + h) - d(tau - h)) / (2 * h)
    d2 = (d(tau + 2 * h) - d(tau - 2 * h)) / (4 * h)
    fd = (4 * d1 - d2) / 3
    assert p.sensitivity(tau) == pytest.approx(fd, rel=FINITE_DIFFERENCE_RTOL * 1e-2)
    # and it is not the frozen profile's (the shape's part is a tenth of it at L+ ~ 30)
    frozen = p.deform(tau).solution.tip_deflection_slope * p.forcing_per_stress * p.length
    assert abs(frozen / fd - 1.0) > 0.02


def test_inverse_round_trip_and_shapes():
    p = _pillar(base_angle=-0.3)
    taus = np.array([[0.0, 0.01, 0.4], [2.0, -0.7, 5.0]])
    st = p.deform(taus)
    assert st.height_in_wall_units.shape == taus.shape
    back = p.wall_shear_stress_from_tip_deflection(st.tip_deflection)
    assert back.shape == taus.shape
    assert np.allclose(back, taus, rtol=1e-10, atol=1e-14)
    s2 = p.state_from_tip_deflection(st.tip_deflection[1, 2])
    assert s2.wall_shear_stress == pytest.approx(5.0, rel=1e-10)
    assert s2.height_in_wall_units == pytest.approx(st.height_in_wall_units[1, 2], rel=1e-10)


def test_calibration_fit_measure_and_linear_range():
    truth = _pillar()
    tau = np.linspace(0.2, 4.0, 8)
    d = truth.tip_deflection(tau)
    guess = _pillar(youngs_modulus=2e5)
    fit = calibration.fit(guess, d, wall_shear_stress=tau, free=("youngs_modulus",))
    assert fit.success
    assert fit.bed.youngs_modulus == pytest.approx(1e5, rel=1e-8)
    assert fit.bed.profile == "wall-law" and fit.bed.density == pytest.approx(998.21)
    m = calibration.measure(fit.bed, d[3], sigma=1e-7, fit=fit)
    assert m.wall_shear_stress == pytest.approx(tau[3], rel=1e-8)
    # its error is sigma over the exact sensitivity (the fit's covariance ~ 0 here)
    assert m.wall_shear_stress_stderr == pytest.approx(1e-7 / truth.sensitivity(tau[3]), rel=1e-3)
    lr = truth.linear_range(0.05)
    assert lr.success
    # the linear formula's error is rtol at the end of the range
    lin = truth.linear_wall_shear_stress_from_tip_deflection(lr.tip_deflection)
    assert abs(lin / lr.wall_shear_stress - 1.0) == pytest.approx(0.05, rel=1e-8)
    # the law of the wall ends the linear range sooner than the sublayer (its U falls below z)
    sub = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e5, fluid="water")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.ModelValidityWarning)
        assert lr.wall_shear_stress < sub.linear_range(0.05).wall_shear_stress


def test_calibration_jacobian_against_central_differences():
    # every free parameter, through L+ for the length (theory.md §12, the law of the wall)
    from dataclasses import replace

    from tolerances import PILLAR_JACOBIAN_FD_RTOL

    from hairbed.calibration import PILLAR_FREE_PARAMETERS, _pillar_model_at

    pillar = _pillar(base_angle=0.2)
    tau = np.linspace(0.3, 5.0, 5)
    names = tuple(PILLAR_FREE_PARAMETERS)
    d, jac, dd_dtau = _pillar_model_at(pillar, tau, pillar._solve(pillar._forcing(tau)), names)
    np.testing.assert_array_equal(
        d, calibration.model_tip_deflection(pillar, wall_shear_stress=tau)
    )
    assert np.allclose(dd_dtau, pillar.sensitivity(tau), rtol=1e-14, atol=0)
    for j, name in enumerate(names):
        v = getattr(pillar, name)
        h = 1e-5 * (1.0 if name == "base_angle" else abs(v))
        up, down = replace(pillar, **{name: v + h}), replace(pillar, **{name: v - h})
        fd = (
            calibration.model_tip_deflection(up, wall_shear_stress=tau)
            - calibration.model_tip_deflection(down, wall_shear_stress=tau)
        ) / (2 * h)
        big = np.max(np.abs(jac[:, j]))
        assert np.max(np.abs(fd - jac[:, j])) <= PILLAR_JACOBIAN_FD_RTOL * big, name
    # the length's column is not the frozen profile's: L+ carries a part of it far above the
    # tolerance, so that the differences above would see it missing
    sol = pillar._solve(pillar._forcing(tau))
    part = pillar._tip_derivatives(tau, sol)["log_l_plus"]
    big = np.max(np.abs(jac[:, names.index("length")]))
    assert np.max(np.abs(part)) > 1e3 * PILLAR_JACOBIAN_FD_RTOL * big


# -- presets, warnings, bad input -------------------------------------------------------------


def test_fluid_presets():
    for name, (eta, rho) in {
        "water": (1.0016e-3, 998.21),
        "glycerol": (1.412, 1261.3),
        "air": (1.825e-5, 1.2041),
    }.items():
        p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid=name)
        assert (p.viscosity, p.density) == (eta, rho)
    p = hairbed.Pillar(
        length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="water", viscosity=1.1e-3
    )
    assert (p.viscosity, p.density) == (1.1e-3, 998.21)  # the value given wins
    with pytest.raises(ValueError, match=r"fluid must be one of 'water', 'glycerol', 'air'"):
        hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="honey")
    with pytest.raises(TypeError, match="viscosity"):
        hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6)


def test_l_plus_is_reported_and_checked_by_default_with_a_preset():
    p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, fluid="water")
    with pytest.warns(hairbed.ModelValidityWarning, match=r"L\+ = 31.5 .*profile='wall-law'"):
        st = p.deform(1.0)
    # L+ = L sqrt(tau/rho)/nu, written out
    assert st.height_in_wall_units == pytest.approx(
        1e-3 * math.sqrt(1.0 / 998.21) * 998.21 / 1.0016e-3, rel=1e-14
    )
    with warnings.catch_warnings():
        warnings.filterwarnings("error", message="the pillar stands")
        p.deform(0.02)  # L+ = 4.5: in the sublayer, no warning
        _pillar().deform(1.0)  # the wall law at L+ = 31.5: no warning


def test_missing_density_is_told_once_per_pillar():
    p = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, viscosity=1e-3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        st = p.deform(1.0)
        p.deform([0.5, 2.0])
        p.wall_shear_stress_from_tip_deflection(st.tip_deflection)
        p.sensitivity(1.0)
    told = [w for w in caught if "no density" in str(w.message)]
    assert len(told) == 1 and issubclass(told[0].category, hairbed.ModelValidityWarning)
    assert "density=" in str(told[0].message) and "fluid=" in str(told[0].message)
    assert math.isnan(st.height_in_wall_units) and math.isnan(st.reynolds_number)
    q = hairbed.Pillar(length=1e-3, radius=50e-6, youngs_modulus=1e6, viscosity=1e-3)
    with pytest.warns(hairbed.ModelValidityWarning, match="no density"):
        q.deform(1.0)  # another pillar is told again


def test_wall_law_bad_input():
    with pytest.raises(ValueError, match=r"'wall-law' needs the fluid's density"):
        hairbed.Pillar(
            length=1e-3, radius=50e-6, youngs_modulus=1e6, viscosity=1e-3, profile="wall-law"
        )
    with pytest.raises(ValueError, match=r"profile must be one of .*'wall-law'"):
        _pillar(profile="log-law")
    p = _pillar(profile="wall-law", youngs_modulus=1e9)
    with pytest.raises(
        ValueError, match=r"wall_shear_stress 1000000.0 Pa \(first at index 1\).*above L\+ = 10000"
    ):
        p.deform([1.0, 1e6])


# -- the command line -------------------------------------------------------------------------


def _cli(*args):
    import contextlib
    import io

    from hairbed.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


def test_cli_wall_law_and_fluid():
    si = ["--pillar", "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e5"]
    code, out, _ = _cli(
        "solve", *si, "--fluid", "water", "--profile", "wall-law", "--wall-shear-stress", "1",
        "--json",
    )  # fmt: skip
    assert code == 0
    got = json.loads(out)
    st = _pillar().deform(1.0)
    assert got["height_in_wall_units"] == pytest.approx(st.height_in_wall_units, rel=1e-15)
    assert got["tip_deflection_m"] == pytest.approx(st.tip_deflection, rel=1e-15)
    code, out, err = _cli("solve", "--pillar", "--forcing", "2", "--profile", "wall-law")
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "--profile wall-law needs an SI pillar" in lines[0]
    code, _, err = _cli("solve", *si, "--fluid", "honey", "--wall-shear-stress", "1")
    assert code == 2 and "--fluid" in err and "'water'" in err
    code, _, err = _cli("solve", *si, "--profile", "wall-law", "--viscosity", "1e-3",
                        "--wall-shear-stress", "1")  # fmt: skip
    assert code == 2 and "needs the fluid's density" in err


def test_cli_sweep_of_a_wall_law_pillar():
    pytest.importorskip("xarray")
    si = ["--pillar", "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e5"]
    code, out, _ = _cli(
        "sweep", *si, "--fluid", "water", "--profile", "wall-law",
        "--wall-shear-stress", "0.1,1.05,2",
    )  # fmt: skip
    assert code == 0
    header, *rows = out.strip().splitlines()
    names = header.split(",")
    table = np.array([[float(v) for v in r.split(",")] for r in rows])
    st = _pillar().deform([0.1, 1.05, 2.0])
    for col, field in (
        ("height_in_wall_units [1]", "height_in_wall_units"),
        ("tip_deflection [m]", "tip_deflection"),
        ("sensitivity [m Pa-1]", "sensitivity"),
    ):
        assert np.allclose(table[:, names.index(col)], getattr(st, field), rtol=1e-14, atol=0)
    code, _, err = _cli("sweep", "--fluid", "water", "--omega2", "1:2:3")
    assert code == 2 and "--fluid needs --pillar" in err


def test_cli_calibration_file_round_trip(tmp_path):
    truth = _pillar(youngs_modulus=1.3e5)
    tau = np.linspace(0.2, 4.0, 7)
    d = truth.tip_deflection(tau)
    data = tmp_path / "points.csv"
    data.write_text(
        "wall_shear_stress [Pa],tip_deflection [m]\n"
        + "".join(f"{float(t)!r},{float(x)!r}\n" for t, x in zip(tau, d))
    )
    si = ["--pillar", "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e5"]
    code, out, err = _cli(
        "calibrate", *si, "--fluid", "water", "--profile", "wall-law", "--data", str(data),
        "--free", "youngs_modulus", "--sigma", "1e-8", "--json",
    )  # fmt: skip
    assert code == 0, err
    saved = json.loads(out)
    assert saved["bed"]["profile"] == "wall-law" and saved["bed"]["density"] == 998.21
    assert saved["bed"]["youngs_modulus"] == pytest.approx(1.3e5, rel=1e-9)
    cal = tmp_path / "cal.json"
    cal.write_text(out)
    code, out, err = _cli(
        "measure", "--pillar", "--calibration", str(cal), "--tip-deflection", repr(float(d[3])),
        "--sigma", "1e-7", "--json",
    )  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["wall_shear_stress"] == pytest.approx(tau[3], rel=1e-8)
