"""``blockmesh mesh``: its options, and the run that sends the arguments on.

One domain goes to :mod:`~blockmesh.commands.mesh.single`, several to
:mod:`~blockmesh.commands.mesh.batch`, ``--partitions`` to
:mod:`~blockmesh.commands.mesh.partitioned`.
"""

from __future__ import annotations

import argparse

from blockmesh.commands import Group, Option, Options, registration
from blockmesh.commands._partitions import check_partition_arguments, partition_options
from blockmesh.commands._progress import StageProgress
from blockmesh.commands.common import (
    check_level_options,
    domain_arguments,
    inline_polygon,
    load_target,
    parse_patch_options,
    print_json,
    printable,
)
from blockmesh.commands.mesh.arguments import DEFAULT_LEVEL, mesh_options
from blockmesh.commands.mesh.batch import expand_globs, run_batch
from blockmesh.commands.mesh.partitioned import run_partitioned
from blockmesh.commands.mesh.report import print_report
from blockmesh.commands.mesh.single import mesh_one
from blockmesh.commands.options import (
    JSON_OPTION,
    level_option,
    max_memory_option,
    placement_options,
    plot_option,
    scheme_option,
)
from blockmesh.errors import BlockMeshError
from blockmesh.io import SPLITS
from blockmesh.refinement.pipeline import NUMBERINGS

#: The options of ``blockmesh mesh``, in the order of its ``--help``.
OPTIONS: Options = (
    *domain_arguments(many=True),
    level_option(
        f"refinement level: every block becomes 6**L pentagons (default {DEFAULT_LEVEL}; "
        "a mesh file keeps its own level, and L more levels refine it further; with --size, or "
        "a domain file with a [size] table, 0 unless given)",
    ),
    Option(
        "--size",
        "-s",
        metavar="H",
        help="cut the domain into cells of diameter H instead of refining its blocks: every "
        "cell's diameter at most 1.5 x the size asked at its centroid, with about as few cells "
        "as that allows. H is a number or an expression in x and y, the size wanted at each "
        "point ('0.02 + 0.1*sqrt(x^2 + y^2)'); a domain file's [size] table gives more (sizes "
        "per region, near patches or points). With --level L too, the size sets the blocks "
        "and the level refines them further (6**L cells each)",
    ),
    Option(
        "--uniform",
        action="store_true",
        help="corner-true: instead of refining the blocks LEVEL times (where the cells at block "
        "corners grow 1.5 times per level relative to the others), cut the domain into cells of "
        "one size, about as many as LEVEL would make",
    ),
    Option(
        "--gradation",
        type=float,
        metavar="R",
        help="with --size: the largest size ratio between neighbouring cells that the sizes "
        "asked may grow by (default 1.3)",
    ),
    Option(
        "--numbering",
        choices=NUMBERINGS,
        default="nested",
        help="node numbering: the paper's nested one (default) or reverse Cuthill-McKee",
    ),
    *placement_options("the mesh"),
    Option(
        "-o",
        "--output",
        metavar="PATH",
        help="write the mesh; the format follows the extension (.vtu .vtk .xdmf .msh .mat .npz, "
        "or a directory with --format openfoam); with several domains use {name}, e.g. "
        "'out/{name}.vtu'",
    ),
    Option("--format", metavar="FORMAT", help="output format, overriding the extension"),
    Option(
        "--split",
        choices=SPLITS,
        help="how .msh output splits pentagons (gmsh has no pentagons; default tri5)",
    ),
    Option(
        "--compression",
        choices=("none", "zlib", "lzma"),
        help="compression of the output, where the format has it (default none: the fastest; "
        "zlib makes a .vtu about 2.5x smaller for about 4x the time)",
    ),
    Group(
        "local refinement",
        "after the uniform LEVEL, split only some cells (their new edge nodes hang on the coarse "
        "neighbours, at most one per side; the mesh then has polygons of 5 to 11 vertices). "
        "Several options mark the union; every round asks them again on the refined mesh.",
        Option(
            "--refine-where",
            action="append",
            default=[],
            metavar="EXPR",
            help="split the cells where EXPR(x, y) > 0 at the centre or a vertex, e.g. "
            "'0.2 - sqrt((x-1)^2 + (y-1)^2)' (repeatable)",
        ),
        Option(
            "--refine-region",
            action="append",
            default=[],
            metavar="NAME",
            help="split the cells of region NAME (repeatable)",
        ),
        Option(
            "--refine-near",
            action="append",
            default=[],
            metavar="PATCH:DISTANCE",
            help="split the cells within DISTANCE of boundary patch PATCH (repeatable)",
        ),
        scheme_option("--refine-scheme"),
        Option(
            "--refine-rounds",
            type=int,
            default=1,
            metavar="K",
            help="rounds of local refinement (default 1)",
        ),
    ),
    plot_option("the mesh"),
    Option("--quality-plot", metavar="PNG", help="histograms of angles and aspect ratios"),
    Option(
        "--size-plot",
        metavar="PNG",
        help="draw the cell sizes: diameters, and diameter over the size asked (or over the "
        "neighbours') with the worst cells outlined",
    ),
    max_memory_option("meshes"),
    *partition_options(
        "make the mesh, each piece written by its worker (-o OUT.pvtu or OUT.xdmf),"
    ),
    JSON_OPTION,
)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh mesh`` with the parsed ``args``; returns the exit code."""
    check_level_options(args)
    if check_partition_arguments(args):
        return run_partitioned(args)
    options = mesh_options(args)
    if args.polygon is not None:
        if args.domain:
            raise BlockMeshError("give either DOMAIN or --polygon, not both")
        domains: list[str] = []
    else:
        if not args.domain:
            raise BlockMeshError(
                'no domain: give catalogue names or .toml files, or --polygon "x1,y1 x2,y2 ..."'
            )
        domains = expand_globs(args.domain)
    patches = parse_patch_options(args.patch)
    if len(domains) > 1:
        if patches:
            raise BlockMeshError("--patch names the edges of one outline; mesh one domain")
        return run_batch(domains, options, args)
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
    report = mesh_one(target, options, args.output, progress=progress)
    if args.json:
        print_json(report)
    else:
        print_report(report)
    return 0


register = registration("mesh", OPTIONS, run)
