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


def test_the_fold_check_and_the_solve() -> None:
    """One LU per state: the solve of J du = -dR/dp column by column against the residual,
    and a fold (kappa_1(J) >= 1e14, estimated from the factors), a zero pivot or a non-finite
    J leave the derivatives unset (NaN, status 1)."""
    from hairbed._core.porous_sensitivity import _solve_checked

    rng = np.random.default_rng(7)
    jac = rng.standard_normal((40, 40)) + 40.0 * np.eye(40)
    rhs = rng.standard_normal((40, 6))
    out = np.full((40, 6), np.nan)
    assert _solve_checked(jac, rhs, out)
    assert np.max(np.abs(jac @ out + rhs)) < 1e-13 * np.max(np.abs(rhs))
    # rank one short by 1e-15 of its scale: kappa ~ 1e15, above the fold's bound
    u, _, vt = np.linalg.svd(rng.standard_normal((40, 40)))
    near = u @ np.diag(np.r_[np.ones(39), 1e-15]) @ vt
    fine = u @ np.diag(np.r_[np.ones(39), 1e-12]) @ vt  # kappa ~ 1e12: below it
    assert _solve_checked(fine, rhs, out)
    # backward stable: the residual at rounding of |J| |x| (|x| ~ 1e12 here)
    assert np.max(np.abs(fine @ out + rhs)) < 1e-13 * np.max(np.abs(out))
    singular = jac.copy()
    singular[:, 3] = singular[:, 5]
    nan = jac.copy()
    nan[2, 2] = np.nan
    for bad in (near, singular, nan, np.zeros((40, 40))):
        out = np.full((40, 6), np.nan)
        assert not _solve_checked(bad, rhs, out)
        assert np.all(np.isnan(out))
