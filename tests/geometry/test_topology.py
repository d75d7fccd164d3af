"""The topology primitives on random meshes: neighbours, boundaries, loops and pieces agree."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE, examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.errors import TopologyError
from blockmesh.geometry.topology import (
    boundary_loops,
    boundary_of_cells,
    boundary_slots,
    cell_neighbours,
    connected_pieces,
    count_loops,
    edge_index,
    edge_keys,
    unique_edges,
)


def _grid_triangles(nx: int, ny: int) -> tuple[np.ndarray, int]:
    """A structured triangulation of an nx × ny grid (counter-clockwise triangles)."""
    ids = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    a, b, c, d = ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]
    cells = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return cells, ids.size


@given(st.integers(1, 6), st.integers(1, 6))
@settings(max_examples=examples(30))
def test_neighbours_are_symmetric_and_count_the_interior_edges(nx, ny):
    cells, n = _grid_triangles(nx, ny)
    nb = cell_neighbours(cells, n)
    flat = nb.ravel()
    shared = np.flatnonzero(flat >= 0)
    assert np.array_equal(flat[flat[shared]], shared)  # the facing slot faces back
    keys = edge_keys(cells, np.roll(cells, -1, axis=1), n).ravel()
    assert np.array_equal(keys[shared], keys[flat[shared]])
    edges = unique_edges(cells, n)
    interior = nx * (ny - 1) + ny * (nx - 1) + nx * ny
    assert edges.shape[0] == interior + 2 * (nx + ny)
    assert shared.size == 2 * interior


@given(st.integers(1, 6), st.integers(1, 6))
@settings(max_examples=examples(30))
def test_boundary_is_one_closed_loop_around_a_grid(nx, ny):
    cells, n = _grid_triangles(nx, ny)
    nb = cell_neighbours(cells, n)
    loop = boundary_loops(cells, nb)
    assert loop.shape[0] == 2 * (nx + ny)
    assert np.array_equal(loop[1:, 0], loop[:-1, 1]) and loop[-1, 1] == loop[0, 0]
    assert count_loops(loop) == 1
    slots = boundary_slots(cells, nb, loop, n)
    assert np.all(nb.ravel()[slots] == -1)
    assert sorted(map(tuple, boundary_of_cells(cells, n))) == sorted(map(tuple, loop))


def test_edge_index_maps_every_slot_to_its_edge():
    cells, n = _grid_triangles(3, 2)
    keys, slot_edge = edge_index(cells, n)
    a, b = np.divmod(keys[slot_edge], n)
    nxt = np.roll(cells, -1, axis=1)
    assert np.array_equal(np.minimum(cells, nxt), a) and np.array_equal(np.maximum(cells, nxt), b)


def test_pieces_and_loops_of_two_separate_squares():
    cells = np.array([[0, 1, 2, 3], [4, 5, 6, 7]])
    nb = cell_neighbours(cells, 8)
    count, label = connected_pieces(nb)
    assert count == 2 and label[0] != label[1]
    assert count_loops(boundary_of_cells(cells, 8)) == 2


def test_an_edge_in_three_cells_is_named():
    with pytest.raises(TopologyError, match=r"edge \(0, 1\) belongs to three or more cells"):
        cell_neighbours(np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]]), 5)


@pytest.mark.parametrize("name", CATALOGUE)
def test_refined_catalogue_meshes_have_consistent_topology(name):
    mesh = blockmesh.load_domain(name).mesh(2)
    nb = cell_neighbours(mesh.cells, mesh.n_points)
    slots = boundary_slots(mesh.cells, nb, mesh.boundary_edges, mesh.n_points)
    assert slots.size == mesh.boundary_edges.shape[0] == np.count_nonzero(nb < 0)
    assert unique_edges(mesh.cells, mesh.n_points).shape[0] == mesh.n_edges
    holes = count_loops(mesh.boundary_edges) - connected_pieces(nb)[0]
    euler = mesh.n_points - mesh.n_edges + mesh.n_cells
    assert euler == 1 - holes
