"""Integrals over a domain summed partition by partition on the workers."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from blockmesh._system.memory import format_count
from blockmesh.checks import renamed_keywords, whole_number
from blockmesh.distributed.budget import check_workers
from blockmesh.distributed.cluster import ProgressCallback, dask_client, run_tasks
from blockmesh.distributed.partition import partition
from blockmesh.distributed.tasks import integrate_piece_task
from blockmesh.errors import ArgumentTypeError, ResourceError
from blockmesh.mesh.mesh import Mesh
from blockmesh.quadrature import DEFAULT_MAX_POINTS, IntegrationResult, rule_info

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain


@renamed_keywords(function="f")
def integrate_with_estimate(
    target: Domain | Mesh,
    f: Any,
    *,
    order: int,
    level: int | None = None,
    rule: str = "paper",
    partitions: int | None = None,
    client: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
    max_points: int | None = None,
    exact_geometry: bool = False,
    progress: ProgressCallback | None = None,
) -> Any:
    """The integral over ``target`` at ``level``, partition by partition, with its estimate.

    Each worker builds its piece and integrates over it with
    :func:`blockmesh.quadrature.integrate_with_estimate` (``order``, ``rule`` as there); the
    client adds the values (``math.fsum``: the serial value to round-off) and the error
    estimates, and the result has converged when every partition's has. ``level`` is as for
    :func:`blockmesh.integrate`: a Domain's refinement level, or for a Mesh the level to reach
    (above its own). ``f`` is the integrand as for :func:`blockmesh.integrate` and must be
    picklable: an expression string, or a function defined at module level (``function=``, its
    former name, still works with a :class:`DeprecationWarning`). ``max_points`` bounds the
    evaluations of the whole integral.
    ``exact_geometry`` integrates over the true curved cells, as :func:`blockmesh.integrate`
    does (every piece carries its curved edges).

    Returns
    -------
    IntegrationResult
    """
    if level is None:
        steps = 0
    elif isinstance(target, Mesh):
        steps = whole_number(level, "level") - target.level
    else:
        steps = whole_number(level, "level")
    budget = DEFAULT_MAX_POINTS if max_points is None else whole_number(max_points, "max_points")
    if not isinstance(exact_geometry, bool):
        raise ArgumentTypeError(f"exact_geometry must be True or False, got {exact_geometry!r}")
    with dask_client(client, workers=workers, scheduler=scheduler) as active:
        n_workers = len(active.scheduler_info().get("workers", {})) or 1
        parts = partition(target, steps, partitions if partitions is not None else n_workers)
        info = rule_info(rule, order)
        points = parts.n_cells * info.points_per_cell
        if points > budget:
            raise ResourceError(
                f"{format_count(points)} evaluations of f are more than max_points "
                f"({format_count(budget)}); lower the level or the order, or raise max_points"
            )
        check_workers(parts, active)
        scattered = active.scatter(parts, broadcast=True, hash=False)
        futures = [
            active.submit(
                integrate_piece_task,
                scattered,
                p,
                f,
                order,
                rule,
                budget,
                exact_geometry,
                pure=False,
            )
            for p in range(parts.n_partitions)
        ]
        results = run_tasks(futures, progress)
    value = math.fsum(r.value for r in results)
    estimate = math.fsum(r.error_estimate for r in results)
    unresolved = [r for r in results if not r.converged]
    message = (
        f"sum of {parts.n_partitions} partitions; {unresolved[0].message}"
        if unresolved
        else f"sum of {parts.n_partitions} partitions, each {results[0].message}"
    )
    level_made = parts.base.level + parts.steps
    return IntegrationResult(
        value=value,
        error_estimate=estimate,
        order=results[0].order,
        level=level_made,
        rule=results[0].rule,
        cells=sum(r.cells for r in results),
        points=sum(r.points for r in results),
        converged=not unresolved,
        message=message,
        history=((level_made, results[0].order, value),),
    )


@renamed_keywords(function="f")
def integrate(target: Domain | Mesh, f: Any, **options: Any) -> float:
    """The value of :func:`integrate_with_estimate` (same options): a float.

    ``f`` as for :func:`blockmesh.integrate` (``function=`` is its deprecated name).

    Examples
    --------
    >>> import blockmesh, blockmesh.distributed as bd
    >>> bd.integrate(blockmesh.load_domain("sp"), f="1", order=1, level=2,
    ...              partitions=3, workers=1)  # doctest: +SKIP
    5.0
    """
    return integrate_with_estimate(target, f, **options).value
