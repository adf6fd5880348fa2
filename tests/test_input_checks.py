"""Every input checked: one row per reproducer and per secondary parameter.

Each row calls a public function with one bad argument and expects a ValueError or TypeError
whose message names the parameter and its allowed range (and, for arrays, the first offending
index in array order), never a numpy repr such as ``np.float64(...)``. The units rows check
the pint conversions and the plausibility warnings of :class:`hairbed.HairBed`.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import hairbed
from hairbed import branches, calibration, inverse, numerics, quasistatic, stability, sweeps

BED_KW = dict(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
)
BED = hairbed.HairBed(**BED_KW)
SOL = hairbed.solve(2.0, 0.5)
SOLS = hairbed.solve([1.0, 2.0, 3.0], 0.5)
X20, Z20 = SOL.profile(20)

#: (id, call, exception, regex of the message)
ROWS = [
    # -- the reproducers of the issue
    (
        "stability(1.0): not a Solution",
        lambda: stability.linear_stability(1.0),
        TypeError,
        r"solution must be a hairbed\.Solution .*got float",
    ),
    (
        "curve num=nan",
        lambda: branches.curve(0.9, -1.5, num=float("nan")),
        ValueError,
        r"num must be an integer >= 2 and <= 10000000, got nan",
    ),
    (
        "collocation num_nodes=None",
        lambda: numerics.collocation(2, 0.5, num_nodes=None),
        ValueError,
        r"nodes must be an integer >= 3 and <= 1000000, got None",
    ),
    (
        "theta of 4 arc lengths on 3 states",
        lambda: SOLS.theta([0, 0.5, 0.75, 1]),
        ValueError,
        r"sigma must broadcast against the solution's shape \(3,\), got shape \(4,\)",
    ),
    (
        "solve(timedelta64)",
        lambda: hairbed.solve(np.timedelta64(1, "s"), 0.5),
        ValueError,
        r"omega2 must be a real number .*timedelta64",
    ),
    (
        "linear inverse below rest",
        lambda: inverse.linear_omega2_from_tip_deflection(-0.5, 0.5, 0.1),
        ValueError,
        r"x1 must lie in \[sin\(theta0\), 1\) = \[0\.0998\d*, 1\), got -0\.5",
    ),
    (
        "linear bed calibration beyond the hair",
        lambda: BED.linear_velocity_from_tip_deflection(2e-3),
        ValueError,
        r"deflection: the tip deflection must lie in \(-length, length\) = "
        r"\(-0\.001, 0\.001\) m, got 0\.002",
    ),
    (
        "fit_profile of a hair lying on the wall (all heights zero)",
        lambda: inverse.fit_profile(np.linspace(0.0, 1.0, 20), np.zeros(20), 0.5),
        ValueError,
        r"z must have a point above the wall \(z > 0\).*got all 20 heights <= 0",
    ),
    (
        "from_parameter(complex)",
        lambda: hairbed.from_parameter(np.array([0.5 + 9j]), 0.5),
        ValueError,
        r"t must be a real number .*complex number \(\(0\.5\+9j\); the imaginary part is "
        r"never dropped\) \(first at index 0\)",
    ),
    # -- types inside arrays, first offending index in C order
    (
        "bool omega2",
        lambda: hairbed.solve(True, 0.5),
        ValueError,
        r"omega2 must be a real number .*a boolean",
    ),
    (
        "bools in an array",
        lambda: hairbed.solve(np.array([True, False]), 0.5),
        ValueError,
        r"omega2 .*a boolean \(True\) \(first at index 0\)",
    ),
    (
        "datetime64 eps",
        lambda: hairbed.solve(1.0, np.datetime64("2020-01-01")),
        ValueError,
        r"eps must be a real number .*datetime64",
    ),
    (
        "a string inside a list",
        lambda: hairbed.solve([[1.0, 2.0], [3.0, "x"]], 0.5),
        ValueError,
        r"omega2 .*a string \('x'\) \(first at index \(1, 1\)\)",
    ),
    (
        "None inside a list",
        lambda: hairbed.solve(1.0, 0.5, [0.1, None]),
        ValueError,
        r"theta0 .*None \(first at index 1\)",
    ),
    (
        "an object inside an array",
        lambda: hairbed.solve(np.array([1.0, object()], dtype=object), 0.5),
        ValueError,
        r"omega2 .*a object \(first at index 1\)",
    ),
    (
        "ragged list",
        lambda: hairbed.solve([[1.0, 2.0], [3.0]], 0.5),
        ValueError,
        r"omega2 must be a real number .*ragged",
    ),
    (
        "complex with a zero imaginary part",
        lambda: hairbed.solve(np.array([1.0 + 0j, 2.0 + 1e-300j]), 0.5),
        ValueError,
        r"omega2 .*complex number .*\(first at index 1\)",
    ),
    (
        "int beyond float range",
        lambda: hairbed.solve(10**400, 0.5),
        ValueError,
        r"omega2 must be finite",
    ),
    (
        "first bad index in C order",
        lambda: hairbed.solve([[1.0, 2.0], [-1.0, -2.0]], 0.5),
        ValueError,
        r"omega2 must lie in \[0, inf\), got -1\.0 \(first at index \(1, 0\)\)",
    ),
    (
        "no numpy repr for a numpy scalar n",
        lambda: hairbed.solve(1.0, 0.5, n=np.float64(1.5)),
        ValueError,
        r"n must be a whole number >= 0 \(at most 10\^9\), got 1\.5$",
    ),
    (
        "n too large for the kernels",
        lambda: hairbed.solve(1.0, 0.5, n=2**63),
        ValueError,
        r"n must be a whole number >= 0 \(at most 10\^9\)",
    ),
    (
        "sign 2.0",
        lambda: hairbed.solve(1.0, 0.5, sign=np.int64(2)),
        ValueError,
        r"sign must be \+1 or -1, got 2$",
    ),
    # -- one row per secondary parameter
    (
        "solve_all max_n",
        lambda: hairbed.solve_all(2.0, 0.5, max_n=-1),
        ValueError,
        r"max_n must be an integer >= 0, got -1",
    ),
    (
        "solve_all too many branches",
        lambda: hairbed.solve_all(1e300, 0.5),
        ValueError,
        r"solve_all searches at most 10000 .*unless max_n is given",
    ),
    (
        "Solution.profile num",
        lambda: SOL.profile(1),
        ValueError,
        r"num must be an integer >= 2 and <= 10000000, got 1",
    ),
    (
        "Solution.profile num huge (an integral float shown as given, not as 309 digits)",
        lambda: SOL.profile(1e308),
        ValueError,
        r"num must be an integer >= 2 and <= 10000000, got 1e\+308$",
    ),
    (
        "Solution.profile num float",
        lambda: SOL.profile(2.5),
        ValueError,
        r"num must be an integer .*got 2\.5",
    ),
    (
        "Solution.theta sigma range",
        lambda: SOLS.theta([0.5, 1.5]),
        ValueError,
        r"sigma must lie in \[0, 1\], got 1\.5 \(first at index 1\)",
    ),
    (
        "Solution index",
        lambda: SOLS[7],
        IndexError,
        r"index 7 does not select states of a Solution of shape \(3,\)",
    ),
    ("curve num", lambda: branches.curve(0.5, num=1), ValueError, r"num must be an integer >= 2"),
    (
        "curve t_span order",
        lambda: branches.curve(0.5, t_span=(1.0, -1.0)),
        ValueError,
        r"t_span must be two finite increasing numbers",
    ),
    (
        "curve t_span shape",
        lambda: branches.curve(0.5, t_span=(1.0,)),
        ValueError,
        r"t_span must be two .*shape \(1,\)",
    ),
    (
        "log_slope t",
        lambda: branches.log_slope(1e4, 0.9, -1.5),
        ValueError,
        r"t must lie in \[-700, 700\]",
    ),
    (
        "equilibrium num",
        lambda: stability.equilibrium(2, 0.5, 0, np.zeros(3), num=True),
        ValueError,
        r"num must be an integer >= 2 and <= 1000000, got True",
    ),
    (
        "equilibrium xtol",
        lambda: stability.equilibrium(2, 0.5, 0, np.zeros(11), 10, xtol=0),
        ValueError,
        r"xtol must be positive, got 0\.0 \[rad\]",
    ),
    (
        "equilibrium maxiter",
        lambda: stability.equilibrium(2, 0.5, 0, np.zeros(11), 10, maxiter=0),
        ValueError,
        r"maxiter must be an integer >= 1",
    ),
    (
        "equilibrium guess shape",
        lambda: stability.equilibrium(2, 0.5, 0, np.zeros(5), 10),
        ValueError,
        r"guess must give theta at the num \+ 1 = 11 nodes, got shape \(5,\)",
    ),
    (
        "equilibrium guess NaN",
        lambda: stability.equilibrium(2, 0.5, 0, [0.0, np.nan, 0.0], 2),
        ValueError,
        r"guess must be finite .*\(first at index 1\)",
    ),
    (
        "linear_stability num",
        lambda: stability.linear_stability(SOL, num=10**5),
        ValueError,
        r"num must be an integer >= 2 and <= 4000",
    ),
    (
        "linear_stability k",
        lambda: stability.linear_stability(SOL, num=10, k=0),
        ValueError,
        r"k must be an integer >= 1 and <= 10",
    ),
    (
        "is_stable num",
        lambda: stability.is_stable(SOL, num="100"),
        ValueError,
        r"num must be an integer .*got '100'",
    ),
    (
        "relax t_end",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), -1.0, num=10),
        ValueError,
        r"t_end must be positive",
    ),
    (
        "relax method",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), 1.0, num=10, method="RK45"),
        ValueError,
        r"method must be one of 'BDF', 'Radau', 'LSODA', got 'RK45'",
    ),
    (
        "relax rtol",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), 1.0, num=10, rtol=1e-20),
        ValueError,
        r"rtol must lie in \[2\.22\d*e-14, 1\)",
    ),
    (
        "relax atol",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), 1.0, num=10, atol=1e-310),
        ValueError,
        r"atol must lie in \[1e-30, inf\) \[rad\]",
    ),
    (
        "relax t_eval",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), 1.0, num=10, t_eval=[0.0, 2.0]),
        ValueError,
        r"t_eval must be increasing times in \[0, t_end\] .*\(first at index 1\)",
    ),
    (
        "relax t_eval empty",
        lambda: stability.relax(2, 0.5, 0, np.zeros(11), 1.0, num=10, t_eval=[]),
        ValueError,
        r"t_eval must be a non-empty 1-D array",
    ),
    (
        "relax omega2 beyond the grid",
        lambda: stability.relax(1e9, 0.5, 0, np.zeros(11), 1.0, num=10),
        ValueError,
        r"omega2 must lie in \[0, 1e\+08\]",
    ),
    (
        "finite_difference num",
        lambda: numerics.finite_difference(2, 0.5, num=1),
        ValueError,
        r"num must be an integer >= 2",
    ),
    (
        "finite_difference method",
        lambda: numerics.finite_difference(2, 0.5, method="x"),
        ValueError,
        r"method must be one of 'newton', 'root', got 'x'",
    ),
    (
        "finite_difference xtol",
        lambda: numerics.finite_difference(2, 0.5, xtol=-1.0),
        ValueError,
        r"xtol must be positive, got -1\.0 \[rad\]",
    ),
    (
        "finite_difference maxiter",
        lambda: numerics.finite_difference(2, 0.5, maxiter=1.5),
        ValueError,
        r"maxiter must be an integer >= 1 and <= 1000000, got 1\.5",
    ),
    (
        "finite_difference guess",
        lambda: numerics.finite_difference(2, 0.5, guess="0"),
        ValueError,
        r"guess must be a real number",
    ),
    (
        "finite_difference guess huge",
        lambda: numerics.finite_difference(2, 0.5, guess=1e300),
        ValueError,
        r"guess must lie in \[-1000, 1000\] \[rad\]",
    ),
    (
        "finite_difference guess function",
        lambda: numerics.finite_difference(2, 0.5, guess=lambda s: s[:3]),
        ValueError,
        r"guess\(sigma\) must give one value per "
        r"node \(80\), got shape \(3,\)",
    ),
    (
        "finite_difference omega2",
        lambda: numerics.finite_difference(1e9, 0.5),
        ValueError,
        r"omega2 must lie in \[0, 1e\+08\]",
    ),
    (
        "finite_difference arrays",
        lambda: numerics.finite_difference([2.0], 0.5),
        ValueError,
        r"omega2, eps and theta0 must be scalars",
    ),
    (
        "shooting num",
        lambda: numerics.shooting(2, 0.5, num=2),
        ValueError,
        r"num must be an integer >= 3",
    ),
    (
        "shooting tol",
        lambda: numerics.shooting(2, 0.5, rtol=float("nan")),
        ValueError,
        r"tol must be finite",
    ),
    (
        "shooting maxiter",
        lambda: numerics.shooting(2, 0.5, maxiter=0),
        ValueError,
        r"maxiter must be an integer >= 1",
    ),
    (
        "shooting base_curvature",
        lambda: numerics.shooting(2, 0.5, guess=1e5),
        ValueError,
        r"guess must lie in \[-1000, 1000\], got 100000\.0",
    ),
    (
        "shooting omega2",
        lambda: numerics.shooting(1e5, 0.5),
        ValueError,
        r"omega2 must lie in \[0, 10000\] for shooting",
    ),
    (
        "collocation tol",
        lambda: numerics.collocation(2, 0.5, rtol=1e-20),
        ValueError,
        r"tol must lie in \[2\.22\d*e-14, 1\]",
    ),
    (
        "collocation nodes > max_nodes",
        lambda: numerics.collocation(2, 0.5, num_nodes=50, max_nodes=40),
        ValueError,
        r"nodes must not exceed max_nodes = 40, got 50",
    ),
    (
        "collocation max_nodes",
        lambda: numerics.collocation(2, 0.5, max_nodes=2),
        ValueError,
        r"max_nodes must be an integer >= 3",
    ),
    (
        "collocation num",
        lambda: numerics.collocation(2, 0.5, num=np.array([5])),
        ValueError,
        r"num must be an integer .*got an array of shape \(1,\)",
    ),
    (
        "quasistatic path dtype",
        lambda: quasistatic.sweep(["1", "2"], 0.5),
        ValueError,
        r"omega2_path must be a real number",
    ),
    (
        "quasistatic path negative",
        lambda: quasistatic.sweep([1.0, -2.0], 0.5),
        ValueError,
        r"omega2_path must lie in \[0, inf\), got -2\.0 \(first at index 1\)",
    ),
    (
        "quasistatic path shape",
        lambda: quasistatic.sweep([[1.0]], 0.5),
        ValueError,
        r"omega2_path must be one-dimensional",
    ),
    (
        "quasistatic start",
        lambda: quasistatic.sweep([1.0], 0.5, root="mid"),
        ValueError,
        r"root must be one of 'low', 'high', got 'mid'",
    ),
    (
        "fit_profile points",
        lambda: inverse.fit_profile(X20, Z20[:5], 0.5),
        ValueError,
        r"x and z must have the same number of points",
    ),
    (
        "fit_profile far points",
        lambda: inverse.fit_profile(X20 * 1e3, Z20, 0.5),
        ValueError,
        r"x and z must be points along a hair, within 10 hair lengths",
    ),
    (
        "fit_profile theta0",
        lambda: inverse.fit_profile(X20, Z20, 0.5, theta0=2.0),
        ValueError,
        r"theta0 must lie in \(-pi/2, pi/2\), got 2\.0",
    ),
    (
        "fit_profile theta0 array",
        lambda: inverse.fit_profile(X20, Z20, 0.5, theta0=[0.1, 0.2]),
        ValueError,
        r"theta0 must be a single number \[rad\]",
    ),
    (
        "fit_profile omega2_guess",
        lambda: inverse.fit_profile(X20, Z20, 0.5, omega2_guess=-1.0),
        ValueError,
        r"omega2_guess must lie in \[0, inf\), got -1\.0",
    ),
    (
        "fit_profile theta0_guess",
        lambda: inverse.fit_profile(X20, Z20, 0.5, theta0_guess="a"),
        ValueError,
        r"theta0_guess must be a real number",
    ),
    (
        "omega2_from_tip_height h1",
        lambda: inverse.omega2_from_tip_height([0.5, 1e-200], 0.5),
        ValueError,
        r"h1 must lie in \[1e-150, 1\.0\] .*got 1e-200 \(first at index 1\)",
    ),
    (
        "calibration sigma shape",
        lambda: calibration.fit(
            BED, [1e-4, 2e-4, 3e-4], velocity=[0.01, 0.02, 0.03], sigma=[1e-6, 1e-6]
        ),
        ValueError,
        r"sigma must be a single number or one per point \(3\), got shape \(2,\)",
    ),
    (
        "calibration sigma value",
        lambda: calibration.fit(
            BED, [1e-4, 2e-4, 3e-4], velocity=[0.01, 0.02, 0.03], sigma=[1e-6, 0.0, 1e-6]
        ),
        ValueError,
        r"sigma must be > 0 \[m\], got 0\.0 \(first at index 1\)",
    ),
    (
        "calibration sigma scale",
        lambda: calibration.fit(BED, [1e-4, 2e-4, 3e-4], velocity=[0.01, 0.02, 0.03], sigma=1.0),
        ValueError,
        r"sigma must be in \[1e-15, 0\.001\] \[m\], got 1\.0",
    ),
    (
        "calibration free",
        lambda: calibration.fit(BED, [1e-4], velocity=[0.01], free=[np.float64(1.0)]),
        ValueError,
        r"free: unknown parameter 1\.0; allowed",
    ),
    (
        "measure sigma",
        lambda: calibration.measure(BED, 3e-4, sigma=-1e-6),
        ValueError,
        r"sigma must be >= 0 \[m\], got -1e-06",
    ),
    (
        "measure tip_deflection",
        lambda: calibration.measure(BED, 2e-3),
        ValueError,
        r"tip_deflection: the tip deflection must lie in \(-length, length\)",
    ),
    (
        "measure fit",
        lambda: calibration.measure(BED, 3e-4, fit=1.0),
        TypeError,
        r"fit must be a CalibrationFit",
    ),
    (
        "model bed",
        lambda: calibration.model_tip_deflection(None, velocity=0.1),
        TypeError,
        r"bed must be a hairbed\.HairBed or a hairbed\.Pillar, got NoneType",
    ),
    (
        "model velocity overflow",
        lambda: calibration.model_tip_deflection(BED, velocity=[0.1, 1.7e308]),
        ValueError,
        r"velocity must be below .* m/s for this bed .*\(first at index 1\)",
    ),
    (
        "linear_range rtol",
        lambda: calibration.linear_range(BED, rtol=1.0),
        ValueError,
        r"rtol must lie in \(0, 1\), got 1\.0",
    ),
    (
        "sweep chunks",
        lambda: hairbed.sweep([1.0, 2.0], 0.5, chunks=0),
        ValueError,
        r"chunks must be an integer >= 1",
    ),
    (
        "sweep chunks huge",
        lambda: hairbed.sweep([1.0, 2.0], 0.5, chunks=1e308),
        ValueError,
        r"chunks must be an integer >= 1 and <= 1099511627776",
    ),
    (
        "sweep progress",
        lambda: hairbed.sweep([1.0, 2.0], 0.5, progress=np.array([1])),
        TypeError,
        r"progress must be True or False, got an array of shape \(1,\)",
    ),
    (
        "bed_sweep bed",
        lambda: sweeps.bed_sweep("bed", [0.1]),
        TypeError,
        r"bed must be a hairbed\.HairBed, got str",
    ),
    (
        "output_format path",
        lambda: sweeps.output_format(3.0),
        TypeError,
        r"path must be a file name",
    ),
    (
        "HairBed velocity overflow",
        lambda: BED.deform(1.7e308),
        ValueError,
        r"velocity must be below .* m/s for this bed",
    ),
    (
        "HairBed rectification speed",
        lambda: BED.rectification_ratio("fast"),
        ValueError,
        r"speed must be a real number",
    ),
    (
        "HairBed degenerate scales",
        lambda: hairbed.HairBed(**{**BED_KW, "youngs_modulus": 1e-320}),
        ValueError,
        r"velocity scale .*under- or overflow .*check their units",
    ),
    (
        "HairState.profile num",
        lambda: BED.deform(0.1).profile(0),
        ValueError,
        r"num must be an integer >= 2",
    ),
]


@pytest.mark.parametrize(("call", "error", "pattern"), [r[1:] for r in ROWS],
                         ids=[r[0] for r in ROWS])  # fmt: skip
def test_bad_input_is_named(call, error, pattern):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hairbed.UnitsWarning)
        with pytest.raises(error) as info:
            call()
    message = str(info.value)
    assert re.search(pattern, message), message
    assert not re.search(r"\bnp\.[a-z]+[0-9]*\(", message), message


def test_fit_profile_keeps_a_hair_bent_close_to_the_wall():
    """The flat-hair check refuses only heights all <= 0: a hair bent down to a tip height of
    0.014 (omega2 = 1e4), with a base point measured slightly below the wall, still fits the
    forcing it was drawn from (the closed form, eqs. (30), (32))."""
    x, z = hairbed.solve(1e4, 0.5).profile(20)
    z = z.copy()
    z[0] = -1e-4
    fit = inverse.fit_profile(x, z, 0.5)
    assert fit.success
    assert fit.omega2 == pytest.approx(1e4, rel=1e-8)


# -- units ---------------------------------------------------------------------------------------

pint = pytest.importorskip("pint")
U = pint.UnitRegistry()


def test_pint_quantities_are_converted_to_si():
    bed = hairbed.HairBed(
        length=U.Quantity(1, "mm"),
        radius=U.Quantity(50, "um"),
        youngs_modulus=U.Quantity(1, "MPa"),
        channel_height=U.Quantity(0.2, "cm"),
        viscosity=U.Quantity(1000, "cP"),
        spacing=U.Quantity(400, "um"),
        base_angle=U.Quantity(10, "degree"),
        density=U.Quantity(1.26, "g/cm**3"),
    )
    si = hairbed.HairBed(**BED_KW, base_angle=math.radians(10), density=1260.0)
    for name in ("length", "radius", "youngs_modulus", "channel_height", "viscosity",
                 "spacing", "base_angle", "density"):  # fmt: skip
        assert getattr(bed, name) == pytest.approx(getattr(si, name), rel=1e-14), name
    v = U.Quantity(36, "cm/s")
    assert bed.deform(v).tip_deflection == pytest.approx(si.deform(0.36).tip_deflection, 1e-13)
    assert bed.omega2(v) == pytest.approx(si.omega2(0.36), rel=1e-14)
    mixed = [U.Quantity(10, "cm/s"), U.Quantity(0.2, "m/s")]  # a list of quantities
    np.testing.assert_allclose(bed.omega2(mixed), si.omega2([0.1, 0.2]), rtol=1e-14)
    np.testing.assert_allclose(
        bed.omega2(U.Quantity([10.0, 20.0], "cm/s")), si.omega2([0.1, 0.2]), rtol=1e-14
    )
    d = U.Quantity(300, "um")
    assert bed.velocity_from_tip_deflection(d) == pytest.approx(
        si.velocity_from_tip_deflection(3e-4), rel=1e-12
    )
    assert bed.linear_velocity_from_tip_deflection(d) == pytest.approx(
        si.linear_velocity_from_tip_deflection(3e-4), rel=1e-14
    )
    tau = U.Quantity(0.05, "kPa")
    assert calibration.model_tip_deflection(si, wall_shear_stress=tau) == pytest.approx(
        calibration.model_tip_deflection(si, wall_shear_stress=50.0), rel=1e-14
    )
    # dimensionless inputs of the core, and an angle in degrees
    sol = hairbed.solve(U.Quantity(2.0, ""), 0.5, U.Quantity(5.0, "degree"))
    assert sol.xi == hairbed.solve(2.0, 0.5, math.radians(5.0)).xi


@pytest.mark.parametrize(
    ("call", "pattern"),
    [
        (lambda: hairbed.HairBed(**{**BED_KW, "length": U.Quantity(1, "kg")}),
         r"length must be a quantity in \[m\] .*got one in kg"),
        (lambda: hairbed.HairBed(**{**BED_KW, "viscosity": U.Quantity(1, "m**2/s")}),
         r"viscosity must be a quantity in \[Pa\*s\]"),
        (lambda: BED.deform(U.Quantity(1, "Pa")), r"velocity must be a quantity in \[m/s\]"),
        (lambda: BED.velocity_from_tip_deflection(U.Quantity(1, "s")),
         r"deflection must be a quantity in \[m\]"),
        (lambda: calibration.model_tip_deflection(BED, wall_shear_stress=U.Quantity(1, "m")),
         r"wall_shear_stress must be a quantity in \[Pa\]"),
        (lambda: hairbed.solve(U.Quantity(2.0, "m"), 0.5), r"omega2 must be a quantity in "
         r"dimensionless"),
    ],
)  # fmt: skip
def test_a_quantity_of_the_wrong_dimension_names_the_parameter_and_unit(call, pattern):
    with pytest.raises(ValueError, match=pattern):
        call()


@pytest.mark.parametrize(
    ("change", "pattern"),
    [
        (dict(length=2.0, channel_height=5.0, spacing=1.0),
         r"length = 2 m is outside the plausible range \[1e-08, 1\] m: micrometres given as "
         r"metres\?"),
        (dict(youngs_modulus=1.0), r"youngs_modulus = 1 Pa .*a modulus in kPa, MPa or GPa "
         r"given as Pa\?"),
        (dict(youngs_modulus=1e15), r"youngs_modulus = 1e\+15 Pa .*stiffer than diamond"),
        (dict(viscosity=1e-6 / 10), r"viscosity = 1e-07 Pa s .*kinematic viscosity"),
        (dict(radius=5e-10, spacing=4e-9), r"radius = 5e-10 m .*metres converted twice"),
        (dict(density=1e-3), r"density = 0\.001 kg/m\^3 .*below any gas"),
    ],
)  # fmt: skip
def test_implausible_units_warn_naming_the_parameter_and_the_slip(change, pattern):
    with pytest.warns(hairbed.UnitsWarning, match=pattern) as record:
        hairbed.HairBed(**{**BED_KW, **change})
    assert all(issubclass(w.category, UserWarning) for w in record)


def test_plausible_beds_and_invalid_beds_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", hairbed.UnitsWarning)
        hairbed.HairBed(**BED_KW, density=1000.0)  # the docstring's bed: silent
        with pytest.raises(ValueError, match="less than half the spacing"):
            hairbed.HairBed(**{**BED_KW, "radius": 50.0})  # invalid: only the error
    low, high = hairbed.units.PLAUSIBLE_RANGES["length"][:2]
    assert (low, high) == (1e-8, 1.0)
