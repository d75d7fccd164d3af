"""Which cells to refine: by an expression, by region, or by the distance to a patch.

Each function returns a *marking*, a callable ``marking(mesh) -> mask`` that
:func:`blockmesh.refine` (``cells=``) asks again on every round's mesh, so that "the cells within
0.1 of the wall" are the cells of the refined mesh within 0.1 of the wall in the next round.

- :func:`where`: cells where an expression of ``x, y`` is positive at the cell's vertex mean or at
  one of its vertices (``"0.3 - sqrt((x-1)^2 + (y-1)^2)"``: within 0.3 of (1, 1));
- :func:`in_region`: the cells of a named region;
- :func:`near_patch`: the cells within a distance of a boundary patch's edges (shapely's
  distance between the cell and the patch, so a cell counts when any part of it is that near);
- :func:`any_of`: the union of several markings.

A marking that marks no cell of the mesh it is first asked about raises
:class:`~blockmesh.errors.ArgumentError` saying so (and why: the expression is nowhere positive,
the region or patch is elsewhere); unknown regions and patches raise
:class:`~blockmesh.errors.UnknownNameError` listing the names there are.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("l-shape").mesh(1)
>>> int(where("0.2 - sqrt((x-1)^2 + (y-1)^2)")(mesh).sum())
6
>>> int(near_patch("inlet", 0.1)(mesh).sum()), int(in_region("corner")(mesh).sum())
(6, 48)
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from blockmesh.errors import ArgumentError, UnknownNameError
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh, as_polygon_mesh
from blockmesh.numerics.expr import parse_expression

__all__ = ["Marking", "any_of", "check_marks", "in_region", "near_patch", "parse_near", "where"]

#: A marking: the mesh of a round in, a boolean mask over its cells out.
Marking = Callable[[Mesh | PolygonMesh], np.ndarray]


def where(expression: str) -> Marking:
    """The cells where ``expression`` (of x, y) is positive at the vertex mean or a vertex.

    The expression is parsed now (ExpressionError with the column of a mistake).
    """
    function = parse_expression(expression)

    def marking(mesh: Mesh | PolygonMesh) -> np.ndarray:
        pm = as_polygon_mesh(mesh)
        centre = pm.vertex_means()
        with np.errstate(all="ignore"):
            inside = np.asarray(function(centre[:, 0], centre[:, 1])) > 0
            at_vertex = np.asarray(function(pm.points[:, 0], pm.points[:, 1])) > 0
        owner = pm.polygon_cells().slot_cell()
        inside = inside | (np.bincount(owner, at_vertex[pm.nodes], minlength=pm.n_cells) > 0)
        return inside

    marking.__doc__ = f"where {expression!r} > 0"
    return marking


def in_region(name: str) -> Marking:
    """The cells of the region ``name`` (UnknownNameError listing the regions)."""

    def marking(mesh: Mesh | PolygonMesh) -> np.ndarray:
        if name not in mesh.region_names:
            raise UnknownNameError(
                f"no region {name!r}; the regions are {', '.join(mesh.region_names)}"
            )
        return np.asarray(mesh.region) == mesh.region_names.index(name)

    marking.__doc__ = f"in region {name!r}"
    return marking


def near_patch(patch: str, distance: float) -> Marking:
    """The cells within ``distance`` (>= 0) of the edges of boundary patch ``patch``."""
    if isinstance(distance, bool) or not np.isfinite(float(distance)) or float(distance) < 0:
        raise ArgumentError(f"the distance to patch {patch!r} must be >= 0, got {distance!r}")
    reach = float(distance)

    def marking(mesh: Mesh | PolygonMesh) -> np.ndarray:
        import shapely

        pm = as_polygon_mesh(mesh)
        edges = pm.patch_edges(patch)
        lines = shapely.multilinestrings(shapely.linestrings(pm.points[edges]))
        out = np.zeros(pm.n_cells, dtype=bool)
        for group in pm.groups:
            cells = shapely.polygons(pm.points[group.cells])
            out[group.index] = shapely.dwithin(cells, lines, reach)
        return out

    marking.__doc__ = f"within {reach:g} of patch {patch!r}"
    return marking


def parse_near(text: str) -> tuple[str, float]:
    """``"PATCH:DISTANCE"`` as ``(patch, distance)`` (ArgumentError on a malformed text).

    Examples
    --------
    >>> parse_near("wall:0.25")
    ('wall', 0.25)
    """
    patch, sign, number = text.rpartition(":")
    try:
        distance = float(number)
    except ValueError:
        distance = float("nan")
    if not sign or not patch.strip() or not np.isfinite(distance) or distance < 0:
        raise ArgumentError(
            f"{text!r}: write PATCH:DISTANCE, a patch name and a distance >= 0 (e.g. wall:0.1)"
        )
    return patch.strip(), distance


def any_of(*markings: Marking) -> Marking:
    """The cells any of ``markings`` marks."""
    if not markings:
        raise ArgumentError("any_of needs at least one marking")

    def marking(mesh: Mesh | PolygonMesh) -> np.ndarray:
        out = np.zeros(mesh.n_cells, dtype=bool)
        for part in markings:
            out |= np.asarray(part(mesh), dtype=bool)
        return out

    marking.__doc__ = " or ".join(m.__doc__ or "a marking" for m in markings)
    return marking


def check_marks(marking: Marking, mesh: Mesh | PolygonMesh) -> np.ndarray:
    """The mask of ``marking`` on ``mesh``; ArgumentError naming it when it marks no cell."""
    mask = np.asarray(marking(mesh), dtype=bool)
    if not mask.any():
        raise ArgumentError(
            f"the marking ({marking.__doc__ or 'given'}) marks none of the {mesh.n_cells:,} "
            "cells; nothing would be refined"
        )
    return mask
