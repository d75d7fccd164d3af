"""``blockmesh check``: validate a domain and print its conformity certificate."""

from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

from blockmesh.commands import Options, registration
from blockmesh.commands.common import (
    domain_arguments,
    json_error,
    print_json,
    printable,
    resolve_target,
)
from blockmesh.commands.options import JSON_OPTION
from blockmesh.domain.blockgraph import certificate
from blockmesh.domain.curve_checks import CHECK_LEVELS
from blockmesh.domain.domain import Domain
from blockmesh.errors import BlockMeshError
from blockmesh.geometry.topology import cell_neighbours, connected_pieces, graph_components
from blockmesh.mesh.labels import interface_summary
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

#: The options of ``blockmesh check``, in the order of its ``--help``.
OPTIONS: Options = (*domain_arguments(), JSON_OPTION)


def run(args: argparse.Namespace) -> int:
    """Run ``blockmesh check`` with the parsed ``args``; returns the exit code."""
    name = args.domain or "polygon"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            target = resolve_target(args)
            if isinstance(target, PolygonMesh):
                target.check_geometry()
                return _report_polygons(target, args, [str(w.message) for w in caught])
            domain = target if isinstance(target, Domain) else domain_of_mesh(target)
        except BlockMeshError as error:
            problems = str(error).splitlines()
            if args.json:
                print_json(
                    {
                        "domain": name,
                        "valid": False,
                        **json_error(type(error).__name__, str(error), 1),
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


register = registration("check", OPTIONS, run)


def polygon_report(mesh: PolygonMesh) -> dict:
    """What ``blockmesh check`` establishes about a polygon mesh (JSON-ready)."""
    sizes = mesh.cell_sizes()
    quality = mesh.quality()
    edges = mesh.edges()
    loops = graph_components(mesh.n_points, mesh.boundary_edges[:, 0], mesh.boundary_edges[:, 1])
    on_boundary = np.unique(mesh.boundary_edges)
    pieces = int(np.unique(loops[1][on_boundary]).size) if on_boundary.size else 0
    euler = mesh.n_points - int(edges.shape[0]) + mesh.n_cells
    return {
        "domain": mesh.name or "mesh",
        "valid": True,
        "kind": "polygons",
        "level": mesh.level,
        "cells": mesh.n_cells,
        "nodes": mesh.n_points,
        "edges": int(edges.shape[0]),
        "boundary_edges": int(mesh.boundary_edges.shape[0]),
        "area": mesh.area,
        "cells_by_vertices": {int(k): int(v) for k, v in enumerate(np.bincount(sizes)) if v},
        "hanging_nodes": int(mesh.hanging_nodes().size),
        "most_hanging_nodes_per_side": int(mesh.side_lengths().max()) - 1,
        "euler_characteristic": euler,
        "boundary_loops": pieces,
        "patches": {
            name: int(np.count_nonzero(mesh.boundary_patch == k))
            for k, name in enumerate(mesh.patch_names)
        },
        "regions": {
            name: int(np.count_nonzero(mesh.region == k))
            for k, name in enumerate(mesh.region_names)
        },
        "interfaces": interface_summary(mesh),
        "convex_counter_clockwise": mesh.n_cells - quality.not_strictly_convex,
        "min_angle": quality.min_angle,
        "max_angle": quality.max_angle,
        "max_aspect_ratio": quality.max_aspect_ratio,
    }


def _report_polygons(mesh: PolygonMesh, args: argparse.Namespace, caught: list[str]) -> int:
    report = polygon_report(mesh)
    report["warnings"] = caught
    if args.json:
        print_json(report)
        return 0
    r = report
    sizes = ", ".join(f"{v:,} with {k}" for k, v in r["cells_by_vertices"].items())
    print(f"mesh {printable(r['domain'])}: valid (polygon cells, level {r['level']})")
    print(f"  cells {r['cells']:,} ({sizes} vertices), nodes {r['nodes']:,}, area {r['area']:.12g}")
    print(
        f"  edges {r['edges']:,}, boundary edges {r['boundary_edges']:,}; Euler characteristic "
        f"{r['euler_characteristic']}"
    )
    print(
        f"  hanging nodes {r['hanging_nodes']:,} (at most {r['most_hanging_nodes_per_side']} "
        "per side)"
    )
    for patch, count in r["patches"].items():
        print(f"    patch {printable(patch)}: {count:,} edges")
    for region, count in r["regions"].items():
        print(f"    region {printable(region)}: {count:,} cells")
    _print_interfaces(r["interfaces"])
    print(
        f"  convex and counter-clockwise cells {r['convex_counter_clockwise']:,}/{r['cells']:,} "
        "(hanging nodes are straight vertices)"
    )
    print(
        f"  angles at the corners {r['min_angle']:.2f}° .. {r['max_angle']:.2f}°, max aspect "
        f"ratio {r['max_aspect_ratio']:.3g}"
    )
    for message in caught:
        print(f"  warning: {printable(str(message))}")
    return 0


def _curves_line(domain: Domain) -> str:
    """What the curve checks established, for the text certificate."""
    from collections import Counter

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
    interfaces = {name: edges.tolist() for name, edges in mesh.interfaces.items() if len(edges)}
    pieces, _ = connected_pieces(cell_neighbours(mesh.cells, mesh.n_points))
    return Domain.from_blocks(
        mesh.points,
        mesh.cells,
        patches,
        regions,
        name=mesh.name or "mesh",
        description=f"a level-{mesh.level} mesh read from a file",
        layout=f"mesh, level {mesh.level}",
        interfaces=interfaces,
        components=pieces,
    )


def _print_interfaces(interfaces: dict) -> None:
    for interface, info in interfaces.items():
        count = info["edges"]
        first, second = info["between"]
        print(
            f"    interface {printable(interface)}: {count:,} edge{'s' if count != 1 else ''} "
            f"between {printable(first)} and {printable(second)} (internal)"
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
        area = c["region_areas"][region]
        print(f"    region {printable(region)} (area {area:.12g}): blocks {listed}{more}")
    _print_interfaces(c["interfaces"])
    pieces = c["connected_components"]
    separate = " (separate parts: the mesh is not connected)" if pieces > 1 else ""
    print(
        f"  Euler characteristic {c['euler_characteristic']} "
        f"({pieces} piece{'s' if pieces != 1 else ''}, {c['holes']} "
        f"hole{'s' if c['holes'] != 1 else ''}){separate}"
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
