"""Refinement of a block mesh into a conforming all-pentagon mesh, numbered like the paper.

Each cell splits into six (paper eq. 1a): the corners ``v_i``, the edge midpoints
``u_i = (v_i + v_i+1) / 2`` and the inner points ``w_i = (u_i + p) / 2`` with ``p`` the vertex
mean. Level by level, cells in order, each cell numbers the midpoints of its edges that are not
numbered yet, then its five inner points (the paper's ``nodaladdressesforpentagon``, 0-based).

How it is fast: the numbering of one refined pentagon does not depend on its shape, so it is built
once per level (:mod:`blockmesh.refinement.template`) and every block maps its local node ids to
global ids with whole-array operations (:mod:`blockmesh.refinement.plan`). A node on an edge shared
by two blocks is numbered by the lower block, exactly as the paper's walk does, and the higher block
reads the same ids back along the edge. Coordinates are computed level by level from the parent
cells with the paper's arithmetic. Blocks, in groups, are refined independently on worker threads
straight into the output (:mod:`blockmesh.refinement.grouped`); a deep refinement first refines the
base and uses its cells as blocks, which the nested numbering makes the same mesh bit for bit.

This module is the entry point (:func:`refine`, :func:`check_level`): it reads the arguments,
checks that the level fits (:mod:`blockmesh.refinement.limits`), has the mesh built and assembled
(:mod:`blockmesh.refinement.assemble`), grades and renumbers it; with ``cells=`` it hands over to
local refinement (:mod:`blockmesh.refinement.local`).

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.refine(blockmesh.load_domain("square-cut"), 2)
>>> mesh.n_cells, mesh.n_points, mesh.level
(144, 241, 2)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol, TypedDict, Unpack, overload

import numpy as np

from blockmesh.checks import choice, whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError, ResourceError
from blockmesh.geometry.topology import cell_neighbours
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.refinement.assemble import build, build_placed
from blockmesh.refinement.grading import graded_mesh
from blockmesh.refinement.limits import check_memory, check_precision
from blockmesh.refinement.local import refine_locally
from blockmesh.refinement.placement import (
    LaplacianSmoothing,
    PaperPlacement,
    Placement,
    as_placement,
)

__all__ = ["MAX_LEVEL", "MAX_SMOOTH", "NUMBERINGS", "check_level", "refine"]

#: Node numberings :func:`refine` offers.
NUMBERINGS = ("nested", "rcm")
#: Highest level asked for that is answered with a size estimate (every level multiplies the
#: cells by 6, so level 30 is beyond any machine already); higher levels are refused outright.
MAX_LEVEL = 10_000
#: Most Laplacian sweeps per level (``smooth``): a few cure most of the distortion.
MAX_SMOOTH = 1_000

ProgressCallback = Callable[[int, int], None]


class BlockSource(Protocol):
    """What :func:`refine` refines besides a Mesh: anything with a block mesh (a Domain)."""

    def block_mesh(self) -> Mesh:
        """The blocks as a level-0 mesh."""
        ...


# --------------------------------------------------------------------------- refinement
def _block_mesh_of(target: BlockSource | Mesh | PolygonMesh) -> Mesh:
    if isinstance(target, Mesh):
        return target
    if not isinstance(target, PolygonMesh) and callable(getattr(target, "block_mesh", None)):
        return target.block_mesh()
    raise ArgumentTypeError(f"refine() takes a Domain or a Mesh, not {type(target).__name__}")


class RefineOptions(TypedDict, total=False):
    """The keywords of :func:`refine` that do not change what it returns (see there)."""

    scheme: str
    numbering: str
    smooth: int
    placement: str | Placement
    max_memory: int | None
    progress: ProgressCallback | None
    threads: int | None


@overload
def refine(
    domain_or_mesh: BlockSource | Mesh,
    level: int,
    *,
    cells: None = None,
    **options: Unpack[RefineOptions],
) -> Mesh: ...


@overload
def refine(
    domain_or_mesh: BlockSource | Mesh | PolygonMesh,
    level: int | None = None,
    *,
    cells: Any,
    **options: Unpack[RefineOptions],
) -> PolygonMesh: ...


@overload
def refine(
    domain_or_mesh: PolygonMesh,
    level: int | None = None,
    *,
    cells: Any = None,
    **options: Unpack[RefineOptions],
) -> PolygonMesh: ...


def refine(
    domain_or_mesh: BlockSource | Mesh | PolygonMesh,
    level: int | None = None,
    *,
    cells: Any = None,
    scheme: str = "pentagons",
    numbering: str = "nested",
    smooth: int = 0,
    placement: str | Placement = "paper",
    max_memory: int | None = None,
    progress: ProgressCallback | None = None,
    threads: int | None = None,
) -> Mesh | PolygonMesh:
    """Refine a domain (or a mesh) ``level`` times: every cell becomes 6**level pentagons.

    With ``cells=``, only the marked cells are split (local refinement,
    :mod:`blockmesh.refinement.local`): their new edge nodes become straight vertices (hanging
    nodes, at most one per side) of their coarse neighbours, and the result is a
    :class:`~blockmesh.mesh.polygons.PolygonMesh`.

    Parameters
    ----------
    domain_or_mesh : Domain, Mesh or PolygonMesh
        A Domain is refined from its block mesh (level 0); a Mesh from its own cells, so
        ``refine(refine(d, 2), 1)`` equals ``refine(d, 3)`` (for a domain without a grading:
        the graded edges of a Domain's ``grading`` are spaced geometrically at the level made,
        :mod:`blockmesh.refinement.grading`). A PolygonMesh is refined by the local rule (every
        cell marked, unless ``cells`` says otherwise).
    level : int
        How many times each cell is split (>= 0). The result's ``level`` is the input's plus this.
        With ``cells``, the rounds of local refinement (default 1).
    cells : boolean mask, cell ids or callable, optional
        The cells to split: a mask over the cells, their ids, or ``cells(mesh)`` returning
        either (asked again on every round's mesh; ids and masks mark the children of the
        marked cells in later rounds). A marking of no cell is an error.
    scheme : {"pentagons", "quads"}
        With ``cells``: how a marked cell is split (:data:`blockmesh.refinement.local.SCHEMES`):
        the paper's six pentagons (its general-polygon form for other cells), or
        quadrilaterals through the centre.
    numbering : {"nested", "rcm"}
        ``"nested"`` (default) is the paper's numbering: every node id of the previous level is
        kept. ``"rcm"`` renumbers the nodes by reverse Cuthill-McKee to reduce the bandwidth.
    smooth : int
        Laplacian sweeps per level (see :mod:`blockmesh.refinement.smoothing`); 0 keeps the paper's
        exact scheme. The same as ``placement=LaplacianSmoothing(smooth)``.
    placement : str or Placement
        Where the nodes of every new level go (:mod:`blockmesh.refinement.placement`):
        ``"paper"`` (default, the paper's exact scheme), ``"optimized"``, ``"angles"``, or a
        :class:`~blockmesh.refinement.placement.Placement`. Any but the paper's refines one level
        at a time and places the nodes after each; cells, counts, patches and regions stay the
        paper's.
    max_memory : int, optional
        Refuse to build a mesh needing more bytes than this (default: the memory available now).
    progress : callable, optional
        Called as ``progress(done, total)`` as the work proceeds (in the calling thread).
    threads : int, optional
        Worker threads sharing the blocks (default: the cores available, at most 8, or
        ``BLOCKMESH_THREADS``). The result is the same bit for bit for any number.

    Returns
    -------
    Mesh

    Raises
    ------
    ResourceError
        When the predicted size does not fit, naming the largest level that does.

    Examples
    --------
    >>> import blockmesh
    >>> mesh = blockmesh.refine(blockmesh.load_domain("sp"), 1)
    >>> mesh.cells[0].tolist(), mesh.points[10].tolist()
    ([0, 5, 10, 14, 9], [0.0, -0.6])
    >>> local = blockmesh.refine(mesh, cells=[0])
    >>> local.n_cells, sorted(set(local.cell_sizes().tolist()))
    (11, [5, 6])
    """
    if cells is not None or isinstance(domain_or_mesh, PolygonMesh):
        if not (isinstance(placement, str) and placement == "paper"):
            raise ArgumentError(
                f"placement={placement!r} applies to uniform refinement; local refinement "
                "(cells=, or a PolygonMesh) places the nodes by the paper's rule"
            )
        return _refine_locally(
            domain_or_mesh, level, cells, numbering, smooth, max_memory, progress, threads, scheme
        )
    if scheme != "pentagons":
        raise ArgumentError(
            f"scheme={scheme!r} applies to local refinement (cells=); uniform refinement is the "
            "paper's"
        )
    if level is None:
        raise ArgumentError("refine() needs a level (how many times to split every cell)")
    level = whole_number(level, "level", maximum=MAX_LEVEL)
    choice(numbering, NUMBERINGS, "numbering")
    smooth = whole_number(smooth, "smooth", maximum=MAX_SMOOTH)
    placement = as_placement(placement)
    if isinstance(placement, LaplacianSmoothing):
        if smooth not in (0, placement.sweeps):
            raise ArgumentError(
                f"smooth={smooth} and placement={placement!r} ask for two smoothings; give one"
            )
        smooth, placement = placement.sweeps, PaperPlacement()
    if max_memory is not None:
        max_memory = whole_number(max_memory, "max_memory", minimum=1)
    if threads is not None:
        threads = whole_number(threads, "threads", minimum=1)
    base = _block_mesh_of(domain_or_mesh)
    neighbour = cell_neighbours(base.cells, base.n_points)
    n_shared = int(np.count_nonzero(neighbour >= 0)) // 2
    check_memory(base, n_shared, level, max_memory)
    check_precision(base, level)
    try:
        if placement.nested:
            mesh = build(base, neighbour, level, smooth, progress, threads)
        else:
            mesh = build_placed(base, level, smooth, placement, progress, threads)
    except MemoryError:
        raise ResourceError(
            f"ran out of memory refining {base.name or 'the mesh'} to level {base.level + level} "
            "although the prediction fitted (other programs may be using memory); try a lower "
            "level or free memory"
        ) from None
    grading = getattr(domain_or_mesh, "grading", None)
    if grading and not isinstance(domain_or_mesh, Mesh):
        mesh = graded_mesh(base, mesh, grading)
    if numbering == "rcm":
        mesh = mesh.with_rcm_numbering()
    return mesh


def _refine_locally(
    target: BlockSource | Mesh | PolygonMesh,
    level: int | None,
    cells: Any,
    numbering: str,
    smooth: int,
    max_memory: int | None,
    progress: ProgressCallback | None,
    threads: int | None,
    scheme: str = "pentagons",
) -> PolygonMesh:
    """:func:`refine` with ``cells=``, or of a PolygonMesh: the local rule, round by round."""
    rounds = 1 if level is None and cells is not None else level
    if rounds is None:
        raise ArgumentError("refine() of a PolygonMesh needs a level or cells=")
    rounds = whole_number(rounds, "level")
    choice(numbering, ("nested",), "numbering (local refinement keeps the nested numbering)")
    if whole_number(smooth, "smooth"):
        raise ArgumentError(
            "smooth= applies to uniform refinement; local refinement keeps the paper's rule"
        )
    if threads is not None:
        whole_number(threads, "threads", minimum=1)
    if max_memory is not None:
        max_memory = whole_number(max_memory, "max_memory", minimum=1)
    mesh = target if isinstance(target, PolygonMesh) else _block_mesh_of(target)
    if rounds == 0:
        return as_polygon_mesh(mesh)
    marking = cells if cells is not None else np.ones(mesh.n_cells, dtype=bool)
    return refine_locally(
        mesh, marking, rounds, max_memory=max_memory, progress=progress, scheme=scheme
    )


def check_level(
    domain_or_mesh: BlockSource | Mesh, level: int, *, max_memory: int | None = None
) -> None:
    """Raise now if refining ``domain_or_mesh`` ``level`` times cannot be done.

    The checks :func:`refine` makes before it builds anything: a whole number ``level`` up to
    :data:`MAX_LEVEL`, a predicted size within ``max_memory`` (default: the memory available),
    cells that double precision resolves. For callers that refine one level at a time.

    Examples
    --------
    >>> import blockmesh
    >>> check_level(blockmesh.load_domain("sp"), 60)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ResourceError: level 60 of 'sp' needs about 10^48 B ...
    """
    level = whole_number(level, "level", maximum=MAX_LEVEL)
    if max_memory is not None:
        max_memory = whole_number(max_memory, "max_memory", minimum=1)
    base = _block_mesh_of(domain_or_mesh)
    neighbour = cell_neighbours(base.cells, base.n_points)
    check_memory(base, int(np.count_nonzero(neighbour >= 0)) // 2, level, max_memory)
    check_precision(base, level)
