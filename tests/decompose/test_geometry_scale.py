"""Where a domain sits and how large it is do not change its verdict (issue 14, item 2; 11, 7).

Validation and decomposition work in local coordinates: a valid domain moved up to 1e12 times its
size away and scaled by 1e-6..1e6 stays valid (or, where doubles cannot hold its blocks, gets the
one clear "double precision" error), an invalid one stays invalid, and the polygons blockmesh
decomposes always pass blockmesh's own check, skinny ones included.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from helpers import assert_blocks_tile, examples, polygon_with_holes, run_cli
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh import BlockMeshError, Domain, DomainError, TopologyError
from blockmesh.geometry import is_strictly_convex, local_frame, signed_area

MOVES = st.tuples(
    st.floats(-12, 12),  # log10 of the offset in units of the domain's size
    st.floats(0, 2 * math.pi),  # direction of the offset
    st.floats(-6, 6),  # log10 of the scale
)


def moved(points, move, size):
    exponent, angle, scale_exponent = move
    scale = 10.0**scale_exponent
    offset = 10.0**exponent * size * scale * np.array([math.cos(angle), math.sin(angle)])
    return np.asarray(points, dtype=float) * scale + offset


def assert_valid_blocks(domain: Domain) -> None:
    local = local_frame(domain.vertices).to_local(domain.vertices)
    assert np.all(is_strictly_convex(local[domain.blocks]))


@settings(max_examples=examples(25), suppress_health_check=[HealthCheck.too_slow])
@given(polygon_with_holes(n_max=20, holes_max=2), MOVES)
def test_moved_and_scaled_polygons_keep_their_verdict(case, move):
    outer, holes = case
    size = float(np.ptp(outer, axis=0).max())
    here = Domain.from_polygon(outer, holes)
    assert_valid_blocks(here)
    rings = [moved(outer, move, size), *(moved(h, move, size) for h in holes)]
    try:
        there = Domain.from_polygon(rings[0], rings[1:])
    except DomainError as error:
        # Only where doubles truly cannot hold the blocks: offsets of 1e10 sizes and more.
        assert "double precision" in str(error)
        assert move[0] > 9
        return
    assert_valid_blocks(there)
    # The same verdict; the blocks themselves may differ where round-off decides a near tie.
    # The moved polygon is the input rounded to doubles there: its own area is the reference.
    assert_blocks_tile(there, shapely.Polygon(rings[0], rings[1:]))
    area = abs(float(signed_area(rings[0]))) - sum(abs(float(signed_area(h))) for h in rings[1:])
    assert area == pytest.approx(here.area * 100.0 ** move[2], rel=1e-3)


@settings(max_examples=examples(30))
@given(st.sampled_from(["square-cut", "l-shape", "ring", "joined-8", "hexagon"]), MOVES)
def test_moved_and_scaled_block_domains_stay_valid(name, move):
    domain = blockmesh.load_domain(name)
    size = float(np.ptp(domain.vertices, axis=0).max())
    there = Domain.from_blocks(
        moved(domain.vertices, move, size), domain.blocks, domain.patches, domain.regions
    )
    assert there.n_blocks == domain.n_blocks and there.n_shared_edges == domain.n_shared_edges
    assert there.patch_names == domain.patch_names


@settings(max_examples=examples(30))
@given(
    st.sampled_from(["sp", "square-cut", "l-shape", "ring", "hexagon"]), MOVES, st.integers(0, 4)
)
def test_moved_and_scaled_domains_refine_to_valid_meshes(name, move, level):
    """Meshes, not only blocks: wherever a domain sits and whatever its size, refinement gives
    a mesh whose every cell is strictly convex and counter-clockwise, of the scaled area, or
    one clear error where double precision cannot resolve the level's cells."""
    domain = blockmesh.load_domain(name)
    size = float(np.ptp(domain.vertices, axis=0).max())
    there = Domain.from_blocks(
        moved(domain.vertices, move, size), domain.blocks, domain.patches, domain.regions
    )
    try:
        mesh = there.mesh(level)
    except BlockMeshError as error:
        assert "double precision" in str(error), error
        assert move[0] > 8  # only 1e8 sizes and more from the origin
        return
    mesh.check_geometry()  # the final guard: every cell strictly convex and counter-clockwise
    assert mesh.n_cells == domain.n_blocks * 6**level
    rounding = 1e3 * np.finfo(float).eps * max(1.0, 10.0 ** move[0])  # of the moved corners
    assert mesh.area == pytest.approx(domain.area * 100.0 ** move[2], rel=rounding)
    quality = mesh.quality()
    assert quality.not_strictly_convex == 0 and 0 < quality.min_angle <= quality.max_angle < 180


@settings(max_examples=examples(30))
@given(MOVES)
def test_invalid_domains_stay_invalid_wherever_they_sit(move):
    crossing = [(0, 0), (2, 0), (0, 2), (2, 2)]
    with pytest.raises(DomainError, match="cross"):
        Domain.from_polygon(moved(crossing, move, 2.0))
    # A hanging node: block 1 ends in the middle of block 0's edge (1, 2).
    vertices = [(0, 0), (2, 0), (2, 2), (1, 3), (0, 2), (2, 1), (4, 0.5), (4.5, 1.5), (3.5, 2.5)]
    with pytest.raises((DomainError, TopologyError)):
        Domain.from_blocks(moved(vertices, move, 4.5), [(0, 1, 2, 3, 4), (5, 6, 7, 8, 2)])


# ----------------------------------------------------------------------------- reproducers
@pytest.mark.parametrize(
    "polygon",
    [
        "1e9,1e9 1000000001,1e9 1000000001,1000000001 1e9,1000000001",  # was "zero area"
        "1e10,1e10 10000000001,1e10 1e10,10000000001",  # was "not convex (286.1°)"
        "5e7,5e7 50000001,5e7 50000000.5,50000001",  # blocks were "zero area"
        "0,0 1,0 0.5,1e-6",  # was 63 "gap" problems
        "0,0 1000,0 0,0.001",  # was 88 "gap or overlap" problems (issue 11)
        "0,0 1000000,0 1000000,1 0,1",  # a 1:1e6 quadrilateral (issue 11)
        "0,0 1e9,0 1e9,1 0,1",  # 1:1e9
    ],
)
def test_reproducers_pass_blockmesh_check(capsys, polygon):
    code, out, err = run_cli(capsys, "check", "--polygon", polygon)
    assert code == 0, err
    assert "valid" in out


@settings(max_examples=examples(30))
@given(
    st.floats(0, 9),  # log10 of the aspect ratio
    st.floats(-2, 3),  # where the apex sits along the base (triangles), or the top's skew
    st.booleans(),
)
def test_skinny_polygons_pass_their_own_check_or_are_too_thin(log_aspect, shift, quad):
    height = 10.0**-log_aspect
    if quad:
        polygon = [(0, 0), (1, 0), (1 + shift * height, height), (shift * height, height)]
    else:
        polygon = [(0, 0), (1, 0), (shift, height)]
    try:
        domain = Domain.from_polygon(polygon)
    except BlockMeshError as error:
        assert isinstance(error, DomainError) and "too thin" in str(error), error
        return
    assert_valid_blocks(domain)
    assert_blocks_tile(domain, shapely.Polygon(polygon))


def test_aspect_ratios_up_to_1e9_work():
    for aspect in 10.0 ** np.arange(0, 10):
        assert_valid_blocks(Domain.from_polygon([(0, 0), (1, 0), (0.5, 1 / aspect)]))
        assert_valid_blocks(Domain.from_polygon([(0, 0), (aspect, 0), (aspect, 1), (0, 1)]))


def test_thinner_than_doubles_can_decompose_is_one_clear_error():
    with pytest.raises(DomainError, match="too thin"):
        Domain.from_polygon([(0, 0), (1, 0), (0.5, 1e-11)])
