"""NumPy ``.npz``: every array of a :class:`~blockmesh.mesh.Mesh` plus its names, lossless.

The archive holds ``points, cells, block_id, parent, boundary_edges, boundary_patch, region`` as
they are, ``patch_names`` and ``region_names`` as unicode arrays, ``level``, ``name`` and
``format_version``, for a composite domain ``interface_edges``, ``interface_patch`` and
``interface_names``, and for a mesh with curved edges the arrays of
:data:`~blockmesh.io._common.CURVE_ARRAYS` (so that refining the mesh read back follows the
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

from pathlib import Path

import numpy as np

from blockmesh._system.atomic import atomic_file
from blockmesh.errors import ExportError
from blockmesh.io.common import Format, curve_arrays, curves_from_arrays, mesh_from_arrays
from blockmesh.io.polygons import POLYGONS, polygon_mesh_from_arrays
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["FORMAT", "read_npz", "write_npz"]

_ARRAYS = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch", "region")
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


def read_npz(path: Path) -> Mesh | PolygonMesh:
    """Read a mesh written by :func:`write_npz` (a PolygonMesh when it holds one)."""
    where = str(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            polygons = "cell_offsets" in data
            needed = [k for k in _ARRAYS if k != "cells"] if polygons else list(_ARRAYS)
            if polygons:
                needed += ["cell_nodes"]
            missing = [k for k in (*needed, "patch_names", "region_names") if k not in data]
            if missing:
                raise ExportError(
                    f"{where} is not a blockmesh .npz: it lacks {', '.join(missing)} "
                    "(write it with blockmesh.io.write)"
                )
            arrays = {k: data[k] for k in data.files}
    except ExportError:
        raise
    except Exception as exc:  # zipfile and numpy raise many kinds for damaged archives
        raise ExportError(f"cannot read {where} as .npz: {exc}") from None
    if "cell_offsets" in arrays:
        return polygon_mesh_from_arrays(
            arrays["points"],
            arrays["cell_offsets"],
            arrays["cell_nodes"],
            where=where,
            block_id=arrays["block_id"],
            parent=arrays["parent"],
            region=arrays["region"],
            region_names=[str(s) for s in arrays["region_names"].tolist()],
            boundary_edges=arrays["boundary_edges"],
            boundary_patch=arrays["boundary_patch"],
            patch_names=[str(s) for s in arrays["patch_names"].tolist()],
            cell_level=arrays.get("cell_level"),
            level=int(arrays.get("level", 0)),
            name=str(arrays.get("name", "")),
        )
    return mesh_from_arrays(
        arrays["points"],
        arrays["cells"],
        where=where,
        block_id=arrays["block_id"],
        parent=arrays["parent"],
        region=arrays["region"],
        region_names=[str(s) for s in arrays["region_names"].tolist()],
        boundary_edges=arrays["boundary_edges"],
        boundary_patch=arrays["boundary_patch"],
        patch_names=[str(s) for s in arrays["patch_names"].tolist()],
        interface_edges=arrays.get("interface_edges"),
        interface_patch=arrays.get("interface_patch"),
        interface_names=(
            [str(s) for s in arrays["interface_names"].tolist()]
            if "interface_names" in arrays
            else None
        ),
        level=int(arrays.get("level", 0)),
        name=str(arrays.get("name", "")),
        curves=curves_from_arrays(arrays, where),
    )


FORMAT = Format(
    name="npz",
    description="NumPy archive of every mesh array (lossless)",
    extensions=(".npz",),
    writer=write_npz,
    reader=read_npz,
    compressions=("none", "zlib"),
)
