"""The curved catalogue domains at levels 0-6: nodes on the curves, valid cells, counts, areas."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from curved_references import AREAS
from helpers import CURVED_CATALOGUE

import blockmesh
from blockmesh.curves import Arc
from blockmesh.geometry import is_strictly_convex
from blockmesh.geometry.topology import edge_keys
from blockmesh.refinement.sizes import predict_size

LEVELS = [*range(6), pytest.param(6, marks=pytest.mark.slow)]


@pytest.fixture(scope="module")
def curved():
    return {name: blockmesh.load_domain(name) for name in CURVED_CATALOGUE}


def test_the_curved_catalogue_is_there(curved):
    assert set(curved) == {
        "plate-hole",
        "quarter-plate-hole",
        "disc",
        "annulus",
        "cylinder-channel",
    }
    for domain in curved.values():
        assert domain.curves and all(isinstance(c, Arc) for c in domain.curves.values())
        assert domain.description
    assert curved["cylinder-channel"].patch_names == ("inlet", "outlet", "walls", "cylinder")
    assert set(curved["quarter-plate-hole"].patch_names) == {"hole", "down", "right", "up", "left"}


@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_domain_area_is_the_true_area(curved, name):
    assert curved[name].area == pytest.approx(AREAS[name], rel=1e-14)


def _mesh_invariants(domain, mesh, level):
    size = float(np.hypot(*np.ptp(domain.vertices, axis=0)))
    # Counts: the closed forms of the straight refinement (curves move nodes, not numbers).
    predicted = predict_size(
        domain.n_blocks, domain.n_vertices, domain.n_shared_edges,
        domain.boundary_edges.shape[0], level, level,
    )  # fmt: skip
    assert (mesh.n_cells, mesh.n_points, mesh.n_edges) == (
        predicted.cells,
        predicted.nodes,
        predicted.edges,
    )
    assert mesh.boundary_edges.shape[0] == predicted.boundary_edges
    # Conforming: every edge in one or two cells, the boundary edges exactly those in one.
    keys = edge_keys(mesh.cells, np.roll(mesh.cells, -1, axis=1), mesh.n_points).ravel()
    unique, counts = np.unique(keys, return_counts=True)
    assert set(np.unique(counts).tolist()) <= {1, 2}
    boundary = edge_keys(mesh.boundary_edges[:, 0], mesh.boundary_edges[:, 1], mesh.n_points)
    assert np.array_equal(np.sort(boundary), unique[counts == 1])
    # Every cell strictly convex and counter-clockwise.
    assert np.all(is_strictly_convex(mesh.cell_coordinates()))
    mesh.check_geometry()
    # Every node of a curved patch on its circle, to 1e-12 of the domain's size.
    curved_patches = {
        k for k, name in enumerate(domain.patch_names)
        if any(tuple(e) in domain.curves or tuple(e[::-1]) in domain.curves
               for e in domain.patches[name].tolist())
    }  # fmt: skip
    on_curve = np.isin(mesh.boundary_patch, sorted(curved_patches))
    curve_keys = edge_keys(mesh.curves.edges[:, 0], mesh.curves.edges[:, 1], mesh.n_points)
    assert np.isin(boundary[on_curve], curve_keys).all()
    for k, arc in enumerate(mesh.curves.curves):
        nodes = np.unique(mesh.curves.edges[mesh.curves.curve == k])
        centre, radius = np.array(arc.centre_point), arc.radius
        gap = np.abs(np.hypot(*(mesh.points[nodes] - centre).T) - radius)
        assert gap.max() <= 1e-12 * size
    assert mesh.curves.distances(mesh.points).max() == 0.0


@pytest.mark.parametrize("level", LEVELS)
@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_curved_catalogue_meshes_are_valid(curved, name, level):
    domain = curved[name]
    mesh = domain.mesh(level)
    _mesh_invariants(domain, mesh, level)
    assert len(mesh.curves) == len(domain.curves) * 2**level


@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_nodes_keep_their_places_level_to_level(curved, name):
    domain = curved[name]
    coarse = domain.mesh(2)
    fine = domain.mesh(3)
    assert np.array_equal(fine.points[: coarse.n_points], coarse.points)
    assert np.array_equal(fine.cells.reshape(-1, 6, 5)[:, :5, 0], coarse.cells)


@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_straight_area_converges_at_second_order(curved, name):
    true = AREAS[name]
    errors = [true - curved[name].mesh(level).area for level in range(1, 6)]
    ratios = [a / b for a, b in itertools.pairwise(errors)]
    # Chords cut the bulges off convex arcs and add the hole's segments on concave ones: the
    # error keeps its sign and shrinks four times per level.
    assert all(3.5 < r < 4.5 for r in ratios[1:]), ratios


@pytest.mark.parametrize("level", [0, 3])
@pytest.mark.parametrize("name", CURVED_CATALOGUE)
def test_curved_area_is_exact_at_every_level(curved, name, level):
    mesh = curved[name].mesh(level)
    assert mesh.curved_area == pytest.approx(AREAS[name], rel=1e-14)
    assert abs(mesh.area - AREAS[name]) > 1e-9
