"""The load description of one element: the one vocabulary of every collocation kernel.

A rod clamped at theta0 is loaded by parts that each model contributes (theory.md §11-§13):
a horizontal tip force, a load per unit height, the resistive-force drag of a flow, the
fluid of a porous bed. A kernel reads one row ``desc[e]`` of ``NDESC`` named slots per
element; each model fills the slots of its own parts and leaves the others at zero, and no
model carries one quantity in another's slot.

=========  ==========================================================================
slot       meaning (load units of theory.md)
=========  ==========================================================================
D_THETA0   the clamp angle theta0 [rad]
D_OMEGA2   omega^2, the wall's drive of a bed (the gap's shear stress at rest)
D_EPS      eps = L/H, the hair's length over the channel's height
D_PI       Pi, the pressure gradient's load per unit height (pressure drive, input)
D_Q        q, the set flow rate (flow drive; Pi is then an unknown)
D_TIP      a horizontal tip force (a bed's frozen tip load in a scan, a pillar's tip load)
D_LAMBDA   Lambda, the pillar's drag forcing (zeta_perp U L^3/(E I) of the profile U)
D_GAMMA    gamma = zeta_par/zeta_perp, the drag's anisotropy (1: isotropic)
D_X1       the target tip deflection of the porous bed's inverse (its forcing then an unknown)
D_KAPPA    kappa = k/L^2, the porous bed's permeability
D_HFIX     a porous scan's frozen tip height seen by the gap (NaN: free)
D_DX1      the target tip displacement x1 - sin(theta0) of the pillar's inverse (Lambda then
           an unknown): carried apart from x1, which rounds it away near the wall
=========  ==========================================================================
"""

from __future__ import annotations

__all__ = [
    "D_DX1",
    "D_EPS",
    "D_GAMMA",
    "D_HFIX",
    "D_KAPPA",
    "D_LAMBDA",
    "D_OMEGA2",
    "D_PI",
    "D_Q",
    "D_THETA0",
    "D_TIP",
    "D_X1",
    "NDESC",
]

D_THETA0 = 0
D_OMEGA2 = 1
D_EPS = 2
D_PI = 3
D_Q = 4
D_TIP = 5
D_LAMBDA = 6
D_GAMMA = 7
D_X1 = 8
D_KAPPA = 9
D_HFIX = 10
D_DX1 = 11
NDESC = 12
