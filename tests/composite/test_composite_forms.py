"""Every input form of a composite domain gives the same Domain for the same geometry (issue 23).

TOML ``[[parts]]``, a GeoJSON FeatureCollection, WKT (a MULTIPOLYGON, a GEOMETRYCOLLECTION and
``NAME = WKT`` lines), ``Domain.compose`` of shapely geometries and of Domains (curved ones
included), and ``Domain.from_shapely`` of a MultiPolygon.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely

import blockmesh
from blockmesh import Domain

# Two touching rectangles ("a" then "b") and an L of three (the third overlapping both).
A = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
B = [(1.0, 0.0), (2.5, 0.0), (2.5, 1.0), (1.0, 1.0)]
C = [(0.5, 0.5), (2.0, 0.5), (2.0, 2.0), (0.5, 2.0)]


def same(one: Domain, two: Domain) -> None:
    assert np.array_equal(one.vertices, two.vertices)
    assert np.array_equal(one.blocks, two.blocks)
    assert np.array_equal(one.region, two.region)
    assert one.region_names == two.region_names
    assert np.array_equal(one.interface_edges, two.interface_edges)
    assert one.interface_names == two.interface_names
    assert np.array_equal(one.boundary_edges, two.boundary_edges)


def toml_parts(parts: dict[str, list]) -> str:
    lines = []
    for region, ring in parts.items():
        lines += ["[[parts]]", f'region = "{region}"', f"polygon = {[list(p) for p in ring]}"]
    return "\n".join(lines)


def wkt_polygon(ring) -> str:
    return shapely.Polygon(ring).wkt


@pytest.mark.parametrize("parts", [{"a": A, "b": B}, {"a": A, "b": B, "c": C}], ids=["2", "3"])
def test_every_straight_form_gives_the_same_blocks(tmp_path, parts):
    reference = Domain.from_toml_text(toml_parts(parts), name="parts")
    forms = {}
    collection = {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "properties": {"region": region},
                "geometry": {"type": "Polygon", "coordinates": [[*map(list, ring), list(ring[0])]]},
            }
            for region, ring in parts.items()
        ],
    }
    (tmp_path / "parts.geojson").write_text(json.dumps(collection))
    forms["geojson"] = blockmesh.load_domain(tmp_path / "parts.geojson")
    named = "\n".join(f"{region} = {wkt_polygon(ring)}" for region, ring in parts.items())
    (tmp_path / "named.wkt").write_text(named + "\n")
    forms["wkt lines"] = blockmesh.load_domain(tmp_path / "named.wkt")
    forms["compose"] = Domain.compose({r: shapely.Polygon(ring) for r, ring in parts.items()})
    multi = shapely.MultiPolygon([shapely.Polygon(ring) for ring in parts.values()])
    forms["from_shapely"] = Domain.from_shapely(multi, region=list(parts))
    # Rings given the other way round and from another corner change nothing.
    turned = {r: [*ring[2:], *ring[:2]][::-1] for r, ring in parts.items()}
    forms["turned"] = Domain.compose({r: shapely.Polygon(ring) for r, ring in turned.items()})
    for form, domain in forms.items():
        same(domain, reference), form
    # Unnamed WKT parts are part0, part1, ...: the same blocks under those names.
    (tmp_path / "multi.wkt").write_text(multi.wkt)
    (tmp_path / "collection.wkt").write_text(shapely.GeometryCollection(list(multi.geoms)).wkt)
    for path in ("multi.wkt", "collection.wkt"):
        unnamed = blockmesh.load_domain(tmp_path / path)
        assert unnamed.region_names == tuple(f"part{k}" for k in range(len(parts)))
        assert np.array_equal(unnamed.blocks, reference.blocks)


def test_every_curved_form_gives_the_same_blocks():
    """A fibre in a matrix: a circle part, a Domain disc, or the matrix's hole filled."""
    square = [[0, 0], [2, 0], [2, 2], [0, 2]]
    text = f"""
[[parts]]
region = "matrix"
polygon = {square}
[[parts]]
region = "fibre"
circles = [{{center = [1.0, 1.0], radius = 0.5}}]
"""
    reference = Domain.from_toml_text(text)
    disc = Domain.from_circle((1.0, 1.0), 0.5)
    holed = {"polygon": square, "circles": [{"center": [1.0, 1.0], "radius": 0.5}]}
    plate = Domain.from_polygon(square, circles=[{"center": (1.0, 1.0), "radius": 0.5}])
    forms = {
        "compose a disc Domain": Domain.compose({"matrix": shapely.Polygon(square), "fibre": disc}),
        "compose a table": Domain.compose({"matrix": {"polygon": square}, "fibre": disc}),
        "hole filled (table)": Domain.compose({"matrix": holed, "fibre": disc}),
        "hole filled (Domain)": Domain.compose({"matrix": plate, "fibre": disc}),
    }
    for form, domain in forms.items():
        same(domain, reference), form
    # The fibre keeps a true circle on both sides: every interface vertex is on it.
    ring = reference.vertices[np.unique(reference.interface_edges)]
    assert np.abs(np.hypot(*(ring - 1.0).T) - 0.5).max() < 1e-15
