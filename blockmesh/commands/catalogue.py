"""``blockmesh catalogue``: list the ready-made domains."""

from __future__ import annotations

import argparse
from typing import Any

from blockmesh.commands import Options, registration
from blockmesh.commands.common import print_json
from blockmesh.commands.options import JSON_OPTION
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.domain.loading import load_domain

#: The options of ``blockmesh catalogue``, in the order of its ``--help``.
OPTIONS: Options = (JSON_OPTION,)


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
    # Columns as wide as their longest entry, so that long names do not push the others.
    patches = [", ".join(row["patches"]) for row in rows]
    name_width = max([len("name"), *(len(row["name"]) for row in rows)])
    patch_width = max([len("patches"), *(len(p) for p in patches)])
    name, patches_title = "name", "patches"
    print(
        f"{name:<{name_width}} {'blocks':>6} {'area':>10}  {patches_title:<{patch_width}}  "
        "description"
    )
    for row, listed in zip(rows, patches, strict=True):
        print(
            f"{row['name']:<{name_width}} {row['blocks']:>6} {row['area']:>10.6g}  "
            f"{listed:<{patch_width}}  {row['description']}"
        )
    return 0


register = registration("catalogue", OPTIONS, run)
