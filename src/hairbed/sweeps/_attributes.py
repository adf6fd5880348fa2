"""The names and CF attributes of a sweep's dimensions, variables and dataset, from the one
variables table (:mod:`hairbed._variables`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._variables import BED, LOADED, PILLAR, SI, SOLUTION, names
from .._version import __version__

__all__ = [
    "ATTRS",
    "BED_ATTRS",
    "DIMS",
    "LOADED_ATTRS",
    "PILLAR_ATTRS",
    "PILLAR_DIMS",
    "PILLAR_VARIABLES",
    "PUMPED_ATTRS",
    "VARIABLES",
]

#: The grid's dimensions, in their order.
DIMS = ("omega2", "eps", "theta0")

#: Data variables of :func:`hairbed.sweep`, in order: every Solution field that is not a
#: coordinate or the branch label, then the stress ratio.
VARIABLES = names(SOLUTION, "state", "solve", "derived")

#: CF attributes of every coordinate and variable of the dimensionless sweep: name -> (units,
#: long_name). "1" is CF's dimensionless unit; lengths in units of the hair length L are
#: dimensionless too (udunits reads "L" as a litre), which their long_name says.
ATTRS: dict[str, tuple[str, str]] = {
    k: (SOLUTION[k].units, SOLUTION[k].long_name) for k in (*DIMS, *VARIABLES)
}

#: The variables stored as integers (the others are float64, ``physical`` bool).
INTEGER = tuple(k for k in VARIABLES if SOLUTION[k].dtype == "int64")
#: CF flags of ``status``.
STATUS_FLAGS = {
    "flag_values": np.array([0, -1, -2], dtype=np.int64),
    "flag_meanings": "converged no_such_state iteration_limit",
}

_MIRRORED = " (mirrored frame for v < 0)"
#: The dimensionless fields kept beside a bed's SI ones: the state's lengths and angle (as
#: ``scaled_<name>``, in the solved, mirrored frame), the rest under their own names.
BED_SCALED = ("tip_height", "tip_deflection", "tip_displacement", "tip_angle")
_BED_DIMENSIONLESS = ("xi", "omega_eps", "energy", "base_curvature", "t", "n_roots")

#: SI sweep of a bed (:func:`hairbed.sweeps.bed_sweep`): name -> (units, long_name). Every
#: field of a HairState (``velocity`` the dimension), the solved base angle, then the
#: dimensionless fields.
BED_ATTRS: dict[str, tuple[str, str]] = {
    **{k: (SI[k].units, SI[k].long_name) for k in ("velocity", "omega2")},
    "theta0": ("rad", "base angle of the solved problem, sign(v) theta0 (mirrored for v < 0)"),
    **{k: (SI[k].units, SI[k].long_name) for k in names(SI) if k not in ("velocity", "omega2")},
    **{f"scaled_{k}": (ATTRS[k][0], ATTRS[k][1] + _MIRRORED) for k in BED_SCALED},
    **{k: ATTRS[k] for k in (*_BED_DIMENSIONLESS, "physical", "status")},
}
#: Coordinates of a bed's sweep besides ``velocity``, and its data variables, in order.
BED_COORDS = ("omega2", "theta0", "direction")
BED_VARIABLES = tuple(k for k in BED_ATTRS if k != "velocity" and k not in BED_COORDS)
#: The LoadedState fields a sweep holds (``stable`` comes from solve_loaded_all only).
_SWEPT = tuple(k for k in LOADED if k != "stable")
#: SI sweep of a pump-driven bed (``HairBed.sweep`` with ``pressure_gradient`` or
#: ``flow_rate``): dimensions ``velocity`` and the drive's own quantity; the other SI fields,
#: the dimensionless tip (in the bed's frame: no mirror image) and the distributed-load
#: solver's fields (:data:`hairbed._variables.LOADED`).
PUMPED_ATTRS: dict[str, tuple[str, str]] = {
    **{k: (SI[k].units, SI[k].long_name) for k in names(SI) if k != "direction"},
    **{f"scaled_{k}": ATTRS[k] for k in BED_SCALED if k != "tip_displacement"},
    **{k: ATTRS[k] for k in ("base_curvature", "status")},
    **{k: (LOADED[k].units, LOADED[k].long_name) for k in _SWEPT},
}
#: Data variables of :func:`hairbed.sweep` with ``pi`` or ``q`` (the distributed-load
#: solver): the tip and base of every state, its status, then the solver's own fields
#: (the drive itself, pi or q, is a dimension: not among them).
LOADED_VARIABLES = (
    "tip_height", "tip_deflection", "tip_angle", "base_curvature", "status",
    *(k for k in _SWEPT if k not in ("pi", "q")),
)  # fmt: skip
#: Their CF attributes, and those of the two extra dimensions ``pi`` and ``q``.
LOADED_ATTRS: dict[str, tuple[str, str]] = {
    **{k: ATTRS[k] for k in (*DIMS, *LOADED_VARIABLES) if k in ATTRS},
    **{k: (LOADED[k].units, LOADED[k].long_name) for k in _SWEPT},
}

#: The integer variables of a pumped sweep.
PUMPED_INTEGER = ("status", *(k for k in _SWEPT if LOADED[k].dtype == "int64"))
#: The dimensions of a pillar's sweep (:func:`hairbed.sweep` with ``forcing``), in their
#: order: the inputs of :func:`hairbed.solve_pillar` (:data:`hairbed._variables.PILLAR`).
PILLAR_DIMS = names(PILLAR, "pillar_input")
#: Its data variables: every PillarState field but the inputs (``stable`` comes from
#: solve_pillar_all only).
PILLAR_VARIABLES = tuple(k for k in names(PILLAR, "pillar") if k != "stable")
#: CF attributes of its coordinates and variables.
PILLAR_ATTRS: dict[str, tuple[str, str]] = {
    k: (PILLAR[k].units, PILLAR[k].long_name) for k in (*PILLAR_DIMS, *PILLAR_VARIABLES)
}
#: Its integer variables.
PILLAR_INTEGER = tuple(k for k in PILLAR_VARIABLES if PILLAR[k].dtype == "int64")

#: The drives of a pumped sweep: name -> (its SI quantity, its dimensionless one).
PUMP_DRIVES = {"pressure_gradient": "pi", "flow_rate": "q"}


def pumped_variables(drive: str) -> tuple[str, ...]:
    """Data variables of a pumped sweep by ``drive`` ("pressure_gradient" or "flow_rate")."""
    other = "q" if drive == "pressure_gradient" else "pi"  # NaN for this drive: left out
    skip = {"velocity", "omega2", drive, other}
    return tuple(k for k in PUMPED_ATTRS if k not in skip)


#: The bed's parameters recorded in a bed sweep's attributes (``bed_<name>`` and its units).
BED_PARAMETERS = (*(k for k in names(BED, "bed") if k != "density"), "velocity_scale")
#: Their CF units.
BED_UNITS = {k: BED[k].units for k in BED_PARAMETERS}


def cf(pair: tuple[str, str]) -> dict[str, Any]:
    """``{"units", "long_name"}`` of an (units, long_name) pair."""
    return {"units": pair[0], "long_name": pair[1]}


def variable_attrs(pair: tuple[str, str], name: str) -> dict[str, Any]:
    """CF attributes of a data variable (the flags too, for ``status``)."""
    attrs = cf(pair)
    if name == "status":
        attrs.update(STATUS_FLAGS)
    return attrs


def dataset_attrs(title: str, source: str, sign: int, n: int, root: str) -> dict[str, Any]:
    """The global attributes of every sweep: CF, provenance, the branch and root choice."""
    return {
        "title": title,
        "Conventions": "CF-1.8",
        "source": f"hairbed {__version__}{source}",
        "references": "arXiv:2203.04169",
        "hairbed_version": __version__,
        "branch_sign": np.int64(sign),
        "branch_n": np.int64(n),
        "physical_branch": np.int64(sign == 1 and n == 0),
        "root": root,
    }
