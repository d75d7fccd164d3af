"""What the format modules share: the :class:`Format` record, metadata and mesh rebuilding.

Examples
--------
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> pts = np.array([[0, 0], [2, 0], [2.5, 1], [2, 2], [0, 2.0]])
>>> mesh = Mesh.from_cells(pts, [[0, 1, 2, 3, 4]])
>>> decode_metadata(encode_metadata(mesh))["patch_names"]
['boundary']
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ExportError
from ..mesh import Mesh
from ..topology import boundary_of_cells

__all__ = [
    "METADATA_VERSION",
    "Format",
    "check_mesh",
    "decode_metadata",
    "encode_metadata",
    "mesh_from_arrays",
]

#: Version of the JSON metadata block (names, level) the formats carry.
METADATA_VERSION = 1


@dataclass(frozen=True)
class Format:
    """One file format of the registry :data:`blockmesh.io.FORMATS`.

    Attributes
    ----------
    name : str
        The registry key and the ``--format`` name.
    description : str
        One line for listings.
    extensions : tuple of str
        File name endings (lower case, with the dot) that select this format.
    can_read : bool
        Whether :func:`blockmesh.io.read` reads it back.
    needs_split : bool
        Whether the format has no pentagons, so ``split`` must be given.
    compressions : tuple of str
        Accepted ``compression`` values; the first is the default.
    directory : bool
        Whether the output is a directory (OpenFOAM) rather than a file.
    options : tuple of str
        Extra keyword options the writer takes (e.g. ``dz`` for OpenFOAM).
    """

    name: str
    description: str
    extensions: tuple[str, ...]
    writer: Callable[..., Path] = field(repr=False)
    reader: Callable[[Path], Mesh] | None = field(default=None, repr=False)
    needs_split: bool = False
    compressions: tuple[str, ...] = ("none",)
    directory: bool = False
    options: tuple[str, ...] = ()

    @property
    def can_read(self) -> bool:
        """Whether :func:`blockmesh.io.read` can read this format."""
        return self.reader is not None

    @property
    def default_compression(self) -> str:
        """The compression used when none is asked for."""
        return self.compressions[0]


def check_mesh(mesh: Any) -> Mesh:
    """``mesh`` itself if it is a non-empty :class:`~blockmesh.mesh.Mesh`, else ExportError."""
    if not isinstance(mesh, Mesh):
        raise ExportError(
            f"write() takes a blockmesh Mesh (from blockmesh.refine), got {type(mesh).__name__}"
        )
    if mesh.n_cells == 0:
        raise ExportError("the mesh has no cells; there is nothing to write")
    return mesh


def encode_metadata(mesh: Mesh) -> str:
    """The names and level of a mesh as a JSON string (what the arrays cannot carry)."""
    return json.dumps(
        {
            "blockmesh_io": METADATA_VERSION,
            "name": mesh.name,
            "level": int(mesh.level),
            "patch_names": list(mesh.patch_names),
            "region_names": list(mesh.region_names),
        },
        ensure_ascii=False,
        separators=(",", ":"),
    )


def decode_metadata(text: str | bytes | None, where: str = "the file") -> dict[str, Any]:
    """The dictionary of :func:`encode_metadata` (``{}`` for ``None``); ExportError if broken."""
    if text is None:
        return {}
    if isinstance(text, bytes | bytearray | np.ndarray):
        text = bytes(text).decode("utf-8")
    try:
        meta = json.loads(text)
    except ValueError as exc:
        raise ExportError(f"the blockmesh metadata in {where} is not valid JSON: {exc}") from None
    if not isinstance(meta, dict):
        raise ExportError(f"the blockmesh metadata in {where} is not a JSON object")
    return meta


def _index_array(values: Any, n: int, what: str, where: str) -> np.ndarray:
    arr = np.asarray(values).reshape(-1)
    if arr.shape[0] != n:
        raise ExportError(f"{where}: {what} has {arr.shape[0]} entries, expected {n}")
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
        raise ExportError(f"{where}: {what} holds non-finite values")
    return arr.astype(np.int64)


def mesh_from_arrays(
    points: np.ndarray,
    cells: np.ndarray,
    *,
    where: str,
    block_id: np.ndarray | None = None,
    parent: np.ndarray | None = None,
    region: np.ndarray | None = None,
    region_names: tuple[str, ...] | list[str] | None = None,
    boundary_edges: np.ndarray | None = None,
    boundary_patch: np.ndarray | None = None,
    patch_names: tuple[str, ...] | list[str] | None = None,
    level: int = 0,
    name: str = "",
) -> Mesh:
    """A :class:`Mesh` from arrays read from a file, with defaults for what the file lacks.

    Missing block ids become 0 for every cell; a missing parent -1; a missing region the single
    region ``"domain"``; missing boundary edges are found from the cells and put in one patch
    ``"boundary"``. Shapes and index ranges are checked; ``where`` names the file in the
    :class:`ExportError` raised when they are wrong.
    """
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] < 2:
        raise ExportError(f"{where}: the points have shape {points.shape}, expected (N, 2)")
    points = np.ascontiguousarray(points[:, :2])
    cells = np.asarray(cells)
    if cells.ndim != 2 or cells.shape[1] != 5:
        raise ExportError(
            f"{where}: the cells have shape {cells.shape}; blockmesh reads pentagons only (M, 5)"
        )
    cells = cells.astype(np.int64)
    n, m = points.shape[0], cells.shape[0]
    if cells.size and (cells.min() < 0 or cells.max() >= n):
        raise ExportError(
            f"{where}: cell node ids run from {cells.min()} to {cells.max()}, "
            f"but there are {n} points"
        )
    block_id = (
        np.zeros(m, np.int64) if block_id is None else _index_array(block_id, m, "block_id", where)
    )
    parent = (
        np.full(m, -1, np.int64) if parent is None else _index_array(parent, m, "parent", where)
    )
    if region is None:
        region = np.zeros(m, dtype=np.int64)
        region_names = region_names or ("domain",)
    region = _index_array(region, m, "region", where)
    if region_names is None:
        region_names = tuple(f"region_{k}" for k in range(int(region.max(initial=-1)) + 1))
    if region.size and (region.min() < 0 or region.max() >= len(region_names)):
        raise ExportError(
            f"{where}: region indices run from {region.min()} to {region.max()}, "
            f"but there are {len(region_names)} region names"
        )
    if boundary_edges is None:
        boundary_edges = boundary_of_cells(cells, n)
        boundary_patch = np.zeros(boundary_edges.shape[0], dtype=np.int64)
        patch_names = patch_names or ("boundary",)
    boundary_edges = np.asarray(boundary_edges).astype(np.int64).reshape(-1, 2)
    eb = boundary_edges.shape[0]
    if boundary_patch is None:
        boundary_patch = np.zeros(eb, dtype=np.int64)
    boundary_patch = _index_array(boundary_patch, eb, "boundary_patch", where)
    if patch_names is None:
        patch_names = tuple(f"patch_{k}" for k in range(int(boundary_patch.max(initial=-1)) + 1))
    if boundary_patch.size and (
        boundary_patch.min() < 0 or boundary_patch.max() >= len(patch_names)
    ):
        raise ExportError(
            f"{where}: patch indices run from {boundary_patch.min()} to {boundary_patch.max()}, "
            f"but there are {len(patch_names)} patch names"
        )
    if boundary_edges.size and (boundary_edges.min() < 0 or boundary_edges.max() >= n):
        raise ExportError(f"{where}: boundary edge node ids are out of range (0..{n - 1})")
    return Mesh(
        points=points,
        cells=cells,
        block_id=block_id,
        parent=parent,
        boundary_edges=boundary_edges,
        boundary_patch=boundary_patch,
        patch_names=tuple(str(p) for p in patch_names),
        region=region,
        region_names=tuple(str(r) for r in region_names),
        level=int(level),
        name=str(name),
    )
