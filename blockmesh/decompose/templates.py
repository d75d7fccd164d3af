"""Templates: fixed splits of triangles, quadrilaterals and convex n-gons into convex pentagons.

Three templates, each a list of faces over numbered nodes whose positions are fixed combinations of
the piece's corners:

- the **triangle template** (9 pentagons; nodes in barycentric coordinates), with two nodes on every
  side at the symmetric fractions 0.335645 / 0.664355, so that triangles sharing a side agree on it;
- the **square template** (8 pentagons), mapped onto a convex quadrilateral by the projective map of
  the unit square; its side nodes sit at shape-dependent positions, so it stands alone;
- the **ring-and-hub template** of a convex n-gon (``3 n`` pentagons): a corner cell at each corner,
  an edge cell on each side (holding the side's two nodes, at the same symmetric fractions) and
  ``n`` sectors around a hub at the vertex mean. Each sector of the fan ``(c_i, c_i+1, hub)`` holds
  three inner nodes at fixed barycentric weights; for ``n = 3`` the template *is* the triangle
  template (the same nodes and faces). Because every side carries two nodes at the same fractions,
  any partition of a domain into convex pieces becomes a conforming pentagon mesh.

Affine maps keep straight lines and convexity, so the triangle template is valid for every
triangle; the ring-and-hub template is placed by the same weights in each sector of a convex piece
and checked (and improved) by the caller.

Examples
--------
>>> import numpy as np
>>> faces = ring_hub_faces(4)
>>> faces.shape
(12, 5)
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> nodes = ring_hub_nodes(square[None])[0]
>>> from blockmesh.geometry import is_strictly_convex
>>> bool(np.all(is_strictly_convex(nodes[faces])))
True
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = [
    "BALANCED_SECTOR_WEIGHTS",
    "EDGE_FRACTIONS",
    "SQUARE_FACES",
    "SQUARE_NODES",
    "TRIANGLE_FACES",
    "TRIANGLE_WEIGHTS",
    "ring_hub_faces",
    "ring_hub_nodes",
    "square_weights",
]

# The triangle template's constants: side nodes at a = 0.664355 from one corner; inner nodes
# (p, q, r) and (s, s, 1 - 2 s) in barycentric coordinates.
_A, _P, _Q, _R, _S = 0.664355, 0.528535, 0.297646, 0.173819, 0.383415

#: Where the two nodes of a template side sit, as fractions of the side from its first corner.
EDGE_FRACTIONS = (1.0 - _A, _A)


def _triangle_weights() -> np.ndarray:
    a, p, q, r, s = _A, _P, _Q, _R, _S
    t = 1.0 / 3.0
    b, u = 1.0 - a, 1.0 - 2.0 * s
    return np.array(
        [
            (1, 0, 0), (a, b, 0), (b, a, 0), (q, p, r), (s, s, u), (p, q, r), (p, r, q),
            (a, 0, b), (b, 0, a), (0, 0, 1), (0, b, a), (r, q, p), (q, r, p), (s, u, s),
            (t, t, t), (u, s, s), (r, p, q), (0, a, b), (0, 1, 0),
        ],
        dtype=np.float64,
    )  # fmt: skip


#: Barycentric weights (on corners A, B, C) of the triangle template's 19 nodes.
TRIANGLE_WEIGHTS = _triangle_weights()
#: The triangle template's 9 faces, counter-clockwise, over the nodes of TRIANGLE_WEIGHTS.
TRIANGLE_FACES = np.array(
    [
        [0, 1, 5, 6, 7], [1, 2, 3, 4, 5], [2, 18, 17, 16, 3], [3, 16, 15, 14, 4],
        [4, 14, 13, 6, 5], [6, 13, 12, 8, 7], [8, 12, 11, 10, 9], [10, 11, 15, 16, 17],
        [11, 12, 13, 14, 15],
    ]
)  # fmt: skip


def _square_nodes() -> np.ndarray:
    y1, c, d, e, g = 0.306387, 0.229053, 0.313345, 0.377906, 0.372143
    return np.array(
        [
            (0, 0), (0.5, 0), (0.5, c), (d, e), (0, y1), (0, 1 - y1), (0, 1), (0.5, 1), (1, 1),
            (1, 1 - y1), (1 - d, 1 - e), (0.5, 1 - c), (d, 1 - e), (g, 0.5), (1 - g, 0.5),
            (1 - d, e), (1, y1), (1, 0),
        ],
        dtype=np.float64,
    )  # fmt: skip


#: The square template's 18 nodes in the unit square.
SQUARE_NODES = _square_nodes()
#: The square template's 8 faces, counter-clockwise, over SQUARE_NODES.
SQUARE_FACES = np.array(
    [
        [0, 1, 2, 3, 4], [1, 17, 16, 15, 2], [2, 15, 14, 13, 3], [3, 13, 12, 5, 4],
        [5, 12, 11, 7, 6], [7, 11, 10, 9, 8], [9, 10, 14, 15, 16], [10, 11, 12, 13, 14],
    ]
)  # fmt: skip


def square_weights(quad: np.ndarray) -> np.ndarray:
    """Homogeneous weights of the square template's nodes on the corners of ``quad``.

    The projective map sending the unit square's corners to ``quad`` sends ``(u, v)`` to
    ``sum_i phi_i w_i Q_i / sum_i phi_i w_i`` with the bilinear weights ``phi`` of ``(u, v)`` and
    ``w_i`` twice the area of the triangle of the other three corners (the diagonals cut each
    other in the ratios of these areas). Nodes on an edge get weight on its two corners only.

    Examples
    --------
    >>> quad = np.array([[0, 0], [2, 0], [2, 1], [0, 1]], dtype=float)
    >>> w = square_weights(quad)
    >>> bool(np.allclose(w @ quad / w.sum(axis=1, keepdims=True), SQUARE_NODES * [2, 1]))
    True
    """
    u, v = SQUARE_NODES[:, 0:1], SQUARE_NODES[:, 1:2]
    phi = np.hstack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v])
    # Twice the area of the triangle without corner i is the cross product at corner i + 2,
    # computed as corner_sines does, so it is positive whenever the quad meets the contract.
    inc, out = quad - np.roll(quad, 1, axis=0), np.roll(quad, -1, axis=0) - quad
    return phi * np.roll(inc[:, 0] * out[:, 1] - inc[:, 1] * out[:, 0], -2)


def _sector_weights() -> np.ndarray:
    """Weights on (c_i, c_i+1, hub) of the three inner nodes of sector i: p_i, s_i, q_i.

    The triangle template's inner nodes near side AB, rewritten on (A, B, centroid): with
    C = 3 H - A - B, the node (p, q, r) becomes (p - r, q - r, 3 r), and so on.
    """
    p, q, r, s = _P, _Q, _R, _S
    u = 1.0 - 2.0 * s
    return np.array([(p - r, q - r, 3 * r), (s - u, s - u, 3 * u), (q - r, p - r, 3 * r)])


_SECTOR_WEIGHTS = _sector_weights()

#: Inner nodes of the *balanced* triangle template, ``(p, q, s)`` as in MATH.md section 4 (the
#: side fractions unchanged): the 9 cells of an equilateral triangle have diameters 0.293-0.343
#: of its side (the standard template's: 0.186-0.413), angles 60-145 degrees, area / diameter^2
#: at least 0.42. Found by minimising the largest cell diameter under those angle and roundness
#: bounds; for meshes made to a size field, where the cells' spread of sizes costs cells.
_BALANCED = (0.634211, 0.313434, 0.363466)


def _balanced_sector_weights() -> np.ndarray:
    p, q, s = _BALANCED
    r, u = 1.0 - p - q, 1.0 - 2.0 * s
    return np.array([(p - r, q - r, 3 * r), (s - u, s - u, 3 * u), (q - r, p - r, 3 * r)])


#: Sector weights of the balanced template (for :func:`ring_hub_nodes`).
BALANCED_SECTOR_WEIGHTS = _balanced_sector_weights()
BALANCED_SECTOR_WEIGHTS.setflags(write=False)


@lru_cache(maxsize=64)
def ring_hub_faces(n: int) -> np.ndarray:
    """The ``3 n`` faces of the ring-and-hub template of an n-gon, over its ``6 n + 1`` nodes.

    Node numbering: corners ``0..n-1``; side i's nodes ``n + 2 i`` (near corner i) and
    ``n + 2 i + 1`` (near corner i + 1); the hub ``3 n``; sector i's inner nodes
    ``3 n + 1 + 3 i + (0, 1, 2)`` (p_i near corner i, s_i inward of the side, q_i near corner
    i + 1). Faces: corner cells, then edge cells, then sectors, each counter-clockwise.

    Examples
    --------
    >>> ring_hub_faces(3)[0].tolist()  # the corner cell at corner 0
    [8, 0, 3, 10, 18]
    """
    i = np.arange(n)
    prev = (i - 1) % n
    nxt = (i + 1) % n
    side = n + 2 * i
    inner = 3 * n + 1 + 3 * i
    corner = np.column_stack([n + 2 * prev + 1, i, side, inner, 3 * n + 1 + 3 * prev + 2])
    edge = np.column_stack([side, side + 1, inner + 2, inner + 1, inner])
    sector = np.column_stack(
        [np.full(n, 3 * n), inner + 1, inner + 2, 3 * n + 1 + 3 * nxt, 3 * n + 2 + 3 * nxt]
    )
    faces = np.vstack([corner, edge, sector]).astype(np.int64)
    faces.setflags(write=False)
    return faces


def ring_hub_nodes(
    corners: np.ndarray,
    sides: np.ndarray | None = None,
    sector_weights: np.ndarray | None = None,
) -> np.ndarray:
    """Node coordinates of the ring-and-hub template for pieces of the same corner count.

    Parameters
    ----------
    corners : ndarray (P, n, 2)
        Each piece's corners, counter-clockwise.
    sides : ndarray (P, n, 2, 2), optional
        The side nodes (near the first corner, near the second), when they are computed elsewhere
        (shared with a neighbour, bit for bit); by default at :data:`EDGE_FRACTIONS`.
    sector_weights : ndarray (3, 3), optional
        Weights of each sector's three inner nodes on (corner i, corner i + 1, hub); by
        default the standard template's (:data:`BALANCED_SECTOR_WEIGHTS` is the other choice).

    Returns
    -------
    ndarray (P, 6 n + 1, 2)
    """
    corners = np.asarray(corners, dtype=np.float64)
    count, n = corners.shape[:2]
    ahead = np.roll(corners, -1, axis=1)
    if sides is None:
        f1, f2 = EDGE_FRACTIONS
        sides = np.stack([corners + f1 * (ahead - corners), corners + f2 * (ahead - corners)], 2)
    hub = corners.mean(axis=1, keepdims=True)
    w = _SECTOR_WEIGHTS if sector_weights is None else np.asarray(sector_weights)
    inner = (
        w[None, None, :, 0:1] * corners[:, :, None, :]
        + w[None, None, :, 1:2] * ahead[:, :, None, :]
        + w[None, None, :, 2:3] * hub[:, :, None, :]
    )
    return np.concatenate(
        [corners, sides.reshape(count, 2 * n, 2), hub, inner.reshape(count, 3 * n, 2)], axis=1
    )
