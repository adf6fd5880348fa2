"""Optional dependencies: the one table of which extra installs what, and their import.

``import hairbed`` needs only numpy, scipy and numba; sweeps' formats, figures and the
explorer need modules of the extras of pyproject.toml. An absent one is an ImportError whose
message names the module and the ``pip install 'hairbed[<extra>]'`` that brings it.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["EXTRAS", "extra_of", "install_hint", "require"]

#: Optional module (top-level name) -> the extra of pyproject.toml that installs it.
EXTRAS: dict[str, str] = {
    "matplotlib": "plot",
    "xarray": "sweep",
    "dask": "sweep",
    "distributed": "sweep",
    "netCDF4": "sweep",
    "zarr": "sweep",
    "pyarrow": "sweep",
    "tqdm": "sweep",
    "panel": "app",
    "bokeh": "app",
    "param": "app",
}


def install_hint(module: str) -> str:
    """``pip install 'hairbed[<extra>]'`` for an optional ``module`` (a key of EXTRAS)."""
    return f"pip install 'hairbed[{EXTRAS[module.split('.')[0]]}]'"


def extra_of(exc: ImportError) -> str | None:
    """The extra whose module ``exc`` failed to import, or None (not an optional one)."""
    name = (exc.name or "").split(".")[0]
    return EXTRAS.get(name)


def require(module: str, what: str) -> ModuleType:
    """Import the optional ``module``, or raise the ImportError that says how to install it.

    Parameters
    ----------
    module : str
        A module of an extra, e.g. ``"pyarrow.parquet"`` (its top-level name is in EXTRAS).
    what : str
        What needs it, the message's subject: ``"parquet output needs pyarrow: ..."`` (a
        subject ending in s takes "need": ``"figures need matplotlib: ..."``).

    Examples
    --------
    >>> require("math", "a test").__name__
    'math'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        verb = "need" if what.endswith("s") else "needs"
        raise ImportError(f"{what} {verb} {top}: {install_hint(top)}", name=top) from exc
