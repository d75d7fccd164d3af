"""Exact polynomials: expansion of expressions, mappings, and the limits of both."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from helpers import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from blockmesh.errors import ArgumentError, ArgumentTypeError, ExpressionError
from blockmesh.numerics.expr import as_polynomial, parse_expression
from blockmesh.numerics.polynomial import MAX_POLYNOMIAL_DEGREE, degree


def test_decimal_literals_are_exact():
    poly = parse_expression("(0.2*x + 0.3*y)^2").polynomial()
    assert poly == {(0, 2): Fraction(9, 100), (1, 1): Fraction(12, 100), (2, 0): Fraction(4, 100)}
    assert parse_expression("1e-3 * x + 1_000").polynomial() == {
        (0, 0): Fraction(1000),
        (1, 0): Fraction(1, 1000),
    }
    assert parse_expression("x / 3 - x / 3").polynomial() == {}


def test_irrational_constants_give_float_coefficients():
    poly = parse_expression("pi * x + sqrt(2) + y / 2").polynomial()
    assert poly[(1, 0)] == math.pi and isinstance(poly[(1, 0)], float)
    assert poly[(0, 0)] == math.sqrt(2)
    assert poly[(0, 1)] == Fraction(1, 2)


@pytest.mark.parametrize(
    ("text", "message", "column"),
    [
        ("sin(x)", "not a polynomial: sin(...) of x or y", 1),
        ("x + exp(y)", "not a polynomial: exp(...) of x or y", 5),
        ("1/x", "not a polynomial: division by x", 3),
        ("(x^4 + y^3) / (1 + x^2)", "not a polynomial: division by 1 + x^2", 16),
        ("x^-1", "the exponent -1 is not a whole number >= 0", 3),
        ("x^0.5", "the exponent 0.5 is not a whole number >= 0", 3),
        ("x^(1/2)", "the exponent 1/2 is not a whole number >= 0", 4),
        ("x^y", "the exponent depends on x or y", 3),
        ("x^pi", "the exponent pi is not a whole number", 3),
        ("(x + y)^201", "degree exceeds 200", 1),
        ("x^150 * y^100", "degree exceeds 200", 1),
        ("x / (y - y)", "division by zero", 1),
    ],
)
def test_non_polynomials_are_refused_with_the_place(text, message, column):
    with pytest.raises(ExpressionError) as info:
        parse_expression(text).polynomial()
    assert message in str(info.value)
    assert str(info.value).splitlines()[0].endswith(f"at column {column}")


def test_integer_power_via_squaring_matches_repeated_products():
    poly = parse_expression("(x + 2*y - 1)^7").polynomial()
    assert sum(poly.values()) == (1 + 2 - 1) ** 7  # value at x = y = 1
    assert poly[(0, 0)] == -1 and poly[(7, 0)] == 1 and poly[(0, 7)] == 128


_atoms = st.sampled_from(["x", "y", "1", "2", "0.5", "3.25", "(x - 1)", "(2*y + x)"])


@st.composite
def _polynomial_texts(draw, depth=0):
    if depth > 3 or draw(st.booleans()):
        return draw(_atoms)
    op = draw(st.sampled_from(["+", "-", "*", "^"]))
    left = draw(_polynomial_texts(depth + 1))
    if op == "^":
        return f"({left})^{draw(st.integers(0, 4))}"
    return f"({left} {op} {draw(_polynomial_texts(depth + 1))})"


@settings(max_examples=examples(150))
@given(
    _polynomial_texts(),
    st.fractions(-3, 3, max_denominator=7),
    st.fractions(-3, 3, max_denominator=7),
)
def test_polynomial_agrees_with_evaluation(text, x, y):
    f = parse_expression(text)
    poly = f.polynomial()
    exact = sum(c * x**a * y**b for (a, b), c in poly.items())
    value = float(f(float(x), float(y)))
    scale = 1 + sum(abs(c) * abs(x) ** a * abs(y) ** b for (a, b), c in poly.items())
    assert abs(value - float(exact)) <= 1e-13 * float(scale)


def test_long_chains_expand():
    text = " + ".join(["x*y"] * 300) + " - x/2"
    assert parse_expression(text).polynomial() == {(1, 0): Fraction(-1, 2), (1, 1): Fraction(300)}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("pi * x^2 * 1e300 * 1e300", "coefficients overflow a float64"),
        ("(1e300 * pi * x)^2", "coefficients overflow a float64"),
        ("x * 1e200 * 1e200 * pi", "coefficients overflow a float64"),
    ],
)
def test_float_coefficients_that_overflow_are_errors(text, message):
    """`pi/(1e-400 + 0*y)` with --exact raised ZeroDivisionError (issue 14); overflow likewise."""
    with pytest.raises(ExpressionError, match=message):
        parse_expression(text).polynomial()


def test_exact_coefficients_may_be_huge():
    assert parse_expression("x * 10^200 * 10^200").polynomial() == {(1, 0): Fraction(10**400)}


def test_mapping_polynomials():
    assert as_polynomial({(1, 0): 2, (0, 0): 0}) == {(1, 0): Fraction(2)}
    assert as_polynomial({(1, 0): Fraction(1, 3), (0, 2): 0.5}) == {
        (1, 0): Fraction(1, 3),
        (0, 2): 0.5,
    }
    assert degree(as_polynomial({(3, 4): 1})) == 7
    with pytest.raises(ArgumentError, match="pair"):
        as_polynomial({(1,): 1})
    with pytest.raises(ArgumentError, match="exceeds"):
        as_polynomial({(MAX_POLYNOMIAL_DEGREE, 1): 1})
    with pytest.raises(ArgumentTypeError, match="must be a number"):
        as_polynomial({(1, 0): "x"})
    with pytest.raises(ArgumentError, match="not finite"):
        as_polynomial({(1, 0): float("nan")})
    with pytest.raises(ArgumentTypeError, match="mapping"):
        as_polynomial(3)
    assert math.isfinite(float(sum(as_polynomial("(x + y)^3").values())))
    assert np.int64(2) in {k[0] for k in as_polynomial({(np.int64(2), 0): 1})}
