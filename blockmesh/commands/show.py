"""``blockmesh show``: a picture of a domain's blocks, vertices and patches."""

from __future__ import annotations

import argparse

from blockmesh.commands import Option, Options, registration
from blockmesh.commands.common import (
    domain_arguments,
    plural,
    printable,
    resolve_target,
    safe_component,
)
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.plot import LABEL_LIMIT, LABELS, plot_domain, plot_mesh

#: The options of ``blockmesh show``, in the order of its ``--help``.
OPTIONS: Options = (
    *domain_arguments(),
    Option("-o", "--output", metavar="FILE.png", help="picture file (default: NAME.png, here)"),
    Option(
        "--labels",
        choices=LABELS,
        default="auto",
        help="number the blocks: auto (default) where the number fits inside its block, so that "
        "none overlap; all; or none (a mesh file: its cells and nodes, auto up to "
        f"{LABEL_LIMIT} cells)",
    ),
)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh show`` with the parsed ``args``; returns the exit code."""
    target = resolve_target(args)
    output = args.output or f"{safe_component(target.name or 'mesh')}.png"
    if isinstance(target, Mesh | PolygonMesh):
        labels = {"auto": None, "all": True, "none": False}[args.labels]
        path = plot_mesh(target, output, labels=labels)
        what = f"level {target.level}, {plural(target.n_cells, 'cell')}"
    else:
        path = plot_domain(target, output, labels=args.labels)
        what = plural(target.n_blocks, "block")
    print(f"wrote {printable(str(path))} ({printable(target.name)}: {what})")
    return 0


register = registration("show", OPTIONS, run)
