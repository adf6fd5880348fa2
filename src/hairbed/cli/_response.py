"""``hairbed response``: a pillar sensor's frequency response, resonance and bandwidth.

hairbed.Pillar.frequency_response (theory.md §14): the tip deflection per wall shear stress
H(f) [m/Pa] linearised about the static state at the mean stress, with the resonance, its
quality factor and the usable bandwidth. CSV on stdout (the summary in ``#`` lines above the
header), one JSON document (--json), or a file by its extension (--out: .nc with the summary
in its attributes, .csv, .parquet, .zarr).
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import warnings
from typing import Any

import numpy as np

from ..sensor_dynamics import BANDWIDTH_MIN_TOLERANCE
from ._options import add_bed_options, add_command, add_json, add_sensor_pillar_options
from ._options import sensor_pillar_from as _pillar_from
from ._output import check_dataset_output, print_json, write_dataset_output
from ._report import UsageError

#: The smallest --phase-tolerance [deg]: the library's smallest tolerance, 1e-12 rad.
_PHASE_MIN_DEG = math.degrees(BANDWIDTH_MIN_TOLERANCE)

#: ``hairbed response --help``: the summary line, the description and the examples.
ABOUT = """a pillar sensor's frequency response: magnitude, phase, resonance, Q, bandwidth

The tip deflection per wall shear stress H(f) [m/Pa] of an isolated pillar sensor
(hairbed.Pillar.frequency_response, theory.md §14), linearised about its static state at the
mean --wall-shear-stress (default 0), with Sader's oscillating-cylinder drag (default) or the
quasi-steady resistive force with the fluid's added mass (--drag-model). The pillar is given as for
'hairbed measure --pillar' with the fluid's density (--fluid, or --viscosity with --density);
--pillar may be left out. Prints frequency [Hz], magnitude [m/Pa] and phase [deg] (a lag is
negative) at --frequencies (log-spaced from a spec LO:HI:N, or a list), and above them, in
'#' lines, the static gain [m/Pa], the resonance frequency [Hz], its quality factor and the
bandwidth [Hz] where abs(H)/H(0) stays within --magnitude-tolerance of 1 and the phase within
--phase-tolerance [deg] of 0.

Sweeps (hairbed.sweeps, dask with --chunks): --mean-stresses SPEC maps H over the grid of
(mean stress, frequency) (response_sweep); --amplitudes SPEC integrates the nonlinear pillar
under tau_w(t) = tau + a sin(2 pi f t) over the grid of (amplitude, frequency) about
--wall-shear-stress (amplitude_sweep, quasi-steady drag): the first harmonic per amplitude
beside the linear H, the mean shift and the distortion. Either writes a dataset to --out
(.nc, .zarr, .csv, .parquet) or a long CSV table on stdout; SPEC is a value, a list A,B,...
or START:STOP:NUM[:log]. Phases are in degrees everywhere.

examples:
  hairbed response --pillar-density 970 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --fluid water --frequencies 1:2000:200 > bode.csv
  hairbed response --pillar-density 970 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --fluid water --frequencies 1:2000:50 \\
      --mean-stresses 0:4:9 --chunks 3 --out bode_map.nc
  hairbed response --pillar-density 970 --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --fluid air --frequencies 100,447,1000 --json
"""

__all__ = ["ABOUT", "add_parser", "parse_frequencies", "run"]

#: The most frequencies of a LO:HI:N spec.
MAX_N = 1_000_000


def add_parser(sub: Any) -> None:
    """The ``response`` subcommand's parser."""
    p = add_command(sub, "response", run, ABOUT)
    g = p.add_argument_group("the response")
    g.add_argument(
        "--frequencies",
        default="1:1000:200",
        metavar="SPEC",
        help="LO:HI:N, N log-spaced frequencies from LO > 0 to HI [Hz] (LO:HI:N:log is the "
        "same), or a comma-separated list F1,F2,... [Hz] >= 0 (default 1:1000:200)",
    )
    g.add_argument(
        "--wall-shear-stress",
        type=float,
        default=0.0,
        metavar="TAU",
        help="the mean stress of the linearisation [Pa] (default 0)",
    )
    g.add_argument(
        "--pillar-density",
        type=float,
        required=True,
        metavar="RHO",
        help="the pillar's density [kg/m^3] (its inertia; PDMS about 970)",
    )
    g.add_argument(
        "--drag-model",
        choices=("sader", "quasi-steady"),
        default="sader",
        help="the drag of the motion (default sader, Sader's oscillating cylinder)",
    )
    g.add_argument(
        "--magnitude-tolerance",
        type=float,
        default=0.05,
        metavar="R",
        help="the bandwidth's magnitude tolerance, relative, in "
        f"[{BANDWIDTH_MIN_TOLERANCE:g}, 1) (default 0.05)",
    )
    g.add_argument(
        "--phase-tolerance",
        type=float,
        default=5.0,
        metavar="DEG",
        help=f"the bandwidth's phase tolerance [deg], in [{_PHASE_MIN_DEG:.3g}, 180) (default 5)",
    )
    g.add_argument(
        "--mean-stresses",
        metavar="SPEC",
        help="sweep the mean stress [Pa] too: the (wall_shear_stress, frequency) grid of H "
        "as a dataset (hairbed.sweeps.response_sweep)",
    )
    g.add_argument(
        "--amplitudes",
        metavar="SPEC",
        help="the nonlinear periodic response over (amplitude [Pa] > 0, frequency) about "
        "--wall-shear-stress (hairbed.sweeps.amplitude_sweep; quasi-steady drag)",
    )
    g.add_argument(
        "--chunks",
        type=int,
        metavar="N",
        help="compute a sweep in chunks of N along each dimension with dask",
    )
    g.add_argument(
        "--out",
        metavar="FILE",
        help="write to FILE by its extension (.nc, .csv, .parquet, .zarr) instead of CSV on "
        "stdout",
    )
    add_json(p, "print one JSON document (with the units) instead of CSV")
    add_bed_options(p, velocity=False)
    add_sensor_pillar_options(p)
    for action in p._actions:  # a bed's, refused for a pillar: not in the help
        if action.dest in ("spacing", "packing_fraction"):
            action.help = argparse.SUPPRESS


def parse_frequencies(spec: str) -> Any:
    """The frequencies [Hz] of ``LO:HI:N`` (log-spaced; ``LO:HI:N:log``, the spelling of
    every other SPEC, is the same) or ``F1,F2,...``; a usage error naming --frequencies
    otherwise."""
    text = spec.strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) == 4 and parts[3].strip() == "log":
            parts = parts[:3]
        try:
            if len(parts) != 3:
                raise ValueError
            lo, hi, n = float(parts[0]), float(parts[1]), int(parts[2])
        except ValueError:
            raise UsageError(
                f"--frequencies {spec!r}: expected LO:HI:N or LO:HI:N:log, both log-spaced "
                "(numbers, N an integer)"
            ) from None
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi and 2 <= n <= MAX_N):
            raise UsageError(
                f"--frequencies {spec!r}: needs 0 < LO < HI finite [Hz] and N in [2, {MAX_N}]"
            )
        return np.geomspace(lo, hi, n)
    try:
        values = np.array([float(v) for v in text.split(",")], dtype=np.float64)
    except ValueError:
        raise UsageError(
            f"--frequencies {spec!r}: expected LO:HI:N or a list F1,F2,... of numbers [Hz]"
        ) from None
    return values


def _summary(r: Any) -> dict[str, Any]:
    return {
        "static_gain": r.static_gain,
        "resonance_frequency": r.resonance_frequency,
        "quality_factor": r.quality_factor,
        "bandwidth": r.bandwidth,
        "magnitude_tolerance": r.magnitude_tolerance,
        "phase_tolerance": math.degrees(r.phase_tolerance),
        "wall_shear_stress": r.wall_shear_stress,
        "drag": r.drag,
        "time_scale": r.time_scale,
        "inertia_number": r.inertia_number,
        "valid_below": r.valid_below,
        "status": r.status,
        "success": r.success,
        "message": r.message,
    }


#: The summary's units (JSON's "units", the CSV's '#' lines).
SUMMARY_UNITS = {
    "static_gain": "m/Pa",
    "resonance_frequency": "Hz",
    "quality_factor": "1",
    "bandwidth": "Hz",
    "magnitude_tolerance": "1",
    "phase_tolerance": "deg",
    "wall_shear_stress": "Pa",
    "time_scale": "s",
    "inertia_number": "1",
    "valid_below": "Hz",
}


def _sweep(args: argparse.Namespace, pillar: Any, freq: Any) -> int:
    """--mean-stresses or --amplitudes: a dataset to --out or a long CSV on stdout."""
    from hairbed import sweeps

    if args.mean_stresses is not None and args.amplitudes is not None:
        raise UsageError("give --mean-stresses or --amplitudes, not both")
    if args.json:
        raise UsageError(
            "a sweep is a dataset: give --out FILE or none (CSV on stdout), not --json"
        )
    if args.chunks is not None and args.chunks < 1:
        raise UsageError(f"--chunks must be an integer >= 1, got {args.chunks}")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if args.mean_stresses is not None:
            stress = sweeps.parse_spec(args.mean_stresses, "--mean-stresses")
            ds = sweeps.response_sweep(
                pillar,
                freq,
                stress,
                pillar_density=args.pillar_density,
                drag=args.drag_model,
                chunks=args.chunks,
            )
        else:
            if args.drag_model != "quasi-steady":
                raise UsageError(
                    "--amplitudes integrates the pillar in time with the quasi-steady drag: "
                    "give --drag-model quasi-steady"
                )
            amps = sweeps.parse_spec(args.amplitudes, "--amplitudes")
            ds = sweeps.amplitude_sweep(
                pillar,
                amps,
                freq,
                wall_shear_stress=args.wall_shear_stress,
                pillar_density=args.pillar_density,
                chunks=args.chunks,
            )
        ds = ds.compute()
    for note in caught:
        warnings.warn_explicit(note.message, note.category, note.filename, note.lineno)
    if "phase" in ds.data_vars and ds["phase"].attrs.get("units") == "rad":
        # the CLI's phases are in degrees, as the plain response's
        ds["phase"] = np.degrees(ds["phase"]).assign_attrs({**ds["phase"].attrs, "units": "deg"})
    write_dataset_output(ds, args.out)
    return 0


def _tolerances(args: argparse.Namespace) -> tuple[float, float]:
    """(--magnitude-tolerance, --phase-tolerance [deg]) within the library's ranges
    (:data:`hairbed.sensor_dynamics.BANDWIDTH_MIN_TOLERANCE`: below, abs(H)/H(0) - 1 is
    rounding), else a one-line usage error naming the option."""
    mtol, ptol = args.magnitude_tolerance, args.phase_tolerance
    if not BANDWIDTH_MIN_TOLERANCE <= mtol < 1.0:
        raise UsageError(
            f"--magnitude-tolerance must be in [{BANDWIDTH_MIN_TOLERANCE:g}, 1), got {mtol!r}"
        )
    if not (BANDWIDTH_MIN_TOLERANCE <= math.radians(ptol) and ptol < 180.0):
        raise UsageError(
            f"--phase-tolerance must be in [{_PHASE_MIN_DEG:.3g}, 180) [deg], got {ptol!r}"
        )
    return mtol, ptol


def run(args: argparse.Namespace) -> int:
    """The response as CSV (the summary in '#' lines), JSON or a file."""
    if args.json and args.out is not None:
        raise UsageError("give --json or --out, not both")
    if not args.json:
        check_dataset_output(args.out)
    mtol, ptol = _tolerances(args)
    freq = parse_frequencies(args.frequencies)
    pillar = _pillar_from(args, "response")
    if args.mean_stresses is not None or args.amplitudes is not None:
        return _sweep(args, pillar, freq)
    if args.chunks is not None:
        raise UsageError("--chunks is for a sweep: give --mean-stresses or --amplitudes")
    with warnings.catch_warnings(record=True) as caught:  # an error alone is one line
        warnings.simplefilter("always")
        r = pillar.frequency_response(
            freq,
            wall_shear_stress=args.wall_shear_stress,
            pillar_density=args.pillar_density,
            drag=args.drag_model,
            magnitude_tolerance=mtol,
            phase_tolerance=math.radians(ptol),
        )
    for note in caught:  # the response stands: its warnings, each once, as the CLI prints them
        warnings.warn_explicit(note.message, note.category, note.filename, note.lineno)
    phase = np.degrees(r.phase)
    summary = _summary(r)
    if args.json:
        print_json(
            {
                "units": {"frequency": "Hz", "magnitude": "m/Pa", "phase": "deg", **SUMMARY_UNITS},
                "frequency": r.frequency.tolist(),
                "magnitude": r.magnitude.tolist(),
                "phase": phase.tolist(),
                **summary,
            }
        )
        return 0
    if args.out is not None:
        ds = r.to_xarray()[["magnitude", "phase"]]
        ds["phase"] = ("frequency", phase, {"units": "deg", "long_name": "phase of H"})
        write_dataset_output(ds, args.out)
        return 0
    for key, value in summary.items():
        unit = SUMMARY_UNITS.get(key)
        shown = f"{value:.10g}" if isinstance(value, float) else str(value)
        print(f"# {key}{f' [{unit}]' if unit else ''} = {shown}")
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["frequency [Hz]", "magnitude [m/Pa]", "phase [deg]"])
    for row in zip(r.frequency, r.magnitude, phase):
        w.writerow([f"{v:.12g}" for v in row])
    return 0
