"""Quality across blocks on decomposed domains: the ``angles`` node placement (issue 8, item 6).

Every node off the domain boundary moves (block-edge nodes included), boundary nodes slide along
their own straight edge, corners and patch ends stay, every cell stays strictly convex and the
cells, counts, patches and regions are the paper's.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
from helpers import run_cli

from blockmesh import Domain, load_domain
from blockmesh.errors import ArgumentError
from blockmesh.geometry import is_strictly_convex
from blockmesh.refinement.improve import optimize_nodes, refine_with_rule

OUTLINE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
PATCHES = {"outlet": [1], "inlet": [4], "walls": [0, 2, 3, 5]}
#: Where the patches change along straight runs is a corner of OUTLINE here; one more split:
STRAIGHT = [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
STRAIGHT_PATCHES = {"inflow": [0], "walls": [1, 2, 3, 4, 5, 6]}


@pytest.fixture(scope="module")
def meshes():
    domain = Domain.from_polygon(STRAIGHT, patches=STRAIGHT_PATCHES)
    return domain, domain.mesh(2), refine_with_rule(domain, 2, rule="angles")


def test_same_cells_counts_patches_and_area(meshes):
    domain, paper, better = meshes
    assert np.array_equal(better.cells, paper.cells)
    assert better.n_points == paper.n_points
    assert np.array_equal(better.boundary_edges, paper.boundary_edges)
    assert np.array_equal(better.boundary_patch, paper.boundary_patch)
    assert better.patch_names == paper.patch_names
    assert np.all(is_strictly_convex(better.points[better.cells]))
    assert better.quality().not_strictly_convex == 0
    assert better.area == pytest.approx(shapely.Polygon(STRAIGHT).area, rel=1e-12)


def test_every_node_off_the_boundary_moves_block_edges_included(meshes):
    domain, paper, better = meshes
    on_boundary = np.zeros(paper.n_points, dtype=bool)
    on_boundary[paper.boundary_edges] = True
    # Block vertices keep their ids in the nested numbering; the inner ones sit on block edges.
    block_vertex = np.arange(paper.n_points) < domain.n_vertices
    moved = np.any(better.points != paper.points, axis=1)
    assert moved[block_vertex & ~on_boundary].all()
    assert moved[~on_boundary].mean() > 0.99


def test_boundary_nodes_slide_on_their_edge_corners_and_patch_ends_stay(meshes):
    domain, paper, better = meshes
    nodes = np.unique(paper.boundary_edges)
    outline = shapely.Polygon(STRAIGHT).exterior
    distance = shapely.distance(shapely.points(better.points[nodes]), outline)
    assert distance.max() <= 1e-12
    assert np.any(better.points[nodes] != paper.points[nodes])  # some of them slide
    fixed = [i for i in nodes if tuple(paper.points[i]) in {tuple(map(float, p)) for p in STRAIGHT}]
    assert len(fixed) == len(STRAIGHT)  # (1, 0) is where inflow meets walls: kept and fixed
    assert np.array_equal(better.points[fixed], paper.points[fixed])


@pytest.mark.parametrize("name", ["t-junction", "star"])
def test_worst_angle_raised_on_decomposed_catalogue_domains(name):
    domain = load_domain(name)
    paper, better = domain.mesh(2), refine_with_rule(domain, 2, rule="angles")
    assert better.n_cells == paper.n_cells and better.n_points == paper.n_points
    assert better.quality().min_angle > paper.quality().min_angle + 3.0
    assert better.quality().max_angle < paper.quality().max_angle


def test_curved_boundary_nodes_stay_on_the_curve():
    domain = load_domain("plate-hole")  # a circular hole of radius 0.5 about the origin
    better = refine_with_rule(domain, 2, rule="angles")
    nodes = np.unique(better.boundary_edges)
    radius = np.hypot(*better.points[nodes].T)
    on_hole = radius < 1.0
    assert np.count_nonzero(on_hole) > 16
    assert np.abs(radius[on_hole] - 0.5).max() <= 1e-12
    assert better.quality().not_strictly_convex == 0


def test_options_are_checked():
    mesh = load_domain("sp").mesh(1)
    with pytest.raises(ArgumentError, match="power must be"):
        optimize_nodes(mesh, power=0.5)
    with pytest.raises(ArgumentError, match="unknown size target"):
        optimize_nodes(mesh, size_target="blocks")


def test_cli_quality_rule_angles(capsys):
    code, stdout, _ = run_cli(capsys, "mesh", "l-outline", "--level", "2", "--json")
    paper = json.loads(stdout)
    code, stdout, _ = run_cli(
        capsys, "mesh", "l-outline", "--level", "2", "--quality-rule", "angles", "--json"
    )
    better = json.loads(stdout)
    assert code == 0 and better["quality_rule"] == "angles"
    assert better["cells"] == paper["cells"] and better["nodes"] == paper["nodes"]
    assert better["quality"]["min_angle"] > paper["quality"]["min_angle"]
    assert better["quality"]["not_strictly_convex"] == 0
