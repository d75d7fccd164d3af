"""Moving free nodes: the worst never worse, always convex, fixed nodes fixed, sliders on line."""

from __future__ import annotations

import numpy as np
from helpers import examples
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from blockmesh.decompose.optimise import improve_angles, worst_score
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.geometry import is_strictly_convex, signed_area
from blockmesh.geometry.polygons import corner_sines


def jittered_grid(seed_values):
    side = np.linspace(0, 1, 4)
    x, y = np.meshgrid(side, side)
    points = np.column_stack([x.ravel(), y.ravel()])
    inner = [5, 6, 9, 10]
    points[inner] += 0.12 * np.array(seed_values).reshape(4, 2)
    triangles = []
    for i in range(3):
        for j in range(3):
            a, b, c, d = 4 * i + j, 4 * i + j + 1, 4 * (i + 1) + j + 1, 4 * (i + 1) + j
            triangles += [[a, b, c], [a, c, d]]
    return points, np.array(triangles)


@settings(max_examples=examples(40))
@given(st.lists(st.floats(-1, 1), min_size=8, max_size=8))
def test_moves_never_make_any_block_worse_or_non_convex(jitter):
    points, triangles = jittered_grid(jitter)
    assume(np.all(signed_area(points[triangles]) > 1e-3))  # a triangulation to start from
    pieces = pentagons_from_pieces(points, [triangles])
    nodes, blocks = pieces.nodes, pieces.blocks
    fixed = np.zeros(len(nodes), dtype=bool)
    fixed[:16] = True
    slide = np.zeros_like(nodes)
    bottom = pieces.side_chains(np.array([0, 1, 2]), np.array([1, 2, 3]))
    slide[bottom[:, 1:3].ravel()] = [1.0, 0.0]
    fixed[bottom[:, 1:3].ravel()] = False
    moved = improve_angles(nodes, blocks, fixed, slide=slide, target=60.0)
    assert np.all(is_strictly_convex(moved[blocks]))
    assert np.array_equal(moved[fixed], nodes[fixed])
    assert np.all(moved[bottom[:, 1:3].ravel(), 1] == 0.0)  # the sliders stay on y = 0
    # A move is kept only if the worst block around the mover gets better, so no block ever
    # drops below the worst score there was.
    assert worst_score(moved, blocks) >= worst_score(nodes, blocks)


def test_an_edge_collapsed_to_an_ulp_counts_as_a_fold():
    # A node stepped onto its neighbour along their edge leaves the edge an ulp long but with
    # its old direction: every corner still turns (and scores) as before, yet the block is a
    # quadrilateral with one point listed twice. It scores -inf, as a folded block does.
    pentagon = np.array([[0.0, 0.0], [1.0, 0.0], [1.2, 0.6], [0.5, 1.0], [-0.2, 0.6]])
    collapsed = pentagon.copy()
    collapsed[0, 0] = np.nextafter(1.0, 0.0)
    block = np.arange(5)[None]
    for xy in (pentagon, collapsed):
        assert np.all(corner_sines(xy[None]) > 1e-3)
    assert np.isfinite(worst_score(pentagon, block))
    assert worst_score(collapsed, block) == -np.inf


def test_nothing_to_do_returns_a_copy():
    points, triangles = jittered_grid([0.0] * 8)
    pieces = pentagons_from_pieces(points, [triangles])
    fixed = np.ones(len(pieces.nodes), dtype=bool)
    moved = improve_angles(pieces.nodes, pieces.blocks, fixed)
    assert np.array_equal(moved, pieces.nodes) and moved is not pieces.nodes
