"""Gauss-Legendre and Gauss-Jacobi rules against 60-digit mpmath values."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from blockmesh.errors import ArgumentError, ArgumentTypeError, BlockMeshError
from blockmesh.numerics.gauss import MAX_POINTS, gauss_jacobi, gauss_legendre

#: Relative error allowed for nodes and weights: one unit in the last place, about.
ULP_TOL = 2e-16


def _jacobi_pair(n: int, a: int, b: int, x):
    """P_n and P_{n-1} (Jacobi, standard normalisation) in mpmath by the recurrence."""
    p0, p1 = mpmath.mpf(1), ((a + b + 2) * x + a - b) / 2
    if n == 0:
        return p0, mpmath.mpf(0)
    for k in range(2, n + 1):
        c = 2 * k + a + b
        p0, p1 = (
            p1,
            (
                (c - 1) * (c * (c - 2) * x + a * a - b * b) * p1
                - 2 * (k + a - 1) * (k + b - 1) * c * p0
            )
            / (2 * k * (k + a + b) * (c - 2)),
        )
    return p1, p0


def _reference_rule(n: int, a: int, b: int, start: np.ndarray):
    """Nodes and weights to 60 digits: Newton from ``start`` in mpmath."""
    with mpmath.workdps(60):
        nodes, weights = [], []
        gamma = mpmath.gamma
        g = gamma(n + a + 1) * gamma(n + b + 1) / (gamma(n + a + b + 1) * mpmath.factorial(n))
        for x0 in start:
            x = mpmath.mpf(float(x0))
            for _ in range(8):
                p, q = _jacobi_pair(n, a, b, x)
                dp = (n * (a - b - (2 * n + a + b) * x) * p + 2 * (n + a) * (n + b) * q) / (
                    (2 * n + a + b) * (1 - x * x)
                )
                x -= p / dp
            p, q = _jacobi_pair(n, a, b, x)
            dp = (n * (a - b - (2 * n + a + b) * x) * p + 2 * (n + a) * (n + b) * q) / (
                (2 * n + a + b) * (1 - x * x)
            )
            nodes.append(x)
            weights.append(g * mpmath.mpf(2) ** (a + b + 1) / ((1 - x * x) * dp * dp))
        return nodes, weights


def _max_rel_error(values: np.ndarray, reference) -> float:
    worst = 0.0
    for v, r in zip(values, reference, strict=True):
        if r == 0:
            assert v == 0.0
            continue
        worst = max(worst, float(abs((mpmath.mpf(float(v)) - r) / r)))
    return worst


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 7, 10, 16, 20, 31, 46, 64, 100])
def test_legendre_matches_mpmath_to_an_ulp(n):
    x, w = gauss_legendre(n)
    nodes, weights = _reference_rule(n, 0, 0, x)
    assert _max_rel_error(x, nodes) <= ULP_TOL
    assert _max_rel_error(w, weights) <= ULP_TOL


@pytest.mark.parametrize(
    ("n", "alpha", "beta"),
    [
        (1, 0, 1),
        (2, 0, 1),
        (5, 0, 1),
        (11, 0, 1),
        (20, 0, 1),
        (47, 0, 1),
        (100, 0, 1),
        (6, 1, 2),
        (30, 2, 0),
    ],
)
def test_jacobi_matches_mpmath_to_an_ulp(n, alpha, beta):
    x, w = gauss_jacobi(n, alpha, beta)
    nodes, weights = _reference_rule(n, alpha, beta, x)
    assert _max_rel_error(x, nodes) <= ULP_TOL
    assert _max_rel_error(w, weights) <= ULP_TOL


def test_numpy_leggauss_is_the_reason():
    """numpy's weights are ~1e-12 off at n = 100; ours are not (the motivation for gauss.py)."""
    _, w = gauss_legendre(100)
    _, w_numpy = np.polynomial.legendre.leggauss(100)
    assert np.max(np.abs(w_numpy / w - 1)) > 1e-13


@pytest.mark.parametrize("n", [1, 2, 9, 10, 45, 46])
def test_legendre_nodes_are_exactly_symmetric_and_sorted(n):
    x, w = gauss_legendre(n)
    assert np.array_equal(x, -x[::-1])
    assert np.array_equal(w, w[::-1])
    assert np.all(np.diff(x) > 0)
    if n % 2:
        assert x[n // 2] == 0.0


@pytest.mark.parametrize("n", [1, 3, 8, 25])
def test_degree_of_exactness(n):
    x, w = gauss_legendre(n)
    for k in range(2 * n):
        exact = 0.0 if k % 2 else 2 / (k + 1)
        assert abs(np.dot(w, x**k) - exact) < 1e-15
    r, v = gauss_jacobi(n, 0, 1)
    for k in range(2 * n):
        exact = 2 / (k + 1) if k % 2 == 0 else 2 / (k + 2)
        assert abs(np.dot(v, r**k) - exact) < 1e-15  # ∫ (1 + x) x^k dx


def test_rules_are_cached_and_read_only():
    x, w = gauss_legendre(12)
    again, _ = gauss_legendre(12)
    assert again is x
    with pytest.raises(ValueError):
        x[0] = 0.0
    with pytest.raises(ValueError):
        w[0] = 0.0


@pytest.mark.parametrize(
    ("bad", "error"),
    [
        (0, ArgumentError),
        (-1, ArgumentError),
        (MAX_POINTS + 1, ArgumentError),
        (1.5, ArgumentTypeError),
        (True, ArgumentTypeError),
        ("3", ArgumentTypeError),
    ],
)
def test_bad_point_counts_are_refused(bad, error):
    with pytest.raises(error, match="number of Gauss points"):
        gauss_legendre(bad)
    with pytest.raises(BlockMeshError):
        gauss_jacobi(bad)


@pytest.mark.parametrize(("alpha", "beta"), [(-1, 0), (0, 0.5), (True, 1)])
def test_bad_exponents_are_refused(alpha, beta):
    with pytest.raises(BlockMeshError, match="whole number >= 0"):
        gauss_jacobi(3, alpha, beta)
