"""Threads: 8 threads calling ``solve``, ``solve_all``, ``derivatives`` and
``sweep`` at once, on the same input arrays, get results bitwise equal to the serial calls, and
the shared inputs are not changed.

The kernels release the GIL (``nogil=True``), so the threads really run the compiled code at
the same time; any state shared between calls (a scratch buffer, a cache filled lazily, a
module-level array) would show as a difference in some bit. The reference is the serial call
made before the threads start, on copies of the inputs: this tests the absence of interference,
which no single-threaded test can, and each function's accuracy is tested elsewhere against
mpmath. Hypothesis draws the inputs (derandomized: the same examples on every run, a fixed
number of them, so the time is bounded); a fixed battery crosses the folds of a bistable
window and the twirling branches.
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import hairbed

THREADS = 8
#: Examples hypothesis draws (each runs every function in 8 threads at once).
EXAMPLES = 12


def flatten(value: Any, prefix: str = "") -> dict[str, bytes]:
    """Every number of a result as raw bytes (bitwise: NaN payloads and signed zeros too)."""
    out: dict[str, bytes] = {}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            out.update(flatten(getattr(value, f.name), f"{prefix}.{f.name}"))
    elif isinstance(value, Mapping):
        for k in value:
            out.update(flatten(value[k], f"{prefix}[{k}]"))
    elif isinstance(value, list | tuple):
        for i, v in enumerate(value):
            out.update(flatten(v, f"{prefix}[{i}]"))
    elif hasattr(value, "data_vars"):  # an xarray Dataset
        for name in [*value.coords, *value.data_vars]:
            out.update(flatten(np.asarray(value[name].values), f"{prefix}.{name}"))
    elif value is None or isinstance(value, str):
        out[prefix] = repr(value).encode()
    else:
        arr = np.asarray(value)
        out[prefix] = arr.dtype.str.encode() + repr(arr.shape).encode() + arr.tobytes()
    return out


def calls(omega2: np.ndarray, eps: np.ndarray, theta0: np.ndarray) -> list[Callable[[], Any]]:
    """The calls each thread makes, all on the same (shared) input arrays."""
    w0, e0, t0 = float(omega2.flat[0]), float(eps.flat[0]), float(theta0.flat[0])
    return [
        lambda: hairbed.solve(omega2, eps, theta0),
        lambda: hairbed.solve(omega2, eps, theta0, root="high"),
        lambda: hairbed.solve(omega2, eps, theta0, sign=-1, n=1),
        lambda: hairbed.solve_all(w0, e0, t0),
        lambda: hairbed.derivatives(omega2, eps, theta0),
        lambda: hairbed.sweep(omega2, eps[:2], theta0[:2]),
        lambda: hairbed.sweep(omega2, eps[:2], theta0[:2], chunks={"omega2": 3}).compute(),
    ]


def run_at_once(omega2: np.ndarray, eps: np.ndarray, theta0: np.ndarray) -> None:
    inputs = [omega2.copy(), eps.copy(), theta0.copy()]
    serial = [flatten(call()) for call in calls(*inputs)]
    shared = [omega2, eps, theta0]
    before = [a.tobytes() for a in shared]
    todo = calls(*shared)
    barrier = threading.Barrier(THREADS)
    results: dict[int, list[dict[str, bytes]]] = {}
    errors: list[BaseException] = []

    def worker(k: int) -> None:
        try:
            barrier.wait()
            # each thread runs every call, starting at a different one: all mixes overlap
            order = [(k + j) % len(todo) for j in range(len(todo))]
            got: list[dict[str, bytes]] = [{} for _ in todo]
            for i in order:
                got[i] = flatten(todo[i]())
            results[k] = got
        except BaseException as exc:  # reported below, with the thread's number
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(THREADS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert [a.tobytes() for a in shared] == before, "a call changed its input arrays"
    for k, got in results.items():
        for i, (ref, res) in enumerate(zip(serial, got)):
            assert res.keys() == ref.keys(), (k, i)
            differ = [name for name in ref if res[name] != ref[name]]
            assert not differ, f"thread {k}, call {i}: {differ[:5]} differ from the serial call"
    assert len(results) == THREADS


def test_a_bistable_window_and_twirling_branches_in_eight_threads():
    """Fixed inputs: omega2 across the bistable window of (eps, theta0) = (0.9, -1.5)
    (three states between the folds), strong forcing with twirling branches, weak forcing."""
    omega2 = np.array([0.55, 0.6, 0.65, 0.7, 0.8, 1.0, 200.0, 5e4, 1e-9, 2.0])
    eps = np.array([0.9, 0.9, 0.9, 0.9, 0.9, 0.5, 0.5, 0.5, 0.3, 0.5])
    theta0 = np.array([-1.5, -1.5, -1.5, -1.5, -1.5, 0.0, 0.3, 0.0, 1.2, 0.0])
    run_at_once(omega2, eps, theta0)


finite = {"allow_nan": False, "allow_infinity": False}
inputs = st.integers(min_value=1, max_value=40).flatmap(
    lambda size: st.tuples(
        st.lists(
            st.one_of(
                st.floats(0.0, 10.0, **finite),
                st.floats(-12.0, 8.0, **finite).map(lambda p: 10.0**p),
            ),
            min_size=size,
            max_size=size,
        ),
        st.lists(st.floats(0.0, 0.99, **finite), min_size=size, max_size=size),
        st.lists(st.floats(-1.55, 1.55, **finite), min_size=size, max_size=size),
    )
)


@settings(
    max_examples=EXAMPLES,
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=False,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(inputs)
def test_random_inputs_in_eight_threads_match_the_serial_calls(drawn):
    omega2, eps, theta0 = (np.array(v, dtype=np.float64) for v in drawn)
    run_at_once(omega2, eps, theta0)


def test_the_check_can_fail():
    """``flatten`` sees one flipped bit (the last of a mantissa) and a NaN's payload."""
    a = hairbed.solve(2.0, 0.5)
    b = dataclasses.replace(a, xi=np.nextafter(a.xi, 2.0))
    assert flatten(a) != flatten(b)
    nan2 = np.frombuffer((np.float64("nan").view(np.uint64) | np.uint64(1)).tobytes(), np.float64)
    assert flatten(np.array([np.nan])) != flatten(nan2)


pytestmark = pytest.mark.filterwarnings("ignore::hairbed.ModelValidityWarning")
