"""The paper's global numbering of a refined block mesh, block by block, from prefix sums.

The paper's walk numbers, level by level, the new nodes of every cell in order; the cells of a
refined block mesh are block-major at every level (block b owns cells ``b 6^l .. (b+1) 6^l - 1``),
so the nodes new at level ``l`` are grouped by block: block 0's, then block 1's, and so on.
Within a block they come in the order of the refined reference pentagon
(:mod:`blockmesh.template`), except that the nodes inside a block edge shared with a lower
block were numbered by that block. A level-``l`` refinement adds ``2^(l-1)`` nodes inside each
block edge, so

    count(l, b) = n_l - n_(l-1) - (edges of b numbered by a lower block) 2^(l-1)

and the first id block b gives out at level l is a prefix sum of these counts
(:class:`RefinementPlan`). From the plan alone, without the other blocks' arrays, any block's
node ids (:func:`block_node_ids`) and the ids along any block edge (:func:`edge_node_ids`)
follow in O(n_L) and O(2^L log 2^L): this is what lets each block, or each worker of a
distributed run, work on its own.

Coordinates are the paper's arithmetic level by level (:func:`place_level`); the nodes inside a
shared edge are midpoints of midpoints of the edge's two corners, which both blocks compute bit
for bit alike (addition commutes in floating point).

Examples
--------
>>> import blockmesh
>>> from blockmesh.topology import cell_neighbours
>>> base = blockmesh.load_domain("joined-2").block_mesh()
>>> plan = plan_refinement(base.cells, cell_neighbours(base.cells, base.n_points),
...                        base.n_points, 2)
>>> plan.n_nodes == blockmesh.refine(base, 2).n_points
True
>>> plan.counts.tolist()  # new nodes per level (rows) and block (columns)
[[0, 0], [10, 9], [50, 48]]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .template import PentagonTemplate, node_count, pentagon_template

__all__ = [
    "PLACE_CHUNK",
    "RefinementPlan",
    "block_node_ids",
    "edge_node_ids",
    "place_block",
    "place_level",
    "plan_refinement",
]


@dataclass(frozen=True)
class RefinementPlan:
    """Where each block's nodes go in the global numbering of a refinement (small arrays only).

    Attributes
    ----------
    steps : int
        Levels of refinement.
    cells : ndarray (B, 5) int64
        The base cells (blocks) and their node ids.
    neighbour : ndarray (B, 5) int64
        Slot ``5 c + e`` of the same edge in the cell across edge e, or -1 on the boundary.
    taken : ndarray (B, 5) bool
        Edges whose inner nodes a lower-numbered cell numbers.
    offsets, counts : ndarray (steps + 1, B) int64
        The first global id and the number of ids block b gives out at level l (row 0 unused).
    n_base_points : int
    n_nodes : int
        Nodes of the refined mesh.
    """

    steps: int
    cells: np.ndarray
    neighbour: np.ndarray
    taken: np.ndarray
    offsets: np.ndarray
    counts: np.ndarray
    n_base_points: int
    n_nodes: int

    @property
    def n_blocks(self) -> int:
        """Number of base cells B."""
        return int(self.cells.shape[0])

    def nodes_of_block(self, block: int) -> int:
        """Ids block ``block`` gives out over all levels (its corners excluded)."""
        return int(self.counts[1:, block].sum())


def plan_refinement(
    cells: np.ndarray, neighbour: np.ndarray, n_points: int, steps: int
) -> RefinementPlan:
    """The numbering plan of ``steps`` levels of refinement of the base ``cells``. O(B steps).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 3)
    >>> plan.n_nodes, plan.offsets[1:, 0].tolist()
    (345, [5, 15, 65])
    """
    cells = np.asarray(cells, dtype=np.int64)
    neighbour = np.asarray(neighbour, dtype=np.int64)
    n_blocks = cells.shape[0]
    row = np.arange(n_blocks)[:, None]
    taken = (neighbour >= 0) & (neighbour < 5 * row)
    n_taken = taken.sum(axis=1)
    counts = np.zeros((steps + 1, n_blocks), dtype=np.int64)
    for level in range(1, steps + 1):
        counts[level] = node_count(level) - node_count(level - 1) - n_taken * 2 ** (level - 1)
    flat = counts[1:].ravel()
    offsets = np.zeros_like(counts)
    offsets[1:] = (n_points + np.cumsum(flat) - flat).reshape(steps, n_blocks)
    return RefinementPlan(
        steps, cells, neighbour, taken, offsets, counts, int(n_points), int(n_points + flat.sum())
    )


def _level_bounds(steps: int) -> np.ndarray:
    return np.array([node_count(level) for level in range(steps + 1)], dtype=np.int64)


def edge_node_ids(plan: RefinementPlan, block: int, edge: int) -> np.ndarray:
    """Global ids of the ``2^L + 1`` nodes along edge ``edge`` of ``block``, corner to corner.

    Computed from the plan alone: for an edge the block numbers itself, each node's id is its
    block's offset at its level plus its rank among the nodes the block numbers at that level;
    for an edge a lower block numbered, that block's ids read backwards.

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 1)
    >>> edge_node_ids(plan, 0, 0).tolist()
    [0, 5, 1]
    """
    if plan.taken[block, edge]:
        lower, lower_edge = divmod(int(plan.neighbour[block, edge]), 5)
        return edge_node_ids(plan, lower, lower_edge)[::-1].copy()
    level, rank = _edge_ranks(plan.steps, edge, tuple(plan.taken[block].tolist()))
    ids = np.empty(rank.size + 2, dtype=np.int64)
    ids[0] = plan.cells[block, edge]
    ids[-1] = plan.cells[block, (edge + 1) % 5]
    ids[1:-1] = plan.offsets[level, block] + rank
    return ids


@lru_cache(maxsize=256)
def _edge_ranks(steps: int, edge: int, taken: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Level and rank among the block's own new nodes of that level, of each node inside ``edge``.

    Depends only on the template and on which edges (``taken``) a lower block numbers, so it is
    computed once per combination (2^steps - 1 entries each).
    """
    template = pentagon_template(steps)
    inner = template.edge_nodes[edge][1:-1]
    bounds = _level_bounds(steps)
    level = np.searchsorted(bounds, inner, side="right")
    first = bounds[level - 1]
    skipped = np.zeros(inner.size, dtype=np.int64)
    for other in np.flatnonzero(taken):
        nodes = np.sort(template.edge_nodes[other][1:-1])
        skipped += np.searchsorted(nodes, inner) - np.searchsorted(nodes, first)
    rank = (inner - first) - skipped
    level.setflags(write=False)
    rank.setflags(write=False)
    return level, rank


def block_node_ids(
    plan: RefinementPlan, block: int, out: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Global ids of every template node of ``block`` (n_L,), and which ones the block numbers.

    ``out`` (n_L,) int64 is filled and returned when given (reused buffers save page faults).
    O(n_L).

    Examples
    --------
    >>> import numpy as np
    >>> plan = plan_refinement(np.arange(5)[None], np.full((1, 5), -1), 5, 2)
    >>> ids, own = block_node_ids(plan, 0)
    >>> bool(np.array_equal(ids, np.arange(65))), int(own.sum())
    (True, 60)
    """
    template = pentagon_template(plan.steps)
    n_local = template.n_nodes
    ids = np.empty(n_local, dtype=np.int64) if out is None else out
    own = np.ones(n_local, dtype=bool)
    own[:5] = False
    taken = np.flatnonzero(plan.taken[block])
    for edge in taken:
        own[template.edge_nodes[edge][1:-1]] = False
    np.cumsum(own, out=ids)
    bounds = _level_bounds(plan.steps)
    # Finest level first: each level reads the plain count just below its range.
    for level in range(plan.steps, 0, -1):
        lo, hi = int(bounds[level - 1]), int(bounds[level])
        ids[lo:hi] += plan.offsets[level, block] - 1 - ids[lo - 1]
    ids[:5] = plan.cells[block]
    for edge in taken:
        ids[template.edge_nodes[edge]] = edge_node_ids(plan, block, int(edge))
    return ids, own


#: Parent cells processed at once by :func:`place_level`: small enough for the temporaries to
#: stay in the CPU caches, large enough for numpy's per-call overhead not to matter.
PLACE_CHUNK = 8192


def place_level(local: np.ndarray, step, lo: int) -> None:
    """Coordinates of the nodes new at one level, in every block's local numbering.

    ``local`` holds one complex128 per local node and block, shape (B, n_L) (a point ``(x, y)`` as
    ``x + iy``, which makes gathers and scatters several times faster than on (N, 2) rows). The
    arithmetic runs on the float64 view, corner-major, and is the paper's:
    ``u = (v_i + v_i+1) / 2``, ``p = (v1 + v2 + v3 + v4 + v5) / 5``, ``w = (u + p) / 2``; so the
    results are bit for bit those of the paper's program. Parent cells go in chunks whose new
    nodes are a contiguous run of the output, so the temporaries stay in cache.
    """
    n_blocks = local.shape[0]
    n_parents = step.corners.shape[1]
    for j0 in range(0, n_parents, PLACE_CHUNK):
        j1 = min(j0 + PLACE_CHUNK, n_parents)
        # (B, 5, 2c): corner-major, x/y interleaved. The template's indices are valid by
        # construction; mode="clip" skips numpy's bounds check, which costs more than the gather.
        corners = np.take(local, step.corners[:, j0:j1], axis=1, mode="clip").view(np.float64)
        p = corners[:, 0] + corners[:, 1]
        p += corners[:, 2]
        p += corners[:, 3]
        p += corners[:, 4]
        p /= 5
        new = np.empty((n_blocks, 2, *corners.shape[1:]), dtype=np.float64)  # [u, w]
        u, w = new[:, 0], new[:, 1]
        np.add(corners[:, :4], corners[:, 1:], out=u[:, :4])
        np.add(corners[:, 4], corners[:, 0], out=u[:, 4])
        u *= 0.5  # exact, as / 2
        np.add(u, p[:, None, :], out=w)
        w *= 0.5
        # Slot 10 j + k of the chunk: u_k (k < 5) or w_(k-5) of parent j0 + j.
        slots = np.ascontiguousarray(
            new.view(np.complex128).reshape(n_blocks, 10, -1).swapaxes(1, 2)
        )
        first, last = np.searchsorted(step.source, (10 * j0, 10 * j1))
        np.take(
            slots.reshape(n_blocks, -1),
            step.source[first:last] - 10 * j0,
            axis=1,
            out=local[:, lo + first : lo + last],
            mode="clip",
        )


def place_block(
    template: PentagonTemplate,
    corners: np.ndarray,
    out: np.ndarray,
    after_level: Callable[[np.ndarray, int], None] | None = None,
) -> np.ndarray:
    """Coordinates (complex128) of all template nodes of one block with ``corners`` (5,) complex.

    ``out`` (n_L,) complex128 is filled and returned. O(n_L), the paper's arithmetic.
    ``after_level(out, level)``, when given, runs after each level and may change that level's
    nodes in place (the curve-aware rule of :class:`blockmesh.curved_refinement.CurvedBlocks`).
    """
    out[:5] = corners
    view = out[None, :]
    for level in range(1, template.level + 1):
        place_level(view, template.steps[level - 1], node_count(level - 1))
        if after_level is not None:
            after_level(out, level)
    return out
