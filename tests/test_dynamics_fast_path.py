"""simulate_pillar's scalar fast path: held to the full checks it skips (issue 30).

Plain numbers (floats, numpy float64s, bounded ints; ``num`` and ``max_steps`` ints) in range
skip the array checks of ``check_number``/``check_int``; a float64 ``t_eval`` skips
``as_float_array``; a plain drive level skips ``constant``'s checks. The reference is the
full checks themselves (the path every other input takes): the fast path must accept exactly
the plain inputs they accept, with the same values to the bit, and refuse (hand over to them)
everything else; a run through the fast path must be the run through the full path, bit for
bit, in every output.
"""

from __future__ import annotations

import math
import struct
from typing import Any

import numpy as np
import pytest

from hairbed.dynamics import constant, simulate_pillar
from hairbed.dynamics._integrate import _checked_call, _checked_times, _plain_call
from hairbed.dynamics._signals import as_signal

TE = np.array([0.0, 1.0])
HALF_PI = 0.5 * np.pi
#: candidate values per parameter: inside, on and beyond each bound, the non-finite, the
#: other plain types, and what the fast path must hand over (bools, strings, arrays, None)
EDGES = [0.0, -0.0, 0.5, 1.0, -1.0, 2, 0, 1, np.float64(0.25), math.nextafter(HALF_PI, 0.0),
         HALF_PI, -HALF_PI, 1.0 + 2.0**-52, 1e308, math.inf, -math.inf, math.nan, True,
         "0.5", np.array(0.5), None, 2**60, -(2**60)]  # fmt: skip
INTS = [8, 128, 7, 129, 32, 8.0, np.int64(16), True, 10**12, 10**12 + 1, 1, 0, -5, "8"]
_R = np.random.default_rng(1)
_U = [float(x) for x in _R.uniform(0.0, 1.0, len(EDGES))]
#: valid values of each of (theta0, gamma, mu, chi, num, rtol, atol, max_steps, jump_speed)
VALID: list[list[Any]] = [
    [float(x) for x in _R.uniform(-HALF_PI, HALF_PI, len(EDGES) - 1)]
    + [math.nextafter(-HALF_PI, 0.0)],
    [u or 1.0 for u in _U[:-1]] + [1.0],
    [1e3 * u for u in _U[:-1]] + [0],
    [u or 1.0 for u in _U[:-1]] + [1],
    [int(k) for k in _R.integers(8, 129, len(INTS))],
    [10.0 ** -(12 * u) for u in _U],
    [np.float64(10.0 ** -(12 * u)) for u in _U],
    [int(k) for k in _R.integers(1, 10**12 + 1, len(INTS))],
    [None if u < 0.3 else 10.0 * u for u in _U],
]


def _bits(x: float) -> bytes:
    return struct.pack("<d", x)


def _full(args: tuple[Any, ...]) -> Any:
    try:
        t0, g, m, opts = _checked_call(TE, *args)
    except (ValueError, TypeError):
        return "refused"
    return (t0, g, m, opts)


def _same(fast: Any, full: Any) -> bool:
    t0, g, m, o = fast
    u0, h, n, p = full
    floats = [(t0, u0), (g, h), (m, n), (o.chi, p.chi), (o.rtol, p.rtol), (o.atol, p.atol),
              (o.jump, p.jump)]  # fmt: skip
    return (
        all(type(a) is float and type(b) is float and _bits(a) == _bits(b) for a, b in floats)
        and (o.num, o.max_steps) == (p.num, p.max_steps)
        and type(o.num) is int
        and type(o.max_steps) is int
    )


def _plain(v: object) -> bool:
    return type(v) is float or type(v) is np.float64 or type(v) is int


def test_the_fast_path_accepts_and_refuses_as_the_full_checks() -> None:
    rng = np.random.default_rng(30)
    base = (0.1, 0.5, 0.0, 1.0, 32, 1e-6, 1e-9, 1000, None)
    combos: list[tuple[Any, ...]] = []
    for k in range(9):  # every candidate in each place, the others valid
        for v in INTS if k in (4, 7) else EDGES:
            args: list[Any] = list(base)
            args[k] = v
            combos.append(tuple(args))
    for _ in range(3000):  # and random mixtures of them with valid values
        mixed = [
            (EDGES if rng.random() < 0.15 else VALID[k])[rng.integers(len(EDGES))]
            if k not in (4, 7)
            else (INTS if rng.random() < 0.3 else VALID[k])[rng.integers(len(INTS))]
            for k in range(9)
        ]
        combos.append(tuple(mixed))
    accepted = refused_plain = 0
    for combo in combos:
        fast, full = _plain_call(*combo), _full(combo)
        plain = all(_plain(v) for k, v in enumerate(combo) if not (k == 8 and v is None))
        plain = plain and type(combo[4]) is int and type(combo[7]) is int
        if fast is not None:
            assert full != "refused", combo
            assert _same(fast, full), combo
            accepted += 1
        elif plain:  # a plain input the fast path hands over must be one the checks refuse
            assert full == "refused", combo
            refused_plain += 1
    assert accepted > 100 and refused_plain > 100  # both sides exercised


@pytest.mark.parametrize(
    "times",
    [[0.0, 1.0], [[0.0, 0.5], [1.0, 2.0]], [0.0, 0.0, 1.0], [1.0, 0.5], [0.0, np.nan],
     [np.inf], [], [3.0], [0.0, -0.0]],
)  # fmt: skip
def test_float_times_take_the_checks_values(times: list[Any]) -> None:
    arr = np.asarray(times, dtype=np.float64)
    try:
        full = _checked_times(list(np.asarray(times).reshape(-1)) if arr.size else times)
    except ValueError as exc:
        with pytest.raises(ValueError) as same:
            _checked_times(arr)
        assert str(same.value) == str(exc)
        return
    fast = _checked_times(arr)
    assert fast.dtype == np.float64 and fast.shape == full.shape
    assert fast.tobytes() == full.tobytes()
    assert not np.shares_memory(fast, arr)  # a copy, as the full path's


def test_a_plain_level_is_the_checked_constant() -> None:
    for v in (0.0, -0.0, 2, -3.5, np.float64(1e100), 2**60):
        sig, ref = as_signal(v, "forcing", 0.0, 1.0), constant(v)
        assert sig.kind == ref.kind and _bits(sig.params[0]) == _bits(ref.params[0])
    for v in (math.nan, math.inf, True):
        with pytest.raises((ValueError, TypeError), match="forcing"):
            as_signal(v, "forcing", 0.0, 1.0)


FIELDS = ("t", "forcing", "tip_load", "tip_deflection", "tip_height", "tip_angle",
          "base_moment", "s", "theta", "theta_t")  # fmt: skip


def test_fifty_runs_through_either_path_are_the_same_to_the_bit() -> None:
    rng = np.random.default_rng(7)
    profiles = ["sublayer", lambda z: 1.0 + 0.0 * z, lambda z: z * (1.0 - 0.3 * z)]
    for i in range(50):
        lam = float(rng.uniform(-20.0, 20.0))
        tip = float(rng.uniform(-2.0, 2.0)) if i % 3 == 0 else 0.0
        t0 = float(rng.uniform(-0.4, 0.6))
        g, mu = float(rng.uniform(0.3, 1.0)), float(rng.choice([0.0, 0.0, 2.0, 13.0]))
        num, rtol = int(rng.choice([8, 12, 16])), float(10.0 ** rng.uniform(-6.0, -1.0))
        te = np.sort(rng.uniform(0.0, 2.0, size=int(rng.integers(1, 6))))
        drive = (lambda t, c=lam: c * (1.0 - np.cos(np.pi * np.minimum(t, 1.0)))) if i % 2 else lam
        prof = profiles[i % 3]
        kw = dict(profile=prof, gamma=g, mu=mu, num=num, rtol=rtol, atol=1e-2 * rtol,
                  theta0=t0)  # fmt: skip
        fast = simulate_pillar(drive, te, tip_load=tip, **kw)  # type: ignore[arg-type]
        # the full path: 0-d arrays, a list of times and Signals are not plain scalars
        slow_kw = {k: (np.array(v) if k != "num" and not callable(v) and not isinstance(v, str)
                       else v) for k, v in kw.items()}  # fmt: skip
        slow_kw["num"] = float(num)
        slow = simulate_pillar(
            constant(lam) if not callable(drive) else drive,
            list(te),
            tip_load=constant(tip),
            **slow_kw,  # type: ignore[arg-type]
        )
        assert fast.status == slow.status and fast.t_end == slow.t_end, i
        assert (fast.nsteps, fast.nfev) == (slow.nsteps, slow.nfev), i
        for name in FIELDS:
            a, b = getattr(fast, name), getattr(slow, name)
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), (i, name)


def test_a_callables_sample_times_are_linspaces_and_its_own() -> None:
    from hairbed.dynamics import CALLABLE_SAMPLES

    def scribbler(t: np.ndarray) -> np.ndarray:
        out = np.sin(t)
        t[:] = 0.0  # writes to its argument
        return out

    for t0, t1 in ((0.0, 2.0), (-0.0, 2.0), (1e3, 1e3 + 0.5)):
        for _ in range(2):  # built, then taken from the cache
            sig = as_signal(scribbler, "forcing", t0, t1)
            ref = np.linspace(t0, t1, CALLABLE_SAMPLES)
            assert sig.times.tobytes() == ref.tobytes() and sig.times.flags.writeable
            assert sig.values.tobytes() == np.sin(ref).tobytes()
