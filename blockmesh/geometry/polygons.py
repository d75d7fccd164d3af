"""Polygon predicates and measures on coordinate arrays.

Every function takes polygons as an array of shape ``(..., K, 2)`` (any number of leading axes,
``K`` corners each) and works on all of them at once, without Python loops. Corners are taken in the
order given; "interior" angles assume counter-clockwise order.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
>>> float(signed_area(square))
1.0
>>> interior_angles(square).round(6).tolist()
[90.0, 90.0, 90.0, 90.0]
>>> bool(is_strictly_convex(square))
True
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

#: The names :mod:`blockmesh.geometry` gives from this module (those it has given since 0.1).
PACKAGE_NAMES = (
    "COLLINEAR_SIN_TOL",
    "LocalFrame",
    "corner_sines",
    "interior_angles",
    "is_strictly_convex",
    "local_frame",
    "polygon_diameter",
    "signed_area",
    "vertex_mean",
)

__all__ = [*PACKAGE_NAMES, "DIRECTIONS", "MAX_COORDINATE", "edges_facing"]

#: A corner whose turn has ``|sin| <= COLLINEAR_SIN_TOL`` counts as straight (180 degrees).
#: Sines are computed from coordinate differences, which are exact for nearby points wherever
#: they sit, and are accurate to about 1e-16; so 1e-12 separates a real corner from round-off
#: while letting slivers of aspect ratio up to about 1e10 count as proper corners.
COLLINEAR_SIN_TOL = 1e-12
#: Largest coordinate magnitude accepted from any input (domains and mesh files): squares of
#: coordinate differences must stay finite.
MAX_COORDINATE = 1e150


class LocalFrame(NamedTuple):
    """An origin and a length scale: local coordinates are ``(x - origin) / scale``.

    Validation and decomposition work in local coordinates, so that a domain's verdict does not
    depend on where it sits or how large it is (products of large coordinates lose the digits
    that carry the geometry; differences of nearby ones do not).
    """

    origin: np.ndarray
    scale: float

    def to_local(self, points: np.ndarray) -> np.ndarray:
        """``(points - origin) / scale``."""
        return (np.asarray(points, dtype=np.float64) - self.origin) / self.scale

    def to_global(self, points: np.ndarray) -> np.ndarray:
        """``points * scale + origin`` (the inverse of :meth:`to_local`)."""
        return np.asarray(points, dtype=np.float64) * self.scale + self.origin

    def ulp(self) -> float:
        """Spacing of doubles at the largest coordinate the frame covers (global units)."""
        reach = float(np.max(np.abs(self.origin))) + self.scale
        return float(np.spacing(reach))


def local_frame(points: np.ndarray) -> LocalFrame:
    """The frame of a point set: its bounding-box centre and the bounding box's diagonal.

    Examples
    --------
    >>> frame = local_frame(np.array([[1e9, 1e9], [1e9 + 3, 1e9 + 4]]))
    >>> frame.origin.tolist(), frame.scale
    ([1000000001.5, 1000000002.0], 5.0)
    >>> frame.to_local(np.array([[1e9, 1e9]])).tolist()
    [[-0.3, -0.4]]
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    low, high = p.min(axis=0), p.max(axis=0)
    origin = low + (high - low) / 2
    scale = float(np.hypot(*(high - low)))
    return LocalFrame(origin, scale if scale > 0 else 1.0)


#: The directions an edge of a polygon can face, as named in patch lists, with their unit vectors.
DIRECTIONS = {"left": (-1.0, 0.0), "right": (1.0, 0.0), "bottom": (0.0, -1.0), "top": (0.0, 1.0)}


def edges_facing(ring: np.ndarray) -> dict[str, list[int]]:
    """The edges of a closed ring that face each of :data:`DIRECTIONS`, by their index.

    Edge ``i`` runs from corner ``i`` to corner ``i + 1``; it faces the direction its outward
    normal points most nearly to (outward from the region the ring bounds, whichever way the
    ring runs). An edge at exactly 45 degrees faces left or right; an edge of length zero faces
    nowhere.

    Examples
    --------
    >>> bracket = np.array([[0, 0], [4, 0], [4, 1], [1, 1], [1, 3], [0, 3]], dtype=float)
    >>> edges_facing(bracket)
    {'left': [5], 'right': [1, 3], 'bottom': [0], 'top': [2, 4]}
    >>> edges_facing(bracket[::-1])["right"]  # clockwise: the same edges, numbered backwards
    [1, 3]
    """
    ring = np.asarray(ring, dtype=np.float64)
    step = np.roll(ring, -1, axis=0) - ring
    normal = np.column_stack([step[:, 1], -step[:, 0]])  # outward for a counter-clockwise ring
    if float(signed_area(ring)) < 0:
        normal = -normal
    towards = normal @ np.array(list(DIRECTIONS.values())).T  # (K, 4)
    facing = np.argmax(towards, axis=1)
    moving = np.any(step != 0, axis=1)
    return {
        word: np.flatnonzero(moving & (facing == k)).tolist() for k, word in enumerate(DIRECTIONS)
    }


def signed_area(polygons: np.ndarray) -> np.ndarray:
    """Signed area of each polygon by the shoelace formula (positive when counter-clockwise).

    Each polygon is measured relative to its first corner, so the result does not lose digits
    when the polygon sits far from the origin (a unit square at 1e9 has area 1, not 0).

    Parameters
    ----------
    polygons : ndarray, shape (..., K, 2)

    Returns
    -------
    ndarray, shape (...)

    Examples
    --------
    >>> float(signed_area(np.array([[0, 0], [0, 1], [1, 0]], dtype=float)))
    -0.5
    >>> float(signed_area(np.array([[0, 0], [1, 0], [1, 1], [0, 1]]) + 1e9))
    1.0
    """
    p = np.asarray(polygons, dtype=np.float64)
    p = p - p[..., :1, :]
    x, y = p[..., 0], p[..., 1]
    xn, yn = np.roll(x, -1, axis=-1), np.roll(y, -1, axis=-1)
    return 0.5 * np.sum(x * yn - xn * y, axis=-1)


def vertex_mean(polygons: np.ndarray) -> np.ndarray:
    """Mean of each polygon's corners (the paper's centre point ``p``), shape ``(..., 2)``.

    Examples
    --------
    >>> vertex_mean(np.array([[0, 0], [2, 0], [2, 2], [0, 2]], dtype=float)).tolist()
    [1.0, 1.0]
    """
    return np.asarray(polygons, dtype=np.float64).mean(axis=-2)


def _edge_vectors(polygons: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(polygons, dtype=np.float64)
    incoming = p - np.roll(p, 1, axis=-2)  # from the previous corner to this one
    outgoing = np.roll(p, -1, axis=-2) - p  # from this corner to the next
    return incoming, outgoing


def corner_sines(polygons: np.ndarray) -> np.ndarray:
    """Sine of the turn at each corner: positive for a left (convex, CCW) turn, 0 when straight.

    Returns ``nan`` at a corner with a zero-length adjacent edge.

    Examples
    --------
    >>> corner_sines(np.array([[0, 0], [1, 0], [2, 0], [1, 1]], dtype=float)).round(6).tolist()
    [0.707107, 0.0, 0.707107, 1.0]
    """
    incoming, outgoing = _edge_vectors(polygons)
    cross = incoming[..., 0] * outgoing[..., 1] - incoming[..., 1] * outgoing[..., 0]
    norms = np.hypot(incoming[..., 0], incoming[..., 1]) * np.hypot(
        outgoing[..., 0], outgoing[..., 1]
    )
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norms > 0, cross / np.where(norms > 0, norms, 1.0), np.nan)


def interior_angles(polygons: np.ndarray) -> np.ndarray:
    """Interior angle at each corner in degrees, for counter-clockwise polygons.

    A convex corner is below 180 degrees, a reflex one above.

    Examples
    --------
    >>> tri = np.array([[0, 0], [1, 0], [0, 1]], dtype=float)
    >>> interior_angles(tri).round(6).tolist()
    [90.0, 45.0, 45.0]
    """
    incoming, outgoing = _edge_vectors(polygons)
    cross = incoming[..., 0] * outgoing[..., 1] - incoming[..., 1] * outgoing[..., 0]
    dot = incoming[..., 0] * outgoing[..., 0] + incoming[..., 1] * outgoing[..., 1]
    return 180.0 - np.degrees(np.arctan2(cross, dot))


def is_strictly_convex(polygons: np.ndarray, sin_tol: float = COLLINEAR_SIN_TOL) -> np.ndarray:
    """Whether each polygon is counter-clockwise and strictly convex.

    Every corner must turn left by more than ``sin_tol`` (no straight or reflex corners, no
    repeated corners) and the corners must go around exactly once (no star shapes).

    Examples
    --------
    >>> pent = np.array([[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]], dtype=float)
    >>> bool(is_strictly_convex(pent)), bool(is_strictly_convex(pent[::-1]))
    (True, False)
    """
    sines = corner_sines(polygons)
    left_turns = np.all(np.nan_to_num(sines, nan=-1.0) > sin_tol, axis=-1)
    # Left turns everywhere plus a total turning of exactly 360 degrees rules out pentagrams.
    turning = np.sum(180.0 - interior_angles(polygons), axis=-1)
    return left_turns & np.isclose(turning, 360.0, atol=1e-6)


def polygon_diameter(polygons: np.ndarray) -> np.ndarray:
    """Largest distance between two corners of each polygon, shape ``(...)``.

    Examples
    --------
    >>> float(polygon_diameter(np.array([[0, 0], [3, 0], [3, 4]], dtype=float)))
    5.0
    """
    p = np.asarray(polygons, dtype=np.float64)
    diff = p[..., :, None, :] - p[..., None, :, :]
    return np.sqrt(np.max(np.sum(diff * diff, axis=-1), axis=(-2, -1)))
