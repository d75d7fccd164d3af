"""Splitting pentagons (tri5, tri3, quad5) and rebuilding them (blockmesh.io.pentagons)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers_io import tagged

import blockmesh.io as bio
from blockmesh.errors import ExportError
from blockmesh.geometry import signed_area
from blockmesh.io.pentagons import join_lines, merge_elements
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


def test_children_tile_their_parent(mesh: Mesh) -> None:
    for split in bio.SPLITS:
        s = bio.split_cells(mesh, split)
        area = signed_area(s.points[s.cells])
        assert np.all(area > 0), split
        np.testing.assert_allclose(
            np.bincount(s.parent, weights=area), mesh.cell_areas(), rtol=1e-12
        )


def test_quad5_is_conforming(mesh: Mesh) -> None:
    s = bio.split_cells(mesh, "quad5")
    n = s.points.shape[0]
    a, b = s.cells, np.roll(s.cells, -1, axis=1)
    _, counts = np.unique(np.minimum(a, b) * n + np.maximum(a, b), return_counts=True)
    lines = bio.split_boundary(mesh, "quad5").edges
    assert np.count_nonzero(counts == 1) == lines.shape[0]  # only the boundary halves are free
    assert set(np.unique(counts)) == {1, 2}
    assert np.unique(s.points, axis=0).shape[0] == n  # no duplicate nodes


def canonical(cells: np.ndarray) -> np.ndarray:
    """Each cell rotated to start at its smallest node id (the same polygon, same orientation)."""
    shift = np.argmin(cells, axis=1)
    return np.take_along_axis(cells, (np.arange(5) + shift[:, None]) % 5, axis=1)


@pytest.mark.parametrize("split", ["tri5", "tri3", "quad5"])
def test_merge_undoes_the_split(mesh: Mesh, split: str) -> None:
    s = bio.split_cells(mesh, split)
    fast = merge_elements(
        s.cells, s.parent, s.points, where="x", split=split, corner_nodes=mesh.n_points
    )
    np.testing.assert_array_equal(fast.cells, mesh.cells)
    assert fast.point_index is None  # the corners are exactly the first n_points nodes
    order = np.random.default_rng(1).permutation(s.cells.shape[0])  # any order: outlines
    slow = merge_elements(
        s.cells[order],
        s.parent[order],
        s.points,
        where="x",
        split=split,
        corner_nodes=mesh.n_points,
    )
    np.testing.assert_array_equal(canonical(slow.cells), canonical(mesh.cells))
    b = bio.split_boundary(mesh, split)
    joined, first = join_lines(b.edges, fast.is_corner, "x")
    assert {tuple(e) for e in joined.tolist()} == {tuple(e) for e in mesh.boundary_edges.tolist()}
    np.testing.assert_array_equal(b.patch[first], mesh.boundary_patch)


def test_merge_finds_corners_without_knowing_them(mesh: Mesh) -> None:
    """Without corner_nodes the corners are where the outline turns (not quad5's midpoints)."""
    s = bio.split_cells(mesh, "quad5")
    got = merge_elements(s.cells, s.parent, s.points, where="x")
    assert got.point_index is not None and got.point_index.size == mesh.n_points
    np.testing.assert_array_equal(got.point_index, np.arange(mesh.n_points))
    np.testing.assert_array_equal(got.cells, mesh.cells)


def test_elements_that_are_no_pentagon_are_refused(mesh: Mesh) -> None:
    s = bio.split_cells(mesh, "tri3")
    pentagon = s.parent.copy()
    pentagon[0], pentagon[3] = pentagon[3], pentagon[0]  # two triangles swap pentagons
    with pytest.raises(ExportError, match="do not form|not a pentagon"):
        merge_elements(
            s.cells, pentagon, s.points, where="x", split="tri3", corner_nodes=mesh.n_points
        )


def test_unknown_split(mesh: Mesh) -> None:
    with pytest.raises(ExportError, match="unknown split 'tri9'.*tri5, tri3 or quad5|split 'tri9'"):
        bio.split_cells(mesh, "tri9")


def test_a_tri3_fan_from_another_corner_is_merged_by_its_outline(mesh: Mesh) -> None:
    s = bio.split_cells(mesh, "tri3")
    cells = s.cells.copy()
    c = mesh.cells[0]
    cells[:3] = [[c[1], c[2], c[3]], [c[1], c[3], c[4]], [c[1], c[4], c[0]]]
    got = merge_elements(cells, s.parent, s.points, where="x", split="tri3")
    np.testing.assert_array_equal(canonical(got.cells), canonical(mesh.cells))


@pytest.mark.parametrize("split", ["tri5", "tri3", "quad5"])
def test_pentagons_in_another_order_keep_the_quick_merge(mesh: Mesh, split: str) -> None:
    """Whole pentagons shuffled (each one's elements still together, in order) are merged by
    the split itself, each back to its own id."""
    s = bio.split_cells(mesh, split)
    per = s.cells.shape[0] // mesh.n_cells
    shuffle = np.random.default_rng(2).permutation(mesh.n_cells)
    rows = (shuffle[:, None] * per + np.arange(per)).ravel()
    got = merge_elements(
        s.cells[rows], s.parent[rows], s.points, where="x", split=split, corner_nodes=mesh.n_points
    )
    np.testing.assert_array_equal(got.cells, mesh.cells)
    np.testing.assert_array_equal(got.first_element[shuffle], np.arange(mesh.n_cells) * per)
