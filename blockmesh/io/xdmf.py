"""XDMF 3 + HDF5 (``.xdmf`` with a sibling ``.h5``): the fast path for big meshes (ParaView).

meshio cannot write polygons to XDMF, so the heavy data goes straight to HDF5 with h5py and the
light XML is written with :mod:`xml.etree`. The ``.h5`` file (same stem as the ``.xdmf``) holds

================================ =================================================
``/mesh/points``      (N, 2) f8   node coordinates
``/mesh/cells``       (M, 5) i8   pentagons, counter-clockwise
``/mesh/block_id``, ``/mesh/region``, ``/mesh/parent``    (M,) i8 cell data
``/boundary/edges``   (Eb, 2) i8  boundary edges, domain on the left
``/boundary/patch``   (Eb,) i8    index into the patch names
================================ =================================================

and the root attribute ``blockmesh`` (the JSON of names, level and mesh name). The XDMF file has
one ``Domain`` with a spatial collection of two uniform grids: ``cells`` (``TopologyType="Polygon"
NodesPerElement="5"``, ``Geometry XY``, cell-centred attributes ``block_id``, ``region``,
``parent``) and ``boundary`` (``Polyline`` of 2 nodes, attribute ``patch``), both on the same
points, plus an ``Information`` element ``blockmesh`` with the same JSON.

Compression: ``"none"`` (default, fastest) or ``"zlib"`` (HDF5 gzip level 4, chunked datasets).
The ``.xdmf``/``.h5`` pair is written atomically: both under temporary names, then renamed (an
existing pair is restored if the second rename fails).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_xdmf(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.xdmf")
>>> sorted(p.name for p in path.parent.iterdir())
['sp.h5', 'sp.xdmf']
>>> back = read_xdmf(path)
>>> bool(np.array_equal(back.points, mesh.points)), back.n_cells
(True, 36)
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from ..atomic import atomic_files
from ..errors import ExportError
from ..mesh import Mesh
from ._common import Format, decode_metadata, encode_metadata, mesh_from_arrays

__all__ = ["FORMAT", "read_xdmf", "write_xdmf"]

_CELL_DATA = ("block_id", "region", "parent")


def _h5_path(path: Path) -> Path:
    return Path(path).absolute().with_suffix(".h5")


def _data_item(parent: ET.Element, h5name: str, dataset: str, arr: np.ndarray) -> None:
    number_type = "Float" if arr.dtype.kind == "f" else "Int"
    item = ET.SubElement(
        parent,
        "DataItem",
        Dimensions=" ".join(str(s) for s in arr.shape),
        NumberType=number_type,
        Precision=str(arr.dtype.itemsize),
        Format="HDF",
    )
    item.text = f"{h5name}:{dataset}"


def _xdmf_tree(mesh: Mesh, h5name: str, meta: str) -> ET.ElementTree:
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    ET.SubElement(domain, "Information", Name="blockmesh", Value=meta)
    collection = ET.SubElement(
        domain, "Grid", Name=mesh.name or "mesh", GridType="Collection", CollectionType="Spatial"
    )

    def grid(name: str, topology: str, conn_name: str, conn: np.ndarray) -> ET.Element:
        g = ET.SubElement(collection, "Grid", Name=name, GridType="Uniform")
        top = ET.SubElement(
            g,
            "Topology",
            TopologyType=topology,
            NodesPerElement=str(conn.shape[1]),
            NumberOfElements=str(conn.shape[0]),
        )
        _data_item(top, h5name, conn_name, conn)
        geo = ET.SubElement(g, "Geometry", GeometryType="XY")
        _data_item(geo, h5name, "/mesh/points", mesh.points)
        return g

    cells = grid("cells", "Polygon", "/mesh/cells", mesh.cells)
    for name in _CELL_DATA:
        att = ET.SubElement(cells, "Attribute", Name=name, AttributeType="Scalar", Center="Cell")
        _data_item(att, h5name, f"/mesh/{name}", getattr(mesh, name))
    if mesh.boundary_edges.shape[0]:
        lines = grid("boundary", "Polyline", "/boundary/edges", mesh.boundary_edges)
        att = ET.SubElement(lines, "Attribute", Name="patch", AttributeType="Scalar", Center="Cell")
        _data_item(att, h5name, "/boundary/patch", mesh.boundary_patch)
    ET.indent(root)
    return ET.ElementTree(root)


def write_xdmf(mesh: Mesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (``.xdmf``) and its sibling ``.h5``; returns the ``.xdmf`` path.

    O(N + M), bounded by disk speed without compression.
    """
    import h5py

    path = Path(path).absolute()
    h5 = _h5_path(path)
    if h5 == path:
        raise ExportError(f"cannot write {path}: the XDMF file needs a name not ending in .h5")
    meta = encode_metadata(mesh)
    options = (
        {"compression": "gzip", "compression_opts": 4, "shuffle": True}
        if compression == "zlib"
        else {}
    )
    with atomic_files(path, h5) as (tmp_xdmf, tmp_h5):
        with h5py.File(tmp_h5, "w") as f:
            f.attrs["blockmesh"] = meta
            g = f.create_group("mesh")
            g.create_dataset("points", data=mesh.points, **options)
            g.create_dataset("cells", data=mesh.cells, **options)
            for name in _CELL_DATA:
                g.create_dataset(name, data=getattr(mesh, name), **options)
            b = f.create_group("boundary")
            b.create_dataset("edges", data=mesh.boundary_edges, **options)
            b.create_dataset("patch", data=mesh.boundary_patch, **options)
        tree = _xdmf_tree(mesh, h5.name, meta)
        with open(tmp_xdmf, "wb") as f:
            f.write(
                b'<?xml version="1.0" encoding="utf-8"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n'
            )
            tree.write(f, encoding="utf-8", xml_declaration=False)
            f.write(b"\n")
    return path


def _read_item(item: ET.Element, base: Path, where: str, files: dict) -> np.ndarray:
    import h5py

    fmt = item.get("Format", "XML")
    text = (item.text or "").strip()
    dims = tuple(int(s) for s in item.get("Dimensions", "").split())
    if fmt == "XML":
        arr = np.array(
            text.split(), dtype=np.float64 if item.get("NumberType") == "Float" else np.int64
        )
    elif fmt == "HDF":
        name, _, dataset = text.partition(":")
        file = (base / name).resolve()
        if file not in files:
            if not file.exists():
                raise ExportError(f"{where} refers to {file}, which does not exist")
            files[file] = h5py.File(file, "r")
        if dataset not in files[file]:
            raise ExportError(f"{where}: {file} has no dataset {dataset}")
        arr = files[file][dataset][()]
    else:
        raise ExportError(f"{where}: DataItem Format={fmt!r} is not supported (HDF or XML)")
    return arr.reshape(dims) if dims and int(np.prod(dims)) == arr.size else arr


def read_xdmf(path: Path) -> Mesh:
    """Read a mesh written by :func:`write_xdmf` (h5py + xml.etree).

    Other XDMF files with one ``Polygon`` topology of 5 nodes per element (and optionally a
    ``Polyline`` grid of the boundary) are read too, with defaults for what they lack.
    """
    path = Path(path).absolute()
    where = str(path)
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as exc:
        raise ExportError(f"cannot read {where} as XDMF: {exc}") from None
    info = root.find(".//Information[@Name='blockmesh']")
    meta = decode_metadata(info.get("Value") if info is not None else None, where)
    cells_grid = lines_grid = None
    for g in root.iter("Grid"):
        top = g.find("Topology")
        if top is None:
            continue
        kind = top.get("TopologyType", top.get("Type", ""))
        if kind.lower() == "polygon" and cells_grid is None:
            if top.get("NodesPerElement") != "5":
                raise ExportError(
                    f"{where}: the polygons have {top.get('NodesPerElement')} nodes; "
                    "blockmesh reads pentagons"
                )
            cells_grid = g
        elif kind.lower() == "polyline" and lines_grid is None:
            lines_grid = g
    if cells_grid is None:
        raise ExportError(f'{where} has no Grid with TopologyType="Polygon" NodesPerElement="5"')
    files: dict = {}
    try:

        def item(el: ET.Element | None, what: str) -> np.ndarray:
            found = None if el is None else el.find("DataItem")
            if found is None:
                raise ExportError(f"{where}: no DataItem for {what}")
            return _read_item(found, path.parent, where, files)

        def attribute(g: ET.Element | None, name: str) -> np.ndarray | None:
            if g is None:
                return None
            att = g.find(f"Attribute[@Name='{name}']")
            return None if att is None else item(att, f"attribute {name}")

        points = item(cells_grid.find("Geometry"), "the geometry")
        cells = item(cells_grid.find("Topology"), "the polygons").reshape(-1, 5)
        edges = patch = None
        if lines_grid is not None:
            edges = item(lines_grid.find("Topology"), "the boundary lines").reshape(-1, 2)
            patch = attribute(lines_grid, "patch")
        elif meta:
            edges = np.empty((0, 2), dtype=np.int64)
        return mesh_from_arrays(
            points.reshape(-1, points.shape[-1] if points.ndim == 2 else 2),
            cells,
            where=where,
            block_id=attribute(cells_grid, "block_id"),
            parent=attribute(cells_grid, "parent"),
            region=attribute(cells_grid, "region"),
            region_names=meta.get("region_names"),
            boundary_edges=edges,
            boundary_patch=patch,
            patch_names=meta.get("patch_names") or (("boundary",) if edges is not None else None),
            level=meta.get("level", 0),
            name=meta.get("name", ""),
        )
    finally:
        for f in files.values():
            f.close()


FORMAT = Format(
    name="xdmf",
    description="XDMF 3 + HDF5 pair (ParaView), polygons written directly with h5py: fastest",
    extensions=(".xdmf", ".xmf"),
    writer=write_xdmf,
    reader=read_xdmf,
    compressions=("none", "zlib"),
)
