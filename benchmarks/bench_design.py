"""Cost of a design (issue 32), as times and ratios measured in one run.

Rows:

1. a three-variable constrained valve design: the largest diodicity at 1 kPa over
   (base_angle, length, spacing) with the resistance ratio at most 2.5 and the model's
   validity, 4 starts [s] (target <= 2 s);
2. a three-variable constrained pillar design: the largest tip deflection at 0.5 Pa over
   (length, radius, youngs_modulus) with a linear range (5 %) of at least 1 Pa, 4 starts [s]
   (target <= 2 s), with how many linear ranges were scanned and how many followed by
   Newton's method (:class:`hairbed.design._linear_range.LinearRangeTracker`), and the same
   design with every linear range scanned (``follow=False``: the cost without the tracker);
3. a 20-point Pareto front, diodicity against resistance ratio (epsilon-constraint) over
   (base_angle, length) [s] (target <= 30 s);
4. gradient cost: one quantity's value and exact gradient over the library's value alone
   (``hairbed.valve.diodicity``, ``Pillar.tip_deflection``; the linear range over its
   tracker's value, both by Newton's method from the pillar's own root) (target <= 3x);
   the sensitivity d(x1 L)/d(tau_w) over ``Pillar.sensitivity`` and the bandwidth over the
   pillar's state and its slowest mode (``linearise_pillar(...).modes(1)``): their gradients
   are second derivatives (jets, the eigenvalue's derivative); the resonance frequency
   over the state and its slowest mode with inertia; the porous bed's diodicity over
   ``valve_curve`` at +-dp; the rectified net flow (``net_flow``, a porous bed pumped
   at 2 kPa, omega T = 1) over its periodic state alone (``periodic_bed``; the gradient by
   the orbit's adjoint, ``periodic_adjoint``: one transposed solve for its six parameter
   columns, not one forward solve each); the snap-through window of a pillar tilted
   upstream, its folds followed from a neighbour (value and gradient) against the
   branch's scan [ms]; every other built-in quantity's value+gradient over the library's
   value alone (:data:`OTHERS`, :func:`_other_ratios`; the closed forms' values are
   attributes of a fraction of a microsecond, their ratios Python's call overhead);
5. the linear range's value: Newton's method from a neighbour's root (10 pillars 0.2 %
   apart in length, after the first's scan) against :meth:`Pillar.linear_range`'s scan [ms].

Each time is the least CPU time (``time.process_time``: free of the load of a shared machine)
of ``--repeat`` runs, the design's caches cleared before each, on one BLAS thread
(``OPENBLAS_NUM_THREADS=1`` unless set: threaded OpenBLAS's spinning threads count as CPU
time); the load average is stored with the figures.

Run: ``python benchmarks/bench_design.py [--repeat N] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import time
import warnings
from typing import Any

sys.path.insert(0, os.path.dirname(__file__))
# before numpy: one core is one. Threaded OpenBLAS spins its idle threads, which
# process_time counts: on a loaded machine the net flow's gradient ratio read 0.9 to 1.6
# threaded against a steady 1.83 to 1.88 on one thread (the Makefile's setting too)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from bench_common import report  # noqa: E402

from hairbed import HairBed, Pillar  # noqa: E402
from hairbed import design as D  # noqa: E402
from hairbed._bed_scales import _scales  # noqa: E402
from hairbed.branches import bistable_window  # noqa: E402
from hairbed.design import _objectives  # noqa: E402
from hairbed.design._linear_range import LinearRangeTracker  # noqa: E402
from hairbed.design._net_flow import pumped_orbit  # noqa: E402
from hairbed.design._objectives import _pillar_groups  # noqa: E402
from hairbed.design._pillar_window import WindowTracker  # noqa: E402
from hairbed.dynamics import linearise_pillar  # noqa: E402
from hairbed.valve import diodicity, valve_curve  # noqa: E402

__all__ = ["main", "run"]


def best(func: Any, repeat: int) -> tuple[float, Any]:
    """(the least CPU time of ``repeat`` runs [s], the result of the last run)."""
    least, out = math.inf, None
    for _ in range(repeat):
        c0 = time.process_time()
        out = func()
        least = min(least, time.process_time() - c0)
    return least, out


def _clear() -> None:
    _objectives._valve_gaps.cache_clear()
    _objectives._pillar_rows.cache_clear()
    _objectives._porous_flows.cache_clear()


def _models() -> tuple[HairBed, Pillar]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bed = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                      viscosity=1.0, spacing=250e-6, base_angle=0.5, density=1200.0)  # fmt: skip
        pillar = Pillar(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=0.1,
                        density=1000.0)  # fmt: skip
    return bed, pillar


#: The rows of :func:`_other_ratios`: (key, label).
OTHERS = (
    ("resistance_ratio", "resistance ratio (dense)"),
    ("porous_resistance_ratio", "porous resistance ratio"),
    ("gap_reynolds", "gap Reynolds number"),
    ("bistable_width", "bistable width"),
    ("brinkman_ratio", "Brinkman ratio (closed form)"),
    ("linear_sensitivity", "linear sensitivity (closed form)"),
    ("l_plus", "L+ (closed form)"),
    ("slenderness", "slenderness (closed form)"),
    ("pillar_reynolds", "pillar Reynolds number"),
    ("snap_window_scanned", "snap window, scanned"),
)


def _other_ratios(
    bed: HairBed,
    pillar: Pillar,
    porous: HairBed,
    snap: Pillar,
    gam_snap: float,
    ratio: Any,
    repeat: int,
) -> dict[str, tuple[float, float, float]]:
    """(value+gradient [s], value [s], their ratio) of the quantities of :data:`OTHERS`, each
    against the library's own value: a valve state at the one drop (``valve_curve``), the
    bistable window (``bistable_window``), the pillar's state (``deform``), the attributes
    of the closed forms (microseconds: the ratio there is Python's call overhead), the snap
    window's folds by a fresh scan (``WindowTracker.folds``) against a fresh quantity."""
    bi = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=1.05e-3,
                 viscosity=1.0, spacing=250e-6, base_angle=-1.0, density=1200.0)  # fmt: skip
    dense_drop = np.array([1000.0])
    q_rr, q_prr = D.resistance_ratio(1000.0, 0.01), D.resistance_ratio(300.0, 0.01)
    q_re, q_bi, q_br = D.gap_reynolds(1000.0, 0.01), D.bistable_width(), D.brinkman_ratio()
    q_ls, q_lp, q_sl = D.linear_sensitivity(), D.l_plus(0.5), D.slenderness()
    q_pr = D.pillar_reynolds(0.5)
    fast = 2000  # closed forms: microseconds a call
    return {
        "resistance_ratio": ratio(
            lambda: q_rr.evaluate(bed),
            lambda: valve_curve(bed, dense_drop, 0.01).resistance_ratio,
        ),
        "porous_resistance_ratio": ratio(
            lambda: q_prr.evaluate(porous),
            lambda: valve_curve(porous, np.array([300.0]), 0.01).resistance_ratio,
        ),
        "gap_reynolds": ratio(
            lambda: q_re.evaluate(bed), lambda: valve_curve(bed, dense_drop, 0.01).tip_height
        ),
        "bistable_width": ratio(
            lambda: q_bi.evaluate(bi), lambda: bistable_window(bi.eps, bi.base_angle)
        ),
        "brinkman_ratio": ratio(
            lambda: q_br.evaluate(bed), lambda: bed.brinkman_length / bed.length, n=fast
        ),
        "linear_sensitivity": ratio(
            lambda: q_ls.evaluate(pillar),
            lambda: pillar.length * pillar.linear_coefficient * pillar.forcing_per_stress,
            n=fast,
        ),
        "l_plus": ratio(
            lambda: q_lp.evaluate(pillar), lambda: pillar._l_plus(np.asarray(0.5)), n=fast
        ),
        "slenderness": ratio(lambda: q_sl.evaluate(pillar), lambda: pillar.slenderness, n=fast),
        "pillar_reynolds": ratio(
            lambda: q_pr.evaluate(pillar), lambda: pillar.deform(0.5).tip_height
        ),
        "snap_window_scanned": ratio(
            lambda: D.snap_window().evaluate(snap),
            lambda: WindowTracker(snap._core_profile, snap.height_ratio).folds(
                snap.base_angle, gam_snap
            ),
            n=1,
        ),
    }


def run(repeat: int = 3) -> dict[str, Any]:
    """Every row; a dict of the figures."""
    bed, pillar = _models()
    valve_vars = [
        D.Variable("base_angle", 0.0, 1.4),
        D.Variable("length", 0.6e-3, 1.5e-3),
        D.Variable("spacing", 200e-6, 400e-6),
    ]
    budget = D.resistance_ratio(1000.0, 0.01) <= 2.5

    def valve() -> D.DesignResult:
        _clear()
        return D.optimise(bed, valve_vars, D.diodicity(1000.0, 0.01), constraints=[budget],
                          sense="max", starts=4)  # fmt: skip

    pillar_vars = [
        D.Variable("length", 300e-6, 800e-6),
        D.Variable("radius", 20e-6, 30e-6),
        D.Variable("youngs_modulus", 0.5e6, 2e6, log=True),
    ]

    trackers: list[Any] = []

    def sensor(follow: bool = True) -> D.DesignResult:
        _clear()
        q = D.linear_range(0.05)  # a new quantity: nothing remembered from the last run
        q._tracker.follow = follow  # type: ignore[attr-defined]
        trackers.append(q._tracker)  # type: ignore[attr-defined]
        return D.optimise(pillar, pillar_vars, D.tip_deflection(0.5),
                          constraints=[q >= 1.0], sense="max", starts=4)  # fmt: skip

    def front() -> D.ParetoFront:
        _clear()
        return D.pareto_front(bed, valve_vars[:2], D.diodicity(1000.0, 0.01),
                              D.resistance_ratio(1000.0, 0.01), senses=("max", "min"),
                              points=20)  # fmt: skip

    t_valve, r_valve = best(valve, repeat)
    t_sensor, r_sensor = best(sensor, repeat)
    scans, newton = trackers[-1].scans, trackers[-1].newton
    t_scanned, r_scanned = best(lambda: sensor(follow=False), repeat)
    t_front, r_front = best(front, 1)

    def ratio(with_grad: Any, value_only: Any, n: int = 20) -> tuple[float, float, float]:
        def many_grad() -> None:
            for _ in range(n):
                _clear()
                with_grad()

        def many_value() -> None:
            for _ in range(n):
                value_only()

        tg, _ = best(many_grad, repeat)
        tv, _ = best(many_value, repeat)
        return tg / n, tv / n, tg / tv

    q_di, q_tip, q_lin = D.diodicity(1000.0, 0.01), D.tip_deflection(0.5), D.linear_range(0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        di = ratio(lambda: q_di.evaluate(bed), lambda: diodicity(bed, 1000.0, 0.01))
        tip = ratio(lambda: q_tip.evaluate(pillar), lambda: pillar.tip_deflection(0.5))
        q_sens, q_band = D.sensitivity(0.5), D.bandwidth(0.5)
        sens = ratio(lambda: q_sens.evaluate(pillar), lambda: pillar.sensitivity(0.5))

        def band_value() -> float:
            st = pillar.deform(0.5).solution
            lin = linearise_pillar(st, profile=pillar._core_profile)
            return float(lin.modes(1).eigenvalues[0].real)

        band = ratio(lambda: q_band.evaluate(pillar), band_value)
        q_res = D.resonance_frequency(0.5, 1000.0)
        light = dataclasses.replace(pillar, viscosity=1e-3)

        def res_value() -> float:
            zeta = light.normal_drag_coefficient
            t_scale = zeta * light.length**4 / light.bending_stiffness
            mu = (1000.0 + 1000.0) * math.pi * light.radius**2 / (zeta * t_scale)
            st = light.deform(0.5).solution
            lin = linearise_pillar(st, profile=light._core_profile, mu=mu, tangential_mass=0.5)
            return float(lin.modes(2).eigenvalues[0].imag)

        res = ratio(lambda: q_res.evaluate(light), res_value)
        porous = HairBed(length=1e-3, radius=50e-6, youngs_modulus=1e6, channel_height=2e-3,
                         viscosity=1.0, spacing=250e-6, base_angle=0.5,
                         model="porous")  # fmt: skip
        q_por = D.diodicity(300.0, 0.01)
        por = ratio(
            lambda: q_por.evaluate(porous),
            lambda: valve_curve(porous, np.array([300.0, -300.0]), 0.01).flow_rate,
        )
        # the rectified net flow: the periodic state alone against it and its gradient
        # (the orbit's adjoint: one transposed solve for the 6 forcing columns)
        q_nf = D.net_flow(2000.0, 0.022, 0.01)
        s_nf = _scales(porous, None)
        pia_nf = 2000.0 / 0.01 * s_nf.pi_per_gradient
        om_nf = 2.0 * math.pi * 0.022 * s_nf.time
        nflow = ratio(
            lambda: q_nf.evaluate(porous),
            lambda: float(np.mean(pumped_orbit(s_nf, pia_nf, om_nf).outputs["flow_rate"])),
            n=2,
        )
        snap = dataclasses.replace(light, base_angle=-1.4)
        tilts = [dataclasses.replace(snap, base_angle=-1.4 - 1e-3 * i) for i in range(1, 11)]

        def window_follow() -> None:
            q = D.snap_window()
            q.evaluate(snap)
            for p in tilts:
                q.evaluate(p)

        def window_scan() -> None:
            D.snap_window().evaluate(snap)

        t_wfollow, _ = best(window_follow, repeat)
        t_wscan, _ = best(window_scan, repeat)
        # every other built-in quantity: value+gradient over the library's value alone
        gam_snap = _pillar_groups(snap)[2]
        others = _other_ratios(bed, pillar, porous, snap, gam_snap, ratio, repeat)
        tracker = q_lin._tracker  # type: ignore[attr-defined]
        lin = ratio(
            lambda: q_lin._evaluate.__wrapped__(pillar, "spacing"),  # type: ignore[attr-defined]
            lambda: tracker(pillar),
            n=5,
        )
        # the value alone: Newton's method from a neighbour's root against the full scan
        near = [dataclasses.replace(pillar, length=pillar.length * (1.0 + 0.002 * i))
                for i in range(1, 11)]  # fmt: skip

        def follow() -> None:
            fresh = LinearRangeTracker(0.05)
            fresh(pillar)
            for p in near:
                fresh(p)

        def scan() -> None:
            pillar.linear_range(0.05)
            for p in near:
                p.linear_range(0.05)

        t_follow, _ = best(follow, repeat)
        t_scan, _ = best(scan, repeat)
    return {
        "load_average": list(os.getloadavg()),
        "valve_design_s": t_valve,
        "valve_design_success": r_valve.success,
        "valve_design_nfev": r_valve.nfev,
        "valve_design_objective": r_valve.objective,
        "sensor_design_s": t_sensor,
        "sensor_design_success": r_sensor.success,
        "sensor_design_nfev": r_sensor.nfev,
        "sensor_linear_range_scans": scans,
        "sensor_linear_range_newton": newton,
        "sensor_design_scanned_s": t_scanned,
        "sensor_design_speedup": t_scanned / t_sensor,
        "sensor_design_objective_difference": abs(r_sensor.objective / r_scanned.objective - 1),
        "pareto_20_s": t_front,
        "pareto_status": r_front.status,
        "diodicity_grad_ms": di[0] * 1e3,
        "diodicity_value_ms": di[1] * 1e3,
        "diodicity_ratio": di[2],
        "tip_grad_ms": tip[0] * 1e3,
        "tip_value_ms": tip[1] * 1e3,
        "tip_ratio": tip[2],
        "sensitivity_grad_ms": sens[0] * 1e3,
        "sensitivity_value_ms": sens[1] * 1e3,
        "sensitivity_ratio": sens[2],
        "bandwidth_grad_ms": band[0] * 1e3,
        "bandwidth_value_ms": band[1] * 1e3,
        "bandwidth_ratio": band[2],
        "resonance_grad_ms": res[0] * 1e3,
        "resonance_value_ms": res[1] * 1e3,
        "resonance_ratio": res[2],
        "porous_diodicity_grad_ms": por[0] * 1e3,
        "porous_diodicity_value_ms": por[1] * 1e3,
        "porous_diodicity_ratio": por[2],
        "net_flow_grad_ms": nflow[0] * 1e3,
        "net_flow_value_ms": nflow[1] * 1e3,
        "net_flow_ratio": nflow[2],
        "snap_window_followed_ms": (t_wfollow - t_wscan) / 10 * 1e3,
        "snap_window_scan_ms": t_wscan * 1e3,
        "linear_range_grad_ms": lin[0] * 1e3,
        "linear_range_value_ms": lin[1] * 1e3,
        "linear_range_ratio": lin[2],
        "linear_range_newton_ms": (t_follow - t_scan / 11) / 10 * 1e3,
        "linear_range_scan_ms": t_scan / 11 * 1e3,
        **{f"{k}_grad_ms": v[0] * 1e3 for k, v in others.items()},
        **{f"{k}_value_ms": v[1] * 1e3 for k, v in others.items()},
        **{f"{k}_ratio": v[2] for k, v in others.items()},
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    f = run(args.repeat)
    rows = [
        ("3-variable valve design, CPU [s] (target <= 2)",
         f"{f['valve_design_s']:.3f}  ({f['valve_design_nfev']} evaluations, "
         f"success {f['valve_design_success']})"),
        ("3-variable sensor design, CPU [s] (target <= 2)",
         f"{f['sensor_design_s']:.3f}  ({f['sensor_design_nfev']} evaluations, "
         f"success {f['sensor_design_success']}; linear ranges: "
         f"{f['sensor_linear_range_scans']} scanned, "
         f"{f['sensor_linear_range_newton']} by Newton)"),
        ("  the same, every linear range scanned [s]",
         f"{f['sensor_design_scanned_s']:.3f}  ({f['sensor_design_speedup']:.2f}x slower; "
         f"optima differ by {f['sensor_design_objective_difference']:.1e} relative)"),
        ("20-point Pareto front, CPU [s] (target <= 30)", f"{f['pareto_20_s']:.2f}"),
        ("diodicity: value+gradient / value (target <= 3)",
         f"{f['diodicity_ratio']:.2f}  ({f['diodicity_grad_ms']:.2f} / "
         f"{f['diodicity_value_ms']:.2f} ms)"),
        ("tip deflection: value+gradient / value",
         f"{f['tip_ratio']:.2f}  ({f['tip_grad_ms']:.2f} / {f['tip_value_ms']:.2f} ms)"),
        ("sensitivity: value+gradient / value (target <= 3)",
         f"{f['sensitivity_ratio']:.2f}  ({f['sensitivity_grad_ms']:.2f} / "
         f"{f['sensitivity_value_ms']:.2f} ms)"),
        ("bandwidth: value+gradient / value (target <= 3)",
         f"{f['bandwidth_ratio']:.2f}  ({f['bandwidth_grad_ms']:.2f} / "
         f"{f['bandwidth_value_ms']:.2f} ms)"),
        ("resonance frequency: value+gradient / value (target <= 3)",
         f"{f['resonance_ratio']:.2f}  ({f['resonance_grad_ms']:.2f} / "
         f"{f['resonance_value_ms']:.2f} ms)"),
        ("porous diodicity: value+gradient / value (target <= 3)",
         f"{f['porous_diodicity_ratio']:.2f}  ({f['porous_diodicity_grad_ms']:.2f} / "
         f"{f['porous_diodicity_value_ms']:.2f} ms)"),
        ("net flow: value+gradient / value (target <= 3)",
         f"{f['net_flow_ratio']:.2f}  ({f['net_flow_grad_ms']:.1f} / "
         f"{f['net_flow_value_ms']:.1f} ms)"),
        ("snap window: followed from a neighbour / scanned [ms]",
         f"{f['snap_window_followed_ms']:.1f} / {f['snap_window_scan_ms']:.1f}"),
        ("linear range: value+gradient / value",
         f"{f['linear_range_ratio']:.2f}  ({f['linear_range_grad_ms']:.1f} / "
         f"{f['linear_range_value_ms']:.1f} ms)"),
        *[(f"{label}: value+gradient / value (target <= 3)",
           f"{f[key + '_ratio']:.2f}  ({f[key + '_grad_ms']:.4g} / "
           f"{f[key + '_value_ms']:.4g} ms)") for key, label in OTHERS],
        ("linear range: Newton from a neighbour / full scan [ms]",
         f"{f['linear_range_newton_ms']:.1f} / {f['linear_range_scan_ms']:.1f}"),
        ("load average (1, 5, 15 min) at the end",
         " ".join(f"{x:.1f}" for x in f["load_average"])),
    ]  # fmt: skip
    report(rows, f, args.json)


if __name__ == "__main__":
    main()
