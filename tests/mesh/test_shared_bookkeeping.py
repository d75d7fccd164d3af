"""A Mesh and a PolygonMesh keep patches, regions, interfaces and numbering alike.

The bookkeeping both mesh kinds share has one home (``blockmesh.mesh.arrays``, ``labels``,
``numbering``): the same inputs give the same results through either class, and the same bad
inputs the same errors, named after the class.
"""

from __future__ import annotations

import numpy as np
import pytest

import blockmesh
from blockmesh.errors import ArgumentError, ArgumentTypeError, UnknownNameError
from blockmesh.mesh import Mesh, MeshQuality, PolygonMesh


@pytest.fixture(params=["joined-2", "layered-plate", "disc"])
def pair(request) -> tuple[Mesh, PolygonMesh]:
    mesh = blockmesh.load_domain(request.param).mesh(1)
    return mesh, PolygonMesh.from_mesh(mesh)


def _same_mesh(a: Mesh, b: Mesh) -> bool:
    names = ("points", "cells", "block_id", "parent", "boundary_edges", "boundary_patch",
             "region", "interface_edges", "interface_patch")  # fmt: skip
    arrays = all(np.array_equal(getattr(a, n), getattr(b, n)) for n in names)
    labels = (a.patch_names, a.region_names, a.interface_names, a.level, a.name) == (
        b.patch_names, b.region_names, b.interface_names, b.level, b.name
    )  # fmt: skip
    return arrays and labels


def test_relabelled_copies_agree_through_either_class(pair):
    mesh, polygons = pair
    patch = np.arange(mesh.boundary_edges.shape[0]) % 2
    region = np.arange(mesh.n_cells) % 3
    for change in (
        lambda m: m.with_patches(patch, ["even", "odd"]),
        lambda m: m.with_regions(region, ["a", "b", "c"]),
        lambda m: m.with_points(m.points * 2.0),
        lambda m: m.with_name("copy"),
        lambda m: m.renumbered(np.arange(m.n_points)[::-1]),
    ):
        assert _same_mesh(change(polygons).to_mesh(), change(mesh))
    assert {k: v.tolist() for k, v in polygons.interfaces.items()} == {
        k: v.tolist() for k, v in mesh.interfaces.items()
    }
    assert np.array_equal(polygons.interface_cells(), mesh.interface_cells())
    for name in mesh.patch_names:
        assert np.array_equal(polygons.patch_edges(name), mesh.patch_edges(name))


def test_a_copy_leaves_the_original_and_its_caches_alone(pair):
    mesh, polygons = pair
    for m in (mesh, polygons):
        before = m.quality()
        other = m.with_points(m.points * 3.0)
        assert m.quality() == before
        assert other.quality().max_area == pytest.approx(9 * before.max_area)


@pytest.mark.parametrize(
    ("change", "error", "message"),
    [
        (lambda m: m.with_patches(m.boundary_patch, ["a", "a"]), ArgumentError,
         "patch_names must be different names"),
        (lambda m: m.with_patches(m.boundary_patch[1:], m.patch_names), ArgumentError,
         "boundary_patch has"),
        (lambda m: m.with_regions(m.region + 5, m.region_names), ArgumentError, "region"),
        (lambda m: m.with_interfaces(m.interface_edges, m.interface_patch, m.patch_names[:1]),
         ArgumentError, "name of a boundary patch"),
        (lambda m: m.with_interfaces(m.boundary_edges[:1], [0], ["glue"]), ArgumentError,
         "interface edge 0"),
        (lambda m: m.renumbered(np.zeros(m.n_points, int)), ArgumentError, "permutation"),
        (lambda m: m.renumbered({"not": "ids"}), ArgumentTypeError, "order must be"),
        (lambda m: m.patch_edges("nowhere"), UnknownNameError, "no patch 'nowhere'"),
    ],
)  # fmt: skip
def test_bad_bookkeeping_is_refused_alike(pair, change, error, message):
    mesh, polygons = pair
    for m, kind in ((mesh, "Mesh"), (polygons, "PolygonMesh")):
        with pytest.raises(error, match=message) as caught:
            change(m)
        if message in ("patch_names must be different names", "boundary_patch has"):
            assert str(caught.value).startswith(f"{kind} ")


def test_quality_records_agree_and_find_their_area_ratio(pair):
    mesh, polygons = pair
    a, b = mesh.quality(), polygons.quality()
    assert a.not_strictly_convex == b.not_strictly_convex == 0
    assert a.min_area == pytest.approx(b.min_area) and a.max_area == pytest.approx(b.max_area)
    assert a.area_ratio == pytest.approx(a.min_area / a.max_area)
    empty = MeshQuality.of(
        min_angle=0.0, max_angle=0.0, max_aspect_ratio=0.0, min_area=0.0, max_area=0.0,
        not_strictly_convex=0,
    )  # fmt: skip
    assert empty.area_ratio == 0.0


def test_bandwidth_and_rcm_agree_through_either_class(pair):
    mesh, polygons = pair
    assert polygons.bandwidth() == mesh.bandwidth()
    rcm = mesh.with_rcm_numbering()
    assert PolygonMesh.from_mesh(rcm).bandwidth() == rcm.bandwidth()
