"""A Mesh checks itself: inconsistent arrays never make a Mesh; copies stay consistent."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE

import blockmesh
from blockmesh.errors import ArgumentError, ArgumentTypeError, DomainError, TopologyError
from blockmesh.mesh import Mesh


def _arrays(mesh: Mesh) -> dict:
    return {
        "points": mesh.points,
        "cells": mesh.cells,
        "block_id": mesh.block_id,
        "parent": mesh.parent,
        "boundary_edges": mesh.boundary_edges,
        "boundary_patch": mesh.boundary_patch,
        "patch_names": mesh.patch_names,
        "region": mesh.region,
        "region_names": mesh.region_names,
        "level": mesh.level,
        "name": mesh.name,
    }


@pytest.fixture
def two_block():
    return blockmesh.load_domain("joined-2").mesh(1)


def test_the_public_constructor_accepts_a_consistent_mesh(two_block):
    again = Mesh(**_arrays(two_block))
    assert np.array_equal(again.cells, two_block.cells) and again.n_points == two_block.n_points


@pytest.mark.parametrize(
    ("change", "error", "message"),
    [
        (lambda a: a | {"cells": a["cells"] + 1000}, ArgumentError, "cell 0 is .* there are"),
        (lambda a: a | {"cells": a["cells"][:, :4]}, ArgumentError, r"shape \(n, 5\)"),
        (lambda a: a | {"cells": a["cells"].astype(float)}, ArgumentTypeError, "integers"),
        (lambda a: a | {"block_id": a["block_id"][:-1]}, ArgumentError, "block_id has"),
        (lambda a: a | {"parent": a["parent"] - 5}, ArgumentError, "parent of cell 0"),
        (lambda a: a | {"region": a["region"] + 1}, ArgumentError, "region of cell 0"),
        (lambda a: a | {"boundary_patch": a["boundary_patch"] + 3}, ArgumentError, "patch"),
        (lambda a: a | {"boundary_edges": a["boundary_edges"][1:],
                        "boundary_patch": a["boundary_patch"][1:]}, TopologyError, "listed"),
        (lambda a: a | {"boundary_edges": a["boundary_edges"][:, ::-1]}, TopologyError, "directed"),
        (lambda a: a | {"cells": a["cells"][:, ::-1]}, ArgumentError, "clockwise"),
        (lambda a: a | {"points": np.where(a["points"] > 1, np.nan, a["points"])}, ArgumentError,
         "not finite"),
        (lambda a: a | {"patch_names": ("a", "a")}, ArgumentError, "different names"),
        (lambda a: a | {"region_names": "domain"}, ArgumentTypeError, "strings"),
        (lambda a: a | {"level": 1.5}, ArgumentTypeError, "level"),
    ],
)  # fmt: skip
def test_inconsistent_arrays_are_refused_with_the_place(two_block, change, error, message):
    with pytest.raises(error, match=message):
        Mesh(**change(_arrays(two_block)))


def test_the_caller_arrays_are_not_frozen_or_shared(two_block):
    arrays = {
        k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in _arrays(two_block).items()
    }
    mesh = Mesh(**arrays)
    assert arrays["points"].flags.writeable and not mesh.points.flags.writeable
    arrays["points"][0] = 99.0
    assert mesh.points[0, 0] != 99.0


def test_with_copies_keep_the_topology_and_check_what_changes(two_block):
    patches = (np.arange(two_block.boundary_edges.shape[0]) % 2).astype(int)
    split = two_block.with_patches(patches, ("even", "odd"))
    assert split.patch_names == ("even", "odd") and len(split.patch_edges("odd")) > 0
    assert np.array_equal(split.cells, two_block.cells)
    regions = two_block.with_regions(np.zeros(two_block.n_cells, int), ["all"])
    assert regions.region_names == ("all",)
    with pytest.raises(ArgumentError, match="patch"):
        two_block.with_patches(patches + 5, ("even", "odd"))
    moved = two_block.with_points(two_block.points * 3)
    assert moved.area == pytest.approx(9 * two_block.area)
    with pytest.raises(ArgumentError, match="clockwise"):
        two_block.with_points(two_block.points * [-1, 1])
    assert two_block.with_name("other").name == "other"


def test_unknown_patch_names_list_the_known_ones(two_block):
    with pytest.raises(KeyError) as caught:
        two_block.patch_edges("inlet")
    assert str(caught.value) == "no patch 'inlet'; the patches are ground, boundary"


def test_repr_is_one_short_line():
    mesh = blockmesh.load_domain("l-shape").mesh(3)
    text = repr(mesh)
    assert "\n" not in text and len(text) < 200
    assert "l-shape" in text and "5,184 cells" in text and "inlet" in text


@pytest.mark.parametrize("name", CATALOGUE)
@pytest.mark.parametrize("level", [0, 2])
def test_every_catalogue_mesh_passes_its_own_checks(name, level):
    mesh = blockmesh.load_domain(name).mesh(level)
    Mesh(**_arrays(mesh))  # the full constructor checks (orientation, boundary matching)
    mesh.check_geometry()


def test_check_geometry_names_the_first_broken_cell(two_block):
    points = two_block.points.copy()
    inner = int(two_block.cells[5, 0])
    points[inner] = points[two_block.cells[5, 2]]  # collapse a corner onto another: degenerate
    broken = Mesh._trusted(**(_arrays(two_block) | {"points": points}))
    with pytest.raises(DomainError, match="not strictly convex"):
        broken.check_geometry()


def test_measures_do_not_depend_on_where_the_mesh_lies():
    mesh = blockmesh.load_domain("square-cut").mesh(3)
    far = mesh.with_points(mesh.points + 1e9)
    assert far.area == pytest.approx(mesh.area, rel=1e-6)
    near, away = mesh.quality(), far.quality()
    assert away.min_angle == pytest.approx(near.min_angle, abs=1e-3)
    assert away.not_strictly_convex == 0
