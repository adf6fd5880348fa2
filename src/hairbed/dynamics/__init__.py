"""Pillar dynamics in time-dependent flow (issue 30, theory.md §14).

- :func:`linearise_pillar`: the linear dynamics about any static pillar state, its modes and
  its transfer functions (drive -> tip deflection, tip height, base moment).
- :func:`hydrodynamic_function` (Sader's Gamma of an oscillating cylinder) and
  :func:`sader_drag_ratio`: the optional frequency-dependent drag of the linear response.
- :func:`simulate_pillar`: the nonlinear pillar in time (compiled Radau IIA), driven by
  :func:`step`, :func:`ramp`, :func:`sine`, :func:`pulses`, :func:`sampled` or a callable;
  :func:`simulate_pillars` many pillars in one call, on threads.
- :func:`simulate_bed`: the porous bed in time (hairs and fluid, theory.md §15), on the same
  compiled Radau IIA; :func:`bed_operators` its semi-discrete system M y' = g(t, y)
  linearised about a steady state: mass vector, exact Jacobian, drives, outputs;
  :func:`simulate_beds` many beds in one call, on threads (a :class:`BedBatch`).
- :func:`snap_through`: a slow ramp through the upper fold of a pillar's snap-through window:
  the jump's delay, the states before and after, the ringing.
- :func:`periodic_bed`: the porous bed's periodic steady state under periodic drives, by
  collocation in time with Newton's method (theory.md §16); :func:`periodic_sensitivity` the
  periodic solution of its forced variational equation (dy/dp along the orbit);
  :func:`periodic_adjoint` the transposed problem for one output's period mean (its
  derivatives in every parameter for one solve).
- :func:`linearise_bed`: the porous bed's linear dynamics about any steady state, its modes
  and its transfer functions (wall speed, pressure or flow rate -> tip deflection, tip
  height, base moment, top wall's stress, flow rate).
"""

from __future__ import annotations

from ._bed import (
    BED_OUTPUTS,
    BED_STATUS,
    BedOperators,
    BedTrajectory,
    bed_operators,
    simulate_bed,
)
from ._bed_batch import BED_BATCH_STATUS, BedBatch, simulate_beds
from ._bed_linear import (
    BED_LINEAR_STATUS,
    BedFrequencyResponse,
    BedModes,
    LinearBed,
    linearise_bed,
)
from ._hydrodynamic import crossover_reynolds, hydrodynamic_function, sader_drag_ratio
from ._integrate import TRAJECTORY_STATUS, PillarTrajectory, simulate_pillar, simulate_pillars
from ._linear import (
    DRIVES,
    LINEAR_STATUS,
    OUTPUTS,
    FrequencyResponse,
    LinearPillar,
    PillarModes,
    linearise_pillar,
)
from ._periodic import (
    PERIODIC_ADJOINT_STATUS,
    PERIODIC_STATUS,
    PeriodicAdjoint,
    PeriodicBed,
    PeriodicSensitivity,
    periodic_adjoint,
    periodic_bed,
    periodic_sensitivity,
)
from ._signals import CALLABLE_SAMPLES, Signal, constant, pulses, ramp, sampled, sine, step
from ._snap import SNAP_STATUS, SnapThrough, snap_through
from ._validity import (
    ROTARY_INERTIA_LIMIT,
    SADER_WAVELENGTH_LIMIT,
    dynamics_validity,
    warn_dynamics_validity,
)

__all__ = [
    "BED_OUTPUTS",
    "BED_STATUS",
    "BedOperators",
    "BedTrajectory",
    "bed_operators",
    "simulate_bed",
    "BED_BATCH_STATUS",
    "BedBatch",
    "simulate_beds",
    "CALLABLE_SAMPLES",
    "PillarTrajectory",
    "Signal",
    "constant",
    "crossover_reynolds",
    "hydrodynamic_function",
    "sader_drag_ratio",
    "pulses",
    "ramp",
    "sampled",
    "simulate_pillar",
    "simulate_pillars",
    "SNAP_STATUS",
    "SnapThrough",
    "snap_through",
    "TRAJECTORY_STATUS",
    "sine",
    "step",
    "DRIVES",
    "LINEAR_STATUS",
    "OUTPUTS",
    "FrequencyResponse",
    "LinearPillar",
    "PillarModes",
    "linearise_pillar",
    "ROTARY_INERTIA_LIMIT",
    "SADER_WAVELENGTH_LIMIT",
    "dynamics_validity",
    "warn_dynamics_validity",
    "BED_LINEAR_STATUS",
    "BedFrequencyResponse",
    "BedModes",
    "LinearBed",
    "linearise_bed",
    "PERIODIC_STATUS",
    "PeriodicBed",
    "PeriodicSensitivity",
    "periodic_bed",
    "periodic_sensitivity",
    "PERIODIC_ADJOINT_STATUS",
    "PeriodicAdjoint",
    "periodic_adjoint",
]
