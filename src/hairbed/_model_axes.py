"""The leading model dimensions of a result of an array-valued model (issue 32).

An array-valued :class:`hairbed.Pillar` or :class:`hairbed.HairBed` of shape ``S`` (its
parameters broadcast together) gives results in time and frequency whose fields carry ``S``
in front of their own axes. This module names those axes for xarray (``pillar`` or
``bed`` for a 1-d model, ``pillar_0``, ``pillar_1``, ... beyond), gives the model's array
parameters as coordinates on them (with their SI units), names an element by its index
in an error, and re-issues the warnings of the elements' runs once per kind.

It imports nothing of the models (which call the modules that call it): a model is read by
its interface (``shape`` and its parameters).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ._core.validation import show

__all__: list[str] = []

#: SI units of the models' parameters (CF spelling), for their coordinates.
PARAMETER_UNITS = {
    "length": "m",
    "radius": "m",
    "youngs_modulus": "Pa",
    "viscosity": "Pa s",
    "base_angle": "rad",
    "drag_scale": "1",
    "channel_height": "m",
    "density": "kg m-3",
    "spacing": "m",
    "packing_fraction": "1",
}


def model_dims(kind: str, shape: tuple[int, ...]) -> tuple[str, ...]:
    """The names of a model's axes: (kind,) for a 1-d model, (kind_0, kind_1, ...) beyond."""
    if len(shape) == 1:
        return (kind,)
    return tuple(f"{kind}_{k}" for k in range(len(shape)))


def checked_index(index: Any, shape: tuple[int, ...], what: str) -> tuple[int, ...]:
    """``index`` (an int or a tuple of ints, negative from the end) into ``shape``, or a
    ValueError."""
    idx = index if isinstance(index, tuple) else (index,)
    whole = all(
        isinstance(i, (int, np.integer)) and not isinstance(i, (bool, np.bool_)) for i in idx
    )
    if not whole or len(idx) != len(shape):
        raise ValueError(
            f"index must be {len(shape)} integer(s) into the {what}'s shape {shape} (an int "
            f"or a tuple), got {show(index)}"
        )
    if not all(-n <= int(i) < n for i, n in zip(idx, shape, strict=True)):
        raise ValueError(f"index {show(index)} is out of range for the {what}'s shape {shape}")
    return tuple(int(i) for i in idx)


def element_index(flat: int, shape: tuple[int, ...]) -> Any:
    """The index of the flat (C order) element ``flat`` of ``shape``: an int for a 1-d
    model, else a tuple (as :meth:`hairbed.Pillar.item` takes it)."""
    idx = tuple(int(i) for i in np.unravel_index(flat, shape))
    return idx[0] if len(idx) == 1 else idx


def model_coords(model: Any, kind: str, names: tuple[str, ...]) -> dict[str, Any]:
    """xarray coordinates on the model's axes: the element index of a 1-d model, and each
    parameter among ``names`` given as an array (broadcast to the model's shape), with its
    SI units."""
    shape = tuple(model.shape)
    dims = model_dims(kind, shape)
    coords: dict[str, Any] = {}
    if len(shape) == 1:
        coords[kind] = (kind, np.arange(shape[0]), {"units": "1", "long_name": f"{kind} index"})
    for name in names:
        value = getattr(model, name, None)
        if value is None or np.ndim(value) == 0:
            continue
        arr = np.broadcast_to(np.asarray(value, dtype=np.float64), shape)
        attrs = {"units": PARAMETER_UNITS.get(name, "1"), "long_name": name.replace("_", " ")}
        coords[name] = (dims, np.array(arr), attrs)
    return coords


def reissue(records: list[list[warnings.WarningMessage]], shape: tuple[int, ...],
            kind: str, stacklevel: int) -> None:  # fmt: skip
    """Re-issue the warnings the elements' runs raised (``records[k]``: the flat element
    k's), once per category: the first element's message, where it is and how many elements
    of the model warned so."""
    first: dict[type[Warning], tuple[int, str]] = {}
    count: dict[type[Warning], int] = {}
    for k, caught in enumerate(records):
        seen = set()
        for w in caught:
            cat = w.category
            if cat not in first:
                first[cat] = (k, str(w.message))
            if cat not in seen:
                count[cat] = count.get(cat, 0) + 1
                seen.add(cat)
    total = len(records)
    for cat, (k, message) in first.items():
        warnings.warn(
            f"{message} ({kind} {element_index(k, shape)}; {count[cat]} of the {total} "
            f"{kind}s warned so)",
            cat,
            stacklevel=stacklevel + 1,
        )
