"""A streaming reader for the VTU files :func:`blockmesh.io.vtu.format.write_vtu` writes.

meshio's reader holds the whole file, each array's base64 text, its decoded bytes and the
decompressed array at once (4-5x the mesh at level 8). The files blockmesh writes have one fixed
layout (meshio's inline ``format="binary"`` arrays, little-endian, ``UInt32`` or ``UInt64``
headers, zlib, lzma or no compression, one piece of pentagons followed by boundary lines, and the
``blockmesh`` field data), so they are read here in chunks: each array's base64 text is decoded a
few megabytes at a time, each compressed block is inflated on its own, and the values go straight
into preallocated arrays of their final shape (the points' third coordinate is dropped on the
way, the polygons and the lines are split as they arrive, the offsets and types are checked
chunk by chunk and never kept).

:func:`read_stream` returns ``None`` for a file it does not handle (no ``blockmesh`` field data,
another layout, cells that are not pentagons and lines); the caller then reads it with meshio.
A file that has the ``blockmesh`` field data and is damaged is an :class:`ExportError` naming
the array and what is wrong with it.

Bounds (see :mod:`blockmesh._system.bounded`): only regular files are opened; a tag is at most
``_TAG_LIMIT`` bytes and its attributes are parsed in linear time; every array's declared size
is checked against what is left of the file (or, compressed, against what the file may expand
to) and against the read's memory limit before its array is allocated; every compressed block
is inflated in pieces and never past the size its header declares.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.io.vtu.format import write_vtu
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> path = write_vtu(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), folder / "a.vtu")
>>> parts = read_stream(path)
>>> parts.cells.tolist(), parts.edges.shape, sorted(parts.cell_data)
([[0, 1, 2, 3, 4]], (5, 2), ['block_id', 'parent', 'patch', 'region'])
"""

from __future__ import annotations

import binascii
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import BinaryIO

import numpy as np

from blockmesh._system.bounded import ReadGuard, inflate
from blockmesh.errors import ExportError
from blockmesh.io.streams import DamagedError, NotOursError, Place, read_own_layout
from blockmesh.io.text import ChunkedBytes, parse_numbers

__all__ = ["VtuParts", "read_stream"]

_CHUNK = 1 << 22  # the least read at a time (base64 characters: a multiple of 4)
_TAG_LIMIT = 1 << 16  # the longest tag the reader accepts
_FIELD_LIMIT = 1 << 28  # the longest ascii field data array (the curved edges are there)
_TYPES = {
    "Int8": "<i1",
    "UInt8": "<u1",
    "Int16": "<i2",
    "UInt16": "<u2",
    "Int32": "<i4",
    "UInt32": "<u4",
    "Int64": "<i8",
    "UInt64": "<u8",
    "Float32": "<f4",
    "Float64": "<f8",
}
#: The compressors of VTK, by the name of the method :func:`blockmesh._system.bounded.inflate` uses.
_COMPRESSORS: dict[str | None, str | None] = {
    None: None,
    "vtkZLibDataCompressor": "zlib",
    "vtkLZMADataCompressor": "lzma",
}
_POLYGON, _LINE = 7, 3  # VTK cell types
_CELL_DATA = ("block_id", "region", "parent", "patch", "interface")
#: One attribute, matched where the previous one ended (never searched for: linear time).
_ATTR = re.compile(rb"""\s*([A-Za-z_:][\w:.-]*)\s*=\s*(?:"([^"<]*)"|'([^'<]*)')""")


def _attributes(rest: bytes) -> dict[str, str]:
    """The attributes of a tag's text after its name, parsed left to right in linear time."""
    attrs: dict[str, str] = {}
    at, end = 0, len(rest.rstrip())
    while at < end:
        match = _ATTR.match(rest, at)
        if match is None:
            raise DamagedError(f"a malformed attribute in a tag: {rest[at : at + 40]!r}")
        value = match[2] if match[2] is not None else match[3]
        attrs[match[1].decode(errors="replace")] = value.decode(errors="replace")
        at = match.end()
    return attrs


@dataclass
class VtuParts:
    """What :func:`read_stream` read.

    Attributes
    ----------
    points : ndarray (N, 2)
    cells : ndarray (M, 5)
    edges : ndarray (Eb, 2)
        The boundary lines.
    cell_data : dict
        ``NAME -> (on the polygons (M,), on the lines (Eb,))`` for ``block_id``, ``region``,
        ``parent`` and ``patch`` (those present).
    fields : dict
        The field data arrays, by name (``blockmesh``, ``patch:NAME``, ``region:NAME``).
    """

    points: np.ndarray
    cells: np.ndarray
    edges: np.ndarray
    cell_data: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    fields: dict[str, np.ndarray] = field(default_factory=dict)


Target = tuple[int, Callable[[int, np.ndarray], None]]


class _Sink:
    """Rows of ``ncomp`` values of ``dtype`` fed as bytes, handed to ``targets`` in turn.

    Each target is ``(rows, put)``; ``put(start, values)`` receives the values (``(k, ncomp)``)
    of its rows ``start .. start + k``.
    """

    def __init__(self, dtype: str, ncomp: int, targets: list[Target]) -> None:
        self.dtype, self.ncomp = np.dtype(dtype), ncomp
        self.row_bytes = self.dtype.itemsize * ncomp
        self.targets = [t for t in targets if t[0] > 0]
        self.tail = b""
        self.part = self.done_rows = 0

    def feed(self, data: bytes | memoryview) -> None:
        if self.tail:
            data = self.tail + bytes(data)
        rows = len(data) // self.row_bytes
        self.tail = bytes(data[rows * self.row_bytes :])
        values = np.frombuffer(data, self.dtype, count=rows * self.ncomp).reshape(rows, self.ncomp)
        at = 0
        while at < rows:
            if self.part >= len(self.targets):
                raise DamagedError("more values than expected")
            size, put = self.targets[self.part]
            take = min(size - self.done_rows, rows - at)
            put(self.done_rows, values[at : at + take])
            at += take
            self.done_rows += take
            if self.done_rows == size:
                self.part, self.done_rows = self.part + 1, 0

    def close(self) -> None:
        if self.tail or self.part != len(self.targets):
            raise DamagedError("fewer values than expected")


def _into(out: np.ndarray, keep: int | None = None) -> Callable[[int, np.ndarray], None]:
    """A ``put`` writing rows into ``out`` (the first ``keep`` components of each)."""
    flat = out.reshape(-1) if keep is None else out

    def put(start: int, values: np.ndarray) -> None:
        if keep is None:
            flat[start : start + values.size] = values.reshape(-1)
        else:
            flat[start : start + values.shape[0]] = values[:, :keep]

    return put


def _expect(
    predicate: Callable[[int, np.ndarray], np.ndarray],
) -> Callable[[int, np.ndarray], None]:
    """A ``put`` checking each chunk ``values`` against ``predicate(start, values)``."""

    def put(start: int, values: np.ndarray) -> None:
        if not np.all(predicate(start, values[:, 0])):
            raise NotOursError("cells other than pentagons and lines")

    return put


class _Scanner(ChunkedBytes):
    """The XML text of a VTU file, read a chunk at a time."""

    def __init__(self, f: BinaryIO, size: int) -> None:
        super().__init__(f, _CHUNK)
        self.size = size

    @property
    def left(self) -> int:
        """Bytes of the file not consumed yet (buffered or not read)."""
        return self.size - self._read + len(self._buf) - self._pos

    def until(self, token: bytes, limit: int = _TAG_LIMIT) -> bytes:
        """The (short: at most ``limit`` bytes) text up to ``token``, which is consumed."""
        while (at := self._buf.find(token, self._pos)) < 0:
            if len(self._buf) - self._pos > limit or not self._more():
                raise DamagedError(f"no {token!r}")
        text = self._buf[self._pos : at]
        self._pos = at + len(token)
        return text

    def tag(self) -> tuple[bytes, dict[str, str]]:
        """The next tag's name (``/NAME`` for an end tag) and attributes; comments skipped."""
        while True:
            self.until(b"<")
            body = self.until(b">")
            if body.startswith((b"!--", b"?")):
                continue
            parts = body.rstrip(b"/").split(None, 1)
            if not parts:
                raise DamagedError("an empty tag")
            return parts[0], _attributes(parts[1] if len(parts) > 1 else b"")

    def stream(self, feed: Callable[[bytes], None], count: int | None = None) -> None:
        """Decode the base64 text up to the next ``<`` (or ``count`` characters) into ``feed``."""
        carry = b""
        left = count
        while True:  # the whitespace before the text
            while self._pos < len(self._buf) and self._buf[self._pos] in b" \t\r\n":
                self._pos += 1
            if self._pos < len(self._buf) or not self._more():
                break
        while True:
            end = self._buf.find(b"<", self._pos)
            stop = len(self._buf) if end < 0 else end
            if left is not None:
                stop = min(stop, self._pos + left)
            text = carry + self._buf[self._pos : stop]
            if left is not None:
                left -= stop - self._pos
            self._pos = stop
            final = end >= 0 or left == 0
            if end >= 0 and stop == end:
                text = text.rstrip()
            usable = len(text) if final else len(text) - len(text) % 4
            if usable % 4:
                raise DamagedError("base64 text of a length that is not a multiple of 4")
            try:
                data = binascii.a2b_base64(text[:usable], strict_mode=True)
            except binascii.Error as exc:
                raise DamagedError(str(exc)) from None
            carry = text[usable:]
            if data:
                feed(data)
            if final:
                return
            if not self._more():
                raise DamagedError("the file ends inside an array")

    def decoded(self, count: int) -> bytes:
        """The bytes of the next ``count`` base64 characters."""
        parts: list[bytes] = []
        self.stream(parts.append, count)
        return b"".join(parts)


def _read_array(
    scan: _Scanner,
    attrs: dict[str, str],
    header: str,
    compressor: str | None,
    plan: Callable[[int, str], _Sink],
    guard: ReadGuard,
) -> None:
    """Read one binary DataArray, its ``plan(nbytes, dtype)`` giving the sink of its values.

    The declared size is checked against what is left of the file (uncompressed: it is all
    there; compressed: the blocks' sizes are) before ``plan`` allocates anything; each compressed
    block is inflated in pieces, never past its declared size.
    """
    dtype = _TYPES.get(attrs.get("type", ""))
    if attrs.get("format") != "binary" or dtype is None:
        raise NotOursError(
            f"format={attrs.get('format')!r} type={attrs.get('type')!r} (blockmesh writes binary "
            "arrays of numbers)"
        )
    htype = np.dtype(header)
    if compressor is None:
        sink: list[_Sink] = []
        pending = b""
        left = scan.left  # bytes of the file from this array's text on

        def first(data: bytes) -> None:
            nonlocal pending
            if not sink:
                pending += data
                if len(pending) < htype.itemsize:
                    return
                size = int(np.frombuffer(pending[: htype.itemsize], htype)[0])
                if size > left * 3 // 4:
                    raise DamagedError(
                        f"its header announces {size:,} bytes, but only {left:,} bytes of "
                        "the file are left (damaged or truncated)"
                    )
                sink.append(plan(size, dtype))
                data, pending = pending[htype.itemsize :], b""
            sink[0].feed(data)

        scan.stream(first)
        if not sink:
            raise DamagedError("an empty array")
        sink[0].close()
        return
    head = np.frombuffer(scan.decoded(4 * htype.itemsize), htype)  # 3 items: 12 or 24 bytes
    if head.size < 3:
        raise DamagedError("a compression header cut short")
    blocks, block, last = (int(v) for v in head[:3])
    if not 0 < blocks < 1 << 40 or block < 1 or not 0 < last <= block:
        raise DamagedError(
            f"a bad compression header ({blocks} blocks of {block} bytes, the last {last})"
        )
    rest = blocks * htype.itemsize
    chars = 4 * -(-(rest + 3 * htype.itemsize) // 3) - 4 * htype.itemsize
    if chars > scan.left:
        raise DamagedError(
            f"its compression header lists {blocks:,} blocks, more than the file can hold"
        )
    sizes = np.frombuffer(scan.decoded(chars), htype)
    if sizes.size != blocks:
        raise DamagedError("a compression header cut short")
    ends = np.cumsum(sizes.astype(np.int64))
    if int(ends[-1]) > scan.left * 3 // 4:
        raise DamagedError(
            f"its {blocks:,} compressed blocks take {int(ends[-1]):,} bytes, but only "
            f"{scan.left:,} bytes of the file are left (damaged or truncated)"
        )
    total = (blocks - 1) * block + last
    if total > guard.expansion_allowed - guard.expanded_bytes:
        raise DamagedError(
            f"its compressed blocks announce {total:,} bytes, more than the file may expand to "
            f"({guard.expansion_allowed:,} bytes: a decompression bomb?)"
        )
    out = plan(total, dtype)
    k, tail = 0, b""

    def feed(data: bytes) -> None:
        nonlocal k, tail
        buf = memoryview(tail + data if tail else data)
        base = int(ends[k - 1]) if k else 0  # the offset of buf[0] in the compressed stream
        while k < blocks and base + len(buf) >= ends[k]:
            lo, hi = (int(ends[k - 1]) if k else 0) - base, int(ends[k]) - base
            what = f"compressed block {k} of {blocks}"
            try:
                raw = inflate(buf[lo:hi], compressor, last if k == blocks - 1 else block, what, "")
            except ExportError as error:
                raise DamagedError(str(error).lstrip(": ")) from None
            out.feed(raw)
            k += 1
        lo = (int(ends[k - 1]) if k else 0) - base
        tail = bytes(buf[lo:])

    scan.stream(feed)
    if k != blocks or tail:
        raise DamagedError(f"{blocks - k} of its {blocks} compressed blocks are missing")
    out.close()


def _field(scan: _Scanner, attrs: dict[str, str], guard: ReadGuard) -> np.ndarray:
    dtype = _TYPES.get(attrs.get("type", ""))
    if attrs.get("format") != "ascii" or dtype is None:
        raise NotOursError("field data that is not ascii")
    text = scan.until(b"</DataArray>", _FIELD_LIMIT)
    name = attrs.get("Name", "")[:40]
    guard.allocate(4 * len(text), f"the field data {name!r}")  # at most len/2 float64 values
    try:
        values = parse_numbers(text, np.float64, "field data")
    except ExportError:
        raise NotOursError("field data that is not numbers") from None
    kind = np.dtype(dtype)
    low, high = (np.iinfo(kind).min, np.iinfo(kind).max) if kind.kind in "iu" else (-np.inf, np.inf)
    if not np.all((values >= low) & (values <= high)):  # NaN fails too
        raise NotOursError(f"field data beyond the range of {kind}")
    return values.astype(dtype)


def _parse(f: BinaryIO, size: int, guard: ReadGuard, place: Place) -> VtuParts:
    scan = _Scanner(f, size)
    name, top = scan.tag()
    if name != b"VTKFile" or top.get("type") != "UnstructuredGrid":
        raise NotOursError("not an unstructured grid")
    if top.get("byte_order", "LittleEndian") != "LittleEndian":
        raise NotOursError("big-endian")
    header = _TYPES.get(top.get("header_type", "UInt32"), "")
    if header not in ("<u4", "<u8") or top.get("compressor") not in _COMPRESSORS:
        raise NotOursError("another header type or compressor")
    compressor = _COMPRESSORS[top.get("compressor")]
    fields: dict[str, np.ndarray] = {}
    if scan.tag()[0] != b"UnstructuredGrid" or scan.tag()[0] != b"FieldData":
        raise NotOursError("no field data")
    while (tag := scan.tag())[0] == b"DataArray":
        fields[tag[1].get("Name", "")] = _field(scan, tag[1], guard)
    name, piece = scan.tag()
    if tag[0] != b"/FieldData" or name != b"Piece" or "blockmesh" not in fields:
        raise NotOursError("not written by blockmesh")
    place.ours, place.where = True, "<Piece>"
    try:
        n, total = int(piece["NumberOfPoints"]), int(piece["NumberOfCells"])
    except (KeyError, ValueError):
        raise NotOursError("no whole-number NumberOfPoints and NumberOfCells") from None
    if n < 0 or total < 0:
        raise DamagedError(f"NumberOfPoints={n}, NumberOfCells={total}")
    shape: dict[str, int] = {}
    empty = np.empty((0, 2))
    parts = VtuParts(empty, np.empty((0, 5), np.int64), np.empty((0, 2), np.int64))

    def plan_points(nbytes: int, dtype: str) -> _Sink:
        if nbytes != 3 * n * np.dtype(dtype).itemsize:
            raise DamagedError(f"{nbytes:,} bytes for {n:,} points of 3 coordinates")
        guard.allocate(16 * n, f"the {n:,} points")
        parts.points = np.empty((n, 2))
        return _Sink(dtype, 3, [(n, _into(parts.points, keep=2))])

    def plan_connectivity(nbytes: int, dtype: str) -> _Sink:
        length = nbytes // np.dtype(dtype).itemsize
        m, rem = divmod(length - 2 * total, 3)  # 5 m + 2 (total - m) == length
        if rem or not 0 < m <= total or nbytes % np.dtype(dtype).itemsize:
            raise NotOursError(
                f"{length:,} node ids for {total:,} cells: not pentagons followed by lines"
            )
        shape["m"], shape["eb"] = m, total - m
        guard.allocate(8 * length, f"the {m:,} pentagons and {total - m:,} boundary lines")
        parts.cells = np.empty((m, 5), np.int64)
        parts.edges = np.empty((total - m, 2), np.int64)
        targets = [(5 * m, _into(parts.cells)), (2 * (total - m), _into(parts.edges))]
        return _Sink(dtype, 1, targets)

    def plan_check(kind: str) -> Callable[[int, str], _Sink]:
        def plan(nbytes: int, dtype: str) -> _Sink:
            if "m" not in shape or nbytes != total * np.dtype(dtype).itemsize:
                raise DamagedError(f"{nbytes:,} bytes for {total:,} cells")
            m = shape["m"]
            if kind == "offsets":
                targets: list[Target] = [
                    (m, _expect(lambda s, v: v == 5 * np.arange(s + 1, s + 1 + v.size))),
                    (
                        total - m,
                        _expect(lambda s, v: v == 5 * m + 2 * np.arange(s + 1, s + 1 + v.size)),
                    ),
                ]
            else:
                targets = [
                    (m, _expect(lambda _, v: v == _POLYGON)),
                    (total - m, _expect(lambda _, v: v == _LINE)),
                ]
            return _Sink(dtype, 1, targets)

        return plan

    def plan_data(key: str) -> Callable[[int, str], _Sink]:
        def plan(nbytes: int, dtype: str) -> _Sink:
            if "m" not in shape or nbytes != total * np.dtype(dtype).itemsize:
                raise DamagedError(f"{nbytes:,} bytes for {total:,} cells")
            guard.allocate(8 * total, f"the cell data {key!r}")
            on = (np.empty(shape["m"], np.int64), np.empty(shape["eb"], np.int64))
            if key in _CELL_DATA:
                parts.cell_data[key] = on
            return _Sink(dtype, 1, [(shape["m"], _into(on[0])), (shape["eb"], _into(on[1]))])

        return plan

    cells = {
        "connectivity": plan_connectivity,
        "offsets": plan_check("offsets"),
        "types": plan_check("types"),
    }
    sections: list[tuple[bytes, dict[str, Callable[[int, str], _Sink]] | None]] = [
        (b"Points", {"Points": plan_points}),
        (b"Cells", cells),
        (b"CellData", None),  # any arrays, each on the polygons then the lines
    ]
    seen: set[str] = set()
    for section, plans in sections:
        place.where = f"<{section.decode()}>"
        if scan.tag()[0] != section:
            raise NotOursError(f"no <{section.decode()}> where it belongs")
        while (tag := scan.tag())[0] == b"DataArray":
            key = tag[1].get("Name", "")
            place.where = f"the DataArray {key!r} in <{section.decode()}>"
            plan = plan_data(key) if plans is None else plans.get(key)
            if plan is None or key in seen:
                raise NotOursError("an array not expected there (or twice)")
            seen.add(key)
            _read_array(scan, tag[1], header, compressor, plan, guard)
            if scan.tag()[0] != b"/DataArray":
                raise NotOursError("no </DataArray> after the data")
            place.where = f"<{section.decode()}>"
        if tag[0] != b"/" + section:
            raise NotOursError(f"<{tag[0].decode(errors='replace')}> where it does not belong")
    place.where = "<Piece>"
    missing = {"Points", "connectivity", "offsets", "types"} - seen
    if missing:
        raise NotOursError(f"no {', '.join(sorted(missing))} array")
    if [scan.tag()[0] for _ in range(3)] != [b"/Piece", b"/UnstructuredGrid", b"/VTKFile"]:
        raise NotOursError("more than one piece")
    parts.fields = fields
    return parts


def read_stream(path: Path) -> VtuParts | None:
    """The arrays of a VTU file written by blockmesh, read in chunks; None for other files.

    Peak memory is the arrays returned plus a few megabytes. Raises :class:`ExportError` for a
    file that is not a regular file, and for one that has blockmesh's field data but is damaged
    (naming the array and what is wrong).
    """
    return read_own_layout(
        path,
        _parse,
        Place(),
        not_ours=(ValueError, TypeError, IndexError, OverflowError, UnicodeDecodeError),
    )
