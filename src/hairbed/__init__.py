"""hairbed: exact deformation of a dense bed of elastic hairs in channel flow.

The numerical core (this package minus ``hairbed.plotting`` and ``hairbed.cli``) imports
numpy and scipy only.
"""

from .solution import Solution
from .solve import from_parameter, from_xi, solve, solve_all

__all__ = ["Solution", "from_parameter", "from_xi", "solve", "solve_all"]
__version__ = "0.1.0"
