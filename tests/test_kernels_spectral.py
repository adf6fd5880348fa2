"""The collocation kernel (``_kernels/spectral.py``) on a sample of the loaded reference.

``make test`` runs this file a second time under ``NUMBA_DISABLE_JIT=1``, where the kernel
executes as plain Python: that checks its source is correct Python (and lets coverage see
it). A few single-state cases of ``tests/data/loaded_mpmath.json``, one per drive and one
strong load, and the drive formulas with their h1-derivatives against central differences.
"""

from __future__ import annotations

import json

import pytest
from conftest import DATA
from tolerances import FINITE_DIFFERENCE_RTOL, LOADED_REFERENCE_ATOL

import hairbed
from hairbed._core._kernels import spectral

CASES = json.loads((DATA / "loaded_mpmath.json").read_text())["cases"]
LABELS = ("pressure+wall", "flow+wall", "flow")
SAMPLE = [next(c for c in CASES if c["label"] == lab and len(c["states"]) == 1) for lab in LABELS]


@pytest.mark.parametrize("case", SAMPLE, ids=lambda c: c["label"])
def test_reference_sample(case):
    kw = {"pi": case["pi"]} if case["drive"] == "pressure" else {"q": case["q"]}
    st = hairbed.solve_loaded(case["omega2"], case["eps"], case["theta0"], **kw)
    ref = case["states"][0]
    assert st.status == 0
    for key, name in (("tip_height", "tip_height"), ("tip_deflection", "tip_deflection")):
        assert abs(getattr(st, name) - float(ref[key])) <= LOADED_REFERENCE_ATOL


@pytest.mark.parametrize(
    ("code", "omega2", "eps", "load", "h"),
    [
        (0, 1.5, 0.5, 2.0, 0.7),
        (0, 0.0, 0.9, -3.0, 0.2),
        (1, 1.5, 0.5, 2.0, 0.7),
        (1, 0.3, 0.95, 4.0, 0.9),
    ],
)
def test_drive_derivatives(code, omega2, eps, load, h):
    w, p, dw, dp = spectral.drive_loads(code, omega2, eps, load, h)
    step = 1e-6
    wp, pp, _, _ = spectral.drive_loads(code, omega2, eps, load, h + step)
    wm, pm, _, _ = spectral.drive_loads(code, omega2, eps, load, h - step)
    assert dw == pytest.approx((wp - wm) / (2 * step), rel=FINITE_DIFFERENCE_RTOL, abs=1e-9)
    assert dp == pytest.approx((pp - pm) / (2 * step), rel=FINITE_DIFFERENCE_RTOL, abs=1e-9)
    assert spectral.drive_loads(2, w, 0.0, p, h) == (w, p, 0.0, 0.0)
