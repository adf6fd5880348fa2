"""simulate_beds (issue 30): a batch of porous beds in one call, on threads.

Each bed of the batch must be bitwise the run simulate_bed gives it alone (the batch adds
no numerics of its own: it shares the runs out and stacks them), and its end state the
static solver's (solve_porous, an independent code path: spectral collocation of the
steady equations) to the integrator's tolerance.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import BedBatch, simulate_bed, simulate_beds, step

TE = np.linspace(0.0, 8.0, 17)
OPTS: dict[str, Any] = {"rtol": 1e-7, "atol": 1e-9}


def test_each_bed_is_its_own_run_and_settles_to_the_static_state() -> None:
    theta0 = np.array([0.2, -0.1, 0.3])
    kappa = np.array([0.1, 1.0, 0.5])
    gamma = np.array([1.0, 0.5, 0.8])
    walls = [step(1.0), step(0.5), 2.0]
    runs = simulate_beds(theta0, kappa, 0.5, t_eval=TE, wall=walls, gamma=gamma, workers=2, **OPTS)
    assert isinstance(runs, BedBatch) and len(runs) == 3
    assert runs.success.tolist() == [True] * 3 and runs.tip_deflection.shape == (3, TE.size)
    assert runs.top == "wall" and runs.pump == "pressure"
    for i in range(3):
        one = simulate_bed(
            float(theta0[i]), float(kappa[i]), 0.5, t_eval=TE, wall=walls[i],
            gamma=float(gamma[i]), **OPTS,
        )  # fmt: skip
        for name in ("tip_deflection", "wall_stress", "flow_rate", "base_moment", "top_drive"):
            assert np.array_equal(getattr(runs, name)[i], getattr(one, name)), (i, name)
        assert runs.nsteps[i] == one.nsteps and runs.num[i] == one.num
        final = 2.0 if i == 2 else (1.0, 0.5)[i]
        st = hairbed.solve_porous(
            final, 0.5, float(theta0[i]), kappa=float(kappa[i]), gamma=float(gamma[i])
        )
        assert abs(runs.tip_deflection[i, -1] - float(st.tip_deflection)) < 1e-6
    # one thread gives the same bits
    again = simulate_beds(theta0, kappa, 0.5, t_eval=TE, wall=walls, gamma=gamma, **OPTS)
    assert np.array_equal(again.wall_stress, runs.wall_stress)
    ds = runs.to_xarray()
    assert ds["tip_deflection"].dims == ("bed", "t")
    assert ds["wall_stress"].attrs["units"] == "E I/(A L^2)"
    assert ds["t"].attrs["units"] == "T" and ds["kappa"].values.tolist() == kappa.tolist()


def test_bad_input_names_the_parameter_and_the_first_bed() -> None:
    with pytest.raises(ValueError, match=r"kappa must lie in \[1e-06, 1e\+06\], got -1.*bed 1"):
        simulate_beds(0.0, [0.1, -1.0, -2.0], 0.5, t_eval=TE)
    with pytest.raises(ValueError, match=r"theta0 must lie in \(-pi/2, pi/2\).*bed 2"):
        simulate_beds([0.0, 0.1, 2.0], 0.1, 0.5, t_eval=TE)
    with pytest.raises(ValueError, match=r"eps must be finite.*index 0"):
        simulate_beds(0.0, 0.1, [np.nan, 0.5], t_eval=TE)
    with pytest.raises(ValueError, match="womersley must be 0 or lie in"):
        simulate_beds(0.0, 0.1, 0.5, womersley=[0.0, 1e-9], t_eval=TE)
    with pytest.raises(ValueError, match="one length, got kappa 2, wall 3"):
        simulate_beds(0.0, [0.1, 0.2], 0.5, t_eval=TE, wall=[1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="scalar or 1-d"):
        simulate_beds(0.0, [[0.1]], 0.5, t_eval=TE)
    with pytest.raises(ValueError, match="at least one bed"):
        simulate_beds(0.0, [], 0.5, t_eval=TE)
    with pytest.raises(ValueError, match="workers"):
        simulate_beds(0.0, 0.1, 0.5, t_eval=TE, workers=0)
    with pytest.raises(TypeError, match=r"wall must be .*got str \(bed 1\)"):
        simulate_beds(0.0, [0.1, 0.2], 0.5, t_eval=[0.0, 0.1], wall=[1.0, "x"])
