"""Measures and integrals over the true curved cells of a mesh (``exact_geometry=True``).

A cell with curved edges is split from a centre ``c`` into straight triangles (its straight edges)
and curved sectors (its curved edges). A sector is the image of the unit square under the paper's
map with the curve in place of the straight edge (``docs/mathematics.md`` §6),

    x(r, s) = (1 - r) c + r γ(s),   dx dy = r det(γ(s) - c, γ'(s)) dr ds,

so the rule in ``r`` is the paper's and the rule in ``s`` runs along the curve. The determinant is
signed: the sectors then add up to the cell by Green's theorem whatever the centre, even where a
concave curve hides part of the cell from it. Areas have closed forms: the straight cell's area
plus, for every curved edge, the signed area between the curve and its chord
(:meth:`blockmesh.curves.Curve.segment_area`).

Examples
--------
>>> import math
>>> import blockmesh
>>> from blockmesh.curves import Arc
>>> corners = [(1, 0), (math.cos(1.2), math.sin(1.2)), (0, 0.4), (0, 0), (0.5, -0.1)]
>>> d = blockmesh.Domain.from_blocks(corners, [(0, 1, 2, 3, 4)], edges={(0, 1): Arc(center=(0, 0))})
>>> mesh = d.block_mesh()
>>> bool(cell_areas(mesh).sum() > mesh.area)
True
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from .curved_refinement import curved_slots
from .curves import Arc, Curve, CurvedEdges, Spline
from .errors import ExpressionError
from .gauss import MAX_POINTS, gauss_jacobi, gauss_legendre

if TYPE_CHECKING:
    from .mesh import Mesh

__all__ = [
    "along_points",
    "area_corrections",
    "cell_areas",
    "curved_cell_integrals",
    "integrate_exact_geometry",
]

_EPS = float(np.finfo(np.float64).eps)


def area_corrections(cells: np.ndarray, n_points: int, curves: CurvedEdges | None) -> np.ndarray:
    """For every cell, the signed area between its curved edges and their chords, shape (M,).

    Positive where a curve bulges out of its cell. Cells without curved edges get 0.
    """
    cells = np.asarray(cells, dtype=np.int64)
    out = np.zeros(cells.shape[0])
    if curves is None or len(curves) == 0:
        return out
    row, forward = curved_slots(cells, n_points, curves)
    cell, _ = np.nonzero(row >= 0)
    rows, ahead = row[row >= 0], forward[row >= 0]
    first = np.where(ahead, curves.start[rows], curves.stop[rows])
    last = np.where(ahead, curves.stop[rows], curves.start[rows])
    for k, curve in enumerate(curves.curves):
        mine = curves.curve[rows] == k
        if np.any(mine):
            np.add.at(out, cell[mine], curve.segment_area(first[mine], last[mine]))
    return out


def cell_areas(mesh: Mesh) -> np.ndarray:
    """Area of every cell bounded by its curved edges (the straight area where it has none)."""
    return mesh.cell_areas() + area_corrections(mesh.cells, mesh.n_points, mesh.curves)


# ---------------------------------------------------------------------------- integration
def _radial_rule(rule: str, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Points ``r`` in (0, 1) and weights for ``∫_0^1 r g(r) dr`` (the factor r included)."""
    if rule == "paper":
        x, w = gauss_legendre(n + 1)
        r = (1 + x) / 2
        return r, w / 2 * r
    x, w = gauss_jacobi(n, 0, 1)
    return (1 + x) / 2, w / 4


def _along_rule(q: int) -> tuple[np.ndarray, np.ndarray]:
    """``q`` Gauss-Legendre points and weights on [0, 1]."""
    x, w = gauss_legendre(q)
    return (1 + x) / 2, w / 2


@lru_cache(maxsize=256)
def _arc_points(n: int, frequency: float) -> int:
    """Gauss-Legendre points that integrate ``cos(ω x)`` on [-1, 1] to round-off.

    For every ω up to ``frequency``; at least n, at most :data:`~blockmesh.gauss.MAX_POINTS` - 1.
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
    """
    if isinstance(curve, Arc):
        angle = abs(curve.sweep * span)
        # Frequencies up to n * angle on [-1, 1]; rounded up so that nearby spans share a rule.
        return _arc_points(n, float(np.ceil(n * angle * 64) / 64))
    if isinstance(curve, Spline):
        return 3 * n + 2
    return n


def _polygon_points(c, a, b, r, wr, s, ws):
    """Points (T, R, S, 2) and weights (T, R, S) of the triangles (c, a, b)."""
    edge = a[:, None, :] + s[None, :, None] * (b - a)[:, None, :]  # (T, S, 2)
    xy = (1 - r)[None, :, None, None] * c[:, None, None, :] + r[None, :, None, None] * edge[:, None]
    twice_area = _cross2(a - c, b - c)
    return xy, np.multiply.outer(twice_area, np.multiply.outer(wr, ws))


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def curved_cell_integrals(
    mesh: Mesh, f, *, order: int, rule: str = "paper", chunk: int = 1 << 15
) -> tuple[np.ndarray, np.ndarray]:
    """Integrals of ``f`` over the true curved cells: ``(cell ids, integrals)``.

    Every cell with a curved edge is split from its vertex mean into the triangles over its
    straight edges and the sectors over its curved edges (module docstring). The rule in ``r`` is
    the rule's (``"paper"``: n + 1 Gauss-Legendre points with the factor r; ``"jacobi"`` and
    ``"fan"``: n Gauss-Jacobi points), n Gauss-Legendre points run along a straight edge and
    :func:`along_points` along each piece of a curve. Polynomials of degree ``2n - 1`` are
    integrated exactly (to round-off on arcs). ``f`` is a vectorised ``f(x, y)``.
    """
    curves = mesh.curves
    if curves is None or len(curves) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0)
    row, forward = curved_slots(mesh.cells, mesh.n_points, curves)
    cells = np.flatnonzero(np.any(row >= 0, axis=1))
    local = np.full(mesh.n_cells, -1)
    local[cells] = np.arange(cells.size)
    corners = mesh.points[mesh.cells[cells]]  # (K, 5, 2)
    centre = (((corners[:, 0] + corners[:, 1]) + corners[:, 2]) + corners[:, 3]) + corners[:, 4]
    centre /= 5
    r, wr = _radial_rule(rule, order)
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (points, weights, owner)
    # Triangles over the straight edges.
    straight_cell, straight_edge = np.nonzero(row[cells] < 0)
    s, ws = _along_rule(order)
    xy, weight = _polygon_points(
        centre[straight_cell],
        corners[straight_cell, straight_edge],
        corners[straight_cell, (straight_edge + 1) % 5],
        r,
        wr,
        s,
        ws,
    )
    parts.append((xy.reshape(-1, 2), weight.reshape(-1), np.repeat(straight_cell, weight[0].size)))
    # Sectors over the curved edges, piece by piece.
    curved_cell, curved_edge = np.nonzero(row[cells] >= 0)
    rows = row[cells][curved_cell, curved_edge]
    ahead = forward[cells][curved_cell, curved_edge]
    t0 = np.where(ahead, curves.start[rows], curves.stop[rows])
    t1 = np.where(ahead, curves.stop[rows], curves.start[rows])
    for k, curve in enumerate(curves.curves):
        mine = np.flatnonzero(curves.curve[rows] == k)
        if mine.size == 0:
            continue
        owner, a, b = curve.pieces(t0[mine], t1[mine])
        owner = curved_cell[mine][owner]
        q = np.array([along_points(curve, order, span) for span in np.abs(b - a)])
        for points in np.unique(q):
            sel = q == points
            sigma, wsigma = _along_rule(int(points))
            span = (b - a)[sel]
            t = a[sel][:, None] + span[:, None] * sigma
            gamma = curve.point(t)  # (P, S, 2)
            tangent = curve.derivative(t) * span[:, None, None]
            c = centre[owner[sel]][:, None, :]
            jac = _cross2(gamma - c, tangent)  # (P, S)
            xy = (1 - r)[None, :, None, None] * c[:, None, :, :] + r[None, :, None, None] * gamma[
                :, None, :, :
            ]
            weight = wr[None, :, None] * (jac * wsigma)[:, None, :]
            parts.append(
                (xy.reshape(-1, 2), weight.reshape(-1), np.repeat(owner[sel], weight[0].size))
            )
    points = np.concatenate([p[0] for p in parts])
    weights = np.concatenate([p[1] for p in parts])
    owners = np.concatenate([p[2] for p in parts])
    out = np.zeros(cells.size)
    with np.errstate(all="ignore"):
        for first in range(0, weights.size, chunk):
            part = slice(first, first + chunk)
            x, y = points[part, 0], points[part, 1]
            values = np.broadcast_to(np.asarray(f(x, y), dtype=np.float64), x.shape)
            if not np.all(np.isfinite(values)):
                bad = int(np.flatnonzero(~np.isfinite(values))[0])
                raise ExpressionError(
                    f"f is not finite ({values[bad]}) at (x, y) = ({float(x[bad])!r}, "
                    f"{float(y[bad])!r}), a quadrature point of cell "
                    f"{int(cells[owners[part][bad]])}; the integrand must be finite on the domain"
                )
            out += np.bincount(owners[part], weights=values * weights[part], minlength=cells.size)
    return cells, out


def integrate_exact_geometry(
    target,
    f,
    *,
    order: int,
    level: int | None = None,
    rule: str = "paper",
    per_cell: bool = False,
) -> float | np.ndarray:
    """Integrate ``f`` over the true curved domain (``exact_geometry``).

    :func:`blockmesh.integrate` on the straight cells, :func:`curved_cell_integrals` on the cells
    with curved edges. Arguments as :func:`blockmesh.integrate`. On a mesh without curves this is
    :func:`blockmesh.integrate` itself.

    Examples
    --------
    >>> import blockmesh
    >>> disc = blockmesh.load_domain("disc")
    >>> value = integrate_exact_geometry(disc, "x^2 + y^2", order=2)  # π/2 on the unit disc
    >>> abs(value - 1.5707963267948966) < 1e-14
    True
    """
    from .expr import parse_expression
    from .quadrature import _mesh_of, integrate

    mesh = _mesh_of(target, level)
    function = parse_expression(f) if isinstance(f, str) else f
    cells = np.array(integrate(mesh, function, order=order, rule=rule, per_cell=True))
    curved, values = curved_cell_integrals(mesh, function, order=order, rule=rule)
    cells[curved] = values
    if per_cell:
        cells.setflags(write=False)
        return cells
    return float(np.sum(cells))
