"""Quality triangulation: a valid triangulation of the polygon, refined towards the target angle."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from helpers import examples, polygon_with_holes
from hypothesis import HealthCheck, given, settings

from blockmesh.decompose.triangulate import triangulate
from blockmesh.domain.validate.rings import check_rings
from blockmesh.errors import ResourceError
from blockmesh.geometry import interior_angles, local_frame, signed_area


def rings_of(outer, holes):
    checked = check_rings([np.asarray(outer, float), *(np.asarray(h, float) for h in holes)])
    frame = local_frame(np.vstack([r.points for r in checked]))
    return [frame.to_local(r.points) for r in checked]


def assert_triangulates(t, rings):
    polygon = shapely.Polygon(rings[0], rings[1:])
    xy = t.points[t.triangles]
    areas = signed_area(xy)
    assert np.all(areas > 0)
    assert abs(areas.sum() - polygon.area) <= 1e-12 * polygon.area + 1e-15
    union = shapely.coverage_union_all(shapely.polygons(xy))
    assert union.symmetric_difference(polygon).area <= 1e-12
    # Each directed edge once; the unmatched ones are exactly the segments.
    e = np.concatenate([t.triangles[:, [0, 1]], t.triangles[:, [1, 2]], t.triangles[:, [2, 0]]])
    directed = set(map(tuple, e.tolist()))
    assert len(directed) == len(e)
    boundary = {d for d in directed if d[::-1] not in directed}
    assert boundary == set(map(tuple, t.segments.tolist()))
    # The ring vertices come first, unchanged; every segment lies on the ring edge it names.
    corners = np.vstack(rings)
    assert np.array_equal(t.points[: len(corners)], corners)
    starts = np.concatenate([[0], np.cumsum([len(r) for r in rings])[:-1]])
    ring_of = np.searchsorted(starts, t.segment_edge, side="right") - 1
    a = corners[t.segment_edge]
    nxt = (
        starts[ring_of]
        + (t.segment_edge - starts[ring_of] + 1) % np.array([len(r) for r in rings])[ring_of]
    )
    b = corners[nxt]
    for p in (t.points[t.segments[:, 0]], t.points[t.segments[:, 1]]):
        cross = (b - a)[:, 0] * (p - a)[:, 1] - (b - a)[:, 1] * (p - a)[:, 0]
        assert np.all(np.abs(cross) <= 1e-12 * np.hypot(*(b - a).T))


@settings(max_examples=examples(30), suppress_health_check=[HealthCheck.too_slow])
@given(polygon_with_holes(n_max=120))
def test_random_polygons_triangulate(case):
    rings = rings_of(*case)
    t = triangulate(rings)
    assert_triangulates(t, rings)


def test_refinement_reaches_the_target_angle():
    outer = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    holes = [[(0.3, 0.3), (0.6, 0.3), (0.6, 0.6), (0.3, 0.6)], [(1.3, 0.4), (1.7, 0.4), (1.5, 0.7)]]
    rings = rings_of(outer, holes)
    plain = triangulate(rings, min_angle=0)
    assert plain.triangles.shape[0] == 13 + 2 * 2 - 2  # no point added: n + 2h - 2 triangles
    assert plain.min_angle() < 15
    for target in (22.0, 30.0, 33.0):
        refined = triangulate(rings, min_angle=target)
        assert refined.min_angle() >= target
        assert_triangulates(refined, rings)
    assert triangulate(rings).min_angle() >= 22.0


def test_sharp_corners_and_slivers_are_left_within_budget():
    # A 1:1e8 sliver cannot be repaired within any budget: it stays as it is, valid.
    sliver = rings_of([(0, 0), (1, 0), (0.5, 1e-8)], [])
    t = triangulate(sliver)
    assert t.points.shape[0] <= 10
    assert_triangulates(t, sliver)
    # A 5-degree wedge: the corner triangle keeps the domain's own angle, the rest is fine.
    wedge = rings_of([(0, 0), (1, 0), (np.cos(np.radians(5)), np.sin(np.radians(5)))], [])
    t = triangulate(wedge)
    angles = interior_angles(t.points[t.triangles])
    assert angles.min() == pytest.approx(5.0, abs=1e-6)
    assert_triangulates(t, wedge)


def test_budget_bounds_the_points_added():
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    ring = rings_of(np.column_stack([np.cos(t), np.sin(t) * 0.05]), [])
    for budget in (0, 10, 100):
        assert triangulate(ring, max_points=budget).points.shape[0] <= 400 + budget


def test_a_shapely_without_constrained_delaunay_is_named_in_the_error(monkeypatch):
    # shapely 2.0 has no constrained_delaunay_triangles (2.1 does): a decomposed catalogue domain
    # then failed with an AttributeError from inside the decomposition.
    import blockmesh

    monkeypatch.delattr(shapely, "constrained_delaunay_triangles")
    monkeypatch.setattr(shapely, "__version__", "2.0.7")
    with pytest.raises(ResourceError, match=r"needs shapely >= 2\.1 .* this is shapely 2\.0\.7"):
        blockmesh.load_domain("backward-step")
