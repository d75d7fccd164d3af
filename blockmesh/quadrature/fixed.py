"""Integration with a fixed rule, order and level: the total, the cells, the points.

Examples
--------
>>> from blockmesh.mesh import Mesh
>>> sp = Mesh.from_cells([(-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)], [[0, 1, 2, 3, 4]])
>>> round(integrate(sp, "(x^4 + y^3) / (1 + x^2)", order=10, level=2), 13)
1.9240305426326
>>> exact = integrate(sp, "x^2 * y", order=2)  # degree 3 = 2n - 1: exact for every rule
>>> abs(integrate(sp, lambda x, y: x * x * y, order=2, rule="fan") - exact) < 1e-15
True
>>> result = integrate_with_estimate(sp, "exp(x) * cos(y)", order=8, level=1)
>>> result.converged, result.error_estimate < 1e-8
(True, True)
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from blockmesh.errors import ArgumentTypeError, BlockMeshWarning
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.quadrature.arguments import (
    Integrand,
    check_chunk,
    check_integrand,
    check_max_points,
    check_nonnegative,
)
from blockmesh.quadrature.curved import exact_sums
from blockmesh.quadrature.estimate import null_rule
from blockmesh.quadrature.kernel import (
    DEFAULT_CHUNK,
    CellSums,
    cell_sums,
    chunks,
    scaled_sum,
    straight_tables,
    total_of,
)
from blockmesh.quadrature.polygons import (
    check_polygon_target,
    polygon_cell_integrals,
    polygon_chunks,
)
from blockmesh.quadrature.registry import get_rule, order_of
from blockmesh.quadrature.result import IntegrationResult
from blockmesh.quadrature.rule import Rule
from blockmesh.quadrature.targets import DEFAULT_MAX_POINTS, MeshPlan, check_work, plan_mesh

__all__ = [
    "DEFAULT_WARN_RTOL",
    "integrate",
    "integrate_cells",
    "integrate_with_estimate",
    "quadrature_points",
]

#: Default warning level: the estimate relative to the sum of the sectors' |integral|.
DEFAULT_WARN_RTOL = 1e-6

#: Round-off allowance added to the warning level (16 ulps of the scale).
_ROUNDOFF = 16 * float(np.finfo(np.float64).eps)

#: |I_n - I_(n+1)| bounds the error of I_n by this factor when one more order at least halves
#: the error (true for smooth integrands; slow, algebraic convergence can need more).
_SAFETY = 2.0

Function = Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class _Arguments:
    """The arguments of :func:`integrate` that its siblings share, as given (checked on use)."""

    target: object
    f: object
    order: object
    level: object
    rule: object
    chunk: object
    max_points: object
    exact_geometry: object


def _prepare(given: _Arguments) -> tuple[Function, Rule, int, MeshPlan, int]:
    """Checked arguments and the work of one pass (refused here when it passes the budget)."""
    found = get_rule(given.rule)  # type: ignore[arg-type]
    n = order_of(found, given.order)
    budget = check_max_points(given.max_points)
    function = check_integrand(given.f)
    plan = plan_mesh(given.target, given.level)
    points = check_work(
        plan, found.info(n).points_per_cell, budget, f"order {n} of the {found.name} rule"
    )
    return function, found, n, plan, points


def _cell_integrals(given: _Arguments) -> CellSums:
    """The rule's integral over every cell of a Mesh or Domain target (one pass, no estimate)."""
    function, found, n, plan, _ = _prepare(given)
    mesh = plan.build()
    sums = cell_sums(mesh, function, found, n, check_chunk(given.chunk))
    return exact_sums(sums, mesh, function, found, n, _flag(given.exact_geometry))


def integrate(
    target: object,
    f: Integrand,
    *,
    order: int,
    level: int | None = None,
    rule: str | Rule = "paper",
    chunk: int = DEFAULT_CHUNK,
    max_points: int = DEFAULT_MAX_POINTS,
    warn_rtol: float | None = DEFAULT_WARN_RTOL,
    exact_geometry: bool = False,
) -> float:
    """Integrate ``f`` over a domain or mesh with a composite Gauss rule.

    Parameters
    ----------
    target : Domain, Mesh or PolygonMesh
        A Domain is refined to ``level`` first (default: its block mesh, level 0).
        A Mesh is used as it is, or refined further when ``level`` is above its own level.
        A PolygonMesh (any vertex counts, hanging nodes) is integrated on its own cells, each
        cut into triangles from its vertex mean (:mod:`blockmesh.quadrature.polygons`).
    f : callable or str
        A vectorised ``f(x, y)`` (numpy arrays in, an array of the same shape or a scalar out)
        or an expression string (see :func:`blockmesh.numerics.expr.parse_expression`).
    order : int
        The rule's order n: exact for polynomials of total degree ``2n - 1``.
    level : int, optional
        Refinement level to integrate on (6**level cells per block).
    rule : {"paper", "jacobi", "fan"} or Rule
        See :mod:`blockmesh.quadrature.registry`; ``"paper"`` reproduces the paper's tables.
    chunk : int
        Most points f is evaluated on at once (bounds the memory).
    max_points : int
        Most evaluations of f; a request above it is refused before any work.
    warn_rtol : float or None
        Warn (:class:`~blockmesh.errors.BlockMeshWarning`) when the error estimate of
        :func:`integrate_with_estimate` is above ``warn_rtol`` times the sum of the sectors'
        ``|integral|``; ``None`` skips the estimate (slightly faster, no warning).
    exact_geometry : bool
        Integrate the cells with curved edges over their true curved shape
        (:mod:`blockmesh.quadrature.curved`) instead of their straight cells; no effect on a
        mesh without curves.

    Returns
    -------
    float

    Raises
    ------
    ArgumentError, ArgumentTypeError, UnknownNameError
        On a bad order, level, rule, chunk or target.
    ExpressionError
        When ``f`` is an invalid expression, not vectorised, not finite at a quadrature point
        (the message gives the point and the cell) or its integral overflows.
    ResourceError
        When the work passes ``max_points``.

    Notes
    -----
    Cost: ``rule_info(rule, order).points_per_cell`` evaluations of f per cell, plus about
    1.5 ns per point to place the points, sum and screen the error (and a second pass one order
    higher when the screen is above the warning level). Cell integrals are summed pairwise.

    Examples
    --------
    >>> from blockmesh.mesh import Mesh
    >>> usp = Mesh.from_cells([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], [[0, 1, 2, 3, 4]])
    >>> round(integrate(usp, "1", order=1), 14)  # the area
    6.0
    """
    given = _Arguments(target, f, order, level, rule, chunk, max_points, exact_geometry)
    if warn_rtol is not None:
        return _estimate(given, warn_rtol, 3).value
    if isinstance(target, PolygonMesh):
        return _polygon_values(target, given)[0].sum()
    return total_of(_cell_integrals(given))


def integrate_cells(
    target: object,
    f: Integrand,
    *,
    order: int,
    level: int | None = None,
    rule: str | Rule = "paper",
    chunk: int = DEFAULT_CHUNK,
    max_points: int = DEFAULT_MAX_POINTS,
    exact_geometry: bool = False,
) -> np.ndarray:
    """The integral of ``f`` over every cell, shape (M,), read-only.

    Arguments as in :func:`integrate`; no error estimate is made.

    Examples
    --------
    >>> from blockmesh.mesh import Mesh
    >>> usp = Mesh.from_cells([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], [[0, 1, 2, 3, 4]])
    >>> cells = integrate_cells(usp, "x", order=1, level=1)
    >>> cells.shape, round(float(cells.sum()), 13)
    ((6,), 7.3333333333333)
    """
    given = _Arguments(target, f, order, level, rule, chunk, max_points, exact_geometry)
    if isinstance(target, PolygonMesh):
        values = _polygon_values(target, given)[0]
        values.setflags(write=False)
        return values
    return _cell_integrals(given).values


def integrate_with_estimate(
    target: object,
    f: Integrand,
    *,
    order: int,
    level: int | None = None,
    rule: str | Rule = "paper",
    chunk: int = DEFAULT_CHUNK,
    max_points: int = DEFAULT_MAX_POINTS,
    warn_rtol: float = DEFAULT_WARN_RTOL,
    exact_geometry: bool = False,
) -> IntegrationResult:
    """Like :func:`integrate`, with an error estimate; warns when the estimate is large.

    The estimate (see :mod:`blockmesh.quadrature.estimate`) is first read off the values the
    rule computed anyway (a conservative screen). When that is above ``warn_rtol`` times the
    scale — the sum of ``|integral|`` over every cell's sectors, about ``∫|f|`` — the rule runs
    again one order higher and the estimate becomes twice the difference, cell by cell (an
    upper bound of the error when one more order at least halves it, as it does for smooth
    integrands). When even that stays above the level, the result has ``converged=False`` and
    names the cell where the estimate is largest, and a
    :class:`~blockmesh.errors.BlockMeshWarning` is issued: the integrand is singular, divergent
    or not resolved at this level and order.

    Returns
    -------
    IntegrationResult
        ``value`` is the result of the requested order (identical to :func:`integrate`).

    Examples
    --------
    >>> import warnings
    >>> import blockmesh
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     result = integrate_with_estimate(blockmesh.load_domain("sp"), "1/(x - 0.3)",
    ...                                      order=10, level=2)
    >>> result.converged, result.error_estimate > 1
    (False, True)
    >>> str(caught[0].message).split(":")[0]
    'the integral is not resolved'
    """
    given = _Arguments(target, f, order, level, rule, chunk, max_points, exact_geometry)
    return _estimate(given, warn_rtol, 3)


def _polygon_values(
    mesh: PolygonMesh, given: _Arguments, chunk: int = DEFAULT_CHUNK
) -> tuple[np.ndarray, Rule, int, int]:
    """Cell integrals over a polygon mesh (the target), the rule, its order and the points used.

    ``given.chunk`` is not read: the polygon quadrature evaluates ``chunk`` points at once.
    """
    found = get_rule(given.rule)  # type: ignore[arg-type]
    n = order_of(found, given.order)
    function = check_integrand(given.f)
    exact = _flag(given.exact_geometry)
    budget = check_max_points(given.max_points)
    points = check_polygon_target(mesh, given.level, exact, found, n, budget)
    return polygon_cell_integrals(mesh, function, found, n, chunk), found, n, points


def _polygon_estimate(
    mesh: PolygonMesh, given: _Arguments, warn_rtol: object, stacklevel: int
) -> IntegrationResult:
    """:func:`integrate_with_estimate` on a polygon mesh: twice the difference to order n + 1."""
    warn_level = check_nonnegative(warn_rtol, "warn_rtol")
    values, found, n, points = _polygon_values(mesh, given, check_chunk(given.chunk))
    check = _check_order(found, n)
    other = _polygon_values(mesh, replace(given, order=check, rule=found))[0]
    per_cell = _SAFETY * np.abs(values - other)
    return _result(
        mesh,
        found,
        2 * points,
        ((mesh.level, n, scaled_sum(values)), (mesh.level, check, scaled_sum(other))),
        per_cell,
        estimate=scaled_sum(per_cell),
        scale=scaled_sum(np.abs(values)),
        limit=scaled_sum(np.abs(values), warn_level + _ROUNDOFF),
        warn_rtol=warn_level,
        how=f"twice the difference to order {check}, cell by cell",
        stacklevel=stacklevel + 1,
    )


def _estimate(given: _Arguments, warn_rtol: object, stacklevel: int) -> IntegrationResult:
    """:func:`integrate_with_estimate` on any target; ``stacklevel`` as seen from here."""
    if isinstance(given.target, PolygonMesh):
        return _polygon_estimate(given.target, given, warn_rtol, stacklevel + 1)
    function, found, n, plan, points = _prepare(given)
    chunk = check_chunk(given.chunk)
    warn_level = check_nonnegative(warn_rtol, "warn_rtol")
    budget = check_max_points(given.max_points)
    mesh = plan.build()
    screen = null_rule(found, n)
    exact = _flag(given.exact_geometry)
    sums = exact_sums(
        cell_sums(mesh, function, found, n, chunk, screen=screen), mesh, function, found, n, exact
    )
    value = total_of(sums)
    magnitude = sums.magnitude if sums.magnitude is not None else np.array([abs(value)])
    scale = scaled_sum(magnitude)  # may be inf (1e308*y): the limit below stays finite
    limit = scaled_sum(magnitude, warn_level + _ROUNDOFF)
    history: tuple[tuple[int, int, float], ...] = ((plan.level, n, value),)
    per_cell = sums.screen if sums.screen is not None else np.zeros(mesh.n_cells)
    estimate = scaled_sum(per_cell) if screen.complete else math.inf
    how = "from the highest resolved polynomial modes of f on each sector"
    if not estimate <= limit:
        check = _check_order(found, n)
        extra = plan.cells * found.info(check).points_per_cell if check >= 1 else None
        if extra is not None and points + extra <= budget:
            other = exact_sums(
                cell_sums(mesh, function, found, check, chunk), mesh, function, found, check, exact
            )
            per_cell = _SAFETY * np.abs(sums.values - other.values)
            estimate = scaled_sum(per_cell)
            points += extra
            history += ((plan.level, check, total_of(other)),)
            how = f"twice the difference to order {check}, cell by cell"
        else:
            how += f" (order {check} not tried: it would pass max_points={budget:,})"
    return _result(
        mesh,
        found,
        points,
        history,
        per_cell,
        estimate=estimate,
        scale=scale,
        limit=limit,
        warn_rtol=warn_level,
        how=how,
        stacklevel=stacklevel + 1,
    )


def _check_order(found: Rule, n: int) -> int:
    """The order the estimate compares order ``n`` with: one higher, or one lower at the top."""
    return n + 1 if n + 1 <= found.max_order else n - 1


def _result(
    mesh: Mesh | PolygonMesh,
    found: Rule,
    points: int,
    history: tuple[tuple[int, int, float], ...],
    per_cell: np.ndarray,
    *,
    estimate: float,
    scale: float,
    limit: float,
    warn_rtol: float,
    how: str,
    stacklevel: int,
) -> IntegrationResult:
    """The result of the first pass in ``history``; warns when ``estimate`` is above ``limit``.

    ``per_cell`` is the estimate cell by cell (the largest names the cell in the message),
    ``how`` says how it was made; ``stacklevel`` as seen from here.
    """
    level, n, value = history[0]
    worst = int(np.argmax(per_cell)) if mesh.n_cells and np.any(per_cell > 0) else None
    converged = estimate <= limit
    message = f"error estimate {estimate:.3g} {how}"
    if not converged:
        message = _not_resolved(mesh, worst, value, estimate, scale, warn_rtol, how)
        warnings.warn(BlockMeshWarning(message), stacklevel=stacklevel)
    return IntegrationResult(
        value,
        estimate,
        n,
        level,
        found.name,
        mesh.n_cells,
        points,
        converged,
        message,
        history,
        worst,
    )


def _flag(exact_geometry: object) -> bool:
    if not isinstance(exact_geometry, bool):
        raise ArgumentTypeError(f"exact_geometry must be True or False, got {exact_geometry!r}")
    return exact_geometry


def _not_resolved(
    mesh: Mesh | PolygonMesh,
    worst: int | None,
    value: float,
    estimate: float,
    scale: float,
    warn_rtol: float,
    how: str,
) -> str:
    where = ""
    if worst is not None:
        corners = mesh.cell(worst) if isinstance(mesh, PolygonMesh) else mesh.cells[worst]
        x, y = mesh.points[corners].mean(axis=0)
        where = f"; it is largest in cell {worst} (around ({x:.6g}, {y:.6g}))"
    larger = f", and larger than the value {value:.6g} itself" if estimate > abs(value) else ""
    return (
        f"the integral is not resolved: the error estimate {estimate:.3g} ({how}) is above "
        f"warn_rtol={warn_rtol:g} times the sum of the sectors' |integral| ({scale:.3g})"
        f"{larger}{where}. The integrand may be singular or divergent there, or need a higher "
        "level or order (integrate_to_tolerance chooses them)"
    )


def quadrature_points(
    target: object,
    *,
    order: int,
    level: int | None = None,
    rule: str | Rule = "paper",
    max_points: int = DEFAULT_MAX_POINTS,
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
    found = get_rule(rule)
    n = order_of(found, order)
    if isinstance(target, PolygonMesh):
        check_polygon_target(target, level, False, found, n, check_max_points(max_points))
        parts = list(polygon_chunks(target, found, n, DEFAULT_CHUNK))
        if not parts:
            empty = np.empty(0)
            return empty, empty.copy(), empty.copy()
        return tuple(  # type: ignore[return-value]
            np.concatenate([part[k].reshape(-1) for part in parts]) for k in (1, 2, 3)
        )
    plan = plan_mesh(target, level)
    check_work(plan, found.info(n).points_per_cell, check_max_points(max_points), f"order {n}")
    _, weights = straight_tables(found, n)
    xs_all, ys_all, ws_all = [], [], []
    for _, xs, ys, d in chunks(plan.build(), found, n, DEFAULT_CHUNK):
        xs_all.append(xs.reshape(-1).copy())
        ys_all.append(ys.reshape(-1).copy())
        ws_all.append(np.multiply.outer(np.where(d == 0, 0.0, d), weights).reshape(-1))
    if not xs_all:
        empty = np.empty(0)
        return empty, empty.copy(), empty.copy()
    return np.concatenate(xs_all), np.concatenate(ys_all), np.concatenate(ws_all)
