"""The composite rules on polygon meshes: exact polynomial integrals to round-off, cell by cell."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh
from blockmesh.errors import ArgumentError, ExpressionError, ResourceError
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.quadrature import (
    integrate,
    integrate_cells,
    integrate_with_estimate,
    quadrature_points,
)
from blockmesh.quadrature.exact import exact_integral
from blockmesh.refinement.local import refine_marked


def _polygon_mesh(name: str, seed: int, rounds: int) -> PolygonMesh:
    mesh = PolygonMesh.from_mesh(blockmesh.load_domain(name).mesh(1))
    rng = np.random.default_rng(seed)
    for _ in range(rounds):
        marked = rng.random(mesh.n_cells) < 0.25
        marked[rng.integers(mesh.n_cells)] = True
        mesh = refine_marked(mesh, marked)
    return mesh


@st.composite
def polynomials(draw: st.DrawFn, degree: int) -> str:
    """A random polynomial of total degree at most ``degree`` with small integer coefficients."""
    terms = []
    for i in range(degree + 1):
        for j in range(degree + 1 - i):
            c = draw(st.integers(-3, 3))
            if c:
                terms.append(f"({c})*x^{i}*y^{j}")
    return " + ".join(terms) or "0"


@given(
    st.sampled_from(["l-shape", "square-cut", "comb", "hexagon", "t-junction"]),
    st.integers(0, 10**6),
    st.integers(1, 3),
    st.sampled_from(["paper", "jacobi", "fan"]),
    st.integers(1, 5),
    st.data(),
)
@settings(max_examples=examples(40), deadline=None)
def test_polynomials_of_degree_2n_minus_1_are_exact(name, seed, rounds, rule, order, data):
    mesh = _polygon_mesh(name, seed, rounds)
    f = data.draw(polynomials(2 * order - 1))
    exact = float(exact_integral(mesh, f))
    value = integrate(mesh, f, order=order, rule=rule, warn_rtol=None)
    scale = integrate(mesh, f"abs({f})", order=order + 2, warn_rtol=None) + 1e-300
    assert abs(value - exact) <= 1e-13 * max(scale, abs(exact), 1.0)


def test_cell_integrals_of_one_are_the_areas():
    mesh = _polygon_mesh("l-shape", 4, 3)
    assert mesh.hanging_nodes().size
    cells = integrate_cells(mesh, "1", order=1)
    np.testing.assert_allclose(cells, mesh.cell_areas(), rtol=1e-13, atol=1e-15)
    moment = integrate_cells(mesh, "x", order=1)  # exact to degree 1: the first moments
    exact = [float(exact_integral(mesh.points[mesh.cell(c)], "x")) for c in range(mesh.n_cells)]
    np.testing.assert_allclose(moment, exact, rtol=1e-12, atol=1e-15)
    x, y, w = quadrature_points(mesh, order=3)
    assert x.shape == y.shape == w.shape
    assert abs(w.sum() - mesh.area) < 1e-13
    assert abs(Fraction(float(np.sum(w * x * y))) - exact_integral(mesh, "x*y")) < 1e-12


def test_the_estimate_and_the_refusals():
    mesh = _polygon_mesh("square-cut", 1, 2)
    result = integrate_with_estimate(mesh, "exp(x*y)", order=4)
    assert result.converged and result.error_estimate < 1e-8
    assert result.cells == mesh.n_cells
    with pytest.raises(ArgumentError, match="integrated on its own cells"):
        integrate(mesh, "1", order=2, level=mesh.level + 1)
    with pytest.raises(ResourceError, match="max_points"):
        integrate(mesh, "1", order=5, max_points=100)
    with pytest.raises(ExpressionError, match="quadrature point of cell"):
        integrate(mesh, "1/(x - x)", order=2, warn_rtol=None)
