"""The memory a whole command needs, predicted before anything big is allocated.

A mesh's counts are known in closed form before it is built
(:func:`blockmesh.refinement.sizes.predict_size`), and every stage of a command needs memory in
proportion to them: the refinement its output plus one block's working arrays (and the template
of the level, unless cached), the quality report almost nothing (it runs in cache-sized chunks),
each export format what its writer builds on top of the mesh, the pictures their figures.
:func:`predict_mesh_command` adds these up stage by stage on top of what the process holds now
(its resident set, read from ``/proc``) and of the libraries a stage still has to import, and
gives the peak of the whole command and the stage where it falls.

The bytes per cell of each stage are measured, not guessed: ``python benchmarks/bench_memory.py
--calibrate`` measures each stage's extra resident memory at two levels and prints the table
:data:`STAGE_COSTS`; ``python benchmarks/bench_memory.py`` checks the whole commands' measured peak
resident sets against the predictions at levels 6 to 9 (within 25 %).

Examples
--------
>>> from blockmesh.refinement.sizes import predict_size
>>> size = predict_size(1, 5, 0, 5, 8, 8)
>>> p = predict_mesh_command(size, n_blocks=1, export=("vtu", None, "zlib"), baseline=10**8)
>>> p.peak_stage, p.peak_bytes > size.output_bytes
('export (vtu, zlib)', True)
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from blockmesh._system.memory import format_bytes, process_rss
from blockmesh._system.threads import default_threads
from blockmesh.errors import ResourceError
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.grouped import BLOCK_LEVEL, workspace_bytes
from blockmesh.refinement.template import TEMPLATE_CACHE_BYTES, node_count, template_is_alive

__all__ = [
    "DRAW_LIMIT",
    "LU_BYTES_PER_NONZERO",
    "SOLVE_COSTS",
    "STAGE_COSTS",
    "MemoryPrediction",
    "MeshSize",
    "StageCost",
    "check_fits",
    "largest_fitting_level",
    "lu_nonzeros",
    "mesh_command_predictor",
    "predict_mesh_command",
    "predict_size",
    "predict_solve_command",
    "solve_command_predictor",
]

#: Meshes with more cells than this are drawn as a picture of their cell density with the block
#: outlines and patches (:func:`blockmesh.plot.plot_mesh`): every polygon would be far below a
#: pixel and take minutes to draw. Here because the pictures' predicted memory depends on it.
DRAW_LIMIT = 200_000


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


@dataclass(frozen=True)
class StageCost:
    """Resident bytes a stage needs beyond the live mesh: ``per_cell * M + constant``.

    ``imports`` are the modules the stage imports, with what importing them costs, counted only
    while they are not imported yet.
    """

    per_cell: int
    constant: int = 0
    imports: tuple[tuple[str, int], ...] = ()

    def bytes(self, cells: int) -> int:
        """Bytes for a mesh of ``cells`` cells, imports included where still needed.

        Integer arithmetic, so that absurd levels give absurd (not overflowing) sizes.
        """
        imports = sum(cost for module, cost in self.imports if module not in sys.modules)
        return self.per_cell * cells + self.constant + imports


_IO = (("blockmesh.io", 10_000_000),)
_PLOT = (("matplotlib.pyplot", 45_000_000),)
_SPARSE = (("scipy.sparse.csgraph", 30_000_000),)

#: Extra resident bytes of each stage (measured by ``benchmarks/bench_memory.py --calibrate`` on
#: this project's machine; keys are stage names, exports as ``("export", format, split or
#: compression)``).
STAGE_COSTS: dict[tuple[str | None, ...], StageCost] = {
    ("report",): StageCost(0, 1_000_000),
    ("rcm",): StageCost(760, 0, _SPARSE),
    ("plot",): StageCost(10, 20_000_000, _PLOT),
    ("plot", "polygons"): StageCost(900, 5_000_000, _PLOT),
    ("quality_plot",): StageCost(26, 60_000_000, _PLOT),
    ("export", "xdmf", "none"): StageCost(60, 12_000_000, _IO),
    ("export", "xdmf", "zlib"): StageCost(58, 22_000_000, _IO),
    ("export", "npz", None): StageCost(10, 2_000_000, _IO),
    ("export", "mat", None): StageCost(345, 2_000_000, (*_IO, ("scipy.io", 20_000_000))),
    # The streaming VTU writer holds pieces of a few MB and, compressing, a few blocks per
    # thread (measured 12-18 MB, 1-2 MB and 13-16 MB at levels 6-8 of sp on two threads; the
    # constants leave room for MAX_THREADS threads).
    ("export", "vtu", "none"): StageCost(0, 20_000_000, _IO),
    ("export", "vtu", "zlib"): StageCost(0, 40_000_000, _IO),
    ("export", "vtu", "lzma"): StageCost(0, 120_000_000, _IO),
    ("export", "msh", "tri3"): StageCost(385, 2_000_000, _IO),
    ("export", "msh", "tri5"): StageCost(620, 2_000_000, _IO),
    ("export", "msh", "quad5"): StageCost(810, 2_000_000, _IO),
    ("export", "openfoam", None): StageCost(435, 2_000_000, _IO),
}

#: Extra resident bytes of ``blockmesh solve`` before its linear solve, per cell of the mesh: the
#: projections, cell matrices, loads and the assembled system held when the factorisation
#: starts (measured by ``benchmarks/bench_solve_memory.py`` on square, l-shape and lake-island,
#: levels 3-5: 1,400-2,200 bytes per cell for poisson, 4,700-7,000 for elasticity, the larger
#: figures on the smaller meshes).
SOLVE_COSTS: dict[str, StageCost] = {
    "poisson": StageCost(1_800, 10_000_000, (("blockmesh.vem", 40_000_000),)),
    "elasticity": StageCost(5_000, 10_000_000, (("blockmesh.vem", 40_000_000),)),
}
#: Resident bytes per non-zero of SuperLU's factors L + U, values, indices and the work space of
#: the factorisation together (measured 20-31).
LU_BYTES_PER_NONZERO = 25
#: The multigrid hierarchy and the conjugate-gradient vectors, per cell (``solver="amg"``).
AMG_BYTES_PER_CELL = 1_500


def lu_nonzeros(nodes: int, components: int = 1) -> int:
    """Predicted non-zeros of SuperLU's L + U for a pentagon mesh of ``nodes`` nodes.

    With the minimum-degree ordering the solver uses, the fill of these planar meshes grows as
    ``n log n`` (as nested dissection's): measured ``nnz(L + U) / n = 39 .. 51`` for 7,700 to
    360,000 nodes, fitted by ``14 + 2.1 log2 n`` within 6 %. Two unknowns per node (elasticity)
    give ``components**2`` times as many (measured 3.7-4.0). Integer arithmetic: absurd sizes do
    not overflow.

    Examples
    --------
    The square at level 5 (93,153 unknowns) gave 4,641,904 non-zeros:

    >>> round(lu_nonzeros(93153) / 4_641_904, 2)
    1.0
    """
    nodes = max(int(nodes), 1)
    return components**2 * nodes * (140 + 21 * nodes.bit_length()) // 10


def predict_solve_command(
    size,
    *,
    n_blocks: int,
    steps: int | None = None,
    equation: str = "poisson",
    solver: str = "direct",
    smooth: int = 0,
    plot: bool = False,
    baseline: int | None = None,
) -> MemoryPrediction:
    """Peak resident memory of ``blockmesh solve`` at each stage, for a mesh of ``size``.

    The stages: the refinement (as :func:`predict_mesh_command`), the assembly
    (:data:`SOLVE_COSTS`), the linear solve (the direct solver's factors: :func:`lu_nonzeros`
    times :data:`LU_BYTES_PER_NONZERO`; multigrid: :data:`AMG_BYTES_PER_CELL`) and the picture.

    Examples
    --------
    >>> from blockmesh.refinement.sizes import predict_size
    >>> p = predict_solve_command(predict_size(48, 63, 80, 16, 6, 6), n_blocks=48, baseline=0)
    >>> [name for name, _ in p.stages], p.peak_stage
    (['refinement', 'assembly (poisson)', 'factorisation (direct solver)'], ...)
    """
    mesh_only = predict_mesh_command(
        size, n_blocks=n_blocks, steps=steps, smooth=smooth, baseline=baseline
    )
    base = mesh_only.baseline
    held = base + size.output_bytes + SOLVE_COSTS[equation].bytes(size.cells)
    stages = [mesh_only.stages[0], (f"assembly ({equation})", held)]
    components = 2 if equation == "elasticity" else 1
    if solver == "direct":
        lu = LU_BYTES_PER_NONZERO * lu_nonzeros(size.nodes, components)
        stages.append(("factorisation (direct solver)", held + lu))
    else:
        stages.append((f"{solver} solve", held + AMG_BYTES_PER_CELL * size.cells))
    if plot:
        stages.append(("plot", held + STAGE_COSTS["plot", "polygons"].bytes(size.cells)))
    return MemoryPrediction(size.level, base, tuple(stages))


#: Template bytes per cell of its level (cells, corners of every level, sources).
TEMPLATE_BYTES_PER_CELL = 62


@dataclass(frozen=True)
class MemoryPrediction:
    """The predicted peak resident memory of each stage of a command, in order.

    Attributes
    ----------
    level : int
    baseline : int
        Resident bytes of the process when the prediction was made.
    stages : tuple of (str, int)
        Each stage's name and the process's predicted peak resident bytes during it.
    """

    level: int
    baseline: int
    stages: tuple[tuple[str, int], ...]

    @property
    def peak_bytes(self) -> int:
        """The largest stage peak: what the whole command needs."""
        return max(peak for _, peak in self.stages)

    @property
    def peak_stage(self) -> str:
        """The stage where the peak falls."""
        return max(self.stages, key=lambda stage: stage[1])[0]


def refinement_working_bytes(
    n_blocks: int, steps: int, *, smooth: int = 0, threads: int | None = None
) -> int:
    """Bytes a refinement holds besides its output: working arrays and the templates it builds.

    Without smoothing, the blocks are refined :data:`~blockmesh.refinement.grouped.BLOCK_LEVEL`
    levels at a time (the base first refined to the difference, a small mesh of its own): each
    worker thread holds one group's working arrays
    (:func:`~blockmesh.refinement.grouped.workspace_bytes`), and the ids along every block edge
    are kept. With smoothing, every block's coordinates, ids and masks at once, and each level's
    sparse adjacency. A template (about :data:`TEMPLATE_BYTES_PER_CELL` bytes per cell of its
    level) is counted unless the template cache already holds it.
    """
    if smooth:
        working = 41 * node_count(steps) * n_blocks + 200 * n_blocks * 6**steps
        template_level = steps
    else:
        template_level = min(steps, BLOCK_LEVEL)
        blocks = n_blocks * 6 ** (steps - template_level)
        threads = default_threads() if threads is None else threads
        working = threads * workspace_bytes(blocks, template_level)
        working += 16 * blocks * (2**template_level + 1) * 5  # ids along every block edge
        working += 100 * blocks  # the base refined to the blocks, when it is
    if not template_is_alive(template_level):
        working += TEMPLATE_BYTES_PER_CELL * 6**template_level
    return working


def predict_mesh_command(
    size,
    *,
    n_blocks: int,
    steps: int | None = None,
    numbering: str = "nested",
    smooth: int = 0,
    export: tuple[str, str | None, str | None] | None = None,
    plot: bool = False,
    quality_plot: bool = False,
    baseline: int | None = None,
) -> MemoryPrediction:
    """Peak resident memory of ``blockmesh mesh`` at each stage, for a mesh of ``size``.

    Parameters
    ----------
    size : MeshSize
        From :func:`blockmesh.refinement.sizes.predict_size`.
    n_blocks : int
        Cells of the mesh being refined (the domain's blocks).
    steps : int, optional
        Levels of refinement (default ``size.level``).
    numbering, smooth
        As :func:`blockmesh.refine`.
    export : (format, split, compression), optional
        The output, as the writer's format name, ``split`` and ``compression`` (None: default).
    plot, quality_plot : bool
        Whether the mesh and its quality histograms are drawn.
    baseline : int, optional
        Resident bytes before the command's work (default: this process now).
    """
    steps = size.level if steps is None else steps
    base = process_rss() if baseline is None else int(baseline)
    cells = size.cells
    mesh = size.output_bytes
    stages = [
        ("refinement", base + mesh + refinement_working_bytes(n_blocks, steps, smooth=smooth))
    ]
    # A template the refinement builds stays cached for the later stages when it fits the cache.

    template_level = steps if smooth else min(steps, BLOCK_LEVEL)
    template = TEMPLATE_BYTES_PER_CELL * 6**template_level
    if not template_is_alive(template_level) and template <= TEMPLATE_CACHE_BYTES:
        mesh += template
    stages.append(("report", base + mesh + STAGE_COSTS["report",].bytes(cells)))
    if numbering == "rcm":
        stages.append(("rcm numbering", base + mesh + STAGE_COSTS["rcm",].bytes(cells)))
    if plot:
        key: tuple[str | None, ...] = ("plot",) if cells > DRAW_LIMIT else ("plot", "polygons")
        stages.append(("plot", base + mesh + STAGE_COSTS[key].bytes(cells)))
    if quality_plot:
        stages.append(("quality plot", base + mesh + STAGE_COSTS["quality_plot",].bytes(cells)))
    if export is not None:
        fmt, split, compression = export
        option = split if fmt == "msh" else compression
        key = ("export", fmt, option)
        if key not in STAGE_COSTS:
            key = ("export", fmt, {"vtu": "none", "xdmf": "none"}.get(fmt))
        cost = STAGE_COSTS.get(key, StageCost(0))
        stages.append(
            (f"export ({fmt}{', ' + option if option else ''})", base + mesh + cost.bytes(cells))
        )
    return MemoryPrediction(size.level, base, tuple(stages))


def largest_fitting_level(
    predict: Callable[[int], MemoryPrediction], level: int, limit: int
) -> int:
    """The highest level below ``level`` whose predicted peak is within ``limit`` (-1: none).

    A bisection (the peak grows with the level): O(log level) predictions, so an absurd level
    (``--level 100000``) is answered at once.

    Examples
    --------
    >>> from blockmesh.refinement.sizes import predict_size
    >>> def predict(level):
    ...     return predict_mesh_command(predict_size(1, 5, 0, 5, level, level), n_blocks=1,
    ...                                 baseline=10**8)
    >>> largest_fitting_level(predict, 100_000, 10**9)
    8
    """
    low, high = -1, level - 1  # low fits (or is -1); every level above high is too big
    while low < high:
        middle = (low + high + 1) // 2
        if predict(middle).peak_bytes <= limit:
            low = middle
        else:
            high = middle - 1
    return low


def check_fits(
    predict: Callable[[int], MemoryPrediction],
    level: int,
    limit: int,
    *,
    what: str,
    offset: int = 0,
    source: str = "the memory available now",
) -> MemoryPrediction:
    """The prediction at ``level``; ResourceError when its peak exceeds ``limit``.

    The message names the stage, the predicted size, the limit and the largest level that fits
    (levels are shown plus ``offset``: the level of the mesh being refined).

    Examples
    --------
    >>> from blockmesh.refinement.sizes import predict_size
    >>> def predict(level):
    ...     return predict_mesh_command(predict_size(1, 5, 0, 5, level, level), n_blocks=1,
    ...                                 baseline=10**8)
    >>> check_fits(predict, 9, 10**9, what="sp")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ResourceError: sp at level 9 needs about ... (refinement), ... fits is 8
    """
    prediction = predict(level)
    if prediction.peak_bytes <= limit:
        return prediction
    fits = largest_fitting_level(predict, level, limit)
    advice = (
        f"the largest level that fits is {offset + fits}"
        if fits >= 0
        else "not even the unrefined mesh fits"
    )
    raise ResourceError(
        f"{what} at level {offset + level} needs about {format_bytes(prediction.peak_bytes)} at "
        f"its peak ({prediction.peak_stage}), more than {source} ({format_bytes(limit)}); {advice}"
    )


def _sizes(target) -> Callable[[int], Any]:
    """``size(steps)``: the :class:`~blockmesh.refinement.sizes.MeshSize` of ``target`` refined."""
    if isinstance(target, Mesh):
        n_boundary = int(target.boundary_edges.shape[0])
        counts = (target.n_cells, target.n_points, (5 * target.n_cells - n_boundary) // 2)
        base_level = target.level
    else:
        n_boundary = int(target.boundary_edges.shape[0])
        counts = (target.n_blocks, target.n_vertices, target.n_shared_edges)
        base_level = 0

    def size(steps: int) -> Any:
        return predict_size(*counts, n_boundary, steps, base_level + steps)

    return size


def _cells_of(target) -> int:
    return int(target.n_cells if isinstance(target, Mesh) else target.n_blocks)


def mesh_command_predictor(target, **stages: Any) -> Callable[[int], MemoryPrediction]:
    """``predict(level)`` for refining ``target`` (a Domain or Mesh) ``level`` times.

    ``stages`` are the options of :func:`predict_mesh_command` (numbering, smooth, export, plot,
    quality_plot); the baseline is this process's resident memory now.

    Examples
    --------
    >>> import blockmesh
    >>> predict = mesh_command_predictor(blockmesh.load_domain("joined-8"), plot=True)
    >>> [stage for stage, _ in predict(7).stages]
    ['refinement', 'report', 'plot']
    """
    size, n_blocks, baseline = _sizes(target), _cells_of(target), process_rss()

    def predict(level: int) -> MemoryPrediction:
        return predict_mesh_command(
            size(level), n_blocks=n_blocks, steps=level, baseline=baseline, **stages
        )

    return predict


def solve_command_predictor(target, **options: Any) -> Callable[[int], MemoryPrediction]:
    """``predict(level)`` for solving on ``target`` (a Domain or Mesh) refined ``level`` times.

    ``options`` are those of :func:`predict_solve_command` (equation, solver, smooth, plot).

    Examples
    --------
    >>> import blockmesh
    >>> predict = solve_command_predictor(blockmesh.load_domain("square"), equation="elasticity")
    >>> predict(6).peak_stage, predict(6).peak_bytes > predict(5).peak_bytes
    ('factorisation (direct solver)', True)
    """
    size, n_blocks, baseline = _sizes(target), _cells_of(target), process_rss()

    def predict(level: int) -> MemoryPrediction:
        return predict_solve_command(
            size(level), n_blocks=n_blocks, steps=level, baseline=baseline, **options
        )

    return predict
