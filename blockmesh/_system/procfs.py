"""The one reader of ``/proc`` files: a named field of ``/proc/self/status`` or ``/proc/meminfo``.

Linux's ``/proc`` files are lines ``Name:   value [unit]``. Every caller that needs one (the
resident set, the peak, the memory available, the file-creation mask) asks :func:`proc_field`,
which returns None where the file or the field is missing (another system, a sandbox), so that
each caller states its own fallback.

Examples
--------
>>> words = proc_field("/proc/self/status", "VmRSS")
>>> words is None or words[1] == "kB"
True
"""

from __future__ import annotations

__all__ = ["proc_field", "proc_kilobytes", "umask"]


def proc_field(path: str, name: str) -> list[str] | None:
    """The words after ``name:`` on its line of the ``/proc`` file ``path`` (None if missing)."""
    prefix = name + ":"
    try:
        with open(path, encoding="ascii", errors="replace") as handle:
            for line in handle:
                if line.startswith(prefix):
                    return line[len(prefix) :].split()
    except OSError:
        return None
    return None


def proc_kilobytes(path: str, name: str) -> int | None:
    """A ``kB`` field of a ``/proc`` file in bytes (None if missing or not a number)."""
    words = proc_field(path, name)
    if not words or not words[0].isdigit():
        return None
    return int(words[0]) * 1024


def umask() -> int:
    """The process's file-creation mask, read without changing it (0o022 where unknown).

    Examples
    --------
    >>> 0 <= umask() <= 0o777
    True
    """
    words = proc_field("/proc/self/status", "Umask")
    try:
        return int(words[0], 8) if words else 0o022
    except ValueError:
        return 0o022
