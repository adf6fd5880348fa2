"""The bed in a rheometer (issue 31, section 2).

- :func:`analyse_laos`: the analysis of a periodic stress under a sinusoidal strain
  (large-amplitude oscillatory shear): Fourier harmonics I_n/I_1 and their phases, odd and
  even (a tilted bed is not symmetric), the elastic and viscous stresses of Cho et al.
  (2005), Ewoldt's Chebyshev coefficients e_n, v_n and G'_M, G'_L, eta'_M, eta'_L (Ewoldt,
  Hosoi & McKinley 2008), and the Lissajous-Bowditch curves. Solver-independent.
- :func:`oscillatory_shear`: small-amplitude oscillatory shear of the porous bed about a
  pre-stress: G'(omega), G''(omega), the phase lag or lead against the wall's speed and the
  crossovers, from the linear bed (:func:`hairbed.dynamics.linearise_bed`);
  :func:`bed_moduli` the same in SI for a :class:`hairbed.HairBed` [Pa, Hz].
- :func:`large_amplitude_shear`: the bed's periodic steady state under a large oscillatory
  strain (:func:`hairbed.dynamics.periodic_bed`, collocation in time; or
  :func:`hairbed.dynamics.simulate_bed` until the transient decays), analysed by
  :func:`analyse_laos`; :func:`pipkin_map` over frequency and amplitude.
- :func:`bed_laos` and :func:`bed_pipkin_map`: the same for a :class:`hairbed.HairBed` in SI
  (frequency [Hz], stress and moduli [Pa], viscosities [Pa s], strain rate [1/s]).
"""

from __future__ import annotations

from ._laos import LAOS_STATUS, STRAIN_SINE_TOL, LAOSAnalysis, analyse_laos
from ._large import (
    LARGE_STATUS,
    LargeAmplitudeShear,
    PipkinMap,
    large_amplitude_shear,
    pipkin_map,
)
from ._saos import SAOS_STATUS, BedModuli, OscillatoryShear, bed_moduli, oscillatory_shear
from ._si import BedLAOS, BedPipkinMap, bed_laos, bed_pipkin_map

__all__ = [
    "LAOS_STATUS",
    "STRAIN_SINE_TOL",
    "LAOSAnalysis",
    "analyse_laos",
    "SAOS_STATUS",
    "OscillatoryShear",
    "oscillatory_shear",
    "BedModuli",
    "bed_moduli",
    "LARGE_STATUS",
    "LargeAmplitudeShear",
    "PipkinMap",
    "large_amplitude_shear",
    "pipkin_map",
    "BedLAOS",
    "BedPipkinMap",
    "bed_laos",
    "bed_pipkin_map",
]
