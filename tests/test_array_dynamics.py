"""Array-valued models in time and frequency (issue 32 item 2): a design scan in one call.

``Pillar.frequency_response``, ``Pillar.simulate``, ``HairBed.simulate`` and
``rheometer.bed_moduli`` (the bed's transfer function in SI) of an array-valued model give
one result with the model's shape in front; each element is compared with the call of the
model's :meth:`item` (the pillar or bed of numbers, built through its own checks): bitwise,
since each element runs the scalar model's own code on the same numbers. The scalar paths
themselves are tested against references written from the equations in
test_sensor_dynamics.py, test_sensor_simulate.py, test_bed_simulation.py and
test_rheometer*.py.
"""

import warnings

import numpy as np
import pytest

from hairbed import HairBed, ModelValidityWarning, Pillar
from hairbed.dynamics import sine
from hairbed.rheometer import bed_moduli

WATER = dict(viscosity=1e-3, density=998.0)
PILLAR = dict(length=1e-3, radius=50e-6, **WATER)


def quiet(call):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        return call()


def test_pillar_frequency_response_over_modulus_and_tilt():
    """A (2, 2) scan (two moduli by two tilts, one about a loaded state): every field of
    every element bitwise the item's, the xarray form with named axes and coordinates."""
    p = Pillar(**PILLAR, youngs_modulus=np.array([[5e5], [2e6]]), base_angle=[0.0, 0.3])
    f = np.array([0.0, 3.0, 30.0, 300.0])
    with pytest.warns(ModelValidityWarning, match=r"\(pillar \(0, 0\); 4 of the 4 pillars"):
        r = p.frequency_response(f, wall_shear_stress=0.5, pillar_density=970.0)
    assert r.shape == (2, 2) and r.response.shape == (2, 2, 4)
    assert r.success.tolist() == [[True, True], [True, True]]
    for idx in np.ndindex(2, 2):
        one = quiet(lambda i=idx: p.item(i).frequency_response(
            f, wall_shear_stress=0.5, pillar_density=970.0))  # fmt: skip
        assert np.array_equal(r.response[idx], one.response)
        for name in ("static_gain", "resonance_frequency", "quality_factor", "bandwidth",
                     "time_scale", "inertia_number", "valid_below"):  # fmt: skip
            assert np.asarray(getattr(r, name))[idx] == getattr(one, name), name
        assert r.item(idx).bandwidth == one.bandwidth and r.item(idx).status == one.status
        assert np.array_equal(quiet(lambda i=idx: r.item(i).at([7.0])), one.at([7.0]))
    # a stiffer pillar rings faster; the tilt changes the loaded state's response
    assert np.all(r.resonance_frequency[1] > r.resonance_frequency[0])
    assert r.static_gain[0, 0] != r.static_gain[0, 1]
    assert quiet(lambda: r.at([1.0, 2.0, 5.0])).shape == (2, 2, 3)
    ds = r.to_xarray()
    assert ds["magnitude"].dims == ("pillar_0", "pillar_1", "frequency")
    assert ds["bandwidth"].dims == ("pillar_0", "pillar_1")
    assert ds["bandwidth"].attrs["units"] == "Hz" and ds["magnitude"].attrs["units"] == "m/Pa"
    assert ds["youngs_modulus"].attrs["units"] == "Pa"
    assert ds["base_angle"].values.tolist() == [[0.0, 0.3], [0.0, 0.3]]
    assert ds["bandwidth"].values.tolist() == r.bandwidth.tolist()


def test_pillar_frequency_response_quasi_steady_and_wall_law():
    """The other drag model and the wall-law profile (whose drive is the profile's own
    change): a 1-d scan of the radius, the axis named ``pillar``."""
    p = quiet(lambda: Pillar(**{**PILLAR, "radius": [30e-6, 60e-6]}, youngs_modulus=1e6,
                             profile="wall-law"))  # fmt: skip
    kw = dict(wall_shear_stress=0.3, pillar_density=970.0, drag="quasi-steady")
    r = quiet(lambda: p.frequency_response([0.0, 20.0], **kw))
    for i in range(2):
        one = quiet(lambda i=i: p.item(i).frequency_response([0.0, 20.0], **kw))
        assert np.array_equal(r.response[i], one.response)
        assert r.bandwidth[i] == one.bandwidth and r.static_gain[i] == one.static_gain
    ds = r.to_xarray()
    assert ds["phase"].dims == ("pillar", "frequency")
    assert ds["radius"].values.tolist() == [30e-6, 60e-6]


def test_pillar_simulate_over_tilt_on_threads():
    """A ringing step (inertia, quasi-steady drag with added mass) over three tilts, on two
    threads: each series bitwise the item's run."""
    p = Pillar(**PILLAR, youngs_modulus=1e6, base_angle=[0.0, 0.25, -0.2])
    t = np.linspace(0.0, 4e-3, 9)
    run = quiet(lambda: p.simulate(1.0, t, pillar_density=970.0, workers=2))
    assert run.shape == (3,) and run.tip_deflection.shape == (3, 9)
    assert run.angle.shape == (3, 9, 13) and run.success.tolist() == [True] * 3
    for i in range(3):
        one = quiet(lambda i=i: p.item(i).simulate(1.0, t, pillar_density=970.0))
        for name in ("wall_shear_stress", "tip_deflection", "tip_height", "tip_angle",
                     "base_moment", "angle", "x", "z", "arc_length"):  # fmt: skip
            assert np.array_equal(getattr(run, name)[i], getattr(one, name)), name
        item = run.item(i)
        assert (item.time_scale, item.inertia_number, item.t_end, item.status) == (
            one.time_scale, one.inertia_number, one.t_end, one.status)  # fmt: skip
    ds = run.to_xarray()
    assert ds["x"].dims == ("pillar", "time", "node") and ds["x"].attrs["units"] == "m"
    assert ds["base_angle"].attrs["units"] == "rad"


def test_pillar_simulate_over_modulus_with_a_signal():
    """A (2, 1) scan of the modulus (each element its own time scale) under a sine in SI,
    overdamped: bitwise the items'."""
    p = Pillar(**PILLAR, youngs_modulus=[[8e5], [1.6e6]])
    t = np.linspace(0.0, 0.01, 6)
    drive = sine(0.5, 0.2, 600.0)  # [Pa], omega [rad/s]
    run = quiet(lambda: p.simulate(drive, t, overdamped=True))
    assert run.tip_deflection.shape == (2, 1, 6)
    for idx in ((0, 0), (1, 0)):
        one = quiet(lambda i=idx: p.item(i).simulate(drive, t, overdamped=True))
        assert np.array_equal(run.tip_deflection[idx], one.tip_deflection)
        assert run.time_scale[idx] == one.time_scale
    assert run.time_scale[1, 0] < run.time_scale[0, 0]  # stiffer: faster


def test_bed_simulate_over_tilt_and_spacing():
    """HairBed.simulate of a (2,) and a (2, 2) bed: each element bitwise its item's run
    (the porous bed in time, theory.md §15), the axes named ``bed``."""
    bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                  viscosity=1.0, spacing=400e-6, model="porous",
                  base_angle=[0.0, 0.4])  # fmt: skip
    times = [0.0, 2.0, 10.0]
    run = bed.simulate(times, velocity=0.1, rtol=1e-6, atol=1e-8)
    assert run.shape == (2,) and run.tip_deflection.shape == (2, 3)
    for i in range(2):
        one = bed.item(i).simulate(times, velocity=0.1, rtol=1e-6, atol=1e-8)
        for name in ("tip_deflection", "tip_height", "tip_angle", "base_moment",
                     "wall_shear_stress", "wall_velocity", "flow_rate",
                     "pressure_gradient"):  # fmt: skip
            assert np.array_equal(getattr(run, name)[i], getattr(one, name)), name
        assert run.item(i).kappa == one.kappa and run.item(i).status == one.status
    ds = run.to_xarray()
    assert ds["tip_deflection"].dims == ("bed", "time")
    assert ds["base_angle"].attrs["units"] == "rad" and ds["kappa"].dims == ("bed",)
    grid = quiet(lambda: HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6,
                                 channel_height=2e-3, viscosity=1.0,
                                 spacing=np.array([[300e-6], [500e-6]]),
                                 base_angle=[0.0, 0.4]))  # fmt: skip
    run = grid.simulate([0.0, 5.0], velocity=0.1, rtol=1e-6, atol=1e-8)
    assert run.tip_deflection.shape == (2, 2, 2) and run.bed_model == "dense"
    one = quiet(lambda: grid.item((1, 0))).simulate([0.0, 5.0], velocity=0.1, rtol=1e-6,
                                                    atol=1e-8)  # fmt: skip
    assert np.array_equal(run.tip_deflection[1, 0], one.tip_deflection)
    assert run.to_xarray()["tip_deflection"].dims == ("bed_0", "bed_1", "time")


def test_array_calls_refuse_bad_inputs():
    """Each call names the parameter (and the element, where it is the element's)."""
    p = Pillar(**PILLAR, youngs_modulus=[1e6, 2e6])
    with pytest.raises(ValueError, match="wall_shear_stress"):
        p.frequency_response([1.0], wall_shear_stress=[0.1, 0.2], pillar_density=970.0)
    with pytest.raises(ValueError, match=r"pillar_density \[kg/m\^3\] is needed"):
        p.frequency_response([1.0])
    with pytest.raises(ValueError, match="frequency must be >= 0"):
        p.frequency_response([-1.0], pillar_density=970.0)
    with pytest.raises(ValueError, match="drag"):
        p.frequency_response([1.0], pillar_density=970.0, drag="stokes")
    dry = Pillar(length=1e-3, radius=50e-6, youngs_modulus=[1e6, 2e6], viscosity=1e-3)
    with pytest.raises(ValueError, match="the fluid's density"):
        quiet(lambda: dry.frequency_response([1.0], pillar_density=970.0))
    r = quiet(lambda: p.frequency_response([1.0], pillar_density=970.0))
    with pytest.raises(ValueError, match=r"index must be 1 integer"):
        r.item((0, 0))
    with pytest.raises(ValueError, match="out of range"):
        r.item(2)
    single = r.item(1)  # a pillar of numbers' response is its own only item
    assert single.item() is single
    with pytest.raises(ValueError, match=r"index must be 0 integer"):
        single.item(0)
    t = [0.0, 1e-3]
    with pytest.raises(ValueError, match="pillar_density"):
        p.simulate(1.0, t)
    with pytest.raises(ValueError, match="workers"):
        p.simulate(1.0, t, overdamped=True, workers=0)
    with pytest.raises(ValueError, match=r"wall_shear_stress must stay within .* \(pillar 1\)"):
        quiet(
            lambda: Pillar(**PILLAR, youngs_modulus=[1e12, 1e3]).simulate(1e99, t, overdamped=True)
        )
    with pytest.raises(ValueError, match="t must not decrease"):
        p.simulate(1.0, [1.0, 0.0], overdamped=True)
    bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                  viscosity=1.0, spacing=400e-6, base_angle=[0.0, 0.4])  # fmt: skip
    with pytest.raises(ValueError, match="hair_density"):
        bed.simulate([0.0, 1.0], velocity=0.1, hair_density=-1.0)
    with pytest.raises(ValueError, match="at most one of velocity"):
        bed.simulate([0.0, 1.0], velocity=0.1, wall_shear_stress=1.0)
    with pytest.raises(ValueError, match=r"velocity must stay within .* \(bed 1\)"):
        HairBed(
            length=1e-3,
            radius=50e-6,
            youngs_modulus=[1e6, 1e3],
            channel_height=2e-3,
            viscosity=1.0,
            spacing=400e-6,
        ).simulate([0.0, 1.0], velocity=1e4)


def test_bed_moduli_over_tilt():
    """rheometer.bed_moduli (the linear bed's transfer function in SI) of an array bed:
    each element bitwise its item's, the xarray form with the ``bed`` axis."""
    bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                  viscosity=1.0, spacing=400e-6, model="porous",
                  base_angle=[0.0, 0.4], density=1000.0)  # fmt: skip
    f, v = [0.01, 0.1, 1.0], [0.0, 0.05]
    r = bed_moduli(bed, f, v)
    assert r.shape == (2,) and r.storage.shape == (2, 3, 2) and r.lead_crossover.shape == (2, 2)
    assert r.status.shape == (2, 3, 2) and r.success.all()
    for i in range(2):
        one = bed_moduli(bed.item(i), f, v)
        for name in ("pre_stress", "storage", "loss", "lead", "lead_crossover",
                     "modulus_crossover"):  # fmt: skip
            assert np.array_equal(getattr(r, name)[i], getattr(one, name), equal_nan=True)
        assert r.item(i).time_scale == one.time_scale
        assert np.array_equal(r.item(i).status, one.status)
    assert r.storage[0, 0, 1] != r.storage[1, 0, 1]  # the tilt matters under a pre-stress
    ds = r.to_xarray()
    assert ds["storage"].dims == ("bed", "frequency", "pre_stress")
    assert ds["storage"].attrs["units"] == "Pa" and ds["base_angle"].attrs["units"] == "rad"
    with pytest.raises(ValueError, match="hair_density"):
        bed_moduli(bed, f, v, hair_density=0.0)
