"""Node placement: where the nodes go once the cells are fixed.

A refinement decides the cells; a *placement* decides where their nodes sit. Every rule that
moves nodes has one interface, :class:`Placement`: ``place(points, cells, freedom)`` returns new
coordinates for the same cells, every cell still strictly convex, where :class:`Freedom` says
which nodes may not move (domain corners, nodes where the patch changes, nodes on curves) and
which may only slide along a line (nodes on a straight piece of boundary). The rules:

================== =========================================================================
``"paper"``        the paper's midpoints and inner points, untouched (:class:`PaperPlacement`)
``"smooth"``       Laplacian sweeps with the block edges kept (:class:`LaplacianSmoothing`)
``"optimized"``    the shape energy minimised, cell sizes made uniform (:class:`ShapeOptimization`)
``"angles"``       the shape energy to the 4th power, each cell keeping its size (the worst
                   corners weigh most; for graded block layouts)
================== =========================================================================

The decomposition's optimiser (:class:`blockmesh.decompose.optimise.WorstAngle`) is one more.
:func:`blockmesh.refine` takes any of them as ``placement=`` and applies it after every level;
nodes on curved edges are placed on their curves first and then held (:meth:`Freedom.of_mesh`).

Examples
--------
>>> import blockmesh
>>> paper = blockmesh.load_domain("square").mesh(3)
>>> better = blockmesh.refine(blockmesh.load_domain("square"), 3, placement="optimized")
>>> better.n_cells == paper.n_cells, better.quality().min_angle > paper.quality().min_angle
(True, True)
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from blockmesh.checks import choice, whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.shape import PlacementReport, optimize_points
from blockmesh.refinement.smoothing import smooth_interior

__all__ = [
    "PLACEMENTS",
    "SIZE_TARGETS",
    "Freedom",
    "LaplacianSmoothing",
    "PaperPlacement",
    "Placement",
    "ShapeOptimization",
    "as_placement",
]

#: The placements known by name (``refine(..., placement=NAME)``, ``--placement NAME``).
PLACEMENTS = ("paper", "optimized", "angles")

#: What the size term of :class:`ShapeOptimization` compares each cell's area with.
SIZE_TARGETS = ("mean", "cells")


@dataclass(frozen=True)
class Freedom:
    """Which nodes a placement may move, and how.

    Attributes
    ----------
    fixed : ndarray (N,) bool
        Nodes that stay where they are.
    slide : ndarray (N, 2) float
        For a node that may move only along a line, the line's unit direction; zeros for a node
        that moves freely (or is fixed).
    """

    fixed: np.ndarray
    slide: np.ndarray

    @classmethod
    def of_mesh(cls, mesh: Mesh) -> Freedom:
        """The freedom of a mesh's nodes: interior nodes move, boundary nodes slide or stay.

        A boundary node slides along its boundary line where the boundary runs straight through
        it within one patch; domain corners, nodes where the patch changes and every node of a
        curved edge stay. An interface node of a composite domain slides along its interface
        where that runs straight through it; where an interface
        turns, changes name, meets another or reaches the boundary, the node stays.

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("square").mesh(1)
        >>> freedom = Freedom.of_mesh(mesh)
        >>> int(freedom.fixed.sum()), int(freedom.slide.any(axis=1).sum())
        (4, 16)
        """
        edges = mesh.boundary_edges
        n = mesh.n_points
        incoming = np.full(n, -1)
        outgoing = np.full(n, -1)
        incoming[edges[:, 1]] = np.arange(edges.shape[0])
        outgoing[edges[:, 0]] = np.arange(edges.shape[0])
        nodes = np.unique(edges)
        before = edges[incoming[nodes], 0]
        after = edges[outgoing[nodes], 1]
        pts = mesh.points
        t_in = pts[nodes] - pts[before]
        t_out = pts[after] - pts[nodes]
        cross = t_in[:, 0] * t_out[:, 1] - t_in[:, 1] * t_out[:, 0]
        norms = np.hypot(*t_in.T) * np.hypot(*t_out.T)
        straight = np.abs(cross) <= COLLINEAR_SIN_TOL * norms
        same_patch = mesh.boundary_patch[incoming[nodes]] == mesh.boundary_patch[outgoing[nodes]]
        slides = straight & same_patch
        fixed = np.zeros(n, dtype=bool)
        fixed[nodes[~slides]] = True
        slide = np.zeros((n, 2))
        slide[nodes[slides]] = t_out[slides] / np.hypot(*t_out[slides].T)[:, None]
        if mesh.interface_edges.shape[0]:
            # Where an interface reaches the boundary the node stays (a corner of both regions).
            meets = np.intersect1d(nodes, mesh.interface_edges)
            fixed[meets] = True
            slide[meets] = 0.0
            inner, direction, stays = _interface_freedom(mesh, nodes)
            slide[inner] = direction
            fixed[stays] = True
        if mesh.curves is not None and len(mesh.curves):
            on_curves = np.unique(mesh.curves.edges)
            fixed[on_curves] = True
            slide[on_curves] = 0.0
        return cls(fixed, slide)


def _interface_freedom(
    mesh: Mesh, boundary_nodes: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Interface nodes that slide along their interface (ids, unit directions), and fixed ones.

    A node inside a straight run of one interface slides along it; where an interface turns
    (a chord of a curve), changes name, meets another or reaches the boundary, the node stays.
    """
    edges = mesh.interface_edges
    ends = np.concatenate([edges, edges[:, ::-1]])
    group = np.concatenate([mesh.interface_patch, mesh.interface_patch])
    order = np.argsort(ends[:, 0], kind="stable")
    ends, group = ends[order], group[order]
    nodes, start, count = np.unique(ends[:, 0], return_index=True, return_counts=True)
    two = count == 2
    first, second = start[two], start[two] + 1
    pts = mesh.points
    t_in = pts[nodes[two]] - pts[ends[first, 1]]
    t_out = pts[ends[second, 1]] - pts[nodes[two]]
    cross = t_in[:, 0] * t_out[:, 1] - t_in[:, 1] * t_out[:, 0]
    norms = np.hypot(*t_in.T) * np.hypot(*t_out.T)
    slides = np.zeros(nodes.size, dtype=bool)
    slides[two] = (
        (np.abs(cross) <= COLLINEAR_SIN_TOL * norms)
        & (group[first] == group[second])
        & ~np.isin(nodes[two], boundary_nodes)
    )
    chosen = slides[two]
    direction = t_out[chosen] / np.hypot(*t_out[chosen].T)[:, None]
    return nodes[slides], direction, nodes[~slides]


class Placement(ABC):
    """A rule for where nodes go once the cells are fixed (see the module notes)."""

    #: The rule's name (``refine(..., placement=name)``).
    name: ClassVar[str]
    #: True when the rule never moves the nodes of earlier levels (the numbering stays nested
    #: and a refined mesh's coarse nodes are its parent's).
    nested: ClassVar[bool]

    @abstractmethod
    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:
        """New coordinates (N, 2) for ``cells``: fixed nodes unchanged, every cell convex."""

    def after_level(self, mesh: Mesh) -> Mesh:
        """The mesh of a new level with its nodes placed by this rule."""
        return mesh.with_points(self.place(mesh.points, mesh.cells, Freedom.of_mesh(mesh)))


@dataclass(frozen=True)
class PaperPlacement(Placement):
    """The paper's placement: edge midpoints and inner points ``(u_i + p) / 2``, untouched."""

    name: ClassVar[str] = "paper"
    nested: ClassVar[bool] = True

    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:  # noqa: ARG002
        """The points as they are."""
        return np.array(points, dtype=np.float64)

    def after_level(self, mesh: Mesh) -> Mesh:
        """The mesh as it is."""
        return mesh


@dataclass(frozen=True)
class LaplacianSmoothing(Placement):
    """``sweeps`` Laplacian sweeps; sliding nodes are held (see :mod:`.smoothing`).

    Inside :func:`blockmesh.refine` the sweeps run on every level with every block edge held
    (``refine(..., smooth=k)`` is this placement), so the blocks keep their outlines.
    """

    sweeps: int = 1
    name: ClassVar[str] = "smooth"
    nested: ClassVar[bool] = False

    def __post_init__(self) -> None:
        whole_number(self.sweeps, "smoothing sweeps", minimum=1)

    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:
        """The points after the sweeps."""
        xy = np.array(points, dtype=np.float64)
        held = freedom.fixed | np.any(freedom.slide != 0, axis=1)
        smooth_interior(xy, np.asarray(cells), xy.shape[0], held, self.sweeps)
        return xy


@dataclass(frozen=True)
class ShapeOptimization(Placement):
    """The shape energy minimised (:mod:`.shape`): ``"optimized"``, or ``"angles"``.

    ``"angles"`` is ``power=4`` with ``size_target="cells"``.
    ``size_target="mean"`` aims every cell at the mean cell area (uniform sizes, for accuracy per
    unknown on evenly sized blocks); ``"cells"`` at the cell's own area before the move (the
    grading of the block layout is kept). ``power`` > 1 weighs the worst corners most.
    """

    size_weight: float = 1.0
    power: float = 1.0
    size_target: str = "mean"
    iterations: int = 60
    tol: float = 1e-7
    nested: ClassVar[bool] = False

    @property
    def name(self) -> str:  # type: ignore[override]
        """``"angles"`` for the worst-corner setting, ``"optimized"`` otherwise."""
        return "angles" if self.power == 4 and self.size_target == "cells" else "optimized"

    def __post_init__(self) -> None:
        whole_number(self.iterations, "iterations")
        if not (isinstance(self.tol, int | float) and self.tol > 0):
            raise ArgumentError(f"tol must be a number > 0, got {self.tol!r}")
        if not (isinstance(self.size_weight, int | float) and self.size_weight >= 0):
            raise ArgumentError(f"size_weight must be a number >= 0, got {self.size_weight!r}")
        if not (isinstance(self.power, int | float) and self.power >= 1):
            raise ArgumentError(f"power must be a number >= 1, got {self.power!r}")
        choice(self.size_target, SIZE_TARGETS, "size target")

    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:
        """The points after at most ``iterations`` L-BFGS steps on the shape energy."""
        points = np.asarray(points, dtype=np.float64)
        cells = np.asarray(cells, dtype=np.int64)
        xy = points[cells]
        areas = 0.5 * np.sum(
            xy[..., 0] * np.roll(xy[..., 1], -1, axis=1)
            - np.roll(xy[..., 0], -1, axis=1) * xy[..., 1],
            axis=1,
        )
        target = areas if self.size_target == "cells" else float(areas.sum()) / len(cells)
        return self._optimized(points, cells, freedom, target)[0]

    def after_level(self, mesh: Mesh) -> Mesh:
        """The mesh with its nodes moved (targets from the mesh's own measures)."""
        return self.improve(mesh)[0]

    def improve(self, mesh: Mesh) -> tuple[Mesh, PlacementReport]:
        """The mesh with its nodes moved, and the report of the move.

        The size targets come from the mesh's own measures (its cell areas, or their mean).
        """
        target = mesh.cell_areas() if self.size_target == "cells" else mesh.area / mesh.n_cells
        points, report = self._optimized(mesh.points, mesh.cells, Freedom.of_mesh(mesh), target)
        return mesh.with_points(points), report

    def _optimized(
        self, points, cells, freedom: Freedom, target
    ) -> tuple[np.ndarray, PlacementReport]:
        return optimize_points(
            points,
            cells,
            freedom.fixed,
            freedom.slide,
            target=target,
            size_weight=float(self.size_weight),
            power=float(self.power),
            iterations=self.iterations,
            tol=self.tol,
        )


def as_placement(placement: str | Placement, *, iterations: int = 60) -> Placement:
    """A :class:`Placement` from its name (one of :data:`PLACEMENTS`) or itself.

    Examples
    --------
    >>> as_placement("angles")
    ShapeOptimization(size_weight=1.0, power=4.0, size_target='cells', iterations=60, tol=1e-07)
    """
    if isinstance(placement, Placement):
        return placement
    if not isinstance(placement, str):
        raise ArgumentTypeError(
            f"placement must be one of {', '.join(PLACEMENTS)} or a Placement, "
            f"not {type(placement).__name__}"
        )
    choice(placement, PLACEMENTS, "placement")
    if placement == "paper":
        return PaperPlacement()
    if placement == "angles":
        return ShapeOptimization(power=4.0, size_target="cells", iterations=iterations)
    return ShapeOptimization(iterations=iterations)
