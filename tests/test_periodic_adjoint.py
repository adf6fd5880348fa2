"""The adjoint of the periodic collocation (hairbed.dynamics.periodic_adjoint).

Reference: the forward sensitivity (periodic_sensitivity: one solve of the variational
problem per column, S = dy/dp, then the outputs' means (1/K) sum_k c_k . S_k), itself checked
against central differences of periodic_bed in tests/test_periodic_bed.py. The adjoint solves
the transposed problem once (lambda, L^T lambda = c/K) and forms lambda . G: the two are
different linear solves of the same discrete problem, equal to rounding (measured 2e-16 to
2e-13 relative on every output, random columns, four drives and orderings of the unknowns).
The net flow's gradient by the adjoint against central differences is
tests/test_design_net_flow.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hairbed._core._kernels import bed as bed_kernel
from hairbed._core._kernels import bed_parameters as bpk
from hairbed.dynamics import (
    BED_OUTPUTS,
    PERIODIC_ADJOINT_STATUS,
    PeriodicAdjoint,
    periodic_adjoint,
    periodic_bed,
    periodic_sensitivity,
    sine,
)

#: The adjoint against the forward sensitivity, relative to the largest derivative.
RTOL = 1e-10
OUTPUTS = (*BED_OUTPUTS, "wall_speed")


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize(
    ("args", "drives"),
    [
        # overdamped hairs, quasi-steady fluid, a set flow rate (the pressure a state)
        ((0.3, 1.0, 0.5), {"omega": 1.0, "flow_rate": sine(0.0, 0.5, 1.0)}),
        # the hairs' and the fluid's inertia: the algebraic unknowns are interleaved with the
        # differential ones (the Schur elimination's permutation is not the identity)
        (
            (0.3, 1.0, 0.5),
            {
                "omega": 2.0,
                "wall": sine(0.0, 1.0, 2.0),
                "inertia": 0.5,
                "womersley": 0.7,
                "tangential_mass": 0.5,
            },
        ),  # fmt: skip
    ],
)
def test_adjoint_is_the_forward_sensitivity(args: tuple, drives: dict) -> None:
    orbit = periodic_bed(*args, **drives)
    assert orbit.success, orbit.message
    kk, m = orbit.y.shape
    forcing = np.random.default_rng(7).standard_normal((kk, m, 3))
    forward = periodic_sensitivity(orbit, forcing).mean_outputs
    for name in OUTPUTS:
        adj = periodic_adjoint(orbit, name)
        assert isinstance(adj, PeriodicAdjoint) and adj.output == name
        assert adj.success and adj.message == PERIODIC_ADJOINT_STATUS[0], (name, adj.residual)
        assert adj.multipliers.shape == (kk, m)
        if np.max(np.abs(forward[name])) == 0.0:  # an output no state moves (a set wall)
            assert np.all(adj.multipliers == 0.0)
            continue
        assert _relative(adj.mean_derivative(forcing), forward[name]) <= RTOL, name
        # one column (K, size) is the 1-column case
        one = adj.mean_derivative(forcing[:, :, 1])
        assert one.shape == (1,)
        assert one[0] == pytest.approx(forward[name][1], rel=RTOL, abs=RTOL * np.max(np.abs(
            forward[name])))  # fmt: skip


def test_adjoint_of_the_pumped_bed_is_the_forward_sensitivity() -> None:
    """The net flow's orbit (design.net_flow's test bed: kappa = 1.5e-3, a pressure drop
    2.2 sin(t), the hairs swinging far: H = 48, the preconditioned GMRES's hardest case)
    and its parameter columns dg/dp - (dM/dp) y' (bed_parameter_phases): the adjoint's
    d(mean flow)/dp against the forward sensitivity's, one solve against seven."""
    orbit = periodic_bed(0.5, 0.0015266302336162853, 0.5, omega=0.9984111915889885,
                         pressure=sine(0.0, 2.2053155816871675, 0.9984111915889885),
                         gamma=0.5055063473445999, tol=1e-12)  # fmt: skip
    assert orbit.success, orbit.message
    sys = orbit._sys
    kk, m = orbit.y.shape
    gp = np.zeros((kk, bpk.NPAR, m))
    mp = np.zeros((kk, bpk.NPAR, m))
    ws = bed_kernel.bed_workspace(sys.num, sys.num_gap)
    assert bpk.bed_parameter_phases(orbit.t, orbit.y, sys.params, gp, mp, np.zeros((m, m)), ws)
    cols = [bpk.P_THETA0, bpk.P_GAMMA, bpk.P_KAPPA, bpk.P_EPS, bpk.P_PUMP]
    forcing = np.stack([gp[:, p] - mp[:, p] * orbit.y_t for p in cols], axis=2)
    forcing[:, :, -1] *= np.sin(orbit.omega * orbit.t)[:, None]  # d/d(amplitude)
    forward = periodic_sensitivity(orbit, forcing).mean_outputs["flow_rate"]
    adj = periodic_adjoint(orbit)
    assert adj.success, adj.message
    assert _relative(adj.mean_derivative(forcing), forward) <= RTOL


def test_bad_adjoint_input_is_named() -> None:
    orbit = periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=sine(0.0, 1.0, 1.0, 0.5 * math.pi),
                         harmonics=4, tol=1e-6)  # fmt: skip
    kk, m = orbit.y.shape
    with pytest.raises(TypeError, match="orbit must be a PeriodicBed"):
        periodic_adjoint("orbit")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="output must be one of"):
        periodic_adjoint(orbit, "speed")
    adj = periodic_adjoint(orbit, "wall_stress")
    with pytest.raises(ValueError, match=rf"forcing must have shape \({kk}, {m}\)"):
        adj.mean_derivative(np.zeros((kk, m + 1)))
    bad = np.zeros((kk, m, 2))
    bad[3, 4, 1] = np.inf
    with pytest.raises(ValueError, match=r"forcing must be finite.*\(3, 4, 1\)"):
        adj.mean_derivative(bad)
