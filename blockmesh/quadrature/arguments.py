"""Argument checks shared by the integration entry points."""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.errors import ArgumentError, ArgumentTypeError
from blockmesh.numerics.expr import parse_expression

__all__ = ["Integrand", "check_chunk", "check_integrand", "check_max_points", "check_nonnegative"]

#: An integrand: a vectorised ``f(x, y)`` or an expression string.
Integrand = str | Callable[[np.ndarray, np.ndarray], np.ndarray]


def check_integrand(f: object) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """``f`` as a callable: expression strings are parsed (and vetted) here."""
    if isinstance(f, str):
        return parse_expression(f)
    if not callable(f):
        raise ArgumentTypeError(
            f"f must be a callable f(x, y) or an expression string, not {type(f).__name__}"
        )
    return f


def check_nonnegative(value: object, name: str) -> float:
    """A finite real number >= 0."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ArgumentTypeError(f"{name} must be a finite number >= 0, got {value!r}")
    number = float(value)
    if not (math.isfinite(number) and number >= 0):
        raise ArgumentError(f"{name} must be a finite number >= 0, got {value!r}")
    return number


def check_chunk(chunk: object) -> int:
    """Points per chunk, a whole number >= 1."""
    return whole_number(chunk, "chunk", minimum=1)


def check_max_points(max_points: object) -> int:
    """The budget of evaluations, a whole number >= 1."""
    return whole_number(max_points, "max_points", minimum=1)
