"""Where domains come from: polygons with holes and patch strings, shapely, WKT, GeoJSON, the CLI,
blocks glued with merge_tol, and the polygon-edge correspondence."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import shapely
from helpers import assert_blocks_tile, assert_patches_follow_edges, run_cli

import blockmesh
from blockmesh import ArgumentTypeError, BlockMeshWarning, Domain, DomainError, DomainFormatError

PLATE = [(0, 0), (4, 0), (4, 2), (0, 2)]
HOLE = [(1.5, 0.5), (2.5, 0.5), (2.5, 1.5), (1.5, 1.5)]
SMALL = [(3.2, 0.2), (3.6, 0.2), (3.4, 0.5)]


# ----------------------------------------------------------------------------- holes and patches
def test_plate_with_holes_and_patch_strings():
    domain = Domain.from_polygon(
        PLATE,
        [HOLE, SMALL],
        patches={"inlet": [3], "outlet": [1], "walls": [0, 2], "cylinder": ["hole 0"],
                 "tip": ["hole 1:0"]},
    )  # fmt: skip
    assert domain.patch_names == ("inlet", "outlet", "walls", "cylinder", "tip", "boundary")
    polygon = shapely.Polygon(PLATE, [HOLE, SMALL])
    assert_blocks_tile(domain, polygon)
    names = {0: "walls", 1: "outlet", 2: "walls", 3: "inlet"}

    def expected(ring, edge):
        if ring == 0:
            return names[edge]
        if ring == 1:
            return "cylinder"
        return "tip" if edge == 0 else "boundary"

    assert_patches_follow_edges(
        domain, [np.array(r, float) for r in (PLATE, HOLE, SMALL)], expected
    )
    # Euler characteristic 1 - h.
    euler = (
        domain.n_vertices - (domain.n_shared_edges + len(domain.boundary_edges)) + domain.n_blocks
    )
    assert euler == 1 - 2


def test_holes_may_run_either_way_round_without_a_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error", BlockMeshWarning)
        one = Domain.from_polygon(PLATE, [HOLE])
        two = Domain.from_polygon(PLATE, [HOLE[::-1]])
    assert one.area == pytest.approx(two.area) == pytest.approx(7.0)


def test_hole_edge_numbers_follow_the_input_order_even_reversed():
    # Hole given clockwise: its edge 0 still runs from its corner 0 to corner 1 as given.
    hole = HOLE[::-1]  # (1.5,1.5) -> (2.5,1.5) -> ... ; edge 0 is the top side
    domain = Domain.from_polygon(PLATE, [hole], patches={"top": ["hole 0:0"]})
    top = domain.vertices[domain.patches["top"]]
    assert np.all(top[:, :, 1] == 1.5)
    chain = domain.polygon_edges[(1, 0)]
    assert {tuple(domain.vertices[chain[0]]), tuple(domain.vertices[chain[-1]])} == {
        (1.5, 1.5),
        (2.5, 1.5),
    }


@pytest.mark.parametrize(
    ("holes", "patches", "kind", "message"),
    [
        ([HOLE], {"a": ["hole 1"]}, DomainError, r"names hole 1, but the polygon has holes 0..0"),
        ([], {"a": ["hole 0"]}, DomainError, "names hole 0, but the polygon has no holes"),
        (
            [HOLE],
            {"a": ["hole 0:4"]},
            DomainError,
            r"edge 4 of hole 0, whose edges are numbered 0..3",
        ),
        ([HOLE], {"a": ["hole"]}, DomainFormatError, r"has 'hole'; for a polygon, a patch lists"),
        ([HOLE], {"a": [1.5]}, DomainFormatError, r"has 1.5; for a polygon"),
        (
            [HOLE],
            {"a": ["hole 0"], "b": ["hole 0:1"]},
            DomainError,
            r"hole 0 edge 1 is in patches 'a' and 'b'",
        ),
        (
            [HOLE],
            {"a": [9]},
            DomainError,
            r"names edge 9, but the polygon's edges are numbered 0..3",
        ),
    ],
)
def test_patch_string_errors(holes, patches, kind, message):
    with pytest.raises(kind, match=message):
        Domain.from_polygon(PLATE, holes, patches=patches)


@pytest.mark.parametrize(
    ("holes", "message"),
    [
        (
            [[(5, 5), (6, 5), (6, 6)]],
            r"hole 0 is not inside the polygon: its vertex 0 \(5, 5\) is outside",
        ),
        ([[(3, 1), (5, 1), (4, 1.5)]], "hole 0 edge .* cross"),
        ([HOLE, [(2, 1), (3, 1), (2.5, 1.8)]], "hole 0 edge .* and hole 1 edge .* cross"),
        ([HOLE, [(1.8, 0.8), (2.2, 0.8), (2.0, 1.2)]], "hole 1 lies inside hole 0"),
        (
            [[(0, 0), (1, 0.5), (0.5, 1)]],
            r"vertex 0 \(0, 0\) and hole 0 vertex 0 \(0, 0\) are the same point",
        ),
        ([[(1, 0), (2, 1), (1, 1)]], "touch"),
        ([[(1, 1e-8), (2, 1), (1, 1)]], "comes within 1e-08 of the polygon"),
        ([[(1, 1), (2, 1), (3, 1)]], "hole 0 has zero area"),
        ([[(1, 1), (2, 1)]], "hole 0 needs at least 3 vertices, got 2"),
        ([[(1, 0.5), (2, 1.5), (2, 0.5), (1, 1.5)]], "hole 0.s edges 0 and 2 cross"),
        ("abc", "holes must be a list of rings"),
        ([[(1, 1), (2, "x"), (2, 2)]], "hole 0 vertex 1 has a y coordinate that is not a number"),
    ],
)
def test_bad_holes_are_named(holes, message):
    with pytest.raises(DomainError, match=message):
        Domain.from_polygon(PLATE, holes)


# ----------------------------------------------------------------------------- correspondence
def test_boundary_source_and_polygon_edges():
    domain = Domain.from_polygon(PLATE, [HOLE])
    assert domain.boundary_source.shape == (len(domain.boundary_edges), 2)
    chains = domain.polygon_edges
    assert set(chains) == {(0, e) for e in range(4)} | {(1, e) for e in range(4)}
    for (ring, edge), chain in chains.items():
        ends = {tuple(domain.vertices[chain[0]]), tuple(domain.vertices[chain[-1]])}
        corners = [PLATE, HOLE][ring]
        assert ends == {
            tuple(map(float, corners[edge])),
            tuple(map(float, corners[(edge + 1) % 4])),
        }
        assert len(chain) >= 2
    blocks = blockmesh.load_domain("square-cut")
    assert np.all(blocks.boundary_source == -1) and not blocks.polygon_edges


def test_dropped_straight_corners_keep_the_input_edges_apart():
    # Vertex 1 is straight and both its edges are in one patch: dropped, but each block edge still
    # knows which of the two input edges it lies on.
    outer = [(0, 0), (2, 0), (4, 0), (4, 2), (0, 2)]
    with pytest.warns(BlockMeshWarning, match=r"vertex 1 \(2, 0\) lies on a straight line"):
        domain = Domain.from_polygon(outer, patches={"floor": [0, 1]})
    for (a, b), (ring, edge) in zip(domain.boundary_edges, domain.boundary_source, strict=True):
        assert ring == 0
        middle = (domain.vertices[a] + domain.vertices[b]) / 2
        if edge == 0:
            assert middle[1] == 0.0 and middle[0] < 2.0
        if edge == 1:
            assert middle[1] == 0.0 and middle[0] > 2.0


# ----------------------------------------------------------------------------- shapely, WKT, JSON
def test_from_shapely():
    ring = shapely.Point(0, 0).buffer(2, quad_segs=4).difference(shapely.box(-1, -1, 1, 1))
    domain = Domain.from_shapely(ring, patches={"inner": ["hole 0"]}, name="ring")
    assert domain.name == "ring" and domain.patch_names == ("inner", "boundary")
    assert_blocks_tile(domain, ring)
    # A MultiPolygon is a composite domain (issue 23): its pieces are regions, here apart.
    two = Domain.from_shapely(
        shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)])
    )
    assert two.region_names == ("part0", "part1") and two.components == 2
    with pytest.raises(ArgumentTypeError, match="takes a shapely Polygon or MultiPolygon, got Li"):
        Domain.from_shapely(shapely.LineString([(0, 0), (1, 1)]))


def test_wkt_file(tmp_path):
    path = tmp_path / "plate.wkt"
    path.write_text(shapely.Polygon(PLATE, [HOLE]).wkt)
    domain = blockmesh.load_domain(path)
    assert domain.name == "plate" and domain.area == pytest.approx(7.0, rel=1e-12)
    (tmp_path / "bad.wkt").write_text("POLYGON ((0 0, 1 0")
    with pytest.raises(DomainFormatError, match="bad.wkt: not Well-Known Text"):
        blockmesh.load_domain(tmp_path / "bad.wkt")
    (tmp_path / "line.wkt").write_text("LINESTRING (0 0, 1 1)")
    with pytest.raises(DomainFormatError, match="line.wkt: expected one Polygon, got a LineString"):
        blockmesh.load_domain(tmp_path / "line.wkt")


def _geojson(coordinates, properties=None, kind="Polygon"):
    feature = {"type": "Feature", "geometry": {"type": kind, "coordinates": coordinates}}
    feature["properties"] = properties or {}
    return {"type": "FeatureCollection", "features": [feature]}


def test_geojson_file_with_named_patches(tmp_path):
    # A lake in a field, lon/lat-like numbers with an altitude, closed rings as GeoJSON has them.
    shell = [[10.0, 50.0, 3], [10.4, 50.0, 3], [10.4, 50.3, 3], [10.0, 50.3, 3], [10.0, 50.0, 3]]
    lake = [[10.1, 50.1], [10.2, 50.1], [10.15, 50.2], [10.1, 50.1]]
    properties = {"name": "field", "description": "a field with a lake",
                  "patches": {"south": [0], "shore": ["hole 0"]}}  # fmt: skip
    path = tmp_path / "field.geojson"
    path.write_text(json.dumps(_geojson([shell, lake], properties)))
    domain = blockmesh.load_domain(path)
    assert domain.name == "field" and domain.description == "a field with a lake"
    assert domain.patch_names == ("south", "shore", "boundary")
    south = domain.vertices[domain.patches["south"]]
    assert np.all(south[:, :, 1] == 50.0)
    polygon = shapely.Polygon([p[:2] for p in shell], [lake])
    assert domain.area == pytest.approx(polygon.area, rel=1e-12)
    # A bare geometry works too; a collection of two features is a composite domain (issue
    # 23), here of two equal parts: the later one covers the earlier entirely.
    bare = tmp_path / "bare.json"
    bare.write_text(json.dumps({"type": "Polygon", "coordinates": [shell]}))
    assert blockmesh.load_domain(bare).name == "bare"
    two = _geojson([shell])
    two["features"] *= 2
    (tmp_path / "two.geojson").write_text(json.dumps(two))
    with pytest.raises(DomainError, match=r"part 0 \('part0'\) is covered entirely by the later"):
        blockmesh.load_domain(tmp_path / "two.geojson")
    (tmp_path / "bad.geojson").write_text("{")
    with pytest.raises(DomainFormatError, match="bad.geojson: not JSON"):
        blockmesh.load_domain(tmp_path / "bad.geojson")
    (tmp_path / "point.geojson").write_text(json.dumps({"type": "Point", "coordinates": [0, 0]}))
    with pytest.raises(DomainFormatError, match="expected a Polygon geometry"):
        blockmesh.load_domain(tmp_path / "point.geojson")


# ----------------------------------------------------------------------------- TOML, CLI
def test_toml_polygon_with_holes_and_round_trip(tmp_path):
    text = """
name = "plate"
polygon = [[0, 0], [4, 0], [4, 2], [0, 2]]
holes = [[[1.5, 0.5], [2.5, 0.5], [2.5, 1.5], [1.5, 1.5]]]
[patches]
inlet = [3]
cylinder = ["hole 0"]
"""
    domain = Domain.from_toml_text(text)
    assert domain.patch_names == ("inlet", "cylinder", "boundary")
    again = blockmesh.load_domain(domain.write_toml(tmp_path / "plate.toml"))
    assert np.array_equal(again.blocks, domain.blocks) and again.patch_names == domain.patch_names
    with pytest.raises(DomainFormatError, match="'holes' belong to a 'polygon'"):
        Domain.from_toml_text("vertices = [[0, 0]]\nblocks = [[0, 1, 2, 3, 4]]\nholes = []")
    with pytest.raises(DomainFormatError, match="key 'holes' must be a list"):
        Domain.from_toml_text("polygon = [[0, 0], [1, 0], [0, 1]]\nholes = 3")


def test_cli_polygon_with_holes(capsys, tmp_path):
    code, out, err = run_cli(
        capsys, "check", "--polygon", "0,0 4,0 4,2 0,2",
        "--hole", "1.5,0.5 2.5,0.5 2.5,1.5 1.5,1.5", "--hole", "3.2,0.2 3.6,0.2 3.4,0.5", "--json",
    )  # fmt: skip
    report = json.loads(out)
    assert code == 0 and report["holes"] == 2 and report["layout"] == "triangulation"
    code, _, err = run_cli(capsys, "check", "--hole", "1,1 2,1 2,2")
    assert code == 1 and "--hole adds a hole to --polygon" in err
    code, _, err = run_cli(capsys, "check", "--polygon", "0,0 4,0 4,2 0,2", "--hole", "1,1 2;1")
    assert code == 1 and "--hole: hole 0: token 2 '2;1'" in err
    picture = tmp_path / "plate.png"
    code, _, err = run_cli(
        capsys, "show", "--polygon", "0,0 4,0 4,2 0,2", "--hole", "1.5,0.5 2.5,0.5 2.5,1.5", "-o",
        str(picture),
    )  # fmt: skip
    assert code == 0 and picture.stat().st_size > 0
    code, out, _ = run_cli(
        capsys, "mesh", "--polygon", "0,0 4,0 4,2 0,2", "--hole", "1.5,0.5 2.5,0.5 2.5,1.5",
        "--level", "1", "--json",
    )  # fmt: skip
    assert code == 0 and json.loads(out)["area"] == pytest.approx(7.5)


def test_cli_geojson_domain(capsys, tmp_path):
    path = tmp_path / "lake.geojson"
    shell = [[0, 0], [3, 0], [3, 2], [0, 2], [0, 0]]
    path.write_text(json.dumps(_geojson([shell, [[1, 0.5], [2, 0.5], [1.5, 1.5], [1, 0.5]]])))
    code, out, err = run_cli(capsys, "check", str(path))
    assert code == 0, err
    assert "1 hole" in out


# ----------------------------------------------------------------------------- merge_tol
def test_blocks_made_apart_are_glued_with_merge_tol():
    left = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2)]
    right = [(2 + 1e-10, 0), (4, 0), (4.5, 1), (4, 2), (2.5, 1 - 1e-10)]
    vertices, blocks = left + right, [(0, 1, 2, 3, 4), (5, 6, 7, 8, 9)]
    with pytest.raises(blockmesh.TopologyError):
        Domain.from_blocks(vertices, blocks)
    domain = Domain.from_blocks(
        vertices, blocks, {"far": [(6, 7)], "near": [(4, 0)]}, merge_tol=1e-6
    )
    assert domain.n_vertices == 8 and domain.n_shared_edges == 1
    assert domain.vertices[domain.patches["far"]].tolist() == [[[4.0, 0.0], [4.5, 1.0]]]
    assert domain.vertices[domain.patches["near"]].tolist() == [[[0.0, 2.0], [0.0, 0.0]]]
    with pytest.raises(DomainFormatError, match="merge_tol must be a distance >= 0"):
        Domain.from_blocks(vertices, blocks, merge_tol=-1.0)


def test_toml_keeps_the_correspondence_and_the_element_sources(tmp_path):
    import meshio

    plate = Domain.from_polygon(PLATE, [HOLE], patches={"cylinder": ["hole 0"]})
    again = blockmesh.load_domain(plate.write_toml(tmp_path / "plate.toml"))
    assert np.array_equal(again.boundary_source, plate.boundary_source)
    assert {k: v.tolist() for k, v in again.polygon_edges.items()} == {
        k: v.tolist() for k, v in plate.polygon_edges.items()
    }
    square = meshio.Mesh(
        np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]]), [("quad", np.array([[0, 1, 2, 3]]))]
    )
    converted = Domain.from_mesh(square)
    assert np.array_equal(
        Domain.from_toml_text(converted.to_toml()).block_source, converted.block_source
    )
    sp = "vertices = [[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]]\nblocks = [[0, 1, 2, 3, 4]]\n"
    with pytest.raises(
        DomainError, match=r"block_source must have one entry per block, shape \(1,\)"
    ):
        Domain.from_toml_text(sp + "block_source = [0, 1]")
    with pytest.raises(DomainFormatError, match=r"boundary_source row 0 is \[0, 1, 2\]"):
        Domain.from_toml_text(sp + "boundary_source = [[0, 1, 2]]")
    with pytest.raises(DomainFormatError, match="'block_source' belongs to explicit blocks"):
        Domain.from_toml_text("polygon = [[0, 0], [1, 0], [0, 1]]\nblock_source = [0]")
