"""Generate the mpmath reference of the corner cases in ``tests/data/corners_mpmath.json``.

Run on demand (about five minutes on two cores)::

    .venv/bin/python tests/reference/generate_corners.py [--workers 2] [--quick]

Like ``generate_reference.py``, whose functions it reuses (``Branch``, ``find_roots``,
``polish``, ``evaluate``, ``legendre_values``, ``taylor_ivp``, ``_golden_extremum``), it imports
nothing from :mod:`hairbed`. It tabulates the inputs of the issue's list of wrong results
(tested by ``tests/test_solver_corners.py``):

* ``three_states``: solve(2.2305002283179594, 0.5, -1.570795) has three physical states; every
  field and the shape of each;
* ``cells``: the physical branch on a grid of (theta0, eps) near theta0 = -pi/2 (theta0 from
  -pi/2 + 1e-7 to -1.45, eps from 0.3 to 0.99) and at a few base angles closer still: its folds
  (the local extrema of omega2 along the branch parameter t, refined by golden-section search and
  by a root of d omega2/dt at higher precision) and, at omega2 inside and outside the three-state
  window, every root (n_roots and each root's fields);
* ``shapes``: every root and theta, x, z at ``SIGMA_SHAPE`` on the physical branch near
  theta0 = +pi/2 (group ``near_half_pi``), at weak forcing omega2 = 1e-300 ... 1e-8 (``weak``) and
  from 1e-300 to 1e3 for the tip displacement x1 - sin(theta0) (``tip``), together with the
  displacements from the rest shape: theta - theta0, x - sigma sin(theta0), z - sigma cos(theta0)
  and x1 - sin(theta0), each to 20 significant digits RELATIVE TO ITSELF.

How roots are found. The physical branch is the explicit curve omega2(t) (t the logit of xi in
[sin theta0, 1)). Its structure is tabulated once per (eps, theta0): omega2 on a grid in t from
t_lo = ln((1 + sin theta0)/2) - 30 (where omega_eps^2 ~ 2 e^t / (1 + sin theta0) ~ 1e-13 and
the hair is in the linear regime: omega2 rises monotonically from 0 below it) to t = 25 (beyond,
omega_eps > 12 grows with t while h1 -> 0, so omega2 is monotone; see ``t_grid`` of
generate_reference.py), every local extremum refined, and a pair of extrema closer together
than the grid step (near the cusp) detected as a local minimum of the discrete slope of
ln omega2 that dips below zero when refined. Between consecutive extrema omega2(t) is monotone,
so the roots at a given omega2 are exactly one per monotone piece whose end values straddle it;
each is bracketed on the grid (or beyond it, by expanding the bracket in the monotone tails) and
refined. As an independent check, ``generate_reference.find_roots`` (a dense grid of the
residual with a search inside every local extremum) is run at a subset of the inputs and must
find the same roots.

Precision. Weak forcing needs many digits: route A forms omega_eps = K - v0 by difference
(digits lost ~ -log10 omega_eps) and the displacements are differences of O(1) numbers (z -
sigma at theta0 = 0 is O(omega2^2)). The working precision is raised accordingly
(``_shape_dps``), and every root is re-refined and re-evaluated with ``PRECISION_STEP`` more
digits: values must agree to 30 digits (relative to max(1, |value|)) and every displacement to
25 digits relative to itself, else the precision is raised and the root redone.

Checks recorded (``checks`` of each root, summary in ``metadata``): the precision check above;
route B (mpmath's Legendre-form ``ellipk``/``ellipf``/``ellipe`` and ``ellipfun``, with
mu = 1 - p exact) where 1 - xi > 1e-150 and the working precision is moderate; for a subset,
Taylor-series integration of theta'' = -omega_eps^2 cos(theta), x' = sin(theta),
z' = cos(theta) from theta0 and the base curvature (``taylor_ivp``), asserting theta'(1) = 0,
the branch label (no interior turning point), theta, x, z at every sigma to 25 digits and the
displacements to 12 digits relative; at weak forcing, agreement of the displacements with
linear theory, theta - theta0 = W c (sigma - sigma^2/2), x - sigma s = W c^2 (sigma^2/2 -
sigma^3/6), z - sigma c = -s W c (sigma^2/2 - sigma^3/6) (and -W^2/2 (sigma^3/3 - sigma^4/4 +
sigma^5/20) at theta0 = 0), W = omega_eps^2, c = cos theta0, s = sin theta0, to relative
O(W / c); and for each root of ``cells`` the condition numbers |d xi / d ln omega2| and
|d theta'(0) / d ln omega2| (the inputs are written only where both are small, so that a
double-precision solver can meet 1e-12).

Every computed number is written as a string with 20 significant digits; inputs are JSON
numbers (binary doubles, converted exactly).
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import multiprocessing
import platform
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))
import generate_reference as gr  # noqa: E402

__all__ = ["build_tasks", "main"]

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "corners_mpmath.json"
OUT_DIGITS = gr.OUT_DIGITS
#: Working precision of the branch grids [decimal digits] (omega_eps >= 1e-7 on the grid).
GRID_DPS = 40
#: Working precision of the roots of the cells and of the fold refinement.
CELL_DPS = 45
#: Extra digits of the precision check.
PRECISION_STEP = 30
#: Digits required: values (relative to max(1, |v|)), displacements (relative to themselves).
VALUE_DIGITS = 30
DISPLACEMENT_DIGITS = 25
#: Largest condition number |d xi/d ln omega2|, |d theta'(0)/d ln omega2| of a tabulated root.
KAPPA_MAX = 50.0
#: Points along the hair where the shapes are tabulated.
SIGMA_SHAPE = (
    0.0,
    1e-6,
    1e-3,
    0.01,
    0.05,
    0.1,
    0.2,
    0.3,
    0.5,
    0.7,
    0.77,
    0.9,
    0.95,
    0.99,
    0.999,
    1.0,
)
FIELDS = gr.FIELDS
HALF_PI = math.pi / 2


def _fmt(v: mpf) -> str:
    return mp.nstr(v, OUT_DIGITS)


# ------------------------------------------------------------------------------------------
# The physical branch as a curve omega2(t)
# ------------------------------------------------------------------------------------------


def _omega2(br: gr.Branch, t: mpf) -> mpf:
    """omega2 on the branch at parameter t (eq. (34)); br.omega2 is not used."""
    st = br.state(t)
    w = st["w"]
    return w * w - br.eps * br.sign * w * mp.sqrt(2 * st["q"])


def _log_slope(br: gr.Branch, t: mpf) -> mpf:
    """d ln(omega2) / dt (mpmath's numerical derivative with raised internal precision)."""
    return mp.diff(lambda u: mp.log(_omega2(br, u)), t)


def _t_lo(br: gr.Branch) -> mpf:
    # omega_eps^2 ~ 2 e^t / (1 + sin theta0) at weak forcing, 1 + sin theta0 = 2 a^2
    return 2 * mp.log(br.a) - 30


def _refine_fold(eps: float, theta0: float, a: mpf, b: mpf, dps: int) -> tuple[mpf, mpf]:
    """The zero of d omega2/dt in [a, b] (where it changes sign) and omega2 there, at dps."""
    mp.dps = dps
    br = gr.Branch(0.0, eps, theta0, 1, 0)
    tz = mp.findroot(lambda u: _log_slope(br, u), (+a, +b), solver="illinois", verify=False)
    if not a <= tz <= b:  # pragma: no cover
        tz = mp.findroot(lambda u: _log_slope(br, u), (+a, +b), solver="bisect", verify=False)
    return tz, _omega2(br, tz)


def branch_structure(eps: float, theta0: float) -> dict[str, Any]:
    """Grid, extrema (folds) and smallest log-slope of the physical branch at (eps, theta0).

    Grid in t: step 2 on [t_lo, t_lo + 20) (the linear regime), then 0.5 up to t = 25. Every
    sign change of the differences of omega2 on the grid is an extremum, refined as the zero of
    d omega2/dt between its neighbours; a positive local minimum of the discrete slope of
    ln omega2 below 1 is refined (golden section on the derivative) and split into two extrema
    if it is negative (a pair of folds closer together than the grid step, near the cusp).
    """
    mp.dps = GRID_DPS
    br = gr.Branch(0.0, eps, theta0, 1, 0)
    lo = _t_lo(br)
    ts = []
    t = lo
    while t < lo + 20:
        ts.append(t)
        t += 2
    while t <= 25:
        ts.append(t)
        t += mpf("0.5")
    fs = [_omega2(br, t) for t in ts]
    assert all(f > 0 for f in fs), (eps, theta0)
    g = [(mp.log(fs[i + 1]) - mp.log(fs[i])) / (ts[i + 1] - ts[i]) for i in range(len(ts) - 1)]
    assert g[0] > 0 and g[-1] > 0, (eps, theta0, g[0], g[-1])
    brackets: list[tuple[mpf, mpf, str]] = []
    for i in range(1, len(ts) - 1):
        d1, d2 = fs[i] - fs[i - 1], fs[i + 1] - fs[i]
        if d1 * d2 < 0:
            brackets.append((ts[i - 1], ts[i + 1], "max" if d1 > 0 else "min"))
    min_slope = min(g)
    for i in range(1, len(g) - 1):
        if g[i] <= g[i - 1] and g[i] <= g[i + 1] and 0 < g[i] < 1:
            a, b = ts[i - 1], ts[i + 2]
            if any(a < y and x < b for x, y, _ in brackets):
                continue
            mp.dps = GRID_DPS
            tm, gm = gr._golden_extremum(lambda u: _log_slope(br, u), a, b, minimum=True, iters=40)
            min_slope = min(min_slope, gm)
            if gm < 0:
                brackets += [(a, tm, "max"), (tm, b, "min")]
    brackets.sort()
    kinds = [k for _, _, k in brackets]
    # omega2 rises from 0 to infinity along the physical branch: extrema alternate max, min
    assert kinds == ["max", "min"] * (len(kinds) // 2), (eps, theta0, kinds)
    folds = []
    for a, b, kind in brackets:
        _, w_lo = _refine_fold(eps, theta0, a, b, GRID_DPS)
        tz, w_fold = _refine_fold(eps, theta0, a, b, CELL_DPS + PRECISION_STEP)
        digits = gr._digits(abs(w_lo / w_fold - 1), GRID_DPS)
        assert digits >= VALUE_DIGITS, (eps, theta0, a, b, digits)
        folds.append({"t": tz, "omega2": w_fold, "kind": kind, "digits": digits})
    t_min_slope = None
    if not folds:
        # refine the smallest slope: how far the branch is from having folds
        k = min(range(len(g)), key=lambda i: g[i])
        a, b = ts[max(k - 1, 0)], ts[min(k + 2, len(ts) - 1)]
        mp.dps = GRID_DPS
        t_min_slope, gm = gr._golden_extremum(
            lambda u: _log_slope(br, u), a, b, minimum=True, iters=40
        )
        min_slope = min(min_slope, gm)
    mp.dps = GRID_DPS
    return {
        "eps": eps,
        "theta0": theta0,
        "ts": ts,
        "fs": fs,
        "folds": folds,
        "min_log_slope": min_slope,
        "t_min_slope": t_min_slope,
    }


def _bracket_in_piece(
    br: gr.Branch, s: dict[str, Any], target: mpf, piece: int
) -> tuple[mpf, mpf] | None:
    """A bracket [a, b] of omega2(t) = target inside monotone piece number ``piece``.

    Pieces are separated by the folds; even pieces rise, odd ones fall. The grid values bracket
    the root inside the grid; in the tails (omega2 -> 0 as t -> -inf, -> inf as t -> inf) the
    bracket is expanded geometrically.
    """
    folds = s["folds"]
    t_a = folds[piece - 1]["t"] if piece > 0 else -mp.inf
    t_b = folds[piece]["t"] if piece < len(folds) else mp.inf
    pts = [(t_a, folds[piece - 1]["omega2"] if piece > 0 else mpf(0))]
    pts += [(t, f) for t, f in zip(s["ts"], s["fs"]) if t_a < t < t_b]
    pts.append((t_b, folds[piece]["omega2"] if piece < len(folds) else mp.inf))
    sgn = 1 if piece % 2 == 0 else -1
    if not sgn * (pts[0][1] - target) < 0 < sgn * (pts[-1][1] - target):
        return None
    for (a, fa), (b, fb) in zip(pts, pts[1:]):  # noqa: B007 (a, b used after the loop)
        if sgn * (fa - target) <= 0 <= sgn * (fb - target):
            break
    step = mpf(10)
    while a == -mp.inf:
        a = b - step
        if _omega2(br, a) < target:
            break
        b, a, step = a, -mp.inf, step * 2
    while b == mp.inf:
        b = a + step
        if _omega2(br, b) > target:
            break
        a, b, step = b, mp.inf, step * 2
    return a, b


def roots_on_branch(s: dict[str, Any], omega2: float, dps: int) -> list[mpf]:
    """Every root t (increasing) of omega2(t) = omega2 on the tabulated physical branch."""
    mp.dps = dps
    br = gr.Branch(omega2, s["eps"], s["theta0"], 1, 0)
    target = mpf(omega2)
    roots = []
    for piece in range(len(s["folds"]) + 1):
        bracket = _bracket_in_piece(br, s, target, piece)
        if bracket is None:
            continue
        a, b = bracket
        t = mp.findroot(br.scaled_residual, (a, b), solver="anderson", verify=False)
        if not a <= t <= b:
            t = mp.findroot(br.scaled_residual, (a, b), solver="bisect", verify=False)
        roots.append(t)
    return roots


# ------------------------------------------------------------------------------------------
# A root, evaluated with its displacements and checked
# ------------------------------------------------------------------------------------------


def _with_displacements(vals: dict[str, Any], theta0: float, sigmas) -> dict[str, Any]:
    th = mpf(theta0)
    s, c = mp.sin(th), mp.cos(th)
    vals["tip_displacement"] = vals["tip_deflection"] - s
    vals["dtheta"] = [v - th for v in vals["theta"]]
    vals["dx"] = [v - mpf(sg) * s for v, sg in zip(vals["x"], sigmas)]
    vals["dz"] = [v - mpf(sg) * c for v, sg in zip(vals["z"], sigmas)]
    if sigmas and sigmas[0] == 0.0:  # the base: exact, not rounding residue
        vals["theta"][0], vals["x"][0], vals["z"][0] = th, mpf(0), mpf(0)
        vals["dtheta"][0] = vals["dx"][0] = vals["dz"][0] = mpf(0)
    return vals


def _relative_digits(a: mpf, b: mpf, cap: int) -> float:
    if a == b:
        return float(cap)
    if b == 0:
        return 0.0
    return gr._digits(abs(a / b - 1), cap)


#: Displacements smaller than this times their value are irrelevant to a double-precision
#: test (its rounding floor is 25 orders larger): they are written as null unless resolved.
NEGLIGIBLE = mpf(10) ** -40
_DISPLACED = {"tip_displacement": "tip_deflection", "dtheta": "theta", "dx": "x", "dz": "z"}


def _precision_digits(lo: dict[str, Any], hi: dict[str, Any]) -> tuple[float, float]:
    """Digits of agreement: values (relative to max(1, |v|)), displacements (relative)."""
    keys = (*FIELDS, "theta", "x", "z")
    value_digits = gr._digits(gr._agreement(lo, hi, keys), 99)
    disp = 99.0
    for k, base in _DISPLACED.items():
        if isinstance(lo[k], list):
            pairs = zip(lo[k], hi[k], hi[base])
        else:
            pairs = [(lo[k], hi[k], hi[base])]
        for a, b, v in pairs:
            digits = _relative_digits(a, b, 99)
            if digits < DISPLACEMENT_DIGITS and abs(b) < NEGLIGIBLE * abs(v):
                continue  # unresolved but negligible: written as null
            disp = min(disp, digits)
    return value_digits, disp


def _null_unresolved(lo: dict[str, Any], hi: dict[str, Any]) -> int:
    """Set the negligible displacements that the two precisions do not resolve to None."""
    count = 0
    for k, base in _DISPLACED.items():
        if isinstance(hi[k], list):
            for i, (a, b, v) in enumerate(zip(lo[k], hi[k], hi[base])):
                if _relative_digits(a, b, 99) < DISPLACEMENT_DIGITS:
                    assert abs(b) < NEGLIGIBLE * abs(v)
                    hi[k][i] = None
                    count += 1
        elif _relative_digits(lo[k], hi[k], 99) < DISPLACEMENT_DIGITS:
            assert abs(hi[k]) < NEGLIGIBLE * abs(hi[base])
            hi[k] = None
            count += 1
    return count


def _shape_dps(omega2: float, theta0: float) -> int:
    """Working precision for the displacements at weak forcing (see module docstring)."""
    # omega_eps ~ omega: K - v0 cancels to it, the numerator of x(sigma) to omega^3 and the
    # displacements are O(omega^2) relative to O(1) values; near theta0 = +-pi/2 the xi range
    # is O(cos^2 theta0). (z - sigma ~ omega^4 at theta0 = 0 is negligible: see NEGLIGIBLE.)
    digits = max(0.0, -math.log10(omega2))
    lost = 1.6 * digits + 2 * max(0.0, -math.log10(math.cos(theta0)))
    return 60 + int(math.ceil(lost))


def evaluate_root(
    omega2: float, eps: float, theta0: float, t: mpf, sigmas, dps: int
) -> tuple[dict[str, Any], dict[str, Any]]:
    """Refine the root near t and evaluate it at dps and dps + PRECISION_STEP (checked)."""
    for _attempt in range(6):
        out = []
        for prec in (dps, dps + PRECISION_STEP):
            mp.dps = prec
            br = gr.Branch(omega2, eps, theta0, 1, 0)
            tr = gr.polish(br, +t, mpf(10) ** (-min(dps - 10, 40)))
            vals = gr.evaluate(br, tr, sigmas)
            vals["t"] = tr
            vals.pop("_state")
            out.append(_with_displacements(vals, theta0, sigmas))
        value_digits, disp_digits = _precision_digits(out[0], out[1])
        if value_digits >= VALUE_DIGITS and disp_digits >= DISPLACEMENT_DIGITS:
            break
        dps += 150
    else:  # pragma: no cover
        raise RuntimeError(f"precision check failed at {(omega2, eps, theta0)}")
    vals = out[1]
    unresolved = _null_unresolved(out[0], vals)
    checks = {
        "dps": dps + PRECISION_STEP,
        "negligible_displacements_not_resolved": unresolved,
        "residual": mp.nstr(abs(br.scaled_residual(vals["t"])), 3),
        "precision_digits": value_digits,
        "displacement_precision_digits": disp_digits,
    }
    return vals, checks


def legendre_check(
    omega2: float, eps: float, theta0: float, vals: dict[str, Any], sigmas
) -> float | None:
    """Digits of agreement with route B (generate_reference.legendre_values)."""
    r = vals["one_minus_xi"]
    if r <= gr.LEGENDRE_MIN_ONE_MINUS_XI:
        return None
    # ellipk - ellipf cancels to omega_eps, and arcsin loses half its digits near theta = +-pi/2
    extra = max(0, int(-mp.log10(vals["omega_eps"]))) + 2 * max(
        0, int(-math.log10(math.cos(theta0)))
    )
    mp.dps = gr.DPS + 10 + (int(-mp.log10(r)) if r < 1 else 0) + extra
    case = {"omega2": omega2, "eps": eps, "theta0": theta0, "sign": 1, "n": 0}
    leg = gr.legendre_values(case, vals["t"], sigmas)
    keys = (*FIELDS, "theta", "x", "z") if vals["theta"] else FIELDS
    return gr._digits(gr._agreement(leg, vals, keys), gr.DPS)


def ode_check(theta0: float, vals: dict[str, Any], sigmas, dps: int) -> dict[str, Any]:
    """Taylor-series integration of the initial value problem (generate_reference.taylor_ivp)."""
    mp.dps = dps
    w = +vals["omega_eps"]
    th = mpf(theta0)
    bc = +vals["base_curvature"]
    start = time.time()
    prof, changes = gr.taylor_ivp(w, th, bc, sigmas, order=2 * dps)
    s, c = mp.sin(th), mp.cos(th)
    worst = mpf(0)
    disp = 99.0
    for k, sg in enumerate(sigmas):
        y, _, x, z = prof[k]
        worst = max(
            worst,
            abs(y - vals["theta"][k]),
            abs(x - vals["x"][k]),
            abs(z - vals["z"][k]),
        )
        for got, ref in ((y - th, vals["dtheta"][k]), (x - sg * s, vals["dx"][k])):
            if ref and abs(ref) > mpf(10) ** (-dps + 15):
                disp = min(disp, _relative_digits(got, ref, 99))
        ref = vals["dz"][k]
        if ref and abs(ref) > mpf(10) ** (-dps + 15) * max(1, abs(vals["z"][k])):
            disp = min(disp, _relative_digits(z - sg * c, ref, 99))
    worst = max(worst, abs(prof[-1][1]) / max(1, abs(bc)))
    digits = gr._digits(worst, dps)
    label_ok = bc > 0 and changes == 0
    out = {
        "dps": dps,
        "digits": digits,
        "displacement_digits": disp,
        "theta_prime_1": mp.nstr(prof[-1][1], 5),
        "label_ok": label_ok,
        "seconds": round(time.time() - start, 1),
    }
    if digits < 25 or disp < 12 or not label_ok:
        raise RuntimeError(f"ODE check failed at theta0={theta0}: {out}")
    return out


def linear_theory_check(
    omega2: float, eps: float, theta0: float, vals: dict[str, Any], sigmas
) -> float:
    """Largest relative deviation of the displacements from linear theory.

    It must be O(W / cos theta0) (the next order), W = omega_eps^2, or at the level of the
    displacements' precision (1e-25).
    """
    th = mpf(theta0)
    s, c = mp.sin(th), mp.cos(th)
    w2 = vals["omega_eps"] ** 2
    worst = mpf(0)
    for k, sg in enumerate(sigmas):
        if sg == 0:
            continue
        u = mpf(sg)
        lin = {
            "dtheta": w2 * c * (u - u * u / 2),
            "dx": w2 * c * c * (u * u / 2 - u**3 / 6),
            "dz": -s * w2 * c * (u * u / 2 - u**3 / 6)
            if theta0 != 0
            else -(w2**2) / 2 * (u**3 / 3 - u**4 / 4 + u**5 / 20),
        }
        for key, v in lin.items():
            if vals[key][k] is not None:
                worst = max(worst, abs(vals[key][k] / v - 1))
    if worst > 10 * w2 / c + mpf(10) ** -DISPLACEMENT_DIGITS:
        raise RuntimeError(f"linear theory disagrees at {(omega2, eps, theta0)}: {worst}")
    return float(worst)


# ------------------------------------------------------------------------------------------
# Tasks
# ------------------------------------------------------------------------------------------


def _fmt_or_none(v: mpf | None) -> str | None:
    return None if v is None else _fmt(v)


def _pack_root(vals: dict[str, Any], checks: dict[str, Any], shape: bool) -> dict[str, Any]:
    entry = {k: _fmt(vals[k]) for k in FIELDS}
    entry["t"] = _fmt(vals["t"])
    entry["tip_displacement"] = _fmt_or_none(vals["tip_displacement"])
    if shape:
        for k in ("theta", "x", "z", "dtheta", "dx", "dz"):
            entry[k] = [_fmt_or_none(v) for v in vals[k]]
    entry["checks"] = checks
    return entry


def _condition(br: gr.Branch, t: mpf) -> tuple[float, float]:
    """|d xi / d ln omega2| and |d theta'(0) / d ln omega2| at the root t (central differences)."""
    h = mpf(10) ** -12
    vals = []
    for u in (t - h, t + h):
        st = br.state(u)
        w = st["w"]
        vals.append((st["q"], w * w - br.eps * w * mp.sqrt(2 * st["q"]), w * mp.sqrt(2 * st["q"])))
    (q0, w0, b0), (q1, w1, b1) = vals
    dlog = mp.log(w1 / w0)
    return float(abs((q1 - q0) / dlog)), float(abs((b1 - b0) / dlog))


def _cell_omega2s(s: dict[str, Any]) -> list[tuple[float, str]]:
    """The forcings tabulated in a cell: inside and outside its three-state window."""
    if s["folds"]:
        hi = float(max(f["omega2"] for f in s["folds"]))
        lo = float(min(f["omega2"] for f in s["folds"]))
        width = hi - lo
        return [
            (lo - 0.15 * width, "below"),
            (lo + 0.15 * width, "inside"),
            (lo + 0.5 * width, "inside"),
            (lo + 0.85 * width, "inside"),
            (hi + 0.15 * width, "above"),
        ]
    mp.dps = GRID_DPS
    br = gr.Branch(0.0, s["eps"], s["theta0"], 1, 0)
    w = float(_omega2(br, s["t_min_slope"]))
    return [(w * f, "monotone") for f in (0.5, 0.9, 1.0, 1.1, 2.0)]


def task_cell(eps: float, theta0: float, group: str, cross_check: bool) -> dict[str, Any]:
    start = time.time()
    s = branch_structure(eps, theta0)
    entries = []
    dropped = 0
    for omega2, where in _cell_omega2s(s):
        # tip_displacement ~ (theta0 + pi/2)^2 near -pi/2: more digits
        dps = CELL_DPS + 2 * max(0, int(-math.log10(math.cos(theta0))))
        ts = roots_on_branch(s, omega2, dps)
        roots = []
        kappas = []
        for t in ts:
            vals, checks = evaluate_root(omega2, eps, theta0, t, (), dps)
            mp.dps = dps
            k_xi, k_bc = _condition(gr.Branch(omega2, eps, theta0, 1, 0), vals["t"])
            checks["kappa_xi"] = round(k_xi, 3)
            checks["kappa_base_curvature"] = round(k_bc, 3)
            kappas.append(max(k_xi, k_bc))
            roots.append(_pack_root(vals, checks, shape=False))
        if kappas and max(kappas) > KAPPA_MAX:
            dropped += 1
            continue
        entry = {"omega2": omega2, "where": where, "n_roots": len(roots), "roots": roots}
        if cross_check:
            mp.dps = gr.DPS
            br = gr.Branch(omega2, eps, theta0, 1, 0)
            ts_ref, _ = gr.find_roots(br)
            ok = len(ts_ref) == len(ts) and all(
                abs(a - b) < mpf(10) ** -20 * max(1, abs(a)) for a, b in zip(ts_ref, ts)
            )
            if not ok:
                raise RuntimeError(f"find_roots disagrees at {(omega2, eps, theta0)}")
            entry["find_roots_agrees"] = True
        entries.append(entry)
    return {
        "kind": "cell",
        "group": group,
        "eps": eps,
        "theta0": theta0,
        "folds": [
            {
                "kind": f["kind"],
                "t": _fmt(f["t"]),
                "omega2": _fmt(f["omega2"]),
                "digits": f["digits"],
            }
            for f in s["folds"]
        ],
        "min_log_slope": _fmt(s["min_log_slope"]),
        "entries": entries,
        "dropped_ill_conditioned": dropped,
        "seconds": round(time.time() - start, 1),
    }


#: Groups whose shapes are tabulated (the others: the fields of every root only).
SHAPE_GROUPS = ("three_states", "near_half_pi", "weak")


def task_shapes(
    eps: float, theta0: float, items: list[tuple[float, list[str], bool]], independent: bool
) -> list[dict[str, Any]]:
    """Every root (and its shape) at (omega2, eps, theta0) for each item (omega2, groups, ode)."""
    s = branch_structure(eps, theta0)
    out = []
    for omega2, groups, ode in items:
        start = time.time()
        sigmas = SIGMA_SHAPE if any(g in SHAPE_GROUPS for g in groups) else ()
        dps = _shape_dps(omega2, theta0)
        ts = roots_on_branch(s, omega2, max(CELL_DPS, dps // 2 + 30))
        if independent:
            mp.dps = gr.DPS
            ts_ref, _ = gr.find_roots(gr.Branch(omega2, eps, theta0, 1, 0))
            assert len(ts_ref) == len(ts) and all(
                abs(a - b) < mpf(10) ** -20 * max(1, abs(a)) for a, b in zip(ts_ref, ts)
            ), (omega2, eps, theta0, ts_ref, ts)
        roots = []
        for t in ts:
            vals, checks = evaluate_root(omega2, eps, theta0, t, sigmas, dps)
            if checks["dps"] <= 150:
                leg = legendre_check(omega2, eps, theta0, vals, sigmas or (0.0, 1.0))
                if leg is not None:
                    checks["legendre_digits"] = leg
                    if leg < VALUE_DIGITS:
                        raise RuntimeError(f"route B disagrees at {(omega2, eps, theta0)}")
            if sigmas and omega2 <= 1e-8 and len(ts) == 1:
                lin = linear_theory_check(omega2, eps, theta0, vals, sigmas)
                checks["linear_theory_deviation"] = mp.nstr(lin, 3)
            if ode and sigmas:
                # the initial value problem amplifies errors by up to e^omega_eps (near
                # theta = pi/2, phi'' = omega_eps^2 phi) and the displacements need their digits
                small = min(abs(vals[k][-1]) for k in ("dtheta", "dx", "dz") if vals[k][-1])
                ode_dps = 30 + int(-mp.log10(small)) + int(vals["omega_eps"] / mp.log(10))
                ode_dps = min(max(45, ode_dps), 110)
                checks["ode"] = ode_check(theta0, vals, sigmas, ode_dps)
            roots.append(_pack_root(vals, checks, shape=bool(sigmas)))
        out.append(
            {
                "kind": "shape",
                "groups": groups,
                "omega2": omega2,
                "eps": eps,
                "theta0": theta0,
                "sigma": list(sigmas),
                "n_roots": len(roots),
                "roots": roots,
                "independent_root_search": independent,
                "seconds": round(time.time() - start, 1),
            }
        )
    return out


def run_task(task: tuple) -> tuple[str, Any]:
    name, args = task
    if name == "cell":
        return name, task_cell(*args)
    return name, task_shapes(*args)


# ------------------------------------------------------------------------------------------
# The inputs
# ------------------------------------------------------------------------------------------

#: The three-state input of the issue.
THREE_STATES = (2.2305002283179594, 0.5, -1.570795)
#: The scan near theta0 = -pi/2: theta0 = -pi/2 + delta, delta log-spaced from 1e-7 to
#: pi/2 - 1.45 (the last one is -1.45 exactly).
SCAN_DELTAS = 16
SCAN_EPS = (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99)
#: Base angles closer to -pi/2 (the upper fold moves to t ~ ln(theta0 + pi/2)); the last is
#: the double next above -pi/2.
EXTREME_THETA0 = (-1.570795, -1.5707963267, -1.5707963267948, -1.5707963267948963)
EXTREME_EPS = (0.3, 0.5, 0.9, 0.99)

#: Near theta0 = +pi/2: (omega2, eps, theta0) of the issue, then a grid.
NEAR_HALF_PI_ISSUE = ((1e4, 0.5, 1.5707963267948963), (400.0, 0.0, 1.5707963257948965))
NEAR_HALF_PI_THETA0 = (1.5707963267948963, 1.5707963257948965, 1.57079632, 1.5707, 1.55)
NEAR_HALF_PI_OMEGA2 = (1e-3, 1.0, 400.0, 1e4, 1e6)
NEAR_HALF_PI_EPS = (0.0, 0.5, 0.99)
#: Weak forcing (shapes) and the tip displacement.
WEAK_OMEGA2 = (1e-300, 1e-100, 1e-30, 1e-16, 1e-12, 1e-8)
WEAK_THETA0 = (0.0, 0.7, -0.7, 1.5)
TIP_OMEGA2 = (*WEAK_OMEGA2, 1e-4, 1e-2, 1.0, 10.0, 100.0, 1e3)
TIP_THETA0 = (*WEAK_THETA0, -1.5, 1.5707963267948963, -1.5707963267948963)
#: Inputs whose shapes are also integrated as an initial value problem.
ODE_INPUTS = {
    (400.0, 0.99, 1.5707963267948963),
    (400.0, 0.0, 1.5707963257948965),
    (1e-8, 0.5, 0.7),
    (1e-12, 0.5, 0.0),
    (1e-8, 0.5, 1.5),
    (1e-30, 0.5, -0.7),
}


def scan_theta0() -> list[float]:
    top = HALF_PI - 1.45
    out = [-HALF_PI + 1e-7 * (top / 1e-7) ** (k / (SCAN_DELTAS - 1)) for k in range(SCAN_DELTAS)]
    out[-1] = -1.45
    return out


def build_tasks(quick: bool = False) -> list[tuple]:
    tasks: list[tuple] = []
    thetas = scan_theta0()
    eps_list = SCAN_EPS
    if quick:
        thetas, eps_list = thetas[::5], eps_list[::3]
    for i, th in enumerate(thetas):
        for j, e in enumerate(eps_list):
            tasks.append(("cell", (e, th, "scan", (i + j) % 20 == 0)))
    for th in EXTREME_THETA0:
        for e in EXTREME_EPS:
            tasks.append(("cell", (e, th, "extreme", e == 0.5)))
    # shapes, grouped by (eps, theta0) so that each branch is tabulated once
    shape_items: dict[tuple[float, float], dict[float, list[str]]] = {}

    def add(omega2: float, eps: float, theta0: float, group: str) -> None:
        groups = shape_items.setdefault((eps, theta0), {}).setdefault(omega2, [])
        if group not in groups:
            groups.append(group)

    w2, e2, t2 = THREE_STATES
    add(w2, e2, t2, "three_states")
    for w, e, th in NEAR_HALF_PI_ISSUE:
        add(w, e, th, "near_half_pi")
    for i, th in enumerate(NEAR_HALF_PI_THETA0):
        for j, w in enumerate(NEAR_HALF_PI_OMEGA2):
            add(w, NEAR_HALF_PI_EPS[(i + j) % 3], th, "near_half_pi")
    for th in WEAK_THETA0:
        for w in WEAK_OMEGA2:
            add(w, 0.5, th, "weak")
    for w in (1e-30, 1e-12):
        for e in (0.0, 0.99):
            add(w, e, 0.7, "weak")
    for th in TIP_THETA0:
        for w in TIP_OMEGA2:
            add(w, 0.5, th, "tip")
    if quick:
        shape_items = {
            k: {w: g for w, g in v.items() if w >= 1e-30} for k, v in shape_items.items()
        }
    for (e, th), items in shape_items.items():
        entries = [
            (w, groups, (w, e, th) in ODE_INPUTS or "three_states" in groups)
            for w, groups in sorted(items.items())
        ]
        # the heavy weak-forcing inputs one per task, the rest together
        heavy = [it for it in entries if it[0] < 1e-20]
        light = [it for it in entries if it[0] >= 1e-20]
        independent = th == THREE_STATES[2] or (e, th) in {
            (x[1], x[2]) for x in NEAR_HALF_PI_ISSUE
        }
        for it in heavy:
            tasks.append(("shapes", (e, th, [it], False)))
        if light:
            tasks.append(("shapes", (e, th, light, independent)))
    return tasks


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="fewer inputs (a smoke test)")
    parser.add_argument("--out", type=Path, default=OUT_PATH)
    args = parser.parse_args(argv)
    tasks = build_tasks(args.quick)

    def cost(task: tuple) -> float:
        if task[0] == "cell":
            return 1.0 + 5.0 * task[1][3]
        items = task[1][2]
        return sum(3.0 + 20.0 * (w < 1e-20) * (-math.log10(w) / 100) for w, _, _ in items)

    order = sorted(range(len(tasks)), key=lambda i: -cost(tasks[i]))
    start = time.time()
    results: list[Any] = [None] * len(tasks)
    with multiprocessing.Pool(args.workers) as pool:
        for k, res in enumerate(pool.imap(run_task, [tasks[i] for i in order])):
            results[order[k]] = res
            name, value = res
            label = (
                f"cell eps={value['eps']} theta0={value['theta0']!r}"
                if name == "cell"
                else f"shapes {[(v['omega2'], v['eps'], v['theta0']) for v in value]}"
            )
            print(f"[{k + 1}/{len(tasks)}] {label} ({time.time() - start:.0f} s)", flush=True)
    elapsed = time.time() - start
    cells = [v for name, v in results if name == "cell"]
    shapes = [case for name, v in results if name == "shapes" for case in v]
    shapes.sort(key=lambda c: (c["theta0"], c["eps"], c["omega2"]))
    three = [c for c in shapes if "three_states" in c["groups"]]
    shape_roots = [r for c in shapes for r in c["roots"]]
    cell_roots = [r for c in cells for e in c["entries"] for r in e["roots"]]
    all_roots = shape_roots + cell_roots
    ode = [r["checks"]["ode"] for r in shape_roots if "ode" in r["checks"]]
    leg = [r["checks"]["legendre_digits"] for r in shape_roots if "legendre_digits" in r["checks"]]
    lin = [
        float(r["checks"]["linear_theory_deviation"])
        for r in shape_roots
        if "linear_theory_deviation" in r["checks"]
    ]
    metadata = {
        "about": "High-precision reference of the corner cases of the issue's wrong results, "
        "generated by tests/reference/generate_corners.py (reusing generate_reference.py; "
        "nothing from hairbed).",
        "mpmath_version": mpmath.__version__,
        "mpmath_backend": mpmath.libmp.BACKEND,
        "python_version": platform.python_version(),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "generation_seconds": round(elapsed, 1),
        "workers": args.workers,
        "quick": args.quick,
        "significant_digits_written": OUT_DIGITS,
        "sigma": list(SIGMA_SHAPE),
        "fields": list(FIELDS),
        "root_order": "increasing xi (root='low' first, 'high' last, 'mid' the middle of 3)",
        "displacements": "tip_displacement = tip_deflection - sin(theta0), dtheta = theta - "
        "theta0, dx = x - sigma sin(theta0), dz = z - sigma cos(theta0), each to 20 digits "
        "relative to itself",
        "n_cells": len(cells),
        "n_cell_entries": sum(len(c["entries"]) for c in cells),
        "n_cell_entries_dropped_ill_conditioned": sum(c["dropped_ill_conditioned"] for c in cells),
        "kappa_max": KAPPA_MAX,
        "n_shape_cases": len(shapes),
        "n_roots": len(all_roots),
        "checks": {
            "precision": f"every root re-refined and re-evaluated with {PRECISION_STEP} more "
            f"digits: values >= {min(r['checks']['precision_digits'] for r in all_roots)} "
            "digits, displacements >= "
            f"{min(r['checks']['displacement_precision_digits'] for r in all_roots)} digits "
            "relative to themselves",
            "route_b": f"{len(leg)} shape roots, >= {min(leg) if leg else None} digits",
            "ode": f"{len(ode)} shape roots, values >= "
            f"{min(c['digits'] for c in ode) if ode else None} digits, displacements >= "
            f"{min(c['displacement_digits'] for c in ode) if ode else None} digits relative",
            "find_roots": "generate_reference.find_roots found the same roots at "
            f"{sum(1 for c in cells for e in c['entries'] if e.get('find_roots_agrees'))} cell "
            f"entries and {sum(1 for c in shapes if c['independent_root_search'])} shape cases",
            "linear_theory": "weak-forcing displacements (omega2 <= 1e-8, "
            f"{len(lin)} roots) agree with linear theory to relative 10 W / cos(theta0) + "
            f"1e-{DISPLACEMENT_DIGITS}; largest deviation {max(lin) if lin else None:.3g}",
            "folds": "golden-section extremum vs zero of d omega2/dt at higher precision: >= "
            f"{min((f['digits'] for c in cells for f in c['folds']), default=None)} digits",
        },
    }
    out = {
        "metadata": metadata,
        "three_states": three[0] if three else None,
        "cells": cells,
        "shapes": shapes,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(f"{len(cells)} cells, {len(shapes)} shape cases, {elapsed:.0f} s; wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
