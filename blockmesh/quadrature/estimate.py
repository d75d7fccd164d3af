"""Error estimates for a fixed rule: a free null-rule screen, then a second opinion.

**The screen** reuses the values of f the rule has already computed. On each sector the
tensor nodes sample f on a grid in ``(r, s)``; summing out one direction leaves a function of
the other, whose expansion in the polynomials orthonormal for the rule's own weights can be read
off the same values exactly up to degree ``N - 1`` (``N`` nodes in that direction). The rule
integrates polynomials up to degree ``2N - 1`` exactly, so its error comes from the part of f
beyond what the grid resolves. The screen takes the magnitudes of the four highest
coefficients (times each sector's Jacobian) summed over the sectors of a cell, and per
direction the top pair ``T = |a_(N-1)| + |a_(N-2)|`` (one odd and one even, against parity),
shrunk once by the decay seen from the pair below (``T · min(1, T / (|a_(N-3)| + |a_(N-4)|))``),
times ``√μ`` (the weights' total, Cauchy-Schwarz); both directions are added. These "null
rules" cost one small matrix product per chunk (no evaluation of f), about 1 ns per point. For
a smooth f the screen is an over-estimate, typically by several orders of magnitude; for a
singular, divergent or unresolved f it is of the size of the integral itself.

**The second opinion**, taken only when the screen is above the warning level (or cannot be
formed: one node in a direction, i.e. order 1): the same rule one order higher on the same
mesh, and the estimate becomes ``2 Σ_cells |I_n - I_(n+1)|``. That bounds the error of the
order-``n`` result itself when one more order at least halves the error (geometric convergence,
as for every smooth integrand); when convergence is slow (a kink or cone point, errors falling
like a power of the order) it can fall short by a small factor. It costs ``(n + 2) / n`` of the
first pass and is skipped (the screen kept) when it would pass the point budget.

Examples
--------
>>> from blockmesh.quadrature import RULES
>>> screen = null_rule(RULES["paper"], 5)
>>> screen.matrix.shape, screen.complete
((30, 8), True)
>>> null_rule(RULES["jacobi"], 1).complete  # one point per sector: nothing to read off
False
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from blockmesh.quadrature.rule import Rule

__all__ = ["MODES", "NullRule", "null_rule"]

#: Coefficients read off per direction: degrees N-1, N-2 (the estimate) and N-3, N-4 (decay).
MODES = 4


@dataclass(frozen=True, eq=False)
class NullRule:
    """The screen's functionals for one rule and order.

    Attributes
    ----------
    matrix : ndarray (P, 2 * MODES)
        ``values (rows, P) @ matrix`` gives, per sector, the coefficients of degrees ``N - 1 ..
        N - 4`` of f's radial profile (first ``MODES`` columns) and along-edge profile (the
        rest), in that order; columns of degrees below 1 are zero.
    radial, along : int
        Nodes per direction.
    complete : bool
        Whether both directions have at least two nodes (else the screen says nothing).
    """

    matrix: np.ndarray
    radial: int
    along: int
    complete: bool

    def combine(self, coefficients: np.ndarray) -> np.ndarray:
        """Estimates from coefficient magnitudes (rows, 2 * MODES) -> (rows,).

        Each row holds ``|a_m|`` (times the Jacobian), summed over the sectors of one cell: per
        direction, the top pair shrunk once by its decay from the pair below (no decay where
        the pair below is zero or missing). Non-finite rows give ``inf``.
        """
        pairs = coefficients @ _PAIRS  # top_r, below_r, top_s, below_s
        top, below = pairs[:, 0::2], pairs[:, 1::2]
        with np.errstate(divide="ignore", invalid="ignore"):
            decay = np.fmin(1.0, top / below)  # 0/0 and x/0 give 1
        estimate = (top * decay) @ _ROOT_MASS
        estimate[~np.isfinite(estimate)] = np.inf
        return estimate


#: Sums the coefficient magnitudes in pairs: (N-1, N-2) and (N-3, N-4), per direction.
_PAIRS = np.kron(np.eye(4), np.ones((2, 1)))

#: √μ per direction: the weights of ∫∫ r dr ds total 1/2 in each (Cauchy-Schwarz).
_ROOT_MASS = np.full(2, math.sqrt(0.5))


def _top_modes(nodes: np.ndarray, measure: np.ndarray) -> np.ndarray:
    """Orthonormal polynomials (discrete ``measure``) of degrees N-1 .. N-MODES at ``nodes``.

    ``nodes`` lie in [0, 1]; the basis is Legendre on [-1, 1] (well conditioned), made
    orthonormal by a QR factorisation weighted by ``√measure``. Degrees below 1 are zero columns.
    """
    count = nodes.size
    out = np.zeros((count, MODES))
    if count < 2:
        return out
    vandermonde = np.polynomial.legendre.legvander(2 * nodes - 1, count - 1)
    root = np.sqrt(measure)
    q, _ = np.linalg.qr(root[:, None] * vandermonde)
    for m in range(MODES):
        degree = count - 1 - m
        if degree >= 1:
            out[:, m] = q[:, degree] / root
    return out


@lru_cache(maxsize=128)
def null_rule(rule: Rule, n: int) -> NullRule:
    """The screen of ``rule`` at order ``n`` (cached)."""
    nodes = rule.nodes(n)
    weights = nodes.weights
    radial = _top_modes(nodes.r, weights.sum(axis=1))
    along = _top_modes(0.5 + nodes.h, weights.sum(axis=0))
    columns = [(weights * radial[:, m][:, None]).reshape(-1) for m in range(MODES)]
    columns += [(weights * along[:, m][None, :]).reshape(-1) for m in range(MODES)]
    matrix = np.ascontiguousarray(np.stack(columns, axis=1))
    matrix.setflags(write=False)
    n_r, n_s = weights.shape
    return NullRule(matrix, n_r, n_s, n_r >= 2 and n_s >= 2)
