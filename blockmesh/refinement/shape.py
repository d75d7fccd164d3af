"""The shape energy of cells and its minimiser: nodes moved so every corner nears a regular one.

The energy is the sum over all cell corners of the corner's distortion from the corner of a
regular polygon with the same number of vertices (Knupp's condition number of the corner's
Jacobian against the ideal one)::

    μ = |A W⁻¹|²_F / (2 det(A W⁻¹)) >= 1,

with ``A = [x_next - x, x_prev - x]`` and W the same matrix for the regular polygon. μ = 1 when
the corner is a scaled, rotated copy of the ideal corner (the right angle, equal edges), and
μ -> ∞ as the corner flattens or folds, so a descent that keeps the energy finite keeps every
corner turning left: every cell stays strictly convex. A size term ``A/Ā + Ā/A - 2`` per cell
(Ā a target area) keeps the cells' sizes. :func:`optimize_points` minimises it by limited-memory
BFGS with a backtracking line search that rejects any step that makes a corner straight or reflex.

Examples
--------
>>> import numpy as np
>>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
>>> bent = square.copy(); bent[2] = [1.4, 0.7]
>>> fixed = np.array([True, True, False, True])
>>> moved, report = optimize_points(bent, np.array([[0, 1, 2, 3]]), fixed, np.zeros((4, 2)),
...                                 target=1.0, iterations=200)
>>> report.energy_after < report.energy_before, np.round(moved[2], 3).tolist()
(True, [1.0, 1.0])
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from blockmesh.geometry.polygons import is_strictly_convex

__all__ = ["PlacementReport", "ShapeEnergy", "optimize_points"]

#: Corners with a left-turn sine at most this are refused by the line search (cells stay convex).
SIN_FLOOR = 1e-6


@dataclass(frozen=True)
class PlacementReport:
    """What an optimisation did: energies per corner before and after, iterations, nodes moved."""

    energy_before: float
    energy_after: float
    iterations: int
    moving_nodes: int
    sliding_nodes: int


class ShapeEnergy:
    """The corner distortion (and the size term) of a fixed set of cells, with gradients.

    The per-corner index arrays are built once; every evaluation is a handful of whole-array
    operations on the x and y coordinates separately, O(M) time and memory.
    """

    def __init__(
        self,
        cells: np.ndarray,
        n_points: int,
        size_weight: float,
        target: float | np.ndarray,
        power: float = 1.0,
    ):
        n = cells.shape[1]
        theta = np.pi * (n - 2) / n  # the corner of a regular n-gon
        winv = np.linalg.inv(np.array([[1.0, np.cos(theta)], [0.0, np.sin(theta)]]))
        s = winv @ winv.T
        self.s00, self.s01, self.s11 = float(s[0, 0]), float(s[0, 1]), float(s[1, 1])
        self.k = float(np.linalg.det(winv))
        self.here = cells.ravel()
        self.next = np.roll(cells, -1, axis=1).ravel()
        self.prev = np.roll(cells, 1, axis=1).ravel()
        self.n_points = n_points
        self.n_cells = cells.shape[0]
        self.per_cell = n
        self.size_weight = size_weight
        self.target = target
        self.power = power
        self.ids = np.concatenate([self.here, self.next, self.prev])

    def __call__(self, x: np.ndarray, y: np.ndarray, want_gradient: bool):
        """(Σ μ + weight · corners per cell · Σ size term, gradient (N, 2) or None)."""
        ax, ay = x[self.next] - x[self.here], y[self.next] - y[self.here]
        bx, by = x[self.prev] - x[self.here], y[self.prev] - y[self.here]
        aa, bb, ab = ax * ax + ay * ay, bx * bx + by * by, ax * bx + ay * by
        d = ax * by - ay * bx
        if np.any(d <= SIN_FLOOR * np.sqrt(aa * bb)):
            return np.inf, None
        f = self.s00 * aa + 2 * self.s01 * ab + self.s11 * bb
        mu = f / (2 * self.k * d)
        value = float(mu.sum()) if self.power == 1 else float(np.sum(mu**self.power))
        area = None
        if self.size_weight:
            area = 0.5 * (x[self.here] * y[self.next] - x[self.next] * y[self.here])
            area = area.reshape(self.n_cells, self.per_cell).sum(axis=1)
            if np.any(area <= 0):
                return np.inf, None
            ratio = area / self.target
            value += self._size_factor() * float(np.sum(ratio + 1 / ratio - 2))
        if not want_gradient:
            return value, None
        scale = 1 / (2 * self.k * d * d)
        if self.power != 1:
            scale = scale * (self.power * mu ** (self.power - 1))
        fa_x, fa_y = 2 * (self.s00 * ax + self.s01 * bx), 2 * (self.s00 * ay + self.s01 * by)
        fb_x, fb_y = 2 * (self.s01 * ax + self.s11 * bx), 2 * (self.s01 * ay + self.s11 * by)
        ga_x, ga_y = (fa_x * d - f * by) * scale, (fa_y * d + f * bx) * scale
        gb_x, gb_y = (fb_x * d + f * ay) * scale, (fb_y * d - f * ax) * scale
        gx = [-(ga_x + gb_x), ga_x, gb_x]
        gy = [-(ga_y + gb_y), ga_y, gb_y]
        if area is not None:
            factor = self._size_factor() * (1 / self.target - self.target / area**2)
            factor = np.repeat(factor, self.per_cell)
            gx[0] = gx[0] + factor * 0.5 * (y[self.next] - y[self.prev])
            gy[0] = gy[0] + factor * 0.5 * (x[self.prev] - x[self.next])
        gradient = np.empty((self.n_points, 2))
        gradient[:, 0] = np.bincount(self.ids, np.concatenate(gx), minlength=self.n_points)
        gradient[:, 1] = np.bincount(self.ids, np.concatenate(gy), minlength=self.n_points)
        return value, gradient

    def _size_factor(self) -> float:
        """The size term is weighted per corner, like the distortion."""
        return self.size_weight * self.per_cell


def optimize_points(
    points: np.ndarray,
    cells: np.ndarray,
    fixed: np.ndarray,
    slide: np.ndarray,
    *,
    target: float | np.ndarray,
    size_weight: float = 1.0,
    power: float = 1.0,
    iterations: int = 300,
    tol: float = 1e-7,
) -> tuple[np.ndarray, PlacementReport]:
    """Node positions that lower the shape energy of ``cells``; every cell stays strictly convex.

    ``fixed`` nodes stay; a node with a nonzero row in ``slide`` moves only along that unit
    direction; every other node moves freely. ``target`` is the area each cell's size term aims
    at (a number, or one per cell). The positions returned are the input's when the descent
    cannot keep every cell strictly convex (the energy's barrier makes that unreachable).
    """
    points = np.asarray(points, dtype=np.float64)
    n_points = points.shape[0]
    sliding = np.flatnonzero(~fixed & np.any(slide != 0, axis=1))
    direction = slide[sliding]
    free = ~np.asarray(fixed, dtype=bool)
    free[sliding] = False
    interior = np.flatnonzero(free)
    origin = points.copy()
    count = cells.size

    def points_of(z: np.ndarray) -> np.ndarray:
        xy = origin.copy()
        xy[interior] += z[: 2 * interior.size].reshape(-1, 2)
        xy[sliding] += z[2 * interior.size :, None] * direction
        return xy

    evaluate = ShapeEnergy(cells, n_points, float(size_weight), target, float(power))

    def energy(z: np.ndarray, gradient: bool):
        xy = points_of(z)
        value, grad = evaluate(xy[:, 0], xy[:, 1], gradient)
        if grad is None:
            return value / count, None
        g = np.concatenate(
            [grad[interior].ravel(), np.einsum("nd,nd->n", grad[sliding], direction)]
        )
        return value / count, g / count

    z = np.zeros(2 * interior.size + sliding.size)
    start, _ = energy(z, False)
    z, end, steps = _lbfgs(energy, z, iterations, tol)
    moved = points_of(z)
    if not np.all(is_strictly_convex(moved[cells])):
        moved = origin
    return moved, PlacementReport(start, end, steps, int(interior.size), int(sliding.size))


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """``a · b`` summed in one fixed order (numpy's pairwise sum), whatever the BLAS threads.

    ``a @ b`` is BLAS's ``ddot``, which OpenBLAS splits over its threads for long vectors (above
    about 10,000 entries): each thread's partial sum rounds differently, so the same placement
    differed in the last bits with ``OPENBLAS_NUM_THREADS=1`` and ``2``, and the descent, which
    amplifies such bits, ended at worst angles that differed from the eighth digit on.
    """
    return float(np.add.reduce(a * b))


def _lbfgs(energy, z: np.ndarray, iterations: int, tol: float, memory: int = 8):
    """Limited-memory BFGS with backtracking (Armijo); infinite energies are rejected steps.

    Every inner product is :func:`_dot`, so the iterates are the same bits for any number of
    BLAS threads.
    """
    value, gradient = energy(z, True)
    history: list[tuple[np.ndarray, np.ndarray, float]] = []
    done = 0
    for done in range(1, iterations + 1):
        q = gradient.copy()
        alphas = []
        for s, y, rho in reversed(history):
            alpha = rho * _dot(s, q)
            q -= alpha * y
            alphas.append(alpha)
        if history:
            s, y, _ = history[-1]
            q *= _dot(s, y) / _dot(y, y)
        else:
            q *= 1e-2 / max(float(np.abs(q).max()), 1e-300)
        for (s, y, rho), alpha in zip(history, reversed(alphas), strict=True):
            q += s * (alpha - rho * _dot(y, q))
        step = -q
        slope = _dot(gradient, step)
        if slope >= 0:
            step, slope, history = -gradient, -_dot(gradient, gradient), []
        t = 1.0
        while True:
            trial, _ = energy(z + t * step, False)
            if np.isfinite(trial) and trial <= value + 1e-4 * t * slope:
                break
            t *= 0.5
            if t < 1e-12:
                return z, value, done
        z_new = z + t * step
        value_new, gradient_new = energy(z_new, True)
        s, y = z_new - z, gradient_new - gradient
        sy = _dot(s, y)
        if sy > 1e-300:
            history.append((s, y, 1.0 / sy))
            history = history[-memory:]
        improvement = value - value_new
        z, value, gradient = z_new, value_new, gradient_new
        if improvement < tol:
            break
    return z, value, done
