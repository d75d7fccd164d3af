"""What every curve shares: the :class:`Curve` base class, points checked, and the shape tolerance.

A curve runs from its ``start`` to its ``end`` point, parametrised on [0, 1]; :class:`Curve`
declares what each kind provides (points, derivatives, segment areas, length, its fields in a
domain file) and implements what follows from those (binding to the ends with the shape checked,
the pieces between breaks, samples to detect crossings). The kinds are in
:mod:`~blockmesh.curves.arc` and :mod:`~blockmesh.curves.piecewise`; :mod:`~blockmesh.curves.types`
lists them by name.

Examples
--------
>>> as_point([1, 2.5], "the centre")
(1.0, 2.5)
>>> as_point([1, "a"], "the centre")
Traceback (most recent call last):
...
blockmesh.errors.DomainFormatError: the centre must be a pair [x, y] of numbers, got [1, 'a']
"""

from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from blockmesh.errors import ArgumentError, DomainError, DomainFormatError

__all__ = ["SHAPE_TOL", "Curve", "Point", "as_point"]

#: Relative tolerance of the shape checks (distances compared with the curve's size).
SHAPE_TOL = 1e-9
#: Samples per spline or polyline piece used to detect a curve crossing itself.
_LOOP_SAMPLES = 24

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


def as_points(value: object, what: str) -> tuple[Point, ...]:
    """``value`` as a non-empty tuple of points (a curve's interior points), checked."""
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


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The cross product ``a x b`` of 2-D vectors (the last axis), a scalar each."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def parameters(t: Any) -> np.ndarray:
    """Parameters as a float64 array (of any shape)."""
    return np.asarray(t, dtype=np.float64)


@dataclass(frozen=True)
class Curve(ABC):
    """What every curve offers.

    The kinds are :class:`~blockmesh.curves.arc.Arc`, :class:`~blockmesh.curves.piecewise.Spline`
    and :class:`~blockmesh.curves.piecewise.Polyline`.

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
        """The same shape bound to the ends ``start`` and ``end``, its shape checked.

        ``where`` (e.g. ``"edge (3, 4)"``) starts every error message; what each kind refuses is
        listed in :mod:`blockmesh.curves.types`.

        Examples
        --------
        >>> from blockmesh.curves import Arc
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
        >>> from blockmesh.curves import Polyline
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


def unset_array() -> np.ndarray:
    """The default of a curve's precomputed arrays, set when it is bound to its ends."""
    return np.zeros(0)


def store(curve: Curve, **values: Any) -> None:
    """Set fields of a frozen curve (its checked inputs and precomputed parametrisation)."""
    for name, value in values.items():
        object.__setattr__(curve, name, value)
