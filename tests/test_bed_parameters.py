"""The porous bed in time: the exact parameter columns dg/dp, dM/dp of M y' = g(t, y; p)
(``_core._kernels.bed_parameters``, issue 32) against central differences of the rates.

Each column is compared with a difference of :func:`hairbed._core._kernels.bed.bed_system`
on a system rebuilt at the shifted parameter (``dynamics._bed._system``), at a random state
y (the rows are functions of y; no state need be a solution): fourth-order central
differences of step 1e-5 for theta0 and eps (truncation ~1e-20, rounding ~1e-11 of the
rows' scale), and a difference of step 0.2 of the value for the parameters g is affine in
(exact for an affine function, whatever the step: the test checks the affinity too). The
drives' columns are compared with ``dynamics._bed._drive_columns``, written out by hand.
"""

from __future__ import annotations

import numpy as np
import pytest

from hairbed._core._kernels import bed as bk
from hairbed._core._kernels import bed_parameters as bpk
from hairbed.dynamics import constant, sine
from hairbed.dynamics._bed import _drive_columns, _evaluate, _mass, _system

#: Relative to the column's largest entry (its rows' rounding is ~1e-12 of the rows' scale,
#: which is up to 1e5 times the smallest column's).
RTOL = 1e-8
# the kernel's flts slots of each parameter
SLOTS = {
    bpk.P_THETA0: 0,
    bpk.P_GAMMA: 1,
    bpk.P_CHI: 2,
    bpk.P_MU: 3,
    bpk.P_KAPPA: 4,
    bpk.P_EPS: 5,
    bpk.P_ALPHA: 6,
}
# (theta0, gamma, chi, mu, kappa, eps, alpha, top, pump): every branch of the rows
CASES = [
    (0.3, 0.7, 1.0, 0.0, 0.2, 0.4, 0.0, 0, 0),  # overdamped, quasi-steady fluid, the pump
    (0.3, 0.7, 0.6, 0.5, 0.2, 0.4, 0.0, 0, 0),  # the hairs' inertia
    (-0.4, 0.6, 1.0, 0.0, 0.05, 0.6, 0.3, 0, 0),  # the fluid's inertia: the gap's grid
    (0.2, 0.8, 0.7, 0.3, 0.5, 0.3, 0.2, 1, 0),  # both, under a set wall stress
    (0.25, 0.9, 1.0, 0.0, 0.3, 0.5, 0.0, 1, 1),  # a set flow rate
    (0.25, 0.9, 1.0, 0.0, 0.3, 0.5, 0.4, 0, 1),  # a set flow rate with the fluid's inertia
]


def _signals(top: int, pump: int) -> tuple:
    return (constant(0.3) if top == 0 else constant(0.2),
            sine(0.0, 0.7, 2.0) if pump == 0 else sine(0.1, 0.05, 2.0))  # fmt: skip


def _build(flts: np.ndarray, top: int, pump: int) -> object:
    return _system(12, 0.0, 8, *(float(v) for v in flts), top, pump, *_signals(top, pump))


@pytest.mark.parametrize("case", CASES)
def test_parameter_columns_match_differences(case: tuple) -> None:
    *values, top, pump = case
    flts = np.array(values, dtype=np.float64)
    sys = _build(flts, top, pump)
    m = sys.layout.size
    rng = np.random.default_rng(7)
    y = 0.3 * rng.standard_normal(m)
    y[: sys.num - 1] = flts[0] + 0.2 * rng.standard_normal(sys.num - 1)  # angles near theta0
    t = 0.37
    gp = np.zeros((bpk.NPAR, m))
    mp = np.zeros((bpk.NPAR, m))
    ok = bpk.bed_parameter_columns(t, y, sys.params, gp, mp, np.zeros((m, m)),
                                   bk.bed_workspace(sys.num, sys.num_gap))  # fmt: skip
    assert ok

    def rows(p: int, value: float) -> tuple[np.ndarray, np.ndarray]:
        f = flts.copy()
        f[SLOTS[p]] = value
        shifted = _build(f, top, pump)
        good, g, _ = _evaluate(shifted, t, y, False)
        assert good
        return g, _mass(shifted)

    for p, slot in SLOTS.items():
        v = float(flts[slot])
        if (p == bpk.P_ALPHA and v == 0.0) or (p in (bpk.P_MU, bpk.P_CHI) and flts[3] == 0.0):
            assert not gp[p].any() and not mp[p].any()  # absent: no column
            continue
        if p in (bpk.P_THETA0, bpk.P_EPS):
            h = 1e-5
            fd = (8.0 * (rows(p, v + h)[0] - rows(p, v - h)[0])
                  - (rows(p, v + 2 * h)[0] - rows(p, v - 2 * h)[0])) / (12.0 * h)  # fmt: skip
            dm = np.zeros(m)
        else:
            h = 0.2 * v
            (g1, m1), (g0, m0) = rows(p, v + h), rows(p, v - h)
            fd, dm = (g1 - g0) / (2.0 * h), (m1 - m0) / (2.0 * h)
        scale = np.max(np.abs(fd))
        assert scale > 0.0
        np.testing.assert_allclose(gp[p], fd, rtol=0, atol=RTOL * scale, err_msg=f"p = {p}")
        np.testing.assert_allclose(mp[p], dm, rtol=0, atol=1e-14, err_msg=f"mass, p = {p}")
    # the drives: g is affine in each; the columns written out by hand in dynamics._bed
    cols = _drive_columns(sys, y)
    top_name = "wall" if top == 0 else "wall_stress"
    pump_name = "pressure" if pump == 0 else "flow_rate"
    for p, name in ((bpk.P_WALL, top_name), (bpk.P_PUMP, pump_name)):
        atol = 1e-13 * max(1.0, float(np.max(np.abs(cols[name]))))
        np.testing.assert_allclose(gp[p], cols[name], rtol=0, atol=atol, err_msg=name)
