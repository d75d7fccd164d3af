"""Local refinement beside curves: midpoints and centres on the curve, the curve table split.

A side of a marked cell on a curve gets its new node on the curve (:func:`curve_midpoints`), a
cell with a curved side its centre by the curved rule (:func:`curved_centres`), the curve table
its split edges halved (:func:`split_curves`); :func:`check_folds` refuses a split whose children
next to the curve fold.
"""

from __future__ import annotations

import numpy as np

from blockmesh.curves.edges import CurvedEdges
from blockmesh.errors import DomainError
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.geometry.topology import edge_keys
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "NO_CURVES",
    "check_folds",
    "curve_midpoints",
    "curved_centres",
    "curved_with_hanging",
    "split_curves",
]

#: An empty curve table (meshes without curves).
NO_CURVES = CurvedEdges(
    edges=np.empty((0, 2), np.int64),
    curve=np.empty(0, np.int64),
    start=np.empty(0),
    stop=np.empty(0),
    curves=(),
)


def curve_midpoints(curves: CurvedEdges, rows: np.ndarray) -> np.ndarray:
    """The curve's point at the mean parameter of each of ``rows`` (the dyadic midpoint)."""
    out = np.empty((rows.size, 2))
    start, stop = curves.start[rows], curves.stop[rows]
    middle = start + 0.5 * (stop - start)
    for index, curve in enumerate(curves.curves):
        mine = curves.curve[rows] == index
        if np.any(mine):
            out[mine] = curve.point(middle[mine])
    return out


def curved_with_hanging(mesh: PolygonMesh, first: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Sides of two edges whose middle node continues a curve (curved, with a hanging node)."""
    continues = np.zeros(first.size, dtype=bool)
    two = length == 2
    if np.any(two):
        straight_on_curve = mesh._curve_continues()
        following_slot = mesh.polygon_cells().next_slot()
        continues[two] = straight_on_curve[following_slot[first[two]]]
    return continues


def curved_centres(
    u_xy: np.ndarray, v_xy: np.ndarray, k: np.ndarray, which: np.ndarray
) -> np.ndarray:
    """``p = (2/k) Σ u_i - (1/k) Σ v_i`` of the marked cells ``which`` (the curved rule).

    For pentagons ``0.4 Σ u - 0.2 Σ v`` with numpy's sums over the five rows, the operations of
    :func:`blockmesh.refinement.curved.curved_block_levels` (so the bits agree). Cells of one
    corner count at a time.
    """
    starts = np.cumsum(k) - k
    chosen = np.flatnonzero(which)
    out = np.empty((chosen.size, 2))
    for size in np.unique(k[chosen]).tolist():
        mine = k[chosen] == size
        rows = starts[chosen[mine]][:, None] + np.arange(size)
        u, v = u_xy[rows], v_xy[rows]
        if size == 5:
            out[mine] = 0.4 * u.sum(axis=1) - 0.2 * v.sum(axis=1)
        else:
            out[mine] = (2.0 / size) * u.sum(axis=1) - (1.0 / size) * v.sum(axis=1)
    return out


def split_curves(curves: CurvedEdges, keys: np.ndarray, mids: np.ndarray, n: int) -> CurvedEdges:
    """The curve table with every edge of ``keys`` replaced by its halves at node ``mids``."""
    key = edge_keys(curves.edges[:, 0], curves.edges[:, 1], n)
    where = np.minimum(np.searchsorted(keys, key), max(keys.size - 1, 0))
    split = (keys.size > 0) & (keys[where] == key)
    repeats = 1 + split.astype(np.int64)
    edges = np.repeat(curves.edges, repeats, axis=0)
    start = np.repeat(curves.start, repeats)
    stop = np.repeat(curves.stop, repeats)
    last = np.cumsum(repeats) - 1
    middle_node = mids[where[split]]
    middle = curves.start[split] + 0.5 * (curves.stop[split] - curves.start[split])
    edges[last[split] - 1, 1] = middle_node
    edges[last[split], 0] = middle_node
    stop[last[split] - 1] = middle
    start[last[split]] = middle
    return CurvedEdges(
        edges=edges,
        curve=np.repeat(curves.curve, repeats),
        start=start,
        stop=stop,
        curves=curves.curves,
    )


def check_folds(old: PolygonMesh, new: PolygonMesh, children: np.ndarray) -> None:
    """DomainError naming the first split cell next to a curve whose children fold.

    ``children`` are the cells of ``new`` the marked cells of ``old`` became.
    """
    areas = new.cell_areas()[children]
    sines = new.turn_sines()
    straight = new.straight_vertices()
    owner = new.polygon_cells().slot_cell()
    bad_vertex = ~(np.nan_to_num(sines, nan=-1.0) > COLLINEAR_SIN_TOL) & ~straight
    bad_cell = np.bincount(owner, bad_vertex, minlength=new.n_cells) > 0
    folded = ~(areas > 0) | bad_cell[children]
    if not np.any(folded):
        return
    child = int(children[np.flatnonzero(folded)[0]])
    parent = int(new.parent[child])
    corners = ", ".join(f"({x:.6g}, {y:.6g})" for x, y in old.points[old.cell(parent)])
    raise DomainError(
        f"refining cell {parent} (vertices {corners}) would fold it: its child {child} next "
        "to the curve is not convex and counter-clockwise; the curve bends too much for this "
        "cell. Refine the blocks along the curve uniformly first (a higher level), or give "
        "the curve more blocks"
    )
