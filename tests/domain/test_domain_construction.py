"""Domain construction and validation: every bad input gets its typed, located error."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import shapely
from helpers import SP, TWO_BLOCKS, TWO_VERTICES

import blockmesh
from blockmesh import BlockMeshWarning, Domain, DomainError, DomainFormatError, TopologyError


# ----------------------------------------------------------------------------- polygon input
@pytest.mark.parametrize(
    ("coords", "kind", "message"),
    [
        ([(0, 0), (1, 0), (float("nan"), 1)], DomainError, r"vertex 2 \(nan, 1.0\) is not finite"),
        ([(0, 0), (1, 0), (math.inf, 1)], DomainError, r"vertex 2 \(inf, 1.0\) is not finite"),
        ([(0, 0), (1, "a"), (0, 1)], DomainFormatError, r"vertex 1 has a y coordinate .* \('a'\)"),
        ([(0, 0), (1, 0, 2), (0, 1)], DomainFormatError, r"vertex 1 is \[1, 0, 2\]: .* pair"),
        ([(0, 0), (1, 0)], DomainError, "at least 3 vertices, got 2"),
        (
            [(0, 0), (1, 0), (1, 1), (1, 0)],
            DomainError,
            r"vertices 1 and 3 are the same point \(1, 0\)",
        ),
        ([(0, 0), (1, 1), (2, 2)], DomainError, "zero area"),
        ([(0, 0), (1, 0), (0.5, 1e-13)], DomainError, "zero area"),
        ([(0, 0), (1, 0), (1e-14, 1e-14)], DomainError, r"vertices 0 and 2 are the same point"),
        (
            [(0, 0), (2, 0), (0, 2), (2, 2)],
            DomainError,
            r"edges 1 \(2, 0\)->\(0, 2\) and 3 \(2, 2\)->\(0, 0\) cross at \(1, 1\)",
        ),
        (
            [(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)],
            DomainError,
            r"edges 0 \(0, 0\)->\(2, 0\) and 3 \(1, 0\)->\(0, 2\) touch at \(1, 0\)",
        ),
    ],
)
def test_bad_polygon(coords, kind, message):
    with pytest.raises(kind, match=message):
        Domain.from_polygon(coords)


def test_non_convex_polygon_is_decomposed():
    # Once rejected ("the corner at vertex 3 (1, 1) (270.0°) turns inward"): now any simple
    # polygon is decomposed, and its blocks tile it exactly.
    coords = [(0, 0), (2, 0), (2, 2), (1, 1), (0, 2)]
    domain = Domain.from_polygon(coords)
    union = shapely.union_all(shapely.polygons(domain.vertices[domain.blocks]))
    assert union.symmetric_difference(shapely.Polygon(coords)).area <= 1e-12
    assert domain.area == pytest.approx(3.0, rel=1e-12)
    assert np.all(blockmesh.geometry.is_strictly_convex(domain.vertices[domain.blocks]))


def test_error_kinds_share_a_base():
    with pytest.raises(blockmesh.BlockMeshError):
        Domain.from_polygon([(0, 0), (1, 0)])


def test_clockwise_polygon_is_reversed_with_a_warning():
    with pytest.warns(BlockMeshWarning, match="clockwise; its vertices were reversed"):
        domain = Domain.from_polygon(SP[::-1])
    assert domain.area == pytest.approx(5.0, rel=1e-15)
    # Vertex 0 stays first, the rest in counter-clockwise order.
    assert domain.vertices[domain.blocks[0]].tolist() == [
        list(SP[-1]),
        *[list(p) for p in SP[:-1]],
    ]


def test_clockwise_polygon_keeps_its_patches_on_the_same_edges():
    # Edge 0 of the input runs (0,0)->(0,1) (clockwise order); it must stay patch "left".
    with pytest.warns(BlockMeshWarning):
        domain = Domain.from_polygon([(0, 0), (0, 1), (1, 1), (1, 0)], patches={"left": [0]})
    left = domain.vertices[domain.patches["left"]]
    assert np.all(left[:, :, 0] == 0.0)
    assert len(domain.patches["left"]) >= 1


def test_closing_vertex_is_dropped_with_a_warning():
    with pytest.warns(BlockMeshWarning, match="repeats the first"):
        domain = Domain.from_polygon([*SP, SP[0]])
    assert domain.n_blocks == 1


def test_collinear_vertex_is_dropped_with_a_warning():
    with pytest.warns(BlockMeshWarning, match=r"vertex 1 \(0, -1\) lies on a straight line"):
        domain = Domain.from_polygon([SP[0], (0.0, -1.0), *SP[1:]])
    assert domain.n_blocks == 1
    assert domain.vertices.tolist() == [list(p) for p in SP]


def test_collinear_vertex_between_two_patches_is_kept_where_they_meet():
    # Once rejected ("vertex 1 (0, -1) is a straight (180°) corner"): now the vertex stays, as
    # the point where patch a ends and patch b begins.
    coords = [SP[0], (0.0, -1.0), *SP[1:]]
    domain = Domain.from_polygon(coords, patches={"a": [0], "b": [1]})
    a, b = domain.vertices[domain.patches["a"]], domain.vertices[domain.patches["b"]]
    assert np.all(a[:, :, 0] <= 0.0) and np.all(b[:, :, 0] >= 0.0)
    assert [0.0, -1.0] in domain.vertices.tolist()
    assert a[:, :, 1].max() == b[:, :, 1].min() == -1.0


def test_polygon_patch_errors():
    with pytest.raises(
        DomainError, match="names edge 7, but the polygon's edges are numbered 0..4"
    ):
        Domain.from_polygon(SP, patches={"a": [7]})
    with pytest.raises(DomainError, match="edge 1 is in patches 'a' and 'b'"):
        Domain.from_polygon(SP, patches={"a": [0, 1], "b": [1]})
    with pytest.raises(DomainFormatError, match="name 'bad name' is not valid"):
        Domain.from_polygon(SP, patches={"bad name": [0]})


# ----------------------------------------------------------------------------- block input
def test_two_blocks_are_valid():
    domain = Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS)
    assert domain.n_blocks == 2 and domain.n_shared_edges == 1
    assert domain.area == pytest.approx(7.5)
    assert domain.patch_names == ("boundary",) and domain.region_names == ("domain",)


def test_block_errors_name_the_block_and_vertex():
    square_ish = [(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)]
    with pytest.raises(
        DomainError,
        match=r"block 0 \(vertices 0, 1, 2, 3, 4\) is not strictly convex: the corner at vertex 1 "
        r"\(1, 0\) is straight \(180°\)",
    ):
        Domain.from_blocks(square_ish, [(0, 1, 2, 3, 4)])
    dart = [(0, 0), (2, 0), (2, 2), (1, 0.5), (0, 2)]
    with pytest.raises(DomainError, match=r"corner at vertex 3 \(1, 0.5\) turns the wrong way"):
        Domain.from_blocks(dart, [(0, 1, 2, 3, 4)])
    star = [(math.cos(a), math.sin(a)) for a in np.arange(5) * 4 * math.pi / 5]
    with pytest.raises(DomainError, match="block 0 .* crosses itself"):
        Domain.from_blocks(star, [(0, 1, 2, 3, 4)])


@pytest.mark.parametrize(
    ("blocks", "message"),
    [
        ([(0, 1, 2, 3)], r"block 0 is \[0, 1, 2, 3\]: a block is a pentagon, 5 vertex ids"),
        ([(0, 1, 2, 3, 9)], "block 0 refers to vertex 9, but the vertices are numbered 0..4"),
        ([(0, 1, 2, 2, 4)], r"block 0 \(0, 1, 2, 2, 4\) uses vertex 2 twice"),
        ([(0, 1, 2, 3, "x")], "block 0 has vertex id 'x', which is not a whole number"),
        ("01234", "expected a list of blocks"),
        ([], "at least one block"),
    ],
)
def test_malformed_blocks(blocks, message):
    with pytest.raises(DomainFormatError, match=message):
        Domain.from_blocks(SP, blocks)


def test_clockwise_block_is_reversed_with_a_warning():
    with pytest.warns(BlockMeshWarning, match="block 0 is now 0, 1, 2, 3, 4"):
        domain = Domain.from_blocks(SP, [(0, 4, 3, 2, 1)])
    assert domain.blocks.tolist() == [[0, 1, 2, 3, 4]]


def test_zero_area_block():
    line = [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0)]
    with pytest.raises(DomainError, match=r"block 0 \(vertices 0, 1, 2, 3, 4\) has zero area"):
        Domain.from_blocks(line, [(0, 1, 2, 3, 4)])


def test_repeated_and_unused_vertices():
    with pytest.raises(DomainError, match=r"vertices 4 and 5 are the same point \(-2, 0\)"):
        Domain.from_blocks([*SP, (-2.0, 0.0)], [(0, 1, 2, 3, 4)])
    with pytest.raises(DomainError, match=r"vertex 5 \(7, 7\) is not used by any block"):
        Domain.from_blocks([*SP, (7.0, 7.0)], [(0, 1, 2, 3, 4)])


def test_overlapping_blocks():
    vertices = [*TWO_VERTICES[:5], (1, 0.5), (3.5, 0.5), (4, 1.5), (3, 2.5), (1.5, 1.5)]
    with pytest.raises(TopologyError, match=r"blocks 0 and 1 overlap \(shared area .* around \("):
        Domain.from_blocks(vertices, [(0, 1, 2, 3, 4), (5, 6, 7, 8, 9)])


def test_same_direction_edge_means_overlap():
    # Both blocks lie above the edge (0, 1) and run along it from 0 to 1.
    vertices = [(0, 0), (2, 0), (2, 2), (1, 3), (0, 2), (2.5, 1), (1, 1.5), (-0.5, 1)]
    with pytest.raises(
        TopologyError, match=r"blocks 0 and 1 both run along edge \(0, 1\) in the same direction"
    ):
        Domain.from_blocks(vertices, [(0, 1, 2, 3, 4), (0, 1, 5, 6, 7)])


def test_edge_in_three_blocks():
    vertices = [(0, 0), (1, 0), (1.2, 1), (0.5, 1.5), (-0.2, 1), (1.5, -1), (0.5, -1.5), (-0.5, -1)]
    vertices += [(0.5, 0.8), (-0.1, 0.5), (1.1, 0.5)]
    blocks = [(0, 1, 2, 3, 4), (1, 0, 7, 6, 5), (0, 1, 10, 8, 9)]
    with pytest.raises(TopologyError, match=r"edge \(0, 1\) belongs to three or more cells"):
        Domain.from_blocks(vertices, blocks)


def test_hanging_node():
    # Block 1 ends at vertex 5 = (2, 1), in the middle of block 0's edge (1, 2) from (2,0) to (2,2).
    vertices = [(0, 0), (2, 0), (2, 2), (1, 3), (0, 2), (2, 1), (4, 0.5), (4.5, 1.5), (3.5, 2.5)]
    with pytest.raises(
        TopologyError, match=r"vertex 5 \(2, 1\) lies on edge \(1, 2\) of block 0 .*hanging node"
    ):
        Domain.from_blocks(vertices, [(0, 1, 2, 3, 4), (5, 6, 7, 8, 2)])


def test_gap_between_blocks():
    # The right block's corners sit 1e-7 off the left block's edge (1, 2), to the right of it.
    normal = np.array([1.0, -0.5]) / np.hypot(1.0, 0.5)
    vertices = [*TWO_VERTICES, tuple(np.array(TWO_VERTICES[1]) + 1e-7 * normal)]
    vertices += [tuple(np.array(TWO_VERTICES[2]) + 1e-7 * normal)]
    with pytest.raises(TopologyError, match=r"is only 1e-07 from edge .* \(a gap or an overlap"):
        Domain.from_blocks(vertices, [(0, 1, 2, 3, 4), (8, 5, 6, 7, 9)])


def test_disconnected_blocks():
    far = [(x + 10, y) for x, y in SP]
    with pytest.raises(TopologyError, match=r"2 separate pieces .* connect block 1 to the rest"):
        Domain.from_blocks([*SP, *far], [(0, 1, 2, 3, 4), (5, 6, 7, 8, 9)])


def test_blocks_touching_at_a_corner_are_not_connected():
    other = [(2, 0), (3, -1), (5, 0), (5, 1), (3, 1)]
    with pytest.raises(TopologyError, match="touching at a corner is not enough"):
        Domain.from_blocks([*SP, *other[1:]], [(0, 1, 2, 3, 4), (2, 5, 6, 7, 8)])


def test_patch_errors():
    with pytest.raises(
        DomainError,
        match=r"patch 'inlet' names edge \(1, 2\), which is not on the boundary: it is "
        r"shared by blocks 0 and 1",
    ):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, {"inlet": [(1, 2)]})
    with pytest.raises(
        DomainError, match=r"names edge \(0, 3\), which is not an edge of any block"
    ):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, {"inlet": [(0, 3)]})
    with pytest.raises(DomainError, match=r"edge \(1, 0\) is in patches 'a' and 'b'"):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, {"a": [(0, 1)], "b": [(1, 0)]})
    with pytest.raises(DomainFormatError, match=r"patch 'a' has 7; each edge is a pair"):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, {"a": [7]})


def test_region_errors():
    with pytest.raises(
        DomainError, match="region 'r' names block 5, but the blocks are numbered 0..1"
    ):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, regions={"r": [5]})
    with pytest.raises(DomainError, match="block 0 is in regions 'r' and 's'"):
        Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, regions={"r": [0], "s": [0]})


def test_patches_and_regions_cover_everything():
    domain = Domain.from_blocks(TWO_VERTICES, TWO_BLOCKS, {"inlet": [(4, 0)]}, {"left": [0]})
    assert domain.patch_names == ("inlet", "boundary")
    assert domain.patches["inlet"].tolist() == [[4, 0]]
    assert domain.region_names == ("left", "domain")
    assert domain.regions["domain"].tolist() == [1]


def test_domain_arrays_are_read_only_and_inputs_untouched():
    vertices = np.array(SP)
    blocks = np.array([[0, 4, 3, 2, 1]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BlockMeshWarning)
        domain = Domain.from_blocks(vertices, blocks)
    assert blocks.tolist() == [[0, 4, 3, 2, 1]]  # the caller's array is not modified
    with pytest.raises(ValueError):
        domain.vertices[0, 0] = 5.0


# ----------------------------------------------------------------------------- TOML
@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("polygon = [[0, 0], [1, 0]]\nname = ]\n", r"malformed TOML: .*at line 2, column 8"),
        ("polygon = 'abc'", "key 'polygon' must be a list .* got a string"),
        ("vertices = [[0, 0]]", "key 'blocks' is missing"),
        ("polygon = [[0,0],[1,0],[0,1]]\nblocks = [[0,1,2,3,4]]", "either 'polygon' or"),
        ("name = 3\npolygon = [[0,0],[1,0],[0,1]]", "key 'name' must be a string, got an integer"),
        ("polygn = [[0,0],[1,0],[0,1]]", "unknown key 'polygn'; the keys are"),
        ("description = 'x'", "no geometry"),
        ("polygon = [[0,0],[1,0],[0,1]]\npatches = 3", "key 'patches' must be a table"),
        (
            "polygon = [[0,0],[1,0],[0,1]]\n[patches]\na = 0",
            "patch 'a' must be a list, got an integer",
        ),
        ("polygon = [[0,0],[1,0],[0,1]]\n[regions]\na = [0]", "'regions' needs explicit blocks"),
    ],
)
def test_malformed_toml(text, message):
    with pytest.raises(DomainFormatError, match=message):
        Domain.from_toml_text(text)


def test_file_errors_name_the_file(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        "vertices = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 2]]\nblocks = [[0, 1, 2, 3]]"
    )
    with pytest.raises(DomainFormatError, match=r"bad.toml: block 0 is \[0, 1, 2, 3\]"):
        blockmesh.load_domain(path)
    with pytest.raises(DomainFormatError, match="no such file"):
        blockmesh.load_domain(tmp_path / "missing.toml")


def test_unknown_catalogue_name_suggests():
    with pytest.raises(DomainFormatError, match="Did you mean square, .*square-cut"):
        blockmesh.load_domain("sqare")


def test_toml_round_trip_is_lossless(catalogue_domain, tmp_path):
    path = catalogue_domain.write_toml(tmp_path / "d.toml")
    again = blockmesh.load_domain(path)
    assert np.array_equal(again.vertices, catalogue_domain.vertices)
    assert np.array_equal(again.blocks, catalogue_domain.blocks)
    assert again.patch_names == catalogue_domain.patch_names
    assert np.array_equal(again.boundary_edges, catalogue_domain.boundary_edges)
    assert np.array_equal(again.boundary_patch, catalogue_domain.boundary_patch)
    assert again.region_names == catalogue_domain.region_names
    assert np.array_equal(again.region, catalogue_domain.region)
    assert again.name == catalogue_domain.name
    assert again.description == catalogue_domain.description


def test_awkward_floats_survive_toml(tmp_path):
    angles = np.arange(5) * 2 * np.pi / 5 + 0.1
    coords = np.c_[np.cos(angles), np.sin(angles)] * 1e-7 + [1e3 / 3, -2.0 / 7]
    domain = Domain.from_polygon(coords, name="tiny")
    again = Domain.from_toml_text(domain.to_toml())
    assert np.array_equal(again.vertices, domain.vertices)


# ----------------------------------------------------------------------------- catalogue
def test_catalogue_entries_are_valid(catalogue_domain):
    d = catalogue_domain
    assert d.description, "every catalogue entry has a one-line description"
    xy = d.vertices[d.blocks]
    assert np.all(blockmesh.geometry.is_strictly_convex(xy))
    union = shapely.union_all(shapely.polygons(xy))
    assert union.area == pytest.approx(d.area, rel=1e-12)
    # Every boundary edge is in exactly one patch; every block in one region.
    assert d.boundary_patch.shape == (d.boundary_edges.shape[0],)
    assert d.region.shape == (d.n_blocks,)


def test_catalogue_contents(catalogue):
    expected = {"sp", "usp", "hexagon", "square-cut", "triangle", "square", "heptagon", "octagon"}
    expected |= {"dodecagon", "l-shape", "ring"} | {f"joined-{k}" for k in range(2, 9)}
    expected |= {"backward-step", "t-junction", "channel-obstacle", "l-outline", "plate-octagon"}
    expected |= {"comb", "star", "lake-island", "cook-membrane"}
    assert expected <= set(catalogue)
    for k in range(2, 9):
        assert catalogue[f"joined-{k}"].n_blocks == k
    convex = {
        name: shapely.union_all(shapely.polygons(d.vertices[d.blocks]))
        for name, d in catalogue.items()
    }
    assert any(
        not math.isclose(g.convex_hull.area, g.area)
        for n, g in convex.items()
        if n.startswith("joined")
    )
    assert catalogue["ring"].block_graph().graph["boundary"]
    # The polygon domains carry the names their users give the boundary.
    assert {"inlet", "outlet", "upperWall", "lowerWall"} <= set(
        catalogue["backward-step"].patch_names
    )
    assert {"inlet", "outlet1", "outlet2", "walls"} == set(catalogue["t-junction"].patch_names)
    assert "obstacle" in catalogue["channel-obstacle"].patch_names
    assert {"clamped", "traction", "hole"} <= set(catalogue["plate-octagon"].patch_names)
    assert {"coast", "shore"} == set(catalogue["lake-island"].patch_names)
    for name in ("channel-obstacle", "plate-octagon", "lake-island"):
        union = shapely.union_all(
            shapely.polygons(catalogue[name].vertices[catalogue[name].blocks])
        )
        assert len(union.interiors) == 1
    assert shapely.union_all(
        shapely.polygons(catalogue["ring"].vertices[catalogue["ring"].blocks])
    ).interiors
