"""Generate ``src/hairbed/_kernels/weak.py``: the weak-forcing series of the clamped hair.

The boundary value problem theta'' = -eps2 cos(theta) on [0, 1], theta(0) = theta0,
theta'(1) = 0, is expanded in powers of eps2 with sympy:
theta = theta0 + sum_k eps2^k theta_k(sigma), each theta_k a polynomial in sigma whose
coefficients are polynomials in s = sin(theta0), c = cos(theta0), homogeneous of degree k.
With cos(delta) = sum_k eps2^k C_k and sin(delta) = sum_k eps2^k S_k, delta = theta - theta0,
the recurrences k C_k = -sum_j j theta_j S_{k-j}, k S_k = sum_j j theta_j C_{k-j} (C_0 = 1,
S_0 = 0) give

    theta_{k+1}'' = -(c C_k - s S_k),  theta_{k+1}(0) = 0,  theta_{k+1}'(1) = 0,
    dx_k = int_0^sigma (s C_k + c S_k),  dz_k = int_0^sigma (c C_k - s S_k)

for the displacements dx = x - sigma s and dz = z - sigma c. The symmetry theta0 -> pi - theta0
(s fixed, c -> -c, delta -> -delta) makes theta_k and dz_k odd in c and dx_k even, and all vanish
at c = 0 (theta = pi/2 is exact), so theta_k = c P, dx_k = c^2 X and dz_k = c Z with P, X
(homogeneous of degree k - 1) and Z (degree k) polynomials in s and c^2. In the variables
a = eps2 s and b = eps2^2 c^2 this is

    dtheta = c eps2   sum_{i + 2j <= N - 1} a^i b^j P_ij(sigma),
    dx     = c^2 eps2 sum_{i + 2j <= N - 1} a^i b^j X_ij(sigma),
    dz     = c        sum_{1 <= i + 2j <= N} a^i b^j Z_ij(sigma),

the orders eps2^1 .. eps2^N of all three. A term of weight w = i + 2j is at most eps2^w
relative to the leading ones (P_00, X_00, and for dz the larger of a Z_10 and b Z_01: odd orders
of dz vanish at s = 0, where it starts at eps2^2), so with N even the truncation error is
O(eps2^N) relative in every output, uniformly in theta0, with nothing cancelling as s -> 0 or
c -> 0.

The script measures that truncation error (the omitted terms up to weight N + EXTRA, relative
to the sum of the magnitudes of the kept terms) on a grid of theta0 in (-pi/2, pi/2) and sigma
in (0, 1], sets WEAK_MAX to the largest eps2 at which it is at most TARGET in every output
(rounded down to one significant digit), checks the sympy orders against an independent
numerical mpmath recursion, and writes the module (formatted by ruff). From the repository
root::

    .venv/bin/python tools/generate_weak_series.py          # writes the module
    .venv/bin/python tools/generate_weak_series.py --check  # fails if the module is stale

sympy is needed only here, never by the package.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
from fractions import Fraction
from functools import reduce
from pathlib import Path

import mpmath as mp
import numpy as np
import sympy as sp

__all__ = ["ORDER", "derive", "main", "render", "split_ab", "truncation_error"]

#: Order N of the series in eps2 (even: see the module docstring).
ORDER = 6
#: Relative truncation error that defines WEAK_MAX.
TARGET = 1e-16
#: Extra weights used to estimate the truncation error.
EXTRA = 4
#: Line length of the generated code.
LINE = 99

ROOT = Path(__file__).resolve().parent.parent
OUTPUT = ROOT / "src" / "hairbed" / "_kernels" / "weak.py"

SIGMA, S, C = sp.symbols("sigma s c")
GENS = (SIGMA, S, C)

#: name -> (power of c in the prefactor, i + 2j - (order - 1)) of the three outputs.
OUTPUTS = {"p": (1, 0), "x": (2, 0), "z": (1, 1)}

Table = dict[tuple[int, int], dict[int, Fraction]]


def derive(order: int) -> dict[str, dict[int, sp.Poly]]:
    """theta_k, dx_k and dz_k for k = 1 .. order, as sympy Polys in (sigma, s, c)."""
    one, zero = sp.Poly(1, *GENS), sp.Poly(0, *GENS)
    s, c = sp.Poly(S, *GENS), sp.Poly(C, *GENS)
    theta: dict[int, sp.Poly] = {}
    dx: dict[int, sp.Poly] = {}
    dz: dict[int, sp.Poly] = {}
    cos_k, sin_k = {0: one}, {0: zero}
    for k in range(1, order + 1):
        slope = (-(c * cos_k[k - 1] - s * sin_k[k - 1])).integrate(SIGMA)
        slope -= sp.Poly(slope.as_expr().subs(SIGMA, 1), *GENS)  # theta_k'(1) = 0
        theta[k] = slope.integrate(SIGMA)  # theta_k(0) = 0
        acc_c, acc_s = zero, zero
        for j in range(1, k + 1):
            acc_c += j * theta[j] * sin_k[k - j]
            acc_s += j * theta[j] * cos_k[k - j]
        cos_k[k] = -acc_c * sp.Rational(1, k)
        sin_k[k] = acc_s * sp.Rational(1, k)
        dx[k] = (s * cos_k[k] + c * sin_k[k]).integrate(SIGMA)
        dz[k] = (c * cos_k[k] - s * sin_k[k]).integrate(SIGMA)
    return {"p": theta, "x": dx, "z": dz}


def split_ab(polys: dict[int, sp.Poly], c_power: int, shift: int) -> Table:
    """Regroup sum_k eps2^k polys[k] as prefactor * sum a^i b^j F_ij(sigma).

    The term s^i c^(c_power + 2j) sigma^m of order k must have i + 2j = k - 1 + shift
    (asserted): F_ij is returned as {m: coefficient}.
    """
    out: Table = {}
    for k, poly in polys.items():
        for (m, i, jc), coef in poly.terms():
            j, rem = divmod(jc - c_power, 2)
            assert rem == 0 and j >= 0, (k, m, i, jc)
            assert i + 2 * j == k - 1 + shift, (k, i, j)
            row = out.setdefault((i, j), {})
            row[m] = row.get(m, Fraction(0)) + Fraction(int(coef.p), int(coef.q))
    return {key: {m: q for m, q in row.items() if q} for key, row in sorted(out.items())}


def kept(name: str, i: int, j: int, order: int) -> bool:
    """Whether the term a^i b^j of output ``name`` is in the series of order ``order``.

    Such a term is at most eps2^(i + 2j) relative to the leading terms of weight 0 for
    dtheta and dx; for dz, relative to |a Z_10| + |b Z_01|, it is at most eps2^(i + 2j - 1)
    if i >= 1 and eps2^(2j - 2) if i = 0.
    """
    w = i + 2 * j
    if name != "z":
        return w <= order - 1
    return w <= order if i >= 1 else w <= order + 1


# ------------------------------------------------------------------------------------------
# truncation error and WEAK_MAX
# ------------------------------------------------------------------------------------------


def _grid() -> tuple[np.ndarray, np.ndarray]:
    half = math.pi / 2
    th = list(np.linspace(-half, half, 181)[1:-1])
    th += [0.0, 1e-8, -1e-8, 1e-4, -1e-4, half - 1e-6, 1e-6 - half, 1.5707, -1.5707]
    sg = [1e-4, 1e-3, 1e-2, *np.linspace(0.05, 1.0, 20)]
    return np.meshgrid(np.array(sg), np.array(th))


def _values(table: Table, sg: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    out = {}
    for key, row in table.items():
        coef = [float(row.get(m, 0)) for m in range(max(row), -1, -1)]
        out[key] = np.polyval(coef, sg)
    return out


def truncation_error(eps2: float, values: dict, s: np.ndarray, c: np.ndarray, order: int):
    """Largest relative truncation error over the grid, per output, at eps2."""
    a, b = eps2 * s, eps2**2 * c**2
    worst = {}
    for name, vals in values.items():
        den = np.zeros_like(s)
        num = np.zeros_like(s)
        for (i, j), v in vals.items():
            term = a**i * b**j * v
            if kept(name, i, j, order):
                den += abs(term)
            else:
                num += term
        worst[name] = float(np.max(abs(num) / den))
    return worst


def weak_max(values: dict, s: np.ndarray, c: np.ndarray, order: int) -> float:
    """Largest eps2 with truncation error <= TARGET, rounded down to one significant digit."""
    lo, hi = 1e-8, 1.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        ok = max(truncation_error(mid, values, s, c, order).values()) <= TARGET
        lo, hi = (mid, hi) if ok else (lo, mid)
    print(f"truncation error {TARGET:g} reached at eps2 = {lo:.3g}")
    exponent = math.floor(math.log10(lo))
    return math.floor(lo / 10**exponent) * 10.0**exponent


# ------------------------------------------------------------------------------------------
# independent check: numerical mpmath recursion on sigma-coefficient lists
# ------------------------------------------------------------------------------------------


def mp_series(s: mp.mpf, c: mp.mpf, order: int) -> dict[str, list[list[mp.mpf]]]:
    """theta_k, dx_k, dz_k (k = 1 .. order) as sigma-coefficient lists, lowest power first."""

    def mul(p, q):
        r = [mp.mpf(0)] * (len(p) + len(q) - 1)
        for i, x in enumerate(p):
            for j, y in enumerate(q):
                r[i + j] += x * y
        return r

    def lin(f, p, g, q):
        n = max(len(p), len(q))
        p = p + [mp.mpf(0)] * (n - len(p))
        q = q + [mp.mpf(0)] * (n - len(q))
        return [f * x + g * y for x, y in zip(p, q)]

    def integ(p):
        return [mp.mpf(0)] + [x / (i + 1) for i, x in enumerate(p)]

    theta, dx, dz = [], [], []
    cos_k, sin_k = [[mp.mpf(1)]], [[mp.mpf(0)]]
    for k in range(1, order + 1):
        slope = integ(lin(-c, cos_k[k - 1], s, sin_k[k - 1]))
        slope[0] = -mp.fsum(slope)
        theta.append(integ(slope))
        acc_c, acc_s = [mp.mpf(0)], [mp.mpf(0)]
        for j in range(1, k + 1):
            acc_c = lin(1, acc_c, j, mul(theta[j - 1], sin_k[k - j]))
            acc_s = lin(1, acc_s, j, mul(theta[j - 1], cos_k[k - j]))
        cos_k.append([-x / k for x in acc_c])
        sin_k.append([x / k for x in acc_s])
        dx.append(integ(lin(s, cos_k[k], c, sin_k[k])))
        dz.append(integ(lin(c, cos_k[k], -s, sin_k[k])))
    return {"p": theta, "x": dx, "z": dz}


def check_against_mpmath(polys: dict[str, dict[int, sp.Poly]], order: int) -> float:
    """Largest relative difference of the sympy orders and the numerical mpmath recursion."""
    worst = mp.mpf(0)
    with mp.workdps(40):
        for theta0 in ("0", "0.3", "-0.7", "1.2", "-1.5", "1.5707"):
            t0 = mp.mpf(theta0)
            s, c = mp.sin(t0), mp.cos(t0)
            series = mp_series(s, c, order)
            for name, orders in polys.items():
                for k in range(1, order + 1):
                    f = sp.lambdify(GENS, orders[k].as_expr(), "mpmath")
                    for sg in ("0.1", "0.5", "1"):
                        ref = mp.polyval(series[name][k - 1][::-1], mp.mpf(sg))
                        if ref != 0:
                            worst = max(worst, abs(f(mp.mpf(sg), s, c) - ref) / abs(ref))
    return float(worst)


# ------------------------------------------------------------------------------------------
# code generation
# ------------------------------------------------------------------------------------------


def _lit(x: int) -> str:
    assert abs(x) < 2**53
    return f"{float(x)!r}"


def _integer_form(row: dict[int, Fraction]) -> tuple[int, Fraction, list[int]]:
    """F(sigma) = scale sigma^m (q_0 + q_1 sigma + ...), integers q with q_0 > 0."""
    low, high = min(row), max(row)
    den = reduce(math.lcm, (q.denominator for q in row.values()), 1)
    ints = [int(row.get(m, Fraction(0)) * den) for m in range(low, high + 1)]
    g = reduce(math.gcd, ints) * (1 if ints[0] > 0 else -1)
    return low, Fraction(g, den), [q // g for q in ints]


def _horner(coeffs: list[str | None], var: str) -> str:
    """coeffs[0] + var * (coeffs[1] + ...), with None for a zero coefficient."""
    expr = coeffs[-1]
    for q in reversed(coeffs[:-1]):
        inner = f"({expr})" if " " in expr else expr
        expr = f"{var} * {inner}" if q is None else f"{q} + {var} * {inner}"
    return expr


def _tuple_code(name: str, items: list[str]) -> str:
    """``name = (items)`` on one line, or wrapped at LINE characters."""
    one = f"{name} = ({', '.join(items)})"
    if len(one) <= LINE:
        return one
    lines, line = [f"{name} = ("], "   "
    for item in items:
        if len(line) + len(item) + 2 > LINE:
            lines.append(line)
            line = "   "
        line += f" {item},"
    return "\n".join([*lines, line, ")"])


def render(tables: dict[str, Table], order: int, wmax: float, errors: dict) -> str:
    """Source of the generated module."""
    consts, lines, sums = [], [], {}
    for name, table in tables.items():
        names = {}
        for (i, j), row in table.items():
            if not kept(name, i, j, order):
                continue
            low, scale, ints = _integer_form(row)
            var = f"{name}{i}{j}"
            names[(i, j)] = var
            const = f"_{var.upper()}"
            consts.append(_tuple_code(const, [_lit(q) for q in reversed(ints)]))
            sign = "-" if scale < 0 else ""
            scale = abs(scale)
            factor = f"({_lit(scale.numerator)} / {_lit(scale.denominator)})"
            powers = " * ".join(["t"] * low)
            lines.append(f"    {var} = {sign}{powers} * _horner(t, {const}) * {factor}")
        rows = []
        for j in range(max(jj for _, jj in names) + 1):
            imax = max(i for i, jj in names if jj == j)
            rows.append(_horner([names.get((i, j)) for i in range(imax + 1)], "a"))
        sums[name] = _horner(rows, "b")
        lines.append("")
    count = len(consts)
    worst = max(errors.values())
    return TEMPLATE.format(
        order=order,
        order_1=order - 1,
        count=count,
        wmax=repr(wmax),
        err=f"{worst:.0e}",
        target=f"{TARGET:.0e}",
        consts="\n".join(consts),
        body="\n".join(lines).rstrip(),
        sum_p=sums["p"],
        sum_x=sums["x"],
        sum_z=sums["z"],
    )


TEMPLATE = '''\
# GENERATED by tools/generate_weak_series.py: do not edit by hand, change and rerun the script.
"""Weak-forcing series of the clamped hair: the small displacements to full relative precision.

For ``theta'' = -eps2 cos(theta)`` on ``0 <= sigma <= 1``, ``theta(0) = theta0``,
``theta'(1) = 0``, with ``x = int_0^sigma sin(theta)`` and ``z = int_0^sigma cos(theta)``, the
closed-form solution gives the displacements ``dtheta = theta - theta0``, ``dx = x - sigma s``
and ``dz = z - sigma c`` (``s = sin(theta0)``, ``c = cos(theta0)``) as differences of O(1)
numbers, which loses their relative accuracy when eps2 is small. Here they come from the
regular expansion ``theta = theta0 + sum_k eps2^k theta_k(sigma)`` instead: ``theta_k''`` is
minus the coefficient of eps2^(k-1) of ``cos(theta0 + delta)`` expanded in ``delta = theta -
theta0``, with ``theta_k(0) = 0`` and ``theta_k'(1) = 0``, so that
``theta_1 = c (sigma - sigma^2 / 2)``; ``dx`` and ``dz`` integrate the expansions of
``sin(theta0 + delta) - s`` and ``cos(theta0 + delta) - c``.

The symmetry ``theta0 -> pi - theta0`` (``c -> -c``) and the exact solution ``theta = pi/2`` at
``c = 0`` factor the orders as ``theta_k = c P``, ``dx_k = c^2 X`` and ``dz_k = c Z``, with P, X
and Z polynomials in s and c^2. In ``a = eps2 s`` and ``b = eps2^2 c^2``, to order
eps2^{order}::

    dtheta = c eps2   sum_{{i + 2j <= {order_1}}} a^i b^j P_ij(sigma)
    dx     = c^2 eps2 sum_{{i + 2j <= {order_1}}} a^i b^j X_ij(sigma)
    dz     = c        sum_{{1 <= i + 2j <= {order}}} a^i b^j Z_ij(sigma)

The leading polynomials ``P_00 = sigma (2 - sigma) / 2``, ``X_00 = sigma^2 (3 - sigma) / 6``,
``Z_10 = -X_00`` and ``Z_01 = -sigma^3 (20 - 15 sigma + 3 sigma^2) / 120`` have no zero in
(0, 1]. Relative to them a term a^i b^j is O(eps2^(i + 2j)) in dtheta and dx. dz starts at
``c b Z_01`` when s = 0 (its odd orders vanish there): relative to ``|a Z_10| + |b Z_01|`` a
term is O(eps2^(i + 2j - 1)) if i >= 1 and O(eps2^(2j - 2)) if i = 0, so that stopping at
the even order {order} leaves O(eps2^{order}) relative in all three. The prefactors carry the
zeros at ``c = 0`` and ``sigma = 0`` exactly, so nothing cancels as ``s -> 0`` or ``c -> 0``
and the results are exactly 0 at ``sigma = 0`` or ``c = 0``. Each polynomial is stored as
integers (highest power first) with a power of sigma and a rational factor and is evaluated
in Horner form; the sum over a and b is a Horner form too.

Accuracy: the truncation error is at most {target} relative in every output for
``eps2 <= WEAK_MAX`` (measured {err} at WEAK_MAX) for every theta0 in (-pi/2, pi/2) and sigma in
(0, 1]; rounding adds a few ulps. The exception is the thin band ``-O(eps2) < s < 0`` where dz
changes sign (its ``a`` and ``b`` terms have opposite signs there): the error of dz is then a
few ulps of ``|c| (|a Z_10| + |b Z_01|)`` rather than of ``|dz|``.
"""

from __future__ import annotations

from .._jit import kernel

__all__ = ["WEAK_MAX", "WEAK_ORDER", "weak_shape"]

#: Order in eps2 of the series.
WEAK_ORDER = {order}
#: Largest eps2 for which the truncation error is at most {target} relative in every output.
WEAK_MAX = {wmax}

# The {count} polynomials P_ij, X_ij, Z_ij of sigma: integer coefficients, highest power first.
# fmt: off
{consts}
# fmt: on


@kernel
def _horner(t: float, coeffs: tuple[float, ...]) -> float:
    """The polynomial with coefficients ``coeffs`` (highest power first) at ``t``."""
    h = 0.0
    for q in coeffs:
        h = h * t + q
    return h


@kernel
def weak_shape(sigma: float, eps2: float, s: float, c: float) -> tuple[float, float, float]:
    """Displacements of the weakly forced hair from its straight clamped line.

    Parameters
    ----------
    sigma : float
        Arc length, in [0, 1].
    eps2 : float
        Forcing ``omega_eps^2``, in [0, WEAK_MAX].
    s, c : float
        ``sin(theta0)`` and ``cos(theta0)`` of the clamping angle theta0 in (-pi/2, pi/2).

    Returns
    -------
    dtheta, dx, dz : float
        ``theta - theta0``, ``x - sigma s`` and ``z - sigma c`` at ``sigma``.
    """
    t = sigma
    a = eps2 * s
    b = (eps2 * eps2) * (c * c)

{body}

    dtheta = c * (eps2 * ({sum_p}))
    dx = c * (c * (eps2 * ({sum_x})))
    dz = c * ({sum_z})
    return dtheta, dx, dz
'''


def main(argv: list[str] | None = None) -> int:
    """Derive, measure, check and write (or with ``--check`` compare) the module."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if the module is stale")
    args = parser.parse_args(argv)

    n = ORDER
    assert n % 2 == 0
    polys = derive(n + 1 + EXTRA)
    tables = {name: split_ab(polys[name], *OUTPUTS[name]) for name in OUTPUTS}

    sg, th = _grid()
    s, c = np.sin(th), np.cos(th)
    values = {name: _values(table, sg) for name, table in tables.items()}
    wmax = weak_max(values, s, c, n)
    errors = truncation_error(wmax, values, s, c, n)
    for eps2 in (1e-3, wmax):
        err = truncation_error(eps2, values, s, c, n)
        shown = ", ".join(f"{k} {v:.1e}" for k, v in err.items())
        print(f"N = {n}, eps2 = {eps2:g}: truncation error {shown}")
    print(f"WEAK_MAX = {wmax:g}")
    mismatch = check_against_mpmath(polys, n + 1)
    print(f"sympy orders vs numerical mpmath recursion: {mismatch:.1e} relative")
    assert mismatch < 1e-35

    text = render(tables, n, wmax, errors)
    ruff = Path(sys.executable).parent / "ruff"
    cmd = [str(ruff), "format", "--stdin-filename", str(OUTPUT), "-"]
    text = subprocess.run(cmd, input=text, capture_output=True, text=True, check=True).stdout
    if args.check:
        if not OUTPUT.exists() or OUTPUT.read_text() != text:
            print(f"{OUTPUT} is stale: rerun tools/generate_weak_series.py")
            return 1
        print(f"{OUTPUT} is up to date")
        return 0
    OUTPUT.write_text(text)
    print(f"wrote {OUTPUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
