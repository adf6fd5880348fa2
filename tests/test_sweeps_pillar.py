"""``hairbed.sweep(forcing=...)``: an isolated pillar's grid (issue 21) - its dimensions, the CF
attributes of the one variables table, and values equal to hairbed.solve_pillar at each point
(each solved alone here), eager and chunked."""

from __future__ import annotations

import numpy as np
import pytest

import hairbed
from hairbed._variables import PILLAR
from hairbed.sweeps import PILLAR_DIMS, PILLAR_VARIABLES

xr = pytest.importorskip("xarray")

FORCING = np.array([0.01, 1.0, 30.0])
THETA0 = np.array([-0.7, 0.0, 0.9])
#: Agreement of a batched solve with the same point solved alone: the Newton iterates of a
#: batch stop together, so the last digits may differ (both converged to 1e-12).
BATCH_ATOL = 1e-11


def _alone(name: str, **kw) -> float:
    return float(getattr(hairbed.solve_pillar(**kw), name))


def test_dimensions_and_attributes():
    ds = hairbed.sweep(forcing=FORCING, theta0=THETA0, gamma=0.6)
    assert dict(ds.sizes) == {"forcing": 3, "theta0": 3}
    assert list(ds.data_vars) == list(PILLAR_VARIABLES)
    assert PILLAR_DIMS == ("forcing", "theta0", "gamma", "tip_load", "height_ratio")
    for name in (*ds.data_vars, *ds.coords):
        v = PILLAR[name]
        assert ds[name].attrs["units"] == v.units and ds[name].attrs["long_name"] == v.long_name
    assert float(ds["gamma"]) == 0.6 and float(ds["tip_load"]) == 0.0
    assert "height_ratio" not in ds.coords
    assert ds["status"].dtype == np.int64 and ds["num"].dtype == np.int64
    assert ds.attrs["profile"] == "sublayer" and "branch_sign" not in ds.attrs
    assert (ds["status"] == 0).all()


def test_values_are_those_of_solve_pillar_point_by_point():
    ds = hairbed.sweep(forcing=FORCING, theta0=THETA0, gamma=0.6, tip_load=0.1)
    for lam in FORCING:
        for t0 in THETA0:
            point = ds.sel(forcing=lam, theta0=t0)
            st = hairbed.solve_pillar(lam, t0, gamma=0.6, tip_load=0.1)
            for name in ("tip_deflection", "tip_height", "tip_angle", "base_curvature",
                         "drag_x", "drag_z"):  # fmt: skip
                assert float(point[name]) == pytest.approx(getattr(st, name), abs=BATCH_ATOL)
            assert int(point["status"]) == st.status


def test_small_forcing_is_the_linear_cantilever_on_every_profile():
    """x1 = Lambda (33 - 26 L/H)/360 for Poiseuille (theory.md §12), the height ratio a
    dimension solved one value at a time."""
    ratios = np.array([0.25, 0.5, 1.0])
    ds = hairbed.sweep(forcing=1e-5, profile="poiseuille", height_ratio=ratios)
    assert dict(ds.sizes) == {"height_ratio": 3}
    linear = 1e-5 * (33.0 - 26.0 * ratios) / 360.0
    np.testing.assert_allclose(ds["tip_deflection"].values, linear, rtol=1e-8)
    assert ds.attrs["profile"] == "poiseuille"


def test_chunked_is_the_eager_sweep():
    pytest.importorskip("dask.array")
    kw = dict(forcing=FORCING, theta0=THETA0, gamma=[0.5, 0.8])
    eager = hairbed.sweep(**kw)
    lazy = hairbed.sweep(**kw, chunks={"theta0": 2})
    assert lazy["tip_deflection"].chunks is not None
    xr.testing.assert_allclose(lazy.compute(), eager, atol=BATCH_ATOL, rtol=0)


def test_a_callable_profile():
    ds = hairbed.sweep(forcing=[1e-5, 10.0], profile=lambda z: z**2)
    assert ds["tip_deflection"].values[0] == pytest.approx(13e-5 / 180, rel=1e-8)
    assert ds.attrs["profile"].startswith("callable")


@pytest.mark.parametrize(
    ("kwargs", "error", "words"),
    [
        (dict(forcing=1.0, omega2=1.0), ValueError, "omega2: a pillar's sweep"),
        (dict(forcing=1.0, root="high"), ValueError, "sign, n and root"),
        (dict(omega2=1.0, eps=0.5, gamma=0.5), ValueError, "gamma applies to a pillar's sweep"),
        (dict(omega2=1.0), TypeError, "needs omega2 and eps"),
        (dict(forcing=[1.0, np.nan]), ValueError, "forcing"),
        (dict(forcing=1.0, theta0=[0.0, 2.0]), ValueError, "theta0 must lie in"),
        (dict(forcing=1.0, gamma=[0.5, 0.0]), ValueError, "gamma must lie in (0, 1]"),
        (dict(forcing=1.0, profile="poiseuille"), ValueError, "needs height_ratio"),
        (dict(forcing=1.0, profile="couette", height_ratio=[0.5, 1.5]), ValueError, "index 1"),
        (dict(forcing=[[1.0]]), ValueError, "1-D"),
        (dict(forcing=[]), ValueError, "empty"),
        (dict(forcing=1.0, chunks={"eps": 2}), ValueError, "unknown dimension"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, error, words):
    with pytest.raises(error) as info:
        hairbed.sweep(**kwargs)
    assert words in str(info.value)
