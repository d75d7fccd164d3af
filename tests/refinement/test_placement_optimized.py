"""Node placement (blockmesh.refinement.improve): catalogue invariants, nesting, bad input."""

from __future__ import annotations

import itertools
import os
import subprocess
import sys

import numpy as np
import pytest
from helpers import CATALOGUE, sweep

import blockmesh
from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.geometry import is_strictly_convex
from blockmesh.refinement.improve import (
    ANGLE_TIE,
    _pick_fraction,
    inner_point_rule,
    optimize_nodes,
    refine_with_rule,
    shape_energy,
)


def _fixed_boundary_nodes(mesh):
    """Boundary nodes at a domain corner or where the patch changes."""
    edges, patch = mesh.boundary_edges, mesh.boundary_patch
    out_edge = {int(a): k for k, (a, _) in enumerate(edges)}
    in_edge = {int(b): k for k, (_, b) in enumerate(edges)}
    fixed = []
    for node in np.unique(edges):
        before, after = edges[in_edge[node]], edges[out_edge[node]]
        t_in = mesh.points[node] - mesh.points[before[0]]
        t_out = mesh.points[after[1]] - mesh.points[node]
        turn = abs(t_in[0] * t_out[1] - t_in[1] * t_out[0])
        if turn > 1e-9 * np.hypot(*t_in) * np.hypot(*t_out) or (
            patch[in_edge[node]] != patch[out_edge[node]]
        ):
            fixed.append(node)
    return np.array(fixed)


@pytest.mark.parametrize("name", sweep(CATALOGUE))
def test_optimized_nodes_keep_the_mesh_and_improve_its_shapes(name):
    mesh = blockmesh.load_domain(name).mesh(2)
    better, report = optimize_nodes(mesh, iterations=60, report=True)
    assert np.array_equal(better.cells, mesh.cells)
    assert np.array_equal(better.boundary_edges, mesh.boundary_edges)
    assert better.patch_names == mesh.patch_names and better.region_names == mesh.region_names
    assert np.all(is_strictly_convex(better.points[better.cells]))
    assert abs(better.area - mesh.area) < 1e-12 * mesh.area  # the boundary did not move
    fixed = _fixed_boundary_nodes(mesh)
    assert np.array_equal(better.points[fixed], mesh.points[fixed])
    # sliding nodes stay on their boundary edge's line
    a, b = mesh.points[mesh.boundary_edges[:, 0]], mesh.points[mesh.boundary_edges[:, 1]]
    moved = better.points[mesh.boundary_edges[:, 0]]
    along, off = b - a, moved - a
    gap = np.abs(along[:, 0] * off[:, 1] - along[:, 1] * off[:, 0]) / np.hypot(*along.T)
    assert gap.max() < 1e-12 * np.ptp(mesh.points).max()
    assert report.energy_after < report.energy_before
    corners_only = optimize_nodes(mesh, size_weight=0, iterations=30)  # distortion alone
    assert shape_energy(corners_only) < shape_energy(mesh)
    assert report.moving_nodes == mesh.n_points - np.unique(mesh.boundary_edges).size


def test_block_edge_nodes_move_too():
    domain = blockmesh.load_domain("square-cut")
    mesh = domain.mesh(2)
    better = optimize_nodes(mesh, iterations=40)
    shared = np.setdiff1d(
        np.unique(domain.mesh(0).cells), np.unique(domain.mesh(0).boundary_edges)
    )  # the block vertex inside the domain
    assert shared.size and np.all(np.any(better.points[shared] != mesh.points[shared], axis=1))


def test_optimized_refinement_keeps_counts_and_raises_the_worst_angle():
    domain = blockmesh.load_domain("sp")
    paper = domain.mesh(4)
    better = refine_with_rule(domain, 4, rule="optimized", iterations=60)
    assert (better.n_cells, better.n_points) == (paper.n_cells, paper.n_points)
    assert np.array_equal(better.cells, paper.cells)
    assert better.quality().min_angle > paper.quality().min_angle + 10
    assert refine_with_rule(domain, 2).points.tobytes() == domain.mesh(2).points.tobytes()


def test_inner_point_rule_is_nested_and_valid():
    domain = blockmesh.load_domain("usp")
    coarse = inner_point_rule(domain, 2)
    fine = inner_point_rule(domain, 3)
    assert np.array_equal(fine.points[: coarse.n_points], coarse.points)  # old nodes stay
    assert fine.n_cells == 216 and fine.quality().not_strictly_convex == 0


def test_inner_point_rule_does_not_depend_on_the_order_of_its_candidates():
    # On the square every t gives the same worst angle to rounding (the worst corners are not
    # next to the inner points): the choice must not fall to the first candidate or to noise.
    square = blockmesh.load_domain("square")
    fractions = (0.35, 0.4, 0.45, 0.5, 0.55, 0.6)
    meshes = [
        inner_point_rule(square, 2, fractions=order)
        for order in (fractions, fractions[::-1], (0.45, 0.6, 0.35, 0.55, 0.5, 0.4))
    ]
    assert all(m.points.tobytes() == meshes[0].points.tobytes() for m in meshes[1:])
    assert meshes[0].points.tobytes() == square.mesh(2).points.tobytes()  # the tie goes to 1/2


def test_tied_worst_angles_are_broken_the_same_way_in_any_order():
    fractions = np.array([0.35, 0.4, 0.55, 0.6, 0.45])
    noise = np.array([0.0, 3e-14, -3e-14, 2e-14, -1e-14])  # equal angles but for rounding
    chosen = set()
    for order in itertools.permutations(range(fractions.size)):
        index = list(order)
        for sign in (1, -1):
            angles = 30.0 + sign * noise[index]
            chosen.add(float(fractions[index][_pick_fraction(fractions[index], angles)]))
    assert chosen == {0.45}  # the one nearest 1/2 (0.55 is as near: the smaller wins)
    # A real difference (more than the tie) still wins, and invalid candidates never do.
    angles = np.array([30.0, 30.0 + 10 * ANGLE_TIE, 30.0, -np.inf, 30.0])
    assert _pick_fraction(fractions, angles) == 1
    assert _pick_fraction(fractions, np.full(5, -np.inf)) is None


_PLACEMENT = """
import hashlib, blockmesh
from blockmesh.improve import optimize_nodes
mesh = optimize_nodes(blockmesh.load_domain("square").mesh(4), iterations=10)
print(hashlib.sha256(mesh.points.tobytes()).hexdigest())
"""


def test_optimized_placement_is_the_same_bits_for_any_blas_thread_count():
    # 26,000 free coordinates at level 4: long enough for OpenBLAS to split a dot product over
    # its threads (it does above about 10,000 entries), which made the runs differ.
    digests = set()
    for threads in ("1", "2"):
        env = {**os.environ, "OPENBLAS_NUM_THREADS": threads, "OMP_NUM_THREADS": threads}
        run = subprocess.run(
            [sys.executable, "-c", _PLACEMENT], env=env, capture_output=True, text=True, timeout=600
        )
        assert run.returncode == 0, run.stderr
        digests.add(run.stdout.strip())
    assert len(digests) == 1, digests


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (lambda m: inner_point_rule(m, 1, fractions=()), ArgumentError, "non-empty sequence"),
        (lambda m: inner_point_rule(m, 1, fractions=(0.4, 1.0)), ArgumentError, r"\[1\] = 1\.0"),
        (lambda m: inner_point_rule(m, 1, fractions="half"), ArgumentTypeError, "numbers"),
        (lambda m: optimize_nodes("mesh"), ArgumentTypeError, "mesh must be a blockmesh Mesh"),
        (lambda m: optimize_nodes(m, iterations=-1), ArgumentError, "iterations must be"),
        (lambda m: optimize_nodes(m, size_weight=-1), ArgumentError, "size_weight must be"),
        (lambda m: refine_with_rule(m, 1, rule="best"), ArgumentError, "unknown quality rule"),
    ],
)
def test_bad_arguments(call, error, match):
    with pytest.raises(error, match=match):
        call(blockmesh.load_domain("sp").mesh(1))
