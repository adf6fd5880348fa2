"""Plain Python values for JSON: the one converter of arrays, numpy scalars and NaN.

numpy's arrays and scalars are not JSON; NaN and the infinities are not *strict* JSON (which
``json.dumps(..., allow_nan=False)`` and every browser's ``JSON.parse`` demand). Everything
that writes JSON (the command line, the explorer's downloads and its plot updates, the
attributes of a sweep's parquet file) converts through :func:`to_plain`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["to_plain"]


def to_plain(value: Any, *, strict: bool = True) -> Any:
    """``value`` as Python scalars, lists and dicts, all the way down.

    Parameters
    ----------
    value : Any
        A scalar, numpy scalar or array, or (nested) lists, tuples and mappings of them.
    strict : bool
        True: NaN and the infinities become None (strict JSON's null). False: they stay floats
        (for a consumer that carries them itself, such as Bokeh's column data).

    Returns
    -------
    Any
        Arrays and tuples become lists, mappings dicts, numpy scalars Python ones.

    Examples
    --------
    >>> to_plain({"x": np.array([1.0, np.nan]), "n": np.int64(3), "t": (np.inf,)})
    {'x': [1.0, None], 'n': 3, 't': [None]}
    >>> to_plain(np.array([1.0, np.nan]), strict=False)
    [1.0, nan]
    """
    if isinstance(value, np.ndarray):
        kind = value.dtype.kind
        if kind in "biu" or (kind == "f" and (not strict or bool(np.isfinite(value).all()))):
            return value.tolist()  # one call: no per-element work for clean numbers
        if kind == "f":
            out = value.astype(object)
            out[~np.isfinite(value)] = None
            return out.tolist()
        return [to_plain(v, strict=strict) for v in value.tolist()]
    if isinstance(value, Mapping):
        return {k: to_plain(v, strict=strict) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [to_plain(v, strict=strict) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if strict and isinstance(value, float) and not math.isfinite(value):
        return None
    return value
