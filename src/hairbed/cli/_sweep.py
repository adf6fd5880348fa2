"""``hairbed sweep``: grids of omega2, eps, theta0 (or wall speeds) to a labelled file.

Everything is checked before any work: the output's format and folder, the options that do
not apply to the form of sweep asked for, the axes. Then the grid is solved here, on a dask
cluster (--scheduler) or along a quasi-static path (--quasistatic).
"""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

import hairbed

from ._grids import legacy_grid, spec
from ._options import (
    BED_OPTIONS,
    PILLAR_OPTIONS,
    add_bed_options,
    add_branch,
    add_command,
    add_eps,
    add_fluid_option,
    add_pillar_options,
    bed_from,
    pillar_keywords,
    refuse,
    refuse_model,
)
from ._output import NO_COMPRESS_HELP, check_dataset_output, write_dataset_output
from ._report import UsageError

#: ``hairbed sweep --help``: the summary line, the description and the examples.
ABOUT = """grids of omega2, eps, theta0 (or wall speed) -> netCDF, zarr, CSV, parquet

Solve on the outer-product grid of --omega2, --eps and --theta0 (or over wall speeds, given
a bed; or, with --pillar, an isolated pillar's grid of --forcing, --theta0, --gamma,
--tip-load and --height-ratio; or, with --pillar and the SI inputs of a pillar, its states
over --wall-shear-stress [Pa], the --velocity of a couette or the --pressure-gradient of a
poiseuille channel, in SI units) and write a labelled table. SPEC is a value, a comma list or
start:stop:num[:log] (negative ones too: --theta0 -1.2:1.2:25, --velocity=-1:-1e-3:4:log; a
linear range through zero holds 0 exactly), or the two-sided logarithmic range
+-start:stop:num:log (the num values of start:stop:num:log and their negatives, 2 num in
increasing order: --wall-shear-stress +-0.01:10:13:log); with --quasistatic, --omega2
START:STOP:NUM:updown (or :log:updown) is a hysteresis loop, up to STOP and back. The output
format follows the extension of --out: .nc (netCDF-4, CF attributes, compressed losslessly
unless --no-compress), .zarr, .csv (one row per grid point, units in the header; the
default, to stdout) or .parquet; files are written whole or not at all.

examples:
  hairbed sweep --omega2 0:10:101 --eps 0.5 > sweep.csv
  hairbed sweep --omega2 1e-3:1e3:100:log --eps 0:0.95:40 --theta0=-1.2:1.2:25 --out grid.nc
  hairbed sweep --omega2 1e-3:1e3:1000:log --eps 0:0.95:100 --theta0 0:1.2:100 \\
      --chunks 50 --progress --out big.zarr
  hairbed sweep --omega2 0.01:100:200:log --eps 0.5,0.9 --chunks 50 \\
      --scheduler tcp://10.0.0.5:8786 --out grid.parquet
  hairbed sweep --omega2 0.5:2:200 --eps 0.9 --theta0=-1.5 --quasistatic
  hairbed sweep --omega2 0.8:1.6:200:updown --eps 0.9 --theta0=-1.5 --quasistatic --out loop.nc
  hairbed sweep --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 --channel-height 2e-3 \\
      --viscosity 1 --spacing 400e-6 --velocity=-0.5:0.5:101 --out bed.nc
  hairbed sweep --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 --channel-height 2e-3 \\
      --viscosity 1 --spacing 400e-6 --wall-shear-stress 0:50:101 --out curve.csv
  hairbed sweep --length 1e-3 ... --spacing 400e-6 --pressure-gradient 10:1e5:50:log \\
      --velocity 0,0.01 --out pumped.nc
  hairbed sweep --length 1e-3 ... --spacing 400e-6 --velocity 0:0.5:51 --model porous \\
      --drag sparse --out porous.nc                # a porous bed (theory.md §13)
  hairbed sweep --pillar --forcing 1e-3:1e3:200:log --theta0=-0.5,0,0.5 --out pillar.nc
  hairbed sweep --pillar --forcing 0:20:101 --profile poiseuille --height-ratio 0.25,0.5,1
  hairbed sweep --pillar --length 500e-6 --radius 25e-6 --youngs-modulus 1e6 \\
      --viscosity 1e-3 --wall-shear-stress 0:10:101 --out pillar_si.csv
"""

__all__ = ["ABOUT", "add_parser", "run"]


def add_parser(sub: Any) -> None:
    """The ``sweep`` subcommand's parser."""
    p = add_command(sub, "sweep", run, ABOUT)
    p.add_argument("--omega2", metavar="SPEC", help="forcing omega^2 [-], >= 0")
    add_eps(p, type=str, metavar="SPEC")
    p.add_argument(
        "--theta0",
        metavar="SPEC",
        help="base angle [rad] (default 0; negative leans into the flow)",
    )
    p.add_argument("--velocity", metavar="SPEC", help="top wall speed v [m/s] (with a bed)")
    p.add_argument(
        "--pressure-gradient",
        metavar="SPEC",
        help="with a bed: a pump's pressure gradient G = -dp/dx [Pa/m], a dimension (the "
        "distributed-load solver; without --velocity the wall is at rest)",
    )
    p.add_argument(
        "--flow-rate",
        metavar="SPEC",
        help="with a bed: a pump's flow rate per unit width Q' [m^2/s], a dimension",
    )
    p.add_argument(
        "--wall-shear-stress",
        metavar="SPEC",
        help="wall shear stress tau [Pa] (with a bed, instead of --velocity): the calibration "
        "curve in stress, each stress at the wall speed that carries it",
    )
    add_branch(p, sign=None, n=None, root="low", root_help="state where several coexist "
               "(default low)")  # fmt: skip
    p.add_argument(
        "--quasistatic",
        action="store_true",
        help="follow the state along a 1-D --omega2 path (jumps at folds: hysteresis); "
        "--omega2 START:STOP:NUM:updown ramps up and back down (2 NUM - 1 points)",
    )
    p.add_argument(
        "--chunks", type=int, metavar="N", help="blocks of N points per dimension (dask)"
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="compute on a running dask.distributed scheduler (needs --chunks)",
    )
    p.add_argument("--progress", action="store_true", help="progress bar with ETA on stderr")
    p.add_argument(
        "--out", metavar="FILE", help="output: .nc, .zarr, .csv or .parquet (default: CSV stdout)"
    )
    p.add_argument("--no-compress", action="store_true", help=NO_COMPRESS_HELP)
    old = p.add_argument_group("the older form of a 1-D range (instead of a SPEC)")
    old.add_argument("--omega2-min", type=float, metavar="X", help="first omega^2 (default 0)")
    old.add_argument("--omega2-max", type=float, metavar="X", help="last omega^2 (default 10)")
    old.add_argument("--velocity-min", type=float, metavar="V", help="first wall speed [m/s]")
    old.add_argument("--velocity-max", type=float, metavar="V", help="last wall speed [m/s]")
    old.add_argument("--num", type=int, help="number of points (default 101)")
    old.add_argument("--log", action="store_true", help="geometric spacing")
    add_bed_options(p, velocity=False, model=True)
    g = add_pillar_options(p, spec=True)
    g.add_argument(
        "--drag-scale",
        type=float,
        metavar="C",
        help="with --pillar and its SI inputs: a factor c > 0 on both drag coefficients [-] "
        "(default 1, Gray & Hancock's)",
    )
    add_fluid_option(g)


_LEGACY_OMEGA2 = {"omega2_min": "--omega2-min", "omega2_max": "--omega2-max"}
_LEGACY_VELOCITY = {"velocity_min": "--velocity-min", "velocity_max": "--velocity-max"}
_SHAPE = {"num": "--num", "log": "--log"}
_BRANCH = {"sign": "--sign", "n": "--n"}


def _bed_axis(args: argparse.Namespace, bed: Any) -> Any:
    """The wall speeds of the sweep of a bed, its other options refused."""
    why = "does not apply to the sweep of a bed (its eps and base angle are fixed)"
    refuse(args, {"omega2": "--omega2", "eps": "--eps", "theta0": "--theta0"}, why)
    refuse(args, _LEGACY_OMEGA2, why)
    refuse(args, _BRANCH, "does not apply: a bed follows the physical branch")
    refuse(args, {"quasistatic": "--quasistatic"}, "takes an --omega2 path, not a bed")
    pumps = {"pressure_gradient": "--pressure-gradient", "flow_rate": "--flow-rate"}
    given = [flag for dest, flag in pumps.items() if getattr(args, dest) is not None]
    if len(given) > 1:
        raise UsageError(f"give at most one pump drive, got {' and '.join(given)}")
    if given:
        why = "does not apply with a pump drive"
        refuse(args, {"wall_shear_stress": "--wall-shear-stress", **_LEGACY_VELOCITY}, why)
        refuse(args, _SHAPE, why)
        return spec(args.velocity, "--velocity")
    if args.wall_shear_stress is not None:
        why = "does not apply with --wall-shear-stress (the speeds follow from the stresses)"
        refuse(args, {"velocity": "--velocity", **_LEGACY_VELOCITY, **_SHAPE}, why)
        return bed.velocity_from_wall_shear_stress(
            spec(args.wall_shear_stress, "--wall-shear-stress")
        )
    if args.velocity is not None:
        refuse(args, {**_LEGACY_VELOCITY, **_SHAPE}, "does not apply with --velocity SPEC")
        return spec(args.velocity, "--velocity")
    if args.velocity_min is not None and args.velocity_max is not None:
        return legacy_grid(args, "velocity", args.velocity_min, args.velocity_max)
    raise UsageError("a sweep of a bed needs --velocity SPEC [m/s]")


def _axes(args: argparse.Namespace) -> tuple[Any, Any, Any]:
    """(omega2, eps, theta0) of a dimensionless sweep."""
    refuse(
        args,
        {
            "velocity": "--velocity",
            "wall_shear_stress": "--wall-shear-stress",
            "pressure_gradient": "--pressure-gradient",
            "flow_rate": "--flow-rate",
            **_LEGACY_VELOCITY,
        },
        "needs the physical inputs of a bed (--length, --radius, ...)",
    )
    if args.eps is None:
        raise UsageError("give --eps SPEC (or the physical inputs of a bed)")
    if args.omega2 is not None:
        refuse(args, {**_LEGACY_OMEGA2, **_SHAPE}, "does not apply with --omega2 SPEC")
        omega2 = spec(args.omega2, "--omega2", path=args.quasistatic)
    else:  # the older form --omega2-min/--omega2-max/--num/--log, default 0:10:101
        lo = 0.0 if args.omega2_min is None else args.omega2_min
        hi = 10.0 if args.omega2_max is None else args.omega2_max
        omega2 = legacy_grid(args, "omega2", lo, hi)
    eps = spec(args.eps, "--eps")
    theta0 = spec(args.theta0, "--theta0")
    return omega2, eps, 0.0 if theta0 is None else theta0


def _check_quasistatic(args: argparse.Namespace, omega2: Any, eps: Any, theta0: Any) -> None:
    why = "does not apply with --quasistatic (a path is followed in order, in one process)"
    refuse(args, {"chunks": "--chunks", "scheduler": "--scheduler"}, why)
    refuse(args, _BRANCH, "does not apply with --quasistatic (it follows the physical branch)")
    if args.root == "mid":
        raise UsageError("--root mid does not apply with --quasistatic (low or high)")
    if np.ndim(omega2) != 1 or np.ndim(eps) != 0 or np.ndim(theta0) != 0:
        raise UsageError(
            "--quasistatic follows a 1-D path: --omega2 a list or range, --eps and "
            "--theta0 single values"
        )
    if args.progress:
        raise UsageError("--progress does not apply with --quasistatic (one pass)")


def _quasistatic(omega2: Any, eps: Any, theta0: Any, root: str) -> Any:
    """The dataset of a quasi-static path: the states followed, the ramp's direction, its
    jumps at folds and the stability of the states followed."""
    from hairbed import sweeps
    from hairbed.quasistatic import sweep_with_jumps

    run = sweep_with_jumps(omega2, eps, theta0, root=root)
    ds = sweeps.path_dataset(run.solution, kind="quasistatic", root=root, omega2=omega2)
    marks = {
        "direction": (
            run.direction,
            "ramp direction (+1 omega2 rising, -1 falling, 0 first point or unchanged)",
        ),
        "jump": (
            run.jumped.astype(np.int8),
            "1 where the state jumped at a fold since the previous point",
        ),
        "stable": (run.stable.astype(np.int8), "1 where the state followed is linearly stable"),
    }
    for name, (values, long_name) in marks.items():
        ds[name] = ("step", values, {"units": "1", "long_name": long_name})
    return ds


#: What a pillar's sweep does not take: dest -> flag.
_HAIR_OPTIONS = {
    "omega2": "--omega2",
    "eps": "--eps",
    "velocity": "--velocity",
    "pressure_gradient": "--pressure-gradient",
    "flow_rate": "--flow-rate",
    "wall_shear_stress": "--wall-shear-stress",
    "quasistatic": "--quasistatic",
    **_BRANCH,
    **_LEGACY_OMEGA2,
    **_LEGACY_VELOCITY,
    **_SHAPE,
    **{kw: flag for flag, (kw, _) in BED_OPTIONS.items()},
}


#: The drives of an SI pillar's sweep: dest -> (flag, the Pillar.deform keyword).
_SI_PILLAR_DRIVES = {
    "wall_shear_stress": "--wall-shear-stress",
    "velocity": "--velocity",
    "pressure_gradient": "--pressure-gradient",
}
#: The SI variables of a pillar's sweep: PillarDeformation field -> (units, long_name).
_SI_PILLAR_VARIABLES = {
    "wall_shear_stress": ("Pa", "wall shear stress tau_w"),
    "velocity": ("m s-1", "wall speed V = tau_w H / eta of the Couette channel"),
    "pressure_gradient": ("Pa m-1", "pressure gradient G = 2 tau_w / H of the Poiseuille channel"),
    "forcing": ("1", "pillar forcing Lambda = zeta_perp tau_w L^4 / (eta E I)"),
    "tip_deflection": ("m", "tip position x1 L relative to the base, along +x"),
    "tip_displacement": ("m", "tip displacement from rest (x1 - sin theta0) L"),
    "tip_height": ("m", "tip height h1 L above the wall"),
    "tip_angle": ("rad", "tip angle theta1 from the wall normal"),
    "base_moment": ("N m", "bending moment at the base E I theta'(0) / L"),
    "drag": ("N", "streamwise drag on the whole pillar"),
    "drag_wall_normal": ("N", "wall-normal drag on the whole pillar"),
    "sensitivity": ("m Pa-1", "d(tip deflection)/d(tau_w), exact"),
    "reynolds_number": ("1", "pillar Reynolds number rho |u(tip)| 2a / eta"),
    "height_in_wall_units": ("1", "pillar length in wall units L+ = L sqrt(|tau_w|/rho) / nu"),
    "status": ("1", "solver status: 0 converged, 3 inaccurate, negative failed"),
}


def _si_pillar_sweep(args: argparse.Namespace) -> Any:
    """``sweep --pillar`` with the SI inputs of a pillar: its states over one drive (wall
    shear stress, or a channel's wall speed or pressure gradient) as a labelled Dataset of
    :meth:`hairbed.Pillar.deform`'s SI fields, the dimensionless ones as ``scaled_*``."""
    from hairbed._optional import optional_import
    from hairbed._variables import PILLAR, cf_attrs

    from ._options import sensor_pillar_from

    xr = optional_import("xarray", "sweep", "sweep")
    why = "does not apply to the sweep of an SI pillar (one axis: its drive)"
    refuse(args, {"chunks": "--chunks", "scheduler": "--scheduler", "progress": "--progress"},
           why)  # fmt: skip
    refuse(args, {"omega2": "--omega2", "eps": "--eps", "quasistatic": "--quasistatic",
                  "flow_rate": "--flow-rate", "theta0": "--theta0", **_BRANCH,
                  **_LEGACY_OMEGA2, **_LEGACY_VELOCITY, **_SHAPE}, why)  # fmt: skip
    if args.root != "low":
        raise UsageError("--root does not apply with --pillar (one state per drive)")
    pillar = sensor_pillar_from(args, "sweep")
    given = [dest for dest in _SI_PILLAR_DRIVES if getattr(args, dest) is not None]
    if len(given) != 1:
        got = f", got {' and '.join(_SI_PILLAR_DRIVES[d] for d in given)}" if given else ""
        raise UsageError(
            "a sweep of an SI pillar needs one of --wall-shear-stress SPEC [Pa], --velocity "
            f"SPEC [m/s] (couette) and --pressure-gradient SPEC [Pa/m] (poiseuille){got}"
        )
    drive = given[0]
    values = np.atleast_1d(spec(getattr(args, drive), _SI_PILLAR_DRIVES[drive]))
    d = pillar.deform(**{drive: values})
    dims = (drive,)
    data: dict[str, Any] = {}
    for name, (units, long_name) in _SI_PILLAR_VARIABLES.items():
        if name == drive:
            continue
        value = np.asarray(getattr(d, name))
        if name in (
            "velocity",
            "pressure_gradient",
            "reynolds_number",
            "height_in_wall_units",
        ) and np.all(np.isnan(value)):
            continue  # the channel has no such drive, or no density: not a column of NaN
        data[name] = (dims, value, {"units": units, "long_name": long_name})
    st = d.solution
    for name in ("tip_deflection", "tip_height", "base_curvature", "drag_x", "drag_z",
                 "tip_deflection_slope", "error_estimate", "residual", "nit", "num"):  # fmt: skip
        key = name if name not in ("tip_deflection", "tip_height") else f"scaled_{name}"
        data[key] = (dims, np.asarray(getattr(st, name)), cf_attrs(PILLAR[name]))
    units, long_name = _SI_PILLAR_VARIABLES[drive]
    coords = {drive: (dims, values, {"units": units, "long_name": long_name})}
    attrs = {
        "title": "hairbed sweep: an isolated pillar in SI units (hairbed.Pillar.deform)",
        "Conventions": "CF-1.8",
        "source": f"hairbed {hairbed.__version__} (hairbed.Pillar.deform)",
        "references": "arXiv:2203.04169",
        "hairbed_version": hairbed.__version__,
        **{
            k: (v if isinstance(v, str) else float(v))
            for k in (
                "length",
                "radius",
                "youngs_modulus",
                "viscosity",
                "base_angle",
                "profile",
                "channel_height",
                "density",
                "drag_scale",
                "fluid",
            )  # fmt: skip
            if (v := getattr(pillar, k)) is not None
        },
        "gamma": float(pillar.drag_ratio),
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _pillar_inputs(args: argparse.Namespace) -> dict[str, Any]:
    """The keywords of a pillar's sweep (hairbed.sweep with forcing=), its axes parsed."""
    refuse(args, _HAIR_OPTIONS, "does not apply with --pillar")
    if args.root != "low":
        raise UsageError("--root does not apply with --pillar (one state per forcing)")
    if args.forcing is None:
        raise UsageError("a pillar's sweep needs --forcing SPEC")
    theta0 = spec(args.theta0, "--theta0")
    kw = {"forcing": spec(args.forcing, "--forcing"), "theta0": 0.0 if theta0 is None else theta0}
    return {**kw, **pillar_keywords(args, spec)}


def run(args: argparse.Namespace) -> int:
    """Check everything, solve the grid (or path) and write it."""

    from ._distributed import compute_on

    check_dataset_output(args.out, args.no_compress)
    if args.chunks is not None and args.chunks < 1:
        raise UsageError(f"--chunks must be >= 1, got {args.chunks}")
    if args.scheduler is not None and args.chunks is None:
        raise UsageError("--scheduler needs --chunks N (the blocks that the workers solve)")
    pillar: dict[str, Any] = {}
    if args.pillar:
        refuse_model(args, "applies to a bed of hairs, not --pillar")
    if args.pillar and any(getattr(args, kw) is not None for kw, _ in BED_OPTIONS.values()):
        write_dataset_output(_si_pillar_sweep(args), args.out, args.no_compress)
        return 0
    if args.pillar:
        refuse(
            args,
            {"drag_scale": "--drag-scale", "fluid": "--fluid"},
            "needs the SI inputs of a pillar",
        )
        pillar = _pillar_inputs(args)
    else:
        refuse(args, {**PILLAR_OPTIONS, "drag_scale": "--drag-scale", "fluid": "--fluid"},
               "needs --pillar (an isolated pillar)")  # fmt: skip
    bed = None if args.pillar else bed_from(args)
    if pillar:
        pass  # every input is in ``pillar``
    elif bed is not None:
        velocity = _bed_axis(args, bed)
        kwargs: dict[str, Any] = {"root": args.root}
        for dest, flag in (
            ("pressure_gradient", "--pressure-gradient"),
            ("flow_rate", "--flow-rate"),
        ):
            if getattr(args, dest) is not None:
                kwargs[dest] = spec(getattr(args, dest), flag)
    else:
        omega2, eps, theta0 = _axes(args)
        sign = 1 if args.sign is None else args.sign
        kwargs = {"sign": sign, "n": 0 if args.n is None else args.n, "root": args.root}
        if args.quasistatic:
            _check_quasistatic(args, omega2, eps, theta0)

    def build(chunks: int | None, progress: bool) -> Any:
        if pillar:
            return hairbed.sweep(chunks=chunks, progress=progress, **pillar)
        if bed is not None:
            return bed.sweep(velocity, chunks=chunks, progress=progress, **kwargs)
        return hairbed.sweep(omega2, eps, theta0, chunks=chunks, progress=progress, **kwargs)

    if args.quasistatic:
        ds = _quasistatic(omega2, eps, theta0, args.root)
    elif args.scheduler is not None:
        ds = compute_on(args.scheduler, build, args.chunks, args.progress)
    else:
        ds = build(args.chunks, args.progress)
    write_dataset_output(ds, args.out, args.no_compress)
    return 0
