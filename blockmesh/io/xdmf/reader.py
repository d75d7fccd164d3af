"""Reading XDMF 3 + HDF5 pairs back into meshes, every HDF5 dataset checked before it is read.

The layout is described in :mod:`blockmesh.io.xdmf.format`; a pair whose write ids differ is
refused, and so is a dataset with an HDF5 filter blockmesh does not write.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import confined, current_guard, open_regular, parse_xml
from blockmesh.errors import ExportError
from blockmesh.io.common import (
    CURVE_ARRAYS,
    curves_from_arrays,
    decode_metadata,
    mesh_from_arrays,
    split_lines,
)
from blockmesh.io.polygons import is_polygon_file, polygon_mesh_from_arrays
from blockmesh.io.text import parse_numbers
from blockmesh.io.xdmf.hdf5_probe import Probe, probe_hdf5
from blockmesh.io.xdmf.writer import XDMF_POLYGON, XDMF_POLYLINE
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["read_xdmf"]

#: HDF5 filters a dataset may use (blockmesh writes gzip with shuffle); others are refused.
_FILTERS = frozenset({"gzip", "shuffle", "fletcher32"})


class HeavyData:
    """The HDF5 files a light file names, opened once each (and their blockmesh metadata).

    A file must be a regular file in the light file's folder
    (:func:`blockmesh._system.bounded.confined`, one message whatever the reason, so the light
    file cannot probe for files elsewhere). Its structure is first described by a child process
    (:func:`~blockmesh.io.xdmf.hdf5_probe.probe_hdf5`: a damaged file can make the HDF5 library
    loop or crash); a dataset must then be reached by hard links only (no external links,
    external storage or virtual datasets: each could read another file), hold numbers, and store
    what it declares: all of its bytes when uncompressed, every chunk when chunked, with gzip at
    most; its size is checked against the read's memory
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


def _read_item(item: ET.Element, heavy: HeavyData) -> np.ndarray:
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


def _mixed_polygons(
    top: np.ndarray, n_elements: int, where: str, offsets: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Polygons (offsets, nodes) and 2-node lines from a mixed topology, polygons first.

    With the offsets blockmesh writes beside, in whole-array steps; otherwise the records are
    walked one by one (files from elsewhere).
    """
    top = top.ravel()
    if offsets is None:
        sizes: list[int] = []
        at = 0
        while at < top.size and top[at] == XDMF_POLYGON:
            if at + 1 >= top.size:
                raise ExportError(f"{where}: the Mixed topology ends inside a polygon")
            sizes.append(int(top[at + 1]))
            if sizes[-1] < 3:
                raise ExportError(
                    f"{where}: the Mixed topology has a polygon of {sizes[-1]} nodes at entry "
                    f"{at + 1} (a polygon has 3 or more)"
                )
            at += 2 + sizes[-1]
        offsets = np.concatenate([[0], np.cumsum(sizes, dtype=np.int64)])
    offsets = np.asarray(offsets).reshape(-1)
    if (
        offsets.dtype.kind not in "iu"
        or offsets.size < 2
        or offsets[0] != 0
        or np.any(np.diff(offsets) < 3)
        or offsets[-1] > top.size
    ):
        raise ExportError(
            f"{where}: the polygon offsets are not whole numbers rising from 0 by 3 or more "
            f"within the topology's {top.size:,} entries"
        )
    offsets = offsets.astype(np.int64)
    m = offsets.size - 1
    total = int(offsets[-1]) + 2 * m
    eb = n_elements - m
    if m < 1 or eb < 0 or total + 4 * eb != top.size:
        raise ExportError(f"{where}: the Mixed topology is not polygons then 2-node lines")
    starts = offsets[:-1] + 2 * np.arange(m)
    sizes_arr = np.diff(offsets)
    if np.any(top[starts] != XDMF_POLYGON) or np.any(top[starts + 1] != sizes_arr):
        raise ExportError(f"{where}: the Mixed topology's polygons do not match their offsets")
    owner = np.repeat(np.arange(m), sizes_arr)
    nodes = top[np.arange(int(offsets[-1])) + 2 * (owner + 1)]
    line = top[total:].reshape(eb, 4)
    if np.any(line[:, 0] != XDMF_POLYLINE) or np.any(line[:, 1] != 2):
        raise ExportError(f"{where}: the Mixed topology holds lines that are not 2-node lines")
    return offsets, nodes, np.ascontiguousarray(line[:, 2:])


def _mixed(top: np.ndarray, n_elements: int, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Pentagons and boundary edges from a mixed topology: pentagons first, then 2-node lines."""
    top = top.ravel()
    m3 = top.size - 4 * n_elements
    if m3 < 0 or m3 % 3:
        raise ExportError(f"{where}: the Mixed topology is not pentagons then 2-node lines")
    m = m3 // 3
    eb = n_elements - m
    if eb < 0:
        raise ExportError(f"{where}: the Mixed topology is not pentagons then 2-node lines")
    poly = top[: 7 * m].reshape(m, 7)
    line = top[7 * m :].reshape(eb, 4)
    if np.any(poly[:, 0] != XDMF_POLYGON) or np.any(poly[:, 1] != 5):
        raise ExportError(
            f"{where}: the Mixed topology holds cells that are not pentagons (blockmesh reads "
            "pentagons then 2-node boundary lines)"
        )
    if np.any(line[:, 0] != XDMF_POLYLINE) or np.any(line[:, 1] != 2):
        raise ExportError(f"{where}: the Mixed topology holds lines that are not 2-node lines")
    return np.ascontiguousarray(poly[:, 2:]), np.ascontiguousarray(line[:, 2:])


def _pentagons(top: np.ndarray, n_elements: int, where: str) -> tuple | None:
    """``_mixed``'s pentagons and lines, or None when the cells are polygons of other sizes."""
    try:
        return _mixed(top, n_elements, where)
    except ExportError:
        top = top.ravel()
        if top.size >= 2 and top[0] == XDMF_POLYGON:
            return None  # polygons, not all of five nodes: read as a PolygonMesh
        raise


def read_xdmf(path: Path) -> Mesh | PolygonMesh:
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
    heavy = HeavyData(path.parent, where, meta.get("write_id"))
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
        edges = patch = interface = None
        block_id, parent, region = (
            attribute(cells_grid, a) for a in ("block_id", "parent", "region")
        )
        mixed = top_el.get("TopologyType", top_el.get("Type", "")).lower() == "mixed"
        number = top_el.get("NumberOfElements", "")
        if mixed and not number.strip().isdigit():
            raise ExportError(
                f"{where}: the Mixed topology has NumberOfElements={number!r:.40}, not a whole "
                "number"
            )
        n_elements = int(number) if mixed else -1
        topology = item(top_el, "the topology") if mixed else np.empty(0, np.int64)
        pentagons = None
        if mixed and not is_polygon_file(meta):
            pentagons = _pentagons(topology, n_elements, where)
        if mixed and pentagons is None:
            stored = meta.get("data")
            offsets = (
                heavy.dataset(f"{stored}:/mesh/offsets")
                if is_polygon_file(meta) and stored
                else None
            )
            offsets, nodes, edges = _mixed_polygons(topology, n_elements, where, offsets)
            m = offsets.size - 1
            columns = {
                name: None if a is None else a[:m].copy()
                for name, a in (
                    ("block_id", block_id),
                    ("parent", parent),
                    ("region", region),
                    ("cell_level", attribute(cells_grid, "cell_level")),
                )
            }
            patch = attribute(cells_grid, "patch")
            interface = attribute(cells_grid, "interface")
            return polygon_mesh_from_arrays(
                _rows(points, points.shape[-1] if points.ndim == 2 else 2, "the points", where),
                offsets,
                nodes,
                where=where,
                region_names=meta.get("region_names"),
                **split_lines(
                    edges,
                    None if patch is None else patch[m:].copy(),
                    None if interface is None else interface[m:].copy(),
                ),
                patch_names=meta.get("patch_names") or ("boundary",),
                interface_names=meta.get("interface_names"),
                level=meta.get("level", 0),
                name=meta.get("name", ""),
                **columns,
            )
        if pentagons is not None:
            cells, edges = pentagons
            m = cells.shape[0]
            block_id, parent, region = (
                None if a is None else a[:m].copy() for a in (block_id, parent, region)
            )
            patch = attribute(cells_grid, "patch")
            patch = None if patch is None else patch[m:].copy()
            interface = attribute(cells_grid, "interface")
            interface = None if interface is None else interface[m:].copy()
        else:
            cells = _rows(item(top_el, "the polygons"), 5, "the polygons", where)
            if lines_grid is not None:
                edges = _rows(
                    item(lines_grid.find("Topology"), "the boundary lines"), 2, "the lines", where
                )
                patch = attribute(lines_grid, "patch")
            elif meta:
                edges = np.empty((0, 2), dtype=np.int64)
        curves = None
        if meta.get("curved_edges"):
            data = top_el.find("DataItem")
            h5name = "" if data is None else (data.text or "").strip().partition(":")[0]
            curves = curves_from_arrays(
                {k: heavy.dataset(f"{h5name}:/curves/{k}") for k in CURVE_ARRAYS}, where
            )
        return mesh_from_arrays(
            _rows(points, points.shape[-1] if points.ndim == 2 else 2, "the points", where),
            cells,
            where=where,
            block_id=block_id,
            parent=parent,
            region=region,
            region_names=meta.get("region_names"),
            **split_lines(edges, patch, interface),
            patch_names=meta.get("patch_names") or (("boundary",) if edges is not None else None),
            interface_names=meta.get("interface_names"),
            level=meta.get("level", 0),
            name=meta.get("name", ""),
            curves=curves,
        )
    finally:
        heavy.close()
