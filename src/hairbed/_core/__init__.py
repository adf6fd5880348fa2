"""The exact core of hairbed: validation, compiled kernels and the result type.

Layers, each importing only from those before it:

* ``validation``: checks of the primary parameters (omega2, eps, theta0, branch, root);
* ``_jit`` and ``_kernels``: the numba kernels (elliptic integrals, Jacobi functions, the
  branch at its parameter, roots and folds, the closed-form shape);
* ``solution``: :class:`Solution`, the typed result that holds a state's values;
* ``solver``: the public wrappers (``solve``, ``solve_all``, ``from_parameter``,
  ``from_xi``, ``fold_parameters``): validate, call a kernel, build a ``Solution``;
* ``loaded``: ``solve_loaded`` and its ``LoadedState``, a tip load plus a load per unit
  height (the pressure and flow drives, issue 20) by Chebyshev collocation;
* ``arclength``: ``continue_loaded``, pseudo-arclength continuation of those states along a
  drive parameter, with the folds.

Nothing here imports the lab modules (units, inverse, branches, ...) or the outer rooms
(cli, plotting); ``tests/test_layering.py`` enforces this.
"""

from __future__ import annotations

from .arclength import LoadedBranch, continue_loaded
from .loaded import LoadedState, solve_loaded, solve_loaded_all
from .solution import Solution
from .solver import fold_parameters, from_parameter, from_xi, solve, solve_all

__all__ = [
    "LoadedBranch",
    "LoadedState",
    "continue_loaded",
    "Solution",
    "fold_parameters",
    "from_parameter",
    "from_xi",
    "solve",
    "solve_all",
    "solve_loaded",
    "solve_loaded_all",
]
