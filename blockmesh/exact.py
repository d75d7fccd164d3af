"""Exact integrals of polynomials over polygons, domains and meshes.

By Green's theorem the integral over a region is a sum over its oriented boundary edges ``P -> Q``
of the integral over the triangle ``(0, P, Q)`` (the paper's Theorem 1), and for a monomial that
triangle integral has a closed form (``x1, y1 = P``, ``x2, y2 = Q``)::

    ∫∫ x^a y^b = (x1 y2 - x2 y1) a! b! / (a+b+2)!
                 * Σ_{k<=a} Σ_{l<=b} C(k+l, l) C(a+b-k-l, b-l) x1^k x2^(a-k) y1^l y2^(b-l)

Everything is computed in exact rational arithmetic (Python integers over a common denominator per
edge). **Float coordinates are converted exactly** with ``Fraction(float)``: the result is the exact
integral over the polygon whose corners are the binary values stored, not over "0.1" as typed.
The result is a :class:`fractions.Fraction` when every coefficient is rational, and a float (the
exact value rounded once) when a coefficient is a float, e.g. from ``pi``.

Examples
--------
>>> from fractions import Fraction
>>> square = [(0, 0), (1, 0), (1, 1), (0, 1)]
>>> exact_integral(square, "x*y + 1/3")
Fraction(7, 12)
>>> exact_integral([(-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)], "(0.2*x + 0.3*y)^19")
Fraction(-389834752439, 7000000000000000000)
>>> exact_integral(square, "sin(x)")
Traceback (most recent call last):
    ...
blockmesh.errors.ExpressionError: not a polynomial: sin(...) of x or y at column 1
  sin(x)
  ^^^^^^
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from decimal import Decimal
from fractions import Fraction
from functools import lru_cache

import numpy as np

from .errors import BlockMeshError, DomainError, ExpressionError
from .expr import Expression, Polynomial, parse_expression
from .mesh import Mesh

__all__ = ["as_polynomial", "exact_integral"]


def as_polynomial(polynomial: str | Expression | Mapping[tuple[int, int], object]) -> Polynomial:
    """A polynomial ``{(a, b): coefficient}`` from an expression string, Expression or mapping.

    Mapping coefficients may be ints, Fractions, Decimals or floats (kept as given).

    Examples
    --------
    >>> as_polynomial("x^2 - 0.5*y")
    {(0, 1): Fraction(-1, 2), (2, 0): Fraction(1, 1)}
    >>> as_polynomial({(1, 2): 3})
    {(1, 2): Fraction(3, 1)}
    """
    if isinstance(polynomial, str):
        return parse_expression(polynomial).polynomial()
    if isinstance(polynomial, Expression):
        return polynomial.polynomial()
    if not isinstance(polynomial, Mapping):
        raise ExpressionError(
            "a polynomial must be an expression string or a mapping {(a, b): coefficient}, "
            f"not {type(polynomial).__name__}"
        )
    out: Polynomial = {}
    for key, coefficient in polynomial.items():
        if (
            not isinstance(key, tuple)
            or len(key) != 2
            or not all(
                isinstance(k, int | np.integer) and not isinstance(k, bool) and k >= 0 for k in key
            )
        ):
            raise ExpressionError(
                f"polynomial key {key!r} must be a pair (a, b) of whole numbers >= 0"
            )
        if isinstance(coefficient, float | np.floating):
            value: Fraction | float = float(coefficient)
            if not math.isfinite(value):
                raise ExpressionError(
                    f"coefficient of x^{key[0]} y^{key[1]} is not finite: {value}"
                )
        elif isinstance(coefficient, int | np.integer | Fraction | Decimal) and not isinstance(
            coefficient, bool
        ):
            value = Fraction(coefficient)
        else:
            raise ExpressionError(
                f"coefficient of x^{key[0]} y^{key[1]} must be a number, not {coefficient!r}"
            )
        if value != 0:
            out[(int(key[0]), int(key[1]))] = value
    return out


def exact_integral(target, polynomial) -> Fraction | float:
    """The exact integral of a polynomial over a polygon, a domain or a mesh.

    Parameters
    ----------
    target : Domain, Mesh or array_like (K, 2)
        A Domain or Mesh is integrated over through its boundary edges (holes and several
        blocks included); a sequence of corners is one simple polygon (either orientation).
        Corners may be ints, floats (converted exactly), Fractions, Decimals or decimal strings.
    polynomial : str, Expression or mapping
        See :func:`as_polynomial`.

    Returns
    -------
    Fraction or float
        A Fraction when every coefficient is rational, else a float.

    Raises
    ------
    ExpressionError
        When the expression is not a polynomial (with the offending part marked).

    Notes
    -----
    Cost: O(E · Σ (a+1)(b+1)) integer operations over the E boundary edges and the monomials.

    Examples
    --------
    >>> exact_integral([(0, 0), (2, 0), (3, 1), (1, 3), (0, 2)], "1")
    Fraction(6, 1)
    >>> exact_integral([(0, 0), (1, 0), (0, 1)], {(0, 0): 0.5})  # float coefficient: float result
    0.25
    """
    poly = as_polynomial(polynomial)
    edges = _boundary_edges(target)
    exact = all(isinstance(c, Fraction) for c in poly.values())
    coefficients = {key: Fraction(c) for key, c in poly.items()}
    total = Fraction(0)
    for start, end in edges:
        total += _edge_integral(start, end, coefficients)
    return total if exact else float(total)


# --------------------------------------------------------------------------- boundary edges
def _fraction(value) -> Fraction:
    if isinstance(value, bool):
        raise DomainError(f"coordinate {value!r} is not a number")
    if isinstance(value, float | np.floating):
        if not math.isfinite(value):
            raise DomainError(f"coordinate {value!r} is not finite")
        return Fraction(float(value))
    if isinstance(value, int | np.integer):
        return Fraction(int(value))
    if isinstance(value, Fraction | Decimal | str):
        try:
            return Fraction(value)
        except (ValueError, ArithmeticError):
            raise DomainError(f"coordinate {value!r} is not a finite number") from None
    raise DomainError(f"coordinate {value!r} is not a number")


def _boundary_edges(target) -> list[tuple[tuple[Fraction, Fraction], tuple[Fraction, Fraction]]]:
    if not isinstance(target, Mesh) and hasattr(target, "block_mesh"):
        target = target.block_mesh()
    if isinstance(target, Mesh):
        if target.boundary_edges.shape[0] == 0:
            raise BlockMeshError("the mesh has no boundary edges to integrate over")
        used = np.unique(target.boundary_edges)
        corner = {
            int(i): (Fraction(float(x)), Fraction(float(y)))
            for i, (x, y) in zip(used, target.points[used], strict=True)
        }
        return [(corner[int(a)], corner[int(b)]) for a, b in target.boundary_edges]
    if isinstance(target, np.ndarray) and target.dtype != object:
        rows: Iterable = target.tolist()
    elif isinstance(target, Iterable) and not isinstance(target, str | bytes):
        rows = list(target)
    else:
        raise BlockMeshError(
            "exact_integral() takes a Domain, a Mesh or a list of (x, y) corners, "
            f"not {type(target).__name__}"
        )
    corners = []
    for k, row in enumerate(rows):
        try:
            x, y = row
        except (TypeError, ValueError):
            raise DomainError(f"corner {k} is {row!r}; each corner must be a pair (x, y)") from None
        corners.append((_fraction(x), _fraction(y)))
    if len(corners) < 3:
        raise DomainError(f"a polygon needs at least 3 corners, got {len(corners)}")
    twice_area = sum(
        (p[0] * q[1] - q[0] * p[1]) for p, q in zip(corners, corners[1:] + corners[:1], strict=True)
    )
    if twice_area < 0:
        corners.reverse()
    return list(zip(corners, corners[1:] + corners[:1], strict=True))


# --------------------------------------------------------------------------- one edge
@lru_cache(maxsize=512)
def _binomials(n: int) -> tuple[tuple[int, ...], ...]:
    return tuple(tuple(math.comb(i, j) for j in range(i + 1)) for i in range(n + 1))


def _edge_integral(start, end, poly: dict[tuple[int, int], Fraction]) -> Fraction:
    """∫∫ over the triangle (0, start, end), signed, of the polynomial."""
    (x1, y1), (x2, y2) = start, end
    denominator = math.lcm(x1.denominator, y1.denominator, x2.denominator, y2.denominator)
    X1, Y1 = int(x1 * denominator), int(y1 * denominator)
    X2, Y2 = int(x2 * denominator), int(y2 * denominator)
    cross = X1 * Y2 - X2 * Y1
    if cross == 0 or not poly:
        return Fraction(0)
    top = max(a + b for a, b in poly)
    binom = _binomials(top)
    px1, px2, py1, py2 = ([v**k for k in range(top + 1)] for v in (X1, X2, Y1, Y2))
    by_degree: dict[int, Fraction] = {}
    for (a, b), coefficient in poly.items():
        m = a + b
        s = 0
        for k in range(a + 1):
            inner = 0
            for l in range(b + 1):
                inner += binom[k + l][l] * binom[m - k - l][b - l] * py1[l] * py2[b - l]
            s += px1[k] * px2[a - k] * inner
        scale = Fraction(math.factorial(a) * math.factorial(b), math.factorial(m + 2))
        by_degree[m] = by_degree.get(m, Fraction(0)) + coefficient * scale * s
    total = sum((value / denominator**m for m, value in by_degree.items()), start=Fraction(0))
    return total * Fraction(cross, denominator * denominator)
