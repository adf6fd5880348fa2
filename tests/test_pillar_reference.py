"""The isolated pillar (issue 21) against its own mpmath reference and its exact limits.

``tests/data/pillar_mpmath.json`` integrates theory.md §12's equations in mpmath (Taylor
shooting at 40 digits, tests/reference/generate_pillar.py) and shares no code with the
solver (the Chebyshev collocation of ``hairbed._core._kernels.spectral``). Here:

- every forward state (three profiles and a callable, theta0 from -1.4 to 1.4, Lambda from
  1e-6 to 1e4, both drag ratios, every state of the snap-through window) within 1e-10, its
  shape at s = j/8 too;
- every inverse case (Lambda from a tip deflection) within 1e-10, and the round trips;
- the folds of the window: two at theta0 = -1.4 and -1.35 near the reference's, none at
  theta0 >= -1.3;
- the small-deflection limits (x1 = Lambda int U s^2 (3 - s)/6, remainder O(Lambda^2) and
  O(Lambda^3) at theta0 = 0) and the tip-loaded elastica of ``hairbed.solve`` as the limit of
  a load concentrated at the tip.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import pytest
from conftest import DATA
from tolerances import PILLAR_CONCENTRATION_RATE, PILLAR_REFERENCE_ATOL

import hairbed

REF = json.loads((DATA / "pillar_mpmath.json").read_text())
CASES: list[dict[str, Any]] = REF["cases"]
INVERSE: list[dict[str, Any]] = REF["inverse"]
SCALARS = ("tip_deflection", "tip_height", "tip_angle", "base_curvature", "drag_x", "drag_z")


def _profile(case: dict[str, Any]) -> dict[str, Any]:
    """The solver's keywords of a reference case's profile (the callable written here)."""
    name = case["profile"]
    par = case["profile_parameters"]
    if name == "callable":
        assert par == {"u": "z**2"}
        return {"profile": lambda z: z**2}
    if "L/H" in par:
        return {"profile": name, "height_ratio": float(par["L/H"])}
    return {"profile": name}


def _ids(case: dict[str, Any]) -> str:
    return (
        f"{case['profile']}-g{case['gamma'][:5]}-th{case['theta0']}-"
        f"L{float(case['forcing']):.3g}-{case['state_index']}of{case['states_at_forcing']}"
    )


def _close(got: float, want: str, atol: float = PILLAR_REFERENCE_ATOL) -> bool:
    w = float(want)
    return abs(got - w) <= atol * max(1.0, abs(w))


def _forward(case: dict[str, Any]) -> Any:
    kw = _profile(case) | {"gamma": float(case["gamma"])}
    lam = float(case["forcing"])
    if case["states_at_forcing"] == 1:
        return hairbed.solve_pillar(lam, case["theta0"], **kw)
    states = hairbed.solve_pillar_all(lam, case["theta0"], **kw)
    assert len(states) == case["states_at_forcing"]
    return states[case["state_index"]]


def test_reference_covers_the_issue():
    assert len(CASES) >= 30 and len(INVERSE) >= 6
    assert {c["profile"] for c in CASES} >= {"sublayer", "couette", "poiseuille", "callable"}
    lams = [float(c["forcing"]) for c in CASES]
    assert min(lams) <= 1e-6 and max(lams) >= 1e4
    th = [c["theta0"] for c in CASES]
    assert min(th) <= -1.4 and max(th) >= 1.4


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_forward_state(case):
    st = _forward(case)
    assert st.status == 0, st.message
    for name in SCALARS:
        assert _close(getattr(st, name), case[name]), (name, getattr(st, name), case[name])
    sh = case["shape"]
    _, x, z, theta = st.shape(np.array([float(v) for v in sh["s"]]))
    for got, want in ((x, sh["x"]), (z, sh["z"]), (theta, sh["theta"])):
        for g, w in zip(got, want):
            assert _close(float(g), w)


@pytest.mark.parametrize("case", CASES, ids=_ids)
def test_base_moment_identity_by_quadrature(case):
    """theta'(0) = int_0^1 (z f_x - x f_z) ds, by Gauss-Legendre on the state's interpolants
    (numpy, not the kernel's quadrature)."""
    st = _forward(case)
    xg, wg = np.polynomial.legendre.leggauss(80)
    s = 0.5 * (xg + 1.0)
    _, x, z, th = st.shape(s)
    kw = _profile(case)
    if callable(kw["profile"]):
        u = kw["profile"](z)
    elif kw["profile"] == "poiseuille":
        u = z * (1.0 - kw["height_ratio"] * z)
    else:
        u = z
    g = float(case["gamma"])
    lam = float(case["forcing"])
    fx = lam * u * (np.cos(th) ** 2 + g * np.sin(th) ** 2)
    fz = -lam * u * (1.0 - g) * np.sin(th) * np.cos(th)
    moment = 0.5 * np.sum(wg * (z * fx - x * fz))
    assert abs(moment - st.base_curvature) <= 1e-11 * max(1.0, abs(moment))


@pytest.mark.parametrize("case", INVERSE, ids=_ids)
def test_inverse_case(case):
    kw = _profile(case) | {"gamma": float(case["gamma"])}
    st = hairbed.solve_pillar_inverse(float(case["tip_deflection"]), case["theta0"], **kw)
    assert st.status == 0, st.message
    assert _close(st.forcing, case["forcing"])
    for name in SCALARS:
        assert _close(getattr(st, name), case[name]), name


@pytest.mark.parametrize("case", [c for c in CASES if float(c["forcing"]) >= 1e-3], ids=_ids)
def test_inverse_round_trip(case):
    """Lambda from the reference state's own tip deflection, within 1e-10 (relative) of the
    reference's Lambda, or within 4 times the change that rounding x1 to a double makes where
    the problem amplifies it (Lambda ~ x1 - sin(theta0) near the straight pillar)."""
    kw = _profile(case) | {"gamma": float(case["gamma"])}
    x1 = float(case["tip_deflection"])
    lam = float(case["forcing"])
    st = hairbed.solve_pillar_inverse(x1, case["theta0"], **kw)
    assert st.status == 0, st.message
    conditioning = abs(x1) / max(abs(x1 - math.sin(case["theta0"])), 1e-300)
    rtol = max(PILLAR_REFERENCE_ATOL, 4 * 2.2e-16 * conditioning)
    assert abs(st.forcing - lam) <= rtol * abs(lam), (st.forcing, lam)
    assert _close(st.tip_height, case["tip_height"])


def _window_folds(label: str) -> list[float]:
    return next(f["folds_near_forcing"] for f in REF["folds"] if f["label"] == label)


@pytest.mark.parametrize(
    ("theta0", "gamma", "label"),
    [
        (-1.4, 0.5, "sublayer g=0.5 th0=-1.4"),
        (-1.35, 0.5, "sublayer g=0.5 th0=-1.35"),
        (-1.4, float(REF["gray_hancock"]["gamma"]), "sublayer g=0.6567 th0=-1.4"),
    ],
)
def test_folds_of_the_window(theta0, gamma, label):
    """The reference locates its folds to within a continuation step (a few %); the branch
    here must find the same two, and the state count must be 3 inside and 1 outside."""
    br = hairbed.continue_pillar(40.0, theta0, gamma=gamma)
    assert br.status == 0
    ref = sorted(_window_folds(label))
    got = sorted(br.folds[:, 0])
    assert len(got) == 2
    for g, r in zip(got, ref):
        assert abs(g - r) <= 0.03 * r, (got, ref)
    lo, hi = got
    mid = 0.5 * (lo + hi)
    assert len(hairbed.solve_pillar_all(mid, theta0, gamma=gamma)) == 3
    assert len(hairbed.solve_pillar_all(0.97 * lo, theta0, gamma=gamma)) == 1
    assert len(hairbed.solve_pillar_all(1.03 * hi, theta0, gamma=gamma)) == 1
    stable = [s.stable for s in hairbed.solve_pillar_all(mid, theta0, gamma=gamma)]
    assert stable == [True, False, True]


@pytest.mark.parametrize(
    "forcing_max, theta0",
    [(1e-16, 0.3), (1e-300, 0.0), (-1e-14, 0.3), (40.0, -1.4), (-40.0, 1.4)],
)
def test_branch_stability_against_its_folds(forcing_max, theta0):
    """``stable`` (the sign of the states' dx1/dLambda) is False exactly between the two
    folds in x1 (found apart, as extrema of Lambda(x1) by golden section) and True elsewhere;
    with no fold, True at every point, the rest state included, also at a forcing so small
    that the grid's x1 or Lambda round to one value (where a difference quotient vanished)."""
    br = hairbed.continue_pillar(forcing_max, theta0, num=64)
    assert br.status == 0
    x = br.tip_deflection
    if br.folds.shape[0] == 0:
        assert br.stable.all()
        return
    assert br.folds.shape[0] == 2
    lo, hi = sorted(br.folds[:, 1])
    step = abs(x[1] - x[0])
    far = np.min(np.abs(x[:, None] - br.folds[None, :, 1]), axis=1) > step
    between = (x > lo) & (x < hi)
    assert np.array_equal(br.stable[far], ~between[far])


@pytest.mark.parametrize(
    "label", [f["label"] for f in REF["folds"] if not f["folds_near_forcing"]]
)
def test_no_fold_where_the_reference_has_none(label):
    spec = next(f for f in REF["folds"] if f["label"] == label)
    like = [c for c in CASES if c["profile"] == spec["profile"] and c["theta0"] == spec["theta0"]]
    kw = (_profile(like[0]) if like else {"profile": spec["profile"]}) | {
        "gamma": float(spec["gamma"])
    }
    br = hairbed.continue_pillar(300.0, spec["theta0"], **kw)
    assert br.status == 0
    assert br.folds.shape == (0, 2)
    assert np.all(np.diff(br.forcing) > 0)


@pytest.mark.parametrize(
    ("kw", "coefficient"),
    [
        ({}, 11 / 120),
        ({"profile": "couette", "height_ratio": 0.5}, 11 / 120),
        ({"profile": "poiseuille", "height_ratio": 0.5}, (33 - 26 * 0.5) / 360),
        ({"profile": "poiseuille", "height_ratio": 1.0}, (33 - 26) / 360),
        ({"profile": lambda z: z**2}, 13 / 180),
        ({"profile": lambda z: np.ones_like(z)}, 1 / 8),
    ],
    ids=["sublayer", "couette", "poiseuille-0.5", "poiseuille-1", "z^2", "uniform"],
)
def test_small_deflection_limit(kw, coefficient):
    """theta0 = 0: x1 = c Lambda + O(Lambda^3) (x1 is odd in Lambda): the relative remainder
    falls by 100 when Lambda falls by 10."""
    lam = np.array([1e-1, 1e-2, 1e-3])
    st = hairbed.solve_pillar(lam, 0.0, **kw)
    rem = np.abs(np.asarray(st.tip_deflection) / (coefficient * lam) - 1.0)
    assert rem[-1] <= 1e-6
    ratio = rem[0] / rem[1]
    assert 80 <= ratio <= 120, rem
    assert np.allclose(
        hairbed.solve_pillar(-lam, 0.0, **kw).tip_deflection,
        -st.tip_deflection,
        rtol=1e-13,
        atol=0,
    )


def test_tilted_small_deflection_limit():
    """x1 = sin(theta0) + 11 Lambda cos^3(theta0)/120 + O(Lambda^2): the remainder over
    Lambda falls by 10 when Lambda does."""
    t0 = 0.6
    lam = np.array([1e-2, 1e-3])
    st = hairbed.solve_pillar(lam, t0)
    rem = np.abs(np.asarray(st.tip_deflection) - math.sin(t0) - 11 * lam * math.cos(t0) ** 3 / 120)
    ratio = (rem[0] / lam[0]) / (rem[1] / lam[1])
    assert 8 <= ratio <= 12, rem


def test_load_concentrated_at_the_tip_is_the_elastica():
    """U = (p + 1) z^p with isotropic drag (gamma = 1: the load is horizontal) puts the load
    within O(1/p) of the tip; the pillar then tends to the tip-loaded elastica of
    ``hairbed.solve`` (eps = 0) with the tip load the pillar's drag, and the difference halves
    as p doubles."""
    errors = []
    for p in (32, 64, 128):
        st = hairbed.solve_pillar(
            1.0, 0.3, profile=lambda z, p=p: (p + 1) * z**p, gamma=1.0, num=256
        )
        assert st.status == 0, st.message
        ref = hairbed.solve(st.drag_x, 0.0, 0.3)
        errors.append(abs(st.tip_deflection - ref.tip_deflection))
        assert abs(st.drag_z) <= 1e-14
    assert errors[-1] <= 0.02
    assert errors[0] / errors[1] >= PILLAR_CONCENTRATION_RATE
    assert errors[1] / errors[2] >= PILLAR_CONCENTRATION_RATE


@pytest.mark.parametrize(
    ("forcing", "theta0", "kw"),
    [
        (0.5, 0.0, {}),
        (50.0, 0.3, {"gamma": 0.657}),
        (15.0, -1.4, {}),
        (3.0, -1.0, {"profile": "poiseuille", "height_ratio": 1.0}),
        (7.0, 1.0, {"profile": lambda z: z**2}),
        (-4.0, 0.4, {}),
    ],
)
def test_tip_deflection_slope_against_richardson(forcing, theta0, kw):
    """dx1/dLambda by implicit differentiation against a Richardson-extrapolated central
    difference of forward solves (an independent path: only the solver's values)."""
    st = hairbed.solve_pillar(forcing, theta0, **kw)

    def central(h: float) -> float:
        up = hairbed.solve_pillar(forcing + h, theta0, **kw).tip_deflection
        down = hairbed.solve_pillar(forcing - h, theta0, **kw).tip_deflection
        return (up - down) / (2 * h)

    h = 1e-3 * abs(forcing)
    rich = (4 * central(h / 2) - central(h)) / 3
    assert st.tip_deflection_slope == pytest.approx(rich, rel=1e-8)


def test_root_picks_every_window_state():
    """root="low"/"mid"/"high" at theta0 = -1.4, Lambda = 15 are the reference's three states
    in the order of the branch from rest; scalars and arrays alike; "mid" outside a window
    says there is no such state."""
    window = sorted(
        (c for c in CASES if c["states_at_forcing"] == 3), key=lambda c: c["state_index"]
    )
    for root, case in zip(("low", "mid", "high"), window):
        st = hairbed.solve_pillar(15.0, -1.4, root=root)
        assert st.status == 0
        for name in SCALARS:
            assert _close(getattr(st, name), case[name]), (root, name)
        arr = hairbed.solve_pillar(np.array([3.0, 15.0]), -1.4, root=root)
        assert _close(float(arr.tip_deflection[1]), case["tip_deflection"])
    lone = hairbed.solve_pillar(3.0, -1.4, root="mid")
    assert lone.status == -1 and math.isnan(lone.tip_deflection)
    assert hairbed.solve_pillar(3.0, -1.4, root="high").status == 0


@pytest.mark.parametrize(
    ("theta0", "gap"), [(-1.5, 1e-3), (-1.5, 1e-7), (-1.4, 1e-3), (-1.4, 1e-7), (1.5, 1e-5)]
)
def test_every_window_state_right_up_to_its_folds(theta0, gap):
    """Within ``gap`` (relative) of either fold, inside the window: three states, the same from
    solve_pillar's root= and from solve_pillar_all, each a true state (the inverse problem at
    its tip deflection gives back its forcing); just outside: one. Before, a forcing between
    a branch grid's extreme Lambda and the fold's lost two states (theta0 = -1.5: at
    Lambda = 37.44, within 0.08 % of the upper fold, root="low" gave the high state, and
    solve_pillar_all found one state from 15.9856 to 18.73, its branch ending before the
    lower fold)."""
    sign = -1.0 if theta0 > 0 else 1.0  # theta0 = +1.5: the mirror, a flow towards -x
    folds = sorted(abs(hairbed.continue_pillar(sign * 60.0, theta0).folds[:, 0]))
    assert len(folds) == 2
    lo, hi = folds
    for lam, inside in [
        (lo * (1 + gap), True),
        (hi * (1 - gap), True),
        (lo * (1 - gap), False),
        (hi * (1 + gap), False),
    ]:
        every = hairbed.solve_pillar_all(sign * lam, theta0)
        picked = [hairbed.solve_pillar(sign * lam, theta0, root=r) for r in ("low", "mid", "high")]
        assert len(every) == (3 if inside else 1), (lam, inside)
        if inside:
            assert [p.status for p in picked] == [0, 0, 0]
            x_picked = sorted(float(p.tip_deflection) for p in picked)
            x_every = [float(s.tip_deflection) for s in every]
            assert np.allclose(x_picked, x_every, rtol=0, atol=1e-9), (lam, x_picked, x_every)
            assert len(set(np.round(x_picked, 12))) == 3
        else:
            assert picked[1].status == -1
            assert float(picked[0].tip_deflection) == pytest.approx(
                float(every[0].tip_deflection), abs=1e-9
            )
        for p in picked:
            if p.status == 0:
                back = hairbed.solve_pillar_inverse(float(p.tip_deflection), theta0)
                assert float(back.forcing) == pytest.approx(sign * lam, rel=1e-9)


def test_a_window_state_is_found_in_its_cell_where_newton_strays(monkeypatch):
    """Where the forward Newton from the branch grid fails or lands outside its crossing's
    cell (another state of the window), root= solves Lambda(x1) = forcing in that cell (the
    Illinois method on the inverse): here every forward Newton of the branch is made to fail,
    and the states are those of the normal path, each a true state."""
    from hairbed._core import pillar as core

    lam = np.array([37.0, 37.4689, 16.0, 15.9857, 60.0])
    normal = {r: hairbed.solve_pillar(lam, -1.5, root=r) for r in ("low", "mid", "high")}
    run = core._kernel_run

    def failing(code, *args, **kwargs):
        out, coefs = run(code, *args, **kwargs)
        if code == core._DRAG:  # theta0 = -1.5: only the branch's forward Newton
            out = out.copy()
            out[0] = -7
        return out, coefs

    monkeypatch.setattr(core, "_kernel_run", failing)
    for root, ref in normal.items():
        st = hairbed.solve_pillar(lam, -1.5, root=root)
        status = np.asarray(st.status)
        assert np.array_equal(status, np.asarray(ref.status)), root
        ok = status == 0
        x1, x_ref = np.asarray(st.tip_deflection), np.asarray(ref.tip_deflection)
        assert np.allclose(x1[ok], x_ref[ok], rtol=0, atol=1e-10), root
        back = core.solve_pillar_inverse(x1[ok], -1.5)
        assert np.allclose(back.forcing, lam[ok], rtol=1e-12, atol=0), root
        assert np.all(np.isfinite(np.asarray(st.tip_angle)[ok]))


def test_a_ramp_through_the_window_is_monotone():
    """root="low" along a ramp of the forcing through the window jumps once, upwards, at the
    upper fold (the quasi-static ramp from rest)."""
    lam = np.linspace(5.0, 30.0, 400)
    st = hairbed.solve_pillar(lam, -1.4)
    x1 = np.asarray(st.tip_deflection)
    assert np.all(np.asarray(st.status) == 0)
    steps = np.diff(x1)
    assert np.all(steps > 0)
    jump = int(np.argmax(steps))
    fold = max(hairbed.continue_pillar(40.0, -1.4).folds[:, 0])
    assert lam[jump] <= fold <= lam[jump + 1]


def test_branch_near_the_wall_is_whole_and_its_folds_do_not_depend_on_the_grid():
    """theta0 = -1.5 (the pillar nearly on the wall): every inverse state of the branch near
    rest is found, each round-trips through the forward solver on its own root, and the folds
    are extrema of Lambda(x1) whatever the grid (they were misplaced by missing points)."""
    x = np.linspace(-0.9935, -0.984, 20)
    inv = hairbed.solve_pillar_inverse(x, -1.5)
    assert np.all(np.asarray(inv.status) == 0)
    # below the upper fold (x1 = -0.98975) the low state, above it the middle one; within
    # about 0.2 % of the fold's forcing the branch grid of root= cannot tell the pair apart
    # (theory.md §12), so the points there are left out of the round trip
    lam = np.asarray(inv.forcing)
    for root, part in (("low", x < -0.9904), ("mid", x > -0.9886)):
        fwd = hairbed.solve_pillar(lam[part], -1.5, root=root)
        assert np.asarray(fwd.tip_deflection) == pytest.approx(x[part], abs=1e-10)
    single = hairbed.solve_pillar_inverse(-0.992, -1.5)  # alone, no neighbour to start from
    assert single.status == 0
    folds = [
        np.sort(hairbed.continue_pillar(100.0, -1.5, num=n).folds[:, 0]) for n in (64, 200, 301)
    ]
    for f in folds[1:]:
        assert f == pytest.approx(folds[0], rel=1e-10)
    # the upper fold is a maximum of Lambda(x1): above every solved point near it
    assert folds[0][1] >= lam.max() and folds[0][1] - lam.max() < 1e-2


@pytest.mark.parametrize("theta0, forcing", [(-1.45, 20.0), (-1.4, 15.0)])
def test_flow_towards_minus_x_is_the_mirror_image(theta0, forcing):
    """Lambda -> -Lambda with theta0 -> -theta0 is the mirror image x -> -x (theory.md §12):
    the folds of the branch and every coexisting state, with its stability, mirrored."""
    br = hairbed.continue_pillar(2 * forcing, theta0, num=150)
    mr = hairbed.continue_pillar(-2 * forcing, -theta0, num=150)
    assert mr.folds[:, 0] == pytest.approx(-br.folds[:, 0], rel=1e-12)
    states = hairbed.solve_pillar_all(forcing, theta0)
    mirrored = hairbed.solve_pillar_all(-forcing, -theta0)
    assert len(states) == len(mirrored) == 3
    for s, m in zip(states, reversed(mirrored)):
        assert m.tip_deflection == pytest.approx(-s.tip_deflection, abs=1e-12)
        assert m.stable == s.stable
    assert [s.stable for s in states] == [True, False, True]
