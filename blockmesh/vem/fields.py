"""Coefficients, loads and boundary data: numbers, safe expressions or callables of (x, y).

Every datum of a problem (a source, a diffusion coefficient, a Dirichlet value, a flux) is given
as a number, an expression string (parsed by :func:`blockmesh.parse_expression`, never
``eval``ed) or a vectorised callable ``f(x, y)``. Vector data (a body force, a traction, a
displacement) are a pair of those, one string ``"EXPR_X, EXPR_Y"``, or a callable returning a
pair; a displacement component
may be ``None`` (or the word ``free``) to leave it unconstrained.

Examples
--------
>>> import numpy as np
>>> f = scalar_field("x + 2*y", "source")
>>> f(np.array([1.0]), np.array([1.0])).tolist()
[3.0]
>>> [c.text for c in vector_field("sin(x), atan2(y, x)", "traction")]
['sin(x)', 'atan2(y, x)']
>>> free_vector_field("free, 0", "displacement")[0] is None
True

A coefficient of a composite domain may differ from region to region: a mapping of region name to
value (``"*"`` for the regions not named) gives a :class:`RegionField`, which is evaluated cell by
cell with the region of each:

>>> kappa = region_field({"fibre": 10, "*": 1}, "diffusion", ("matrix", "fibre"))
>>> kappa.at(np.zeros((2, 1)), np.zeros((2, 1)), np.array([0, 1])).ravel().tolist()
[1.0, 10.0]
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.errors import ArgumentTypeError, ExpressionError, SolverError, UnknownNameError
from blockmesh.numerics.expr import parse_expression

__all__ = [
    "DEFAULT_REGION_KEY",
    "Field",
    "RegionField",
    "free_vector_field",
    "region_field",
    "region_values",
    "region_vector_field",
    "scalar_field",
    "split_pair",
    "vector_field",
]

FREE = "free"
#: The key of a per-region mapping that stands for every region not named.
DEFAULT_REGION_KEY = "*"


@dataclass(frozen=True)
class Field:
    """A scalar function of (x, y), evaluated on arrays, with its description for messages."""

    function: Callable[[np.ndarray, np.ndarray], Any]
    text: str
    what: str
    constant: float | None = None

    @property
    def is_zero(self) -> bool:
        """Whether the field is the constant 0."""
        return self.constant == 0.0

    def __call__(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Values at the points: float64 of ``x``'s shape, finite (SolverError naming a point)."""
        if self.constant is not None:
            return np.full(np.shape(x), self.constant)
        with np.errstate(all="ignore"):
            array = np.asarray(self.function(x, y))
        if array.ndim == 0:
            array = np.full(np.shape(x), float(array))
        elif array.shape != np.shape(x):
            raise ExpressionError(
                f"{self.what} {self.text} returned an array of shape {array.shape} for points of "
                f"shape {np.shape(x)}; it must be vectorised (elementwise on numpy arrays)"
            )
        if np.iscomplexobj(array):
            raise ExpressionError(f"{self.what} {self.text} returned complex values")
        array = array.astype(np.float64, copy=False)
        if not np.all(np.isfinite(array)):
            k = int(np.flatnonzero(~np.isfinite(array.ravel()))[0])
            px, py = float(np.ravel(x)[k]), float(np.ravel(y)[k])
            raise SolverError(
                f"{self.what} {self.text} is not finite ({array.ravel()[k]}) at (x, y) = "
                f"({px!r}, {py!r}); it must be finite on the domain"
            )
        return array

    def at(self, x: np.ndarray, y: np.ndarray, region: np.ndarray | None = None) -> np.ndarray:
        """Values at the points of some cells (rows of ``x``); the cells' regions do not matter."""
        del region
        return self(x, y)


@dataclass(frozen=True)
class RegionField:
    """A scalar datum given region by region: one :class:`Field` per region of the mesh.

    Attributes
    ----------
    pieces : tuple of Field
        The field of each region, in the order of the mesh's region names.
    names : tuple of str
        The region names.
    what : str
        What the datum is, for messages.
    """

    pieces: tuple[Field, ...]
    names: tuple[str, ...]
    what: str

    @property
    def is_zero(self) -> bool:
        """Whether the field is 0 in every region."""
        return all(piece.is_zero for piece in self.pieces)

    @property
    def constant(self) -> float | None:
        """The value when every region has the same constant, else None."""
        values = {piece.constant for piece in self.pieces}
        return values.pop() if len(values) == 1 else None

    @property
    def text(self) -> str:
        """``"matrix=1, fibre=10"``: the pieces by region."""
        return ", ".join(f"{n}={p.text}" for n, p in zip(self.names, self.pieces, strict=True))

    def at(self, x: np.ndarray, y: np.ndarray, region: np.ndarray | None = None) -> np.ndarray:
        """Values at the points ``x, y`` (C, Q) of C cells whose regions are ``region`` (C,)."""
        if region is None:
            raise SolverError(
                f"{self.what} is given per region ({self.text}); it needs the regions of the "
                "cells (a blockmesh Mesh)"
            )
        out = np.empty(np.shape(x))
        region = np.asarray(region)
        for k, piece in enumerate(self.pieces):
            rows = region == k
            if np.any(rows):
                out[rows] = piece(x[rows], y[rows])
        return out

    def __call__(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """A region field is evaluated cell by cell (:meth:`at`), never at bare points."""
        return self.at(x, y, None)


def region_field(spec: Any, what: str, region_names: tuple[str, ...]) -> Field | RegionField:
    """A field from a number, expression or callable, or from a mapping region -> one of those.

    In a mapping ``"*"`` stands for every region not named; every region needs a value.

    Raises
    ------
    UnknownNameError
        For a region the mesh does not have (the message lists its regions).
    SolverError
        For a region left without a value.

    Examples
    --------
    >>> region_field({"a": 1}, "diffusion", ("a", "b"))
    Traceback (most recent call last):
    ...
    blockmesh.errors.SolverError: diffusion is given for the region a but not for b; give every \
region a value (or "*" for the regions not named)
    """
    if not isinstance(spec, Mapping):
        return scalar_field(spec, what)
    pieces = _per_region(spec, what, region_names)
    return RegionField(
        tuple(scalar_field(value, f"{what} in region {name!r}") for name, value in pieces),
        region_names,
        what,
    )


def region_values(spec: Any, what: str, region_names: tuple[str, ...]) -> np.ndarray:
    """One number per region from a number or a mapping region -> number (``"*"``: the rest).

    Examples
    --------
    >>> region_values({"fibre": 10, "*": 1}, "Young's modulus", ("matrix", "fibre")).tolist()
    [1.0, 10.0]
    """
    pairs = (
        _per_region(spec, what, region_names)
        if isinstance(spec, Mapping)
        else [(n, spec) for n in region_names]
    )
    out = []
    for name, value in pairs:
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise ArgumentTypeError(f"{what} in region {name!r} must be a number, got {value!r}")
        out.append(float(value))
    return np.array(out)


def region_vector_field(
    spec: Any, what: str, region_names: tuple[str, ...]
) -> tuple[Field | RegionField, Field | RegionField]:
    """As :func:`vector_field`, or per region from a mapping region -> pair (``"*"``: the rest)."""
    if not isinstance(spec, Mapping):
        return vector_field(spec, what)
    pairs = [
        vector_field(value, f"{what} in region {name!r}")
        for name, value in _per_region(spec, what, region_names)
    ]
    return (
        RegionField(tuple(p[0] for p in pairs), region_names, f"{what} (x part)"),
        RegionField(tuple(p[1] for p in pairs), region_names, f"{what} (y part)"),
    )


def _per_region(
    spec: Mapping[Any, Any], what: str, region_names: tuple[str, ...]
) -> list[tuple[str, Any]]:
    """``(region, value)`` for every region, in order, from a per-region mapping."""
    unknown = [k for k in spec if k != DEFAULT_REGION_KEY and k not in region_names]
    if unknown:
        raise UnknownNameError(
            f"{what} names the region {unknown[0]!r}; the mesh's regions are "
            f"{', '.join(region_names)}"
        )
    missing = [n for n in region_names if n not in spec]
    if missing and DEFAULT_REGION_KEY not in spec:
        given = [n for n in region_names if n in spec]
        raise SolverError(
            f"{what} is given for the region{'s' if len(given) != 1 else ''} "
            f"{', '.join(given) or 'none'} but not for {', '.join(missing)}; give every region a "
            'value (or "*" for the regions not named)'
        )
    return [(n, spec[n] if n in spec else spec[DEFAULT_REGION_KEY]) for n in region_names]


def scalar_field(spec: Any, what: str) -> Field:
    """A :class:`Field` from a number, an expression string or a callable.

    ``what`` names the datum in messages (``"source"``, ``"dirichlet value on patch 'left'"``).
    """
    if isinstance(spec, Field):
        return spec
    if isinstance(spec, numbers.Real) and not isinstance(spec, bool):
        value = float(spec)
        if not np.isfinite(value):
            raise SolverError(f"{what} must be finite, got {spec!r}")
        return Field(lambda _x, _y: value, repr(spec), what, constant=value)
    if isinstance(spec, str):
        expression = parse_expression(spec)
        constant = float(expression(0.0, 0.0)) if expression.is_constant else None
        return Field(expression, spec, what, constant=constant)
    if callable(spec):
        return Field(spec, getattr(spec, "__name__", "function"), what)
    raise ArgumentTypeError(
        f"{what} must be a number, an expression string or a callable f(x, y), not "
        f"{type(spec).__name__}"
    )


def split_pair(text: str, what: str) -> tuple[str, str]:
    """``"A, B"`` split at its one top-level comma (commas inside parentheses stay)."""
    depth = 0
    cuts = []
    for k, char in enumerate(text):
        if char == "(":
            depth += 1
        elif char == ")":
            depth -= 1
        elif char == "," and depth == 0:
            cuts.append(k)
    if len(cuts) != 1:
        raise ExpressionError(
            f"{what} {text!r} must be two expressions separated by a comma, 'X_PART, Y_PART' "
            f"(found {len(cuts) + 1} parts)"
        )
    return text[: cuts[0]].strip(), text[cuts[0] + 1 :].strip()


def _parts(spec: Any, what: str) -> tuple[Any, Any]:
    if isinstance(spec, str):
        return split_pair(spec, what)
    if isinstance(spec, tuple | list) and len(spec) == 2:
        return spec[0], spec[1]
    if callable(spec):  # f(x, y) -> (f_x, f_y): one component each (f is evaluated twice)
        name = getattr(spec, "__name__", "function")
        return _component(spec, 0, name), _component(spec, 1, name)
    raise ArgumentTypeError(
        f"{what} must be a pair (x part, y part), a string 'EXPR_X, EXPR_Y' or a callable "
        f"returning a pair, got {spec!r}"
    )


def _component(function: Callable, k: int, name: str) -> Callable:
    def part(x: np.ndarray, y: np.ndarray) -> Any:
        values = function(x, y)
        if len(values) != 2:
            raise ExpressionError(f"{name}(x, y) must return a pair of arrays (x part, y part)")
        return values[k]

    part.__name__ = f"{name}[{k}]"
    return part


def vector_field(spec: Any, what: str) -> tuple[Field, Field]:
    """Two fields (x and y components) from a pair or an ``"EXPR_X, EXPR_Y"`` string."""
    x_part, y_part = _parts(spec, what)
    return scalar_field(x_part, f"{what} (x part)"), scalar_field(y_part, f"{what} (y part)")


def free_vector_field(spec: Any, what: str) -> tuple[Field | None, Field | None]:
    """As :func:`vector_field`, but a component ``None`` or ``"free"`` is left free (``None``)."""
    fields: list[Field | None] = []
    for axis, part in zip("xy", _parts(spec, what), strict=True):
        if part is None or (isinstance(part, str) and part.strip().lower() == FREE):
            fields.append(None)
        else:
            fields.append(scalar_field(part, f"{what} ({axis} part)"))
    if fields[0] is None and fields[1] is None:
        raise SolverError(f"{what}: both components are free; give at least one")
    return fields[0], fields[1]
