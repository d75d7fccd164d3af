"""Exact polynomial integrals over polygons, domains and meshes."""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest
import sympy
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st
from sympy.integrals.intpoly import polytope_integrate

import blockmesh
from blockmesh.errors import ArgumentTypeError, DomainError, ExpressionError, ResourceError
from blockmesh.mesh import Mesh
from blockmesh.quadrature.exact import as_polynomial, exact_integral
from blockmesh.refinement import refine
from blockmesh.tables import CASES, PENTAGONS


@pytest.mark.parametrize(
    "case", [c for c in CASES if c.exact_fraction], ids=lambda c: f"{c.table}-{c.pentagon}"
)
def test_paper_polynomials_exactly(case):
    value = exact_integral(PENTAGONS[case.pentagon], case.integrand)
    assert isinstance(value, Fraction)
    assert value == Fraction(case.exact_fraction)


def test_the_paper_integrand_of_table_3_as_in_the_brief():
    assert exact_integral(PENTAGONS["SP"], "(0.2*x+0.3*y)^19") == Fraction(
        -389834752439, 7000000000000000000
    )


@settings(max_examples=examples(25))
@given(
    st.lists(
        st.tuples(st.fractions(-3, 3, max_denominator=5), st.fractions(-3, 3, max_denominator=5)),
        min_size=3,
        max_size=3,
    ),
    st.integers(0, 5),
    st.integers(0, 5),
)
def test_monomials_over_triangles_agree_with_sympy(corners, a, b):
    (x1, y1), (x2, y2), (x3, y3) = corners
    twice_area = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1)
    if twice_area == 0:
        return
    if twice_area < 0:
        corners = corners[::-1]
    x, y = sympy.symbols("x y")
    clockwise = corners[::-1]  # sympy's polytope_integrate wants clockwise corners
    polygon = sympy.Polygon(
        *[
            sympy.Point(
                sympy.Rational(p.numerator, p.denominator),
                sympy.Rational(q.numerator, q.denominator),
            )
            for p, q in clockwise
        ]
    )
    expected = polytope_integrate(polygon, x**a * y**b)
    assert exact_integral(corners, {(a, b): 1}) == Fraction(
        int(sympy.numer(expected)), int(sympy.denom(expected))
    )


def test_orientation_does_not_matter():
    usp = list(PENTAGONS["USP"])
    assert exact_integral(usp, "x^3 - y") == exact_integral(usp[::-1], "x^3 - y")
    assert exact_integral(usp, "1") == 6


def test_float_coordinates_are_converted_exactly():
    value = exact_integral([(0, 0), (0.1, 0), (0, 0.1)], "1")
    assert value == Fraction(0.1) ** 2 / 2  # the binary 0.1, not 1/10
    assert exact_integral([("0", "0"), ("0.1", "0"), ("0", "0.1")], "1") == Fraction(1, 200)
    assert exact_integral([(Decimal("0.5"), 0), (1, 0), (1, 1)], "1") == Fraction(1, 4)


def test_float_coefficients_give_a_float():
    value = exact_integral(PENTAGONS["USP"], "pi * x")
    assert isinstance(value, float)
    assert value == pytest.approx(np.pi * float(exact_integral(PENTAGONS["USP"], "x")), rel=1e-15)


def test_domain_and_mesh_agree_with_the_polygon():
    domain = blockmesh.load_domain("sp")
    polygon = exact_integral(PENTAGONS["SP"], "(x - y)^20 / 10^5")
    assert exact_integral(domain, "(x - y)^20 / 10^5") == polygon
    mesh = refine(Mesh.from_cells(np.array(PENTAGONS["SP"], float), [[0, 1, 2, 3, 4]]), 3)
    # boundary nodes sit at dyadic fractions of the integer edges: exactly on the pentagon
    assert exact_integral(mesh, "(x - y)^20 / 10^5") == polygon


def test_domain_with_several_blocks_and_a_hole():
    ring = blockmesh.load_domain("ring")
    assert float(exact_integral(ring, "1")) == pytest.approx(ring.area, rel=1e-14)
    mesh = ring.mesh(1)
    areas = mesh.cell_areas()
    moment = float(np.sum(areas * mesh.points[mesh.cells].mean(axis=1)[:, 0]))  # rough ∫ x
    assert float(exact_integral(ring, "x")) == pytest.approx(moment, abs=1e-9 + 0.05 * abs(moment))


def test_mapping_polynomials():
    assert exact_integral([(0, 0), (1, 0), (0, 1)], {(0, 0): Fraction(1, 3)}) == Fraction(1, 6)
    assert as_polynomial({(1, 0): 2}) == {(1, 0): Fraction(2)}  # still importable from here


def test_a_float_result_beyond_the_range_is_an_error():
    with pytest.raises(ExpressionError, match="beyond the float64 range"):
        exact_integral([(0, 0), (10, 0), (0, 10)], {(0, 0): 1e308})  # 50 x 1e308
    huge = exact_integral([(0, 0), (10, 0), (10, 10)], "x * 10^300")  # exact: a Fraction
    assert isinstance(huge, Fraction) and huge > 10**302


def test_the_work_is_bounded():
    mesh = refine(Mesh.from_cells(np.array(PENTAGONS["SP"], float), np.array([[0, 1, 2, 3, 4]])), 6)
    with pytest.raises(ResourceError, match=r"big-integer steps \(320 boundary edges"):
        exact_integral(mesh, "(x + 2*y + 1)^60")
    assert exact_integral(PENTAGONS["SP"], "(x + y)^20", max_work=10**4) == exact_integral(
        PENTAGONS["SP"], "(x + y)^20"
    )


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("sin(x)", "sin(...) of x or y"),
        ("1/x", "division by x"),
        ("x^-1", "exponent -1"),
        ("x^0.5", "exponent 0.5"),
        ("(x^4+y^3)/(1+x^2)", "division by 1+x^2"),
    ],
)
def test_non_polynomials_raise_not_a_wrong_number(text, message):
    with pytest.raises(ExpressionError, match="not a polynomial") as info:
        exact_integral(PENTAGONS["SP"], text)
    assert message in str(info.value)


@pytest.mark.parametrize(
    ("target", "error", "message"),
    [
        ([(0, 0), (1, 0)], DomainError, "at least 3 corners"),
        ([(0, 0), (1, 0), (1,)], DomainError, "pair"),
        ([(0, 0), (1, 0), (1, float("inf"))], DomainError, "not finite"),
        ([(0, 0), (1, 0), (1, True)], DomainError, "not a number"),
        ([(0, 0), (1, 0), (1, "abc")], DomainError, "not a finite number"),
        ("square", ArgumentTypeError, r"list of \(x, y\) corners"),
        (3.5, ArgumentTypeError, r"list of \(x, y\) corners"),
    ],
)
def test_bad_targets(target, error, message):
    with pytest.raises(error, match=message):
        exact_integral(target, "1")
