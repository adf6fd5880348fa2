"""Generate the high-precision derivatives in ``tests/data/derivatives_mpmath.json``.

Run on demand (about 20 minutes, most of it the cases t = 40 and 60 at 50 and 59 digits;
``--missing`` computes only the cases not yet in the file)::

    .venv/bin/python tests/reference/generate_derivatives.py

Nothing from :mod:`hairbed` is imported. Each case is a state given by its branch parameter t
on the branch (sign, n) at (eps, theta0) (theory.md §2, §9): xi - sin theta0 =
(1 - sin theta0) expit(t). The script computes, with mpmath at DPS digits,

* omega^2 of the state from the branch equation (the paper's eqs. (33), (34)) in Legendre
  form, mpmath's ``ellipk``/``ellipf`` at mu = (1 + xi)/2;
* the outputs independently of the package's closed forms: tip height and tip deflection by
  quadrature (``mpmath.quad``) of cos(theta) and sin(theta) = 2 mu sn^2(v | mu) - 1 along the
  closed-form shape theta = 2 arcsin(sqrt(mu) sn(v | mu)) - pi/2, v = v0 + sign omega_eps
  sigma (eq. (32)), with mpmath's ``ellipfun`` (theta functions); the tip angle as theta(1);
  the base curvature as theta'(0) = omega_eps^2 h1 (eq. (29)) with the quadrature's h1;
* the derivative of every output in omega2, eps and theta0 by ``mpmath.diff`` (numerical
  differentiation at raised working precision) of the composite map (omega2, eps, theta0) ->
  root t of ln omega^2(t) = ln omega2 (``mpmath.findroot`` from the state's t) -> outputs.

Strong forcing on the physical branch (t >= T_SEPARATRIX, omega^2 above ~3e4, where
1 - xi = (1 - sin theta0) expit(-t) < 1e-143 would need hundreds of digits, where a
quadrature of mpmath's theta functions takes hours) is computed on the separatrix instead,
carrying tau = ln p, p = (1 - xi)/2, and never xi itself: K(mu) = ln 4 - tau/2 (DLMF 19.12.1),
F(phi | mu) = atanh(sin phi) and the shape sn = tanh, cn = dn = sech (m = 1, DLMF §22.5),
all exact to O(sqrt(p)) < 1e-70 relative there; the tip height and deflection again by
quadrature of cos(theta) and sin(theta) = 2 tanh^2(v) - 1 along that shape, the tip angle
and xi from sin(theta1) = xi = 1 - 2 p (their derivatives from those of their tiny
distances to pi/2 and 1, which carry their digits).

Numbers are written as strings with 20 significant digits; inputs (t, eps, theta0) are JSON
numbers, read exactly as doubles by the test.
"""

from __future__ import annotations

import datetime
import json
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

__all__ = ["CASES", "compute_case", "main"]

#: Working precision [decimal digits].
DPS = 32
#: Outputs, as in hairbed.sensitivity.OUTPUTS.
OUTPUTS = (
    "xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_displacement",
    "tip_angle",
    "base_curvature",
)
INPUTS = ("omega2", "eps", "theta0")
#: (t, eps, theta0, sign, n): physical states from weak to strong forcing, leaning both
#: ways, the three states of a bistable window, and twirling branches.
CASES = (
    (-8.0, 0.5, 0.0, 1, 0),
    (-2.0, 0.3, 0.6, 1, 0),
    (0.0, 0.5, 0.0, 1, 0),
    (0.7, 0.9, 0.4, 1, 0),
    (1.5, 0.2, -0.7, 1, 0),
    (3.0, 0.6, 1.2, 1, 0),
    (6.0, 0.5, -0.3, 1, 0),
    (10.0, 0.3, 0.1, 1, 0),
    (-4.0, 0.9, -1.5, 1, 0),
    (-1.5, 0.9, -1.5, 1, 0),
    (1.0, 0.9, -1.5, 1, 0),
    (-2.5, 0.95, -1.2, 1, 0),
    (0.5, 0.0, 0.3, 1, 0),
    (1.0, 0.5, 0.2, -1, 0),
    (2.0, 0.4, -0.5, 1, 1),
    (4.0, 0.7, 0.3, -1, 1),
    (0.0, 0.5, 0.8, 1, 1),
    # weak forcing, where small displacements must keep their relative accuracy
    (-12.0, 0.5, 0.6, 1, 0),
    (-16.0, 0.3, -0.8, 1, 0),
    (-20.0, 0.7, 0.3, 1, 0),
    (-30.0, 0.5, 1.0, 1, 0),
    # moderate forcing near theta0 = 0, where d(x1 - sin theta0)/d theta0 vanishes to first order
    (-2.5, 0.25, -0.05, 1, 0),
    # strong forcing, on either side of the short arc's switch to its limit forms (t = 48)
    (40.0, 0.5, 0.3, 1, 0),
    (60.0, 0.5, 0.3, 1, 0),
    # strong forcing, omega^2 from 3e4 to 1e8 (on the separatrix, t >= T_SEPARATRIX): p
    # below 1e-150, subnormal (t = 730) and 0 in doubles (t > 745)
    (360.0, 0.5, 0.0, 1, 0),
    (446.0, 0.5, 0.0, 1, 0),
    (520.0, 0.9, -1.2, 1, 0),
    (610.0, 0.3, 0.8, 1, 0),
    (700.0, 0.99, -0.5, 1, 0),
    (730.0, 0.5, 0.3, 1, 0),
    (760.0, 0.0, -1.5, 1, 0),
    (1500.0, 0.7, 1.4, 1, 0),
    (20000.0, 0.5, 0.2, 1, 0),
)
#: From this t on the physical branch is computed on the separatrix (module docstring).
T_SEPARATRIX = 330.0


def _dps(t: float) -> int:
    """Working precision of a case: more at weak forcing (t << 0), where the tip
    displacement is ~exp(t) and its derivatives are differences of O(1) quadratures, and at
    strong forcing below T_SEPARATRIX (20 < t), where 1 - xi ~ exp(-t) must be resolved."""
    if 20.0 < t < T_SEPARATRIX:
        return DPS + round(0.45 * t)
    return DPS + max(0, round(-t / 2))


def _base(t: Any, theta0: Any) -> tuple[Any, ...]:
    s = mp.sin(theta0)
    q = 1 / (1 + mp.exp(-t))
    xi = s + (1 - s) * q
    return s, xi


def _branch(t: Any, eps: Any, theta0: Any, sign: int, n: int) -> dict[str, Any]:
    """omega^2 and the outputs of the state at t (Legendre forms, quadrature of the shape)."""
    s, xi = _base(t, theta0)
    mu = (1 + xi) / 2
    k = mp.ellipk(mu)
    phi0 = mp.asin(mp.sin(mp.pi / 4 + theta0 / 2) / mp.sqrt(mu))
    v0 = mp.ellipf(phi0, mu)
    oe = (2 * n + 1) * k - sign * v0
    h1_closed = sign * mp.sqrt(2 * (xi - s)) / oe
    omega2 = oe**2 * (1 - eps * h1_closed)

    def sn_dn(sigma: Any) -> tuple[Any, Any]:
        v = v0 + sign * oe * sigma
        return mp.ellipfun("sn", v, m=mu), mp.ellipfun("dn", v, m=mu)

    def sin_theta(sigma: Any) -> Any:
        sn, _ = sn_dn(sigma)
        return 2 * mu * sn**2 - 1

    def cos_theta(sigma: Any) -> Any:
        sn, dn = sn_dn(sigma)
        return 2 * mp.sqrt(mu) * sn * dn

    nodes = [mpf(i) / (4 * (n + 1)) for i in range(4 * (n + 1) + 1)]
    x1 = mp.quad(sin_theta, nodes)
    h1 = mp.quad(cos_theta, nodes)
    sn1, dn1 = sn_dn(1)
    tip_angle = 2 * mp.atan2(mp.sqrt(mu) * sn1, dn1) - mp.pi / 2
    return {
        "ln_omega2": mp.log(omega2),
        "h1_closed": h1_closed,
        "xi": xi,
        "omega_eps": oe,
        "energy": xi * oe**2,
        "tip_height": h1,
        "tip_deflection": x1,
        "tip_displacement": x1 - s,
        "tip_angle": tip_angle,
        "base_curvature": oe**2 * h1,
    }


def _ln_omega2(t: Any, eps: Any, theta0: Any, sign: int, n: int) -> Any:
    s, xi = _base(t, theta0)
    mu = (1 + xi) / 2
    phi0 = mp.asin(mp.sin(mp.pi / 4 + theta0 / 2) / mp.sqrt(mu))
    oe = (2 * n + 1) * mp.ellipk(mu) - sign * mp.ellipf(phi0, mu)
    return mp.log(oe**2 * (1 - eps * sign * mp.sqrt(2 * (xi - s)) / oe))


def _separatrix_base(t: Any, theta0: Any) -> tuple[Any, ...]:
    """sin theta0, xi - sin theta0, p = (1 - xi)/2 and tau = ln p, from t (never from xi)."""
    s = mp.sin(theta0)
    ln_qc = -t - mp.log1p(mp.exp(-t))  # ln expit(-t)
    tau = mp.log((1 - s) / 2) + ln_qc
    return s, (1 - s) / (1 + mp.exp(-t)), mp.exp(tau), tau


def _separatrix_oe(t: Any, theta0: Any) -> tuple[Any, ...]:
    s, d, p, tau = _separatrix_base(t, theta0)
    k = mp.log(4) - tau / 2  # K(1 - p), DLMF 19.12.1
    v0 = mp.atanh(mp.sin(mp.pi / 4 + theta0 / 2) / mp.sqrt(1 - p))  # F(phi0 | 1)
    return s, d, p, v0, k - v0


def _branch_separatrix(t: Any, eps: Any, theta0: Any, sign: int, n: int) -> dict[str, Any]:
    """:func:`_branch` of the physical branch at strong forcing, on the separatrix."""
    assert sign == 1 and n == 0, "the separatrix is the physical branch's limit"
    s, d, p, v0, oe = _separatrix_oe(t, theta0)
    h1_closed = mp.sqrt(2 * d) / oe
    omega2 = oe**2 * (1 - eps * h1_closed)
    layer = [mpf(0)] + [mpf(j) / oe for j in (1, 4, 16, 64) if j < oe] + [mpf(1)]
    x1 = mp.quad(lambda sg: 2 * mp.tanh(v0 + oe * sg) ** 2 - 1, layer)
    h1 = mp.quad(lambda sg: 2 * mp.tanh(v0 + oe * sg) * mp.sech(v0 + oe * sg), layer)
    return {
        "ln_omega2": mp.log(omega2),
        "h1_closed": h1_closed,
        "xi": 1 - 2 * p,
        "xi_minus_1": -2 * p,
        "omega_eps": oe,
        "energy": (1 - 2 * p) * oe**2,
        "tip_height": h1,
        "tip_deflection": x1,
        "tip_displacement": x1 - s,
        "tip_angle": mp.pi / 2 - 2 * mp.asin(mp.sqrt(p)),
        "tip_angle_minus_pi_2": -2 * mp.asin(mp.sqrt(p)),
        "base_curvature": oe**2 * h1,
    }


def _ln_omega2_separatrix(t: Any, eps: Any, theta0: Any, sign: int, n: int) -> Any:
    _, d, _, _, oe = _separatrix_oe(t, theta0)
    return mp.log(oe**2 * (1 - eps * mp.sqrt(2 * d) / oe))


#: What is differentiated for each output (on the separatrix: the distance of xi to 1 and of
#: the tip angle to pi/2, which hold the digits; the constants do not change the derivative).
_CARRIER = {"xi": "xi_minus_1", "tip_angle": "tip_angle_minus_pi_2"}


def compute_case(case: tuple[float, float, float, int, int]) -> dict[str, Any]:
    """The state of one case and the derivatives of its outputs."""
    t, eps, theta0, sign, n = case
    mp.dps = _dps(t)
    separatrix = t >= T_SEPARATRIX
    branch = _branch_separatrix if separatrix else _branch
    ln_omega2 = _ln_omega2_separatrix if separatrix else _ln_omega2
    t0, e0, th0 = mpf(t), mpf(eps), mpf(theta0)
    centre = branch(t0, e0, th0, sign, n)
    assert abs(centre["tip_height"] - centre["h1_closed"]) < mpf(10) ** (5 - DPS)
    ln_w = centre["ln_omega2"]
    cache: dict[tuple[str, str], dict[str, Any]] = {}

    def state(name: str, x: Any) -> dict[str, Any]:
        key = (name, mp.nstr(x, mp.dps + 10))
        if key not in cache:
            args = {"omega2": mp.exp(ln_w), "eps": e0, "theta0": th0}
            args[name] = x
            lw = mp.log(args["omega2"])
            root = mp.findroot(
                lambda tt: ln_omega2(tt, args["eps"], args["theta0"], sign, n) - lw, t0
            )
            cache[key] = branch(root, args["eps"], args["theta0"], sign, n)
        return cache[key]

    centres = {"omega2": mp.exp(ln_w), "eps": e0, "theta0": th0}
    derivs: dict[str, dict[str, str]] = {o: {} for o in OUTPUTS}
    for name in INPUTS:
        for o in OUTPUTS:
            carrier = _CARRIER.get(o, o) if separatrix else o
            value = mp.diff(lambda x, c=carrier, name=name: state(name, x)[c], centres[name])
            derivs[o][name] = mp.nstr(value, 20)
    return {
        "t": t,
        "eps": eps,
        "theta0": theta0,
        "sign": sign,
        "n": n,
        "omega2": mp.nstr(mp.exp(ln_w), 20),
        "values": {o: mp.nstr(centre[o], 20) for o in OUTPUTS},
        "derivatives": derivs,
    }


def main(argv: list[str] | None = None) -> int:
    """Compute every case (or, with ``--missing``, only those not yet in the file)."""
    argv = sys.argv[1:] if argv is None else argv
    path = Path(__file__).resolve().parents[1] / "data" / "derivatives_mpmath.json"
    known: dict[tuple[Any, ...], dict[str, Any]] = {}
    version = mpmath.__version__
    if "--missing" in argv and path.exists():
        previous = json.loads(path.read_text())
        for c in previous["cases"]:
            known[(c["t"], c["eps"], c["theta0"], c["sign"], c["n"])] = c
        kept = previous["metadata"]["mpmath_version"]
        if kept != version:
            version = f"{version} (cases kept from the previous file: {kept})"
    start = time.time()
    cases = []
    for case in CASES:
        cases.append(known[case] if case in known else compute_case(case))
        print(f"case {case} done ({time.time() - start:.0f} s)", file=sys.stderr)
    out = {
        "metadata": {
            "about": "Derivatives of the outputs of a state in omega2, eps, theta0 by "
            "mpmath.diff of the composite map inputs -> root t -> outputs (quadrature of the "
            "closed-form shape), generated by tests/reference/generate_derivatives.py "
            "(nothing from hairbed).",
            "mpmath_version": version,
            "dps": f"{DPS} + round(-t/2) for t < 0, + round(0.45 t) for 20 < t < "
            f"{T_SEPARATRIX}; from t = {T_SEPARATRIX} on the separatrix (module docstring)",
            "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "generation_seconds": round(time.time() - start, 1),
            "significant_digits_written": 20,
        },
        "cases": cases,
    }
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(out, indent=1) + "\n")
    tmp.replace(path)
    print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
