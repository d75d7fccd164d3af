"""Exact integrals of polynomials over domains and meshes with curved edges.

By Green's theorem ``∫∫ f = ∮ F dy`` with ``F = ∫ f dx``: for ``f = x^a y^b``,
``F = x^(a+1) y^b / (a+1)``. Along every boundary edge the line integral has a closed form:

- a straight edge ``P -> Q``: a polynomial in the edge's parameter;
- a polyline: its straight pieces;
- a spline: a cubic polynomial per piece, integrated exactly;
- an arc ``c + R (cos θ, sin θ)``: the binomial expansion of ``(c_x + R cos θ)^(a+1)
  (c_y + R sin θ)^b R cos θ`` and the integrals ``∫ cos^p θ sin^q θ dθ`` by their reduction
  formulas, which leave the powers of ``cos``, ``sin`` at the ends and the angle swept.

The arithmetic is exact (Python fractions). Its inputs are the numbers a curve is made of: the
ends, a spline's control points, an arc's centre, radius and the cosine and sine of its end
angles, all binary floats taken exactly; the angle an arc sweeps is irrational in general, so
with arcs the result is a float (the exact value rounded once, up to the rounding of those
inputs), and a Fraction for straight edges, polylines and splines with rational coefficients.

Examples
--------
>>> import blockmesh
>>> float(blockmesh.exact_integral(blockmesh.load_domain("disc"), "x^2 + y^2"))  # π/2
1.5707963267948966
"""

from __future__ import annotations

import math
from fractions import Fraction
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from blockmesh.curves.edges import curved_slots
from blockmesh.curves.types import Arc, Polyline, Spline
from blockmesh.errors import ArgumentError

if TYPE_CHECKING:
    from blockmesh.mesh.mesh import Mesh

__all__ = ["curved_exact_integral"]

Polynomial = dict[tuple[int, int], Fraction]


def _poly_mul(p: list[Fraction], q: list[Fraction]) -> list[Fraction]:
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        if a:
            for j, b in enumerate(q):
                out[i + j] += a * b
    return out


def _poly_power(p: list[Fraction], k: int) -> list[Fraction]:
    out = [Fraction(1)]
    for _ in range(k):
        out = _poly_mul(out, p)
    return out


def _integrated(p: list[Fraction], u0: Fraction, u1: Fraction) -> Fraction:
    """``∫_u0^u1 p(u) du`` of the polynomial with coefficients ``p`` (lowest degree first)."""
    total = Fraction(0)
    for k, c in enumerate(p):
        if c:
            total += c * (u1 ** (k + 1) - u0 ** (k + 1)) / (k + 1)
    return total


def _line_integral_polynomial(
    x: list[Fraction], y: list[Fraction], poly: Polynomial
) -> list[Fraction]:
    """The integrand of ``∮ F dy`` along ``(x(u), y(u))`` as a polynomial in ``u``."""
    dy = [k * c for k, c in enumerate(y)][1:] or [Fraction(0)]
    total: list[Fraction] = [Fraction(0)]
    for (a, b), coefficient in poly.items():
        term = _poly_mul(_poly_mul(_poly_power(x, a + 1), _poly_power(y, b)), dy)
        scale = coefficient / (a + 1)
        if len(term) > len(total):
            total += [Fraction(0)] * (len(term) - len(total))
        for k, c in enumerate(term):
            total[k] += scale * c
    return total


def _segment(p: np.ndarray, q: np.ndarray, poly: Polynomial) -> Fraction:
    """``∫ F dy`` along the straight segment from ``p`` to ``q``."""
    px, py, qx, qy = (Fraction(float(v)) for v in (p[0], p[1], q[0], q[1]))
    integrand = _line_integral_polynomial([px, qx - px], [py, qy - py], poly)
    return _integrated(integrand, Fraction(0), Fraction(1))


def _polyline(curve: Polyline, t0: float, t1: float, poly: Polynomial) -> Fraction:
    inside = [k for k in curve.breaks().tolist() if min(t0, t1) < k < max(t0, t1)]
    ts = [t0, *(inside if t0 < t1 else inside[::-1]), t1]
    points = curve.point(np.array(ts))
    return sum((_segment(points[i], points[i + 1], poly) for i in range(len(ts) - 1)), Fraction(0))


def _spline(curve: Spline, t0: float, t1: float, poly: Polynomial) -> Fraction:
    _, lo, hi = curve.pieces(np.array([t0]), np.array([t1]))
    total = Fraction(0)
    for a, b in zip(lo.tolist(), hi.tolist(), strict=True):
        piece = int(np.clip(np.searchsorted(curve._knots, (a + b) / 2) - 1, 0, None))
        integrand = _spline_piece(curve, piece, _key(poly))
        k0, k1 = curve._knots[piece], curve._knots[piece + 1]
        # The local parameter u = (t - k0) / (k1 - k0) of the piece, in exact arithmetic.
        width = Fraction(float(k1)) - Fraction(float(k0))
        u0 = (Fraction(a) - Fraction(float(k0))) / width
        u1 = (Fraction(b) - Fraction(float(k0))) / width
        total += _integrated(integrand, u0, u1)
    return total


def _key(poly: Polynomial) -> tuple[tuple[tuple[int, int], Fraction], ...]:
    return tuple(sorted(poly.items()))


@lru_cache(maxsize=64)
def _spline_piece(curve: Spline, piece: int, poly_key) -> list[Fraction]:
    """The line integrand along one cubic piece as a polynomial in its local parameter."""
    p0, p1 = curve._nodes[piece], curve._nodes[piece + 1]
    width = curve._knots[piece + 1] - curve._knots[piece]
    m0, m1 = curve._tangents[piece] * width, curve._tangents[piece + 1] * width
    # The control points as the spline evaluates them (Bernstein form), taken exactly.
    control = [p0, p0 + m0 / 3, p1 - m1 / 3, p1]
    coordinates = []
    for axis in (0, 1):
        b0, b1, b2, b3 = (Fraction(float(c[axis])) for c in control)
        coordinates.append([b0, 3 * (b1 - b0), 3 * (b0 - 2 * b1 + b2), b3 - b0 + 3 * (b1 - b2)])
    return _line_integral_polynomial(coordinates[0], coordinates[1], dict(poly_key))


def _arc(curve: Arc, t0: float, t1: float, poly: Polynomial) -> Fraction:
    """``∫ F dy`` along the arc from ``t0`` to ``t1`` (closed form, module docstring)."""
    cx, cy = (Fraction(v) for v in curve.centre_point)
    radius = Fraction(curve.radius)
    theta0, sweep = curve._theta
    start, end = theta0 + t0 * sweep, theta0 + t1 * sweep
    ends = [(Fraction(math.cos(t)), Fraction(math.sin(t))) for t in (start, end)]
    angle = Fraction(end - start)
    memo: dict[tuple[int, int], Fraction] = {}

    def bracket(p: int, q: int) -> Fraction:
        (c0, s0), (c1, s1) = ends
        return c1**p * s1**q - c0**p * s0**q

    def cos_sin(p: int, q: int) -> Fraction:
        """∫ cos^p sin^q over the arc's angles."""
        if (p, q) in memo:
            return memo[p, q]
        if p == 0 and q == 0:
            value = angle
        elif p == 1 and q == 0:
            value = bracket(0, 1)
        elif p == 0 and q == 1:
            value = -bracket(1, 0)
        elif p >= 2:
            value = bracket(p - 1, q + 1) / (p + q) + Fraction(p - 1, p + q) * cos_sin(p - 2, q)
        elif q >= 2:
            value = -bracket(p + 1, q - 1) / (p + q) + Fraction(q - 1, p + q) * cos_sin(p, q - 2)
        else:  # p == q == 1
            value = bracket(0, 2) / 2
        memo[p, q] = value
        return value

    total = Fraction(0)
    for (a, b), coefficient in poly.items():
        term = Fraction(0)
        for i in range(a + 2):
            for j in range(b + 1):
                term += (
                    math.comb(a + 1, i) * math.comb(b, j) * cx ** (a + 1 - i) * cy ** (b - j)
                    * radius ** (i + j + 1) * cos_sin(i + 1, j)
                )  # fmt: skip
        total += coefficient * term / (a + 1)
    return total


def curved_exact_integral(mesh: Mesh, poly: Polynomial) -> tuple[Fraction, bool]:
    """``∮ F dy`` over the boundary of ``mesh`` with its curved edges: the exact integral.

    ``poly`` maps ``(a, b)`` to Fraction coefficients. Returns the integral, computed from the
    curves' numbers taken exactly, and whether it is rational (no arc's angle in it).
    """
    curves = mesh.curves
    if curves is None:
        raise ArgumentError("the mesh has no curved edges")
    boundary = mesh.boundary_edges
    row, forward = curved_slots(boundary, mesh.n_points, curves)
    row, forward = row[:, 0], forward[:, 0]
    rational = True
    total = Fraction(0)
    for k, (a, b) in enumerate(boundary.tolist()):
        r = int(row[k])
        if r < 0:
            total += _segment(mesh.points[a], mesh.points[b], poly)
            continue
        curve = curves.curves[int(curves.curve[r])]
        t0, t1 = float(curves.start[r]), float(curves.stop[r])
        if not forward[k]:
            t0, t1 = t1, t0
        if isinstance(curve, Arc):
            total += _arc(curve, t0, t1, poly)
            rational = False
        elif isinstance(curve, Spline):
            total += _spline(curve, t0, t1, poly)
        else:
            total += _polyline(curve, t0, t1, poly)  # type: ignore[arg-type]
    return total, rational
