"""Warnings of the lab layer: where the model's assumptions fail (no numerics here)."""

from __future__ import annotations

__all__ = ["ModelValidityWarning", "UnitsWarning"]


class ModelValidityWarning(UserWarning):
    """The inputs are outside the regime in which the model of arXiv:2203.04169 holds.

    Raised (as a warning, the result is still returned) for instance where the gap flow's
    Reynolds number rho |v| (H - h1 L)/eta exceeds 1, so that the Stokes-flow (Couette) load of
    the model, theory.md §7, is no longer the load on the hairs. Silence it with
    ``warnings.simplefilter("ignore", hairbed.ModelValidityWarning)``.
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
