"""Composite quadrature over all-pentagon meshes: the paper's rule and cheaper ones.

Every rule splits each (convex) cell into triangles ``(c, a, b)`` and integrates over each one in
collapsed coordinates,

    ∫∫_T f = 2A ∫_0^1 ∫_0^1 r f((1 - r) c + r ((1 - s) a + s b)) dr ds,

with a tensor Gauss rule in ``(r, s)``. The rules (``order = n``):

======  =================================  ============================  ==========  ======
rule    triangles per cell                 points in (r, s) per triangle  per cell    degree
======  =================================  ============================  ==========  ======
paper   5, apex at the cell's vertex mean  (n+1) Gauss-Legendre x n GL   5 n (n+1)   2n - 1
jacobi  5, apex at the cell's vertex mean  n Gauss-Jacobi(0, 1) x n GL   5 n^2       2n - 1
fan     3, fanned from the cell's corner 0 n Gauss-Jacobi(0, 1) x n GL   3 n^2       2n - 1
======  =================================  ============================  ==========  ======

"degree" is the largest total degree integrated exactly, and it is sharp (a polynomial of degree
m becomes ``r^(i+j+1) s^j`` with ``i + j <= m``; n Gauss-Legendre points in ``s`` are exact to
degree 2n - 1, and so are n+1 Legendre or n Jacobi(0, 1) points in ``r`` with the factor ``r``).

``"paper"`` is the rule of the seed's FIFTH program
(``compositeboundaryintegrationconvexpolygonofpentagons_n``): the apex is the vertex mean, the
weights are its ``ps * wt`` with ``wt = ww * www / 4``, the points its ``xs, ys`` and the factor
its ``d``; triangles with ``d == 0`` are skipped as there. It reproduces Tables 1-11 (to a few
1e-15 of ∫|f|; the tests compare it with a literal transcription of the program's loops). Here
each point is formed as a fixed linear combination of the cell's 5 corners (one matrix product per
chunk of cells), which equals the program's ``xs`` up to round-off. ``"jacobi"`` absorbs the
factor ``r`` into the radial weight (n/(n+1) of the points, and consistently a little fewer
points than ``"paper"`` for the same accuracy on the tables' integrands). ``"fan"`` uses 3
triangles instead of 5, fanned from the corner whose diagonals are shortest: 3/5 of the
``"jacobi"`` points per order, but its triangles are longer, so for the same accuracy it needs
up to 40 % fewer points on compact cells and smooth integrands and up to twice as many on
oscillating or peaked ones (``benchmarks/bench_integrate.py``).

Points are generated and ``f`` evaluated in chunks of at most ``chunk`` points (default
:data:`DEFAULT_CHUNK`, sized for the CPU caches), so memory stays bounded at any level and order.
Gauss rules are accurate to the last bit (:mod:`blockmesh.gauss`).

Examples
--------
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> sp = Mesh.from_cells([(-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)], [[0, 1, 2, 3, 4]])
>>> round(integrate(sp, "(x^4 + y^3) / (1 + x^2)", order=10, level=2), 13)
1.9240305426326
>>> exact = integrate(sp, "x^2 * y", order=2)  # degree 3 = 2n - 1: exact for every rule
>>> abs(integrate(sp, lambda x, y: x * x * y, order=2, rule="fan") - exact) < 1e-15
True
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .errors import BlockMeshError, ExpressionError, ResourceError
from .expr import parse_expression
from .gauss import MAX_POINTS, gauss_jacobi, gauss_legendre
from .mesh import Mesh
from .refinement import refine

__all__ = [
    "DEFAULT_CHUNK",
    "RULES",
    "IntegrationResult",
    "RuleInfo",
    "integrate",
    "integrate_to_tolerance",
    "quadrature_points",
    "rule_info",
]

#: Points per chunk: f is evaluated on arrays of at most this many points.
DEFAULT_CHUNK = 1 << 15

#: The rules and what they are.
RULES: dict[str, str] = {
    "paper": "the paper's rule: 5 triangles at the vertex mean, (n+1) x n Gauss-Legendre",
    "jacobi": "5 triangles at the vertex mean, n x n Gauss-Jacobi(0,1) x Gauss-Legendre",
    "fan": "3 triangles fanned from the corner with the shortest diagonals, n x n as jacobi",
}

_TRIANGLES = {"paper": 5, "jacobi": 5, "fan": 3}

#: Cells whose corners and triangle areas are computed at once.
_GEOMETRY_BLOCK = 1 << 12

#: Relative round-off floor of a result, times ∫|f|: no estimate is taken below it.
_ROUNDOFF = 4 * np.finfo(np.float64).eps

Integrand = str | Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class RuleInfo:
    """What a rule of a given order costs and guarantees.

    Examples
    --------
    >>> info = rule_info("fan", 5)
    >>> info.points_per_cell, info.degree
    (75, 9)
    """

    rule: str
    order: int
    points_per_triangle: int
    triangles_per_cell: int
    degree: int

    @property
    def points_per_cell(self) -> int:
        """Evaluations of f per cell."""
        return self.points_per_triangle * self.triangles_per_cell


def rule_info(rule: str, order: int) -> RuleInfo:
    """Points and exactness degree of ``rule`` at ``order``.

    Examples
    --------
    >>> rule_info("paper", 10)
    RuleInfo(rule='paper', order=10, points_per_triangle=110, triangles_per_cell=5, degree=19)
    """
    _check_rule(rule)
    n = _check_order(order)
    per_triangle = n * (n + 1) if rule == "paper" else n * n
    return RuleInfo(rule, n, per_triangle, _TRIANGLES[rule], 2 * n - 1)


# --------------------------------------------------------------------------- rule tables
@lru_cache(maxsize=128)
def _tables(rule: str, n: int) -> tuple[np.ndarray, np.ndarray]:
    """``(G (5, T*P), weights (P,))``: every quadrature point of a cell from its 5 corners.

    On a triangle with apex ``c`` and edge ``k -> i`` (the paper's ``xk``, ``xi``) a point is
    ``qs c + ps ((xi + xk) / 2 + (xk - xi) t / 2)`` (the paper's ``xs``). The apex is the vertex
    mean (``"paper"``, ``"jacobi"``) or corner 0 (``"fan"``; the corners are rotated per cell to
    put the chosen apex there), so each point is a fixed linear
    combination of the cell's corners: ``x_points = x_corners @ G``, one matrix product per
    chunk of cells. A triangle's integral is ``d * Σ weights * f`` with ``d`` twice its area.
    """
    t, wt = gauss_legendre(n)  # along the edge: the paper's ss, ww
    if rule == "paper":
        x, wx = gauss_legendre(n + 1)  # radial: the paper's sss, www
        ps = (1 + x) / 2
        weights = ps[:, None] * (np.multiply.outer(wx, wt) / 4)  # ps * wt, wt = ww*www/4
    else:
        x, wx = gauss_jacobi(n, 0, 1)  # weight (1 + x) = 2r: absorbs the Jacobian factor r
        ps = (1 + x) / 2
        weights = np.multiply.outer(wx, wt) / 8
    qs = (1 - x) / 2
    apex_w = np.repeat(qs, n)  # P = len(ps) * n points, radial index outer
    mid_w = np.repeat(ps, n)
    half_w = (ps[:, None] * (t[None, :] / 2)).reshape(-1)
    n_points = apex_w.size
    g = np.zeros((5, _TRIANGLES[rule], n_points))
    for tri, (apex, k, i) in enumerate(_triangles(rule)):
        if apex is None:
            g[:, tri] += apex_w / 5
        else:
            g[apex, tri] += apex_w
        g[k, tri] += mid_w / 2 + half_w
        g[i, tri] += mid_w / 2 - half_w
    g = g.reshape(5, -1)
    weights = np.ascontiguousarray(weights.reshape(-1))
    g.setflags(write=False)
    weights.setflags(write=False)
    return g, weights


def _triangles(rule: str) -> list[tuple[int | None, int, int]]:
    """(apex corner or None for the vertex mean, first corner k, second corner i) per triangle."""
    if rule == "fan":
        return [(0, 1, 2), (0, 2, 3), (0, 3, 4)]
    return [(None, e, (e + 1) % 5) for e in range(5)]


# --------------------------------------------------------------------------- argument checks
def _check_rule(rule: str) -> str:
    if rule not in RULES:
        raise BlockMeshError(f"unknown rule {rule!r}; choose one of: {', '.join(RULES)}")
    return rule


def _check_order(order: int) -> int:
    if (
        isinstance(order, bool)
        or not isinstance(order, int | np.integer)
        or not 1 <= order < MAX_POINTS
    ):
        raise BlockMeshError(f"order must be a whole number in 1..{MAX_POINTS - 1}, got {order!r}")
    return int(order)


def _integrand(f: Integrand) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    if isinstance(f, str):
        return parse_expression(f)
    if not callable(f):
        raise ExpressionError(
            f"f must be a callable f(x, y) or an expression string, not {type(f).__name__}"
        )
    return f


def _mesh_of(target, level: int | None) -> Mesh:
    """The mesh to integrate over.

    A Domain refined to ``level`` (default 0), or a Mesh refined from its own level up to ``level``
    (a mesh cannot be coarsened).
    """
    if level is not None and (
        isinstance(level, bool) or not isinstance(level, int | np.integer) or level < 0
    ):
        raise BlockMeshError(f"level must be a whole number >= 0, got {level!r}")
    if isinstance(target, Mesh):
        if level is None or level == target.level:
            return target
        if level < target.level:
            raise BlockMeshError(
                f"level {level} is below the mesh's own level {target.level}; a Mesh can only be "
                "refined further (pass the Domain to integrate on a coarser level)"
            )
        return refine(target, int(level) - target.level)
    if hasattr(target, "block_mesh"):
        return refine(target, 0 if level is None else int(level))
    raise BlockMeshError(f"integrate() takes a Domain or a Mesh, not {type(target).__name__}")


# --------------------------------------------------------------------------- the kernel
def _chunks(
    mesh: Mesh, rule: str, n: int, chunk: int
) -> Iterator[tuple[slice, np.ndarray, np.ndarray, np.ndarray]]:
    """Per chunk of cells: ``(cells, xs (C*T, P), ys (C*T, P), d (C*T,))``.

    ``xs`` and ``ys`` live in buffers reused from chunk to chunk: use them before the next one.
    Corners and ``d`` are computed for blocks of at least :data:`_GEOMETRY_BLOCK` cells at once
    (they do not depend on the order), the points per chunk.
    """
    g = _tables(rule, n)[0].copy()  # numpy's matmul is ~2x slower with a read-only operand
    n_tri = _TRIANGLES[rule]
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


def _corners_and_areas(x_all: np.ndarray, y_all: np.ndarray, cells: np.ndarray, rule: str):
    """Corner coordinates (B, 5) and twice the triangle areas ``d`` (B*T,) of a block of cells.

    ``d`` is the paper's ``(xc-xi)(yk-yi) - (xk-xi)(yc-yi)``, evaluated as
    ``(xk-xc)(yi-yc) - (xi-xc)(yk-yc)`` (the same number up to round-off, fewer passes).
    """
    ring = np.empty((6, cells.shape[0]), dtype=np.int64)  # corner-major: rows are contiguous
    ring[:5] = cells.T
    ring[5] = cells[:, 0]
    if rule == "fan":
        ring = _shortest_fan(x_all, y_all, ring)
    x_ring, y_ring = x_all[ring], y_all[ring]  # (6, B): corner 0 repeated at the end
    X, Y = x_ring[:5], y_ring[:5]
    if rule == "fan":
        xc, yc = x_ring[0], y_ring[0]
        x_ring, y_ring = x_ring[1:5], y_ring[1:5]
    else:  # the paper's vertex mean, summed in its order
        xc = ((((X[0] + X[1]) + X[2]) + X[3]) + X[4]) / 5
        yc = ((((Y[0] + Y[1]) + Y[2]) + Y[3]) + Y[4]) / 5
    dx = x_ring - xc
    dy = y_ring - yc
    d = dx[:-1] * dy[1:] - dx[1:] * dy[:-1]  # (T, B)
    return X.T, Y.T, d.T.reshape(-1)


def _shortest_fan(x_all: np.ndarray, y_all: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Each cell's corners rotated so that corner 0 is the fan apex with the shortest diagonals.

    A convex pentagon has five triangulations, the fans from each corner ``a``, which use the
    diagonals ``a -> a+2`` and ``a+3 -> a``. The fan whose longer diagonal is shortest has the
    most compact triangles (for a smooth integrand, the smallest error at a given order).
    """
    x, y = x_all[ring[:5]], y_all[ring[:5]]  # (5, B)
    skip = [2, 3, 4, 0, 1]
    diagonal = np.hypot(x[skip] - x, y[skip] - y)  # row j: corner j -> j+2
    cost = np.maximum(diagonal, diagonal[[3, 4, 0, 1, 2]])  # apex a: diagonals a, a+3
    apex = np.argmin(cost, axis=0)
    order = (apex + np.arange(6)[:, None]) % 5
    return np.take_along_axis(ring[:5], order, axis=0)


def _evaluate(f, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
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
        values = values.astype(np.float64)
    return values


def _not_finite(mesh: Mesh, f, rule: str, n: int, cell: int) -> BlockMeshError:
    """The error for a non-finite cell integral, naming the first bad quadrature point."""
    one = Mesh.from_cells(mesh.points, mesh.cells[cell : cell + 1])
    _, xs, ys, _ = next(_chunks(one, rule, n, DEFAULT_CHUNK))
    with np.errstate(all="ignore"):
        values = _evaluate(f, xs, ys).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size == 0:
        return BlockMeshError(
            f"the integral over cell {cell} overflows: the weighted sum of f is not finite"
        )
    k = int(bad[0])
    x, y = float(xs.reshape(-1)[k]), float(ys.reshape(-1)[k])
    return BlockMeshError(
        f"f is not finite ({values[k]}) at (x, y) = ({x!r}, {y!r}), a quadrature point "
        f"of cell {cell}; the integrand must be finite on the domain"
    )


def _cell_integrals(mesh: Mesh, f, rule: str, n: int, chunk: int, with_abs: bool = False):
    """Per-cell integrals (M,) and, if asked, per-cell integrals of |f| (for round-off floors)."""
    _, weights = _tables(rule, n)
    n_tri = _TRIANGLES[rule]
    ones = np.ones(n_tri)
    out = np.empty(mesh.n_cells)
    out_abs = np.empty(mesh.n_cells) if with_abs else None
    with np.errstate(all="ignore"):
        for cells, xs, ys, d in _chunks(mesh, rule, n, chunk):
            values = _evaluate(f, xs, ys)
            tri = (values @ weights) * d
            if not d.all():
                tri[d == 0] = 0.0  # the paper skips degenerate triangles (180-degree corners)
            out[cells] = tri.reshape(-1, n_tri) @ ones
            if out_abs is not None:
                tri_abs = (np.abs(values) @ weights) * np.abs(d)
                out_abs[cells] = tri_abs.reshape(-1, n_tri) @ ones
    if not np.isfinite(out).all():
        raise _not_finite(mesh, f, rule, n, int(np.flatnonzero(~np.isfinite(out))[0]))
    return out, out_abs


def _check_chunk(chunk: int) -> int:
    if isinstance(chunk, bool) or not isinstance(chunk, int | np.integer) or chunk < 1:
        raise BlockMeshError(f"chunk must be a whole number of points >= 1, got {chunk!r}")
    return int(chunk)


# --------------------------------------------------------------------------- public API
def integrate(
    target,
    f: Integrand,
    *,
    order: int,
    level: int | None = None,
    rule: str = "paper",
    per_cell: bool = False,
    chunk: int = DEFAULT_CHUNK,
) -> float | np.ndarray:
    """Integrate ``f`` over a domain or mesh with a composite Gauss rule.

    Parameters
    ----------
    target : Domain or Mesh
        A Domain is refined to ``level`` first (default: its block mesh, level 0).
        A Mesh is used as it is, or refined further when ``level`` is above its own level
        (asking for a level below it raises :class:`~blockmesh.errors.BlockMeshError`).
    f : callable or str
        A vectorised ``f(x, y)`` (numpy arrays in, an array of the same shape or a scalar out)
        or an expression string (see :func:`blockmesh.expr.parse_expression`).
    order : int
        The rule's order n: exact for polynomials of total degree ``2n - 1``.
    level : int, optional
        Refinement level to integrate on (6**level cells per block).
    rule : {"paper", "jacobi", "fan"}
        See the module docstring; ``"paper"`` reproduces the paper's tables.
    per_cell : bool
        Return the integral over every cell, shape (M,), instead of the total.
    chunk : int
        Most points f is evaluated on at once (bounds the memory).

    Returns
    -------
    float or ndarray (M,)

    Raises
    ------
    BlockMeshError
        On a bad order, level, rule or target, or when f is not finite at a quadrature point
        (the message gives the point and the cell).
    ExpressionError
        When ``f`` is an invalid expression or not vectorised.

    Notes
    -----
    Cost: ``rule_info(rule, order).points_per_cell`` evaluations of f per cell, plus about
    1 ns per point to place the points and sum. Cell integrals are summed pairwise.

    Examples
    --------
    >>> from blockmesh.mesh import Mesh
    >>> usp = Mesh.from_cells([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], [[0, 1, 2, 3, 4]])
    >>> round(integrate(usp, "1", order=1), 14)  # the area
    6.0
    >>> integrate(usp, "x", order=1, level=1, per_cell=True).shape
    (6,)
    """
    n = _check_order(order)
    _check_rule(rule)
    chunk = _check_chunk(chunk)
    function = _integrand(f)
    mesh = _mesh_of(target, level)
    cells, _ = _cell_integrals(mesh, function, rule, n, chunk)
    if per_cell:
        cells.setflags(write=False)
        return cells
    return float(np.sum(cells))


def quadrature_points(
    target, *, order: int, level: int | None = None, rule: str = "paper"
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All quadrature points and weights at once: ``(x, y, w)`` with ∫∫ f ≈ Σ w f(x, y).

    Memory is ``24 * points`` bytes; :func:`integrate` works in chunks instead.

    Examples
    --------
    >>> from blockmesh.mesh import Mesh
    >>> usp = Mesh.from_cells([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], [[0, 1, 2, 3, 4]])
    >>> x, y, w = quadrature_points(usp, order=2, rule="fan")
    >>> x.shape, round(float(w.sum()), 14)
    ((12,), 6.0)
    """
    n = _check_order(order)
    _check_rule(rule)
    mesh = _mesh_of(target, level)
    _, weights = _tables(rule, n)
    xs_all, ys_all, ws_all = [], [], []
    for _, xs, ys, d in _chunks(mesh, rule, n, DEFAULT_CHUNK):
        xs_all.append(xs.reshape(-1).copy())
        ys_all.append(ys.reshape(-1).copy())
        ws_all.append(np.multiply.outer(np.where(d == 0, 0.0, d), weights).reshape(-1))
    return np.concatenate(xs_all), np.concatenate(ys_all), np.concatenate(ws_all)


# --------------------------------------------------------------------------- to a tolerance
@dataclass(frozen=True)
class IntegrationResult:
    """What :func:`integrate_to_tolerance` found.

    Attributes
    ----------
    value : float
        The last (most accurate) result.
    error_estimate : float
        ``max(|I_k - I_(k-1)|, 4 eps ∫|f|)``: the difference to the previous result (an
        over-estimate of the error of ``value`` while the results converge), never below the
        round-off floor.
    order, level : int
        Where ``value`` was computed.
    rule : str
    cells : int
        Cells of the mesh at ``level``.
    points : int
        Evaluations of f over all the attempts.
    converged : bool
        Whether ``error_estimate`` met the tolerance.
    message : str
        A one-line account (why it stopped when it did not converge).
    history : tuple of (level, order, value)
    """

    value: float
    error_estimate: float
    order: int
    level: int
    rule: str
    cells: int
    points: int
    converged: bool
    message: str
    history: tuple[tuple[int, int, float], ...]

    def __float__(self) -> float:
        return self.value


def _next_order(n: int) -> int:
    return n + max(1, n // 4)


def integrate_to_tolerance(
    target,
    f: Integrand,
    tol: float = 1e-12,
    *,
    rtol: float = 0.0,
    rule: str = "jacobi",
    level: int | None = None,
    start_order: int = 2,
    max_order: int = 40,
    max_level: int = 6,
    max_points: int = 200_000_000,
    chunk: int = DEFAULT_CHUNK,
) -> IntegrationResult:
    """Integrate to ``|error| <= max(tol, rtol * |I|)``, choosing order and level.

    On the starting mesh the order rises (2, 3, 4, 5, 6, 7, 8, 10, 12, 15, ...) while successive
    results converge; when they stop converging (two steps in a row that shrink the difference by
    less than a factor 2) or the order passes ``max_order``, the mesh is refined once and the
    order climbs on from where it was. The estimate is ``|I_k - I_(k-1)|`` (safety factor 1
    with respect to the previous result, so typically far above the error of ``I_k``), never less
    than the round-off floor ``4 eps ∫|f|``; it is accepted once the differences decrease and it
    meets the tolerance. It stops, with ``converged=False`` and a message, when the next step
    would pass ``max_level`` or ``max_points``, or when the differences sit at the round-off
    floor above the tolerance.

    Parameters
    ----------
    target : Domain or Mesh
    f : callable or str
    tol, rtol : float
        Absolute and relative tolerances.
    rule : {"jacobi", "paper", "fan"}
        ``"jacobi"`` (default) needs the fewest points for a given accuracy on the paper's
        integrands, consistently; ``"fan"`` has fewer points per order but longer triangles
        (see the module docstring).
    level : int, optional
        Starting level (default: a Domain's block mesh, or the Mesh as given).
    start_order, max_order, max_level, max_points : int
        Limits of the search.
    chunk : int
        As in :func:`integrate`.

    Returns
    -------
    IntegrationResult

    Raises
    ------
    ResourceError
        When not even the first step fits in ``max_points``.

    Examples
    --------
    >>> from blockmesh.mesh import Mesh
    >>> sp = Mesh.from_cells([(-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)], [[0, 1, 2, 3, 4]])
    >>> result = integrate_to_tolerance(sp, "exp(-((x-1/2)^2 + (y-1/2)^2))", 1e-12)
    >>> result.converged, abs(result.value - 1.729175291842216445) < 1e-12
    (True, True)
    >>> result.error_estimate <= 1e-12
    True
    """
    _check_rule(rule)
    chunk = _check_chunk(chunk)
    for name, value in (("tol", tol), ("rtol", rtol)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value >= 0):
            raise BlockMeshError(f"{name} must be a finite number >= 0, got {value!r}")
    if tol == 0 and rtol == 0:
        raise BlockMeshError("give a tolerance: tol or rtol must be > 0")
    n = _check_order(start_order)
    _check_order(max_order)
    function = _integrand(f)
    mesh = _mesh_of(target, level)

    history: list[tuple[int, int, float]] = []
    points = 0
    previous: float | None = None
    last_diff = math.inf
    stalls = 0
    cells_done = 0
    floor = 0.0
    reason = ""
    diff = math.inf
    while True:
        cost = mesh.n_cells * rule_info(rule, n).points_per_cell
        if points + cost > max_points:
            reason = (
                f"the next step (level {mesh.level}, order {n}) would pass "
                f"max_points={max_points:,}"
            )
            break
        cells, cells_abs = _cell_integrals(mesh, function, rule, n, chunk, with_abs=True)
        value = float(np.sum(cells))
        floor = _ROUNDOFF * float(np.sum(cells_abs)) + 1e-300
        points += cost
        cells_done = mesh.n_cells
        history.append((mesh.level, n, value))
        if previous is not None:
            diff = max(abs(value - previous), floor)
            target_tol = max(tol, rtol * abs(value))
            if diff <= target_tol and (diff <= last_diff or diff <= floor):
                return IntegrationResult(
                    value,
                    diff,
                    n,
                    mesh.level,
                    rule,
                    mesh.n_cells,
                    points,
                    True,
                    f"converged: estimate {diff:.2g} <= {target_tol:.2g} at level {mesh.level}, "
                    f"order {n} ({points:,} points)",
                    tuple(history),
                )
            if diff <= 4 * floor and last_diff <= 4 * floor:
                reason = (
                    f"the results agree to the round-off floor (~{floor:.1g} = 4 eps x ∫|f|), "
                    "which is above the tolerance"
                )
                break
            stalls = stalls + 1 if diff > 0.5 * last_diff else 0
            last_diff = diff
        previous = value
        if stalls >= 2 or _next_order(n) > max_order:
            if mesh.level + 1 > max_level:
                reason = f"the results stopped converging and max_level={max_level} is reached"
                break
            mesh = refine(mesh, 1)
            stalls = 0
        else:
            n = _next_order(n)
    if not history:
        raise ResourceError(f"nothing computed: {reason}")
    level_done, order_done, value = history[-1]
    return IntegrationResult(
        value,
        diff,
        order_done,
        level_done,
        rule,
        cells_done,
        points,
        False,
        f"tolerance {max(tol, rtol * abs(value)):.2g} not reached: estimate {diff:.2g} at level "
        f"{level_done}, order {order_done} after {points:,} points; {reason}",
        tuple(history),
    )
