"""Generate the high-precision derivatives in ``tests/data/derivatives_mpmath.json``.

Run on demand (about a minute)::

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
)


def _dps(t: float) -> int:
    """Working precision of a case: more at weak forcing (t << 0), where the tip
    displacement is ~exp(t) and its derivatives are differences of O(1) quadratures."""
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


def compute_case(case: tuple[float, float, float, int, int]) -> dict[str, Any]:
    """The state of one case and the derivatives of its outputs."""
    t, eps, theta0, sign, n = case
    mp.dps = _dps(t)
    t0, e0, th0 = mpf(t), mpf(eps), mpf(theta0)
    centre = _branch(t0, e0, th0, sign, n)
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
                lambda tt: _ln_omega2(tt, args["eps"], args["theta0"], sign, n) - lw, t0
            )
            cache[key] = _branch(root, args["eps"], args["theta0"], sign, n)
        return cache[key]

    centres = {"omega2": mp.exp(ln_w), "eps": e0, "theta0": th0}
    derivs: dict[str, dict[str, str]] = {o: {} for o in OUTPUTS}
    for name in INPUTS:
        for o in OUTPUTS:
            value = mp.diff(lambda x, o=o, name=name: state(name, x)[o], centres[name])
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
    if "--missing" in argv and path.exists():
        for c in json.loads(path.read_text())["cases"]:
            known[(c["t"], c["eps"], c["theta0"], c["sign"], c["n"])] = c
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
            "mpmath_version": mpmath.__version__,
            "dps": f"{DPS} + round(-t/2) for t < 0",
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
