"""Array-valued HairBed and Pillar (issue 32 item 2): every SI parameter broadcasts.

Each element of an array-model call is compared with the scalar model's own call: bitwise
where the same kernel runs on the same numbers (the model's conversions are computed element
by element by the scalar model's code), to the solver's tolerance where the core chains
neighbouring elements of an array (as it does for an array of loads on one model).
"""

import functools
import pickle
import warnings

import numpy as np
import pytest
from tolerances import ARRAY_MODEL_CHAINED_RTOL

from hairbed import HairBed, ModelValidityWarning, Pillar, calibration
from hairbed._core import loaded as core_loaded
from hairbed.valve import diodicity, valve_states

BED = dict(
    length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3, viscosity=1.0,
    spacing=400e-6,
)  # fmt: skip
PILLAR = dict(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1.0, density=1260.0)
BED_FIELDS = (
    "velocity", "omega2", "tip_deflection", "tip_height", "tip_angle", "wall_shear_stress",
    "force_per_hair", "stress_ratio", "tip_displacement", "reynolds_number", "flow_rate",
    "pressure_gradient",
)  # fmt: skip
PILLAR_FIELDS = (
    "wall_shear_stress", "forcing", "tip_deflection", "tip_height", "tip_angle",
    "tip_displacement", "base_moment", "drag", "drag_wall_normal", "sensitivity",
    "reynolds_number", "height_in_wall_units", "velocity", "pressure_gradient",
)  # fmt: skip


def same(a, b):
    """Bitwise equal floats (NaN equal to NaN)."""
    a, b = np.float64(a), np.float64(b)
    return bool(a == b or (np.isnan(a) and np.isnan(b)))


def assert_elements(state, scalar_state, index, fields, rtol=None):
    """Every field of ``state`` at ``index`` against the scalar model's state (a 0-d or a
    1-element result): bitwise, or within ``rtol``."""
    for name in fields:
        got = np.asarray(getattr(state, name))[index]
        want = np.asarray(getattr(scalar_state, name)).reshape(-1)[0]
        if rtol is None:
            assert same(got, want), (name, index, got, want)
        else:
            np.testing.assert_allclose(got, want, rtol=rtol, atol=0.0, err_msg=name)


def test_diodicity_over_the_tilt_in_one_call(monkeypatch):
    """The issue's example: which tilt maximises the diodicity at 1 kPa (over 1 cm)? One
    call, two compiled solves (forward and backward), each element the scalar bed's."""
    angles = np.linspace(0.0, 1.5, 21)
    calls = []
    solve = core_loaded._solve_loaded_checked

    def counted(*args, **kwargs):
        calls.append(np.shape(args[2]))
        return solve(*args, **kwargs)

    monkeypatch.setattr("hairbed.units._solve_loaded_checked", counted)
    di = diodicity(HairBed(**BED, base_angle=angles), 1000.0, 0.01)
    assert calls == [(21,), (21,)]  # no Python loop over the tilts
    monkeypatch.undo()
    assert di.success and np.shape(di.diodicity) == (21,)
    for i, a in enumerate(angles):
        one = diodicity(HairBed(**BED, base_angle=float(a)), [1000.0], 0.01)
        assert same(di.diodicity[i], one.diodicity[0]), i
        assert same(di.forward.resistance_ratio[i], one.forward.resistance_ratio[0]), i
    # the answer: an interior optimum (upright hairs are no diode; flat ones block both ways)
    best = int(np.argmax(di.diodicity))
    assert 0 < best < angles.size - 1
    assert di.diodicity[0] == pytest.approx(1.0, abs=1e-12)
    assert di.diodicity[best] > 3.0 and angles[best] == pytest.approx(1.175, abs=0.08)


def test_dense_bed_broadcasts_with_the_load():
    """base_angle (3,) and youngs_modulus (2, 1) make a (2, 3) bed; a velocity (4, 1, 1)
    gives (4, 2, 3) states, each the scalar bed's at the scalar speed (bitwise: the scalar
    kernel and the array kernel give the same states)."""
    angles, moduli = np.array([-0.6, 0.0, 0.4]), np.array([[5e5], [2e6]])
    bed = HairBed(**{**BED, "youngs_modulus": moduli}, base_angle=angles, density=1000.0)
    assert bed.shape == (2, 3)
    v = np.array([-0.2, 0.0, 0.05, 0.3]).reshape(4, 1, 1)
    st = bed.deform(v)
    assert np.shape(st.tip_deflection) == (4, 2, 3) and np.shape(st.velocity) == (4, 2, 3)
    for k, i, j in np.ndindex(4, 2, 3):
        one = HairBed(
            **{**BED, "youngs_modulus": float(moduli[i, 0])},
            base_angle=float(angles[j]),
            density=1000.0,
        )
        assert_elements(st, one.deform(float(v[k, 0, 0])), (k, i, j), BED_FIELDS)
    assert np.shape(bed.eps) == (2, 3) and np.shape(bed.velocity_scale) == (2, 3)
    x, z = st.profile(7)  # the shape in metres: the bed's length broadcast per element
    x1, z1 = bed.item((1, 2)).deform(float(v[3, 0, 0])).profile(7)
    assert x.shape == (4, 2, 3, 7) and np.array_equal(x[3, 1, 2], x1)
    assert np.array_equal(z[3, 1, 2], z1)
    ratio = bed.rectification_ratio(0.1)
    for i, j in np.ndindex(2, 3):
        one = bed.item((i, j))
        assert same(ratio[i, j], one.rectification_ratio([0.1])[0])


@pytest.mark.parametrize("drive", ["pressure_gradient", "flow_rate"])
def test_pumped_dense_bed(drive):
    """A pump's drive on an array bed (spacing an array): one distributed-load solve."""
    spacing = np.array([250e-6, 300e-6, 400e-6])
    bed = HairBed(**{**BED, "spacing": spacing}, base_angle=0.3)
    value = {"pressure_gradient": np.array([-2e4, 5e4]), "flow_rate": np.array([-2e-7, 5e-7])}
    load = value[drive][:, None]
    st = bed.deform(velocity=0.01, **{drive: load})
    assert np.shape(st.tip_deflection) == (2, 3)
    for k, j in np.ndindex(2, 3):
        one = HairBed(**{**BED, "spacing": float(spacing[j])}, base_angle=0.3)
        # the scalar bed at a 1-element drive: numpy's vectorised power in the gap flow
        # (g^3) is the array path's too
        ref = one.deform(velocity=0.01, **{drive: load[k]})
        assert_elements(st, ref, (k, j), BED_FIELDS)


def test_porous_bed_every_drive():
    """The porous bed: the wall (including rest, whose stress ratio is a limit) and a pump."""
    angles = np.array([-0.5, 0.2, 0.9])
    bed = HairBed(**BED, base_angle=angles, model="porous")
    st = bed.deform(np.array([[0.0], [0.08]]))
    pumped = bed.deform(pressure_gradient=3e4)
    for j, a in enumerate(angles):
        one = HairBed(**BED, base_angle=float(a), model="porous")
        assert_elements(st, one.deform([0.0]), (0, j), BED_FIELDS)
        assert_elements(st, one.deform([0.08]), (1, j), BED_FIELDS)
        assert_elements(pumped, one.deform(pressure_gradient=[3e4]), (j,), BED_FIELDS)
    assert np.shape(bed.kappa) == (3,) and np.shape(bed.drag_coefficients[0]) == (3,)


@pytest.mark.parametrize("model", ["dense", "porous"])
def test_bed_inverse_from_tip_deflection(model):
    """The sensor's calibration read backwards on an array bed, exact and linear, from a tip
    deflection or a wall shear stress: each element the scalar bed's (tips behind rest are
    flow towards -x)."""
    angles = np.array([-0.5, 0.0, 0.6])
    bed = HairBed(**BED, base_angle=angles, model=model)
    d = np.array([[-2e-4], [1e-4], [6e-4]])
    st = bed.state_from_tip_deflection(d)
    v = bed.velocity_from_tip_deflection(d)
    assert np.shape(v) == (3, 3) and np.array_equal(v, st.velocity)
    linear = bed.linear_velocity_from_tip_deflection(d)
    linear_tau = bed.linear_wall_shear_stress_from_tip_deflection(d)
    tau = np.array([[-50.0], [0.0], [80.0]])
    from_tau = bed.velocity_from_wall_shear_stress(tau)
    for k, j in np.ndindex(3, 3):
        one = HairBed(**BED, base_angle=float(angles[j]), model=model)
        assert_elements(st, one.state_from_tip_deflection(d[k]), (k, j), BED_FIELDS)
        assert same(linear[k, j], one.linear_velocity_from_tip_deflection(d[k])[0])
        assert same(linear_tau[k, j], one.linear_wall_shear_stress_from_tip_deflection(d[k])[0])
        assert same(from_tau[k, j], one.velocity_from_wall_shear_stress(tau[k])[0])


def test_hash_equality_and_items():
    """Array beds hash and compare by value (the design package caches on them); their
    arrays are read-only; item() gives the scalar model of an element."""
    a = HairBed(**BED, base_angle=[0.1, 0.2])
    b = HairBed(**BED, base_angle=np.array([0.1, 0.2]))
    c = HairBed(**BED, base_angle=[0.1, 0.25])
    assert a == b and hash(a) == hash(b) and a != c and len({a, b, c}) == 2
    assert a != HairBed(**BED, base_angle=0.1)
    with pytest.raises(ValueError, match="read-only"):
        a.base_angle[0] = 1.0
    assert a.item(1) == HairBed(**BED, base_angle=0.2)
    assert HairBed(**BED).item() == HairBed(**BED)
    back = pickle.loads(pickle.dumps(a))
    assert back == a and not back.base_angle.flags.writeable
    cached = functools.lru_cache(maxsize=4)(lambda bed: bed.deform(0.1).tip_deflection)
    assert cached(a) is cached(b)
    p = Pillar(**PILLAR, base_angle=[0.0, 0.3])
    q = Pillar(**PILLAR, base_angle=(0.0, 0.3))
    assert p == q and hash(p) == hash(q)
    assert p.item(1) == Pillar(**PILLAR, base_angle=0.3)
    assert p != Pillar(**PILLAR, base_angle=[0.0, 0.31])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            dict(base_angle=[0.1, 0.2, 1.6]),
            r"base_angle must lie in \(-pi/2, pi/2\) \[rad\].*"
            r"got 1\.6 \(first at index 2\)",
        ),
        (dict(radius=[50e-6, -1e-6]), r"radius must lie in \(0, inf\) \[m\].*first at index 1"),
        (
            dict(radius=[50e-6, 250e-6]),
            r"radius \(0\.00025 m\) must be less than half the "
            r"spacing .*first at index 1",
        ),
        (
            dict(length=[1e-3, 3e-3]),
            r"length \(0\.003 m\) must be less than channel_height .*"
            r"first at index 1",
        ),
        (
            dict(length=[1e-3, 1.1e-3], radius=[40e-6, 50e-6, 60e-6]),
            r"must broadcast together.*length \(2,\), radius \(3,\)",
        ),
        (dict(youngs_modulus=[]), r"youngs_modulus must be a number or a non-empty array"),
        (dict(viscosity=[1.0, np.nan]), r"viscosity must lie in .*first at index 1"),
    ],
)
def test_bad_array_parameters(kwargs, message):
    with pytest.raises(ValueError, match=message):
        HairBed(**{**BED, **kwargs})


def test_scalar_only_methods_and_bad_loads_say_so():
    bed = HairBed(**BED, base_angle=[0.1, 0.2])
    with pytest.raises(ValueError, match=r"velocity of shape \(3,\) must broadcast"):
        bed.deform([0.1, 0.2, 0.3])
    for call in (
        lambda: bed.fit_profile([1e-4, 2e-4], [5e-4, 9e-4]),
        lambda: bed.sweep([0.1]),
        lambda: valve_states(bed, 0.01, pressure_drop=(0.0, 1000.0)),
        lambda: calibration.linear_range(bed),
    ):
        with pytest.raises(ValueError, match=r"needs a single bed.*base_angle is an array"):
            call()
    pillar = Pillar(**{**PILLAR, "youngs_modulus": [1e6, 2e6]})
    with pytest.raises(ValueError, match=r"needs a single pillar.*youngs_modulus is an"):
        pillar.linear_range()
    with pytest.raises(ValueError, match=r"channel_height 0\.0004 m \(first at index 1\)"):
        Pillar(**PILLAR, profile="couette", channel_height=[1e-3, 4e-4])
    with pytest.raises(ValueError, match="a callable profile .* needs a single length"):
        Pillar(**{**PILLAR, "length": [5e-4, 6e-4]}, profile=lambda z: z)


@pytest.mark.parametrize(
    ("profile", "extra"),
    [
        ("sublayer", {}),
        ("poiseuille", {"channel_height": np.array([[6e-4], [2e-3]])}),  # L/H 0.83, 0.25
        ("wall-law", {"viscosity": 1e-3, "density": 998.0}),  # water: L+ from 9 to 27
    ],
)
def test_pillar_tilt_scan(profile, extra):
    """A tilt scan of a pillar, also where each element has its own profile (Poiseuille of
    an array L/H, the wall law), at one stress and broadcast with an array of stresses: the
    scalar pillar's states to the solver's tolerance (the pillar core's batched solves are
    not bitwise those of one element even for a scalar pillar: ``deform([2.0, 2.0, 2.0])``
    differs in the last bit between its elements); the conversions bitwise."""
    angles = np.array([-0.9, 0.0, 0.7])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelValidityWarning)
        p = Pillar(**{**PILLAR, **extra}, base_angle=angles, profile=profile)
        st = p.deform(2.0)
        assert np.shape(st.tip_deflection) == p.shape
        for index in np.ndindex(p.shape):
            ref = p.item(index).deform(2.0)
            assert_elements(st, ref, index, PILLAR_FIELDS, ARRAY_MODEL_CHAINED_RTOL)
            assert same(np.asarray(p.forcing_per_stress)[index], p.item(index).forcing_per_stress)
        tau = np.array([0.3, 3.0]).reshape((2,) + (1,) * len(p.shape))
        st = p.deform(tau)
        assert np.shape(st.tip_deflection) == (2, *p.shape)
        for index in np.ndindex(p.shape):
            for k in range(2):
                ref = p.item(index).deform(float(tau.flat[k]))
                assert_elements(st, ref, (k, *index), PILLAR_FIELDS, ARRAY_MODEL_CHAINED_RTOL)
        if profile == "sublayer":
            c1 = p.linear_coefficient
            assert [same(c1[j], p.item(j).linear_coefficient) for j in range(3)] == [True] * 3


def test_pillar_modulus_scan_and_calibration():
    """A modulus scan (the core chains neighbouring elements of one tilt and drag ratio,
    as for an array of stresses): the scalar pillar's states to the solver's tolerance; the
    inverse and the linear calibration of the array pillar likewise."""
    moduli = np.geomspace(3e5, 3e6, 6)
    p = Pillar(**{**PILLAR, "youngs_modulus": moduli}, base_angle=0.2)
    st = p.deform(1.5)
    back = p.wall_shear_stress_from_tip_deflection(st.tip_deflection)
    linear = p.linear_wall_shear_stress_from_tip_deflection(st.tip_deflection)
    for j, e in enumerate(moduli):
        one = Pillar(**{**PILLAR, "youngs_modulus": float(e)}, base_angle=0.2)
        ref = one.deform(1.5)
        assert_elements(st, ref, (j,), PILLAR_FIELDS, rtol=ARRAY_MODEL_CHAINED_RTOL)
        assert same(p.forcing_per_stress[j], one.forcing_per_stress)
        assert back[j] == pytest.approx(1.5, rel=ARRAY_MODEL_CHAINED_RTOL)
        assert same(linear[j], one.linear_wall_shear_stress_from_tip_deflection(
            st.tip_deflection[j]))  # fmt: skip
