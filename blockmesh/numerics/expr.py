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
import math
import warnings
from collections.abc import Callable, Mapping
from typing import Any, NoReturn

import numpy as np
from numpy.typing import ArrayLike

from blockmesh.errors import ArgumentError, ArgumentTypeError, ExpressionError
from blockmesh.numerics.polynomial import (
    MAX_POLYNOMIAL_DEGREE,
    Polynomial,
    expand,
    polynomial_from_mapping,
)
from blockmesh.numerics.syntax import CONSTANTS, chain_links, is_chain

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

#: Longest expression accepted, in characters.
MAX_LENGTH = 2000
#: Deepest expression tree accepted.
MAX_DEPTH = 100
#: Largest ``|p|`` accepted for a constant exponent ``p``.
MAX_EXPONENT = 1000


#: Whitelisted functions: name -> (number of arguments, numpy ufunc).
FUNCTIONS: dict[str, tuple[int, Callable[..., np.ndarray]]] = {
    "sin": (1, np.sin),
    "cos": (1, np.cos),
    "tan": (1, np.tan),
    "exp": (1, np.exp),
    "expm1": (1, np.expm1),
    "log": (1, np.log),
    "log1p": (1, np.log1p),
    "log10": (1, np.log10),
    "log2": (1, np.log2),
    "sqrt": (1, np.sqrt),
    "cbrt": (1, np.cbrt),
    "abs": (1, np.abs),
    "sign": (1, np.sign),
    "floor": (1, np.floor),
    "ceil": (1, np.ceil),
    "sinh": (1, np.sinh),
    "cosh": (1, np.cosh),
    "tanh": (1, np.tanh),
    "arcsin": (1, np.arcsin),
    "arccos": (1, np.arccos),
    "arctan": (1, np.arctan),
    "asin": (1, np.arcsin),
    "acos": (1, np.arccos),
    "atan": (1, np.arctan),
    "arcsinh": (1, np.arcsinh),
    "arccosh": (1, np.arccosh),
    "arctanh": (1, np.arctanh),
    "asinh": (1, np.arcsinh),
    "acosh": (1, np.arccosh),
    "atanh": (1, np.arctanh),
    "atan2": (2, np.arctan2),
    "arctan2": (2, np.arctan2),
    "hypot": (2, np.hypot),
    "min": (2, np.minimum),
    "max": (2, np.maximum),
}

_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide}
_OPERATOR_TEXT = {
    ast.Mod: "%",
    ast.FloorDiv: "//",
    ast.MatMult: "@",
    ast.LShift: "<<",
    ast.RShift: ">>",
    ast.BitOr: "|",
    ast.BitAnd: "&",
    ast.BitXor: "^",
    ast.Invert: "~",
    ast.Not: "not",
}
_NOT_ALLOWED = {
    ast.Lambda: "lambda functions are",
    ast.ListComp: "list comprehensions are",
    ast.SetComp: "set comprehensions are",
    ast.DictComp: "dict comprehensions are",
    ast.GeneratorExp: "generator expressions are",
    ast.IfExp: "conditional expressions ('if ... else') are",
    ast.Compare: "comparisons are",
    ast.BoolOp: "'and' / 'or' are",
    ast.List: "lists are",
    ast.Tuple: "tuples are",
    ast.Set: "sets are",
    ast.Dict: "dicts are",
    ast.JoinedStr: "f-strings are",
    ast.NamedExpr: "assignments (':=') are",
    ast.Await: "'await' is",
    ast.Yield: "'yield' is",
    ast.YieldFrom: "'yield' is",
    ast.Starred: "starred arguments are",
    ast.Slice: "slices are",
}

_Compiled = float | Callable[[np.ndarray, np.ndarray], np.ndarray]


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
    >>> parse_expression("atan2(y, x)")(-1.0, 0.0).item() == math.pi
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

    __slots__ = ("_colmap", "_function", "_python", "_tree", "source", "variables")

    def __init__(self, text: str) -> None:
        if not isinstance(text, str):
            raise ArgumentTypeError(f"an expression must be a string, not {type(text).__name__}")
        self.source = text
        if len(text) > MAX_LENGTH:
            raise ExpressionError(
                f"the expression is {len(text)} characters long; at most {MAX_LENGTH} are allowed"
            )
        if not text.strip():
            raise ExpressionError("the expression is empty; give a function of x and y")
        for col, char in enumerate(text):
            if not (char.isascii() and (char.isprintable() or char == "\t")):
                name = "a line break" if char in "\r\n" else repr(char)
                self._fail_at(col, col + 1, f"{name} is not allowed in an expression")
        self._python, self._colmap = _caret_to_power(text)
        try:
            with warnings.catch_warnings():  # e.g. "invalid decimal literal" for "1in": ours below
                warnings.simplefilter("ignore", SyntaxWarning)
                self._tree = ast.parse(self._python.strip(), mode="eval")
        except SyntaxError as error:
            lead = _leading_spaces(self._python)
            if not error.offset:  # the parser ran out of text: something is missing at the end
                end_of_text = len(self._python.rstrip())
                self._fail(
                    end_of_text, end_of_text + 1, "invalid syntax: the expression ends early"
                )
            start = error.offset - 1 + lead
            end = (error.end_offset or error.offset) - 1 + lead
            detail = "" if error.msg == "invalid syntax" else f" ({error.msg})"
            self._fail(start, max(end, start + 1), f"invalid syntax{detail}")
        except (RecursionError, MemoryError):
            raise ExpressionError(
                f"the expression is nested too deeply (at most {MAX_DEPTH} levels)"
            ) from None
        self._shift_positions(_leading_spaces(self._python))
        self._check_depth()
        self.variables: frozenset[str] = frozenset(
            node.id
            for node in ast.walk(self._tree)
            if isinstance(node, ast.Name) and node.id in ("x", "y")
        )
        self._function: _Compiled = self._build(self._tree.body)

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

    # ------------------------------------------------------------------ errors
    def _fail(self, start: int, end: int, message: str) -> NoReturn:
        """Raise at columns [start, end) of the parsed (``^`` -> ``**``) text."""
        last = len(self._colmap) - 1
        begin = self._colmap[min(max(start, 0), last)]
        stop = self._colmap[min(max(end, start + 1), last)]
        self._fail_at(begin, max(stop, begin + 1), message)

    def _fail_at(self, start: int, end: int, message: str) -> NoReturn:
        text = self.source
        offset, shown = 0, text
        if len(text) > 76:  # a window around the offending part
            offset = max(0, min(start - 30, len(text) - 76))
            shown = ("..." if offset else "") + text[offset : offset + 76]
            shown += "..." if offset + 76 < len(text) else ""
            offset -= 3 if offset else 0
        shown = "".join(c if c.isprintable() else " " for c in shown)
        width = max(1, min(end, start + 76) - start)
        caret = " " * (start - offset) + "^" * width
        raise ExpressionError(f"{message} at column {start + 1}\n  {shown}\n  {caret}")

    def _fail_node(self, node: ast.AST, message: str) -> NoReturn:
        start, end = _span(node)
        self._fail(start, end, message)

    # ------------------------------------------------------------------ vetting + compiling
    def _shift_positions(self, shift: int) -> None:
        if shift:
            for node in ast.walk(self._tree):
                if hasattr(node, "col_offset"):
                    setattr(node, "col_offset", node.col_offset + shift)  # noqa: B010
                    end = getattr(node, "end_col_offset", None)
                    if end is not None:
                        setattr(node, "end_col_offset", end + shift)  # noqa: B010

    def _check_depth(self) -> None:
        """Refuse nesting deeper than MAX_DEPTH.

        A chain ``a + b - c * d ...`` counts as one
        level (it is compiled as a loop), so long sums are fine.
        """
        stack: list[tuple[ast.AST, int]] = [(self._tree.body, 1)]
        while stack:
            node, depth = stack.pop()
            if not hasattr(node, "col_offset"):
                continue  # expression contexts (Load) and operators
            if depth > MAX_DEPTH:
                self._fail_node(
                    node, f"the expression is nested too deeply (at most {MAX_DEPTH} levels)"
                )
            for child in ast.iter_child_nodes(node):
                chained = is_chain(node) and child is getattr(node, "left", None)
                stack.append((child, depth if chained else depth + 1))

    def _build(self, node: ast.AST) -> _Compiled:
        if isinstance(node, ast.Constant):
            return self._constant(node)
        if isinstance(node, ast.Name):
            if node.id == "x":
                return lambda x, _y: x
            if node.id == "y":
                return lambda _x, y: y
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            self._fail_node(node, f"unknown name {node.id!r}; the names are x, y, pi, e")
        if isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.UAdd | ast.USub):
                operand = self._build(node.operand)
                if isinstance(node.op, ast.UAdd):
                    return operand
                if callable(operand):
                    return lambda x, y: np.negative(operand(x, y))
                return -operand
            self._fail_node(node, f"operator {_OPERATOR_TEXT[type(node.op)]!r} is not allowed")
        if isinstance(node, ast.BinOp):
            return self._binary(node)
        if isinstance(node, ast.Call):
            return self._call(node)
        if isinstance(node, ast.Attribute):
            start = node.value.end_col_offset or node.col_offset
            self._fail(start, _span(node)[1], f"attribute access ('.{node.attr}') is not allowed")
        if isinstance(node, ast.Subscript):
            start = node.value.end_col_offset or node.col_offset
            self._fail(start, _span(node)[1], "subscripts ('[...]') are not allowed")
        for kind, what in _NOT_ALLOWED.items():
            if isinstance(node, kind):
                self._fail_node(node, f"{what} not allowed")
        self._fail_node(node, f"{type(node).__name__} is not allowed")  # pragma: no cover
        raise AssertionError  # pragma: no cover

    def _constant(self, node: ast.Constant) -> float:
        value = node.value
        if isinstance(value, bool) or value is None or value is Ellipsis:
            self._fail_node(node, f"{value!r} is not allowed; use numbers, x, y, pi, e")
        if isinstance(value, str | bytes):
            self._fail_node(node, "strings are not allowed")
        if isinstance(value, complex):
            self._fail_node(node, "complex numbers are not allowed")
        try:
            number = float(value)
        except OverflowError:
            self._fail_node(node, "the number is too large for a float64")
        if not math.isfinite(number):
            self._fail_node(node, "the number is too large for a float64")
        if number == 0 and any(c in "123456789" for c in self._text(node).lower().split("e")[0]):
            self._fail_node(
                node, f"the number {self._text(node)} is too small for a float64 (it would be 0)"
            )
        return number

    def _fold(self, node: ast.AST, function: Callable[..., Any], *args: _Compiled) -> float:
        with np.errstate(all="raise"):
            try:
                value = float(function(*(np.float64(a) for a in args if not callable(a))))
            except FloatingPointError as error:
                text = self._text(node)
                self._fail_node(node, f"the constant {text} cannot be evaluated ({error})")
        if not math.isfinite(value):
            self._fail_node(node, f"the constant {self._text(node)} is not a finite number")
        return value

    def _text(self, node: ast.AST) -> str:
        """The node's text as the user wrote it (with ``^``, not ``**``)."""
        start, end = _span(node)
        return self.source[self._colmap[start] : self._colmap[end]]

    def _binary(self, node: ast.BinOp) -> _Compiled:
        if isinstance(node.op, ast.Pow):
            return self._power(node)
        for link in chain_links(node):
            op = type(link.op)
            if op not in _BINARY:
                self._fail_node(
                    link, f"operator {_OPERATOR_TEXT.get(op, op.__name__)!r} is not allowed"
                )
        # A left-associated chain a op b op c ... is compiled as one loop, not nested closures.
        links = chain_links(node)
        acc = self._build(links[0].left)
        steps: list[tuple[Callable, _Compiled]] = []
        for link in links:
            ufunc = _BINARY[type(link.op)]
            right = self._build(link.right)
            if isinstance(link.op, ast.Div) and not callable(right) and right == 0.0:
                self._fail_node(link, "division by zero")
            if not steps and not callable(acc) and not callable(right):
                acc = self._fold(link, ufunc, acc, right)
            else:
                steps.append((ufunc, right))
        if not steps:
            return acc
        if len(steps) == 1:
            return _combine(steps[0][0], acc, steps[0][1])
        return _loop(acc, tuple(steps))

    def _power(self, node: ast.BinOp) -> _Compiled:
        base, exponent = self._build(node.left), self._build(node.right)
        if not callable(exponent) and abs(exponent) > MAX_EXPONENT:
            self._fail_node(
                node.right,
                f"the exponent {self._text(node.right)} = {exponent:g} is too large "
                f"(at most {MAX_EXPONENT} in absolute value)",
            )
        if not callable(base) and not callable(exponent):
            return self._fold(node, np.power, base, exponent)
        if callable(base) and not callable(exponent) and exponent == int(exponent):
            return _integer_power(base, int(exponent))
        return _combine(np.power, base, exponent)

    def _call(self, node: ast.Call) -> _Compiled:
        if isinstance(node.func, ast.Attribute):
            return self._build(node.func)
        if not isinstance(node.func, ast.Name):
            self._fail_node(node.func, "only the named functions can be called")
        name = node.func.id
        if name not in FUNCTIONS:
            if name in ("x", "y") or name in CONSTANTS:
                self._fail_node(node, f"{name!r} is not a function (write {name}*(...))")
            self._fail_node(
                node.func,
                f"unknown function {name!r}; the functions are {', '.join(sorted(FUNCTIONS))}",
            )
        if node.keywords:
            self._fail_node(node.keywords[0].value, "keyword arguments are not allowed")
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                self._fail_node(arg, "starred arguments are not allowed")
        count, ufunc = FUNCTIONS[name]
        if len(node.args) != count:
            plural = "argument" if count == 1 else "arguments"
            self._fail_node(node, f"{name} takes {count} {plural}, got {len(node.args)}")
        args = [self._build(arg) for arg in node.args]
        if not any(callable(a) for a in args):
            return self._fold(node, ufunc, *args)
        if count == 1:
            inner = args[0]
            assert callable(inner)  # not folded above
            return lambda x, y: ufunc(inner(x, y))
        return _combine(ufunc, *args)

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


# --------------------------------------------------------------------------- helpers
def _caret_to_power(text: str) -> tuple[str, list[int]]:
    """Replace ``^`` by ``**``; map each column of the new text to a column of the old one."""
    out: list[str] = []
    colmap: list[int] = []
    for col, char in enumerate(text):
        if char == "^":
            out.append("**")
            colmap.extend((col, col))
        else:
            out.append(char)
            colmap.append(col)
    colmap.append(len(text))
    return "".join(out), colmap


def _span(node: ast.AST) -> tuple[int, int]:
    """Columns ``[start, end)`` of a node in the parsed text (at least one column)."""
    start: int = getattr(node, "col_offset", 0)
    end: int | None = getattr(node, "end_col_offset", None)
    return start, end if end is not None and end > start else start + 1


def _leading_spaces(text: str) -> int:
    return len(text) - len(text.lstrip())


def _loop(first: _Compiled, steps: tuple[tuple[Callable, _Compiled], ...]) -> Callable:
    """A closure evaluating ``first op1 b1 op2 b2 ...`` left to right in a loop."""

    def chain(x, y):
        acc = first(x, y) if callable(first) else first
        for ufunc, operand in steps:
            acc = ufunc(acc, operand(x, y) if callable(operand) else operand)
        return acc

    return chain


def _combine(ufunc, *args: _Compiled):
    """A closure applying ``ufunc`` to compiled arguments (callables or constants)."""
    if len(args) == 2:
        a, b = args
        if callable(a) and callable(b):
            return lambda x, y: ufunc(a(x, y), b(x, y))
        if callable(a):
            return lambda x, y: ufunc(a(x, y), b)
        assert callable(b)  # two constants are folded before
        return lambda x, y: ufunc(a, b(x, y))
    raise AssertionError  # pragma: no cover


def _integer_power(base: Callable, k: int) -> Callable:
    """``base ** k`` for a whole number ``k``.

    Multiplications for small ``|k|``, else ``copysign(|b| ** k, b)`` (libm's pow is ~10x slower on
    negative bases).
    """
    if k == 0:
        return lambda x, y: np.ones_like(base(x, y))
    if k == 1:
        return base
    if k == 2:
        return lambda x, y: np.square(base(x, y))
    if k == 3:

        def cube(x, y):
            b = base(x, y)
            return np.square(b) * b

        return cube
    if k == 4:
        return lambda x, y: np.square(np.square(base(x, y)))
    if k % 2:

        def odd(x, y):
            b = base(x, y)
            return np.copysign(np.power(np.abs(b), k), b)

        return odd
    return lambda x, y: np.power(np.abs(base(x, y)), k)
