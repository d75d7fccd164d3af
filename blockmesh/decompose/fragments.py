"""Several faces that share edges to strictly convex pentagons, conforming across every edge.

A composite domain is a planar subdivision: faces (polygons with holes, one per connected piece of
a region) whose rings share the arrangement's points, two faces meeting along the edges they
share. :func:`decompose_faces` decomposes all of them at once, so that the blocks of two faces
meet edge to edge along every shared edge:

1. every face gets GEOS's constrained Delaunay triangulation, all faces over one point set;
2. the triangulation is refined for quality as one (:mod:`~blockmesh.decompose.triangulate`): a
   shared edge is a segment seen from both faces, never crossed by a cavity, and when it must be
   split both faces get the same new point (or neither does);
3. neighbouring triangles of one face are paired into convex quadrilaterals, never across faces
   (:mod:`~blockmesh.decompose.merge`);
4. every piece becomes its ring-and-hub template with side nodes computed once per side
   (:mod:`~blockmesh.decompose.pieces`), so a shared edge has one set of nodes, numbered once;
5. the free nodes are moved to raise the worst angle, those on a ring edge sliding along it.

Everything runs in the points' local frame and maps back with the arrangement's points restored
bit for bit. Merging is by topology throughout (point ids of the arrangement, side keys of the
pieces), never by coordinates.

Examples
--------
>>> import numpy as np
>>> points = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], dtype=float)
>>> left, right = [np.array([0, 1, 4, 5])], [np.array([1, 2, 3, 4])]
>>> d = decompose_faces(points, [left, right])
>>> np.bincount(d.block_face).tolist() == [d.n_blocks // 2] * 2
True
>>> shared = d.ring_chains[0][0][1]  # face 0, outer ring, edge 1 (corner 1 to corner 4)
>>> shared[[0, -1]].tolist(), d.ring_chains[1][0][3][::-1].tolist() == shared.tolist()
([1, 4], True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.decompose.decomposition import _check_representable
from blockmesh.decompose.merge import pair_triangles
from blockmesh.decompose.optimise import improve_angles
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.triangulate import (
    DEFAULT_MIN_ANGLE,
    _constrained_triangles,
    _Refiner,
)
from blockmesh.errors import DomainError, ResourceError
from blockmesh.geometry.polygons import (
    interior_angles,
    local_frame,
)
from blockmesh.geometry.topology import graph_components

__all__ = ["MAX_FACE_CORNERS", "FaceDecomposition", "decompose_faces"]

#: Most ring corners (counted once per face ring) accepted, as for one polygon.
MAX_FACE_CORNERS = 200_000


@dataclass(frozen=True)
class FaceDecomposition:
    """The blocks of a planar subdivision, and the block vertices along every ring edge.

    Attributes
    ----------
    vertices : ndarray (K, 2) float64, read-only
        The arrangement's points first, bit for bit and in order, then the new nodes.
    blocks : ndarray (B, 5) int64, read-only
        Counter-clockwise strictly convex pentagons.
    block_face : ndarray (B,) int64
        The face each block lies in.
    ring_chains : tuple (faces) of tuple (rings) of tuple (edges) of ndarray
        ``ring_chains[f][r][i]``: the vertex ids along edge ``i`` of ring ``r`` of face ``f``
        (from its corner ``i`` to corner ``i + 1``), ends included. An edge two faces share has
        the same chain in both, read in opposite directions.
    min_angle, max_angle : float
        Smallest and largest interior angle of the blocks, degrees.
    """

    vertices: np.ndarray
    blocks: np.ndarray
    block_face: np.ndarray
    ring_chains: tuple[tuple[tuple[np.ndarray, ...], ...], ...]
    min_angle: float
    max_angle: float

    @property
    def n_blocks(self) -> int:
        """Number of blocks B."""
        return int(self.blocks.shape[0])


def decompose_faces(
    points: np.ndarray,
    faces: Sequence[Sequence[np.ndarray]],
    *,
    min_angle: float = DEFAULT_MIN_ANGLE,
) -> FaceDecomposition:
    """Decompose faces that share edges into blocks that meet edge to edge across them.

    Parameters
    ----------
    points : ndarray (N, 2)
        The arrangement's points: every corner of every face ring, each once.
    faces : sequence of sequences of int arrays
        Each face's rings as point ids: the outer ring counter-clockwise, then its holes
        clockwise (the face on the left of every ring edge). Two faces that meet share the
        points along their common edges, which they run in opposite directions; faces do not
        overlap.
    min_angle : float
        Target smallest angle of the quality triangulation (degrees).

    Returns
    -------
    FaceDecomposition

    Raises
    ------
    ResourceError
        If the rings have more than :data:`MAX_FACE_CORNERS` corners.
    DomainError
        If a face cannot be triangulated (rings nearly touching) or its blocks cannot be
        represented where the domain sits.

    Notes
    -----
    The triangulation's refinement is plain Python (about 20-40 microseconds per point added);
    the rest is whole-array work, O(N log N).
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    rings = [[np.asarray(r, dtype=np.int64) for r in face] for face in faces]
    total = sum(r.size for face in rings for r in face)
    if total > MAX_FACE_CORNERS:
        raise ResourceError(
            f"the parts have {total:,} corners; at most {MAX_FACE_CORNERS:,} are decomposed "
            "(simplify the outlines)"
        )
    frame = local_frame(points)
    local = frame.to_local(points)
    nodes, blocks, block_face, chains = _decompose_local(local, rings, min_angle)
    vertices = frame.to_global(nodes)
    vertices[: len(points)] = points
    _check_representable(vertices, blocks, frame, "the composite domain")
    angles = interior_angles(vertices[blocks])
    for array in (vertices, blocks, block_face, *(c for f in chains for r in f for c in r)):
        array.setflags(write=False)
    return FaceDecomposition(
        vertices=vertices,
        blocks=blocks,
        block_face=block_face,
        ring_chains=chains,
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
    )


def _decompose_local(
    points: np.ndarray, faces: list[list[np.ndarray]], min_angle: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple]:
    """:func:`decompose_faces` in local coordinates: nodes, blocks, block faces, ring chains."""
    ring_starts, ring_stops, edge_face = [], [], []
    for f, face in enumerate(faces):
        for ring in face:
            ring_starts.append(ring)
            ring_stops.append(np.roll(ring, -1))
            edge_face.append(np.full(ring.size, f))
    edge_a = np.concatenate(ring_starts)
    edge_b = np.concatenate(ring_stops)
    face_of_edge = np.concatenate(edge_face)
    triangles = []
    for face in faces:
        coords = [points[ring] for ring in face]
        ids = np.concatenate(face)
        triangles.append(ids[_constrained_triangles(coords, np.vstack(coords))])
    refiner = _Refiner(
        points, np.concatenate(triangles), edge_a, edge_b, sharp=_sharp_corners(points, faces)
    )
    if min_angle > 0:
        refiner.refine(min(float(min_angle), 33.0), 20 * len(points) + 2000)
    t = refiner.result()
    tri_face = _triangle_faces(t.triangles, t.segments, t.segment_edge, face_of_edge, len(t.points))
    quads, rest = [], []
    for f in range(len(faces)):
        q, r = pair_triangles(t.points, t.triangles[tri_face == f])
        quads.append(q)
        rest.append(r)
    pentagons = pentagons_from_pieces(t.points, [np.concatenate(rest), np.concatenate(quads)])
    piece_face = np.concatenate(
        [np.repeat(np.arange(len(faces)), [len(r) for r in rest]),
         np.repeat(np.arange(len(faces)), [len(q) for q in quads])]
    )  # fmt: skip
    nodes, blocks = pentagons.nodes, pentagons.blocks
    block_face = piece_face[pentagons.piece]
    # Chains along every ring edge: its segments in order, each with its two side nodes.
    segment_chains = pentagons.side_chains(t.segments[:, 0], t.segments[:, 1])
    start = points[edge_a[t.segment_edge]]
    direction = points[edge_b[t.segment_edge]] - start
    along = np.sum((t.points[t.segments[:, 0]] - start) * direction, axis=1)
    order = np.lexsort((along, t.segment_edge))
    bounds = np.searchsorted(t.segment_edge[order], np.arange(edge_a.size + 1))
    flat: list[np.ndarray] = []
    for edge in range(edge_a.size):
        run = segment_chains[order[bounds[edge] : bounds[edge + 1]]]
        flat.append(np.concatenate([run[:, :3].ravel(), run[-1:, 3]]))
    fixed = np.zeros(len(nodes), dtype=bool)
    fixed[: len(points)] = True
    slide = np.zeros((len(nodes), 2))
    for chain in flat:
        d = nodes[chain[-1]] - nodes[chain[0]]
        slide[chain[1:-1]] = d / math.hypot(*d)
    nodes = improve_angles(nodes, blocks, fixed, slide=slide)
    chains, k = [], 0
    for face in faces:
        per_ring = []
        for ring in face:
            per_ring.append(tuple(flat[k : k + ring.size]))
            k += ring.size
        chains.append(tuple(per_ring))
    return nodes, blocks, block_face, tuple(chains)


def _sharp_corners(points: np.ndarray, faces: list[list[np.ndarray]]) -> list[bool]:
    """Points where some face has a corner sharper than 60 degrees (left unrepaired there)."""
    sharp = np.zeros(len(points), dtype=bool)
    for face in faces:
        for ring in face:
            before, at, after = points[np.roll(ring, 1)], points[ring], points[np.roll(ring, -1)]
            u, w = before - at, after - at
            turn = np.degrees(
                np.arctan2(w[:, 0] * u[:, 1] - w[:, 1] * u[:, 0], np.sum(w * u, axis=1))
            )
            sharp[ring[np.mod(turn, 360.0) < 60.0]] = True
    return sharp.tolist()


def _triangle_faces(
    triangles: np.ndarray,
    segments: np.ndarray,
    segment_edge: np.ndarray,
    face_of_edge: np.ndarray,
    n_points: int,
) -> np.ndarray:
    """The face of every triangle: the pieces the segments cut the triangulation into."""
    n = triangles.shape[0]
    ahead = np.roll(triangles, -1, axis=1)
    directed = triangles * n_points + ahead  # (T, 3) keys of each triangle's edges
    reverse = ahead * n_points + triangles
    segment_keys = segments[:, 0] * n_points + segments[:, 1]
    order = np.argsort(directed, axis=None)
    flat = directed.ravel()[order]
    where = np.searchsorted(flat, reverse.ravel())
    where = np.minimum(where, flat.size - 1)
    matched = flat[where] == reverse.ravel()
    crossing = ~np.isin(directed.ravel(), segment_keys)
    link = matched & crossing
    rows = np.repeat(np.arange(n), 3)[link]
    cols = order[where[link]] // 3
    _, label = graph_components(n, rows, cols)
    # Each piece has a segment of its own face's rings on its boundary.
    at = np.searchsorted(flat, segment_keys)
    owner = order[at] // 3
    face_of_label = np.full(label.max() + 1, -1, dtype=np.int64)
    face_of_label[label[owner]] = face_of_edge[segment_edge]
    if np.any(face_of_label < 0):
        raise DomainError(
            "the parts could not be triangulated (a piece of the triangulation touches no ring); "
            "check the parts for nearly touching edges"
        )
    return face_of_label[label]
