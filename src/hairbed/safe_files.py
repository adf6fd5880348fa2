"""Files written whole or not at all: a temporary file beside the target, then a rename.

Every file hairbed writes (sweep tables, figures, benchmark JSON) goes through
:func:`atomic_path`: the writer fills a temporary file (or, for a ``.zarr`` store, a
temporary directory) in the target's own directory, named ``.<name>.<random>.tmp<suffix>``
(the suffix kept, so that libraries that look at it still see the format); when the writer
returns, its data are flushed to disk (``fsync``) and the temporary is renamed onto the
target (``os.replace``, atomic on POSIX), then the directory entry is flushed too. If the
writer fails or is interrupted (Ctrl-C is a ``KeyboardInterrupt``, a ``BaseException``), the
temporary is removed and the target, if it existed, is left exactly as it was: a reader
never sees a half-written file.

A directory cannot be renamed onto a non-empty one, so a store that already exists is
first renamed aside, the new one renamed into place, then the old one removed; Ctrl-C is
held back during those two renames, so an interrupt cannot leave the target missing.

A full disk is reported as what it is. Some writers turn the ``ENOSPC`` of the operating
system into an error of their own (netCDF-4/HDF5: ``RuntimeError: NetCDF: HDF error``, and
now and then ``PermissionError`` on the temporary it was just given): when a writer fails with
anything but ``ENOSPC`` while the target's file system has no space left for it,
:func:`atomic_path` raises ``OSError(ENOSPC)`` naming the target instead (the writer's error
chained as its cause), so a caller needs to catch ``OSError`` only.

Examples
--------
>>> import pathlib, tempfile
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> with atomic_path(folder / "a.txt") as tmp:
...     _ = tmp.write_text("whole")
>>> (folder / "a.txt").read_text(), sorted(p.name for p in folder.iterdir())
('whole', ['a.txt'])
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "remove_unfinished", "temporary_names", "write_bytes", "write_text"]

#: Marker in the names of the temporaries (``.<name>.<random>.tmp<suffix>``).
TMP_MARK = ".tmp"

#: The temporaries of the writes under way in this process (for :func:`remove_unfinished`).
_UNFINISHED: dict[Path, None] = {}


def remove_unfinished() -> list[Path]:
    """Remove the temporaries of every write still under way; returns their paths.

    For a program that ends at once on Ctrl-C (``os._exit`` in a signal handler, as the
    ``hairbed`` command does) instead of unwinding: a library that is mid-write (a chunked
    netCDF file, whose worker threads hold its locks) need not be waited for, and no
    temporary is left behind. Targets are never touched: a rename onto a target runs with
    Ctrl-C held back (see the module docstring), so a handler runs before it or after it.
    """
    paths = list(_UNFINISHED)
    for path in paths:
        _remove(path)
        _UNFINISHED.pop(path, None)
    return paths


def temporary_names(target: str | os.PathLike[str]) -> list[Path]:
    """Temporaries of ``target`` present in its directory (normally none: for tests)."""
    target = Path(target)
    prefix = f".{target.name}."
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        return []
    return sorted(p for p in parent.iterdir() if p.name.startswith(prefix) and TMP_MARK in p.name)


def _fsync_path(path: Path, directory: bool = False) -> None:
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:  # some file systems do not open directories: nothing to flush then
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _fsync_tree(path: Path) -> None:
    """fsync every file and directory under ``path`` (a directory store), deepest first."""
    for root, _dirs, files in os.walk(path, topdown=False):
        for name in files:
            _fsync_path(Path(root) / name)
        _fsync_path(Path(root), directory=True)


def _remove(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        # a writer's worker threads may still add files to a directory store while it is
        # removed (Ctrl-C during a chunked zarr write): again until it is gone
        for _ in range(100):
            shutil.rmtree(path, ignore_errors=True)
            if not path.exists():
                break
    else:
        try:
            path.unlink()
        except FileNotFoundError:
            pass


#: Free space [bytes] under which a writer's failure is taken for a full file system.
FULL_BELOW = 1 << 20


def _disk_full(parent: Path) -> bool:
    """True when the file system of ``parent`` has (nearly) no space left for a writer.

    Asked while the writer's temporary still exists (it holds the space it took). Nearly: a
    writer stops at the first block it cannot allocate, which need not be the last free byte.
    """
    try:
        st = os.statvfs(parent)
    except (OSError, AttributeError):  # no statvfs (Windows) or the directory is gone
        return False
    return st.f_bavail * st.f_frsize < FULL_BELOW


def _names_nothing_or_tmp(exc: OSError, tmp: Path) -> bool:
    """True when ``exc`` names no file (a failed ``write``) or the temporary (or within it)."""
    if exc.filename is None:
        return True
    try:
        name = Path(os.fsdecode(exc.filename))
    except TypeError:  # a file descriptor
        return False
    return name == tmp or tmp in name.parents


@contextmanager
def _sigint_held() -> Iterator[None]:
    """Defer Ctrl-C until the block ends (main thread only; elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    try:
        previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    except (ValueError, OSError):  # no signals here (e.g. an embedded interpreter)
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if caught:  # now the handler that was held back: whatever it does (or ignoring it)
            signal.raise_signal(signal.SIGINT)


@contextmanager
def atomic_path(target: str | os.PathLike[str], *, directory: bool = False) -> Iterator[Path]:
    """A temporary path beside ``target`` that becomes ``target`` when the block succeeds.

    Parameters
    ----------
    target : path-like
        The file (or, with ``directory=True``, the directory store) to write. Its directory
        must exist.
    directory : bool, optional
        The writer creates a directory (a ``.zarr`` store) rather than a file. The temporary
        path is then free: the writer creates it.

    Yields
    ------
    pathlib.Path
        Where the writer must write. For a file it exists (empty); for a directory it does not.

    Raises
    ------
    FileNotFoundError
        If the target's directory does not exist.
    IsADirectoryError, NotADirectoryError
        If the target exists and is a directory where a file is expected or vice versa.
    OSError
        Whatever the writer or the rename raises; ``errno.ENOSPC`` (with ``filename`` the
        target) whenever the writer fails on a full file system (module docstring).
    """
    target = Path(target)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"directory {str(parent)!r} of {str(target)!r} does not exist")
    if target.exists() and target.is_dir() != directory:
        kind = "a directory" if target.is_dir() else "a file"
        error = IsADirectoryError if target.is_dir() else NotADirectoryError
        raise error(f"{str(target)!r} exists and is {kind}")
    prefix, suffix = f".{target.name}.", f"{TMP_MARK}{target.suffix}"
    try:
        if directory:
            tmp = Path(tempfile.mkdtemp(prefix=prefix, suffix=suffix, dir=parent))
            tmp.rmdir()  # the writer creates it (stores refuse to write into an existing one)
        else:
            fd, name = tempfile.mkstemp(prefix=prefix, suffix=suffix, dir=parent)
            os.close(fd)
            tmp = Path(name)
    except OSError as exc:  # read-only, full, no permission: say so of the target
        raise type(exc)(exc.errno, exc.strerror, str(target)) from None
    _UNFINISHED[tmp] = None
    try:
        yield tmp
        if directory:
            if not tmp.is_dir():
                raise FileNotFoundError(f"the writer created no directory {str(tmp)!r}")
            _fsync_tree(tmp)
            old: Path | None = None
            try:
                with _sigint_held():  # the two renames (and a restore): all or nothing
                    try:
                        if target.exists():
                            old = Path(
                                tempfile.mkdtemp(prefix=prefix, suffix=".tmp.old", dir=parent)
                            )
                            _UNFINISHED[old] = None  # garbage once both renames are done
                            os.replace(target, old)  # onto an empty directory: allowed
                        os.replace(tmp, target)
                        _UNFINISHED.pop(tmp, None)
                    except BaseException:
                        if old is not None and not target.exists():  # put the old store back
                            os.replace(old, target)
                            _UNFINISHED.pop(old, None)
                            old = None
                        raise
            finally:
                if old is not None:
                    _remove(old)
                    _UNFINISHED.pop(old, None)
        else:
            _fsync_path(tmp)
            try:  # mkstemp makes the file private (0600); give it the usual permissions
                umask = os.umask(0)
                os.umask(umask)
                os.chmod(tmp, 0o666 & ~umask)
            except OSError:
                pass
            os.replace(tmp, target)
            _UNFINISHED.pop(tmp, None)
        _fsync_path(parent, directory=True)
    except Exception as exc:
        enospc = isinstance(exc, OSError) and exc.errno == errno.ENOSPC
        full = not enospc and _disk_full(parent)
        _remove(tmp)
        if isinstance(exc, OSError) and _names_nothing_or_tmp(exc, tmp):
            exc.filename = str(target)  # the file the caller asked for, not a temporary
        if full:
            reason = f"{os.strerror(errno.ENOSPC)} ({type(exc).__name__}: {exc})"
            raise OSError(errno.ENOSPC, reason, str(target)) from exc
        raise
    except BaseException:
        _remove(tmp)
        raise
    finally:
        _UNFINISHED.pop(tmp, None)


def write_bytes(target: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``target`` whole or not at all."""
    with atomic_path(target) as tmp, open(tmp, "wb") as fh:
        fh.write(data)


def write_text(target: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``target`` whole or not at all."""
    write_bytes(target, text.encode(encoding))
