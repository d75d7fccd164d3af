"""Legacy VTK ``.vtk`` (version 5.1, binary) for tools that read the old format, via meshio.

The same grid and cell data as :mod:`blockmesh.io.vtu.format` (pentagons as ``VTK_POLYGON``, then
the boundary edges as ``VTK_LINE``; ``block_id``, ``region``, ``parent`` and ``patch`` with -1 where
they do not apply), written by :func:`meshio.vtk.write`. The dataset's field data, added after
meshio has written the file, holds the same name lookups (``patch:NAME`` and ``region:NAME``,
integer arrays whose value is the index) and the JSON metadata ``blockmesh`` as the VTU (its bytes
as 64-bit integers: the one integer type VTK and meshio read alike in this format); in this format
an array name cannot hold white space, so names are percent-encoded as VTK does (``outer%20wall``:
VTK and ParaView show ``outer wall``).

Reading: the files blockmesh writes are read straight into the mesh's arrays
(:mod:`blockmesh.io.vtk.stream`; a damaged one is an error naming the section); other files
with meshio, in a child process with memory and time limits (:mod:`blockmesh.io.sandbox`), once
every binary section's announced size has been checked against the file.

Version 5.1 (offsets and connectivity) is what meshio and VTK 9 write; readers: VTK >= 9
(ParaView >= 5.9), meshio. Use :mod:`blockmesh.io.vtu.format` for anything newer.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_vtk(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.vtk")
>>> path.read_bytes()[:26]
b'# vtk DataFile Version 5.1'
>>> back = read_vtk(path)
>>> bool(np.array_equal(back.cells, mesh.cells)), back.level
(True, 2)
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from blockmesh._system.atomic import atomic_file, scratch_file
from blockmesh._system.bounded import open_regular
from blockmesh.errors import ExportError
from blockmesh.io.common import Format, decode_metadata, mesh_from_arrays, splice_after
from blockmesh.io.polygons import is_polygon_file
from blockmesh.io.vtk.stream import read_stream
from blockmesh.io.vtu.format import (
    field_data,
    meshio_mesh,
    padded_arrays,
    read_foreign,
)
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["FORMAT", "decode_name", "encode_name", "read_vtk", "write_vtk"]

_DATASET = b"DATASET UNSTRUCTURED_GRID\n"
#: The one array type both VTK's legacy reader and meshio's read alike (the JSON's bytes too).
_TYPES = {"vtktypeint64": np.dtype(">i8")}


def encode_name(name: str) -> str:
    """``name`` with white space, ``%``, quotes and non-ASCII bytes as ``%XX`` (VTK's rule).

    Examples
    --------
    >>> encode_name("patch:outer wall"), decode_name("patch:outer%20wall")
    ('patch:outer%20wall', 'patch:outer wall')
    """
    return "".join(
        chr(b) if 33 <= b <= 126 and b not in b'%"' else f"%{b:02X}" for b in name.encode()
    )


def decode_name(text: str) -> str:
    """The name :func:`encode_name` encoded."""
    raw = re.sub(rb"%([0-9A-Fa-f]{2})", lambda m: bytes([int(m[1], 16)]), text.encode("ascii"))
    return raw.decode("utf-8", errors="replace")


def _field_block(data: dict[str, np.ndarray]) -> bytes:
    parts = [f"FIELD FieldData {len(data)}\n".encode()]
    for name, values in data.items():
        kind = "vtktypeint64"
        parts.append(f"{encode_name(name)} 1 {values.size} {kind}\n".encode())
        parts.append(values.astype(_TYPES[kind]).tobytes() + b"\n")
    return b"".join(parts)


def write_vtk(mesh: Mesh | PolygonMesh, path: Path) -> Path:
    """Write ``mesh`` to ``path`` (atomically) as legacy VTK 5.1; returns the path. O(N + M)."""
    import meshio

    with atomic_file(path) as final, scratch_file(path) as raw:
        meshio.vtk.write(str(raw), meshio_mesh(mesh), binary=True)
        block = _field_block(field_data(mesh, curves=False))
        missing = f"unexpected legacy VTK layout from meshio in {raw}"
        splice_after(raw, final, _DATASET, block, head=1 << 12, missing=missing)
    return Path(path).absolute()


def _read_field(head: bytes, where: str) -> dict[str, np.ndarray]:
    """The dataset's field data (right after the DATASET line), if the file has it there."""
    at = head.find(_DATASET)
    if at < 0:
        return {}
    pos = at + len(_DATASET)
    eol = head.find(b"\n", pos)
    words = head[pos:eol].split()
    if len(words) != 3 or words[0] != b"FIELD":
        return {}
    out: dict[str, np.ndarray] = {}
    pos = eol + 1
    try:
        for _ in range(int(words[2])):
            eol = head.find(b"\n", pos)
            name, comps, tuples, kind = head[pos:eol].decode("ascii").split()
            dtype = _TYPES[kind]
            count = int(comps) * int(tuples)
            start = eol + 1
            stop = start + count * dtype.itemsize
            if stop > len(head):
                raise ValueError("field data larger than the header read")
            out[decode_name(name)] = np.frombuffer(head, dtype=dtype, count=count, offset=start)
            pos = stop + 1
    except (ValueError, KeyError, UnicodeDecodeError) as exc:
        raise ExportError(f"{where}: malformed dataset field data ({exc})") from None
    return out


_SIZES = {
    "double": 8, "float": 4, "vtktypeint64": 8, "vtktypeuint64": 8, "long": 8,
    "unsigned_long": 8, "int": 4, "unsigned_int": 4, "vtktypeint32": 4, "vtktypeuint32": 4,
    "short": 2, "unsigned_short": 2, "vtktypeint16": 2, "vtktypeuint16": 2, "char": 1,
    "unsigned_char": 1, "vtktypeint8": 1, "vtktypeuint8": 1,
}  # fmt: skip


def _check_sizes(path: Path, where: str) -> None:
    """ExportError if a binary legacy file announces more data than it holds (damaged).

    The sections are walked by their headers (each payload is skipped, not read; the cell
    offsets are checked), so a damaged count is caught before a reader allocates for it.
    """
    with open_regular(path) as f:
        size = os.fstat(f.fileno()).st_size
        for _ in range(2):
            f.readline(1 << 16)
        if f.readline(1 << 16).strip().upper() != b"BINARY":
            return

        def skip(count: int, kind: str, line: bytes) -> None:
            if kind not in _SIZES:
                raise LookupError(kind)
            need = count * _SIZES[kind]
            if count < 0 or f.tell() + need > size:
                raise ExportError(
                    f"{where}: the section {line[:60].decode(errors='replace')!r} announces "
                    f"{need} bytes but the file ends before (damaged?)"
                )
            f.seek(need, 1)

        items = 0
        try:
            while line := f.readline(1 << 16):
                words = line.split()
                if not words:
                    continue
                key = words[0].upper()
                if key == b"POINTS":
                    skip(3 * int(words[1]), words[2].decode().lower(), line)
                elif key in (b"OFFSETS", b"CONNECTIVITY"):
                    skip(items, words[1].decode().lower(), line)
                elif key == b"CELLS":
                    items = int(words[1])  # the offsets; the connectivity count is words[2]
                    offsets = f.readline(1 << 16)
                    kind = offsets.split()[1].decode().lower()
                    start = f.tell()
                    skip(items, kind, offsets)
                    if kind == "vtktypeint64":  # the offsets must be 0 .. count, increasing
                        f.seek(start)
                        values = np.frombuffer(f.read(8 * items), dtype=">i8")
                        if values.size and (
                            values[0] != 0
                            or values[-1] != int(words[2])
                            or np.any(np.diff(values) < 0)
                        ):
                            raise ExportError(f"{where}: the cell offsets are damaged")
                    connectivity = f.readline(1 << 16)
                    skip(int(words[2]), connectivity.split()[1].decode().lower(), connectivity)
                elif key == b"CELL_TYPES":
                    skip(int(words[1]), "int", line)
                elif key in (b"CELL_DATA", b"POINT_DATA", b"FIELD", b"DATASET"):
                    continue
                elif len(words) == 4 and words[1].isdigit() and words[2].isdigit():
                    skip(int(words[1]) * int(words[2]), words[3].decode().lower(), line)
                else:
                    return  # a section this check does not know: leave it to the reader
        except (LookupError, ValueError, IndexError, UnicodeDecodeError):
            return


def read_vtk(path: Path) -> Mesh | PolygonMesh:
    """Read a legacy VTK file of pentagons (and boundary lines), as :func:`write_vtk` writes.

    Files from elsewhere (any version meshio reads) are read too when their polygons are all
    pentagons, with the defaults of :func:`blockmesh.io.common.mesh_from_arrays`.
    """
    where = str(path)
    try:
        _check_sizes(Path(path), where)
        with open_regular(path) as f:
            head = f.read(1 << 20)
    except ExportError:
        raise
    except OSError as exc:  # an unreadable file
        raise ExportError(f"cannot read {where} as legacy VTK: {exc}") from None
    fields = _read_field(head, where)
    raw = fields.get("blockmesh")
    meta = decode_metadata(None if raw is None else raw.astype(np.uint8), where)
    polygons = is_polygon_file(meta)
    # ExportError if damaged
    parts = read_stream(Path(path)) if "blockmesh" in fields and not polygons else None
    if parts is not None:  # a file blockmesh wrote: read straight into the arrays
        arrays = padded_arrays(
            parts["points"], parts["cells"], parts["edges"], parts["cell_data"], fields, meta, where
        )
        del parts  # the -1 padding of the cell data is freed before the Mesh is built
        return mesh_from_arrays(where=where, **arrays)
    return read_foreign(path, "vtk", meta=meta, fields=fields)  # another tool's file


FORMAT = Format.of(
    write_vtk, read_vtk, "legacy VTK 5.1 (older VTK tools): polygons + boundary lines, via meshio"
)
