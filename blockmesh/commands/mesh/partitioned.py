"""``blockmesh mesh --partitions P``: one domain made and written piece by piece on Dask workers."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import cast

from blockmesh._system.memory import format_bytes
from blockmesh.commands._partitions import partition_keywords
from blockmesh.commands._progress import StageProgress
from blockmesh.commands.common import (
    check_folders,
    fill_template,
    inline_polygon,
    levels_to_add,
    load_target,
    parse_patch_options,
    print_json,
    printable,
)
from blockmesh.commands.mesh.arguments import DEFAULT_LEVEL
from blockmesh.commands.mesh.report import print_report
from blockmesh.domain.domain import Domain
from blockmesh.errors import BlockMeshError
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

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


def run_partitioned(args: argparse.Namespace) -> int:
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
            memory_limit=args.max_memory,
            progress=tick,
            **partition_keywords(args),
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
    print_report({**report, "output": None}, done="made and written by the workers")
    print(
        f"  wrote {printable(output)} and {report['partitions']} pieces in "
        f"{printable(str(pieces_dir(Path(output))))} ({format_bytes(made.bytes_written)}; arrays "
        f"{format_bytes(made.array_bytes)}) on {made.workers} workers; largest worker peak "
        f"{format_bytes(made.worker_peak_bytes)} (predicted {format_bytes(predicted)})"
    )
    return 0
