"""Exact values on the curved catalogue domains, for the curved tests (import from here)."""

from __future__ import annotations

import math
from fractions import Fraction

from blockmesh.quadrature.exact import exact_integral


def disc_moment(a: int, b: int, radius: float, absolute: bool = False) -> float:
    """∫∫ x^a y^b (or |x^a y^b|) over the disc of ``radius`` around the origin (polar form)."""
    if not absolute and (a % 2 or b % 2):
        return 0.0
    angular = 2 * math.gamma((a + 1) / 2) * math.gamma((b + 1) / 2) / math.gamma((a + b + 2) / 2)
    return radius ** (a + b + 2) / (a + b + 2) * angular


def square_moment(a: int, b: int, half: float, absolute: bool = False) -> float:
    """∫∫ x^a y^b (or its absolute value) over the square [-half, half]^2."""
    if absolute:
        return 4 * half ** (a + 1) / (a + 1) * half ** (b + 1) / (b + 1)
    square = [(-half, -half), (half, -half), (half, half), (-half, half)]
    return float(exact_integral(square, {(a, b): Fraction(1)}))


def moment(name: str, a: int, b: int, absolute: bool = False) -> float:
    """∫∫ x^a y^b (or |x^a y^b|) over the curved catalogue domain ``name``."""
    if name == "disc":
        return disc_moment(a, b, 1.0, absolute)
    if name == "annulus":
        return disc_moment(a, b, 1.0, absolute) - disc_moment(a, b, 0.5, absolute)
    if name == "plate-hole":
        return square_moment(a, b, 2.0, absolute) - disc_moment(a, b, 0.5, absolute)
    raise KeyError(name)


#: The true area of every curved catalogue domain.
AREAS = {
    "disc": math.pi,
    "annulus": math.pi * (1 - 0.25),
    "plate-hole": 16 - math.pi * 0.25,
    "quarter-plate-hole": 4 - math.pi * 0.25 / 4,
    "cylinder-channel": 2.2 * 0.41 - math.pi * 0.05**2,
}
