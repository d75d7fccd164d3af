"""A direct reader for the legacy VTK files :func:`blockmesh.io.vtk.format.write_vtk` writes.

meshio's legacy reader peaks at about 3x the mesh (its cell blocks and cell data are split and
converted in several passes). The files blockmesh writes have one fixed layout (binary VTK 5.1:
``POINTS n double``, ``CELLS``/``OFFSETS``/``CONNECTIVITY`` as ``vtktypeint64``, ``CELL_TYPES``,
and ``CELL_DATA`` as one ``FIELD`` of ``vtktypeint64`` arrays; pentagons then boundary lines),
so their payloads are read here straight into arrays of their final shape and byte-swapped in
place: the polygons and lines, and each cell data array's two parts, are read directly into
their own arrays; the points a chunk at a time (their z column dropped); the offsets and types
are checked a chunk at a time and not kept.

:func:`read_stream` returns None for a file of another layout; the caller then reads it with
meshio. A damaged file (counts beyond the file's end, cut short, offsets or types that are not
pentagons then lines) is an :class:`~blockmesh.errors.ExportError` naming the section. Every count
is checked against what is left of the file and against the read's memory limit
(:mod:`blockmesh._system.bounded`) before its array is allocated.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.io.vtk.format import write_vtk
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> path = write_vtk(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), folder / "a.vtk")
>>> parts = read_stream(path)
>>> parts["cells"].tolist(), parts["edges"].shape, sorted(parts["cell_data"])
([[0, 1, 2, 3, 4]], (5, 2), ['block_id', 'parent', 'patch', 'region'])
"""

from __future__ import annotations

from collections.abc import Callable
from io import BufferedReader
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import ReadGuard
from blockmesh.io.streams import DamagedError, NotOursError, Place, read_own_layout

__all__ = ["read_stream"]

_ROWS = 1 << 18  # rows read at a time for the points, offsets and types
_POLYGON, _LINE = 7, 3  # VTK cell types


def _room(f: BufferedReader, size: int, nbytes: int, what: str, guard: ReadGuard) -> None:
    """DamagedError unless ``nbytes`` of ``what`` fit in the rest of the file; then allocate."""
    left = size - f.tell()
    if nbytes < 0 or nbytes > left:
        raise DamagedError(
            f"{what} take {nbytes:,} bytes, but only {left:,} bytes of the file are left "
            "(damaged or truncated)"
        )
    guard.allocate(nbytes, what)


def _words(f: BufferedReader, *expected: bytes) -> list[bytes]:
    """The next line's words, whose first ones must be ``expected``."""
    words = f.readline(1 << 12).split()
    if words[: len(expected)] != list(expected):
        raise NotOursError(f"expected {expected!r}, got {words[:4]!r}")
    return words


def _into(f: BufferedReader, out: np.ndarray) -> None:
    """Fill ``out`` (native int64 or float64) from the big-endian bytes that follow."""
    view = out.reshape(-1).view(np.uint8).data  # out itself, as bytes
    if f.readinto(view) != view.nbytes:
        raise DamagedError("the file ends inside an array")
    out.byteswap(inplace=True)


def _chunks(
    f: BufferedReader, count: int, dtype: str, put: Callable[[int, np.ndarray], None]
) -> None:
    """Read ``count`` values of ``dtype`` a chunk at a time, handing each to ``put(start, v)``."""
    for start in range(0, count, _ROWS):
        n = min(_ROWS, count - start)
        raw = f.read(n * np.dtype(dtype).itemsize)
        if len(raw) != n * np.dtype(dtype).itemsize:
            raise DamagedError("the file ends inside an array")
        put(start, np.frombuffer(raw, dtype))


def _end_of_array(f: BufferedReader) -> None:
    if f.read(1) != b"\n":
        raise DamagedError("an array of another length than announced")


def _parse(f: Any, size: int, guard: ReadGuard, place: Place) -> dict[str, Any]:
    if not f.readline(64).startswith(b"# vtk DataFile Version 5.1"):
        raise NotOursError("not version 5.1")
    f.readline(1 << 12)  # the title
    _words(f, b"BINARY")
    _words(f, b"DATASET", b"UNSTRUCTURED_GRID")
    n_fields = int(_words(f, b"FIELD", b"FieldData")[2])
    for _ in range(n_fields):  # read by legacy_vtk._read_field already
        _, comps, tuples, _kind = _words(f)
        skip = int(comps) * int(tuples) * 8 + 1
        if skip < 1 or f.tell() + skip > size:
            raise DamagedError("the dataset's field data runs past the end of the file")
        f.seek(skip, 1)
    place.where = "POINTS"
    _, count, kind = _words(f, b"POINTS")
    if kind != b"double":
        raise NotOursError("points that are not doubles")
    n = int(count)
    _room(f, size, 24 * n, f"{n:,} points", guard)
    points = np.empty((n, 2))

    for start in range(0, n, _ROWS):  # (x, y, z) rows, z dropped
        k = min(_ROWS, n - start)
        raw = f.read(24 * k)
        if len(raw) != 24 * k:
            raise DamagedError("the file ends inside the points")
        points[start : start + k] = np.frombuffer(raw, ">f8").reshape(k, 3)[:, :2]
    _end_of_array(f)
    place.where = "CELLS"
    words = _words(f, b"CELLS")
    total, length = int(words[1]) - 1, int(words[2])
    m, rem = divmod(length - 2 * total, 3)  # 5 m + 2 (total - m) == length
    if rem or not 0 < m <= total:
        raise NotOursError("cells other than pentagons and lines")
    eb = total - m
    _room(f, size, 8 * (total + 1 + length), f"{total:,} cells of {length:,} node ids", guard)

    def offsets(start: int, values: np.ndarray) -> None:
        k = np.arange(start, start + values.size)
        if not np.array_equal(values, np.where(k <= m, 5 * k, 5 * m + 2 * (k - m))):
            raise DamagedError("offsets that are not those of pentagons followed by lines")

    place.where = "OFFSETS"
    _words(f, b"OFFSETS", b"vtktypeint64")
    _chunks(f, total + 1, ">i8", offsets)
    _end_of_array(f)
    place.where = "CONNECTIVITY"
    _words(f, b"CONNECTIVITY", b"vtktypeint64")
    cells, edges = np.empty((m, 5), np.int64), np.empty((eb, 2), np.int64)
    _into(f, cells)
    _into(f, edges)
    _end_of_array(f)

    def types(start: int, values: np.ndarray) -> None:
        k = np.arange(start, start + values.size)
        if not np.array_equal(values, np.where(k < m, _POLYGON, _LINE)):
            raise DamagedError("cell types that are not pentagons followed by lines")

    place.where = "CELL_TYPES"
    if int(_words(f, b"CELL_TYPES")[1]) != total:
        raise DamagedError(f"a count other than the {total:,} cells")
    _chunks(f, total, ">i4", types)
    _end_of_array(f)
    place.where = "CELL_DATA"
    if int(_words(f, b"CELL_DATA")[1]) != total:
        raise DamagedError(f"a count other than the {total:,} cells")
    cell_data: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for _ in range(int(_words(f, b"FIELD", b"FieldData")[2])):
        name, comps, tuples, kind = _words(f)
        place.where = f"the cell data {name.decode(errors='replace')!r}"
        if comps != b"1" or int(tuples) != total or kind != b"vtktypeint64":
            raise NotOursError("cell data of another kind")
        _room(f, size, 8 * total, "the cell data", guard)
        on = (np.empty(m, np.int64), np.empty(eb, np.int64))
        _into(f, on[0])
        _into(f, on[1])
        _end_of_array(f)
        cell_data[name.decode("ascii")] = on
    if f.read(1).strip():
        raise NotOursError("more after the cell data")
    return {"points": points, "cells": cells, "edges": edges, "cell_data": cell_data}


def read_stream(path: Path) -> dict[str, Any] | None:
    """The arrays of a legacy VTK file written by blockmesh; None for other files.

    Returns ``points``, ``cells``, ``edges`` and
    ``cell_data`` (``NAME -> (on the polygons, on the lines)``). Peak memory: the arrays returned
    plus a few megabytes. Raises :class:`ExportError` for a damaged file of blockmesh's layout.
    """
    # Damage is reported from the first section on: only blockmesh's layout gets past the header.
    return read_own_layout(
        path, _parse, Place(ours=True), not_ours=(ValueError, IndexError, UnicodeDecodeError)
    )
