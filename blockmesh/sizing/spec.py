"""What a user asks for: a size spec (a number, an expression, a table, a function) and its field.

A size is given in one of these forms, in Python (``size=``) and, but the function, in a
domain file's ``[size]`` table or on the command line (``--size``):

- a number: every cell's diameter at most that;
- an expression in ``x`` and ``y``: ``"0.02 + 0.1*sqrt(x^2 + y^2)"``, the size wanted at each
  point (the safe expressions of :func:`blockmesh.parse_expression`);
- a Python function ``f(x, y)`` of arrays, or a :class:`~blockmesh.sizing.fields.SizeField`;
- a table, combined by the minimum like gmsh's Min field::

      [size]
      default = 0.1                      # a number or an expression
      expression = "0.02 + 0.05*abs(y)"  # optional, one more field
      gradation = 1.3                    # largest size ratio between neighbouring cells
      regions = { fibre = 0.01 }         # a size per region
      [[size.near]]                      # small near a patch or points, growing away
      patch = "hole"                     # or patches = [...], point = [x, y], points = [...]
      size = 0.005
      growth = 1.2                       # per cell, to the default ...
      # distance = [0.05, 0.5]           # ... or gmsh's Threshold: size within 0.05,
      # far = 0.1                        #     far (default: the default size) beyond 0.5

- a list of any of these: their minimum.

:func:`as_size_spec` checks the form and the numbers (a located message for each mistake);
:meth:`SizeSpec.field` turns it into a :class:`~blockmesh.sizing.fields.SizeField` once the
domain is known, since patches and regions are looked up by name (an unknown name is an
:class:`~blockmesh.errors.UnknownNameError` listing the names there are).

Examples
--------
>>> import numpy as np
>>> spec = as_size_spec({"default": 0.1, "near": [{"point": [0, 0], "size": 0.01, "growth": 1.5}]})
>>> spec.field()(np.array([[0.0, 0.0], [0.1, 0.0], [5.0, 0.0]])).round(3).tolist()
[0.01, 0.06, 0.1]
>>> as_size_spec("0.02 + 0.1*sqrt(x^2 + y^2)").field()(np.array([[3.0, 4.0]])).tolist()
[0.52]
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Protocol

import numpy as np

from blockmesh.checks import key_list, unknown_keys
from blockmesh.errors import ArgumentError, ArgumentTypeError, ExpressionError, UnknownNameError
from blockmesh.sizing.fields import (
    Callback,
    Constant,
    Expression,
    InRegion,
    Near,
    SizeField,
    as_field,
    checked_size,
)
from blockmesh.sizing.gradation import DEFAULT_GRADATION, checked_gradation

__all__ = ["NearSpec", "SizeGeometry", "SizeSpec", "as_size_spec"]

#: Keys of a ``[size]`` table.
SIZE_KEYS = {
    "default": "the size everywhere (a number or an expression in x, y)",
    "expression": "one more size field, an expression in x, y",
    "gradation": "the largest size ratio between neighbouring cells (> 1, default 1.3)",
    "regions": "a table: region name = size",
    "near": "[[size.near]] tables: patch|patches|point|points, size, growth or distance",
}
#: Keys of a ``[[size.near]]`` table.
NEAR_KEYS = ("patch", "patches", "point", "points", "size", "growth", "distance", "far", "within")


class SizeGeometry(Protocol):
    """What a size spec needs of a domain to resolve names: its patches and its regions."""

    @property
    def patch_names(self) -> tuple[str, ...]:
        """The boundary patches."""
        ...

    @property
    def region_names(self) -> tuple[str, ...]:
        """The regions."""
        ...

    def patch_segments(self, name: str) -> np.ndarray:
        """Straight pieces (S, 2, 2) along patch ``name`` (curved edges finely sampled)."""
        ...

    def region_polygon(self, name: str) -> Any:
        """The shapely (multi)polygon of region ``name``."""
        ...


@dataclass(frozen=True)
class NearSpec:
    """One ``[[size.near]]`` entry: small near patches or points (see :class:`.fields.Near`)."""

    patches: tuple[str, ...] = ()
    points: tuple[tuple[float, float], ...] = ()
    size: float = 1.0
    growth: float | None = None
    distance: tuple[float, float] | None = None
    far: float | None = None
    within: float = 0.0
    label: str = "size.near"


@dataclass(frozen=True)
class SizeSpec:
    """A checked size request, not yet tied to a domain (see the module notes).

    Attributes
    ----------
    default : float or str or None
        A number or an expression.
    expression : str or None
    regions : mapping of region name to size
    near : tuple of NearSpec
    fields : tuple of SizeField
        Fields given in Python (functions, field objects).
    gradation : float
    source : str
        Where the spec came from (``"size"``, ``"plate.toml [size]"``), for messages.
    table : bool
        Whether it was given as a table (messages then name its keys).
    """

    default: float | str | None = None
    expression: str | None = None
    regions: Mapping[str, float] = field(default_factory=dict)
    near: tuple[NearSpec, ...] = ()
    fields: tuple[SizeField, ...] = ()
    gradation: float = DEFAULT_GRADATION
    source: str = "size"
    table: bool = False

    @property
    def needs_domain(self) -> bool:
        """Whether the spec names patches or regions (so it needs a domain to resolve)."""
        return bool(self.regions) or any(n.patches for n in self.near)

    def field(self, geometry: SizeGeometry | None = None) -> SizeField:
        """The size field of this spec on ``geometry`` (needed when patches or regions are named).

        Raises UnknownNameError for a patch or region the domain does not have.
        """
        parts: list[SizeField] = []
        where = self.source
        named = f"{where} default" if self.table else where
        if isinstance(self.default, str):
            parts.append(Expression(self.default, label=f"{named} {self.default!r}"))
        elif self.default is not None:
            parts.append(Constant(self.default, label=named))
        if self.expression is not None:
            parts.append(
                Expression(self.expression, label=f"{where} expression {self.expression!r}")
            )
        parts.extend(self.fields)
        if (self.regions or any(n.patches for n in self.near)) and geometry is None:
            raise ArgumentError(
                f"{where} names patches or regions; it needs a domain to be resolved"
            )
        for name, size in self.regions.items():
            _known(name, geometry.region_names, "region", where)  # type: ignore[union-attr]
            polygon = geometry.region_polygon(name)  # type: ignore[union-attr]
            parts.append(InRegion(polygon, size, label=f"{where} region {name!r}"))
        far_default = self.default if isinstance(self.default, int | float) else None
        for near in self.near:
            segments = []
            for name in near.patches:
                _known(name, geometry.patch_names, "patch", where)  # type: ignore[union-attr]
                segments.append(geometry.patch_segments(name))  # type: ignore[union-attr]
            far = near.far if near.far is not None else far_default
            if near.distance is not None and far is None:
                raise ArgumentError(
                    f"{near.label} has distance = [d_min, d_max] but no far size, and the "
                    "default size is not a number: give far"
                )
            parts.append(
                Near(
                    points=np.array(near.points, dtype=np.float64).reshape(-1, 2),
                    segments=np.concatenate(segments) if segments else np.zeros((0, 2, 2)),
                    size=near.size,
                    growth=near.growth,
                    distance=near.distance,
                    far=far,
                    within=near.within,
                    label=near.label,
                )
            )
        if not parts:
            raise ArgumentError(f"{where} asks for no size: give a default size")
        return as_field(parts)

    def merged(self, other: SizeSpec) -> SizeSpec:
        """The minimum of two specs (defaults and expressions become fields of the result)."""
        fields = list(self.fields)
        default = self.default
        for spec in (other,):
            for value in (spec.default, spec.expression):
                if value is None:
                    continue
                if default is None:
                    default = value
                elif isinstance(value, str):
                    fields.append(Expression(value, label=f"{spec.source} {value!r}"))
                else:
                    fields.append(Constant(value, label=f"{spec.source}"))
            fields.extend(spec.fields)
        regions = dict(self.regions)
        for name, size in other.regions.items():
            regions[name] = min(size, regions.get(name, math.inf))
        return replace(
            self,
            default=default,
            regions=regions,
            near=self.near + other.near,
            fields=tuple(fields),
            gradation=min(self.gradation, other.gradation),
        )


def _known(name: str, names: Sequence[str], what: str, where: str) -> None:
    if name not in names:
        listed = ", ".join(repr(n) for n in names) or "none"
        plural = "patches" if what == "patch" else f"{what}s"
        raise UnknownNameError(
            f"{where} names {what} {name!r}, which the domain does not have ({plural}: {listed})"
        )


def _number_or_expression(value: object, what: str) -> float | str:
    """A size given as a number or an expression (a string holding a number is a number)."""
    if isinstance(value, str):
        try:
            return checked_size(float(value), what)
        except ValueError:
            pass
        try:
            Expression(value)._function  # noqa: B018  (parse now: a located syntax error)
        except ExpressionError as error:
            raise ExpressionError(f"{what}: {error}") from None
        return value
    return checked_size(value, what)


def _point(value: object, what: str) -> tuple[float, float]:
    if (
        isinstance(value, str | bytes)
        or not isinstance(value, Sequence)
        or len(value) != 2
        or not all(isinstance(c, numbers.Real) and not isinstance(c, bool) for c in value)
    ):
        raise ArgumentError(f"{what} must be a point [x, y], got {value!r}")
    x, y = float(value[0]), float(value[1])
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ArgumentError(f"{what} must be finite, got {value!r}")
    return x, y


def _near(table: object, what: str) -> NearSpec:
    if not isinstance(table, Mapping):
        raise ArgumentTypeError(
            f"{what} must be a table (patch or point, size, growth or distance), got {table!r}"
        )
    unknown = unknown_keys(table, NEAR_KEYS)
    if unknown:
        raise ArgumentError(f"{what} has unknown {unknown}; the keys are {', '.join(NEAR_KEYS)}")
    patches: list[str] = []
    if "patch" in table:
        patches.append(table["patch"])
    if "patches" in table:
        listed = table["patches"]
        if isinstance(listed, str) or not isinstance(listed, Sequence):
            raise ArgumentError(f"{what}: patches must be a list of patch names, got {listed!r}")
        patches.extend(listed)
    for name in patches:
        if not isinstance(name, str):
            raise ArgumentError(f"{what}: a patch is named by a string, got {name!r}")
    points: list[tuple[float, float]] = []
    if "point" in table:
        points.append(_point(table["point"], f"{what}'s point"))
    if "points" in table:
        listed = table["points"]
        if isinstance(listed, str) or not isinstance(listed, Sequence):
            raise ArgumentError(f"{what}: points must be a list of [x, y], got {listed!r}")
        points.extend(_point(p, f"{what}'s point {k}") for k, p in enumerate(listed))
    if not patches and not points:
        raise ArgumentError(f"{what} needs patch, patches, point or points: what is it near?")
    if "size" not in table:
        raise ArgumentError(f"{what} needs size (the cell size at the patch or point)")
    label = f"{what} ({', '.join(repr(p) for p in patches) or 'points'})"
    distance = table.get("distance")
    if distance is not None:
        if isinstance(distance, str) or not isinstance(distance, Sequence) or len(distance) != 2:
            raise ArgumentError(f"{what}: distance must be [d_min, d_max], got {distance!r}")
        distance = tuple(distance)
    spec = NearSpec(
        patches=tuple(patches),
        points=tuple(points),
        size=checked_size(table["size"], f"{what}'s size"),
        growth=table.get("growth"),
        distance=distance,
        far=None if table.get("far") is None else checked_size(table["far"], f"{what}'s far"),
        within=table.get("within", 0.0),
        label=label,
    )
    # Check the numbers now (a Near with a placeholder source runs every check).
    Near(
        points=[(0.0, 0.0)],
        size=spec.size,
        growth=spec.growth,
        distance=spec.distance,
        far=spec.far if spec.far is not None or spec.distance is None else spec.size,
        within=spec.within,
        label=what,
    )
    return spec


def _table(raw: Mapping[str, Any], source: str) -> SizeSpec:
    unknown = unknown_keys(raw, SIZE_KEYS)
    if unknown:
        raise ArgumentError(f"{source} has unknown {unknown}; the keys are: {key_list(SIZE_KEYS)}")
    default = raw.get("default")
    if default is not None:
        default = _number_or_expression(default, f"{source} default")
    expression = raw.get("expression")
    if expression is not None:
        if not isinstance(expression, str):
            raise ArgumentError(
                f"{source} expression must be a string in x and y, got {expression!r}"
            )
        _number_or_expression(expression, f"{source} expression")
    regions = raw.get("regions", {})
    if not isinstance(regions, Mapping):
        raise ArgumentError(f"{source} regions must be a table region = size, got {regions!r}")
    checked_regions = {
        str(name): checked_size(size, f"{source} region {name!r}") for name, size in regions.items()
    }
    near = raw.get("near", [])
    if isinstance(near, Mapping):
        near = [near]
    if isinstance(near, str) or not isinstance(near, Sequence):
        raise ArgumentError(f"{source} near must be a list of [[size.near]] tables, got {near!r}")
    nears = tuple(_near(t, f"{source} near entry {k + 1}") for k, t in enumerate(near))
    gradation = checked_gradation(raw.get("gradation", DEFAULT_GRADATION))
    if default is None and expression is None and not checked_regions and not nears:
        raise ArgumentError(f"{source} asks for no size: give default = a size")
    return SizeSpec(
        default=default,
        expression=expression,
        regions=checked_regions,
        near=nears,
        gradation=gradation,
        source=source,
        table=True,
    )


def as_size_spec(value: object, *, source: str = "size") -> SizeSpec:
    """A :class:`SizeSpec` from any of the forms of the module notes, checked.

    Parameters
    ----------
    value : number, str, callable, SizeField, mapping, SizeSpec, or a list of these
    source : str
        How messages name where the spec came from.

    Examples
    --------
    >>> as_size_spec(0.1).default
    0.1
    >>> as_size_spec(0)
    Traceback (most recent call last):
    ...
    blockmesh.errors.ArgumentError: size must be a finite number > 0, got 0
    """
    if isinstance(value, SizeSpec):
        return value
    if isinstance(value, SizeField):
        return SizeSpec(fields=(value,), source=source)
    if isinstance(value, Mapping):
        return _table(value, source)
    if isinstance(value, str | numbers.Real):
        return SizeSpec(default=_number_or_expression(value, source), source=source)
    if callable(value):
        return SizeSpec(fields=(Callback(value),), source=source)
    if isinstance(value, Sequence) and not isinstance(value, bytes) and value:
        specs = [as_size_spec(v, source=f"{source}[{k}]") for k, v in enumerate(value)]
        out = specs[0]
        for other in specs[1:]:
            out = out.merged(other)
        return replace(out, source=source)
    raise ArgumentTypeError(
        f"{source} must be a number, an expression in x and y, a function f(x, y), a size table "
        f"or a list of these; got {type(value).__name__}"
    )
