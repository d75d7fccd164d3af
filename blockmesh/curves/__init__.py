"""Curved edges: the curve types, and the table of a mesh's edges that lie on them.

:mod:`~blockmesh.curves.base` defines what every :class:`Curve` shares,
:mod:`~blockmesh.curves.arc` the :class:`Arc`, :mod:`~blockmesh.curves.piecewise` the
:class:`Polyline` and the :class:`Spline`, and :mod:`~blockmesh.curves.types` names the kinds for
domain files (and gives every name at its old path); :mod:`~blockmesh.curves.edges` holds the
:class:`CurvedEdges` table every stage shares. Each stage keeps its own curved work beside its
straight work: nodes placed on curves in :mod:`blockmesh.refinement.curved`, curved domains and
their checks in :mod:`blockmesh.domain`, integrals over curved cells in
:mod:`blockmesh.quadrature.curved`.
"""

from __future__ import annotations

from blockmesh.curves.edges import CurvedEdges, area_corrections, curved_slots, edge_points
from blockmesh.curves.types import CURVE_KINDS, Arc, Curve, Polyline, Spline, curve_from_fields

__all__ = [
    "CURVE_KINDS",
    "Arc",
    "Curve",
    "CurvedEdges",
    "Polyline",
    "Spline",
    "area_corrections",
    "curve_from_fields",
    "curved_slots",
    "edge_points",
]
