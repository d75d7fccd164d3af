"""Signals that stop a command (Ctrl-C, SIGTERM, SIGHUP), recorded so nothing can swallow them.

Python raises :class:`KeyboardInterrupt` wherever the main thread is when Ctrl-C arrives. When
that is inside a finaliser (a ``__del__`` or a weak-reference callback: h5py drops its objects
through ``WeakValueDictionary`` callbacks while an HDF5 file closes), the interpreter prints
"Exception ignored in: ..." and carries on, so a write that was interrupted finishes and the
command exits 0.

While :func:`stop_on_signals` is active, SIGINT, SIGTERM and SIGHUP are *recorded* before they
raise (:class:`KeyboardInterrupt`; :class:`Terminated` for the other two), and a report of one
swallowed in a finaliser is kept quiet. :func:`raise_pending` raises a recorded signal again: the
atomic writers (:mod:`blockmesh._system.atomic`) call it just before the rename that commits an
output, so an interrupted write leaves no output, and the command line calls it when a command
returns.
Outside :func:`stop_on_signals` (the library used from Python), nothing is recorded and
:func:`raise_pending` does nothing.

Examples
--------
>>> with stop_on_signals():
...     pending()
>>> raise_pending()  # nothing recorded: returns
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator
from types import FrameType
from typing import Any

__all__ = ["Terminated", "pending", "raise_pending", "stop_on_signals"]


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP arrived: unwound like Ctrl-C, so no output is left half-written."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


#: The signal recorded while :func:`stop_on_signals` is active (None: none arrived).
_received: list[int] = []


def pending() -> int | None:
    """The number of the signal that arrived while :func:`stop_on_signals` ran, or None."""
    return _received[0] if _received else None


def _interrupt(signum: int) -> KeyboardInterrupt:
    return KeyboardInterrupt() if signum == signal.SIGINT else Terminated(signum)


def raise_pending() -> None:
    """Raise the recorded signal's exception again, if a signal arrived; else return.

    Called before an output is committed and when a command returns: a signal whose exception a
    finaliser swallowed still stops the command.
    """
    signum = pending()
    if signum is not None:
        raise _interrupt(signum)


def _record(signum: int, _frame: FrameType | None) -> None:
    if not _received:
        _received.append(signum)
    raise _interrupt(signum)


def _quiet_when_recorded(previous: Any) -> Any:
    """An ``unraisablehook`` that drops the report of a recorded signal's swallowed exception."""

    def hook(report: Any) -> None:
        if _received and isinstance(report.exc_value, KeyboardInterrupt):
            return  # acted on by raise_pending(); the report would only alarm
        previous(report)

    return hook


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Record and raise SIGINT, SIGTERM and SIGHUP in the block (main thread only).

    A signal that was ignored (``SIG_IGN``, e.g. SIGHUP under ``nohup``) stays ignored.
    The previous handlers and ``sys.unraisablehook`` are restored afterwards, and the record is
    cleared.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    names = ("SIGINT", "SIGTERM", "SIGHUP")
    wanted = [getattr(signal, name) for name in names if hasattr(signal, name)]
    _received.clear()
    # A signal ignored when the command started (nohup, a background job) stays ignored.
    wanted = [signum for signum in wanted if signal.getsignal(signum) is not signal.SIG_IGN]
    previous = {signum: signal.signal(signum, _record) for signum in wanted}
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _quiet_when_recorded(previous_hook)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        sys.unraisablehook = previous_hook
        _received.clear()
