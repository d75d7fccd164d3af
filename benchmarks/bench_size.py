"""Size control measured: blockmesh's size-driven pentagons beside gmsh, and what they are worth.

Four parts, each a table of ``docs/benchmarks/size.md``:

1. **Quality beside gmsh.** Every catalogue domain at one size (``sqrt(area) / 40``) and a few
   distance-threshold fields; gmsh meshes the same outline (arcs as arcs) with the same field
   (its size callback is our field, scaled until its cell count is within 5 % of ours), as
   triangles (Frontal-Delaunay) and as recombined quadrilaterals (Blossom). Worst interior
   angle, 1st-percentile angle, worst aspect ratio (diameter^2 / area over that of the regular
   polygon: 1 is regular) and processor time (``time.process_time``, one gmsh thread).
2. **Accuracy per unknown.** The same virtual element solver on size-driven pentagons and on the
   paper's refinement, and P1 (scikit-fem) on gmsh's Delaunay triangles of the same size field:
   Cook's membrane (the vertical displacement at (48, 52), reference 23.9676, MATH.md section
   10) with uniform sizes; the L-shape's singular solution ``r^(2/3) sin(2 phi / 3)`` (H1 error)
   with a field graded towards the re-entrant corner.
3. **Speed.** The size-driven decomposition at about 10^5 blocks (uniform and graded).
4. **Grading and corners.** The graded channel (ratio 10 towards one wall) at levels 0-4; the
   cell at the L-shape's re-entrant corner against the mean cell, the paper's refinement beside
   ``Domain.uniform`` (the corner-true option).

Run: ``python benchmarks/bench_size.py [--quick]`` (gmsh and scikit-fem: ``pip install -e
'.[test]'``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
from _page import Page, add_arguments

import blockmesh
from blockmesh.curves import Arc
from blockmesh.domain.catalogue import catalogue_names
from blockmesh.geometry.polygons import interior_angles, polygon_diameter, signed_area
from blockmesh.sizing import as_size_spec

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "sizing"))

#: diameter^2 / area of the regular triangle, square and pentagon.
REGULAR_ASPECT = {3: 4 / math.sqrt(3), 4: 2.0, 5: 1 / 0.6572}
COOK = [(0.0, 0.0), (48.0, 44.0), (48.0, 60.0), (0.0, 44.0)]
COOK_REFERENCE = 23.9676


# ---------------------------------------------------------------------------- measures
def shape_measures(points: np.ndarray, cells: np.ndarray) -> dict[str, float]:
    """Worst and 1st-percentile angle, worst normalised aspect ratio of cells of one kind."""
    xy = points[cells]
    angles = interior_angles(xy)
    area = np.abs(signed_area(xy))
    aspect = polygon_diameter(xy) ** 2 / area / REGULAR_ASPECT[cells.shape[1]]
    return {
        "worst": float(angles.min()),
        "p1": float(np.percentile(angles, 1)),
        "aspect": float(aspect.max()),
    }


# ---------------------------------------------------------------------------- gmsh
def _gmsh_outline(domain) -> None:
    """The domain's boundary loops as a gmsh plane surface (arcs as circle arcs)."""
    import gmsh

    geo = gmsh.model.geo
    tags = {}
    for v in np.unique(domain.boundary_edges):
        x, y = domain.vertices[v]
        tags[int(v)] = geo.addPoint(float(x), float(y), 0.0)
    loops, current, start = [], [], None
    for a, b in domain.boundary_edges.tolist():
        if start is None:
            start = a
        curve = domain.curves.get((a, b)) or domain.curves.get((b, a))
        if isinstance(curve, Arc):
            cx, cy = curve.centre_point
            centre = geo.addPoint(cx, cy, 0.0)
            current.append(geo.addCircleArc(tags[a], centre, tags[b]))
        else:
            current.append(geo.addLine(tags[a], tags[b]))
        if b == start:
            loops.append(geo.addCurveLoop(current))
            current, start = [], None
    # The outer loop (largest area) first.
    areas = []
    for loop in domain_loops(domain):
        xy = domain.vertices[loop]
        areas.append(abs(float(signed_area(xy[None])[0])))
    order = np.argsort(areas)[::-1]
    geo.addPlaneSurface([loops[k] for k in order])
    geo.synchronize()


def _gmsh_regions(domain) -> None:
    """A composite domain's regions as gmsh plane surfaces sharing their interface curves.

    Every edge between two regions, and every boundary edge, is one gmsh curve (arcs as circle
    arcs) used by the surfaces on both sides, so gmsh's mesh conforms across the interfaces as
    ours does (what gmsh's ``fragment`` makes of overlapping parts).
    """
    import gmsh
    import shapely

    geo = gmsh.model.geo
    n = len(domain.vertices)
    names = list(domain.regions)
    region_of = np.full(domain.n_blocks, -1, dtype=np.int64)
    for r, name in enumerate(names):
        region_of[np.asarray(domain.regions[name])] = r
    tail = domain.blocks.ravel()
    head = np.roll(domain.blocks, -1, axis=1).ravel()
    region = np.repeat(region_of, domain.blocks.shape[1])
    count = len(names)
    own = (tail * n + head) * count + region
    # A directed block edge is on its region's outline when its reverse is not in the region.
    on = ~np.isin((head * n + tail) * count + region, own)
    points: dict[int, int] = {}
    curves: dict[tuple[int, int], int] = {}

    def point(v: int) -> int:
        if v not in points:
            x, y = domain.vertices[v]
            points[v] = geo.addPoint(float(x), float(y), 0.0)
        return points[v]

    def curve(a: int, b: int) -> int:
        low, high = min(a, b), max(a, b)
        if (low, high) not in curves:
            shape = domain.curves.get((low, high)) or domain.curves.get((high, low))
            if isinstance(shape, Arc):
                cx, cy = shape.centre_point
                centre = geo.addPoint(cx, cy, 0.0)
                curves[low, high] = geo.addCircleArc(point(low), centre, point(high))
            else:
                curves[low, high] = geo.addLine(point(low), point(high))
        tag = curves[low, high]
        return tag if a == low else -tag

    for r in range(count):
        sel = on & (region == r)
        ahead = dict(zip(tail[sel].tolist(), head[sel].tolist(), strict=True))
        loops = []
        while ahead:
            start = next(iter(ahead))
            ring, v = [start], ahead.pop(start)
            while v != start:
                ring.append(v)
                v = ahead.pop(v)
            loops.append(ring)
        # Counter-clockwise loops bound the region's pieces, clockwise ones are their holes.
        area = [float(signed_area(domain.vertices[ring][None])[0]) for ring in loops]
        outer = [k for k in range(len(loops)) if area[k] > 0]
        holes: dict[int, list[int]] = {k: [] for k in outer}
        for k in range(len(loops)):
            if area[k] < 0:
                inside = shapely.Point(domain.vertices[loops[k][0]])
                around = [
                    j for j in outer if shapely.Polygon(domain.vertices[loops[j]]).covers(inside)
                ]
                holes[min(around, key=lambda j: area[j])].append(k)
        for k in outer:
            tags = [
                geo.addCurveLoop(
                    [
                        curve(a, b)
                        for a, b in zip(loops[j], loops[j][1:] + loops[j][:1], strict=True)
                    ]
                )
                for j in [k, *holes[k]]
            ]
            geo.addPlaneSurface(tags)
    geo.synchronize()


def domain_loops(domain) -> list[np.ndarray]:
    loops, current, start = [], [], None
    for a, b in domain.boundary_edges.tolist():
        if start is None:
            start = a
        current.append(a)
        if b == start:
            loops.append(np.array(current))
            current, start = [], None
    return loops


def _gmsh_polygon(corners: np.ndarray) -> None:
    """A polygon (one counter-clockwise loop) as a gmsh plane surface."""
    import gmsh

    geo = gmsh.model.geo
    tags = [geo.addPoint(float(x), float(y), 0.0) for x, y in corners]
    lines = [geo.addLine(a, b) for a, b in zip(tags, tags[1:] + tags[:1], strict=True)]
    geo.addPlaneSurface([geo.addCurveLoop(lines)])
    geo.synchronize()


def gmsh_mesh(domain, field, scale: float, quads: bool, polygon: np.ndarray | None = None):
    """gmsh's mesh of the domain (or of ``polygon``) with sizes ``scale * field``.

    Returns the points, the cells by corner count and the processor seconds of the meshing.
    """
    import gmsh

    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("d")
        if polygon is None and len(domain.regions) > 1:
            _gmsh_regions(domain)
        elif polygon is None:
            _gmsh_outline(domain)
        else:
            _gmsh_polygon(polygon)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        if quads:
            gmsh.option.setNumber("Mesh.RecombineAll", 1)
            gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)  # Blossom
        gmsh.model.mesh.setSizeCallback(
            lambda _dim, _tag, x, y, _z, _lc: float(scale * field(np.array([[x, y]]))[0])
        )
        started = time.process_time()
        gmsh.model.mesh.generate(2)
        seconds = time.process_time() - started
        tags, coords, _ = gmsh.model.mesh.getNodes()
        points = np.asarray(coords).reshape(-1, 3)[:, :2]
        index = np.full(int(tags.max()) + 1, -1)
        index[tags.astype(np.int64)] = np.arange(len(tags))
        kinds, _, nodes = gmsh.model.mesh.getElements(2)
        cells = {}
        for kind, flat in zip(kinds, nodes, strict=True):
            n = {2: 3, 3: 4}[int(kind)]
            cells[n] = index[np.asarray(flat, dtype=np.int64)].reshape(-1, n)
    finally:
        gmsh.finalize()
    return points, cells, seconds


def matched_gmsh(domain, field, target: int, quads: bool, tol: float = 0.05):
    """gmsh's mesh with a cell count within ``tol`` of ``target`` (the field scaled)."""
    scale = 1.0
    for _ in range(12):
        points, cells, seconds = gmsh_mesh(domain, field, scale, quads)
        count = sum(len(c) for c in cells.values())
        if abs(count / target - 1) <= tol:
            break
        scale *= math.sqrt(count / target)
    return points, cells, seconds, count


# ---------------------------------------------------------------------------- part 1
def quality(page: Page, quick: bool) -> None:
    table = page.table(
        "Quality beside gmsh at equal cell count (+-5 %)",
        ["domain", "field", "cells", "ours: worst / 1% angle, aspect, s",
         "gmsh triangles", "gmsh quads", "corner"],
    )  # fmt: skip
    names = catalogue_names()
    if quick:
        names = ["square", "l-shape", "plate-hole", "star", "cook-membrane"]
    cases = [(n, "sqrt(A)/40") for n in names]
    cases += [
        ("plate-hole", {"default": 0.2, "near": [{"patch": "hole", "size": 0.02, "growth": 1.2}]}),
        ("l-shape", {"default": 0.1, "near": [{"point": [1, 1], "size": 0.005, "growth": 1.2}]}),
    ]
    wins = above = total = 0
    losses: list[str] = []
    for name, spec in cases:
        domain = blockmesh.load_domain(name)
        if spec == "sqrt(A)/40":
            spec_value: object = math.sqrt(domain.area) / 40
            label = f"h = {spec_value:.3g}"
        else:
            spec_value, label = spec, "threshold"
        started = time.process_time()
        sized = domain.with_size(spec_value)
        ours_s = time.process_time() - started
        ours = shape_measures(sized.vertices, sized.blocks)
        field = sized.size_field
        tri_points, tri_cells, tri_s, tri_n = matched_gmsh(domain, field, sized.n_blocks, False)
        tri = shape_measures(tri_points, tri_cells[3])
        q_points, q_cells, q_s, q_n = matched_gmsh(domain, field, sized.n_blocks, True)
        quad = shape_measures(q_points, q_cells[4]) if 4 in q_cells else {"worst": math.nan}
        sharpest = sharpest_corner(domain)
        total += 1
        wins += ours["worst"] >= tri["worst"]
        if ours["worst"] < tri["worst"]:
            losses.append(f"{name} ({label}: {ours['worst']:.1f} against {tri['worst']:.1f})")
        above += ours["worst"] >= 25 or sharpest < 25
        table.row(
            name, label, sized.n_blocks,
            f"{ours['worst']:.1f} / {ours['p1']:.1f}, {ours['aspect']:.2f}, {ours_s:.2f}",
            f"{tri['worst']:.1f} / {tri['p1']:.1f}, {tri['aspect']:.2f}, {tri_s:.2f} ({tri_n})",
            f"{quad['worst']:.1f} / {quad.get('p1', math.nan):.1f}, "
            f"{quad.get('aspect', math.nan):.2f}, {q_s:.2f} ({q_n})",
            f"{sharpest:.0f}",
        )  # fmt: skip
    table.note(
        "Each entry: worst interior angle / 1st-percentile angle (degrees), worst aspect ratio "
        "(diameter^2 / area over the regular polygon's: 1 is regular), processor seconds (gmsh: "
        "its cell count in brackets). 'corner' is the domain's sharpest corner (a cell there "
        f"cannot do better). Worst angle >= 25 degrees (or the domain's corner sharper): "
        f"{above} of {total}; >= gmsh triangles' worst angle: {wins} of {total}. "
        "Composite domains (several regions): gmsh meshes each region as a surface, the "
        "surfaces sharing the interface curves (as gmsh's fragment makes them), so both meshes "
        "conform across the interfaces. "
        + (
            "The pentagons' worst angle is below gmsh triangles' on: " + "; ".join(losses) + "."
            if losses
            else "The pentagons' worst angle is at least gmsh triangles' on every row."
        )
    )


def sharpest_corner(domain) -> float:
    """The domain's sharpest corner, in degrees, on the domain's side (chords of curves)."""
    worst = 180.0
    for loop in domain_loops(domain):
        xy = domain.vertices[loop]
        before = xy - np.roll(xy, 1, axis=0)
        after = np.roll(xy, -1, axis=0) - xy
        turn = np.degrees(
            np.arctan2(_cross2(before, after), np.sum(before * after, axis=1))
        )  # left turns positive: the domain is on the left of its boundary
        worst = min(worst, float((180.0 - turn).min()))
    return worst


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


# ---------------------------------------------------------------------------- part 2
def accuracy(page: Page, quick: bool) -> None:
    import bench_accuracy as acc

    cook = blockmesh.Domain.from_polygon(COOK, patches={"clamped": [3], "loaded": [1]}, name="cook")
    table = page.table(
        "Accuracy per unknown: Cook's membrane, v(48, 52) (reference 23.9676)",
        ["method", "size / level", "unknowns", "v(48, 52)", "error"],
    )
    rows = []
    for level in range(1, (3 if quick else 4) + 1):
        run = acc.vem_cook("pentagons (paper)", level, cook.mesh(level))
        rows.append(("VEM, paper's refinement", f"level {level}", run))
    for h in (8.0, 4.0, 2.0) if quick else (8.0, 4.0, 2.0, 1.0):
        run = acc.vem_cook("pentagons (sized)", 0, cook.with_size(h).mesh(0))
        rows.append(("VEM, size-driven pentagons", f"h = {h:g}", run))
    for h in (4.0, 2.0, 1.0) if quick else (4.0, 2.0, 1.0, 0.5):
        mesh = skfem_triangles(cook, as_size_spec(h).field(), acc.COOK_WITH_POINT)
        run = acc.fem_cook("P1", 0, mesh)
        rows.append(("P1 on gmsh Delaunay, same field", f"h = {h:g}", run))
    for method, size, run in rows:
        table.row(
            method, size, run.dof, f"{run.value:.4f}", f"{abs(run.value - COOK_REFERENCE):.4f}"
        )
    table.note(_winner(rows, lambda r: abs(r.value - COOK_REFERENCE)))

    lshape = blockmesh.load_domain("l-outline")
    table = page.table(
        "Accuracy per unknown: the L-shape's singular solution r^(2/3) sin(2 phi / 3), H1 error",
        ["method", "size / level", "unknowns", "H1 error", "L2 error"],
    )
    rows = []
    for level in range(2, (4 if quick else 5) + 1):
        run = acc.vem_poisson("corner", "pentagons (paper)", level, lshape.mesh(level))
        rows.append(("VEM, paper's refinement", f"level {level}", run))
    for h in (0.1, 0.05, 0.025) if quick else (0.1, 0.05, 0.025, 0.0125):
        spec = {"default": h, "near": [{"point": [1, 1], "size": h / 16, "growth": 1.25}]}
        run = acc.vem_poisson("corner", "sized", 0, lshape.with_size(spec).mesh(0))
        rows.append(("VEM, size-driven, graded to the corner", f"h = {h:g}", run))
        mesh = skfem_triangles(lshape, as_size_spec(spec).field())
        run = acc.fem_poisson("corner", "P1", 0, mesh)
        rows.append(("P1 on gmsh Delaunay, same field", f"h = {h:g}", run))
    for method, size, run in rows:
        table.row(method, size, run.dof, f"{run.h1:.3e}", f"{run.l2:.3e}")
    table.note(_winner(rows, lambda r: r.h1))


def skfem_triangles(domain, field, polygon: np.ndarray | None = None):
    """scikit-fem's MeshTri of gmsh's Delaunay triangles for ``field`` (sizes as triangle edges)."""
    import skfem

    points, cells, _ = gmsh_mesh(domain, field, 1.0, False, polygon)
    used = np.unique(cells[3])
    index = np.full(len(points), -1)
    index[used] = np.arange(used.size)
    return skfem.MeshTri(points[used].T.copy(), index[cells[3]].T.copy())


def _winner(rows, error) -> str:
    """Which method has the smallest error at matched unknowns (log-log interpolation)."""
    methods: dict[str, list] = {}
    for method, _, run in rows:
        methods.setdefault(method, []).append((run.dof, error(run)))
    lows = [min(d for d, _ in v) for v in methods.values()]
    highs = [max(d for d, _ in v) for v in methods.values()]
    lo, hi = max(lows), min(highs)
    if lo >= hi:
        return "The methods' unknowns do not overlap; compare the rows."
    at = math.sqrt(lo * hi)
    values = {}
    for method, pairs in methods.items():
        pairs.sort()
        d = np.log([p[0] for p in pairs])
        e = np.log([max(p[1], 1e-300) for p in pairs])
        values[method] = float(np.exp(np.interp(math.log(at), d, e)))
    best = min(values, key=values.get)  # type: ignore[arg-type]
    listed = "; ".join(f"{m}: {v:.3g}" for m, v in values.items())
    return (
        f"At {at:,.0f} unknowns (interpolated): {listed}. The winner is **{best}** "
        f"({max(values.values()) / values[best]:.2g} times smaller error than the worst)."
    )


# ---------------------------------------------------------------------------- part 3
def speed(page: Page, quick: bool) -> None:
    table = page.table(
        "Speed: the size-driven decomposition at about 10^5 blocks",
        ["domain", "field", "blocks", "processor s", "wall s", "us per block"],
    )
    square = blockmesh.load_domain("square")
    plate = blockmesh.load_domain("plate-hole")
    target = 20_000 if quick else 100_000
    h = math.sqrt(1.35 / (0.6572 * target))
    hp = math.sqrt(1.35 * plate.area / (0.6572 * target))
    near = {"default": 1.5 * hp, "near": [{"patch": "hole", "size": hp / 3, "growth": 1.2}]}
    cases = [
        (square, f"h = {h:.4g}", h),
        (plate, f"{1.5 * hp:.3g}, near the hole {hp / 3:.3g} growing 1.2 per cell", near),
    ]
    for domain, label, spec in cases:
        wall = time.perf_counter()
        cpu = time.process_time()
        sized = domain.with_size(spec)
        cpu = time.process_time() - cpu
        wall = time.perf_counter() - wall
        table.row(domain.name, label, f"{sized.n_blocks:,}", f"{cpu:.1f}", f"{wall:.1f}",
                  f"{1e6 * cpu / sized.n_blocks:.0f}")  # fmt: skip
    table.note(
        "Processor time of Domain.with_size (the field's check, the prediction, the outline, "
        "the fill and relaxation, the triangulations, the templates, the optimiser, the "
        "repairs, the Domain's own checks), single-threaded; wall time shows how busy the "
        "machine was."
    )


# ---------------------------------------------------------------------------- part 4
def grading_and_corners(page: Page, quick: bool) -> None:
    from test_grading import graded_channel

    from blockmesh.refinement.grading import geometric_fractions

    table = page.table(
        "The graded channel (ratio 10 towards the top wall)",
        ["level", "cells", "largest deviation from geometric", "worst angle", "not convex"],
    )
    domain = graded_channel()
    for level in range(5):
        mesh = domain.mesh(level)
        worst = 0.0
        for (a, b), ratio in domain.grading.items():
            start, stop = domain.vertices[a], domain.vertices[b]
            length = float(np.hypot(*(stop - start)))
            along = (mesh.points - start) @ (stop - start) / length**2
            across = np.abs(_cross(mesh.points - start, stop - start)) / length
            on = np.sort(along[(across < 1e-12) & (along > -1e-12) & (along < 1 + 1e-12)])
            worst = max(worst, float(np.max(np.abs(on - geometric_fractions(ratio, 2**level)))))
        q = mesh.quality()
        table.row(level, mesh.n_cells, f"{worst:.1e}", f"{q.min_angle:.1f}", q.not_strictly_convex)
    table = page.table(
        "Corner-true: the cell at the L-shape's re-entrant corner over the mean cell area",
        ["level", "paper: cells", "paper: corner / mean", "uniform: cells",
         "uniform: corner / mean", "neighbour ratio paper / uniform"],
    )  # fmt: skip
    lshape = blockmesh.load_domain("l-shape")
    for level in range(1, (4 if quick else 5) + 1):
        paper = lshape.mesh(level)
        even = lshape.uniform(level).block_mesh()
        shares = []
        for mesh in (paper, even):
            v = int(np.argmin(np.hypot(*(mesh.points - [1, 1]).T)))
            areas = mesh.cell_areas()
            shares.append(areas[np.any(mesh.cells == v, axis=1)].max() / areas.mean())
        ratios = []
        for mesh in (paper, even):
            from blockmesh.sizing import size_report

            ratios.append(size_report(mesh.points, mesh.cells).neighbour_ratio)
        table.row(level, paper.n_cells, f"{shares[0]:.2f}", even.n_cells, f"{shares[1]:.2f}",
                  f"{ratios[0]:.2f} / {ratios[1]:.2f}")  # fmt: skip


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[1] - a[:, 1] * b[0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer domains and sizes")
    parser.add_argument(
        "--parts", default="quality,accuracy,speed,grading", help="which parts to run"
    )
    add_arguments(parser)
    args = parser.parse_args()
    page = Page("size", "Size control", __doc__)
    parts = args.parts.split(",")
    if "quality" in parts:
        quality(page, args.quick)
    if "accuracy" in parts:
        accuracy(page, args.quick)
    if "speed" in parts:
        speed(page, args.quick)
    if "grading" in parts:
        grading_and_corners(page, args.quick)
    page.write(args)


if __name__ == "__main__":
    main()
