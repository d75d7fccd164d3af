"""Refinement of a block mesh a group of blocks at a time, on worker threads.

The numbering plan (:mod:`blockmesh.refinement.plan`) tells every block where its nodes go without
looking at any other block, so blocks are refined independently and written straight into the
output arrays, each into its own ranges: a block's cells, and at every level a contiguous run of
node ids. Consecutive blocks give consecutive runs, so a *group* of consecutive blocks is one
run per level too, and small blocks are refined a group at a time with whole-array operations
over ``(G, n_L)`` arrays (G blocks of ``n_L`` template nodes), which keeps the per-call overhead
of numpy negligible and the working arrays in the CPU caches.

Groups are handed to worker threads (:func:`blockmesh._system.threads.run_parallel`; numpy releases
the interpreter lock inside its loops) while another thread populates the output's pages
(:mod:`blockmesh._system.prefault`): on two cores, two workers and that thread beat one worker by
about 13 % over the catalogue. Every group writes what it alone owns, so the result is the same bit
for bit whatever the number of threads.

Examples
--------
>>> import blockmesh
>>> from blockmesh.geometry.topology import cell_neighbours
>>> base = blockmesh.load_domain("joined-2").block_mesh()
>>> out = refine_blocks(base, cell_neighbours(base.cells, base.n_points), 2, threads=2)
>>> out.cells.shape, out.points.shape
((72, 5), (125, 2))
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from blockmesh._system.prefault import Prefault
from blockmesh._system.threads import run_parallel
from blockmesh.geometry.topology import boundary_slots
from blockmesh.refinement.plan import (
    PLACE_CHUNK,
    NodePattern,
    PlaceScratch,
    chunk_coordinates,
    edge_id_table,
    group_node_ids,
    node_pattern,
    place_level,
    plan_refinement,
)
from blockmesh.refinement.template import LevelStep, node_count, pentagon_template

if TYPE_CHECKING:
    from blockmesh.mesh.mesh import Mesh
    from blockmesh.refinement.curved import CurvedBlocks

__all__ = ["BLOCK_LEVEL", "GROUP_NODES", "RefinedBlocks", "refine_blocks", "workspace_bytes"]

#: Blocks are refined at most this many levels at once: a deeper refinement first refines the
#: base to the difference (a mesh of 1/6^6 of the output's size) and refines its cells as blocks.
#: The numbering is nested, so the result is the same bit for bit; blocks of this size keep the
#: template and each group's working arrays in the CPU caches, and give the worker threads many
#: groups to share (level 6 was 12 % faster than 5 over the catalogue, paired runs).
BLOCK_LEVEL = 6

#: Template nodes of the blocks refined together (when blocks are small): the group's
#: coordinates, ids and masks (25 bytes a node) stay in the CPU's last-level cache.
GROUP_NODES = 1 << 18


@dataclass(frozen=True)
class RefinedBlocks:
    """The arrays of a refined block mesh (see :class:`blockmesh.Mesh` for their meaning).

    ``boundary_nodes`` (Eb, 2^L + 1) are the nodes along each boundary edge of the base, in the
    base's order; ``block_id`` and ``region`` repeat the base's values per refined cell.
    """

    points: np.ndarray
    cells: np.ndarray
    block_id: np.ndarray
    parent: np.ndarray
    region: np.ndarray
    boundary_nodes: np.ndarray


def refine_blocks(
    base: Mesh,
    neighbour: np.ndarray,
    level: int,
    *,
    curved: CurvedBlocks | None = None,
    threads: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RefinedBlocks:
    """Every block of ``base`` refined ``level`` times, numbered like the paper.

    Parameters
    ----------
    base : Mesh
        The blocks; ``neighbour`` is :func:`blockmesh.geometry.topology.cell_neighbours` of its
        cells.
    level : int
        Levels of refinement (>= 0).
    curved : CurvedBlocks, optional
        The curve-aware rule for the blocks with a curved edge (recorded as they are refined).
    threads : int, optional
        Worker threads (default :func:`blockmesh._system.threads.default_threads`); 1 works in the
        calling thread.
    progress : callable, optional
        ``progress(done, total)`` after each group of blocks, called in the calling thread.
    """
    plan = plan_refinement(base.cells, neighbour, base.n_points, level)
    template = pentagon_template(level)
    n_local, per_block = template.n_nodes, 6**level
    n_blocks = base.n_cells
    edge_ids = edge_id_table(plan)
    size = _group_size(n_blocks, n_local)
    groups = [(b, min(b + size, n_blocks)) for b in range(0, n_blocks, size)]

    points = np.empty(plan.n_nodes, dtype=np.complex128)
    points[: base.n_points] = base.points.view(np.complex128)[:, 0]
    cells = np.empty((n_blocks * per_block, 5), dtype=np.int64)
    # Cell c comes from cell c // 6 of the level before (from none without refinement).
    parent = np.empty(n_blocks * per_block, dtype=np.int64) if level else np.full(n_blocks, -1)
    # Per-cell copies of the blocks' values; all-zero ones come from np.zeros (lazily zeroed
    # memory, never touched here), the others are filled group by group.
    sources = {"block_id": base.block_id, "region": base.region}
    columns = {
        name: np.empty(n_blocks * per_block, dtype=np.int64)
        if np.any(values)
        else np.zeros(n_blocks * per_block, dtype=np.int64)
        for name, values in sources.items()
    }
    filled = {name: columns[name] for name, values in sources.items() if np.any(values)}
    corners = base.points.view(np.complex128)[:, 0]
    bounds = [node_count(step) for step in range(level + 1)]
    is_curved = np.zeros(n_blocks, dtype=bool) if curved is None else curved.is_curved
    fix_level = None if curved is None else curved.fix_level
    fix_finest = None if curved is None else curved.fix_finest_level

    def refine_group(group: tuple[int, int], work: _Workspace) -> None:
        b0, b1 = group
        count = b1 - b0
        local, ids = work.local[:count], work.ids[:count]
        local[:, :5] = corners[base.cells[b0:b1]]
        curved_here = (np.flatnonzero(is_curved[b0:b1]) + b0).tolist()
        patterns = [node_pattern(level, tuple(plan.taken[b].tolist())) for b in range(b0, b1)]
        # The finest level (5/6 of the nodes) goes straight to the output; curved blocks then
        # correct their nodes near the curves there (fix_finest_level).
        direct = level > 0
        for step in range(1, level + 1 - direct):
            place_level(local, template.steps[step - 1], bounds[step - 1], work.scratch)
            for block in curved_here:
                fix_level(local[block - b0], step, block)  # type: ignore[misc]
        if direct:
            _place_finest_level(
                local,
                template.steps[-1],
                level,
                plan.offsets[level, b0:b1],
                patterns,
                points,
                work.scratch,
            )
        group_node_ids(plan, b0, b1, edge_ids[b0:b1], out=ids, template=template)
        if direct:
            for block in curved_here:
                k = block - b0
                fix_finest(local[k], ids[k], patterns[k].own, block, points)  # type: ignore[misc]
        shares = [any(pattern.taken) for pattern in patterns]
        for step in range(1, level + 1 - direct):
            lo, hi = bounds[step - 1], bounds[step]
            start = int(plan.offsets[step, b0])
            stop = int(plan.offsets[step, b1 - 1] + plan.counts[step, b1 - 1])
            # The nodes these blocks number, in order (lower blocks have the others): one run of
            # the output, gathered from the rows of local at once.
            if not any(shares):
                np.copyto(points[start:stop].reshape(count, hi - lo), local[:, lo:hi])
                continue
            keeps = [pattern.keep[step - 1] for pattern in patterns]
            index = np.concatenate(keeps)
            index += np.repeat(
                np.arange(lo, lo + count * n_local, n_local), [k.size for k in keeps]
            )
            np.take(local.reshape(-1), index, out=points[start:stop], mode="clip")
        np.take(
            ids,
            template.cells,
            axis=1,
            out=cells[b0 * per_block : b1 * per_block].reshape(count, per_block, 5),
            mode="clip",
        )
        first = b0 * per_block // 6
        if level:
            parent[b0 * per_block : b1 * per_block].reshape(-1, 6)[:] = np.arange(
                first, first + count * per_block // 6
            )[:, None]
        for name, array in filled.items():
            array[b0 * per_block : b1 * per_block].reshape(count, per_block)[:] = sources[name][
                b0:b1, None
            ]

    # Every group fills its share of each of these from front to back (of the points, the
    # finest level's run after the coarser levels' runs).
    finest = int(plan.offsets[level, 0]) if level else plan.n_nodes
    filling = [cells, parent, *filled.values(), points[:finest], points[finest:]]

    reported = iter(range(1, len(groups) + 1))
    with Prefault(filling):
        run_parallel(
            refine_group,
            groups,
            threads=threads,
            workspace=lambda: _Workspace(size, n_local),
            finished=None if progress is None else lambda *_: progress(next(reported), len(groups)),
        )

    if curved is not None:
        for block in np.flatnonzero(is_curved).tolist():
            curved.record(block, edge_ids[block])
    cell, edge = np.divmod(
        boundary_slots(base.cells, neighbour, base.boundary_edges, base.n_points), 5
    )
    return RefinedBlocks(
        points=points.view(np.float64).reshape(-1, 2),
        cells=cells,
        block_id=columns["block_id"],
        parent=parent,
        region=columns["region"],
        boundary_nodes=edge_ids[cell, edge],
    )


def _group_size(n_blocks: int, n_local: int) -> int:
    """Blocks per group: as many as :data:`GROUP_NODES` allows, at least 1, at most all."""
    return max(1, min(n_blocks, GROUP_NODES // n_local))


def workspace_bytes(n_blocks: int, level: int) -> int:
    """Bytes one worker thread of :func:`refine_blocks` touches for its working arrays.

    The coordinates and ids of a group (24 bytes a node) and the part of
    :class:`~blockmesh.refinement.plan.PlaceScratch` the largest chunk of parents uses (about 600
    bytes a parent).

    Examples
    --------
    >>> workspace_bytes(8, 6) // 2**20
    9
    """
    n_local = node_count(level)
    rows = _group_size(n_blocks, n_local)
    parents = min(rows * max(1, PLACE_CHUNK // rows), rows * 6 ** max(level - 1, 0))
    return 24 * rows * n_local + 600 * parents


def _place_finest_level(
    local: np.ndarray,
    step: LevelStep,
    level: int,
    offsets: np.ndarray,
    patterns: list[NodePattern],
    points: np.ndarray,
    scratch: PlaceScratch,
) -> None:
    """The nodes new at the finest level, each block's own ones written straight into ``points``.

    Block k of the group numbers its own nodes of this level from ``offsets[k]`` on, in the order
    of their slots (``patterns[k].last_source``); the others belong to lower blocks.
    """
    n_parents = step.corners.shape[1]
    chunk = scratch.chunk
    where = [_finest_positions(level, pattern.taken, chunk) for pattern in patterns]
    for c, j0 in enumerate(range(0, n_parents, chunk)):
        j1 = min(j0 + chunk, n_parents)
        slots = chunk_coordinates(local, step, j0, j1, scratch, slot_major=True)
        for k, (position, bounds) in enumerate(where):
            first, last = int(bounds[c]), int(bounds[c + 1])
            start = int(offsets[k]) + first
            target = points[start : start + last - first]
            np.take(slots[k], position[first:last], out=target, mode="clip")


@lru_cache(maxsize=64)
def _finest_positions(
    level: int, taken: tuple[bool, ...], chunk: int
) -> tuple[np.ndarray, np.ndarray]:
    """Where the block's own nodes of the finest level are in the slot-major chunks.

    Returns the position of each in :func:`~blockmesh.refinement.plan.chunk_coordinates`' slot-major
    output of its chunk of ``chunk`` parents, and the index of the first of them in each chunk
    (with the count at the end).
    """
    source = node_pattern(level, taken).last_source
    parent, slot = np.divmod(source, 10)
    position = slot * chunk + parent % chunk
    n_chunks = -(-(int(parent[-1]) + 1) // chunk) if source.size else 0
    bounds = np.searchsorted(parent, chunk * np.arange(n_chunks + 1))
    bounds[-1] = source.size
    position.setflags(write=False)
    return position, bounds


class _Workspace:
    """One thread's working arrays for groups of up to ``rows`` blocks of ``n_local`` nodes."""

    def __init__(self, rows: int, n_local: int) -> None:
        self.local = np.empty((rows, n_local), dtype=np.complex128)
        self.ids = np.empty((rows, n_local), dtype=np.int64)
        self.scratch = PlaceScratch(rows)
