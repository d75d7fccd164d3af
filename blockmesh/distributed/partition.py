"""Partitions of a refinement: groups of whole blocks, balanced by cells, numbered without talking.

Every block of a domain refined ``L`` times yields ``6^L`` cells, so groups of consecutive blocks
of (nearly) equal size are balanced. When a domain has fewer blocks than partitions, or too few
for a good balance, the **units** are the cells of a coarser level ``k`` instead (``B 6^k`` of
them): refining the level-``k`` mesh ``L - k`` more times gives exactly the mesh of level ``L``,
numbering and coordinates included, so nothing changes but the grain. ``k`` is also kept at
least ``L - MAX_TASK_STEPS``, so that a task's template of the remaining levels stays small.

Global ids need no communication: the numbering plan (:mod:`blockmesh.refinement.plan`) gives every
unit's ids from prefix sums of per-unit counts, and the cells are unit-major, so partition ``p``
owns the contiguous cells ``first_cell(p) .. first_cell(p + 1) - 1``. A node on an edge between
two partitions belongs to the partition of the lower unit (which numbers it, as the serial walk
does); a unit corner to the partition of the lowest unit using it. Other partitions hold a copy
of such a node, marked as a ghost.

Examples
--------
>>> import blockmesh
>>> parts = partition(blockmesh.load_domain("joined-8"), 5, 4)
>>> parts.split_level, parts.n_units, [parts.cells(p) for p in range(4)]
(0, 8, [15552, 15552, 15552, 15552])
>>> parts = partition(blockmesh.load_domain("sp"), 5, 4)
>>> parts.split_level, parts.n_units, parts.starts.tolist()
(2, 36, [0, 9, 18, 27, 36])
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError, BlockMeshWarning
from blockmesh.geometry.topology import boundary_slots, cell_neighbours
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.pipeline import refine
from blockmesh.refinement.plan import RefinementPlan, plan_refinement

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["MAX_PARTITIONS", "MAX_TASK_STEPS", "Partitioning", "partition"]

#: Levels one task refines its units at most (the template of 7 levels is about 17 MB).
MAX_TASK_STEPS = 7
#: Most partitions of one mesh (each is a task, a file and a piece of the index).
MAX_PARTITIONS = 10_000
#: The largest partition may hold this many times the cells of the smallest.
_BALANCE = 1.25


@dataclass(frozen=True)
class Partitioning:
    """How a refinement to ``level`` is cut into partitions of whole units.

    Attributes
    ----------
    level : int
        Levels of refinement of the target (the mesh made has the target's level plus this).
    split_level : int
        The level ``k`` whose cells are the units (0: the domain's blocks).
    base : Mesh
        The level-``k`` mesh; its cells are the units.
    plan : RefinementPlan
        The numbering of the ``level - k`` remaining levels over the units.
    starts : ndarray (P + 1,) int64
        Partition p holds units ``starts[p] .. starts[p + 1] - 1``.
    corner_owner : ndarray (base nodes,) int64
        The partition owning each node of the base mesh.
    boundary_unit, boundary_side : ndarray (base boundary edges,) int64
        The unit and its edge (0..4) of each boundary edge of the base mesh, in its order.
    """

    level: int
    split_level: int
    base: Mesh
    plan: RefinementPlan
    starts: np.ndarray
    corner_owner: np.ndarray
    boundary_unit: np.ndarray
    boundary_side: np.ndarray

    @property
    def n_partitions(self) -> int:
        """Number of partitions P."""
        return int(self.starts.size - 1)

    @property
    def n_units(self) -> int:
        """Number of units (cells of the base mesh)."""
        return self.base.n_cells

    @property
    def steps(self) -> int:
        """Levels each task refines its units."""
        return self.level - self.split_level

    @property
    def n_cells(self) -> int:
        """Cells of the whole mesh."""
        return self.n_units * 6**self.steps

    @property
    def n_nodes(self) -> int:
        """Nodes of the whole mesh."""
        return self.plan.n_nodes

    def units(self, piece: int) -> range:
        """The units of partition ``piece``."""
        return range(int(self.starts[piece]), int(self.starts[piece + 1]))

    def cells(self, piece: int) -> int:
        """Cells of partition ``piece``."""
        return len(self.units(piece)) * 6**self.steps

    def first_cell(self, piece: int) -> int:
        """Global id of the first cell of partition ``piece``."""
        return int(self.starts[piece]) * 6**self.steps


def _split_level(n_blocks: int, level: int, partitions: int) -> int:
    """The coarsest level whose cells give ``partitions`` balanced groups (see the module)."""
    for k in range(max(0, level - MAX_TASK_STEPS), level):
        units = n_blocks * 6**k
        if units < partitions:
            continue
        smallest, largest = units // partitions, -(-units // partitions)
        if largest <= _BALANCE * smallest:
            return k
    return level - 1


def partition(target: Domain | Mesh | PolygonMesh, level: int, partitions: int) -> Partitioning:
    """Cut the refinement of ``target`` to ``level`` into ``partitions`` balanced partitions.

    O(B 6^k) for the level-``k`` base mesh and its numbering plan; nothing of the final mesh is
    built.

    Raises
    ------
    ArgumentError
        For a level below 1 or more partitions than the mesh one level below has cells.
    ArgumentTypeError
        For a :class:`~blockmesh.mesh.polygons.PolygonMesh`: the pieces are uniform refinements
        of pentagon blocks, whose nodes on shared edges are numbered by (edge, k/2^L); a mesh of
        hanging nodes and polygons of other sizes has no such numbering, so it is refined,
        written and integrated in one process.
    """
    if isinstance(target, PolygonMesh):
        raise ArgumentTypeError(
            "the distributed (Dask) pieces refine pentagon blocks uniformly; a PolygonMesh "
            f"({target.n_cells:,} cells of {int(target.cell_sizes().min())} to "
            f"{int(target.cell_sizes().max())} vertices, hanging nodes) is refined, written and "
            "integrated in one process: use blockmesh.refine, blockmesh.write and "
            "blockmesh.integrate without partitions"
        )
    level = whole_number(level, "level")
    partitions = whole_number(partitions, "partitions", minimum=1, maximum=MAX_PARTITIONS)
    coarse = target if isinstance(target, Mesh) else target.block_mesh()
    if coarse.interface_names:
        warnings.warn(
            f"the partitioned pieces carry the regions ({', '.join(coarse.region_names)}) but "
            f"not the interfaces ({', '.join(coarse.interface_names)}): refine without "
            "partitions to have them in the file",
            BlockMeshWarning,
            stacklevel=2,
        )
    if level < 1:
        raise ArgumentError("a partitioned refinement needs level >= 1 (level 0 is the blocks)")
    most = coarse.n_cells * 6 ** (level - 1)
    if partitions > most:
        raise ArgumentError(
            f"partitions={partitions} is more than the cells of level {level - 1} allow: "
            f"at most {most:,} at level {level} (a partition holds whole cells of a lower level)"
        )
    k = _split_level(coarse.n_cells, level, partitions)
    base = refine(coarse, k) if k else coarse
    neighbour = cell_neighbours(base.cells, base.n_points)
    plan = plan_refinement(base.cells, neighbour, base.n_points, level - k)
    units = base.n_cells
    starts = (np.arange(partitions + 1, dtype=np.int64) * units) // partitions
    lowest = np.full(base.n_points, units, dtype=np.int64)
    np.minimum.at(lowest, base.cells, np.arange(units)[:, None])
    corner_owner = np.searchsorted(starts, lowest, side="right") - 1
    slots = boundary_slots(base.cells, neighbour, base.boundary_edges, base.n_points)
    boundary_unit, boundary_side = np.divmod(slots, 5)
    return Partitioning(level, k, base, plan, starts, corner_owner, boundary_unit, boundary_side)
