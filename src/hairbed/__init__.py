"""hairbed: exact deformation of a dense bed of elastic hairs in channel flow.

The numerical core (everything here except ``hairbed.plotting`` and ``hairbed.cli``) imports
numpy and scipy only; ``hairbed.plotting`` needs matplotlib.
"""

# submodules build on the core and use hairbed.solve only at call time
from . import branches, inverse, quasistatic, rheology, stability
from .solution import Solution
from .solve import from_parameter, from_xi, solve, solve_all
from .units import HairBed, HairState

__all__ = [
    "HairBed",
    "HairState",
    "Solution",
    "branches",
    "from_parameter",
    "from_xi",
    "inverse",
    "quasistatic",
    "rheology",
    "solve",
    "solve_all",
    "stability",
]
__version__ = "0.1.0"
