"""Worst angles of level-3 meshes on the decomposed catalogue domains, beside gmsh's.

Run: ``python benchmarks/bench_quality.py [NAMES...]`` (gmsh with ``pip install -e '.[bench]'``).
For each domain given as a polygon (with holes) in the catalogue, meshes it at ``--level``
(default 3) with the paper's node placement, with ``--placement optimized`` (corner
distortion plus uniform cell sizes, after every level) and with ``--placement angles`` (the
worst corners weighted most, every cell keeping its size); then asks gmsh for a triangle mesh
and a quadrilateral mesh (Frontal-Delaunay for quads, blossom recombination) of the same
polygon with about the same number of cells (the mesh size is corrected until the count is
within 5 %), and prints every mesh's cells, smallest and largest interior angle. The smallest
corner of the domain itself is printed too: no cell at that corner can have a larger angle.
Not a test: the times are of a shared machine.
"""

from __future__ import annotations

import argparse
import time
import tomllib

import numpy as np
from _page import Page, add_arguments

from blockmesh import load_domain
from blockmesh.domain.catalogue import catalogue_path
from blockmesh.geometry import interior_angles
from blockmesh.refinement.improve import refine_with_rule

#: The catalogue domains given as polygons (issue 8's new ones).
DOMAINS = [
    "backward-step",
    "t-junction",
    "channel-obstacle",
    "l-outline",
    "plate-octagon",
    "cook-membrane",
    "comb",
    "star",
    "lake-island",
]


def rings_of(name: str) -> list[np.ndarray]:
    """The outer ring and the holes of a catalogue domain's polygon form."""
    data = tomllib.loads(catalogue_path(name).read_text())
    return [np.asarray(data["polygon"], float)] + [
        np.asarray(h, float) for h in data.get("holes", [])
    ]


def ring_area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))


def smallest_corner(rings: list[np.ndarray]) -> float:
    """The smallest angle of the domain at a corner, in degrees (inside the domain)."""
    worst = 180.0
    for k, ring in enumerate(rings):
        ccw = ring if (ring_area_signed(ring) > 0) == (k == 0) else ring[::-1]
        worst = min(worst, float(interior_angles(ccw[None])[0].min()))
    return worst


def ring_area_signed(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def gmsh_mesh(rings: list[np.ndarray], size: float, quads: bool) -> np.ndarray:
    """gmsh's mesh of the polygon at uniform ``size``: element corners (M, k, 2)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        if quads:
            gmsh.option.setNumber("Mesh.Algorithm", 8)
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
            gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
        loops = []
        for ring in rings:
            tags = [gmsh.model.geo.addPoint(x, y, 0, size) for x, y in ring]
            lines = [gmsh.model.geo.addLine(tags[i], tags[(i + 1) % len(tags)])
                     for i in range(len(tags))]  # fmt: skip
            loops.append(gmsh.model.geo.addCurveLoop(lines))
        gmsh.model.geo.addPlaneSurface(loops)
        gmsh.model.geo.synchronize()
        gmsh.model.mesh.generate(2)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        xy = np.empty((int(node_tags.max()) + 1, 2))
        xy[node_tags.astype(int)] = coords.reshape(-1, 3)[:, :2]
        types, _, nodes = gmsh.model.mesh.getElements(2)
        cells = []
        for kind, conn in zip(types, nodes, strict=True):
            k = {2: 3, 3: 4}[int(kind)]
            cells.append(xy[conn.astype(int).reshape(-1, k)])
        return cells
    finally:
        gmsh.finalize()


def element_angles(cells: list[np.ndarray]) -> tuple[int, float, float]:
    """(count, min angle, max angle) of elements given as corner arrays, any orientation."""
    lo, hi, count = 180.0, 0.0, 0
    for corners in cells:
        x, y = corners[..., 0], corners[..., 1]
        clockwise = np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1) < 0
        corners = np.where(clockwise[:, None, None], corners[:, ::-1], corners)
        angles = interior_angles(corners)
        lo, hi, count = (
            min(lo, float(angles.min())),
            max(hi, float(angles.max())),
            count + len(corners),
        )
    return count, lo, hi


def gmsh_at_count(rings: list[np.ndarray], cells: int, quads: bool):
    """gmsh's mesh with about ``cells`` elements: (count, min angle, max angle, size)."""
    area = ring_area(rings[0]) - sum(ring_area(h) for h in rings[1:])
    per_cell = area / cells
    size = np.sqrt(per_cell) if quads else np.sqrt(4 * per_cell / np.sqrt(3))
    for _ in range(6):
        count, lo, hi = element_angles(gmsh_mesh(rings, size, quads))
        if abs(count - cells) <= 0.05 * cells:
            break
        size *= np.sqrt(count / cells)
    return count, lo, hi


DASH = "\u2013"  # between the ends of a range

ABOUT = """\
Level-3 meshes of the catalogue's decomposed domains with the paper's node placement,
`--placement optimized` (corner distortion plus uniform cell sizes, after every level) and
`--placement angles` (the worst corners weighted most, every cell keeping its size), beside
gmsh's triangle and quadrilateral meshes (Frontal-Delaunay, blossom recombination) of the same
polygon with the same number of cells within 5 %: each mesh's smallest and largest interior
angle. The smallest corner of the domain itself is shown too: no cell at that corner can have a
larger angle. The seconds are those of the node moves, on a shared machine."""


def _angles(low: float, high: float) -> str:
    return f"{low:.1f}°{DASH}{high:.1f}°"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", default=DOMAINS)
    parser.add_argument("--level", type=int, default=3)
    parser.add_argument("--no-gmsh", action="store_true")
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("quality", "Mesh quality against gmsh", ABOUT)
    peers = [] if args.no_gmsh else ["gmsh triangles", "gmsh quads"]
    table = page.table(
        f"Worst angles at level {args.level}",
        [
            "domain (blocks)",
            "smallest corner",
            "cells",
            "paper",
            "`optimized`",
            "`angles`",
            "seconds: paper, optimized, angles",
            *peers,
        ],
    )
    for name in args.names:
        domain = load_domain(name)
        rings = rings_of(name)
        cells = 0
        angles, seconds = [], []
        for rule in ("paper", "optimized", "angles"):
            started = time.perf_counter()
            mesh = refine_with_rule(domain, args.level, rule=rule)
            seconds.append(time.perf_counter() - started)
            quality = mesh.quality()
            assert (
                quality.not_strictly_convex == 0 and mesh.n_cells == domain.n_blocks * 6**args.level
            )
            cells = mesh.n_cells
            angles.append(_angles(quality.min_angle, quality.max_angle))
        row = [
            f"{name} ({domain.n_blocks})",
            f"{smallest_corner(rings):.1f}°",
            f"{cells:,}",
            *angles,
            ", ".join(f"{t:.1f}" for t in seconds),
        ]
        for quads in () if args.no_gmsh else (False, True):
            count, lo, hi = gmsh_at_count(rings, cells, quads)
            row.append(f"{_angles(lo, hi)} ({count:,})")
        table.row(*row)
    if peers:
        table.note("gmsh columns: the angles, and the number of cells in brackets.")
    page.write(args)


if __name__ == "__main__":
    main()
