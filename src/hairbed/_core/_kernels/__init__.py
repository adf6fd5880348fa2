"""Compiled kernels of the exact solver (numba, declared with ``hairbed._core._jit.kernel``).

The kernels trust their inputs: validation happens in the Python wrappers before a kernel
is called. Every kernel works on one element; the array drivers loop over elements inside
compiled code, so scalars and arrays run the same arithmetic and agree bitwise.
"""

__all__ = ["FIELDS"]

#: The columns of every solving kernel's output, in order: one list that the kernels write and
#: :class:`hairbed.Solution` reads (this module imports nothing, so reading it
#: compiles and loads nothing).
FIELDS = (
    "t",
    "n_roots",
    "status",
    "omega2",
    "xi",
    "omega_eps",
    "energy",
    "tip_height",
    "tip_deflection",
    "tip_displacement",
    "tip_angle",
    "base_curvature",
)
