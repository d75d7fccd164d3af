"""Local refinement: properties over catalogue domains and random markings, several rounds deep.

Every refined mesh is checked for what a conforming polygon mesh must be: it tiles the domain
(areas add up to the domain's, the boundary is the domain's boundary subdivided, the constructor's
full checks pass: no edge in three cells, boundary edges exactly the free edges), every cell is
convex and counter-clockwise (hanging nodes are straight vertices), no side carries more than one
hanging node, the counts match the closed forms for the marked set, and marking every cell of a
pentagon mesh is uniform refinement bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from helpers import CATALOGUE, examples
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.errors import ArgumentError, DomainError, ResourceError
from blockmesh.geometry.topology import PolygonCells, cell_neighbours, edge_keys
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.local import (
    HANGING_PER_SIDE,
    close_marking,
    predict_local_size,
    refine_locally,
    refine_marked,
)

DOMAINS = ["sp", "l-shape", "square-cut", "joined-3", "hexagon", "comb", "backward-step"]
CURVED = ["disc", "quarter-plate-hole", "annulus"]


def _full_copy(mesh: PolygonMesh) -> PolygonMesh:
    """The mesh rebuilt through the checking constructor (every construction check runs)."""
    return PolygonMesh(
        points=mesh.points,
        offsets=mesh.offsets,
        nodes=mesh.nodes,
        block_id=mesh.block_id,
        parent=mesh.parent,
        boundary_edges=mesh.boundary_edges,
        boundary_patch=mesh.boundary_patch,
        patch_names=mesh.patch_names,
        region=mesh.region,
        region_names=mesh.region_names,
        cell_level=mesh.cell_level,
        level=mesh.level,
        name=mesh.name,
        curves=mesh.curves,
    )


def _check_mesh(mesh: PolygonMesh, base: blockmesh.Mesh, curved: bool) -> None:
    _full_copy(mesh)
    mesh.check_geometry()  # every cell convex and counter-clockwise
    assert int(mesh.side_lengths().max()) <= HANGING_PER_SIDE + 1
    # every edge in at most two cells: the neighbour search refuses three
    neighbour = cell_neighbours(mesh.polygon_cells(), mesh.n_points)
    interior = int(np.count_nonzero(neighbour >= 0))
    assert interior % 2 == 0
    assert mesh.boundary_edges.shape[0] == int(np.count_nonzero(neighbour < 0))
    if curved:
        assert abs(mesh.curved_area - base.curved_area) < 1e-11 * base.curved_area
        assert float(np.max(mesh.curves.distances(mesh.points))) < 1e-12
    else:
        assert abs(mesh.area - base.area) < 1e-11 * base.area
        if mesh.n_cells > 6000:  # the union below is slow; the area and the checks above hold
            return
        # tiling: the union of the cells is the domain, without gaps or overlaps
        polygons = [shapely.Polygon(mesh.points[mesh.cell(c)]) for c in range(mesh.n_cells)]
        union = shapely.union_all(polygons)
        outline = shapely.union_all(shapely.polygons(base.points[base.cells]))
        assert abs(union.area - outline.area) < 1e-9 * outline.area
        assert shapely.symmetric_difference(union, outline).area < 1e-9 * outline.area
        # every boundary edge lies on an edge of the base's boundary, its patch kept
        a = mesh.points[mesh.boundary_edges[:, 0]]
        b = mesh.points[mesh.boundary_edges[:, 1]]
        mid = (a + b) / 2
        lines = shapely.linestrings(base.points[base.boundary_edges])
        tree = shapely.STRtree(lines)
        near = tree.query_nearest(shapely.points(mid), return_distance=True)
        assert float(near[1].max()) < 1e-9
        base_patch = base.boundary_patch[near[0][1]]
        assert np.array_equal(mesh.boundary_patch[near[0][0]], base_patch)
        assert mesh.patch_names == base.patch_names


def _expected_counts(
    mesh: PolygonMesh, marked: np.ndarray, scheme: str = "pentagons"
) -> tuple[int, int]:
    """Closed forms: M + Σ k_c cells, N + Σ k_c + (distinct split edges) nodes (pentagons);
    M + Σ (k_c - 1) cells, N + (marked) + (distinct split edges) nodes (quads)."""
    corners = mesh.corner_counts()
    side, length = mesh.sides()
    corner_slot = np.flatnonzero(~mesh.straight_vertices())
    owner = mesh.polygon_cells().slot_cell()[corner_slot]
    whole = marked[owner] & (length == 1)
    slots = corner_slot[whole]
    following = mesh.polygon_cells().following()
    keys = np.unique(edge_keys(mesh.nodes[slots], following[slots], mesh.n_points))
    added = int(corners[marked].sum())
    if scheme == "quads":
        count = int(marked.sum())
        return mesh.n_cells + added - count, mesh.n_points + count + keys.size
    return mesh.n_cells + added, mesh.n_points + added + keys.size


@pytest.mark.parametrize("name", DOMAINS + CURVED)
def test_marking_every_cell_is_uniform_refinement_bit_for_bit(name):
    mesh = blockmesh.load_domain(name).mesh(1)
    local = blockmesh.refine(mesh, cells=np.ones(mesh.n_cells, dtype=bool))
    uniform = blockmesh.refine(mesh, 1)
    again = local.to_mesh()
    assert np.array_equal(again.points, uniform.points)
    assert np.array_equal(again.cells, uniform.cells)
    assert np.array_equal(again.boundary_edges, uniform.boundary_edges)
    assert np.array_equal(again.boundary_patch, uniform.boundary_patch)
    assert np.array_equal(again.parent, uniform.parent)
    assert np.array_equal(again.region, uniform.region)
    assert again.level == uniform.level
    if uniform.curves is not None:
        rows = {tuple(e) for e in local.curves.edges.tolist()}
        assert rows == {tuple(e) for e in uniform.curves.edges.tolist()}


@st.composite
def markings(draw: st.DrawFn, names: list[str]) -> tuple[str, int, list[np.ndarray]]:
    name = draw(st.sampled_from(names))
    level = draw(st.integers(0, 1))
    rounds = draw(st.integers(1, 4))
    seeds = [draw(st.integers(0, 2**31 - 1)) for _ in range(rounds)]
    fractions = [draw(st.floats(0.01, 0.3)) for _ in range(rounds)]
    return name, level, list(zip(seeds, fractions, strict=True))


def _random_mask(mesh: PolygonMesh, seed: int, fraction: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    mask = rng.random(mesh.n_cells) < fraction
    mask[rng.integers(mesh.n_cells)] = True
    return mask


@given(markings(DOMAINS), st.sampled_from(["pentagons", "pentagons", "quads"]))
@settings(max_examples=examples(40), deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_random_markings_several_rounds_deep(case, scheme):
    name, level, rounds = case
    base = blockmesh.load_domain(name).mesh(level)
    mesh = PolygonMesh.from_mesh(base)
    for seed, fraction in rounds:
        wanted = _random_mask(mesh, seed, fraction)
        closed = close_marking(mesh, wanted)
        assert np.all(closed[wanted])
        cells, nodes = _expected_counts(mesh, closed, scheme)
        predicted = predict_local_size(mesh, closed, scheme)
        assert (predicted.cells, predicted.nodes) == (cells, nodes)
        fine = refine_marked(mesh, wanted, scheme=scheme)
        assert (fine.n_cells, fine.n_points) == (cells, nodes)
        assert fine.level == mesh.level + 1
        children = fine.cell_level > mesh.cell_level[fine.parent]
        assert np.array_equal(np.unique(fine.parent[children]), np.flatnonzero(closed))
        assert np.all(fine.region == mesh.region[fine.parent])
        assert np.all(fine.block_id == mesh.block_id[fine.parent])
        _check_mesh(fine, base, curved=False)
        mesh = fine


@given(markings(CURVED))
@settings(max_examples=examples(15), deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_random_markings_keep_nodes_on_the_curves(case):
    name, level, rounds = case
    base = blockmesh.load_domain(name).mesh(level)
    mesh = PolygonMesh.from_mesh(base)
    for seed, fraction in rounds[:3]:
        mesh = refine_marked(mesh, _random_mask(mesh, seed, fraction))
        _check_mesh(mesh, base, curved=True)


def test_general_polygons_split_into_pentagons_and_a_central_polygon():
    hexagon = np.array([[np.cos(t), np.sin(t)] for t in np.linspace(0, 2 * np.pi, 7)[:-1]])
    triangle = [[2.0, 0.0], [3.0, 0.0], [2.5, 1.0]]
    pts = np.vstack([hexagon, triangle])
    mesh = PolygonMesh.from_cells(pts, [list(range(6)), [6, 7, 8]])
    fine = refine_marked(mesh, [0, 1])
    sizes = fine.cell_sizes().tolist()
    assert sizes == [5] * 6 + [6] + [5] * 3 + [3]
    assert abs(fine.area - mesh.area) < 1e-14
    fine.check_geometry()
    # the central cell keeps the parent's shape: its corners are the midpoint polygon shrunk
    centre = fine.points[fine.cell(6)]
    mids = (hexagon + np.roll(hexagon, -1, axis=0)) / 2
    assert np.allclose(centre, (mids + hexagon.mean(axis=0)) / 2)


@given(
    st.integers(3, 12),
    st.lists(st.floats(0.2, 1.0), min_size=12, max_size=12),
    st.floats(0, 2 * np.pi),
)
@settings(max_examples=examples(60), deadline=None)
def test_children_of_convex_polygons_are_convex(n, radii, turn):
    angles = turn + 2 * np.pi * np.arange(n) / n
    ring = np.column_stack([np.cos(angles), np.sin(angles)]) * np.array(radii[:n])[:, None]
    hull = shapely.convex_hull(shapely.multipoints(ring))
    xy = np.asarray(hull.exterior.coords)[:-1]
    if not shapely.is_ccw(hull.exterior):
        xy = xy[::-1]
    mesh = PolygonMesh.from_cells(xy, [list(range(xy.shape[0]))])
    fine = refine_locally(mesh, [0], rounds=2)
    fine.check_geometry()
    assert abs(fine.area - mesh.area) < 1e-12 * mesh.area


def test_the_marking_is_closed_so_one_hanging_node_per_side_at_most():
    mesh = blockmesh.load_domain("joined-2").mesh(0)
    once = refine_marked(mesh, [0])
    assert once.side_lengths().max() == 2
    child = 1  # halves a side of the hexagon (old cell 1)
    twice = refine_marked(once, [child])
    assert twice.side_lengths().max() == 2
    assert twice.n_cells == once.n_cells + 5 + 5  # the hexagon (5 corners) was split too


@pytest.mark.parametrize("name", CATALOGUE[:6])
def test_counts_of_one_marked_cell_per_block(name):
    base = blockmesh.load_domain(name).mesh(0)
    marked = np.zeros(base.n_cells, dtype=bool)
    marked[::2] = True
    fine = refine_marked(base, marked)
    assert fine.n_cells == base.n_cells + 5 * int(marked.sum())
    _check_mesh(fine, base, curved=False)


def test_bad_markings_are_located():
    mesh = blockmesh.load_domain("sp").mesh(1)
    with pytest.raises(ArgumentError, match="marks none of the 6 cells"):
        blockmesh.refine(mesh, cells=np.zeros(6, dtype=bool))
    with pytest.raises(ArgumentError, match="cell 9 does not exist"):
        blockmesh.refine(mesh, cells=[9])
    with pytest.raises(ArgumentError, match="one entry per cell"):
        blockmesh.refine(mesh, cells=np.ones(4, dtype=bool))
    with pytest.raises(ResourceError, match="marked cells"):
        refine_marked(mesh, [0, 1], max_memory=1000)


def test_a_side_with_two_hanging_nodes_is_refused():
    pts = [(0, 0), (3, 0), (3, 1), (0, 1), (1, 1), (2, 1), (1, 2), (2, 2), (0, 2), (3, 2)]
    cells = [[0, 1, 2, 5, 4, 3], [3, 4, 6, 8], [4, 5, 7, 6], [5, 2, 9, 7]]
    mesh = PolygonMesh.from_cells(pts, cells)
    assert int(mesh.side_lengths().max()) == 3
    with pytest.raises(DomainError, match="2 hanging nodes on one side"):
        refine_marked(mesh, [0])


def test_folding_on_a_curve_is_located():
    from blockmesh.curves import Arc
    from blockmesh.curves.edges import CurvedEdges

    # An arc bulging deep into its cell (the Domain checks would refuse it; built by hand).
    pentagon = np.array([(0, 0), (1, 0), (1.2, 0.5), (1, 1), (0, 1)], dtype=float)
    arc = Arc(through=(0.5, 0.2)).with_ends(tuple(pentagon[3]), tuple(pentagon[4]))
    curves = CurvedEdges(edges=[[3, 4]], curve=[0], start=[0.0], stop=[1.0], curves=(arc,))
    plain = blockmesh.Mesh.from_cells(pentagon, [[0, 1, 2, 3, 4]])
    mesh = blockmesh.Mesh(
        points=plain.points,
        cells=plain.cells,
        block_id=plain.block_id,
        parent=plain.parent,
        boundary_edges=plain.boundary_edges,
        boundary_patch=plain.boundary_patch,
        patch_names=plain.patch_names,
        region=plain.region,
        region_names=plain.region_names,
        curves=curves,
    )
    with pytest.raises(DomainError, match="refining cell 0 .* would fold it"):
        refine_marked(mesh, [0])


def test_refine_of_a_polygon_mesh_and_rounds():
    mesh = blockmesh.load_domain("l-shape").mesh(1)
    corner = lambda m: np.hypot(*m.vertex_means().T) < 0.3  # noqa: E731
    fine = blockmesh.refine(mesh, 3, cells=corner)
    assert fine.level == 4 and int(fine.cell_level.max()) == 4
    again = blockmesh.refine(fine, 1)  # a PolygonMesh: every cell split
    assert again.n_cells == fine.n_cells + int(fine.corner_counts().sum())
    _check_mesh(again, mesh, curved=False)
    assert PolygonCells(again.offsets, again.nodes).n_cells == again.n_cells


def test_the_quad_scheme_is_a_quadtree_on_squares():
    square = PolygonMesh.from_cells([(0, 0), (1, 0), (1, 1), (0, 1)], [[0, 1, 2, 3]])
    fine = refine_locally(square, [0], rounds=3, scheme="quads")
    assert fine.n_cells == 64 and set(fine.cell_sizes().tolist()) == {4}
    np.testing.assert_allclose(fine.cell_areas(), 1 / 64)
    once = refine_marked(fine, [0], scheme="quads")  # its neighbours get hanging nodes
    assert once.hanging_nodes().size == 2 and int(once.side_lengths().max()) == 2
    with pytest.raises(ArgumentError, match="unknown scheme"):
        refine_marked(square, [0], scheme="hexagons")
