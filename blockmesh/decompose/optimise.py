"""Move the free nodes of a block mesh to raise its worst angle; every block stays strictly convex.

The blocks of a decomposition are placed by fixed template weights; moving the nodes that are not
fixed by the domain improves the worst corners. A node's *score* is the worst corner of the blocks
around it, measured as ``min(theta, 1.5 (180 - theta))`` (so 30 and 160 degrees score alike:
sharp and flat corners are equally bad, and a regular pentagon's 108 degrees is the balance
point). Each sweep tries, for every free node, a step towards the mean of its neighbours along
block edges (full, then half, then a quarter); a move is kept only if every block around the node
stays strictly convex and the node's score rises. Nodes on the domain boundary that are not
corners may slide along their boundary line; corners and nodes marked fixed never move.

Nodes are moved in independent sets (no two in one block), so that every acceptance test sees
exactly the blocks it changes; each set is one whole-array step.

Examples
--------
>>> import numpy as np
>>> from blockmesh.decompose.templates import ring_hub_faces, ring_hub_nodes
>>> quad = np.array([[0, 0], [3, 0], [3, 1], [0, 1]], dtype=float)
>>> nodes, faces = ring_hub_nodes(quad[None])[0], ring_hub_faces(4)
>>> fixed = np.zeros(len(nodes), dtype=bool)
>>> fixed[:12] = True  # corners and side nodes stay
>>> better = improve_angles(nodes, faces, fixed)
>>> bool(worst_score(better, faces) > worst_score(nodes, faces))
True
"""

from __future__ import annotations

import numpy as np

from ..geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles

__all__ = ["improve_angles", "worst_score"]

#: Weight of flat corners against sharp ones in the score (``min(theta, 1.5 (180 - theta))``).
_FLAT_WEIGHT = 1.5
#: A kept block must keep every corner turning by at least this sine (a margin above the
#: strict-convexity tolerance, so that mapping back to global coordinates cannot undo it).
_SINE_MARGIN = 1e3 * COLLINEAR_SIN_TOL
_STEPS = (1.0, 0.5, 0.25)


def _block_scores(points: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    xy = points[blocks]
    angles = interior_angles(xy)
    score = np.minimum(angles, _FLAT_WEIGHT * (180.0 - angles)).min(axis=1)
    convex = np.all(corner_sines(xy) > _SINE_MARGIN, axis=1)
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
    sweeps: int = 6,
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
    sweeps : int
        Passes over all nodes.

    Returns
    -------
    ndarray (N, 2)
        The improved positions (a new array); nodes never move so that a block stops being
        strictly convex or the worst corner around the node gets worse.

    Notes
    -----
    O(sweeps * B) with whole-array steps over independent sets of nodes.
    """
    points = np.array(points, dtype=np.float64)
    blocks = np.asarray(blocks, dtype=np.int64)
    n = points.shape[0]
    movable = ~np.asarray(fixed, dtype=bool)
    if not movable.any() or not len(blocks):
        return points
    # Neighbours along block edges, as a CSR-like pair list (each undirected edge once per side).
    a = blocks.ravel()
    b = np.roll(blocks, -1, axis=1).ravel()
    pairs = np.unique(np.concatenate([a * n + b, b * n + a]))
    src, dst = np.divmod(pairs, n)
    degree = np.bincount(src, minlength=n)
    neighbours_from = np.searchsorted(src, np.arange(n))
    # Blocks around each node.
    order = np.argsort(a, kind="stable")
    node_of_slot = a[order]
    block_of_slot = order // 5
    first = np.searchsorted(node_of_slot, np.arange(n))
    count = np.bincount(a, minlength=n)
    colours = _independent_sets(blocks, movable, n)
    direction = None if slide is None else np.asarray(slide, dtype=np.float64)
    score = _block_scores(points, blocks)
    for _ in range(sweeps):
        moved_any = False
        for nodes in colours:
            near = dst[_slots_of(nodes, neighbours_from, degree)]
            whose = np.repeat(np.arange(nodes.size), degree[nodes])
            mean = (
                np.column_stack(
                    [
                        np.bincount(whose, weights=points[near, axis], minlength=nodes.size)
                        for axis in (0, 1)
                    ]
                )
                / np.maximum(degree[nodes], 1)[:, None]
            )
            step = mean - points[nodes]
            if direction is not None:
                d = direction[nodes]
                along = np.sum(step * d, axis=1)
                sliding = np.any(d != 0, axis=1)
                step = np.where(sliding[:, None], along[:, None] * d, step)
            slots = _slots_of(nodes, first, count)
            around = block_of_slot[slots]
            owner = np.repeat(np.arange(nodes.size), count[nodes])
            before = np.full(nodes.size, np.inf)
            np.minimum.at(before, owner, score[around])
            pending = np.ones(nodes.size, dtype=bool)
            for factor in _STEPS:
                if not pending.any():
                    break
                trial = points.copy()
                trial[nodes[pending]] += factor * step[pending]
                new_scores = _block_scores(trial, blocks[around])
                after = np.full(nodes.size, np.inf)
                np.minimum.at(after, owner, new_scores)
                accept = pending & (after > before + 1e-9)
                if accept.any():
                    points[nodes[accept]] = trial[nodes[accept]]
                    keep = accept[owner]
                    score[around[keep]] = new_scores[keep]
                    moved_any = True
                pending &= ~accept
        if not moved_any:
            break
    return points


def _slots_of(nodes: np.ndarray, first: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Positions ``first[v] .. first[v] + count[v] - 1`` for every ``v`` in ``nodes``, in order."""
    lengths = count[nodes]
    starts = np.repeat(first[nodes] - np.cumsum(lengths) + lengths, lengths)
    return starts + np.arange(lengths.sum())


def _independent_sets(blocks: np.ndarray, movable: np.ndarray, n: int) -> list[np.ndarray]:
    """Split the movable nodes into sets with no two nodes in one block (greedy, whole-array).

    Round by round, a node joins the current set when its priority is the highest among the
    unassigned nodes of every block around it; priorities come from a fixed-seed generator, so
    the split is deterministic.
    """
    rng = np.random.default_rng(12345)
    priority = rng.permutation(n).astype(np.float64)
    left = movable.copy()
    sets = []
    while left.any():
        live = np.where(left[blocks], priority[blocks], -1.0)
        top = live.max(axis=1)
        best = np.full(n, -1.0)
        np.maximum.at(best, blocks.ravel(), np.repeat(top, 5))
        chosen = np.flatnonzero(left & (priority >= best))
        sets.append(chosen)
        left[chosen] = False
    return sets
