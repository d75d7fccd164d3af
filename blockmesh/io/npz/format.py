"""NumPy ``.npz``: every array of a :class:`~blockmesh.mesh.Mesh` plus its names, lossless.

The archive holds ``points, cells, block_id, parent, boundary_edges, boundary_patch, region`` as
they are, ``patch_names`` and ``region_names`` as unicode arrays, ``level``, ``name`` and
``format_version``, for a composite domain ``interface_edges``, ``interface_patch`` and
``interface_names``, and for a mesh with curved edges the arrays of
:data:`~blockmesh.io.common.CURVE_ARRAYS` (so that refining the mesh read back follows the
curves); nothing needs pickling (it is read with ``allow_pickle=False``).
``compression="zlib"`` uses :func:`numpy.savez_compressed`; the default ``"none"`` is
:func:`numpy.savez` (fastest).

A :class:`~blockmesh.mesh.polygons.PolygonMesh` is written with ``cell_offsets`` and
``cell_nodes`` (its compressed rows) and ``cell_level`` instead of ``cells``, and ``kind`` =
``"polygons"``; it is read back as one, every array equal.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_npz(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.npz")
>>> back = read_npz(path)
>>> bool(np.array_equal(back.cells, mesh.cells)), back.level
(True, 2)
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.atomic import atomic_file
from blockmesh._system.bounded import current_guard, open_regular, reading
from blockmesh.errors import ExportError, ResourceError
from blockmesh.io.common import (
    CURVE_ARRAYS,
    Format,
    curve_arrays,
    curves_from_arrays,
    mesh_from_arrays,
)
from blockmesh.io.polygons import POLYGONS, polygon_mesh_from_arrays
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["FORMAT", "read_npz", "write_npz"]

_ARRAYS = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch", "region")
_POLYGON_ARRAYS = ("cell_offsets", "cell_nodes", "cell_level")
_VERSION = 1


def write_npz(mesh: Mesh | PolygonMesh, path: Path, *, compression: str = "none") -> Path:
    """Write ``mesh`` to ``path`` (atomically); returns the path. O(N + M)."""
    if isinstance(mesh, PolygonMesh):
        arrays = {key: getattr(mesh, key) for key in _ARRAYS if key != "cells"}
        arrays["cell_offsets"] = mesh.offsets
        arrays["cell_nodes"] = mesh.nodes
        arrays["cell_level"] = mesh.cell_level
        arrays["kind"] = np.array(POLYGONS, dtype=str)
    else:
        arrays = {key: getattr(mesh, key) for key in _ARRAYS}
    arrays["patch_names"] = np.array(mesh.patch_names, dtype=str)
    arrays["region_names"] = np.array(mesh.region_names, dtype=str)
    arrays["level"] = np.array(mesh.level, dtype=np.int64)
    arrays["name"] = np.array(mesh.name, dtype=str)
    arrays["format_version"] = np.array(_VERSION, dtype=np.int64)
    if mesh.interface_names:
        arrays["interface_edges"] = mesh.interface_edges
        arrays["interface_patch"] = mesh.interface_patch
        arrays["interface_names"] = np.array(mesh.interface_names, dtype=str)
    arrays.update(curve_arrays(mesh))
    save = np.savez_compressed if compression == "zlib" else np.savez
    with atomic_file(path) as tmp, open(tmp, "wb") as f:
        save(f, **arrays)
    return Path(path).absolute()


def _members(archive: Any, wanted: tuple[str, ...], where: str, size: int) -> dict[str, int]:
    """Each wanted member's array size in bytes, from its ``.npy`` header; nothing else is read.

    ExportError for a member whose header is not an array of numbers or text, whose declared
    size in the archive does not match its header, or whose data expands past what the file
    may; ResourceError when the arrays together exceed the read's memory limit.
    """
    import zipfile

    guard = current_guard(where)
    out: dict[str, int] = {}
    for key in wanted:
        try:
            info = archive.getinfo(f"{key}.npy")
        except KeyError:
            continue
        what = f"the array {key!r}"
        try:
            with archive.open(info) as member:
                version = np.lib.format.read_magic(member)
                if version == (1, 0):
                    shape, _, dtype = np.lib.format.read_array_header_1_0(member)
                elif version == (2, 0):
                    shape, _, dtype = np.lib.format.read_array_header_2_0(member)
                else:
                    raise ValueError(f".npy format version {version}")
                header = member.tell() if member.seekable() else None
        except Exception as exc:  # zipfile and numpy raise many kinds for a damaged header
            raise ExportError(f"{where}: {what} has no readable .npy header ({exc})") from None
        if dtype.kind not in "biufU" or dtype.hasobject:
            raise ExportError(f"{where}: {what} holds {dtype} values (blockmesh writes numbers)")
        count = 1
        for extent in shape:
            count *= int(extent)
        nbytes = count * dtype.itemsize
        if header is not None and info.file_size != header + nbytes:
            raise ExportError(
                f"{where}: {what} declares {nbytes:,} bytes in its header but the archive lists "
                f"{info.file_size - header:,} (damaged)"
            )
        if info.compress_type == zipfile.ZIP_STORED:
            guard.stored(info.file_size, size, what)
        else:
            guard.expanded(info.file_size, what)
        guard.allocate(nbytes, what)
        out[key] = nbytes
    return out


def read_npz(path: Path) -> Mesh | PolygonMesh:
    """Read a mesh written by :func:`write_npz` (a PolygonMesh when it holds one).

    Every array's ``.npy`` header is read first: its size is checked against the archive's
    listing, the file (or what compressed data may expand to) and the read's memory limit before
    any array is loaded; only the arrays of a mesh are loaded, never pickles.
    """
    import zipfile

    where = str(path)
    keys = (
        *_ARRAYS, *_POLYGON_ARRAYS, "patch_names", "region_names", "level", "name",
        "format_version", "kind", "interface_edges", "interface_patch", "interface_names",
        *CURVE_ARRAYS,
    )  # fmt: skip
    with reading(where), open_regular(path) as handle:
        size = os.fstat(handle.fileno()).st_size
        try:
            with zipfile.ZipFile(handle) as archive:
                present = _members(archive, keys, where, size)
                polygons = "cell_offsets" in present
                needed = [k for k in _ARRAYS if k != "cells"] if polygons else list(_ARRAYS)
                if polygons:
                    needed += ["cell_nodes"]
                missing = [k for k in (*needed, "patch_names", "region_names") if k not in present]
                if missing:
                    raise ExportError(
                        f"{where} is not a blockmesh .npz: it lacks {', '.join(missing)} "
                        "(write it with blockmesh.io.write)"
                    )
                arrays = {}
                for key in present:
                    with archive.open(f"{key}.npy") as member:
                        arrays[key] = np.lib.format.read_array(member, allow_pickle=False)
        except (ExportError, ResourceError):
            raise
        except Exception as exc:  # zipfile and numpy raise many kinds for damaged archives
            raise ExportError(f"cannot read {where} as .npz: {exc}") from None
    common: dict[str, Any] = {
        "where": where,
        "block_id": arrays["block_id"],
        "parent": arrays["parent"],
        "region": arrays["region"],
        "region_names": _text(arrays["region_names"], "region_names", where),
        "boundary_edges": arrays["boundary_edges"],
        "boundary_patch": arrays["boundary_patch"],
        "patch_names": _text(arrays["patch_names"], "patch_names", where),
        "interface_edges": arrays.get("interface_edges"),
        "interface_patch": arrays.get("interface_patch"),
        "interface_names": (
            _text(arrays["interface_names"], "interface_names", where)
            if "interface_names" in arrays
            else None
        ),
        "level": arrays.get("level", 0),
        "name": _text(arrays.get("name", np.array("")), "name", where, scalar=True),
    }
    if polygons:
        return polygon_mesh_from_arrays(
            arrays["points"],
            arrays["cell_offsets"],
            arrays["cell_nodes"],
            cell_level=arrays.get("cell_level"),
            **common,
        )
    return mesh_from_arrays(
        arrays["points"], arrays["cells"], curves=curves_from_arrays(arrays, where), **common
    )


def _text(values: np.ndarray, key: str, where: str, *, scalar: bool = False) -> Any:
    """The strings of a unicode array (a list, or one string with ``scalar``)."""
    wanted_ndim = 0 if scalar else 1
    if values.dtype.kind != "U" or values.ndim != wanted_ndim:
        shape = "one string" if scalar else "a list of strings"
        raise ExportError(
            f"{where}: the array {key!r} is not {shape} ({values.dtype}, {values.shape})"
        )
    return str(values) if scalar else [str(v) for v in values.tolist()]


FORMAT = Format.of(
    write_npz,
    read_npz,
    "NumPy archive of every mesh array (lossless)",
    compressions=("none", "zlib"),
)
