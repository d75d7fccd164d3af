"""Circular arcs: through a point between the ends, or around a centre.

An :class:`Arc` is given by the point it passes through (``through``) or by its centre
(``center``, the shorter of the two arcs), parametrised uniformly in angle; binding it to its
ends (:meth:`~blockmesh.curves.base.Curve.with_ends`) finds the circle and refuses an arc that
cannot reach both ends, a through point on the line of the ends, or ends opposite each other
across a given centre.

Examples
--------
>>> arc = Arc(center=(0, 0)).with_ends((1, 0), (0, 1))
>>> arc.point([0, 0.5, 1]).round(12).tolist()
[[1.0, 0.0], [0.707106781187, 0.707106781187], [0.0, 1.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from blockmesh.curves.base import (
    SHAPE_TOL,
    Curve,
    Point,
    as_point,
    cross,
    parameters,
    store,
    unset_array,
)
from blockmesh.errors import DomainError, DomainFormatError, fmt_point

__all__ = ["Arc"]


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
    _c: np.ndarray = field(default_factory=unset_array, init=False, repr=False, compare=False)
    _r: float = field(default=0.0, init=False, repr=False, compare=False)
    _theta: tuple[float, float] = field(default=(0.0, 0.0), init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if (self.through is None) == (self.center is None):
            raise DomainFormatError(
                "an arc needs exactly one of through = [x, y] or center = [x, y]"
            )
        if self.through is not None:
            store(self, through=as_point(self.through, "the arc's through point"))
        else:
            store(self, center=as_point(self.center, "the arc's center"))

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
            twice_area = float(cross(b, a))  # > 0 when start -> through -> end turns right
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
            d = 2.0 * float(cross(a, b))
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
        store(self, _c=centre, _r=radius, _theta=(theta0, sweep))

    def point(self, t: Any) -> np.ndarray:
        """Points ``c + R (cos θ, sin θ)`` at ``θ = θ0 + tΔ``; exactly the ends at 0 and 1."""
        p, q = self._ends()
        t = parameters(t)
        angle = self._theta[0] + t * self._theta[1]
        out = np.stack([np.cos(angle), np.sin(angle)], axis=-1) * self._r + self._c
        out[t == 0] = p
        out[t == 1] = q
        return out

    def derivative(self, t: Any) -> np.ndarray:
        """``RΔ (-sin θ, cos θ)``."""
        self._ends()
        angle = self._theta[0] + parameters(t) * self._theta[1]
        return np.stack([-np.sin(angle), np.cos(angle)], axis=-1) * (self._r * self._theta[1])

    def segment_area(self, t0: Any, t1: Any) -> np.ndarray:
        """``(R²/2)(φ - sin φ)`` with ``φ = Δ (t1 - t0)`` (the circular segment, signed)."""
        self._ends()
        phi = (parameters(t1) - parameters(t0)) * self._theta[1]
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
    return math.atan2(float(cross(a, b)), float(a @ b))
