"""The bed's moduli figure draws oscillatory_shear's numbers (recomputed on its own grid)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from hairbed.plotting import FIGURES, fig_bed_moduli  # noqa: E402
from hairbed.rheometer import oscillatory_shear  # noqa: E402


def _line(fig, gid):
    for ax in fig.axes:
        for ln in ax.lines:
            if ln.get_gid() == gid:
                return ln
    raise AssertionError(f"no line {gid}")


def test_bed_moduli_draws_the_moduli_and_the_crossover() -> None:
    assert FIGURES["bed_moduli"] is fig_bed_moduli
    fig = fig_bed_moduli(num=6, forcings=(0.0,))
    om = np.asarray(_line(fig, "loss_0").get_xdata())
    ref = oscillatory_shear(om, 0.0, eps=0.5, kappa=1.0, inertia=1.0)
    np.testing.assert_allclose(_line(fig, "loss_0").get_ydata(), ref.loss[:, 0], rtol=1e-12)
    g1 = ref.storage[:, 0]
    pos = np.asarray(_line(fig, "storage_0").get_ydata(), dtype=float)
    neg = np.asarray(_line(fig, "storage_negative_0").get_ydata(), dtype=float)
    np.testing.assert_allclose(np.where(g1 > 0, pos, -neg), g1, rtol=1e-12)
    assert np.any(g1 > 0) and np.any(g1 < 0)  # the hair's inertia: lag, then lead
    np.testing.assert_allclose(
        _line(fig, "lead_0").get_ydata(), np.degrees(ref.lead[:, 0]), rtol=1e-12
    )
    dot = _line(fig, "crossover_0")
    assert dot.get_xdata()[0] == pytest.approx(ref.lead_crossover[0], rel=1e-9)
    with pytest.raises(ValueError, match="frequency_range"):
        fig_bed_moduli(frequency_range=(1.0, 0.5))
