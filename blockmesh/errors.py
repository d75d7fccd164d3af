"""Typed errors and warnings raised by blockmesh.

Every failure the library detects is a :class:`BlockMeshError`; the subclasses say which stage
found it. Messages name the offending vertex, edge, block, key or token, with coordinates, and say
how to fix the input. The command line prints the message (no traceback) and exits non-zero.

Examples
--------
>>> from blockmesh.errors import BlockMeshError, DomainError
>>> issubclass(DomainError, BlockMeshError)
True
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = [
    "ArgumentError",
    "ArgumentTypeError",
    "BlockMeshError",
    "BlockMeshWarning",
    "DomainError",
    "DomainFormatError",
    "ExportError",
    "ExpressionError",
    "ResourceError",
    "SolverError",
    "TopologyError",
    "UnknownNameError",
    "fmt_point",
]


class BlockMeshError(Exception):
    """Base class of every error blockmesh raises on bad input or impossible requests."""


class ArgumentError(BlockMeshError, ValueError):
    """An argument of a library call has a value it cannot take (a level of -1, an unknown rule).

    Also a :class:`ValueError`, so code that catches the built-in keeps working.
    """


class ArgumentTypeError(BlockMeshError, TypeError):
    """An argument of a library call has the wrong type (a string where a Mesh is needed).

    Also a :class:`TypeError`.
    """


class UnknownNameError(ArgumentError, KeyError):
    """A name (patch, region, format, catalogue entry) that does not exist.

    The message lists the names that do exist. Also a :class:`KeyError` (and a
    ``ValueError``); its text is the plain message.
    """

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class DomainError(BlockMeshError):
    """The geometry of a domain is invalid (coordinates, orientation, convexity, area)."""


class DomainFormatError(DomainError):
    """A domain file or inline polygon cannot be parsed (malformed TOML, wrong keys or types)."""


class TopologyError(BlockMeshError):
    """Blocks do not form a conforming, connected block mesh (overlaps, gaps, hanging nodes)."""


class ExpressionError(BlockMeshError):
    """A function expression is malformed, unsafe or not what the operation needs."""


class ExportError(BlockMeshError):
    """A mesh cannot be written or read in the requested format."""


class ResourceError(BlockMeshError):
    """A request needs more memory (or other resources) than allowed."""


class SolverError(BlockMeshError):
    """A boundary-value problem is ill-posed (no Dirichlet data, unknown patch) or unsolvable."""


class BlockMeshWarning(UserWarning):
    """Something the user should know about: input accepted after a repair, or a result to doubt.

    Repairs: clockwise order reversed, a repeated closing vertex or a straight corner dropped.
    Doubts: an integral whose error estimate is large (a singular or unresolved integrand).
    """


def fmt_point(point: Iterable[float], digits: int = 12) -> str:
    """A point as messages show it: ``(x, y)``, each coordinate to ``digits`` significant digits.

    Examples
    --------
    >>> fmt_point([1.0, 0.25]), fmt_point((1 / 3, 2.0), digits=6)
    ('(1, 0.25)', '(0.333333, 2)')
    """
    return "(" + ", ".join(f"{float(c):.{digits}g}" for c in point) + ")"
