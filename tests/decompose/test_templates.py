"""Templates and pieces: ring-and-hub templates, shared side nodes, merged quadrilaterals."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import assume, given
from hypothesis import strategies as st

from blockmesh.decompose.merge import pair_triangles
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.templates import (
    EDGE_FRACTIONS,
    TRIANGLE_FACES,
    TRIANGLE_WEIGHTS,
    ring_hub_faces,
    ring_hub_nodes,
)
from blockmesh.geometry import interior_angles, is_strictly_convex, signed_area


def regular(n: int) -> np.ndarray:
    t = 2 * np.pi * np.arange(n) / n
    return np.column_stack([np.cos(t), np.sin(t)])


def test_edge_fractions_are_symmetric():
    a, b = EDGE_FRACTIONS
    assert a + b == 1.0 and a == pytest.approx(0.335645)


@given(st.lists(st.tuples(st.floats(-5, 5), st.floats(-5, 5)), min_size=3, max_size=3))
def test_the_ring_and_hub_triangle_is_the_triangle_template(points):
    triangle = np.array(points)
    area = signed_area(triangle)
    assume(abs(area) > 1e-3)
    if area < 0:
        triangle = triangle[::-1]
    ring = ring_hub_nodes(triangle[None])[0]
    plain = TRIANGLE_WEIGHTS @ triangle
    # The same 19 points and the same 9 faces, numbered differently.
    order = [np.flatnonzero(np.all(np.isclose(plain, p, atol=1e-12), axis=1)) for p in ring]
    assert all(len(o) == 1 for o in order)
    mapping = np.array([o[0] for o in order])
    faces = {tuple(np.roll(f, -int(np.argmin(f)))) for f in mapping[ring_hub_faces(3)]}
    expected = {tuple(np.roll(f, -int(np.argmin(f)))) for f in TRIANGLE_FACES}
    assert faces == expected


@pytest.mark.parametrize("n", [3, 4, 5, 6, 7, 8])
def test_ring_and_hub_of_regular_polygons(n):
    polygon = regular(n)
    nodes = ring_hub_nodes(polygon[None])[0]
    faces = ring_hub_faces(n)
    assert faces.shape == (3 * n, 5) and nodes.shape == (6 * n + 1, 2)
    assert np.all(is_strictly_convex(nodes[faces]))
    assert signed_area(nodes[faces]).sum() == pytest.approx(signed_area(polygon), rel=1e-12)
    # 3F = (n - 2) + K + 2 N_i with K = 2n side nodes and N_i = 3n + 1 inner nodes.
    assert 3 * faces.shape[0] == (n - 2) + 2 * n + 2 * (3 * n + 1)
    angles = interior_angles(nodes[faces])
    assert angles.min() > 40 and angles.max() < 160


def test_pieces_share_their_side_nodes_bit_for_bit():
    points = np.array([[0, 0], [1, 0], [1.2, 1], [0, 1], [2, 0.3], [2.1, 1.4]], dtype=float)
    groups = [np.array([[1, 4, 2]]), np.array([[0, 1, 2, 3]]), np.array([[2, 4, 5]])]
    result = pentagons_from_pieces(points, groups)
    assert result.blocks.shape[0] == 9 + 12 + 9
    assert np.array_equal(result.nodes[: len(points)], points)
    # Edge to edge: each directed block edge once, interior ones twice in opposite directions.
    b = result.blocks
    edges = set(zip(b.ravel().tolist(), np.roll(b, -1, axis=1).ravel().tolist(), strict=True))
    assert len(edges) == b.size
    boundary = {e for e in edges if e[::-1] not in edges}
    outer = shapely.Polygon(points[[0, 1, 4, 5, 2, 3]])
    union = shapely.union_all(shapely.polygons(result.nodes[b]))
    assert union.symmetric_difference(outer).area < 1e-12
    assert len(boundary) == 6 * 3  # 6 outer sides, 3 block edges each
    chain = result.side_chain(1, 2)
    assert chain.tolist() == result.side_chain(2, 1)[::-1].tolist()
    f1, f2 = EDGE_FRACTIONS
    np.testing.assert_allclose(
        result.nodes[chain[1:3]], [points[1] + f * (points[2] - points[1]) for f in (f1, f2)]
    )


def test_pairs_make_round_convex_quadrilaterals():
    side = np.linspace(0, 1, 5)
    x, y = np.meshgrid(side, side)
    points = np.column_stack([x.ravel(), y.ravel()])
    triangles = []
    for i in range(4):
        for j in range(4):
            a, b, c, d = 5 * i + j, 5 * i + j + 1, 5 * (i + 1) + j + 1, 5 * (i + 1) + j
            triangles += [[a, b, c], [a, c, d]]
    quads, rest = pair_triangles(points, np.array(triangles))
    assert quads.shape[0] * 2 + rest.shape[0] == 32
    assert quads.shape[0] == 16  # every square found again
    assert np.all(is_strictly_convex(points[quads]))
    assert interior_angles(points[quads]).max() < 150
