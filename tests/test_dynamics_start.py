"""simulate_pillar's cheap loose runs (issue 30's speed against PyElastica): the least
Chebyshev degree N = 4, the starting step, a callable drive sampled to the run's tolerance.

References independent of the integrator: the mpmath static states of
tests/data/pillar_mpmath.json (tests/reference/generate_pillar.py), which constant drives
relax to at every degree, the error falling with N; the callable itself at times between its
samples; the same run at a tight tolerance and the old first step (1e-6) for the start.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hairbed.dynamics import CALLABLE_SAMPLES, simulate_pillar, step
from hairbed.dynamics._integrate import LEAST_NUM
from hairbed.dynamics._signals import CALLABLE_LEAST_SAMPLES, as_signal

DATA = Path(__file__).parent / "data" / "pillar_mpmath.json"


def _case(forcing: float, theta0: float) -> dict[str, str]:
    cases = json.loads(DATA.read_text())["cases"]
    return next(
        c
        for c in cases
        if c["profile"] == "sublayer" and c["forcing"] == forcing and c["theta0"] == theta0
    )


@pytest.mark.parametrize(("forcing", "theta0"), [(100.0, 1.4), (1.0, -0.7), (30.0, -0.7)])
def test_the_least_degree_relaxes_to_the_mpmath_state_converging(
    forcing: float, theta0: float
) -> None:
    """A step from rest to a constant Lambda, run to t = 20 T (the start decayed to below
    1e-15) at N = 4, 8, 12: the tip within 5e-3 of mpmath's at N = 4 (measured 1.0e-5,
    1.1e-5, 3.2e-3) and at least ten times nearer at each next degree."""
    case = _case(forcing, theta0)
    ref = float(case["tip_deflection"])
    gamma = float(case["gamma"])
    errors = []
    for num in (LEAST_NUM, 8, 12):
        run = simulate_pillar(
            step(forcing), [0.0, 20.0], theta0=theta0, gamma=gamma, num=num, rtol=1e-10,
            atol=1e-12,
        )  # fmt: skip
        assert run.success and run.status == 0
        errors.append(abs(float(run.tip_deflection[-1]) - ref))
    assert errors[0] <= 5e-3, errors
    assert errors[1] <= 0.1 * errors[0] and errors[2] <= 0.1 * errors[1], errors


def test_below_the_least_degree_is_refused() -> None:
    with pytest.raises(ValueError, match=r"num must be an integer >= 4 and <= 128, got 3"):
        simulate_pillar(1.0, [0.0, 1.0], num=LEAST_NUM - 1)


def _smooth_rise(t: np.ndarray) -> np.ndarray:
    """Lambda = 1 - cos(pi t) until t = 1, then 2 (benchmarks/bench_pyelastica.py's)."""
    return 1.0 - np.cos(np.pi * np.minimum(t, 1.0))


def test_the_starting_step_from_rest_under_a_rising_drive() -> None:
    """The ringing pillar (mu = 13) from rest as the flow rises like t^2: f(t0, y0) = 0, so
    the start says nothing of the time scale; the probes find it (the first step 0.1-0.5 T,
    not 1e-6 growing fivefold a step). At rtol 1e-6 the run is the run with the old first
    step 1e-6 to the tolerance, and both are within 1e-5 of a run at rtol 1e-11."""
    te = np.array([0.0, 0.5, 1.0, 1.5, 2.0])
    kw: dict[str, Any] = dict(profile=lambda z: np.ones_like(z), gamma=1.0, mu=13.0, num=12)
    ref = simulate_pillar(_smooth_rise, te, rtol=1e-11, atol=1e-13, **kw)
    run = simulate_pillar(_smooth_rise, te, rtol=1e-6, atol=1e-8, **kw)
    assert ref.success and run.success
    assert np.max(np.abs(run.tip_deflection - ref.tip_deflection)) <= 1e-5
    loose = simulate_pillar(_smooth_rise, te, rtol=1.0, atol=1e-2, **kw)
    assert loose.success and loose.nreject == 0 and loose.nsteps <= 6
    assert np.max(np.abs(loose.tip_deflection - ref.tip_deflection)) <= 5e-3


@pytest.mark.parametrize("rtol", [1.0, 1e-3, 1e-6])
@pytest.mark.parametrize("omega", [1.0, 40.0])
def test_a_callable_is_sampled_to_the_runs_tolerance(rtol: float, omega: float) -> None:
    """d(t) = 1 - cos(omega t) + 0.3 t over [0, 2]: the interpolant of its samples within
    rtol max|d| of d itself at 2001 times between them (measured: at most 0.15 of it);
    the fewest samples where d is smooth on their spacing, more where not."""

    def func(t: np.ndarray) -> np.ndarray:
        return 1.0 - np.cos(omega * t) + 0.3 * t

    sig = as_signal(func, "forcing", 0.0, 2.0, rtol)
    count = sig.times.size
    assert CALLABLE_LEAST_SAMPLES <= count <= CALLABLE_SAMPLES
    assert math.log2(count - 1).is_integer()
    t = np.linspace(0.0, 2.0, 2001)
    err = np.max(np.abs(sig(t) - func(t)))
    assert err <= rtol * np.max(np.abs(func(t))), (count, err)
    if omega == 40.0 and rtol <= 1e-3:
        assert count > CALLABLE_LEAST_SAMPLES
    assert as_signal(func, "forcing", 0.0, 2.0).times.size == CALLABLE_SAMPLES
    assert as_signal(func, "forcing", 0.0, 2.0, 1e-10).times.size == CALLABLE_SAMPLES
