"""Size fields, size specs, gradation and the predicted count: properties and located errors."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import shapely
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.domain.sized import _OUTLINE_SAMPLES, BYTES_PER_BLOCK, DomainGeometry, size_fits
from blockmesh.errors import ArgumentError, ExpressionError, ResourceError, UnknownNameError
from blockmesh.sizing import (
    PENTAGON_AREA,
    Callback,
    Constant,
    Expression,
    InRegion,
    Minimum,
    Near,
    as_size_spec,
    grade,
    ideal_count,
    mesh_ideal_count,
)
from blockmesh.sizing.predict import _SEARCH_STEPS, EVALUATIONS, RELATIVE_TOLERANCE

RNG = np.random.default_rng(24)


def test_minimum_is_the_pointwise_minimum():
    xy = RNG.uniform(-2, 2, (200, 2))
    parts = [
        Constant(0.3),
        Expression("0.05 + abs(x)"),
        Near(points=[(0, 0)], size=0.01, growth=1.5),
    ]
    got = Minimum(tuple(parts))(xy)
    assert np.array_equal(got, np.minimum.reduce([p(xy) for p in parts]))


def test_near_growth_grows_by_the_rate_per_cell():
    wall = Near(segments=[((0, 0), (1, 0))], size=0.01, growth=1.2)
    d = np.linspace(0, 1, 11)
    h = wall(np.column_stack([np.full_like(d, 0.5), d]))
    # One cell of size h further on, the size is growth * h: dh/dd = growth - 1.
    assert np.allclose(np.diff(h) / np.diff(d), 0.2)
    assert h[0] == 0.01


def test_near_distance_is_gmsh_threshold():
    field = Near(points=[(0, 0)], size=0.01, distance=(0.1, 0.5), far=0.2)
    r = np.array([0.0, 0.1, 0.3, 0.5, 3.0])
    h = field(np.column_stack([r, np.zeros_like(r)]))
    assert np.allclose(h, [0.01, 0.01, 0.105, 0.2, 0.2])


def test_in_region_asks_nothing_outside():
    field = InRegion(shapely.box(0, 0, 1, 1), 0.05)
    assert field(np.array([[0.5, 0.5], [1.5, 0.5]])).tolist() == [0.05, math.inf]


@pytest.mark.parametrize(
    "value, message",
    [
        (0, "must be a finite number > 0, got 0"),
        (-1.5, "must be a finite number > 0"),
        (float("nan"), "must be a finite number > 0"),
        (float("inf"), "must be a finite number > 0"),
        (
            {"default": 0.1, "near": [{"point": [0, 0], "size": 0.01, "growth": 1.0}]},
            "growth must be > 1",
        ),
        (
            {"default": 0.1, "near": [{"point": [0, 0], "size": 0.1, "distance": [0.5, 0.1]}]},
            "0 <= d_min < d_max",
        ),
        ({"default": 0.1, "nearby": []}, "unknown key 'nearby'"),
        ({"default": 0.1, "near": [{"size": 0.1, "growth": 1.2}]}, "what is it near"),
        ({"default": 0.1, "gradation": 1.0}, "gradation must be > 1"),
        ({}, "asks for no size"),
    ],
)
def test_bad_sizes_are_located(value, message):
    with pytest.raises(ArgumentError, match=message):
        as_size_spec(value).field()


def test_bad_expression_is_located():
    with pytest.raises(ExpressionError, match=r"column"):
        as_size_spec("0.1 + (x")
    square = blockmesh.load_domain("square")
    with pytest.raises(ExpressionError, match=r"size '1/x' gives inf at \(0, "):
        square.with_size("1/x")
    with pytest.raises(ExpressionError, match=r"gives nan at"):
        square.with_size("sqrt(x - 0.5)")


def test_bad_callable_is_located():
    square = blockmesh.load_domain("square")
    pattern = r"size function <lambda> gives (\S+) at \((\S+), (\S+)\);"
    with pytest.raises(ArgumentError, match=pattern) as info:
        square.with_size(lambda x, y: x - 1)
    value, x, y = (float(v) for v in re.search(pattern, str(info.value)).groups())
    assert value == pytest.approx(x - 1) and value <= 0
    assert shapely.box(0, 0, 1, 1).buffer(1e-9).contains(shapely.Point(x, y))


def test_size_zero_on_the_boundary_is_located():
    # Box centres never fall on the boundary: the boundary is checked on its own.
    square = blockmesh.load_domain("square")
    with pytest.raises(ExpressionError, match=r"'0.1\*y' gives 0.0 at \(\S+, 0\)"):
        square.with_size("0.1*y")


class Counting:
    """A size function that counts the points it is asked about."""

    def __init__(self, function) -> None:
        self.function = function
        self.points = 0

    def __call__(self, x, y):
        self.points += len(x)
        return self.function(x, y)


#: Points the guard may evaluate besides the count's budget: the boundary check (1,024 per
#: width, and the corners) and the search for the smallest size (8 a step).
GUARD_EXTRA = 4 * _OUTLINE_SAMPLES + 8 * _SEARCH_STEPS


def test_size_falling_to_zero_inside_is_refused_not_scaled():
    # Zero along a line that no sample hits: no scale of the field fits, so the guard says
    # where the sizes fall instead of naming a size that would not fit either.
    square = blockmesh.load_domain("square")
    field = Expression("0.1*abs(x - 0.30017)")
    pattern = r"gets ever smaller near \(([^,]+), "
    with pytest.raises(ArgumentError, match=pattern) as info:
        size_fits(field, DomainGeometry(square), 2**20)
    assert float(re.search(pattern, str(info.value)).group(1)) == pytest.approx(0.30017, abs=1e-9)
    # With any memory at all: the count stops at its budget, and the search finds the line.
    counting = Counting(lambda x, y: 0.1 * np.abs(x - 0.30017))
    with pytest.raises(ArgumentError, match=pattern) as info:
        size_fits(Callback(counting), DomainGeometry(square), 2**50)
    assert float(re.search(pattern, str(info.value)).group(1)) == pytest.approx(0.30017, abs=1e-9)
    assert counting.points <= EVALUATIONS + GUARD_EXTRA


def test_size_falling_to_zero_at_a_point_is_located():
    plate = blockmesh.load_domain("plate-hole")
    pattern = r"gets ever smaller near \(([^,]+), ([^)]+)\)"
    with pytest.raises(ArgumentError, match=pattern) as info:
        plate.with_size("0.2*sqrt((x - 1.234567)^2 + (y + 0.7654321)^2)")
    x, y = (float(v) for v in re.search(pattern, str(info.value)).groups())
    assert (x, y) == (pytest.approx(1.234567, abs=1e-9), pytest.approx(-0.7654321, abs=1e-9))


def test_unknown_patch_and_region_name_the_known_ones():
    plate = blockmesh.load_domain("plate-hole")
    with pytest.raises(UnknownNameError, match=r"patch 'hole 0'.*\(patches: 'hole', 'right'"):
        plate.with_size(
            {"default": 0.2, "near": [{"patch": "hole 0", "size": 0.02, "growth": 1.2}]}
        )
    with pytest.raises(UnknownNameError, match=r"region 'core'.*regions: 'domain'"):
        plate.with_size({"default": 0.2, "regions": {"core": 0.05}})


@settings(max_examples=examples(25), deadline=None)
@given(
    inside=st.floats(0.005, 0.05),
    outside=st.floats(0.1, 1.0),
    rate=st.floats(1.05, 2.0),
)
def test_gradation_bounds_the_growth_and_never_raises_the_field(inside, outside, rate):
    field = Minimum((Constant(outside), InRegion(shapely.box(0.4, 0.4, 0.6, 0.6), inside)))
    g = np.linspace(0, 1, 41)
    x, y = np.meshgrid(g, g)
    samples = np.column_stack([x.ravel(), y.ravel()])
    i = np.arange(samples.shape[0]).reshape(41, 41)
    edges = np.vstack(
        [np.column_stack([i[:, :-1].ravel(), i[:, 1:].ravel()]),
         np.column_stack([i[:-1].ravel(), i[1:].ravel()])]
    )  # fmt: skip
    graded = grade(field, rate, samples, edges)
    a, b = RNG.uniform(0, 1, (300, 2)), RNG.uniform(0, 1, (300, 2))
    ha, hb = graded(a), graded(b)
    # Lipschitz with slope rate - 1: along the grid's edges (at most sqrt(2) times the straight
    # distance), and to within the slope times the spacing between samples.
    slope, spacing = rate - 1, 1 / 40
    bound = slope * (math.sqrt(2) * np.hypot(*(a - b).T) + 2 * spacing)
    assert np.all(np.abs(ha - hb) <= bound + 1e-12)
    assert np.all(ha <= field(a) + 1e-15)


def test_ideal_count_integrates_one_over_a_h_squared():
    square = shapely.box(0, 0, 2, 1)
    exact = 2 / (PENTAGON_AREA * 0.05**2)
    assert ideal_count(Constant(0.05), square).cells == pytest.approx(exact, rel=1e-9)
    # A linear field: the integral of 1/(a (0.1 + 0.1 x)^2) over [0, 2] x [0, 1]
    # is 1/(a 0.1^2) * 2/3.
    linear = ideal_count(Expression("0.1 + 0.1*x"), square).cells
    assert linear == pytest.approx(2 / 3 / (PENTAGON_AREA * 0.01), rel=0.03)
    assert not ideal_count(Constant(1e-4), square, limit=1e5).complete


def test_mesh_ideal_count_agrees_with_the_quadtree():
    plate = blockmesh.load_domain("square").with_size(0.05)
    mesh = plate.block_mesh()
    field = Expression("0.02 + 0.05*x")
    quadtree = ideal_count(field, shapely.box(0, 0, 1, 1)).cells
    assert mesh_ideal_count(field, mesh.points, mesh.cells) == pytest.approx(quadtree, rel=0.02)


@pytest.mark.parametrize("size", [1e-4, 1e-5, 1e-7])
def test_memory_guard_names_the_largest_size_that_fits(size):
    square = blockmesh.load_domain("square")
    limit = 200 * 2**20
    pattern = r"asks for ([0-9,]+) cells.*largest size that fits is about ([0-9.e-]+)"
    with pytest.raises(ResourceError, match=pattern) as info:
        square.with_size(size, max_memory=limit)
    cells, fits = re.search(pattern, str(info.value)).groups()
    assert int(cells.replace(",", "")) == pytest.approx(1 / (PENTAGON_AREA * size**2), rel=1e-6)
    # The same whatever the size asked: the size whose ideal count fits the blocks' budget.
    assert float(fits) == pytest.approx(
        (limit / (1.5 * BYTES_PER_BLOCK) * PENTAGON_AREA) ** -0.5, rel=2e-3
    )
    size_fits(Constant(float(fits) * 1.01), DomainGeometry(square), limit)  # no error
    with pytest.raises(ResourceError):
        size_fits(Constant(float(fits) * 0.99), DomainGeometry(square), limit)


def test_memory_guard_evaluates_the_field_a_bounded_number_of_times():
    # A field asking for billions of cells is counted in a few thousand evaluations (it varies
    # little), one asking for millions along a line within the budget, whatever the sizes.
    square = blockmesh.load_domain("square")
    for size, most in ((1e-6, 5000), (1e-9, 5000)):
        counting = Counting(lambda x, y, size=size: size * (1 + x))
        with pytest.raises(ResourceError, match="largest size that fits is about"):
            size_fits(Callback(counting), DomainGeometry(square), 2**30)
        assert counting.points <= most + GUARD_EXTRA
    counting = Counting(lambda x, y: 1e-6 + 0.2 * y)  # a wall at y = 0 asking for 1e-6
    with pytest.raises(ResourceError, match="at least"):
        size_fits(Callback(counting), DomainGeometry(square), 2**30)
    assert counting.points <= EVALUATIONS + GUARD_EXTRA


@settings(max_examples=20, deadline=None)
@given(
    base=st.floats(0.005, 0.1),
    slope=st.floats(0.0, 2.0),
    angle=st.floats(0, 2 * math.pi),
    scale=st.floats(1e-6, 1e3),
)
def test_ideal_count_scales_and_is_a_lower_bound_when_cut_short(base, slope, angle, scale):
    # The count of h scaled by s is the count over s^2 (the quadrature's choices do not depend
    # on the scale), and a count cut short by its budget is below the full one (to within the
    # tolerance: the triangles left are counted by their own rule).
    text = f"{base} + {slope}*abs({math.cos(angle)}*x + {math.sin(angle)}*y)"
    plate = shapely.box(-1, -0.5, 1, 0.5)
    full = ideal_count(Expression(text), plate)
    scaled = ideal_count(Expression(f"{scale}*({text})"), plate)
    assert full.complete and scaled.complete
    assert scaled.cells * scale**2 == pytest.approx(full.cells, rel=1e-9)
    short = ideal_count(Expression(text), plate, budget=full.evaluations // 2)
    assert not short.complete and short.cells <= full.cells * (1 + RELATIVE_TOLERANCE)
