"""Curved block edges: circular arcs, splines and polylines, each parametrised on [0, 1].

A curve runs from its ``start`` to its ``end`` point; ``point(t)`` and ``derivative(t)`` take a
number or an array of parameters and return points of shape ``(..., 2)``. The types are small
frozen values:

- :class:`Arc`: a circular arc given by a point it passes through (``through``) or by its centre
  (``center``, the shorter of the two arcs); uniform in angle.
- :class:`Spline`: the C1 cubic through the given interior points (tangents from the parabola
  through each point and its neighbours), parametrised by the chord lengths between the points.
- :class:`Polyline`: the straight pieces through the given interior points, uniform in length.

A curve is written without its ends and bound to the two vertices of a block edge by
:meth:`Curve.with_ends` (``Domain.from_blocks(..., edges=...)`` does that). Binding checks the
shape and raises :class:`~blockmesh.errors.DomainError` with the reason: an arc whose centre is
not equally far from both ends, a through point on the line of the ends, a spline that crosses
itself. Nodes of a refined mesh on a curved block edge sit at the dyadic parameters ``k/2^L`` of
its curve (``docs/mathematics.md`` §1), so every boundary node lies on the curve.

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

import math
import numbers
import re
from abc import ABC, abstractmethod
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from blockmesh.errors import ArgumentError, DomainError, DomainFormatError, fmt_point

__all__ = ["CURVE_KINDS", "Arc", "Curve", "Polyline", "Spline", "curve_from_fields"]

#: Relative tolerance of the shape checks (distances compared with the curve's size).
SHAPE_TOL = 1e-9
#: Samples per spline or polyline piece used to detect a curve crossing itself.
_LOOP_SAMPLES = 24
#: Most interior points of one spline or polyline (each piece is sampled to check for loops).
MAX_CURVE_POINTS = 5_000

Point = tuple[float, float]


def as_point(value: object, what: str) -> Point:
    """``value`` as an ``(x, y)`` pair of finite floats, or DomainFormatError naming ``what``."""
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        raise DomainFormatError(f"{what} must be a pair [x, y], got {value!r:.80}")
    pair = list(value)
    if len(pair) != 2 or not all(
        isinstance(c, numbers.Real) and not isinstance(c, bool) for c in pair
    ):
        raise DomainFormatError(f"{what} must be a pair [x, y] of numbers, got {value!r:.80}")
    try:
        x, y = float(pair[0]), float(pair[1])
    except OverflowError:
        raise DomainError(f"{what} has a coordinate too large for a double") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise DomainError(f"{what} ({x!r}, {y!r}) is not finite")
    return (x, y)


def _points(value: object, what: str) -> tuple[Point, ...]:
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        raise DomainFormatError(f"{what} must be a list of [x, y] pairs, got {value!r}")
    points = tuple(as_point(p, f"{what} {k}") for k, p in enumerate(value))
    if not points:
        raise DomainFormatError(
            f"{what} is empty: give at least one interior point (a straight edge needs no entry)"
        )
    return points


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _parameters(t: Any) -> np.ndarray:
    return np.asarray(t, dtype=np.float64)


@dataclass(frozen=True)
class Curve(ABC):
    """What every curve offers; see :class:`Arc`, :class:`Spline` and :class:`Polyline`.

    Attributes
    ----------
    start, end : (x, y) or None
        The ends, set by :meth:`with_ends` (None for a curve not yet bound to an edge).
    """

    kind: ClassVar[str] = "curve"

    start: Point | None = field(default=None, kw_only=True)
    end: Point | None = field(default=None, kw_only=True)

    # ------------------------------------------------------------------ binding
    def with_ends(self, start: Iterable[float], end: Iterable[float], where: str = "") -> Curve:
        """The same shape bound to the ends ``start`` and ``end`` (checked; see the module doc).

        ``where`` (e.g. ``"edge (3, 4)"``) starts every error message.

        Examples
        --------
        >>> Arc(center=(0, 0)).with_ends((1, 0), (0, 2), "edge (0, 1)")  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        blockmesh.errors.DomainError: the arc on edge (0, 1) cannot reach both ends ...
        """
        bound = replace(self, start=as_point(start, "start"), end=as_point(end, "end"))
        bound._prepare(where)
        return bound

    @abstractmethod
    def _prepare(self, where: str) -> None:
        """Compute and store the parametrisation; raise DomainError if the shape is invalid."""
        raise NotImplementedError

    def _label(self, where: str) -> str:
        return f"the {self.kind} on {where}" if where else f"the {self.kind}"

    def _ends(self) -> tuple[np.ndarray, np.ndarray]:
        if self.start is None or self.end is None:
            raise ArgumentError(
                f"this {self.kind} has no ends yet; bind it to an edge with "
                "with_ends(start, end) or give it to Domain.from_blocks(..., edges=...)"
            )
        return np.array(self.start), np.array(self.end)

    # ------------------------------------------------------------------ geometry
    @abstractmethod
    def point(self, t: Any) -> np.ndarray:
        """Points at the parameters ``t`` (any shape), shape ``t.shape + (2,)``."""
        raise NotImplementedError

    @abstractmethod
    def derivative(self, t: Any) -> np.ndarray:
        """Derivatives dγ/dt at the parameters ``t``, shape ``t.shape + (2,)``."""
        raise NotImplementedError

    def breaks(self) -> np.ndarray:
        """Parameters strictly inside (0, 1) where the curve's pieces join (empty for an arc).

        Between two breaks the curve is a polynomial (spline, polyline) or an arc, so quadrature
        over a piece is exact or converges fast.
        """
        return np.zeros(0)

    def pieces(self, t0: np.ndarray, t1: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The intervals from ``t0[i]`` to ``t1[i]`` cut at the :meth:`breaks` inside them.

        Returns ``(owner, a, b)``: piece ``j`` runs from parameter ``a[j]`` to ``b[j]`` (in the
        direction from ``t0`` to ``t1``) and belongs to interval ``owner[j]``; pieces of an
        interval are consecutive and in order.

        Examples
        --------
        >>> line = Polyline(points=[(1, 0)]).with_ends((0, 0), (2, 0))
        >>> [v.tolist() for v in line.pieces(np.array([0.25, 1.0]), np.array([0.75, 0.75]))]
        [[0, 0, 1], [0.25, 0.5, 1.0], [0.5, 0.75, 0.75]]
        """
        t0 = np.asarray(t0, dtype=np.float64).ravel()
        t1 = np.asarray(t1, dtype=np.float64).ravel()
        knots = np.concatenate([[-np.inf], self.breaks(), [np.inf]])
        lo, hi = np.minimum(t0, t1), np.maximum(t0, t1)
        first = np.searchsorted(knots, lo, side="right")
        count = np.maximum(np.searchsorted(knots, hi, side="left") - first, 0) + 1
        owner = np.repeat(np.arange(t0.size), count)
        piece = np.arange(owner.size) - np.repeat(np.cumsum(count) - count, count)
        ahead = (t1 >= t0)[owner]
        # Count pieces from the interval's t0 end: forwards from lo, backwards from hi.
        k = np.where(ahead, piece, count[owner] - 1 - piece)
        cut = knots[np.clip(first[owner] + k - 1, 0, knots.size - 1)]
        after = knots[np.clip(first[owner] + k, 0, knots.size - 1)]
        left = np.where(k == 0, lo[owner], cut)
        right = np.where(k == count[owner] - 1, hi[owner], after)
        a = np.where(ahead, left, right)
        b = np.where(ahead, right, left)
        return owner, a, b

    @abstractmethod
    def segment_area(self, t0: Any, t1: Any) -> np.ndarray:
        """Signed area between the curve from ``t0`` to ``t1`` and its chord.

        ``(1/2) ∫ det(γ(t) - γ(t0), γ'(t)) dt``: positive when the curve bulges to the right of
        the chord's direction (outwards of a counter-clockwise cell whose edge it replaces).
        """
        raise NotImplementedError

    @property
    @abstractmethod
    def length(self) -> float:
        """Length of the curve."""
        raise NotImplementedError

    @abstractmethod
    def to_fields(self) -> dict[str, Any]:
        """The shape's defining values, as a domain file writes them (ends not included)."""
        raise NotImplementedError

    def _polyline_samples(self) -> np.ndarray:
        """Points along the curve, dense enough to see it cross itself or another edge."""
        pieces = 1 + self.breaks().size
        return self.point(np.linspace(0.0, 1.0, pieces * _LOOP_SAMPLES + 1))


def _empty() -> np.ndarray:
    return np.zeros(0)


def _store(curve: Curve, **values: Any) -> None:
    for name, value in values.items():
        object.__setattr__(curve, name, value)


# ---------------------------------------------------------------------------- arcs
@dataclass(frozen=True)
class Arc(Curve):
    """A circular arc through ``through``, or around ``center`` (the shorter way); give one.

    Parametrised uniformly in angle: ``γ(t) = c + R (cos(θ0 + tΔ), sin(θ0 + tΔ))``. With
    ``center``, both ends must be at the same distance from it (to 1e-9 relative) and must not
    be opposite each other (a half circle has two possible arcs: give ``through`` then).

    Examples
    --------
    >>> arc = Arc(through=(0, 1)).with_ends((-1, 0), (1, 0))
    >>> arc.centre_point, round(arc.radius, 12), round(arc.sweep, 12)
    ((0.0, 0.0), 1.0, -3.14159265359)
    >>> arc.derivative(0.5).round(12).tolist()  # clockwise over the top
    [3.14159265359, -0.0]
    """

    kind: ClassVar[str] = "arc"

    through: Point | None = None
    center: Point | None = None
    _c: np.ndarray = field(default_factory=_empty, init=False, repr=False, compare=False)
    _r: float = field(default=0.0, init=False, repr=False, compare=False)
    _theta: tuple[float, float] = field(default=(0.0, 0.0), init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if (self.through is None) == (self.center is None):
            raise DomainFormatError(
                "an arc needs exactly one of through = [x, y] or center = [x, y]"
            )
        if self.through is not None:
            _store(self, through=as_point(self.through, "the arc's through point"))
        else:
            _store(self, center=as_point(self.center, "the arc's center"))

    @property
    def radius(self) -> float:
        """Radius R."""
        self._ends()
        return self._r

    @property
    def sweep(self) -> float:
        """Signed angle Δ from start to end (positive counter-clockwise), radians."""
        self._ends()
        return self._theta[1]

    @property
    def centre_point(self) -> Point:
        """Centre of the circle (whether given or found from ``through``)."""
        self._ends()
        return (float(self._c[0]), float(self._c[1]))

    def _prepare(self, where: str) -> None:
        p, q = self._ends()
        label = self._label(where)
        chord = float(np.hypot(*(q - p)))
        if chord == 0.0:
            raise DomainError(f"{label} has both ends at {fmt_point(p)}")
        if self.through is not None:
            m = np.array(self.through)
            a, b = q - p, m - p
            twice_area = float(_cross(b, a))  # > 0 when start -> through -> end turns right
            scale = max(chord, float(np.hypot(*b)), float(np.hypot(*(m - q))))
            if min(float(np.hypot(*b)), float(np.hypot(*(m - q)))) <= SHAPE_TOL * scale:
                raise DomainError(
                    f"{label} has its through point {fmt_point(m)} at an end; give a point on the "
                    "arc between the ends"
                )
            if abs(twice_area) <= SHAPE_TOL * scale * scale:
                raise DomainError(
                    f"{label}: the through point {fmt_point(m)} is on the straight line between "
                    "the "
                    f"ends {fmt_point(p)} and {fmt_point(q)}; for a straight edge leave the edge "
                    "out, or "
                    "move the point off the line"
                )
            d = 2.0 * float(_cross(a, b))
            aa, bb = float(a @ a), float(b @ b)
            centre = p + np.array([b[1] * aa - a[1] * bb, a[0] * bb - b[0] * aa]) / d
            radius = float(np.hypot(*(p - centre)))
            theta0 = math.atan2(p[1] - centre[1], p[0] - centre[0])
            # Counter-clockwise turns from the start to the end and to the through point: the
            # arc runs counter-clockwise when it meets the through point on the way.
            full = 2 * math.pi
            to_end = _angle_between(p - centre, q - centre) % full
            to_through = _angle_between(p - centre, m - centre) % full
            sweep = to_end if to_through < to_end else to_end - full
        else:
            centre = np.array(self.center)
            r0, r1 = float(np.hypot(*(p - centre))), float(np.hypot(*(q - centre)))
            if abs(r0 - r1) > SHAPE_TOL * max(r0, r1):
                raise DomainError(
                    f"{label} cannot reach both ends from its centre {fmt_point(centre)}: the "
                    "start "
                    f"{fmt_point(p)} is {r0:.12g} from it and the end {fmt_point(q)} {r1:.12g} "
                    "(they differ "
                    f"by {abs(r0 - r1):.3g}); put the centre on the perpendicular bisector of "
                    "the ends, or give a through point instead"
                )
            radius = 0.5 * (r0 + r1)
            theta0 = math.atan2(p[1] - centre[1], p[0] - centre[0])
            sweep = _angle_between(p - centre, q - centre)
            if abs(sweep) >= math.pi * (1 - SHAPE_TOL):
                raise DomainError(
                    f"{label}: the ends {fmt_point(p)} and {fmt_point(q)} are opposite each "
                    "other across "
                    f"the centre {fmt_point(centre)}, so either half circle fits; give a through "
                    "point instead of the centre"
                )
        _store(self, _c=centre, _r=radius, _theta=(theta0, sweep))

    def point(self, t: Any) -> np.ndarray:
        """Points ``c + R (cos θ, sin θ)`` at ``θ = θ0 + tΔ``; exactly the ends at 0 and 1."""
        p, q = self._ends()
        t = _parameters(t)
        angle = self._theta[0] + t * self._theta[1]
        out = np.stack([np.cos(angle), np.sin(angle)], axis=-1) * self._r + self._c
        out[t == 0] = p
        out[t == 1] = q
        return out

    def derivative(self, t: Any) -> np.ndarray:
        """``RΔ (-sin θ, cos θ)``."""
        self._ends()
        angle = self._theta[0] + _parameters(t) * self._theta[1]
        return np.stack([-np.sin(angle), np.cos(angle)], axis=-1) * (self._r * self._theta[1])

    def segment_area(self, t0: Any, t1: Any) -> np.ndarray:
        """``(R²/2)(φ - sin φ)`` with ``φ = Δ (t1 - t0)`` (the circular segment, signed)."""
        self._ends()
        phi = (_parameters(t1) - _parameters(t0)) * self._theta[1]
        # φ - sin φ loses digits for small φ; its series is accurate there.
        small = np.abs(phi) < 1e-2
        phi2 = phi * phi
        series = phi * phi2 / 6 * (1 - phi2 / 20 * (1 - phi2 / 42 * (1 - phi2 / 72)))
        return 0.5 * self._r**2 * np.where(small, series, phi - np.sin(phi))

    @property
    def length(self) -> float:
        """``R |Δ|``."""
        self._ends()
        return self._r * abs(self._theta[1])

    def to_fields(self) -> dict[str, Any]:
        """``{"through": [x, y]}`` or ``{"center": [x, y]}``, as given."""
        if self.through is not None:
            return {"through": list(self.through)}
        return {"center": list(self.center)}  # type: ignore[arg-type]


def _angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """Signed angle from vector ``a`` to vector ``b``, in (-π, π]."""
    return math.atan2(float(_cross(a, b)), float(a @ b))


# ---------------------------------------------------------------------------- piecewise curves
@dataclass(frozen=True)
class _Pieces(Curve):
    """A curve through ``start``, the interior ``points`` and ``end``, in pieces."""

    points: tuple[Point, ...] = ()
    _knots: np.ndarray = field(default_factory=_empty, init=False, repr=False, compare=False)
    _nodes: np.ndarray = field(default_factory=_empty, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if hasattr(self.points, "__len__") and len(self.points) > MAX_CURVE_POINTS:
            raise DomainError(
                f"the {self.kind} has {len(self.points):,} points; at most {MAX_CURVE_POINTS:,} "
                "(a curve of more is a polygon: give its corners)"
            )
        _store(self, points=_points(self.points, f"the {self.kind}'s points"))

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
        _store(self, _knots=knots, _nodes=nodes)
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
        t = _parameters(t)
        piece, _, u = self._locate(t)
        a, b = self._nodes[piece], self._nodes[piece + 1]
        out = a + u[..., None] * (b - a)
        out[t == 1] = self._nodes[-1]
        return out

    def derivative(self, t: Any) -> np.ndarray:
        """Constant on each piece (the right-hand derivative at the points)."""
        self._ends()
        piece, width, _ = self._locate(_parameters(t))
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

    _tangents: np.ndarray = field(default_factory=_empty, init=False, repr=False, compare=False)

    def _prepare_pieces(self) -> None:
        nodes, knots = self._nodes, self._knots
        h = np.diff(knots)[:, None]
        slope = np.diff(nodes, axis=0) / h
        tangents = np.empty_like(nodes)
        # Interior: the parabola's tangent (Bessel), weighting each side's slope by the other width.
        tangents[1:-1] = (slope[:-1] * h[1:] + slope[1:] * h[:-1]) / (h[:-1] + h[1:])
        tangents[0] = 2 * slope[0] - tangents[1]
        tangents[-1] = 2 * slope[-1] - tangents[-2]
        _store(self, _tangents=tangents)

    def _hermite(self, t: Any, derivative: bool) -> np.ndarray:
        self._ends()
        t = _parameters(t)
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
    t0, t1 = np.broadcast_arrays(_parameters(t0), _parameters(t1))
    owner, left, right = curve.pieces(t0.ravel(), t1.ravel())
    x, w = np.polynomial.legendre.leggauss(n)
    s = left[:, None] + (right - left)[:, None] * (x + 1) / 2
    origin = curve.point(t0.ravel())[owner][:, None, :]
    values = _cross(curve.point(s) - origin, curve.derivative(s)) @ w * (right - left) / 2
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


# ---------------------------------------------------------------------------- domain files
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
