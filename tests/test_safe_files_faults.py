"""A full disk and a read-only directory: every writer of hairbed ends with one
clear error naming the file and the reason, leaves no temporary file, and keeps an existing
target byte for byte.

The full disk is a real one: a 64 KiB tmpfs mounted for the test (root only: CI runs as root;
elsewhere these tests skip, saying so). The read-only directory is a read-only tmpfs for root
(who ignores permission bits) and a ``chmod a-w`` directory for any other user. The writers:
``hairbed.sweeps.write_dataset`` in every format, eager and chunked (dask), ``hairbed sweep
--out``, ``hairbed.plotting.make_all`` and ``hairbed figures --out``. The explorer's downloads
are files in memory (nothing to fill): tests/test_explorer_sessions.py checks that they are
made for every view.
"""

from __future__ import annotations

import errno
import os
import shutil
import stat
import subprocess
import sys
import uuid
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed import safe_files

pytest.importorskip("xarray")
pytest.importorskip("dask.array")
sweeps = pytest.importorskip("hairbed.sweeps")

#: A grid whose files are far larger than the 64 KiB file system (~1.5 MB of float64).
OMEGA2, EPS = np.geomspace(1e-2, 1e3, 2000), np.linspace(0.0, 0.9, 5)
GRID = ["--omega2", "0.01:1000:2000:log", "--eps", "0:0.9:5"]
OLD = b"an existing target, to be kept byte for byte\n"
FORMATS = [".nc", ".zarr", ".csv", ".parquet"]
#: Root gets a read-only file system, anyone else a directory without write permission.
ROOT = os.geteuid() == 0


def _mount(where: Path, options: str) -> None:
    if os.geteuid() != 0 or shutil.which("mount") is None:
        pytest.skip("mounting a tmpfs needs root (CI runs as root)")
    proc = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)],
        capture_output=True,
        text=True,
    )
    if proc.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {proc.stderr.strip()}")


def _umount(where: Path) -> None:
    subprocess.run(["umount", "-l", str(where)], capture_output=True)


@pytest.fixture
def full_disk(tmp_path):
    """A 64 KiB tmpfs holding one small existing target per format (``old.<ext>``)."""
    where = tmp_path / "tiny"
    where.mkdir()
    _mount(where, "size=64k,mode=0777")
    try:
        for ext in FORMATS:
            _old(where / f"old{ext}")
        yield where
    finally:
        _umount(where)


def _old(target: Path) -> None:
    if target.suffix == ".zarr":
        target.mkdir()
        (target / "marker").write_bytes(OLD)
    else:
        target.write_bytes(OLD)


def _unchanged(target: Path) -> bool:
    if target.suffix == ".zarr":
        return sorted(p.name for p in target.iterdir()) == ["marker"] and (
            (target / "marker").read_bytes() == OLD
        )
    return target.read_bytes() == OLD


@pytest.fixture
def read_only(tmp_path):
    """A directory nobody may write into, holding ``old.<ext>`` per format."""
    where = tmp_path / "ro"
    where.mkdir()
    for ext in FORMATS:
        _old(where / f"old{ext}")
    if os.geteuid() == 0:  # root ignores permission bits: a read-only file system then
        seed = tmp_path / "seed"
        where.rename(seed)
        where.mkdir()
        _mount(where, "size=1m,mode=0777")
        try:
            for item in seed.iterdir():
                shutil.move(str(item), where / item.name)
            subprocess.run(["mount", "-o", "remount,ro", str(where)], check=True)
            yield where
        finally:
            _umount(where)
    else:
        where.chmod(stat.S_IRUSR | stat.S_IXUSR)
        try:
            yield where
        finally:
            where.chmod(stat.S_IRWXU)


def _listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def _dataset(chunked: bool):
    return hairbed.sweep(OMEGA2, EPS, chunks={"omega2": 500} if chunked else None)


@pytest.mark.parametrize("chunked", [False, True])
@pytest.mark.parametrize("ext", FORMATS)
def test_a_sweep_on_a_full_disk_is_one_oserror_naming_the_target(full_disk, ext, chunked):
    before = _listing(full_disk)
    for name in (f"new{ext}", f"old{ext}"):
        target = full_disk / name
        with pytest.raises(OSError) as caught:
            sweeps.write_dataset(_dataset(chunked), target)
        assert caught.value.errno == errno.ENOSPC, repr(caught.value)
        assert caught.value.filename == str(target)
        assert safe_files.temporary_names(target) == []
    assert _listing(full_disk) == before  # no new file, no temporary
    assert _unchanged(full_disk / f"old{ext}")


@pytest.mark.parametrize("ext", FORMATS)
def test_a_sweep_into_a_read_only_directory_is_one_oserror_naming_the_target(read_only, ext):
    before = _listing(read_only)
    for name in (f"new{ext}", f"old{ext}"):
        target = read_only / name
        with pytest.raises(OSError) as caught:
            sweeps.write_dataset(_dataset(False), target)
        assert caught.value.errno in (errno.EROFS, errno.EACCES), repr(caught.value)
        assert caught.value.filename == str(target)
    assert _listing(read_only) == before
    assert _unchanged(read_only / f"old{ext}")


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    from hairbed.cli import main

    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def _one_line(err: str, path: Path, *reasons: str, head: str = "hairbed: ") -> None:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"{head}cannot write {path}: "), lines[0]
    assert any(r in lines[0] for r in reasons), lines[0]


@pytest.mark.parametrize("chunks", [[], ["--chunks", "500"]])
@pytest.mark.parametrize("ext", [".nc", ".zarr", ".csv"])
def test_hairbed_sweep_on_a_full_disk_says_so_in_one_line(full_disk, capsys, ext, chunks):
    before = _listing(full_disk)
    for name in (f"new{ext}", f"old{ext}"):
        target = full_disk / name
        status, out, err = _cli(capsys, "sweep", *GRID, *chunks, "--out", str(target))
        assert status == 1 and out == ""
        _one_line(err, target, os.strerror(errno.ENOSPC))
    assert _listing(full_disk) == before
    assert _unchanged(full_disk / f"old{ext}")


@pytest.mark.parametrize("ext", [".nc", ".parquet"])
def test_hairbed_sweep_into_a_read_only_directory_says_so_in_one_line(read_only, capsys, ext):
    before = _listing(read_only)
    for name in (f"new{ext}", f"old{ext}"):
        target = read_only / name
        status, out, err = _cli(capsys, "sweep", *GRID, "--out", str(target))
        assert status == 2 and out == ""  # refused before any work: bad input
        reason = "read-only file system" if ROOT else "permission denied"
        _one_line(err, target, reason, head="hairbed: error: ")
    assert _listing(read_only) == before
    assert _unchanged(read_only / f"old{ext}")


def test_the_command_on_a_full_disk_in_a_real_process(full_disk):
    """The console command end to end: exit status 1, one line, nothing left behind."""
    target = full_disk / "old.nc"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run(
        [sys.executable, "-m", "hairbed", "sweep", *GRID, "--chunks", "500", "--out", str(target)],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert proc.returncode == 1 and proc.stdout == ""
    _one_line(proc.stderr, target, os.strerror(errno.ENOSPC))
    assert _unchanged(target) and safe_files.temporary_names(target) == []


# -- figures -----------------------------------------------------------------------------------

pytest.importorskip("matplotlib")
FIGURE = "pendulum"  # one figure larger than the file system (a PNG of ~100 KB at 150 dpi)


def test_make_all_on_a_full_disk_names_the_figure(full_disk):
    from hairbed.plotting import make_all

    out = full_disk / "figs"
    out.mkdir()
    (out / f"{FIGURE}.png").write_bytes(OLD)
    with pytest.raises(OSError) as caught:
        make_all(out, only=[FIGURE])
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(out / f"{FIGURE}.png")
    assert _listing(out) == [f"{FIGURE}.png"]
    assert (out / f"{FIGURE}.png").read_bytes() == OLD


def test_hairbed_figures_on_a_full_disk_says_so_in_one_line(full_disk, capsys):
    out = full_disk / "figs"
    out.mkdir()
    (out / f"{FIGURE}.png").write_bytes(OLD)
    status, _, err = _cli(capsys, "figures", "--only", FIGURE, "--quiet", "--out", str(out))
    assert status == 1
    _one_line(err, out / f"{FIGURE}.png", os.strerror(errno.ENOSPC))
    assert _listing(out) == [f"{FIGURE}.png"]
    assert (out / f"{FIGURE}.png").read_bytes() == OLD


def test_hairbed_figures_into_a_read_only_directory_says_so_in_one_line(read_only, capsys):
    out = read_only / f"figs-{uuid.uuid4().hex}"
    status, _, err = _cli(capsys, "figures", "--only", FIGURE, "--quiet", "--out", str(out))
    assert status == 2  # refused before any work: bad input (the README's exit status 2)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"hairbed: error: cannot write {out}"), err
    assert not out.exists()


# -- the rule itself, on a writer that hides the ENOSPC (as netCDF-4/HDF5 does) ----------------


def test_a_library_error_on_a_full_disk_becomes_enospc(full_disk):
    target = full_disk / "hidden.bin"

    def writer(path: Path) -> None:
        try:
            path.write_bytes(b"x" * 200_000)
        except OSError:
            raise RuntimeError("HDF error") from None

    with pytest.raises(OSError) as caught, safe_files.atomic_path(target) as tmp:
        writer(tmp)
    assert caught.value.errno == errno.ENOSPC and caught.value.filename == str(target)
    assert "RuntimeError: HDF error" in caught.value.strerror
    assert isinstance(caught.value.__cause__, RuntimeError)
    assert not target.exists() and safe_files.temporary_names(target) == []


def test_a_library_error_with_space_left_stays_what_it_is(tmp_path):
    target = tmp_path / "fine.bin"
    with pytest.raises(RuntimeError, match="a bug"), safe_files.atomic_path(target):
        raise RuntimeError("a bug")
    assert not target.exists() and safe_files.temporary_names(target) == []
