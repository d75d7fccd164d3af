"""The numpy paths for small graphs and point sets give what scipy gives."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

import blockmesh.domain.validate as validate
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
    pairs = validate.close_pairs(points, 0.15)
    expected = cKDTree(points).query_pairs(r=0.15, output_type="ndarray")
    assert sorted(map(tuple, pairs.tolist())) == sorted(map(tuple, np.sort(expected, 1).tolist()))
