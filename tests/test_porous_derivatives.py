"""Exact derivatives of porous states against Richardson differences of the solver."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import hairbed
from hairbed._core.porous_sensitivity import porous_derivatives


def _solve(b: dict[str, Any]) -> Any:
    rest = {k: v for k, v in b.items() if k not in ("omega2", "eps", "theta0")}
    return hairbed.solve_porous(b["omega2"], b["eps"], b["theta0"], **rest)


def _richardson(f: Any, x: float, h: float) -> np.ndarray:
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


@pytest.mark.parametrize(
    "base",
    [
        dict(omega2=2.0, eps=0.5, theta0=0.3, kappa=0.05, gamma=0.7, pi=0.0),
        dict(omega2=0.5, eps=0.6, theta0=-0.4, kappa=3.0, gamma=0.9, pi=1.5),
        dict(omega2=0.5, eps=0.5, theta0=0.2, kappa=2e-3, gamma=0.6, q=1.0),
    ],
    ids=["wall", "pressure", "flow"],
)
def test_every_derivative_against_richardson_differences(base: dict[str, Any]) -> None:
    d = porous_derivatives(_solve(base))
    assert d.status == 0
    outs = list(d.table)
    for p in d.table["tip_height"]:

        def f(x: float, p: str = p) -> np.ndarray:
            b = dict(base)
            b[p] = x
            st = _solve(b)
            return np.array([float(getattr(st, o)) for o in outs])

        h = 1e-4 * (abs(base[p]) or 1.0)  # relative: kappa spans decades
        num = _richardson(f, base[p], h)
        exact = np.array([d.table[o][p] for o in outs])
        err = np.abs(num - exact) / np.maximum(1.0, np.abs(exact))
        assert np.all(err < 1e-8), (p, dict(zip(outs, err)))


def test_arrays_are_their_elements() -> None:
    st = hairbed.solve_porous([1.0, 2.0], 0.5, [[0.1], [0.4]], kappa=[0.01, 1.0])
    d = porous_derivatives(st)
    one = porous_derivatives(hairbed.solve_porous(2.0, 0.5, 0.4, kappa=1.0))
    assert np.shape(d.table["tip_deflection"]["kappa"]) == (2, 2)
    assert d.table["tip_deflection"]["kappa"][1, 1] == pytest.approx(
        one.table["tip_deflection"]["kappa"], rel=1e-12
    )
    with pytest.raises(TypeError, match="PorousState"):
        porous_derivatives(hairbed.solve(2.0, 0.5))  # type: ignore[arg-type]
