"""Refinement of a block mesh into a conforming all-pentagon mesh, numbered like the paper.

Each cell splits into six (paper eq. 1a): the corners ``v_i``, the edge midpoints
``u_i = (v_i + v_i+1) / 2`` and the inner points ``w_i = (u_i + p) / 2`` with ``p`` the vertex
mean. Level by level, cells in order, each cell numbers the midpoints of its edges that are not
numbered yet, then its five inner points (the paper's ``nodaladdressesforpentagon``, 0-based).

How it is fast: the numbering of one refined pentagon does not depend on its shape, so it is built
once per level (:mod:`blockmesh.template`) and every block maps its local node ids to global ids
with whole-array operations (:mod:`blockmesh.blockplan`). A node on an edge shared by two blocks
is numbered by the lower block, exactly as the paper's walk does, and the higher block reads the
same ids back along the edge. Coordinates are computed level by level from the parent cells with
the paper's arithmetic. Blocks, in groups, are refined independently on worker threads straight
into the output (:mod:`blockmesh.grouped_refinement`); a deep refinement first refines the base and
uses its cells as blocks, which the nested numbering makes the same mesh bit for bit.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.refine(blockmesh.load_domain("square-cut"), 2)
>>> mesh.n_cells, mesh.n_points, mesh.level
(144, 241, 2)
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from . import grouped_refinement as grouped
from .blockplan import edge_id_table, group_node_ids, plan_refinement
from .blockplan import place_level as _place_level
from .checks import choice, whole_number
from .errors import ArgumentTypeError, ResourceError
from .grouped_refinement import RefinedBlocks, refine_blocks
from .mesh import Mesh
from .template import node_count, pentagon_template
from .topology import boundary_slots, cell_neighbours

__all__ = [
    "MAX_LEVEL",
    "MAX_SMOOTH",
    "NUMBERINGS",
    "MeshSize",
    "available_memory",
    "check_level",
    "predict_size",
    "refine",
]

#: Node numberings :func:`refine` offers.
NUMBERINGS = ("nested", "rcm")
#: Highest level asked for that is answered with a size estimate (every level multiplies the
#: cells by 6, so level 30 is beyond any machine already); higher levels are refused outright.
MAX_LEVEL = 10_000
#: Most Laplacian sweeps per level (``smooth``): a few cure most of the distortion.
MAX_SMOOTH = 1_000

if TYPE_CHECKING:
    from .curved_refinement import CurvedBlocks
    from .domain import Domain

ProgressCallback = Callable[[int, int], None]


# --------------------------------------------------------------------------- sizes and memory
@dataclass(frozen=True)
class MeshSize:
    """Counts and memory of a mesh before it is built (docs/mathematics.md §2)."""

    level: int
    cells: int
    nodes: int
    edges: int
    boundary_edges: int
    output_bytes: int
    peak_bytes: int


def predict_size(
    n_blocks: int, n_points: int, n_shared: int, n_boundary: int, steps: int, level: int
) -> MeshSize:
    """Exact counts and the memory a refinement needs, from the closed forms.

    ``n_blocks`` cells with ``n_points`` nodes, ``n_shared`` interior and ``n_boundary``
    boundary edges, refined ``steps`` times to reach ``level``.

    Examples
    --------
    >>> s = predict_size(1, 5, 0, 5, 8, 8)
    >>> s.cells, s.nodes, s.edges
    (1679616, 2520065, 4199680)
    """
    cells = n_blocks * 6**steps
    nodes = n_points + n_blocks * (node_count(steps) - 5) - n_shared * (2**steps - 1)
    edges = (5 * n_blocks * (6**steps + 2**steps)) // 2 - n_shared * 2**steps
    boundary = n_boundary * 2**steps
    # points 16 B, cells 40 B, block_id + parent + region 24 B, boundary 24 B per edge.
    output = 16 * nodes + 64 * cells + 24 * boundary
    # Global ids of the block nodes and the coarser levels' cells while coordinates are computed.
    working = 8 * n_blocks * node_count(steps) + 16 * cells
    return MeshSize(level, cells, nodes, edges, boundary, output, output + working)


def available_memory() -> int:
    """Bytes of memory available to this process now (``MemAvailable`` on Linux).

    Examples
    --------
    >>> available_memory() > 0
    True
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1 << 62


def format_bytes(n: int | float) -> str:
    """A byte count for people: ``"1.2 GB"``; from 10^15 on, the power of ten.

    Examples
    --------
    >>> format_bytes(999), format_bytes(1_234_567), format_bytes(6**300)
    ('999 B', '1.2 MB', '10^233 B')
    """
    if n >= 1e15:
        return f"10^{_log10(n)} B"
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.1f} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1000
    raise AssertionError  # pragma: no cover


def format_count(n: int) -> str:
    """A count with thousands separators; beyond 10^15 as a power of ten (no 200-digit numbers).

    Examples
    --------
    >>> format_count(1_679_616), format_count(6**1000)
    ('1,679,616', '10^778')
    """
    return f"{n:,}" if n < 10**15 else f"10^{_log10(n)}"


def _log10(n: int | float) -> int:
    return int(math.log10(n)) if n > 0 else 0


# --------------------------------------------------------------------------- refinement
def _block_mesh_of(target: Domain | Mesh) -> Mesh:
    from .domain import Domain

    if isinstance(target, Mesh):
        return target
    if isinstance(target, Domain):
        return target.block_mesh()
    raise ArgumentTypeError(f"refine() takes a Domain or a Mesh, not {type(target).__name__}")


def refine(
    domain_or_mesh: Domain | Mesh,
    level: int,
    *,
    numbering: str = "nested",
    smooth: int = 0,
    max_memory: int | None = None,
    progress: ProgressCallback | None = None,
    threads: int | None = None,
) -> Mesh:
    """Refine a domain (or a mesh) ``level`` times: every cell becomes 6**level pentagons.

    Parameters
    ----------
    domain_or_mesh : Domain or Mesh
        A Domain is refined from its block mesh (level 0); a Mesh from its own cells, so
        ``refine(refine(d, 2), 1)`` equals ``refine(d, 3)``.
    level : int
        How many times each cell is split (>= 0). The result's ``level`` is the input's plus this.
    numbering : {"nested", "rcm"}
        ``"nested"`` (default) is the paper's numbering: every node id of the previous level is
        kept. ``"rcm"`` renumbers the nodes by reverse Cuthill-McKee to reduce the bandwidth.
    smooth : int
        Laplacian sweeps per level (see :mod:`blockmesh.smooth`); 0 keeps the paper's exact scheme.
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
    """
    level = whole_number(level, "level", maximum=MAX_LEVEL)
    choice(numbering, NUMBERINGS, "numbering")
    smooth = whole_number(smooth, "smooth", maximum=MAX_SMOOTH)
    if max_memory is not None:
        max_memory = whole_number(max_memory, "max_memory", minimum=1)
    if threads is not None:
        threads = whole_number(threads, "threads", minimum=1)
    base = _block_mesh_of(domain_or_mesh)
    neighbour = cell_neighbours(base.cells, base.n_points)
    n_shared = int(np.count_nonzero(neighbour >= 0)) // 2
    _check_memory(base, n_shared, level, max_memory)
    _check_precision(base, level)
    try:
        mesh = _build(base, neighbour, level, smooth, progress, threads)
    except MemoryError:
        raise ResourceError(
            f"ran out of memory refining {base.name or 'the mesh'} to level {base.level + level} "
            "although the prediction fitted (other programs may be using memory); try a lower "
            "level or free memory"
        ) from None
    if numbering == "rcm":
        mesh = mesh.with_rcm_numbering()
    return mesh


def _build(
    base: Mesh,
    neighbour: np.ndarray,
    level: int,
    smooth: int,
    progress,
    threads: int | None = None,
) -> Mesh:
    """The refined mesh; cells with curved edges follow the curve-aware rule in the same pass.

    With smoothing, every block is refined at once level by level (the sweeps cross blocks) and
    the curved cells are then recomputed by :func:`~blockmesh.curved_refinement.place_on_curves`.
    """
    from .curved_refinement import CurvedBlocks, place_on_curves

    has_curves = base.curves is not None and len(base.curves) > 0
    if smooth:
        mesh = _build_smoothed(base, neighbour, level, smooth, progress)
        return place_on_curves(base, mesh, level, smooth) if has_curves else mesh
    if level > grouped.BLOCK_LEVEL:
        # Refine the base to the difference first and its cells as blocks (see BLOCK_LEVEL).
        first = level - grouped.BLOCK_LEVEL
        base = _build(base, neighbour, first, 0, None, threads)
        neighbour = cell_neighbours(base.cells, base.n_points)
        level -= first
    curved = CurvedBlocks(base, level) if has_curves else None
    refined = refine_blocks(
        base, neighbour, level, curved=curved, threads=threads, progress=progress
    )
    return _assemble(base, refined, level, curved)


def _build_smoothed(base: Mesh, neighbour: np.ndarray, level: int, smooth: int, progress) -> Mesh:
    """All blocks at once, level by level, with ``smooth`` Laplacian sweeps after each level."""
    from .smooth import block_edge_nodes, smooth_interior

    plan = plan_refinement(base.cells, neighbour, base.n_points, level)
    edge_ids = edge_id_table(plan)
    ids = group_node_ids(plan, 0, base.n_cells, edge_ids)
    template = pentagon_template(level)
    local = np.empty((base.n_cells, template.n_nodes), dtype=np.complex128)
    local[:, :5] = base.points.view(np.complex128)[base.cells, 0]
    points = np.empty(plan.n_nodes, dtype=np.complex128)
    fixed = block_edge_nodes(ids, level)
    for step in range(1, level + 1):
        lo, hi = node_count(step - 1), node_count(step)
        _place_level(local, template.steps[step - 1], lo)
        level_cells = ids[:, pentagon_template(step).cells].reshape(-1, 5)
        points[ids[:, :hi]] = local[:, :hi]
        n_level = int(ids[:, :hi].max()) + 1
        xy = points.view(np.float64).reshape(-1, 2)
        smooth_interior(xy, level_cells, n_level, fixed, smooth)
        local[:, :hi] = points[ids[:, :hi]]
        if progress is not None:
            progress(step, level)
    np.put(points, ids, local, mode="clip")  # shared nodes get the same value twice
    del local
    cell, edge = np.divmod(
        boundary_slots(base.cells, neighbour, base.boundary_edges, base.n_points), 5
    )
    per_block = 6**level
    refined = RefinedBlocks(
        points=points.view(np.float64).reshape(-1, 2),
        cells=np.take(ids, template.cells, axis=1, mode="clip").reshape(-1, 5),
        block_id=_repeat(base.block_id, per_block),
        parent=_parents(base.n_cells * per_block, level),
        region=_repeat(base.region, per_block),
        boundary_nodes=edge_ids[cell, edge],
    )
    return _assemble(base, refined, level)


def _assemble(
    base: Mesh, refined: RefinedBlocks, steps: int, curved: CurvedBlocks | None = None
) -> Mesh:
    """The Mesh of ``base`` refined ``steps`` times from the arrays ``refined``.

    ``curved``, when given, has recorded every curved block: the mesh gets its refined curves.
    """
    along = refined.boundary_nodes
    boundary_edges = np.stack([along[:, :-1], along[:, 1:]], axis=-1).reshape(-1, 2)
    arrays = {
        "points": refined.points,
        "cells": refined.cells,
        "block_id": refined.block_id,
        "parent": refined.parent,
        "boundary_edges": boundary_edges,
        "boundary_patch": np.repeat(base.boundary_patch, 2**steps),
        "region": refined.region,
    }
    for array in arrays.values():
        array.setflags(write=False)
    return Mesh._trusted(
        check_ranges=False,
        **arrays,
        patch_names=base.patch_names,
        region_names=base.region_names,
        level=base.level + steps,
        name=base.name,
        curves=None if curved is None else curved.refined(),
    )


def _parents(n_cells: int, steps: int) -> np.ndarray:
    """Parent of each refined cell: cell c comes from cell c // 6 (none without refinement)."""
    if steps == 0:
        return np.full(n_cells, -1, dtype=np.int64)
    return np.repeat(np.arange(n_cells // 6, dtype=np.int64), 6)


def _repeat(values: np.ndarray, count: int) -> np.ndarray:
    """``np.repeat(values, count)``; all zeros come from ``np.zeros`` (lazily zeroed memory)."""
    if not np.any(values):
        return np.zeros(values.size * count, dtype=np.int64)
    return np.repeat(values, count)


def check_level(
    domain_or_mesh: Domain | Mesh, level: int, *, max_memory: int | None = None
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
    _check_memory(base, int(np.count_nonzero(neighbour >= 0)) // 2, level, max_memory)
    _check_precision(base, level)


def _check_memory(base: Mesh, n_shared: int, level: int, max_memory: int | None) -> None:
    n_boundary = 5 * base.n_cells - 2 * n_shared
    limit = available_memory() if max_memory is None else int(max_memory)

    def size(steps: int) -> MeshSize:
        return predict_size(
            base.n_cells, base.n_points, n_shared, n_boundary, steps, base.level + steps
        )

    wanted = size(level)
    if wanted.peak_bytes <= limit:
        return
    from .memory import largest_fitting_level

    fits = largest_fitting_level(size, level, limit)  # type: ignore[arg-type]
    source = "the limit given" if max_memory is not None else "the memory available now"
    advice = (
        f"the largest level that fits is {base.level + fits}"
        if fits >= 0
        else "not even the unrefined mesh fits"
    )
    name = f" of {base.name!r}" if base.name else ""
    raise ResourceError(
        f"level {base.level + level}{name} needs about {format_bytes(wanted.peak_bytes)} "
        f"({format_count(wanted.cells)} cells, {format_count(wanted.nodes)} nodes), more than "
        f"{source} ({format_bytes(limit)}); {advice}"
    )


#: Each level shrinks the shortest cell edge by at most this factor (half the length, and the
#: inner cells' worsening shape; measured 0.43..0.5 per level on the catalogue).
_EDGE_SHRINK = 0.4
#: Shortest edge allowed, in units of the coordinates' spacing (ulp) where the mesh lies.
_MIN_EDGE_ULPS = 64


def _check_precision(base: Mesh, level: int) -> None:
    """Refuse a level whose cells double precision cannot resolve where the mesh lies.

    Far from the origin the spacing of float64 numbers (their ulp) grows: at 1e15 it is 0.125, so
    a unit square there cannot hold cells a tenth across. The shortest edge at ``level`` is
    estimated from the base's shortest edge and compared with the ulp of the largest coordinate.
    """
    if level == 0 or base.n_cells == 0:
        return
    xy = base.points[base.cells]
    edges = np.hypot(*(np.roll(xy, -1, axis=1) - xy).transpose(2, 0, 1))
    shortest = float(edges.min())
    spacing = float(np.spacing(np.max(np.abs(base.points))))
    finest = next(
        (k for k in range(level + 1) if shortest * _EDGE_SHRINK**k < _MIN_EDGE_ULPS * spacing),
        None,
    )
    if finest is None:
        return
    where = float(np.max(np.abs(base.points)))
    usable = (
        f"the highest level it resolves is {base.level + finest - 1}"
        if finest > 0
        else "not even the unrefined mesh is resolved"
    )
    raise ResourceError(
        f"level {base.level + level} would need cells about "
        f"{shortest * _EDGE_SHRINK**level:.2g} across at coordinates near {where:.3g}, where "
        f"double precision only resolves steps of {spacing:.2g}; {usable}. Move the domain "
        "near the origin (subtract a point inside it from every vertex) to refine further"
    )
