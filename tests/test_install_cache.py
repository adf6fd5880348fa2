"""The numba cache in a real install: a wheel of this tree, installed with pip
(not editable) into a fresh virtual environment whose site-packages nobody may write, gives
correct results with a writable HOME (the kernels cached in the user's cache directory), with a
read-only HOME (no cache at all: one line on stderr naming ``NUMBA_CACHE_DIR``, no warning
flood), with ``NUMBA_CACHE_DIR`` set, and with damaged cache files (truncated index and data
files: removed and rebuilt, never an error).

"Nobody may write": a read-only bind mount for root (who ignores permission bits; CI runs as
root), ``chmod -R a-w`` for anyone else. The dependencies are those of the running interpreter
(a ``.pth`` file in the new environment): nothing is downloaded. Results are checked against
the second mpmath reference set (``tests/data/reference_cases.json``). Each process that finds
no usable cache compiles every kernel it needs (tens of seconds): marked slow.
"""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest
from tolerances import ATOL, RTOL

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[1]
FIELDS = ("xi", "tip_height", "tip_deflection")

#: Run by the installed package's interpreter: solve the reference inputs, print JSON.
CHILD = """
import json, sys, time
start = time.perf_counter()
import numpy as np
import hairbed
w, e, t = (np.array(v, dtype=float) for v in json.loads(sys.argv[1]))
sol = hairbed.solve(w, e, t)
print(json.dumps({
    "file": hairbed.__file__,
    "seconds": time.perf_counter() - start,
    **{f: np.asarray(getattr(sol, f)).tolist() for f in sys.argv[2].split(",")},
}))
"""


@pytest.fixture(scope="module")
def reference(data_dir):
    cases = json.loads((data_dir / "reference_cases.json").read_text())["forward"]
    cases = [c for c in cases if len(c["solutions"]) == 1][:12]
    inputs = [[c[k] for c in cases] for k in ("omega2", "eps", "theta0")]
    expected = {f: np.array([float(c["solutions"][0][f]) for c in cases]) for f in FIELDS}
    return inputs, expected


def _read_only(path: Path) -> None:
    """Make ``path`` unwritable for this process: a read-only bind mount (root), or chmod."""
    if os.geteuid() == 0:
        for cmd in (["mount", "--bind", str(path), str(path)],
                    ["mount", "-o", "remount,bind,ro", str(path)]):  # fmt: skip
            proc = subprocess.run(cmd, capture_output=True, text=True)
            if proc.returncode != 0:
                _writable(path)
                pytest.skip(f"root cannot make a read-only bind mount here: {proc.stderr.strip()}")
    else:
        for root, dirs, files in os.walk(path):
            for name in [*dirs, *files]:
                p = Path(root) / name
                if not p.is_symlink():
                    p.chmod(p.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
        path.chmod(path.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))
    probe = path / ".probe"
    try:
        probe.touch()
    except OSError:
        return
    probe.unlink()
    pytest.skip(f"{path} stays writable for this user")


def _writable(path: Path) -> None:
    if os.geteuid() == 0:
        subprocess.run(["umount", str(path)], capture_output=True)
    else:
        for root, dirs, _files in os.walk(path):
            for name in dirs:
                (Path(root) / name).chmod(stat.S_IRWXU)
        path.chmod(stat.S_IRWXU)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The python of a fresh venv holding a pip-installed wheel of this tree, read-only."""
    base = tmp_path_factory.mktemp("install")
    tree = base / "tree"
    tree.mkdir()
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info", "*.nbi", "*.nbc")
    shutil.copytree(REPO / "src", tree / "src", ignore=ignore)
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy2(REPO / name, tree / name)
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "--no-input"]
    # a PYTHONPATH to a source tree would make pip see hairbed installed already
    clean = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    build = subprocess.run(
        [*pip, "wheel", "--no-deps", "--no-build-isolation", "--no-index"]
        + ["-w", str(base / "wheel"), str(tree)],
        capture_output=True,
        text=True,
        env=clean,
    )
    if build.returncode != 0:
        last = (build.stderr.strip().splitlines() or ["?"])[-1]
        pytest.fail(f"cannot build a wheel (the test extra has setuptools>=77): {last}")
    (wheel,) = (base / "wheel").glob("hairbed-*.whl")
    venv = base / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run(
        [*pip, "--python", str(python), "install", "--no-deps", "--no-index", str(wheel)],
        check=True,
        capture_output=True,
        env=clean,
    )
    site = Path(
        subprocess.run(
            [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.strip()
    )
    import llvmlite
    import numba
    import scipy

    deps = {str(Path(m.__file__).resolve().parents[1]) for m in (np, numba, llvmlite, scipy)}
    deps.add(sysconfig.get_paths()["purelib"])
    (site / "_hairbed_test_deps.pth").write_text("\n".join(sorted(deps)) + "\n")
    _read_only(venv)
    yield python, site
    _writable(venv)


def _home(tmp_path: Path, writable: bool) -> Path:
    home = tmp_path / ("home" if writable else "home-ro")
    home.mkdir()
    if not writable:
        _read_only(home)
    return home


def _run(python: Path, home: Path, reference, **env: str):
    inputs, expected = reference
    environ = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(home), **env}
    for key in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "SYSTEMROOT"):
        if key in os.environ:
            environ[key] = os.environ[key]
    proc = subprocess.run(
        [str(python), "-c", CHILD, json.dumps(inputs), ",".join(FIELDS)],
        capture_output=True,
        text=True,
        env=environ,
        timeout=900,
        cwd=home,
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert Path(out["file"]).resolve().is_relative_to(python.parents[1].resolve()), out["file"]
    for f in FIELDS:
        np.testing.assert_allclose(out[f], expected[f], rtol=RTOL, atol=ATOL, err_msg=f)
    return out, proc.stderr


def _cache_files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*") if p.suffix in (".nbi", ".nbc"))


def test_read_only_site_packages_writable_home(installed, reference, tmp_path):
    python, site = installed
    assert not _cache_files(site)  # the wheel carries no cache
    home = _home(tmp_path, writable=True)
    cold, err = _run(python, home, reference)
    assert err == ""
    cached = _cache_files(home / ".cache" / "numba")
    assert cached, "nothing cached in the user's cache directory"
    warm, err = _run(python, home, reference)
    assert err == ""
    assert _cache_files(home / ".cache" / "numba") == cached  # loaded, not written again

    # damage every cache file: index files truncated, data files garbage
    for path in cached:
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 3] if path.suffix == ".nbi" else b"\x80garbage")
    damaged, err = _run(python, home, reference)
    assert err == "", err  # no UnpicklingError, no warning
    # the kernels the run loaded are cached anew (inlined helpers it never loads on their own
    # keep their damaged files: never read, they cost nothing)
    data = [p for p in _cache_files(home / ".cache" / "numba") if p.suffix == ".nbc"]
    rebuilt = [p for p in data if p.stat().st_size > len(b"\x80garbage")]
    assert len(rebuilt) > len(data) // 2, f"{len(rebuilt)} of {len(data)} rebuilt"
    _, err = _run(python, home, reference)  # and the rebuilt cache loads
    assert err == ""


def test_read_only_site_packages_read_only_home_says_so_once(installed, reference, tmp_path):
    python, _ = installed
    home = _home(tmp_path, writable=False)
    try:
        _, err = _run(python, home, reference)
    finally:
        _writable(home)
    lines = err.splitlines()
    assert len(lines) == 1, err  # one line, however many kernels: no warning flood
    assert lines[0].startswith("hairbed: cannot cache the compiled kernels"), lines[0]
    assert "NUMBA_CACHE_DIR" in lines[0]


def test_numba_cache_dir_is_the_way_out(installed, reference, tmp_path):
    python, _ = installed
    home = _home(tmp_path, writable=False)
    cache = tmp_path / "cache"
    cache.mkdir()
    try:
        _, err = _run(python, home, reference, NUMBA_CACHE_DIR=str(cache))
    finally:
        _writable(home)
    assert err == ""
    assert _cache_files(cache)
