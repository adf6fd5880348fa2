"""A worker dies mid-sweep: on a ``distributed.LocalCluster`` of 2 worker
processes, one worker process is killed (SIGKILL) while a chunked sweep is being computed and
written. Either the sweep completes with values bitwise equal to the serial run (the scheduler
recomputes the lost blocks on the other worker or on the nanny's new process), or, when the
cluster allows no retry (``distributed.scheduler.allowed-failures = 0``), it ends with one
clear error and no file: neither a partial target nor a temporary, an existing target kept
byte for byte. Both for the library call (``hairbed.sweeps.write_dataset`` of a chunked
``hairbed.sweep`` under a ``distributed.Client``) and for ``hairbed sweep --scheduler``.

The kill is timed from the scheduler's own task states: once some blocks are done and others
are not, so the death falls inside the computation, never before or after it (the test checks
that it did). Marked slow (about a minute: two clusters of two processes on a loaded machine).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed import safe_files

xr = pytest.importorskip("xarray")
pytest.importorskip("netCDF4")
distributed = pytest.importorskip("distributed")
dask = pytest.importorskip("dask")
sweeps = pytest.importorskip("hairbed.sweeps")

pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore")]

#: 80,000 points in 10 blocks (a few seconds of work for 2 single-threaded workers).
OMEGA2 = np.geomspace(1e-3, 1e3, 200)
EPS = np.linspace(0.0, 0.95, 20)
THETA0 = np.linspace(-1.2, 1.2, 20)
SPEC = ["--omega2", "0.001:1000:200:log", "--eps", "0:0.95:20", "--theta0=-1.2:1.2:20"]
OLD = b"an existing target\n"


@pytest.fixture(scope="module")
def serial():
    return hairbed.sweep(OMEGA2, EPS, THETA0)


def _cluster(allowed_failures: int):
    with dask.config.set({"distributed.scheduler.allowed-failures": allowed_failures}):
        cluster = distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=50,
        )
    client = distributed.Client(cluster, set_as_default=False)
    client.run(lambda: hairbed.solve(1.0, 0.5).xi)  # load the kernels in each worker
    return cluster, client


@pytest.fixture(scope="module")
def retrying():
    cluster, client = _cluster(3)  # dask's default
    yield cluster, client
    client.close()
    cluster.close()


@pytest.fixture(scope="module")
def unforgiving():
    cluster, client = _cluster(0)
    yield cluster, client
    client.close()
    cluster.close()


def _states(dask_scheduler) -> dict[str, int]:
    counts: dict[str, int] = {}
    for ts in dask_scheduler.tasks.values():
        if str(ts.key).find("grid_block") >= 0:
            counts[ts.state] = counts.get(ts.state, 0) + 1
    return counts


class Killer(threading.Thread):
    """Kills one worker process once some blocks are in memory and others are not."""

    def __init__(self, client) -> None:
        super().__init__(daemon=True)
        self.client = client
        self.pids = client.run(os.getpid)
        self.left_at_kill: int | None = None
        self.stop = threading.Event()

    def run(self) -> None:
        while not self.stop.is_set():
            counts = self.client.run_on_scheduler(_states)
            done, total = counts.get("memory", 0) + counts.get("released", 0), sum(counts.values())
            if done >= 1 and total - done >= 3:
                victim = max(self.pids.values())
                os.kill(victim, signal.SIGKILL)
                self.left_at_kill = total - done
                return
            time.sleep(0.02)

    def finish(self) -> None:
        self.stop.set()
        self.join(30)
        assert self.left_at_kill is not None, "the sweep ended before a worker could be killed"
        self.client.wait_for_workers(2, timeout=60)  # the nanny's new process, for the next test
        assert self.client.run(os.getpid) != self.pids, "no worker was replaced"


def _same_bits(path: Path, serial) -> None:
    got = xr.open_dataset(path)
    try:
        for name in [*serial.coords, *serial.data_vars]:
            ref, res = np.asarray(serial[name].values), np.asarray(got[name].values)
            assert res.dtype == ref.dtype and res.tobytes() == ref.tobytes(), name
    finally:
        got.close()


def test_the_library_call_survives_a_dying_worker(retrying, serial, tmp_path):
    cluster, client = retrying
    target = tmp_path / "grid.nc"
    with client.as_current():
        ds = hairbed.sweep(OMEGA2, EPS, THETA0, chunks={"eps": 2})
        killer = Killer(client)
        killer.start()
        assert sweeps.write_dataset(ds, target) == OMEGA2.size * EPS.size * THETA0.size
    killer.finish()
    _same_bits(target, serial)
    assert safe_files.temporary_names(target) == []


def test_the_library_call_without_retries_fails_whole(unforgiving, tmp_path):
    cluster, client = unforgiving
    target = tmp_path / "grid.nc"
    target.write_bytes(OLD)
    with client.as_current():
        ds = hairbed.sweep(OMEGA2, EPS, THETA0, chunks={"eps": 2})
        killer = Killer(client)
        killer.start()
        with pytest.raises(distributed.KilledWorker):
            sweeps.write_dataset(ds, target)
    killer.finish()
    assert target.read_bytes() == OLD
    assert sorted(p.name for p in tmp_path.iterdir()) == ["grid.nc"]


def _command(address: str, target: Path) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.Popen(
        [sys.executable, "-m", "hairbed", "sweep", *SPEC, "--chunks", "20"]
        + ["--scheduler", address, "--out", str(target)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )


def test_hairbed_sweep_scheduler_survives_a_dying_worker(retrying, serial, tmp_path):
    cluster, client = retrying
    target = tmp_path / "grid.nc"
    killer = Killer(client)
    killer.start()
    proc = _command(cluster.scheduler_address, target)
    out, err = proc.communicate(timeout=600)
    killer.finish()
    assert proc.returncode == 0, err
    points = OMEGA2.size * EPS.size * THETA0.size
    assert err.strip().splitlines()[-1] == f"wrote {target} ({points} points)"
    _same_bits(target, serial)
    assert safe_files.temporary_names(target) == []


def test_hairbed_sweep_scheduler_without_retries_is_one_line(unforgiving, tmp_path):
    cluster, client = unforgiving
    target = tmp_path / "grid.nc"
    target.write_bytes(OLD)
    killer = Killer(client)
    killer.start()
    proc = _command(cluster.scheduler_address, target)
    out, err = proc.communicate(timeout=600)
    killer.finish()
    lines = err.strip().splitlines()
    assert proc.returncode == 1 and out == "", err
    assert len(lines) == 1 and lines[0].startswith("hairbed: "), err
    assert "worker" in lines[0] and cluster.scheduler_address in lines[0], lines[0]
    assert target.read_bytes() == OLD
    assert sorted(p.name for p in tmp_path.iterdir()) == ["grid.nc"]
