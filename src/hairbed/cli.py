"""The ``hairbed`` command line: a thin layer over the library.

Subcommands: ``solve``, ``sweep``, ``invert``, ``bistability``, ``calibrate``, ``measure``,
``figures``, ``bench``, ``demo``, ``explore``. Run ``hairbed <command> --help`` for the options
and examples of each. Bad input ends with one line ``hairbed: error: <message>`` on stderr and
exit status 2; a file that cannot be written with ``hairbed: cannot write PATH: <reason>`` and
a missing optional dependency with ``hairbed: <command> needs <module>: pip install
'hairbed[<extra>]'``, both exit status 1; Ctrl-C with the one line ``hairbed: interrupted`` and
exit status 130, leaving no partial file behind; a warning (of the library, such as a flow
outside the model's validity, or of numpy) is the one line ``hairbed: warning: <message>`` on
stderr. Negative numbers parse as values everywhere, in exponent form too (``--theta0 -1e-1``).

Examples
--------
>>> main(["solve", "--omega2", "2", "--eps", "0.5", "--json"])  # doctest: +ELLIPSIS
{"omega2": 2.0, "eps": 0.5, "theta0": 0.0, "sign": 1, "n": 0, "xi": 0.84725391654124...
0
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import signal
import sys
import time
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

import hairbed

__all__ = ["main", "run_and_exit"]

PROG = "hairbed"

#: Fields of a Solution with a short description and unit, for the readable table.
FIELDS: dict[str, str] = {
    "omega2": "forcing omega^2 [-]",
    "eps": "confinement eps = L/H [-]",
    "theta0": "base angle [rad]",
    "sign": "sign of the base curvature",
    "n": "interior turning points",
    "xi": "xi = E/omega_eps^2 = sin(theta1) [-]",
    "omega_eps": "effective frequency omega_eps [-]",
    "energy": "Hamiltonian E [-]",
    "tip_height": "tip height h1 [L]",
    "tip_deflection": "tip deflection x1 [L]",
    "tip_angle": "tip angle theta1 [rad]",
    "base_curvature": "base curvature theta'(0) [1/L]",
    "n_roots": "states on this branch",
    "physical": "physical branch",
}

#: Physical inputs of a bed: option name -> (HairBed keyword, help text).
BED_OPTIONS: dict[str, tuple[str, str]] = {
    "--length": ("length", "hair length L [m]"),
    "--radius": ("radius", "hair radius a [m]"),
    "--youngs-modulus": ("youngs_modulus", "Young's modulus E [Pa]"),
    "--channel-height": ("channel_height", "channel height H [m]"),
    "--viscosity": ("viscosity", "dynamic viscosity eta [Pa s]"),
    "--spacing": ("spacing", "hexagonal hair spacing delta [m] (or --packing-fraction)"),
    "--packing-fraction": ("packing_fraction", "packing fraction phi [-] (or --spacing)"),
    "--base-angle": (
        "base_angle",
        "base angle theta0 [rad] (default 0; negative leans into a flow towards +x)",
    ),
    "--density": ("density", "fluid density rho [kg/m^3] (optional: checks Re < 1)"),
}
_BED_REQUIRED = ("length", "radius", "youngs_modulus", "channel_height", "viscosity")


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class CommandError(Exception):
    """The command cannot run here (a file not writable, an extra not installed): reported as
    the one line ``hairbed: <message>``, exit status 1."""


class WriteError(CommandError):
    """``path`` cannot be written: ``hairbed: cannot write PATH: <reason>``."""

    def __init__(self, path: Any, reason: Any) -> None:
        if isinstance(reason, OSError):
            reason = reason.strerror or str(reason)
        super().__init__(f"cannot write {path}: {reason}")


#: Optional module (top-level name) -> the extra of pyproject.toml that installs it.
EXTRAS: dict[str, str] = {
    "matplotlib": "plot",
    "xarray": "sweep",
    "dask": "sweep",
    "distributed": "sweep",
    "netCDF4": "sweep",
    "zarr": "sweep",
    "pyarrow": "sweep",
    "tqdm": "sweep",
    "panel": "app",
    "bokeh": "app",
    "param": "app",
}


def _need(module: str, what: str) -> None:
    """Import ``module`` (an optional dependency) or raise the CommandError naming its extra."""
    import importlib

    try:
        importlib.import_module(module)
    except ImportError:
        verb = "need" if what.endswith("s") else "needs"
        extra = EXTRAS[module.split(".")[0]]
        raise CommandError(f"{what} {verb} {module}: pip install 'hairbed[{extra}]'") from None


#: A negative number as a value, not an option: -1, -.5, -1e-1, -1.2:1.2:25, -inf, -nan
#: (argparse's own pattern, ``^-\d+$|^-\d*\.\d+$``, takes ``-1e-1`` for an option).
NEGATIVE_NUMBER = re.compile(r"^-(?:\.?\d|inf(?:inity)?$|nan$)", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """argparse, but errors are one line on stderr (no usage block) and every negative number
    (exponent form, SPEC, -inf) is a value."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message: str) -> None:  # type: ignore[override]
        raise UsageError(message)


def _formatter(prog: str) -> argparse.HelpFormatter:
    return argparse.RawDescriptionHelpFormatter(prog, max_help_position=32)


# -- output helpers -------------------------------------------------------------------------


def _jsonable(value: Any) -> Any:
    """Python scalars/lists for json; NaN and infinities become null (strict JSON)."""
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _fmt(value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, float):
        return f"{value:.15g}"
    return str(value)


def _table(rows: dict[str, Any], notes: dict[str, str] | None = None) -> str:
    notes = notes or {}
    width = max(len(k) for k in rows)
    vwidth = max(len(_fmt(v)) for v in rows.values())
    lines = []
    for key, value in rows.items():
        note = notes.get(key, "")
        lines.append(f"  {key:<{width}}  {_fmt(value):>{vwidth}}  {note}".rstrip())
    return "\n".join(lines)


def _solution_table(sol: Any) -> str:
    return _table(sol.as_dict(), FIELDS)


def _check_output(path: str, *, directory: bool = False, parents: bool = False) -> None:
    """Refuse, before any work, an output ``path`` that cannot be written (a WriteError).

    With ``parents`` the missing directories of ``path`` will be created: the nearest one
    that exists is checked instead.
    """
    import os
    import tempfile
    from pathlib import Path

    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if parents:
        while not parent.exists() and parent != parent.parent:
            parent, target = parent.parent, parent
    if not parent.exists():
        raise WriteError(path, f"directory {str(parent)!r} does not exist")
    if not parent.is_dir():
        raise WriteError(path, f"{str(parent)!r} is not a directory")
    if target.is_dir() and not directory:
        raise WriteError(path, "it is a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise WriteError(path, f"permission denied in {str(parent)!r}")
    try:  # what access() cannot tell (a read-only or special file system, root's rights)
        with tempfile.TemporaryFile(dir=parent, prefix=f".{target.name}.probe"):
            pass
    except OSError as exc:
        raise WriteError(path, exc) from None


def _figure_format(path: str, option: str) -> str:
    """The image format of ``path`` from its extension (PNG without one), checked."""
    from pathlib import Path

    from matplotlib.backend_bases import FigureCanvasBase

    fmt = Path(path).suffix.lstrip(".").lower() or "png"
    known = FigureCanvasBase.get_supported_filetypes()
    if fmt not in known:
        raise UsageError(
            f"{option} {path}: unknown image format {fmt!r}; use one of .{', .'.join(known)}"
        )
    return fmt


def _save_figure(fig: Any, path: str, fmt: str) -> None:
    """Save a matplotlib figure whole or not at all."""
    from hairbed.safe_files import atomic_path

    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=150, format=fmt)
    except OSError as exc:
        raise WriteError(path, exc) from None


# -- shared option groups -------------------------------------------------------------------


def _add_bed_options(p: argparse.ArgumentParser, velocity: bool = True) -> None:
    g = p.add_argument_group("physical inputs (SI units; replace --omega2/--eps)")
    for opt, (_, text) in BED_OPTIONS.items():
        g.add_argument(opt, type=float, metavar="X", help=text)
    if velocity:
        g.add_argument("--velocity", type=float, metavar="V", help="top wall speed v [m/s]")


def _bed(args: argparse.Namespace) -> Any | None:
    """The HairBed of the physical options, or None when none is given."""
    given = {kw: getattr(args, kw) for kw, _ in BED_OPTIONS.values()}
    given = {k: v for k, v in given.items() if v is not None}
    if not given:
        return None
    missing = [k for k in _BED_REQUIRED if k not in given]
    if missing:
        names = ", ".join("--" + k.replace("_", "-") for k in missing)
        raise UsageError(f"physical inputs need also {names}")
    return hairbed.HairBed(**given)


# -- subcommands ----------------------------------------------------------------------------


def _cmd_solve(args: argparse.Namespace) -> int:
    fmt = ""
    if args.plot:  # checked before any work
        _need("matplotlib", "solve --plot")
        fmt = _figure_format(args.plot, "--plot")
        _check_output(args.plot)
    bed = _bed(args)
    if bed is not None:
        if args.omega2 is not None or args.eps is not None or args.theta0 is not None:
            raise UsageError(
                "give either --omega2/--eps/--theta0 or the physical inputs, not both"
            )
        if args.velocity is None:
            raise UsageError("physical inputs need --velocity [m/s]")
        state = bed.deform(args.velocity, root=args.root or "low")
        si = {
            "velocity": state.velocity,
            "omega2": state.omega2,
            "eps": bed.eps,
            "tip_deflection_m": state.tip_deflection,
            "tip_height_m": state.tip_height,
            "tip_angle": state.tip_angle,
            "wall_shear_stress_Pa": state.wall_shear_stress,
            "force_per_hair_N": state.force_per_hair,
            "stress_ratio": state.stress_ratio,
            "tip_displacement_m": state.tip_displacement,
        }
        if bed.density is not None:
            si["reynolds_number"] = state.reynolds_number
        sols = [state.solution]
        if args.json:
            print(json.dumps(_jsonable({**si, "solution": state.solution.as_dict()})))
        else:
            print(f"Hair bed {bed!r}")
            print(_table(si, {"velocity": "[m/s]", "tip_angle": "[rad]"}))
            print("dimensionless state:")
            print(_solution_table(state.solution))
    else:
        if args.omega2 is None or args.eps is None:
            raise UsageError("give --omega2 and --eps (or the physical inputs with --velocity)")
        theta0 = 0.0 if args.theta0 is None else args.theta0
        if args.all_branches:
            hairbed.solve(args.omega2, args.eps, theta0)  # validates the inputs
            sols = hairbed.solve_all(args.omega2, args.eps, theta0)
            head = (
                f"{len(sols)} state(s) at omega2={args.omega2:g}, eps={args.eps:g}, "
                f"theta0={theta0:g}:"
            )
            _print_states(_labelled(sols), args.json, head)
        else:
            s = hairbed.solve(
                args.omega2, args.eps, theta0, sign=args.sign, n=args.n, root=args.root or "low"
            )
            sols = [s]
            if args.root is None and s.success and s.n_roots > 1:
                # inside a window: every state of the branch, labelled, with its stability
                roots = ("low", "mid", "high") if s.n_roots == 3 else ("low", "high")
                sols = [
                    hairbed.solve(args.omega2, args.eps, theta0, sign=args.sign, n=args.n, root=r)
                    for r in roots
                ]
                head = (
                    f"{len(sols)} states on branch sign={args.sign:+d}, n={args.n} at "
                    f"omega2={args.omega2:g}, eps={args.eps:g}, theta0={theta0:g} "
                    "(a bistable window; --root selects one):"
                )
                _print_states(_labelled(sols), args.json, head)
            elif args.json:
                print(json.dumps(_jsonable(s.as_dict())))
            else:
                print(_solution_table(s))
    if args.plot:
        from hairbed.plotting import fig_states

        _save_figure(fig_states(sols), args.plot, fmt)
        what = f"{len(sols)} profile{'s' if len(sols) > 1 else ''}"
        print(f"wrote {args.plot} ({fmt.upper()}, {what})", file=sys.stderr)
    return 0


def _progress_bar(total: int) -> Any:
    """A tqdm bar on stderr, shown once the work has run a second (with an ETA)."""
    from tqdm import tqdm

    from hairbed.sweeps import PROGRESS_DELAY

    return tqdm(
        total=total, unit="task", delay=PROGRESS_DELAY, file=sys.stderr, desc="hairbed sweep"
    )


def _spec(text: str | None, option: str) -> Any:
    """A SPEC of the sweep: a value, a comma list, or start:stop:num[:log] (or :lin)."""
    if text is None:
        return None
    form = "a number, a comma list or start:stop:num[:log]"
    parts = text.split(":")
    try:
        if len(parts) == 1:
            items = [p for p in text.split(",")]
            if len(items) == 1:
                return float(items[0])
            return np.array([float(p) for p in items])
        if len(parts) not in (3, 4):
            raise ValueError
        start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
        spacing = parts[3].strip().lower() if len(parts) == 4 else "lin"
    except ValueError:
        raise UsageError(f"{option} must be {form}, got {text!r}") from None
    if spacing not in ("lin", "log"):
        raise UsageError(f"{option}: the fourth field of start:stop:num:log is 'log' or 'lin'")
    if num < 1:
        raise UsageError(f"{option}: num in start:stop:num must be >= 1, got {num}")
    if spacing == "log":
        if start <= 0 or stop <= 0:
            raise UsageError(f"{option}: a log range needs positive bounds, got {text!r}")
        return np.geomspace(start, stop, num)
    return np.linspace(start, stop, num)


def _legacy_grid(args: argparse.Namespace, name: str, lo: float | None, hi: float | None) -> Any:
    """--<name>-min/--<name>-max/--num/--log (the older form of a 1-D SPEC)."""
    num = 101 if args.num is None else args.num
    if num < 1:
        raise UsageError(f"--num must be >= 1, got {num}")
    if args.log:
        if lo is None or hi is None or lo <= 0 or hi <= 0:
            raise UsageError(f"--log needs positive --{name}-min and --{name}-max")
        return np.geomspace(lo, hi, num)
    if lo is None or hi is None:
        raise UsageError(f"give --{name}-min and --{name}-max")
    return np.linspace(lo, hi, num)


def _refuse(args: argparse.Namespace, options: dict[str, str], why: str) -> None:
    """UsageError naming the first of ``options`` (dest -> flag) that was given."""
    for dest, flag in options.items():
        value = getattr(args, dest)
        if value is not None and value is not False:
            raise UsageError(f"{flag} {why}")


def _cmd_sweep(args: argparse.Namespace) -> int:
    from hairbed import sweeps

    # -- everything is checked before any work ------------------------------------------------
    out = args.out
    to_stdout = out is None or out == "-"
    if not to_stdout:
        kind = sweeps.output_format(out)  # an unknown extension is refused here
        _check_output(out, directory=kind == "zarr")
    if args.chunks is not None and args.chunks < 1:
        raise UsageError(f"--chunks must be >= 1, got {args.chunks}")
    if args.scheduler is not None and args.chunks is None:
        raise UsageError("--scheduler needs --chunks N (the blocks that the workers solve)")
    legacy_w = {"omega2_min": "--omega2-min", "omega2_max": "--omega2-max"}
    legacy_v = {"velocity_min": "--velocity-min", "velocity_max": "--velocity-max"}
    shape = {"num": "--num", "log": "--log"}
    omega2: Any = None
    eps: Any = None
    theta0: Any = None
    velocity: Any = None
    bed = _bed(args)
    if bed is not None:
        why = "does not apply to the sweep of a bed (its eps and base angle are fixed)"
        _refuse(args, {"omega2": "--omega2", "eps": "--eps", "theta0": "--theta0"}, why)
        _refuse(args, legacy_w, why)
        _refuse(args, {"sign": "--sign", "n": "--n"}, "does not apply: a bed follows the "
                "physical branch")  # fmt: skip
        _refuse(args, {"quasistatic": "--quasistatic"}, "takes an --omega2 path, not a bed")
        if args.velocity is not None:
            _refuse(args, {**legacy_v, **shape}, "does not apply with --velocity SPEC")
            velocity = _spec(args.velocity, "--velocity")
        elif args.velocity_min is not None and args.velocity_max is not None:
            velocity = _legacy_grid(args, "velocity", args.velocity_min, args.velocity_max)
        else:
            raise UsageError("a sweep of a bed needs --velocity SPEC [m/s]")
        kwargs: dict[str, Any] = {"root": args.root}
    else:
        why = "needs the physical inputs of a bed (--length, --radius, ...)"
        _refuse(args, {"velocity": "--velocity", **legacy_v}, why)
        if args.eps is None:
            raise UsageError("give --eps SPEC (or the physical inputs of a bed)")
        if args.omega2 is not None:
            _refuse(args, {**legacy_w, **shape}, "does not apply with --omega2 SPEC")
            omega2 = _spec(args.omega2, "--omega2")
        else:  # the older form --omega2-min/--omega2-max/--num/--log, default 0:10:101
            lo = 0.0 if args.omega2_min is None else args.omega2_min
            hi = 10.0 if args.omega2_max is None else args.omega2_max
            omega2 = _legacy_grid(args, "omega2", lo, hi)
        eps = _spec(args.eps, "--eps")
        theta0 = _spec(args.theta0, "--theta0")
        theta0 = 0.0 if theta0 is None else theta0
        sign = 1 if args.sign is None else args.sign
        n = 0 if args.n is None else args.n
        kwargs = {"sign": sign, "n": n, "root": args.root}
    if args.quasistatic:
        why = "does not apply with --quasistatic (a path is followed in order, in one process)"
        _refuse(args, {"chunks": "--chunks", "scheduler": "--scheduler"}, why)
        _refuse(args, {"sign": "--sign", "n": "--n"}, "does not apply with --quasistatic "
                "(it follows the physical branch)")  # fmt: skip
        if args.root == "mid":
            raise UsageError("--root mid does not apply with --quasistatic (low or high)")
        if np.ndim(omega2) != 1 or np.ndim(eps) != 0 or np.ndim(theta0) != 0:
            raise UsageError(
                "--quasistatic follows a 1-D path: --omega2 a list or range, --eps and "
                "--theta0 single values"
            )
        if args.progress:
            raise UsageError("--progress does not apply with --quasistatic (one pass)")

    # -- the work ------------------------------------------------------------------------------
    def build(chunks: int | None, progress: bool) -> Any:
        if bed is not None:
            return bed.sweep(velocity, chunks=chunks, progress=progress, **kwargs)
        return hairbed.sweep(omega2, eps, theta0, chunks=chunks, progress=progress, **kwargs)

    if args.quasistatic:
        from hairbed.quasistatic import sweep_with_jumps

        run = sweep_with_jumps(omega2, eps, theta0, start=args.root)
        ds = sweeps.path_dataset(run.solution, kind="quasistatic", root=args.root, omega2=omega2)
        # the ramp's direction, its jumps at folds and the stability of the states followed
        ds["direction"] = (
            "step",
            run.direction,
            {
                "units": "1",
                "long_name": "ramp direction "
                "(+1 omega2 rising, -1 falling, 0 first point or unchanged)",
            },
        )
        ds["jump"] = (
            "step",
            run.jumped.astype(np.int8),
            {
                "units": "1",
                "long_name": "1 where the state jumped at a fold since the previous point",
            },
        )
        ds["stable"] = ("step", run.stable.astype(np.int8), {"units": "1", "long_name": "1 "
                        "where the state followed is linearly stable"})  # fmt: skip
    elif args.scheduler is not None:
        ds = _distributed(args.scheduler, build, args.chunks, args.progress)
    else:
        ds = build(args.chunks, args.progress)
    if to_stdout:
        sweeps.write_csv_stream(ds, sys.stdout)
        sys.stdout.flush()
        return 0
    try:
        points = sweeps.write_dataset(ds, out)
    except OSError as exc:
        raise WriteError(out, exc) from None
    print(f"wrote {out} ({points} points)", file=sys.stderr)
    return 0


def _distributed(address: str, build: Any, chunks: int, progress: bool) -> Any:
    """The sweep computed on the dask.distributed cluster at ``address``, gathered here."""
    try:
        import distributed
    except ImportError as exc:
        raise UsageError("--scheduler needs distributed: pip install 'hairbed[sweep]'") from exc
    try:
        client = distributed.Client(address, timeout="10s", set_as_default=True)
    except (OSError, TimeoutError, ValueError) as exc:
        message = " ".join(str(exc).split())
        raise UsageError(
            f"--scheduler: could not connect to a dask scheduler at {address!r} ({message})"
        ) from exc
    with client:
        try:
            # the workers' stderr is not ours: the bar follows the blocks' futures from here
            persisted = build(chunks, False).persist()
            futures = distributed.futures_of(persisted)
            if progress:
                with _progress_bar(len(futures)) as bar:
                    for _ in distributed.as_completed(futures):
                        bar.update(1)
            return persisted.compute()
        except distributed.KilledWorker as exc:  # lost tasks are retried; this one no more
            first = " ".join(str(exc).split()).split(". ")[0]
            raise CommandError(
                f"sweep: workers of the dask scheduler at {address} died while computing it, "
                f"nothing written ({first})"
            ) from None


def _cmd_invert(args: argparse.Namespace) -> int:
    sigma = args.sigma
    if sigma is not None and not (math.isfinite(sigma) and sigma >= 0.0):
        raise UsageError(f"--sigma must be finite and >= 0, got {sigma:g}")
    bed = _bed(args)
    if bed is not None:
        if args.eps is not None or args.theta0 is not None:
            raise UsageError("give either --eps/--theta0 or the physical inputs, not both")
        st = bed.state_from_tip_deflection(args.tip_deflection)
        out = {
            "tip_deflection_m": args.tip_deflection,
            "velocity": st.velocity,
            "omega2": st.omega2,
            "wall_shear_stress_Pa": st.wall_shear_stress,
            "force_per_hair_N": st.force_per_hair,
            "tip_height_m": st.tip_height,
        }
        notes = {"velocity": "[m/s]", "omega2": "[-]"}
        if sigma is not None:
            # first order through the exact slope of the calibration curve
            from hairbed import calibration

            m = calibration.measure(bed, args.tip_deflection, sigma=sigma)
            out["sigma_m"] = sigma
            out["velocity_stderr"] = m.velocity_stderr
            out["omega2_stderr"] = m.velocity_stderr / bed.velocity_scale
            out["wall_shear_stress_stderr_Pa"] = m.wall_shear_stress_stderr
            notes["velocity_stderr"] = "[m/s], from --sigma"
        if args.json:
            print(json.dumps(_jsonable(out)))
        else:
            print(_table(out, notes))
        return 0
    if args.eps is None:
        raise UsageError("give --eps (or the physical inputs of a bed)")
    theta0 = 0.0 if args.theta0 is None else args.theta0
    sol = hairbed.inverse.solution_from_tip_deflection(args.tip_deflection, args.eps, theta0)
    stderr = None
    if sigma is not None:
        # first order: sigma / |d x1/d omega2|, the exact derivative (hairbed.derivatives)
        slope = float(hairbed.sensitivity.derivatives_at(sol)["tip_deflection"]["omega2"])
        stderr = sigma / abs(slope) if slope != 0.0 else math.inf
    if args.json:
        out = sol.as_dict()
        if stderr is not None:
            out = {**out, "sigma": sigma, "omega2_stderr": stderr}
        print(json.dumps(_jsonable(out)))
    else:
        if stderr is None:
            print(f"omega2 = {float(sol.omega2):.15g}")
        else:
            print(f"omega2 = {float(sol.omega2):.15g} +- {stderr:.3g} (from --sigma {sigma:g})")
        print(_solution_table(sol))
    return 0


def _cmd_figures(args: argparse.Namespace) -> int:
    from pathlib import Path

    _need("matplotlib", "figures")
    from hairbed.plotting import make_all, parse_settings

    if args.dpi < 1:
        raise UsageError(f"--dpi must be >= 1, got {args.dpi}")
    settings = parse_settings(args.set or [], args.only)  # names and values, before any work
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise WriteError(args.out, "it exists and is not a directory")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise WriteError(args.out, exc) from None
    _check_output(str(out / "figure.png"))
    start = time.perf_counter()
    try:
        paths = make_all(
            args.out, dpi=args.dpi, only=args.only, verbose=not args.quiet, settings=settings
        )
    except OSError as exc:
        raise WriteError(exc.filename or args.out, exc) from None
    print(f"{len(paths)} figures in {args.out}/ ({time.perf_counter() - start:.1f} s)")
    return 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from pathlib import Path

    from hairbed import _benchmark

    if args.n is not None and args.n < 2:
        raise UsageError(f"--n must be >= 2, got {args.n}")
    if args.repeat < 1:
        raise UsageError(f"--repeat must be >= 1, got {args.repeat}")
    if args.seed < 0:
        raise UsageError(f"--seed must be >= 0, got {args.seed}")
    out = None if args.json is None else Path(args.json)
    if out is not None:
        _check_output(args.json, parents=True)  # missing folders are created

    def progress(message: str) -> None:
        print(f"{PROG} bench: {message}", file=sys.stderr, flush=True)

    result = _benchmark.measure(
        not args.full,
        args.rows,
        progress if args.progress else None,
        repeat=args.repeat,
        seed=args.seed,
        cold=True if args.cold else None,
        n=args.n,
    )
    print(_benchmark.format_report(result), flush=True)
    if out is not None:
        try:
            _benchmark.write_json(result, out)
        except OSError as exc:
            raise WriteError(out, exc) from None
    return 0


def _cmd_explore(args: argparse.Namespace) -> int:
    from hairbed.explorer import AppMissingError, serve

    if not 0 <= args.port <= 65535:
        raise UsageError(f"--port must be in [0, 65535], got {args.port}")
    for flag in ("session_token_expiration", "check_unused_sessions", "unused_session_lifetime"):
        if getattr(args, flag) < 1:
            option = "--" + flag.replace("_", "-")
            raise UsageError(f"{option} must be >= 1, got {getattr(args, flag)}")
    try:
        serve(
            port=args.port,
            host=args.host,
            show=not args.no_browser,
            allow_websocket_origin=args.allow_websocket_origin or (),
            session_token_expiration=args.session_token_expiration,
            check_unused_sessions=args.check_unused_sessions,
            unused_session_lifetime=args.unused_session_lifetime,
        )
    except AppMissingError as exc:
        raise CommandError(_one_line(exc)) from None  # names the module and the app extra
    except OSError as exc:  # the port is taken, the address is not ours, ...
        raise UsageError(
            f"cannot serve on {args.host}:{args.port}: {exc.strerror or exc}"
        ) from None
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    sol = hairbed.solve(2.0, 0.5, 0.0)
    print("The paper's example: a hair standing upright (theta0 = 0) in a channel twice its")
    print("length (eps = L/H = 0.5) under forcing omega^2 = 2; exact solution:")
    print(_solution_table(sol))
    return 0


# -- states, stability, bistability (issue 12) ---------------------------------------------

#: Help text of a base angle: its sign convention.
THETA0_HELP = (
    "base angle theta0 [rad], in (-pi/2, pi/2); default 0. Positive leans with the flow, "
    "negative leans into it (where a tight channel can hold three states)"
)


def _root_labels(count: int) -> list[str]:
    """Labels of the states of one branch in increasing xi: low/mid/high (or 'only')."""
    return {1: ["only"], 2: ["low", "high"], 3: ["low", "mid", "high"]}.get(
        count, [f"root {i + 1}" for i in range(count)]
    )


def _stable(sol: Any) -> bool | None:
    """Linear stability of one state (None where it cannot be classified)."""
    from hairbed.stability import linear_stability

    result = linear_stability(sol, num=100 if sol.n == 0 else 200, k=1)
    return bool(result.stable) if result.success else None


def _labelled(sols: list[Any]) -> list[tuple[Any, str, bool | None]]:
    """Each state with its root label within its branch and its stability."""
    out = []
    i = 0
    while i < len(sols):
        j = i
        while j < len(sols) and (sols[j].sign, sols[j].n) == (sols[i].sign, sols[i].n):
            j += 1
        labels = _root_labels(j - i)
        out += [(s, lab, _stable(s)) for s, lab in zip(sols[i:j], labels)]
        i = j
    return out


def _stability_word(stable: bool | None) -> str:
    return {True: "stable", False: "unstable", None: "not classified"}[stable]


def _print_states(labelled: list[tuple[Any, str, bool | None]], as_json: bool, head: str) -> None:
    if as_json:
        print(json.dumps(_jsonable([{**s.as_dict(), "root": lab, "stable": st}
                                    for s, lab, st in labelled])))  # fmt: skip
        return
    print(head)
    for s, lab, st in labelled:
        branch = f"branch sign={s.sign:+d}, n={s.n}" + (" (physical)" if s.physical else "")
        print(f"{branch}, {lab} state ({_stability_word(st)}):")
        print(_solution_table(s))


def _cmd_bistability(args: argparse.Namespace) -> int:
    from hairbed import branches

    eps, theta0 = args.eps, args.theta0
    hairbed.solve(0.0, eps, theta0)  # validates the inputs, with their messages
    cusp = float(branches.cusp(theta0))
    f = branches.folds(eps, theta0)
    tip = np.asarray(hairbed.from_parameter(f.t, eps, theta0).tip_deflection).reshape(-1)
    folds = [
        {"omega2": float(w), "xi": float(x), "tip_deflection": float(d), "t": float(t)}
        for w, x, d, t in zip(f.omega2, f.xi, tip, f.t)
    ]
    win = branches.bistable_window(eps, theta0)
    window = [win.lower, win.upper] if win.exists else None
    if args.json:
        out = {"eps": eps, "theta0": theta0, "cusp_eps": cusp, "folds": folds, "window": window}
        print(json.dumps(_jsonable(out)))
        return 0
    lean = "into the flow" if theta0 < 0 else ("upright" if theta0 == 0 else "with the flow")
    print(f"hair bed at eps = {eps:g}, theta0 = {theta0:g} (leaning {lean})")
    if cusp < 1.0:
        print(f"  cusp: folds exist for eps > eps_c(theta0) = {cusp:.12g}")
    else:
        print("  cusp: none (the physical branch is monotone for every eps < 1 at this theta0)")
    if window is None:
        print("  no folds: one physical state at every omega^2 (no bistable window)")
        return 0
    for name, fold in zip(("lower", "upper"), folds):
        print(
            f"  {name} fold: omega2 = {fold['omega2']:.12g}, xi = {fold['xi']:.12g}, "
            f"tip deflection = {fold['tip_deflection']:.12g} [L]"
        )
    print(
        f"  window: three physical states (low and high stable, mid unstable) for "
        f"{window[0]:.12g} < omega2 < {window[1]:.12g}"
    )
    return 0


# -- calibration (issue 12) --------------------------------------------------------------------


def _read_calibration_csv(path: str) -> dict[str, np.ndarray]:
    """Columns tip_deflection and velocity or wall_shear_stress (optional sigma) of a CSV."""
    import csv

    try:
        with open(path, newline="") as fh:
            rows = list(csv.reader(fh))
    except OSError as exc:
        raise UsageError(f"--data: cannot read {path}: {exc.strerror or exc}") from None
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise UsageError(f"--data {path}: needs a header line and at least one row")
    header = [h.strip().lower() for h in rows[0]]
    allowed = ("tip_deflection", "velocity", "wall_shear_stress", "sigma")
    for h in header:
        if h not in allowed:
            raise UsageError(f"--data {path}: unknown column {h!r}; allowed: {', '.join(allowed)}")
    columns: dict[str, list[float]] = {h: [] for h in header}
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise UsageError(f"--data {path}: line {i} has {len(row)} fields, not {len(header)}")
        for h, cell in zip(header, row):
            try:
                columns[h].append(float(cell))
            except ValueError:
                raise UsageError(f"--data {path}: line {i}, {h}: not a number: {cell!r}") from None
    if "tip_deflection" not in columns:
        raise UsageError(f"--data {path}: needs a tip_deflection column [m]")
    if ("velocity" in columns) == ("wall_shear_stress" in columns):
        raise UsageError(
            f"--data {path}: needs exactly one of the columns velocity [m/s] and "
            "wall_shear_stress [Pa]"
        )
    return {h: np.array(v) for h, v in columns.items()}


def _need_bed(args: argparse.Namespace, what: str) -> Any:
    bed = _bed(args)
    if bed is None:
        raise UsageError(f"{what} needs the physical inputs of a bed (--length, --radius, ...)")
    return bed


def _cmd_calibrate(args: argparse.Namespace) -> int:
    from hairbed import calibration

    bed = _need_bed(args, "calibrate")
    data = _read_calibration_csv(args.data)
    sigma: Any = data.get("sigma")
    if args.sigma is not None:
        if sigma is not None:
            raise UsageError("give --sigma or a sigma column in --data, not both")
        sigma = args.sigma
    result = calibration.fit(
        bed,
        data["tip_deflection"],
        velocity=data.get("velocity"),
        wall_shear_stress=data.get("wall_shear_stress"),
        sigma=sigma,
        free=args.free,
    )
    units = calibration.FREE_PARAMETERS
    if args.json:
        out = {
            "parameters": {
                p: {"value": result.values[p], "stderr": result.stderr[p], "unit": units[p]}
                for p in result.parameters
            },
            "covariance": result.covariance,
            "chi2": result.chi2,
            "dof": result.dof,
            "residuals": result.residuals,
            "points": int(result.residuals.size),
            "kind": result.kind,
            "geometry": result.geometry,
            "success": result.success,
            "status": result.status,
            "message": result.message,
        }
        print(json.dumps(_jsonable(out)))
    else:
        print(f"calibration of {result.residuals.size} points ({result.kind} known):")
        width = max(len(p) for p in result.parameters)
        for p in result.parameters:
            print(
                f"  {p:<{width}}  {result.values[p]:.10g} +- {result.stderr[p]:.3g} [{units[p]}]"
            )
        print(f"  chi2 = {result.chi2:.6g} for {result.dof} degrees of freedom")
        print(f"  {'converged' if result.success else 'NOT converged'}: {result.message}")
    if not result.success:
        print(f"{PROG}: warning: the fit did not succeed: {result.message}", file=sys.stderr)
        return 1
    return 0


def _load_calibration(path: str, bed: Any) -> Any:
    """The CalibrationFit of a ``hairbed calibrate --json`` output, applied to ``bed``."""
    from dataclasses import replace

    from hairbed import calibration

    try:
        with open(path) as fh:
            data = json.load(fh)
        params = data["parameters"]
        names = tuple(params)
        values = {p: float(params[p]["value"]) for p in names}
        stderr = {p: float(params[p]["stderr"]) for p in names}
        cov = np.array(data["covariance"], dtype=np.float64)
        geometry = data.get("geometry", "spacing")
    except OSError as exc:
        raise UsageError(f"--calibration: cannot read {path}: {exc.strerror or exc}") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise UsageError(
            f"--calibration {path}: not the JSON of 'hairbed calibrate --json' ({exc})"
        ) from None
    if cov.shape != (len(names), len(names)):
        raise UsageError(f"--calibration {path}: covariance is not {len(names)} x {len(names)}")
    for p in names:
        if p not in calibration.FREE_PARAMETERS:
            raise UsageError(f"--calibration {path}: unknown parameter {p!r}")
    other = "packing_fraction" if geometry == "spacing" else "spacing"
    fitted = replace(bed, **{other: None}, **values)
    return calibration.CalibrationFit(
        bed=fitted,
        parameters=names,
        values=values,
        stderr=stderr,
        covariance=cov,
        residuals=np.asarray(data.get("residuals", []), dtype=np.float64),
        chi2=float(data.get("chi2", math.nan)),
        dof=int(data.get("dof", 0)),
        kind=str(data.get("kind", "velocity")),
        success=bool(data.get("success", True)),
        status=int(data.get("status", 1)),
        message=str(data.get("message", "")),
        nfev=0,
        geometry=geometry,
    )


def _cmd_measure(args: argparse.Namespace) -> int:
    from hairbed import calibration

    bed = _need_bed(args, "measure")
    fit = None if args.calibration is None else _load_calibration(args.calibration, bed)
    if fit is not None:
        bed = fit.bed
    m = calibration.measure(bed, args.tip_deflection, sigma=args.sigma, fit=fit)
    st = m.state
    if args.json:
        out = {
            "tip_deflection": m.tip_deflection,
            "sigma": args.sigma,
            "wall_shear_stress": m.wall_shear_stress,
            "wall_shear_stress_stderr": m.wall_shear_stress_stderr,
            "velocity": m.velocity,
            "velocity_stderr": m.velocity_stderr,
            "omega2": st.omega2,
            "reynolds_number": st.reynolds_number,
            "success": m.success,
            "message": m.message,
        }
        print(json.dumps(_jsonable(out)))
        return 0
    print(f"tau = {m.wall_shear_stress:.6g} +- {m.wall_shear_stress_stderr:.2g} Pa")
    print(f"v   = {m.velocity:.6g} +- {m.velocity_stderr:.2g} m/s")
    return 0


def _show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: Any = None,
    line: str | None = None,
) -> None:
    """warnings.showwarning of the command line: one line ``hairbed: warning: ...``, once per
    text (a warning raised in a loop is printed once)."""
    text = " ".join(str(message).split())
    if text in _WARNED:
        return
    _WARNED.add(text)
    print(f"{PROG}: warning: {text}", file=sys.stderr)


#: Texts of the warnings printed by this run of :func:`main`.
_WARNED: set[str] = set()


# -- parser ---------------------------------------------------------------------------------


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``hairbed`` (exposed for the documentation and tests)."""
    parser = _Parser(
        prog=PROG,
        formatter_class=_formatter,
        description="Exact deformation of a dense bed of elastic hairs in channel flow "
        "(Smucker, Vural, Alvarado & Morrison).",
        epilog="examples:\n"
        "  hairbed demo\n"
        "  hairbed solve --omega2 2 --eps 0.5\n"
        "  hairbed sweep --omega2 0.01:100:200:log --eps 0.5,0.9 --theta0 0 --out sweep.nc\n"
        "  hairbed invert --tip-deflection 0.6 --eps 0.5\n"
        "  hairbed figures --out figures\n"
        "run 'hairbed <command> --help' for the options of a command",
    )
    parser.add_argument("--version", action="version", version=f"hairbed {hairbed.__version__}")
    sub = parser.add_subparsers(dest="command", metavar="command", parser_class=_Parser)

    p = sub.add_parser(
        "solve",
        help="solve one state (table or JSON)",
        formatter_class=_formatter,
        description="Solve the boundary-value problem for one set of inputs.",
        epilog="examples:\n"
        "  hairbed solve --omega2 2 --eps 0.5\n"
        "  hairbed solve --omega2 2 --eps 0.5 --theta0 0.3 --json\n"
        "  hairbed solve --omega2 200 --eps 0.5 --all-branches --plot states.png\n"
        "  hairbed solve --omega2 1.2 --eps 0.9 --theta0 -1.5 --root high\n"
        "  hairbed solve --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 \\\n"
        "      --channel-height 2e-3 --viscosity 1 --spacing 400e-6 --velocity 0.1",
    )
    p.add_argument("--omega2", type=float, help="forcing omega^2 [-], >= 0")
    p.add_argument("--eps", type=float, help="confinement eps = L/H [-], in [0, 1)")
    p.add_argument("--theta0", type=float, help=THETA0_HELP)
    p.add_argument(
        "--sign",
        type=int,
        default=1,
        choices=(1, -1),
        help="sign of the base curvature of the branch (default 1)",
    )
    p.add_argument("--n", type=int, default=0, help="interior turning points (default 0)")
    p.add_argument(
        "--root",
        choices=("low", "mid", "high"),
        help="which state where several coexist (default: inside a bistable window, all of "
        "them, labelled low/mid/high with their stability; elsewhere the one state)",
    )
    p.add_argument(
        "--all-branches",
        action="store_true",
        help="every state on every branch, labelled low/mid/high and stable/unstable",
    )
    p.add_argument("--json", action="store_true", help="print JSON (fields by API names)")
    p.add_argument("--plot", metavar="FILE", help="also draw the profile(s) into FILE (PNG)")
    _add_bed_options(p)
    p.set_defaults(func=_cmd_solve)

    p = sub.add_parser(
        "sweep",
        help="grids of omega2, eps, theta0 (or wall speed) -> netCDF, zarr, CSV, parquet",
        formatter_class=_formatter,
        description="Solve on the outer-product grid of --omega2, --eps and --theta0 (or over "
        "wall speeds, given a bed) and write a labelled table. SPEC is a value, a comma list "
        "or start:stop:num[:log] (negative ones too: --theta0 -1.2:1.2:25). The output "
        "format follows the extension of --out: .nc (netCDF-4, CF attributes), .zarr, .csv "
        "(one row per grid point, units in the header; the default, to stdout) or .parquet; "
        "files are written whole or not at all.",
        epilog="examples:\n"
        "  hairbed sweep --omega2 0:10:101 --eps 0.5 > sweep.csv\n"
        "  hairbed sweep --omega2 1e-3:1e3:100:log --eps 0:0.95:40 --theta0=-1.2:1.2:25 "
        "--out grid.nc\n"
        "  hairbed sweep --omega2 1e-3:1e3:1000:log --eps 0:0.95:100 --theta0 0:1.2:100 "
        "--chunks 50 --progress --out big.zarr\n"
        "  hairbed sweep --omega2 0.01:100:200:log --eps 0.5,0.9 --chunks 50 "
        "--scheduler tcp://10.0.0.5:8786 --out grid.parquet\n"
        "  hairbed sweep --omega2 0.5:2:200 --eps 0.9 --theta0=-1.5 --quasistatic\n"
        "  hairbed sweep --length 1e-3 --radius 50e-6 --youngs-modulus 1e6 "
        "--channel-height 2e-3 \\\n"
        "      --viscosity 1 --spacing 400e-6 --velocity=-0.5:0.5:101 --out bed.nc",
    )
    p.add_argument("--omega2", metavar="SPEC", help="forcing omega^2 [-], >= 0")
    p.add_argument("--eps", metavar="SPEC", help="confinement eps = L/H [-], in [0, 1)")
    p.add_argument(
        "--theta0",
        metavar="SPEC",
        help="base angle [rad] (default 0; negative leans into the flow)",
    )
    p.add_argument("--velocity", metavar="SPEC", help="top wall speed v [m/s] (with a bed)")
    p.add_argument(
        "--sign", type=int, choices=(1, -1), help="sign of the base curvature (default 1)"
    )
    p.add_argument("--n", type=int, help="interior turning points of the branch (default 0)")
    p.add_argument(
        "--root",
        default="low",
        choices=("low", "mid", "high"),
        help="state where several coexist (default low)",
    )
    p.add_argument(
        "--quasistatic",
        action="store_true",
        help="follow the state along a 1-D --omega2 path (jumps at folds: hysteresis)",
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
    old = p.add_argument_group("the older form of a 1-D range (instead of a SPEC)")
    old.add_argument("--omega2-min", type=float, metavar="X", help="first omega^2 (default 0)")
    old.add_argument("--omega2-max", type=float, metavar="X", help="last omega^2 (default 10)")
    old.add_argument("--velocity-min", type=float, metavar="V", help="first wall speed [m/s]")
    old.add_argument("--velocity-max", type=float, metavar="V", help="last wall speed [m/s]")
    old.add_argument("--num", type=int, help="number of points (default 101)")
    old.add_argument("--log", action="store_true", help="geometric spacing")
    _add_bed_options(p, velocity=False)
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser(
        "invert",
        help="forcing from a measured tip deflection",
        formatter_class=_formatter,
        description="Find the forcing omega^2 (and, given a bed, the wall speed and wall shear "
        "stress) of the physical state with a given tip deflection.",
        epilog="examples:\n"
        "  hairbed invert --tip-deflection 0.6158 --eps 0.5\n"
        "  hairbed invert --tip-deflection 0.3 --eps 0.9 --theta0 0.2 --json\n"
        "  hairbed invert --tip-deflection 0.6158 --eps 0.5 --sigma 1e-3\n"
        "  hairbed invert --tip-deflection 3.7e-4 --length 1e-3 --radius 50e-6 \\\n"
        "      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6",
    )
    p.add_argument(
        "--tip-deflection",
        type=float,
        required=True,
        help="tip deflection x1 [L] (in metres when a bed is given)",
    )
    p.add_argument("--eps", type=float, help="confinement eps = L/H [-], in [0, 1)")
    p.add_argument("--theta0", type=float, help=THETA0_HELP)
    p.add_argument(
        "--sigma",
        type=float,
        metavar="S",
        help="standard error of the tip deflection (same unit): adds the standard error of "
        "omega2 (and of the wall speed and stress, given a bed), to first order",
    )
    p.add_argument("--json", action="store_true", help="print JSON")
    _add_bed_options(p, velocity=False)
    p.set_defaults(func=_cmd_invert)

    p = sub.add_parser(
        "figures",
        help="write every figure as PNG",
        formatter_class=_formatter,
        description="Recompute the paper's figures and the new ones and write PNG files "
        "(whole or not at all). --set KEY=VALUE passes a parameter to every selected figure "
        "that has it (a comma list for a tuple, e.g. eps_values=0.3,0.9); the figures and "
        "their parameters: model (omega2, eps, theta0), pendulum (omega2), phase_portrait "
        "(xis), solution (eps_values, num), theta0s (eps, theta0s, num), profiles (omega2s, "
        "eps, num), twirling (omega2, eps, theta0), bistability (n_theta, n_eps, theta0s), "
        "hysteresis (eps, theta0, num), rheology (eps_values, theta0, num), calibration "
        "(eps_values, theta0, num), physical_units (length, radius, youngs_modulus, "
        "channel_height, viscosity, spacing [SI], base_angles, max_velocity, num), "
        "fd_convergence (omega2s, nums, eps), speed (n, repeat).",
        epilog="examples:\n  hairbed figures --out figures\n"
        "  hairbed figures --out figs --only solution hysteresis --dpi 300\n"
        "  hairbed figures --out figs --only hysteresis --set eps=0.95 --set theta0=-1.2",
    )
    p.add_argument("--out", default="figures", help="output folder (default ./figures)")
    p.add_argument("--dpi", type=int, default=150, help="resolution (default 150)")
    p.add_argument("--only", nargs="+", metavar="NAME", help="only these figures")
    p.add_argument("--quiet", action="store_true", help="no line per figure")
    p.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="a parameter of the figures (repeatable), e.g. --set eps=0.9 --set theta0=-1.2",
    )
    p.set_defaults(func=_cmd_figures)

    p = sub.add_parser(
        "bench",
        help="measure every row of the speed table (ratios, targets)",
        formatter_class=_formatter,
        description="Measure the speed and memory table of benchmarks/bench_solve.py in one "
        "run: batch and scalar solves against scipy.special.ellipkinc, solve_all, profiles, "
        "the finite differences, peak memory, threads and whole processes, each against its "
        "target. By default with reduced sizes (about 30 s; figures not comparable with the "
        "targets); --full for the full sizes (about 2-3 minutes).",
        epilog="examples:\n  hairbed bench\n  hairbed bench --full --json bench.json\n"
        "  hairbed bench --rows 1 2 3 --n 1000000 --repeat 5",
    )
    size = p.add_mutually_exclusive_group()
    size.add_argument("--quick", action="store_true", help="reduced sizes (the default)")
    size.add_argument("--full", action="store_true", help="full sizes (1e6 elements ...)")
    p.add_argument("--n", type=int, help="batch size (default 1e5, 1e6 with --full)")
    p.add_argument("--repeat", type=int, default=3, help="best of this many runs (default 3)")
    p.add_argument("--seed", type=int, default=2026, help="random inputs (default 2026)")
    p.add_argument(
        "--rows",
        type=int,
        nargs="+",
        choices=range(1, 12),
        metavar="ROW",
        help="only these rows, 1 to 11 (default all)",
    )
    p.add_argument("--cold", action="store_true", help="also time a cold numba cache")
    p.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    p.add_argument("--progress", action="store_true", help="a line per section on stderr")
    p.set_defaults(func=_cmd_bench)

    p = sub.add_parser(
        "demo",
        help="the paper's worked example",
        formatter_class=_formatter,
        description="Solve omega2 = 2, eps = 0.5, theta0 = 0 and print the state.",
        epilog="example:\n  hairbed demo",
    )
    p.set_defaults(func=_cmd_demo)

    p = sub.add_parser(
        "explore",
        help="the interactive explorer in a web browser",
        formatter_class=_formatter,
        description="Serve the interactive explorer (needs the app extra: pip install "
        "'hairbed[app]'): sliders and exact entry of omega2, eps and theta0 or of a bed in SI "
        "units; every coexisting state in the channel, the branch diagram, the bistability map, "
        "the phase portrait and a table; the inputs in the page's URL; JSON and CSV downloads. "
        "Listens on the loopback interface unless --host says otherwise. Each browser session "
        "holds about 1 MB of server memory until it is discarded, --unused-session-lifetime "
        "after its page was closed.",
        epilog="examples:\n  hairbed explore\n  hairbed explore --port 8000 --no-browser\n"
        "  hairbed explore --host 0.0.0.0 --port 8000 --allow-websocket-origin example.org",
    )
    p.add_argument("--port", type=int, default=5006, help="TCP port (default 5006; 0: any free)")
    p.add_argument(
        "--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1, loopback)"
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a web browser")
    p.add_argument(
        "--allow-websocket-origin",
        action="append",
        metavar="HOST[:PORT]",
        help="also accept pages served as HOST[:PORT] (behind a proxy); repeatable",
    )
    p.add_argument(
        "--session-token-expiration",
        type=int,
        default=300,
        metavar="S",
        help="seconds a page has to connect to its session (default 300)",
    )
    p.add_argument(
        "--check-unused-sessions",
        type=int,
        default=17000,
        metavar="MS",
        help="how often to look for closed sessions [ms] (default 17000)",
    )
    p.add_argument(
        "--unused-session-lifetime",
        type=int,
        default=15000,
        metavar="MS",
        help="discard a closed session's state after this long [ms] (default 15000)",
    )
    p.set_defaults(func=_cmd_explore)

    p = sub.add_parser(
        "bistability",
        help="cusp, folds and bistable window of a hair bed (eps, theta0)",
        formatter_class=_formatter,
        description="The cusp confinement eps_c(theta0) above which the physical branch folds, "
        "its fold points (omega2, xi, tip deflection) and the window of omega2 in which three "
        "physical states coexist (or that there is none). Negative theta0 leans the hairs into "
        "the flow: only then (and for eps > eps_c) is there a window (theory.md §5).",
        epilog="examples:\n"
        "  hairbed bistability --eps 0.95 --theta0=-1.2\n"
        "  hairbed bistability --eps 0.9 --theta0=-1.5 --json\n"
        "JSON keys: cusp_eps, folds (list of {omega2, xi, tip_deflection, t}), window "
        "([lower, upper] or null)",
    )
    p.add_argument("--eps", type=float, required=True, help="confinement eps = L/H [-], in [0, 1)")
    p.add_argument("--theta0", type=float, required=True, help=THETA0_HELP)
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_cmd_bistability)

    p = sub.add_parser(
        "calibrate",
        help="fit a sensor's unknown parameters to measured tip deflections",
        formatter_class=_formatter,
        description="Fit the free parameters of a bed (by default Young's modulus) to tip "
        "deflections measured at known wall speeds or wall shear stresses, by weighted least "
        "squares on the exact calibration curve with its exact Jacobian "
        "(hairbed.calibration.fit). --data is a CSV file with a header line: tip_deflection "
        "[m] and either velocity [m/s] or wall_shear_stress [Pa], optionally sigma [m] (the "
        "standard deviation of each deflection). The bed options give the starting values and "
        "the fixed parameters. Exit status 1 when the fit does not succeed.",
        epilog="examples:\n"
        "  hairbed calibrate --data points.csv --length 1e-3 --radius 50e-6 \\\n"
        "      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6\n"
        "  hairbed calibrate --data points.csv --free youngs_modulus,base_angle --sigma 1e-6 "
        "... --json",
    )
    p.add_argument("--data", required=True, metavar="FILE.csv", help="calibration points (CSV)")
    p.add_argument(
        "--free",
        default="youngs_modulus",
        metavar="P1,P2",
        help="parameters to fit, comma-separated: length, radius, youngs_modulus, "
        "channel_height, viscosity, spacing, packing_fraction, base_angle "
        "(default youngs_modulus)",
    )
    p.add_argument(
        "--sigma", type=float, metavar="S", help="standard deviation of every deflection [m]"
    )
    p.add_argument("--json", action="store_true", help="print JSON")
    _add_bed_options(p, velocity=False)
    p.set_defaults(func=_cmd_calibrate)

    p = sub.add_parser(
        "measure",
        help="wall shear stress and speed (+- sigma) from a tip deflection",
        formatter_class=_formatter,
        description="Read the wall shear stress and the wall speed of a flow from the measured "
        "tip deflection of a bed (hairbed.calibration.measure), with standard errors from the "
        "deflection's --sigma and, with --calibration, the covariance of a calibration.",
        epilog="examples:\n"
        "  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --length 1e-3 --radius 50e-6 \\\n"
        "      --youngs-modulus 1e6 --channel-height 2e-3 --viscosity 1 --spacing 400e-6\n"
        "  hairbed calibrate --data points.csv ... --json > cal.json\n"
        "  hairbed measure --tip-deflection 3e-4 --sigma 1e-6 --calibration cal.json ...",
    )
    p.add_argument(
        "--calibration",
        metavar="FILE.json",
        help="the output of 'hairbed calibrate --json': its fitted values replace the bed's, "
        "its covariance enters the errors",
    )
    p.add_argument(
        "--tip-deflection", type=float, required=True, metavar="X", help="tip deflection [m]"
    )
    p.add_argument(
        "--sigma", type=float, default=0.0, metavar="S", help="its standard deviation [m]"
    )
    p.add_argument("--json", action="store_true", help="print JSON")
    _add_bed_options(p, velocity=False)
    p.set_defaults(func=_cmd_measure)

    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status (0 ok, 1 a file not writable or an extra
    not installed, 2 bad input, 130 Ctrl-C).

    Warnings (of the library, such as :class:`hairbed.ModelValidityWarning`, or of numpy) are
    printed as one line ``hairbed: warning: <message>`` on stderr, each text once.
    """
    _WARNED.clear()
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return _run(argv)
    except KeyboardInterrupt:  # between the handlers of _run (e.g. leaving the warnings block)
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


def run_and_exit() -> None:
    """The ``hairbed`` command: :func:`main`, then exit with its status.

    After Ctrl-C the process ends at once (``os._exit`` once stdout and stderr are flushed):
    the interpreter's normal shutdown would join the worker threads of a chunked sweep, which
    go on computing the blocks already queued, and a second Ctrl-C there would end in a
    traceback. Files are already whole or removed by then (``hairbed.safe_files``). A Ctrl-C
    after the command has done its work (while the interpreter shuts down) ends the process at
    once with the command's own status, silently. The console script starts the command with
    ``hairbed._command.run_and_exit``, which also handles a Ctrl-C while this module is
    imported.

    While the command runs, Ctrl-C does not unwind the stack (a ``KeyboardInterrupt``) but
    ends the process from the signal handler: the temporaries of the files being written are
    removed (:func:`hairbed.safe_files.remove_unfinished`; a rename onto a target holds the
    signal back until it is done), the one line is printed, exit status 130. Unwinding could
    wait without end: a chunked netCDF write closes its file on the way out, which needs the
    locks that its worker threads hold while they go on with the blocks already queued.
    """
    import hairbed.safe_files  # noqa: F401 (for the handler, which must not import)

    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _interrupted)
    code = main()
    if code == 130:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(130)

    def finished(signum: int, frame: object) -> None:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        except (OSError, ValueError):  # a closed pipe (``hairbed sweep ... | head``)
            pass
        os._exit(code)

    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, finished)
    sys.exit(code)


def _interrupted(signum: int, frame: object) -> None:
    """Ctrl-C while a command runs: remove partial files, one line, exit 130, at once."""
    sys.modules["hairbed.safe_files"].remove_unfinished()  # imported with the handler
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing to keep
            pass
    try:
        print(f"{PROG}: interrupted", file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass
    os._exit(130)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())  # one line, whatever the library wrote


def _run(argv: Sequence[str] | None) -> int:
    command = "hairbed"
    try:
        parser = build_parser()
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 0
        command = args.command
        return int(args.func(args))
    except (UsageError, ValueError) as exc:
        print(f"{PROG}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except ArithmeticError as exc:  # an overflow the library did not catch (a huge input)
        print(f"{PROG}: error: numerical overflow ({_one_line(exc)})", file=sys.stderr)
        return 2
    except CommandError as exc:
        print(f"{PROG}: {_one_line(exc)}", file=sys.stderr)
        return 1
    except ImportError as exc:  # an optional dependency missing deeper down
        name = (getattr(exc, "name", None) or "").split(".")[0]
        if "pip install" in str(exc):
            print(f"{PROG}: {_one_line(exc)}", file=sys.stderr)
        elif name in EXTRAS:
            print(
                f"{PROG}: {command} needs {name}: pip install 'hairbed[{EXTRAS[name]}]'",
                file=sys.stderr,
            )
        else:
            raise
        return 1
    except BrokenPipeError:  # e.g. `hairbed sweep ... | head`
        return 0
    except KeyboardInterrupt:  # Ctrl-C: files are written whole or not at all
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    run_and_exit()
