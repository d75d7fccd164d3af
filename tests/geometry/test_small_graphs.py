"""The numpy paths for small graphs and point sets give what scipy gives."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

import blockmesh.domain.validate.points as validate_points
import blockmesh.geometry.topology as topology


@pytest.mark.parametrize("seed", range(20))
def test_graph_components_equal_scipy(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 400))
    m = int(rng.integers(0, 2 * n))
    a, b = rng.integers(0, n, m), rng.integers(0, n, m)
    count, label = topology.graph_components(n, a, b)
    graph = coo_matrix((np.ones(m), (a, b)), shape=(n, n))
    expected_count, expected = connected_components(graph, directed=False)
    assert count == expected_count
    np.testing.assert_array_equal(label, expected)


def test_graph_components_long_path():
    n = topology._SMALL_GRAPH
    order = np.random.default_rng(0).permutation(n)
    count, label = topology.graph_components(n, order[:-1], order[1:])
    assert count == 1 and not label.any()


@pytest.mark.parametrize("seed", range(10))
def test_close_pairs_equal_kdtree(seed):
    rng = np.random.default_rng(seed)
    points = rng.integers(0, 30, (int(rng.integers(2, 700)), 2)) * 0.1
    pairs = validate_points.close_pairs(points, 0.15)
    expected = cKDTree(points).query_pairs(r=0.15, output_type="ndarray")
    assert sorted(map(tuple, pairs.tolist())) == sorted(map(tuple, np.sort(expected, 1).tolist()))


@pytest.mark.parametrize("seed", range(10))
def test_swept_close_pairs_equal_kdtree(seed):
    # Above the brute-force size: the sweep along x (points on a grid share x coordinates).
    rng = np.random.default_rng(seed)
    n = validate_points._BRUTE_FORCE_POINTS + int(rng.integers(1, 2000))
    points = rng.integers(0, 300, (n, 2)) * 0.01 + rng.normal(0, 1e-4, (n, 2))
    r = float(rng.uniform(1e-4, 3e-3))
    swept = validate_points._swept_pairs(points, r)
    expected = cKDTree(points).query_pairs(r=r, output_type="ndarray")
    assert swept is not None
    assert sorted(map(tuple, swept.tolist())) == sorted(map(tuple, np.sort(expected, 1).tolist()))
    same = validate_points.close_pairs(points, r)
    assert sorted(map(tuple, np.sort(same, 1).tolist())) == sorted(map(tuple, swept.tolist()))


def test_close_pairs_crowded_in_x_falls_back_to_the_tree():
    # Every point within r in x of every other: the sweep would compare n^2 / 2 pairs.
    n = validate_points._BRUTE_FORCE_POINTS + 10
    points = np.column_stack([np.zeros(n), np.arange(n, dtype=float)])
    assert validate_points._swept_pairs(points, 0.5) is None
    assert validate_points.close_pairs(points, 1.0).shape == (n - 1, 2)


def test_close_pairs_crowded_in_x_below_the_tree_size_compare_all_pairs():
    # A few hundred points within r of one another in x: the sweep gives up, and all pairs are
    # compared (no k-d tree, so scipy.spatial stays unimported for ordinary domains).
    n = 300
    points = np.column_stack([np.zeros(n), np.arange(n, dtype=float)])
    assert validate_points._swept_pairs(points, 0.5) is None
    pairs = validate_points.close_pairs(points, 1.0)
    assert sorted(map(tuple, pairs.tolist())) == [(k, k + 1) for k in range(n - 1)]
