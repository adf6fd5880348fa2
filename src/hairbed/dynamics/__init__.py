"""Pillar dynamics in time-dependent flow (issue 30, theory.md §13).

- :func:`linearise_pillar`: the linear dynamics about any static pillar state, its modes and
  its transfer functions (drive -> tip deflection, tip height, base moment).
"""

from __future__ import annotations

from ._linear import (
    DRIVES,
    LINEAR_STATUS,
    OUTPUTS,
    FrequencyResponse,
    LinearPillar,
    PillarModes,
    linearise_pillar,
)

__all__ = [
    "DRIVES",
    "LINEAR_STATUS",
    "OUTPUTS",
    "FrequencyResponse",
    "LinearPillar",
    "PillarModes",
    "linearise_pillar",
]
