"""A hostile battery against the newer API (issue 33): the pump-driven bed, the valve, the
isolated pillar, their derivatives and calibration files; then this session's API (the
pillar's dynamics and the sensor's, ``hairbed.design``, the porous bed's branch and SI
workflows) and its command line (``hairbed design``, ``measure --pillar --series``,
``--model porous`` on invert/linear-range/calibrate/measure/``valve --states``,
``hairbed simulate``, ``hairbed response``, ``hairbed rheometer`` and ``hairbed pump``), run
in-process from a temporary directory.

Each call gets a valid set of arguments with one of them replaced by a hostile value (from a
catalogue of NaN, infinities, huge and tiny numbers, zeros, empty and 0-d arrays, wrong
dtypes and shapes, strings, None and objects) or by a value that is valid but at an edge
(a zero or negative drive, an empty array, a base angle next to the wall, ...). Each outcome
falls in one class:

* ``ok``: a result that says what it is, or a ValueError/TypeError naming the parameter;
* ``internal traceback``: any other exception, a ValueError/TypeError raised inside numpy or
  scipy or not naming the parameter, or a numpy/Python warning leaking out;
* ``bad input accepted``: NaN, an infinity, a complex number, a string or an object that
  is not a number given for a number, and a result came back;
* ``silent NaN``: a result with NaN where its status (or the lack of one) says it is fine;
* ``silent empty``: an empty list of states, or an empty result for a non-empty input,
  with no status that says why;
* ``valid input rejected``: an edge value that the documentation allows raised.

A command-line run is ``internal traceback`` when it raises or prints a traceback, a warning
or more than one line on stderr; ``bad input accepted`` when NaN, an infinity or a string
for a number exits 0; ``silent empty`` when it exits 0 with nothing on stdout; ``silent
NaN`` when stdout shows nan with nothing said on stderr.

Run ``python tools/hostile_battery.py [--json out.json] [--quick] [--new] [--no-cli]``
(``--new``: this session's API and the CLI only): it prints the count per class and each
finding, and exits 1 when any class but ``ok`` has a count.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import time
import traceback
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import hairbed
from hairbed import calibration, calibration_files, sensitivity, valve

CLASSES = (
    "ok",
    "internal traceback",
    "bad input accepted",
    "silent NaN",
    "silent empty",
    "valid input rejected",
)
OWN_WARNINGS = (hairbed.ModelValidityWarning, hairbed.UnitsWarning, hairbed.CalibrationWarning)


class _Opaque:
    def __repr__(self) -> str:
        return "<opaque>"


#: (class, value, must be refused): the hostile catalogue, tried on every argument.
HOSTILE: list[tuple[str, Any, bool]] = [
    ("nan", math.nan, True),
    ("nan", np.float64("nan"), True),
    ("nan", [0.5, math.nan], True),
    ("inf", math.inf, True),
    ("inf", -math.inf, True),
    ("inf", np.array([0.1, np.inf]), True),
    ("negative", -1.0, False),
    ("negative", -1e-300, False),
    ("negative", np.array([0.2, -0.5]), False),
    ("huge", 1e300, False),
    ("huge", 1.7e308, False),
    ("huge", 10**400, False),
    ("tiny", 5e-324, False),
    ("tiny", 1e-310, False),
    ("zero", 0, False),
    ("zero", -0.0, False),
    ("empty", np.array([]), False),
    ("empty", [], False),
    ("empty", np.empty((0, 3)), False),
    ("0-d", np.array(0.3), False),
    ("dtype", True, False),
    ("dtype", 0.5 + 1j, True),
    ("dtype", np.array([0.5 + 9j]), True),
    ("dtype", np.float16(0.5), False),
    ("dtype", np.array([0.5], dtype=object), False),
    ("dtype", np.array(["0.5"]), False),
    ("dtype", np.timedelta64(1, "s"), True),
    ("shape", [[0.1, 0.2], [0.3]], False),
    ("shape", np.full((2, 3), 0.4), False),
    ("shape", [[[0.5]]], False),
    ("string", "abc", True),
    ("string", "", True),
    ("string", "0.5", False),
    ("none", None, False),
    ("object", _Opaque(), True),
    ("object", {}, True),
    ("object", [0.5, "a"], True),
]


@dataclass
class Target:
    """One callable with valid arguments; ``edges`` holds valid values per argument that must
    be accepted; ``text`` names the arguments that are not numbers (strings, objects)."""

    name: str
    call: Callable[..., Any]
    args: dict[str, Any]
    fuzz: tuple[str, ...] = ()
    edges: dict[str, list[Any]] | None = None
    text: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.fuzz:
            self.fuzz = tuple(self.args)


BED_KW = dict(
    length=1e-3,
    radius=50e-6,
    youngs_modulus=1e6,
    channel_height=2e-3,
    viscosity=1.0,
    spacing=400e-6,
    base_angle=0.1,
)
PILLAR_KW = dict(length=500e-6, radius=25e-6, youngs_modulus=1e6, viscosity=1e-3, base_angle=0.1)


def _targets() -> list[Target]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bed = hairbed.HairBed(**BED_KW)
        pillar = hairbed.Pillar(**PILLAR_KW)
        tau = [1.0, 5.0, 20.0]
        pillar_d = pillar.tip_deflection(tau)
        pillar_fit = calibration.fit(pillar, pillar_d, wall_shear_stress=tau, sigma=1e-7)
        grads = [200.0, 1e3, 3e3]
        bed_d = [float(bed.deform(pressure_gradient=g).tip_deflection) for g in grads]
        bed_fit = calibration.fit(bed, bed_d, pressure_gradient=grads, sigma=1e-7)
        loaded = hairbed.solve_loaded([0.5, 1.0], 0.5, 0.1, pi=2.0)
        pil_state = hairbed.solve_pillar([2.0, 20.0], 0.2)
    return [
        Target(
            "solve_loaded",
            hairbed.solve_loaded,
            dict(omega2=0.5, eps=0.5, theta0=0.1, pi=2.0, root="low", num=None, rtol=1e-12),
            edges={
                "omega2": [0.0, -2.0, [0.0, 1e-12, 5.0], np.array([])],
                "eps": [0.0 + 1e-9, 0.99, [0.1, 0.9]],
                "theta0": [-1.5, 1.5, 0.0],
                "pi": [0.0, -3.0, 1e-300, [1.0, -1.0]],
                "root": ["mid", "high"],
                "num": [8, 512],
                "rtol": [1e-6, 1e-14],
            },
            text=("root",),
        ),
        Target(
            "solve_loaded[q]",
            hairbed.solve_loaded,
            dict(omega2=0.5, eps=0.5, theta0=0.1, q=2.0),
            edges={"q": [0.0, -2.0, [0.0, 1.0]], "omega2": [0.0, -1.0]},
        ),
        Target(
            "solve_loaded_all",
            hairbed.solve_loaded_all,
            dict(omega2=0.51, eps=0.95, theta0=-1.2, pi=0.0, num_scan=16, rtol=1e-12),
            edges={
                "omega2": [0.0, 1e-9, -0.5],
                "pi": [0.0, 1.0, -1.0, None],
                "theta0": [0.0, 1.2, -1.55],
                "num_scan": [8, 100],
            },
        ),
        Target(
            "continue_loaded",
            hairbed.continue_loaded,
            dict(omega2=0.0, eps=0.9, theta0=-1.2, q=0.005, stop=0.05, ds=0.05, max_steps=40),
            edges={"stop": [-0.05, 0.01], "omega2": [0.5]},
        ),
        Target(
            "derivatives[pi]",
            hairbed.derivatives,
            dict(omega2=0.5, eps=0.5, theta0=0.1, pi=2.0),
            edges={"omega2": [0.0, [0.0, 1.0], np.array([])], "pi": [0.0, -1.0]},
            fuzz=("omega2", "eps", "theta0", "pi"),
        ),
        Target(
            "derivatives[q]",
            hairbed.derivatives,
            dict(omega2=0.5, eps=0.5, theta0=0.1, q=1.0),
            edges={"q": [0.0, -1.0]},
            fuzz=("omega2", "eps", "q"),
        ),
        Target(
            "derivatives",
            hairbed.derivatives,
            dict(omega2=2.0, eps=0.5, theta0=0.1),
            edges={"omega2": [0.0, 1e-300, [0.0, 2.0]], "theta0": [-1.2, 1.5]},
            fuzz=("omega2", "eps", "theta0"),
        ),
        Target(
            "derivatives_at[loaded]",
            lambda sol: sensitivity.derivatives_at(sol),
            dict(sol=loaded),
            edges={"sol": [hairbed.solve_loaded(np.array([]), 0.5, pi=1.0)]},
        ),
        Target(
            "derivatives_at[pillar]",
            lambda sol: sensitivity.derivatives_at(sol),
            dict(sol=pil_state),
            edges={"sol": [hairbed.solve_pillar(np.array([])), hairbed.solve_pillar(0.0)]},
        ),
        Target(
            "solve_pillar",
            hairbed.solve_pillar,
            dict(
                forcing=5.0,
                theta0=0.1,
                profile="poiseuille",
                height_ratio=0.5,
                gamma=0.6,
                tip_load=0.0,
                root="low",
                num=None,
                rtol=1e-12,
            ),
            edges={
                "forcing": [0.0, -5.0, 1e-8, 1e5, [0.0, 1.0, -1.0], np.array([])],
                "theta0": [-1.4, 1.4, -1.5, -1.52, 0.0],
                "gamma": [1.0, 1e-3],
                "tip_load": [-1.0, 2.0],
                "height_ratio": [1.0, 1e-3],
                "root": ["mid", "high"],
                "num": [8, 512],
            },
            text=("profile", "root"),
        ),
        Target(
            "solve_pillar[callable]",
            hairbed.solve_pillar,
            dict(forcing=2.0, profile=lambda z: z * (1.0 - 0.3 * z)),
            edges={
                "profile": [lambda z: 0.0 * z, lambda z: np.sin(z), lambda z: 1.0 + 0.0 * z],
            },
            fuzz=("forcing", "profile"),
            text=("profile",),
        ),
        Target(
            "solve_pillar_inverse",
            hairbed.solve_pillar_inverse,
            dict(tip_deflection=0.3, theta0=0.1, profile="sublayer", gamma=0.6, tip_load=0.0),
            edges={
                "tip_deflection": [0.0999, -0.5, 0.99, [0.2, -0.2]],
                "theta0": [-1.3, 1.3],
            },
            text=("profile",),
        ),
        Target(
            "solve_pillar_all",
            hairbed.solve_pillar_all,
            dict(forcing=15.0, theta0=-1.4, gamma=0.5, num=16),
            edges={
                "forcing": [1e-6, -15.0, 1e4, 1e300],
                "theta0": [0.0, 1.4, -1.5],
                "num": [16, 400],
            },
        ),
        Target(
            "continue_pillar",
            hairbed.continue_pillar,
            dict(forcing_max=20.0, theta0=-1.4, gamma=0.5, num=16),
            edges={"forcing_max": [-20.0, 1e-6, 1e4], "theta0": [0.0, -1.5]},
        ),
        Target(
            "gray_hancock_ratio",
            hairbed.gray_hancock_ratio,
            dict(slenderness=20.0),
            edges={"slenderness": [math.exp(1.5) / 2.0, 1e300, [3.0, 30.0]]},
        ),
        Target(
            "Pillar",
            lambda **kw: hairbed.Pillar(**kw),
            dict(PILLAR_KW),
            edges={"base_angle": [-1.5, 0.0], "radius": [200e-6]},
        ),
        Target(
            "Pillar.deform",
            lambda wall_shear_stress: pillar.deform(wall_shear_stress),
            dict(wall_shear_stress=[1.0, 5.0]),
            edges={"wall_shear_stress": [0.0, -3.0, np.array([]), 1e-9]},
        ),
        Target(
            "Pillar.tip_deflection",
            lambda wall_shear_stress: pillar.tip_deflection(wall_shear_stress),
            dict(wall_shear_stress=2.0),
            edges={"wall_shear_stress": [0.0, -2.0]},
        ),
        Target(
            "Pillar.wall_shear_stress_from_tip_deflection",
            lambda tip_deflection: pillar.wall_shear_stress_from_tip_deflection(tip_deflection),
            dict(tip_deflection=float(pillar_d[1])),
            edges={"tip_deflection": [float(np.sin(0.1)) * 500e-6]},
        ),
        Target(
            "HairBed.deform[pressure_gradient]",
            lambda pressure_gradient, velocity: bed.deform(
                velocity, pressure_gradient=pressure_gradient
            ),
            dict(pressure_gradient=[200.0, 2e3], velocity=None),
            edges={
                "pressure_gradient": [0.0, -500.0, [0.0, 1e3], 1e-300],
                "velocity": [0.0, -0.01, 0.01],
            },
        ),
        Target(
            "HairBed.deform[flow_rate]",
            lambda flow_rate: bed.deform(flow_rate=flow_rate),
            dict(flow_rate=1e-6),
            edges={"flow_rate": [0.0, -1e-6, [0.0, 1e-7]]},
        ),
        Target(
            "HairBed.sweep[pressure_gradient]",
            lambda pressure_gradient: bed.sweep(pressure_gradient=pressure_gradient),
            dict(pressure_gradient=[100.0, 1e3]),
            edges={"pressure_gradient": [[0.0, 1e3], [-1e3, 0.0]]},
        ),
        Target(
            "valve.valve_curve",
            lambda pressure_drop, channel_length: valve.valve_curve(
                bed, pressure_drop, channel_length
            ),
            dict(pressure_drop=[20.0, 200.0], channel_length=0.01),
            edges={"pressure_drop": [0.0, [-200.0, 0.0, 200.0]], "channel_length": [1e-6, 10.0]},
        ),
        Target(
            "valve.diodicity",
            lambda pressure_drop, channel_length: valve.diodicity(
                bed, pressure_drop, channel_length
            ),
            dict(pressure_drop=200.0, channel_length=0.01),
            edges={"pressure_drop": [-200.0, [1.0, 200.0]]},
        ),
        Target(
            "valve.valve_states",
            lambda flow_rate, velocity, max_steps: valve.valve_states(
                bed, 0.01, flow_rate=flow_rate, velocity=velocity, max_steps=max_steps
            ),
            dict(flow_rate=[0.0, 2e-7], velocity=0.0, max_steps=40),
            edges={"flow_rate": [[-2e-7, 2e-7], [1e-7]], "velocity": [0.001, -0.001]},
        ),
        Target(
            "valve.valve_states[pressure_drop]",
            lambda pressure_drop: valve.valve_states(bed, 0.01, pressure_drop=pressure_drop),
            dict(pressure_drop=[0.0, 200.0]),
            edges={"pressure_drop": [[-200.0, 200.0], [50.0]]},
        ),
        Target(
            "calibration.fit[pillar]",
            lambda tip_deflection, wall_shear_stress, sigma, free: calibration.fit(
                pillar, tip_deflection, wall_shear_stress=wall_shear_stress, sigma=sigma, free=free
            ),
            dict(
                tip_deflection=pillar_d,
                wall_shear_stress=tau,
                sigma=1e-7,
                free=("youngs_modulus",),
            ),
            edges={
                "free": ["base_angle", ("youngs_modulus", "base_angle"), "drag_scale"],
                "sigma": [None, [1e-7, 2e-7, 3e-7]],
            },
            text=("free",),
        ),
        Target(
            "calibration.fit[pressure_gradient]",
            lambda tip_deflection, pressure_gradient, sigma: calibration.fit(
                bed, tip_deflection, pressure_gradient=pressure_gradient, sigma=sigma
            ),
            dict(tip_deflection=bed_d, pressure_gradient=grads, sigma=1e-7),
            edges={"sigma": [None]},
        ),
        Target(
            "calibration.measure[pillar]",
            lambda tip_deflection, sigma: calibration.measure(
                pillar, tip_deflection, sigma=sigma, fit=pillar_fit
            ),
            dict(tip_deflection=3e-5, sigma=1e-7),
            edges={"tip_deflection": [[1e-5, 3e-5], float(np.sin(0.1)) * 500e-6], "sigma": [0.0]},
        ),
        Target(
            "calibration.measure[pressure_gradient]",
            lambda tip_deflection: calibration.measure(bed, tip_deflection, fit=bed_fit),
            dict(tip_deflection=bed_d[1]),
        ),
        Target(
            "calibration_from_dict[pillar]",
            lambda data: calibration_files.calibration_from_dict(data),
            dict(data=calibration_files.calibration_to_dict(pillar_fit)),
            edges={
                "data": [
                    {**calibration_files.calibration_to_dict(pillar_fit), "geometry": "spacing"}
                ]
            },
            text=("data",),
        ),
        Target(
            "calibration_from_dict[bed]",
            lambda data: calibration_files.calibration_from_dict(data),
            dict(data=calibration_files.calibration_to_dict(bed_fit)),
            text=("data",),
        ),
    ]


def _new_targets() -> list[Target]:
    """This session's API: the dynamics, the sensor's dynamics, design, the porous bed."""
    from hairbed import design, dynamics, porous_curves, sensor_dynamics

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pillar = hairbed.Pillar(**PILLAR_KW, density=1000.0)
        state = hairbed.solve_pillar(2.0, 0.1)
        linear = dynamics.linearise_pillar(state)
        series = [float(d) for d in pillar.tip_deflection(1.0 + 0.1 * np.sin(np.arange(64) / 5))]
        response = pillar.frequency_response(
            [10.0, 100.0], wall_shear_stress=1.0, pillar_density=1000.0
        )
        dbed = hairbed.HairBed(**BED_KW, density=1000.0)
        var = design.Variable("length", 300e-6, 1e-3)
        porous = hairbed.HairBed(**BED_KW, model="porous")
        pv = [0.02, 0.05, 0.1]
        pd = [float(porous.deform(v).tip_deflection) for v in pv]
        pfit = calibration.fit(porous, pd, velocity=pv, sigma=1e-6)

    def quantity(factory: Callable[..., Any], model: Any) -> Callable[..., Any]:
        return lambda **kw: factory(**kw)(model)

    return [
        Target(
            "dynamics.linearise_pillar",
            lambda **kw: dynamics.linearise_pillar(**kw).modes(4),
            dict(state=state, mu=0.1, tangential_mass=1.0, height_ratio=None),
            edges={"mu": [0.0], "tangential_mass": [1e-3]},
        ),
        Target(
            "LinearPillar.modes",
            lambda **kw: linear.modes(**kw),
            dict(num_modes=4, num=16),
            edges={"num_modes": [1], "num": [None, 8]},
        ),
        Target(
            "LinearPillar.frequency_response",
            lambda **kw: linear.frequency_response(**kw),
            dict(omega=[0.1, 1.0], drive="forcing", num=16),
            edges={"omega": [0.0, [0.0, 1e3]], "drive": ["tip_load"]},
            text=("drive",),
        ),
        Target(
            "dynamics.simulate_pillar",
            dynamics.simulate_pillar,
            dict(forcing=2.0, t_eval=[0.0, 0.05], theta0=0.1, mu=0.0, num=8, max_steps=2000),
            edges={
                "forcing": [0.0, -2.0, dynamics.step(2.0), lambda t: 2.0],
                "t_eval": [[0.0], [0.0, 1e-9]],
                "mu": [0.1],
                "theta0": [-1.2],
            },
        ),
        Target(
            "dynamics.simulate_pillars",
            dynamics.simulate_pillars,
            dict(forcing=[1.0, 2.0], t_eval=[0.0, 0.05], theta0=0.1, num=8, max_steps=2000),
            edges={"forcing": [[1.0]], "theta0": [[0.1, 0.2]]},
        ),
        Target("dynamics.step", dynamics.step, dict(after=1.0, before=0.0, at=0.1)),
        Target("dynamics.ramp", dynamics.ramp, dict(start=0.0, end=1.0, t_start=0.0, t_end=1.0)),
        Target("dynamics.sine", dynamics.sine, dict(mean=1.0, amplitude=0.5, omega=2.0)),
        Target(
            "dynamics.pulses",
            dynamics.pulses,
            dict(base=0.0, height=1.0, period=1.0, width=0.2, start=0.0),
        ),
        Target(
            "dynamics.sampled",
            dynamics.sampled,
            dict(times=[0.0, 1.0, 2.0], values=[0.0, 1.0, 0.5]),
            edges={"times": [[0.0, 1.0, 5.0]]},
        ),
        Target(
            "dynamics.hydrodynamic_function",
            dynamics.hydrodynamic_function,
            dict(reynolds=[1.0, 10.0]),
            edges={"reynolds": [1e-6, 1e6]},
        ),
        Target(
            "dynamics.sader_drag_ratio",
            dynamics.sader_drag_ratio,
            dict(omega=[1.0, 2.0], reynolds_scale=10.0, slenderness=20.0),
            edges={"omega": [0.0]},
        ),
        Target(
            "dynamics.dynamics_validity",
            dynamics.dynamics_validity,
            dict(omega=[1.0], mu=0.1, reynolds_scale=10.0, slenderness=20.0),
            edges={"mu": [0.0], "omega": [[0.0]]},
        ),
        Target(
            "Pillar.frequency_response",
            lambda **kw: pillar.frequency_response(**kw),
            dict(frequency=[10.0, 100.0], wall_shear_stress=1.0, pillar_density=1000.0),
            edges={"frequency": [0.0, [0.0, 1e3]], "wall_shear_stress": [0.0, -1.0]},
        ),
        Target(
            "SensorResponse.at",
            lambda **kw: response.at(**kw),
            dict(frequency=[5.0, 50.0]),
            edges={"frequency": [0.0]},
        ),
        Target(
            "Pillar.wall_shear_stress_from_tip_deflection_series",
            lambda **kw: pillar.wall_shear_stress_from_tip_deflection_series(**kw),
            dict(tip_deflection=series, sample_rate=1000.0, pillar_density=1000.0),
            edges={"noise_sigma": [0.0, 1e-8]},
        ),
        Target(
            "sensor_dynamics.simulate",
            lambda **kw: sensor_dynamics.simulate(pillar, **kw),
            dict(wall_shear_stress=1.0, t=[0.0, 1e-3], overdamped=True, num=8, max_steps=2000),
            edges={"wall_shear_stress": [0.0, -1.0, dynamics.step(1.0)], "t": [[0.0]]},
        ),
        Target(
            "Pillar.simulate",
            lambda **kw: pillar.simulate(**kw),
            dict(wall_shear_stress=1.0, t=[0.0, 1e-4, 1e-3], pillar_density=1000.0, num=8),
        ),
        Target(
            "design.Variable",
            design.Variable,
            dict(name="length", low=1e-4, high=1e-3, log=True),
            fuzz=("low", "high", "log"),  # any name is a Variable's: Space checks it
        ),
        Target(
            "design.optimise",
            design.optimise,
            dict(
                base=pillar,
                variables=var,
                objective=design.slenderness(),
                sense="max",
                starts=1,
                validity=False,
                maxiter=10,
            ),
            edges={"starts": [1, 3], "x0": [{"length": 5e-4}]},
            text=("sense",),
        ),
        Target(
            "design.pareto_front",
            design.pareto_front,
            dict(
                base=pillar,
                variables=var,
                first=design.slenderness(),
                second=design.linear_sensitivity(),
                points=3,
                starts=1,
                validity=False,
            ),
            edges={"points": [2]},
        ),
        Target(
            "design.diodicity",
            quantity(design.diodicity, dbed),
            dict(pressure_drop=100.0, channel_length=0.01),
        ),
        Target(
            "design.resistance_ratio",
            quantity(design.resistance_ratio, dbed),
            dict(pressure_drop=100.0, channel_length=0.01),
            edges={"pressure_drop": [-100.0]},
        ),
        Target(
            "design.tip_deflection",
            quantity(design.tip_deflection, pillar),
            dict(wall_shear_stress=1.0),
            edges={"wall_shear_stress": [1e-3, 50.0]},
        ),
        Target(
            "design.bandwidth", quantity(design.bandwidth, pillar), dict(wall_shear_stress=1.0)
        ),
        Target("design.linear_range", quantity(design.linear_range, pillar), dict(rtol=0.1)),
        Target(
            "porous_curves.porous_branch",
            porous_curves.porous_branch,
            dict(eps=0.5, theta0=0.1, kappa=0.1, gamma=1.0, x1_max=0.9, num=8),
            edges={"eps": [0.0], "theta0": [-1.2], "gamma": [1.0]},
        ),
        Target(
            "HairBed.deform[porous]",
            lambda **kw: porous.deform(**kw),
            dict(velocity=0.01, pressure_gradient=500.0),
            edges={"pressure_gradient": [0.0, -500.0], "velocity": [0.0, -0.01]},
        ),
        Target(
            "HairBed.deform[porous flow_rate]",
            lambda **kw: porous.deform(**kw),
            dict(flow_rate=1e-6),
            edges={"flow_rate": [0.0, -1e-6]},
        ),
        Target(
            "calibration.fit[porous]",
            lambda **kw: calibration.fit(porous, **kw),
            dict(tip_deflection=pd, velocity=pv, sigma=1e-6),
            edges={"sigma": [None]},
        ),
        Target(
            "calibration.measure[porous]",
            lambda **kw: calibration.measure(porous, fit=pfit, **kw),
            dict(tip_deflection=pd[1], sigma=1e-6),
            edges={"sigma": [0.0], "tip_deflection": [[pd[0], pd[2]]]},
        ),
        Target(
            "valve.valve_states[porous]",
            lambda **kw: valve.valve_states(porous, 0.01, **kw),
            dict(flow_rate=[0.0, 2e-7], max_steps=40),
            edges={"flow_rate": [[-2e-7, 2e-7]]},
        ),
        Target(
            "valve.valve_curve[porous]",
            lambda **kw: valve.valve_curve(porous, **kw),
            dict(pressure_drop=[10.0, 100.0], channel_length=0.01),
            edges={"pressure_drop": [0.0, [-100.0, 100.0]]},
        ),
        *_later_targets(pillar),
        *_periodic_targets(),
        *_fifth_targets(),
    ]


def _later_targets(pillar: Any) -> list[Target]:
    """Added later this session: the porous bed in time (and linearised), the rheometer
    (LAOS's analysis, small-amplitude shear), the sensor's sweeps over stress, amplitude and
    frequency, the resonance as a quantity, the valve's switching and a pump's net flow."""
    from hairbed import design, dynamics, sweeps, valve_dynamics
    from hairbed.rheometer import (
        analyse_laos,
        bed_moduli,
        large_amplitude_shear,
        oscillatory_shear,
    )

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        state = hairbed.solve_porous(2.0, 0.5, 0.1, kappa=0.1)
        phase = np.arange(64) * 2.0 * np.pi / 64.0
        strain = 0.5 * np.sin(phase)
        stress = 2.0 * strain + 0.3 * strain**3 + 0.75 * np.cos(phase)
        laos = analyse_laos(phase, strain, stress)
        bed = hairbed.HairBed(**BED_KW, density=1000.0)

    def resonance(**kw: Any) -> Any:
        return design.resonance_frequency(**kw)(pillar)

    return [
        Target(
            "dynamics.simulate_bed",
            lambda **kw: dynamics.simulate_bed(**kw),
            dict(
                theta0=0.0,
                kappa=0.1,
                eps=0.5,
                t_eval=[0.0, 0.05],
                wall=1.0,
                inertia=0.0,
                womersley=0.0,
                num=8,
                num_gap=4,
                max_steps=500,
            ),
            edges={
                "wall": [0.0, -1.0, dynamics.step(1.0)],
                "theta0": [-1.2, 1.2],
                "inertia": [0.1],
                "womersley": [1.0],
                "t_eval": [[0.0]],
            },
        ),
        Target(
            "dynamics.bed_operators",
            lambda **kw: dynamics.bed_operators(**kw),
            dict(state=state, inertia=0.1, womersley=0.0, num=8, num_gap=4),
            edges={"inertia": [0.0], "womersley": [2.0]},
        ),
        Target(
            "rheometer.analyse_laos",
            lambda **kw: analyse_laos(**kw),
            dict(time=phase, strain=strain, stress=stress, periods=1, num_harmonics=None),
            edges={"num_harmonics": [1, 31], "stress": [0.0 * stress + 1.0]},
        ),
        Target(
            "LAOSAnalysis.stress",
            lambda theta: laos.stress(theta),
            dict(theta=[0.0, 1.0]),
            edges={"theta": [0.0, -1e6, np.array([])]},
        ),
        Target(
            "sweeps.response_sweep",
            lambda **kw: sweeps.response_sweep(pillar, **kw),
            dict(
                frequency=[10.0, 100.0],
                wall_shear_stress=[0.0, 1.0],
                pillar_density=1000.0,
                drag="quasi-steady",
            ),
            edges={"frequency": [0.0, [0.0, 1e3]], "wall_shear_stress": [-1.0], "drag": ["sader"]},
            text=("drag",),
        ),
        Target(
            "sweeps.amplitude_sweep",
            lambda **kw: sweeps.amplitude_sweep(pillar, **kw),
            dict(
                amplitude=[0.1],
                frequency=[10.0],
                wall_shear_stress=1.0,
                pillar_density=1000.0,
                periods=2,
                num=8,
            ),
            fuzz=("amplitude", "frequency", "wall_shear_stress", "periods"),
            edges={"amplitude": [[0.1, 0.5]], "wall_shear_stress": [0.0]},
        ),
        Target(
            "design.resonance_frequency",
            resonance,
            dict(wall_shear_stress=1.0, pillar_density=1000.0),
            edges={"wall_shear_stress": [0.0, 10.0], "pillar_density": [2000.0]},
        ),
        Target(
            "dynamics.linearise_bed",
            lambda **kw: dynamics.linearise_bed(**kw).modes(2, num=8, num_gap=4),
            dict(state=state, inertia=0.1, womersley=0.0),
            edges={"inertia": [0.0], "womersley": [2.0]},
        ),
        Target(
            "rheometer.oscillatory_shear",
            lambda **kw: oscillatory_shear(**kw),
            dict(omega=1.0, forcing=0.0, eps=0.5, kappa=1.0, inertia=0.0, womersley=0.0),
            edges={"omega": [[0.1, 10.0]], "forcing": [1.0], "inertia": [0.5]},
        ),
        Target(
            "rheometer.large_amplitude_shear",
            lambda **kw: large_amplitude_shear(**kw),
            dict(omega=1.0, strain_amplitude=0.5, eps=0.5, kappa=1.0, samples=16, max_periods=20),
            fuzz=("omega", "strain_amplitude", "eps", "kappa"),
        ),
        Target(
            "rheometer.bed_moduli",
            lambda **kw: bed_moduli(bed, **kw),
            dict(frequency=[1.0, 10.0], speed=0.0, hair_density=None),
            edges={"speed": [0.01], "hair_density": [1000.0], "frequency": [1e-3]},
        ),
        Target(
            "valve_dynamics.valve_switching",
            lambda **kw: valve_dynamics.valve_switching(bed, **kw),
            dict(pressure_drop=100.0, channel_length=0.01, num_times=11),
            fuzz=("pressure_drop", "channel_length", "num_times"),
            edges={"pressure_drop": [-100.0]},
        ),
        Target(
            "valve_dynamics.pump_net_flow",
            lambda **kw: valve_dynamics.pump_net_flow(bed, **kw),
            dict(
                amplitude=100.0,
                frequency=1.0,
                channel_length=0.01,
                samples_per_period=16,
                max_periods=20,
            ),
            fuzz=("amplitude", "frequency", "channel_length"),
        ),
    ]


def _periodic_targets() -> list[Target]:
    """Added in the fourth round: the bed's periodic state by collocation and its
    sensitivity, batches of beds in time, the rheometer's LAOS in SI, array-valued SI
    models (issue 32)."""
    from hairbed import design, dynamics
    from hairbed.rheometer import bed_laos, bed_pipkin_map

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wall = dynamics.sine(0.0, 1.0, 1.0)
        orbit = dynamics.periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall, num=8, tol=1e-6)
        ones = np.ones(orbit.y.shape)
        bed = hairbed.HairBed(**BED_KW, density=1000.0)
        beds = hairbed.HairBed(**{**BED_KW, "base_angle": [0.0, 0.2]})
        pillars = hairbed.Pillar(**{**PILLAR_KW, "youngs_modulus": [1e6, 2e6]})

    return [
        Target(
            "dynamics.periodic_bed",
            lambda **kw: dynamics.periodic_bed(**kw),
            dict(
                theta0=0.0,
                kappa=1.0,
                eps=0.5,
                omega=1.0,
                wall=wall,
                pressure=None,
                gamma=1.0,
                inertia=0.0,
                tangential_mass=1.0,
                womersley=0.0,
                num=8,
                num_gap=4,
                tol=1e-6,
                harmonics=4,
                max_harmonics=64,
                max_iterations=30,
            ),  # fmt: skip
            edges={
                "wall": [0.0, 1.0, dynamics.sine(0.5, 1.0, 2.0), dynamics.sine(0.0, 0.2, 3.0)],
                "pressure": [0.0, dynamics.sine(0.0, 0.5, 1.0)],
                "theta0": [-1.2, 1.2],
                "inertia": [0.1],
                "womersley": [1.0],
                "harmonics": [2],
                "tol": [1e-3, 1e-13],
                "max_harmonics": [4],
                "kappa": [1e-6, 1e6],
            },
        ),
        Target(
            "dynamics.periodic_sensitivity",
            lambda **kw: dynamics.periodic_sensitivity(**kw),
            dict(orbit=orbit, forcing=ones),
            edges={
                "forcing": [
                    np.zeros(orbit.y.shape),
                    ones[:, :, None].repeat(2, 2),
                    lambda t, y: np.ones_like(y),
                ],
            },  # fmt: skip
        ),
        Target(
            "PeriodicBed.states_at",
            lambda **kw: orbit.states_at(**kw),
            dict(t=[0.0, 1.0]),
            edges={"t": [0.0, -1e6, np.array([])]},
        ),  # fmt: skip
        Target(
            "PeriodicBed.outputs_at",
            lambda **kw: orbit.outputs_at(**kw),
            dict(t=[0.0, 1.0]),
            edges={"t": [0.0, 1e6]},
        ),  # fmt: skip
        Target(
            "PeriodicBed.mean",
            lambda **kw: orbit.mean(**kw),
            dict(output="tip_deflection"),
            edges={"output": ["wall_stress"]},
            text=("output",),
        ),  # fmt: skip
        Target(
            "dynamics.simulate_beds",
            lambda **kw: dynamics.simulate_beds(**kw),
            dict(
                theta0=0.0,
                kappa=[0.1, 1.0],
                eps=0.5,
                t_eval=[0.0, 0.05],
                wall=1.0,
                gamma=1.0,
                inertia=0.0,
                womersley=0.0,
                num=8,
                num_gap=4,
                max_steps=500,
                workers=1,
            ),  # fmt: skip
            edges={
                "theta0": [[0.0, 0.2], -1.2],
                "kappa": [1.0, [1e-6, 1e6]],
                "wall": [0.0, [1.0, 2.0], [dynamics.step(1.0), 0.5], dynamics.step(1.0)],
                "inertia": [[0.0, 0.1]],
                "womersley": [[0.0, 1.0]],
                "workers": [2],
                "t_eval": [[0.0]],
            },
        ),
        *(
            [
                Target(
                    "design.net_flow",  # the Quantity only: an evaluation takes tens of s
                    lambda **kw: design.net_flow(**kw),
                    dict(pressure_amplitude=100.0, frequency=1.0, channel_length=0.01),
                    edges={"hair_density": [1000.0], "pressure_amplitude": [1e-3]},
                )
            ]
            if hasattr(design, "net_flow")
            else []
        ),
        Target(
            "dynamics.simulate_pillar[exponential]",
            lambda **kw: dynamics.simulate_pillar(**kw),
            dict(
                forcing=2.0, t_eval=[0.0, 0.05], theta0=0.1, mu=0.1, num=8, method="exponential"
            ),  # fmt: skip
            fuzz=("method", "forcing", "t_eval", "mu", "theta0", "rtol", "jump_speed"),
            edges={
                "forcing": [0.0, -2.0, dynamics.step(2.0), dynamics.sine(1.0, 0.5, 3.0)],
                "mu": [0.0, 10.0],
                "t_eval": [[0.0], [0.0, 1e-9]],
                "theta0": [-1.2],
                "rtol": [1e-4],
            },
            text=("method",),
        ),
        Target(
            "rheometer.bed_laos",
            lambda **kw: bed_laos(bed, **kw),
            dict(frequency=1.0, strain_amplitude=0.1, speed=0.0, samples=16, max_periods=20),
            fuzz=("frequency", "strain_amplitude", "speed", "samples"),
            edges={"speed": [1e-4, -1e-4], "strain_amplitude": [1e-6]},
        ),
        Target(
            "rheometer.bed_pipkin_map",
            lambda **kw: bed_pipkin_map(bed, **kw),
            dict(frequencies=[1.0], strain_amplitudes=[0.1], samples=16, max_periods=20),
            fuzz=("frequencies", "strain_amplitudes", "workers"),
            edges={"frequencies": [1.0], "strain_amplitudes": [0.1]},
        ),
        Target(
            "HairBed[array]",
            lambda **kw: hairbed.HairBed(**kw),
            dict(BED_KW, base_angle=[0.0, 0.2]),
            edges={
                "base_angle": [[[0.0], [0.2]], np.array([0.1])],
                "youngs_modulus": [[1e6, 2e6]],
                "spacing": [[300e-6, 400e-6]],
            },
        ),
        Target(
            "HairBed[array].deform",
            lambda **kw: beds.deform(**kw),
            dict(velocity=[0.05, 0.1]),
            edges={"velocity": [0.1, [[0.05], [0.1]], 0.0]},
        ),
        Target(
            "HairBed[array].deform[pressure_gradient]",
            lambda **kw: beds.deform(**kw),
            dict(velocity=0.01, pressure_gradient=500.0),
            edges={"pressure_gradient": [[0.0, -500.0]]},
        ),
        Target(
            "valve.valve_curve[array]",
            lambda **kw: valve.valve_curve(beds, **kw),
            dict(pressure_drop=100.0, channel_length=0.01),
            edges={"pressure_drop": [[-100.0, 100.0]]},
        ),
        *(
            Target(
                f"HairBed[array].{meth}",
                lambda _m=meth, **kw: getattr(beds, _m)(**kw),
                {arg: value},
                edges={arg: [[value, 2.0 * value], 0.0, [[value], [2.0 * value]]]},
            )
            for meth, arg, value in (
                ("linear_velocity_from_tip_deflection", "deflection", 3e-4),
                ("linear_wall_shear_stress_from_tip_deflection", "deflection", 3e-4),
                ("velocity_from_wall_shear_stress", "wall_shear_stress", 1.0),
            )
        ),
        Target(
            "Pillar[array]",
            lambda **kw: hairbed.Pillar(**kw),
            dict(PILLAR_KW, youngs_modulus=[1e6, 2e6]),
            edges={"length": [[400e-6, 500e-6]], "base_angle": [[0.0, 0.1]]},
        ),
        Target(
            "Pillar[array].tip_deflection",
            lambda **kw: pillars.tip_deflection(**kw),
            dict(wall_shear_stress=1.0),
            edges={"wall_shear_stress": [[1.0, 2.0], 0.0, [[1.0], [2.0]]]},
        ),
        Target(
            "Pillar[array].wall_shear_stress_from_tip_deflection",
            lambda **kw: pillars.wall_shear_stress_from_tip_deflection(**kw),
            dict(tip_deflection=3e-5),
            edges={"tip_deflection": [[3e-5, 1e-5], 0.0]},
        ),
    ]


def _fifth_targets() -> list[Target]:
    """Added in the fifth round: the bed in time in SI (``HairBed.simulate``), the valve's
    time scales and pump sweep, and the dynamic SI methods of array models where they
    exist (issue 32 item 2)."""
    from hairbed import dynamics, valve_dynamics

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bed = hairbed.HairBed(**BED_KW, density=1000.0)
        pillars = hairbed.Pillar(**{**PILLAR_KW, "youngs_modulus": [1e6, 2e6]}, density=1000.0)
        beds = hairbed.HairBed(**{**BED_KW, "base_angle": [0.0, 0.2]})
    targets = [
        Target(
            "HairBed.simulate",
            lambda **kw: bed.simulate(**kw),
            dict(times=[0.0, 1.0, 2.0], velocity=0.05, num=8, num_gap=4, max_steps=2000),
            fuzz=("times", "velocity", "pressure_gradient", "hair_density", "num", "rtol"),
            edges={
                "velocity": [0.0, -0.05, dynamics.step(0.05), dynamics.sine(0.0, 0.02, 2.0)],
                "pressure_gradient": [500.0, -500.0],
                "hair_density": [1000.0],
                "times": [[0.0]],
            },
        ),
        Target(
            "valve_dynamics.bed_time_scales",
            lambda **kw: valve_dynamics.bed_time_scales(bed, **kw),
            dict(hair_density=1000.0),
            edges={"hair_density": [None]},
        ),
        Target(
            "valve_dynamics.pump_sweep",
            lambda **kw: valve_dynamics.pump_sweep(bed, **kw),
            dict(
                amplitude=[100.0],
                frequency=[1.0],
                channel_length=0.01,
                samples_per_period=16,
                max_periods=20,
            ),
            fuzz=("amplitude", "frequency", "channel_length"),
            edges={"amplitude": [[50.0, 100.0]]},
        ),
        Target(
            "HairBed[array].simulate",
            lambda **kw: beds.simulate(**kw),
            dict(times=[0.0, 1.0], velocity=0.05, num=8, num_gap=4, max_steps=2000),
            fuzz=("times", "velocity", "workers"),
            edges={"workers": [2]},
        ),
        Target(
            "Pillar[array].frequency_response",
            lambda **kw: pillars.frequency_response(**kw),
            dict(frequency=[10.0, 100.0], wall_shear_stress=1.0, pillar_density=1000.0),
        ),
        Target(
            "Pillar[array].simulate",
            lambda **kw: pillars.simulate(**kw),
            dict(wall_shear_stress=1.0, t=[0.0, 1e-4, 1e-3], pillar_density=1000.0, num=8),
            fuzz=("wall_shear_stress", "t", "pillar_density"),
        ),
    ]
    if hasattr(dynamics, "periodic_adjoint"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            wall = dynamics.sine(0.0, 1.0, 1.0)
            orbit = dynamics.periodic_bed(0.0, 1.0, 0.5, omega=1.0, wall=wall, num=8, tol=1e-6)
            adjoint = dynamics.periodic_adjoint(orbit)
        targets += [
            Target(
                "dynamics.periodic_adjoint",
                lambda **kw: dynamics.periodic_adjoint(**kw),
                dict(orbit=orbit, output="flow_rate"),
                edges={"output": ["wall_stress", "tip_deflection"]},
                text=("output", "orbit"),
            ),
            Target(
                "PeriodicAdjoint.mean_derivative",
                lambda **kw: adjoint.mean_derivative(**kw),
                dict(forcing=np.ones(orbit.y.shape)),
                edges={"forcing": [np.zeros(orbit.y.shape)]},
            ),
        ]
    return targets


# -- the command line ---------------------------------------------------------------------------

_BED_ARGS = [
    "--length=1e-3",
    "--radius=50e-6",
    "--youngs-modulus=1e6",
    "--channel-height=2e-3",
    "--viscosity=1",
    "--spacing=400e-6",
]
_PILLAR_ARGS = [
    "--length=500e-6",
    "--radius=25e-6",
    "--youngs-modulus=1e6",
    "--fluid=water",
    "--base-angle=0.1",
]
_SERIES = "series.csv"
_DESIGN = "design.toml"
_DESIGN_TEXT = """[model]
kind = "pillar"
length = 500e-6
radius = 25e-6
youngs_modulus = 1e6
viscosity = 1e-3
base_angle = 0.1

[[variables]]
name = "length"
low = {low}
high = {high}

[objective]
quantity = "slenderness"
sense = "max"

[options]
starts = {starts}
validity = false
"""
#: name -> (valid argv, options to fuzz, edge values: [(option, value)] that must be taken)
CLI_COMMANDS: dict[str, tuple[list[str], tuple[str, ...], list[tuple[str, str]]]] = {
    "measure --pillar --series": (
        [
            "measure",
            "--pillar",
            f"--series={_SERIES}",
            "--sample-rate=1000",
            "--pillar-density=1000",
            "--sigma=0",
            *_PILLAR_ARGS,
        ],
        ("--sample-rate", "--pillar-density", "--sigma", "--series"),
        [("--sigma", "1e-8"), ("--series-drag", "quasi-steady")],
    ),  # fmt: skip
    "invert --model porous": (
        ["invert", "--tip-deflection=3e-4", "--model=porous", *_BED_ARGS],
        ("--tip-deflection", "--model", "--drag", "--spacing"),
        [("--drag", "sparse")],
    ),
    "linear-range --model porous": (
        ["linear-range", "--rtol=0.05", "--model=porous", *_BED_ARGS],
        ("--rtol", "--model", "--drag"),
        [],
    ),
    "calibrate --model porous": (
        ["calibrate", "--data=points.csv", "--sigma=1e-6", "--model=porous", *_BED_ARGS],
        ("--sigma", "--model", "--free"),
        [],
    ),  # fmt: skip
    "measure --model porous": (
        ["measure", "--tip-deflection=3e-4", "--sigma=1e-6", "--model=porous", *_BED_ARGS],
        ("--tip-deflection", "--sigma", "--model"),
        [("--sigma", "0")],
    ),
    "valve --states --model porous": (
        [
            "valve",
            "--states",
            "--flow-rate=0,2e-7",
            "--channel-length=0.01",
            "--max-steps=40",
            "--model=porous",
            *_BED_ARGS,
        ],
        ("--flow-rate", "--channel-length", "--max-steps", "--model"),
        [("--flow-rate", "-2e-7,2e-7")],
    ),  # fmt: skip
    "simulate": (
        [
            "simulate",
            "--wall-shear-stress=1",
            "--t-end=1e-3",
            "--samples=5",
            "--pillar-density=1000",
            "--num=8",
            *_PILLAR_ARGS,
        ],
        (
            "--wall-shear-stress",
            "--frequency",
            "--amplitude",
            "--t-end",
            "--samples",
            "--pillar-density",
            "--num",
            "--rtol",
        ),
        [("--wall-shear-stress", "0"), ("--wall-shear-stress", "-1"), ("--samples", "2")],
    ),  # fmt: skip
    "response": (
        [
            "response",
            "--frequencies=1:1000:5",
            "--wall-shear-stress=1",
            "--pillar-density=1000",
            *_PILLAR_ARGS,
        ],
        (
            "--frequencies",
            "--wall-shear-stress",
            "--pillar-density",
            "--magnitude-tolerance",
            "--phase-tolerance",
        ),
        [("--frequencies", "0,10"), ("--wall-shear-stress", "0")],
    ),  # fmt: skip
    "response --mean-stresses": (
        [
            "response",
            "--frequencies=10,100",
            "--mean-stresses=0:2:3",
            "--pillar-density=1000",
            *_PILLAR_ARGS,
        ],
        ("--mean-stresses", "--frequencies", "--chunks"),
        [("--mean-stresses", "-1,0,1"), ("--chunks", "2")],
    ),  # fmt: skip
    "response --amplitudes": (
        [
            "response",
            "--frequencies=10",
            "--amplitudes=0.1",
            "--wall-shear-stress=1",
            "--drag-model=quasi-steady",
            "--pillar-density=1000",
            *_PILLAR_ARGS,
        ],
        ("--amplitudes", "--frequencies", "--wall-shear-stress"),
        [("--amplitudes", "0.1,0.2")],
    ),  # fmt: skip
    "rheometer": (
        ["rheometer", "--frequencies=1,10", "--density=1000", *_BED_ARGS],
        ("--frequencies", "--velocity", "--hair-density", "--density"),
        [("--velocity", "-0.01"), ("--velocity", "0")],
    ),
    "rheometer --laos": (
        ["rheometer", "--laos=0.1", "--frequencies=1", "--samples=16", *_BED_ARGS],
        ("--laos", "--frequencies", "--samples", "--velocity"),
        [("--velocity", "1e-4"), ("--velocity", "-1e-4"), ("--laos", "1e-6")],
    ),
    "rheometer --laos --pipkin": (
        [
            "rheometer",
            "--laos=0.1,0.2",
            "--pipkin",
            "--frequencies=1",
            "--samples=16",
            "--workers=1",
            *_BED_ARGS,
        ],
        ("--laos", "--frequencies", "--workers"),
        [("--workers", "2"), ("--laos", "0.1")],
    ),  # fmt: skip
    "pump --switch": (
        [
            "pump",
            "--switch=300",
            "--duration=1",
            "--num-times=5",
            "--channel-length=0.01",
            *_BED_ARGS,
        ],
        (
            "--switch",
            "--initial-pressure-drop",
            "--duration",
            "--num-times",
            "--channel-length",
            "--hair-density",
        ),
        [("--switch", "-300"), ("--switch", "0")],
    ),  # fmt: skip
    "pump --amplitudes": (
        [
            "pump",
            "--amplitudes=100",
            "--frequencies=1",
            "--samples-per-period=16",
            "--channel-length=0.01",
            *_BED_ARGS,
        ],
        ("--amplitudes", "--frequencies", "--samples-per-period"),
        [("--frequencies", "0.1,1")],
    ),  # fmt: skip
    "design": (
        ["design", _DESIGN],
        ("low", "high", "starts"),
        [("low", "1e-4")],
    ),
}
#: (class, command-line spelling, must be refused)
CLI_HOSTILE: list[tuple[str, str, bool]] = [
    ("nan", "nan", True),
    ("inf", "inf", True),
    ("inf", "-inf", True),
    ("inf", "1e400", True),
    ("negative", "-1", False),
    ("huge", "1e308", False),
    ("tiny", "5e-324", False),
    ("zero", "0", False),
    ("empty", "", True),
    ("string", "abc", True),
    ("string", "1,,2", True),
    ("string", "1j", True),
]


def _cli_files(where: str) -> None:
    """The inputs of the CLI battery: a series, calibration points, a design spec."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pillar = hairbed.Pillar(**{**PILLAR_KW, "viscosity": 1.0016e-3}, density=998.2)
        d = pillar.tip_deflection(1.0 + 0.1 * np.sin(np.arange(64) / 5))
        porous = hairbed.HairBed(**BED_KW, model="porous")
        bed_d = [float(porous.deform(v).tip_deflection) for v in (0.02, 0.05, 0.1)]
    with open(os.path.join(where, _SERIES), "w") as fh:
        fh.write("tip_deflection\n" + "".join(f"{float(x)!r}\n" for x in d))
    with open(os.path.join(where, "points.csv"), "w") as fh:
        fh.write("velocity,tip_deflection\n")
        fh.writelines(f"{v},{float(x)!r}\n" for v, x in zip((0.02, 0.05, 0.1), bed_d, strict=True))
    _design_file(where, {})


def _design_file(where: str, change: dict[str, str]) -> None:
    values = {"low": "300e-6", "high": "1e-3", "starts": "1", **change}
    with open(os.path.join(where, _DESIGN), "w") as fh:
        fh.write(_DESIGN_TEXT.format(**values))


def run_cli(argv: list[str], refuse: bool, edge: bool) -> tuple[str, str]:
    """The class of one in-process CLI run."""
    import contextlib
    import io

    from hairbed.cli import main as cli_main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        with warnings.catch_warnings():
            warnings.simplefilter("default")
            try:
                code = cli_main(argv)
            except SystemExit as exc:
                code = exc.code if isinstance(exc.code, int) else 1
            except Exception as exc:  # noqa: BLE001 - the finding
                return "internal traceback", f"{type(exc).__name__}: {exc}"
    text, lines = err.getvalue(), err.getvalue().splitlines()
    if "Traceback" in text or "Warning:" in text:
        return "internal traceback", f"stderr {text[-200:]!r}"
    lines = [line for line in lines if not line.startswith("hairbed: warning: ")]
    if code != 0:
        if len(lines) != 1:
            return "internal traceback", f"exit {code} with {len(lines)} stderr lines"
        return ("valid input rejected", lines[0]) if edge else ("ok", "")
    if refuse:
        return "bad input accepted", "exit 0"
    body = out.getvalue()
    if not body.strip() and "--out" not in " ".join(argv):
        return "silent empty", "exit 0 with nothing on stdout"
    if re.search(r"\bnan\b", body.lower()) and not text.strip():
        return "silent NaN", "nan on stdout with exit 0 and no word on stderr"
    return "ok", ""


def run_cli_battery(
    counts: Counter[str], findings: list[str], only: str | None, quick: bool
) -> dict[str, Counter[str]]:
    import tempfile

    per: dict[str, Counter[str]] = {}
    hostile = CLI_HOSTILE[:6] if quick else CLI_HOSTILE
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory() as where:
        _cli_files(where)
        os.chdir(where)
        try:
            for name, (base, options, edges) in CLI_COMMANDS.items():
                if only and not any(o in name for o in only.split(",")):
                    continue
                tally: Counter[str] = Counter()
                cases = [(o, c, v, r, False) for o in options for c, v, r in hostile]
                cases += [(o, "edge", v, False, True) for o, v in edges]
                for option, cls, value, refuse, edge in cases:
                    if name == "design":
                        _design_file(where, {option: value if value else "''"})
                        argv = list(base)
                        if option != "starts" and cls == "negative":
                            refuse = False
                    else:
                        argv = [a for a in base if not a.startswith(option + "=")]
                        argv.append(f"{option}={value}")
                    kind, why = run_cli(argv, refuse, edge)
                    counts[kind] += 1
                    tally[kind] += 1
                    if kind != "ok":
                        shown = f"{option}={value!r}"
                        findings.append(f"{kind}: hairbed {name} {shown} [{cls}]: {why}")
                _design_file(where, {})
                per["cli " + name] = tally
                print(f"cli {name}: {sum(tally.values())} calls {dict(tally)}", flush=True)
        finally:
            os.chdir(cwd)
    return per


def _hostile_documents(target: Target) -> list[tuple[str, Any, bool]]:
    """Hostile calibration documents: the valid one with one entry broken."""
    base = target.args["data"]
    out: list[tuple[str, Any, bool]] = []
    for key in list(base):
        for cls, bad in (("nan", math.nan), ("string", "abc"), ("none", None), ("object", [])):
            out.append((f"document {cls}", {**base, key: bad}, False))
        out.append(("document missing", {k: v for k, v in base.items() if k != key}, False))
    cov = np.asarray(base["covariance"], dtype=np.float64)
    out.append(
        ("document negative variance", {**base, "covariance": (-np.abs(cov)).tolist()}, True)
    )
    params = dict(base["parameters"])
    first = next(iter(params))
    broken = {**params, first: {**params[first], "stderr": -1.0}}
    out.append(("document negative stderr", {**base, "parameters": broken}, True))
    return out


# -- judging one outcome ------------------------------------------------------------------------

#: Value fields that must hold a number wherever a state's status is not negative.
STATE_FIELDS = {
    "LoadedState": ("tip_height", "tip_deflection", "tip_angle", "base_curvature"),
    "PillarState": ("tip_height", "tip_deflection", "tip_angle", "base_curvature", "drag_x"),
    "HairState": ("tip_deflection", "tip_height", "wall_shear_stress", "stress_ratio"),
    "PillarDeformation": ("tip_deflection", "tip_height", "drag", "base_moment"),
    "ValveCurve": ("flow_rate", "resistance_ratio", "tip_height"),
    "Diodicity": ("diodicity",),
    "Measurement": ("wall_shear_stress",),
    "PillarBranch": ("forcing", "tip_deflection"),
    "LoadedBranch": ("values", "tip_height"),
    "ValveStates": ("branch_tip_height",),
}


def _status_mask(obj: Any, shape: tuple[int, ...]) -> np.ndarray:
    status = getattr(obj, "status", None)
    if status is None and hasattr(obj, "solution"):
        status = getattr(obj.solution, "status", None)
    if status is None:
        return np.ones(shape, dtype=bool)
    try:
        return np.broadcast_to(np.asarray(status) >= 0, shape)
    except ValueError:
        return (
            np.ones(shape, dtype=bool)
            if np.all(np.asarray(status) >= 0)
            else np.zeros(shape, bool)
        )


def _judge_result(result: Any, empty_input: bool) -> tuple[str, str] | None:
    """("silent NaN" | "silent empty", why) of a returned result, or None."""
    if isinstance(result, list):
        if not result:
            return "silent empty", "an empty list"
        for item in result:
            found = _judge_result(item, empty_input)
            if found:
                return found
        return None
    name = type(result).__name__
    if name == "Derivatives":
        ok = np.asarray(result.status) == 0
        for out, row in result.table.items():
            for inp, v in row.items():
                a = np.asarray(v, dtype=np.float64)
                if np.any(np.isnan(a) & np.broadcast_to(ok, a.shape)):
                    return "silent NaN", f"d{out}/d{inp} NaN with status 0"
        for inp, v in result.dt.items():
            a = np.asarray(v, dtype=np.float64)
            if np.any(np.isnan(a) & np.broadcast_to(ok, a.shape)):
                return "silent NaN", f"dt/d{inp} NaN with status 0"
        return None
    if name == "CalibrationFit":
        if result.status >= 0:
            for k, v in result.values.items():
                if math.isnan(v) or math.isnan(result.stderr[k]):
                    return "silent NaN", f"{k} NaN with status {result.status}"
        return None
    if name in STATE_FIELDS:
        for f in STATE_FIELDS[name]:
            a = np.asarray(getattr(result, f), dtype=np.float64)
            if a.size == 0:
                if not empty_input and name in ("PillarBranch", "LoadedBranch", "ValveStates"):
                    if getattr(result, "status", 0) >= 0:
                        return "silent empty", f"{name}.{f} empty with status 0"
                continue
            if name in ("PillarBranch", "LoadedBranch", "ValveStates"):
                if getattr(result, "status", 0) == 0 and np.all(np.isnan(a)):
                    return "silent NaN", f"{name}.{f} all NaN with status 0"
                continue
            if name == "ValveStates":
                continue
            mask = _status_mask(result, a.shape)
            if np.any(np.isnan(a) & mask):
                return "silent NaN", f"{name}.{f} NaN where the status is not negative"
        if name == "ValveCurve":
            return _judge_result(result.states, empty_input)
        if name == "Diodicity":
            return _judge_result(result.forward, empty_input) or _judge_result(
                result.backward, empty_input
            )
        return None
    if isinstance(result, (float, np.floating, np.complexfloating, np.ndarray)):
        a = np.asarray(result)
        if a.dtype.kind in "fc" and np.any(np.isnan(a)):
            return "silent NaN", "a bare NaN"
    return None


def _inside_numpy(exc: BaseException) -> bool:
    """Whether the exception was raised in numpy's or scipy's own code."""
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return False
    last = frames[-1].filename.replace(os.sep, "/")
    return "/numpy/" in last or "/scipy/" in last


def _is_empty(value: Any) -> bool:
    try:
        return np.size(np.asarray(value, dtype=object)) == 0
    except Exception:  # noqa: BLE001 - ragged: not empty
        return False


def run_one(target: Target, param: str, value: Any, refuse: bool, edge: bool) -> tuple[str, str]:
    kwargs = dict(target.args)
    kwargs[param] = value
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with np.errstate(over="warn", invalid="warn", divide="warn", under="ignore"):
            try:
                result = target.call(**kwargs)
            except (ValueError, TypeError, ArithmeticError) as exc:
                if isinstance(exc, ArithmeticError) and (
                    isinstance(exc, OverflowError) or not target.name.startswith("design.")
                ):  # a design quantity's documented "no state there"; nothing else
                    return "internal traceback", f"{type(exc).__name__}: {exc}"
                message = str(exc)
                leaked = [w for w in caught if not issubclass(w.category, OWN_WARNINGS)]
                if _inside_numpy(exc):
                    return "internal traceback", f"{type(exc).__name__} inside numpy: {message}"
                if leaked:
                    return "internal traceback", f"leaked {leaked[0].category.__name__}"
                if param not in message and not (param == "sol" and "sol" in message):
                    return "internal traceback", f"does not name {param!r}: {message}"
                if edge:
                    return "valid input rejected", message
                return "ok", ""
            except Exception as exc:  # noqa: BLE001 - the finding
                return "internal traceback", f"{type(exc).__name__}: {exc}"
    leaked = [w for w in caught if not issubclass(w.category, OWN_WARNINGS)]
    if leaked:
        return "internal traceback", f"leaked {leaked[0].category.__name__}: {leaked[0].message}"
    if refuse:
        return "bad input accepted", f"returned {type(result).__name__}"
    judged = _judge_result(result, _is_empty(value))
    if judged:
        return judged
    return "ok", ""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", help="write the counts and findings to this file")
    parser.add_argument("--quick", action="store_true", help="the first 8 hostile values only")
    parser.add_argument(
        "--only", help="targets whose name contains this (a comma-separated list: any of them)"
    )
    parser.add_argument("--no-cli", action="store_true", help="the Python API only")
    parser.add_argument(
        "--new", action="store_true", help="this session's API only (dynamics, design, ...)"
    )
    args = parser.parse_args(argv)
    counts: Counter[str] = Counter()
    per_target: dict[str, Counter[str]] = {}
    findings: list[str] = []
    start = time.perf_counter()
    hostile = HOSTILE[:8] if args.quick else HOSTILE
    for target in [*([] if args.new else _targets()), *_new_targets()]:
        if args.only and not any(o in target.name for o in args.only.split(",")):
            continue
        tally: Counter[str] = Counter()
        for param in target.fuzz:
            cases = [(c, v, r, False) for c, v, r in hostile]
            if param == "data":
                cases += [(c, v, r, False) for c, v, r in _hostile_documents(target)]
            if param in target.text:  # not a number: refused, whatever it is
                cases = [(c, v, c in ("nan", "inf", "object") or r, e) for c, v, r, e in cases]
            cases += [("edge", v, False, True) for v in (target.edges or {}).get(param, [])]
            for cls, value, refuse, edge in cases:
                kind, why = run_one(target, param, value, refuse, edge)
                counts[kind] += 1
                tally[kind] += 1
                if kind != "ok":
                    shown = repr(value)
                    shown = shown if len(shown) < 70 else shown[:67] + "..."
                    findings.append(f"{kind}: {target.name}({param}={shown}) [{cls}]: {why}")
        per_target[target.name] = tally
        print(f"{target.name}: {sum(tally.values())} calls {dict(tally)}", flush=True)
    if not args.no_cli:
        per_target.update(run_cli_battery(counts, findings, args.only, args.quick))
    total = sum(counts.values())
    print(f"\n{total} calls in {time.perf_counter() - start:.0f} s")
    for cls in CLASSES:
        print(f"  {cls}: {counts[cls]}")
    for line in findings:
        print(line)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(
                {
                    "hairbed_version": hairbed.__version__,
                    "calls": total,
                    "counts": {c: counts[c] for c in CLASSES},
                    "per_target": {k: dict(v) for k, v in per_target.items()},
                    "findings": findings,
                },
                fh,
                indent=1,
            )
    return 1 if any(counts[c] for c in CLASSES[1:]) else 0


if __name__ == "__main__":
    sys.exit(main())
