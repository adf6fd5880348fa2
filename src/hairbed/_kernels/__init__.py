"""Compiled kernels of the exact solver (numba, declared with ``hairbed._jit.kernel``).

The kernels trust their inputs: validation happens in the Python wrappers before a kernel
is called. Every kernel works on one element; the array drivers loop over elements inside
compiled code, so scalars and arrays run the same arithmetic and agree bitwise.
"""
