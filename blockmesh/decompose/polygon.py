"""Any polygon with holes to strictly convex pentagonal blocks: the decomposition's front door.

:func:`decompose_polygon` takes validated rings (:func:`blockmesh.validate.check_rings`) and
chooses the route:

- a strictly convex polygon without holes and with at most :data:`CONVEX_LIMIT` corners goes to the
  exact layouts of :mod:`blockmesh.decompose.convex` (the fewest blocks: 1 for a pentagon, 9 for a
  triangle, ``ceil((n - 2) / 3)`` for ``n >= 6``), unless their worst angle is below
  :data:`CONVEX_MIN_ANGLE` and the general route does better (a 50:1 rectangle);
- everything else (non-convex polygons, holes, straight corners kept between two patches, many
  corners) is triangulated with quality refinement (:mod:`blockmesh.decompose.triangulate`),
  neighbouring triangles are paired into convex quadrilaterals where that keeps them round
  (:mod:`blockmesh.decompose.merge`), every piece becomes its ring-and-hub template (9 pentagons
  for a triangle, 12 for a quadrilateral) with side nodes shared bit for bit
  (:mod:`blockmesh.decompose.pieces`), and the free nodes are moved to raise the worst angle
  (:mod:`blockmesh.decompose.optimise`).

Both work in the rings' local frame (:func:`blockmesh.geometry.local_frame`) and map back, the
rings' own corners bit for bit, so the result does not depend on where the polygon sits.

Examples
--------
>>> import numpy as np
>>> outer = np.array([[0, 0], [3, 0], [3, 3], [0, 3]], dtype=float)
>>> hole = np.array([[1, 1], [1, 2], [2, 2], [2, 1]], dtype=float)  # clockwise
>>> d = decompose_polygon([outer, hole])
>>> d.layout, len(d.hole_chains), bool(d.min_angle > 20)
('triangulation', 1, True)
>>> d.vertices[:4].tolist() == outer.tolist()  # the corners come first, unchanged
True
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import DomainError, ResourceError
from ..geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles, local_frame
from .convex import _CHORD_LIMIT, Decomposition, decompose_convex_polygon
from .merge import pair_triangles
from .optimise import improve_angles
from .pieces import pentagons_from_pieces
from .triangulate import DEFAULT_MIN_ANGLE, triangulate

__all__ = [
    "CONVEX_LIMIT",
    "CONVEX_MIN_ANGLE",
    "MAX_CORNERS",
    "check_corner_count",
    "decompose_polygon",
]

#: Strictly convex polygons (no holes) with at most this many corners get the exact layouts.
CONVEX_LIMIT = _CHORD_LIMIT
#: Exact convex layouts with a worst angle below this (degrees) are compared with the general route.
CONVEX_MIN_ANGLE = 20.0
#: Most ring corners accepted: what the decomposition does in seconds. Measured on this
#: project's machine (2 cores): a smooth 1,000-corner outline in about 5 s, a jagged one (a
#: random star, whose close features grade the triangulation down: 80,000 blocks) in about 10 s;
#: 2,000 corners took 6 s and 36 s, 10,000 smooth ones 38 s.
MAX_CORNERS = 1_000


def check_corner_count(total: int, what: str = "the polygon") -> None:
    """ResourceError when ``total`` corners are more than :data:`MAX_CORNERS`.

    Called as soon as the corners are counted (by the readers, before anything is parsed
    further or decomposed).

    Examples
    --------
    >>> check_corner_count(1_000_000)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ResourceError: the polygon has 1,000,000 corners; at most 1,000 are ...
    """
    if total > MAX_CORNERS:
        raise ResourceError(
            f"{what} has {total:,} corners; at most {MAX_CORNERS:,} are decomposed, which takes "
            "seconds (simplify the outline, e.g. with shapely's simplify, or split the domain "
            "into parts)"
        )


def decompose_polygon(
    rings: Sequence[np.ndarray], *, min_angle: float = DEFAULT_MIN_ANGLE
) -> Decomposition:
    """Split a polygon with holes into strictly convex pentagons that meet edge to edge.

    Parameters
    ----------
    rings : sequence of ndarray (n_r, 2)
        The outer ring counter-clockwise, then the holes clockwise, as
        :func:`blockmesh.validate.check_rings` returns them.
    min_angle : float
        Target smallest angle of the quality triangulation (degrees) for the general route.

    Returns
    -------
    Decomposition
        ``vertices`` start with the rings' corners, ring after ring, bit for bit;
        ``edge_chains`` run along the outer ring's edges, ``hole_chains[k]`` along hole k's.

    Raises
    ------
    ResourceError
        If the rings have more than :data:`MAX_CORNERS` corners.
    DomainError
        If double precision cannot hold the blocks where the polygon sits (blocks smaller than a
        few units in the last place of its coordinates).
    """
    rings = [np.asarray(r, dtype=np.float64) for r in rings]
    check_corner_count(sum(len(r) for r in rings))
    frame = local_frame(np.vstack(rings))
    local = [frame.to_local(r) for r in rings]
    decomposition = None
    if len(rings) == 1 and len(rings[0]) <= CONVEX_LIMIT and _strictly_convex(local[0]):
        try:
            decomposition = decompose_convex_polygon(local[0])
        except (DomainError, ValueError):
            decomposition = None  # too thin for the exact layouts: the general route copes
    if decomposition is None or decomposition.min_angle < CONVEX_MIN_ANGLE:
        general = _triangulated(local, min_angle)
        # A clear margin, so that round-off (say, of a shift) does not flip the choice.
        if decomposition is None or general.min_angle > decomposition.min_angle + 1.0:
            decomposition = general
    return _to_global(decomposition, rings, frame)


def _strictly_convex(ring: np.ndarray) -> bool:
    return bool(np.all(corner_sines(ring) > COLLINEAR_SIN_TOL))


def _triangulated(rings: list[np.ndarray], min_angle: float) -> Decomposition:
    """Quality triangulation, a template per triangle, then the free nodes moved."""
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
    nodes = improve_angles(nodes, blocks, fixed, slide=slide)
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


def _to_global(d: Decomposition, rings: list[np.ndarray], frame) -> Decomposition:
    """Map a decomposition made in local coordinates back; the ring corners bit for bit."""
    vertices = frame.to_global(d.vertices)
    corners = np.vstack(rings)
    vertices[: len(corners)] = corners
    _check_representable(vertices, d.blocks, frame)
    angles = interior_angles(vertices[d.blocks])
    for a in (vertices, d.blocks, *d.edge_chains, *(c for h in d.hole_chains for c in h)):
        a.setflags(write=False)
    return Decomposition(
        vertices=vertices,
        blocks=d.blocks,
        edge_chains=d.edge_chains,
        layout=d.layout,
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
        hole_chains=d.hole_chains,
    )


def _check_representable(vertices: np.ndarray, blocks: np.ndarray, frame) -> None:
    """Blocks that rounding to the global coordinates made non-convex: too small for doubles."""
    sines = corner_sines(vertices[blocks])
    bad = np.flatnonzero(~np.all(sines > COLLINEAR_SIN_TOL, axis=1))
    if bad.size:
        size = float(np.ptp(vertices[blocks[bad[0]]], axis=0).max())
        raise DomainError(
            f"the polygon is too small for where it sits to be decomposed in double precision: "
            f"its blocks are about {size:.3g} across "
            f"at coordinates near {float(np.max(np.abs(frame.origin))):.3g}, where doubles are "
            f"only {frame.ulp():.3g} apart, and rounding folds {bad.size} of them; move the "
            "domain near the origin (or use other units)"
        )
