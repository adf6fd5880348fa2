"""``hairbed sweep --scheduler``: a sweep's blocks solved on a dask.distributed cluster."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

from ._report import CommandError, UsageError

__all__ = ["compute_on", "progress_bar"]


def progress_bar(total: int) -> Any:
    """A tqdm bar on stderr, shown once the work has run a second (with an ETA)."""
    from tqdm import tqdm

    from hairbed.sweeps import PROGRESS_DELAY

    return tqdm(
        total=total, unit="task", delay=PROGRESS_DELAY, file=sys.stderr, desc="hairbed sweep"
    )


def compute_on(
    address: str, build: Callable[[int | None, bool], Any], chunks: int, progress: bool
) -> Any:
    """The sweep ``build(chunks, progress)`` computed on the cluster at ``address``, gathered
    here."""
    try:
        import distributed
    except ImportError as exc:
        raise UsageError("--scheduler needs distributed: pip install 'hairbed[sweep]'") from exc
    try:
        client = distributed.Client(address, timeout="10s", set_as_default=True)
    except (OSError, TimeoutError, ValueError) as exc:
        message = " ".join(str(exc).split())
        raise UsageError(
            f"--scheduler: could not connect to a dask scheduler at {address!r} ({message})"
        ) from exc
    with client:
        try:
            # the workers' stderr is not ours: the bar follows the blocks' futures from here
            persisted = build(chunks, False).persist()
            futures = distributed.futures_of(persisted)
            if progress:
                with progress_bar(len(futures)) as bar:
                    for _ in distributed.as_completed(futures):
                        bar.update(1)
            return persisted.compute()
        except distributed.KilledWorker as exc:  # lost tasks are retried; this one no more
            first = " ".join(str(exc).split()).split(". ")[0]
            raise CommandError(
                f"sweep: workers of the dask scheduler at {address} died while computing it, "
                f"nothing written ({first})"
            ) from None
