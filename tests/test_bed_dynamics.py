"""The porous bed in time (issue 30, theory.md §15): its semi-discrete system and operators.

References: Richardson (fourth-order central) differences of the system g(t, y) for the
exact Jacobian, the drives' columns and the outputs' rows; :func:`hairbed.solve_porous`
(the statics' own collocation, a different set of rows) for the steady states.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import (
    BED_OUTPUTS,
    bed_operators,
    sampled,
    simulate_bed,
    simulate_pillar,
    sine,
    step,
)
from hairbed.dynamics._bed import _evaluate, _output_values, _system
from hairbed.dynamics._signals import constant


def _richardson(func: Callable[[np.ndarray], np.ndarray], x: np.ndarray, h: float) -> np.ndarray:
    """d func/dx by the fourth-order central difference, column by column."""
    cols = []
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = h * max(1.0, abs(x[k]))
        d = (8.0 * (func(x + e) - func(x - e)) - (func(x + 2 * e) - func(x - 2 * e))) / 12.0
        cols.append(d / e[k])
    return np.array(cols).T


@pytest.mark.parametrize(
    ("load", "mu", "alpha"),
    [
        ({"pi": 0.7}, 0.0, 0.0),
        ({"pi": 0.7}, 0.6, 0.5),
        ({"q": 0.4}, 0.0, 0.5),
        ({"q": 0.4}, 0.6, 0.0),
    ],
)
def test_bed_operators_against_differences(
    load: dict[str, float], mu: float, alpha: float
) -> None:
    """J = dg/dy, the drives' columns dg/dd and the outputs' rows of :func:`bed_operators`
    against Richardson differences of g and of the outputs, at the steady state and (for J)
    at a perturbed one; the steady vector's g vanishes; its outputs are the static
    solver's."""
    st = hairbed.solve_porous(1.5, 0.5, 0.3, kappa=0.05, gamma=0.6, **load)
    op = bed_operators(st, inertia=mu, tangential_mass=0.8, womersley=alpha, num=12, num_gap=8)
    flow = "q" in load
    pump = 1 if flow else 0
    pump_value = float(load["q"] if flow else load["pi"])
    sys = _system(12, float(st._map), 8, 0.3, 0.6, 0.8, mu, 0.05, 0.5, alpha, 0, pump,
                  constant(1.5), constant(pump_value))  # fmt: skip
    y = op.steady
    ok, g, jac = _evaluate(sys, 0.0, y, True)
    assert ok and np.max(np.abs(g)) < 1e-11
    assert np.array_equal(jac, op.jacobian)
    rng = np.random.default_rng(3)
    for yy in (y, y + 0.03 * rng.standard_normal(y.size)):
        _, _, jac = _evaluate(sys, 0.0, yy, True)
        num = _richardson(lambda x: _evaluate(sys, 0.0, x, False)[1], yy, 1e-5)
        scale = 1.0 + np.max(np.abs(num), axis=1, keepdims=True)
        assert np.max(np.abs(jac - num) / scale) < 1e-8

    # the drives' columns
    def with_drive(name: str, value: float) -> np.ndarray:
        wall = value if name == "wall" else 1.5
        pv = value if name != "wall" else pump_value
        s2 = _system(12, float(st._map), 8, 0.3, 0.6, 0.8, mu, 0.05, 0.5, alpha, 0, pump,
                     constant(wall), constant(pv))  # fmt: skip
        return _evaluate(s2, 0.0, y, False)[1]

    assert set(op.drives) == {"wall", "flow_rate" if flow else "pressure"}
    for name, col in op.drives.items():
        d0 = 1.5 if name == "wall" else pump_value

        def column(x: np.ndarray, nm: str = name) -> np.ndarray:
            return with_drive(nm, float(x[0]))

        num = _richardson(column, np.array([d0]), 1e-5)[:, 0]
        assert np.max(np.abs(col - num)) < 1e-8 * (1.0 + np.max(np.abs(num)))
    # the outputs' rows, and their values against the static solver
    for name in BED_OUTPUTS:

        def out(x: np.ndarray, nm: str = name) -> np.ndarray:
            return np.atleast_1d(_output_values(sys, x, pump_value)[nm])

        num = _richardson(out, y, 1e-5)[0]
        assert np.max(np.abs(op.outputs[name] - num)) < 1e-8 * (1.0 + np.max(np.abs(num)))
    # at the state's own degree (32) the steady outputs are the static solver's
    ov = bed_operators(st, inertia=mu, womersley=alpha).output_values
    top = st.tip_stress - st.pi * (1.0 / st.eps - st.tip_height)
    want = {"tip_deflection": st.tip_deflection, "tip_height": st.tip_height,
            "base_moment": st.base_curvature, "wall_stress": top}  # fmt: skip
    for name, value in want.items():
        assert abs(ov[name] - value) < 1e-10, name
    if flow:
        assert abs(ov["flow_rate"] - 0.4) < 1e-12 and abs(ov["pressure"] - st.pi) < 1e-10
    mass = op.mass
    lay = op.layout
    assert np.all(mass[:11] == 1.0) and lay["size"] == y.size == mass.size
    assert np.all(mass[lay["stress"] : lay["stress"] + 13] == 0.0)
    assert np.all(mass[lay["v"] : lay["v"] + 11] == alpha * 0.05)


def test_bed_operators_bad_input() -> None:
    st = hairbed.solve_porous(1.5, 0.5, 0.3, kappa=0.05)
    with pytest.raises(TypeError, match="state"):
        bed_operators(hairbed.solve_porous([1.0, 2.0], 0.5, kappa=0.05))
    with pytest.raises(TypeError, match="state"):
        bed_operators(1.0)  # type: ignore[arg-type]
    for kw, name in (({"inertia": -1.0}, "inertia"), ({"womersley": np.nan}, "womersley"),
                     ({"tangential_mass": 0.0}, "tangential_mass"), ({"num": 4}, "num"),
                     ({"num_gap": 2}, "num_gap")):  # fmt: skip
        with pytest.raises(ValueError, match=name):
            bed_operators(st, **kw)
    with pytest.raises(ValueError, match="eps"):
        bed_operators(hairbed.solve_porous(1.5, 0.0, 0.3, kappa=0.05))
    for name, value in (("inertia", 1e308), ("womersley", 1e300), ("womersley", 2.0**63)):
        kwargs: dict[str, Any] = {name: value}
        with pytest.raises(ValueError, match=name):
            bed_operators(st, **kwargs)


# ---------------------------------------------------------------------------------------
# simulate_bed
# ---------------------------------------------------------------------------------------


def _smooth(a: float, b: float, span: float = 2.0) -> Callable[[np.ndarray], np.ndarray]:
    """a to b as 1 - cos over [0, span]: smooth at its start (the ringing hair's drive)."""
    return lambda t: (
        a
        + (b - a)
        * np.where(t < span, 0.5 * (1.0 - np.cos(np.pi * np.clip(t, 0.0, span) / span)), 1.0)
    )


def _top_stress(st: Any) -> float:
    return float(st.tip_stress - st.pi * (1.0 / st.eps - st.tip_height))


@pytest.mark.parametrize(
    ("kw", "static", "kappa", "num"),
    [
        ({"wall": step(1.0)}, {"omega2": 1.0}, 0.1, None),
        ({"wall": 1.0, "pressure": step(0.8), "womersley": 0.5}, {"omega2": 1.0, "pi": 0.8},
         0.3, None),
        ({"wall": 1.0, "flow_rate": _smooth(0.0, 0.5), "womersley": 0.5},
         {"omega2": 1.0, "q": 0.5}, 0.1, None),
        ({"wall": 1.0, "flow_rate": step(0.5)}, {"omega2": 1.0, "q": 0.5}, 0.1, None),
        ({"wall": _smooth(0.0, 3.0), "inertia": 0.2}, {"omega2": 3.0}, 1.0, 24),
        ({"wall": _smooth(0.0, 3.0), "inertia": 0.2, "womersley": 0.3, "gamma": 0.6},
         {"omega2": 3.0, "gamma": 0.6}, 1.0, 24),
    ],
)  # fmt: skip
def test_constant_drives_relax_to_the_static_state(
    kw: dict[str, Any], static: dict[str, float], kappa: float, num: int | None
) -> None:
    """Under drives that end constant the bed relaxes to solve_porous's state (the statics'
    own rows: integrated, on its own ladder of degrees) within 1e-10: the wall, pressure and
    flow drives, a quasi-steady and an inertial fluid (the flow drive's Pi then of index 2),
    overdamped and inertial hairs."""
    gamma = static.pop("gamma", 1.0)
    st = hairbed.solve_porous(theta0=0.3, eps=0.5, kappa=kappa, gamma=gamma, **static)
    mu = kw.get("inertia", 0.0)
    run = simulate_bed(0.3, kappa, 0.5, t_eval=[0.0, 1.0, 22.0 if mu else 8.0], num=num,
                       rtol=1e-6 if not mu else 1e-5, atol=1e-8 if not mu else 1e-6,
                       max_steps=5000, **kw)  # fmt: skip
    assert run.success, run.message
    got = (run.tip_deflection[-1], run.tip_height[-1], run.base_moment[-1], run.wall_stress[-1])
    want = (st.tip_deflection, st.tip_height, st.base_curvature, _top_stress(st))
    assert np.max(np.abs(np.subtract(got, want))) < 1e-10
    assert abs(run.pressure[-1] - st.pi) < 1e-9 * max(1.0, abs(st.pi))
    assert abs(run.wall_speed[-1] - st.omega2) < 1e-9
    if "q" in static:
        assert abs(run.flow_rate[-1] - 0.5) < 1e-10


def test_a_set_wall_stress_relaxes_to_the_static_state() -> None:
    """A step in the top wall's shear stress (the wall's speed free): the end state is the
    static solver's at the wall speed it reached, whose own top stress is the one set."""
    run = simulate_bed(0.3, 0.1, 0.5, wall_stress=step(1.2), pressure=0.4,
                       t_eval=[0.0, 1.0, 8.0], rtol=1e-6, atol=1e-8)  # fmt: skip
    assert run.success and run.top == "wall_stress"
    st = hairbed.solve_porous(float(run.wall_speed[-1]), 0.5, 0.3, kappa=0.1, pi=0.4)
    assert abs(_top_stress(st) - 1.2) < 1e-10
    assert abs(run.tip_deflection[-1] - st.tip_deflection) < 1e-10
    assert abs(run.wall_stress[-1] - 1.2) < 1e-12


def test_simulate_bed_bad_input() -> None:
    """Each parameter refused by name; a flow rate that jumps with fluid inertia refused."""
    ok: dict[str, Any] = {"theta0": 0.2, "kappa": 0.1, "eps": 0.5, "t_eval": [0.0, 1.0]}
    bad = [
        ("theta0", 2.0), ("kappa", 0.0), ("kappa", np.inf), ("kappa", 1e-7), ("kappa", 1e7),
        ("eps", 1.0), ("eps", 0.0), ("eps", 1e-4), ("gamma", 0.0), ("inertia", -1.0),
        ("inertia", np.inf), ("inertia", 1e-9), ("inertia", 1e8), ("tangential_mass", 1.5),
        ("womersley", -0.1), ("womersley", 1e300), ("womersley", 5e-324), ("num", 4),
        ("num_gap", 3), ("rtol", 0.0), ("atol", -1.0), ("max_steps", 0),
        ("t_eval", [1.0, 0.0]), ("t_eval", [0.0, np.nan]), ("wall", 1e300), ("wall", 2**63),
        ("pressure", step(1e7)), ("wall_stress", np.nan),
    ]  # fmt: skip
    for name, value in bad:
        with pytest.raises(ValueError, match=name):
            simulate_bed(**{**ok, name: value})
    with pytest.raises(ValueError, match="wall_stress"):
        simulate_bed(**ok, wall=1.0, wall_stress=1.0)
    with pytest.raises(ValueError, match="flow_rate"):
        simulate_bed(**ok, pressure=1.0, flow_rate=1.0)
    with pytest.raises(TypeError, match="wall"):
        simulate_bed(**ok, wall="fast")
    with pytest.raises(ValueError, match="flow_rate must not jump"):
        simulate_bed(**ok, flow_rate=step(0.5), womersley=0.1)
    with pytest.raises(TypeError, match="initial"):
        simulate_bed(**ok, initial=1.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="initial"):
        simulate_bed(**ok, initial=hairbed.solve_porous(1.0, 0.5, 0.2, kappa=0.2))


def _cheb_cumulative(s: np.ndarray, values: np.ndarray) -> np.ndarray:
    """int_0^s values ds' at the nodes s of a plain Chebyshev-Gauss-Lobatto grid on [0, 1],
    by the test's own Chebyshev interpolant (numpy), row by row."""
    out = np.empty_like(values)
    for i, row in enumerate(values):
        c = np.polynomial.chebyshev.chebfit(2.0 * s - 1.0, row, s.size - 1)
        anti = np.polynomial.chebyshev.chebint(c, lbnd=-1.0) / 2.0
        out[i] = np.polynomial.chebyshev.chebval(2.0 * s - 1.0, anti)
    return out


def test_momentum_budget_of_the_quasi_steady_fluid() -> None:
    """The fluid's horizontal momentum over the channel (alpha = 0): the top wall's stress
    minus the bottom's plus the pump's push Pi/eps balances the drag of the moving hairs,
    int_0^1 f_x ds with f_x = K_xx (v - x_t) - K_xz z_t on the velocity relative to the
    hairs (r_t by the test's own quadrature of the rates), at every output time of the bed
    under an oscillating pressure (the plain map: nodes of a plain Chebyshev grid), to the
    integrator's tolerance."""
    gamma = 0.6
    run = simulate_bed(0.3, 1.0, 0.5, wall=1.0, pressure=sine(1.0, 1.0, 3.0), gamma=gamma,
                       t_eval=np.linspace(0.0, 1.5, 7), num=24, rtol=1e-9,
                       atol=1e-11)  # fmt: skip
    assert run.success
    s, th, tt = run.s, run.theta, run.theta_t
    c, sn = np.cos(th), np.sin(th)
    xt = _cheb_cumulative(s, tt * c)
    zt = _cheb_cumulative(s, -tt * sn)
    kxx = 1.0 - (1.0 - gamma) * sn * sn
    kxz = -(1.0 - gamma) * sn * c
    fx = kxx * (run.velocity - xt) - kxz * zt
    drag = _cheb_cumulative(s, fx)[:, -1]
    budget = run.wall_stress - run.stress[:, 0] + run.pressure / 0.5 - drag
    # (measured 1.9e-9: the algebraic rows hold at the steps' stages, the output times are
    # the dense output's, accurate to the tolerance)
    assert np.max(np.abs(budget)) < 1e-8 * np.max(np.abs(drag))
    assert np.max(np.abs(tt)) > 0.1  # the hairs did move


def test_quasi_steady_limit_and_pillar_limit_rates() -> None:
    """alpha -> 0: the fluid's inertia vanishes like alpha (the tip deflection's largest
    difference from the alpha = 0 fast path, wall speed rising smoothly over 1 T; measured
    rate 1.00). kappa -> infinity at fixed Lambda = omega2/kappa: each hair is the isolated
    pillar of simulate_pillar in the undisturbed Couette flow (profile "couette", L/H = eps,
    the same gamma) like 1/kappa (measured 1.00)."""
    tt = np.linspace(0.0, 1.0, 801)
    drive = sampled(tt, 0.5 * (1.0 - np.cos(np.pi * tt)))
    te = [0.0, 0.25, 0.5, 1.0, 1.5]
    opts: dict[str, Any] = {"t_eval": te, "rtol": 1e-9, "atol": 1e-11, "num": 16}
    ref = simulate_bed(0.2, 0.3, 0.5, wall=drive, **opts)
    errs = []
    for alpha in (0.02, 0.01):
        run = simulate_bed(0.2, 0.3, 0.5, wall=drive, womersley=alpha, num_gap=12, **opts)
        errs.append(np.max(np.abs(run.tip_deflection - ref.tip_deflection)))
    assert 1e-4 < errs[0] < 1e-2
    assert abs(np.log2(errs[0] / errs[1]) - 1.0) < 0.05
    pil = simulate_pillar(step(2.0), te, theta0=0.2, profile="couette", height_ratio=0.5,
                          gamma=0.7, num=16, rtol=1e-10, atol=1e-12)  # fmt: skip
    errs = []
    for kappa in (1e3, 1e4):
        run = simulate_bed(0.2, kappa, 0.5, wall=step(2.0 * kappa), gamma=0.7, t_eval=te,
                           rtol=1e-10, atol=1e-12, num=16)  # fmt: skip
        errs.append(np.max(np.abs(run.tip_deflection - pil.tip_deflection)))
    assert errs[0] < 1e-4
    assert abs(np.log10(errs[0] / errs[1]) - 1.0) < 0.05


def test_accuracy_against_twice_the_resolution() -> None:
    """A step of the top wall's speed (kappa = 0.1, the tips' map): N = 24 at rtol 1e-8
    against N = 48 at rtol 1e-10, the tip deflection within 1e-8 at every output time
    (measured 5e-11 at N = 32 against 64)."""
    te = [0.0, 0.05, 0.3, 1.0, 3.0]
    a = simulate_bed(0.2, 0.1, 0.5, wall=step(1.0), t_eval=te, num=24, rtol=1e-8, atol=1e-10)
    b = simulate_bed(0.2, 0.1, 0.5, wall=step(1.0), t_eval=te, num=48, rtol=1e-10, atol=1e-12)
    assert a.success and b.success
    assert np.max(np.abs(a.tip_deflection - b.tip_deflection)) < 1e-8
    # the top stress too, after the impulsive start (at t = 0 the step's stress has the
    # hairs' singular start in it: 4e-5 apart)
    assert np.max(np.abs(a.wall_stress[1:] - b.wall_stress[1:])) < 1e-8


@pytest.mark.parametrize(
    ("mu", "alpha", "drives"),
    [
        (0.2, 0.0, {"wall": sine(0.5, 0.5, 2.0, -np.pi / 2)}),
        (13.0, 0.3, {"wall": sine(0.5, 0.5, 2.0, -np.pi / 2)}),
        (0.2, 0.3, {"wall": 1.0, "flow_rate": sine(0.1, 0.1, 2.0, -np.pi / 2)}),
    ],
)  # fmt: skip
def test_inertial_accuracy_against_twice_the_resolution(
    mu: float, alpha: float, drives: dict[str, Any]
) -> None:
    """Issue 30's accuracy target for the inertial bed: hairs with inertia (mu = 0.2, and 13,
    the ringing pillar in water), a quasi-steady and an inertial fluid, and the flow-rate
    drive whose Pi is of index 2 (alpha > 0); drives smooth at their start (a wall speed or
    flow rate rising as 1 - cos(2 t)). N = 24 at rtol 1e-8 against N = 48 at rtol 1e-10: the
    tip deflection within 1e-8 at every output time (measured to t = 3: 6.5e-12, 9.5e-12 and
    1.8e-12). A step drive is not covered: with inertia it rings in every mode the grid
    holds (theory.md §15): at mu = 0.2, alpha = 0, 200,000 steps at N = 24 end before t = 3."""
    te = [0.0, 0.3, 1.0]
    common = {"t_eval": te, "inertia": mu, "womersley": alpha, **drives}
    a = simulate_bed(0.2, 0.1, 0.5, num=24, rtol=1e-8, atol=1e-10, **common)
    b = simulate_bed(0.2, 0.1, 0.5, num=48, rtol=1e-10, atol=1e-10, **common)
    assert a.success and b.success, (a.message, b.message)
    assert np.max(np.abs(a.tip_deflection - b.tip_deflection)) < 1e-8
    # the hairs do move: the drive's work is not lost in the comparison
    assert np.ptp(b.tip_deflection) > 1e-3


def test_the_wall_event_the_xarray_and_a_given_start() -> None:
    """A downstream-tilted inertial hair (theta0 = 1.3, mu = 1) struck by a step of the top
    wall's speed overshoots to abs(theta) = pi/2: status -8 at t_end (N = 12 and 16 agree on
    it to 4e-5), the values after it NaN; the trajectory as xarray with CF attributes; a
    run started from a given static state of its own drives stays there."""
    run = simulate_bed(1.3, 1.0, 0.5, wall=step(300.0), inertia=1.0,
                       t_eval=[0.0, 0.05, 0.5], num=12, rtol=1e-6, atol=1e-8)  # fmt: skip
    assert run.status == -8 and not run.success and "pi/2" in run.message
    assert 0.17 < run.t_end < 0.18
    assert np.isfinite(run.tip_deflection[1]) and np.isnan(run.tip_deflection[2])
    ds = run.to_xarray()
    assert ds["tip_deflection"].attrs["units"] == "L"
    assert ds["theta"].dims == ("t", "s") and ds.attrs["status"] == -8
    assert all("long_name" in ds[v].attrs for v in ds.data_vars)
    st = hairbed.solve_porous(2.0, 0.5, 0.3, kappa=0.2, pi=0.5)
    run = simulate_bed(0.3, 0.2, 0.5, wall=2.0, pressure=0.5, initial=st, t_eval=[0.0, 1.0])
    assert run.success and np.max(np.abs(run.tip_deflection - st.tip_deflection)) < 1e-12


def _dense_limit_reference(theta0: float, eps: float, omega2: float, te: np.ndarray) -> Any:
    """The dense limit in time (theory.md §15; gamma = 1, Pi = 0, alpha = 0, overdamped),
    written here from its equations: theta'' + W cos theta + sin theta int_s^1 z_t ds' = 0,
    z_t = -int_0^s sin(theta) theta_t, W = omega2/(1 - eps h1(t)); numpy's Chebyshev
    operators (N = 16, plain nodes) and scipy's Radau. Returns x1 at te."""
    from scipy.integrate import solve_ivp

    cheb = np.polynomial.chebyshev
    num = 16
    x = -np.cos(np.pi * np.arange(num + 1) / num)
    vinv = np.linalg.inv(cheb.chebvander(x, num))
    d1 = np.array([cheb.chebval(x, cheb.chebder(c)) * 2.0 for c in vinv.T]).T
    d2 = np.array([cheb.chebval(x, cheb.chebder(c, 2)) * 4.0 for c in vinv.T]).T
    im = np.array([cheb.chebval(x, cheb.chebint(c, lbnd=-1.0)) / 2.0 for c in vinv.T]).T
    srow = -d1[num, :num] / d1[num, num]
    lift = np.zeros((num + 1, num - 1))
    lift[1:num] = np.eye(num - 1)
    lift[num] = srow[1:num]
    tail = im[num][None, :] - im

    def full(inner: np.ndarray) -> np.ndarray:
        th = np.concatenate([[theta0], inner, [0.0]])
        th[num] = srow @ th[:num]
        return th

    def rates(t: float, y: np.ndarray) -> np.ndarray:
        th = full(y)
        load = omega2 / (1.0 - eps * (im[num] @ np.cos(th)))
        rhs = -(d2 @ th + load * np.cos(th))
        sn = np.sin(th)
        amat = sn[:, None] * (tail @ (-im @ (sn[:, None] * lift)))
        return np.asarray(np.linalg.solve(amat[1:num], rhs[1:num]))

    sol = solve_ivp(rates, (te[0], te[-1]), np.full(num - 1, theta0), method="Radau",
                    t_eval=te, rtol=1e-8, atol=1e-10)  # fmt: skip
    assert sol.status == 0
    return np.array([im[num] @ np.sin(full(y)) for y in sol.y.T])


def test_dense_limit_in_time() -> None:
    """kappa -> 0: the fluid inside the bed moves with the hairs horizontally (their drag is
    the vertical one of the relative velocity) and the tips carry the gap's stress W; a step
    of the wall's speed converges to that reduced model like sqrt(kappa) (the tips' layer),
    during the motion (t = 0.02, 0.1 T) and at rest (measured 0.57 and 0.51 from kappa = 1e-2
    to 1e-3 and 1e-4)."""
    te = np.array([0.0, 0.02, 0.1, 2.0])
    ref = _dense_limit_reference(0.5, 0.5, 1.0, te)
    errs = []
    for kappa, num in ((1e-2, 32), (1e-3, 48)):
        run = simulate_bed(0.5, kappa, 0.5, wall=step(1.0), t_eval=te, num=num, rtol=1e-9,
                           atol=1e-11)  # fmt: skip
        errs.append(np.abs(run.tip_deflection[1:] - ref[1:]))
    assert np.all(errs[1] < 0.01)
    rate = np.log10(errs[0] / errs[1])
    assert np.all((rate > 0.45) & (rate < 0.65)), rate


@pytest.mark.parametrize("alpha", [0.0, 0.5])
def test_steady_response_with_the_feedthrough(alpha: float) -> None:
    """The steady (omega = 0) response to the pump, c . (-J^-1 b) + f, of
    :func:`bed_operators` and :func:`linearise_bed` against Richardson differences of the
    static solver (:func:`hairbed.solve_porous` at Pi +- h, +- 2h): with a quasi-steady fluid
    the top stress and the flux read Pi directly (f = -g and -eps^2 g^3), not otherwise."""
    eps, kap, th, pi0 = 0.5, 0.05, 0.3, 0.7
    st = hairbed.solve_porous(1.5, eps, th, kappa=kap, gamma=0.6, pi=pi0)
    op = bed_operators(st, womersley=alpha)
    gg = 1.0 / eps - st.tip_height
    f = op.feedthrough["pressure"]
    want_f = np.zeros(len(BED_OUTPUTS))
    if alpha == 0.0:
        want_f[BED_OUTPUTS.index("wall_stress")] = -gg
        want_f[BED_OUTPUTS.index("flow_rate")] = -(eps**2) * gg**3
    assert np.max(np.abs(f - want_f)) < 1e-12 * (1.0 + gg**3)
    assert np.all(op.feedthrough["wall"] == 0.0)
    dy = np.linalg.solve(op.jacobian, -op.drives["pressure"])
    lin = {k: float(op.outputs[k] @ dy + f[BED_OUTPUTS.index(k)]) for k in BED_OUTPUTS}

    def outputs(pi: float) -> np.ndarray:
        s = hairbed.solve_porous(1.5, eps, th, kappa=kap, gamma=0.6, pi=pi)
        top = s.tip_stress - pi * (1.0 / eps - s.tip_height)
        return np.array([s.tip_deflection, s.tip_height, s.base_curvature, top])

    def pressure(q: float) -> float:
        return float(hairbed.solve_porous(1.5, eps, th, kappa=kap, gamma=0.6, q=q).pi)

    def richardson(func: Callable[[float], Any], x: float, h: float) -> Any:
        return (8.0 * (func(x + h) - func(x - h)) - (func(x + 2 * h) - func(x - 2 * h))) / (
            12.0 * h
        )

    # the flux: dq/dPi = 1/(dPi/dq) along the static family under the flow drive, about
    # the flow rate of this state (its Pi the static solver's to 1e-10)
    q0 = op.output_values["flow_rate"]
    assert abs(pressure(q0) - pi0) < 1e-10
    ref = np.append(richardson(outputs, pi0, 1e-3), 1.0 / richardson(pressure, q0, 1e-3))
    for i, name in enumerate(BED_OUTPUTS):
        assert abs(lin[name] - ref[i]) < 1e-10 * (1.0 + abs(ref[i])), (name, lin[name], ref[i])
    # linearise_bed takes the same feedthrough: its response at omega -> 0
    resp = hairbed.dynamics.linearise_bed(st, womersley=alpha).frequency_response(
        [0.0], "pressure", num=op.num, num_gap=16
    )
    for i, name in enumerate(BED_OUTPUTS):
        got = complex(getattr(resp, name)[0])
        assert abs(got - ref[i]) < 1e-10 * (1.0 + abs(ref[i])), (name, got, ref[i])


def test_tight_absolute_tolerance_and_a_tilted_oscillation() -> None:
    """Regression (issue 30): with atol 100 times below rtol the run stalled at its first
    step (status -3), and a tilted bed (theta0 = 0.4) under an oscillating wall failed in
    mid-run, both from the algebraic unknowns' rounding in the Newton and error norms (fixed
    in 320bb5a: both norms over the differential components). Both now run through with few
    rejections, and the tighter run agrees with the default one to the tolerances."""
    te = np.linspace(0.0, 2.0 * np.pi, 65)
    runs = [
        simulate_bed(
            0.4, 1.0, 0.5, t_eval=te, wall=sine(0.0, 1.0, 1.0, np.pi / 2), rtol=rt, atol=at
        )
        for rt, at in ((1e-9, 1e-11), (1e-8, 1e-10))
    ]
    for run in runs:
        assert run.success and run.t_end == te[-1]
        assert run.nreject < 0.05 * run.nsteps
    scale = np.max(np.abs(runs[0].wall_stress))
    assert np.max(np.abs(runs[0].wall_stress - runs[1].wall_stress)) < 1e-7 * scale
    assert np.max(np.abs(runs[0].tip_deflection - runs[1].tip_deflection)) < 1e-8
