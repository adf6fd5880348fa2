"""What the results of the Chebyshev collocation (``_kernels.spectral``) share.

:class:`hairbed.LoadedState` (the pressure and flow drives, theory.md §11) and
:class:`hairbed.PillarState` (the isolated pillar, theory.md §12) are frozen dataclasses of
the same kernel's columns; their ``success``, ``message`` and ``shape_of_fields`` are
written once, here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .outputs import scalar_or_array
from .validation import STATUS_MESSAGES, status_messages

__all__ = ["CollocatedState"]


class CollocatedState:
    """The base of the collocation's result types: the properties read from ``status`` and
    the shape of ``tip_height`` (the subclasses are dataclasses with those fields)."""

    status: Any
    tip_height: Any

    @property
    def success(self) -> Any:
        """True where the state converged within the tolerance (status 0)."""
        return scalar_or_array(np.asarray(self.status) == 0)

    @property
    def message(self) -> str | list[Any]:
        """``STATUS_MESSAGES`` of ``status`` (a nested list for arrays)."""
        return status_messages(self.status, STATUS_MESSAGES)

    @property
    def shape_of_fields(self) -> tuple[int, ...]:
        """Shape of the array fields (() for a single state)."""
        return np.shape(self.tip_height)
