"""``hairbed rheometer``: the bed's storage and loss moduli under small-amplitude oscillatory
shear about a pre-stress (hairbed.rheometer.bed_moduli, issue 31 §2a); with ``--laos``
large-amplitude oscillatory shear in SI (hairbed.rheometer.bed_laos) and with ``--pipkin``
its Pipkin map (hairbed.rheometer.bed_pipkin_map, issue 31 §2b).
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

from ._grids import spec
from ._options import add_bed_options, add_command, add_json, need_bed
from ._output import NO_COMPRESS_HELP, check_dataset_output, print_json, write_dataset_output
from ._report import UsageError, say_status

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

--laos GAMMA0 gives large-amplitude oscillatory shear instead (hairbed.rheometer.bed_laos;
overdamped hairs): the bed's periodic state under the strain gamma0 sin(2 pi f t) at one
frequency, found by integrating until the transient decays. Prints, in '#' lines, the
first harmonic's G'_1, G''_1 [Pa], Ewoldt's G'_M, G'_L [Pa], eta'_M, eta'_L [Pa s], the
Chebyshev coefficients e_1, e_3, e_5 [Pa] and v_1, v_3, v_5 [Pa s], I_3/I_1, the even part
over I_1 (a tilted bed), the pre-stress and the scales; then the last period: time [s],
strain, strain rate [1/s] and stress [Pa] (the Lissajous-Bowditch curves). --out .nc or
.zarr writes the period with every harmonic, .csv or .parquet the period's table. With
--pipkin, --laos takes a SPEC of amplitudes and the command prints the Pipkin map over
--frequencies x --laos: G'_1, G''_1, I_3/I_1, the even ratio, G'_M, G'_L, eta'_M, eta'_L at
each point (--workers processes share the runs; a run takes tens of milliseconds).

examples:
  hairbed rheometer --frequencies 0.1:1000:41:log --length 1e-3 --radius 50e-6 \\
      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 250e-6 \\
      --density 1000
  hairbed rheometer --frequencies 1,10,100 --velocity 1e-3 --length 1e-3 ... --json
  hairbed rheometer --laos 30 --frequencies 0.1 --length 1e-3 ... --out laos.nc
  hairbed rheometer --laos 1,10,30 --pipkin --frequencies 0.1,1 --length 1e-3 ... --workers 2
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
    g = p.add_argument_group("large amplitude (--laos, --pipkin)")
    g.add_argument(
        "--laos",
        metavar="SPEC",
        help="large-amplitude oscillatory shear at the strain amplitude gamma0 [-] > 0 (the top "
        "wall's displacement over the channel's height) instead of the small-amplitude moduli; "
        "a SPEC of amplitudes with --pipkin",
    )
    g.add_argument(
        "--pipkin",
        action="store_true",
        help="with --laos: the Pipkin map over --frequencies x --laos",
    )
    g.add_argument(
        "--samples",
        type=int,
        default=64,
        metavar="N",
        help="samples per period of the large-amplitude run, in [16, 4096] (default 64)",
    )
    g.add_argument(
        "--workers",
        type=int,
        default=1,
        metavar="N",
        help="processes sharing the Pipkin map's runs, in [1, 64] (default 1)",
    )
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


def _cells(status: Any, message: str, what: str) -> str:
    """The worst status's message with how many of the grid's points have it."""
    s = np.asarray(status).reshape(-1)
    worst = _worst(s)
    return f"{int(np.sum(s == worst))} of {s.size} {what}: {message}"


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
    amplitudes = _amplitudes(args)
    bed = need_bed(args, "rheometer")
    to_stdout = args.out is None or check_dataset_output(args.out, args.no_compress)
    if args.json and not to_stdout:
        raise UsageError("--json and --out cannot be combined")
    if amplitudes is not None:
        if args.pipkin:
            return _run_pipkin(args, bed, freq, amplitudes, to_stdout)
        return _run_laos(args, bed, freq, amplitudes, to_stdout)
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
    return say_status(worst, _cells(status, SAOS_STATUS[worst], "frequencies"))


def _amplitudes(args: argparse.Namespace) -> Any:
    """--laos's strain amplitudes (None without it), and the options that go with it."""
    if args.laos is None:
        for given, flag in ((args.pipkin, "--pipkin"), (args.workers != 1, "--workers"),
                            (args.samples != 64, "--samples")):  # fmt: skip
            if given:
                raise UsageError(f"{flag} applies to --laos only")
        return None
    if args.hair_density is not None:
        raise UsageError("--hair-density does not apply to --laos (its hairs are overdamped)")
    g = np.asarray(spec(args.laos, "--laos"), dtype=np.float64).reshape(-1)
    bad = ~np.isfinite(g) | (g <= 0.0)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise UsageError(
            f"--laos must be strain amplitudes > 0 [-], got {float(g[i])!r} (first at index {i})"
        )
    if not 16 <= args.samples <= 4096:
        raise UsageError(f"--samples must lie in [16, 4096], got {args.samples}")
    if not 1 <= args.workers <= 64:
        raise UsageError(f"--workers must lie in [1, 64], got {args.workers}")
    return g


#: The units of the large-amplitude run's '#' summary and JSON.
LAOS_UNITS = {
    "frequency": "Hz",
    "strain_amplitude": "1",
    "velocity": "m/s",
    "pre_stress": "Pa",
    "storage": "Pa",
    "loss": "Pa",
    "minimum_modulus": "Pa",
    "large_modulus": "Pa",
    "minimum_viscosity": "Pa s",
    "large_viscosity": "Pa s",
    "elastic_chebyshev": "Pa",
    "viscous_chebyshev": "Pa s",
    "third_harmonic": "1",
    "even_ratio": "1",
    "mean_stress": "Pa",
    "periodic_error": "1",
    "time_scale": "s",
    "modulus_scale": "Pa",
    "kappa": "1",
    "eps": "1",
    "womersley": "1",
}


def _print_summary(summary: dict[str, Any], units: dict[str, str]) -> None:
    for key, value in summary.items():
        unit = units.get(key)
        if isinstance(value, list):
            shown = ", ".join(repr(float(v)) for v in value)
        else:
            shown = repr(value) if isinstance(value, float) else str(value)
        print(f"# {key} = {shown} [{unit}]" if unit else f"# {key} = {shown}")


def _run_laos(
    args: argparse.Namespace, bed: Any, freq: Any, amplitudes: Any, to_stdout: bool
) -> int:
    """``hairbed rheometer --laos GAMMA0``: the periodic state at one frequency."""
    from hairbed.rheometer import bed_laos

    if freq.size != 1 or amplitudes.size != 1:
        raise UsageError(
            "--laos gives the periodic state at one frequency and one strain amplitude, got "
            f"{freq.size} and {amplitudes.size} (use --pipkin for a map)"
        )
    r = bed_laos(bed, float(freq[0]), float(amplitudes[0]), args.velocity, samples=args.samples)
    ok = r.dimensionless.analysis is not None
    summary: dict[str, Any] = {
        "frequency": r.frequency,
        "strain_amplitude": r.strain_amplitude,
        "velocity": r.speed,
        "pre_stress": r.pre_stress,
        "storage": float(r.storage[0]) if ok else math.nan,
        "loss": float(r.loss[0]) if ok else math.nan,
        "minimum_modulus": r.minimum_modulus,
        "large_modulus": r.large_modulus,
        "minimum_viscosity": r.minimum_viscosity,
        "large_viscosity": r.large_viscosity,
        "elastic_chebyshev": r.elastic_chebyshev[:3].tolist(),
        "viscous_chebyshev": r.viscous_chebyshev[:3].tolist(),
        "third_harmonic": float(r.relative_intensity[2]) if r.harmonic.size > 2 else math.nan,
        "even_ratio": r.even_ratio,
        "mean_stress": r.mean_stress,
        "periods": r.dimensionless.periods,
        "periodic_error": r.dimensionless.periodic_error,
        "time_scale": r.time_scale,
        "modulus_scale": r.modulus_scale,
        "kappa": r.kappa,
        "eps": r.eps,
        "womersley": r.womersley,
        "status": r.status,
        "message": str(r.message),
    }
    if args.json:
        print_json(
            {
                "units": LAOS_UNITS
                | {"time": "s", "strain": "1", "strain_rate": "1/s", "stress": "Pa",
                   "relative_intensity": "1", "harmonic_storage": "Pa", "harmonic_loss": "Pa"},
                **summary,
                "elastic_chebyshev": r.elastic_chebyshev.tolist(),
                "viscous_chebyshev": r.viscous_chebyshev.tolist(),
                "harmonic": r.harmonic.tolist(),
                "relative_intensity": r.relative_intensity.tolist(),
                "harmonic_storage": r.storage.tolist(),
                "harmonic_loss": r.loss.tolist(),
                "time": r.time.tolist(),
                "strain": r.strain.tolist(),
                "strain_rate": r.strain_rate.tolist(),
                "stress": r.stress.tolist(),
            }
        )  # fmt: skip
    elif not to_stdout:
        ds = r.to_xarray()
        if str(args.out).lower().endswith((".csv", ".parquet")):  # a table: the period only
            keep = ("strain", "strain_rate", "stress", "quasi_static_stress")
            ds = ds[list(keep)].drop_vars(["harmonic", "odd_harmonic"], errors="ignore")
        write_dataset_output(ds, args.out, args.no_compress)
    else:
        _print_summary(summary, LAOS_UNITS)
        print("time [s],strain,strain rate [1/s],stress [Pa]")
        for t, g, gd, s in zip(r.time, r.strain, r.strain_rate, r.stress):
            print(f"{float(t)!r},{float(g)!r},{float(gd)!r},{float(s)!r}")
    return say_status(int(r.status), r.message)


#: The Pipkin map's columns: name -> unit.
PIPKIN_COLUMNS = {
    "storage": "Pa",
    "loss": "Pa",
    "third_harmonic": "1",
    "even_ratio": "1",
    "minimum_modulus": "Pa",
    "large_modulus": "Pa",
    "minimum_viscosity": "Pa s",
    "large_viscosity": "Pa s",
}


def _run_pipkin(
    args: argparse.Namespace, bed: Any, freq: Any, amplitudes: Any, to_stdout: bool
) -> int:
    """``hairbed rheometer --laos SPEC --pipkin``: the map over frequency and amplitude."""
    from hairbed.rheometer import LARGE_STATUS, bed_pipkin_map

    m = bed_pipkin_map(
        bed, freq, amplitudes, args.velocity, workers=args.workers, samples=args.samples
    )
    d = m.dimensionless
    worst = _worst(m.status)
    sc = {"kappa": m.kappa, "eps": m.eps, "womersley": m.womersley}
    summary: dict[str, Any] = {
        "velocity": m.speed,
        "pre_stress": m.pre_stress,
        "time_scale": m.time_scale,
        "modulus_scale": m.modulus_scale,
        **sc,
        "status": worst,
        "message": LARGE_STATUS[worst],
    }
    if args.json:
        print_json(
            {
                "units": {"frequency": "Hz", "strain_amplitude": "1"} | PIPKIN_COLUMNS
                | SUMMARY_UNITS,
                "frequency": m.frequency.tolist(),
                "strain_amplitude": m.strain_amplitude.tolist(),
                **{k: getattr(m, k).tolist() for k in PIPKIN_COLUMNS},
                "point_status": m.status.tolist(),
                **summary,
            }
        )  # fmt: skip
    elif not to_stdout:
        ds = m.to_xarray()
        for key in sc:
            ds.attrs[key] = sc[key]
        write_dataset_output(ds, args.out, args.no_compress)
    else:
        _print_summary(summary, SUMMARY_UNITS)
        head = ",".join(f"{k} [{u}]" if u != "1" else k for k, u in PIPKIN_COLUMNS.items())
        print(f"frequency [Hz],strain_amplitude,{head},status")
        for i, f in enumerate(m.frequency):
            for j, g in enumerate(m.strain_amplitude):
                row = ",".join(repr(float(getattr(m, k)[i, j])) for k in PIPKIN_COLUMNS)
                print(f"{float(f)!r},{float(g)!r},{row},{int(d.status[i, j])}")
    return say_status(worst, _cells(m.status, LARGE_STATUS[worst], "cells"))
