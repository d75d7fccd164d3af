"""``blockmesh check``: validate a domain and print its conformity certificate."""

from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

from ..blockgraph import certificate
from ..domain import Domain
from ..errors import BlockMeshError
from ..mesh import Mesh
from ._common import add_domain_arguments, print_json, printable, resolve_target


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``check`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "check",
        help="validate a domain and print its conformity certificate",
        description="Validate a domain (catalogue name, .toml file or --polygon). Prints the "
        "certificate (blocks, shared edges, boundary edges per patch, Euler characteristic, "
        "orientation, strict convexity and angles of every block) and exits 0 when valid; "
        "prints the located errors and exits 1 otherwise.",
    )
    add_domain_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh check`` with the parsed ``args``; returns the exit code."""
    name = args.domain or "polygon"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            target = resolve_target(args)
            domain = target if isinstance(target, Domain) else domain_of_mesh(target)
        except BlockMeshError as error:
            problems = str(error).splitlines()
            if args.json:
                print_json(
                    {
                        "domain": name,
                        "valid": False,
                        "error": type(error).__name__,
                        "problems": [p.strip() for p in problems if p.strip()],
                    }
                )
            else:
                shown = printable(str(name))
                reason = printable(str(error), keep="\n")  # several problems: one per line
                print(f"blockmesh check: {shown} is not valid: {reason}", file=sys.stderr)
            return 1
    report = certificate(domain)
    report["warnings"] = [str(w.message) for w in caught]
    if args.json:
        print_json(report)
        return 0
    _print_certificate(report)
    if domain.curves:
        print(_curves_line(domain))
    return 0


def _curves_line(domain: Domain) -> str:
    """What the curve checks established, for the text certificate."""
    from collections import Counter

    from ..curve_checks import CHECK_LEVELS

    kinds = Counter(curve.kind for curve in domain.curves.values())
    listed = ", ".join(f"{n} {kind}{'s' if n != 1 else ''}" for kind, n in kinds.items())
    return (
        f"  curved edges {len(domain.curves)} ({listed}): the blocks stay strictly convex with "
        f"them, refined to level {CHECK_LEVELS}"
    )


#: Blocks listed one per line in the text certificate (all of them are in the JSON).
_LISTED = 40


def domain_of_mesh(mesh: Mesh) -> Domain:
    """A mesh's cells as the blocks of a Domain, checked like any domain (patches, regions kept)."""
    patches = {
        name: mesh.patch_edges(name).tolist()
        for name in mesh.patch_names
        if np.any(mesh.boundary_patch == mesh.patch_names.index(name))
    }
    regions = {
        name: np.flatnonzero(mesh.region == k).tolist()
        for k, name in enumerate(mesh.region_names)
        if np.any(mesh.region == k)
    }
    return Domain.from_blocks(
        mesh.points,
        mesh.cells,
        patches,
        regions,
        name=mesh.name or "mesh",
        description=f"a level-{mesh.level} mesh read from a file",
        layout=f"mesh, level {mesh.level}",
    )


def _print_certificate(c: dict) -> None:
    print(f"domain {printable(c['domain'])}: valid ({c['layout']})")
    print(f"  blocks {c['blocks']}, vertices {c['vertices']}, area {c['area']:.12g}")
    print(f"  shared edges {c['shared_edges']}, boundary edges {c['boundary_edges']}")
    for patch, count in c["patches"].items():
        print(f"    patch {printable(patch)}: {count} edge{'s' if count != 1 else ''}")
    for region, blocks in c["regions"].items():
        listed = ", ".join(map(str, blocks[:_LISTED]))
        more = f" ... ({len(blocks):,} in all)" if len(blocks) > _LISTED else ""
        print(f"    region {printable(region)}: blocks {listed}{more}")
    print(
        f"  Euler characteristic {c['euler_characteristic']} "
        f"({c['connected_components']} piece, {c['holes']} hole{'s' if c['holes'] != 1 else ''})"
    )
    ccw = sum(b["counter_clockwise"] for b in c["block_details"])
    convex = sum(b["strictly_convex"] for b in c["block_details"])
    print(f"  counter-clockwise blocks {ccw}/{c['blocks']}, strictly convex {convex}/{c['blocks']}")
    print(f"  angles {c['min_angle']:.2f}° .. {c['max_angle']:.2f}°")
    print("  block  vertices                   area         min°     max°")
    for b in c["block_details"][:_LISTED]:
        vertices = " ".join(f"{v:>4}" for v in b["vertices"])
        print(
            f"  {b['block']:>5}  {vertices}  {b['area']:>11.6g}  {b['min_angle']:7.2f}  "
            f"{b['max_angle']:7.2f}"
        )
    if c["blocks"] > _LISTED:
        print(f"  ... and {c['blocks'] - _LISTED:,} more blocks (all of them with --json)")
    for message in c["warnings"]:
        print(f"  warning: {printable(message)}")
