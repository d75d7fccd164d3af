"""``blockmesh convert``: an existing triangle/quadrilateral mesh to a pentagonal block domain."""

from __future__ import annotations

import argparse
from collections import Counter
from pathlib import Path

import numpy as np

from blockmesh.commands import Option, Options, registration
from blockmesh.commands.common import check_folders, check_level_options, print_json, printable
from blockmesh.commands.options import JSON_OPTION, level_option
from blockmesh.domain.domain import Domain
from blockmesh.errors import ArgumentError
from blockmesh.io import SPLITS, write

#: The options of ``blockmesh convert``, in the order of its ``--help``.
OPTIONS: Options = (
    Option("input", metavar="IN", help="the mesh file to convert"),
    Option(
        "-o",
        "--output",
        required=True,
        metavar="OUT",
        help="a .toml domain file, or a mesh file in any format 'blockmesh mesh' writes",
    ),
    level_option("refinement levels for a mesh output (default 0: the blocks themselves)", 0),
    Option("--format", metavar="FORMAT", help="output format, overriding the extension"),
    Option(
        "--split", choices=SPLITS, help="how .msh output splits pentagons (gmsh has no pentagons)"
    ),
    Option("--name", help="the domain's name (default: the input file's stem)"),
    JSON_OPTION,
)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh convert`` with the parsed ``args``; returns the exit code."""
    check_level_options(args)
    check_folders(args.output)
    domain = Domain.from_mesh(args.input, name=args.name)
    output = Path(args.output)
    if output.suffix.lower() == ".toml" and args.format is None:
        if args.level:
            raise ArgumentError(
                "a .toml output holds the blocks themselves; --level applies to mesh outputs"
            )
        written = domain.write_toml(output)
        cells = domain.n_blocks
    else:
        mesh = domain.mesh(args.level)
        written = write(mesh, output, format=args.format, split=args.split)
        cells = mesh.n_cells
    sources = Counter(np.bincount(domain.block_source).tolist()) if domain.n_blocks else {}
    report = {
        "input": args.input,
        "output": str(written),
        "domain": domain.name,
        "layout": domain.layout,
        "elements": int(domain.block_source.max()) + 1 if domain.n_blocks else 0,
        "blocks": domain.n_blocks,
        "blocks_per_element": {str(k): v for k, v in sorted(sources.items())},
        "patches": {
            name: int(np.count_nonzero(domain.boundary_patch == k))
            for k, name in enumerate(domain.patch_names)
        },
        "regions": {name: int(ids.size) for name, ids in domain.regions.items()},
        "level": args.level,
        "cells": cells,
        "min_angle": float(domain.block_angles().min()),
        "max_angle": float(domain.block_angles().max()),
    }
    if args.json:
        print_json(report)
        return 0
    per = ", ".join(f"{count} with {k} blocks" for k, count in report["blocks_per_element"].items())
    print(
        f"converted {printable(args.input)}: {report['elements']} elements ({per}) -> "
        f"{domain.n_blocks} pentagonal blocks ({domain.layout}), angles "
        f"{report['min_angle']:.2f}° .. {report['max_angle']:.2f}°"
    )
    for name, count in report["patches"].items():
        print(f"  patch {printable(name)}: {count} edges")
    for name, count in report["regions"].items():
        print(f"  region {printable(name)}: {count} blocks")
    print(f"wrote {printable(str(written))} (level {args.level}, {cells:,} cells)")
    return 0


register = registration("convert", OPTIONS, run)
