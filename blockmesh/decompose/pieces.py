"""Convex pieces to pentagons: the ring-and-hub template on every piece, sides shared bit for bit.

A partition of a domain into convex pieces that meet side to side (a triangulation, triangles and
quadrilaterals of an existing mesh, or merged triangles) becomes a conforming mesh of strictly
convex pentagons when every piece is replaced by its ring-and-hub template
(:mod:`blockmesh.decompose.templates`): the two nodes of a side sit at the symmetric fractions
0.335645 / 0.664355 of it, whichever piece looks at it. Each side's nodes are computed once, from
the side's lower-numbered end, so both pieces get the same numbers and the same coordinates.

Examples
--------
>>> import numpy as np
>>> points = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> result = pentagons_from_pieces(points, [np.array([[0, 1, 2], [0, 2, 3]])])
>>> result.blocks.shape, result.nodes.shape  # 4 corners, 2 nodes on each of 5 sides, 2 x 10
((18, 5), (34, 2))
>>> result.side_chain(0, 1).tolist()  # along the side from corner 0 to corner 1
[0, 4, 5, 1]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.decompose.templates import EDGE_FRACTIONS, ring_hub_faces, ring_hub_nodes

__all__ = ["PiecePentagons", "pentagons_from_pieces"]


@dataclass(frozen=True)
class PiecePentagons:
    """The pentagons of a set of convex pieces.

    Attributes
    ----------
    nodes : ndarray (N, 2)
        The pieces' corners first (the input points, unchanged), then two nodes per side, then
        each piece's hub and inner nodes.
    blocks : ndarray (B, 5)
        Counter-clockwise pentagons, piece after piece (``3 n`` per n-gon), in the order of the
        groups and of the pieces within them.
    piece : ndarray (B,)
        The piece (numbered across the groups) each pentagon comes from.
    side_keys : ndarray (S,)
        The sides as sorted keys ``lo * K + hi`` of their corner ids (K input points).
    n_corners : int
        K, the number of input points.
    """

    nodes: np.ndarray
    blocks: np.ndarray
    piece: np.ndarray
    side_keys: np.ndarray
    n_corners: int

    def side_chain(self, a: int, b: int) -> np.ndarray:
        """Node ids along the side from corner ``a`` to corner ``b``: ``a``, two nodes, ``b``."""
        return self.side_chains(np.array([a]), np.array([b]))[0]

    def side_chains(self, starts: np.ndarray, stops: np.ndarray) -> np.ndarray:
        """The chains (E, 4) of many sides at once, as :meth:`side_chain`."""
        return _side_chains(self.side_keys, self.n_corners, starts, stops)


def _side_chains(keys: np.ndarray, k: int, starts: np.ndarray, stops: np.ndarray) -> np.ndarray:
    starts = np.asarray(starts, dtype=np.int64)
    stops = np.asarray(stops, dtype=np.int64)
    lo, hi = np.minimum(starts, stops), np.maximum(starts, stops)
    e = np.searchsorted(keys, lo * k + hi)
    first = k + 2 * e + (starts != lo)
    second = k + 2 * e + (starts == lo)
    return np.column_stack([starts, first, second, stops])


def pentagons_from_pieces(points: np.ndarray, groups: Sequence[np.ndarray]) -> PiecePentagons:
    """Replace every convex piece by its ring-and-hub template, conformingly.

    Parameters
    ----------
    points : ndarray (K, 2)
        The pieces' corners.
    groups : sequence of ndarray (P_g, n_g)
        Pieces with ``n_g`` corners each, counter-clockwise, strictly convex, meeting side to side
        (each side shared by at most two pieces, in opposite directions).

    Returns
    -------
    PiecePentagons

    Notes
    -----
    O(K + sum of P_g n_g) with whole-array operations, one pass per group.
    """
    points = np.asarray(points, dtype=np.float64)
    k = points.shape[0]
    groups = [np.asarray(g, dtype=np.int64).reshape(len(g), -1) for g in groups if len(g)]
    starts = np.concatenate([g.ravel() for g in groups]) if groups else np.zeros(0, np.int64)
    stops = (
        np.concatenate([np.roll(g, -1, axis=1).ravel() for g in groups])
        if groups
        else np.zeros(0, np.int64)
    )
    keys = np.unique(np.minimum(starts, stops) * k + np.maximum(starts, stops))
    lo, hi = np.divmod(keys, k)
    f1, f2 = EDGE_FRACTIONS
    step = points[hi] - points[lo]
    side_nodes = np.stack([points[lo] + f1 * step, points[lo] + f2 * step], axis=1)
    nodes = [points, side_nodes.reshape(-1, 2)]
    blocks, piece = [], []
    next_id = k + 2 * keys.size
    first_piece = 0
    for g in groups:
        count, n = g.shape
        ahead = np.roll(g, -1, axis=1)
        chains = _side_chains(keys, k, g.ravel(), ahead.ravel()).reshape(count, n, 4)
        ids = np.empty((count, 6 * n + 1), dtype=np.int64)
        ids[:, :n] = g
        ids[:, n : 3 * n] = chains[:, :, 1:3].reshape(count, 2 * n)
        ids[:, 3 * n :] = next_id + np.arange(count * (3 * n + 1)).reshape(count, 3 * n + 1)
        next_id += count * (3 * n + 1)
        sides = np.concatenate([nodes[0], nodes[1]])[chains[:, :, 1:3]]
        placed = ring_hub_nodes(points[g], sides)
        nodes.append(placed[:, 3 * n :].reshape(-1, 2))
        faces = ring_hub_faces(n)
        blocks.append(ids[:, faces].reshape(-1, 5))
        piece.append(np.repeat(first_piece + np.arange(count), faces.shape[0]))
        first_piece += count
    return PiecePentagons(
        nodes=np.concatenate(nodes),
        blocks=np.concatenate(blocks) if blocks else np.zeros((0, 5), np.int64),
        piece=np.concatenate(piece) if piece else np.zeros(0, np.int64),
        side_keys=keys,
        n_corners=k,
    )
