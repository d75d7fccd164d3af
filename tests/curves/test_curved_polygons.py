"""Curves in the polygon form: arcs on polygon and hole edges, circular holes, whole circles."""

from __future__ import annotations

import math

import numpy as np
import pytest

from blockmesh import Domain
from blockmesh.curves import Arc
from blockmesh.errors import DomainError, DomainFormatError

CHANNEL = [(0, 0), (4, 0), (4, 2), (0, 2)]


def _on_circle(mesh, centre, radius, patch):
    nodes = np.unique(mesh.patch_edges(patch))
    gap = np.abs(np.hypot(*(mesh.points[nodes] - centre).T) - radius)
    return float(gap.max())


@pytest.fixture(scope="module")
def channel():
    return Domain.from_polygon(
        CHANNEL,
        patches={"inlet": [3], "outlet": [1]},
        circles=[{"center": (1.5, 1.0), "radius": 0.4, "patch": "cylinder"}],
    )


def test_a_circular_hole_is_decomposed_and_curved(channel):
    assert channel.patch_names == ("inlet", "outlet", "cylinder", "boundary")
    assert channel.area == pytest.approx(8 - math.pi * 0.16, rel=1e-14)
    for level in range(4):
        mesh = channel.mesh(level)
        mesh.check_geometry()
        assert _on_circle(mesh, (1.5, 1.0), 0.4, "cylinder") < 1e-15
        assert mesh.curved_area == pytest.approx(channel.area, rel=1e-13)
    assert np.array_equal(
        channel.boundary_source[:, 0] >= 0, np.ones(len(channel.boundary_edges), bool)
    )


def test_arcs_on_outer_and_hole_edges():
    hole = [(1, 0.5), (3, 0.5), (3, 1.5), (1, 1.5)]
    d = Domain.from_polygon(
        CHANNEL, [hole], arcs={2: Arc(through=(2, 2.3)), "hole 0:2": Arc(center=(2, 0.2))},
        patches={"top": [2], "hole": ["hole 0"]},
    )  # fmt: skip
    top = Arc(through=(2, 2.3)).with_ends((4, 2), (0, 2))
    dent = Arc(center=(2, 0.2)).with_ends((3, 1.5), (1, 1.5))
    # The top bulges out of the domain; the hole's top edge bulges into it.
    expected = 8 - 2 + float(top.segment_area(0, 1)) - float(dent.segment_area(0, 1))
    assert d.area == pytest.approx(expected, rel=1e-13)
    mesh = d.mesh(3)
    mesh.check_geometry()
    assert _on_circle(mesh, top.centre_point, top.radius, "top") < 1e-14
    assert mesh.curves.distances(mesh.points).max() == 0.0


def test_a_whole_circle_is_the_eleven_block_disc():
    d = Domain.from_circle((1, -2), 3.0, patch="rim", name="big")
    assert (d.n_blocks, d.patch_names, d.layout, d.name) == (11, ("rim",), "disc", "big")
    assert d.area == pytest.approx(9 * math.pi, rel=1e-14)
    mesh = d.mesh(4)
    mesh.check_geometry()
    assert _on_circle(mesh, (1, -2), 3.0, "rim") < 1e-14


def test_toml_polygon_form_with_curves():
    text = """
polygon = [[0, 0], [4, 0], [4, 2], [0, 2]]
circles = [{center = [1.5, 1], radius = 0.4, patch = "cylinder", sides = 12}]
[patches]
inlet = [3]
[[arcs]]
edge = 2
through = [2, 2.3]
"""
    d = Domain.from_toml_text(text)
    assert "cylinder" in d.patch_names and len(d.curves) > 12
    again = Domain.from_toml_text(d.to_toml())  # written back as explicit blocks with [[edges]]
    assert np.array_equal(again.mesh(2).points, d.mesh(2).points)
    disc = Domain.from_toml_text('circle = {center = [0, 0], radius = 2, patch = "rim"}')
    assert disc.n_blocks == 11 and disc.area == pytest.approx(4 * math.pi, rel=1e-14)


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"arcs": {7: Arc(through=(2, 2.3))}}, DomainError, "the polygon has edges 0..3"),
        ({"arcs": {"hole 0:1": Arc(center=(0, 0))}}, DomainError, "there are no holes"),
        ({"arcs": {"top": Arc(center=(0, 0))}}, DomainFormatError, "outer edge index i or 'hole"),
        ({"arcs": {2: "round"}}, DomainFormatError, "must be an Arc(through=...)"),
        ({"arcs": {2: Arc(center=(3, 3))}}, DomainError, "cannot reach both ends"),
        ({"circles": [{"center": (1, 1)}]}, DomainFormatError, "needs center = [x, y] and radius"),
        ({"circles": [{"center": (1, 1), "radius": -1}]}, DomainError, "radius must be a finite"),
        ({"circles": [{"center": (1, 1), "radius": 0.3, "colour": "red"}]}, DomainFormatError,
         "not 'colour'"),
        ({"circles": [{"center": (1, 1), "radius": 0.3, "sides": 2}]}, DomainFormatError,
         "sides must be a whole number in 3..64"),
        ({"arcs": {0: Arc(through=(2, 1.8))}}, DomainError,
         "the polygon's curved edges do not fit its decomposition (the arc on the polygon's "
         "edge 0 moved the vertices of the blocks below onto the curve"),
        # Crossings name the edges as given (not the decomposition's sampled edges).
        ({"arcs": {0: Arc(through=(2, 1.8)), 2: Arc(through=(2, 0.1))}}, DomainError,
         "the polygon's edge 0 (an arc) and the polygon's edge 2 (an arc) meet near"),
        ({"arcs": {0: Arc(through=(2, 2.5))}}, DomainError,
         "the polygon's edge 0 (an arc) and the polygon's edge 3 meet near (0, 0.8996"),
        ({"circles": [{"center": (3.9, 1), "radius": 0.3}]}, DomainError,
         "the polygon's edge 1 and circle 0 meet near (4, 0.71"),
        ({"circles": [{"center": (2, 1), "radius": 0.3}, {"center": (2.4, 1), "radius": 0.3}]},
         DomainError, "circle 0 and circle 1 meet near (2.2, 1.2"),
        ({"holes": [[(1.5, 0.5), (2.5, 0.5), (2.5, 1.5), (1.5, 1.5)]],
          "arcs": {0: Arc(through=(2, 0.8))}}, DomainError,
         "the polygon's edge 0 (an arc) and hole 0's edge 3 meet near (1.5, 0.75"),
        ({"holes": [[(1.5, 0.5), (2.5, 0.5), (2.5, 1.5), (1.5, 1.5)]],
          "arcs": {"hole 0:0": Arc(through=(2, -0.1))}}, DomainError,
         "the polygon's edge 0 and hole 0's edge 0 (an arc) meet near"),
    ],
)  # fmt: skip
def test_bad_polygon_curves_are_located(kwargs, error, message):
    kwargs = dict(kwargs)
    holes = kwargs.pop("holes", None)
    with pytest.raises(error) as caught:
        Domain.from_polygon(CHANNEL, holes, **kwargs)
    assert message in str(caught.value)


@pytest.mark.parametrize(
    "text, message",
    [
        ("circle = {center = [0, 0], radius = 1}\npolygon = [[0, 0], [1, 0], [0, 1]]",
         "a 'circle' is the whole domain; leave out 'polygon'"),
        ("circle = {center = [0, 0]}", "'circle' takes center = [x, y], radius = r"),
        ("circle = 3", "'circle' must be a table"),
        ("vertices = [[0, 0], [1, 0], [1, 1], [0.5, 1.5], [0, 1]]\nblocks = [[0, 1, 2, 3, 4]]\n"
         "[[arcs]]\nedge = 0\nthrough = [0.5, -0.1]", "'arcs' belong to a 'polygon'"),
        ("polygon = [[0, 0], [1, 0], [0, 1]]\n[[arcs]]\nthrough = [0.5, -0.1]",
         "[[arcs]] entry 1 needs edge = i"),
        ("polygon = [[0, 0], [1, 0], [0, 1]]\ncircles = 3", "'circles' must be a list of tables"),
    ],
)  # fmt: skip
def test_bad_toml_curves_are_located(text, message):
    with pytest.raises(DomainFormatError) as caught:
        Domain.from_toml_text(text)
    assert message in str(caught.value)
