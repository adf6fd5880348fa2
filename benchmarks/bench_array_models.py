"""Speed of design scans on array-valued models (issue 32 item 2): one call against a loop.

Rows (each the best of ``--repeat`` runs in one run, process CPU time beside the wall):

1. ``diodicity`` of a dense valve bed over 61 base angles at 1 kPa over 1 cm: one call on a
   ``HairBed(base_angle=array)`` against a Python loop over 61 scalar beds (each built and
   asked), the ratio of the two, and that the answers are bitwise the same;
2. the same for the porous bed (``model="porous"``, 21 angles);
3. ``Pillar.sensitivity`` at 1 Pa over 200 Young's moduli: one call against the loop;
4. building the array bed of row 1 (its conversions are computed element by element by the
   scalar bed's code) against building one scalar bed, per element;
5. ``Pillar.frequency_response`` of 20 pillars (Young's moduli 0.3 to 3 MPa, in water,
   Sader's drag, 50 frequencies, with the resonance, quality factor and bandwidth of each):
   one call on the array pillar against a Python loop over its ``item(i)``, and that the
   answers are bitwise the same. The linearisation is per pillar (each its own pencil), so
   the one call runs the elements one after the other: the ratio is the loop's overhead.

Run: ``python benchmarks/bench_array_models.py [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: one core is one

import argparse  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
from bench_common import best_cpu, report  # noqa: E402

import hairbed  # noqa: E402
from hairbed import HairBed, Pillar  # noqa: E402
from hairbed.valve import diodicity  # noqa: E402

__all__ = ["main", "run"]

BED = dict(
    length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3, viscosity=1.0,
    spacing=400e-6,
)  # fmt: skip
PILLAR = dict(length=500e-6, radius=25e-6, viscosity=1.0, density=1260.0)


def _valve(model: str, num: int, repeat: int) -> dict[str, Any]:
    angles = np.linspace(0.0, 1.5, num)

    def one_call() -> Any:
        return np.asarray(
            diodicity(HairBed(**BED, base_angle=angles, model=model), 1000.0, 0.01).diodicity
        )

    def loop() -> Any:
        return np.array(
            [
                diodicity(
                    HairBed(**BED, base_angle=float(a), model=model), [1000.0], 0.01
                ).diodicity[0]
                for a in angles
            ]
        )

    one_call(), loop()  # load the compiled kernels outside the timings
    t_one, c_one, a = best_cpu(one_call, repeat)
    t_loop, c_loop, b = best_cpu(loop, repeat)
    return {
        "num": num,
        "one_call_s": t_one,
        "one_call_cpu_s": c_one,
        "loop_s": t_loop,
        "loop_cpu_s": c_loop,
        "ratio": t_loop / t_one,
        "cpu_ratio": c_loop / c_one,
        "bitwise": bool(np.array_equal(a, b)),
        "best_angle": float(angles[int(np.argmax(a))]),
    }


def _frequency_response(repeat: int) -> dict[str, Any]:
    """Row 5: 20 pillars' frequency responses, one call against the loop over item(i)."""
    moduli = np.geomspace(3e5, 3e6, 20)
    freq = np.geomspace(1.0, 1e3, 50)
    pillar = Pillar(length=1e-3, radius=50e-6, youngs_modulus=moduli, fluid="water")
    kw = {"pillar_density": 970.0}

    def one_call() -> Any:
        r = pillar.frequency_response(freq, **kw)
        return np.concatenate([r.response.ravel().view(np.float64), r.bandwidth])

    def loop() -> Any:
        rows = [pillar.item(i).frequency_response(freq, **kw) for i in range(moduli.size)]
        return np.concatenate(
            [np.stack([r.response for r in rows]).ravel().view(np.float64),
             np.array([r.bandwidth for r in rows])]
        )  # fmt: skip

    one_call(), loop()
    t_one, c_one, a = best_cpu(one_call, repeat)
    t_loop, c_loop, b = best_cpu(loop, repeat)
    return {
        "num": moduli.size,
        "frequencies": freq.size,
        "one_call_s": t_one,
        "one_call_cpu_s": c_one,
        "loop_s": t_loop,
        "loop_cpu_s": c_loop,
        "ratio": t_loop / t_one,
        "cpu_ratio": c_loop / c_one,
        "bitwise": bool(np.array_equal(a, b)),
    }


def run(repeat: int = 3) -> tuple[list[tuple[str, str]], dict[str, Any]]:
    """The rows (name, shown value) and the figures."""
    figures: dict[str, Any] = {"hairbed": hairbed.__version__, "numpy": np.__version__}
    figures["load_average"] = os.getloadavg()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        figures["dense_valve"] = _valve("dense", 61, repeat)
        figures["porous_valve"] = _valve("porous", 21, repeat)
        moduli = np.geomspace(2e5, 5e6, 200)

        def pillars_one() -> Any:
            return np.asarray(Pillar(**PILLAR, youngs_modulus=moduli).sensitivity(1.0))

        def pillars_loop() -> Any:
            return np.array(
                [Pillar(**PILLAR, youngs_modulus=float(e)).sensitivity(1.0) for e in moduli]
            )

        pillars_one(), pillars_loop()
        t_one, c_one, a = best_cpu(pillars_one, repeat)
        t_loop, c_loop, b = best_cpu(pillars_loop, repeat)
        figures["pillar_sensitivity"] = {
            "num": moduli.size,
            "one_call_s": t_one,
            "one_call_cpu_s": c_one,
            "loop_s": t_loop,
            "loop_cpu_s": c_loop,
            "ratio": t_loop / t_one,
            "cpu_ratio": c_loop / c_one,
            "largest_rel_difference": float(np.max(np.abs(a / b - 1.0))),
        }
        figures["pillar_frequency_response"] = _frequency_response(repeat)
        angles = np.linspace(0.0, 1.5, 61)
        t_arr, _, _ = best_cpu(lambda: HairBed(**BED, base_angle=angles), repeat)
        t_one_bed, _, _ = best_cpu(lambda: HairBed(**BED, base_angle=0.3), repeat * 10)
        figures["build"] = {
            "array_bed_s": t_arr,
            "per_element_s": t_arr / angles.size,
            "scalar_bed_s": t_one_bed,
        }
    rows = []
    for name in ("dense_valve", "porous_valve", "pillar_sensitivity", "pillar_frequency_response"):
        r = figures[name]
        rows.append(
            (
                f"{name} ({r['num']})",
                f"one call {1e3 * r['one_call_s']:.1f} ms, loop {1e3 * r['loop_s']:.1f} ms, "
                f"loop/one {r['ratio']:.1f}x (CPU {r['cpu_ratio']:.1f}x)",
            )
        )
    b = figures["build"]
    rows.append(
        (
            "build (61 tilts)",
            f"{1e3 * b['array_bed_s']:.2f} ms ({1e6 * b['per_element_s']:.1f} us an "
            f"element; a scalar bed {1e6 * b['scalar_bed_s']:.1f} us)",
        )
    )
    rows.append(("load average", ", ".join(f"{x:.2f}" for x in figures["load_average"])))
    return rows, figures


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    rows, figures = run(args.repeat)
    report(rows, figures, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
