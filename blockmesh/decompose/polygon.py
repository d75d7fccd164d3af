"""Any polygon with holes to strictly convex pentagonal blocks: the decomposition's front door.

:func:`decompose_polygon` takes validated rings (:func:`blockmesh.domain.validate.check_rings`) and
chooses the route:

- a strictly convex polygon without holes and with at most :data:`CONVEX_LIMIT` corners goes to the
  exact layouts of :mod:`blockmesh.decompose.convex` (the fewest blocks: 1 for a pentagon, 9 for a
  triangle, ``ceil((n - 2) / 3)`` for ``n >= 6``), unless their worst angle is below
  :data:`CONVEX_MIN_ANGLE` and the general route does better (a 50:1 rectangle);
- everything else (non-convex polygons, holes, straight corners kept between two patches, many
  corners) is triangulated with quality refinement (:mod:`blockmesh.decompose.triangulate`),
  neighbouring triangles are paired into convex quadrilaterals where that keeps them round
  (:mod:`blockmesh.decompose.merge`), every piece becomes its ring-and-hub template (9 pentagons
  for a triangle, 12 for a quadrilateral) with side nodes shared bit for bit
  (:mod:`blockmesh.decompose.pieces`), and the free nodes are moved to raise the worst angle
  (:mod:`blockmesh.decompose.optimise`).

Both work in the rings' local frame (:func:`blockmesh.geometry.local_frame`) and map back, the
rings' own corners bit for bit, so the result does not depend on where the polygon sits.

Examples
--------
>>> import numpy as np
>>> outer = np.array([[0, 0], [3, 0], [3, 3], [0, 3]], dtype=float)
>>> hole = np.array([[1, 1], [1, 2], [2, 2], [2, 1]], dtype=float)  # clockwise
>>> d = decompose_polygon([outer, hole])
>>> d.layout, len(d.hole_chains), bool(d.min_angle > 20)
('triangulation', 1, True)
>>> d.vertices[:4].tolist() == outer.tolist()  # the corners come first, unchanged
True
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from blockmesh.decompose.convex import CHORD_LIMIT, check_corners_clear, decompose_convex_polygon
from blockmesh.decompose.decomposition import Decomposition, in_local_frame
from blockmesh.decompose.triangulate import DEFAULT_MIN_ANGLE
from blockmesh.decompose.triangulated import triangulated_decomposition
from blockmesh.errors import DomainError, DomainFormatError, ResourceError
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    corner_sines,
)

__all__ = [
    "CONVEX_LIMIT",
    "CONVEX_MIN_ANGLE",
    "MAX_CORNERS",
    "MAX_FILE_CORNERS",
    "check_corner_count",
    "check_file_corners",
    "decompose_polygon",
]

#: Strictly convex polygons (no holes) with at most this many corners get the exact layouts.
CONVEX_LIMIT = CHORD_LIMIT
#: Exact convex layouts with a worst angle below this (degrees) are compared with the general route.
CONVEX_MIN_ANGLE = 20.0
#: Most ring corners accepted: what the decomposition does in seconds. Measured on this
#: project's machine (2 cores): a smooth 1,000-corner outline in about 5 s, a jagged one (a
#: random star, whose close features grade the triangulation down: 80,000 blocks) in about 10 s;
#: 2,000 corners took 6 s and 36 s, 10,000 smooth ones 38 s.
MAX_CORNERS = 1_000


#: Most corners of all the polygons of one domain file, counted before it is parsed (a
#: composite domain's parts have at most :data:`MAX_CORNERS` each): a file of millions of
#: coordinates is refused in milliseconds instead of being parsed first.
MAX_FILE_CORNERS = 20 * MAX_CORNERS


def check_file_corners(count: int, path: Any, counted: str) -> None:
    """DomainFormatError when a domain file's ``count`` corners exceed :data:`MAX_FILE_CORNERS`.

    ``counted`` names what was counted in the text (one per corner), for the message.

    Examples
    --------
    >>> check_file_corners(10**6, "big.wkt", "comma")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: big.wkt: the outline has about 1,000,000 corners (a comma...
    """
    if count > MAX_FILE_CORNERS:
        raise DomainFormatError(
            f"{path}: the outline has about {count:,} corners (a {counted} per corner, counted "
            f"before parsing); a domain file holds at most {MAX_FILE_CORNERS:,}, and a polygon "
            f"at most {MAX_CORNERS:,}, which the decomposition does in seconds (simplify the "
            "outline, or split the domain into parts)"
        )


def check_corner_count(total: int, what: str = "the polygon") -> None:
    """ResourceError when ``total`` corners are more than :data:`MAX_CORNERS`.

    Called as soon as the corners are counted (by the readers, before anything is parsed
    further or decomposed).

    Examples
    --------
    >>> check_corner_count(1_000_000)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.ResourceError: the polygon has 1,000,000 corners; at most 1,000 are ...
    """
    if total > MAX_CORNERS:
        raise ResourceError(
            f"{what} has {total:,} corners; at most {MAX_CORNERS:,} are decomposed, which takes "
            "seconds (simplify the outline, e.g. with shapely's simplify, or split the domain "
            "into parts)"
        )


def decompose_polygon(
    rings: Sequence[np.ndarray], *, min_angle: float = DEFAULT_MIN_ANGLE
) -> Decomposition:
    """Split a polygon with holes into strictly convex pentagons that meet edge to edge.

    Parameters
    ----------
    rings : sequence of ndarray (n_r, 2)
        The outer ring counter-clockwise, then the holes clockwise, as
        :func:`blockmesh.domain.validate.check_rings` returns them.
    min_angle : float
        Target smallest angle of the quality triangulation (degrees) for the general route.

    Returns
    -------
    Decomposition
        ``vertices`` start with the rings' corners, ring after ring, bit for bit;
        ``edge_chains`` run along the outer ring's edges, ``hole_chains[k]`` along hole k's.

    Raises
    ------
    ResourceError
        If the rings have more than :data:`MAX_CORNERS` corners.
    DomainError
        If double precision cannot hold the blocks where the polygon sits (blocks smaller than a
        few units in the last place of its coordinates, or, for the exact convex layouts, a
        block corner within a few of them of the chord of its neighbours:
        :func:`~blockmesh.decompose.convex.check_corners_clear`).
    """
    rings = [np.asarray(r, dtype=np.float64) for r in rings]
    check_corner_count(sum(len(r) for r in rings))

    def best(local: list[np.ndarray]) -> Decomposition:
        decomposition = None
        if len(local) == 1 and len(local[0]) <= CONVEX_LIMIT and _strictly_convex(local[0]):
            try:
                decomposition = decompose_convex_polygon(local[0])
            except (DomainError, ValueError):
                decomposition = None  # too thin for the exact layouts: the general route copes
        if decomposition is None or decomposition.min_angle < CONVEX_MIN_ANGLE:
            general = triangulated_decomposition(local, min_angle)
            # A clear margin, so that round-off (say, of a shift) does not flip the choice.
            if decomposition is None or general.min_angle > decomposition.min_angle + 1.0:
                decomposition = general
        return decomposition

    # The routes work in the local frame, where a sliver is wide in units of the spacing of
    # doubles; back where the polygon sits it may be a few spacings wide (a triangle 5e-15 wide
    # at x = 1), its block corners too close to their chords to stay corners. The exact convex
    # layouts are checked for that as decompose_convex_polygon checks them; the general route
    # only for folds (in_local_frame): it keeps ring corners that may themselves sit within
    # round-off of their chords (boolean operations rounded to a grid leave such corners).
    decomposition = in_local_frame(rings, best)
    if decomposition.layout != "triangulation":
        check_corners_clear(decomposition.vertices, decomposition.blocks)
    return decomposition


def _strictly_convex(ring: np.ndarray) -> bool:
    return bool(np.all(corner_sines(ring) > COLLINEAR_SIN_TOL))
