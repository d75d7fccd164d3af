"""Partitioned mesh files: a ``.vtu`` or ``.h5`` piece per partition, and an index over them.

Layout, for an index ``out.pvtu`` (or ``out.xdmf``)::

    out.pvtu                                the index: ParaView's parallel VTU, one <Piece> per
                                            partition
    out.pvtu.pieces/1a2b3c4d/out_0000.vtu   partition 0, ... (a folder of its own per write)
    out.xdmf                                or an XDMF spatial collection, with
    out.xdmf.pieces/1a2b3c4d/out_0000.h5    its HDF5 pieces

**VTU pieces** are VTK XML unstructured grids with raw appended binary data (``header_type
UInt64``, little endian), written array by array in bounded chunks: polygon cells followed by the
piece's boundary edges as line cells, the cell data of :mod:`blockmesh.io.vtu.format` (``block_id``,
``region``, ``parent``, ``patch``; -1 where they do not apply) plus ``boundary_order`` (the
position of a line in the whole mesh's boundary list), and the point data ``GlobalNodeIds``
(Int64, the node's id in the whole mesh) and ``vtkGhostType`` (UInt8, 1 = a duplicate of a node
another piece owns). The ``.pvtu`` index names ``GlobalNodeIds`` as the global ids, so ParaView
merges the pieces seamlessly.

**HDF5 pieces** hold ``/mesh/points``, ``/mesh/cells``, ``/mesh/block_id``, ``/mesh/region``,
``/mesh/parent``, ``/mesh/global_node_ids``, ``/mesh/ghost``, ``/boundary/edges``,
``/boundary/patch`` and ``/boundary/order``; the ``.xdmf`` index is a spatial collection of
one polygon grid and one polyline grid per piece.

Every piece and the index carry a JSON attribute ``blockmesh``: the names, level and mesh name
(as :func:`blockmesh.io.common.encode_metadata`), and the piece's place in the whole.

Examples
--------
>>> import pathlib, tempfile, blockmesh
>>> from blockmesh.distributed.partition import partition
>>> from blockmesh.distributed.pieces import build_piece
>>> piece = build_piece(partition(blockmesh.load_domain("joined-2"), 2, 2), 1)
>>> path = write_vtu_piece(piece, pathlib.Path(tempfile.mkdtemp()) / "p.vtu")
>>> back = read_piece(path)
>>> bool((back.global_node_ids == piece.global_node_ids).all()), back.mesh.n_cells
(True, 36)
"""

from __future__ import annotations

import itertools
import json
import os
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, Any
from xml.sax.saxutils import quoteattr

import numpy as np

from blockmesh._system.bounded import (
    check_regular,
    confined,
    current_guard,
    open_regular,
    parse_xml,
)
from blockmesh.distributed.pieces import Piece
from blockmesh.errors import ExportError
from blockmesh.io.xdmf.reader import HeavyData
from blockmesh.mesh.mesh import Mesh

__all__ = [
    "INDEX_SUFFIXES",
    "piece_name",
    "pieces_dir",
    "read_piece",
    "read_pieces",
    "write_h5_piece",
    "write_pvtu_index",
    "write_vtu_piece",
    "write_xdmf_index",
]

#: Index files a partitioned mesh can have, and the extension of their pieces.
INDEX_SUFFIXES = {".pvtu": ".vtu", ".xdmf": ".h5"}

_CHUNK = 1 << 18
_VTK_POLYGON, _VTK_LINE = 7, 3
_CELL_DATA = ("block_id", "region", "parent")
_TYPES: dict[np.dtype, str] = {
    np.dtype(np.float64): "Float64",
    np.dtype(np.int64): "Int64",
    np.dtype(np.uint8): "UInt8",
    np.dtype(np.int32): "Int32",
}


def pieces_dir(index: Path) -> Path:
    """The folder of an index's pieces: ``out.pvtu.pieces`` beside ``out.pvtu``."""
    index = Path(index)
    return index.with_name(index.name + ".pieces")


def piece_name(index: Path, piece: int) -> str:
    """File name of piece ``piece`` of ``index``: ``out_0003.vtu`` for ``out.pvtu``."""
    index = Path(index)
    return f"{index.stem}_{piece:04d}{INDEX_SUFFIXES[index.suffix.lower()]}"


def _metadata(piece: Piece) -> dict[str, Any]:
    mesh = piece.mesh
    return {
        "blockmesh_piece": 1,
        "name": mesh.name,
        "level": int(mesh.level),
        "patch_names": list(mesh.patch_names),
        "region_names": list(mesh.region_names),
        "piece": piece.index,
        "pieces": piece.n_pieces,
        "first_cell": piece.first_cell,
        "cells_total": piece.n_cells_total,
        "nodes_total": piece.n_nodes_total,
        "boundary_total": piece.n_boundary_total,
    }


# ------------------------------------------------------------------------------ VTU pieces
class _Appended:
    """Arrays of a VTU file's appended section: their headers now, their bytes streamed later."""

    def __init__(self) -> None:
        self.offset = 0
        self.writers: list[tuple[int, Any]] = []

    def add(self, nbytes: int, chunks) -> int:
        """Reserve ``nbytes`` (written by the generator ``chunks``); returns the array's offset."""
        offset = self.offset
        self.writers.append((nbytes, chunks))
        self.offset += 8 + nbytes
        return offset

    def write(self, handle: IO[bytes]) -> None:
        for nbytes, chunks in self.writers:
            handle.write(np.uint64(nbytes).tobytes())
            written = 0
            for chunk in chunks():
                handle.write(np.ascontiguousarray(chunk).data)
                written += chunk.nbytes
            if written != nbytes:  # pragma: no cover - a bug in this module
                raise ExportError(f"internal error: wrote {written} of {nbytes} bytes")


def _in_chunks(*arrays: np.ndarray) -> Iterator[np.ndarray]:
    for array in arrays:
        flat = array.reshape(-1)
        for start in range(0, flat.size, _CHUNK):
            yield flat[start : start + _CHUNK]


def _points_xyz(points: np.ndarray) -> Iterator[np.ndarray]:
    buffer = np.zeros((min(_CHUNK, max(points.shape[0], 1)), 3))
    for start in range(0, points.shape[0], _CHUNK):
        block = points[start : start + _CHUNK]
        out = buffer[: block.shape[0]]
        out[:, :2] = block
        yield out


def _filled(value: int, count: int, dtype) -> Iterator[np.ndarray]:
    block = np.full(min(_CHUNK, max(count, 1)), value, dtype=dtype)
    for start in range(0, count, _CHUNK):
        yield block[: min(_CHUNK, count - start)]


def _offsets(n_cells: int, n_lines: int) -> Iterator[np.ndarray]:
    for start in range(0, n_cells, _CHUNK):
        yield 5 * np.arange(start + 1, min(start + _CHUNK, n_cells) + 1, dtype=np.int64)
    for start in range(0, n_lines, _CHUNK):
        stop = min(start + _CHUNK, n_lines)
        yield 5 * n_cells + 2 * np.arange(start + 1, stop + 1, dtype=np.int64)


def _data_array(name: str | None, dtype, offset: int, components: int = 1) -> str:
    named = f" Name={quoteattr(name)}" if name else ""
    parts = f' NumberOfComponents="{components}"' if components > 1 else ""
    return (
        f'<DataArray type="{_TYPES[np.dtype(dtype)]}"{named}{parts} format="appended" '
        f'offset="{offset}"/>\n'
    )


def _field_data(meta: dict[str, Any]) -> str:
    data = np.frombuffer(json.dumps(meta, ensure_ascii=False).encode("utf-8"), dtype=np.uint8)
    return (
        f'<FieldData>\n<DataArray type="UInt8" Name="blockmesh" NumberOfTuples="{data.size}" '
        f'format="ascii">\n{" ".join(map(str, data.tolist()))}\n</DataArray>\n</FieldData>\n'
    )


def write_vtu_piece(piece: Piece, path: Path) -> Path:
    """Write ``piece`` to ``path`` as VTU with raw appended data. O(piece), bounded memory."""
    mesh = piece.mesh
    m, eb, n = mesh.n_cells, int(mesh.boundary_edges.shape[0]), mesh.n_points
    data = _Appended()
    point_data = _data_array(
        "GlobalNodeIds", np.int64, data.add(8 * n, lambda: _in_chunks(piece.global_node_ids))
    )
    point_data += _data_array(
        "vtkGhostType", np.uint8, data.add(n, lambda: _in_chunks(piece.ghost.view(np.uint8)))
    )
    cell_data = ""
    for name in _CELL_DATA:
        values = getattr(mesh, name)
        offset = data.add(
            8 * (m + eb),
            lambda values=values: itertools.chain(_in_chunks(values), _filled(-1, eb, np.int64)),
        )
        cell_data += _data_array(name, np.int64, offset)
    offset = data.add(
        8 * (m + eb),
        lambda: itertools.chain(_filled(-1, m, np.int64), _in_chunks(mesh.boundary_patch)),
    )
    cell_data += _data_array("patch", np.int64, offset)
    offset = data.add(
        8 * (m + eb),
        lambda: itertools.chain(_filled(-1, m, np.int64), _in_chunks(piece.boundary_order)),
    )
    cell_data += _data_array("boundary_order", np.int64, offset)
    points = _data_array(None, np.float64, data.add(24 * n, lambda: _points_xyz(mesh.points)), 3)
    connectivity = data.add(
        8 * (5 * m + 2 * eb), lambda: _in_chunks(mesh.cells, mesh.boundary_edges)
    )
    offsets = data.add(8 * (m + eb), lambda: _offsets(m, eb))
    types = data.add(
        m + eb,
        lambda: itertools.chain(
            _filled(_VTK_POLYGON, m, np.uint8), _filled(_VTK_LINE, eb, np.uint8)
        ),
    )
    header = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt64">\n<UnstructuredGrid>\n'
        + _field_data(_metadata(piece))
        + f'<Piece NumberOfPoints="{n}" NumberOfCells="{m + eb}">\n'
        + f'<PointData GlobalIds="GlobalNodeIds">\n{point_data}</PointData>\n'
        + f"<CellData>\n{cell_data}</CellData>\n"
        + f"<Points>\n{points}</Points>\n"
        + "<Cells>\n"
        + _data_array("connectivity", np.int64, connectivity)
        + _data_array("offsets", np.int64, offsets)
        + _data_array("types", np.uint8, types)
        + "</Cells>\n</Piece>\n</UnstructuredGrid>\n"
        + '<AppendedData encoding="raw">\n_'
    )
    path = Path(path)
    with open(path, "wb") as handle:
        handle.write(header.encode("utf-8"))
        data.write(handle)
        handle.write(b"\n</AppendedData>\n</VTKFile>\n")
    return path


def write_pvtu_index(path: Path, pieces: Sequence[str], meta: dict[str, Any]) -> Path:
    """Write the ``.pvtu`` index over the piece files ``pieces`` (paths relative to it)."""
    cell_arrays = "".join(
        f'<PDataArray type="Int64" Name="{name}"/>\n'
        for name in (*_CELL_DATA, "patch", "boundary_order")
    )
    sources = "".join(f"<Piece Source={quoteattr(source)}/>\n" for source in pieces)
    text = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt64">\n<PUnstructuredGrid GhostLevel="0">\n'
        + _field_data(meta)
        + '<PPointData GlobalIds="GlobalNodeIds">\n'
        + '<PDataArray type="Int64" Name="GlobalNodeIds"/>\n'
        + '<PDataArray type="UInt8" Name="vtkGhostType"/>\n</PPointData>\n'
        + f"<PCellData>\n{cell_arrays}</PCellData>\n"
        + '<PPoints>\n<PDataArray type="Float64" NumberOfComponents="3"/>\n</PPoints>\n'
        + sources
        + "</PUnstructuredGrid>\n</VTKFile>\n"
    )
    Path(path).write_text(text, encoding="utf-8")
    return Path(path)


# ------------------------------------------------------------------------------ HDF5 pieces
def write_h5_piece(piece: Piece, path: Path) -> Path:
    """Write ``piece`` to ``path`` as an HDF5 file (the layout of the module docstring)."""
    import h5py

    mesh = piece.mesh
    with h5py.File(path, "w") as f:
        f.attrs["blockmesh"] = json.dumps(_metadata(piece), ensure_ascii=False)
        g = f.create_group("mesh")
        g.create_dataset("points", data=mesh.points)
        g.create_dataset("cells", data=mesh.cells)
        for name in _CELL_DATA:
            g.create_dataset(name, data=getattr(mesh, name))
        g.create_dataset("global_node_ids", data=piece.global_node_ids)
        g.create_dataset("ghost", data=piece.ghost.view(np.uint8))
        b = f.create_group("boundary")
        b.create_dataset("edges", data=mesh.boundary_edges)
        b.create_dataset("patch", data=mesh.boundary_patch)
        b.create_dataset("order", data=piece.boundary_order)
    return Path(path)


def _item(parent: ET.Element, source: str, dataset: str, shape, dtype) -> None:
    dtype = np.dtype(dtype)
    item = ET.SubElement(
        parent,
        "DataItem",
        Dimensions=" ".join(str(s) for s in shape),
        NumberType={"f": "Float", "u": "UInt"}.get(dtype.kind, "Int"),
        Precision=str(dtype.itemsize),
        Format="HDF",
    )
    item.text = f"{source}:{dataset}"


def write_xdmf_index(
    path: Path, pieces: Sequence[str], counts: Sequence[dict[str, int]], meta: dict[str, Any]
) -> Path:
    """Write the ``.xdmf`` index: a spatial collection over the HDF5 ``pieces``.

    ``counts[p]`` gives piece p's ``nodes``, ``cells`` and ``boundary_edges``.
    """
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    ET.SubElement(domain, "Information", Name="blockmesh", Value=json.dumps(meta))
    collection = ET.SubElement(
        domain,
        "Grid",
        Name=meta.get("name") or "mesh",
        GridType="Collection",
        CollectionType="Spatial",
    )
    for k, (source, count) in enumerate(zip(pieces, counts, strict=True)):
        n, m, eb = count["nodes"], count["cells"], count["boundary_edges"]
        for kind, topology, dataset, size, width in (
            ("cells", "Polygon", "/mesh/cells", m, 5),
            ("boundary", "Polyline", "/boundary/edges", eb, 2),
        ):
            if size == 0:
                continue
            grid = ET.SubElement(collection, "Grid", Name=f"{kind}_{k:04d}", GridType="Uniform")
            top = ET.SubElement(
                grid,
                "Topology",
                TopologyType=topology,
                NodesPerElement=str(width),
                NumberOfElements=str(size),
            )
            _item(top, source, dataset, (size, width), np.int64)
            geometry = ET.SubElement(grid, "Geometry", GeometryType="XY")
            _item(geometry, source, "/mesh/points", (n, 2), np.float64)
            for name, center, where, length, dtype in (
                ("GlobalNodeIds", "Node", "/mesh/global_node_ids", n, np.int64),
                ("vtkGhostType", "Node", "/mesh/ghost", n, np.uint8),
                *(
                    ((name, "Cell", f"/mesh/{name}", m, np.int64) for name in _CELL_DATA)
                    if kind == "cells"
                    else (
                        ("patch", "Cell", "/boundary/patch", eb, np.int64),
                        ("boundary_order", "Cell", "/boundary/order", eb, np.int64),
                    )
                ),
            ):
                attribute = ET.SubElement(
                    grid, "Attribute", Name=name, AttributeType="Scalar", Center=center
                )
                _item(attribute, source, where, (length,), dtype)
    ET.indent(root)
    with open(path, "wb") as handle:
        handle.write(b'<?xml version="1.0" encoding="utf-8"?>\n')
        ET.ElementTree(root).write(handle, encoding="utf-8", xml_declaration=False)
        handle.write(b"\n")
    return Path(path)


# ------------------------------------------------------------------------------ reading back
def _vtu_arrays(path: Path) -> tuple[dict[str, Any], dict[str, np.ndarray], int, int]:
    """The metadata, every named array, and the point and cell counts of a VTU piece.

    Every offset and length is checked against the file before its array is taken.
    """
    where = str(path)
    with open_regular(path) as handle:
        size = os.fstat(handle.fileno()).st_size
        current_guard(where).allocate(size, "the piece")
        raw = handle.read()
    marker = raw.find(b'<AppendedData encoding="raw">')
    start = raw.find(b"_", marker) + 1
    if marker < 0 or start <= 0:
        raise ExportError(f"{path} is not a blockmesh VTU piece (no raw appended data)")
    root = parse_xml(raw[:marker] + b"</VTKFile>", where)
    piece = root.find("UnstructuredGrid/Piece")
    field = root.find("UnstructuredGrid/FieldData/DataArray[@Name='blockmesh']")
    if piece is None or field is None or field.text is None:
        raise ExportError(f"{path} is not a blockmesh VTU piece")
    try:
        meta = json.loads(bytes(int(v) for v in field.text.split()).decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as error:
        raise ExportError(f"{path}: the blockmesh field data is not JSON ({error})") from None
    dtypes = {name: dtype for dtype, name in _TYPES.items()}
    arrays: dict[str, np.ndarray] = {}
    for element in piece.iter("DataArray"):
        name = element.get("Name") or "Points"
        text = element.get("offset", "0")
        dtype = dtypes.get(element.get("type", ""))
        if not text.isdigit() or dtype is None:
            raise ExportError(f"{path}: the array {name!r:.60} has no offset or a type of its own")
        offset = start + int(text)
        if offset + 8 > len(raw):
            raise ExportError(f"{path}: the array {name!r:.60} starts past the end of the file")
        nbytes = int(np.frombuffer(raw, dtype=np.uint64, count=1, offset=offset)[0])
        if nbytes > len(raw) - offset - 8 or nbytes % dtype.itemsize:
            raise ExportError(
                f"{path}: the array {name!r:.60} announces {nbytes:,} bytes, past the end of the "
                "file (damaged or truncated)"
            )
        values = np.frombuffer(raw, dtype=dtype, count=nbytes // dtype.itemsize, offset=offset + 8)
        arrays[name] = values
    counts = (piece.get("NumberOfPoints", "0"), piece.get("NumberOfCells", "0"))
    if not all(c.isdigit() and len(c) < 19 for c in counts):
        raise ExportError(f"{path}: the piece's counts {counts} are not whole numbers")
    return meta, arrays, int(counts[0]), int(counts[1])


#: The piece metadata that are counts, and what each counts.
_COUNTS = ("piece", "pieces", "first_cell", "cells_total", "nodes_total", "boundary_total")


def _piece_from_arrays(meta: dict[str, Any], a: dict[str, np.ndarray], where: str) -> Piece:
    if not isinstance(meta, dict) or not all(
        isinstance(meta.get(key), int) and not isinstance(meta.get(key), bool)
        and 0 <= meta[key] < 2**62
        for key in (*_COUNTS, "level")
    ):  # fmt: skip
        raise ExportError(f"{where} is not a complete blockmesh piece: its counts are not whole")
    n_nodes, n_boundary = meta["nodes_total"], meta["boundary_total"]
    try:
        ids = np.asarray(a["global_node_ids"], dtype=np.int64)
        order = np.asarray(a["order"], dtype=np.int64)
        cells = np.asarray(a["cells"], dtype=np.int64).reshape(-1, 5)
        edges = np.asarray(a["edges"], dtype=np.int64).reshape(-1, 2)
        points = np.asarray(a["points"], dtype=np.float64).reshape(-1, 2)
    except (KeyError, ValueError, TypeError) as error:
        raise ExportError(f"{where} is not a complete blockmesh piece: {error}") from None
    n = points.shape[0]
    if (
        ids.size != n
        or (ids.size and (ids.min() < 0 or ids.max() >= n_nodes))
        or (order.size and (order.min() < 0 or order.max() >= n_boundary))
        or order.size != edges.shape[0]
        or (cells.size and (cells.min() < 0 or cells.max() >= n))
        or (edges.size and (edges.min() < 0 or edges.max() >= n))
        or meta["piece"] >= meta["pieces"]
    ):
        raise ExportError(
            f"{where} is not a consistent blockmesh piece: node ids, cells, boundary lines or the "
            "piece number are out of range"
        )
    try:
        mesh = Mesh._trusted(
            points=np.asarray(a["points"], dtype=np.float64).reshape(-1, 2),
            cells=a["cells"].reshape(-1, 5),
            block_id=a["block_id"],
            parent=a["parent"],
            boundary_edges=a["edges"].reshape(-1, 2),
            boundary_patch=a["patch"],
            patch_names=tuple(meta["patch_names"]),
            region=a["region"],
            region_names=tuple(meta["region_names"]),
            level=int(meta["level"]),
            name=str(meta["name"]),
        )
        return Piece(
            mesh=mesh,
            global_node_ids=np.asarray(a["global_node_ids"], dtype=np.int64),
            ghost=np.asarray(a["ghost"]).astype(bool),
            boundary_order=np.asarray(a["order"], dtype=np.int64),
            index=int(meta["piece"]),
            n_pieces=int(meta["pieces"]),
            first_cell=int(meta["first_cell"]),
            n_cells_total=int(meta["cells_total"]),
            n_nodes_total=int(meta["nodes_total"]),
            n_boundary_total=int(meta["boundary_total"]),
        )
    except (KeyError, ValueError, TypeError) as error:
        raise ExportError(f"{where} is not a complete blockmesh piece: {error}") from None


def read_piece(path: Path) -> Piece:
    """Read a piece written by :func:`write_vtu_piece` or :func:`write_h5_piece`."""
    path = Path(path)
    check_regular(path)
    if path.suffix.lower() == ".h5":
        heavy = HeavyData(path.parent, str(path), None)
        try:
            names = {
                "points": "mesh/points",
                "cells": "mesh/cells",
                "global_node_ids": "mesh/global_node_ids",
                "ghost": "mesh/ghost",
                "edges": "boundary/edges",
                "patch": "boundary/patch",
                "order": "boundary/order",
                **{name: f"mesh/{name}" for name in _CELL_DATA},
            }
            arrays = {key: heavy.dataset(f"{path.name}:{item}") for key, item in names.items()}
            raw_meta = heavy.metadata(next(iter(heavy.files)))
        finally:
            heavy.close()
        try:
            meta = json.loads(raw_meta or "")
        except ValueError as error:
            raise ExportError(f"{path}: no blockmesh metadata ({error})") from None
        return _piece_from_arrays(meta, arrays, str(path))
    meta, raw, _, n_cells = _vtu_arrays(path)
    missing = {"types", "connectivity", "Points", "GlobalNodeIds", "vtkGhostType"} - set(raw)
    missing |= {"patch", "boundary_order", *_CELL_DATA} - set(raw)
    if missing:
        raise ExportError(f"{path} is not a blockmesh VTU piece: no {', '.join(sorted(missing))}")
    m = int(np.count_nonzero(raw["types"] == _VTK_POLYGON))
    connectivity = raw["connectivity"]
    arrays = {
        "points": raw["Points"].reshape(-1, 3)[:, :2],
        "cells": connectivity[: 5 * m],
        "edges": connectivity[5 * m :],
        "global_node_ids": raw["GlobalNodeIds"],
        "ghost": raw["vtkGhostType"],
        "patch": raw["patch"][m:n_cells],
        "order": raw["boundary_order"][m:n_cells],
        **{name: raw[name][:m] for name in _CELL_DATA},
    }
    return _piece_from_arrays(meta, arrays, str(path))


def read_pieces(index: Path) -> list[Path]:
    """The piece files an index (``.pvtu`` or ``.xdmf``) names, in order."""
    index = Path(index)
    where = str(index)
    with open_regular(index) as handle:
        size = os.fstat(handle.fileno()).st_size
        current_guard(where).allocate(8 * size, "the index's XML tree")
        root = parse_xml(handle.read(), where)
    if index.suffix.lower() == ".pvtu":
        sources = [p.get("Source", "") for p in root.iter("Piece")]
    else:
        sources = []
        seen: set[str] = set()
        for item in root.iter("DataItem"):
            source = (item.text or "").strip().partition(":")[0]
            if source and source not in seen:
                seen.add(source)
                sources.append(source)
    return [confined(index.parent, source, where, "piece") for source in sources]
