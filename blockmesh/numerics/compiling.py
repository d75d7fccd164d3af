"""A parsed expression tree to a vectorised function: the whitelist, and closures over numpy.

The second step of :mod:`~blockmesh.numerics.expr`: the tree :mod:`~blockmesh.numerics.parsing`
made is walked once, every node checked against the whitelist (numbers, the names ``x``, ``y``,
``pi``, ``e``, the operators ``+ - * / **``, unary ``-``/``+`` and calls of the functions in
:data:`FUNCTIONS` with the right number of positional arguments, constant exponents up to
:data:`MAX_EXPONENT`) and turned into nested Python closures over numpy ufuncs. Constant
sub-expressions are folded on the way, so the result is a float when the expression depends on
neither x nor y. Nothing is passed to ``eval`` or ``compile``: running the result can only call
the whitelisted numpy functions.

Examples
--------
>>> parsed = ParsedText("2*x + sqrt(4)")
>>> f = compile_node(parsed, parsed.tree.body)
>>> f(np.array([1.0, 2.0]), 0.0).tolist()
[4.0, 6.0]
>>> compile_node(parsed, parsed.tree.body.right)  # folded
2.0
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from blockmesh.numerics.parsing import ParsedText, span
from blockmesh.numerics.syntax import CONSTANTS, chain_links

__all__ = ["FUNCTIONS", "MAX_EXPONENT", "Compiled", "compile_node"]

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

#: A compiled (sub-)expression: a folded constant, or a function of the arrays x and y.
Compiled = float | Callable[[np.ndarray, np.ndarray], np.ndarray]


def compile_node(parsed: ParsedText, node: ast.AST) -> Compiled:
    """The node of ``parsed``'s tree as a constant or a function ``f(x, y)`` of arrays.

    Raises
    ------
    ExpressionError
        For a node outside the whitelist (through :meth:`ParsedText.fail_node`), a division by
        a constant zero, an exponent too large, or a constant part that is not a finite number.
    """
    return _Compiler(parsed).build(node)


class _Compiler:
    """Builds closures bottom-up; refusals are raised at the node's columns in the text."""

    def __init__(self, parsed: ParsedText) -> None:
        self.parsed = parsed

    def build(self, node: ast.AST) -> Compiled:
        fail_node = self.parsed.fail_node
        if isinstance(node, ast.Constant):
            return self._constant(node)
        if isinstance(node, ast.Name):
            if node.id == "x":
                return lambda x, _y: x
            if node.id == "y":
                return lambda _x, y: y
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            fail_node(node, f"unknown name {node.id!r}; the names are x, y, pi, e")
        if isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.UAdd | ast.USub):
                operand = self.build(node.operand)
                if isinstance(node.op, ast.UAdd):
                    return operand
                if callable(operand):
                    return lambda x, y: np.negative(operand(x, y))
                return -operand
            fail_node(node, f"operator {_OPERATOR_TEXT[type(node.op)]!r} is not allowed")
        if isinstance(node, ast.BinOp):
            return self._binary(node)
        if isinstance(node, ast.Call):
            return self._call(node)
        if isinstance(node, ast.Attribute):
            start = node.value.end_col_offset or node.col_offset
            self.parsed.fail(
                start, span(node)[1], f"attribute access ('.{node.attr}') is not allowed"
            )
        if isinstance(node, ast.Subscript):
            start = node.value.end_col_offset or node.col_offset
            self.parsed.fail(start, span(node)[1], "subscripts ('[...]') are not allowed")
        for kind, what in _NOT_ALLOWED.items():
            if isinstance(node, kind):
                fail_node(node, f"{what} not allowed")
        fail_node(node, f"{type(node).__name__} is not allowed")  # pragma: no cover
        raise AssertionError  # pragma: no cover

    def _constant(self, node: ast.Constant) -> float:
        fail_node, text = self.parsed.fail_node, self.parsed.text
        value = node.value
        if isinstance(value, bool) or value is None or value is Ellipsis:
            fail_node(node, f"{value!r} is not allowed; use numbers, x, y, pi, e")
        if isinstance(value, str | bytes):
            fail_node(node, "strings are not allowed")
        if isinstance(value, complex):
            fail_node(node, "complex numbers are not allowed")
        try:
            number = float(value)
        except OverflowError:
            fail_node(node, "the number is too large for a float64")
        if not math.isfinite(number):
            fail_node(node, "the number is too large for a float64")
        if number == 0 and any(c in "123456789" for c in text(node).lower().split("e")[0]):
            fail_node(node, f"the number {text(node)} is too small for a float64 (it would be 0)")
        return number

    def _fold(self, node: ast.AST, function: Callable[..., Any], *args: Compiled) -> float:
        fail_node, text = self.parsed.fail_node, self.parsed.text
        with np.errstate(all="raise"):
            try:
                value = float(function(*(np.float64(a) for a in args if not callable(a))))
            except FloatingPointError as error:
                fail_node(node, f"the constant {text(node)} cannot be evaluated ({error})")
        if not math.isfinite(value):
            fail_node(node, f"the constant {text(node)} is not a finite number")
        return value

    def _binary(self, node: ast.BinOp) -> Compiled:
        if isinstance(node.op, ast.Pow):
            return self._power(node)
        for link in chain_links(node):
            op = type(link.op)
            if op not in _BINARY:
                self.parsed.fail_node(
                    link, f"operator {_OPERATOR_TEXT.get(op, op.__name__)!r} is not allowed"
                )
        # A left-associated chain a op b op c ... is compiled as one loop, not nested closures.
        links = chain_links(node)
        acc = self.build(links[0].left)
        steps: list[tuple[Callable, Compiled]] = []
        for link in links:
            ufunc = _BINARY[type(link.op)]
            right = self.build(link.right)
            if isinstance(link.op, ast.Div) and not callable(right) and right == 0.0:
                self.parsed.fail_node(link, "division by zero")
            if not steps and not callable(acc) and not callable(right):
                acc = self._fold(link, ufunc, acc, right)
            else:
                steps.append((ufunc, right))
        if not steps:
            return acc
        if len(steps) == 1:
            return _combine(steps[0][0], acc, steps[0][1])
        return _loop(acc, tuple(steps))

    def _power(self, node: ast.BinOp) -> Compiled:
        base, exponent = self.build(node.left), self.build(node.right)
        if not callable(exponent) and abs(exponent) > MAX_EXPONENT:
            self.parsed.fail_node(
                node.right,
                f"the exponent {self.parsed.text(node.right)} = {exponent:g} is too large "
                f"(at most {MAX_EXPONENT} in absolute value)",
            )
        if not callable(base) and not callable(exponent):
            return self._fold(node, np.power, base, exponent)
        if callable(base) and not callable(exponent) and exponent == int(exponent):
            return _integer_power(base, int(exponent))
        return _combine(np.power, base, exponent)

    def _call(self, node: ast.Call) -> Compiled:
        fail_node = self.parsed.fail_node
        if isinstance(node.func, ast.Attribute):
            return self.build(node.func)
        if not isinstance(node.func, ast.Name):
            fail_node(node.func, "only the named functions can be called")
        name = node.func.id
        if name not in FUNCTIONS:
            if name in ("x", "y") or name in CONSTANTS:
                fail_node(node, f"{name!r} is not a function (write {name}*(...))")
            fail_node(
                node.func,
                f"unknown function {name!r}; the functions are {', '.join(sorted(FUNCTIONS))}",
            )
        if node.keywords:
            fail_node(node.keywords[0].value, "keyword arguments are not allowed")
        for arg in node.args:
            if isinstance(arg, ast.Starred):
                fail_node(arg, "starred arguments are not allowed")
        count, ufunc = FUNCTIONS[name]
        if len(node.args) != count:
            plural = "argument" if count == 1 else "arguments"
            fail_node(node, f"{name} takes {count} {plural}, got {len(node.args)}")
        args = [self.build(arg) for arg in node.args]
        if not any(callable(a) for a in args):
            return self._fold(node, ufunc, *args)
        if count == 1:
            inner = args[0]
            assert callable(inner)  # not folded above
            return lambda x, y: ufunc(inner(x, y))
        return _combine(ufunc, *args)


def _loop(first: Compiled, steps: tuple[tuple[Callable, Compiled], ...]) -> Callable:
    """A closure evaluating ``first op1 b1 op2 b2 ...`` left to right in a loop."""

    def chain(x, y):
        acc = first(x, y) if callable(first) else first
        for ufunc, operand in steps:
            acc = ufunc(acc, operand(x, y) if callable(operand) else operand)
        return acc

    return chain


def _combine(ufunc, *args: Compiled):
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
