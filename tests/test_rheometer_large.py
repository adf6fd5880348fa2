"""Large-amplitude oscillatory shear of the porous bed in time (issue 31 §2b).

References independent of the time integrator: at low frequency the static solver
(``solve_porous``'s top stress at the instantaneous forcing, the quasi-static rheology), with
the difference shrinking like omega; at small amplitude the linear bed's G* (tested against
mpmath in tests/test_rheometer_saos.py).
"""

from __future__ import annotations

import numpy as np
import pytest

from hairbed.rheometer import large_amplitude_shear, oscillatory_shear, pipkin_map


def test_low_frequency_is_the_quasi_static_rheology() -> None:
    diffs = []
    for om in (1e-3, 3e-3):
        # gamma0 = 1/omega: the forcing swings by +-1 (kappa = 1), far beyond the linear range
        r = large_amplitude_shear(om, 1.0 / om, eps=0.5, kappa=1.0, rtol=1e-10)
        assert r.success and r.periodic_error < 1e-6 and r.analysis is not None
        assert r.analysis.relative_intensity[2] > 1e-4  # the third harmonic of shear-thinning
        diffs.append(np.max(np.abs(r.stress - r.quasi_static_stress)) / np.max(np.abs(r.stress)))
    assert diffs[0] < 1e-5
    rate = np.log(diffs[1] / diffs[0]) / np.log(3.0)
    assert abs(rate - 1.0) < 0.1, (diffs, rate)


def test_small_amplitude_is_the_linear_bed_and_tilt_is_asymmetric() -> None:
    lin = oscillatory_shear([1.0], eps=0.5, kappa=1.0)
    g_lin = lin.storage[0, 0] + 1j * lin.loss[0, 0]
    pm = pipkin_map([1.0], [0.01, 1.0], eps=0.5, kappa=1.0, workers=2)
    assert np.all(pm.success)
    alone = pipkin_map([1.0], [0.01, 1.0], eps=0.5, kappa=1.0)  # the same runs, in process
    for name in ("storage", "loss", "third_harmonic", "large_viscosity"):
        assert np.array_equal(getattr(pm, name), getattr(alone, name)), name
    g_small = pm.storage[0, 0] + 1j * pm.loss[0, 0]
    assert abs(g_small - g_lin) < 1e-6 * abs(g_lin)
    assert pm.even_ratio[0, 1] < 1e-6  # the upright bed is symmetric
    assert pm.third_harmonic[0, 1] > 100 * pm.third_harmonic[0, 0]
    ds = pm.to_xarray()
    assert ds["storage"].dims == ("frequency", "amplitude")
    assert ds["storage"].attrs["units"] == "E I/(A L^2)"
    tilted = large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0, theta0=0.4)
    assert tilted.success and tilted.analysis is not None
    assert tilted.analysis.even_ratio > 1e-3  # with and against the grain differ


def test_first_harmonic_is_the_linear_modulus_to_1e_10() -> None:
    """G' + i G'' of the nonlinear periodic state -> the linear bed's G* like gamma0^2 (the
    quadratic part feeds harmonics 0 and 2, the first harmonic's change is O(gamma0^2));
    one Richardson step removes it: within 1e-10 (measured by the default collocation
    2.9e-15, by the transient at rtol 1e-12 1.4e-11; the deviations at gamma0 = 8e-3 and
    4e-3 are 2.9e-8 and 7.3e-9, ratio 4.00)."""
    lin = oscillatory_shear([1.0], eps=0.5, kappa=1.0)
    g_lin = lin.storage[0, 0] + 1j * lin.loss[0, 0]
    g = {}
    for g0 in (8e-3, 4e-3):
        r = large_amplitude_shear(1.0, g0, eps=0.5, kappa=1.0, rtol=1e-12, periodic_tol=1e-9)
        assert r.analysis is not None and r.periodic_error < 1e-8
        g[g0] = r.analysis.storage[0] + 1j * r.analysis.loss[0]
    dev = {k: abs(v - g_lin) / abs(g_lin) for k, v in g.items()}
    assert 3.8 < dev[8e-3] / dev[4e-3] < 4.2, dev
    extrapolated = (4.0 * g[4e-3] - g[8e-3]) / 3.0
    assert abs(extrapolated - g_lin) < 1e-10 * abs(g_lin)


def test_collocation_and_the_transient_baseline_agree() -> None:
    """method="transient" (Radau IIA until the start has decayed, the baseline) and the
    default collocation give the same periodic stress and analysis (measured 1.4e-9 at the
    transient's rtol 1e-9; 4.9e-11 at rtol 1e-11)."""
    col = large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0, periodic_tol=1e-8)
    tra = large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0, periodic_tol=1e-8,
                                method="transient", rtol=1e-10)  # fmt: skip
    assert col.success and tra.success
    assert col.method == "collocation" and tra.method == "transient"
    assert col.periods == 0 and tra.periods >= 3 and col.harmonics >= 12
    np.testing.assert_allclose(col.t, tra.t - tra.t[0], rtol=0, atol=1e-12)
    assert np.max(np.abs(col.stress - tra.stress)) < 1e-8 * np.max(np.abs(tra.stress))
    assert col.analysis is not None and tra.analysis is not None
    assert abs(col.analysis.storage[0] - tra.analysis.storage[0]) < 1e-8
    with pytest.raises(ValueError, match="method must be one of"):
        large_amplitude_shear(1.0, 1.0, eps=0.5, kappa=1.0, method="shooting")
