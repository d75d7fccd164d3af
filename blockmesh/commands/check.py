"""``blockmesh check``: validate a domain and print its conformity certificate."""

from __future__ import annotations

import argparse
import sys
import warnings

from ..blockgraph import certificate
from ..errors import BlockMeshError
from ._common import add_domain_arguments, print_json, resolve_domain


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
            domain = resolve_domain(args)
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
                print(f"blockmesh check: {name} is not valid: {error}", file=sys.stderr)
            return 1
    report = certificate(domain)
    report["warnings"] = [str(w.message) for w in caught]
    if args.json:
        print_json(report)
        return 0
    _print_certificate(report)
    return 0


def _print_certificate(c: dict) -> None:
    print(f"domain {c['domain']}: valid ({c['layout']})")
    print(f"  blocks {c['blocks']}, vertices {c['vertices']}, area {c['area']:.12g}")
    print(f"  shared edges {c['shared_edges']}, boundary edges {c['boundary_edges']}")
    for patch, count in c["patches"].items():
        print(f"    patch {patch}: {count} edge{'s' if count != 1 else ''}")
    for region, blocks in c["regions"].items():
        print(f"    region {region}: blocks {', '.join(map(str, blocks))}")
    print(
        f"  Euler characteristic {c['euler_characteristic']} "
        f"({c['connected_components']} piece, {c['holes']} hole{'s' if c['holes'] != 1 else ''})"
    )
    ccw = sum(b["counter_clockwise"] for b in c["block_details"])
    convex = sum(b["strictly_convex"] for b in c["block_details"])
    print(f"  counter-clockwise blocks {ccw}/{c['blocks']}, strictly convex {convex}/{c['blocks']}")
    print(f"  angles {c['min_angle']:.2f}° .. {c['max_angle']:.2f}°")
    print("  block  vertices                   area         min°     max°")
    for b in c["block_details"]:
        vertices = " ".join(f"{v:>4}" for v in b["vertices"])
        print(
            f"  {b['block']:>5}  {vertices}  {b['area']:>11.6g}  {b['min_angle']:7.2f}  "
            f"{b['max_angle']:7.2f}"
        )
    for message in c["warnings"]:
        print(f"  warning: {message}")
