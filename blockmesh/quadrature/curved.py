"""Integrals over the true curved cells of a mesh (``exact_geometry=True``).

A cell with curved edges is split from its vertex mean ``c`` into straight triangles (over its
straight edges) and curved sectors (over its curved edges). A sector is the image of the unit
square under the rules' map with the curve in place of the straight edge
(:mod:`blockmesh.quadrature.rule`, ``docs/mathematics.md`` §6),

    x(r, s) = (1 - r) c + r γ(s),   dx dy = r det(γ(s) - c, γ'(s)) dr ds,

so the rule's radial nodes serve unchanged and the nodes along the edge run along the curve:
as many Gauss-Legendre points on each piece of the curve as make the sector's integral of a
polynomial of degree ``2n - 1`` exact (:func:`along_points`). The determinant is signed: the
sectors then add up to the cell by Green's theorem whatever the centre, even where a concave
curve hides part of the cell from it. Straight cells are integrated by the rule itself.

Areas have closed forms (:meth:`blockmesh.mesh.Mesh.curved_cell_areas`): the straight cell's
area plus, for every curved edge, the signed area between the curve and its chord.

Examples
--------
>>> import math
>>> import blockmesh
>>> from blockmesh.curves import Arc
>>> corners = [(1, 0), (math.cos(1.2), math.sin(1.2)), (0, 0.4), (0, 0), (0.5, -0.1)]
>>> d = blockmesh.Domain.from_blocks(corners, [(0, 1, 2, 3, 4)], edges={(0, 1): Arc(center=(0, 0))})
>>> mesh = d.block_mesh()
>>> bool(mesh.curved_cell_areas().sum() > mesh.area)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from blockmesh.curves.edges import curved_slots
from blockmesh.curves.types import Arc, Curve, Spline
from blockmesh.errors import ExpressionError
from blockmesh.numerics.gauss import MAX_POINTS, gauss_legendre
from blockmesh.quadrature.kernel import CellSums

if TYPE_CHECKING:
    from blockmesh.mesh.mesh import Mesh
    from blockmesh.quadrature.kernel import CellSums
    from blockmesh.quadrature.rule import Rule

__all__ = [
    "CurvedCells",
    "along_points",
    "curved_cells",
    "exact_sums",
]

_EPS = float(np.finfo(np.float64).eps)


# ---------------------------------------------------------------------------- integration
def _along_rule(q: int) -> tuple[np.ndarray, np.ndarray]:
    """``q`` Gauss-Legendre points and weights on [0, 1]."""
    x, w = gauss_legendre(q)
    return (1 + x) / 2, w / 2


@lru_cache(maxsize=256)
def _arc_points(n: int, frequency: float) -> int:
    """Gauss-Legendre points that integrate ``cos(ω x)`` on [-1, 1] to round-off.

    For every ω up to ``frequency``; at least n, at most
    :data:`~blockmesh.numerics.gauss.MAX_POINTS` - 1.
    """
    exact = 2 * np.sinc(frequency / np.pi)
    for q in range(n, MAX_POINTS):
        x, w = gauss_legendre(q)
        if abs(float(w @ np.cos(frequency * x)) - exact) <= 2 * _EPS:
            return q
    return MAX_POINTS - 1


def along_points(curve: Curve, n: int, span: float) -> int:
    """Points along a piece of ``curve`` spanning ``span`` in parameter, for a rule of order n.

    With them the sector's integral of a polynomial of degree ``2n - 1`` is exact on a polyline
    or spline piece (the integrand is a polynomial of degree ``2n - 1``, resp. ``6n + 2``, in
    the parameter) and exact to round-off on an arc (a trigonometric polynomial of degree ``2n``
    in the angle).

    Examples
    --------
    >>> from blockmesh.curves import Arc, Spline
    >>> quarter = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    >>> along_points(quarter, 5, 1.0), along_points(quarter, 5, 1 / 64)
    (16, 5)
    >>> along_points(Spline(points=[(1, 1)]).with_ends((0, 0), (2, 0)), 5, 0.5)
    17
    """
    if isinstance(curve, Arc):
        angle = abs(curve.sweep * span)
        # Frequencies up to n * angle on [-1, 1]; rounded up so that nearby spans share a rule.
        return _arc_points(n, float(np.ceil(n * angle * 64) / 64))
    if isinstance(curve, Spline):
        return 3 * n + 2
    return n


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _split_rule(rule: Rule, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The rule's radial nodes and weights (the factor r included) and its nodes along an edge.

    A rule's weights are a product ``u_j v_k`` with ``Σ v_k = 1`` and ``Σ u_j = 1/2``.
    """
    nodes = rule.nodes(n)
    return nodes.r, nodes.weights.sum(axis=1), 0.5 + nodes.h, 2 * nodes.weights.sum(axis=0)


@dataclass(frozen=True, eq=False)
class CurvedCells:
    """Integrals over the true cells with curved edges of a mesh.

    Attributes
    ----------
    cells : ndarray (K,) int64
        The cells with a curved edge.
    values : ndarray (K,)
        The integral of f over each (curved) cell.
    magnitude : ndarray (K,)
        The sum of ``|integral|`` over each cell's sectors.
    absolute : ndarray (K,) or None
        The integral of ``|f|``, when asked for.
    """

    cells: np.ndarray
    values: np.ndarray
    magnitude: np.ndarray
    absolute: np.ndarray | None


def curved_cells(
    mesh: Mesh, f, rule: Rule, n: int, *, chunk: int = 1 << 15, absolute: bool = False
) -> CurvedCells:
    """Integrate ``f`` over every cell of ``mesh`` that has a curved edge (module docstring).

    The apex of the sectors is the cell's vertex mean whatever the rule's layout; the rule's
    radial nodes and weights are used, with its nodes along the straight edges and
    :func:`along_points` Gauss-Legendre points along each piece of a curve. ``f`` is a
    vectorised ``f(x, y)``.
    """
    curves = mesh.curves
    none = np.zeros(0)
    if curves is None or len(curves) == 0:
        return CurvedCells(np.zeros(0, dtype=np.int64), none, none, none if absolute else None)
    row, forward = curved_slots(mesh.cells, mesh.n_points, curves)
    cells = np.flatnonzero(np.any(row >= 0, axis=1))
    corners = mesh.points[mesh.cells[cells]]  # (K, 5, 2)
    centre = (((corners[:, 0] + corners[:, 1]) + corners[:, 2]) + corners[:, 3]) + corners[:, 4]
    centre /= 5
    r, wr, s, ws = _split_rule(rule, n)
    # Every sector as points (P, 2) and weights (P,), numbered by a sector id; cell of a sector.
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    sector_cell: list[np.ndarray] = []

    def add(c: np.ndarray, gamma: np.ndarray, tangent: np.ndarray, w: np.ndarray, owner):
        """Sectors from apexes c (S, 2) to edges gamma (S, Q, 2), weights w (Q,) along."""
        first = sum(a.size for a in sector_cell)
        jac = _cross2(gamma - c[:, None, :], tangent)  # (S, Q)
        xy = (1 - r)[None, :, None, None] * c[:, None, None, :] + r[None, :, None, None] * gamma[
            :, None, :, :
        ]
        weight = wr[None, :, None] * (jac * w)[:, None, :]
        ids = np.repeat(np.arange(first, first + owner.size), weight[0].size)
        parts.append((xy.reshape(-1, 2), weight.reshape(-1), ids))
        sector_cell.append(owner)

    # Triangles over the straight edges: γ(s) = a + s (b - a).
    k_cell, k_edge = np.nonzero(row[cells] < 0)
    a = corners[k_cell, k_edge]
    b = corners[k_cell, (k_edge + 1) % 5]
    gamma = a[:, None, :] + s[None, :, None] * (b - a)[:, None, :]
    add(centre[k_cell], gamma, np.broadcast_to((b - a)[:, None, :], gamma.shape), ws, k_cell)
    # Sectors over the curved edges, piece by piece.
    c_cell, c_edge = np.nonzero(row[cells] >= 0)
    rows = row[cells][c_cell, c_edge]
    ahead = forward[cells][c_cell, c_edge]
    t0 = np.where(ahead, curves.start[rows], curves.stop[rows])
    t1 = np.where(ahead, curves.stop[rows], curves.start[rows])
    for k, curve in enumerate(curves.curves):
        mine = np.flatnonzero(curves.curve[rows] == k)
        if mine.size == 0:
            continue
        owner, lo, hi = curve.pieces(t0[mine], t1[mine])
        owner = c_cell[mine][owner]
        q = np.array([along_points(curve, n, span) for span in np.abs(hi - lo)])
        for points in np.unique(q).tolist():
            sel = q == points
            sigma, wsigma = _along_rule(points)
            span = (hi - lo)[sel]
            t = lo[sel][:, None] + span[:, None] * sigma
            tangent = curve.derivative(t) * span[:, None, None]
            add(centre[owner[sel]], curve.point(t), tangent, wsigma, owner[sel])
    points = np.concatenate([p[0] for p in parts])
    weights = np.concatenate([p[1] for p in parts])
    sector = np.concatenate([p[2] for p in parts])
    owners = np.concatenate(sector_cell)
    n_sectors = owners.size
    per_sector = np.zeros(n_sectors)
    per_sector_abs = np.zeros(n_sectors) if absolute else None
    with np.errstate(all="ignore"):
        for first in range(0, weights.size, chunk):
            part = slice(first, first + chunk)
            x, y = points[part, 0], points[part, 1]
            values = np.broadcast_to(np.asarray(f(x, y), dtype=np.float64), x.shape)
            if not np.all(np.isfinite(values)):
                bad = int(np.flatnonzero(~np.isfinite(values))[0])
                cell = int(cells[owners[sector[part][bad]]])
                raise ExpressionError(
                    f"f is not finite ({values[bad]}) at (x, y) = ({float(x[bad])!r}, "
                    f"{float(y[bad])!r}), a quadrature point of cell {cell}; the integrand "
                    "must be finite on the domain"
                )
            per_sector += np.bincount(sector[part], values * weights[part], minlength=n_sectors)
            if per_sector_abs is not None:
                per_sector_abs += np.bincount(
                    sector[part], np.abs(values * weights[part]), minlength=n_sectors
                )
    total = np.bincount(owners, per_sector, minlength=cells.size)
    magnitude = np.bincount(owners, np.abs(per_sector), minlength=cells.size)
    total_abs = (
        None
        if per_sector_abs is None
        else np.bincount(owners, per_sector_abs, minlength=cells.size)
    )
    return CurvedCells(cells, total, magnitude, total_abs)


def exact_sums(sums: CellSums, mesh: Mesh, f, rule: Rule, n: int, exact_geometry: bool) -> CellSums:
    """``sums`` (a rule's cell sums) with the cells that have curved edges integrated exactly.

    Returns ``sums`` itself when ``exact_geometry`` is False or the mesh has no curves. The
    screen estimate of a curved cell becomes twice the difference to order ``n + 1`` over the
    true cell.

    Examples
    --------
    >>> import blockmesh
    >>> from blockmesh.quadrature import RULES
    >>> from blockmesh.quadrature.kernel import cell_sums
    >>> disc = blockmesh.load_domain("disc").block_mesh()
    >>> one = lambda x, y: np.ones_like(x)
    >>> straight = cell_sums(disc, one, RULES["paper"], 2, 1 << 15)
    >>> round(float(exact_sums(straight, disc, one, RULES["paper"], 2, True).values.sum()), 14)
    3.14159265358979
    """
    if not exact_geometry or mesh.curves is None or len(mesh.curves) == 0:
        return sums

    curved = curved_cells(mesh, f, rule, n, absolute=sums.absolute is not None)

    def replaced(array: np.ndarray | None, new: np.ndarray | None) -> np.ndarray | None:
        if array is None or new is None:
            return array
        out = np.array(array)
        out[curved.cells] = new
        out.setflags(write=False)
        return out

    screen = None
    if sums.screen is not None:
        higher = curved_cells(mesh, f, rule, min(n + 1, rule.max_order)).values
        screen = 2 * np.abs(curved.values - higher)
    return CellSums(
        replaced(sums.values, curved.values),  # type: ignore[arg-type]
        replaced(sums.absolute, curved.absolute),
        replaced(sums.screen, screen),
        replaced(sums.magnitude, curved.magnitude),
    )
