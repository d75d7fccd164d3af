"""Integration to a tolerance: the order rises, then the mesh is refined, until results agree.

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

from __future__ import annotations

import math

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError, ResourceError
from blockmesh.quadrature.arguments import (
    Integrand,
    check_chunk,
    check_integrand,
    check_max_points,
    check_nonnegative,
)
from blockmesh.quadrature.curved import exact_sums
from blockmesh.quadrature.kernel import DEFAULT_CHUNK, cell_sums, scaled_sum, total_of
from blockmesh.quadrature.registry import get_rule, order_of
from blockmesh.quadrature.result import IntegrationResult
from blockmesh.quadrature.rule import Rule
from blockmesh.quadrature.targets import plan_mesh
from blockmesh.refinement.pipeline import refine

__all__ = ["integrate_to_tolerance"]

#: Relative round-off floor of a result, times ∫|f|: no estimate is taken below it.
_ROUNDOFF = 4 * np.finfo(np.float64).eps


def _next_order(n: int) -> int:
    return n + max(1, n // 4)


def integrate_to_tolerance(
    target: object,
    f: Integrand,
    tol: float = 1e-12,
    *,
    rtol: float = 0.0,
    rule: str | Rule = "jacobi",
    level: int | None = None,
    start_order: int = 2,
    max_order: int = 40,
    max_level: int = 6,
    max_points: int = 200_000_000,
    chunk: int = DEFAULT_CHUNK,
    exact_geometry: bool = False,
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
    rule : {"jacobi", "paper", "fan"} or Rule
        ``"jacobi"`` (default) needs the fewest points for a given accuracy on the paper's
        integrands, consistently; ``"fan"`` has fewer points per order but longer triangles
        (see :mod:`blockmesh.quadrature.fan`).
    level : int, optional
        Starting level (default: a Domain's block mesh, or the Mesh as given).
    start_order, max_order, max_level, max_points : int
        Limits of the search.
    chunk, exact_geometry
        As in :func:`~blockmesh.quadrature.integrate`.

    Returns
    -------
    IntegrationResult

    Raises
    ------
    ResourceError
        When not even the first step fits in ``max_points`` (before any work).
    """
    found = get_rule(rule)
    chunk = check_chunk(chunk)
    tol = check_nonnegative(tol, "tol")
    rtol = check_nonnegative(rtol, "rtol")
    if tol == 0 and rtol == 0:
        raise ArgumentError("give a tolerance: tol or rtol must be > 0")
    if not isinstance(exact_geometry, bool):
        raise ArgumentTypeError(f"exact_geometry must be True or False, got {exact_geometry!r}")
    n = order_of(found, start_order)
    order_of(found, max_order)
    max_points = check_max_points(max_points)
    function = check_integrand(f)
    plan = plan_mesh(target, level)
    if plan.cells * found.info(n).points_per_cell > max_points:
        raise ResourceError(
            f"nothing computed: the next step (level {plan.level}, order {n}) would pass "
            f"max_points={max_points:,}"
        )
    mesh = plan.build()

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
        cost = mesh.n_cells * found.info(n).points_per_cell
        if points + cost > max_points:
            reason = (
                f"the next step (level {mesh.level}, order {n}) would pass "
                f"max_points={max_points:,}"
            )
            break
        sums = exact_sums(
            cell_sums(mesh, function, found, n, chunk, absolute=True),
            mesh, function, found, n, exact_geometry,
        )  # fmt: skip
        value = total_of(sums)
        assert sums.absolute is not None  # asked for above
        floor = scaled_sum(sums.absolute, _ROUNDOFF) + 1e-300
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
                    found.name,
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
    level_done, order_done, value = history[-1]
    return IntegrationResult(
        value,
        diff,
        order_done,
        level_done,
        found.name,
        cells_done,
        points,
        False,
        f"tolerance {max(tol, rtol * abs(value)):.2g} not reached: estimate {diff:.2g} at level "
        f"{level_done}, order {order_done} after {points:,} points; {reason}",
        tuple(history),
    )
