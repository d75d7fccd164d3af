"""MATLAB ``.mat`` (v5) for PolyMesher-style and virtual element (VEM) codes.

Variables (every index and id 1-based, as MATLAB counts):

================== ============================================================================
``Node``           N x 2 double, the node coordinates
``Element``        M x 1 cell array; ``Element{k}`` is a 1 x 5 double row of the node ids of cell
                   k, counter-clockwise (what PolyMesher and VEM codes take)
``BoundaryNodes``  struct, one field per patch: the sorted node ids on that patch (column)
``BoundaryEdges``  struct, one field per patch: E x 2 node ids, domain on the left of each edge
``BlockId``        M x 1, the block of each cell (block id + 1)
``Region``         M x 1, index into ``RegionNames``
``Parent``         M x 1, the cell's parent at the previous level (0 at level 0)
``PatchNames``     1 x P cell array of char; ``RegionNames`` likewise
``InterfaceEdges`` struct, one field per interface of a composite domain: E x 2 node ids, the
                   interface's first region on the left of each edge (only with interfaces)
``InterfaceNames`` 1 x I cell array of char (only with interfaces)
``Level``          the refinement level; ``Name`` the mesh name
``CurvedEdges``    (a mesh with curved edges only) how many: the file keeps the nodes on the
                   curves but not the curves, and :func:`read_mat` warns that refining the mesh
                   read gives straight edges
``CellLevel``      M x 1, per cell its refinement level (polygon meshes only)
``Kind``           ``'polygons'`` for a polygon mesh (then ``Element{k}`` has as many ids as cell
                   k has vertices, hanging nodes included)
================== ============================================================================

Struct field names are the patch names made valid MATLAB identifiers (other characters become
``_``, a leading non-letter gets ``p_``); fields are in ``PatchNames`` order, which is how
:func:`read_mat` maps them back.

scipy writes a cell array one element at a time (about 30 s for 1.7 M cells), so ``Element`` is
written here as one block of identical fixed-size records built with numpy and appended after
the variables :func:`scipy.io.savemat` writes. ``compression="zlib"`` compresses every variable
(MATLAB's default); ``"none"`` is the default here (faster).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> import scipy.io
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 1)
>>> path = write_mat(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.mat")
>>> data = scipy.io.loadmat(path)
>>> data["Node"].shape, data["Element"].shape, data["Element"][0, 0].tolist()
((15, 2), (6, 1), [[1.0, 6.0, 11.0, 15.0, 10.0]])
"""

from __future__ import annotations

import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from blockmesh._system.atomic import atomic_file
from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError, ResourceError
from blockmesh.io.common import Format, mesh_from_arrays
from blockmesh.io.mat.check import check_mat
from blockmesh.io.names import MATLAB_NAME
from blockmesh.io.polygons import POLYGONS, polygon_mesh_from_arrays
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["FORMAT", "matlab_name", "read_mat", "write_mat"]

_MI_INT8, _MI_INT32, _MI_UINT32, _MI_DOUBLE, _MI_MATRIX, _MI_COMPRESSED = 1, 5, 6, 9, 14, 15
_MX_CELL, _MX_DOUBLE = 1, 6


def matlab_name(name: str) -> str:
    """``name`` made a valid MATLAB identifier (at most 63 characters; see :data:`MATLAB_NAME`).

    Examples
    --------
    >>> matlab_name("outer wall"), matlab_name("2nd"), len(matlab_name("x" * 100))
    ('outer_wall', 'p_2nd', 63)
    """
    return MATLAB_NAME.clean(name)


def _record(k: int) -> np.dtype:
    """One element of the cell array: tag, flags, dims (1, k), empty name, real part (k doubles)."""
    return np.dtype([("head", "<u4", (14,)), ("data", "<f8", (k,))])


def _record_head(k: int) -> list[int]:
    return [_MI_MATRIX, 48 + 8 * k, _MI_UINT32, 8, _MX_DOUBLE, 0,
            _MI_INT32, 8, 1, k, _MI_INT8, 0, _MI_DOUBLE, 8 * k]  # fmt: skip


def _cell_array_bytes(name: str, rows: np.ndarray) -> bytes:
    """A MAT v5 ``miMATRIX`` element: an M x 1 cell array of 1 x k double rows. O(M k)."""
    m, k = rows.shape
    # each cell: tag, flags, dims (1, k), empty name, real part (k doubles)
    cells = np.empty(m, dtype=_record(k))
    cells["head"] = _record_head(k)
    cells["data"] = rows
    body = cells.tobytes()
    raw = name.encode("ascii")
    padded = raw + b"\0" * (-len(raw) % 8)
    header = np.array(
        [_MI_UINT32, 8, _MX_CELL, 0, _MI_INT32, 8, m, 1, _MI_INT8, len(raw)], dtype="<u4"
    ).tobytes()
    size = len(header) + len(padded) + len(body)
    if size >= 2**32:
        raise ExportError(
            f"the mesh is too large for a MATLAB v5 file ({m} cells); use --format xdmf or npz"
        )
    return np.array([_MI_MATRIX, size], dtype="<u4").tobytes() + header + padded + body


def _ragged_cell_array_bytes(name: str, offsets: np.ndarray, nodes: np.ndarray) -> bytes:
    """A MAT v5 M x 1 cell array of 1 x k_c double rows (k_c varying), built with numpy. O(S)."""
    sizes = np.diff(offsets)
    m = sizes.size
    record = 56 + 8 * sizes  # the head (14 uint32) and k doubles: always a multiple of 8
    starts = np.concatenate([[0], np.cumsum(record)])
    body = np.zeros(int(starts[-1]), dtype=np.uint8)
    for k in np.unique(sizes).tolist():
        mine = np.flatnonzero(sizes == k)
        rows = np.empty(mine.size, dtype=_record(k))
        rows["head"] = _record_head(k)
        rows["data"] = nodes[offsets[mine][:, None] + np.arange(k)] + 1.0
        flat = np.frombuffer(rows.tobytes(), dtype=np.uint8).reshape(mine.size, -1)
        body[starts[mine][:, None] + np.arange(flat.shape[1])] = flat
    raw = name.encode("ascii")
    padded = raw + b"\0" * (-len(raw) % 8)
    header = np.array(
        [_MI_UINT32, 8, _MX_CELL, 0, _MI_INT32, 8, m, 1, _MI_INT8, len(raw)], dtype="<u4"
    ).tobytes()
    size = len(header) + len(padded) + body.size
    if size >= 2**32:
        raise ExportError(
            f"the mesh is too large for a MATLAB v5 file ({m} cells); use --format xdmf or npz"
        )
    return np.array([_MI_MATRIX, size], dtype="<u4").tobytes() + header + padded + body.tobytes()


def write_mat(mesh: Mesh | PolygonMesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (atomically) as a MATLAB v5 file; returns the path. O(N + M)."""
    import scipy.io

    fields = MATLAB_NAME.unique(mesh.patch_names)
    nodes, edges = {}, {}
    for k, field in enumerate(fields):
        e = mesh.boundary_edges[mesh.boundary_patch == k] + 1.0
        edges[field] = e.reshape(-1, 2)
        nodes[field] = np.unique(e).reshape(-1, 1)
    variables = {
        "Node": mesh.points,
        "BoundaryNodes": nodes,
        "BoundaryEdges": edges,
        "BlockId": (mesh.block_id + 1.0).reshape(-1, 1),
        "Region": (mesh.region + 1.0).reshape(-1, 1),
        "Parent": (mesh.parent + 1.0).reshape(-1, 1),
        "PatchNames": np.array(list(mesh.patch_names), dtype=object).reshape(1, -1),
        "RegionNames": np.array(list(mesh.region_names), dtype=object).reshape(1, -1),
        "Level": float(mesh.level),
        "Name": mesh.name,
    }
    if mesh.interface_names:
        variables["InterfaceEdges"] = {
            field: (mesh.interface_edges[mesh.interface_patch == k] + 1.0).reshape(-1, 2)
            for k, field in enumerate(MATLAB_NAME.unique(mesh.interface_names))
        }
        variables["InterfaceNames"] = np.array(list(mesh.interface_names), dtype=object).reshape(
            1, -1
        )
    if mesh.curves:
        variables["CurvedEdges"] = float(len(mesh.curves))
    if isinstance(mesh, PolygonMesh):
        variables["CellLevel"] = mesh.cell_level.astype(np.float64).reshape(-1, 1)
        variables["Kind"] = POLYGONS
        element = _ragged_cell_array_bytes("Element", mesh.offsets, mesh.nodes)
    else:
        element = _cell_array_bytes("Element", (mesh.cells + 1).astype(np.float64))
    if compression == "zlib":
        packed = zlib.compress(element, 1)
        element = np.array([_MI_COMPRESSED, len(packed)], dtype="<u4").tobytes() + packed
    with atomic_file(path) as tmp, open(tmp, "wb") as f:
        scipy.io.savemat(
            f, variables, format="5", do_compression=compression == "zlib", oned_as="column"
        )
        f.write(element)
    return Path(path).absolute()


#: The variables :func:`write_mat` writes.
_VARIABLES = ("Node", "Element", "BoundaryNodes", "BoundaryEdges", "BlockId", "Region", "Parent",
              "PatchNames", "RegionNames", "Level", "Name", "InterfaceEdges",
              "InterfaceNames", "CurvedEdges", "CellLevel", "Kind")  # fmt: skip


def _chunks(f: BinaryIO, size: int, compressed: bool, step: int = 1 << 22) -> Iterator[bytes]:
    """The ``size`` bytes of a data element from ``f``, decompressed if need be, in pieces."""
    unpack = zlib.decompressobj() if compressed else None
    left = size
    while left:
        piece = f.read(min(step, left))
        if not piece:
            return
        left -= len(piece)
        if unpack is None:
            yield piece
        else:
            while piece:
                yield unpack.decompress(piece, step)
                piece = unpack.unconsumed_tail
    if unpack is not None:
        yield unpack.flush()


class _Bytes:
    """Exactly ``n`` bytes at a time from a stream of pieces."""

    def __init__(self, pieces: Iterator[bytes], compressed: bool = False) -> None:
        self.pieces, self.buf, self.compressed = pieces, bytearray(), compressed

    def take(self, n: int) -> bytes | None:
        while len(self.buf) < n:
            piece = next(self.pieces, None)
            if piece is None:
                return None
            self.buf += piece
        out = bytes(self.buf[:n])
        del self.buf[:n]
        return out


def _element_cells(path: Path) -> np.ndarray | None:
    """``Element`` as (M, 5) 0-based node ids when it has the layout :func:`write_mat` writes.

    The variables are scanned by their tags (the others are skipped, not read); the records of
    the cell array are then read in chunks straight into the result, O(M) time and no more
    memory than the result. None for any other layout (e.g. saved by MATLAB), which
    :func:`scipy.io.loadmat` then reads.
    """
    guard = current_guard(path)
    with open_regular(path) as f:
        header = f.read(128)
        if len(header) < 128 or header[126:128] != b"IM":
            return None  # not little-endian v5
        while True:
            tag = f.read(8)
            if len(tag) < 8:
                return None
            kind, size = (int(v) for v in np.frombuffer(tag, dtype="<u4"))
            start = f.tell()
            if kind in (_MI_COMPRESSED, _MI_MATRIX):
                stream = _Bytes(_chunks(f, size, kind == _MI_COMPRESSED), kind == _MI_COMPRESSED)
                inner = kind
                if kind == _MI_COMPRESSED:
                    raw = stream.take(8)
                    inner = int(np.frombuffer(raw, dtype="<u4")[0]) if raw else 0
                head = stream.take(48) if inner == _MI_MATRIX else None
                if head is not None and _name(head) == b"Element":
                    room = (
                        guard.expansion_allowed - guard.expanded_bytes
                        if kind == _MI_COMPRESSED
                        else size
                    )
                    return _records(stream, head, room, str(path))
            f.seek(start + size + (-size % 8 if kind == _MI_MATRIX else 0))  # none after zlib


def _name(head: bytes) -> bytes | None:
    """The variable name in the first 48 bytes of a miMATRIX body (None if unusual)."""
    words = np.frombuffer(head[:40], dtype="<u4")
    if words[0] != _MI_UINT32 or words[4] != _MI_INT32 or words[5] != 8 or words[8] != _MI_INT8:
        return None
    length = int(words[9])
    return head[40 : 40 + length] if length <= 8 else None


def _records(
    stream: _Bytes, head: bytes, room: int, where: str, chunk: int = 1 << 16
) -> np.ndarray | None:
    """The cells of a cell array of M records of 1 x 5 doubles (None if it is not that).

    ``room`` is the most bytes the element can hold (its size, or what its compressed data may
    expand to): M is checked against it, and the cells against the read's memory limit, before
    they are allocated.
    """
    flags = np.frombuffer(head[:40], dtype="<u4")
    m, cols = int(flags[6]), int(flags[7])
    if (int(flags[2]) & 0xFF) != _MX_CELL or cols != 1:
        return None
    record, expected = _record(5), np.array(_record_head(5), dtype="<u4")
    if m * record.itemsize > room:
        raise ExportError(
            f"{where}: Element announces {m:,} cells ({m * record.itemsize:,} bytes), more than "
            f"the file holds ({room:,} bytes; damaged, or made to expand)"
        )
    current_guard(where).allocate(40 * m, f"the {m:,} cells of Element")
    cells = np.empty((m, 5), dtype=np.int64)
    for at in range(0, m, chunk):
        n = min(chunk, m - at)
        raw = stream.take(n * record.itemsize)
        if raw is None:
            return None
        if stream.compressed:
            current_guard(where).expanded(len(raw), "Element")
        part = np.frombuffer(raw, dtype=record)
        rows = part["data"]
        with np.errstate(invalid="ignore"):  # NaN compares False: refused below
            whole = (rows == np.floor(rows)) & (np.abs(rows) < 2.0**62)  # NaN and inf fail
        if not np.all(part["head"] == expected) or not np.all(whole):
            return None
        cells[at : at + n] = rows
    cells -= 1
    return cells


def _numbers(value: Any, name: str, where: str) -> np.ndarray:
    """The variable ``name`` as float64; ExportError if it does not hold numbers."""
    array = np.asarray(value)
    if array.dtype.kind not in "biuf":
        raise ExportError(f"{where}: {name} holds {array.dtype} values, not numbers")
    return array.astype(np.float64)


def _whole(values: np.ndarray, name: str, where: str) -> np.ndarray:
    """``values`` as int64; ExportError unless they are whole numbers of int64's range."""
    if values.size and (
        not np.all(np.isfinite(values))
        or np.any(values != np.floor(values))
        or np.abs(values).max() >= 2**62
    ):
        raise ExportError(f"{where}: {name} holds values that are not whole numbers")
    return values.astype(np.int64)


def _rows(values: np.ndarray, width: int, name: str, where: str) -> np.ndarray:
    """``values`` as rows of ``width`` (a matrix of that width, or its transpose if a vector)."""
    if values.ndim == 2 and values.shape[1] == width:
        return values
    if values.size % width == 0 and values.ndim <= 2 and 1 in values.shape:
        return values.reshape(-1, width)
    raise ExportError(f"{where}: {name} has shape {values.shape}, not rows of {width}")


def _strings(value: np.ndarray) -> list[str]:
    return [str(np.asarray(v).ravel()[0]) if np.asarray(v).size else "" for v in value.ravel()]


def _element_rows(element: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray]:
    """0-based compressed rows (offsets, nodes) from ``Element`` (a cell array of any rows)."""
    if element.dtype != object:
        rows = _numbers(element, "Element", where)
        rows = rows.reshape(rows.shape[0], -1) if rows.ndim else rows.reshape(0, 0)
        parts = list(rows)
    else:
        parts = [_numbers(v, "Element", where).ravel() for v in element.ravel()]
    sizes = np.array([p.size for p in parts], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    flat = np.concatenate(parts) if parts else np.empty(0)
    return offsets, _whole(flat, "Element", where) - 1


def _cells(element: np.ndarray, where: str) -> np.ndarray:
    """0-based (M, 5) node ids from ``Element`` as scipy read it (a cell array or a matrix)."""
    if element.dtype == object:
        try:
            rows = np.vstack(list(element.ravel())).astype(np.float64) if element.size else element
        except ValueError:
            rows = np.empty((0, 0))
        if element.size and rows.shape != (element.size, 5):
            raise ExportError(
                f"{where}: some elements are not rows of 5 node ids; blockmesh reads pentagons"
            )
        rows = np.asarray(rows, dtype=np.float64).reshape(-1, 5)
    else:
        rows = np.asarray(element, dtype=np.float64).reshape(-1, 5)
    if not np.all(np.isfinite(rows)) or np.any(rows != np.floor(rows)):
        raise ExportError(f"{where}: Element holds node ids that are not whole numbers")
    cells = rows.astype(np.int64)
    cells -= 1
    return cells


def read_mat(path: Path) -> Mesh | PolygonMesh:
    """Read a mesh written by :func:`write_mat` (via :func:`scipy.io.loadmat`).

    Files from PolyMesher (``Node`` and ``Element`` only) are read too, as a Mesh when every
    element is a pentagon and a PolygonMesh otherwise; the boundary is then found from the
    cells.
    """
    import scipy.io

    where = str(path)
    try:
        fast = _element_cells(Path(path))
        check_mat(Path(path), skip=("Element",) if fast is not None else ())
        wanted = None if fast is None else [v for v in _VARIABLES if v != "Element"]
        with open_regular(path) as handle:
            data = scipy.io.loadmat(handle, squeeze_me=False, variable_names=wanted)
    except (ExportError, ResourceError):
        raise
    except Exception as exc:  # scipy raises several kinds for broken files
        raise ExportError(f"cannot read {where} as a MATLAB file: {exc}") from None
    if "Node" not in data or (fast is None and "Element" not in data):
        raise ExportError(f"{where} has no Node and Element variables (PolyMesher layout)")
    polygons = "Kind" in data and _strings(data["Kind"]) == [POLYGONS]
    offsets = nodes = np.zeros(0, np.int64)
    cells = np.zeros((0, 5), np.int64)
    if fast is None:
        offsets, nodes = _element_rows(data.pop("Element"), where)
        polygons = polygons or bool(np.any(np.diff(offsets) != 5))
        if not polygons:
            cells = nodes.reshape(-1, 5)
    else:
        cells = fast
        if polygons:
            offsets, nodes = np.arange(fast.shape[0] + 1) * 5, fast.ravel()
    del fast

    def column(name: str, shift: int) -> np.ndarray | None:
        if name not in data:
            return None
        return _whole(_numbers(data[name], name, where), name, where).ravel() - shift

    patch_names = _strings(data["PatchNames"]) if "PatchNames" in data else None
    region_names = _strings(data["RegionNames"]) if "RegionNames" in data else None
    edges = patch = None
    if "BoundaryEdges" in data and patch_names is not None:
        struct = data["BoundaryEdges"]
        fields = struct.dtype.names or ()
        if len(fields) != len(patch_names) or (fields and struct.size != 1):
            raise ExportError(
                f"{where}: BoundaryEdges has {len(fields)} fields for {len(patch_names)} PatchNames"
            )
        parts = [
            _rows(_numbers(struct.ravel()[0][f], f"BoundaryEdges.{f}", where), 2, f, where)
            for f in fields
        ]
        edges = _whole(np.concatenate(parts) if parts else np.empty((0, 2)), "BoundaryEdges", where)
        edges -= 1
        patch = np.repeat(np.arange(len(parts)), [p.shape[0] for p in parts])
    level = np.asarray(data["Level"]) if "Level" in data else 0
    common: dict[str, Any] = {
        "where": where,
        "block_id": column("BlockId", 1),
        "parent": column("Parent", 1),
        "region": column("Region", 1),
        "region_names": region_names,
        "boundary_edges": edges,
        "boundary_patch": patch,
        "patch_names": patch_names,
        "level": level,
        "name": _strings(data["Name"])[0] if "Name" in data and data["Name"].size else "",
        **_interfaces(data, where),
    }
    points = _numbers(data["Node"], "Node", where)
    if polygons:
        return polygon_mesh_from_arrays(
            points, offsets, nodes, cell_level=column("CellLevel", 0), **common
        )
    dropped = int(np.asarray(data["CurvedEdges"]).ravel()[0]) if "CurvedEdges" in data else 0
    return mesh_from_arrays(points, cells, dropped_curves=dropped, **common)


def _interfaces(data: dict, where: str) -> dict[str, Any]:
    """The interface arguments of the Mesh from ``InterfaceEdges`` and ``InterfaceNames``."""
    if "InterfaceEdges" not in data or "InterfaceNames" not in data:
        return {}
    names = _strings(data["InterfaceNames"])
    struct = data["InterfaceEdges"]
    fields = struct.dtype.names or ()
    if len(fields) != len(names):
        raise ExportError(
            f"{where}: InterfaceEdges has {len(fields)} fields for {len(names)} InterfaceNames"
        )
    if fields and struct.size != 1:
        raise ExportError(f"{where}: InterfaceEdges is not one struct ({struct.shape})")
    parts = [
        _rows(_numbers(struct.ravel()[0][f], f"InterfaceEdges.{f}", where), 2, f, where)
        for f in fields
    ]
    edges = _whole(np.concatenate(parts) if parts else np.empty((0, 2)), "InterfaceEdges", where)
    edges -= 1
    return {
        "interface_edges": edges,
        "interface_patch": np.repeat(np.arange(len(parts)), [p.shape[0] for p in parts]),
        "interface_names": names,
    }


FORMAT = Format.of(
    write_mat,
    read_mat,
    "MATLAB v5 (PolyMesher/VEM): Node, Element cell array, boundary per patch",
    compressions=("none", "zlib"),
)
