"""Double-double arithmetic on numpy arrays: about 32 significant digits from pairs of float64.

A double-double number is a pair ``(hi, lo)`` of float64 values (or arrays) with
``|lo| <= ulp(hi) / 2``; its value is ``hi + lo`` exactly. The building blocks are the error-free
transformations of Knuth (``two_sum``) and Dekker (``split``, ``two_prod``), which need no fused
multiply-add and so give the same bits on every machine. Used by the Gauss rules
(:mod:`blockmesh.numerics.gauss`, Newton steps to full double precision) and by the exact decimal
printing of :mod:`blockmesh.io.text`.

Examples
--------
>>> s, e = two_sum(1.0, 1e-17)
>>> s, e
(1.0, 1e-17)
>>> p, e = two_prod(0.1, 0.1)
>>> p, e == 0.1 * 0.1 - p
(0.010000000000000002, False)
>>> from fractions import Fraction
>>> Fraction(p) + Fraction(e) == Fraction(0.1) * Fraction(0.1)
True
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

__all__ = [
    "dd_add",
    "dd_div",
    "dd_mul",
    "dd_mul_d",
    "dd_of",
    "fast_two_sum",
    "split",
    "two_prod",
    "two_sum",
]

#: 2**27 + 1, Dekker's splitting constant: ``split`` cuts a float64 into two 26-bit halves.
SPLITTER = 134217729.0

Pair = tuple[Any, Any]


def two_sum(a: Any, b: Any) -> Pair:
    """``(s, e)`` with ``s = fl(a + b)`` and ``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def fast_two_sum(a: Any, b: Any) -> Pair:
    """Like :func:`two_sum`, valid when ``|a| >= |b|`` (Dekker)."""
    s = a + b
    return s, b - (s - a)


def split(a: Any) -> Pair:
    """``(hi, lo)`` with ``a = hi + lo`` and both halves of at most 26 significant bits."""
    t = SPLITTER * a
    hi = t - (t - a)
    return hi, a - hi


def two_prod(a: Any, b: Any) -> Pair:
    """``(p, e)`` with ``p = fl(a * b)`` and ``a * b = p + e`` exactly (no overflow assumed)."""
    p = a * b
    ah, al = split(a)
    bh, bl = split(b)
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


def dd_add(ah: Any, al: Any, bh: Any, bl: Any) -> Pair:
    """Sum of two double-doubles."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    s, e = fast_two_sum(s, e + t)
    return fast_two_sum(s, e + f)


def dd_mul(ah: Any, al: Any, bh: Any, bl: Any) -> Pair:
    """Product of two double-doubles."""
    p, e = two_prod(ah, bh)
    return fast_two_sum(p, e + (ah * bl + al * bh))


def dd_mul_d(ah: Any, al: Any, b: Any) -> Pair:
    """Product of a double-double and a float64."""
    p, e = two_prod(ah, b)
    return fast_two_sum(p, e + al * b)


def dd_div(ah: Any, al: Any, bh: Any, bl: Any) -> Pair:
    """Quotient of two double-doubles (three correction steps).

    Examples
    --------
    >>> h, l = dd_div(1.0, 0.0, 3.0, 0.0)
    >>> Fraction(h) + Fraction(l) - Fraction(1, 3) < Fraction(1, 10**32)
    True
    """
    q1 = ah / bh
    ph, pl = dd_mul_d(bh, bl, q1)
    rh, rl = dd_add(ah, al, -ph, -pl)
    q2 = rh / bh
    ph, pl = dd_mul_d(bh, bl, q2)
    rh, rl = dd_add(rh, rl, -ph, -pl)
    q3 = rh / bh
    h, l = fast_two_sum(q1, q2)
    return dd_add(h, l, q3, 0.0 * q3)


def dd_of(value: Fraction) -> tuple[float, float]:
    """The double-double nearest a rational number.

    Examples
    --------
    >>> dd_of(Fraction(1, 3))
    (0.3333333333333333, 1.850371707708594e-17)
    """
    hi = float(value)
    return hi, float(value - Fraction(hi))
