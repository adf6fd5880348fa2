"""The weak-forcing series kernel against mpmath solutions of the boundary value problem.

theta'' = -eps2 cos(theta), theta(0) = theta0, theta'(1) = 0; x' = sin(theta), z' = cos(theta).
The reference is the same regular perturbation series, computed numerically in mpmath at 50
digits to 15 orders (the orders decay like 0.4^k, so the truncation is below 1e-43 relative for
eps2 <= 3e-3), itself checked against an independent Taylor-series shooting solution of the
boundary value problem.
"""

from __future__ import annotations

import math
from functools import cache

import mpmath as mp
import pytest

from hairbed._core._kernels.weak import WEAK_MAX, WEAK_ORDER, weak_shape


def _horner(coeffs, x):
    """Polynomial with coefficients in descending powers (mpmath.polyval's order, without its
    deprecation of that order)."""
    acc = mp.mpf(0)
    for c in coeffs:
        acc = acc * x + c
    return acc


DPS = 50
ORDERS = 15
EPS2 = (1e-300, 1e-30, 1e-12, 1e-6, 1e-4, WEAK_MAX)
THETA0 = (0.0, 0.3, -0.7, 1.2, -1.5, 1.5707)
SIGMA = (0.0, 0.1, 0.5, 0.9, 1.0)
RTOL = 1e-14
#: Absolute slack for results in the subnormal range (20 subnormal ulps).
TINY = 20 * 2.0**-1074


# ------------------------------------------------------------------------------------------
# mpmath reference: the series, numerically, on sigma-coefficient lists
# ------------------------------------------------------------------------------------------


def _mul(p: list, q: list) -> list:
    r = [mp.mpf(0)] * (len(p) + len(q) - 1)
    for i, x in enumerate(p):
        for j, y in enumerate(q):
            r[i + j] += x * y
    return r


def _lin(f, p: list, g, q: list) -> list:
    n = max(len(p), len(q))
    p = p + [mp.mpf(0)] * (n - len(p))
    q = q + [mp.mpf(0)] * (n - len(q))
    return [f * x + g * y for x, y in zip(p, q)]


def _integ(p: list) -> list:
    return [mp.mpf(0)] + [x / (i + 1) for i, x in enumerate(p)]


@cache
def _series(theta0: float) -> tuple[list, list, list]:
    """theta_k, dx_k, dz_k for k = 1 .. ORDERS: sigma-coefficients, lowest power first.

    cos(delta) = sum eps2^k C_k, sin(delta) = sum eps2^k S_k with k C_k = -sum j theta_j
    S_{k-j}, k S_k = sum j theta_j C_{k-j}; theta_k'' = -(c C_{k-1} - s S_{k-1}).
    """
    with mp.workdps(DPS):
        t0 = mp.mpf(theta0)
        s, c = mp.sin(t0), mp.cos(t0)
        theta, dx, dz = [], [], []
        cos_k, sin_k = [[mp.mpf(1)]], [[mp.mpf(0)]]
        for k in range(1, ORDERS + 1):
            slope = _integ(_lin(-c, cos_k[k - 1], s, sin_k[k - 1]))
            slope[0] = -mp.fsum(slope)  # theta_k'(1) = 0
            theta.append(_integ(slope))  # theta_k(0) = 0
            acc_c, acc_s = [mp.mpf(0)], [mp.mpf(0)]
            for j in range(1, k + 1):
                acc_c = _lin(1, acc_c, j, _mul(theta[j - 1], sin_k[k - j]))
                acc_s = _lin(1, acc_s, j, _mul(theta[j - 1], cos_k[k - j]))
            cos_k.append([-x / k for x in acc_c])
            sin_k.append([x / k for x in acc_s])
            dx.append(_integ(_lin(s, cos_k[k], c, sin_k[k])))
            dz.append(_integ(_lin(c, cos_k[k], -s, sin_k[k])))
    return theta, dx, dz


def reference(eps2: float, theta0: float, sigma: float) -> tuple[mp.mpf, mp.mpf, mp.mpf]:
    """(theta - theta0, x - sigma s, z - sigma c) from the mpmath series."""
    with mp.workdps(DPS):
        e, t = mp.mpf(eps2), mp.mpf(sigma)
        return tuple(
            mp.fsum(e ** (k + 1) * _horner(p[::-1], t) for k, p in enumerate(orders))
            for orders in _series(theta0)
        )


# ------------------------------------------------------------------------------------------
# independent check of the reference: Taylor-series shooting on theta'(0)
# ------------------------------------------------------------------------------------------


def _taylor_ivp(eps2, theta0, slope0, sigmas, order=30, h="0.5"):
    """theta, theta', x, z at each sigma of ``sigmas`` (increasing), Taylor steps of <= h."""
    h = mp.mpf(h)
    y, dy, x, z = mp.mpf(theta0), slope0, mp.mpf(0), mp.mpf(0)
    pos, out = mp.mpf(0), []
    for target in sigmas:
        target = mp.mpf(target)
        while pos < target:
            step = min(h, target - pos)
            yc = [y, dy] + [mp.mpf(0)] * order
            cc = [mp.cos(y)] + [mp.mpf(0)] * order
            ss = [mp.sin(y)] + [mp.mpf(0)] * order
            for k in range(order - 1):
                yc[k + 2] = -eps2 * cc[k] / ((k + 1) * (k + 2))
                d = [(k - j + 1) * yc[k - j + 1] for j in range(k + 1)]
                cc[k + 1] = -mp.fsum(ss[j] * d[j] for j in range(k + 1)) / (k + 1)
                ss[k + 1] = mp.fsum(cc[j] * d[j] for j in range(k + 1)) / (k + 1)
            dyc = [(k + 1) * yc[k + 1] for k in range(order)]
            x += _horner([ss[k] / (k + 1) for k in range(order - 1)][::-1] + [0], step)
            z += _horner([cc[k] / (k + 1) for k in range(order - 1)][::-1] + [0], step)
            y = _horner(yc[:order][::-1], step)
            dy = _horner(dyc[: order - 1][::-1], step)
            pos += step
        out.append((y, dy, x, z))
    return out


def shooting(eps2: float, theta0: float, sigmas) -> list[tuple[mp.mpf, mp.mpf, mp.mpf]]:
    """(theta - theta0, x - sigma s, z - sigma c) by shooting on theta'(0) (secant method)."""
    with mp.workdps(DPS):
        e = mp.mpf(eps2)

        def tip_slope(p0):
            return _taylor_ivp(e, theta0, p0, [1])[0][1]

        guess = e * mp.cos(mp.mpf(theta0))  # first order: theta'(0) = eps2 c
        p0 = mp.findroot(tip_slope, (guess, guess * (1 + mp.mpf("1e-3"))), solver="secant")
        t0 = mp.mpf(theta0)
        s, c = mp.sin(t0), mp.cos(t0)
        prof = _taylor_ivp(e, theta0, p0, sigmas)
        return [(y - t0, x - sg * s, z - sg * c) for sg, (y, _, x, z) in zip(sigmas, prof)]


@pytest.mark.parametrize(("eps2", "theta0"), [(WEAK_MAX, 0.0), (WEAK_MAX, -1.5), (1e-4, 1.2)])
def test_reference_series_matches_shooting(eps2, theta0):
    sigmas = [0.1, 0.5, 0.9, 1.0]
    for sg, ode in zip(sigmas, shooting(eps2, theta0, sigmas)):
        for a, b in zip(reference(eps2, theta0, sg), ode):
            assert abs(a - b) <= mp.mpf("1e-35") * abs(b)


# ------------------------------------------------------------------------------------------
# the kernel
# ------------------------------------------------------------------------------------------


def _rel_errors(eps2: float, theta0: float) -> list[float]:
    s, c = math.sin(theta0), math.cos(theta0)
    worst = []
    for sg in SIGMA:
        got = weak_shape(sg, eps2, s, c)
        if sg == 0.0:
            assert got == (0.0, 0.0, 0.0)
            continue
        for value, ref in zip(got, reference(eps2, theta0, sg)):
            assert ref != 0
            err = abs(mp.mpf(value) - ref)
            assert err <= RTOL * abs(ref) + TINY, (sg, value, ref)
            if abs(ref) > 2.0**-1022:
                worst.append(float(err / abs(ref)))
    return worst


@pytest.mark.parametrize("eps2", EPS2)
def test_weak_shape_relative_accuracy(eps2):
    worst = [e for theta0 in THETA0 for e in _rel_errors(eps2, theta0)]
    assert max(worst) <= RTOL


def test_weak_max_is_within_the_documented_order():
    # eps2^N with N = WEAK_ORDER and the decay ~ 0.4^k of the coefficients: ~1e-17 at WEAK_MAX
    assert WEAK_ORDER == 6
    assert 1e-4 <= WEAK_MAX <= 1e-2


def test_clamp_vertical_to_the_flow_is_exact():
    # c = 0: theta = pi/2 solves the problem, all displacements vanish
    assert weak_shape(0.7, WEAK_MAX, 1.0, 0.0) == (0.0, 0.0, 0.0)


def test_dz_at_theta0_zero_starts_at_second_order():
    # s = 0: dz = -eps2^2 sigma^3 (20 - 15 sigma + 3 sigma^2) / 120 + O(eps2^4), no first order
    for eps2 in (1e-100, 1e-20, 1e-8):
        sg = 0.5
        _, _, dz = weak_shape(sg, eps2, 0.0, 1.0)
        lead = -(eps2**2) * sg**3 * (20 - 15 * sg + 3 * sg**2) / 120
        assert dz == pytest.approx(lead, rel=1e-15)


def test_dz_sign_change_band_is_accurate_in_absolute_terms():
    # for -O(eps2) < s < 0 dz changes sign: its error is a few ulps of the size of its terms
    eps2, sg = 1e-3, 0.6
    z10 = -(sg**2) * (3 - sg) / 6
    z01 = -(sg**3) * (20 - 15 * sg + 3 * sg**2) / 120
    for theta0 in (-1e-4, -2e-4):
        s, c = math.sin(theta0), math.cos(theta0)
        scale = abs(c) * (abs(eps2 * s * z10) + abs(eps2**2 * c**2 * z01))
        _, _, dz = weak_shape(sg, eps2, s, c)
        assert abs(mp.mpf(dz) - reference(eps2, theta0, sg)[2]) <= 1e-15 * scale
