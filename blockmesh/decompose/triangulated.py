"""The general route: a quality triangulation, a template per piece, then the free nodes moved.

Any polygon with holes goes this way when no exact convex layout suits it: the triangulation
(:mod:`~blockmesh.decompose.triangulate`) is paired into quadrilaterals where the pair is convex
(:mod:`~blockmesh.decompose.merge`), every piece becomes pentagons by its template
(:mod:`~blockmesh.decompose.pieces`), and the nodes off the corners are moved to raise the worst
angle (:mod:`~blockmesh.decompose.optimise`), sliding along the polygon's edges.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> d = triangulated_decomposition([square], min_angle=30.0)
>>> d.layout, bool(d.min_angle > 30)
('triangulation', True)
"""

from __future__ import annotations

import numpy as np

from blockmesh.decompose.decomposition import Decomposition
from blockmesh.decompose.merge import pair_triangles
from blockmesh.decompose.optimise import WorstAngle
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.triangulate import triangulate
from blockmesh.geometry.polygons import interior_angles
from blockmesh.refinement.placement import Freedom

__all__ = ["triangulated_decomposition"]


def triangulated_decomposition(rings: list[np.ndarray], min_angle: float) -> Decomposition:
    """Quality triangulation, a template per piece, then the free nodes moved.

    ``rings`` as :func:`~blockmesh.decompose.decompose_polygon` takes them, in a local frame.
    """
    t = triangulate(rings, min_angle=min_angle)
    quads, triangles = pair_triangles(t.points, t.triangles)
    pentagons = pentagons_from_pieces(t.points, [triangles, quads])
    nodes, blocks = pentagons.nodes, pentagons.blocks
    # Chains along every ring edge: the segments on it in order, each with its two side nodes.
    counts = [len(r) for r in rings]
    offsets = np.concatenate([[0], np.cumsum(counts)])
    chains_of_segments = pentagons.side_chains(t.segments[:, 0], t.segments[:, 1])
    n_edges = int(offsets[-1])
    ring_points = np.vstack(rings)
    # Sort the segments by ring edge, then along it (their start's distance from its corner).
    nxt = np.array([_ring_next(e, offsets) for e in range(n_edges)], dtype=np.int64)
    start = ring_points[t.segment_edge]
    direction = ring_points[nxt[t.segment_edge]] - start
    along = np.sum((t.points[t.segments[:, 0]] - start) * direction, axis=1)
    order = np.lexsort((along, t.segment_edge))
    bounds = np.searchsorted(t.segment_edge[order], np.arange(n_edges + 1))
    ring_chains: list[np.ndarray] = []
    for edge in range(n_edges):
        ordered = chains_of_segments[order[bounds[edge] : bounds[edge + 1]]]
        ring_chains.append(np.concatenate([ordered[:, :3].ravel(), ordered[-1:, 3]]))
    fixed, slide = _boundary_freedom(nodes, ring_chains, n_edges)
    nodes = WorstAngle().place(nodes, blocks, Freedom(fixed, slide))
    per_ring = [ring_chains[offsets[r] : offsets[r + 1]] for r in range(len(rings))]
    angles = interior_angles(nodes[blocks])
    return Decomposition(
        vertices=nodes,
        blocks=blocks,
        edge_chains=tuple(per_ring[0]),
        layout="triangulation",
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
        hole_chains=tuple(tuple(c) for c in per_ring[1:]),
    )


def _ring_next(edge: int, offsets: np.ndarray) -> int:
    ring = int(np.searchsorted(offsets, edge, side="right")) - 1
    start, stop = int(offsets[ring]), int(offsets[ring + 1])
    return start + (edge - start + 1) % (stop - start)


def _boundary_freedom(
    nodes: np.ndarray, chains: list[np.ndarray], n_corners: int
) -> tuple[np.ndarray, np.ndarray]:
    """Ring corners are fixed; the other nodes of a ring edge may slide along it."""
    fixed = np.zeros(len(nodes), dtype=bool)
    fixed[:n_corners] = True
    slide = np.zeros((len(nodes), 2))
    for chain in chains:
        inner = chain[1:-1]
        d = nodes[chain[-1]] - nodes[chain[0]]
        slide[inner] = d / np.hypot(*d)
    return fixed, slide
