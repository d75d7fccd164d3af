"""``blockmesh mesh`` of one domain: cut to sizes, refine, measure, draw and write; its report.

Each stage has its progress line and turns running out of memory into a located
:class:`~blockmesh.errors.ResourceError`; the whole command's peak is predicted and checked
against the memory first.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from typing import Any, NamedTuple

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, process_rss
from blockmesh.commands._progress import StageProgress
from blockmesh.commands.common import fill_template, levels_to_add, printable
from blockmesh.commands.mesh.arguments import DEFAULT_LEVEL
from blockmesh.domain.domain import Domain
from blockmesh.errors import BlockMeshError, ResourceError
from blockmesh.io import check_options, format_for_path, write
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.improve import refine_with_rule
from blockmesh.refinement.local import predict_local_size, refine_locally
from blockmesh.refinement.marking import check_marks
from blockmesh.refinement.pipeline import refine
from blockmesh.refinement.sizes import check_fits, mesh_command_predictor
from blockmesh.sizing.measure import size_report
from blockmesh.sizing.spec import as_size_spec


def _export_key(options: dict[str, Any], output: str | None):
    if not output:
        return None
    fmt = format_for_path(output, options["format"])
    chosen = check_options(fmt, split=options["split"], compression=options["compression"])
    return fmt.name, chosen.get("split"), chosen.get("compression", fmt.default_compression)


def _check_memory(target: Domain | Mesh, options: dict[str, Any], output: str | None):
    """The whole command's predicted peak; ResourceError before anything big is allocated."""
    predict = mesh_command_predictor(
        target,
        numbering=options["numbering"],
        smooth=options["smooth"],
        export=_export_key(options, output),
        plot=bool(options["plot"]),
        quality_plot=bool(options["quality_plot"]),
    )
    given = options["max_memory"]
    limit = given if given is not None else available_memory() + process_rss()
    return check_fits(
        predict,
        options["level"],
        limit,
        what=target.name or "the mesh",
        offset=target.level if isinstance(target, Mesh) else 0,
        source="--max-memory" if given is not None else "the memory available now",
    )


@contextlib.contextmanager
def _stage(progress: StageProgress, label: str, prediction) -> Iterator[Callable[[int, int], None]]:
    """A stage of the command: its progress line, and MemoryError as a located ResourceError."""
    try:
        with progress.stage(label) as tick:
            yield tick
    except MemoryError:
        raise ResourceError(
            f"ran out of memory while {label} (the command was predicted to need about "
            f"{format_bytes(prediction.peak_bytes)} at level {prediction.level}); other programs "
            "may be using memory: free some, or try a lower level"
        ) from None


def _sized(
    target: Domain | Mesh | PolygonMesh, options: dict[str, Any], progress: StageProgress
) -> tuple[Domain | Mesh | PolygonMesh, int]:
    """The domain cut to ``--size`` (when given), and the levels to add to it.

    Without ``--level``: a domain cut to sizes (``--size`` or a ``[size]`` table) and a mesh
    file add none, any other domain :data:`DEFAULT_LEVEL`.
    """
    size = options["size"]
    if options.get("uniform"):
        if not isinstance(target, Domain):
            raise BlockMeshError("--uniform cuts a domain into cells; give the domain, not a mesh")
        level = options["level"] if options["level"] is not None else DEFAULT_LEVEL
        with progress.stage("cutting into cells of one size"):
            return target.uniform(level, max_memory=options["max_memory"]), 0
    if size is None:
        sized = isinstance(target, Domain) and target.size_field is not None
        return target, levels_to_add(options["level"], target, 0 if sized else DEFAULT_LEVEL)
    if not isinstance(target, Domain):
        raise BlockMeshError(
            f"--size cuts a domain into cells of a size; {target.name or 'this'} is a mesh "
            "(refine it with --level, or give the domain it came from)"
        )
    with progress.stage("cutting into cells of the sizes asked"):
        domain = target.with_size(
            as_size_spec(size, source="--size"),
            gradation=options["gradation"],
            max_memory=options["max_memory"],
        )
    return domain, options["level"] if options["level"] is not None else 0


class _PolygonPrediction(NamedTuple):
    """What the stages' messages say of a polygon mesh refined further (its own guard ran)."""

    peak_bytes: int
    level: int


def _refine_polygons(
    target: PolygonMesh, options: dict[str, Any], progress: StageProgress
) -> tuple[PolygonMesh, _PolygonPrediction]:
    """A polygon mesh read from a file, every cell split ``--level`` times by the local rule."""
    if options["smooth"] or options["quality_rule"] != "paper" or options["numbering"] != "nested":
        raise BlockMeshError(
            f"{printable(target.name or 'the mesh')} is a polygon mesh (hanging nodes): it is "
            "refined by the paper's rule, without --smooth, --quality-rule or --numbering rcm"
        )
    size = predict_local_size(target, np.ones(target.n_cells, dtype=bool))
    prediction = _PolygonPrediction(size.peak_bytes, target.level + options["level"])
    if options["level"] == 0:
        return target, prediction
    with _stage(progress, "refining", prediction) as tick:
        mesh = refine(target, options["level"], max_memory=options["max_memory"], progress=tick)
    return mesh, prediction


def mesh_one(
    target: Domain | Mesh | PolygonMesh,
    options: dict[str, Any],
    output: str | None,
    progress: StageProgress | None = None,
) -> dict[str, Any]:
    """Mesh, draw and write one domain (or refine a mesh further); the JSON-ready report."""
    progress = progress or StageProgress("", enabled=False)
    started = time.perf_counter()
    target, level = _sized(target, options, progress)
    options = {**options, "level": level}
    mesh: Mesh | PolygonMesh
    prediction: Any
    if isinstance(target, PolygonMesh):
        mesh, prediction = _refine_polygons(target, options, progress)
    else:
        prediction = _check_memory(target, options, output)
        with _stage(progress, "refining", prediction) as tick:
            mesh = refine(
                target,
                options["level"] if options["quality_rule"] == "paper" else 0,
                smooth=options["smooth"],
                max_memory=options["max_memory"],
                progress=tick,
            )
            if options["quality_rule"] != "paper":
                mesh = refine_with_rule(
                    mesh,
                    options["level"],
                    rule=options["quality_rule"],
                    smooth=options["smooth"],
                    max_memory=options["max_memory"],
                )
    local = None
    if options["marking"] is not None:
        with _stage(progress, "refining the marked cells", prediction) as tick:
            mesh, local = _refine_marked(mesh, options, tick)
    seconds = time.perf_counter() - started
    field = target.size_field if isinstance(target, Domain) else None
    with _stage(progress, "measuring the cells", prediction) as tick:
        quality = mesh.quality(progress=tick)
        bandwidth: dict[str, int | None] = {"nested": mesh.bandwidth(), "rcm": None}
        cells = mesh.cells if isinstance(mesh, Mesh) else mesh.polygon_cells()
        sizes = size_report(mesh.points, cells, field, curves=mesh.curves)
    if options["numbering"] == "rcm" and isinstance(mesh, Mesh):
        with _stage(progress, "renumbering (reverse Cuthill-McKee)", prediction):
            mesh = mesh.with_rcm_numbering()
            bandwidth["rcm"] = mesh.bandwidth()
    if quality.not_strictly_convex:
        mesh.check_geometry()  # names the first broken cell; never report a broken mesh as made
    report = {
        "domain": mesh.name,
        "level": mesh.level,
        "nodes": mesh.n_points,
        "cells": mesh.n_cells,
        "edges": mesh.n_edges,
        "boundary_edges": int(mesh.boundary_edges.shape[0]),
        "area": mesh.area,
        "quality": quality.as_dict(),
        "sizes": sizes.as_dict(),
        "size_asked": options["size"] if field is not None else None,
        "bandwidth": bandwidth,
        "numbering": options["numbering"],
        "smooth": options["smooth"],
        "placement": options["quality_rule"],
        "quality_rule": options["quality_rule"],  # the earlier key, kept
        "seconds": seconds,
        "predicted_peak_bytes": prediction.peak_bytes,
        "plot": None,
        "quality_plot": None,
        "size_plot": None,
        "output": None,
    }
    if local is not None:
        report["local_refinement"] = local
    if options["plot"]:
        from blockmesh.plot import plot_mesh

        with _stage(progress, "drawing the mesh", prediction), _fill(options["plot"], mesh) as at:
            report["plot"] = str(plot_mesh(mesh, at))
    if options["quality_plot"]:
        from blockmesh.plot import plot_quality

        with (
            _stage(progress, "drawing the quality histograms", prediction),
            _fill(options["quality_plot"], mesh) as at,
        ):
            report["quality_plot"] = str(plot_quality(mesh, at))
    if options["size_plot"]:
        from blockmesh.plot import plot_sizes

        with (
            _stage(progress, "drawing the cell sizes", prediction),
            _fill(options["size_plot"], mesh) as at,
        ):
            report["size_plot"] = str(plot_sizes(mesh, at, field=field))
    if output:
        with (
            _fill(output, mesh) as target_path,
            _stage(progress, f"writing {target_path}", prediction),
        ):
            report["output"] = str(
                write(
                    mesh,
                    target_path,
                    format=options["format"],
                    split=options["split"],
                    compression=options["compression"],
                )
            )
    return report


def _refine_marked(
    mesh: Mesh | PolygonMesh, options: dict[str, Any], tick: Callable[[int, int], None]
) -> tuple[PolygonMesh, dict[str, Any]]:
    """The rounds of local refinement the options ask for, and what they did."""
    marking = options["marking"]
    rounds = options["refine_rounds"]
    check_marks(marking, mesh)  # a marking of no cell is an error, not a silent no-op
    marked: list[int] = []

    def counting(current: Mesh | PolygonMesh) -> np.ndarray:
        mask = np.asarray(marking(current), dtype=bool)
        marked.append(int(mask.sum()))
        return mask

    counting.__doc__ = marking.__doc__
    refined = refine_locally(
        mesh,
        counting,
        rounds,
        max_memory=options["max_memory"],
        progress=tick,
        scheme=options["refine_scheme"],
    )
    return refined, {
        "rounds": len(marked) if marked[-1] else len(marked) - 1,
        "marked": [m for m in marked if m],
        "marking": marking.__doc__,
        "scheme": options["refine_scheme"],
        "hanging_nodes": int(refined.hanging_nodes().size),
        "max_vertices": int(refined.cell_sizes().max()),
    }


def _fill(pattern: str, mesh: Mesh | PolygonMesh) -> contextlib.AbstractContextManager[str]:
    return fill_template(pattern, name=mesh.name or "mesh", level=mesh.level)
