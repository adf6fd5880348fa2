"""The stored linear bed (tests/data/bed_linear_mpmath.json, issue 30) in its static limit.

The generator (tests/reference/generate_bed_linear.py, mpmath only) solves the straight bed's
small motion X(z), v(z) e^{i omega t} by two methods that agree to 1e-25; at omega = 0 it must
be the straight bed's linear Brinkman theory of theory.md §13, which hairbed evaluates (by its
own quadrature) to start every porous solve: the wall drive per unit V [L/T] is the forcing
omega2 = eps kappa V, the pressure drive per unit Pi.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from hairbed._core.porous import _linear_deflection

DATA = Path(__file__).resolve().parent / "data" / "bed_linear_mpmath.json"


def test_static_limit_is_the_linear_brinkman_theory() -> None:
    doc = json.loads(DATA.read_text())
    assert not doc["quick"] and doc["agree_tol"] <= 1e-25
    cases = doc["responses"]
    assert len(cases) >= 12
    kap = np.array([c["kappa"] for c in cases])
    eps = np.array([c["eps"] for c in cases])
    rows = [c["responses"][0] for c in cases]
    assert all(r["omega"] == 0.0 for r in rows)
    wall = np.array([r["wall"]["tip_deflection"] for r in rows])
    press = np.array([r["pressure"]["tip_deflection"] for r in rows])
    assert np.all(wall[:, 1] == 0.0) and np.all(press[:, 1] == 0.0)
    zero = np.zeros_like(kap)
    x_wall = _linear_deflection(eps * kap, eps, kap, zero)
    x_press = _linear_deflection(zero, eps, kap, zero + 1.0)
    assert np.max(np.abs(x_wall / wall[:, 0] - 1.0)) < 1e-12
    assert np.max(np.abs(x_press / press[:, 0] - 1.0)) < 1e-12
    # the omega grid spans 1e-3 to 1e4 and kappa 1e-3 to 1e3
    om = [r["omega"] for r in cases[0]["responses"]]
    assert om[1] == 1e-3 and om[-1] == 1e4
    assert kap.min() == 1e-3 and kap.max() == 1e3
