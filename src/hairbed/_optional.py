"""Optional dependencies: imported when a feature needs them, with an error that says how to
install them when they are missing (``import hairbed`` imports none of them)."""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["optional_import"]


def optional_import(module: str, what: str, extra: str) -> Any:
    """Import ``module`` for ``what``, or raise an ImportError naming the extra to install.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"dask.array"``.
    what : str
        The feature that needs it, for the message ("a chunked sweep").
    extra : str
        The extra of pyproject.toml that installs it ("sweep").

    Raises
    ------
    ImportError
        ``<what> needs <package>: pip install 'hairbed[<extra>]'``, chained to the original.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        package = module.split(".")[0]
        raise ImportError(f"{what} needs {package}: pip install 'hairbed[{extra}]'") from exc
