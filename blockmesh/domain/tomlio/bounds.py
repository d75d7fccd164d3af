"""A domain file read within bounds: its kind, its size, its nesting, its numbers, its corners.

A domain file may come from anywhere: :func:`read_text_bounded` opens only a regular file of at
most :data:`MAX_FILE_BYTES`, and :func:`check_limits` scans the text before the TOML parser sees
it, for arrays and tables nested deeper than :data:`MAX_NESTING`, integers of more than
:data:`MAX_DIGITS` digits and polygons of more corners than the decomposition takes.

Examples
--------
>>> check_limits("polygon = " + "[" * 20 + "]" * 20, "inline")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: inline: arrays or tables nest more than 16 deep at line 1, ...
"""

from __future__ import annotations

import re
from pathlib import Path

from blockmesh._system.bounded import check_regular
from blockmesh.decompose.polygon import MAX_CORNERS, MAX_FILE_CORNERS
from blockmesh.errors import DomainFormatError

__all__ = ["MAX_DIGITS", "MAX_FILE_BYTES", "MAX_NESTING", "check_limits", "read_text_bounded"]

#: Largest domain file read (bytes): ample for a million vertices.
MAX_FILE_BYTES = 64 * 2**20
#: Deepest nesting of arrays and inline tables (a domain file needs 4: holes of corners).
MAX_NESTING = 16
#: Most digits in an integer (a vertex id or an edge index has a handful).
MAX_DIGITS = 30


def read_text_bounded(path: str | Path, *, what: str = "domain file") -> str:
    """The text of a regular file of at most :data:`MAX_FILE_BYTES`, as UTF-8.

    FIFOs, devices, sockets and directories are refused before they are opened (reading one
    would block or never end); so are files larger than the cap.

    Examples
    --------
    >>> read_text_bounded("/dev/zero")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: cannot read /dev/zero: it is a character device, not a ...
    """
    path = Path(path)
    check_regular(path, what=what, error=DomainFormatError)
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as error:
        raise DomainFormatError(f"{path}: cannot read the file ({error.strerror})") from None
    if len(data) > MAX_FILE_BYTES:
        raise DomainFormatError(
            f"{path}: the file is larger than {MAX_FILE_BYTES // 2**20} MiB, the most a {what} "
            "may be"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise DomainFormatError(
            f"{path}: not UTF-8 text (byte {error.start}, line {line}); a {what} is a text file"
        ) from None


#: A top-level key at the start of a line (``polygon =``), for counting the corners it holds.
_KEY = re.compile(r"""[ \t]*("[^"\n]*"|'[^'\n]*'|[A-Za-z0-9_-]+)[ \t]*=""")
#: The keys whose numbers are polygon corners (two each), counted while scanning.
_CORNER_KEYS = frozenset({"polygon", "holes"})


def check_limits(text: str, source: str) -> None:
    """Nesting depth, integer size and polygon corners, checked before the TOML parser runs.

    A small scanner that skips strings and comments: ``[`` and ``{`` in values open a level (a
    ``[table]`` header at the start of a line is not a value); digits runs outside strings are
    numbers. The numbers of ``polygon`` and ``holes`` are counted as they are met, per table (a
    composite domain's ``[[parts]]`` each have their own polygon): more than twice
    :data:`~blockmesh.decompose.polygon.MAX_CORNERS` in one table, or twice
    :data:`~blockmesh.decompose.polygon.MAX_FILE_CORNERS` in the file, is refused at once,
    before the parser or the geometry sees them.
    """
    depth = 0
    line, column = 1, 0
    i, n = 0, len(text)
    at_line_start = True
    key = ""
    corner_numbers = file_numbers = 0  # of the polygon being read, of the whole file
    while i < n:
        c = text[i]
        if c == "\n":
            line, column, at_line_start = line + 1, 0, True
            i += 1
            continue
        column += 1
        if c in " \t\r":
            i += 1
            continue
        if c == "#":
            stop = text.find("\n", i)
            i = n if stop < 0 else stop
            continue
        if c in "\"'":
            quote = text[i : i + 3] if text[i : i + 3] in ('"""', "'''") else c
            j = i + len(quote)
            while j < n:
                if quote[0] == '"' and text[j] == "\\":
                    j += 2
                    continue
                if text.startswith(quote, j):
                    break
                j += 1
            skipped = text[i : j + len(quote)]
            line += skipped.count("\n")
            i = j + len(quote)
            at_line_start = False
            continue
        if at_line_start and depth == 0 and c not in "[{":
            found = _KEY.match(text, i)
            if found is not None:
                key = found[1].strip("\"'")
        if c in "[{" and not (at_line_start and c == "[" and depth == 0):
            depth += 1
            if depth > MAX_NESTING:
                raise DomainFormatError(
                    f"{source}: arrays or tables nest more than {MAX_NESTING} deep at line "
                    f"{line}, column {column}; a domain file needs at most 4 levels"
                )
        elif c in "]}" and depth > 0:
            depth -= 1
        elif c.isdigit():
            match = _NUMBER.match(text, i)
            token = match.group(0) if match else c
            digits = sum(ch.isdigit() for ch in token.split("e")[0].split("E")[0])
            if digits > MAX_DIGITS and not any(ch in token for ch in ".eE"):
                raise DomainFormatError(
                    f"{source}: the integer at line {line}, column {column} has {digits} digits; "
                    f"numbers in a domain file have at most {MAX_DIGITS}"
                )
            if key in _CORNER_KEYS and depth:
                corner_numbers += 1
                file_numbers += 1
                if corner_numbers > 2 * MAX_CORNERS or file_numbers > 2 * MAX_FILE_CORNERS:
                    most, what = (
                        (MAX_CORNERS, "the polygon and its holes")
                        if corner_numbers > 2 * MAX_CORNERS
                        else (MAX_FILE_CORNERS, "the polygons of the file")
                    )
                    raise DomainFormatError(
                        f"{source}: {what} have more than {most:,} corners (counted up to line "
                        f"{line}); a polygon of at most {MAX_CORNERS:,} is decomposed in seconds, "
                        f"a file holds at most {MAX_FILE_CORNERS:,} (simplify the outline, or "
                        "split the domain into parts)"
                    )
            i += len(token)
            column += len(token) - 1
            at_line_start = False
            continue
        if c == "[" and at_line_start and depth == 0:  # a table header: a part of its own
            corner_numbers, key = 0, ""
            stop = text.find("\n", i)
            i = n if stop < 0 else stop
            continue
        at_line_start = False
        i += 1


_NUMBER = re.compile(r"[0-9][0-9_]*(?:\.[0-9_]*)?(?:[eE][+-]?[0-9_]+)?")
