"""``blockmesh catalogue``: list the ready-made domains."""

from __future__ import annotations

import argparse
from typing import Any

from blockmesh.commands.common import print_json
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.domain.loading import load_domain


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``catalogue`` subcommand and its options to ``subparsers``."""
    parser = subparsers.add_parser(
        "catalogue",
        help="list the catalogue of ready-made domains",
        description="List the catalogue domains: name, blocks, area, patches, description.",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh catalogue`` with the parsed ``args``; returns the exit code."""
    rows: list[dict[str, Any]] = []
    for name in catalogue_names():
        domain = load_domain(name)
        rows.append(
            {
                "name": name,
                "blocks": domain.n_blocks,
                "area": domain.area,
                "patches": list(domain.patch_names),
                "regions": list(domain.region_names),
                "layout": domain.layout,
                "description": domain.description,
            }
        )
    if args.json:
        print_json({"domains": rows})
        return 0
    print(f"{'name':<12} {'blocks':>6} {'area':>10}  {'patches':<26} description")
    for row in rows:
        patches = ", ".join(row["patches"])
        print(
            f"{row['name']:<12} {row['blocks']:>6} {row['area']:>10.6g}  {patches:<26} "
            f"{row['description']}"
        )
    return 0
