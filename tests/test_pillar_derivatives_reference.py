"""Derivatives of pillar states against the independent mpmath reference (issue 21).

tests/data/pillar_derivatives_mpmath.json (tests/reference/generate_pillar_derivatives.py):
central differences, at 40+ digits, of the mpmath shooting of generate_pillar.py (which shares
no code with the solver) in Lambda, theta0, gamma and the Poiseuille height ratio, on states
of the sublayer, Poiseuille, Couette and U = z^2 profiles, tilted both ways.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from tolerances import PILLAR_DERIVATIVE_REFERENCE_RTOL

import hairbed
from hairbed.sensitivity import derivatives_at

DATA = Path(__file__).parent / "data" / "pillar_derivatives_mpmath.json"


def _square(z):
    return z * z


def test_against_mpmath_central_differences() -> None:
    cases = json.loads(DATA.read_text())["cases"]
    assert len(cases) >= 8
    assert {c["profile"] for c in cases} >= {"sublayer", "poiseuille", "couette", "callable"}
    assert min(c["theta0"] for c in cases) < -1.0 and max(c["theta0"] for c in cases) > 1.0
    worst, count = 0.0, 0
    for c in cases:
        profile = _square if c["profile"] == "callable" else c["profile"]
        ratio = c["height_ratio"]
        st = hairbed.solve_pillar(
            c["forcing"], c["theta0"], profile=profile, height_ratio=ratio, gamma=float(c["gamma"])
        )
        assert st.success
        for o, ref in c["state"].items():  # the same state
            assert abs(getattr(st, o) - float(ref)) <= 1e-10 * max(1.0, abs(float(ref)))
        d = derivatives_at(st, profile=profile, height_ratio=ratio)
        assert d.success
        for o, row in c["d"].items():
            for name, ref in row.items():
                r = float(ref)
                err = abs(d[o][name] - r) / max(1.0, abs(r))
                worst = max(worst, err)
                count += 1
                assert err <= PILLAR_DERIVATIVE_REFERENCE_RTOL, (
                    c["profile"],
                    c["theta0"],
                    o,
                    name,
                )
    assert count >= 8 * 6 * 3
    assert np.isfinite(worst)
