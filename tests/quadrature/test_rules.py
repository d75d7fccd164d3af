"""The rules: the degree they really integrate, their counts, the registry, the sector map."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from blockmesh.errors import ArgumentTypeError, UnknownNameError
from blockmesh.mesh import Mesh
from blockmesh.quadrature import RULES, Rule, get_rule, integrate, quadrature_points, rule_info
from blockmesh.quadrature.exact import exact_integral
from blockmesh.quadrature.layouts import CENTRE
from blockmesh.quadrature.paper import RULE as PAPER
from blockmesh.tables import PENTAGONS

SP = np.array(PENTAGONS["SP"], dtype=float)
USP = np.array(PENTAGONS["USP"], dtype=float)


def _pentagon(points) -> Mesh:
    return Mesh.from_cells(np.asarray(points, dtype=float), np.array([[0, 1, 2, 3, 4]]))


@st.composite
def convex_pentagons(draw):
    """Five points on an ellipse at sorted angles (gaps < pi), mapped by a random affine map."""
    gaps = draw(st.lists(st.floats(0.15, 2.0), min_size=5, max_size=5))
    total = sum(gaps)
    gaps = [g * 2 * math.pi / total for g in gaps]
    if max(gaps) >= math.pi * 0.97:
        gaps = [2 * math.pi / 5] * 5
    start = draw(st.floats(0, 2 * math.pi))
    angles = start + np.cumsum([0.0, *gaps[:4]])
    unit = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    a, b, c, d = (draw(st.floats(-1.5, 1.5)) for _ in range(4))
    matrix = np.array([[1.0 + abs(a), b * 0.5], [c * 0.5, 0.4 + abs(d)]])
    shift = np.array([draw(st.floats(-1, 1)), draw(st.floats(-1, 1))])
    if np.linalg.det(matrix) < 0:  # a reflection: keep the corners counter-clockwise
        unit = unit[::-1]
    return unit @ matrix.T + shift


def _monomial_errors(points, rule: str, n: int, degree: int):
    """Largest |rule - exact| / round-off scale over monomials of total degree ``degree``."""
    mesh = _pentagon(points)
    x, y, w = quadrature_points(mesh, order=n, rule=rule)
    worst = 0.0
    for a in range(degree + 1):
        b = degree - a
        values = x**a * y**b
        exact = float(exact_integral(points, {(a, b): 1}))
        scale = float(np.sum(np.abs(w * values))) + 1e-300
        worst = max(worst, abs(float(np.dot(w, values)) - exact) / scale)
    return worst


@settings(max_examples=examples(20))
@given(convex_pentagons(), st.sampled_from(tuple(RULES)))
def test_every_monomial_up_to_degree_2n_minus_1_is_exact(points, rule):
    for n in range(1, 9):
        for degree in range(2 * n):
            assert _monomial_errors(points, rule, n, degree) < 1e-13, (rule, n, degree)


@pytest.mark.parametrize("rule", tuple(RULES))
@pytest.mark.parametrize("n", [1, 2, 3, 5, 8])
def test_degree_2n_is_not_exact(rule, n):
    """The degree is sharp: some monomial of degree 2n is off by far more than round-off."""
    assert _monomial_errors(USP * 0.7 + 0.1, rule, n, 2 * n) > 1e-11


def test_rule_info_counts_and_degrees():
    assert rule_info("paper", 5).points_per_cell == 150
    assert rule_info("jacobi", 5).points_per_cell == 125
    assert rule_info("fan", 5).points_per_cell == 75
    assert {rule_info(r, 7).degree for r in RULES} == {13}
    x, _, _ = quadrature_points(_pentagon(SP), order=4, level=1, rule="jacobi")
    assert x.size == 6 * rule_info("jacobi", 4).points_per_cell


@pytest.mark.parametrize("rule", tuple(RULES))
@pytest.mark.parametrize("n", [1, 2, 7, 30])
def test_sector_nodes_are_a_product_rule_for_r_dr_ds(rule, n):
    """The weights carry the factor r: Σ w = ∫∫ r = 1/2, Σ w r^k = 1/(k+2) up to the degree."""
    nodes = RULES[rule].nodes(n)
    assert np.all(nodes.weights > 0) and not nodes.weights.flags.writeable
    np.testing.assert_allclose(nodes.r + nodes.one_minus_r, 1.0, rtol=0, atol=2e-16)
    assert np.all((nodes.h > -0.5) & (nodes.h < 0.5))
    u, v = nodes.weights.sum(axis=1), nodes.weights.sum(axis=0)
    np.testing.assert_allclose(np.outer(u, v) / 0.5, nodes.weights, rtol=1e-13)  # rank one
    for k in range(nodes.degree + 1):
        assert float(np.dot(u, nodes.r**k)) == pytest.approx(1 / (k + 2), rel=1e-13)
        assert float(np.dot(v, (0.5 + nodes.h) ** k)) == pytest.approx(0.5 / (k + 1), rel=1e-13)


def test_the_registry_names_and_refuses():
    assert list(RULES) == ["paper", "jacobi", "fan"]
    assert get_rule("jacobi") is RULES["jacobi"] and get_rule(PAPER) is PAPER
    with pytest.raises(UnknownNameError, match="unknown rule 'simpson'; choose one of: paper"):
        get_rule("simpson")
    with pytest.raises(ArgumentTypeError, match="rule must be a rule name or a Rule"):
        get_rule(3)  # type: ignore[arg-type]


def test_a_new_rule_is_one_record():
    """A Rule built from nodes and a layout works everywhere a registered name does."""
    from blockmesh.quadrature.jacobi import jacobi_nodes

    mine = Rule("mine", "jacobi nodes at the vertex mean", CENTRE, jacobi_nodes, 999)
    mesh = _pentagon(USP)
    assert integrate(mesh, "exp(x) * y", order=6, rule=mine) == integrate(
        mesh, "exp(x) * y", order=6, rule="jacobi"
    )
    assert rule_info(mine, 3).points_per_cell == 45


@pytest.mark.parametrize("rule", ["paper", "jacobi"])
def test_the_sector_map_integrates_a_curved_edge(rule):
    """The seam for curved edges: the same nodes on x = (1-r) c + r γ(s), weight w |det(γ-c, γ')|.

    A quarter disc of radius 1 seen from its centre: ∫∫ 1 = π/4 and ∫∫ x^2 = π/16, to round-off,
    with γ an exact circular arc — no rule changes, only the map.
    """
    nodes = RULES[rule].nodes(12)
    s = 0.5 + nodes.h
    theta = s * math.pi / 2
    gamma = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    dgamma = np.stack([-np.sin(theta), np.cos(theta)], axis=1) * (math.pi / 2)
    centre = np.zeros(2)
    det = np.abs(
        (gamma[:, 0] - centre[0]) * dgamma[:, 1] - (gamma[:, 1] - centre[1]) * dgamma[:, 0]
    )
    points = nodes.one_minus_r[:, None, None] * centre + nodes.r[:, None, None] * gamma[None]
    weights = nodes.weights * det[None, :]
    assert float(weights.sum()) == pytest.approx(math.pi / 4, rel=1e-14)
    assert float(np.sum(weights * points[..., 0] ** 2)) == pytest.approx(math.pi / 16, rel=1e-13)
