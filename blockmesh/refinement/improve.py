"""Better node placement on a fixed mesh: same cells and counts, better shapes, every cell convex.

The paper's refinement degrades with level (the worst angle shrinks by about a quarter per level)
and :mod:`blockmesh.refinement.smoothing` cannot move the nodes on block edges.
:func:`optimize_nodes` moves every node that is not on the domain boundary, block-edge nodes
included, and lets boundary nodes slide along their own straight boundary line (interface nodes
of a composite domain along their straight interface); domain corners, the nodes where the patch
changes and the nodes on curves stay where they are
(:meth:`~blockmesh.refinement.placement.Freedom.of_mesh`). Topology, counts, patches and regions
are unchanged, and every cell stays strictly convex. It minimises the shape energy of
:mod:`blockmesh.refinement.shape`; :class:`~blockmesh.refinement.placement.ShapeOptimization` is
the same as a placement rule, which ``refine(..., placement="optimized")`` (or ``"angles"``:
``power=4``, ``size_target="cells"``) applies after every level; :func:`refine_with_rule` is that
call under its earlier name.

:func:`inner_point_rule` is the cheaper, nested alternative: it refines level by level and puts
the five inner points of every cell at ``p + t (u_i - p)`` with the ``t`` per level that
maximises the worst angle (the paper's rule is ``t = 1/2``).

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(3)
>>> better = optimize_nodes(mesh)
>>> better.n_cells == mesh.n_cells and better.quality().not_strictly_convex == 0
True
>>> round(mesh.quality().min_angle, 1), round(better.quality().min_angle, 1)
(31.8, 54.6)
"""

from __future__ import annotations

from typing import Literal, overload

import numpy as np

from blockmesh.checks import choice, whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.pipeline import MAX_LEVEL, check_level, refine
from blockmesh.refinement.placement import (
    PLACEMENTS,
    SIZE_TARGETS,
    ShapeOptimization,
    as_placement,
)
from blockmesh.refinement.shape import PlacementReport, ShapeEnergy

__all__ = [
    "ANGLE_TIE",
    "QUALITY_RULES",
    "SIZE_TARGETS",
    "PlacementReport",
    "inner_point_rule",
    "optimize_nodes",
    "refine_with_rule",
    "shape_energy",
]

#: Node-placement rules of a refinement (the names of
#: :data:`blockmesh.refinement.placement.PLACEMENTS`): the paper's; optimised node placement after
#: every level with cell sizes made uniform ("optimized", for accuracy per unknown on evenly sized
#: blocks); or after every level against the worst corners, each cell keeping about its size
#: ("angles", for graded block layouts such as decomposed polygons).
QUALITY_RULES = PLACEMENTS


def shape_energy(mesh: Mesh) -> float:
    """The mean corner distortion μ of a mesh (1 for regular pentagons; inf if a cell folds).

    Examples
    --------
    >>> import blockmesh
    >>> round(shape_energy(blockmesh.load_domain("sp").mesh(0)), 4)
    1.249
    """
    energy = ShapeEnergy(mesh.cells, mesh.n_points, 0.0, 1.0)
    value, _ = energy(mesh.points[:, 0], mesh.points[:, 1], want_gradient=False)
    return value / mesh.cells.size


def _check_mesh(mesh: object) -> Mesh:
    if not isinstance(mesh, Mesh):
        raise ArgumentTypeError(f"mesh must be a blockmesh Mesh, not {type(mesh).__name__}")
    return mesh


@overload
def optimize_nodes(
    mesh: Mesh,
    *,
    size_weight: float = ...,
    iterations: int = ...,
    tol: float = ...,
    report: Literal[False] = ...,
    power: float = ...,
    size_target: str = ...,
) -> Mesh: ...


@overload
def optimize_nodes(
    mesh: Mesh,
    *,
    size_weight: float = ...,
    iterations: int = ...,
    tol: float = ...,
    report: Literal[True],
    power: float = ...,
    size_target: str = ...,
) -> tuple[Mesh, PlacementReport]: ...


def optimize_nodes(
    mesh: Mesh,
    *,
    size_weight: float = 1.0,
    iterations: int = 300,
    tol: float = 1e-7,
    report: bool = False,
    power: float = 1.0,
    size_target: str = "mean",
) -> Mesh | tuple[Mesh, PlacementReport]:
    """Move the nodes of ``mesh`` to minimise the corner distortion, keeping every cell convex.

    Parameters
    ----------
    mesh : Mesh
    size_weight : float
        Weight of the size term ``mean(A/Ā + Ā/A - 2)`` (Ā the mean cell area) against the mean
        corner distortion: without it (0) the corners improve most but the cell sizes spread
        (which costs accuracy per degree of freedom on smooth problems); 1 keeps both.
    iterations : int
        Most L-BFGS iterations (each costs about two energy evaluations, O(M)).
    tol : float
        Stop when an iteration lowers the mean corner energy by less than this.
    report : bool
        Also return a :class:`PlacementReport`.
    power : float
        Minimise ``Σ μ**power`` (>= 1): 1 weighs every corner alike and improves the average
        corner; larger powers (4) concentrate on the worst corners, which on graded meshes is
        what raises the worst angle.
    size_target : {"mean", "cells"}
        The area each cell's size term aims at: the mean cell area (sizes made uniform over the
        whole mesh), or the cell's own area before the move (the grading of the block layout,
        small blocks at sharp corners and in narrow parts, is kept).

    Returns
    -------
    Mesh, or (Mesh, PlacementReport)
        The same cells, patches and regions on moved points (``mesh.with_points``).

    Examples
    --------
    >>> import blockmesh
    >>> mesh = blockmesh.load_domain("l-shape").mesh(2)
    >>> better, info = optimize_nodes(mesh, report=True)
    >>> info.energy_after < info.energy_before, better.area == mesh.area
    (True, True)
    """
    mesh = _check_mesh(mesh)
    rule = ShapeOptimization(
        size_weight=size_weight,
        power=power,
        size_target=size_target,
        iterations=iterations,
        tol=tol,
    )
    better, info = rule.improve(mesh)
    return (better, info) if report else better


#: Worst angles (degrees) this close to the best are a tie in :func:`inner_point_rule`. Candidates
#: whose worst corner is one the inner points do not touch have the same worst angle computed
#: from different points: equal but for rounding (3e-14 degrees apart was seen), so a plain
#: maximum picked among them by that noise.
ANGLE_TIE = 1e-9


def _pick_fraction(fractions: np.ndarray, angles: np.ndarray) -> int | None:
    """The index of the fraction :func:`inner_point_rule` takes, or None if no candidate is valid.

    The largest worst angle wins; candidates within :data:`ANGLE_TIE` of it are a tie, won by the
    fraction nearest the paper's 1/2, then by the smaller one. The choice depends on the set of
    (fraction, angle) pairs only, not on their order or on rounding noise in equal angles.
    """
    valid = np.isfinite(angles)
    if not valid.any():
        return None
    tied = np.flatnonzero(valid & (angles >= angles[valid].max() - ANGLE_TIE))
    order = np.lexsort((fractions[tied], np.abs(fractions[tied] - 0.5)))
    return int(tied[order[0]])


def inner_point_rule(
    target, level: int, *, fractions: tuple[float, ...] = (0.35, 0.4, 0.45, 0.5, 0.55, 0.6)
) -> Mesh:
    """Refine level by level, each time with the inner points ``w = p + t (u - p)``.

    ``t`` is chosen per level among ``fractions`` (each in (0, 1)) to maximise the worst angle of
    the new level (``t = 1/2`` is the paper's rule). Worst angles within :data:`ANGLE_TIE` degrees
    of the best tie, and a tie goes to the fraction nearest 1/2 (then the smaller): the choice does
    not depend on the order of ``fractions`` or on rounding. Nested (old nodes never move),
    conforming, and with the paper's counts.

    Examples
    --------
    >>> import blockmesh
    >>> mesh = inner_point_rule(blockmesh.load_domain("sp"), 3)
    >>> mesh.n_cells, mesh.quality().min_angle >= blockmesh.load_domain("sp").mesh(3).quality(
    ...     ).min_angle
    (216, True)
    """
    level = whole_number(level, "level", maximum=MAX_LEVEL)
    ts = _check_fractions(fractions)
    check_level(target, level)  # refused now, not after some levels
    mesh = refine(target, 0)
    for _ in range(level):
        child = refine(mesh, 1)
        centre = mesh.points[mesh.cells].mean(axis=1)  # the paper's p, per parent
        angles = np.full(ts.size, -np.inf)  # one trial mesh at a time in memory
        for k, t in enumerate(ts):
            quality = _inner_points_at(child, centre, float(t)).quality()
            if quality.not_strictly_convex == 0:
                angles[k] = quality.min_angle
        best = _pick_fraction(ts, angles)
        mesh = child if best is None else _inner_points_at(child, centre, float(ts[best]))
    return mesh


def _inner_points_at(child: Mesh, centre: np.ndarray, t: float) -> Mesh:
    """``child`` (one level of the paper's refinement) with ``w = p + t (u - p)`` per parent."""
    cells = child.cells.reshape(-1, 6, 5)
    inner = cells[:, 5, :]  # w_1..w_5 of every parent
    mids = cells[:, :5, 1]  # u_k is corner 1 of child k
    xy = child.points.copy()
    moved = centre[:, None, :] + t * (child.points[mids] - centre[:, None, :])
    xy[inner.ravel()] = moved.reshape(-1, 2)
    return child.with_points(xy)


def _check_fractions(fractions: object) -> np.ndarray:
    """``fractions`` as a float array, or a located error: a non-empty sequence in (0, 1)."""
    try:
        ts = np.array(fractions, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(
            f"fractions must be a sequence of numbers, got {fractions!r}"
        ) from None
    if ts.ndim != 1 or ts.size == 0:
        raise ArgumentError(f"fractions must be a non-empty sequence of numbers, got {fractions!r}")
    outside = np.flatnonzero(~((ts > 0) & (ts < 1)))
    if outside.size:
        raise ArgumentError(
            f"fractions must lie in (0, 1): fractions[{outside[0]}] = {float(ts[outside[0]])!r}"
        )
    return ts


def refine_with_rule(
    target,
    level: int,
    *,
    rule: str = "paper",
    smooth: int = 0,
    iterations: int = 60,
    max_memory: int | None = None,
) -> Mesh:
    """Refine ``level`` times with a node-placement rule (one of :data:`QUALITY_RULES`).

    ``"paper"`` is :func:`blockmesh.refine` itself. ``"optimized"`` refines one level at a time
    and runs :func:`optimize_nodes` (``iterations`` L-BFGS steps) after each level, so every level
    starts from well-shaped cells; the cells, counts, patches and regions are the paper's.
    ``"angles"`` does the same with ``power=4`` and ``size_target="cells"``: the worst corners
    weigh most and every cell keeps about the size the refinement gave it, which on graded block
    layouts (decomposed polygons, converted meshes) raises the worst angle where ``"optimized"``,
    equalising all cell sizes, can lower it. (On
    the accuracy benchmark's square, 15, 30, 60 or 100 iterations per level gave the same errors
    within 2 %, but the worst angle at level 5 was 19.4° with 30 and 28.6° with 60, the default.)
    ``max_memory`` is passed to every :func:`blockmesh.refine` step.

    Examples
    --------
    >>> import blockmesh
    >>> domain = blockmesh.load_domain("square")
    >>> paper, better = domain.mesh(3), refine_with_rule(domain, 3, rule="optimized")
    >>> better.n_cells == paper.n_cells, better.quality().min_angle > paper.quality().min_angle
    (True, True)
    """
    choice(rule, QUALITY_RULES, "quality rule")
    return refine(
        target,
        level,
        smooth=smooth,
        placement=as_placement(rule, iterations=iterations),
        max_memory=max_memory,
    )
