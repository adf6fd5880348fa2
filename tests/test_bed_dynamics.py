"""The porous bed in time (issue 30, theory.md §15): its semi-discrete system and operators.

References: Richardson (fourth-order central) differences of the system g(t, y) for the
exact Jacobian, the drives' columns and the outputs' rows; :func:`hairbed.solve_porous`
(the statics' own collocation, a different set of rows) for the steady states.
"""

from __future__ import annotations

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import BED_OUTPUTS, bed_operators
from hairbed.dynamics._bed import _evaluate, _output_values, _system
from hairbed.dynamics._signals import constant


def _richardson(func, x: np.ndarray, h: float) -> np.ndarray:
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
    pump_value = load.get("q", load.get("pi"))
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
        num = _richardson(lambda x, nm=name: with_drive(nm, float(x[0])), np.array([d0]), 1e-5)[
            :, 0
        ]
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
