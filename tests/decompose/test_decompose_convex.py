"""Tests of :mod:`blockmesh.decompose.convex`: convex polygons split into strictly convex pentagons.

The property tests check, on random convex polygons (skinny ones included), everything a conforming
block mesh needs: exact tiling, strictly convex counter-clockwise pentagons, edge-to-edge contact
(no hanging nodes), boundary chains, block counts and the reported angles.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import shapely
from helpers import examples
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

import blockmesh.decompose.convex as decompose
import blockmesh.decompose.templates as templates
from blockmesh.decompose import Decomposition, decompose_convex_polygon, decompose_polygon
from blockmesh.errors import DomainError
from blockmesh.geometry import (
    corner_sines,
    interior_angles,
    is_strictly_convex,
    polygon_diameter,
    signed_area,
)

REL = 1e-12
PAPER_HEXAGON = np.array([[0.1, 0], [0.7, 0.2], [1, 0.5], [0.75, 0.85], [0.5, 1], [0, 0.25]])
#: Spacings of doubles (at the polygon's largest coordinate) by which every corner of a polygon
#: stands clear of the chord of its neighbours, above which no layout is refused as too thin for
#: where it sits: block corners must stand 16 spacings clear of theirs (STRAIGHT_ULPS), and they
#: stand at least 0.0075 of the polygon's clearance off in the triangle template (its corners'
#: smallest area share; 0.05 measured), 0.06 measured in the quadrilateral template and 0.5 in
#: the chord and star layouts (a midpoint halves a corner's clearance).
CLEAR = 3000
#: Sliver triangles from the unit circle (angles 0, 1e-9 and 1e-5): 1e-5 long, 5e-15 wide, so
#: 22 spacings of doubles wide at x = 1 and 11 at x = 2.5. Their blocks stood 2 spacings off
#: their chords (a mesh reads that as a straight vertex, a hanging node) and, at 2.5, one folded.
SLIVER_AT_1 = np.array([[1.0, 0.0], [1.0, 1e-09], [0.99999999995, 9.999999999833334e-06]])
SLIVER_AT_2_5 = np.array([[2.5, 0.0], [2.5, 1e-09], [2.49999999995, 9.999999999833334e-06]])
#: Another from the unit circle (angles 0, 1e-9, 1.19e-7), whose blocks fold when rounded back.
SLIVER_FOLDS = np.column_stack(
    [np.cos([0.0, 1e-9, 1.1920929e-07]), np.sin([0.0, 1e-9, 1.1920929e-07])]
)
#: A slab 1e-5 by 1e-14 at (1, 1): 45 spacings thick.
SLAB_AT_1 = 1.0 + np.array([[0.0, 0.0], [1e-5, 0.0], [1e-5, 1e-14], [0.0, 1e-14]])


def regular(n: int) -> np.ndarray:
    t = 2 * np.pi * np.arange(n) / n
    return np.column_stack([np.cos(t), np.sin(t)])


def meets_contract(polygon: np.ndarray) -> bool:
    """Counter-clockwise, strictly convex, no edge shorter than 1e-11 times the diameter."""
    edges = np.hypot(*(np.roll(polygon, -1, axis=0) - polygon).T)
    return bool(is_strictly_convex(polygon)) and edges.min() > 1e-11 * polygon_diameter(polygon)


def clearance(polygon: np.ndarray) -> float:
    """Smallest distance of a corner from the chord of its neighbours, in spacings of doubles."""
    inc = polygon - np.roll(polygon, 1, axis=0)
    out = np.roll(polygon, -1, axis=0) - polygon
    cross = np.abs(inc[:, 0] * out[:, 1] - inc[:, 1] * out[:, 0])
    off = cross / np.hypot(*(inc + out).T)
    return float(off.min() / np.spacing(np.abs(polygon).max()))


def assume_template_room(polygon: np.ndarray) -> None:
    """Triangles and quadrilaterals with corners of sine above 1e-10.

    Templates need a little room: a corner of sine 1e-12 (the contract's limit) can leave
    template corners below it (see test_too_thin_polygon_raises), or just above it, with blocks
    so thin (a quadrilateral with a corner of sine 2.3e-12: blocks 1e-13 thick, 0.2 long) that
    assert_valid's relative tolerance (1e-12 of an edge's length) takes a vertex for a hanging
    node on the next block's edge. And every corner must stand clear of its neighbours' chord in
    doubles: a corner 1.1e-16 off it (sine 2.2e-10 along edges 1e-6 long, coordinates near 1, as
    the ci profile drew) leaves a template corner no double can place off its chord, which the
    decomposition refuses ("too thin for where it sits").
    """
    if len(polygon) <= 4:
        assume(corner_sines(polygon).min() > 1e-10)
        before, after = np.roll(polygon, 1, axis=0), np.roll(polygon, -1, axis=0)
        u, w = polygon - before, after - before
        offset = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / np.hypot(w[:, 0], w[:, 1])
        assume(offset.min() > 256 * np.spacing(np.abs(polygon).max()))


def expected_blocks(n: int) -> int:
    return {3: 9, 4: 8, 5: 1}.get(n, math.ceil((n - 2) / 3))


def chord_score(polygon: np.ndarray) -> float:
    """Score of the best chord layout alone (the worst corner the chords create or split)."""
    return decompose._chord_layout(polygon, expected_blocks(len(polygon))).score


def assert_valid(polygon: np.ndarray, d: Decomposition) -> None:
    """Every property a conforming decomposition of ``polygon`` must have."""
    n = len(polygon)
    v, b = d.vertices, d.blocks
    assert v.dtype == np.float64 and v.ndim == 2 and v.shape[1] == 2
    assert b.dtype == np.int64 and b.shape == (expected_blocks(n), 5)
    assert not v.flags.writeable and not b.flags.writeable
    assert all(not c.flags.writeable for c in d.edge_chains)
    assert v[:n].tobytes() == polygon.tobytes()  # the polygon's vertices, bit for bit
    assert np.array_equal(np.unique(b), np.arange(len(v)))  # every vertex is used
    assert d.layout == {3: "triangle-template", 4: "quad-template", 5: "pentagon"}.get(n, d.layout)
    assert n < 6 or d.layout in ("chords", "star")

    corners = v[b]
    assert np.all(is_strictly_convex(corners))  # counter-clockwise and strictly convex
    angles = interior_angles(corners)
    assert d.min_angle == angles.min() and d.max_angle == angles.max()

    # Areas to 1e-12 relative, plus the round-off floor: a point stored on an edge is off it by
    # an ulp of its coordinates, which moves areas by about that times the perimeter (this
    # matters for slivers and for polygons far from the origin). Measures are taken in
    # coordinates centred on the polygon, where the subtraction adds no relevant error.
    origin = polygon.mean(axis=0)
    area = signed_area(polygon - origin)
    perimeter = np.hypot(*(polygon - np.roll(polygon, 1, axis=0)).T).sum()
    ulp = np.finfo(np.float64).eps * np.abs(polygon).max()
    tol = REL * area + 8 * ulp * perimeter
    assert abs(signed_area(corners - origin).sum() - area) <= tol
    pieces = [shapely.Polygon(c) for c in corners - origin]
    domain = shapely.Polygon(polygon - origin)
    assert shapely.unary_union(pieces).symmetric_difference(domain).area <= tol
    for i in range(len(pieces)):
        for j in range(i + 1, len(pieces)):
            assert pieces[i].intersection(pieces[j]).area <= tol

    # Edge to edge: each directed edge once; an interior edge also runs the other way in exactly
    # one other block; the edges without a twin are exactly the boundary chains' steps.
    edges = np.stack([b, np.roll(b, -1, axis=1)], axis=-1).reshape(-1, 2)
    directed = [tuple(e) for e in edges.tolist()]
    assert len(set(directed)) == len(directed)
    boundary = {e for e in directed if e[::-1] not in set(directed)}
    chain_steps = {(int(p), int(q)) for c in d.edge_chains for p, q in itertools.pairwise(c)}
    assert boundary == chain_steps

    # Chains: vertex i to vertex i + 1, in order along the edge, on the edge.
    scale = float(np.ptp(polygon, axis=0).max())
    assert len(d.edge_chains) == n
    for i, chain in enumerate(d.edge_chains):
        assert chain[0] == i and chain[-1] == (i + 1) % n
        a, e = polygon[i], polygon[(i + 1) % n]
        rel = v[chain] - a
        t = rel @ (e - a) / ((e - a) @ (e - a))
        assert np.all(np.diff(t) > 0)
        off_line = np.abs(rel[:, 0] * (e - a)[1] - rel[:, 1] * (e - a)[0]) / np.hypot(*(e - a))
        assert np.all(off_line <= REL * scale + 8 * ulp)

    assert_no_hanging_node(polygon, v, b)


def assert_no_hanging_node(polygon: np.ndarray, v: np.ndarray, b: np.ndarray) -> None:
    """No vertex lies strictly inside an edge of a block it is not a corner of."""
    ulp = np.finfo(np.float64).eps * np.abs(polygon).max()
    edges = np.stack([b, np.roll(b, -1, axis=1)], axis=-1).reshape(-1, 2)
    p, q = v[edges[:, 0]], v[edges[:, 1]]
    seg = q - p
    rel = v[None, :, :] - p[:, None, :]
    t = (rel @ seg[:, :, None])[..., 0] / np.sum(seg * seg, axis=1)[:, None]
    length = np.hypot(seg[:, 0], seg[:, 1])[:, None]
    dist = np.abs(rel[..., 0] * seg[:, None, 1] - rel[..., 1] * seg[:, None, 0]) / length
    inside = (t > 1e-9) & (t < 1 - 1e-9) & (dist <= REL * length + 8 * ulp)
    assert not inside.any()


# --- polygon strategies -------------------------------------------------------------------


@st.composite
def ellipse_polygons(draw: st.DrawFn, n_min: int = 3, n_max: int = 16) -> np.ndarray:
    """Convex n-gons on an ellipse of aspect ratio up to 1:50, rotated, scaled and moved."""
    n = draw(st.integers(n_min, n_max))
    angles = draw(
        st.lists(st.floats(0, 2 * np.pi, exclude_max=True), min_size=n, max_size=n, unique=True)
    )
    aspect = draw(st.floats(1, 50))
    turn = draw(st.floats(0, 2 * np.pi))
    scale = draw(st.floats(1e-3, 1e3))
    shift = draw(st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)))
    t = np.sort(np.array(angles))
    local = np.column_stack([np.cos(t), np.sin(t) / aspect]) * scale
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    polygon = local @ rot.T + np.array(shift)
    assume(meets_contract(polygon))
    return polygon


@st.composite
def thin_triangles(draw: st.DrawFn) -> np.ndarray:
    """Near-degenerate triangles: apex at height 1e-6..1 over a unit base, anywhere along it."""
    x = draw(st.floats(-3, 4))
    h = 10 ** draw(st.floats(-6, 0))
    return np.array([[0.0, 0.0], [1.0, 0.0], [x, h]])


@st.composite
def thin_quads(draw: st.DrawFn) -> np.ndarray:
    """Near-degenerate quadrilaterals: thin slabs, kites and near-triangles."""
    h = 10 ** draw(st.floats(-6, 0))
    x2, x3 = draw(st.floats(-3, 4)), draw(st.floats(-3, 4))
    y2 = h * draw(st.floats(0.2, 5))
    quad = np.array([[0.0, 0.0], [1.0, 0.0], [max(x2, x3), y2], [min(x2, x3), h]])
    assume(meets_contract(quad))
    return quad


# --- properties ---------------------------------------------------------------------------


@settings(max_examples=examples(200))
@given(ellipse_polygons())
@example(SLIVER_AT_1)
@example(SLIVER_AT_2_5)
def test_random_convex_polygons_split_conformingly(polygon: np.ndarray) -> None:
    assume_template_room(polygon)
    # Every layout works in the polygon's own coordinates, where a sliver far from the origin
    # can be only a few spacings of doubles wide, and its blocks' corners cannot stand clear of
    # their chords: refused then (a located DomainError), and only then (CLEAR).
    try:
        d = decompose_convex_polygon(polygon)
    except DomainError as error:
        assert "too thin for where it sits" in str(error)
        assert clearance(polygon) <= CLEAR
        return
    assert_valid(polygon, d)


@pytest.mark.parametrize("sliver", [SLIVER_AT_1, SLIVER_AT_2_5, SLAB_AT_1])
def test_sliver_too_thin_for_where_it_sits(sliver: np.ndarray) -> None:
    assert meets_contract(sliver) and corner_sines(sliver).min() > 1e-10
    assert clearance(sliver) < 50
    with pytest.raises(DomainError, match=r"too thin for where it sits.*\(vertex \d+\)"):
        decompose_convex_polygon(sliver)
    # The local frame does not help: the blocks must come back to where the sliver sits.
    with pytest.raises(DomainError, match="too thin for where it sits"):
        decompose_polygon([sliver])
    # Near the origin the same sliver is 1e7 spacings wide and splits.
    local = sliver - sliver[0]
    assert clearance(local) > 1e6
    assert_valid(local, decompose_convex_polygon(local))
    d = decompose_polygon([local])
    assert np.all(is_strictly_convex(d.vertices[d.blocks]))


@settings(max_examples=examples(100))
@given(ellipse_polygons())
@example(SLIVER_AT_1)
@example(SLIVER_FOLDS)
def test_decompose_polygon_checks_blocks_where_the_polygon_sits(polygon: np.ndarray) -> None:
    # decompose_polygon works in the polygon's local frame, where every sliver is wide; its
    # blocks come back to where the polygon sits, and are refused only when too thin there
    # (corners too close to their chords, or blocks folded by the rounding on the way back).
    try:
        d = decompose_polygon([polygon])
    except DomainError as error:
        assert "for where it sits to be decomposed in double precision" in str(error)
        assert clearance(polygon) <= CLEAR
        return
    corners = d.vertices[d.blocks]
    assert np.all(is_strictly_convex(corners))
    assert d.vertices[: len(polygon)].tobytes() == polygon.tobytes()
    assert_no_hanging_node(polygon, d.vertices, d.blocks)
    if d.layout == "triangulation":
        return  # may keep ring corners within round-off of their chords (checked for folds)
    inc = corners - np.roll(corners, 1, axis=1)
    out = np.roll(corners, -1, axis=1) - corners
    off = np.abs(inc[..., 0] * out[..., 1] - inc[..., 1] * out[..., 0]) / np.hypot(
        *np.moveaxis(inc + out, -1, 0)
    )
    assert np.all(off > 16 * np.spacing(np.abs(corners).max(axis=(1, 2)))[:, None])


def test_many_corners_too_thin_for_where_they_sit() -> None:
    # Beyond the chord programme the triangulation works in a local frame; its blocks are
    # checked where the polygon sits (they came back with a corner 1.1 spacings off its chord).
    with pytest.raises(DomainError, match="too thin for where it sits"):
        decompose_convex_polygon(1.0 + regular(20) * [1e-7, 1e-14])


@given(ellipse_polygons(6, 16))
def test_star_kept_only_when_better(polygon: np.ndarray) -> None:
    assume(clearance(polygon) > CLEAR)  # else maybe too thin for where it sits
    d = decompose_convex_polygon(polygon)
    star = decompose._star_layout(polygon)
    assert star is None or len(polygon) % 3 == 0
    tol = decompose._SCORE_TOL
    chords = decompose._chord_layout(polygon, len(d.blocks))
    better = star is not None and (
        star.score > chord_score(polygon) + tol
        or (
            star.score >= chord_score(polygon) - tol
            and decompose._min_angle(star) > decompose._min_angle(chords) + tol
        )
    )
    assert d.layout == ("star" if better else "chords")
    if better:
        theta = interior_angles(d.vertices[d.blocks])[:, [0, 1, 4]]  # hub and spoke corners
        assert np.minimum(theta, 180 - theta).min() == star.score


@settings(max_examples=examples(150))
@given(st.one_of(thin_triangles(), thin_quads()))
def test_near_degenerate_triangles_and_quads(polygon: np.ndarray) -> None:
    assume_template_room(polygon)
    assert_valid(polygon, decompose_convex_polygon(polygon))


# --- specific polygons --------------------------------------------------------------------


def test_regular_12gon_prefers_the_star() -> None:
    # docs/mathematics.md §4: worst created angle 45 degrees with chords, 75 with the star.
    polygon = regular(12)
    d = decompose_convex_polygon(polygon)
    assert_valid(polygon, d)
    assert d.layout == "star"
    assert chord_score(polygon) == pytest.approx(45.0)
    assert d.min_angle == pytest.approx(75.0)  # spokes halve the 150-degree corners
    assert d.max_angle == pytest.approx(150.0)


def test_regular_9gon_tie_goes_to_the_larger_smallest_angle() -> None:
    # Both layouts create a 120-degree corner (score 60); the star's smallest angle is 70, the
    # chords' 60, so the star is kept.
    polygon = regular(9)
    d = decompose_convex_polygon(polygon)
    assert chord_score(polygon) == pytest.approx(60.0)
    assert d.layout == "star"
    assert d.min_angle == pytest.approx(70.0)


def test_paper_hexagon_gives_two_blocks() -> None:
    d = decompose_convex_polygon(PAPER_HEXAGON)
    assert_valid(PAPER_HEXAGON, d)
    assert d.layout == "chords" and len(d.blocks) == 2


@pytest.mark.parametrize(("n", "split"), [(7, 900 / 14), (8, 67.5)])
def test_regular_7_and_8_gons(n: int, split: float) -> None:
    # n = 7: vertex to opposite midpoint, halving a 900/7-degree corner;
    # n = 8: the long diagonal, halving two 135-degree corners.
    polygon = regular(n)
    d = decompose_convex_polygon(polygon)
    assert_valid(polygon, d)
    assert d.layout == "chords" and len(d.blocks) == 2
    assert d.min_angle == pytest.approx(split)
    assert chord_score(polygon) == pytest.approx(split)


def test_used_midpoints_are_exact_midpoints() -> None:
    d = decompose_convex_polygon(regular(7))
    for i, chain in enumerate(d.edge_chains):
        for k in chain[1:-1]:
            assert (
                d.vertices[k].tobytes() == ((d.vertices[i] + d.vertices[(i + 1) % 7]) / 2).tobytes()
            )


def test_equilateral_triangle_angles() -> None:
    triangle = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, math.sqrt(3) / 2]])
    d = decompose_convex_polygon(triangle)
    assert_valid(triangle, d)
    assert d.min_angle == pytest.approx(60.0, abs=0.05)
    assert d.max_angle == pytest.approx(132.0, abs=0.05)


def test_unit_square_angles_and_template_nodes() -> None:
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    d = decompose_convex_polygon(square)
    assert_valid(square, d)
    assert d.min_angle == pytest.approx(77.1, abs=0.05)
    assert d.max_angle == pytest.approx(128.6, abs=0.05)
    # The projective map of the unit square onto itself is the identity.
    inner = np.array([not np.any(np.all(n == square, axis=1)) for n in templates.SQUARE_NODES])
    np.testing.assert_allclose(d.vertices[4:], templates.SQUARE_NODES[inner], atol=1e-15)


def test_pentagon_is_its_own_block() -> None:
    pentagon = regular(5)
    d = decompose_convex_polygon(pentagon)
    assert_valid(pentagon, d)
    assert d.layout == "pentagon" and d.blocks.tolist() == [[0, 1, 2, 3, 4]]


def test_input_is_not_mutated_and_result_is_deterministic() -> None:
    polygon = regular(11) * [3.0, 1.0]
    before = polygon.copy()
    first, second = decompose_convex_polygon(polygon), decompose_convex_polygon(polygon)
    assert np.array_equal(polygon, before)
    assert np.array_equal(first.blocks, second.blocks)
    assert np.array_equal(first.vertices, second.vertices)
    with pytest.raises(ValueError, match="read-only"):
        first.vertices[0, 0] = 1.0


@pytest.mark.parametrize(
    "polygon",
    [
        regular(6)[::-1],  # clockwise
        np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]]),  # straight corner
        np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),  # repeated point
        np.array([[0.0, 0.0], [1.0, 0.0]]),  # too few vertices
        np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1e-300], [0.0, 1.0]]),  # nearly repeated point
        np.zeros((4, 3)),  # wrong shape
        np.array([[0.0, 0.0], [1.0, 0.0], [np.nan, 1.0]]),  # not finite
        np.array([[0, 0], [2, 0], [1, 0.2], [2, 1], [0, 1]], dtype=float),  # not convex
    ],
)
def test_broken_contract_raises_value_error(polygon: np.ndarray) -> None:
    with pytest.raises(ValueError, match="polygon"):
        decompose_convex_polygon(polygon)


def test_too_thin_polygon_raises() -> None:
    # Corners of sine just above 1e-12 meet the contract, but template corners fall below it.
    sliver = np.array([[0.0, 0.0], [1.0, 0.0], [-1.3, 3.3e-12]])
    assert meets_contract(sliver)
    with pytest.raises(DomainError, match="too thin"):
        decompose_convex_polygon(sliver)


def test_chord_layout_with_one_more_piece() -> None:
    octagon = regular(8)
    layout = decompose._chord_layout(octagon, 3)
    d = decompose._finished(layout)
    assert d.blocks.shape == (3, 5)
    assert len(d.vertices) == 8 + 3  # 3 * 3 - 8 + 2 midpoints
    assert np.all(is_strictly_convex(d.vertices[d.blocks]))
    assert signed_area(d.vertices[d.blocks]).sum() == pytest.approx(signed_area(octagon))
    # Hexagons have no 3-piece chord layout (it would need 5 of the 6 midpoints).
    assert decompose._chord_layout(regular(6), 3) is None


def test_fallback_to_one_more_piece(monkeypatch: pytest.MonkeyPatch) -> None:
    chord_layout = decompose._chord_layout

    def no_minimum(polygon: np.ndarray, pieces: int) -> decompose._Layout | None:
        return None if pieces == 2 else chord_layout(polygon, pieces)

    monkeypatch.setattr(decompose, "_chord_layout", no_minimum)
    assert len(decompose_convex_polygon(regular(8)).blocks) == 3
    with pytest.raises(DomainError, match="too thin"):
        decompose_convex_polygon(regular(7))  # no 3-piece layout either


@pytest.mark.parametrize("n", [17, 64, 96])
def test_large_convex_polygons_leave_the_chord_programme(n: int) -> None:
    # The O(n^5) programme took 14 s for a 64-gon and 197 s for a 96-gon, with thin pieces;
    # beyond 16 corners the quality triangulation takes over.
    polygon = regular(n)
    d = decompose_convex_polygon(polygon)
    assert d.layout == "triangulation"
    assert np.array_equal(d.vertices[:n], polygon)
    assert np.all(is_strictly_convex(d.vertices[d.blocks]))
    assert signed_area(d.vertices[d.blocks]).sum() == pytest.approx(signed_area(polygon), rel=1e-12)
    assert d.min_angle > 30.0
    for i, chain in enumerate(d.edge_chains):
        assert chain[0] == i and chain[-1] == (i + 1) % n
