"""The one place where hairbed's numba options live.

Every compiled kernel of the package is declared with :func:`kernel`, which is
``numba.njit(nogil=True, cache=True, error_model="numpy")`` (IEEE division: x/0 is inf or
NaN, as in numpy, without a Python exception check on every division) with two safeguards:

* **Stale caches cannot give wrong answers.** numba keys a cached kernel on the source of the
  file that defines it, but a kernel inlines the kernels it calls from other files: after an
  edit of ``_kernels/elliptic.py`` a cached ``_kernels/roots.py`` kernel would still hold the
  old code. Here every kernel's cache is keyed on the SHA-256 of all the kernel sources
  together (the files of ``hairbed._core._kernels`` and this one), so any edit recompiles all.
* **Caching can be switched off**: ``HAIRBED_NUMBA_CACHE=0`` in the environment (cached kernels
  have crashed dask workers in other libraries, sgkit issues #869 and #1156). The cache lives in
  ``__pycache__`` beside the kernel sources, or in the user's cache directory when that is
  not writable (``NUMBA_CACHE_DIR`` is honoured).
* **A damaged cache cannot stop a computation.** numba unpickles its index and data files
  unguarded: a truncated or foreign file (a full disk, an interrupted copy, another version)
  raised ``UnpicklingError`` from ``hairbed.solve``. Here a cache file that cannot be read is
  removed and the kernel compiled anew (and cached again); a cache that cannot be written
  costs the next process a compilation, never an error.
* **No cache is said once.** In an install whose site-packages is read-only, with no writable
  user cache directory either (a container's read-only HOME), every process compiles the
  kernels again (about a minute); one line on stderr says so and names ``NUMBA_CACHE_DIR``,
  once per process however many kernels there are (none with ``HAIRBED_NUMBA_CACHE=0``).

Kernels compile lazily, on their first call, so ``import hairbed`` compiles nothing.
``NUMBA_DISABLE_JIT=1`` runs every kernel as plain Python (the tests use it for coverage).
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numba
from numba.core import caching, config
from numba.misc.appdirs import AppDirs

__all__ = ["CACHE_ENABLED", "kernel", "kernel_sources_hash"]

F = TypeVar("F", bound=Callable[..., Any])

_HERE = Path(__file__).resolve().parent
_KERNEL_DIR = _HERE / "_kernels"

#: False when HAIRBED_NUMBA_CACHE is 0, false, no or off.
CACHE_ENABLED = os.environ.get("HAIRBED_NUMBA_CACHE", "1").strip().lower() not in (
    "0",
    "false",
    "no",
    "off",
)


@functools.lru_cache(maxsize=1)
def kernel_sources_hash() -> str:
    """SHA-256 over the kernel sources (``_kernels/*.py`` and this file), read once."""
    digest = hashlib.sha256()
    for path in sorted([*_KERNEL_DIR.glob("*.py"), Path(__file__).resolve()]):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


class _KernelStampMixin:
    """Source stamp = hash of every kernel source, not only the defining file."""

    def get_source_stamp(self) -> str:
        return kernel_sources_hash()


class _InTreeLocator(_KernelStampMixin, caching.InTreeCacheLocator):
    pass


class _UserWideLocator(_KernelStampMixin, caching.UserWideCacheLocator):
    pass


class _UserProvidedLocator(_KernelStampMixin, caching.UserProvidedCacheLocator):
    pass


class _KernelCacheImpl(caching.CompileResultCacheImpl):
    _locator_classes = [_UserProvidedLocator, _InTreeLocator, _UserWideLocator]


class _KernelCache(caching.FunctionCache):
    _impl_class = _KernelCacheImpl

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        try:
            return super().load_overload(sig, target_context)
        except Exception:  # a damaged index or data file: drop them all, compile anew
            index = Path(self._cache_file._index_path)
            for path in [index, *index.parent.glob(f"{index.stem}.*.nbc")]:
                try:
                    path.unlink()
                except OSError:
                    pass
            return None

    def save_overload(self, sig: Any, data: Any) -> None:
        try:
            super().save_overload(sig, data)
        except Exception:  # an unreadable old index, a full disk: the next run compiles
            pass


#: Set once the "cannot cache" line has been written (one line per process).
_SAID_NO_CACHE: list[bool] = []


def _say_no_cache() -> None:
    """One line on stderr: the kernels cannot be cached here, and what to do about it."""
    if _SAID_NO_CACHE:
        return
    _SAID_NO_CACHE.append(True)
    user = AppDirs(appname="numba", appauthor=False).user_cache_dir
    where = f"{_KERNEL_DIR / '__pycache__'} and {user}"
    chosen = getattr(config, "CACHE_DIR", "")  # NUMBA_CACHE_DIR
    if chosen:
        where = f"{chosen}, {where}"
    sys.stderr.write(
        f"hairbed: cannot cache the compiled kernels (none of {where} is writable): every "
        "process compiles them again (about a minute); set NUMBA_CACHE_DIR to a writable "
        "directory (or HAIRBED_NUMBA_CACHE=0 to compile without this note)\n"
    )


def kernel(func: F | None = None, **options: Any) -> Any:
    """Compile ``func`` as a hairbed kernel: ``numba.njit(nogil=True)``, cached (see above).

    Extra keyword options go to ``numba.njit`` (for instance ``inline="always"`` for tiny
    helpers). Usable bare (``@kernel``) or with options (``@kernel(inline="always")``).
    """

    def wrap(f: F) -> Any:
        dispatcher = numba.njit(nogil=True, cache=False, error_model="numpy", **options)(f)
        if CACHE_ENABLED and not getattr(config, "DISABLE_JIT", 0):  # set at numba's import
            try:
                dispatcher._cache = _KernelCache(dispatcher.py_func)
            except RuntimeError:  # no writable cache location: compile every time
                _say_no_cache()
        return dispatcher

    return wrap(func) if func is not None else wrap
