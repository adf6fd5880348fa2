"""Many pillars in one call: hairbed.dynamics.simulate_pillars (issue 30).

The reference is the one-pillar path, simulate_pillar, run pillar by pillar (a batch shares
the static solves and the threads, not the integration: the runs agree to the round-off of
their static starts, solved in one batch), and the static solver for where the runs end.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import simulate_pillar, simulate_pillars, sine, step


def test_a_batch_is_each_pillar_alone() -> None:
    lams = np.array([2.0, 15.0, -7.0, 30.0])
    th = np.array([0.0, 0.3, -0.4, 0.1])
    mus = np.array([0.0, 0.0, 0.0, 0.0])
    kw: dict[str, Any] = {"rtol": 1e-8, "atol": 1e-10}
    te = [0.0, 0.05, 3.0]
    runs = simulate_pillars([step(x) for x in lams], te, theta0=th, mu=mus, **kw)
    threaded = simulate_pillars([step(x) for x in lams], te, theta0=th, mu=mus, workers=2, **kw)
    assert len(runs) == lams.size == len(threaded)
    for i, run in enumerate(runs):
        alone = simulate_pillar(step(lams[i]), te, theta0=th[i], mu=mus[i], **kw)
        # the same run but for the static start's round-off (solved in one batch)
        assert run.success and np.allclose(run.theta, alone.theta, rtol=0.0, atol=1e-10)
        assert np.array_equal(threaded[i].theta, run.theta)  # threads change nothing
    # relaxed to their static states by t = 3
    st = hairbed.solve_pillar(lams, th)
    assert np.all(np.abs([r.tip_deflection[-1] for r in runs] - st.tip_deflection) <= 1e-8)


def test_a_batch_with_inertia() -> None:
    """Per-pillar mu: the inertia number reaches each run (mu = 0 and 13 on a slow sine
    from rest at its mean, N = 12: a short run)."""
    te = [0.0, 0.5, 1.0]
    kw: dict[str, Any] = {"num": 12, "rtol": 1e-6, "atol": 1e-8}
    runs = simulate_pillars(sine(3.0, 0.5, 1.0), te, mu=[0.0, 13.0], **kw)
    for mu, run in zip((0.0, 13.0), runs, strict=True):
        alone = simulate_pillar(sine(3.0, 0.5, 1.0), te, mu=mu, **kw)
        assert run.mu == mu and run.success
        assert np.allclose(run.theta, alone.theta, rtol=0.0, atol=1e-10)
    assert runs[0].tip_deflection[-1] != runs[1].tip_deflection[-1]


def test_one_drive_broadcasts() -> None:
    runs = simulate_pillars(step(5.0), [0.0, 2.0], theta0=[0.0, 0.2], rtol=1e-6, atol=1e-8)
    assert [r.theta0 for r in runs] == [0.0, 0.2]
    assert runs[0].forcing[-1] == runs[1].forcing[-1] == 5.0


def test_bad_batch_inputs() -> None:
    with pytest.raises(ValueError, match="one length"):
        simulate_pillars([step(1.0), step(2.0)], [0.0, 1.0], theta0=[0.0, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"theta0 .*\(pillar 1\)"):
        simulate_pillars(step(1.0), [0.0, 1.0], theta0=[0.0, 2.0])
    with pytest.raises(ValueError, match=r"mu .*\(pillar 0\)"):
        simulate_pillars(step(1.0), [0.0, 1.0], mu=[-1.0, 0.0])
    with pytest.raises(ValueError, match="workers"):
        simulate_pillars(step(1.0), [0.0, 1.0], workers=0)
    with pytest.raises(ValueError, match="theta0 must be a scalar or 1-d"):
        simulate_pillars(step(1.0), [0.0, 1.0], theta0=np.zeros((2, 2)))
    with pytest.raises(ValueError, match="at least one pillar"):
        simulate_pillars([], [0.0, 1.0])
