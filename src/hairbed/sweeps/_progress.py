"""A progress bar for sweeps: tqdm on stderr, fed by the blocks as they finish."""

from __future__ import annotations

import importlib
import sys
import threading
from typing import Any


def _delay() -> float:
    # read from the package when a bar is made, so that setting
    # hairbed.sweeps.PROGRESS_DELAY takes effect (the package is imported: it called us)
    return float(importlib.import_module(__package__).PROGRESS_DELAY)


class Progress:
    """A tqdm bar on stderr fed by the blocks as they finish (ETA from the rate so far).

    Shown only once the work has run for ``delay`` seconds (default
    ``hairbed.sweeps.PROGRESS_DELAY``), so short sweeps print nothing. Thread-safe (the
    threaded scheduler's blocks report from their threads). A copy sent to another process
    (a distributed worker) reports nothing: its stderr is not the user's.
    """

    def __init__(
        self, total: int, delay: float | None = None, desc: str = "hairbed sweep"
    ) -> None:
        self.total = int(total)
        self.desc = desc
        self.delay = _delay() if delay is None else delay
        self._lock = threading.Lock()
        self._bar: Any = None
        self._done = 0

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (NoProgress, ())

    def start(self) -> None:
        with self._lock:
            if self._bar is None:
                from tqdm import tqdm

                self._bar = tqdm(
                    total=self.total,
                    unit="pt",
                    unit_scale=True,
                    delay=self.delay,
                    file=sys.stderr,
                    desc=self.desc,
                    dynamic_ncols=True,
                )

    def update(self, count: int) -> None:
        self.start()
        with self._lock:
            self._bar.update(count)
            self._done += count
            if self._done >= self.total:  # a second compute of the dataset gets a new bar
                self._bar.close()
                self._bar, self._done = None, 0


class NoProgress:
    """What a :class:`Progress` becomes in another process: reports nothing."""

    def start(self) -> None:
        pass

    def update(self, count: int) -> None:
        pass
