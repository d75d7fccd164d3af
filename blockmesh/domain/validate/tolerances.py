"""The tolerances of the domain checks: when two points are one, when two rings touch.

Every check works in the domain's local frame (:func:`blockmesh.geometry.polygons.local_frame`),
so these are relative to the domain's size, and the verdicts do not depend on where it sits.

Examples
--------
>>> import numpy as np
>>> from blockmesh.geometry.polygons import local_frame
>>> same_point_tol(local_frame(np.array([[0.0, 0.0], [1.0, 1.0]]))) == GAP_TOL
True
"""

from __future__ import annotations

from blockmesh.geometry.polygons import LocalFrame

__all__ = ["GAP_TOL", "MIN_EXTENT", "NEAR_TOL", "same_point_tol"]

#: Two distinct points closer than this (relative to the domain's size, or 4 ulps of its
#: coordinates where that is more) are "the same point"; a vertex this close to an edge it is not
#: on is a hanging node. Small enough for slivers of aspect ratio up to about 1e10.
GAP_TOL = 1e-11
#: Separate boundary loops (or rings) closer than this, relative to the domain's size, are taken
#: for a gap between blocks that should meet (or rings that touch).
NEAR_TOL = 1e-6
#: Smallest span of a domain's coordinates accepted: its areas (squares of spans, and smaller
#: still at high levels) must not underflow to zero.
MIN_EXTENT = 1e-100


def same_point_tol(frame: LocalFrame) -> float:
    """Distance (local units) under which two points count as one: GAP_TOL or a few ulps."""
    return max(GAP_TOL, 4.0 * frame.ulp() / frame.scale)
