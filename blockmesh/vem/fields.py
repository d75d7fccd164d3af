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
"""

from __future__ import annotations

import numbers
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.errors import ArgumentTypeError, ExpressionError, SolverError
from blockmesh.numerics.expr import parse_expression

__all__ = ["Field", "free_vector_field", "scalar_field", "split_pair", "vector_field"]

FREE = "free"


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
