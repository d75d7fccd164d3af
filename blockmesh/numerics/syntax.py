"""What expressions and their expansion share: the named constants and chains of operators.

A chain is a left-associated run of binary operators other than ``**``, ``((a + b) - c) * d``:
Python's parser nests it to the left, and the depth check (:mod:`~blockmesh.numerics.parsing`),
the compiler (:mod:`~blockmesh.numerics.compiling`) and the expansion into polynomials
(:mod:`~blockmesh.numerics.polynomial`) walk it as a flat list, so that a sum of ten thousand
terms does not recurse ten thousand deep.

Examples
--------
>>> import ast
>>> node = ast.parse("a + b - c", mode="eval").body
>>> [type(link.op).__name__ for link in chain_links(node)]
['Add', 'Sub']
>>> sorted(CONSTANTS)
['e', 'pi']
"""

from __future__ import annotations

import ast
import math

__all__ = ["CONSTANTS", "chain_links", "is_chain"]

#: The named constants an expression may use.
CONSTANTS: dict[str, float] = {"pi": math.pi, "e": math.e}


def is_chain(node: ast.AST) -> bool:
    """Whether ``node`` is a binary operation that chains (any operator but ``**``)."""
    return isinstance(node, ast.BinOp) and not isinstance(node.op, ast.Pow)


def chain_links(node: ast.BinOp) -> list[ast.BinOp]:
    """The links of a left-associated chain ``((a op b) op c) ...``, innermost first."""
    links: list[ast.BinOp] = []
    link: ast.expr = node
    while is_chain(link):
        assert isinstance(link, ast.BinOp)
        links.append(link)
        link = link.left
    return links[::-1]
