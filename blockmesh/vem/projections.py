"""The lowest-order virtual element space on a polygon: projections computed from the boundary.

On a polygon E with vertices x_1..x_n (counter-clockwise), a function v of the space is linear on
every edge and known by its vertex values. Its gradient projection ``Π∇v`` is the linear
polynomial with

* the mean gradient of v: ``∇Π∇v = (1/|E|) ∫_E ∇v = (1/|E|) ∫_∂E v n ds``, computable exactly
  from the vertex values because v is linear on each edge, and
* the mean of the vertex values of v.

So ``Π∇v(x) = mean_i v(x_i) + (W v)·(x - c)`` with c the vertex mean and W the ``2 x n``
matrix ``W[:, i] = (n_(i-1) |e_(i-1)| + n_i |e_i|) / (2 |E|)`` (the two edges at vertex i, with
their outward normals). This is the projection of Sutton's "VEM in 50 lines" (its matrices
``D``, ``B``, ``G`` give the same polynomial), written without inverting ``G``. On a triangle
``Π∇`` is the identity on the space: the method is then the P1 finite element method.

In the enhanced space of lowest order the L2 projection ``Π⁰`` onto linear polynomials equals
``Π∇``, so one matrix serves the stiffness, the mass, the load and the error norms.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
>>> p = projections(square, np.array([[0, 1, 2, 3]]))
>>> p.gradient[0].round(12).tolist()  # W: the gradient of Π∇v from the vertex values
[[-0.5, 0.5, 0.5, -0.5], [-0.5, -0.5, 0.5, 0.5]]
>>> v = np.array([1.0, 3.0, 5.0, 3.0])  # 1 + 2x + 2y at the corners: reproduced exactly
>>> (p.matrix[0] @ v).round(12).tolist()
[1.0, 3.0, 5.0, 3.0]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from blockmesh.geometry.polygons import signed_area

__all__ = ["Projections", "projections"]


@dataclass(frozen=True, eq=False)
class Projections:
    """Geometry and the projection ``Π∇`` of every cell of one group (n vertices each).

    Attributes
    ----------
    area : ndarray (M,)
    centre : ndarray (M, 2)
        Vertex means c.
    gradient : ndarray (M, 2, n)
        W: ``∇Π∇v = W v`` for the vertex values v.
    matrix : ndarray (M, n, n)
        ``Π∇`` in the nodal basis: ``(matrix @ v)[i] = Π∇v(x_i)``.
    """

    area: np.ndarray
    centre: np.ndarray
    gradient: np.ndarray
    matrix: np.ndarray

    @property
    def size(self) -> int:
        """Vertices per cell."""
        return int(self.gradient.shape[2])

    def monomials(self, x: np.ndarray, y: np.ndarray, cells: slice = slice(None)) -> np.ndarray:
        """``(1, x - c_x, y - c_y)`` at points of the cells: shape (C, Q, 3) for ``x, y`` (C, Q).

        ``Π∇φ_j = monomials @ coefficients[:, :, j]``: integrals of a weight times ``Π∇φ_j``
        need only the weight's moments against these three.
        """
        centre = self.centre[cells]
        return np.stack([np.ones_like(x), x - centre[:, 0:1], y - centre[:, 1:2]], axis=-1)

    @property
    def coefficients(self) -> np.ndarray:
        """``Π∇φ_j`` in the basis ``(1, x - c_x, y - c_y)``: shape (M, 3, n)."""
        m, _, n = self.gradient.shape
        out = np.empty((m, 3, n))
        out[:, 0] = 1.0 / n
        out[:, 1:] = self.gradient
        return out

    def residual(self) -> np.ndarray:
        """``I - Π∇`` (M, n, n): what the projection misses, the argument of the stabilisation."""
        return np.eye(self.size) - self.matrix


def projections(points: np.ndarray, cells: np.ndarray) -> Projections:
    """The projections of every cell of a group (cells of one vertex count, counter-clockwise).

    O(M n²) time and memory, whole-array operations only.
    """
    corners = points[cells]  # (M, n, 2)
    n = cells.shape[1]
    area = signed_area(corners)
    centre = corners.mean(axis=1)
    after = np.roll(corners, -1, axis=1)
    before = np.roll(corners, 1, axis=1)
    gradient = np.empty((cells.shape[0], 2, n))
    gradient[:, 0, :] = (after[..., 1] - before[..., 1]) / (2 * area[:, None])
    gradient[:, 1, :] = (before[..., 0] - after[..., 0]) / (2 * area[:, None])
    offset = corners - centre[:, None, :]
    matrix = 1.0 / n + np.matmul(offset, gradient)
    return Projections(area, centre, gradient, matrix)
