"""Warnings of the lab layer: where the model's assumptions fail (no numerics here), and the
deprecation of renamed parameters."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar, cast

__all__ = ["CalibrationWarning", "ModelValidityWarning", "UnitsWarning", "renamed_parameters"]

_F = TypeVar("_F", bound=Callable[..., Any])


class ModelValidityWarning(UserWarning):
    """The inputs are outside the regime in which the model of arXiv:2203.04169 holds.

    Raised (as a warning, the result is still returned) for instance where the gap flow's
    Reynolds number rho |v| (H - h1 L)/eta exceeds 1, so that the Stokes-flow (Couette) load of
    the model, theory.md §7, is no longer the load on the hairs. Silence it with
    ``warnings.simplefilter("ignore", hairbed.ModelValidityWarning)``.
    """


class CalibrationWarning(UserWarning):
    """A calibration fit ended, but its answer is weaker than it looks.

    Issued (the fit is still returned, with a positive ``status``) by
    :func:`hairbed.calibration.fit` when there are no degrees of freedom: as many points as
    free parameters, so that the curve passes through every point, chi2 says nothing of the
    model and, without ``sigma``, the standard errors are infinite (scipy's ``curve_fit``
    issues its ``OptimizeWarning`` for the same case).
    """


class UnitsWarning(UserWarning):
    """An SI input is outside any plausible range: most likely a unit slip.

    Issued (the input is still used) for instance by :class:`hairbed.HairBed` for a hair
    longer than a metre (micrometres given as metres?) or a Young's modulus below 1 kPa (a
    modulus in MPa given as Pa?); the message names the parameter and the likely slip, and
    ``hairbed.units.PLAUSIBLE_RANGES`` lists the ranges. Silence it with
    ``warnings.simplefilter("ignore", hairbed.UnitsWarning)``, or pass pint quantities
    (``ureg.Quantity(500, "um")``), which are converted to SI.
    """


def renamed_parameters(**renames: str) -> Callable[[_F], _F]:
    """Keep a function's old keyword names working while they are deprecated.

    Each ``old="new"`` maps a call with ``old=...`` to ``new=...`` and issues a FutureWarning
    that names the new name (pvlib's ``renamed_kwarg_warning``); passing both is a TypeError.
    The nomenclature these serve is the table in CONTRIBUTING.md.
    """

    def decorate(func: _F) -> _F:
        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            for old, new in renames.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(
                            f"{func.__name__}() got {old!r} (deprecated) and {new!r}: give "
                            f"{new!r} only"
                        )
                    warnings.warn(
                        f"{func.__name__}(): the parameter {old!r} is deprecated and will be "
                        f"removed; use {new!r}",
                        FutureWarning,
                        stacklevel=2,
                    )
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return cast(_F, wrapper)

    return decorate
