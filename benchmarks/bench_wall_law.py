"""Cost of the law-of-the-wall profile of a pillar (issue 31) over the viscous sublayer, as
ratios measured in one run.

The same SI pillar (500 um, 25 um, 1 MPa, in water) with ``profile="wall-law"`` and with the
default "sublayer" profile. Rows (each the best of ``--repeat`` runs):

1. one state (``Pillar.deform``, scalar, repeated: the profile of a stress met before is
   kept by the pillar);
2. a calibration curve of ``--num`` stresses from 0.01 to 10 Pa (L+ from 1.6 to 50): each
   stress has its own profile, one solve per distinct L+;
3. deflections to tau_w (``wall_shear_stress_from_tip_deflection``) of a tenth as many
   points: Newton in ln tau_w, a batched inverse a step;
4. ``Pillar.linear_range(0.01)``.

Run: ``python benchmarks/bench_wall_law.py [--quick] [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import warnings
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import hairbed
from hairbed import safe_files

__all__ = ["main", "run"]

GEOMETRY = {"length": 500e-6, "radius": 25e-6, "youngs_modulus": 1e6, "fluid": "water"}


def _best(func: Callable[[], Any], repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False, repeat: int = 3) -> dict[str, Any]:
    """Every row's times [s] and the ratio wall-law/sublayer."""
    warnings.simplefilter("ignore", hairbed.ModelValidityWarning)  # Re and L+: known here
    wall = hairbed.Pillar(**GEOMETRY, profile="wall-law")
    sub = hairbed.Pillar(**GEOMETRY)
    num = 50 if quick else 200
    tau = np.geomspace(1e-2, 10.0, num)
    d_wall = np.asarray(wall.deform(tau[::10]).tip_deflection)
    d_sub = np.asarray(sub.deform(tau[::10]).tip_deflection)
    rows: dict[str, Any] = {}

    def row(name: str, f_wall: Callable[[], Any], f_sub: Callable[[], Any], n: int) -> None:
        tw, ts = _best(f_wall, n), _best(f_sub, n)
        rows[name] = {"wall_law_s": tw, "sublayer_s": ts, "ratio": tw / ts}

    row("one_state", lambda: wall.deform(1.0), lambda: sub.deform(1.0), repeat * 10)
    row("curve", lambda: wall.deform(tau), lambda: sub.deform(tau), repeat)
    row(
        "inverse",
        lambda: wall.wall_shear_stress_from_tip_deflection(d_wall),
        lambda: sub.wall_shear_stress_from_tip_deflection(d_sub),
        repeat,
    )
    row("linear_range", lambda: wall.linear_range(0.01), lambda: sub.linear_range(0.01), 1)
    rows["curve"]["num"] = num
    rows["inverse"]["num"] = int(d_wall.size)
    return {"hairbed": hairbed.__version__, "numpy": np.__version__, "rows": rows}


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    out = run(args.quick, args.repeat)
    for name, r in out["rows"].items():
        shown = ", ".join(f"{k} = {v:.4g}" for k, v in r.items())
        print(f"{name:13s} {shown}")
    if args.json:  # written whole or not at all
        safe_files.write_bytes(args.json, json.dumps(out, indent=1).encode())
    return 0


if __name__ == "__main__":
    sys.exit(main())
