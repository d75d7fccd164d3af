"""VTK ``.vtu`` (ParaView, VisIt, meshio): polygon cells plus the boundary as ``line`` cells.

Written by :mod:`blockmesh.io.vtu.writer` in meshio's layout (arrays streamed piece by piece,
compressed blocks on several threads). The grid holds the pentagons (VTK_POLYGON) followed by
the boundary edges and then the interface edges of a composite domain (VTK_LINE), with integer
cell data

=========== =========================== ==========================================
array       on the polygons             on the lines
=========== =========================== ==========================================
block_id    the cell's block            -1
region      index into the region names -1
parent      the cell's parent (level-1) -1
patch       -1                          index into the patch names (-1: interface)
interface   -1                          index into the interface names (-1: patch)
=========== =========================== ==========================================

(``interface`` only when the mesh has interfaces.) Names, for ParaView and for blockmesh. The
*field data* holds one integer array per patch, region and interface, named ``patch:NAME``,
``region:NAME`` and ``interface:NAME``, whose value is the index the ``patch``, ``region`` and
``interface`` arrays use (ParaView lists them in its Information panel: ``patch:inlet  [1, 1]``;
a Threshold on ``interface`` shows the interface lines).
Text arrays would show better, but meshio cannot read them. The names, the level and the mesh
name are also a JSON object, the ``UInt8`` field-data array ``blockmesh`` (its UTF-8 bytes), which
blockmesh reads back. A mesh with curved edges also has the field data arrays of
:data:`~blockmesh.io.common.CURVE_ARRAYS` (``curve_edges`` flattened, ``curve_index``,
``curve_start``, ``curve_stop``, and ``curve_shapes``, the bytes of a JSON list), so that
refining the mesh read back follows its curves. meshio and VTK read all of it back.

Reading: the files blockmesh writes are decoded in chunks straight into the mesh's arrays
(:mod:`blockmesh.io.vtu.stream`, about 1.7x the mesh at its peak; a damaged one is an error
naming the array); other VTU files are read with meshio in a child process with memory and time
limits (:mod:`blockmesh.io.sandbox`).

Compression: ``"none"`` (the default: raw base64, the fastest, about twice the time of the
refinement that made the mesh), ``"zlib"`` (zlib level 1 on several threads: about 2.5x smaller
for about 4x the time of ``"none"``; ParaView reads it everywhere) or ``"lzma"`` (a third
smaller than zlib, tens of times slower). At level 7 of the l-shape (6.7 M cells) on two busy
cores: none 1.9 s of CPU and 690 MB, zlib 7.6 s and 278 MB, against 0.8 s for the refinement
(meshio's writer, before: 9.6 s and 1,111 MB, 22.4 s and 287 MB);
``benchmarks/bench_export.py --vtu`` measures them.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_vtu(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.vtu")
>>> back = read_vtu(path)
>>> bool(np.array_equal(back.cells, mesh.cells)), back.patch_names
(True, ('boundary',))
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.sax.saxutils import quoteattr

import numpy as np

if TYPE_CHECKING:
    import meshio

from blockmesh._system.atomic import atomic_file, scratch_file
from blockmesh.errors import ExportError
from blockmesh.io.common import (
    Format,
    curve_arrays,
    curves_from_arrays,
    decode_metadata,
    encode_metadata,
    line_arrays,
    mesh_from_arrays,
    name_lookup,
    splice_after,
    split_lines,
)
from blockmesh.io.polygons import (
    POLYGONS,
    blocks_to_rows,
    is_polygon_file,
    polygon_mesh_from_arrays,
)
from blockmesh.io.sandbox import read_with_meshio
from blockmesh.io.vtu.stream import read_stream
from blockmesh.io.vtu.writer import write_vtu_stream
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "FORMAT",
    "field_data",
    "holds_polygons",
    "insert_field_data",
    "mesh_from_meshio",
    "meshio_arrays",
    "meshio_mesh",
    "own_arrays",
    "padded_arrays",
    "polygon_mesh_from_meshio",
    "read_foreign",
    "read_vtu",
    "write_vtu",
]

_FIELD = "blockmesh"


def field_data(mesh: Mesh | PolygonMesh, *, curves: bool = True) -> dict[str, np.ndarray]:
    """The field data of a VTK file of ``mesh``: name lookups, metadata, curved edges.

    That is the ``KIND:NAME`` lookups, the JSON metadata (``cells: polygons`` for a polygon mesh)
    and, with ``curves``, the curved edges (:func:`~blockmesh.io.common.curve_arrays`, flattened).

    Examples
    --------
    >>> import numpy as np
    >>> from blockmesh.mesh import Mesh
    >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    >>> sorted(field_data(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]])))
    ['blockmesh', 'patch:boundary', 'region:domain']
    """
    kinds = (
        ("patch", mesh.patch_names),
        ("region", mesh.region_names),
        ("interface", mesh.interface_names),
    )
    data = {
        name: np.array([index], dtype=np.int64)
        for kind, names in kinds
        for name, index in name_lookup(kind, names).items()
    }
    extra = {"cells": POLYGONS} if isinstance(mesh, PolygonMesh) else {}
    data[_FIELD] = np.frombuffer(encode_metadata(mesh, **extra).encode("utf-8"), dtype=np.uint8)
    if curves:
        data.update({k: v.reshape(-1) for k, v in curve_arrays(mesh).items()})
    return data


def _field_data_xml(data: dict[str, np.ndarray]) -> bytes:
    arrays = []
    kinds = {"u": "UInt8", "i": "Int64", "f": "Float64"}
    for name, values in data.items():
        kind = kinds[values.dtype.kind]
        text = " ".join(map(str, values.tolist()))
        arrays.append(
            f'<DataArray type="{kind}" Name={quoteattr(name)} NumberOfTuples="{values.size}" '
            f'format="ascii">\n{text}\n</DataArray>\n'
        )
    return ("<FieldData>\n" + "".join(arrays) + "</FieldData>\n").encode("utf-8")


def insert_field_data(src: Path, dst: Path, data: dict[str, np.ndarray]) -> None:
    """Copy a VTU file meshio wrote (``src``) to ``dst`` with ``data`` as its field data.

    meshio writes no field data; ``data`` maps names to integer (or ``uint8``) arrays, as
    :func:`field_data` gives them; they go in a <FieldData> block in <UnstructuredGrid>. Other
    writers of VTU files (solutions) use it too.
    """
    tag = b"<UnstructuredGrid>"
    missing = f"unexpected VTU layout from meshio in {src}: no {tag.decode()}"
    splice_after(src, dst, tag, b"\n" + _field_data_xml(data), head=1 << 16, missing=missing)


def meshio_mesh(mesh: Mesh | PolygonMesh) -> meshio.Mesh:
    """``mesh`` as a :class:`meshio.Mesh`: polygons then lines (boundary, interfaces), -1 padded.

    A PolygonMesh's cells go in one polygon block per vertex count, with the cell data
    ``cell_index`` (each cell's position in the mesh) and ``cell_level``.
    """
    import meshio

    if isinstance(mesh, PolygonMesh):
        return _meshio_polygons(mesh)
    m = mesh.n_cells
    edges, patch, interface = line_arrays(mesh)
    eb = edges.shape[0]
    minus_m, minus_eb = np.full(m, -1, np.int64), np.full(eb, -1, np.int64)
    cells = [("polygon", mesh.cells)]
    if eb:
        cells.append(("line", edges))

    def data(on_cells: np.ndarray, on_lines: np.ndarray) -> list[np.ndarray]:
        return [on_cells, on_lines] if eb else [on_cells]

    cell_data = {
        "block_id": data(mesh.block_id, minus_eb),
        "region": data(mesh.region, minus_eb),
        "parent": data(mesh.parent, minus_eb),
        "patch": data(minus_m, patch),
    }
    if mesh.interface_names:
        cell_data["interface"] = data(minus_m, interface)
    return meshio.Mesh(
        np.column_stack([mesh.points, np.zeros(mesh.n_points)]), cells, cell_data=cell_data
    )


def _meshio_polygons(mesh: PolygonMesh) -> meshio.Mesh:
    import meshio

    groups = mesh.groups
    edges, patch, interface = line_arrays(mesh)
    eb = edges.shape[0]
    cells = [("polygon", g.cells) for g in groups]
    if eb:
        cells.append(("line", edges))
    minus_eb = np.full(eb, -1, np.int64)

    def data(values: np.ndarray | None, on_lines: np.ndarray | None = None) -> list[np.ndarray]:
        parts = [
            np.full(g.n_cells, -1, np.int64) if values is None else values[g.index] for g in groups
        ]
        return parts + ([minus_eb if on_lines is None else on_lines] if eb else [])

    cell_data = {
        "block_id": data(mesh.block_id),
        "region": data(mesh.region),
        "parent": data(mesh.parent),
        "patch": data(None, patch),
        "cell_index": data(np.arange(mesh.n_cells, dtype=np.int64)),
        "cell_level": data(mesh.cell_level),
    }
    if mesh.interface_names:
        cell_data["interface"] = data(None, interface)
    return meshio.Mesh(
        np.column_stack([mesh.points, np.zeros(mesh.n_points)]), cells, cell_data=cell_data
    )


Blocks = list[tuple[int, np.ndarray]]


def _cell_blocks(vm: meshio.Mesh, where: str, reads: str) -> tuple[Blocks, Blocks]:
    """The polygon blocks and the line blocks of ``vm`` as (index, data); ExportError for others.

    ``reads`` says what the caller reads, for the message.
    """
    blocks = [(k, c.type, np.asarray(c.data)) for k, c in enumerate(vm.cells)]
    polys = [(k, d) for k, t, d in blocks if t in ("polygon", "pentagon")]
    lines = [(k, d) for k, t, d in blocks if t == "line"]
    others = sorted({t for _, t, _ in blocks} - {"polygon", "pentagon", "line"})
    if others or not polys:
        raise ExportError(
            f"{where} holds {', '.join(others) or 'no polygon'} cells; blockmesh reads {reads}"
        )
    return polys, lines


def _line_arrays(
    vm: meshio.Mesh,
    meta: dict,
    lines: Blocks,
    gather: Callable[[str, Blocks], np.ndarray | None],
) -> tuple[dict[str, Any], list[str] | None]:
    """The line blocks as boundary and interface edges (:func:`split_lines`), and the patch names.

    ``gather(name, blocks)`` is the cell data ``name`` of those blocks, or None.
    """
    edges = np.concatenate([d for _, d in lines]) if lines else None
    patch = gather("patch", lines) if lines else None
    patch_names = _names(meta, vm.field_data, "patch")
    if edges is not None and patch is None:
        patch_names = patch_names or ["boundary"]
    lines_split = split_lines(edges, patch, gather("interface", lines) if lines else None)
    if lines_split["boundary_edges"] is None and meta:
        lines_split["boundary_edges"] = np.empty((0, 2))
    return lines_split, patch_names


def polygon_mesh_from_meshio(vm: meshio.Mesh, meta: dict, where: str) -> PolygonMesh:
    """A :class:`PolygonMesh` from a meshio mesh of polygons of any sizes (and their lines).

    The cells are taken in the file's order, or in the order of the cell data ``cell_index``
    when present (blockmesh writes one block per vertex count).
    """
    polys, lines = _cell_blocks(
        vm, where, "polygon meshes (polygon cells, optionally with boundary lines)"
    )

    def gather(name: str, which: list[tuple[int, np.ndarray]]) -> np.ndarray | None:
        if name not in vm.cell_data:
            return None
        return np.concatenate([np.asarray(vm.cell_data[name][k]).ravel() for k, _ in which])

    offsets, nodes = blocks_to_rows([d for _, d in polys])
    columns = {name: gather(name, polys) for name in ("block_id", "parent", "region", "cell_level")}
    index = gather("cell_index", polys)
    if index is not None:
        order = np.argsort(index, kind="stable")
        if not np.array_equal(index[order], np.arange(index.size)):
            raise ExportError(f"{where}: the cell_index data is not a permutation of the cells")
        sizes = np.diff(offsets)[order]
        starts = offsets[:-1][order]
        offsets = np.concatenate([[0], np.cumsum(sizes)])
        run = np.repeat(starts - offsets[:-1], sizes)
        nodes = nodes[np.arange(nodes.size) + run]
        columns = {k: None if v is None else v[order] for k, v in columns.items()}
    lines_split, patch_names = _line_arrays(vm, meta, lines, gather)
    return polygon_mesh_from_arrays(
        vm.points,
        offsets,
        nodes,
        where=where,
        region_names=_names(meta, vm.field_data, "region"),
        **lines_split,
        patch_names=patch_names,
        interface_names=_names(meta, vm.field_data, "interface"),
        level=meta.get("level", 0),
        name=meta.get("name", ""),
        **columns,
    )


def holds_polygons(vm: meshio.Mesh, meta: dict) -> bool:
    """Whether a meshio mesh read from a file is a polygon mesh (not all pentagons)."""
    if is_polygon_file(meta):
        return True
    return any(
        c.type == "polygon" and np.asarray(c.data).ndim == 2 and np.asarray(c.data).shape[1] != 5
        for c in vm.cells
    )


def write_vtu(mesh: Mesh | PolygonMesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (atomically) as VTU; returns the path. O(N + M).

    An all-pentagon mesh is streamed (:mod:`blockmesh.io.vtu.writer`): the arrays piece by
    piece, compressed blocks on several threads, in meshio's layout with the field data in place.
    A polygon mesh (cells of several sizes) goes through meshio, a polygon block per vertex count.
    """
    if not isinstance(mesh, PolygonMesh):
        with atomic_file(path) as final, open(final, "wb") as out:
            write_vtu_stream(out, mesh, _field_data_xml(field_data(mesh)), compression=compression)
        return Path(path).absolute()
    import meshio

    out = meshio_mesh(mesh)
    big = max(mesh.nodes.nbytes * 2, mesh.points.nbytes * 2) >= 2**31
    with atomic_file(path) as final, scratch_file(path) as raw:
        meshio.vtu.write(
            str(raw),
            out,
            binary=True,
            compression=None if compression == "none" else compression,
            header_type="UInt64" if big else None,
        )
        insert_field_data(raw, final, field_data(mesh))
    return Path(path).absolute()


def _names(meta: dict, fields: dict, kind: str) -> list[str] | None:
    """The names of ``kind`` from the metadata, else from the ``KIND:NAME`` lookups."""
    names = meta.get(f"{kind}_names")
    if isinstance(names, list):
        return [str(n) for n in names]
    prefix = f"{kind}:"
    lookup = {
        int(np.asarray(v).ravel()[0]): k[len(prefix) :]
        for k, v in fields.items()
        if k.startswith(prefix) and np.asarray(v).size == 1
    }
    if not lookup or sorted(lookup) != list(range(len(lookup))):
        return None
    return [lookup[k] for k in range(len(lookup))]


def _curves(meta: dict, fields: dict, where: str) -> dict[str, Any]:
    """The level, name and curves arguments of :func:`mesh_from_arrays` from the field data."""
    return {
        "level": meta.get("level", 0),
        "name": meta.get("name", ""),
        "curves": curves_from_arrays(fields, where),
        "dropped_curves": meta.get("curved_edges", 0),
    }


def mesh_from_meshio(vm: meshio.Mesh, meta: dict, where: str) -> Mesh:
    """A :class:`Mesh` from a meshio mesh of pentagons (and boundary lines) read from ``where``.

    Cell data ``block_id``, ``region``, ``parent`` and ``patch`` are used when present, names
    from ``meta`` (the JSON metadata) or the ``patch:NAME`` lookups of the field data.
    """
    return mesh_from_arrays(where=where, **meshio_arrays(vm, meta, where))


def meshio_arrays(vm: meshio.Mesh, meta: dict, where: str) -> dict[str, Any]:
    """The arguments of :func:`mesh_from_arrays` for :func:`mesh_from_meshio`."""
    polys, lines = _cell_blocks(
        vm, where, "pentagon meshes only (polygons of 5 nodes, optionally with boundary lines)"
    )
    if any(np.asarray(d).ndim != 2 or np.asarray(d).shape[1] != 5 for _, d in polys):
        raise ExportError(f"{where}: some polygons do not have 5 nodes; blockmesh reads pentagons")

    def gather(name: str, which: list[tuple[int, np.ndarray]]) -> np.ndarray | None:
        if name not in vm.cell_data:
            return None
        parts = [np.asarray(vm.cell_data[name][k]).ravel() for k, _ in which]
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    cells = polys[0][1] if len(polys) == 1 else np.concatenate([d for _, d in polys])
    lines_split, patch_names = _line_arrays(vm, meta, lines, gather)
    return {
        "points": vm.points,
        "cells": cells,
        "block_id": gather("block_id", polys),
        "parent": gather("parent", polys),
        "region": gather("region", polys),
        "region_names": _names(meta, vm.field_data, "region"),
        **lines_split,
        "patch_names": patch_names,
        "interface_names": _names(meta, vm.field_data, "interface"),
        **_curves(meta, vm.field_data, where),
    }


def padded_arrays(
    points: np.ndarray,
    cells: np.ndarray,
    edges: np.ndarray,
    cell_data: dict[str, tuple[np.ndarray, np.ndarray]],
    fields: dict[str, np.ndarray],
    meta: dict,
    where: str = "the file",
) -> dict[str, Any]:
    """The arguments of :func:`mesh_from_arrays` from a VTK file's arrays, read directly.

    ``cell_data`` maps ``block_id``, ``region``, ``parent`` and ``patch`` (those present) to
    their values on the polygons and on the lines; names from ``meta`` or the field data.
    """

    def on(name: str, part: int) -> np.ndarray | None:
        return cell_data[name][part] if name in cell_data else None

    patch = on("patch", 1)
    return {
        "points": points,
        "cells": cells,
        "block_id": on("block_id", 0),
        "parent": on("parent", 0),
        "region": on("region", 0),
        "region_names": _names(meta, fields, "region"),
        **split_lines(edges, patch, on("interface", 1)),
        "patch_names": _names(meta, fields, "patch")
        or (None if patch is not None else ["boundary"]),
        "interface_names": _names(meta, fields, "interface"),
        **_curves(meta, fields, where),
    }


def own_arrays(arrays: dict[str, Any]) -> dict[str, Any]:
    """``arrays`` (from :func:`meshio_arrays`) replaced one by one by compact native copies.

    meshio's arrays are views (the polygons and the lines of one connectivity array, big-endian
    for legacy VTK, points with a z column) that :func:`mesh_from_arrays` would copy all at once
    while they are alive; copied here one at a time, each of meshio's buffers is freed as its last
    view is replaced (once the meshio mesh itself is gone). Returns ``arrays``.
    """
    for key in list(arrays):
        value = arrays[key]
        if isinstance(value, np.ndarray):
            if key == "points" and value.ndim == 2:
                value = value[:, :2]
            arrays[key] = np.array(value, dtype=value.dtype.newbyteorder("="), order="C")
            del value
    return arrays


def read_vtu(path: Path) -> Mesh | PolygonMesh:
    """Read a VTU file of pentagons (and boundary lines), as written by :func:`write_vtu`.

    Files from elsewhere are read too when their polygons are all pentagons: missing data gets
    the defaults of :func:`blockmesh.io.common.mesh_from_arrays`. The files blockmesh wrote are
    read in chunks straight into the mesh's arrays (:mod:`blockmesh.io.vtu.stream`); others with
    meshio, in a child process with memory and time limits (:mod:`blockmesh.io.sandbox`).
    """
    where = str(path)
    parts = read_stream(Path(path))  # ExportError for a damaged blockmesh file
    if parts is not None:  # pentagons only: a polygon file is never one it handles
        meta = decode_metadata(parts.fields[_FIELD].astype(np.uint8), where)
        arrays = padded_arrays(
            parts.points, parts.cells, parts.edges, parts.cell_data, parts.fields, meta, where
        )
        del parts  # the -1 padding of the cell data is freed before the Mesh is built
        return mesh_from_arrays(where=where, **arrays)
    return read_foreign(path, "vtu")  # another tool's file


def read_foreign(
    path: Path,
    kind: str,
    *,
    meta: dict | None = None,
    fields: dict[str, np.ndarray] | None = None,
) -> Mesh | PolygonMesh:
    """A mesh from a ``kind`` file (``"vtu"`` or ``"vtk"``) of another tool, read with meshio.

    meshio reads it in a child process with memory and time limits
    (:mod:`blockmesh.io.sandbox`). ``fields`` (field data read beforehand) are added to the
    file's; ``meta`` is the JSON metadata when already decoded, else it is decoded from the field
    data. Polygons of other sizes than five make a :class:`PolygonMesh`.
    """
    where = str(path)
    vm = read_with_meshio(path, kind)  # in a child process, with limits
    if fields is not None:
        vm.field_data = {**vm.field_data, **fields}
    if meta is None:
        raw = vm.field_data.get(_FIELD)
        meta = decode_metadata(None if raw is None else np.asarray(raw).astype(np.uint8), where)
    if holds_polygons(vm, meta):
        return polygon_mesh_from_meshio(vm, meta, where)
    arrays = meshio_arrays(vm, meta, where)
    del vm  # meshio's copies are freed (one by one, by own_arrays) before the Mesh is built
    return mesh_from_arrays(where=where, **own_arrays(arrays))


FORMAT = Format.of(
    write_vtu,
    read_vtu,
    "VTK unstructured grid (ParaView): polygons + boundary lines",
    compressions=("none", "zlib", "lzma"),
)
