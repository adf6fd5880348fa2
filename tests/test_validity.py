"""Validity of the model: density, the gap's Reynolds number, ModelValidityWarning."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import hairbed
from hairbed import HairBed, ModelValidityWarning


def water_sensor(**kw: float) -> HairBed:
    """A short stiff pillar in a 1 mm water channel."""
    base = dict(
        length=1e-4,
        radius=20e-6,
        youngs_modulus=1e9,
        channel_height=1e-3,
        viscosity=1e-3,
        spacing=200e-6,
        density=1000.0,
    )
    return HairBed(**{**base, **kw})


def test_fast_flow_in_water_warns() -> None:
    bed = water_sensor()
    with pytest.warns(ModelValidityWarning, match="Reynolds number of the gap flow"):
        state = bed.deform(17.0)
    gap = bed.channel_height - state.tip_height
    assert state.reynolds_number == pytest.approx(1000.0 * 17.0 * gap / 1e-3, rel=1e-14)
    assert 1.5e4 < state.reynolds_number < 1.7e4  # about 17,000 on the whole channel height


def test_slow_flow_does_not_warn() -> None:
    bed = water_sensor()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelValidityWarning)
        state = bed.deform(1e-4)
    assert state.reynolds_number == pytest.approx(0.1 * (1 - state.tip_height / 1e-3), rel=1e-12)


def test_no_density_no_reynolds_number() -> None:
    bed = water_sensor(density=None)  # type: ignore[arg-type]
    with warnings.catch_warnings():
        warnings.simplefilter("error", ModelValidityWarning)
        state = bed.deform(np.array([1e-4, 17.0]))
    assert np.all(np.isnan(state.reynolds_number))


def test_array_warning_counts_points() -> None:
    with pytest.warns(ModelValidityWarning, match="at 2 point"):
        water_sensor().deform(np.array([1e-4, 5.0, -17.0]))


def test_density_is_validated() -> None:
    with pytest.raises(ValueError, match="density"):
        water_sensor(density=-1.0)
    with pytest.raises(ValueError, match="density"):
        water_sensor(density=math.nan)


def test_tip_displacement_in_metres() -> None:
    bed = water_sensor(base_angle=0.3, density=None)  # type: ignore[arg-type]
    v = np.array([1e-3, 0.5, -0.5])
    state = bed.deform(v)
    rest = bed.length * math.sin(0.3)
    # along +x: the deflection minus its rest value (for v < 0 too: the same rest position),
    # exact relative to itself
    x1 = np.asarray(state.tip_deflection)
    assert state.tip_displacement == pytest.approx(x1 - rest, rel=1e-6)
    assert np.sign(state.tip_displacement).tolist() == [1.0, 1.0, -1.0]
    weak = bed.deform(1e-12).tip_displacement
    # a point load at the tip: F L^3 cos^2 / (3 E I) to first order
    w = bed.omega2(1e-12) / (1 - bed.eps * math.cos(0.3))
    assert weak == pytest.approx(bed.length * w * math.cos(0.3) ** 2 / 3, rel=1e-6)


def test_warning_is_exported() -> None:
    assert issubclass(hairbed.ModelValidityWarning, UserWarning)
    assert "ModelValidityWarning" in hairbed.__all__
