"""What every composite mesh must satisfy, checked against the parts' exact geometry.

``shapes`` are the parts as shapely geometries (circles followed finely), in the order of the
parts: the region of a point is the last part containing it (a later part is cut out of the
earlier ones).
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import shapely

import blockmesh
from blockmesh.domain.catalogue import catalogue_path
from blockmesh.geometry.topology import cell_neighbours

#: Segments per quarter circle of the exact shapes (area error about 1e-7 relative).
FINE = 2048


def disc(center, radius) -> shapely.Polygon:
    return shapely.Point(*center).buffer(radius, quad_segs=FINE)


def table_shape(table: dict) -> shapely.Geometry:
    """A ``[[parts]]`` table as a shapely geometry (straight polygons; circles fine)."""
    circles = list(table.get("circles", []))
    if "circle" in table:
        circles.append(table["circle"])
    discs = [disc(c["center"], c["radius"]) for c in circles]
    if "polygon" not in table:
        return shapely.union_all(discs)
    assert "arcs" not in table, "arcs are not followed here"
    shape = shapely.Polygon(table["polygon"], table.get("holes", []))
    for hole in discs:
        shape = shape.difference(hole)
    return shape


def catalogue_shapes(name: str) -> dict[str, shapely.Geometry]:
    """The parts of a composite catalogue domain, region -> exact shape, in order."""
    raw = tomllib.loads(catalogue_path(name).read_text())
    return {table["region"]: table_shape(table) for table in raw["parts"]}


def outline_bulge(shapes: dict[str, shapely.Geometry]) -> float:
    """How far the shapes' polygonal circles may be from the true ones: a chord's bulge.

    Bounded by that of a circle as wide as all the shapes together.
    """
    box = np.ptp(np.asarray(shapely.union_all(list(shapes.values())).bounds).reshape(2, 2), axis=0)
    return float(np.hypot(*box)) * (1 - np.cos(np.pi / (4 * FINE)))


def region_shapes(shapes: dict[str, shapely.Geometry]) -> dict[str, shapely.Geometry]:
    """Region i: part i minus every later part."""
    names = list(shapes)
    out = {}
    for i, name in enumerate(names):
        later = [shapes[n] for n in names[i + 1 :]]
        out[name] = shapes[name].difference(shapely.union_all(later)) if later else shapes[name]
    return out


def expected_regions(points: np.ndarray, shapes: dict[str, shapely.Geometry]) -> np.ndarray:
    """The index of the last part containing each point (-1 where none does)."""
    out = np.full(len(points), -1)
    for k, shape in enumerate(shapes.values()):
        out[shapely.contains_xy(shape, points[:, 0], points[:, 1])] = k
    return out


def full_check(mesh: blockmesh.Mesh) -> blockmesh.Mesh:
    """The mesh rebuilt through the Mesh constructor: every check it has runs."""
    fields = (
        "points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch",
        "patch_names", "region", "region_names", "level", "name", "curves",
        "interface_edges", "interface_patch", "interface_names",
    )  # fmt: skip
    return blockmesh.Mesh(**{f: getattr(mesh, f) for f in fields})


def assert_composite(mesh: blockmesh.Mesh, shapes: dict[str, shapely.Geometry]) -> None:
    """Tiling, conformity across interfaces, convexity, regions, interface names, areas."""
    full_check(mesh)  # counter-clockwise cells, boundary = free edges, interfaces between cells
    mesh.check_geometry()  # every cell strictly convex
    assert mesh.quality().not_strictly_convex == 0
    # No two nodes at one place: the regions share their interface nodes (one id each side).
    assert np.unique(mesh.points, axis=0).shape[0] == mesh.n_points
    # The region of every cell, by a point-in-part test of its vertex mean. The shapes' circles
    # are polygons, so a centre nearer a part's outline than their chords' bulge cannot be placed
    # by this test: a cell disagreeing with it must lie that near (tiny cells at a crossing of
    # an arc and an edge do).
    assert mesh.region_names == tuple(shapes)
    centres = mesh.points[mesh.cells].mean(axis=1)
    wrong = np.flatnonzero(expected_regions(centres, shapes) != mesh.region)
    if wrong.size:
        outlines = shapely.union_all([shapely.boundary(s) for s in shapes.values()])
        away = shapely.distance(outlines, shapely.points(centres[wrong]))
        assert away.max() <= outline_bulge(shapes), (wrong.size, centres[wrong[np.argmax(away)]])
    # Interfaces: exactly the edges between cells of two regions, named "A|B" in part order.
    cells = mesh.interface_cells()
    sides = mesh.region[cells]
    assert np.all(sides[:, 0] < sides[:, 1])  # the first region on the left
    names = [f"{mesh.region_names[a]}|{mesh.region_names[b]}" for a, b in sides.tolist()]
    assert names == [mesh.interface_names[k] for k in mesh.interface_patch]
    neighbour = cell_neighbours(mesh.cells, mesh.n_points)
    c, e = np.nonzero(neighbour >= 0)
    other = neighbour[c, e] // 5
    across = int(np.count_nonzero(mesh.region[c] != mesh.region[other])) // 2
    assert across == mesh.interface_edges.shape[0]
    # Areas: every region's cells (their curved edges included) cover exactly its shape. The
    # shapes' circles are polygons: a region's area is off by up to its outline's length times
    # their chords' bulge (for a tiny region beside a circle more than the relative tolerance).
    areas = mesh.curved_cell_areas()
    bulge = outline_bulge(shapes)
    for k, (name, region) in enumerate(region_shapes(shapes).items()):
        got = np.sum(areas[mesh.region == k])
        assert got == pytest.approx(region.area, rel=2e-6, abs=region.length * bulge), name
    # Nodes on curves lie on them (both regions of a curved interface see the same nodes).
    if mesh.curves is not None and len(mesh.curves):
        assert float(mesh.curves.distances(mesh.points).max()) == 0.0
