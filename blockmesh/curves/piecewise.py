"""Curves in pieces through interior points: polylines and C1 cubic splines.

Both run through their ``start``, the interior ``points`` and their ``end``, parametrised by the
chord lengths between the points, and refuse, when bound to their ends, a point listed twice
or a curve that crosses itself (found through GEOS):

- :class:`Polyline`: the straight pieces, uniform in length;
- :class:`Spline`: the C1 cubic whose tangent at each point is that of the parabola through it
  and its neighbours.

Examples
--------
>>> line = Polyline(points=[(1, 1)]).with_ends((0, 0), (2, 0))
>>> line.breaks().tolist(), line.point(0.75).tolist()
([0.5], [1.5, 0.5])
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from blockmesh.curves.base import SHAPE_TOL, Curve, as_points, cross, parameters, store, unset_array
from blockmesh.errors import DomainError, fmt_point

__all__ = ["MAX_CURVE_POINTS", "Polyline", "Spline"]

#: Most interior points of one spline or polyline (each piece is sampled to check for loops).
MAX_CURVE_POINTS = 5_000


@dataclass(frozen=True)
class _Pieces(Curve):
    """A curve through ``start``, the interior ``points`` and ``end``, in pieces."""

    points: tuple[tuple[float, float], ...] = ()
    _knots: np.ndarray = field(default_factory=unset_array, init=False, repr=False, compare=False)
    _nodes: np.ndarray = field(default_factory=unset_array, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if hasattr(self.points, "__len__") and len(self.points) > MAX_CURVE_POINTS:
            raise DomainError(
                f"the {self.kind} has {len(self.points):,} points; at most {MAX_CURVE_POINTS:,} "
                "(a curve of more is a polygon: give its corners)"
            )
        store(self, points=as_points(self.points, f"the {self.kind}'s points"))

    def _prepare(self, where: str) -> None:
        p, q = self._ends()
        nodes = np.vstack([p, np.array(self.points), q])
        steps = np.hypot(*np.diff(nodes, axis=0).T)
        label = self._label(where)
        size = float(steps.sum())
        repeated = np.flatnonzero(steps <= SHAPE_TOL * size)
        if repeated.size:
            k = int(repeated[0])
            raise DomainError(
                f"{label} passes twice through {fmt_point(nodes[k])} (points {k} and {k + 1} of "
                "start, points..., end coincide); list every point once"
            )
        knots = np.concatenate([[0.0], np.cumsum(steps) / size])
        knots[-1] = 1.0
        store(self, _knots=knots, _nodes=nodes)
        self._prepare_pieces()
        # the polyline through the points first (n points, not 24 n samples): a curve whose
        # points run over each other loops, and GEOS, slower on lines that overlap much, is
        # spared its samples
        crossing = _first_crossing(nodes)
        if crossing is None:
            crossing = _first_crossing(self._polyline_samples())
        if crossing is not None:
            raise DomainError(
                f"{label} crosses itself near {fmt_point(crossing)}; reorder its points or space "
                "them "
                "so that it does not loop"
            )

    def _prepare_pieces(self) -> None:
        """Precompute what evaluating the pieces needs (a hook: a polyline needs nothing more)."""

    def breaks(self) -> np.ndarray:
        """The parameters of the interior points."""
        self._ends()
        return self._knots[1:-1].copy()

    def _locate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Piece index, its parameter width and the local parameter ``u`` in [0, 1] of ``t``."""
        knots = self._knots
        piece = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2)
        width = knots[piece + 1] - knots[piece]
        return piece, width, (t - knots[piece]) / width

    def to_fields(self) -> dict[str, Any]:
        """``{"points": [[x, y], ...]}``."""
        return {"points": [list(p) for p in self.points]}


@dataclass(frozen=True)
class Polyline(_Pieces):
    """Straight pieces through the interior ``points``, parametrised uniformly in length.

    Examples
    --------
    >>> line = Polyline(points=[(1, 1)]).with_ends((0, 0), (2, 0))
    >>> line.point([0.25, 0.5]).tolist(), round(line.length, 12)
    ([[0.5, 0.5], [1.0, 1.0]], 2.828427124746)
    """

    kind: ClassVar[str] = "polyline"

    def point(self, t: Any) -> np.ndarray:
        """Linear interpolation between the points."""
        self._ends()
        t = parameters(t)
        piece, _, u = self._locate(t)
        a, b = self._nodes[piece], self._nodes[piece + 1]
        out = a + u[..., None] * (b - a)
        out[t == 1] = self._nodes[-1]
        return out

    def derivative(self, t: Any) -> np.ndarray:
        """Constant on each piece (the right-hand derivative at the points)."""
        self._ends()
        piece, width, _ = self._locate(parameters(t))
        return (self._nodes[piece + 1] - self._nodes[piece]) / width[..., None]

    def segment_area(self, t0: Any, t1: Any) -> np.ndarray:
        """Exact (the integrand is linear on each piece)."""
        return _piecewise_segment_area(self, t0, t1, 1)

    @property
    def length(self) -> float:
        """Sum of the pieces' lengths."""
        self._ends()
        return float(np.sum(np.hypot(*np.diff(self._nodes, axis=0).T)))


@dataclass(frozen=True)
class Spline(_Pieces):
    """The C1 cubic through the interior ``points``, parametrised by chord length.

    Each piece between two points is a cubic Hermite polynomial; the tangent at a point is that of
    the parabola (in the chord-length parameter) through it and its two neighbours, at the ends
    through the first or last three points. Collinear points give the straight segment.

    Examples
    --------
    >>> s = Spline(points=[(1, 1)]).with_ends((0, 0), (2, 0))
    >>> s.point([0.25, 0.75]).round(12).tolist()
    [[0.5, 0.75], [1.5, 0.75]]
    """

    kind: ClassVar[str] = "spline"

    _tangents: np.ndarray = field(
        default_factory=unset_array, init=False, repr=False, compare=False
    )

    def _prepare_pieces(self) -> None:
        nodes, knots = self._nodes, self._knots
        h = np.diff(knots)[:, None]
        slope = np.diff(nodes, axis=0) / h
        tangents = np.empty_like(nodes)
        # Interior: the parabola's tangent (Bessel), weighting each side's slope by the other width.
        tangents[1:-1] = (slope[:-1] * h[1:] + slope[1:] * h[:-1]) / (h[:-1] + h[1:])
        tangents[0] = 2 * slope[0] - tangents[1]
        tangents[-1] = 2 * slope[-1] - tangents[-2]
        store(self, _tangents=tangents)

    def _hermite(self, t: Any, derivative: bool) -> np.ndarray:
        self._ends()
        t = parameters(t)
        piece, width, u = self._locate(t)
        p0, p1 = self._nodes[piece], self._nodes[piece + 1]
        m0 = self._tangents[piece] * width[..., None]
        m1 = self._tangents[piece + 1] * width[..., None]
        u = u[..., None]
        if derivative:
            u2 = u * u
            return (
                (6 * u2 - 6 * u) * p0
                + (3 * u2 - 4 * u + 1) * m0
                + (6 * u - 6 * u2) * p1
                + (3 * u2 - 2 * u) * m1
            ) / width[..., None]
        # Bernstein form: control points p0, p0 + m0/3, p1 - m1/3, p1.
        v = 1 - u
        out = v * v * (v * p0 + 3 * u * (p0 + m0 / 3)) + u * u * (3 * v * (p1 - m1 / 3) + u * p1)
        out[t == 1] = self._nodes[-1]
        return out

    def point(self, t: Any) -> np.ndarray:
        """Points on the cubic pieces."""
        return self._hermite(t, derivative=False)

    def derivative(self, t: Any) -> np.ndarray:
        """Derivatives of the cubic pieces (continuous at the points)."""
        return self._hermite(t, derivative=True)

    def segment_area(self, t0: Any, t1: Any) -> np.ndarray:
        """Exact for the cubic pieces (Gauss-Legendre with 4 points on each piece)."""
        return _piecewise_segment_area(self, t0, t1, 4)

    @property
    def length(self) -> float:
        """Arc length (Gauss-Legendre with 16 points on each piece)."""
        self._ends()
        x, w = np.polynomial.legendre.leggauss(16)
        total = 0.0
        for a, b in zip(self._knots[:-1], self._knots[1:], strict=True):
            t = a + (b - a) * (x + 1) / 2
            total += (b - a) / 2 * float(w @ np.hypot(*self.derivative(t).T))
        return total


def _piecewise_segment_area(curve: _Pieces, t0: Any, t1: Any, n: int) -> np.ndarray:
    """``segment_area`` by ``n``-point Gauss-Legendre on every piece of every interval."""
    t0, t1 = np.broadcast_arrays(parameters(t0), parameters(t1))
    owner, left, right = curve.pieces(t0.ravel(), t1.ravel())
    x, w = np.polynomial.legendre.leggauss(n)
    s = left[:, None] + (right - left)[:, None] * (x + 1) / 2
    origin = curve.point(t0.ravel())[owner][:, None, :]
    values = cross(curve.point(s) - origin, curve.derivative(s)) @ w * (right - left) / 2
    return 0.5 * np.bincount(owner, weights=values, minlength=t0.size).reshape(t0.shape)


# ---------------------------------------------------------------------------- self-crossings
def _first_crossing(line: np.ndarray) -> np.ndarray | None:
    """A point where two non-adjacent segments of the open polyline ``line`` meet, or None.

    O(n log n) in the n points, in O(n) memory (GEOS): whether the line is simple decides; where
    it crosses is what GEOS's validity check of the line closed into a ring reports (its first
    self-intersection; the start when it names none). Collinear pieces doubling back count as
    crossings too.

    Examples
    --------
    >>> _first_crossing(np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, -1.0]])).tolist()
    [1.0, 0.0]
    >>> _first_crossing(np.array([[0, 0], [1, 0], [1, 1.0]])) is None
    True
    """
    import shapely

    if line.shape[0] < 4 or not np.all(np.isfinite(line)):
        return None
    if shapely.is_simple(shapely.linestrings(line)):
        return None
    reason = shapely.is_valid_reason(shapely.polygons(np.vstack([line, line[:1]])))
    found = _WHERE.search(reason or "")
    return np.array([float(found[1]), float(found[2])]) if found else line[0]


_WHERE = re.compile(r"\[([-+0-9.eE]+) ([-+0-9.eE]+)")
