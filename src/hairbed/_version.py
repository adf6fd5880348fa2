"""The version of hairbed, written here only (``hairbed.__version__``, pyproject's dynamic
version and every file hairbed writes read it from here)."""

__version__ = "0.1.0"
