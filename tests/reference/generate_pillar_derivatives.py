"""Generate ``tests/data/pillar_derivatives_mpmath.json``: derivatives of pillar states (issue 21).

Run on demand (a few minutes on two cores)::

    .venv/bin/python tests/reference/generate_pillar_derivatives.py [--workers 2] [--out PATH]

It imports nothing from :mod:`hairbed`: the states are those of the independent mpmath
shooting of ``generate_pillar.py`` (Taylor-series integration, Newton at raised precision,
written from docs/theory.md §12), and the derivatives are its central differences

    dY/dp = (Y(p + h) - Y(p - h))/(2 h),   h = ``STEP`` (relative for Lambda),

in Lambda, theta0, gamma and (Poiseuille) the height ratio L/H (U = z - (L/H) z^2), every
perturbed state re-converged from the central one at the working precision (40 digits plus
the base amplification's): the truncation error is O(h^2) ~ 1e-24, the rounding
10^-(dps - 2)/h ~ 1e-26. Check: each derivative again with h/2 agrees to ``STEP_TOL``
(relative to max(1, abs(value))). Outputs: tip deflection, tip height, tip angle, base
curvature, drag_x, drag_z (lengths in L, forces in E I/L^2), written as strings of
``OUT_DIGITS`` digits.
"""

from __future__ import annotations

import argparse
import datetime
import json
import multiprocessing
import sys
import time
from pathlib import Path
from typing import Any

import mpmath
from mpmath import mp, mpf

sys.path.insert(0, str(Path(__file__).resolve().parent))
import generate_pillar as gp  # noqa: E402  (the reference solver, next to this file)

OUT_PATH = Path(__file__).resolve().parents[1] / "data" / "pillar_derivatives_mpmath.json"
STEP = mpf("1e-12")
STEP_TOL = mpf("1e-18")
OUT_DIGITS = 25
OUTPUTS = ("tip_deflection", "tip_height", "tip_angle", "base_curvature", "drag_x", "drag_z")
#: (profile, L/H or None, gamma (decimal string or "gh"), theta0, Lambda)
STATES = [
    ("sublayer", None, "0.5", 0.0, 1e-3),
    ("sublayer", None, "0.5", 0.3, 3.0),
    ("sublayer", None, "gh", -0.8, 50.0),
    ("sublayer", None, "0.6", 1.2, 200.0),
    ("sublayer", None, "0.5", -1.3, 0.5),
    ("poiseuille", "0.6", "0.5", 0.2, 20.0),
    ("poiseuille", "1", "gh", -0.5, 100.0),
    ("poiseuille", "0.3", "0.7", 1.0, 5.0),
    ("couette", "0.5", "0.5", 0.6, 30.0),
    ("callable", None, "0.55", -0.4, 40.0),
]


def _case(profile: str, ratio: str | None, gamma: str, theta0: float) -> dict[str, Any]:
    g = mp.nstr(gp.gray_hancock_gamma(gp.SLENDERNESS), 40) if gamma == "gh" else gamma
    params = {"L/H": ratio} if ratio is not None else {}
    return gp._prepare(
        {"profile": profile, "profile_parameters": params, "gamma": g, "theta0": theta0}
    )


def _outputs(unk: list[Any], r: dict[str, Any]) -> dict[str, Any]:
    end = r["nodes"][-1]
    return {
        "tip_deflection": end[4],
        "tip_height": end[5],
        "tip_angle": end[0],
        "base_curvature": unk[0],
        "drag_x": unk[1],
        "drag_z": unk[2],
    }


def _solve(c: dict[str, Any], unk: list[Any], lam: Any) -> tuple[list[Any], dict[str, Any]]:
    order, off = gp.ORDERS[0]
    unk, _, r = gp.newton_mp(c, unk, lam, order, off)
    return unk, _outputs(unk, r)


def _jacobian(c: dict[str, Any], unk: list[Any], lam: Any) -> Any:
    """d(residual)/d(m0, F_x0, F_z0) at the central state, by differences at step
    10^(-dps/2) (as generate_pillar.newton_mp)."""
    order, off = gp.ORDERS[0]
    res, _ = gp.residual_mp(c, unk, lam, order, off)
    jac = mpmath.matrix(3, 3)
    for i in range(3):
        w = list(unk)
        dh = mpf(10) ** (-(mp.dps // 2)) * max(mpf(1), abs(unk[i]))
        w[i] += dh
        ri, _ = gp.residual_mp(c, w, lam, order, off)
        for j in range(3):
            jac[j, i] = (ri[j] - res[j]) / dh
    return jac


def _chord(
    c: dict[str, Any], unk: list[Any], lam: Any, jac: Any
) -> tuple[list[Any], dict[str, Any]]:
    """A perturbed state by chord iterations with the central state's Jacobian (the
    perturbation is 1e-12: each iteration gains about 12 digits)."""
    order, off = gp.ORDERS[0]
    v = list(unk)
    scale = max(mpf(1), max(abs(q) for q in v))
    for _ in range(12):
        res, r = gp.residual_mp(c, v, lam, order, off)
        if max(abs(q) for q in res) < mpf(10) ** (-(mp.dps - 2)) * scale:
            return v, _outputs(v, r)
        dv = mpmath.lu_solve(jac, mpmath.matrix([-q for q in res]))
        v = [v[i] + dv[i] for i in range(3)]
    raise RuntimeError(f"{c['label']}: chord iterations do not converge")


def compute(item: tuple[Any, ...]) -> dict[str, Any]:
    t0 = time.time()
    profile, ratio, gamma, theta0, lam_f = item
    c = _case(profile, ratio, gamma, theta0)
    guess = gp.continue_branch(c, [lam_f])["states"][lam_f]
    if len(guess) != 1:
        raise RuntimeError(f"{c['label']}: {len(guess)} states at Lambda = {lam_f}")
    amp = gp.amplification(c, guess[0], lam_f)
    mp.dps = gp.DPS + int(amp / 2.302585 * 1.2) + 4
    gp._mp_setup(c)
    lam = mpf(lam_f)
    unk0, base = _solve(c, [mpf(float(q)) for q in guess[0]], lam)
    jac = _jacobian(c, unk0, lam)
    inputs = ["forcing", "theta0", "gamma"] + (["height_ratio"] if profile == "poiseuille" else [])
    derivs: dict[str, dict[str, str]] = {o: {} for o in OUTPUTS}
    worst = mpf(0)
    for name in inputs:
        est = []
        for h in (STEP, STEP / 2):
            vals = []
            for sgn in (1, -1):
                cc = dict(c)
                lm = lam
                if name == "forcing":
                    lm = lam * (1 + sgn * h)
                elif name == "theta0":
                    cc["m_theta0"] = c["m_theta0"] + sgn * h
                elif name == "gamma":
                    cc["m_gamma"] = c["m_gamma"] + sgn * h
                else:  # U = z - r z^2: a2 = -r
                    cc["m_a2"] = c["m_a2"] - sgn * h
                _, out = _chord(cc, unk0, lm, jac)
                vals.append(out)
            width = 2 * h * (lam if name == "forcing" else 1)
            est.append({o: (vals[0][o] - vals[1][o]) / width for o in OUTPUTS})
        for o in OUTPUTS:
            d = abs(est[0][o] - est[1][o]) / max(mpf(1), abs(est[1][o]))
            worst = max(worst, d)
            if d > STEP_TOL:
                raise RuntimeError(f"{c['label']} {name} {o}: steps disagree by {d}")
            derivs[o][name] = mp.nstr(est[1][o], OUT_DIGITS)
    rec = {
        "profile": profile,
        "height_ratio": None if ratio is None else float(ratio),
        "gamma": c["gamma"],
        "theta0": theta0,
        "forcing": lam_f,
        "state": {o: mp.nstr(base[o], OUT_DIGITS) for o in OUTPUTS},
        "d": derivs,
        "checks": {"dps": mp.dps, "steps_agree": mp.nstr(worst, 3)},
        "seconds": round(time.time() - t0, 1),
    }
    mp.dps = 30
    return rec


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=OUT_PATH)
    args = ap.parse_args(argv)
    t0 = time.time()
    cases = []
    with multiprocessing.Pool(args.workers) as pool:
        for rec in pool.imap_unordered(compute, STATES, chunksize=1):
            cases.append(rec)
            print(
                f"{rec['profile']} theta0={rec['theta0']} Lambda={rec['forcing']}: "
                f"{rec['seconds']} s",
                flush=True,
            )
    cases.sort(key=lambda r: STATES.index(
        next(s for s in STATES if s[0] == r["profile"] and s[3] == r["theta0"]
             and s[4] == r["forcing"])))  # fmt: skip
    doc = {
        "generator": "tests/reference/generate_pillar_derivatives.py",
        "generated": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "mpmath": mpmath.__version__,
        "step": str(STEP),
        "step_tol": str(STEP_TOL),
        "note": "central differences of the mpmath shooting of generate_pillar.py; forcing "
        "is Lambda; gamma a decimal string; height_ratio the L/H of U = z - (L/H) z^2",
        "cases": cases,
        "seconds": round(time.time() - t0, 1),
    }
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    print(f"wrote {args.out} ({len(cases)} states, {doc['seconds']} s)")


if __name__ == "__main__":
    main()
