"""The LAOS figures draw large_amplitude_shear's numbers (recomputed here at the same inputs):
the elastic and viscous Lissajous curves of fig_bed_lissajous and a cell of fig_pipkin."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from hairbed.plotting import FIGURES, fig_bed_lissajous, fig_pipkin  # noqa: E402
from hairbed.rheometer import large_amplitude_shear  # noqa: E402


def _line(fig, gid):
    for ax in fig.axes:
        for ln in ax.lines:
            if ln.get_gid() == gid:
                return ln
    raise AssertionError(f"no line {gid}")


def test_lissajous_and_pipkin_draw_the_periodic_state() -> None:
    assert FIGURES["bed_lissajous"] is fig_bed_lissajous and FIGURES["pipkin"] is fig_pipkin
    g0, om = 30.0, 1.0
    r = large_amplitude_shear(om, g0, eps=0.5, kappa=0.1, theta0=0.4)
    assert r.analysis is not None
    c = r.analysis.lissajous(33)
    big, el = np.max(np.abs(c["total"])), np.max(np.abs(c["elastic"]))
    fig = fig_bed_lissajous(omega=om, strain_amplitudes=(g0,), num=33)
    np.testing.assert_allclose(_line(fig, "elastic_0").get_xdata(), c["strain"] / g0, rtol=1e-12)
    np.testing.assert_allclose(_line(fig, "elastic_0").get_ydata(), c["elastic"] / el, atol=1e-9)
    np.testing.assert_allclose(
        _line(fig, "viscous_view_0").get_xdata(), c["strain_rate"] / (g0 * om), atol=1e-12
    )
    np.testing.assert_allclose(_line(fig, "viscous_view_0").get_ydata(), c["total"] / big,
                               atol=1e-9)  # fmt: skip
    # the hairs stiffen at this amplitude: the elastic curve is not a straight line
    assert r.analysis.stiffening_ratio > 0.5
    pip = fig_pipkin(omegas=(om,), strain_amplitudes=(g0,), num=33)
    np.testing.assert_allclose(_line(pip, "pipkin_0_0").get_ydata(), c["elastic"] / el, atol=1e-9)
    with pytest.raises(ValueError, match="num"):
        fig_pipkin(num=3)
