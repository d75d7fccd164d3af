"""Refinement with curved edges: the straight cells untouched, shared curves, refining in steps,
renumbering, smoothing, and random blocks with random arcs."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import USP, examples
from hypothesis import event, given, settings
from hypothesis import strategies as st

import blockmesh
import blockmesh.refinement.grouped
from blockmesh import Domain
from blockmesh.curves import Arc, Spline
from blockmesh.errors import DomainError
from blockmesh.geometry import is_strictly_convex

#: Catalogue domains with curved edges.
CURVED_CATALOGUE = ("annulus", "cylinder-channel", "disc", "plate-hole", "quarter-plate-hole")


def _arc(points, a, b, ratio):
    p, q = np.asarray(points[a], float), np.asarray(points[b], float)
    chord = np.hypot(*(q - p))
    d = (q - p) / chord
    return Arc(through=tuple((p + q) / 2 + ratio * chord * np.array([d[1], -d[0]])))


def test_blocks_without_curves_keep_the_papers_bits():
    l_shape = blockmesh.load_domain("l-shape")
    outer = l_shape.boundary_edges[0]
    curved = Domain.from_blocks(
        l_shape.vertices, l_shape.blocks, edges={tuple(outer): _arc(l_shape.vertices, *outer, 0.1)}
    )
    straight, bent = l_shape.mesh(4), curved.mesh(4)
    assert np.array_equal(straight.cells, bent.cells)
    touched = np.any(np.isin(l_shape.blocks, outer), axis=1)  # blocks with the curved edge
    curved_block = np.flatnonzero([set(map(int, outer)) <= set(b.tolist()) for b in l_shape.blocks])
    assert curved_block.size == 1
    other = ~np.isin(bent.block_id, curved_block)
    nodes = np.unique(bent.cells[other])
    assert np.array_equal(bent.points[nodes], straight.points[nodes])
    moved = np.flatnonzero(np.any(bent.points != straight.points, axis=1))
    assert moved.size and np.isin(moved, bent.cells[~other]).all()
    assert touched.any()


def test_a_curve_shared_by_two_blocks_gives_both_the_same_nodes():
    vertices = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)]
    blocks = [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)]
    d = Domain.from_blocks(vertices, blocks, edges={(1, 2): _arc(vertices, 1, 2, 0.08)})
    for level in range(5):
        mesh = d.mesh(level)
        mesh.check_geometry()
        assert mesh.curves.distances(mesh.points).max() == 0.0
        assert len(mesh.curves) == 2**level
        # The curve is inside the domain: no boundary edge lies on it.
        keys = {tuple(sorted(e)) for e in mesh.curves.edges.tolist()}
        assert keys.isdisjoint({tuple(sorted(e)) for e in mesh.boundary_edges.tolist()})
    assert d.area == pytest.approx(
        Domain.from_blocks(vertices, blocks).area, rel=1e-15
    )  # what one block gains the other loses


@pytest.mark.parametrize("name", ["disc", "plate-hole"])
def test_refining_in_steps_equals_refining_at_once(name):
    d = blockmesh.load_domain(name)
    once, stepwise = d.mesh(3), blockmesh.refine(blockmesh.refine(d, 1), 2)
    for field in ("points", "cells", "boundary_edges", "block_id", "parent"):
        assert np.array_equal(getattr(once, field), getattr(stepwise, field)), field
    for field in ("edges", "curve", "start", "stop"):
        assert np.array_equal(getattr(once.curves, field), getattr(stepwise.curves, field)), field


def _two_pass(base, level):
    """The reference: the straight refinement, then the curved cells recomputed by
    place_on_curves (what refine did before the curve-aware rule ran in the same pass)."""
    import dataclasses

    from blockmesh.refinement.curved import place_on_curves

    straight = blockmesh.refine(dataclasses.replace(base, curves=None), level)
    return place_on_curves(base, straight, level)


@pytest.mark.parametrize("name", CURVED_CATALOGUE)
@pytest.mark.parametrize(("level", "block_level"), [(2, 6), (5, 6), (4, 2)])
def test_one_pass_equals_the_straight_refinement_then_place_on_curves(
    name, level, block_level, monkeypatch
):
    # block_level 2: level 4 first refines the base 2 levels, then its cells as blocks.
    monkeypatch.setattr(blockmesh.refinement.grouped, "BLOCK_LEVEL", block_level)
    # Every bit is compared (tobytes: also the sign of zeros), and refining a refined mesh too.
    base = blockmesh.load_domain(name).block_mesh()
    for start in (base, blockmesh.refine(base, 1)):
        got, want = blockmesh.refine(start, level), _two_pass(start, level)
        for field in ("points", "cells", "boundary_edges", "boundary_patch"):
            assert getattr(got, field).tobytes() == getattr(want, field).tobytes(), field
        for field in ("edges", "curve", "start", "stop"):
            assert getattr(got.curves, field).tobytes() == getattr(want.curves, field).tobytes()


def test_renumbering_carries_the_curves():
    mesh = blockmesh.refine(blockmesh.load_domain("annulus"), 3, numbering="rcm")
    assert mesh.curves.distances(mesh.points).max() == 0.0
    assert mesh.curved_area == pytest.approx(0.75 * np.pi, rel=1e-14)


def test_smoothing_curved_blocks_keeps_them_valid_and_on_their_curves():
    d = blockmesh.load_domain("quarter-plate-hole")
    plain, smooth = d.mesh(4), d.mesh(4, smooth=3)
    assert np.array_equal(smooth.cells, plain.cells)
    smooth.check_geometry()
    assert smooth.quality().min_angle > plain.quality().min_angle
    assert np.array_equal(smooth.points[smooth.boundary_edges], plain.points[plain.boundary_edges])
    assert smooth.curves.distances(smooth.points).max() == 0.0


def test_the_centre_rule_keeps_a_concave_arc_valid():
    """USP with a concave arc (sagitta 0.35 chord, into the block) on edge (0, 1).

    With the vertex mean as the cells' centre, 2, 7 and 21 cells fold at levels 3, 4 and 5
    (measured); the centre (2/5) sum u - (1/5) sum v keeps every cell valid at every level.
    """
    d = Domain.from_blocks(USP, [(0, 1, 2, 3, 4)], edges={(0, 1): _arc(USP, 0, 1, -0.35)})
    for level in range(1, 6):
        assert np.all(is_strictly_convex(d.mesh(level).cell_coordinates()))


def test_splines_and_polylines_refine_onto_their_curves():
    pentagon = [(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)]
    edges = {(0, 1): Spline(points=[(0.7, -0.15), (1.4, -0.1)]),
             (2, 3): blockmesh.curves.Polyline(points=[(2.2, 2.1)])}  # fmt: skip
    mesh = Domain.from_blocks(pentagon, [(0, 1, 2, 3, 4)], edges=edges).mesh(5)
    mesh.check_geometry()
    assert mesh.curves.distances(mesh.points).max() == 0.0


@st.composite
def pentagons_with_arcs(draw):
    """A convex pentagon (corners on a circle, then sheared and squashed) and 1-5 arcs."""
    gaps = np.array(draw(st.lists(st.floats(0.3, 2.0), min_size=5, max_size=5)))
    angles = np.cumsum(gaps) * 2 * np.pi / gaps.sum()
    squash, shear = draw(st.floats(0.3, 1.0)), draw(st.floats(-0.8, 0.8))
    circle = np.c_[np.cos(angles), np.sin(angles)]
    points = circle @ np.array([[1.0, 0.0], [shear, squash]])
    bulge = st.one_of(st.floats(-0.3, -0.005), st.floats(0.005, 0.3))  # sagitta / chord
    ratios = draw(st.lists(bulge, min_size=5, max_size=5))
    curved = draw(st.lists(st.booleans(), min_size=5, max_size=5))
    curved[draw(st.integers(0, 4))] = True
    return points, [r if c else None for r, c in zip(ratios, curved, strict=True)]


@settings(max_examples=examples(80))
@given(pentagons_with_arcs())
def test_random_blocks_with_random_arcs_refine_or_are_refused_up_front(case):
    points, ratios = case
    edges = {(k, (k + 1) % 5): _arc(points, k, (k + 1) % 5, r)
             for k, r in enumerate(ratios) if r is not None}  # fmt: skip
    try:
        d = Domain.from_blocks(points, [(0, 1, 2, 3, 4)], edges=edges)
    except DomainError as error:
        event("refused up front")
        message = str(error)
        assert message.startswith("block 0 (vertices 0, 1, 2, 3, 4)")
        assert "on edge (" in message and ("bulge less" in message or "move the" in message)
        return
    event("refined to level 5")
    mesh = d.mesh(5)
    xy = mesh.cell_coordinates()
    assert np.all(is_strictly_convex(xy))
    mesh.check_geometry()
    assert mesh.curves.distances(mesh.points).max() == 0.0
