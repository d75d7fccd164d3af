"""Expression text to a vetted Python syntax tree, and errors that point into the text.

The first step of :mod:`~blockmesh.numerics.expr`: the text is checked for its length (at most
:data:`MAX_LENGTH` characters) and its characters (printable ASCII), ``^`` is rewritten as ``**``
(remembering which column of the rewritten text came from which column of the user's), Python's
:mod:`ast` parses it (``mode="eval"``), and the tree is refused when it nests deeper than
:data:`MAX_DEPTH`. Which nodes are allowed is decided when the tree is compiled
(:mod:`~blockmesh.numerics.compiling`); every refusal, there or here, goes through
:meth:`ParsedText.fail_node`, which raises :class:`~blockmesh.errors.ExpressionError` with the
column and a caret line under the offending part of the text as the user wrote it.

Examples
--------
>>> parsed = ParsedText("x^2 + 1")
>>> parsed.python, ast.dump(parsed.tree.body.op)
('x**2 + 1', 'Add()')
>>> parsed.text(parsed.tree.body.left)  # a node's text, as written
'x^2'
>>> ParsedText("x + y²")
Traceback (most recent call last):
    ...
blockmesh.errors.ExpressionError: '²' is not allowed in an expression at column 6
  x + y²
       ^
"""

from __future__ import annotations

import ast
import warnings
from typing import NoReturn

from blockmesh.errors import ArgumentTypeError, ExpressionError
from blockmesh.numerics.syntax import is_chain

__all__ = ["MAX_DEPTH", "MAX_LENGTH", "ParsedText", "span"]

#: Longest expression accepted, in characters.
MAX_LENGTH = 2000
#: Deepest expression tree accepted.
MAX_DEPTH = 100


class ParsedText:
    """Expression text parsed into a syntax tree, with its columns mapped back to the text.

    Raises :class:`~blockmesh.errors.ExpressionError` on construction for text too long, empty,
    with characters other than printable ASCII, not valid syntax or nested too deeply.

    Attributes
    ----------
    source : str
        The text as given.
    python : str
        The text with ``^`` written ``**`` (what :mod:`ast` parsed).
    colmap : list of int
        For each column of ``python`` (and one past its end), the column of ``source``.
    tree : ast.Expression
        The parsed tree; node columns are those of ``python``.
    """

    __slots__ = ("colmap", "python", "source", "tree")

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
                self.fail_at(col, col + 1, f"{name} is not allowed in an expression")
        self.python, self.colmap = _caret_to_power(text)
        try:
            with warnings.catch_warnings():  # e.g. "invalid decimal literal" for "1in": ours below
                warnings.simplefilter("ignore", SyntaxWarning)
                self.tree = ast.parse(self.python.strip(), mode="eval")
        except SyntaxError as error:
            lead = _leading_spaces(self.python)
            if not error.offset:  # the parser ran out of text: something is missing at the end
                end_of_text = len(self.python.rstrip())
                self.fail(end_of_text, end_of_text + 1, "invalid syntax: the expression ends early")
            start = error.offset - 1 + lead
            end = (error.end_offset or error.offset) - 1 + lead
            detail = "" if error.msg == "invalid syntax" else f" ({error.msg})"
            self.fail(start, max(end, start + 1), f"invalid syntax{detail}")
        except (RecursionError, MemoryError):
            raise ExpressionError(
                f"the expression is nested too deeply (at most {MAX_DEPTH} levels)"
            ) from None
        self._shift_positions(_leading_spaces(self.python))
        self._check_depth()

    # ------------------------------------------------------------------ errors
    def fail(self, start: int, end: int, message: str) -> NoReturn:
        """Raise at columns [start, end) of the parsed (``^`` -> ``**``) text."""
        last = len(self.colmap) - 1
        begin = self.colmap[min(max(start, 0), last)]
        stop = self.colmap[min(max(end, start + 1), last)]
        self.fail_at(begin, max(stop, begin + 1), message)

    def fail_at(self, start: int, end: int, message: str) -> NoReturn:
        """Raise at columns [start, end) of the text as given, with a caret line under them."""
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

    def fail_node(self, node: ast.AST, message: str) -> NoReturn:
        """Raise at the columns of ``node``."""
        start, end = span(node)
        self.fail(start, end, message)

    def text(self, node: ast.AST) -> str:
        """The node's text as the user wrote it (with ``^``, not ``**``)."""
        start, end = span(node)
        return self.source[self.colmap[start] : self.colmap[end]]

    # ------------------------------------------------------------------ vetting
    def _shift_positions(self, shift: int) -> None:
        if shift:
            for node in ast.walk(self.tree):
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
        stack: list[tuple[ast.AST, int]] = [(self.tree.body, 1)]
        while stack:
            node, depth = stack.pop()
            if not hasattr(node, "col_offset"):
                continue  # expression contexts (Load) and operators
            if depth > MAX_DEPTH:
                self.fail_node(
                    node, f"the expression is nested too deeply (at most {MAX_DEPTH} levels)"
                )
            for child in ast.iter_child_nodes(node):
                chained = is_chain(node) and child is getattr(node, "left", None)
                stack.append((child, depth if chained else depth + 1))


def span(node: ast.AST) -> tuple[int, int]:
    """Columns ``[start, end)`` of a node in the parsed text (at least one column)."""
    start: int = getattr(node, "col_offset", 0)
    end: int | None = getattr(node, "end_col_offset", None)
    return start, end if end is not None and end > start else start + 1


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


def _leading_spaces(text: str) -> int:
    return len(text) - len(text.lstrip())
