"""The result of every decomposition, and the local frame every decomposition is made in.

A decomposition is computed in a local frame (the polygon moved near the origin and scaled to
unit size, :func:`blockmesh.geometry.local_frame`), where the geometric tolerances mean the same
whatever the polygon's size and place, then mapped back with the polygon's own corners restored
bit for bit (:func:`in_local_frame`).

Examples
--------
>>> import numpy as np
>>> from blockmesh.decompose.convex import decompose_convex_polygon
>>> d = decompose_convex_polygon(np.array([[0, 0], [1, 0], [0, 1]], dtype=float))
>>> d.layout, d.blocks.shape, d.edge_chains[0].tolist()
('triangle-template', (9, 5), [0, 3, 4, 1])
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.errors import DomainError
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    LocalFrame,
    corner_sines,
    interior_angles,
    local_frame,
)

__all__ = ["Decomposition", "in_local_frame"]


@dataclass(frozen=True)
class Decomposition:
    """A convex polygon split into strictly convex pentagons that meet edge to edge.

    Attributes
    ----------
    vertices : ndarray, shape (K, 2), float64, read-only
        Rows ``0..n-1`` are the polygon's vertices, bit for bit and in order; then the new points
        (used edge midpoints, the hub, template nodes).
    blocks : ndarray, shape (B, 5), int64, read-only
        Each row a counter-clockwise, strictly convex pentagon of vertex ids.
    edge_chains : tuple of ndarray
        ``edge_chains[i]`` lists the vertex ids along polygon edge ``i``, from vertex ``i`` to
        vertex ``(i + 1) % n`` inclusive, in order.
    layout : str
        ``"pentagon"``, ``"chords"``, ``"star"``, ``"triangle-template"`` or ``"quad-template"``
        for a convex polygon's exact layouts; ``"triangulation"`` for the general route of
        :func:`blockmesh.decompose.decompose_polygon`.
    min_angle, max_angle : float
        Smallest and largest interior angle over all blocks, in degrees.
    hole_chains : tuple of tuple of ndarray
        ``hole_chains[k][i]``: the vertex ids along edge ``i`` of hole ``k``, as ``edge_chains``
        (empty for a polygon without holes).

    """

    vertices: np.ndarray
    blocks: np.ndarray
    edge_chains: tuple[np.ndarray, ...]
    layout: str
    min_angle: float
    max_angle: float
    hole_chains: tuple[tuple[np.ndarray, ...], ...] = ()


def in_local_frame(
    rings: Sequence[np.ndarray], decompose: Callable[[list[np.ndarray]], Decomposition]
) -> Decomposition:
    """``decompose`` applied to the rings in their local frame, its result mapped back.

    The rings' corners come back bit for bit; the blocks are checked to stay strictly convex
    once rounded to the global coordinates.
    """
    rings = [np.asarray(r, dtype=np.float64) for r in rings]
    frame = local_frame(np.vstack(rings))
    return _to_global(decompose([frame.to_local(r) for r in rings]), rings, frame)


def _to_global(d: Decomposition, rings: list[np.ndarray], frame: LocalFrame) -> Decomposition:
    """Map a decomposition made in local coordinates back; the ring corners bit for bit."""
    vertices = frame.to_global(d.vertices)
    corners = np.vstack(rings)
    vertices[: len(corners)] = corners
    _check_representable(vertices, d.blocks, frame)
    angles = interior_angles(vertices[d.blocks])
    for a in (vertices, d.blocks, *d.edge_chains, *(c for h in d.hole_chains for c in h)):
        a.setflags(write=False)
    return Decomposition(
        vertices=vertices,
        blocks=d.blocks,
        edge_chains=d.edge_chains,
        layout=d.layout,
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
        hole_chains=d.hole_chains,
    )


def _check_representable(
    vertices: np.ndarray,
    blocks: np.ndarray,
    frame: LocalFrame,
    what: str = "the polygon",
    advice: str = "move the domain near the origin (or use other units)",
) -> None:
    """Blocks that rounding to the global coordinates made non-convex: too small for doubles.

    ``what`` names what was decomposed and ``advice`` ends the message (what to do instead).
    """
    sines = corner_sines(vertices[blocks])
    bad = np.flatnonzero(~np.all(sines > COLLINEAR_SIN_TOL, axis=1))
    if bad.size:
        size = float(np.ptp(vertices[blocks[bad[0]]], axis=0).max())
        raise DomainError(
            f"{what} is too small for where it sits to be decomposed in double precision: "
            f"its blocks are about {size:.3g} across "
            f"at coordinates near {float(np.max(np.abs(frame.origin))):.3g}, where doubles are "
            f"only {frame.ulp():.3g} apart, and rounding folds {bad.size} of them; {advice}"
        )
