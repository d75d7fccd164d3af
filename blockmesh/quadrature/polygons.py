"""The composite rules on polygon meshes: cells of any number of vertices, hanging nodes included.

The paper's rule works for any convex (indeed any star-shaped) polygon, not only for pentagons:
cut the cell of ``k`` vertices into ``k`` triangles ``(c, v_i, v_i+1)`` from its vertex mean
``c`` and integrate each in collapsed coordinates with the rule's tensor Gauss table
(:class:`~blockmesh.quadrature.rule.SectorNodes`)::

    ∫∫_(c, a, b) f ≈ |det(a - c, b - c)| Σ_jk w_jk f((1 - r_j) c + r_j ((a + b)/2 + h_k (b - a))).

Each triangle is integrated exactly to the rule's degree (``2n - 1``), so the cell is too: a
polynomial of degree ``2n - 1`` integrates exactly over any polygon mesh (the tests check it to
round-off against exact rational integrals). A straight vertex (a hanging node) is a vertex like
any other: it only adds a triangle. The ``"fan"`` rule takes the cell's vertex 0 as the apex of
its triangles (those with vertex 0 on their edge have no area and contribute nothing).

Cells are taken a group of one vertex count at a time (:attr:`PolygonMesh.groups`), in chunks of
a bounded number of points; the cell integrals come back in the mesh's cell order.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.refine(blockmesh.load_domain("sp").mesh(1), cells=[0])
>>> values = polygon_cell_integrals(mesh, lambda x, y: 1 + 0 * x, get_rule("paper"), 1)
>>> round(float(values.sum()), 13), values.shape
(5.0, (11,))
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from blockmesh.errors import ArgumentError, ExpressionError, ResourceError
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.quadrature.kernel import evaluate
from blockmesh.quadrature.registry import get_rule
from blockmesh.quadrature.rule import Rule

__all__ = [
    "check_polygon_target",
    "get_rule",
    "polygon_cell_integrals",
    "polygon_chunks",
    "polygon_points_per_cell",
]

Function = Callable[[np.ndarray, np.ndarray], np.ndarray]


def _apex_is_mean(rule: Rule) -> bool:
    return all(apex is None for apex, _, _ in rule.layout.sectors)


def polygon_points_per_cell(rule: Rule, n: int, sizes: np.ndarray) -> np.ndarray:
    """Evaluations of f for each cell of ``sizes`` vertices (one triangle per vertex)."""
    return np.asarray(sizes, dtype=np.int64) * rule.nodes(n).points_per_sector


def polygon_chunks(
    mesh: PolygonMesh, rule: Rule, n: int, chunk: int
) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Per chunk of cells of one size: ``(cells (C,), x (C, P), y (C, P), w (C, P))``.

    ``∫_cell f ≈ Σ_p w f(x, y)`` for every cell of the chunk (ids into the mesh's cells).
    """
    nodes = rule.nodes(n)
    r, one_minus_r = nodes.r[:, None], nodes.one_minus_r[:, None]
    h = nodes.h[None, :]
    weights = nodes.weights.reshape(-1)
    mean_apex = _apex_is_mean(rule)
    for group in mesh.groups:
        k = group.size
        per_cell = k * weights.size
        step = max(1, chunk // per_cell)
        for start in range(0, group.n_cells, step):
            cells = group.cells[start : start + step]
            corners = mesh.points[cells]  # (C, k, 2)
            apex = corners.mean(axis=1) if mean_apex else corners[:, 0]
            a = corners
            b = np.roll(corners, -1, axis=1)
            ca = a - apex[:, None, :]
            cb = b - apex[:, None, :]
            det = np.abs(ca[..., 0] * cb[..., 1] - ca[..., 1] * cb[..., 0])  # (C, k)
            mid = (a + b) / 2
            along = b - a
            edge = mid[:, :, None, None, :] + h[None, None, :, :, None] * along[:, :, None, None, :]
            xy = (
                one_minus_r[None, None, :, :, None] * apex[:, None, None, None, :]
                + r[None, None, :, :, None] * edge
            )  # (C, k, Nr, Ns, 2)
            c = cells.shape[0]
            w = (det[:, :, None] * weights[None, None, :]).reshape(c, -1)
            yield (
                group.index[start : start + step],
                xy[..., 0].reshape(c, -1),
                xy[..., 1].reshape(c, -1),
                w,
            )


def polygon_cell_integrals(
    mesh: PolygonMesh, f: Function, rule: Rule, n: int, chunk: int = 1 << 20
) -> np.ndarray:
    """The integral of ``f`` over every cell of ``mesh`` (M,), with ``rule`` of order ``n``.

    ExpressionError naming the point and the cell where f is not finite.
    """
    out = np.zeros(mesh.n_cells)
    for cells, x, y, w in polygon_chunks(mesh, rule, n, chunk):
        with np.errstate(all="ignore"):  # non-finite values are reported below, located
            values = evaluate(f, x, y)
        if not np.all(np.isfinite(values)):
            row, col = np.unravel_index(int(np.flatnonzero(~np.isfinite(values))[0]), x.shape)
            raise ExpressionError(
                f"f is not finite ({values[row, col]}) at (x, y) = ({x[row, col]!r}, "
                f"{y[row, col]!r}), a quadrature point of cell {int(cells[row])}"
            )
        out[cells] = np.sum(w * values, axis=1)
    return out


def check_polygon_target(
    mesh: PolygonMesh, level: object, exact_geometry: bool, rule: Rule, n: int, budget: int
) -> int:
    """Refuse what a polygon mesh cannot do; the number of points the integration takes."""
    if level is not None and level != mesh.level:
        raise ArgumentError(
            f"a PolygonMesh is integrated on its own cells (level {mesh.level}), not at level "
            f"{level}; refine it first (blockmesh.refine(mesh, ...))"
        )
    if exact_geometry and mesh.curves is not None and len(mesh.curves):
        raise ArgumentError(
            "exact_geometry integrates curved pentagons; on a PolygonMesh the cells are "
            "integrated as straight polygons (give exact_geometry=False)"
        )
    points = int(polygon_points_per_cell(rule, n, mesh.cell_sizes()).sum())
    if points > budget:
        raise ResourceError(
            f"integrating over {mesh.name or 'the mesh'} ({mesh.n_cells:,} cells) with order "
            f"{n} of the {rule.name} rule takes {points:,} evaluations of f, more than "
            f"max_points={budget:,}; lower the order or raise max_points"
        )
    return points
