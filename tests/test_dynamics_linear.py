"""Linear pillar dynamics (issue 30, theory.md §14): hairbed.dynamics.linearise_pillar.

References, written here from the equations and sharing no code with the solver:

- the Euler-Bernoulli cantilever with drag and mass, W'''' - k^4 W = p(s), k^4 = mu omega^2 -
  i omega, W(0) = W'(0) = 0, W''(1) = 0, W'''(1) = -P, solved in mpmath by the Krylov
  functions of k s for a tip load, a uniform load and the sublayer's linear load p = s;
- its eigenvalues from 1 + cos(beta) cosh(beta) = 0 (mpmath roots): lambda = -beta^4 when
  overdamped, mu lambda^2 + lambda + beta^4 = 0 with inertia;
- the tilted straight pillar: normal motion only, its load cos(theta0) of the horizontal one;
- at omega -> 0, central differences of the static solver at a large deflection.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from tolerances import DYNAMICS_LINEAR_RTOL, PILLAR_DERIVATIVE_FD_RTOL

import hairbed
from hairbed.dynamics import hydrodynamic_function, linearise_pillar, sader_drag_ratio

OMEGA = np.logspace(-3.0, 4.0, 15)
MUS = (0.0, 1.0, 13.0)


def _uniform(z: np.ndarray) -> np.ndarray:
    return np.ones_like(z)


def _cantilever(
    omega: float, mu: float, load: str, drag: complex = 1.0
) -> tuple[complex, complex]:
    """(tip deflection W(1), base curvature W''(0)) per unit load, in mpmath; ``drag`` a
    complex multiple of the normal drag (k^4 = mu omega^2 - i omega drag)."""
    k4 = mp.mpf(mu) * mp.mpf(omega) ** 2 - 1j * mp.mpf(omega) * mp.mpc(drag)
    k = mp.sqrt(mp.sqrt(k4))
    with mp.workdps(30 + int(abs(k))):  # cosh(k) ~ e^|k| cancels in the 2 x 2 solve
        k4 = mp.mpf(mu) * mp.mpf(omega) ** 2 - 1j * mp.mpf(omega) * mp.mpc(drag)
        k = mp.sqrt(mp.sqrt(k4))

        def kry(x: mp.mpf) -> tuple[mp.mpc, ...]:
            ch, co, sh, si = mp.cosh(k * x), mp.cos(k * x), mp.sinh(k * x), mp.sin(k * x)
            return (
                (ch + co) / 2,
                (sh + si) / (2 * k),
                (ch - co) / (2 * k**2),
                (sh - si) / (2 * k**3),
            )

        k1, k2, k3, k4f = kry(mp.mpf(1))
        tip = 0
        if load == "tip":
            wp = (0, 0, 0, 0)  # the particular solution and its derivatives at s = 1
            tip = 1
        elif load == "uniform":  # W_p = (K1 - 1)/k^4
            wp = ((k1 - 1) / k4, k4f, k3, k2)
        else:  # p = s: W_p = (K2 - s)/k^4
            wp = ((k2 - 1) / k4, (k1 - 1) / k4, k4f, k3)
        # W = C3 K3 + C4 K4 + W_p: W''(1) = 0, W'''(1) = -P
        mat = mp.matrix([[k1, k2], [k4 * k4f, k1]])
        c3, c4 = mp.lu_solve(mat, mp.matrix([-wp[2], -tip - wp[3]]))
        return complex(c3 * k3 + c4 * k4f + wp[0]), complex(c3)


@pytest.fixture(scope="module")
def straight() -> dict[str, object]:
    return {
        "tip": hairbed.solve_pillar(0.0),
        "uniform": hairbed.solve_pillar(0.0, profile=_uniform),
        "linear": hairbed.solve_pillar(0.0),
    }


@pytest.mark.parametrize("mu", MUS)
@pytest.mark.parametrize("load", ["tip", "uniform", "linear"])
def test_straight_cantilever_krylov(straight: dict, load: str, mu: float) -> None:
    prof = _uniform if load == "uniform" else "sublayer"
    lin = linearise_pillar(straight[load], profile=prof, mu=mu)
    r = lin.frequency_response(OMEGA, "tip_load" if load == "tip" else "forcing")
    assert np.all(r.success) and r.omega.shape == OMEGA.shape
    for i, om in enumerate(OMEGA):
        w1, m0 = _cantilever(float(om), mu, load)
        # relative to the deflection's scale: at high frequency a uniform load's tip response
        # is a cancellation (1e-3 of the base layer's deflection m0/|k|^2 at mu = 13, omega =
        # 3e3), so its own relative error is not the solver's
        k2 = abs(complex(mu * om * om, -om)) ** 0.5
        scale = max(abs(w1), abs(m0) / (1.0 + k2))
        assert abs(r.tip_deflection[i] - w1) <= DYNAMICS_LINEAR_RTOL * scale, (om, i)
        assert abs(r.base_moment[i] - m0) <= DYNAMICS_LINEAR_RTOL * abs(m0), (om, i)
        assert abs(r.tip_height[i]) <= DYNAMICS_LINEAR_RTOL * scale  # second order


def test_static_limits_of_the_closed_forms(straight: dict) -> None:
    """omega -> 0: the static cantilever's 1/3 (tip force), 1/8 (uniform), 11/120 (p = s)."""
    for load, want in (("tip", 1 / 3), ("uniform", 1 / 8), ("linear", 11 / 120)):
        prof = _uniform if load == "uniform" else "sublayer"
        r = linearise_pillar(straight[load], profile=prof).frequency_response(
            0.0, "tip_load" if load == "tip" else "forcing"
        )
        assert abs(r.tip_deflection[0] - want) <= DYNAMICS_LINEAR_RTOL * want
        assert abs(r.tip_deflection[0].imag) <= 1e-15


def _beta(n: int) -> mp.mpf:
    with mp.workdps(40):
        return mp.findroot(lambda b: 1 + mp.cos(b) * mp.cosh(b), (2 * n - 1) * mp.pi / 2)


@pytest.mark.parametrize("mu", MUS)
@pytest.mark.parametrize("theta0", [0.0, 0.7])
def test_eigenvalues_of_the_cantilever(mu: float, theta0: float) -> None:
    modes = linearise_pillar(hairbed.solve_pillar(0.0, theta0), mu=mu).modes(8)
    assert modes.success and modes.shapes.shape == (8, modes.s.size)
    want = []
    for n in range(1, 5):
        b4 = complex(_beta(n) ** 4)
        if mu == 0.0:
            want.append(-b4)
        else:  # mu lambda^2 + lambda + beta^4 = 0
            disc = np.sqrt(complex(1.0 - 4.0 * mu * b4))
            want += [(-1.0 - disc) / (2 * mu), (-1.0 + disc) / (2 * mu)]
    want = np.array(want)
    want = want[np.lexsort((want.imag, np.abs(want)))][: 4 if mu == 0.0 else 8]
    got = modes.eigenvalues[: want.size]
    err = np.abs(got[None, :] - want[:, None]).min(axis=1)  # a pair's order is free
    assert np.all(err <= DYNAMICS_LINEAR_RTOL * np.abs(want)), (got, want)
    assert np.all(modes.damping_ratio[: want.size] > 0.0)


@pytest.mark.parametrize("mu", [1e8, 1e20, 1e100, 1e300])
def test_heavy_pillars_keep_their_decay_rates(mu: float) -> None:
    """A heavy pillar rings for ~mu periods: its decay rate Re lambda = -1/(2 mu) is
    1/sqrt(mu) of its frequency, and must keep its own relative precision (mu = 1e20 once
    gave a growing mode, 1e30 no mode at all). mpmath roots of mu lambda^2 + lambda + beta^4."""
    modes = linearise_pillar(hairbed.solve_pillar(0.0), mu=mu).modes(4)
    assert modes.success
    for k, n in enumerate((1, 1, 2, 2)):
        with mp.workdps(40):
            im = mp.sqrt(4 * mp.mpf(mu) * _beta(n) ** 4 - 1) / (2 * mp.mpf(mu))
            re = -1 / (2 * mp.mpf(mu))
        got = modes.eigenvalues[k]
        assert abs(got.real - float(re)) <= DYNAMICS_LINEAR_RTOL * abs(float(re)), (k, got)
        assert abs(abs(got.imag) - float(im)) <= DYNAMICS_LINEAR_RTOL * float(im), (k, got)


@pytest.mark.parametrize("mu", [0.0, 13.0])
def test_tilted_straight_pillar_moves_normally(mu: float) -> None:
    """Tilted at theta0, at rest: the horizontal tip force's normal part is P cos(theta0),
    the sublayer's normal load Lambda s cos^2(theta0); the tip moves along the normal
    (cos theta0, -sin theta0)."""
    t0 = 0.7
    c, s = np.cos(t0), np.sin(t0)
    lin = linearise_pillar(hairbed.solve_pillar(0.0, t0), mu=mu)
    om = np.array([1e-2, 0.9, 30.0, 2e3])
    for drive, load, scale in (("tip_load", "tip", c), ("forcing", "linear", c * c)):
        r = lin.frequency_response(om, drive)
        w = np.array([_cantilever(float(x), mu, load)[0] for x in om]) * scale
        tol = DYNAMICS_LINEAR_RTOL * np.abs(w)
        assert np.all(np.abs(r.tip_deflection - c * w) <= tol)
        assert np.all(np.abs(r.tip_height + s * w) <= tol)


@pytest.mark.parametrize(
    ("lam", "theta0", "gamma", "tip"), [(40.0, 0.3, 0.6, 0.0), (15.0, -1.0, 0.5, 0.3)]
)
def test_zero_frequency_is_the_static_derivative(
    lam: float, theta0: float, gamma: float, tip: float
) -> None:
    """At omega = 0 the response is the static state's derivative: central differences of
    solve_pillar (each perturbed state solved anew), at a large deflection."""
    st = hairbed.solve_pillar(lam, theta0, gamma=gamma, tip_load=tip)
    lin = linearise_pillar(st, mu=13.0)
    for drive, name in (("forcing", "forcing"), ("tip_load", "tip_load")):
        r = lin.frequency_response([0.0], drive)
        args = {"forcing": lam, "theta0": theta0, "gamma": gamma, "tip_load": tip}
        h = 1e-4
        fd = {}
        for sign in (1.0, -1.0):
            a = dict(args)
            a[name] += sign * h
            fd[sign] = hairbed.solve_pillar(**a)
        for out, attr in (
            ("tip_deflection", "tip_deflection"),
            ("tip_height", "tip_height"),
            ("base_moment", "base_curvature"),
        ):
            want = (getattr(fd[1.0], attr) - getattr(fd[-1.0], attr)) / (2 * h)
            got = getattr(r, out)[0]
            assert abs(got.imag) <= 1e-12 * max(1.0, abs(want))
            assert abs(got.real - want) <= PILLAR_DERIVATIVE_FD_RTOL * max(1e-2, abs(want)) * 10


@pytest.mark.parametrize("mu", (0.0, 13.0))
def test_profile_drive_is_the_cantilever_under_its_load(straight: dict, mu: float) -> None:
    """drive="profile": a flow change delta V(z) loads the straight pillar by V: V = 2 + 3 z
    (coefficients in 2 z - 1, and as a callable) is twice the uniform load's Krylov response
    plus three times the linear load's, at every frequency and through both solvers (a band
    of over 64 frequencies takes the Schur form)."""
    lin = linearise_pillar(straight["linear"], mu=mu)
    om = np.concatenate([OMEGA, np.logspace(0.0, 2.0, 70)])
    by_coef = lin.frequency_response(om, "profile", drive_profile=[3.5, 1.5])
    by_func = lin.frequency_response(OMEGA, "profile", drive_profile=lambda z: 2.0 + 3.0 * z)
    assert by_coef.drive == "profile" and np.all(by_coef.success)
    for i, w in enumerate(om):
        u1, u0 = _cantilever(float(w), mu, "uniform")
        s1, s0 = _cantilever(float(w), mu, "linear")
        w1, m0 = 2 * u1 + 3 * s1, 2 * u0 + 3 * s0
        k2 = abs(complex(mu * w * w, -w)) ** 0.5
        scale = max(abs(w1), abs(m0) / (1.0 + k2))
        assert abs(by_coef.tip_deflection[i] - w1) <= DYNAMICS_LINEAR_RTOL * scale, (w, i)
        assert abs(by_coef.base_moment[i] - m0) <= DYNAMICS_LINEAR_RTOL * abs(m0), (w, i)
        if i < OMEGA.size:
            assert abs(by_func.tip_deflection[i] - w1) <= DYNAMICS_LINEAR_RTOL * scale
    with pytest.raises(ValueError, match="drive_profile"):
        lin.frequency_response(1.0, "profile")
    with pytest.raises(ValueError, match="drive='profile'"):
        lin.frequency_response(1.0, drive_profile=[1.0])
    with pytest.raises(ValueError, match=r"drive_profile .*index 1"):
        lin.frequency_response(1.0, "profile", drive_profile=[1.0, np.inf])
    with pytest.raises(ValueError, match="1-D"):
        lin.frequency_response(1.0, "profile", drive_profile=[[1.0]])
    with pytest.raises(ValueError, match="drive_profile"):
        lin.frequency_response(1.0, "profile", drive_profile="sublayer")


def test_bad_inputs() -> None:
    st = hairbed.solve_pillar(5.0)
    with pytest.raises(ValueError, match="mu"):
        linearise_pillar(st, mu=-1.0)
    with pytest.raises(ValueError, match="tangential_mass"):
        linearise_pillar(st, tangential_mass=0.0)
    with pytest.raises(ValueError, match="profile"):
        linearise_pillar(st, profile="poiseuille", height_ratio=0.9)
    with pytest.raises(ValueError, match="one state"):
        linearise_pillar(hairbed.solve_pillar([1.0, 2.0]))
    with pytest.raises(TypeError, match="PillarState"):
        linearise_pillar(hairbed.solve(1.0, 0.5))  # type: ignore[arg-type]
    lin = linearise_pillar(st)
    with pytest.raises(ValueError, match=r"omega .* index 2"):
        lin.frequency_response([1.0, 2.0, -1.0])
    with pytest.raises(ValueError, match="omega"):
        lin.frequency_response(np.nan)
    with pytest.raises(ValueError, match="drive"):
        lin.frequency_response(1.0, "pressure")
    with pytest.raises(ValueError, match="num_modes"):
        lin.modes(0)


def test_beyond_resolution_is_flagged_and_xarray() -> None:
    lin = linearise_pillar(hairbed.solve_pillar(0.0), mu=13.0)
    r = lin.frequency_response([1.0, 1e5])
    assert list(r.status) == [0, 3] and r.success.tolist() == [True, False]
    assert "inaccurate" in r.message[1]
    pytest.importorskip("xarray")
    ds = r.to_xarray()
    assert ds["tip_deflection_gain"].dims == ("omega",)
    assert ds["omega"].attrs["units"] == "1/T" and ds.attrs["mu"] == 13.0
    assert np.allclose(
        ds["tip_deflection_real"] + 1j * ds["tip_deflection_imag"], r.tip_deflection
    )


@pytest.mark.parametrize(("mu", "low", "high"), [(0.0, 1e5, 1e6), (13.0, 80.0, 280.0)])
def test_a_band_through_the_schur_form(mu: float, low: float, high: float) -> None:
    """Many frequencies of one band above N = 32 (|k| in (16, 48]: N = 64) go through the
    Schur form and one step of iterative refinement."""
    om = np.linspace(low, high, 70)
    r = linearise_pillar(hairbed.solve_pillar(0.0), mu=mu).frequency_response(om, "tip_load")
    assert np.all(r.num == 64)
    want = np.array([_cantilever(float(x), mu, "tip")[0] for x in om])
    assert np.all(np.abs(r.tip_deflection - want) <= DYNAMICS_LINEAR_RTOL * np.abs(want))


def _gamma_mpmath(re: float) -> complex:
    """Sader's Gamma_circ in mpmath (J. Appl. Phys. 84, 64 (1998), eq. (20))."""
    with mp.workdps(40):
        root = mp.sqrt(1j * mp.mpf(re))
        arg = -1j * root
        return complex(1 + 4j * mp.besselk(1, arg) / (root * mp.besselk(0, arg)))


def test_hydrodynamic_function_against_mpmath() -> None:
    re = np.logspace(-4, 4, 17)
    got = hydrodynamic_function(re)
    want = np.array([_gamma_mpmath(float(x)) for x in re])
    assert np.all(np.abs(got - want) <= 1e-12 * np.abs(want))
    assert np.all(got.imag > 0.0) and abs(got[-1].real - 1.0) < 0.05  # -> potential flow
    with pytest.raises(ValueError, match="reynolds"):
        hydrodynamic_function([1.0, 0.0])


def test_unsteady_drag_response_is_the_cantilever_with_sader_drag() -> None:
    """With Sader's drag the straight cantilever is W'''' - k^4 W = p, k^4 = mu omega^2 -
    i omega D(omega), D from mpmath's Gamma; below the crossover D = 1 (quasi-steady)."""
    scale, slender, mu = 0.05, 20.0, 2.0
    lin = linearise_pillar(hairbed.solve_pillar(0.0), mu=mu)
    om = np.array([1e-4, 0.5, 3.0, 40.0, 500.0])
    r = lin.frequency_response(om, "tip_load", unsteady_drag=(scale, slender))
    log = np.log(2 * slender) + 0.5
    for i, w in enumerate(om):
        re = scale * w
        d = 1.0 if re < 2.0 / slender**2 else 1j * log * re * np.conj(_gamma_mpmath(re)) / 4
        want = _cantilever(float(w), mu, "tip", d)[0]
        assert abs(r.tip_deflection[i] - want) <= DYNAMICS_LINEAR_RTOL * abs(want), (w, d)
    assert sader_drag_ratio(1e-4, scale, slender) == 1.0
    quasi = lin.frequency_response(om[:1], "tip_load").tip_deflection[0]
    assert abs(r.tip_deflection[0] - quasi) <= DYNAMICS_LINEAR_RTOL * abs(quasi)
    with pytest.raises(ValueError, match="tangential_mass"):
        linearise_pillar(hairbed.solve_pillar(0.0), tangential_mass=0.5).frequency_response(
            1.0, unsteady_drag=(scale, slender)
        )


@pytest.mark.parametrize("mu", [0.0, 13.0])
def test_stability_of_the_snap_through_window(mu: float) -> None:
    """theta0 = -1.4, Lambda = 15: three states; the physical linearisation finds the middle
    one unstable (one real growing mode) and the others stable, as the branch's slope says
    (solve_pillar_all's ``stable``, a different method)."""
    states = hairbed.solve_pillar_all(15.0, -1.4)
    assert len(states) == 3
    for st in states:
        lin = linearise_pillar(st, mu=mu)
        assert lin.stable == bool(st.stable), (st.tip_deflection, lin.growth_rate())
        if not st.stable:
            grow = lin.modes(2).eigenvalues[0]
            # measured 2.37 overdamped, 0.389 at mu = 13 (near the root of 13 l^2 + l = 2.37)
            assert grow.real > (1.0 if mu == 0.0 else 0.1) and grow.imag == 0.0
