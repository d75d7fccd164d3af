"""Curved block edges: circular arcs, splines and polylines, each parametrised on [0, 1].

A curve runs from its ``start`` to its ``end`` point; ``point(t)`` and ``derivative(t)`` take a
number or an array of parameters and return points of shape ``(..., 2)``. The types are small
frozen values:

- :class:`~blockmesh.curves.arc.Arc`: a circular arc given by a point it passes through
  (``through``) or by its centre (``center``, the shorter of the two arcs); uniform in angle.
- :class:`~blockmesh.curves.piecewise.Spline`: the C1 cubic through the given interior points
  (tangents from the parabola through each point and its neighbours), parametrised by the chord
  lengths between the points.
- :class:`~blockmesh.curves.piecewise.Polyline`: the straight pieces through the given interior
  points, uniform in length.

A curve is written without its ends and bound to the two vertices of a block edge by
:meth:`Curve.with_ends <blockmesh.curves.base.Curve.with_ends>`
(``Domain.from_blocks(..., edges=...)`` does that). Binding checks the shape and raises
:class:`~blockmesh.errors.DomainError` with the reason: an arc whose centre is not equally far
from both ends, a through point on the line of the ends, a spline that crosses itself. Nodes of a
refined mesh on a curved block edge sit at the dyadic parameters ``k/2^L`` of its curve
(``docs/mathematics.md`` §1), so every boundary node lies on the curve.

The base class and what the kinds share are in :mod:`~blockmesh.curves.base`, the kinds in
:mod:`~blockmesh.curves.arc` and :mod:`~blockmesh.curves.piecewise`; this module names them for
domain files (:data:`CURVE_KINDS`, :func:`curve_from_fields`) and gives every name at its old path.

Examples
--------
>>> arc = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
>>> arc.point([0, 0.5, 1]).round(12).tolist()
[[1.0, 0.0], [0.707106781187, 0.707106781187], [0.0, 1.0]]
>>> round(arc.length, 12) == round(3.141592653589793 / 2, 12)
True
>>> Spline(points=[(1, 1)]).with_ends((0, 0), (2, 0)).point(0.5).tolist()
[1.0, 1.0]
"""

from __future__ import annotations

from typing import Any

from blockmesh.curves.arc import Arc
from blockmesh.curves.base import SHAPE_TOL as SHAPE_TOL
from blockmesh.curves.base import Curve
from blockmesh.curves.base import Point as Point
from blockmesh.curves.base import as_point as as_point
from blockmesh.curves.piecewise import MAX_CURVE_POINTS as MAX_CURVE_POINTS
from blockmesh.curves.piecewise import Polyline, Spline
from blockmesh.errors import DomainError, DomainFormatError

__all__ = ["CURVE_KINDS", "Arc", "Curve", "Polyline", "Spline", "curve_from_fields"]


#: The curve kinds a domain file names, and the fields each takes.
CURVE_KINDS: dict[str, tuple[type[Curve], tuple[str, ...]]] = {
    "arc": (Arc, ("through", "center")),
    "spline": (Spline, ("points",)),
    "polyline": (Polyline, ("points",)),
}


def curve_from_fields(kind: str, fields: dict[str, Any], where: str) -> Curve:
    """A curve of ``kind`` from its fields as a domain file gives them (unbound).

    Examples
    --------
    >>> curve_from_fields("arc", {"center": [0, 0]}, "edges entry 1")
    Arc(start=None, end=None, through=None, center=(0.0, 0.0))
    """
    if kind not in CURVE_KINDS:
        raise DomainFormatError(
            f"{where}: unknown curve {kind!r}; the curves are {', '.join(CURVE_KINDS)}"
        )
    cls, names = CURVE_KINDS[kind]
    unknown = sorted(set(fields) - set(names))
    if unknown:
        raise DomainFormatError(
            f"{where}: a {kind} takes {' or '.join(names)}, not {', '.join(map(repr, unknown))}"
        )
    try:
        return cls(**fields)
    except (DomainError, TypeError) as error:
        raise DomainFormatError(f"{where}: {error}") from None
