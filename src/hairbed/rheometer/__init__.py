"""The bed in a rheometer (issue 31, section 2).

- :func:`analyse_laos`: the analysis of a periodic stress under a sinusoidal strain
  (large-amplitude oscillatory shear): Fourier harmonics I_n/I_1 and their phases, odd and
  even (a tilted bed is not symmetric), the elastic and viscous stresses of Cho et al.
  (2005), Ewoldt's Chebyshev coefficients e_n, v_n and G'_M, G'_L, eta'_M, eta'_L (Ewoldt,
  Hosoi & McKinley 2008), and the Lissajous-Bowditch curves. Solver-independent.
"""

from __future__ import annotations

from ._laos import LAOS_STATUS, STRAIN_SINE_TOL, LAOSAnalysis, analyse_laos

__all__ = [
    "LAOS_STATUS",
    "STRAIN_SINE_TOL",
    "LAOSAnalysis",
    "analyse_laos",
]
