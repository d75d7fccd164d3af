"""Five sectors at the vertex mean, n Gauss-Jacobi(0, 1) x n Gauss-Legendre points.

The radial Gauss-Jacobi rule has the weight ``(1 + x)``, which is the Jacobian factor ``2r`` of
the collapsed coordinates: ``n`` radial points are exact to degree ``2n - 1`` in ``r`` after the
factor, one point fewer than the paper's ``n + 1`` Legendre points for the same degree
(``n**2`` points per sector instead of ``n (n + 1)``).

Examples
--------
>>> RULE.info(5).points_per_cell
125
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from blockmesh.numerics.gauss import MAX_POINTS, gauss_jacobi, gauss_legendre
from blockmesh.quadrature.layouts import CENTRE
from blockmesh.quadrature.rule import Rule, SectorNodes

__all__ = ["RULE", "jacobi_nodes"]


@lru_cache(maxsize=128)
def jacobi_nodes(n: int) -> SectorNodes:
    """``n`` Gauss-Jacobi(0, 1) radial points x ``n`` Gauss-Legendre points along the edge."""
    t, wt = gauss_legendre(n)
    x, wx = gauss_jacobi(n, 0, 1)  # weight (1 + x) = 2r: absorbs the Jacobian factor r
    return SectorNodes.from_gauss(x, t, np.multiply.outer(wx, wt) / 8, degree=2 * n - 1)


RULE = Rule(
    name="jacobi",
    description="5 triangles at the vertex mean, n x n Gauss-Jacobi(0,1) x Gauss-Legendre",
    layout=CENTRE,
    nodes=jacobi_nodes,
    max_order=MAX_POINTS - 1,
)
