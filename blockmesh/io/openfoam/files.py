"""Reading the files of an OpenFOAM ``polyMesh`` folder: headers, lists, patches, faces and zones.

The files (ASCII, or gzipped) are parsed line by line in chunks
(:class:`blockmesh.io.text.TextReader`): a ``FoamFile`` header (:func:`foam_file`), a list
(:func:`read_list`), the patches of ``boundary`` (:func:`read_boundary`), ranges of ``faces``
(:func:`read_faces`) and the cell and face zones; :func:`find_polymesh` finds the folder of a
case. Every count is checked against what is left of the file before anything is allocated.
Both readers of a case use them (:mod:`blockmesh.io.openfoam.reader` for pentagons,
:mod:`blockmesh.io.openfoam.polygons` for polygons).
"""

from __future__ import annotations

import contextlib
import gzip
import os
import re
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError
from blockmesh.io.text import TextReader, parse_numbers

__all__ = [
    "FaceSizeError",
    "Inflated",
    "find_polymesh",
    "foam_file",
    "header_counts",
    "list_size",
    "read_boundary",
    "read_face_zones",
    "read_faces",
    "read_list",
    "read_zones",
]


class FaceSizeError(ExportError):
    """Faces of a range that are not all of the size asked for (e.g. polygons, not pentagons)."""


_INT32 = np.iinfo(np.int32).max
#: Most lines, and most bytes of a line, of a ``FoamFile`` header.
_HEADER_LINES, _HEADER_LINE = 200, 4096
#: Most digits of a count (a face or point count of int64).
_DIGITS = 18


class Inflated:
    """A gzip stream whose output is counted against the read's expansion allowance."""

    def __init__(self, packed: BinaryIO, where: str) -> None:
        self.stream = gzip.GzipFile(fileobj=packed, mode="rb")
        self.where = where

    def read(self, size: int = -1, /) -> bytes:
        """Up to ``size`` bytes inflated (4 MB for -1), counted against the allowance."""
        data = self.stream.read(size if size >= 0 else 1 << 22)
        current_guard(self.where).expanded(len(data), "the gzip stream")
        return data


@contextlib.contextmanager
def foam_file(poly: Path, name: str) -> Iterator[tuple[TextReader, dict[str, str]]]:
    """A reader positioned after the ``FoamFile`` header of ``poly/name`` (or ``name.gz``).

    Also yields the header's entries. Raises :class:`ExportError` for a missing file, one that
    is not a regular file (a FIFO would block), a missing header or a binary file. A gzipped file
    is inflated a chunk at a time, within what the files read may expand to.
    """
    plain, packed = poly / name, poly / f"{name}.gz"
    if os.path.lexists(plain):
        raw, where = open_regular(plain), str(plain)
    elif os.path.lexists(packed):
        raw, where = open_regular(packed), str(packed)
    else:
        raise ExportError(f"{poly} has no {name} file; is it an OpenFOAM polyMesh directory?")
    with raw:
        handle: Any = raw
        size = None
        if where.endswith(".gz"):
            guard = current_guard(where)
            handle = Inflated(raw, where)
            size = guard.expansion_allowed - guard.expanded_bytes
        r = TextReader(handle, where, size=size)
        try:
            header = _header(r)
        except (OSError, EOFError, zlib.error) as exc:
            raise ExportError(f"cannot read {where}: {exc}") from None
        try:
            yield r, header
        except (OSError, EOFError, zlib.error) as exc:  # a damaged gzip stream
            raise ExportError(f"cannot read {where}: {exc}") from None


def _header(r: TextReader) -> dict[str, str]:
    """The entries of the ``FoamFile { ... }`` header; the reader is left after it."""
    while True:
        line = r.line()
        if line.strip().startswith(b"FoamFile"):
            break
        if r.at_end or r.line_number > 1000:
            raise ExportError(f"{r.where} has no FoamFile header")
    lines: list[bytes] = []
    while not lines or b"}" not in lines[-1]:
        line = r.line()
        if (r.at_end and not line) or len(lines) > _HEADER_LINES:
            raise ExportError(
                f"{r.where}: the FoamFile header does not end (no }} within {_HEADER_LINES} lines)"
            )
        lines.append(line[:_HEADER_LINE])
    text = b"\n".join(lines) + b"\n"
    header = {}
    for entry in text.split(b"}")[0].strip().lstrip(b"{").decode(errors="replace").split(";"):
        parts = entry.split(None, 1)
        if len(parts) == 2:
            header[parts[0]] = parts[1].strip().strip('"')
    if header.get("format", "ascii") != "ascii":
        raise ExportError(
            f"{r.where} is in binary format; blockmesh reads ASCII polyMesh files "
            "(run foamFormatConvert with writeFormat ascii)"
        )
    return header


def _significant(r: TextReader) -> bytes:
    """The next line that is not blank and not a ``//`` comment."""
    while True:
        text = r.line().strip()
        if text and not text.startswith(b"//"):
            return text
        if r.at_end:
            raise ExportError(f"{r.where}: the file ends at line {r.line_number} before a list")


_INLINE = re.compile(rb"^(\d+)\s*\((.*)\)\s*;?$")
_UNIFORM = re.compile(rb"^(\d+)\s*\{(.*)\}\s*;?$")


def read_list(
    r: TextReader, cols: int, dtype: type, *, skip: int = 0, out_dtype: type | None = None
) -> tuple[int, np.ndarray]:
    """The count and the rows from ``skip`` on of the next list ``N ( items )`` (one item a line).

    Items ``(x y z)`` and ``4(a b c d)`` are read as plain numbers (the parentheses are blanks).
    Short lists written on one line (``3(0 1 2)``) and uniform lists (``3{7}``) are read too.
    """
    text = _significant(r)
    for pattern in (_INLINE, _UNIFORM):
        match = pattern.match(text)
        if match:
            count = _count(match[1], r)
            if pattern is _UNIFORM:
                current_guard(r.where).allocate(8 * cols * count, f"a uniform list of {count:,}")
            inner = match[2].replace(b"(", b" ").replace(b")", b" ")
            values = parse_numbers(inner, dtype, f"{r.where}, line {r.line_number}")
            if pattern is _UNIFORM:
                values = np.repeat(values, count)
            if values.size != count * cols:
                raise ExportError(f"{r.where}, line {r.line_number}: malformed list {text[:60]!r}")
            return count, values.reshape(count, cols)[skip:].astype(out_dtype or dtype)
    if not text.isdigit():
        raise ExportError(
            f"{r.where}, line {r.line_number}: expected a list size, got {text[:60]!r}"
        )
    count = _count(text, r)
    if _significant(r) != b"(":
        raise ExportError(f"{r.where}, line {r.line_number}: expected ( after the list size")
    r.skip(skip)
    rows = r.table(count - skip, cols, dtype, out_dtype, blank=b"()")
    if not _significant(r).startswith(b")"):
        raise ExportError(f"{r.where}, line {r.line_number}: the list of {count} does not end")
    return count, rows


def _count(digits: bytes, r: TextReader) -> int:
    """A list size (whole number of at most :data:`_DIGITS` digits)."""
    if len(digits) > _DIGITS:
        raise ExportError(
            f"{r.where}, line {r.line_number}: a list size of {len(digits)} digits (damaged?)"
        )
    return int(digits)


def list_size(r: TextReader) -> int:
    """The size that opens the next list (its first significant line); ExportError otherwise."""
    text = _significant(r)
    match = re.match(rb"^(\d+)", text)
    if match is None:
        raise ExportError(
            f"{r.where}, line {r.line_number}: expected a list size, got {text[:60]!r}"
        )
    return _count(match[1], r)


#: A comment (an unclosed one runs to the end: one pass, linear time).
_COMMENT = re.compile(r"//[^\n]*|/\*.*?(?:\*/|\Z)", flags=re.S)


def _tokens(text: str) -> list[str]:
    text = _COMMENT.sub(" ", text)
    return re.findall(r'"[^"]*"|[{}();]|[^\s{}();]+', text)


def read_boundary(poly: Path) -> list[dict[str, str]]:
    """The patches of ``poly/boundary``: one dictionary of entries (and ``name``) each."""
    with foam_file(poly, "boundary") as (r, _):
        body = r.rest()
        where = r.where
    toks = _tokens(body.decode(errors="replace"))
    try:
        k = toks.index("(") + 1
        patches = []
        while k < len(toks) and toks[k] != ")":
            name, k = toks[k], k + 2  # skip name and "{"
            entry: dict[str, str] = {"name": name}
            while toks[k] != "}":
                key, k = toks[k], k + 1
                value = []
                depth = 0
                while depth or toks[k] != ";":
                    depth += toks[k] == "("
                    depth -= toks[k] == ")"
                    value.append(toks[k])
                    k += 1
                entry[key] = " ".join(value)
                k += 1
            patches.append(entry)
            k += 1
    except (ValueError, IndexError):
        raise ExportError(f"{where}: malformed patch list") from None
    for p in patches:
        for key in ("nFaces", "startFace"):
            entry_value = p.get(key, "")
            if not entry_value.isdigit() or len(entry_value) > _DIGITS:
                raise ExportError(
                    f"{where}: patch {p['name'][:60]!r} has {key} {entry_value[:30]!r}, not a "
                    "whole number"
                )
    return patches


def read_faces(poly: Path, ranges: list[tuple[int, int, int]]) -> list[np.ndarray]:
    """The faces ``start`` to ``start + count - 1`` of ``poly/faces``, each of ``size`` nodes.

    ``ranges`` are ``(start, count, size)``, in increasing order of ``start``; returns one
    ``(count, size)`` array of node ids each. Faces before and between are skipped, not parsed.
    Raises :class:`ExportError` when a face in a range has another size.
    """
    out = []
    with foam_file(poly, "faces") as (r, header):
        if header.get("class") == "faceCompactList":
            raise ExportError(f"{r.where}: faceCompactList files are not supported (faceList)")
        count = list_size(r)
        if _significant(r) != b"(":
            raise ExportError(f"{r.where}: expected ( after the number of faces")
        at = 0
        for start, n, size in ranges:
            if start < at or start + n > count:
                raise ExportError(f"{r.where}: faces {start}..{start + n - 1} are not in the file")
            r.skip(start - at)
            try:
                rows = r.table(
                    n, 1 + size, np.int64, np.int32 if count <= _INT32 else np.int64, blank=b"()"
                )
            except ExportError:
                raise FaceSizeError(
                    f"{r.where}: faces {start}..{start + n - 1} are not all of {size} nodes"
                ) from None
            if np.any(rows[:, 0] != size):
                raise FaceSizeError(
                    f"{r.where}: faces {start}..{start + n - 1} are not all of {size} nodes"
                )
            out.append(rows[:, 1:])
            at = start + n
    return out


def header_counts(header: dict[str, str]) -> dict[str, int]:
    """The counts a header's ``note`` gives (``nPoints``, ``nCells``, ``nFaces``, ...) by name.

    The note reads ``"nPoints:.. nCells:.. nFaces:.. nInternalFaces:.."``.
    """
    return {k: int(v) for k, v in re.findall(r"(n\w+):\s*(\d+)", header.get("note", ""))}


def _zones(poly: Path, file: str) -> list[tuple[str, dict[str, np.ndarray]]] | None:
    """The zones of ``poly/file`` (``cellZones``, ``faceZones``): each name and its lists.

    The lists are the ``NAME List<label|bool> ...`` entries of each zone (``cellLabels``,
    ``faceLabels``, ``flipMap``), read whether written one value a line, inline or uniform.
    None when there is no such file.
    """
    if not ((poly / file).exists() or (poly / f"{file}.gz").exists()):
        return None
    out: list[tuple[str, dict[str, np.ndarray]]] = []
    with foam_file(poly, file) as (r, _):
        n_zones = list_size(r)
        if _significant(r) != b"(":
            raise ExportError(f"{r.where}: expected ( after the number of zones")
        for _ in range(n_zones):
            name = _significant(r).decode(errors="replace")
            if _significant(r) != b"{":
                raise ExportError(f"{r.where}, line {r.line_number}: expected {{ after zone {name}")
            found: dict[str, np.ndarray] = {}
            while True:
                line = _significant(r)
                if line.startswith(b"}"):
                    break
                match = re.match(rb"(\w+)\s+List<(?:label|bool)>\s*(.*)$", line)
                if match is not None:
                    found[match[1].decode()] = _zone_list(r, match[2].strip())
            out.append((name, found))
    return out


def _zone_list(r: TextReader, rest: bytes) -> np.ndarray:
    """The values of a zone's list whose first line (after ``List<...>``) is ``rest``."""
    where = f"{r.where}, line {r.line_number}"
    for pattern in (_INLINE, _UNIFORM):
        inner = pattern.match(rest)
        if inner:
            values = parse_numbers(inner[2], np.int64, where)
            if pattern is _INLINE:
                return values
            count = int(inner[1]) if len(inner[1]) <= _DIGITS else -1
            if count < 0 or values.size != 1:
                raise ExportError(
                    f"{where}: a uniform list {rest[:60]!r} is not COUNT{{VALUE}} with a count of "
                    f"at most {_DIGITS} digits"
                )
            current_guard(r.where).allocate(8 * count, f"a uniform list of {count:,}")
            return np.repeat(values, count)
    count = _count(rest, r) if rest.isdigit() else list_size(r)
    if _significant(r) != b"(":
        raise ExportError(f"{where}: expected (")
    values = r.table(count, 1, np.int64).ravel()
    _significant(r)  # the closing ")" (or ");")
    return values


def read_zones(poly: Path, n_cells: int) -> tuple[np.ndarray, list[str]] | None:
    """Each cell's zone index and the zone names from ``cellZones`` ("unzoned" last), or None."""
    zones = _zones(poly, "cellZones")
    if zones is None:
        return None
    where = str(poly / "cellZones")
    region = np.full(n_cells, -1, dtype=np.int64)
    names: list[str] = []
    for name, lists in zones:
        labels = lists.get("cellLabels")
        if labels is None:
            raise ExportError(f"{where}: zone {name} has no cellLabels")
        if labels.size and (labels.min() < 0 or labels.max() >= n_cells):
            raise ExportError(f"{where}: zone {name} names cells outside 0..{n_cells - 1}")
        region[labels] = len(names)
        names.append(name)
    if np.any(region < 0):
        region[region < 0] = len(names)
        names.append("unzoned")
    return region, names


def find_polymesh(path: Path) -> Path:
    """The ``polyMesh`` folder of ``path`` (a case, its ``constant`` or the folder itself)."""
    candidates = [path / "constant" / "polyMesh", path / "polyMesh", path]
    poly = next(
        (c for c in candidates if (c / "boundary").exists() or (c / "boundary.gz").exists()), None
    )
    if poly is not None:
        return poly
    leftovers = sorted(
        p.name
        for c in (path / "constant", path)
        if c.is_dir()
        for p in c.iterdir()
        if p.name.startswith(".polyMesh.") or p.name.startswith(".constant.")
    )
    hint = (
        f"; an interrupted write left {', '.join(leftovers)}: write the mesh again (blockmesh "
        "then puts back or removes them)"
        if leftovers
        else ""
    )
    raise ExportError(
        f"{path} holds no OpenFOAM polyMesh (looked for constant/polyMesh/boundary){hint}"
    )


def read_face_zones(
    poly: Path, n_internal: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]] | None:
    """The internal faces of every face zone: labels, flips, zone index, zone names (or None)."""
    zones = _zones(poly, "faceZones")
    if not zones:
        return None
    where = str(poly / "faceZones")
    labels, flips, names = [], [], []
    for name, lists in zones:
        face = lists.get("faceLabels")
        if face is None:
            raise ExportError(f"{where}: face zone {name} has no faceLabels")
        if face.size and (face.min() < 0 or face.max() >= n_internal):
            raise ExportError(
                f"{where}: face zone {name} names faces outside the internal faces "
                f"0..{n_internal - 1} (blockmesh reads zones of internal faces: interfaces)"
            )
        flip = lists.get("flipMap", np.zeros(face.size, dtype=np.int64))
        if flip.size != face.size:
            raise ExportError(f"{where}: face zone {name}'s flipMap has another length")
        labels.append(face)
        flips.append(flip != 0)
        names.append(name)
    zone = np.repeat(np.arange(len(names)), [f.size for f in labels])
    return np.concatenate(labels), np.concatenate(flips), zone, names
