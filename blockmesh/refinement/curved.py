"""Refinement of cells with curved edges: midpoints on the curve, a centre that keeps cells valid.

:func:`blockmesh.refine` computes every node with the paper's straight arithmetic; when the mesh
has curves (``Mesh.curves``), the base cells with a curved edge follow, level by level, the
curve-aware rule (``docs/mathematics.md`` §1 and the curved-edge paragraph of §6) in the same pass
(:class:`CurvedBlocks` recomputes after each level only the nodes of the parents touching a curve;
with smoothing, :func:`place_on_curves` recomputes the curved cells after the straight
refinement):

- the midpoint ``u`` of a cell edge lying on a curved block edge is the curve's point at the mean
  of the edge's two parameters (so every node on the edge is the curve's point at ``k/2^L``, and
  two cells sharing the edge get the same bits);
- the midpoint of any other edge is ``(v_i + v_i+1)/2`` as in the paper;
- the centre of a cell with a curved edge is ``p = (2/5) Σ u_i - (1/5) Σ v_i``, which is the vertex
  mean when every edge is straight (then ``Σ u_i = Σ v_i``) and, unlike the vertex mean, keeps the
  cells next to a concave arc convex; a cell without a curved edge keeps the vertex mean, computed
  as the paper does;
- the inner points are ``w_i = (u_i + p)/2``.

Nodes on the straight edges of a base cell are left as the straight refinement put them, so cells
without curves, and the nodes they share with curved cells, are bit for bit the paper's.

Examples
--------
>>> import blockmesh
>>> from blockmesh.curves import Arc
>>> square = [(0, 0), (1, 0), (1.5, 0.5), (1, 1), (0, 1)]
>>> d = blockmesh.Domain.from_blocks(
...     square, [(0, 1, 2, 3, 4)], edges={(3, 4): Arc(through=(0.5, 1.2))}
... )
>>> mesh = d.mesh(3)
>>> float(np.max(mesh.curves.distances(mesh.points))) < 1e-15
True
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import cache
from typing import TYPE_CHECKING

import numpy as np

from blockmesh.curves.edges import CurvedEdges, curved_slots, edge_points
from blockmesh.refinement.smoothing import smooth_interior
from blockmesh.refinement.template import node_count, pentagon_template

if TYPE_CHECKING:
    from blockmesh.mesh.mesh import Mesh

__all__ = [
    "CurvedBlocks",
    "curved_block_levels",
    "curved_cell_nodes",
    "place_on_curves",
    "refined_curves",
]

#: Local nodes (cells x nodes) processed at once: bounds the temporaries.
_CHUNK_NODES = 1 << 21


@cache
def _step_ids(step: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local ids at one level: the parents' corners, midpoints ``u_k`` and inner points ``w_k``.

    Each array is (C, 5) for the C = 6^(step-1) cells of the previous level; child ``k`` of parent
    ``j`` is ``<v_k, u_k, w_k, w_k-1, u_k-1>`` and child 5 is ``<w_0 .. w_4>``.
    """
    parents = pentagon_template(step - 1).cells
    children = pentagon_template(step).cells.reshape(-1, 6, 5)
    return parents, children[:, :5, 1].copy(), children[:, 5, :].copy()


@cache
def edge_midpoints(step: int, level: int) -> tuple[tuple[np.ndarray, ...], ...]:
    """Per block edge ``e``: the parents with an edge on it, and where its midpoint lies.

    ``(j, k, position)``: parent ``j`` at ``step - 1`` has its edge ``k`` on block edge ``e``,
    whose midpoint is point ``position`` of ``e`` at ``level`` (an index into ``along``).
    """
    _, u_ids, _ = _step_ids(step)
    template = pentagon_template(level)
    out = []
    for e in range(5):
        j, k = np.nonzero(template.edge_of_node[u_ids] == e)
        position = np.empty(template.n_nodes, dtype=np.int64)
        position[template.edge_nodes[e]] = np.arange(template.edge_nodes.shape[1])
        out.append((j, k, position[u_ids[j, k]]))
    return tuple(out)


@cache
def _curved_parents(step: int, level: int, edges: tuple[int, ...]):
    """The parents at ``step`` with an edge on one of the block edges ``edges``, and those edges.

    Returns ``(v_ids, u_ids, w_ids, on_curve)``: the local ids of the M parents' corners,
    midpoints and inner points, each (M, 5), and per block edge of ``edges`` ``(j, k, position)``
    (parent ``j`` of the M has its edge ``k`` on it, at point ``position`` along it).
    """
    parents, u_ids, w_ids = _step_ids(step)
    midpoints = edge_midpoints(step, level)
    has = np.unique(np.concatenate([midpoints[e][0] for e in edges]))
    on_curve = tuple(
        (np.searchsorted(has, midpoints[e][0]), midpoints[e][1], midpoints[e][2]) for e in edges
    )
    return parents[has], u_ids[has], w_ids[has], on_curve


@cache
def _ring_parents(step: int, level: int) -> np.ndarray:
    """The cells at ``step - 1`` with an edge on one of the five block edges (sorted ids)."""
    return np.unique(np.concatenate([j for j, _, _ in edge_midpoints(step, level)]))


def curved_block_levels(
    corners: np.ndarray,
    along: np.ndarray,
    curved: np.ndarray,
    level: int,
    smooth: int = 0,
    *,
    ring: bool = False,
) -> Iterator[tuple[int, np.ndarray]]:
    """Refine pentagons with curved edges level by level; yields ``(step, xy)`` for 0..level.

    Parameters
    ----------
    corners : ndarray (B, 5, 2)
        The cells' corners, counter-clockwise.
    along : ndarray (B, 5, 2^level + 1, 2)
        For each curved edge ``k`` of a cell, the curve's points at the parameters ``j/2^level``
        from corner ``k`` to corner ``k+1`` (ignored where ``curved`` is False).
    curved : ndarray (B, 5) bool
        Which cell edges are curved.
    level : int
    smooth : int
        Laplacian sweeps per level on the nodes inside each cell (see
        :mod:`blockmesh.refinement.smoothing`).
    ring : bool
        Refine only the cells along the block's edges (those with an edge on one, level by
        level): O(2^level) cells per block instead of O(6^level). Their children's nodes, and so
        every node on the block's edges, are set; the other entries of ``xy`` are not. Not with
        ``smooth`` (a sweep moves every inner node).

    Yields
    ------
    step : int
    xy : ndarray (B, n_level, 2)
        The local node coordinates (the template's numbering); entries ``0..n_step-1`` are set.
        The same array is yielded at every step (copy it to keep one level).
    """
    if ring and smooth:
        raise ValueError("ring=True refines the cells along the edges only: no smoothing")
    template = pentagon_template(level)
    n_cells = corners.shape[0]
    xy = np.empty((n_cells, template.n_nodes, 2))
    xy[:, :5] = corners
    fixed = template.edge_of_node != -1
    yield 0, xy
    for step in range(1, level + 1):
        parents, u_ids, w_ids = _step_ids(step)
        midpoints = edge_midpoints(step, level)
        if ring:
            chosen = _ring_parents(step, level)
            parents, u_ids, w_ids = parents[chosen], u_ids[chosen], w_ids[chosen]
            midpoints = tuple((np.searchsorted(chosen, j), k, at) for j, k, at in midpoints)
        v = xy[:, parents]  # (B, C, 5, 2)
        u = v + v[:, :, [1, 2, 3, 4, 0]]
        u *= 0.5
        has = np.zeros(u.shape[:2], dtype=bool)  # parents with an edge on a curve
        for e, (j, k, position) in enumerate(midpoints):
            rows = np.flatnonzero(curved[:, e])
            if rows.size:
                u[rows[:, None], j, k] = along[rows[:, None], e, position]
                has[rows[:, None], j] = True
        p = (((v[:, :, 0] + v[:, :, 1]) + v[:, :, 2]) + v[:, :, 3]) + v[:, :, 4]
        p /= 5
        p[has] = 0.4 * u[has].sum(axis=1) - 0.2 * v[has].sum(axis=1)
        w = u + p[:, :, None, :]
        w *= 0.5
        xy[:, u_ids] = u
        xy[:, w_ids] = w
        if smooth:
            _smooth_cells(xy, step, fixed, smooth)
        yield step, xy


def _smooth_cells(xy: np.ndarray, step: int, fixed: np.ndarray, sweeps: int) -> None:
    """Laplacian sweeps on each cell's inner nodes at ``step`` (its edge nodes stay)."""
    cells = pentagon_template(step).cells
    n = node_count(step)
    for b in range(xy.shape[0]):
        local = xy[b, :n]
        smooth_interior(local, cells, n, fixed[:n], sweeps)


def _block_inputs(
    points: np.ndarray, cells: np.ndarray, row: np.ndarray, forward: np.ndarray, table: np.ndarray
):
    """Corners, on-curve points along each edge (in the cell's direction) and the curved mask."""
    corners = points[cells]
    curved = row >= 0
    along = np.zeros((*cells.shape, table.shape[1], 2))
    along[curved] = table[row[curved]]
    backward = curved & ~forward
    along[backward] = along[backward][:, ::-1]
    return corners, along, curved


@cache
def _straight_edge_nodes(level: int) -> np.ndarray:
    """(5, n_level) bool: the template nodes on each of a cell's five edges."""
    template = pentagon_template(level)
    out = np.zeros((5, template.n_nodes), dtype=bool)
    for k in range(5):
        out[k, template.edge_nodes[k]] = True
    out.setflags(write=False)
    return out


def curved_cell_nodes(
    points: np.ndarray,
    cells: np.ndarray,
    row: np.ndarray,
    forward: np.ndarray,
    table: np.ndarray,
    level: int,
    smooth: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    """The local nodes of cells with curved edges refined ``level`` times, and which ones move.

    ``row`` and ``forward`` are the cells' rows of :func:`curved_slots`, ``table`` the curves'
    points of :func:`edge_points` at ``level``. Returns ``(xy, moved)``: ``xy`` (G, n_level, 2)
    in the template's numbering, ``moved`` (G, n_level) bool, False on the cells' straight edges,
    whose nodes stay where the straight refinement puts them (shared with straight neighbours).
    The arithmetic is element by element, so a cell's nodes do not depend on the cells refined
    with it: :func:`place_on_curves` and a partition's piece get the same bits.
    """
    corners, along, curved = _block_inputs(points, cells, row, forward, table)
    *_, (_, xy) = curved_block_levels(corners, along, curved, level, smooth)
    straight = _straight_edge_nodes(level)
    kept = np.zeros(xy.shape[:2], dtype=bool)
    for k in range(5):
        kept[~curved[:, k]] |= straight[k]
    return xy, ~kept


def refined_curves(curves: CurvedEdges, rows: np.ndarray, along_ids: np.ndarray, level: int):
    """The curved edges of a refinement: rows ``rows`` of ``curves``, each cut into 2^level.

    ``along_ids`` (len(rows), 2^level + 1) are the node ids along each row's edge, in the
    curve's direction; the pieces keep the curve and get the dyadic parameters between.
    """
    fractions = np.arange(2**level + 1) / 2**level
    start, stop = curves.start[rows, None], curves.stop[rows, None]
    params = start + fractions * (stop - start)
    return CurvedEdges(
        edges=np.stack([along_ids[:, :-1], along_ids[:, 1:]], axis=-1).reshape(-1, 2),
        curve=np.repeat(curves.curve[rows], 2**level),
        start=params[:, :-1].ravel(),
        stop=params[:, 1:].ravel(),
        curves=curves.curves,
    )


class CurvedBlocks:
    """The curve-aware rule applied in the same pass as the straight refinement, block by block.

    The straight refinement (:func:`blockmesh.refinement.plan.place_level`) computes every node of a
    level with the paper's arithmetic; :meth:`fix_level` then recomputes, in place, only the
    nodes of the parents with an edge on a curved block edge: their midpoints on the curve, their
    centre ``p = (2/5) Σ u_i - (1/5) Σ v_i`` and their inner points. Every other node of the
    straight pass is already what :func:`curved_block_levels` computes (the same operations in
    the same order), so a block's nodes are bit for bit those of :func:`curved_cell_nodes`, and
    the curved blocks cost one refinement, not two.

    Parameters
    ----------
    base : Mesh
        The mesh refined; ``base.curves`` is not empty.
    level : int
        Levels of refinement.
    """

    def __init__(self, base: Mesh, level: int) -> None:
        curves = base.curves
        if curves is None or len(curves) == 0:
            raise ValueError("CurvedBlocks needs a mesh with curved edges")
        self.curves = curves
        self.level = level
        self.row, self.forward = curved_slots(base.cells, base.n_points, curves)
        self.is_curved = np.any(self.row >= 0, axis=1)
        table = edge_points(curves, level)
        #: The curves' points along every curved edge, complex128 (E, 2^level + 1).
        self.table = table.view(np.complex128)[..., 0]
        self.along_ids = np.empty((len(curves), 2**level + 1), dtype=np.int64)

    def along(self, block: int, edge: int) -> np.ndarray:
        """Points (complex) along edge ``edge`` of ``block`` from its corner ``edge`` on."""
        points = self.table[self.row[block, edge]]
        return points if self.forward[block, edge] else points[::-1]

    def fix_level(self, local: np.ndarray, step: int, block: int) -> None:
        """Recompute the nodes new at ``step`` of ``block``'s parents touching a curved edge.

        ``local`` (n_level,) complex128 holds the block's nodes in the template's numbering,
        those of ``step`` from the straight arithmetic; it is modified in place.
        """
        edges = tuple(np.flatnonzero(self.row[block] >= 0).tolist())
        v_ids, u_ids, w_ids, on_curve = _curved_parents(step, self.level, edges)
        v = local[v_ids].view(np.float64).reshape(v_ids.shape[0], 5, 2)
        u = local[u_ids]
        for e, (j, k, position) in zip(edges, on_curve, strict=True):
            u[j, k] = self.along(block, e)[position]
        u = u.view(np.float64).reshape(u_ids.shape[0], 5, 2)
        # The same expressions, on arrays of the same layout, as curved_block_levels.
        p = 0.4 * u.sum(axis=1) - 0.2 * v.sum(axis=1)
        w = u + p[:, None, :]
        w *= 0.5
        local[u_ids] = u.view(np.complex128)[..., 0]
        local[w_ids] = w.view(np.complex128)[..., 0]

    def fix_finest_level(
        self, local: np.ndarray, ids: np.ndarray, own: np.ndarray, block: int, points: np.ndarray
    ) -> None:
        """:meth:`fix_level` at the finest level when that level went straight to ``points``.

        The refinement writes the finest level's straight coordinates into the output without
        keeping them in ``local`` (n_L,) complex128, whose coarser levels are set. Here the
        straight midpoints of the parents touching a curved edge are computed again (the same
        operations as :func:`~blockmesh.refinement.plan.chunk_coordinates`), :meth:`fix_level` moves
        them and their inner points, and the nodes ``block`` numbers itself (``own``) are
        written to ``points`` at their global ``ids`` (n_L,).
        """
        edges = tuple(np.flatnonzero(self.row[block] >= 0).tolist())
        v_ids, u_ids, w_ids, _ = _curved_parents(self.level, self.level, edges)
        v = local[v_ids].view(np.float64).reshape(v_ids.shape[0], 5, 2)
        u = np.empty_like(v)
        np.add(v[:, :4], v[:, 1:], out=u[:, :4])
        np.add(v[:, 4], v[:, 0], out=u[:, 4])
        u *= 0.5
        local[u_ids] = u.view(np.complex128)[..., 0]
        self.fix_level(local, self.level, block)
        nodes = np.concatenate([u_ids.ravel(), w_ids.ravel()])
        nodes = nodes[own[nodes]]
        points[ids[nodes]] = local[nodes]

    def record(self, block: int, edge_ids: np.ndarray) -> None:
        """Note the global ids of ``block``'s nodes along its edges.

        ``edge_ids`` (5, 2^L + 1) are the block's rows of
        :func:`blockmesh.refinement.plan.edge_id_table`.
        """
        for edge in np.flatnonzero(self.row[block] >= 0).tolist():
            nodes = edge_ids[edge]
            self.along_ids[self.row[block, edge]] = (
                nodes if self.forward[block, edge] else nodes[::-1]
            )

    def refined(self) -> CurvedEdges:
        """The refined curved edges, once :meth:`record` has seen every curved block."""
        return refined_curves(self.curves, np.arange(len(self.curves)), self.along_ids, self.level)


def place_on_curves(base: Mesh, mesh: Mesh, level: int, smooth: int = 0) -> Mesh:
    """``mesh`` (``base`` refined ``level`` times, straight) with its cells on the curves.

    Recomputes the nodes of the base cells with a curved edge (see the module docstring) and
    returns the mesh with those nodes moved and its ``curves`` refined: every curved edge of the
    base becomes ``2^level`` curved edges of the result.
    """
    curves = base.curves
    if curves is None or len(curves) == 0:
        return mesh
    template = pentagon_template(level)
    row, forward = curved_slots(base.cells, base.n_points, curves)
    curved_cells = np.flatnonzero(np.any(row >= 0, axis=1))
    table = edge_points(curves, level)
    points = np.array(mesh.points)
    repeat = 6**level
    # Local node -> global id of a base cell, from the cells it became.
    scatter = template.cells.ravel()
    along_ids = np.empty((len(curves), template.edge_nodes.shape[1]), dtype=np.int64)
    chunk = max(1, _CHUNK_NODES // template.n_nodes)
    for first in range(0, curved_cells.size, chunk):
        group = curved_cells[first : first + chunk]
        ids = np.empty((group.size, template.n_nodes), dtype=np.int64)
        children = mesh.cells.reshape(-1, repeat * 5)[group]
        ids[:, scatter] = children
        xy, moved = curved_cell_nodes(
            base.points, base.cells[group], row[group], forward[group], table, level, smooth
        )
        # Write every node but those on the cell's straight edges (the straight ones are kept).
        points[ids[moved]] = xy[moved]
        # Node ids along every curved edge, in the curve's direction.
        for k in range(5):
            rows = row[group, k]
            hit = rows >= 0
            nodes = ids[hit][:, template.edge_nodes[k]]
            nodes[~forward[group, k][hit]] = nodes[~forward[group, k][hit]][:, ::-1]
            along_ids[rows[hit]] = nodes
    refined = refined_curves(curves, np.arange(len(curves)), along_ids, level)
    return mesh._copy(points=points, curves=refined)
