"""The paper's rule: five sectors at the vertex mean, (n+1) x n Gauss-Legendre points.

This is the rule of the seed's FIFTH program
(``compositeboundaryintegrationconvexpolygonofpentagons_n``): on each sector the radial
direction has ``n + 1`` Gauss-Legendre points (the paper's ``sss, www``) and the edge ``n`` (its
``ss, ww``); the weight of a point is the program's ``ps * wt`` with ``wt = ww * www / 4``. It
reproduces the paper's Tables 1-11 (:mod:`blockmesh.tables`; ``docs/mathematics.md`` §6, and §7
for the paper's misprints). Exact to total degree ``2n - 1``
(``n`` points along the edge are exact to degree ``2n - 1`` in ``s``, ``n + 1`` radial points with
the factor ``r`` to degree ``2n`` in ``r``).

Examples
--------
>>> RULE.info(10)
RuleInfo(rule='paper', order=10, points_per_triangle=110, triangles_per_cell=5, degree=19)
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from blockmesh.numerics.gauss import MAX_POINTS, gauss_legendre
from blockmesh.quadrature.layouts import CENTRE
from blockmesh.quadrature.rule import Rule, SectorNodes

__all__ = ["RULE"]


@lru_cache(maxsize=128)
def _nodes(n: int) -> SectorNodes:
    t, wt = gauss_legendre(n)  # along the edge: the paper's ss, ww
    x, wx = gauss_legendre(n + 1)  # radial: the paper's sss, www
    ps = (1 + x) / 2
    weights = ps[:, None] * (np.multiply.outer(wx, wt) / 4)  # ps * wt, wt = ww*www/4
    return SectorNodes.from_gauss(x, t, weights, degree=2 * n - 1)


RULE = Rule(
    name="paper",
    description="the paper's rule: 5 triangles at the vertex mean, (n+1) x n Gauss-Legendre",
    layout=CENTRE,
    nodes=_nodes,
    max_order=MAX_POINTS - 1,
)
