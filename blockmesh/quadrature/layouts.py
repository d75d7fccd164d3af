"""The two ways the rules cut a pentagon: five sectors at the vertex mean, or a fan of three.

Examples
--------
>>> CENTRE.sectors_per_cell, CORNER_FAN.sectors_per_cell
(5, 3)
>>> CENTRE.sectors[0]  # apex at the vertex mean, edge from corner 1 to corner 0
(None, 0, 1)
"""

from __future__ import annotations

import numpy as np

from blockmesh.quadrature.rule import Layout

__all__ = ["CENTRE", "CORNER_FAN"]


def _shortest_fan(x_all: np.ndarray, y_all: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Each cell's corners rotated so that corner 0 is the fan apex with the shortest diagonals.

    A convex pentagon has five triangulations, the fans from each corner ``a``, which use the
    diagonals ``a -> a+2`` and ``a+3 -> a``. The fan whose longer diagonal is shortest has the
    most compact triangles (for a smooth integrand, the smallest error at a given order).
    """
    x, y = x_all[ring[:5]], y_all[ring[:5]]  # (5, B)
    skip = [2, 3, 4, 0, 1]
    diagonal = np.hypot(x[skip] - x, y[skip] - y)  # row j: corner j -> j+2
    cost = np.maximum(diagonal, diagonal[[3, 4, 0, 1, 2]])  # apex a: diagonals a, a+3
    apex = np.argmin(cost, axis=0)
    order = (apex + np.arange(6)[:, None]) % 5
    return np.take_along_axis(ring[:5], order, axis=0)


#: Five sectors with the apex at the cell's vertex mean (the paper's split), edge ``e`` walked
#: from corner ``e + 1`` to corner ``e``.
CENTRE = Layout(
    name="centre",
    sectors=tuple((None, e, (e + 1) % 5) for e in range(5)),
)

#: Three triangles fanned from the corner whose diagonals are shortest (straight cells only).
CORNER_FAN = Layout(
    name="corner fan",
    sectors=((0, 1, 2), (0, 2, 3), (0, 3, 4)),
    orient=_shortest_fan,
    edges_are_cell_edges=False,
)
