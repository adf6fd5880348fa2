"""The shape of what the library returns: a 0-d result as a Python scalar, else an array.

Kept apart from :mod:`hairbed._core.validation` (which checks what comes in): a result on its
way out is not checked again.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["float_or_array", "scalar_or_array"]


def scalar_or_array(value: Any) -> Any:
    """A 0-d value as a Python scalar (float, int, bool), anything else as an array."""
    arr = np.asarray(value)
    return arr.item() if arr.ndim == 0 else arr


def float_or_array(value: Any) -> float | NDArray[np.float64]:
    """A 0-d result as a Python float, anything else as a float64 array (the lab's returns)."""
    arr = np.asarray(value, dtype=np.float64)
    return float(arr) if arr.ndim == 0 else arr
