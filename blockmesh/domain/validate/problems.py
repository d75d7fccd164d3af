"""How the checks report: every problem of a stage at once, each on its own line.

The checks of domain input (:mod:`blockmesh.domain.validate`) collect the problems they find and
raise them together with :func:`raise_problems`, so that a user fixes a file in one pass rather
than one error at a time.

Examples
--------
>>> raise_problems(ValueError, ["vertex 1 is bad", "vertex 4 is bad"])
Traceback (most recent call last):
...
ValueError: 2 problems:
  vertex 1 is bad
  vertex 4 is bad
"""

from __future__ import annotations

__all__ = ["raise_problems", "shortened"]

#: Most problems listed in one message.
_MAX_LISTED = 8


def raise_problems(kind: type[Exception], problems: list[str]) -> None:
    """Raise ``kind`` listing ``problems`` (at most eight shown), or nothing when there are none."""
    if not problems:
        return
    if len(problems) == 1:
        raise kind(problems[0])
    shown = problems[:_MAX_LISTED]
    more = len(problems) - len(shown)
    tail = f"\n  ... and {more} more" if more else ""
    raise kind(f"{len(problems)} problems:\n  " + "\n  ".join(shown) + tail)


def shortened(item: object) -> str:
    """``repr(item)``, cut to 60 characters for a message."""
    text = repr(item)
    return text if len(text) <= 60 else text[:57] + "..."
