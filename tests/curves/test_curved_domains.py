"""Curved edges on domains: from_blocks(edges=...), TOML [[edges]], round trips, located errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import SP

import blockmesh
from blockmesh import Domain
from blockmesh.curves import Arc, Polyline, Spline
from blockmesh.errors import DomainError, DomainFormatError

PENTAGON = [(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)]


def _arc_with_sagitta(points, a, b, ratio):
    """An arc on edge (a, b) bulging by ``ratio`` x its chord (to the right of a -> b)."""
    p, q = np.asarray(points[a], float), np.asarray(points[b], float)
    chord = np.hypot(*(q - p))
    d = (q - p) / chord
    return Arc(through=tuple((p + q) / 2 + ratio * chord * np.array([d[1], -d[0]])))


def test_curves_are_bound_to_their_vertices():
    d = Domain.from_blocks(PENTAGON, [(0, 1, 2, 3, 4)], edges={(1, 0): Arc(through=(1, -0.2))})
    ((key, arc),) = d.curves.items()
    assert key == (1, 0) and arc.start == (2.0, 0.0) and arc.end == (0.0, 0.0)
    with pytest.raises(TypeError):
        d.curves[(0, 1)] = arc  # read-only
    # The block runs 0 -> 1, against the curve: its area gains the segment the other way round.
    assert d.area == pytest.approx(6.0 - float(arc.segment_area(0, 1)), rel=1e-15)
    assert d.area > 6.0


def test_curved_area_of_a_block_adds_the_segments():
    spline = Spline(points=[(1, -0.1)])
    line = Polyline(points=[(2.6, 0.4)])
    d = Domain.from_blocks(PENTAGON, [(0, 1, 2, 3, 4)], edges={(0, 1): spline, (1, 2): line})
    segments = d.curves[(0, 1)].segment_area(0, 1) + d.curves[(1, 2)].segment_area(0, 1)
    assert d.area == pytest.approx(6.0 + segments, rel=1e-15)
    assert d.block_areas() == pytest.approx([d.area])


def test_a_domain_rebuilt_from_its_fields_keeps_its_curves():
    d = Domain.from_blocks(PENTAGON, [(0, 1, 2, 3, 4)], edges={(0, 1): Arc(through=(1, -0.2))})
    again = Domain(
        d.name, d.vertices, d.blocks, d.boundary_edges, d.boundary_patch, d.patch_names,
        d.region, d.region_names, curves=d.curves,
    )  # fmt: skip
    assert dict(again.curves) == dict(d.curves)
    assert np.array_equal(again.mesh(3).points, d.mesh(3).points)


@pytest.mark.parametrize(
    "edges, error, message",
    [
        ({(0, 2): Arc(center=(1, 1))}, DomainError, "edge (0, 2) is not a block edge"),
        ({(0, 9): Arc(center=(1, 1))}, DomainError, "names vertex 9, but the vertices are"),
        ({(0, 1.5): Arc(center=(1, 1))}, DomainFormatError, "vertex ids must be whole numbers"),
        ({(0, 1): "arc"}, DomainFormatError, "must map to a curve (Arc, Spline or Polyline)"),
        ({(0, 1): Arc(through=(1, -0.2)), (1, 0): Arc(through=(1, 0.2))}, DomainError,
         "edge (1, 0) has two curves (it is also given as (0, 1))"),
        ({(0, 1): Arc(center=(1.5, 5))}, DomainError,
         "the arc on edge (0, 1) cannot reach both ends"),
        ({(0, 1): Arc(through=(1, 0))}, DomainError, "on the straight line"),
        ({(0, 1): Arc(through=(1, -0.2), start=(0, 0), end=(5, 0))}, DomainError,
         "has an end at (5, 0), but vertex 1 is at (2, 0)"),
        ([(0, 1)], DomainFormatError, "edges must map vertex pairs"),
        ({(0, 1): Spline(points=[(3, -1), (-1, -1)])}, DomainError,
         "the spline on edge (0, 1) crosses itself"),
    ],
)  # fmt: skip
def test_bad_curves_are_located(edges, error, message):
    with pytest.raises(error) as caught:
        Domain.from_blocks(PENTAGON, [(0, 1, 2, 3, 4)], edges=edges)
    assert message in str(caught.value)


def test_a_bulge_that_makes_a_corner_reflex_is_refused():
    with pytest.raises(DomainError) as caught:
        Domain.from_blocks(PENTAGON, [(0, 1, 2, 3, 4)], edges={(1, 2): Arc(through=(2.9, 0.2))})
    message = str(caught.value)
    assert message.startswith("block 0 (vertices 0, 1, 2, 3, 4) is not convex at vertex 1 (2, 0)")
    assert "with the arc on edge (1, 2) the corner is" in message and "more than 180" in message


def test_a_concave_arc_that_folds_cells_is_refused_with_the_level():
    arc = _arc_with_sagitta(SP, 0, 1, -0.45)  # deep into the symmetric pentagon
    with pytest.raises(DomainError) as caught:
        Domain.from_blocks(SP, [(0, 1, 2, 3, 4)], edges={(0, 1): arc})
    message = str(caught.value)
    assert "block 0 (vertices 0, 1, 2, 3, 4) does not stay convex with the arc on edge (0, 1)" in (
        message
    )
    assert "refined to level" in message and "make the curve bulge less" in message


def test_an_arc_running_into_another_block_is_refused():
    # A U: a base block and two arms; an arc on the left arm bulges across the gap.
    vertices = [
        (1.5, -1),
        (3, 0),
        (2, 0.5),
        (1, 0.5),
        (0, 0),
        (0.96, 2.6),
        (0.3, 2.9),
        (-0.3, 2.4),
        (3.3, 2.3),
        (2.5, 2.9),
        (1.1, 2.6),
    ]
    blocks = [(0, 1, 2, 3, 4), (4, 3, 5, 6, 7), (1, 8, 9, 10, 2)]  # fmt: skip
    Domain.from_blocks(vertices, blocks, edges={(3, 5): _arc_with_sagitta(vertices, 3, 5, 0.03)})
    with pytest.raises(DomainError) as caught:
        Domain.from_blocks(vertices, blocks, edges={(3, 5): _arc_with_sagitta(vertices, 3, 5, 0.3)})
    message = str(caught.value)
    assert message.startswith(
        "block 1 (vertices 4, 3, 5, 6, 7) with the arc on edge (3, 5) runs into block 2 near ("
    )
    assert "make the curve bulge less" in message


def test_toml_edges_round_trip_bit_for_bit(tmp_path):
    text = """
name = "curvy"
vertices = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]
blocks = [[0, 1, 2, 3, 4]]
[[edges]]
arc = [0, 1]
through = [1, -0.15]
[[edges]]
spline = [2, 3]
points = [[2.3, 2.2], [1.6, 2.8]]
[[edges]]
polyline = [4, 0]
points = [[-0.2, 1.0]]
[[edges]]
arc = [3, 4]
center = [2.0, 1.0]
"""
    d = Domain.from_toml_text(text)
    assert [c.kind for c in d.curves.values()] == ["arc", "spline", "polyline", "arc"]
    path = d.write_toml(tmp_path / "curvy.toml")
    again = blockmesh.load_domain(path)
    assert dict(again.curves) == dict(d.curves)
    assert np.array_equal(again.mesh(4).points, d.mesh(4).points)
    assert again.area == d.area


@pytest.mark.parametrize(
    "extra, message",
    [
        ("edges = 3", "'edges' must be [[edges]] tables"),
        ("[[edges]]\nthrough = [1, 1]", "[[edges]] entry 1 needs exactly one of arc, spline"),
        ("[[edges]]\narc = [0, 1]\nspline = [0, 1]", "needs exactly one of"),
        ("[[edges]]\narc = [0]\nthrough = [1, 1]", "arc must be [a, b], two vertex ids"),
        ("[[edges]]\narc = [0, 1]\npoints = [[1, 1]]", "a arc takes through or center"),
        ("[[edges]]\narc = [0, 1]\nthrough = [1, -1]\n[[edges]]\narc = [1, 0]\nthrough = [1, 1]",
         "[[edges]] entry 2: edge [1, 0] already has a curve"),
        ("[[edges]]\nspline = [0, 1]\npoints = []", "give at least one interior point"),
    ],
)  # fmt: skip
def test_toml_edge_errors_name_the_entry(extra, message):
    text = "vertices = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]\nblocks = [[0, 1, 2, 3, 4]]\n"
    with pytest.raises(DomainFormatError) as caught:
        Domain.from_toml_text(text + extra)
    assert message in str(caught.value)


def test_toml_edges_need_explicit_blocks():
    with pytest.raises(DomainFormatError, match="'edges' needs explicit blocks"):
        Domain.from_toml_text("polygon = [[0, 0], [1, 0], [0, 1]]\n[[edges]]\narc = [0, 1]\n")


def test_catalogue_curved_domains_round_trip(tmp_path):
    for name in ("disc", "cylinder-channel"):
        d = blockmesh.load_domain(name)
        again = Domain.from_toml_text(d.to_toml())
        assert dict(again.curves) == dict(d.curves)
        assert np.array_equal(again.mesh(2).points, d.mesh(2).points)


def test_cli_check_and_catalogue_know_curved_domains(capsys):
    from helpers import run_cli

    code, out, _ = run_cli(capsys, "check", "annulus")
    assert code == 0 and "valid" in out
    code, out, _ = run_cli(capsys, "catalogue")
    assert code == 0 and "quarter-plate-hole" in out
    assert math.isclose(blockmesh.load_domain("annulus").area, 0.75 * math.pi, rel_tol=1e-14)


def _every_cell_convex(vertices, blocks, curves, levels: int = 5) -> bool:
    """The check as it was: every cell of every curved block at every level (6^5 per block)."""
    from blockmesh.curves.edges import curved_slots, edge_points
    from blockmesh.domain.curve_checks import curved_edges
    from blockmesh.geometry import COLLINEAR_SIN_TOL, corner_sines, signed_area
    from blockmesh.refinement.curved import curved_block_levels
    from blockmesh.refinement.template import pentagon_template

    vertices, blocks = np.asarray(vertices, float), np.asarray(blocks)
    table = curved_edges(curves)
    row, forward = curved_slots(blocks, vertices.shape[0], table)
    which = np.flatnonzero(np.any(row >= 0, axis=1))
    mask = row[which] >= 0
    along = np.zeros((which.size, 5, 2**levels + 1, 2))
    along[mask] = edge_points(table, levels)[row[which][mask]]
    backward = mask & ~forward[which]
    along[backward] = along[backward][:, ::-1]
    for step, xy in curved_block_levels(vertices[blocks[which]], along, mask, levels):
        local = xy[:, pentagon_template(step).cells]
        local = local - local[:, :, :1]
        if not (np.all(corner_sines(local) > COLLINEAR_SIN_TOL) and np.all(signed_area(local) > 0)):
            return False
    return True


@pytest.mark.parametrize("edges", [(0,), (0, 2), (1, 3), (0, 1, 2, 3, 4)])
def test_the_curve_check_measures_fewer_cells_with_the_same_verdict(edges):
    """The check measures only the children of cells on a curve (issue 22: 8.7 s of a 13.1 s
    command); the cells it skips are straight refinements of strictly convex cells. Its verdict
    is the verdict of measuring every cell, for bulges in and out up to folding the block."""
    from blockmesh.domain.curve_checks import check_curved_blocks

    verdicts = []
    for ratio in np.linspace(-0.6, 0.6, 48):  # not 0: a straight edge is no curve
        curves = {
            (k, (k + 1) % 5): _arc_with_sagitta(SP, k, (k + 1) % 5, ratio).with_ends(
                SP[k], SP[(k + 1) % 5]
            )
            for k in edges
        }
        try:
            check_curved_blocks(np.array(SP, float), np.array([[0, 1, 2, 3, 4]]), curves)
            passed = True
        except DomainError as error:
            if "does not stay convex" not in str(error):
                continue  # refused before the cells (a reflex corner, a crossing)
            passed = False
        verdicts.append(passed)
        assert passed == _every_cell_convex(SP, [[0, 1, 2, 3, 4]], curves), (edges, ratio)
    assert True in verdicts
    # the sweep crosses the limit (with five arcs the corners and outlines refuse first)
    assert False in verdicts or len(edges) == 5


def test_the_cells_measured_grow_as_two_to_the_level_per_curved_edge():
    from blockmesh.domain.curve_checks import _children_near

    for step in range(1, 6):
        assert _children_near(step, 5, 2).size == 6 * 2 ** (step - 1)  # of 6^step cells


def test_a_domain_that_passed_is_not_checked_again(monkeypatch):
    """The checks reran on every check/show/mesh/solve of the same domain (issue 22)."""
    import blockmesh.domain.curve_checks as curve_checks

    calls = []
    real = curve_checks._check_cells
    monkeypatch.setattr(curve_checks, "_check_cells", lambda *a: calls.append(1) or real(*a))
    edges = {(0, 1): _arc_with_sagitta(SP, 0, 1, -0.17)}
    first = Domain.from_blocks(SP, [(0, 1, 2, 3, 4)], edges=edges)
    checked = len(calls)
    again = Domain.from_blocks(SP, [(0, 1, 2, 3, 4)], edges=edges)
    assert checked == 5 and len(calls) == checked  # one call per level, then none
    assert again.curves == first.curves
    moved = Domain.from_blocks(
        SP, [(0, 1, 2, 3, 4)], edges={(0, 1): _arc_with_sagitta(SP, 0, 1, -0.18)}
    )
    assert len(calls) == 2 * checked and moved.curves != first.curves
