"""``hairbed measure --pillar --series data.csv``: a tip-deflection series to the stress series.

The pillar sensor in time (hairbed.sensor_dynamics.wall_shear_stress_from_tip_deflection_series,
theory.md §14): the exact static inverse about the mean and a Wiener deconvolution of the
dynamics. The CSV has a header line with ``tip_deflection [m]`` and optionally ``time [s]``
(uniform; else --sample-rate [Hz]); the output is a CSV (or with --json one JSON document) of
time [s], wall_shear_stress [Pa], its 1-sigma band [Pa] and the quasi-static deflection [m].
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from typing import Any

from hairbed.sensor_dynamics import wall_shear_stress_from_tip_deflection_series

from ._options import sensor_pillar_from
from ._output import print_json, read_input
from ._report import UsageError

__all__ = ["add_series_options", "refuse_series_options", "run_series"]


def add_series_options(p: argparse.ArgumentParser) -> None:
    """The options of a measured series (with --pillar)."""
    g = p.add_argument_group(
        "a tip-deflection series (with --pillar; theory.md §14; --sigma is the noise [m], "
        "estimated where 0)"
    )
    g.add_argument(
        "--series",
        metavar="FILE.csv",
        help="a tip-deflection series: CSV with the columns tip_deflection [m] and optionally "
        "time [s] (uniform); prints the wall-shear-stress series with its 1-sigma band",
    )
    g.add_argument("--sample-rate", type=float, metavar="HZ", help="the series' rate [Hz]")
    g.add_argument(
        "--pillar-density",
        type=float,
        metavar="RHO",
        help="the pillar's density [kg/m^3] (its inertia), needed with --series",
    )
    g.add_argument(
        "--series-drag",
        choices=("sader", "quasi-steady"),
        default="sader",
        help="the drag of the pillar's motion, default sader (Sader's oscillating cylinder)",
    )


def refuse_series_options(args: argparse.Namespace) -> None:
    """A series option given without --series: a usage error naming it."""
    for opt, name, default in (
        ("--sample-rate", "sample_rate", None),
        ("--pillar-density", "pillar_density", None),
        ("--series-drag", "series_drag", "sader"),
    ):
        if getattr(args, name) != default:
            raise UsageError(f"{opt} needs --series (a tip-deflection series)")


def read_series(path: str) -> tuple[list[float], list[float] | None]:
    """(tip deflections [m], times [s] or None) of a series CSV (a header line; ``#`` lines
    and empty lines skipped; a unit in brackets must be the SI one)."""
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise ValueError(f"{path}: needs a header line and rows of tip_deflection [m]")
    units = {"tip_deflection": "m", "time": "s"}
    header = []
    for cell in rows[0]:
        name, _, unit = cell.strip().partition("[")
        name = name.strip().lower()
        if name not in units:
            raise ValueError(f"{path}: unknown column {cell.strip()!r} (tip_deflection, time)")
        if unit and unit.rstrip("] ").strip() != units[name]:
            raise ValueError(f"{path}: column {name} must be in [{units[name]}], got {cell!r}")
        header.append(name)
    if "tip_deflection" not in header:
        raise ValueError(f"{path}: needs a tip_deflection column [m]")
    cols: dict[str, list[float]] = {h: [] for h in header}
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise ValueError(f"{path}: line {i} has {len(row)} fields, not {len(header)}")
        for h, cell in zip(header, row):
            try:
                cols[h].append(float(cell))
            except ValueError:
                raise ValueError(f"{path}: line {i}, {h}: not a number: {cell!r}") from None
    return cols["tip_deflection"], cols.get("time")


def run_series(args: argparse.Namespace) -> int:
    """The stress series of --series on the --pillar; CSV (or JSON) on stdout."""
    if not args.pillar:
        raise UsageError("--series needs --pillar (an isolated pillar sensor)")
    if args.calibration is not None:
        raise UsageError("--series takes the pillar's options, not --calibration")
    if args.tip_deflection is not None:
        raise UsageError("give --tip-deflection or --series, not both")
    if args.pillar_density is None:
        raise UsageError("--series needs --pillar-density [kg/m^3] (the pillar's inertia)")
    if not (math.isfinite(args.sigma) and args.sigma >= 0.0):
        raise UsageError(
            f"--sigma must be the series' noise [m], finite and >= 0 (0: estimated from the "
            f"series), got {args.sigma!r}"
        )
    pillar = sensor_pillar_from(args, "measure --series")
    deflection, times = read_input(read_series, args.series, "--series")
    if (times is None) == (args.sample_rate is None):
        raise UsageError("--series needs a time column [s] or --sample-rate [Hz], not both")
    out = wall_shear_stress_from_tip_deflection_series(
        pillar,
        deflection,
        args.sample_rate,
        times=times,
        noise_sigma=args.sigma if args.sigma > 0.0 else None,
        pillar_density=args.pillar_density,
        drag=args.series_drag,
    )
    resp: Any = out.response
    if args.json:
        print_json(
            {
                "units": {
                    "time": "s",
                    "wall_shear_stress": "Pa",
                    "wall_shear_stress_sigma": "Pa",
                    "quasi_static_deflection": "m",
                    "frequency": "Hz",
                    "stress_spectrum": "Pa^2/Hz",
                },
                "time": out.time.tolist(),
                "wall_shear_stress": out.wall_shear_stress.tolist(),
                "wall_shear_stress_sigma": out.wall_shear_stress_sigma.tolist(),
                "quasi_static_deflection": out.quasi_static_deflection.tolist(),
                "frequency": out.frequency.tolist(),
                "stress_spectrum": out.stress_spectrum.tolist(),
                "mean_wall_shear_stress": out.mean_wall_shear_stress,
                "noise_sigma": out.noise_sigma,
                "noise_estimated": out.noise_estimated,
                "sample_rate": out.sample_rate,
                "drag": resp.drag,
                "resonance_frequency": resp.resonance_frequency,
                "quality_factor": resp.quality_factor,
                "bandwidth": resp.bandwidth,
                "success": out.success,
                "message": out.message,
            }
        )
        return 0
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(
        [
            "time [s]",
            "wall_shear_stress [Pa]",
            "wall_shear_stress_sigma [Pa]",
            "quasi_static_deflection [m]",
        ]
    )
    for row in zip(
        out.time,
        out.wall_shear_stress,
        out.wall_shear_stress_sigma,
        out.quasi_static_deflection,
    ):
        w.writerow([f"{v:.10g}" for v in row])
    return 0
