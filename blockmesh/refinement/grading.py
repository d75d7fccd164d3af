"""Edge grading for explicit blocks (blockMesh's ``edgeGrading`` for pentagons).

A grading gives a block edge ``(a, b)`` a ratio ``r``: refined to level L, the edge's ``N = 2^L``
pieces are spaced geometrically from ``a`` to ``b``, the last ``r`` times the first:

    s_k = (q^k - 1) / (q^N - 1),   q = r^(1 / (N - 1)),   k = 0..N,

at every level (so the spacing is geometric at each level, not only at the last; the nodes of
coarser levels move, the numbering does not). Both blocks that share the edge read its nodes from
the one chain of the refined mesh, so they agree bit for bit. The nodes inside the blocks that
touch a graded edge follow by a discrete harmonic extension of the edges' displacement (each
moves by the mean of its neighbours' moves), so a block graded on two opposite sides, like a
channel graded towards a wall, has its inside rows graded alike. A grading that would fold a
cell is refused with the block, the edge, the level and the place.

Examples
--------
>>> import numpy as np
>>> geometric_fractions(10.0, 4).round(6).tolist()
[0.0, 0.056192, 0.177255, 0.438077, 1.0]
>>> from blockmesh import Domain
>>> d = Domain.from_blocks(
...     [(0, 0), (1, 0), (1.2, 0.5), (1, 1), (0, 1)], [(0, 1, 2, 3, 4)], grading={(4, 0): 4.0}
... )
>>> mesh = d.mesh(2)
>>> left = sorted(mesh.points[np.isclose(mesh.points[:, 0], 0), 1].round(6).tolist())
>>> [round(b - a, 6) for a, b in zip(left, left[1:])]  # 1 -> 0: each piece 4^(1/3) the last
[0.439211, 0.276685, 0.174301, 0.109803]
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from typing import Any

import numpy as np

from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL, corner_sines
from blockmesh.geometry.topology import cell_neighbours, unique_edges
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.plan import edge_id_table, plan_refinement

__all__ = ["MAX_RATIO", "check_grading", "geometric_fractions", "graded_mesh"]

#: Largest grading ratio accepted (and smallest, its inverse).
MAX_RATIO = 1e6


def geometric_fractions(ratio: float, pieces: int) -> np.ndarray:
    """Geometric fractions from 0 to 1: ``pieces`` pieces, the last ``ratio`` times the first.

    Examples
    --------
    >>> geometric_fractions(1.0, 4).tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    """
    k = np.arange(pieces + 1, dtype=np.float64)
    if pieces < 2 or ratio == 1.0:
        return k / pieces
    log_q = math.log(ratio) / (pieces - 1)
    # (q^k - 1) / (q^N - 1) with expm1 for full precision when q is near 1.
    return np.expm1(k * log_q) / math.expm1(pieces * log_q)


def check_grading(
    grading: object, blocks: np.ndarray, curved: Any = ()
) -> dict[tuple[int, int], float]:
    """The grading as ``{(a, b): ratio}``, checked: block edges, finite ratios, one per edge.

    ``(a, b): r`` and ``(b, a): 1 / r`` are the same grading; both may be given if they agree.
    Curved edges (``curved``: their vertex pairs) cannot be graded.
    """
    if grading is None:
        return {}
    if not isinstance(grading, Mapping):
        raise DomainFormatError(
            f"grading must map block edges (a, b) to ratios, got {type(grading).__name__}"
        )
    edges = {
        (int(a), int(b))
        for block in np.asarray(blocks).tolist()
        for a, b in zip(block, block[1:] + block[:1], strict=True)
    }
    curved_pairs = {tuple(map(int, k)) for k in curved}
    out: dict[tuple[int, int], float] = {}
    for key, ratio in grading.items():
        if isinstance(key, str | bytes) or not hasattr(key, "__len__") or len(key) != 2:
            raise DomainFormatError(f"a graded edge is a pair (a, b) of vertex ids, got {key!r}")
        if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in key):
            raise DomainFormatError(f"graded edge {key!r}: vertex ids are whole numbers")
        a, b = int(key[0]), int(key[1])
        if (a, b) not in edges and (b, a) not in edges:
            raise DomainError(
                f"graded edge ({a}, {b}) is not a block edge (vertices {a} and {b} are not "
                "neighbours in any block)"
            )
        if (a, b) in curved_pairs or (b, a) in curved_pairs:
            raise DomainError(
                f"graded edge ({a}, {b}) is curved; grading applies to straight block edges"
            )
        if isinstance(ratio, bool) or not isinstance(ratio, numbers.Real):
            raise DomainFormatError(f"graded edge ({a}, {b}): the ratio must be a number")
        r = float(ratio)
        if not (math.isfinite(r) and 1 / MAX_RATIO <= r <= MAX_RATIO):
            raise DomainError(
                f"graded edge ({a}, {b}): the ratio (last piece over first) must be a finite "
                f"number between {1 / MAX_RATIO:g} and {MAX_RATIO:g}, got {ratio!r}"
            )
        other = out.get((b, a))
        if other is not None and abs(other * r - 1.0) > 1e-12:
            raise DomainError(
                f"edge ({a}, {b}) is graded twice: ratio {r:g} from {a} to {b} and {other:g} "
                f"from {b} to {a} (these agree only if one is the inverse of the other)"
            )
        if other is None:
            out[(a, b)] = r
    return out


def graded_mesh(base: Mesh, mesh: Mesh, grading: Mapping[tuple[int, int], float]) -> Mesh:
    """``mesh`` (``base`` refined with the nested numbering) with its graded edges spaced.

    The nodes along every graded block edge move to :func:`geometric_fractions`; the nodes inside
    the blocks around them follow by a discrete harmonic extension of the move; every cell must
    stay strictly convex (DomainError otherwise, naming the block, the edge and where).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import spsolve

    steps = mesh.level - base.level
    if not grading or steps < 1:
        return mesh
    neighbour = cell_neighbours(base.cells, base.n_points)
    plan = plan_refinement(base.cells, neighbour, base.n_points, steps)
    table = edge_id_table(plan)  # (B, 5, 2^L + 1), corner e to corner e + 1
    points = np.array(mesh.points)
    move = np.zeros_like(points)
    touched = np.zeros(base.n_cells, dtype=bool)
    pieces = 2**steps
    for (a, b), ratio in grading.items():
        block, edge = _find_edge(base.cells, a, b)
        chain = table[block, edge]
        if base.cells[block, edge] != a:
            chain = chain[::-1]
        start, stop = base.points[a], base.points[b]
        placed = start + geometric_fractions(ratio, pieces)[:, None] * (stop - start)
        placed[0], placed[-1] = start, stop
        move[chain] = placed - points[chain]
        touched[block] = True
        other = neighbour[block, edge]
        if other >= 0:
            touched[other // 5] = True
    on_edges = np.zeros(len(points), dtype=bool)
    on_edges[table.ravel()] = True
    cells_near = mesh.cells[touched[mesh.block_id]]
    inner = np.unique(cells_near.ravel())
    inner = inner[~on_edges[inner]]
    if inner.size:
        edges = unique_edges(cells_near, len(points))
        n = len(points)
        tail, head = edges[:, 0], edges[:, 1]
        graph = coo_matrix(
            (np.ones(2 * len(tail)), (np.r_[tail, head], np.r_[head, tail])), shape=(n, n)
        ).tocsr()
        degree = np.asarray(graph.sum(axis=1)).ravel()
        index = np.full(n, -1)
        index[inner] = np.arange(inner.size)
        sub = graph[inner]
        known = sub[:, ~np.isin(np.arange(n), inner)]
        laplacian = (
            coo_matrix((degree[inner], (np.arange(inner.size), np.arange(inner.size))))
            - sub[:, inner]
        ).tocsc()
        outside = np.flatnonzero(index < 0)
        rhs = known @ move[outside]
        move[inner] = np.column_stack(
            [spsolve(laplacian, rhs[:, 0]), spsolve(laplacian, rhs[:, 1])]
        )
    points += move
    _check_folds(base, mesh, points, grading)
    return mesh._copy(points=points)


def _find_edge(cells: np.ndarray, a: int, b: int) -> tuple[int, int]:
    """A block and the slot of its edge between vertices ``a`` and ``b``."""
    following = np.roll(cells, -1, axis=1)
    hit = np.argwhere(((cells == a) & (following == b)) | ((cells == b) & (following == a)))
    block, edge = hit[0]
    return int(block), int(edge)


def _check_folds(base: Mesh, mesh: Mesh, points: np.ndarray, grading: Mapping) -> None:
    sines = corner_sines(points[mesh.cells])
    bad = np.flatnonzero(~np.all(sines > COLLINEAR_SIN_TOL, axis=1))
    if not bad.size:
        return
    cell = int(bad[0])
    block = int(mesh.block_id[cell])
    corners = base.cells[block].tolist()
    mine = [
        f"({a}, {b}) ratio {r:g}" for (a, b), r in grading.items() if a in corners and b in corners
    ]
    edges = ", ".join(mine) if mine else "its neighbours' graded edges"
    where = fmt_point(points[mesh.cells[cell]].mean(axis=0))
    raise DomainError(
        f"the grading folds cell {cell} of block {block} at level {mesh.level} near {where} "
        f"({bad.size} cells fold in all; block {block} has graded edges {edges}): use a smaller "
        "ratio, grade the opposite edge of the block alike, or split the block"
    )
