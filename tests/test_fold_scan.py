"""The fold scan of the twirling branches finds the same folds on its coarse production grid as
on a grid 16 times finer, at random inputs and densely across the windows where folds appear
(near theta0 = -pi/2, where pairs of folds are born at a cusp)."""

from __future__ import annotations

import numpy as np
import pytest

from hairbed._core._kernels import roots

FINE = 1.0 / 32.0


def _counts(eps, theta0, sign, n, step):
    folds = np.full(roots.MAX_FOLDS, np.nan)
    out = np.empty((len(eps), roots.MAX_FOLDS + 1))
    for i, (e, t) in enumerate(zip(eps, theta0)):
        c = roots.scan_folds_step(float(e), float(t), sign, n, folds, step, np.empty(0))
        out[i, 0] = c
        out[i, 1:] = np.where(np.arange(roots.MAX_FOLDS) < c, folds, np.nan)
    return out


def _same(a, b):
    np.testing.assert_array_equal(a[:, 0], b[:, 0])  # the number of folds
    np.testing.assert_allclose(a[:, 1:], b[:, 1:], rtol=1e-7, atol=1e-7, equal_nan=True)


@pytest.mark.parametrize("sign,n", [(1, 1), (1, 2), (-1, 0), (-1, 1), (-1, 3)])
def test_coarse_scan_matches_fine_scan_at_random_inputs(sign, n):
    rng = np.random.default_rng(100 * n + (sign > 0))
    size = 300
    eps = rng.uniform(0.0, 0.999, size)
    theta0 = np.concatenate(
        [
            rng.uniform(-1.5707963, 1.5707963, size // 2),
            -np.pi / 2 + 10.0 ** rng.uniform(-15.0, -1.0, size - size // 2),
        ]
    )
    _same(_counts(eps, theta0, sign, n, roots._SCAN_STEP), _counts(eps, theta0, sign, n, FINE))


@pytest.mark.parametrize("theta0", [-1.5707963, -1.5707, -1.57, -1.56, -1.5])
@pytest.mark.parametrize("sign,n", [(1, 1), (-1, 1)])
def test_coarse_scan_matches_fine_scan_across_eps(theta0, sign, n):
    eps = np.linspace(0.0, 0.999, 400)
    theta = np.full(eps.size, theta0)
    _same(_counts(eps, theta, sign, n, roots._SCAN_STEP), _counts(eps, theta, sign, n, FINE))
