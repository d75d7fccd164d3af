"""Move the free nodes of a block mesh to raise its worst angle; every block stays strictly convex.

The blocks of a decomposition are placed by fixed template weights; moving the nodes that are not
fixed by the domain improves the worst corners. A block's *score* is its worst corner, measured as
``min(theta, 1.5 (180 - theta))`` (so 30 and 160 degrees score alike: sharp and flat corners are
equally bad, and a regular pentagon's 108 degrees is about the balance point); a node's score is
the worst score of the blocks around it.

Only nodes whose score is below ``target`` are worked on (few, in a mesh from a quality
triangulation). Each sweep tries, for each of them, a step to the mean of its neighbours along
block edges and steps of a fraction of its shortest edge in six directions, and keeps the best
move that raises the node's score while every block around it stays strictly convex; a node that
finds nothing halves its step, and after two such sweeps is left alone. Nodes on the domain
boundary that are not corners may slide along their boundary line; corners and nodes marked fixed
never move. Nodes are moved in independent sets (no two in one block), so that every acceptance
test sees exactly the blocks it changes; each set is one whole-array step.

Examples
--------
>>> import numpy as np
>>> from blockmesh.decompose.templates import ring_hub_faces, ring_hub_nodes
>>> quad = np.array([[0, 0], [3, 0], [3, 1], [0, 1]], dtype=float)
>>> nodes, faces = ring_hub_nodes(quad[None])[0], ring_hub_faces(4)
>>> fixed = np.zeros(len(nodes), dtype=bool)
>>> fixed[:12] = True  # corners and side nodes stay
>>> better = improve_angles(nodes, faces, fixed)
>>> bool(worst_score(better, faces) > worst_score(nodes, faces) + 5)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.refinement.placement import Freedom, Placement

__all__ = ["WorstAngle", "improve_angles", "worst_score"]

#: Weight of flat corners against sharp ones in the score (``min(theta, 1.5 (180 - theta))``).
_FLAT_WEIGHT = 1.5
#: A kept block keeps every corner turning by at least this sine (a margin above the
#: strict-convexity tolerance, so that mapping back to global coordinates cannot undo it).
_SINE_MARGIN = 1e3 * COLLINEAR_SIN_TOL
#: A kept block keeps every edge longer than this times its largest coordinate (in size): so
#: long that rounding its ends (an ulp each) turns it by less than the sine margin. The corner
#: test alone cannot see an edge collapse: a node stepped onto its neighbour leaves an edge an
#: ulp long whose direction (its coordinates' difference) is still the old one, so both of its
#: corners still turn and score as before, while the block is a quadrilateral with one point
#: twice (an edge 1e-17 long failed the global checks as a fold or a repeated point).
_EDGE_MARGIN = float(np.finfo(np.float64).eps) / _SINE_MARGIN
_DIRECTIONS = np.exp(2j * np.pi * np.arange(6) / 6)
#: A node that finds no better position this many times is left where it is.
_GIVE_UP = 2


#: With sizes asked, a block's diameter over its size scores like a corner: the target at
#: ``_SIZE_OK`` and below, falling to ``_SIZE_SCORE`` at ``_SIZE_LIMIT``, then slowly further
#: (so a block too large is shrunk at the cost of corners down to about that score, no lower).
_SIZE_OK, _SIZE_LIMIT, _SIZE_SCORE = 1.35, 1.5, 26.0
#: The ten pairs of a pentagon's corners (its diameter is the longest of them).
_PAIRS = np.triu_indices(5, 1)


def _block_scores(
    points: np.ndarray,
    blocks: np.ndarray,
    sizes: np.ndarray | None = None,
    target: float = 38.0,
    limits: np.ndarray | None = None,
) -> np.ndarray:
    """Score of each block; ``-inf`` where a corner turns too little or an edge is too short.

    A block is kept only when every corner turns by the sine margin and every edge is longer
    than the edge margin times its largest coordinate (see ``_EDGE_MARGIN``). The score needs
    only the sharpest and the flattest corner, so it is computed from their cosines: two
    arccosines per block instead of five angles. With ``sizes`` (the size asked
    of each block), a block whose diameter passes ``_SIZE_OK`` times its size scores lower too
    (see ``_SIZE_SCORE``). With ``limits`` (the largest diameter allowed of each block), a
    block beyond its limit scores ``-inf``, as a folded one does.
    """
    xy = points[blocks]
    incoming = xy - xy[:, [4, 0, 1, 2, 3]]
    outgoing = xy[:, [1, 2, 3, 4, 0]] - xy
    cross = incoming[..., 0] * outgoing[..., 1] - incoming[..., 1] * outgoing[..., 0]
    dot = incoming[..., 0] * outgoing[..., 0] + incoming[..., 1] * outgoing[..., 1]
    lengths = np.hypot(outgoing[..., 0], outgoing[..., 1])
    norms = lengths[:, [4, 0, 1, 2, 3]] * lengths
    convex = np.all(cross > _SINE_MARGIN * norms, axis=1) & (
        lengths.min(axis=1) > _EDGE_MARGIN * np.abs(xy).max(axis=(1, 2))
    )
    # The interior angle is 180 degrees minus the turn; its cosine is -dot / norms.
    with np.errstate(invalid="ignore", divide="ignore"):
        cosine = -dot / norms
    sharpest = np.degrees(np.arccos(np.clip(np.nanmax(cosine, axis=1), -1.0, 1.0)))
    flattest = np.degrees(np.arccos(np.clip(np.nanmin(cosine, axis=1), -1.0, 1.0)))
    score = np.minimum(sharpest, _FLAT_WEIGHT * (180.0 - flattest))
    if sizes is not None or limits is not None:
        diff = xy[:, _PAIRS[0]] - xy[:, _PAIRS[1]]
        diameter = np.sqrt(np.max(diff[..., 0] ** 2 + diff[..., 1] ** 2, axis=1))
    if limits is not None:
        convex &= diameter <= limits
    if sizes is not None:
        ratio = diameter / sizes
        falling = (target - _SIZE_SCORE) / (_SIZE_LIMIT - _SIZE_OK)
        size_score = np.where(
            ratio <= _SIZE_LIMIT,
            target - falling * np.maximum(ratio - _SIZE_OK, 0.0),
            _SIZE_SCORE - 10.0 * (ratio - _SIZE_LIMIT),
        )
        score = np.minimum(score, size_score)
    return np.where(convex, score, -np.inf)


def worst_score(points: np.ndarray, blocks: np.ndarray) -> float:
    """The worst corner score of any block (see the module notes), in degrees."""
    return float(_block_scores(points, blocks).min()) if len(blocks) else np.inf


def improve_angles(
    points: np.ndarray,
    blocks: np.ndarray,
    fixed: np.ndarray,
    *,
    slide: np.ndarray | None = None,
    target: float = 38.0,
    sweeps: int = 5,
    sizes: np.ndarray | None = None,
    limits: np.ndarray | None = None,
) -> np.ndarray:
    """Return new node positions with a better worst angle around every moved node.

    Parameters
    ----------
    points : ndarray (N, 2)
        Node positions (local coordinates recommended).
    blocks : ndarray (B, 5)
        Counter-clockwise strictly convex blocks.
    fixed : ndarray (N,) bool
        Nodes that must not move.
    slide : ndarray (N, 2), optional
        For nodes that may move only along a line (boundary nodes), the line's unit direction;
        rows of zeros for nodes that move freely.
    target : float
        Nodes scoring at least this (degrees) are left alone.
    sweeps : int
        Most passes over the nodes below target.
    sizes : ndarray (B,), optional
        The diameter asked of each block: blocks larger than 1.35 times it score lower (as a
        26-degree corner at 1.5 times), so nodes move to shrink them while the angles allow.
    limits : ndarray (B,), optional
        The largest diameter allowed of each block: no node moves so that a block passes it
        (a block already beyond it keeps its nodes where they are).

    Returns
    -------
    ndarray (N, 2)
        The improved positions (a new array). No node moves so that a block stops being strictly
        convex or the worst corner around the node gets worse.

    Notes
    -----
    O(B) to set up, then O(k) per sweep for the k blocks around the nodes below target.
    """
    points = np.array(points, dtype=np.float64)
    blocks = np.asarray(blocks, dtype=np.int64)
    n = points.shape[0]
    if not len(blocks):
        return points
    sizes = None if sizes is None else np.asarray(sizes, dtype=np.float64)
    limits = None if limits is None else np.asarray(limits, dtype=np.float64)
    score = _block_scores(points, blocks, sizes, target, limits)
    corner_of = blocks.ravel()
    node_score = np.full(n, np.inf)
    np.minimum.at(node_score, corner_of, np.repeat(score, 5))
    active = ~np.asarray(fixed, dtype=bool) & (node_score < target)
    if not active.any():
        return points
    # Blocks around each node (CSR by node), and neighbours along block edges.
    order = np.argsort(corner_of, kind="stable")
    block_of = order // 5
    first = np.searchsorted(corner_of[order], np.arange(n))
    count = np.bincount(corner_of, minlength=n)
    # Neighbours only of the nodes that may move: the block edges of the blocks around them.
    near_blocks = blocks[np.unique(block_of[_ranges(first[active], count[active])])]
    tail = near_blocks.ravel()
    ahead = np.roll(near_blocks, -1, axis=1).ravel()
    pairs = np.unique(np.concatenate([tail * n + ahead, ahead * n + tail]))
    src, dst = np.divmod(pairs, n)
    degree = np.bincount(src, minlength=n)
    near_from = np.searchsorted(src, np.arange(n))
    direction = None if slide is None else np.asarray(slide, dtype=np.float64)
    nodes_all = np.flatnonzero(active)
    shortest = _shortest_edges(points, nodes_all, dst, near_from, degree)
    step_size = np.zeros(n)
    step_size[nodes_all] = 0.25 * shortest
    failures = np.zeros(n, dtype=np.int64)
    for _ in range(sweeps):
        improved = False
        for nodes in _independent_sets(blocks, active, block_of, first, count, n):
            if _sweep_set(
                points, blocks, score, nodes, block_of, first, count, dst, near_from, degree,
                direction, step_size, failures, sizes, target, limits,
            ):  # fmt: skip
                improved = True
        if not improved:
            break
        node_score = np.full(n, np.inf)
        np.minimum.at(node_score, corner_of, np.repeat(score, 5))
        active &= (node_score < target) & (failures < _GIVE_UP)
        if not active.any():
            break
    return points


@dataclass(frozen=True)
class WorstAngle(Placement):
    """The decomposition's optimiser as a node placement: :func:`improve_angles` on every node.

    With ``sizes`` (the diameter asked of each cell), cells beyond 1.3 times their size count as
    bad corners do; with ``limits`` (the largest diameter allowed of each cell), no cell grows
    past it (see :func:`improve_angles`).

    Examples
    --------
    With every cell's diameter held within a tenth of what it was:

    >>> import numpy as np
    >>> from blockmesh.decompose.templates import ring_hub_faces, ring_hub_nodes
    >>> from blockmesh.sizing.measure import cell_diameters
    >>> quad = np.array([[0, 0], [2, 0], [2, 1], [0, 1]], dtype=float)
    >>> nodes, faces = ring_hub_nodes(quad[None])[0], ring_hub_faces(4)
    >>> held = Freedom(np.arange(len(nodes)) < 12, np.zeros_like(nodes))
    >>> limits = 1.1 * cell_diameters(nodes, faces)
    >>> moved = WorstAngle(target=60.0, limits=limits).place(nodes, faces, held)
    >>> bool(worst_score(moved, faces) > worst_score(nodes, faces) + 20)
    True
    >>> bool(np.all(cell_diameters(moved, faces) <= limits))
    True
    """

    target: float = 38.0
    sweeps: int = 5
    sizes: np.ndarray | None = None
    limits: np.ndarray | None = None
    name: ClassVar[str] = "worst-angle"
    nested: ClassVar[bool] = False

    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:
        """New positions with a better worst angle around every node that moved."""
        return improve_angles(
            points,
            cells,
            freedom.fixed,
            slide=freedom.slide,
            target=self.target,
            sweeps=self.sweeps,
            sizes=self.sizes,
            limits=self.limits,
        )


def _sweep_set(
    points, blocks, score, nodes, block_of, first, count, dst, near_from, degree, direction,
    step_size, failures, sizes=None, target=38.0, limits=None,
) -> bool:  # fmt: skip
    """Try every candidate move of an independent set of nodes; keep the best improving one."""
    slots = _ranges(first[nodes], count[nodes])
    around = block_of[slots]
    owner = np.repeat(np.arange(nodes.size), count[nodes])
    before = np.full(nodes.size, np.inf)
    np.minimum.at(before, owner, score[around])
    near = dst[_ranges(near_from[nodes], degree[nodes])]
    whose = np.repeat(np.arange(nodes.size), degree[nodes])
    mean = (
        np.column_stack(
            [np.bincount(whose, weights=points[near, k], minlength=nodes.size) for k in (0, 1)]
        )
        / np.maximum(degree[nodes], 1)[:, None]
    )
    h = step_size[nodes][:, None]
    moves = [mean - points[nodes], 0.5 * (mean - points[nodes])]
    moves += [h * [d.real, d.imag] for d in _DIRECTIONS]
    best_gain = np.zeros(nodes.size)
    best_move = np.zeros((nodes.size, 2))
    best_scores = None
    start = points[nodes].copy()
    for move in moves:
        if direction is not None:
            d = direction[nodes]
            sliding = np.any(d != 0, axis=1)
            move = np.where(sliding[:, None], np.sum(move * d, axis=1)[:, None] * d, move)
        points[nodes] = start + move
        trial = _block_scores(
            points,
            blocks[around],
            None if sizes is None else sizes[around],
            target,
            None if limits is None else limits[around],
        )
        after = np.full(nodes.size, np.inf)
        np.minimum.at(after, owner, trial)
        with np.errstate(invalid="ignore"):
            gain = np.nan_to_num(after - before, nan=0.0)  # -inf to -inf: no gain
        better = gain > np.maximum(best_gain, 1e-9)
        if better.any():
            best_gain[better] = gain[better]
            best_move[better] = move[better]
            keep = better[owner]
            best_scores = trial if best_scores is None else np.where(keep, trial, best_scores)
    moved = best_gain > 0
    points[nodes] = start + np.where(moved[:, None], best_move, 0.0)
    if moved.any():
        keep = moved[owner]
        score[around[keep]] = best_scores[keep]  # type: ignore[index]
    step_size[nodes[~moved]] *= 0.5
    failures[nodes[~moved]] += 1
    return bool(moved.any())


def _shortest_edges(points, nodes, dst, near_from, degree) -> np.ndarray:
    near = dst[_ranges(near_from[nodes], degree[nodes])]
    whose = np.repeat(np.arange(nodes.size), degree[nodes])
    length = np.hypot(*(points[near] - points[nodes[whose]]).T)
    shortest = np.full(nodes.size, np.inf)
    np.minimum.at(shortest, whose, length)
    return shortest


def _ranges(starts: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """``starts[i] .. starts[i] + lengths[i] - 1`` for every i, concatenated."""
    offsets = np.repeat(starts - np.cumsum(lengths) + lengths, lengths)
    return offsets + np.arange(int(lengths.sum()))


def _independent_sets(blocks, active, block_of, first, count, n) -> list[np.ndarray]:
    """Split the active nodes into sets with no two nodes in one block (greedy, whole-array).

    Round by round, a node joins the current set when its priority is the highest among the
    unassigned active nodes of every block around it; priorities are a fixed function of the node
    id, so the split is deterministic.
    """
    priority = ((np.arange(n, dtype=np.uint64) * np.uint64(2654435761)) % np.uint64(2**32)).astype(
        np.float64
    )
    left = active.copy()
    sets = []
    nodes = np.flatnonzero(left)
    slots = _ranges(first[nodes], count[nodes])
    touched = np.unique(block_of[slots])
    sub = blocks[touched]
    while left.any():
        live = np.where(left[sub], priority[sub], -1.0)
        top = live.max(axis=1)
        best = np.full(n, -1.0)
        np.maximum.at(best, sub.ravel(), np.repeat(top, 5))
        chosen = np.flatnonzero(left & (priority >= best))
        sets.append(chosen)
        left[chosen] = False
    return sets
