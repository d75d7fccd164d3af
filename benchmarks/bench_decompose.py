"""Decomposition of polygons into pentagonal blocks: time and blocks against n, with peers.

Run: ``python benchmarks/bench_decompose.py`` (peers with ``pip install -e '.[bench]'``).
For star-shaped polygons of n = 50 .. 2000 corners (and 2000 with 10 holes), a circle-like
64-gon and the L-shape with two holes, prints the time of ``Domain.from_polygon`` (validation,
quality triangulation, templates, node optimisation and the Domain's own check), the blocks, the
worst block angles, and time per corner (flat means linear growth). In the same run, the peers
on the same polygons: shapely's constrained Delaunay triangulation alone (no quality), Triangle
``pq30`` (quality triangulation, a C library) and gmsh's 2-D mesher, with their triangle counts;
and Triangle's triangles through the 9-pentagon template (the by-construction alternative: its
blocks and angles, no node moves); blockmesh's share of the time spent in its own triangulation is
printed as well. Not a test:
timings on shared machines are noisy; each figure is the best of a few runs after a warm-up.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
import shapely
from _page import Page, add_arguments

from blockmesh import Domain
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.triangulate import triangulate
from blockmesh.domain.validate.rings import check_rings
from blockmesh.geometry import interior_angles, local_frame


def star(n: int, lobes: int = 7, depth: float = 0.3) -> np.ndarray:
    t = 2 * np.pi * np.arange(n) / n
    r = 1 + depth * np.sin(lobes * t)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def circle(n: int, radius: float = 1.0, centre=(0.0, 0.0)) -> np.ndarray:
    t = 2 * np.pi * np.arange(n) / n
    return np.column_stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)])


def cases(sizes: list[int]) -> list[tuple[str, np.ndarray, list[np.ndarray]]]:
    out = [
        (
            "L-shape, 2 holes",
            np.array([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], dtype=float),
            [
                np.array([(0.3, 0.3), (0.6, 0.3), (0.6, 0.6), (0.3, 0.6)]),
                np.array([(1.3, 0.4), (1.7, 0.4), (1.5, 0.7)]),
            ],
        ),
        ("circle-like 64-gon", circle(64), []),
    ]
    out += [(f"star, n = {n}", star(n), []) for n in sizes]
    holes = [
        circle(20, 0.08, (0.5 * np.cos(a), 0.5 * np.sin(a)))
        for a in np.linspace(0, 2 * np.pi, 11)[:-1]
    ]
    out.append(("star 2000 + 10 holes", star(2000), holes))
    return out


def best_of(function, repeat: int) -> float:
    function()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def local_rings(outer, holes):
    rings = [r.points for r in check_rings([outer, *holes])]
    frame = local_frame(np.vstack(rings))
    return [frame.to_local(r) for r in rings]


def shapely_cdt(outer, holes, repeat):
    polygon = shapely.Polygon(outer, holes)
    seconds = best_of(lambda: shapely.constrained_delaunay_triangles(polygon), repeat)
    return seconds, len(shapely.get_parts(shapely.constrained_delaunay_triangles(polygon)))


def triangle_pq30(outer, holes, repeat):
    try:
        import triangle
    except ImportError:
        return None
    points, segments, hole_points = [], [], []
    for ring in [outer, *holes]:
        start = len(points)
        points += ring.tolist()
        segments += [(start + i, start + (i + 1) % len(ring)) for i in range(len(ring))]
    for ring in holes:
        hole_points.append(shapely.Polygon(ring).representative_point().coords[0])
    geometry = {"vertices": np.array(points), "segments": np.array(segments)}
    if hole_points:
        geometry["holes"] = np.array(hole_points)
    out = {}

    def run():
        out["t"] = triangle.triangulate(geometry, "pq30")

    seconds = best_of(run, repeat)
    # The by-construction alternative: Triangle's triangles, each its 9-pentagon template.
    pieces = pentagons_from_pieces(out["t"]["vertices"], [out["t"]["triangles"]])
    angles = interior_angles(pieces.nodes[pieces.blocks])
    return seconds, len(out["t"]["triangles"]), len(pieces.blocks), angles.min(), angles.max()


def gmsh_mesh(outer, holes, repeat):
    try:
        import gmsh
    except ImportError:
        return None
    size = float(np.median(np.hypot(*(np.roll(outer, -1, axis=0) - outer).T))) * 2
    out = {}

    def run():
        gmsh.initialize(readConfigFiles=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("Mesh.MeshSizeMax", size * 8)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
            loops = []
            for ring in [outer, *holes]:
                tags = [gmsh.model.geo.addPoint(x, y, 0, size) for x, y in ring]
                lines = [
                    gmsh.model.geo.addLine(tags[i], tags[(i + 1) % len(tags)])
                    for i in range(len(tags))
                ]
                loops.append(gmsh.model.geo.addCurveLoop(lines))
            gmsh.model.geo.addPlaneSurface(loops)
            gmsh.model.geo.synchronize()
            gmsh.model.mesh.generate(2)
            _, tags, _ = gmsh.model.mesh.getElements(2)
            out["n"] = sum(len(t) for t in tags)
        finally:
            gmsh.finalize()

    return best_of(run, repeat), out["n"]


DASH = "\u2013"  # between the ends of a range


def _ms(seconds: float) -> str:
    """Milliseconds with three significant digits."""
    return f"{seconds * 1e3:#.3g} ms"


ABOUT = """\
`Domain.from_polygon` end to end (validation, quality triangulation, templates, node moves and the
domain's own check) on star-shaped polygons of n corners (and 2000 with 10 holes), a circle-like
64-gon and the L-shape with two holes, and the peers on the same polygons in the same run:
shapely's constrained Delaunay triangulation alone (no quality), Triangle `pq30` (a C library),
its triangles through the 9-pentagon template, and gmsh's 2-D mesher with each corner's size its
shorter edge. Best of a few runs after a warm-up."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="*", default=[50, 100, 200, 500, 1000, 2000])
    parser.add_argument("--repeat", type=int, default=3)
    add_arguments(parser)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    page = Page("decompose", "Decomposition of polygons", ABOUT)
    table = page.table(
        "`Domain.from_polygon` against the peers on the same polygons",
        [
            "polygon",
            "corners",
            "time",
            "µs/corner",
            "blocks",
            "block angles",
            "own triangulation",
            "shapely CDT",
            "Triangle `pq30`",
            "`pq30` + templates",
            "gmsh",
        ],
    )
    rows = []
    for name, outer, holes in cases(args.sizes):
        corners = len(outer) + sum(len(h) for h in holes)
        repeat = args.repeat if corners <= 500 else 1
        seconds = best_of(lambda o=outer, h=holes: Domain.from_polygon(o, h), repeat)
        d = Domain.from_polygon(outer, holes)
        angles = d.block_angles()
        rings = local_rings(outer, holes)
        own = best_of(lambda r=rings: triangulate(r), repeat)
        cdt = shapely_cdt(outer, holes, repeat)
        tri = triangle_pq30(outer, holes, repeat)
        msh = gmsh_mesh(outer, holes, 1)

        def peer(result):
            return "-" if result is None else f"{_ms(result[0])}, {result[1]:,} tri"

        templated = "-" if tri is None else f"{tri[2]:,}, {tri[3]:.1f}°{DASH}{tri[4]:.1f}°"
        table.row(
            name,
            corners,
            f"{seconds:.3f} s",
            f"{seconds / corners * 1e6:,.0f}",
            f"{d.n_blocks:,}",
            f"{angles.min():.1f}°{DASH}{angles.max():.1f}°",
            f"{own / seconds:.0%}",
            f"{_ms(cdt[0])}, {cdt[1]:,} tri",
            peer(tri),
            templated,
            peer(msh),
        )
        rows.append((name, corners, seconds, d.n_blocks))
    star_rows = [r for r in rows if r[0].startswith("star, n")]
    if len(star_rows) >= 2:
        (_, n0, t0, b0), (_, n1, t1, b1) = star_rows[0], star_rows[-1]
        growth = np.log(t1 / t0) / np.log(n1 / n0)
        blocks = np.log(b1 / b0) / np.log(n1 / n0)
        table.note(
            f"Growth from n = {n0} to {n1}: time ~ n^{growth:.2f}, blocks ~ n^{blocks:.2f} "
            "(1.00 is linear)."
        )
    table.note(
        "own triangulation: the share of blockmesh's time spent in its quality triangulation. "
        "Triangle `pq30` + templates: Triangle's triangles each made its 9-pentagon template "
        "(the by-construction alternative, without node moves): blocks and their angles."
    )
    page.write(args)


if __name__ == "__main__":
    main()
