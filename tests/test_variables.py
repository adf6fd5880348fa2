"""The variables table (hairbed._variables) against what the code actually holds.

The table is the one place that names, units and labels the fields; these tests hold it equal
to the kernel's output columns, the :class:`hairbed.Solution`, :class:`hairbed.units.HairBed`
and :class:`hairbed.units.HairState` dataclasses, and the types a solve really returns.
"""

from __future__ import annotations

import ast
import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import hairbed
from hairbed import _variables
from hairbed._core._kernels import FIELDS
from hairbed._variables import (
    BED,
    BED_REQUIRED,
    GROUPS,
    LOADED,
    PILLAR,
    POROUS,
    SI,
    SOLUTION,
    WINDOW,
    Variable,
    cf_attrs,
    names,
)
from hairbed.units import HairBed, HairState

#: Solution fields that no kernel writes: the inputs passed through, the branch label and
#: ``physical``, which the wrapper computes from the branch and the status.
SOLUTION_ONLY = {"eps", "theta0", "sign", "n", "physical"}


def _bed() -> HairBed:
    return HairBed(
        length=1e-3,
        radius=50e-6,
        youngs_modulus=1e6,
        channel_height=2e-3,
        viscosity=1.0,
        spacing=400e-6,
        density=1000.0,
    )


def test_the_solution_groups_are_the_solution_fields_in_order():
    fields = tuple(f.name for f in dataclasses.fields(hairbed.Solution))
    assert names(SOLUTION, "input", "branch", "state", "solve") == fields


def test_the_table_names_exactly_the_kernel_fields():
    kernel = set(FIELDS)
    assert len(kernel) == len(FIELDS)
    solution = set(names(SOLUTION, "input", "branch", "state", "solve"))
    assert kernel <= solution, kernel - solution
    assert solution - kernel == SOLUTION_ONLY


def test_the_bed_group_is_the_hairbed_fields_in_order():
    # every field is named: the numbers (group bed), then the model's choices (bed_model)
    fields = tuple(f.name for f in dataclasses.fields(HairBed))
    assert names(BED, "bed", "bed_model") == fields
    assert names(BED, "bed_model") == ("model", "drag")
    assert all(BED[k].dtype == "float64" for k in names(BED, "bed"))


def test_the_required_bed_parameters_are_the_fields_without_a_default():
    fields = dataclasses.fields(HairBed)
    assert BED_REQUIRED == tuple(f.name for f in fields if f.default is dataclasses.MISSING)
    assert set(BED_REQUIRED) <= set(names(BED, "bed"))


def test_every_derived_bed_variable_is_a_hairbed_property():
    bed = _bed()
    for name in names(BED, "bed_derived"):
        assert isinstance(getattr(HairBed, name), property), name
        assert math.isfinite(getattr(bed, name)) and getattr(bed, name) > 0, name


def test_the_si_table_is_the_hairstate_fields_in_order():
    fields = tuple(f.name for f in dataclasses.fields(HairState))
    assert names(SI) == tuple(f for f in fields if f not in ("bed", "solution"))
    assert set(names(SI, "si")) == set(SI)


def test_the_dtypes_are_those_a_solve_returns():
    for value in (2.0, np.array([0.5, 2.0])):
        sol = hairbed.solve(value, 0.5)
        for name in names(SOLUTION, "input", "branch", "state", "solve"):
            got = np.asarray(getattr(sol, name))
            want = np.dtype(SOLUTION[name].dtype)
            assert got.dtype.kind == want.kind, (name, got.dtype, want)


def test_the_si_values_are_floats():
    state = _bed().deform(np.array([-0.1, 0.1]))
    for name, v in SI.items():
        assert v.dtype == "float64"
        assert np.asarray(getattr(state, name)).dtype == np.float64, name


def test_entries_are_complete():
    for table in (SOLUTION, BED, SI, WINDOW, LOADED, PILLAR, POROUS):
        for key, v in table.items():
            assert isinstance(v, Variable) and v.name == key
            assert v.group in GROUPS
            assert v.units and v.long_name and v.label and v.description, key
            # strings only for a bed's choice of model
            assert v.dtype in ("float64", "int64", "bool") or (
                v.dtype == "str" and v.group == "bed_model"
            ), key
            assert "[" not in v.label, key  # the unit goes in ``unit``, shown by ``heading``
            # dimensionless in CF exactly when people read no physical unit (a pillar's
            # forces are in E I/L^2)
            assert (v.units == "1") == (v.unit in ("", "-", "L", "1/L", "EI/L^2")), key


def test_counts_and_flags_have_no_unit_shown():
    for v in SOLUTION.values():
        if v.dtype != "float64":
            assert v.unit == "" and v.heading == v.label, v.name
    assert SOLUTION["tip_height"].heading == "tip height h1 [L]"
    assert SOLUTION["sign"].heading == "sign of theta'(0)"


def test_cf_attrs():
    assert cf_attrs(SOLUTION["theta0"]) == {
        "units": "rad",
        "long_name": "base angle theta0 from the wall normal",
    }


def test_names_refuses_an_unknown_group():
    with pytest.raises(ValueError, match="groups must be among .* got 'states'"):
        names(SOLUTION, "states")


def test_the_entries_cannot_change():
    with pytest.raises(TypeError):
        SOLUTION["xi"] = SOLUTION["eps"]  # type: ignore[index]
    with pytest.raises(dataclasses.FrozenInstanceError):
        SOLUTION["xi"].units = "m"  # type: ignore[misc]


def test_the_module_imports_nothing_of_hairbed():
    tree = ast.parse(Path(_variables.__file__).read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            assert node.level == 0 and not (node.module or "").startswith("hairbed"), node.module
        elif isinstance(node, ast.Import):
            assert all(not a.name.startswith("hairbed") for a in node.names)


def test_the_loaded_table_and_solution_name_every_loaded_state_field():
    import dataclasses

    from hairbed import LoadedState

    fields = [f.name for f in dataclasses.fields(LoadedState) if not f.name.startswith("_")]
    fields.remove("drive")  # a string label, not a variable
    assert set(fields) == set(LOADED) | (set(fields) & set(SOLUTION))
    assert [k for k in fields if k in LOADED] == list(LOADED)


def test_the_pillar_table_names_every_pillar_state_field_in_order():
    from hairbed import PillarState

    fields = [f.name for f in dataclasses.fields(PillarState) if not f.name.startswith("_")]
    inputs = [k for k in names(PILLAR, "pillar_input") if k != "height_ratio"]
    assert [*inputs, *names(PILLAR, "pillar")] == fields


def test_the_pillar_dtypes_are_those_a_solve_returns():
    state = hairbed.solve_pillar(np.array([0.5, 2.0]))
    for name, v in PILLAR.items():
        if v.group != "pillar" or name == "stable":
            continue
        kind = np.asarray(getattr(state, name)).dtype.kind
        assert kind == {"float64": "f", "int64": "i"}[v.dtype], name
