"""Optional dependencies: imported when a feature needs them, with an error that says how to
install them when they are missing (``import hairbed`` imports none of them).

The one table of which extra of pyproject.toml installs which optional module
(:data:`EXTRAS`), and the one import of them (:func:`optional_import`), for every room: the
sweeps' formats, the figures, the explorer and the command line.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["EXTRAS", "extra_of", "install_hint", "optional_import"]

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
    """``pip install 'hairbed[<extra>]'`` for an optional ``module`` (its top-level name a key
    of :data:`EXTRAS`)."""
    return f"pip install 'hairbed[{EXTRAS[module.split('.')[0]]}]'"


def extra_of(exc: ImportError) -> str | None:
    """The extra whose module ``exc`` failed to import, or None (not an optional one)."""
    return EXTRAS.get((exc.name or "").split(".")[0])


def optional_import(module: str, what: str, extra: str | None = None) -> Any:
    """Import ``module`` for ``what``, or raise an ImportError naming the extra to install.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"dask.array"``.
    what : str
        The feature that needs it, the message's subject ("a chunked sweep"; one ending in s
        takes "need": "figures need matplotlib").
    extra : str, optional
        The extra of pyproject.toml that installs it ("sweep"); by default the one of
        :data:`EXTRAS`.

    Raises
    ------
    ImportError
        ``<what> needs <package>: pip install 'hairbed[<extra>]'``, chained to the original,
        with ``name`` the package.

    Examples
    --------
    >>> optional_import("math", "a test").__name__
    'math'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        package = module.split(".")[0]
        hint = install_hint(package) if extra is None else f"pip install 'hairbed[{extra}]'"
        verb = "need" if what.endswith("s") else "needs"
        raise ImportError(f"{what} {verb} {package}: {hint}", name=package) from exc
