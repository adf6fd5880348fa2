"""Checking of user input: one place, clear messages naming the parameter and its range."""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "as_float_array",
    "broadcast_named",
    "check_branch",
    "check_inputs",
    "check_root",
    "check_state_inputs",
    "float_or_array",
]

HALF_PI = 0.5 * np.pi


def float_or_array(value: Any) -> float | NDArray[np.float64]:
    """A 0-d result as a Python float, anything else as a float64 array (the lab's returns)."""
    arr = np.asarray(value, dtype=np.float64)
    return float(arr) if arr.ndim == 0 else arr


def _first_index(mask: NDArray[np.bool_]) -> str:
    """Describe where the first True of ``mask`` is (empty for scalars)."""
    if mask.ndim == 0:
        return ""
    idx = tuple(int(i) for i in np.unravel_index(int(np.argmax(mask)), mask.shape))
    return f" (first at index {idx[0] if len(idx) == 1 else idx})"


def as_float_array(value: Any, name: str, allow_minus_inf: bool = False) -> NDArray[np.float64]:
    """Convert ``value`` to a float array, refusing non-numbers, NaN and infinity.

    Parameters
    ----------
    value : array_like
        What the user passed.
    name : str
        Parameter name used in the error message.
    allow_minus_inf : bool, optional
        Accept -inf (the end of a branch parameter's range); NaN and +inf stay refused.

    Raises
    ------
    ValueError
        If ``value`` is not real-numeric, or holds NaN or infinity.
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(
            f"{name} must be a real number or an array of real numbers, got {value!r}"
        )
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise ValueError(f"{name} must be a real number or an array of real numbers") from exc
    if arr.dtype == np.bool_ or not (
        np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)
    ):
        raise ValueError(
            f"{name} must be a real number or an array of real numbers, got dtype {arr.dtype}"
        )
    arr = arr.astype(np.float64)
    bad = ~np.isfinite(arr)
    if allow_minus_inf:
        bad &= arr != -np.inf
    if np.any(bad):
        what = (
            "a real number or -inf (not NaN or +inf)"
            if allow_minus_inf
            else "finite (not NaN or infinity)"
        )
        raise ValueError(f"{name} must be {what}{_first_index(bad)}")
    return arr


def _check_range(arr: NDArray[np.float64], bad: NDArray[np.bool_], name: str, rng: str) -> None:
    if np.any(bad):
        first = float(arr[bad].flat[0])
        raise ValueError(f"{name} must lie in {rng}, got {first!r}{_first_index(bad)}")


def check_inputs(
    omega2: Any, eps: Any, theta0: Any
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Validate and broadcast the three physical inputs of the dimensionless problem.

    Parameters
    ----------
    omega2 : array_like
        Forcing parameter omega^2 [-], must be >= 0.
    eps : array_like
        Confinement eps = L/H [-], must be in [0, 1).
    theta0 : array_like
        Base angle [rad], must be in (-pi/2, pi/2).

    Returns
    -------
    omega2, eps, theta0 : ndarray
        Float arrays broadcast to a common shape.

    Raises
    ------
    ValueError
        Naming the offending parameter, its allowed range and (for arrays) the first bad index.
    """
    w = as_float_array(omega2, "omega2")
    e = as_float_array(eps, "eps")
    t = as_float_array(theta0, "theta0")
    _check_range(w, w < 0.0, "omega2", "[0, inf)")
    _check_range(e, (e < 0.0) | (e >= 1.0), "eps", "[0, 1)")
    _check_range(t, np.abs(t) >= HALF_PI, "theta0", "(-pi/2, pi/2)")
    w, e, t = broadcast_named(("omega2", w), ("eps", e), ("theta0", t))
    return w, e, t


def broadcast_named(*named: tuple[str, NDArray[np.float64]]) -> tuple[NDArray[np.float64], ...]:
    """Broadcast named arrays to one shape (copies), naming them all if they do not fit."""
    arrays = [a for _, a in named]
    try:
        out = np.broadcast_arrays(*arrays)
    except ValueError as exc:
        names = ", ".join(n for n, _ in named[:-1]) + f" and {named[-1][0]}"
        shapes = ", ".join(str(np.shape(a)) for a in arrays[:-1]) + f" and {np.shape(arrays[-1])}"
        raise ValueError(f"{names} must broadcast together, got shapes {shapes}") from exc
    return tuple(np.array(a) for a in out)


def check_state_inputs(
    value: Any, name: str, eps: Any, theta0: Any
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """A finite array ``value`` (range checked by the caller) with valid eps and theta0,
    broadcast together; for functions whose first input is a state rather than omega2."""
    v = as_float_array(value, name)
    _, e, t = check_inputs(0.0, eps, theta0)
    v, e, t = broadcast_named((name, v), ("eps", e), ("theta0", t))
    return v, e, t


def check_branch(sign: Any, n: Any) -> tuple[int, int]:
    """Validate a branch label: ``sign`` in {+1, -1}, ``n`` a whole number >= 0."""
    if type(sign) is int and type(n) is int and (sign == 1 or sign == -1) and n >= 0:
        return sign, n  # the common case, without the abstract-base-class checks
    if isinstance(sign, bool) or not isinstance(sign, numbers.Real) or sign not in (1, -1):
        raise ValueError(f"sign must be +1 or -1, got {sign!r}")
    if (
        isinstance(n, bool)
        or not isinstance(n, numbers.Real)
        or not float(n).is_integer()
        or n < 0
    ):
        raise ValueError(f"n must be a whole number >= 0, got {n!r}")
    return (1 if sign == 1 else -1), int(float(n))


ROOTS = ("low", "mid", "high")


def check_root(root: Any) -> str:
    """Validate the root selector of a multi-valued branch."""
    if not isinstance(root, str) or root not in ROOTS:
        raise ValueError(f"root must be one of 'low', 'mid', 'high', got {root!r}")
    return root
