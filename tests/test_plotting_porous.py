"""The porous bed's gallery figure: collective stiffening between its two limits."""

from __future__ import annotations

import numpy as np
import pytest

from hairbed.plotting import FIGURES, fig_collective_stiffening


def test_stiffening_meets_the_pillar_and_the_dense_bed() -> None:
    fig = fig_collective_stiffening(phi_range=(1e-6, 0.5), num=5)
    ax = fig.axes[0]
    lines = {line.get_label(): line.get_ydata() for line in ax.get_lines()}
    porous = np.asarray(lines["porous bed, drag 'crossover'"])
    pillar = float(np.asarray(lines["isolated pillar (sparse limit)"])[0])
    dense = np.asarray(lines["dense bed, tip load (the paper)"])
    # stiffer with density on the dense side (phi = 7e-4, 0.019, 0.5); the crossover's drag
    # grows with the density at first (the array's cut-off falls below the hair's length)
    assert np.all(np.diff(porous[2:]) < 0)
    assert porous[0] == pytest.approx(pillar, rel=0.1)  # the sparse limit
    assert porous[-1] == pytest.approx(dense[-1], rel=0.03)  # the dense limit
    assert "collective_stiffening" in FIGURES


def test_bad_range_is_refused() -> None:
    with pytest.raises(ValueError, match="phi_range"):
        fig_collective_stiffening(phi_range=(0.1, 0.9))
