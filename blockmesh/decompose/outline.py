"""The outline the size-driven decomposition fills, and its sampling at the sizes asked.

An :class:`Outline` is corners joined by chains (straight or curved; boundaries, and interfaces
between regions), each chain knowing the region on its left and on its right. Every chain gets
points at spacings that follow the triangle edge length wanted (arc length along curves, which
also get a point every :data:`CURVE_TURN` of turning, or every :data:`CURVE_TURN_SAFE` when
the outline asks for it); the points are fixed from there on, and
each chain is sampled once, so a shared interface is the same on both sides. The sampled chains
(:class:`_Chains`) are what :mod:`blockmesh.decompose.sized_triangles` fills and triangulates;
:func:`arc_pieces` gives the curve of each piece of a chain to the Domain made from the blocks.

Examples
--------
>>> square = Outline.from_rings([np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)])
>>> square.chains.tolist()
[[0, 1], [1, 2], [2, 3], [3, 0]]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.curves.types import Arc, Curve
from blockmesh.errors import ResourceError

__all__ = ["CURVE_TURN", "CURVE_TURN_SAFE", "MAX_BLOCKS", "ChainCurve", "Outline", "arc_pieces"]

#: Largest turn of a curved chain between two of its points (radians): 40 degrees (each
#: block edge along it, a third of that). Finer sampling costs cells where the field is coarse
#: beside a small curve: at 30 degrees fibre-cell at sqrt(area) / 25 (fibres of radius 3.75 h)
#: needed 2.33 times the ideal count, at 40 degrees 1.84 times.
CURVE_TURN = 2 * math.pi / 9
#: The turn of an outline sampled again because a block along a curve folded at 40 degrees
#: (30 degrees; a curve bulging across a block much larger than its radius of curvature,
#: e.g. fibre-cell at sizes above the fibres' diameter).
CURVE_TURN_SAFE = math.pi / 6
#: Most blocks made (about 9 per triangle); beyond, ResourceError (the memory guard of
#: :func:`blockmesh.sizing.ideal_count` says so first, for sizes it can see).
MAX_BLOCKS = 20_000_000


@dataclass(frozen=True, eq=False)
class ChainCurve:
    """A stretch of a curve from parameter ``t0`` to ``t1`` (``t1 < t0`` runs it backwards).

    Examples
    --------
    >>> quarter = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
    >>> ChainCurve(quarter, 1.0, 0.0).point(np.array([0.0, 1.0])).round(12).tolist()
    [[0.0, 1.0], [1.0, 0.0]]
    """

    curve: Curve
    t0: float = 0.0
    t1: float = 1.0

    def parameter(self, s: np.ndarray) -> np.ndarray:
        """The curve's parameter at the chain's parameter ``s``."""
        return self.t0 + np.asarray(s, dtype=np.float64) * (self.t1 - self.t0)

    def point(self, s: np.ndarray) -> np.ndarray:
        """Points at the chain's parameters ``s`` in [0, 1]."""
        return np.asarray(self.curve.point(self.parameter(s)))

    def derivative(self, s: np.ndarray) -> np.ndarray:
        """Derivatives with respect to the chain's parameter."""
        return np.asarray(self.curve.derivative(self.parameter(s))) * (self.t1 - self.t0)


@dataclass(frozen=True, eq=False)
class Outline:
    """Corners joined by chains (straight or curved), with the regions on their sides.

    Attributes
    ----------
    corners : ndarray (K, 2)
    chains : ndarray (C, 2) int
        Each chain runs from corner ``chains[c, 0]`` to ``chains[c, 1]``.
    curves : tuple of (ChainCurve or None)
        Each chain's curve from its start (parameter 0) to its end (1), or None if straight.
    left, right : ndarray (C,) int
        The region on each side of the chain as it runs; -1 outside the domain.
    curve_turn : float
        Largest turn of a curved chain between two of its points, in radians
        (:data:`CURVE_TURN`; :data:`CURVE_TURN_SAFE` samples curves more finely).
    """

    corners: np.ndarray
    chains: np.ndarray
    curves: tuple[ChainCurve | None, ...]
    left: np.ndarray
    right: np.ndarray
    curve_turn: float = CURVE_TURN

    @classmethod
    def from_rings(
        cls, rings: Sequence[np.ndarray], curves: Sequence[Curve | None] | None = None
    ) -> Outline:
        """A one-region outline from rings (outer counter-clockwise, holes clockwise).

        ``curves`` lists a curve (or None) per ring edge, ring after ring.

        Examples
        --------
        >>> Outline.from_rings([np.array([[0, 0], [1, 0], [0, 1]], dtype=float)]).chains.tolist()
        [[0, 1], [1, 2], [2, 0]]
        """
        counts = [len(r) for r in rings]
        corners = np.vstack([np.asarray(r, dtype=np.float64) for r in rings])
        start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        a = np.concatenate([s + np.arange(c) for s, c in zip(start, counts, strict=True)])
        b = np.concatenate([s + (np.arange(c) + 1) % c for s, c in zip(start, counts, strict=True)])
        n = len(a)
        given = (
            tuple(None if c is None else ChainCurve(c) for c in curves)
            if curves is not None
            else (None,) * n
        )
        return cls(
            corners, np.column_stack([a, b]), given, np.zeros(n, np.int64), -np.ones(n, np.int64)
        )


# ---------------------------------------------------------------------------- sampling
def _chain_params(outline: Outline, c: int, length, *, pieces_at_least: int = 1) -> np.ndarray:
    """Parameters (m + 1,) from 0 to 1 spacing the chain at the triangle side ``length``.

    The arc length is integrated with a dense sampling; the points are equally spaced in
    ``integral of ds / L`` (so the pieces follow the field along the chain), at least
    ``pieces_at_least`` of them, and curves get a piece per ``outline.curve_turn`` of turning.
    """
    a, b = outline.chains[c]
    curve = outline.curves[c]
    p, q = outline.corners[a], outline.corners[b]

    def where(t: np.ndarray) -> np.ndarray:
        return p + t[:, None] * (q - p) if curve is None else curve.point(t)

    samples = 32
    pieces = pieces_at_least
    turns = 0
    if curve is not None:
        tangent = curve.derivative(np.linspace(0.0, 1.0, 257))
        heading = np.unwrap(np.arctan2(tangent[:, 1], tangent[:, 0]))
        turns = math.ceil(float(np.sum(np.abs(np.diff(heading)))) / outline.curve_turn - 1e-9)
    for _ in range(4):
        t = np.linspace(0.0, 1.0, samples + 1)
        xy = where(t)
        ds = np.hypot(*np.diff(xy, axis=0).T)
        middle = where(0.5 * (t[:-1] + t[1:]))
        measure = np.concatenate([[0.0], np.cumsum(ds / length(middle))])
        pieces = max(pieces_at_least, turns, round(float(measure[-1])), 1)
        if samples >= 8 * pieces:
            break
        samples = 8 * pieces
    if pieces > MAX_BLOCKS:
        raise ResourceError(
            f"the size field asks for {pieces:,} pieces along one boundary or interface line; "
            "give larger sizes"
        )
    # Equal steps of the measure (and of the turning, on curves, where it asks for more).
    targets = np.linspace(0.0, float(measure[-1]), pieces + 1)
    params = np.interp(targets, measure, t)
    if turns > round(float(measure[-1])):
        params = np.linspace(0.0, 1.0, pieces + 1)
    params[0], params[-1] = 0.0, 1.0
    return params


def _chain_points(outline: Outline, c: int, params: np.ndarray) -> np.ndarray:
    """Global coordinates of chain ``c`` at ``params`` (the ends are the corners, bit for bit)."""
    a, b = outline.chains[c]
    curve = outline.curves[c]
    p, q = outline.corners[a], outline.corners[b]
    xy = p + params[:, None] * (q - p) if curve is None else np.asarray(curve.point(params))
    xy = np.array(xy, dtype=np.float64)
    xy[0], xy[-1] = p, q
    return xy


class _Chains:
    """The outline's sample points (fixed) and segments, each segment on one chain."""

    def __init__(self, outline: Outline, frame, length) -> None:
        self.outline = outline
        self.frame = frame
        k = len(outline.corners)
        points = [outline.corners]
        seg_a, seg_b, seg_chain, seg_t0, seg_t1 = [], [], [], [], []
        self.params: list[np.ndarray] = []
        next_id = k
        for c in range(len(outline.chains)):
            params = _chain_params(outline, c, length)
            self.params.append(params)
            inner = len(params) - 2
            ids = np.concatenate(
                [[outline.chains[c, 0]], next_id + np.arange(inner), [outline.chains[c, 1]]]
            )
            points.append(_chain_points(outline, c, params)[1:-1])
            next_id += inner
            seg_a.append(ids[:-1])
            seg_b.append(ids[1:])
            seg_chain.append(np.full(len(ids) - 1, c))
            seg_t0.append(params[:-1])
            seg_t1.append(params[1:])
        self.global_points = np.vstack(points)
        self.a = np.concatenate(seg_a)
        self.b = np.concatenate(seg_b)
        self.chain = np.concatenate(seg_chain)
        self.t0 = np.concatenate(seg_t0)
        self.t1 = np.concatenate(seg_t1)

    @property
    def n(self) -> int:
        return len(self.global_points)

    def local(self) -> np.ndarray:
        return self.frame.to_local(self.global_points)

    def segments(self) -> np.ndarray:
        """The segments in local coordinates, (S, 2, 2)."""
        local = self.local()
        return np.stack([local[self.a], local[self.b]], axis=1)

    def split(self, segments: np.ndarray) -> None:
        """Split the given segments at their middle parameter (a new fixed point each)."""
        t = 0.5 * (self.t0[segments] + self.t1[segments])
        new_points = np.empty((len(segments), 2))
        for c in np.unique(self.chain[segments]):
            sel = self.chain[segments] == c
            new_points[sel] = _chain_points(
                self.outline, int(c), np.concatenate([[0.0], t[sel], [1.0]])
            )[1:-1]
        ids = self.n + np.arange(len(segments))
        self.global_points = np.vstack([self.global_points, new_points])
        keep_b, keep_t1 = self.b[segments].copy(), self.t1[segments].copy()
        self.b[segments] = ids
        self.t1[segments] = t
        self.a = np.concatenate([self.a, ids])
        self.b = np.concatenate([self.b, keep_b])
        self.chain = np.concatenate([self.chain, self.chain[segments]])
        self.t0 = np.concatenate([self.t0, t])
        self.t1 = np.concatenate([self.t1, keep_t1])


def arc_pieces(outline: Outline, c: int, params: np.ndarray) -> list[Curve]:
    """The curve of chain ``c`` between consecutive ``params``, each as an arc through its middle.

    An arc chain's pieces are arcs of the same circle; a spline's are the arcs through three of
    its points (its ends and its middle), close to it at the sizes of a sized mesh.
    """
    curve = outline.curves[c]
    if curve is None:
        return []
    middle = curve.point(0.5 * (params[:-1] + params[1:]))
    return [Arc(through=(float(x), float(y))) for x, y in np.asarray(middle)]
