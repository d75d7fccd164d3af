"""Exact polynomials in x and y: expansion of a vetted expression, and the algebra behind it.

A polynomial is a dict ``{(a, b): coefficient of x**a y**b}``. Coefficients are exact
:class:`~fractions.Fraction` values — decimal literals are read from the expression's text as
exact decimals, so ``0.2`` is 1/5, not the binary float — or floats where an irrational
constant (``pi``, ``e``, ``sqrt(2)``, ...) entered; a float coefficient makes every result it
touches a float. Expansion is bounded: total degree at most :data:`MAX_POLYNOMIAL_DEGREE`, at
most :data:`MAX_EXPANSION_WORK` coefficient products, float coefficients finite.

Examples
--------
>>> from blockmesh.numerics.expr import parse_expression
>>> expand(parse_expression("(0.2*x + 0.3*y)^2"))
{(0, 2): Fraction(9, 100), (1, 1): Fraction(3, 25), (2, 0): Fraction(1, 25)}
>>> polynomial_from_mapping({(1, 2): 3})
{(1, 2): Fraction(3, 1)}
>>> expand(parse_expression("pi * x^2 * 1e300 * 1e300"))
Traceback (most recent call last):
...
blockmesh.errors.ExpressionError: the polynomial's coefficients overflow a float64 at column 1
  pi * x^2 * 1e300 * 1e300
  ^^^^^^^^^^^^^^^^^^^^^^^^
"""

from __future__ import annotations

import ast
import math
from collections.abc import Mapping
from decimal import Decimal
from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.numerics.compiling import compile_node
from blockmesh.numerics.syntax import CONSTANTS, chain_links

if TYPE_CHECKING:
    from blockmesh.numerics.expr import Expression

__all__ = [
    "MAX_EXPANSION_WORK",
    "MAX_POLYNOMIAL_DEGREE",
    "Polynomial",
    "degree",
    "expand",
    "polynomial_from_mapping",
]

#: Largest total degree :func:`expand` expands to.
MAX_POLYNOMIAL_DEGREE = 200
#: Most coefficient products one expansion may take.
MAX_EXPANSION_WORK = 2_000_000

#: A polynomial in x and y: {(a, b): coefficient of x**a * y**b}. Coefficients are exact
#: Fractions, or floats where an irrational constant (pi, e, sqrt(2), ...) entered.
Polynomial = dict[tuple[int, int], Fraction | float]


def degree(polynomial: Polynomial) -> int:
    """The total degree (0 for a constant or the zero polynomial).

    Examples
    --------
    >>> degree({(2, 3): 1, (0, 1): 5})
    5
    """
    return max((a + b for a, b in polynomial), default=0)


def expand(expression: Expression) -> Polynomial:
    """The polynomial of a vetted :class:`~blockmesh.numerics.expr.Expression`.

    Raises
    ------
    ExpressionError
        When the expression is not a polynomial, expands too far or overflows, with the part of
        the text responsible marked.
    """
    return _Expander(expression).run()


class _Expander:
    """Walks an Expression's vetted tree bottom-up into a Polynomial."""

    def __init__(self, expression: Expression) -> None:
        self.expression = expression
        self.budget = MAX_EXPANSION_WORK

    def run(self) -> Polynomial:
        return self.node(self.expression._parsed.tree.body)

    def fail(self, node: ast.AST, message: str) -> None:
        self.expression._parsed.fail_node(node, message)

    def text(self, node: ast.AST) -> str:
        return self.expression._parsed.text(node)

    def node(self, node: ast.AST) -> Polynomial:
        try:
            result = self._node(node)
        except (OverflowError, ZeroDivisionError):
            result = {(0, 0): math.inf}
        if any(isinstance(c, float) and not math.isfinite(c) for c in result.values()):
            self.fail(node, "the polynomial's coefficients overflow a float64")
        return result

    def _node(self, node: ast.AST) -> Polynomial:
        if isinstance(node, ast.Constant):
            return _constant(_exact_literal(self.text(node), node.value))
        if isinstance(node, ast.Name):
            if node.id == "x":
                return {(1, 0): Fraction(1)}
            if node.id == "y":
                return {(0, 1): Fraction(1)}
            return _constant(CONSTANTS[node.id])
        if isinstance(node, ast.UnaryOp):
            operand = self.node(node.operand)
            return operand if isinstance(node.op, ast.UAdd) else {k: -c for k, c in operand.items()}
        if isinstance(node, ast.Call):
            if any(
                isinstance(n, ast.Name) and n.id in ("x", "y")
                for a in node.args
                for n in ast.walk(a)
            ):
                name = node.func.id if isinstance(node.func, ast.Name) else "a function"
                self.fail(node, f"not a polynomial: {name}(...) of x or y")
            value = compile_node(self.expression._parsed, node)
            return _constant(float(value))  # type: ignore[arg-type]
        if not isinstance(node, ast.BinOp):  # pragma: no cover - the tree is vetted
            self.fail(node, f"{type(node).__name__} is not allowed")
            return {}
        if not isinstance(node.op, ast.Pow):
            links = chain_links(node)
            acc = self.node(links[0].left)
            for link in links:
                acc = self.step(link, acc, self.node(link.right))
            return acc
        return self.power(node, self.node(node.left), self.node(node.right))

    def step(self, node: ast.BinOp, left: Polynomial, right: Polynomial) -> Polynomial:
        op = type(node.op)
        if op is ast.Add:
            return _add(left, right, 1)
        if op is ast.Sub:
            return _add(left, right, -1)
        if op is ast.Mult:
            return self.multiply(node, left, right)
        if any(key != (0, 0) for key in right):
            self.fail(
                node.right,
                f"not a polynomial: division by {self.text(node.right)}, which depends on x or y",
            )
        divisor = right.get((0, 0), 0)
        if divisor == 0:
            self.fail(node, "division by zero")
        return {k: c / divisor for k, c in left.items()}

    def power(self, node: ast.BinOp, left: Polynomial, right: Polynomial) -> Polynomial:
        if any(key != (0, 0) for key in right):
            self.fail(node.right, "not a polynomial: the exponent depends on x or y")
        exponent = right.get((0, 0), Fraction(0))
        if not (isinstance(exponent, Fraction) and exponent.denominator == 1 and exponent >= 0):
            shown = self.text(node.right).strip("() ")
            self.fail(
                node.right, f"not a polynomial: the exponent {shown} is not a whole number >= 0"
            )
        result: Polynomial = {(0, 0): Fraction(1)}
        square, k = left, int(exponent)
        if degree(left) * k > MAX_POLYNOMIAL_DEGREE:
            self.fail(
                node,
                f"the polynomial's degree exceeds {MAX_POLYNOMIAL_DEGREE}; "
                "too large to expand exactly",
            )
        while k:
            if k & 1:
                result = self.multiply(node, result, square)
            k >>= 1
            if k:
                square = self.multiply(node, square, square)
        return result

    def multiply(self, node: ast.AST, a: Polynomial, b: Polynomial) -> Polynomial:
        if degree(a) + degree(b) > MAX_POLYNOMIAL_DEGREE:
            self.fail(
                node,
                f"the polynomial's degree exceeds {MAX_POLYNOMIAL_DEGREE}; "
                "too large to expand exactly",
            )
        self.budget -= len(a) * len(b)
        if self.budget < 0:
            self.fail(node, "the polynomial has too many terms to expand exactly")
        out: Polynomial = {}
        for (i, j), c in a.items():
            for (k, l), d in b.items():
                key = (i + k, j + l)
                out[key] = out.get(key, 0) + c * d
        return {k: c for k, c in sorted(out.items()) if c != 0}


def polynomial_from_mapping(polynomial: Mapping) -> Polynomial:
    """A polynomial ``{(a, b): coefficient}`` checked and normalised from any mapping.

    Coefficients may be ints, Fractions, Decimals (made exact Fractions) or floats (kept as
    given); zero coefficients are dropped. Expressions are read by
    :func:`blockmesh.numerics.expr.as_polynomial`.

    Raises
    ------
    ArgumentError, ArgumentTypeError
        For a key that is not a pair of whole numbers, a degree over the limit, or a coefficient
        that is not a finite number.

    Examples
    --------
    >>> polynomial_from_mapping({(1, 2): 3, (0, 0): 0})
    {(1, 2): Fraction(3, 1)}
    """
    out: Polynomial = {}
    for key, coefficient in polynomial.items():
        if (
            not isinstance(key, tuple)
            or len(key) != 2
            or not all(
                isinstance(k, int | np.integer) and not isinstance(k, bool) and k >= 0 for k in key
            )
        ):
            raise ArgumentError(
                f"polynomial key {key!r} must be a pair (a, b) of whole numbers >= 0"
            )
        a, b = int(key[0]), int(key[1])
        if a + b > MAX_POLYNOMIAL_DEGREE:
            raise ArgumentError(
                f"polynomial key {key!r}: total degree {a + b} exceeds {MAX_POLYNOMIAL_DEGREE}"
            )
        value: Fraction | float
        if isinstance(coefficient, float | np.floating):
            value = float(coefficient)
            if not math.isfinite(value):
                raise ArgumentError(f"coefficient of x^{a} y^{b} is not finite: {value}")
        elif isinstance(coefficient, int | np.integer | Fraction | Decimal) and not isinstance(
            coefficient, bool
        ):
            try:
                value = Fraction(coefficient)  # type: ignore[arg-type]
            except (ValueError, OverflowError):
                raise ArgumentError(
                    f"coefficient of x^{a} y^{b} is not finite: {coefficient}"
                ) from None
        else:
            raise ArgumentTypeError(
                f"coefficient of x^{a} y^{b} must be a number, not {coefficient!r}"
            )
        if value != 0:
            out[(a, b)] = out.get((a, b), 0) + value
    return out


# --------------------------------------------------------------------------- helpers
def _exact_literal(text: str, value: object) -> Fraction:
    try:
        return Fraction(text.replace("_", ""))
    except ValueError:  # hexadecimal, octal or binary integer literals
        return Fraction(int(value))  # type: ignore[call-overload]


def _constant(value: Fraction | float) -> Polynomial:
    return {(0, 0): value} if value != 0 else {}


def _add(a: Polynomial, b: Polynomial, sign: int) -> Polynomial:
    out = dict(a)
    for key, c in b.items():
        out[key] = out.get(key, 0) + sign * c
    return {k: c for k, c in sorted(out.items()) if c != 0}
