"""The Mesh's boundary check works in bounded memory: every mesh read from a file runs it."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.errors import TopologyError
from blockmesh.geometry.topology import boundary_slots, cell_neighbours, check_boundary


def test_check_boundary_peak_is_below_the_mesh():
    mesh = blockmesh.refine(blockmesh.load_domain("joined-2"), 7)  # many chunks
    tracemalloc.start()
    try:
        check_boundary(mesh.cells, mesh.boundary_edges, mesh.n_points)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    # one int64 key and two flags per cell side: 50 of the mesh's 88 bytes per cell
    assert peak < 0.7 * mesh.nbytes()


def test_check_boundary_agrees_with_boundary_slots_across_chunks():
    mesh = blockmesh.refine(blockmesh.load_domain("ring"), 5)
    cells, edges, n = mesh.cells, mesh.boundary_edges, mesh.n_points
    check_boundary(cells, edges, n)
    boundary_slots(cells, cell_neighbours(cells, n), edges, n)
    rng = np.random.default_rng(0)
    for _ in range(5):
        broken = edges.copy()
        row = int(rng.integers(edges.shape[0]))
        broken[row] = broken[row, ::-1]  # against its cell's direction
        with pytest.raises(TopologyError, match=f"boundary edge {row} "):
            check_boundary(cells, broken, n)
        with pytest.raises(TopologyError, match=f"boundary edge {row} "):
            boundary_slots(cells, cell_neighbours(cells, n), broken, n)


def _verdict(check, *args) -> str:
    try:
        check(*args)
    except TopologyError as error:
        message = str(error)
        return message.split(" (")[0] if message.startswith("boundary edge ") else message[:40]
    return "ok"


@settings(max_examples=examples(40))
@given(
    st.sampled_from(["ring", "lake-island", "square-cut", "annulus"]),
    st.sampled_from(["none", "reverse", "interior", "interior reversed", "twice", "drop"]),
    st.integers(0, 2**32 - 1),
)
def test_check_boundary_gives_the_verdict_of_boundary_slots(name, change, seed):
    """Listed boundaries broken in every way a file can break them, against the reference."""
    mesh = blockmesh.load_domain(name).mesh(2)
    cells, n = mesh.cells, mesh.n_points
    neighbour = cell_neighbours(cells, n)
    edges = mesh.boundary_edges.copy()
    rng = np.random.default_rng(seed)
    row = int(rng.integers(edges.shape[0]))
    if change == "reverse":
        edges[row] = edges[row, ::-1]
    elif change.startswith("interior"):
        cell, side = np.argwhere(neighbour >= 0)[int(rng.integers(np.sum(neighbour >= 0)))]
        edges[row] = cells[cell, side], cells[cell, (side + 1) % 5]
        if change.endswith("reversed"):
            edges[row] = edges[row, ::-1]
    elif change == "twice":
        edges[row] = edges[(row + 1) % edges.shape[0]]
    elif change == "drop":
        edges = np.delete(edges, row, axis=0)
    expected = _verdict(boundary_slots, cells, neighbour, edges, n)
    assert _verdict(check_boundary, cells, edges, n) == expected
    assert (expected == "ok") == (change == "none")


def test_check_boundary_when_every_node_is_on_the_boundary():
    """Cells that touch nothing (all their sides free): the directions of every slot count."""
    pentagon = np.array([[0, 0], [2, 0], [3, 1], [1, 3], [-1, 1]], dtype=float)
    points = np.concatenate([pentagon, pentagon + 10.0])
    cells = np.array([[0, 1, 2, 3, 4], [5, 6, 7, 8, 9]])
    edges = np.stack([cells.ravel(), np.roll(cells, -1, axis=1).ravel()], axis=1)
    mesh = blockmesh.Mesh.from_cells(points, cells)  # the constructor's check runs too
    assert np.array_equal(np.sort(mesh.boundary_edges, axis=0), np.sort(edges, axis=0))
    assert _verdict(check_boundary, cells, edges, 10) == "ok"
    broken = edges.copy()
    broken[7] = broken[7, ::-1]
    assert _verdict(check_boundary, cells, broken, 10) == "boundary edge 7"
    assert _verdict(boundary_slots, cells, cell_neighbours(cells, 10), broken, 10) == (
        "boundary edge 7"
    )
