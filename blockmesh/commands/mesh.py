"""``blockmesh mesh``: refine one or many domains, report quality, draw and export.

With several domains (catalogue names, files or globs) the meshes are made in parallel on up to
two processes; ``-o`` must then name each output with ``{name}`` (and may use ``{level}``). A
domain that fails is reported and does not stop the others; the exit code is then 1.
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any

from ..domain import Domain
from ..errors import BlockMeshError
from ..io import SPLITS, format_for_path
from ..mesh import Mesh
from ..refinement import NUMBERINGS, refine
from ._common import (
    ProgressBar,
    add_domain_arguments,
    check_folders,
    fill_template,
    inline_polygon,
    load_target,
    parse_size,
    print_json,
    printable,
)

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
    parser.add_argument(
        "--level",
        "-l",
        type=int,
        default=DEFAULT_LEVEL,
        metavar="L",
        help=f"refinement level: every block becomes 6**L pentagons (default {DEFAULT_LEVEL})",
    )
    parser.add_argument(
        "--numbering",
        choices=NUMBERINGS,
        default="nested",
        help="node numbering: the paper's nested one (default) or reverse Cuthill-McKee",
    )
    parser.add_argument(
        "--smooth", type=int, default=0, metavar="K", help="Laplacian sweeps per level (default 0)"
    )
    parser.add_argument(
        "-o",
        "--output",
        metavar="PATH",
        help="write the mesh; the format follows the extension (.vtu .xdmf .msh .mat .npz, or a "
        "directory with --format openfoam); with several domains use {name}, e.g. 'out/{name}.vtu'",
    )
    parser.add_argument(
        "--format", metavar="FORMAT", help="output format, overriding the extension"
    )
    parser.add_argument(
        "--split", choices=SPLITS, help="how .msh output splits pentagons (gmsh has no pentagons)"
    )
    parser.add_argument(
        "--compression",
        choices=("none", "zlib", "lzma"),
        help="compression of the output, where the format has it (default: zlib for .vtu, none "
        "otherwise)",
    )
    parser.add_argument("--plot", metavar="PNG", help="draw the mesh")
    parser.add_argument(
        "--quality-plot", metavar="PNG", help="histograms of angles and aspect ratios"
    )
    parser.add_argument(
        "--max-memory",
        type=parse_size,
        metavar="SIZE",
        help="refuse meshes predicted to need more memory (e.g. 4G; default: what is available)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run)


# ---------------------------------------------------------------------------- one domain
def _mesh_one(
    target: Domain | Mesh, options: dict[str, Any], output: str | None, progress=None
) -> dict[str, Any]:
    """Mesh, draw and write one domain (or refine a mesh further); the JSON-ready report."""
    started = time.perf_counter()
    mesh = refine(
        target,
        options["level"],
        smooth=options["smooth"],
        max_memory=options["max_memory"],
        progress=progress,
    )
    seconds = time.perf_counter() - started
    bandwidth: dict[str, int | None] = {"nested": mesh.bandwidth(), "rcm": None}
    if options["numbering"] == "rcm":
        mesh = mesh.with_rcm_numbering()
        bandwidth["rcm"] = mesh.bandwidth()
    quality = mesh.quality()
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
        "bandwidth": bandwidth,
        "numbering": options["numbering"],
        "smooth": options["smooth"],
        "seconds": seconds,
        "plot": None,
        "quality_plot": None,
        "output": None,
    }
    if options["plot"]:
        from ..plot import plot_mesh

        report["plot"] = str(plot_mesh(mesh, _fill(options["plot"], mesh)))
    if options["quality_plot"]:
        from ..plot import plot_quality

        report["quality_plot"] = str(plot_quality(mesh, _fill(options["quality_plot"], mesh)))
    if output:
        from ..io import write

        report["output"] = str(
            write(
                mesh,
                _fill(output, mesh),
                format=options["format"],
                split=options["split"],
                compression=options["compression"],
            )
        )
    return report


def _fill(pattern: str, mesh: Mesh) -> str:
    return fill_template(pattern, name=mesh.name or "mesh", level=mesh.level)


def _options(args: argparse.Namespace) -> dict[str, Any]:
    if args.level < 0:
        raise BlockMeshError(f"--level must be 0 or more, got {args.level}")
    if args.smooth < 0:
        raise BlockMeshError(f"--smooth must be 0 or more, got {args.smooth}")
    check_folders(args.output, args.plot, args.quality_plot)
    if args.output:
        # Fail before meshing: an unknown format or a missing --split is known now.
        fmt = format_for_path(args.output, args.format)
        if fmt.needs_split and args.split is None:
            raise BlockMeshError(
                f"{args.output}: gmsh .msh has no pentagons; choose --split tri5, tri3 or quad5"
            )
    return {
        "level": args.level,
        "numbering": args.numbering,
        "smooth": args.smooth,
        "max_memory": args.max_memory,
        "plot": args.plot,
        "quality_plot": args.quality_plot,
        "format": args.format,
        "split": args.split,
        "compression": args.compression,
    }


def _print_report(report: dict[str, Any]) -> None:
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
    bandwidth = report["bandwidth"]
    line = f"  bandwidth {bandwidth['nested']:,} (nested)"
    if bandwidth["rcm"] is not None:
        line += f" -> {bandwidth['rcm']:,} (reverse Cuthill-McKee)"
    print(line + f"; refined in {report['seconds']:.3f} s")
    for key, label in (("plot", "plot"), ("quality_plot", "quality plot"), ("output", "mesh")):
        if report[key]:
            print(f"  wrote {label} {report[key]}")


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
        return {"ok": True, **_mesh_one(load_target(name), options, output)}
    except BlockMeshError as error:
        return {"ok": False, "domain": name, "error": str(error)}


def _run_batch(names: list[str], options: dict[str, Any], args: argparse.Namespace) -> int:
    output = args.output
    for key in ("output", "plot", "quality_plot"):
        value = getattr(args, key)
        if value and "{name}" not in value:
            raise BlockMeshError(
                f"with several domains, --{key.replace('_', '-')} must contain {{name}} so that "
                f"each domain gets its own file, e.g. 'out/{{name}}.vtu'"
            )
    bar = ProgressBar(f"meshing {len(names)} domains", enabled=ProgressBar.wanted(args))
    results: list[dict[str, Any]] = []
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
                written = [r[k] for k in ("output", "plot", "quality_plot") if r[k]]
                print(
                    f"{printable(r['domain']):<16} {r['cells']:>12,} {r['nodes']:>12,} "
                    f"{q['min_angle']:>7.2f} {q['max_angle']:>7.2f} {r['seconds']:>7.3f}  "
                    f"{', '.join(written) or '-'}"
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
    if len(domains) > 1:
        return _run_batch(domains, options, args)
    target = inline_polygon(args.polygon) if args.polygon is not None else load_target(domains[0])
    bar = ProgressBar(f"{printable(target.name)}: refining", enabled=ProgressBar.wanted(args))
    report = _mesh_one(target, options, args.output, progress=bar)
    if args.json:
        print_json(report)
    else:
        _print_report(report)
    return 0
