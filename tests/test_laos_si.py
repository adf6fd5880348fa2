"""Large-amplitude oscillatory shear of a HairBed in SI (hairbed.rheometer.bed_laos,
bed_pipkin_map; issue 31 §2b).

The SI wrappers must be the dimensionless run (hairbed.rheometer.large_amplitude_shear, whose
numerics are tested in test_rheometer_large.py) in the bed's scales. The scales are written
here again from their definitions (theory.md §13-§15), independently of hairbed._bed_scales:

    E I = E pi a^4/4,  A = (sqrt 3/2) s^2 (hexagonal packing of spacing s),
    T = zeta_perp L^4/(E I),  kappa = eta A/(zeta_perp L^2),  eps = L/H,
    alpha = rho L^2/(eta T),  omega2* = eta A L^2 v/(E I H),  sigma [Pa] = Q E I/(A L^2),

with zeta_perp, zeta_par the bed's drag law (HairBed.drag_coefficients: the drag law is not
what is tested here).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed.rheometer import bed_laos, bed_pipkin_map, large_amplitude_shear

BED: dict[str, Any] = {
    "length": 1e-3,
    "radius": 50e-6,
    "youngs_modulus": 1e6,
    "channel_height": 2e-3,
    "viscosity": 1.0,
    "spacing": 250e-6,
    "density": 1000.0,
    "base_angle": 0.3,  # tilted: even harmonics and a mean stress
}
FREQ, GAMMA0, SPEED = 0.1, 30.0, 1e-3  # [Hz], [-], [m/s]: I_3/I_1 ~ 1e-2, far from linear


def _scales() -> dict[str, float]:
    L, a, E, H = BED["length"], BED["radius"], BED["youngs_modulus"], BED["channel_height"]
    eta, s, rho = BED["viscosity"], BED["spacing"], BED["density"]
    ei = E * math.pi * a**4 / 4.0
    area = math.sqrt(3.0) / 2.0 * s**2
    zeta, zeta_par = hairbed.HairBed(**BED).drag_coefficients
    t = zeta * L**4 / ei
    return {
        "T": t,
        "kappa": eta * area / (zeta * L**2),
        "eps": L / H,
        "gamma": zeta_par / zeta,
        "alpha": rho * L**2 / (eta * t),
        "omega2": eta * area * L**2 * SPEED / (ei * H),
        "sigma": ei / (area * L**2),
    }


@pytest.fixture(scope="module")
def runs() -> tuple[Any, Any, dict[str, float]]:
    sc = _scales()
    si = bed_laos(hairbed.HairBed(**BED), FREQ, GAMMA0, SPEED)
    dim = large_amplitude_shear(
        2.0 * math.pi * FREQ * sc["T"], GAMMA0, eps=sc["eps"], kappa=sc["kappa"],
        theta0=BED["base_angle"], gamma=sc["gamma"], forcing=sc["omega2"], womersley=sc["alpha"],
    )  # fmt: skip
    return si, dim, sc


def test_si_is_the_dimensionless_run_in_independent_scales(runs: Any) -> None:
    si, dim, sc = runs
    assert si.success and dim.success and dim.analysis is not None
    a, s, t = dim.analysis, sc["sigma"], sc["T"]
    assert a.relative_intensity[2] > 1e-3 and a.even_ratio > 1e-3  # nonlinear, asymmetric
    for name, want in (("time_scale", t), ("modulus_scale", s), ("kappa", sc["kappa"]),
                       ("eps", sc["eps"]), ("womersley", sc["alpha"])):  # fmt: skip
        assert getattr(si, name) == pytest.approx(want, rel=1e-13), name
    # the integrator's rtol 1e-9 on inputs rounded apart (measured 5.7e-10)
    np.testing.assert_allclose(si.stress, dim.stress * s, rtol=1e-7)
    np.testing.assert_allclose(si.quasi_static_stress, dim.quasi_static_stress * s, rtol=1e-7)
    # the sampled period: N uniform samples of 1/f seconds, the strain and its rate in SI
    n = si.time.size
    np.testing.assert_allclose(si.time, np.arange(n) / (n * FREQ), rtol=1e-12, atol=1e-12)
    w = 2.0 * math.pi * FREQ
    np.testing.assert_allclose(si.strain, GAMMA0 * np.sin(w * si.time), rtol=0, atol=1e-9)
    np.testing.assert_allclose(si.strain_rate, GAMMA0 * w * np.cos(w * si.time), atol=1e-8)
    i1 = float(a.intensity[0]) * s
    np.testing.assert_allclose(si.storage, a.storage * s, rtol=0, atol=1e-7 * i1)
    np.testing.assert_allclose(si.loss, a.loss * s, rtol=0, atol=1e-7 * i1)
    np.testing.assert_allclose(si.relative_intensity[:8], a.relative_intensity[:8], atol=1e-7)
    np.testing.assert_allclose(si.elastic_chebyshev, a.elastic_chebyshev * s, atol=1e-7 * i1)
    np.testing.assert_allclose(
        si.viscous_chebyshev, a.viscous_chebyshev * s * t, atol=1e-7 * i1 * t
    )
    assert si.minimum_modulus == pytest.approx(a.minimum_modulus * s, rel=1e-6)
    assert si.large_modulus == pytest.approx(a.large_modulus * s, rel=1e-6)
    assert si.minimum_viscosity == pytest.approx(a.minimum_viscosity * s * t, rel=1e-6)
    assert si.large_viscosity == pytest.approx(a.large_viscosity * s * t, rel=1e-6)
    assert si.mean_stress == pytest.approx(a.mean_stress * s, rel=1e-6)
    # the pre-stress: the static bed's top stress at the steady forcing
    st = hairbed.solve_porous(sc["omega2"], sc["eps"], BED["base_angle"], kappa=sc["kappa"],
                              gamma=sc["gamma"])  # fmt: skip
    assert si.pre_stress == pytest.approx(float(st.tip_stress) * s, rel=1e-12)
    # the Lissajous curves in SI, summed from the harmonics, pass through the samples
    liss = si.lissajous(n + 1)
    np.testing.assert_allclose(liss["total"][:-1], si.stress, rtol=0, atol=1e-6 * i1)
    np.testing.assert_allclose(liss["strain_rate"][:-1], si.strain_rate, atol=1e-9)


def test_si_files_and_pipkin_map(runs: Any) -> None:
    xr = pytest.importorskip("xarray")
    si = runs[0]
    ds = si.to_xarray()
    assert isinstance(ds, xr.Dataset)
    units = {"stress": "Pa", "strain_rate": "s-1", "elastic_chebyshev": "Pa",
             "viscous_chebyshev": "Pa s", "storage": "Pa", "relative_intensity": "1"}  # fmt: skip
    for key, unit in units.items():
        assert ds[key].attrs["units"] == unit and ds[key].attrs["long_name"]
    assert ds["time"].attrs["units"] == "s"
    # one cell of the map is the same run as bed_laos
    pm = bed_pipkin_map(hairbed.HairBed(**BED), [FREQ], [GAMMA0], SPEED)
    assert pm.success.all()
    assert pm.storage[0, 0] == si.storage[0] and pm.large_viscosity[0, 0] == si.large_viscosity
    assert pm.third_harmonic[0, 0] == si.relative_intensity[2]
    dm = pm.to_xarray()
    assert dm["large_viscosity"].attrs["units"] == "Pa s"
    assert dm["frequency"].attrs["units"] == "Hz"


@pytest.mark.parametrize(
    ("args", "kwargs", "words"),
    [
        ((0.0, 1.0), {}, "frequency must be > 0 [Hz]"),
        ((1e12, 1.0), {}, "frequency must lie in"),
        ((math.nan, 1.0), {}, "frequency"),
        ((1.0, -1.0), {}, "strain_amplitude must be > 0"),
        ((1.0, 1.0, math.inf), {}, "speed"),
        ((1e5, 1e6), {}, "too fast for this bed"),
        ((1.0, 1.0), {"samples": 3}, "samples"),
    ],
)
def test_bad_input_is_named(args: tuple[Any, ...], kwargs: dict[str, Any], words: str) -> None:
    with pytest.raises(ValueError, match=words.replace("[", r"\[").replace("]", r"\]")):
        bed_laos(hairbed.HairBed(**BED), *args, **kwargs)


def test_bad_map_input_is_named() -> None:
    bed = hairbed.HairBed(**BED)
    with pytest.raises(ValueError, match=r"frequencies must be > 0 \[Hz\], got -1.0 .*index 1"):
        bed_pipkin_map(bed, [1.0, -1.0], [1.0])
    with pytest.raises(ValueError, match=r"strain_amplitudes .*index 0"):
        bed_pipkin_map(bed, [1.0], [0.0])
    with pytest.raises(TypeError, match="bed must be a HairBed"):
        bed_laos("bed", 1.0, 1.0)  # type: ignore[arg-type]
