"""Checking of user input: one place, clear messages naming the parameter and its range."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from .outputs import float_or_array, scalar_or_array  # re-exported: their old home

__all__ = [
    "STATUS_MESSAGES",
    "as_float_array",
    "broadcast_named",
    "check_branch",
    "check_choice",
    "check_flag",
    "check_inputs",
    "check_int",
    "check_number",
    "check_positive",
    "check_real_array",
    "check_root",
    "check_scalar_inputs",
    "check_sigma",
    "check_state_inputs",
    "check_tip_deflection",
    "check_type",
    "float_or_array",
    "scalar_or_array",
    "least_squares_status",
    "real_values",
    "status_messages",
    "node_values",
    "show",
    "to_si",
]

HALF_PI = 0.5 * np.pi


#: The one table of status codes of every result (scipy.optimize's convention): 0 ok;
#: negative a failure (the values are NaN, or those of the last iterate); positive ok with a
#: caveat that ``message`` names. An underlying solver's own code (scipy's least_squares,
#: solve_bvp, solve_ivp, root) is kept apart, in a result's ``solver_status``.
STATUS_MESSAGES: Mapping[int, str] = MappingProxyType(
    {
        0: "ok",
        1: "at a fold: the derivatives with respect to the inputs are infinite (dR/dt = 0)",
        2: "a standard error is infinite (at a fold of the bed, or an undetermined fit)",
        3: "converged, but inaccurate: the answer is known to miss the tolerance (see message)",
        4: "within the tolerance over the whole searched range: the values are at its end",
        5: "no degrees of freedom: as many data points as free parameters (see message)",
        6: (
            "a state, but the count of the states is a lower bound: the branch could not be "
            "followed through a snap-through window (other states may coexist)"
        ),
        -1: "no such state: the branch has fewer roots at these inputs than the one requested",
        -2: "iteration limit reached",
        -3: "the iteration broke down (singular step, no descent, integrator failure)",
        -4: "the data do not determine every free parameter (singular Jacobian)",
        -5: "not differentiable: the end t = -inf of a twirling branch (NaN)",
        -6: "improper input to the underlying solver",
        -7: (
            "no state reached from the start: Newton and the load continuation from rest "
            "stopped (a fold on the way, or no state at these inputs)"
        ),
        -8: (
            "outside the model: the hair reaches |theta| = pi/2, where its height z(s) stops "
            "being monotone (the porous bed's fluid is solved along z)"
        ),
    }
)


def least_squares_status(code: int) -> int:
    """:func:`scipy.optimize.least_squares`'s status in the one convention: its 1 to 4 (which
    tolerance stopped it) 0, its 0 (evaluation limit) -2, its -1 (improper input) -6."""
    return 0 if code > 0 else (-2 if code == 0 else -6)


def status_messages(status: Any, messages: Mapping[int, str] = STATUS_MESSAGES) -> str | list[Any]:
    """``messages`` (:data:`STATUS_MESSAGES`) of a status code, or a nested list of them for
    an array of codes."""
    st = np.asarray(status)
    if st.ndim == 0:
        return messages[int(st)]
    return np.vectorize(messages.__getitem__, otypes=[object])(st).tolist()


class StatusResult:
    """The ``success`` and ``message`` of a result type with a ``status`` field, read in the
    class's own status table ``_status_table`` (scalars and arrays of codes alike)."""

    status: Any
    _status_table: ClassVar[Mapping[int, str]]

    @property
    def success(self) -> Any:
        """True where status is 0 (an array of them for an array of codes)."""
        return self.status == 0

    @property
    def message(self) -> Any:
        """The status table's message of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, self._status_table)


def _first_index(mask: NDArray[np.bool_]) -> str:
    """Describe where the first True of ``mask`` is (empty for scalars)."""
    if mask.ndim == 0:
        return ""
    idx = tuple(int(i) for i in np.unravel_index(int(np.argmax(mask)), mask.shape))
    return f" (first at index {idx[0] if len(idx) == 1 else idx})"


def show(value: Any) -> str:
    """A value as a message shows it: numbers as plain Python reprs (never ``np.float64(...)``),
    anything else by its repr, cut to 60 characters."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    if isinstance(value, (np.timedelta64, np.datetime64)):
        return f"{type(value).__name__} {value!s}"
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return repr(value)
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _is_quantity(value: Any) -> bool:
    """A pint quantity (duck-typed: it has ``.to`` and ``.magnitude``)?"""
    return hasattr(value, "magnitude") and hasattr(value, "to")


def to_si(value: Any, name: str, unit: str | None) -> Any:
    """A pint quantity converted to its magnitude in ``unit`` (SI); anything else unchanged.

    pint is imported only when ``value`` looks like a quantity (has ``.to`` and
    ``.magnitude``), so it is optional at run time. ``unit`` is a pint unit expression
    ("m", "Pa", "m/s", "Pa*s", "kg/m**3", "rad"); "" or None means dimensionless.

    Raises
    ------
    ValueError
        If the quantity's dimensions do not convert to ``unit``, naming ``name`` and the unit.
    """
    if not _is_quantity(value):
        return value
    try:
        import pint
    except ImportError:  # not a pint quantity after all
        return value
    target = unit or "dimensionless"
    try:
        return value.to(target).magnitude
    except pint.DimensionalityError:
        shown = f"[{unit}]" if unit else "dimensionless"
        raise ValueError(
            f"{name} must be a quantity in {shown} (or a plain number in SI units), got one in "
            f"{value.units:~}"
        ) from None


def _not_real(element: Any) -> bool:
    return isinstance(element, (bool, np.bool_)) or not isinstance(element, numbers.Real)


def _what(element: Any) -> str:
    if isinstance(element, (bool, np.bool_)):
        return f"a boolean ({show(element)})"
    if isinstance(element, (complex, np.complexfloating)):
        return f"a complex number ({show(element)}; the imaginary part is never dropped)"
    if isinstance(element, (str, bytes)):
        return f"a string ({show(element)})"
    if isinstance(element, (np.timedelta64, np.datetime64)):
        return f"a {type(element).__name__} ({element!s})"
    if element is None:
        return "None"
    if isinstance(element, (list, tuple, np.ndarray)):
        return "a nested sequence of another length (a ragged array)"
    return f"a {type(element).__name__}"


def _where(index: tuple[int, ...]) -> str:
    if not index:
        return ""
    return f" (first at index {index[0] if len(index) == 1 else index})"


def check_real_array(value: Any, name: str, unit: str | None = None) -> NDArray[Any]:
    """``value`` as a numpy array of real numbers (integer or float dtype), or an error.

    The one gate of every numeric input: refuses None, strings and bytes, booleans, complex
    numbers (never dropping an imaginary part silently), ``timedelta64`` / ``datetime64``,
    objects that are not real numbers and ragged nested sequences, naming the parameter and
    (for arrays) the first offending index in array (C) order. A pint quantity is converted
    to its magnitude in ``unit`` first (:func:`to_si`). NaN and infinity pass (see
    :func:`as_float_array`).

    Raises
    ------
    ValueError
        If ``value`` is not real-numeric.
    """
    value = to_si(value, name, unit)
    expected = f"{name} must be a real number or an array of real numbers"
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(f"{expected}, got {show(value)}")
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError):  # ragged lists and the like
        arr = None
    if arr is not None and arr.dtype.kind in "iuf":
        return arr
    if arr is not None and arr.dtype.kind in "bc":
        flat = arr.reshape(-1)
        if arr.dtype.kind == "c" and np.any(flat.imag != 0.0):
            i = int(np.argmax(flat.imag != 0.0))
        else:
            i = 0
        if flat.size == 0:
            raise ValueError(f"{expected}, got an empty array of dtype {arr.dtype}")
        index = tuple(int(k) for k in np.unravel_index(i, arr.shape))
        element = flat[i]
        raise ValueError(f"{expected}, got {_what(element)}{_where(index)}")
    if arr is not None and arr.dtype.kind in "mM":
        raise ValueError(
            f"{expected}, got dtype {arr.dtype} (a {'time' if arr.dtype.kind == 'm' else 'date'}"
            " is not a number: convert it to seconds first)"
        )
    # strings, objects, ragged sequences: look at the elements themselves, in order
    try:
        obj = np.empty(np.shape(np.asarray(value, dtype=object)), dtype=object)
        obj[...] = np.asarray(value, dtype=object)
    except (ValueError, TypeError):
        obj = None
    if obj is not None:
        elements = []
        for i, element in enumerate(obj.reshape(-1)):
            element = to_si(element, name, unit)  # a list of quantities, element by element
            if _not_real(element) or (
                isinstance(element, np.generic) and element.dtype.kind in "mM"
            ):
                index = tuple(int(k) for k in np.unravel_index(i, obj.shape)) if obj.ndim else ()
                raise ValueError(f"{expected}, got {_what(element)}{_where(index)}")
            elements.append(element)
        try:
            with np.errstate(over="ignore"):
                return np.array([float(v) for v in elements]).reshape(obj.shape)
        except OverflowError:
            raise ValueError(f"{name} must be finite: an integer too large for a float") from None
    raise ValueError(f"{expected} (a rectangular array, not a ragged nested sequence)")


def as_float_array(
    value: Any, name: str, allow_minus_inf: bool = False, unit: str | None = None
) -> NDArray[np.float64]:
    """Convert ``value`` to a float array, refusing non-numbers, NaN and infinity.

    Parameters
    ----------
    value : array_like
        What the user passed (a pint quantity is converted to ``unit`` first).
    name : str
        Parameter name used in the error message.
    allow_minus_inf : bool, optional
        Accept -inf (the end of a branch parameter's range); NaN and +inf stay refused.
    unit : str, optional
        The SI unit a pint quantity is converted to (:func:`to_si`); dimensionless by default.

    Raises
    ------
    ValueError
        If ``value`` is not real-numeric (:func:`check_real_array`), or holds NaN or infinity.
    """
    arr = check_real_array(value, name, unit)
    with np.errstate(over="ignore"):  # float128 beyond the float64 range: infinite, refused
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


def _range_text(low: float | None, high: float | None, low_open: bool, high_open: bool) -> str:
    lo = "-inf" if low is None else f"{low:g}"
    hi = "inf" if high is None else f"{high:g}"
    left = "(" if low_open or low is None else "["
    right = ")" if high_open or high is None else "]"
    return f"{left}{lo}, {hi}{right}"


def check_number(
    value: Any,
    name: str,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    unit: str | None = None,
    shown: str | None = None,
) -> float:
    """A single finite real number in the range given, as a float (a tolerance, a time, ...).

    ``low``/``high`` bound the range (None: unbounded), closed unless ``low_open`` /
    ``high_open``; ``unit`` is the SI unit of the number ("" or None: dimensionless), used to
    convert a pint quantity and shown in the message; ``shown`` the range the messages state
    instead (a caller's narrower range that it checks itself, as :func:`check_positive`).

    Raises
    ------
    ValueError
        Naming ``name`` and its range, for non-numbers, booleans, arrays, NaN, infinity and
        values outside the range.
    """
    rng = (shown or _range_text(low, high, low_open, high_open)) + (f" [{unit}]" if unit else "")
    arr = check_real_array(value, name, unit)
    if arr.ndim != 0:
        bounded = low is not None or high is not None or shown is not None
        where = f" in {rng}" if bounded else (f" [{unit}]" if unit else "")
        raise ValueError(
            f"{name} must be a single number{where}, got an array of shape {arr.shape}"
        )
    with np.errstate(over="ignore"):
        x = float(arr)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, in {rng}, got {x!r}")
    if (low is not None and (x < low or (low_open and x == low))) or (
        high is not None and (x > high or (high_open and x == high))
    ):
        raise ValueError(f"{name} must lie in {rng}, got {x!r}")
    return x


def check_positive(value: Any, name: str, unit: str | None = None) -> float:
    """A single finite real number > 0 (a size, a tolerance), as a float; see
    :func:`check_number`."""
    x = check_number(value, name, unit=unit, shown="(0, inf)")
    if not x > 0.0:
        raise ValueError(f"{name} must be positive, got {x!r}" + (f" [{unit}]" if unit else ""))
    return x


def _whole(value: Any) -> int | None:
    """``value`` as an int if it is a whole number (not a bool, a time or a fraction)."""
    if isinstance(value, (bool, np.bool_, np.timedelta64, np.datetime64)):
        return None
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isfinite(x) and x.is_integer():
            return int(x)
    return None


def check_int(value: Any, name: str, low: int | None = None, high: int | None = None) -> int:
    """A whole number in [low, high] (None: unbounded), as an int: a grid size, an iteration
    limit, a count. Integers of any kind and integral floats (``200.0``) are accepted;
    booleans, fractions, NaN, infinity, strings and arrays are not.

    Raises
    ------
    ValueError
        Naming ``name`` and its range.
    """
    if low is not None and high is not None:
        rng = f"an integer >= {low} and <= {high}"
    elif low is not None:
        rng = f"an integer >= {low}"
    elif high is not None:
        rng = f"an integer <= {high}"
    else:
        rng = "an integer"
    k = _whole(value)
    if k is None:
        raise ValueError(f"{name} must be {rng}, got {show(value)}")
    if (low is not None and k < low) or (high is not None and k > high):
        raise ValueError(f"{name} must be {rng}, got {show(value)}")  # 1e+308, not 309 digits
    return k


def check_flag(value: Any, name: str) -> bool:
    """True or False (numpy's bools too), nothing else."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {show(value)}")


def check_choice(value: Any, name: str, choices: tuple[str, ...]) -> str:
    """One of the strings ``choices``."""
    if not isinstance(value, str) or value not in choices:
        listed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} must be one of {listed}, got {show(value)}")
    return value


#: The largest angle [rad] a starting guess may hold (about 160 turns: any twirling branch
#: a discretisation can resolve).
MAX_GUESS_ANGLE = 1000.0


def node_values(guess: Any, name: str, sigma: NDArray[np.float64]) -> NDArray[np.float64]:
    """Finite angles [rad] (at most ``MAX_GUESS_ANGLE`` in size) at the nodes ``sigma`` from a
    number or a function of sigma (a starting guess of theta), as a new array of ``sigma``'s
    shape."""
    label = f"{name}(sigma)" if callable(guess) else name
    values = as_float_array(guess(sigma) if callable(guess) else guess, label, unit="rad")
    if not callable(guess) and values.ndim:
        raise ValueError(
            f"{name} must be a number [rad] or a function of sigma, got an array of shape "
            f"{values.shape}"
        )
    try:
        values = np.broadcast_to(values, sigma.shape).copy()
    except ValueError:
        raise ValueError(
            f"{label} must give one value per node ({sigma.size}), got shape {values.shape}"
        ) from None
    _check_range(
        values,
        np.abs(values) > MAX_GUESS_ANGLE,
        label,
        f"[-{MAX_GUESS_ANGLE:g}, {MAX_GUESS_ANGLE:g}] [rad]",
    )
    return values


def check_type(value: Any, name: str, kind: type | tuple[type, ...], what: str) -> Any:
    """``value`` itself if it is an instance of ``kind``, else a TypeError naming ``name`` and
    ``what`` it must be."""
    if not isinstance(value, kind):
        raise TypeError(f"{name} must be {what}, got {type(value).__name__}")
    return value


def check_scalar_inputs(
    omega2: Any = 0.0,
    eps: Any = 0.0,
    theta0: Any = 0.0,
    *,
    omega2_max: float | None = None,
    why: str = "",
    given: tuple[str, ...] = ("omega2", "eps", "theta0"),
) -> tuple[float, float, float]:
    """The physical inputs as floats, checked like :func:`check_inputs`, for functions that
    take one state (or one branch) at a time: the one scalar-parameter check. ``given`` names
    the inputs the caller takes (the others stay at their defaults, out of the messages);
    ``omega2_max`` bounds the forcing (``why`` says why)."""
    w, e, t = check_inputs(omega2, eps, theta0)
    values = {"omega2": omega2, "eps": eps, "theta0": theta0}
    if any(np.ndim(values[name]) for name in given):
        names = given[0] if len(given) == 1 else ", ".join(given[:-1]) + f" and {given[-1]}"
        verb = "must be a scalar" if len(given) == 1 else "must be scalars"
        raise ValueError(
            f"{names} {verb} here (one state per call); loop over arrays yourself, or use "
            "hairbed.solve, which broadcasts"
        )
    wf = float(w)
    if omega2_max is not None and wf > omega2_max:
        raise ValueError(f"omega2 must lie in [0, {omega2_max:g}]{why}, got {wf!r}")
    return wf, float(e), float(t)


def check_sigma(
    sigma: Any,
    name: str,
    shape: tuple[int, ...],
    *,
    unit: str | None = None,
    allow_zero: bool = False,
    low: float = 0.0,
    high: float = math.inf,
) -> NDArray[np.float64]:
    """Standard uncertainties of data points of ``shape``: one number for all, or one per point.

    Returns a float array of ``shape`` (an array with one value per point, whatever its own
    shape, is read in C order). Each must be finite and > 0 (>= 0 with ``allow_zero``), in
    ``unit`` (a pint quantity is converted to it); nonzero values in [low, high] (the scale of
    the data: an uncertainty beyond the largest possible value says nothing, one a trillion
    times below the data's scale is not an uncertainty).

    Raises
    ------
    ValueError
        For a number of values other than 1 or one per point, or a value out of range, naming
        ``name`` and the first offending index.
    """
    s = as_float_array(sigma, name, unit=unit)
    size = math.prod(shape)
    if s.ndim == 0:
        s = np.full(shape, float(s))
    elif s.size == size:
        s = s.reshape(shape)
    else:
        raise ValueError(
            f"{name} must be a single number or one per point ({size}), got shape {s.shape}"
        )
    bad = s < 0.0 if allow_zero else s <= 0.0
    u = f" [{unit}]" if unit else ""
    if np.any(bad):
        rng = ">= 0" if allow_zero else "> 0"
        raise ValueError(
            f"{name} must be {rng}{u}, got {float(s[bad].flat[0])!r}{_first_index(bad)}"
        )
    bad = (s != 0.0) & ((s < low) | (s > high))
    if np.any(bad):
        zero = "0 or " if allow_zero else ""
        raise ValueError(
            f"{name} must be {zero}in [{low:g}, {high:g}]{u}, got {float(s[bad].flat[0])!r}"
            f"{_first_index(bad)}"
        )
    return s


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


def check_tip_deflection(
    x1: Any, eps: Any, theta0: Any, name: str = "x1"
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """A tip deflection x1 [-] that a flow towards +x can give, with eps and theta0, broadcast.

    x1 lies in [sin(theta0), 1): from the hair at rest (x1 = sin(theta0), also where that
    rounds to 1) to, but not including, a hair lying flat. x1 = 1 is reached only in the
    limit omega2 -> inf, so a value of 1 (or one that a state's x1 rounds to) has no finite
    forcing to give back: a ValueError, as a tip at the bed's full length is for
    :class:`hairbed.HairBed` and a tip height below 1e-150 for the tip-height inverse.
    """
    v, e, t = check_state_inputs(x1, name, eps, theta0)
    s = np.sin(t)
    bad = ((v < s) | (v >= 1.0)) & (v != s)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        got = float(v.ravel()[i])
        why = (
            ": x1 = 1 is a hair lying flat, reached only in the limit omega2 -> inf"
            if got == 1.0
            else ": the flow bends a hair from its rest position towards +x, never past flat"
        )
        raise ValueError(
            f"{name} must lie in [sin(theta0), 1) = [{float(s.ravel()[i])!r}, 1), got "
            f"{got!r}{_first_index(bad)}{why}"
        )
    return v, e, t


#: The largest interior turning-point count of a branch label (the kernels count in int64).
MAX_N = 10**9


def check_branch(sign: Any, n: Any) -> tuple[int, int]:
    """Validate a branch label: ``sign`` in {+1, -1}, ``n`` a whole number >= 0."""
    if type(sign) is int and type(n) is int and (sign == 1 or sign == -1) and 0 <= n <= MAX_N:
        return sign, n  # the common case, without the abstract-base-class checks
    s = _whole(sign)
    if s not in (1, -1):
        raise ValueError(f"sign must be +1 or -1, got {show(sign)}")
    k = _whole(n)
    if k is None or not 0 <= k <= MAX_N:
        raise ValueError(f"n must be a whole number >= 0 (at most 10^9), got {show(n)}")
    return s, k


ROOTS = ("low", "mid", "high")


def check_root(root: Any) -> str:
    """Validate the root selector of a multi-valued branch."""
    return check_choice(root, "root", ROOTS)


def real_values(raw: Any, who: str, what: str) -> NDArray[np.float64]:
    """``raw`` (what a user's callable returned) as float64, or a TypeError saying ``who``
    "must return" ``what``: for values that are not numbers, and for complex ones (numpy
    would drop their imaginary part with only a ComplexWarning, issue 33)."""
    try:
        arr = np.asarray(raw)
        if np.iscomplexobj(arr):
            raise TypeError
        return np.asarray(arr, dtype=np.float64)
    except (TypeError, ValueError):
        kind = "complex values" if np.iscomplexobj(raw) else type(raw).__name__
        raise TypeError(f"{who} must return {what}, got {kind}") from None
