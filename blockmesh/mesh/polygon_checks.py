"""The arrays and cells of a polygon mesh checked: shapes, index ranges, orientation, star shape.

What the constructor of :class:`~blockmesh.mesh.polygons.PolygonMesh` checks, beside the checks
it shares with :class:`~blockmesh.mesh.Mesh` (:mod:`blockmesh.mesh.arrays`):
:func:`freeze_polygon_arrays` reads and freezes the arrays, :func:`check_polygon_arrays` checks
the offsets, lengths and index ranges (O(S)), :func:`check_polygon_cells` the cells themselves
(distinct nodes, counter-clockwise and star-shaped from the vertex mean, the boundary edges
exactly the free cell edges, the interface edges between two cells).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.geometry.topology import check_boundary
from blockmesh.mesh.arrays import check_finite, check_label_lengths, freeze_labels, read_only
from blockmesh.mesh.polygon_geometry import cell_scale, fan_areas

if TYPE_CHECKING:
    from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "STAR_TOL",
    "check_polygon_arrays",
    "check_polygon_cells",
    "freeze_polygon_arrays",
    "int_array",
]

#: Relative size (against the squared size of the cell) below which a fan triangle from the
#: vertex mean counts as having no area: such a cell is not star-shaped from its vertex mean.
STAR_TOL = 1e-14


def int_array(values: Any, what: str) -> np.ndarray:
    """``values`` as int64 (ArgumentTypeError for floats or what cannot be read)."""
    if isinstance(values, np.ndarray) and values.dtype.kind == "f":
        raise ArgumentTypeError(f"PolygonMesh {what} must be integers, got {values.dtype}")
    try:
        array = np.asarray(values, dtype=np.int64)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(f"PolygonMesh {what} cannot be read as int64: {error}") from None
    return array


def freeze_polygon_arrays(mesh: PolygonMesh) -> None:
    """Read the arrays of ``mesh`` as float64 and int64, check their shapes, freeze them."""
    set_ = object.__setattr__
    try:
        points = np.asarray(mesh.points, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(f"PolygonMesh points cannot be read as float64: {error}") from None
    if points.ndim != 2 or points.shape[1] != 2:
        raise ArgumentError(f"PolygonMesh points must have shape (n, 2), got {points.shape}")
    set_(mesh, "points", read_only(points, mesh.points))
    for name, tail in (
        ("offsets", ()),
        ("nodes", ()),
        ("block_id", ()),
        ("parent", ()),
        ("boundary_patch", ()),
        ("region", ()),
        ("cell_level", ()),
        ("interface_patch", ()),
        ("boundary_edges", (2,)),
        ("interface_edges", (2,)),
    ):
        original = getattr(mesh, name)
        array = int_array(original, name)
        if name in ("boundary_edges", "interface_edges"):
            array = array.reshape(-1, 2) if array.size == 0 else array
        if array.ndim != 1 + len(tail) or array.shape[1:] != tail:
            shape = "(n" + "".join(f", {t}" for t in tail) + ")"
            raise ArgumentError(f"PolygonMesh {name} must have shape {shape}, got {array.shape}")
        set_(mesh, name, read_only(array, original))
    freeze_labels(mesh, "PolygonMesh")


def check_polygon_arrays(mesh: PolygonMesh) -> None:
    """Shapes, lengths, offsets and index ranges (O(S))."""
    offsets = mesh.offsets
    if offsets.size == 0 or offsets[0] != 0 or offsets[-1] != mesh.nodes.size:
        raise ArgumentError(
            f"PolygonMesh offsets must run from 0 to the number of nodes listed "
            f"({mesh.nodes.size}), got {offsets[:1].tolist()}..{offsets[-1:].tolist()}"
        )
    sizes = np.diff(offsets)
    if np.any(sizes < 3):
        small = int(np.flatnonzero(sizes < 3)[0])
        raise ArgumentError(
            f"cell {small} has {int(sizes[small])} vertices; a cell needs 3 or more"
        )
    check_label_lengths(mesh, "PolygonMesh", ("block_id", "parent", "region", "cell_level"))
    n = mesh.n_points
    for values, what, low, high in (
        (mesh.nodes, "cell node", 0, n),
        (mesh.boundary_edges, "boundary edge node", 0, n),
        (mesh.block_id, "block_id", 0, None),
        (mesh.parent, "parent", -1, None),
        (mesh.cell_level, "cell_level", 0, None),
        (mesh.boundary_patch, "boundary_patch", 0, len(mesh.patch_names)),
        (mesh.region, "region", 0, len(mesh.region_names)),
        (mesh.interface_edges, "interface edge node", 0, n),
        (mesh.interface_patch, "interface_patch", 0, len(mesh.interface_names)),
    ):
        if values.size == 0:
            continue
        bad: np.ndarray = values < low
        if high is not None:
            bad |= values >= high
        if np.any(bad):
            at = int(np.flatnonzero(bad.ravel())[0])
            valid = f"{low}.." if high is None else f"{low}..{high - 1}"
            raise ArgumentError(
                f"{what} {values.ravel()[at]} (entry {at}) is out of range (valid: {valid})"
            )
    if mesh.curves is not None and len(mesh.curves) and int(mesh.curves.edges.max()) >= n:
        raise ArgumentError(f"a curved edge names a node >= {n}, the number of points")


def check_polygon_cells(mesh: PolygonMesh) -> None:
    """Finite points, distinct nodes, CCW and star-shaped cells, the boundary edges."""
    check_finite(mesh.points)
    cells = mesh.polygon_cells()
    owner = cells.slot_cell()
    order = np.lexsort((mesh.nodes, owner))
    repeated = (mesh.nodes[order][1:] == mesh.nodes[order][:-1]) & (
        owner[order][1:] == owner[order][:-1]
    )
    if np.any(repeated):
        cell = int(owner[order][1:][repeated][0])
        raise ArgumentError(f"cell {cell} {mesh.cell(cell).tolist()} repeats a node")
    fan = fan_areas(mesh)
    scale = cell_scale(mesh)
    bad = ~(fan > STAR_TOL * scale[owner])
    if np.any(bad):
        cell = int(owner[np.flatnonzero(bad)[0]])
        clockwise = not mesh.cell_areas()[cell] > 0
        why = (
            "is clockwise or has no area; cells run counter-clockwise"
            if clockwise
            else "is not star-shaped with respect to its vertex mean"
        )
        raise ArgumentError(f"cell {cell} (nodes {mesh.cell(cell).tolist()}) {why}")
    check_boundary(cells, mesh.boundary_edges, mesh.n_points)
    if mesh.interface_edges.shape[0]:
        mesh.interface_cells()
