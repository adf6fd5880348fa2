"""Warnings of the lab layer: where the model's assumptions fail (no numerics here)."""

from __future__ import annotations

__all__ = ["ModelValidityWarning"]


class ModelValidityWarning(UserWarning):
    """The inputs are outside the regime in which the model of arXiv:2203.04169 holds.

    Raised (as a warning, the result is still returned) for instance where the gap flow's
    Reynolds number rho |v| (H - h1 L)/eta exceeds 1, so that the Stokes-flow (Couette) load of
    the model, theory.md §7, is no longer the load on the hairs. Silence it with
    ``warnings.simplefilter("ignore", hairbed.ModelValidityWarning)``.
    """
