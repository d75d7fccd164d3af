"""Refinement invariants over the catalogue and levels, the paper's numbering, RCM, memory guard."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE, LARGE_CATALOGUE, SP, TWO_BLOCKS, TWO_VERTICES
from paper_numbering import paper_cells

import blockmesh
from blockmesh import Domain, Mesh, ResourceError, refine
from blockmesh.geometry import is_strictly_convex, signed_area
from blockmesh.geometry.topology import edge_keys
from blockmesh.refinement.sizes import predict_size

LEVELS = range(5)

# The paper's rule applied by hand to one pentagon <0 1 2 3 4> (0-based; docs/mathematics.md §3).
# Level 1: corners 0-4, midpoints u1..u5 = 5-9, inner points w1..w5 = 10-14 (Fig. 2).
PAPER_LEVEL_1 = [
    [0, 5, 10, 14, 9], [1, 6, 11, 10, 5], [2, 7, 12, 11, 6],
    [3, 8, 13, 12, 7], [4, 9, 14, 13, 8], [10, 11, 12, 13, 14],
]  # fmt: skip
# Level 2: each level-1 cell in order numbers its new midpoints then its five inner points; e.g.
# cell 1 <1 6 11 10 5> numbers (1,6)=25 (6,11)=26 (11,10)=27, finds (10,5)=16 from cell 0,
# numbers (5,1)=28, then w = 29..33.
PAPER_LEVEL_2 = [
    [0, 15, 20, 24, 19], [5, 16, 21, 20, 15], [10, 17, 22, 21, 16],
    [14, 18, 23, 22, 17], [9, 19, 24, 23, 18], [20, 21, 22, 23, 24],
    [1, 25, 29, 33, 28], [6, 26, 30, 29, 25], [11, 27, 31, 30, 26],
    [10, 16, 32, 31, 27], [5, 28, 33, 32, 16], [29, 30, 31, 32, 33],
    [2, 34, 38, 42, 37], [7, 35, 39, 38, 34], [12, 36, 40, 39, 35],
    [11, 26, 41, 40, 36], [6, 37, 42, 41, 26], [38, 39, 40, 41, 42],
    [3, 43, 47, 51, 46], [8, 44, 48, 47, 43], [13, 45, 49, 48, 44],
    [12, 35, 50, 49, 45], [7, 46, 51, 50, 35], [47, 48, 49, 50, 51],
    [4, 52, 55, 59, 54], [9, 18, 56, 55, 52], [14, 53, 57, 56, 18],
    [13, 44, 58, 57, 53], [8, 54, 59, 58, 44], [55, 56, 57, 58, 59],
    [10, 27, 60, 64, 17], [11, 36, 61, 60, 27], [12, 45, 62, 61, 36],
    [13, 53, 63, 62, 45], [14, 17, 64, 63, 53], [60, 61, 62, 63, 64],
]  # fmt: skip


@pytest.fixture(scope="module")
def meshes(catalogue):
    return {(name, level): catalogue[name].mesh(level) for name in CATALOGUE for level in LEVELS}


@pytest.fixture(
    params=[
        # level 4 of the largest domains (124k to 276k cells) in the slow set
        pytest.param((name, level), marks=pytest.mark.slow)
        if level == 4 and name in LARGE_CATALOGUE
        else (name, level)
        for name in CATALOGUE
        for level in LEVELS
    ],
    ids=str,
)
def case(request, catalogue, meshes):
    name, level = request.param
    return catalogue[name], meshes[name, level], level


def test_large_catalogue_is_the_domains_of_90_blocks_or_more(catalogue):
    # The catalogue sweeps leave these to the slow set; a new large domain belongs in the list.
    large = sorted(name for name, domain in catalogue.items() if domain.n_blocks >= 90)
    assert large == sorted(LARGE_CATALOGUE)


def _edge_use(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    keys = edge_keys(mesh.cells, np.roll(mesh.cells, -1, axis=1), mesh.n_points).ravel()
    unique, counts = np.unique(keys, return_counts=True)
    return unique, counts


def test_counts_match_the_closed_forms(case):
    domain, mesh, level = case
    size = predict_size(
        domain.n_blocks, domain.n_vertices, domain.n_shared_edges,
        domain.boundary_edges.shape[0], level, level,
    )  # fmt: skip
    b, i, v0 = domain.n_blocks, domain.n_shared_edges, domain.n_vertices
    assert mesh.n_cells == b * 6**level == size.cells
    nodes = v0 - 4 * b + i + (3 * b * 6**level + 5 * b * 2**level) // 2 - i * 2**level
    assert mesh.n_points == nodes == size.nodes
    assert len(mesh.edges()) == mesh.n_edges == (5 * b * (6**level + 2**level)) // 2 - i * 2**level
    assert mesh.n_edges == size.edges
    assert mesh.boundary_edges.shape[0] == (5 * b - 2 * i) * 2**level == size.boundary_edges


def test_every_edge_in_one_or_two_cells(case):
    _, mesh, _ = case
    keys, counts = _edge_use(mesh)
    assert set(np.unique(counts)) <= {1, 2}
    boundary = edge_keys(mesh.boundary_edges[:, 0], mesh.boundary_edges[:, 1], mesh.n_points)
    assert np.array_equal(np.sort(boundary), keys[counts == 1])


def test_area_preserved_and_cells_strictly_convex_ccw(case):
    domain, mesh, _ = case
    xy = mesh.cell_coordinates()
    assert np.all(signed_area(xy) > 0)
    assert np.all(is_strictly_convex(xy))
    assert mesh.area == pytest.approx(domain.area, rel=1e-12)
    assert mesh.quality().not_strictly_convex == 0


def test_no_two_nodes_coincide(case):
    _, mesh, _ = case
    assert np.unique(mesh.points, axis=0).shape[0] == mesh.n_points
    assert np.array_equal(np.unique(mesh.cells), np.arange(mesh.n_points))


def test_nested_prefix_property(case, meshes):
    domain, mesh, level = case
    if level == 0:
        assert np.array_equal(mesh.points, domain.vertices)
        assert np.array_equal(mesh.cells, domain.blocks)
        assert np.all(mesh.parent == -1)
        return
    coarse = meshes[domain.name, level - 1]
    assert np.array_equal(mesh.points[: coarse.n_points], coarse.points)
    assert np.array_equal(mesh.parent, np.arange(mesh.n_cells) // 6)
    # Corner k of a parent is corner 0 of its child k.
    family = mesh.cells.reshape(-1, 6, 5)
    assert np.array_equal(family[:, :5, 0], coarse.cells)
    assert np.array_equal(mesh.block_id, np.repeat(coarse.block_id, 6))
    assert np.array_equal(mesh.region, np.repeat(coarse.region, 6))


def test_boundary_edges_keep_their_patch(case):
    domain, mesh, level = case
    assert mesh.patch_names == domain.patch_names
    # Each boundary edge lies on the coarse boundary edge it came from, in order.
    coarse = np.repeat(domain.boundary_edges, 2**level, axis=0)
    a, b = domain.vertices[coarse[:, 0]], domain.vertices[coarse[:, 1]]
    for end in (0, 1):
        p = mesh.points[mesh.boundary_edges[:, end]]
        cross = (b - a)[:, 0] * (p - a)[:, 1] - (b - a)[:, 1] * (p - a)[:, 0]
        assert np.allclose(cross, 0.0, atol=1e-12 * domain.area)
    assert np.array_equal(mesh.boundary_patch, np.repeat(domain.boundary_patch, 2**level))
    # Boundary edges run with the domain on their left, as the cells do.
    directed = mesh.cells * mesh.n_points + np.roll(mesh.cells, -1, axis=1)
    listed = mesh.boundary_edges[:, 0] * mesh.n_points + mesh.boundary_edges[:, 1]
    assert np.isin(listed, directed).all()


def test_paper_numbering_single_pentagon():
    domain = Domain.from_polygon(SP)
    assert domain.mesh(1).cells.tolist() == PAPER_LEVEL_1
    assert domain.mesh(2).cells.tolist() == PAPER_LEVEL_2
    points = domain.mesh(1).points
    # The paper's program prints these for SP (X, Y of the FIFTH program's example).
    assert points[5:].tolist() == [
        [0.0, -1.0], [1.5, -0.5], [1.0, 0.5], [-1.0, 0.5], [-1.5, -0.5],
        [0.0, -0.6], [0.75, -0.35], [0.5, 0.15], [-0.5, 0.15], [-0.75, -0.35],
    ]  # fmt: skip


@pytest.mark.parametrize("level", [1, 2, 3, 4])
def test_numbering_matches_a_literal_transcription(level):
    domain = Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS)
    assert domain.mesh(level).cells.tolist() == paper_cells(domain.blocks.tolist(), level)


def test_refining_a_mesh_equals_refining_the_domain(catalogue):
    domain = catalogue["l-shape"]
    once, twice = domain.mesh(3), refine(refine(domain, 1), 2)
    for name in ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch"):
        assert np.array_equal(getattr(once, name), getattr(twice, name)), name
    assert twice.level == 3


def test_rcm_lowers_the_bandwidth(catalogue_domain):
    mesh = catalogue_domain.mesh(3)
    rcm = refine(catalogue_domain, 3, numbering="rcm")
    assert rcm.bandwidth() < mesh.bandwidth()
    assert rcm.area == pytest.approx(mesh.area, rel=1e-12)
    assert np.allclose(np.sort(rcm.points, axis=0), np.sort(mesh.points, axis=0))


def test_smoothing_keeps_the_mesh_valid_and_improves_angles(catalogue):
    for name in ("sp", "l-shape", "ring", "triangle"):
        domain = catalogue[name]
        plain, smooth = domain.mesh(4), domain.mesh(4, smooth=3)
        assert smooth.quality().not_strictly_convex == 0
        assert smooth.area == pytest.approx(domain.area, rel=1e-12)
        assert np.array_equal(smooth.cells, plain.cells)
        assert smooth.quality().min_angle >= plain.quality().min_angle
        # Block edges (and so the boundary) do not move.
        assert np.array_equal(
            smooth.points[smooth.boundary_edges], plain.points[plain.boundary_edges]
        )


def test_memory_guard_names_the_largest_level_that_fits(catalogue):
    domain = catalogue["square-cut"]
    with pytest.raises(
        ResourceError, match=r"level 9 of 'square-cut' needs about .* largest level that fits is 6"
    ):
        refine(domain, 9, max_memory=100_000_000)
    with pytest.raises(ResourceError, match="not even the unrefined mesh fits"):
        refine(domain, 2, max_memory=10)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"level": -1}, "level must be a whole number in 0..10000, got -1"),
        ({"level": 10**30}, "level must be a whole number in 0..10000"),
        ({"level": 1.5}, "level must be a whole number"),
        (
            {"level": 1, "numbering": "metis"},
            "unknown numbering 'metis'; choose one of: nested, rcm",
        ),
        ({"level": 1, "smooth": -2}, "smooth must be a whole number"),
    ],
)
def test_bad_arguments(kwargs, message):
    with pytest.raises(blockmesh.BlockMeshError, match=message):
        refine(Domain.from_polygon(SP), **kwargs)


def test_mesh_arrays_are_read_only(catalogue):
    mesh = catalogue["sp"].mesh(2)
    for array in (mesh.points, mesh.cells, mesh.block_id, mesh.parent, mesh.boundary_edges):
        with pytest.raises(ValueError):
            array[0] = 0


def test_from_cells_and_refine_of_a_plain_mesh():
    mesh = refine(Mesh.from_cells(np.array(SP), [[0, 1, 2, 3, 4]]), 3)
    assert mesh.n_cells == 216 and mesh.area == pytest.approx(5.0, rel=1e-14)


@pytest.mark.parametrize("threads", [1, 2])
def test_running_out_of_memory_is_a_resource_error(catalogue, monkeypatch, threads):
    # In a worker thread too: the failure reaches the caller, the other threads stop.
    import blockmesh.refinement.grouped as grouped

    def exhausted(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(grouped, "place_level", exhausted)
    with pytest.raises(ResourceError, match="ran out of memory refining joined-8 to level 3"):
        refine(catalogue["joined-8"], 3, threads=threads)
