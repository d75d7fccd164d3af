"""A streaming writer of VTU files: arrays piece by piece, blocks compressed on several threads.

meshio's VTU writer holds every array's bytes, its compressed blocks and its base64 text at once
and compresses 32 KB blocks at zlib's default level on one core: at level 7 it was the slowest
stage of ``blockmesh mesh -o m.vtu`` by far (issue 22). This writer keeps meshio's layout, which
meshio, VTK (ParaView) and :mod:`blockmesh.io.vtu_stream` read (inline ``format="binary"``
arrays, base64, one piece of pentagons followed by boundary and interface lines, ``UInt64``
headers), and:

- produces each array in pieces of rows (the points with their zero ``z`` a few thousand rows at
  a time, the offsets and cell types computed as they go), never the whole array at once;
- with compression, cuts the array's bytes into blocks of :data:`BLOCK_BYTES` and compresses
  them on :func:`~blockmesh.threads.default_threads` threads (zlib and lzma release the
  interpreter lock), at :data:`ZLIB_LEVEL` for zlib; the header, whose length is known in
  advance, is written in place once the blocks' sizes are known;
- writes connectivity, offsets and the integer cell data as ``Int32`` when every value fits
  (``Int64`` otherwise; the readers widen them again), the cell types as ``UInt8``.

It holds the mesh plus a few blocks per thread. The XML around the arrays is short; the field
data block (names, metadata, curves) is given ready-made by :mod:`blockmesh.io.vtu`.

Examples
--------
>>> import io, numpy as np
>>> pieces = _Blocks(16)
>>> blocks = [bytes(b) for b in pieces.feed(b"0123456789")] + [bytes(b) for b in pieces.feed(
...     b"abcdefghij")] + [bytes(b) for b in pieces.close()]
>>> blocks
[b'0123456789abcdef', b'ghij']
"""

from __future__ import annotations

import binascii
import lzma
import zlib
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from typing import BinaryIO

import numpy as np

from blockmesh._system.threads import default_threads
from blockmesh.io.common import line_arrays
from blockmesh.mesh.mesh import Mesh

__all__ = ["BLOCK_BYTES", "ZLIB_LEVEL", "write_vtu_stream"]

#: Uncompressed bytes per compressed block (VTK's readers take any size; meshio uses 32 KB).
BLOCK_BYTES = 1 << 20
#: zlib's level for ``compression="zlib"``: on these arrays level 1 is about 3 times as fast as
#: the default 6 and the files are as small within 0.2 % (``benchmarks/bench_export.py --vtu``).
ZLIB_LEVEL = 1
#: Rows of an array produced at a time (a few MB of points, offsets or cell data).
_ROWS = 1 << 17
_POLYGON, _LINE = 7, 3  # VTK cell types
_VTK_TYPES = {"<f8": "Float64", "<i8": "Int64", "<i4": "Int32", "|u1": "UInt8"}
_B64_CHUNK = 3 << 20  # bytes base64-encoded at a time: a multiple of 3 (no padding inside)


# ------------------------------------------------------------------------------ the arrays
class _Array:
    """One DataArray: its name, type, components and its bytes as a sequence of pieces."""

    def __init__(
        self, name: str, dtype: str, ncomp: int, nbytes: int, pieces: Callable[[], Iterator]
    ) -> None:
        self.name, self.dtype, self.ncomp, self.nbytes = name, np.dtype(dtype), ncomp, nbytes
        self.pieces = pieces

    def xml(self) -> bytes:
        kind = _VTK_TYPES[self.dtype.str]
        comps = f' NumberOfComponents="{self.ncomp}"' if self.ncomp > 1 else ""
        return f'<DataArray type="{kind}" Name="{self.name}"{comps} format="binary">\n'.encode()


def _rows(n: int) -> Iterator[tuple[int, int]]:
    for start in range(0, n, _ROWS):
        yield start, min(start + _ROWS, n)


def _index_type(largest: int) -> str:
    """``Int32`` when every value fits, else ``Int64``."""
    return "<i4" if largest < 2**31 else "<i8"


def _points(points: np.ndarray) -> _Array:
    def pieces() -> Iterator[np.ndarray]:
        for a, b in _rows(points.shape[0]):
            xyz = np.zeros((b - a, 3))
            xyz[:, :2] = points[a:b]
            yield xyz

    return _Array("Points", "<f8", 3, 24 * points.shape[0], pieces)


def _joined(name: str, first: np.ndarray, second: np.ndarray, dtype: str) -> _Array:
    """The rows of ``first`` then those of ``second``, as ``dtype``."""

    def pieces() -> Iterator[np.ndarray]:
        for part in (first, second):
            for a, b in _rows(part.shape[0]):
                yield np.ascontiguousarray(part[a:b], dtype=dtype)

    size = np.dtype(dtype).itemsize * (first.size + second.size)
    return _Array(name, dtype, 1, size, pieces)


def _computed(name: str, dtype: str, n: int, make: Callable[[int, int], np.ndarray]) -> _Array:
    """``make(a, b)`` gives entries ``a .. b - 1`` of an array of ``n``."""

    def pieces() -> Iterator[np.ndarray]:
        for a, b in _rows(n):
            yield make(a, b)

    return _Array(name, dtype, 1, np.dtype(dtype).itemsize * n, pieces)


def _arrays(mesh: Mesh) -> tuple[list[_Array], list[_Array], list[_Array]]:
    """The Points, Cells and CellData arrays of ``mesh`` (pentagons, boundary and interface lines).

    The ``interface`` cell data is written only when the mesh has interfaces.
    """
    edges, patch, interface = line_arrays(mesh)
    m, eb = mesh.n_cells, int(edges.shape[0])
    index = _index_type(max(mesh.n_points, 5 * m + 2 * eb + 1))
    total = m + eb

    def offsets(a: int, b: int) -> np.ndarray:
        k = np.arange(a + 1, b + 1, dtype=np.int64)
        return np.where(k <= m, 5 * k, 5 * m + 2 * (k - m)).astype(index)

    def types(a: int, b: int) -> np.ndarray:
        return np.where(np.arange(a, b) < m, _POLYGON, _LINE).astype(np.uint8)

    cells = [
        _joined("connectivity", mesh.cells, edges, index),
        _computed("offsets", index, total, offsets),
        _computed("types", "|u1", total, types),
    ]
    minus_m, minus_eb = np.full(m, -1, np.int32), np.full(eb, -1, np.int32)
    data = []
    columns = [
        ("block_id", mesh.block_id, minus_eb),
        ("region", mesh.region, minus_eb),
        ("parent", mesh.parent, minus_eb),
        ("patch", minus_m, patch),
    ]
    if mesh.interface_names:
        columns.append(("interface", minus_m, interface))
    for name, on_cells, on_lines in columns:
        largest = max(int(np.abs(on_cells).max(initial=0)), int(np.abs(on_lines).max(initial=0)))
        data.append(_joined(name, on_cells, on_lines, _index_type(largest)))
    return [_points(mesh.points)], cells, data


# ------------------------------------------------------------------------------- the bytes
class _Blocks:
    """Bytes fed in pieces, handed out in blocks of ``size`` (the last one shorter)."""

    def __init__(self, size: int) -> None:
        self.size = size
        self.pending = bytearray()

    def feed(self, data: bytes | memoryview) -> Iterator[memoryview]:
        view = memoryview(data).cast("B")
        if self.pending:
            take = min(self.size - len(self.pending), len(view))
            self.pending += view[:take]
            view = view[take:]
            if len(self.pending) < self.size:
                return
            yield memoryview(bytes(self.pending))
            self.pending.clear()
        whole = len(view) - len(view) % self.size
        for start in range(0, whole, self.size):
            yield view[start : start + self.size]
        self.pending += view[whole:]

    def close(self) -> Iterator[memoryview]:
        if self.pending:
            yield memoryview(bytes(self.pending))
            self.pending.clear()


class _Base64:
    """A base64 text written in pieces: each a multiple of 3 bytes, so no padding inside."""

    def __init__(self, out: BinaryIO) -> None:
        self.out, self.carry = out, b""

    def write(self, data: bytes | memoryview) -> None:
        view = memoryview(data).cast("B")
        if self.carry:
            need = (3 - len(self.carry)) % 3
            head = self.carry + bytes(view[:need])
            view = view[need:]
            if len(head) % 3:  # still short: wait for more bytes
                self.carry = head
                return
            self.out.write(binascii.b2a_base64(head, newline=False))
        for start in range(0, len(view) - len(view) % 3, _B64_CHUNK):
            stop = min(start + _B64_CHUNK, len(view) - len(view) % 3)
            self.out.write(binascii.b2a_base64(view[start:stop], newline=False))
        self.carry = bytes(view[len(view) - len(view) % 3 :])

    def close(self) -> None:
        if self.carry:
            self.out.write(binascii.b2a_base64(self.carry, newline=False))
        self.carry = b""


def _pieces(array: _Array) -> Iterator[memoryview]:
    for piece in array.pieces():
        yield np.ascontiguousarray(piece).data.cast("B")


def _write_raw(out: BinaryIO, array: _Array) -> None:
    """``UInt64`` byte count, then the bytes: one base64 text (as meshio writes it)."""
    text = _Base64(out)
    text.write(np.array([array.nbytes], dtype="<u8").tobytes())
    for piece in _pieces(array):
        text.write(piece)
    text.close()


def _in_order(
    pool: ThreadPoolExecutor, compress: Callable[[memoryview], bytes], blocks: Iterable, depth: int
) -> Iterator[bytes]:
    """``compress(block)`` for every block, on the pool, in order; at most ``depth`` pending."""
    pending: deque[Future[bytes]] = deque()
    for block in blocks:
        pending.append(pool.submit(compress, block))
        if len(pending) >= depth:
            yield pending.popleft().result()
    while pending:
        yield pending.popleft().result()


def _write_compressed(
    out: BinaryIO, array: _Array, compress: Callable[[memoryview], bytes], pool, depth: int
) -> None:
    """The header ``[blocks, block size, last size, compressed sizes...]`` then the blocks.

    The header's base64 length is known from the block count, so a placeholder is written first
    and replaced when the compressed sizes are known (the file must be seekable).
    """
    n_blocks = -(-array.nbytes // BLOCK_BYTES)
    last = array.nbytes - (n_blocks - 1) * BLOCK_BYTES if n_blocks else 0
    header_chars = 4 * -(-8 * (3 + n_blocks) // 3)
    at = out.tell()
    out.write(b"A" * header_chars)

    def blocks() -> Iterator[memoryview]:
        cutter = _Blocks(BLOCK_BYTES)
        for piece in _pieces(array):
            yield from cutter.feed(piece)
        yield from cutter.close()

    sizes = []
    text = _Base64(out)
    for packed in _in_order(pool, compress, blocks(), depth):
        sizes.append(len(packed))
        text.write(packed)
    text.close()
    if len(sizes) != n_blocks:
        raise AssertionError(f"{array.name}: {len(sizes)} blocks written, {n_blocks} expected")
    end = out.tell()
    header = np.array([n_blocks, BLOCK_BYTES, last, *sizes], dtype="<u8").tobytes()
    out.seek(at)
    out.write(binascii.b2a_base64(header, newline=False))
    out.seek(end)


def _compressor(compression: str) -> Callable[[memoryview], bytes] | None:
    if compression == "zlib":
        return lambda block: zlib.compress(block, ZLIB_LEVEL)
    if compression == "lzma":
        return lambda block: lzma.compress(block, filters=_LZMA_FILTERS)
    return None


#: LZMA2 at the default preset with a dictionary of one block (a larger one cannot help):
#: about 10 MB per compressing thread instead of the preset's 94 MB.
_LZMA_FILTERS = [{"id": lzma.FILTER_LZMA2, "preset": 6, "dict_size": BLOCK_BYTES}]


_COMPRESSORS = {"zlib": "vtkZLibDataCompressor", "lzma": "vtkLZMADataCompressor"}


def write_vtu_stream(
    out: BinaryIO,
    mesh: Mesh,
    field_data_xml: bytes,
    *,
    compression: str = "none",
    threads: int | None = None,
) -> None:
    """Write ``mesh`` as a VTU file to the seekable binary stream ``out`` (module docstring).

    ``field_data_xml`` is the ``<FieldData>`` element, written before the piece.
    """
    compress = _compressor(compression)
    threads = default_threads() if threads is None else threads
    compressor = f' compressor="{_COMPRESSORS[compression]}"' if compress else ""
    out.write(
        b'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" '
        b'byte_order="LittleEndian" header_type="UInt64"' + compressor.encode() + b">\n"
        b"<!--This file was written by blockmesh-->\n<UnstructuredGrid>\n"
    )
    out.write(field_data_xml)
    total = mesh.n_cells + int(mesh.boundary_edges.shape[0]) + int(mesh.interface_edges.shape[0])
    out.write(f'<Piece NumberOfPoints="{mesh.n_points}" NumberOfCells="{total}">\n'.encode())
    points, cells, data = _arrays(mesh)
    with ThreadPoolExecutor(max_workers=max(1, threads)) as pool:
        for tag, arrays in ((b"Points", points), (b"Cells", cells), (b"CellData", data)):
            out.write(b"<" + tag + b">\n")
            for array in arrays:
                out.write(array.xml())
                if compress is None:
                    _write_raw(out, array)
                else:
                    _write_compressed(out, array, compress, pool, 2 * max(1, threads))
                out.write(b"\n</DataArray>\n")
            out.write(b"</" + tag + b">\n")
    out.write(b"</Piece>\n</UnstructuredGrid>\n</VTKFile>\n")
