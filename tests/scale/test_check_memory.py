"""The Mesh's boundary check works in bounded memory: every mesh read from a file runs it."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import blockmesh
from blockmesh.errors import TopologyError
from blockmesh.topology import boundary_slots, cell_neighbours, check_boundary


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
