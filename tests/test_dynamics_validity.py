"""The pillar dynamics' ModelValidityWarning (issue 30, theory.md §14): each threshold
against the physical condition written in SI from its definition (the Stokes layer
sqrt(2 nu/omega) against the pillar's length, the bending wavelength against the diameter,
the section's radius of gyration times the wavenumber), just inside and just outside it."""

from __future__ import annotations

import math
import warnings

import pytest

import hairbed
from hairbed.dynamics import (
    ROTARY_INERTIA_LIMIT,
    SADER_WAVELENGTH_LIMIT,
    dynamics_validity,
    linearise_pillar,
    sader_drag_ratio,
)

# the PDMS pillar in water of the issue: L = 1 mm, a = 50 um, E = 1 MPa
LENGTH, RADIUS, YOUNGS, ETA, RHO_F = 1e-3, 50e-6, 1e6, 1e-3, 1e3
ZETA = 4.0 * math.pi * ETA / (math.log(2.0 * LENGTH / RADIUS) + 0.5)
T = ZETA * LENGTH**4 / (YOUNGS * math.pi * RADIUS**4 / 4.0)
REYNOLDS_SCALE = RHO_F * (2.0 * RADIUS) ** 2 / (4.0 * ETA * T)
SLENDER = LENGTH / RADIUS


def _messages(omega: float, mu: float = 0.0, unsteady: bool = False) -> tuple[str, ...]:
    return dynamics_validity([omega], mu, REYNOLDS_SCALE, SLENDER, unsteady_drag=unsteady)


def test_quasi_steady_drag_fails_where_the_stokes_layer_is_shorter_than_the_pillar() -> None:
    omega_si = 2.0 * ETA / (RHO_F * LENGTH**2)  # sqrt(2 nu/omega) = L [rad/s]
    edge = omega_si * T  # [1/T]
    assert not any("Stokes layer" in m for m in _messages(0.99 * edge))
    (msg,) = [m for m in _messages(1.01 * edge) if "Stokes layer" in m]
    assert "D4" in msg and "unsteady_drag" in msg
    # the layer in radii, sqrt(2 nu/omega)/a, at the resonance of the pillar (~2 kHz)
    omega = 2.0 * math.pi * 300.0
    layer = math.sqrt(2.0 * ETA / (RHO_F * omega)) / RADIUS
    (msg,) = [m for m in _messages(omega * T) if "Stokes layer" in m]
    assert f"{layer:.3g} radii" in msg


def test_rotary_inertia_limit() -> None:
    """Overdamped, |k|^4 = omega: (a |k|/2)^2 = limit at |k| = 2 sqrt(limit) L/a."""
    edge = (2.0 * math.sqrt(ROTARY_INERTIA_LIMIT) * SLENDER) ** 4
    assert not any("rotary" in m for m in _messages(0.99 * edge))
    assert any("rotary" in m and "D1" in m for m in _messages(1.01 * edge))
    # with inertia the wavenumber is |mu omega^2 - i omega|^(1/4)
    mu = 13.0
    k_edge = 2.0 * math.sqrt(ROTARY_INERTIA_LIMIT) * SLENDER
    # mu^2 omega^4 + omega^2 = k^8, a quadratic in omega^2
    om = math.sqrt((-1.0 + math.sqrt(1.0 + 4.0 * mu**2 * k_edge**8)) / (2.0 * mu**2))
    assert not any("rotary" in m for m in _messages(0.99 * om, mu))
    assert any("rotary" in m for m in _messages(1.01 * om, mu))


def test_sader_drag_wavelength_limit() -> None:
    """With the oscillating cylinder's drag, the wavelength 2 pi/|k| against
    SADER_WAVELENGTH_LIMIT diameters 2a, |k|^4 = |mu omega^2 - i omega D|, found by bisection
    in omega here."""
    mu = 2.0

    def diameters(om: float) -> float:
        d = complex(sader_drag_ratio(om, REYNOLDS_SCALE, SLENDER))
        k = abs(mu * om * om - 1j * om * d) ** 0.25 / LENGTH  # [1/m]
        return (2.0 * math.pi / k) / (2.0 * RADIUS)

    lo, hi = 1.0, 1e8
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if diameters(mid) > SADER_WAVELENGTH_LIMIT else (lo, mid)
    assert not any("Sader" in m for m in _messages(0.99 * lo, mu, True))
    assert any("Sader" in m for m in _messages(1.01 * hi, mu, True))
    # the Stokes-layer message is the quasi-steady drag's only
    assert not any("Stokes layer" in m for m in _messages(1e3, mu, True))


def test_frequency_response_with_sader_drag_warns() -> None:
    lin = linearise_pillar(hairbed.solve_pillar(5.0), mu=2.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lin.frequency_response([0.1, 1.0], unsteady_drag=(REYNOLDS_SCALE, SLENDER))
    with pytest.warns(hairbed.ModelValidityWarning) as record:
        lin.frequency_response([0.1, 1e4], unsteady_drag=(REYNOLDS_SCALE, SLENDER))
    texts = [str(w.message) for w in record]
    assert len(texts) == 2 and "rotary inertia" in texts[1] and "Sader" in texts[0]
    assert all(w.filename == __file__ for w in record)  # they point at the caller


def test_bad_inputs() -> None:
    with pytest.raises(ValueError, match=r"omega.*index 1"):
        dynamics_validity([1.0, -1.0], 0.0, 1.0, 20.0)
    with pytest.raises(ValueError, match="reynolds_scale"):
        dynamics_validity([1.0], 0.0, 0.0, 20.0)
    with pytest.raises(ValueError, match="slenderness"):
        dynamics_validity([1.0], 0.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="mu"):
        dynamics_validity([1.0], -1.0, 1.0, 20.0)
    assert dynamics_validity([], 0.0, 1.0, 20.0) == ()
