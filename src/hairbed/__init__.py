"""hairbed: exact deformation of a dense bed of elastic hairs in channel flow.

The numerical core (everything here except ``hairbed.plotting`` and ``hairbed.cli``) needs
numpy, scipy and numba (its kernels); ``hairbed.plotting`` needs matplotlib.

Importing hairbed imports nothing heavy (not even numpy): every public name is imported on
first attribute access (PEP 562), the solver's (``Solution``, ``solve``, ``solve_all``,
``from_parameter``, ``from_xi``: numpy and the solver's wrappers, no compiled kernel, no
scipy) as well as the lab modules (``branches``, ``inverse``, ``quasistatic``, ``rheology``,
``stability``, ``numerics``, ``units``, ``sweeps``, ...) and the names ``HairBed``,
``HairState`` and ``sweep``. So a command imports only what it needs (``import hairbed``
imports neither xarray nor dask), and the ``hairbed`` command takes over Ctrl-C before numpy is
imported (``hairbed._command``: a one-line ``hairbed: interrupted`` from its first milliseconds).
"""

from __future__ import annotations

from ._version import __version__ as __version__

#: False at run time, true for type checkers (``typing.TYPE_CHECKING`` without importing
#: ``typing``, about 15 ms of the command's start-up before it can take over Ctrl-C).
TYPE_CHECKING = False
if TYPE_CHECKING:  # the lazy names, for type checkers and IDEs
    from typing import Any

    from . import (
        branches,
        calibration,
        calibration_files,
        design,
        inverse,
        numerics,
        pillars,
        profile_fit,
        quasistatic,
        rheology,
        rheometer,
        sensitivity,
        sensor_dynamics,
        stability,
        sweeps,
        units,
        valve,
    )
    from ._core.arclength import LoadedBranch, continue_loaded
    from ._core.loaded import LoadedState, solve_loaded, solve_loaded_all
    from ._core.pillar import PillarState, gray_hancock_ratio, solve_pillar, solve_pillar_inverse
    from ._core.pillar_branch import PillarBranch, continue_pillar, solve_pillar_all
    from ._core.porous import PorousState, solve_porous, solve_porous_all
    from ._core.solution import Solution
    from ._core.solver import from_parameter, from_xi, solve, solve_all
    from ._core.wall_law import spalding_u_plus, spalding_y_plus
    from ._warnings import CalibrationWarning, ModelValidityWarning, UnitsWarning
    from .explorer import explore
    from .pillars import Pillar, PillarDeformation
    from .sensitivity import derivatives
    from .sweeps import sweep
    from .units import HairBed, HairState

__all__ = [
    "CalibrationWarning",
    "HairBed",
    "HairState",
    "LoadedBranch",
    "LoadedState",
    "ModelValidityWarning",
    "Pillar",
    "PillarBranch",
    "PillarDeformation",
    "PillarState",
    "PorousState",
    "Solution",
    "UnitsWarning",
    "branches",
    "calibration",
    "calibration_files",
    "continue_loaded",
    "continue_pillar",
    "derivatives",
    "design",
    "dynamics",
    "explore",
    "from_parameter",
    "from_xi",
    "gray_hancock_ratio",
    "inverse",
    "numerics",
    "pillars",
    "profile_fit",
    "quasistatic",
    "rheology",
    "rheometer",
    "solve",
    "solve_loaded",
    "solve_loaded_all",
    "solve_pillar",
    "solve_pillar_all",
    "solve_pillar_inverse",
    "solve_porous",
    "solve_porous_all",
    "sensitivity",
    "sensor_dynamics",
    "solve_all",
    "spalding_u_plus",
    "spalding_y_plus",
    "stability",
    "sweep",
    "sweeps",
    "units",
    "valve",
]

#: Submodules imported on first access as ``hairbed.<name>``.
_LAZY_MODULES = frozenset(
    {
        "branches",
        "calibration",
        "calibration_files",
        "design",
        "dynamics",
        "inverse",
        "numerics",
        "pillars",
        "profile_fit",
        "quasistatic",
        "rheology",
        "rheometer",
        "sensitivity",
        "sensor_dynamics",
        "stability",
        "sweeps",
        "units",
        "valve",
    }
)
#: Names imported on first access: name -> submodule that defines it.
_LAZY_NAMES = {
    "Solution": "_core.solution",
    "LoadedState": "_core.loaded",
    "solve_loaded": "_core.loaded",
    "solve_loaded_all": "_core.loaded",
    "PillarState": "_core.pillar",
    "spalding_u_plus": "_core.wall_law",
    "spalding_y_plus": "_core.wall_law",
    "gray_hancock_ratio": "_core.pillar",
    "solve_pillar": "_core.pillar",
    "solve_pillar_inverse": "_core.pillar",
    "PillarBranch": "_core.pillar_branch",
    "continue_pillar": "_core.pillar_branch",
    "solve_pillar_all": "_core.pillar_branch",
    "PorousState": "_core.porous",
    "solve_porous": "_core.porous",
    "solve_porous_all": "_core.porous",
    "LoadedBranch": "_core.arclength",
    "continue_loaded": "_core.arclength",
    "from_parameter": "_core.solver",
    "from_xi": "_core.solver",
    "solve": "_core.solver",
    "solve_all": "_core.solver",
    "HairBed": "units",
    "HairState": "units",
    "Pillar": "pillars",
    "PillarDeformation": "pillars",
    "CalibrationWarning": "_warnings",
    "ModelValidityWarning": "_warnings",
    "UnitsWarning": "_warnings",
    "derivatives": "sensitivity",
    "explore": "explorer",
    "sweep": "sweeps",
}


def __getattr__(name: str) -> Any:
    """Import a lab module (or a name of one) on first access, then cache it here."""
    import importlib  # here, not above: ``import hairbed`` imports nothing the interpreter has not

    if name in _LAZY_MODULES:
        value = importlib.import_module(f"{__name__}.{name}")
    elif name in _LAZY_NAMES:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY_NAMES[name]}"), name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
