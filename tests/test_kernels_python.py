"""A sample of the mpmath reference through the whole solver, for the run without the JIT.

``make test`` runs this file (with the kernel tests) a second time under
``NUMBA_DISABLE_JIT=1``, where every kernel executes as plain Python: that run checks that the
kernels' source is itself correct Python, and lets coverage tools see it. Under the JIT it is a
quick cross-section of test_reference.py. Every group of the reference is represented:
physical corners, bistable windows, twirling branches on both signs, empty branches.
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest
from conftest import DATA
from tolerances import ATOL, RTOL

import hairbed

REFERENCE = json.loads((DATA / "reference_mpmath.json").read_text())
SIGMA = np.array(REFERENCE["metadata"]["sigma"], dtype=np.float64)
FIELDS = ("xi", "omega_eps", "energy", "tip_height", "tip_deflection", "tip_angle")


def _sample() -> list[dict[str, Any]]:
    """Two cases of every group (first and last), deterministic."""
    by_group: dict[str, list[dict[str, Any]]] = {}
    for case in REFERENCE["cases"]:
        by_group.setdefault(case["group"], []).append(case)
    out = []
    for cases in by_group.values():
        out += [cases[0], cases[-1]] if len(cases) > 1 else cases
    return out


SAMPLE = _sample()


@pytest.mark.parametrize("case", SAMPLE, ids=[c["id"] for c in SAMPLE])
def test_solver_matches_reference(case: dict[str, Any]) -> None:
    roots = case["roots"]
    names = ["low", "mid", "high"] if len(roots) == 3 else ["low", "high"][: len(roots)]
    sol = hairbed.solve(
        case["omega2"], case["eps"], case["theta0"], sign=case["sign"], n=case["n"]
    )
    assert sol.n_roots == case["n_roots"]
    if not roots:
        assert sol.status == -1 and np.isnan(sol.xi)
        return
    for name, ref in zip(names, roots if len(roots) != 2 else [roots[0], roots[-1]]):
        s = hairbed.solve(
            case["omega2"], case["eps"], case["theta0"], sign=case["sign"], n=case["n"], root=name
        )
        assert s.status == 0
        for f in FIELDS:
            np.testing.assert_allclose(getattr(s, f), float(ref[f]), rtol=RTOL, atol=ATOL)
        for f in ("theta", "x", "z"):
            want = np.array([float(v) for v in ref[f]])
            np.testing.assert_allclose(getattr(s, f)(SIGMA), want, rtol=RTOL, atol=ATOL)


def test_solve_all_and_from_parameter() -> None:
    states = hairbed.solve_all(50.0, 0.5)
    assert [(s.sign, s.n) for s in states] == [(1, 0), (-1, 0), (1, 1)]
    for s in states:
        back = hairbed.from_parameter(s.t, 0.5, sign=s.sign, n=s.n)
        np.testing.assert_allclose(back.omega2, 50.0, rtol=1e-12)
