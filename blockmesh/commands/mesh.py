"""``blockmesh mesh``: refine one or many domains, report quality, draw and export.

With several domains (catalogue names, files or globs) the meshes are made in parallel on up to
two processes; ``-o`` must then name each output with ``{name}`` (and may use ``{level}``). A
domain that fails is reported and does not stop the others; the exit code is then 1.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import os
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, NamedTuple, cast

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, process_rss
from blockmesh.commands._partitions import add_partition_arguments, check_partition_arguments
from blockmesh.commands._progress import StageProgress
from blockmesh.commands.common import (
    ProgressBar,
    add_domain_arguments,
    check_folders,
    check_level_options,
    fill_template,
    inline_polygon,
    levels_to_add,
    load_target,
    parse_patch_options,
    print_json,
    printable,
)
from blockmesh.commands.options import (
    add_json_option,
    add_level_option,
    add_max_memory_option,
    add_placement_options,
    add_plot_option,
)
from blockmesh.domain.domain import Domain
from blockmesh.errors import BlockMeshError, ResourceError
from blockmesh.io import SPLITS, check_options, format_for_path, write
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.improve import refine_with_rule
from blockmesh.refinement.local import SCHEMES, predict_local_size, refine_locally
from blockmesh.refinement.marking import (
    Marking,
    any_of,
    check_marks,
    in_region,
    near_patch,
    parse_near,
    where,
)
from blockmesh.refinement.pipeline import NUMBERINGS, refine
from blockmesh.refinement.sizes import check_fits, mesh_command_predictor
from blockmesh.sizing.gradation import checked_gradation
from blockmesh.sizing.measure import size_report
from blockmesh.sizing.spec import as_size_spec

#: The level meshed when none is given (as ``blockmesh integrate``).
DEFAULT_LEVEL = 2


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``mesh`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "mesh",
        help="refine domains into all-pentagon meshes; report, draw, export",
        description="Refine DOMAIN (or several) LEVEL times: every block becomes 6**LEVEL "
        "pentagons. Prints counts and quality; draws and writes the mesh on request.",
    )
    add_domain_arguments(parser, many=True)
    add_level_option(
        parser,
        f"refinement level: every block becomes 6**L pentagons (default {DEFAULT_LEVEL}; "
        "a mesh file keeps its own level, and L more levels refine it further; with --size, or "
        "a domain file with a [size] table, 0 unless given)",
    )
    parser.add_argument(
        "--size",
        "-s",
        metavar="H",
        help="cut the domain into cells of diameter H instead of refining its blocks: every "
        "cell's diameter at most 1.5 x the size asked at its centroid, with about as few cells "
        "as that allows. H is a number or an expression in x and y, the size wanted at each "
        "point ('0.02 + 0.1*sqrt(x^2 + y^2)'); a domain file's [size] table gives more (sizes "
        "per region, near patches or points). With --level L too, the size sets the blocks "
        "and the level refines them further (6**L cells each)",
    )
    parser.add_argument(
        "--uniform",
        action="store_true",
        help="corner-true: instead of refining the blocks LEVEL times (where the cells at block "
        "corners grow 1.5 times per level relative to the others), cut the domain into cells of "
        "one size, about as many as LEVEL would make",
    )
    parser.add_argument(
        "--gradation",
        type=float,
        metavar="R",
        help="with --size: the largest size ratio between neighbouring cells that the sizes "
        "asked may grow by (default 1.3)",
    )
    parser.add_argument(
        "--numbering",
        choices=NUMBERINGS,
        default="nested",
        help="node numbering: the paper's nested one (default) or reverse Cuthill-McKee",
    )
    add_placement_options(parser, "the mesh")
    parser.add_argument(
        "-o",
        "--output",
        metavar="PATH",
        help="write the mesh; the format follows the extension (.vtu .vtk .xdmf .msh .mat .npz, "
        "or a directory with --format openfoam); with several domains use {name}, e.g. "
        "'out/{name}.vtu'",
    )
    parser.add_argument(
        "--format", metavar="FORMAT", help="output format, overriding the extension"
    )
    parser.add_argument(
        "--split",
        choices=SPLITS,
        help="how .msh output splits pentagons (gmsh has no pentagons; default tri5)",
    )
    parser.add_argument(
        "--compression",
        choices=("none", "zlib", "lzma"),
        help="compression of the output, where the format has it (default none: the fastest; "
        "zlib makes a .vtu about 2.5x smaller for about 4x the time)",
    )
    local = parser.add_argument_group(
        "local refinement",
        "after the uniform LEVEL, split only some cells (their new edge nodes hang on the coarse "
        "neighbours, at most one per side; the mesh then has polygons of 5 to 11 vertices). "
        "Several options mark the union; every round asks them again on the refined mesh.",
    )
    local.add_argument(
        "--refine-where",
        action="append",
        default=[],
        metavar="EXPR",
        help="split the cells where EXPR(x, y) > 0 at the centre or a vertex, e.g. "
        "'0.2 - sqrt((x-1)^2 + (y-1)^2)' (repeatable)",
    )
    local.add_argument(
        "--refine-region",
        action="append",
        default=[],
        metavar="NAME",
        help="split the cells of region NAME (repeatable)",
    )
    local.add_argument(
        "--refine-near",
        action="append",
        default=[],
        metavar="PATCH:DISTANCE",
        help="split the cells within DISTANCE of boundary patch PATCH (repeatable)",
    )
    local.add_argument(
        "--refine-scheme",
        choices=tuple(SCHEMES),
        default="pentagons",
        help="how a marked cell is split: the paper's six pentagons (default; other polygons "
        "into corner pentagons and a central polygon), or quadrilaterals through its centre",
    )
    local.add_argument(
        "--refine-rounds",
        type=int,
        default=1,
        metavar="K",
        help="rounds of local refinement (default 1)",
    )
    add_plot_option(parser, "the mesh")
    parser.add_argument(
        "--quality-plot", metavar="PNG", help="histograms of angles and aspect ratios"
    )
    parser.add_argument(
        "--size-plot",
        metavar="PNG",
        help="draw the cell sizes: diameters, and diameter over the size asked (or over the "
        "neighbours') with the worst cells outlined",
    )
    add_max_memory_option(parser, "meshes")
    add_partition_arguments(
        parser, "make the mesh, each piece written by its worker (-o OUT.pvtu or OUT.xdmf),"
    )
    add_json_option(parser)
    parser.set_defaults(run=run)


# ---------------------------------------------------------------------------- one domain
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


def _size_value(text: str) -> float | str:
    """``--size`` as a number when it is one, else the expression text."""
    try:
        return float(text)
    except ValueError:
        return text


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


def _mesh_one(
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


def _marking(args: argparse.Namespace) -> Marking | None:
    """The union of the --refine-* options as one marking (None without them)."""
    parts: list[Marking] = [where(text) for text in args.refine_where]
    parts += [in_region(name) for name in args.refine_region]
    parts += [near_patch(*parse_near(text)) for text in args.refine_near]
    if args.refine_rounds < 1:
        raise BlockMeshError(f"--refine-rounds must be 1 or more, got {args.refine_rounds}")
    if not parts:
        if args.refine_rounds != 1:
            raise BlockMeshError(
                "--refine-rounds counts rounds of local refinement: give --refine-where, "
                "--refine-region or --refine-near too"
            )
        return None
    return parts[0] if len(parts) == 1 else any_of(*parts)


def _fill(pattern: str, mesh: Mesh | PolygonMesh) -> contextlib.AbstractContextManager[str]:
    return fill_template(pattern, name=mesh.name or "mesh", level=mesh.level)


def _options(args: argparse.Namespace) -> dict[str, Any]:
    check_level_options(args)
    if args.uniform and args.size is not None:
        raise BlockMeshError("give --uniform (one size, the count of --level) or --size, not both")
    if args.gradation is not None and args.size is None:
        raise BlockMeshError("--gradation goes with --size (how fast the sizes asked may grow)")
    size = None
    if args.size is not None:
        size = _size_value(args.size)
        as_size_spec(size, source="--size")  # a located message for a bad size, before meshing
    if args.gradation is not None:
        checked_gradation(args.gradation)
    check_folders(args.output, args.plot, args.quality_plot, args.size_plot)
    if args.output:
        # Fail before meshing: an unknown format or an option it does not take is known now.
        fmt = format_for_path(args.output, args.format)
        check_options(fmt, split=args.split, compression=args.compression)
    marking = _marking(args)
    if marking is not None and args.numbering != "nested":
        raise BlockMeshError(
            "--numbering rcm renumbers an all-pentagon mesh; local refinement keeps the nested "
            "numbering"
        )
    return {
        "marking": marking,
        "refine_rounds": args.refine_rounds,
        "refine_scheme": args.refine_scheme,
        "level": args.level,
        "size": size,
        "uniform": args.uniform,
        "gradation": args.gradation,
        "size_plot": args.size_plot,
        "numbering": args.numbering,
        "smooth": args.smooth,
        "quality_rule": args.quality_rule,
        "max_memory": args.max_memory,
        "plot": args.plot,
        "quality_plot": args.quality_plot,
        "format": args.format,
        "split": args.split,
        "compression": args.compression,
    }


def _print_report(report: dict[str, Any], done: str = "refined") -> None:
    q = report["quality"]
    print(
        f"{printable(report['domain'])}: level {report['level']}, {report['cells']:,} cells, "
        f"{report['nodes']:,} nodes, {report['edges']:,} edges "
        f"({report['boundary_edges']:,} on the boundary), area {report['area']:.12g}"
    )
    print(
        f"  angles {q['min_angle']:.2f}° .. {q['max_angle']:.2f}°, max aspect ratio "
        f"{q['max_aspect_ratio']:.3g}, area ratio {q['area_ratio']:.3g}, "
        f"not strictly convex: {q['not_strictly_convex']}"
    )
    for line in _size_lines(report):
        print(line)
    local = report.get("local_refinement")
    if local:
        counts = ", ".join(f"{m:,}" for m in local["marked"])
        print(
            f"  local refinement: {local['rounds']} round(s) marking {counts} cells "
            f"({printable(local['marking'])}); "
            f"{local['hanging_nodes']:,} hanging nodes, cells of up to {local['max_vertices']} "
            "vertices"
        )
    bandwidth = report["bandwidth"]
    line = f"  bandwidth {bandwidth['nested']:,} (nested)"
    if bandwidth["rcm"] is not None:
        line += f" -> {bandwidth['rcm']:,} (reverse Cuthill-McKee)"
    print(line + f"; {done} in {report['seconds']:.3f} s")
    for key, label in (
        ("plot", "plot"),
        ("quality_plot", "quality plot"),
        ("size_plot", "size plot"),
        ("output", "mesh"),
    ):
        if report.get(key):
            print(f"  wrote {label} {printable(report[key])}")


def _size_lines(report: dict[str, Any]) -> list[str]:
    """The size report: diameters and neighbours; size got against size asked when sized."""
    s = report.get("sizes")
    if not s:
        return []
    a, b = s["neighbour_cells"]
    lines = [
        f"  cell diameters {s['min_diameter']:.4g} .. {s['max_diameter']:.4g}; largest "
        f"neighbour size ratio {s['neighbour_ratio']:.3g} (cells {a} and {b})"
    ]
    if s["worst_ratio"] is not None:
        x, y = s["worst_point"]
        lines.append(
            f"  size got / size asked: worst {s['worst_ratio']:.3g} (cell {s['worst_cell']} near "
            f"({x:.6g}, {y:.6g})), mean {s['mean_ratio']:.3g}; {report['cells']:,} cells = "
            f"{s['count_ratio']:.3g} x the ideal {s['ideal_cells']:,.0f}"
        )
    return lines


# ---------------------------------------------------------------------------- partitioned
_NOT_PARTITIONED = {
    "size": "--size",
    "uniform": "--uniform",
    "size_plot": "--size-plot",
    "plot": "--plot",
    "quality_plot": "--quality-plot",
    "format": "--format",
    "split": "--split",
    "compression": "--compression",
}


def _partitioned_options(args: argparse.Namespace) -> None:
    if args.scheduler is not None and args.max_memory is not None:
        raise BlockMeshError(
            "--max-memory sets the local workers' memory limit; with --scheduler the workers' "
            "own limits apply"
        )
    if args.level is not None and args.level < 1:
        raise BlockMeshError(f"--partitions needs --level 1 or more, got {args.level}")
    if args.refine_where or args.refine_region or args.refine_near:
        raise BlockMeshError(
            "--partitions makes a uniform mesh; local refinement (--refine-where, "
            "--refine-region, --refine-near) runs without --partitions"
        )
    if args.numbering != "nested" or args.smooth or args.quality_rule != "paper":
        raise BlockMeshError(
            "--partitions makes the paper's mesh: nested numbering, no smoothing, the paper's "
            "quality rule"
        )
    for key, flag in _NOT_PARTITIONED.items():
        if getattr(args, key):
            raise BlockMeshError(
                f"{flag} is not available with --partitions: the workers write their pieces as "
                ".vtu (index OUT.pvtu) or .h5 (index OUT.xdmf)"
            )
    if not args.output or Path(args.output).suffix.lower() not in (".pvtu", ".xdmf"):
        raise BlockMeshError(
            "--partitions writes the mesh as pieces: give -o OUT.pvtu (ParaView's parallel VTU) "
            "or -o OUT.xdmf (an XDMF collection of HDF5 pieces)"
        )
    check_folders(args.output)


def _run_partitioned(args: argparse.Namespace) -> int:
    """``blockmesh mesh DOMAIN --partitions P [--workers N | --scheduler ADDRESS] -o OUT.pvtu``."""
    _partitioned_options(args)
    patches = parse_patch_options(args.patch)
    if args.polygon is not None:
        if args.domain:
            raise BlockMeshError("give either DOMAIN or --polygon, not both")
        target: Domain | Mesh | PolygonMesh = inline_polygon(args.polygon, args.hole, patches)
    else:
        if len(args.domain or []) != 1:
            raise BlockMeshError("--partitions meshes one domain at a time")
        target = load_target(args.domain[0], progress=StageProgress.wanted(args), patches=patches)
    from blockmesh import distributed
    from blockmesh.distributed.files import pieces_dir

    steps = levels_to_add(args.level, target, DEFAULT_LEVEL)
    if steps < 1:
        raise BlockMeshError(
            f"--partitions refines {printable(target.name or 'the mesh')} further: give --level "
            "1 or more (the levels to add to the mesh file's own)"
        )
    level = target.level + steps if isinstance(target, Mesh | PolygonMesh) else steps
    progress = StageProgress(printable(target.name), enabled=StageProgress.wanted(args))
    parts = distributed.partition(target, steps, args.partitions)  # refuses PolygonMesh
    predicted = max(distributed.predict_task_bytes(parts, p) for p in range(parts.n_partitions))
    label = f"making {args.partitions} pieces on Dask workers"
    with (
        fill_template(args.output, name=target.name or "mesh", level=level) as output,
        progress.stage(label) as tick,
    ):
        made = distributed.refine_to(
            cast(Domain | Mesh, target),  # partition() has refused a PolygonMesh
            steps,
            output,
            partitions=args.partitions,
            workers=args.workers,
            scheduler=args.scheduler,
            memory_limit=args.max_memory,
            progress=tick,
        )
    report = {
        "domain": target.name,
        "level": made.level,
        "nodes": made.nodes,
        "cells": made.cells,
        "edges": (5 * made.cells + made.boundary_edges) // 2,
        "boundary_edges": made.boundary_edges,
        "area": made.area,
        "quality": made.quality.as_dict(),
        "bandwidth": {"nested": made.bandwidth, "rcm": None},
        "numbering": "nested",
        "smooth": 0,
        "seconds": made.seconds,
        "predicted_peak_bytes": predicted,
        "plot": None,
        "quality_plot": None,
        "output": str(made.path),
        "partitions": len(made.pieces),
        "pieces": [str(p) for p in made.pieces],
        "workers": made.workers,
        "bytes_written": made.bytes_written,
        "array_bytes": made.array_bytes,
        "worker_peak_bytes": made.worker_peak_bytes,
    }
    if args.json:
        print_json(report)
        return 0
    _print_report({**report, "output": None}, done="made and written by the workers")
    print(
        f"  wrote {printable(output)} and {report['partitions']} pieces in "
        f"{printable(str(pieces_dir(Path(output))))} ({format_bytes(made.bytes_written)}; arrays "
        f"{format_bytes(made.array_bytes)}) on {made.workers} workers; largest worker peak "
        f"{format_bytes(made.worker_peak_bytes)} (predicted {format_bytes(predicted)})"
    )
    return 0


# ---------------------------------------------------------------------------- many domains
def _expand(names: list[str]) -> list[str]:
    expanded = []
    for name in names:
        if any(c in name for c in "*?["):
            matches = sorted(glob.glob(name))
            if not matches:
                raise BlockMeshError(f"no file matches {name!r}")
            expanded += matches
        else:
            expanded.append(name)
    return expanded


def _batch_worker(name: str, options: dict[str, Any], output: str | None) -> dict[str, Any]:
    try:
        target = load_target(name, max_memory=options["max_memory"])
        return {"ok": True, **_mesh_one(target, options, output)}
    except BlockMeshError as error:
        return {"ok": False, "domain": name, "error": str(error)}


def _run_batch(names: list[str], options: dict[str, Any], args: argparse.Namespace) -> int:
    output = args.output
    for key in ("output", "plot", "quality_plot", "size_plot"):
        value = getattr(args, key)
        if value and "{name}" not in value:
            raise BlockMeshError(
                f"with several domains, --{key.replace('_', '-')} must contain {{name}} so that "
                f"each domain gets its own file, e.g. 'out/{{name}}.vtu'"
            )
    bar = ProgressBar(f"meshing {len(names)} domains", enabled=ProgressBar.wanted(args))
    results: list[dict[str, Any]] = []
    from concurrent.futures import ProcessPoolExecutor, as_completed

    workers = min(2, len(names), os.cpu_count() or 1)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(_batch_worker, name, options, output): name for name in names}
        for done, future in enumerate(as_completed(futures), start=1):
            results.append(future.result())
            bar(done, len(names))
    order = {name: k for k, name in enumerate(names)}
    results.sort(key=lambda r: order.get(r["domain"], len(names)))
    failures = [r for r in results if not r["ok"]]
    if args.json:
        print_json({"domains": results, "failed": len(failures)})
    else:
        print(
            f"{'domain':<16} {'cells':>12} {'nodes':>12} {'min°':>7} {'max°':>7} {'s':>7}  output"
        )
        for r in results:
            if r["ok"]:
                q = r["quality"]
                written = [r[k] for k in ("output", "plot", "quality_plot", "size_plot") if r[k]]
                print(
                    f"{printable(r['domain']):<16} {r['cells']:>12,} {r['nodes']:>12,} "
                    f"{q['min_angle']:>7.2f} {q['max_angle']:>7.2f} {r['seconds']:>7.3f}  "
                    f"{printable(', '.join(written)) or '-'}"
                )
            else:
                print(f"{printable(r['domain']):<16} FAILED: {printable(r['error'])}")
        print(f"{len(results) - len(failures)} of {len(results)} domains meshed")
    for r in failures:
        print(
            f"blockmesh mesh: {printable(r['domain'])}: error: {printable(r['error'])}",
            file=sys.stderr,
        )
    return 1 if failures else 0


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh mesh`` with the parsed ``args``; returns the exit code."""
    check_level_options(args)
    if check_partition_arguments(args):
        return _run_partitioned(args)
    options = _options(args)
    if args.polygon is not None:
        if args.domain:
            raise BlockMeshError("give either DOMAIN or --polygon, not both")
        domains: list[str] = []
    else:
        if not args.domain:
            raise BlockMeshError(
                'no domain: give catalogue names or .toml files, or --polygon "x1,y1 x2,y2 ..."'
            )
        domains = _expand(args.domain)
    patches = parse_patch_options(args.patch)
    if len(domains) > 1:
        if patches:
            raise BlockMeshError("--patch names the edges of one outline; mesh one domain")
        return _run_batch(domains, options, args)
    if args.hole and args.polygon is None:
        raise BlockMeshError(
            '--hole adds a hole to --polygon "x1,y1 x2,y2 ..."; give --polygon too'
        )
    target = (
        inline_polygon(args.polygon, args.hole, patches)
        if args.polygon is not None
        else load_target(
            domains[0],
            progress=StageProgress.wanted(args),
            patches=patches,
            max_memory=options["max_memory"],
        )
    )
    progress = StageProgress(printable(target.name), enabled=StageProgress.wanted(args))
    report = _mesh_one(target, options, args.output, progress=progress)
    if args.json:
        print_json(report)
    else:
        _print_report(report)
    return 0
