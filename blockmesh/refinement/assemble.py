"""Building the refined mesh: blocks refined in groups, or level by level, and the Mesh assembled.

:func:`build` refines a block mesh by the paper's placement, block groups on worker threads
(:mod:`blockmesh.refinement.grouped`), a deep level first refined to its base, cells with curved
edges by the curve-aware rule in the same pass; :func:`build_smoothed` refines every block at
once level by level with Laplacian sweeps between; :func:`build_placed` one level at a time with
another node placement after each. :func:`assemble` makes the :class:`~blockmesh.mesh.Mesh` of
the refined arrays: boundary edges and patches, regions, interfaces and curves carried to the
new level.
"""

from __future__ import annotations

import numpy as np

import blockmesh.refinement.grouped as grouped
from blockmesh.geometry.topology import boundary_slots, cell_neighbours
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.curved import CurvedBlocks, place_on_curves
from blockmesh.refinement.grouped import RefinedBlocks, refine_blocks
from blockmesh.refinement.interfaces import refined_interfaces
from blockmesh.refinement.placement import Placement
from blockmesh.refinement.plan import edge_id_table, group_node_ids, plan_refinement
from blockmesh.refinement.plan import place_level as _place_level
from blockmesh.refinement.smoothing import block_edge_nodes, smooth_interior
from blockmesh.refinement.template import node_count, pentagon_template

__all__ = ["assemble", "build", "build_placed", "build_smoothed"]


def build_placed(
    base: Mesh, level: int, smooth: int, placement: Placement, progress, threads: int | None
) -> Mesh:
    """One level at a time, the nodes of each new level placed by ``placement``."""
    mesh = base
    for step in range(level):
        neighbour = cell_neighbours(mesh.cells, mesh.n_points)
        mesh = placement.after_level(build(mesh, neighbour, 1, smooth, None, threads))
        if progress is not None:
            progress(step + 1, level)
    return mesh


def build(
    base: Mesh,
    neighbour: np.ndarray,
    level: int,
    smooth: int,
    progress,
    threads: int | None = None,
) -> Mesh:
    """The refined mesh; cells with curved edges follow the curve-aware rule in the same pass.

    With smoothing, every block is refined at once level by level (the sweeps cross blocks) and
    the curved cells are then recomputed by :func:`~blockmesh.refinement.curved.place_on_curves`.
    """
    has_curves = base.curves is not None and len(base.curves) > 0
    if smooth:
        mesh = build_smoothed(base, neighbour, level, smooth, progress)
        return place_on_curves(base, mesh, level, smooth) if has_curves else mesh
    if level > grouped.BLOCK_LEVEL:
        # Refine the base to the difference first and its cells as blocks (see BLOCK_LEVEL).
        first = level - grouped.BLOCK_LEVEL
        base = build(base, neighbour, first, 0, None, threads)
        neighbour = cell_neighbours(base.cells, base.n_points)
        level -= first
    curved = CurvedBlocks(base, level) if has_curves else None
    refined = refine_blocks(
        base, neighbour, level, curved=curved, threads=threads, progress=progress
    )
    return assemble(base, refined, level, curved, neighbour)


def build_smoothed(base: Mesh, neighbour: np.ndarray, level: int, smooth: int, progress) -> Mesh:
    """All blocks at once, level by level, with ``smooth`` Laplacian sweeps after each level."""
    plan = plan_refinement(base.cells, neighbour, base.n_points, level)
    edge_ids = edge_id_table(plan)
    template = pentagon_template(level)
    ids = group_node_ids(plan, 0, base.n_cells, edge_ids, template=template)
    local = np.empty((base.n_cells, template.n_nodes), dtype=np.complex128)
    local[:, :5] = base.points.view(np.complex128)[base.cells, 0]
    points = np.empty(plan.n_nodes, dtype=np.complex128)
    fixed = block_edge_nodes(ids, template)
    for step in range(1, level + 1):
        lo, hi = node_count(step - 1), node_count(step)
        _place_level(local, template.steps[step - 1], lo)
        level_cells = ids[:, template.cells_of_level(step)].reshape(-1, 5)
        points[ids[:, :hi]] = local[:, :hi]
        n_level = int(ids[:, :hi].max()) + 1
        xy = points.view(np.float64).reshape(-1, 2)
        smooth_interior(xy, level_cells, n_level, fixed, smooth)
        local[:, :hi] = points[ids[:, :hi]]
        if progress is not None:
            progress(step, level)
    np.put(points, ids, local, mode="clip")  # shared nodes get the same value twice
    del local
    cell, edge = np.divmod(
        boundary_slots(base.cells, neighbour, base.boundary_edges, base.n_points), 5
    )
    per_block = 6**level
    refined = RefinedBlocks(
        points=points.view(np.float64).reshape(-1, 2),
        cells=np.take(ids, template.cells, axis=1, mode="clip").reshape(-1, 5),
        block_id=_repeat(base.block_id, per_block),
        parent=_parents(base.n_cells * per_block, level),
        region=_repeat(base.region, per_block),
        boundary_nodes=edge_ids[cell, edge],
    )
    return assemble(base, refined, level, neighbour=neighbour)


def assemble(
    base: Mesh,
    refined: RefinedBlocks,
    steps: int,
    curved: CurvedBlocks | None = None,
    neighbour: np.ndarray | None = None,
) -> Mesh:
    """The Mesh of ``base`` refined ``steps`` times from the arrays ``refined``.

    ``curved``, when given, has recorded every curved block: the mesh gets its refined curves.
    ``neighbour`` (the base's cell neighbours) is needed when the base has interfaces.
    """
    along = refined.boundary_nodes
    boundary_edges = np.stack([along[:, :-1], along[:, 1:]], axis=-1).reshape(-1, 2)
    arrays = {
        "points": refined.points,
        "cells": refined.cells,
        "block_id": refined.block_id,
        "parent": refined.parent if steps else base.parent,  # no step: the same cells
        "boundary_edges": boundary_edges,
        "boundary_patch": np.repeat(base.boundary_patch, 2**steps),
        "region": refined.region,
    }
    if base.interface_edges.shape[0]:
        if neighbour is None:
            neighbour = cell_neighbours(base.cells, base.n_points)
        arrays["interface_edges"] = refined_interfaces(base, neighbour, steps)
        arrays["interface_patch"] = np.repeat(base.interface_patch, 2**steps)
    for array in arrays.values():
        array.setflags(write=False)
    return Mesh._trusted(
        check_ranges=False,
        **arrays,
        patch_names=base.patch_names,
        region_names=base.region_names,
        interface_names=base.interface_names,
        level=base.level + steps,
        name=base.name,
        curves=None if curved is None else curved.refined(),
    )


def _parents(n_cells: int, steps: int) -> np.ndarray:
    """Parent of each refined cell: cell c comes from cell c // 6 (none without refinement)."""
    if steps == 0:
        return np.full(n_cells, -1, dtype=np.int64)
    return np.repeat(np.arange(n_cells // 6, dtype=np.int64), 6)


def _repeat(values: np.ndarray, count: int) -> np.ndarray:
    """``np.repeat(values, count)``; all zeros come from ``np.zeros`` (lazily zeroed memory)."""
    if not np.any(values):
        return np.zeros(values.size * count, dtype=np.int64)
    return np.repeat(values, count)
