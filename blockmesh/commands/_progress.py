"""Progress of a command's stages on stderr: a line for every stage that runs over a second.

``with progress.stage("writing vtu") as tick:`` runs a stage; ``tick(done, total)`` (optional)
reports how far it is. A background thread draws the stage's line (a bar when the stage reports
fractions, the elapsed time otherwise) once the stage has run for :data:`SHOW_AFTER` seconds, and
ends it with the stage's time; quick stages print nothing. Drawn only on a terminal and without
``--json`` (:meth:`StageProgress.wanted`).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import threading
import time
from collections.abc import Callable, Iterator

__all__ = ["SHOW_AFTER", "StageProgress", "printable"]

#: Seconds a stage runs before its line appears.
SHOW_AFTER = 1.0
_TICK = 0.2
_WIDTH = 30


def printable(text: str, *, keep: str = "") -> str:
    r"""``text`` with control characters shown as escapes, safe to print on a terminal.

    Examples
    --------
    >>> print(printable("ring\x1b[2J"))
    ring\x1b[2J
    """
    return "".join(c if c.isprintable() or c in keep else repr(c)[1:-1] for c in text)


class StageProgress:
    """Progress lines for the stages of one command, prefixed with ``prefix``."""

    def __init__(self, prefix: str, *, enabled: bool, stream=None) -> None:
        self.prefix = prefix
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        self._lock = threading.Lock()
        self._label = ""
        self._started = 0.0
        self._fraction: tuple[int, int] | None = None
        self._shown = False

    @staticmethod
    def wanted(args: argparse.Namespace) -> bool:
        """True when stderr is a terminal and no JSON was asked for."""
        return sys.stderr.isatty() and not getattr(args, "json", False)

    def _draw(self, final: bool = False) -> None:
        elapsed = time.perf_counter() - self._started
        if self._fraction is not None:
            done, total = self._fraction
            filled = int(_WIDTH * done / max(total, 1))
            bar = f" [{'#' * filled}{'.' * (_WIDTH - filled)}] {done:,}/{total:,}"
        else:
            bar = " ..."
        end = f" done in {elapsed:.1f} s\n" if final else f" {elapsed:6.1f} s"
        self.stream.write(f"\r{self.prefix}: {self._label}{bar}{end}")
        self.stream.flush()
        self._shown = True

    def _watch(self, stop: threading.Event) -> None:
        while not stop.wait(_TICK):
            with self._lock:
                if time.perf_counter() - self._started >= SHOW_AFTER:
                    self._draw()

    @contextlib.contextmanager
    def stage(self, label: str) -> Iterator[Callable[[int, int], None]]:
        """Run one stage; yields ``tick(done, total)``."""

        def tick(done: int, total: int) -> None:
            with self._lock:
                self._fraction = (done, total)

        if not self.enabled:
            yield tick
            return
        with self._lock:
            self._label, self._started, self._fraction, self._shown = (
                printable(label),
                time.perf_counter(),
                None,
                False,
            )
        stop = threading.Event()
        watcher = threading.Thread(target=self._watch, args=(stop,), daemon=True)
        watcher.start()
        finished = False
        try:
            yield tick
            finished = True
        finally:
            stop.set()
            watcher.join()
            with self._lock:
                # A stage past SHOW_AFTER gets its line even when the watcher never ran (a
                # loaded machine can starve the thread for the whole stage).
                due = self._shown or time.perf_counter() - self._started >= SHOW_AFTER
                if due and finished:
                    self._draw(final=True)
                elif due:
                    if not self._shown:
                        self._draw()
                    self.stream.write("\n")
                    self.stream.flush()
