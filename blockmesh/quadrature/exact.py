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
from collections.abc import Iterable
from decimal import Decimal
from fractions import Fraction
from functools import lru_cache

import numpy as np

from blockmesh.checks import whole_number
from blockmesh.domain.domain import Domain
from blockmesh.errors import (
    ArgumentError,
    ArgumentTypeError,
    DomainError,
    ExpressionError,
    ResourceError,
)
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.numerics.expr import as_polynomial
from blockmesh.quadrature.exact_curved import curved_exact_integral

__all__ = ["MAX_EXACT_WORK", "as_polynomial", "exact_integral"]

#: Default most big-integer steps (boundary edges x Σ (a+1)(b+1) over the monomials) one exact
#: integral may take: a few seconds.
MAX_EXACT_WORK = 20_000_000


def exact_integral(
    target: object, polynomial: object, *, max_work: int = MAX_EXACT_WORK
) -> Fraction | float:
    """The exact integral of a polynomial over a polygon, a domain or a mesh.

    Parameters
    ----------
    target : Domain, Mesh, PolygonMesh or array_like (K, 2)
        A Domain or a mesh is integrated over through its boundary edges (holes and several
        blocks included), along its curves where it has curved edges
        (:mod:`blockmesh.quadrature.exact_curved`: closed forms; a float result when there are
        arcs); a sequence of corners is one simple polygon (either orientation). Corners may be
        ints, floats (converted exactly), Fractions, Decimals or decimal strings.
    polynomial : str, Expression or mapping
        See :func:`~blockmesh.numerics.expr.as_polynomial`.
    max_work : int
        Refuse (before any work) a request needing more big-integer steps than this.

    Returns
    -------
    Fraction or float
        A Fraction when every coefficient is rational, else a float.

    Raises
    ------
    ExpressionError
        When the expression is not a polynomial (with the offending part marked), or a float
        result overflows.
    ArgumentTypeError, DomainError
        For a target that is not a Domain, Mesh or list of corners, or bad corners.
    ResourceError
        When the work passes ``max_work``.

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
    budget = whole_number(max_work, "max_work", minimum=1)
    poly = as_polynomial(polynomial)
    curved = _with_curves(target)
    if (
        curved is not None
    ):  # curved edges: closed forms along the curves (blockmesh.quadrature.exact_curved)
        return _curved(curved, poly, budget)
    edges = _boundary_edges(target)
    work = len(edges) * sum((a + 1) * (b + 1) for a, b in poly)
    if work > budget:
        raise ResourceError(
            f"the exact integral takes about {work:,} big-integer steps ({len(edges):,} boundary "
            f"edges, {len(poly):,} monomials up to degree {max(a + b for a, b in poly)}), above "
            f"max_work={budget:,}; integrate numerically instead, or raise max_work"
        )
    exact = all(isinstance(c, Fraction) for c in poly.values())
    coefficients = {key: Fraction(c) for key, c in poly.items()}
    total = Fraction(0)
    for start, end in edges:
        total += _edge_integral(start, end, coefficients)
    if exact:
        return total
    try:
        return float(total)
    except OverflowError:
        raise ExpressionError(
            "the exact integral is beyond the float64 range (about 1.8e308); with a float "
            "coefficient (pi, e, sqrt(...)) the result is a float"
        ) from None


def _with_curves(target: object) -> Mesh | None:
    """The mesh to integrate over when ``target`` is a Domain or Mesh with curved edges."""
    mesh = target.block_mesh() if isinstance(target, Domain) else target
    if isinstance(mesh, PolygonMesh) and mesh.curves is not None and len(mesh.curves):
        raise ArgumentError(
            "the exact integral over a polygon mesh with curved edges is not available; "
            "integrate over its Domain, or its straight cells with blockmesh.integrate"
        )
    if isinstance(mesh, Mesh) and mesh.curves is not None and len(mesh.curves):
        return mesh
    return None


def _curved(mesh: Mesh, poly, budget: int) -> Fraction | float:
    edges = mesh.boundary_edges.shape[0]
    work = edges * sum((a + 2) * (b + 1) for a, b in poly) * 4
    if work > budget:
        raise ResourceError(
            f"the exact integral takes about {work:,} big-integer steps ({edges:,} boundary "
            f"edges with curves, {len(poly):,} monomials), above max_work={budget:,}; integrate "
            "numerically instead (exact_geometry=True), or raise max_work"
        )
    total, rational = curved_exact_integral(mesh, {k: Fraction(c) for k, c in poly.items()})
    if rational and all(isinstance(c, Fraction) for c in poly.values()):
        return total
    try:
        return float(total)
    except OverflowError:
        raise ExpressionError("the exact integral is beyond the float64 range") from None


# --------------------------------------------------------------------------- boundary edges
def _fraction(value: object) -> Fraction:
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


def _boundary_edges(
    target: object,
) -> list[tuple[tuple[Fraction, Fraction], tuple[Fraction, Fraction]]]:
    if isinstance(target, Domain):
        target = target.block_mesh()
    if isinstance(target, Mesh | PolygonMesh):
        if target.boundary_edges.shape[0] == 0:
            raise ArgumentError("the mesh has no boundary edges to integrate over")
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
        raise ArgumentTypeError(
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
