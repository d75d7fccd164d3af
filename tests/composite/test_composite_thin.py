"""Thin overlaps: every fragment goes to the right part however thin, or a located refusal.

Where two outlines run close, along different curves (two discs overlapping in a lens, a disc's
cap cut off by a straight edge, two polygons overlapping in a sliver), each region's area must be
its part's area minus the later parts' (exact formulas, within 1e-9 relative), and the interface
must lie on the later part's outline (the earlier one is cut there). A region left as a sliver
too thin to mesh with convex blocks is refused with a message naming the parts and the place.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from composite_checks import assert_composite
from composite_checks import disc as disc_shape
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from blockmesh import Domain, DomainError

#: Widths of the overlaps: from clearly visible to a millionth of the parts' size.
WIDTHS = [1e-1, 1e-2, 2.5e-3, 1e-3, 1e-4, 1e-5, 1e-6]


def lens_area(r1: float, r2: float, d: float) -> float:
    """Area of the overlap of two discs of radii ``r1``, ``r2`` whose centres are ``d`` apart."""
    a1 = r1 * r1 * math.acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
    a2 = r2 * r2 * math.acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2))
    k = (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2)
    return a1 + a2 - 0.5 * math.sqrt(k)


def cap_area(r: float, depth: float) -> float:
    """Area of the part of a disc of radius ``r`` beyond a line ``depth`` inside its edge."""
    h = r - depth
    return r * r * math.acos(h / r) - h * math.sqrt(r * r - h * h)


def disc(centre, radius) -> dict:
    return {"circles": [{"center": [float(c) for c in centre], "radius": radius}]}


def region_areas(domain: Domain, level: int) -> np.ndarray:
    mesh = domain.mesh(level)
    mesh.check_geometry()  # strictly convex cells
    areas = mesh.curved_cell_areas()
    return np.bincount(mesh.region, weights=areas, minlength=len(mesh.region_names))


def assert_areas(domain: Domain, expected: list[float], levels=(0, 1)) -> None:
    for level in levels:
        got = region_areas(domain, level)
        assert got.tolist() == pytest.approx(expected, rel=1e-9, abs=1e-13), level


def interface_points(domain: Domain) -> np.ndarray:
    mesh = domain.mesh(1)
    return mesh.points[np.unique(mesh.interface_edges)]


def two_discs(r0: float, r1: float, width: float, turn: float) -> tuple[dict, np.ndarray]:
    """Discs p0 and p1 (later) overlapping in a lens ``width`` wide, their centres ``turn``."""
    c0 = np.array([1.0, 1.0])
    c1 = c0 + (r0 + r1 - width) * np.array([math.cos(turn), math.sin(turn)])
    return {"p0": disc(c0, r0), "p1": disc(c1, r1)}, c1


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("radii", [(0.7, 0.7), (0.7, 0.4)])
def test_a_lens_between_two_discs_goes_to_the_later_disc(radii, width):
    r0, r1 = radii
    parts, c1 = two_discs(r0, r1, width, 0.3)
    domain = Domain.compose(parts)
    lens = lens_area(r0, r1, r0 + r1 - width)
    assert_areas(domain, [math.pi * r0 * r0 - lens, math.pi * r1 * r1])
    # The interface is the later disc's circle: the earlier one is cut along it.
    on = np.hypot(*(interface_points(domain) - c1).T)
    assert np.abs(on - r1).max() <= 1e-12


@pytest.mark.parametrize("width", WIDTHS)
@pytest.mark.parametrize("disc_first", [True, False])
def test_a_disc_cap_cut_by_a_straight_edge_goes_to_the_later_part(disc_first, width):
    r = 0.7
    centre = np.array([0.5, 1.0 + r - width])  # the disc dips `width` into the square's top
    square = shapely.box(0, 0, 1, 1)
    cap = cap_area(r, width)
    if disc_first:
        domain = Domain.compose({"disc": disc(centre, r), "square": square})
        assert_areas(domain, [math.pi * r * r - cap, 1.0])
        assert np.abs(interface_points(domain)[:, 1] - 1.0).max() <= 1e-12
    else:
        domain = Domain.compose({"square": square, "disc": disc(centre, r)})
        assert_areas(domain, [1.0 - cap, math.pi * r * r])
        on = np.hypot(*(interface_points(domain) - centre).T)
        assert np.abs(on - r).max() <= 1e-12


@pytest.mark.parametrize("width", WIDTHS)
def test_a_sliver_overlap_of_two_polygons_goes_to_the_later(width):
    a = shapely.Polygon([(0, 0), (1, 0), (1.2, 1), (0, 1)])
    b = shapely.Polygon([(1 - width, 0), (2, 0), (2, 1), (1.2 - width, 1)])
    domain = Domain.compose({"a": a, "b": b})
    assert_areas(domain, [a.difference(b).area, b.area])


@pytest.mark.parametrize("width", [1e-1, 1e-4, 1e-5])
def test_a_polygon_left_as_a_sliver_keeps_it(width):
    a = shapely.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
    b = shapely.Polygon([(0, width), (1, 1.5 * width), (1, 1), (0, 1)])
    domain = Domain.compose({"a": a, "b": b})
    assert_areas(domain, [a.difference(b).area, b.area], levels=(0,))


def test_a_polygon_sliver_thinner_than_the_tolerance_is_refused():
    a = shapely.box(0, 0, 1, 1)
    with pytest.raises(DomainError, match=r"a sliver of part 0 \('a'\) is only 1e-07 wide near"):
        Domain.compose({"a": a, "b": shapely.box(0, 1e-7, 1, 1)})


def crescent(big: float, small: float, width: float) -> dict:
    """A small disc p poking ``width`` out of a big later disc q: p is left a crescent."""
    c = np.array([1.0, 1.0])
    u = np.array([math.cos(0.3), math.sin(0.3)])
    return {"p": disc(c + (big - small + width) * u, small), "q": disc(c, big)}


@pytest.mark.parametrize(("small", "width"), [(0.1, 1e-2), (0.1, 2.5e-3), (0.4, 2.5e-3)])
def test_a_crescent_left_of_an_earlier_disc_is_kept(small, width):
    # (0.4, 2.5e-3) was refused as too thin before the chords were graded towards the crossings.
    big = 1.0
    domain = Domain.compose(crescent(big, small, width))
    lens = lens_area(big, small, big - small + width)
    assert_areas(domain, [math.pi * small * small - lens, math.pi * big * big])


def test_a_crescent_too_thin_for_convex_blocks_is_refused_where_it_is():
    # Its curved sides move its blocks' nodes by more than it is wide: a located refusal.
    with pytest.raises(
        DomainError,
        match=r"part 0 \('p'\) is too thin near \(1\.9\d+, 1\.\d+\) \(a sliver about 0\.00\d* "
        r"wide there, between the outlines of part 0 \('p'\) and part 1 \('q'\)\).*"
        r"overlap the parts by more",
    ):
        Domain.compose(crescent(1.0, 0.4, 3e-4))


def test_a_crescent_thinner_than_the_tolerance_is_refused():
    with pytest.raises(
        DomainError,
        match=r"a sliver of part 0 \('p'\) is only [\d.e-]+ wide near .*"
        r"part 0 \('p'\) and part 1 \('q'\)",
    ):
        Domain.compose(crescent(1.0, 0.4, 1e-6))


@settings(max_examples=examples(50), deadline=None)
@given(
    st.sampled_from([0.3, 0.5, 0.7, 1.1]),
    st.sampled_from([0.3, 0.5, 0.7, 1.1]),
    st.floats(-6, -1),
    st.floats(0, 2 * math.pi),
)
def test_thin_lenses_go_to_the_later_disc(r0, r1, exponent, turn):
    width = 10.0**exponent
    parts, c1 = two_discs(r0, r1, width, turn)
    domain = Domain.compose(parts)
    lens = lens_area(r0, r1, r0 + r1 - width)
    assert_areas(domain, [math.pi * r0 * r0 - lens, math.pi * r1 * r1], levels=(0,))
    on = np.hypot(*(interface_points(domain) - c1).T)
    assert np.abs(on - r1).max() <= 1e-12 * max(1.0, float(np.abs(c1).max()))


@pytest.mark.parametrize("poke", [0.0013, 0.005])
def test_a_disc_poking_through_an_edge_at_a_sharp_angle_leaves_cusps_that_are_meshed(poke):
    # The circle crosses the square's edge at 4.1 degrees (poke 0.0013): the square keeps two
    # cusps that sharp beside the disc. Refused as too thin before the circle's chords were
    # graded towards sharp crossings; poke 0.005 made 9,756 blocks, now about 4,200.
    square = shapely.box(0, 0, 2, 1.5)
    centre, radius = (0.9, 0.5 - poke), 0.5
    shapes = {"base": square, "disc": disc_shape(centre, radius)}
    domain = Domain.compose({"base": square, "disc": disc(centre, radius)})
    assert_composite(domain.mesh(0), shapes)


def test_a_corner_between_a_chord_and_the_circle_lies_in_the_disc():
    # The triangle's tip is 0.003 inside the circle, but outside the chord the circle is
    # followed with there: its edges crossed the chord where they do not cross the circle, and
    # the crossings computed twice, 2e-17 apart, were refused as a gap.
    square = shapely.box(0, 0, 2, 1.5)
    centre, radius = np.array([0.7, 0.7]), 0.5
    tip = centre + (radius - 3e-3) * np.array([math.cos(0.2), math.sin(0.2)])
    inner = centre + np.array([[0.25, -0.075], [0.2, 0.15]])
    triangle = shapely.Polygon([tip, *inner])
    shapes = {"base": square, "disc": disc_shape(centre, radius), "tri": triangle}
    domain = Domain.compose({"base": square, "disc": disc(centre, radius), "tri": triangle})
    assert_composite(domain.mesh(0), shapes)


@pytest.mark.parametrize("gap", [3e-4, pytest.param(1e-4, marks=pytest.mark.slow)])
@pytest.mark.parametrize("layout", ["beside an edge", "side by side", "one inside the other"])
def test_a_circle_nearly_touching_another_outline_is_meshed(layout, gap):
    # A gap this thin beside a circle was refused as too thin (from 3e-4 beside an edge or inside
    # a disc, 1e-4 between two discs): the circle is now followed at points graded towards the
    # gap's narrowest place, so the chords bulge by a small part of the gap beside them.
    square = shapely.box(0, 0, 2, 1.5)
    circles = {
        "beside an edge": [((1.5 - gap, 0.7), 0.5)],
        "side by side": [((0.6, 0.7), 0.4), ((1.4 + gap, 0.7), 0.4)],
        "one inside the other": [((1.0, 0.75), 0.7), ((1.4 - gap, 0.75), 0.3)],
    }[layout]
    given = {f"c{k}": disc(centre, radius) for k, (centre, radius) in enumerate(circles)}
    shapes = {f"c{k}": disc_shape(centre, radius) for k, (centre, radius) in enumerate(circles)}
    domain = Domain.compose({"base": square, **given})
    assert_composite(domain.mesh(0), {"base": square, **shapes})
