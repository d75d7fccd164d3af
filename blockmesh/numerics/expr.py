"""Safe function expressions: text such as ``"(x^4 + y^3) / (1 + x^2)"`` to a vectorised f(x, y).

The text is parsed by Python's :mod:`ast` (``mode="eval"``) and every node is checked against a
whitelist: numbers, the names ``x``, ``y``, ``pi``, ``e``, the operators ``+ - * / **`` (``^`` is
accepted for power), unary ``-``/``+``, parentheses and calls of the functions in
:data:`FUNCTIONS` with the right number of positional arguments. Anything else (attributes, other
names or calls, keywords, subscripts, lambdas, comprehensions, strings, comparisons, conditional
expressions, exponents above :data:`MAX_EXPONENT`, text longer than :data:`MAX_LENGTH` characters
or nested deeper than :data:`MAX_DEPTH`) raises :class:`~blockmesh.errors.ExpressionError` with
the column and a caret line under the offending part.

Nothing is ever passed to ``eval`` or ``compile``: the vetted tree is walked once and turned into
nested Python closures over numpy ufuncs (constant sub-expressions are folded on the way). Running
the result can therefore only call the whitelisted numpy functions, whatever the text was.

The same tree also converts to an exact polynomial (:meth:`Expression.polynomial`): decimal
literals are read from the text as exact decimals (``0.2`` is 1/5, not the binary float), so
``(0.2*x + 0.3*y)^19`` has exact rational coefficients.

This module is the public face of the engine; the work is done in steps, a module each:
:mod:`~blockmesh.numerics.parsing` (the text checked and parsed, errors located in it),
:mod:`~blockmesh.numerics.compiling` (the whitelist, and the tree to closures) and
:mod:`~blockmesh.numerics.polynomial` (the tree expanded into a polynomial).

Examples
--------
>>> f = parse_expression("(x^4 + y^3) / (1 + x^2)")
>>> float(f(1.0, 2.0))
4.5
>>> f(np.array([0.0, 1.0]), 2.0).tolist()
[8.0, 4.5]
>>> parse_expression("2*x*y + y/4").polynomial()
{(0, 1): Fraction(1, 4), (1, 1): Fraction(2, 1)}
>>> parse_expression("os.system('ls')")
Traceback (most recent call last):
    ...
blockmesh.errors.ExpressionError: attribute access ('.system') is not allowed at column 3
  os.system('ls')
    ^^^^^^^
"""

from __future__ import annotations

import ast
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike

from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.numerics.compiling import FUNCTIONS, MAX_EXPONENT, Compiled, compile_node
from blockmesh.numerics.parsing import MAX_DEPTH, MAX_LENGTH, ParsedText
from blockmesh.numerics.polynomial import (
    MAX_POLYNOMIAL_DEGREE,
    Polynomial,
    expand,
    polynomial_from_mapping,
)
from blockmesh.numerics.syntax import CONSTANTS

__all__ = [
    "CONSTANTS",
    "FUNCTIONS",
    "MAX_DEPTH",
    "MAX_EXPONENT",
    "MAX_LENGTH",
    "MAX_POLYNOMIAL_DEGREE",
    "Expression",
    "Polynomial",
    "as_polynomial",
    "parse_expression",
]


def as_polynomial(polynomial: object) -> Polynomial:
    """A polynomial ``{(a, b): coefficient}`` from an expression string, Expression or mapping.

    Mapping coefficients may be ints, Fractions, Decimals or floats (kept as given; see
    :func:`~blockmesh.numerics.polynomial.polynomial_from_mapping`).

    Raises
    ------
    ExpressionError
        For an expression that is not a polynomial.
    ArgumentTypeError, ArgumentError
        For a value that is neither, or a mapping with bad keys or coefficients.

    Examples
    --------
    >>> as_polynomial("x^2 - 0.5*y")
    {(0, 1): Fraction(-1, 2), (2, 0): Fraction(1, 1)}
    """
    if isinstance(polynomial, str):
        return parse_expression(polynomial).polynomial()
    if isinstance(polynomial, Expression):
        return polynomial.polynomial()
    if not isinstance(polynomial, Mapping):
        raise ArgumentTypeError(
            "a polynomial must be an expression string or a mapping {(a, b): coefficient}, "
            f"not {type(polynomial).__name__}"
        )
    return polynomial_from_mapping(polynomial)


def parse_expression(text: str) -> Expression:
    """Parse and vet ``text``; the result is a vectorised ``f(x, y)``.

    Parameters
    ----------
    text : str
        One line, at most :data:`MAX_LENGTH` characters, e.g. ``"exp(-100*((x-0.5)^2 + y^2))"``.

    Returns
    -------
    Expression

    Raises
    ------
    ExpressionError
        On anything outside the whitelist, with the column and a caret line.

    Examples
    --------
    >>> parse_expression("atan2(y, x)")(-1.0, 0.0).item() == np.pi
    True
    >>> parse_expression("sin(x, y)")
    Traceback (most recent call last):
        ...
    blockmesh.errors.ExpressionError: sin takes 1 argument, got 2 at column 1
      sin(x, y)
      ^^^^^^^^^
    """
    return Expression(text)


class Expression:
    """A vetted expression of x and y, callable on arrays.

    Use :func:`parse_expression` to make one. ``expr(x, y)`` broadcasts ``x`` and ``y`` and
    returns a float64 array of their common shape (constants are broadcast too).

    Attributes
    ----------
    source : str
        The text as given.
    variables : frozenset of str
        Which of ``"x"``, ``"y"`` occur.

    Examples
    --------
    >>> f = parse_expression("3")
    >>> f(np.zeros((2, 2)), 0.0).tolist()
    [[3.0, 3.0], [3.0, 3.0]]
    >>> sorted(parse_expression("x + pi").variables)
    ['x']
    """

    __slots__ = ("_function", "_parsed", "source", "variables")

    def __init__(self, text: str) -> None:
        self._parsed = ParsedText(text)
        self.source: str = text
        self.variables: frozenset[str] = frozenset(
            node.id
            for node in ast.walk(self._parsed.tree)
            if isinstance(node, ast.Name) and node.id in ("x", "y")
        )
        self._function: Compiled = compile_node(self._parsed, self._parsed.tree.body)

    # ------------------------------------------------------------------ evaluation
    def __call__(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Evaluate on arrays (or scalars) ``x`` and ``y``; float64 of their broadcast shape."""
        try:
            x = np.asarray(x, dtype=np.float64)
            y = np.asarray(y, dtype=np.float64)
        except (TypeError, ValueError):
            raise ArgumentTypeError(
                f"{self!r} takes numbers or arrays of numbers for x and y, got "
                f"{type(x).__name__} and {type(y).__name__}"
            ) from None
        try:
            shape = np.broadcast_shapes(x.shape, y.shape)
        except ValueError:
            raise ArgumentError(
                f"{self!r}: x and y have shapes {x.shape} and {y.shape}, which do not broadcast"
            ) from None
        function = self._function
        out = np.asarray(function(x, y) if callable(function) else function, dtype=np.float64)
        if out.shape != shape:
            out = np.array(np.broadcast_to(out, shape))
        return out

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"

    @property
    def is_constant(self) -> bool:
        """True when the expression does not depend on x or y."""
        return not callable(self._function)

    # ------------------------------------------------------------------ polynomials
    def polynomial(self) -> Polynomial:
        """The expression as an exact polynomial ``{(a, b): coefficient of x**a y**b}``.

        Decimal literals are exact decimals (``0.2`` -> ``Fraction(1, 5)``); ``pi``, ``e`` and
        constant function calls (``sqrt(2)``) enter as floats, which makes later results floats.
        Zero coefficients are dropped. See :func:`blockmesh.numerics.polynomial.expand`.

        Raises
        ------
        ExpressionError
            When the expression is not a polynomial (a function of x or y, division by a
            non-constant, an exponent that is not a whole number >= 0), expands beyond
            :data:`~blockmesh.numerics.polynomial.MAX_POLYNOMIAL_DEGREE`, or a float coefficient
            overflows; the message points at the offending part.

        Examples
        --------
        >>> parse_expression("(x + 1)^2 / 2").polynomial()
        {(0, 0): Fraction(1, 2), (1, 0): Fraction(1, 1), (2, 0): Fraction(1, 2)}
        >>> parse_expression("x^0.5").polynomial()  # doctest: +ELLIPSIS
        Traceback (most recent call last):
            ...
        blockmesh.errors.ExpressionError: not a polynomial: the exponent 0.5 is not ... at column 3
          x^0.5
            ^^^
        """
        return expand(self)
