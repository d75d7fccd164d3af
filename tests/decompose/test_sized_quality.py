"""The size-driven decomposition's angle levers: the triangle smoothing and the capped optimiser."""

from __future__ import annotations

import numpy as np
from helpers import examples
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from test_optimise import jittered_grid

from blockmesh.decompose.optimise import WorstAngle, improve_angles, worst_score
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.sized_angles import SIZE_CAP, SizedAngles
from blockmesh.decompose.triangle_quality import (
    MERGE_BELOW,
    SIDE_CAP,
    _angles,
    _longest,
    _min_angles,
    _smooth,
    _triangles,
    raise_triangle_angles,
    worst_triangle_angle,
)
from blockmesh.geometry import is_strictly_convex, signed_area
from blockmesh.refinement.placement import Freedom
from blockmesh.sizing.measure import cell_diameters


def unit_square(xy: np.ndarray) -> np.ndarray:
    return np.all((xy > 0) & (xy < 1), axis=1)


def square_outline(per_side: int) -> np.ndarray:
    t = np.arange(per_side) / per_side
    return np.vstack(
        [
            np.column_stack([t, 0 * t]),
            np.column_stack([0 * t + 1, t]),
            np.column_stack([1 - t, 0 * t + 1]),
            np.column_stack([0 * t, 1 - t]),
        ]
    )


@settings(max_examples=examples(30), deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_smoothing_raises_the_worst_angle_and_keeps_the_fixed_points(seed):
    rng = np.random.default_rng(seed)
    fixed = square_outline(6)
    free = 0.1 + 0.8 * rng.random((20, 2))
    before = worst_triangle_angle(np.vstack([fixed, free]), unit_square)
    moved = raise_triangle_angles(fixed, free, unit_square)
    after = worst_triangle_angle(np.vstack([fixed, moved]), unit_square)
    assert moved.shape == free.shape
    assert np.all(unit_square(moved))
    # Every accepted move raises the worst angle around the mover and touches no other
    # triangle's worst; the triangulation made again can only do better (Delaunay maximises
    # the smallest angle over the triangulations of the points).
    assert after >= before - 1e-9


def test_a_crowded_square_corner_is_merged_to_two_triangles():
    fixed = square_outline(4)
    # Two free points near the corner (0, 0), at 30 and 60 degrees: three triangles there.
    free = np.array(
        [[0.25 * np.cos(a), 0.25 * np.sin(a)] for a in np.radians([30, 60])] + [[0.6, 0.6]]
    )
    points = np.vstack([fixed, free])
    fan = np.any(_triangles(points, unit_square) == 0, axis=1)
    assert fan.sum() == 3 and MERGE_BELOW > 90.0 / 3
    merged = raise_triangle_angles(fixed, free, unit_square, merge=True)
    points = np.vstack([fixed, merged])
    tri = _triangles(points, unit_square)
    angles, _ = _angles(points[tri])
    at_corner = angles[tri == 0]
    assert len(merged) == len(free) - 1
    assert len(at_corner) == 2 and at_corner.min() > MERGE_BELOW


def test_without_merge_the_points_are_as_many():
    fixed = square_outline(4)
    free = np.array([[0.2, 0.1], [0.1, 0.2], [0.6, 0.6]])
    assert len(raise_triangle_angles(fixed, free, unit_square)) == 3


@settings(max_examples=examples(30), deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=8, max_size=8), st.floats(0.3, 0.6))
def test_a_limit_on_the_diameters_is_never_passed(jitter, size):
    points, triangles = jittered_grid(jitter)
    assume(np.all(signed_area(points[triangles]) > 1e-3))
    pieces = pentagons_from_pieces(points, [triangles])
    nodes, blocks = pieces.nodes, pieces.blocks
    fixed = np.arange(len(nodes)) < 16
    diameters = cell_diameters(nodes, blocks)
    limits = np.maximum(size * np.ones(len(blocks)), diameters)
    moved = improve_angles(nodes, blocks, fixed, target=70.0, limits=limits)
    assert np.all(cell_diameters(moved, blocks) <= limits)
    assert np.all(is_strictly_convex(moved[blocks]))
    assert worst_score(moved, blocks) >= worst_score(nodes, blocks)


@settings(max_examples=examples(20), deadline=None)
@given(st.lists(st.floats(-1, 1), min_size=8, max_size=8), st.floats(0.15, 0.4))
def test_sized_angles_keep_cells_within_the_cap_they_met(jitter, size):
    points, triangles = jittered_grid(jitter)
    pieces = pentagons_from_pieces(points, [triangles])
    nodes, blocks = pieces.nodes, pieces.blocks
    assume(np.all(signed_area(points[triangles]) > 1e-3))
    fixed = np.arange(len(nodes)) < 16
    sizes = np.full(len(blocks), size)
    freedom = Freedom(fixed, np.zeros_like(nodes))
    first = SizedAngles(target=45.0, sizes=sizes).place(nodes, blocks, freedom)
    assert np.all(is_strictly_convex(first[blocks]))
    assert np.array_equal(first[fixed], nodes[fixed])
    # The second pass lets no cell grow beyond the cap unless it was beyond it already.
    sized_only = WorstAngle(45.0, 5, sizes).place(nodes, blocks, freedom)
    allowed = np.maximum(SIZE_CAP * sizes, cell_diameters(sized_only, blocks))
    assert np.all(cell_diameters(first, blocks) <= allowed * (1 + 1e-12))


@settings(max_examples=examples(20), deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.2, 0.5))
def test_with_the_side_wanted_no_triangle_grows_past_the_cap(seed, side):
    rng = np.random.default_rng(seed)
    fixed = square_outline(5)
    points = np.vstack([fixed, 0.1 + 0.8 * rng.random((15, 2))])
    tri = _triangles(points, unit_square)
    before = _longest(points[tri])
    worst_before = _min_angles(points[tri]).min()
    wanted = np.full(len(points), side)
    mobile = np.arange(len(points)) >= len(fixed)
    _smooth(points, mobile, tri, unit_square, wanted)  # moves the points in place
    after = _longest(points[tri])
    # On the triangulation it was given, no triangle passes the cap (or its length before),
    # none folds, and the worst angle is no worse.
    assert np.all(after <= np.maximum(SIDE_CAP * side, before) * (1 + 1e-12))
    assert _min_angles(points[tri]).min() >= worst_before
    assert np.array_equal(points[: len(fixed)], fixed)
