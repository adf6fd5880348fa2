"""The SPEC of a grid axis or a forcing path, parsed in one place (``hairbed sweep``'s axes,
``--quasistatic``, ``hairbed bistability --map`` and :func:`hairbed.quasistatic.sweep_with_jumps`).

A SPEC is one of

- a number: ``0.5`` (a scalar);
- a comma list: ``0.1,0.5,2`` (the values in the order given);
- ``start:stop:num``: num points from start to stop, both included, evenly spaced;
  ``start:stop:num:lin`` says the same;
- ``start:stop:num:log``: num points spaced geometrically (bounds of one sign: both
  negative gives negative values, e.g. ``-1e4:-10:4:log``);
- ``+-start:stop:num:log`` (or ``±start:...``, and ``+-stop`` may carry the sign too): a
  two-sided logarithmic range, the num points of start:stop:num:log mirrored to negative
  values, 2 num points in increasing order, e.g. ``+-10:1e4:4:log`` is -1e4, -1e3, -100,
  -10, 10, 100, 1e3, 1e4 (start > 0; zero is not in it: add it with a comma list if needed);
- ``start:stop:num:updown`` (or ``start:stop:num:log:updown``): a ramp from start to stop
  and back to start, the 2 num - 1 points of the ramp out (num points, lin or log) then the
  same values back in reverse, the turning point ``stop`` once. A *path* of forcing for a
  quasi-static sweep (a hysteresis loop from one spec); a grid axis refuses it (its values
  repeat).

Negative numbers are values (``-1.2:1.2:25``). A linear range through zero holds 0 exactly
where its step lands there (``-0.05:0.1:4``, not 6.9e-18). Bad text is a ValueError naming the
option and saying which field is wrong; so is a NaN or an infinity, and a num above 10^7. The
values' ranges are the caller's to check (a negative omega^2, eps >= 1, ...).

Examples
--------
>>> parse_spec("0.4:0.6:3:updown", "--omega2", path=True).tolist()
[0.4, 0.5, 0.6, 0.5, 0.4]
>>> parse_spec("1:100:3:log", "--omega2").tolist()
[1.0, 10.0, 100.0]
>>> parse_spec("0.5", "--eps")
0.5
>>> parse_spec("+-10:1000:3:log", "--pressure-drop").tolist()
[-1000.0, -100.0, -10.0, 10.0, 100.0, 1000.0]
>>> parse_spec("-0.05:0.1:4", "--velocity").tolist()
[-0.05, 0.0, 0.05, 0.1]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._core.validation import check_flag

__all__ = ["MAX_SPEC_POINTS", "SPEC_FORMS", "parse_spec"]

#: The most points ``num`` of start:stop:num may ask for.
MAX_SPEC_POINTS = 10_000_000

#: The forms of a SPEC, as error messages name them.
SPEC_FORMS = "a number, a comma list or start:stop:num[:log]"
#: ... and with the ramp of a path.
PATH_FORMS = "a number, a comma list or start:stop:num[:log][:updown]"
#: The prefixes of a two-sided logarithmic range's bounds.
_TWO_SIDED = ("+-", "\u00b1")


def _finite(values: NDArray[np.float64], name: str, text: str) -> None:
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} must hold finite numbers (not NaN or infinity), got {text!r}")


def _ramp(
    start: float, stop: float, num: int, spacing: str, name: str, text: str
) -> NDArray[np.float64]:
    if spacing == "log":
        if not (start > 0 and stop > 0) and not (start < 0 and stop < 0):
            raise ValueError(
                f"{name}: a log range needs positive bounds (or both negative; a two-sided one "
                f"is +-start:stop:num:log), got {text!r}"
            )
        return np.geomspace(start, stop, num)
    values = np.linspace(start, stop, num)
    if num > 1 and start * stop < 0:  # through zero: the point meant to be 0 is 0
        k = int(round(-start * (num - 1) / (stop - start)))
        tiny = 8 * np.finfo(float).eps * max(abs(start), abs(stop))
        if 0 <= k < num and abs(values[k]) <= tiny:
            values[k] = 0.0
    return values


def _strip_two_sided(part: str) -> tuple[str, bool]:
    """A bound without its +- (or ±) prefix, and whether it had one."""
    for prefix in _TWO_SIDED:
        if part.startswith(prefix):
            return part[len(prefix) :], True
    return part, False


def parse_spec(text: str, name: str, *, path: bool = False) -> float | NDArray[np.float64]:
    """The values of a SPEC (module docstring): a float, or a 1-D float64 array.

    Parameters
    ----------
    text : str
        The SPEC.
    name : str
        The option or parameter it was given as, named by the errors (``"--omega2"``).
    path : bool
        Whether an up-and-down ramp (``:updown``) is allowed: True for a path of forcing
        (``--quasistatic``, :func:`hairbed.quasistatic.sweep_with_jumps`), False for a grid
        axis.

    Raises
    ------
    ValueError
        Naming ``name``, the forms allowed and the field that is wrong.
    TypeError
        If ``text`` is not a str.
    """
    if not isinstance(text, str):
        raise TypeError(f"{name} must be a SPEC (a str), got {type(text).__name__}")
    path = check_flag(path, "path")
    form = PATH_FORMS if path else SPEC_FORMS
    parts = [p.strip() for p in text.split(":")]
    parts[0], two_sided = _strip_two_sided(parts[0])
    if len(parts) > 1:
        parts[1], stop_sided = _strip_two_sided(parts[1])
        two_sided = two_sided or stop_sided
    if two_sided and (len(parts) == 1 or [p.lower() for p in parts[3:]] != ["log"]):
        raise ValueError(
            f"{name}: +- makes a two-sided logarithmic range, +-start:stop:num:log (e.g. "
            f"+-10:1e4:20:log); a linear one through zero is -stop:stop:num; got {text!r}"
        )
    try:
        if len(parts) == 1:
            values = np.array([float(p) for p in text.split(",")])
        elif len(parts) in (3, 4, 5):
            start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
            values = np.array([start, stop])
        else:
            raise ValueError
    except ValueError:
        raise ValueError(f"{name} must be {form}, got {text!r}") from None
    _finite(values, name, text)
    if len(parts) == 1:
        return float(values[0]) if values.size == 1 else values
    words = [p.lower() for p in parts[3:]]
    updown = bool(words) and words[-1] == "updown"
    if updown:
        words.pop()
    if len(words) > 1 or (words and words[0] not in ("lin", "log")):
        raise ValueError(
            f"{name}: the fourth field of start:stop:num:log is 'log' or 'lin'"
            + (" (then optionally 'updown')" if path else "")
            + f", got {text!r}"
        )
    if updown and not path:
        raise ValueError(
            f"{name}: :updown makes a path (up then down, values repeated), not a grid axis; "
            "use it with --quasistatic (or hairbed.quasistatic.sweep_with_jumps)"
        )
    if num < 1:
        raise ValueError(f"{name}: num in start:stop:num must be >= 1, got {num}")
    if num > MAX_SPEC_POINTS:
        raise ValueError(
            f"{name}: num in start:stop:num must be at most {MAX_SPEC_POINTS:.0e}, got {num}"
        )
    if two_sided:
        if not 0 < start < stop:
            raise ValueError(
                f"{name}: +-start:stop:num:log needs 0 < start < stop (magnitudes), got {text!r}"
            )
        side = np.geomspace(start, stop, num)
        return np.concatenate([-side[::-1], side])
    ramp = _ramp(start, stop, num, words[0] if words else "lin", name, text)
    if updown:
        return np.concatenate([ramp, ramp[-2::-1]])
    return ramp
