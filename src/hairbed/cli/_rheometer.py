"""``hairbed rheometer``: the bed's storage and loss moduli under small-amplitude oscillatory
shear about a pre-stress (hairbed.rheometer.bed_moduli, issue 31 §2a).

Large-amplitude shear (hairbed.rheometer.large_amplitude_shear, pipkin_map) exists in the
bed's units only (time in T, stress in E I/(A L^2)); it has no SI entry yet, so this command
gives the small-amplitude moduli only.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ._grids import spec
from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import NO_COMPRESS_HELP, check_dataset_output, print_json, write_dataset_output
from ._report import UsageError

#: ``hairbed rheometer --help``: the summary line, the description and the examples.
ABOUT = """the bed in a rheometer: G'(f), G''(f) and the phase about a pre-stress, the crossovers

Small-amplitude oscillatory shear of the bed of hairs between the channel's walls
(hairbed.rheometer.bed_moduli; its porous description, theory.md §13-§15, with the drag law
of --drag): the top wall oscillates about a steady speed --velocity [m/s] (the pre-stress,
default 0: the bed at rest) with a small strain gamma = delta/H, and the stress on it per
strain gives the complex modulus G* = G' + i G'' [Pa]. Prints, at each of --frequencies f [Hz],
G' [Pa], G'' [Pa], the phase delta = arg G* of the stress against the strain [deg] (above
90 the stress leads the wall's speed: inertia) and the status; above them, in '#' lines, the
pre-stress [Pa], the lead crossover (G' changes sign) and the modulus crossover (G' = G'')
[Hz] ("none within the frequencies" where none lies in them; null in JSON, NaN in files),
the time scale T = zeta L^4/(E I) [s], the modulus scale E I/(A L^2) [Pa] and the groups
kappa, eps, the Womersley number (from --density; a quasi-steady fluid without it) and the
hairs' inertia number (from --hair-density; overdamped hairs without it). --json prints one
JSON document; --out FILE writes a dataset with units (.nc, .zarr, .csv, .parquet). SPEC is
a value, a list A,B,... or START:STOP:NUM[:log], increasing and > 0.

Large-amplitude shear (harmonics, Ewoldt's measures) exists only in the bed's units
(hairbed.rheometer.large_amplitude_shear): not on the command line yet.

examples:
  hairbed rheometer --frequencies 0.1:1000:41:log --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 250e-6 \\
      --density 1000
  hairbed rheometer --frequencies 1,10,100 --velocity 1e-3 --length 1e-3 ... --json
"""

__all__ = ["ABOUT", "add_parser", "run"]

#: The units of the '#' summary (and of JSON's "units").
SUMMARY_UNITS = {
    "velocity": "m/s",
    "pre_stress": "Pa",
    "lead_crossover": "Hz",
    "modulus_crossover": "Hz",
    "time_scale": "s",
    "modulus_scale": "Pa",
    "kappa": "1",
    "eps": "1",
    "womersley": "1",
    "inertia": "1",
}


def add_parser(sub: Any) -> None:
    """The ``rheometer`` subcommand's parser."""
    p = add_command(sub, "rheometer", run, ABOUT)
    g = p.add_argument_group("the oscillation")
    g.add_argument(
        "--frequencies",
        required=True,
        metavar="SPEC",
        help="the frequencies f [Hz], finite, > 0 and increasing",
    )
    g.add_argument(
        "--velocity",
        type=float,
        default=0.0,
        metavar="V",
        help="the top wall's steady speed of the pre-stress [m/s] (default 0; the sign is the "
        "direction)",
    )
    g.add_argument(
        "--hair-density",
        type=float,
        metavar="RHO",
        help="the hairs' density [kg/m^3] (their inertia; overdamped without it)",
    )
    g.add_argument(
        "--out",
        metavar="FILE",
        help="a dataset with units: .nc, .zarr, .csv or .parquet (a table on stdout without it)",
    )
    g.add_argument("--no-compress", action="store_true", help=NO_COMPRESS_HELP)
    add_json(p)
    add_bed_options(p, velocity=False, model=True)


def _frequencies(text: str) -> Any:
    """--frequencies: finite, > 0, increasing (a usage error naming the first bad index)."""
    f = np.asarray(spec(text, "--frequencies"), dtype=np.float64).reshape(-1)
    bad = ~np.isfinite(f) | (f <= 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise UsageError(
            f"--frequencies must be finite and > 0 [Hz], got {float(f[i])!r} (first at index {i})"
        )
    if f.size > 1 and np.any(np.diff(f) <= 0.0):
        i = int(np.flatnonzero(np.diff(f) <= 0.0)[0]) + 1
        raise UsageError(f"--frequencies must increase, got f[{i}] <= f[{i - 1}]")
    return f


def _worst(status: Any) -> int:
    """The status that speaks for all frequencies: a failure first, else the largest."""
    s = np.asarray(status).reshape(-1)
    return int(s.min()) if s.min() < 0 else int(s.max())


def run(args: argparse.Namespace) -> int:
    """``hairbed rheometer``."""
    from hairbed.rheometer import SAOS_STATUS, bed_moduli

    if not math.isfinite(args.velocity):
        raise UsageError(f"--velocity must be a finite speed [m/s], got {args.velocity!r}")
    freq = _frequencies(args.frequencies)
    bed = need_bed(args, "rheometer")
    to_stdout = args.out is None or check_dataset_output(args.out, args.no_compress)
    if args.json and not to_stdout:
        raise UsageError("--json and --out cannot be combined")
    try:
        r = bed_moduli(bed, freq, args.velocity, hair_density=args.hair_density)
    except ValueError as exc:  # the hairs' inertia number out of the linear bed's range
        if args.hair_density is None or not str(exc).startswith("inertia"):
            raise
        raise UsageError(f"--hair-density {args.hair_density!r} gives {exc}") from None
    d = r.dimensionless
    storage, loss = r.storage[:, 0], r.loss[:, 0]
    phase = np.degrees(d.phase[:, 0])
    status = r.status[:, 0]
    worst = _worst(status)
    summary: dict[str, Any] = {
        "velocity": float(r.speed[0]),
        "pre_stress": float(r.pre_stress[0]),
        "lead_crossover": float(r.lead_crossover[0]),
        "modulus_crossover": float(r.modulus_crossover[0]),
        "time_scale": r.time_scale,
        "modulus_scale": r.modulus_scale,
        "kappa": d.kappa,
        "eps": d.eps,
        "womersley": d.womersley,
        "inertia": d.inertia,
        "status": worst,
        "message": SAOS_STATUS[worst],
    }
    if args.json:
        print_json(
            {
                "units": {"frequency": "Hz", "storage": "Pa", "loss": "Pa", "phase": "deg"}
                | SUMMARY_UNITS,
                "frequency": r.frequency.tolist(),
                "storage": storage.tolist(),
                "loss": loss.tolist(),
                "phase": phase.tolist(),
                "frequency_status": status.tolist(),
                **summary,
            }
        )
    elif not to_stdout:
        ds = r.to_xarray()
        ds["phase"] = (
            ("frequency", "pre_stress"),
            np.degrees(d.phase),
            {"units": "deg", "long_name": "stress phase against the strain"},
        )
        for key in ("kappa", "eps", "womersley", "inertia"):
            ds.attrs[key] = summary[key]
        write_dataset_output(ds, args.out, args.no_compress)
    else:
        for key, value in summary.items():
            unit = SUMMARY_UNITS.get(key)
            shown = repr(value) if isinstance(value, float) else str(value)
            if key.endswith("_crossover") and not math.isfinite(value):
                shown = "none within the frequencies"  # the CSV's words, not a bare nan
            print(f"# {key} = {shown} [{unit}]" if unit else f"# {key} = {shown}")
        print("frequency [Hz],storage [Pa],loss [Pa],phase [deg],status")
        for f, gs, gl, ph, st in zip(r.frequency, storage, loss, phase, status):
            print(f"{float(f)!r},{float(gs)!r},{float(gl)!r},{float(ph)!r},{int(st)}")
    return 0 if worst >= 0 else 1
