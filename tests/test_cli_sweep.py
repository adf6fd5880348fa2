"""`hairbed sweep` over grids: every format round-trips, options apply or are refused, and
an interrupted write (SIGINT in a real process) leaves no partial file and an old one intact.

Values read back are compared with ``hairbed.solve`` at the same points, bitwise (every format
stores float64 exactly; the CSV writes shortest round-trip reprs), and with the closed form of
the hair at rest (omega^2 = 0: h1 = cos theta0).
"""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed import safe_files, sweeps

xr = pytest.importorskip("xarray")
pytest.importorskip("dask.array")

BED = [
    "--length", "1e-3", "--radius", "50e-6", "--youngs-modulus", "1e6",
    "--channel-height", "2e-3", "--viscosity", "1", "--spacing", "400e-6",
]  # fmt: skip
GRID = ["--omega2", "0,0.5,2,30", "--eps", "0.2,0.5", "--theta0=-0.4:0.6:3"]
W, E, T = np.array([0.0, 0.5, 2.0, 30.0]), np.array([0.2, 0.5]), np.linspace(-0.4, 0.6, 3)
#: A grid that takes far longer than the interrupt tests wait (about 4e6 points in blocks of
#: 2e4: the process stops within a block of the interrupt).
LONG = ["--omega2", "1e-3:1e3:400:log", "--eps", "0:0.95:100", "--theta0=-1.2:1.2:100"]


def run(*args: str, **kw) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "hairbed", *args], capture_output=True, text=True, timeout=180, **kw
    )


def one_error(capsys, args, *words):
    from hairbed.cli import main

    status = main(args)
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("hairbed: error: "), err
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def reference(names=("xi", "tip_height", "tip_deflection", "status", "physical")):
    ww, ee, tt = np.meshgrid(W, E, T, indexing="ij")
    sol = hairbed.solve(ww, ee, tt)
    return {n: np.asarray(getattr(sol, n)) for n in names}, (ww, ee, tt)


@pytest.mark.parametrize("ext", [".nc", ".zarr", ".csv", ".parquet"])
@pytest.mark.parametrize("chunks", [[], ["--chunks", "2"]])
def test_every_format_round_trips(tmp_path, ext, chunks):
    out = tmp_path / f"grid{ext}"
    proc = run("sweep", *GRID, *chunks, "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr.strip() == f"wrote {out} ({W.size * E.size * T.size} points)"
    assert safe_files.temporary_names(out) == []
    ref, (ww, ee, tt) = reference()
    if ext in (".nc", ".zarr"):
        ds = xr.open_dataset(out) if ext == ".nc" else xr.open_zarr(out)
        assert tuple(ds.dims) == ("omega2", "eps", "theta0")
        np.testing.assert_array_equal(ds["omega2"].values, W)
        for name, value in ref.items():
            got = ds[name].values
            assert got.dtype == value.dtype, name
            np.testing.assert_array_equal(got, value)
        for name in ds.variables:
            assert ds[name].attrs["units"] == sweeps.ATTRS[name][0], name
            assert ds[name].attrs["long_name"] == sweeps.ATTRS[name][1], name
        assert ds.attrs["hairbed_version"] == hairbed.__version__
        assert ds.attrs["root"] == "low" and int(ds.attrs["branch_sign"]) == 1
        rest = ds["tip_height"].sel(omega2=0.0).values
        np.testing.assert_allclose(rest, np.broadcast_to(np.cos(T), rest.shape), rtol=1e-15)
        ds.close()
        return
    columns, units = sweeps.read_table(out)
    assert list(columns)[:3] == ["omega2", "eps", "theta0"]  # long format, one row a point
    assert len(columns["omega2"]) == ww.size
    np.testing.assert_array_equal(columns["omega2"], ww.reshape(-1))
    np.testing.assert_array_equal(columns["theta0"], tt.reshape(-1))
    for name, value in ref.items():
        np.testing.assert_array_equal(columns[name], value.reshape(-1))
        assert columns[name].dtype == value.dtype
    assert units == {n: sweeps.ATTRS[n][0] for n in columns}
    if ext == ".csv":  # a plain CSV reader sees the units in the header
        with open(out, newline="") as fh:
            header = next(csv.reader(fh))
        assert header[:3] == ["omega2 [1]", "eps [1]", "theta0 [rad]"]
    else:  # and pyarrow in the schema's metadata
        import pyarrow.parquet as pq

        schema = pq.read_schema(out)
        assert schema.field("tip_angle").metadata[b"units"] == b"rad"
        assert b"hairbed_version" in schema.metadata[b"hairbed"]


def test_a_bed_sweep_in_si_units(tmp_path):
    out = tmp_path / "bed.nc"
    proc = run("sweep", *BED, "--velocity=-0.5:0.5:5", "--chunks", "2", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    ds = xr.open_dataset(out)
    bed = hairbed.HairBed(1e-3, 50e-6, 1e6, 2e-3, 1.0, spacing=400e-6)
    st = bed.deform(np.linspace(-0.5, 0.5, 5))
    np.testing.assert_array_equal(ds["wall_shear_stress"].values, st.wall_shear_stress)
    np.testing.assert_array_equal(ds["tip_deflection"].values, st.tip_deflection)
    assert ds["wall_shear_stress"].attrs["units"] == "Pa"
    assert ds["velocity"].attrs["units"] == "m s-1"
    assert ds.attrs["bed_spacing"] == 400e-6
    ds.close()
    legacy = run("sweep", *BED, "--velocity-min", "0", "--velocity-max", "0.1", "--num", "3")
    assert legacy.returncode == 0, legacy.stderr
    rows = list(csv.DictReader(legacy.stdout.splitlines()))
    assert [float(r["velocity [m s-1]"]) for r in rows] == [0.0, 0.05, 0.1]


def test_quasistatic_path_and_stdout(capsys):
    from hairbed.cli import main

    assert main(["sweep", "--omega2", "0.8:1.6:9", "--eps", "0.9", "--theta0=-1.5",
                 "--quasistatic"]) == 0  # fmt: skip
    rows = list(csv.DictReader(capsys.readouterr().out.splitlines()))
    path = hairbed.quasistatic.sweep(np.linspace(0.8, 1.6, 9), 0.9, -1.5)
    assert [float(r["xi [1]"]) for r in rows] == np.asarray(path.xi).tolist()
    assert [float(r["omega2 [1]"]) for r in rows] == np.linspace(0.8, 1.6, 9).tolist()
    assert main(["sweep", "--omega2", "0,2", "--eps", "0.5"]) == 0
    rows = list(csv.DictReader(capsys.readouterr().out.splitlines()))
    assert float(rows[1]["xi [1]"]) == hairbed.solve(2.0, 0.5).xi


def test_progress_on_stderr(tmp_path, monkeypatch, capsys):
    from hairbed.cli import main

    monkeypatch.setattr(sweeps, "PROGRESS_DELAY", 0.0)
    assert (
        main(["sweep", *GRID, "--chunks", "1", "--progress", "--out", str(tmp_path / "p.nc")]) == 0
    )
    err = capsys.readouterr().err
    assert "hairbed sweep" in err and "100%" in err and "wrote" in err


def test_out_in_a_missing_directory_is_a_write_error(capsys):
    """Refused before any work, as every output of the command line (test_cli_errors)."""
    from hairbed.cli import main

    assert main(["sweep", "--omega2", "1", "--eps", "0.5", "--out", "/no/such/dir/x.nc"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err == (
        "hairbed: error: cannot write /no/such/dir/x.nc: directory '/no/such/dir' does not exist\n"
    )


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--omega2", "1", "--eps", "0.5", "--out", "x.txt"], ["'.txt'", ".nc", ".parquet"]),
        (["--omega2", "1", "--eps", "0.5", "--out", "x"], ["no extension"]),
        (["--omega2", "1:2", "--eps", "0.5"], ["--omega2", "start:stop:num"]),
        (["--omega2", "a,b", "--eps", "0.5"], ["--omega2"]),
        (["--omega2", "1:2:3:cubic", "--eps", "0.5"], ["--omega2", "log"]),
        (["--omega2", "0:2:3:log", "--eps", "0.5"], ["--omega2", "positive"]),
        (["--omega2", "1:2:0", "--eps", "0.5"], ["--omega2", ">= 1"]),
        (["--omega2", "1"], ["--eps"]),
        (["--omega2", "1", "--eps", "0.5,1.2"], ["eps", "[0, 1)", "index 1"]),
        (["--omega2", "1", "--eps", "0.5", "--num", "5"], ["--num"]),
        (["--omega2", "1", "--eps", "0.5", "--omega2-max", "5"], ["--omega2-max"]),
        (["--omega2", "1", "--eps", "0.5", "--velocity", "1"], ["--velocity", "bed"]),
        (["--omega2", "1", "--eps", "0.5", "--chunks", "0"], ["--chunks"]),
        (
            ["--omega2", "1", "--eps", "0.5", "--scheduler", "tcp://x:1"],
            ["--scheduler", "--chunks"],
        ),
        (["--omega2", "1,2", "--eps", "0.5", "--quasistatic", "--chunks", "2"], ["--chunks"]),
        (["--omega2", "1,2", "--eps", "0.5,0.6", "--quasistatic"], ["--quasistatic", "1-D"]),
        (["--omega2", "1,2", "--eps", "0.5", "--quasistatic", "--root", "mid"], ["--root"]),
        (["--omega2", "1,2", "--eps", "0.5", "--quasistatic", "--sign", "-1"], ["--sign"]),
        (["--omega2", "1,2", "--eps", "0.5", "--quasistatic", "--progress"], ["--progress"]),
        ([*BED, "--velocity", "1", "--eps", "0.5"], ["--eps", "bed"]),
        ([*BED, "--velocity", "1", "--n", "1"], ["--n"]),
        ([*BED, "--velocity", "1", "--quasistatic"], ["--quasistatic"]),
        ([*BED, "--velocity", "1", "--num", "3"], ["--num"]),
        ([*BED], ["--velocity"]),
    ],
)
def test_every_option_applies_or_is_refused(args, words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    one_error(capsys, ["sweep", *args], *words)
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_unknown_extension_is_refused_in_a_real_process(tmp_path):
    out = tmp_path / "grid.xlsx"
    proc = run("sweep", *LONG, "--out", str(out))  # refused before any work: fast
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "'.xlsx'" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_scheduler_address_uses_a_running_cluster(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    from hairbed.cli import main

    out = tmp_path / "g.parquet"
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        args = [*GRID, "--chunks", "2", "--scheduler", cluster.scheduler_address]
        assert main(["sweep", *args, "--out", str(out)]) == 0
    assert "wrote" in capsys.readouterr().err
    columns, _ = sweeps.read_table(out)
    ref, _ = reference()
    np.testing.assert_array_equal(columns["xi"], ref["xi"].reshape(-1))


# -- interrupts ---------------------------------------------------------------------------------


def _interrupt(tmp_path: Path, target: Path, args: list[str], wait_for_temporary: bool):
    """Start a sweep, SIGINT it mid-way (once its temporary exists, or during the solve)."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [sys.executable, "-m", "hairbed", "sweep", *args, "--out", str(target)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 120
        if wait_for_temporary:
            while not safe_files.temporary_names(target):
                assert proc.poll() is None, proc.communicate()
                assert time.monotonic() < deadline
                time.sleep(0.01)
            time.sleep(0.3)  # well inside the write
        else:
            time.sleep(4.0)  # imported, solving in memory (the eager path: no file yet)
        assert proc.poll() is None, "the sweep ended before the interrupt: make it longer"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    return proc.returncode, out, err


@pytest.mark.parametrize(
    ("ext", "existing"),
    [(".nc", False), (".zarr", False), (".csv", False), (".parquet", False), (".nc", True),
     (".zarr", True)],
)  # fmt: skip
def test_sigint_during_a_write_leaves_no_partial_file(tmp_path, ext, existing):
    target = tmp_path / f"grid{ext}"
    before = None
    if existing:
        proc = run("sweep", *GRID, "--out", str(target))
        assert proc.returncode == 0, proc.stderr
        before = {
            p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()
        }
    status, out, err = _interrupt(tmp_path, target, [*LONG, "--chunks", "25"], True)
    assert status == 130
    assert err == "hairbed: interrupted\n"  # one line, no traceback
    assert out == ""
    assert safe_files.temporary_names(target) == []  # no stray temporary
    if existing:
        after = {
            p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()
        }
        assert after == before  # the old target, byte for byte
        ds = xr.open_dataset(target) if ext == ".nc" else xr.open_zarr(target)
        np.testing.assert_array_equal(ds["omega2"].values, W)
        ds.close()
    else:
        assert list(tmp_path.iterdir()) == []


_STUCK_WRITER = """
import sys, threading, time
from hairbed import _command, safe_files, sweeps

held = threading.Lock()
threading.Thread(target=lambda: (held.acquire(), time.sleep(1e6)), daemon=True).start()


def stuck(ds, path, compress=True):  # clean-up waits on a worker thread's lock, as netCDF's
    with safe_files.atomic_path(path) as tmp:
        tmp.write_text("partial")
        print("writing", flush=True)
        try:
            time.sleep(1e6)
        finally:
            held.acquire()  # unwinding would wait here without end


sweeps.write_dataset = stuck
sys.argv = ["hairbed", "sweep", "--omega2", "1,2", "--eps", "0.5", "--out", sys.argv[1]]
_command.run_and_exit()
"""


def test_sigint_does_not_wait_for_a_stuck_writer(tmp_path):
    """Ctrl-C ends the command from the signal handler: no unwinding into a writer's locks."""
    target = tmp_path / "grid.nc"
    proc = subprocess.Popen(
        [sys.executable, "-c", _STUCK_WRITER, str(target)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline() == "writing\n", proc.communicate()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert (proc.returncode, err) == (130, "hairbed: interrupted\n")
    assert list(tmp_path.iterdir()) == []  # the temporary removed, no target


def test_sigint_while_solving_in_memory(tmp_path):
    target = tmp_path / "grid.nc"
    status, out, err = _interrupt(tmp_path, target, LONG, False)
    assert (status, out, err) == (130, "", "hairbed: interrupted\n")
    assert list(tmp_path.iterdir()) == []


# -- the safe files themselves --------------------------------------------------------------------


def test_atomic_file_whole_or_not_at_all(tmp_path):
    target = tmp_path / "t.csv"
    safe_files.write_text(target, "old\n")
    for error in (RuntimeError, KeyboardInterrupt):
        with pytest.raises(error), safe_files.atomic_path(target) as tmp:
            tmp.write_text("half")
            assert tmp.parent == tmp_path and tmp.suffix == ".csv" and tmp != target
            raise error
        assert target.read_text() == "old\n"
        assert sorted(tmp_path.iterdir()) == [target]
    safe_files.write_text(target, "new\n")
    assert target.read_text() == "new\n" and sorted(tmp_path.iterdir()) == [target]
    umask = os.umask(0)
    os.umask(umask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~umask  # not mkstemp's private 0600
    with pytest.raises(FileNotFoundError), safe_files.atomic_path(tmp_path / "no" / "x.csv"):
        pass
    with pytest.raises(IsADirectoryError), safe_files.atomic_path(tmp_path):
        pass


def test_remove_unfinished_takes_only_the_temporaries(tmp_path):
    """What a hard-exit Ctrl-C handler calls: the temporaries go, the targets stay."""
    target = tmp_path / "t.csv"
    safe_files.write_text(target, "old\n")
    store = tmp_path / "s.zarr"
    with pytest.raises(RuntimeError), safe_files.atomic_path(target) as tmp:
        tmp.write_text("half")
        with safe_files.atomic_path(store, directory=True) as tmp_store:
            tmp_store.mkdir()
            (tmp_store / "part").write_text("half")
            assert sorted(safe_files.remove_unfinished()) == sorted([tmp, tmp_store])
            assert not tmp.exists() and not tmp_store.exists()
            assert safe_files.remove_unfinished() == []  # nothing twice
            raise RuntimeError
    assert target.read_text() == "old\n" and sorted(tmp_path.iterdir()) == [target]
    assert safe_files.remove_unfinished() == []


def test_sigint_during_the_renames_of_a_store_runs_after_them(tmp_path, monkeypatch):
    """Ctrl-C between the two renames of a store is held back until both are done."""
    target = tmp_path / "s.zarr"
    with safe_files.atomic_path(target, directory=True) as tmp:
        tmp.mkdir()
        (tmp / "part").write_text("one")
    real_replace = os.replace
    seen: list[list[str]] = []

    def replace(src, dst):
        if not seen:
            signal.raise_signal(signal.SIGINT)  # arrives between the renames
        real_replace(src, dst)

    def handler(signum, frame):  # what the hairbed command does: clean up, then stop
        seen.append([p.name for p in safe_files.remove_unfinished()])

    monkeypatch.setattr(safe_files.os, "replace", replace)
    previous = signal.signal(signal.SIGINT, handler)
    try:
        with safe_files.atomic_path(target, directory=True) as tmp:
            tmp.mkdir()
            (tmp / "part").write_text("two")
    finally:
        signal.signal(signal.SIGINT, previous)
    assert len(seen) == 1  # once, after the renames: only the old store was left to remove
    assert len(seen[0]) == 1 and seen[0][0].endswith(".tmp.old")
    assert (target / "part").read_text() == "two" and sorted(tmp_path.iterdir()) == [target]


def test_atomic_directory_store(tmp_path):
    target = tmp_path / "s.zarr"
    for content in ("one", "two"):
        with safe_files.atomic_path(target, directory=True) as tmp:
            assert not tmp.exists()
            tmp.mkdir()
            (tmp / "part").write_text(content)
        assert (target / "part").read_text() == content
        assert sorted(tmp_path.iterdir()) == [target]
    with pytest.raises(KeyboardInterrupt), safe_files.atomic_path(target, directory=True) as tmp:
        tmp.mkdir()
        (tmp / "part").write_text("three")
        raise KeyboardInterrupt
    assert (target / "part").read_text() == "two" and sorted(tmp_path.iterdir()) == [target]
    (tmp_path / "f").write_text("a file")
    with pytest.raises(NotADirectoryError):
        with safe_files.atomic_path(tmp_path / "f", directory=True):
            pass
