"""Builders and harnesses shared by the tests (import them: ``from helpers import ...``)."""

from __future__ import annotations

import importlib
import math

import pytest
from hypothesis import settings

from blockmesh.cli import main
from blockmesh.domain.catalogue import catalogue_names, catalogue_path

#: The catalogue domains with curved edges (their refined cells approach the curves, so the
#: straight-edged invariants, area preserved and nodes on the block edges, do not apply to them).
CURVED_CATALOGUE = [n for n in catalogue_names() if "[[edges]]" in catalogue_path(n).read_text()]
#: Every composite catalogue domain name (several parts, some with circles; tested on their own).
COMPOSITE_CATALOGUE = [n for n in catalogue_names() if "[[parts]]" in catalogue_path(n).read_text()]
#: Every straight-edged catalogue domain name of one material.
CATALOGUE = [
    n for n in catalogue_names() if n not in CURVED_CATALOGUE and n not in COMPOSITE_CATALOGUE
]
#: The straight-edged catalogue domains of about a hundred blocks or more (decomposed polygons):
#: a sweep over the catalogue whose work grows with the blocks takes them in the slow set only
#: (:func:`sweep`). ``test_large_catalogue_is_the_domains_of_90_blocks_or_more`` keeps the list.
LARGE_CATALOGUE = ("channel-obstacle", "comb", "lake-island", "plate-octagon")


def missing(module: str) -> bool:
    """Whether ``module`` cannot be imported (an optional extra is absent).

    Imported, not only looked up: ``tests/`` is on ``sys.path``, so a test folder such as
    ``tests/distributed`` would pass for the package of that name.
    """
    try:
        importlib.import_module(module)
    except ImportError:
        return True
    return False


def sweep(names, large=LARGE_CATALOGUE) -> list:
    """``names`` as parameters, the ``large`` ones marked ``slow`` (run by ``-m slow``)."""
    return [pytest.param(n, marks=pytest.mark.slow) if n in large else n for n in names]


#: The paper's symmetric and unsymmetrical pentagons.
SP = [(-1.0, -1.0), (1.0, -1.0), (2.0, 0.0), (0.0, 1.0), (-2.0, 0.0)]
USP = [(0.0, 0.0), (2.0, 0.0), (3.0, 1.0), (1.0, 3.0), (0.0, 2.0)]
#: Two pentagons sharing the edge (1, 2).
TWO_VERTICES = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)]
TWO_BLOCKS = [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)]


#: Examples per property in the ``ci`` hypothesis profile (hypothesis's own default count); the
#: profiles are registered in ``conftest.py``.
CI_EXAMPLES = 100


def examples(ci: int) -> int:
    """The examples of a property that runs ``ci`` of them in the ``ci`` profile, here and now.

    The count scales with the loaded profile (``settings.default``, chosen before the test modules
    are imported): ``ci`` in the ``ci`` profile, a tenth of it (at least one) in the default one.
    Use it as ``@settings(max_examples=examples(600))``; a property with the profile's own count
    needs no ``settings`` at all.
    """
    return max(1, math.ceil(ci * settings.default.max_examples / CI_EXAMPLES))


def slow_except(values: list[object], *kept: object) -> list[object]:
    """``values`` as parameters, every one but ``kept`` marked slow.

    For a parametrised test whose cases prove the same property at different costs: the default
    run keeps a cheap sample (``kept``) and the slow set adds the rest, e.g.
    ``@pytest.mark.parametrize("name", slow_except(FORMAT_NAMES, "vtu"))``.
    """
    unknown = [value for value in kept if value not in values]
    assert not unknown, f"kept values {unknown!r} are not among {values!r}"
    return [
        value if value in kept else pytest.param(value, marks=pytest.mark.slow) for value in values
    ]


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """Run ``blockmesh ARGV...`` through :func:`blockmesh.cli.main`: (exit code, stdout, stderr)."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# ----------------------------------------------------------------------------- polygons
# Random simple polygons for the decomposition tests (hypothesis strategies and checks).
import numpy as np  # noqa: E402
import shapely  # noqa: E402
from hypothesis import assume  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from blockmesh.geometry import is_strictly_convex, local_frame, signed_area  # noqa: E402


@st.composite
def star_ring(draw: st.DrawFn, n_min: int = 3, n_max: int = 300, depth: float = 0.7) -> np.ndarray:
    """A star-shaped polygon about the origin (simple, usually not convex), counter-clockwise."""
    n = draw(st.integers(n_min, n_max))
    gaps = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    # Star-shaped about the origin only when every corner-to-corner turn is under half a turn;
    # past it the origin is outside and the ring may cross itself (four corners, one wide gap).
    assume(gaps.max() < 0.5 * gaps.sum())
    radii = np.array(draw(st.lists(st.floats(1.0 - depth, 1.0), min_size=n, max_size=n)))
    angles = 2 * np.pi * np.cumsum(gaps) / gaps.sum()
    ring = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    # Three corners within half a turn run clockwise; every ring here runs counter-clockwise.
    return ring if signed_area(ring) > 0 else ring[::-1]


@st.composite
def boolean_polygon(draw: st.DrawFn) -> shapely.Polygon:
    """Unions and differences of random convex polygons: holes, notches and narrow parts."""
    pieces = []
    for _ in range(draw(st.integers(2, 4))):
        centre = draw(st.tuples(st.floats(-1, 1), st.floats(-1, 1)))
        size = draw(st.floats(0.3, 1.2))
        count = draw(st.integers(3, 8))
        xy = np.array(draw(st.lists(st.tuples(st.floats(-1, 1), st.floats(-1, 1)),
                                    min_size=count, max_size=count)))  # fmt: skip
        pieces.append(shapely.convex_hull(shapely.multipoints(np.array(centre) + size * xy)))
    shape = pieces[0]
    for piece, cut in zip(pieces[1:], draw(st.lists(st.booleans(), min_size=3, max_size=3)),
                          strict=False):  # fmt: skip
        shape = shape.difference(piece) if cut else shape.union(piece)
    # Tiny coordinates (hypothesis draws values like 1e-180) make GEOS's snapping divide by zero;
    # the snapped shape is still a shape, checked by the tests' own assumptions.
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        shape = shapely.set_precision(shape, 1e-3)
    parts = [p for p in shapely.get_parts(shape) if isinstance(p, shapely.Polygon)]
    if not parts:
        return shapely.Polygon()
    return max(parts, key=lambda p: p.area)


@st.composite
def polygon_with_holes(
    draw: st.DrawFn,
    n_max: int = 300,
    holes_max: int = 5,
    depth: float = 0.5,
    aspect_max: float = 10.0,
) -> tuple[np.ndarray, list[np.ndarray]]:
    """A star-shaped, possibly skinny polygon with 0..holes_max small holes well inside it.

    The polygon is star-shaped about the origin, so a hole centred on the segment from the
    origin to a corner lies inside it when it is small enough (checked, with a margin).
    """
    outer = draw(star_ring(3, n_max, depth=depth))
    aspect = draw(st.floats(1.0, aspect_max))
    turn = draw(st.floats(0, np.pi))
    rotation = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    outer = (outer * [1.0, 1.0 / aspect]) @ rotation.T
    shell = shapely.Polygon(outer)
    size = float(np.ptp(outer, axis=0).max())
    holes: list[np.ndarray] = []
    kept: list[shapely.Polygon] = []
    for _ in range(draw(st.integers(0, holes_max))):
        corner = outer[draw(st.integers(0, len(outer) - 1))]
        where = corner * draw(st.floats(0.0, 0.8))
        radius = size * draw(st.floats(0.005, 0.05))
        hole = where + radius * draw(star_ring(3, 8, depth=0.4))
        polygon = shapely.Polygon(hole)
        margin = 0.2 * radius
        if shell.buffer(-margin).contains(polygon) and not any(
            polygon.buffer(margin).intersects(k) for k in kept
        ):
            holes.append(hole)
            kept.append(polygon)
    return outer, holes


def assert_blocks_tile(domain, polygon: shapely.Polygon, *, rel: float = 1e-12) -> None:
    """Blocks are strictly convex CCW pentagons tiling ``polygon`` exactly, edge to edge."""
    v, b = domain.vertices, domain.blocks
    frame = local_frame(v)
    corners = frame.to_local(v)[b]
    assert b.shape[1] == 5
    assert np.all(is_strictly_convex(corners)), "a block is not a strictly convex CCW pentagon"
    local_polygon = shapely.transform(polygon, frame.to_local)
    area = local_polygon.area
    perimeter = local_polygon.length
    ulp = np.finfo(np.float64).eps * (np.abs(frame.origin).max() / frame.scale + 1)
    tol = rel * area + 16 * ulp * perimeter
    assert abs(float(signed_area(corners).sum()) - area) <= tol
    # The blocks form a coverage (checked edge to edge below; overlaps would fail the area test),
    # so GEOS's fast coverage union applies.
    union = shapely.coverage_union_all(shapely.polygons(corners))
    assert union.symmetric_difference(local_polygon).area <= tol
    # Edge to edge: each directed edge once; interior edges twice, opposite ways.
    start, stop = b.ravel(), np.roll(b, -1, axis=1).ravel()
    n = v.shape[0]
    directed = start * n + stop
    assert np.unique(directed).size == directed.size
    twin = np.isin(stop * n + start, directed)
    assert np.array_equal(np.sort(directed[~twin]), np.sort(
        domain.boundary_edges[:, 0] * n + domain.boundary_edges[:, 1]))  # fmt: skip
    # No hanging node: no vertex inside a block edge it is not an end of.
    local = frame.to_local(v)
    segments = shapely.linestrings(np.stack([local[start], local[stop]], axis=1))
    points = shapely.points(local)
    vertex, segment = shapely.STRtree(segments).query(points, predicate="dwithin", distance=1e-13)
    assert np.all((vertex == start[segment]) | (vertex == stop[segment])), "a hanging node"


def assert_patches_follow_edges(domain, rings: list[np.ndarray], edge_patch) -> None:
    """Every boundary edge lies on the polygon edge ``boundary_source`` names, in its patch."""
    v = domain.vertices
    frame = local_frame(v)
    for (a, b), patch, (ring, edge) in zip(
        domain.boundary_edges, domain.boundary_patch, domain.boundary_source, strict=True
    ):
        assert ring >= 0 and edge >= 0
        p, q = rings[ring][edge], rings[ring][(edge + 1) % len(rings[ring])]
        for point in (v[a], v[b]):
            u, w = q - p, point - p
            d = abs(u[0] * w[1] - u[1] * w[0]) / np.hypot(*u)
            assert d <= 1e-9 * frame.scale, (
                "a boundary edge off the polygon edge it is said to lie on"
            )
        expected = edge_patch(ring, edge)
        assert domain.patch_names[patch] == expected
