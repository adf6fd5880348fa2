"""LAOS analysis (issue 31 §2b) on synthetic signals whose coefficients are known in closed form.

The material is sigma = s0 + G g + c g^3 + eta gd + d gd^3 + b g gd + k g^2 with the strain
g = g0 sin(theta), gd = g0 omega cos(theta): sin^3 = (3 sin - sin 3)/4 and cos^3 = (3 cos +
cos 3)/4 give the harmonics by hand, and by definition G'_M = G, G'_L = G + c g0^2,
eta'_M = eta, eta'_L = eta + d gd0^2 (Ewoldt, Hosoi & McKinley 2008); the b and k terms are
the even (asymmetric) part: (b g0^2 omega/2) sin 2 theta and (k g0^2/2)(1 - cos 2 theta).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hairbed.rheometer import analyse_laos

G, C, ETA, D, B, K, S0 = 2.0, -0.7, 1.3, 0.25, 0.4, -0.9, 0.05
G0, OMEGA = 0.8, 3.7


def _material(g, gd, even=True):
    out = G * g + C * g**3 + ETA * gd + D * gd**3
    if even:
        out = out + S0 + B * g * gd + K * g * g
    return out


def _record(per=48, periods=1, t0=0.3, phi=0.6, even=True):
    size = per * periods
    t = t0 + np.arange(size) * (2 * math.pi * periods / OMEGA) / size
    th = OMEGA * t + phi
    g = G0 * np.sin(th)
    gd = G0 * OMEGA * np.cos(th)
    return t, g, _material(g, gd, even)


def test_harmonics_and_chebyshev_closed_form() -> None:
    t, g, s = _record(periods=3)
    r = analyse_laos(t, g, s, periods=3)
    gd0 = G0 * OMEGA
    assert r.status == 0 and r.success and r.message == "ok"
    assert r.omega == pytest.approx(OMEGA, rel=1e-13)
    assert r.strain_amplitude == pytest.approx(G0, rel=1e-13)
    assert r.strain_phase == pytest.approx(0.6, abs=1e-13)
    storage = {1: G + 0.75 * C * G0**2, 2: B * G0 * OMEGA / 2, 3: -C * G0**2 / 4}
    loss = {1: ETA * OMEGA + 0.75 * D * OMEGA * gd0**2, 2: -K * G0 / 2, 3: D * OMEGA * gd0**2 / 4}
    for n in range(1, r.harmonic.size + 1):
        assert r.storage[n - 1] == pytest.approx(storage.get(n, 0.0), abs=1e-13)
        assert r.loss[n - 1] == pytest.approx(loss.get(n, 0.0), abs=1e-13)
    assert r.mean_stress == pytest.approx(S0 + K * G0**2 / 2, abs=1e-14)
    mod = {n: math.hypot(storage[n], loss[n]) for n in (1, 2, 3)}
    assert r.relative_intensity[2] == pytest.approx(mod[3] / mod[1], rel=1e-12)
    assert r.relative_intensity[1] == pytest.approx(mod[2] / mod[1], rel=1e-12)
    assert r.phase[0] == pytest.approx(math.atan2(loss[1], storage[1]), abs=1e-13)
    assert r.phase[1] == pytest.approx(math.atan2(loss[2], storage[2]), abs=1e-12)
    # Ewoldt's coefficients and measures
    assert r.elastic_chebyshev[:2] == pytest.approx(
        [G + 0.75 * C * G0**2, C * G0**2 / 4], abs=1e-13
    )
    assert r.viscous_chebyshev[:2] == pytest.approx(
        [ETA + 0.75 * D * gd0**2, D * gd0**2 / 4], abs=1e-13
    )
    assert r.minimum_modulus == pytest.approx(G, abs=1e-13)
    assert r.large_modulus == pytest.approx(G + C * G0**2, abs=1e-13)
    assert r.minimum_viscosity == pytest.approx(ETA, abs=1e-13)
    assert r.large_viscosity == pytest.approx(ETA + D * gd0**2, abs=1e-13)
    assert r.stiffening_ratio == pytest.approx(C * G0**2 / (G + C * G0**2), abs=1e-13)
    assert r.thickening_ratio == pytest.approx(D * gd0**2 / (ETA + D * gd0**2), abs=1e-13)
    even = math.hypot(mod[2] * G0, S0 + K * G0**2 / 2) / (mod[1] * G0)
    assert r.even_ratio == pytest.approx(even, rel=1e-12)
    assert r.nonperiodic < 1e-13
    # Lissajous-Bowditch curves: the elastic stress is sigma'(gamma), the viscous sigma''(gd)
    cur = r.lissajous(101)
    g, gd = cur["strain"], cur["strain_rate"]
    assert np.allclose(cur["elastic"], G * g + C * g**3, rtol=0, atol=1e-13)
    assert np.allclose(cur["viscous"], ETA * gd + D * gd**3, rtol=0, atol=1e-12)
    assert np.allclose(cur["asymmetric"], S0 + B * g * gd + K * g * g, rtol=0, atol=1e-13)
    assert np.allclose(cur["total"], _material(g, gd), rtol=0, atol=1e-12)


def test_symmetric_material_status_and_bad_input() -> None:
    # an odd material has no even harmonics and no mean
    t, g, s = _record(even=False, phi=0.0, t0=0.0)
    r = analyse_laos(t, g, s)
    assert r.even_ratio < 1e-14 and abs(r.mean_stress) < 1e-14
    # a decaying transient over two periods is not periodic (status 1)
    t2, g2, s2 = _record(periods=2)
    r2 = analyse_laos(t2, g2, s2 + 0.1 * np.exp(-t2), periods=2)
    assert r2.status == 1 and not r2.success and r2.nonperiodic > 1e-3
    # a sharp stress sampled coarsely: its highest harmonic is not negligible (status 2)
    t3, g3, _ = _record(per=16, phi=0.0, t0=0.0)
    r3 = analyse_laos(t3, g3, np.tanh(20 * g3))
    assert r3.status == 2 and "aliased" in r3.message
    with pytest.raises(ValueError, match="uniformly sampled.*index 4"):
        tt = t.copy()
        tt[5] += 1e-3
        analyse_laos(tt, g, s)
    with pytest.raises(ValueError, match="strain must be gamma0 sin"):
        analyse_laos(t, g + 0.01 * g**2, s)
    with pytest.raises(ValueError, match="one length"):
        analyse_laos(t, g, s[:-1])
    with pytest.raises(ValueError, match="stress"):
        analyse_laos(t, g, np.where(t > 1, np.nan, s))
    with pytest.raises(ValueError, match="periods must divide"):
        analyse_laos(t, g, s, periods=5)
    with pytest.raises(ValueError, match="num_harmonics must be an integer in \\[1, 23\\]"):
        analyse_laos(t, g, s, num_harmonics=24)
    with pytest.raises(ValueError, match="strain must oscillate"):
        analyse_laos(t, 0 * g, s)
