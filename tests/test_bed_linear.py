"""The porous bed's linear dynamics (issue 30) against the independent mpmath reference.

tests/data/bed_linear_mpmath.json (tests/reference/generate_bed_linear.py, two methods agreeing
to 1e-25) holds the straight bed's transfer functions per unit wall speed V [L/T] and per unit
Pi; the wall drive of ``linearise_bed`` is per unit omega2 = eps kappa V. The errors are
relative to the larger of the value and its static value (at high frequency a response is a
cancellation far below its scale).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed.dynamics import linearise_bed

DATA = json.loads(
    (Path(__file__).resolve().parent / "data" / "bed_linear_mpmath.json").read_text()
)
TOL = 1e-10
#: (kappa, eps, alpha, mu) and the largest omega tested (the cost of larger degrees)
CASES = {
    (1.0, 0.5, 0.0, 0.0): 1e4,
    (1e-3, 0.8, 1.0, 13.0): 100.0,
    (0.1, 0.25, 0.1, 0.0): 100.0,
    (1.0, 0.9, 10.0, 0.0): 31.7,
    (1e3, 0.5, 0.01, 13.0): 10.0,
}
PAIRS = (
    ("tip_deflection", "tip_deflection"),
    ("wall_stress", "top_stress"),
    ("base_moment", "base_moment"),
)


def _case(key):
    for c in DATA["responses"]:
        if (c["kappa"], c["eps"], c["alpha"], c["mu"]) == key:
            return c
    raise KeyError(key)


def test_transfer_functions_against_mpmath() -> None:
    worst = 0.0
    for key, top in CASES.items():
        kappa, eps, alpha, mu = key
        case = _case(key)
        # omega = 0 and whole decades (the stored grid has half decades)
        rows = [
            r
            for r in case["responses"]
            if r["omega"] <= top and (r["omega"] == 0.0 or abs(math.log10(r["omega"]) % 1) < 1e-9)
        ]
        om = np.array([r["omega"] for r in rows])
        lin = linearise_bed(
            hairbed.solve_porous(0.0, eps, kappa=kappa), inertia=mu, womersley=alpha
        )
        assert lin.drives == ("wall", "pressure")
        for drive, scale in (("wall", 1.0 / (eps * kappa)), ("pressure", 1.0)):
            fr = lin.frequency_response(om, drive)
            assert np.all(fr.status == 0) and np.all(fr.success)
            for name, ref in PAIRS:
                want = np.array([complex(*r[drive][ref]) for r in rows]) * scale
                err = np.abs(getattr(fr, name) - want) / np.maximum(abs(want), abs(want[0]))
                worst = max(worst, float(err.max()))
                assert err.max() < TOL, (key, drive, name, float(err.max()))
    assert worst > 0.0


def test_many_frequencies_against_mpmath() -> None:
    """A band of 64 frequencies or more takes the modal form where its checks pass, else the
    Schur form: the same reference, the same 1e-10, on every stored frequency (half decades,
    each asked 64 times: the first kappa = 1 bed and the bed at alpha = 10 are modal, those
    with mu = 13 fall back)."""
    worst, methods = 0.0, set()
    for key, top in CASES.items():
        kappa, eps, alpha, mu = key
        rows = [r for r in _case(key)["responses"] if r["omega"] <= top]
        om = np.array([r["omega"] for r in rows])
        reps = 64
        lin = linearise_bed(
            hairbed.solve_porous(0.0, eps, kappa=kappa), inertia=mu, womersley=alpha
        )
        for drive, scale in (("wall", 1.0 / (eps * kappa)), ("pressure", 1.0)):
            fr = lin.frequency_response(np.tile(om, reps), drive)
            assert np.all(fr.status == 0)
            methods |= set(fr.method)
            for name, ref in PAIRS:
                want = np.array([complex(*r[drive][ref]) for r in rows]) * scale
                got = getattr(fr, name).reshape(reps, -1)
                err = np.abs(got - want) / np.maximum(abs(want), abs(want[0]))
                worst = max(worst, float(err.max()))
                assert err.max() < TOL, (key, drive, name, float(err.max()))
    assert methods == {"modal", "schur"} and worst > 0.0


def test_pillar_limit_modes() -> None:
    """At large kappa the bed's hair modes tend to the cantilever's, lambda = -beta^4
    (1 + cos beta cosh beta = 0) overdamped and mu lambda^2 + lambda + beta^4 = 0 with inertia,
    like 1/kappa; at kappa = 1e3 they equal the reference's roots of the bed's own
    determinant within 1e-10."""
    betas = np.array(DATA["betas"])
    for mode in DATA["modes"]:
        if mode["kappa"] != 1e3:
            continue
        mu = mode["mu"]
        lin = linearise_bed(hairbed.solve_porous(0.0, mode["eps"], kappa=1e3), inertia=mu)
        got = lin.modes(8 if mu else 4)
        lam = got.eigenvalues
        if mu:
            lam = lam[lam.imag > 0]
        want = np.array([complex(*x) for x in mode["eigenvalues"]])
        assert np.max(np.abs(lam[:4] - want) / np.abs(want)) < TOL
        assert got.success and got.num == 32
    # the approach to the cantilever, overdamped: the gap closes like 1/kappa
    gaps = []
    for kappa in (1e2, 1e3, 1e4):
        lam = linearise_bed(hairbed.solve_porous(0.0, 0.5, kappa=kappa)).modes(2).eigenvalues
        gaps.append(np.abs(lam.real + betas[:2] ** 4) / betas[:2] ** 4)
    rate = np.log10(gaps[2] / gaps[1])
    assert np.all(np.abs(rate + 1.0) < 0.05), rate
    assert np.all(np.abs(np.log10(gaps[1] / gaps[0]) + 1.0) < 0.1)


def test_bad_input_and_results() -> None:
    st = hairbed.solve_porous(0.5, 0.5, 0.2, kappa=0.5)
    lin = linearise_bed(st)
    with pytest.raises(ValueError, match="drive must be one of"):
        lin.frequency_response(1.0, "flow_rate")
    with pytest.raises(ValueError, match="omega must be finite and >= 0.*index 1"):
        lin.frequency_response([1.0, -2.0])
    with pytest.raises(ValueError, match="num must be an integer in \\[8, 128\\]"):
        lin.frequency_response(1.0, num=256)
    with pytest.raises(TypeError, match="PorousState"):
        linearise_bed(hairbed.solve_pillar(1.0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="womersley"):
        linearise_bed(st, womersley=-1.0)
    with pytest.raises(ValueError, match="one state"):
        linearise_bed(hairbed.solve_porous([0.1, 0.2], 0.5, kappa=1.0))
    # a tilted, deflected state: stable, and the static limit is the solver's derivative
    assert lin.stable and lin.growth_rate() < 0.0
    fr = lin.frequency_response([0.0, 1.0, 3e8])
    assert fr.status.tolist() == [0, 0, 3] and fr.success.tolist() == [True, True, False]
    assert lin.frequency_response([1.0, 1e6], num=32).status.tolist() == [0, 3]
    h = 1e-6
    up = hairbed.solve_porous(0.5 + h, 0.5, 0.2, kappa=0.5)
    dn = hairbed.solve_porous(0.5 - h, 0.5, 0.2, kappa=0.5)
    dx = (float(up.tip_deflection) - float(dn.tip_deflection)) / (2 * h)
    assert abs(fr.tip_deflection[0] - dx) < 1e-8 * abs(dx)
    # a state of the flow drive (Pi the unknown that holds q): the static limit in q
    flow = linearise_bed(hairbed.solve_porous(0.5, 0.5, 0.2, q=1.0, kappa=0.5))
    assert flow.drives == ("wall", "flow_rate")
    fq = flow.frequency_response([0.0], "flow_rate")
    h = 1e-5
    up, dn = (hairbed.solve_porous(0.5, 0.5, 0.2, q=1.0 + d, kappa=0.5) for d in (h, -h))

    def top(st):  # the top wall's stress Q(h1) - Pi g of the gap's exact profile
        return float(st.tip_stress) - float(st.pi) * (2.0 - float(st.tip_height))

    dx = (float(up.tip_deflection) - float(dn.tip_deflection)) / (2 * h)
    assert abs(fq.tip_deflection[0] - dx) < 1e-8 * abs(dx)
    dq = (top(up) - top(dn)) / (2 * h)
    assert abs(fq.wall_stress[0] - dq) < 1e-8 * abs(dq)
    assert abs(fq.flow_rate[0] - 1.0) < 1e-12
    # 80 frequencies: the modal form (the flow rate under the wall drive vanishes
    # identically; the check judges it against the largest output), equal to one LU per
    # frequency of a fresh linearisation
    om = np.geomspace(1e-2, 10.0, 80)
    many = flow.frequency_response(om, "wall")
    few = linearise_bed(flow.state).frequency_response(om[::8], "wall")
    assert set(many.method) == {"modal"} and set(few.method) == {"lu"}
    assert np.max(np.abs(many.flow_rate)) < 1e-10
    for name in ("tip_deflection", "wall_stress", "base_moment"):
        a, b = getattr(many, name)[::8], getattr(few, name)
        assert np.max(np.abs(a - b) / np.maximum(abs(b), abs(b[0]))) < 1e-10, name
    ds = fr.to_xarray()
    assert ds["wall_stress_gain"].attrs["units"] == "E I/(A L^2)"
    assert ds["omega"].attrs["units"] == "1/T" and math.isclose(ds.attrs["inertia"], 0.0)
