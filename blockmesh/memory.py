"""The memory a whole command needs, predicted before anything big is allocated.

A mesh's counts are known in closed form before it is built
(:func:`blockmesh.refinement.predict_size`), and every stage of a command needs memory in
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
>>> from blockmesh.refinement import predict_size
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

from .errors import ResourceError
from .template import TEMPLATE_CACHE_BYTES, node_count, template_is_alive

__all__ = [
    "STAGE_COSTS",
    "MemoryPrediction",
    "StageCost",
    "check_fits",
    "largest_fitting_level",
    "mesh_command_predictor",
    "peak_rss",
    "predict_mesh_command",
    "process_rss",
    "reset_peak_rss",
]


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
    ("export", "vtu", "none"): StageCost(290, 2_000_000, _IO),
    ("export", "vtu", "zlib"): StageCost(250, 2_000_000, _IO),
    ("export", "vtu", "lzma"): StageCost(225, 2_000_000, _IO),
    ("export", "msh", "tri3"): StageCost(385, 2_000_000, _IO),
    ("export", "msh", "tri5"): StageCost(620, 2_000_000, _IO),
    ("export", "msh", "quad5"): StageCost(810, 2_000_000, _IO),
    ("export", "openfoam", None): StageCost(435, 2_000_000, _IO),
}

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


def process_rss() -> int:
    """Resident bytes of this process now (``VmRSS``; 0 where ``/proc`` is missing).

    Examples
    --------
    >>> process_rss() > 0
    True
    """
    return _status_field("VmRSS:")


def peak_rss() -> int:
    """Peak resident bytes of this process (``VmHWM``, resettable by :func:`reset_peak_rss`)."""
    return _status_field("VmHWM:")


def reset_peak_rss() -> bool:
    """Restart the peak (``VmHWM``) from the current resident set; False where unsupported."""
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as handle:
            handle.write("5")
    except OSError:
        return False
    return True


def _status_field(field: str) -> int:
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith(field):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    if field == "VmHWM:":
        import resource

        return int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024
    return 0


def refinement_working_bytes(
    n_blocks: int, steps: int, *, smooth: int = 0, threads: int | None = None
) -> int:
    """Bytes a refinement holds besides its output: working arrays and the templates it builds.

    Without smoothing, the blocks are refined :data:`~blockmesh.grouped_refinement.BLOCK_LEVEL`
    levels at a time (the base first refined to the difference, a small mesh of its own): each
    worker thread holds one group's working arrays
    (:func:`~blockmesh.grouped_refinement.workspace_bytes`), and the ids along every block edge
    are kept. With smoothing, every block's coordinates, ids and masks at once, and each level's
    sparse adjacency. A template (about :data:`TEMPLATE_BYTES_PER_CELL` bytes per cell of its
    level) is counted unless the template cache already holds it.
    """
    from .grouped_refinement import BLOCK_LEVEL, workspace_bytes
    from .threads import default_threads

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
        From :func:`blockmesh.refinement.predict_size`.
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
    from .grouped_refinement import BLOCK_LEVEL

    template_level = steps if smooth else min(steps, BLOCK_LEVEL)
    template = TEMPLATE_BYTES_PER_CELL * 6**template_level
    if not template_is_alive(template_level) and template <= TEMPLATE_CACHE_BYTES:
        mesh += template
    stages.append(("report", base + mesh + STAGE_COSTS["report",].bytes(cells)))
    if numbering == "rcm":
        stages.append(("rcm numbering", base + mesh + STAGE_COSTS["rcm",].bytes(cells)))
    if plot:
        from .plot import DRAW_LIMIT

        key: tuple[str | None, ...] = ("plot",) if cells > DRAW_LIMIT else ("plot", "polygons")
        stages.append(("plot", base + mesh + STAGE_COSTS[key].bytes(cells)))
    if quality_plot:
        stages.append(("quality plot", base + mesh + STAGE_COSTS["quality_plot",].bytes(cells)))
    if export is not None:
        fmt, split, compression = export
        option = split if fmt == "msh" else compression
        key = ("export", fmt, option)
        if key not in STAGE_COSTS:
            key = ("export", fmt, {"vtu": "zlib", "xdmf": "none"}.get(fmt))
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
    >>> from blockmesh.refinement import predict_size
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
    >>> from blockmesh.refinement import predict_size
    >>> def predict(level):
    ...     return predict_mesh_command(predict_size(1, 5, 0, 5, level, level), n_blocks=1,
    ...                                 baseline=10**8)
    >>> check_fits(predict, 9, 10**9, what="sp")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ResourceError: sp at level 9 needs about ... (refinement), ... fits is 8
    """
    from .refinement import format_bytes

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
    from .mesh import Mesh
    from .refinement import predict_size

    if isinstance(target, Mesh):
        n_boundary = int(target.boundary_edges.shape[0])
        counts = (target.n_cells, target.n_points, (5 * target.n_cells - n_boundary) // 2)
        base_level = target.level
    else:
        n_boundary = int(target.boundary_edges.shape[0])
        counts = (target.n_blocks, target.n_vertices, target.n_shared_edges)
        base_level = 0
    baseline = process_rss()

    def predict(level: int) -> MemoryPrediction:
        size = predict_size(*counts, n_boundary, level, base_level + level)
        return predict_mesh_command(
            size, n_blocks=counts[0], steps=level, baseline=baseline, **stages
        )

    return predict
