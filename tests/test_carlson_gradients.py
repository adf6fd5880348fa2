"""The gradients of R_F and R_D (hairbed._carlson_gradients) against mpmath.

mpmath differentiates its own elliptic integrals at 40 digits (an independent reference); the
points include the near-coincident arguments x -> z of a barely bent hair, where the closed
forms of the partials (DLMF 19.18) difference two nearly equal R_D.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from hairbed._carlson_gradients import rd_gradient, rf_gradient, rf_rd_gradient

POINTS = [
    (0.3, 1.2, 2.0),
    (1e-12, 0.5, 1.0000001e-12),  # x -> z, both small: weak forcing of the physical branch
    (0.7, 0.7, 0.7000001),  # all three nearly equal
    (1e-30, 1.0, 1e-20),  # widely spread
    (5.0, 1e-8, 3.0),
    (2e-9, 0.4, 2.00000004e-9),
    (1e3, 1e-3, 1.0),
]


def _rf_of_both(x, y, z):
    return rf_rd_gradient(x, y, z)[0]


def _rd_of_both(x, y, z):
    return rf_rd_gradient(x, y, z)[1]


@pytest.mark.parametrize(
    ("numpy_fn", "mp_fn"),
    [
        (rf_gradient, mp.elliprf),
        (rd_gradient, mp.elliprd),
        (_rf_of_both, mp.elliprf),  # one duplication for both: R_F takes R_D's extra steps
        (_rd_of_both, mp.elliprd),
    ],
)
def test_value_and_gradient_against_mpmath(numpy_fn, mp_fn) -> None:
    x, y, z = (np.array(a) for a in zip(*POINTS))
    value, grad = numpy_fn(x, y, z)
    with mp.workdps(40):
        for i, args in enumerate(POINTS):
            ref = mp_fn(*args)
            assert abs(value[i] - ref) <= 2e-15 * abs(ref), (i, args)
            for k in range(3):

                def along(u, k=k, args=args):
                    a = list(args)
                    a[k] = u
                    return mp_fn(*a)

                ref_k = mp.diff(along, args[k])
                assert abs(grad[k][i] - ref_k) <= 3e-15 * abs(ref_k), (i, k, args)


def test_identities() -> None:
    """Euler's relation for the homogeneous functions, and dR_F/dz = -R_D(x, y, z)/6."""
    rng = np.random.default_rng(7)
    x, y, z = rng.uniform(1e-6, 3.0, (3, 200))
    f, gf = rf_gradient(x, y, z)
    d, gd = rd_gradient(x, y, z)
    np.testing.assert_allclose(x * gf[0] + y * gf[1] + z * gf[2], -0.5 * f, rtol=1e-14)
    np.testing.assert_allclose(x * gd[0] + y * gd[1] + z * gd[2], -1.5 * d, rtol=1e-14)
    np.testing.assert_allclose(gf[2], -d / 6.0, rtol=1e-14)


def test_shapes_broadcast() -> None:
    v, g = rf_gradient(np.full((2, 3), 0.5), np.array(1.0), np.array([1.0, 2.0, 3.0]))
    assert v.shape == (2, 3) and all(gk.shape == (2, 3) for gk in g)
