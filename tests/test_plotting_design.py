"""The gallery's worked designs (issue 32): the figures draw the library's numbers.

Each figure's lines are compared with the library's functions called here on their own:
the Pareto front with :func:`hairbed.design.pareto_front`, the chosen valve's curve with
:func:`hairbed.valve.valve_curve` (and its diodicity with :func:`hairbed.valve.diodicity`),
the chosen pillar's calibration with :meth:`hairbed.Pillar.tip_deflection` and the end of
its linear range with :meth:`hairbed.Pillar.linear_range`.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from hairbed import design as D  # noqa: E402
from hairbed.plotting import fig_sensor_design, fig_valve_design  # noqa: E402
from hairbed.plotting.design import (  # noqa: E402
    _sensor_pillar,
    _valve_bed,
    sensor_design_example,
    valve_design_example,
)
from hairbed.valve import diodicity, valve_curve  # noqa: E402


def _line(ax, label):
    return next(line for line in ax.lines if line.get_label() == label)


def test_valve_design_figure_draws_the_library_numbers():
    fig = fig_valve_design(points=4, num=11)
    axp, axv = fig.axes
    front, chosen = valve_design_example(points=4)
    assert chosen.success
    # the front, against the library's own front of the same problem
    variables = [D.Variable("base_angle", 0.0, 1.4), D.Variable("length", 0.6e-3, 1.5e-3)]
    ref = D.pareto_front(_valve_bed(), variables, D.diodicity(1000.0, 0.01),
                         D.resistance_ratio(1000.0, 0.01), senses=("max", "min"), points=4,
                         starts=4)  # fmt: skip
    x, y = _line(axp, "Pareto front").get_data()
    np.testing.assert_allclose(x, ref.second, rtol=1e-9)
    np.testing.assert_allclose(y, ref.first, rtol=1e-9)
    # the chosen design meets its budget and the figure marks it
    assert D.resistance_ratio(1000.0, 0.01)(chosen.design) <= 2.5 * (1 + 1e-7)
    sx, sy = _line(axp, "chosen design").get_data()
    assert sy[0] == pytest.approx(chosen.objective, rel=1e-12)
    # the valve curve is valve_curve's, and its flow ratio at +-dp is the diodicity
    dp = np.linspace(-2000.0, 2000.0, 11)
    q = np.asarray(valve_curve(chosen.design, dp, 0.01).flow_rate)
    x, y = _line(axv, "chosen design").get_data()
    np.testing.assert_array_equal(x, dp)
    np.testing.assert_allclose(y, q * 1e6, rtol=1e-12)
    marks = next(line for line in axv.lines if line.get_marker() == "o")
    mx, my = (np.asarray(v, dtype=float) for v in marks.get_data())
    assert list(mx) == [1000.0, -1000.0]
    assert my[0] / abs(my[1]) == pytest.approx(
        diodicity(chosen.design, 1000.0, 0.01).diodicity, rel=1e-9
    )
    assert chosen.objective == pytest.approx(
        diodicity(chosen.design, 1000.0, 0.01).diodicity, rel=1e-9
    )
    x, y = _line(axv, "starting bed").get_data()
    np.testing.assert_allclose(y, np.asarray(valve_curve(_valve_bed(), dp, 0.01).flow_rate) * 1e6)


def test_sensor_design_figure_draws_the_library_numbers():
    fig = fig_sensor_design(points=4, num=11)
    axp, axc = fig.axes
    front, chosen = sensor_design_example(points=4)
    assert chosen.success
    p = chosen.design
    # the front's points: the sensitivity is the closed form L c1 K, the range linear_range's
    x, y = _line(axp, "Pareto front").get_data()
    np.testing.assert_allclose(x, front.second, rtol=1e-9)
    np.testing.assert_allclose(y, front.first * 1e6, rtol=1e-9)
    for r, xi, yi in zip(front.results, x, y, strict=True):
        q = r.design
        assert xi == pytest.approx(q.linear_range(0.05).wall_shear_stress, rel=1e-9)
        slope = q.length * q.linear_coefficient * q.forcing_per_stress
        assert yi == pytest.approx(slope * 1e6, rel=1e-12)
    # the chosen pillar reaches the range asked for
    end = p.linear_range(0.05)
    assert end.wall_shear_stress >= 1.0 * (1 - 1e-7)
    # the calibration curve is the pillar's exact tip deflection over twice its range
    tau = np.linspace(0.0, 2.0 * end.wall_shear_stress, 11)
    x, y = _line(axc, "exact").get_data()
    np.testing.assert_allclose(x, tau, rtol=1e-12)
    np.testing.assert_allclose(y, np.asarray(p.tip_deflection(tau)) * 1e6, rtol=1e-12)
    x, y = _line(axc, "linear formula").get_data()
    # the linear formula's reading of the deflection at the marked end is rtol off
    mx, my = _line(axc, "linear range end (0.05)").get_data()
    read = (my[0] * 1e-6) / chosen.objective
    assert abs(read / mx[0] - 1.0) == pytest.approx(0.05, rel=1e-8)
    assert _sensor_pillar().radius == p.radius  # the radius is held
