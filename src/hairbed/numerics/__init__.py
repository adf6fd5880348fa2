"""Numerical baselines for the hair problem: finite differences, shooting and collocation.

These are independent checks of the analytic solution (:func:`hairbed.solve`) and the paper's
point of comparison (its section on hair profiles). They solve one state per call: scalar
``omega2``, ``eps`` and ``theta0`` only (arrays raise ValueError). All return a
:class:`NumericalResult` whose ``sign`` and ``n`` are read off the converged shape, so a solver
that lands on a twirling branch says so; non-convergence is reported in the result, not raised.

:func:`pillar_method_of_lines` is the second-order finite-difference baseline of the pillar's
dynamics (:func:`hairbed.dynamics.simulate_pillar`, theory.md §14).
"""

from ._collocation import collocation
from ._finite_difference import finite_difference
from ._pillar_lines import PillarLinesResult, pillar_method_of_lines
from ._result import NumericalResult
from ._shooting import shooting

__all__ = [
    "NumericalResult",
    "PillarLinesResult",
    "collocation",
    "finite_difference",
    "pillar_method_of_lines",
    "shooting",
]
