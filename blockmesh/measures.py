"""Cell measures of a pentagon mesh in one chunked pass: areas, angles, aspect, convexity.

:meth:`Mesh.quality <blockmesh.mesh.Mesh.quality>`, :attr:`Mesh.area <blockmesh.mesh.Mesh.area>`
and :meth:`Mesh.check_geometry <blockmesh.mesh.Mesh.check_geometry>` all read the same
:class:`CellMeasures`, computed once per mesh by :func:`measure_cells`.

How it is fast: cells are visited in chunks small enough for every temporary to stay in the CPU
caches, corner-major (one contiguous row per corner), and only differences of nearby points are
used (edge vectors and diagonals), so results do not depend on where the mesh lies. Three identities
avoid most of the per-corner work:

- the sine of a corner's turn satisfies ``sin^2 = cross^2 / (cross^2 + dot^2)`` (Lagrange's
  identity ``|a|^2 |b|^2 = (a.b)^2 + (a x b)^2``), so "every corner turns left by more than the
  tolerance" is ``cross > 0`` and ``|dot / cross| < K`` for all corners, without square roots;
- for left turns, ``dot / cross = cot(turn)`` decreases with the turn, so the smallest interior
  angle sits at the smallest ``dot / cross`` and the largest at the largest: ``arctan2`` runs
  for two corners per chunk, not for all of them;
- the shoelace area is ``2A = sum_k (x_k - x_0)(y_(k+1) - y_(k-1))``, whose second factors are
  the diagonals already needed for the diameter.

A chunk where any corner fails the fast test (a straight, reflex or degenerate corner, or
non-finite values) is measured again with the plain formulas of :mod:`blockmesh.geometry`, so
the counts of bad cells are exactly those formulas' counts.

Examples
--------
>>> import blockmesh
>>> m = measure_cells(blockmesh.load_domain("sp").mesh(1))
>>> round(m.min_angle, 1), round(m.max_angle, 1), m.not_strictly_convex, round(m.area, 12)
(56.3, 150.3, 0, 5.0)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .geometry import COLLINEAR_SIN_TOL, corner_sines, interior_angles, signed_area

if TYPE_CHECKING:
    from .mesh import Mesh

__all__ = ["CHUNK", "CellMeasures", "cell_shapes", "measure_cells"]

#: Cells measured at once: (2, 7, CHUNK) float64 corners and a few (5, CHUNK) temporaries stay
#: within a core's L2 cache.
CHUNK = 4096

#: ``|cot(turn)| < _COT_LIMIT`` means ``sin(turn) > COLLINEAR_SIN_TOL`` with a safety margin: a
#: corner closer to the tolerance than that is measured by the plain formula.
_COT_LIMIT = math.sqrt(1.0 / COLLINEAR_SIN_TOL**2 - 1.0) * (1.0 - 1e-6)


@dataclass(frozen=True)
class CellMeasures:
    """What one pass over the cells finds (angles in degrees).

    Attributes
    ----------
    area : float
        Sum of the cell areas.
    min_area, max_area : float
    min_angle, max_angle : float
        Smallest and largest interior angle over all corners.
    max_aspect_ratio : float
        Largest diameter**2 / area (``inf`` when a cell has no positive area).
    not_strictly_convex : int
        Cells with a corner whose turn has sine at most ``COLLINEAR_SIN_TOL``.
    invalid : int
        Cells that are not strictly convex or have no positive area (what
        :meth:`~blockmesh.mesh.Mesh.check_geometry` refuses).
    first_invalid : int
        The first such cell, or -1.
    """

    area: float
    min_area: float
    max_area: float
    min_angle: float
    max_angle: float
    max_aspect_ratio: float
    not_strictly_convex: int
    invalid: int
    first_invalid: int


class _Accumulator:
    """Running extremes and sums over the chunks."""

    def __init__(self) -> None:
        self.area_sums: list[float] = []
        self.min_area, self.max_area = math.inf, -math.inf
        self.min_angle, self.max_angle = math.inf, -math.inf
        self.max_aspect = 0.0
        self.not_strictly_convex = 0
        self.invalid, self.first_invalid = 0, -1

    def add(self, start: int, areas, diam2, min_angle: float, max_angle: float, sharp) -> None:
        """Fold in one chunk; ``sharp`` None means every corner of it turns left enough."""
        smallest = float(areas.min())
        self.area_sums.append(float(areas.sum()))
        self.min_area = min(self.min_area, smallest)
        self.max_area = max(self.max_area, float(areas.max()))
        self.min_angle = min(self.min_angle, min_angle)
        self.max_angle = max(self.max_angle, max_angle)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
        self.max_aspect = max(self.max_aspect, float(aspect.max()))
        if sharp is None:  # every corner is known to turn left by more than the tolerance
            if smallest > 0:
                return
            bad = ~(areas > 0)
        else:
            self.not_strictly_convex += int(np.count_nonzero(~sharp))
            bad = ~(sharp & (areas > 0))
        if np.any(bad):
            if self.first_invalid < 0:
                self.first_invalid = start + int(np.flatnonzero(bad)[0])
            self.invalid += int(np.count_nonzero(bad))

    def result(self) -> CellMeasures:
        return CellMeasures(
            area=math.fsum(self.area_sums),
            min_area=self.min_area,
            max_area=self.max_area,
            min_angle=self.min_angle,
            max_angle=self.max_angle,
            max_aspect_ratio=self.max_aspect,
            not_strictly_convex=self.not_strictly_convex,
            invalid=self.invalid,
            first_invalid=self.first_invalid,
        )


def _plain_chunk(points: np.ndarray, cells: np.ndarray, start: int, acc: _Accumulator) -> None:
    """The chunk measured with the plain formulas (corners relative to each cell's first)."""
    xy = points[cells]
    xy -= xy[:, :1]
    angles = interior_angles(xy)
    areas = signed_area(xy)
    diff = xy[:, :, None, :] - xy[:, None, :, :]
    diam2 = np.max(np.einsum("mijk,mijk->mij", diff, diff), axis=(1, 2))
    sines = np.nan_to_num(corner_sines(xy), nan=-1.0)
    sharp = np.all(sines > COLLINEAR_SIN_TOL, axis=1)
    acc.add(start, areas, diam2, float(angles.min()), float(angles.max()), sharp)


def measure_cells(
    mesh: Mesh, *, chunk: int = CHUNK, progress: Callable[[int, int], None] | None = None
) -> CellMeasures:
    """Areas, angles, aspect ratios and convexity of every cell, in one pass of ``chunk`` cells.

    O(M) time; memory O(chunk) besides the mesh. ``progress(done, total)`` is called every 256
    chunks with the cells measured so far.

    Examples
    --------
    >>> import blockmesh
    >>> m = measure_cells(blockmesh.load_domain("square-cut").mesh(3))
    >>> m.invalid, m.first_invalid, round(m.area, 12)
    (0, -1, 0.875)
    """
    acc = _Accumulator()
    n_cells = mesh.n_cells
    if n_cells == 0:
        return CellMeasures(0.0, math.inf, -math.inf, math.inf, -math.inf, 0.0, 0, 0, -1)
    z_points = mesh.points.view(np.complex128).reshape(-1)
    buffer = np.empty((2, 7, min(chunk, n_cells)))
    with np.errstate(all="ignore"):  # overflow and 0/0 fail the fast test: plain formulas
        for start in range(0, n_cells, chunk):
            cells = mesh.cells[start : start + chunk]
            m = cells.shape[0]
            # b[:, j] = corner j mod 5 (x then y), so that every edge and diagonal is one slice.
            b = buffer[:, :, :m]
            z = np.take(z_points, cells.T, mode="clip")  # (5, m); ids checked by the Mesh
            b[0, :5] = z.real
            b[1, :5] = z.imag
            b[:, 5:] = b[:, :2]
            edges = b[:, 1:] - b[:, :-1]  # (2, 6, m): corner j to j+1; edge 5 is edge 0 again
            diagonals = b[:, 2:] - b[:, :-2]  # (2, 5, m): corner j to j+2
            ex, ey = edges
            # Corners 1..4, 0: incoming edge j, outgoing edge j+1.
            cross = ex[:-1] * ey[1:]
            cross -= ey[:-1] * ex[1:]
            if not np.all(cross > 0):
                _plain_chunk(mesh.points, cells, start, acc)
                continue
            dot = ex[:-1] * ex[1:]
            dot += ey[:-1] * ey[1:]
            cot = dot / cross
            low, high = int(np.argmin(cot)), int(np.argmax(cot))
            if not (cot.flat[low] > -_COT_LIMIT and cot.flat[high] < _COT_LIMIT):
                _plain_chunk(mesh.points, cells, start, acc)
                continue
            areas = (b[0, 1:5] - b[0, :1]) * diagonals[1, :4]
            areas = areas.sum(axis=0)
            areas *= 0.5
            squares = edges[:, 1:] * edges[:, 1:]
            diam2 = (squares[0] + squares[1]).max(axis=0)
            diagonals *= diagonals
            np.maximum(diam2, (diagonals[0] + diagonals[1]).max(axis=0), out=diam2)
            # The largest cot is the smallest turn: the largest interior angle; and vice versa.
            turn = np.arctan2(cross.flat[[low, high]], dot.flat[[low, high]])
            min_angle, max_angle = (180.0 - np.degrees(turn)).tolist()
            acc.add(start, areas, diam2, min_angle, max_angle, None)
            if progress is not None and (start // chunk) % 256 == 255:
                progress(start + m, n_cells)
    return acc.result()


def cell_shapes(mesh: Mesh, *, chunk: int = 1 << 16) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Interior angles (5, m) in degrees and aspect ratios (m,) of the cells, chunk by chunk.

    For histograms of the whole mesh in bounded memory (``plot_quality``). Aspect ratio is
    diameter**2 / area, ``inf`` where a cell has no positive area.

    Examples
    --------
    >>> import blockmesh
    >>> angles, aspect = next(cell_shapes(blockmesh.load_domain("sp").mesh(0)))
    >>> angles.round(1).ravel().tolist(), aspect.round(3).tolist()
    ([135.0, 135.0, 71.6, 126.9, 71.6], [3.2])
    """
    z_points = mesh.points.view(np.complex128).reshape(-1)
    for start in range(0, mesh.n_cells, chunk):
        z = np.take(z_points, mesh.cells[start : start + chunk].T, mode="clip")  # (5, m)
        edges = np.roll(z, -1, axis=0) - z  # edge k from corner k to k + 1
        turn = edges * np.roll(edges, 1, axis=0).conj()  # at corner k: incoming edge k - 1
        angles = 180.0 - np.degrees(np.angle(turn))
        local = z[1:] - z[0]
        areas = 0.5 * (local[:-1].conj() * local[1:]).imag.sum(axis=0)
        diam2 = np.max(np.abs(z[:, None, :] - z[None, :, :]) ** 2, axis=(0, 1))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            aspect = np.where(areas > 0, diam2 / np.where(areas > 0, areas, 1.0), np.inf)
        yield angles, aspect
