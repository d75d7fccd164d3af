"""The curve types: parametrisations, derivatives, areas, pieces and the shape checks."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from blockmesh.curves import Arc, Polyline, Spline, curve_from_fields
from blockmesh.curves.edges import CurvedEdges
from blockmesh.errors import ArgumentError, DomainError, DomainFormatError

T = np.linspace(0, 1, 41)


def _derivative_matches(curve, t):
    h = 1e-6
    numeric = (curve.point(t + h) - curve.point(t - h)) / (2 * h)
    scale = np.abs(curve.derivative(t)).max()
    assert np.allclose(numeric, curve.derivative(t), atol=1e-7 * scale)


_X, _W = np.polynomial.legendre.leggauss(200)


def _numeric_segment_area(curve, t0, t1):
    x, w = _X, _W
    cuts = np.unique(np.r_[t0, t1, [b for b in curve.breaks() if min(t0, t1) < b < max(t0, t1)]])
    total, origin = 0.0, curve.point(t0)
    for a, b in itertools.pairwise(cuts):
        t = a + (b - a) * (x + 1) / 2
        g, d = curve.point(t) - origin, curve.derivative(t)
        total += (b - a) / 2 * w @ (g[:, 0] * d[:, 1] - g[:, 1] * d[:, 0])
    return 0.5 * total * (1 if t1 >= t0 else -1)


@pytest.mark.parametrize("through_y, sweep", [(1.0, -math.pi), (-1.0, math.pi)])
def test_arc_through_goes_the_way_of_its_point(through_y, sweep):
    arc = Arc(through=(0, through_y)).with_ends((-1, 0), (1, 0))
    assert arc.centre_point == pytest.approx((0, 0), abs=1e-15)
    assert arc.radius == pytest.approx(1.0) and arc.sweep == pytest.approx(sweep)
    assert arc.point(0.5) == pytest.approx((0, through_y), abs=1e-15)


def test_arc_through_a_point_on_the_long_way():
    arc = Arc(through=(0, -1)).with_ends((1, 0), (0, 1))  # three quarters, clockwise
    assert arc.sweep == pytest.approx(-1.5 * math.pi)
    assert arc.length == pytest.approx(1.5 * math.pi)
    assert np.hypot(*arc.point(T).T) == pytest.approx(np.ones(T.size), abs=1e-15)


def test_arc_by_centre_is_the_short_way_and_exact_at_the_ends():
    arc = Arc(center=(0, 0)).with_ends((0, 2), (2, 0))
    assert arc.sweep == pytest.approx(-math.pi / 2)
    assert arc.point([0, 1]).tolist() == [[0.0, 2.0], [2.0, 0.0]]
    assert arc.point(0.5) == pytest.approx((math.sqrt(2), math.sqrt(2)))
    _derivative_matches(arc, T[1:-1])


@pytest.mark.parametrize(
    "curve",
    [
        Arc(through=(0.3, 0.4)).with_ends((0, 0), (1, 0)),
        Arc(center=(0.5, 2)).with_ends((0, 0), (1, 0)),
        Spline(points=[(0.2, 0.3), (0.5, -0.1), (0.8, 0.2)]).with_ends((0, 0), (1, 0)),
        Polyline(points=[(0.3, 0.3), (0.6, -0.2)]).with_ends((0, 0), (1, 0)),
    ],
    ids=["arc-through", "arc-centre", "spline", "polyline"],
)
def test_segment_areas_and_derivatives(curve):
    inner = T[1:-1][np.all(np.abs(T[1:-1, None] - curve.breaks()) > 1e-3, axis=1)]
    _derivative_matches(curve, inner)
    for t0, t1 in [(0.0, 1.0), (0.1, 0.85), (0.7, 0.2)]:
        exact = _numeric_segment_area(curve, t0, t1)
        assert curve.segment_area(t0, t1) == pytest.approx(exact, rel=1e-13, abs=1e-16)
    assert curve.point(T).shape == (T.size, 2) and curve.derivative(T[:, None]).shape == (
        T.size,
        1,
        2,
    )


def test_small_arc_segments_keep_their_digits():
    arc = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    phi = 1e-5 * math.pi / 2
    assert arc.segment_area(0, 1e-5) == pytest.approx(0.5 * (phi**3 / 6 - phi**5 / 120), rel=1e-12)


def test_spline_interpolates_is_c1_and_converges_to_a_smooth_curve():
    def deviation(count):
        xs = np.linspace(0, 1, count + 2)[1:-1]
        spline = Spline(points=np.c_[xs, xs**2]).with_ends((0, 0), (1, 1))
        assert np.allclose(spline.point(spline.breaks()), np.c_[xs, xs**2], rtol=0, atol=1e-15)
        d, left = spline.derivative(spline.breaks()), spline.derivative(spline.breaks() - 1e-12)
        assert np.allclose(d, left, rtol=1e-6)  # C1 at the points
        p = spline.point(np.linspace(0, 1, 401))
        return np.abs(p[:, 1] - p[:, 0] ** 2).max()

    coarse, fine = deviation(3), deviation(9)
    assert fine < coarse / 8 and fine < 1e-3


def test_spline_through_collinear_points_is_the_segment():
    spline = Spline(points=[(0.25, 0.5), (0.5, 1.0)]).with_ends((0, 0), (1, 2))
    assert np.allclose(spline.point(T), np.c_[T, 2 * T], rtol=0, atol=1e-15)


def test_polyline_runs_uniformly_in_length():
    line = Polyline(points=[(1, 0), (1, 1)]).with_ends((0, 0), (0, 1))
    assert line.breaks() == pytest.approx([1 / 3, 2 / 3])
    assert np.allclose(line.point([1 / 6, 0.5, 5 / 6]), [[0.5, 0], [1, 0.5], [0.5, 1]])
    assert line.length == pytest.approx(3.0)


def test_pieces_cut_intervals_at_the_breaks_in_either_direction():
    line = Polyline(points=[(1, 0), (1, 1)]).with_ends((0, 0), (0, 1))
    owner, a, b = line.pieces(np.array([0.0, 0.9, 0.5]), np.array([1.0, 0.1, 0.6]))
    assert owner.tolist() == [0, 0, 0, 1, 1, 1, 2]
    assert a == pytest.approx([0, 1 / 3, 2 / 3, 0.9, 2 / 3, 1 / 3, 0.5])
    assert b == pytest.approx([1 / 3, 2 / 3, 1, 2 / 3, 1 / 3, 0.1, 0.6])


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Arc(center=(0, 0)).with_ends((1, 0), (0, 2), "edge (3, 4)"),
         "the arc on edge (3, 4) cannot reach both ends from its centre (0, 0): the start (1, 0)"),
        (lambda: Arc(center=(0, 0)).with_ends((1, 0), (-1, 0)), "opposite each other"),
        (lambda: Arc(through=(0.5, 0)).with_ends((0, 0), (1, 0)), "on the straight line"),
        (lambda: Arc(through=(1, 0)).with_ends((0, 0), (1, 0)), "through point (1, 0) at an end"),
        (lambda: Arc(center=(0, 0)).with_ends((1, 1), (1, 1)), "both ends at (1, 1)"),
        (lambda: Spline(points=[(2, 1), (-1, 1)]).with_ends((0, 0), (1, 0)), "crosses itself"),
        (lambda: Polyline(points=[(1, 1), (1, -1), (0.5, 0.5)]).with_ends((0, 0), (2, 0)),
         "crosses itself near"),
        (lambda: Spline(points=[(0, 0)]).with_ends((0, 0), (1, 0)), "passes twice through (0, 0)"),
    ],
)  # fmt: skip
def test_invalid_shapes_are_located(make, message):
    with pytest.raises(DomainError, match=message.replace("(", r"\(").replace(")", r"\)")):
        make()


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Arc(), "exactly one of through"),
        (lambda: Arc(through=(1, 1), center=(0, 0)), "exactly one of through"),
        (lambda: Arc(through=(1, "a")), "pair"),
        (lambda: Spline(points=[]), "at least one interior point"),
        (lambda: Polyline(points="abc"), "list of"),
        (lambda: curve_from_fields("circle", {}, "entry 1"), "unknown curve 'circle'"),
        (lambda: curve_from_fields("arc", {"points": []}, "entry 1"), "takes through or center"),
    ],
)  # fmt: skip
def test_malformed_curves(make, message):
    with pytest.raises(DomainFormatError, match=message):
        make()


def test_an_unbound_curve_says_how_to_bind_it():
    with pytest.raises(ArgumentError, match="with_ends"):
        Arc(center=(0, 0)).point(0.5)


def test_curved_edges_table_checks_itself_and_renumbers():
    arc = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    table = CurvedEdges([[0, 1]], [0], [0.0], [1.0], (arc,))
    assert table.renumbered(np.array([5, 7])).edges.tolist() == [[5, 7]]
    with pytest.raises(ArgumentError):
        CurvedEdges([[0, 1]], [1], [0.0], [1.0], (arc,))
    assert table.distances(np.array([[1.0, 0.0], [0.0, 1.0]])).tolist() == [0.0]


@settings(max_examples=examples(60))
@given(
    st.floats(-3, 3), st.floats(-3, 3), st.floats(0.1, 3), st.floats(0.05, 3.0),
    st.floats(0, 2 * math.pi), st.booleans(),
)  # fmt: skip
def test_random_arcs_stay_on_their_circle(cx, cy, radius, span, start, clockwise):
    """An arc through its mid-angle point has the circle's centre and radius, both ways."""
    sweep = -span if clockwise else span
    c = np.array([cx, cy])
    ends = c + radius * np.array([[math.cos(start), math.sin(start)],
                                  [math.cos(start + sweep), math.sin(start + sweep)]])  # fmt: skip
    mid = c + radius * np.array([math.cos(start + sweep / 2), math.sin(start + sweep / 2)])
    arc = Arc(through=tuple(mid)).with_ends(ends[0], ends[1])
    assert arc.sweep == pytest.approx(sweep, rel=1e-9, abs=1e-9)
    assert np.hypot(*(arc.point(T) - c).T) == pytest.approx(np.full(T.size, radius), rel=1e-9)
    assert arc.segment_area(0, 1) == pytest.approx(
        0.5 * radius**2 * (sweep - math.sin(sweep)), rel=1e-8, abs=1e-12
    )
