"""Small-amplitude oscillatory shear of the porous bed (issue 31 §2a) against mpmath.

The strain is the top wall's displacement over H, so the wall speed per unit strain is
i omega H and G* = i omega (top stress per unit V)/eps in §13's load units, with the stored
transfer functions of tests/data/bed_linear_mpmath.json (per unit V [L/T]) and, at the lead
crossover found by the workflow, the generator's own shooting (mpmath) at that frequency.
"""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest

from hairbed.rheometer import bed_moduli, large_amplitude_shear, oscillatory_shear

HERE = Path(__file__).resolve().parent
DATA = json.loads((HERE / "data" / "bed_linear_mpmath.json").read_text())


def _generator():
    spec = importlib.util.spec_from_file_location(
        "generate_bed_linear", HERE / "reference" / "generate_bed_linear.py"
    )
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_moduli_against_mpmath() -> None:
    case = next(
        c for c in DATA["responses"] if (c["kappa"], c["alpha"], c["mu"]) == (1.0, 1.0, 1.0)
    )
    rows = [r for r in case["responses"] if 0.0 < r["omega"] <= 10.0]
    om = np.array([r["omega"] for r in rows])
    eps = case["eps"]
    res = oscillatory_shear(om, eps=eps, kappa=1.0, inertia=1.0, womersley=1.0)
    want = 1j * om * np.array([complex(*r["wall"]["top_stress"]) for r in rows]) / eps
    got = res.storage[:, 0] + 1j * res.loss[:, 0]
    assert np.max(np.abs(got - want) / np.abs(want)) < 1e-10
    assert np.all(res.status == 0) and res.pre_stress[0] == 0.0
    # the fluid's inertia leads: G' < 0 at every frequency here
    assert np.all(res.storage < 0) and np.all(res.lead > 0)


def test_lead_crossover_and_prestress() -> None:
    """Hair inertia (mu = 1, quasi-steady fluid): the stress lags the wall's speed at low
    frequency (elastic hairs) and leads it above the crossover; at the crossover found, the
    mpmath G' vanishes."""
    om = np.logspace(-1, 2, 7)
    res = oscillatory_shear(om, [0.0, 2.0], eps=0.5, kappa=1.0, inertia=1.0)
    wc = float(res.lead_crossover[0])
    assert 1.0 < wc < 30.0
    assert res.storage[0, 0] > 0 and res.storage[-1, 0] < 0
    gen = _generator()
    with mp.workdps(40):
        top = gen.method1(1.0, 0.5, 0.0, 1.0, wc, 1, 0)["top_stress"]
    g = 1j * wc * complex(top) / 0.5
    assert abs(g.real) < 1e-10 * abs(g)
    # a pre-stressed bed: its state's stress, its own crossover
    assert res.pre_stress[1] > 2.0 and math.isfinite(res.lead_crossover[1])
    assert res.lead_crossover[1] != pytest.approx(wc, rel=1e-6)
    ds = res.to_xarray()
    assert ds["storage"].dims == ("frequency", "pre_stress")
    assert (
        ds["storage"].attrs["units"] == "E I/(A L^2)" and ds["frequency"].attrs["units"] == "1/T"
    )
    # without inertia no lead: G' >= 0 everywhere, no crossover
    calm = oscillatory_shear(om, 2.0, eps=0.5, kappa=1.0, theta0=0.3)
    assert np.all(calm.storage > 0) and np.all(calm.lead < 0)
    assert np.all(np.isnan(calm.lead_crossover))
    with pytest.raises(ValueError, match="omega must be finite and > 0.*index 0"):
        oscillatory_shear([0.0, 1.0], eps=0.5, kappa=1.0)
    with pytest.raises(ValueError, match="omega must increase"):
        oscillatory_shear([2.0, 1.0], eps=0.5, kappa=1.0)
    with pytest.raises(ValueError, match="eps"):
        oscillatory_shear([1.0], eps=1.5, kappa=1.0)


def test_si_moduli_of_a_hair_bed() -> None:
    """bed_moduli in SI: at low frequency G''/(2 pi f) is the bed's effective viscosity,
    the steady wall stress per shear rate tau H/v of HairBed.wall_shear_stress (the units
    module's own conversions and the static porous solver)."""
    import warnings

    import hairbed
    from hairbed.rheometer import bed_moduli

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bed = hairbed.HairBed(
            length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
            viscosity=1e-3, spacing=4e-4, density=1000.0, model="porous",
        )  # fmt: skip
        v = 1e-7
        eta_eff = float(bed.wall_shear_stress(v)) * bed.channel_height / v
    res = bed_moduli(bed, [1e-4, 1e-3, 10.0], hair_density=1100.0)
    slope = res.loss[:2, 0] / (2 * np.pi * res.frequency[:2])
    assert abs(slope[0] / eta_eff - 1.0) < 1e-6
    assert abs(slope[1] / eta_eff - 1.0) < 1e-4
    assert np.all(res.success) and res.modulus_scale > 0 and res.time_scale > 0
    # water's inertia (alpha about 290): the stress leads the wall's speed
    assert res.storage[-1, 0] < 0 and res.lead[-1, 0] > 0
    assert res.to_xarray()["storage"].attrs["units"] == "Pa"
    with pytest.raises(TypeError, match="HairBed"):
        bed_moduli("bed", [1.0])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="hair_density"):
        bed_moduli(bed, [1.0], hair_density=-1.0)


def _si_bed() -> object:
    from hairbed import HairBed

    return HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                   viscosity=1.0, spacing=250e-6)  # fmt: skip


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: oscillatory_shear([1.0], eps=5e-324, kappa=1.0), "eps"),
        (lambda: oscillatory_shear([1.0], eps=0.5, kappa=1e300), "kappa"),
        (lambda: large_amplitude_shear(1e300, 0.1, eps=0.5, kappa=1.0), "omega"),
        (lambda: large_amplitude_shear(1e8, 0.1, eps=0.5, kappa=1.0), "strain_amplitude"),
        (lambda: large_amplitude_shear(1.0, 0.1, eps=0.5, kappa=5e-324), "kappa"),
        (lambda: bed_moduli(_si_bed(), [1.0, -2.0], 0.0), r"frequency.*index 1"),
        (lambda: bed_moduli(_si_bed(), [1e300], 0.0), "frequency"),
        (lambda: bed_moduli(_si_bed(), [1.0], 1.7e308), "speed"),
    ],
)
def test_hostile_rheometer_inputs_are_named(call, match) -> None:
    """The battery's findings (tools/hostile_battery.py): each bad input named, no
    ArithmeticError, numpy LinAlgError or leaked warning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=match):
            call()
