"""Writing XDMF 3 + HDF5 pairs: the heavy arrays with h5py, the light XML with xml.etree.

The layout is described in :mod:`blockmesh.io.xdmf.format`; the pair is committed atomically
(:func:`blockmesh._system.atomic.atomic_with_data`).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import re
import secrets
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.atomic import atomic_with_data
from blockmesh.errors import ExportError
from blockmesh.io.common import (
    curve_arrays,
    encode_metadata,
    line_arrays,
    name_lookup,
)
from blockmesh.io.polygons import POLYGONS
from blockmesh.io.xdmf.hdf5_probe import probe_hdf5
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["XDMF_POLYGON", "XDMF_POLYLINE", "write_xdmf"]

_CELL_DATA = ("block_id", "region", "parent", "patch")
#: XDMF's mixed-topology codes: a polygon (then its node count and nodes), a polyline.
XDMF_POLYGON, XDMF_POLYLINE = 3, 2


def _data_item(parent: ET.Element, source: str, shape: tuple[int, ...], kind: str) -> None:
    item = ET.SubElement(
        parent,
        "DataItem",
        Dimensions=" ".join(str(s) for s in shape),
        NumberType=kind,
        Precision="8",
        Format="HDF",
    )
    item.text = source


def _xdmf_tree(
    mesh: Mesh | PolygonMesh, h5name: str, meta: str, topology_size: int | None = None
) -> ET.ElementTree:
    m, eb = mesh.n_cells, mesh.boundary_edges.shape[0] + mesh.interface_edges.shape[0]
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    grid = ET.SubElement(domain, "Grid", Name=mesh.name or "mesh", GridType="Uniform")
    top = ET.SubElement(grid, "Topology", TopologyType="Mixed", NumberOfElements=str(m + eb))
    size = 7 * m + 4 * eb if topology_size is None else topology_size
    _data_item(top, f"{h5name}:/mesh/topology", (size,), "Int")
    geo = ET.SubElement(grid, "Geometry", GeometryType="XY")
    _data_item(geo, f"{h5name}:/mesh/points", mesh.points.shape, "Float")
    names = _CELL_DATA + (("interface",) if mesh.interface_names else ())
    names += ("cell_level",) if isinstance(mesh, PolygonMesh) else ()
    for name in names:
        att = ET.SubElement(grid, "Attribute", Name=name, AttributeType="Scalar", Center="Cell")
        _data_item(att, f"{h5name}:/mesh/{name}", (m + eb,), "Int")
    kinds = (
        ("patch", mesh.patch_names),
        ("region", mesh.region_names),
        ("interface", mesh.interface_names),
    )
    for kind, names in kinds:
        for label, index in name_lookup(kind, names).items():
            att = ET.SubElement(
                grid, "Attribute", Name=label, AttributeType="Scalar", Center="Grid"
            )
            item = ET.SubElement(
                att, "DataItem", Dimensions="1", NumberType="Int", Precision="8", Format="XML"
            )
            item.text = str(index)
    ET.SubElement(grid, "Information", Name="blockmesh", Value=meta)
    ET.indent(root)
    return ET.ElementTree(root)


def _padded(on_cells: np.ndarray, m: int, eb: int, *, lines: bool = False) -> np.ndarray:
    out = np.full(m + eb, -1, dtype=np.int64)
    if lines:
        out[m:] = on_cells
    else:
        out[:m] = on_cells
    return out


def _owned(light: str) -> Callable[[Path], bool]:
    """Whether an ``.h5`` file is the data file of an earlier write of the light file ``light``.

    Its attribute is read by a child process (:func:`~blockmesh.io.xdmf.hdf5_probe.probe_hdf5`): a
    damaged file found in the folder cannot stall the write.
    """

    def owned(path: Path) -> bool:
        try:
            raw = probe_hdf5(path, str(path)).attribute
        except ExportError:  # not an HDF5 file, or a damaged one: not ours to remove
            return False
        if raw is None:
            return False
        try:
            meta = json.loads(raw)
        except (TypeError, ValueError):
            return False
        return isinstance(meta, dict) and meta.get("light", light) == light

    return owned


@contextlib.contextmanager
def _hdf5_errors() -> Iterator[None]:
    """HDF5's failures (h5py raises OSError or RuntimeError) as an OSError with their errno."""
    try:
        yield
    except (OSError, RuntimeError) as error:
        found = re.search(r"errno = (\d+)", str(error))
        code = int(found[1]) if found else (getattr(error, "errno", None) or errno.EIO)
        raise OSError(code, os.strerror(code)) from error


def _dataset_options(compression: str) -> dict[str, Any]:
    """h5py's dataset options for ``compression`` (gzip level 4, shuffled, for ``"zlib"``)."""
    if compression == "zlib":
        return {"compression": "gzip", "compression_opts": 4, "shuffle": True}
    return {}


def _write_light(path: Path, tree: ET.ElementTree) -> None:
    """The light XML file: declaration, doctype and the tree."""
    with open(path, "wb") as f:
        f.write(b'<?xml version="1.0" encoding="utf-8"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n')
        tree.write(f, encoding="utf-8", xml_declaration=False)
        f.write(b"\n")


def write_xdmf(mesh: Mesh | PolygonMesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (``.xdmf``) and its ``.h5``; returns the ``.xdmf`` path.

    O(N + M), bounded by disk speed without compression. A PolygonMesh's cells go in the same
    ``Mixed`` topology, ``3 n v0 .. v(n-1)`` each, with ``/mesh/offsets`` (its compressed rows'
    offsets) and ``/mesh/cell_level`` beside.
    """
    import h5py

    path = Path(path).absolute()
    if path.suffix.lower() == ".h5":
        raise ExportError(f"cannot write {path}: the XDMF file needs a name not ending in .h5")
    if isinstance(mesh, PolygonMesh):
        return _write_polygons(mesh, path, compression)
    m = mesh.n_cells
    edges, patch, interface = line_arrays(mesh)
    eb = edges.shape[0]
    options = _dataset_options(compression)
    write_id = secrets.token_hex(8)
    with atomic_with_data(path, ".h5", owned=_owned(path.name)) as (tmp_xdmf, tmp_h5, h5):
        meta = encode_metadata(mesh, light=path.name, data=h5.name, write_id=write_id, n_cells=m)
        with _hdf5_errors(), h5py.File(tmp_h5, "w") as f:
            f.attrs["blockmesh"] = meta
            g = f.create_group("mesh")
            g.create_dataset("points", data=mesh.points, **options)
            top = g.create_dataset("topology", shape=(7 * m + 4 * eb,), dtype=np.int64, **options)
            poly = np.empty((m, 7), dtype=np.int64)
            poly[:, 0], poly[:, 1], poly[:, 2:] = XDMF_POLYGON, 5, mesh.cells
            top[: 7 * m] = poly.ravel()
            del poly
            if eb:
                line = np.empty((eb, 4), dtype=np.int64)
                line[:, 0], line[:, 1], line[:, 2:] = XDMF_POLYLINE, 2, edges
                top[7 * m :] = line.ravel()
            for name in ("block_id", "region", "parent"):
                g.create_dataset(name, data=_padded(getattr(mesh, name), m, eb), **options)
            g.create_dataset("patch", data=_padded(patch, m, eb, lines=True), **options)
            if mesh.interface_names:
                g.create_dataset("interface", data=_padded(interface, m, eb, lines=True), **options)
            curves = curve_arrays(mesh)
            if curves:
                c = f.create_group("curves")
                for name, values in curves.items():
                    c.create_dataset(name, data=values)
        tree = _xdmf_tree(mesh, h5.name, meta)
        _write_light(tmp_xdmf, tree)
    return path


def _polygon_topology(mesh: PolygonMesh, edges: np.ndarray) -> np.ndarray:
    """The Mixed topology of a PolygonMesh: ``3 n v..`` per cell, then ``2 2 a b`` per edge."""
    m, eb = mesh.n_cells, edges.shape[0]
    sizes = mesh.cell_sizes()
    starts = mesh.offsets[:-1] + 2 * np.arange(m)  # each record 2 + n long
    total = int(mesh.nodes.size) + 2 * m
    top = np.empty(total + 4 * eb, dtype=np.int64)
    top[starts] = XDMF_POLYGON
    top[starts + 1] = sizes
    owner = mesh.polygon_cells().slot_cell()
    top[np.arange(mesh.nodes.size) + 2 * (owner + 1)] = mesh.nodes
    if eb:
        line = np.empty((eb, 4), dtype=np.int64)
        line[:, 0], line[:, 1], line[:, 2:] = XDMF_POLYLINE, 2, edges
        top[total:] = line.ravel()
    return top


def _write_polygons(mesh: PolygonMesh, path: Path, compression: str) -> Path:
    import h5py

    m = mesh.n_cells
    edges, patch, interface = line_arrays(mesh)
    eb = edges.shape[0]
    options = _dataset_options(compression)
    write_id = secrets.token_hex(8)
    top = _polygon_topology(mesh, edges)
    with atomic_with_data(path, ".h5", owned=_owned(path.name)) as (tmp_xdmf, tmp_h5, h5):
        meta = encode_metadata(
            mesh, light=path.name, data=h5.name, write_id=write_id, n_cells=m, cells=POLYGONS
        )
        with _hdf5_errors(), h5py.File(tmp_h5, "w") as f:
            f.attrs["blockmesh"] = meta
            g = f.create_group("mesh")
            g.create_dataset("points", data=mesh.points, **options)
            g.create_dataset("topology", data=top, **options)
            g.create_dataset("offsets", data=mesh.offsets, **options)
            for name in ("block_id", "region", "parent", "cell_level"):
                g.create_dataset(name, data=_padded(getattr(mesh, name), m, eb), **options)
            g.create_dataset("patch", data=_padded(patch, m, eb, lines=True), **options)
            if mesh.interface_names:
                g.create_dataset("interface", data=_padded(interface, m, eb, lines=True), **options)
        tree = _xdmf_tree(mesh, h5.name, meta, topology_size=top.size)
        _write_light(tmp_xdmf, tree)
    return path
