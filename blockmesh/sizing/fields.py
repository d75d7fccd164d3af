"""Size fields: the cell size wanted at every point, ``h(x, y)``, combined by their minimum.

A size field answers one question, "how large may a cell be here?", for many points at once:
``field(xy)`` takes an ``(N, 2)`` array of points and returns ``N`` sizes, a size being a cell's
diameter (the largest distance between two of its corners). The kinds follow gmsh's fields:

==================== =========================================================================
:class:`Constant`    one size everywhere (gmsh's characteristic length)
:class:`Expression`  a safe expression in ``x`` and ``y`` (gmsh's MathEval)
:class:`Callback`    a Python function ``f(x, y) -> sizes`` on arrays (gmsh's callback)
:class:`Near`        small near points or boundary pieces, growing with the distance from them:
                     by a rate per cell, or between two distances (gmsh's Distance + Threshold)
:class:`InRegion`    a size inside some polygons, none outside (gmsh's Restrict / per-surface)
:class:`Minimum`     the smallest of several fields (gmsh's Min)
:class:`Graded`      a field whose growth is limited, so neighbouring cells' sizes stay within a
                     ratio even where the field jumps (see :mod:`blockmesh.sizing.gradation`)
==================== =========================================================================

A field may answer ``inf`` where it asks nothing (outside its region, say); the field a mesh is
made for must be finite and positive everywhere in the domain, and :func:`checked_sizes` says
where it is not, with the point and the field's own name.

Examples
--------
>>> import numpy as np
>>> hole = Near(points=[(0.0, 0.0)], size=0.01, growth=1.2)
>>> field = Minimum((Constant(0.1), hole))
>>> field(np.array([[0.0, 0.0], [0.1, 0.0], [3.0, 0.0]])).round(4).tolist()
[0.01, 0.03, 0.1]
"""

from __future__ import annotations

import math
import numbers
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from blockmesh.errors import (
    ArgumentError,
    ArgumentTypeError,
    BlockMeshError,
    ExpressionError,
    fmt_point,
)
from blockmesh.numerics.expr import parse_expression

#: The names :mod:`blockmesh.sizing` gives from this module: the size fields and the constant.
FIELD_NAMES = (
    "PENTAGON_AREA",
    "Callback",
    "Constant",
    "Expression",
    "InRegion",
    "Minimum",
    "Near",
    "SizeField",
)

__all__ = [*FIELD_NAMES, "as_field", "checked_size", "checked_sizes"]

#: Area of a regular pentagon of diameter 1 (its diagonal): a mesh of cells of diameter at most
#: h covers at most this times h^2 per cell, so it has at least ``area / (PENTAGON_AREA h^2)``.
PENTAGON_AREA = 0.6572


def _points(xy: Any) -> np.ndarray:
    points = np.asarray(xy, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 2:
        raise ArgumentError(f"a size field takes points of shape (N, 2), got {points.shape}")
    return points


def checked_size(value: object, what: str) -> float:
    """A size given as a number: finite and > 0, else ArgumentError naming ``what``.

    Examples
    --------
    >>> checked_size(0.5, "size")
    0.5
    >>> checked_size(-1, "the default size")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentError: the default size must be a finite number > 0, got -1
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(
            f"{what} must be a number (a cell diameter), got {type(value).__name__} {value!r}"
        )
    number = float(value)
    if not (math.isfinite(number) and number > 0):
        raise ArgumentError(f"{what} must be a finite number > 0, got {value!r}")
    return number


class SizeField(ABC):
    """The cell size wanted at each point (see the module notes)."""

    #: How messages name the field ("the size expression '...'", "[size] near 'hole'").
    label: str

    @abstractmethod
    def values(self, xy: np.ndarray) -> np.ndarray:
        """Sizes at the points ``xy`` (N, 2), unchecked: ``inf`` where the field asks nothing."""

    def __call__(self, xy: Any) -> np.ndarray:
        """Sizes at the points ``xy`` (N, 2), each field checked (NaN, zero and less refused)."""
        return checked_sizes(self, _points(xy), final=False)

    def seeds(self) -> np.ndarray:
        """Points (S, 2) where the field is locally smallest (where sampling must look)."""
        return np.zeros((0, 2))

    def parts(self) -> tuple[SizeField, ...]:
        """The fields this one combines (itself for a simple field)."""
        return (self,)

    @property
    def smallest(self) -> float:
        """A lower bound of the field's values (0 when not known)."""
        return 0.0

    def _check(self, xy: np.ndarray, sizes: np.ndarray) -> None:
        """Raise where this field's own values are not sizes (NaN, <= 0, -inf)."""
        bad = ~(sizes > 0)  # NaN too
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ArgumentError(
                f"{self.label} gives {sizes[k]!r} at {fmt_point(xy[k])}; a size must be > 0"
            )


def checked_sizes(field: SizeField, xy: np.ndarray, *, final: bool = True) -> np.ndarray:
    """``field`` at ``xy`` with every part checked; ``final`` also refuses ``inf``.

    The error names the part that fails and the first point where it does, so that a user who
    combined several fields knows which to change.

    Examples
    --------
    >>> checked_sizes(Expression("1 - x"), np.array([[0.5, 0.0], [2.0, 1.0]]))
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExpressionError: the size expression '1 - x' gives -1.0 at (2, 1); a size \
must be a finite number > 0 everywhere in the domain
    """
    xy = _points(xy)
    for part in field.parts():
        if part is not field:
            part._check(xy, part.values(xy))
    with np.errstate(all="ignore"):
        sizes = np.asarray(field.values(xy), dtype=np.float64)
    field._check(xy, sizes)
    if final:
        unasked = ~np.isfinite(sizes)
        if unasked.any():
            k = int(np.flatnonzero(unasked)[0])
            raise ArgumentError(
                f"the size field asks no size at {fmt_point(xy[k])} (it is outside every region "
                "and beyond every near-field there); give a default size"
            )
    return sizes


def _check_finite_sizes(
    label: str, xy: np.ndarray, sizes: np.ndarray, error: type[BlockMeshError]
) -> None:
    """Raise ``error`` at the first point where a user's function gives no finite size > 0."""
    bad = ~(np.isfinite(sizes) & (sizes > 0))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise error(
            f"{label} gives {float(sizes[k])!r} at {fmt_point(xy[k])}; a size must be a "
            "finite number > 0 everywhere in the domain"
        )


# ---------------------------------------------------------------------------- kinds
class OneSize(SizeField):
    """A field that asks one size wherever it asks any (:class:`Constant`, :class:`InRegion`)."""

    #: The size asked.
    size: float

    @property
    def smallest(self) -> float:
        """The size."""
        return self.size


@dataclass(frozen=True)
class Constant(OneSize):
    """One size everywhere.

    Examples
    --------
    >>> Constant(0.5)(np.zeros((2, 2))).tolist()
    [0.5, 0.5]
    """

    size: float
    label: str = "the size"

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", checked_size(self.size, self.label))

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The size at every point."""
        return np.full(len(xy), self.size)


@dataclass(frozen=True, eq=False)
class Expression(SizeField):
    """A safe expression in ``x`` and ``y`` (:func:`blockmesh.parse_expression`).

    Examples
    --------
    >>> Expression("0.02 + 0.1*sqrt(x^2 + y^2)")(np.array([[3.0, 4.0]])).tolist()
    [0.52]
    """

    text: str
    label: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.text, str):
            raise ArgumentTypeError(
                f"a size expression is a string, got {type(self.text).__name__}"
            )
        if not self.label:
            object.__setattr__(self, "label", f"the size expression {self.text!r}")

    @cached_property
    def _function(self):
        return parse_expression(self.text)

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The expression at the points (NaN and inf are left for :meth:`_check`)."""
        with np.errstate(all="ignore"):
            return np.asarray(self._function(xy[:, 0], xy[:, 1]), dtype=np.float64)

    def _check(self, xy: np.ndarray, sizes: np.ndarray) -> None:
        _check_finite_sizes(self.label, xy, sizes, ExpressionError)


@dataclass(frozen=True, eq=False)
class Callback(SizeField):
    """A Python function ``f(x, y)`` of arrays returning the sizes (or one number).

    Examples
    --------
    >>> Callback(lambda x, y: 0.1 + 0 * x)(np.zeros((3, 2))).tolist()
    [0.1, 0.1, 0.1]
    """

    function: Callable[[np.ndarray, np.ndarray], Any]
    label: str = ""

    def __post_init__(self) -> None:
        if not callable(self.function):
            raise ArgumentTypeError(
                f"a size callback must be callable, got {type(self.function).__name__}"
            )
        if not self.label:
            name = getattr(self.function, "__name__", type(self.function).__name__)
            object.__setattr__(self, "label", f"the size function {name}")

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The function's answer, broadcast to one size per point."""
        try:
            out = np.asarray(self.function(xy[:, 0].copy(), xy[:, 1].copy()), dtype=np.float64)
            return np.array(np.broadcast_to(out, (len(xy),)))
        except (TypeError, ValueError) as error:
            raise ArgumentError(
                f"{self.label} must take two arrays x, y of {len(xy)} coordinates and return "
                f"{len(xy)} sizes (or one number): {error}"
            ) from None

    def _check(self, xy: np.ndarray, sizes: np.ndarray) -> None:
        _check_finite_sizes(self.label, xy, sizes, ArgumentError)


@dataclass(frozen=True, eq=False)
class Near(SizeField):
    """Small near points and segments, growing with the distance ``d`` from them.

    With ``growth`` (gmsh users: a rate per cell): ``size + (growth - 1) * max(d - within, 0)``,
    which makes each cell about ``growth`` times its neighbour towards the source. With
    ``distance = (d_min, d_max)`` (gmsh's Threshold): ``size`` up to ``d_min``, ``far`` from
    ``d_max`` on, linear in between. Beyond the reach the field asks nothing (``inf``) unless
    ``far`` is given; combine it with a default by :class:`Minimum`.

    Parameters
    ----------
    points : sequence of (x, y), optional
    segments : sequence of ((x0, y0), (x1, y1)), optional
        Straight pieces (a patch's edges; curved patches are given by their sampled pieces).
    size : float
        The size at the source.
    growth : float, optional
        Size ratio per cell (> 1), e.g. 1.2.
    distance : (float, float), optional
        ``(d_min, d_max)`` with ``0 <= d_min < d_max``.
    far : float, optional
        The size at ``d_max`` and beyond (needed with ``distance``; with ``growth``, a cap).
    within : float
        With ``growth``: the distance up to which the size stays ``size`` (default 0).

    Examples
    --------
    >>> wall = Near(segments=[((0, 0), (1, 0))], size=0.01, distance=(0.1, 0.5), far=0.1)
    >>> wall(np.array([[0.5, 0.05], [0.5, 0.3], [0.5, 2.0]])).round(4).tolist()
    [0.01, 0.055, 0.1]
    """

    points: Any = ()
    segments: Any = ()
    size: float = 1.0
    growth: float | None = None
    distance: tuple[float, float] | None = None
    far: float | None = None
    within: float = 0.0
    label: str = "the near-field"
    _points_array: np.ndarray = field(init=False, repr=False)
    _segments_array: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        points = np.asarray(self.points, dtype=np.float64).reshape(-1, 2)
        segments = np.asarray(self.segments, dtype=np.float64).reshape(-1, 2, 2)
        if not len(points) and not len(segments):
            raise ArgumentError(f"{self.label} has no points or segments to be near")
        if not (np.all(np.isfinite(points)) and np.all(np.isfinite(segments))):
            raise ArgumentError(f"{self.label} has a point that is not finite")
        object.__setattr__(self, "_points_array", points)
        object.__setattr__(self, "_segments_array", segments)
        object.__setattr__(self, "size", checked_size(self.size, f"{self.label}'s size"))
        if (self.growth is None) == (self.distance is None):
            raise ArgumentError(
                f"{self.label} needs either growth (a size ratio per cell, e.g. 1.2) or distance "
                "= [d_min, d_max] (the size grows from size at d_min to far at d_max)"
            )
        if self.far is not None:
            object.__setattr__(self, "far", checked_size(self.far, f"{self.label}'s far size"))
        if self.growth is not None:
            growth = checked_size(self.growth, f"{self.label}'s growth")
            if growth <= 1.0:
                raise ArgumentError(
                    f"{self.label}'s growth must be > 1 (a size ratio per cell), got "
                    f"{self.growth!r}"
                )
            object.__setattr__(self, "growth", growth)
            within = float(self.within)
            if not (math.isfinite(within) and within >= 0):
                raise ArgumentError(f"{self.label}'s within must be a distance >= 0")
        else:
            pair = tuple(self.distance)  # type: ignore[arg-type]
            if len(pair) != 2 or not all(
                isinstance(d, numbers.Real) and not isinstance(d, bool) for d in pair
            ):
                raise ArgumentError(
                    f"{self.label}'s distance must be [d_min, d_max], got {self.distance!r}"
                )
            low, high = float(pair[0]), float(pair[1])
            if not (math.isfinite(high) and 0 <= low < high):
                raise ArgumentError(
                    f"{self.label}'s distance must be [d_min, d_max] with 0 <= d_min < d_max, "
                    f"got {list(pair)}"
                )
            if self.far is None:
                raise ArgumentError(
                    f"{self.label} with distance = [d_min, d_max] needs the size far from it "
                    "(far, or a default size)"
                )
            object.__setattr__(self, "distance", (low, high))

    @cached_property
    def _tree(self):
        import shapely

        geoms = list(shapely.points(self._points_array)) + list(
            shapely.linestrings(self._segments_array)
        )
        return shapely.STRtree(geoms)

    def distances(self, xy: np.ndarray) -> np.ndarray:
        """Distance from each point to the nearest source point or segment."""
        import shapely

        if not len(xy):
            return np.zeros(0)
        index, dist = self._tree.query_nearest(
            shapely.points(xy), return_distance=True, all_matches=False
        )
        out = np.full(len(xy), np.inf)
        np.minimum.at(out, index[0], dist)
        return out

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The size at the points' distances."""
        d = self.distances(xy)
        if self.growth is not None:
            h = self.size + (self.growth - 1.0) * np.maximum(d - self.within, 0.0)
            return h if self.far is None else np.minimum(h, self.far)
        low, high = self.distance  # type: ignore[misc]
        far = float(self.far)  # type: ignore[arg-type]
        t = np.clip((d - low) / (high - low), 0.0, 1.0)
        return self.size + t * (far - self.size)

    def seeds(self) -> np.ndarray:
        """The source points and the segments' ends and midpoints."""
        s = self._segments_array
        return np.vstack([self._points_array, s[:, 0], s[:, 1], s.mean(axis=1)])

    @property
    def smallest(self) -> float:
        """The size at the source (or ``far``, if smaller)."""
        return min(self.size, self.far) if self.far is not None else self.size


@dataclass(frozen=True, eq=False)
class InRegion(OneSize):
    """A size inside a shapely (multi)polygon, nothing (``inf``) outside.

    Examples
    --------
    >>> import shapely
    >>> inside = InRegion(shapely.box(0, 0, 1, 1), 0.05, label="region 'core'")
    >>> inside(np.array([[0.5, 0.5], [2.0, 0.5]])).tolist()
    [0.05, inf]
    """

    polygon: Any
    size: float
    label: str = "the region size"

    def __post_init__(self) -> None:
        import shapely

        object.__setattr__(self, "size", checked_size(self.size, f"{self.label}'s size"))
        shapely.prepare(self.polygon)

    def values(self, xy: np.ndarray) -> np.ndarray:
        """``size`` where the point is inside (or on the boundary of) the polygon."""
        import shapely

        inside = shapely.intersects_xy(self.polygon, xy[:, 0], xy[:, 1])
        return np.where(inside, self.size, np.inf)

    def seeds(self) -> np.ndarray:
        """A point inside each part of the polygon and the corners of its boundary."""
        import shapely

        corners = shapely.get_coordinates(shapely.boundary(self.polygon))
        parts = shapely.get_parts(self.polygon)
        inner = shapely.get_coordinates(shapely.point_on_surface(parts))
        return np.vstack([inner, corners])


@dataclass(frozen=True, eq=False)
class Minimum(SizeField):
    """The smallest of several fields at every point (gmsh's Min field).

    Examples
    --------
    >>> m = Minimum((Constant(1.0), Expression("0.5 + x")))
    >>> m(np.array([[0.0, 0.0], [1.0, 0.0]])).tolist()
    [0.5, 1.0]
    """

    fields: tuple[SizeField, ...]
    label: str = "the size field"

    def __post_init__(self) -> None:
        fields = tuple(self.fields)
        if not fields:
            raise ArgumentError("a minimum of size fields needs at least one field")
        flat: list[SizeField] = []
        for f in fields:
            if not isinstance(f, SizeField):
                raise ArgumentTypeError(f"Minimum takes size fields, got {type(f).__name__}")
            flat.extend(f.fields if isinstance(f, Minimum) else (f,))
        object.__setattr__(self, "fields", tuple(flat))

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The pointwise minimum (NaN propagates, so a bad part is seen)."""
        out = np.full(len(xy), np.inf)
        for f in self.fields:
            out = np.minimum(out, f.values(xy))
        return out

    def parts(self) -> tuple[SizeField, ...]:
        """The combined fields (each checked on its own)."""
        return self.fields

    def seeds(self) -> np.ndarray:
        """Every part's seeds."""
        return np.vstack([f.seeds() for f in self.fields])

    @property
    def smallest(self) -> float:
        """The smallest of the parts' bounds."""
        return min(f.smallest for f in self.fields)

    def _check(self, xy: np.ndarray, sizes: np.ndarray) -> None:  # noqa: ARG002
        return  # the parts are checked one by one


def as_field(items: Iterable[SizeField] | Sequence[SizeField]) -> SizeField:
    """One field from several: the field itself, or their :class:`Minimum`.

    Examples
    --------
    >>> as_field([Constant(1.0)])
    Constant(size=1.0, label='the size')
    """
    items = list(items)
    return items[0] if len(items) == 1 else Minimum(tuple(items))
