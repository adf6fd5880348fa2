"""hairbed against PyElastica on one pillar step response (issue 30), in one run.

The pillar: a clamped, upright, slender rod (L = 1, E I = 1, zeta_perp = 1, so T = 1) of mass
per unit length mu = 13 (the PDMS pillar in water: it rings), under an isotropic resistive
drag (gamma = 1) in a uniform flow whose speed rises smoothly from 0 to Lambda = 2 over one T,
Lambda(t) = 1 - cos(pi t) for t < 1 (and 2 after): the distributed load f = Lambda(t) e_x -
r_t per unit length. The tip deflection x1 at t = 0.5, 1, 1.5 and 2 T.

- **hairbed**: ``simulate_pillar(..., profile=U = 1, gamma=1, mu=13)``, the inextensible
  Kirchhoff rod of theory.md §14; the reference is N = 16, rtol 1e-10 (N = 32 agrees to
  1e-10).
- **PyElastica** (``pyelastica``, a benchmark-only dependency: ``pip install -e .[bench]``):
  a Cosserat rod (extensible and shearable, Poisson ratio 0.5) of radius a = 0.01 L, clamped
  at the base (``OneEndFixedBC``), the drag and the flow load as a forcing on the nodes
  (weights of the nodes' lengths), the position Verlet stepper at a fixed step, a fraction
  0.25, 0.5 or 0.8 of the explicit limit of the axial and shear waves (dt ~ a^2 sqrt(mu)
  up to n = 40, ~ 1/n beyond; at 1.0 the run blows up). Each n is run at each fraction and
  PyElastica's time is that of its cheapest stable run (error within 10 % of the 0.25 run's:
  the error is the discretisation's in space, falling only like 1/n, 4.5e-3 at n = 20,
  2.1e-3 at n = 40, 1.0e-3 at n = 80, 5.1e-4 at n = 160, measured at t = 2 T). Its forcing
  two ways (:data:`FORCINGS`): PyElastica's documented ``NoForces`` subclass in numpy, and
  the same forcing as one numba kernel (15 to 20 % less CPU).
- The speed ratio is PyElastica's time at each n over hairbed's time at the cheapest
  setting tried whose error is at most PyElastica's there (target >= 1000x), by wall time
  and by CPU time (``time.process_time``: on a loaded machine PyElastica's one long run gets
  a fraction of a core while hairbed's best of twenty short calls gets a whole one, so only
  the CPU ratio is free of the load); PyElastica's first step (its numba compilation) and
  hairbed's first call are excluded. The load average is stored with the figures.

Measured (one quiet run, load 0.9 on 2 cores, benchmarks/results/bench_pyelastica.json), CPU
times: hairbed 0.16 ms at 1.5e-3 (N = 4, the least simulate_pillar takes, rtol 1), 0.18 ms at
7.8e-4 (N = 4, rtol 0.3), 0.19 ms at 4.8e-4 (N = 4, rtol 0.1), 0.21 ms at 1.7e-3 (N = 8, rtol
1), 63 ms at 2.9e-12 (N = 16, rtol 1e-8). At N = 4, rtol 1 the compiled run
(``pillar_run.run_radau``: the first step, Radau IIA, the outputs) is ~0.055 ms: 3 steps,
the first 0.2 T by Hairer, Norsett & Wanner's starting step (before: 1e-6, growing at most
5x a step, 11 steps at N = 8); the call's Python the rest, of which the callable drive
(sampled at 65 times at rtol 1, and its resolution check) and the callable profile's fit
(the user's functions) are 0.02 to 0.03 ms each in the call. PyElastica at its
cheapest stable step, numpy forcing / compiled forcing: 196 / 164 ms (n = 20, step 0.8),
222 / 190 ms (n = 40, 0.8), 591 / 517 ms (n = 80, 0.5; at 0.8 it blows up), 1019 / 920 ms
(n = 160, 0.8). The CPU-time ratio at PyElastica's accuracy: 1218x / 1022x (n = 20),
1385x / 1186x (n = 40), 3373x / 2949x (n = 80), 5325x / 4809x (n = 160): the target
>= 1000x holds at every n, by 2 % at n = 20 with the compiled forcing (the last session's
run: 485x / 406x at n = 20, 552x / 467x at n = 40, hairbed's cheapest 0.41 ms at N = 8).
Under load 13-14 the same code measured 1331x / 1120x at n = 20 (PyElastica's long runs
lose more to the load than hairbed's short calls, even in CPU time).

Run: ``python benchmarks/bench_pyelastica.py [--elements 20 40 80 160] [--json PATH]``. Without
pyelastica it prints one line and exits 0.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import sys
import time
from typing import Any

import numpy as np

from hairbed.dynamics import simulate_pillar

__all__ = ["main", "run"]

MU = 13.0  # the inertia number m E I/(zeta_perp^2 L^4)
LAMBDA = 2.0  # the flow's final speed (load per length) [E I/L^3]
RISE = 1.0  # the rise time [T]
RADIUS = 0.01  # PyElastica's radius [L] (hairbed's rod is inextensible: a -> 0)
TIMES = np.array([0.5, 1.0, 1.5, 2.0])  # [T]
#: hairbed settings tried, cheapest first: (N, rtol); N = 4 is the least simulate_pillar takes
SETTINGS = (
    (4, 1.0), (4, 3e-1), (4, 1e-1), (6, 1.0), (6, 1e-1), (8, 1.0), (8, 3e-1), (8, 1e-1),
    (8, 1e-2), (8, 1e-3), (8, 1e-4), (12, 1e-5), (16, 1e-6), (16, 1e-8),
)  # fmt: skip
#: PyElastica's forcing: "python", the NoForces subclass of numpy operations (PyElastica's
#: documented way to add a force), or "compiled", the same forcing in one numba kernel and the
#: drive by the math module (the fastest PyElastica this benchmark found)
FORCINGS = ("python", "compiled")
#: hairbed's calls per setting: the best CPU (and wall) time of these
REPEAT = 20
#: PyElastica's steps tried, as fractions of the explicit limit (:func:`_time_step`); the
#: cheapest stable one is PyElastica's time (at 1.0 the run blows up)
STEP_FRACTIONS = (0.25, 0.5, 0.8)
#: A run is stable where its error is within this factor of the most cautious step's
STABLE_ERROR_RATIO = 1.1


def drive(t: Any) -> Any:
    """Lambda(t) = (Lambda/2) (1 - cos(pi t/RISE)) until RISE, then Lambda."""
    tt = np.minimum(np.asarray(t, dtype=np.float64), RISE)
    return LAMBDA * 0.5 * (1.0 - np.cos(np.pi * tt / RISE))


def _uniform(z: Any) -> Any:
    return np.ones_like(z)


def hairbed_tip(num: int, rtol: float) -> np.ndarray:
    """hairbed's tip deflection at TIMES."""
    run = simulate_pillar(
        drive, np.concatenate([[0.0], TIMES]), profile=_uniform, gamma=1.0, mu=MU, num=num,
        rtol=rtol, atol=1e-2 * rtol,
    )  # fmt: skip
    if not run.success:
        raise RuntimeError(f"hairbed failed: {run.message}")
    return np.asarray(run.tip_deflection[1:])


def _scalar_drive(t: float) -> float:
    """:func:`drive` at one time, by the math module (PyElastica's forcing calls it each step)."""
    return LAMBDA * 0.5 * (1.0 - math.cos(math.pi * min(float(t), RISE) / RISE))


@functools.lru_cache(maxsize=1)
def _compiled_drag() -> Any:
    """The drag f = Lambda e_x - r_t on the nodes as one numba kernel (compiled on first use,
    within PyElastica's excluded first step)."""
    from numba import njit

    @njit(cache=False)  # type: ignore[misc]
    def drag(ext: Any, w: Any, vel: Any, lam: float) -> None:
        for k in range(w.size):
            ext[0, k] += w[k] * (lam - vel[0, k])
            ext[1, k] -= w[k] * vel[1, k]
            ext[2, k] -= w[k] * vel[2, k]

    return drag


def _elastica_rod(ea: Any, n: int, forcing: str = "python") -> tuple[Any, Any]:
    """A simulator with the clamped rod and the flow's drag (``forcing``: see
    :data:`FORCINGS`), finalised."""
    compiled = _compiled_drag() if forcing == "compiled" else None

    class Drag(ea.NoForces):
        """f = Lambda(t) e_x - r_t per unit length (zeta_perp = 1, isotropic), lumped."""

        def __init__(self, weights: np.ndarray) -> None:
            super().__init__()
            self.weights = weights

        def apply_forces(self, system: Any, time: float = 0.0) -> None:
            if compiled is not None:
                compiled(system.external_forces, self.weights, system.velocity_collection,
                         _scalar_drive(time))  # fmt: skip
                return
            system.external_forces[0] += self.weights * float(drive(time))
            system.external_forces -= self.weights * system.velocity_collection

    class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing):
        pass

    inertia = np.pi * RADIUS**4 / 4.0
    youngs = 1.0 / inertia  # E I = 1
    density = MU / (np.pi * RADIUS**2)  # rho A = mu
    sim = Simulator()
    rod = ea.CosseratRod.straight_rod(
        n, np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]), 1.0, RADIUS,
        density, youngs_modulus=youngs, shear_modulus=youngs / 3.0,
    )  # fmt: skip
    sim.append(rod)
    sim.constrain(rod).using(
        ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,)
    )
    weights = np.zeros(n + 1)
    weights[:-1] += 0.5 * rod.rest_lengths
    weights[1:] += 0.5 * rod.rest_lengths
    sim.add_forcing_to(rod).using(Drag, weights=weights)
    sim.finalize()
    return sim, rod


def _time_step(n: int, fraction: float = 0.25) -> float:
    """A ``fraction`` of the explicit limit, rounded to divide 0.5: the smaller of the axial
    wave's dx/c, c = 2/(a sqrt(mu)) [L/T], and the shear-rotation frequency's ~ 0.64/a^2."""
    limit = min((1.0 / n) * RADIUS * np.sqrt(MU) / 2.0, 2.0 / (4.0 / np.sqrt(3 * MU) / RADIUS**2))
    steps = int(np.ceil(0.5 / (fraction * limit)))
    return 0.5 / steps


def elastica_tip(
    ea: Any, n: int, forcing: str = "python", fraction: float = 0.25
) -> tuple[np.ndarray, float, int, float]:
    """PyElastica's tip deflection at TIMES, its time [s] (after the first step), the
    number of steps and its CPU time [s] (this process's, ``time.process_time``), at the
    step :func:`_time_step` (n, fraction)."""
    sim, rod = _elastica_rod(ea, n, forcing)
    stepper = ea.PositionVerlet()
    dt = _time_step(n, fraction)
    t = np.float64(0.0)
    t = stepper.step(sim, t, np.float64(dt))  # compiles
    p0 = time.process_time()
    c0 = time.perf_counter()
    out = []
    count = 1
    for target in TIMES:
        k = int(round((target - float(t)) / dt))
        for _ in range(k):
            t = stepper.step(sim, t, np.float64(dt))
        count += k
        out.append(float(rod.position_collection[0, -1]))
    return np.array(out), time.perf_counter() - c0, count, time.process_time() - p0


def run(elements: list[int]) -> dict[str, Any]:
    """Every figure of the comparison."""
    import elastica as ea

    reference = hairbed_tip(16, 1e-10)
    hb = []
    for num, rtol in SETTINGS:
        hairbed_tip(num, rtol)  # warm
        best, cpu = np.inf, np.inf
        for _ in range(REPEAT):
            p0 = time.process_time()
            c0 = time.perf_counter()
            tip = hairbed_tip(num, rtol)
            best = min(best, time.perf_counter() - c0)
            cpu = min(cpu, time.process_time() - p0)
        hb.append((num, rtol, best, float(np.max(np.abs(tip - reference))), cpu))
    pe = []
    for n in elements:
        for forcing in FORCINGS:
            runs = []
            for fraction in STEP_FRACTIONS:
                tip, seconds, count, cpu = elastica_tip(ea, n, forcing, fraction)
                runs.append(
                    (fraction, count, seconds, cpu, float(np.max(np.abs(tip - reference))))
                )
            # stable: the error of the most cautious step (its spatial error) within 10 %
            stable = [r for r in runs if r[4] <= STABLE_ERROR_RATIO * runs[0][4]]
            fraction, count, seconds, cpu, error = min(stable, key=lambda r: r[3])
            fits = [h for h in hb if h[3] <= error]
            ratio = seconds / min(h[2] for h in fits) if fits else float("nan")
            ratio_cpu = cpu / min(h[4] for h in fits) if fits else float("nan")
            pe.append((n, count, seconds, error, ratio, cpu, ratio_cpu, forcing, fraction, runs))
    finest = pe[-1]
    fits = [h for h in hb if h[3] <= finest[3]]
    chosen = min(fits, key=lambda h: h[2]) if fits else hb[-1]
    return {
        "reference_tip": reference.tolist(),
        "load_average": list(os.getloadavg()),
        "hairbed": [dict(zip(("num", "rtol", "seconds", "error", "cpu_seconds"), h)) for h in hb],
        "pyelastica": [
            dict(
                zip(
                    (
                        "elements",
                        "steps",
                        "seconds",
                        "error",
                        "ratio",
                        "cpu_seconds",
                        "ratio_cpu",
                        "forcing",
                        "step_fraction",
                        "runs (step fraction, steps, s, CPU s, error)",
                    ),  # fmt: skip
                    p,
                )
            )
            for p in pe
        ],
        "pyelastica_error": finest[3],
        "hairbed_at_that_accuracy": dict(
            zip(("num", "rtol", "seconds", "error", "cpu_seconds"), chosen)
        ),
        "speed_ratio": finest[2] / chosen[2],
        "speed_ratio_cpu": finest[5] / min(h[4] for h in fits) if fits else float("nan"),
        "least_ratio_cpu": min(p[6] for p in pe),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[20, 40, 80, 160])
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    try:
        import elastica  # noqa: F401
    except ImportError:
        print("bench_pyelastica: skipped, pyelastica is not installed (pip install -e .[bench])")
        return 0
    figs = run(sorted(args.elements))
    print(f"reference tip deflection at t = {TIMES.tolist()} T: {figs['reference_tip']}")
    print(f"load average (1, 5, 15 min) at the end: {figs['load_average']}")
    for h in figs["hairbed"]:
        print(
            f"hairbed    N = {h['num']:3d}, rtol {h['rtol']:.0e}: {1e3 * h['seconds']:9.3f} ms "
            f"(CPU {1e3 * h['cpu_seconds']:.3f} ms), error {h['error']:.1e}"
        )
    for p in figs["pyelastica"]:
        for fraction, count, seconds, cpu, error in p[
            "runs (step fraction, steps, s, CPU s, error)"
        ]:
            print(
                f"PyElastica n = {p['elements']:3d}, {p['forcing']:8s} forcing, step "
                f"{fraction:.2f} of the limit, {count:6d} steps: {1e3 * seconds:7.1f} ms (CPU "
                f"{1e3 * cpu:6.1f} ms), error {error:.1e}"
            )
        print(
            f"  the cheapest stable (step {p['step_fraction']:.2f}): hairbed at that accuracy "
            f"{p['ratio']:.0f}x faster (CPU time {p['ratio_cpu']:.0f}x)"
        )
    c = figs["hairbed_at_that_accuracy"]
    print(
        f"PyElastica's finest error {figs['pyelastica_error']:.1e}; hairbed at N = {c['num']}, "
        f"rtol {c['rtol']:.0e} ({c['error']:.1e}) is {figs['speed_ratio']:.0f}x faster "
        f"(CPU time {figs['speed_ratio_cpu']:.0f}x)"
    )
    print(
        f"the least CPU-time ratio over every row: {figs['least_ratio_cpu']:.0f}x "
        "[target >= 1000x]"
    )
    if args.json:
        import json

        with open(args.json, "w") as fh:
            json.dump(figs, fh, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
