"""The kernel: quadrature points of straight-edged cells placed in chunks, and cell sums.

A rule's :class:`~blockmesh.quadrature.rule.SectorNodes` live on the unit square; on a sector
with apex ``c`` and straight edge ``γ(s) = (a + b) / 2 + h (b - a)`` the point of node
``(r, h)`` is ``(1 - r) c + r ((a + b) / 2 + h (b - a))`` (the paper's ``xs``) and the
Jacobian's determinant is the constant ``d = det(b - c, a - c)``, twice the triangle's area. Each
point is therefore a fixed linear combination of the cell's 5 corners, ``x_points = x_corners @
G``: one matrix product per chunk of cells. (A curved edge would replace this placement by
``(1 - r) c + r γ(s)`` and multiply each weight by ``|det(γ(s) - c, γ'(s))|``; the rules do not
change. See :mod:`blockmesh.quadrature.rule`.)

Points are generated and ``f`` evaluated in chunks of at most ``chunk`` points, so memory stays
bounded at any level and order.

Examples
--------
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.quadrature import RULES
>>> usp = Mesh.from_cells([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], [[0, 1, 2, 3, 4]])
>>> sums = cell_sums(usp, lambda x, y: np.ones_like(x), RULES["paper"], 2, DEFAULT_CHUNK)
>>> round(float(sums.values[0]), 14)  # the area
6.0
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from blockmesh.errors import ExpressionError
from blockmesh.mesh.mesh import Mesh
from blockmesh.quadrature.estimate import NullRule
from blockmesh.quadrature.rule import Rule

__all__ = [
    "DEFAULT_CHUNK",
    "CellSums",
    "cell_sums",
    "chunks",
    "evaluate",
    "straight_tables",
    "total_of",
]

#: Points per chunk: f is evaluated on arrays of at most this many points.
DEFAULT_CHUNK = 1 << 15

#: Cells whose corners and triangle areas are computed at once.
_GEOMETRY_BLOCK = 1 << 12

Function = Callable[[np.ndarray, np.ndarray], np.ndarray]


@lru_cache(maxsize=128)
def straight_tables(rule: Rule, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(G (5, T*P), weights (P,))``: every point of a straight cell from its 5 corners.

    Column ``t*P + p`` of ``G`` holds the weights of the 5 corners in point ``p`` of sector
    ``t``; a sector's integral is ``d * Σ weights * f``.
    """
    nodes = rule.nodes(n)
    n_along = nodes.h.size
    apex_w = np.repeat(nodes.one_minus_r, n_along)  # radial index outer
    mid_w = np.repeat(nodes.r, n_along)
    half_w = (nodes.r[:, None] * nodes.h[None, :]).reshape(-1)
    per_sector = np.zeros((5, rule.sectors_per_cell, apex_w.size))
    for sector, (apex, k, i) in enumerate(rule.layout.sectors):
        if apex is None:  # the vertex mean
            per_sector[:, sector] += apex_w / 5
        else:
            per_sector[apex, sector] += apex_w
        per_sector[k, sector] += mid_w / 2 + half_w
        per_sector[i, sector] += mid_w / 2 - half_w
    g = per_sector.reshape(5, -1)
    weights = np.ascontiguousarray(nodes.weights.reshape(-1))
    g.setflags(write=False)
    weights.setflags(write=False)
    return g, weights


def chunks(
    mesh: Mesh, rule: Rule, n: int, chunk: int
) -> Iterator[tuple[slice, np.ndarray, np.ndarray, np.ndarray]]:
    """Per chunk of cells: ``(cells, xs (C*T, P), ys (C*T, P), d (C*T,))``.

    ``xs`` and ``ys`` live in buffers reused from chunk to chunk: use them before the next one.
    Corners and ``d`` are computed for blocks of at least :data:`_GEOMETRY_BLOCK` cells at once
    (they do not depend on the order), the points per chunk.
    """
    g = straight_tables(rule, n)[0].copy()  # numpy's matmul is ~2x slower with a read-only operand
    n_tri = rule.sectors_per_cell
    per_cell = g.shape[1]
    step = max(1, min(chunk // per_cell, mesh.n_cells))
    block = max(step, _GEOMETRY_BLOCK)
    x_all = np.ascontiguousarray(mesh.points[:, 0])
    y_all = np.ascontiguousarray(mesh.points[:, 1])
    x_buffer = np.empty((step, per_cell))
    y_buffer = np.empty((step, per_cell))
    for first in range(0, mesh.n_cells, block):
        cells = mesh.cells[first : first + block]
        X, Y, d_block = _corners_and_areas(x_all, y_all, cells, rule)
        for start in range(0, cells.shape[0], step):
            c = min(step, cells.shape[0] - start)
            xs = np.matmul(X[start : start + c], g, out=x_buffer[:c]).reshape(c * n_tri, -1)
            ys = np.matmul(Y[start : start + c], g, out=y_buffer[:c]).reshape(c * n_tri, -1)
            d = d_block[start * n_tri : (start + c) * n_tri]
            yield slice(first + start, first + start + c), xs, ys, d


def _corners_and_areas(
    x_all: np.ndarray, y_all: np.ndarray, cells: np.ndarray, rule: Rule
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Corner coordinates (B, 5) and twice the sector areas ``d`` (B*T,) of a block of cells.

    ``d`` is the paper's ``(xc-xi)(yk-yi) - (xk-xi)(yc-yi)``, evaluated as
    ``(xk-xc)(yi-yc) - (xi-xc)(yk-yc)`` (the same number up to round-off, fewer passes).
    """
    ring = np.empty((6, cells.shape[0]), dtype=np.int64)  # corner-major: rows are contiguous
    ring[:5] = cells.T
    ring[5] = cells[:, 0]
    layout = rule.layout
    if layout.orient is not None:
        ring = layout.orient(x_all, y_all, ring)
    x_ring, y_ring = x_all[ring], y_all[ring]  # (6, B): corner 0 repeated at the end
    X, Y = x_ring[:5], y_ring[:5]
    if any(apex is None for apex, _, _ in layout.sectors):  # the paper's vertex mean, in its order
        xc = ((((X[0] + X[1]) + X[2]) + X[3]) + X[4]) / 5
        yc = ((((Y[0] + Y[1]) + Y[2]) + Y[3]) + Y[4]) / 5
    d = np.empty((layout.sectors_per_cell, cells.shape[0]))
    for t, (apex, k, i) in enumerate(layout.sectors):
        ax, ay = (xc, yc) if apex is None else (X[apex], Y[apex])
        d[t] = (X[k] - ax) * (Y[i] - ay) - (X[i] - ax) * (Y[k] - ay)
    return X.T, Y.T, d.T.reshape(-1)


def evaluate(f: Function, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """``f(xs, ys)`` as a float64 array of ``xs.shape`` (scalars broadcast), checked."""
    values = f(xs, ys)
    if type(values) is not np.ndarray or values.shape != xs.shape:
        values = np.asarray(values)
        if values.ndim != 0:
            raise ExpressionError(
                f"f(x, y) returned an array of shape {values.shape} for inputs of shape "
                f"{xs.shape}; f must be vectorised (elementwise on numpy arrays)"
            )
        values = np.full(xs.shape, values)
    if values.dtype != np.float64:
        if np.iscomplexobj(values):
            raise ExpressionError(
                "f(x, y) returned complex values; integrate its real and imaginary parts"
            )
        try:
            values = values.astype(np.float64)
        except (TypeError, ValueError):
            raise ExpressionError(f"f(x, y) returned {values.dtype} values, not numbers") from None
    return values


@dataclass(frozen=True, eq=False)
class CellSums:
    """Per-cell results of one rule and order over a mesh.

    Attributes
    ----------
    values : ndarray (M,)
        The integral over each cell.
    absolute : ndarray (M,) or None
        The rule applied to ``|f|`` (when asked): the scale of the round-off.
    screen : ndarray (M,) or None
        The null-rule error estimate of each cell (when a screen is asked for; see
        :mod:`blockmesh.quadrature.estimate`), from its sectors' coefficients summed.
    magnitude : ndarray (M,) or None
        With the screen: the sum of ``|integral|`` over each cell's sectors, the scale the
        estimate is compared with (free, and unlike ``|values|`` not zero for a cell over which
        an odd integrand cancels).
    """

    values: np.ndarray
    absolute: np.ndarray | None
    screen: np.ndarray | None
    magnitude: np.ndarray | None = None


def cell_sums(
    mesh: Mesh,
    f: Function,
    rule: Rule,
    n: int,
    chunk: int,
    *,
    absolute: bool = False,
    screen: NullRule | None = None,
) -> CellSums:
    """Apply ``rule`` of order ``n`` to every cell of ``mesh``.

    Sectors with ``d == 0`` (a 180-degree corner of the cell) are skipped, as in the paper's
    program. A non-finite cell integral raises :class:`~blockmesh.errors.ExpressionError`
    naming the cell and the first quadrature point where ``f`` is not finite.
    """
    _, weights = straight_tables(rule, n)
    n_tri = rule.sectors_per_cell
    ones = np.ones(n_tri)
    out = np.empty(mesh.n_cells)
    out_abs = np.empty(mesh.n_cells) if absolute else None
    out_screen = np.empty(mesh.n_cells) if screen is not None else None
    out_magnitude = np.empty(mesh.n_cells) if screen is not None else None
    screening = (
        None
        if screen is None or out_screen is None
        else _Screening(screen, out_screen, n_tri, max(chunk // (weights.size * n_tri), 1))
    )
    with np.errstate(all="ignore"):
        for cells, xs, ys, d in chunks(mesh, rule, n, chunk):
            values = evaluate(f, xs, ys)
            tri = (values @ weights) * d
            flat = not d.all()
            if flat:
                tri[d == 0] = 0.0  # the paper skips degenerate triangles (180-degree corners)
            out[cells] = tri.reshape(-1, n_tri) @ ones
            if out_abs is not None:
                tri_abs = (np.abs(values) @ weights) * np.abs(d)
                if flat:
                    tri_abs[d == 0] = 0.0
                out_abs[cells] = tri_abs.reshape(-1, n_tri) @ ones
            if screening is not None and out_magnitude is not None:
                out_magnitude[cells] = np.abs(tri).reshape(-1, n_tri) @ ones
                screening.add(cells, values, d)
        if screening is not None:
            screening.flush()
    if not np.isfinite(out).all():
        raise _not_finite(mesh, f, rule, n, int(np.flatnonzero(~np.isfinite(out))[0]))
    for array in (out, out_abs, out_screen, out_magnitude):
        if array is not None:
            array.setflags(write=False)
    return CellSums(out, out_abs, out_screen, out_magnitude)


class _Screening:
    """Per-cell null-rule estimates: coefficients per chunk, combined a block of cells at a time.

    Per chunk, ``|values @ matrix|`` weighted by each sector's ``|d|`` is summed over the
    sectors of every cell (two small products into reused buffers); every
    :data:`_GEOMETRY_BLOCK` cells the per-cell sums are combined into estimates.
    """

    def __init__(self, screen: NullRule, out: np.ndarray, n_tri: int, cells: int) -> None:
        self.screen, self.out, self.n_tri = screen, out, n_tri
        width = screen.matrix.shape[1]
        self.matrix = screen.matrix.copy()  # writeable: numpy's matmul is slower on read-only
        self.product = np.empty((cells * n_tri, width))
        self.pending = np.empty((max(_GEOMETRY_BLOCK, cells) + cells, width))
        self.first = 0  # the first cell in ``pending``
        self.filled = 0  # cells in ``pending``

    def add(self, cells: slice, values: np.ndarray, d: np.ndarray) -> None:
        rows = values.shape[0]
        count = rows // self.n_tri
        product = np.matmul(values, self.matrix, out=self.product[:rows])
        np.abs(product, out=product)
        if self.filled == 0:
            self.first = cells.start
        weights = np.abs(d).reshape(count, self.n_tri)
        if not d.all():
            product[d == 0] = 0.0  # skipped sectors (180-degree corners), even if f is NaN
        np.einsum(
            "ct,ctk->ck",
            weights,
            product.reshape(count, self.n_tri, -1),
            out=self.pending[self.filled : self.filled + count],
        )
        self.filled += count
        if self.filled >= _GEOMETRY_BLOCK:
            self.flush()

    def flush(self) -> None:
        if self.filled:
            block = self.pending[: self.filled]
            self.out[self.first : self.first + self.filled] = self.screen.combine(block)
            self.filled = 0


def scaled_sum(values: np.ndarray, factor: float = 1.0) -> float:
    """``factor * sum(values)`` for non-negative ``values``, without overflowing on the way.

    The sum of magnitudes that sets a tolerance (``sum |integral|`` of the cells) may pass the
    float64 range although the integral itself does not (``1e308*y``): the values are divided by
    their largest before summing, so a small ``factor`` (a relative tolerance) still gives the
    finite threshold it should, and only a result truly beyond the range is ``inf``.

    Parameters
    ----------
    values : numpy.ndarray
        Non-negative numbers (NaN-free).
    factor : float, optional
        A non-negative multiplier applied before scaling back.

    Returns
    -------
    float
        ``factor * sum(values)``, ``inf`` only when that is beyond the float64 range.

    Examples
    --------
    >>> scaled_sum(np.array([1e308, 1e308, 1e308, 1e308]), 0.25)
    1e+308
    >>> scaled_sum(np.array([1e308, 1e308]))
    inf
    """
    if values.size == 0:
        return 0.0
    largest = float(np.max(values))
    if largest == 0.0 or not math.isfinite(largest):
        return factor * largest
    with np.errstate(over="ignore"):
        return float(largest * (factor * float(np.sum(values / largest))))


def total_of(sums: CellSums) -> float:
    """The sum of the cell integrals; an error when it overflows although each cell is finite."""
    with np.errstate(over="ignore"):
        total = float(np.sum(sums.values))
    if not math.isfinite(total):
        worst = int(np.argmax(np.abs(sums.values)))
        raise ExpressionError(
            f"the integral overflows: every cell integral is finite (the largest, "
            f"{float(sums.values[worst]):.3g}, over cell {worst}) but their sum is beyond the "
            "float64 range (about 1.8e308); scale f down"
        )
    return total


def _not_finite(mesh: Mesh, f: Function, rule: Rule, n: int, cell: int) -> ExpressionError:
    """The error for a non-finite cell integral, naming the first bad quadrature point."""
    one = Mesh.from_cells(mesh.points, mesh.cells[cell : cell + 1])
    _, xs, ys, _ = next(chunks(one, rule, n, DEFAULT_CHUNK))
    with np.errstate(all="ignore"):
        values = evaluate(f, xs, ys).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size == 0:
        return ExpressionError(
            f"the integral over cell {cell} overflows: f is finite at its quadrature points but "
            "the weighted sum is not (about 1.8e308 is the largest float64); scale f down"
        )
    k = int(bad[0])
    x, y = float(xs.reshape(-1)[k]), float(ys.reshape(-1)[k])
    return ExpressionError(
        f"f is not finite ({values[k]}) at (x, y) = ({x!r}, {y!r}), a quadrature point "
        f"of cell {cell}; the integrand must be finite on the domain"
    )
