"""XDMF 3 + HDF5 (``.xdmf`` naming a sibling ``.h5``): the fast path for big meshes (ParaView).

meshio cannot write polygons to XDMF, so the heavy data goes straight to HDF5 with h5py and the
light XML is written with :mod:`xml.etree`. The XDMF file holds one uniform grid, like the VTU:
a ``Mixed`` topology of the pentagons (``Polygon`` of 5 nodes) followed by the boundary edges
(``Polyline`` of 2), ``Geometry XY``, the cell attributes ``block_id``, ``region``, ``parent`` and
``patch`` (-1 where they do not apply), the name lookups ``patch:NAME`` and ``region:NAME`` as
grid attributes (ParaView shows them as field data: the index each name has), and an
``Information`` element ``blockmesh`` with the JSON metadata. The ``.h5`` file holds

============================ ============== ===============================================
``/mesh/points``             (N, 2) f8      node coordinates
``/mesh/topology``           (7M + 4Eb,) i8 per pentagon ``3 5 v0 .. v4``, per boundary edge
                                            ``2 2 a b`` (XDMF's mixed layout)
``/mesh/block_id``, ``/mesh/region``, ``/mesh/parent``, ``/mesh/patch``
                             (M + Eb,) i8   cell data, -1 where it does not apply
============================ ============== ===============================================

and the root attribute ``blockmesh`` (the same JSON). The cells, in h5py:
``f["mesh/topology"][: 7 * M].reshape(M, 7)[:, 2:]``.

Files, atomically. The ``.h5`` of ``mesh.xdmf`` is ``mesh.<8 hex digits>.h5``, a new name at
every write; it is renamed in first and the ``.xdmf`` last, so a reader sees the old pair or the
new one, never a mix; the ``.h5`` of the previous write is then removed
(:func:`blockmesh.atomic.atomic_with_data`). Both files carry the same write id, and
:func:`read_xdmf` refuses a pair whose ids differ.

ParaView. Open the ``.xdmf`` with a path that names its folder (``./mesh.xdmf``, or any path
from File > Open): ParaView's XDMF 3 reader mislocates the ``.h5`` of a bare relative file name
(``OpenDataFile("mesh.xdmf")`` aborts).

meshio cannot read this file (nor any XDMF of polygons: its XDMF reader has no polygon cells);
read it with :func:`blockmesh.read`, or write a ``.vtu`` for meshio.

Compression: ``"none"`` (default, fastest) or ``"zlib"`` (HDF5 gzip level 4, chunked datasets).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_xdmf(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.xdmf")
>>> [p.suffix for p in sorted(path.parent.iterdir())]
['.h5', '.xdmf']
>>> back = read_xdmf(path)
>>> bool(np.array_equal(back.points, mesh.points)), back.n_cells
(True, 36)
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

from ..atomic import atomic_with_data
from ..bounded import confined, current_guard, open_regular, parse_xml
from ..errors import ExportError
from ..mesh import Mesh
from ._common import Format, decode_metadata, encode_metadata, mesh_from_arrays, name_lookup
from .hdf5_probe import Probe, probe_hdf5
from .text import parse_numbers

__all__ = ["FORMAT", "read_xdmf", "write_xdmf"]

_CELL_DATA = ("block_id", "region", "parent", "patch")
_POLYGON, _POLYLINE = 3, 2


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


def _xdmf_tree(mesh: Mesh, h5name: str, meta: str) -> ET.ElementTree:
    m, eb = mesh.n_cells, mesh.boundary_edges.shape[0]
    root = ET.Element("Xdmf", Version="3.0")
    domain = ET.SubElement(root, "Domain")
    grid = ET.SubElement(domain, "Grid", Name=mesh.name or "mesh", GridType="Uniform")
    top = ET.SubElement(grid, "Topology", TopologyType="Mixed", NumberOfElements=str(m + eb))
    _data_item(top, f"{h5name}:/mesh/topology", (7 * m + 4 * eb,), "Int")
    geo = ET.SubElement(grid, "Geometry", GeometryType="XY")
    _data_item(geo, f"{h5name}:/mesh/points", mesh.points.shape, "Float")
    for name in _CELL_DATA:
        att = ET.SubElement(grid, "Attribute", Name=name, AttributeType="Scalar", Center="Cell")
        _data_item(att, f"{h5name}:/mesh/{name}", (m + eb,), "Int")
    for kind, names in (("patch", mesh.patch_names), ("region", mesh.region_names)):
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

    Its attribute is read by a child process (:func:`~blockmesh.io.hdf5_probe.probe_hdf5`): a
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


def write_xdmf(mesh: Mesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (``.xdmf``) and its ``.h5``; returns the ``.xdmf`` path.

    O(N + M), bounded by disk speed without compression.
    """
    import h5py

    path = Path(path).absolute()
    if path.suffix.lower() == ".h5":
        raise ExportError(f"cannot write {path}: the XDMF file needs a name not ending in .h5")
    m, eb = mesh.n_cells, mesh.boundary_edges.shape[0]
    options: dict[str, Any] = (
        {"compression": "gzip", "compression_opts": 4, "shuffle": True}
        if compression == "zlib"
        else {}
    )
    write_id = secrets.token_hex(8)
    with atomic_with_data(path, ".h5", owned=_owned(path.name)) as (tmp_xdmf, tmp_h5, h5):
        meta = encode_metadata(mesh, light=path.name, data=h5.name, write_id=write_id, n_cells=m)
        with _hdf5_errors(), h5py.File(tmp_h5, "w") as f:
            f.attrs["blockmesh"] = meta
            g = f.create_group("mesh")
            g.create_dataset("points", data=mesh.points, **options)
            top = g.create_dataset("topology", shape=(7 * m + 4 * eb,), dtype=np.int64, **options)
            poly = np.empty((m, 7), dtype=np.int64)
            poly[:, 0], poly[:, 1], poly[:, 2:] = _POLYGON, 5, mesh.cells
            top[: 7 * m] = poly.ravel()
            del poly
            if eb:
                line = np.empty((eb, 4), dtype=np.int64)
                line[:, 0], line[:, 1], line[:, 2:] = _POLYLINE, 2, mesh.boundary_edges
                top[7 * m :] = line.ravel()
            for name in ("block_id", "region", "parent"):
                g.create_dataset(name, data=_padded(getattr(mesh, name), m, eb), **options)
            g.create_dataset(
                "patch", data=_padded(mesh.boundary_patch, m, eb, lines=True), **options
            )
        tree = _xdmf_tree(mesh, h5.name, meta)
        with open(tmp_xdmf, "wb") as f:
            f.write(
                b'<?xml version="1.0" encoding="utf-8"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n'
            )
            tree.write(f, encoding="utf-8", xml_declaration=False)
            f.write(b"\n")
    return path


# ----------------------------------------------------------------------------------- reading
#: HDF5 filters a dataset may use (blockmesh writes gzip with shuffle); others are refused.
_FILTERS = frozenset({"gzip", "shuffle", "fletcher32"})


class _Heavy:
    """The HDF5 files a light file names, opened once each (and their blockmesh metadata).

    A file must be a regular file in the light file's folder (:func:`blockmesh.bounded.confined`,
    one message whatever the reason, so the light file cannot probe for files elsewhere). Its
    structure is first described by a child process (:func:`~blockmesh.io.hdf5_probe.probe_hdf5`:
    a damaged file can make the HDF5 library loop or crash); a dataset must then be reached by
    hard links only (no external links, external storage or virtual datasets: each could read
    another file), hold numbers, and store what it declares: all of its bytes when uncompressed,
    every chunk when chunked, with gzip at most; its size is checked against the read's memory
    limit before it is read, in this process.
    """

    def __init__(self, base: Path, where: str, write_id: str | None) -> None:
        self.base, self.where, self.write_id = base, where, write_id
        self.files: dict[Path, Any] = {}
        self.probes: dict[Path, Probe] = {}

    def dataset(self, source: str) -> np.ndarray:
        import h5py

        name, _, dataset = source.strip().partition(":")
        file = confined(self.base, name, self.where, "HDF5 file")
        if file not in self.files:
            self.probes[file] = probe_hdf5(file, self.where)
            self._check_pair(file)
            try:
                self.files[file] = h5py.File(file, "r")
            except Exception as exc:  # h5py raises OSError and others for a damaged file
                raise ExportError(f"cannot read {file} as HDF5: {_short(exc)}") from None
            current_guard(self.where).opened(file.stat().st_size)
        key = "/".join(p for p in dataset.split("/") if p)
        self._check_dataset(self.probes[file].datasets.get(key), key, file)
        try:
            return self.files[file][key][()]
        except Exception as exc:  # h5py raises many kinds for a damaged file
            raise ExportError(f"cannot read /{key} from {file}: {_short(exc)}") from None

    def _check_dataset(self, info: dict[str, Any] | None, key: str, file: Path) -> None:
        what = f"{self.where}: the dataset /{key} of {file.name}"
        if not key or info is None:
            raise ExportError(f"{self.where}: {file.name} has no dataset /{key}")
        if info.get("link") != "HardLink":
            raise ExportError(
                f"{what} is reached by a {info.get('link')} (blockmesh follows no links out of a "
                "data file, and reads datasets only)"
            )
        if info["kind"] not in "iuf" or info["itemsize"] > 8:
            raise ExportError(f"{what} holds {info['dtype']} values, not numbers")
        if info["virtual"] or info["external"]:
            raise ExportError(f"{what} keeps its data in other files (blockmesh reads none)")
        unknown = sorted(set(info["filters"]) - _FILTERS)
        if unknown:
            raise ExportError(f"{what} uses the filter {unknown[0]} (blockmesh reads gzip)")
        if not info["readable"]:
            raise ExportError(f"{what} cannot be read (the HDF5 library fails on it)")
        size = 1
        for extent in info["shape"]:
            size *= extent
        nbytes = size * info["itemsize"]
        stored = info["stored"]
        guard = current_guard(self.where)
        if info["chunks"] is None:
            if stored != nbytes:
                raise ExportError(
                    f"{what} declares {nbytes:,} bytes but stores {stored:,} (damaged, or made to "
                    "expand)"
                )
        else:
            chunks = 1
            for extent, chunk in zip(info["shape"], info["chunks"], strict=True):
                chunks *= -(-extent // max(chunk, 1))
            if info["chunks_stored"] != chunks:
                raise ExportError(
                    f"{what} declares {chunks:,} chunks but stores {info['chunks_stored']:,} "
                    "(damaged, or made to expand)"
                )
            if not info["filters"] and stored < nbytes:
                raise ExportError(f"{what} declares {nbytes:,} bytes but stores {stored:,}")
            if info["filters"]:
                guard.expanded(nbytes, what.split(": ", 1)[1])
        guard.allocate(nbytes, f"the dataset /{key}")

    def _check_pair(self, file: Path) -> None:
        """ExportError if ``file`` was written by another write than the light file."""
        if self.write_id is None:
            return
        raw = self.probes[file].attribute
        got = decode_metadata(raw, str(file)).get("write_id") if raw is not None else None
        if got != self.write_id:
            raise ExportError(
                f"{self.where} and {file.name} do not belong together: they come from different "
                f"writes (write ids {self.write_id} and {got}); write the mesh again"
            )

    def metadata(self, file: Path) -> str | None:
        """The ``blockmesh`` attribute of ``file`` (probed already by :meth:`dataset`)."""
        return self.probes[file].attribute

    def close(self) -> None:
        for f in self.files.values():
            f.close()


def _short(error: BaseException) -> str:
    """An exception's message on one line, at most 300 characters."""
    text = " ".join(str(error).split())
    return text if len(text) <= 300 else text[:297] + "..."


def _read_item(item: ET.Element, heavy: _Heavy) -> np.ndarray:
    fmt = item.get("Format", "XML")
    text = (item.text or "").strip()
    try:
        dims = tuple(int(s) for s in item.get("Dimensions", "").split())
    except ValueError:
        raise ExportError(
            f"{heavy.where}: a DataItem has Dimensions={item.get('Dimensions')!r:.60}, not whole "
            "numbers"
        ) from None
    if fmt == "XML":
        kind = np.float64 if item.get("NumberType", "Float") == "Float" else np.int64
        arr = parse_numbers(text.encode(), kind, f"{heavy.where}: a DataItem")
    elif fmt == "HDF":
        arr = heavy.dataset(text)
    else:
        raise ExportError(f"{heavy.where}: DataItem Format={fmt!r} is not supported (HDF or XML)")
    return arr.reshape(dims) if dims and int(np.prod(dims)) == arr.size else arr


def _rows(values: np.ndarray, width: int, what: str, where: str) -> np.ndarray:
    """``values`` as rows of ``width``; ExportError when their number does not divide."""
    if width < 1 or values.size % width:
        raise ExportError(f"{where}: {what} hold {values.size:,} numbers, not rows of {width}")
    return values.reshape(-1, width)


def _mixed(top: np.ndarray, n_elements: int, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Pentagons and boundary edges from a mixed topology: pentagons first, then 2-node lines."""
    top = top.ravel()
    m3 = top.size - 4 * n_elements
    if m3 < 0 or m3 % 3:
        raise ExportError(f"{where}: the Mixed topology is not pentagons then 2-node lines")
    m = m3 // 3
    eb = n_elements - m
    poly = top[: 7 * m].reshape(m, 7)
    line = top[7 * m :].reshape(eb, 4)
    if np.any(poly[:, 0] != _POLYGON) or np.any(poly[:, 1] != 5):
        raise ExportError(
            f"{where}: the Mixed topology holds cells that are not pentagons (blockmesh reads "
            "pentagons then 2-node boundary lines)"
        )
    if np.any(line[:, 0] != _POLYLINE) or np.any(line[:, 1] != 2):
        raise ExportError(f"{where}: the Mixed topology holds lines that are not 2-node lines")
    return np.ascontiguousarray(poly[:, 2:]), np.ascontiguousarray(line[:, 2:])


def read_xdmf(path: Path) -> Mesh:
    """Read a mesh written by :func:`write_xdmf` (h5py + xml.etree).

    Also reads the earlier layout (a collection of a ``Polygon`` grid and a ``Polyline`` grid)
    and other XDMF files with one ``Polygon`` topology of 5 nodes per element, with defaults for
    what they lack.
    """
    path = Path(path).absolute()
    where = str(path)
    guard = current_guard(where)
    with open_regular(path) as handle:
        size = os.fstat(handle.fileno()).st_size
        guard.allocate(8 * size, "the XML tree")  # expat's tree: a few times the text
        data = handle.read()
    root = parse_xml(data, where)
    del data
    info = root.find(".//Information[@Name='blockmesh']")
    meta = decode_metadata(info.get("Value") if info is not None else None, where)
    cells_grid = lines_grid = None
    for g in root.iter("Grid"):
        top = g.find("Topology")
        if top is None:
            continue
        kind = top.get("TopologyType", top.get("Type", "")).lower()
        if kind in ("polygon", "mixed") and cells_grid is None:
            if kind == "polygon" and top.get("NodesPerElement") != "5":
                raise ExportError(
                    f"{where}: the polygons have {top.get('NodesPerElement')} nodes; "
                    "blockmesh reads pentagons"
                )
            cells_grid = g
        elif kind == "polyline" and lines_grid is None:
            lines_grid = g
    if cells_grid is None:
        raise ExportError(f'{where} has no Grid with a "Mixed" or "Polygon" (5 nodes) topology')
    heavy = _Heavy(path.parent, where, meta.get("write_id"))
    try:

        def item(el: ET.Element | None, what: str) -> np.ndarray:
            found = None if el is None else el.find("DataItem")
            if found is None:
                raise ExportError(f"{where}: no DataItem for {what}")
            return _read_item(found, heavy)

        def attribute(g: ET.Element | None, name: str) -> np.ndarray | None:
            if g is None:
                return None
            att = g.find(f"Attribute[@Name='{name}']")
            return None if att is None else item(att, f"attribute {name}")

        points = item(cells_grid.find("Geometry"), "the geometry")
        top_el = cells_grid.find("Topology")
        assert top_el is not None
        edges = patch = None
        block_id, parent, region = (
            attribute(cells_grid, a) for a in ("block_id", "parent", "region")
        )
        if top_el.get("TopologyType", top_el.get("Type", "")).lower() == "mixed":
            number = top_el.get("NumberOfElements", "")
            if not number.strip().isdigit():
                raise ExportError(
                    f"{where}: the Mixed topology has NumberOfElements={number!r:.40}, not a whole "
                    "number"
                )
            cells, edges = _mixed(item(top_el, "the topology"), int(number), where)
            m = cells.shape[0]
            block_id, parent, region = (
                None if a is None else a[:m].copy() for a in (block_id, parent, region)
            )
            patch = attribute(cells_grid, "patch")
            patch = None if patch is None else patch[m:].copy()
        else:
            cells = _rows(item(top_el, "the polygons"), 5, "the polygons", where)
            if lines_grid is not None:
                edges = _rows(
                    item(lines_grid.find("Topology"), "the boundary lines"), 2, "the lines", where
                )
                patch = attribute(lines_grid, "patch")
            elif meta:
                edges = np.empty((0, 2), dtype=np.int64)
        return mesh_from_arrays(
            _rows(points, points.shape[-1] if points.ndim == 2 else 2, "the points", where),
            cells,
            where=where,
            block_id=block_id,
            parent=parent,
            region=region,
            region_names=meta.get("region_names"),
            boundary_edges=edges,
            boundary_patch=patch,
            patch_names=meta.get("patch_names") or (("boundary",) if edges is not None else None),
            level=meta.get("level", 0),
            name=meta.get("name", ""),
        )
    finally:
        heavy.close()


FORMAT = Format(
    name="xdmf",
    description="XDMF 3 + HDF5 pair (ParaView), polygons written directly with h5py: fastest",
    extensions=(".xdmf", ".xmf"),
    writer=write_xdmf,
    reader=read_xdmf,
    compressions=("none", "zlib"),
)
