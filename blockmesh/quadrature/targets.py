"""What to integrate over: a Domain or a Mesh at a level, and the work that implies.

The number of cells at a level is known before refining (``6**level`` per block), so a request
whose points would pass the budget is refused before any memory is spent on it.

Examples
--------
>>> import blockmesh
>>> plan = plan_mesh(blockmesh.load_domain("l-shape"), 3)
>>> plan.cells, plan.level
(5184, 3)
>>> check_work(plan, 550, 1_000_000, "order 10 of the paper rule")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
blockmesh.errors.ResourceError: integrating over l-shape at level 3 ... takes 2,851,200 ...
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from blockmesh.checks import whole_number
from blockmesh.domain.domain import Domain
from blockmesh.errors import ArgumentError, ArgumentTypeError, ResourceError
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.pipeline import refine

__all__ = ["DEFAULT_MAX_POINTS", "MeshPlan", "check_work", "count", "plan_mesh"]

#: Default budget of evaluations of f for one call (about 5-30 s for common integrands).
DEFAULT_MAX_POINTS = 1_000_000_000


@dataclass(frozen=True)
class MeshPlan:
    """A mesh to integrate over, before it is built.

    Attributes
    ----------
    base : Mesh
        The block mesh of a Domain, or the Mesh given.
    steps : int
        Refinements still to apply to ``base``.
    level : int
        The level integrated on.
    cells : int
        Cells at that level.
    name : str
    """

    base: Mesh
    steps: int
    level: int
    cells: int
    name: str

    def build(self) -> Mesh:
        """The mesh at :attr:`level` (refined now when needed)."""
        return self.base if self.steps == 0 else refine(self.base, self.steps)


def plan_mesh(target: object, level: object = None) -> MeshPlan:
    """The mesh to integrate over.

    A Domain is refined to ``level`` (default 0, its block mesh); a Mesh is used as it is, or
    refined from its own level up to ``level`` (a mesh cannot be coarsened).

    Raises
    ------
    ArgumentTypeError
        When ``target`` is neither a Domain nor a Mesh, or ``level`` is not a whole number.
    ArgumentError
        When ``level`` is negative or below a Mesh's own level.
    """
    wanted = None if level is None else whole_number(level, "level")
    if isinstance(target, Mesh):
        base = target
        if wanted is not None and wanted < target.level:
            raise ArgumentError(
                f"level {wanted} is below the mesh's own level {target.level}; a Mesh can only "
                "be refined further (pass the Domain to integrate on a coarser level)"
            )
    elif isinstance(target, Domain):
        base = target.block_mesh()
    else:
        raise ArgumentTypeError(
            f"the target must be a Domain or a Mesh, not {type(target).__name__}"
        )
    final = base.level if wanted is None else wanted
    steps = final - base.level
    return MeshPlan(base, steps, final, base.n_cells * 6**steps, base.name or "the mesh")


def count(number: int) -> str:
    """A count for messages: ``1,234,567``, or ``1.2e+40`` beyond 15 digits."""
    return f"{number:,}" if number < 10**15 else f"{Decimal(number):.2e}"


def check_work(plan: MeshPlan, per_cell: int, max_points: int, what: str) -> int:
    """The evaluations of f a pass implies; ResourceError (before any work) above ``max_points``."""
    points = plan.cells * per_cell
    if points > max_points:
        raise ResourceError(
            f"integrating over {plan.name} at level {plan.level} with {what} takes "
            f"{count(points)} evaluations of f ({count(plan.cells)} cells x {count(per_cell)} "
            f"points), above max_points={max_points:,}; lower the level or the order, or raise "
            "max_points"
        )
    return points
