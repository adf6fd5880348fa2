"""Speed of the exact solver, as ratios measured in one run (issue 2, item 6).

(a) time per solution of ``hairbed.solve`` on 1e6 random physical-branch parameter sets
    (omega2 log-uniform in [1e-3, 1e3], eps in [0, 0.95], theta0 in [0, 1.2]);
(b) time per element of one ``scipy.special.ellipkinc`` call on 1e6 elements;
the ratio a/b (target <= 5), and the median latency of one scalar ``solve`` call.

Run: ``python benchmarks/bench_solve.py [--size N]``. Timings are best-of-3 to damp the noise of
a shared machine; no timing is asserted anywhere in the tests.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import special

import hairbed


def best_of(fn, repeat: int = 3) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1_000_000)
    parser.add_argument("--scalar-calls", type=int, default=300)
    args = parser.parse_args()
    rng = np.random.default_rng(2026)
    n = args.size
    omega2 = 10.0 ** rng.uniform(-3.0, 3.0, n)
    eps = rng.uniform(0.0, 0.95, n)
    theta0 = rng.uniform(0.0, 1.2, n)
    phi = rng.uniform(0.0, 0.5 * np.pi, n)
    m = rng.uniform(0.0, 1.0, n)

    t_solve = best_of(lambda: hairbed.solve(omega2, eps, theta0)) / n
    t_ellip = best_of(lambda: special.ellipkinc(phi, m)) / n

    hairbed.solve(2.0, 0.5)
    lat = []
    for i in range(args.scalar_calls):
        start = time.perf_counter()
        hairbed.solve(omega2[i], eps[i], theta0[i])
        lat.append(time.perf_counter() - start)

    print(f"elements                      : {n}")
    print(f"(a) solve, per solution       : {t_solve * 1e9:9.0f} ns")
    print(f"(b) ellipkinc, per element    : {t_ellip * 1e9:9.0f} ns")
    print(f"ratio a/b                     : {t_solve / t_ellip:9.1f}   (target <= 5)")
    print(f"scalar solve, median latency  : {np.median(lat) * 1e6:9.0f} us (target <= 50 us)")


if __name__ == "__main__":
    main()
