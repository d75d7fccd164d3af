"""Geometry of polygon cells: areas, turns, straight vertices, corners, sides and measures.

The measures of a :class:`~blockmesh.mesh.polygons.PolygonMesh`, computed over its vertex slots
with whole-array operations (the module notes of :mod:`blockmesh.mesh.polygons` define corners,
straight vertices and sides). The mesh's methods of the same names call these and keep what is
cached in the mesh.

Examples
--------
>>> from blockmesh.mesh.polygons import PolygonMesh
>>> pts = [(0, 0), (1, 0), (1, 0.5), (1, 1), (0, 1), (2, 0), (2, 0.5), (2, 1)]
>>> mesh = PolygonMesh.from_cells(pts, [[0, 1, 2, 3, 4], [1, 5, 6, 2], [2, 6, 7, 3]])
>>> corner_counts(mesh).tolist(), cell_areas(mesh).tolist()
([4, 4, 4], [1.0, 0.5, 0.5])
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.curves.edges import curved_slots
from blockmesh.errors import DomainError
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL

if TYPE_CHECKING:
    from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "STRAIGHT_ULPS",
    "cell_areas",
    "cell_diameters",
    "cell_scale",
    "corner_counts",
    "curve_continues",
    "fan_areas",
    "measure",
    "sides",
    "slot_vectors",
    "straight_vertices",
    "triangles",
    "turn_sines",
    "vertex_means",
]

#: A vertex within this many coordinate spacings (ulps) of the chord of its two neighbours is
#: straight whatever its sine: midpoints are rounded to the spacing.
STRAIGHT_ULPS = 16


def slot_vectors(mesh: PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
    """For every slot (vertex), the incoming and the outgoing edge vectors (S, 2) each."""
    cells = mesh.polygon_cells()
    here = mesh.points[mesh.nodes]
    after = mesh.points[cells.following()]
    before = mesh.points[mesh.nodes[cells.previous_slot()]]
    return here - before, after - here


def fan_areas(mesh: PolygonMesh) -> np.ndarray:
    """Areas of the triangles (vertex mean, vertex s, next vertex) of every slot (S,)."""
    cells = mesh.polygon_cells()
    owner = cells.slot_cell()
    centre = mesh.vertex_means()[owner]
    a = mesh.points[mesh.nodes] - centre
    b = mesh.points[cells.following()] - centre
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def cell_scale(mesh: PolygonMesh) -> np.ndarray:
    """The squared largest distance of a cell's vertex from its vertex mean (M,)."""
    owner = mesh.polygon_cells().slot_cell()
    offset = mesh.points[mesh.nodes] - mesh.vertex_means()[owner]
    reach = np.max(np.abs(offset), axis=1) ** 2
    out = np.zeros(mesh.n_cells)
    np.maximum.at(out, owner, reach)
    return out


def vertex_means(mesh: PolygonMesh) -> np.ndarray:
    """The mean of every cell's vertices (M, 2), hanging nodes included."""
    owner = mesh.polygon_cells().slot_cell()
    sizes = mesh.cell_sizes()
    xy = mesh.points[mesh.nodes]
    return np.stack(
        [np.bincount(owner, xy[:, k], minlength=mesh.n_cells) / sizes for k in range(2)],
        axis=1,
    )


def cell_areas(mesh: PolygonMesh) -> np.ndarray:
    """Area of every cell (positive for counter-clockwise cells), shape (M,).

    Measured relative to each cell's first vertex (areas do not depend on where the mesh
    lies).
    """
    cells = mesh.polygon_cells()
    owner = cells.slot_cell()
    first = mesh.points[mesh.nodes[mesh.offsets[:-1]]][owner]
    a = mesh.points[mesh.nodes] - first
    b = mesh.points[cells.following()] - first
    twice = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return 0.5 * np.bincount(owner, twice, minlength=mesh.n_cells)


def cell_diameters(mesh: PolygonMesh) -> np.ndarray:
    """Largest distance between two vertices of every cell (M,)."""
    out = np.empty(mesh.n_cells)
    for group in mesh.groups:
        xy = mesh.points[group.cells]
        diff = xy[:, :, None, :] - xy[:, None, :, :]
        out[group.index] = np.sqrt(np.max(np.sum(diff * diff, axis=-1), axis=(1, 2)))
    return out


def curve_continues(mesh: PolygonMesh) -> np.ndarray:
    """For every slot, whether its vertex sits between two edges on the same curve."""
    if mesh.curves is None or len(mesh.curves) == 0:
        return np.zeros(mesh.nodes.size, dtype=bool)
    if "curve_continues" not in mesh._cache:
        cells = mesh.polygon_cells()
        row, _ = curved_slots(cells, mesh.n_points, mesh.curves)
        previous = row[cells.previous_slot()]
        same = (row >= 0) & (previous >= 0)
        same &= mesh.curves.curve[np.maximum(row, 0)] == mesh.curves.curve[np.maximum(previous, 0)]
        mesh._cache["curve_continues"] = same
    return mesh._cache["curve_continues"]


def turn_sines(mesh: PolygonMesh) -> np.ndarray:
    """Sine of the turn at every vertex (S,), in slot order: > 0 left, 0 straight.

    NaN at a vertex with a zero-length edge.
    """
    incoming, outgoing = slot_vectors(mesh)
    cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
    norms = np.hypot(*incoming.T) * np.hypot(*outgoing.T)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norms > 0, cross / np.where(norms > 0, norms, 1.0), np.nan)


def straight_vertices(mesh: PolygonMesh) -> np.ndarray:
    """For every slot, whether its vertex is straight in its cell (180 degrees), (S,) bool.

    Straight: the edges continue forwards and the turn's sine is within
    :data:`~blockmesh.geometry.COLLINEAR_SIN_TOL` or the vertex is within 16 coordinate
    spacings of the chord of its neighbours (a rounded midpoint); or both edges lie on the
    same curve. Hanging nodes are straight
    vertices of the coarser cell.
    """
    if "straight" not in mesh._cache:
        incoming, outgoing = slot_vectors(mesh)
        sines = mesh.turn_sines()
        forward = np.einsum("sd,sd->s", incoming, outgoing) > 0
        straight = (np.abs(np.nan_to_num(sines, nan=1.0)) <= COLLINEAR_SIN_TOL) & forward
        # A midpoint is rounded to the coordinates' spacing: far from the origin a node
        # halving a short edge can be that far off the chord. Within a few spacings of it
        # the vertex is straight.
        cross = np.abs(incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0])
        chord = np.hypot(*(incoming + outgoing).T)
        reach = np.max(np.abs(mesh.points[mesh.nodes]), axis=1)
        off = np.divide(cross, chord, out=np.full_like(cross, np.inf), where=chord > 0)
        straight |= forward & (off <= STRAIGHT_ULPS * np.spacing(reach))
        straight |= curve_continues(mesh)
        straight.setflags(write=False)
        mesh._cache["straight"] = straight
    return mesh._cache["straight"]


def corner_counts(mesh: PolygonMesh) -> np.ndarray:
    """Corners of every cell (M,): its vertices that are not straight."""
    owner = mesh.polygon_cells().slot_cell()
    return np.bincount(owner, ~mesh.straight_vertices(), minlength=mesh.n_cells).astype(np.int64)


def sides(mesh: PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
    """The side (corner to corner run of edges) of every slot, and each side's edge count.

    Returns ``(side (S,), length (K,))``: slot ``s`` lies on side ``side[s]``, numbered cell
    by cell; a side of length ``k`` carries ``k - 1`` straight vertices (hanging nodes).
    Raises DomainError naming a cell without three corners.
    """
    if "sides" not in mesh._cache:
        corner = ~mesh.straight_vertices()
        counts = mesh.corner_counts()
        if np.any(counts < 3):
            bad = int(np.flatnonzero(counts < 3)[0])
            raise DomainError(
                f"cell {bad} (nodes {mesh.cell(bad).tolist()}) has {int(counts[bad])} "
                "corners; a cell needs three or more vertices where its boundary turns"
            )
        cells = mesh.polygon_cells()
        owner = cells.slot_cell()
        running = np.cumsum(corner)  # corners up to and including each slot
        before = np.concatenate([[0], running])[mesh.offsets[:-1]]  # corners of earlier cells
        last = running[mesh.offsets[1:] - 1] - 1  # the last side of every cell
        side = running - 1
        wraps = (running - before[owner]) == 0  # slots before the cell's first corner
        side[wraps] = last[owner[wraps]]
        length = np.bincount(side, minlength=int(running[-1]) if running.size else 0)
        side.setflags(write=False)
        length.setflags(write=False)
        mesh._cache["sides"] = (side, length)
    return mesh._cache["sides"]


def measure(mesh: PolygonMesh) -> dict[str, Any]:
    """Corner angles, areas, aspect and convexity of all cells, once (cached)."""
    if "measures" in mesh._cache:
        return mesh._cache["measures"]
    sines = mesh.turn_sines()
    straight = mesh.straight_vertices()
    incoming, outgoing = slot_vectors(mesh)
    cross = incoming[:, 0] * outgoing[:, 1] - incoming[:, 1] * outgoing[:, 0]
    dot = np.einsum("sd,sd->s", incoming, outgoing)
    angles = 180.0 - np.degrees(np.arctan2(cross, dot))
    corner = ~straight
    left = np.nan_to_num(sines, nan=-1.0) > COLLINEAR_SIN_TOL
    owner = mesh.polygon_cells().slot_cell()
    bad_vertex = ~(left | straight)
    bad = np.bincount(owner, bad_vertex, minlength=mesh.n_cells) > 0
    corners = np.bincount(owner, corner, minlength=mesh.n_cells)
    # Every vertex's turn counts: a straight vertex on a straight side turns by nothing, one
    # on a curve (a node a finer neighbour put on a curved interface) by the curve's bend,
    # to the left or, on the curve's concave side, to the right.
    turning = np.bincount(owner, 180.0 - angles, minlength=mesh.n_cells)
    bad |= corners < 3
    bad |= ~np.isclose(turning, 360.0, atol=1e-6)
    areas = mesh.cell_areas()
    bad |= ~(areas > 0)
    diam2 = mesh.cell_diameters() ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
    corner_angles = angles[corner]
    result = {
        "area": math.fsum(areas.tolist()),
        "min_area": float(areas.min()) if areas.size else math.nan,
        "max_area": float(areas.max()) if areas.size else math.nan,
        "min_angle": float(corner_angles.min()) if corner_angles.size else math.nan,
        "max_angle": float(corner_angles.max()) if corner_angles.size else math.nan,
        "max_aspect_ratio": float(aspect.max()) if aspect.size else math.nan,
        "not_strictly_convex": int(np.count_nonzero(bad)),
        "invalid": np.flatnonzero(bad),
    }
    mesh._cache["measures"] = result
    return result


def triangles(mesh: PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
    """A fan of triangles from vertex 0 of every cell: ``(triangles (T, 3), cell (T,))``.

    Each cell of n vertices gives n - 2 triangles, counter-clockwise (convex cells only
    make valid fans; a straight vertex 0 gives a triangle of no area, which the pictures and
    the formats that need triangles tolerate).
    """
    sizes = mesh.cell_sizes()
    count = sizes - 2
    cell = np.repeat(np.arange(mesh.n_cells, dtype=np.int64), count)
    start = np.repeat(mesh.offsets[:-1], count)
    k = np.arange(cell.size) - np.repeat(np.cumsum(count) - count, count)
    tris = np.stack([mesh.nodes[start], mesh.nodes[start + k + 1], mesh.nodes[start + k + 2]], 1)
    return tris, cell
