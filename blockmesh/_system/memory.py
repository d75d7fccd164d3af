"""Memory of this process and of the machine, and byte counts written for people.

What is available (``MemAvailable``), what this process holds (``VmRSS``) and held at most
(``VmHWM``), read through :mod:`blockmesh._system.procfs`; the predictions of what a command will
need are in :mod:`blockmesh.refinement.sizes`.

Examples
--------
>>> available_memory() > 0, process_rss() > 0
(True, True)
>>> format_bytes(1_234_567), format_count(1_679_616)
('1.2 MB', '1,679,616')
"""

from __future__ import annotations

import math
import os

from blockmesh._system.procfs import proc_kilobytes

__all__ = [
    "available_memory",
    "format_bytes",
    "format_count",
    "peak_rss",
    "process_rss",
    "reset_peak_rss",
]


def available_memory() -> int:
    """Bytes of memory available to this process now (``MemAvailable`` on Linux).

    Examples
    --------
    >>> available_memory() > 0
    True
    """
    available = proc_kilobytes("/proc/meminfo", "MemAvailable")
    if available is not None:
        return available
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1 << 62


def format_bytes(n: int | float) -> str:
    """A byte count for people: ``"1.2 GB"``; from 10^15 on, the power of ten.

    Examples
    --------
    >>> format_bytes(999), format_bytes(1_234_567), format_bytes(6**300)
    ('999 B', '1.2 MB', '10^233 B')
    """
    if n >= 1e15:
        return f"10^{_log10(n)} B"
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1000
    raise AssertionError  # pragma: no cover


def format_count(n: int) -> str:
    """A count with thousands separators; beyond 10^15 as a power of ten (no 200-digit numbers).

    Examples
    --------
    >>> format_count(1_679_616), format_count(6**1000)
    ('1,679,616', '10^778')
    """
    return f"{n:,}" if n < 10**15 else f"10^{_log10(n)}"


def _log10(n: int | float) -> int:
    return int(math.log10(n)) if n > 0 else 0


def process_rss() -> int:
    """Resident bytes of this process now (``VmRSS``; 0 where ``/proc`` is missing).

    Examples
    --------
    >>> process_rss() > 0
    True
    """
    return proc_kilobytes("/proc/self/status", "VmRSS") or 0


def peak_rss() -> int:
    """Peak resident bytes of this process (``VmHWM``, resettable by :func:`reset_peak_rss`)."""
    peak = proc_kilobytes("/proc/self/status", "VmHWM")
    if peak is not None:
        return peak
    import resource

    return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024


def reset_peak_rss() -> bool:
    """Restart the peak (``VmHWM``) from the current resident set; False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as handle:
            handle.write("5")
    except OSError:
        return False
    return True
